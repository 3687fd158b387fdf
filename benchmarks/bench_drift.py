"""Invariant drift over a long run: relative error of T, |L| and L in space against time.

    python -m benchmarks.bench_drift [--quick] [--steps S] [--dt DT] [--plot DIR]

Each fixed-step method (splitting 2/4/6, implicit midpoint, rk4) takes 1e6 steps of 0.01 on
I = (1, 2, 3), omega0 = (0.01, 1, 0.01), with orientation; dop853 at rtol 1e-10 over the same
span is shown for contrast. See polhode.bench.drift.
"""

from __future__ import annotations

import argparse
import os

from polhode import bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1e5 steps")
    parser.add_argument("--steps", type=int, default=None, help="default 1e6 (1e5 with --quick)")
    parser.add_argument("--dt", type=float, default=0.01)
    parser.add_argument("--plot", metavar="DIR", help="write drift.png there")
    args = parser.parse_args()
    steps = args.steps or (100_000 if args.quick else 1_000_000)
    print(f"# bench_drift ({bench.machine()})")
    result = bench.drift("flip", steps=steps, dt=args.dt)
    print(result.table())
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
        print(f"wrote {bench.plot_drift(result, os.path.join(args.plot, 'drift.png'))}")


if __name__ == "__main__":
    main()
