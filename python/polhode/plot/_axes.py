"""What the plots share: the floor of the log axes, the Axes a plot draws on (a new figure's,
or the caller's, checked to be of the right kind; matplotlib imported here, when called), and
the checks of a trajectory argument (one body, with its orientation where one is needed)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from polhode._coerce import as_finite
from polhode.errors import ArgumentError, ShapeError
from polhode.plot._labels import AXIS_ROLES

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.simulation import Trajectory

__all__ = ["AXIS_ROLES", "FLOOR", "axes_for", "check_floor", "new_axes", "one_trajectory"]


#: Errors below this are drawn at this value so a log axis can show exact zeros.
FLOOR = 1e-17


def new_axes(projection: str | None = None) -> Axes:
    """The Axes of a new figure (never pyplot's), laid out so that nothing is clipped."""
    from matplotlib.figure import Figure

    if projection == "3d":
        import mpl_toolkits.mplot3d  # noqa: F401  (registers the projection)

    figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    return figure.add_subplot(projection=projection)


#: The names matplotlib gives its Axes classes (``Axes.name``) by projection.
_KINDS = {None: ("rectilinear", "a 2-D Axes"), "3d": ("3d", "a 3-D Axes (projection='3d')")}


def axes_for(ax: Any, projection: str | None = None) -> Axes:
    """``ax`` if it is an Axes of the right kind (2-D rectilinear, or 3-D), a new figure's if
    None; TypeError naming ``ax`` for anything else (a string, a 3-D Axes for a 2-D plot, a
    polar one)."""
    if ax is None:
        return new_axes(projection)
    from matplotlib.axes import Axes

    name, wanted = _KINDS[projection]
    if not isinstance(ax, Axes):
        raise TypeError(
            f"Expected `ax` to be {wanted} or None, got {type(ax).__name__}.",
        )
    if getattr(ax, "name", None) != name:
        raise TypeError(
            f"Expected `ax` to be {wanted} or None, got a {ax.name} Axes"
            + (" (this plot is 3-D: figure.add_subplot(projection='3d'))." if name == "3d" else ".")
        )
    return ax


def check_floor(floor: Any) -> float:
    """The floor of a log axis: a finite positive number."""
    return as_finite("floor", floor, positive=True)


def one_trajectory(
    traj: Any, what: str, *, name: str = "traj", orientation: bool = False, moving: bool = False
) -> Trajectory:
    """``traj`` if it is one body's Trajectory: TypeError for anything else, ShapeError for a
    batch, ArgumentError without the orientation when ``orientation``, or at rest (no angular
    momentum at the first output time) when ``moving``."""
    from polhode.simulation import Trajectory

    if not isinstance(traj, Trajectory):
        raise TypeError(f"Expected `{name}` to be a polhode.Trajectory, got {type(traj).__name__}.")
    if np.ndim(traj.omega) != 2:
        # A batch is indexed where Trajectory supports it (sweep[k]); else simulated apart.
        how = f"`{name}[k]`" if hasattr(type(traj), "__getitem__") else "simulate that body alone"
        raise ShapeError(
            f"{what} draws one body; `{name}` is a batch of {np.shape(traj.omega)[0]} bodies: "
            f"pass one body's trajectory ({how}).",
            argument=name,
        )
    if orientation and traj.quaternion is None:
        raise ArgumentError(
            f"`{name}` has no orientation (simulated with orientation=False), which {what} "
            "needs: simulate with orientation=True.",
            argument=name,
        )
    if moving and (
        traj.t.size == 0 or not np.any(np.asarray(traj.angular_momentum_body)[0] != 0.0)
    ):
        raise ArgumentError(
            f"`{name}` is at rest at its first output time (omega = 0, no angular momentum): "
            f"{what} has nothing to draw.",
            argument=name,
        )
    return traj
