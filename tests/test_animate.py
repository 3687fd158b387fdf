"""plot.animate: the drawn body, its principal axes, omega and L, frame by frame.

The frames are rendered through a matplotlib movie writer that reads the artists back after
each frame is drawn; the drawn axes are compared with the rotation of an independent
integration (scipy's DOP853 on Euler's equations with the quaternion, ``reference.rigid_body``)
and with the trajectory's own orientation. The drawn shapes are checked against the mass
properties by trimesh: the volume, centroid and inertia of each surface drawn are those of the
solid the body was built from.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode import _shapes
from reference import rigid_body

matplotlib = pytest.importorskip("matplotlib")
trimesh = pytest.importorskip("trimesh")
from matplotlib.animation import AbstractMovieWriter  # noqa: E402

LINES = ("axis1", "axis2", "axis3", "omega", "angular_momentum", "mark")


class Recorder(AbstractMovieWriter):
    """A movie writer that keeps, for every frame it is asked to grab, the data of the lines
    named in LINES (start and end points) and the title."""

    def __init__(self):
        super().__init__(fps=10)
        self.frames = []

    def setup(self, fig, outfile, dpi=None):
        super().setup(fig, outfile, dpi)

    def grab_frame(self, **savefig_kwargs):
        self.fig.canvas.draw()
        ax = self.fig.axes[0]
        frame = {}
        for line in ax.get_lines():
            if line.get_gid() in LINES:
                frame[line.get_gid()] = np.array(line.get_data_3d()).T  # (2, 3): start, end
        frame["title"] = ax.get_title()
        self.frames.append(frame)

    def finish(self):
        pass


def record(anim, tmp_path):
    writer = Recorder()
    anim.save(str(tmp_path / "unused"), writer=writer)
    return writer.frames


def t_handle():
    shaft = ph.Body.cylinder(0.3, 0.01, 0.2)
    bar = ph.Body.cylinder(0.2, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    return shaft + bar.translated([0.0, 0.0, 0.1])


def test_drawn_axes_omega_and_l_follow_an_independent_integration(tmp_path):
    body = t_handle()
    p = body.principal()
    # The flip: the axes turn over. Its timing is set by the distance of the energy from the
    # separatrix, Delta = sum I_i (I_i - I_2) w_i^2 ~ I_1 I_2 eps^2 for a spin 10 e_2 + eps e_1,
    # which one rounding of the moments (~1e-16 I_2^2 |w|^2) moves by 1e-16 (|w|/eps)^2 I_2/I_1
    # relative: mid-flip, any two double-precision integrations differ by about that much in
    # the directions. eps = 1e-3 made it ~1e-7 (an rtol 1e-12 reference and polhode disagreed
    # by 1.2e-7, rk4's disagreement growing as dt shrank: round-off amplified, not truncation);
    # eps = 3e-2 makes it ~1e-10, well inside the 1e-8 compared below, and still flips in 5 s.
    spin = 10.0 * p.axes[:, 1] + 3e-2 * p.axes[:, 0]
    q0 = Rotation.from_rotvec([0.3, -0.2, 0.5])
    t = np.linspace(0.0, 5.0, 101)
    sol = ph.simulate(body, spin, t, orientation0=q0)
    anim = ph.plot.animate(sol, body, frames=9)
    frames = record(anim, tmp_path)
    indices = anim.frame_indices
    assert len(frames) == len(indices) == 9
    np.testing.assert_array_equal(indices, np.linspace(0, 100, 9).round())

    omega_ref, q_ref = rigid_body(
        body.inertia, spin, q0.as_quat(), t[indices], lambda *_: np.zeros(3), rtol=1e-12
    )
    r_ref = Rotation.from_quat(q_ref).as_matrix()
    r_sol = Rotation.from_quat(sol.quaternion[indices]).as_matrix()
    l_space = r_ref[0] @ body.inertia @ spin
    flipped = []
    for frame, r, r_own, w, ti in zip(frames, r_ref, r_sol, omega_ref, t[indices], strict=True):
        assert frame["title"] == f"t = {ti:.4g} s"
        for k in range(3):
            start, end = frame[f"axis{k + 1}"]
            np.testing.assert_allclose(start, 0.0, atol=1e-15)  # free body: about its centre
            drawn = (end - start) / np.linalg.norm(end - start)
            # the trajectory's own rotation, to rounding
            np.testing.assert_allclose(drawn, r_own @ p.axes[:, k], atol=1e-13)
            # and the independent integration's (rtol 1e-12 over 5 s)
            np.testing.assert_allclose(drawn, r @ p.axes[:, k], atol=1e-8)
        start, end = frame["omega"]
        np.testing.assert_allclose(
            (end - start) / np.linalg.norm(end - start), r @ w / np.linalg.norm(w), atol=1e-8
        )
        start, end = frame["angular_momentum"]
        np.testing.assert_allclose(
            (end - start) / np.linalg.norm(end - start),
            l_space / np.linalg.norm(l_space),
            atol=1e-10,
        )
        flipped.append(float(np.dot(r @ p.axes[:, 1], l_space)) < 0)
    # The intermediate axis starts along L and turns over within the 5 s (over at ~1.2 s, back
    # at ~3 s).
    assert not flipped[0] and any(flipped)


def test_heavy_top_turns_about_its_pivot(tmp_path):
    top = ph.Body.cone(0.1, 0.04, 0.03)
    pivot = [0.0, 0.0, 0.03]  # the apex
    tilt = Rotation.from_rotvec([np.pi - 0.2, 0.0, 0.0])
    t = np.linspace(0.0, 0.5, 51)
    sol = ph.simulate(
        top, [0.0, 0.0, -150.0], t, orientation0=tilt, torque=ph.torque.Gravity(pivot=pivot)
    )
    anim = ph.plot.animate(sol, top, frames=6, origin=pivot)
    frames = record(anim, tmp_path)
    r = Rotation.from_quat(sol.quaternion[anim.frame_indices]).as_matrix()
    for frame, rk in zip(frames, r, strict=True):
        start, _ = frame["axis1"]
        # The axes start at the centre of mass, seen from the pivot held at the origin.
        np.testing.assert_allclose(start, rk @ (top.center_of_mass - pivot), atol=1e-15)


def test_saved_gif_and_jupyter_html_have_every_frame(tmp_path):
    from PIL import Image

    body = ph.Body.cuboid(1.0, [0.3, 0.1, 0.02])
    sol = ph.simulate(body, [0.0, 5.0, 0.05], np.linspace(0.0, 4.0, 41))
    path = tmp_path / "bar.gif"
    ph.plot.animate(sol, body, frames=5, path=str(path))
    with Image.open(path) as gif:
        assert gif.n_frames == 5
    html = ph.plot.animate(sol, body, frames=4).to_jshtml()
    assert html.count("data:image/png;base64") == 4


def test_animate_rejects_what_it_cannot_draw(tmp_path, monkeypatch):
    body = ph.Body.sphere(1.0, 0.1)
    t = np.linspace(0.0, 1.0, 11)
    sol = ph.simulate(body, [0.0, 0.0, 1.0], t)
    batch = ph.simulate(body, [[0.0, 0.0, 1.0]] * 2, t)
    with pytest.raises(ValueError, match="batch"):
        ph.plot.animate(batch, body)
    with pytest.raises(ValueError, match="orientation"):
        ph.plot.animate(ph.simulate(body, [0.0, 0.0, 1.0], t, orientation=False), body)
    with pytest.raises(TypeError, match="body"):
        ph.plot.animate(sol, "sphere")
    # Moments are taken (drawn as their inertia box), but they must be the trajectory's.
    with pytest.raises(ph.ArgumentError, match="does not match") as error:
        ph.plot.animate(sol, [1.0, 1.0, 1.0])
    assert error.value.argument == "body"
    ph.plot.animate(sol, [0.004, 0.004, 0.004], frames=2).to_jshtml()  # 2/5 m r^2
    with pytest.raises(ValueError, match="at least 1"):
        ph.plot.animate(sol, body, frames=0)
    with pytest.raises(ValueError, match="index"):
        ph.plot.animate(sol, body, frames=[0, 11])
    with pytest.raises(TypeError, match="frames"):
        ph.plot.animate(sol, body, frames=2.5)
    with pytest.raises(TypeError, match="space_axes"):
        ph.plot.animate(sol, body, frames=2, space_axes="yes")
    with pytest.raises(ValueError, match=".gif or .mp4"):
        ph.plot.animate(sol, body, frames=2, path=str(tmp_path / "x.txt"))
    import matplotlib.animation

    monkeypatch.setattr(matplotlib.animation.writers, "is_available", lambda name: False)
    with pytest.raises(RuntimeError, match="ffmpeg"):
        ph.plot.animate(sol, body, frames=2, path=str(tmp_path / "x.mp4"))
    assert not (tmp_path / "x.mp4").exists()


# -------------------------------------------------------------------------------------------------
# The shapes drawn are the bodies' (trimesh's volume, centroid and inertia of the surfaces)
# -------------------------------------------------------------------------------------------------


def as_trimesh(polygons):
    """A closed surface of polygons as one trimesh, fan-triangulated, outward."""
    triangles = [np.array([q[0], q[k], q[k + 1]]) for q in polygons for k in range(1, len(q) - 1)]
    vertices = np.concatenate(triangles)
    mesh = trimesh.Trimesh(vertices, np.arange(len(vertices)).reshape(-1, 3), process=True)
    if mesh.volume < 0:
        mesh.invert()
    return mesh


SOLIDS = [
    ("sphere", (2.0, 0.3)),
    ("cuboid", (2.0, [0.3, 0.2, 0.1])),
    ("cylinder", (2.0, 0.1, 0.5)),
    ("tube", (2.0, 0.05, 0.1, 0.3)),
    ("cone", (2.0, 0.1, 0.4)),
    ("ellipsoid", (2.0, [0.3, 0.2, 0.1])),
    ("torus", (2.0, 0.3, 0.1)),
    ("capsule", (2.0, 0.1, 0.3)),
]


@pytest.mark.parametrize(("kind", "args"), SOLIDS, ids=[s[0] for s in SOLIDS])
def test_drawn_solid_has_the_solids_centre_and_inertia(kind, args):
    # Moved off the origin and turned, so that the placement is checked too.
    turn = Rotation.from_rotvec([0.4, -0.7, 0.2])
    body = getattr(ph.Body, kind)(*args).rotated(turn).translated([0.5, -0.2, 1.0])
    mesh = as_trimesh(_shapes.surface(_shapes.of(body), resolution=192))
    mesh.density = body.mass / mesh.volume
    size = np.sqrt(np.trace(body.inertia) / body.mass)
    # The inscribed polygons of 192 sides miss 1 - sin(x)/x ~ 1.8e-4 of a disc's area.
    np.testing.assert_allclose(mesh.center_mass, body.center_of_mass, atol=1e-4 * size)
    np.testing.assert_allclose(
        mesh.moment_inertia, body.inertia, atol=2e-3 * np.max(np.abs(body.inertia))
    )


def test_composite_parts_are_drawn_where_they_were_put():
    body = t_handle().rotated(Rotation.from_rotvec([0.0, 0.5, 0.0])).scaled(length_scale=2.0)
    shape = _shapes.of(body)
    assert [p.kind for p in shape] == ["cylinder", "cylinder"]
    masses = (0.3, 0.2)
    volumes = [as_trimesh(_shapes.surface((p,), resolution=192)) for p in shape]
    centre = sum(m * v.center_mass for m, v in zip(masses, volumes, strict=True)) / sum(masses)
    np.testing.assert_allclose(centre, body.center_of_mass, atol=1e-6)
    # The bar (0.12 long, scaled to 0.24) lies along x turned by the rotation: 0.24 long there.
    along = Rotation.from_rotvec([0.0, 0.5, 0.0]).apply([1.0, 0.0, 0.0])
    assert np.ptp(volumes[1].vertices @ along) == pytest.approx(0.24, rel=1e-12)
    assert np.ptp(volumes[0].vertices @ along) == pytest.approx(0.04, rel=1e-12)  # the shaft


def test_point_masses_are_balls_at_their_positions():
    positions = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    body = ph.Body.point_masses([8.0, 1.0, 1.0], positions).translated([0.0, 0.0, 3.0])
    balls = _shapes.surface(_shapes.of(body), resolution=24)
    per_ball = len(balls) // 3
    for k in range(3):
        points = np.concatenate(balls[k * per_ball : (k + 1) * per_ball])
        centre = (points.max(axis=0) + points.min(axis=0)) / 2
        np.testing.assert_allclose(centre, positions[k] + [0.0, 0.0, 3.0], atol=1e-12)
    radii = [np.ptp(np.concatenate(balls[k * per_ball : (k + 1) * per_ball])[:, 2]) for k in (0, 1)]
    assert radii[0] == pytest.approx(2.0 * radii[1])  # volume with mass: (8/1)^(1/3)


def test_a_body_without_geometry_is_drawn_as_its_equivalent_ellipsoid():
    rng = np.random.default_rng(3)
    points = rng.normal(size=(50, 3)) * [0.3, 0.2, 0.1]
    cloud = ph.Body.point_masses(rng.uniform(1.0, 2.0, 50), points)
    body = ph.Body.from_inertia(cloud.mass, cloud.inertia, center_of_mass=cloud.center_of_mass)
    mesh = as_trimesh(_shapes.surface(_shapes.of(body), resolution=192))
    mesh.density = body.mass / mesh.volume
    np.testing.assert_allclose(mesh.center_mass, body.center_of_mass, atol=1e-12)
    np.testing.assert_allclose(
        mesh.moment_inertia, body.inertia, atol=2e-3 * np.max(np.abs(body.inertia))
    )
    # Added to a solid, it keeps its place as a part of the composite.
    composite = body + ph.Body.sphere(1.0, 0.1).translated([2.0, 0.0, 0.0])
    assert [p.kind for p in _shapes.of(composite)] == ["ellipsoid", "sphere"]


def test_one_end_is_marked_so_that_the_flip_is_seen(tmp_path):
    """The T-handle spun about its intermediate axis (its cross bar, symmetric end to end):
    the end of the bar that points toward L at t0 is orange, and the ball beyond it is carried
    by the rotation, toward L at first and away from it after the flip."""
    body = t_handle()
    p = body.principal()
    # In closed form: the bar (0.12 long, radius 0.01, along x at z = 0.1) is the
    # intermediate axis; the centre of mass is on the z axis.
    com_z = (0.3 * 0.0 + 0.2 * 0.1) / 0.5
    np.testing.assert_allclose(body.center_of_mass, [0.0, 0.0, com_z], atol=1e-15)
    assert abs(p.axes[0, 1]) == pytest.approx(1.0)
    spin = 10.0 * p.axes[:, 1] + 3e-2 * p.axes[:, 0]
    t = np.linspace(0.0, 5.0, 101)
    sol = ph.simulate(body, spin, t)
    anim = ph.plot.animate(sol, body, frames=21)
    assert anim.mark == 1
    toward = np.sign((body.inertia @ spin)[0])  # the bar's end along +x or -x toward L
    np.testing.assert_allclose(anim.mark_direction, [toward, 0.0, 0.0], atol=1e-15)
    # The orange faces: the last fifth of the bar along that end, nothing else.
    surface = next(c for c in anim._fig.axes[0].collections if c.get_gid() == "body")
    colors = surface.get_facecolor()
    orange = np.all(np.abs(colors[:, :3] - matplotlib.colors.to_rgb("#ff7f0e")) < 0.25, axis=1)
    assert orange.any() and not orange.all()
    # The ball: on the bar's axis line, beyond its end (x = 0.06 toward L), carried by R(t).
    frames = record(anim, tmp_path)
    r = Rotation.from_quat(sol.quaternion[anim.frame_indices]).as_matrix()
    l_space = sol.angular_momentum_space[0]
    end = np.array([0.06 * toward, 0.0, 0.1]) - body.center_of_mass
    sides = []
    for frame, rk in zip(frames, r, strict=True):
        (ball,) = frame["mark"]
        beyond = rk.T @ ball - end  # body coordinates, from the end
        np.testing.assert_allclose(beyond[1:], 0.0, atol=1e-12)
        assert 0.0 < beyond[0] * toward < 0.02  # just beyond the end, along the bar
        sides.append(float(np.dot(ball - rk @ np.array([0.0, 0.0, 0.1 - com_z]), l_space)))
    assert sides[0] > 0 and min(sides) < 0  # toward L at first, then turned over


class _LeftoverNumpy:
    """numpy, but ``empty`` returns arrays full of 1e308, as leftover bits may be."""

    def __getattr__(self, name):
        return getattr(np, name)

    @staticmethod
    def empty(shape, *args, **kwargs):
        out = np.empty(shape, *args, **kwargs)
        if out.dtype.kind == "f":
            out.fill(1e308)
        return out


def test_the_surface_draws_whatever_new_arrays_hold(monkeypatch):
    """matplotlib's Poly3DCollection keeps polygons of several lengths in an array from
    np.empty and projects its unused entries too (matplotlib 3.11): leftover bits overflowed now
    and then, numpy's RuntimeWarning at draw time (an error here: pytest's filterwarnings). The
    capped T-handle's polygons have 3 to 6 vertices; animate hands them over with one length
    (vertices repeated in order): with np.empty's arrays full of 1e308 in matplotlib's 3-D
    module, every frame draws without a warning, each polygon with its own vertices."""
    from mpl_toolkits.mplot3d import art3d

    body = t_handle()
    sol = ph.simulate(body, [0.3, 10.0, 0.2], np.linspace(0.0, 1.0, 11))
    monkeypatch.setattr(art3d, "np", _LeftoverNumpy())
    anim = ph.plot.animate(sol, body, frames=3)
    anim.to_jshtml()
    surface = next(c for c in anim._fig.axes[0].collections if c.get_gid() == "body")
    faces = np.asarray(surface._faces)  # the 3-D polygons matplotlib holds, in body axes
    r = Rotation.from_quat(sol.quaternion[anim.frame_indices[-1]]).as_matrix()
    lengths = {len(q) for q in faces}
    assert len(lengths) == 1 and np.all(np.abs(faces) < 1.0), lengths
    # Each drawn polygon, back in body axes, lies on one solid's surface: its distinct
    # vertices are 3 or more, in a plane (a face of the cylinders' polygonal surfaces).
    for q in faces @ r:
        distinct = np.unique(q.round(12), axis=0)
        assert len(distinct) >= 3
        centred = distinct - distinct.mean(axis=0)
        assert np.linalg.svd(centred, compute_uv=False)[-1] < 1e-9
