"""``polhode spin``: simulate one body free of external torques, optionally with internal rotors,
report its motion and the drift of its invariants, and write it (CSV, a plot, Poinsot's scene)."""

from __future__ import annotations

import argparse
import csv
import dataclasses
import os
import re
import sys
import textwrap
import time
import warnings
from typing import Any

import numpy as np

import polhode as ph
from polhode import _core
from polhode._formats import number
from polhode._physics import breaks_triangle_inequality, wheel_rate
from polhode._quantities import QUANTITIES, Quantity
from polhode.cli._common import (
    UsageError,
    axes_words,
    body_of,
    check_file,
    plots_available,
    scenes_available,
    vector,
)
from polhode.invariants import max_relative_drift

#: The methods that take a fixed step ``--dt``; ``--order`` is the splitting's, ``--rtol``
#: dop853's.
FIXED_STEP = tuple(name for name, stepping in _core.METHODS.items() if stepping == "fixed")


#: At most this many output times (the trajectory, every quantity, is kept in memory; the
#: memory check of polhode.simulate says when it does not fit).
MAX_POINTS = 10_000_000


def _check_plot(path: str) -> None:
    """matplotlib importable (imported now, before the run is timed) and a file it can write."""
    if not plots_available():
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
    check_file("--plot", path)


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
        check_file("--csv", args.csv)
    if args.plot is not None:
        _check_plot(args.plot)
    if args.html is not None:
        _check_html(args, rotors)
    written: dict[str, str] = {}
    for option in ("--csv", "--plot", "--html"):
        path = getattr(args, option[2:])
        if path is not None:
            same = written.get(os.path.abspath(path))
            if same is not None:
                raise UsageError(option, f"{path!r} is also the {same} file.")
            written[os.path.abspath(path)] = option
    return rotors


def _check_html(args: argparse.Namespace, rotors: list[ph.rotors.Rotor]) -> None:
    """What :func:`polhode.plot.scene` refuses, refused before any work: rotors, a body at
    rest; plotly importable and a file it can write."""
    if rotors:
        raise UsageError(
            "--html",
            f"Poinsot's construction is that of one rigid body, not with {_rotor_option(args)}: "
            "the rotors exchange momentum with the body, whose own I omega is then not "
            "conserved (--plot draws the run; polhode.plot.animate draws it turning).",
        )
    if not any(args.omega):
        raise UsageError(
            "--html",
            "the body is at rest (--omega 0 0 0): no energy ellipsoid, no invariable plane to "
            "draw.",
        )
    if not scenes_available():
        raise UsageError("--html", "needs plotly: pip install 'polhode[plot]'.")
    check_file("--html", args.html)


#: ``--wheel AX AY AZ INERTIA [RATE0 [TORQUE]]``: the fields of :class:`polhode.rotors.Wheel`
#: in order (the torque a constant); ``--damper INERTIA DAMPING``: those of
#: :class:`polhode.rotors.SphericalDamper`.
WHEEL_FIELDS = ("ax", "ay", "az", "inertia", "rate0", "torque")


DAMPER_FIELDS = ("inertia", "damping")


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
                what = "wheel" if option == "--wheel" else "damper"
                raise UsageError(option, f"{what} {k} ({option} {numbers}): {error}") from None
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
                f"axis {vector(axis)} (body axes x, y, z), inertia {rotor.inertia:g}, "
                f"rate0 {rotor.rate0:g}, torque {rotor.torque:g}"
            )
        else:
            assert isinstance(rotor, ph.rotors.SphericalDamper)
            what = f"inertia {rotor.inertia:g}, damping {rotor.damping:g}"
        lines.append(f"  {name:16s} {what}")
    lines.append(f"rotor rates at t = {t_end:g} (relative to the body, body axes):")
    for name, rotor, rate in zip(names, rotors, sol.rotor_rates[-1], strict=True):
        if isinstance(rotor, ph.rotors.Wheel):
            spin = float(wheel_rate(rotor, rate))
            lines.append(f"  {name:16s} {spin:.9g}   (about its axis)")
        else:
            lines.append(f"  {name:16s} {vector(rate)}   (body axes x, y, z)")
    return lines


def principal_labels(body: Any) -> bool:
    """Whether the body's own axes are its principal axes 1, 2, 3 (moments ascending), so
    that a vector in body axes has the components 1, 2, 3 (else x, y, z): principal moments
    given in ascending order, or a Body whose principal axes are its own, in that order."""
    if isinstance(body, ph.Body):
        return bool(np.array_equal(body.principal().axes, np.eye(3)))
    moments = np.asarray(body, dtype=float)
    return bool(moments[0] <= moments[1] <= moments[2])


def omega_columns(body: Any) -> list[str]:
    """The CSV's omega columns: ``omega_1 (rad/s)``.. in principal axes, else ``omega_x``.."""
    (omega,) = (q for q in QUANTITIES if q.name == "omega")
    return _quantity_columns(omega, body)


def _components(quantity: Quantity, body: Any) -> list[str]:
    """How the CSV names the components of a quantity at one output time: a vector in body
    axes by :func:`principal_labels` (1, 2, 3 or x, y, z), one in space axes x, y, z, a
    scalar-last quaternion x, y, z, w; a scalar has none; any other shape its indices."""
    shape = quantity.shape
    if shape == ():
        return []
    if shape == (3,) and quantity.frame == "body":
        return list("123" if principal_labels(body) else "xyz")
    if shape == (3,):
        return list("xyz")
    if shape == (4,):
        return list("xyzw")
    return [str(k) for k in range(int(np.prod([d for d in shape if d != "rotors"])))]


def _unit(quantity: Quantity) -> str:
    return "" if quantity.unit == "1" else f" ({quantity.unit})"


def _quantity_columns(quantity: Quantity, body: Any) -> list[str]:
    """The CSV's columns of a quantity (not one per rotor): its name and unit, by component."""
    components = _components(quantity, body)
    if not components:
        return [f"{quantity.name}{_unit(quantity)}"]
    return [f"{quantity.name}_{c}{_unit(quantity)}" for c in components]


def _rotor_columns(
    quantity: Quantity, rotors: list[ph.rotors.Rotor], body: Any
) -> list[str]:
    """The CSV's columns of a quantity per rotor, each rotor as the report names it
    (``wheel1``, ``damper1``): for the rotors' rates, a wheel's rate about its axis and a
    damper's relative angular velocity (in body axes, numbered as omega's)."""
    columns = []
    inner = dataclasses.replace(quantity, shape=quantity.shape[1:])  # one rotor's
    for name, rotor in zip(_rotor_names(rotors), rotors, strict=True):
        stem = name.replace(" ", "")
        if quantity.name != "rotor_rates":
            columns += [f"{stem}_{c}" for c in _quantity_columns(inner, body)]
        elif isinstance(rotor, ph.rotors.Wheel):
            columns.append(f"{stem}_rate{_unit(quantity)}")
        else:
            columns += [f"{stem}_rate_{c}{_unit(quantity)}" for c in _components(inner, body)]
    return columns


def _rotor_values(
    quantity: Quantity, value: np.ndarray, rotors: list[ph.rotors.Rotor]
) -> np.ndarray:
    """(M, columns) of :func:`_rotor_columns` from the quantity's (M, R, ...) values."""
    parts = []
    for k, rotor in enumerate(rotors):
        rate = value[:, k].reshape(len(value), -1)
        if quantity.name == "rotor_rates" and isinstance(rotor, ph.rotors.Wheel):
            parts.append(wheel_rate(rotor, rate)[:, None])
        else:
            parts.append(rate)
    return np.column_stack(parts)


def csv_table(
    sol: ph.Trajectory, body: Any, rotors: list[ph.rotors.Rotor]
) -> tuple[list[str], np.ndarray]:
    """The header and the (M, columns) numbers of ``polhode spin --csv``: the output times, then
    every quantity of the run in the order of the core's table (``polhode._core.QUANTITIES``),
    each with its unit: a vector by component, a quantity of the rotors by rotor."""
    header, columns = ["t (s)"], [sol.t[:, None]]
    for quantity in QUANTITIES:
        value = getattr(sol, quantity.name)
        if value is None:
            continue
        if "rotors" in quantity.shape:
            header += _rotor_columns(quantity, rotors, body)
            columns.append(_rotor_values(quantity, value, rotors))
        else:
            header += _quantity_columns(quantity, body)
            columns.append(value.reshape(len(value), -1))
    return header, np.column_stack(columns)


def _axes_words(body: Any) -> str:
    """How the report names the body's axes: principal axes 1, 2, 3 or body axes x, y, z."""
    return "principal axes 1, 2, 3" if principal_labels(body) else "body axes x, y, z"


def run(args: argparse.Namespace) -> int:
    rotors = _check_spin(args)
    if args.body:
        body: Any = body_of(args.body)
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
    # An end time: the output times that resolve the motion (polhode.simulate's rule).
    times = args.t if args.points is None else np.linspace(0.0, args.t, args.points)
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
        rotor = re.match(r"rotors\[(\d+)\]", error.argument or "")
        if rotor and int(rotor.group(1)) < len(rotors):
            # A rotor's field, named as Python indexes it: named here as the report does.
            name = _rotor_names(rotors)[int(rotor.group(1))]
            message = str(error).replace(rotor.group(0), name)
            raise UsageError(f"--{name.split()[0]}", message) from None
        raise
    assert sol.quaternion is not None
    if source == "--moments" and breaks_triangle_inequality(body):
        print(
            f"polhode spin: note: the moments {' '.join(f'{m:g}' for m in body)} break "
            "I1 + I2 >= I3: Euler's equations hold for them, but no mass distribution has them.",
            file=sys.stderr,
        )
    rest = a.regime == "rest"
    print(f"principal moments  {vector(a.moments)}   (I1 <= I2 <= I3)")
    if isinstance(body, ph.Body) and not principal_labels(body):
        print(f"principal axes     {axes_words(body.principal().axes)}   (in body axes x, y, z)")
    if rest:
        print(f"regime             rest (omega0 = 0{'' if rotors else ': the body stays at rest'})")
    else:
        print(f"regime             {a.regime}; axis stability {', '.join(a.axis_stability)}")
        for line in textwrap.wrap(a.description, 100 - 19, break_on_hyphens=False):
            print(f"{'':19s}{line}")
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
    print(f"omega at t = {args.t:g}  {vector(sol.omega[-1])}   (rad/s, {_axes_words(body)})")
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
    if args.html:
        _spin_scene(sol, body if isinstance(body, ph.Body) else None, args.html)
    if args.csv:
        with open(args.csv, "w", newline="") as handle:
            writer = csv.writer(handle)
            header, table = csv_table(sol, body, rotors)
            writer.writerow(header)
            for row in table:
                writer.writerow([number(x) for x in row])
        print(f"trajectory written to {args.csv}")
    return 0


def _spin_scene(sol: ph.Trajectory, body: ph.Body | None, path: str) -> None:
    """Poinsot's construction of the run, as an HTML page; the scene's warnings (output times
    too few or too far apart to draw the curves) as notes naming --points."""
    from polhode import plot

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        plot.scene(sol, body, path=path)
    for warning in caught:
        print(
            f"polhode spin: note: --html: {warning.message} (here: raise --points)",
            file=sys.stderr,
        )
    print(f"Poinsot's construction written to {path}")


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
