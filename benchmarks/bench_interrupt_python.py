"""How fast Ctrl-C stops polhode's long Python-side paths (numpy work, no Rust loop to watch).

    python -m benchmarks.bench_interrupt_python [--repeats R] [--scale S] [--only NAME ...]

As ``benchmarks.bench_interrupt``: each call is run to its end once (its wall and CPU time),
then R times interrupted, the signal sent once the process has used a fraction f of that CPU
time (f spread over 0.1 .. 0.9). For each, the CPU time the process used from the signal to
the KeyboardInterrupt (what the call still did: robust on a loaded machine) and the wall time;
the table gives the median and the largest of each, and how often the interrupt was lost (the
call returned although signalled well before its end).

The calls (``--scale`` multiplies their size): ``perturbation`` at 5e7 times,
``Trajectory.euler_angles`` of 1.5e7 times, ``invariants.relative_drift`` of 1.5e7 times and
``Trajectory.orientation``'s rotations. The import of trimesh by ``Body.from_file`` (its
``except BaseException`` lost the interrupt) is measured in fresh processes: the signal once
``trimesh`` is being imported and the process has used 0 to 0.3 s more CPU.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import polhode as ph
from polhode.invariants import relative_drift


def calls(scale: float) -> dict[str, Callable[[], Any]]:
    out: dict[str, Callable[[], Any]] = {}
    n = int(5e7 * scale)
    t = np.linspace(0.0, 10.0, n)
    out[f"perturbation, {n:.1e} times"] = lambda: ph.perturbation(
        (1.0, 2.0, 3.0), (1e-3, -2e-3, 1.0), t
    )
    m = int(1.5e7 * scale)
    traj = ph.simulate((1.0, 2.0, 3.0), (0.3, 1.0, 0.2), np.linspace(0.0, 1e4, m))
    out[f"euler_angles, {m:.1e} times"] = lambda: traj.euler_angles()
    out[f"relative_drift, {m:.1e} times"] = lambda: relative_drift(traj)
    return out


def interrupted(call: Callable[[], Any], cpu_at: float) -> tuple[bool, float, float]:
    """(returned, CPU after the signal, wall after the signal)."""
    done = threading.Event()
    sent: dict[str, float] = {}

    def sender() -> None:
        cpu0 = time.process_time()
        while not done.is_set():
            if time.process_time() - cpu0 >= cpu_at:
                sent["wall"], sent["cpu"] = time.perf_counter(), time.process_time()
                os.kill(os.getpid(), signal.SIGINT)
                return
            time.sleep(0.001)

    thread = threading.Thread(target=sender)
    returned = False
    try:
        try:
            thread.start()
            call()
            returned = True
        finally:
            wall, cpu = time.perf_counter(), time.process_time()
            done.set()
            thread.join()
        time.sleep(0.05)
    except KeyboardInterrupt:
        pass
    if "wall" not in sent:
        return returned, float("nan"), float("nan")
    return returned, cpu - sent["cpu"], wall - sent["wall"]


def row(name: str, full: tuple[float, float] | None, records: list[tuple[bool, float, float]]):
    cpus = [c for r, c, _ in records if not r and c == c]
    walls = [w for r, _, w in records if not r and w == w]
    lost = sum(1 for r, c, _ in records if r and c == c)
    head = f"{name:40s} " + (f"{full[0]:8.2f} {full[1]:8.2f} " if full else f"{'':8s} {'':8s} ")
    if cpus:
        head += (
            f"{statistics.median(cpus):8.3f} {max(cpus):8.3f} "
            f"{statistics.median(walls):8.3f} {max(walls):8.3f}"
        )
    print(head + f" {lost:5d}/{len(records)}", flush=True)


def measure_calls(names: list[str] | None, repeats: int, scale: float) -> None:
    for name, call in calls(scale).items():
        if names and not any(pattern in name for pattern in names):
            continue
        wall0, cpu0 = time.perf_counter(), time.process_time()
        call()
        wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
        records = []
        for k in range(repeats):
            fraction = 0.1 + 0.8 * k / max(repeats - 1, 1)
            records.append(interrupted(call, fraction * cpu))
        row(name, (wall, cpu), records)


_IMPORT_PROBE = r"""
import json, os, signal, sys, threading, time
delay, path = float(sys.argv[1]), sys.argv[2]
import polhode as ph
signal.signal(signal.SIGINT, signal.default_int_handler)
sent = {}
def sender():
    while "trimesh" not in sys.modules:
        time.sleep(0.0002)
    cpu0 = time.process_time()
    while time.process_time() - cpu0 < delay:
        time.sleep(0.0002)
    sent["wall"], sent["cpu"] = time.perf_counter(), time.process_time()
    os.kill(os.getpid(), signal.SIGINT)
threading.Thread(target=sender, daemon=True).start()
returned = False
try:
    try:
        ph.Body.from_file(path, density=1.0)
        returned = True
    finally:
        wall, cpu = time.perf_counter(), time.process_time()
    time.sleep(0.05)
except KeyboardInterrupt:
    pass
print(json.dumps([returned, cpu - sent["cpu"], wall - sent["wall"]]))
"""


def measure_import(repeats: int) -> None:
    """Body.from_file of a small STL in fresh processes, signalled during trimesh's import."""
    import trimesh

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "ball.stl")
        trimesh.creation.icosphere(subdivisions=2).export(path)
        records = []
        for k in range(repeats):
            delay = 0.3 * k / max(repeats - 1, 1)
            # Not check=True: a KeyboardInterrupt that left code run by PyRun_String inside an
            # extension's import (then caught) makes CPython end the process by SIGINT once
            # done (its "unhandled_keyboard_interrupt" flag), after the line printed here.
            done = subprocess.run(
                [sys.executable, "-c", _IMPORT_PROBE, str(delay), path],
                capture_output=True,
                text=True,
                check=False,
            )
            records.append(tuple(json.loads(done.stdout.strip().splitlines()[-1])))
        row("Body.from_file: trimesh's import", None, records)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--only", nargs="*", default=None)
    args = parser.parse_args()
    signal.signal(signal.SIGINT, signal.default_int_handler)
    print(f"# bench_interrupt_python: {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    print(
        f"{'call':40s} {'full (s)':>8s} {'CPU (s)':>8s} {'CPU med':>8s} {'CPU max':>8s} "
        f"{'wall med':>8s} {'wall max':>8s} {'lost':>5s}  (after the signal)"
    )
    if not args.only or any("import" in name for name in args.only):
        measure_import(args.repeats)
    measure_calls(args.only, args.repeats, args.scale)


if __name__ == "__main__":
    main()
