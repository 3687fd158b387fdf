"""Poinsot's construction, live: a plotly figure of a torque-free motion (the ``plot`` extra).

:func:`scene` draws, in space axes and frame by frame, the body turning about its fixed point,
its energy ellipsoid ``w . I w = 2T`` (fixed in the body) rolling without slipping on the
invariable plane (perpendicular to L, at ``2T / |L|`` from the fixed point), omega from the
fixed point to the contact point, the polhode (omega's path on the ellipsoid) and the
herpolhode (its path on the plane). plotly is imported inside the function: ``import polhode``
never needs it.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode import _shapes
from polhode._coerce import as_array, as_integer, as_scalar
from polhode.errors import ArgumentError, ShapeError

if TYPE_CHECKING:
    import plotly.graph_objects as go

    from polhode.bodies import Body
    from polhode.simulation import Trajectory

__all__ = ["scene"]

Array = NDArray[np.float64]

#: The traces of :func:`scene`, in order, by ``uid``: every frame updates all of them.
TRACES = (
    "body",
    "mark",
    "axis1",
    "axis2",
    "axis3",
    "ellipsoid",
    "polhode",
    "plane",
    "herpolhode",
    "L",
    "L_head",
    "omega",
    "omega_head",
    "contact",
)

#: Colours of the principal axes I1, I2, I3 (smallest, intermediate, largest moment), as in
#: :func:`polhode.plot.animate`.
AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")

#: Colours of a body's parts, in the order they were added; the marked end is MARK_COLOR.
PART_COLORS = ("#8fa8c8", "#d9a66b", "#9cc28f", "#c98fb8", "#c8c28f", "#8fc8c2")
MARK_COLOR = "#ff7f0e"

#: The words of the principal axes, indexed 0, 1, 2 with the moments ascending.
AXIS_ROLES = ("smallest", "intermediate", "largest")

#: Largest turn of omega (degrees, in the body or in space) between two points of the curves
#: before :func:`scene` warns that they are too far apart to draw the curves.
MAX_TURN = 20.0

#: Fewer output times than this, and :func:`scene` warns that they cannot draw the motion.
MIN_TIMES = 10

#: The units the labels say by default (SI), by quantity.
UNITS = {"time": "s", "length": "m", "mass": "kg"}

#: Relative change of L in space above which the figure says that L is not conserved.
L_TOLERANCE = 1e-6


# -------------------------------------------------------------------------------------------------
# Checks
# -------------------------------------------------------------------------------------------------


def _check_trajectory(trajectory: Any) -> Trajectory:
    from polhode.simulation import Trajectory

    if not isinstance(trajectory, Trajectory):
        raise TypeError(
            f"Expected `trajectory` to be a polhode.Trajectory, got {type(trajectory).__name__}."
        )
    if np.ndim(trajectory.omega) != 2:
        raise ShapeError(
            f"scene draws one body; `trajectory` is a batch of {np.shape(trajectory.omega)[0]} "
            "bodies: pass one body's trajectory (simulate that body alone).",
            argument="trajectory",
        )
    if trajectory.quaternion is None:
        raise ArgumentError(
            "`trajectory` has no orientation (simulated with orientation=False): simulate "
            "with orientation=True to draw the body in space.",
            argument="trajectory",
        )
    if trajectory.rotor_rates is not None:
        raise ArgumentError(
            "`trajectory` has internal rotors: Poinsot's construction is that of one rigid "
            "body, whose own momentum I omega is not conserved when rotors exchange momentum "
            "with it. Draw it with polhode.plot.animate.",
            argument="trajectory",
        )
    if trajectory.t.size < 2:
        raise ArgumentError(
            f"Expected `trajectory` to have at least 2 output times, got {trajectory.t.size}.",
            argument="trajectory",
        )
    return trajectory


def _units(units: Any) -> dict[str, str]:
    """The units of :func:`scene`'s labels: SI, with those given in place."""
    if units is None:
        return dict(UNITS)
    if not isinstance(units, Mapping):
        raise TypeError(
            f"Expected `units` to be a dict such as {UNITS}, got {type(units).__name__}."
        )
    unknown = sorted(str(k) for k in units if k not in UNITS)
    if unknown:
        raise ArgumentError(
            f"Expected the keys of `units` among {sorted(UNITS)}, got {unknown}.", argument="units"
        )
    for key, value in units.items():
        if not isinstance(value, str) or not value.strip():
            raise ArgumentError(
                f"Expected `units[{key!r}]` to be a unit's name, got {value!r}.", argument="units"
            )
    return {**UNITS, **{k: str(v).strip() for k, v in units.items()}}


def _frame_indices(frames: Any, count: int) -> NDArray[np.int64]:
    """Indices into the output times: ``frames`` evenly spaced ones, or those given."""
    if isinstance(frames, bool) or not (
        isinstance(frames, int | np.integer) or np.ndim(frames) == 1
    ):
        raise TypeError(
            f"Expected `frames` to be a number of frames or indices, got {type(frames).__name__}."
        )
    if np.ndim(frames) == 0:
        if int(frames) < 1:
            raise ArgumentError(
                f"Expected `frames` to be at least 1, got {frames}.", argument="frames"
            )
        return np.unique(
            np.linspace(0, count - 1, min(int(frames), count)).round().astype(np.int64)
        )
    indices = np.asarray(frames)
    if indices.dtype.kind not in "iu" or indices.size == 0:
        raise ArgumentError(
            "Expected `frames` to be a non-empty array of output-time indices.", argument="frames"
        )
    if np.any(indices < -count) or np.any(indices >= count):
        raise ArgumentError(
            f"Expected `frames` to index the {count} output times, got {frames!r}.",
            argument="frames",
        )
    return np.asarray(indices % count, dtype=np.int64)


def _relative_mismatch(a: Array, b: Array) -> float:
    scale = float(np.max(np.abs(b))) if b.size else 0.0
    return float(np.max(np.abs(a - b))) / scale if scale > 0 else float(np.max(np.abs(a - b)))


def _inertia(trajectory: Trajectory, body: Body | None, origin: Array | None) -> Array:
    """The inertia tensor (about the fixed point, in the trajectory's body axes) of the motion.

    With a Body: its tensor about ``origin`` (default the centre of mass), checked against the
    trajectory's principal moments and against its ``I omega``. Without: the diagonal of the
    trajectory's moments when its omega is in those axes (a motion simulated with principal
    moments), else the tensor fitted to ``I omega`` over the output times.
    """
    moments = np.asarray(trajectory.moments, dtype=np.float64)
    omega = np.asarray(trajectory.omega, dtype=np.float64)
    momentum = np.asarray(trajectory.angular_momentum_body, dtype=np.float64)
    if body is not None:
        tensor = body.inertia if origin is None else body.inertia_about(origin)
        eigen = np.linalg.eigvalsh(tensor)
        about = "its centre of mass" if origin is None else f"origin={origin.tolist()}"
        if _relative_mismatch(eigen, np.sort(moments)) > 1e-9:
            hint = " (for a heavy top, pass origin=the pivot)" if origin is None else ""
            raise ArgumentError(
                f"`body` does not match `trajectory`: its principal moments about {about} are "
                f"{eigen.tolist()}, the trajectory's {np.sort(moments).tolist()}; pass the body "
                f"the trajectory was simulated with{hint}.",
                argument="body",
            )
        if _relative_mismatch(omega @ tensor.T, momentum) > 1e-9:
            raise ArgumentError(
                "`body` does not match `trajectory`: its principal moments agree but its axes "
                "do not (I omega differs from the trajectory's angular_momentum_body); pass "
                "the body the trajectory was simulated with, in the same axes.",
                argument="body",
            )
        return np.asarray(tensor, dtype=np.float64)
    diagonal = np.diag(moments)
    if _relative_mismatch(omega * moments, momentum) <= 1e-9:
        return diagonal
    # omega in axes that are not principal (a tensor or a Body was simulated): the tensor
    # from L = I omega at the output times, if they span every direction.
    if np.linalg.matrix_rank(omega, tol=1e-8 * float(np.max(np.abs(omega)))) == 3:
        solution, *_ = np.linalg.lstsq(omega, momentum, rcond=None)
        tensor = (solution + solution.T) / 2.0
        if (
            _relative_mismatch(omega @ tensor, momentum) <= 1e-8
            and _relative_mismatch(np.linalg.eigvalsh(tensor), np.sort(moments)) <= 1e-8
        ):
            return tensor
    raise ArgumentError(
        "`trajectory` was simulated in body axes that are not principal (with a Body or an "
        "inertia tensor): pass that Body as `body`.",
        argument="body",
    )


# -------------------------------------------------------------------------------------------------
# Geometry
# -------------------------------------------------------------------------------------------------


def unit_sphere(resolution: int) -> tuple[Array, NDArray[np.int64]]:
    """Vertices (V, 3) and triangles (F, 3) of a latitude-longitude unit sphere with
    ``resolution`` segments around the equator."""
    n_lon = max(int(resolution), 6)
    n_lat = max(n_lon // 2, 3)
    theta = np.linspace(0.0, np.pi, n_lat + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * np.pi, n_lon, endpoint=False)
    rings = np.stack(
        [
            np.outer(np.sin(theta), np.cos(phi)),
            np.outer(np.sin(theta), np.sin(phi)),
            np.outer(np.cos(theta), np.ones_like(phi)),
        ],
        axis=-1,
    ).reshape(-1, 3)
    vertices = np.vstack([[0.0, 0.0, 1.0], rings, [0.0, 0.0, -1.0]])
    bottom = len(vertices) - 1

    def at(ring: int, k: int) -> int:
        return 1 + ring * n_lon + k % n_lon

    faces = []
    for k in range(n_lon):
        faces.append((0, at(0, k), at(0, k + 1)))
        faces.append((bottom, at(n_lat - 2, k + 1), at(n_lat - 2, k)))
        for ring in range(n_lat - 2):
            a, b = at(ring, k), at(ring, k + 1)
            c, d = at(ring + 1, k), at(ring + 1, k + 1)
            faces.append((a, c, d))
            faces.append((a, d, b))
    return vertices, np.asarray(faces, dtype=np.int64)


def _triangles(polygons: list[Array]) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]]:
    """Shared vertices, triangles (fans of the polygons) and each triangle's polygon index."""
    if not polygons:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    sizes = np.array([len(q) for q in polygons])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    points = np.concatenate(polygons).astype(np.float64)
    faces, owner = [], []
    for p, (start, size) in enumerate(zip(starts, sizes, strict=True)):
        for k in range(1, size - 1):
            faces.append((start, start + k, start + k + 1))
            owner.append(p)
    vertices, inverse = np.unique(points, axis=0, return_inverse=True)
    triangles = inverse.reshape(-1)[np.asarray(faces, dtype=np.int64)]
    keep = (
        (triangles[:, 0] != triangles[:, 1])
        & (triangles[:, 1] != triangles[:, 2])
        & (triangles[:, 0] != triangles[:, 2])
    )
    return vertices, triangles[keep], np.asarray(owner, dtype=np.int64)[keep]


def _decimated(
    vertices: Array, faces: NDArray[np.int64], owner: NDArray[np.int64], limit: int
) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]]:
    """At most ``limit`` vertices, by clustering on a grid (each cell's vertices merged into
    their mean; triangles that collapse dropped)."""
    if len(vertices) <= limit:
        return vertices, faces, owner
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    span = float(np.max(high - low)) or 1.0
    cells = max(int(np.cbrt(limit)) * 2, 2)
    while True:
        key = np.floor((vertices - low) / span * cells).astype(np.int64)
        _, cluster = np.unique(key, axis=0, return_inverse=True)
        cluster = cluster.reshape(-1)
        count = int(cluster.max()) + 1
        if count <= limit or cells <= 2:
            break
        cells = int(cells * 0.85)
    merged = np.zeros((count, 3))
    np.add.at(merged, cluster, vertices)
    merged /= np.bincount(cluster, minlength=count)[:, None]
    triangles = cluster[faces]
    keep = (
        (triangles[:, 0] != triangles[:, 1])
        & (triangles[:, 1] != triangles[:, 2])
        & (triangles[:, 0] != triangles[:, 2])
    )
    return merged, triangles[keep], owner[keep]


def _inertia_box(tensor: Array) -> list[Array]:
    """Faces of the uniform cuboid with these principal moments (up to a common scale: its
    mass is unknown), along the principal axes; sides a_k^2 ~ I_i + I_j - I_k (a thin side
    where the moments break the triangle inequality)."""
    moments, axes = np.linalg.eigh(tensor)
    squares = np.sum(moments) - 2.0 * moments
    squares = np.maximum(squares, 1e-4 * float(np.max(squares)))
    shape = _shapes.part("cuboid", size=np.sqrt(squares))
    return _shapes.surface(_shapes.moved(shape, axes, np.zeros(3)) or ())


def _body_mesh(
    body: Body | None, tensor: Array, origin: Array, resolution: int, max_vertices: int
) -> tuple[Array, NDArray[np.int64], NDArray[np.int64], str]:
    """The body's surface about the fixed point (body coordinates): vertices, triangles, each
    triangle's part index, and what it is."""
    if body is None:
        polygons = _inertia_box(tensor)
        owner_part = [0] * len(polygons)
        what = "inertia box"
    else:
        shape = _shapes.of(body)
        parts = [_shapes.surface((p,), resolution) for p in shape]
        polygons = [q for part in parts for q in part]
        owner_part = [k for k, part in enumerate(parts) for _ in part]
        what = "equivalent ellipsoid" if body._shape is None else "body"
    vertices, faces, owner = _triangles([np.asarray(q) - origin for q in polygons])
    part_of = np.asarray(owner_part, dtype=np.int64)[owner]
    vertices, faces, part_of = _decimated(vertices, faces, part_of, max_vertices)
    return vertices, faces, part_of, what


#: The marked end of a body: the part of it in the last CAP of its extent along the axis.
CAP = 0.2


def _cut(
    vertices: Array, faces: NDArray[np.int64], signed: Array
) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]]:
    """The triangles cut by the plane ``signed == 0`` (``signed`` each vertex's signed
    distance): new vertices and triangles, and each new triangle's old one. A point where the
    plane crosses an edge is computed from the edge's ends in index order, so that the two
    triangles sharing the edge share it too."""
    above = signed > 0.0
    new_points: dict[tuple[int, int], int] = {}
    points = [vertices]
    count = len(vertices)

    def crossing(u: int, w: int) -> int:
        nonlocal count
        key = (min(u, w), max(u, w))
        if key not in new_points:
            a, b = key
            t = signed[a] / (signed[a] - signed[b])
            points.append((vertices[a] + t * (vertices[b] - vertices[a]))[None, :])
            new_points[key] = count
            count += 1
        return new_points[key]

    out, source = [], []
    for f, (a, b, c) in enumerate(faces):
        sides = above[[a, b, c]]
        if sides.all() or not sides.any():
            out.append((a, b, c))
            source.append(f)
            continue
        # Rotate so that the lone vertex (on its side alone) comes first; order is kept.
        lone = int(np.flatnonzero(sides != (sides.sum() >= 2))[0])
        i, j, k = np.roll([a, b, c], -lone)
        p, q = crossing(i, j), crossing(i, k)
        out += [(i, p, q), (p, j, k), (p, k, q)]
        source += [f, f, f]
    return (
        np.vstack(points),
        np.asarray(out, dtype=np.int64).reshape(-1, 3),
        np.asarray(source, dtype=np.int64),
    )


def _marked_end(
    vertices: Array, faces: NDArray[np.int64], part_of: NDArray[np.int64], direction: Array
) -> tuple[Array, NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_], Array]:
    """The surface cut where the last CAP of the body's extent along ``direction`` begins:
    vertices, triangles, their parts, which triangles are in that cap, and the point drawn at
    the end (the cap's centre, moved along ``direction`` to the body's end)."""
    along = vertices @ direction
    low, high = float(np.min(along)), float(np.max(along))
    if not high > low:
        return vertices, faces, part_of, np.zeros(len(faces), dtype=bool), high * direction
    level = high - CAP * (high - low)
    vertices, faces, source = _cut(vertices, faces, along - level)
    corners = vertices[faces]
    capped = corners.mean(axis=1) @ direction > level
    areas = np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    weights = areas * capped
    if weights.sum() > 0:
        centre = (corners.mean(axis=1) * weights[:, None]).sum(axis=0) / weights.sum()
    else:
        centre = vertices[int(np.argmax(vertices @ direction))]
    point = centre + (high - centre @ direction) * direction
    return vertices, faces, part_of[source], capped, point


def _largest_turn(vectors: Array) -> float:
    """The largest angle (degrees) between consecutive rows."""
    if len(vectors) < 2:
        return 0.0
    a, b = vectors[:-1], vectors[1:]
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    return float(np.degrees(np.max(np.arctan2(cross, np.einsum("ij,ij->i", a, b)))))


def _plane_disc(centre: Array, e1: Array, e2: Array, radius: float, n: int = 48) -> Array:
    """Vertices of a disc: its centre, then n points of its rim."""
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = centre + radius * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    return np.vstack([centre, rim])


def _arrow_head(tip: Array, direction: Array, length: float, radius: float, n: int = 12) -> Array:
    """Vertices of a cone: its tip, its base's centre, then n points of its base's rim."""
    norm = float(np.linalg.norm(direction))
    u = direction / norm if norm > 0 else np.array([0.0, 0.0, 1.0])
    helper = np.eye(3)[int(np.argmin(np.abs(u)))]
    a = np.cross(u, helper)
    a /= np.linalg.norm(a)
    b = np.cross(u, a)
    base = tip - length * u
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = base + radius * (np.cos(phi)[:, None] * a + np.sin(phi)[:, None] * b)
    return np.vstack([tip, base, rim])


def _fan(n: int, centre: int = 0, first: int = 1) -> NDArray[np.int64]:
    """Triangles (centre, first + k, first + k + 1) around a closed rim of n points."""
    k = np.arange(n)
    return np.column_stack([np.full(n, centre), first + k, first + (k + 1) % n])


def _cone_faces(n: int = 12) -> NDArray[np.int64]:
    return np.vstack([_fan(n, 0, 2), _fan(n, 1, 2)[:, [0, 2, 1]]])


def _basis(normal: Array, hint: Array) -> tuple[Array, Array]:
    """e1, e2 with (e1, e2, normal) right-handed and orthonormal, e1 along hint's part in the
    plane (or an axis's, when the hint is along the normal)."""
    for c in (hint, *np.eye(3)[np.argsort(np.abs(normal))]):
        e1 = c - np.dot(c, normal) * normal
        size = float(np.linalg.norm(e1))
        if size > 1e-6 * max(float(np.linalg.norm(c)), 1e-300):
            e1 = e1 / size
            return e1, np.cross(normal, e1)
    raise AssertionError("no direction off the normal")  # pragma: no cover


# -------------------------------------------------------------------------------------------------
# The figure
# -------------------------------------------------------------------------------------------------


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
    says the regime (:func:`polhode.analyze`'s ``regime`` of the motion at the first output
    time) and the frame's time.

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
    body : Body, optional
        The body it was simulated with (its principal moments and axes must match the
        trajectory's); default: drawn as the box of the trajectory's moments.
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
        Segments around a circle of the ellipsoid and of the body's solids.
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
        a screen shows) or ``numpy.float64``.
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
    from scipy.spatial.transform import Rotation

    from polhode.analysis import analyze
    from polhode.bodies import Body

    trajectory = _check_trajectory(trajectory)
    if body is not None and not isinstance(body, Body):
        raise TypeError(f"Expected `body` to be a polhode.Body or None, got {type(body).__name__}.")
    fixed = None
    if origin is not None:
        if body is None:
            raise ArgumentError(
                "`origin` is a point of `body`: give it with a Body.", argument="origin"
            )
        fixed = as_array("origin", origin, (3,))
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
    curve_points = as_integer("curve_points", curve_points, minimum=2)
    resolution = as_integer("resolution", resolution, minimum=6)
    max_vertices = as_integer("max_vertices", max_vertices, minimum=8)
    frame_duration = as_scalar("frame_duration", frame_duration)
    if not (np.isfinite(frame_duration) and frame_duration >= 0):
        raise ArgumentError(
            f"Expected `frame_duration` to be finite and >= 0, got {frame_duration}.",
            argument="frame_duration",
        )

    unit = _units(units)
    rate = f"rad/{unit['time']}"
    t = np.asarray(trajectory.t, dtype=np.float64)
    omega_body = np.asarray(trajectory.omega, dtype=np.float64)
    if not np.all(np.any(omega_body != 0.0, axis=1)):
        raise ArgumentError(
            "`trajectory` is at rest at some output time (omega = 0): no energy ellipsoid, no "
            "invariable plane.",
            argument="trajectory",
        )
    indices = _frame_indices(frames, t.size)
    tensor = _inertia(trajectory, body, fixed)
    moments, axes = np.linalg.eigh(tensor)
    if mark is None:
        mark = int(np.argmax(np.abs(omega_body[0] @ axes)))
    else:
        mark = as_integer("mark", mark, allowed=(0, 1, 2))
    mark = int(mark)
    direction = axes[:, mark] * (-1.0 if (tensor @ omega_body[0]) @ axes[:, mark] < 0 else 1.0)

    # Every output time: rotations, omega in space, T, L in space.
    rotations = Rotation.from_quat(np.asarray(trajectory.quaternion)).as_matrix()
    omega_space = np.einsum("mij,mj->mi", rotations, omega_body)
    momentum_body = omega_body @ tensor.T
    energy = 0.5 * np.einsum("mi,mi->m", omega_body, momentum_body)
    momentum = np.einsum("mij,mj->mi", rotations, momentum_body)
    size_l = np.linalg.norm(momentum, axis=1)
    normal = momentum / size_l[:, None]
    distance = 2.0 * energy / size_l
    change = float(np.max(np.linalg.norm(momentum - momentum[0], axis=1)) / size_l[0])
    moving = change > L_TOLERANCE

    # The curves: at most curve_points output times, every frame's among them.
    every = np.unique(np.linspace(0, t.size - 1, min(curve_points, t.size)).round())
    curve = np.union1d(every.astype(np.int64), indices)
    turn = max(_largest_turn(omega_body[curve]), _largest_turn(omega_space[curve]))
    if t.size < MIN_TIMES:
        warnings.warn(
            f"`trajectory` has {t.size} output times: the scene has as many frames at most, and "
            "its curves as many points. Simulate at more output times "
            "(t=numpy.linspace(t0, t1, 1000)).",
            UserWarning,
            stacklevel=2,
        )
    elif turn > MAX_TURN:
        advice = (
            "raise `curve_points`"
            if curve.size < t.size
            else "simulate at more output times (t=numpy.linspace(t0, t1, 1000))"
        )
        warnings.warn(
            "The polhode and the herpolhode are drawn as straight segments between output "
            f"times, and omega turns by up to {turn:.0f} degrees between two of them: {advice}.",
            UserWarning,
            stacklevel=2,
        )

    # Sizes: the largest semi-axis, the plane's reach, the scene's half-width.
    semi = np.sqrt(2.0 * energy[:, None] / moments[None, :])  # (M, 3)
    largest = float(np.max(semi))
    centres = distance[:, None] * normal
    spread = float(np.max(np.linalg.norm(omega_space - centres, axis=1)))
    radius = max(1.15 * spread, 0.6 * largest)
    half = 1.08 * max(largest, float(np.max(np.sqrt(distance**2 + radius**2))))
    l_length = 0.97 * half
    head_length, head_radius = 0.07 * half, 0.025 * half

    # The body about the fixed point, scaled to fit in the smallest ellipsoid of the frames.
    origin_point = (
        (body.center_of_mass if fixed is None else fixed) if body is not None else np.zeros(3)
    )
    vertices, faces, part_of, what = _body_mesh(
        body, tensor, origin_point, resolution, max_vertices
    )
    quadratic = np.einsum("vi,ij,vj->v", vertices, tensor, vertices)
    reach = float(np.max(quadratic)) if vertices.size else 0.0
    scale = 0.85 * float(np.sqrt(2.0 * np.min(energy) / reach)) if reach > 0 else 1.0
    vertices, faces, part_of, capped, mark_point = _marked_end(vertices, faces, part_of, direction)
    face_colors = np.where(capped, MARK_COLOR, np.asarray(PART_COLORS)[part_of % len(PART_COLORS)])

    sphere, sphere_faces = unit_sphere(resolution)
    e1, e2 = _basis(normal[0], omega_space[0] - centres[0])

    # The regime, from the motion at the first output time.
    regime = analyze(tensor, omega_body[0]).regime
    if moving:
        condition = f"L not conserved (changes by {change:.2g} of |L|): L and the plane move"
    else:
        condition = f"regime {regime}"

    def cast(values: Array) -> NDArray[Any]:
        return np.ascontiguousarray(values, dtype=store)

    def xyz(points: Array) -> dict[str, NDArray[Any]]:
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        return {"x": cast(points[:, 0]), "y": cast(points[:, 1]), "z": cast(points[:, 2])}

    def frame_data(k: int) -> list[dict[str, Any]]:
        """x, y, z of every trace (TRACES' order) at output time index k."""
        r = rotations[k]
        ellipsoid_body = (sphere * semi[k]) @ axes.T
        e1k, e2k = _basis(normal[k], e1)
        shown = curve[curve <= k]
        omega_tip = omega_space[k]
        l_tip = l_length * normal[k]
        data = [
            xyz(scale * vertices @ r.T),
            xyz(scale * (r @ mark_point)),
        ]
        for a in range(3):
            tip = semi[k, a] * (r @ axes[:, a])
            data.append(xyz(np.stack([-tip, tip])))
        data += [
            xyz(ellipsoid_body @ r.T),
            xyz(omega_body[shown] @ r.T),
            xyz(_plane_disc(distance[k] * normal[k], e1k, e2k, radius)),
            xyz(omega_space[shown]),
            xyz(np.stack([np.zeros(3), l_tip - head_length * normal[k]])),
            xyz(_arrow_head(l_tip, normal[k], head_length, head_radius)),
            xyz(
                np.stack(
                    [np.zeros(3), omega_tip - head_length * omega_tip / np.linalg.norm(omega_tip)]
                )
            ),
            xyz(_arrow_head(omega_tip, omega_tip, head_length, head_radius)),
            xyz(omega_tip),
        ]
        return data

    def title(k: int) -> str:
        return f"Poinsot's construction ({condition})<br>t = {t[k]:.4g} {unit['time']}"

    first = frame_data(int(indices[0]))
    plane_faces = _fan(48)
    cone_faces = _cone_faces()
    flat = {"flatshading": True, "hoverinfo": "skip"}
    if body is None:
        body_name = f"inertia box of the moments ({scale:.3g} {rate} per {unit['length']})"
    else:
        body_name = f"{what} ({scale:.3g} {rate} per {unit['length']})"
    traces: list[Any] = [
        go.Mesh3d(
            **first[0],
            i=faces[:, 0],
            j=faces[:, 1],
            k=faces[:, 2],
            facecolor=face_colors,
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
                f"marked end: +I{mark + 1} axis (toward L at t = {t[indices[0]]:.3g} "
                f"{unit['time']})"
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
    traces += [
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
                f"L, {'moving' if moving else 'fixed'} (|L| = {size_l[indices[0]]:.4g} "
                f"{unit['mass']} {unit['length']}^2/{unit['time']}; its direction)"
            ),
            legendgroup="L",
            uid="L",
            hoverinfo="skip",
        ),
        go.Mesh3d(
            **first[10],
            i=cone_faces[:, 0],
            j=cone_faces[:, 1],
            k=cone_faces[:, 2],
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
            i=cone_faces[:, 0],
            j=cone_faces[:, 1],
            k=cone_faces[:, 2],
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

    names = [str(k) for k in range(len(indices))]
    every_trace = list(range(len(TRACES)))
    animation_frames = [
        go.Frame(
            name=name,
            data=[
                go.Mesh3d(**d)
                if TRACES[n] in ("body", "ellipsoid", "plane", "L_head", "omega_head")
                else go.Scatter3d(**d)
                for n, d in enumerate(frame_data(int(k)))
            ],
            traces=every_trace,
            layout={"title": {"text": title(int(k))}},
        )
        for name, k in zip(names, indices, strict=True)
    ]

    play = {
        "frame": {"duration": frame_duration, "redraw": True},
        "transition": {"duration": 0},
        "fromcurrent": True,
        "mode": "immediate",
    }
    step = {
        "frame": {"duration": 0, "redraw": True},
        "transition": {"duration": 0},
        "mode": "immediate",
    }
    eye_direction = 0.93 * (0.8 * e1 + 0.6 * e2) + 0.45 * normal[0]
    eye = 2.25 * eye_direction / np.linalg.norm(eye_direction)
    axis_style = {
        "range": [-half, half],
        "autorange": False,
        "showbackground": True,
        "backgroundcolor": "#f4f4f4",
        "gridcolor": "#dddddd",
        "zerolinecolor": "#bbbbbb",
    }
    layout = go.Layout(
        title={"text": title(int(indices[0])), "x": 0.5, "xanchor": "center"},
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
                "up": dict(zip("xyz", normal[0].tolist(), strict=True)),
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
                "currentvalue": {"prefix": "t = ", "suffix": f" {unit['time']}", "visible": True},
                "steps": [
                    {"label": f"{t[k]:.3g}", "method": "animate", "args": [[name], step]}
                    for name, k in zip(names, indices, strict=True)
                ],
            }
        ],
        meta={
            "frame_indices": indices.tolist(),
            "body_scale": scale,
            "mark": mark,
            "mark_direction": direction.tolist(),
        },
    )
    figure = go.Figure(data=traces, layout=layout, frames=animation_frames)
    if path is not None:
        figure.write_html(path, include_plotlyjs=True, auto_play=False)
    return figure
