"""Plots of the motion (matplotlib, the ``plot`` extra).

Every function draws on an ``ax`` if given, otherwise on a new :class:`matplotlib.figure.Figure`
(never pyplot's global state, so it works headless), and returns the Axes. matplotlib is imported
inside the functions: ``import polhode`` never needs it.

Lines are tagged with ``Line2D.get_gid()`` so their data can be found again (the tests do):
``"omega1"``.., ``"drift:energy"``.., ``"polhode:<T>"``, ``"separatrix"``, ``"trajectory"``,
``"herpolhode"``, ``"work_precision:<name>"``, ``"perturbation_error:<order>"``,
``"slope:<order + 1>"``, ``"dissipation:<curve>"``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_flag
from polhode.invariants import angular_momentum_space, relative_drift

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.simulation import Trajectory

__all__ = [
    "animate",
    "dissipation",
    "drift",
    "herpolhode",
    "omega",
    "perturbation_error",
    "polhode",
    "scene",
    "work_precision",
]

#: The principal axes by role, indexed 0, 1, 2 with the moments ascending.
AXIS_ROLES = ("smallest", "intermediate", "largest")

#: Errors below this are drawn at this value so a log axis can show exact zeros.
FLOOR = 1e-17


def _new_axes(projection: str | None = None) -> Axes:
    from matplotlib.figure import Figure

    if projection == "3d":
        import mpl_toolkits.mplot3d  # noqa: F401  (registers the projection)

    figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    return figure.add_subplot(projection=projection)


def _single(traj: Trajectory, what: str) -> None:
    if np.ndim(traj.omega) != 2:
        raise ValueError(
            f"{what} plots one trajectory; got a batch of {np.shape(traj.omega)[0]} "
            "(index it first, e.g. a Trajectory built from traj.omega[k])."
        )


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
    _single(traj, "omega")
    ax = _new_axes() if ax is None else ax
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
    _single(traj, "drift")
    errors = relative_drift(traj)
    ax = _new_axes() if ax is None else ax
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
    _single(traj, "dissipation")
    ax = _new_axes() if ax is None else ax
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


def _default_energies(moments: NDArray[np.float64], l2: float) -> list[float]:
    """Kinetic energies spread on both sides of the separatrix, as D = L^2/(2T) in (I1, I3)."""
    i1, i2, i3 = moments
    ds = [i1 + (i2 - i1) * f for f in (0.15, 0.4, 0.65, 0.88)]
    ds += [i2 + (i3 - i2) * f for f in (0.12, 0.35, 0.6, 0.85)]
    ds = [d for d in ds if i1 < d < i3 and d != i2]
    return [l2 / (2.0 * d) for d in ds]


def polhode_curves(
    moments: Sequence[float], angular_momentum_norm: float, energy: float, n: int = 400
) -> list[NDArray[np.float64]]:
    """The closed curve(s) where the sphere ``|L|`` = const meets the ellipsoid sum L_i^2/I_i = 2T.

    Returns one (n, 3) array per branch (body principal axes, moments ascending): two branches,
    one around +axis and one around -axis (the smallest axis, 0, if 2T > L^2/I2; the largest, 2,
    if below).
    """
    i1, i2, i3 = (float(m) for m in moments)
    l2 = float(angular_momentum_norm) ** 2
    two_t = 2.0 * float(energy)
    if not (l2 / i3 <= two_t <= l2 / i1):
        raise ValueError(
            f"Expected the energy in [L^2/(2 I3), L^2/(2 I1)] = [{l2 / (2 * i3)}, "
            f"{l2 / (2 * i1)}] for |L| = {angular_momentum_norm}, got {energy}."
        )
    phi = np.linspace(0.0, 2.0 * np.pi, n)
    c, s = np.cos(phi), np.sin(phi)
    if two_t < l2 / i2 or (i1 == i2 and two_t <= l2 / i1):
        # around the largest axis: L1^2 (1/I1 - 1/I3) + L2^2 (1/I2 - 1/I3) = 2T - L^2/I3
        rhs = max(two_t - l2 / i3, 0.0)
        a = np.sqrt(rhs / (1 / i1 - 1 / i3)) * c
        b = np.sqrt(rhs / (1 / i2 - 1 / i3)) * s
        rest = np.sqrt(np.maximum(l2 - a * a - b * b, 0.0))
        return [np.column_stack([a, b, sign * rest]) for sign in (1.0, -1.0)]
    # around the smallest axis: L2^2 (1/I1 - 1/I2) + L3^2 (1/I1 - 1/I3) = L^2/I1 - 2T
    rhs = max(l2 / i1 - two_t, 0.0)
    b = np.sqrt(rhs / (1 / i1 - 1 / i2)) * c if i1 != i2 else 0.0 * c
    d = np.sqrt(rhs / (1 / i1 - 1 / i3)) * s
    rest = np.sqrt(np.maximum(l2 - b * b - d * d, 0.0))
    return [np.column_stack([sign * rest, b, d]) for sign in (1.0, -1.0)]


def separatrix_curves(
    moments: Sequence[float], angular_momentum_norm: float, n: int = 400
) -> list[NDArray[np.float64]]:
    """The separatrices 2T = L^2/I2 on the sphere: two great circles L3 = +-k L1, with
    k^2 = (1/I1 - 1/I2)/(1/I2 - 1/I3). Empty for a symmetric body (I1 = I2 or I2 = I3)."""
    i1, i2, i3 = (float(m) for m in moments)
    if not i1 < i2 < i3:
        return []
    L = float(angular_momentum_norm)
    k = np.sqrt((1 / i1 - 1 / i2) / (1 / i2 - 1 / i3))
    phi = np.linspace(0.0, 2.0 * np.pi, n)
    l1 = L * np.cos(phi) / np.sqrt(1.0 + k * k)
    l2 = L * np.sin(phi)
    return [np.column_stack([l1, l2, sign * k * l1]) for sign in (1.0, -1.0)]


def polhode(
    moments: Sequence[float] | None = None,
    angular_momentum_norm: float | None = None,
    energies: Sequence[float] | None = None,
    ax: Axes | None = None,
    *,
    traj: Trajectory | None = None,
    sphere: bool = True,
    n: int = 400,
) -> Axes:
    """The polhode: the body angular momentum on the sphere ``|L|`` = const (3D axes).

    Parameters
    ----------
    moments : (3,) principal moments, ascending; default ``traj.moments``.
    angular_momentum_norm : ``|L|``; default ``|L|`` of ``traj`` at t[0], else 1.
    energies : kinetic energies T, one closed curve pair (both branches) each; default eight
        levels on both sides of the separatrix.
    ax : a 3D Axes (``projection="3d"``) or None for a new figure.
    traj : a trajectory whose ``angular_momentum_body`` is overlaid (it is in the body's own
        axes: simulate with principal moments, or a body whose axes are principal).
    sphere : draw a faint wireframe of the sphere.
    n : points per curve.

    The separatrices (2T = L^2/I2) are drawn in black, the energy levels in colour.

    Examples
    --------
    Every curve lies on the sphere ``|L| = 1``:

    >>> import numpy as np
    >>> import polhode as ph
    >>> ax = ph.plot.polhode([1.0, 2.0, 3.0])
    >>> curves = [np.array(line.get_data_3d()) for line in ax.get_lines()
    ...           if line.get_gid().startswith("polhode")]
    >>> len(curves), bool(all(np.allclose(np.linalg.norm(c, axis=0), 1.0) for c in curves))
    (16, True)
    """
    if traj is not None:
        _single(traj, "polhode")
    if moments is None:
        if traj is None:
            raise TypeError("polhode() needs `moments` or `traj`.")
        moments = traj.moments
    m = np.asarray(moments, dtype=np.float64)
    if m.shape != (3,) or not np.all(np.isfinite(m)) or np.any(m <= 0):
        raise ValueError(f"Expected three positive finite principal moments, got {moments!r}.")
    if np.any(np.diff(m) < 0):
        raise ValueError(f"Expected the principal moments ascending, got {m.tolist()}.")
    if m[0] == m[2]:
        raise ValueError("A spherical top (I1 = I2 = I3) has no polhode: every axis is fixed.")
    if angular_momentum_norm is None:
        angular_momentum_norm = (
            1.0 if traj is None else float(np.linalg.norm(traj.angular_momentum_body[0]))
        )
    L = float(angular_momentum_norm)
    if energies is None:
        energies = _default_energies(m, L * L)

    ax = _new_axes("3d") if ax is None else ax
    if as_flag("sphere", sphere):
        u, v = np.mgrid[0 : 2 * np.pi : 25j, 0 : np.pi : 13j]
        ax.plot_wireframe(
            L * np.cos(u) * np.sin(v),
            L * np.sin(u) * np.sin(v),
            L * np.cos(v),
            color="0.85",
            linewidth=0.4,
        )
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    t_lo, t_hi = L * L / (2 * m[2]), L * L / (2 * m[0])
    for energy in energies:
        color = cmap((energy - t_lo) / (t_hi - t_lo) if t_hi > t_lo else 0.5)
        for curve in polhode_curves(m, L, energy, n):
            ax.plot(*curve.T, color=color, linewidth=1.0, gid=f"polhode:{float(energy)!r}")
    for k, curve in enumerate(separatrix_curves(m, L, n)):
        ax.plot(
            *curve.T,
            color="black",
            linewidth=1.8,
            linestyle="--",
            gid="separatrix",
            label="separatrix" if k == 0 else None,
        )
    if traj is not None:
        Lb = np.asarray(traj.angular_momentum_body, dtype=np.float64)
        ax.plot(*Lb.T, color="tab:red", linewidth=2.0, gid="trajectory", label="trajectory")
    ax.set_xlabel("L, smallest axis (0)")
    ax.set_ylabel("L, intermediate axis (1)")
    ax.set_zlabel("L, largest axis (2)")
    ax.set_box_aspect((1, 1, 1))
    ax.set_title("Polhode: L on |L| = const (body axes)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left")
    return ax


def invariable_plane_basis(
    angular_momentum: Sequence[float], hint: Sequence[float] | None = None
) -> NDArray[np.float64]:
    """Rows e1, e2, n: an orthonormal right-handed basis with n = L/``|L|``; e1 along the part of
    ``hint`` perpendicular to n when that is not zero."""
    n = np.asarray(angular_momentum, dtype=np.float64)
    n = n / np.linalg.norm(n)
    candidates = [] if hint is None else [np.asarray(hint, dtype=np.float64)]
    candidates += list(np.eye(3)[np.argsort(np.abs(n))])
    for c in candidates:
        e1 = c - np.dot(c, n) * n
        norm = np.linalg.norm(e1)
        if norm > 1e-8 * max(np.linalg.norm(c), 1e-300):
            e1 = e1 / norm
            break
    e2 = np.cross(n, e1)
    return np.array([e1, e2, n])


def omega_space(traj: Trajectory) -> NDArray[np.float64]:
    """The angular velocity in space axes, (M, 3)."""
    from scipy.spatial.transform import Rotation

    _single(traj, "herpolhode")
    if traj.quaternion is None:
        raise ValueError("The herpolhode needs the orientation: simulate with orientation=True.")
    return np.asarray(Rotation.from_quat(traj.quaternion).apply(traj.omega), dtype=np.float64)


def herpolhode(traj: Trajectory, ax: Axes | None = None) -> Axes:
    """The herpolhode: the tip of omega in space, in the invariable plane (perpendicular to L).

    Coordinates are along e1, e2 of :func:`invariable_plane_basis` for L(t0), with e1 along the
    initial omega's part in the plane; the component along L, 2T/``|L|``, is constant and dropped.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.3, 1.0, 0.2], np.linspace(0.0, 20.0, 401))
    >>> ax = ph.plot.herpolhode(sol)
    >>> [line.get_gid() for line in ax.get_lines()]
    ['herpolhode', 'L axis', 'start']
    """
    w = omega_space(traj)
    space = angular_momentum_space(traj)
    assert space is not None  # omega_space has checked the orientation
    basis = invariable_plane_basis(space[0], hint=w[0])
    xy = w @ basis[:2].T
    ax = _new_axes() if ax is None else ax
    ax.plot(xy[:, 0], xy[:, 1], color="tab:blue", linewidth=1.0, gid="herpolhode")
    ax.plot([0.0], [0.0], marker="+", color="black", markersize=10, gid="L axis", label="L axis")
    ax.plot(
        xy[:1, 0], xy[:1, 1], marker="o", color="tab:red", linestyle="", gid="start", label="t0"
    )
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("omega . e1 (invariable plane)")
    ax.set_ylabel("omega . e2 (invariable plane)")
    ax.set_title("Herpolhode")
    ax.legend(loc="upper right")
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
    ax = _new_axes() if ax is None else ax
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
    omega0 = epsilons[:, None] * shape
    omega0[:, axis] = spin
    exact = simulate(moments, omega0, times, method="exact", orientation=False).omega
    errors = {}
    for order in orders:
        errors[int(order)] = np.array(
            [
                np.max(np.abs(perturbation(moments, w, times, axis=axis, order=order) - e))
                for w, e in zip(omega0, exact, strict=True)
            ]
        )
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
    ax = _new_axes() if ax is None else ax
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


#: Colours of the principal axes 0, 1, 2 (smallest, intermediate, largest) in :func:`animate`.
AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")

#: Colours of a composite body's parts in :func:`animate`, in the order they were added.
PART_COLORS = ("#8fa8c8", "#d9a66b", "#9cc28f", "#c98fb8", "#c8c28f", "#8fc8c2")


def _frame_indices(frames: Any, count: int) -> NDArray[np.int64]:
    """Indices into the output times: ``frames`` evenly spaced ones, or those given."""
    if isinstance(frames, bool) or not (
        isinstance(frames, int | np.integer) or np.ndim(frames) == 1
    ):
        raise TypeError(
            f"Expected `frames` to be a number of frames or indices, got {type(frames).__name__}."
        )
    if np.ndim(frames) == 0:
        if int(frames) < 1:
            raise ValueError(f"Expected `frames` to be at least 1, got {frames}.")
        return np.unique(
            np.linspace(0, count - 1, min(int(frames), count)).round().astype(np.int64)
        )
    indices = np.asarray(frames)
    if indices.dtype.kind not in "iu" or indices.size == 0:
        raise ValueError("Expected `frames` to be a non-empty array of output-time indices.")
    if np.any(indices < -count) or np.any(indices >= count):
        raise ValueError(f"Expected `frames` to index the {count} output times, got {frames!r}.")
    return np.asarray(indices % count, dtype=np.int64)


def _writer(path: str) -> str:
    """The matplotlib writer for a file name: pillow for .gif, ffmpeg for .mp4."""
    from matplotlib import animation

    suffix = path.rsplit(".", 1)[-1].lower() if "." in path else ""
    if suffix == "gif":
        return "pillow"
    if suffix in ("mp4", "m4v", "mov"):
        if not animation.writers.is_available("ffmpeg"):
            raise RuntimeError(
                f"Saving {path!r} needs ffmpeg on the PATH (not found); save a .gif instead "
                "(pillow), or show it in Jupyter with .to_jshtml()."
            )
        return "ffmpeg"
    raise ValueError(f"Expected `path` to end in .gif or .mp4, got {path!r}.")


def animate(
    traj: Trajectory,
    body: Any,
    *,
    frames: Any = 60,
    origin: Any = None,
    ax: Axes | None = None,
    interval: float = 50.0,
    resolution: int = 24,
    path: str | None = None,
    dpi: float = 80.0,
    space_axes: bool = False,
) -> Any:
    """The body turning in space: its shape, principal axes, omega and L, frame by frame.

    Each frame draws the body at one output time of ``traj``: every point of the body at
    ``R(t) (x - origin)`` in space axes, where ``R(t)`` is the trajectory's orientation (body
    to space) and ``origin`` the body point held fixed (the centre of mass of a free body, the
    pivot of a heavy top). The principal axes are drawn through the centre of mass in red,
    green and blue (smallest, intermediate, largest moment, ``body.principal()``), from the
    centre of mass outward, omega in
    space in black and the angular momentum in space in purple (fixed without a torque), both
    scaled to their largest value over the frames.

    The shape is the one the body was built from: solids, meshes and point masses (drawn as
    balls), each part of a composite in its own colour; a body with no geometry
    (``Body.from_inertia``) is drawn as its equivalent ellipsoid (the uniform solid ellipsoid
    with the same inertia).

    Parameters
    ----------
    traj : Trajectory
        One body's motion with its orientation, simulated with ``body`` (or in the same axes:
        ``traj.omega`` and the orientation refer to the body's own axes).
    body : Body
        The body whose shape is drawn.
    frames : int or array_like of int
        The number of frames, at evenly spaced output times (default 60; at most one per
        output time), or the indices of the output times to draw.
    origin : (3,) array_like, optional
        The body point (body coordinates) drawn fixed at the origin of space; default the
        centre of mass.
    ax : a 3D Axes, optional
        Drawn on if given (``projection="3d"``), else on a new figure.
    interval : float
        Milliseconds between frames when shown (the frame rate of a saved file is
        1000 / interval).
    resolution : int
        Segments around a circle of a solid's surface.
    path : str, optional
        Save the animation there: ``.gif`` (pillow) or ``.mp4`` (ffmpeg, if on the PATH).
    dpi : float
        Resolution of a saved file.
    space_axes : bool
        Draw the space axes' ticks, grid and panes (default False: the fixed angular momentum
        is the reference, and each frame renders about four times faster without them).

    Returns
    -------
    matplotlib.animation.FuncAnimation
        ``.save(...)`` writes it, ``.to_jshtml()`` shows it in Jupyter (e.g.
        ``IPython.display.HTML(anim.to_jshtml())``). The line artists carry the gids
        ``"axis0"``, ``"axis1"``, ``"axis2"``, ``"omega"`` and ``"angular_momentum"``, the
        surface ``"body"``; ``anim.frame_indices`` holds the output-time index of each frame.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> bar = ph.Body.cuboid(1.0, [0.3, 0.1, 0.02])
    >>> sol = ph.simulate(bar, [0.0, 5.0, 0.05], np.linspace(0.0, 4.0, 41))
    >>> anim = ph.plot.animate(sol, bar, frames=10)
    >>> len(anim.frame_indices)
    10
    >>> html = anim.to_jshtml()  # in Jupyter: IPython.display.HTML(html)
    """
    from matplotlib.animation import FuncAnimation
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    from scipy.spatial.transform import Rotation

    from polhode import _shapes
    from polhode._coerce import as_array
    from polhode.bodies import Body

    _single(traj, "animate")
    space_axes = as_flag("space_axes", space_axes)
    if not isinstance(body, Body):
        raise TypeError(f"Expected `body` to be a polhode.Body, got {type(body).__name__}.")
    if traj.quaternion is None:
        raise ValueError("animate needs the orientation: simulate with orientation=True.")
    indices = _frame_indices(frames, traj.t.size)
    writer = None if path is None else _writer(path)
    fixed = body.center_of_mass if origin is None else as_array("origin", origin, (3,))
    rotations = Rotation.from_quat(traj.quaternion[indices]).as_matrix()
    axes_body = body.principal().axes
    omega_space = np.einsum("fij,fj->fi", rotations, traj.omega[indices])
    momentum = traj.angular_momentum_space
    l_space = np.zeros_like(omega_space) if momentum is None else momentum[indices]

    shape = _shapes.of(body)
    parts = [_shapes.surface((p,), resolution) for p in shape]
    colors = [PART_COLORS[k % len(PART_COLORS)] for k, part in enumerate(parts) for _ in part]
    polygons = [q - fixed for part in parts for q in part]
    reach = max(float(np.max(np.linalg.norm(q, axis=1))) for q in polygons)
    com = body.center_of_mass - fixed
    size = 1.1 * max(reach, float(np.linalg.norm(com)) + 1e-300)
    arrow = 0.9 * size

    def scaled(vectors: NDArray[np.float64]) -> NDArray[np.float64]:
        biggest = float(np.max(np.linalg.norm(vectors, axis=1)))
        return vectors * (arrow / biggest) if biggest > 0 else vectors

    omega_drawn, l_drawn = scaled(omega_space), scaled(l_space)
    axis_length = 0.8 * size

    if ax is None:
        import mpl_toolkits.mplot3d  # noqa: F401  (registers the projection)
        from matplotlib.figure import Figure

        ax = Figure(figsize=(5.0, 5.0), layout="constrained").add_subplot(projection="3d")
    figure = ax.figure
    surface = Poly3DCollection(
        polygons,
        facecolors=colors,
        edgecolors=(0.2, 0.2, 0.2, 0.25),
        linewidths=0.3,
        shade=True,
        gid="body",
    )
    ax.add_collection3d(surface)
    lines = {}
    for k in range(3):
        (lines[f"axis{k}"],) = ax.plot(
            [],
            [],
            [],
            color=AXIS_COLORS[k],
            linewidth=2.0,
            gid=f"axis{k}",
            label=f"{AXIS_ROLES[k]} axis ({k})",
        )
    (lines["omega"],) = ax.plot(
        [], [], [], color="black", linewidth=2.0, gid="omega", label="omega"
    )
    (lines["angular_momentum"],) = ax.plot(
        [],
        [],
        [],
        color="tab:purple",
        linewidth=2.0,
        linestyle="--",
        gid="angular_momentum",
        label="L",
    )
    ax.set_xlim(-size, size)
    ax.set_ylim(-size, size)
    ax.set_zlim(-size, size)
    if space_axes:
        ax.set_box_aspect((1, 1, 1))
    else:
        # The cube of the limits holds the sphere the body turns in: without the axes drawn,
        # zoom in on that sphere.
        ax.set_box_aspect((1, 1, 1), zoom=1.5)
        ax.set_axis_off()
    ax.legend(loc="upper left", fontsize="small")
    title = ax.set_title("")

    def segment(name: str, start: NDArray[np.float64], vector: NDArray[np.float64]) -> None:
        ends = np.stack([start, start + vector])
        lines[name].set_data_3d(ends[:, 0], ends[:, 1], ends[:, 2])

    def draw(frame: int) -> list[Any]:
        r = rotations[frame]
        surface.set_verts([q @ r.T for q in polygons])
        centre = r @ com
        for k in range(3):
            segment(f"axis{k}", centre, axis_length * (r @ axes_body[:, k]))
        segment("omega", np.zeros(3), omega_drawn[frame])
        segment("angular_momentum", np.zeros(3), l_drawn[frame])
        title.set_text(f"t = {traj.t[indices[frame]]:.4g}")
        return [surface, *lines.values(), title]

    animation = FuncAnimation(
        figure, draw, frames=len(indices), interval=interval, blit=False, repeat=True
    )
    animation.frame_indices = indices  # type: ignore[attr-defined]
    if path is not None:
        animation.save(path, writer=writer, fps=1000.0 / interval, dpi=dpi)
    return animation


from polhode._scene import scene  # noqa: E402  (plotly, imported inside)
