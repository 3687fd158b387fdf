"""The geometry of the free motion: the polhode on the sphere of |L| (with its separatrices)
and the herpolhode in the invariable plane."""

from __future__ import annotations

import sys
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_finite, as_finite_array, as_flag, as_float_array, as_integer
from polhode._norms import norms
from polhode.errors import ArgumentError, NonFiniteError, NonPositiveError, ShapeError
from polhode.invariants import angular_momentum_space
from polhode.plot._axes import axes_for, one_trajectory
from polhode.plot._frames import body_axes, fits, principal_of
from polhode.plot._labels import labelled, subscripted, units_of

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.simulation import Trajectory

__all__ = [
    "herpolhode",
    "invariable_plane_basis",
    "omega_space",
    "polhode",
    "polhode_curves",
    "separatrix_curves",
]

#: The most points a curve may have (``n``): a curve of 400 is smooth at any size a screen
#: shows, and 18 curves of this many already take matplotlib seconds to draw.
MAX_POINTS = 100_000

#: A trajectory is drawn coloured by time (by default) where its energy changes by more than
#: this, relative: a damper or a torque at work.
ENERGY_CHANGE = 1e-3


def _moments(moments: Any) -> NDArray[np.float64]:
    """Three positive finite principal moments, ascending."""
    m = as_finite_array("moments", moments, (3,))
    if not np.all(m > 0):
        raise NonPositiveError(
            f"Expected `moments` to be positive, got {m.tolist()}.", argument="moments"
        )
    if np.any(np.diff(m) < 0):
        raise ArgumentError(
            f"Expected `moments` ascending (principal axes 1, 2, 3), got {m.tolist()}.",
            argument="moments",
        )
    return m


def _points(n: Any) -> int:
    """The points of a curve, ``n``: an integer from 2 to MAX_POINTS."""
    return as_integer("n", n, minimum=2, maximum=MAX_POINTS, why="points per curve")


def _default_energies(moments: NDArray[np.float64], ell: float) -> list[float]:
    """Kinetic energies spread on both sides of the separatrix, as D = L^2/(2T) in (I1, I3)."""
    i1, i2, i3 = moments
    ds = [i1 + (i2 - i1) * f for f in (0.15, 0.4, 0.65, 0.88)]
    ds += [i2 + (i3 - i2) * f for f in (0.12, 0.35, 0.6, 0.85)]
    ds = [d for d in ds if i1 < d < i3 and d != i2]
    return [ell * (ell / (2.0 * d)) for d in ds]


def _energy_range(moments: NDArray[np.float64], ell: float, name: str) -> tuple[float, float]:
    """[L^2/(2 I3), L^2/(2 I1)]: the kinetic energies of ``|L| = ell`` with these moments (L^2
    never formed: it overflows for |L| = 1e155 where T does not); an ArgumentError naming
    ``name`` where they are beyond double precision (no energy could be drawn)."""
    low = ell * (ell / (2.0 * float(moments[2])))
    high = ell * (ell / (2.0 * float(moments[0])))
    if not (low >= sys.float_info.min and high <= sys.float_info.max):
        raise ArgumentError(
            f"Expected `{name}` to give kinetic energies within double precision: |L| = "
            f"{ell:.6g} with the moments {moments.tolist()} gives L^2/(2 I3) = {low:.3g} to "
            f"L^2/(2 I1) = {high:.3g}.",
            argument=name,
        )
    return low, high


def polhode_curves(
    moments: Sequence[float], angular_momentum_norm: float, energy: float, n: int = 400
) -> list[NDArray[np.float64]]:
    """The closed curve(s) where the sphere ``|L|`` = const meets the ellipsoid sum L_i^2/I_i = 2T.

    ``moments`` are the principal moments, ascending (I1 <= I2 <= I3), not all equal. Returns
    one (n, 3) array per branch, in the principal axes: two branches, one around +axis and one
    around -axis (axis 1, of the smallest moment, if 2T > L^2/I2; axis 3, of the largest, if
    below).
    """
    inertia = _moments(moments)
    i1, i2, i3 = (float(m) for m in inertia)
    if i1 == i3:
        raise ArgumentError(
            f"Expected `moments` not all equal, got {inertia.tolist()}: a spherical top has no "
            "polhode (every axis is fixed).",
            argument="moments",
        )
    ell = as_finite("angular_momentum_norm", angular_momentum_norm, positive=True)
    energy = as_finite("energy", energy)
    n = _points(n)
    low, high = _energy_range(inertia, ell, "angular_momentum_norm")
    if not low <= energy <= high:
        raise ArgumentError(
            f"Expected `energy` in [L^2/(2 I3), L^2/(2 I1)] = [{low:.6g}, {high:.6g}] for "
            f"|L| = {ell:.6g}, got {energy:.6g}.",
            argument="energy",
        )
    # On the unit sphere u = L / |L|: sum u_i^2 / I_i = k = 2T / L^2, within [1/I3, 1/I1].
    k = min(max(2.0 * (energy / ell) / ell, 1.0 / i3), 1.0 / i1)
    phi = np.linspace(0.0, 2.0 * np.pi, n)
    c, s = np.cos(phi), np.sin(phi)
    if k < 1.0 / i2 or (i1 == i2 and k <= 1.0 / i1):
        # around the largest axis: u1^2 (1/I1 - 1/I3) + u2^2 (1/I2 - 1/I3) = k - 1/I3
        rhs = max(k - 1.0 / i3, 0.0)
        a = np.sqrt(rhs / (1 / i1 - 1 / i3)) * c
        b = np.sqrt(rhs / (1 / i2 - 1 / i3)) * s
        rest = np.sqrt(np.maximum(1.0 - a * a - b * b, 0.0))
        return [ell * np.column_stack([a, b, sign * rest]) for sign in (1.0, -1.0)]
    # around the smallest axis: u2^2 (1/I1 - 1/I2) + u3^2 (1/I1 - 1/I3) = 1/I1 - k
    rhs = max(1.0 / i1 - k, 0.0)
    b = np.sqrt(rhs / (1 / i1 - 1 / i2)) * c if i1 != i2 else 0.0 * c
    d = np.sqrt(rhs / (1 / i1 - 1 / i3)) * s
    rest = np.sqrt(np.maximum(1.0 - b * b - d * d, 0.0))
    return [ell * np.column_stack([sign * rest, b, d]) for sign in (1.0, -1.0)]


def separatrix_curves(
    moments: Sequence[float], angular_momentum_norm: float, n: int = 400
) -> list[NDArray[np.float64]]:
    """The separatrices 2T = L^2/I2 on the sphere: two great circles L3 = +-k L1, with
    k^2 = (1/I1 - 1/I2)/(1/I2 - 1/I3), in the principal axes (``moments`` ascending). Empty
    for a symmetric body (I1 = I2 or I2 = I3)."""
    i1, i2, i3 = (float(m) for m in _moments(moments))
    ell = as_finite("angular_momentum_norm", angular_momentum_norm, positive=True)
    n = _points(n)
    if not i1 < i2 < i3:
        return []
    k = np.sqrt((1 / i1 - 1 / i2) / (1 / i2 - 1 / i3))
    phi = np.linspace(0.0, 2.0 * np.pi, n)
    l1 = ell * np.cos(phi) / np.sqrt(1.0 + k * k)
    l2 = ell * np.sin(phi)
    return [np.column_stack([l1, l2, sign * k * l1]) for sign in (1.0, -1.0)]


def _in_principal_axes(
    body: Any, traj: Trajectory | None
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """The principal moments (ascending) and, with ``traj``, its angular momentum in those
    axes (M, 3): from ``body`` (checked against the trajectory), else from the trajectory's
    own data."""
    if body is None and traj is None:
        raise TypeError(
            "plot.polhode needs `body` (a Body, principal moments (3,) or an inertia tensor) "
            "or `traj`."
        )
    momentum = None if traj is None else np.asarray(traj.angular_momentum_body, dtype=np.float64)
    if body is not None:
        moments, axes = principal_of(body)
        if traj is not None and not fits(traj, axes @ np.diag(moments) @ axes.T):
            raise ArgumentError(
                "`body` does not match `traj`: its inertia (principal moments "
                f"{moments.tolist()}) does not give the trajectory's angular momentum from its "
                f"omega (moments {np.sort(traj.moments).tolist()}); pass the body the trajectory "
                "was simulated with, in the same axes.",
                argument="body",
            )
        return moments, None if momentum is None else momentum @ axes
    assert traj is not None and momentum is not None
    frame = body_axes(traj)
    if frame.axes is None:
        raise ArgumentError(
            "`traj` does not tell its principal axes (its body axes are not principal and its "
            "omega does not span every direction, as in a steady spin): pass the body it was "
            "simulated with as `body`.",
            argument="traj",
        )
    return frame.moments, momentum @ frame.axes


def _energies(
    energies: Any, moments: NDArray[np.float64], ell: float, low: float, high: float
) -> list[float]:
    """The energy levels drawn: ``energies`` (checked within [low, high], those of ``|L| =
    ell``), or by default eight on both sides of the separatrix."""
    if energies is None:
        return _default_energies(moments, ell)
    levels = as_float_array("energies", energies)
    if levels.ndim != 1:
        raise ShapeError(
            f"Expected `energies` to have shape (K,), got {levels.shape}.", argument="energies"
        )
    if not np.all(np.isfinite(levels)):
        raise NonFiniteError(
            f"Expected `energies` to be finite, got {levels.tolist()}.", argument="energies"
        )
    outside = levels[(levels < low) | (levels > high)]
    if outside.size:
        raise ArgumentError(
            f"Expected `energies` in [L^2/(2 I3), L^2/(2 I1)] = [{low:.6g}, {high:.6g}] for "
            f"|L| = {ell:.6g}, got {outside.tolist()}.",
            argument="energies",
        )
    return [float(e) for e in levels]


def polhode(
    body: Any = None,
    angular_momentum_norm: float | None = None,
    energies: Sequence[float] | None = None,
    ax: Axes | None = None,
    *,
    traj: Trajectory | None = None,
    sphere: bool = True,
    n: int = 400,
    color_by_time: bool | None = None,
    units: Mapping[str, str] | None = None,
) -> Axes:
    """The polhode: the angular momentum in the principal axes on the sphere ``|L|`` = const
    (3D axes), the axes numbered 1, 2, 3 with I1 <= I2 <= I3.

    Parameters
    ----------
    body : Body, (3,) principal moments or (3, 3) inertia tensor, optional
        The body, as :func:`polhode.simulate` takes it (moments in any order); default: the
        trajectory's (``traj``).
    angular_momentum_norm : ``|L|``; default ``|L|`` of ``traj`` at t[0], else 1.
    energies : kinetic energies T, one closed curve pair (both branches) each; default eight
        levels on both sides of the separatrix.
    ax : a 3D Axes (``projection="3d"``) or None for a new figure.
    traj : a trajectory whose angular momentum is overlaid, turned into the principal axes:
        those of ``body``, which must be the body it was simulated with, or without ``body``
        those its own omega and angular momentum tell.
    sphere : draw a faint wireframe of the sphere.
    n : points per curve (2 to 100000).
    color_by_time : draw the trajectory coloured by time, with a colour bar, its start and its
        end marked (and the energy levels only if ``energies`` are given: it crosses them);
        default: where its energy changes by more than 0.1 % (a damper or a torque at work),
        where it would otherwise be a tangle.
    units : the units of the labels (see :func:`polhode.plot.omega`): L in mass length^2 per
        time.

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
    >>> ax.get_xlabel()
    '$L_{1}$ (kg m$^2$/s)'
    """
    if traj is not None:
        traj = one_trajectory(traj, "plot.polhode", moving=True)
    moments, momentum = _in_principal_axes(body, traj)
    if moments[0] == moments[2]:
        raise ArgumentError(
            "A spherical top (I1 = I2 = I3) has no polhode: every axis is fixed.",
            argument="body" if body is not None else "traj",
        )
    sphere = as_flag("sphere", sphere)
    n = _points(n)
    unit = units_of(units)
    if angular_momentum_norm is None:
        ell = 1.0 if momentum is None else float(norms(momentum[0]))
        t_lo, t_hi = _energy_range(moments, ell, "body" if momentum is None else "traj")
    else:
        ell = as_finite("angular_momentum_norm", angular_momentum_norm, positive=True)
        t_lo, t_hi = _energy_range(moments, ell, "angular_momentum_norm")
    by_time = _by_time(color_by_time, traj)
    # Coloured by time, the trajectory crosses the energy levels: none unless asked for.
    levels = [] if by_time and energies is None else _energies(energies, moments, ell, t_lo, t_hi)
    ax = axes_for(ax, "3d")

    if sphere:
        u, v = np.mgrid[0 : 2 * np.pi : 25j, 0 : np.pi : 13j]
        ax.plot_wireframe(
            ell * np.cos(u) * np.sin(v),
            ell * np.sin(u) * np.sin(v),
            ell * np.cos(v),
            color="0.85",
            linewidth=0.4,
        )
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    for energy in levels:
        color = cmap((energy - t_lo) / (t_hi - t_lo) if t_hi > t_lo else 0.5)
        for curve in polhode_curves(moments, ell, energy, n):
            ax.plot(*curve.T, color=color, linewidth=1.0, gid=f"polhode:{float(energy)!r}")
    for k, curve in enumerate(separatrix_curves(moments, ell, n)):
        ax.plot(
            *curve.T,
            color="black",
            linewidth=1.8,
            linestyle="--",
            gid="separatrix",
            label="separatrix" if k == 0 else None,
        )
    if traj is not None and momentum is not None:
        _trajectory(ax, traj, momentum, by_time, unit.time)
    _label_axes(ax, [labelled(subscripted("L", k + 1), unit.momentum()) for k in range(3)])
    ax.set_title("Polhode: $L$ on $|L|$ = const, principal axes ($I_1 \\leq I_2 \\leq I_3$)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left")
    return ax


def _label_axes(ax: Axes, labels: list[str]) -> None:
    """Labels on the three axes of a cube of 3-D Axes, set off from five ticks each so that
    they do not run into the tick labels, and the cube shrunk a little so that the labels
    stay inside the figure."""
    from matplotlib.ticker import MaxNLocator

    for axis, label in zip((ax.xaxis, ax.yaxis, ax.zaxis), labels, strict=True):  # type: ignore[attr-defined]
        axis.set_major_locator(MaxNLocator(5))
        axis.set_label_text(label)
        axis.labelpad = 8
    ax.set_box_aspect((1, 1, 1), zoom=0.88)


def _by_time(color_by_time: Any, traj: Trajectory | None) -> bool:
    if traj is None:
        if color_by_time is not None:
            as_flag("color_by_time", color_by_time)
        return False
    if color_by_time is not None:
        return as_flag("color_by_time", color_by_time)
    energy = np.asarray(traj.energy, dtype=np.float64)
    return bool(np.max(np.abs(energy - energy[0])) > ENERGY_CHANGE * abs(energy[0]))


def _trajectory(
    ax: Axes, traj: Trajectory, momentum: NDArray[np.float64], by_time: bool, time_unit: str
) -> None:
    """The trajectory's L on the sphere: the line ``"trajectory"`` in red, or, coloured by
    time, the segments ``"trajectory:time"`` with a colour bar and the mark of t0 (the line
    then holds the same points, hidden)."""
    (line,) = ax.plot(
        *momentum.T, color="tab:red", linewidth=2.0, gid="trajectory", label="trajectory"
    )
    if not by_time:
        return
    from matplotlib.colors import Normalize
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    line.set_visible(False)
    line.set_label("_trajectory")
    ax.computed_zorder = False  # type: ignore[attr-defined]  # drawn in order: the ends on top
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap

    # plasma without its last, pale yellow, which would vanish on the white background.
    cmap = ListedColormap(colormaps["plasma"](np.linspace(0.0, 0.85, 256)))
    t = np.asarray(traj.t, dtype=np.float64)
    segments = np.stack([momentum[:-1], momentum[1:]], axis=1)
    colors = Line3DCollection(
        segments, cmap=cmap, norm=Normalize(float(t[0]), float(t[-1])), linewidth=0.9
    )
    colors.set_array((t[:-1] + t[1:]) / 2.0)
    colors.set_gid("trajectory:time")
    ax.add_collection3d(colors)
    for gid, k, marker, label in (("start", 0, "o", "$t_0$"), ("end", -1, "s", "end")):
        ax.plot(
            *momentum[k].reshape(3, 1),
            marker=marker,
            color=cmap(0.0 if k == 0 else 1.0),
            markeredgecolor="black",
            markersize=6,
            linestyle="",
            gid=gid,
            label=label,
        )
    ax.figure.colorbar(colors, ax=ax, shrink=0.6, pad=0.04, label=labelled("$t$", time_unit))


def invariable_plane_basis(
    angular_momentum: Sequence[float], hint: Sequence[float] | None = None
) -> NDArray[np.float64]:
    """Rows e1, e2, n: an orthonormal right-handed basis with n = L/``|L|`` (L not zero); e1
    along the part of ``hint`` perpendicular to n when that is not zero."""
    n = as_finite_array("angular_momentum", angular_momentum, (3,))
    size = float(np.max(np.abs(n)))
    if size == 0.0:
        raise ArgumentError(
            "Expected `angular_momentum` to be non-zero (the invariable plane is perpendicular "
            "to it), got [0, 0, 0].",
            argument="angular_momentum",
        )
    n = n / size  # scaled first: the norm of 1e154-sized entries would overflow
    n = n / np.linalg.norm(n)
    given = None if hint is None else as_finite_array("hint", hint, (3,))
    largest = 0.0 if given is None else float(np.max(np.abs(given)))
    # scaled first, as L: the dot products of 1e155-sized entries would overflow
    candidates = [given / largest] if given is not None and largest > 0.0 else []
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
    """The angular velocity in space axes, (M, 3): the trajectory's ``omega_space`` (the core
    turns omega into space at each output time), or, for a trajectory made without it, its
    ``omega`` turned by its ``quaternion``.

    Examples
    --------
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.3, 1.0, 0.2], [0.0, 1.0, 2.0])
    >>> ph.plot.omega_space(sol) is sol.omega_space
    True
    """
    traj = one_trajectory(traj, "plot.omega_space", orientation=True)
    if traj.omega_space is not None:
        return traj.omega_space
    from scipy.spatial.transform import Rotation

    assert traj.quaternion is not None
    return np.asarray(Rotation.from_quat(traj.quaternion).apply(traj.omega), dtype=np.float64)


def herpolhode(
    traj: Trajectory, ax: Axes | None = None, *, units: Mapping[str, str] | None = None
) -> Axes:
    """The herpolhode: the tip of omega in space, in the invariable plane (perpendicular to L).

    Coordinates are along e1, e2 of :func:`invariable_plane_basis` for L(t0), with e1 along the
    initial omega's part in the plane; the component along L, 2T/``|L|``, is constant and dropped.
    ``units`` as in :func:`polhode.plot.omega`.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.3, 1.0, 0.2], np.linspace(0.0, 20.0, 401))
    >>> ax = ph.plot.herpolhode(sol)
    >>> [line.get_gid() for line in ax.get_lines()]
    ['herpolhode', 'L axis', 'start']
    >>> ax.get_xlabel()
    '$\\\\omega \\\\cdot e_1$ (rad/s)'
    """
    traj = one_trajectory(traj, "plot.herpolhode", orientation=True, moving=True)
    unit = units_of(units)
    ax = axes_for(ax)
    w = omega_space(traj)
    space = angular_momentum_space(traj)
    assert space is not None  # one_trajectory has checked the orientation
    basis = invariable_plane_basis(space[0], hint=w[0])
    xy = w @ basis[:2].T
    ax.plot(xy[:, 0], xy[:, 1], color="tab:blue", linewidth=1.0, gid="herpolhode")
    ax.plot([0.0], [0.0], marker="+", color="black", markersize=10, gid="L axis", label="$L$ axis")
    ax.plot(
        xy[:1, 0], xy[:1, 1], marker="o", color="tab:red", linestyle="", gid="start", label="$t_0$"
    )
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(labelled("$\\omega \\cdot e_1$", unit.rate))
    ax.set_ylabel(labelled("$\\omega \\cdot e_2$", unit.rate))
    ax.set_title("Herpolhode: $\\omega$ in the invariable plane ($e_1, e_2 \\perp L$)")
    ax.legend(loc="upper right")
    return ax
