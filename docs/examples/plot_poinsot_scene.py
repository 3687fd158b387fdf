"""
Poinsot's construction, live
============================

Poinsot's picture of a torque-free rotation: the body's energy ellipsoid ``w . I w = 2T``,
fixed in the body, rolls without slipping on the invariable plane, which is perpendicular to
the (fixed) angular momentum L at the distance ``2T / |L|`` from the fixed point. The point of
contact is the tip of omega; it traces the polhode on the ellipsoid and the herpolhode on the
plane. :func:`polhode.plot.scene` draws it frame by frame as an interactive plotly figure, with
the body itself turning inside its ellipsoid.

Here the T-handle of :doc:`the tennis-racket example <plot_tennis_racket>`, spun about its
intermediate axis: the orange end of its cross bar points toward L at the start and away from it
after each flip. The picture below is a headless Chromium's screenshot of this figure at
t = 2.78 s (tests/test_scene.py renders and steps it):

.. image:: /img/scene.png
   :alt: The T-handle inside its translucent energy ellipsoid, which touches the grey invariable
         plane at the tip of omega; L points up in purple; the polhode in red on the ellipsoid,
         the herpolhode in blue on the plane; the orange end of the bar points down after the
         flip.
"""

# sphinx_gallery_thumbnail_path = "img/scene.png"

import tempfile
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

import polhode as ph

# %%
# The T-handle: a shaft along z and a cross bar along x at its top (kg, m). Spun at 10 rad/s
# about its intermediate axis (the bar's), nudged about the smallest; turned so that L points up.
shaft = ph.Body.cylinder(mass=0.3, radius=0.01, length=0.2)
bar = ph.Body.cylinder(0.2, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
t_handle = shaft + bar.translated([0.0, 0.0, 0.1])
p = t_handle.principal()
spin = 10.0 * p.axes[:, 1] + 1e-3 * p.axes[:, 0]
flip = ph.analyze(t_handle, spin).flip_interval
up, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [t_handle.angular_momentum_body(spin)])
t = np.linspace(0.0, 2.2 * flip, 1001)
sol = ph.simulate(t_handle, spin, t, orientation0=up)

# %%
# The figure: 120 frames at evenly spaced output times (the polhode and the herpolhode go
# through up to 400 of the 1001), a Play button and a time slider. ``fig.show()`` displays it in
# Jupyter; the legend's entries hide and show each element; the mouse turns the camera.
fig = ph.plot.scene(sol, t_handle)
print(f"{len(fig.frames)} frames, t from 0 to {sol.t[-1]:.3f} s")
print(fig.layout.title.text.replace("<br>", ", "))
print(f"the body is drawn at {fig.layout.meta['body_scale']:.3g} rad/s per metre")

# %%
# A page that works offline: plotly.js is embedded (``include_plotlyjs=True``, plotly's
# default), so it opens without a network; ``auto_play=False`` waits for Play.
# ``ph.plot.scene(sol, t_handle, path="t_handle.html")`` writes the same page.
path = Path(tempfile.mkdtemp()) / "t_handle.html"
fig.write_html(path, include_plotlyjs=True, auto_play=False)
remote = path.read_text(encoding="utf-8").count('<script src="http')
print(f"{path.name}: {path.stat().st_size / 1e6:.1f} MB, scripts from the network: {remote}")
