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
    return 0


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = argparse.ArgumentParser(prog="polhode", description="Rigid-body rotation.")
    commands = parser.add_subparsers(dest="command")
    demo = commands.add_parser("demo", help="principal moments and axes of a few bodies")
    demo.set_defaults(run=_demo)
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    if args.command is None:
        return _demo(args)
    result: int = args.run(args)
    return result
