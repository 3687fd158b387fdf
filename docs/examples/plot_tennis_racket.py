"""
The tennis-racket flip
======================

A T-handle spun about its axis of intermediate moment turns over again and again: the
Dzhanibekov effect, or tennis-racket theorem. :func:`polhode.analyze` predicts when, the exact
solution shows it, and :func:`polhode.plot.animate` draws it.
"""

import matplotlib.pyplot as plt
import numpy as np
from scipy.spatial.transform import Rotation

import polhode as ph

# %%
# The body: a shaft along z and a cross bar along x at its top (masses in kg, lengths in m).
shaft = ph.Body.cylinder(mass=0.3, radius=0.01, length=0.2)
bar = ph.Body.cylinder(0.2, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
t_handle = shaft + bar.translated([0.0, 0.0, 0.1])
p = t_handle.principal()
print(t_handle)
print(p)

# %%
# Spin it at 10 rad/s about the intermediate axis (``p.axes[:, 1]``, axis 2), nudged by
# 1e-3 rad/s about the smallest. The analysis says the intermediate axis is unstable and how
# often the handle flips.
spin = 10.0 * p.axes[:, 1] + 1e-3 * p.axes[:, 0]
a = ph.analyze(t_handle, spin)
print(a.regime, a.axis_stability)
print(f"a flip every {a.flip_interval:.4f} s")
print(f"growth rate {a.linearized['rate']:.3f} /s")

# %%
# The exact solution, with the body turned so that its angular momentum points up in space.
# The component of omega along the intermediate axis changes sign at every flip.
momentum = t_handle.angular_momentum_body(spin)
up, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [momentum])
t = np.linspace(0.0, 4.4 * a.flip_interval, 2001)
sol = ph.simulate(t_handle, spin, t, orientation0=up)
along = sol.omega @ p.axes  # omega in principal axes
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
for k, role in enumerate(("smallest", "intermediate", "largest")):
    ax.plot(t, along[:, k], label=f"$\\omega_{k + 1}$ ({role} moment)")
for k in range(1, 5):
    ax.axvline(k * a.flip_interval - a.flip_interval / 2, color="0.8", zorder=0)
ax.set_xlabel("t (s)")
ax.set_ylabel("$\\omega$ in the principal axes (rad/s)")
ax.set_title("The T-handle's angular velocity: a flip every half period")
ax.legend(loc="lower right")

# %%
# The handle in space: L (dashed) stays fixed; the intermediate axis (green) starts along it and
# turns over, while omega (black) wanders. The frames are 24 of the 2001 output times.
fig = plt.figure(figsize=(5, 5), dpi=72, layout="constrained")
ax = fig.add_subplot(projection="3d")
anim = ph.plot.animate(sol, t_handle, frames=24, interval=120, ax=ax)
