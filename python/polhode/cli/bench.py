"""``polhode bench``: the benchmark suite (polhode.bench), or its kernels against the hardware."""

from __future__ import annotations

import argparse


def run(args: argparse.Namespace) -> int:
    from polhode import bench

    if args.kernels:
        from polhode.bench import kernels

        print(f"# polhode bench --kernels{' --quick' if args.quick else ''} ({bench.machine()})")
        print(f"# peers: {bench.peers()}\n")
        print(kernels.run(quick=args.quick, repeats=args.repeats or 5).table())
        return 0
    bench.run(quick=args.quick, repeats=args.repeats)
    return 0
