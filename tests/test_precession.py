"""Precession and nutation seen from space (polhode.analyze) against independent references.

- a symmetric top: ``|L| / I_t`` and ``arccos(I_s w_s / |L|)`` (Landau-Lifshitz par. 33), written
  here;
- three distinct moments: the mean over one period of the precession rate of the axis ``p`` the
  motion circulates about, ``phi' = G (m_a^2/I_a + m_b^2/I_b) / (m_a^2 + m_b^2)`` (z-x-z Euler
  angles with space z along L and body z along p), integrated by mpmath's quadrature over the
  Jacobi elliptic solution at 30 digits (not the Rust form: another polar axis, no R_J), and the
  extremes of the nutation angle from the invariants (``m_p^2 = I_p Delta_j / (I_p - I_j)`` where
  the third component vanishes);
- rates fitted from trajectories: the azimuth about L of the axis p, unwrapped over many periods,
  from ``simulate`` (dop853, and the exact solution) and from scipy's DOP853.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import polhode as ph
from reference import euler_rhs, qmul
from reference_motion import turns_over_exact

EPS = float(np.finfo(float).eps)

SYMMETRIC = [
    ("oblate", (2.0, 2.0, 3.0), (0.3, -0.4, 0.5), 2),
    ("prolate", (2.0, 3.0, 3.0), (0.5, 0.3, -0.4), 0),
    ("oblate, spin negative", (2.0, 2.0, 3.0), (0.3, -0.4, -0.5), 2),
    ("prolate, spin negative", (2.0, 3.0, 3.0), (-0.5, 0.3, -0.4), 0),
    ("near the axis", (1.0, 1.0, 1.5), (1e-5, 0.0, 2.0), 2),
    ("across the axis", (1.0, 1.0, 1.5), (1.0, 0.5, 0.0), 2),
]


@pytest.mark.parametrize(("label", "moments", "omega", "s"), SYMMETRIC,
                         ids=[c[0] for c in SYMMETRIC])
def test_symmetric_top_against_the_closed_form(label, moments, omega, s):
    a = ph.analyze(moments, omega)
    assert a.regime == "symmetric"
    # analyze sorts the moments: the symmetry axis is 0 (prolate) or 2 (oblate) there too.
    i_s = moments[s]
    i_t = moments[(s + 1) % 3]
    momentum = math.sqrt(sum((i * w) ** 2 for i, w in zip(moments, omega, strict=True)))
    assert a.precession_rate_space == pytest.approx(momentum / i_t, rel=4 * EPS)
    across = math.hypot(i_t * omega[(s + 1) % 3], i_t * omega[(s + 2) % 3])
    theta = math.atan2(across, i_s * omega[s])  # arccos(I_s w_s / |L|), accurate near 0
    assert a.nutation_angle[0] == a.nutation_angle[1]
    assert a.nutation_angle[0] == pytest.approx(theta, rel=8 * EPS, abs=8 * EPS)


def _reference(moments, omega, dps=30):
    """(mean precession rate about L, (min, max) nutation angle) of the axis p that L circulates
    about, moments ascending and distinct, by mpmath from the textbook solution."""
    with mp.workdps(dps):
        i = [mp.mpf(float(x)) for x in moments]
        w = [mp.mpf(float(x)) for x in omega]
        g2 = sum((a * b) ** 2 for a, b in zip(i, w, strict=True))
        t2 = sum(a * b * b for a, b in zip(i, w, strict=True))
        g = mp.sqrt(g2)
        delta = [g2 - t2 * x for x in i]  # G^2 - 2T I_j
        p, a = (2, 0) if delta[1] > 0 else (0, 2)
        ip, ia, ib = i[p], i[a], i[1]
        # m_a = B_a cn u, m_b = B_b sn u, m_p = B_p dn u; u = lambda t (Landau-Lifshitz par. 37).
        ba2 = ia * (-delta[p]) / (ia - ip)
        bb2 = ib * (-delta[p]) / (ib - ip)
        bp2 = ip * delta[a] / (ip - ia)
        m = (ib - ia) * (-delta[p]) / ((ip - ib) * delta[a])
        k = mp.ellipk(m)

        def rate(u):
            sn, cn, _ = (mp.ellipfun(f, u, m=m) for f in ("sn", "cn", "dn"))
            ma2, mb2 = ba2 * cn**2, bb2 * sn**2
            return g * (ma2 / ia + mb2 / ib) / (ma2 + mb2)

        # The rate depends on sn^2 alone: its mean over a quarter period is the mean.
        mean = mp.quad(rate, [0, k]) / k
        # The extremes of m_p: where m_b = 0 (B_p) and where m_a = 0 (I_p Delta_b / (I_p - I_b)).
        cos_hi = mp.sqrt(bp2) / g
        cos_lo = mp.sqrt(ip * delta[1] / (ip - ib)) / g
        sign = 1 if w[p] > 0 else -1
        angles = sorted(float(mp.acos(sign * c)) for c in (cos_hi, cos_lo))
        return float(mean), tuple(angles), p


# Both extreme axes, and each with the evaluation's polar axis on either side (the Rust form
# takes the axis p or the other extreme one as its polar axis, by the moments).
ASYMMETRIC = [
    ("largest, (1, 2, 3)", (1.0, 2.0, 3.0), (0.2, 0.3, 1.0)),
    ("largest, (1, 1.2, 3)", (1.0, 1.2, 3.0), (0.2, 0.3, 1.0)),
    ("smallest, (1, 2, 3)", (1.0, 2.0, 3.0), (1.0, 0.3, 0.2)),
    ("smallest, (1, 1.2, 3)", (1.0, 1.2, 3.0), (1.0, 0.1, 0.05)),
    ("largest, spin negative", (1.0, 2.0, 3.0), (0.2, -0.3, -1.0)),
    ("smallest, spin negative", (1.0, 2.0, 3.0), (-1.0, 0.3, 0.2)),
    ("near the separatrix", (1.0, 2.0, 3.0), (0.5, 1.0, 0.4)),
    ("nearly symmetric", (1.0, 1.0 + 1e-6, 2.0), (0.3, 0.1, 1.0)),
    ("a thin rod about its axis", (1e-3, 1.0, 1.001), (1.0, 1e-4, 2e-4)),
    ("hlw benchmark moments", (0.6, 0.8, 1.0), (0.4, 0.9, 0.1)),
]


@pytest.mark.parametrize(("label", "moments", "omega"), ASYMMETRIC,
                         ids=[c[0] for c in ASYMMETRIC])
def test_asymmetric_body_against_mpmath(label, moments, omega):
    a = ph.analyze(moments, omega)
    mean, angles, p = _reference(moments, omega)
    assert a.regime == ("about_largest_axis" if p == 2 else "about_smallest_axis")
    # The rate comes from double-double complete integrals (cel) and the period: a few eps,
    # times the cancellation between G/I_x and the 2 pi / P of the polar axis (I_3 / I_1 at
    # most, for the rod).
    scale = max(moments) / min(moments)
    assert a.precession_rate_space == pytest.approx(mean, rel=64 * EPS * scale)
    assert a.precession_rate_space > 0
    # The nutation angles from the amplitudes: eps-accurate atan2s of B_1, B_2, B_3 and k';
    # none where the body turns over (the axis tumbles: analyze's nutation_angle is None
    # there), as the exact criterion says of "near the separatrix" and the HLW moments.
    if turns_over_exact(moments, omega):
        assert a.turns_over and a.nutation_angle is None, label
        assert label in ("near the separatrix", "hlw benchmark moments"), label
        return
    np.testing.assert_allclose(a.nutation_angle, angles, rtol=1e-13, atol=1e-13)


def _azimuth(quaternion, axis, l_space):
    """The azimuth about L of the body axis ``axis`` along a trajectory, unwrapped."""
    ell = l_space / np.linalg.norm(l_space)
    u = np.cross(ell, [1.0, 0.0, 0.0] if abs(ell[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(ell, u)
    a = Rotation.from_quat(quaternion).apply(np.eye(3)[axis])
    return np.unwrap(np.arctan2(a @ v, a @ u))


def _scipy_orientation(moments, omega, times):
    """The orientation (x, y, z, w) by scipy's DOP853 at rtol 1e-12, independent of polhode."""
    rhs_w = euler_rhs(moments)

    def rhs(t, y):
        dq = 0.5 * qmul(y[3:], np.array([y[0], y[1], y[2], 0.0]))
        return np.concatenate([rhs_w(t, y[:3]), dq])

    y0 = np.concatenate([omega, [0.0, 0.0, 0.0, 1.0]])
    sol = solve_ivp(rhs, (0.0, times[-1]), y0, t_eval=times, method="DOP853", rtol=1e-12,
                    atol=1e-14)
    q = sol.y[3:].T
    return q / np.linalg.norm(q, axis=1)[:, None]


FITTED = [c for c in ASYMMETRIC if "rod" not in c[0]] + [c[:3] for c in SYMMETRIC[:2]]


@pytest.mark.parametrize(("label", "moments", "omega"), FITTED, ids=[c[0] for c in FITTED])
def test_rate_fitted_from_trajectories(label, moments, omega):
    """The azimuth about L of the axis the motion circulates about, unwrapped over 10 periods
    of omega (200 samples a period), from simulate (dop853 at rtol 1e-12, and the exact
    solution) and, for the first cases, from scipy's DOP853."""
    a = ph.analyze(moments, omega)
    if a.regime == "symmetric":
        axis = 0 if moments[0] != moments[1] else 2
    else:
        axis = 2 if a.regime == "about_largest_axis" else 0
    periods = 10
    times = np.linspace(0.0, periods * a.period, periods * 200 + 1)
    l_space = np.asarray(moments) * np.asarray(omega)
    runs = {
        method: ph.simulate(moments, omega, times, method=method, rtol=1e-12).quaternion
        for method in ("dop853", "exact")
    }
    if label in [c[0] for c in FITTED[:4]]:
        runs["scipy"] = _scipy_orientation(moments, omega, times)
    for name, quaternion in runs.items():
        azimuth = _azimuth(quaternion, axis, l_space)
        # Sampled at whole periods the wobble within a period cancels: the net turn over 10
        # periods is the mean rate, to the integration's error (rtol 1e-12; measured below
        # 1.5e-12 relative for dop853 and scipy, 1e-15 for the exact solution).
        net = (azimuth[-1] - azimuth[0]) / times[-1]
        assert net == pytest.approx(a.precession_rate_space, rel=1e-11), name
        # A least-squares slope: a zero-mean periodic wobble of amplitude A moves it by at most
        # sqrt(12) A / (n P) (Cauchy-Schwarz, n P the span); A stays below 0.05 rad here (the
        # largest slope error measured is 0.022 rad / (n P)).
        slope = np.polyfit(times, azimuth, 1)[0]
        assert abs(slope - a.precession_rate_space) <= 0.2 / times[-1], (name, slope)


@pytest.mark.parametrize("axis", [0, 2])
def test_steady_rotation_is_the_limit_of_nearby_motions(axis):
    moments = (1.0, 2.0, 3.0)
    omega = np.zeros(3)
    omega[axis] = 1.5
    steady = ph.analyze(moments, omega)
    assert steady.nutation_angle == (0.0, 0.0)
    near = omega.copy()
    near[1] = 1e-7
    nearby = ph.analyze(moments, near)
    # The rate depends on the amplitude quadratically: 1e-14 relative at 1e-7.
    assert steady.precession_rate_space == pytest.approx(nearby.precession_rate_space, rel=1e-12)
    assert nearby.nutation_angle[1] < 1e-6
    flipped = ph.analyze(moments, -omega)
    assert flipped.nutation_angle == (math.pi, math.pi)
    assert flipped.precession_rate_space == steady.precession_rate_space


def test_no_precession_where_the_motion_does_not_circulate():
    # Rest, steady rotation about the intermediate axis, the separatrix (I = (3, 4, 6),
    # w = (2, w2, 1): Delta_2 = 3 * 4 * (3 - 4) + 6 * 1 * (6 - 4) = 0 exactly).
    for moments, omega, regime in [
        ((1.0, 2.0, 4.0), (0.0, 0.0, 0.0), "rest"),
        ((1.0, 2.0, 4.0), (0.0, 1.0, 0.0), "steady_intermediate"),
        ((3.0, 4.0, 6.0), (2.0, 0.7, 1.0), "separatrix"),
    ]:
        a = ph.analyze(moments, omega)
        assert a.regime == regime
        assert a.precession_rate_space is None and a.nutation_angle is None, regime
    # A sphere turns about L = I w at |w|; no axis is singled out to nutate.
    sphere = ph.analyze((2.0, 2.0, 2.0), (0.3, 0.4, 1.2))
    assert sphere.precession_rate_space == pytest.approx(1.3, rel=4 * EPS)
    assert sphere.nutation_angle is None
