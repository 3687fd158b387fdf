"""Batch throughput: body-steps per second against the number of bodies, on all cores.

    python -m benchmarks.bench_throughput [--quick] [--repeats R] [--plot DIR]
        [--sizes N ...] [--methods NAME ...]

N random bodies (1 to 1e6) integrated with each method, with and without orientation, for
about 2e7 rk4 body-steps per call (at least 10 steps each; fewer steps for the costlier methods,
see polhode.bench.throughput); the exact method is timed on output times instead (evaluations
per second). The time is of the whole Python call; the repeats are interleaved. For N >= 1e4 a
numpy structure-of-arrays RK4 (one core) is timed in the same run, and each method's rate is
also given as a multiple of it ("x numpy rk4"). See polhode.bench.throughput.
"""

from __future__ import annotations

import argparse
import os
from typing import Any

from polhode import bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N up to 1e5, rk4 and exact")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--plot", metavar="DIR", help="write throughput.png there")
    parser.add_argument("--sizes", type=int, nargs="+", help="the numbers of bodies N")
    parser.add_argument("--methods", nargs="+", help="the methods (default: all)")
    args = parser.parse_args()
    print(f"# bench_throughput ({bench.machine()})")
    options: dict[str, Any] = {}
    if args.quick:
        options = {"sizes": (1, 100, 10_000, 100_000), "methods": ("rk4", "exact"), "work": 2e6}
    if args.sizes:
        options["sizes"] = tuple(args.sizes)
    if args.methods:
        options["methods"] = tuple(args.methods)
    result = bench.throughput(repeats=args.repeats, **options)
    print(result.table())
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
        print(f"wrote {bench.plot_throughput(result, os.path.join(args.plot, 'throughput.png'))}")


if __name__ == "__main__":
    main()
