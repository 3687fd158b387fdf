"""External torques for :func:`polhode.simulate`, evaluated in Rust (a function is the slow path).

Every model gives the torque about the centre of mass (or, for :class:`Gravity`, about the fixed
pivot), in the body's own axes (the axes its inertia is given in), and they add:
``BodyFixed(...) + SpaceFixed(...)``. The core rotates every model into the principal axes it
integrates in. A Python callable ``torque(t, omega, quaternion) -> (3,)`` works too: ``omega``
in body axes, ``quaternion`` the body-to-space orientation (x, y, z, w), the torque returned in
body axes. It is called from Rust at every stage of every step, holding the GIL: expect
scipy-like speed, not polhode's.

The models are immutable values: a simulation reads them and never writes on them, so one
model can serve any number of runs and bodies.
"""

from __future__ import annotations

import reprlib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from polhode import _core
from polhode._coerce import (
    as_array,
    as_flag,
    as_float_array,
    as_scalar,
    read_only_arrays,
)
from polhode.errors import ShapeError

__all__ = [
    "BodyFixed",
    "Function",
    "Gravity",
    "GravityGradient",
    "SpaceFixed",
    "Sum",
    "Torque",
    "Window",
    "as_torque",
]


def _torque_value(value: Any) -> NDArray[np.float64]:
    """What a torque function returned, as a (3,) float array, or a clear error: real numbers
    only (numpy's own conversion took the real part of complex numbers, read strings and
    dates as numbers, None as NaN and ignored a mask)."""
    if type(value) is np.ndarray and value.dtype == np.float64 and value.shape == (3,):
        return value
    if value is None or isinstance(value, str | bytes | dict) or np.ma.is_masked(value):
        raise TypeError(
            f"Expected `torque` to return 3 numbers (body axes), got {type(value).__name__}"
            f"{' with masked values' if np.ma.is_masked(value) else ''}."
        )
    try:
        array = as_float_array("torque", value)
    except TypeError as error:
        raise TypeError(
            f"Expected `torque` to return 3 real numbers (body axes), got {reprlib.repr(value)}."
        ) from error
    if array.shape != (3,):
        raise ShapeError(
            f"Expected `torque` to return shape (3,), got shape {array.shape}.", argument="torque"
        )
    return array


def _sequence(name: str, value: Any) -> Any:
    """``value`` if it is a sequence (an iterable other than a string, a torque or a
    number), else a TypeError naming ``name``."""
    if isinstance(value, str | bytes | Torque) or not isinstance(value, Iterable):
        raise TypeError(f"Expected `{name}` to be a sequence, got {type(value).__name__}.")
    return value


class Torque:
    """Base class of the torque models; models add with ``+``.

    A model's ``kind`` (its class name) and its named fields are what the core reads; its
    parameters are checked by the core when it is made.

    Examples
    --------
    >>> import polhode as ph
    >>> model = ph.torque.BodyFixed([0.0, 0.0, 1.0]) + ph.torque.SpaceFixed([0.5, 0.0, 0.0])
    >>> isinstance(model, ph.torque.Torque), model.kind, len(model.terms)
    (True, 'Sum', 2)
    """

    kind: ClassVar[str] = ""

    def __post_init__(self) -> None:
        _core.check_torque(self)

    def __setstate__(self, state: dict[str, Any]) -> None:
        # Unpickled or deep-copied, a model is what its constructor made: its arrays read-only
        # again and its fields checked by the core.
        self.__dict__.update(read_only_arrays(state))
        self.__post_init__()

    def __add__(self, other: object) -> Torque:
        if isinstance(other, Torque):
            return Sum([self, other])
        return NotImplemented


def _vector(name: str, value: Any) -> NDArray[np.float64]:
    array = as_array(name, value, (3,))
    array.flags.writeable = False
    return array


def _optional_vector(name: str, value: Any) -> NDArray[np.float64] | None:
    return None if value is None else _vector(name, value)


@dataclass(frozen=True, eq=False)
class BodyFixed(Torque):
    """A constant torque in body axes (e.g. a thruster fixed to the body).

    Examples
    --------
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], 2.0, method="rk4", dt=0.01,
    ...                   torque=ph.torque.BodyFixed([0.0, 0.0, 3.0]))
    >>> round(float(sol.omega[-1, 2]), 12)  # tau / I3 * t
    2.0
    """

    kind: ClassVar[str] = "BodyFixed"
    torque: NDArray[np.float64]

    def __init__(self, torque: Any) -> None:
        object.__setattr__(self, "torque", _vector("torque", torque))
        self.__post_init__()

    def __repr__(self) -> str:
        return f"BodyFixed({self.torque.tolist()})"


@dataclass(frozen=True, eq=False)
class SpaceFixed(Torque):
    """A constant torque in space axes.

    Examples
    --------
    Half a newton metre about the space z axis on a body at rest (I = 1): L grows as tau t.

    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 1.0, 1.0], [0.0, 0.0, 0.0], 2.0,
    ...                   torque=ph.torque.SpaceFixed([0.0, 0.0, 0.5]))
    >>> sol.angular_momentum_space[-1].round(12).tolist()
    [0.0, 0.0, 1.0]
    """

    kind: ClassVar[str] = "SpaceFixed"
    torque: NDArray[np.float64]

    def __init__(self, torque: Any) -> None:
        object.__setattr__(self, "torque", _vector("torque", torque))
        self.__post_init__()

    def __repr__(self) -> str:
        return f"SpaceFixed({self.torque.tolist()})"


@dataclass(frozen=True, eq=False)
class Gravity(Torque):
    """Uniform gravity on a body hinged at a fixed pivot: the heavy top.

    The torque about the pivot is ``r_cm x m g`` with ``r_cm`` the centre of mass seen from the
    pivot. With a :class:`polhode.Body`, :func:`polhode.simulate` integrates with the body's
    inertia about ``pivot`` (body coordinates, default the body's origin) and takes the mass
    and centre of mass from the body. With principal moments or a tensor instead of a Body,
    they must already be about the pivot, and ``mass`` and ``center_of_mass`` (from the pivot,
    in the body's axes) are required; ``pivot`` is then not taken.

    Parameters
    ----------
    gravity : (3,) array_like
        The gravitational acceleration in space axes (default (0, 0, -9.81)).
    pivot : (3,) array_like, optional
        The pivot in body coordinates (with a Body; default its origin).
    mass, center_of_mass : optional
        Only with principal moments or a tensor instead of a Body.

    Examples
    --------
    A fast top: a cone (100 g, r = 4 cm, 3 cm from base to apex) spinning at 150 rad/s on its
    apex, tilted 0.3 rad from the vertical. Its axis precesses at about 3.2 rad/s (the
    gyroscopic estimate m g l / (I_s omega_s) is 3.07 rad/s):

    >>> import numpy as np
    >>> import polhode as ph
    >>> from scipy.spatial.transform import Rotation
    >>> top = ph.Body.cone(0.1, 0.04, 0.03)  # base disc at z = 0, apex at z = 0.03
    >>> t = np.linspace(0.0, 4.0, 401)
    >>> sol = ph.simulate(top, [0.0, 0.0, 150.0], t,
    ...                   orientation0=Rotation.from_rotvec([np.pi - 0.3, 0.0, 0.0]),
    ...                   torque=ph.torque.Gravity(pivot=[0.0, 0.0, 0.03]))
    >>> up = sol.orientation.apply([0.0, 0.0, -1.0])  # the top's axis, apex to base
    >>> azimuth = np.unwrap(np.arctan2(up[:, 1], up[:, 0]))
    >>> round(float(abs(azimuth[-1] - azimuth[0]) / 4.0), 1)
    3.2
    """

    kind: ClassVar[str] = "Gravity"
    gravity: NDArray[np.float64]
    pivot: NDArray[np.float64] | None
    mass: float | None
    center_of_mass: NDArray[np.float64] | None

    def __init__(
        self,
        gravity: Any = (0.0, 0.0, -9.81),
        *,
        pivot: Any = None,
        mass: float | None = None,
        center_of_mass: Any = None,
    ) -> None:
        object.__setattr__(self, "gravity", _vector("gravity", gravity))
        object.__setattr__(self, "pivot", _optional_vector("pivot", pivot))
        object.__setattr__(self, "mass", None if mass is None else as_scalar("mass", mass))
        object.__setattr__(
            self, "center_of_mass", _optional_vector("center_of_mass", center_of_mass)
        )
        self.__post_init__()

    def __repr__(self) -> str:
        pivot = None if self.pivot is None else self.pivot.tolist()
        return f"Gravity({self.gravity.tolist()}, pivot={pivot})"


@dataclass(frozen=True, eq=False)
class GravityGradient(Torque):
    """Gravity-gradient torque on a satellite in a circular orbit: ``3 n^2 r x (I r)``.

    ``r`` is the unit radial direction in body axes and ``I`` the body's inertia tensor in
    those axes; in space, ``r`` turns about ``orbit_normal`` at the mean motion
    ``n = sqrt(mu / a^3)``, starting from ``radial0`` at t = 0. Both are directions (any
    size); ``radial0`` is projected into the orbit plane (its part along ``orbit_normal``
    dropped), and must not be parallel to ``orbit_normal``.

    Examples
    --------
    A satellite of I = (1, 2, 3) turned 0.1 rad about the orbit normal from the radial
    direction: the torque pulls its axis of least inertia back, at
    ``tau_z = -3 n^2 sin(0.1) cos(0.1)``.

    >>> import numpy as np
    >>> import polhode as ph
    >>> from scipy.spatial.transform import Rotation
    >>> n = 1e-3
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], 0.01,
    ...                   orientation0=Rotation.from_rotvec([0.0, 0.0, 0.1]),
    ...                   torque=ph.torque.GravityGradient(n))
    >>> tau = -3 * n**2 * np.sin(0.1) * np.cos(0.1)
    >>> round(float(sol.omega[-1, 2] / (tau * 0.01 / 3.0)), 3)  # omega_z = tau t / I3
    1.0
    """

    kind: ClassVar[str] = "GravityGradient"
    mean_motion: float
    orbit_normal: NDArray[np.float64]
    radial0: NDArray[np.float64]

    def __init__(
        self,
        mean_motion: float,
        orbit_normal: Any = (0.0, 0.0, 1.0),
        radial0: Any = (1.0, 0.0, 0.0),
    ) -> None:
        object.__setattr__(self, "mean_motion", as_scalar("mean_motion", mean_motion))
        object.__setattr__(self, "orbit_normal", _vector("orbit_normal", orbit_normal))
        object.__setattr__(self, "radial0", _vector("radial0", radial0))
        self.__post_init__()


@dataclass(frozen=True, eq=False)
class Window(Torque):
    """``torque`` acting only for ``start <= t < end``; the integrators step to both ends.

    Examples
    --------
    Two newton metres for one second, then nothing: the spin ends at tau (end - start) / I.

    >>> import polhode as ph
    >>> kick = ph.torque.Window(ph.torque.BodyFixed([0.0, 0.0, 2.0]), 0.0, 1.0)
    >>> sol = ph.simulate([1.0, 1.0, 1.0], [0.0, 0.0, 0.0], 3.0, torque=kick, method="rk4",
    ...                   dt=0.1)
    >>> sol.omega[-1].round(12).tolist()
    [0.0, 0.0, 2.0]
    """

    kind: ClassVar[str] = "Window"
    torque: Torque
    start: float
    end: float

    def __init__(self, torque: Any, start: float, end: float) -> None:
        object.__setattr__(self, "torque", as_torque(torque))
        object.__setattr__(self, "start", as_scalar("start", start))
        object.__setattr__(self, "end", as_scalar("end", end))
        self.__post_init__()


@dataclass(frozen=True, eq=False)
class Sum(Torque):
    """The sum of several torques.

    Examples
    --------
    >>> import polhode as ph
    >>> both = ph.torque.Sum([ph.torque.BodyFixed([0.0, 0.0, 1.0])] * 2)
    >>> sol = ph.simulate([1.0, 1.0, 1.0], [0.0, 0.0, 0.0], 1.0, torque=both)
    >>> sol.omega[-1].round(12).tolist()
    [0.0, 0.0, 2.0]
    """

    kind: ClassVar[str] = "Sum"
    terms: tuple[Torque, ...] = field(default=())

    def __init__(self, terms: Sequence[Any]) -> None:
        object.__setattr__(self, "terms", tuple(as_torque(t) for t in _sequence("terms", terms)))
        self.__post_init__()


@dataclass(frozen=True, eq=False)
class Function(Torque):
    """A Python callable ``torque(t, omega, quaternion) -> (3,)`` in body axes (slow path).

    Declare ``depends_on_orientation=False`` or ``depends_on_omega=False`` when true (a wrong
    declaration gives wrong results) and the times at which it jumps (``discontinuities``), so
    that no step straddles a jump. For a smooth torque that acts only on an interval, prefer
    ``Window(Function(smooth), start, end)`` to a function that switches itself: the window is
    decided once per segment while the smooth part is evaluated at every stage, which keeps
    the order-4 and order-6 splittings at their full order (a self-switching function costs
    them about three orders).

    Examples
    --------
    A drag torque ``-c omega`` slows a sphere's spin as ``exp(-c t / I)``:

    >>> import numpy as np
    >>> import polhode as ph
    >>> drag = ph.torque.Function(lambda t, w, q: -0.5 * w, depends_on_orientation=False)
    >>> sol = ph.simulate([1.0, 1.0, 1.0], [0.0, 0.0, 1.0], 2.0, torque=drag)
    >>> round(float(sol.omega[-1, 2]), 8), round(float(np.exp(-1.0)), 8)
    (0.36787944, 0.36787944)
    """

    kind: ClassVar[str] = "Function"
    function: Callable[..., Any]
    depends_on_orientation: bool
    depends_on_omega: bool
    discontinuities: tuple[float, ...]

    def __init__(
        self,
        function: Callable[..., Any],
        *,
        depends_on_orientation: bool = True,
        depends_on_omega: bool = True,
        discontinuities: Sequence[float] = (),
    ) -> None:
        if not callable(function):
            raise TypeError(f"Expected `torque` to be callable, got {type(function).__name__}.")
        object.__setattr__(self, "function", function)
        for name, flag in (
            ("depends_on_orientation", depends_on_orientation),
            ("depends_on_omega", depends_on_omega),
        ):
            object.__setattr__(self, name, as_flag(name, flag))
        object.__setattr__(
            self,
            "discontinuities",
            tuple(
                as_scalar("discontinuities", t)
                for t in _sequence("discontinuities", discontinuities)
            ),
        )
        self.__post_init__()

    def _call(self, t: float, omega: Any, quaternion: Any) -> NDArray[np.float64]:
        """The function at (t, omega, quaternion), its value checked (called by the core)."""
        return _torque_value(self.function(t, np.asarray(omega), np.asarray(quaternion)))


def as_torque(torque: Any) -> Torque:
    """A torque model from a model or a plain callable.

    Examples
    --------
    >>> import polhode as ph
    >>> ph.torque.as_torque(lambda t, w, q: (0.0, 0.0, 0.0)).kind
    'Function'
    >>> ph.torque.as_torque(ph.torque.BodyFixed([1.0, 0.0, 0.0]))
    BodyFixed([1.0, 0.0, 0.0])
    """
    if isinstance(torque, Torque):
        return torque
    if callable(torque):
        return Function(torque)
    raise TypeError(
        "Expected `torque` to be a polhode.torque model or a callable, "
        f"got {type(torque).__name__}."
    )
