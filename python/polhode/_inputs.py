"""The ``body`` argument of :func:`polhode.simulate`, :func:`polhode.analyze` and
:func:`polhode.rotors.nutation_rate`: what the core takes for it, and one body's principal
frame.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_float_array
from polhode.bodies import Body
from polhode.errors import ShapeError
from polhode.principal_axes import principal

__all__ = ["EYE", "core_body", "merged", "principal_frame"]


def core_body(body: Any) -> Any:
    """What the core takes for ``body``: the core of a Body, a list of them, or numbers."""
    if type(body) is np.ndarray:
        # Numbers (neither a Body nor a list): the two checks below skipped, in a small call.
        return as_float_array("body", body)
    if isinstance(body, Body):
        return body._core
    if isinstance(body, (list, tuple)) and body and all(isinstance(b, Body) for b in body):
        return [b._core for b in body]
    return as_float_array("body", body)


#: The axes of principal moments given as numbers (read-only: returned, never written).
EYE = np.eye(3)
EYE.flags.writeable = False


def merged(moments: NDArray[np.float64], rtol: float | None) -> NDArray[np.float64]:
    """Principal moments given as numbers, those whose gap is at most ``rtol`` times the
    largest replaced by their mean (none without ``rtol``: numbers are taken as they are)."""
    if rtol is None:
        return moments
    out = moments.copy()
    order = np.argsort(out, kind="stable")
    tolerance = rtol * float(np.max(np.abs(out)))
    groups: list[list[int]] = [[int(order[0])]]
    for a, b in zip(order[:-1], order[1:], strict=True):
        if out[b] - out[a] <= tolerance:
            groups[-1].append(int(b))
        else:
            groups.append([int(b)])
    for group in groups:
        out[group] = float(np.mean(moments[group]))
    return out


def principal_frame(
    body: Any, rtol: float | None, coerced: Any = None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The principal moments (as given, or ascending) and axes (columns, body coordinates)
    of one body: a Body, principal moments (3,) or an inertia tensor (3, 3); moments within
    ``rtol`` returned equal. ``coerced``, if an array, is ``body`` already coerced (what
    ``core_body`` gives for numbers): not coerced again."""
    if type(coerced) is np.ndarray:
        array = coerced
    elif isinstance(body, Body):
        p = body.principal(rtol)
        return p.moments, p.axes
    else:
        array = as_float_array("body", body)
    if array.shape == (3,):
        return (array if rtol is None else merged(array, rtol)), EYE
    if array.shape == (3, 3):
        p = principal(array, rtol)
        return p.moments, p.axes
    raise ShapeError(
        "Expected `body` to be one body (a Body, principal moments (3,) or an inertia tensor "
        f"(3, 3)), got shape {array.shape}.",
        argument="body",
    )
