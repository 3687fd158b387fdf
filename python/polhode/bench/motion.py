"""Motion benchmarks: work-precision against the 30-digit reference, the cost to reach an
error, invariant drift over a long run, and batch throughput.

Errors of the motion are measured against :data:`REFERENCE`, the state at the end time computed
at 30 digits by an independent exact-arithmetic Taylor integrator (``tests/reference_motion.py``;
``python -m benchmarks.reference_values`` regenerates the constants and ``tests/test_bench.py``
checks them), never against another double-precision approximation, polhode's exact solution
included.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode.bench import adapters
from polhode.bench._timing import median as _median
from polhode.bench._timing import spread as _spread
from polhode.invariants import relative_drift
from polhode.simulation import simulate

Array = NDArray[np.float64]

# --------------------------------------------------------------------------------------------
# Work-precision: one body, torque-free, against the exact solution.


@dataclass(frozen=True)
class Case:
    """A torque-free body: principal moments, initial angular velocity, end time."""

    name: str
    moments: tuple[float, float, float]
    omega0: tuple[float, float, float]
    t_end: float
    label: str


_HLW_M0 = np.array([math.cos(1.1), 0.0, math.sin(1.1)])
CASES = {
    "flip": Case(
        "flip",
        (1.0, 2.0, 3.0),
        (0.01, 1.0, 0.01),
        100.0,
        "I = (1, 2, 3), omega0 = (0.01, 1, 0.01), t = 100 (five tennis-racket flips)",
    ),
    "hlw": Case(
        "hlw",
        (2.0, 1.0, 2.0 / 3.0),
        tuple(float(x) for x in _HLW_M0 / np.array([2.0, 1.0, 2.0 / 3.0])),  # type: ignore[arg-type]
        100.0,
        "I = (2, 1, 2/3), m0 = (cos 1.1, 0, sin 1.1), t = 100 (Hairer-Lubich-Wanner)",
    ),
    "long": Case(
        "long",
        (1.0, 2.0, 3.0),
        (0.01, 1.0, 0.01),
        1.0e4,
        "I = (1, 2, 3), omega0 = (0.01, 1, 0.01), t = 1e4 (a long run: 500 flips)",
    ),
}


# The state (omega, xyzw quaternion) at t_end of each case, from the identity orientation, rounded
# from 30 digits (see the module docstring).
REFERENCE: dict[str, tuple[tuple[float, float, float], tuple[float, float, float, float]]] = {
    "flip": (
        (0.009550413196755434, -1.0000043947942285, 0.009852417507542),
        (0.9654395742742695, -7.971609403975472e-05, -0.26015690880105513, -0.01564624151485416),
    ),
    "hlw": (
        (-0.08867415693748931, -0.5904185243334242, 1.1810569286879014),
        (-0.2616786950327903, 0.22583910742775595, 0.30591607152762923, 0.887094310264288),
    ),
    "long": (
        (0.46311058913583414, -0.8863569158246923, 0.2675016621566673),
        (0.13935358609147006, 0.2138558794832752, 0.9626791568197566, 0.08997267295509609),
    ),
}


@dataclass
class Point:
    """One setting of one series: wall times of the repeats and the errors at the end."""

    setting: str
    seconds: list[float]
    error_omega: float
    error_orientation: float

    @property
    def median(self) -> float:
        return _median(self.seconds)

    def error(self, which: str = "omega") -> float:
        """The relative error of omega (``"omega"``), the orientation error in radians
        (``"orientation"``), or the larger of the two (``"both"``)."""
        if which == "omega":
            return self.error_omega
        if which == "orientation":
            return self.error_orientation
        return max(self.error_omega, self.error_orientation)


@dataclass
class Series:
    """A method swept over its step or tolerance."""

    name: str
    peer: bool
    points: list[Point] = field(default_factory=list)


@dataclass
class WorkPrecision:
    """Every series of one case, and the peers that were not installed."""

    case: Case
    series: list[Series]
    skipped: list[str]

    def get(self, name: str) -> Series | None:
        return next((s for s in self.series if s.name == name), None)

    def table(self) -> str:
        lines = [
            f"{self.case.label}",
            f"{'series':26s} {'setting':>12s} {'median ms':>10s} {'spread ms':>17s} "
            f"{'err omega':>10s} {'err orientation':>16s}",
        ]
        for s in self.series:
            for p in s.points:
                lines.append(
                    f"{s.name:26s} {p.setting:>12s} {p.median * 1e3:10.3f} "
                    f"{_spread(p.seconds):>17s} {p.error_omega:10.1e} {p.error_orientation:16.1e}"
                )
        if self.skipped:
            lines.append(f"(left out: {', '.join(self.skipped)})")
        return "\n".join(lines)


def _orientation_error(q: Array, q_ref: Array) -> float:
    """The angle (rad) of the rotation between two orientations, xyzw quaternions."""
    q = q / np.linalg.norm(q)
    # r = conj(q_ref) * q; its angle is 2 atan2(|r_vec|, |r_w|).
    w = abs(float(np.dot(q, q_ref)))
    v = q_ref[3] * q[:3] - q[3] * q_ref[:3] - np.cross(q_ref[:3], q[:3])
    return 2.0 * math.atan2(float(np.linalg.norm(v)), w)


def _errors(omega: Array, quaternion: Array, reference: tuple[Array, Array]) -> tuple[float, float]:
    w_ref, q_ref = reference
    e_w = float(np.linalg.norm(omega - w_ref) / np.linalg.norm(w_ref))
    return e_w, _orientation_error(quaternion, q_ref)


# Sweeps: coarse to fine. A series stops at the first setting whose first call exceeds the
# budget (the finer ones would cost more still).
_RTOLS = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13]
_RTOLS_QUICK = [1e-5, 1e-7, 1e-9, 1e-11, 1e-13]
_DTS = [0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001]
_DTS_QUICK = [0.1, 0.02, 0.005]
_MUJOCO_DTS = [0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 0.0005]
_MUJOCO_DTS_QUICK = [0.02, 0.005]


def _sweeps(
    case: Case, quick: bool, peers: bool, skipped: list[str]
) -> list[tuple[str, bool, list[tuple[str, adapters.Runner]]]]:
    """(series name, is a peer, [(setting, a call returning omega and quaternion at t_end)])."""
    moments = np.array(case.moments)
    omega0 = np.array(case.omega0)
    span = [0.0, case.t_end]
    rtols = _RTOLS_QUICK if quick else _RTOLS
    dts = _DTS_QUICK if quick else _DTS

    def polhode(**kwargs: Any) -> adapters.Runner:
        def run() -> tuple[Array, Array]:
            traj = simulate(moments, omega0, span, **kwargs)
            assert traj.quaternion is not None
            return traj.omega[-1], traj.quaternion[-1]

        return run

    sweeps: list[tuple[str, bool, list[tuple[str, adapters.Runner]]]] = [
        ("polhode exact", False, [("-", polhode(method="exact"))]),
        (
            "polhode dop853",
            False,
            [(f"rtol {r:.0e}", polhode(method="dop853", rtol=r)) for r in rtols],
        ),
        ("polhode rk4", False, [(f"dt {d:g}", polhode(method="rk4", dt=d)) for d in dts]),
    ]
    for order in (2, 4, 6):
        sweeps.append(
            (
                f"polhode splitting {order}",
                False,
                [
                    (f"dt {d:g}", polhode(method="splitting", dt=d, order=order))
                    for d in dts
                    if order > 2 or d <= 0.1
                ],
            )
        )
    sweeps.append(
        ("polhode midpoint", False, [(f"dt {d:g}", polhode(method="midpoint", dt=d)) for d in dts])
    )
    if not peers:
        return sweeps

    def scipy(method: str, rtol: float) -> adapters.Runner:
        return adapters.scipy_runner(case.moments, case.omega0, case.t_end, method, rtol)

    def mujoco(integrator: str, dt: float) -> adapters.Runner:
        return adapters.mujoco_runner(case.moments, case.omega0, case.t_end, integrator, dt)

    for name in ("RK45", "DOP853", "LSODA"):
        settings = [r for r in rtols if r >= adapters.SCIPY_MIN_RTOL]
        sweeps.append(
            (f"scipy {name}", True, [(f"rtol {r:.0e}", scipy(name, r)) for r in settings])
        )
    if not adapters.mujoco_installed():
        skipped.append("MuJoCo (not installed)")
        return sweeps
    mujoco_dts = _MUJOCO_DTS_QUICK if quick else _MUJOCO_DTS
    if adapters.mujoco_rejects(case.moments):  # HLW's case: 1 + 2/3 < 2
        skipped.append("MuJoCo (it rejects moments that break I1 + I2 >= I3)")
        return sweeps
    for integrator, label in (("Euler", "MuJoCo Euler"), ("RK4", "MuJoCo RK4")):
        sweeps.append(
            (
                label,
                True,
                [(f"dt {d:g}", mujoco(integrator, d)) for d in mujoco_dts],
            )
        )
    return sweeps


#: Calls shorter than this (s) are timed after an untimed call of the same, so that the
#: other series run in between do not leave them cold.
WARM_BELOW = 0.01


def work_precision(
    case: Case | str = "flip",
    *,
    quick: bool = False,
    repeats: int = 5,
    budget: float = 3.0,
    peers: bool = True,
) -> WorkPrecision:
    """Wall time of the whole Python call against the error at ``t_end``, for every polhode
    method and the peers (scipy's solve_ivp RK45, DOP853 and LSODA on omega + quaternion;
    MuJoCo's Euler and RK4 on a free body, when installed).

    The first round sweeps each series from coarse to fine and stops it at the first setting
    that takes longer than ``budget`` seconds. Then ``repeats`` rounds re-run every setting
    kept, all series in turn, and their times are the ones kept (the first round's only for
    a setting over the budget, run once, or with ``repeats=1``). A call shorter than
    :data:`WARM_BELOW` is preceded by an untimed one.
    """
    case = CASES[case] if isinstance(case, str) else case
    if case.name in REFERENCE:
        w_ref, q_ref = REFERENCE[case.name]
        reference = (np.array(w_ref), np.array(q_ref))
    else:  # a user's own case: polhode's exact solution is the best reference at hand
        exact = simulate(case.moments, case.omega0, [0.0, case.t_end], method="exact")
        assert exact.quaternion is not None
        reference = (exact.omega[-1], exact.quaternion[-1])
    skipped: list[str] = []
    sweeps = _sweeps(case, quick, peers, skipped)
    jobs: list[tuple[Series, Point, adapters.Runner]] = []
    result = WorkPrecision(case, [], skipped)
    for name, peer, settings in sweeps:
        series = Series(name, peer)
        result.series.append(series)
        for setting, run in settings:
            start = time.perf_counter()
            omega, quaternion = run()
            seconds = time.perf_counter() - start
            e_w, e_q = _errors(omega, quaternion, reference)
            point = Point(setting, [seconds], e_w, e_q)
            series.points.append(point)
            jobs.append((series, point, run))
            if seconds > budget:
                break
    for _ in range(repeats if repeats > 1 else 0):
        for _series, point, run in jobs:
            if point.seconds[0] > budget:
                continue  # one call is enough to place a point this slow
            if point.seconds[0] < WARM_BELOW:
                run()  # warm the caches after the other series, as timeit would
            start = time.perf_counter()
            run()
            point.seconds.append(time.perf_counter() - start)
    if repeats > 1:
        for _series, point, _run in jobs:
            if len(point.seconds) > 1:
                del point.seconds[0]  # the sweep's call: cold, and first
    return result


def cost_at(series: Series, error: float, which: str = "omega") -> float | None:
    """The time the series needs to reach ``error`` (see :meth:`Point.error` for ``which``):
    log-log interpolation on its cheapest settings (the Pareto front) between the last one
    above ``error`` and the first one at or below; None if it never gets there."""
    front: list[tuple[float, float]] = []
    for p in sorted(series.points, key=lambda p: p.median):
        if not front or p.error(which) < front[-1][1]:
            front.append((p.median, p.error(which)))
    for k, (seconds, err) in enumerate(front):
        if err <= error:
            if k == 0:
                return seconds
            t0, e0 = front[k - 1]
            if err <= 0.0:
                return seconds
            f = math.log(e0 / error) / math.log(e0 / err)
            return math.exp(math.log(t0) + f * (math.log(seconds) - math.log(t0)))
    return None


def best_at(
    result: WorkPrecision, error: float, peer: bool, which: str = "omega"
) -> tuple[str, float] | None:
    """The fastest series (of polhode's or of the peers') reaching ``error``, and its cost."""
    costs = [
        (s.name, c)
        for s in result.series
        if s.peer == peer and (c := cost_at(s, error, which)) is not None
    ]
    return min(costs, key=lambda x: x[1]) if costs else None


def targets(
    result: WorkPrecision,
    levels: Sequence[float] = (1e-6, 1e-8, 1e-10, 1e-12),
    which: str = "omega",
) -> str:
    """At each error level (of omega, the orientation or both: :meth:`Point.error`): the cost of
    polhode's dop853, of polhode's fastest method, of scipy's DOP853 and of MuJoCo's RK4, and
    the ratios (how many times faster polhode is); '-' where a series does not get there."""
    ours = result.get("polhode dop853")
    scipy = result.get("scipy DOP853")
    mujoco = result.get("MuJoCo RK4")
    lines = [
        f"{'error':>7s} {'dop853 ms':>10s} {'best polhode':>28s} {'scipy DOP853':>13s} "
        f"{'x dop853':>9s} {'x best':>8s} {'MuJoCo RK4':>11s} {'x best':>8s}"
    ]

    def ms(x: float | None) -> str:
        return "-" if x is None else f"{x * 1e3:.3f}"

    def ratio(a: float | None, b: float | None) -> str:
        return "-" if a is None or b is None else f"{a / b:.0f}x"

    for level in levels:
        dop = None if ours is None else cost_at(ours, level, which)
        best = best_at(result, level, peer=False, which=which)
        best_cost = None if best is None else best[1]
        best_name = "-" if best is None else f"{best[0][8:]} {best[1] * 1e3:.3f}"
        sci = None if scipy is None else cost_at(scipy, level, which)
        muj = None if mujoco is None else cost_at(mujoco, level, which)
        lines.append(
            f"{level:7.0e} {ms(dop):>10s} {best_name:>28s} {ms(sci):>13s} "
            f"{ratio(sci, dop):>9s} {ratio(sci, best_cost):>8s} {ms(muj):>11s} "
            f"{ratio(muj, best_cost):>8s}"
        )
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------
# Invariant drift over a long run.


#: The keys of :attr:`Drift.errors` by key of :func:`polhode.invariants.relative_drift`.
_DRIFT_KEYS = {"energy": "T", "angular_momentum_norm": "|L|", "angular_momentum_space": "L"}


@dataclass
class Drift:
    """Relative errors of T, |L| and L in space at log-spaced times, per method: ``errors[name]``
    is keyed ``"T"``, ``"|L|"`` and ``"L"`` (:func:`polhode.invariants.relative_drift`)."""

    case: Case
    dt: float
    steps: int
    t: Array
    errors: dict[str, dict[str, Array]]
    seconds: dict[str, float]

    def table(self) -> str:
        lines = [
            f"{self.case.label.split(', t =')[0]}, dt = {self.dt:g}, {self.steps:.0e} steps, "
            "largest relative error over the run (and at the end)",
            f"{'method':22s} {'wall s':>7s} {'T':>19s} {'|L|':>19s} {'L in space':>19s}",
        ]
        for name, errs in self.errors.items():
            cells = [f"{np.max(errs[k]):8.1e} ({errs[k][-1]:8.1e})" for k in ("T", "|L|", "L")]
            lines.append(f"{name:22s} {self.seconds[name]:7.2f} " + " ".join(cells))
        return "\n".join(lines)


def drift(
    case: Case | str = "flip", *, steps: int = 1_000_000, dt: float = 0.01, samples: int = 300
) -> Drift:
    """Integrates ``steps`` fixed steps of ``dt`` with each fixed-step method (and dop853 at
    rtol 1e-10 for contrast) and records the relative errors of the invariants at ``samples``
    log-spaced times (whole multiples of ``dt``, so that every step is ``dt``)."""
    case = CASES[case] if isinstance(case, str) else case
    k = np.unique(np.round(np.logspace(0, math.log10(steps), samples)).astype(np.int64))
    t = np.concatenate([[0.0], k * dt])
    methods: dict[str, dict[str, Any]] = {
        "splitting 2": {"method": "splitting", "order": 2, "dt": dt},
        "splitting 4": {"method": "splitting", "order": 4, "dt": dt},
        "splitting 6": {"method": "splitting", "order": 6, "dt": dt},
        "midpoint": {"method": "midpoint", "dt": dt},
        "rk4": {"method": "rk4", "dt": dt},
        "dop853 rtol 1e-10": {"method": "dop853", "rtol": 1e-10},
    }
    errors: dict[str, dict[str, Array]] = {}
    seconds: dict[str, float] = {}
    for name, kwargs in methods.items():
        start = time.perf_counter()
        traj = simulate(case.moments, case.omega0, t, **kwargs)
        seconds[name] = time.perf_counter() - start
        drifts = relative_drift(traj)
        # t0 itself (zero error) is left out of the log-spaced times.
        errors[name] = {short: drifts[key][1:] for key, short in _DRIFT_KEYS.items()}
    return Drift(case, dt, steps, t[1:], errors, seconds)


# --------------------------------------------------------------------------------------------
# Batch throughput.


#: The name of the batch peer's rows in :class:`Throughput`: :func:`adapters.numpy_rk4`.
NUMPY_RK4 = "numpy rk4"

#: The peer is timed from this N on (below it, numpy's per-call overhead is all one measures).
NUMPY_RK4_MIN_N = 10_000


@dataclass
class Throughput:
    """Body-steps per second (integrators) or evaluations per second (exact) against N, and the
    numpy structure-of-arrays RK4 (rows named :data:`NUMPY_RK4`) for N >= 1e4."""

    rows: list[tuple[str, bool, int, int, list[float]]]  # method, orientation, N, work, seconds

    def rate(self, method: str, orientation: bool) -> dict[int, float]:
        return {
            n: work / _median(secs)
            for m, a, n, work, secs in self.rows
            if m == method and a == orientation
        }

    def ratio(self, method: str, orientation: bool) -> dict[int, float]:
        """The rate of ``method`` over the numpy RK4's (same N and orientation, same run)."""
        peer = self.rate(NUMPY_RK4, orientation)
        return {n: r / peer[n] for n, r in self.rate(method, orientation).items() if n in peer}

    def table(self) -> str:
        lines = [
            f"{'method':14s} {'orientation':>11s} {'N':>8s} {'median ms':>10s} {'spread ms':>17s} "
            f"{'per second':>11s} {'':10s} {'x numpy rk4':>11s}"
        ]
        for method, orientation, n, work, secs in self.rows:
            unit = "evals" if method == "exact" else "body-steps"
            ratio = self.ratio(method, orientation).get(n)
            shown = "" if ratio is None or method in (NUMPY_RK4, "exact") else f"{ratio:.3g}"
            lines.append(
                f"{method:14s} {str(orientation):>11s} {n:8d} {_median(secs) * 1e3:10.2f} "
                f"{_spread(secs):>17s} {work / _median(secs):11.3g} {unit:10s} {shown:>11s}"
            )
        return "\n".join(lines)


def random_bodies(n: int, rng: np.random.Generator) -> tuple[Array, Array]:
    """Principal moments that satisfy the triangle inequality and random angular velocities."""
    moments = np.sort(rng.uniform(1.0, 2.0, size=(n, 3)), axis=1)
    return moments, rng.normal(size=(n, 3))


def throughput(
    *,
    sizes: Sequence[int] = (1, 10, 100, 1_000, 10_000, 100_000, 1_000_000),
    methods: Sequence[str] = ("rk4", "splitting", "midpoint", "dop853", "exact"),
    work: float = 2e7,
    repeats: int = 3,
    dt: float = 0.01,
    peer: bool = True,
) -> Throughput:
    """For each N, integrates N random bodies on all cores for about ``work / N`` rk4 steps
    (at least 10), or as many as take about as long with the other methods (a half for
    midpoint, a quarter for the splitting, an eighth for dop853), and reports body-steps per
    second, with and without orientation; the exact method is timed on an eighth as many
    output times (evaluations per second). With ``peer``, the numpy structure-of-arrays RK4
    (:func:`adapters.numpy_rk4`, one core) is timed too for N >= 1e4, on an eighth as many
    steps. Every setting runs once in each repeat, in turn (interleaved)."""
    rng = np.random.default_rng(0)
    # Roughly the cost of a step (an exact evaluation) in rk4 steps: equal time per row.
    cost = {"splitting": 4, "midpoint": 2, "dop853": 8, "exact": 8, NUMPY_RK4: 8}
    runs: list[tuple[str, bool, int, Any]] = []
    for n in sizes:
        moments, omega0 = random_bodies(n, rng)
        steps = int(max(10, min(100_000, work // n)))
        names = list(methods) + ([NUMPY_RK4] if peer and n >= NUMPY_RK4_MIN_N else [])
        for method in names:
            steps_m = max(10, steps // cost.get(method, 1))
            for orientation in (True, False):
                runs.append(
                    (
                        method,
                        orientation,
                        n,
                        _throughput_run(method, orientation, moments, omega0, steps_m, dt),
                    )
                )
    seconds: list[list[float]] = [[] for _ in runs]
    totals = [0] * len(runs)
    for _ in range(repeats):
        for k, (_m, _a, _n, run) in enumerate(runs):
            start = time.perf_counter()
            totals[k] = run()
            seconds[k].append(time.perf_counter() - start)
    return Throughput([(m, a, n, totals[k], seconds[k]) for k, (m, a, n, _) in enumerate(runs)])


def _throughput_run(
    method: str, orientation: bool, moments: Array, omega0: Array, steps: int, dt: float
) -> Any:
    """A call of one setting of :func:`throughput`, returning its work (body-steps or exact
    evaluations)."""
    n = len(moments)
    if method == NUMPY_RK4:

        def peer() -> int:
            adapters.numpy_rk4(moments, omega0, steps, dt, orientation=orientation)
            return n * steps

        return peer
    if method == "exact":
        times = np.linspace(0.0, steps * dt, steps)
        kwargs: dict[str, Any] = {"method": "exact"}
    elif method == "dop853":
        times = np.array([0.0, steps * dt])
        kwargs = {"method": "dop853", "rtol": 1e-8}
    else:
        times = np.array([0.0, steps * dt])
        kwargs = {"method": method, "dt": dt}

    def call() -> int:
        traj = simulate(moments, omega0, times, orientation=orientation, **kwargs)
        if method == "exact":
            return n * len(times)
        return int(np.sum(traj.stats["steps"]))

    return call
