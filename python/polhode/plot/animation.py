"""The body turning in space, frame by frame (matplotlib's FuncAnimation)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_flag
from polhode.plot._axes import AXIS_ROLES, single

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.simulation import Trajectory

__all__ = ["AXIS_COLORS", "PART_COLORS", "animate"]


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

    single(traj, "animate")
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
