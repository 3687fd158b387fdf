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
        lambda sol, b=BOUND[method]: (close(sol.t, [0.0, 2.0], 0.0),
                                      close(sol.omega, scipy_motion(M123, W, [0.0, 2.0])[0], b)),
        "scipy at t0 and 2")
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


def csv_rows(path):
    return np.loadtxt(path.format(tmp=_TMP.name), delimiter=",", skiprows=1, ndmin=2)


def csv_check(path, omega_q_ref, bound):
    def check(stdout, stderr):
        rows = csv_rows(path)
        w_ref, q_ref = omega_q_ref(rows[:, 0])
        close(rows[:, 1:4], w_ref, bound, what="omega")
        same_rotation(rows[:, 4:8], q_ref, max(bound, 64 * EPS))

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
       lambda out, errors: close(csv_rows("{tmp}/top.csv")[:, 1:4],
                                 symmetric_omega((2, 3, 2), [0.3, 1.0, -0.4],
                                                 csv_rows("{tmp}/top.csv")[:, 0]), 256 * EPS))
cli_ok("--body cylinder", ["spin", "--body", "cylinder", "mass=1", "radius=0.1", "length=0.5",
                           *OMEGA, "--t", "1", "--points", "3"],
       lambda out, errors: close(printed("principal moments", out),
                                 np.sort(np.diag(ref.cylinder(1.0, 0.1, 0.5).inertia)), 1e-4))
cli_ok("rk4 at 1e-3", [*SPIN, *OMEGA, "--t", "2", "--points", "5", "--method", "rk4", "--dt",
                       "1e-3", "--csv", "{tmp}/rk4.csv"],
       lambda out, errors: close(csv_rows("{tmp}/rk4.csv")[:, 1:4],
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
