"""The drift of the invariants of a torque-free motion: kinetic energy T, ``|L|`` and L in space.

Every place in polhode that reports how well a trajectory keeps its invariants (``plot.drift``,
the command line, the benchmarks) computes it here.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._chunks import CHUNK, spans
from polhode._coerce import as_float_array
from polhode._norms import norms
from polhode.errors import PolhodeError, ShapeError

__all__ = ["angular_momentum_space", "max_relative_drift", "relative_drift"]

Array = NDArray[np.float64]


def angular_momentum_space(traj: Any) -> Array | None:
    """The angular momentum in space axes, (..., M, 3), or None without orientation.

    The one place that reads it off a trajectory.

    Examples
    --------
    From the identity orientation, L in space starts as I omega0:

    >>> import polhode as ph
    >>> from polhode.invariants import angular_momentum_space
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], [0.0, 10.0])
    >>> angular_momentum_space(sol)[0].round(12).tolist()
    [0.01, 2.0, 0.03]
    >>> angular_momentum_space(ph.simulate([1.0, 2.0, 3.0], [0.0, 1.0, 0.0], 1.0,
    ...                                    orientation=False)) is None
    True
    """
    value = _field(traj, "angular_momentum_space")
    return None if value is None else _array(value, "angular_momentum_space", 2)


#: What a trajectory must have for the functions here (polhode.Trajectory has them all).
_FIELDS = ("energy", "angular_momentum_body", "angular_momentum_space")


def _field(traj: Any, name: str) -> Any:
    """``traj.name``, or a TypeError naming ``traj`` for an object that is no trajectory."""
    try:
        return getattr(traj, name)
    except AttributeError:
        raise TypeError(
            "Expected `traj` to be a polhode.Trajectory (or an object with "
            f"{', '.join(_FIELDS)}), got {type(traj).__name__}."
        ) from None


def _array(value: Any, name: str, trailing: int) -> Array:
    """A trajectory's field as float64, with at least ``trailing`` dimensions (times, and 3
    for a vector); errors name ``traj`` and the field."""
    try:
        array = as_float_array(f"traj.{name}", value)
    except PolhodeError as error:  # named by the field in the message, `traj` the argument
        raise type(error)(str(error), argument="traj") from None
    if array.ndim < trailing or (trailing == 2 and array.shape[-1] != 3):
        shape = "(..., M, 3)" if trailing == 2 else "(..., M)"
        raise ShapeError(
            f"Expected `traj.{name}` to have shape {shape}, got {tuple(array.shape)}.",
            argument="traj",
        )
    return array


def _against_first(error: Array, first: Array) -> Array:
    """``error / |first|``, or ``error`` itself where ``first`` is zero."""
    scale = np.abs(first)
    return error / np.where(scale == 0.0, 1.0, scale)


def relative_drift(traj: Any) -> dict[str, Array]:
    """The error of each invariant against its value at the first output time, per output time.

    Parameters
    ----------
    traj : a :class:`polhode.Trajectory`, one body (M output times) or a batch (N, M); any
        object with ``energy`` (..., M), ``angular_momentum_body`` (..., M, 3) and the space
        angular momentum (..., M, 3) or None (see :func:`angular_momentum_space`) will do.

    Returns
    -------
    dict of (..., M) float arrays, 0 at the first output time:

    ``"energy"``
        ``|T(t) - T(t0)| / |T(t0)|``.
    ``"angular_momentum_norm"``
        ``||L(t)| - |L(t0)|| / |L(t0)|``, with L in body axes (the norm is the same in space).
    ``"angular_momentum_space"``
        ``|L(t) - L(t0)| / |L(t0)|``, the vector in space axes (left out without orientation).

    Where the value at t0 is zero (a body at rest: T, ``|L|`` and L are all zero), dividing by it
    means nothing, and the entry is the absolute error instead (the numerator alone); in a
    batch this is decided body by body.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> from polhode.invariants import relative_drift
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], np.linspace(0.0, 100.0, 11),
    ...                   method="rk4", dt=0.1)
    >>> drift = relative_drift(sol)
    >>> sorted(drift), drift["energy"].shape, float(drift["energy"][0])
    (['angular_momentum_norm', 'angular_momentum_space', 'energy'], (11,), 0.0)
    """
    for name in _FIELDS:
        _field(traj, name)  # a TypeError before any work for an object that is no trajectory
    energy = _array(traj.energy, "energy", 1)
    body = _array(traj.angular_momentum_body, "angular_momentum_body", 2)
    space = angular_momentum_space(traj)
    for name, vector in (("angular_momentum_body", body), ("angular_momentum_space", space)):
        if vector is not None and vector.shape[:-1] != energy.shape:
            raise ShapeError(
                f"Expected `traj.{name}` to have shape {energy.shape + (3,)} to match "
                f"`traj.energy`, got {vector.shape}.",
                argument="traj",
            )
    keys = ["energy", "angular_momentum_norm"]
    if space is not None:
        keys.append("angular_momentum_space")
    out = {key: np.empty(energy.shape) for key in keys}
    # Bodies (rows) and times in blocks of about CHUNK values (polhode._chunks: Ctrl-C is not
    # held up by one numpy call over a long trajectory); each value as the whole at once.
    times = energy.shape[-1]
    rows = energy.reshape(math.prod(energy.shape[:-1]), times)
    flat = {key: value.reshape(rows.shape) for key, value in out.items()}
    body_rows = body.reshape(*rows.shape, 3)
    space_rows = None if space is None else space.reshape(*rows.shape, 3)
    for bodies in spans(len(rows), max(1, CHUNK // max(times, 1))):
        e0 = rows[bodies, :1]
        n0 = norms(body_rows[bodies, :1])
        s0 = None if space_rows is None else space_rows[bodies, :1, :]
        for span in spans(times):
            e = rows[bodies, span]
            flat["energy"][bodies, span] = _against_first(np.abs(e - e0), e0)
            n = norms(body_rows[bodies, span])
            flat["angular_momentum_norm"][bodies, span] = _against_first(np.abs(n - n0), n0)
            if space_rows is not None:
                flat["angular_momentum_space"][bodies, span] = _against_first(
                    norms(space_rows[bodies, span] - s0),
                    norms(s0),
                )
    return out


def max_relative_drift(traj: Any) -> dict[str, float]:
    """The largest entry of each array of :func:`relative_drift`: over the output times, and
    over the bodies of a batch (NaN if any entry is NaN; 0 for an empty batch, which drifts
    by nothing).

    Examples
    --------
    The splitting keeps ``|L|`` and L in space to rounding; rk4 keeps nothing exactly:

    >>> import polhode as ph
    >>> from polhode.invariants import max_relative_drift
    >>> for method in ("splitting", "rk4"):
    ...     drift = max_relative_drift(ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 100.0,
    ...                                            method=method, dt=0.1))
    ...     print(method, drift["angular_momentum_space"] < 1e-14)
    splitting True
    rk4 False
    """
    return {
        key: float(np.max(values)) if values.size else 0.0
        for key, values in relative_drift(traj).items()
    }
