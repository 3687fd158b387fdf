"""``polhode demo``: principal axes of a few bodies, the tennis-racket flip of a T-handle, the
major-axis rule with a damper, their plots, the flip animated and Poinsot's construction of it
(an HTML page)."""

from __future__ import annotations

import argparse
import os
import textwrap
from typing import Any

import numpy as np

import polhode as ph
from polhode.cli._common import (
    axes_words,
    check_folder,
    plots_available,
    scenes_available,
    vector,
)
from polhode.invariants import max_relative_drift


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


def run(args: argparse.Namespace) -> int:
    plots = not args.no_plots and plots_available()
    if plots:
        check_folder("--out", args.out)
    print(
        "polhode: principal moments (ascending: I1 <= I2 <= I3) and principal axes 1, 2, 3 (in "
        "the body's axes x, y, z) about the centre of mass\n"
    )
    for name, body in _bodies():
        p = body.principal()
        print(f"{name}")
        print(f"  mass            {body.mass:.6g}")
        print(f"  centre of mass  {vector(body.center_of_mass)}")
        print(f"  moments         {vector(p.moments)}   multiplicity {p.multiplicity}")
        print(f"  axes            {axes_words(p.axes)}")
        print()
    _flip_demo()
    print()
    _damper_demo()
    if plots:
        _demo_plots(args.out)
    elif not args.no_plots:
        print("\n(plots skipped: matplotlib is not installed; pip install 'polhode[plot]')")
    return 0


def _poinsot(body: ph.Body, spin: Any, flip_interval: float, out: str) -> str | None:
    """``poinsot.html``: Poinsot's construction of the T-handle's flip (polhode.plot.scene),
    L pointing up; None (with a note) without plotly."""
    if not scenes_available():
        print("\n(poinsot.html skipped: plotly is not installed; pip install 'polhode[plot]')")
        return None
    from polhode import plot

    sol = ph.simulate(body, spin, np.linspace(0.0, 2.2 * flip_interval, 1001), orientation0=_up(
        body, spin
    ))
    path = os.path.join(out, "poinsot.html")
    plot.scene(sol, body, path=path)
    return path


def _up(body: ph.Body, spin: Any) -> Any:
    """The orientation that turns the body's angular momentum along the space z axis."""
    from scipy.spatial.transform import Rotation

    up, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [body.angular_momentum_body(spin)])
    return up


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
    page = _poinsot(t_handle, spin, a.flip_interval, out)
    if page is not None:
        print(f"Poinsot's construction of the flip (open it in a browser): {page}")


#: Frames of the demo's animation (two flips): enough to see the handle turn over, few enough
#: that the demo stays quick (about 0.1 s a frame).
ANIMATION_FRAMES = 40


def _flip_animation(body: ph.Body, spin: Any, flip_interval: float, out: str) -> str:
    """``tennis_racket.gif``: the T-handle's flip in space, L pointing up."""
    from polhode import plot

    t = np.linspace(0.0, 2.2 * flip_interval, 4 * ANIMATION_FRAMES)
    sol = ph.simulate(body, spin, t, orientation0=_up(body, spin))
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
        f"t = {sol.t[-1]:g} s omega = {vector(w, 4)} rad/s (about the largest axis)"
    )


def _flip_demo() -> None:
    """The tennis-racket flip of the T-handle: predicted, observed, and what is conserved."""
    t_handle = dict(_bodies())["T-handle (two cylinders, kg and m)"]
    p = t_handle.principal()
    spin = 10.0 * p.axes[:, 1] + 1e-3 * p.axes[:, 0]  # rad/s about the intermediate axis, nudged
    a = ph.analyze(t_handle, spin)
    print("T-handle spun at 10 rad/s about its intermediate axis, nudged by 1e-3 rad/s")
    for line in textwrap.wrap(a.description, 100 - 18, break_on_hyphens=False):
        print(f"{'':18s}{line}")
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
