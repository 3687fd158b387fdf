"""Files in: triangle meshes, robot descriptions (URDF, MJCF), and an audit of their inertials.

- :func:`read_mesh` reads STL (ascii and binary), OBJ, PLY, OFF and glTF/GLB with trimesh's
  loaders and returns the meshes of the file as bodies (``Body.from_file`` is their composite).
- :func:`read_urdf` (parsed by yourdfpy) and :func:`read_mjcf` (MuJoCo's ``MjSpec``: the values
  as written, before MuJoCo's compiler changes or rejects them) return one :class:`Body` per link
  or body, in that link's own frame.
- :func:`audit` checks every link's declared inertial and its geometry, and returns a
  :class:`Finding` for each link (``polhode audit FILE`` prints them).

The mass properties are polhode's own (exact mesh integrals, the core's solids); the libraries
only read the files. They are optional: ``pip install 'polhode[mesh]'`` (trimesh) and
``'polhode[robots]'`` (yourdfpy and MuJoCo).

A broken file raises :class:`polhode.errors.FileFormatError`, whose message and attributes name
the file, the link (or body, or mesh part) and the field at fault; a missing file raises
:class:`FileNotFoundError`.

Examples
--------
>>> import polhode as ph
>>> import polhode.io
>>> import os, tempfile
>>> urdf = '''<robot name="r"><link name="arm"><inertial>
...   <origin xyz="0 0 0.1" rpy="0 0 0"/><mass value="2"/>
...   <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/>
... </inertial></link></robot>'''
>>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
>>> with open(path, "w") as handle:
...     _ = handle.write(urdf)
>>> bodies = ph.io.read_urdf(path)
>>> bodies["arm"].mass, bodies["arm"].center_of_mass.tolist()
(2.0, [0.0, 0.0, 0.1])
>>> [(f.link, f.severity) for f in ph.io.audit(path)]
[('arm', 'ok')]
"""

from __future__ import annotations

import importlib
import math
import os
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_flag, as_float_array, as_scalar
from polhode.bodies import Body
from polhode.errors import (
    ArgumentError,
    FileFormatError,
    NonFiniteError,
    NonPositiveError,
    PolhodeError,
    ShapeError,
)

__all__ = ["Finding", "MESH_FORMATS", "audit", "read_mesh", "read_mjcf", "read_urdf"]

#: The mesh formats :func:`read_mesh` reads (by the file's extension), all through trimesh.
MESH_FORMATS = ("stl", "obj", "ply", "off", "gltf", "glb")


# --- shared helpers --------------------------------------------------------------------------


def _fspath(path: Any, name: str = "path") -> str:
    """A path as a str (TypeError for anything that is not a str or os.PathLike)."""
    if isinstance(path, bytes) or not isinstance(path, str | os.PathLike):
        raise TypeError(f"Expected `{name}` to be a path (str or os.PathLike), got {type(path)}.")
    return os.fspath(path)


def _existing(path: str) -> str:
    """``path`` if it is a file; FileNotFoundError (naming it) or FileFormatError (a folder)."""
    if not os.path.exists(path):
        raise FileNotFoundError(2, "No such file", path)
    if os.path.isdir(path):
        raise FileFormatError(f"{path}: is a folder, expected a file.", path=path)
    return path


def _require(module: str, extra: str) -> Any:
    """Import an optional dependency, or say which extra installs it."""
    try:
        return importlib.import_module(module)
    except ImportError as error:
        raise ImportError(
            f"Reading this file needs {module}: pip install 'polhode[{extra}]'."
        ) from error


def _density_or_mass(
    density: Any, mass: Any, *, required: bool
) -> tuple[float | None, float | None]:
    """Check ``density`` and ``mass``: at most one (exactly one if ``required``), a finite
    positive number."""
    if density is not None and mass is not None:
        raise ArgumentError("Give exactly one of `density` and `mass`, got both.", argument="mass")
    if required and density is None and mass is None:
        raise ArgumentError(
            "Give exactly one of `density` and `mass`, got neither.", argument="density"
        )
    out: list[float | None] = []
    for name, value in (("density", density), ("mass", mass)):
        if value is None:
            out.append(None)
            continue
        x = as_scalar(name, value)
        if not math.isfinite(x):
            raise NonFiniteError(f"Expected `{name}` to be finite, got {x}.", argument=name)
        if x <= 0:
            raise NonPositiveError(f"Expected `{name}` to be positive, got {x:g}.", argument=name)
        out.append(x)
    return out[0], out[1]


def _as_scale(value: Any, name: str = "scale") -> NDArray[np.float64]:
    """A scale factor: one number or three (per axis), finite and non-zero (a negative factor
    mirrors the mesh)."""
    array = as_float_array(name, value)
    if array.shape in ((), (1,)):  # ascontiguousarray makes a number (1,)
        array = np.full(3, float(array.reshape(-1)[0]))
    if array.shape != (3,):
        raise ShapeError(
            f"Expected `{name}` to be a number or 3 numbers, got shape {array.shape}.",
            argument=name,
        )
    if not np.all(np.isfinite(array)):
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got {array.tolist()}.", argument=name
        )
    if np.any(array == 0):
        raise ArgumentError(
            f"Expected `{name}` to be non-zero, got {array.tolist()}.", argument=name
        )
    return array


def _quat_matrix(wxyz: Sequence[float]) -> NDArray[np.float64]:
    """Rotation matrix of a (w, x, y, z) quaternion (MuJoCo's order), normalised."""
    from scipy.spatial.transform import Rotation

    w, x, y, z = (float(c) for c in wxyz)
    return np.asarray(Rotation.from_quat([x, y, z, w]).as_matrix())


def _placed(body: Body, rotation: NDArray[np.float64], offset: Any) -> Body:
    """``body`` rotated by ``rotation`` about its origin, then moved by ``offset``."""
    if not np.array_equal(rotation, np.eye(3)):
        body = body.rotated(rotation)
    offset = np.asarray(offset, dtype=float)
    return body.translated(offset) if np.any(offset) else body


def _merge_vertices(
    vertices: NDArray[np.float64], faces: NDArray[np.int64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Vertices at exactly the same position merged into one (STL repeats every vertex per
    triangle; OBJ and glTF split vertices along texture seams), and the triangles that then
    repeat a vertex (zero area) dropped."""
    if len(vertices) == 0:
        return vertices, faces
    unique, inverse = np.unique(vertices, axis=0, return_inverse=True)
    f = np.asarray(inverse).reshape(-1)[faces]
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])
    return np.ascontiguousarray(unique), np.ascontiguousarray(f[keep], dtype=np.int64)


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


# --- meshes ----------------------------------------------------------------------------------


def _mesh_parts(
    path: str, scale: NDArray[np.float64]
) -> list[tuple[str, NDArray[np.float64], NDArray[np.int64]]]:
    """(name, vertices, faces) of every triangle mesh in the file: placed by the file's scene
    graph (glTF nodes), scaled, duplicate vertices merged."""
    _existing(path)
    extension = os.path.splitext(path)[1].lower().lstrip(".")
    if extension not in MESH_FORMATS:
        got = "." + extension if extension else "no extension"
        known = ", ".join("." + e for e in MESH_FORMATS)
        raise FileFormatError(
            f"{path}: expected a mesh file ending in {known}, got {got}.", path=path
        )
    trimesh = _require("trimesh", "mesh")
    options: dict[str, Any] = {"process": False}
    if extension == "obj":  # one part per object ('o'), as glTF has one per node
        options.update(split_objects=True, group_material=False)
    try:
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
        vertices, faces = _merge_vertices(
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


def _unit_volume(kind: str, sizes: Any, volume: Any) -> float:
    """The volume of a primitive (its mass at unit density) from its positive, finite
    ``sizes``, or a PolhodeError naming the sizes: a negative or zero size was reported as a
    "mass" that must be positive, and a volume beyond double precision as a mass of inf or 0."""
    values = [float(x) for x in np.ravel(sizes)]
    if not all(math.isfinite(x) and x > 0 for x in values):
        raise ArgumentError(
            f"expected the {kind}'s sizes to be positive and finite, got {values}.",
            argument="size",
        )
    try:
        with np.errstate(over="ignore", under="ignore"):
            v = float(volume(*values))
    except OverflowError:  # Python's float power raises where numpy gives inf
        v = math.inf
    if not (math.isfinite(v) and v >= np.finfo(float).tiny):
        raise ArgumentError(
            f"the {kind}'s volume at sizes {values} is beyond double precision ({v:g}): its "
            "mass at a density cannot be represented.",
            argument="size",
        )
    return v


def _mesh_body(
    path: str,
    name: str,
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    density: float,
    shell: bool,
    fix_winding: bool,
    link: str | None = None,
    field: str | None = None,
) -> Body:
    """Body.mesh with the error re-raised as a FileFormatError naming the file and part."""
    try:
        return Body.mesh(vertices, faces, density=density, shell=shell, fix_winding=fix_winding)
    except PolhodeError as error:
        where = f"link {link!r}: " if link is not None else ""
        raise FileFormatError(
            f"{path}: {where}mesh {name!r}: {error.message}",
            path=path,
            link=link if link is not None else name,
            field=field if field is not None else error.argument,
        ) from error


def read_mesh(
    path: str | os.PathLike[str],
    *,
    density: float | None = None,
    mass: float | None = None,
    shell: bool = False,
    scale: float | Sequence[float] = 1.0,
    fix_winding: bool = False,
) -> dict[str, Body]:
    """The meshes of a file, each as a body, by the names the file gives them.

    Reads STL (ascii and binary), OBJ, PLY, OFF, glTF and GLB (by the extension) with
    trimesh's loaders; the mass properties are polhode's exact mesh integrals. Each part is
    placed by the file's scene graph (a glTF node's transform; an OBJ file has one part per
    object), then scaled. Vertices at exactly the same position are merged, so that a triangle
    soup (STL) closes.

    Parameters
    ----------
    path : str or os.PathLike
        The mesh file.
    density, mass : float
        Exactly one: the density of every part (mass per volume, or per area with
        ``shell=True``), or the total mass of the file, shared between the parts in proportion
        to their volumes (areas).
    shell : bool
        Mass on the surfaces (a thin shell) rather than in the volumes; the meshes need not
        then be closed.
    scale : float or (3,) floats
        Length scale applied to the vertices, e.g. 0.001 for a file in millimetres read in
        metres; three numbers scale each axis (a negative one mirrors).
    fix_winding : bool
        Turn an inside-out part (faces wound clockwise seen from outside) the right way out
        instead of raising.

    Returns
    -------
    dict[str, Body]
        One body per mesh part (in the file's coordinates, scaled); ``Body.from_file`` is their
        sum.

    Raises
    ------
    FileNotFoundError
        No such file.
    polhode.errors.FileFormatError
        Not a mesh of a known format, no triangles, or a part that is open (unless
        ``shell=True``), inside out or of zero volume; the message names the file and the part.
    polhode.errors.ArgumentError, NonPositiveError, NonFiniteError
        Bad ``density``, ``mass`` or ``scale``.

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> off = ("OFF\\n4 4 0\\n0 0 0\\n1 0 0\\n0 1 0\\n0 0 1\\n"
    ...        "3 0 2 1\\n3 0 1 3\\n3 0 3 2\\n3 1 2 3\\n")
    >>> path = os.path.join(tempfile.mkdtemp(), "tetrahedron.off")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(off)
    >>> parts = ph.io.read_mesh(path, density=6.0)
    >>> [(name, round(body.mass, 12)) for name, body in parts.items()]
    [('tetrahedron.off', 1.0)]
    """
    path = _fspath(path)
    rho, total = _density_or_mass(density, mass, required=True)
    as_flag("shell", shell)
    as_flag("fix_winding", fix_winding)
    factor = _as_scale(scale)
    parts = _mesh_parts(path, factor)
    if total is None:
        return {name: _mesh_body(path, name, v, f, rho, shell, fix_winding) for name, v, f in parts}
    # The total mass shared by volume (area): each part at unit density in units of 2^k, the
    # power of two of the largest coordinate (exactly), then its mass scaled to its share and
    # its lengths by 2^k. At unit density in the file's units the volumes of a mesh scaled by
    # 1e-100 underflowed (I = 0 for a cube of mass 1), and those scaled by 1e62 overflowed.
    largest = max(float(np.max(np.abs(v))) for _, v, _ in parts)
    k = math.frexp(largest)[1] - 1 if largest > 0 else 0
    unit = {
        name: _mesh_body(path, name, np.ldexp(v, -k), f, 1.0, shell, fix_winding)
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


def _mesh_arrays(
    path: str, scale: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """All the triangles of a mesh file as one mesh (a robot description's mesh is one)."""
    parts = _mesh_parts(path, scale)
    if len(parts) == 1:
        return parts[0][1], parts[0][2]
    offsets = np.cumsum([0] + [len(v) for _, v, _ in parts[:-1]])
    vertices = np.concatenate([v for _, v, _ in parts])
    faces = np.concatenate([f + o for (_, _, f), o in zip(parts, offsets, strict=True)])
    return vertices, faces


# --- shared by the robot readers -------------------------------------------------------------


@dataclass(frozen=True)
class _Inertial:
    """A declared inertial in the link frame: mass, centre of mass, tensor about it."""

    mass: float
    center_of_mass: NDArray[np.float64]
    inertia: NDArray[np.float64]
    field: str  # the element the tensor came from, for messages


@dataclass(frozen=True)
class _Part:
    """One geometry element of a link: a body of unit density placed in the link frame (or
    the error that prevented computing it), and - MJCF - the density the file gives it."""

    name: str
    body: Body | None
    error: Exception | None
    density: float = 1.0


@dataclass
class _Link:
    """A link (URDF) or body (MJCF): its declared inertial, if any, and its geometry."""

    name: str
    inertial: _Inertial | None
    parts: list[_Part]


def _declared_body(path: str, kind: str, link: _Link) -> Body:
    """The Body of a link's declared inertial, or FileFormatError naming the field."""
    assert link.inertial is not None
    i = link.inertial
    try:
        return Body.from_inertia(i.mass, i.inertia, i.center_of_mass)
    except PolhodeError as error:
        field = i.field.rsplit(".", 1)[0] + ".mass" if error.argument == "mass" else i.field
        raise FileFormatError(
            f"{path}: {kind} {link.name!r}: {field}: {error.message}",
            path=path,
            link=link.name,
            field=field,
        ) from error


def _geometry_body(link: _Link, file_density: bool = False) -> Body | None:
    """The link's geometry at unit density (mass = volume) or, with ``file_density``, at the
    densities the file gives its geoms; None without geometry. The first part that could not
    be computed raises its error."""
    bodies = []
    for part in link.parts:
        if part.error is not None:
            raise part.error
        if part.body is not None:
            scale = part.density if file_density else 1.0
            bodies.append(part.body if scale == 1.0 else part.body.scaled(mass_scale=scale))
    return sum(bodies[1:], bodies[0]) if bodies else None


def _resolve(
    path: str, kind: str, links: list[_Link], density: float | None, mass: float | None
) -> dict[str, Body]:
    """Declared inertials as bodies; with ``density`` or a total ``mass`` (shared by volume),
    the other links from their geometry; in the file's order."""
    out: dict[str, Body] = {}
    derived: dict[str, Body] = {}
    for link in links:
        if link.inertial is not None:
            out[link.name] = _declared_body(path, kind, link)
        elif density is not None or mass is not None:
            body = _geometry_body(link)
            if body is not None:
                derived[link.name] = body
    if mass is not None and derived:
        volume = math.fsum(b.mass for b in derived.values())
        derived = {k: b.scaled(mass_scale=mass / volume) for k, b in derived.items()}
    elif density is not None:
        derived = {k: b.scaled(mass_scale=density) for k, b in derived.items()}
    out.update(derived)
    return {link.name: out[link.name] for link in links if link.name in out}


# --- URDF ------------------------------------------------------------------------------------

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


def _urdf_links(path: str, geometry: str, shapes_of: str) -> list[_Link]:
    """Every link of a URDF file: its declared inertial and its geometry (unit density), the
    geometry computed for ``shapes_of`` = "all" links, the links "without" an inertial, or
    "none"."""
    _existing(path)
    yourdfpy = _require("yourdfpy", "robots")
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
            inertial = _Inertial(
                float(link.inertial.mass),
                np.array(origin[:3, 3], dtype=float),
                _symmetric(tensor),
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
                parts.append(_Part(f"{tag}[{k}]", body, None))
            except (FileFormatError, FileNotFoundError) as error:
                parts.append(_Part(f"{tag}[{k}]", None, error))
        links.append(_Link(link.name, inertial, parts))
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
            body = Body.cuboid(_unit_volume("box", size, lambda a, b, c: a * b * c), size)
        elif g.cylinder is not None:
            r, length = float(g.cylinder.radius), float(g.cylinder.length)
            v = _unit_volume("cylinder", (r, length), lambda r, h: math.pi * r * r * h)
            body = Body.cylinder(v, r, length)
        elif g.sphere is not None:
            r = float(g.sphere.radius)
            body = Body.sphere(_unit_volume("sphere", r, lambda r: 4.0 / 3.0 * math.pi * r**3), r)
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
            scale = _as_scale(1.0 if g.mesh.scale is None else g.mesh.scale)
            vertices, faces = _mesh_arrays(filename, scale)
            body = _mesh_body(
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
    return _placed(body, origin[:3, :3], origin[:3, 3])


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
    path = _fspath(path)
    rho, total = _density_or_mass(density, mass, required=False)
    if geometry not in ("collision", "visual"):
        raise ArgumentError(
            f"Expected `geometry` to be 'collision' or 'visual', got {geometry!r}.",
            argument="geometry",
        )
    needed = "none" if rho is None and total is None else "without"
    links = _urdf_links(path, geometry, needed)
    return _resolve(path, "link", links, rho, total)


# --- MJCF ------------------------------------------------------------------------------------


def _mjcf_spec(path: str) -> Any:
    """MuJoCo's MjSpec of a file, its parse errors as FileFormatError naming the body."""
    _existing(path)
    mujoco = _require("mujoco", "robots")
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


def _mjcf_links(path: str) -> tuple[list[_Link], bool]:
    """Every body of an MJCF file (the world left out): its declared inertial, and its geoms
    at unit density with the density the file gives each (geoms of no mass left out); and
    whether MuJoCo infers inertials from geoms (the compiler's ``inertiafromgeom`` is not
    false)."""
    spec = _mjcf_spec(path)
    mujoco = importlib.import_module("mujoco")
    folder = os.path.dirname(os.path.abspath(path))
    low, high = (int(x) for x in spec.compiler.inertiagrouprange)
    infer = spec.compiler.inertiafromgeom != mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    links = []
    # An unnamed body is "body K" (K its MuJoCo id), unless a body is named so: then
    # "body K (unnamed)" (the two shared a key, and one of them was lost without a word).
    taken = {body.name for body in spec.bodies if body.name}
    for index, body in enumerate(spec.bodies):
        if index == 0:
            continue  # the world
        name = body.name
        if not name:
            name = f"body {index}"
            while name in taken:
                name += " (unnamed)"
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
            if np.isnan(full[0]):
                rotation = _mjcf_rotation(
                    path, name, "inertial.quat", _mjcf_quat(spec, body.iquat, body.ialt)
                )
                # An infinite moment gives NaN entries (inf * 0): refused or reported later.
                with np.errstate(invalid="ignore", over="ignore"):
                    tensor = rotation @ np.diag(np.asarray(body.inertia, dtype=float)) @ rotation.T
                inertial = _Inertial(
                    float(body.mass), com, _symmetric(tensor), "inertial.diaginertia"
                )
            else:
                xx, yy, zz, xy, xz, yz = full
                tensor = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
                inertial = _Inertial(float(body.mass), com, tensor, "inertial.fullinertia")
        parts = []
        for k, geom in enumerate(body.geoms):
            label = f"geom {geom.name!r}" if geom.name else f"geom[{k}]"
            if not low <= geom.group <= high:
                continue
            try:
                part, density = _mjcf_geom(spec, mujoco, path, folder, name, label, geom)
            except (FileFormatError, FileNotFoundError) as error:
                parts.append(_Part(label, None, error))
                continue
            if part is not None:
                parts.append(_Part(label, part, None, density))
        links.append(_Link(name, inertial, parts))
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
                Body.spherical_shell(_unit_volume("sphere", r, lambda r: 4 * math.pi * r * r), r)
                if shell
                else Body.sphere(_unit_volume("sphere", r, lambda r: 4 / 3 * math.pi * r**3), r)
            )
        elif shell:
            raise fail("shell inertia is supported for spheres and meshes only.", "shellinertia")
        elif kind == t.mjGEOM_CAPSULE:
            r, h = size[0], 2 * size[1]
            v = _unit_volume("capsule", (r, h), lambda r, h: math.pi * (r * r * h + 4 / 3 * r**3))
            unit = Body.capsule(v, r, h)
        elif kind == t.mjGEOM_CYLINDER:
            r, h = size[0], 2 * size[1]
            v = _unit_volume("cylinder", (r, h), lambda r, h: math.pi * r * r * h)
            unit = Body.cylinder(v, r, h)
        elif kind == t.mjGEOM_ELLIPSOID:
            v = _unit_volume("ellipsoid", size, lambda a, b, c: 4 / 3 * math.pi * (a * b * c))
            unit = Body.ellipsoid(v, size)
        elif kind == t.mjGEOM_BOX:
            unit = Body.cuboid(_unit_volume("box", size, lambda a, b, c: 8 * (a * b * c)), 2 * size)
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
        return _placed(unit, rotation, position), density
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
    scale = _as_scale(np.asarray(mesh.scale, dtype=float), "mesh.scale")
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
        vertices, faces = _mesh_arrays(filename, np.ones(3))
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
    return _mesh_body(source, label, vertices, faces, 1.0, shell, False, link=body, field=field)


def read_mjcf(
    path: str | os.PathLike[str],
    *,
    density: float | None = None,
    mass: float | None = None,
) -> dict[str, Body]:
    """The bodies of a MuJoCo MJCF file, each in its own frame.

    The file is parsed by MuJoCo (``mujoco.MjSpec.from_file``) and its values are taken as
    written, before MuJoCo's compiler changes or rejects them (``settotalmass``,
    ``boundmass``, ``balanceinertia`` are not applied, nor ``inertiafromgeom="true"``'s
    replacing of declared inertials; a tensor that breaks the triangle inequality raises here
    with the body's name, as :func:`audit` reports it).

    A body with an ``<inertial>`` gets it: ``pos``, ``mass`` and ``diaginertia`` turned by
    ``quat`` (or euler, axisangle, xyaxes, zaxis, in the file's angle unit and Euler sequence),
    or ``fullinertia`` (I_xx, I_yy, I_zz, I_xy, I_xz, I_yz, tensor elements in the body's axes).
    A body without one gets, as in MuJoCo, the mass properties of its geoms (spheres,
    capsules, cylinders, ellipsoids, boxes and meshes, with their ``fromto``, frames, and
    each geom's ``density`` or ``mass``; geoms outside the compiler's ``inertiagrouprange``
    left out), computed by polhode. ``density`` or ``mass`` replace the file's densities for
    those bodies (a geom the file gives no mass, ``density="0"`` or ``mass="0"`` as visual
    geoms have, stays out). Bodies of no mass are left out; so is the world.

    A mesh's ``inertia`` attribute is followed for ``"convex"`` (its convex hull, also used
    for vertices without faces) and ``"shell"``; ``"exact"`` and MuJoCo's default
    ``"legacy"`` both give the exact integrals of the closed mesh. MuJoCo's legacy integration
    differs for non-convex meshes (it overstates an L-shaped prism's mass by 59%); polhode's
    value is then the right one, and MuJoCo's agrees with it with ``inertia="exact"``.

    Parameters
    ----------
    path : str or os.PathLike
        The MJCF (MuJoCo XML) file.
    density : float, optional
        One density for the geoms of every body without an inertial (instead of the geoms'
        own ``density`` and ``mass``).
    mass : float, optional
        Total mass of the bodies without an inertial, shared in proportion to the volumes of
        their geoms.

    Returns
    -------
    dict[str, Body]
        By body name (an unnamed body as ``"body K"``, K its MuJoCo body id, or
        ``"body K (unnamed)"`` if a body is named ``"body K"``), in the file's
        order.

    Raises
    ------
    FileNotFoundError
        No such file.
    polhode.errors.FileFormatError
        MuJoCo cannot parse the file (its message, with the body around the line it names), a
        declared inertial that is not one, or a geom whose mass properties cannot be computed;
        ``link`` and ``field`` name the body and the attribute.

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> xml = '''<mujoco><worldbody>
    ...   <body name="arm"><inertial pos="0 0 0.1" mass="2" diaginertia="0.02 0.02 0.01"/></body>
    ...   <body name="ball"><geom type="sphere" size="0.1" density="1000"/></body>
    ... </worldbody></mujoco>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "m.xml")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(xml)
    >>> bodies = ph.io.read_mjcf(path)
    >>> bodies["arm"].center_of_mass.tolist(), round(bodies["ball"].mass, 6)
    ([0.0, 0.0, 0.1], 4.18879)
    """
    path = _fspath(path)
    rho, total = _density_or_mass(density, mass, required=False)
    links, infer = _mjcf_links(path)
    if rho is not None or total is not None:
        return _resolve(path, "body", links, rho, total)
    # MuJoCo's semantics: a body without an inertial has its geoms' at their own densities.
    out: dict[str, Body] = {}
    for link in links:
        if link.inertial is not None:
            out[link.name] = _declared_body(path, "body", link)
        elif infer:
            body = _geometry_body(link, file_density=True)
            if body is not None:
                out[link.name] = body
    return out


# --- audit -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Finding:
    """One result of :func:`audit` about one link.

    Attributes
    ----------
    link : str
        The link (URDF) or body (MJCF).
    severity : str
        ``"error"`` (not a physical inertial: a simulator rejects it or computes nonsense),
        ``"warning"`` (physical but suspicious), ``"info"`` (worth knowing) or ``"ok"``.
    check : str
        Which check: ``"mass"``, ``"positive_definite"``, ``"triangle_inequality"``,
        ``"small_moment"``, ``"geometry"`` (the declared tensor disagrees with the link's
        geometry), ``"products_swapped"``, ``"products_sign"``, ``"parallel_axis"``,
        ``"about_origin"``, ``"origin_far"`` (the centre of mass far from the geometry),
        ``"geometry_error"`` (the geometry could not be computed), ``"no_inertial"`` or
        ``"ok"``.
    message : str
        What is wrong, with the numbers.
    corrected : str or None
        A corrected ``<inertial>`` element (URDF or MJCF, as the file) from the link's geometry
        with its declared mass, where one can be computed.

    Examples
    --------
    >>> from polhode.io import Finding
    >>> f = Finding("forearm", "error", "mass", "<mass value> is 0: no body has no mass.", None)
    >>> f.severity, f.check
    ('error', 'mass')
    """

    link: str
    severity: str
    check: str
    message: str
    corrected: str | None = None


def _relative(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """||a - b|| / ||b|| (Frobenius), inf if b is zero and a is not."""
    scale = float(np.linalg.norm(b))
    difference = float(np.linalg.norm(a - b))
    if scale == 0:
        return 0.0 if difference == 0 else math.inf
    return difference / scale


_PRODUCTS = ((0, 1), (0, 2), (1, 2))
_PRODUCT_NAMES = ("ixy", "ixz", "iyz")


def _with_products(tensor: NDArray[np.float64], values: Sequence[float]) -> NDArray[np.float64]:
    out = tensor.copy()
    for (i, j), v in zip(_PRODUCTS, values, strict=True):
        out[i, j] = out[j, i] = v
    return out


def _symmetric(tensor: NDArray[np.float64]) -> NDArray[np.float64]:
    """The mean of ``tensor`` and its transpose, without overflow near the largest double
    (a declared moment of 1e308 read as inf)."""
    with np.errstate(over="ignore"):
        mean = (tensor + tensor.T) / 2
    if np.all(np.isfinite(mean)) or not np.all(np.isfinite(tensor)):
        return mean
    return tensor / 2 + tensor.T / 2


def _audit_link(
    link: _Link, kind: str, fmt: str, rtol: float, density: float | None
) -> list[Finding]:
    """The findings about one link (see :func:`audit`)."""
    findings: list[Finding] = []
    name = link.name

    def add(severity: str, check: str, message: str, corrected: str | None = None) -> None:
        findings.append(Finding(name, severity, check, message, corrected))

    # The geometry, at unit density, with the parts' own bodies kept for the diagnoses.
    geometry: Body | None = None
    parts = [p.body for p in link.parts if p.body is not None]
    for part in link.parts:
        if part.error is not None:
            add("warning", "geometry_error", f"{part.name}: {part.error}")
    if parts and len(parts) == sum(1 for p in link.parts if p.error is None):
        geometry = sum(parts[1:], parts[0])
    if link.inertial is None:
        if kind == "body":  # MJCF: MuJoCo infers the inertial from the geoms
            if geometry is not None:
                inferred = _geometry_body(link, file_density=True)
                assert inferred is not None
                add(
                    "info",
                    "no_inertial",
                    f"no <inertial>: inferred from the geoms, mass {inferred.mass:.6g}.",
                )
            elif not findings:
                add("info", "no_inertial", "no <inertial> and no geoms with mass.")
            return findings
        corrected = None
        if geometry is not None and density is not None:
            corrected = _inertial_text(geometry.scaled(mass_scale=density), fmt)
        add(
            "info",
            "no_inertial",
            "no <inertial>: a massless link (fine for a frame; a moving link needs one)"
            + (" and it has geometry" if geometry is not None else "")
            + ".",
            corrected,
        )
        return findings

    i = link.inertial
    m, com, tensor = i.mass, i.center_of_mass, i.inertia
    eps = np.finfo(float).eps
    # The geometry with the declared mass (or the given density), for the comparisons.
    reference = None
    if geometry is not None:
        if math.isfinite(m) and m > 0:
            reference = geometry.scaled(mass_scale=m / geometry.mass)
        elif density is not None:
            reference = geometry.scaled(mass_scale=density)
    corrected = None if reference is None else _inertial_text(reference, fmt)

    if not (math.isfinite(m) and m > 0):
        add(
            "error",
            "mass",
            f"mass {m:g} is not positive"
            + ("" if corrected else " (give a density to compute one from the geometry)")
            + ".",
            corrected,
        )
    if not np.all(np.isfinite(tensor)):
        # Every comparison below is False with a NaN (the verdict was "ok"), and eigvalsh
        # raises LinAlgError on one.
        add(
            "error",
            "non_finite",
            f"the inertia tensor has entries that are not finite: {tensor.tolist()}.",
            corrected,
        )
        return findings
    moments = np.linalg.eigvalsh(tensor)
    largest = float(np.max(np.abs(moments))) if moments.size else 0.0
    tolerance = 16 * eps * max(largest, float(np.abs(tensor).max()))
    error_found = False
    if moments[0] < -tolerance:
        error_found = True
        add(
            "error",
            "positive_definite",
            f"the inertia tensor is not positive semidefinite: principal moments "
            f"{_fmt(moments)} (one is negative).",
            corrected,
        )
    # In halves (exactly): moments near the largest double would overflow the sum.
    elif moments[0] / 2 + moments[1] / 2 < moments[2] / 2 - tolerance / 2:
        error_found = True
        excess = (moments[2] - moments[0] - moments[1]) / moments[2]
        add(
            "error",
            "triangle_inequality",
            f"principal moments {_fmt(moments)} break the triangle inequality "
            f"I1 + I2 >= I3 (I3 exceeds I1 + I2 by {excess:.3g} of I3): no mass distribution "
            "has them.",
            corrected,
        )
    elif largest == 0:
        add(
            "warning",
            "small_moment",
            "all principal moments are zero (a point mass): simulators that need a positive "
            "definite inertia reject it or give it a floor.",
            corrected,
        )
    elif moments[0] <= 1e-6 * moments[2]:
        add(
            "warning",
            "small_moment",
            f"the smallest principal moment {moments[0]:.3g} is {moments[0] / moments[2]:.2g} "
            "of the largest (a rod or a point mass): near-singular for a simulator.",
            corrected,
        )

    if reference is not None:
        target = reference.inertia
        mismatch = _relative(tensor, target)
        distance = float(np.linalg.norm(com - reference.center_of_mass))
        gyration = math.sqrt(max(float(np.trace(reference.second_moment)), 0.0) / reference.mass)
        if distance > 2 * gyration:
            add(
                "warning",
                "origin_far",
                f"the centre of mass {_fmt(com)} is {distance:.3g} from the geometry's "
                f"{_fmt(reference.center_of_mass)}, {distance / gyration:.3g} times the "
                f"geometry's radius of gyration {gyration:.3g}: outside the geometry.",
                corrected,
            )
        # A known mistake is named whenever undoing it makes the tensor agree with the
        # geometry far better (products of inertia are small next to the moments, so a swap
        # can hide inside the tolerance); a tensor already in error is not compared.
        diagnosis = None if error_found else _diagnose(tensor, reference, link, m, rtol, mismatch)
        if diagnosis is not None:
            check, text = diagnosis
            add("warning", check, text, corrected)
        elif mismatch > rtol and not error_found:
            add(
                "warning",
                "geometry",
                f"the inertia tensor differs from that of the link's geometry at the same "
                f"mass by {mismatch:.3g} (relative, Frobenius; tolerance {rtol:g}): "
                f"principal moments {_fmt(moments)}, geometry "
                f"{_fmt(np.linalg.eigvalsh(target))}.",
                corrected,
            )
    if not findings and not error_found:
        add("ok", "ok", "consistent" + (" with its geometry." if reference is not None else "."))
    return findings


def _diagnose(
    tensor: NDArray[np.float64],
    reference: Body,
    link: _Link,
    m: float,
    rtol: float,
    mismatch: float,
) -> tuple[str, str] | None:
    """A known exporter mistake that explains the mismatch with the geometry, if one does:
    undoing it brings the tensor within rtol/5 of the geometry's and 10 times closer than it
    was."""
    import itertools

    target = reference.inertia
    tight = min(rtol / 5, mismatch / 10)
    products = [tensor[i, j] for i, j in _PRODUCTS]
    if _relative(_with_products(tensor, [-p for p in products]), target) < tight:
        return (
            "products_sign",
            "the products of inertia have the wrong sign: they are written as +sum m x y, "
            "the tensor elements are -sum m x y.",
        )
    for order in itertools.permutations(range(3)):
        if order == (0, 1, 2):
            continue
        for sign in (1, -1):
            candidate = _with_products(tensor, [sign * products[k] for k in order])
            if _relative(candidate, target) < tight:
                moved = [
                    f"{_PRODUCT_NAMES[k]} is written as {_PRODUCT_NAMES[order.index(k)]}"
                    for k in range(3)
                    if order.index(k) != k
                ]
                return (
                    "products_swapped",
                    "the products of inertia are in the wrong places: "
                    + ", ".join(moved)
                    + (" (and of the wrong sign)" if sign < 0 else "")
                    + ".",
                )
    about_origin = reference.inertia_about(np.zeros(3))
    if np.any(reference.center_of_mass) and _relative(tensor, about_origin) < tight:
        return (
            "about_origin",
            "the tensor is the geometry's inertia about the link origin, not about the centre "
            "of mass: the parallel-axis term m d^2 is included where it must not be.",
        )
    parts = [p.body for p in link.parts if p.body is not None]
    if len(parts) > 1:
        volume = math.fsum(b.mass for b in parts)
        summed = sum((b.inertia * (m / volume) for b in parts), np.zeros((3, 3)))
        if _relative(tensor, summed) < tight:
            return (
                "parallel_axis",
                f"the tensor is the sum of the {len(parts)} parts' inertias each about its own "
                "centre of mass: the parallel-axis terms m d^2 that move them to the link's "
                "centre of mass are missing.",
            )
    return None


def _fmt(values: Any) -> str:
    return "(" + ", ".join(f"{float(v):.4g}" for v in np.asarray(values).ravel()) + ")"


def _inertial_text(body: Body, fmt: str) -> str:
    return body.to_urdf_inertial() if fmt == "urdf" else body.to_mjcf()


def _format_of(path: str) -> str:
    """'urdf' or 'mjcf', by the root element of the XML."""
    import xml.etree.ElementTree as ET

    _existing(path)
    try:
        for _, element in ET.iterparse(path, events=("start",)):
            tag = element.tag
            break
        else:
            raise FileFormatError(f"{path}: an empty XML file.", path=path)
    except ET.ParseError as error:
        raise FileFormatError(f"{path}: not valid XML: {error}", path=path) from error
    if tag == "robot":
        return "urdf"
    if tag == "mujoco":
        return "mjcf"
    raise FileFormatError(
        f"{path}: expected a URDF (<robot>) or MJCF (<mujoco>) file, got <{tag}>.", path=path
    )


def audit(
    path: str | os.PathLike[str],
    *,
    rtol: float = 0.25,
    geometry: str = "collision",
    density: float | None = None,
) -> list[Finding]:
    """Check every link's declared inertial of a URDF or MJCF file against physics and against
    the link's own geometry.

    For each link (URDF) or body (MJCF):

    - errors: a mass that is not positive; a tensor that is not positive semidefinite; principal
      moments that break the triangle inequality I1 + I2 >= I3 (no mass distribution has them;
      MuJoCo refuses them);
    - warnings: a principal moment below 1e-6 of the largest, or all zero (a point mass); a
      tensor that differs from that of the link's geometry, taken as uniform with the declared
      mass, by more than ``rtol`` (relative Frobenius norm), with the cause named where it is a
      known exporter mistake (products of inertia swapped or of the wrong sign, the tensor about
      the link origin rather than the centre of mass, the parts summed without their
      parallel-axis terms); a centre of mass more than twice the geometry's radius of gyration
      from the geometry's centre of mass; geometry that cannot be computed (an open mesh, a
      missing file);
    - info: a link without an inertial (massless in URDF; inferred from the geoms in MJCF);
    - ok: nothing found.

    The geometry is the link's collision geometry (``geometry="visual"`` for its visual one;
    a link without collision geometry uses its visual one). Where the geometry can be
    computed, a finding carries the corrected inertial (``Finding.corrected``: the geometry's,
    at the declared mass, or at ``density`` when the declared mass is unusable).

    Parameters
    ----------
    path : str or os.PathLike
        A URDF (root ``<robot>``) or MJCF (root ``<mujoco>``) file.
    rtol : float
        Relative tolerance of the comparison with the geometry (default 0.25: real links are
        not uniform, so only a gross disagreement is reported).
    geometry : {"collision", "visual"}
        The URDF geometry compared with (MJCF: the geoms in the inertia group range).
    density : float, optional
        Density for the corrected inertial of a link whose declared mass is unusable, and for
        links without an inertial.

    Returns
    -------
    list[Finding]
        At least one per link, in the file's order.

    Raises
    ------
    FileNotFoundError, polhode.errors.FileFormatError
        The file cannot be read (a broken inertial is a finding, not an error).

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> urdf = '''<robot name="r"><link name="bad"><inertial><mass value="1"/>
    ...   <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"/></inertial></link></robot>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(urdf)
    >>> [(f.link, f.severity, f.check) for f in ph.io.audit(path)]
    [('bad', 'error', 'triangle_inequality')]
    """
    path = _fspath(path)
    tolerance = as_scalar("rtol", rtol)
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise ArgumentError(f"Expected `rtol` to be positive, got {tolerance}.", argument="rtol")
    rho, _ = _density_or_mass(density, None, required=False)
    if geometry not in ("collision", "visual"):
        raise ArgumentError(
            f"Expected `geometry` to be 'collision' or 'visual', got {geometry!r}.",
            argument="geometry",
        )
    fmt = _format_of(path)
    if fmt == "urdf":
        links = _urdf_links(path, geometry, "all")
        kind = "link"
    else:
        links, _ = _mjcf_links(path)
        kind = "body"
    findings: list[Finding] = []
    for link in links:
        findings.extend(_audit_link(link, kind, fmt, tolerance, rho))
    return findings
