"""What polhode does when the memory runs out: each call under a ``ulimit -v`` limit.

    python -m benchmarks.memory_limits [--only NAME ...]

Each case runs in a fresh process (``bash -c "ulimit -v KB; exec python ..."``) whose address
space is capped so that its input fits and what the call must allocate for its size (its
outputs, its working memory) does not. The process builds its input, makes the call, and then
makes a small call of the same function to show that it can go on. The outcome is one of:
``MemoryError: <message>`` (wanted: the message says what to ask for instead), ``returned``
(the call fitted after all), another exception (a ``PanicException`` is a bug), or ``killed by
signal N`` (an abort: "memory allocation of ... failed").
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import textwrap

import numpy as np

from benchmarks.bench_interrupt import torus

#: name -> (limit in MiB, code that builds the input, the call, a small call after it).
CASES: dict[str, tuple[int, str, str, str]] = {
    "principal, 2e7 tensors": (
        2600,
        "x = np.tile(np.diag([1.0, 2.0, 3.0]), (20_000_000, 1, 1))",
        "ph.principal(x)",
        "ph.principal(np.eye(3))",
    ),
    "principal(continuous=True), 2e7 tensors": (
        2600,
        "x = np.tile(np.diag([1.0, 2.0, 3.0]), (20_000_000, 1, 1))",
        "ph.principal(x, continuous=True)",
        "ph.principal(np.tile(np.eye(3), (2, 1, 1)), continuous=True)",
    ),
    "point_masses_inertia, 2.5e7 frames": (
        1500,
        "x = np.zeros((25_000_000, 1, 3), dtype=np.float32)",
        "ph.point_masses_inertia([1.0], x)",
        "ph.point_masses_inertia([1.0, 2.0], np.eye(3)[:2])",
    ),
    "point_masses_inertia, one frame of 3e7 points": (
        1500,
        "x = np.zeros((1, 30_000_000, 3), dtype=np.float32); x[0, :, 0] = 1.0; x[0, 1, 0] = 0.0\n"
        "m = np.ones(30_000_000)",
        "ph.point_masses_inertia(m, x)",
        "ph.point_masses_inertia([1.0, 2.0], np.eye(3)[:2])",
    ),
    "Body.point_masses, 3e7 points": (
        1800,
        "r = np.random.default_rng(0).normal(size=(30_000_000, 3)); m = np.ones(30_000_000)",
        "ph.Body.point_masses(m, r)",
        "ph.Body.point_masses([1.0, 2.0], np.eye(3)[:2])",
    ),
    "Body.mesh, 1.8e7 faces": (
        1200,
        "v, f = load('torus')",
        "ph.Body.mesh(v, f, density=1.0)",
        "ph.Body.mesh(*torus(8), density=1.0)",
    ),
    "Body.mesh open (the closedness check merges and welds), 1.8e7 faces": (
        1200,
        "v, f = load('torus'); f = f[1:]",
        "ph.Body.mesh(v, f, density=1.0)",
        "ph.Body.mesh(*torus(8), density=1.0)",
    ),
    "merge_vertices (a triangle soup), 2e7 faces": (
        2300,
        "from polhode._meshes import merge_vertices\nsoup, faces = load('soup')",
        "merge_vertices(soup, faces)",
        "merge_vertices(np.eye(3), np.array([[0, 1, 2]]))",
    ),
    "simulate, 1e7 bodies (moments per body)": (
        2000,
        "m = np.tile([1.0, 2.0, 3.0], (10_000_000, 1)); w = np.tile([0.1, 1.0, 0.1], "
        "(10_000_000, 1))",
        "ph.simulate(m, w, [0.0, 1.0], method='exact')",
        "ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], 1.0)",
    ),
    "simulate, one body at 3e7 output times": (
        2000,
        "t = np.linspace(0.0, 10.0, 30_000_000)",
        "ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], t, method='exact')",
        "ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], 1.0)",
    ),
}

CHILD = """
import json, os, sys
import numpy as np
import polhode as ph
from benchmarks.bench_interrupt import torus

def load(name):
    with np.load(os.path.join(os.environ["POLHODE_INPUTS"], name + ".npz")) as data:
        return [data[key] for key in sorted(data.files)]

{build}
try:
    {call}
    outcome = "returned"
except MemoryError as error:
    outcome = f"MemoryError: {{error}}"
except BaseException as error:
    outcome = f"{{type(error).__module__}}.{{type(error).__name__}}: {{error}}"
{after}
print(json.dumps({{"outcome": outcome, "after": "the next call ran"}}))
"""


def prepare(directory: str) -> None:
    """The meshes, made once without a limit (numpy's temporaries would not fit under it):
    a closed torus of 1.8e7 faces, and a triangle soup of 2e7 faces (STL's layout: every
    triangle its own three vertices)."""
    v, f = torus(3000)
    np.savez(os.path.join(directory, "torus.npz"), a=v, b=f)
    v, f = torus(3163)
    soup = np.ascontiguousarray(v[f].reshape(-1, 3))
    del v, f
    faces = np.arange(len(soup), dtype=np.int64).reshape(-1, 3)
    np.savez(os.path.join(directory, "soup.npz"), a=soup, b=faces)


def run(name: str, directory: str) -> dict[str, str]:
    limit, build, call, after = CASES[name]
    code = CHILD.format(build=build, call=call, after=after)
    done = subprocess.run(
        ["bash", "-c", f'ulimit -v {limit * 1024}; exec "$0" -c "$1"', sys.executable, code],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "POLHODE_INPUTS": directory},
    )
    lines = done.stdout.strip().splitlines()
    if done.returncode == 0 and lines:
        return {"limit": f"{limit} MiB", **json.loads(lines[-1])}
    errors = done.stderr.strip().splitlines() or [""]
    said = next((line for line in errors if "memory allocation" in line), errors[-1])
    how = (
        f"killed by signal {-done.returncode}" if done.returncode < 0 else
        f"exit {done.returncode}"
    )
    return {"limit": f"{limit} MiB", "outcome": f"{how}: {said}", "after": "-"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", help="cases whose name contains one of these")
    args = parser.parse_args()
    names = [n for n in CASES if not args.only or any(o in n for o in args.only)]
    with tempfile.TemporaryDirectory() as directory:
        if any("load(" in CASES[n][1] for n in names):
            prepare(directory)
        for name in names:
            report(name, run(name, directory))


def report(name: str, result: dict[str, str]) -> None:
    print(f"{name} (ulimit -v {result['limit']}):")
    print(textwrap.indent(textwrap.fill(result["outcome"], 96), "    "))
    print(f"    after: {result['after']}", flush=True)


if __name__ == "__main__":
    main()
