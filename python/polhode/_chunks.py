"""Long numpy work in chunks, so that Ctrl-C is not held up: numpy holds the interpreter for a
whole call (a sine of 5e7 numbers is a second), and Python runs its SIGINT handler between
calls only. Work on arrays of up to :data:`CHUNK` elements at a time takes milliseconds.

The sequential operations come here with their carries, bit for bit what numpy gives for the
whole array: ``np.cumsum`` and ``np.maximum.accumulate`` are sequential loops (the carry is
the previous partial result, put in front of the next chunk), and ``np.unwrap`` is a difference,
elementwise corrections and such a cumulative sum. Elementwise work gives each element the same
bits in any chunk: the chunks start at multiples of :data:`CHUNK`, a power of two, so that
numpy's vector loops see the same alignment.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["CHUNK", "accumulate", "spans", "unwrap"]

#: Rows per chunk: 2^18 (about 2.6e5; a few milliseconds of numpy work, so that a Ctrl-C waits
#: well under 0.2 s even on a loaded machine; 2^20 let euler_angles take up to 0.25 s).
CHUNK = 1 << 18


def spans(n: int, chunk: int | None = None) -> Iterator[slice]:
    """Slices covering range(n) in order, ``chunk`` (default :data:`CHUNK`, read at each call)
    at a time; one empty slice for n = 0."""
    chunk = CHUNK if chunk is None else chunk
    if n == 0:
        yield slice(0, 0)
        return
    for start in range(0, n, chunk):
        yield slice(start, min(start + chunk, n))


def accumulate(ufunc: Any, x: NDArray[Any], chunk: int | None = None) -> NDArray[Any]:
    """``ufunc.accumulate(x, axis=0)`` (``np.add``: ``np.cumsum``) chunk by chunk, bit for bit
    the same: each chunk is accumulated after the previous chunk's last partial result."""
    x = np.asarray(x)
    out = np.empty_like(x)
    carry = None
    for span in spans(len(x), chunk):
        if carry is None:
            ufunc.accumulate(x[span], axis=0, out=out[span])
        else:
            part = ufunc.accumulate(np.concatenate([carry, x[span]]), axis=0)
            out[span] = part[1:]
        if span.stop > span.start:
            carry = out[span.stop - 1 : span.stop]
    return out


def unwrap(p: NDArray[np.float64], chunk: int | None = None) -> NDArray[np.float64]:
    """``np.unwrap(p, axis=0)`` (period 2 pi) chunk by chunk, bit for bit the same."""
    p = np.asarray(p, dtype=np.float64)
    if len(p) < 2:
        return np.array(p, copy=True)
    # Every row is written below (row 0 here, the others chunk by chunk): no whole-array copy,
    # which for 1.8e7 rows of three took 0.1 s with Ctrl-C held.
    up = np.empty_like(p)
    up[0] = p[0]
    period = 2 * math.pi
    high, low = period / 2, -period / 2
    carry = None  # the cumulative correction up to the previous chunk's last difference
    for span in spans(len(p) - 1, chunk):
        # Differences dd[k] = p[k + 1] - p[k] for k in the span.
        dd = np.diff(p[span.start : span.stop + 1], axis=0)
        ddmod = np.mod(dd - low, period) + low
        np.copyto(ddmod, high, where=(ddmod == low) & (dd > 0))
        correct = ddmod - dd
        np.copyto(correct, 0, where=abs(dd) < high)
        if carry is None:
            total = np.cumsum(correct, axis=0)
        else:
            total = np.cumsum(np.concatenate([carry, correct]), axis=0)[1:]
        up[span.start + 1 : span.stop + 1] = p[span.start + 1 : span.stop + 1] + total
        carry = total[-1:]
    return up
