"""The audit of a robot description: every link's declared inertial against physics and
against the link's own geometry."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_scalar, density_or_mass
from polhode._files import fspath
from polhode.bodies import Body
from polhode.errors import ArgumentError
from polhode.io._links import Link, format_of, geometry_body
from polhode.io.mjcf import mjcf_links
from polhode.io.urdf import urdf_links

__all__ = ["Finding", "audit"]


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


def _audit_link(
    link: Link, kind: str, fmt: str, rtol: float, density: float | None
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
                inferred = geometry_body(link, file_density=True)
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
    link: Link,
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
        links = urdf_links(path, geometry, "all")
        kind = "link"
    else:
        links, _ = mjcf_links(path)
        kind = "body"
    findings: list[Finding] = []
    for link in links:
        findings.extend(_audit_link(link, kind, fmt, tolerance, rho))
    return findings
