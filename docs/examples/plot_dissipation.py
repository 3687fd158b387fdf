"""
Dissipation: the major-axis rule
================================

A body spun about its axis of smallest moment, carrying a spherical damper (a ball in a
viscous cavity, the Kane damper). Friction takes kinetic energy T but no angular momentum, so T
falls at fixed ``|L|`` until the body spins about its axis of largest moment: the reason
Explorer 1 tumbled in 1958.
"""

import matplotlib.pyplot as plt
import numpy as np

import polhode as ph
from polhode import plot

# %%
# Principal moments 1, 4, 5 (the damper locked), spun at 2 rad/s about the smallest axis. The
# linearised energy-sink rate says how fast a small nutation grows away from that axis.
damper = ph.rotors.SphericalDamper(inertia=0.2, damping=0.1)
moments = [1.0, 4.0, 5.0]
omega0 = [2.0, 0.01, 0.01]
analysis = ph.analyze(moments, omega0, rotors=[damper])
print(
    f"nutation rate {analysis.nutation_rate:.4f} 1/s: "
    f"grows e-fold every {analysis.nutation_time_constant:.1f} s"
)

# %%
# The motion with the damper (dop853, the default for rotors). T falls from its start to
# L^2 / (2 I3), the energy of a spin about the largest axis, crossing the separatrix's energy
# L^2 / (2 I2) on the way; ``|L|`` stays where it was.
t = np.linspace(0.0, 400.0, 4001)
sol = ph.simulate(moments, omega0, t, rotors=[damper])
ell = np.linalg.norm(sol.angular_momentum_body, axis=-1)
print(f"T: {sol.energy[0]:.5f} -> {sol.energy[-1]:.5f} (L^2/(2 I3) = {ell[0] ** 2 / 10:.5f})")
print(f"|L| drift: {np.max(np.abs(ell / ell[0] - 1)):.1e}")

fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
plot.dissipation(sol, ax=left)
plot.omega(sol, ax=right)
right.set_title("The spin moves from axis 1 to axis 3")

# %%
# The angular momentum in the body, on the sphere ``|L|`` = const: coloured by time, it
# spirals away from axis 1, crosses the separatrix and settles on axis 3.
fig = plt.figure(figsize=(7, 5.5), layout="constrained")
plot.polhode(traj=sol, ax=fig.add_subplot(projection="3d"))
plt.show()
