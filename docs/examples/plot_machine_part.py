"""
A composite machine part
========================

A crank on a flywheel: a shaft, a flywheel, a crank web, a crank pin and a counterweight. Built
from solids, it has its mass properties at once. Its axis of largest moment is tilted from the
shaft, so it is dynamically unbalanced: spun freely about its shaft, the shaft wobbles.
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
# The shaft runs along z with the flywheel below; above it, the web lies along x, with the
# crank pin at x = 5.5 cm on one side and the counterweight on the other.
shaft = cylinder(0.012, 0.08)
flywheel = cylinder(0.1, 0.015).translated([0.0, 0.0, -0.02])
web = cuboid([0.08, 0.025, 0.012]).translated([0.025, 0.0, 0.026])
pin = cylinder(0.008, 0.025).translated([0.055, 0.0, 0.0445])
counterweight = cuboid([0.03, 0.05, 0.012]).translated([-0.025, 0.0, 0.026])
crank = shaft + flywheel + web + pin + counterweight
p = crank.principal()
print(crank)
print("principal axes (columns):")
print(p.axes.round(4))

# %%
# The product of inertia I_xz is not zero: the axis of the largest moment leans from the shaft.
tilt = np.degrees(np.arccos(abs(p.axes[2, 2])))
print(f"I_xz = {crank.inertia[0, 2]:.3e} kg m^2")
print(f"the largest axis is {tilt:.2f} deg from the shaft")

# %%
# The inertia as a simulator reads it: MuJoCo's ``<inertial>`` and URDF's.
print(crank.to_mjcf())
print(crank.to_urdf_inertial())

# %%
# Spun freely at 30 rad/s about its shaft, it turns about the fixed angular momentum L, which
# is not along the shaft: the shaft cones about L. Seen from above, the tip of the shaft's
# direction runs round a small circle about L.
t = np.linspace(0.0, 1.0, 2001)
sol = ph.simulate(crank, [0.0, 0.0, 30.0], t)
momentum = sol.angular_momentum_space[0] / np.linalg.norm(sol.angular_momentum_space[0])
shaft_axis = sol.orientation.apply([0.0, 0.0, 1.0])
wobble = np.degrees(np.arccos(np.clip(shaft_axis @ momentum, -1.0, 1.0)))
print(f"the shaft leans up to {wobble.max():.2f} deg from L")

fig, ax = plt.subplots(figsize=(5, 5), layout="constrained")
ax.plot(shaft_axis[:, 0], shaft_axis[:, 1], linewidth=0.8)
ax.plot(*momentum[:2], "+", color="tab:purple", markersize=12, label="L")
ax.set_aspect("equal")
ax.set_xlabel("x (space)")
ax.set_ylabel("y (space)")
ax.set_title("Direction of the shaft, seen from above")
ax.legend()

# %%
# The crank turning (16 frames of the first second).
fig = plt.figure(figsize=(5, 5), dpi=72, layout="constrained")
ax = fig.add_subplot(projection="3d")
anim = ph.plot.animate(sol, crank, frames=16, interval=120, ax=ax)
