"""One body to t = 100: wall time against the error at the end, polhode against scipy.

    python -m benchmarks.bench_motion [--quick] [--repeats R]

Case: I = (1, 2, 3), omega0 = (0.01, 1, 0.01) (five tennis-racket flips by t = 100), with
orientation. The error is measured against polhode's exact solution, which the test suite
checks to 1e-13 against an independent exact-arithmetic Taylor reference
(tests/reference_motion.py): relative error of omega and of the attitude quaternion (up to
sign) at t = 100. scipy integrates the same 7 equations (omega and the quaternion) with a
numpy right-hand side. Every timing is of the whole Python call; the peers alternate with
polhode in each repeat and medians are printed.
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

import polhode as ph
from benchmarks._common import interleaved, machine

MOMENTS = np.array([1.0, 2.0, 3.0])
OMEGA0 = np.array([0.01, 1.0, 0.01])
T_END = 100.0


def scipy_rhs(_t: float, y: np.ndarray) -> np.ndarray:
    w, q = y[:3], y[3:]
    i1, i2, i3 = MOMENTS
    dw = np.array(
        [(i2 - i3) / i1 * w[1] * w[2], (i3 - i1) / i2 * w[2] * w[0], (i1 - i2) / i3 * w[0] * w[1]]
    )
    x, yq, z, s = q
    # q' = q (x) (0, w) / 2, scalar-last.
    dq = 0.5 * np.array(
        [
            s * w[0] + yq * w[2] - z * w[1],
            s * w[1] + z * w[0] - x * w[2],
            s * w[2] + x * w[1] - yq * w[0],
            -(x * w[0] + yq * w[1] + z * w[2]),
        ]
    )
    return np.concatenate([dw, dq])


def errors(omega: np.ndarray, quat: np.ndarray, exact: ph.Trajectory) -> tuple[float, float]:
    assert exact.quaternion is not None
    w_ref, q_ref = exact.omega[-1], exact.quaternion[-1]
    q = quat / np.linalg.norm(quat)
    e_w = float(np.linalg.norm(omega - w_ref) / np.linalg.norm(w_ref))
    e_q = float(min(np.linalg.norm(q - q_ref), np.linalg.norm(q + q_ref)))
    return e_w, e_q


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer settings, 3 repeats")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    from scipy.integrate import solve_ivp

    repeats = 3 if args.quick else args.repeats
    exact = ph.simulate(MOMENTS, OMEGA0, [0.0, T_END], method="exact")
    runs = {
        "polhode exact": lambda: ph.simulate(MOMENTS, OMEGA0, [0.0, T_END], method="exact"),
    }
    rtols = [1e-6, 1e-9, 1e-12] if args.quick else [1e-6, 1e-8, 1e-10, 1e-12]
    for rtol in rtols:
        runs[f"polhode dop853 rtol={rtol:.0e}"] = lambda r=rtol: ph.simulate(
            MOMENTS, OMEGA0, [0.0, T_END], method="dop853", rtol=r
        )
        runs[f"scipy DOP853 rtol={rtol:.0e}"] = lambda r=rtol: solve_ivp(
            scipy_rhs,
            (0.0, T_END),
            np.concatenate([OMEGA0, [0.0, 0.0, 0.0, 1.0]]),
            method="DOP853",
            rtol=r,
            atol=r * np.linalg.norm(OMEGA0),
        )
    dts = [1e-1, 1e-2] if args.quick else [1e-1, 3e-2, 1e-2, 3e-3]
    for dt in dts:
        for method, extra in (("splitting", {"order": 4}), ("rk4", {}), ("midpoint", {})):
            label = f"polhode {method} dt={dt:.0e}"
            runs[label] = lambda m=method, d=dt, e=extra: ph.simulate(
                MOMENTS, OMEGA0, [0.0, T_END], method=m, dt=d, **e
            )
    times, results = interleaved(runs, repeats)
    print(f"# bench_motion ({machine()})")
    print(f"# I = {MOMENTS.tolist()}, omega0 = {OMEGA0.tolist()}, t = 0..{T_END:g}, with attitude")
    print(f"{'series':34s} {'median ms':>10s} {'err omega':>10s} {'err attitude':>13s}")
    for name, result in results.items():
        if name.startswith("scipy"):
            omega, quat = result.y[:3, -1], result.y[3:, -1]
        else:
            omega, quat = result.omega[-1], result.quaternion[-1]
        e_w, e_q = errors(omega, quat, exact)
        median = statistics.median(times[name]) * 1e3
        print(f"{name:34s} {median:10.3f} {e_w:10.1e} {e_q:13.1e}")
    print("\nspeed-up of polhode dop853 over scipy DOP853 at the same rtol:")
    for rtol in rtols:
        ours = statistics.median(times[f"polhode dop853 rtol={rtol:.0e}"])
        theirs = statistics.median(times[f"scipy DOP853 rtol={rtol:.0e}"])
        print(f"  rtol {rtol:.0e}: {theirs / ours:7.1f}x")


if __name__ == "__main__":
    main()
