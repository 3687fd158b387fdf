"""Mass properties and principal axes at the edges of double precision, under any number of
threads, and in the engine formats: the right answer or a typed error naming the argument,
never NaN, inf or a plausible wrong value (Ctrl-C: tests/test_interrupt.py).

References: mpmath eigenvalues of the float tensor taken as exact (its exponents are unbounded),
closed forms scaled by exact powers of two, exact rational point-mass sums (tests/reference.py).
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest

import polhode as ph
import reference as ref
from conftest import assert_close_normwise, check_eigen
from reference import EPS

MAX = sys.float_info.max
SMALLEST = math.ldexp(1.0, -1074)  # the smallest subnormal, the spacing of all subnormals


def spd(seed: int, moments=(1.0, 2.0, 3.5)) -> np.ndarray:
    """A random symmetric positive definite tensor with the given eigenvalues (before rounding)."""
    r = ref.random_rotation(np.random.default_rng(seed))
    a = r @ np.diag(moments) @ r.T
    return (a + a.T) / 2


def spectral_norm_mp(values) -> mpmath.mpf:
    """||A||_2 of a symmetric tensor from its exact eigenvalues."""
    return max(abs(v) for v in values)


def normalised(a: np.ndarray, moments: np.ndarray):
    """The tensor and its moments times the same power of two (exact), largest entry in [0.5, 1):
    the backward-error checks of conftest then run in numbers numpy can square."""
    e = math.frexp(float(np.max(np.abs(a))))[1]
    return np.ldexp(a, -e), np.ldexp(moments, -e)


def axis_rotation(axis: str, angle: float) -> np.ndarray:
    """The rotation by `angle` about the coordinate axis `axis` ("x", "y" or "z")."""
    c, s = math.cos(angle), math.sin(angle)
    i = "xyz".index(axis)
    j, k = (i + 1) % 3, (i + 2) % 3
    r = np.eye(3)
    r[j, j], r[j, k], r[k, j], r[k, k] = c, -s, s, c
    return r


def assert_names(error: pytest.ExceptionInfo, argument: str, *words: str) -> None:
    assert error.value.argument == argument, (error.value.argument, str(error.value))
    message = str(error.value)
    for word in words:
        assert word in message, message


# ---------------------------------------------------------------------------------------------
# 1. principal() at every scale of double precision
# ---------------------------------------------------------------------------------------------

SCALES = [-300, -250, -200, -154, -100, -30, 0, 30, 100, 154, 200, 250, 300, 307]


@pytest.mark.parametrize("exponent", SCALES)
def test_principal_is_backward_stable_at_every_scale(exponent):
    # The tensor as rounded is the exact input of the reference. Moments within 10 eps ||A|| of
    # its exact eigenvalues (Weyl: an eigenvalue moves at most the backward error, which the
    # project bounds by 10 eps ||A||), all three distinct (the gaps are ~||A||, far above any
    # merging tolerance), and the residual bounds of conftest.check_eigen on the same tensor
    # times a power of two. Before scaling, 1e154 and above overflowed the Frobenius norm behind
    # the merging tolerance and merged all three moments.
    a = spd(exponent + 1000) * 10.0**exponent
    p = ph.principal(a)
    exact = ref.eigvalsh_mp(a)
    bound = 10 * EPS * spectral_norm_mp(exact)
    for k in range(3):
        assert abs(mpmath.mpf(float(p.moments[k])) - exact[k]) <= bound, (k, p.moments, exact)
    np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])
    scaled, moments = normalised(a, p.moments)
    check_eigen(scaled, moments, p.axes, what=f"1e{exponent}")


@pytest.mark.parametrize("scale", [1e-310, 1e-315, math.ldexp(1.0, -1060)])
def test_principal_of_a_subnormal_tensor_is_finite_and_right(scale):
    # Entries below the smallest normal double (2.2e-308) carry few digits; the reference takes
    # the rounded tensor as exact. The solve runs on the tensor scaled up by a power of two
    # (exact), within 10 eps ||A||; writing each moment back as a subnormal rounds it to a
    # multiple of 2^-1074, at most two such steps (the power of two is applied in two halves).
    # Before: NaN (the reciprocal of the largest entry overflowed).
    a = spd(7) * scale
    assert np.max(np.abs(a)) < sys.float_info.min
    p = ph.principal(a)
    assert np.all(np.isfinite(p.moments)) and np.all(np.isfinite(p.axes))
    values, vectors = ref.eigh_mp(a)
    bound = 10 * EPS * spectral_norm_mp(values) + 2 * SMALLEST
    for k in range(3):
        assert abs(mpmath.mpf(float(p.moments[k])) - values[k]) <= bound, (k, p.moments, values)
    np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])
    # Axes: each within 10 eps ||A|| / gap of the exact eigenvector (the gaps are ~||A||).
    for k in range(3):
        gap = min(abs(values[k] - values[j]) for j in range(3) if j != k)
        angle = ref.axis_angle(p.axes[:, k], vectors[:, k])
        assert angle <= float(10 * EPS * spectral_norm_mp(values) / gap), (k, angle)


@pytest.mark.parametrize("exponent", [-300, -154, 0, 154, 300, 307])
def test_multiplicities_hold_at_every_scale(exponent):
    # A symmetric top, a sphere and an asymmetric body at the same scale, one by one and as a
    # batch: the multiplicity is a property of the shape, not of the units.
    s = 10.0**exponent
    r = ref.random_rotation(np.random.default_rng(exponent + 5000))
    top = (r @ np.diag([1.0, 1.0, 2.0]) @ r.T) * s
    sphere = np.eye(3) * (1.5 * s)
    asymmetric = spd(exponent + 6000) * s
    expected = {"top": [2, 2, 1], "sphere": [3, 3, 3], "asymmetric": [1, 1, 1]}
    tensors = {"top": top, "sphere": sphere, "asymmetric": asymmetric}
    batch = ph.principal(np.stack(list(tensors.values())))
    for i, (name, tensor) in enumerate(tensors.items()):
        p = ph.principal(tensor)
        np.testing.assert_array_equal(p.multiplicity, expected[name], err_msg=name)
        np.testing.assert_array_equal(batch.multiplicity[i], expected[name], err_msg=name)
        np.testing.assert_array_equal(batch.moments[i], p.moments, err_msg=name)
        scaled, moments = normalised(tensor, p.moments)
        check_eigen(scaled, moments, p.axes, what=f"{name} 1e{exponent}")
    moments = ph.principal(sphere).moments
    assert moments[0] == moments[1] == moments[2]
    assert moments[0] == pytest.approx(1.5 * s, rel=10 * EPS)
    moments = ph.principal(top).moments
    assert moments[0] == moments[1]


def test_principal_up_to_the_largest_double_and_beyond():
    # [[a, b, 0], [b, a, 0], [0, 0, c]] has eigenvalues a - b, a + b, c. With a + b = 1.65e308
    # every moment is a double (right to 10 eps ||A|| as above); with 1.9e308 the largest is
    # not, and the error says so, naming `inertia` (and, in a batch, the first such tensor as
    # its `body`).
    # Before: the trace overflowed and the moments came out NaN.
    fits = np.array([[0.85e308, 0.8e308, 0.0], [0.8e308, 0.85e308, 0.0], [0.0, 0.0, 1.0e308]])
    p = ph.principal(fits)
    exact = ref.eigvalsh_mp(fits)
    bound = 10 * EPS * spectral_norm_mp(exact)
    for k in range(3):
        assert abs(mpmath.mpf(float(p.moments[k])) - exact[k]) <= bound
    beyond = np.array([[1e308, 0.9e308, 0.0], [0.9e308, 1e308, 0.0], [0.0, 0.0, 1e308]])
    with pytest.raises(ph.ArgumentError) as error:
        ph.principal(beyond)
    assert_names(error, "inertia", "overflow", "double precision", "1.9e+308")
    with pytest.raises(ph.ArgumentError) as error:
        ph.principal(np.stack([fits, beyond, fits, beyond]))
    assert_names(error, "inertia", "body 1: ", "overflow")
    assert error.value.body == 1


@pytest.mark.parametrize("exponent", [-300, -200, -100, 0, 100, 200, 300, 307])
def test_body_principal_at_every_scale(exponent):
    # Body.from_inertia goes through the eigensolve (10 eps ||I||), the principal second
    # moments c = tr(I)/2 - I (2 roundings of ||I||) and their square roots; principal() then
    # squares the factor's singular values and adds (3 more): 16 eps ||I|| covers it. The
    # inertia read back is within the round-trip bound of test_bodies (8 eps).
    i = spd(exponent + 7000, moments=(1.0, 2.0, 2.5)) * 10.0**exponent
    body = ph.Body.from_inertia(1.0, i)
    p = body.principal()
    exact = ref.eigvalsh_mp(i)
    bound = 16 * EPS * spectral_norm_mp(exact)
    for k in range(3):
        assert abs(mpmath.mpf(float(p.moments[k])) - exact[k]) <= bound, (k, p.moments, exact)
    np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])
    assert_close_normwise(body.inertia, i, 8 * EPS, what="inertia")
    scaled, moments = normalised(i, p.moments)
    check_eigen(scaled, moments, p.axes, residual_eps=16.0, what=f"1e{exponent}")


@pytest.mark.parametrize(
    ("mass", "length"),
    [
        # Moments just under the largest double, where the sum of the factor's squared singular
        # values (behind the merging tolerance) exceeded it: the moments merged into one.
        (1.0, 1.9 * 2.0**510),
        # Tiny masses at tiny lengths: moments ~2^-900, squares far below 2^-1022 on the way.
        (2.0**-600, 1.9 * 2.0**-150),
        (1e200, 1e53),
    ],
)
def test_point_cloud_principal_at_the_edges_keeps_its_symmetry(mass, length):
    # Six equal masses at +-a x, +-a y, +-0.75 a z: a symmetric top, I1 = I2 = 3.125 m a^2,
    # I3 = 4 m a^2, against the exact rational reference; 16 eps ||I|| as for the tensor path.
    a = length
    positions = np.array(
        [[a, 0, 0], [-a, 0, 0], [0, a, 0], [0, -a, 0], [0, 0, 0.75 * a], [0, 0, -0.75 * a]]
    )
    masses = np.full(6, mass)
    body = ph.Body.point_masses(masses, positions)
    p = body.principal()
    expected, _ = ref.principal_cloud_mp(masses, positions)
    np.testing.assert_allclose(p.moments, expected, rtol=0, atol=16 * EPS * max(expected))
    np.testing.assert_array_equal(p.multiplicity, [2, 2, 1])
    assert np.all(np.isfinite(body.inertia))


# ---------------------------------------------------------------------------------------------
# 2. from_inertia up to the largest double
# ---------------------------------------------------------------------------------------------


def test_from_inertia_of_8e307_is_represented():
    # Before: the trace overflowed and the body came out with a zero tensor. Within the
    # round-trip bound of test_bodies (8 eps), as for a tensor of 1.
    body = ph.Body.from_inertia(1.0, np.eye(3) * 8e307)
    assert_close_normwise(body.inertia, np.eye(3) * 8e307, 8 * EPS)
    assert_close_normwise(body.second_moment, np.eye(3) * 4e307, 8 * EPS)
    p = body.principal()
    np.testing.assert_allclose(p.moments, [8e307] * 3, rtol=8 * EPS)
    np.testing.assert_array_equal(p.multiplicity, [3, 3, 3])


@pytest.mark.parametrize(
    "moments", [(MAX, MAX, MAX), (MAX / 2, MAX / 2, MAX), (0.5 * MAX, 0.8 * MAX, 0.9 * MAX)]
)
def test_from_inertia_up_to_the_largest_double(moments):
    # The largest double itself, a planar body reaching it, and a rotated asymmetric one: read
    # back within the round-trip bound, moments within 16 eps ||I|| (as above).
    rotated = moments[0] != moments[2] and moments[0] != moments[1]
    r = ref.random_rotation(np.random.default_rng(11)) if rotated else np.eye(3)
    i = r @ np.diag(moments) @ r.T
    i = 0.5 * i + 0.5 * i.T  # (i + i.T) / 2 would overflow
    body = ph.Body.from_inertia(2.0, i)
    assert_close_normwise(body.inertia, i, 8 * EPS, what="inertia")
    exact = ref.eigvalsh_mp(i)
    p = body.principal()
    for k in range(3):
        assert abs(mpmath.mpf(float(p.moments[k])) - exact[k]) <= 16 * EPS * max(exact)


def test_from_inertia_beyond_the_largest_double_raises():
    # A body with moments (1, 1, 1.9) e308 (I1 + I2 >= I3), turned 45 degrees about y:
    # [[1.45, 0, 0.45], [0, 1, 0], [0.45, 0, 1.45]] e308. Every entry is a double but its
    # largest moment is not.
    i = np.array([[1.45e308, 0.0, 0.45e308], [0.0, 1.0e308, 0.0], [0.45e308, 0.0, 1.45e308]])
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.from_inertia(1.0, i)
    assert_names(error, "inertia", "overflow", "double precision")


# ---------------------------------------------------------------------------------------------
# 3. Constructors and composites at the overflow boundary, on both sides
# ---------------------------------------------------------------------------------------------

# Lengths of 2 to 6, so that every largest moment at mass 1 is at least 2: the mass at the
# boundary, and twice it, are then doubles.
SOLIDS = [
    ("sphere", (3.0,), ("radius",)),
    ("spherical_shell", (3.0,), ("radius",)),
    ("cuboid", ((3.0, 4.0, 5.0),), ("size",)),
    ("cylinder", (3.0, 6.0), ("radius", "length")),
    ("tube", (2.0, 3.0, 6.0), ("inner_radius", "outer_radius", "length")),
    ("cone", (3.0, 6.0), ("radius", "length")),
    ("ellipsoid", ((3.0, 4.0, 5.0),), ("semi_axes",)),
    ("rod", (6.0,), ("length",)),
    ("disk", (3.0,), ("radius",)),
    ("torus", (3.0, 1.0), ("major_radius", "minor_radius")),
    ("capsule", (3.0, 6.0), ("radius", "length")),
]


def times_pow2(params, k: int):
    """Every length of `params` times 2^k (exact)."""
    return tuple(
        tuple(math.ldexp(x, k) for x in p) if isinstance(p, tuple) else math.ldexp(p, k)
        for p in params
    )


def largest_exponent(value: float, power: int) -> int:
    """The largest k with value 2^(power k) a double (exactly: value is one, and the power of
    two only moves its exponent)."""
    k = math.floor((1024 - math.log2(value)) / power) + 1
    while Fraction(value) * Fraction(2) ** (power * k) > Fraction(MAX):
        k -= 1
    return k


@pytest.mark.parametrize(("name", "params", "lengths"), SOLIDS, ids=[s[0] for s in SOLIDS])
def test_solid_at_the_largest_lengths(name, params, lengths):
    # The moments are m L^2 times the closed form: with lengths 2^k (exact) they are the closed
    # form at unit scale times 4^k. The largest k whose moments are doubles must give them (the
    # closed-form bound of test_bodies, 1e-14); one more must raise, naming a length. Before:
    # m r r overflowed on the way (the first) and inf came back silently (the second).
    closed = ref.SOLIDS[name](1.0, *params).inertia
    k = largest_exponent(float(np.max(closed)), 2)
    body = getattr(ph.Body, name)(1.0, *times_pow2(params, k))
    assert_close_normwise(body.inertia, np.ldexp(closed, 2 * k), 1e-14, what=name)
    assert np.all(np.isfinite(body.principal().moments))
    with pytest.raises(ph.ArgumentError) as error:
        getattr(ph.Body, name)(1.0, *times_pow2(params, k + 1))
    assert error.value.argument in lengths, str(error.value)
    assert "overflow" in str(error.value) and "double precision" in str(error.value)


@pytest.mark.parametrize(("name", "params", "lengths"), SOLIDS, ids=[s[0] for s in SOLIDS])
def test_solid_at_the_largest_masses(name, params, lengths):
    # The same boundary in the mass (moments linear in it): 2^j just fits, 2^(j+1) raises
    # naming `mass`.
    closed = ref.SOLIDS[name](1.0, *params).inertia
    j = largest_exponent(float(np.max(closed)), 1)
    body = getattr(ph.Body, name)(math.ldexp(1.0, j), *params)
    assert_close_normwise(body.inertia, np.ldexp(closed, j), 1e-14, what=name)
    with pytest.raises(ph.ArgumentError) as error:
        getattr(ph.Body, name)(math.ldexp(1.0, j + 1), *params)
    assert_names(error, "mass", "overflow")


@pytest.mark.parametrize(
    ("mass_exponent", "distance_exponent", "blamed"), [(0, 512, "positions"), (1000, 12, "masses")]
)
def test_two_point_masses_at_the_boundary(mass_exponent, distance_exponent, blamed):
    # Two masses m at distance d: I = (m/2) d^2 about the perpendicular axes, 0 about the line.
    # Here 2^1023 (the largest power of two that is a double); twice the distance overflows, and
    # the error names the argument that drives it. 4 eps as test_bodies' two point masses.
    m, d = math.ldexp(1.0, mass_exponent), math.ldexp(1.0, distance_exponent)
    body = ph.Body.point_masses([m, m], [[0.0, 0.0, 0.0], [d, 0.0, 0.0]])
    expected = np.diag([0.0, 2.0**1023, 2.0**1023])
    assert_close_normwise(body.inertia, expected, 4 * EPS)
    p = body.principal()
    top = 2.0**1023
    np.testing.assert_allclose(p.moments, [0.0, top, top], rtol=0, atol=4 * EPS * top)
    np.testing.assert_array_equal(p.multiplicity, [1, 2, 2])
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.point_masses([m, m], [[0.0, 0.0, 0.0], [2 * d, 0.0, 0.0]])
    assert_names(error, blamed, "overflow", "double precision")


def test_point_masses_whose_moments_overflow_raise_instead_of_vanishing():
    # Before: the first moment overflowed, NaN rows were skipped by the factorisation and the
    # body came back with a zero inertia tensor.
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.point_masses([1e300, 1e300], [[0.0, 0.0, 0.0], [1e10, 0.0, 0.0]])
    assert_names(error, "masses", "overflow")


BOX_FACES = np.array(
    [[0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6], [0, 1, 5], [0, 5, 4]]
    + [[2, 6, 7], [2, 7, 3], [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]]
)


def cube(side: float) -> np.ndarray:
    """The vertices of a cube of edge `side` centred on the origin (vertex k: bits x, y, z)."""
    k = np.arange(8)
    return (np.stack([(k >> b) & 1 for b in range(3)], axis=1) - 0.5) * side


@pytest.mark.parametrize(
    ("side", "density", "mass", "blamed"),
    [
        # rho L^5 / 6 with L = 2^205: 2^1025 / 6 fits; 2^206 does not.
        (2.0**205, 1.0, None, "vertices"),
        # rho 4^5 / 6 with rho = 2^1016 fits (the mass 64 rho too); 2^1017 does not.
        (4.0, 2.0**1016, None, "density"),
        # m L^2 / 6 with m = 1, L = 2^513 fits (2^1026 / 6); 2^514 does not.
        (2.0**513, None, 1.0, "vertices"),
    ],
)
def test_mesh_at_the_boundary(side, density, mass, blamed):
    # A cube: I = M L^2 / 6 about every axis through its centre, M = rho L^3. Before: the
    # integrals (~L^5) overflowed where the moments did not.
    faces = BOX_FACES
    body = ph.Body.mesh(cube(side), faces, density=density, mass=mass)
    total = mass if mass is not None else density * side**3
    expected = total * (side / 6 * side)
    assert math.isfinite(expected)
    assert_close_normwise(body.inertia, np.eye(3) * expected, 1e-14)
    assert body.mass == pytest.approx(total, rel=4 * EPS)
    if blamed == "density":
        bigger = {"vertices": cube(side), "density": 2 * density}
    else:
        bigger = {"vertices": cube(2 * side), "density": density}
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.mesh(bigger["vertices"], faces, density=bigger["density"], mass=mass)
    assert_names(error, blamed, "overflow", "double precision")


@pytest.mark.parametrize(
    ("mass", "radius", "fits", "beyond"),
    [
        # Exact powers of two: the shift term (m/2) d^2 = 2^1023 at d = 2^312.
        (2.0**400, 1.0, 2.0**312, 2.0**313),
        # The 1e200-scale parts: (m/2) d^2 = 5e305 at d = 1e53, 5e309 at d = 1e55.
        (1e200, 1e50, 1e53, 1e55),
    ],
)
def test_composite_keeps_the_shift_term_up_to_the_largest_double(mass, radius, fits, beyond):
    # Two equal spheres at distance d along x: I_xx = 2 (2/5) m r^2, I_yy = I_zz = that plus
    # the reduced mass times d^2, (m/2) d^2, in mpmath. Within 8 eps (a few roundings of the
    # parts and of the shift row). Beyond the largest double: an error naming `other`.
    a = ph.Body.sphere(mass, radius)
    composite = a + a.translated([fits, 0.0, 0.0])
    with mpmath.workdps(40):
        own = 2 * mpmath.mpf(2) / 5 * mpmath.mpf(mass) * mpmath.mpf(radius) ** 2
        shift = mpmath.mpf(mass) / 2 * mpmath.mpf(fits) ** 2
        expected = np.diag([float(own), float(own + shift), float(own + shift)])
    assert_close_normwise(composite.inertia, expected, 8 * EPS)
    p = composite.principal()
    np.testing.assert_allclose(p.moments, np.sort(np.diag(expected)), rtol=8 * EPS)
    np.testing.assert_array_equal(p.multiplicity, [1, 2, 2])
    with pytest.raises(ph.ArgumentError) as error:
        _ = a + a.translated([beyond, 0.0, 0.0])
    assert_names(error, "other", "overflow", "double precision")


def test_composite_whose_mass_overflows_raises():
    heavy = ph.Body.point_masses([1e308], [[0.0, 0.0, 0.0]])
    with pytest.raises(ph.ArgumentError) as error:
        sum([heavy, heavy])
    assert_names(error, "other", "mass", "overflow")


def test_scaled_and_translated_at_the_boundary():
    # scaled(m, l) multiplies the moments by m l^2: 2^1000 * 2^40 overflows as one factor but
    # the result 0.4 * 2^-600 * 2^1040 is a double. Before: inf.
    small = ph.Body.sphere(2.0**-600, 1.0)
    big = small.scaled(2.0**1000, 2.0**20)
    np.testing.assert_allclose(big.principal().moments, [0.4 * 2.0**440] * 3, rtol=4 * EPS)
    assert big.mass == 2.0**400
    with pytest.raises(ph.ArgumentError) as error:
        small.scaled(2.0**1000, 2.0**400)
    assert_names(error, "mass_scale", "overflow")
    with pytest.raises(ph.ArgumentError) as error:
        small.scaled(2.0**10, 2.0**900)
    assert_names(error, "length_scale", "overflow")
    # translated: a centre of mass beyond the largest double.
    far = ph.Body.sphere(1.0, 1.0).translated([1e308, 0.0, 0.0])
    with pytest.raises(ph.ArgumentError) as error:
        far.translated([1e308, 0.0, 0.0])
    assert_names(error, "offset", "centre of mass", "overflow")


def test_queries_whose_results_overflow_raise_naming_the_argument():
    body = ph.Body.sphere(2.5, 2.0)  # I = 4 about every axis
    with pytest.raises(ph.ArgumentError) as error:
        body.inertia_about([1e155, 0.0, 0.0])
    assert_names(error, "point", "overflow")
    assert body.inertia_about([1e150, 0.0, 0.0])[1, 1] == pytest.approx(2.5e300, rel=2 * EPS)
    with pytest.raises(ph.ArgumentError) as error:
        body.kinetic_energy([1e155, 0.0, 0.0])
    assert_names(error, "omega", "overflow")
    with pytest.raises(ph.ArgumentError) as error:
        body.angular_momentum_body([1e308, 0.0, 0.0])
    assert_names(error, "omega", "overflow")
    assert body.angular_momentum_body([1e307, 0.0, 0.0])[0] == pytest.approx(4e307, rel=2 * EPS)


# ---------------------------------------------------------------------------------------------
# 4. Bit for bit the same under any number of threads
# ---------------------------------------------------------------------------------------------

THREADS = """
import hashlib
import numpy as np
import polhode as ph

def torus(nu, nv, major=3.0, minor=1.0):
    u = np.linspace(0, 2 * np.pi, nu, endpoint=False)[:, None]
    v = np.linspace(0, 2 * np.pi, nv, endpoint=False)[None, :]
    x = (major + minor * np.cos(v)) * np.cos(u)
    y = (major + minor * np.cos(v)) * np.sin(u)
    z = minor * np.sin(v) + 0 * u
    vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1) + [1e3, -2e3, 5e2]
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + (j + 1) % nv
    d = i * nv + (j + 1) % nv
    faces = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    return vertices, faces

def digest(body):
    h = hashlib.sha256()
    p = body.principal()
    for x in (np.array([body.mass]), body.center_of_mass, body.inertia, body.second_moment,
              p.moments, p.axes):
        h.update(np.ascontiguousarray(x).tobytes())
    return h.hexdigest()

rng = np.random.default_rng(2024)
n = 2_000_000
masses = rng.uniform(0.1, 2.0, n)
positions = rng.normal(size=(n, 3)) * [1.0, 2.0, 3.0] + [1e3, 0.0, -5e2]
print("points", digest(ph.Body.point_masses(masses, positions)))
vertices, faces = torus(700, 700)
print("mesh", digest(ph.Body.mesh(vertices, faces, density=1.0, fix_winding=True)))
print("shell", digest(ph.Body.mesh(vertices, faces, density=1.0, shell=True)))
tensors = rng.normal(size=(300_000, 3, 3))
p = ph.principal(tensors + tensors.transpose(0, 2, 1))
print("principal", hashlib.sha256(p.moments.tobytes() + p.axes.tobytes()).hexdigest())
"""


def test_results_are_bit_identical_for_any_number_of_threads():
    # Every sum runs over fixed chunks whose results are combined in order on one thread, so
    # the number of threads cannot change a bit. Before: point masses differed in the last bit
    # between RAYON_NUM_THREADS=1 and 2 (rayon's reduction tree follows the work stealing).
    outputs = {}
    for threads in ("1", "2", "3", None):
        env = dict(os.environ)
        env.pop("RAYON_NUM_THREADS", None)
        if threads is not None:
            env["RAYON_NUM_THREADS"] = threads
        run = subprocess.run(
            [sys.executable, "-c", THREADS], capture_output=True, text=True, env=env, check=True
        )
        outputs[threads] = run.stdout
    assert len(outputs["1"].splitlines()) == 4, outputs["1"]
    for threads, out in outputs.items():
        assert out == outputs["1"], (threads, out, outputs["1"])


# ---------------------------------------------------------------------------------------------
# 5. URDF roll, pitch, yaw without a warning, gimbal lock included
# ---------------------------------------------------------------------------------------------


def urdf_rpy_and_frame(body: ph.Body):
    xml = body.to_urdf_inertial()
    rpy = [float(x) for x in re.search(r'rpy="([^"]+)"', xml).group(1).split()]
    return rpy, body.principal().axes


def assert_rpy_reproduces_the_frame(body: ph.Body, what: str):
    # The rpy of a URDF <origin> is R = Rz(yaw) Ry(pitch) Rx(roll); it must give the principal
    # frame to 1e-12 (rounding of the angles and their sines: a few eps), warnings as errors.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rpy, axes = urdf_rpy_and_frame(body)
    rebuilt = ref.fixed_axis_rpy_matrix(*rpy)
    error = float(np.max(np.abs(rebuilt - axes)))
    assert error <= 1e-12, (what, rpy, error)
    assert -math.pi / 2 <= rpy[1] <= math.pi / 2, (what, rpy)


def test_t_handle_urdf_has_no_gimbal_lock_warning():
    # The README's T-handle: its principal frame has its smallest axis along z, pitch = -pi/2.
    # Before: scipy's as_euler warned (an error under this suite's filterwarnings).
    shaft = ph.Body.cylinder(mass=0.3, radius=0.01, length=0.2)
    bar = ph.Body.cylinder(0.2, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    t_handle = shaft + bar.translated([0, 0, 0.1])
    rpy, axes = urdf_rpy_and_frame(t_handle)
    assert abs(abs(axes[2, 0]) - 1.0) <= 1e-15  # gimbal-locked indeed
    assert_rpy_reproduces_the_frame(t_handle, "t-handle")


@pytest.mark.parametrize("angle", [0.0, 0.3, -2.0, math.pi])
def test_gimbal_locked_frames_are_reproduced(angle):
    # Moments (3, 2, 1) along x, y, z: the smallest axis is z, so the frame's first column is
    # +-z, pitch = -+pi/2 exactly; turning the body about z keeps it locked.
    r = axis_rotation("z", angle)
    body = ph.Body.from_inertia(1.0, r @ np.diag([3.0, 2.0, 1.0]) @ r.T)
    assert_rpy_reproduces_the_frame(body, f"locked {angle}")


@pytest.mark.parametrize("tilt", [1e-3, 1e-7, 1e-9, 1e-12, 1e-15])
def test_nearly_gimbal_locked_frames_are_reproduced(tilt):
    # Near the lock, yaw and roll are each ill-determined (by eps / cos(pitch)) but the roll is
    # taken with the computed yaw removed, so the frame still comes back to rounding.
    r = axis_rotation("y", tilt) @ axis_rotation("z", 0.7)
    body = ph.Body.from_inertia(1.0, r @ np.diag([3.0, 2.0, 1.0]) @ r.T)
    assert_rpy_reproduces_the_frame(body, f"tilt {tilt}")


def test_random_frames_are_reproduced():
    rng = np.random.default_rng(77)
    for i in range(200):
        r = ref.random_rotation(rng)
        body = ph.Body.from_inertia(1.0, r @ np.diag([1.0, 1.7, 2.2]) @ r.T)
        assert_rpy_reproduces_the_frame(body, f"random {i}")


# ---------------------------------------------------------------------------------------------
# 6. Numbers in messages in short form
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "shown"),
    [
        (lambda: ph.Body.tube(1.0, 1e300, 1e299, 1.0), "1e300"),
        (lambda: ph.Body.torus(1.0, 1e-300, 1e300), "1e300"),
        (lambda: ph.Body.capsule(1.0, 1.0, -1e300), "-1e300"),
        (lambda: ph.principal(np.eye(3), rtol=-1e300), "-1e300"),
        (lambda: ph.Body.tube(1.0, 3e-300, 1e-300, 1.0), "3e-300"),
    ],
)
def test_messages_show_numbers_in_short_form(call, shown):
    # Rust's `{}` writes 1e300 as 301 digits; the messages show the shortest round-trip form.
    with pytest.raises(ph.PolhodeError) as error:
        call()
    message = str(error.value)
    assert re.search(r"\d{20}", message) is None, message
    assert shown in message, message
    assert len(message) < 200, message


def test_overflow_messages_are_short():
    with pytest.raises(ph.ArgumentError) as error:
        ph.Body.sphere(1e300, 1e10)
    message = str(error.value)
    assert re.search(r"\d{20}", message) is None, message
    assert "4.0e+319" in message, message  # the size it would have: 2/5 1e300 (1e10)^2


@pytest.mark.parametrize("heavy", [1e121, 1e130, 1e200])
def test_a_mass_beyond_2_to_the_400_beside_light_ones(heavy):
    """Masses beyond 2^400 take the scaled path, which centred the rows about the first point:
    the heavy point's row was the rounding of its offset, weighted by its mass (I = 7.7e96
    instead of 0.81 for masses 1 and 1e130). The reference is a 60-digit mpmath sum."""
    rng = np.random.default_rng(7)
    r = rng.normal(size=(60, 3))
    m = rng.uniform(0.5, 2.0, 60)
    m[-1] = heavy
    body = ph.Body.point_masses(m, r)
    with mpmath.workdps(60):
        ms = [mpmath.mpf(float(x)) for x in m]
        rs = [[mpmath.mpf(float(x)) for x in row] for row in r]
        total = sum(ms)
        c = [sum(mi * ri[k] for mi, ri in zip(ms, rs, strict=True)) / total for k in range(3)]
        second = [
            [sum(mi * (ri[j] - c[j]) * (ri[k] - c[k]) for mi, ri in zip(ms, rs, strict=True))
             for k in range(3)]
            for j in range(3)
        ]
        trace = second[0][0] + second[1][1] + second[2][2]
        inertia = np.array(
            [[float((trace if j == k else 0) - second[j][k]) for k in range(3)] for j in range(3)]
        )
    assert np.abs(body.inertia - inertia).max() <= 1e-14 * np.abs(inertia).max()
    # Two points, the closed form m M / (m + M) d^2 (0.81 for m = 1, d = 0.9).
    pair = ph.Body.point_masses([1.0, heavy], [[0.0, 0.0, 0.1], [0.0, 0.0, 1.0]])
    assert pair.inertia[0, 0] == pytest.approx(0.81, rel=4e-16)
