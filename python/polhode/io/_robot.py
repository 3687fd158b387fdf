"""What the robot readers return and how they put it together: the links read as bodies, the
massless frames, the links left out (named in one warning), and with ``merge_fixed`` one body
per moving part (each link fused, through its chain of fixed joints, into the nearest link that
moves or is a root)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Mapping

import numpy as np
from numpy.typing import NDArray

from polhode.bodies import Body
from polhode.errors import FileFormatError, PolhodeError, RobotFileWarning
from polhode.io._links import Inertial, Link, geometry_body, placed

__all__ = ["Links", "MJMINVAL", "assemble", "inertial_check", "part_roots", "to_root"]

#: MuJoCo's mjMINVAL: a moving body whose mass or a principal moment is below it is refused
#: ("mass and inertia of moving bodies must be larger than mjMINVAL").
MJMINVAL = 1e-15


class Links(dict[str, Body]):
    """What :func:`polhode.io.read_urdf` and :func:`polhode.io.read_mjcf` return:
    ``{link: Body}`` (each in its link's (MJCF: body's) frame, or with ``merge_fixed=True`` one
    per moving part, in the frame of the part's first link), a dict in the file's order, with
    what was not read as a body.

    Attributes
    ----------
    path : str
        The file.
    frames : dict[str, str]
        The massless links (no ``<inertial>``, or mass 0) that a simulator takes as frames: on
        a fixed joint, the root, or a moving link whose part carries mass on its fixed links;
        ``{link: why}``.
    left_out : dict[str, str]
        The links that have no body because the file gives them none a simulator accepts, and
        why (the field and the check that failed): a tensor that is not positive semidefinite or
        breaks the triangle inequality, a negative mass, a moving link without mass, an
        inertial that cannot be read. The :class:`polhode.errors.RobotFileWarning` of the call
        names the same links.
    merged : dict[str, str]
        With ``merge_fixed=True``: ``{link: the part it was fused into}`` for every link on a
        chain of fixed joints (empty otherwise; an MJCF body whose mass MuJoCo drops with the
        world's is merged into ``"world"``).
    notes : dict[str, list[str]]
        What the simulator does to a link that a reader of the file should know (MJCF: a
        geom's mass dropped, a negative mass raised to 0, a mesh that is not closed).

    Examples
    --------
    >>> import os, tempfile, warnings
    >>> import polhode as ph
    >>> urdf = '''<robot name="r">
    ...   <link name="base"/>
    ...   <link name="arm"><inertial><mass value="2"/>
    ...     <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
    ...   <link name="tool0"/>
    ...   <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
    ...     <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    ...   <joint name="flange" type="fixed"><parent link="arm"/><child link="tool0"/></joint>
    ... </robot>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(urdf)
    >>> links = ph.io.read_urdf(path)
    >>> list(links), sorted(links.frames), links.left_out
    (['arm'], ['base', 'tool0'], {})
    """

    path: str
    frames: dict[str, str]
    left_out: dict[str, str]
    merged: dict[str, str]
    notes: dict[str, list[str]]

    def __init__(
        self,
        bodies: Mapping[str, Body] | Iterable[tuple[str, Body]] = (),
        *,
        path: str = "",
        frames: Mapping[str, str] | None = None,
        left_out: Mapping[str, str] | None = None,
        merged: Mapping[str, str] | None = None,
        notes: Mapping[str, Iterable[str]] | None = None,
    ):
        super().__init__(bodies)
        self.path = path
        self.frames = dict(frames or {})
        self.left_out = dict(left_out or {})
        self.merged = dict(merged or {})
        self.notes = {k: list(v) for k, v in (notes or {}).items()}


def inertial_check(inertial: Inertial) -> tuple[str, str, str] | None:
    """``(check, field, message)`` for a declared inertial that no body has (a simulator
    refuses it or the value is impossible), else None. ``check`` is ``"mass"`` (negative or
    not finite), ``"non_finite"``, ``"positive_definite"`` or ``"triangle_inequality"``. A mass
    of 0 passes here (a frame, or a moving link without mass: the joint decides)."""
    mass_field = inertial.field.split(".")[0] + ".mass"
    m = inertial.mass
    if not math.isfinite(m):
        return "mass", mass_field, f"the mass {m} is not finite."
    if m < 0:
        return "mass", mass_field, f"the mass {m:g} is negative: no body has a negative mass."
    tensor = inertial.inertia
    if not np.all(np.isfinite(tensor)):
        return (
            "non_finite",
            inertial.field,
            f"the inertia tensor has entries that are not finite: {tensor.tolist()}.",
        )
    if m == 0:
        return None
    try:
        Body.from_inertia(m, tensor, inertial.center_of_mass)
    except PolhodeError as error:
        if error.argument == "center_of_mass":
            field = inertial.field.split(".")[0] + ".origin"
            return "non_finite", field, error.message
        moments = np.linalg.eigvalsh(tensor)
        largest = float(np.max(np.abs(moments)))
        shown = ", ".join(f"{x:.4g}" for x in moments)
        if moments[0] < -16 * np.finfo(float).eps * largest:
            return (
                "positive_definite",
                inertial.field,
                f"the inertia tensor is not positive semidefinite: principal moments {shown} "
                "(one is negative).",
            )
        excess = (moments[2] - moments[0] - moments[1]) / moments[2]
        return (
            "triangle_inequality",
            inertial.field,
            f"principal moments {shown} break the triangle inequality I1 + I2 >= I3 (I3 "
            f"exceeds I1 + I2 by {excess:.3g} of I3): no mass distribution has them.",
        )
    return None


def part_roots(links: list[Link]) -> dict[str, str]:
    """``{link: the first link of its moving part}``: up its chain of fixed joints to a link
    that moves or is a root."""
    by_name = {link.name: link for link in links}
    roots: dict[str, str] = {}
    for link in links:
        chain = []
        current = link
        while current.joint == "fixed" and current.parent in by_name:
            if current.name in roots:
                break
            chain.append(current.name)
            current = by_name[current.parent]
        root = roots.get(current.name, current.name)
        for name in chain:
            roots[name] = root
        roots[current.name] = root
    return roots


def to_root(
    links: list[Link], roots: Mapping[str, str]
) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """``{link: (R, p)}``: each link's frame in its part's first link's frame, ``x_root = R
    x_link + p``, composed along the chain of fixed joints (``(R1, p1)(R2, p2) = (R1 R2,
    R1 p2 + p1)``, from the root down)."""
    by_name = {link.name: link for link in links}
    out: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}

    def placement(name: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        if name in out:
            return out[name]
        link = by_name[name]
        if roots[name] == name or link.origin is None or link.parent is None:
            result = (np.eye(3), np.zeros(3))
        else:
            r1, p1 = placement(link.parent)
            r2, p2 = link.origin
            result = (r1 @ r2, r1 @ p2 + p1)
        out[name] = result
        return result

    for link in links:
        placement(link.name)
    return out


def _fail(path: str, kind: str, name: str, field: str, message: str) -> FileFormatError:
    return FileFormatError(
        f"{path}: {kind} {name!r}: {field}: {message}", path=path, link=name, field=field
    )


def assemble(
    path: str,
    kind: str,
    links: list[Link],
    density: float | None,
    mass: float | None,
    *,
    strict: bool,
    merge_fixed: bool,
    notes: Iterable[tuple[str, str]] = (),
    stacklevel: int = 3,
) -> Links:
    """The result of a robot reader from its links: each link's body (its declared inertial;
    without one, its geometry at ``density``, or at one density giving the links without an
    inertial the total ``mass``), the massless frames, the links left out with why, and with
    ``merge_fixed`` one body per moving part. ``strict`` raises the first of ``notes``
    (file-level ``(field, remark)``), then the first link left out, as a FileFormatError;
    otherwise they are named in one RobotFileWarning."""
    own: dict[str, Body] = {}
    derived: dict[str, Body] = {}
    massless: dict[str, str] = {}
    refused: dict[str, tuple[str, str]] = {}  # link: (field, why)
    for link in links:
        if link.problem is not None:
            refused[link.name] = link.problem
            continue
        if link.inertial is not None:
            found = inertial_check(link.inertial)
            if found is not None:
                refused[link.name] = (found[1], found[2])
            elif link.inertial.mass == 0:
                massless[link.name] = "mass 0"
            else:
                own[link.name] = Body.from_inertia(
                    link.inertial.mass, link.inertial.inertia, link.inertial.center_of_mass
                )
            continue
        if density is not None or mass is not None:
            try:
                body = geometry_body(link)
            except (FileFormatError, FileNotFoundError) as error:
                field = getattr(error, "field", None) or "geometry"
                refused[link.name] = (field, _message(error, path, kind, link.name, field))
                continue
            if body is not None:
                derived[link.name] = body
                continue
        massless[link.name] = "no <inertial>"
    if mass is not None and derived:
        volume = math.fsum(b.mass for b in derived.values())
        derived = {k: b.scaled(mass_scale=mass / volume) for k, b in derived.items()}
    elif density is not None:
        derived = {k: b.scaled(mass_scale=density) for k, b in derived.items()}
    own.update(derived)

    roots = part_roots(links)
    members: dict[str, list[str]] = {}
    for link in links:
        members.setdefault(roots[link.name], []).append(link.name)
    frames: dict[str, str] = {}
    for link in links:
        why = massless.get(link.name)
        if why is None:
            continue
        if link.joint == "root":
            frames[link.name] = f"{why}: the root"
        elif link.joint == "fixed":
            frames[link.name] = f"{why}: on a fixed joint to {link.parent!r}"
        else:
            carriers = [n for n in members[roots[link.name]] if n in own and n != link.name]
            if carriers:
                frames[link.name] = (
                    f"{why}: a moving link whose part carries mass on its fixed links "
                    + ", ".join(repr(n) for n in carriers)
                )
            else:
                field = "inertial" if why == "no <inertial>" else f"{_inertial_tag(link)}.mass"
                refused[link.name] = (
                    field,
                    f"a moving link without mass ({why}, and no link fixed to it has any): "
                    "simulators refuse it (MuJoCo: 'mass and inertia of moving bodies must be "
                    "larger than mjMINVAL') or give it a floor.",
                )
    order = [link.name for link in links]
    left_out = {n: f"{refused[n][0]}: {refused[n][1]}" for n in order if n in refused}
    if strict:
        for field, message in notes:
            raise FileFormatError(f"{path}: {field}: {message}", path=path, field=field)
        for name in order:
            if name in refused:
                raise _fail(path, kind, name, *refused[name])
    remarks = [message for _, message in notes]
    if left_out:
        count = len(left_out)
        remarks.append(
            f"{count} {kind}{'' if count == 1 else 's'} left out: "
            + "; ".join(f"{n!r} ({why})" for n, why in left_out.items())
        )
    if remarks:
        warnings.warn(
            RobotFileWarning(f"{path}: " + " ".join(remarks), path=path, links=left_out),
            stacklevel=stacklevel,
        )
    if not merge_fixed:
        return Links(
            ((n, own[n]) for n in order if n in own),
            path=path,
            frames=frames,
            left_out=left_out,
        )
    placements = to_root(links, roots)
    bodies: dict[str, Body] = {}
    merged: dict[str, str] = {}
    for root, names in members.items():
        parts = []
        for name in names:
            if name != root:
                merged[name] = root
            if name in own:
                rotation, offset = placements[name]
                parts.append(placed(own[name], rotation, offset))
        if parts:
            bodies[root] = sum(parts[1:], parts[0])
        elif root not in left_out and root not in frames:
            frames[root] = "a part without mass"
    return Links(
        ((n, bodies[n]) for n in order if n in bodies),
        path=path,
        frames=frames,
        left_out=left_out,
        merged=merged,
    )


def _inertial_tag(link: Link) -> str:
    return link.inertial.field.split(".")[0] if link.inertial is not None else "inertial"


def _message(error: BaseException, path: str, kind: str, name: str, field: str) -> str:
    """An error's message without what the warning says already: the robot file's path, the
    link's name and the field (a mesh file's path stays)."""
    text = getattr(error, "message", None) or str(error)
    for prefix in (f"{path}: ", f"{kind} {name!r}: ", f"{field}: "):
        if text.startswith(prefix):
            text = text[len(prefix) :]
    return text.replace(f"{kind} {name!r}: ", "", 1)
