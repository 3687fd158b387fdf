"""Speed against error: the benchmark suite behind ``polhode bench`` and ``benchmarks/``.

Every measurement runs polhode and its peers in the same process, alternating between them in
each repeat so that the machine's noise falls on all alike, and keeps every repeat: tables
quote medians with the spread. Errors of the motion are measured against
:data:`~polhode.bench.motion.REFERENCE`, an independent 30-digit reference, never against
another double-precision approximation, polhode's exact solution included.

The peers are optional: scipy (a dependency), MuJoCo and trimesh (the ``bench`` extra); a
series whose peer is not installed is left out and named in the result's ``skipped``.

Modules: :mod:`~polhode.bench.adapters` (the peers, called as their users would),
:mod:`~polhode.bench.motion` (work-precision, drift, throughput), :mod:`~polhode.bench.mass`
(eigensolve, point masses, meshes), :mod:`~polhode.bench.plots` (the figures). Their public
names are re-exported here. :mod:`~polhode.bench.kernels` (each kernel against its peer and
the hardware's limits, ``polhode bench --kernels``) is imported by name. ``import polhode``
does not import this package.
"""

from __future__ import annotations

import os
import platform
from collections.abc import Callable
from typing import Any

import numpy as np

from polhode._version import __version__
from polhode.bench.mass import Versus, eigensolve, mesh, mesh_offset, point_masses
from polhode.bench.motion import (
    CASES,
    REFERENCE,
    WARM_BELOW,
    Case,
    Drift,
    Point,
    Series,
    Throughput,
    WorkPrecision,
    best_at,
    cost_at,
    drift,
    targets,
    throughput,
    work_precision,
)
from polhode.bench.plots import plot_drift, plot_throughput, plot_work_precision

__all__ = [
    "CASES",
    "REFERENCE",
    "WARM_BELOW",
    "Case",
    "Drift",
    "Point",
    "Series",
    "Throughput",
    "Versus",
    "WorkPrecision",
    "best_at",
    "cost_at",
    "drift",
    "eigensolve",
    "machine",
    "mesh",
    "mesh_offset",
    "peers",
    "plot_drift",
    "plot_throughput",
    "plot_work_precision",
    "point_masses",
    "run",
    "targets",
    "throughput",
    "work_precision",
]


def machine() -> str:
    """One line naming the machine and the versions of polhode and numpy."""
    cpu = platform.processor() or platform.machine()
    return (
        f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {np.__version__}, polhode {__version__}"
    )


def peers() -> str:
    """The versions of the peers that are installed."""
    import importlib.metadata as metadata

    found = []
    for name in ("scipy", "mujoco", "trimesh", "matplotlib"):
        try:
            found.append(f"{name} {metadata.version(name)}")
        except metadata.PackageNotFoundError:
            found.append(f"{name} not installed")
    return ", ".join(found)


def run(
    quick: bool = True, repeats: int | None = None, print_: Callable[[str], Any] = print
) -> None:
    """Runs the suite and prints its tables: work-precision on the flip case with the ratios at
    matching error, batch throughput, eigensolve, point masses and (with trimesh) meshes.
    ``quick`` keeps it under a minute."""
    repeats = (3 if quick else 5) if repeats is None else repeats
    print_(f"# polhode bench{' --quick' if quick else ''} ({machine()})")
    print_(f"# peers: {peers()}\n")
    wp = work_precision("flip", quick=quick, repeats=repeats, budget=1.0 if quick else 3.0)
    print_("## Work-precision, one body, torque-free, errors against the exact solution")
    print_(wp.table())
    for which in ("omega", "orientation"):
        print_(
            f"\nCost to reach each error of the {which} (ms, interpolated), and how many times "
            "faster polhode is:"
        )
        print_(targets(wp, which=which))
    sizes = (1, 100, 10_000, 100_000) if quick else (1, 10, 100, 1_000, 10_000, 100_000, 10**6)
    print_("\n## Batch throughput on all cores")
    tp = throughput(
        sizes=sizes,
        methods=("rk4", "exact") if quick else ("rk4", "splitting", "midpoint", "dop853", "exact"),
        work=2e6 if quick else 2e7,
        repeats=repeats,
    )
    print_(tp.table())
    print_("\n## Mass properties")
    for v in eigensolve(100_000 if quick else 1_000_000, repeats):
        print_(v.table())
    print_(point_masses(1_000_000 if quick else 10_000_000, repeats).table())
    m = mesh(5 if quick else 7, repeats)
    print_("(trimesh not installed: mesh comparison left out)" if m is None else m.table())
