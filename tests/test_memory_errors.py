"""Memory that runs out is a MemoryError that says what to ask for instead, never an abort.

Each case runs in a fresh process whose address space is capped (``RLIMIT_AS``) just above what
it uses once its input is built and polhode's thread pool is started: the input fits, what the
call must allocate for the input's size (its outputs, its working memory) does not. The child
makes the call, then a small call of the same function (the process goes on), and prints the
outcome. Before the fallible allocation these calls aborted the interpreter (signal 6, "memory
allocation of N bytes failed") or raised ``PanicException: PyObject pointer is null`` (numpy's
output arrays); ``benchmarks/memory_limits.py`` runs the same calls at full size under
``ulimit -v``.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

resource = pytest.importorskip("resource")

pytestmark = pytest.mark.skipif(
    sys.platform != "linux" or not hasattr(resource, "RLIMIT_AS"),
    reason="RLIMIT_AS caps the address space on Linux only",
)

#: The child: `build` makes the input, a small call starts the thread pool, then the address
#: space is capped at what the process has mapped plus HEADROOM, and `call` is made.
CHILD = textwrap.dedent(
    """
    import json, resource
    import numpy as np
    import polhode as ph
    from polhode._meshes import merge_vertices

    def torus(n):
        u = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        uu, vv = np.meshgrid(u, u, indexing="ij")
        r = 3.0 + np.cos(vv)
        vertices = np.stack([r * np.cos(uu), r * np.sin(uu), np.sin(vv)], -1).reshape(-1, 3)
        i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        a, b = i * n + j, ((i + 1) % n) * n + j
        c, d = ((i + 1) % n) * n + (j + 1) % n, i * n + (j + 1) % n
        faces = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)])
        return np.ascontiguousarray(vertices), faces.reshape(-1, 3).astype(np.int64)

    def mapped():
        with open("/proc/self/status") as status:
            line = next(line for line in status if line.startswith("VmSize:"))
        return int(line.split()[1]) * 1024

    {build}
    # Start the thread pool (a batch runs on it) and the call's own path once, uncapped.
    ph.simulate(np.tile([1.0, 2.0, 3.0], (64, 1)), np.ones((64, 3)), 1.0)
    {small}
    limit = mapped() + {headroom}
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    try:
        {call}
        outcome, message = "returned", ""
    except MemoryError as error:
        outcome, message = "MemoryError", str(error)
    except BaseException as error:
        outcome, message = type(error).__name__, str(error)
    {small}
    print(json.dumps({{"outcome": outcome, "message": message}}))
    """
)

#: 16 MiB above what the process has mapped: room for the call's small allocations, not for its
#: input-sized ones (each case asks for 100 MB or more).
HEADROOM = 16 << 20

#: name -> (build, call, small call, words the message must hold).
CASES = {
    "principal": (
        "x = np.tile(np.diag([1.0, 2.0, 3.0]), (1_500_000, 1, 1))",
        "ph.principal(x)",
        "ph.principal(np.eye(3))",
        ("principal moments", "fewer tensors"),
    ),
    "principal, continuous": (
        "x = np.tile(np.diag([1.0, 2.0, 3.0]), (1_500_000, 1, 1))",
        "ph.principal(x, continuous=True)",
        "ph.principal(np.tile(np.eye(3), (2, 1, 1)), continuous=True)",
        ("principal moments", "fewer tensors"),
    ),
    "point_masses_inertia": (
        "x = np.zeros((2_000_000, 1, 3), dtype=np.float32)",
        "ph.point_masses_inertia([1.0], x)",
        "ph.point_masses_inertia([1.0, 2.0], np.eye(3)[:2])",
        ("inertia tensors of the frames", "fewer frames"),
    ),
    "Body.mesh": (
        "v, f = torus(1500)",
        "ph.Body.mesh(v, f, density=1.0)",
        "ph.Body.mesh(*torus(8), density=1.0)",
        ("working memory of the mesh", "fewer faces"),
    ),
    "Body.mesh, open": (
        "v, f = torus(1500); f = f[1:]",
        "ph.Body.mesh(v, f, density=1.0)",
        "ph.Body.mesh(*torus(8), density=1.0)",
        ("working memory of the mesh", "fewer faces"),
    ),
    "merge_vertices": (
        "v, f = torus(1200); soup = np.ascontiguousarray(v[f].reshape(-1, 3)); "
        "faces = np.arange(len(soup), dtype=np.int64).reshape(-1, 3); del v, f",
        "merge_vertices(soup, faces)",
        "merge_vertices(np.eye(3), np.array([[0, 1, 2]]))",
        ("mesh", "fewer faces"),
    ),
    "simulate, many bodies": (
        "m = np.tile([1.0, 2.0, 3.0], (3_000_000, 1)); w = np.tile([0.1, 1.0, 0.1], "
        "(3_000_000, 1))",
        "ph.simulate(m, w, [0.0, 1.0], method='exact')",
        "ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], 1.0)",
        ("bodies", "polhode.dask"),
    ),
    "simulate, many output times": (
        "t = np.linspace(0.0, 10.0, 2_000_000)",
        "ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], t, method='exact')",
        "ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], 1.0)",
        ("the outputs", "fewer output times", "polhode.dask"),
    ),
}


@pytest.mark.parametrize("name", CASES)
def test_an_allocation_that_does_not_fit_is_a_memory_error_and_the_process_goes_on(name):
    build, call, small, words = CASES[name]
    code = CHILD.format(build=build, call=call, small=small, headroom=HEADROOM)
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=False
    )
    # An abort ends the child by a signal (returncode < 0), a panic with a traceback.
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr[-2000:]}"
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["outcome"] == "MemoryError", result
    message = result["message"]
    assert message.startswith("Cannot allocate "), message
    for word in words:
        assert word in message, message
