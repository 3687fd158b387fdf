"""What the readers of robot descriptions share: a link's records (its declared inertial and
its geometry), the bodies made of them, and which format a file is."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._files import existing, require
from polhode.bodies import Body
from polhode.errors import ArgumentError, FileFormatError, PolhodeError

__all__ = [
    "Inertial",
    "Link",
    "Note",
    "Part",
    "declared_body",
    "format_of",
    "geometry_body",
    "placed",
    "resolve",
    "symmetric",
    "unit_volume",
]


@dataclass(frozen=True)
class Inertial:
    """A declared inertial in the link frame: mass, centre of mass, tensor about it."""

    mass: float
    center_of_mass: NDArray[np.float64]
    inertia: NDArray[np.float64]
    field: str  # the element the tensor came from, for messages


@dataclass(frozen=True)
class Part:
    """One geometry element of a link: a body of unit density placed in the link frame (or
    the error that prevented computing it), and - MJCF - the density the file gives it."""

    name: str
    body: Body | None
    error: Exception | None
    density: float = 1.0


@dataclass(frozen=True)
class Note:
    """Something a reader found about a link that :func:`polhode.io.audit` reports as a finding
    of its own (``severity``, ``check``, ``message``, ``corrected``): the hook through which a
    format's reader says what only it knows (e.g. how MuJoCo's compiler changes a body's
    inertial)."""

    severity: str
    check: str
    message: str
    corrected: str | None = None


@dataclass
class Link:
    """A link (URDF) or body (MJCF): its declared inertial, if any, its geometry, and how it
    hangs on its parent.

    ``joint`` is ``"root"`` (no parent), ``"fixed"`` (welded to its parent: a URDF fixed joint,
    an MJCF body without joints) or ``"moving"``; ``parent`` names the parent link, and
    ``origin`` is the (rotation, offset) of the link's frame in its parent's, ``x_parent = R
    x_link + p`` (None where unknown). ``problem`` is ``(field, message)`` when the declared
    inertial cannot be read at all (a missing ``<inertia>``, two ``<inertial>`` elements, a
    number that is not one); ``notes`` are findings for the audit."""

    name: str
    inertial: Inertial | None
    parts: list[Part]
    joint: str = "moving"
    parent: str | None = None
    origin: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
    problem: tuple[str, str] | None = None
    notes: list[Note] = field(default_factory=list)


def declared_body(path: str, kind: str, link: Link) -> Body:
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


def geometry_body(link: Link, file_density: bool = False) -> Body | None:
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


def resolve(
    path: str, kind: str, links: list[Link], density: float | None, mass: float | None
) -> dict[str, Body]:
    """Declared inertials as bodies; with ``density`` or a total ``mass`` (shared by volume),
    the other links from their geometry; in the file's order."""
    out: dict[str, Body] = {}
    derived: dict[str, Body] = {}
    for link in links:
        if link.inertial is not None:
            out[link.name] = declared_body(path, kind, link)
        elif density is not None or mass is not None:
            body = geometry_body(link)
            if body is not None:
                derived[link.name] = body
    if mass is not None and derived:
        volume = math.fsum(b.mass for b in derived.values())
        derived = {k: b.scaled(mass_scale=mass / volume) for k, b in derived.items()}
    elif density is not None:
        derived = {k: b.scaled(mass_scale=density) for k, b in derived.items()}
    out.update(derived)
    return {link.name: out[link.name] for link in links if link.name in out}


def placed(body: Body, rotation: NDArray[np.float64], offset: Any) -> Body:
    """``body`` rotated by ``rotation`` about its origin, then moved by ``offset``."""
    if not np.array_equal(rotation, np.eye(3)):
        body = body.rotated(rotation)
    offset = np.asarray(offset, dtype=float)
    return body.translated(offset) if np.any(offset) else body


def unit_volume(kind: str, sizes: Any, volume: Any) -> float:
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


def symmetric(tensor: NDArray[np.float64]) -> NDArray[np.float64]:
    """The mean of ``tensor`` and its transpose, without overflow near the largest double
    (a declared moment of 1e308 read as inf)."""
    with np.errstate(over="ignore"):
        mean = (tensor + tensor.T) / 2
    if np.all(np.isfinite(mean)) or not np.all(np.isfinite(tensor)):
        return mean
    return tensor / 2 + tensor.T / 2


def format_of(path: str) -> str:
    """'urdf' or 'mjcf', by the root element of the XML (undeclared namespace prefixes, such
    as Drake's ``drake:`` in URDF files, do not matter here)."""
    existing(path)
    etree = require("lxml.etree", "robots")  # a dependency of yourdfpy
    tag = None
    try:  # the first start tag only: the readers (lxml for URDF, MuJoCo for MJCF) judge the rest
        with open(path, "rb") as handle:
            for _, element in etree.iterparse(handle, events=("start",), recover=True):
                tag = element.tag
                break
    except etree.XMLSyntaxError as error:
        raise FileFormatError(f"{path}: not valid XML: {error}", path=path) from error
    if not isinstance(tag, str):
        raise FileFormatError(f"{path}: not valid XML: no root element.", path=path)
    if tag == "robot":
        return "urdf"
    if tag == "mujoco":
        return "mjcf"
    raise FileFormatError(
        f"{path}: expected a URDF (<robot>) or MJCF (<mujoco>) file, got <{tag}>.", path=path
    )


def xml_root(path: str) -> Any:
    """The root element of an XML file (lxml), comments left out. Undeclared namespace
    prefixes (``drake:acceleration`` without ``xmlns:drake``: Drake's extensions, which
    yourdfpy and MuJoCo read) and ``--`` inside a comment are not errors; anything else that is
    not well-formed XML (a truncated file, a tag that does not close) is a FileFormatError."""
    etree = require("lxml.etree", "robots")  # a dependency of yourdfpy

    parser = etree.XMLParser(remove_comments=True, recover=True)
    try:
        tree = etree.parse(path, parser)
    except etree.XMLSyntaxError as error:  # recover still gives up on some files
        raise FileFormatError(f"{path}: not valid XML: {error}", path=path) from error
    # Harmless: undeclared prefixes, and "--" inside a comment (read by tinyxml2, thus by
    # MuJoCo and ROS's urdfdom).
    fatal = [
        e
        for e in parser.error_log
        if e.domain_name != "NAMESPACE" and e.type_name != "ERR_HYPHEN_IN_COMMENT"
    ]
    root = tree.getroot()
    if fatal or root is None:
        first = fatal[0] if fatal else None
        where = f", line {first.line}, column {first.column}" if first is not None else ""
        what = first.message if first is not None else "no root element"
        raise FileFormatError(f"{path}: not valid XML: {what}{where}", path=path)
    return root
