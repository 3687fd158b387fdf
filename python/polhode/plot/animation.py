"""The body turning in space, frame by frame (matplotlib's FuncAnimation)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_finite, as_finite_array, as_flag, as_path
from polhode._files import writable
from polhode._norms import norms
from polhode.errors import ArgumentError
from polhode.plot._axes import axes_for, one_trajectory
from polhode.plot._frames import body_axes, fits, principal_of
from polhode.plot._labels import Units, axis_name, units_of
from polhode.plot._poinsot import (
    MARK_COLOR,
    capped_polygons,
    check_resolution,
    equal_lengths,
    frame_indices,
    inertia_box,
    mark_of,
)
from polhode.plot._poinsot import (
    PART_COLORS as PART_COLORS,
)
from polhode.plot.geometry import omega_space as space_rate

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from polhode.bodies import Body
    from polhode.simulation import Trajectory

__all__ = ["AXIS_COLORS", "PART_COLORS", "animate"]

Array = NDArray[np.float64]

#: The ball of the marked end is drawn this far beyond the end (a fraction of the scene's
#: half-width), so that the body does not hide it.
MARK_OFFSET = 0.06

#: The longest interval between frames (ms): a GIF keeps each frame's delay in 16 bits of
#: hundredths of a second, 655.35 s, and matplotlib's writer fails beyond it.
MAX_INTERVAL = 655_350.0

#: The resolution of a saved file (dots per inch): at least MIN_DPI, where the smallest text
#: (8 points) is a pixel high (below it FreeType refuses the glyphs and matplotlib's writer
#: fails), and at most MAX_PIXELS pixels a side for the figure (an 8K frame; the writers keep
#: every frame in memory).
MIN_DPI = 10.0
MAX_PIXELS = 8192

#: Colours of the principal axes 1, 2, 3 (smallest, intermediate, largest moment) in
#: :func:`animate`.
AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")


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
    raise ArgumentError(f"Expected `path` to end in .gif or .mp4, got {path!r}.", argument="path")


@dataclass
class _Shape:
    """What animate draws of the body, about the point held fixed (body coordinates): the
    polygons of each part, the centre of mass, the principal axes (columns, moments
    ascending)."""

    parts: list[list[Array]]
    com: Array
    axes: Array


def _mismatch(traj: Trajectory, tensor: Array, about: str, hint: str) -> ArgumentError:
    return ArgumentError(
        f"`body` does not match `traj`: its inertia about {about} (principal moments "
        f"{np.linalg.eigvalsh(tensor).tolist()}) does not give the trajectory's angular "
        f"momentum from its omega (moments {np.sort(traj.moments).tolist()}); pass the body "
        f"the trajectory was simulated with, in the same axes{hint}.",
        argument="body",
    )


def _shape_of(traj: Trajectory, body: Any, origin: Any, resolution: int) -> _Shape:
    """The body as drawn, checked against the trajectory: a Body's own shape about ``origin``
    (default its centre of mass); for principal moments or a tensor (or None: the
    trajectory's own, read off its data), the uniform box with those moments about its
    centre."""
    from polhode import _shapes
    from polhode.bodies import Body

    fixed = None if origin is None else as_finite_array("origin", origin, (3,))
    if isinstance(body, Body):
        tensor = np.asarray(body.inertia if fixed is None else body.inertia_about(fixed))
        if not fits(traj, tensor):
            about = "its centre of mass" if fixed is None else f"origin={fixed.tolist()}"
            hint = " (for a heavy top, pass origin=the pivot)" if fixed is None else ""
            raise _mismatch(traj, tensor, about, hint)
        point = body.center_of_mass if fixed is None else fixed
        parts = [_shapes.surface((p,), resolution) for p in _shapes.of(body)]
        return _Shape(
            [[q - point for q in part] for part in parts],
            body.center_of_mass - point,
            np.asarray(body.principal().axes, dtype=np.float64),
        )
    if fixed is not None:
        raise ArgumentError(
            "`origin` is a point of `body`: give it with a Body.", argument="origin"
        )
    if body is None:
        frame = body_axes(traj)
        if frame.axes is None:
            raise ArgumentError(
                "`traj` does not tell its principal axes (its body axes are not principal and "
                "its omega does not span every direction): pass its body as `body`.",
                argument="body",
            )
        moments, axes = frame.moments, frame.axes
    else:
        moments, axes = principal_of(body)
    tensor = axes @ np.diag(moments) @ axes.T
    if not fits(traj, tensor):
        raise _mismatch(traj, tensor, "its centre", "")
    return _Shape([inertia_box(tensor)], np.zeros(3), axes)


@dataclass
class _Options:
    indices: NDArray[np.int64]
    interval: float
    resolution: int
    path: str | None
    writer: str | None
    dpi: float
    space_axes: bool
    unit: Units


def _options(traj: Trajectory, **given: Any) -> _Options:
    """animate's options, checked."""
    path = None if given["path"] is None else writable(as_path("path", given["path"]))
    return _Options(
        indices=frame_indices(given["frames"], traj.t.size),
        interval=_interval(given["interval"]),
        resolution=check_resolution(given["resolution"]),
        path=path,
        writer=None if path is None else _writer(path),
        dpi=as_finite("dpi", given["dpi"], positive=True),
        space_axes=as_flag("space_axes", given["space_axes"]),
        unit=units_of(given["units"]),
    )


def _interval(interval: Any) -> float:
    value = as_finite("interval", interval, positive=True)
    if value > MAX_INTERVAL:
        raise ArgumentError(
            f"Expected `interval` to be at most {MAX_INTERVAL:g} ms (the longest frame a GIF "
            f"holds), got {value:g}.",
            argument="interval",
        )
    return value


def _check_dpi(dpi: float, figure: Any) -> None:
    """A saved file's resolution: at least MIN_DPI, and the figure at most MAX_PIXELS a side."""
    inches = float(np.max(figure.get_size_inches()))
    if not MIN_DPI <= dpi <= MAX_PIXELS / inches:
        raise ArgumentError(
            f"Expected `dpi` from {MIN_DPI:g} (text a pixel high) to {MAX_PIXELS / inches:g} "
            f"(a {inches:g} inch figure in {MAX_PIXELS} pixels), got {dpi:g}.",
            argument="dpi",
        )


def animate(
    traj: Trajectory,
    body: Body | Any = None,
    *,
    frames: Any = 60,
    origin: Any = None,
    ax: Axes | None = None,
    interval: float = 50.0,
    resolution: int = 24,
    path: str | None = None,
    dpi: float = 80.0,
    space_axes: bool = False,
    mark: int | None = None,
    units: Mapping[str, str] | None = None,
) -> Any:
    """The body turning in space: its shape, principal axes, omega and L, frame by frame.

    Each frame draws the body at one output time of ``traj``: every point of the body at
    ``R(t) (x - origin)`` in space axes, where ``R(t)`` is the trajectory's orientation (body
    to space) and ``origin`` the body point held fixed (the centre of mass of a free body, the
    pivot of a heavy top). The principal axes I1, I2, I3 (smallest, intermediate, largest
    moment, ``body.principal()``) are drawn through the centre of mass in red, green and blue,
    from the centre of mass outward, omega in space in black and the angular momentum in space
    in purple (fixed without a torque), both scaled to their largest value over the frames.
    One end of the body is **marked** in orange (the last fifth of the body along principal
    axis ``mark``, and a ball where it ends), the end that pointed toward L at the first output
    time, so that a flip is seen even for a body symmetric end to end (as in
    :func:`polhode.plot.scene`).

    The shape is the one the body was built from: solids, meshes and point masses (drawn as
    balls), each part of a composite in its own colour; a body with no geometry
    (``Body.from_inertia``) is drawn as its equivalent ellipsoid (the uniform solid ellipsoid
    with the same inertia); a body given as principal moments or a tensor, as
    :func:`polhode.simulate` takes it, or none, as the uniform box with those moments (up to
    its unknown mass) about its centre, as :func:`polhode.plot.scene` does.

    Parameters
    ----------
    traj : Trajectory
        One body's motion with its orientation, simulated with ``body`` (its inertia, about
        ``origin``, must give the trajectory's angular momentum from its omega).
    body : Body, (3,) principal moments or (3, 3) inertia tensor, optional
        The body whose shape is drawn; moments or a tensor (in the body axes of ``traj``), or
        None for the trajectory's own (read off its omega and angular momentum), are drawn as
        their inertia box.
    frames : int or array_like of int
        The number of frames, at evenly spaced output times (default 60; at most one per
        output time), or the indices of the output times to draw.
    origin : (3,) array_like, optional
        With a Body: the body point (body coordinates) drawn fixed at the origin of space;
        default the centre of mass.
    ax : a 3D Axes, optional
        Drawn on if given (``projection="3d"``), else on a new figure.
    interval : float
        Milliseconds between frames when shown (positive, at most 655350: the longest a GIF
        holds; the frame rate of a saved file is 1000 / interval).
    resolution : int
        Segments around a circle of a solid's surface (6 to 360, one a degree).
    path : str, optional
        Save the animation there: ``.gif`` (pillow) or ``.mp4`` (ffmpeg, if on the PATH).
    dpi : float
        Resolution of a saved file, in dots per inch: at least 10 (the smallest text a pixel
        high), at most 8192 pixels a side of the figure (1638 for the default 5 inches).
    space_axes : bool
        Draw the space axes' ticks, grid and panes (default False: the fixed angular momentum
        is the reference, and each frame renders about four times faster without them).
    mark : {0, 1, 2}, optional
        The principal axis (a 0-based index, moments ascending: axis ``mark + 1``) whose end is
        marked; default the one omega had its largest component along at the first output
        time (the axis spun about).
    units : dict, optional
        The units of the labels (see :func:`polhode.plot.omega`): the time in the title.

    Returns
    -------
    matplotlib.animation.FuncAnimation
        ``.save(...)`` writes it, ``.to_jshtml()`` shows it in Jupyter (e.g.
        ``IPython.display.HTML(anim.to_jshtml())``). The line artists carry the gids
        ``"axis1"``, ``"axis2"``, ``"axis3"`` (the principal axes), ``"omega"``,
        ``"angular_momentum"`` and ``"mark"`` (the ball just beyond the marked end), the surface
        ``"body"``; ``anim.frame_indices`` holds the output-time index of each frame,
        ``anim.mark`` the marked axis (0-based) and ``anim.mark_direction`` its marked end
        (body coordinates).

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> bar = ph.Body.cuboid(1.0, [0.3, 0.1, 0.02])
    >>> sol = ph.simulate(bar, [0.0, 5.0, 0.05], np.linspace(0.0, 4.0, 41))
    >>> anim = ph.plot.animate(sol, bar, frames=10)
    >>> len(anim.frame_indices), anim.mark
    (10, 1)
    >>> html = anim.to_jshtml()  # in Jupyter: IPython.display.HTML(html)
    """
    traj = one_trajectory(traj, "plot.animate", orientation=True)
    options = _options(
        traj,
        frames=frames,
        interval=interval,
        resolution=resolution,
        path=path,
        dpi=dpi,
        space_axes=space_axes,
        units=units,
    )
    shape = _shape_of(traj, body, origin, options.resolution)
    momentum0 = np.asarray(traj.angular_momentum_body, dtype=np.float64)[0]
    marked, direction = mark_of(shape.axes, traj.omega[0], momentum0, mark)
    ax = axes_for(ax, "3d") if ax is not None else _new_axes()
    if options.path is not None:
        _check_dpi(options.dpi, getattr(ax.figure, "figure", ax.figure))
    animation = _Drawing(traj, shape, options, marked, direction).animate(ax)
    if options.path is not None:
        animation.save(
            options.path, writer=options.writer, fps=1000.0 / options.interval, dpi=options.dpi
        )
    return animation


def _new_axes() -> Axes:
    import mpl_toolkits.mplot3d  # noqa: F401  (registers the projection)
    from matplotlib.figure import Figure

    return Figure(figsize=(5.0, 5.0), layout="constrained").add_subplot(projection="3d")


class _Drawing:
    """The artists of :func:`animate` and how each frame moves them."""

    def __init__(
        self, traj: Trajectory, shape: _Shape, options: _Options, mark: int, direction: Array
    ):
        from scipy.spatial.transform import Rotation

        self.traj, self.options, self.mark, self.direction = traj, options, mark, direction
        indices = options.indices
        assert traj.quaternion is not None
        self.rotations = Rotation.from_quat(traj.quaternion[indices]).as_matrix()
        self.axes_body = shape.axes
        omega_space = space_rate(traj)[indices]
        momentum = traj.angular_momentum_space
        l_space = np.zeros_like(omega_space) if momentum is None else momentum[indices]

        polygons = [q for part in shape.parts for q in part]
        owner = [k for k, part in enumerate(shape.parts) for _ in part]
        pieces, owner, capped, end = capped_polygons(polygons, owner, direction)
        self.polygons = equal_lengths(pieces)
        self.colors = [
            MARK_COLOR if cap else PART_COLORS[k % len(PART_COLORS)]
            for k, cap in zip(owner, capped, strict=True)
        ]
        self.end = end
        reach = max(float(np.max(norms(q))) for q in pieces)
        self.com = shape.com
        self.size = 1.1 * max(reach, float(norms(self.com)) + 1e-300)
        arrow = 0.9 * self.size

        def scaled(vectors: Array) -> Array:
            biggest = float(np.max(norms(vectors)))
            return vectors * (arrow / biggest) if biggest > 0 else vectors

        self.omega_drawn, self.l_drawn = scaled(omega_space), scaled(l_space)
        # The ball just beyond the marked end, where the body does not hide it.
        self.ball = end + MARK_OFFSET * self.size * direction
        self.axis_length = 0.8 * self.size

    def animate(self, ax: Axes) -> Any:
        from matplotlib.animation import FuncAnimation
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        surface = Poly3DCollection(
            self.polygons,
            facecolors=self.colors,
            edgecolors=(0.2, 0.2, 0.2, 0.25),
            linewidths=0.3,
            shade=True,
            gid="body",
        )
        ax.add_collection3d(surface)
        lines = self._lines(ax)
        size = self.size
        ax.set_xlim(-size, size)
        ax.set_ylim(-size, size)
        ax.set_zlim(-size, size)
        if self.options.space_axes:
            ax.set_box_aspect((1, 1, 1))
        else:
            # The cube of the limits holds the sphere the body turns in: without the axes
            # drawn, zoom in on that sphere.
            ax.set_box_aspect((1, 1, 1), zoom=1.5)
            ax.set_axis_off()
        ax.legend(loc="upper left", fontsize="small")
        title = ax.set_title("")
        t, indices, unit = self.traj.t, self.options.indices, self.options.unit

        def segment(name: str, start: Array, vector: Array) -> None:
            ends = np.stack([start, start + vector])
            lines[name].set_data_3d(ends[:, 0], ends[:, 1], ends[:, 2])

        def draw(frame: int) -> list[Any]:
            r = self.rotations[frame]
            surface.set_verts([q @ r.T for q in self.polygons])
            centre = r @ self.com
            for k in range(3):
                segment(f"axis{k + 1}", centre, self.axis_length * (r @ self.axes_body[:, k]))
            segment("omega", np.zeros(3), self.omega_drawn[frame])
            segment("angular_momentum", np.zeros(3), self.l_drawn[frame])
            tip = r @ self.ball
            lines["mark"].set_data_3d([tip[0]], [tip[1]], [tip[2]])
            title.set_text(f"t = {t[indices[frame]]:.4g} {unit.time}")
            return [surface, *lines.values(), title]

        animation = FuncAnimation(
            ax.figure,
            draw,
            frames=len(indices),
            interval=self.options.interval,
            blit=False,
            repeat=True,
        )
        animation.frame_indices = indices  # type: ignore[attr-defined]
        animation.mark = self.mark  # type: ignore[attr-defined]
        animation.mark_direction = self.direction  # type: ignore[attr-defined]
        return animation

    def _lines(self, ax: Axes) -> dict[str, Any]:
        lines = {}
        for k in range(3):
            (lines[f"axis{k + 1}"],) = ax.plot(
                [],
                [],
                [],
                color=AXIS_COLORS[k],
                linewidth=2.0,
                gid=f"axis{k + 1}",
                label=axis_name(k),
            )
        (lines["omega"],) = ax.plot(
            [], [], [], color="black", linewidth=2.0, gid="omega", label="$\\omega$"
        )
        (lines["angular_momentum"],) = ax.plot(
            [],
            [],
            [],
            color="tab:purple",
            linewidth=2.0,
            linestyle="--",
            gid="angular_momentum",
            label="$L$",
        )
        (lines["mark"],) = ax.plot(
            [],
            [],
            [],
            marker="o",
            markersize=7,
            color=MARK_COLOR,
            markeredgecolor="black",
            linestyle="",
            gid="mark",
            label=f"marked end: $+I_{{{self.mark + 1}}}$ axis, toward $L$ at $t_0$",
        )
        return lines
