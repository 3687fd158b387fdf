"""Batch throughput: body-steps per second against the number of bodies, on all cores.

    python -m benchmarks.bench_throughput [--quick] [--repeats R] [--plot DIR]

N random bodies (1 to 1e6) integrated with each method, with and without orientation, for
about 2e7 rk4 body-steps per call (at least 10 steps each; fewer steps for the costlier methods,
see polhode.bench.throughput); the exact method is timed on output times instead (evaluations
per second). The time is of the whole Python call. See
polhode.bench.throughput.
"""

from __future__ import annotations

import argparse
import os

from polhode import bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N up to 1e5, rk4 and exact")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--plot", metavar="DIR", help="write throughput.png there")
    args = parser.parse_args()
    print(f"# bench_throughput ({bench.machine()})")
    if args.quick:
        result = bench.throughput(
            sizes=(1, 100, 10_000, 100_000),
            methods=("rk4", "exact"),
            work=2e6,
            repeats=args.repeats,
        )
    else:
        result = bench.throughput(repeats=args.repeats)
    print(result.table())
    if args.plot:
        os.makedirs(args.plot, exist_ok=True)
        print(f"wrote {bench.plot_throughput(result, os.path.join(args.plot, 'throughput.png'))}")


if __name__ == "__main__":
    main()
