"""The ``polhode`` command line: ``polhode demo`` (the default), ``polhode spin``,
``polhode inertia``, ``polhode audit`` and ``polhode bench``."""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import polhode as ph
from polhode import _core
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
    print()
    _damper_demo()
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
    # The major-axis rule: T falls at fixed |L|, the polhode spirals to the largest axis.
    damped, _ = _damped()
    for name, ax in (
        ("damper_energy.png", plot.dissipation(damped)),
        ("damper_polhode.png", plot.polhode(traj=damped)),
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


#: The major-axis rule: a body spun about its smallest axis with a spherical damper inside
#: (the moments include the damper locked).
DAMPED = {"moments": (1.0, 4.0, 5.0), "omega0": (2.0, 0.01, 0.01), "inertia": 0.2, "damping": 0.1}


def _damped() -> tuple[ph.Trajectory, ph.Analysis]:
    """The damped spin of :data:`DAMPED` over about 13 growth times, and its analysis (with
    the damper's nutation rate and time constant)."""
    damper = ph.rotors.SphericalDamper(DAMPED["inertia"], DAMPED["damping"])
    t = np.linspace(0.0, 400.0, 4001)
    sol = ph.simulate(DAMPED["moments"], DAMPED["omega0"], t, rotors=[damper])
    return sol, ph.analyze(DAMPED["moments"], DAMPED["omega0"], rotors=[damper])


def _damper_demo() -> None:
    """The major-axis rule: a damper drains T at fixed |L| until the body spins about its
    largest axis."""
    sol, analysis = _damped()
    rate, time_constant = analysis.nutation_rate, analysis.nutation_time_constant
    assert rate is not None and time_constant is not None
    moments = np.asarray(DAMPED["moments"])
    ell = np.linalg.norm(sol.angular_momentum_space, axis=1)
    l2 = ell[0] ** 2
    crossing = sol.t[np.argmax(sol.energy < l2 / (2 * moments[1]))]
    w = sol.omega[-1]
    print(
        f"A body with moments {' '.join(f'{m:g}' for m in moments)} spun at "
        f"{DAMPED['omega0'][0]:g} rad/s about its smallest axis, with a spherical damper "
        f"(J {DAMPED['inertia']:g}, c {DAMPED['damping']:g})"
    )
    print(
        f"  predicted       the nutation grows at {rate:.4f} /s "
        f"(e-folding time {time_constant:.1f} s), linearised"
    )
    print(
        f"  energy          T {sol.energy[0]:.4f} -> {sol.energy[-1]:.4f}; crosses the "
        f"separatrix L^2/(2 I2) at t = {crossing:.0f} s; the largest axis's L^2/(2 I3) = "
        f"{l2 / (2 * moments[2]):.4f}"
    )
    print(
        f"  angular momentum |L| fixed to {np.max(np.abs(ell / ell[0] - 1)):.1e}; at "
        f"t = {sol.t[-1]:g} s omega = {np.array2string(w, precision=4)} (about the largest axis)"
    )


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


#: The solids ``--body`` takes and their keys, from the core's table: ``mass``, then each
#: parameter, a vector one (a cuboid's size, an ellipsoid's semi-axes) as its x, y, z
#: components ``a b c``.
SOLIDS = {
    kind: ("mass", *(n for name, width in p for n in ((name,) if width == 1 else ("a", "b", "c"))))
    for kind, p in _core.SOLIDS.items()
}

#: The methods that take a fixed step ``--dt``; ``--order`` is the splitting's, ``--rtol``
#: dop853's.
FIXED_STEP = tuple(name for name, stepping in _core.METHODS.items() if stepping == "fixed")

#: At most this many output times (the trajectory, 8 numbers a time, is kept in memory).
MAX_POINTS = 10_000_000


#: ``--body mesh``: the file, exactly one of density and mass, and optionally scale and shell.
MESH_KEYS = ("path", "density", "mass", "scale", "shell")


def _key_values(
    pairs: list[str], allowed: Any, kind: str, takes: str, form: str
) -> dict[str, str]:
    """``--body``'s ``NAME=VALUE`` words as a dict: each name one of ``allowed``, once."""
    values: dict[str, str] = {}
    for pair in pairs:
        name, equals, value = pair.partition("=")
        if not equals:
            raise UsageError("--body", f"expected {form}, got {pair!r}; {takes}.")
        if name not in allowed:
            raise UsageError("--body", f"unknown key {name!r} for {kind}; {takes}.")
        if name in values:
            raise UsageError("--body", f"{name} is given twice; {takes}.")
        values[name] = value
    return values


def _mesh(pairs: list[str]) -> ph.Body:
    """A body from a mesh file: ``mesh path=FILE density=D`` (or ``mass=M``), optionally
    ``scale=S`` and ``shell=true``."""
    takes = "mesh takes path=FILE and density=NUMBER or mass=NUMBER, optionally scale=NUMBER "
    takes += "and shell=true"
    values = _key_values(pairs, MESH_KEYS, "mesh", takes, "NAME=VALUE")
    if "path" not in values:
        raise UsageError("--body", f"missing path; {takes}.")
    if ("density" in values) == ("mass" in values):
        given = "both" if "density" in values else "neither"
        raise UsageError("--body", f"give exactly one of density and mass, got {given}; {takes}.")
    numbers: dict[str, float] = {}
    for name in ("density", "mass", "scale"):
        if name in values:
            try:
                numbers[name] = float(values[name])
            except ValueError:
                raise UsageError(
                    "--body", f"expected {name}=NUMBER, got {name}={values[name]}; {takes}."
                ) from None
    shell = values.get("shell", "false").lower()
    if shell not in ("true", "false"):
        raise UsageError("--body", f"expected shell=true or shell=false, got shell={shell}.")
    try:
        return ph.Body.from_file(
            values["path"],
            density=numbers.get("density"),
            mass=numbers.get("mass"),
            scale=numbers.get("scale", 1.0),
            shell=shell == "true",
        )
    except (ph.PolhodeError, OSError, ImportError) as error:
        raise UsageError("--body", f"mesh: {error}") from None


def _solid(words: list[str]) -> ph.Body:
    """A solid from ``KIND NAME=VALUE ...``, e.g. ``cylinder mass=1 radius=0.1 length=0.5``,
    or a mesh file, ``mesh path=part.stl density=2700``."""
    kind, *pairs = words
    if kind == "mesh":
        return _mesh(pairs)
    if kind not in SOLIDS:
        raise UsageError("--body", f"expected one of {', '.join(SOLIDS)} or mesh, got {kind!r}.")
    expected = SOLIDS[kind]
    takes = f"{kind} takes {', '.join(expected)} (as NAME=NUMBER)"
    values: dict[str, float] = {}
    for name, value in _key_values(pairs, expected, kind, takes, "NAME=NUMBER").items():
        try:
            values[name] = float(value)
        except ValueError:
            raise UsageError(
                "--body", f"expected NAME=NUMBER, got {f'{name}={value}'!r}; {takes}."
            ) from None
    missing = [n for n in expected if n not in values]
    if missing:
        raise UsageError("--body", f"missing {', '.join(missing)}; {takes}.")
    parameters: dict[str, Any] = {}
    for name, width in _core.SOLIDS[kind]:
        parameters[name] = values[name] if width == 1 else [values[k] for k in ("a", "b", "c")]
    try:
        return ph.Body.solid(kind, values["mass"], **parameters)
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


def _check_spin(args: argparse.Namespace) -> list[ph.rotors.Rotor]:
    """The combinations argparse cannot check, the rotors and the output files, before any
    work; returns the rotors (wheels first, then dampers, each in the order given)."""
    method = args.method
    rotors = _spin_rotors(args)
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
    if args.rtol is not None and method != "dop853" and not (method == "auto" and rotors):
        raise UsageError(
            "--rtol",
            f"applies to --method dop853 only (what auto picks with --wheel or --damper), not "
            f"to {method}"
            + (" (the exact solution, without rotors)." if method == "auto" else "."),
        )
    if rotors:
        _check_rotor_method(args, rotors)
    if args.csv is not None:
        _check_file("--csv", args.csv)
    if args.plot is not None:
        _check_plot(args.plot)
        if args.csv is not None and os.path.abspath(args.csv) == os.path.abspath(args.plot):
            raise UsageError("--plot", f"{args.plot!r} is also the --csv file.")
    return rotors


#: ``--wheel AX AY AZ INERTIA [RATE0 [TORQUE]]``: the fields of :class:`polhode.rotors.Wheel`
#: in order (the torque a constant); ``--damper INERTIA DAMPING``: those of
#: :class:`polhode.rotors.SphericalDamper`.
WHEEL_FIELDS = ("ax", "ay", "az", "inertia", "rate0", "torque")
DAMPER_FIELDS = ("inertia", "damping")


class _Group(argparse.Action):
    """An option taking ``fewest`` to ``len(names)`` numbers, repeatable: one group of numbers
    (one rotor) per use, appended in order."""

    def __init__(self, *args: Any, names: tuple[str, ...], fewest: int, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.names, self.fewest = names, fewest

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: Any,
        option_string: str | None = None,
    ) -> None:
        most = len(self.names)
        if not self.fewest <= len(values) <= most:
            optional = self.names[self.fewest :]
            form = " ".join(n.upper() for n in self.names[: self.fewest])
            if optional:
                form += " " + " ".join(f"[{n.upper()}" for n in optional) + "]" * len(optional)
            count = f"{self.fewest}" if self.fewest == most else f"{self.fewest} to {most}"
            raise argparse.ArgumentError(
                self, f"expected {count} numbers ({form}), got {len(values)}."
            )
        setattr(namespace, self.dest, [*(getattr(namespace, self.dest) or []), list(values)])


def _spin_rotors(args: argparse.Namespace) -> list[ph.rotors.Rotor]:
    """The rotors of ``--wheel`` and ``--damper`` (wheels first), each checked by the core as
    it is made: a bad one is a usage error naming its option, its number and its field."""
    rotors: list[ph.rotors.Rotor] = []
    for option, groups, make in (
        ("--wheel", args.wheel, lambda v: ph.rotors.Wheel(v[:3], *v[3:])),
        ("--damper", args.damper, lambda v: ph.rotors.SphericalDamper(*v)),
    ):
        for k, values in enumerate(groups or (), start=1):
            try:
                rotors.append(make(values))
            except ph.PolhodeError as error:
                numbers = " ".join(f"{v:g}" for v in values)
                raise UsageError(option, f"{option} {numbers} (number {k}): {error}") from None
    return rotors


def _rotor_option(args: argparse.Namespace) -> str:
    """The option(s) an error about the rotors as a whole names."""
    given = [o for o, v in (("--wheel", args.wheel), ("--damper", args.damper)) if v]
    return " and ".join(given)


def _check_rotor_method(args: argparse.Namespace, rotors: list[ph.rotors.Rotor]) -> None:
    """That ``--method`` takes rotors, as the core says (a run of no body: no work)."""
    try:
        _core.simulate(
            np.zeros((0, 3)),
            np.zeros((0, 3)),
            np.zeros(1),
            method=args.method,
            dt=args.dt,
            rotors=rotors,
        )
    except ph.PolhodeError as error:
        if error.argument != "rotors":
            raise
        raise UsageError(
            "--method", f"{args.method} cannot take {_rotor_option(args)}: {error}"
        ) from None


def _rotor_names(rotors: list[ph.rotors.Rotor]) -> list[str]:
    """``wheel 1``, ``wheel 2``, ``damper 1``, ...: each rotor as the report and the CSV name
    it."""
    names, counts = [], {"Wheel": 0, "SphericalDamper": 0}
    for rotor in rotors:
        counts[rotor.kind] += 1
        names.append(f"{'wheel' if rotor.kind == 'Wheel' else 'damper'} {counts[rotor.kind]}")
    return names


def _rotor_report(
    sol: ph.Trajectory, rotors: list[ph.rotors.Rotor], t_end: float
) -> list[str]:
    """The rotors, their rates at the end (relative to the body) and the total energy."""
    assert sol.rotor_rates is not None
    lines = []
    names = _rotor_names(rotors)
    for name, rotor in zip(names, rotors, strict=True):
        if isinstance(rotor, ph.rotors.Wheel):
            axis = rotor.axis / np.linalg.norm(rotor.axis)
            what = (
                f"axis {np.array2string(axis, precision=6)}, inertia {rotor.inertia:g}, "
                f"rate0 {rotor.rate0:g}, torque {rotor.torque:g}"
            )
        else:
            assert isinstance(rotor, ph.rotors.SphericalDamper)
            what = f"inertia {rotor.inertia:g}, damping {rotor.damping:g}"
        lines.append(f"  {name:16s} {what}")
    lines.append(f"rotor rates at t = {t_end:g} (relative to the body, body axes):")
    for name, rotor, rate in zip(names, rotors, sol.rotor_rates[-1], strict=True):
        if isinstance(rotor, ph.rotors.Wheel):
            spin = float(_wheel_rate(rotor, rate))
            lines.append(f"  {name:16s} {spin:.9g}   (about its axis)")
        else:
            lines.append(f"  {name:16s} {rate}")
    return lines


def _wheel_rate(wheel: ph.rotors.Wheel, rate: np.ndarray) -> np.ndarray:
    """A wheel's rate about its axis from its ``rotor_rates`` vector ``W a`` (a the unit axis),
    by the largest component of ``a`` (W itself for an axis along a body axis)."""
    axis = wheel.axis / np.linalg.norm(wheel.axis)
    k = int(np.argmax(np.abs(axis)))
    return np.asarray(rate[..., k] / axis[k])


def _rotor_columns(rotors: list[ph.rotors.Rotor]) -> list[str]:
    """The CSV's rotor columns: a wheel's rate about its axis, a damper's relative angular
    velocity (body axes)."""
    columns = []
    for name, rotor in zip(_rotor_names(rotors), rotors, strict=True):
        stem = name.replace(" ", "")
        if isinstance(rotor, ph.rotors.Wheel):
            columns.append(f"{stem}_rate")
        else:
            columns += [f"{stem}_rate_x", f"{stem}_rate_y", f"{stem}_rate_z"]
    return columns


def _rotor_values(sol: ph.Trajectory, rotors: list[ph.rotors.Rotor]) -> np.ndarray:
    """(M, columns) of :func:`_rotor_columns`."""
    assert sol.rotor_rates is not None
    parts = []
    for k, rotor in enumerate(rotors):
        rate = sol.rotor_rates[:, k]
        if isinstance(rotor, ph.rotors.Wheel):
            parts.append(_wheel_rate(rotor, rate)[:, None])
        else:
            parts.append(rate)
    return np.column_stack(parts)


def _breaks_triangle(moments: np.ndarray) -> bool:
    """Whether I1 + I2 >= I3 fails beyond rounding (the tolerance of Body.from_inertia)."""
    half_trace = float(np.sum(moments)) / 2
    return half_trace - float(np.max(moments)) < -16 * np.finfo(float).eps * half_trace


def _spin(args: argparse.Namespace) -> int:
    rotors = _check_spin(args)
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
    if rotors:
        options["rotors"] = rotors
    omega0 = np.array(args.omega, dtype=float)
    times = np.linspace(0.0, args.t, args.points)
    # The option behind each argument an error can name (max_steps: the steps dop853 needed
    # to reach --t, which has no option of its own).
    option_of = {
        "body": source,
        "omega0": "--omega",
        "t": "--t",
        "dt": "--dt",
        "rtol": "--rtol",
        "max_steps": "--t",
        "rotors": _rotor_option(args),
    }
    try:
        a = ph.analyze(body, omega0, rotors=rotors or None)
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
        print(f"regime             rest (omega0 = 0{'' if rotors else ': the body stays at rest'})")
    else:
        print(f"regime             {a.regime}; axis stability {', '.join(a.axis_stability)}")
    if a.period is not None:
        print(f"period             {a.period:.9g}   (omega in the body)")
    if a.flip_interval is not None:
        print(f"flip interval      {a.flip_interval:.9g}")
    if a.precession_rate_body is not None:
        print(f"precession (body)  {a.precession_rate_body:.9g}   (omega about the symmetry axis)")
    if a.precession_rate_space is not None:
        print(f"precession (space) {a.precession_rate_space:.9g}   (mean rate about L)")
    if a.nutation_angle is not None:
        lo, hi = np.degrees(a.nutation_angle)
        angle = f"{lo:.6g} deg" if lo == hi else f"{lo:.6g} to {hi:.6g} deg"
        print(f"nutation angle     {angle}")
    if rotors:
        print("(the regime, period and precession above are those of the free body with its")
        print(" rotors locked, at t = 0; the rotors change the motion)")
        if a.nutation_rate is not None and a.nutation_time_constant is None:
            # No spin, or a damper without damping: nothing decays or grows.
            print(f"nutation rate      {a.nutation_rate:.9g}   (the damper's, linearised: steady)")
        elif a.nutation_rate is not None:
            print(
                f"nutation rate      {a.nutation_rate:.9g}   (the damper's, linearised: "
                f"{'decays' if a.nutation_rate < 0 else 'grows'}, e-folding time "
                f"{a.nutation_time_constant:.6g})"
            )
        print("rotors:")
        print("\n".join(_rotor_report(sol, rotors, args.t)))
    print(f"omega at t = {args.t:g}  {sol.omega[-1]}")
    print(
        f"method {sol.stats['method']}: {sol.stats['steps']} steps, "
        f"{sol.stats['evaluations']} evaluations, {elapsed * 1e3:.2f} ms"
    )
    drift = max_relative_drift(sol)
    # A damper takes energy and a motor gives or takes it: T is then not an invariant.
    dampers = [
        name
        for name, r in zip(_rotor_names(rotors), rotors, strict=True)
        if isinstance(r, ph.rotors.SphericalDamper) and r.damping > 0
    ]
    motors = [
        f"the motor of {name}"
        for name, r in zip(_rotor_names(rotors), rotors, strict=True)
        if isinstance(r, ph.rotors.Wheel) and r.torque != 0
    ]
    if rest and not rotors:
        # T, |L| and L are all zero: the drift is the absolute error (polhode.invariants).
        print("invariant drift (max absolute error over the run; at rest all are zero):")
    elif rotors:
        zero = sol.energy[0] == 0.0 or not np.any(sol.angular_momentum_body[0])
        what = "max error over the run, absolute where zero at t = 0" if zero else (
            "max relative error over the run"
        )
        print(f"invariant drift ({what}; totals, rotors included):")
    else:
        print("invariant drift (max relative error over the run):")
    if dampers or motors:
        energy = sol.energy
        print(
            f"  energy T         {energy[0]:.9g} -> {energy[-1]:.9g}   (not an invariant: "
            f"changed by {', '.join(dampers + motors)})"
        )
        if not motors:
            # dT/dt = -c |s - w|^2: a rise is the integration's error.
            rise = float(np.max(np.diff(energy), initial=0.0)) / abs(float(energy[0]) or 1.0)
            print(f"                   falls monotonically: largest rise between outputs "
                  f"{rise:.2e} of T(0)")
    else:
        print(f"  energy T         {drift['energy']:.2e}")
    print(f"  |L|              {drift['angular_momentum_norm']:.2e}")
    print(f"  L in space       {drift['angular_momentum_space']:.2e}")
    if args.plot:
        _spin_plot(sol, args.plot)
    if args.csv:
        with open(args.csv, "w", newline="") as handle:
            writer = csv.writer(handle)
            header = ["t", "omega_x", "omega_y", "omega_z", "qx", "qy", "qz", "qw"]
            columns = [sol.t, sol.omega, sol.quaternion]
            if rotors:
                header += _rotor_columns(rotors)
                columns.append(_rotor_values(sol, rotors))
            writer.writerow(header)
            for row in np.column_stack(columns):
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


def _audit(args: argparse.Namespace) -> int:
    """The audit table of a URDF or MJCF file; 1 if any link has an error, 2 for a bad file."""
    from polhode.io import audit

    try:
        findings = audit(args.file, rtol=args.rtol, geometry=args.geometry, density=args.density)
    except (ph.PolhodeError, OSError, ImportError) as error:
        print(f"polhode audit: error: {error}", file=sys.stderr)
        return 2
    width = max([4] + [len(f.link) for f in findings])
    print(f"{'link':{width}s}  {'severity':8s}  {'check':19s}  message")
    for f in findings:
        print(f"{f.link:{width}s}  {f.severity:8s}  {f.check:19s}  {f.message}")
    corrected = [f for f in findings if f.corrected and f.severity in ("error", "warning")]
    shown: set[str] = set()
    for f in corrected:
        if f.link in shown:
            continue
        shown.add(f.link)
        print(f"\ncorrected inertial of {f.link} (from its geometry, at its declared mass):")
        print("\n".join("  " + line for line in (f.corrected or "").splitlines()))
    counts = {s: sum(1 for f in findings if f.severity == s) for s in ("error", "warning")}
    links = len({f.link for f in findings})
    print(f"\n{links} links: {counts['error']} errors, {counts['warning']} warnings")
    return 1 if counts["error"] else 0


#: ``polhode inertia``: robot descriptions by extension (then URDF or MJCF by the XML's root
#: element), meshes by ``polhode.io.MESH_FORMATS``; any other file is a molecule read by ASE.
ROBOT_EXTENSIONS = ("urdf", "xml", "mjcf")

#: The options of ``polhode inertia`` that apply to some kinds of file only:
#: option -> (attribute, kinds).
INERTIA_OPTIONS = {
    "--density": ("density", ("mesh", "urdf", "mjcf")),
    "--mass": ("mass", ("mesh", "urdf", "mjcf")),
    "--scale": ("scale", ("mesh",)),
    "--shell": ("shell", ("mesh",)),
    "--fix-winding": ("fix_winding", ("mesh",)),
    "--masses": ("masses", ("molecule",)),
    "--unit": ("unit", ("molecule",)),
    "--format": ("format", ("molecule",)),
    "--frames": ("frames", ("molecule",)),
}

#: Where a molecule's atomic masses come from (Body.from_atoms), as ``polhode inertia`` says.
MASS_SOURCES = {
    "most_abundant": "most abundant isotopes (AME 2020 masses, CIAAW abundances; periodictable)",
    "average": "standard atomic weights (CIAAW 2021; periodictable)",
}

#: The option behind each argument the readers' errors can name.
INERTIA_ARGUMENTS = {
    "density": "--density",
    "mass": "--mass",
    "scale": "--scale",
    "masses": "--masses",
    "point": "--point",
}

_KIND_NAMES = {"mesh": "mesh files", "urdf": "URDF", "mjcf": "MJCF", "molecule": "molecule files"}
_LABEL = 21  # the width of the labels of `polhode inertia`'s text output


def _file_kind(args: argparse.Namespace) -> str:
    """``mesh``, ``urdf``, ``mjcf`` or ``molecule`` (``--format`` means a molecule)."""
    from polhode.io import MESH_FORMATS
    from polhode.io._links import format_of

    if args.format is not None:
        return "molecule"
    extension = os.path.splitext(args.file)[1].lower().lstrip(".")
    if extension in MESH_FORMATS:
        return "mesh"
    if extension in ROBOT_EXTENSIONS:
        return format_of(args.file)
    return "molecule"


def _check_inertia(args: argparse.Namespace, kind: str) -> None:
    """Options given for another kind of file, a mesh without a density or a mass, and the
    --frames file, before any work."""
    for option, (name, kinds) in INERTIA_OPTIONS.items():
        value = getattr(args, name)
        if value is not None and value is not False and kind not in kinds:
            applies = " and ".join(_KIND_NAMES[k] for k in kinds)
            raise UsageError(
                option, f"applies to {applies} only; {args.file!r} is read as {_KIND_NAMES[kind]}."
            )
    if kind == "mesh" and args.density is None and args.mass is None:
        raise UsageError("--density", "a mesh file needs --density or --mass.")
    if args.frames is not None:
        _check_file("--frames", args.frames)
        if os.path.abspath(args.frames) == os.path.abspath(args.file):
            raise UsageError("--frames", f"{args.frames!r} is the file read.")


def _words(values: Any) -> str:
    return " ".join(f"{float(x) + 0.0:.9g}" for x in np.ravel(values))  # + 0.0: no -0


def _properties(body: ph.Body, args: argparse.Namespace) -> dict[str, Any]:
    """One body's mass properties as plain numbers (its JSON), with --point and --spatial."""
    p = body.principal()
    out: dict[str, Any] = {
        "mass": body.mass,
        "center_of_mass": body.center_of_mass.tolist(),
        "inertia": body.inertia.tolist(),
        "principal_moments": p.moments.tolist(),
        "principal_axes": p.axes.tolist(),
    }
    point = [0.0, 0.0, 0.0] if args.point is None else list(args.point)
    if args.point is not None:
        out["inertia_about_point"] = {"point": point, "inertia": body.inertia_about(point).tolist()}
    if args.spatial is not None:
        matrix = body.spatial_inertia(point, convention=args.spatial)
        out["spatial_inertia"] = {
            "convention": args.spatial,
            "point": point,
            "matrix": matrix.tolist(),
        }
    return out


def _print_matrix(label: str, matrix: Any) -> None:
    """A matrix in aligned columns, its label on the first row."""
    cells = [[f"{float(x) + 0.0:.9g}" for x in row] for row in np.asarray(matrix)]
    widths = [max(len(cell) for cell in column) for column in zip(*cells, strict=True)]
    for i, row in enumerate(cells):
        text = "  ".join(f"{cell:>{w}}" for cell, w in zip(row, widths, strict=True))
        print(f"{label if i == 0 else '':{_LABEL}s}{text}")


def _print_extras(props: dict[str, Any], axes: str) -> None:
    """--point's tensor and --spatial's matrix of one body, if asked for."""
    if "inertia_about_point" in props:
        about = props["inertia_about_point"]
        _print_matrix("inertia about point", about["inertia"])
        print(f"{'':{_LABEL}s}(about {_words(about['point'])}, in {axes})")
    if "spatial_inertia" in props:
        spatial = props["spatial_inertia"]
        _print_matrix("spatial inertia", spatial["matrix"])
        order = "linear" if spatial["convention"] == "pinocchio" else "angular"
        print(
            f"{'':{_LABEL}s}({spatial['convention']}: {order} block first; about "
            f"{_words(spatial['point'])}, in {axes})"
        )


def _print_body(props: dict[str, Any]) -> None:
    """One body's mass properties, as ``polhode inertia`` prints them."""
    print(f"{'mass':{_LABEL}s}{props['mass']:.9g}")
    print(f"{'centre of mass':{_LABEL}s}{_words(props['center_of_mass'])}")
    _print_matrix("inertia", props["inertia"])
    print(f"{'':{_LABEL}s}(about the centre of mass, in the file's axes; I_xy = -sum m x y)")
    print(f"{'principal moments':{_LABEL}s}{_words(props['principal_moments'])}   (ascending)")
    _print_matrix("principal axes", props["principal_axes"])
    print(f"{'':{_LABEL}s}(the columns)")
    _print_extras(props, "the file's axes")


def _read_molecule(args: argparse.Namespace, every_frame: bool) -> tuple[list[str], Any]:
    """(symbols, positions (T, N, 3)) of a molecule file's first frame, or of all its frames,
    read by ASE; a FileFormatError naming the file if it cannot be read."""
    try:
        import ase.io
    except ImportError as error:
        raise ImportError(
            "Reading a molecule from a file needs ASE: pip install 'polhode[chem]'."
        ) from error
    from polhode.io import MESH_FORMATS

    path = args.file
    try:
        read = ase.io.read(path, index=":" if every_frame else 0, format=args.format)
    except Exception as error:  # ASE's readers raise whatever their parsers do
        known = ", ".join("." + e for e in (*MESH_FORMATS, *ROBOT_EXTENSIONS))
        raise ph.FileFormatError(
            f"{path}: could not read a molecule with ASE ({type(error).__name__}: {error}). "
            f"Meshes and robot descriptions are known by their extension ({known}), any other "
            "file is read as a molecule (--format names ASE's format).",
            path=path,
        ) from error
    frames = read if isinstance(read, list) else [read]
    if not frames or len(frames[0]) == 0:
        raise ph.FileFormatError(f"{path}: holds no atoms.", path=path)
    symbols = list(frames[0].get_chemical_symbols())
    for t, atoms in enumerate(frames[1:], start=1):
        if list(atoms.get_chemical_symbols()) != symbols:
            raise ph.FileFormatError(
                f"{path}: frame {t} holds other atoms ({atoms.get_chemical_formula()}, "
                f"{len(atoms)}) than frame 0 ({frames[0].get_chemical_formula()}, "
                f"{len(symbols)}): --frames follows the same atoms through every frame.",
                path=path,
                field=f"frame {t}",
            )
    return symbols, np.stack([atoms.get_positions() for atoms in frames])


def _formula(symbols: list[str]) -> str:
    """Hill order: C, H, then the others alphabetically (without carbon, all alphabetically)."""
    counts: dict[str, int] = {}
    for s in symbols:
        counts[s] = counts.get(s, 0) + 1
    first = [s for s in ("C", "H") if s in counts] if "C" in counts else []
    order = first + sorted(s for s in counts if s not in first)
    return "".join(s + (str(counts[s]) if counts[s] > 1 else "") for s in order)


def _molecule(args: argparse.Namespace, result: dict[str, Any]) -> tuple[ph.Body, Any]:
    """The molecule (the file's first frame), its rotational constants put in ``result``, and
    with --frames the principal axes of every frame, followed in time (else None)."""
    from polhode._atoms import atom_masses
    from polhode.molecule import asymmetry, rotational_constants, rotor_type

    choice = args.masses or "most_abundant"
    symbols, positions = _read_molecule(args, every_frame=args.frames is not None)
    try:
        _, masses = atom_masses(symbols, choice)
    except ph.PolhodeError as error:  # an element the table does not know, or has no mass for
        raise ph.FileFormatError(
            f"{args.file}: {error.message}", path=args.file, field=error.argument
        ) from error
    body = ph.Body.from_atoms(symbols, positions[0], masses=masses)
    result.update(
        atoms=len(symbols),
        formula=_formula(symbols),
        masses=choice,
        mass_source=MASS_SOURCES[choice],
        units={"length": "angstrom", "mass": "u"},
    )
    if body.principal().moments[2] > 0:
        unit = args.unit or "MHz"
        a, b, c = rotational_constants(body, unit=unit)
        kind = rotor_type(body)
        result["rotational_constants"] = {"unit": unit, "A": a, "B": b, "C": c}
        result["asymmetry"] = None if kind == "spherical" else asymmetry(body)
        result["rotor_type"] = kind
    else:  # one atom, or atoms at one point: no rotation, no spectrum
        result.update(rotational_constants=None, asymmetry=None, rotor_type=None)
    series = None
    if args.frames is not None:
        series = ph.principal(ph.point_masses_inertia(masses, positions), continuous=True)
        result["frames"] = {"count": int(positions.shape[0]), "csv": args.frames}
    return body, series


def _write_frames(path: str, series: ph.Principal) -> None:
    """Each frame's principal moments and axes (followed from frame to frame) as CSV."""
    header = ["frame", "moment_0", "moment_1", "moment_2"]
    header += [f"axis_{k}_{c}" for k in range(3) for c in "xyz"]
    axes = np.swapaxes(series.axes, 1, 2).reshape(-1, 9)  # axis 0's x, y, z, then axis 1's...
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for t, (moments, row) in enumerate(zip(series.moments, axes, strict=True)):
            writer.writerow([t, *(repr(float(x)) for x in (*moments, *row))])


def _read_inertia(args: argparse.Namespace) -> tuple[dict[str, Any], Any]:
    """The result of ``polhode inertia`` (its JSON) and the molecule's series (or None)."""
    kind = _file_kind(args)
    _check_inertia(args, kind)
    result: dict[str, Any] = {"file": args.file, "kind": kind}
    series = None
    if kind == "mesh":
        from polhode.io import read_mesh

        parts = read_mesh(
            args.file,
            density=args.density,
            mass=args.mass,
            scale=1.0 if args.scale is None else args.scale,
            shell=bool(args.shell),
            fix_winding=bool(args.fix_winding),
        )
        bodies = list(parts.values())
        result.update(_properties(sum(bodies[1:], bodies[0]), args))
        if len(parts) > 1:
            result["parts"] = {name: _properties(b, args) for name, b in parts.items()}
    elif kind in ("urdf", "mjcf"):
        from polhode.io import read_mjcf, read_urdf

        reader = read_urdf if kind == "urdf" else read_mjcf
        links = reader(args.file, density=args.density, mass=args.mass)
        result["links"] = {name: _properties(b, args) for name, b in links.items()}
    else:
        body, series = _molecule(args, result)
        result.update(_properties(body, args))
    return result, series


def _inertia(args: argparse.Namespace) -> int:
    """The mass properties of a mesh file, of a robot description's links or of a molecule;
    2 for a file that cannot be read."""
    path = args.file
    try:
        if not os.path.exists(path):
            raise FileNotFoundError(f"{path}: no such file.")
        if os.path.isdir(path):
            raise IsADirectoryError(f"{path}: is a folder, expected a file.")
        result, series = _read_inertia(args)
    except UsageError:
        raise
    except ph.PolhodeError as error:
        option = INERTIA_ARGUMENTS.get(error.argument or "")
        if option is not None and not isinstance(error, ph.FileFormatError):
            raise UsageError(option, str(error)) from None
        message = str(error) if path in str(error) else f"{path}: {error}"
        robot = os.path.splitext(path)[1].lower().lstrip(".") in ROBOT_EXTENSIONS
        if isinstance(error, ph.FileFormatError) and error.link is not None and robot:
            message += f" (`polhode audit {path}` checks every link.)"
        print(f"polhode inertia: error: {message}", file=sys.stderr)
        return 2
    except (ImportError, OSError) as error:  # a missing extra; the file or a file it names
        message = str(error) if path in str(error) else f"{path}: {error}"
        print(f"polhode inertia: error: {message}", file=sys.stderr)
        return 2
    if series is not None:
        _write_frames(args.frames, series)
    if args.json:
        print(json.dumps(result))
    else:
        _print_inertia(result)
    return 0


def _print_links(result: dict[str, Any]) -> None:
    """A robot description's links: a row each, then --point's and --spatial's matrices."""
    links = result["links"]
    what = "link" if result["kind"] == "urdf" else "body"
    noun = what if len(links) == 1 else "bodies" if what == "body" else "links"
    print(
        f"{result['file']}: {result['kind'].upper()}, {len(links)} {noun} with mass (the "
        "declared inertials, or from the geometry; each in its own frame: the centre of mass, "
        "and the inertia about it in the frame's axes)"
    )
    if not links:
        return
    names = ("mass", "com_x", "com_y", "com_z", "ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    rows = [[what, *names]]
    for name, props in links.items():
        i = np.asarray(props["inertia"])
        row = [props["mass"], *props["center_of_mass"]]
        row += [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
        rows.append([name, *(f"{float(x) + 0.0:.9g}" for x in row)])
    widths = [max(len(cell) for cell in column) for column in zip(*rows, strict=True)]
    for row in rows:
        cells = [f"{row[0]:{widths[0]}s}"]
        cells += [f"{cell:>{w}s}" for cell, w in zip(row[1:], widths[1:], strict=True)]
        print("  ".join(cells))
    for name, props in links.items():
        if "inertia_about_point" in props or "spatial_inertia" in props:
            print(f"\n{name}")
            _print_extras(props, f"the {what}'s frame")


def _print_inertia(result: dict[str, Any]) -> None:
    """The text output of ``polhode inertia``."""
    kind = result["kind"]
    if kind in ("urdf", "mjcf"):
        _print_links(result)
        return
    if kind == "mesh":
        parts = result.get("parts", {})
        print(f"{result['file']}: mesh" + (f", {len(parts)} parts (their sum)" if parts else ""))
    else:
        print(
            f"{result['file']}: molecule {result['formula']}, {result['atoms']} atoms; "
            f"angstrom and u; masses: {result['mass_source']}"
        )
    _print_body(result)
    for name, props in result.get("parts", {}).items():
        print(
            f"{'part ' + name:{_LABEL}s}mass {props['mass']:.9g}, centre of mass "
            f"{_words(props['center_of_mass'])}"
        )
    if kind != "molecule":
        return
    constants = result["rotational_constants"]
    if constants is None:
        print(f"{'rotational constants':{_LABEL}s}none (all moments zero: no rotation)")
    else:
        a = "- (linear)" if constants["A"] is None else f"{constants['A']:.9g}"
        print(
            f"{'rotational constants':{_LABEL}s}A {a}  B {constants['B']:.9g}  "
            f"C {constants['C']:.9g}  {constants['unit']}"
        )
        kappa = result["asymmetry"]
        shown = "undefined (a spherical top)" if kappa is None else f"{kappa:.9g}"
        print(f"{'asymmetry (Ray)':{_LABEL}s}{shown}")
        print(f"{'rotor type':{_LABEL}s}{result['rotor_type']}")
    if "frames" in result:
        frames = result["frames"]
        print(
            f"\n{frames['count']} frames: principal moments and axes of each written to "
            f"{frames['csv']} (followed from frame to frame: no sign flips, no swaps)"
        )


def _bench(args: argparse.Namespace) -> int:
    from polhode import bench

    if args.kernels:
        from polhode.bench import kernels

        print(f"# polhode bench --kernels{' --quick' if args.quick else ''} ({bench.machine()})")
        print(f"# peers: {bench.peers()}\n")
        print(kernels.run(quick=args.quick, repeats=args.repeats or 5).table())
        return 0
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
        description="Simulate one torque-free body, optionally with internal rotors (--wheel, "
        "--damper). Give --moments or --body.",
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
        + "), or a mesh file: 'mesh path=part.stl density=2700' (or mass=M; scale=S, "
        "shell=true optional; STL, OBJ, PLY, OFF, glTF/GLB)",
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
        help=f"step of the fixed-step methods ({', '.join(FIXED_STEP)}; required by them)",
    )
    spin.add_argument(
        "--order", type=int, choices=(2, 4, 6), help="order of --method splitting (default 4)"
    )
    spin.add_argument(
        "--rtol",
        type=_number("a finite tolerance between 0 and 1", positive=True, below=1.0),
        help="relative tolerance of --method dop853 (default 1e-10)",
    )
    spin.add_argument(
        "--wheel",
        action=_Group,
        nargs="+",
        type=_number("a finite number (a wheel's axis, inertia, rate0 or torque)"),
        names=WHEEL_FIELDS,
        fewest=4,
        metavar="NUMBER",
        help="a reaction wheel, AX AY AZ INERTIA [RATE0 [TORQUE]]: its axis in body axes, its "
        "axial inertia, its rate relative to the body at t = 0 (default 0) and a constant "
        "motor torque on it (default 0); repeatable. The body's moments include it, locked",
    )
    spin.add_argument(
        "--damper",
        action=_Group,
        nargs=2,
        type=_number("a finite number (a damper's inertia or damping)"),
        names=DAMPER_FIELDS,
        fewest=2,
        metavar=("INERTIA", "DAMPING"),
        help="a spherical (Kane) damper: the sphere's inertia and the viscous coefficient; "
        "repeatable. The body's moments include it, locked. With rotors --method is auto "
        "(dop853), dop853 or rk4",
    )
    spin.add_argument(
        "--csv",
        help="write t, omega and the quaternion (xyzw) to this file, and each rotor's rate "
        "relative to the body (a wheel's about its axis: wheel1_rate; a damper's vector: "
        "damper1_rate_x, _y, _z)",
    )
    spin.add_argument("--plot", help="write omega and the invariant drift to this image (.png)")
    spin.set_defaults(run=_spin)
    audit_parser = commands.add_parser(
        "audit",
        help="check the declared inertials of a URDF or MJCF file",
        description="Check every link's declared inertial: errors (non-positive mass, not "
        "positive semidefinite, triangle inequality broken), warnings (a near-zero principal "
        "moment, disagreement with the link's own geometry, a centre of mass far from it), "
        "with a corrected inertial where the geometry gives one. Exit status 1 if any error "
        "is found, 2 if the file cannot be read, 0 otherwise.",
    )
    audit_parser.add_argument("file", help="a URDF (.urdf) or MJCF (MuJoCo .xml) file")
    audit_parser.add_argument(
        "--rtol",
        type=_number("a positive finite tolerance", positive=True),
        default=0.25,
        help="relative tolerance of the comparison with the geometry (default 0.25)",
    )
    audit_parser.add_argument(
        "--geometry",
        choices=("collision", "visual"),
        default="collision",
        help="URDF geometry to compare with (default collision)",
    )
    audit_parser.add_argument(
        "--density",
        type=_number("a positive finite density", positive=True),
        help="density for the corrected inertial of a link whose mass is unusable",
    )
    audit_parser.set_defaults(run=_audit)
    inertia_parser = commands.add_parser(
        "inertia",
        help="mass properties of a file: a mesh, a robot description's links, a molecule",
        description="Mass properties of a file: the mass, the centre of mass, the inertia "
        "tensor about it and the principal moments and axes. A mesh file (STL, OBJ, PLY, OFF, "
        "glTF/GLB: give --density or --mass) as one uniform body; a URDF or MJCF file as a row "
        "per link from its declared inertial, in the link's frame; any other file as a "
        "molecule read by ASE (XYZ, PDB, CIF, ...; angstrom and u), with its rotational "
        "constants, Ray's asymmetry and rotor type. Exit status 2 if the file cannot be read.",
    )
    inertia_parser.add_argument("file", help="a mesh, URDF, MJCF or molecule file")
    amount = inertia_parser.add_mutually_exclusive_group()
    amount.add_argument(
        "--density",
        type=_number("a positive finite density", positive=True),
        help="mesh: mass per volume (per area with --shell); URDF/MJCF: the density of the "
        "links without an inertial",
    )
    amount.add_argument(
        "--mass",
        type=_number("a positive finite mass", positive=True),
        help="mesh: the total mass; URDF/MJCF: the total mass of the links without an inertial",
    )
    inertia_parser.add_argument(
        "--scale",
        type=_number("a finite non-zero number"),
        help="mesh: length scale of the coordinates (0.001 reads millimetres as metres)",
    )
    inertia_parser.add_argument(
        "--shell", action="store_true", help="mesh: the mass on the surface (a thin shell)"
    )
    inertia_parser.add_argument(
        "--fix-winding", action="store_true", help="mesh: turn an inside-out mesh right way out"
    )
    inertia_parser.add_argument(
        "--masses",
        choices=tuple(MASS_SOURCES),
        help="molecule: the atomic masses, the most abundant isotope's (default) or the "
        "standard atomic weight",
    )
    inertia_parser.add_argument(
        "--unit",
        choices=ph.molecule.UNITS,
        help="molecule: the unit of the rotational constants (default MHz)",
    )
    inertia_parser.add_argument(
        "--format", help="molecule: ASE's name of the file format (default from the extension)"
    )
    inertia_parser.add_argument(
        "--frames",
        metavar="OUT.csv",
        help="molecule: write each frame's principal moments and axes to this CSV, the axes "
        "followed from frame to frame (no sign flips or swaps; the moments follow their axes)",
    )
    inertia_parser.add_argument(
        "--point",
        nargs=3,
        type=_number("a finite number (a coordinate of the point)"),
        metavar=("X", "Y", "Z"),
        help="also the inertia tensor about this point (in the file's or the link's frame)",
    )
    inertia_parser.add_argument(
        "--spatial",
        choices=ph.bodies.SPATIAL_CONVENTIONS,
        help="also the 6x6 spatial inertia in this convention (about --point, default the "
        "origin of the file's or the link's frame)",
    )
    inertia_parser.add_argument(
        "--json", action="store_true", help="print JSON (machine-readable) instead of text"
    )
    inertia_parser.set_defaults(run=_inertia)
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
        help="repeats per setting (default 3/5; at least 5 with --kernels)",
    )
    bench_parser.add_argument(
        "--kernels",
        action="store_true",
        help="only the kernels against the hardware: each kernel's time per element against "
        "its peer and target, flops and bytes per element, fraction of the machine's limit",
    )
    bench_parser.set_defaults(run=_bench)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status: 0, 2 for bad arguments (with a message on
    stderr, never a traceback), 1 when writing an output fails, 130 on Ctrl-C, 141 (as a shell
    reports SIGPIPE) when the reader of the output goes away, as in ``polhode ... | head``."""
    try:
        return _main(argv)
    except BrokenPipeError:
        # Whatever is still buffered for the closed pipe goes nowhere, quietly, at exit too.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


def _main(argv: list[str] | None) -> int:
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
    except BrokenPipeError:
        raise  # main's: the reader went away, not an error of the output
    except OSError as error:
        print(f"polhode {args.command}: error: {error}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"polhode {args.command}: interrupted", file=sys.stderr)
        return 130
    return result
