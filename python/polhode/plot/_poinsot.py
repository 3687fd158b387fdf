"""The parts of :func:`polhode.plot.scene` (and what :func:`polhode.plot.animate` shares with
it): the checks of its arguments, the body's mesh and its marked end, arrows, discs and the
frames' geometry (numpy only)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode import _shapes
from polhode._coerce import as_integer, unmasked
from polhode._norms import norms
from polhode.errors import ArgumentError
from polhode.plot._axes import one_trajectory
from polhode.plot._labels import AXIS_ROLES

if TYPE_CHECKING:
    from polhode.bodies import Body
    from polhode.simulation import Trajectory


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

__all__ = [
    "AXIS_COLORS",
    "AXIS_ROLES",
    "CAP",
    "L_TOLERANCE",
    "MARK_COLOR",
    "MAX_RESOLUTION",
    "MAX_TURN",
    "MIN_TIMES",
    "PART_COLORS",
    "TRACES",
    "arrow_cone_faces",
    "arrow_head",
    "body_mesh",
    "capped_polygons",
    "equal_lengths",
    "check_resolution",
    "check_trajectory",
    "fan_faces",
    "frame_indices",
    "inertia_about_origin",
    "largest_turn",
    "mark_of",
    "marked_end",
    "plane_basis",
    "plane_disc",
    "unit_sphere",
]

#: Largest turn of omega (degrees, in the body or in space) between two points of the curves
#: before :func:`scene` warns that they are too far apart to draw the curves.
MAX_TURN = 20.0

#: Fewer output times than this, and :func:`scene` warns that they cannot draw the motion.
MIN_TIMES = 10

#: The most segments around a circle (``resolution`` of :func:`scene` and :func:`animate`): one
#: per degree. A sphere of this resolution has 64,800 faces, in every frame.
MAX_RESOLUTION = 360

#: Relative change of L in space above which the figure says that L is not conserved.
L_TOLERANCE = 1e-6


# -------------------------------------------------------------------------------------------------
# Checks
# -------------------------------------------------------------------------------------------------


def check_trajectory(trajectory: Any) -> Trajectory:
    trajectory = one_trajectory(trajectory, "scene", name="trajectory", orientation=True)
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


def check_resolution(resolution: Any) -> int:
    """Segments around a circle: an integer from 6 to MAX_RESOLUTION."""
    return as_integer(
        "resolution", resolution, minimum=6, maximum=MAX_RESOLUTION, why="one segment a degree"
    )


def frame_indices(frames: Any, count: int) -> NDArray[np.int64]:
    """Indices into the ``count`` output times: ``frames`` evenly spaced ones (a number, at
    least 1), or those given (integers from -count to count - 1)."""
    if np.ndim(frames) == 0:
        number = as_integer("frames", frames)
        if number < 1:
            raise ArgumentError(
                f"Expected `frames` to be at least 1, got {number}.", argument="frames"
            )
        return np.unique(np.linspace(0, count - 1, min(number, count)).round().astype(np.int64))
    if isinstance(frames, str | bytes) or np.ndim(frames) != 1:
        raise TypeError(
            f"Expected `frames` to be a number of frames or indices, got {type(frames).__name__}."
        )
    indices = np.asarray(unmasked("frames", frames))
    if indices.size == 0:
        raise ArgumentError(
            "Expected `frames` to be a non-empty array of output-time indices.", argument="frames"
        )
    if indices.dtype.kind not in "iu":
        raise TypeError(
            f"Expected `frames` to be output-time indices (integers), got {indices.dtype}."
        )
    if np.any(indices < -count) or np.any(indices >= count):
        raise ArgumentError(
            f"Expected `frames` to index the {count} output times, got {indices.tolist()}.",
            argument="frames",
        )
    return np.asarray(indices % count, dtype=np.int64)


def relative_mismatch(a: Array, b: Array) -> float:
    scale = float(np.max(np.abs(b))) if b.size else 0.0
    return float(np.max(np.abs(a - b))) / scale if scale > 0 else float(np.max(np.abs(a - b)))


def inertia_about_origin(
    trajectory: Trajectory, body: Body | None, origin: Array | None, tensor: Array | None = None
) -> Array:
    """The inertia tensor (about the fixed point, in the trajectory's body axes) of the motion.

    With a Body: its tensor about ``origin`` (default the centre of mass), and with ``tensor``
    (a body given as principal moments or a tensor) that tensor, checked against the
    trajectory's principal moments and against its ``I omega``. Without: the diagonal of the
    trajectory's moments when its omega is in those axes (a motion simulated with principal
    moments), else the tensor fitted to ``I omega`` over the output times.
    """
    moments = np.asarray(trajectory.moments, dtype=np.float64)
    omega = np.asarray(trajectory.omega, dtype=np.float64)
    momentum = np.asarray(trajectory.angular_momentum_body, dtype=np.float64)
    if body is not None or tensor is not None:
        if tensor is None:
            assert body is not None
            tensor = body.inertia if origin is None else body.inertia_about(origin)
        eigen = np.linalg.eigvalsh(tensor)
        about = "its centre of mass" if origin is None else f"origin={origin.tolist()}"
        if relative_mismatch(eigen, np.sort(moments)) > 1e-9:
            hint = " (for a heavy top, pass origin=the pivot)" if origin is None else ""
            raise ArgumentError(
                f"`body` does not match `trajectory`: its principal moments about {about} are "
                f"{eigen.tolist()}, the trajectory's {np.sort(moments).tolist()}; pass the body "
                f"the trajectory was simulated with{hint}.",
                argument="body",
            )
        if relative_mismatch(omega @ tensor.T, momentum) > 1e-9:
            raise ArgumentError(
                "`body` does not match `trajectory`: its principal moments agree but its axes "
                "do not (I omega differs from the trajectory's angular_momentum_body); pass "
                "the body the trajectory was simulated with, in the same axes.",
                argument="body",
            )
        return np.asarray(tensor, dtype=np.float64)
    diagonal = np.diag(moments)
    if relative_mismatch(omega * moments, momentum) <= 1e-9:
        return diagonal
    # omega in axes that are not principal (a tensor or a Body was simulated): the tensor
    # from L = I omega at the output times, if they span every direction.
    if np.linalg.matrix_rank(omega, tol=1e-8 * float(np.max(np.abs(omega)))) == 3:
        solution, *_ = np.linalg.lstsq(omega, momentum, rcond=None)
        tensor = (solution + solution.T) / 2.0
        if (
            relative_mismatch(omega @ tensor, momentum) <= 1e-8
            and relative_mismatch(np.linalg.eigvalsh(tensor), np.sort(moments)) <= 1e-8
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


def triangles(polygons: list[Array]) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]]:
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


def decimated(
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


def inertia_box(tensor: Array) -> list[Array]:
    """Faces of the uniform cuboid with these principal moments, along the principal axes;
    sides a_k^2 ~ I_i + I_j - I_k (a thin side where the moments break the triangle
    inequality), up to a common scale (its mass is unknown): the longest side 1, whatever the
    size of the moments (1e300 or 1e-300)."""
    moments, axes = np.linalg.eigh(tensor)
    squares = np.sum(moments) - 2.0 * moments
    squares = np.maximum(squares / float(np.max(squares)), 1e-4)
    shape = _shapes.part("cuboid", size=np.sqrt(squares))
    return _shapes.surface(_shapes.moved(shape, axes, np.zeros(3)) or ())


def body_mesh(
    body: Body | None, tensor: Array, origin: Array, resolution: int, max_vertices: int
) -> tuple[Array, NDArray[np.int64], NDArray[np.int64], str]:
    """The body's surface about the fixed point (body coordinates): vertices, triangles, each
    triangle's part index, and what it is."""
    if body is None:
        polygons = inertia_box(tensor)
        owner_part = [0] * len(polygons)
        what = "inertia box"
    else:
        shape = _shapes.of(body)
        parts = [_shapes.surface((p,), resolution) for p in shape]
        polygons = [q for part in parts for q in part]
        owner_part = [k for k, part in enumerate(parts) for _ in part]
        what = "equivalent ellipsoid" if body._shape is None else "body"
    vertices, faces, owner = triangles([np.asarray(q) - origin for q in polygons])
    part_of = np.asarray(owner_part, dtype=np.int64)[owner]
    vertices, faces, part_of = decimated(vertices, faces, part_of, max_vertices)
    return vertices, faces, part_of, what


#: The marked end of a body: the part of it in the last CAP of its extent along the axis.
CAP = 0.2


def cut_end(
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


def marked_end(
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
    vertices, faces, source = cut_end(vertices, faces, along - level)
    corners = vertices[faces]
    capped = corners.mean(axis=1) @ direction > level
    areas = norms(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]))
    weights = areas * capped
    if weights.sum() > 0:
        centre = (corners.mean(axis=1) * weights[:, None]).sum(axis=0) / weights.sum()
    else:
        centre = vertices[int(np.argmax(vertices @ direction))]
    point = centre + (high - centre @ direction) * direction
    return vertices, faces, part_of[source], capped, point


def mark_of(axes: Array, omega: Array, momentum: Array, mark: Any) -> tuple[int, Array]:
    """The principal axis whose end is marked (``mark``, a 0-based index of the moments
    ascending; default the one ``omega``, the first output time's, has its largest component
    along: the axis spun about) and its marked end, the direction along it that points toward
    the angular momentum ``momentum`` (body coordinates) at that time."""
    if mark is None:
        k = int(np.argmax(np.abs(omega @ axes)))
    else:
        k = as_integer("mark", mark, allowed=(0, 1, 2))
    return k, axes[:, k] * (-1.0 if momentum @ axes[:, k] < 0 else 1.0)


def _clipped(polygon: Array, signed: Array, above: bool) -> Array:
    """The part of a convex polygon on one side of the plane ``signed == 0`` (Sutherland and
    Hodgman's clipping; vertices on the plane belong to both sides)."""
    side = signed >= 0.0 if above else signed <= 0.0
    out = []
    count = len(polygon)
    for i in range(count):
        j = (i + 1) % count
        if side[i]:
            out.append(polygon[i])
        if signed[i] * signed[j] < 0.0:
            t = signed[i] / (signed[i] - signed[j])
            out.append(polygon[i] + t * (polygon[j] - polygon[i]))
    return np.asarray(out, dtype=np.float64).reshape(-1, 3)


def equal_lengths(polygons: list[Array]) -> list[Array]:
    """The polygons, each with as many vertices as the longest (its own repeated in order), for
    matplotlib's Poly3DCollection: it keeps polygons of several lengths in an array from
    ``np.empty`` and projects the unused entries too, whose leftover bits overflowed now and
    then (numpy's RuntimeWarning at draw time, matplotlib 3.11). The repeats are chosen so that
    the vertices matplotlib takes for a polygon's normal (0, n // 3, 2 n // 3 of n) are those it
    takes of the polygon itself: the shading is unchanged, and so is every outline."""
    longest = max((len(q) for q in polygons), default=0)
    out = []
    for q in polygons:
        count = len(q)
        if count == longest:
            out.append(q)
            continue
        # Three runs, each onto its third of the polygon, in order and onto every vertex.
        cuts = (0, longest // 3, 2 * longest // 3, longest)
        marks = (0, count // 3, 2 * count // 3, count)
        index = np.concatenate(
            [
                marks[k] + (np.arange(cuts[k + 1] - cuts[k]) * (marks[k + 1] - marks[k]))
                // (cuts[k + 1] - cuts[k])
                for k in range(3)
            ]
        )
        out.append(q[index])
    return out


def capped_polygons(
    polygons: list[Array], owner: list[int], direction: Array
) -> tuple[list[Array], list[int], NDArray[np.bool_], Array]:
    """The polygons cut where the last CAP of the body's extent along ``direction`` begins
    (:func:`marked_end` for polygons, which :func:`polhode.plot.animate` draws): the pieces,
    each piece's owner (its polygon's), which pieces are in that cap, and the point drawn at
    the end (the cap's centre, moved along ``direction`` to the body's end)."""
    along = [q @ direction for q in polygons]
    low = min(float(np.min(a)) for a in along)
    high = max(float(np.max(a)) for a in along)
    if not high > low:
        return polygons, owner, np.zeros(len(polygons), dtype=bool), high * direction
    level = high - CAP * (high - low)
    pieces: list[Array] = []
    owners: list[int] = []
    capped: list[bool] = []
    for polygon, part, a in zip(polygons, owner, along, strict=True):
        signed = a - level
        if np.all(signed >= 0.0) or np.all(signed <= 0.0):
            pieces.append(polygon)
            owners.append(part)
            capped.append(bool(np.mean(signed) > 0.0))
            continue
        for above in (True, False):
            piece = _clipped(polygon, signed, above)
            if len(piece) >= 3:
                pieces.append(piece)
                owners.append(part)
                capped.append(above)
    flags = np.asarray(capped, dtype=bool)
    centres = np.array([q.mean(axis=0) for q in pieces])
    areas = np.array([_area(q) for q in pieces]) * flags
    if areas.sum() > 0:
        centre = (centres * areas[:, None]).sum(axis=0) / areas.sum()
    else:
        points = np.concatenate(polygons)
        centre = points[int(np.argmax(points @ direction))]
    return pieces, owners, flags, centre + (high - centre @ direction) * direction


def _area(polygon: Array) -> float:
    """The area of a planar polygon (the norm of half the sum of its fan's cross products)."""
    first = polygon[0]
    total = np.zeros(3)
    for a, b in zip(polygon[1:-1], polygon[2:], strict=True):
        total += np.cross(a - first, b - first)
    return float(norms(total)) / 2.0


def largest_turn(vectors: Array) -> float:
    """The largest angle (degrees) between consecutive rows."""
    if len(vectors) < 2:
        return 0.0
    a, b = vectors[:-1], vectors[1:]
    cross = norms(np.cross(a, b))
    return float(np.degrees(np.max(np.arctan2(cross, np.einsum("ij,ij->i", a, b)))))


def plane_disc(centre: Array, e1: Array, e2: Array, radius: float, n: int = 48) -> Array:
    """Vertices of a disc: its centre, then n points of its rim."""
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = centre + radius * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    return np.vstack([centre, rim])


def arrow_head(tip: Array, direction: Array, length: float, radius: float, n: int = 12) -> Array:
    """Vertices of a cone: its tip, its base's centre, then n points of its base's rim."""
    norm = float(norms(direction))
    u = direction / norm if norm > 0 else np.array([0.0, 0.0, 1.0])
    helper = np.eye(3)[int(np.argmin(np.abs(u)))]
    a = np.cross(u, helper)
    a /= norms(a)
    b = np.cross(u, a)
    base = tip - length * u
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = base + radius * (np.cos(phi)[:, None] * a + np.sin(phi)[:, None] * b)
    return np.vstack([tip, base, rim])


def fan_faces(n: int, centre: int = 0, first: int = 1) -> NDArray[np.int64]:
    """Triangles (centre, first + k, first + k + 1) around a closed rim of n points."""
    k = np.arange(n)
    return np.column_stack([np.full(n, centre), first + k, first + (k + 1) % n])


def arrow_cone_faces(n: int = 12) -> NDArray[np.int64]:
    return np.vstack([fan_faces(n, 0, 2), fan_faces(n, 1, 2)[:, [0, 2, 1]]])


def plane_basis(normal: Array, hint: Array) -> tuple[Array, Array]:
    """e1, e2 with (e1, e2, normal) right-handed and orthonormal, e1 along hint's part in the
    plane (or an axis's, when the hint is along the normal)."""
    for c in (hint, *np.eye(3)[np.argsort(np.abs(normal))]):
        e1 = c - np.dot(c, normal) * normal
        size = float(norms(e1))
        if size > 1e-6 * max(float(norms(c)), 1e-300):
            e1 = e1 / size
            return e1, np.cross(normal, e1)
    raise AssertionError("no direction off the normal")  # pragma: no cover


# -------------------------------------------------------------------------------------------------
# The figure
# -------------------------------------------------------------------------------------------------
