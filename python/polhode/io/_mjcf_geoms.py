"""The geoms of an MJCF body as MuJoCo compiles them (user_objects.cc mjCGeom::Compile,
GetVolume, SetInertia): placement (``fromto``, orientations, ``<frame>``s and their scale),
the measure MuJoCo takes (volume, or area with ``shellinertia``), the mass (``mass``, which
MuJoCo silently drops when the measure is at most 1e-14, or ``density`` times the measure)
and the inertia. Each geom becomes a :class:`polhode.Body` in its body's frame.

Solids are polhode's (``Body.sphere``, ``capsule``, ``cylinder``, ``ellipsoid``, ``cuboid``,
``spherical_shell``); the other shells are MuJoCo's formulas, reproduced (the cylinder, box and
capsule shells are exact thin-shell results; the ellipsoid's area is Thomsen's approximation and
its inertia a difference of two solids 1e-6 apart, as MuJoCo computes them). A height field
weighs as the box MuJoCo takes for it; a plane has no volume.
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode.bodies import Body
from polhode.errors import PolhodeError
from polhode.io._links import placed
from polhode.io._mujoco_mesh import (
    MESH_MODES,
    MeshError,
    MeshInertia,
    mesh_inertia,
    quat_matrix,
    read_mujoco_mesh,
)

__all__ = [
    "EPS",
    "GeomError",
    "GeomInertial",
    "FileLevelError",
    "Meshes",
    "Placement",
    "frame_placement",
    "geom_inertial",
    "orientation",
]

#: MuJoCo's mjEPS: a geom's measure at most this has no mass, whatever its ``mass`` says.
EPS = 1e-14


class GeomError(Exception):
    """A geom MuJoCo refuses, or whose mass properties polhode cannot compute: ``field`` is the
    attribute at fault (``"geom[2].size"``), the message the reason."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field
        self.message = message


class FileLevelError(GeomError):
    """Not a body MuJoCo refuses but a file polhode cannot read: a value that is not a number
    (the file is malformed), or something MuJoCo compiles that polhode does not read (a
    stretching frame, which would make everything inside it wrong). The reader raises it."""


@dataclass(frozen=True)
class Placement:
    """The accumulated effect of the ``<frame>``s around an element: lengths multiplied by
    ``scale``, masses by ``mass``."""

    scale: float = 1.0
    mass: float = 1.0


@dataclass(frozen=True)
class GeomInertial:
    """A geom's share of its body: its Body in the body frame (None if it has no mass), the
    meshes it integrates in MuJoCo's ``legacy`` mode, and notes."""

    body: Body | None
    legacy: tuple[str, ...]
    notes: tuple[str, ...]


def orientation(compiler: Any, quat: Any, alt: Any) -> NDArray[np.float64]:
    """An element's (w, x, y, z) orientation, normalised: ``quat`` or its alternative (euler,
    axisangle, xyaxes, zaxis), resolved by MuJoCo's own function with the angle unit and
    Euler sequence of the element's compiler."""
    mujoco = importlib.import_module("mujoco")
    if alt.type == mujoco.mjtOrientation.mjORIENTATION_QUAT:
        q = np.asarray(quat, dtype=float)
    else:
        q = np.asarray(
            mujoco.MjSpec.resolve_orientation(compiler.degree, compiler.eulerseq, alt),
            dtype=float,
        )
    norm = float(np.linalg.norm(q))
    if not math.isfinite(norm):
        raise FileLevelError("quat", f"expected a finite quaternion, got {q.tolist()}.")
    if norm * norm < EPS:
        raise GeomError("quat", f"expected a non-zero quaternion, got {q.tolist()}.")
    return q if abs(norm - 1) <= EPS else q / norm


def frame_placement(element: Any) -> tuple[NDArray[np.float64], NDArray[np.float64], float, float]:
    """The rotation, offset, length scale and mass factor that carry coordinates of the
    innermost ``<frame>`` around ``element`` (its ``frame``) to the enclosing body's (or,
    for a body, to its parent's): frames inside frames compose, each scaling its contents
    about its origin."""
    rotation = np.eye(3)
    offset = np.zeros(3)
    scale = 1.0
    mass = 1.0
    frame = element.frame
    chain = []
    while frame is not None:
        chain.append(frame)
        frame = frame.frame
    for frame in chain:  # innermost first: x -> pos + R (s x)
        s, m = frame_scale(frame)
        r = quat_matrix(orientation(frame.compiler, frame.quat, frame.alt))
        rotation = r @ rotation
        offset = np.asarray(frame.pos, dtype=float) + r @ (s * offset)
        scale *= s
        mass *= m
    return rotation, offset, scale, mass


def frame_scale(frame: Any) -> tuple[float, float]:
    """A frame's length scale and mass factor (MuJoCo 4: ``scale``, ``massscale``; 0 means
    the volume ratio). A stretch (three different scales) is not supported."""
    s = np.asarray(frame.scale, dtype=float)
    if not (np.all(np.isfinite(s)) and np.all(s > 0)):
        raise GeomError("frame.scale", f"expected positive finite scales, got {s.tolist()}.")
    if not (s[0] == s[1] == s[2]):
        raise FileLevelError(
            "frame.scale",
            f"a <frame> that stretches its contents (scale {s.tolist()}) is not supported; "
            "polhode reads frames of one scale",
        )
    massscale = float(frame.massscale)
    return float(s[0]), (massscale if massscale > 0 else float(s[0]) ** 3)


class Meshes:
    """The meshes of a model as MuJoCo compiles them, each computed once per scale."""

    def __init__(self, spec: Any, folder: str, exact_legacy: bool = False):
        self.spec = spec
        self.folder = folder
        self.exact_legacy = exact_legacy  # integrate "legacy" meshes exactly (audit)
        self.cache: dict[tuple[str, float], MeshInertia | MeshError] = {}

    def mode(self, mesh: Any) -> str:
        return MESH_MODES[int(mesh.inertia)]

    def get(self, name: str, scale: float) -> MeshInertia:
        key = (name, scale)
        if key not in self.cache:
            try:
                self.cache[key] = self._compute(name, scale)
            except MeshError as error:
                self.cache[key] = error
        found = self.cache[key]
        if isinstance(found, MeshError):
            raise found
        return found

    def _compute(self, name: str, scale: float) -> MeshInertia:
        mesh = self.spec.mesh(name)
        if mesh is None:
            raise MeshError(f"no mesh asset named {name!r}.")
        if mesh.plugin.active:
            raise MeshError(f"mesh {name!r} is made by a plugin, which polhode does not run.")
        if mesh.file:
            try:
                vertices, faces = read_mujoco_mesh(self.path(mesh), str(mesh.content_type or ""))
            except MeshError as error:
                raise MeshError(f"mesh {name!r}: {error}") from None
        else:
            vertices = np.asarray(mesh.uservert, dtype=np.float32).astype(float).reshape(-1, 3)
            faces = np.asarray(mesh.userface, dtype=np.int64).reshape(-1, 3)
            if len(vertices) == 0:
                raise MeshError(f"mesh {name!r} has neither a file nor vertices.")
        mode = self.mode(mesh)
        if mode == "legacy" and self.exact_legacy:
            mode = "exact"
        try:
            return mesh_inertia(
                vertices,
                faces,
                mode,
                np.asarray(mesh.scale, dtype=float) * scale,
                np.asarray(mesh.refpos, dtype=float),
                np.asarray(mesh.refquat, dtype=float),
                int(mesh.maxhullvert),
                strict_exact=self.exact_legacy,
            )
        except MeshError as error:
            raise MeshError(f"mesh {name!r}: {error}") from None

    def path(self, mesh: Any) -> str:
        """The mesh's file as MuJoCo finds it: the model's folder, the compiler's meshdir,
        the file (its folders stripped with ``strippath``)."""
        import os

        file = str(mesh.file)
        if self.spec.strippath:
            file = os.path.basename(file)
        meshdir = str(getattr(mesh.compiler, "meshdir", "") or self.spec.meshdir or "")
        return os.path.join(self.folder, meshdir, file)


def _z2quat(vec: NDArray[np.float64]) -> NDArray[np.float64]:
    """mjuu_z2quat: the rotation taking +z to the unit vector ``vec``."""
    axis = np.cross([0.0, 0.0, 1.0], vec)
    norm = float(np.linalg.norm(axis))
    if norm * norm < EPS:
        norm = 0.0
    elif abs(norm - 1) > EPS:
        axis = axis / norm
    if norm < 1e-10:
        axis = np.array([1.0, 0.0, 0.0])
    angle = math.atan2(norm, float(vec[2]))
    return np.concatenate([[math.cos(angle / 2)], axis * math.sin(angle / 2)])


#: Number of size parameters MuJoCo checks per geom type (mjGEOMINFO), by name.
_SIZES = {"plane": 0, "hfield": 0, "sphere": 1, "capsule": 2, "ellipsoid": 3, "cylinder": 2,
          "box": 3, "mesh": 0, "sdf": 0}  # fmt: skip


def geom_inertial(geom: Any, label: str, meshes: Meshes, outer: Placement) -> GeomInertial:
    """A geom's mass properties in its body's frame, as MuJoCo compiles them; ``outer`` is
    the placement of the body's own frames (their scale applies to everything in it).
    GeomError where MuJoCo refuses the geom or polhode cannot compute it."""
    try:
        return _geom_inertial(geom, label, meshes, outer)
    except GeomError as error:
        field = error.field if error.field.startswith(label) else f"{label}.{error.field}"
        raise type(error)(field, error.message) from None
    except MeshError as error:
        raise GeomError(f"{label}.mesh", str(error)) from None


def _geom_inertial(geom: Any, label: str, meshes: Meshes, outer: Placement) -> GeomInertial:
    mujoco = importlib.import_module("mujoco")
    kind = str(geom.type).split("_")[-1].lower()  # mjtGeom.mjGEOM_BOX -> "box"
    size = np.asarray(geom.size, dtype=float).copy()
    fromto = np.asarray(geom.fromto, dtype=float)
    pos = np.asarray(geom.pos, dtype=float).copy()
    notes: list[str] = []
    legacy: tuple[str, ...] = ()
    for what, values in (("size", size), ("pos", pos), ("mass", [geom.mass]),
                         ("density", [geom.density])):  # fmt: skip
        if what == "mass" and np.isnan(geom.mass):
            continue
        if not np.all(np.isfinite(values)):
            wanted = "a finite position" if what == "pos" else "finite numbers"
            raise FileLevelError(what, f"expected {wanted}, got {np.asarray(values).tolist()}.")
    if not np.isnan(fromto[0]) and not np.all(np.isfinite(fromto)):
        raise FileLevelError("fromto", f"expected finite numbers, got {fromto.tolist()}.")
    if not np.isnan(fromto[0]):
        if kind not in ("capsule", "cylinder", "ellipsoid", "box"):
            raise GeomError("fromto", "fromto requires a capsule, cylinder, box or ellipsoid.")
        if np.any(pos):
            raise GeomError("fromto", "both pos and fromto are given.")
        vec = fromto[:3] - fromto[3:]
        length = float(np.linalg.norm(vec))
        half = length / 2 if length * length >= EPS else 0.0
        if half < EPS:
            raise GeomError("fromto", "the two fromto points are too close.")
        vec = vec / length if abs(length - 1) > EPS else vec
        size[1] = half
        if kind in ("ellipsoid", "box"):
            size[2], size[1] = size[1], size[0]
        pos = (fromto[:3] + fromto[3:]) / 2
        quat = _z2quat(vec)
    else:
        quat = orientation(geom.compiler, geom.quat, geom.alt)
    rotation = quat_matrix(quat)
    inner_rotation, inner_offset, inner_scale, inner_mass = frame_placement(geom)
    scale = outer.scale * inner_scale
    factor = outer.mass * inner_mass
    shell = geom.typeinertia == mujoco.mjtGeomInertia.mjINERTIA_SHELL
    mesh: MeshInertia | None = None
    mesh_shell = False
    if geom.meshname and kind != "hfield":
        if not np.isnan(fromto[0]):
            raise GeomError("fromto", "fromto cannot be used with a mesh.")
        m = meshes.spec.mesh(geom.meshname)
        mesh = meshes.get(geom.meshname, scale)
        if m is not None and meshes.mode(m) == "legacy" and not meshes.exact_legacy:
            legacy = (str(geom.meshname),)
        mesh_shell = m is not None and meshes.mode(m) == "shell"
        notes += [f"mesh {geom.meshname!r}: {n}" for n in mesh.notes]
        if kind in ("mesh", "sdf") and shell:
            raise GeomError(
                "shellinertia", "for mesh geoms, inertia is set in the mesh asset (inertia=)."
            )
    elif kind in ("mesh", "sdf"):
        raise GeomError("mesh", "a mesh geom without a mesh.")
    # The geom's measure (volume, or area for shells) and its inertia per unit mass, in the
    # geom frame; ``center`` the point of the geom frame its centre of mass is at.
    center = np.zeros(3)
    turn = np.eye(3)
    if kind in ("mesh", "sdf"):
        assert mesh is not None
        measure = mesh.measure
        center, unit = mesh.center, mesh.tensor / mesh.measure
        unit_body = None
    else:
        if mesh is not None:  # a primitive fitted to the mesh
            size, offset = _fitted(kind, mesh, float(geom.fitscale), meshes.spec.compiler.fitaabb)
            center = mesh.center + mesh.axes @ offset
            turn = mesh.axes
            count = _SIZES[kind]
            if np.any(~(size[:count] > 0)):
                bad = int(np.argmax(~(size[:count] > 0)))
                raise GeomError(
                    "mesh", f"fitted to the mesh, its size {bad} is {size[bad]:g}, not positive."
                )
        elif kind == "hfield":
            field = meshes.spec.hfield(geom.hfieldname)
            if field is None:
                raise GeomError("hfield", f"no height field named {geom.hfieldname!r}.")
            h = np.asarray(field.size, dtype=float)
            size = np.array([h[0], h[1], 0.25 * h[2] + 0.5 * h[3]])
        else:
            count = _SIZES.get(kind)
            if count is None:
                raise GeomError("type", f"geoms of type {kind} have no mass MuJoCo computes.")
            if np.any(~(size[:count] > 0)):
                raise GeomError(
                    "size", f"size {int(np.argmax(~(size[:count] > 0)))} must be positive."
                )
        if mesh is None:  # (a fitted primitive has the sizes of the scaled mesh)
            size = size * scale
        measure = _measure("box" if kind == "hfield" else kind, size, shell)
        unit = None
        unit_body = (kind, size, shell)
    if not math.isfinite(measure):
        raise GeomError(
            "size", f"its {'area' if shell else 'volume'} is beyond double precision ({measure})."
        )
    if not np.isnan(geom.mass):
        given = float(geom.mass) * factor
        if given == 0:
            return GeomInertial(None, legacy, tuple(notes))
        if not measure > EPS:
            if given != 0:
                notes.append(
                    f"its mass {float(geom.mass):g} is dropped: MuJoCo gives no mass to a geom "
                    f"of {'area' if shell else 'volume'} {measure:.3g} <= 1e-14"
                )
            return GeomInertial(None, legacy, tuple(notes))
        mass = given
    else:
        density = float(geom.density)
        if density == 0:
            return GeomInertial(None, legacy, tuple(notes))
        if density < 0:
            raise GeomError("density", f"the density {density:g} is negative.")
        # A frame's scale turns a density per volume by m / s^3, one per area (a shell) by
        # m / s^2: the mass is the same material's, times massscale.
        surface = shell or (mesh is not None and kind in ("mesh", "sdf") and mesh_shell)
        mass = density * factor / scale ** (2 if surface else 3) * measure
    if mass < 0:
        raise GeomError("mass", f"the mass {mass:g} is negative.")
    if not math.isfinite(mass):
        raise GeomError("density", f"its mass is beyond double precision ({mass}).")
    if not mass > EPS:
        return GeomInertial(None, legacy, tuple(notes))
    try:
        if unit_body is not None:
            body = _primitive(mass, *unit_body)
        else:
            assert unit is not None
            body = Body.from_inertia(mass, mass * unit)
    except PolhodeError as error:
        raise GeomError("size", error.message) from None
    # The primitive about its centre -> the geom frame -> the body frame: the frames inside
    # the body scale the geom's position by theirs, and the body's own frames everything.
    origin = outer.scale * (inner_offset + inner_rotation @ (inner_scale * pos))
    if not np.all(np.isfinite(origin)):  # a frame's position
        raise FileLevelError("pos", f"expected a finite position, got {origin.tolist()}.")
    try:
        body = placed(placed(body, turn, center), inner_rotation @ rotation, origin)
    except PolhodeError as error:  # beyond double precision
        raise GeomError("pos", error.message) from None
    return GeomInertial(body, legacy, tuple(notes))


def _fitted(
    kind: str, mesh: MeshInertia, fitscale: float, aabb: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """MuJoCo's primitive fitted to a mesh (user_mesh.cc mjCMesh::FitGeom): its sizes, from
    the mesh's equivalent inertia box or (``fitaabb``) its bounding box in the principal
    frame, times ``fitscale``; and its centre in that frame."""
    offset = np.zeros(3)
    size = np.zeros(3)
    if not aabb:
        a, b, c = mesh.moments
        box = 0.5 * np.sqrt(6 * np.array([b + c - a, a + c - b, a + b - c]) / mesh.measure)
        if kind == "sphere":
            size[0] = box.sum() / 3
        elif kind == "capsule":
            size[0] = (box[0] + box[1]) / 2
            size[1] = max(0.0, box[2] - size[0] / 2)
        elif kind == "cylinder":
            size[0] = (box[0] + box[1]) / 2
            size[1] = box[2]
        elif kind in ("ellipsoid", "box"):
            size[:] = box
        else:
            raise GeomError("type", f"a {kind} cannot be fitted to a mesh.")
    else:
        local = (mesh.vertices - mesh.center) @ mesh.axes
        low, high = local.min(axis=0), local.max(axis=0)
        offset = (low + high) / 2
        half = high - offset
        if kind == "sphere":
            size[0] = half.max()
        elif kind in ("capsule", "cylinder"):
            size[0] = max(half[0], half[1])
            size[1] = half[2] - (size[0] if kind == "capsule" else 0.0)
        elif kind in ("ellipsoid", "box"):
            size[:] = half
        else:
            raise GeomError("type", f"a {kind} cannot be fitted to a mesh.")
    return size * fitscale, offset


def _measure(kind: str, size: NDArray[np.float64], shell: bool) -> float:
    """mjCGeom::GetVolume: the volume, or with ``shell`` the area, of a primitive."""
    r = float(size[0])
    if kind == "sphere":
        return 4 * math.pi * r * r if shell else 4 * math.pi * r * r * r / 3
    if kind == "capsule":
        h = 2 * float(size[1])
        return (
            4 * math.pi * r * r + 2 * math.pi * r * h
            if shell
            else math.pi * (r * r * h + 4 * r * r * r / 3)
        )
    if kind == "cylinder":
        h = 2 * float(size[1])
        return 2 * math.pi * r * r + 2 * math.pi * r * h if shell else math.pi * r * r * h
    a, b, c = (float(x) for x in size[:3])
    if kind == "ellipsoid":
        if shell:  # Thomsen's approximation, as MuJoCo
            p = 1.6075
            return 4 * math.pi * (((a * b) ** p + (b * c) ** p + (c * a) ** p) / 3) ** (1 / p)
        return 4 * math.pi * a * b * c / 3
    if kind == "box":
        return 8 * (a * b + b * c + c * a) if shell else a * b * c * 8
    return 0.0  # a plane


def _primitive(mass: float, kind: str, size: NDArray[np.float64], shell: bool) -> Body:
    """A primitive of ``mass`` about its centre in its own axes: polhode's solids, MuJoCo's
    shell formulas (mjCGeom::SetInertia)."""
    r = float(size[0])
    if kind == "sphere":
        return Body.spherical_shell(mass, r) if shell else Body.sphere(mass, r)
    if not shell:
        if kind == "capsule":
            return Body.capsule(mass, r, 2 * float(size[1]))
        if kind == "cylinder":
            return Body.cylinder(mass, r, 2 * float(size[1]))
        if kind == "ellipsoid":
            return Body.ellipsoid(mass, size[:3])
        if kind in ("box", "hfield"):
            return Body.cuboid(mass, 2 * size[:3])
    return Body.from_inertia(mass, np.diag(_shell_inertia(mass, kind, size)))


def _shell_inertia(mass: float, kind: str, size: NDArray[np.float64]) -> list[float]:
    """MuJoCo's diagonal inertia of a thin shell (mjCGeom::SetInertia, mjINERTIA_SHELL)."""
    if kind == "capsule":
        r, half = float(size[0]), float(size[1])
        height = 2 * half
        a_sphere = 4 * math.pi * r * r
        a_cylinder = 2 * math.pi * r * height
        sphere = mass * a_sphere / (a_sphere + a_cylinder)
        cylinder = mass - sphere
        i = [cylinder * (6 * r * r + height * height) / 12] * 2 + [cylinder * r * r]
        s = 2 * sphere * r * r / 3
        hs_com = r / 2
        hs_pos = half + hs_com
        d = sphere * (hs_pos * hs_pos - hs_com * hs_com)
        return [i[0] + s + d, i[1] + s + d, i[2] + s]
    if kind == "cylinder":
        r, half = float(size[0]), float(size[1])
        height = 2 * half
        a_disk = math.pi * r * r
        a_cylinder = 2 * math.pi * r * height
        disk = mass * a_disk / (2 * a_disk + a_cylinder)
        cylinder = mass - 2 * disk
        i = [cylinder * (6 * r * r + height * height) / 12] * 2 + [cylinder * r * r]
        dx = disk * r * r / 4 + disk * half * half
        dz = disk * r * r / 2
        return [i[0] + 2 * dx, i[1] + 2 * dx, i[2] + 2 * dz]
    a, b, c = (float(x) for x in size[:3])
    s00, s11, s22 = a * a, b * b, c * c
    if kind == "ellipsoid":
        eps = 1e-6
        va = 4 * math.pi * a * b * c / 3
        ae, be, ce = a + eps, b + eps, c + eps
        vb = 4 * math.pi * ae * be * ce / 3
        density = mass / (vb - va)
        ma = va * density
        mb = vb * density
        ia = [ma * (s11 + s22) / 5, ma * (s00 + s22) / 5, ma * (s00 + s11) / 5]
        ib = [
            mb * (be * be + ce * ce) / 5,
            mb * (ae * ae + ce * ce) / 5,
            mb * (ae * ae + be * be) / 5,
        ]
        return [ib[k] - ia[k] for k in range(3)]
    # box
    lx, ly, lz = 2 * a, 2 * b, 2 * c
    a0, a1, a2 = lx * ly, ly * lz, lz * lx
    total = 2 * (a0 + a1 + a2)
    m0, m1, m2 = mass * a0 / total, mass * a1 / total, mass * a2 / total
    ix0, iy0, iz0 = m0 * ly * ly / 12, m0 * lx * lx / 12, m0 * (lx * lx + ly * ly) / 12
    ix1, iy1, iz1 = m1 * (ly * ly + lz * lz) / 12, m1 * lz * lz / 12, m1 * ly * ly / 12
    ix2, iy2, iz2 = m2 * lz * lz / 12, m2 * (lx * lx + lz * lz) / 12, m2 * lx * lx / 12
    return [
        2 * (m0 * s22 + m2 * s11 + ix0 + ix1 + ix2),
        2 * (m0 * s22 + m1 * s00 + iy0 + iy1 + iy2),
        2 * (m1 * s00 + m2 * s11 + iz0 + iz1 + iz2),
    ]
