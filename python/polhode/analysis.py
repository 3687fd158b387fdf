"""Understanding a torque-free motion: regime, periods, precession and axis stability."""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display
from polhode._coerce import as_float_array as _as_float_array
from polhode._coerce import as_scalar
from polhode._inputs import EYE as _EYE
from polhode._inputs import core_body as _simulation_body
from polhode._inputs import principal_frame as _principal_frame
from polhode.errors import ArgumentError, ShapeError
from polhode.rotors import SphericalDamper, as_rotors, nutation_rate

__all__ = ["Analysis", "analyze"]


@dataclass(frozen=True, repr=False)
class Analysis:
    """What can be said of a torque-free motion without integrating it.

    Attributes
    ----------
    moments : (3,) numpy.ndarray
        Principal moments, ascending (I1 <= I2 <= I3).
    omega : (3,) numpy.ndarray
        The initial angular velocity in those principal axes.
    energy : float
        Kinetic energy T.
    angular_momentum_norm : float
        ``|L|``.
    regime : str
        ``"rest"``; ``"spherical"``; ``"symmetric"`` (two equal moments);
        ``"about_smallest_axis"`` or ``"about_largest_axis"`` (L circulates in the body about
        the axis of the smallest or largest moment: L^2 < 2 T I2 or L^2 > 2 T I2);
        ``"separatrix"`` (L^2 = 2 T I2: one flip,
        taking forever); ``"steady_intermediate"`` (rotation about the intermediate axis,
        unstable).
    period : float or None
        Period of the angular velocity in the body, 4 K(m) / lambda (2 pi / ``|Omega|`` for a
        symmetric top); None when the motion is not periodic.
    flip_interval : float or None
        Time between successive sign changes of the intermediate component (the tennis-racket
        flips): half the period. None for symmetric, steady or separatrix motion.
    precession_rate_body : float or None
        For a symmetric top, the rate at which omega (and L) precess about the symmetry axis
        in the body, ``Omega = w_s (I_s - I_t) / I_t``; None otherwise.
    precession_rate_space : float or None
        The mean rate (positive, about +L) at which the body precesses about L in space: the
        mean rate of the azimuth about L of the axis the motion circulates about (the symmetry
        axis, or the axis of the smallest or largest moment as ``regime`` says). ``|L| / I_t``
        for a symmetric top (I_t the transverse moment); for three distinct moments the
        exact solution's mean over one period of omega, through the complete elliptic integral
        of the third kind; for a steady rotation about the axis of the smallest or largest
        moment the limit of the motions about it. None at rest, on the separatrix and in
        steady rotation about the intermediate axis.
    nutation_angle : (float, float) or None
        The range (min, max) of the angle between L and that same axis (taken along its
        principal direction: above pi/2 when L is nearer its negative end). A symmetric top
        nutates at a constant angle, ``arccos(I_s w_s / |L|)`` (min == max); three distinct
        moments swing between the two. None when ``precession_rate_space`` is, and for a
        sphere.
    axis_stability : tuple of str
        For each principal axis, ``"stable"`` (smallest or largest moment), ``"unstable"``
        (intermediate) or ``"neutral"`` (a moment shared with another axis).
    linearized : dict
        Rotation near the axis closest to omega: ``axis`` (0, 1, 2), ``kind``
        (``"oscillation"`` or ``"growth"``) and ``rate``: with the axis a rotation rate w and
        the other two moments Ia, Ib, Omega_a = w (I - Ib)/Ia and Omega_b = w (I - Ia)/Ib;
        oscillation at sqrt(Omega_a Omega_b) when they share a sign, exponential growth at
        sqrt(-Omega_a Omega_b) otherwise.
    nutation_rate : float or None
        With ``rotors=[damper]`` (one :class:`polhode.rotors.SphericalDamper`), the damper's
        linearised rate: :func:`polhode.rotors.nutation_rate`, a small nutation about the spin
        axis growing or decaying as ``exp(nutation_rate * t)`` (< 0 about the axis of the
        largest moment, > 0 about the smallest: the energy sink), in closed form for a body
        symmetric about the spin axis. None without rotors, and with wheels or several dampers
        (no closed form or linearisation is given for them).
    nutation_time_constant : float or None
        ``1 / |nutation_rate|``, the e-folding time of the nutation: the damper's time
        constant ``-1 / nutation_rate`` when the spin is damped (``nutation_rate < 0``: the
        nutation, and ``2 T I3 - |L|^2``, fall by e every ``nutation_time_constant`` and
        ``nutation_time_constant / 2``), the growth time ``1 / nutation_rate`` when it grows
        (the spin about the smallest axis). None when ``nutation_rate`` is None or 0 (no
        damping or no spin: nothing grows or decays).

    Examples
    --------
    >>> import polhode as ph
    >>> ph.analyze([1.0, 2.0, 3.0], [0.01, 1.0, 0.01])
    Analysis(regime='about_largest_axis', moments=[1, 2, 3], omega=[0.01, 1, 0.01],
             energy=1.0002, angular_momentum_norm=2.00025, period=39.1057,
             flip_interval=19.5529, precession_rate_body=None,
             precession_rate_space=1.10722, nutation_angle=(0.523555, 1.55855),
             axis_stability=('stable', 'unstable', 'stable'),
             linearized={axis=1, kind='growth', rate=0.57735})
    """

    moments: NDArray[np.float64]
    omega: NDArray[np.float64]
    energy: float
    angular_momentum_norm: float
    regime: str
    period: float | None
    flip_interval: float | None
    precession_rate_body: float | None
    precession_rate_space: float | None
    nutation_angle: tuple[float, float] | None
    axis_stability: tuple[str, str, str]
    linearized: dict[str, Any] = field(default_factory=dict)
    nutation_rate: float | None = None
    nutation_time_constant: float | None = None

    def _summary(self) -> list[tuple[str, str]]:
        linearized = ", ".join(
            f"{k}={v!r}" if isinstance(v, str) else f"{k}={_display.number(v)}"
            for k, v in self.linearized.items()
        )
        return [
            ("regime", repr(self.regime)),
            ("moments", _display.vector(self.moments)),
            ("omega", _display.vector(self.omega)),
            ("energy", _display.number(self.energy)),
            ("angular_momentum_norm", _display.number(self.angular_momentum_norm)),
            ("period", _display.number(self.period)),
            ("flip_interval", _display.number(self.flip_interval)),
            ("precession_rate_body", _display.number(self.precession_rate_body)),
            ("precession_rate_space", _display.number(self.precession_rate_space)),
            (
                "nutation_angle",
                "None"
                if self.nutation_angle is None
                else "(" + ", ".join(_display.number(a) for a in self.nutation_angle) + ")",
            ),
            ("axis_stability", repr(tuple(self.axis_stability))),
            ("linearized", "{" + linearized + "}"),
        ] + [
            (name, _display.number(getattr(self, name)))
            for name in ("nutation_rate", "nutation_time_constant")
            if getattr(self, name) is not None  # shown with a damper only
        ]

    def __repr__(self) -> str:
        return "Analysis(" + ", ".join(f"{k}={v}" for k, v in self._summary()) + ")"

    def _repr_html_(self) -> str:
        return _display.html_table("Analysis", self._summary())


def _rate(what: str, value: Fraction | float) -> float:
    """A rate of the analysis as a double, or an ArgumentError naming ``body`` when it lies
    beyond the largest double (moments spanning more than the range of doubles)."""
    try:
        result = float(value)
    except OverflowError:
        result = math.inf
    if not math.isfinite(result):
        raise ArgumentError(
            f"Invalid `body`: {what} of this motion overflows double precision (the moments "
            "span more than the range of doubles).",
            argument="body",
        )
    return result


#: The regime of a motion about the axis of the smallest or the largest moment, by axis index.
_ABOUT = {0: "about_smallest_axis", 2: "about_largest_axis"}


#: The two other axes of each axis.
_OTHERS = ((1, 2), (0, 2), (0, 1))


def _order3(m: list[float]) -> tuple[int, int, int]:
    """The indices that sort three numbers ascending, equal ones in their order (what
    ``numpy.argsort(m, kind="stable")`` gives), by comparisons: a small call."""
    a, b, c = m
    if a <= b:
        if b <= c:
            return (0, 1, 2)
        return (0, 2, 1) if a <= c else (2, 0, 1)
    if a <= c:
        return (1, 0, 2)
    return (1, 2, 0) if b <= c else (2, 1, 0)


def analyze(
    body: Any, omega0: Any, rtol: float | None = None, *, rotors: Any = None
) -> Analysis:
    """Regime, period, flip interval, precession, nutation and axis stability of a torque-free
    motion; with a damper, its nutation rate and time constant.

    ``body`` as in :func:`polhode.simulate` (a single body); ``omega0`` in body axes.

    Two moments are equal when they are equal numbers: as given, or as returned by the
    principal-axes solve of a Body or a tensor (which merges moments within its tolerance).
    ``rtol`` (finite, >= 0) merges more: the tolerance of that solve, and for principal moments
    given as numbers, gaps up to ``rtol`` times the largest moment (the moments are then
    replaced by their mean, in the result and in the analysis). The regime, the period, the
    precession and the axis stability all describe the same moments.

    ``rotors`` as in :func:`polhode.simulate` (the body's inertia includes them, locked, and
    they must fit inside it). The free-body entries describe that locked body at ``t0``; with
    one :class:`polhode.rotors.SphericalDamper` the analysis adds its ``nutation_rate`` and
    ``nutation_time_constant`` (the energy sink's time constant), None otherwise.

    Returns
    -------
    Analysis

    Examples
    --------
    Spun about the intermediate axis of I = (1, 2, 3), the body flips; the perturbation grows
    at the rate sqrt(1/3) = 0.57735 (Omega_a = (I2 - I3)/I1 = -1, Omega_b = (I2 - I1)/I3 = 1/3):

    >>> import polhode as ph
    >>> a = ph.analyze([1.0, 2.0, 3.0], [0.01, 1.0, 0.01])
    >>> a.regime, a.axis_stability
    ('about_largest_axis', ('stable', 'unstable', 'stable'))
    >>> round(a.flip_interval, 4), a.linearized["kind"], round(a.linearized["rate"], 5)
    (19.5529, 'growth', 0.57735)

    A symmetric top precesses at Omega = w_s (I_s - I_t) / I_t:

    >>> top = ph.analyze([1.0, 1.0, 2.0], [0.1, 0.0, 1.0])
    >>> top.regime, top.precession_rate_body
    ('symmetric', 1.0)

    A spherical damper settles a spin about the largest axis with the time constant
    ``-1 / nutation_rate``, and tips one about the smallest axis over (growth time
    ``1 / nutation_rate``):

    >>> damper = ph.rotors.SphericalDamper(0.2, 0.1)
    >>> settles = ph.analyze([1.0, 4.0, 5.0], [0.01, 0.01, 2.0], rotors=[damper])
    >>> round(settles.nutation_rate, 5), round(settles.nutation_time_constant, 3)
    (-0.04163, 24.024)
    >>> tips = ph.analyze([1.0, 4.0, 5.0], [2.0, 0.01, 0.01], rotors=[damper])
    >>> round(tips.nutation_rate, 5), round(tips.nutation_time_constant, 3)
    (0.03314, 30.179)
    """
    if rtol is not None:
        rtol = as_scalar("rtol", rtol)
        if not (np.isfinite(rtol) and rtol >= 0):
            raise ArgumentError(
                f"Expected `rtol` to be finite and >= 0, got {rtol!r}.", argument="rtol"
            )
    omega_body = _as_float_array("omega0", omega0)
    if omega_body.shape != (3,):
        raise ShapeError(
            f"Expected `omega0` to have shape (3,) (analyze takes one body; polhode.dask.analyze "
            f"takes N), got {omega_body.shape}.",
            argument="omega0",
        )
    rotors = () if rotors is None else as_rotors(rotors)
    # The same checks as simulate (body, positive moments, finite omega0 and energy; the rotors
    # inside the body), in the core, and nothing else (free_rotation below builds the closed
    # form, with its own checks).
    coerced = _simulation_body(body)
    _core.check_motion(coerced, omega_body, rotors=list(rotors) if rotors else None)
    moments, axes = _principal_frame(body, rtol, coerced)
    # Ascending moments (a stable sort, as numpy's); Python floats from here on: a small call.
    m = moments.tolist()
    order = _order3(m)
    # omega in the principal axes: with the identity (moments given as numbers), what the
    # product would give (+ 0.0: its zeros are +0) without its cost.
    w3 = (
        [x + 0.0 for x in omega_body.tolist()] if axes is _EYE else (omega_body @ axes).tolist()
    )
    mom = [m[i] for i in order]
    omega = [w3[i] for i in order]
    info = _core.free_rotation(mom, omega)
    regime = info["regime"]
    if regime == "about_axis":
        regime = _ABOUT[info["axis"]]
    period = info["period"]
    flip = period / 2 if regime in _ABOUT.values() and period is not None else None
    nutation = info["nutation_angle"]
    precession = None
    # Equal as the core's regime sees them (exactly): the merging is done above.
    equal = [mom[1] == mom[0], mom[2] == mom[1]]
    if equal[0] != equal[1]:
        s = 2 if equal[0] else 0  # the symmetry axis: the distinct moment
        t = 1
        precession = _rate(
            "the precession rate w_s (I_s - I_t) / I_t",
            Fraction(omega[s]) * (Fraction(mom[s]) - Fraction(mom[t])) / Fraction(mom[t]),
        )
    if equal[0] and equal[1]:
        stability: tuple[str, str, str] = ("neutral", "neutral", "neutral")
    elif equal[0]:
        stability = ("neutral", "neutral", "stable")
    elif equal[1]:
        stability = ("stable", "neutral", "neutral")
    else:
        stability = ("stable", "unstable", "stable")
    # The axis of the largest |omega|, the first of equal ones (as numpy's argmax).
    s0, s1, s2 = abs(omega[0]), abs(omega[1]), abs(omega[2])
    k = 0 if s0 >= s1 and s0 >= s2 else 1 if s1 >= s2 else 2
    a, b = _OTHERS[k]
    w = omega[k]
    ma, mb, mk = mom[a], mom[b], mom[k]
    # Omega_a Omega_b = w^2 (I_k - I_b) (I_k - I_a) / (I_a I_b), and the rate its square root:
    # in doubles when the product is a normal number (moments within 1e308 of each other, w
    # not below 1e-154), else from the two square roots apart (a product of 1e-400 was 0,
    # "growth at rate 0"); a rate beyond the largest double is an error, not inf. (Python
    # floats overflow to inf, and inf * 0 is nan, without raising.)
    product = (w * (mk - mb) / ma) * (w * (mk - ma) / mb)
    if math.isfinite(product) and abs(product) >= sys.float_info.min:
        rate = math.sqrt(abs(product))
    else:
        rate = abs(w) * (math.sqrt(abs(mk - mb)) / math.sqrt(ma)) * (
            math.sqrt(abs(mk - ma)) / math.sqrt(mb)
        )
    rate = _rate("the linearized rate sqrt(|Omega_a Omega_b|)", rate)
    growth = w != 0.0 and (mk - mb < 0.0 < mk - ma or mk - ma < 0.0 < mk - mb)
    linearized = {
        "axis": k,
        "kind": "growth" if growth else "oscillation",
        "rate": rate,
    }
    damper_rate: float | None = None
    if len(rotors) == 1 and isinstance(rotors[0], SphericalDamper):
        damper_rate = nutation_rate(mom, omega, rotors[0])
    # The fields set in one step (a frozen dataclass's __init__ sets each through
    # object.__setattr__): the same object as Analysis(...) with these fields, in their order.
    analysis = object.__new__(Analysis)
    analysis.__dict__.update(
        moments=np.array(mom),
        omega=np.array(omega),
        energy=float(info["energy"]),
        angular_momentum_norm=float(info["angular_momentum_norm"]),
        regime=regime,
        period=period,
        flip_interval=flip,
        precession_rate_body=precession,
        precession_rate_space=info["precession_rate_space"],
        nutation_angle=None if nutation is None else (float(nutation[0]), float(nutation[1])),
        axis_stability=stability,
        linearized=linearized,
        nutation_rate=damper_rate,
        nutation_time_constant=None if not damper_rate else 1.0 / abs(damper_rate),
    )
    return analysis
