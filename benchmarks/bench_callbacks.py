"""How fast a batch with Python callbacks stops: at the first exception of a callback, and at
Ctrl-C.

    python -m benchmarks.bench_callbacks [--repeats R] [--only NAME ...]

Each case is a batch whose every body calls Python at every stage: a torque ``Function``
(``rk4``, ``splitting``, ``dop853``) or a ``Wheel(torque=callable)`` (``dop853``), run in a
fresh process (``python -c``), so that the signal and the counts are its own.

- ``raise``: the callback raises at its 1000th call (a count shared by every body); the table
  gives the number of calls made until the exception reached the caller (the whole batch makes
  about N x the calls of one body) and the time from the raise to the caller.
- ``SIGINT``: the process signals itself from a helper thread once the callback has been called
  2000 times; the table gives the time from the signal to the KeyboardInterrupt and the calls
  made after it.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import textwrap

#: name -> (bodies, method, "torque" or "wheel", end time, step).
CASES: dict[str, tuple[int, str, str, float, float]] = {
    "16 bodies, torque Function, rk4": (16, "rk4", "torque", 20.0, 1e-3),
    "16 bodies, torque Function, splitting": (16, "splitting", "torque", 20.0, 1e-3),
    "16 bodies, torque Function, dop853": (16, "dop853", "torque", 2000.0, 0.0),
    "16 bodies, Wheel(torque=callable), dop853": (16, "dop853", "wheel", 2000.0, 0.0),
    "64 bodies, torque Function, rk4": (64, "rk4", "torque", 20.0, 1e-3),
    "2 bodies, torque Function, splitting": (2, "splitting", "torque", 200.0, 1e-3),
    "64 bodies, Wheel(torque=callable), dop853": (64, "dop853", "wheel", 2000.0, 0.0),
}

#: The child: runs one case in `mode` ("raise" or "sigint") and prints a JSON line.
CHILD = textwrap.dedent(
    """
    import json, os, signal, sys, threading, time
    import numpy as np
    import polhode as ph

    n, method, kind, end, dt, mode = json.loads(sys.argv[1])
    signal.signal(signal.SIGINT, signal.default_int_handler)
    state = {"calls": 0, "at": None, "calls_at": None}

    def note():
        state["calls"] += 1
        if mode == "raise" and state["calls"] == 1000:
            state["at"] = time.perf_counter()
            raise ZeroDivisionError("the 1000th call")

    def torque(t, w, q):
        note()
        return (0.0, 0.0, 1e-3)

    def motor(t, w, rate):
        note()
        return 1e-3

    rng = np.random.default_rng(1)
    moments = rng.uniform(1.0, 3.0, (n, 3))
    omega0 = rng.normal(size=(n, 3))
    options = {"method": method}
    if dt:
        options["dt"] = dt
    if kind == "torque":
        options["torque"] = ph.torque.Function(torque)
    else:
        options["rotors"] = [ph.rotors.Wheel([0.0, 0.0, 1.0], inertia=0.1, torque=motor)]
        options["rtol"] = 1e-12

    def sender():
        while state["calls"] < 2000:
            time.sleep(0.0005)
        state["calls_at"] = state["calls"]
        state["at"] = time.perf_counter()
        os.kill(os.getpid(), signal.SIGINT)

    if mode == "sigint":
        threading.Thread(target=sender, daemon=True).start()
    outcome = "returned"
    try:
        ph.simulate(moments, omega0, np.linspace(0.0, end, 11), **options)
    except (ZeroDivisionError, KeyboardInterrupt) as error:
        outcome = f"{type(error).__name__}: {error}"
    ended = time.perf_counter()
    latency = None if state["at"] is None else ended - state["at"]
    after = None if state["calls_at"] is None else state["calls"] - state["calls_at"]
    print(json.dumps({"outcome": outcome, "calls": state["calls"], "latency": latency,
                      "after": after}))
    """
)


def run(case: tuple[int, str, str, float, float], mode: str, timeout: float = 120.0) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps([*case, mode])],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    lines = done.stdout.strip().splitlines()
    if done.returncode != 0 or not lines:
        return {"outcome": f"exit {done.returncode}: {done.stderr.strip()[-300:]}"}
    return json.loads(lines[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--only", nargs="*", help="cases whose name contains any of these")
    args = parser.parse_args()
    for name, case in CASES.items():
        if args.only and not any(part in name for part in args.only):
            continue
        for mode in ("raise", "sigint"):
            results = [run(case, mode) for _ in range(args.repeats)]
            latencies = [r["latency"] for r in results if r.get("latency") is not None]
            outcomes = sorted({r["outcome"] for r in results})
            calls = [r.get("calls") for r in results]
            after = [r.get("after") for r in results]
            figure = (
                f"latency median {statistics.median(latencies):.3f} s, max {max(latencies):.3f} s"
                if latencies
                else "no latency"
            )
            extra = f"calls {calls}" if mode == "raise" else f"calls after the signal {after}"
            print(f"{name}, {mode}: {figure}; {extra}; {'; '.join(outcomes)}", flush=True)


if __name__ == "__main__":
    main()
