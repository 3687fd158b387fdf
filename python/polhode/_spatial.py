"""Spatial inertia: the (6, 6) matrix of a body about a point, its inverse, and a body from one.

The work of :meth:`polhode.Body.spatial_inertia` and :meth:`polhode.Body.from_spatial_inertia`
(whose docstrings give the formulas), in Featherstone's block order (angular first), with
Pinocchio's (linear first) on request. The body type is passed in: :mod:`polhode.bodies`
imports this module.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_array, as_flag, as_scalar
from polhode.errors import ArgumentError, InertiaError, NonFiniteError, NonPositiveError

__all__ = ["cross_matrix", "from_spatial_inertia", "spatial_inertia"]


def cross_matrix(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """[v]: the matrix of the cross product, [v] w = v x w."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def spatial_inertia(body: Any, point: Any, inverse: Any, linear_first: bool) -> NDArray[np.float64]:
    """:meth:`polhode.Body.spatial_inertia` of ``body`` (its convention checked): the linear
    block first if ``linear_first`` (Pinocchio's order)."""
    inverse = as_flag("inverse", inverse)
    p = np.zeros(3) if point is None else as_array("point", point, (3,))
    m = body.mass
    c = body.center_of_mass - p
    cross = cross_matrix(c)
    out = np.empty((6, 6))
    if not inverse:
        out[:3, :3] = body.inertia_about(p)
        out[:3, 3:] = m * cross
        out[3:, :3] = m * cross.T
        out[3:, 3:] = m * np.eye(3)
    else:
        principal = body.principal()  # the core's solve at its own tolerance
        moments, axes = principal.moments, principal.axes
        if not moments[0] > 0:
            raise InertiaError(
                "Expected a body with positive principal moments for the inverse spatial "
                f"inertia, got {moments.tolist()}: the spatial inertia is singular.",
                argument="inverse",
            )
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            inv = (axes / moments) @ axes.T  # I_c^-1 from the principal axes
            inv = (inv + inv.T) / 2
            out[:3, :3] = inv
            out[:3, 3:] = -inv @ cross
            out[3:, :3] = cross @ inv
            lower = np.eye(3) / m - cross @ inv @ cross
            out[3:, 3:] = (lower + lower.T) / 2
        if not np.isfinite(out).all():
            raise InertiaError(
                "The inverse spatial inertia overflows double precision: the smallest "
                f"principal moment is {moments[0]:.6g} (mass {m:.6g}, centre of mass "
                f"{np.linalg.norm(c):.6g} from the point).",
                argument="inverse",
            )
    if linear_first:
        out = np.block([[out[3:, 3:], out[3:, :3]], [out[:3, 3:], out[:3, :3]]])
    return out


def from_spatial_inertia(
    body_type: Any, matrix: Any, point: Any, rtol: Any, linear_first: bool
) -> Any:
    """:meth:`polhode.Body.from_spatial_inertia` (its convention checked): a ``body_type`` from
    a spatial inertia, its linear block first if ``linear_first``."""
    s = as_array("matrix", matrix, (6, 6))
    tolerance = as_scalar("rtol", rtol)
    if not (math.isfinite(tolerance) and tolerance >= 0):
        raise ArgumentError(
            f"Expected `rtol` to be a finite number >= 0, got {tolerance}.", argument="rtol"
        )
    p = np.zeros(3) if point is None else as_array("point", point, (3,))
    if not np.all(np.isfinite(s)):
        raise NonFiniteError(
            "Expected `matrix` to be finite, got a NaN or an infinity.", argument="matrix"
        )
    if linear_first:
        s = np.block([[s[3:, 3:], s[3:, :3]], [s[:3, 3:], s[:3, :3]]])
    bound = tolerance * float(np.abs(s).max())
    asymmetry = float(np.abs(s - s.T).max())
    if asymmetry > bound:
        raise InertiaError(
            f"Expected `matrix` to be symmetric, got |S - S^T| up to {asymmetry:.3g} "
            f"(tolerance {bound:.3g}).",
            argument="matrix",
        )
    lower = s[3:, 3:]
    m = float(np.median(np.diag(lower)))  # exact when the three agree
    if not m > 0:
        raise NonPositiveError(
            f"Expected `matrix` to have a positive mass m in its m 1 block, got {m:g}.",
            argument="matrix",
        )
    if float(np.abs(lower - m * np.eye(3)).max()) > bound:
        raise InertiaError(
            "Expected the mass block of `matrix` to be m times the identity, got "
            f"{lower.tolist()}.",
            argument="matrix",
        )
    coupling = (s[:3, 3:] + s[3:, :3].T) / 2
    if float(np.abs(coupling + coupling.T).max()) > bound:
        raise InertiaError(
            "Expected the coupling block of `matrix` to be m [c] (skew-symmetric), got "
            f"{coupling.tolist()}.",
            argument="matrix",
        )
    c = np.array(
        [
            coupling[2, 1] - coupling[1, 2],
            coupling[0, 2] - coupling[2, 0],
            coupling[1, 0] - coupling[0, 1],
        ]
    ) / (2 * m)
    cross = cross_matrix(c)
    upper = (s[:3, :3] + s[:3, :3].T) / 2
    about_center = upper - m * cross @ cross.T
    about_center = (about_center + about_center.T) / 2
    try:
        return body_type.from_inertia(m, about_center, p + c)
    except InertiaError as error:
        # Recovering I_c = I_p - m [c][c]^T leaves rounding of about eps ||I_p||: a point
        # mass, a rod or a flat body away from the point (a zero moment, or the triangle
        # inequality with equality) came out a hair outside the valid tensors, and their
        # own spatial inertia was refused. Within 16 eps ||I_p|| of valid, the moments are
        # put back on the boundary (a change of that size, the recovery's own error).
        slack = 16 * np.finfo(float).eps * float(np.abs(upper).max())
        moments, axes = np.linalg.eigh(about_center)
        if moments[0] >= -slack and moments[2] - moments[0] - moments[1] <= slack:
            moments = np.maximum(moments, 0.0)
            moments[2] = min(moments[2], moments[0] + moments[1])
            repaired = (axes * moments) @ axes.T
            return body_type.from_inertia(m, (repaired + repaired.T) / 2, p + c)
        raise InertiaError(
            "Expected `matrix` to be the spatial inertia of a body, but the rotational "
            f"inertia about the centre of mass it implies is not an inertia tensor: "
            f"{error.message}",
            argument="matrix",
        ) from error
