"""The ``polhode`` command line: ``polhode demo`` (the default), ``polhode spin`` and
``polhode bench``."""

from __future__ import annotations

import argparse
import csv
import sys
from typing import Any

import numpy as np

import polhode as ph
from polhode.invariants import max_relative_drift

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
        ("uniform cube (1 kg, 0.1 m) about its centre", ph.Body.cuboid(1.0, [0.1, 0.1, 0.1])),
        ("cylinder (2 kg, r 0.05 m, L 0.4 m)", ph.Body.cylinder(2.0, 0.05, 0.4)),
        ("T-handle (two cylinders, kg and m)", t_handle),
        ("water molecule (u and angstrom)", water),
    ]


def _demo(args: argparse.Namespace) -> int:
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
    if not args.no_plots:
        _demo_plots(args.out)
    return 0


def _demo_plots(out: str) -> None:
    """PNG plots of the T-handle's flip, in principal axes, written into ``out``."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("\n(plots skipped: matplotlib is not installed; pip install 'polhode[plot]')")
        return
    import os

    from polhode import plot

    t_handle = dict(_bodies())["T-handle (two cylinders, kg and m)"]
    p = t_handle.principal()
    spin = 10.0 * p.axes[:, 1] + 1e-3 * p.axes[:, 0]
    omega_p = p.axes.T @ spin  # the same motion in principal axes, where the polhode lives
    a = ph.analyze(p.moments, omega_p)
    t = np.linspace(0.0, 3.2 * a.flip_interval, 4001)
    exact = ph.simulate(p.moments, omega_p, t, method="exact")
    split = ph.simulate(p.moments, omega_p, t, method="splitting", dt=1e-3, order=4)
    os.makedirs(out, exist_ok=True)
    written = []
    for name, ax in (
        ("flip_omega.png", plot.omega(exact)),
        ("flip_drift_splitting.png", plot.drift(split)),
        ("flip_polhode.png", plot.polhode(traj=exact)),
        ("flip_herpolhode.png", plot.herpolhode(exact)),
    ):
        path = os.path.join(out, name)
        ax.figure.savefig(path, dpi=100)
        written.append(path)
    # Near the stable axis of least inertia: the expansion's error falls like eps^(n+1).
    ax = plot.perturbation_error(p.moments, axis=0)
    path = os.path.join(out, "perturbation_error.png")
    ax.figure.savefig(path, dpi=100)
    written.append(path)
    print(f"\nplots written: {', '.join(written)}")


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
        drift = max_relative_drift(sol)
        print(
            f"  {method:10s}      {crossings.size} flips, every {interval:.4f} s; "
            f"max |dT/T| {drift['energy']:.1e}, "
            f"max |dL/L| {drift['angular_momentum_space']:.1e}, "
            f"{sol.stats['wall_time'] * 1e3:.1f} ms"
        )


SOLIDS = {
    "sphere": ("mass", "radius"),
    "spherical_shell": ("mass", "radius"),
    "cuboid": ("mass", "a", "b", "c"),
    "cylinder": ("mass", "radius", "length"),
    "tube": ("mass", "inner_radius", "outer_radius", "length"),
    "cone": ("mass", "radius", "length"),
    "ellipsoid": ("mass", "a", "b", "c"),
    "torus": ("mass", "major_radius", "minor_radius"),
    "capsule": ("mass", "radius", "length"),
}


def _solid(words: list[str]) -> ph.Body:
    """A solid from ``KIND NAME=VALUE ...``, e.g. ``cylinder mass=1 radius=0.1 length=0.5``."""
    kind, *pairs = words
    if kind not in SOLIDS:
        raise ph.PolhodeError(
            f"Expected `--body` to name one of {', '.join(SOLIDS)}, got {kind!r}."
        )
    values: dict[str, float] = {}
    for pair in pairs:
        name, _, value = pair.partition("=")
        try:
            values[name] = float(value)
        except ValueError:
            raise ph.PolhodeError(
                f"Expected `--body` parameters as NAME=NUMBER, got {pair!r}."
            ) from None
    expected = SOLIDS[kind]
    if sorted(values) != sorted(expected):
        raise ph.PolhodeError(
            f"Expected `--body {kind}` to give {' '.join(n + '=...' for n in expected)}, "
            f"got {' '.join(pairs) or 'nothing'}."
        )
    args = [values[n] for n in expected]
    if kind in ("cuboid", "ellipsoid"):
        return getattr(ph.Body, kind)(args[0], args[1:])
    return getattr(ph.Body, kind)(*args)


def _spin(args: argparse.Namespace) -> int:
    body: Any = _solid(args.body) if args.body else np.array(args.moments, dtype=float)
    omega0 = np.array(args.omega, dtype=float)
    times = np.linspace(0.0, args.t, args.points)
    options: dict[str, Any] = {"method": args.method, "rtol": args.rtol, "order": args.order}
    if args.dt is not None:
        options["dt"] = args.dt
    a = ph.analyze(body, omega0)
    sol = ph.simulate(body, omega0, times, **options)
    assert sol.quaternion is not None
    np.set_printoptions(precision=6, suppress=True)
    print(f"principal moments  {a.moments}")
    print(f"regime             {a.regime}; axis stability {', '.join(a.axis_stability)}")
    if a.period is not None:
        print(f"period             {a.period:.9g}   (omega in the body)")
    if a.flip_interval is not None:
        print(f"flip interval      {a.flip_interval:.9g}")
    if a.precession_rate is not None:
        print(f"precession rate    {a.precession_rate:.9g}   (symmetric top, body frame)")
    print(f"omega at t = {args.t:g}  {sol.omega[-1]}")
    print(
        f"method {sol.stats['method']}: {sol.stats['steps']} steps, "
        f"{sol.stats['evaluations']} evaluations, {sol.stats['wall_time'] * 1e3:.2f} ms"
    )
    drift = max_relative_drift(sol)
    print("invariant drift (max relative error over the run):")
    print(f"  energy T         {drift['energy']:.2e}")
    print(f"  |L|              {drift['angular_momentum_norm']:.2e}")
    print(f"  L in space       {drift['angular_momentum_space']:.2e}")
    if args.plot:
        _spin_plot(sol, args.plot)
    if args.csv:
        with open(args.csv, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["t", "omega_x", "omega_y", "omega_z", "qx", "qy", "qz", "qw"])
            for row in np.column_stack([sol.t, sol.omega, sol.quaternion]):
                writer.writerow([repr(float(x)) for x in row])
        print(f"trajectory written to {args.csv}")
    return 0


def _spin_plot(sol: ph.Trajectory, path: str) -> None:
    """omega against time and the invariant drift, side by side, into one PNG."""
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise ph.PolhodeError(
            "Expected matplotlib for `--plot`; pip install 'polhode[plot]'."
        ) from None
    from polhode import plot

    figure = Figure(figsize=(12, 4.5), layout="constrained")
    left, right = figure.subplots(1, 2)
    plot.omega(sol, ax=left)
    plot.drift(sol, ax=right)
    figure.savefig(path, dpi=100)
    print(f"plot written to {path}")


def _bench(args: argparse.Namespace) -> int:
    from polhode import bench

    if args.repeats is not None and args.repeats < 1:
        raise ph.PolhodeError(f"Expected `--repeats` to be at least 1, got {args.repeats}.")
    bench.run(quick=args.quick, repeats=args.repeats)
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="polhode", description="Rigid-body rotation.")
    commands = parser.add_subparsers(dest="command")
    demo = commands.add_parser(
        "demo", help="principal axes of a few bodies and the tennis-racket flip of a T-handle"
    )
    demo.add_argument(
        "--out", default="polhode-demo", help="folder for the PNG plots (default ./polhode-demo)"
    )
    demo.add_argument("--no-plots", action="store_true", help="print only, write no PNG")
    demo.set_defaults(run=_demo)
    spin = commands.add_parser(
        "spin",
        help="simulate one torque-free body and report its motion and invariant drift",
        description="Simulate one torque-free body. Give --moments or --body.",
    )
    source = spin.add_mutually_exclusive_group(required=True)
    source.add_argument("--moments", nargs=3, type=float, metavar=("I1", "I2", "I3"))
    source.add_argument(
        "--body",
        nargs="+",
        metavar="KIND NAME=VALUE",
        help="a solid, e.g. 'cylinder mass=1 radius=0.1 length=0.5' (kinds: "
        + ", ".join(SOLIDS)
        + ")",
    )
    spin.add_argument("--omega", nargs=3, type=float, required=True, metavar=("W1", "W2", "W3"))
    spin.add_argument("--t", type=float, required=True, help="end time")
    spin.add_argument("--points", type=int, default=1001, help="output times (default 1001)")
    spin.add_argument("--method", default="auto", choices=ph.simulation.METHODS)
    spin.add_argument("--dt", type=float, help="step of the fixed-step methods")
    spin.add_argument("--order", type=int, default=4, choices=(2, 4, 6))
    spin.add_argument("--rtol", type=float, default=1e-10)
    spin.add_argument("--csv", help="write t, omega and the quaternion (xyzw) to this file")
    spin.add_argument("--plot", help="write omega and the invariant drift to this PNG")
    spin.set_defaults(run=_spin)
    bench_parser = commands.add_parser(
        "bench",
        help="speed against error, polhode against scipy, MuJoCo, numpy and trimesh",
        description="Run the benchmark suite and print its tables (benchmarks/ in the source "
        "tree has the full suite and the report).",
    )
    bench_parser.add_argument("--quick", action="store_true", help="under a minute")
    bench_parser.add_argument("--repeats", type=int, help="repeats per setting (default 3/5)")
    bench_parser.set_defaults(run=_bench)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status (2 for bad arguments, never a traceback)."""
    parser = _parser()
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    if args.command is None:
        args = parser.parse_args(["demo"])
    if getattr(args, "points", 2) < 2:
        parser.error("argument --points: expected at least 2")
    try:
        result: int = args.run(args)
    except (ValueError, TypeError) as error:  # PolhodeError is a ValueError
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 1
    return result
