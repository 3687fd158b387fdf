"""The inputs of :mod:`polhode.dask`: checked at the call, split into blocks of bodies along N.

Apart from :mod:`polhode.dask` so that it stays small; only that module uses these.
"""

from __future__ import annotations

from typing import Any

import dask
import dask.array as da
import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_float_array as _as_float_array
from polhode._coerce import as_integer
from polhode.errors import PolhodeError, ShapeError

__all__ = [
    "as_input",
    "blocked",
    "in_block",
    "orientation_input",
    "row_chunks",
    "rows_of",
    "shape_text",
]



def shape_text(shape: tuple[Any, ...]) -> str:
    return "(" + ", ".join(map(str, shape)) + (",)" if len(shape) == 1 else ")")


def as_input(name: str, value: Any) -> da.Array | NDArray[np.float64]:
    """A dask array (kept lazy, cast to float64) or a float64 numpy array, (3,) or (N, 3)."""
    if isinstance(value, da.Array):
        if value.dtype.kind not in "biuf":
            raise TypeError(
                f"Expected `{name}` to be an array of real numbers, got dtype {value.dtype}."
            )
        array: Any = value.astype(np.float64)
    else:
        array = _as_float_array(name, value)
    if array.shape != (3,) and not (array.ndim == 2 and array.shape[1] == 3):
        raise ShapeError(
            f"Expected `{name}` to have shape (3,) or (N, 3), got {shape_text(array.shape)}.",
            argument=name,
        )
    if array.ndim == 2 and np.isnan(array.shape[0]):
        raise ShapeError(
            f"Expected `{name}` to have a known number of rows, got unknown chunk sizes "
            "(call .compute_chunk_sizes() first).",
            argument=name,
        )
    return array


def rows_of(body: Any, omega0: Any) -> int:
    """The number of bodies N: the rows of ``omega0`` (N, 3); ``body`` has N rows or one (3,)
    row shared by all."""
    if omega0.ndim != 2:
        raise ShapeError(
            "Expected `omega0` to have shape (N, 3) (one row per body), "
            f"got {shape_text(omega0.shape)}.",
            argument="omega0",
        )
    n = int(omega0.shape[0])
    if body.ndim == 2 and int(body.shape[0]) != n:
        raise ShapeError(
            f"Expected `body` to have shape (3,) or ({n}, 3) to match `omega0`, "
            f"got {shape_text(body.shape)}.",
            argument="body",
        )
    return n


def row_chunks(chunks: Any, n: int, record_bytes: int, *arrays: Any) -> tuple[int, ...]:
    """Rows per block: ``chunks`` if given, else the first dask input's, else blocks of about
    dask's ``array.chunk-size`` of output."""
    if chunks is not None:
        size = as_integer("chunks", chunks, minimum=1)
        return da.core.normalize_chunks((size,), (n,))[0]
    for array in arrays:
        if isinstance(array, da.Array) and array.ndim >= 2:
            return tuple(int(c) for c in array.chunks[0])
    from dask.utils import parse_bytes

    target = parse_bytes(dask.config.get("array.chunk-size"))
    size = max(1, target // max(record_bytes, 1))
    return da.core.normalize_chunks((size,), (n,))[0]


def blocked(array: Any, n: int, row_chunks: tuple[int, ...]) -> da.Array:
    """(N, ...) dask array with the given row chunks and one chunk along every other axis; a
    (3,) row is broadcast to every body."""
    if array.ndim == 1:
        if not isinstance(array, da.Array):
            array = da.from_array(array, chunks=-1)
        return da.broadcast_to(array, (n, 3), chunks=(row_chunks, 3))
    chunks = (row_chunks, *array.shape[1:])
    if isinstance(array, da.Array):
        return array.rechunk(chunks)
    return da.from_array(array, chunks=chunks)


def orientation_input(orientation0: Any, n: int) -> tuple[Any, Any, bool]:
    """(shared, per_body, stack): one orientation for every body, or an (N, 4) or (N, 3, 3)
    array; ``stack`` when the array holds the quaternions of a scipy Rotation stack."""
    if orientation0 is None:
        return None, None, False
    from scipy.spatial.transform import Rotation

    if isinstance(orientation0, Rotation):
        if orientation0.single or len(orientation0) == 1:
            return orientation0, None, False
        quaternions = orientation0.as_quat()
        if quaternions.shape != (n, 4):
            raise ShapeError(
                f"Expected `orientation0` to hold 1 or {n} rotations, got {len(orientation0)}.",
                argument="orientation0",
            )
        return None, quaternions, True
    if isinstance(orientation0, da.Array):
        if orientation0.dtype.kind not in "biuf":
            raise TypeError(
                "Expected `orientation0` to be an array of real numbers, "
                f"got dtype {orientation0.dtype}."
            )
        per_body = orientation0.astype(np.float64)
    else:
        per_body = _as_float_array("orientation0", orientation0)
    if per_body.shape in ((4,), (3, 3)) or (per_body.ndim >= 2 and per_body.shape[0] == 1):
        return np.asarray(per_body), None, False  # one rotation for all: small, computed now
    if per_body.shape not in ((n, 4), (n, 3, 3)):
        raise ShapeError(
            "Expected `orientation0` to be a scipy Rotation, a (3, 3) matrix, an (x, y, z, w) "
            f"quaternion, or ({n}, 4) quaternions or ({n}, 3, 3) matrices (one per body), "
            f"got shape {shape_text(per_body.shape)}.",
            argument="orientation0",
        )
    return None, per_body, False


def in_block(error: PolhodeError, rows: NDArray[np.int64]) -> PolhodeError:
    """The error of a block, its body numbered in the whole batch."""
    if error.body is None or not rows.size:
        return error
    return error.for_body(int(rows[error.body]))
