"""The cost of polhode.dask against one polhode.simulate call on the same batch, on one machine.

    python -m benchmarks.bench_dask [--n N] [--repeats R] [--blocks B] [--cluster]

N random bodies (default 1e5), rk4 with dt = 0.01 to t = 10 (1000 steps each), 11 output times,
with orientation. Timed, whole calls with the result in numpy: polhode.simulate;
polhode.dask.simulate(...).compute() on the threaded scheduler in one block and in B blocks;
with --cluster, on a LocalCluster of one single-threaded worker process per core. The variants
take turns, R rounds, so that a load that comes and goes hits them alike; the table gives the
median wall time and, in process, the median CPU time (all threads).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import time

import numpy as np

import polhode as ph


def main() -> None:
    import polhode.dask as phd

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--blocks", type=int, default=8)
    parser.add_argument("--cluster", action="store_true")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    moments = np.sort(rng.uniform(1.0, 4.0, (args.n, 3)), axis=1)
    omega0 = rng.normal(size=(args.n, 3))
    t = np.linspace(0.0, 10.0, 11)
    options = {"method": "rk4", "dt": 0.01}
    chunks = -(-args.n // args.blocks)

    def lazy(chunks=None):
        return phd.simulate(moments, omega0, t, chunks=chunks, **options)

    variants = {
        "polhode.simulate": lambda: ph.simulate(moments, omega0, t, **options),
        "dask, threads, 1 block": lambda: lazy().compute(scheduler="threads"),
        f"dask, threads, {args.blocks} blocks": lambda: lazy(chunks).compute(scheduler="threads"),
    }
    with contextlib.ExitStack() as stack:
        if args.cluster:
            from distributed import Client, LocalCluster

            cluster = stack.enter_context(
                LocalCluster(threads_per_worker=1, processes=True, dashboard_address=None)
            )
            client = stack.enter_context(Client(cluster))
            name = f"dask, LocalCluster {len(cluster.workers)} workers, {args.blocks} blocks"
            variants[name] = lambda: lazy(chunks).compute(scheduler=client)
            lazy(chunks).compute(scheduler=client)  # warm the workers (imports)
        wall: dict[str, list[float]] = {name: [] for name in variants}
        cpu: dict[str, list[float]] = {name: [] for name in variants}
        for _ in range(args.repeats):
            for name, run in variants.items():
                started, cpu_started = time.perf_counter(), time.process_time()
                run()
                wall[name].append(time.perf_counter() - started)
                cpu[name].append(time.process_time() - cpu_started)
    cores = os.cpu_count()
    print(f"# bench_dask: N = {args.n}, rk4 dt = 0.01 to t = 10, 11 outputs, {cores} cores")
    plain_wall = statistics.median(wall["polhode.simulate"])
    plain_cpu = statistics.median(cpu["polhode.simulate"])
    print(f"{'':44s} {'wall (s)':>9s} {'vs plain':>9s} {'CPU (s)':>9s} {'vs plain':>9s}")
    for name in variants:
        w, c = statistics.median(wall[name]), statistics.median(cpu[name])
        cpu_text = (
            f"{c:9.2f} {c / plain_cpu:8.2f}x" if "Cluster" not in name else f"{'-':>9s} {'':9s}"
        )
        print(f"{name:44s} {w:9.2f} {w / plain_wall:8.2f}x {cpu_text}")
    print(f"(median of {args.repeats}; wall times spread {spread(wall)})")


def spread(times: dict[str, list[float]]) -> str:
    """The largest relative spread (max - min) / median over the variants."""
    worst = max((max(v) - min(v)) / statistics.median(v) for v in times.values())
    return f"up to {100 * worst:.0f}% of the median"


if __name__ == "__main__":
    main()
