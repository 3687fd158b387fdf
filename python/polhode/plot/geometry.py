"""The geometry of the free motion: the polhode on the sphere of |L| (with its separatrices)
and the herpolhode in the invariable plane."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_flag
from polhode.invariants import angular_momentum_space
from polhode.plot._axes import new_axes, single

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
        single(traj, "polhode")
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

    ax = new_axes("3d") if ax is None else ax
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

    single(traj, "herpolhode")
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
    ax = new_axes() if ax is None else ax
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
