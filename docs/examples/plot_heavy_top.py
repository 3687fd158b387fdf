"""
The heavy top
=============

A squat cone spinning on its apex under gravity: a fast top. Its axis precesses slowly about
the vertical and nods (nutation) quickly, as the gyroscopic approximation predicts.
"""

import matplotlib.pyplot as plt
import numpy as np
from scipy.spatial.transform import Rotation

import polhode as ph

# %%
# A 100 g cone of base radius 4 cm, 3 cm from its base to its apex. Its origin is the centre of
# its base, its apex at z = 3 cm: that is the pivot, on the floor. Turned apex down, with its axis
# 0.3 rad from the vertical, and spun at 150 rad/s about its axis.
top = ph.Body.cone(0.1, 0.04, 0.03)
apex = np.array([0.0, 0.0, 0.03])
tilted = Rotation.from_rotvec([np.pi - 0.3, 0.0, 0.0])
t = np.linspace(0.0, 4.0, 4001)
sol = ph.simulate(
    top, [0.0, 0.0, 150.0], t, orientation0=tilted, torque=ph.torque.Gravity(pivot=apex)
)
print(sol)

# %%
# The top's axis in space (apex to base), its tilt from the vertical and the azimuth of its
# precession.
up = sol.orientation.apply([0.0, 0.0, -1.0])
tilt = np.arccos(up[:, 2])
azimuth = np.unwrap(np.arctan2(up[:, 1], up[:, 0]))
rate = np.polyfit(t, azimuth, 1)[0]

# %%
# The gyroscopic (fast-top) precession rate is m g l / (I_s omega_s), with l the distance from
# the apex to the centre of mass and I_s the moment about the axis.
m, g = top.mass, 9.81
arm = np.linalg.norm(top.center_of_mass - apex)
i_s = 0.3 * m * 0.04**2
gyroscopic = m * g * arm / (i_s * 150.0)
print(f"precession: {abs(rate):.3f} rad/s simulated, {gyroscopic:.3f} gyroscopic")
print(f"nutation: the tilt nods between {tilt.min():.4f} and {tilt.max():.4f} rad")

fig, (top_view, nod) = plt.subplots(1, 2, figsize=(9, 4), layout="constrained")
top_view.plot(up[:, 0], up[:, 1], linewidth=0.8)
top_view.plot(up[:1, 0], up[:1, 1], "o", color="tab:red", label="t = 0")
top_view.set_aspect("equal")
top_view.set_xlabel("x")
top_view.set_ylabel("y")
top_view.set_title("Tip of the axis seen from above: precession")
top_view.legend()
nod.plot(t[:400], tilt[:400])
nod.set_xlabel("t (s)")
nod.set_ylabel("tilt from the vertical (rad)")
nod.set_title("Nutation")
