"""MuJoCo's meshes for MJCF as MuJoCo compiles it: the mesh files read as MuJoCo reads them
(binary STL, OBJ, MSH; vertices stored as float32), moved by ``refpos``/``refquat`` and scaled,
and their volume, centre and inertia in each ``<mesh inertia=...>`` mode.

- ``exact``, ``convex`` (the convex hull of every vertex) and ``shell`` are polhode's exact
  integrals (:meth:`polhode.Body.mesh`) of the mesh MuJoCo holds. A mesh that is not closed,
  which MuJoCo integrates all the same (its value then depends on where its face centroid
  lies), gets MuJoCo's own formula, with a note.
- ``legacy`` (MuJoCo 4.0.0's default) is MuJoCo's formula, reproduced here: pyramids from the
  area-weighted centroid of the faces to each face, their volumes taken in absolute value,
  then again from the centre so found. It equals the exact integral for a mesh every face of
  which is seen from outside from both points, and over-counts other non-convex meshes.

MuJoCo's own formulas (user_mesh.cc, ``ComputeVolume``, ``ComputeInertia``) are in
:func:`mujoco_integrals`, vectorised; MuJoCo sums face by face, so the two agree to a few
units in the last place.
"""

from __future__ import annotations

import math
import os
import struct
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from polhode._meshes import merge_vertices
from polhode.bodies import Body
from polhode.errors import PolhodeError

__all__ = [
    "MESH_MODES",
    "MeshError",
    "MeshInertia",
    "eig3",
    "mesh_inertia",
    "mujoco_integrals",
    "quat_matrix",
    "read_mujoco_mesh",
]

#: MuJoCo's mesh inertia modes (``<mesh inertia=...>``), by the value of mjtMeshInertia.
MESH_MODES = ("convex", "exact", "legacy", "shell")

#: MuJoCo's mjMINVAL: the smallest area, volume, mass and moment it takes for non-zero.
MINVAL = 1e-15


class MeshError(Exception):
    """A mesh MuJoCo refuses (or that cannot be read): the message is MuJoCo's reason."""


@dataclass(frozen=True)
class MeshInertia:
    """A mesh's mass properties per unit density as MuJoCo computes them, in the mesh's
    coordinates (after refpos, refquat and scale): ``measure`` (the volume, or the area for
    ``inertia="shell"``), the centre, the inertia tensor about the centre, and the principal
    moments (decreasing) and axes (columns) of MuJoCo's own eigensolver, which place a
    primitive fitted to the mesh. ``vertices`` are the mesh's, for a fit to its bounding
    box; ``notes`` say what MuJoCo does that a reader should know."""

    measure: float
    center: NDArray[np.float64]
    tensor: NDArray[np.float64]
    moments: NDArray[np.float64]
    axes: NDArray[np.float64]
    vertices: NDArray[np.float64]
    notes: tuple[str, ...]


def quat_matrix(wxyz: NDArray[np.float64]) -> NDArray[np.float64]:
    """The rotation of a (w, x, y, z) quaternion, normalised first (mjuu_quat2mat after
    mjuu_normvec)."""
    q = np.asarray(wxyz, dtype=float)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


# --- reading mesh files as MuJoCo does -------------------------------------------------------


def read_mujoco_mesh(
    path: str, content_type: str = ""
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The vertices (float32 values, as float64) and triangles MuJoCo reads from a mesh file:
    binary STL, OBJ (the faces of its first object only, as MuJoCo's decoder takes them) or
    MuJoCo's MSH. MeshError with MuJoCo's reason for what it refuses."""
    kind = {"model/stl": "stl", "model/obj": "obj", "model/vnd.mujoco.msh": "msh"}.get(
        content_type, os.path.splitext(path)[1].lower().lstrip(".")
    )
    if kind not in ("stl", "obj", "msh"):
        raise MeshError(
            f"MuJoCo reads STL, OBJ and MSH mesh files, not {os.path.basename(path)!r}."
        )
    if not os.path.isfile(path):
        raise MeshError(f"the mesh file {path!r} is not found.")
    with open(path, "rb") as handle:
        data = handle.read()
    if kind == "stl":
        return _read_stl(path, data)
    if kind == "msh":
        return _read_msh(path, data)
    return _read_obj(path, data)


def _read_stl(path: str, data: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Binary STL, as MuJoCo's stl_decoder: 1 to 200000 triangles, the size exact (an ASCII
    STL is refused), vertices shared by their bit pattern."""
    if len(data) < 84:
        raise MeshError(f"invalid header in STL file {path!r} (an ASCII STL file?).")
    (count,) = struct.unpack_from("<i", data, 80)
    if not 1 <= count <= 200000:
        raise MeshError(
            f"MuJoCo reads binary STL files of 1 to 200000 triangles; {path!r} says {count} "
            "(an ASCII STL file?)."
        )
    if count * 50 != len(data) - 84:
        raise MeshError(f"STL file {path!r} has the wrong size (an ASCII STL file?).")
    records = np.frombuffer(data, dtype=np.uint8, offset=84).reshape(count, 50)
    corners = records[:, 12:48].copy().view("<f4").reshape(-1, 3)
    if np.any(np.abs(corners) > 2.0**30):
        raise MeshError(f"a vertex of STL file {path!r} exceeds MuJoCo's bounds (2^30).")
    # Vertices shared by bit pattern (0.0 and -0.0 are two), in order of first appearance.
    keys = np.ascontiguousarray(corners).view(np.dtype((np.void, 12))).reshape(-1)
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    vertices = corners[first[order]].astype(float)
    faces = rank[np.asarray(inverse).reshape(-1)].reshape(count, 3).astype(np.int64)
    return vertices, faces


def _read_msh(path: str, data: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """MuJoCo's MSH: four int32 counts (vertices, normals, texture coordinates, faces), then
    float32 vertices, normals, texture coordinates and int32 faces."""
    if len(data) < 16:
        raise MeshError(f"missing header in MSH file {path!r}.")
    nv, nn, nt, nf = struct.unpack_from("<4i", data, 0)
    if nv < 4 or nf < 0 or nn < 0 or nt < 0 or (nn and nn != nv) or (nt and nt != nv):
        raise MeshError(f"invalid sizes in MSH file {path!r}.")
    if len(data) != 16 + 12 * nv + 12 * nn + 8 * nt + 12 * nf:
        raise MeshError(f"unexpected file size in MSH file {path!r}.")
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=16).reshape(-1, 3)
    offset = 16 + 12 * nv + 12 * nn + 8 * nt
    faces = np.frombuffer(data, dtype="<i4", count=3 * nf, offset=offset).reshape(-1, 3)
    return vertices.astype(float), faces.astype(np.int64)


def _read_obj(path: str, data: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """OBJ as MuJoCo's obj_decoder takes it from tinyobjloader: every vertex, and the faces
    of the first shape (a new shape starts at an ``o`` or ``g`` line once the current one has
    faces); triangles as they are, quads split (0, 1, 2), (0, 2, 3); larger polygons are
    refused."""
    vertices: list[tuple[float, float, float]] = []
    shapes: list[list[list[int]]] = [[]]
    for number, raw in enumerate(data.decode("utf-8", errors="replace").splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        head, _, rest = line.partition(" ")
        if head == "v":
            parts = rest.split()
            try:
                vertices.append(tuple(float(x) for x in parts[:3]))  # type: ignore[arg-type]
            except (ValueError, IndexError):
                raise MeshError(f"{path!r} line {number}: a vertex needs 3 numbers.") from None
            if len(parts) < 3:
                raise MeshError(f"{path!r} line {number}: a vertex needs 3 numbers.")
        elif head in ("o", "g"):
            if shapes[-1]:
                shapes.append([])
        elif head == "f":
            corners = []
            for token in rest.split():
                try:
                    index = int(token.split("/")[0])
                except ValueError:
                    raise MeshError(f"{path!r} line {number}: bad face index {token!r}.") from None
                corners.append(index - 1 if index > 0 else len(vertices) + index)
            shapes[-1].append(corners)
    faces: list[list[int]] = []
    for polygon in shapes[0]:
        if len(polygon) == 3:
            faces.append(polygon)
        elif len(polygon) == 4:
            faces += [[polygon[0], polygon[1], polygon[2]], [polygon[0], polygon[2], polygon[3]]]
        else:
            raise MeshError(
                f"MuJoCo reads OBJ faces of 3 or 4 vertices; {path!r} has one of {len(polygon)}."
            )
    v = np.asarray(vertices, dtype=np.float32).astype(float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(f) and (f.min() < 0 or f.max() >= len(v)):
        raise MeshError(f"{path!r}: a face refers to a vertex that does not exist.")
    return v, f


# --- MuJoCo's integrals ----------------------------------------------------------------------


def _triangles(
    v: NDArray[np.float64], f: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Area, unit normal and centroid of each triangle, as MuJoCo's ``triangle()`` (a triangle
    whose doubled area is below mjMINVAL has area 0)."""
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    centers = (a + b + c) / 3
    cross = np.cross(b - a, c - a)
    length = np.sqrt(np.einsum("ij,ij->i", cross, cross))
    small = length < MINVAL
    area = np.where(small, 0.0, 0.5 * length)
    normals = cross / np.where(small, 1.0, length)[:, None]
    return area, normals, centers


def mujoco_integrals(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], mode: str
) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """MuJoCo's measure (volume, or area for "shell"), centre and inertia tensor per unit
    density of a mesh (user_mesh.cc ComputeFaceCentroid, ComputeVolume or
    ComputeSurfaceArea, ComputeInertia), ``mode`` one of "legacy", "exact" (also convex,
    on the hull's faces) and "shell". MeshError where MuJoCo refuses the mesh."""
    area, normals, centers = _triangles(vertices, faces)
    total_area = math.fsum(area)
    if total_area < MINVAL:
        raise MeshError("its surface area is too small (MuJoCo: below 1e-15).")
    facecen = (area[:, None] * centers).sum(axis=0) / total_area
    if mode == "shell":
        measure = total_area
        center = facecen
    else:
        volumes = np.einsum("ij,ij->i", centers - facecen, normals) * area / 3
        if mode == "legacy":
            volumes = np.abs(volumes)
        measure = math.fsum(volumes)
        if measure < MINVAL:
            if measure < 0:
                raise MeshError("its volume is negative (triangles wound inward).")
            raise MeshError("its volume is too small (MuJoCo: below 1e-15).")
        center = (volumes[:, None] * (0.75 * centers + 0.25 * facecen)).sum(axis=0) / measure
    # Second pass: pyramids from the centre (for legacy, their volumes in absolute value
    # again; their sum becomes the volume).
    vc = vertices - center
    area, normals, centers = _triangles(vc, faces)
    if mode == "shell":
        weights = area / 12
        measure = math.fsum(area)
    else:
        volumes = np.einsum("ij,ij->i", centers, normals) * area / 3
        if mode == "legacy":
            volumes = np.abs(volumes)
        measure = math.fsum(volumes)
        weights = volumes / 20
    d, e, g = vc[faces[:, 0]], vc[faces[:, 1]], vc[faces[:, 2]]
    s = d + e + g
    # sum over triangles of w (2 (DD + EE + FF) + DE + ED + DF + FD + EF + FE)
    #   = w (DD + EE + FF + S S^T)
    second = np.einsum("t,ti,tj->ij", weights, d, d)
    second += np.einsum("t,ti,tj->ij", weights, e, e)
    second += np.einsum("t,ti,tj->ij", weights, g, g)
    second += np.einsum("t,ti,tj->ij", weights, s, s)
    tensor = np.trace(second) * np.eye(3) - second
    return float(measure), center, (tensor + tensor.T) / 2


def _orientation_conflict(
    faces: NDArray[np.int64], area: NDArray[np.float64]
) -> tuple[int, int] | None:
    """The first directed edge (a, b) used by two faces, among faces of area above
    sqrt(mjMINVAL), as MuJoCo checks ``exact`` meshes; None if there is none."""
    keep = faces[area > math.sqrt(MINVAL)]
    edges = np.concatenate([keep[:, [0, 1]], keep[:, [1, 2]], keep[:, [2, 0]]])
    if len(edges) == 0:
        return None
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    repeated = unique[counts > 1]
    return (int(repeated[0, 0]), int(repeated[0, 1])) if len(repeated) else None


def _convex_hull(vertices: NDArray[np.float64], maxhullvert: int) -> NDArray[np.int64]:
    """Outward-wound triangles of the convex hull (Qhull's "Qt", as MuJoCo; with
    ``maxhullvert`` its "Q9 TA" limit too)."""
    from scipy.spatial import ConvexHull

    options = "Qt"
    if maxhullvert > -1:
        options += f" Q9 TA{maxhullvert - 4}"
    try:
        hull = ConvexHull(vertices, qhull_options=options)
    except Exception as error:  # Qhull: flat, collinear or too few points
        raise MeshError(f"it has no convex hull ({type(error).__name__}).") from error
    faces = np.array(hull.simplices, dtype=np.int64)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    faces[inward] = faces[inward][:, ::-1]
    return faces


def mesh_inertia(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    mode: str,
    scale: NDArray[np.float64],
    refpos: NDArray[np.float64],
    refquat: NDArray[np.float64],
    maxhullvert: int = -1,
    strict_exact: bool = False,
) -> MeshInertia:
    """A mesh as MuJoCo compiles it (user_mesh.cc mjCMesh::Process): ``vertices`` (float32
    values) moved by ``refpos``, turned back by ``refquat``, scaled (a mirror reverses the
    winding), then integrated in ``mode``. MeshError where MuJoCo refuses it.

    With ``strict_exact`` (the exact value a legacy mesh is compared with), ``exact`` is
    polhode's integral of the closed mesh or a MeshError saying why there is none: neither
    MuJoCo's orientation check nor its formula for open meshes."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(v) < 4:
        raise MeshError("MuJoCo needs at least 4 vertices.")
    if not np.all(np.isfinite(v)):
        raise MeshError("a vertex is not finite.")
    if len(f) and (f.min() < 0 or f.max() >= len(v)):
        raise MeshError("a face refers to a vertex that does not exist.")
    if np.any(refpos):
        v = v - refpos
    if not np.array_equal(refquat, [1.0, 0.0, 0.0, 0.0]):
        v = v @ quat_matrix(refquat)
    if not np.array_equal(scale, [1.0, 1.0, 1.0]):
        v = v * scale
    if np.prod(scale) < 0 and len(f):
        f = np.ascontiguousarray(f[:, [0, 2, 1]])
    notes: list[str] = []
    if len(f) == 0:
        f = _convex_hull(v, maxhullvert)  # a cloud of points: its hull, in every mode
        notes.append("no faces: its convex hull")
    if mode == "exact" and not strict_exact:
        area, _, _ = _triangles(np.asarray(vertices, dtype=float), f)
        conflict = _orientation_conflict(f, area)
        if conflict is not None:
            raise MeshError(
                'MuJoCo refuses it in inertia="exact": its faces have inconsistent '
                f"orientation (the edge from vertex {conflict[0] + 1} to {conflict[1] + 1} "
                "is used twice in the same direction)."
            )
    if mode == "convex":
        f = _convex_hull(v, maxhullvert)
    # MuJoCo's formula is the reference for the checks; the exact modes then take polhode's
    # own integrals of the same mesh.
    measure, center, tensor = mujoco_integrals(v, f, "exact" if mode == "convex" else mode)
    if mode != "legacy":
        unique, merged = merge_vertices(v, f)
        try:
            body = Body.mesh(unique, merged, density=1.0, shell=mode == "shell")
        except PolhodeError as error:
            if strict_exact:
                raise MeshError(f"it has no exact volume: {error.message}") from None
            notes.append(
                f"polhode cannot integrate it ({error.message}); MuJoCo's integral of it, "
                "which depends on where its face centroid lies, is taken"
            )
        else:
            measure, center, tensor = body.mass, body.center_of_mass, body.inertia
    moments, axes = _principal(tensor)
    if moments[2] <= 0:
        raise MeshError("an eigenvalue of its inertia is not positive.")
    a, b, c = moments
    if (
        a + b < c * (1 - 1e-6) - 1e-9
        or a + c < b * (1 - 1e-6) - 1e-9
        or b + c < a * (1 - 1e-6) - 1e-9
    ):
        raise MeshError("the eigenvalues of its inertia violate A + B >= C.")
    return MeshInertia(measure, center, tensor, moments, axes, v, tuple(notes))


def _principal(tensor: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """MuJoCo's principal moments (decreasing) and axes (the columns of a rotation)."""
    moments, quat = eig3(tensor)
    return moments, quat_matrix(quat)


def eig3(matrix: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """MuJoCo's mjuu_eig3 (user_util.cc), step by step: Jacobi rotations accumulated in a
    quaternion until the largest off-diagonal element is below 1e-12 or the rotation's cosine
    above 1 - 1e-12, then the eigenvalues sorted in decreasing order by quarter turns. Returns
    the eigenvalues and the quaternion (w, x, y, z) of the eigenvectors. It fixes the frame a
    primitive fitted to a mesh takes, as MuJoCo places it (the axes of an exact solver can
    differ from it by up to ~1e-6 rad, and in any way within a degenerate eigenspace)."""
    eps = 1e-12
    quat = np.array([1.0, 0.0, 0.0, 0.0])
    values = np.diag(matrix).copy()
    for _ in range(500):
        r = _quat_rotation(quat)
        d = r.T @ matrix @ r
        values = np.array([d[0, 0], d[1, 1], d[2, 2]])
        if abs(d[0, 1]) > abs(d[0, 2]) and abs(d[0, 1]) > abs(d[1, 2]):
            row, col, axis = 0, 1, 2
        elif abs(d[0, 2]) > abs(d[1, 2]):
            row, col, axis = 0, 2, 1
        else:
            row, col, axis = 1, 2, 0
        if abs(d[row, col]) < eps:
            break
        tau = (d[col, col] - d[row, row]) / (2 * d[row, col])
        if tau >= 0:
            t = 1 / (tau + math.sqrt(1 + tau * tau))
        else:
            t = -1 / (-tau + math.sqrt(1 + tau * tau))
        cosine = 1 / math.sqrt(1 + t * t)
        if cosine > 1 - eps:
            break
        turn = np.zeros(4)
        turn[axis + 1] = (
            -math.sqrt(0.5 - 0.5 * cosine) if tau >= 0 else math.sqrt(0.5 - 0.5 * cosine)
        )
        if axis == 1:
            turn[axis + 1] = -turn[axis + 1]
        turn[0] = math.sqrt(1 - turn[axis + 1] ** 2)
        quat = _normalised(_quat_product(quat, _normalised(turn)))
    for j in range(3):
        k = j % 2
        if values[k] + eps < values[k + 1]:
            values[k], values[k + 1] = values[k + 1], values[k]
            turn = np.zeros(4)
            turn[0] = 0.707106781186548
            turn[(k + 2) % 3 + 1] = turn[0]
            quat = _normalised(_quat_product(quat, turn))
    return values, quat


def _quat_rotation(q: NDArray[np.float64]) -> NDArray[np.float64]:
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _quat_product(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def _normalised(q: NDArray[np.float64]) -> NDArray[np.float64]:
    norm = float(np.linalg.norm(q))
    if norm * norm < 1e-14 or abs(norm - 1) <= 1e-14:
        return q
    return q / norm
