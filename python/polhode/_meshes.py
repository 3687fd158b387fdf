"""Mesh files: the triangle meshes of STL, OBJ, PLY, OFF and glTF/GLB files as bodies.

trimesh's loaders read the file and polhode's exact mesh integrals (:meth:`polhode.Body.mesh`)
give the mass properties. This is the low level of :meth:`polhode.Body.from_file` and of
:mod:`polhode.io` (:func:`polhode.io.read_mesh`, the meshes of robot descriptions); the body
type is passed in, since :mod:`polhode.bodies` imports this module.
"""

from __future__ import annotations

import math
import os
import re
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core
from polhode._coerce import as_flag, as_scale, density_or_mass
from polhode._files import existing, fspath, keeping_interrupts, require
from polhode.errors import ArgumentError, FileFormatError, PolhodeError

__all__ = [
    "MESH_FORMATS",
    "merge_vertices",
    "mesh_arrays",
    "mesh_body",
    "mesh_parts",
    "read_bodies",
]

#: The mesh formats :func:`polhode.io.read_mesh` reads (by the file's extension), all through
#: trimesh.
MESH_FORMATS = ("stl", "obj", "ply", "off", "gltf", "glb")


def merge_vertices(
    vertices: NDArray[np.float64], faces: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices at exactly the same position merged into one, the first kept (STL repeats every
    vertex per triangle; OBJ and glTF split vertices along texture seams), and the triangles
    that then repeat a vertex (zero area) dropped. The core's hash table (O(vertices), Ctrl-C
    stops it on a large mesh); vertices that differ by exporters' noise are merged later, for
    the closedness check only (:meth:`polhode.Body.mesh`)."""
    if len(vertices) == 0:
        return vertices, faces
    return _core.merge_vertices(
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(faces, dtype=np.int64),
    )


def mesh_parts(
    path: str, scale: NDArray[np.float64]
) -> list[tuple[str, NDArray[np.float64], NDArray[np.int64]]]:
    """(name, vertices, faces) of every triangle mesh in the file: placed by the file's scene
    graph (glTF nodes), scaled, duplicate vertices merged."""
    existing(path)
    extension = os.path.splitext(path)[1].lower().lstrip(".")
    if extension not in MESH_FORMATS:
        got = "." + extension if extension else "no extension"
        known = ", ".join("." + e for e in MESH_FORMATS)
        raise FileFormatError(
            f"{path}: expected a mesh file ending in {known}, got {got}.", path=path
        )
    trimesh = require("trimesh", "mesh")
    options: dict[str, Any] = {"process": False}
    if extension == "obj":  # one part per object ('o'), as glTF has one per node
        options.update(split_objects=True, group_material=False)
    try:
        with keeping_interrupts("trimesh"):  # its loaders swallow BaseException here and there
            scene = trimesh.load_scene(path, file_type=extension, **options)
    except Exception as error:  # the loaders raise whatever their parsers do
        raise FileFormatError(
            f"{path}: cannot be read as a {extension.upper()} mesh: "
            f"{type(error).__name__}: {error}",
            path=path,
        ) from error
    parts = []
    for node in scene.graph.nodes_geometry:
        transform, geometry_name = scene.graph[node]
        mesh = scene.geometry.get(geometry_name)
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
            continue  # point clouds, paths
        vertices, faces = merge_vertices(
            np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)
        )
        matrix = np.asarray(transform, dtype=float)
        linear = matrix[:3, :3] * scale[:, None]  # the scene's transform, then the scale
        vertices = vertices @ linear.T + matrix[:3, 3] * scale
        # A mirror turns the winding inside out (the sign alone: det overflows at scale 1e103).
        if np.linalg.slogdet(linear)[0] < 0:
            faces = np.ascontiguousarray(faces[:, ::-1])
        parts.append((str(node), vertices, faces))
    if not parts:
        raise FileFormatError(f"{path}: holds no triangle mesh.", path=path)
    return parts


def mesh_arrays(
    path: str, scale: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """All the triangles of a mesh file as one mesh (a robot description's mesh is one)."""
    parts = mesh_parts(path, scale)
    if len(parts) == 1:
        return parts[0][1], parts[0][2]
    offsets = np.cumsum([0] + [len(v) for _, v, _ in parts[:-1]])
    vertices = np.concatenate([v for _, v, _ in parts])
    faces = np.concatenate([f + o for (_, _, f), o in zip(parts, offsets, strict=True)])
    return vertices, faces


def mesh_body(
    body_type: Any,
    path: str,
    name: str,
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    density: float,
    shell: bool,
    fix_winding: bool,
    link: str | None = None,
    field: str | None = None,
) -> Any:
    """``body_type.mesh`` (:meth:`polhode.Body.mesh`) with the error re-raised as a
    FileFormatError naming the file and part."""
    try:
        return body_type.mesh(
            vertices, faces, density=density, shell=shell, fix_winding=fix_winding
        )
    except PolhodeError as error:
        where = f"link {link!r}: " if link is not None else ""
        raise FileFormatError(
            f"{path}: {where}mesh {name!r}: {error.message}",
            path=path,
            link=link if link is not None else name,
            field=field if field is not None else error.argument,
        ) from error


def read_bodies(
    body_type: Any,
    path: Any,
    *,
    density: Any,
    mass: Any,
    shell: Any,
    scale: Any,
    fix_winding: Any,
) -> dict[str, Any]:
    """What :func:`polhode.io.read_mesh` returns (and :meth:`polhode.Body.from_file` sums): the
    meshes of a file as bodies of ``body_type`` (:class:`polhode.Body`), by name; the
    arguments are checked here."""
    path = fspath(path)
    rho, total = density_or_mass(density, mass, required=True)
    as_flag("shell", shell)
    as_flag("fix_winding", fix_winding)
    factor = as_scale(scale)
    parts = mesh_parts(path, factor)
    try:
        return _bodies(body_type, path, parts, rho, total, shell, fix_winding)
    except PolhodeError as error:
        if np.all(factor == 1.0) or not _fits_unscaled(
            body_type, path, parts, factor, rho, total, shell, fix_winding
        ):
            raise
        # The file's own mesh is within double precision (and whole), this scale's is not: the
        # scale is at fault (it used to be a FileFormatError naming the file).
        raise ArgumentError(
            f"Invalid `scale` {factor.tolist()}: {error.message}", argument="scale"
        ) from error


def _fits_unscaled(
    body_type: Any,
    path: str,
    parts: list[tuple[str, NDArray[np.float64], NDArray[np.int64]]],
    factor: NDArray[np.float64],
    rho: float | None,
    total: float | None,
    shell: bool,
    fix_winding: bool,
) -> bool:
    """Whether the file's meshes at scale 1 (the scaled vertices divided by the scale, to
    rounding) make bodies: where they do, what failed is the scale's."""
    with np.errstate(over="ignore", invalid="ignore"):
        unscaled = [(name, v / factor, f) for name, v, f in parts]
    if not all(np.all(np.isfinite(v)) for _, v, _ in unscaled):
        return False
    try:
        _bodies(body_type, path, unscaled, rho, total, shell, fix_winding)
    except PolhodeError:
        return False
    return True


def _bodies(
    body_type: Any,
    path: str,
    parts: list[tuple[str, NDArray[np.float64], NDArray[np.int64]]],
    rho: float | None,
    total: float | None,
    shell: bool,
    fix_winding: bool,
) -> dict[str, Any]:
    """The bodies of the meshes ``parts`` at density ``rho``, or sharing the mass ``total``."""
    if total is None:
        assert rho is not None
        return {
            name: mesh_body(body_type, path, name, v, f, rho, shell, fix_winding)
            for name, v, f in parts
        }
    # The total mass shared by volume (area): each part at unit density in units of 2^k, the
    # power of two of the largest coordinate (exactly), then its mass scaled to its share and
    # its lengths by 2^k. At unit density in the file's units the volumes of a mesh scaled by
    # 1e-100 underflowed (I = 0 for a cube of mass 1), and those scaled by 1e62 overflowed.
    largest = max(float(np.max(np.abs(v))) for _, v, _ in parts)
    k = math.frexp(largest)[1] - 1 if largest > 0 else 0
    unit = {
        name: mesh_body(body_type, path, name, np.ldexp(v, -k), f, 1.0, shell, fix_winding)
        for name, v, f in parts
    }
    measure = math.fsum(b.mass for b in unit.values())
    bodies = {}
    for name, b in unit.items():
        try:
            bodies[name] = b.scaled(mass_scale=total / measure, length_scale=math.ldexp(1.0, k))
        except PolhodeError as error:
            # The core names its own arguments (mass_scale, length_scale): what is out of
            # range is this part at this mass and scale.
            reason = re.sub(r"^Invalid `[^`]*`: ", "", error.message)
            raise FileFormatError(
                f"{path}: mesh {name!r}: with mass = {total:g} and this scale, {reason}",
                path=path,
                link=name,
                field="scale",
            ) from error
    return bodies
