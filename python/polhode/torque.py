"""External torques for :func:`polhode.simulate`, evaluated in Rust (a callable is the slow path).

Every model gives the torque about the centre of mass (or, for :class:`Gravity`, about the fixed
pivot) and they add: ``BodyFixed(...) + SpaceFixed(...)``. A Python callable
``torque(t, omega, quaternion) -> (3,)`` works too: ``omega`` in body axes, ``quaternion`` the
body-to-space orientation (x, y, z, w), the torque returned in body axes. It is called from Rust
at every stage of every step, holding the GIL: expect scipy-like speed, not polhode's.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_array, as_scalar

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


def _finite(name: str, value: NDArray[np.float64]) -> NDArray[np.float64]:
    if not np.all(np.isfinite(value)):
        from polhode._core import PolhodeError

        raise PolhodeError(f"Expected `{name}` to be finite, got {value.tolist()}.")
    return value


def _torque_value(value: Any) -> NDArray[np.float64]:
    """What a callable torque returned, as a (3,) float array, or a clear error."""
    from polhode._core import PolhodeError

    if value is None or isinstance(value, str | bytes | dict):
        raise TypeError(
            f"Expected `torque` to return 3 numbers (body axes), got {type(value).__name__}."
        )
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise TypeError(
            f"Expected `torque` to return 3 numbers (body axes), got {value!r}."
        ) from error
    if array.shape != (3,):
        raise PolhodeError(f"Expected `torque` to return shape (3,), got shape {array.shape}.")
    return array


class Torque:
    """Base class of the torque models; models add with ``+``."""

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        """The plain-data form the Rust core reads; ``axes`` are the principal axes (columns,
        in body coordinates) the integration runs in."""
        raise NotImplementedError

    def _gravity(self) -> Gravity | None:
        return None

    def __add__(self, other: object) -> Torque:
        if isinstance(other, Torque):
            return Sum([self, other])
        return NotImplemented


class BodyFixed(Torque):
    """A constant torque in body axes (e.g. a thruster fixed to the body)."""

    def __init__(self, torque: Any) -> None:
        self.torque = as_array("torque", torque, (3,))

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        return ("body", tuple(axes.T @ self.torque))

    def __repr__(self) -> str:
        return f"BodyFixed({self.torque.tolist()})"


class SpaceFixed(Torque):
    """A constant torque in space axes."""

    def __init__(self, torque: Any) -> None:
        self.torque = as_array("torque", torque, (3,))

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        return ("space", tuple(self.torque))

    def __repr__(self) -> str:
        return f"SpaceFixed({self.torque.tolist()})"


class Gravity(Torque):
    """Uniform gravity on a body hinged at a fixed pivot: the heavy top.

    The torque about the pivot is ``r_cm x m g`` with ``r_cm`` the centre of mass seen from the
    pivot. With a :class:`polhode.Body`, :func:`polhode.simulate` integrates with the body's
    inertia about ``pivot`` (body coordinates) and takes the mass and centre of mass from the
    body. With principal moments instead of a Body, the moments must already be about the pivot
    and ``mass`` and ``center_of_mass`` (from the pivot, in those principal axes) are required.

    Parameters
    ----------
    gravity : (3,) array_like
        The gravitational acceleration in space axes (default (0, 0, -9.81)).
    pivot : (3,) array_like, optional
        The pivot in body coordinates (with a Body; default its origin).
    mass, center_of_mass : optional
        Only with principal moments instead of a Body.
    """

    def __init__(
        self,
        gravity: Any = (0.0, 0.0, -9.81),
        *,
        pivot: Any = None,
        mass: float | None = None,
        center_of_mass: Any = None,
    ) -> None:
        self.gravity = _finite("gravity", as_array("gravity", gravity, (3,)))
        self.pivot = None if pivot is None else _finite("pivot", as_array("pivot", pivot, (3,)))
        self.mass = None if mass is None else as_scalar("mass", mass)
        self.center_of_mass = (
            None if center_of_mass is None else as_array("center_of_mass", center_of_mass, (3,))
        )
        self._resolved: tuple[float, NDArray[np.float64]] | None = None

    def _gravity(self) -> Gravity | None:
        return self

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        if self._resolved is not None:
            mass, r_body = self._resolved
            return ("pivot_gravity", mass, tuple(axes.T @ r_body), tuple(self.gravity))
        if self.mass is None or self.center_of_mass is None:
            from polhode._core import PolhodeError

            raise PolhodeError(
                "Expected `mass` and `center_of_mass` in Gravity(...) when the body is given by "
                "its principal moments (or pass a polhode.Body)."
            )
        return ("pivot_gravity", self.mass, tuple(self.center_of_mass), tuple(self.gravity))

    def __repr__(self) -> str:
        return f"Gravity({self.gravity.tolist()}, pivot={self.pivot})"


class GravityGradient(Torque):
    """Gravity-gradient torque on a satellite in a circular orbit: ``3 n^2 r x (I r)``.

    ``r`` is the unit radial direction in body axes; in space it turns about ``orbit_normal`` at
    the mean motion ``n = sqrt(mu / a^3)``, starting from ``radial0`` at t = 0.
    """

    def __init__(
        self,
        mean_motion: float,
        orbit_normal: Any = (0.0, 0.0, 1.0),
        radial0: Any = (1.0, 0.0, 0.0),
    ) -> None:
        self.mean_motion = as_scalar("mean_motion", mean_motion)
        self.orbit_normal = as_array("orbit_normal", orbit_normal, (3,))
        self.radial0 = as_array("radial0", radial0, (3,))

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        return (
            "gravity_gradient",
            self.mean_motion,
            tuple(self.orbit_normal),
            tuple(self.radial0),
        )


class Window(Torque):
    """``torque`` acting only for ``start <= t < end``; the integrators step to both ends."""

    def __init__(self, torque: Any, start: float, end: float) -> None:
        self.torque = as_torque(torque)
        self.start = as_scalar("start", start)
        self.end = as_scalar("end", end)

    def _gravity(self) -> Gravity | None:
        return self.torque._gravity()

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        return ("window", self.start, self.end, self.torque._spec(axes))


class Sum(Torque):
    """The sum of several torques."""

    def __init__(self, terms: Sequence[Any]) -> None:
        self.terms = [as_torque(t) for t in terms]

    def _gravity(self) -> Gravity | None:
        found = [g for g in (t._gravity() for t in self.terms) if g is not None]
        return found[0] if found else None

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        return ("sum", [t._spec(axes) for t in self.terms])


class Function(Torque):
    """A Python callable ``torque(t, omega, quaternion) -> (3,)`` in body axes (slow path).

    Declare ``depends_on_attitude=False`` or ``depends_on_omega=False`` when true (a wrong
    declaration gives wrong results) and the times at which it jumps (``discontinuities``), so
    that no step straddles a jump. For a smooth torque that acts only on an interval, prefer
    ``Window(Function(smooth), start, end)`` to a function that switches itself: the window is
    decided once per segment while the smooth part is evaluated at every stage, which keeps
    the order-4 and order-6 splittings at their full order (a self-switching function costs
    them about three orders).
    """

    def __init__(
        self,
        function: Callable[..., Any],
        *,
        depends_on_attitude: bool = True,
        depends_on_omega: bool = True,
        discontinuities: Sequence[float] = (),
    ) -> None:
        if not callable(function):
            raise TypeError(f"Expected `torque` to be callable, got {type(function).__name__}.")
        self.function = function
        self.depends_on_attitude = bool(depends_on_attitude)
        self.depends_on_omega = bool(depends_on_omega)
        self.discontinuities = [as_scalar("discontinuities", t) for t in discontinuities]

    def _spec(self, axes: NDArray[np.float64]) -> tuple[Any, ...]:
        function = self.function
        if np.array_equal(axes, np.eye(3)):

            def in_principal(t: float, omega: Any, quaternion: Any) -> Any:
                return _torque_value(function(t, np.asarray(omega), np.asarray(quaternion)))
        else:
            from scipy.spatial.transform import Rotation

            to_body = Rotation.from_matrix(axes).inv()

            def in_principal(t: float, omega: Any, quaternion: Any) -> Any:
                # Principal to body: omega_b = V omega_p, R_b = R_p V^T, torque_p = V^T torque_b.
                q_body = (Rotation.from_quat(quaternion) * to_body).as_quat()
                torque = _torque_value(function(t, axes @ np.asarray(omega), q_body))
                return axes.T @ torque

        return (
            "callable",
            in_principal,
            self.depends_on_attitude,
            self.depends_on_omega,
            self.discontinuities,
        )


def as_torque(torque: Any) -> Torque:
    """A torque model from a model or a plain callable."""
    if isinstance(torque, Torque):
        return torque
    if callable(torque):
        return Function(torque)
    raise TypeError(
        "Expected `torque` to be a polhode.torque model or a callable, "
        f"got {type(torque).__name__}."
    )
