"""polhode.analyze against independent references.

- energy and |L| against exact rational arithmetic;
- the period 4 K(m) / lambda against mpmath (m and lambda formed exactly from the binary inputs
  with fractions, K at 80 digits), cross-checked with the Taylor reference's constants;
- the flip interval against the sign changes of the intermediate component in a scipy
  integration (DOP853, rtol 1e-12, event location);
- the symmetric-top precession rate, and the linearised oscillation frequency / growth rate near
  each axis, against scipy integrations of a small perturbation.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import polhode as ph
from reference import euler_rhs
from reference_motion import motion_constants, turns_over_exact

SMALLEST, LARGEST = "about_smallest_axis", "about_largest_axis"

EPS = float(np.finfo(float).eps)


def _mpf(x: Fraction):
    return mp.mpf(x.numerator) / x.denominator


def exact_invariants(moments, omega):
    i = [Fraction(float(x)) for x in moments]
    w = [Fraction(float(x)) for x in omega]
    m = [a * b for a, b in zip(i, w, strict=True)]
    g2 = sum(x * x for x in m)
    t2 = sum(a * b for a, b in zip(m, w, strict=True))
    return i, w, g2, t2


def exact_period(moments, omega):
    """4 K(m) / lambda, every quantity formed exactly (both regimes)."""
    i, _, g2, t2 = exact_invariants(moments, omega)
    i1, i2, i3 = sorted(i)
    d1, d2, d3 = g2 - t2 * i1, g2 - t2 * i2, g2 - t2 * i3
    if d2 > 0:  # about axis 3
        k2 = (i2 - i1) * (-d3) / ((i3 - i2) * d1)
        lam2 = d1 * (i3 - i2) / (i1 * i2 * i3)
    else:  # about axis 1
        k2 = (i3 - i2) * d1 / ((i2 - i1) * (-d3))
        lam2 = (-d3) * (i2 - i1) / (i1 * i2 * i3)
    # K(m) near m = 1 costs log10(1 / (1 - m)) digits (up to 25 here): 80 digits
    with mp.workdps(80):
        return 4 * mp.ellipk(_mpf(k2)) / mp.sqrt(_mpf(lam2))


# ---------------------------------------------------------------------------------------------
# Energy, |L|, regime, stability
# ---------------------------------------------------------------------------------------------

GENERAL = [
    ("I=(1,2,3) about 3", (1.0, 2.0, 3.0), (0.3, -0.5, 0.8), "about_largest_axis"),
    ("I=(1,2,3) about 1", (1.0, 2.0, 3.0), (0.9, 0.2, -0.1), "about_smallest_axis"),
    ("unsorted (3,1,2)", (3.0, 1.0, 2.0), (-0.2, 0.7, 0.4), None),
    (
        "HLW (2,1,2/3)",
        (2.0, 1.0, 2.0 / 3.0),
        (math.cos(1.1) / 2, 0.0, math.sin(1.1) * 1.5),
        "about_smallest_axis",
    ),
    ("Krogh (151,49,200)", (151.0, 49.0, 200.0), (0.0, -1.0, -1.0), "about_largest_axis"),
    ("flip eps=1e-2", (3.0, 5.0, 9.0), (0.0, 0.4, 0.01 / 9), "about_largest_axis"),
    ("flip eps=1e-6", (3.0, 5.0, 9.0), (0.0, 0.4, 1e-6 / 9), "about_largest_axis"),
    ("flip eps=1e-12", (3.0, 5.0, 9.0), (0.0, 0.4, 1e-12 / 9), "about_largest_axis"),
    ("near separatrix +1e-6", (2.0, 3.0, 6.0), (0.375, 0.5, 0.125 * (1 + 1e-6)), LARGEST),
    ("near separatrix +1e-12", (2.0, 3.0, 6.0), (0.375, 0.5, 0.125 * (1 + 1e-12)), LARGEST),
    ("near separatrix -1e-12", (2.0, 3.0, 6.0), (0.375, 0.5, 0.125 * (1 - 1e-12)), SMALLEST),
    ("near symmetric 1+1e-8", (1.0, 1.0 + 1e-8, 2.0), (0.3, 0.4, 0.5), "about_largest_axis"),
    ("thin rod", (6.58e-6, 1.7231e-4, 1.7243e-4), (50.0, 2.0, 1.0), "about_smallest_axis"),
    ("flat (1,0.75,0.25)", (1.0, 0.75, 0.25), (1.0, 0.01, 0.01), "about_largest_axis"),
]
GENERAL_IDS = [g[0] for g in GENERAL]


@pytest.mark.parametrize(("label", "moments", "omega", "regime"), GENERAL, ids=GENERAL_IDS)
def test_energy_and_angular_momentum(label, moments, omega, regime):
    a = ph.analyze(moments, omega)
    _, _, g2, t2 = exact_invariants(moments, omega)
    energy = float(t2 / 2)
    norm = float(mp.sqrt(_mpf(g2)))
    assert abs(a.energy - energy) <= 4 * EPS * energy, (a.energy, energy)
    assert abs(a.angular_momentum_norm - norm) <= 4 * EPS * norm, (a.angular_momentum_norm, norm)
    assert np.all(np.diff(a.moments) >= 0)
    np.testing.assert_array_equal(np.sort(moments), a.moments)
    assert a.axis_stability == ("stable", "unstable", "stable")


@pytest.mark.parametrize(("label", "moments", "omega", "regime"), GENERAL, ids=GENERAL_IDS)
def test_regime_from_the_sign_of_delta2(label, moments, omega, regime):
    i, _, g2, t2 = exact_invariants(moments, omega)
    d2 = g2 - t2 * sorted(i)[1]
    expected = "about_largest_axis" if d2 > 0 else "about_smallest_axis"
    assert regime in (None, expected)
    assert ph.analyze(moments, omega).regime == expected


@pytest.mark.parametrize(("label", "moments", "omega", "regime"), GENERAL, ids=GENERAL_IDS)
def test_period_against_mpmath(label, moments, omega, regime):
    a = ph.analyze(moments, omega)
    p = exact_period(moments, omega)
    with mp.workdps(80):
        c = motion_constants(moments, omega)  # the Taylor reference's own closed form
        assert abs(c["period"] - p) <= mp.mpf(10) ** -30 * p
    err = abs(a.period - float(p)) / float(p)
    assert err <= 1e-14, f"{label}: period {a.period!r}, mpmath {mp.nstr(p, 20)}: rel {err:.2e}"
    # The flip interval is half the period where the body turns over, else None.
    assert a.turns_over == turns_over_exact(moments, omega), label
    if a.turns_over:
        assert a.flip_interval == pytest.approx(a.period / 2, rel=4 * EPS)
    else:
        assert a.flip_interval is None and a.nutation_angle is not None


SPECIAL = [
    (
        "separatrix",
        (2.0, 3.0, 6.0),
        (0.375, 0.5, 0.125),
        "separatrix",
        ("stable", "unstable", "stable"),
    ),
    (
        "separatrix other sign",
        (2.0, 3.0, 6.0),
        (-0.375, 0.5, 0.125),
        "separatrix",
        ("stable", "unstable", "stable"),
    ),
    (
        "steady intermediate",
        (1.0, 2.0, 3.0),
        (0.0, 0.7, 0.0),
        "steady_intermediate",
        ("stable", "unstable", "stable"),
    ),
    ("rest", (1.0, 2.0, 3.0), (0.0, 0.0, 0.0), "rest", ("stable", "unstable", "stable")),
    (
        "oblate symmetric",
        (2.0, 2.0, 3.0),
        (0.3, -0.4, 0.5),
        "symmetric",
        ("neutral", "neutral", "stable"),
    ),
    (
        "prolate symmetric",
        (2.0, 3.0, 3.0),
        (0.5, 0.3, -0.4),
        "symmetric",
        ("stable", "neutral", "neutral"),
    ),
    ("sphere", (1.0, 1.0, 1.0), (0.3, -0.4, 0.5), "spherical", ("neutral", "neutral", "neutral")),
]


@pytest.mark.parametrize(
    ("label", "moments", "omega", "regime", "stability"), SPECIAL, ids=[s[0] for s in SPECIAL]
)
def test_special_regimes(label, moments, omega, regime, stability):
    a = ph.analyze(moments, omega)
    assert a.regime == regime
    assert a.axis_stability == stability
    if regime in ("separatrix", "steady_intermediate", "rest", "spherical"):
        assert a.period is None and a.flip_interval is None
    if regime == "separatrix":
        i, _, g2, t2 = exact_invariants(moments, omega)
        assert g2 == t2 * sorted(i)[1]
    _, _, g2, t2 = exact_invariants(moments, omega)
    assert abs(a.energy - float(t2 / 2)) <= 4 * EPS * float(t2 / 2)


def test_body_in_non_principal_axes():
    """A rotated box: analysed in its (ascending) principal axes."""
    body = ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)).rotated(Rotation.from_rotvec([0.3, -0.5, 0.7]))
    omega = np.array([0.4, -0.9, 0.25])
    a = ph.analyze(body, omega)
    inertia = body.inertia
    energy = 0.5 * omega @ inertia @ omega
    norm = np.linalg.norm(inertia @ omega)
    assert abs(a.energy - energy) <= 1e-14 * energy
    assert abs(a.angular_momentum_norm - norm) <= 1e-14 * norm
    np.testing.assert_allclose(a.moments, np.linalg.eigvalsh(inertia), rtol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(a.omega), np.linalg.norm(omega), rtol=1e-14)
    # the period from the principal moments and the principal-axes omega
    np.testing.assert_allclose(0.5 * np.sum(a.moments * a.omega**2), energy, rtol=1e-14)
    p = exact_period(a.moments, a.omega)
    assert abs(a.period - float(p)) <= 1e-13 * float(p)


# ---------------------------------------------------------------------------------------------
# Flip interval observed in an independent integration
# ---------------------------------------------------------------------------------------------


@functools.cache
def _crossings(moments, omega, component, t_end):
    event = lambda t, w: w[component]  # noqa: E731
    sol = solve_ivp(
        euler_rhs(moments),
        (0.0, t_end),
        omega,
        method="DOP853",
        rtol=1e-12,
        atol=1e-14 * max(abs(x) for x in omega),
        events=event,
    )
    return sol.t_events[0]


FLIPS = [GENERAL[0], GENERAL[1], GENERAL[3], GENERAL[5], GENERAL[2]]


@pytest.mark.parametrize(("label", "moments", "omega", "regime"), FLIPS, ids=[f[0] for f in FLIPS])
def test_flip_interval_observed(label, moments, omega, regime):
    # The intermediate component changes sign every half period, whether the body turns over
    # (then every flip_interval) or only wobbles about the axis L circulates about.
    a = ph.analyze(moments, omega)
    mid = int(np.argsort(moments)[1])
    crossings = _crossings(tuple(moments), tuple(omega), mid, 2.6 * a.period)
    gaps = np.diff(crossings[crossings > 1e-9 * a.period])  # a start on a crossing: no gap
    assert len(gaps) >= 4, crossings
    half = a.period / 2
    assert np.max(np.abs(gaps - half)) <= 1e-8 * half, (gaps, half)
    assert a.flip_interval is None or a.flip_interval == half


#: The T-handle of I = (3, 5, 9) with L_2 = 2 (spun at 0.4 rad/s about its intermediate axis),
#: nudged more and more about the largest (L_3 = e) or the smallest (L_1 = e) axis: it turns
#: over up to a nudge between 1 and 1.2 either way, then wobbles about the axis L circulates
#: about.
NUDGED = [
    (f"T-handle nudged {axis} {e}", (3.0, 5.0, 9.0), w, None)
    for axis, e, w in [
        *(("L3", e, (0.0, 0.4, e / 9)) for e in (0.5, 1.0, 1.2, 1.4, 1.5, 2.0, 4.0)),
        *(("L1", e, (e / 3, 0.4, 0.0)) for e in (0.3, 0.9, 1.2, 1.4, 1.8)),
    ]
]


@pytest.mark.parametrize(
    ("label", "moments", "omega", "regime"),
    GENERAL + NUDGED,
    ids=GENERAL_IDS + [n[0] for n in NUDGED],
)
def test_turns_over_when_l_dwells_near_the_intermediate_axis(label, moments, omega, regime):
    # Observed in an independent integration (scipy's DOP853 over one period): the fraction of
    # the time L lies within 45 degrees of either end of the intermediate axis, against 1/2.
    a = ph.analyze(moments, omega)
    order = np.argsort(moments)
    m = np.asarray(moments, dtype=float)[order]
    w0 = np.asarray(omega, dtype=float)[order]
    sol = solve_ivp(
        euler_rhs(tuple(m)),
        (0.0, a.period),
        w0,
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        dense_output=True,
    )
    w = sol.sol(np.linspace(0.0, a.period, 200_001)[:-1])
    big_l = m[:, None] * w
    near = np.abs(big_l[1]) >= 2**-0.5 * np.linalg.norm(big_l, axis=0)
    fraction = float(np.mean(near))
    if abs(fraction - 0.5) > 1e-3:  # not at the boundary itself
        assert a.turns_over == (fraction > 0.5), (label, fraction)
    if a.turns_over:
        # Both ends of axis 2: L_2 reverses within the period.
        assert big_l[1].max() > 0 > big_l[1].min()
        assert "turns over every" in a.description and "axis 2" in a.description


def test_a_stable_spin_about_the_smallest_axis_does_not_flip():
    # A box 0.1 x 0.2 x 0.5 spun at 10 rad/s about its long axis (the smallest moment): analyze
    # once gave flip_interval=0.566 and "flip interval" printed for it.
    box = ph.Body.cuboid(1.0, [0.1, 0.2, 0.5])
    a = ph.analyze(box, [0.05, 0.05, 10.0])
    assert a.regime == "about_smallest_axis" and a.spin_axis == 0
    assert a.flip_interval is None and not a.turns_over
    assert a.nutation_angle is not None and np.degrees(a.nutation_angle[1]) < 3
    assert a.description.startswith("Spun about axis 1 (I1, the smallest moment: stable)")
    assert "stable spin" in a.description and "turns over" not in a.description


@pytest.mark.parametrize(
    ("moments", "omega", "words"),
    [
        ((1.0, 2.0, 3.0), (0.0, 0.0, 0.0), "At rest."),
        ((2.0, 2.0, 2.0), (1.0, 0.0, 0.0), "A spherical body"),
        ((1.0, 1.0, 2.0), (0.1, 0.0, 1.0), "a symmetric top"),
        ((1.0, 2.0, 3.0), (0.0, 1.0, 0.0), "a steady rotation"),
        ((2.0, 3.0, 6.0), (0.375, 0.5, 0.125), "on the separatrix"),
        ((3.0, 5.0, 9.0), (0.0, 0.4, 0.01 / 9), "turns over every 59.06 s"),
    ],
)
def test_each_regime_is_described(moments, omega, words):
    assert words in ph.analyze(moments, omega).description


# ---------------------------------------------------------------------------------------------
# Symmetric top: the precession rate of omega in the body
# ---------------------------------------------------------------------------------------------

SYMMETRIC = [
    ("oblate (2,2,3)", (2.0, 2.0, 3.0), (0.3, -0.4, 0.5), 2),
    ("prolate (2,3,3)", (2.0, 3.0, 3.0), (0.5, 0.3, -0.4), 0),
    ("oblate, spin negative", (2.0, 2.0, 3.0), (0.3, -0.4, -0.5), 2),
    ("unsorted (3,2,2)", (3.0, 2.0, 2.0), (0.5, 0.3, -0.4), 0),
]


@pytest.mark.parametrize(
    ("label", "moments", "omega", "s"), SYMMETRIC, ids=[s[0] for s in SYMMETRIC]
)
def test_symmetric_precession_rate(label, moments, omega, s):
    a = ph.analyze(moments, omega)
    assert a.regime == "symmetric"
    it = moments[(s + 1) % 3]
    expected = omega[s] * (moments[s] - it) / it  # Omega = w_s (I_s - I_t) / I_t
    assert a.precession_rate_body == pytest.approx(expected, rel=4 * EPS)
    # observed: the angle of (w_a, w_b), (s, a, b) cyclic, turns at Omega
    t_end = 30.0
    times = np.linspace(0.0, t_end, 601)
    sol = solve_ivp(
        euler_rhs(moments),
        (0.0, t_end),
        omega,
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        t_eval=times,
    )
    wa, wb = sol.y[(s + 1) % 3], sol.y[(s + 2) % 3]
    angle = np.unwrap(np.arctan2(wb, wa))
    rate = (angle[-1] - angle[0]) / t_end
    assert abs(rate - a.precession_rate_body) <= 1e-9 * abs(rate), (rate, a.precession_rate_body)
    assert a.period == pytest.approx(2 * math.pi / abs(expected), rel=1e-14)


# ---------------------------------------------------------------------------------------------
# Linearised motion near each axis
# ---------------------------------------------------------------------------------------------


def test_linearized_oscillation_near_the_largest_axis():
    moments = (1.0, 2.0, 3.0)
    eps = 1e-6
    omega = (eps, eps, 1.0)
    a = ph.analyze(moments, omega)
    lin = a.linearized
    assert lin["axis"] == 2 and lin["kind"] == "oscillation"
    omega1 = omega[2] * (moments[2] - moments[1]) / moments[0]
    omega2 = omega[2] * (moments[2] - moments[0]) / moments[1]
    assert lin["rate"] == pytest.approx(math.sqrt(omega1 * omega2), rel=4 * EPS)
    crossings = _crossings(moments, omega, 0, 40.0)
    observed = math.pi / np.mean(np.diff(crossings))
    assert abs(observed - lin["rate"]) <= 1e-7 * lin["rate"], (observed, lin["rate"])
    # and the exact period agrees with the linear one to O(eps^2)
    assert abs(a.period - 2 * math.pi / lin["rate"]) <= 1e-9 * a.period


def test_linearized_oscillation_near_the_smallest_axis():
    moments = (1.0, 2.0, 3.0)
    eps = 1e-6
    omega = (-1.5, eps, -eps)
    lin = ph.analyze(moments, omega).linearized
    assert lin["axis"] == 0 and lin["kind"] == "oscillation"
    w = omega[0]
    expected = math.sqrt(
        (w * (moments[0] - moments[2]) / moments[1]) * (w * (moments[0] - moments[1]) / moments[2])
    )
    assert lin["rate"] == pytest.approx(expected, rel=4 * EPS)
    crossings = _crossings(moments, omega, 1, 40.0)
    observed = math.pi / np.mean(np.diff(crossings))
    assert abs(observed - lin["rate"]) <= 1e-7 * lin["rate"], (observed, lin["rate"])


@pytest.mark.parametrize("w2", [1.0, -0.7])
def test_linearized_growth_near_the_intermediate_axis(w2):
    moments = (1.0, 2.0, 3.0)
    # w1' = -A w3, w3' = -B w1 with A = w2 (I3 - I2)/I1, B = w2 (I2 - I1)/I3: growth sqrt(A B)
    # along the unstable eigenvector w3 = -s w1 / A
    big_a = w2 * (moments[2] - moments[1]) / moments[0]
    big_b = w2 * (moments[1] - moments[0]) / moments[2]
    s = math.sqrt(big_a * big_b)
    eps = 1e-9 * abs(w2)
    omega = (eps, w2, -s * eps / big_a)
    lin = ph.analyze(moments, omega).linearized
    assert lin["axis"] == 1 and lin["kind"] == "growth"
    assert lin["rate"] == pytest.approx(s, rel=4 * EPS)
    t_end = math.log(1e3) / s  # grows 1000-fold, still linear (1e-6 of w2)
    sol = solve_ivp(
        euler_rhs(moments), (0.0, t_end), omega, method="DOP853", rtol=1e-13, atol=1e-22
    )
    observed = math.log(abs(sol.y[0, -1]) / eps) / t_end
    assert abs(observed - lin["rate"]) <= 1e-6 * lin["rate"], (observed, lin["rate"])
    assert ph.analyze(moments, omega).regime in ("about_smallest_axis", "about_largest_axis")


def test_linearized_uses_the_principal_axes_of_a_rotated_body():
    """A box turned by 90 degrees about z: its x spin is a spin about a principal axis."""
    box = ph.Body.cuboid(1.0, (1.0, 2.0, 3.0))  # moments (13, 10, 5)/12 about x, y, z
    turned = box.rotated(Rotation.from_rotvec([0.0, 0.0, np.pi / 2]))
    omega_body = turned.inertia  # use the body frame: spin about the axis of the largest moment
    k = int(np.argmax(np.diag(omega_body)))
    spin = np.zeros(3)
    spin[k] = 2.0
    a = ph.analyze(turned, spin)
    assert a.linearized["axis"] == 2 and a.linearized["kind"] == "oscillation"
    m = np.array([5.0, 10.0, 13.0]) / 12
    np.testing.assert_allclose(a.moments, m, rtol=1e-14)
    expected = 2.0 * math.sqrt((m[2] - m[1]) / m[0] * (m[2] - m[0]) / m[1])
    assert a.linearized["rate"] == pytest.approx(expected, rel=1e-13)


def test_linearized_rate_of_extreme_moments_does_not_overflow():
    """Two inputs the fuzz found: the product Omega_a Omega_b overflowed (a RuntimeWarning and
    inf) where the rate itself, |w| (I - Ia) / Ia for a spin about a symmetry axis, or 0 when the
    spin axis shares its moment, is a double."""
    a = ph.analyze([1.0, 1.0, 1.340781e154], [0.0, 0.0, 1.0])
    assert a.linearized["kind"] == "oscillation"
    assert a.linearized["rate"] == pytest.approx(1.340781e154 - 1.0, rel=4 * EPS)
    a = ph.analyze([1.0, 2.568133e307, 1.0], [0.0, 0.0, 7.0])
    assert a.linearized == {"axis": 1, "kind": "oscillation", "rate": 0.0}


@pytest.mark.parametrize("w", [1e-200, 1e-160, 1e-100, 1.0, 1e150])
def test_the_linearized_rate_scales_with_omega(w):
    """About the middle axis the rate is |w| sqrt((I3 - I2)(I2 - I1) / (I1 I3)): w^2 times the
    ratios underflowed below w = 1e-154 (rate 0 at 1e-200, "growth at rate 0"; 2.4e-4 off at
    1e-160)."""
    moments = (1.0, 2.0, 3.0)
    linearized = ph.analyze(moments, (0.0, w, 0.0)).linearized
    assert linearized["kind"] == "growth"
    exact = w * math.sqrt((3.0 - 2.0) * (2.0 - 1.0) / (1.0 * 3.0))
    assert linearized["rate"] == pytest.approx(exact, rel=4 * np.finfo(float).eps)
