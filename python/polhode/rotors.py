"""Internal rotors for :func:`polhode.simulate`: reaction wheels and spherical (Kane) dampers.

``polhode.simulate(body, omega0, t, rotors=[...])`` integrates the body with its rotors in Rust
(the gyrostat equations; ``method`` ``"dop853"``, what ``"auto"`` picks, or ``"rk4"``) and
returns ``sol.rotor_rates``, each rotor's angular velocity relative to the body (body axes);
``angular_momentum_space``, ``angular_momentum_body`` and ``energy`` are then those of the whole
system, rotors included.

The body's inertia is that of the whole system with its rotors locked (it includes their mass
and all of their inertia): a rotor that never turns relative to the body changes nothing.
``I - sum J a a^T`` (wheels) ``- sum J 1`` (dampers) must stay positive definite. The equations
are written out in ``docs/rotors.md``.

Rotors are immutable values, like the torque models: a simulation reads them and never writes
on them. Their parameters are checked by the core when they are made.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from polhode import _core
from polhode._coerce import as_array, as_float_array, as_scalar, read_only_arrays
from polhode._inputs import principal_frame
from polhode.errors import NonFiniteError, PolhodeError

__all__ = ["Rotor", "SphericalDamper", "Wheel", "as_rotors", "nutation_rate"]


class Rotor:
    """Base class of the rotors. A rotor's ``kind`` (its class name) and its named fields are
    what the core reads.

    Examples
    --------
    >>> from polhode.rotors import Rotor, SphericalDamper, Wheel
    >>> issubclass(Wheel, Rotor), issubclass(SphericalDamper, Rotor)
    (True, True)
    """

    kind: ClassVar[str] = ""

    def __post_init__(self) -> None:
        _core.check_rotor(self)

    def __setstate__(self, state: dict[str, Any]) -> None:
        # Unpickled or deep-copied, a model is what its constructor made: its arrays read-only
        # again and its fields checked by the core.
        self.__dict__.update(read_only_arrays(state))
        self.__post_init__()


def _motor(torque: Any) -> float | NDArray[np.float64] | Callable[..., Any]:
    if callable(torque):
        return torque
    if isinstance(torque, bool | np.bool_):
        raise TypeError(
            "Expected a wheel's `torque` to be a number, (time, torque) pairs or a function, "
            "got bool."
        )
    if isinstance(torque, int | float | np.integer | np.floating) and not isinstance(torque, bool):
        return as_scalar("torque", torque)
    array = as_float_array("torque", torque)
    if array.ndim == 0:
        return float(array)
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)
class Wheel(Rotor):
    """A wheel spinning on a body-fixed axis (a reaction or momentum wheel, a rotor).

    Parameters
    ----------
    axis : (3,) array_like
        Its spin axis in the body's own axes (non-zero; normalised).
    inertia : float
        Its moment of inertia about that axis, J > 0.
    rate0 : float
        Its spin rate relative to the body at ``t0``, about ``axis`` (default 0).
    torque : float, (K, 2) array_like or callable
        The motor's torque on the wheel about ``axis`` (the body feels the opposite): a
        constant (default 0); a schedule of ``(time, torque)`` pairs, each torque acting from
        its time to the next (the last one onwards, zero before the first; times increasing),
        the integrators stepping to each switch; or a callable ``torque(t, omega, rate) ->
        float`` of the time, the body's angular velocity (its own axes) and the wheel's rate
        relative to the body, called from Rust at every stage (the slow path, like a torque
        function).

    Examples
    --------
    A wheel spun up from rest turns the body the other way (angular momentum stays zero):

    >>> import polhode as ph
    >>> wheel = ph.rotors.Wheel([0, 0, 1], inertia=0.1, torque=[(0.0, 0.05), (1.0, 0.0)])
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], 2.0, rotors=[wheel])
    >>> round(float(sol.rotor_rates[-1, 0, 2]), 9)  # 0.05 / 0.1 * 1 s, relative to the body
    0.517241379
    >>> round(float(sol.omega[-1, 2]), 9)  # the body: -h / (I3 - J) = -0.05 / 2.9
    -0.017241379
    """

    kind: ClassVar[str] = "Wheel"
    axis: NDArray[np.float64]
    inertia: float
    rate0: float
    torque: float | NDArray[np.float64] | Callable[..., Any]

    def __init__(self, axis: Any, inertia: float, rate0: float = 0.0, torque: Any = 0.0) -> None:
        axis = as_array("axis", axis, (3,))
        axis.flags.writeable = False
        object.__setattr__(self, "axis", axis)
        object.__setattr__(self, "inertia", as_scalar("inertia", inertia))
        object.__setattr__(self, "rate0", as_scalar("rate0", rate0))
        object.__setattr__(self, "torque", _motor(torque))
        self.__post_init__()

    def __repr__(self) -> str:
        torque = self.torque
        if isinstance(torque, np.ndarray):
            torque = torque.tolist()
        return (
            f"Wheel({self.axis.tolist()}, inertia={self.inertia}, rate0={self.rate0}, "
            f"torque={torque!r})"
        )

    def _call_torque(self, t: float, omega: Any, rate: float) -> float:
        """The torque function at (t, omega, rate), its value checked (called by the core)."""
        assert callable(self.torque)
        value = self.torque(t, np.asarray(omega), rate)
        real = isinstance(value, numbers.Real | np.integer | np.floating) or (
            isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iuf"
        )
        if isinstance(value, bool | np.bool_) or not real:
            raise TypeError(
                "Expected a wheel's `torque` function to return a real number, got "
                f"{type(value).__name__}"
                f"{f' of {value.dtype}' if isinstance(value, np.ndarray) else ''}."
            )
        try:
            return float(value)
        except OverflowError:
            # An integer beyond double precision (10**400): not finite as a torque.
            raise NonFiniteError(
                "Expected a wheel's `torque` function to return a finite number, got an integer "
                "beyond double precision.",
                argument="torque",
            ) from None


@dataclass(frozen=True, eq=False)
class SphericalDamper(Rotor):
    """A sphere of inertia J in a spherical cavity, coupled to the body by a viscous torque: the
    Kane damper, an energy sink.

    The fluid's torque on the sphere is ``-c (s - w)`` (``s`` the sphere's angular velocity,
    ``w`` the body's), the body getting ``+c (s - w)``: kinetic energy goes at ``c |s - w|^2``
    while the total angular momentum stays fixed, so the body ends spinning about its axis of
    largest moment. The sphere starts turning with the body.

    Parameters
    ----------
    inertia : float
        The sphere's moment of inertia J > 0.
    damping : float
        The viscous coefficient c >= 0 (torque per unit relative rate).

    Examples
    --------
    >>> import polhode as ph
    >>> damper = ph.rotors.SphericalDamper(inertia=0.2, damping=0.1)
    >>> sol = ph.simulate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], [0.0, 300.0], rotors=[damper])
    >>> bool(sol.energy[-1] < sol.energy[0])   # the damper drains T at fixed |L|
    True
    """

    kind: ClassVar[str] = "SphericalDamper"
    inertia: float
    damping: float

    def __init__(self, inertia: float, damping: float) -> None:
        object.__setattr__(self, "inertia", as_scalar("inertia", inertia))
        object.__setattr__(self, "damping", as_scalar("damping", damping))
        self.__post_init__()


def as_rotors(rotors: Any) -> tuple[Rotor, ...]:
    """A tuple of rotors from a rotor or a sequence of them; TypeError for anything else.

    Examples
    --------
    >>> from polhode.rotors import SphericalDamper, as_rotors
    >>> as_rotors(SphericalDamper(0.2, 0.1))
    (SphericalDamper(inertia=0.2, damping=0.1),)
    """
    if isinstance(rotors, Rotor):
        return (rotors,)
    if isinstance(rotors, str | bytes) or not isinstance(rotors, Sequence | tuple):
        raise TypeError(
            "Expected `rotors` to be a sequence of polhode.rotors rotors (Wheel, "
            f"SphericalDamper), got {type(rotors).__name__}."
        )
    for rotor in rotors:
        if not isinstance(rotor, Rotor):
            raise TypeError(
                "Expected `rotors` to hold polhode.rotors rotors (Wheel, SphericalDamper), got "
                f"{type(rotor).__name__}."
            )
    return tuple(rotors)


def _principal(body: Any, omega0: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Ascending principal moments (rotors locked) and omega0 in those axes."""
    omega = as_array("omega0", omega0, (3,))
    moments, axes = principal_frame(body, None)
    order = np.argsort(moments, kind="stable")
    return moments[order], (omega @ axes)[order]


def nutation_rate(body: Any, omega0: Any, damper: SphericalDamper) -> float:
    """The exponential rate of the nutation of a spin with a spherical damper, linearised.

    The body spins about the principal axis nearest ``omega0`` at ``w`` (``omega0``'s component
    along it), its sphere turning with it; a small nutation then grows or decays as
    ``exp(rate * t)``: ``rate < 0`` about the axis of the largest moment (the damper's time
    constant is ``-1 / rate``), ``rate > 0`` about the smallest (the energy-sink instability
    that tipped Explorer 1), the energy ``2 T I_k - |L|^2`` (``I_k`` the spin axis's moment)
    following at ``2 rate``.

    For a body symmetric about the spin axis the rate is in closed form (``docs/rotors.md``):
    with ``A_t = I_t - J``, ``A_s = I_s - J`` (the moments without the sphere's spinning
    inertia), ``l = w (A_s - A_t) / A_t``, ``k = c / J`` and ``m = c / A_t``, the rate is the
    larger real part of the two roots of ``s^2 + (i (w - l) + k + m) s + l w - i l k = 0``: for
    weak coupling (``c / J`` well below ``w I_s / I_t``) the nutation's, the root near ``i l``,
    with ``rate = -c (A_s - A_t) / (A_s A_t)``, the energy-sink estimate (Likins, JPL TR 32-860,
    1966; Hughes 1986); with a heavy sphere the sphere's own mode. Otherwise it is the largest
    real part of the eigenvalues of the motion (body and sphere) linearised about the spin, the
    modes of the steady family (zero eigenvalues) left out.

    Parameters
    ----------
    body : Body, (3,) principal moments or (3, 3) tensor
        The body with its rotors locked, as in :func:`polhode.simulate`.
    omega0 : (3,) array_like
        The angular velocity in body axes; the spin axis is its principal component of largest
        magnitude.
    damper : SphericalDamper
        The damper.

    Returns
    -------
    float
        The rate (1 / time).

    Examples
    --------
    A damper makes a spin about the smallest axis grow away from it, and one about the largest
    settle (moments with the damper locked):

    >>> from polhode.rotors import SphericalDamper, nutation_rate
    >>> damper = SphericalDamper(0.2, 0.1)
    >>> round(nutation_rate([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], damper), 5)
    0.03314
    >>> round(nutation_rate([1.0, 4.0, 5.0], [0.01, 0.01, 2.0], damper), 5)
    -0.04163
    """
    if not isinstance(damper, SphericalDamper):
        raise TypeError(
            "Expected `damper` to be a polhode.rotors.SphericalDamper, got "
            f"{type(damper).__name__}."
        )
    moments, omega = _principal(body, omega0)
    k = int(np.argmax(np.abs(omega)))
    a, b = [j for j in range(3) if j != k]
    spin, j, c = float(omega[k]), damper.inertia, damper.damping
    if not np.all(moments - j > 0):
        raise PolhodeError(
            "Expected the damper's inertia to lie inside the body's: every principal moment "
            f"above J = {j:g}, got moments {moments.tolist()}.",
            argument="damper",
        )
    if spin == 0.0 or c == 0.0:
        return 0.0
    if moments[a] == moments[b]:
        a_t, a_s = moments[a] - j, moments[k] - j
        ell = spin * (a_s - a_t) / a_t
        kappa, mu = c / j, c / a_t
        half = 0.5 * (1j * (spin - ell) + kappa + mu)
        root = np.sqrt(half * half - (ell * spin - 1j * ell * kappa))
        # The slower of the two modes: the nutation (the root near i l) under weak coupling;
        # with a heavy sphere (J above about 2 I_t - I_s) the sphere's own mode is slower, and
        # taking the nutation's gave a rate 8x too fast (the general branch, 1e-9 away, was
        # right).
        return float(max((-half + root).real, (-half - root).real))
    a_mat = np.diag(moments - j)
    w0 = np.zeros(3)
    w0[k] = spin

    def cross(v: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])

    inverse = np.diag(1.0 / (moments - j))
    jacobian = np.block(
        [
            [inverse @ (-cross(w0) @ a_mat + cross(a_mat @ w0) - c * np.eye(3)), c * inverse],
            [cross(w0) + (c / j) * np.eye(3), -cross(w0) - (c / j) * np.eye(3)],
        ]
    )
    eigenvalues = np.linalg.eigvals(jacobian)
    scale = max(abs(spin), c / j, c / float(moments.min()))
    moving = eigenvalues[np.abs(eigenvalues) > 1e-9 * scale]
    return float(np.max(moving.real))
