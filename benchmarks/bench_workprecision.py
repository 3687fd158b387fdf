"""Work-precision: one body, torque-free, wall time against the error at the end.

    python -m benchmarks.bench_workprecision [--quick] [--repeats R] [--case flip|hlw|long|all]
                                              [--plot DIR]

Every polhode method (exact; dop853 over rtol; rk4, splitting 2/4/6 and midpoint over dt)
against scipy's solve_ivp (RK45, DOP853, LSODA on omega and the quaternion, a numpy
right-hand side) and MuJoCo (a free body with gravity off, Euler and RK4, run by
mujoco.rollout) when installed. Errors are against a 30-digit reference (polhode.bench.REFERENCE).
Then the cost of each to reach 1e-6 ... 1e-12 and the ratios. See polhode.bench.work_precision.
"""

from __future__ import annotations

import argparse
import os

from polhode import bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer settings (under a minute)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--case", default="flip", choices=[*bench.CASES, "all"])
    parser.add_argument("--budget", type=float, default=3.0, help="seconds per call, at most")
    parser.add_argument("--plot", metavar="DIR", help="write work_precision_<case>.png there")
    args = parser.parse_args()
    print(f"# bench_workprecision ({bench.machine()})")
    cases = list(bench.CASES) if args.case == "all" else [args.case]
    for case in cases:
        result = bench.work_precision(
            case, quick=args.quick, repeats=args.repeats, budget=args.budget
        )
        print()
        print(result.table())
        for which in ("omega", "orientation"):
            print(f"\ncost to reach each error of the {which} (ms), and polhode's speed-up:")
            print(bench.targets(result, which=which))
        if args.plot:
            os.makedirs(args.plot, exist_ok=True)
            path = os.path.join(args.plot, f"work_precision_{case}.png")
            print(f"wrote {bench.plot_work_precision(result, path)}")


if __name__ == "__main__":
    main()
