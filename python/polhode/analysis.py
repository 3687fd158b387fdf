"""Understanding a torque-free motion: regime, periods, precession and axis stability."""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field, fields
from fractions import Fraction
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display
from polhode._coerce import as_float_array as _as_float_array
from polhode._coerce import as_scalar
from polhode._equality import fields_equal
from polhode._inputs import EYE as _EYE
from polhode._inputs import core_body as _simulation_body
from polhode._inputs import principal_frame as _principal_frame
from polhode.errors import ArgumentError, ShapeError
from polhode.rotors import SphericalDamper, as_rotors, nutation_rate

__all__ = ["Analysis", "analyze"]


@dataclass(frozen=True, repr=False, eq=False)
class Analysis:
    """What can be said of a torque-free motion without integrating it.

    Two analyses are equal (``==``) when every field is, arrays exactly (NaN equal to NaN in
    the same place): an analysis equals its copies and a repeated run's; it is not hashable.

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
        Where the body turns over (``turns_over``), the time between two turnovers (the
        tennis-racket flips): half the period, the time between successive reversals of L's
        component along the intermediate axis. None for every other motion: a stable spin (its
        intermediate component also changes sign every half period, but as a wobble about the
        axis it circulates about: nothing turns over), a symmetric top, a steady rotation, the
        separatrix (one flip, taking forever).
    turns_over : bool
        Whether the body turns over: L circulates about the axis of the smallest or the largest
        moment, but spends more than half of each period within 45 degrees of one end or the
        other of the intermediate axis, so that the body spins mostly about that axis, one way
        and then the other (the tennis-racket flip). In closed form, with ``L_2 = A sn(u | m)``
        along the motion: ``A^2 / |L|^2 > (1 + sqrt(1 - m)) / 2``, since ``sn(K/2) =
        1 / sqrt(1 + sqrt(1 - m))``. A spin near the circulation axis, or a nearly symmetric
        body's wobble (m near 0: the transverse part of L turns evenly), does not; a motion
        near the separatrix (m near 1) does.
    spin_axis : int or None
        The principal axis (0, 1, 2: I1, I2, I3) the body was spun about: the largest component
        of omega in principal axes (the first of equal ones); None at rest.
    description : str
        The motion in one sentence, axes numbered 1, 2, 3 as I1 <= I2 <= I3: which axis it was
        spun about, which L circulates about, and whether it turns over (and how often) or
        nutates (and by how much).
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
        moments swing between the two. None when ``precession_rate_space`` is, for a sphere,
        and where the body turns over (``turns_over``: the axis then tumbles, it does not
        nutate).
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
    >>> a = ph.analyze([1.0, 2.0, 3.0], [0.01, 1.0, 0.01])
    >>> a
    Analysis(regime='about_largest_axis', moments=[1, 2, 3], omega=[0.01, 1, 0.01],
             energy=1.0002, angular_momentum_norm=2.00025, period=39.1057,
             flip_interval=19.5529, turns_over=True, spin_axis=1,
             precession_rate_body=None, precession_rate_space=1.10722, nutation_angle=None,
             axis_stability=('stable', 'unstable', 'stable'),
             linearized={axis=1, kind='growth', rate=0.57735})
    >>> import textwrap
    >>> print(textwrap.fill(a.description, 90))
    Spun about axis 2 (I2, the intermediate moment: unstable); L circulates about axis 3 (I3,
    the largest moment) and the body turns over every 19.55 s (the tennis-racket flip).
    """

    moments: NDArray[np.float64]
    omega: NDArray[np.float64]
    energy: float
    angular_momentum_norm: float
    regime: str
    period: float | None
    flip_interval: float | None
    turns_over: bool
    spin_axis: int | None
    precession_rate_body: float | None
    precession_rate_space: float | None
    nutation_angle: tuple[float, float] | None
    axis_stability: tuple[str, str, str]
    linearized: dict[str, Any] = field(default_factory=dict)
    nutation_rate: float | None = None
    nutation_time_constant: float | None = None
    description: str = ""

    def __eq__(self, other: object) -> Any:
        return fields_equal(self, other, tuple(f.name for f in fields(self)))

    __hash__ = None  # type: ignore[assignment]  # arrays: equal by value, so not hashable

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
            ("turns_over", repr(self.turns_over)),
            ("spin_axis", repr(self.spin_axis)),
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

#: Each principal axis, as a person reads it (numbered 1, 2, 3 as I1 <= I2 <= I3).
_AXIS_WORDS = (
    "axis 1 (I1, the smallest moment",
    "axis 2 (I2, the intermediate moment",
    "axis 3 (I3, the largest moment",
)


def _turns_over(regime: str, mom: list[float], energy: float, norm: float) -> bool:
    """Whether L, circulating about the axis of the smallest or largest moment, spends more
    than half of each period within 45 degrees of the intermediate axis (see
    Analysis.turns_over): ``A^2 / |L|^2 > (1 + sqrt(1 - m)) / 2`` with ``A^2`` the largest
    ``L_2^2`` and ``m`` the motion's elliptic parameter."""
    if regime not in _ABOUT.values() or not energy > 0.0:
        return False
    i1, i2, i3 = mom
    d = (norm / (2.0 * energy)) * norm  # |L|^2 / 2T, between I1 and I3
    # Products of ratios, never of two moments: those overflowed for moments of 1e200
    # (turns_over False) and underflowed for 1e-200, or [1, 1e161, 2] (a ZeroDivisionError).
    if regime == "about_largest_axis":  # L_2 = A sn, L_1 = .. cn, L_3 = .. dn
        reach = (i2 / d) * ((i3 - d) / (i3 - i2))
        m = ((i2 - i1) / (i3 - i2)) * ((i3 - d) / (d - i1))
    else:
        reach = (i2 / d) * ((d - i1) / (i2 - i1))
        m = ((i3 - i2) / (i2 - i1)) * ((d - i1) / (i3 - d))
    # |sn u| >= s0 for more than half of [0, K] iff s0 < sn(K/2) = 1 / sqrt(1 + sqrt(1 - m)).
    return 2.0 * reach - 1.0 > math.sqrt(max(0.0, 1.0 - m))


def _describe(
    regime: str,
    spin: int | None,
    stability: tuple[str, str, str],
    flip: float | None,
    nutation: tuple[float, float] | None,
    symmetry_axis: int | None,
) -> str:
    """The motion in one sentence (see Analysis.description)."""
    if regime == "rest" or spin is None:
        return "At rest."
    if regime == "spherical":
        return "A spherical body (I1 = I2 = I3): omega stays fixed, in the body and in space."
    spun = f"Spun about {_AXIS_WORDS[spin]}: {stability[spin]})"
    if regime == "symmetric":
        axis = _AXIS_WORDS[symmetry_axis if symmetry_axis is not None else 2].split(" (")[0]
        return (
            f"{spun}; a symmetric top: omega and L precess about its symmetry {axis} at a "
            "constant angle."
        )
    if regime == "steady_intermediate":
        return (
            f"{spun}, exactly: a steady rotation that the slightest nudge turns into a "
            "tumble (the tennis-racket flip)."
        )
    if regime == "separatrix":
        return (
            f"{spun}; on the separatrix (|L|^2 = 2 T I2): the body turns over once, taking "
            "forever."
        )
    about = 2 if regime == "about_largest_axis" else 0
    circulates = (
        "L circulates about it" if about == spin else f"L circulates about {_AXIS_WORDS[about]})"
    )
    if flip is not None:
        return (
            f"{spun}; {circulates} and the body turns over every {flip:.4g} s (the "
            "tennis-racket flip)."
        )
    text = f"{spun}; {circulates}: a stable spin"
    if nutation is not None:
        lo, hi = (math.degrees(x) for x in nutation)
        span = f"{lo:.3g} deg" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g} to {hi:.3g} deg"
        text += f", axis {about + 1} {span} from L"
    return text + "."


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
    energy = float(info["energy"])
    norm = float(info["angular_momentum_norm"])
    turns_over = period is not None and _turns_over(regime, mom, energy, norm)
    flip = period / 2 if turns_over else None
    nutation = None if turns_over else info["nutation_angle"]
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
    spin = None if regime == "rest" else k
    angles = None if nutation is None else (float(nutation[0]), float(nutation[1]))
    symmetry_axis = None if equal[0] == equal[1] else (2 if equal[0] else 0)
    description = _describe(regime, spin, stability, flip, angles, symmetry_axis)
    # The fields set in one step (a frozen dataclass's __init__ sets each through
    # object.__setattr__): the same object as Analysis(...) with these fields, in their order.
    analysis = object.__new__(Analysis)
    analysis.__dict__.update(
        moments=np.array(mom),
        omega=np.array(omega),
        energy=energy,
        angular_momentum_norm=norm,
        regime=regime,
        period=period,
        flip_interval=flip,
        turns_over=turns_over,
        spin_axis=spin,
        precession_rate_body=precession,
        precession_rate_space=info["precession_rate_space"],
        nutation_angle=angles,
        axis_stability=stability,
        linearized=linearized,
        nutation_rate=damper_rate,
        nutation_time_constant=None if not damper_rate else 1.0 / abs(damper_rate),
        description=description,
    )
    return analysis
