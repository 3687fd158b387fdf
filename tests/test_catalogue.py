"""The catalogue of bad and extreme inputs: one table across the whole public API.

Each row of ``CATALOGUE`` is one input (an id, the area of the API, a zero-argument call) and
what it must give:

- ``Raises``: a typed error of exactly that class, whose ``argument`` names the argument at
  fault (and ``body`` the body of a batch); a ``TypeError`` names the argument in its message;
- ``Value``: a finite answer, checked against a reference written apart from polhode (closed
  forms in this file or in ``tests/reference.py``, exact powers-of-two scalings of them, mpmath
  eigenvalues, scipy's DOP853 on Euler's equations, ``tests/reference_motion.py``), never
  against polhode itself;
- ``Exit``: for the command line, the exit status, and for status 2 the option the message
  names (no traceback), for status 0 what it printed or wrote.

Every value row also checks that every float of the answer is finite; every error row that its
message is short (no number printed with hundreds of digits) and holds no traceback. Tolerances
are in units of eps where round-off is the limit, and say where they come from. A row that shows
a defect not yet fixed carries ``xfail`` (strict) with the reason.

``python tests/test_catalogue.py`` (or ``pytest -s -k test_the_table``) prints the totals by
area and kind.
"""

from __future__ import annotations

import atexit
import collections
import contextlib
import io
import math
import re
import shutil
import sys
import tempfile
import types
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import mpmath
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
import reference as ref
from conftest import check_eigen
from reference import EPS, euler_omega, rigid_body, rotate_by_quaternion
from reference_motion import exact_period, turns_over_exact

NAN, INF = math.nan, math.inf
MAX = sys.float_info.max
TINY = math.ldexp(1.0, -1074)  # the smallest subnormal: the spacing of every subnormal


# ---------------------------------------------------------------------------------------------
# The shape of a row
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Raises:
    """Exactly ``error``, naming ``argument`` (``.argument`` of a PolhodeError, the message of
    any other class) and, in a batch, ``body``; ``fragment`` must be in the message."""

    error: type[BaseException]
    argument: str | None
    body: int | None = None
    fragment: str | None = None


@dataclass(frozen=True)
class Value:
    """A finite result that ``check(result)`` compares with ``reference``."""

    check: Callable[[Any], None]
    reference: str


@dataclass(frozen=True)
class Exit:
    """``polhode.cli.main(argv)``: status ``code``; for 2, a one-line error naming ``option``;
    ``check(stdout, stderr)`` for what a successful run printed."""

    code: int
    option: str | None = None
    check: Callable[[str, str], None] | None = None


@dataclass(frozen=True)
class Row:
    id: str
    area: str
    call: Callable[[], Any]
    expect: Raises | Value | Exit
    xfail: str | None = None

    @property
    def kind(self) -> str:
        if isinstance(self.expect, Raises):
            return "error"
        if isinstance(self.expect, Exit):
            return "value" if self.expect.code == 0 else "error"
        return "value"


CATALOGUE: list[Row] = []


def err(area, id_, call, error, argument, body=None, fragment=None, xfail=None):
    CATALOGUE.append(Row(f"{area}/{id_}", area, call, Raises(error, argument, body, fragment),
                         xfail))


def val(area, id_, call, check, reference, xfail=None):
    CATALOGUE.append(Row(f"{area}/{id_}", area, call, Value(check, reference), xfail))


# ---------------------------------------------------------------------------------------------
# Comparisons
# ---------------------------------------------------------------------------------------------


def close(actual, expected, rtol, atol=0.0, what=""):
    """max |actual - expected| <= rtol max |expected| + atol (norm-wise: the rounding of the
    large entries shows in the small ones)."""
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    scale = float(np.max(np.abs(expected))) if expected.size else 0.0
    error = float(np.max(np.abs(actual - expected))) if expected.size else 0.0
    assert error <= rtol * scale + atol, (
        f"{what}: max error {error:.3e} > {rtol:.1e} * {scale:.3e} + {atol:.1e}\n"
        f"actual   {actual.tolist()}\nexpected {expected.tolist()}"
    )


def same_rotation(q, q_ref, tol, what="quaternion"):
    """Quaternions (..., 4) equal up to the sign of each (q and -q are one rotation)."""
    q, q_ref = np.asarray(q, dtype=float), np.asarray(q_ref, dtype=float)
    error = np.minimum(np.linalg.norm(q - q_ref, axis=-1), np.linalg.norm(q + q_ref, axis=-1))
    assert np.max(error) <= tol, f"{what}: {np.max(error):.3e} > {tol:.1e}"


def finite_everywhere(result, what="result"):
    """Every float in the result is finite (arrays, tuples, dicts, dataclasses, Bodies)."""
    if result is None or isinstance(result, str | bool | int):
        return
    if isinstance(result, float):
        assert math.isfinite(result), f"{what} = {result}"
    elif isinstance(result, np.ndarray):
        if result.dtype.kind == "f":
            assert np.all(np.isfinite(result)), f"{what}: non-finite entries"
    elif isinstance(result, dict):
        for k, v in result.items():
            finite_everywhere(v, f"{what}[{k!r}]")
    elif isinstance(result, tuple | list):
        for k, v in enumerate(result):
            finite_everywhere(v, f"{what}[{k}]")
    elif isinstance(result, ph.Body):
        finite_everywhere((result.mass, result.center_of_mass, result.inertia), what)
    elif isinstance(result, ph.Principal):
        finite_everywhere((result.moments, result.axes), what)
    elif hasattr(result, "__dataclass_fields__"):
        for name in result.__dataclass_fields__:
            if name != "stats":
                finite_everywhere(getattr(result, name), f"{what}.{name}")


# ---------------------------------------------------------------------------------------------
# Closed forms of the motion (torque-free unless said), written from Euler's equations
# ---------------------------------------------------------------------------------------------


def quat_exp(axis_rate, t):
    """The body-fixed rotation at constant rate ``axis_rate`` (body axes) for time ``t``:
    (sin(|w| t / 2) w / |w|, cos(|w| t / 2)), xyzw."""
    w = np.asarray(axis_rate, dtype=float)
    n = float(np.linalg.norm(w))
    if n == 0.0:
        return np.array([0.0, 0.0, 0.0, 1.0])
    return np.concatenate([math.sin(n * t / 2) * w / n, [math.cos(n * t / 2)]])


def sphere_motion(omega0, times, q0=(0.0, 0.0, 0.0, 1.0)):
    """A sphere (or any body at rest, or spinning about a principal axis): omega constant and
    q(t) = q0 (x) exp(omega t / 2)."""
    w = np.tile(np.asarray(omega0, dtype=float), (len(times), 1))
    q = np.array([ref.qmul(np.asarray(q0, float), quat_exp(omega0, t)) for t in times])
    return w, q


def symmetric_omega(moments, omega0, times):
    """omega of a symmetric top (two equal moments, the distinct one anywhere in the triple):
    the component along the symmetry axis s is constant, the two others turn about it at
    Omega = w_s (I_s - I_t) / I_t (Euler's equations with I_a = I_b = I_t), in the order that
    keeps the sign of Euler's equations (s -> a -> b cyclic)."""
    i = [float(x) for x in moments]
    s = next(k for k in range(3) if i[k] != i[(k + 1) % 3] and i[k] != i[(k + 2) % 3])
    a, b = (s + 1) % 3, (s + 2) % 3
    w0 = np.asarray(omega0, dtype=float)
    rate = w0[s] * (i[s] - i[a]) / i[a]
    out = np.empty((len(times), 3))
    for n, t in enumerate(times):
        # I_a w_a' = (I_b - I_s) w_b w_s  =>  w_a' = -rate w_b,  w_b' = rate w_a
        c, sn = math.cos(rate * t), math.sin(rate * t)
        out[n, s] = w0[s]
        out[n, a] = w0[a] * c - w0[b] * sn
        out[n, b] = w0[a] * sn + w0[b] * c
    return out


def energy_exact(moments, omega) -> float:
    """T = sum I w^2 / 2 in exact rationals (then rounded once)."""
    return float(sum(Fraction(float(i)) * Fraction(float(w)) ** 2 for i, w in
                     zip(moments, omega, strict=True)) / 2)


def momentum_norm_exact(moments, omega) -> float:
    """|L| from the exact rational L^2 (mpmath square root at 40 digits)."""
    square = sum((Fraction(float(i)) * Fraction(float(w))) ** 2 for i, w in
                 zip(moments, omega, strict=True))
    with mpmath.workdps(40):
        return float(mpmath.sqrt(mpmath.mpf(square.numerator) / square.denominator))


# ---------------------------------------------------------------------------------------------
# 1. Constructors: every solid at its edges, point masses, tensors, engine formats, composites
# ---------------------------------------------------------------------------------------------

SOLIDS = {
    # name: (lengths at unit scale, their argument names); lengths 2 to 6 as in
    # test_mass_extremes, so that the boundaries below are exact powers of two.
    "sphere": ((3.0,), ("radius",)),
    "spherical_shell": ((3.0,), ("radius",)),
    "cuboid": (((3.0, 4.0, 5.0),), ("size",)),
    "cylinder": ((3.0, 6.0), ("radius", "length")),
    "tube": ((2.0, 3.0, 6.0), ("inner_radius", "outer_radius", "length")),
    "cone": ((3.0, 6.0), ("radius", "length")),
    "ellipsoid": (((3.0, 4.0, 5.0),), ("semi_axes",)),
    "rod": ((6.0,), ("length",)),
    "disk": ((3.0,), ("radius",)),
    "torus": ((3.0, 1.0), ("major_radius", "minor_radius")),
    "capsule": ((3.0, 6.0), ("radius", "length")),
}


def times_pow2(params, k: int):
    """Every length of ``params`` times 2^k (exact)."""
    return tuple(
        tuple(math.ldexp(x, k) for x in p) if isinstance(p, tuple) else math.ldexp(p, k)
        for p in params
    )


def with_first(params, value):
    """``params`` with the first length (or the first entry of a size vector) set to value."""
    first = params[0]
    if isinstance(first, tuple):
        return ((value, *first[1:]), *params[1:])
    return (value, *params[1:])


def largest_exponent(value: float, power: int) -> int:
    """The largest k with value 2^(power k) a double."""
    k = math.floor((1024 - math.log2(value)) / power) + 1
    while Fraction(value) * Fraction(2) ** (power * k) > Fraction(MAX):
        k -= 1
    return k


def solid_check(name, params, j, k):
    """The closed form of tests/reference.py at unit scale, times 2^j (mass) 2^(2k) (lengths
    squared), exactly: the body made with mass 2^j and lengths 2^k must match it within 16 eps
    (the closed form's few roundings on each side, as test_mass_extremes) plus two subnormal
    spacings where the moments underflow."""
    closed = ref.SOLIDS[name](1.0, *params)

    def check(body):
        close(body.mass, math.ldexp(1.0, j), 0.0, what="mass")
        close(body.inertia, np.ldexp(closed.inertia, j + 2 * k), 16 * EPS, 2 * TINY, "inertia")
        close(body.center_of_mass, np.ldexp(closed.center_of_mass, k), 16 * EPS, 2 * TINY,
              "center_of_mass")

    return check


for _name, (_params, _lengths) in SOLIDS.items():
    _make = getattr(ph.Body, _name)
    _first = _lengths[0]
    area = "constructors"
    err(area, f"{_name}/mass=0", lambda m=_make, p=_params: m(0.0, *p), ph.NonPositiveError,
        "mass")
    err(area, f"{_name}/mass=-1", lambda m=_make, p=_params: m(-1.0, *p), ph.NonPositiveError,
        "mass")
    err(area, f"{_name}/mass=nan", lambda m=_make, p=_params: m(NAN, *p), ph.NonFiniteError,
        "mass")
    err(area, f"{_name}/mass='1'", lambda m=_make, p=_params: m("1", *p), TypeError, "mass")
    err(area, f"{_name}/mass=1+0j", lambda m=_make, p=_params: m(1 + 0j, *p), TypeError, "mass")
    err(area, f"{_name}/{_first}=nan", lambda m=_make, p=_params: m(1.0, *with_first(p, NAN)),
        ph.NonFiniteError, _first)
    err(area, f"{_name}/{_first}=-inf", lambda m=_make, p=_params: m(1.0, *with_first(p, -INF)),
        ph.NonFiniteError, _first)
    if _name not in ("tube",):  # a tube's inner radius may be 0 (a cylinder), see below
        err(area, f"{_name}/{_first}=-1", lambda m=_make, p=_params: m(1.0, *with_first(p, -1.0)),
            ph.NonPositiveError, _first)
    # The overflow boundary in the lengths and in the mass: the largest power of two that fits
    # gives the closed form, the next raises naming the argument that drives it.
    _closed = float(np.max(ref.SOLIDS[_name](1.0, *_params).inertia))
    _k = largest_exponent(_closed, 2)
    _j = largest_exponent(_closed, 1)
    val(area, f"{_name}/lengths=2^{_k}", lambda m=_make, p=_params, k=_k: m(1.0, *times_pow2(p, k)),
        solid_check(_name, _params, 0, _k), "closed form x 2^2k")
    err(area, f"{_name}/lengths=2^{_k + 1}",
        lambda m=_make, p=_params, k=_k: m(1.0, *times_pow2(p, k + 1)), ph.ArgumentError,
        _lengths[-1] if _name in ("tube", "capsule", "cylinder", "cone") else _first,
        fragment="overflow")
    val(area, f"{_name}/mass=2^{_j}", lambda m=_make, p=_params, j=_j: m(math.ldexp(1.0, j), *p),
        solid_check(_name, _params, _j, 0), "closed form x 2^j")
    err(area, f"{_name}/mass=2^{_j + 1}",
        lambda m=_make, p=_params, j=_j: m(math.ldexp(1.0, j + 1), *p), ph.ArgumentError, "mass",
        fragment="overflow")
    # Tiny: lengths 2^-520 (moments ~2^-1038, subnormal), mass 2^-1070 (subnormal).
    val(area, f"{_name}/lengths=2^-520", lambda m=_make, p=_params: m(1.0, *times_pow2(p, -520)),
        solid_check(_name, _params, 0, -520), "closed form x 2^-1040, rounded to subnormals")
    val(area, f"{_name}/mass=2^-1070", lambda m=_make, p=_params: m(math.ldexp(1.0, -1070), *p),
        solid_check(_name, _params, -1070, 0), "closed form x 2^-1070, rounded to subnormals")
    val(area, f"{_name}/mass=2^600,lengths=2^-300",
        lambda m=_make, p=_params: m(math.ldexp(1.0, 600), *times_pow2(p, -300)),
        solid_check(_name, _params, 600, -300), "closed form x 2^0 (exact)")

area = "constructors"
SOLID = ph.Body.solid
err(area, "solid/kind='pyramid'", lambda: SOLID("pyramid", 1.0), ph.ArgumentError, "kind")
err(area, "solid/kind=3", lambda: SOLID(3, 1.0, radius=1.0), TypeError, "kind")
err(area, "solid/sphere without radius", lambda: SOLID("sphere", 1.0), TypeError, "radius")
err(area, "solid/sphere with a length", lambda: SOLID("sphere", 1.0, radius=1.0, length=2.0),
    TypeError, None, fragment="length")
err(area, "solid/radius='x'", lambda: SOLID("sphere", 1.0, radius="x"), TypeError, "radius")
err(area, "solid/radius=nan", lambda: SOLID("sphere", 1.0, radius=NAN), ph.NonFiniteError,
    "radius")
err(area, "solid/cuboid size (2,)", lambda: SOLID("cuboid", 1.0, size=(1.0, 2.0)), ph.ShapeError,
    "size")
err(area, "solid/point mass=0", lambda: SOLID("point", 0.0), ph.NonPositiveError, "mass")
val(area, "solid/point", lambda: SOLID("point", 2.5),
    lambda b: (close(b.mass, 2.5, 0.0), close(b.inertia, np.zeros((3, 3)), 0.0)),
    "a point mass: no inertia about itself")
val(area, "solid/cylinder at 2^500", lambda: SOLID("cylinder", 1.0, radius=3 * 2.0**500,
                                                   length=6 * 2.0**500),
    solid_check("cylinder", (3.0, 6.0), 0, 500), "closed form x 2^1000")
err(area, "cuboid/size=(1,2)", lambda: ph.Body.cuboid(1.0, (1.0, 2.0)), ph.ShapeError, "size")
err(area, "cuboid/size=[None,2,3]", lambda: ph.Body.cuboid(1.0, [None, 2.0, 3.0]), TypeError,
    "size")
err(area, "cuboid/size='abc'", lambda: ph.Body.cuboid(1.0, "abc"), TypeError, "size")
err(area, "ellipsoid/semi_axes=[[1,2,3]]", lambda: ph.Body.ellipsoid(1.0, [[1.0, 2.0, 3.0]]),
    ph.ShapeError, "semi_axes")
err(area, "ellipsoid/semi_axes=complex",
    lambda: ph.Body.ellipsoid(1.0, np.array([1.0, 2.0, 3.0]) + 0j), TypeError, "semi_axes")
err(area, "tube/inner=outer", lambda: ph.Body.tube(1.0, 2.0, 2.0, 1.0), ph.ArgumentError,
    "inner_radius")
err(area, "tube/inner=-1", lambda: ph.Body.tube(1.0, -1.0, 2.0, 1.0), ph.ArgumentError,
    "inner_radius")
val(area, "tube/inner=0", lambda: ph.Body.tube(2.0, 0.0, 3.0, 6.0),
    lambda b: close(b.inertia, ref.cylinder(2.0, 3.0, 6.0).inertia, 8 * EPS),
    "a tube without a hole is the cylinder's closed form")
err(area, "torus/minor>major", lambda: ph.Body.torus(1.0, 1.0, 2.0), ph.ArgumentError,
    "minor_radius")
val(area, "torus/horn(minor=major)", lambda: ph.Body.torus(1.0, 2.0, 2.0),
    lambda b: close(b.inertia, ref.torus(1.0, 2.0, 2.0).inertia, 8 * EPS), "closed form")
val(area, "capsule/length=0", lambda: ph.Body.capsule(5.0, 2.0, 0.0),
    lambda b: close(b.inertia, ref.sphere(5.0, 2.0).inertia, 8 * EPS),
    "a capsule of length 0 is the sphere's closed form")
val(area, "cylinder/radius=1e-300", lambda: ph.Body.cylinder(1.0, 1e-300, 2.0),
    lambda b: close(b.inertia, np.diag([1 / 3, 1 / 3, 0.0]), 8 * EPS, TINY),
    "closed form (m r^2 / 2 underflows to 0: a rod)")
err(area, "disk/radius=True", lambda: ph.Body.disk(1.0, True), TypeError, "radius")
err(area, "Body(3)", lambda: ph.Body(3), TypeError, None)

# Point masses
PM = ph.Body.point_masses
err(area, "point_masses/empty", lambda: PM([], np.zeros((0, 3))), ph.ShapeError, "masses")
err(area, "point_masses/count mismatch", lambda: PM([1.0, 2.0], [[0.0, 0.0, 0.0]]),
    ph.ShapeError, "positions")
err(area, "point_masses/mass=0", lambda: PM([1.0, 0.0], [[0, 0, 0], [1, 0, 0]]),
    ph.NonPositiveError, "masses")
err(area, "point_masses/mass=-2", lambda: PM([1.0, -2.0], [[0, 0, 0], [1, 0, 0]]),
    ph.NonPositiveError, "masses")
err(area, "point_masses/mass=inf", lambda: PM([INF], [[0, 0, 0]]), ph.NonFiniteError, "masses")
err(area, "point_masses/position=nan", lambda: PM([1.0], [[NAN, 0, 0]]), ph.NonFiniteError,
    "positions")
err(area, "point_masses/positions (1,2)", lambda: PM([1.0], [[0.0, 0.0]]), ph.ShapeError,
    "positions")
err(area, "point_masses/positions (3,)", lambda: PM([1.0], [0.0, 0.0, 0.0]), ph.ShapeError,
    "positions")
err(area, "point_masses/masses (1,1)", lambda: PM([[1.0]], [[0, 0, 0]]), ph.ShapeError, "masses")
err(area, "point_masses/masses='a'", lambda: PM("a", [[0, 0, 0]]), TypeError, "masses")
err(area, "point_masses/masses complex", lambda: PM([1 + 0j], [[0, 0, 0]]), TypeError, "masses")
err(area, "point_masses/positions=None", lambda: PM([1.0], None), TypeError, "positions")
err(area, "point_masses/masses [1,None]",
    lambda: PM(np.array([1, None], dtype=object), [[0, 0, 0], [1, 0, 0]]), TypeError, "masses")
err(area, "point_masses/sum of masses overflows",
    lambda: PM([1e308, 1e308], [[0, 0, 0], [1, 0, 0]]), ph.ArgumentError, "masses",
    fragment="overflow")
err(area, "point_masses/+-1e154", lambda: PM([1.0, 1.0], [[1e154, 0, 0], [-1e154, 0, 0]]),
    ph.ArgumentError, "positions", fragment="overflow")


def pm_check(masses, positions, rtol=4 * EPS, atol=0.0):
    """Against the exact rational sums of tests/reference.py; the centre of mass to 4 eps of
    the positions' size (norm-wise: it may be 0 while the points are not)."""
    exact = ref.point_mass_properties_exact(masses, positions)
    size = float(np.max(np.abs(positions)))

    def check(body):
        close(body.mass, exact.mass, rtol, what="mass")
        close(body.center_of_mass, exact.center_of_mass, rtol, atol + 4 * EPS * size,
              "center_of_mass")
        close(body.inertia, exact.inertia, rtol, atol, "inertia")

    return check


for _label, _m, _r in [
    ("masses 1e200 at +-1e50", [1e200, 1e200], [[1e50, 0, 0], [-1e50, 0, 0]]),
    ("masses 1e-300 at +-1e-100", [1e-300, 1e-300], [[1e-100, 0, 0], [-1e-100, 0, 0]]),
    ("+-1 about 1e8", [1.0, 1.0], [[1e8 + 1, 0, 0], [1e8 - 1, 0, 0]]),
    ("+-2^511", [1.0, 1.0], [[2.0**511, 0, 0], [-(2.0**511), 0, 0]]),
    ("one point", [3.0], [[1.0, -2.0, 5.0]]),
    ("masses 1 and 1e-20", [1.0, 1e-20], [[0, 0, 0], [1, 0, 0]]),
    ("subnormal masses", [5e-324, 5e-324], [[1.0, 0, 0], [-1.0, 0, 0]]),
    ("collinear", [1.0, 2.0, 3.0], [[0, 0, 1], [0, 0, 2], [0, 0, -4]]),
]:
    val(area, f"point_masses/{_label}", lambda m=_m, r=_r: PM(m, r),
        pm_check(_m, _r, atol=2 * TINY), "exact rational sums")
val(area, "point_masses/int and float32 dtypes",
    lambda: PM(np.array([1, 2]), np.array([[0, 0, 0], [1, 0, 0]], dtype=np.float32)),
    pm_check([1.0, 2.0], [[0, 0, 0], [1, 0, 0]]), "exact rational sums")

# Tensors: from_inertia, from_fullinertia, from_urdf_inertia
FI = ph.Body.from_inertia
err(area, "from_inertia/asymmetric", lambda: FI(1.0, [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]),
    ph.InertiaError, "inertia")
err(area, "from_inertia/indefinite", lambda: FI(1.0, np.diag([1.0, 1.0, -1.0])), ph.InertiaError,
    "inertia")
err(area, "from_inertia/triangle", lambda: FI(1.0, np.diag([1.0, 1.0, 3.0])), ph.InertiaError,
    "inertia")
err(area, "from_inertia/nan", lambda: FI(1.0, np.diag([1.0, NAN, 1.0])), ph.NonFiniteError,
    "inertia")
err(area, "from_inertia/(2,2)", lambda: FI(1.0, np.eye(2)), ph.ShapeError, "inertia")
err(area, "from_inertia/com (2,)", lambda: FI(1.0, np.eye(3), [0, 0]), ph.ShapeError,
    "center_of_mass")
err(area, "from_inertia/com inf", lambda: FI(1.0, np.eye(3), [0, 0, INF]), ph.NonFiniteError,
    "center_of_mass")
err(area, "from_inertia/mass=0", lambda: FI(0.0, np.eye(3)), ph.NonPositiveError, "mass")
err(area, "from_inertia/beyond the largest double",
    lambda: FI(1.0, [[1.45e308, 0, 0.45e308], [0, 1e308, 0], [0.45e308, 0, 1.45e308]]),
    ph.ArgumentError, "inertia", fragment="overflow")
for _label, _tensor in [
    ("8e307", np.eye(3) * 8e307),
    ("the largest double", np.eye(3) * MAX),
    ("1e-310 (subnormal)", np.eye(3) * 1e-310),
    ("zero (a point mass)", np.zeros((3, 3))),
    ("planar (I3 = I1 + I2)", np.diag([1.0, 2.0, 3.0])),
]:
    val(area, f"from_inertia/{_label}", lambda t=_tensor: FI(1.0, t),
        lambda b, t=_tensor: close(b.inertia, t, 8 * EPS, 2 * TINY, "inertia"),
        "the tensor given (round trip through the square-root form)")
val(area, "from_inertia/rod (0,1,1) principal",
    lambda: FI(2.0, np.diag([1.0, 1.0, 0.0])).principal(),
    lambda p: (close(p.moments, [0.0, 1.0, 1.0], 8 * EPS),
               np.testing.assert_array_equal(p.multiplicity, [1, 2, 2])),
    "the diagonal, ascending")
err(area, "from_fullinertia/(3,)", lambda: ph.Body.from_fullinertia(1.0, [1, 2, 3]),
    ph.ShapeError, "fullinertia")
err(area, "from_fullinertia/nan", lambda: ph.Body.from_fullinertia(1.0, [1, 1, 1, NAN, 0, 0]),
    ph.NonFiniteError, "fullinertia")
err(area, "from_fullinertia/indefinite", lambda: ph.Body.from_fullinertia(1.0, [1, 1, 1, 2, 0, 0]),
    ph.InertiaError, "fullinertia")
val(area, "from_fullinertia/MuJoCo order",
    lambda: ph.Body.from_fullinertia(1.0, [2, 3, 4, 0.1, 0.2, 0.3]),
    lambda b: close(b.inertia, [[2, 0.1, 0.2], [0.1, 3, 0.3], [0.2, 0.3, 4]], 8 * EPS),
    "(xx, yy, zz, xy, xz, yz) as tensor elements")
URDF = {"ixx": 2.0, "ixy": 0.1, "ixz": 0.2, "iyy": 3.0, "iyz": 0.3, "izz": 4.0}
err(area, "from_urdf_inertia/ixy=nan",
    lambda: ph.Body.from_urdf_inertia(1.0, **{**URDF, "ixy": NAN}),
    ph.NonFiniteError, "ixy")
err(area, "from_urdf_inertia/izz='4'",
    lambda: ph.Body.from_urdf_inertia(1.0, **{**URDF, "izz": "4"}),
    TypeError, "izz")
err(area, "from_urdf_inertia/izz=9 (triangle)",
    lambda: ph.Body.from_urdf_inertia(1.0, **{**URDF, "izz": 9.0}), ph.InertiaError, "inertia")
val(area, "from_urdf_inertia/values", lambda: ph.Body.from_urdf_inertia(1.0, **URDF),
    lambda b: close(b.inertia, [[2, 0.1, 0.2], [0.1, 3, 0.3], [0.2, 0.3, 4]], 8 * EPS),
    "URDF attributes as tensor elements")

# Composites
area = "constructors"
err(area, "composite/mass overflows",
    lambda: ph.Body.sphere(1e308, 1.0) + ph.Body.sphere(1e308, 1.0),
    ph.ArgumentError, "other", fragment="overflow")
err(area, "composite/m d^2 overflows",
    lambda: ph.Body.sphere(1.0, 1.0).translated([1e200, 0, 0])
    + ph.Body.sphere(1.0, 1.0).translated([-1e200, 0, 0]),
    ph.ArgumentError, "other", fragment="overflow")
err(area, "composite/+ 1", lambda: ph.Body.sphere(1.0, 1.0) + 1, TypeError, None)


def composite_check(parts_ref, rtol=16 * EPS):
    exact = ref.compose(parts_ref)

    def check(body):
        close(body.mass, exact.mass, rtol, what="mass")
        close(body.center_of_mass, exact.center_of_mass, rtol, TINY, "center_of_mass")
        close(body.inertia, exact.inertia, rtol, TINY, "inertia")

    return check


val(area, "composite/1e200-mass spheres at +-1 (m d^2 kept)",
    lambda: ph.Body.sphere(1e200, 1.0).translated([1, 0, 0])
    + ph.Body.sphere(1e200, 1.0).translated([-1, 0, 0]),
    composite_check([ref.translate(ref.sphere(1e200, 1.0), [1, 0, 0]),
                     ref.translate(ref.sphere(1e200, 1.0), [-1, 0, 0])]),
    "parallel-axis sum (tests/reference.py)")
val(area, "composite/spheres at +-1e100",
    lambda: ph.Body.sphere(1.0, 1.0).translated([1e100, 0, 0])
    + ph.Body.sphere(1.0, 1.0).translated([-1e100, 0, 0]),
    composite_check([ref.translate(ref.sphere(1.0, 1.0), [1e100, 0, 0]),
                     ref.translate(ref.sphere(1.0, 1.0), [-1e100, 0, 0])]),
    "parallel-axis sum")
_MU = 1e-12 / (1 + 1e-12)  # the reduced mass of the speck at distance 1
val(area, "composite/heavy sphere and a 1e-12 speck",
    lambda: (ph.Body.sphere(1.0, 1.0) + ph.Body.point_masses([1e-12], [[1.0, 0, 0]])).principal(),
    lambda p: (np.testing.assert_array_equal(p.multiplicity, [1, 2, 2]),
               close(abs(p.axes[0, 0]), 1.0, 4 * EPS, what="axis 0 along x"),
               close(p.moments[1] - p.moments[0], _MU, 8 * EPS * 0.4 / _MU, what="anisotropy")),
    "closed form: moments 0.4, 0.4 + mu, 0.4 + mu (mu = m / (1 + m)); the gap to 8 eps of 0.4")
val(area, "composite/two crossed rods (sum())",
    lambda: sum([ph.Body.rod(1.0, 2.0), ph.Body.rod(1.0, 2.0).rotated([[0, 0, 1], [0, 1, 0],
                                                                          [-1, 0, 0]])]),
    lambda b: close(b.inertia, np.diag([1 / 3, 2 / 3, 1 / 3]), 8 * EPS),
    "two crossed rods: m L^2 / 12 about each perpendicular axis")

# ---------------------------------------------------------------------------------------------
# 2. Body methods: shifts, rotations, inertia about a point and in axes, scaling, queries
# ---------------------------------------------------------------------------------------------

area = "body"
BOX = ph.Body.cuboid(2.0, (1.0, 2.0, 3.0))
BOX_REF = ref.cuboid(2.0, (1.0, 2.0, 3.0))
err(area, "translated/nan", lambda: BOX.translated([NAN, 0, 0]), ph.NonFiniteError, "offset")
err(area, "translated/(2,)", lambda: BOX.translated([1.0, 0.0]), ph.ShapeError, "offset")
err(area, "translated/str", lambda: BOX.translated("up"), TypeError, "offset")
err(area, "translated/1e308 twice", lambda: BOX.translated([1e308, 0, 0]).translated([1e308, 0, 0]),
    ph.ArgumentError, "offset", fragment="overflow")
val(area, "translated/1e308", lambda: BOX.translated([1e308, 0, 0]),
    lambda b: (close(b.center_of_mass, [1e308, 0, 0], 0.0),
               close(b.inertia, BOX_REF.inertia, 8 * EPS)),
    "the offset; the inertia about the centre of mass unchanged")
err(area, "rotated/not orthogonal", lambda: BOX.rotated(np.eye(3) * 2), ph.ArgumentError,
    "rotation")
err(area, "rotated/reflection", lambda: BOX.rotated(np.diag([1.0, 1.0, -1.0])), ph.ArgumentError,
    "rotation")
err(area, "rotated/zero quaternion", lambda: BOX.rotated([0, 0, 0, 0]), ph.ArgumentError,
    "rotation")
err(area, "rotated/nan quaternion", lambda: BOX.rotated([NAN, 0, 0, 1]), ph.NonFiniteError,
    "rotation")
err(area, "rotated/(3,)", lambda: BOX.rotated([1.0, 0.0, 0.0]), ph.ShapeError, "rotation")
err(area, "rotated/str", lambda: BOX.rotated("x"), TypeError, "rotation")
err(area, "rotated/Rotation stack",
    lambda: BOX.rotated(Rotation.from_rotvec([[0, 0, 1], [0, 1, 0]])),
    ph.ShapeError, "rotation")
_Q45 = np.array([1.0, 0.0, 0.0, 1.0])
for _label, _q in [("quaternion 1e300", _Q45 * 1e300), ("quaternion 1e-320", _Q45 * 1e-320),
                   ("unnormalised quaternion", _Q45 * 3.0)]:
    val(area, f"rotated/{_label}", lambda q=_q: BOX.rotated(q),
        lambda b: close(b.inertia, ref.rotate(BOX_REF, Rotation.from_rotvec([math.pi / 2, 0, 0]))
                        .inertia, 8 * EPS),
        "R I R^T, R a quarter turn about x (scipy)")
err(area, "inertia_about/point nan", lambda: BOX.inertia_about([NAN, 0, 0]), ph.NonFiniteError,
    "point")
err(area, "inertia_about/point 1e200", lambda: BOX.inertia_about([1e200, 0, 0]), ph.ArgumentError,
    "point", fragment="overflow")
err(area, "inertia_about/axes not orthogonal", lambda: BOX.inertia_about([0, 0, 0], np.eye(3) * 2),
    ph.ArgumentError, "axes")
err(area, "inertia_about/axes (2,2)", lambda: BOX.inertia_about([0, 0, 0], np.eye(2)),
    ph.ShapeError, "axes")
val(area, "inertia_about/point 1e100", lambda: BOX.inertia_about([1e100, 0, 0]),
    lambda i: close(i, ref.parallel_axis(BOX_REF.inertia, 2.0, [0, 0, 0], [1e100, 0, 0]),
                    8 * EPS),
    "Steiner (tests/reference.py)")
val(area, "inertia_about/axes as quaternion", lambda: BOX.inertia_about([0, 1, 0], [0, 0, 1, 1]),
    lambda i: close(i, (lambda a: a.T @ ref.parallel_axis(BOX_REF.inertia, 2.0, [0, 0, 0],
                                                           [0, 1, 0]) @ a)(
        Rotation.from_quat([0, 0, 1, 1]).as_matrix()), 8 * EPS),
    "A^T I_p A with A from scipy")
err(area, "scaled/mass_scale=0", lambda: BOX.scaled(0.0, 1.0), ph.NonPositiveError, "mass_scale")
err(area, "scaled/length_scale=-1", lambda: BOX.scaled(1.0, -1.0), ph.NonPositiveError,
    "length_scale")
err(area, "scaled/mass_scale=nan", lambda: BOX.scaled(NAN, 1.0), ph.NonFiniteError, "mass_scale")
err(area, "scaled/length_scale=1e200", lambda: BOX.scaled(1.0, 1e200), ph.ArgumentError,
    "length_scale", fragment="overflow")
err(area, "scaled/mass_scale=1e308", lambda: BOX.scaled(1e308, 1.0), ph.ArgumentError,
    "mass_scale", fragment="overflow")
val(area, "scaled/2^-500 and 2^-250", lambda: BOX.scaled(2.0**-500, 2.0**-250),
    lambda b: close(b.inertia, np.ldexp(BOX_REF.inertia, -1000), 8 * EPS, 2 * TINY),
    "closed form x 2^-1000 (subnormal)")
err(area, "principal/rtol=-1", lambda: BOX.principal(-1.0), ph.ArgumentError, "rtol")
err(area, "principal/rtol=nan", lambda: BOX.principal(NAN), ph.ArgumentError, "rtol")
err(area, "principal/rtol='x'", lambda: BOX.principal("x"), TypeError, "rtol")
err(area, "angular_momentum_body/nan", lambda: BOX.angular_momentum_body([NAN, 0, 0]),
    ph.NonFiniteError, "omega")
err(area, "angular_momentum_body/1e308", lambda: BOX.angular_momentum_body([1e308, 0, 0]),
    ph.ArgumentError, "omega", fragment="overflow")
err(area, "kinetic_energy/1e200", lambda: BOX.kinetic_energy([1e200, 0, 0]), ph.ArgumentError,
    "omega", fragment="overflow")
err(area, "kinetic_energy/(2,)", lambda: BOX.kinetic_energy([1.0, 0.0]), ph.ShapeError, "omega")
val(area, "kinetic_energy/1e150", lambda: BOX.kinetic_energy([1e150, 1e150, 0]),
    lambda e: close(e, energy_exact(np.diag(BOX_REF.inertia), [1e150, 1e150, 0]), 4 * EPS),
    "exact rational T")
val(area, "angular_momentum_body/1e-300", lambda: BOX.angular_momentum_body([1e-300, 0, 1e-300]),
    lambda m: close(m, np.diag(BOX_REF.inertia) * [1e-300, 0, 1e-300], 4 * EPS), "I w")
val(area, "to_urdf_inertial/T-handle (gimbal lock, no warning)",
    lambda: (ph.Body.cylinder(1.0, 0.02, 0.3)
             + ph.Body.cylinder(0.5, 0.02, 0.2).rotated([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
             .translated([0, 0, 0.15])).to_urdf_inertial(),
    lambda text: (lambda rpy: close(ref.fixed_axis_rpy_matrix(*rpy), (
        ph.Body.cylinder(1.0, 0.02, 0.3)
        + ph.Body.cylinder(0.5, 0.02, 0.2).rotated([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
        .translated([0, 0, 0.15])).principal().axes, 8 * EPS))(
        [float(x) for x in text.split('rpy="')[1].split('"')[0].split()]),
    "rpy read back through the textbook Rz Ry Rx (tests/reference.py)")

# ---------------------------------------------------------------------------------------------
# 3. principal(): scaled, degenerate, non-symmetric, indefinite, single and batched
# ---------------------------------------------------------------------------------------------

area = "principal"
_R = ref.random_rotation(np.random.default_rng(13))
SPD = _R @ np.diag([1.0, 2.0, 3.5]) @ _R.T
SPD = (SPD + SPD.T) / 2


def principal_check(tensor, multiplicity=(1, 1, 1)):
    """Moments within 10 eps ||A|| of the mpmath eigenvalues of the tensor as given (Weyl), plus
    two subnormal spacings; the axes' residual and orthogonality (conftest.check_eigen) on the
    tensor times a power of two (exact)."""
    a = np.asarray(tensor, dtype=float)
    exact = ref.eigvalsh_mp(a)
    bound = 10 * EPS * max(abs(v) for v in exact) + 2 * TINY

    def check(p):
        for k in range(3):
            assert abs(mpmath.mpf(float(p.moments[k])) - exact[k]) <= bound, (k, p.moments, exact)
        np.testing.assert_array_equal(p.multiplicity, multiplicity)
        if np.max(np.abs(a)) >= sys.float_info.min:
            e = math.frexp(float(np.max(np.abs(a))))[1]
            check_eigen(np.ldexp(a, -e), np.ldexp(p.moments, -e), p.axes)

    return check


for _exponent in [-320, -310, -300, -200, -154, -100, 0, 100, 154, 200, 300, 307]:
    _a = SPD * 10.0**_exponent
    val(area, f"SPD x 1e{_exponent}", lambda a=_a: ph.principal(a), principal_check(_a),
        "mpmath eigenvalues (60 digits)")
_top = _R @ np.diag([1.0, 1.0, 2.0]) @ _R.T
_top = (_top + _top.T) / 2
for _exponent in [-300, 0, 154, 300]:
    _a = _top * 10.0**_exponent
    val(area, f"symmetric top x 1e{_exponent}", lambda a=_a: ph.principal(a),
        principal_check(_a, (2, 2, 1)), "mpmath eigenvalues; multiplicity 2 2 1")
val(area, "sphere 1.5e300", lambda: ph.principal(np.eye(3) * 1.5e300),
    principal_check(np.eye(3) * 1.5e300, (3, 3, 3)), "the diagonal; multiplicity 3 3 3")
val(area, "indefinite", lambda: ph.principal(np.diag([-1.0, 2.0, 3.0])),
    principal_check(np.diag([-1.0, 2.0, 3.0])), "the diagonal (any symmetric tensor)")
val(area, "zero", lambda: ph.principal(np.zeros((3, 3))),
    principal_check(np.zeros((3, 3)), (3, 3, 3)), "0 0 0, multiplicity 3")
val(area, "+-the largest double", lambda: ph.principal(np.diag([MAX, 1.0, -MAX])),
    principal_check(np.diag([MAX, 1.0, -MAX])), "the diagonal")
_big = np.array([[0.85e308, 0.8e308, 0.0], [0.8e308, 0.85e308, 0.0], [0.0, 0.0, 1e308]])
val(area, "moments up to 1.65e308", lambda: ph.principal(_big), principal_check(_big),
    "mpmath eigenvalues")
err(area, "a moment beyond the largest double",
    lambda: ph.principal([[1e308, 0.9e308, 0], [0.9e308, 1e308, 0], [0, 0, 1e308]]),
    ph.ArgumentError, "inertia", fragment="overflow")
val(area, "integer dtype", lambda: ph.principal(np.diag([3, 1, 2])),
    principal_check(np.diag([3.0, 1.0, 2.0])), "the diagonal")
val(area, "float32 dtype", lambda: ph.principal(SPD.astype(np.float32)),
    principal_check(SPD.astype(np.float32).astype(float)), "mpmath, of the float32 values")
err(area, "non-symmetric", lambda: ph.principal([[1, 1, 0], [0, 1, 0], [0, 0, 1]]),
    ph.InertiaError, "inertia")
err(area, "nan", lambda: ph.principal(np.diag([NAN, 2.0, 3.0])), ph.NonFiniteError, "inertia")
err(area, "inf off the diagonal", lambda: ph.principal([[1, INF, 0], [INF, 1, 0], [0, 0, 1]]),
    ph.NonFiniteError, "inertia")
err(area, "(3,)", lambda: ph.principal(np.ones(3)), ph.ShapeError, "inertia")
err(area, "(2,2,3,3)", lambda: ph.principal(np.zeros((2, 2, 3, 3))), ph.ShapeError, "inertia")
err(area, "(3,4)", lambda: ph.principal(np.zeros((3, 4))), ph.ShapeError, "inertia")
err(area, "str", lambda: ph.principal("I"), TypeError, "inertia")
err(area, "complex", lambda: ph.principal(SPD + 0j), TypeError, "inertia")
err(area, "rtol=-1", lambda: ph.principal(SPD, -1.0), ph.ArgumentError, "rtol")
err(area, "rtol=inf", lambda: ph.principal(SPD, INF), ph.ArgumentError, "rtol")
err(area, "batch/nan in tensor 1", lambda: ph.principal(np.stack([SPD, np.diag([NAN, 2, 3.0])])),
    ph.NonFiniteError, "inertia", body=1)
err(area, "batch/non-symmetric tensor 2",
    lambda: ph.principal(np.stack([SPD, SPD, [[1, 1, 0], [0, 1, 0], [0, 0, 1.0]]])),
    ph.InertiaError, "inertia", body=2)
err(area, "batch/overflow in tensor 1",
    lambda: ph.principal(
        np.stack([_big, [[1e308, 0.9e308, 0], [0.9e308, 1e308, 0], [0, 0, 1e308]]])),
    ph.ArgumentError, "inertia", body=1)
val(area, "batch/empty", lambda: ph.principal(np.zeros((0, 3, 3))),
    lambda p: (np.testing.assert_array_equal(p.moments.shape, (0, 3)),
               np.testing.assert_array_equal(p.axes.shape, (0, 3, 3))), "shapes (0, 3), (0, 3, 3)")


def batch_check(tensors, multiplicities):
    checks = [principal_check(t, m) for t, m in zip(tensors, multiplicities, strict=True)]

    def check(p):
        for k, c in enumerate(checks):
            c(ph.Principal(p.moments[k], p.axes[k], p.multiplicity[k]))

    return check


_batch = [SPD * 1e-300, _top, np.eye(3) * 2.0, SPD * 1e300]
val(area, "batch/mixed scales and multiplicities", lambda: ph.principal(np.stack(_batch)),
    batch_check(_batch, [(1, 1, 1), (2, 2, 1), (3, 3, 3), (1, 1, 1)]), "mpmath, tensor by tensor")

# ---------------------------------------------------------------------------------------------
# 4. simulate, per method: every argument and keyword at its edges
# ---------------------------------------------------------------------------------------------

M123 = (1.0, 2.0, 3.0)
W = np.array([0.3, 1.0, -0.4])
TIMES = np.array([0.0, 0.5, 1.25, 2.0])
TILT = Rotation.from_rotvec([0.3, -0.2, 0.5]).as_quat()
SETTINGS = {
    "exact": {},
    "splitting": {"dt": 1e-3},
    "midpoint": {"dt": 1e-3},
    "rk4": {"dt": 1e-3},
    "dop853": {"rtol": 1e-12},
}
# Each method's own error over TIMES at these settings, relative to max |omega| (order 4 for
# splitting and rk4 at dt = 1e-3, order 2 for the midpoint rule, dop853 at rtol 1e-12), the
# exact solution to the reference's own accuracy (scipy DOP853 at rtol 1e-13: 1e-11 here).
BOUND = {"exact": 1e-11, "splitting": 1e-8, "midpoint": 1e-6, "rk4": 1e-9, "dop853": 1e-8}
# Against a closed form evaluated in doubles: the exact solution to a few hundred eps (the phase
# of a few radians carries a few ulp of it), the integrators as above.
CLOSED = {**BOUND, "exact": 256 * EPS}
_memo: dict = {}


def memo(key, make):
    if key not in _memo:
        _memo[key] = make()
    return _memo[key]


def scipy_motion(moments_or_tensor, omega0, times, q0=(0.0, 0.0, 0.0, 1.0)):
    """omega and q by scipy's DOP853 on Euler's equations with the full tensor (reference.py)."""
    tensor = np.asarray(moments_or_tensor, dtype=float)
    if tensor.shape == (3,):
        tensor = np.diag(tensor)
    key = ("scipy", tensor.tobytes(), np.asarray(omega0, float).tobytes(),
           np.asarray(times, float).tobytes(), np.asarray(q0, float).tobytes())
    return memo(key, lambda: rigid_body(tensor, np.asarray(omega0, float), np.asarray(q0, float),
                                        np.asarray(times, float), lambda t, w, q: np.zeros(3)))


def motion_check(method, omega_ref, q_ref=None, scale_w=1.0, closed=False, moments=None,
                 omega0=None):
    """omega (and q) against a reference, to the method's bound; with ``moments``, T and |L|
    of every output against their exact values at t0 (the motion conserves both)."""
    bound = (CLOSED if closed else BOUND)[method]

    def check(sol):
        w_ref = np.asarray(omega_ref() if callable(omega_ref) else omega_ref, dtype=float)
        close(sol.omega / scale_w, w_ref / scale_w, bound, what="omega")
        if q_ref is not None:
            q = np.asarray(q_ref() if callable(q_ref) else q_ref, dtype=float)
            same_rotation(sol.quaternion, q, max(bound, 64 * EPS))
        if moments is not None:
            energy = energy_exact(moments, omega0)
            norm = momentum_norm_exact(moments, omega0)
            conserve = {"exact": 64 * EPS, "midpoint": 64 * EPS, "splitting": bound}.get(
                method, bound)
            close(sol.energy, np.full(sol.energy.shape, energy), conserve, what="energy")
            close(np.linalg.norm(sol.angular_momentum_body, axis=-1),
                  np.full(sol.energy.shape, norm), max(conserve, 64 * EPS), what="|L|")

    return check


def sim(method, *args, **kwargs):
    return lambda: ph.simulate(*args, method=method, **{**SETTINGS[method], **kwargs})


def scaled_omega_check(method, moments, w, times, s):
    """(I, s w) at t/s is s times (I, w) at t (Euler's equations are homogeneous in omega and
    1/t): against scipy at unit scale; q(t/s) of (I, s w) is q(t) of (I, w)."""

    def check(sol):
        w_ref, q_ref = scipy_motion(moments, w, times)
        close(sol.omega / s, w_ref, BOUND[method], what="omega / s")
        same_rotation(sol.quaternion, q_ref, max(BOUND[method], 64 * EPS))

    return check


_T = np.array([[3.0, 0.4, -0.2], [0.4, 2.0, 0.3], [-0.2, 0.3, 1.5]])
_B = ph.Body.cuboid(1.0, (1.0, 1.6, 2.5)).rotated(Rotation.from_rotvec([0.4, -0.7, 0.5]))

for method in SETTINGS:
    area = f"simulate/{method}"
    fixed = method in ("splitting", "midpoint", "rk4")
    # --- errors common to every method ---------------------------------------------------
    err(area, "omega0=nan", sim(method, M123, [NAN, 0, 0], 1.0), ph.NonFiniteError, "omega0")
    err(area, "omega0=-inf", sim(method, M123, [0, -INF, 0], 1.0), ph.NonFiniteError, "omega0")
    err(area, "omega0 (2,)", sim(method, M123, [1.0, 0.0], 1.0), ph.ShapeError, "omega0")
    err(area, "omega0 (2,2,3)", sim(method, M123, np.ones((2, 2, 3)), 1.0), ph.ShapeError,
        "omega0")
    err(area, "omega0='abc'", sim(method, M123, "abc", 1.0), TypeError, "omega0")
    err(area, "omega0=[1,None,2]", sim(method, M123, [1.0, None, 2.0], 1.0), TypeError, "omega0")
    err(area, "omega0 complex", sim(method, M123, W + 0j, 1.0), TypeError, "omega0")
    err(area, "omega0=1e200 (T overflows)", sim(method, M123, [1e200, 1e200, 1e200], 1.0),
        ph.ArgumentError, "omega0", fragment="overflow")
    err(area, "moments (0,1,1)", sim(method, [0.0, 1.0, 1.0], W, 1.0), ph.ArgumentError, "body")
    err(area, "moments (-1,1,1)", sim(method, [-1.0, 1.0, 1.0], W, 1.0), ph.ArgumentError, "body")
    err(area, "moments (inf,1,1)", sim(method, [INF, 1.0, 1.0], W, 1.0), ph.ArgumentError, "body")
    err(area, "tensor not symmetric", sim(method, [[1, 1, 0], [0, 2, 0], [0, 0, 3.0]], W, 1.0),
        ph.InertiaError, "body")
    err(area, "tensor indefinite", sim(method, np.diag([-1.0, 2.0, 3.0]), W, 1.0),
        ph.ArgumentError, "body")
    err(area, "body=rod", sim(method, ph.Body.rod(1.0, 1.0), W, 1.0), ph.ArgumentError, "body")
    err(area, "body='box'", sim(method, "box", W, 1.0), TypeError, "body")
    err(area, "body (2,3) for one omega0", sim(method, np.ones((2, 3)), W, 1.0), ph.ShapeError,
        "body")
    err(area, "t=[0,nan]", sim(method, M123, W, [0.0, NAN]), ph.NonFiniteError, "t")
    err(area, "t decreasing", sim(method, M123, W, [0.0, 2.0, 1.0]), ph.ArgumentError, "t")
    err(area, "t before t0", sim(method, M123, W, [0.0, 1.0], t0=0.5), ph.ArgumentError, "t")
    err(area, "t=[]", sim(method, M123, W, []), ph.ShapeError, "t")
    err(area, "t (1,2)", sim(method, M123, W, [[0.0, 1.0]]), ph.ShapeError, "t")
    err(area, "t='soon'", sim(method, M123, W, "soon"), TypeError, "t")
    err(area, "t0=inf", sim(method, M123, W, 1.0, t0=INF), ph.NonFiniteError, "t0")
    err(area, "t0='0'", sim(method, M123, W, 1.0, t0="0"), TypeError, "t0")
    err(area, "orientation0 zero quaternion", sim(method, M123, W, 1.0, orientation0=[0, 0, 0, 0]),
        ph.ArgumentError, "orientation0")
    err(area, "orientation0 reflection",
        sim(method, M123, W, 1.0, orientation0=np.diag([1.0, 1.0, -1.0])), ph.ArgumentError,
        "orientation0")
    err(area, "orientation0 nan", sim(method, M123, W, 1.0, orientation0=[NAN, 0, 0, 1]),
        ph.NonFiniteError, "orientation0")
    err(area, "orientation0 (3,)", sim(method, M123, W, 1.0, orientation0=[0, 0, 1.0]),
        ph.ShapeError, "orientation0")
    err(area, "batch/omega0 nan in body 2",
        sim(method, np.tile(M123, (3, 1)), np.array([W, W, [0, NAN, 0]]), 1.0), ph.NonFiniteError,
        "omega0", body=2)
    err(area, "batch/moments zero in body 1",
        sim(method, np.array([M123, [1.0, 0.0, 1.0], M123]), np.array([W, W, W]), 1.0),
        ph.ArgumentError, "body", body=1)
    err(area, "batch/a rod among Bodies",
        sim(method, [ph.Body.sphere(1.0, 1.0), ph.Body.rod(1.0, 1.0)], np.array([W, W]), 1.0),
        ph.ArgumentError, "body", body=1)
    err(area, "batch/2 orientations for 3 bodies",
        sim(method, M123, np.array([W, W, W]), 1.0, orientation0=np.tile([0, 0, 0, 1.0], (2, 1))),
        ph.ShapeError, "orientation0")
    err(area, "batch/zero quaternion for body 1",
        sim(method, M123, np.array([W, W, W]), 1.0,
            orientation0=np.array([[0, 0, 0, 1.0], [0, 0, 0, 0], [0, 0, 0, 1]])),
        ph.ArgumentError, "orientation0", body=1)
    err(area, "batch/2 Bodies for 3 rows", sim(method, [ph.Body.sphere(1.0, 1.0)] * 2,
                                               np.array([W, W, W]), 1.0), ph.ShapeError, "body")
    err(area, "max_steps=0", sim(method, M123, W, 1.0, max_steps=0), ph.ArgumentError, "max_steps")
    err(area, "max_steps=1.5", sim(method, M123, W, 1.0, max_steps=1.5), TypeError, "max_steps")
    err(area, "method=3", lambda: ph.simulate(M123, W, 1.0, method=3), TypeError, "method")
    err(area, "progress='yes'", sim(method, M123, W, 1.0, progress="yes"), TypeError, "progress")
    err(area, "progress raises", sim(method, M123, W, 1.0, progress=lambda f: 1 / 0),
        ZeroDivisionError, None)
    err(area, "orientation0 Rotation stack of 2 for one body",
        sim(method, M123, W, 1.0, orientation0=Rotation.from_rotvec([[0, 0, 1.0], [0, 1.0, 0]])),
        ph.ShapeError, "orientation0")
    # --- values common to every method ---------------------------------------------------
    val(area, "rest", sim(method, M123, [0.0, 0.0, 0.0], TIMES, orientation0=TILT),
        motion_check(method, np.zeros((4, 3)), np.tile(TILT, (4, 1)), closed=True,
                     moments=M123, omega0=[0, 0, 0]),
        "omega = 0, q = q0, T = |L| = 0")
    val(area, "sphere", sim(method, [2.0, 2.0, 2.0], W, TIMES, orientation0=TILT),
        motion_check(method, *sphere_motion(W, TIMES, TILT), closed=True, moments=(2, 2, 2),
                     omega0=W),
        "closed form: omega constant, q0 exp(omega t / 2)")
    for _moments in [(1.0, 1.0, 2.0), (2.0, 3.0, 2.0), (3.0, 2.0, 2.0), (1.0, 1.0, 3.0)]:
        val(area, f"symmetric {_moments}", sim(method, _moments, W, TIMES),
            motion_check(method, symmetric_omega(_moments, W, TIMES), closed=True,
                         moments=_moments, omega0=W),
            "closed form of the symmetric top (distinct moment anywhere; (1,1,3) breaks "
            "I1 + I2 >= I3)")
    val(area, "asymmetric (1,2,3) with q", sim(method, M123, W, TIMES, orientation0=TILT),
        motion_check(method, lambda: scipy_motion(M123, W, TIMES, TILT)[0],
                     lambda: scipy_motion(M123, W, TIMES, TILT)[1], moments=M123, omega0=W),
        "scipy DOP853 (reference.rigid_body)")
    val(area, "breaks I1 + I2 >= I3 (1,2,4)", sim(method, (1.0, 2.0, 4.0), W, TIMES),
        motion_check(method, lambda: scipy_motion((1.0, 2.0, 4.0), W, TIMES)[0]),
        "scipy DOP853")
    val(area, "tensor in non-principal axes", sim(method, _T, W, TIMES, orientation0=TILT),
        motion_check(method, lambda: scipy_motion(_T, W, TIMES, TILT)[0],
                     lambda: scipy_motion(_T, W, TIMES, TILT)[1]),
        "scipy DOP853 with the full tensor in body axes")
    val(area, "Body in non-principal axes", sim(method, _B, W, TIMES),
        motion_check(method, lambda: scipy_motion(_B.inertia, W, TIMES)[0],
                     lambda: scipy_motion(_B.inertia, W, TIMES)[1]),
        "scipy DOP853 with the Body's tensor")
    for _s in (1e-150, 1e150):
        val(area, f"moments x {_s:g}", sim(method, np.multiply(M123, _s), W, TIMES),
            motion_check(method, lambda: scipy_motion(M123, W, TIMES)[0]),
            "scipy at unit moments (omega depends on the ratios only)")
    for _s in (1e-150, 1e100):
        _kw = {"dt": 1e-3 / _s} if fixed else {}
        val(area, f"omega0 x {_s:g}, t / {_s:g}", sim(method, M123, W * _s, TIMES / _s, **_kw),
            scaled_omega_check(method, M123, W, TIMES, _s), "scipy at unit scale, scaled")
    val(area, "t0=1e6", sim(method, M123, W, 1e6 + TIMES, t0=1e6),
        motion_check(method, lambda: scipy_motion(M123, W, TIMES)[0]),
        "scipy from 0 (the motion is time-invariant)")
    val(area, "t0=-3, negative times", sim(method, M123, W, TIMES - 3.0, t0=-3.0),
        motion_check(method, lambda: scipy_motion(M123, W, TIMES)[0]), "scipy from 0")
    val(area, "repeated output times", sim(method, M123, W, [0.0, 1.25, 1.25, 1.25, 2.0]),
        motion_check(method, lambda: scipy_motion(M123, W, [0.0, 1.25, 1.25, 1.25, 2.0])[0]),
        "scipy")
    # The integrators return omega0 itself at t0; the exact solution evaluates its closed form
    # there (a few eps).
    val(area, "t = [t0]", sim(method, M123, W, [0.0]),
        lambda sol, b=(CLOSED[method] if method == "exact" else 0.0): close(sol.omega, [W], b),
        "omega0 itself")
    val(area, "end time only (t=2)", sim(method, M123, W, 2.0),
        lambda sol, b=BOUND[method]: (assert_true(sol.t[0] == 0.0 and sol.t[-1] == 2.0),
                                      assert_true(sol.t.size >= 49 and np.all(np.diff(sol.t) > 0)),
                                      close(sol.omega, scipy_motion(M123, W, sol.t)[0], b)),
        "scipy at every output time from t0 to 2 (at least 49 of them)")
    val(area, "orientation=False", sim(method, M123, W, TIMES, orientation=False),
        lambda sol, b=BOUND[method]: (assert_none(sol.quaternion),
                                      close(sol.omega, scipy_motion(M123, W, TIMES)[0], b)),
        "scipy; no quaternion")
    val(area, "batch/sphere, top, rest",
        sim(method, np.array([[2.0, 2.0, 2.0], [1.0, 1.0, 2.0], [1.0, 2.0, 3.0]]),
            np.array([W, W, [0.0, 0.0, 0.0]]), TIMES),
        lambda sol, b=CLOSED[method]: close(
            sol.omega, [np.tile(W, (4, 1)), symmetric_omega((1, 1, 2), W, TIMES),
                        np.zeros((4, 3))], b),
        "closed forms, body by body")
    val(area, "batch/empty", sim(method, M123, np.zeros((0, 3)), TIMES),
        lambda sol: (np.testing.assert_array_equal(sol.omega.shape, (0, 4, 3)),
                     np.testing.assert_array_equal(sol.stats["steps"].shape, (0,))),
        "shapes (0, M, 3), steps (0,)")
    val(area, "omega0 1e-300 (tiny but normal)", sim(method, M123, W * 1e-300, TIMES),
        lambda sol: close(sol.omega, np.tile(W * 1e-300, (4, 1)), 1e-12, 4 * TINY),
        "omega constant to 1e-12 (rates ~1e-300 per unit time)")
    val(area, "omega0 subnormal (5e-324, 0, 0)", sim(method, M123, [5e-324, 0.0, 0.0], TIMES),
        lambda sol: close(sol.omega, np.tile([5e-324, 0.0, 0.0], (4, 1)), 0.0, 2 * TINY),
        "a spin about a principal axis: constant")
    val(area, "moments 1e-300 (tiny but normal)", sim(method, np.multiply(M123, 1e-300), W, TIMES),
        motion_check(method, lambda: scipy_motion(M123, W, TIMES)[0]),
        "scipy at unit moments")
    # --- per method ------------------------------------------------------------------------
    if method == "exact":
        err(area, "t=1e90 (no digits of the phase left)", sim(method, M123, W, [0.0, 1e90]),
            ph.ArgumentError, "t", fragment="1e90")
        err(area, "torque", sim(method, M123, W, 1.0, torque=ph.torque.BodyFixed([0, 0, 1.0])),
            ph.ArgumentError, "torque")
        err(area, "moments 1e-150..1e150 at t=1 (beyond the time bound)",
            sim(method, (1e-150, 1.0, 1e150), W, [0.0, 1.0]), ph.ArgumentError, "t")
        _big_t = [0.0, 1e14, 3e14]
        val(area, "t=3e14 (within the time bound)", sim(method, M123, W, _big_t),
            lambda sol: (
                close(sol.energy, np.full(3, energy_exact(M123, W)), 64 * EPS, what="T"),
                close(np.linalg.norm(sol.angular_momentum_space, axis=-1),
                      np.full(3, momentum_norm_exact(M123, W)), 64 * EPS, what="|L|"),
                close(sol.angular_momentum_space, np.tile(sol.angular_momentum_space[0], (3, 1)),
                      64 * EPS, what="L in space")),
            "T, |L| and L in space of the exact rational initial state")
        for _label, _w in [("(0.1, 0.4, 1e-200)", (0.1, 0.4, 1e-200)),
                           ("(1e-170, 0.4, 0.1)", (1e-170, 0.4, 0.1)),
                           ("(5e-320, 0.4, 0.0) subnormal", (5e-320, 0.4, 0.0))]:
            _times = np.array([0.0, 2.0, 7.5, 15.0])
            val(area, f"tiny component {_label}",
                sim(method, (3.0, 5.0, 9.0), _w, _times),
                motion_check(method, lambda w=_w, t=_times: scipy_motion((3.0, 5.0, 9.0), w, t)[0],
                             lambda w=_w, t=_times: scipy_motion((3.0, 5.0, 9.0), w, t)[1]),
                "scipy DOP853 (no separatrix here: an ordinary motion)")
        for _moments in [(2.0, 2.0, 3.0), (2.0, 3.0, 2.0)]:
            val(area, f"symmetric {_moments} at |omega| 1e-170",
                sim(method, _moments, W * 1e-170, TIMES * 1e170),
                scaled_omega_check(method, _moments, W, TIMES, 1e-170),
                "scipy at unit scale, scaled")
        val(area, "moments 1e-150..1e150 within the time bound",
            sim(method, (1e-150, 1.0, 1e150), (0.3, 0.4, 0.5), [0.0, 1e-226, 3e-226]),
            lambda sol: (
                close(sol.energy, np.full(3, energy_exact((1e-150, 1.0, 1e150), (0.3, 0.4, 0.5))),
                      64 * EPS, what="T"),
                close(np.linalg.norm(sol.angular_momentum_body, axis=-1),
                      np.full(3, momentum_norm_exact((1e-150, 1.0, 1e150), (0.3, 0.4, 0.5))),
                      64 * EPS, what="|L|")),
            "T and |L| of the exact rational initial state")
    if fixed:
        err(area, "dt missing", lambda m=method: ph.simulate(M123, W, 1.0, method=m),
            ph.ArgumentError, "dt")
        err(area, "dt=0", sim(method, M123, W, 1.0, dt=0.0), ph.NonPositiveError, "dt")
        err(area, "dt=-0.1", sim(method, M123, W, 1.0, dt=-0.1), ph.NonPositiveError, "dt")
        err(area, "dt=nan", sim(method, M123, W, 1.0, dt=NAN), ph.NonFiniteError, "dt")
        err(area, "dt='0.1'", sim(method, M123, W, 1.0, dt="0.1"), TypeError, "dt")
        err(area, "dt=1e-300 (too many steps, short message)", sim(method, M123, W, 1.0, dt=1e-300),
            ph.ArgumentError, "dt", fragment="dt = 1e-300 needs")
        err(area, "t=1e90", sim(method, M123, W, [0.0, 1e90]), ph.ArgumentError, "dt")
        err(area, "max_steps=1", sim(method, M123, W, 1.0, max_steps=1), ph.ArgumentError, "dt")
        val(area, "dt=1e300 (one step per output interval)",
            sim(method, M123, [0.0, 0.0, 2.5], TIMES, dt=1e300, orientation=False),
            lambda sol: close(sol.omega, np.tile([0.0, 0.0, 2.5], (4, 1)), 0.0),
            "a spin about a principal axis: omega constant for any step")
    if method == "splitting":
        err(area, "order=3", sim(method, M123, W, 1.0, order=3), ph.ArgumentError, "order")
        err(area, "order='4'", sim(method, M123, W, 1.0, order="4"), TypeError, "order")
        for _order, _dt, _bound in [(2, 1e-4, 1e-7), (6, 1e-2, 1e-9)]:
            val(area, f"order={_order}", sim(method, M123, W, TIMES, order=_order, dt=_dt),
                lambda sol, b=_bound: close(sol.omega, scipy_motion(M123, W, TIMES)[0], b),
                f"scipy (order {_order} at dt {_dt:g}: error below {_bound:g})")
    if method == "midpoint":
        err(area, "Newton fails (dt 0.2 at |omega| 70)", sim(method, M123, [30.0, 40.0, 50.0], 10.0,
                                                             dt=0.2),
            ph.ConvergenceError, "dt")
    if method == "rk4":
        err(area, "omega blows up (dt 10 at |omega| 37)", sim(method, M123, [10.0, 20.0, 30.0],
                                                              1e4, dt=10.0),
            ph.NonFiniteError, "dt", fragment="blew up")
        err(area, "orientation blows up beside finite omega",
            sim(method, (1.0, 1.0, 1.0), [1e3, 1e3, 1e3], [0.0, 1e4], dt=10.0),
            ph.NonFiniteError, "dt", fragment="orientation")
    if method == "dop853":
        err(area, "rtol=0", sim(method, M123, W, 1.0, rtol=0.0), ph.NonPositiveError, "rtol")
        err(area, "rtol=1e-20 (short message)", sim(method, M123, W, 1.0, rtol=1e-20),
            ph.ArgumentError, "rtol", fragment="got 1e-20")
        err(area, "rtol=nan", sim(method, M123, W, 1.0, rtol=NAN), ph.NonFiniteError, "rtol")
        err(area, "atol=-1", sim(method, M123, W, 1.0, atol=-1.0), ph.NonPositiveError, "atol")
        err(area, "atol=0", sim(method, M123, W, 1.0, atol=0.0), ph.NonPositiveError, "atol")
        err(area, "max_steps=1", sim(method, M123, W, 1.0, max_steps=1), ph.ConvergenceError,
            "max_steps")
        err(area, "t=1e90 (max_steps, short message)",
            sim(method, M123, W, [0.0, 1e90], max_steps=10_000), ph.ConvergenceError,
            "max_steps", fragment="t = 1e90")
        val(area, "omega0 1e150 over 1e-160", sim(method, M123, W * 1e150, TIMES * 1e-150),
            scaled_omega_check(method, M123, W, TIMES, 1e150), "scipy at unit scale, scaled")
        val(area, "atol=1e-300", sim(method, M123, W, TIMES, atol=1e-300),
            motion_check(method, lambda: scipy_motion(M123, W, TIMES)[0]), "scipy")


def assert_none(value):
    assert value is None, value


area = "simulate"
err(area, "method='euler'", lambda: ph.simulate(M123, W, 1.0, method="euler"), ph.ArgumentError,
    "method")
err(area, "method='RK4'", lambda: ph.simulate(M123, W, 1.0, method="RK4"), ph.ArgumentError,
    "method")
err(area, "outputs larger than memory", lambda: ph.simulate(M123, np.zeros((1_000_000, 3)),
                                                            np.linspace(0, 1, 1_000_000)),
    MemoryError, None, fragment="polhode.dask")
err(area, "torque=3", lambda: ph.simulate(M123, W, 1.0, torque=3), TypeError, "torque")
val(area, "progress callback gets [0, 1]",
    lambda: (lambda seen: (ph.simulate(M123, W, TIMES, method="rk4", dt=1e-3,
                                       progress=seen.append), seen)[1])([]),
    lambda seen: (assert_true(seen and seen[-1] == 1.0 and all(0 <= f <= 1 for f in seen)
                              and seen == sorted(seen), seen)),
    "the documented contract: fractions in [0, 1], non-decreasing, 1.0 at the end")
def _first_run_in_a_fresh_process():
    import subprocess

    code = (
        "import sys, polhode as ph\n"
        "sol = ph.simulate([1.0, 2.0, 3.0], [0.3, 1.0, -0.4], [0.0, 1.0],"
        " orientation0=[0.0, 0.0, 0.6, 0.8])\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] == 'scipy'))\n"
        "print(sol.quaternion[0].tolist())\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=True)
    return done.stdout.splitlines()


val(area, "orientation0 as a quaternion: no scipy import in the run (wall_time)",
    _first_run_in_a_fresh_process,
    lambda lines: (assert_true(lines[0] == "[]", lines[0]),
                   close([float(x) for x in lines[1].strip("[]").split(",")],
                         [0.0, 0.0, 0.6, 0.8], 4 * EPS)),
    "sys.modules of a fresh process; q(t0) = the quaternion given")
val(area, "auto with a torque is dop853",
    lambda: ph.simulate((2.0, 2.0, 2.0), W, TIMES, torque=ph.torque.BodyFixed([0.0, 0.0, 1.0])),
    lambda sol: (assert_true(sol.stats["method"] == "dop853", sol.stats["method"]),
                 close(sol.omega, W + np.outer(TIMES, [0.0, 0.0, 0.5]), 1e-9)),
    "a sphere under a body-fixed torque: omega0 + tau t / I")


def assert_true(condition, what=""):
    assert condition, what


# ---------------------------------------------------------------------------------------------
# 5. analyze
# ---------------------------------------------------------------------------------------------

area = "analyze"
err(area, "omega0 (1,3)", lambda: ph.analyze(M123, [[1.0, 0.0, 0.0]]), ph.ShapeError, "omega0")
err(area, "omega0 nan", lambda: ph.analyze(M123, [NAN, 0.0, 0.0]), ph.NonFiniteError, "omega0")
err(area, "omega0 'abc'", lambda: ph.analyze(M123, "abc"), TypeError, "omega0")
err(area, "omega0 1e200 (T overflows)", lambda: ph.analyze(M123, [1e200, 0.0, 0.0]),
    ph.ArgumentError, "omega0", fragment="overflow")
err(area, "moments (0,1,1)", lambda: ph.analyze([0.0, 1.0, 1.0], W), ph.ArgumentError, "body")
err(area, "body=rod", lambda: ph.analyze(ph.Body.rod(1.0, 1.0), W), ph.ArgumentError, "body")
err(area, "body (2,3)", lambda: ph.analyze(np.ones((2, 3)), W), ph.ShapeError, "body")
err(area, "body 'box'", lambda: ph.analyze("box", W), TypeError, "body")
err(area, "tensor not symmetric", lambda: ph.analyze([[1, 1, 0], [0, 2, 0], [0, 0, 3.0]], W),
    ph.InertiaError, "body")
err(area, "rtol=-1", lambda: ph.analyze(M123, W, rtol=-1.0), ph.ArgumentError, "rtol")
err(area, "rtol=nan", lambda: ph.analyze(M123, W, rtol=NAN), ph.ArgumentError, "rtol")
err(area, "rtol='x'", lambda: ph.analyze(M123, W, rtol="x"), TypeError, "rtol")


def classify(moments, omega):
    """The regime from exact rationals: L^2 against 2 T I2 (Landau-Lifshitz par. 37)."""
    i = [Fraction(float(x)) for x in moments]
    w = [Fraction(float(x)) for x in omega]
    l2 = sum((a * b) ** 2 for a, b in zip(i, w, strict=True))
    t2 = sum(a * b * b for a, b in zip(i, w, strict=True))
    if l2 == 0:
        return "rest"
    if len(set(i)) == 1:
        return "spherical"
    if len(set(i)) == 2:
        return "symmetric"
    order = sorted(range(3), key=lambda k: i[k])
    d = l2 - t2 * i[order[1]]
    if d == 0:
        return "separatrix" if w[order[1]] * w[order[1]] * i[order[1]] != t2 else \
            "steady_intermediate"
    return "about_largest_axis" if d > 0 else "about_smallest_axis"


def analysis_check(moments, omega, stability=None, precession=None):
    """Regime (exact rationals), T and |L| (exact), the period (mpmath, exact_period), the flip
    interval (half of it, off the symmetric case) and, when given, the axis stability and the
    symmetric top's precession rate (closed form)."""
    regime = classify(moments, omega)

    def check(a):
        assert a.regime == regime, (a.regime, regime)
        close(a.energy, energy_exact(moments, omega), 4 * EPS, what="T")
        close(a.angular_momentum_norm, momentum_norm_exact(moments, omega), 4 * EPS, what="|L|")
        period = exact_period(moments, omega)
        if period is None or regime in ("separatrix", "steady_intermediate", "rest"):
            assert a.period is None, a.period
        else:
            close(a.period, float(period), 1e-13, what="period")
        if regime.startswith("about") and a.period is not None and turns_over_exact(
            moments, omega
        ):
            close(a.flip_interval, a.period / 2, 4 * EPS, what="flip interval")
            assert a.turns_over and a.nutation_angle is None
        else:
            assert a.flip_interval is None and not a.turns_over, a.flip_interval
        if stability is not None:
            assert a.axis_stability == stability, a.axis_stability
        if precession is not None:
            close(a.precession_rate_body, precession, 4 * EPS, what="precession rate")
        elif regime != "symmetric":
            assert a.precession_rate_body is None, a.precession_rate_body

    return check


STABLE = ("stable", "unstable", "stable")
for _label, _m, _w, _stab, _prec in [
    ("asymmetric", M123, W, STABLE, None),
    ("rest", M123, (0.0, 0.0, 0.0), STABLE, None),
    ("sphere", (2.0, 2.0, 2.0), W, ("neutral",) * 3, None),
    ("oblate top", (1.0, 1.0, 2.0), W, ("neutral", "neutral", "stable"), -0.4 * (2 - 1) / 1),
    ("distinct moment in the middle (2,3,2)", (2.0, 3.0, 2.0), W,
     ("neutral", "neutral", "stable"), None),
    ("steady about the intermediate axis", M123, (0.0, 1.0, 0.0), STABLE, None),
    ("separatrix exactly (1,5,9), (3, 0.5, 1)", (1.0, 5.0, 9.0), (3.0, 0.5, 1.0), STABLE, None),
    ("|omega| 1e150", M123, (1e150, 1e149, 0.0), STABLE, None),
    ("|omega| 1e-200", M123, (1e-200, 1e-200, 0.0), STABLE, None),
    ("subnormal omega", M123, (5e-324, 0.0, 0.0), STABLE, None),
    ("breaks I1 + I2 >= I3 (1,2,4)", (1.0, 2.0, 4.0), W, STABLE, None),
    ("moments 1e-150, 1, 1e150 (distinct)", (1e-150, 1.0, 1e150), W, STABLE, None),
    ("moments 1, 1 + 2 eps, 2 (distinct)", (1.0, 1.0 + 2 * EPS, 2.0), W, STABLE, None),
    ("unsorted (3,1,2)", (3.0, 1.0, 2.0), W, STABLE, None),
]:
    val(area, _label, lambda m=_m, w=_w: ph.analyze(m, w), analysis_check(_m, _w, _stab, _prec),
        "exact rationals (regime, T, |L|), mpmath (period), closed forms")
val(area, "tensor (non-diagonal)", lambda: ph.analyze(_T, W),
    lambda a: (close(a.energy, 0.5 * W @ _T @ W, 4 * EPS, what="T"),
               close(a.angular_momentum_norm, np.linalg.norm(_T @ W), 4 * EPS, what="|L|"),
               close(a.moments, np.linalg.eigvalsh(_T), 16 * EPS, what="moments")),
    "numpy: T = w.Iw/2, |Iw|, eigvalsh")
val(area, "rtol=0.1 merges (1, 1.01, 2)", lambda: ph.analyze((1.0, 1.01, 2.0), W, rtol=0.1),
    lambda a: (assert_true(a.regime == "symmetric", a.regime),
               assert_true(a.axis_stability == ("neutral", "neutral", "stable"), a.axis_stability),
               assert_true(a.moments[0] == a.moments[1], a.moments)),
    "the documented merging: moments within rtol are one (a symmetric top)")

# ---------------------------------------------------------------------------------------------
# 6. perturbation
# ---------------------------------------------------------------------------------------------

area = "perturbation"
PW = np.array([1e-3, -2e-3, 1.0])  # a spin about the largest axis, eps ~ 2e-3
PT = np.array([0.0, 0.3, 1.0, 2.5])
err(area, "eps > 1/2", lambda: ph.perturbation(M123, [1.0, 1.0, 1.0], [0.0, 1.0]),
    ph.ArgumentError, "omega0")
err(area, "phase drifted (t=1e7)", lambda: ph.perturbation(M123, PW, [0.0, 1e7]),
    ph.ArgumentError, "t")
err(area, "growth about the intermediate axis (t=100)",
    lambda: ph.perturbation(M123, [0.01, 1.0, 0.0], [0.0, 100.0]), ph.ArgumentError, "t")
err(area, "no spin about the axis", lambda: ph.perturbation(M123, PW, [0.0, 1.0], axis=1),
    ph.ArgumentError, "omega0")
err(area, "omega0 = 0", lambda: ph.perturbation(M123, [0.0, 0.0, 0.0], [0.0, 1.0]),
    ph.ArgumentError, "omega0")
err(area, "omega0 nan", lambda: ph.perturbation(M123, [NAN, 0.0, 1.0], [0.0, 1.0]),
    ph.NonFiniteError, "omega0")
err(area, "t nan", lambda: ph.perturbation(M123, PW, [0.0, NAN]), ph.NonFiniteError, "t")
err(area, "moments negative", lambda: ph.perturbation([-1.0, 2.0, 3.0], PW, [0.0, 1.0]),
    ph.ArgumentError, "moments")
err(area, "moments (2,)", lambda: ph.perturbation([1.0, 2.0], PW, [0.0, 1.0]), ph.ShapeError,
    "moments")
err(area, "omega0 (2,)", lambda: ph.perturbation(M123, [0.0, 1.0], [0.0, 1.0]), ph.ShapeError,
    "omega0")
err(area, "t (1,2)", lambda: ph.perturbation(M123, PW, [[0.0, 1.0]]), ph.ShapeError, "t")
err(area, "order=3", lambda: ph.perturbation(M123, PW, [0.0, 1.0], order=3), ph.ArgumentError,
    "order")
err(area, "order='2'", lambda: ph.perturbation(M123, PW, [0.0, 1.0], order="2"), TypeError,
    "order")
err(area, "axis=3", lambda: ph.perturbation(M123, PW, [0.0, 1.0], axis=3), ph.ArgumentError,
    "axis")
err(area, "axis='z'", lambda: ph.perturbation(M123, PW, [0.0, 1.0], axis="z"), TypeError, "axis")
err(area, "omega0 complex", lambda: ph.perturbation(M123, PW + 0j, [0.0, 1.0]), TypeError,
    "omega0")
err(area, "rates overflow (1e300)", lambda: ph.perturbation(M123, [1e298, 0.0, 1e300],
                                                            [0.0, 1e-300]),
    ph.NonFiniteError, "omega0")


def perturbation_check(moments, omega0, times, order, s=1.0):
    """scipy's DOP853 on Euler's equations; the order-n expansion is exact to O(eps^(n+1)):
    within 10 eps^(n+1) |W| here (eps = |omega_perp| / |W|, constants of order 1 for these
    moments). With ``s``: (I, s w) at t / s is s times (I, w) at t."""
    w = np.asarray(omega0, dtype=float)
    eps = float(np.linalg.norm(w[:2]) / abs(w[2]))

    def check(result):
        reference = euler_omega(moments, w, np.asarray(times, float))
        close(np.asarray(result) / s, reference, 10 * eps ** (order + 1), what=f"order {order}")

    return check


for _order in (0, 1, 2):
    val(area, f"order {_order}", lambda o=_order: ph.perturbation(M123, PW, PT, order=o),
        perturbation_check(M123, PW, PT, _order), "scipy DOP853")
val(area, "omega0 x 1e150, t / 1e150", lambda: ph.perturbation(M123, PW * 1e150, PT / 1e150),
    perturbation_check(M123, PW, PT, 2, s=1e150), "scipy at unit scale, scaled")
val(area, "omega0 x 1e-150, t x 1e150", lambda: ph.perturbation(M123, PW * 1e-150, PT * 1e150),
    perturbation_check(M123, PW, PT, 2, s=1e-150), "scipy at unit scale, scaled")
val(area, "pure spin at t=1e300", lambda: ph.perturbation(M123, [0.0, 0.0, 2.0], [0.0, 1e300]),
    lambda r: close(r, [[0.0, 0.0, 2.0], [0.0, 0.0, 2.0]], 0.0), "the steady rotation")
val(area, "scalar t", lambda: ph.perturbation(M123, PW, 1.0),
    perturbation_check(M123, PW, [1.0], 2), "scipy DOP853")

# ---------------------------------------------------------------------------------------------
# 7. Torque models
# ---------------------------------------------------------------------------------------------

area = "torque"
TQ = ph.torque
Z = (0.0, 0.0, 1.0)
err(area, "BodyFixed nan", lambda: TQ.BodyFixed([NAN, 0, 0]), ph.NonFiniteError, "torque")
err(area, "BodyFixed (2,)", lambda: TQ.BodyFixed([1.0, 0.0]), ph.ShapeError, "torque")
err(area, "BodyFixed 'up'", lambda: TQ.BodyFixed("up"), TypeError, "torque")
err(area, "SpaceFixed inf", lambda: TQ.SpaceFixed([0, INF, 0]), ph.NonFiniteError, "torque")
err(area, "SpaceFixed None", lambda: TQ.SpaceFixed(None), TypeError, "torque")
err(area, "Gravity nan", lambda: TQ.Gravity([NAN, 0, 0]), ph.NonFiniteError, "gravity")
err(area, "Gravity pivot (2,)", lambda: TQ.Gravity(pivot=[0.0, 0.0]), ph.ShapeError, "pivot")
err(area, "Gravity pivot nan", lambda: TQ.Gravity(pivot=[NAN, 0, 0]), ph.NonFiniteError, "pivot")
err(area, "Gravity mass=0", lambda: TQ.Gravity(mass=0.0, center_of_mass=Z), ph.NonPositiveError,
    "mass")
err(area, "Gravity mass='heavy'", lambda: TQ.Gravity(mass="heavy", center_of_mass=Z), TypeError,
    "mass")
err(area, "Gravity center_of_mass nan", lambda: TQ.Gravity(mass=1.0, center_of_mass=[0, 0, NAN]),
    ph.NonFiniteError, "center_of_mass")
err(area, "Gravity on bare moments without mass",
    lambda: ph.simulate(M123, W, 1.0, torque=TQ.Gravity()), ph.ArgumentError, "torque")
err(area, "GravityGradient nan", lambda: TQ.GravityGradient(NAN), ph.NonFiniteError,
    "mean_motion")
err(area, "GravityGradient orbit_normal 0", lambda: TQ.GravityGradient(1.0, orbit_normal=(0, 0, 0)),
    ph.ArgumentError, "orbit_normal")
err(area, "GravityGradient radial0 along the normal",
    lambda: TQ.GravityGradient(1.0, radial0=(0, 0, 2)), ph.ArgumentError, "radial0")
err(area, "GravityGradient mean_motion='fast'", lambda: TQ.GravityGradient("fast"), TypeError,
    "mean_motion")
err(area, "Window start > end", lambda: TQ.Window(TQ.BodyFixed(Z), 2.0, 1.0), ph.ArgumentError,
    "start")
err(area, "Window start nan", lambda: TQ.Window(TQ.BodyFixed(Z), NAN, 1.0), ph.ArgumentError,
    "start")
err(area, "Window start 'soon'", lambda: TQ.Window(TQ.BodyFixed(Z), "soon", 1.0), TypeError,
    "start")
err(area, "Window of 3", lambda: TQ.Window(3, 0.0, 1.0), TypeError, "torque")
err(area, "Sum with 3", lambda: TQ.Sum([TQ.BodyFixed(Z), 3]), TypeError, "torque")
err(area, "BodyFixed + 3", lambda: TQ.BodyFixed(Z) + 3, TypeError, None)
err(area, "Function of 3", lambda: TQ.Function(3), TypeError, "torque")
err(area, "Function discontinuities nan",
    lambda: TQ.Function(lambda t, w, q: (0, 0, 0), discontinuities=[NAN]), ph.NonFiniteError,
    "discontinuities")
err(area, "Function discontinuities ['a']",
    lambda: TQ.Function(lambda t, w, q: (0, 0, 0), discontinuities=["a"]), TypeError,
    "discontinuities")


class Boom(RuntimeError):
    """A user's own exception, raised by a torque function."""


def _boom(t, w, q):
    raise Boom("kaboom")


for _method, _kw in [("dop853", {}), ("rk4", {"dt": 0.01}), ("splitting", {"dt": 0.01}),
                     ("midpoint", {"dt": 0.01})]:
    err(area, f"function returns nan ({_method})",
        lambda m=_method, k=_kw: ph.simulate(M123, W, 1.0, method=m, torque=lambda t, w, q:
                                             (NAN, 0, 0), **k), ph.NonFiniteError, "torque")
    err(area, f"function raises ({_method})",
        lambda m=_method, k=_kw: ph.simulate(M123, W, 1.0, method=m, torque=_boom, **k), Boom, None)
err(area, "function returns (0, 0)",
    lambda: ph.simulate(M123, W, 1.0, torque=lambda t, w, q: (0.0, 0.0)), ph.ShapeError, "torque")
err(area, "function returns None",
    lambda: ph.simulate(M123, W, 1.0, torque=lambda t, w, q: None), TypeError, "torque")
err(area, "function returns complex",
    lambda: ph.simulate(M123, W, 1.0, torque=lambda t, w, q: (1j, 0, 0)), TypeError, "torque")
err(area, "function returns inf (rk4)",
    lambda: ph.simulate(M123, W, 1.0, method="rk4", dt=0.1, torque=lambda t, w, q: (INF, 0, 0)),
    ph.NonFiniteError, "torque")
err(area, "BodyFixed nan reaches simulate",
    lambda: ph.simulate(M123, W, 1.0, torque=TQ.BodyFixed([NAN, 0, 0])), ph.NonFiniteError,
    "torque")

SPHERE2 = (2.0, 2.0, 2.0)  # omega x I omega = 0: a torque adds tau t / I to omega


def sphere_torque_check(rate, bound=1e-9):
    """omega(t) = omega0 + integral of tau / I (a sphere: Euler's equations are I w' = tau)."""

    def check(sol):
        expected = np.array([W + rate(t) for t in sol.t])
        close(sol.omega, expected, bound, what="omega")

    return check


for _method, _kw in [("dop853", {"rtol": 1e-12}), ("rk4", {"dt": 1e-3}),
                     ("splitting", {"dt": 1e-3}), ("midpoint", {"dt": 1e-3})]:
    val(area, f"BodyFixed on a sphere ({_method})",
        lambda m=_method, k=_kw: ph.simulate(SPHERE2, W, TIMES, method=m,
                                             torque=TQ.BodyFixed([0.2, -0.4, 1.0]), **k),
        sphere_torque_check(lambda t: np.array([0.2, -0.4, 1.0]) * t / 2), "omega0 + tau t / I")
    val(area, f"SpaceFixed: L in space grows by tau t ({_method})",
        lambda m=_method, k=_kw: ph.simulate(M123, W, TIMES, method=m, orientation0=TILT,
                                             torque=TQ.SpaceFixed([0.3, 0.1, -0.2]), **k),
        lambda sol, b=BOUND[_method]: close(
            sol.angular_momentum_space,
            rotate_by_quaternion(TILT, np.multiply(M123, W)) + np.outer(TIMES, [0.3, 0.1, -0.2]),
            b, what="L in space"),
        "dL/dt = tau in space (closed form for any body)")
val(area, "Window on a sphere", lambda: ph.simulate(SPHERE2, W, TIMES,
                                                    torque=TQ.Window(TQ.BodyFixed(Z), 0.4, 1.5)),
    sphere_torque_check(lambda t: np.array(Z) * (min(max(t, 0.4), 1.5) - 0.4) / 2),
    "omega0 + tau (overlap of [0, t] with the window) / I")
val(area, "Window (-inf, inf) is always on",
    lambda: ph.simulate(SPHERE2, W, TIMES, torque=TQ.Window(TQ.BodyFixed(Z), -INF, INF)),
    sphere_torque_check(lambda t: np.array(Z) * t / 2), "omega0 + tau t / I")
val(area, "Window of zero length is off",
    lambda: ph.simulate(SPHERE2, W, TIMES, torque=TQ.Window(TQ.BodyFixed(Z), 1.0, 1.0)),
    sphere_torque_check(lambda t: np.zeros(3)), "omega0")
val(area, "Sum([]) is no torque", lambda: ph.simulate(SPHERE2, W, TIMES, torque=TQ.Sum([])),
    sphere_torque_check(lambda t: np.zeros(3)), "omega0")
val(area, "Sum of BodyFixed and Function",
    lambda: ph.simulate(SPHERE2, W, TIMES, torque=TQ.BodyFixed(Z) + TQ.Function(
        lambda t, w, q: (0.0, 2 * t, 0.0), depends_on_omega=False, depends_on_orientation=False)),
    sphere_torque_check(lambda t: np.array([0.0, t * t, t]) / 2), "closed-form integral / I")
val(area, "BodyFixed 1e150 from rest (omega only)",
    lambda: ph.simulate(SPHERE2, [0.0, 0.0, 0.0], TIMES, torque=TQ.BodyFixed([0.0, 0.0, 1e150]),
                        orientation=False),
    lambda sol: close(sol.omega[:, 2], TIMES * 0.5e150, 1e-12, what="omega_z"), "tau t / I")
for _method, _kw in [("dop853", {}), ("rk4", {"dt": 0.05}), ("splitting", {"dt": 0.05})]:
    err(area, f"BodyFixed 1e154 drives T beyond doubles ({_method})",
        lambda m=_method, k=_kw: ph.simulate((0.05, 0.05, 0.05), [0.0, 0.0, 0.0], [0.0, 0.5],
                                             method=m, torque=TQ.BodyFixed([0.0, 0.0, 1e154]),
                                             orientation=False, **k),
        ph.NonFiniteError, "t", fragment="`energy`")
val(area, "BodyFixed 1e-300", lambda: ph.simulate(SPHERE2, W, TIMES, method="rk4", dt=0.1,
                                                  torque=TQ.BodyFixed([0.0, 0.0, 1e-300])),
    sphere_torque_check(lambda t: np.zeros(3), bound=4 * EPS), "omega0 (+ 1e-300: below ulp)")


def heavy_top_check(body, pivot, g):
    """The heavy top's invariants: the energy T + V, V = -m g . (R r_cm), and the component of L
    (about the pivot, in space) along gravity (closed form from the equations of motion)."""
    r = np.asarray(body.center_of_mass) - pivot
    inertia = body.inertia_about(pivot)

    def check(sol):
        rot = Rotation.from_quat(sol.quaternion)
        energy = 0.5 * np.einsum("ni,ij,nj->n", sol.omega, inertia, sol.omega)
        energy -= body.mass * rot.apply(r) @ g
        close(energy, np.full(energy.shape, energy[0]), 1e-9, what="T + V")
        lz = rot.apply(sol.omega @ inertia.T) @ g
        close(lz, np.full(lz.shape, lz[0]), 1e-9, what="L . g")

    return check


_top_body = ph.Body.cone(1.0, 0.3, 1.0).rotated(Rotation.from_rotvec([0.1, 0.2, 0.0]))
for _method, _kw in [("dop853", {"rtol": 1e-12}), ("rk4", {"dt": 1e-3}),
                     ("splitting", {"dt": 1e-3})]:
    val(area, f"Gravity: heavy top invariants ({_method})",
        lambda m=_method, k=_kw: ph.simulate(_top_body, [0.5, -0.3, 8.0], TIMES, method=m,
                                             orientation0=TILT,
                                             torque=TQ.Gravity(pivot=[0.0, 0.0, 0.0]), **k),
        heavy_top_check(_top_body, np.zeros(3), np.array([0.0, 0.0, -9.81])),
        "energy and L . g conserved")


def gravity_gradient(n, normal, radial0, inertia):
    k = np.asarray(normal, float) / np.linalg.norm(normal)
    r0 = np.asarray(radial0, float)
    r0 = r0 - k * (k @ r0)
    r0 = r0 / np.linalg.norm(r0)
    along = np.cross(k, r0)

    def tau(t, w, q):
        r = rotate_by_quaternion(q * [-1, -1, -1, 1], r0 * np.cos(n * t) + along * np.sin(n * t))
        return 3.0 * n * n * np.cross(r, inertia @ r)

    return tau


val(area, "GravityGradient vs scipy",
    lambda: ph.simulate(_T, W, TIMES, orientation0=TILT, rtol=1e-12,
                        torque=TQ.GravityGradient(1.3, (0.1, 0.2, 1.0), (1.0, 0.3, 0.0))),
    lambda sol: close(sol.omega, rigid_body(_T, W, TILT, TIMES, gravity_gradient(
        1.3, (0.1, 0.2, 1.0), (1.0, 0.3, 0.0), _T))[0], 1e-8),
    "scipy DOP853 with 3 n^2 r x I r in body axes")

# ---------------------------------------------------------------------------------------------
# 8. Meshes
# ---------------------------------------------------------------------------------------------

area = "mesh"
TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
CUBE_V = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
CUBE_F = np.array([
    [0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
    [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3],
])
MESH = ph.Body.mesh
# The unit right tetrahedron: volume 1/6, centroid (1/4, 1/4, 1/4); about it, per unit mass,
# I_xx = 6 (1/60 + 1/60 - 2 (1/6)(1/16)) = 3/40 and I_xy = -6 (1/120 - (1/6)(1/16)) = 1/80.
TET_I = np.array([[3 / 40, 1 / 80, 1 / 80], [1 / 80, 3 / 40, 1 / 80], [1 / 80, 1 / 80, 3 / 40]])


def mesh_check(mass, inertia, com, scale=0, rtol=16 * EPS):
    """The closed form times 2^scale (lengths) and the mass."""

    def check(b):
        close(b.mass, mass, rtol, what="mass")
        close(b.inertia, np.ldexp(np.asarray(inertia) * mass, 2 * scale), rtol, 2 * TINY,
              "inertia")
        close(b.center_of_mass, np.ldexp(com, scale), rtol, 2 * TINY, "center_of_mass")

    return check


err(area, "inside out", lambda: MESH(CUBE_V, CUBE_F[:, ::-1], density=1.0), ph.ArgumentError,
    "faces", fragment="inside out")
err(area, "open (a face missing)", lambda: MESH(CUBE_V, CUBE_F[:-1], density=1.0),
    ph.ArgumentError, "faces")
err(area, "three faces", lambda: MESH(TET_V, TET_F[:3], density=1.0), ph.ArgumentError, "faces")
err(area, "a flipped face", lambda: MESH(CUBE_V, np.vstack([CUBE_F[:-1], CUBE_F[-1:, ::-1]]),
                                         density=1.0), ph.ArgumentError, "faces")
err(area, "a face twice", lambda: MESH(TET_V, np.vstack([TET_F, TET_F[:1]]), density=1.0),
    ph.ArgumentError, "faces")
err(area, "density and mass", lambda: MESH(TET_V, TET_F, density=1.0, mass=1.0),
    ph.ArgumentError, "density")
err(area, "neither density nor mass", lambda: MESH(TET_V, TET_F), ph.ArgumentError, "mass")
err(area, "index out of range", lambda: MESH(TET_V, TET_F + 1, density=1.0), ph.ArgumentError,
    "faces")
err(area, "negative index", lambda: MESH(TET_V, TET_F - 1, density=1.0), ph.ArgumentError, "faces")
err(area, "index 2^63 + 5 (uint64)",
    lambda: MESH(TET_V, np.array([[0, 1, 2**63 + 5]] * 4, dtype=np.uint64), mass=1.0),
    ph.ArgumentError, "faces")
err(area, "a triangle repeating a vertex", lambda: MESH(TET_V, np.vstack([TET_F[:3], [[1, 1, 3]]]),
                                                         density=1.0), ph.ArgumentError, "faces")
err(area, "float faces", lambda: MESH(TET_V, TET_F.astype(float), density=1.0), TypeError, "faces")
err(area, "bool faces", lambda: MESH(TET_V, TET_F.astype(bool), density=1.0), TypeError, "faces")
err(area, "faces (4,2)", lambda: MESH(TET_V, TET_F[:, :2], density=1.0), ph.ShapeError, "faces")
err(area, "faces 'abc'", lambda: MESH(TET_V, "abc", density=1.0), TypeError, "faces")
err(area, "no faces", lambda: MESH(TET_V, np.zeros((0, 3), dtype=int), density=1.0),
    ph.ArgumentError, "faces")
err(area, "collinear vertices (no volume)",
    lambda: MESH(np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0.0]]), TET_F, density=1.0),
    ph.ArgumentError, "vertices")
err(area, "vertices nan", lambda: MESH(np.where(TET_V == 1, NAN, TET_V), TET_F, density=1.0),
    ph.NonFiniteError, "vertices")
err(area, "vertices (4,2)", lambda: MESH(TET_V[:, :2], TET_F, density=1.0), ph.ShapeError,
    "vertices")
err(area, "vertices 'abc'", lambda: MESH("abc", TET_F, density=1.0), TypeError, "vertices")
err(area, "vertices 1e200 (mass overflows)", lambda: MESH(TET_V * 1e200, TET_F, density=1.0),
    ph.ArgumentError, "vertices", fragment="overflow")
err(area, "density 0", lambda: MESH(TET_V, TET_F, density=0.0), ph.NonPositiveError, "density")
err(area, "density -1", lambda: MESH(TET_V, TET_F, density=-1.0), ph.NonPositiveError, "density")
err(area, "density nan", lambda: MESH(TET_V, TET_F, density=NAN), ph.NonFiniteError, "density")
err(area, "mass '1'", lambda: MESH(TET_V, TET_F, mass="1"), TypeError, "mass")
err(area, "shell 'yes'", lambda: MESH(TET_V, TET_F, mass=1.0, shell="yes"), TypeError, "shell")
err(area, "fix_winding 1", lambda: MESH(TET_V, TET_F, mass=1.0, fix_winding=1), TypeError,
    "fix_winding")
err(area, "from_trimesh(3)", lambda: ph.Body.from_trimesh(3, mass=1.0), TypeError, "mesh")
val(area, "tetrahedron", lambda: MESH(TET_V, TET_F, density=6.0),
    mesh_check(1.0, TET_I, [0.25] * 3), "closed form of the right tetrahedron")
for _k in (300, -300, 500):
    val(area, f"tetrahedron x 2^{_k}, mass 1",
        lambda k=_k: MESH(np.ldexp(TET_V, k), TET_F, mass=1.0),
        mesh_check(1.0, TET_I, [0.25] * 3, scale=_k), "closed form x 2^2k")
err(area, "tetrahedron x 2^-500, density 1 (the mass underflows)",
    lambda: MESH(np.ldexp(TET_V, -500), TET_F, density=1.0), ph.ArgumentError, "vertices",
    fragment="underflow")
val(area, "tetrahedron 1e10 from the origin", lambda: MESH(TET_V + 1e10, TET_F, mass=1.0),
    lambda b: (close(b.inertia, TET_I, 1e-9, what="inertia"),
               close(b.center_of_mass, [1e10 + 0.25] * 3, 4 * EPS)),
    "closed form (to 1e-9: the vertices themselves are rounded at 1e10 to 2e-6 relative of 1)")
val(area, "cube", lambda: MESH(CUBE_V, CUBE_F, mass=2.0),
    lambda b: close(b.inertia, ref.cuboid(2.0, (1.0, 1.0, 1.0)).inertia, 16 * EPS),
    "the cuboid's closed form")
val(area, "cube inside out, fix_winding", lambda: MESH(CUBE_V, CUBE_F[:, ::-1], mass=2.0,
                                                       fix_winding=True),
    lambda b: close(b.inertia, ref.cuboid(2.0, (1.0, 1.0, 1.0)).inertia, 16 * EPS),
    "the cuboid's closed form")
val(area, "cube shell", lambda: MESH(CUBE_V, CUBE_F, mass=3.0, shell=True),
    lambda b: close(b.inertia, np.eye(3) * 5 * 3.0 / 18, 16 * EPS),
    "hollow cube surface: 5 m a^2 / 18")
val(area, "cube with a cavity (nested shells)",
    lambda: MESH(np.vstack([CUBE_V * 2, CUBE_V]), np.vstack([CUBE_F, CUBE_F[:, ::-1] + 8]),
                 density=1.0),
    lambda b: (close(b.mass, 8.0 - 1.0, 4 * EPS),
               close(b.inertia, np.eye(3) * (8 * 4 / 6 - 1 / 6), 16 * EPS)),
    "outer box minus inner box, rho V a^2 / 6 each")
val(area, "open tetrahedron as a shell", lambda: MESH(TET_V, TET_F[:3], density=1.0, shell=True),
    lambda b: close(b.mass, 1.5, 4 * EPS), "three right triangles of area 1/2")
val(area, "int vertices, int32 faces", lambda: MESH(TET_V.astype(int), TET_F.astype(np.int32),
                                                    density=6),
    mesh_check(1.0, TET_I, [0.25] * 3), "closed form")
val(area, "uint16 faces", lambda: MESH(TET_V, TET_F.astype(np.uint16), mass=1.0),
    mesh_check(1.0, TET_I, [0.25] * 3), "closed form")


def _trimesh_box():
    trimesh = pytest.importorskip("trimesh")
    return ph.Body.from_trimesh(trimesh.creation.box(extents=(1.0, 2.0, 3.0)), mass=2.0)


val(area, "from_trimesh box", _trimesh_box,
    lambda b: close(b.inertia, ref.cuboid(2.0, (1.0, 2.0, 3.0)).inertia, 16 * EPS),
    "the cuboid's closed form")

# ---------------------------------------------------------------------------------------------
# 9. polhode.dask (small batches, computed in process)
# ---------------------------------------------------------------------------------------------

area = "dask"
W4 = np.array([W, 2 * W, -W, [0.0, 0.0, 0.0]])


def dask_call(function, *args, compute=True, **kwargs):
    def run():
        phd = pytest.importorskip("polhode.dask")
        lazy = getattr(phd, function)(*args, **kwargs)
        return lazy.compute(scheduler="sync") if compute else lazy

    return run


def dask_array(array, chunks):
    def make():
        da = pytest.importorskip("dask.array")
        return da.from_array(np.asarray(array), chunks=chunks)

    return make


def lazy(make_args, function, compute=True, **kwargs):
    """A dask call whose inputs are dask arrays made when the row runs."""

    def run():
        phd = pytest.importorskip("polhode.dask")
        result = getattr(phd, function)(*[a() if callable(a) else a for a in make_args], **kwargs)
        return result.compute(scheduler="sync") if compute else result

    return run


_W4_NAN = np.where(np.arange(12).reshape(4, 3) == 7, NAN, W4)
err(area, "simulate/omega0 (3,)", dask_call("simulate", M123, W, [0.0, 1.0]), ph.ShapeError,
    "omega0")
err(area, "simulate/omega0 (4,2)", dask_call("simulate", M123, np.ones((4, 2)), [0.0, 1.0]),
    ph.ShapeError, "omega0")
err(area, "simulate/body (3,3) for 4 rows", dask_call("simulate", np.ones((3, 3)), W4, [0.0, 1.0]),
    ph.ShapeError, "body")
err(area, "simulate/chunks=0", dask_call("simulate", M123, W4, [0.0, 1.0], chunks=0),
    ph.ArgumentError, "chunks")
err(area, "simulate/chunks='a'", dask_call("simulate", M123, W4, [0.0, 1.0], chunks="a"),
    TypeError, "chunks")
err(area, "simulate/method='euler'", dask_call("simulate", M123, W4, [0.0, 1.0], method="euler"),
    ph.ArgumentError, "method")
err(area, "simulate/rk4 without dt", dask_call("simulate", M123, W4, [0.0, 1.0], method="rk4"),
    ph.ArgumentError, "dt")
err(area, "simulate/t nan", dask_call("simulate", M123, W4, [0.0, NAN]), ph.NonFiniteError, "t")
err(area, "simulate/numpy omega0 nan in body 2 (at once)",
    dask_call("simulate", M123, _W4_NAN, [0.0, 1.0], compute=False), ph.NonFiniteError, "omega0",
    body=2)
err(area, "simulate/dask omega0 nan in body 2 (in its block)",
    lazy([M123, dask_array(_W4_NAN, 2), [0.0, 1.0]], "simulate"), ph.NonFiniteError, "omega0",
    body=2)
err(area, "simulate/dask moments zero in body 3",
    lazy([dask_array([M123, M123, M123, [1.0, 0.0, 1.0]], 2), W4, [0.0, 1.0]], "simulate"),
    ph.ArgumentError, "body", body=3)
err(area, "simulate/dask strings", lazy([M123, dask_array(np.full((4, 3), "a"), 2), [0.0, 1.0]],
                                       "simulate", compute=False), TypeError, "omega0")
err(area, "simulate/3 orientations for 4 bodies",
    dask_call("simulate", M123, W4, [0.0, 1.0], orientation0=np.tile([0, 0, 0, 1.0], (3, 1))),
    ph.ShapeError, "orientation0")
err(area, "simulate/dask zero quaternion for body 3",
    lambda: pytest.importorskip("polhode.dask").simulate(
        M123, W4, [0.0, 1.0],
        orientation0=dask_array([[0, 0, 0, 1.0]] * 3 + [[0, 0, 0, 0.0]], 2)()).compute(
        scheduler="sync"),
    ph.ArgumentError, "orientation0", body=3)
err(area, "simulate/omega0 1e200 in body 0", dask_call("simulate", M123, np.full((2, 3), 1e200),
                                                       [0.0, 1.0], compute=False),
    ph.ArgumentError, "omega0", body=0)
err(area, "simulate/unknown keyword", dask_call("simulate", M123, W4, [0.0, 1.0], frobnicate=1),
    TypeError, None)
err(area, "analyze/rtol=-1", dask_call("analyze", M123, W4, rtol=-1.0, compute=False),
    ph.ArgumentError, "rtol")
err(area, "analyze/omega0 (3,)", dask_call("analyze", M123, W, compute=False), ph.ShapeError,
    "omega0")
err(area, "analyze/dask omega0 nan in body 2",
    lazy([M123, dask_array(_W4_NAN, 1)], "analyze"), ph.NonFiniteError, "omega0", body=2)
val(area, "simulate/sphere, top, rest in blocks of 2",
    lazy([dask_array([[2.0, 2.0, 2.0], [1.0, 1.0, 2.0], M123, [1.0, 2.0, 3.0]], 2), W4, TIMES],
         "simulate"),
    lambda sol: close(sol.omega, [np.tile(W, (4, 1)), symmetric_omega((1, 1, 2), 2 * W, TIMES),
                                  scipy_motion(M123, -W, TIMES)[0], np.zeros((4, 3))], 1e-11),
    "closed forms and scipy, body by body")
val(area, "simulate/empty batch", dask_call("simulate", M123, np.zeros((0, 3)), TIMES),
    lambda sol: np.testing.assert_array_equal(sol.omega.shape, (0, 4, 3)), "shape (0, M, 3)")
_W3 = np.array([W, [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]])


def _dask_analysis():
    a = dask_call("analyze", M123, _W3)()
    # polhode.dask documents NaN for the None of polhode.analyze (no period here): kept apart
    # from the numbers that must be finite.
    return {"regime": a.regime, "energy": a.energy, "period is NaN": np.isnan(a.period)}


val(area, "analyze/regimes", _dask_analysis,
    lambda a: (np.testing.assert_array_equal(
        a["regime"], [classify(M123, W), "steady_intermediate", "rest"]),
        close(a["energy"], [energy_exact(M123, w) for w in _W3], 4 * EPS),
        np.testing.assert_array_equal(a["period is NaN"],
                                      [exact_period(M123, w) is None for w in _W3])),
    "exact rational classification and T; NaN periods where analyze says None")

# ---------------------------------------------------------------------------------------------
# 10. The command line
# ---------------------------------------------------------------------------------------------

area = "cli"
_TMP = types.SimpleNamespace(name=tempfile.mkdtemp(prefix="polhode-catalogue-"))
atexit.register(shutil.rmtree, _TMP.name, ignore_errors=True)
SPIN = ["spin", "--moments", "1", "2", "3"]
OMEGA = ["--omega", "0.3", "1", "-0.4"]


def cli(*argv):
    def run():
        from polhode.cli import main

        out, errors = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(errors):
            code = main([a.format(tmp=_TMP.name) for a in argv])
        return code, out.getvalue(), errors.getvalue()

    return run


def cli_err(id_, argv, option, xfail=None):
    CATALOGUE.append(Row(f"{area}/{id_}", area, cli(*argv), Exit(2, option), xfail))


def cli_ok(id_, argv, check, xfail=None):
    CATALOGUE.append(Row(f"{area}/{id_}", area, cli(*argv), Exit(0, None, check), xfail))


cli_err("--t inf", [*SPIN, *OMEGA, "--t", "inf"], "--t")
cli_err("--t -1", [*SPIN, *OMEGA, "--t", "-1"], "--t")
cli_err("--t nan", [*SPIN, *OMEGA, "--t", "nan"], "--t")
cli_err("--t 1e999", [*SPIN, *OMEGA, "--t", "1e999"], "--t")
cli_err("--t 1e90 (exact: no digits of the phase)", [*SPIN, *OMEGA, "--t", "1e90"], "--t")
cli_err("--moments 0", ["spin", "--moments", "0", "2", "3", *OMEGA, "--t", "1"], "--moments")
cli_err("--moments nan", ["spin", "--moments", "1", "nan", "3", *OMEGA, "--t", "1"], "--moments")
cli_err("--moments x", ["spin", "--moments", "1", "2", "x", *OMEGA, "--t", "1"], "--moments")
cli_err("--moments two values", ["spin", "--moments", "1", "2", *OMEGA, "--t", "1"], "--moments")
cli_err("--omega inf", [*SPIN, "--omega", "inf", "1", "1", "--t", "1"], "--omega")
cli_err("--omega 1e200 (T overflows)", [*SPIN, "--omega", "1e200", "1", "1", "--t", "1"],
        "--omega")
cli_err("--omega missing", [*SPIN, "--t", "1"], "--omega")
cli_err("--dt with exact", [*SPIN, *OMEGA, "--t", "1", "--dt", "0.1"], "--dt")
cli_err("--dt 0", [*SPIN, *OMEGA, "--t", "1", "--method", "rk4", "--dt", "0"], "--dt")
cli_err("rk4 without --dt", [*SPIN, *OMEGA, "--t", "1", "--method", "rk4"], "--dt")
cli_err("--dt 1e-300 (too many steps)", [*SPIN, *OMEGA, "--t", "1", "--method", "rk4", "--dt",
                                         "1e-300"], "--dt")
cli_err("rk4 blows up", [*SPIN, "--omega", "10", "20", "30", "--t", "1e4", "--method", "rk4",
                         "--dt", "10"], "--dt")
cli_err("midpoint Newton fails", [*SPIN, "--omega", "30", "40", "50", "--t", "10", "--points", "3",
                                  "--method", "midpoint", "--dt", "0.2"], "--dt")
cli_err("--order 3", [*SPIN, *OMEGA, "--t", "1", "--method", "splitting", "--dt", "0.1",
                      "--order", "3"], "--order")
cli_err("--rtol 2", [*SPIN, *OMEGA, "--t", "1", "--method", "dop853", "--rtol", "2"], "--rtol")
cli_err("--rtol with exact", [*SPIN, *OMEGA, "--t", "1", "--rtol", "1e-8"], "--rtol")
cli_err("--points 1", [*SPIN, *OMEGA, "--t", "1", "--points", "1"], "--points")
cli_err("--method euler", [*SPIN, *OMEGA, "--t", "1", "--method", "euler"], "--method")
cli_err("--csv in a missing folder", [*SPIN, *OMEGA, "--t", "1", "--csv", "{tmp}/no/run.csv"],
        "--csv")
cli_err("--plot .xyz", [*SPIN, *OMEGA, "--t", "1", "--plot", "{tmp}/run.xyz"], "--plot")
cli_err("--body pyramid", ["spin", "--body", "pyramid", "mass=1", *OMEGA, "--t", "1"], "--body")
cli_err("--body unknown key", ["spin", "--body", "sphere", "mass=1", "radus=1", *OMEGA, "--t",
                               "1"], "radus")
cli_err("--body radius=1e300 (overflow)", ["spin", "--body", "sphere", "mass=1", "radius=1e300",
                                           *OMEGA, "--t", "1"], "--body")
cli_err("--body torus minor > major", ["spin", "--body", "torus", "mass=1", "major_radius=1",
                                       "minor_radius=2", *OMEGA, "--t", "1"], "--body")
cli_err("--body a rod (zero moment)", ["spin", "--body", "cylinder", "mass=1", "radius=1e-300",
                                       "length=1", *OMEGA, "--t", "1"], "--body")
cli_err("--body and --moments", [*SPIN, "--body", "sphere", "mass=1", "radius=1", *OMEGA, "--t",
                                 "1"], "--body")
cli_err("unknown command", ["frobnicate"], "frobnicate")
cli_err("bench --repeats 0", ["bench", "--repeats", "0"], "--repeats")


def printed(label, stdout):
    """The numbers printed after ``label`` on its line, up to the first ``]``, e.g.
    'principal moments  [1 2 3]   (I1 <= I2 <= I3)'."""
    line = next(x for x in stdout.splitlines() if x.startswith(label))
    return np.array([float(v) for v in line[len(label):].split("]")[0].replace("[", " ")
                     .split()])


def no_nan(stdout, stderr):
    assert "nan" not in stdout.lower() and "inf" not in stdout.lower(), stdout
    assert stderr == "", stderr


def csv_rows(path, quantity=None):
    """The CSV's rows, or the columns of one quantity (the CSV holds every quantity of the run,
    each column headed by its name, a component and its unit: ``omega_1 (rad/s)``)."""
    path = path.format(tmp=_TMP.name)
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if quantity is None:
        return rows
    with open(path) as handle:
        header = handle.readline().rstrip("\n").split(",")
    pattern = re.compile(rf"{quantity}_[123xyzw]( \(.*\))?")
    columns = [k for k, name in enumerate(header) if pattern.fullmatch(name)]
    assert len(columns) == {"omega": 3, "quaternion": 4}[quantity], header
    return rows[:, columns]


CSV_OMEGA, CSV_QUATERNION = "omega", "quaternion"


def csv_check(path, omega_q_ref, bound):
    def check(stdout, stderr):
        rows = csv_rows(path)
        w_ref, q_ref = omega_q_ref(rows[:, 0])
        close(csv_rows(path, CSV_OMEGA), w_ref, bound, what="omega")
        same_rotation(csv_rows(path, CSV_QUATERNION), q_ref, max(bound, 64 * EPS))

    return check


cli_ok("omega = 0 (rest, no NaN, no warning)", [*SPIN, "--omega", "0", "0", "0", "--t", "1",
                                                "--points", "3"],
       lambda out, errors: (no_nan(out, errors), assert_true("rest" in out, out)))
cli_ok("omega 1e-300", [*SPIN, "--omega", "1e-300", "0", "0", "--t", "1", "--points", "3"],
       no_nan)
cli_ok("moments breaking I1 + I2 >= I3: a one-line note", ["spin", "--moments", "1", "1", "3",
                                                           *OMEGA, "--t", "1", "--points", "3"],
       lambda out, errors: assert_true(errors.count("\n") == 1 and "I1 + I2 >= I3" in errors,
                                       errors))
cli_ok("--version", ["--version"], lambda out, errors: assert_true(
    out.strip() == f"polhode {ph.__version__}", out))
cli_ok("sphere to csv", ["spin", "--moments", "2", "2", "2", *OMEGA, "--t", "2", "--points", "5",
                         "--csv", "{tmp}/sphere.csv"],
       csv_check("{tmp}/sphere.csv", lambda t: sphere_motion([0.3, 1.0, -0.4], t), 64 * EPS),
       )
cli_ok("symmetric top (2,3,2) to csv", ["spin", "--moments", "2", "3", "2", *OMEGA, "--t", "2",
                                        "--points", "5", "--csv", "{tmp}/top.csv"],
       lambda out, errors: close(csv_rows("{tmp}/top.csv", CSV_OMEGA),
                                 symmetric_omega((2, 3, 2), [0.3, 1.0, -0.4],
                                                 csv_rows("{tmp}/top.csv")[:, 0]), 256 * EPS))
cli_ok("--body cylinder", ["spin", "--body", "cylinder", "mass=1", "radius=0.1", "length=0.5",
                           *OMEGA, "--t", "1", "--points", "3"],
       lambda out, errors: close(printed("principal moments", out),
                                 np.sort(np.diag(ref.cylinder(1.0, 0.1, 0.5).inertia)), 1e-4))
cli_ok("rk4 at 1e-3", [*SPIN, *OMEGA, "--t", "2", "--points", "5", "--method", "rk4", "--dt",
                       "1e-3", "--csv", "{tmp}/rk4.csv"],
       lambda out, errors: close(csv_rows("{tmp}/rk4.csv", CSV_OMEGA),
                                 scipy_motion(M123, W, np.linspace(0, 2, 5))[0], 1e-9))


def _subprocess_version():
    import subprocess

    done = subprocess.run([sys.executable, "-m", "polhode", "--version"], capture_output=True,
                          text=True, timeout=60)
    return done.returncode, done.stdout, done.stderr


CATALOGUE.append(Row("cli/python -m polhode --version", "cli", _subprocess_version,
                     Exit(0, None, lambda out, errors: assert_true(
                         out.strip() == f"polhode {ph.__version__}" and errors == "", out))))


# ---------------------------------------------------------------------------------------------
# 11. An adversarial probe's faults, and a wider probe: invariants, molecules, files (io),
#     argument types of simulate and analyze, masked arrays and numbers beyond double
#     precision everywhere, pickling
# ---------------------------------------------------------------------------------------------

#: The rows from here on are an adversarial probe's faults and a wider probe of the public API
#: (``python tests/catalogue_outcomes.py`` counts their outcomes on any version of polhode).
PROBE_FIRST_ROW = len(CATALOGUE)
BIG = 2**2000  # an integer beyond double precision: float(BIG) raises OverflowError


def masked(values, mask):
    return np.ma.array(np.asarray(values, dtype=float), mask=mask)


def trajectory_like(energy, body, space=None):
    """Any object with a trajectory's three fields (what polhode.invariants documents)."""
    return types.SimpleNamespace(
        energy=energy, angular_momentum_body=body, angular_momentum_space=space
    )


def assert_equal(actual, expected, what=""):
    """Equal exactly (the reference is exact in doubles)."""
    assert np.array_equal(np.asarray(actual), np.asarray(expected)), (
        f"{what}: {np.asarray(actual).tolist()} != {np.asarray(expected).tolist()}"
    )


def keys_values(expected: dict):
    """A dict of arrays (or floats) exactly equal to ``expected``, key by key."""

    def check(result):
        assert sorted(result) == sorted(expected), (sorted(result), sorted(expected))
        for key, value in expected.items():
            assert_equal(result[key], value, key)

    return check


# --- invariants -------------------------------------------------------------------------------

area = "invariants"
from polhode import invariants as INV  # noqa: E402

_TRAJ = ph.simulate(M123, W, TIMES, method="rk4", dt=0.1)
for _name, _function in (
    ("max_relative_drift", INV.max_relative_drift),
    ("relative_drift", INV.relative_drift),
    ("angular_momentum_space", INV.angular_momentum_space),
):
    for _label, _bad in (("'x'", "x"), ("None", None), ("3", 3), ("a Body", BOX),
                         ("a dict", {"energy": [1.0]}), ("omega array", np.zeros((4, 3)))):
        err(area, f"{_name}({_label})", lambda f=_function, b=_bad: f(b), TypeError, "traj")
err(area, "energy of strings", lambda: INV.relative_drift(
    trajectory_like("abc", np.zeros((3, 3)))), TypeError, "traj.energy")
err(area, "energy beyond doubles", lambda: INV.relative_drift(
    trajectory_like([BIG, 1], np.zeros((2, 3)))), ph.NonFiniteError, "traj")
err(area, "masked energy", lambda: INV.relative_drift(
    trajectory_like(masked([1.0, 2.0], [0, 1]), np.zeros((2, 3)))), ph.ArgumentError, "traj")
err(area, "L body (M, 2)", lambda: INV.relative_drift(
    trajectory_like([1.0, 2.0], np.zeros((2, 2)))), ph.ShapeError, "traj")
err(area, "L body of other times", lambda: INV.relative_drift(
    trajectory_like([1.0, 2.0], np.zeros((3, 3)))), ph.ShapeError, "traj")
err(area, "L space of other times", lambda: INV.relative_drift(
    trajectory_like([1.0, 2.0], np.zeros((2, 3)), np.zeros((5, 3)))), ph.ShapeError, "traj")
err(area, "L space of strings", lambda: INV.angular_momentum_space(
    trajectory_like([1.0], np.zeros((1, 3)), "up")), TypeError, "traj.angular_momentum_space")
# Exact values: the drifts of hand-made fields (|T - T0| / |T0|, ||L| - |L0|| / |L0|).
_E = [2.0, 3.0, 1.0]
_LB = [[3.0, 4.0, 0.0], [0.0, 0.0, 10.0], [6.0, 8.0, 0.0]]  # |L| = 5, 10, 10
_LS = [[0.0, 0.0, 5.0], [0.0, 0.0, 5.0], [0.0, 5.0, 5.0]]  # |L - L0| = 0, 0, 5
val(area, "relative_drift of given fields",
    lambda: INV.relative_drift(trajectory_like(_E, _LB, _LS)),
    keys_values({"energy": [0.0, 0.5, 0.5], "angular_momentum_norm": [0.0, 1.0, 1.0],
                 "angular_momentum_space": [0.0, 0.0, 1.0]}), "exact quotients")
val(area, "relative_drift without L in space",
    lambda: INV.relative_drift(trajectory_like(_E, _LB)),
    keys_values({"energy": [0.0, 0.5, 0.5], "angular_momentum_norm": [0.0, 1.0, 1.0]}),
    "exact quotients, no space key")
val(area, "max_relative_drift of given fields",
    lambda: INV.max_relative_drift(trajectory_like(_E, _LB, _LS)),
    keys_values({"energy": 0.5, "angular_momentum_norm": 1.0, "angular_momentum_space": 1.0}),
    "exact quotients")
val(area, "a body at rest drifts by absolute errors",
    lambda: INV.relative_drift(trajectory_like([0.0, 0.25], [[0.0] * 3, [0.0, 0.0, 0.5]])),
    keys_values({"energy": [0.0, 0.25], "angular_momentum_norm": [0.0, 0.5]}),
    "the numerator where the first value is 0")
val(area, "a batch decides body by body",
    lambda: INV.relative_drift(trajectory_like([[2.0, 1.0], [0.0, 3.0]],
                                               [[[1.0, 0, 0], [2.0, 0, 0]], [[0.0] * 3] * 2])),
    keys_values({"energy": [[0.0, 0.5], [0.0, 3.0]],
                 "angular_momentum_norm": [[0.0, 1.0], [0.0, 0.0]]}), "per-body quotients")
val(area, "max of an empty batch is 0",
    lambda: INV.max_relative_drift(trajectory_like(np.zeros((0, 4)), np.zeros((0, 4, 3)))),
    keys_values({"energy": 0.0, "angular_momentum_norm": 0.0}), "no entries: no drift")
val(area, "angular_momentum_space without orientation is None",
    lambda: INV.angular_momentum_space(ph.simulate(M123, W, 1.0, orientation=False)),
    lambda r: assert_true(r is None, repr(r)), "orientation=False keeps no L in space")
val(area, "a sphere's exact motion drifts by nothing",
    lambda: INV.max_relative_drift(ph.simulate((2.0, 2.0, 2.0), W, TIMES)),
    lambda r: assert_true(max(r.values()) <= 4 * EPS, r), "omega constant: T, |L|, L fixed")
val(area, "masked fields with nothing masked",
    lambda: INV.relative_drift(trajectory_like(masked(_E, [0, 0, 0]), _LB)),
    keys_values({"energy": [0.0, 0.5, 0.5], "angular_momentum_norm": [0.0, 1.0, 1.0]}),
    "the data of an unmasked masked array")
for _k in (1000, -1000):  # |L|^2 beyond doubles: the norms overflowed, or underflowed to 0
    val(area, f"relative_drift of given fields times 2^{_k}",
        lambda k=_k: INV.relative_drift(trajectory_like(*(np.ldexp(x, k) for x in (_E, _LB, _LS)))),
        keys_values({"energy": [0.0, 0.5, 0.5], "angular_momentum_norm": [0.0, 1.0, 1.0],
                     "angular_momentum_space": [0.0, 0.0, 1.0]}),
        "exact quotients (the power of two cancels)")

# --- numbers beyond double precision, masked arrays: every way arrays and numbers come in ------

area = "constructors"
for _name, _call, _argument in (
    ("sphere mass 2**2000", lambda: ph.Body.sphere(mass=BIG, radius=1.0), "mass"),
    ("sphere radius 2**2000", lambda: ph.Body.sphere(1.0, BIG), "radius"),
    ("cylinder length -2**2000", lambda: ph.Body.cylinder(1.0, 0.1, -BIG), "length"),
    ("solid torus major_radius 2**2000",
     lambda: ph.Body.solid("torus", 1.0, major_radius=BIG, minor_radius=1.0), "major_radius"),
    ("cuboid size [2**2000, 1, 1]", lambda: ph.Body.cuboid(1.0, [BIG, 1, 1]), "size"),
    ("sphere mass Fraction 10**400", lambda: ph.Body.sphere(Fraction(10**400, 3), 1.0), "mass"),
    ("point_masses masses [2**2000]", lambda: PM([BIG], [[0, 0, 0]]), "masses"),
    ("point_masses positions 2**2000", lambda: PM([1.0], [[0, BIG, 0]]), "positions"),
    ("from_inertia mass 2**2000", lambda: FI(BIG, np.eye(3)), "mass"),
    ("from_inertia tensor 2**2000", lambda: FI(1.0, [[BIG, 0, 0], [0, 1, 0], [0, 0, 1]]),
     "inertia"),
    ("from_urdf_inertia izz 2**2000", lambda: ph.Body.from_urdf_inertia(
        1.0, ixx=1, ixy=0, ixz=0, iyy=1, iyz=0, izz=BIG), "izz"),
    ("mesh density 2**2000", lambda: MESH(TET_V, TET_F, density=BIG), "density"),
    ("mesh vertices 2**2000", lambda: MESH([[0, 0, 0], [BIG, 0, 0], [0, 1, 0], [0, 0, 1]],
                                           TET_F, density=1.0), "vertices"),
):
    err(area, _name, _call, ph.NonFiniteError, _argument)
for _name, _call, _argument in (
    ("point_masses masses masked", lambda: PM(masked([1.0, 2.0], [0, 1]), np.eye(2, 3)),
     "masses"),
    ("point_masses positions masked", lambda: PM([1.0, 2.0], masked(np.eye(2, 3), np.eye(2, 3))),
     "positions"),
    ("from_inertia inertia masked", lambda: FI(1.0, masked(np.eye(3), np.eye(3))), "inertia"),
    ("from_inertia centre masked", lambda: FI(1.0, np.eye(3), masked([0, 0, 1], [1, 0, 0])),
     "center_of_mass"),
    ("cuboid size masked", lambda: ph.Body.cuboid(1.0, masked([1, 2, 3], [0, 0, 1])), "size"),
    ("sphere mass np.ma.masked", lambda: ph.Body.sphere(np.ma.masked, 1.0), "mass"),
    ("mesh faces masked", lambda: MESH(TET_V, np.ma.array(TET_F, mask=TET_F == 3), density=1.0),
     "faces"),
    ("mesh vertices masked", lambda: MESH(masked(TET_V, TET_V > 0.5), TET_F, density=1.0),
     "vertices"),
    ("from_fullinertia masked", lambda: ph.Body.from_fullinertia(
        1.0, masked([1, 1, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0])), "fullinertia"),
    ("from_spatial_inertia masked", lambda: ph.Body.from_spatial_inertia(
        masked(np.eye(6), np.eye(6))), "matrix"),
):
    err(area, _name, _call, ph.ArgumentError, _argument)
val(area, "sphere mass np.array(2.0)", lambda: ph.Body.sphere(np.array(2.0), 0.5),
    lambda b: close(b.inertia, np.eye(3) * 0.2, EPS), "2/5 m r^2")
val(area, "sphere mass Fraction(1, 3)", lambda: ph.Body.sphere(Fraction(1, 3), 3.0),
    lambda b: close(b.inertia, np.eye(3) * 1.2, 2 * EPS), "2/5 (1/3) 9")
val(area, "sphere mass 10**300 (an int within doubles)", lambda: ph.Body.sphere(10**300, 1e-100),
    lambda b: close(b.inertia, np.eye(3) * 0.4e100, 4 * EPS), "2/5 m r^2")
val(area, "point_masses of integer arrays", lambda: PM(np.array([1, 3]), np.array([[0, 0, 0],
                                                                              [4, 0, 0]])),
    lambda b: (close(b.center_of_mass, [3.0, 0, 0], 0.0),
               close(b.inertia, np.diag([0.0, 12.0, 12.0]), EPS)),
    "m1 m2 d^2 / (m1 + m2) = 12")
val(area, "point_masses masked with nothing masked",
    lambda: PM(masked([1.0, 3.0], [0, 0]), masked([[0, 0, 0], [4, 0, 0]], np.zeros((2, 3)))),
    lambda b: close(b.inertia, np.diag([0.0, 12.0, 12.0]), EPS), "the data of the arrays")
err(area, "solid kind None", lambda: ph.Body.solid(None, 1.0), TypeError, "kind")
err(area, "from_urdf_inertia ixx None", lambda: ph.Body.from_urdf_inertia(
    1.0, ixx=None, ixy=0, ixz=0, iyy=1, iyz=0, izz=1), TypeError, "ixx")
err(area, "from_spatial_inertia convention 3",
    lambda: ph.Body.from_spatial_inertia(np.eye(6), convention=3), ph.ArgumentError, "convention")
err(area, "from_spatial_inertia rtol 'x'",
    lambda: ph.Body.from_spatial_inertia(np.eye(6), rtol="x"), TypeError, "rtol")

# The componentwise tensor of a needle and of points just off an axis (exact values
# in rational arithmetic: tests/test_tensor_components.py).
_NEEDLE = (1.0, 1e-8, 1.0)
_AXIAL = Fraction(1.0) * Fraction(1e-8) ** 2 / 2  # m r^2 / 2, exactly, of the doubles given


def relative_to(exact_value, bound=16 * EPS, what=""):
    def check(x):
        error = abs(Fraction(float(x)) - exact_value) / exact_value
        assert error <= bound, f"{what}: {float(x)!r} for {float(exact_value)!r}"

    return check


val(area, "needle inertia[2, 2]", lambda: ph.Body.cylinder(*_NEEDLE).inertia[2, 2],
    relative_to(_AXIAL), "m r^2 / 2 in rationals")
val(area, "needle to_urdf_inertia izz", lambda: ph.Body.cylinder(*_NEEDLE).to_urdf_inertia()["izz"],
    relative_to(_AXIAL), "m r^2 / 2 in rationals")
val(area, "needle kinetic energy about its axis",
    lambda: ph.Body.cylinder(*_NEEDLE).kinetic_energy([0.0, 0.0, 3.0]),
    relative_to(_AXIAL * 9 / 2), "I_zz w^2 / 2 in rationals")
val(area, "needle spatial inertia about a point on its axis",
    lambda: ph.Body.cylinder(*_NEEDLE).spatial_inertia([0.0, 0.0, 0.3])[2, 2],
    relative_to(_AXIAL), "I_zz + m (d_x^2 + d_y^2) = I_zz")
_OFF = 1e-8
_FOUR = [[_OFF, 0, 0.5], [-_OFF, 0, -0.5], [0, _OFF, 0.2], [0, -_OFF, -0.2]]
val(area, "four points 1e-8 off the z axis: inertia[2, 2]",
    lambda: PM([1.0] * 4, _FOUR).inertia[2, 2], relative_to(4 * Fraction(_OFF) ** 2),
    "sum m (x^2 + y^2) in rationals")
val(area, "simulate of a needle's tensor keeps its energy",
    lambda: ph.simulate(ph.Body.cylinder(*_NEEDLE).inertia, [0.0, 0.0, 2.0], [0.0, 1.0]).energy,
    lambda e: [relative_to(_AXIAL * 2, 64 * EPS)(x) for x in e], "I_zz w^2 / 2")

# Pickling and deep copies: the round trip is the body, to its closed form.
area = "body"
import copy  # noqa: E402
import pickle  # noqa: E402

for _label, _copy in (("pickle", lambda b: pickle.loads(pickle.dumps(b))),
                      ("deepcopy", copy.deepcopy), ("pickle protocol 0",
                                                    lambda b: pickle.loads(pickle.dumps(b, 0)))):
    val(area, f"needle after {_label}", lambda c=_copy: c(ph.Body.cylinder(*_NEEDLE)).inertia[2, 2],
        relative_to(_AXIAL), "m r^2 / 2 in rationals")
    val(area, f"far composite after {_label}",
        lambda c=_copy: c(BOX.translated([1e8, 0.0, 0.0]) + ph.Body.sphere(1e-12, 1.0)),
        composite_check([ref.translate(BOX_REF, [1e8, 0.0, 0.0]), ref.sphere(1e-12, 1.0)],
                        rtol=1e-8), "reference composition (the offset costs 1e8 eps)")
    val(area, f"Principal after {_label}", lambda c=_copy: c(ph.principal(SPD)),
        principal_check(SPD), "mpmath eigenvalues")
    val(area, f"Trajectory after {_label}", lambda c=_copy: c(ph.simulate((2.0,) * 3, W, TIMES)),
        lambda sol: (close(sol.omega, sphere_motion(W, TIMES)[0], 0.0),
                     same_rotation(sol.quaternion, sphere_motion(W, TIMES)[1], 16 * EPS)),
        "a sphere: omega constant, q = exp(omega t / 2)")
    val(area, f"BodyFixed after {_label} stays read-only",
        lambda c=_copy: c(TQ.BodyFixed([0.0, 0.0, 1.0])).torque.flags.writeable,
        lambda w: assert_true(w is False, repr(w)), "models are immutable")
# Equality of the result types: every field equal, arrays exactly, NaN equal to NaN in the same
# place (polhode._equality); not hashable. Was: Analysis == Analysis raised numpy's "truth value
# of an array is ambiguous", Principal == Principal was identity (False for a copy).
area = "results"


def compared(make):
    """A row's call: for each (label, a, b, expected) of ``make()``, a == b and a != b."""
    return lambda: [(label, a == b, a != b, expected) for label, a, b, expected in make()]


def as_expected(results):
    for label, eq, ne, expected in results:
        assert eq is expected and ne is (not expected), (label, eq, ne)


def _analyses():
    a = ph.analyze(M123, W)
    return [("the same call", a, ph.analyze(M123, W), True),
            ("pickled", a, pickle.loads(pickle.dumps(a)), True),
            ("deep-copied", a, copy.deepcopy(a), True),
            ("another omega", a, ph.analyze(M123, W * 2), False),
            ("another body", a, ph.analyze((1.0, 2.0, 3.5), W), False),
            ("a str", a, "an Analysis", False), ("None", a, None, False)]


def _principals():
    p = ph.principal(SPD)
    batch = ph.principal(np.stack([SPD, np.eye(3)]))
    with_nan = ph.Principal(np.array([NAN, 1.0, 2.0]), np.eye(3), np.array([1, 1, 1]))
    signed = ph.Principal(np.array([0.0, 1.0, 2.0]), np.eye(3), np.array([1, 1, 1]))
    return [("the same tensor", p, ph.principal(SPD), True),
            ("pickled", p, pickle.loads(pickle.dumps(p)), True),
            ("another tensor", p, ph.principal(np.diag([1.0, 2.0, 3.5])), False),
            ("a batch", p, batch, False),
            ("the same batch", batch, ph.principal(np.stack([SPD, np.eye(3)])), True),
            ("its tuple", p, tuple(p), False), ("(moments, axes)", p, (p.moments, p.axes), False),
            ("NaN in the same place", with_nan, copy.deepcopy(with_nan), True),
            ("0.0 and -0.0", signed,
             ph.Principal(np.array([-0.0, 1.0, 2.0]), np.eye(3), np.array([1, 1, 1])), True),
            ("another multiplicity", signed,
             ph.Principal(signed.moments, signed.axes, np.array([1, 2, 2])), False)]


val(area, "Analysis ==", compared(_analyses), as_expected,
    "the same call, its copies: equal; another omega or body, another type: not")
val(area, "Principal ==", compared(_principals), as_expected,
    "the same tensor, copies, NaN in the same place, 0.0 and -0.0: equal; another tensor, "
    "a batch, a tuple, another multiplicity: not")
err(area, "hash(Analysis)", lambda: hash(ph.analyze(M123, W)), TypeError, None,
    fragment="unhashable")
err(area, "hash(Principal)", lambda: hash(ph.principal(SPD)), TypeError, None,
    fragment="unhashable")
val(area, "Trajectory == its copy",
    compared(lambda: [("deep-copied", *(lambda t: (t, copy.deepcopy(t)))(
        ph.simulate(M123, W, TIMES)), True)]), as_expected,
    "equal motion, stats apart")
area = "body"
err(area, "inertia_about point masked", lambda: BOX.inertia_about(masked([0, 0, 1], [1, 0, 0])),
    ph.ArgumentError, "point")
err(area, "translated masked", lambda: BOX.translated(masked([0, 0, 1], [0, 1, 0])),
    ph.ArgumentError, "offset")
err(area, "translated 2**2000", lambda: BOX.translated([BIG, 0, 0]), ph.NonFiniteError, "offset")
err(area, "rotated masked quaternion", lambda: BOX.rotated(masked([0, 0, 0, 1], [1, 0, 0, 0])),
    ph.ArgumentError, "rotation")
err(area, "scaled mass_scale 2**2000", lambda: BOX.scaled(BIG), ph.NonFiniteError, "mass_scale")
err(area, "scaled length_scale -2**2000", lambda: BOX.scaled(1.0, -BIG), ph.NonFiniteError,
    "length_scale")
err(area, "kinetic_energy omega masked", lambda: BOX.kinetic_energy(masked(W, [0, 0, 1])),
    ph.ArgumentError, "omega")
err(area, "kinetic_energy omega 2**2000", lambda: BOX.kinetic_energy([BIG, 0, 0]),
    ph.NonFiniteError, "omega")
err(area, "angular_momentum_body omega masked",
    lambda: BOX.angular_momentum_body(masked(W, [1, 0, 0])), ph.ArgumentError, "omega")
err(area, "spatial_inertia point masked", lambda: BOX.spatial_inertia(masked([0, 0, 1], [1, 0, 0])),
    ph.ArgumentError, "point")
err(area, "spatial_inertia inverse 1", lambda: BOX.spatial_inertia(inverse=1), TypeError, "inverse")
err(area, "principal rtol 2**2000", lambda: BOX.principal(rtol=BIG), ph.NonFiniteError, "rtol")
val(area, "inertia_about a masked point with nothing masked",
    lambda: BOX.inertia_about(masked([0.0, 0.0, 1.0], [0, 0, 0])),
    lambda i: close(i, ref.parallel_axis(BOX_REF.inertia, 2.0, np.zeros(3), [0.0, 0.0, 1.0]),
                    4 * EPS), "parallel axis")

# --- principal() and point_masses_inertia(): options and array kinds -------------------------

area = "principal"
err(area, "masked entries", lambda: ph.principal(masked(np.diag([1.0, 2.0, 3.0]),
                                                                   np.eye(3))),
    ph.ArgumentError, "inertia")
err(area, "masked entries in a batch", lambda: ph.principal(masked(np.stack([SPD, SPD]),
                                                                   np.arange(18).reshape(2, 3, 3)
                                                                   == 17)),
    ph.ArgumentError, "inertia")
err(area, "masked entries, continuous", lambda: ph.principal(
    masked(np.stack([SPD, SPD]), np.arange(18).reshape(2, 3, 3) == 0), continuous=True),
    ph.ArgumentError, "inertia")
val(area, "masked array with nothing masked",
    lambda: ph.principal(np.ma.array(SPD, mask=np.zeros((3, 3), dtype=bool))),
    principal_check(SPD), "mpmath eigenvalues")
val(area, "masked array without a mask", lambda: ph.principal(np.ma.array(SPD)),
    principal_check(SPD), "mpmath eigenvalues")
err(area, "rtol 2**2000", lambda: ph.principal(SPD, rtol=BIG), ph.NonFiniteError, "rtol")
err(area, "rtol 'x'", lambda: ph.principal(SPD, rtol="x"), TypeError, "rtol")
err(area, "rtol [1e-3]", lambda: ph.principal(SPD, rtol=[1e-3]), TypeError, "rtol")
err(area, "rtol inf", lambda: ph.principal(SPD, rtol=INF), ph.ArgumentError, "rtol")
err(area, "continuous 1", lambda: ph.principal(np.stack([SPD] * 2), continuous=1), TypeError,
    "continuous")
err(area, "continuous 'yes'", lambda: ph.principal(np.stack([SPD] * 2), continuous="yes"),
    TypeError, "continuous")
err(area, "entries beyond doubles", lambda: ph.principal([[BIG, 0, 0], [0, 1, 0], [0, 0, 1]]),
    ph.NonFiniteError, "inertia")
err(area, "a None entry", lambda: ph.principal([[1, 0, 0], [0, None, 0], [0, 0, 1]]), TypeError,
    "inertia")
err(area, "ragged rows", lambda: ph.principal([[1, 0, 0], [0, 1], [0, 0, 1]]), TypeError,
    "inertia")
err(area, "(4, 4)", lambda: ph.principal(np.eye(4)), ph.ShapeError, "inertia")
val(area, "a bool identity", lambda: ph.principal(np.eye(3, dtype=bool)),
    lambda p: (close(p.moments, [1.0, 1.0, 1.0], 0.0), assert_equal(p.multiplicity, [3, 3, 3])),
    "the identity: one triple moment")
val(area, "int entries", lambda: ph.principal(np.diag([3, 1, 2])),
    lambda p: (close(p.moments, [1.0, 2.0, 3.0], 0.0),
               close(np.abs(p.axes), [[0, 0, 1], [1, 0, 0], [0, 1, 0]], 0.0)),
    "a diagonal tensor: its entries, sorted")
val(area, "float32 entries", lambda: ph.principal(SPD.astype(np.float32)),
    principal_check(SPD.astype(np.float32).astype(np.float64)), "mpmath of the float32 values")
val(area, "Fortran order", lambda: ph.principal(np.asfortranarray(SPD)), principal_check(SPD),
    "mpmath eigenvalues")
val(area, "a strided batch", lambda: ph.principal(np.stack([SPD, np.eye(3), SPD])[::2]),
    batch_check([SPD, SPD], [(1, 1, 1), (1, 1, 1)]), "mpmath eigenvalues")
val(area, "an empty batch, continuous", lambda: ph.principal(np.zeros((0, 3, 3)), continuous=True),
    lambda p: assert_true(p.moments.shape == (0, 3) and p.axes.shape == (0, 3, 3)),
    "no tensors, no axes")
PMI = ph.point_masses_inertia
err(area, "point_masses_inertia masses masked",
    lambda: PMI(masked([1.0, 1.0], [1, 0]), np.eye(2, 3)), ph.ArgumentError, "masses")
err(area, "point_masses_inertia positions masked",
    lambda: PMI([1.0, 1.0], masked(np.eye(2, 3), np.eye(2, 3))), ph.ArgumentError, "positions")
err(area, "point_masses_inertia float32 positions masked",
    lambda: PMI([1.0, 1.0], np.ma.array(np.eye(2, 3, dtype=np.float32), mask=np.eye(2, 3))),
    ph.ArgumentError, "positions")
err(area, "point_masses_inertia positions 2**2000",
    lambda: PMI([1.0, 1.0], [[0, 0, 0], [BIG, 0, 0]]), ph.NonFiniteError, "positions")
err(area, "point_masses_inertia masses 'x'", lambda: PMI("x", np.eye(2, 3)), TypeError, "masses")
err(area, "point_masses_inertia positions (1, 2, 2, 3)",
    lambda: PMI([1.0, 1.0], np.ones((1, 2, 2, 3))), ph.ShapeError, "positions")
val(area, "point_masses_inertia float16 positions",
    lambda: PMI([1.0, 3.0], np.array([[0, 0, 0], [4, 0, 0]], dtype=np.float16)),
    lambda i: close(i, np.diag([0.0, 12.0, 12.0]), EPS), "m1 m2 d^2 / (m1 + m2)")
val(area, "point_masses_inertia float32 masked, nothing masked",
    lambda: PMI([1.0, 3.0], np.ma.array(np.array([[0, 0, 0], [4, 0, 0]], dtype=np.float32))),
    lambda i: close(i, np.diag([0.0, 12.0, 12.0]), EPS), "m1 m2 d^2 / (m1 + m2)")

# --- simulate and analyze: the types of their arguments (the values are the core's) ---------

area = "simulate"
SIM_BAD_TYPES = [
    ("method None", {"method": None}, "method"),
    ("method b'rk4'", {"method": b"rk4"}, "method"),
    ("method ['rk4']", {"method": ["rk4"]}, "method"),
    ("dt '0.1'", {"method": "rk4", "dt": "0.1"}, "dt"),
    ("dt [0.1]", {"method": "rk4", "dt": [0.1]}, "dt"),
    ("dt Decimal", {"method": "rk4", "dt": __import__("decimal").Decimal("0.1")}, "dt"),
    ("dt complex", {"method": "rk4", "dt": 0.1 + 0j}, "dt"),
    ("dt True", {"method": "rk4", "dt": True}, "dt"),
    ("order 4.0", {"method": "splitting", "dt": 0.1, "order": 4.0}, "order"),
    ("order '4'", {"method": "splitting", "dt": 0.1, "order": "4"}, "order"),
    ("order None", {"method": "splitting", "dt": 0.1, "order": None}, "order"),
    ("rtol '1e-8'", {"method": "dop853", "rtol": "1e-8"}, "rtol"),
    ("rtol None", {"method": "dop853", "rtol": None}, "rtol"),
    ("atol '1'", {"method": "dop853", "atol": "1"}, "atol"),
    ("t0 '0'", {"t0": "0"}, "t0"),
    ("t0 None", {"t0": None}, "t0"),
    ("orientation 'no'", {"orientation": "no"}, "orientation"),
    ("orientation 0", {"orientation": 0}, "orientation"),
    ("orientation None", {"orientation": None}, "orientation"),
    ("max_steps 1.5", {"method": "rk4", "dt": 0.1, "max_steps": 1.5}, "max_steps"),
    ("max_steps '10'", {"method": "rk4", "dt": 0.1, "max_steps": "10"}, "max_steps"),
    ("progress 'yes'", {"progress": "yes"}, "progress"),
    ("progress 1", {"progress": 1}, "progress"),
    ("torque 'gravity'", {"torque": "gravity"}, "torque"),
    ("torque 3", {"torque": 3}, "torque"),
    ("torque [0, 0, 1]", {"torque": [0.0, 0.0, 1.0]}, "torque"),
    ("rotors 'wheel'", {"rotors": "wheel"}, "rotors"),
    ("rotors [3]", {"rotors": [3]}, "rotors"),
    ("orientation0 'x'", {"orientation0": "x"}, "orientation0"),
]
for _label, _kwargs, _argument in SIM_BAD_TYPES:
    err(area, _label, lambda k=_kwargs: ph.simulate(M123, W, 1.0, **k), TypeError, _argument)
for _label, _args, _argument in (
    ("body 'cube'", ("cube", W, 1.0), "body"),
    ("body None", (None, W, 1.0), "body"),
    ("body a dict", ({"I": 1}, W, 1.0), "body"),
    ("omega0 None", (M123, None, 1.0), "omega0"),
    ("omega0 'xyz'", (M123, "xyz", 1.0), "omega0"),
    ("t '10'", (M123, W, "10"), "t"),
    ("t None", (M123, W, None), "t"),
    ("t a dict", (M123, W, {1: 2}), "t"),
    ("t a set", (M123, W, {1.0, 2.0})  , "t"),
    ("t a generator", (M123, W, (x for x in [0.0, 1.0])), "t"),
):
    err(area, _label, lambda a=_args: ph.simulate(*a), TypeError, _argument)
for _label, _call, _argument in (
    ("t masked", lambda: ph.simulate(M123, W, masked([0.0, 1.0, 2.0], [0, 1, 0])), "t"),
    ("omega0 masked", lambda: ph.simulate(M123, masked(W, [1, 0, 0]), 1.0), "omega0"),
    ("body masked", lambda: ph.simulate(masked(M123, [0, 1, 0]), W, 1.0), "body"),
    ("orientation0 masked", lambda: ph.simulate(M123, W, 1.0, orientation0=masked(
        [0, 0, 0, 1], [0, 0, 0, 1])), "orientation0"),
    ("batch omega0 masked", lambda: ph.simulate(M123, masked(np.ones((2, 3)), np.eye(2, 3)),
                                                1.0), "omega0"),
):
    err(area, _label, _call, ph.ArgumentError, _argument)
for _label, _call, _argument in (
    ("t 2**2000", lambda: ph.simulate(M123, W, BIG), "t"),
    ("t [0, 2**2000]", lambda: ph.simulate(M123, W, [0, BIG]), "t"),
    ("omega0 [2**2000, 0, 0]", lambda: ph.simulate(M123, [BIG, 0, 0], 1.0), "omega0"),
    ("dt 2**2000", lambda: ph.simulate(M123, W, 1.0, method="rk4", dt=BIG), "dt"),
    ("t0 -2**2000", lambda: ph.simulate(M123, W, 1.0, t0=-BIG), "t0"),
    ("rtol 2**2000", lambda: ph.simulate(M123, W, 1.0, method="dop853", rtol=BIG), "rtol"),
    ("body moments 2**2000", lambda: ph.simulate([1, 2, BIG], W, 1.0), "body"),
):
    err(area, _label, _call, ph.NonFiniteError, _argument)
err(area, "max_steps 2**70", lambda: ph.simulate(M123, W, 1.0, method="rk4", dt=0.1,
                                                 max_steps=2**70), ph.ArgumentError, "max_steps")
_SPHERE_T = np.array([0.0, 0.5, 1.0])
for _label, _kwargs, _bound in (
    ("dt Fraction(1, 1000)", {"method": "rk4", "dt": Fraction(1, 1000)}, BOUND["rk4"]),
    ("dt np.float32(0.001)", {"method": "rk4", "dt": np.float32(0.001)}, BOUND["rk4"]),
    ("order np.int8(4)", {"method": "splitting", "dt": 1e-3, "order": np.int8(4)},
     BOUND["splitting"]),
    ("orientation np.bool_(True)", {"orientation": np.bool_(True)}, CLOSED["exact"]),
    ("t0 np.float32(0)", {"t0": np.float32(0.0)}, CLOSED["exact"]),
    ("t masked, nothing masked", {}, CLOSED["exact"]),
):
    val(area, _label,
        lambda k=_kwargs, lbl=_label: ph.simulate(
            (2.0, 2.0, 2.0), W,
            masked(_SPHERE_T, [0, 0, 0]) if lbl.startswith("t masked") else _SPHERE_T, **k),
        lambda sol, b=_bound: (close(sol.omega, sphere_motion(W, _SPHERE_T)[0], b),
                               same_rotation(sol.quaternion, sphere_motion(W, _SPHERE_T)[1], b)),
        "a sphere: omega constant, q = exp(omega t / 2) (the method's error bound)")
val(area, "orientation np.bool_(False)",
    lambda: ph.simulate((2.0, 2.0, 2.0), W, 1.0, orientation=np.bool_(False)),
    lambda sol: (assert_true(sol.quaternion is None),
                 close(sol.omega, np.tile(W, (sol.t.size, 1)), 4 * EPS)),
    "a sphere: omega constant")
# Euler angles of a trajectory.
_SPIN_Z = ph.simulate((1.0, 2.0, 3.0), [0.0, 0.0, 1.5], np.linspace(0.0, 10.0, 41))
err(area, "euler_angles seq 3", lambda: _SPIN_Z.euler_angles(3), TypeError, "seq")
err(area, "euler_angles seq 'ABC'", lambda: _SPIN_Z.euler_angles("ABC"), ph.ArgumentError, "seq")
err(area, "euler_angles seq 'ZZX'", lambda: _SPIN_Z.euler_angles("ZZX"), ph.ArgumentError, "seq")
err(area, "euler_angles degrees 1", lambda: _SPIN_Z.euler_angles(degrees=1), TypeError, "degrees")
err(area, "euler_angles without orientation",
    lambda: ph.simulate(M123, W, 1.0, orientation=False).euler_angles(), ph.ArgumentError,
    "orientation")
val(area, "euler_angles of a spin about z (ZXZ)", lambda: _SPIN_Z.euler_angles(),
    lambda a: close(a, np.column_stack([1.5 * np.linspace(0.0, 10.0, 41), np.zeros((41, 2))]),
                    64 * EPS, 1e-13), "phi = w t, unwrapped; theta = psi = 0 (gimbal lock)")
val(area, "euler_angles of a spin about x (ZYX, degrees)",
    lambda: ph.simulate((1.0, 2.0, 3.0), [2.0, 0.0, 0.0], np.linspace(0.0, 9.0, 37)).euler_angles(
        "ZYX", degrees=True),
    lambda a: close(a, np.column_stack([np.zeros((37, 2)), np.degrees(2.0 * np.linspace(
        0.0, 9.0, 37))]), 64 * EPS, 1e-11), "Tait-Bryan: the third angle is w t, unwrapped")

area = "analyze"
for _label, _call, _error, _argument in (
    ("body 'x'", lambda: ph.analyze("x", W), TypeError, "body"),
    ("omega0 None", lambda: ph.analyze(M123, None), TypeError, "omega0"),
    ("rtol 'x'", lambda: ph.analyze(M123, W, rtol="x"), TypeError, "rtol"),
    ("rtol 2**2000", lambda: ph.analyze(M123, W, rtol=BIG), ph.NonFiniteError, "rtol"),
    ("rotors 3", lambda: ph.analyze(M123, W, rotors=3), TypeError, "rotors"),
    ("body masked", lambda: ph.analyze(masked(M123, [1, 0, 0]), W), ph.ArgumentError, "body"),
    ("omega0 masked", lambda: ph.analyze(M123, masked(W, [0, 0, 1])), ph.ArgumentError,
     "omega0"),
    ("omega0 2**2000", lambda: ph.analyze(M123, [BIG, 0, 0]), ph.NonFiniteError, "omega0"),
    ("nutation_rate body 'x'", lambda: ph.rotors.nutation_rate(
        "x", W, ph.rotors.SphericalDamper(0.1, 0.1)), TypeError, "body"),
    ("nutation_rate damper a Wheel", lambda: ph.rotors.nutation_rate(
        M123, W, ph.rotors.Wheel([0, 0, 1], 0.1)), TypeError, "damper"),
    ("nutation_rate damper None", lambda: ph.rotors.nutation_rate(M123, W, None), TypeError,
     "damper"),
    ("nutation_rate omega0 masked", lambda: ph.rotors.nutation_rate(
        M123, masked(W, [1, 0, 0]), ph.rotors.SphericalDamper(0.1, 0.1)), ph.ArgumentError,
     "omega0"),
):
    err(area, _label, _call, _error, _argument)
val(area, "a diagonal tensor as the body", lambda: ph.analyze(np.diag([3.0, 1.0, 2.0]),
                                                              [0.0, 0.0, 1.0]),
    lambda a: (assert_true(a.regime == "steady_intermediate", a.regime),
               close(a.energy, 1.0, 0.0), close(a.angular_momentum_norm, 2.0, 0.0)),
    "a spin about z, I_zz = 2 the intermediate moment: steady, T = 1, |L| = 2")
# At the ends of double precision: products of two moments of 2^+-1000 are beyond doubles
# (turns_over was False at 2^1000, a ZeroDivisionError at 2^-1000); the motion does not depend
# on the scale of the moments.
for _k in (1000, -1000):
    _SCALED = tuple(math.ldexp(x, _k) for x in M123)
    val(area, f"moments 2^{_k} [1, 2, 3] that turn over",
        lambda m=_SCALED: ph.analyze(m, [0.1, 1.0, 0.2]),
        analysis_check(_SCALED, [0.1, 1.0, 0.2]),
        "exact invariants, turns_over_exact and exact_period in rationals (any scale)")

# --- perturbation: argument types and masked arrays ---------------------------------------------

area = "perturbation"
for _label, _call, _error, _argument in (
    ("moments 'abc'", lambda: ph.perturbation("abc", PW, [0.0, 1.0]), TypeError, "moments"),
    ("moments None", lambda: ph.perturbation(None, PW, [0.0, 1.0]), TypeError, "moments"),
    ("t '1'", lambda: ph.perturbation(M123, PW, "1"), TypeError, "t"),
    ("t None", lambda: ph.perturbation(M123, PW, None), TypeError, "t"),
    ("axis 1.0", lambda: ph.perturbation(M123, PW, [0.0, 1.0], axis=1.0), TypeError, "axis"),
    ("axis True", lambda: ph.perturbation(M123, PW, [0.0, 1.0], axis=True), TypeError, "axis"),
    ("axis -1", lambda: ph.perturbation(M123, PW, [0.0, 1.0], axis=-1), ph.ArgumentError,
     "axis"),
    ("order 2.0", lambda: ph.perturbation(M123, PW, [0.0, 1.0], order=2.0), TypeError, "order"),
    ("order None", lambda: ph.perturbation(M123, PW, [0.0, 1.0], order=None), TypeError,
     "order"),
    ("order -1", lambda: ph.perturbation(M123, PW, [0.0, 1.0], order=-1), ph.ArgumentError,
     "order"),
    ("omega0 (3, 1)", lambda: ph.perturbation(M123, [[1e-3], [0.0], [1.0]], [0.0, 1.0]),
     ph.ShapeError, "omega0"),
    ("t (1, 1)", lambda: ph.perturbation(M123, PW, [[1.0]]), ph.ShapeError, "t"),
    ("moments (1, 3)", lambda: ph.perturbation([M123], PW, [0.0, 1.0]), ph.ShapeError,
     "moments"),
    ("moments inf", lambda: ph.perturbation([1.0, 2.0, INF], PW, [0.0, 1.0]), ph.ArgumentError,
     "moments"),
    ("omega0 masked", lambda: ph.perturbation(M123, masked(PW, [1, 0, 0]), [0.0, 1.0]),
     ph.ArgumentError, "omega0"),
    ("t masked", lambda: ph.perturbation(M123, PW, masked([0.0, 1.0], [0, 1])),
     ph.ArgumentError, "t"),
    ("moments masked", lambda: ph.perturbation(masked(M123, [0, 0, 1]), PW, [0.0, 1.0]),
     ph.ArgumentError, "moments"),
    ("t 2**2000", lambda: ph.perturbation(M123, PW, [0, BIG]), ph.NonFiniteError, "t"),
    ("omega0 2**2000", lambda: ph.perturbation(M123, [0, 0, BIG], [0.0, 1.0]), ph.NonFiniteError,
     "omega0"),
):
    err(area, _label, _call, _error, _argument)
val(area, "no times", lambda: ph.perturbation(M123, PW, []),
    lambda r: assert_true(np.shape(r) == (0, 3), np.shape(r)), "(0, 3)")
val(area, "a sphere: omega constant", lambda: ph.perturbation((2.0, 2.0, 2.0), PW, PT),
    lambda r: close(r, np.tile(PW, (len(PT), 1)), 0.0), "omega x I omega = 0")
val(area, "a symmetric top about its axis", lambda: ph.perturbation((2.0, 2.0, 3.0), PW, PT),
    perturbation_check((2.0, 2.0, 3.0), PW, PT, 2), "scipy DOP853")
val(area, "a pure spin from integers", lambda: ph.perturbation([1, 2, 3], [0, 0, 2], [0, 1]),
    lambda r: close(r, [[0.0, 0.0, 2.0], [0.0, 0.0, 2.0]], 0.0), "the steady rotation")
val(area, "a masked t with nothing masked",
    lambda: ph.perturbation(M123, PW, masked(PT, [0, 0, 0, 0])),
    perturbation_check(M123, PW, PT, 2), "scipy DOP853")

# --- molecules ---------------------------------------------------------------------------------

area = "molecule"
from polhode import molecule as MOL  # noqa: E402

_WATER_R = [[0, 0, 0.1173], [0, 0.7572, -0.4692], [0, -0.7572, -0.4692]]
_WATER = ph.Body.from_atoms(["O", "H", "H"], _WATER_R)
_CO = ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.128323]])
_HE = ph.Body.from_atoms(["He"], [[0, 0, 0]])
_CH4_D = 1.087 / 3**0.5
_CH4 = ph.Body.from_atoms(["C", "H", "H", "H", "H"], [
    [0, 0, 0], [_CH4_D, _CH4_D, _CH4_D], [_CH4_D, -_CH4_D, -_CH4_D], [-_CH4_D, _CH4_D, -_CH4_D],
    [-_CH4_D, -_CH4_D, _CH4_D]])
# AME 2020 (M. Wang et al. 2021); periodictable, which polhode reads, rounds them to 10-12
# digits (16O: 15.9949146193 for 15.994914619257): values are compared to MASSES_RTOL.
MASSES_RTOL = 1e-10
_AME = {"1H": 1.007825031898, "2H": 2.014101777844, "12C": 12.0, "13C": 13.003354835336,
        "16O": 15.994914619257}
for _function in (MOL.rotational_constants, MOL.rotor_type, MOL.asymmetry):
    _fname = _function.__name__
    for _label, _kwargs, _error, _argument in (
        ("rtol -1", {"rtol": -1.0}, ph.ArgumentError, "rtol"),
        ("rtol nan", {"rtol": NAN}, ph.ArgumentError, "rtol"),
        ("rtol 1", {"rtol": 1.0}, ph.ArgumentError, "rtol"),
        ("rtol '1e-3'", {"rtol": "1e-3"}, TypeError, "rtol"),
        ("rtol True", {"rtol": True}, TypeError, "rtol"),
        ("rtol 2**2000", {"rtol": BIG}, ph.NonFiniteError, "rtol"),
    ):
        err(area, f"{_fname} {_label}", lambda f=_function, k=_kwargs: f(_WATER, **k), _error,
            _argument)
    err(area, f"{_fname} of moments", lambda f=_function: f([1.0, 2.0, 3.0]), TypeError, "body")
    err(area, f"{_fname} of None", lambda f=_function: f(None), TypeError, "body")
    err(area, f"{_fname} of one atom", lambda f=_function: f(_HE), ph.ArgumentError, "body")
for _label, _kwargs, _error, _argument in (
    ("unit 5", {"unit": 5}, TypeError, "unit"),
    ("unit 'Hz'", {"unit": "Hz"}, ph.ArgumentError, "unit"),
    ("unit 'mhz'", {"unit": "mhz"}, ph.ArgumentError, "unit"),
    ("unit None", {"unit": None}, TypeError, "unit"),
    ("length_unit 'feet'", {"length_unit": "feet"}, ph.ArgumentError, "length_unit"),
    ("length_unit 3", {"length_unit": 3}, TypeError, "length_unit"),
    ("mass_unit None", {"mass_unit": None}, TypeError, "mass_unit"),
    ("mass_unit 'g'", {"mass_unit": "g"}, ph.ArgumentError, "mass_unit"),
):
    err(area, f"rotational_constants {_label}",
        lambda k=_kwargs: MOL.rotational_constants(_WATER, **k), _error, _argument)
err(area, "asymmetry of a spherical top", lambda: MOL.asymmetry(_CH4), ph.ArgumentError, "body")


def _b_mhz(moment_u_angstrom2: float) -> float:
    """B = h / (8 pi^2 I) in MHz for I in u angstrom^2 (CODATA through scipy.constants)."""
    import scipy.constants as sc

    kg_m2 = moment_u_angstrom2 * sc.physical_constants["atomic mass constant"][0] * 1e-20
    return sc.h / (8 * math.pi**2 * kg_m2) * 1e-6


def _diatomic_moment(m1, m2, r):
    return m1 * m2 / (m1 + m2) * r * r


def _water_moments():
    """numpy's eigenvalues of the water molecule's inertia tensor (AME 2020 masses)."""
    m = np.array([_AME["16O"], _AME["1H"], _AME["1H"]])
    r = np.asarray(_WATER_R, dtype=float)
    r = r - m @ r / m.sum()
    inertia = sum(mk * (rk @ rk * np.eye(3) - np.outer(rk, rk))
                  for mk, rk in zip(m, r, strict=True))
    return np.linalg.eigvalsh(inertia)


val(area, "CO: linear, A None, B from h / (8 pi^2 mu r^2)", lambda: MOL.rotational_constants(_CO),
    lambda c: (assert_true(c.A is None), close(c.B, _b_mhz(_diatomic_moment(
        _AME["12C"], _AME["16O"], 1.128323)), MASSES_RTOL), assert_true(c.B == c.C)),
    "CODATA constants, AME masses")
val(area, "13C16O over 12C16O: B scales as 1 / mu",
    lambda: MOL.rotational_constants(ph.Body.from_atoms(["13C", "O"], [[0, 0, 0], [0, 0, 1.1]])).B
    / MOL.rotational_constants(ph.Body.from_atoms(["C", "O"], [[0, 0, 0], [0, 0, 1.1]])).B,
    lambda ratio: close(ratio, (_AME["12C"] * _AME["16O"] / (_AME["12C"] + _AME["16O"]))
                        / (_AME["13C"] * _AME["16O"] / (_AME["13C"] + _AME["16O"])),
                        MASSES_RTOL),
    "reduced masses")
val(area, "D2 over H2: B halves (to the masses)",
    lambda: MOL.rotational_constants(ph.Body.from_atoms(["D", "D"], [[0, 0, 0], [0, 0, 0.74]])).B
    / MOL.rotational_constants(ph.Body.from_atoms(["H", "H"], [[0, 0, 0], [0, 0, 0.74]])).B,
    lambda ratio: close(ratio, _AME["1H"] / _AME["2H"], MASSES_RTOL), "reduced masses m / 2")
val(area, "asymmetry of CO is -1", lambda: MOL.asymmetry(_CO),
    lambda k: close(k, -1.0, 0.0), "the prolate limit")
val(area, "CO2 is linear", lambda: MOL.rotor_type(ph.Body.from_atoms(
    ["O", "C", "O"], [[0, 0, -1.16], [0, 0, 0], [0, 0, 1.16]])),
    lambda t: assert_true(t == "linear", t), "all atoms on a line")
val(area, "methane is spherical", lambda: MOL.rotor_type(_CH4),
    lambda t: assert_true(t == "spherical", t), "tetrahedral symmetry")
val(area, "water's constants from numpy's moments", lambda: MOL.rotational_constants(_WATER),
    lambda c: close([c.A, c.B, c.C], [_b_mhz(x) for x in _water_moments()], MASSES_RTOL),
    "numpy eigvalsh, CODATA")
val(area, "water's asymmetry by Ray's formula", lambda: MOL.asymmetry(_WATER),
    lambda k: close(k, (lambda a, b, c: (2 * b - a - c) / (a - c))(
        *[1.0 / x for x in _water_moments()]), MASSES_RTOL), "kappa = (2B - A - C) / (A - C)")
val(area, "GHz is MHz / 1000", lambda: (MOL.rotational_constants(_WATER, "GHz"),
                                        MOL.rotational_constants(_WATER, "MHz")),
    lambda pair: close(pair[0], np.asarray(pair[1]) / 1000, 2 * EPS), "unit conversion")
val(area, "cm-1 is MHz / (100 c)", lambda: (MOL.rotational_constants(_WATER, "cm-1"),
                                            MOL.rotational_constants(_WATER, "MHz")),
    lambda pair: close(pair[0], np.asarray(pair[1]) * 1e6 / (100 * 299792458.0), 4 * EPS),
    "c = 299792458 m/s exactly")
val(area, "length_unit nm of a body in nm", lambda: MOL.rotational_constants(
    ph.Body.from_atoms(["O", "H", "H"], np.asarray(_WATER_R) / 10), length_unit="nm"),
    lambda c: close([c.A, c.B, c.C], [_b_mhz(x) for x in _water_moments()], MASSES_RTOL),
    "the same molecule")
val(area, "mass_unit kg of a body in kg", lambda: MOL.rotational_constants(
    ph.Body.from_atoms(["O", "H", "H"], _WATER_R,
                       masses=np.array([_AME["16O"], _AME["1H"], _AME["1H"]])
                       * 1.66053906892e-27), mass_unit="kg"),
    lambda c: close([c.A, c.B, c.C], [_b_mhz(x) for x in _water_moments()], 1e-9),
    "the same molecule (the atomic mass constant to 1e-9)")
val(area, "atomic numbers are the elements", lambda: ph.Body.from_atoms([6, 8], [[0, 0, 0],
                                                                                [0, 0, 1.0]]),
    lambda b: close(b.mass, _AME["12C"] + _AME["16O"], MASSES_RTOL), "AME 2020")
val(area, "numpy integer labels", lambda: ph.Body.from_atoms(np.array([1, 1]), [[0, 0, 0],
                                                                                [0, 0, 1.0]]),
    lambda b: close(b.mass, 2 * _AME["1H"], MASSES_RTOL), "AME 2020")
val(area, "isotopes 13C, D, 2H", lambda: ph.Body.from_atoms(["13C", "D", "2H"], np.eye(3)),
    lambda b: close(b.mass, _AME["13C"] + 2 * _AME["2H"], MASSES_RTOL), "AME 2020")
val(area, "average masses", lambda: ph.Body.from_atoms(["O", "H", "H"], _WATER_R,
                                                       masses="average"),
    lambda b: close(b.mass, 15.999 + 2 * 1.008, 2 * EPS), "CIAAW 2021 abridged")
for _label, _call, _error, _argument in (
    ("symbols '99C'", lambda: ph.Body.from_atoms(["99C"], [[0, 0, 0]]), ph.ArgumentError,
     "symbols"),
    ("symbols [0]", lambda: ph.Body.from_atoms([0], [[0, 0, 0]]), ph.ArgumentError, "symbols"),
    ("symbols [119]", lambda: ph.Body.from_atoms([119], [[0, 0, 0]]), ph.ArgumentError,
     "symbols"),
    ("symbols 'CL'", lambda: ph.Body.from_atoms(["CL"], [[0, 0, 0]]), ph.ArgumentError,
     "symbols"),
    ("symbols '3D'", lambda: ph.Body.from_atoms(["3D"], [[0, 0, 0]]), ph.ArgumentError,
     "symbols"),
    ("symbols 'Xx'", lambda: ph.Body.from_atoms(["Xx"], [[0, 0, 0]]), ph.ArgumentError,
     "symbols"),
    ("symbols 'OHH'", lambda: ph.Body.from_atoms("OHH", np.zeros((3, 3))), TypeError, "symbols"),
    ("symbols None", lambda: ph.Body.from_atoms(None, [[0, 0, 0]]), TypeError, "symbols"),
    ("symbols [8.0]", lambda: ph.Body.from_atoms([8.0], [[0, 0, 0]]), TypeError, "symbols[0]"),
    ("symbols [True]", lambda: ph.Body.from_atoms([True], [[0, 0, 0]]), TypeError,
     "symbols[0]"),
    ("symbols []", lambda: ph.Body.from_atoms([], np.zeros((0, 3))), ph.ShapeError, "symbols"),
    ("masses 'heavy'", lambda: ph.Body.from_atoms(["O"], [[0, 0, 0]], masses="heavy"),
     ph.ArgumentError, "masses"),
    ("masses None", lambda: ph.Body.from_atoms(["O"], [[0, 0, 0]], masses=None), TypeError,
     "masses"),
    ("masses [-1]", lambda: ph.Body.from_atoms(["O"], [[0, 0, 0]], masses=[-1.0]),
     ph.NonPositiveError, "masses"),
    ("masses (2,) for one atom", lambda: ph.Body.from_atoms(["O"], [[0, 0, 0]], masses=[1, 2]),
     ph.ShapeError, "masses"),
    ("masses masked", lambda: ph.Body.from_atoms(["O", "H"], np.eye(2, 3),
                                                 masses=masked([16, 1], [0, 1])),
     ph.ArgumentError, "masses"),
    ("Tc average", lambda: ph.Body.from_atoms(["Tc"], [[0, 0, 0]], masses="average"),
     ph.ArgumentError, "symbols"),
    ("Tc most abundant", lambda: ph.Body.from_atoms(["Tc"], [[0, 0, 0]]), ph.ArgumentError,
     "symbols"),
    ("positions nan", lambda: ph.Body.from_atoms(["O"], [[0, 0, NAN]]), ph.NonFiniteError,
     "positions"),
    ("positions (1, 2)", lambda: ph.Body.from_atoms(["O"], [[0, 0]]), ph.ShapeError, "positions"),
    ("positions of two for one", lambda: ph.Body.from_atoms(["O"], np.zeros((2, 3))),
     ph.ShapeError, "positions"),
    ("positions masked", lambda: ph.Body.from_atoms(["O"], masked([[0, 0, 1]], [[0, 0, 1]])),
     ph.ArgumentError, "positions"),
):
    err(area, f"from_atoms {_label}", _call, _error, _argument)


def _molecule_files():
    """Files written by ASE (once): three frames of ethanol in one XYZ, one water, an empty
    file and one that is no molecule."""
    folder = f"{_TMP.name}/molecules"
    import os

    if not os.path.isdir(folder):
        import ase.build
        import ase.io

        os.makedirs(folder)
        base = ase.build.molecule("CH3CH2OH")
        frames = []
        for k in range(3):
            atoms = base.copy()
            atoms.positions = atoms.positions * (1.0 + 0.2 * k)
            frames.append(atoms)
        ase.io.write(f"{folder}/frames.xyz", frames)
        ase.io.write(f"{folder}/water.xyz", ase.build.molecule("H2O"))
        with open(f"{folder}/empty.xyz", "w"):
            pass
        with open(f"{folder}/garbage.xyz", "w") as handle:
            handle.write("this is not\nan xyz file\n")
    return folder


def from_file(name, **kwargs):
    return lambda: ph.Body.from_molecule(f"{_molecule_files()}/{name}", **kwargs)


def _frame_inertia(k):
    """numpy's inertia of frame k as ASE reads it back (AME masses of C, H, O)."""
    import ase.io

    atoms = ase.io.read(f"{_molecule_files()}/frames.xyz", index=k)
    m = np.array([_AME[{"C": "12C", "H": "1H", "O": "16O"}[s]]
                  for s in atoms.get_chemical_symbols()])
    r = atoms.get_positions()
    r = r - m @ r / m.sum()
    return sum(mk * (rk @ rk * np.eye(3) - np.outer(rk, rk)) for mk, rk in zip(m, r, strict=True))


for _k in (0, 1, 2):
    val(area, f"from_molecule conformer={_k} of a 3-frame XYZ",
        from_file("frames.xyz", conformer=_k),
        lambda b, k=_k: close(b.inertia, _frame_inertia(k), 1e-10),
        "numpy on ASE's frame k (masses to 1e-12)")
val(area, "from_molecule default conformer is the first", from_file("frames.xyz"),
    lambda b: close(b.inertia, _frame_inertia(0), 1e-10), "numpy on ASE's frame 0")
for _label, _call, _error, _argument in (
    ("conformer 3 of 3 frames", from_file("frames.xyz", conformer=3), ph.ArgumentError,
     "conformer"),
    ("conformer -2", from_file("frames.xyz", conformer=-2), ph.ArgumentError, "conformer"),
    ("conformer 1 of one structure", from_file("water.xyz", conformer=1), ph.ArgumentError,
     "conformer"),
    ("conformer 'a'", from_file("frames.xyz", conformer="a"), TypeError, "conformer"),
    ("conformer 1.0", from_file("frames.xyz", conformer=1.0), TypeError, "conformer"),
    ("conformer of an ASE Atoms", lambda: ph.Body.from_molecule(
        __import__("ase.build").build.molecule("H2O"), conformer=1), ph.ArgumentError,
     "conformer"),
    ("format 3", from_file("water.xyz", format=3), TypeError, "format"),
    ("format 'nonsense'", from_file("water.xyz", format="nonsense"), ph.ArgumentError, "format"),
    ("format with an ASE Atoms", lambda: ph.Body.from_molecule(
        __import__("ase.build").build.molecule("H2O"), format="xyz"), ph.ArgumentError,
     "format"),
    ("an empty file", from_file("empty.xyz"), ph.FileFormatError, "molecule"),
    ("a garbage file", from_file("garbage.xyz"), ph.FileFormatError, "molecule"),
    ("a folder", lambda: ph.Body.from_molecule(_molecule_files()), ph.FileFormatError,
     "molecule"),
    ("molecule 3", lambda: ph.Body.from_molecule(3), TypeError, "molecule"),
    ("molecule bytes", lambda: ph.Body.from_molecule(b"water.xyz"), TypeError, "molecule"),
):
    err(area, f"from_molecule {_label}", _call, _error, _argument)
err(area, "from_molecule a missing file", from_file("missing.xyz"), FileNotFoundError, "molecule")

# --- files: polhode.io and Body.from_file with every kind of argument ---------------------------

area = "io"
import pathlib  # noqa: E402

from polhode import io as PIO  # noqa: E402


def _io_files():
    """Small files (once): a tetrahedron as OFF (and as .txt), an empty STL, a one-link URDF
    with a turned inertial, an MJCF body, broken XML, a folder named like a mesh."""
    import os

    folder = f"{_TMP.name}/io"
    if os.path.isdir(folder):
        return folder
    os.makedirs(f"{folder}/folder.stl")
    off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
    files = {
        "tet.off": off,
        "tet.txt": off,
        "inside_out.off": off.replace("3 0 2 1", "3 0 1 2").replace("3 0 1 3", "3 0 3 1")
        .replace("3 0 3 2", "3 0 2 3").replace("3 1 2 3", "3 1 3 2"),
        "empty.stl": "",
        "garbage.stl": "solid nothing\nthis is not an stl\n",
        "link.urdf": '<robot name="r"><link name="a"><inertial><origin xyz="0.1 0.2 0.3" '
        'rpy="0.3 -0.2 0.5"/><mass value="2"/><inertia ixx="1" ixy="0" ixz="0" iyy="2" '
        'iyz="0" izz="2.5"/></inertial></link></robot>',
        "body.xml": '<mujoco><worldbody><body name="b"><inertial pos="0.1 0 0" '
        'quat="0.9238795325112867 0 0 0.3826834323650898" mass="3" diaginertia="1 2 2.5"/>'
        "</body></worldbody></mujoco>",
        "broken.urdf": "<robot",
    }
    for name, text in files.items():
        with open(f"{folder}/{name}", "w") as handle:
            handle.write(text)
    return folder


def at(name):
    return f"{_io_files()}/{name}"


def tetrahedron_exact(vertices, mass):
    """A uniform tetrahedron's centre and inertia about it, in rationals (Tonon 2004: the
    second moment about the origin is M/20 (sum v v^T + s s^T), s = sum v)."""
    v = [[Fraction(float(x)) for x in row] for row in vertices]
    s = [sum(row[i] for row in v) for i in range(3)]
    m = Fraction(float(mass))
    c = [[m / 20 * (sum(row[i] * row[j] for row in v) + s[i] * s[j]) for j in range(3)]
         for i in range(3)]
    com = [x / 4 for x in s]
    c = [[c[i][j] - m * com[i] * com[j] for j in range(3)] for i in range(3)]
    trace = c[0][0] + c[1][1] + c[2][2]
    inertia = [[(trace if i == j else 0) - c[i][j] for j in range(3)] for i in range(3)]
    return np.array([float(x) for x in com]), np.array([[float(x) for x in r] for r in inertia])


def mesh_file_check(vertices, mass, rtol=16 * EPS):
    com, inertia = tetrahedron_exact(vertices, mass)

    def check(result):
        body = result if isinstance(result, ph.Body) else sum(result.values(), 0)
        close(body.mass, mass, rtol, what="mass")
        close(body.center_of_mass, com, rtol, what="center_of_mass")
        close(body.inertia, inertia, rtol, what="inertia")

    return check


_TET = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
val(area, "read_mesh a str path", lambda: PIO.read_mesh(at("tet.off"), mass=1.0),
    mesh_file_check(_TET, 1.0), "Tonon's closed form in rationals")
val(area, "read_mesh a pathlib.Path", lambda: PIO.read_mesh(pathlib.Path(at("tet.off")),
                                                            density=6.0),
    mesh_file_check(_TET, 1.0), "volume 1/6 at density 6: mass 1")
val(area, "read_mesh scale 2", lambda: PIO.read_mesh(at("tet.off"), mass=1.0, scale=2.0),
    mesh_file_check(np.multiply(_TET, 2.0), 1.0), "Tonon, the vertices doubled")
val(area, "read_mesh scale (1, 2, 3)", lambda: PIO.read_mesh(at("tet.off"), mass=1.0,
                                                             scale=(1, 2, 3)),
    mesh_file_check(np.multiply(_TET, [1, 2, 3]), 1.0), "Tonon, each axis scaled")
val(area, "read_mesh scale -1 mirrors", lambda: PIO.read_mesh(at("tet.off"), mass=1.0, scale=-1),
    mesh_file_check(np.multiply(_TET, -1.0), 1.0), "Tonon of the mirrored tetrahedron")
val(area, "read_mesh fix_winding of an inside-out file",
    lambda: PIO.read_mesh(at("inside_out.off"), mass=1.0, fix_winding=True),
    mesh_file_check(_TET, 1.0), "Tonon's closed form")
val(area, "read_mesh shell", lambda: PIO.read_mesh(at("tet.off"), mass=1.0, shell=True),
    lambda r: close(r["tet.off"].mass, 1.0, 0.0), "the mass given")
val(area, "from_file density 6", lambda: ph.Body.from_file(pathlib.Path(at("tet.off")),
                                                           density=6.0),
    mesh_file_check(_TET, 1.0), "Tonon's closed form")
for _label, _call, _error, _argument in (
    ("read_mesh path bytes", lambda: PIO.read_mesh(at("tet.off").encode(), mass=1.0), TypeError,
     "path"),
    ("read_mesh path None", lambda: PIO.read_mesh(None, mass=1.0), TypeError, "path"),
    ("read_mesh path 3", lambda: PIO.read_mesh(3, mass=1.0), TypeError, "path"),
    ("read_mesh a folder", lambda: PIO.read_mesh(at("folder.stl"), mass=1.0),
     ph.FileFormatError, "path"),
    ("read_mesh .txt", lambda: PIO.read_mesh(at("tet.txt"), mass=1.0), ph.FileFormatError,
     "path"),
    ("read_mesh an empty STL", lambda: PIO.read_mesh(at("empty.stl"), mass=1.0),
     ph.FileFormatError, "path"),
    ("read_mesh a garbage STL", lambda: PIO.read_mesh(at("garbage.stl"), mass=1.0),
     ph.FileFormatError, "path"),
    ("read_mesh inside out", lambda: PIO.read_mesh(at("inside_out.off"), mass=1.0),
     ph.FileFormatError, "path"),
    ("read_mesh density and mass", lambda: PIO.read_mesh(at("tet.off"), mass=1.0, density=1.0),
     ph.ArgumentError, "mass"),
    ("read_mesh neither", lambda: PIO.read_mesh(at("tet.off")), ph.ArgumentError, "density"),
    ("read_mesh mass '1'", lambda: PIO.read_mesh(at("tet.off"), mass="1"), TypeError, "mass"),
    ("read_mesh mass nan", lambda: PIO.read_mesh(at("tet.off"), mass=NAN), ph.NonFiniteError,
     "mass"),
    ("read_mesh mass 2**2000", lambda: PIO.read_mesh(at("tet.off"), mass=BIG),
     ph.NonFiniteError, "mass"),
    ("read_mesh density -1", lambda: PIO.read_mesh(at("tet.off"), density=-1),
     ph.NonPositiveError, "density"),
    ("read_mesh scale 0", lambda: PIO.read_mesh(at("tet.off"), mass=1, scale=0),
     ph.ArgumentError, "scale"),
    ("read_mesh scale (2,)", lambda: PIO.read_mesh(at("tet.off"), mass=1, scale=[1, 2]),
     ph.ShapeError, "scale"),
    ("read_mesh scale '2'", lambda: PIO.read_mesh(at("tet.off"), mass=1, scale="2"), TypeError,
     "scale"),
    ("read_mesh scale inf", lambda: PIO.read_mesh(at("tet.off"), mass=1, scale=INF),
     ph.NonFiniteError, "scale"),
    ("read_mesh scale masked", lambda: PIO.read_mesh(at("tet.off"), mass=1, scale=masked(
        [1, 2, 3], [0, 1, 0])), ph.ArgumentError, "scale"),
    ("read_mesh shell 'yes'", lambda: PIO.read_mesh(at("tet.off"), mass=1, shell="yes"),
     TypeError, "shell"),
    ("read_mesh fix_winding 1", lambda: PIO.read_mesh(at("tet.off"), mass=1, fix_winding=1),
     TypeError, "fix_winding"),
    ("from_file a folder", lambda: ph.Body.from_file(at("folder.stl"), mass=1.0),
     ph.FileFormatError, "path"),
    ("from_file scale nan", lambda: ph.Body.from_file(at("tet.off"), mass=1.0, scale=NAN),
     ph.NonFiniteError, "scale"),
    ("from_file neither", lambda: ph.Body.from_file(at("tet.off")), ph.ArgumentError,
     "density"),
    # A scale whose mesh is beyond double precision, where the file's own is not, is the
    # scale's fault (it was a FileFormatError naming the file).
    ("from_file scale 1e200, mass", lambda: ph.Body.from_file(at("tet.off"), mass=1.0,
                                                             scale=1e200), ph.ArgumentError,
     "scale"),
    ("from_file scale 1e200, density", lambda: ph.Body.from_file(at("tet.off"), density=1.0,
                                                                scale=1e200), ph.ArgumentError,
     "scale"),
    ("from_file scale 1e-200, density (the mass underflows)",
     lambda: ph.Body.from_file(at("tet.off"), density=1.0, scale=1e-200), ph.ArgumentError,
     "scale"),
    ("read_mesh scale 1e200", lambda: PIO.read_mesh(at("tet.off"), mass=1.0, scale=1e200),
     ph.ArgumentError, "scale"),
    ("read_mesh scale (1e200, 1, 1) (flat to rounding)",
     lambda: PIO.read_mesh(at("tet.off"), mass=1.0, scale=(1e200, 1, 1)), ph.ArgumentError,
     "scale"),
    ("read_mesh scale 1e308, density", lambda: PIO.read_mesh(at("tet.off"), density=1.0,
                                                             scale=1e308), ph.ArgumentError,
     "scale"),
):
    err(area, _label, _call, _error, _argument)
val(area, "from_file scale 1e100, mass 1", lambda: ph.Body.from_file(at("tet.off"), mass=1.0,
                                                                     scale=1e100),
    mesh_file_check(np.multiply(_TET, 1e100), 1.0), "Tonon, the vertices times 1e100")
err(area, "read_mesh a missing file", lambda: PIO.read_mesh(at("missing.off"), mass=1.0),
    FileNotFoundError, None, fragment="missing.off")
err(area, "from_file a missing file", lambda: ph.Body.from_file(at("missing.stl"), mass=1.0),
    FileNotFoundError, None, fragment="missing.stl")


def _turned(rotation, moments, mass, com):
    r = rotation.as_matrix()

    def check(bodies):
        (body,) = bodies.values()
        close(body.mass, mass, 0.0, what="mass")
        close(body.center_of_mass, com, EPS, what="center_of_mass")
        close(body.inertia, r @ np.diag(moments) @ r.T, 8 * EPS, what="inertia")

    return check


val(area, "read_urdf a turned inertial", lambda: PIO.read_urdf(at("link.urdf")),
    _turned(Rotation.from_euler("xyz", [0.3, -0.2, 0.5]), [1.0, 2.0, 2.5], 2.0, [0.1, 0.2, 0.3]),
    "R diag R^T, R = Rz(yaw) Ry(pitch) Rx(roll) (scipy)")
val(area, "read_urdf a pathlib.Path", lambda: PIO.read_urdf(pathlib.Path(at("link.urdf"))),
    _turned(Rotation.from_euler("xyz", [0.3, -0.2, 0.5]), [1.0, 2.0, 2.5], 2.0, [0.1, 0.2, 0.3]),
    "R diag R^T (scipy)")
val(area, "read_mjcf a turned diaginertia", lambda: PIO.read_mjcf(pathlib.Path(at("body.xml"))),
    _turned(Rotation.from_quat([0, 0, 0.3826834323650898, 0.9238795325112867]), [1.0, 2.0, 2.5],
            3.0, [0.1, 0.0, 0.0]), "R diag R^T, quat w x y z (scipy)")
val(area, "audit of a consistent link", lambda: PIO.audit(at("link.urdf")),
    lambda findings: assert_true([f.severity for f in findings] == ["ok"], findings),
    "a physical inertial without geometry")
for _label, _call, _error, _argument in (
    ("read_urdf path None", lambda: PIO.read_urdf(None), TypeError, "path"),
    ("read_urdf path bytes", lambda: PIO.read_urdf(at("link.urdf").encode()), TypeError, "path"),
    ("read_urdf a folder", lambda: PIO.read_urdf(_io_files()), ph.FileFormatError, "path"),
    ("read_urdf broken XML", lambda: PIO.read_urdf(at("broken.urdf")), ph.FileFormatError,
     "path"),
    ("read_urdf a mesh file", lambda: PIO.read_urdf(at("tet.off")), ph.FileFormatError, "path"),
    ("read_urdf geometry 'both'", lambda: PIO.read_urdf(at("link.urdf"), geometry="both"),
     ph.ArgumentError, "geometry"),
    ("read_urdf density and mass", lambda: PIO.read_urdf(at("link.urdf"), density=1, mass=1),
     ph.ArgumentError, "mass"),
    ("read_urdf density '1'", lambda: PIO.read_urdf(at("link.urdf"), density="1"), TypeError,
     "density"),
    ("read_urdf mass 0", lambda: PIO.read_urdf(at("link.urdf"), mass=0.0), ph.NonPositiveError,
     "mass"),
    ("read_mjcf path None", lambda: PIO.read_mjcf(None), TypeError, "path"),
    ("read_mjcf a folder", lambda: PIO.read_mjcf(_io_files()), ph.FileFormatError, "path"),
    ("read_mjcf broken XML", lambda: PIO.read_mjcf(at("broken.urdf")), ph.FileFormatError,
     "path"),
    ("read_mjcf density and mass", lambda: PIO.read_mjcf(at("body.xml"), density=1, mass=1,
                                                         as_written=True),
     ph.ArgumentError, "mass"),
    ("read_mjcf mass 0", lambda: PIO.read_mjcf(at("body.xml"), mass=0, as_written=True),
     ph.NonPositiveError, "mass"),
    ("read_mjcf density nan", lambda: PIO.read_mjcf(at("body.xml"), density=NAN,
                                                    as_written=True),
     ph.NonFiniteError, "density"),
    ("read_mjcf density as MuJoCo compiles", lambda: PIO.read_mjcf(at("body.xml"), density=1),
     ph.ArgumentError, "density"),
    ("audit rtol -1", lambda: PIO.audit(at("link.urdf"), rtol=-1), ph.ArgumentError, "rtol"),
    ("audit rtol 'x'", lambda: PIO.audit(at("link.urdf"), rtol="x"), TypeError, "rtol"),
    ("audit geometry 'x'", lambda: PIO.audit(at("link.urdf"), geometry="x"), ph.ArgumentError,
     "geometry"),
    ("audit a mesh file", lambda: PIO.audit(at("tet.off")), ph.FileFormatError, "path"),
    ("audit density 0", lambda: PIO.audit(at("link.urdf"), density=0), ph.NonPositiveError,
     "density"),
    ("audit path None", lambda: PIO.audit(None), TypeError, "path"),
):
    err(area, _label, _call, _error, _argument)
for _label, _call, _name in (
    ("read_urdf a missing file", lambda: PIO.read_urdf(at("missing.urdf")), "missing.urdf"),
    ("read_mjcf a missing file", lambda: PIO.read_mjcf(at("missing.xml")), "missing.xml"),
    ("audit a missing file", lambda: PIO.audit(at("missing.urdf")), "missing.urdf"),
):
    err(area, _label, _call, FileNotFoundError, None, fragment=_name)


# ---------------------------------------------------------------------------------------------
# Running the table
# ---------------------------------------------------------------------------------------------


def _params():
    for row in CATALOGUE:
        marks = [pytest.mark.xfail(strict=True, reason=row.xfail)] if row.xfail else []
        yield pytest.param(row, id=row.id, marks=marks)


@pytest.mark.parametrize("row", list(_params()))
def test_row(row: Row):
    expect = row.expect
    if isinstance(expect, Raises):
        with pytest.raises(BaseException) as info:  # noqa: PT011, B017 - checked below
            row.call()
        error = info.value
        assert type(error) is expect.error, (
            f"expected {expect.error.__name__}, got {type(error).__name__}: {error}"
        )
        message = str(error)
        if issubclass(expect.error, ph.PolhodeError):
            assert error.argument == expect.argument, (error.argument, message)
            assert error.body == expect.body, (error.body, message)
        elif expect.argument is not None:
            assert f"`{expect.argument}`" in message, message
        if expect.fragment is not None:
            assert expect.fragment in message, message
        assert "Traceback" not in message and len(message) < 600, message
    elif isinstance(expect, Value):
        result = row.call()
        finite_everywhere(result)
        expect.check(result)
    else:
        code, out, errors = row.call()
        assert code == expect.code, (code, out, errors)
        assert "Traceback" not in errors, errors
        if expect.code == 2:
            lines = [x for x in errors.splitlines() if x.strip()]
            assert "error" in lines[-1] and expect.option in lines[-1], errors
            assert out == "", out
        if expect.check is not None:
            expect.check(out, errors)


def test_the_table():
    """At least 300 rows, unique ids, every area, every PolhodeError naming its argument; the
    totals by area and by kind are printed (pytest -s, or -rA)."""
    ids = [row.id for row in CATALOGUE]
    duplicates = [i for i, n in collections.Counter(ids).items() if n > 1]
    assert not duplicates, duplicates
    assert len(CATALOGUE) >= 300, len(CATALOGUE)
    for row in CATALOGUE:
        if isinstance(row.expect, Raises) and issubclass(row.expect.error, ph.PolhodeError):
            assert row.expect.argument is not None, row.id
    areas = collections.Counter(row.area.split("/")[0] for row in CATALOGUE)
    for area_name in ("constructors", "body", "principal", "simulate", "analyze", "perturbation",
                      "torque", "mesh", "dask", "cli"):
        assert areas[area_name] > 0, area_name
    for method in SETTINGS:
        assert any(row.area == f"simulate/{method}" for row in CATALOGUE), method
    print(totals())


def totals() -> str:
    by_area: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for row in CATALOGUE:
        by_area[row.area][row.kind] += 1
        if row.xfail:
            by_area[row.area]["xfail"] += 1
    lines = [f"{'area':24s} {'rows':>5s} {'errors':>7s} {'values':>7s} {'xfail':>6s}"]
    total: collections.Counter = collections.Counter()
    for name, count in by_area.items():
        rows = count["error"] + count["value"]
        total.update(count)
        lines.append(f"{name:24s} {rows:5d} {count['error']:7d} {count['value']:7d} "
                     f"{count['xfail']:6d}")
    lines.append(f"{'total':24s} {total['error'] + total['value']:5d} {total['error']:7d} "
                 f"{total['value']:7d} {total['xfail']:6d}")
    return "\n".join(lines)


if __name__ == "__main__":
    print(totals())
