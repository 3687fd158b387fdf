"""Plots against time and against the cost: omega, the drift of the invariants, the energy
sink of a damper, work-precision, and the error of the perturbation expansion."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_finite, as_finite_array, as_float_array, as_integer
from polhode._norms import norms
from polhode.errors import (
    ArgumentError,
    NonFiniteError,
    NonPositiveError,
    PolhodeError,
    ShapeError,
)
from polhode.invariants import relative_drift
from polhode.plot._axes import FLOOR, axes_for, check_floor, one_trajectory
from polhode.plot._frames import body_axes, principal_of
from polhode.plot._labels import AXIS_ROLES, labelled, subscripted, units_of

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.simulation import Trajectory

__all__ = [
    "DRIFT_CURVES",
    "PERTURBATION_DIRECTION",
    "SLOPE_OFFSET",
    "dissipation",
    "drift",
    "omega",
    "perturbation_error",
    "perturbation_errors",
    "work_precision",
]


def omega(
    traj: Trajectory, ax: Axes | None = None, *, units: Mapping[str, str] | None = None
) -> Axes:
    """The three body-axis components of the angular velocity against time.

    A trajectory's omega is in the body's own axes. Where those are principal (the body was
    given as principal moments, or its axes are principal: read off the trajectory's omega and
    angular momentum), the components are labelled by principal axis, omega_1, omega_2,
    omega_3 with I1 <= I2 <= I3, and drawn in that order; otherwise omega_x, omega_y, omega_z.
    The line of ``traj.omega[:, k]`` has the gid ``"omega[k]"``.

    Parameters
    ----------
    traj : Trajectory
        One body's motion.
    ax : a 2-D matplotlib Axes, optional
        Drawn on if given, else on a new figure.
    units : dict, optional
        The units of the labels, ``{"time": "s", "length": "m", "mass": "kg"}`` by default
        (SI; omega is in rad per time unit).

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], np.linspace(0.0, 50.0, 501))
    >>> ax = ph.plot.omega(sol)
    >>> [line.get_gid() for line in ax.get_lines()]
    ['omega[0]', 'omega[1]', 'omega[2]']
    >>> [text.get_text() for text in ax.get_legend().get_texts()]
    ['$\\\\omega_{1}$', '$\\\\omega_{2}$', '$\\\\omega_{3}$']
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('$t$ (s)', '$\\\\omega$ (rad/s)')
    >>> ax.figure.savefig("omega.png")  # doctest: +SKIP
    """
    traj = one_trajectory(traj, "plot.omega")
    unit = units_of(units)
    ax = axes_for(ax)
    numbers = body_axes(traj).numbers
    if numbers is None:
        order, names, where = [0, 1, 2], ["x", "y", "z"], "body axes x, y, z (not principal)"
    else:
        order = sorted(range(3), key=lambda k: numbers[k])
        names, where = [str(n) for n in numbers], "principal axes, $I_1 \\leq I_2 \\leq I_3$"
    for k in order:
        ax.plot(traj.t, traj.omega[:, k], label=subscripted("\\omega", names[k]), gid=f"omega[{k}]")
    ax.set_xlabel(labelled("$t$", unit.time))
    ax.set_ylabel(labelled("$\\omega$", unit.rate))
    ax.set_title(f"Angular velocity in the {where}")
    ax.legend()
    return ax


#: The curves of :func:`drift`, by key of :func:`polhode.invariants.relative_drift`: the
#: label, and the line's gid after ``"drift:"``.
DRIFT_CURVES = {
    "energy": ("$T$", "energy"),
    "angular_momentum_norm": ("$|L|$", "|L| body"),
    "angular_momentum_space": ("$L$ in space", "L space"),
}


def drift(
    traj: Trajectory,
    ax: Axes | None = None,
    floor: float = FLOOR,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """Relative drift of the invariants against time on a log axis
    (:func:`polhode.invariants.relative_drift`).

    Curves (in this order): T, ``|L|``, L in space (if the trajectory has an orientation); each
    relative to its value at the first output time, so dimensionless. Values below ``floor``
    (a positive number; exact zeros) are drawn at the floor, shown dashed. ``units`` as in
    :func:`omega` (here the unit of time).

    Examples
    --------
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 100.0, method="rk4", dt=0.1)
    >>> ax = ph.plot.drift(sol)
    >>> [line.get_gid() for line in ax.get_lines()]
    ['drift:energy', 'drift:|L| body', 'drift:L space', 'floor']
    """
    traj = one_trajectory(traj, "plot.drift")
    floor = check_floor(floor)
    unit = units_of(units)
    ax = axes_for(ax)
    errors = relative_drift(traj)
    for key, values in errors.items():
        label, gid = DRIFT_CURVES[key]
        ax.semilogy(traj.t, np.maximum(values, floor), label=label, gid=f"drift:{gid}")
    ax.axhline(floor, color="0.5", linestyle="--", linewidth=0.8, gid="floor")
    ax.annotate(
        f"floor {floor:.0e} (zero error)",
        xy=(0.01, floor),
        xycoords=("axes fraction", "data"),
        xytext=(0, 3),
        textcoords="offset points",
        fontsize="small",
        color="0.4",
    )
    ax.set_xlabel(labelled("$t$", unit.time))
    ax.set_ylabel("relative drift, $|X(t) - X(t_0)| / |X(t_0)|$")
    ax.set_title("Drift of the invariants")
    ax.legend()
    return ax


def dissipation(
    traj: Trajectory, ax: Axes | None = None, *, units: Mapping[str, str] | None = None
) -> Axes:
    """The energy sink: T and ``|L|`` against time, each relative to its value at t[0], with the
    energies of the separatrix (L^2 / (2 I2)) and of the spin about the largest axis
    (L^2 / (2 I3)), where a damper takes a body at fixed ``|L|`` (``traj.moments`` the principal
    moments with the rotors locked; I1 <= I2 <= I3). ``units`` as in :func:`omega` (here the
    unit of time).

    Lines: ``"dissipation:energy"``, ``"dissipation:angular_momentum"``,
    ``"dissipation:separatrix"``, ``"dissipation:largest_axis"``.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> from polhode import plot
    >>> damper = ph.rotors.SphericalDamper(0.2, 0.1)
    >>> sol = ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], np.linspace(0, 200, 201),
    ...                   rotors=[damper])
    >>> ax = plot.dissipation(sol)
    >>> sorted(line.get_gid() for line in ax.lines)[:2]
    ['dissipation:angular_momentum', 'dissipation:energy']
    """
    traj = one_trajectory(traj, "plot.dissipation", moving=True)
    unit = units_of(units)
    ax = axes_for(ax)
    moments = np.sort(np.asarray(traj.moments, dtype=np.float64))
    ell = norms(np.asarray(traj.angular_momentum_body, dtype=np.float64))
    energy = np.asarray(traj.energy, dtype=np.float64)
    t0_energy, ell0 = float(energy[0]), float(ell[0])

    def level(moment: float) -> float:
        """L(t0)^2 / (2 I) / T(t0), L^2 never formed (it overflows where T does not)."""
        return (ell0 / moment) * (ell0 / (2.0 * t0_energy))

    ax.plot(traj.t, energy / t0_energy, label="$T / T(t_0)$", gid="dissipation:energy")
    ax.plot(traj.t, ell / ell0, label="$|L| / |L(t_0)|$", gid="dissipation:angular_momentum")
    ax.axhline(
        level(moments[1]),
        color="black",
        linestyle="--",
        linewidth=1.0,
        label="separatrix, $L^2 / (2 I_2)$",
        gid="dissipation:separatrix",
    )
    ax.axhline(
        level(moments[2]),
        color="0.5",
        linestyle=":",
        linewidth=1.2,
        label="spin about axis 3, $L^2 / (2 I_3)$",
        gid="dissipation:largest_axis",
    )
    ax.set_xlabel(labelled("$t$", unit.time))
    ax.set_ylabel("relative to its value at $t_0$")
    ax.set_title("Energy sink: $T$ falls, $|L|$ stays")
    ax.legend()
    return ax


def _series(results: Any) -> list[tuple[str, NDArray[np.float64], NDArray[np.float64]]]:
    """The checked ``(name, times, errors)`` of work_precision's ``results``."""
    if not isinstance(results, Mapping):
        raise TypeError(
            "Expected `results` to be a dict {name: (times, errors)}, got "
            f"{type(results).__name__}."
        )
    if not results:
        raise ArgumentError(
            "Expected `results` to hold at least one series, got {}.", argument="results"
        )
    out = []
    for name, pair in results.items():
        where = f"results[{name!r}]"
        if not isinstance(pair, Sequence) or isinstance(pair, str | bytes) or len(pair) != 2:
            raise TypeError(
                f"Expected `{where}` to be a pair (times, errors), got {type(pair).__name__}"
                + (f" of {len(pair)}." if isinstance(pair, Sequence) else ".")
            )
        try:
            x = as_float_array(where, pair[0])
            y = as_float_array(where, pair[1])
        except PolhodeError as error:  # masked, or beyond double precision
            raise type(error)(error.message, argument="results") from None
        if x.ndim != 1 or x.shape != y.shape or x.size == 0:
            raise ShapeError(
                f"Expected `{where}` to be times and errors of one shape (K,), K >= 1, got "
                f"{np.shape(pair[0])} and {np.shape(pair[1])}.",
                argument="results",
            )
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            raise NonFiniteError(
                f"Expected `{where}` to be finite, got times {x.tolist()} and errors {y.tolist()}.",
                argument="results",
            )
        if np.any(x <= 0):
            raise NonPositiveError(
                f"Expected the times of `{where}` to be positive (a log axis), got {x.tolist()}.",
                argument="results",
            )
        if np.any(y < 0):
            raise ArgumentError(
                f"Expected the errors of `{where}` to be >= 0, got {y.tolist()}.",
                argument="results",
            )
        out.append((str(name), x, y))
    return out


def work_precision(
    results: Mapping[str, tuple[Any, Any]],
    ax: Axes | None = None,
    floor: float = FLOOR,
    *,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """Error against (wall) time on log-log axes, one series per name: ``{name: (times,
    errors)}`` with positive times and errors >= 0, relative errors (dimensionless, as
    :mod:`polhode.bench` gives them; another error: ``ax.set_ylabel(...)``). Errors below
    ``floor`` are drawn at the floor. ``units``: ``{"time": ...}`` is the unit of the times
    (default s).

    Examples
    --------
    >>> import polhode as ph
    >>> ax = ph.plot.work_precision({"rk4": ([1e-4, 4e-4], [1e-6, 4e-9]),
    ...                              "exact": ([9e-5], [0.0])})
    >>> [line.get_gid() for line in ax.get_lines()]
    ['work_precision:rk4', 'work_precision:exact']
    >>> ax.get_lines()[1].get_ydata().tolist()  # an exact zero, drawn at the floor
    [1e-17]
    """
    series = _series(results)
    floor = check_floor(floor)
    unit = units_of(units)
    ax = axes_for(ax)
    for name, x, errors in series:
        y = np.maximum(errors, floor)
        order = np.argsort(x, kind="stable")
        ax.loglog(x[order], y[order], marker="o", label=name, gid=f"work_precision:{name}")
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())  # crowded labels over less than a decade
    ax.set_xlabel(labelled("wall time", unit.time))
    ax.set_ylabel("relative error")
    ax.set_title("Work-precision")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax


#: The reference lines eps^(n+1) are drawn this factor below the smallest-eps error, so that
#: they stay visible beside a curve of exactly that slope.
SLOPE_OFFSET = 4.0


#: Direction of the small components of omega0 in :func:`perturbation_error` (the spin axis's
#: entry is replaced by the spin).
PERTURBATION_DIRECTION = (0.7, -0.4, 0.5)


#: perturbation()'s and simulate()'s arguments, as perturbation_errors' arguments that set
#: them (omega0: see _renamed).
_ARGUMENTS = {"moments": "body", "order": "orders"}


def _renamed(error: Any, omega0: str) -> Any:
    """``error`` (a PolhodeError of perturbation() or simulate()) naming the argument of
    perturbation_errors that set the one it names: ``omega0`` is eps * direction with the
    spin on the axis, checked finite and within the domain before the calls, so what is left
    of it is ``omega0``'s: the spin (its size overflows) or eps (the expansion's own domain)."""
    name = str(error.argument)
    argument = omega0 if name == "omega0" else _ARGUMENTS.get(name, error.argument)
    return type(error)(error.message, argument=argument)


def _epsilons(eps: Any) -> NDArray[np.float64]:
    epsilons = as_float_array("eps", eps)
    if np.ndim(eps) != 1 or epsilons.size == 0:
        raise ShapeError(
            f"Expected `eps` to be a 1-D array of values (K,), K >= 1, got shape {np.shape(eps)}.",
            argument="eps",
        )
    if not np.all(np.isfinite(epsilons)):
        raise NonFiniteError(
            f"Expected `eps` to be finite, got {epsilons.tolist()}.", argument="eps"
        )
    if not np.all(epsilons > 0):
        raise NonPositiveError(
            f"Expected `eps` to be positive, got {epsilons.tolist()}.", argument="eps"
        )
    return epsilons


def _orders(orders: Any) -> list[int]:
    if isinstance(orders, str | bytes) or not isinstance(orders, Sequence | np.ndarray):
        raise TypeError(
            f"Expected `orders` to be a sequence of orders (0, 1, 2), got {type(orders).__name__}."
        )
    if len(orders) == 0:
        raise ArgumentError(
            "Expected `orders` to hold at least one order, got none.", argument="orders"
        )
    return [as_integer("orders", n, allowed=(0, 1, 2)) for n in orders]


def _times(t: Any) -> NDArray[np.float64]:
    if np.ndim(t) == 0:  # an end time (or not a number: a TypeError naming `t`)
        return np.linspace(0.0, as_finite("t", t, positive=True), 41)
    times = as_float_array("t", t)
    if times.ndim != 1 or times.size == 0:
        raise ShapeError(
            f"Expected `t` to be an end time or times (M,), M >= 1, got shape {times.shape}.",
            argument="t",
        )
    if not np.all(np.isfinite(times)):
        raise NonFiniteError(f"Expected `t` to be finite, got {times.tolist()}.", argument="t")
    if times[0] != 0.0:
        raise ArgumentError(
            f"Expected `t` to start at 0 (omega0 is the angular velocity at t = 0), got "
            f"{times[0]}.",
            argument="t",
        )
    return times


def perturbation_errors(
    body: Any,
    axis: int,
    eps: Any,
    orders: Sequence[int] = (1, 2),
    t: Any = 2.0,
    *,
    spin: float = 1.0,
    direction: Sequence[float] = PERTURBATION_DIRECTION,
) -> dict[int, NDArray[np.float64]]:
    """Largest error of the expansion of each order against the exact solution, per eps.

    ``body`` is what :func:`polhode.simulate` takes for one body (a Body, principal moments in
    any order, an inertia tensor); the motion is computed in its principal axes, moments
    ascending, and ``axis`` (0, 1 or 2) indexes them (principal axis ``axis + 1``). For each
    ``eps``, omega0 is ``eps * direction`` with the ``axis`` entry set to ``spin``; the error is
    max |omega_expansion - omega_exact| over the components and the times ``t`` (an end time
    means 41 times from 0 to it; times must start at 0). The exact solution is
    ``polhode.simulate(..., method="exact")``, all eps in one batch.
    """
    from polhode.perturbation import EPS_MAX, perturbation
    from polhode.simulation import simulate

    moments, _ = principal_of(body)
    axis = as_integer("axis", axis, allowed=(0, 1, 2))
    epsilons = _epsilons(eps)
    orders = _orders(orders)
    times = _times(t)
    spin = as_finite("spin", spin)
    if spin == 0.0:
        raise ArgumentError(
            "Expected `spin` to be non-zero (the spin about `axis`), got 0.", argument="spin"
        )
    shape = as_finite_array("direction", direction, (3,))
    off_axis = float(norms(np.delete(shape, axis)))
    if off_axis == 0.0:
        raise ArgumentError(
            f"Expected `direction` to have a component off axis {axis + 1} (its entry [{axis}] is "
            f"replaced by the spin), got {shape.tolist()}.",
            argument="direction",
        )
    largest = float(np.max(epsilons)) * off_axis / abs(spin)
    if not largest <= EPS_MAX:
        raise ArgumentError(
            f"Expected `eps` within the expansion's domain, eps |direction off the axis| / |spin| "
            f"<= {EPS_MAX}, got {largest:.3g} for eps = {float(np.max(epsilons)):.3g}.",
            argument="eps",
        )
    omega0 = epsilons[:, None] * shape
    omega0[:, axis] = spin
    try:
        exact = simulate(moments, omega0, times, method="exact", orientation=False).omega
    except PolhodeError as error:
        raise _renamed(error, "spin") from error
    errors = {}
    for order in orders:
        try:
            expansions = [perturbation(moments, w, times, axis=axis, order=order) for w in omega0]
        except NonFiniteError as error:
            raise _renamed(error, "spin") from error
        except PolhodeError as error:
            raise _renamed(error, "eps") from error
        errors[order] = np.array(
            [np.max(np.abs(x - e)) for x, e in zip(expansions, exact, strict=True)]
        )
    return errors


def perturbation_error(
    body: Any,
    axis: int = 2,
    eps: Any = None,
    orders: Sequence[int] = (1, 2),
    t: Any = 2.0,
    ax: Axes | None = None,
    *,
    spin: float = 1.0,
    direction: Sequence[float] = PERTURBATION_DIRECTION,
    floor: float = FLOOR,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """Error of the perturbation expansion against eps on log-log axes, with slopes eps^(n+1).

    Spin ``spin`` (rad per time unit) about principal axis ``axis`` of ``body`` (a Body,
    principal moments or a tensor, as :func:`polhode.simulate` takes; ``axis`` 0, 1 or 2
    indexes the moments ascending), perturbed by ``eps * direction`` (default eps: 13 values
    from 1e-4 to 1e-1); for each order n in ``orders``, the largest error of
    :func:`polhode.perturbation` against the exact solution over the times ``t`` (see
    :func:`perturbation_errors`), with a dashed reference line eps^(n+1) starting
    ``SLOPE_OFFSET`` below its smallest-eps point. Errors below ``floor`` are drawn at the
    floor. ``units`` as in :func:`omega` (the error is in rad per time unit).

    Examples
    --------
    Near the axis of the smallest moment, the first order's error falls like eps^2:

    >>> import numpy as np
    >>> import polhode as ph
    >>> ax = ph.plot.perturbation_error([1.0, 2.0, 3.0], axis=0, eps=[1e-3, 1e-2])
    >>> first = next(line for line in ax.get_lines() if line.get_gid() == "perturbation_error:1")
    >>> errors = first.get_ydata()
    >>> round(float(np.log10(errors[1] / errors[0])), 2)  # over one decade of eps
    2.0
    >>> ax.get_title()
    'Expansion near axis 1 (smallest moment)'
    """
    epsilons = np.logspace(-4.0, -1.0, 13) if eps is None else _epsilons(eps)
    try:
        errors = perturbation_errors(
            body, axis, epsilons, orders, t, spin=spin, direction=direction
        )
    except ArgumentError as error:
        if eps is not None or error.argument != "eps":
            raise
        # eps by default: the perturbation is too large for the expansion by the direction's
        # size against the spin, which is what the caller gave.
        raise ArgumentError(
            f"{error.message} With eps by default (1e-4 to 0.1), `direction` off the axis "
            "must be at most 5 |spin|: a smaller direction or a larger spin.",
            argument="direction",
        ) from None
    floor = check_floor(floor)
    unit = units_of(units)
    ax = axes_for(ax)
    order_of = np.argsort(epsilons, kind="stable")
    x = epsilons[order_of]
    for n, values in errors.items():
        y = np.maximum(values[order_of], floor)
        (line,) = ax.loglog(x, y, marker="o", label=f"order {n}", gid=f"perturbation_error:{n}")
        ax.loglog(
            x,
            y[0] / SLOPE_OFFSET * (x / x[0]) ** (n + 1),
            color=line.get_color(),
            linestyle="--",
            linewidth=0.8,
            label=f"$\\epsilon^{{{n + 1}}}$",
            gid=f"slope:{n + 1}",
        )
    ax.set_xlabel("$\\epsilon$, the perturbation's size relative to the spin")
    ax.set_ylabel(labelled("$\\max\\,|\\omega - \\omega_{exact}|$", unit.rate))
    k = int(axis)
    ax.set_title(f"Expansion near axis {k + 1} ({AXIS_ROLES[k]} moment)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax
