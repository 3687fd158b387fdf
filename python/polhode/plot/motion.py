"""Plots against time and against the cost: omega, the drift of the invariants, the energy
sink of a damper, work-precision, and the error of the perturbation expansion."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_integer
from polhode.errors import PolhodeError
from polhode.invariants import relative_drift
from polhode.plot._axes import AXIS_ROLES, FLOOR, new_axes, single

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


def omega(traj: Trajectory, ax: Axes | None = None) -> Axes:
    """The three body-axis components of the angular velocity against time.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], np.linspace(0.0, 50.0, 501))
    >>> ax = ph.plot.omega(sol)
    >>> [line.get_gid() for line in ax.get_lines()]
    ['omega1', 'omega2', 'omega3']
    >>> bool(np.array_equal(ax.get_lines()[1].get_ydata(), sol.omega[:, 1]))
    True
    >>> ax.figure.savefig("omega.png")  # doctest: +SKIP
    """
    single(traj, "omega")
    ax = new_axes() if ax is None else ax
    for k in range(3):
        ax.plot(traj.t, traj.omega[:, k], label=f"omega{k + 1}", gid=f"omega{k + 1}")
    ax.set_xlabel("t")
    ax.set_ylabel("omega (body axes)")
    ax.set_title("Angular velocity")
    ax.legend()
    return ax


#: The curves of :func:`drift`, by key of :func:`polhode.invariants.relative_drift`: the
#: label, and the line's gid after ``"drift:"``.
DRIFT_CURVES = {
    "energy": ("T", "energy"),
    "angular_momentum_norm": ("|L| (body)", "|L| body"),
    "angular_momentum_space": ("L (space)", "L space"),
}


def drift(traj: Trajectory, ax: Axes | None = None, floor: float = FLOOR) -> Axes:
    """Relative drift of the invariants against time on a log axis
    (:func:`polhode.invariants.relative_drift`).

    Curves (in this order): T, ``|L|`` in body axes, L in space (if the trajectory has an
    orientation); values below ``floor`` (exact zeros) are drawn at the floor, shown dashed.

    Examples
    --------
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 100.0, method="rk4", dt=0.1)
    >>> ax = ph.plot.drift(sol)
    >>> [line.get_gid() for line in ax.get_lines()]
    ['drift:energy', 'drift:|L| body', 'drift:L space', 'floor']
    """
    single(traj, "drift")
    errors = relative_drift(traj)
    ax = new_axes() if ax is None else ax
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
    ax.set_xlabel("t")
    ax.set_ylabel("relative error")
    ax.set_title("Drift of the invariants")
    ax.legend()
    return ax


def dissipation(traj: Trajectory, ax: Axes | None = None) -> Axes:
    """The energy sink: T and ``|L|`` against time, each relative to its value at t[0], with the
    energies of the separatrix (L^2 / (2 I2)) and of the spin about the largest axis
    (L^2 / (2 I3)), where a damper takes a body at fixed ``|L|`` (``traj.moments`` the principal
    moments with the rotors locked, ascending).

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
    single(traj, "dissipation")
    ax = new_axes() if ax is None else ax
    moments = np.sort(np.asarray(traj.moments, dtype=np.float64))
    ell = np.linalg.norm(np.asarray(traj.angular_momentum_body, dtype=np.float64), axis=-1)
    energy = np.asarray(traj.energy, dtype=np.float64)
    t0_energy, l2 = energy[0], ell[0] ** 2
    ax.plot(traj.t, energy / t0_energy, label="T", gid="dissipation:energy")
    ax.plot(traj.t, ell / ell[0], label="|L|", gid="dissipation:angular_momentum")
    ax.axhline(
        l2 / (2 * moments[1]) / t0_energy,
        color="black",
        linestyle="--",
        linewidth=1.0,
        label="separatrix, L^2/(2 I2)",
        gid="dissipation:separatrix",
    )
    ax.axhline(
        l2 / (2 * moments[2]) / t0_energy,
        color="0.5",
        linestyle=":",
        linewidth=1.2,
        label="largest axis, L^2/(2 I3)",
        gid="dissipation:largest_axis",
    )
    ax.set_xlabel("t")
    ax.set_ylabel("relative to t = 0")
    ax.set_title("Energy sink: T falls, |L| stays")
    ax.legend()
    return ax


def work_precision(
    results: Mapping[str, tuple[Any, Any]], ax: Axes | None = None, floor: float = FLOOR
) -> Axes:
    """Error against (wall) time on log-log axes, one series per name: ``{name: (times,
    errors)}``. Errors below ``floor`` are drawn at the floor.

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
    ax = new_axes() if ax is None else ax
    for name, (times, errors) in results.items():
        x = np.asarray(times, dtype=np.float64)
        y = np.maximum(np.asarray(errors, dtype=np.float64), floor)
        if x.shape != y.shape or x.ndim != 1:
            raise ValueError(
                f"Expected matching 1-D times and errors for {name!r}, got {x.shape}, {y.shape}."
            )
        order = np.argsort(x, kind="stable")
        ax.loglog(x[order], y[order], marker="o", label=str(name), gid=f"work_precision:{name}")
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())  # crowded labels over less than a decade
    ax.set_xlabel("time")
    ax.set_ylabel("error")
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


def perturbation_errors(
    moments: Sequence[float],
    axis: int,
    eps: Any,
    orders: Sequence[int] = (1, 2),
    t: Any = 2.0,
    *,
    spin: float = 1.0,
    direction: Sequence[float] = PERTURBATION_DIRECTION,
) -> dict[int, NDArray[np.float64]]:
    """Largest error of the expansion of each order against the exact solution, per eps.

    For each ``eps``, omega0 is ``eps * direction`` with the ``axis`` entry set to ``spin``; the
    error is max |omega_expansion - omega_exact| over the components and the times ``t`` (an end
    time means 41 times from 0 to it). The exact solution is ``polhode.simulate(...,
    method="exact")``, all eps in one batch.
    """
    from polhode.perturbation import perturbation
    from polhode.simulation import simulate

    epsilons = np.asarray(eps, dtype=np.float64)
    if epsilons.ndim != 1 or epsilons.size == 0:
        raise ValueError(f"Expected `eps` to be a 1-D array of values, got shape {epsilons.shape}.")
    if not np.all(np.isfinite(epsilons) & (epsilons > 0)):
        raise ValueError(f"Expected `eps` to be positive and finite, got {epsilons.tolist()}.")
    times = np.asarray(t, dtype=np.float64)
    if times.ndim == 0:
        times = np.linspace(0.0, float(times), 41)
    shape = np.asarray(direction, dtype=np.float64)
    if shape.shape != (3,) or not np.all(np.isfinite(shape)):
        raise ValueError(f"Expected `direction` to be three finite numbers, got {direction!r}.")
    if isinstance(axis, bool) or axis not in (0, 1, 2):
        raise ValueError(f"Expected `axis` to be 0, 1 or 2, got {axis!r}.")
    if isinstance(orders, str | bytes) or not isinstance(orders, Iterable):
        raise TypeError(f"Expected `orders` to be a sequence of 0, 1, 2, got {orders!r}.")
    checked = [as_integer("orders", order, allowed=(0, 1, 2)) for order in orders]
    omega0 = epsilons[:, None] * shape
    omega0[:, axis] = spin
    exact = simulate(moments, omega0, times, method="exact", orientation=False).omega
    errors = {}
    for order in checked:
        values = []
        for eps_k, w, e in zip(epsilons, omega0, exact, strict=True):
            try:
                expansion = perturbation(moments, w, times, axis=axis, order=order)
            except PolhodeError as error:
                if error.argument != "omega0":
                    raise
                # omega0 is made of eps here: an eps outside the expansion's domain.
                raise type(error)(
                    f"Invalid `eps`: {eps_k:g} is outside the expansion's domain ({error})",
                    argument="eps",
                ) from None
            values.append(np.max(np.abs(expansion - e)))
        errors[order] = np.array(values)
    return errors


def perturbation_error(
    moments: Sequence[float],
    axis: int = 2,
    eps: Any = None,
    orders: Sequence[int] = (1, 2),
    t: Any = 2.0,
    ax: Axes | None = None,
    *,
    spin: float = 1.0,
    direction: Sequence[float] = PERTURBATION_DIRECTION,
    floor: float = FLOOR,
) -> Axes:
    """Error of the perturbation expansion against eps on log-log axes, with slopes eps^(n+1).

    Spin ``spin`` about principal ``axis`` of ``moments``, perturbed by ``eps * direction``
    (default eps: 13 values from 1e-4 to 1e-1); for each order n in ``orders``, the largest error
    of :func:`polhode.perturbation` against the exact solution over the times ``t`` (see
    :func:`perturbation_errors`), with a dashed reference line eps^(n+1) starting
    ``SLOPE_OFFSET`` below its smallest-eps point. Errors below ``floor`` are drawn at the floor.

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
    """
    epsilons = np.logspace(-4.0, -1.0, 13) if eps is None else np.asarray(eps, dtype=np.float64)
    errors = perturbation_errors(moments, axis, epsilons, orders, t, spin=spin, direction=direction)
    ax = new_axes() if ax is None else ax
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
    ax.set_xlabel("$\\epsilon$ (size of the perturbation)")
    ax.set_ylabel("max |omega - omega_exact|")
    ax.set_title(
        f"Perturbation expansion near the {AXIS_ROLES[axis]} axis ({axis}): "
        "error against $\\epsilon$"
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax
