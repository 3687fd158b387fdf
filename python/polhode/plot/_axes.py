"""What the plots share: the roles of the principal axes, the floor of the log axes, a new
figure's Axes (matplotlib imported here, when called), one trajectory, not a batch."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.simulation import Trajectory

__all__ = ["AXIS_ROLES", "FLOOR", "new_axes", "single"]


#: The principal axes by role, indexed 0, 1, 2 with the moments ascending.
AXIS_ROLES = ("smallest", "intermediate", "largest")


#: Errors below this are drawn at this value so a log axis can show exact zeros.
FLOOR = 1e-17


def new_axes(projection: str | None = None) -> Axes:
    from matplotlib.figure import Figure

    if projection == "3d":
        import mpl_toolkits.mplot3d  # noqa: F401  (registers the projection)

    figure = Figure(figsize=(6.4, 4.8), layout="constrained")
    return figure.add_subplot(projection=projection)


def single(traj: Trajectory, what: str) -> None:
    if np.ndim(traj.omega) != 2:
        raise ValueError(
            f"{what} plots one trajectory; got a batch of {np.shape(traj.omega)[0]} "
            "(index it first, e.g. a Trajectory built from traj.omega[k])."
        )
