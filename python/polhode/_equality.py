"""``==`` of the result types (:class:`polhode.Principal`, :class:`polhode.Analysis`,
:class:`polhode.Trajectory`): value equality, field by field, exact.

``a == b`` when ``b`` is of the same type and every field is equal:

- arrays: the same shape and every element equal, as ``numpy.array_equal`` says (IEEE
  equality: ``0.0 == -0.0``), with NaN equal to NaN in the same place, so that a result equals
  itself and its copies (pickle, ``copy.deepcopy``, a Dask worker's); dtypes are not compared
  (a result's are fixed);
- numbers, strings, None: ``==`` (NaN equal to NaN, as in arrays); tuples, lists and dicts
  element by element (dicts: the same keys).

Exact, not to a tolerance: two results are equal when they hold the same numbers (a run
repeated, a copy); results of different computations that agree to rounding are compared with
``numpy.allclose`` on their fields. Results hold arrays, which may be changed in place: they are
not hashable (``__hash__ = None``), as the ``eq`` of a dataclass makes them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["equal", "fields_equal"]


def equal(a: Any, b: Any) -> bool:
    """Whether two field values are equal (module docstring)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        if not (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)) or a.shape != b.shape:
            return False
        nan = a.dtype.kind in "fc" and b.dtype.kind in "fc"
        return bool(np.array_equal(a, b, equal_nan=nan))
    if isinstance(a, dict) or isinstance(b, dict):
        return (
            isinstance(a, dict)
            and isinstance(b, dict)
            and a.keys() == b.keys()
            and all(equal(a[k], b[k]) for k in a)
        )
    if isinstance(a, tuple | list) or isinstance(b, tuple | list):
        return (
            type(a) is type(b)
            and len(a) == len(b)
            and all(equal(x, y) for x, y in zip(a, b, strict=True))
        )
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return bool(a == b)


def fields_equal(a: Any, b: Any, names: tuple[str, ...]) -> Any:
    """``a == b`` of a result type by the fields ``names``: NotImplemented for another type
    (Python then tries ``b == a``, and falls back on identity)."""
    if type(a) is not type(b):
        return NotImplemented
    return a is b or all(equal(getattr(a, name), getattr(b, name)) for name in names)
