"""The ``polhode`` command line: ``polhode demo`` (the default)."""

from __future__ import annotations

import argparse
import sys

import numpy as np

import polhode as ph

__all__ = ["main"]


def _bodies() -> list[tuple[str, ph.Body]]:
    """A few bodies a student meets first, built with the body API."""
    handle = ph.Body.cylinder(0.30, 0.01, 0.20)  # the T-handle's shaft, along z
    bar = ph.Body.cylinder(0.20, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    t_handle = handle + bar.translated([0.0, 0.0, 0.10])
    # Water: O at the origin, H at 0.9572 A with an H-O-H angle of 104.52 degrees.
    half = np.radians(104.52) / 2
    water = ph.Body.point_masses(
        [15.999, 1.008, 1.008],
        [
            [0.0, 0.0, 0.0],
            [0.9572 * np.sin(half), 0.0, 0.9572 * np.cos(half)],
            [-0.9572 * np.sin(half), 0.0, 0.9572 * np.cos(half)],
        ],
    )
    return [
        ("uniform cube (1 kg, 0.1 m) about its centre", ph.Body.box(1.0, [0.1, 0.1, 0.1])),
        ("cylinder (2 kg, r 0.05 m, L 0.4 m)", ph.Body.cylinder(2.0, 0.05, 0.4)),
        ("T-handle (two cylinders, kg and m)", t_handle),
        ("water molecule (u and angstrom)", water),
    ]


def _demo(_: argparse.Namespace) -> int:
    np.set_printoptions(precision=6, suppress=True)
    print("polhode: principal moments (ascending) and axes (columns) about the centre of mass\n")
    for name, body in _bodies():
        p = body.principal()
        print(f"{name}")
        print(f"  mass            {body.mass:.6g}")
        print(f"  centre of mass  {body.center_of_mass}")
        print(f"  moments         {p.moments}   multiplicity {p.multiplicity}")
        for row in np.array2string(p.axes).splitlines():
            print(
                f"  axes            {row}" if row.startswith("[[") else f"                  {row}"
            )
        print()
    _flip_demo()
    return 0


def _flip_demo() -> None:
    """The tennis-racket flip of the T-handle: predicted, observed, and what is conserved."""
    t_handle = dict(_bodies())["T-handle (two cylinders, kg and m)"]
    p = t_handle.principal()
    spin = 10.0 * p.axes[:, 1] + 1e-3 * p.axes[:, 0]  # rad/s about the intermediate axis, nudged
    a = ph.analyze(t_handle, spin)
    print("T-handle spun at 10 rad/s about its intermediate axis, nudged by 1e-3 rad/s")
    print(f"  regime          {a.regime}; axis stability {', '.join(a.axis_stability)}")
    print(f"  predicted       a flip every {a.flip_interval:.4f} s (period {a.period:.4f} s)")
    t = np.linspace(0.0, 5.5 * a.flip_interval, 20001)
    for method, options in (("exact", {}), ("splitting", {"dt": 1e-3, "order": 4})):
        sol = ph.simulate(t_handle, spin, t, method=method, **options)
        along = sol.omega @ p.axes[:, 1]
        crossings = t[1:][np.sign(along[1:]) != np.sign(along[:-1])]
        interval = float(np.mean(np.diff(crossings))) if crossings.size > 1 else float("nan")
        energy = float(np.max(np.abs(sol.energy / sol.energy[0] - 1)))
        assert sol.angular_momentum is not None
        l_space = sol.angular_momentum
        drift = float(
            np.max(np.linalg.norm(l_space - l_space[0], axis=1)) / np.linalg.norm(l_space[0])
        )
        print(
            f"  {method:10s}      {crossings.size} flips, every {interval:.4f} s; "
            f"max |dT/T| {energy:.1e}, max |dL/L| {drift:.1e}, "
            f"{sol.stats['wall_time'] * 1e3:.1f} ms"
        )


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = argparse.ArgumentParser(prog="polhode", description="Rigid-body rotation.")
    commands = parser.add_subparsers(dest="command")
    demo = commands.add_parser(
        "demo", help="principal axes of a few bodies and the tennis-racket flip of a T-handle"
    )
    demo.set_defaults(run=_demo)
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    if args.command is None:
        return _demo(args)
    result: int = args.run(args)
    return result
