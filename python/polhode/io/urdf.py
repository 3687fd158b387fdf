"""URDF: the links of a robot description, read whole (a link a simulator would refuse is left
out and named), each field checked on the XML so that a bad one is named with its link."""

from __future__ import annotations

import logging
import math
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_flag, as_scale, density_or_mass
from polhode._files import existing, fspath, require
from polhode._meshes import mesh_arrays, mesh_body
from polhode.bodies import Body
from polhode.errors import ArgumentError, FileFormatError, PolhodeError
from polhode.io._links import Inertial, Link, Part, placed, symmetric, unit_volume, xml_root
from polhode.io._robot import Links, assemble

__all__ = ["read_urdf", "rpy_matrix", "urdf_links"]

_SPACE = re.compile(r"\s+")

#: URDF's joint types that do not move (every other type moves: revolute, continuous,
#: prismatic, floating, planar).
_FIXED = ("fixed",)


class _Bad(Exception):
    """A field that cannot be read: ``field`` and what is wrong."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field
        self.message = message


def _numbers(text: str | None, count: Sequence[int]) -> list[float] | None:
    """``count`` finite numbers, whitespace separated, from an attribute, or None."""
    if text is None:
        return None
    words = [w for w in _SPACE.split(text.strip()) if w]
    if len(words) not in count:
        return None
    try:
        values = [float(w) for w in words]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


def _attr(
    element: Any, attr: str, field: str, count: Sequence[int] = (1,), default: str | None = None
) -> list[float]:
    text = element.get(attr, default)
    if text is None:
        raise _Bad(field, f"the attribute {attr!r} is missing.")
    values = _numbers(text, count)
    if values is None:
        n = " or ".join(str(c) for c in count)
        plural = "s" if count != (1,) else ""
        raise _Bad(field, f"expected {n} finite number{plural}, got {text!r}.")
    return values


def rpy_matrix(roll: float, pitch: float, yaw: float) -> NDArray[np.float64]:
    """URDF's ``rpy``: R = Rz(yaw) Ry(pitch) Rx(roll) (fixed axes x, y, z), with the products
    in the order of yourdfpy's (trimesh's ``euler_matrix(r, p, y, "sxyz")``), so that both
    readers give the same bits."""
    si, sj, sk = np.sin(roll), np.sin(pitch), np.sin(yaw)
    ci, cj, ck = np.cos(roll), np.cos(pitch), np.cos(yaw)
    cc, cs = ci * ck, ci * sk
    sc, ss = si * ck, si * sk
    return np.array(
        [
            [cj * ck, sj * sc - cs, sj * cc + ss],
            [cj * sk, sj * ss + cc, sj * cs - sc],
            [-sj, cj * si, cj * ci],
        ],
        dtype=float,
    )


def _origin(element: Any, prefix: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The (rotation, offset) of an element's ``<origin xyz rpy>`` (identity without one)."""
    origin = element.find("origin")
    if origin is None:
        return np.eye(3), np.zeros(3)
    xyz = _attr(origin, "xyz", f"{prefix}.origin.xyz", (3,), "0 0 0")
    rpy = _attr(origin, "rpy", f"{prefix}.origin.rpy", (3,), "0 0 0")
    return rpy_matrix(*rpy), np.array(xyz, dtype=float)


def _inertial(link: Any) -> Inertial | None:
    """A link's declared inertial (tensor turned into the link's axes), or _Bad naming the
    field; None without an ``<inertial>``."""
    elements = link.findall("inertial")
    if not elements:
        return None
    if len(elements) > 1:
        lines = ", ".join(str(e.sourceline) for e in elements)
        raise _Bad(
            "inertial",
            f"{len(elements)} <inertial> elements (lines {lines}); URDF allows one, and "
            "readers differ on which they take.",
        )
    inertial = elements[0]
    rotation, com = _origin(inertial, "inertial")
    masses = inertial.findall("mass")
    if not masses:
        raise _Bad("inertial.mass", "the <inertial> has no <mass>.")
    if len(masses) > 1:
        raise _Bad("inertial.mass", f"the <inertial> has {len(masses)} <mass> elements.")
    (m,) = _attr(masses[0], "value", "inertial.mass")
    tensors = inertial.findall("inertia")
    if not tensors:
        raise _Bad("inertial.inertia", "the <inertial> has no <inertia>.")
    if len(tensors) > 1:
        raise _Bad("inertial.inertia", f"the <inertial> has {len(tensors)} <inertia> elements.")
    v = {
        key: _attr(tensors[0], key, f"inertial.inertia.{key}")[0]
        for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    }
    tensor = np.array(
        [
            [v["ixx"], v["ixy"], v["ixz"]],
            [v["ixy"], v["iyy"], v["iyz"]],
            [v["ixz"], v["iyz"], v["izz"]],
        ]
    )
    with np.errstate(over="ignore", invalid="ignore"):
        turned = rotation @ tensor @ rotation.T
    return Inertial(m, com, symmetric(turned), "inertial.inertia")


@dataclass(frozen=True)
class _Shape:
    """A ``<collision>`` or ``<visual>`` element, read later if its geometry is needed."""

    label: str  # "collision[0]"
    element: Any


def _check_shape(shape: _Shape) -> None:
    """The fields of a geometry element, or _Bad naming the first that cannot be read."""
    _origin(shape.element, shape.label)
    geometry = shape.element.find("geometry")
    if geometry is None or len(geometry) == 0:
        raise _Bad(f"{shape.label}.geometry", "no geometry given.")
    g = geometry[0]
    field = f"{shape.label}.geometry.{g.tag}"
    if g.tag == "box":
        _attr(g, "size", f"{field}.size", (3,))
    elif g.tag == "cylinder":
        _attr(g, "radius", f"{field}.radius")
        _attr(g, "length", f"{field}.length")
    elif g.tag == "sphere":
        _attr(g, "radius", f"{field}.radius")
    elif g.tag == "mesh":
        if not g.get("filename"):
            raise _Bad(f"{field}.filename", "no filename given.")
        if g.get("scale") is not None:
            _attr(g, "scale", f"{field}.scale", (1, 3))


@dataclass
class _Robot:
    """A URDF file read: its links, and what the file says wrong about itself as a whole."""

    links: list[Link]
    notes: list[tuple[str, str]]


def _joints(path: str, root: Any, names: set[str], origins: bool) -> dict[str, Any]:
    """``{child: (joint name, type, parent, (R, p) or None)}``; a file whose joints do not make
    a tree of its links is refused, naming the joint."""

    def fail(joint: str | None, field: str, message: str) -> FileFormatError:
        where = f"joint {joint!r}: " if joint else ""
        return FileFormatError(f"{path}: {where}{field}: {message}", path=path, field=field)

    out: dict[str, Any] = {}
    for element in root.findall("joint"):
        name = element.get("name")
        if not name:
            raise fail(None, "joint.name", f"a <joint> on line {element.sourceline} has no name.")
        ends = {}
        for end in ("parent", "child"):
            tag = element.find(end)
            link = tag.get("link") if tag is not None else None
            if not link:
                raise fail(name, f"{end}.link", f"the <joint> has no <{end} link=...>.")
            if link not in names:
                raise fail(name, f"{end}.link", f"no <link> is named {link!r}.")
            ends[end] = link
        child = ends["child"]
        if child in out:
            raise fail(
                name, "child.link", f"the link {child!r} is already the child of {out[child][0]!r}."
            )
        kind = element.get("type") or ""
        origin = None
        if origins:
            try:
                origin = _origin(element, "joint")
            except _Bad as bad:
                raise fail(name, bad.field, bad.message) from None
        out[child] = (name, kind, ends["parent"], origin)
    # No cycles: from every link, the chain of parents ends.
    for start in out:
        seen = {start}
        current = start
        while current in out:
            current = out[current][2]
            if current in seen:
                cycle = f"the joints form a cycle through {start!r}."
                raise fail(out[start][0], "parent.link", cycle)
            seen.add(current)
    return out


def _read(path: str, geometry: str, shapes_of: str, strict: bool, origins: bool) -> _Robot:
    existing(path)
    require("yourdfpy", "robots")  # its rules resolve mesh file names; lxml comes with it
    root = xml_root(path)
    if root.tag != "robot":
        raise FileFormatError(
            f"{path}: robot: expected a <robot> element, got <{root.tag}>.",
            path=path,
            field="robot",
        )
    notes = []
    if not root.get("name"):
        remark = "the <robot> has no name (URDF requires one); read all the same."
        notes.append(("robot.name", remark))
    elements: list[tuple[str, Any]] = []
    names: set[str] = set()
    for element in root.findall("link"):
        name = element.get("name")
        if not name:
            raise FileFormatError(
                f"{path}: link.name: a <link> on line {element.sourceline} has no name.",
                path=path,
                field="link.name",
            )
        if name in names:
            raise FileFormatError(
                f"{path}: link {name!r}: link.name: two links have this name (line "
                f"{element.sourceline}).",
                path=path,
                link=name,
                field="link.name",
            )
        names.add(name)
        elements.append((name, element))
    joints = _joints(path, root, names, origins)
    folder = os.path.dirname(os.path.abspath(path))
    links = []
    for name, element in elements:
        inertial, problem = None, None
        try:
            inertial = _inertial(element)
        except _Bad as bad:
            problem = (bad.field, bad.message)
        shapes = {tag: element.findall(tag) for tag in ("collision", "visual")}
        every = [_Shape(f"{t}[{k}]", e) for t in shapes for k, e in enumerate(shapes[t])]
        if strict and problem is None:  # every field must be readable, used or not
            for shape in every:
                try:
                    _check_shape(shape)
                except _Bad as bad:
                    problem = (bad.field, bad.message)
                    break
        tag = geometry
        chosen = shapes[tag]
        if geometry == "collision" and not chosen:
            tag, chosen = "visual", shapes["visual"]
        wanted = shapes_of == "all" or (shapes_of == "without" and inertial is None)
        parts = []
        if wanted and problem is None:
            for k, shape in enumerate(chosen):
                label = f"{tag}[{k}]"
                try:
                    body = _shape_body(path, name, _Shape(label, shape), folder)
                    parts.append(Part(label, body, None))
                except (FileFormatError, FileNotFoundError) as error:
                    parts.append(Part(label, None, error))
        if name in joints:
            joint_name, kind, parent, origin = joints[name]
            motion = "fixed" if kind in _FIXED else "moving"
        else:
            parent, origin, motion = None, None, "root"
        links.append(Link(name, inertial, parts, motion, parent, origin, problem))
    return _Robot(links, notes)


def urdf_links(
    path: str, geometry: str, shapes_of: str, *, strict: bool = False, origins: bool = False
) -> list[Link]:
    """Every link of a URDF file: its declared inertial (or the problem that keeps it from
    being read), its geometry at unit density for ``shapes_of`` = "all" links, the links
    "without" an inertial, or "none", and its joint (with the joint's origin if ``origins``)."""
    return _read(path, geometry, shapes_of, strict, origins).links


def _shape_body(path: str, link: str, shape: _Shape, folder: str) -> Body | None:
    """A URDF <collision>/<visual> geometry as a unit-density body in the link frame."""
    field = f"{shape.label}.geometry"

    def fail(message: str, where: str = field) -> FileFormatError:
        return FileFormatError(
            f"{path}: link {link!r}: {where}: {message}", path=path, link=link, field=where
        )

    try:
        _check_shape(shape)
    except _Bad as bad:
        raise fail(bad.message, bad.field) from None
    rotation, offset = _origin(shape.element, shape.label)
    g = shape.element.find("geometry")[0]
    try:
        if g.tag == "box":
            size = np.asarray(_attr(g, "size", "", (3,)), dtype=float)
            if np.any(size == 0):
                return None  # a placeholder of no volume (a frame drawn as an empty box)
            body = Body.cuboid(unit_volume("box", size, lambda a, b, c: a * b * c), size)
        elif g.tag == "cylinder":
            r, length = _attr(g, "radius", "")[0], _attr(g, "length", "")[0]
            if r == 0 or length == 0:
                return None
            v = unit_volume("cylinder", (r, length), lambda r, h: math.pi * r * r * h)
            body = Body.cylinder(v, r, length)
        elif g.tag == "sphere":
            (r,) = _attr(g, "radius", "")
            if r == 0:
                return None
            body = Body.sphere(unit_volume("sphere", r, lambda r: 4.0 / 3.0 * math.pi * r**3), r)
        elif g.tag == "mesh":
            from yourdfpy.urdf import filename_handler_magic

            name = g.get("filename")
            # yourdfpy logs a warning for a name it cannot resolve: the error below says it.
            logger = logging.getLogger("yourdfpy.urdf")
            disabled, logger.disabled = logger.disabled, True
            try:
                filename = filename_handler_magic(name, dir=folder)
            finally:
                logger.disabled = disabled
            if not os.path.isfile(filename):
                raise fail(
                    f"the mesh {name!r} is not found (looked for {filename!r}).",
                    f"{field}.mesh.filename",
                )
            scale = g.get("scale")
            factor = as_scale(1.0 if scale is None else _attr(g, "scale", "", (1, 3)))
            vertices, faces = mesh_arrays(filename, factor)
            body = mesh_body(
                Body,
                filename,
                os.path.basename(filename),
                vertices,
                faces,
                1.0,
                False,
                False,
                link=link,
                field=f"{field}.mesh",
            )
        else:
            return None
    except FileFormatError:
        raise
    except PolhodeError as error:
        raise fail(error.message) from error
    return placed(body, rotation, offset)


def read_urdf(
    path: str | os.PathLike[str],
    *,
    density: float | None = None,
    mass: float | None = None,
    geometry: str = "collision",
    merge_fixed: bool = False,
    strict: bool = False,
) -> Links:
    """The links of a URDF file as bodies, each in its link's frame; or, with
    ``merge_fixed=True``, one body per moving part.

    A link's body comes from its ``<inertial>``: the ``<origin xyz rpy>`` places the centre of
    mass and turns the ``<inertia>`` (ixx ... izz: tensor elements, I_xy = -sum m x y, about
    the centre of mass in the axes of the origin's frame) into the link's axes. A mass with an
    all-zero ``<inertia>`` is a point mass.

    The file is read whole, as simulators read it:

    - a link without an ``<inertial>`` (or of mass 0) is massless in URDF: on a fixed joint, as
      the root, or on a moving joint whose fixed links carry mass, it is a frame
      (``result.frames``); with ``density`` or ``mass`` it gets the mass properties of its
      geometry instead (boxes, cylinders, spheres and meshes). Declared inertials are never
      replaced;
    - a link no simulator accepts is left out of the result and named, with the field and the
      check it fails, in ``result.left_out`` and in one
      :class:`polhode.errors.RobotFileWarning` for the file: a tensor that is not positive
      semidefinite or breaks the triangle inequality I1 + I2 >= I3, a negative mass, a moving
      link without mass (none on the links fixed to it either), an inertial that cannot be
      read (no ``<mass>`` or ``<inertia>``, two ``<inertial>`` elements, a number that is not
      one). ``strict=True`` raises the first instead;
    - a file that is not a robot description at all is refused: not XML, no ``<robot>``, two
      links of one name, joints naming links that do not exist or not making a tree.

    With ``merge_fixed=True`` each link on a fixed joint is fused into its parent, along chains
    of fixed joints, as MuJoCo's ``fusestatic`` and Pinocchio do: its body is placed by the
    composed joint origins and added (masses, centres of mass and tensors with their
    parallel-axis terms). The result has one body per moving part, named after its first link
    (the one on the moving joint; the root's part is the root's, kept though MuJoCo fixes it to
    the world and drops its mass), in that link's frame; ``result.merged`` says which links went
    where. Links without an inertial stay massless, as URDF and Pinocchio read them (MuJoCo gives
    them their collision geometry's mass at 1000 kg/m^3: ``density=1000.0`` does that).

    Parameters
    ----------
    path : str or os.PathLike
        The URDF file (mesh file names are resolved as yourdfpy does: ``package://`` and
        relative names are looked for next to the file and in the folders above it).
    density : float, optional
        Density of the geometry of the links without an inertial.
    mass : float, optional
        Total mass of the links without an inertial, shared in proportion to the volumes of
        their geometry (one uniform density).
    geometry : {"collision", "visual"}
        Which geometry gives the links without an inertial their mass properties; with
        ``"collision"``, a link with no ``<collision>`` uses its ``<visual>``.
    merge_fixed : bool
        One body per moving part (see above).
    strict : bool
        Raise on the first link that would be left out (and on a ``<robot>`` without a name, or
        a geometry element that cannot be read) instead of warning.

    Returns
    -------
    polhode.io.Links
        ``{link: Body}`` in the file's order (a dict), with ``frames``, ``left_out`` and
        ``merged``.

    Raises
    ------
    FileNotFoundError
        No such file.
    polhode.errors.FileFormatError
        Not a robot description; with ``strict``, the first link that would be left out
        (``link`` and ``field`` name it: with ``density`` or ``mass``, a link whose geometry
        cannot be computed is one).

    Warns
    -----
    polhode.errors.RobotFileWarning
        Once per file, naming every link left out and why (``warning.links``).

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> urdf = '''<robot name="r">
    ...   <link name="base"><collision><geometry><box size="0.2 0.1 0.1"/></geometry>
    ...   </collision></link>
    ...   <link name="tool"><inertial><origin xyz="0 0 0.05" rpy="0 0 1.5707963267948966"/>
    ...     <mass value="0.5"/><inertia ixx="2e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/>
    ...   </inertial></link>
    ...   <joint name="mount" type="fixed"><parent link="base"/><child link="tool"/>
    ...     <origin xyz="0.1 0 0"/></joint>
    ... </robot>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(urdf)
    >>> links = ph.io.read_urdf(path)
    >>> list(links), links.frames  # base has no inertial: the root, a frame
    (['tool'], {'base': 'no <inertial>: the root'})
    >>> bodies = ph.io.read_urdf(path, density=1000.0)
    >>> round(bodies["base"].mass, 12), bool(bodies["tool"].inertia[1, 1] > 1.9e-4)
    (2.0, True)
    >>> parts = ph.io.read_urdf(path, density=1000.0, merge_fixed=True)  # one rigid part
    >>> list(parts), parts.merged, round(parts["base"].mass, 12)
    (['base'], {'tool': 'base'}, 2.5)
    >>> parts["base"].center_of_mass.round(6).tolist()  # (2 x 0 + 0.5 x 0.1) / 2.5 in x
    [0.02, 0.0, 0.01]
    """
    path = fspath(path)
    rho, total = density_or_mass(density, mass, required=False)
    if geometry not in ("collision", "visual"):
        raise ArgumentError(
            f"Expected `geometry` to be 'collision' or 'visual', got {geometry!r}.",
            argument="geometry",
        )
    strict = as_flag("strict", strict)
    merge_fixed = as_flag("merge_fixed", merge_fixed)
    needed = "none" if rho is None and total is None else "without"
    robot = _read(path, geometry, needed, strict, merge_fixed)
    return assemble(
        path,
        "link",
        robot.links,
        rho,
        total,
        strict=strict,
        merge_fixed=merge_fixed,
        notes=robot.notes,
    )
