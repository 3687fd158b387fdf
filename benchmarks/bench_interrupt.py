"""How fast Ctrl-C stops a long polhode call, and how fast polhode.dask's workers go idle after it.

    python -m benchmarks.bench_interrupt [--quick] [--repeats R] [--scale S] [--only NAME ...]
        [--no-dask]

Each long call is first run to its end once (its wall and CPU time), then R times interrupted:
a helper thread waits until the call has used a fraction f of that CPU time (f spread over
0.1 .. 0.9 across the repeats, so that the signal lands in every phase of the call, its
conversions included), sends SIGINT to the process and notes the time; the latency is from
there to the KeyboardInterrupt in the main thread. The table gives the median and the largest.

The calls (``--scale`` multiplies their size; ``--quick`` is a tenth, 3 repeats): a single-body
exact run with 1e7 output times, ``principal`` on 1e7 tensors, ``Body.point_masses`` with 1e7
points, ``Body.mesh`` of a torus with 1.8e7 faces, and a batch of 2000 bodies with each method
(2000 outputs for the exact solution, 2e4 steps of 0.01 for the fixed-step methods).

The Dask case (threaded scheduler, 2 workers, blocks of one body that take seconds each): SIGINT
once every worker is inside its polhode call; after the KeyboardInterrupt, the time until every
polhode call running in a worker thread has ended (``idle``), and the CPU time the process
spends in the second after the interrupt (``CPU/s``; 2.0 would be two busy workers).
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import polhode as ph


def torus(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed torus mesh of 2 n^2 faces (n x n quads), wound outward."""
    u = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    uu, vv = np.meshgrid(u, u, indexing="ij")
    r = 3.0 + np.cos(vv)
    vertices = np.stack([r * np.cos(uu), r * np.sin(uu), np.sin(vv)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = i * n + j
    b = ((i + 1) % n) * n + j
    c = ((i + 1) % n) * n + (j + 1) % n
    d = i * n + (j + 1) % n
    faces = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    return np.ascontiguousarray(vertices), faces.astype(np.int64)


def calls(scale: float) -> dict[str, Callable[[], Any]]:
    """The long calls, their inputs made once."""
    rng = np.random.default_rng(0)
    out: dict[str, Callable[[], Any]] = {}
    m = int(1e7 * scale)
    t_exact = np.linspace(0.0, 1e5, m)
    out[f"exact, 1 body, {m:.0e} outputs"] = lambda: ph.simulate(
        (1.0, 2.0, 3.0), (0.3, 1.0, 0.2), t_exact, method="exact"
    )
    n = int(1e7 * scale)
    base = rng.normal(size=(1000, 3, 3))
    tensors = np.ascontiguousarray(np.tile(base + base.transpose(0, 2, 1), (n // 1000, 1, 1)))
    out[f"principal, {n:.0e} tensors"] = lambda: ph.principal(tensors)
    masses = rng.uniform(0.5, 1.0, n)
    positions = rng.normal(size=(n, 3))
    out[f"point_masses, {n:.0e} points"] = lambda: ph.Body.point_masses(masses, positions)
    vertices, faces = torus(int(3000 * scale**0.5))
    out[f"mesh, {len(faces):.0e} faces"] = lambda: ph.Body.mesh(vertices, faces, density=1.0)
    n_batch = 2000
    moments = rng.uniform(1.0, 3.0, (n_batch, 3))
    omega0 = rng.normal(size=(n_batch, 3))
    t_batch = np.linspace(0.0, 200.0 * scale, 11)
    methods: dict[str, dict[str, Any]] = {
        "exact": {"t": np.linspace(0.0, 1e3, int(2000 * scale)), "orientation": False},
        "splitting": {"dt": 0.01},
        "midpoint": {"dt": 0.01},
        "rk4": {"dt": 0.01},
        "dop853": {"rtol": 1e-12},
    }
    for method, options in methods.items():
        options = {"t": t_batch, **options}

        def run(method: str = method, options: dict[str, Any] = options) -> Any:
            return ph.simulate(moments, omega0, method=method, **options)

        out[f"batch of {n_batch}, {method}"] = run
    return out


def interrupted(call: Callable[[], Any], cpu_at: float) -> float | None:
    """Runs `call`, sends SIGINT once the process has used `cpu_at` s of CPU since the start;
    the latency from the signal to KeyboardInterrupt (None if the call ended first)."""
    done = threading.Event()
    sent: list[float] = []

    def sender() -> None:
        cpu0 = time.process_time()
        while not done.is_set():
            if time.process_time() - cpu0 >= cpu_at:
                sent.append(time.perf_counter())
                os.kill(os.getpid(), signal.SIGINT)
                return
            time.sleep(0.002)

    thread = threading.Thread(target=sender)
    returned = False
    try:
        try:
            thread.start()
            call()
            returned = True
        finally:
            caught = time.perf_counter()
            done.set()
            thread.join()
        time.sleep(0.05)  # a signal sent as the call returned is raised here
    except KeyboardInterrupt:
        pass
    return None if returned or not sent else caught - sent[0]


def measure_calls(names: list[str] | None, repeats: int, scale: float) -> None:
    print(f"{'call':36s} {'full (s)':>9s} {'CPU (s)':>8s} {'median':>8s} {'max':>8s}  (latency)")
    for name, call in calls(scale).items():
        if names and not any(pattern in name for pattern in names):
            continue
        wall0, cpu0 = time.perf_counter(), time.process_time()
        call()
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        latencies = []
        for k in range(repeats):
            fraction = 0.1 + 0.8 * k / max(repeats - 1, 1)
            latency = interrupted(call, fraction * cpu)
            if latency is not None:
                latencies.append(latency)
        if latencies:
            text = f"{statistics.median(latencies):8.3f} {max(latencies):8.3f}"
        else:
            text = f"{'-':>8s} {'-':>8s}"
        missed = repeats - len(latencies)
        note = f"  ({missed} ended before the signal)" if missed else ""
        print(f"{name:36s} {wall:9.2f} {cpu:8.2f} {text}{note}", flush=True)


def measure_dask(repeats: int) -> None:
    import dask

    import polhode.dask as phd

    # One rk4 body per block, 1e8 steps: several seconds of work per block.
    n = 8
    moments = np.tile([1.0, 2.0, 3.0], (n, 1))
    omega0 = np.tile([0.1, 1.0, 0.1], (n, 1))
    lock = threading.Lock()
    running: dict[int, float] = {}
    under_way = threading.Event()
    original = ph.simulate

    def watched(*args: Any, **kwargs: Any) -> Any:
        key = threading.get_ident()
        with lock:
            running[key] = time.perf_counter()
        try:
            return original(*args, **kwargs)
        finally:
            with lock:
                running.pop(key, None)

    def progress(fraction: float) -> None:
        with lock:
            if len(running) >= 2 and fraction > 0:
                under_way.set()

    idle, rates = [], []
    ph.simulate = watched  # type: ignore[assignment]
    try:
        for _ in range(repeats):
            under_way.clear()
            traj = phd.simulate(
                moments, omega0, 1e6, method="rk4", dt=1e-2, chunks=1, progress=progress
            )

            def sender() -> None:
                under_way.wait()
                os.kill(os.getpid(), signal.SIGINT)

            thread = threading.Thread(target=sender)
            thread.start()
            try:
                with dask.config.set(num_workers=2):
                    traj.compute(scheduler="threads")
                raise RuntimeError("the compute ended before the signal")
            except KeyboardInterrupt:
                caught, cpu0 = time.perf_counter(), time.process_time()
            thread.join()
            while True:
                with lock:
                    if not running:
                        break
                if time.perf_counter() - caught > 300:
                    raise RuntimeError("the workers are still busy after 300 s")
                time.sleep(0.001)
            idle.append(time.perf_counter() - caught)
            time.sleep(max(0.0, 1.0 - (time.perf_counter() - caught)))
            rates.append((time.process_time() - cpu0) / (time.perf_counter() - caught))
    finally:
        ph.simulate = original  # type: ignore[assignment]
    print(
        f"dask threads, 2 workers: idle after {statistics.median(idle):.3f} s "
        f"(max {max(idle):.3f}); CPU/s in the next second {statistics.median(rates):.2f} "
        f"(max {max(rates):.2f})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--only", nargs="*", default=None)
    parser.add_argument("--no-dask", action="store_true")
    parser.add_argument("--quick", action="store_true", help="--scale 0.1 --repeats 3")
    args = parser.parse_args()
    if args.quick:
        args.scale, args.repeats = 0.1, 3
    signal.signal(signal.SIGINT, signal.default_int_handler)
    print(f"# bench_interrupt: {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    measure_calls(args.only, args.repeats, args.scale)
    if not args.no_dask:
        measure_dask(args.repeats)


if __name__ == "__main__":
    main()
