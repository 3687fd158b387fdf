"""Euclidean norms that neither overflow nor underflow where the norm itself is a double.

numpy's norm squares the entries: a vector of 1e155 overflows (inf, with a RuntimeWarning), one
of 1e-170 underflows to 0 (and a quotient by it to a NaN or a warning). :func:`norms` scales
each vector first by the power of two of its largest entry, which is exact: wherever numpy's
norm (summed along an axis) neither overflows nor underflows, the result is numpy's, bit for
bit; elsewhere it is the norm to rounding, and inf only where the norm itself is beyond double
precision.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["norms"]


def norms(vectors: Any, axis: int = -1) -> NDArray[np.float64]:
    """The Euclidean norms of ``vectors`` along ``axis`` (a float for one vector)."""
    x = np.asarray(vectors, dtype=np.float64)
    if x.size == 0:
        return np.linalg.norm(x, axis=axis)
    largest = np.max(np.abs(x), axis=axis, keepdims=True)
    _, exponent = np.frexp(largest)  # largest = f 2^exponent, f in [1/2, 1); 0 for 0 and inf
    scaled = np.ldexp(x, -exponent)  # exact but for entries 2^-1022 below the largest
    with np.errstate(over="ignore"):
        return np.ldexp(np.linalg.norm(scaled, axis=axis), np.squeeze(exponent, axis=axis))
