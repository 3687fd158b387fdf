"""The ``polhode`` command line: ``polhode demo`` (the default), ``polhode spin`` and
``polhode bench``."""

from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time
from collections.abc import Callable
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


class UsageError(Exception):
    """A bad command line found after parsing: exit status 2 with a message naming ``option``."""

    def __init__(self, option: str, message: str):
        super().__init__(f"argument {option}: {message}")
        self.option = option


def _demo(args: argparse.Namespace) -> int:
    plots = not args.no_plots and _plots_available()
    if plots:
        _check_folder("--out", args.out)
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
    if plots:
        _demo_plots(args.out)
    elif not args.no_plots:
        print("\n(plots skipped: matplotlib is not installed; pip install 'polhode[plot]')")
    return 0


def _plots_available() -> bool:
    """Whether matplotlib imports (imported now, so that no run times its import)."""
    try:
        import matplotlib.figure  # noqa: F401
    except ImportError:
        return False
    return True


def _demo_plots(out: str) -> None:
    """PNG plots of the T-handle's flip, in principal axes, written into ``out``."""
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
    written.append(_flip_animation(t_handle, spin, a.flip_interval, out))
    print(f"\nplots written: {', '.join(written)}")


#: Frames of the demo's animation (two flips): enough to see the handle turn over, few enough
#: that the demo stays quick (about 0.1 s a frame).
ANIMATION_FRAMES = 40


def _flip_animation(body: ph.Body, spin: Any, flip_interval: float, out: str) -> str:
    """``tennis_racket.gif``: the T-handle's flip in space, L pointing up."""
    from scipy.spatial.transform import Rotation

    from polhode import plot

    # Turn the body so that its angular momentum points along the space z axis.
    up, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [body.angular_momentum_body(spin)])
    t = np.linspace(0.0, 2.2 * flip_interval, 4 * ANIMATION_FRAMES)
    sol = ph.simulate(body, spin, t, orientation0=up)
    path = os.path.join(out, "tennis_racket.gif")
    plot.animate(sol, body, frames=ANIMATION_FRAMES, interval=80, path=path)
    return path


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

#: The methods that take a fixed step ``--dt``; ``--order`` is the splitting's, ``--rtol``
#: dop853's.
FIXED_STEP = ("splitting", "midpoint", "rk4")

#: At most this many output times (the trajectory, 8 numbers a time, is kept in memory).
MAX_POINTS = 10_000_000


def _solid(words: list[str]) -> ph.Body:
    """A solid from ``KIND NAME=VALUE ...``, e.g. ``cylinder mass=1 radius=0.1 length=0.5``."""
    kind, *pairs = words
    if kind not in SOLIDS:
        raise UsageError("--body", f"expected one of {', '.join(SOLIDS)}, got {kind!r}.")
    expected = SOLIDS[kind]
    takes = f"{kind} takes {', '.join(expected)} (as NAME=NUMBER)"
    values: dict[str, float] = {}
    for pair in pairs:
        name, equals, value = pair.partition("=")
        if not equals:
            raise UsageError("--body", f"expected NAME=NUMBER, got {pair!r}; {takes}.")
        if name not in expected:
            raise UsageError("--body", f"unknown key {name!r} for {kind}; {takes}.")
        if name in values:
            raise UsageError("--body", f"{name} is given twice; {takes}.")
        try:
            values[name] = float(value)
        except ValueError:
            raise UsageError("--body", f"expected NAME=NUMBER, got {pair!r}; {takes}.") from None
    missing = [n for n in expected if n not in values]
    if missing:
        raise UsageError("--body", f"missing {', '.join(missing)}; {takes}.")
    args = [values[n] for n in expected]
    try:
        if kind in ("cuboid", "ellipsoid"):
            return getattr(ph.Body, kind)(args[0], args[1:])
        return getattr(ph.Body, kind)(*args)
    except ph.PolhodeError as error:
        raise UsageError("--body", f"{kind}: {error}") from None


def _check_file(option: str, path: str) -> None:
    """That ``path`` can be written (its folder exists and is writable, it is not a folder),
    by creating it now; a file that did not exist is removed again."""
    if not path:
        raise UsageError(option, "expected a file name, got ''.")
    existed = os.path.lexists(path)
    if os.path.isdir(path):
        raise UsageError(option, f"{path!r} is a folder, expected a file name.")
    try:
        with open(path, "a"):
            pass
    except OSError as error:
        raise UsageError(option, f"cannot write {path!r}: {error.strerror}.") from None
    if not existed:
        os.remove(path)


def _check_folder(option: str, path: str) -> None:
    """That the folder ``path`` exists and is writable, or can be created."""
    if not path:
        raise UsageError(option, "expected a folder name, got ''.")
    folder = os.path.abspath(path)
    while not os.path.exists(folder):
        folder = os.path.dirname(folder)
    if not os.path.isdir(folder):
        raise UsageError(option, f"cannot create the folder {path!r}: {folder!r} is a file.")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(option, f"cannot write into {folder!r} (permission denied).")


def _check_plot(path: str) -> None:
    """matplotlib importable (imported now, before the run is timed) and a file it can write."""
    if not _plots_available():
        raise UsageError("--plot", "needs matplotlib: pip install 'polhode[plot]'.")
    from matplotlib.backend_bases import FigureCanvasBase

    formats = FigureCanvasBase.get_supported_filetypes()
    extension = os.path.splitext(path)[1].lstrip(".").lower()
    if extension not in formats:
        raise UsageError(
            "--plot",
            "expected an image file name ending in .png or another format matplotlib writes "
            f"(.{', .'.join(sorted(set(formats) - {'png'}))}), got {path!r}.",
        )
    _check_file("--plot", path)


def _check_spin(args: argparse.Namespace) -> None:
    """The combinations argparse cannot check, and the output files, before any work."""
    method = args.method
    if args.dt is not None and method not in FIXED_STEP:
        raise UsageError(
            "--dt",
            f"applies to {', '.join(FIXED_STEP[:-1])} and {FIXED_STEP[-1]} only (fixed steps), "
            f"not to --method {method}.",
        )
    if args.dt is None and method in FIXED_STEP:
        raise UsageError("--dt", f"--method {method} takes a fixed step: give --dt.")
    if args.order is not None and method != "splitting":
        raise UsageError("--order", f"applies to --method splitting only, not to {method}.")
    if args.rtol is not None and method != "dop853":
        raise UsageError(
            "--rtol",
            f"applies to --method dop853 only, not to {method}"
            + (" (the exact solution, without a torque)." if method == "auto" else "."),
        )
    if args.csv is not None:
        _check_file("--csv", args.csv)
    if args.plot is not None:
        _check_plot(args.plot)
        if args.csv is not None and os.path.abspath(args.csv) == os.path.abspath(args.plot):
            raise UsageError("--plot", f"{args.plot!r} is also the --csv file.")


def _breaks_triangle(moments: np.ndarray) -> bool:
    """Whether I1 + I2 >= I3 fails beyond rounding (the tolerance of Body.from_inertia)."""
    half_trace = float(np.sum(moments)) / 2
    return half_trace - float(np.max(moments)) < -16 * np.finfo(float).eps * half_trace


def _spin(args: argparse.Namespace) -> int:
    _check_spin(args)
    if args.body:
        body: Any = _solid(args.body)
        source = "--body"
    else:
        body = np.array(args.moments, dtype=float)
        source = "--moments"
    options: dict[str, Any] = {"method": args.method}
    if args.dt is not None:
        options["dt"] = args.dt
    if args.order is not None:
        options["order"] = args.order
    if args.rtol is not None:
        options["rtol"] = args.rtol
    omega0 = np.array(args.omega, dtype=float)
    times = np.linspace(0.0, args.t, args.points)
    option_of = {"body": source, "omega0": "--omega", "t": "--t", "dt": "--dt", "rtol": "--rtol"}
    try:
        a = ph.analyze(body, omega0)
        started = time.perf_counter()
        sol = ph.simulate(body, omega0, times, **options)
        elapsed = time.perf_counter() - started
    except ph.PolhodeError as error:
        if error.argument in option_of:
            raise UsageError(option_of[error.argument], str(error)) from None
        raise
    assert sol.quaternion is not None
    if source == "--moments" and _breaks_triangle(body):
        print(
            f"polhode spin: note: the moments {' '.join(f'{m:g}' for m in body)} break "
            "I1 + I2 >= I3: Euler's equations hold for them, but no mass distribution has them.",
            file=sys.stderr,
        )
    rest = a.regime == "rest"
    np.set_printoptions(precision=6, suppress=True)
    print(f"principal moments  {a.moments}")
    if rest:
        print("regime             rest (omega0 = 0: the body stays at rest)")
    else:
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
        f"{sol.stats['evaluations']} evaluations, {elapsed * 1e3:.2f} ms"
    )
    drift = max_relative_drift(sol)
    if rest:
        # T, |L| and L are all zero: the drift is the absolute error (polhode.invariants).
        print("invariant drift (max absolute error over the run; at rest all are zero):")
    else:
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
    """omega against time and the invariant drift, side by side, into one image."""
    from matplotlib.figure import Figure

    from polhode import plot

    figure = Figure(figsize=(12, 4.5), layout="constrained")
    left, right = figure.subplots(1, 2)
    plot.omega(sol, ax=left)
    plot.drift(sol, ax=right)
    figure.savefig(path, dpi=100)
    print(f"plot written to {path}")


def _bench(args: argparse.Namespace) -> int:
    from polhode import bench

    bench.run(quick=args.quick, repeats=args.repeats)
    return 0


def _number(
    what: str, *, minimum: float | None = None, positive: bool = False, below: float | None = None
) -> Callable[[str], float]:
    """An argparse type: a finite float, optionally >= minimum, > 0 or < below."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.") from None
        if (
            not math.isfinite(value)
            or (minimum is not None and value < minimum)
            or (positive and value <= 0)
            or (below is not None and value >= below)
        ):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.")
        return value

    return parse


def _integer(what: str, minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """An argparse type: an integer in [minimum, maximum]."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.") from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.")
        return value

    return parse


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="polhode", description="Rigid-body rotation.")
    parser.add_argument("--version", action="version", version=f"polhode {ph.__version__}")
    commands = parser.add_subparsers(dest="command")
    demo = commands.add_parser(
        "demo", help="principal axes of a few bodies and the tennis-racket flip of a T-handle"
    )
    demo.add_argument(
        "--out",
        default="polhode-demo",
        help="folder for the PNG plots and tennis_racket.gif (default ./polhode-demo)",
    )
    demo.add_argument("--no-plots", action="store_true", help="print only, write no file")
    demo.set_defaults(run=_demo)
    spin = commands.add_parser(
        "spin",
        help="simulate one torque-free body and report its motion and invariant drift",
        description="Simulate one torque-free body. Give --moments or --body.",
    )
    source = spin.add_mutually_exclusive_group(required=True)
    source.add_argument(
        "--moments",
        nargs=3,
        type=_number("a positive finite number (a principal moment)", positive=True),
        metavar=("I1", "I2", "I3"),
        help="principal moments (any positive numbers; Euler's equations need no more)",
    )
    source.add_argument(
        "--body",
        nargs="+",
        metavar="KIND NAME=VALUE",
        help="a solid, e.g. 'cylinder mass=1 radius=0.1 length=0.5' (kinds and keys: "
        + "; ".join(f"{kind} {' '.join(keys)}" for kind, keys in SOLIDS.items())
        + ")",
    )
    spin.add_argument(
        "--omega",
        nargs=3,
        type=_number("a finite number (a component of omega0, in body axes)"),
        required=True,
        metavar=("W1", "W2", "W3"),
    )
    spin.add_argument(
        "--t", type=_number("a finite end time >= 0", minimum=0.0), required=True, help="end time"
    )
    spin.add_argument(
        "--points",
        type=_integer(f"an integer from 2 to {MAX_POINTS}", 2, MAX_POINTS),
        default=1001,
        help="output times (default 1001)",
    )
    spin.add_argument("--method", default="auto", choices=ph.simulation.METHODS)
    spin.add_argument(
        "--dt",
        type=_number("a positive finite step", positive=True),
        help="step of the fixed-step methods (splitting, midpoint, rk4; required by them)",
    )
    spin.add_argument(
        "--order", type=int, choices=(2, 4, 6), help="order of --method splitting (default 4)"
    )
    spin.add_argument(
        "--rtol",
        type=_number("a finite tolerance between 0 and 1", positive=True, below=1.0),
        help="relative tolerance of --method dop853 (default 1e-10)",
    )
    spin.add_argument("--csv", help="write t, omega and the quaternion (xyzw) to this file")
    spin.add_argument("--plot", help="write omega and the invariant drift to this image (.png)")
    spin.set_defaults(run=_spin)
    bench_parser = commands.add_parser(
        "bench",
        help="speed against error, polhode against scipy, MuJoCo, numpy and trimesh",
        description="Run the benchmark suite and print its tables (benchmarks/ in the source "
        "tree has the full suite and the report).",
    )
    bench_parser.add_argument("--quick", action="store_true", help="under a minute")
    bench_parser.add_argument(
        "--repeats",
        type=_integer("an integer >= 1", 1),
        help="repeats per setting (default 3/5)",
    )
    bench_parser.set_defaults(run=_bench)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status: 0, 2 for bad arguments (with a message on
    stderr, never a traceback), 1 when writing an output fails, 130 on Ctrl-C."""
    parser = _parser()
    try:
        args = parser.parse_args(sys.argv[1:] if argv is None else argv)
        if args.command is None:
            args = parser.parse_args(["demo"])
    except SystemExit as stop:  # argparse: --help, --version, or a message and status 2
        return stop.code if isinstance(stop.code, int) else 0 if stop.code is None else 2
    try:
        result: int = args.run(args)
    except UsageError as error:
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 2
    except (ValueError, TypeError) as error:  # PolhodeError is a ValueError
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"polhode {args.command}: interrupted", file=sys.stderr)
        return 130
    return result
