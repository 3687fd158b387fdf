"""The kernels against the hardware: a roofline of each kernel beside its peer, in one run.

    python -m benchmarks.bench_kernels [--quick] [--repeats R] [--only GROUP ...]

Each row of :mod:`polhode.bench.kernels`: polhode's time per element, the peer's in the same
run (medians of R >= 5 interleaved repeats), their ratio against the target, the flops and
bytes per element and the fraction of the machine's limit (its memory bandwidth measured
first, its peak flop rate from the CPU's vector width). ``--quick``: a tenth of the sizes;
``--only``: some of the groups of rows (eigensolve, mesh, point_masses, exact, batch,
small_calls).
"""

from __future__ import annotations

import argparse

from polhode import bench
from polhode.bench import kernels


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument(
        "--only", nargs="+", choices=kernels.GROUPS, help="only these groups of rows"
    )
    args = parser.parse_args()
    print(f"# bench_kernels{' --quick' if args.quick else ''} ({bench.machine()})")
    print(f"# peers: {bench.peers()}\n")
    print(kernels.run(quick=args.quick, repeats=args.repeats, only=args.only).table())


if __name__ == "__main__":
    main()
