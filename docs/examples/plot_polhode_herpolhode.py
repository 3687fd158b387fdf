"""
Polhode and herpolhode
======================

Poinsot's construction: in the body, the angular momentum runs along the polhode, where the
sphere ``|L|`` = const meets the energy ellipsoid; in space, omega traces the herpolhode on the
invariable plane, perpendicular to the fixed L.
"""

import matplotlib.pyplot as plt
import numpy as np

import polhode as ph

moments = [1.0, 2.0, 3.0]
omega0 = np.array([0.3, 1.0, 0.2])
a = ph.analyze(moments, omega0)
sol = ph.simulate(moments, omega0, np.linspace(0.0, 2 * a.period, 2001))
print(a)

# %%
# The polhodes at eight energies, the separatrices (dashed) through the intermediate axis, and
# this motion's L in red.
fig = plt.figure(figsize=(6, 6), layout="constrained")
ph.plot.polhode(traj=sol, ax=fig.add_subplot(projection="3d"))

# %%
# The herpolhode: omega in space, in the invariable plane. It is not closed: the body does not
# come back to its orientation after a period of omega.
fig, ax = plt.subplots(figsize=(5, 5), layout="constrained")
ph.plot.herpolhode(sol, ax=ax)
