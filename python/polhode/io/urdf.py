"""URDF: the links of a robot description (parsed by yourdfpy, every field checked first)."""

from __future__ import annotations

import math
import os
import re
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from polhode._coerce import as_scale, density_or_mass
from polhode._files import existing, fspath, require
from polhode._meshes import mesh_arrays, mesh_body
from polhode.bodies import Body
from polhode.errors import ArgumentError, FileFormatError, PolhodeError
from polhode.io._links import Inertial, Link, Part, placed, resolve, symmetric, unit_volume

__all__ = ["read_urdf", "urdf_links"]

_NUMBER = re.compile(r"\s+")


def _numbers(text: str | None, count: Sequence[int]) -> list[float] | None:
    """``count`` finite numbers (whitespace separated, as yourdfpy reads them: with commas
    the checker passed what yourdfpy then failed to read, without the link or the field) from
    an attribute, or None."""
    if text is None:
        return None
    words = [w for w in _NUMBER.split(text.strip()) if w]
    if len(words) not in count:
        return None
    try:
        values = [float(w) for w in words]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


class _UrdfChecker:
    """Checks, on the XML, every field yourdfpy reads, so that a bad one is reported with the
    link and the field (yourdfpy fills a missing ``ixx`` with 1 and a missing mass value with
    0, and raises unnamed ValueErrors on bad numbers)."""

    def __init__(self, path: str):
        self.path = path

    def fail(self, link: str | None, field: str, message: str) -> FileFormatError:
        where = f"link {link!r}: " if link is not None else ""
        return FileFormatError(
            f"{self.path}: {where}{field}: {message}", path=self.path, link=link, field=field
        )

    def number_attr(
        self,
        element: Any,
        attr: str,
        link: str,
        field: str,
        count: Sequence[int] = (1,),
        default: str | None = None,
    ) -> None:
        text = element.get(attr, default)
        if text is None:
            raise self.fail(link, field, f"the attribute {attr!r} is missing.")
        if _numbers(text, count) is None:
            n = " or ".join(str(c) for c in count)
            raise self.fail(
                link,
                field,
                f"expected {n} finite number{'s' if count != (1,) else ''}, got {text!r}.",
            )

    def origin(self, element: Any, link: str, prefix: str) -> None:
        origin = element.find("origin")
        if origin is not None:
            self.number_attr(origin, "xyz", link, f"{prefix}.origin.xyz", (3,), "0 0 0")
            self.number_attr(origin, "rpy", link, f"{prefix}.origin.rpy", (3,), "0 0 0")

    def check(self, root: Any) -> None:
        if root.tag != "robot":
            raise self.fail(None, "robot", f"expected a <robot> element, got <{root.tag}>.")
        if not root.get("name"):
            # yourdfpy raised KeyError: 'name'.
            raise self.fail(None, "robot.name", "the <robot> has no name.")
        names: set[str] = set()
        for element in root.findall("link"):
            name = element.get("name")
            if not name:
                raise self.fail(
                    None, "link.name", f"a <link> on line {element.sourceline} has no name."
                )
            if name in names:
                raise self.fail(name, "link.name", "two links have this name.")
            names.add(name)
            inertial = element.find("inertial")
            if inertial is not None:
                self.origin(inertial, name, "inertial")
                mass = inertial.find("mass")
                if mass is None:
                    raise self.fail(name, "inertial.mass", "the <inertial> has no <mass>.")
                self.number_attr(mass, "value", name, "inertial.mass")
                inertia = inertial.find("inertia")
                if inertia is None:
                    raise self.fail(name, "inertial.inertia", "the <inertial> has no <inertia>.")
                for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
                    self.number_attr(inertia, key, name, f"inertial.inertia.{key}")
            for tag in ("collision", "visual"):
                for k, shape in enumerate(element.findall(tag)):
                    prefix = f"{tag}[{k}]"
                    self.origin(shape, name, prefix)
                    geometry = shape.find("geometry")
                    if geometry is None or len(geometry) == 0:
                        raise self.fail(name, f"{prefix}.geometry", "no geometry given.")
                    g = geometry[0]
                    field = f"{prefix}.geometry.{g.tag}"
                    if g.tag == "box":
                        self.number_attr(g, "size", name, f"{field}.size", (3,))
                    elif g.tag == "cylinder":
                        self.number_attr(g, "radius", name, f"{field}.radius")
                        self.number_attr(g, "length", name, f"{field}.length")
                    elif g.tag == "sphere":
                        self.number_attr(g, "radius", name, f"{field}.radius")
                    elif g.tag == "mesh":
                        if not g.get("filename"):
                            raise self.fail(name, f"{field}.filename", "no filename given.")
                        if g.get("scale") is not None:
                            self.number_attr(g, "scale", name, f"{field}.scale", (1, 3))


def urdf_links(path: str, geometry: str, shapes_of: str) -> list[Link]:
    """Every link of a URDF file: its declared inertial and its geometry (unit density), the
    geometry computed for ``shapes_of`` = "all" links, the links "without" an inertial, or
    "none"."""
    existing(path)
    yourdfpy = require("yourdfpy", "robots")
    from lxml import etree  # a dependency of yourdfpy

    try:
        root = etree.parse(path, etree.XMLParser(remove_comments=True)).getroot()
    except etree.XMLSyntaxError as error:
        raise FileFormatError(f"{path}: not valid XML: {error}", path=path) from error
    _UrdfChecker(path).check(root)
    try:
        model = yourdfpy.URDF.load(
            path,
            build_scene_graph=False,
            build_collision_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
        )
    except Exception as error:  # yourdfpy raises what its parser meets
        raise FileFormatError(
            f"{path}: yourdfpy cannot read it: {type(error).__name__}: {error}", path=path
        ) from error
    from yourdfpy.urdf import filename_handler_magic

    folder = os.path.dirname(os.path.abspath(path))
    links = []
    for link in model.robot.links:
        inertial = None
        if link.inertial is not None:
            origin = np.eye(4) if link.inertial.origin is None else link.inertial.origin
            rotation = np.asarray(origin[:3, :3], dtype=float)
            tensor = rotation @ np.asarray(link.inertial.inertia, dtype=float) @ rotation.T
            inertial = Inertial(
                float(link.inertial.mass),
                np.array(origin[:3, 3], dtype=float),
                symmetric(tensor),
                "inertial.inertia",
            )
        shapes = link.collisions if geometry == "collision" else link.visuals
        tag = geometry
        if geometry == "collision" and not shapes:
            shapes, tag = link.visuals, "visual"
        if shapes_of == "none" or (shapes_of == "without" and inertial is not None):
            shapes = []
        parts = []
        for k, shape in enumerate(shapes):
            field = f"{tag}[{k}].geometry"
            try:
                body = _urdf_shape(path, link.name, field, shape, filename_handler_magic, folder)
                parts.append(Part(f"{tag}[{k}]", body, None))
            except (FileFormatError, FileNotFoundError) as error:
                parts.append(Part(f"{tag}[{k}]", None, error))
        links.append(Link(link.name, inertial, parts))
    return links


def _urdf_shape(
    path: str, link: str, field: str, shape: Any, resolve: Callable[..., str], folder: str
) -> Body | None:
    """A URDF <collision>/<visual> geometry as a unit-density body in the link frame."""
    g = shape.geometry
    origin = np.eye(4) if shape.origin is None else np.asarray(shape.origin, dtype=float)
    sizes = (
        g.box.size
        if g.box is not None
        else (g.cylinder.radius, g.cylinder.length)
        if g.cylinder is not None
        else (g.sphere.radius,)
        if g.sphere is not None
        else (1.0,)
    )
    if np.any(np.asarray(sizes, dtype=float) == 0):
        return None  # a placeholder of no volume (a frame drawn as an empty box)
    try:
        if g.box is not None:
            size = np.asarray(g.box.size, dtype=float)
            body = Body.cuboid(unit_volume("box", size, lambda a, b, c: a * b * c), size)
        elif g.cylinder is not None:
            r, length = float(g.cylinder.radius), float(g.cylinder.length)
            v = unit_volume("cylinder", (r, length), lambda r, h: math.pi * r * r * h)
            body = Body.cylinder(v, r, length)
        elif g.sphere is not None:
            r = float(g.sphere.radius)
            body = Body.sphere(unit_volume("sphere", r, lambda r: 4.0 / 3.0 * math.pi * r**3), r)
        elif g.mesh is not None:
            filename = resolve(g.mesh.filename, dir=folder)
            if not os.path.isfile(filename):
                raise FileFormatError(
                    f"{path}: link {link!r}: {field}.mesh.filename: the mesh "
                    f"{g.mesh.filename!r} is not found (looked for {filename!r}).",
                    path=path,
                    link=link,
                    field=f"{field}.mesh.filename",
                )
            scale = as_scale(1.0 if g.mesh.scale is None else g.mesh.scale)
            vertices, faces = mesh_arrays(filename, scale)
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
        raise FileFormatError(
            f"{path}: link {link!r}: {field}: {error.message}",
            path=path,
            link=link,
            field=field,
        ) from error
    return placed(body, origin[:3, :3], origin[:3, 3])


def read_urdf(
    path: str | os.PathLike[str],
    *,
    density: float | None = None,
    mass: float | None = None,
    geometry: str = "collision",
) -> dict[str, Body]:
    """The links of a URDF file as bodies, each in its link's frame.

    A link's body comes from its ``<inertial>``: the ``<origin xyz rpy>`` places the centre of
    mass and turns the ``<inertia>`` (ixx ... izz: tensor elements, I_xy = -sum m x y, about
    the centre of mass in the axes of the origin's frame) into the link's axes. The file is
    parsed by yourdfpy, and every field it reads is checked first, so that a bad one raises
    naming the link and the field.

    A link without an ``<inertial>`` is massless in URDF and is left out, unless ``density``
    or ``mass`` is given: it then gets the mass properties of its geometry (boxes, cylinders,
    spheres and meshes; the meshes through :func:`read_mesh`'s loader). Declared inertials are
    never replaced.

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

    Returns
    -------
    dict[str, Body]
        By link name, in the file's order.

    Raises
    ------
    FileNotFoundError
        No such file.
    polhode.errors.FileFormatError
        Not a URDF file, a missing or malformed field, a declared inertial that is not one
        (non-positive mass, a tensor that is not positive semidefinite or breaks the triangle
        inequality), or a geometry that cannot be computed; ``link`` and ``field`` name it.

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
    ... </robot>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(urdf)
    >>> sorted(ph.io.read_urdf(path))  # base has no inertial: massless, left out
    ['tool']
    >>> bodies = ph.io.read_urdf(path, density=1000.0)
    >>> round(bodies["base"].mass, 12), bool(bodies["tool"].inertia[1, 1] > 1.9e-4)
    (2.0, True)
    """
    path = fspath(path)
    rho, total = density_or_mass(density, mass, required=False)
    if geometry not in ("collision", "visual"):
        raise ArgumentError(
            f"Expected `geometry` to be 'collision' or 'visual', got {geometry!r}.",
            argument="geometry",
        )
    needed = "none" if rho is None and total is None else "without"
    links = urdf_links(path, geometry, needed)
    return resolve(path, "link", links, rho, total)
