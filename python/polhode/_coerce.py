"""Input coercion shared by the Python layer: array-likes to float64, rotations to matrices,
a mesh's faces, scale and amount of matter.

Errors name the argument and say what was expected and what came, in the form
``Expected `name` to have shape (3,), got (2,).``
"""

from __future__ import annotations

import math
import numbers
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode.errors import ArgumentError, NonFiniteError, NonPositiveError, ShapeError

#: float64's dtype: numpy keeps one instance of each built-in dtype.
_FLOAT64 = np.dtype(np.float64)

__all__ = [
    "as_array",
    "as_double",
    "as_faces",
    "as_finite",
    "as_finite_array",
    "as_flag",
    "as_float_array",
    "as_integer",
    "as_path",
    "as_rotation_matrix",
    "as_scalar",
    "as_scale",
    "density_or_mass",
    "read_only_arrays",
    "unmasked",
]


def _shape_str(shape: tuple[int, ...]) -> str:
    if len(shape) == 1:
        return f"({shape[0]},)"
    return "(" + ", ".join(str(d) for d in shape) + ")"


def unmasked(name: str, value: Any) -> Any:
    """``value``, or the data of a numpy masked array with nothing masked; an ArgumentError
    naming ``name`` for a masked array with masked entries (numpy's conversions would read the
    values under the mask, whatever they are, as data)."""
    if not isinstance(value, np.ma.MaskedArray):
        return value
    masked = int(np.count_nonzero(np.ma.getmaskarray(value)))
    if masked:
        raise ArgumentError(
            f"Expected `{name}` to have no masked entries, got a masked array with {masked} "
            f"masked of {value.size}: fill them (array.filled(value)) or leave them out.",
            argument=name,
        )
    return np.asarray(value.data)


def as_double(name: str, value: Any) -> float:
    """``float(value)`` of a real number (an int, a Fraction, a numpy scalar), or a
    NonFiniteError naming ``name`` for one beyond double precision (``2**2000``), which
    ``float`` would raise as an OverflowError."""
    try:
        return float(value)
    except OverflowError:
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got a number beyond double precision.",
            argument=name,
        ) from None


def as_scalar(name: str, value: Any) -> float:
    """A real number as float; TypeError for anything else (bool, str, arrays), NonFiniteError
    for one beyond double precision, ArgumentError for a masked value."""
    if type(value) is float:
        return value
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "fiu":
            return as_double(name, unmasked(name, value))
        raise TypeError(f"Expected `{name}` to be a real number, got {type(value).__name__}.")
    return as_double(name, value)


def as_finite(name: str, value: Any, *, positive: bool = False) -> float:
    """A finite real number (``positive``: above zero) as float: TypeError naming ``name`` for
    anything but a real number, NonFiniteError for NaN and infinities, NonPositiveError for
    zero or less where a positive number is asked for."""
    x = as_scalar(name, value)
    if not math.isfinite(x):
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got {_finite_str(x)}.", argument=name
        )
    if positive and not x > 0.0:
        raise NonPositiveError(f"Expected `{name}` to be positive, got {x:g}.", argument=name)
    return x


def _finite_str(x: float) -> str:
    """A non-finite number as the core writes it: NaN, inf, -inf."""
    return "NaN" if math.isnan(x) else str(x)


def as_path(name: str, value: Any) -> str:
    """A file name: a str or an ``os.PathLike`` of one, as str; TypeError naming ``name`` for
    anything else (bytes included)."""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    if not isinstance(value, str):
        raise TypeError(f"Expected `{name}` to be a file name (str), got {_kind(value)}.")
    return value


def as_flag(name: str, value: Any) -> bool:
    """True or False (a Python or numpy bool); TypeError naming ``name`` for anything else
    (``bool("no")`` is True)."""
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"Expected `{name}` to be a bool, got {type(value).__name__}.")
    return bool(value)


def _kind(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return f"an array of dtype {value.dtype}"
    return type(value).__name__


def as_float_array(name: str, value: Any) -> NDArray[np.float64]:
    """A C-contiguous float64 array of any shape: TypeError naming ``name`` for anything that
    is not real numbers (strings, None, complex numbers, objects), also inside a list (numpy
    would read ``[1, None]`` as ``[1, nan]``). At least one dimension, as
    ``numpy.ascontiguousarray`` gives: a scalar comes back with shape (1,). A C-contiguous
    float64 array is returned as it is, and anything else is read by numpy once: this runs
    several times in every small call."""
    if type(value) is np.ndarray:
        if value.dtype is _FLOAT64 and value.flags.c_contiguous and value.ndim:
            return value
        raw: NDArray[Any] = value
    elif isinstance(value, np.ma.MaskedArray):
        raw = unmasked(name, value)
    elif value is None or isinstance(value, str | bytes):
        raise TypeError(f"Expected `{name}` to be an array of real numbers, got {_kind(value)}.")
    else:
        try:
            raw = np.asarray(value)
        except (TypeError, ValueError) as error:
            raise TypeError(
                f"Expected `{name}` to be an array of real numbers, got {_kind(value)}."
            ) from error
    kind = raw.dtype.kind
    if kind not in "biuf" and not (kind == "O" and _all_real(raw)):
        what = (
            _kind(value)
            if kind in "Oc" or isinstance(value, np.ndarray)
            else f"{_kind(value)} of {raw.dtype}"
        )
        raise TypeError(f"Expected `{name}` to be an array of real numbers, got {what}.")
    try:
        return np.ascontiguousarray(raw, dtype=np.float64)
    except OverflowError:
        # Python integers (or Fractions) beyond double precision, e.g. [2**2000, 1, 1].
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got a number beyond double precision.",
            argument=name,
        ) from None
    except (TypeError, ValueError) as error:
        raise TypeError(
            f"Expected `{name}` to be an array of real numbers, got {_kind(value)}."
        ) from error


def _all_real(array: NDArray[Any]) -> bool:
    """Whether every element of an object array is a real number (None, strings and complex
    numbers are not)."""
    return all(
        isinstance(x, numbers.Real) and not isinstance(x, bool) or isinstance(x, np.bool_ | bool)
        for x in array.flat
    )


def as_array(name: str, value: Any, shape: tuple[int | None, ...]) -> NDArray[np.float64]:
    """A C-contiguous float64 array of the given shape (None matches any length)."""
    array = as_float_array(name, value)
    expected = "(" + ", ".join("N" if d is None else str(d) for d in shape)
    expected += ",)" if len(shape) == 1 else ")"
    if array.ndim != len(shape) or any(
        d is not None and d != a for d, a in zip(shape, array.shape, strict=True)
    ):
        raise ShapeError(
            f"Expected `{name}` to have shape {expected}, got {_shape_str(array.shape)}.",
            argument=name,
        )
    return array


def as_finite_array(name: str, value: Any, shape: tuple[int | None, ...]) -> NDArray[np.float64]:
    """:func:`as_array` of finite numbers: NonFiniteError naming ``name`` (and the first
    offending entry) for a NaN or an infinity."""
    array = as_array(name, value, shape)
    if not np.all(np.isfinite(array)):
        index = tuple(int(i) for i in np.argwhere(~np.isfinite(array))[0])
        where = f"{name}[{', '.join(map(str, index))}]" if index else name
        raise NonFiniteError(
            f"Expected `{where}` to be finite, got {_finite_str(float(array[index]))}.",
            argument=name,
        )
    return array


def as_rotation_matrix(name: str, rotation: Any) -> NDArray[np.float64]:
    """A proper rotation matrix from a scipy Rotation, a (3, 3) matrix or an xyzw quaternion."""
    from scipy.spatial.transform import Rotation

    if isinstance(rotation, Rotation):
        if not rotation.single:
            raise ShapeError(
                f"Expected `{name}` to be a single rotation, got a stack.", argument=name
            )
        return np.ascontiguousarray(rotation.as_matrix(), dtype=np.float64)
    if rotation is None or isinstance(rotation, str | bytes):
        raise TypeError(
            f"Expected `{name}` to be a scipy Rotation, a (3, 3) matrix or an (x, y, z, w) "
            f"quaternion, got {type(rotation).__name__}."
        )
    try:
        array = as_float_array(name, rotation)
    except TypeError as error:
        raise TypeError(
            f"Expected `{name}` to be a scipy Rotation, a (3, 3) matrix or an (x, y, z, w) "
            f"quaternion, got {_kind(rotation)}."
        ) from error
    if not np.all(np.isfinite(array)):
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got {array.tolist()}.", argument=name
        )
    if array.shape == (4,):
        largest = float(np.max(np.abs(array)))
        if largest == 0.0:
            raise ArgumentError(
                f"Expected `{name}` to be a non-zero quaternion, got {array}.", argument=name
            )
        unit = array / largest  # scaled first: the norm of 1e154-sized entries would overflow
        return np.ascontiguousarray(Rotation.from_quat(unit / np.linalg.norm(unit)).as_matrix())
    if array.shape == (3, 3):
        return np.ascontiguousarray(array)
    raise ShapeError(
        f"Expected `{name}` to have shape (3, 3) or (4,) (an x, y, z, w quaternion), "
        f"got {_shape_str(array.shape)}.",
        argument=name,
    )


#: 2^63: the core takes integers as signed 64-bit numbers.
_I64 = 2**63


def as_integer(
    name: str,
    value: Any,
    *,
    allowed: tuple[int, ...] = (),
    minimum: int | None = None,
    maximum: int | None = None,
    why: str = "",
) -> int:
    """An integer (bool excluded; a numpy integer, or a 0-d array of one) of 64 bits, as the
    core takes it: TypeError for other types, ArgumentError outside the range (``allowed``,
    ``minimum``, ``maximum``, the last one's reason ``why``; a masked value is an
    ArgumentError as in :func:`unmasked`)."""
    if type(value) is int and not allowed and minimum is None and maximum is None:
        if -_I64 <= value < _I64:
            return value
    if isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iu":
        value = unmasked(name, value)[()]
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"Expected `{name}` to be an integer, got {type(value).__name__}.")
    result = int(value)
    if not -_I64 <= result < _I64:
        raise ArgumentError(
            f"Expected `{name}` to be a 64-bit integer (below 2^63 in size), got {result}.",
            argument=name,
        )
    if allowed and result not in allowed:
        choices = ", ".join(map(str, allowed))
        raise ArgumentError(
            f"Expected `{name}` to be one of {choices}, got {result}.", argument=name
        )
    if minimum is not None and result < minimum:
        raise ArgumentError(f"Expected `{name}` to be >= {minimum}, got {result}.", argument=name)
    if maximum is not None and result > maximum:
        because = f" ({why})" if why else ""
        raise ArgumentError(
            f"Expected `{name}` to be <= {maximum}{because}, got {result}.", argument=name
        )
    return result


def as_faces(faces: Any) -> NDArray[np.int64]:
    """(M, 3) integer vertex indices as a C-contiguous int64 array."""
    if faces is None or isinstance(faces, str | bytes):
        raise TypeError(
            f"Expected `faces` to be an array of vertex indices, got {type(faces).__name__}."
        )
    faces = unmasked("faces", faces)
    try:
        array = np.asarray(faces)
    except (TypeError, ValueError) as error:
        raise TypeError(
            f"Expected `faces` to be an array of vertex indices, got {type(faces).__name__}."
        ) from error
    if array.dtype.kind not in "iu" and not (array.size == 0 and array.dtype.kind == "f"):
        raise TypeError(f"Expected `faces` to be an array of integers, got dtype {array.dtype}.")
    if array.ndim != 2 or array.shape[1] != 3:
        shape = "(" + ", ".join(str(d) for d in array.shape) + (",)" if array.ndim == 1 else ")")
        raise ShapeError(f"Expected `faces` to have shape (M, 3), got {shape}.", argument="faces")
    if array.dtype.kind == "u" and array.size and int(array.max()) > np.iinfo(np.int64).max:
        raise ArgumentError(
            f"Expected `faces` to hold vertex indices, got {int(array.max())}.", argument="faces"
        )
    return np.ascontiguousarray(array, dtype=np.int64)


def density_or_mass(
    density: Any, mass: Any, *, required: bool
) -> tuple[float | None, float | None]:
    """Check ``density`` and ``mass``: at most one (exactly one if ``required``), a finite
    positive number."""
    if density is not None and mass is not None:
        raise ArgumentError("Give exactly one of `density` and `mass`, got both.", argument="mass")
    if required and density is None and mass is None:
        raise ArgumentError(
            "Give exactly one of `density` and `mass`, got neither.", argument="density"
        )
    out: list[float | None] = []
    for name, value in (("density", density), ("mass", mass)):
        if value is None:
            out.append(None)
            continue
        x = as_scalar(name, value)
        if not math.isfinite(x):
            raise NonFiniteError(f"Expected `{name}` to be finite, got {x}.", argument=name)
        if x <= 0:
            raise NonPositiveError(f"Expected `{name}` to be positive, got {x:g}.", argument=name)
        out.append(x)
    return out[0], out[1]


def as_scale(value: Any, name: str = "scale") -> NDArray[np.float64]:
    """A scale factor: one number or three (per axis), finite and non-zero (a negative factor
    mirrors the mesh)."""
    array = as_float_array(name, value)
    if array.shape in ((), (1,)):  # ascontiguousarray makes a number (1,)
        array = np.full(3, float(array.reshape(-1)[0]))
    if array.shape != (3,):
        raise ShapeError(
            f"Expected `{name}` to be a number or 3 numbers, got shape {array.shape}.",
            argument=name,
        )
    if not np.all(np.isfinite(array)):
        raise NonFiniteError(
            f"Expected `{name}` to be finite, got {array.tolist()}.", argument=name
        )
    if np.any(array == 0):
        raise ArgumentError(
            f"Expected `{name}` to be non-zero, got {array.tolist()}.", argument=name
        )
    return array


def read_only_arrays(state: dict[str, Any]) -> dict[str, Any]:
    """An unpickled or deep-copied model's state with its arrays read-only again, as its
    constructor made them (numpy's pickles load writeable): for ``__setstate__``."""
    for value in state.values():
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    return state
