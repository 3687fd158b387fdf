"""
A molecule: principal axes and rotational constants
===================================================

Ethanol from ASE's collection of molecules (needs ``pip install 'polhode[chem]'``): its
inertia tensor with isotope masses, its principal axes, the rotational constants A >= B >= C a
microwave spectroscopist measures, and Ray's asymmetry parameter.
"""

import matplotlib.pyplot as plt
import numpy as np
from ase.build import molecule

import polhode as ph

# %%
# Positions in angstrom, masses in u (the most abundant isotopes, AME 2020, by default).
atoms = molecule("CH3CH2OH")
body = ph.Body.from_molecule(atoms)
constants = ph.molecule.rotational_constants(body, unit="GHz")
print(constants)
print(f"kappa = {ph.molecule.asymmetry(body):.3f}, a {ph.molecule.rotor_type(body)} rotor")

# %%
# The atoms in the principal frame: a is the axis of the smallest moment (A the largest
# constant), c the one of the largest. The molecule lies long along a.
moments, axes = body.principal()
xyz = (atoms.positions - body.center_of_mass) @ axes
size = 40 * np.asarray(atoms.get_masses())
fig, (ab, ac) = plt.subplots(1, 2, figsize=(10, 4))
for ax, (i, j) in ((ab, (0, 1)), (ac, (0, 2))):
    ax.scatter(xyz[:, i], xyz[:, j], s=size, c=atoms.get_atomic_numbers(), cmap="viridis")
    for symbol, p in zip(atoms.get_chemical_symbols(), xyz, strict=True):
        ax.annotate(symbol, (p[i], p[j]), ha="center", va="center", color="w", fontsize=8)
    ax.set_xlabel("abc"[i] + " (angstrom)")
    ax.set_ylabel("abc"[j] + " (angstrom)")
    ax.set_aspect("equal")
fig.suptitle("ethanol in its principal axes (marker area ~ mass)")
fig.tight_layout()
plt.show()
