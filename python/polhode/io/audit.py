"""The audit of a robot description: every link's declared inertial against what simulators
accept, against physics and against the link's own geometry."""

from __future__ import annotations

import itertools
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import ROUND_CEILING, ROUND_FLOOR, ROUND_HALF_EVEN, Decimal
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_scalar, density_or_mass
from polhode._files import fspath
from polhode._formats import fixed_axis_rpy
from polhode.bodies import Body
from polhode.errors import ArgumentError
from polhode.io._links import Link, format_of, geometry_body, placed
from polhode.io._robot import MJMINVAL, inertial_check, part_roots, to_root
from polhode.io.mjcf import mjcf_links
from polhode.io.urdf import urdf_links

__all__ = ["CHECKS", "Finding", "audit"]

#: Every check of :func:`audit`, with the severities it can have and what it means.
CHECKS = {
    "malformed": ("error", "the inertial cannot be read (simulators refuse the file)"),
    "mass": ("error", "a negative or non-finite mass; mass 0 on a moving part"),
    "non_finite": ("error", "a tensor or centre of mass that is not finite"),
    "positive_definite": ("error", "a tensor that is not positive semidefinite"),
    "triangle_inequality": ("error", "principal moments that break I1 + I2 >= I3"),
    "no_inertial": ("error, info", "a moving link without an inertial (error if nothing fixed "
                    "to it has mass); MJCF: inferred from the geoms (info)"),
    "moving_part": ("error", "a moving part with a principal moment below MuJoCo's mjMINVAL"),
    "frame": ("info", "a massless link on a fixed joint or the root"),
    "point_mass": ("info", "a mass with a zero tensor where it does no harm"),
    "small_moment": ("warning", "a principal moment below 1e-6 of the largest"),
    "units": ("warning", "a mass or tensor off by a power of 1000 (grams, millimetres)"),
    "geometry": ("warning, info", "the tensor differs from the link's geometry's (info when "
                 "only part of the geometry could be computed)"),
    "products_swapped": ("warning", "products of inertia in the wrong places"),
    "products_sign": ("warning", "products of inertia of the wrong sign"),
    "mirrored": ("warning", "the tensor of the link's mirror image (left for right)"),
    "about_origin": ("warning", "the tensor about the link origin, not the centre of mass"),
    "parallel_axis": ("warning", "parts summed without their parallel-axis terms"),
    "origin_far": ("warning, info", "the centre of mass far from the geometry"),
    "geometry_error": ("warning, info", "geometry that cannot be computed (warning: a missing "
                       "file; info: a format polhode does not read, an open mesh)"),
    "ok": ("ok", "nothing found"),
}  # fmt: skip


@dataclass(frozen=True)
class Finding:
    """One result of :func:`audit` about one link: at most one per link and check.

    Attributes
    ----------
    link : str
        The link (URDF) or body (MJCF).
    severity : str
        ``"error"`` (a simulator refuses the model, or the value is physically impossible),
        ``"warning"`` (plausible but suspicious), ``"info"`` (a frame or a note) or ``"ok"``.
    check : str
        Which check (:data:`polhode.io.AUDIT_CHECKS` lists them): ``"malformed"``,
        ``"mass"``, ``"non_finite"``, ``"positive_definite"``, ``"triangle_inequality"``,
        ``"no_inertial"``, ``"moving_part"``, ``"frame"``, ``"point_mass"``,
        ``"small_moment"``, ``"units"``, ``"geometry"`` (the declared tensor disagrees with the
        link's geometry) or the cause found for it (``"products_swapped"``,
        ``"products_sign"``, ``"mirrored"``, ``"about_origin"``, ``"parallel_axis"``),
        ``"origin_far"``,
        ``"geometry_error"``, or ``"ok"``; a reader may add its own (MJCF).
    message : str
        What is wrong, with the numbers.
    corrected : str or None
        A corrected ``<inertial>`` element (URDF or MJCF, as the file) from the link's geometry
        with its declared mass, rounded to the digits that matter, where one can be computed.

    Examples
    --------
    >>> from polhode.io import Finding
    >>> f = Finding("forearm", "error", "mass", "<mass value> is -1: no body has it.", None)
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


def _fmt(values: Any) -> str:
    return "(" + ", ".join(f"{float(v):.4g}" for v in np.asarray(values).ravel()) + ")"


# --- the corrected inertial, to the digits that matter -------------------------------------


def _rounded(x: float, exponent: int, rounding: str = ROUND_HALF_EVEN) -> str:
    """``x`` to a multiple of ``10**exponent``, as the shortest decimal ("0" below half a
    step; ``ROUND_CEILING``/``ROUND_FLOOR`` for bounds that must hold)."""
    d = Decimal(repr(float(x))).quantize(Decimal(1).scaleb(exponent), rounding=rounding)
    if d == 0:
        return "0"
    d = d.normalize()
    if d == d.to_integral_value() and abs(d) < Decimal(10) ** 15:
        return str(int(d))
    return format(d, "g").replace("E", "e")


def _exponent(size: float, digits: int = 6) -> int:
    """The power of ten that keeps ``digits`` significant digits of ``size``."""
    return math.floor(math.log10(size)) - digits + 1 if size > 0 else 0


def _inertial_text(body: Body, fmt: str) -> str:
    """The body's ``<inertial>`` (URDF) or MJCF ``<inertial/>`` in principal form, rounded to
    six significant digits of its scales (within 5e-6 of each): the mass; the centre of mass
    on the scale of the body's size (its radius of gyration, or its distance from the origin if
    larger); the angles to 1e-6 rad; the moments on the scale of the largest (for a flat body,
    whose I1 + I2 = I3, the two
    smaller rounded up and the largest down, so that I1 + I2 >= I3 still holds). Not the 17
    digits of round-off: an angle or a coordinate of 9.6e-20 next to sizes of 0.1 is 0."""
    p = body.principal()
    moments = p.moments
    gyration = math.sqrt(max(float(moments.sum()), 0.0) / (2 * body.mass))
    size = max(gyration, float(np.linalg.norm(body.center_of_mass)))
    length = _exponent(size)
    mass = _rounded(body.mass, _exponent(body.mass))
    xyz = " ".join(_rounded(float(c), length) for c in body.center_of_mass)
    scale = _exponent(float(moments[2]))
    i1, i2, i3 = (_rounded(float(m), scale) for m in moments)
    if Decimal(i1) + Decimal(i2) < Decimal(i3):  # a flat body: keep I1 + I2 >= I3 true
        i1, i2 = (_rounded(float(m), scale, ROUND_CEILING) for m in moments[:2])
        i3 = _rounded(float(moments[2]), scale, ROUND_FLOOR)
    if fmt == "urdf":
        rpy = " ".join(_rounded(a, -6) for a in fixed_axis_rpy(p.axes))
        return (
            "<inertial>\n"
            f'  <origin xyz="{xyz}" rpy="{rpy}"/>\n'
            f'  <mass value="{mass}"/>\n'
            f'  <inertia ixx="{i1}" ixy="0" ixz="0" iyy="{i2}" iyz="0" izz="{i3}"/>\n'
            "</inertial>"
        )
    w_last = p.rotation.as_quat()
    quat = " ".join(_rounded(float(q), -7) for q in (w_last[3], *w_last[:3]))
    return f'<inertial pos="{xyz}" quat="{quat}" mass="{mass}" diaginertia="{i1} {i2} {i3}"/>'


# --- what the links around a link say ------------------------------------------------------


class _Robot:
    """The links of a file with their bodies (declared, or for MJCF inferred from the geoms),
    their moving parts and the placements of each link in its part."""

    def __init__(self, links: list[Link], fmt: str, infer: bool):
        self.fmt = fmt
        self.links = links
        self.roots = part_roots(links)
        self.members: dict[str, list[str]] = {}
        for link in links:
            self.members.setdefault(self.roots[link.name], []).append(link.name)
        self.own: dict[str, Body] = {}
        #: MJCF bodies whose inertial MuJoCo infers from geoms that polhode cannot compute
        #: (a mesh it does not read, a missing file): their mass is unknown here, so nothing is
        #: concluded from it.
        self.unknown: set[str] = set()
        for link in links:
            body = _declared(link)
            if body is None and link.inertial is None and fmt == "mjcf" and infer:
                if any(p.error is not None for p in link.parts):
                    self.unknown.add(link.name)
                    continue
                body = geometry_body(link, file_density=True)
            if body is not None:
                self.own[link.name] = body
        self.placements = to_root(links, self.roots)

    def carriers(self, link: Link) -> list[str]:
        """The other links of the link's part that have mass (or may have: unknown)."""
        return [
            n
            for n in self.members[self.roots[link.name]]
            if (n in self.own or n in self.unknown) and n != link.name
        ]

    def part(self, link: Link) -> Body | None:
        """The moving part whose first link is ``link``: its links' bodies in its frame."""
        bodies = []
        for name in self.members[self.roots[link.name]]:
            if name in self.own:
                rotation, offset = self.placements[name]
                bodies.append(placed(self.own[name], rotation, offset))
        return sum(bodies[1:], bodies[0]) if bodies else None

    def accepted(self, link: Link) -> bool:
        """Whether MuJoCo accepts the moving body: its mass and each principal moment at least
        mjMINVAL; for URDF (whose importer fuses fixed links, fusestatic) the part's, for MJCF
        the body's own or one of its jointless descendants' (checked one by one, as MuJoCo)."""
        if any(n in self.unknown for n in self.members[self.roots[link.name]]):
            return True  # a mass polhode cannot compute: MuJoCo's to judge
        if self.fmt == "urdf":
            candidates = [self.part(link)]
        else:
            candidates = [self.own.get(n) for n in self.members[self.roots[link.name]]]
        return any(
            b is not None and b.mass >= MJMINVAL and b.principal().moments[0] >= MJMINVAL
            for b in candidates
        )


def _declared(link: Link) -> Body | None:
    """The body of a link's declared inertial if a simulator accepts it (mass > 0)."""
    i = link.inertial
    if link.problem is not None or i is None or inertial_check(i) is not None or i.mass == 0:
        return None
    return Body.from_inertia(i.mass, i.inertia, i.center_of_mass)


def _where(link: Link) -> str:
    if link.joint == "root":
        return "as the root"
    if link.parent is None:
        return "welded to the world"
    return f"on a fixed joint to {link.parent!r}"


# --- one link --------------------------------------------------------------------------------


def _audit_link(
    link: Link, robot: _Robot, kind: str, rtol: float, density: float | None
) -> list[Finding]:
    """The findings about one link (see :func:`audit`): at most one per check."""
    fmt = robot.fmt
    findings: list[Finding] = []

    def add(severity: str, check: str, message: str, corrected: str | None = None) -> None:
        findings.append(Finding(link.name, severity, check, message, corrected))

    for note in link.notes:  # what only the format's reader knows
        add(note.severity, note.check, note.message, note.corrected)

    # The geometry at unit density: the parts that could be computed, and those that could not.
    computed = [p for p in link.parts if p.body is not None]
    failed = [p for p in link.parts if p.error is not None]
    geometry = sum((p.body for p in computed[1:]), computed[0].body) if computed else None
    partial = ""
    if failed:
        missing = any(isinstance(p.error, FileNotFoundError) or "not found" in str(p.error)
                      for p in failed)  # fmt: skip
        listed = "; ".join(f"{p.name}: {_short(p.error)}" for p in failed[:3])
        more = f" (and {len(failed) - 3} more)" if len(failed) > 3 else ""
        total = len(computed) + len(failed) + sum(
            1 for p in link.parts if p.body is None and p.error is None
        )
        if geometry is not None:
            partial = f" (compared with {len(computed)} of {total} geometry parts only)"
            after = f"the comparison with the geometry uses the other {len(computed)} only."
        else:
            after = "the inertial is not compared with the geometry."
        add(
            "warning" if missing else "info",
            "geometry_error",
            f"{len(failed)} of {total} geometry parts cannot be computed: {listed}{more}; {after}",
        )

    def at_density(what: Body | None) -> str | None:
        if what is None or partial or density is None:
            return None
        return _inertial_text(what.scaled(mass_scale=density), fmt)

    if link.problem is not None:
        field, message = link.problem
        add(
            "error",
            "malformed",
            f"{field}: {message} Simulators refuse the file (MuJoCo, urdfdom).",
            at_density(geometry),
        )
        return findings

    massless = link.inertial is None or (
        link.inertial.mass == 0 and inertial_check(link.inertial) is None
    )
    what = "no <inertial>" if link.inertial is None else "mass 0"
    if massless:
        inferred = robot.own.get(link.name) if link.inertial is None else None
        if link.name in robot.unknown:
            add(
                "info",
                "no_inertial",
                "no <inertial>: MuJoCo infers it from geoms that polhode cannot compute here.",
            )
        elif inferred is not None:  # MJCF: MuJoCo infers the inertial from the geoms
            add(
                "info",
                "no_inertial",
                f"no <inertial>: inferred from the geoms, mass {inferred.mass:.6g}.",
            )
        elif link.joint != "moving":
            add("info", "frame", f"{what}: a frame (massless) {_where(link)}.")
        elif robot.carriers(link):
            carriers = ", ".join(repr(n) for n in robot.carriers(link))
            add(
                "info",
                "no_inertial" if link.inertial is None else "mass",
                f"{what} on a moving joint: massless, its part's mass is on its fixed links "
                f"{carriers} (simulators accept it).",
            )
        else:
            hint = ""
            if geometry is not None and fmt == "urdf" and link.inertial is None:
                hint = (
                    " (MuJoCo's URDF importer would give it its collision geometry's mass at "
                    f"1000 kg/m^3, {1000 * geometry.mass:.4g} kg)"
                )
            add(
                "error",
                "no_inertial" if link.inertial is None else "mass",
                f"{what} on a moving joint, and nothing fixed to it has mass: a moving body has "
                f"mass. MuJoCo refuses it ('mass and inertia of moving bodies must be larger "
                f"than mjMINVAL'){hint}; Pinocchio and Drake give it a singular mass matrix.",
                at_density(geometry),
            )
        if link.inertial is None:
            return findings

    i = link.inertial
    assert i is not None
    m, com, tensor = i.mass, i.center_of_mass, i.inertia
    # The geometry with the declared mass (or the given density), for the comparisons.
    reference = None
    if geometry is not None and not partial:
        if math.isfinite(m) and m > 0:
            reference = geometry.scaled(mass_scale=m / geometry.mass)
        elif density is not None:
            reference = geometry.scaled(mass_scale=density)
    corrected = None if reference is None else _inertial_text(reference, fmt)

    found = inertial_check(i)
    if found is not None:
        check, field, message = found
        cause = ""
        if check in ("positive_definite", "triangle_inequality") and reference is not None:
            # An exporter's mistake can make a tensor impossible: undoing it may explain it.
            mismatch = _relative(tensor, reference.inertia)
            diagnosis = _diagnose(tensor, reference, link, m, rtol, mismatch)
            if diagnosis is not None:
                cause = f" The cause ({diagnosis[0]}): {diagnosis[1]}"
        add("error", check, f"{field}: {message}{cause}", corrected)
        return findings
    if m == 0:
        return findings

    moments = np.linalg.eigvalsh(tensor)
    error_found = False
    if link.joint == "moving" and not robot.accepted(link):
        error_found = True
        part = robot.part(link)
        shown = _fmt(part.principal().moments) if part is not None else "(none)"
        add(
            "error",
            "moving_part",
            f"the moving part's principal moments {shown} (this link with what is fixed to it)"
            f" include one below MuJoCo's mjMINVAL = 1e-15: MuJoCo refuses it ('mass and "
            "inertia of moving bodies must be larger than mjMINVAL'), and a rotation about that "
            "axis has no inertia.",
            corrected,
        )
    if not np.any(tensor):
        if not error_found:
            where = _where(link) if link.joint != "moving" else "on a moving joint"
            add(
                "info",
                "point_mass",
                f"a point mass ({m:.6g}, zero tensor) {where}: fine where it is fused into "
                "its part, which has inertia from its other links or from the offset.",
            )
    elif moments[0] <= 1e-6 * moments[2] and not error_found:
        add(
            "warning",
            "small_moment",
            f"the smallest principal moment {moments[0]:.3g} is {moments[0] / moments[2]:.2g} "
            "of the largest (a rod): near-singular for a simulator.",
            corrected,
        )

    if geometry is not None and geometry.mass > 0:
        _compare(link, m, com, tensor, geometry, reference, partial, rtol, fmt, add)
    if not findings:
        add("ok", "ok", "consistent" + (" with its geometry." if reference is not None else "."))
    return findings


def _short(error: BaseException | None) -> str:
    text = str(error)
    for cut in (": link ", "mesh '"):
        if cut in text:
            text = text[text.index(cut) :]
    return text if len(text) <= 160 else text[:157] + "..."


# --- against the geometry --------------------------------------------------------------------

#: Densities (kg/m^3, SI as URDF is) that no part of a robot has: below, lighter than air;
#: above, heavier than osmium (22 590).
_LIGHTEST, _HEAVIEST = 1.0, 1e5


def _compare(
    link: Link,
    m: float,
    com: NDArray[np.float64],
    tensor: NDArray[np.float64],
    geometry: Body,
    reference: Body | None,
    partial: str,
    rtol: float,
    fmt: str,
    add: Any,
) -> None:
    """The declared inertial against the link's geometry at the declared mass: units, the
    centre of mass, the tensor, and a known mistake that explains a difference."""
    if reference is None:  # partial geometry, or no usable mass
        reference = geometry.scaled(mass_scale=m / geometry.mass) if m > 0 else None
        if reference is None:
            return
    severity = "info" if partial else "warning"
    target = reference.inertia
    mismatch = _relative(tensor, target)
    corrected = None if partial else _inertial_text(reference, fmt)

    units = None if partial else _units(m, tensor, geometry, reference, rtol)
    if units is not None:
        text, mass_scale = units
        fixed = reference.scaled(mass_scale=mass_scale)
        add("warning", "units", text, _inertial_text(fixed, fmt))
    distance = float(np.linalg.norm(com - reference.center_of_mass))
    gyration = math.sqrt(max(float(np.trace(reference.second_moment)), 0.0) / reference.mass)
    if distance > 2 * gyration:
        add(
            severity,
            "origin_far",
            f"the centre of mass {_fmt(com)} is {distance:.3g} from the geometry's "
            f"{_fmt(reference.center_of_mass)}, {distance / gyration:.3g} times the "
            f"geometry's radius of gyration {gyration:.3g}: outside the geometry{partial}.",
            corrected,
        )
    if units is not None:
        return
    diagnosis = None if partial else _diagnose(tensor, reference, link, m, rtol, mismatch)
    if diagnosis is not None:
        check, text = diagnosis
        add("warning", check, text, corrected)
    elif mismatch > rtol:
        add(
            severity,
            "geometry",
            f"the inertia tensor differs from that of the link's geometry at the same mass by "
            f"{mismatch:.3g} (relative, Frobenius; tolerance {rtol:g}): principal moments "
            f"{_fmt(np.linalg.eigvalsh(tensor))}, geometry {_fmt(np.linalg.eigvalsh(target))}"
            f"{partial}.",
            corrected,
        )


def _units(
    m: float, tensor: NDArray[np.float64], geometry: Body, reference: Body, rtol: float
) -> tuple[str, float] | None:
    """A mass or tensor off by a power of 1000 (URDF is SI: kg, m): the message, and the factor
    the declared mass takes to be right; None unless the evidence holds.

    - The tensor is 10^k times the geometry's at the declared mass (k = -6, -3, 3, 6, 9) and,
      divided by 10^k, agrees with it within ``rtol`` (shape and size: a unit changes no
      ratio): grams for kilograms in the mass (-3) or in the tensor (3), millimetres for metres
      in the tensor (6, 9 with grams), or a geometry 1000 times too large (-6: a mesh in
      millimetres without ``scale="0.001"``, then also lighter than air);
    - the tensor agrees with the geometry at the declared mass (so the geometry has the link's
      size) and the mass over its volume is a density above 1e5 kg/m^3 (heavier than any
      material) that is plausible at 1/1000: mass and tensor in grams."""
    rho = m / geometry.mass
    target = reference.inertia
    scale = float(np.trace(tensor)) / float(np.trace(target))
    if scale <= 0:
        return None
    power = round(math.log10(scale) / 3) * 3
    if power == 0:
        if _relative(tensor, target) <= rtol and rho > _HEAVIEST and 30 <= rho / 1000 <= 3e4:
            return (
                f"the mass {m:.6g} over the geometry's volume {geometry.mass:.4g} m^3 is a "
                f"density of {rho:.4g} kg/m^3, heavier than any material, while the tensor "
                "agrees with the geometry at that mass: the mass and the tensor are in grams "
                f"(at {m / 1000:.6g} kg, {rho / 1000:.4g} kg/m^3).",
                1e-3,
            )
        return None
    if power not in (-6, -3, 3, 6, 9) or _relative(tensor / 10.0**power, target) > rtol:
        return None
    head = (
        f"the inertia tensor is {scale:.3g} times that of the link's geometry at the same mass "
        f"and, divided by 1e{power}, agrees with it"
    )
    if power == -3:
        return (
            f"{head}: the mass is in grams (at {m / 1000:.6g} kg the tensor matches; the "
            f"density is then {rho / 1000:.4g} kg/m^3).",
            1e-3,
        )
    if power == -6:
        light = rho < _LIGHTEST and 30 <= rho * 1e9 <= 3e4
        return (
            f"{head}: the geometry is 1000 times too large"
            + (
                f" (a density of {rho:.3g} kg/m^3, {rho * 1e9:.4g} at 1e-9 of the volume): a "
                'mesh in millimetres read without scale="0.001".'
                if light
                else " (a mesh in millimetres read as metres) or the tensor in m^2 for mm^2."
            ),
            1.0,
        )
    meaning = {
        3: "the tensor is in g m^2 (grams) while the mass is in kg",
        6: "the tensor is in kg mm^2 (millimetres for metres)",
        9: "the tensor is in g mm^2 (grams and millimetres)",
    }[power]
    return f"{head}: {meaning}.", 1.0


def _diagnose(
    tensor: NDArray[np.float64],
    reference: Body,
    link: Link,
    m: float,
    rtol: float,
    mismatch: float,
) -> tuple[str, str] | None:
    """A known exporter mistake that explains the difference with the geometry: undoing it
    brings the tensor within ``rtol`` of the geometry's (as close as a link that agrees) and
    three times closer than it was; or, for a tensor already within ``rtol``, within rtol/5
    and ten times closer (products of inertia are small next to the moments, so a swap can hide
    inside the tolerance)."""
    target = reference.inertia
    if mismatch > rtol:
        tight = min(rtol, mismatch / 3)
    else:
        tight = min(rtol / 5, mismatch / 10)
    products = [tensor[i, j] for i, j in _PRODUCTS]
    best: tuple[float, str, str] | None = None

    def consider(candidate: NDArray[np.float64], check: str, text: str) -> None:
        nonlocal best
        error = _relative(candidate, target)
        if error < tight and (best is None or error < best[0]):
            best = (error, check, text)

    if any(products):
        consider(
            _with_products(tensor, [-p for p in products]),
            "products_sign",
            "the products of inertia have the wrong sign: they are written as +sum m x y, "
            "the tensor elements are -sum m x y.",
        )
        for axis, name in enumerate("xyz"):
            # A mirror image in the plane normal to one axis: the two products with that axis
            # change sign (a left link's tensor given to the right one).
            flipped = [-p if axis in pair else p for p, pair in zip(products, _PRODUCTS,
                                                                     strict=True)]  # fmt: skip
            plane = "".join(a for a in "xyz" if a != name)
            signs = " and ".join(
                n for n, pair in zip(_PRODUCT_NAMES, _PRODUCTS, strict=True) if axis in pair
            )
            consider(
                _with_products(tensor, flipped),
                "mirrored",
                f"the tensor is that of the link's mirror image in the {plane} plane ({signs} "
                "of the wrong sign): a left link's inertial given to the right one, or the "
                "other way round.",
            )
        for order in itertools.permutations(range(3)):
            if order == (0, 1, 2):
                continue
            for sign in (1, -1):
                moved = [
                    f"{_PRODUCT_NAMES[k]} is written as {_PRODUCT_NAMES[order.index(k)]}"
                    for k in range(3)
                    if order.index(k) != k
                ]
                consider(
                    _with_products(tensor, [sign * products[k] for k in order]),
                    "products_swapped",
                    "the products of inertia are in the wrong places: "
                    + ", ".join(moved)
                    + (" (and of the wrong sign)" if sign < 0 else "")
                    + ".",
                )
    c = np.asarray(link.inertial.center_of_mass if link.inertial is not None else 0.0)
    if np.any(c):
        # Undone: the parallel-axis term about the link origin taken off again.
        shift = m * (float(c @ c) * np.eye(3) - np.outer(c, c))
        consider(
            tensor - shift,
            "about_origin",
            "the tensor is the geometry's inertia about the link origin, not about the centre "
            "of mass: the parallel-axis term m d^2 is included where it must not be.",
        )
    parts = [p.body for p in link.parts if p.body is not None]
    if len(parts) > 1:
        volume = math.fsum(b.mass for b in parts)
        summed = sum((b.inertia * (m / volume) for b in parts), np.zeros((3, 3)))
        # Undone: the parallel-axis terms of the parts added back.
        consider(
            tensor + (target - summed),
            "parallel_axis",
            f"the tensor is the sum of the {len(parts)} parts' inertias each about its own "
            "centre of mass: the parallel-axis terms m d^2 that move them to the link's centre "
            "of mass are missing.",
        )
    return None if best is None else (best[1], best[2])


def audit(
    path: str | os.PathLike[str],
    *,
    rtol: float = 0.25,
    geometry: str = "collision",
    density: float | None = None,
) -> list[Finding]:
    """Check every link's declared inertial of a URDF or MJCF file against what simulators
    accept, against physics and against the link's own geometry.

    The severities follow the simulators, link by link and joint by joint:

    - **error**: a simulator refuses the model or the value is physically impossible: an
      inertial that cannot be read; a negative mass; a tensor that is not positive
      semidefinite or breaks the triangle inequality I1 + I2 >= I3; a moving link with no mass
      (no inertial, or mass 0) when nothing fixed to it has any, or whose moving part (with
      its fixed links: MuJoCo's URDF importer fuses them) has a principal moment below
      MuJoCo's mjMINVAL = 1e-15 (MuJoCo: "mass and inertia of moving bodies must be larger
      than mjMINVAL");
    - **warning**: plausible but suspicious: a principal moment below 1e-6 of the largest; a
      mass or tensor off by a power of 1000 against the geometry (grams for kilograms,
      millimetres for metres: SI units assumed); a tensor that differs from that of the link's
      geometry, taken as uniform with the declared mass, by more than ``rtol`` (relative
      Frobenius norm), with the cause named where undoing a known exporter mistake makes it
      agree (products of inertia swapped or of the wrong sign, the tensor of the mirror image,
      the tensor about the link origin rather than the centre of mass, parts summed without
      their parallel-axis terms); a centre
      of mass more than twice the geometry's radius of gyration from the geometry's; a mesh
      file that is missing;
    - **info**: a frame (a massless link on a fixed joint, the root, or a moving link whose
      fixed links carry its part's mass); a point mass where it does no harm; geometry polhode
      cannot compute (a format it does not read, an open mesh), said once per link with the
      parts; MJCF: an inertial inferred from the geoms. A comparison with only part of a
      link's geometry (the rest could not be computed) is an info finding that says so;
    - **ok**: nothing found.

    One finding per link and check. The geometry is the link's collision geometry
    (``geometry="visual"`` for its visual one; a link without collision geometry uses its
    visual one). Where the geometry can be computed, a finding carries the corrected inertial
    (``Finding.corrected``: the geometry's, at the declared mass, or at ``density`` when the
    declared mass is unusable), rounded to six significant digits. A format's reader can add
    findings of its own (``Link.notes``: e.g. for MJCF, how MuJoCo's compiler changes a body's
    inertial). :data:`polhode.io.AUDIT_CHECKS` lists every check.

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
        The file cannot be read as a robot description (a broken inertial is a finding, not an
        error).

    Examples
    --------
    >>> import os, tempfile
    >>> import polhode as ph
    >>> urdf = '''<robot name="r"><link name="base"/>
    ...   <link name="bad"><inertial><mass value="1"/>
    ...   <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="3"/></inertial></link>
    ...   <joint name="j" type="continuous"><parent link="base"/><child link="bad"/></joint>
    ... </robot>'''
    >>> path = os.path.join(tempfile.mkdtemp(), "r.urdf")
    >>> with open(path, "w") as handle:
    ...     _ = handle.write(urdf)
    >>> [(f.link, f.severity, f.check) for f in ph.io.audit(path)]
    [('base', 'info', 'frame'), ('bad', 'error', 'triangle_inequality')]
    """
    path = fspath(path)
    tolerance = as_scalar("rtol", rtol)
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise ArgumentError(f"Expected `rtol` to be positive, got {tolerance}.", argument="rtol")
    rho, _ = density_or_mass(density, None, required=False)
    if geometry not in ("collision", "visual"):
        raise ArgumentError(
            f"Expected `geometry` to be 'collision' or 'visual', got {geometry!r}.",
            argument="geometry",
        )
    fmt = format_of(path)
    if fmt == "urdf":
        links = urdf_links(path, geometry, "all", origins=True)
        kind, infer = "link", False
    else:
        links, infer = mjcf_links(path)
        kind = "body"
    robot = _Robot(links, fmt, infer)
    findings: list[Finding] = []
    for link in links:
        findings.extend(_audit_link(link, robot, kind, tolerance, rho))
    return findings
