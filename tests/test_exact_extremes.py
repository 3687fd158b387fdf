"""The exact solution on extreme input, each case against an independent reference.

1. Range: an omega component of 1e-170 or a subnormal one next to one of 0.4, a symmetric top
   at |omega| ~ 1e-170, moments spanning 1e-150..1e150: against ``exact_closed_form`` (mpmath
   on exact rational invariants, as many digits as the motion needs), the period against
   ``exact_period``, and the exact scalings by powers of two: ``(s I, w)`` is the motion of
   ``(I, w)`` and ``(I, s w)`` at ``t`` is ``s`` times ``(I, w)`` at ``s t``.
2. Time: double precision ends where one ulp of t turns the fastest angle of the motion by a
   quarter turn (``|t| <= 2^50 2 pi / R``). Just below, the answer is accurate and T, |L|
   conserved; just above, and at t = 1e90, an error, never a number.
3. The separatrix (Delta_2 = 0 exactly) and the motions within rounding of it: each component
   relative to a 50-digit evaluation of the closed form along t, until the components underflow.
4. Order and signs: symmetric tops with the distinct moment first, in the middle or last, and
   (1, 2, 3) in all six orders, with every sign of omega, against the Taylor reference
   ``reference_motion`` (omega and the quaternion, up to 1e5 periods).

Bounds in units of eps: each output is a product of about five rounded factors (the amplitude,
the moment, the elliptic or hyperbolic function, the unit) and the phase is carried in
double-double, so a few ulp; ``ULP = 10`` allows for the elliptic functions' own rounding (up to
about 4 ulp measured) and no more.
"""

from __future__ import annotations

import functools
import itertools
import math

import numpy as np
import pytest

import polhode as ph
from reference_motion import exact_closed_form, exact_period, reference_motion

EPS = float(np.finfo(float).eps)
ULP = 10
TINY = float(np.finfo(float).tiny)
_q = np.array([0.1, -0.2, 0.3, 0.9])
Q0 = tuple(float(x) for x in _q / np.linalg.norm(_q))


def scaled_rel(x, ref):
    """Per row ``|x - ref| / |ref|``, both scaled by the power of two of ``max |ref|`` first (no
    square underflows for rows of 1e-170)."""
    x, ref = np.asarray(x, float), np.asarray(ref, float)
    e = np.floor(np.log2(np.max(np.abs(ref), axis=-1, keepdims=True)))
    scale = np.ldexp(1.0, e.astype(int))
    x, ref = x / scale, ref / scale
    return np.linalg.norm(x - ref, axis=-1) / np.linalg.norm(ref, axis=-1)


def quat_err(q, ref):
    q, ref = np.asarray(q), np.asarray(ref)
    return np.minimum(np.linalg.norm(q - ref, axis=-1), np.linalg.norm(q + ref, axis=-1))


@functools.cache
def _closed(moments, omega0, times, dps):
    return exact_closed_form(moments, omega0, Q0, np.array(times), dps=dps)


def closed(moments, omega0, times, dps=20):
    return _closed(
        tuple(map(float, moments)), tuple(map(float, omega0)), tuple(map(float, times)), dps
    )


def check_against(label, moments, omega0, times, w_ref, q_ref, bound=ULP * EPS):
    sol = ph.simulate(moments, omega0, times, orientation0=Q0, method="exact")
    ew = scaled_rel(sol.omega, w_ref)
    eq = quat_err(sol.quaternion, q_ref)
    bad = (ew > bound) | (eq > bound)
    rows = "\n".join(
        f"  t = {t:.6g}: omega {a / EPS:.1f} ulp, quaternion {b / EPS:.1f} ulp"
        + ("  <-- FAIL" if x else "")
        for t, a, b, x in zip(times, ew, eq, bad, strict=True)
    )
    assert not bad.any(), (
        f"{label}: exact solution vs reference (bound {bound / EPS:g} ulp):\n{rows}"
    )
    return sol


# ---------------------------------------------------------------------------------------------
# 1. Range
# ---------------------------------------------------------------------------------------------

I359 = (3.0, 5.0, 9.0)
EXTREME = [
    # near the intermediate axis: Delta_2 ~ 1e-340 (its squares underflow), k' ~ 1e-170
    ("tiny lo and hi", I359, (1e-170, 0.4, 1e-170), "about_largest_axis"),
    ("tiny lo and hi, signs", I359, (-1e-170, 0.4, 3e-170), "about_largest_axis"),
    ("tiny lo", I359, (1e-170, 0.4, 0.1), "about_largest_axis"),
    ("tiny hi", I359, (0.1, 0.4, 1e-200), "about_smallest_axis"),
    # subnormal components
    ("subnormal lo", I359, (5e-320, 0.4, 0.0), "about_smallest_axis"),
    ("subnormal lo and hi", I359, (5e-320, 0.4, 7e-321), "about_smallest_axis"),
    ("subnormal near the largest axis", I359, (1e-320, 1e-320, 0.4), "about_largest_axis"),
    ("subnormal near the smallest axis", I359, (0.3, 1e-320, -1e-320), "about_smallest_axis"),
    # moments spanning 1e300
    ("moments 1e-150..1e150", (1e-150, 1.0, 1e150), (0.3, 0.4, 0.5), None),
    ("moments 1e-150..1e150, fast", (1e-150, 1.0, 1e150), (1e75, 0.4, 1e-75), None),
    ("moments 1e150..1e-150, fast", (1e150, 1e-150, 1.0), (1e-75, 1e75, 0.4), None),
    # k' ~ 1 (near-circular functions), L within 1e-47 of the smallest axis: the transverse
    # components set the quaternion through psi (a random search found u0 1e-8 off here)
    (
        "moments 1e-12..1e33, near the smallest axis",
        (3.6795152100972124e33, 6.58682710771732e-05, 9.354964852355093e-13),
        (-1.281415334939086e-53, -7.407558310025045e-20, -3.1379448139871975e39),
        "about_smallest_axis",
    ),
]
SYMMETRIC_TINY = [
    ("oblate at 1e-170", (2.0, 2.0, 3.0), (1e-170, 2e-170, 3e-170)),
    ("middle axis at 1e-170", (2.0, 3.0, 2.0), (1e-170, -2e-170, 3e-170)),
    ("prolate at 1e-170", (3.0, 2.0, 2.0), (-1e-170, 2e-170, 3e-170)),
]
FRACTIONS = (0.0, 0.13, 0.5, 3.7)


def period_times(moments, omega0):
    p = float(exact_period(moments, omega0))
    return np.array(FRACTIONS) * p


@pytest.mark.parametrize(
    ("label", "moments", "omega0", "regime"), EXTREME, ids=[c[0] for c in EXTREME]
)
def test_extreme_range_against_the_closed_form(label, moments, omega0, regime):
    times = period_times(moments, omega0)
    w_ref, q_ref = closed(moments, omega0, times)
    sol = check_against(label, moments, omega0, times, w_ref, q_ref)
    # The given components come back at t = 0, tiny ones included (componentwise).
    w0 = np.asarray(omega0)
    assert np.all(np.abs(sol.omega[0] - w0) <= 2 * EPS * np.abs(w0)), sol.omega[0]
    if regime is not None:
        # (analyze's linearised rates overflow for the moments spanning 1e300: not asked there.)
        a = ph.analyze(moments, omega0)
        assert a.regime == regime
        assert abs(a.period - float(exact_period(moments, omega0))) <= 4 * EPS * a.period


def test_tiny_components_flip_like_the_closed_form():
    """(1e-170, 0.4, 1e-170): half a period later omega_2 is -0.4 (the flip), where the
    separatrix that the underflowing squares suggest would keep +0.4."""
    p = float(exact_period(I359, (1e-170, 0.4, 1e-170)))
    sol = ph.simulate(I359, (1e-170, 0.4, 1e-170), [0.5 * p], method="exact")
    assert abs(sol.omega[0, 1] + 0.4) < 1e-12


@pytest.mark.parametrize(
    ("label", "moments", "omega0"), SYMMETRIC_TINY, ids=[c[0] for c in SYMMETRIC_TINY]
)
def test_symmetric_top_at_tiny_rates(label, moments, omega0):
    times = period_times(moments, omega0)
    w_ref, q_ref = closed(moments, omega0, times)
    sol = check_against(label, moments, omega0, times, w_ref, q_ref)
    assert np.all(np.isfinite(sol.quaternion))


def test_subnormal_symmetric_top():
    """|omega| ~ 5e-320: nothing representable turns it much, and nothing is NaN."""
    moments, omega0 = (2.0, 2.0, 3.0), (5e-320, 0.0, 3e-321)
    times = np.array([0.0, 1e300, 1.7e308])
    w_ref, q_ref = closed(moments, omega0, times)
    sol = ph.simulate(moments, omega0, times, orientation0=Q0, method="exact")
    # Subnormal outputs hold few digits: within one unit of the last subnormal place.
    assert np.all(np.abs(sol.omega - w_ref) <= 4.95e-324)
    assert np.all(quat_err(sol.quaternion, q_ref) <= ULP * EPS)


SCALED = [
    (I359, (0.1, 0.4, -0.05)),
    ((2.0, 3.0, 6.0), (-1.5, -2.0, -0.5)),
    ((2.0, 3.0, 2.0), (0.3, -0.4, 0.5)),
    (I359, (1e-170, 0.4, 1e-170)),
    (I359, (5e-320, 0.4, 7e-321)),
    ((1e-150, 1.0, 1e150), (1e75, 0.4, 1e-75)),
    ((1.0, 2.0, 3.125), (-1.875e-8, 2.0, 1e-8)),
]


@pytest.mark.parametrize(("moments", "omega0"), SCALED)
@pytest.mark.parametrize("k", [-150, -3, 1, 4, 101])
def test_scaling_by_powers_of_two_is_exact(moments, omega0, k):
    """(s I, w) is the motion of (I, w); (I, s w) at t is s (I, w) at s t. Powers of four keep
    every internal double (so bitwise by construction); odd powers go through libm's hypot and
    atan2 at other scales, which may round differently: 2 ulp."""
    s = 2.0**k
    bound = 0.0 if k % 2 == 0 else 2 * EPS
    p = exact_period(moments, omega0)
    times = np.array([0.0, 0.3, 1.7, 13.1]) * (float(p) if p else 1.0)
    base = ph.simulate(moments, omega0, times, orientation0=Q0, method="exact")
    a = ph.simulate(tuple(x * s for x in moments), omega0, times, orientation0=Q0, method="exact")
    assert np.all(scaled_rel(a.omega, base.omega) <= bound)
    assert np.all(quat_err(a.quaternion, base.quaternion) <= bound)
    ws = tuple(x * s for x in omega0)
    if any(x / s != y for x, y in zip(ws, omega0, strict=True)):
        return  # a subnormal component would lose bits: not an exact scaling
    b = ph.simulate(moments, ws, times / s, orientation0=Q0, method="exact")
    assert np.all(scaled_rel(b.omega / s, base.omega) <= bound)
    assert np.all(quat_err(b.quaternion, base.quaternion) <= bound)


# ---------------------------------------------------------------------------------------------
# 2. Where double precision ends
# ---------------------------------------------------------------------------------------------


def accepted(moments, omega0, t):
    try:
        ph.simulate(moments, omega0, [t], orientation0=Q0, method="exact")
    except ph.PolhodeError:
        return False
    return True


def time_bound(moments, omega0):
    """The largest accepted time, by bisection on its logarithm (relative 1e-12)."""
    lo, hi = 1.0, 1e300
    assert accepted(moments, omega0, lo) and not accepted(moments, omega0, hi)
    while hi / lo > 1 + 1e-12:
        mid = math.sqrt(lo * hi)
        if accepted(moments, omega0, mid):
            lo = mid
        else:
            hi = mid
    return lo


BOUND_CASES = [
    ("general", I359, (0.1, 0.4, -0.05)),
    ("symmetric, axis in the middle", (2.0, 3.0, 2.0), (0.3, -0.4, 0.5)),
    ("steady", (1.0, 2.0, 3.0), (0.0, 0.0, 0.75)),
    ("separatrix", (2.0, 3.0, 6.0), (-1.5, -2.0, -0.5)),
]


@pytest.mark.parametrize(
    ("label", "moments", "omega0"), BOUND_CASES, ids=[c[0] for c in BOUND_CASES]
)
def test_time_bound_both_sides(label, moments, omega0):
    tb = time_bound(moments, omega0)
    g = float(np.linalg.norm(np.multiply(moments, omega0)))
    # Every angular rate of the motion is below 2 G / I_min (the precession bound counts its
    # varying part once more), and the phase of omega alone turns 2 pi per period: so
    # 2^50 pi I_min / G <= t_b <= 2^50 T.
    assert tb >= 2**50 * math.pi * min(moments) / g
    p = exact_period(moments, omega0)
    if p is not None:
        assert tb <= 2**50 * float(p)
    if label == "steady":
        # The fastest angle is the rotation itself: t_b = 2^50 2 pi / |w|.
        assert abs(tb - 2**51 * math.pi / 0.75) <= 1e-11 * tb
    # Just below: accurate, T and |L| conserved to rounding.
    times = np.array([0.5 * tb, tb * (1 - 1e-9)])
    if p is not None:
        w_ref, q_ref = reference_motion(moments, omega0, Q0, times, dps=30, method="periodic")
    else:
        w_ref, q_ref = closed(moments, omega0, times, dps=30)
    sol = check_against(label, moments, omega0, times, w_ref, q_ref)
    e0 = 0.5 * float(np.dot(np.multiply(moments, omega0), omega0))
    assert np.all(np.abs(sol.energy - e0) <= 4 * EPS * e0)
    lnorm = np.linalg.norm(sol.omega * np.asarray(moments), axis=-1)
    assert np.all(np.abs(lnorm - g) <= 4 * EPS * g)
    # Just above and far above: an error, not a number.
    for t in (tb * (1 + 1e-9), 1e90):
        with pytest.raises(ph.PolhodeError):
            ph.simulate(moments, omega0, [0.0, t], orientation0=Q0, method="exact")


# ---------------------------------------------------------------------------------------------
# 3. The separatrix
# ---------------------------------------------------------------------------------------------


def separatrix_cases():
    """Exact separatrices: I = (2, 3, 6) with |w1| = 3 |w3| and I = (1, 2, 3.125) with
    w = (1.875, ., 1) (Delta_2 = -m1^2 + 0.36 m3^2 = 0 in binary), every order of the moments
    and every sign."""
    cases = []
    for moments, w in (((2.0, 3.0, 6.0), (1.5, 2.0, 0.5)), ((1.0, 2.0, 3.125), (1.875, 0.5, 1.0))):
        for perm in itertools.permutations(range(3)):
            for signs in itertools.product((1, -1), repeat=3):
                cases.append(
                    (
                        tuple(moments[i] for i in perm),
                        tuple(s * w[i] for s, i in zip(signs, perm, strict=True)),
                    )
                )
    return cases


SEPARATRIX = separatrix_cases()


def test_separatrix_cases_are_exact():
    for moments, omega0 in SEPARATRIX:
        assert ph.analyze(moments, omega0).regime == "separatrix", (moments, omega0)


def componentwise(x, ref):
    """Relative error of each component where the reference is a normal double; where it is
    below, the absolute error in units of the smallest normal."""
    x, ref = np.asarray(x), np.asarray(ref)
    normal = np.abs(ref) >= TINY
    rel = np.where(normal, np.abs(x - ref) / np.where(normal, np.abs(ref), 1.0), 0.0)
    below = np.where(normal, 0.0, np.abs(x - ref) / TINY)
    return rel, below


def separatrix_rate(moments, omega0):
    """lambda = sqrt(Delta_1 (I3 - I2) / (I1 I2 I3)) in the frame (smallest, middle, largest)."""
    i1, i2, i3 = sorted(moments)
    m = np.multiply(moments, omega0)
    d1 = float(m @ m - np.dot(m, omega0) * i1)
    return math.sqrt(d1 * (i3 - i2) / (i1 * i2 * i3))


@pytest.mark.parametrize(("moments", "omega0"), SEPARATRIX[3::17])
def test_separatrix_componentwise_to_underflow(moments, omega0):
    """Each component of omega, relative, against the 50-digit closed form (sech and tanh of
    u = lambda t + u0) for lambda t from 0 to 800, where sech u underflows."""
    lam = separatrix_rate(moments, omega0)
    times = np.concatenate([np.linspace(0.0, 30.0, 16), np.linspace(50.0, 800.0, 11)]) / lam
    w_ref, q_ref = closed(moments, omega0, times, dps=50)
    sol = ph.simulate(moments, omega0, times, orientation0=Q0, method="exact")
    rel, below = componentwise(sol.omega, w_ref)
    assert rel.max() <= ULP * EPS, (rel.max(axis=0) / EPS, moments, omega0)
    assert below.max() <= ULP * EPS
    # The decaying components reach the subnormals (or zero) within the times.
    assert np.sort(np.abs(w_ref[-1]))[1] < TINY
    assert np.all(quat_err(sol.quaternion, q_ref) <= ULP * EPS)


NEAR_SEPARATRIX = [
    # |Delta_2| / G^2 ~ 1e-33: k' ~ 1e-16 (hyperbolic functions with first-order corrections)
    ((1.0, 2.0, 3.125), (-1.875e-8, 2.0, 1e-8)),
    # k' ~ 1e-170 (hyperbolic functions, k' carried with its exponent)
    (I359, (1e-170, 0.4, -1e-170)),
]


@pytest.mark.parametrize(("moments", "omega0"), NEAR_SEPARATRIX)
def test_near_separatrix_decaying_components(moments, omega0):
    """Within rounding of the separatrix: the components that decay like sech (the smallest and
    the largest axes) keep their relative digits; the one crossing zero is checked normwise."""
    p = float(exact_period(moments, omega0))
    times = np.concatenate([np.linspace(0.0, 0.5, 11), [0.77, 1.0, 3.3]]) * p
    w_ref, q_ref = closed(moments, omega0, times, dps=30)
    sol = check_against("near separatrix", moments, omega0, times, w_ref, q_ref)
    lo, hi = int(np.argmin(moments)), int(np.argmax(moments))
    rel, _ = componentwise(sol.omega[:, [lo, hi]], w_ref[:, [lo, hi]])
    assert rel.max() <= ULP * EPS, rel.max(axis=0) / EPS


THETA_RANGE = [
    # The precession phase as a theta series (nome q <= 0.5): q from 0.01 to just below 0.5,
    # and m -> 0 with nu = B1^2/B3^2 or I3 (I2 - I1) / (I1 (I3 - I2)) far from 1 (moments 1e-6
    # apart).
    ("generic, q ~ 0.01", (1.0, 2.0, 3.0), (0.3, 0.5, 0.8)),
    ("q ~ 0.33", (2.0, 3.0, 6.0), (1.5, 0.2, 0.5005)),
    ("q ~ 0.41", (2.0, 3.0, 6.0), (1.5, 0.2, 0.50005)),
    ("q ~ 0.48", (2.0, 3.0, 6.0), (1.5, 0.2, 0.500005)),
    ("I2 - I1 = 1e-6", (1.0, 1.000001, 3.0), (0.3, 0.5, 0.8)),
    ("I3 - I2 = 1e-6", (1.0, 2.999999, 3.0), (0.3, 0.5, 0.8)),
]


@pytest.mark.parametrize(
    ("label", "moments", "omega0"), THETA_RANGE, ids=[c[0] for c in THETA_RANGE]
)
def test_theta_series_phase(label, moments, omega0):
    """Where the phase is summed as a theta series, omega and the attitude against the
    closed form (mpmath) over a period and 1e4 periods out."""
    p = float(exact_period(moments, omega0))
    times = np.array([*FRACTIONS, 1e4 + 0.3]) * p
    w_ref, q_ref = closed(moments, omega0, times, dps=30)
    check_against(label, moments, omega0, times, w_ref, q_ref)


# ---------------------------------------------------------------------------------------------
# 4. Every order, every sign
# ---------------------------------------------------------------------------------------------

ORDERS = sorted(
    {
        perm
        for base in ((1.0, 1.0, 2.0), (1.0, 2.0, 2.0), (1.0, 2.0, 3.0))
        for perm in itertools.permutations(base)
    }
)
SIGNS = list(itertools.product((1, -1), repeat=3))
PERIODS = np.array([0.0, 0.37, 1.3, 10.3, 1000.3, 1e5 + 0.7])


@pytest.mark.parametrize("moments", ORDERS, ids=[str(o) for o in ORDERS])
def test_every_order_and_sign_against_the_taylor_reference(moments):
    """Symmetric tops with the distinct moment in each position and (1, 2, 3) in each order,
    every sign of omega: omega and the quaternion against the exact-arithmetic Taylor series
    (its exact quasi-periodicity beyond two periods)."""
    for signs in SIGNS:
        omega0 = tuple(s * x for s, x in zip(signs, (0.3, 0.4, 0.5), strict=True))
        times = PERIODS * float(exact_period(moments, omega0))
        w_ref, q_ref = reference_motion(moments, omega0, Q0, times, dps=20, method="periodic")
        check_against(f"I = {moments}, w0 = {omega0}", moments, omega0, times, w_ref, q_ref)
    if len(set(moments)) == 2:
        axis = [i for i in range(3) if moments.count(moments[i]) == 1][0]
        sol = ph.simulate(moments, (0.3, 0.4, 0.5), PERIODS[:4], method="exact")
        # omega_s is constant about the symmetry axis, and only about it.
        assert np.all(sol.omega[:, axis] == (0.3, 0.4, 0.5)[axis])
        others = [i for i in range(3) if i != axis]
        assert not np.all(sol.omega[:, others] == sol.omega[0, others])
