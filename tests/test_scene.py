"""polhode.plot.scene: Poinsot's construction as a plotly figure, checked frame by frame against
the geometry computed here from the trajectory (rotation matrices from the quaternions by the
textbook formula, inertia tensors in closed form), then rendered by a real browser.

The browser test loads the written HTML in headless Chromium (Debian's ``chromium``, WebGL on
the CPU through SwiftShader; tests/browser.py), takes a screenshot, steps the animation and
presses Play. It skips only when no Chromium is on the PATH and ``CI`` is not set; in CI it
runs (.ci/run installs chromium). With ``POLHODE_SCENE_PNG=path`` it also saves its screenshot
there: docs/img/scene.png was made so (a 256-colour PNG).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

go = pytest.importorskip("plotly.graph_objects")

import polhode as ph  # noqa: E402
from polhode import plot  # noqa: E402
from reference import cuboid, parallel_axis  # noqa: E402

F32 = float(np.finfo(np.float32).eps)

#: A bar spun about its intermediate axis (y), nudged: it flips (about 1.6 s between flips).
SIZE = (0.3, 0.1, 0.02)
OMEGA0 = (0.05, 5.0, 0.05)


def quaternion_matrix(q):
    """Body-to-space rotation of a unit quaternion (x, y, z, w), the textbook formula."""
    x, y, z, w = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def trace(fig, uid, frame=None):
    """The (n, 3) points of the trace ``uid`` in frame ``frame`` (None: the figure's data)."""
    index = [t.uid for t in fig.data].index(uid)
    data = fig.data[index] if frame is None else fig.frames[frame].data[index]
    return np.column_stack([np.asarray(data.x), np.asarray(data.y), np.asarray(data.z)]).astype(
        np.float64
    )


@pytest.fixture(scope="module")
def bar():
    return ph.Body.cuboid(1.0, SIZE)


@pytest.fixture(scope="module")
def bar_inertia():
    return cuboid(1.0, SIZE).inertia


@pytest.fixture(scope="module")
def flipping(bar):
    return ph.simulate(bar, OMEGA0, np.linspace(0.0, 6.0, 601))


def construction(traj, k, inertia):
    """omega in space, R, T, L in space, the plane's normal and distance at output time k."""
    r = quaternion_matrix(traj.quaternion[k])
    w = traj.omega[k]
    energy = 0.5 * w @ inertia @ w
    momentum = r @ inertia @ w
    normal = momentum / np.linalg.norm(momentum)
    return r @ w, r, energy, momentum, normal, 2.0 * energy / np.linalg.norm(momentum)


def sampled_times(points, omega, atol):
    """The output times (indices into ``omega``) the points are omega at, in order."""
    found = []
    for point in points:
        gaps = np.max(np.abs(omega - point), axis=1)
        j = int(np.argmin(gaps))
        assert gaps[j] <= atol, (point, omega[j])
        found.append(j)
    assert all(a < b for a, b in zip(found, found[1:], strict=False))
    return found


def check_frames(fig, traj, inertia, rtol, moving=False):
    """Every frame's Poinsot construction against the one computed here, to ``rtol``."""
    meta = fig.layout.meta
    indices = meta["frame_indices"]
    assert len(fig.frames) == len(indices)
    tensor_inverse = np.linalg.inv(inertia)
    moments, axes = np.linalg.eigh(inertia)
    for f, k in enumerate(indices):
        tip, r, energy, momentum, normal, distance = construction(traj, k, inertia)
        scale = np.linalg.norm(tip)
        space_inertia = r @ inertia @ r.T

        def on_ellipsoid(points, tol=rtol, inertia=space_inertia, energy=energy):
            values = np.einsum("ni,ij,nj->n", points, inertia, points)
            np.testing.assert_allclose(values, 2.0 * energy, rtol=tol)

        # The contact point is omega's tip: on the ellipsoid, on the plane, where the
        # ellipsoid's normal (the gradient I w) is L's direction: the plane is tangent there.
        contact = trace(fig, "contact", f)
        np.testing.assert_allclose(contact[0], tip, rtol=0, atol=rtol * scale)
        on_ellipsoid(contact)
        assert abs(contact[0] @ normal - distance) <= rtol * scale
        gradient = space_inertia @ contact[0]
        assert np.linalg.norm(np.cross(gradient / np.linalg.norm(gradient), normal)) <= 10 * rtol
        # The arrow of omega ends at the contact; its shaft starts at the fixed point.
        np.testing.assert_allclose(trace(fig, "omega_head", f)[0], tip, atol=rtol * scale)
        shaft = trace(fig, "omega", f)
        np.testing.assert_allclose(shaft[0], 0.0, atol=0)
        assert np.linalg.norm(np.cross(shaft[1], tip)) <= 10 * rtol * scale * np.linalg.norm(
            shaft[1]
        )
        # The plane: perpendicular to L at 2T/|L| (its centre the foot of the perpendicular).
        disc = trace(fig, "plane", f)
        np.testing.assert_allclose(disc @ normal, distance, rtol=rtol)
        np.testing.assert_allclose(disc[0], distance * normal, atol=rtol * scale)
        across = np.cross(disc[1] - disc[0], disc[5] - disc[0])
        np.testing.assert_allclose(across / np.linalg.norm(across), normal, atol=10 * rtol)
        # The ellipsoid w.Iw = 2T turned with the body: on one side of the plane, touching it
        # (its support along L, sqrt(2T n.I^-1 n) in body axes, is the plane's distance).
        ellipsoid = trace(fig, "ellipsoid", f)
        on_ellipsoid(ellipsoid)
        assert np.max(ellipsoid @ normal) <= distance * (1 + rtol)
        n_body = r.T @ normal
        support = np.sqrt(2.0 * energy * n_body @ tensor_inverse @ n_body)
        assert abs(support - distance) <= 1e-12 * distance
        # The polhode: omega at the output times up to this one, carried with the body: on
        # this frame's ellipsoid (T conserved to the method's drift), ending at the contact.
        polhode = trace(fig, "polhode", f)
        on_ellipsoid(polhode, tol=max(rtol, 1e-5) if not moving else 1.0)
        np.testing.assert_allclose(polhode[-1], tip, atol=rtol * scale)
        carried = polhode @ r  # back in body axes
        shown = sampled_times(carried, traj.omega[: k + 1], rtol * scale)
        assert shown[-1] == k and all(i in shown for i in indices if i <= k)
        # The herpolhode: omega in space at the same times, on the plane, ending at the contact.
        herpolhode = trace(fig, "herpolhode", f)
        expected = np.array([quaternion_matrix(traj.quaternion[j]) @ traj.omega[j] for j in shown])
        np.testing.assert_allclose(herpolhode, expected, atol=rtol * scale)
        if not moving:
            # On this frame's plane, to rounding and to the method's drift of the plane (L in
            # space and 2T/|L| at each point's own time, against this frame's).
            for j, point in zip(shown, herpolhode, strict=True):
                _, _, _, _, normal_j, distance_j = construction(traj, j, inertia)
                drift = np.linalg.norm(point) * np.linalg.norm(normal_j - normal) + abs(
                    distance_j - distance
                )
                assert abs(point @ normal - distance) <= rtol * scale + 1.01 * drift
        # L: along its direction from the fixed point, fixed without a torque.
        shaft = trace(fig, "L", f)
        np.testing.assert_allclose(shaft[0], 0.0, atol=0)
        np.testing.assert_allclose(shaft[1] / np.linalg.norm(shaft[1]), normal, atol=10 * rtol)
        # The principal axes: the ellipsoid's, from -sqrt(2T/I_a) to +sqrt(2T/I_a).
        for a in range(3):
            ends = trace(fig, f"axis{a + 1}", f)
            half = np.sqrt(2.0 * energy / moments[a]) * (r @ axes[:, a])
            assert min(
                np.max(np.abs(ends - np.stack([-half, half]))),
                np.max(np.abs(ends - np.stack([half, -half]))),
            ) <= rtol * np.linalg.norm(half)
        # Everything inside the scene's fixed cube.
        half_width = fig.layout.scene.xaxis.range[1]
        for uid in ("body", "ellipsoid", "plane", "L_head", "omega_head", "herpolhode"):
            assert np.max(np.abs(trace(fig, uid, f))) <= half_width


@pytest.mark.parametrize(
    ("method", "options", "rtol"),
    [
        ("exact", {}, 8 * F32),
        ("rk4", {"dt": 1e-3}, 8 * F32),
        ("splitting", {"dt": 1e-3}, 8 * F32),
        ("midpoint", {"dt": 1e-3}, 8 * F32),
        ("dop853", {}, 8 * F32),
    ],
)
def test_every_frame_is_poinsots_construction(bar, bar_inertia, method, options, rtol):
    traj = ph.simulate(bar, OMEGA0, np.linspace(0.0, 6.0, 601), method=method, **options)
    fig = plot.scene(traj, bar, frames=25)
    check_frames(fig, traj, bar_inertia, rtol)


def test_float64_holds_the_construction_to_rounding(flipping, bar, bar_inertia):
    fig = plot.scene(flipping, bar, frames=12, dtype=np.float64)
    check_frames(fig, flipping, bar_inertia, 1e-12)


def test_the_body_turns_with_the_trajectory_and_its_end_is_marked(flipping, bar, bar_inertia):
    fig = plot.scene(flipping, bar, frames=40, dtype=np.float64)
    meta = fig.layout.meta
    scale, indices = meta["body_scale"], meta["frame_indices"]
    # Marked: the axis spun about (y, the intermediate one: mark 1), its end toward L at t0.
    assert meta["mark"] == 1
    np.testing.assert_allclose(meta["mark_direction"], [0.0, 1.0, 0.0], atol=1e-12)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * (
        np.asarray(SIZE) / 2
    )
    body = fig.data[0]
    faces = np.column_stack([body.i, body.j, body.k])
    colors = np.asarray(body.facecolor)
    signs = []
    for f, k in enumerate(indices):
        r = quaternion_matrix(flipping.quaternion[k])
        drawn = trace(fig, "body", f)
        # In the body's axes (R^T, divided by the scale), every vertex is on the box's
        # surface and every corner is one of them: the body turned by R(q_k).
        local = drawn @ r / scale
        ratio = np.abs(local) / (np.asarray(SIZE) / 2)
        assert np.all(ratio <= 1 + 1e-12)
        assert np.all(np.abs(np.max(ratio, axis=1) - 1.0) <= 1e-12)
        for corner in corners:
            assert np.min(np.linalg.norm(local - corner, axis=1)) <= 1e-12
        # The cap: the faces beyond 0.6 of the half-height along +y, and only those; the ball
        # at the centre of the end face.
        centroids = local[faces].mean(axis=1)[:, 1]
        orange = colors == "#ff7f0e"
        assert orange.any() and (~orange).any()
        assert np.all(centroids[orange] > 0.6 * SIZE[1] / 2 - 1e-12)
        assert np.all(centroids[~orange] < 0.6 * SIZE[1] / 2 + 1e-12)
        ball = trace(fig, "mark", f)[0]
        np.testing.assert_allclose(ball, scale * r @ [0.0, SIZE[1] / 2, 0.0], atol=1e-12)
        _, _, _, momentum, _, _ = construction(flipping, k, bar_inertia)
        signs.append(np.sign(ball @ momentum))
    # Toward L at t0, away from it after the flip: the flip is seen.
    assert signs[0] > 0 and min(signs) < 0


def test_a_stable_spin_keeps_its_marked_end_toward_l(bar):
    traj = ph.simulate(bar, [0.05, 0.05, 5.0], np.linspace(0.0, 6.0, 301))
    fig = plot.scene(traj, bar, frames=30)
    assert fig.layout.meta["mark"] == 2
    # Spun about its largest axis: a stable spin, and the title does not speak of a flip.
    assert "(L circulates about axis 3 (I3): a stable spin)" in fig.frames[0].layout.title.text
    for f, k in enumerate(fig.layout.meta["frame_indices"]):
        momentum = quaternion_matrix(traj.quaternion[k]) @ bar.inertia @ traj.omega[k]
        assert trace(fig, "mark", f)[0] @ momentum > 0


def test_legend_titles_units_and_controls(flipping, bar):
    fig = plot.scene(flipping, bar, frames=10)
    names = " | ".join(t.name or "" for t in fig.data if t.showlegend is not False)
    for words in (
        "body",
        "marked end",
        "I1 axis",
        "I2 axis",
        "I3 axis",
        "energy ellipsoid",
        "polhode",
        "invariable plane",
        "herpolhode",
        "L, fixed",
        "kg m^2/s",
        "omega (rad/s)",
        "contact point",
    ):
        assert words in names, words
    for axis in (fig.layout.scene.xaxis, fig.layout.scene.yaxis, fig.layout.scene.zaxis):
        assert axis.title.text.endswith("(rad/s)")
        assert list(axis.range) == list(fig.layout.scene.xaxis.range)
        assert axis.autorange is False
    assert fig.layout.scene.aspectmode == "cube"
    # Spun near its intermediate axis, the bar turns over: the title says so, with analyze's
    # interval and the axis L circulates about, numbered as a person reads it (here the
    # largest, I3), never the regime's code name.
    analysis = ph.analyze(bar, OMEGA0)
    assert analysis.turns_over and analysis.regime == "about_largest_axis"
    words = (
        f"L circulates about axis 3 (I3); the body turns over every "
        f"{analysis.flip_interval:.4g} s"
    )
    times = flipping.t[fig.layout.meta["frame_indices"]]
    for frame, t in zip(fig.frames, times, strict=True):
        text = frame.layout.title.text
        assert f"Poinsot's construction ({words})<br>" in text
        assert "regime" not in text and "about_largest_axis" not in text
        assert re.search(r"t = ([-0-9.e+]+) s", text).group(1) == f"{t:.4g}"
    (menu,) = fig.layout.updatemenus
    assert [b.label for b in menu.buttons] == ["Play", "Pause"]
    assert menu.buttons[0].method == "animate"
    (slider,) = fig.layout.sliders
    assert [list(s.args[0]) for s in slider.steps] == [[f.name] for f in fig.frames]
    assert slider.currentvalue.suffix == " s"


def test_other_units_in_every_label(flipping, bar):
    fig = plot.scene(flipping, bar, frames=5, units={"time": "min", "length": "mm"})
    assert fig.layout.scene.xaxis.title.text == "x, space (rad/min)"
    names = " | ".join(t.name or "" for t in fig.data)
    assert "kg mm^2/min" in names and "omega (rad/min)" in names and "rad/min per mm" in names
    assert fig.layout.sliders[0].currentvalue.suffix == " min"
    assert fig.frames[-1].layout.title.text.endswith(f"t = {flipping.t[-1]:.4g} min")
    assert " turns over every " in fig.frames[-1].layout.title.text
    assert fig.frames[-1].layout.title.text.split("<br>")[0].endswith(" min)")
    with pytest.raises(ph.ArgumentError, match="angle") as error:
        plot.scene(flipping, bar, units={"angle": "deg"})
    assert error.value.argument == "units"
    with pytest.raises(ph.ArgumentError) as error:
        plot.scene(flipping, bar, units={"time": ""})
    assert error.value.argument == "units"
    with pytest.raises(TypeError, match="units"):
        plot.scene(flipping, bar, units="SI")


def test_output_times_too_far_apart_to_draw_are_said(bar):
    with pytest.warns(UserWarning, match="has 2 output times"):
        fig = plot.scene(ph.simulate(bar, OMEGA0, [0.0, 6.0]), bar)
    assert len(fig.frames) == 2
    # An end time gives output times that resolve the motion: no warning (they are errors).
    plot.scene(ph.simulate(bar, OMEGA0, 6.0), bar, frames=5)
    # 61 output times over 60 s: omega turns by more than 20 degrees between two.
    with pytest.warns(UserWarning, match="more output times"):
        plot.scene(ph.simulate(bar, OMEGA0, np.linspace(0.0, 60.0, 61)), bar, frames=5)
    # Dense enough, but only 50 of them drawn.
    dense = ph.simulate(bar, OMEGA0, np.linspace(0.0, 60.0, 6001))
    with pytest.warns(UserWarning, match="raise `curve_points`"):
        plot.scene(dense, bar, frames=5, curve_points=50)
    plot.scene(dense, bar, frames=5, curve_points=3000)  # no warning (they are errors here)


def test_without_a_body_the_trajectorys_moments(flipping):
    moments = [1.0, 2.0, 3.0]
    traj = ph.simulate(moments, [0.3, 1.0, 0.2], np.linspace(0.0, 10.0, 401))
    fig = plot.scene(traj, frames=15)
    check_frames(fig, traj, np.diag(moments), 8 * F32)
    assert fig.data[0].name.startswith("inertia box")
    # Moments in another order are the body's own axes.
    traj = ph.simulate([3.0, 1.0, 2.0], [0.3, 1.0, 0.2], np.linspace(0.0, 10.0, 401))
    check_frames(plot.scene(traj, frames=8), traj, np.diag([3.0, 1.0, 2.0]), 8 * F32)


def test_without_a_body_a_tensor_is_found_from_l_and_omega():
    from scipy.spatial.transform import Rotation

    r = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix()
    tensor = r @ np.diag([1.0, 2.0, 3.0]) @ r.T
    traj = ph.simulate(tensor, [0.3, 1.0, 0.2], np.linspace(0.0, 10.0, 401))
    check_frames(plot.scene(traj, frames=8), traj, tensor, 8 * F32)
    # A steady spin about a principal axis spans one direction only: the body is needed.
    steady = ph.simulate(tensor, r[:, 2], np.linspace(0.0, 1.0, 11))
    with pytest.raises(ph.ArgumentError, match="pass that Body") as error:
        plot.scene(steady)
    assert error.value.argument == "body"


def test_a_mesh_body_is_drawn_from_its_vertices():
    # An irregular tetrahedron, wound outward.
    vertices = np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.2, 0.0], [0.05, 0.04, 0.1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    body = ph.Body.mesh(vertices, faces, mass=1.0)
    traj = ph.simulate(body, [0.5, 1.0, 8.0], np.linspace(0.0, 3.0, 121))
    fig = plot.scene(traj, body, frames=12, dtype=np.float64)
    check_frames(fig, traj, body.inertia, 1e-12)
    scale = fig.layout.meta["body_scale"]
    com = vertices.mean(axis=0)  # a tetrahedron's centroid
    np.testing.assert_allclose(body.center_of_mass, com, atol=1e-15)
    for f, k in enumerate(fig.layout.meta["frame_indices"]):
        drawn = trace(fig, "body", f)
        expected = scale * (vertices - com) @ quaternion_matrix(traj.quaternion[k]).T
        for point in expected:
            assert np.min(np.linalg.norm(drawn - point, axis=1)) <= 1e-12 * scale


def test_a_large_mesh_is_simplified():
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.1)  # 10242 vertices
    body = ph.Body.from_trimesh(sphere, density=1000.0)
    traj = ph.simulate(body, [0.1, 0.2, 3.0], np.linspace(0.0, 1.0, 21))
    fig = plot.scene(traj, body, frames=3, max_vertices=1500)
    drawn = trace(fig, "body")
    assert len(drawn) <= 1500 * 1.1  # the cap's cut adds a ring of vertices
    radius = np.linalg.norm(drawn, axis=1) / fig.layout.meta["body_scale"]
    assert np.all(np.abs(radius - 0.1) <= 0.01)


def test_a_torque_moves_l_and_the_title_says_so(bar, bar_inertia):
    push = ph.torque.BodyFixed([0.0, 0.0, 0.002])
    traj = ph.simulate(bar, OMEGA0, np.linspace(0.0, 4.0, 201), torque=push)
    fig = plot.scene(traj, bar, frames=10)
    check_frames(fig, traj, bar_inertia, 8 * F32, moving=True)
    assert "L not conserved" in fig.frames[-1].layout.title.text
    assert "L, moving" in fig.data[[t.uid for t in fig.data].index("L")].name
    first, last = trace(fig, "L", 0)[1], trace(fig, "L", len(fig.frames) - 1)[1]
    assert np.linalg.norm(first - last) > 1e-3 * np.linalg.norm(first)


def test_a_heavy_top_turns_about_its_pivot():
    from scipy.spatial.transform import Rotation

    top = ph.Body.cone(0.1, 0.04, 0.03)
    pivot = [0.0, 0.0, 0.03]
    traj = ph.simulate(
        top,
        [0.0, 0.0, 150.0],
        np.linspace(0.0, 0.5, 101),
        orientation0=Rotation.from_rotvec([np.pi - 0.3, 0.0, 0.0]),
        torque=ph.torque.Gravity(pivot=pivot),
    )
    with pytest.raises(ph.ArgumentError, match="origin=the pivot") as error:
        plot.scene(traj, top)
    assert error.value.argument == "body"
    fig = plot.scene(traj, top, origin=pivot, frames=8)
    about_pivot = parallel_axis(top.inertia, top.mass, top.center_of_mass, pivot)
    check_frames(fig, traj, about_pivot, 8 * F32, moving=True)


def test_bad_input_is_refused_with_the_argument_named(flipping, bar):
    t = np.linspace(0.0, 1.0, 11)
    cases = [
        (ph.simulate(bar, OMEGA0, t, orientation=False), {}, ph.ArgumentError, "trajectory"),
        (ph.simulate(bar, np.ones((2, 3)), t), {}, ph.ShapeError, "trajectory"),
        (flipping, {"body": ph.Body.cuboid(1.0, [0.3, 0.1, 0.03])}, ph.ArgumentError, "body"),
        # The same moments in other axes: x and y swapped.
        (flipping, {"body": ph.Body.cuboid(1.0, [0.1, 0.3, 0.02])}, ph.ArgumentError, "body"),
        (flipping, {"frames": 0}, ph.ArgumentError, "frames"),
        (flipping, {"frames": [0, 601]}, ph.ArgumentError, "frames"),
        (flipping, {"mark": 3}, ph.ArgumentError, "mark"),
        (flipping, {"origin": [0.0, 0.0, 0.0]}, ph.ArgumentError, "origin"),
        (flipping, {"body": bar, "origin": [0.0, 0.0]}, ph.ShapeError, "origin"),
        (flipping, {"dtype": np.int32}, ph.ArgumentError, "dtype"),
        (flipping, {"curve_points": 1}, ph.ArgumentError, "curve_points"),
        (flipping, {"frame_duration": -1.0}, ph.ArgumentError, "frame_duration"),
        (ph.simulate(bar, [0.0, 0.0, 0.0], t), {}, ph.ArgumentError, "trajectory"),
    ]
    damper = ph.rotors.SphericalDamper(0.2, 0.1)
    cases.append(
        (
            ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], t, rotors=[damper]),
            {},
            ph.ArgumentError,
            "trajectory",
        )
    )
    for traj, options, kind, argument in cases:
        options = dict(options)
        body = options.pop("body", None)
        with pytest.raises(kind) as error:
            plot.scene(traj, body, **options)
        assert error.value.argument == argument, (options, str(error.value))
    with pytest.raises(ph.ShapeError, match="one body's trajectory"):
        plot.scene(ph.simulate(bar, np.ones((2, 3)), t))
    with pytest.raises(ph.ArgumentError, match="orientation=True"):
        plot.scene(ph.simulate(bar, OMEGA0, t, orientation=False))
    with pytest.raises(TypeError, match="polhode.Trajectory"):
        plot.scene("traj")
    with pytest.raises(TypeError, match="Body"):
        plot.scene(flipping, "bar")
    # Moments are taken as simulate takes them, but they must be the trajectory's.
    with pytest.raises(ph.ArgumentError, match="does not match") as error:
        plot.scene(flipping, [1.0, 2.0, 3.0])
    assert error.value.argument == "body"


def test_a_body_given_as_moments_or_a_tensor_is_its_inertia_box(flipping, bar_inertia):
    """The bar's closed-form moments (in its own axes, which are principal), as numbers or as
    the tensor: the construction of the closed-form tensor, the body drawn as its box."""
    for body in (np.diag(bar_inertia), bar_inertia):
        fig = plot.scene(flipping, body, frames=6)
        check_frames(fig, flipping, bar_inertia, 8 * F32)
        assert fig.data[0].name.startswith("inertia box")
    with pytest.raises(ph.ArgumentError) as error:
        plot.scene(flipping, bar_inertia, origin=[0.0, 0.0, 0.01])
    assert error.value.argument == "origin"
    with pytest.raises(TypeError, match="mark"):
        plot.scene(flipping, mark=1.5)


def test_import_polhode_does_not_import_plotly():
    code = "import sys, polhode, polhode.plot; print('plotly' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_the_html_works_offline(flipping, bar, tmp_path):
    path = tmp_path / "scene.html"
    fig = plot.scene(flipping, bar, path=str(path))
    html = path.read_text(encoding="utf-8")
    assert not re.search(r"<script[^>]*\bsrc\s*=\s*[\"']?(https?:)?//", html)
    assert "<script src=" not in html  # no script from anywhere: every one inline
    from plotly.offline import get_plotlyjs

    assert get_plotlyjs() in html  # the whole library, inlined
    assert len(fig.frames) == 120
    size = path.stat().st_size
    assert size < 10e6, size  # plotly.js (4.8 MB) and 120 frames of float32


# -------------------------------------------------------------------------------------------------
# A real browser
# -------------------------------------------------------------------------------------------------


def t_handle_scene(path: Path, frames: int = 60):
    """The gallery's T-handle, spun about its intermediate axis, L up: two flips."""
    from scipy.spatial.transform import Rotation

    shaft = ph.Body.cylinder(mass=0.3, radius=0.01, length=0.2)
    bar = ph.Body.cylinder(0.2, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    t_handle = shaft + bar.translated([0.0, 0.0, 0.1])
    p = t_handle.principal()
    spin = 10.0 * p.axes[:, 1] + 1e-3 * p.axes[:, 0]
    flip = ph.analyze(t_handle, spin).flip_interval
    up, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [t_handle.angular_momentum_body(spin)])
    traj = ph.simulate(t_handle, spin, np.linspace(0.0, 2.2 * flip, 1001), orientation0=up)
    return plot.scene(traj, t_handle, frames=frames, path=str(path))


def chromium_or_skip():
    from browser import find_chromium

    binary = find_chromium()
    if binary is None:
        if os.environ.get("CI"):
            pytest.fail("CI is set but no Chromium is on the PATH (.ci/run installs chromium)")
        pytest.skip("no Chromium on the PATH (apt-get install chromium)")
    return binary


GRAPH = "document.querySelector('.plotly-graph-div')"

#: True once plotly has drawn the figure and its WebGL scene exists.
DRAWN = (
    f"(() => {{ const gd = {GRAPH}; return !!(gd && gd._fullLayout && gd._fullLayout.scene"
    " && gd._fullLayout.scene._scene && gd.querySelector('canvas')); })()"
)

#: The slider's active step and the title.
STATE = (
    f"(() => {{ const gd = {GRAPH}; return [gd._fullLayout.sliders[0].active,"
    " gd._fullLayout.title.text]; })()"
)


def scene_pixels(image):
    """The part of the screenshot the 3-D scene takes (right of the legend, below the title,
    above the slider)."""
    h, w, _ = image.shape
    return image[int(0.12 * h) : int(0.8 * h), int(0.3 * w) : w]


def distinct_colors(pixels):
    return len(np.unique(pixels.reshape(-1, 3), axis=0))


def near(pixels, rgb, tol=12):
    return int(np.sum(np.all(np.abs(pixels.astype(int) - rgb) <= tol, axis=-1)))


def test_a_browser_renders_the_scene_and_steps_its_frames(tmp_path):
    binary = chromium_or_skip()
    from browser import Chromium

    path = tmp_path / "scene.html"
    fig = t_handle_scene(path)
    frames = len(fig.frames)
    with Chromium(binary) as browser:
        browser.open(path.as_uri(), width=1000, height=750)
        browser.wait_for(DRAWN)
        renderer = browser.evaluate(
            "(() => { const g = document.createElement('canvas').getContext('webgl');"
            " if (!g) return null; const d = g.getExtension('WEBGL_debug_renderer_info');"
            " return d ? g.getParameter(d.UNMASKED_RENDERER_WEBGL) : 'webgl'; })()"
        )
        assert renderer, f"no WebGL in the browser: {browser.log()[-2000:]}"
        # Two animation frames of the page's own, so that the scene has been painted.
        browser.evaluate(
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))", True
        )
        first = browser.screenshot()
        assert browser.evaluate(STATE) == [0, fig.frames[0].layout.title.text]
        scene = scene_pixels(first)
        # Not blank: the shaded meshes give many colours; L's purple line is drawn.
        assert distinct_colors(scene) > 300, distinct_colors(scene)
        assert near(scene, (0x94, 0x67, 0xBD)) > 50
        # A frame by the API, as the slider does: state, title and picture change.
        target = frames // 2
        browser.evaluate(
            f"Plotly.animate({GRAPH}, ['{fig.frames[target].name}'], {{frame: {{duration: 0,"
            " redraw: true}, transition: {duration: 0}, mode: 'immediate'})",
            True,
        )
        browser.evaluate(
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))", True
        )
        assert browser.evaluate(STATE) == [target, fig.frames[target].layout.title.text]
        second = browser.screenshot()
        changed = np.any(scene_pixels(second) != scene, axis=-1)
        assert changed.sum() > 2000, changed.sum()
        if os.environ.get("POLHODE_SCENE_PNG"):
            from PIL import Image

            Image.fromarray(second).quantize(256).save(os.environ["POLHODE_SCENE_PNG"])
        # Play, pressed as a user does (a mouse click on the button): the frames advance.
        box = browser.evaluate(
            "(() => { const b = [...document.querySelectorAll('.updatemenu-button')]"
            ".find(e => e.textContent === 'Play').getBoundingClientRect();"
            " return [b.x + b.width / 2, b.y + b.height / 2]; })()"
        )
        for kind in ("mousePressed", "mouseReleased"):
            browser.send(
                "Input.dispatchMouseEvent",
                {"type": kind, "x": box[0], "y": box[1], "button": "left", "clickCount": 1},
            )
        active = browser.wait_for(
            f"(() => {{ const a = {GRAPH}._fullLayout.sliders[0].active;"
            f" return a >= {target + 3} ? a : 0; }})()",
            timeout=15,
        )
        assert target + 3 <= active < frames
