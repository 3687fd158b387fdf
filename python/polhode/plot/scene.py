"""Poinsot's construction, live: a plotly figure of a torque-free motion (the ``plot`` extra).

:func:`scene` draws, in space axes and frame by frame, the body turning about its fixed point,
its energy ellipsoid ``w . I w = 2T`` (fixed in the body) rolling without slipping on the
invariable plane (perpendicular to L, at ``2T / |L|`` from the fixed point), omega from the
fixed point to the contact point, the polhode (omega's path on the ellipsoid) and the
herpolhode (its path on the plane). plotly is imported inside the function: ``import polhode``
never needs it.

The work is in steps, each a function: the arguments checked (:func:`_settings`), the motion
at every output time and the frames' times (:class:`_Motion`), the sizes of the scene and the
body's mesh (:class:`_Geometry`), each frame's points (:func:`_frame_data`), the traces, the
frames and the layout.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_finite, as_finite_array, as_integer, as_path
from polhode._files import writable
from polhode._norms import norms
from polhode.errors import ArgumentError
from polhode.plot._frames import principal_of
from polhode.plot._labels import Units, units_of
from polhode.plot._poinsot import (
    AXIS_COLORS,
    AXIS_ROLES,
    L_TOLERANCE,
    MARK_COLOR,
    MAX_TURN,
    MIN_TIMES,
    PART_COLORS,
    TRACES,
    Array,
    arrow_cone_faces,
    arrow_head,
    body_mesh,
    check_resolution,
    check_trajectory,
    fan_faces,
    frame_indices,
    inertia_about_origin,
    largest_turn,
    mark_of,
    marked_end,
    plane_basis,
    plane_disc,
    unit_sphere,
)
from polhode.plot.geometry import omega_space as space_rate

if TYPE_CHECKING:
    import plotly.graph_objects as go

    from polhode.bodies import Body
    from polhode.simulation import Trajectory

__all__ = ["scene"]


def scene(
    trajectory: Trajectory,
    body: Body | None = None,
    *,
    frames: Any = 120,
    origin: Any = None,
    mark: int | None = None,
    curve_points: int = 400,
    resolution: int = 24,
    max_vertices: int = 3000,
    frame_duration: float = 60.0,
    dtype: Any = np.float32,
    units: Mapping[str, str] | None = None,
    path: str | None = None,
) -> go.Figure:
    """Poinsot's construction, live: a plotly figure with animation frames, a play button and a
    time slider.

    In space axes, about the body's fixed point (the centre of mass of a free body) and frame
    by frame at output times of ``trajectory``:

    - the **body** turning: the shape it was built from (solids, meshes, point masses; each
      part in its own colour), its equivalent ellipsoid if it has no geometry
      (``Body.from_inertia``), or without ``body`` the uniform box with the trajectory's
      moments. Lengths are drawn at the scale the legend says (rad/s per metre), so that the
      body fits inside its ellipsoid. One end is **marked** in orange (its faces, and a ball
      where the body ends along that principal axis): the end of principal axis ``mark``
      that pointed toward L at the first output time, so that a flip is seen;
    - the **principal axes** I1, I2, I3 (red, green, blue: smallest, intermediate, largest
      moment), the axes of the ellipsoid;
    - the **energy ellipsoid** ``w . I w = 2T`` (I about the fixed point, in body axes; semi-
      axes ``sqrt(2T / I_k)``), fixed in the body: it touches the invariable plane at the tip
      of omega and rolls on it without slipping;
    - the **invariable plane**, perpendicular to L at the distance ``2T / |L|`` from the fixed
      point (a disc);
    - **L**, fixed (its direction, drawn to the edge of the scene; its size in the legend), and
      **omega**, from the fixed point to the contact point;
    - the **polhode**, omega's path on the ellipsoid (traced in the body and carried with it),
      and the **herpolhode**, omega's path on the plane (fixed in space), each up to the
      frame's time.

    Coordinates are those of omega, in rad/s (SI units by default, see ``units``); the title
    says what the motion does (from :func:`polhode.analyze` of its state at the first output
    time: the axis L circulates about, numbered 1, 2, 3, and whether the body turns over, every
    ``flip_interval``) and the frame's time.

    The ellipsoid and the plane of each frame are those of that frame's omega: T = w . I w / 2,
    L = R I w. Without a torque they are the same in every frame (to the method's drift). A
    trajectory under a torque is drawn the same way, frame by frame: L and the plane then move,
    the herpolhode does not lie on one plane, and the title says by how much L changed.
    Rotors are refused (their momentum is not the body's).

    Parameters
    ----------
    trajectory : Trajectory
        One body's motion with its orientation (any method, ``orientation=True``). The
        polhode and herpolhode go through its output times (at most ``curve_points`` of them):
        give output times close enough to draw them.
    body : Body, (3,) principal moments or (3, 3) inertia tensor, optional
        The body it was simulated with, as :func:`polhode.simulate` takes it (its principal
        moments and axes must match the trajectory's); principal moments or a tensor are
        drawn as their inertia box; default: drawn as the box of the trajectory's moments.
    frames : int or array_like of int
        The number of frames at evenly spaced output times (default 120, at most one per
        output time), or the indices of the output times.
    origin : (3,) array_like, optional
        With ``body``: the body point held fixed (body coordinates), e.g. the pivot of a heavy
        top; default the centre of mass.
    mark : {0, 1, 2}, optional
        The principal axis (moments ascending) whose end is marked; default the one omega had
        its largest component along at the first output time (the axis it was spun about).
    curve_points : int
        Largest number of points of the polhode and the herpolhode (default 400; every
        frame's own time is one of them).
    resolution : int
        Segments around a circle of the ellipsoid and of the body's solids (6 to 360, one a
        degree).
    max_vertices : int
        A body with more vertices (a large mesh) is simplified to about this many, by merging
        the vertices of each cell of a grid.
    frame_duration : float
        Milliseconds per frame when playing.
    units : dict, optional
        The units the labels say, by quantity: ``{"time": "s", "length": "m", "mass": "kg"}``
        (the default, SI); give those the trajectory and the body were in (any consistent set:
        omega is then in rad per time unit, L in mass length^2 per time).
    dtype : numpy float type
        The numbers the figure stores: ``numpy.float32`` (default: half the file size; what
        a screen shows) or ``numpy.float64``; float32 holds scenes from 1e-30 to 1e38 rad/s
        across (an ArgumentError beyond).
    path : str, optional
        Also write the figure there as a self-contained HTML page (plotly.js embedded, no
        network needed), not playing until its Play button is pressed: the same as
        ``fig.write_html(path, include_plotlyjs=True, auto_play=False)``.

    Returns
    -------
    plotly.graph_objects.Figure
        ``fig.show()`` in Jupyter, ``fig.write_html(path)`` (plotly.js embedded: works
        offline; ``include_plotlyjs="cdn"`` writes a smaller file that needs the network).
        Its traces, by ``uid``: ``"body"``, ``"mark"``, ``"axis1"``.. ``"axis3"``,
        ``"ellipsoid"``, ``"polhode"``, ``"plane"``, ``"herpolhode"``, ``"L"``, ``"L_head"``,
        ``"omega"``, ``"omega_head"``, ``"contact"``; every frame (``fig.frames``, named
        ``"0"``, ``"1"``..) updates all of them in that order. ``fig.layout.meta`` holds
        ``frame_indices`` (the output-time index of each frame), ``body_scale`` (rad/s per
        metre), ``mark`` (the axis) and ``mark_direction`` (its marked end, body coordinates).

    Raises
    ------
    ShapeError
        ``trajectory`` is a batch.
    ArgumentError
        ``trajectory`` has no orientation, has rotors, or is at rest; ``body`` does not match
        it (other moments or other axes); a bad ``frames``, ``mark``, ``origin``, ``units``,
        ``dtype`` or size.

    Warns
    -----
    UserWarning
        The output times are too few (under 10) or too far apart to draw the curves (omega
        turns by more than 20 degrees between two of their points).

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> bar = ph.Body.cuboid(1.0, [0.3, 0.1, 0.02])
    >>> sol = ph.simulate(bar, [0.05, 5.0, 0.05], np.linspace(0.0, 6.0, 601))
    >>> fig = ph.plot.scene(sol, bar, frames=30)
    >>> len(fig.frames), [trace.uid for trace in fig.data][:3]
    (30, ['body', 'mark', 'axis1'])
    >>> fig.write_html("scene.html")  # doctest: +SKIP
    """
    import plotly.graph_objects as go

    trajectory = check_trajectory(trajectory)
    body, tensor = _body(body)
    settings = _settings(
        body,
        origin=origin,
        dtype=dtype,
        curve_points=curve_points,
        resolution=resolution,
        max_vertices=max_vertices,
        frame_duration=frame_duration,
        units=units,
        path=path,
    )
    motion = _Motion(trajectory, body, tensor, settings, frames, mark)
    geometry = _Geometry(motion, body, settings)
    _check_store(settings.store, geometry.half)
    figure = go.Figure(
        data=_traces(motion, geometry, body, settings),
        layout=_layout(motion, geometry, settings),
        frames=_frames(motion, geometry, settings),
    )
    if settings.path is not None:
        figure.write_html(settings.path, include_plotlyjs=True, auto_play=False)
    return figure


def _body(body: Any) -> tuple[Body | None, Array | None]:
    """A Body (drawn as it was built), or principal moments or a tensor (in the trajectory's
    body axes: drawn as their inertia box, as without a body) as that tensor."""
    from polhode.bodies import Body

    if body is None or isinstance(body, Body):
        return body, None
    moments, axes = principal_of(body)
    return None, axes @ np.diag(moments) @ axes.T


#: The sizes of a scene (its half-width, in rad/s) that float32 holds: its largest numbers
#: below float32's largest (3.4e38, with room for the plane and the arrows), and details of
#: 2^-24 of it above float32's smallest normal number (1.2e-38).
FLOAT32_SCENE = (1e-30, 1e38)


def _check_store(store: np.dtype[Any], half: float) -> None:
    """float32 only for a scene that it holds (FLOAT32_SCENE)."""
    low, high = FLOAT32_SCENE
    if store == np.dtype(np.float32) and not low <= half <= high:
        raise ArgumentError(
            f"Expected `dtype` to hold the scene: it is {half:.3g} rad/s across, beyond what "
            f"float32 holds ({low:g} to {high:g}); pass dtype=numpy.float64.",
            argument="dtype",
        )


@dataclass(frozen=True)
class _Settings:
    """scene's arguments, checked."""

    fixed: Array | None
    store: np.dtype[Any]
    curve_points: int
    resolution: int
    max_vertices: int
    frame_duration: float
    unit: Units
    path: str | None


def _settings(body: Any, *, origin: Any, dtype: Any, **given: Any) -> _Settings:
    from polhode.bodies import Body

    if body is not None and not isinstance(body, Body):
        raise TypeError(f"Expected `body` to be a polhode.Body or None, got {type(body).__name__}.")
    fixed = None
    if origin is not None:
        if body is None:
            raise ArgumentError(
                "`origin` is a point of `body`: give it with a Body.", argument="origin"
            )
        fixed = as_finite_array("origin", origin, (3,))
    if not (isinstance(dtype, type) or isinstance(dtype, np.dtype) or isinstance(dtype, str)):
        raise TypeError(f"Expected `dtype` to be numpy.float32 or float64, got {dtype!r}.")
    try:
        store = np.dtype(dtype)
    except TypeError as error:
        raise TypeError(
            f"Expected `dtype` to be numpy.float32 or float64, got {dtype!r}."
        ) from error
    if store not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise ArgumentError(
            f"Expected `dtype` to be numpy.float32 or float64, got {store}.", argument="dtype"
        )
    frame_duration = as_finite("frame_duration", given["frame_duration"])
    if not frame_duration >= 0:
        raise ArgumentError(
            f"Expected `frame_duration` to be finite and >= 0, got {frame_duration}.",
            argument="frame_duration",
        )
    return _Settings(
        fixed=fixed,
        store=store,
        curve_points=as_integer("curve_points", given["curve_points"], minimum=2),
        resolution=check_resolution(given["resolution"]),
        max_vertices=as_integer("max_vertices", given["max_vertices"], minimum=8),
        frame_duration=frame_duration,
        unit=units_of(given["units"]),
        path=None if given["path"] is None else writable(as_path("path", given["path"])),
    )


class _Motion:
    """The motion at every output time (rotations, omega in body and space, T, L), the
    tensor and its principal axes, the marked axis, the frames' and the curves' output
    times, and whether L moves."""

    def __init__(
        self,
        trajectory: Trajectory,
        body: Body | None,
        given: Array | None,
        settings: _Settings,
        frames: Any,
        mark: Any,
    ):
        from scipy.spatial.transform import Rotation

        self.t = t = np.asarray(trajectory.t, dtype=np.float64)
        self.omega_body = omega_body = np.asarray(trajectory.omega, dtype=np.float64)
        if not np.all(np.any(omega_body != 0.0, axis=1)):
            raise ArgumentError(
                "`trajectory` is at rest at some output time (omega = 0): no energy ellipsoid, "
                "no invariable plane.",
                argument="trajectory",
            )
        self.indices = indices = frame_indices(frames, t.size)
        self.tensor = tensor = inertia_about_origin(trajectory, body, settings.fixed, given)
        self.moments, self.axes = np.linalg.eigh(tensor)
        self.mark, self.direction = mark_of(self.axes, omega_body[0], tensor @ omega_body[0], mark)

        # Every output time: rotations, omega in space, T, L in space.
        self.rotations = Rotation.from_quat(np.asarray(trajectory.quaternion)).as_matrix()
        self.omega_space = np.asarray(space_rate(trajectory), dtype=np.float64)
        momentum_body = omega_body @ tensor.T
        self.energy = 0.5 * np.einsum("mi,mi->m", omega_body, momentum_body)
        momentum = np.einsum("mij,mj->mi", self.rotations, momentum_body)
        self.size_l = norms(momentum)
        self.normal = momentum / self.size_l[:, None]
        self.distance = 2.0 * self.energy / self.size_l
        self.change = float(np.max(norms(momentum - momentum[0])) / self.size_l[0])
        self.moving = self.change > L_TOLERANCE

        # The curves: at most curve_points output times, every frame's among them.
        every = np.unique(np.linspace(0, t.size - 1, min(settings.curve_points, t.size)).round())
        self.curve = np.union1d(every.astype(np.int64), indices)
        self._warn_if_sparse()

    def _warn_if_sparse(self) -> None:
        t, curve = self.t, self.curve
        turn = max(largest_turn(self.omega_body[curve]), largest_turn(self.omega_space[curve]))
        if t.size < MIN_TIMES:
            warnings.warn(
                f"`trajectory` has {t.size} output times: the scene has as many frames at most, "
                "and its curves as many points. Simulate at more output times "
                "(t=numpy.linspace(t0, t1, 1000)).",
                UserWarning,
                stacklevel=4,
            )
        elif turn > MAX_TURN:
            advice = (
                "raise `curve_points`"
                if curve.size < t.size
                else "simulate at more output times (t=numpy.linspace(t0, t1, 1000))"
            )
            warnings.warn(
                "The polhode and the herpolhode are drawn as straight segments between output "
                f"times, and omega turns by up to {turn:.0f} degrees between two of them: "
                f"{advice}.",
                UserWarning,
                stacklevel=4,
            )


class _Geometry:
    """The scene's sizes, the body's mesh (scaled to fit in its smallest ellipsoid, its end
    marked), the ellipsoid's sphere, the plane's first basis vector and the regime."""

    def __init__(self, motion: _Motion, body: Body | None, settings: _Settings):
        from polhode.analysis import analyze

        energy, distance, normal = motion.energy, motion.distance, motion.normal
        # Sizes: the largest semi-axis, the plane's reach, the scene's half-width.
        self.semi = np.sqrt(2.0 * energy[:, None] / motion.moments[None, :])  # (M, 3)
        largest = float(np.max(self.semi))
        self.centres = distance[:, None] * normal
        spread = float(np.max(norms(motion.omega_space - self.centres)))
        self.radius = max(1.15 * spread, 0.6 * largest)
        self.half = half = 1.08 * max(largest, float(np.max(np.sqrt(distance**2 + self.radius**2))))
        self.l_length = 0.97 * half
        self.head_length, self.head_radius = 0.07 * half, 0.025 * half

        # The body about the fixed point, scaled to fit in the smallest ellipsoid of the frames.
        fixed, tensor = settings.fixed, motion.tensor
        origin_point = (
            (body.center_of_mass if fixed is None else fixed) if body is not None else np.zeros(3)
        )
        vertices, faces, part_of, self.what = body_mesh(
            body, tensor, origin_point, settings.resolution, settings.max_vertices
        )
        quadratic = np.einsum("vi,ij,vj->v", vertices, tensor, vertices)
        reach = float(np.max(quadratic)) if vertices.size else 0.0
        self.scale = 0.85 * float(np.sqrt(2.0 * np.min(energy) / reach)) if reach > 0 else 1.0
        self.vertices, self.faces, part_of, capped, self.mark_point = marked_end(
            vertices, faces, part_of, motion.direction
        )
        self.face_colors = np.where(
            capped, MARK_COLOR, np.asarray(PART_COLORS)[part_of % len(PART_COLORS)]
        )
        self.sphere, self.sphere_faces = unit_sphere(settings.resolution)
        self.e1, self.e2 = plane_basis(normal[0], motion.omega_space[0] - self.centres[0])

        # What the motion does, from its state at the first output time.
        self.analysis = analyze(tensor, motion.omega_body[0])
        self.moving = motion.moving
        self.change = motion.change

    def condition(self, unit: Units) -> str:
        """What the title says the motion does: the words of :func:`polhode.analyze` (which
        axis L circulates about, whether the body turns over), short."""
        if self.moving:
            return f"L not conserved (changes by {self.change:.2g} of |L|): L and the plane move"
        return motion_words(self.analysis, unit.time)

    def title(self, motion: _Motion, unit: Units, k: int) -> str:
        return (
            f"Poinsot's construction ({self.condition(unit)})<br>"
            f"t = {motion.t[k]:.4g} {unit.time}"
        )


def motion_words(analysis: Any, time_unit: str) -> str:
    """The motion in a few words for a title, from an :class:`polhode.Analysis`: which axis L
    circulates about (numbered 1, 2, 3), and whether the body turns over, with its interval."""
    regime = analysis.regime
    if regime == "rest":
        return "at rest"
    if regime == "spherical":
        return "a spherical body: omega fixed"
    if regime == "symmetric":
        return "a symmetric top: omega and L precess at a constant angle"
    if regime == "steady_intermediate":
        return "a steady spin about axis 2 (I2): unstable"
    if regime == "separatrix":
        return "on the separatrix: the body turns over once"
    axis = 3 if regime == "about_largest_axis" else 1
    about = f"L circulates about axis {axis} (I{axis})"
    if analysis.turns_over:
        return f"{about}; the body turns over every {analysis.flip_interval:.4g} {time_unit}"
    return f"{about}: a stable spin"


def _frame_data(
    motion: _Motion, geometry: _Geometry, store: np.dtype[Any], k: int
) -> list[dict[str, NDArray[Any]]]:
    """x, y, z of every trace (TRACES' order) at output time index k."""

    def xyz(points: Array) -> dict[str, NDArray[Any]]:
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        return {
            axis: np.ascontiguousarray(points[:, a], dtype=store) for a, axis in enumerate("xyz")
        }

    g = geometry
    r = motion.rotations[k]
    normal = motion.normal[k]
    ellipsoid_body = (g.sphere * g.semi[k]) @ motion.axes.T
    e1k, e2k = plane_basis(normal, g.e1)
    shown = motion.curve[motion.curve <= k]
    omega_tip = motion.omega_space[k]
    l_tip = g.l_length * normal
    data = [
        xyz(g.scale * g.vertices @ r.T),
        xyz(g.scale * (r @ g.mark_point)),
    ]
    for a in range(3):
        tip = g.semi[k, a] * (r @ motion.axes[:, a])
        data.append(xyz(np.stack([-tip, tip])))
    data += [
        xyz(ellipsoid_body @ r.T),
        xyz(motion.omega_body[shown] @ r.T),
        xyz(plane_disc(motion.distance[k] * normal, e1k, e2k, g.radius)),
        xyz(motion.omega_space[shown]),
        xyz(np.stack([np.zeros(3), l_tip - g.head_length * normal])),
        xyz(arrow_head(l_tip, normal, g.head_length, g.head_radius)),
        xyz(
            np.stack(
                [np.zeros(3), omega_tip - g.head_length * omega_tip / norms(omega_tip)]
            )
        ),
        xyz(arrow_head(omega_tip, omega_tip, g.head_length, g.head_radius)),
        xyz(omega_tip),
    ]
    return data


def _traces(
    motion: _Motion, geometry: _Geometry, body: Body | None, settings: _Settings
) -> list[Any]:
    """The traces of the first frame, in TRACES' order."""
    import plotly.graph_objects as go

    first = _frame_data(motion, geometry, settings.store, int(motion.indices[0]))
    unit, rate, g = settings.unit, settings.unit.rate, geometry
    flat = {"flatshading": True, "hoverinfo": "skip"}
    if body is None:
        body_name = f"inertia box of the moments ({g.scale:.3g} {rate} per {unit.length})"
    else:
        body_name = f"{g.what} ({g.scale:.3g} {rate} per {unit.length})"
    traces: list[Any] = [
        go.Mesh3d(
            **first[0],
            i=g.faces[:, 0],
            j=g.faces[:, 1],
            k=g.faces[:, 2],
            facecolor=g.face_colors,
            name=body_name,
            showlegend=True,
            uid="body",
            lighting={"ambient": 0.55, "diffuse": 0.7, "specular": 0.15},
            **flat,
        ),
        go.Scatter3d(
            **first[1],
            mode="markers",
            marker={"size": 9, "color": MARK_COLOR, "line": {"color": "black", "width": 1}},
            name=(
                f"marked end: +I{motion.mark + 1} axis (toward L at t = "
                f"{motion.t[motion.indices[0]]:.3g} {unit.time})"
            ),
            uid="mark",
            hoverinfo="skip",
        ),
    ]
    for a in range(3):
        traces.append(
            go.Scatter3d(
                **first[2 + a],
                mode="lines",
                line={"color": AXIS_COLORS[a], "width": 4},
                name=f"I{a + 1} axis ({AXIS_ROLES[a]} moment)",
                uid=f"axis{a + 1}",
                hoverinfo="skip",
            )
        )
    return traces + _construction_traces(first, motion, geometry, settings)


def _construction_traces(
    first: list[dict[str, NDArray[Any]]], motion: _Motion, geometry: _Geometry, settings: _Settings
) -> list[Any]:
    """The traces after the body and its axes: the ellipsoid, the polhode, the plane, the
    herpolhode, L and omega with their heads, the contact point."""
    import plotly.graph_objects as go

    unit, rate = settings.unit, settings.unit.rate
    flat = {"flatshading": True, "hoverinfo": "skip"}
    sphere_faces = geometry.sphere_faces
    plane_faces = fan_faces(48)
    cone_triangles = arrow_cone_faces()
    return [
        go.Mesh3d(
            **first[5],
            i=sphere_faces[:, 0],
            j=sphere_faces[:, 1],
            k=sphere_faces[:, 2],
            color="#9ecae1",
            opacity=0.3,
            name="energy ellipsoid w.Iw = 2T (fixed in the body)",
            showlegend=True,
            uid="ellipsoid",
            hoverinfo="skip",
        ),
        go.Scatter3d(
            **first[6],
            mode="lines",
            line={"color": "#d62728", "width": 5},
            name="polhode (omega on the ellipsoid)",
            uid="polhode",
            hoverinfo="skip",
        ),
        go.Mesh3d(
            **first[7],
            i=plane_faces[:, 0],
            j=plane_faces[:, 1],
            k=plane_faces[:, 2],
            color="#bdbdbd",
            opacity=0.35,
            name="invariable plane (perpendicular to L, at 2T/|L|)",
            showlegend=True,
            uid="plane",
            **flat,
        ),
        go.Scatter3d(
            **first[8],
            mode="lines",
            line={"color": "#1f77b4", "width": 5},
            name="herpolhode (omega on the plane)",
            uid="herpolhode",
            hoverinfo="skip",
        ),
        go.Scatter3d(
            **first[9],
            mode="lines",
            line={"color": "#9467bd", "width": 6},
            name=(
                f"L, {'moving' if motion.moving else 'fixed'} (|L| = "
                f"{motion.size_l[motion.indices[0]]:.4g} {unit.momentum('^2')}; its direction)"
            ),
            legendgroup="L",
            uid="L",
            hoverinfo="skip",
        ),
        go.Mesh3d(
            **first[10],
            i=cone_triangles[:, 0],
            j=cone_triangles[:, 1],
            k=cone_triangles[:, 2],
            color="#9467bd",
            legendgroup="L",
            showlegend=False,
            uid="L_head",
            **flat,
        ),
        go.Scatter3d(
            **first[11],
            mode="lines",
            line={"color": "black", "width": 6},
            name=f"omega ({rate})",
            legendgroup="omega",
            uid="omega",
            hoverinfo="skip",
        ),
        go.Mesh3d(
            **first[12],
            i=cone_triangles[:, 0],
            j=cone_triangles[:, 1],
            k=cone_triangles[:, 2],
            color="black",
            legendgroup="omega",
            showlegend=False,
            uid="omega_head",
            **flat,
        ),
        go.Scatter3d(
            **first[13],
            mode="markers",
            marker={"size": 4, "color": "black"},
            name="contact point (tip of omega)",
            uid="contact",
            hoverinfo="skip",
        ),
    ]


def _frames(motion: _Motion, geometry: _Geometry, settings: _Settings) -> list[Any]:
    """One plotly frame per frame index, named "0", "1"..: every trace's points and the
    title."""
    import plotly.graph_objects as go

    every_trace = list(range(len(TRACES)))
    meshes = ("body", "ellipsoid", "plane", "L_head", "omega_head")
    return [
        go.Frame(
            name=str(f),
            data=[
                go.Mesh3d(**d) if TRACES[n] in meshes else go.Scatter3d(**d)
                for n, d in enumerate(_frame_data(motion, geometry, settings.store, int(k)))
            ],
            traces=every_trace,
            layout={"title": {"text": geometry.title(motion, settings.unit, int(k))}},
        )
        for f, k in enumerate(motion.indices)
    ]


def _layout(motion: _Motion, geometry: _Geometry, settings: _Settings) -> Any:
    """The layout: the title, the legend, the scene's axes and camera (looking across L, up
    along it), the Play and Pause buttons, the time slider, and the meta data."""
    import plotly.graph_objects as go

    unit, rate, half = settings.unit, settings.unit.rate, geometry.half
    names = [str(f) for f in range(len(motion.indices))]
    play = {
        "frame": {"duration": settings.frame_duration, "redraw": True},
        "transition": {"duration": 0},
        "fromcurrent": True,
        "mode": "immediate",
    }
    step = {
        "frame": {"duration": 0, "redraw": True},
        "transition": {"duration": 0},
        "mode": "immediate",
    }
    normal = motion.normal[0]
    eye_direction = 0.93 * (0.8 * geometry.e1 + 0.6 * geometry.e2) + 0.45 * normal
    eye = 2.25 * eye_direction / norms(eye_direction)
    axis_style = {
        "range": [-half, half],
        "autorange": False,
        "showbackground": True,
        "backgroundcolor": "#f4f4f4",
        "gridcolor": "#dddddd",
        "zerolinecolor": "#bbbbbb",
    }
    return go.Layout(
        title={
            "text": geometry.title(motion, unit, int(motion.indices[0])),
            # At the left, above the legend: plotly's tool bar takes the top right corner.
            "x": 0.01,
            "xanchor": "left",
        },
        height=720,
        margin={"l": 10, "r": 10, "t": 70, "b": 80},
        legend={"x": 0.0, "y": 0.97, "yanchor": "top", "font": {"size": 11}},
        scene={
            "domain": {"x": [0.27, 1.0], "y": [0.0, 1.0]},
            "xaxis": {**axis_style, "title": {"text": f"x, space ({rate})"}},
            "yaxis": {**axis_style, "title": {"text": f"y, space ({rate})"}},
            "zaxis": {**axis_style, "title": {"text": f"z, space ({rate})"}},
            "aspectmode": "cube",
            "camera": {
                "up": dict(zip("xyz", normal.tolist(), strict=True)),
                "eye": dict(zip("xyz", eye.tolist(), strict=True)),
                "center": {"x": 0.0, "y": 0.0, "z": 0.0},
            },
        },
        uirevision="scene",
        updatemenus=[
            {
                "type": "buttons",
                "direction": "left",
                "x": 0.0,
                "y": 0.0,
                "xanchor": "left",
                "yanchor": "top",
                "pad": {"t": 10, "r": 10},
                "showactive": False,
                "buttons": [
                    {"label": "Play", "method": "animate", "args": [None, play]},
                    {"label": "Pause", "method": "animate", "args": [[None], step]},
                ],
            }
        ],
        sliders=[
            {
                "active": 0,
                "x": 0.12,
                "len": 0.88,
                "y": 0.0,
                "yanchor": "top",
                "pad": {"t": 10},
                "currentvalue": {"prefix": "t = ", "suffix": f" {unit.time}", "visible": True},
                "steps": [
                    {"label": f"{motion.t[k]:.3g}", "method": "animate", "args": [[name], step]}
                    for name, k in zip(names, motion.indices, strict=True)
                ],
            }
        ],
        meta={
            "frame_indices": motion.indices.tolist(),
            "body_scale": geometry.scale,
            "mark": motion.mark,
            "mark_direction": motion.direction.tolist(),
        },
    )
