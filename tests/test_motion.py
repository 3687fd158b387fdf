"""polhode.simulate against independent references: accuracy, conservation, orders, batches.

References (nothing here compares polhode with itself):
- ``reference_motion`` (Taylor series in exact arithmetic, plus the exact quasi-periodicity of
  free rotation for long times) for the torque-free motion;
- scipy's DOP853 at rtol 1e-13 on the tensor form of Euler's equations ``I w' + w x I w = 0``
  (and ``q' = q (x) (0, w) / 2``) for bodies in non-principal axes;
- conservation laws the method guarantees (|L| and L in space for the Lie-Poisson splitting,
  T and |L| for the implicit midpoint rule);
- convergence orders (error ratio when halving dt).

Accuracy targets: "exact" within 1e-13 relative in omega and in the attitude
(quaternion up to sign) up to 100 periods, and an error growth of about 1e-15 per period beyond
(checked at 1e3..1e6 periods; "about" is taken as a factor 2: bound 1e-13 + 2e-15 N).
"""

from __future__ import annotations

import functools
import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

import polhode as ph
from reference import qmul
from reference_motion import midpoint_step_mp, motion_constants, reference_motion, rel_errors

EPS = float(np.finfo(float).eps)
Q_ID = (0.0, 0.0, 0.0, 1.0)
_q = np.array([0.1, -0.2, 0.3, 0.9])
Q0 = tuple(float(x) for x in _q / np.linalg.norm(_q))

EXACT_SHORT = 1e-13  # relative, up to 100 periods
EXACT_GROWTH = 2e-15  # per period beyond ("~1e-15", factor 2 allowed)
LONG_PERIODS = (1e3, 1e4, 1e5, 1e6)
FIXED = [("splitting", 2), ("splitting", 4), ("splitting", 6), ("midpoint", 2), ("rk4", 4)]


# ---------------------------------------------------------------------------------------------
# References (cached: the Taylor reference costs 0.05-1 s a call)
# ---------------------------------------------------------------------------------------------


@functools.cache
def _reference(moments, omega0, quat0, times, dps=20, method="periodic"):
    w, q = reference_motion(moments, omega0, quat0, np.array(times), dps=dps, method=method)
    w.setflags(write=False)
    q.setflags(write=False)
    return w, q


def reference(moments, omega0, quat0, times, dps=20, method="periodic"):
    return _reference(
        tuple(map(float, moments)),
        tuple(map(float, omega0)),
        tuple(map(float, quat0)),
        tuple(map(float, times)),
        dps,
        method,
    )


@functools.cache
def _period(moments, omega0):
    with mp.workdps(80):  # K(m) near m = 1 costs log10(1 / (1 - m)) digits
        return float(motion_constants(moments, omega0)["period"])


def period(moments, omega0) -> float:
    return _period(tuple(map(float, moments)), tuple(map(float, omega0)))


def exact_times(moments, omega0):
    """Output times: fractions of a period up to 100 periods, then 1e3..1e6 periods."""
    p = period(moments, omega0)
    short = np.array([0.0, 0.37, 1.0, 3.61, 10.3, 57.7, 99.13, 100.0]) * p
    long = np.array(LONG_PERIODS) * p + 0.3 * p
    return np.concatenate([short, long]), p


def exact_bound(t, p):
    n = t / p
    return np.where(n <= 100.0 + 1e-9, EXACT_SHORT, EXACT_SHORT + EXACT_GROWTH * n)


def check_exact(moments, omega0, quat0, label):
    times, p = exact_times(moments, omega0)
    w_ref, q_ref = reference(moments, omega0, quat0, times)
    sol = ph.simulate(moments, omega0, times, orientation0=quat0, method="exact")
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    bound = exact_bound(times, p)
    bad = (ew > bound) | (eq > bound)
    table = "\n".join(
        f"  t = {t / p:9.2f} periods: omega {a:.2e}, quaternion {b:.2e} (bound {c:.1e})"
        for t, a, b, c in zip(times, ew, eq, bound, strict=True)
    )
    assert not bad.any(), f"{label}: exact solution off the reference:\n{table}"


# ---------------------------------------------------------------------------------------------
# exact: the closed form against the Taylor reference
# ---------------------------------------------------------------------------------------------

GENERIC = [
    ("I=(1,2,3) about axis 3", (1.0, 2.0, 3.0), (0.3, -0.5, 0.8)),
    ("I=(1,2,3) about axis 1", (1.0, 2.0, 3.0), (0.9, 0.2, -0.1)),
    ("unsorted I=(3,1,2)", (3.0, 1.0, 2.0), (-0.2, 0.7, 0.4)),
    ("unsorted I=(2,3,1)", (2.0, 3.0, 1.0), (0.5, 0.1, -0.6)),
    ("small body I~1e-3", (1e-3, 2e-3, 2.5e-3), (100.0, -50.0, 30.0)),
    ("large body I~1e6, slow", (4e6, 5e6, 7e6), (1e-3, 2e-3, -4e-4)),
]


@pytest.mark.parametrize(("label", "moments", "omega0"), GENERIC, ids=[g[0] for g in GENERIC])
def test_exact_matches_reference(label, moments, omega0):
    check_exact(moments, omega0, Q0, label)


SIGNS = [(a, b, c) for a in (1, -1) for b in (1, -1) for c in (1, -1)]


@pytest.mark.parametrize("signs", SIGNS, ids=[str(s) for s in SIGNS])
@pytest.mark.parametrize("regime", ["axis3", "axis1"])
def test_exact_every_sign_of_every_component(signs, regime):
    """Both signs of each component, in both regimes (sign errors in the published closed
    forms are the classical failure)."""
    base = (0.3, 0.5, 0.8) if regime == "axis3" else (0.9, 0.4, 0.2)
    omega0 = tuple(s * w for s, w in zip(signs, base, strict=True))
    moments = (1.0, 2.0, 3.0)
    p = period(moments, omega0)
    times = np.array([0.0, 0.21, 0.5, 0.77, 1.0, 13.4]) * p
    w_ref, q_ref = reference(moments, omega0, Q0, times)
    sol = ph.simulate(moments, omega0, times, orientation0=Q0, method="exact")
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    assert ew.max() <= EXACT_SHORT and eq.max() <= EXACT_SHORT, (ew, eq)


def test_exact_with_t0_and_repeated_times():
    """t0 shifts the origin; repeated output times give repeated states; t = t0 gives the
    initial state (times chosen so that t - t0 is exact)."""
    moments, omega0 = (1.0, 2.0, 3.0), (0.3, -0.5, 0.8)
    t0 = 2.5
    times = np.array([2.5, 3.0, 3.0, 7.25, 20.5, 100.0])
    w_ref, q_ref = reference(moments, omega0, Q0, times - t0)
    sol = ph.simulate(moments, omega0, times, orientation0=Q0, method="exact", t0=t0)
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    assert ew.max() <= EXACT_SHORT and eq.max() <= EXACT_SHORT, (ew, eq)
    assert np.array_equal(sol.omega[1], sol.omega[2])
    # The integrators return the initial state itself at t = t0 (documented in the core).
    for method, order in FIXED:
        fixed = ph.simulate(
            moments, omega0, times[:3], orientation0=Q0, method=method, dt=0.1, order=order, t0=t0
        )
        assert np.array_equal(fixed.omega[0], omega0), method
        assert np.array_equal(fixed.omega[1], fixed.omega[2]), method


@pytest.mark.parametrize("t0", [1.7e9, 1e10, 1e14, -3e12])
@pytest.mark.parametrize("method", ["dop853", "rk4", "splitting", "midpoint"])
def test_a_late_start_integrates_as_a_start_at_zero(method, t0):
    """Torque-free motion does not depend on the time origin: from t0 (a Unix time, say) to
    output times t, every method gives the numbers of a run from 0 to t - t0, bit for bit.
    dop853 summed its time as t + h, losing up to half an ulp of t per step: 6.6e-8 off after
    two time units at t0 = 1e10, and steps refused as too small at 1e14. The exact solution at
    t - t0 is the reference for the accuracy."""
    moments, omega0 = (1.0, 2.0, 3.0), (0.3, 1.0, 0.2)
    times = t0 + np.linspace(0.0, 2.0, 9)
    kw = {} if method == "dop853" else {"dt": 0.01}
    late = ph.simulate(moments, omega0, times, t0=t0, method=method, **kw)
    early = ph.simulate(moments, omega0, times - t0, method=method, **kw)
    assert np.array_equal(late.omega, early.omega)
    assert np.array_equal(late.quaternion, early.quaternion)
    exact = ph.simulate(moments, omega0, times - t0, method="exact")
    bound = 1e-9 if method == "dop853" else 1e-6
    assert np.abs(late.omega - exact.omega).max() <= bound


def test_end_time_scalar_gives_t0_to_end():
    moments, omega0 = (1.0, 2.0, 3.0), (0.3, -0.5, 0.8)
    sol = ph.simulate(moments, omega0, 4.0, orientation0=Q0)
    # Evenly spaced from t0 to the end (the exact solution; how many: test_sampling.py).
    np.testing.assert_array_equal(sol.t, np.linspace(0.0, 4.0, sol.t.size))
    assert sol.t.size >= 49
    w_ref, q_ref = reference(moments, omega0, Q0, sol.t)
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    assert ew.max() <= EXACT_SHORT and eq.max() <= EXACT_SHORT, (ew, eq)
    assert sol.stats["method"] == "exact"  # auto without torque


@pytest.mark.parametrize(
    "orientation0",
    [
        Rotation.from_quat(Q0),
        Rotation.from_quat(Q0).as_matrix(),
        np.array(Q0),
        -np.array(Q0),  # the same rotation
        3.0 * np.array(Q0),  # normalised on input
    ],
    ids=["Rotation", "matrix", "quaternion", "minus-quaternion", "unnormalised"],
)
def test_orientation0_forms(orientation0):
    moments, omega0 = (1.0, 2.0, 3.0), (0.3, -0.5, 0.8)
    times = np.array([0.0, 1.5, 9.0])
    w_ref, q_ref = reference(moments, omega0, Q0, times)
    sol = ph.simulate(moments, omega0, times, orientation0=orientation0)
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    assert ew.max() <= EXACT_SHORT and eq.max() <= 4 * EXACT_SHORT, (ew, eq)
    r_ref = Rotation.from_quat(q_ref).as_matrix()
    r = sol.orientation.as_matrix()
    assert np.max(np.abs(r - r_ref)) <= 1e-13


def test_trajectory_fields_are_consistent_with_the_reference():
    """energy, angular_momentum (space), angular_momentum_body against the reference state."""
    moments, omega0 = np.array([1.0, 2.0, 3.0]), (0.3, -0.5, 0.8)
    times = np.linspace(0.0, 30.0, 7)
    w_ref, q_ref = reference(moments, omega0, Q0, times)
    sol = ph.simulate(moments, omega0, times, orientation0=Q0)
    l_body = w_ref * moments
    l_space = Rotation.from_quat(q_ref).apply(l_body)
    energy = 0.5 * np.sum(w_ref * l_body, axis=1)
    scale = np.linalg.norm(l_body[0])
    assert np.max(np.abs(sol.angular_momentum_body - l_body)) <= 1e-13 * scale
    assert np.max(np.abs(sol.angular_momentum_space - l_space)) <= 1e-13 * scale
    assert np.max(np.abs(sol.energy - energy)) <= 1e-13 * energy[0]
    np.testing.assert_array_equal(sol.moments, moments)
    assert sol.quaternion.shape == (7, 4) and sol.omega.shape == (7, 3)
    assert sol.omega.dtype == np.float64 and sol.quaternion.dtype == np.float64


# ---------------------------------------------------------------------------------------------
# Integrators: orders, dop853 tolerance
# ---------------------------------------------------------------------------------------------

HLW = ((2.0, 1.0, 2.0 / 3.0), (math.cos(1.1) / 2.0, 0.0, math.sin(1.1) * 1.5))
BODY123 = ((1.0, 2.0, 3.0), (0.3, -0.5, 0.8))


def _max_err(sol, w_ref, q_ref):
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    return float(max(ew.max(), eq.max()))


# (method, order, dt): dt in the asymptotic range, errors well above round-off
ORDER_CASES = [
    ("splitting", 2, 0.04),
    ("splitting", 4, 0.08),
    ("splitting", 6, 0.15),
    ("midpoint", 2, 0.04),
    ("rk4", 4, 0.08),
]


@pytest.mark.parametrize("body", ["HLW", "I=(1,2,3)"])
@pytest.mark.parametrize(
    ("method", "order", "dt"), ORDER_CASES, ids=[f"{m}{o}" for m, o, _ in ORDER_CASES]
)
def test_convergence_order(body, method, order, dt):
    """Error ratio when halving dt is 2^p (omega and attitude, at t = 10)."""
    moments, omega0 = HLW if body == "HLW" else BODY123
    times = np.array([0.0, 3.0, 10.0])
    w_ref, q_ref = reference(moments, omega0, Q0, times, method="direct")
    errors = []
    for h in (dt, dt / 2, dt / 4):
        sol = ph.simulate(moments, omega0, times, orientation0=Q0, method=method, dt=h, order=order)
        errors.append(_max_err(sol, w_ref, q_ref))
    observed = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert errors[-1] > 1e-12, f"errors {errors} at round-off: choose a larger dt"
    assert np.all(observed >= order - 0.3), (
        f"{method} order {order}: errors {errors}, observed orders {observed}"
    )


@pytest.mark.parametrize("rtol", [1e-8, 1e-10, 1e-12])
def test_dop853_meets_its_tolerance(rtol):
    moments, omega0 = HLW
    times = np.linspace(0.0, 20.0, 9)
    w_ref, q_ref = reference(moments, omega0, Q0, times, method="direct")
    sol = ph.simulate(moments, omega0, times, orientation0=Q0, method="dop853", rtol=rtol)
    err = _max_err(sol, w_ref, q_ref)
    assert err <= 100 * rtol, f"dop853 rtol={rtol}: error {err:.2e} > 100 rtol"
    assert 0 < sol.stats["steps"] <= sol.stats["evaluations"]


def test_fixed_step_methods_hit_the_output_times_exactly():
    """Output times not multiples of dt: steps are shortened, never skipped (the error stays
    at the method's level, an off-grid output would show an O(dt) error)."""
    moments, omega0 = BODY123
    times = np.array([0.0, 0.0123, 1.0, math.pi, 7.77])
    w_ref, q_ref = reference(moments, omega0, Q0, times, method="direct")
    for method, order in FIXED:
        sol = ph.simulate(
            moments, omega0, times, orientation0=Q0, method=method, dt=0.01, order=order
        )
        err = _max_err(sol, w_ref, q_ref)
        # an output off the step grid would be wrong by ~|w'| dt ~ 3e-3
        bound = 1e-4 if order == 2 else 1e-8
        assert err <= bound, f"{method}{order}: {err:.2e}"
        np.testing.assert_array_equal(sol.t, times)


# ---------------------------------------------------------------------------------------------
# Conservation over 1e6 steps
# ---------------------------------------------------------------------------------------------

LONG = dict(moments=(1.0, 2.0, 3.0), omega0=(0.3, -0.5, 0.8), dt=0.01, steps=1_000_000)


def _long_run(method, order, orientation):
    p = LONG
    times = np.linspace(0.0, p["dt"] * p["steps"], 2001)
    sol = ph.simulate(
        p["moments"],
        p["omega0"],
        times,
        orientation0=Q0,
        method=method,
        dt=p["dt"],
        order=order,
        orientation=orientation,
    )
    assert sol.stats["steps"] == p["steps"]
    assert sol.stats["wall_time"] < 10.0, f"1e6 steps took {sol.stats['wall_time']:.1f} s"
    m = np.array(p["moments"])
    w0 = np.array(p["omega0"])
    t0 = 0.5 * np.sum(m * w0 * w0)
    g0 = np.linalg.norm(m * w0)
    l0 = Rotation.from_quat(Q0).apply(m * w0)
    return sol, t0, g0, l0


def roundoff_walk(order, steps):
    """Round-off allowance of a long run: a random walk of ~5 axis rotations per Strang stage
    (1, 3 or 7 stages a step), each rounding to ~eps: eps sqrt(5 stages steps)."""
    stages = {2: 1, 4: 3, 6: 7}[order]
    return EPS * math.sqrt(5 * stages * steps)


def _tenths(err):
    k = len(err) // 10
    return float(err[:k].max()), float(err[-k:].max())


@pytest.mark.parametrize("order", [2, 4, 6])
def test_splitting_conserves_l_exactly_and_energy_without_drift(order):
    sol, t0, g0, l0 = _long_run("splitting", order, True)
    g_err = np.abs(np.linalg.norm(sol.angular_momentum_body, axis=1) - g0) / g0
    l_err = np.linalg.norm(sol.angular_momentum_space - l0, axis=1) / g0
    t_err = np.abs(sol.energy - t0) / t0
    first, last = _tenths(t_err)
    assert g_err.max() <= 1e-12, f"|L| drift {g_err.max():.2e} after 1e6 steps"
    assert l_err.max() <= 1e-12, f"L in space drift {l_err.max():.2e} after 1e6 steps"
    walk = roundoff_walk(order, LONG["steps"])
    assert last <= 2 * first + walk, (
        f"energy drifts: max |dT|/T {first:.2e} over the first tenth, {last:.2e} over the last"
        f" (allowed 2 x first + round-off walk {walk:.1e})"
    )


def test_midpoint_conserves_energy_and_l_norm():
    sol, t0, g0, _ = _long_run("midpoint", 2, False)
    g_err = np.abs(np.linalg.norm(sol.angular_momentum_body, axis=1) - g0) / g0
    t_err = np.abs(sol.energy - t0) / t0
    assert t_err.max() <= 1e-12, f"midpoint |dT|/T = {t_err.max():.2e} after 1e6 steps"
    assert g_err.max() <= 1e-12, f"midpoint |d|L||/|L| = {g_err.max():.2e} after 1e6 steps"


def test_midpoint_energy_walks_without_bias():
    """Round-off moves T in a random walk with mean zero. Over 2000 random bodies and 5e4 steps
    the mean relative change of T is within 4 standard errors of zero, and its spread is that
    of one rounding of w a step (about 0.3 eps sqrt(steps): the new w is w0 + 2 z, z the
    midpoint increment). Measured when this was written: -0.5 standard errors and 0.32. Two
    ways of getting it wrong, also measured: a Newton iteration stopped a quarter of an ulp
    short of the root (always on the same side along a motion) drifted by 11.7 standard
    errors; the midpoint rounded as w0 + k f(w_m) and doubled, three roundings a step, spread
    0.77 (and drifted by 2.1 standard errors). Same bits on every CPU: not a flaky test."""
    rng = np.random.default_rng(5)
    n, steps, dt = 2000, 50_000, 0.01
    moments = np.sort(rng.uniform(1.0, 2.0, size=(n, 3)), axis=1)
    omega0 = rng.normal(size=(n, 3))
    sol = ph.simulate(
        moments, omega0, np.array([0.0, steps * dt]), method="midpoint", dt=dt, orientation=False
    )
    t0 = 0.5 * np.sum(moments * omega0**2, axis=1)
    change = (0.5 * np.sum(moments * sol.omega[:, -1] ** 2, axis=1) - t0) / t0
    standard_error = change.std() / np.sqrt(n)
    assert abs(change.mean()) <= 4 * standard_error, (change.mean(), standard_error)
    spread = np.sqrt(np.mean(change**2)) / (EPS * np.sqrt(steps))
    assert spread <= 0.45, spread


@pytest.mark.parametrize("h", [1e-3, 0.01, 0.05, 0.2, 0.5])
def test_midpoint_step_against_its_definition(h):
    """One midpoint step against the rule's definition solved at 50 digits
    (reference_motion.midpoint_step_mp, the quaternion by a 4x4 linear solve). The steps run
    from those the integrator finishes with one Newton iteration after its fixed-point
    predictor to those too large for the predictor (k |J| > 1/4 at h = 0.5), where Newton
    starts from the Euler guess; slow bodies (|w| ~ 0.01) start at the root. The new w is
    w0 + 2 z rounded once, z the increment solved to round-off relative to itself: within half
    an ulp of |w1| plus a few eps of |w1 - w0|. A batch (the SIMD lanes) and three bodies
    alone (the scalar path)."""
    rng = np.random.default_rng(int(h * 1e4))
    n = 12
    moments = np.sort(rng.uniform(0.5, 3.0, (n, 3)), axis=1)
    moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
    omega0 = rng.normal(size=(n, 3)) * rng.choice([0.01, 1.0, 3.0], size=(n, 1))
    quat0 = Rotation.random(n, random_state=5).as_quat()
    times = np.array([0.0, h])
    batch = ph.simulate(moments, omega0, times, orientation0=quat0, method="midpoint", dt=h)
    for i in range(n):
        runs = [(batch.omega[i, -1], batch.quaternion[i, -1])]
        if i < 3:
            alone = ph.simulate(
                moments[i], omega0[i], times, orientation0=quat0[i], method="midpoint", dt=h
            )
            runs.append((alone.omega[-1], alone.quaternion[-1]))
        w_mp, q_mp = midpoint_step_mp(moments[i], omega0[i], quat0[i], h)
        w_ref = np.array([float(x) for x in w_mp])
        q_ref = np.array([float(x) for x in q_mp])
        bound = EPS * (0.5 * np.max(np.abs(w_ref)) + 4 * np.max(np.abs(w_ref - omega0[i])))
        for omega, quat in runs:
            assert np.max(np.abs(omega - w_ref)) <= bound, (i, omega - w_ref, bound)
            quat = quat if np.dot(quat, q_ref) > 0 else -quat
            assert np.max(np.abs(quat - q_ref)) <= 4 * EPS, (i, quat - q_ref)


@pytest.mark.parametrize("h", [0.01, 0.05, 0.2])
def test_torqued_midpoint_step_against_its_definition(h):
    """As test_midpoint_step_against_its_definition, under a constant torque in body axes (the
    torqued Newton iteration, also solved for the increment): within half an ulp of |w1| plus
    a few eps of |w1 - w0|. Measured when written: at most 0.34 of that bound; the midpoint
    rounded as w0 + k f(w_m) and doubled reached 1.81 of it."""
    rng = np.random.default_rng(int(h * 1e4) + 1)
    n = 8
    moments = np.sort(rng.uniform(0.5, 3.0, (n, 3)), axis=1)
    moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
    omega0 = rng.normal(size=(n, 3)) * rng.choice([0.01, 1.0, 3.0], size=(n, 1))
    quat0 = Rotation.random(n, random_state=6).as_quat()
    tau = rng.normal(size=3)
    times = np.array([0.0, h])
    for i in range(n):
        sol = ph.simulate(
            moments[i], omega0[i], times, orientation0=quat0[i], method="midpoint", dt=h,
            torque=ph.torque.BodyFixed(tau),
        )
        w_mp, q_mp = midpoint_step_mp(moments[i], omega0[i], quat0[i], h, torque_body=tau)
        w_ref = np.array([float(x) for x in w_mp])
        q_ref = np.array([float(x) for x in q_mp])
        bound = EPS * (0.5 * np.max(np.abs(w_ref)) + 4 * np.max(np.abs(w_ref - omega0[i])))
        assert np.max(np.abs(sol.omega[-1] - w_ref)) <= bound, (i, sol.omega[-1] - w_ref, bound)
        quat = sol.quaternion[-1]
        quat = quat if np.dot(quat, q_ref) > 0 else -quat
        assert np.max(np.abs(quat - q_ref)) <= 4 * EPS, (i, quat - q_ref)


# ---------------------------------------------------------------------------------------------
# Batches and orientation=False
# ---------------------------------------------------------------------------------------------

METHOD_KW = [
    ("exact", {}),
    ("splitting", {"dt": 0.05, "order": 2}),
    ("splitting", {"dt": 0.05, "order": 4}),
    ("splitting", {"dt": 0.05, "order": 6}),
    ("midpoint", {"dt": 0.05}),
    ("rk4", {"dt": 0.05}),
    ("dop853", {"rtol": 1e-9}),
]
METHOD_IDS = [m + str(kw.get("order", "")) for m, kw in METHOD_KW]


def _batch_inputs(n=6):
    rng = np.random.default_rng(7)
    moments = np.sort(rng.uniform(0.5, 3.0, (n, 3)), axis=1)
    moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
    omega0 = rng.normal(size=(n, 3))
    quat0 = Rotation.random(n, random_state=3).as_quat()
    moments[1] = (2.0, 2.0, 3.0)  # a symmetric body in the batch
    omega0[2] = (0.0, 0.0, 0.0)  # a body at rest
    return moments, omega0, quat0


FIELDS = ("omega", "quaternion", "angular_momentum_space", "angular_momentum_body", "energy")


BATCH_CASES = [(m, kw, False) for m, kw in METHOD_KW] + [
    (m, kw, True)
    for m, kw in METHOD_KW
    if m != "exact"  # exact is torque-free
]


@pytest.mark.parametrize(
    ("method", "kw", "torque"),
    BATCH_CASES,
    ids=[
        f"{i}-{'torqued' if c[2] else 'free'}"
        for i, c in zip(METHOD_IDS + METHOD_IDS[1:], BATCH_CASES, strict=True)
    ],
)
def test_batch_is_bitwise_the_single_body(method, kw, torque):
    moments, omega0, quat0 = _batch_inputs()
    tq = ph.torque.BodyFixed((0.1, 0.0, 0.2)) + ph.torque.SpaceFixed((0.0, -0.05, 0.0))
    tq = tq if torque else None
    times = np.linspace(0.0, 7.0, 8)
    batch = ph.simulate(moments, omega0, times, orientation0=quat0, method=method, torque=tq, **kw)
    assert batch.omega.shape == (6, 8, 3) and batch.quaternion.shape == (6, 8, 4)
    assert batch.energy.shape == (6, 8) and batch.moments.shape == (6, 3)
    for i in range(len(moments)):
        single = ph.simulate(
            moments[i], omega0[i], times, orientation0=quat0[i], method=method, torque=tq, **kw
        )
        for name in FIELDS:
            assert np.array_equal(getattr(batch, name)[i], getattr(single, name)), (method, i, name)


# Torque-free fixed-step batches run in blocks of bodies (SIMD lanes): every body must still be
# bit for bit its own single run (the scalar path), whatever its block-mates.

BLOCK_METHODS = [
    ("splitting", {"dt": 0.05, "order": 2}),
    ("splitting", {"dt": 0.05, "order": 4}),
    ("splitting", {"dt": 0.05, "order": 6}),
    ("midpoint", {"dt": 0.05}),
    ("rk4", {"dt": 0.05}),
]


def _mixed_bodies(n):
    """n bodies unlike each other: random triaxial ones in every order of the moments (so
    different axis orders for the splitting), a symmetric top, one just off the separatrix, one
    at rest, and a fast one whose rotation angles per step exceed 1/4 (the splitting's library
    sine there) and whose midpoint Newton iterations take longer than the others'."""
    rng = np.random.default_rng(11)
    moments = rng.uniform(0.5, 3.0, (n, 3))
    moments[:, 2] = np.minimum(moments[:, 2], moments[:, 0] + moments[:, 1])
    omega0 = rng.normal(size=(n, 3))
    special = [
        ((2.0, 2.0, 3.0), (0.3, 0.1, 1.0)),  # symmetric
        ((1.0, 2.0, 3.0), (1e-9, 1.0, 1e-9)),  # near the separatrix (intermediate axis)
        ((1.0, 2.0, 2.5), (0.0, 0.0, 0.0)),  # at rest
        ((3.0, 1.0, 2.0), (12.0, -7.0, 9.0)),  # fast: |omega| dt ~ 0.8
    ]
    for k, (m, w) in enumerate(special[: max(0, n - 1)]):
        moments[1 + k] = m
        omega0[1 + k] = w
    quat0 = Rotation.random(n, random_state=5).as_quat()
    return moments, omega0, quat0


@pytest.mark.parametrize("n", [1, 2, 3, 5, 7, 9])
@pytest.mark.parametrize(
    ("method", "kw"), BLOCK_METHODS, ids=[m + str(kw.get("order", "")) for m, kw in BLOCK_METHODS]
)
def test_batch_in_blocks_is_bitwise_each_body_alone(method, kw, n):
    """N not a multiple of the block width, mixed bodies in one block, with and without the
    orientation, uneven output times: each body equals its single run bit for bit, stats too."""
    moments, omega0, quat0 = _mixed_bodies(n)
    times = np.array([0.0, 0.02, 0.5, 0.5, 1.3, 4.0])
    for orientation in (True, False):
        batch = ph.simulate(
            moments, omega0, times, orientation0=quat0, orientation=orientation, method=method, **kw
        )
        for i in range(n):
            single = ph.simulate(
                moments[i],
                omega0[i],
                times,
                orientation0=quat0[i],
                orientation=orientation,
                method=method,
                **kw,
            )
            names = FIELDS if orientation else ("omega", "angular_momentum_body", "energy")
            for name in names:
                assert np.array_equal(getattr(batch, name)[i], getattr(single, name)), (i, name)
            for key in ("steps", "evaluations"):
                assert batch.stats[key][i] == single.stats[key], (i, key)


def test_a_tensor_body_in_a_block_is_its_single_run():
    """Bodies given by inertia tensors (integrated in their principal axes, reported in their
    own) in a block of the lanes: each is its single run."""
    rng = np.random.default_rng(2)
    rot = Rotation.random(5, random_state=8).as_matrix()
    bodies = [
        ph.Body.from_inertia(1.0, r @ np.diag(np.sort(rng.uniform(1.0, 2.0, 3))) @ r.T) for r in rot
    ]
    omega0 = rng.normal(size=(5, 3))
    times = np.linspace(0.0, 2.0, 5)
    for method, kw in BLOCK_METHODS:
        batch = ph.simulate(bodies, omega0, times, method=method, **kw)
        for i in range(5):
            single = ph.simulate(bodies[i], omega0[i], times, method=method, **kw)
            for name in FIELDS:
                assert np.array_equal(getattr(batch, name)[i], getattr(single, name)), (i, name)


@pytest.mark.parametrize("method", ["rk4", "midpoint"])
def test_a_failing_body_in_a_block_is_named_with_its_own_error(method):
    """A body that fails in its block (rk4 blows up, the midpoint rule's Newton iteration
    fails; the free splitting keeps |L| and cannot) while its block-mates go on: the batch
    raises the error that body raises alone, naming it; with two failing bodies, the first by
    index."""
    fast = {"rk4": (3000.0, -2000.0, 2500.0), "midpoint": (1e5, -2e5, 3e5)}[method]
    moments, omega0, quat0 = _mixed_bodies(6)
    times = np.array([0.0, 1.0, 20.0])
    omega0[5] = fast
    with pytest.raises(ph.PolhodeError) as alone:
        ph.simulate(moments[5], omega0[5], times, orientation0=quat0[5], method=method, dt=0.05)
    with pytest.raises(type(alone.value)) as info:
        ph.simulate(moments, omega0, times, orientation0=quat0, method=method, dt=0.05)
    assert info.value.body == 5 and info.value.argument == alone.value.argument == "dt"
    assert str(info.value) == f"body 5: {alone.value}"
    omega0[2] = fast
    with pytest.raises(type(alone.value)) as info:
        ph.simulate(moments, omega0, times, orientation0=quat0, method=method, dt=0.05)
    assert info.value.body == 2


def test_batch_shares_a_single_row():
    """One body for N omega0 rows, one orientation for all; omega0 of shape (3,) is one body,
    so N bodies with one omega0 row is an error that says how to ask for N."""
    moments, omega0, quat0 = _batch_inputs()
    times = np.linspace(0.0, 3.0, 4)
    with pytest.raises(ph.ShapeError, match=r"omega0.*\(N, 3\)") as info:
        ph.simulate(moments, omega0[0], times, orientation0=quat0[0])
    assert info.value.argument == "body"
    a = ph.simulate(moments, np.tile(omega0[0], (6, 1)), times, orientation0=quat0[0])
    b = ph.simulate(moments[0], omega0, times, orientation0=quat0[0])
    assert a.omega.shape == b.omega.shape == (6, 4, 3)
    for i in range(6):
        sa = ph.simulate(moments[i], omega0[0], times, orientation0=quat0[0])
        sb = ph.simulate(moments[0], omega0[i], times, orientation0=quat0[0])
        assert np.array_equal(a.omega[i], sa.omega) and np.array_equal(
            a.quaternion[i], sa.quaternion
        )
        assert np.array_equal(b.omega[i], sb.omega) and np.array_equal(
            b.quaternion[i], sb.quaternion
        )
    assert isinstance(a.orientation, list) and len(a.orientation) == 6


def test_batch_against_reference():
    moments, omega0, quat0 = _batch_inputs(4)
    times = np.array([0.0, 2.0, 11.0])
    sol = ph.simulate(moments, omega0, times, orientation0=quat0)
    for i in range(4):
        if not np.any(omega0[i]):  # the body at rest stays at rest, attitude unchanged
            assert not np.any(sol.omega[i])
            assert np.max(np.abs(sol.quaternion[i] - quat0[i])) <= 2 * EPS
            continue
        w_ref, q_ref = reference(moments[i], omega0[i], quat0[i], times, method="direct")
        ew, eq = rel_errors(sol.omega[i], sol.quaternion[i], w_ref, q_ref)
        assert ew.max() <= EXACT_SHORT and eq.max() <= EXACT_SHORT, (i, ew, eq)


# orientation=False integrates omega alone. The docs do not promise the same omega; for the
# methods whose omega update does not read the attitude (exact, midpoint, rk4) it is the same
# arithmetic, hence bitwise equal. The splitting with attitude re-projects m from L_space each
# step (round-off differences) and dop853 controls the error of the quaternion too (different
# steps): equal to their accuracy only.
BITWISE_WITHOUT_ORIENTATION = {"exact", "midpoint", "rk4"}


@pytest.mark.parametrize(("method", "kw"), METHOD_KW, ids=METHOD_IDS)
def test_orientation_false_gives_the_same_omega(method, kw):
    moments, omega0 = BODY123
    times = np.linspace(0.0, 20.0, 11)
    with_q = ph.simulate(moments, omega0, times, orientation0=Q0, method=method, **kw)
    without = ph.simulate(
        moments, omega0, times, orientation0=Q0, method=method, orientation=False, **kw
    )
    assert without.quaternion is None and without.angular_momentum_space is None
    assert without.orientation is None
    np.testing.assert_array_equal(without.energy.shape, (11,))
    if method in BITWISE_WITHOUT_ORIENTATION:
        assert np.array_equal(with_q.omega, without.omega), method
    else:
        scale = np.linalg.norm(omega0)
        diff = np.max(np.abs(with_q.omega - without.omega)) / scale
        assert diff <= (1e-13 if method == "splitting" else 10 * kw["rtol"]), diff


# ---------------------------------------------------------------------------------------------
# Bodies in non-principal axes
# ---------------------------------------------------------------------------------------------


@functools.cache
def _tensor_reference(inertia_key, omega0, quat0, t_end, n):
    """scipy DOP853 on I w' = -w x I w with the full tensor, and q' = q (x) (0, w) / 2."""
    inertia = np.array(inertia_key).reshape(3, 3)
    inverse = np.linalg.inv(inertia)

    def rhs(t, y):
        w = y[:3]
        return np.concatenate(
            [-inverse @ np.cross(w, inertia @ w), 0.5 * qmul(y[3:], np.append(w, 0.0))]
        )

    times = np.linspace(0.0, t_end, n)
    sol = solve_ivp(
        rhs,
        (0.0, t_end),
        np.concatenate([omega0, quat0]),
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
        t_eval=times,
    )
    return times, sol.y[:3].T, sol.y[3:].T


ROTATED_BOX = ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)).rotated(Rotation.from_rotvec([0.3, -0.5, 0.7]))


@pytest.mark.parametrize(
    ("method", "kw", "tol"),
    [
        ("exact", {}, 1e-11),
        ("dop853", {"rtol": 1e-12}, 1e-9),
        ("splitting", {"dt": 0.01, "order": 4}, 1e-7),
        ("rk4", {"dt": 0.01}, 1e-8),
        ("midpoint", {"dt": 0.002}, 1e-4),
    ],
)
def test_body_in_non_principal_axes(method, kw, tol):
    """A rotated box: integrated in principal axes, reported in its own axes."""
    body = ROTATED_BOX
    inertia = body.inertia
    assert np.max(np.abs(inertia - np.diag(np.diag(inertia)))) > 0.05  # really off-diagonal
    omega0 = np.array([0.4, -0.9, 0.25])
    q0 = Rotation.from_rotvec([0.1, 0.2, -0.3]).as_quat()
    times, w_ref, q_ref = _tensor_reference(
        tuple(inertia.ravel()), tuple(omega0), tuple(q0), 30.0, 31
    )
    sol = ph.simulate(body, omega0, times, orientation0=q0, method=method, **kw)
    ew, eq = rel_errors(sol.omega, sol.quaternion, w_ref, q_ref)
    assert max(ew.max(), eq.max()) <= tol, (ew.max(), eq.max())
    # omega in the body's own axes; L = R I w in space, conserved; L_body = I w; T = w.I.w/2
    l_space = Rotation.from_quat(sol.quaternion).apply(sol.omega @ inertia.T)
    g0 = np.linalg.norm(inertia @ omega0)
    assert np.max(np.abs(sol.angular_momentum_space - l_space)) <= 1e-14 * g0 * 8
    assert np.max(np.abs(sol.angular_momentum_body - sol.omega @ inertia.T)) <= 8e-15 * g0
    energy = 0.5 * np.einsum("ij,ij->i", sol.omega, sol.omega @ inertia.T)
    assert np.max(np.abs(sol.energy - energy)) <= 8 * EPS * energy[0]
    if method in ("exact", "splitting"):
        l0 = Rotation.from_quat(q0).apply(inertia @ omega0)
        assert np.max(np.abs(sol.angular_momentum_space - l0)) <= 1e-13 * g0
    moments = np.linalg.eigvalsh(inertia)
    np.testing.assert_allclose(np.sort(sol.moments), moments, rtol=1e-14)


def test_tensor_input_is_the_body():
    """A (3, 3) tensor is handled like the Body it came from."""
    omega0 = (0.4, -0.9, 0.25)
    times = np.linspace(0.0, 10.0, 5)
    a = ph.simulate(ROTATED_BOX, omega0, times)
    b = ph.simulate(ROTATED_BOX.inertia, omega0, times)
    ew, eq = rel_errors(b.omega, b.quaternion, a.omega, a.quaternion)
    assert max(ew.max(), eq.max()) <= 1e-13, (ew, eq)
    np.testing.assert_allclose(b.moments, a.moments, rtol=1e-14)


@pytest.mark.parametrize("size", [1e300, 1e-300, 5e-324, 1e308])
def test_an_orientation_quaternion_of_any_size_is_its_direction(size):
    """orientation0 is normalised: (1e300, 1e300, 0, 0), whose squared norm overflows, and
    (1e-300, 1e-300, 0, 0), whose squared norm underflows, were refused as "a non-zero
    quaternion, got 0". They are the rotation of (1, 1, 0, 0), bit for bit."""
    moments, omega0, t = (1.0, 2.0, 3.0), (0.3, 1.0, 0.2), [0.0, 1.0]
    unit = ph.simulate(moments, omega0, t, orientation0=(1.0, 1.0, 0.0, 0.0), method="exact")
    scaled = ph.simulate(moments, omega0, t, orientation0=(size, size, 0.0, 0.0), method="exact")
    assert np.array_equal(scaled.quaternion, unit.quaternion)
