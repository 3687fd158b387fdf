"""MJCF read as written (``read_mjcf(path, as_written=True)`` and the audit): the file parsed by
MuJoCo's ``MjSpec``, each body's declared ``<inertial>`` taken as it is, and the geoms of the
bodies without one computed by polhode at the densities or masses the file gives them, before
MuJoCo's compiler changes anything (``inertiafromgeom="true"``, bounds, ``settotalmass``,
legacy mesh inertia); also MuJoCo's parse of a file, with its errors as FileFormatErrors."""

from __future__ import annotations

import importlib
import math
import os
import re
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_scale
from polhode._files import existing, require
from polhode._meshes import mesh_arrays, mesh_body
from polhode.bodies import Body
from polhode.errors import FileFormatError, PolhodeError
from polhode.io._links import (
    Inertial,
    Link,
    Part,
    declared_body,
    geometry_body,
    placed,
    resolve,
    symmetric,
    unit_volume,
)
from polhode.io._mjcf_compile import body_names

__all__ = ["mjcf_links", "mjcf_spec", "read_as_written"]


def _quat_matrix(wxyz: Sequence[float]) -> NDArray[np.float64]:
    """Rotation matrix of a (w, x, y, z) quaternion (MuJoCo's order), normalised."""
    from scipy.spatial.transform import Rotation

    w, x, y, z = (float(c) for c in wxyz)
    return np.asarray(Rotation.from_quat([x, y, z, w]).as_matrix())


def _convex_hull(vertices: NDArray[np.float64]) -> NDArray[np.int64]:
    """Outward-wound triangles of the convex hull of ``vertices`` (scipy's Qhull)."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(vertices)
    faces = np.array(hull.simplices, dtype=np.int64)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    inward = np.einsum("ij,ij->i", normals, hull.equations[:, :3]) < 0
    faces[inward] = faces[inward][:, ::-1]
    return faces


def mjcf_spec(path: str) -> Any:
    """MuJoCo's MjSpec of a file, its parse errors as FileFormatError naming the body."""
    existing(path)
    mujoco = require("mujoco", "robots")
    try:
        return mujoco.MjSpec.from_file(path)
    except Exception as error:  # MuJoCo's parser raises ValueError with its message
        message = str(error).strip()
        element = re.search(r"Element '([^']*)'", message)
        line = re.search(r"line (\d+)", message)
        tag = element.group(1) if element else None
        body = _mjcf_body_at(path, int(line.group(1)), tag) if line else None
        where = f"body {body!r}: " if body else ""
        raise FileFormatError(
            f"{path}: {where}{message}",
            path=path,
            link=body,
            field=element.group(1) if element else None,
        ) from error


def _mjcf_body_at(path: str, line: int, tag: str | None) -> str | None:
    """The name of the innermost named <body> around (or at) the ``tag`` element that starts
    on ``line``, if it can be found."""
    import xml.etree.ElementTree as ET

    try:
        parser = ET.XMLPullParser(events=("start", "end"))
        with open(path, "rb") as handle:
            lines = handle.read().split(b"\n")
        stack: list[str | None] = []
        for number, chunk in enumerate(lines[:line], start=1):
            parser.feed(chunk + b"\n")
            for event, element in parser.read_events():
                if event == "start" and element.tag == "body":
                    stack.append(element.get("name"))
                if event == "start" and number == line and tag in (None, element.tag):
                    return next((n for n in reversed(stack) if n), None)
                if event == "end" and element.tag == "body":
                    stack.pop()
        return None
    except (ET.ParseError, OSError, IndexError):  # only decorates a message
        return None


def _mjcf_quat(spec: Any, quat: Any, alt: Any) -> NDArray[np.float64]:
    """An element's orientation as a (w, x, y, z) quaternion: ``quat`` or the alternative
    (euler, axisangle, xyaxes, zaxis), resolved by MuJoCo's own function with the file's
    angle unit and Euler sequence."""
    mujoco = importlib.import_module("mujoco")
    if alt.type == mujoco.mjtOrientation.mjORIENTATION_QUAT:
        return np.asarray(quat, dtype=float)
    return np.asarray(
        mujoco.MjSpec.resolve_orientation(spec.compiler.degree, spec.compiler.eulerseq, alt),
        dtype=float,
    )


def _mjcf_rotation(
    path: str, body: str, field: str, wxyz: NDArray[np.float64]
) -> NDArray[np.float64]:
    if not np.all(np.isfinite(wxyz)) or not np.any(wxyz):
        raise FileFormatError(
            f"{path}: body {body!r}: {field}: expected a non-zero finite quaternion, "
            f"got {wxyz.tolist()}.",
            path=path,
            link=body,
            field=field,
        )
    return _quat_matrix(wxyz)


def mjcf_links(path: str) -> tuple[list[Link], bool]:
    """Every body of an MJCF file (the world left out): its declared inertial, and its geoms
    at unit density with the density the file gives each (geoms of no mass left out); and
    whether MuJoCo infers inertials from geoms (the compiler's ``inertiafromgeom`` is not
    false)."""
    spec = mjcf_spec(path)
    mujoco = importlib.import_module("mujoco")
    folder = os.path.dirname(os.path.abspath(path))
    low, high = (int(x) for x in spec.compiler.inertiagrouprange)
    infer = spec.compiler.inertiafromgeom != mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    links = []
    # An unnamed body is "body K" (K its MuJoCo id), or "body K (unnamed)" if a body is named
    # so, as read_mjcf names it (the two shared a key, and one of them was lost without a word).
    bodies = list(spec.bodies)
    names: list[str | None] = [None, *body_names(spec)[1:]]  # the world's is None
    for index, body in enumerate(bodies):
        if index == 0:
            continue  # the world
        name = names[index]
        # How it hangs on its parent (for audit): moving with joints, else welded to it (the
        # world's children without joints too, with no parent link).
        up = next(i for i, b in enumerate(bodies[:index]) if b == body.parent)
        joint = "moving" if len(body.joints) else "fixed"
        try:
            turn = _quat_matrix(_mjcf_quat(spec, body.quat, body.alt))
            origin = (turn, np.asarray(body.pos, dtype=float))
        except ValueError:  # a zero quaternion: the reader says so where it matters
            origin = None
        inertial = None
        if body.explicitinertial:
            full = np.asarray(body.fullinertia, dtype=float)
            com = np.asarray(body.ipos, dtype=float)
            if not np.all(np.isfinite(com)):
                raise FileFormatError(
                    f"{path}: body {name!r}: inertial.pos: expected 3 finite numbers, got "
                    f"{com.tolist()}.",
                    path=path,
                    link=name,
                    field="inertial.pos",
                )
            diagonal = np.asarray(body.inertia, dtype=float)
            if not np.isnan(full[0]) and np.any(diagonal != 0):
                raise FileFormatError(
                    f"{path}: body {name!r}: inertial: both diaginertia {diagonal.tolist()} "
                    f"and fullinertia {full.tolist()} are given (MuJoCo refuses the model); "
                    "give one.",
                    path=path,
                    link=name,
                    field="inertial.diaginertia",
                )
            if np.isnan(full[0]):
                rotation = _mjcf_rotation(
                    path, name, "inertial.quat", _mjcf_quat(spec, body.iquat, body.ialt)
                )
                # An infinite moment gives NaN entries (inf * 0): refused or reported later.
                with np.errstate(invalid="ignore", over="ignore"):
                    tensor = rotation @ np.diag(np.asarray(body.inertia, dtype=float)) @ rotation.T
                inertial = Inertial(
                    float(body.mass), com, symmetric(tensor), "inertial.diaginertia"
                )
            else:
                xx, yy, zz, xy, xz, yz = full
                tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
                inertial = Inertial(float(body.mass), com, tensor, "inertial.fullinertia")
        parts = []
        for k, geom in enumerate(body.geoms):
            label = f"geom {geom.name!r}" if geom.name else f"geom[{k}]"
            if not low <= geom.group <= high:
                continue
            try:
                part, density = _mjcf_geom(spec, mujoco, path, folder, name, label, geom)
            except (FileFormatError, FileNotFoundError) as error:
                parts.append(Part(label, None, error))
                continue
            if part is not None:
                parts.append(Part(label, part, None, density))
        links.append(Link(name, inertial, parts, joint, names[up], origin))
    return links, infer


def _mjcf_geom(
    spec: Any, mujoco: Any, path: str, folder: str, body: str, label: str, geom: Any
) -> tuple[Body | None, float]:
    """A geom as a unit-density body in its body's frame, and the density the file gives it
    (its ``density``, or its ``mass`` over its volume); None for a geom of no mass."""
    t = mujoco.mjtGeom
    kind = geom.type
    size = np.asarray(geom.size, dtype=float).copy()
    fromto = np.asarray(geom.fromto, dtype=float)
    field = f"{label}"

    def fail(message: str, what: str = "") -> FileFormatError:
        f = f"{field}.{what}" if what else field
        return FileFormatError(
            f"{path}: body {body!r}: {f}: {message}", path=path, link=body, field=f
        )

    if kind in (t.mjGEOM_PLANE, t.mjGEOM_HFIELD, t.mjGEOM_SDF):
        raise fail(f"a {str(kind).split('_')[-1].lower()} geom has no volume polhode computes.")
    if geom.meshname and kind != t.mjGEOM_MESH:
        raise fail(
            "a primitive fitted to a mesh (a mesh attribute on a non-mesh geom) is not supported.",
            "mesh",
        )
    if not np.isnan(fromto[0]):
        if kind not in (t.mjGEOM_CAPSULE, t.mjGEOM_CYLINDER, t.mjGEOM_ELLIPSOID, t.mjGEOM_BOX):
            raise fail("fromto applies to capsules, cylinders, ellipsoids and boxes.", "fromto")
        axis = fromto[:3] - fromto[3:]
        half = float(np.linalg.norm(axis)) / 2
        if not half > 0:
            raise fail("the two fromto points coincide.", "fromto")
        if kind in (t.mjGEOM_ELLIPSOID, t.mjGEOM_BOX):  # as MuJoCo's compiler does
            size[1], size[2] = size[0], half
        else:
            size[1] = half
        quat = np.zeros(4)
        mujoco.mju_quatZ2Vec(quat, axis / (2 * half))
        position = (fromto[:3] + fromto[3:]) / 2
    else:
        quat = _mjcf_quat(spec, geom.quat, geom.alt)
        position = np.asarray(geom.pos, dtype=float)
    rotation = _mjcf_rotation(path, body, f"{field}.quat", quat)
    # Frames around the geom, innermost first.
    frame = geom.frame
    while frame is not None:
        if np.any(np.asarray(frame.scale, dtype=float) != 1.0):
            raise fail(f"a scaling <frame> ({frame.name or 'unnamed'}) is not supported.")
        r = _mjcf_rotation(path, body, "frame.quat", _mjcf_quat(spec, frame.quat, frame.alt))
        position = r @ position + np.asarray(frame.pos, dtype=float)
        rotation = r @ rotation
        frame = frame.frame
    shell = geom.typeinertia == mujoco.mjtGeomInertia.mjINERTIA_SHELL
    try:
        if kind == t.mjGEOM_MESH:
            unit = _mjcf_mesh(spec, mujoco, path, folder, body, field, geom)
        elif kind == t.mjGEOM_SPHERE:
            r = size[0]
            unit = (
                Body.spherical_shell(unit_volume("sphere", r, lambda r: 4 * math.pi * r * r), r)
                if shell
                else Body.sphere(unit_volume("sphere", r, lambda r: 4 / 3 * math.pi * r**3), r)
            )
        elif shell:
            raise fail("shell inertia is supported for spheres and meshes only.", "shellinertia")
        elif kind == t.mjGEOM_CAPSULE:
            r, h = size[0], 2 * size[1]
            v = unit_volume("capsule", (r, h), lambda r, h: math.pi * (r * r * h + 4 / 3 * r**3))
            unit = Body.capsule(v, r, h)
        elif kind == t.mjGEOM_CYLINDER:
            r, h = size[0], 2 * size[1]
            v = unit_volume("cylinder", (r, h), lambda r, h: math.pi * r * r * h)
            unit = Body.cylinder(v, r, h)
        elif kind == t.mjGEOM_ELLIPSOID:
            v = unit_volume("ellipsoid", size, lambda a, b, c: 4 / 3 * math.pi * (a * b * c))
            unit = Body.ellipsoid(v, size)
        elif kind == t.mjGEOM_BOX:
            unit = Body.cuboid(unit_volume("box", size, lambda a, b, c: 8 * (a * b * c)), 2 * size)
        else:
            raise fail(f"geoms of type {kind} have no volume polhode computes.")
    except FileFormatError:
        raise
    except PolhodeError as error:
        raise fail(error.message, "size") from error
    if not np.isnan(geom.mass):
        if geom.mass == 0:
            return None, 0.0
        if not geom.mass > 0:
            raise fail(f"expected a mass >= 0, got {geom.mass:g}.", "mass")
        density = float(geom.mass) / unit.mass
    else:
        if geom.density == 0:
            return None, 0.0
        if not geom.density > 0:
            raise fail(f"expected a density >= 0, got {geom.density:g}.", "density")
        density = float(geom.density)
    if not np.all(np.isfinite(position)):
        # The geom's pos, or a frame's around it (the error named `offset`, an internal
        # argument, without the file or the body).
        raise fail(f"expected a finite position, got {np.asarray(position).tolist()}.", "pos")
    try:
        return placed(unit, rotation, position), density
    except PolhodeError as error:
        raise fail(error.message, "pos") from error


def _mjcf_mesh(
    spec: Any, mujoco: Any, path: str, folder: str, body: str, field: str, geom: Any
) -> Body:
    """A mesh geom's mesh as a unit-density body in the geom's frame (MuJoCo's mesh: the file
    or the inline vertices, moved by refpos/refquat, then scaled; the convex hull for
    inertia="convex" or vertices without faces; a shell for inertia="shell")."""
    mesh = spec.mesh(geom.meshname)
    if mesh is None:
        raise FileFormatError(
            f"{path}: body {body!r}: {field}.mesh: no mesh asset named {geom.meshname!r}.",
            path=path,
            link=body,
            field=f"{field}.mesh",
        )
    scale = as_scale(np.asarray(mesh.scale, dtype=float), "mesh.scale")
    label = f"mesh {mesh.name!r}"
    if mesh.file:
        name = os.path.basename(mesh.file) if spec.strippath else mesh.file
        meshdir = spec.meshdir or ""
        filename = os.path.join(folder, meshdir, name)
        if not os.path.isfile(filename):
            raise FileFormatError(
                f"{path}: body {body!r}: {field}: the mesh file {mesh.file!r} is not found "
                f"(looked for {filename!r}).",
                path=path,
                link=body,
                field=f"{field}.mesh.file",
            )
        vertices, faces = mesh_arrays(filename, np.ones(3))
        source = filename
    elif len(mesh.uservert):
        vertices = np.asarray(mesh.uservert, dtype=float).reshape(-1, 3)
        faces = np.asarray(mesh.userface, dtype=np.int64).reshape(-1, 3)
        source = path
    else:
        raise FileFormatError(
            f"{path}: body {body!r}: {field}: {label} has neither a file nor vertices "
            "(built-in and plugin meshes are not supported).",
            path=path,
            link=body,
            field=f"{field}.mesh",
        )
    # As MuJoCo's compiler: refpos subtracted, turned back by refquat, then scaled.
    refpos = np.asarray(mesh.refpos, dtype=float)
    refquat = np.asarray(mesh.refquat, dtype=float)
    if np.any(refpos):
        vertices = vertices - refpos
    if not np.array_equal(refquat, [1.0, 0.0, 0.0, 0.0]):
        vertices = vertices @ _quat_matrix(refquat)
    vertices = vertices * scale
    if np.prod(scale) < 0 and len(faces):
        faces = np.ascontiguousarray(faces[:, ::-1])
    kind = mesh.inertia
    shell = kind == mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
    if len(faces) == 0 or kind == mujoco.mjtMeshInertia.mjMESH_INERTIA_CONVEX:
        try:
            faces = _convex_hull(vertices)
        except Exception as error:  # Qhull: flat or too few points
            raise FileFormatError(
                f"{path}: body {body!r}: {field}: {label}: no convex hull: {error}",
                path=path,
                link=body,
                field=f"{field}.mesh",
            ) from error
    return mesh_body(
        Body, source, label, vertices, faces, 1.0, shell, False, link=body, field=field
    )


def read_as_written(path: str, density: float | None, mass: float | None) -> dict[str, Body]:
    """The bodies as written (see the module), by name in the file's order; bodies of no mass
    left out. ``density`` or a total ``mass`` replace the file's densities for the bodies
    without an inertial."""
    links, infer = mjcf_links(path)
    if density is not None or mass is not None:
        return resolve(path, "body", links, density, mass)
    # MuJoCo's semantics: a body without an inertial has its geoms' at their own densities.
    out: dict[str, Body] = {}
    for link in links:
        if link.inertial is not None:
            out[link.name] = declared_body(path, "body", link)
        elif infer:
            body = geometry_body(link, file_density=True)
            if body is not None:
                out[link.name] = body
    return out
