"""
A composite machine part
========================

A crank: a hub, a web, a crank pin and a counterweight. Built from solids, it has its mass
properties at once; its principal axes show that it is dynamically unbalanced, and spun about
its shaft it wobbles.
"""

import matplotlib.pyplot as plt
import numpy as np

import polhode as ph

steel = 7850.0  # kg/m^3


def cuboid(size):
    return ph.Body.cuboid(steel * np.prod(size), size)


def cylinder(radius, length):
    return ph.Body.cylinder(steel * np.pi * radius**2 * length, radius, length)


# %%
# The shaft runs along z; the web lies in the xz plane; the crank pin sticks out at x = 6 cm on
# one side of the web, the counterweight at x = -4 cm on the other side.
hub = cylinder(0.02, 0.06)
web = cuboid([0.14, 0.03, 0.015]).translated([0.01, 0.0, 0.0375])
pin = cylinder(0.012, 0.05).translated([0.06, 0.0, 0.07])
counterweight = cuboid([0.05, 0.06, 0.02]).translated([-0.045, 0.0, 0.02])
crank = hub + web + pin + counterweight
p = crank.principal()
print(crank)
print("centre of mass (m):", crank.center_of_mass)
print("principal axes (columns):")
print(p.axes)

# %%
# The largest axis is tilted from the shaft (z): a product of inertia I_xz is not zero.
tilt = np.degrees(np.arccos(abs(p.axes[2, 2])))
print(f"I_xz = {crank.inertia[0, 2]:.3e} kg m^2")
print(f"the largest axis is {tilt:.2f} deg from z")

# %%
# The inertia as a simulator reads it: MuJoCo's ``<inertial>`` and URDF's.
print(crank.to_mjcf())
print(crank.to_urdf_inertial())

# %%
# Spun freely at 30 rad/s about its shaft, it does not keep turning about the shaft: the
# principal axes cone about the fixed angular momentum.
t = np.linspace(0.0, 1.0, 241)
sol = ph.simulate(crank, [0.0, 0.0, 30.0], t)
fig = plt.figure(figsize=(5, 5), dpi=72, layout="constrained")
ax = fig.add_subplot(projection="3d")
anim = ph.plot.animate(sol, crank, frames=16, interval=120, ax=ax)
