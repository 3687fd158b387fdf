"""The axes a plot's numbers are in: a ``body`` argument as ``simulate`` takes it (a Body,
principal moments in any order, an inertia tensor) read as its principal moments and axes, and
a trajectory's body axes identified from its own data (are they principal, and which is which).

A trajectory's ``omega`` and ``angular_momentum_body`` are in the body's own axes, which are
principal when the body was given as principal moments (in the order given) or as a Body or
tensor whose axes happen to be principal. The trajectory says which by its data: with rotors
(each of inertia J, at rate ``rotor_rates`` relative to the body, ``docs/rotors.md``) the total
angular momentum is ``H = I omega + sum J rate``, linear in the six entries of the tensor ``I``
and the rotors' J; :func:`body_tensor` solves for them by least squares over the output times
and keeps the answer only where it is determined (the output times span every direction) and
exact (residual and principal moments within 1e-9 of the trajectory's).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_float_array
from polhode.errors import (
    NonFiniteError,
    NonPositiveError,
    PolhodeError,
    ShapeError,
)

if TYPE_CHECKING:
    from polhode.simulation import Trajectory

__all__ = ["BodyAxes", "RTOL", "body_axes", "body_tensor", "principal_of"]

Array = NDArray[np.float64]

#: Relative agreement asked of an identified tensor (its residual and its principal moments),
#: and below which products of inertia count as zero.
RTOL = 1e-9

#: At most this many output times enter the least-squares fit (the residual is then checked
#: at every output time).
FIT_TIMES = 2048


def principal_of(body: Any, name: str = "body") -> tuple[Array, Array]:
    """The principal moments (ascending) and axes (columns, in the body's coordinates) of a
    body as ``simulate`` takes one: a Body, principal moments (3,) in any order (their axes
    are the coordinate axes, reordered), or an inertia tensor (3, 3). Errors name ``name``."""
    from polhode.bodies import Body
    from polhode.principal_axes import principal

    if isinstance(body, Body):
        p = body.principal()
        return np.asarray(p.moments, dtype=np.float64), np.asarray(p.axes, dtype=np.float64)
    if body is None or isinstance(body, str | bytes):
        raise TypeError(
            f"Expected `{name}` to be a Body, principal moments (3,) or an inertia tensor (3, 3), "
            f"got {type(body).__name__}."
        )
    array = as_float_array(name, body)
    if array.shape not in ((3,), (3, 3)):
        raise ShapeError(
            f"Expected `{name}` to be one body (a Body, principal moments (3,) or an inertia "
            f"tensor (3, 3)), got shape {array.shape}.",
            argument=name,
        )
    if not np.all(np.isfinite(array)):
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got {array.tolist()}.", argument=name
        )
    if array.shape == (3,):
        order = np.argsort(array, kind="stable")
        moments, axes = array[order], np.eye(3)[:, order]
    else:
        try:
            p = principal(array)
        except PolhodeError as error:
            message = error.message.replace("`inertia", f"`{name}")
            raise type(error)(message, argument=name) from None
        moments, axes = np.asarray(p.moments), np.asarray(p.axes)
    if not np.all(moments > 0.0):
        raise NonPositiveError(
            f"Expected the principal moments of `{name}` to be positive, got {moments.tolist()}.",
            argument=name,
        )
    return moments, axes


def _fit_rows(traj: Trajectory) -> tuple[Array, Array, Array, Array | None]:
    """omega (M, 3), L (M, 3), the rotors' rates (M, R, 3) or None, as float64."""
    omega = np.asarray(traj.omega, dtype=np.float64)
    momentum = np.asarray(traj.angular_momentum_body, dtype=np.float64)
    rates = None if traj.rotor_rates is None else np.asarray(traj.rotor_rates, dtype=np.float64)
    return omega, momentum, rates, np.asarray(traj.moments, dtype=np.float64)


def _design(omega: Array, rates: Array | None) -> Array:
    """The rows of H = I omega + sum J rate, three per output time, against the unknowns
    (I11, I22, I33, I12, I13, I23, J1, .. JR)."""
    w0, w1, w2 = omega[:, 0], omega[:, 1], omega[:, 2]
    zero = np.zeros_like(w0)
    rows = np.stack(
        [
            np.stack([w0, zero, zero, w1, w2, zero], axis=1),
            np.stack([zero, w1, zero, w0, zero, w2], axis=1),
            np.stack([zero, zero, w2, zero, w0, w1], axis=1),
        ],
        axis=1,
    )  # (M, 3, 6)
    if rates is not None:
        rows = np.concatenate([rows, rates.transpose(0, 2, 1)], axis=2)  # (M, 3, 6 + R)
    return rows.reshape(-1, rows.shape[2])


def _tensor(values: Array) -> Array:
    i11, i22, i33, i12, i13, i23 = values[:6]
    return np.array([[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]])


def _rotor_part(
    omega: Array, momentum: Array, rates: Array | None, tensor: Array
) -> tuple[Array, float]:
    """H - I omega less its best fit by the rotors' rates, and its largest entry relative
    to |H|."""
    rest = momentum - omega @ tensor.T
    if rates is not None and rates.shape[1]:
        design = rates.transpose(0, 2, 1).reshape(-1, rates.shape[1])
        coefficients, *_ = np.linalg.lstsq(design, rest.reshape(-1), rcond=None)
        rest = rest - (design @ coefficients).reshape(rest.shape)
    scale = float(np.max(np.abs(momentum))) if momentum.size else 0.0
    return rest, float(np.max(np.abs(rest))) / scale if scale > 0 else 0.0


def fits(traj: Trajectory, tensor: Array) -> bool:
    """Whether ``tensor`` (body axes) is the trajectory's inertia: H = I omega + rotors'
    momentum at every output time, and its principal moments those of the trajectory."""
    omega, momentum, rates, moments = _fit_rows(traj)
    _, residual = _rotor_part(omega, momentum, rates, tensor)
    eigen = np.linalg.eigvalsh(tensor)
    scale = float(np.max(np.abs(moments)))
    return residual <= RTOL and float(np.max(np.abs(eigen - np.sort(moments)))) <= RTOL * scale


def body_tensor(traj: Trajectory) -> Array | None:
    """The inertia tensor in the trajectory's body axes, read off its omega and angular
    momentum (and rotor rates); None where they do not determine it (a steady spin, a body at
    rest) or do not fit one."""
    omega, momentum, rates, moments = _fit_rows(traj)
    if omega.shape[0] == 0:
        return None
    step = max(1, omega.shape[0] // FIT_TIMES)
    design = _design(omega[::step], None if rates is None else rates[::step])
    target = momentum[::step].reshape(-1)
    width = float(np.max(np.abs(design))) if design.size else 0.0
    if width == 0.0:
        return None
    columns = np.max(np.abs(design), axis=0)
    if np.any(columns == 0.0):
        return None
    scaled = design / columns
    if np.linalg.matrix_rank(scaled, tol=1e-8 * float(np.max(np.abs(scaled)))) < design.shape[1]:
        return None
    solution, *_ = np.linalg.lstsq(scaled, target, rcond=None)
    tensor = _tensor(solution / columns)
    return tensor if fits(traj, tensor) else None


@dataclass(frozen=True)
class BodyAxes:
    """What a trajectory's body axes are.

    ``numbers``: the principal number (1, 2, 3, moments ascending) of each body axis, or None
    where they are not principal or cannot be told; ``moments``: the principal moments,
    ascending; ``axes``: the principal axes (columns, body coordinates), or None where the
    trajectory does not tell them."""

    numbers: tuple[int, int, int] | None
    moments: Array
    axes: Array | None


def _numbers(diagonal: Array) -> tuple[int, int, int]:
    order = np.argsort(diagonal, kind="stable")
    numbers = [0, 0, 0]
    for rank, axis in enumerate(order):
        numbers[int(axis)] = rank + 1
    return (numbers[0], numbers[1], numbers[2])


def body_axes(traj: Trajectory) -> BodyAxes:
    """The trajectory's body axes: principal (and numbered) or not, from its own data
    (:func:`body_tensor`). Where the data do not determine the tensor (a steady spin), the
    body's axes are taken as principal if the trajectory's moments, in their order, fit it
    (principal moments given to ``simulate`` are in the body's axes); otherwise unknown."""
    moments = np.asarray(traj.moments, dtype=np.float64)
    ascending = np.sort(moments)
    tensor = body_tensor(traj)
    if tensor is None:
        diagonal = np.diag(moments)
        if fits(traj, diagonal):
            numbers = _numbers(moments)
            return BodyAxes(numbers, ascending, np.eye(3)[:, np.argsort(moments, kind="stable")])
        return BodyAxes(None, ascending, None)
    scale = float(np.max(np.abs(ascending)))
    off = tensor - np.diag(np.diag(tensor))
    if float(np.max(np.abs(off))) <= RTOL * scale:
        diagonal = np.diag(tensor)
        return BodyAxes(
            _numbers(diagonal), ascending, np.eye(3)[:, np.argsort(diagonal, kind="stable")]
        )
    from polhode.principal_axes import principal

    p = principal((tensor + tensor.T) / 2.0)
    return BodyAxes(None, ascending, np.asarray(p.axes, dtype=np.float64))
