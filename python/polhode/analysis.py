"""Understanding a torque-free motion: regime, periods, precession and axis stability."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core
from polhode._coerce import as_float_array as _as_float_array
from polhode.bodies import Body
from polhode.errors import ArgumentError, ShapeError
from polhode.principal_axes import principal
from polhode.simulation import _body as _simulation_body

__all__ = ["Analysis", "analyze"]


@dataclass(frozen=True)
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
        |L|.
    regime : str
        ``"rest"``; ``"spherical"``; ``"symmetric"`` (two equal moments);
        ``"about_smallest_axis"`` or ``"about_largest_axis"`` (L circulates in the body about
        the axis of the smallest or largest moment: L^2 < 2 T I2 or L^2 > 2 T I2);
        ``"separatrix"`` (L^2 = 2 T I2: one flip,
        taking forever); ``"steady_intermediate"`` (rotation about the intermediate axis,
        unstable).
    period : float or None
        Period of the angular velocity in the body, 4 K(m) / lambda (2 pi / |Omega| for a
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


#: The regime of a motion about the axis of the smallest or the largest moment, by axis index.
_ABOUT = {0: "about_smallest_axis", 2: "about_largest_axis"}


def _principal_frame(body: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The principal moments (as given, or ascending) and axes (columns, body coordinates)
    of one body: a Body, principal moments (3,) or an inertia tensor (3, 3)."""
    if isinstance(body, Body):
        p = body.principal()
        return p.moments, p.axes
    array = _as_float_array("body", body)
    if array.shape == (3,):
        return array, np.eye(3)
    if array.shape == (3, 3):
        p = principal(array)
        return p.moments, p.axes
    raise ShapeError(
        "Expected `body` to be one body (a Body, principal moments (3,) or an inertia tensor "
        f"(3, 3)), got shape {array.shape}.",
        argument="body",
    )


def analyze(body: Any, omega0: Any, rtol: float | None = None) -> Analysis:
    """Regime, period, flip interval, precession, nutation and axis stability of a torque-free
    motion.

    ``body`` as in :func:`polhode.simulate` (a single body); ``omega0`` in body axes. Moments
    within ``rtol`` (the principal-axes tolerance) count as equal.
    """
    omega_body = _as_float_array("omega0", omega0)
    if omega_body.shape != (3,):
        raise ShapeError(
            f"Expected `omega0` to have shape (3,) (analyze takes one body; polhode.dask.analyze "
            f"takes N), got {omega_body.shape}.",
            argument="omega0",
        )
    # The same checks as simulate (positive moments, finite omega0 and energy), in the core.
    _core.simulate(_simulation_body(body), omega_body, np.zeros(1), method="exact",
                   orientation=False)
    moments, axes = _principal_frame(body)
    order = np.argsort(moments, kind="stable")
    moments = moments[order]
    omega = (omega_body @ axes)[order]
    info = _core.free_rotation(tuple(moments), tuple(omega))
    regime = info["regime"]
    if regime == "about_axis":
        regime = _ABOUT[info["axis"]]
    period = info["period"]
    flip = period / 2 if regime in _ABOUT.values() and period is not None else None
    nutation = info["nutation_angle"]
    precession = None
    scale = float(np.max(moments))
    tolerance = (8 * np.finfo(float).eps if rtol is None else rtol) * scale
    equal = [abs(moments[1] - moments[0]) <= tolerance, abs(moments[2] - moments[1]) <= tolerance]
    if regime == "symmetric" or (equal[0] != equal[1]):
        s = 2 if equal[0] else 0  # the symmetry axis: the distinct moment
        t = 1
        precession = float(omega[s] * (moments[s] - moments[t]) / moments[t])
    if equal[0] and equal[1]:
        stability: tuple[str, str, str] = ("neutral", "neutral", "neutral")
    elif equal[0]:
        stability = ("neutral", "neutral", "stable")
    elif equal[1]:
        stability = ("stable", "neutral", "neutral")
    else:
        stability = ("stable", "unstable", "stable")
    k = int(np.argmax(np.abs(omega)))
    a, b = [j for j in range(3) if j != k]
    w = float(omega[k])
    # Omega_a Omega_b = w^2 (I - Ib)(I - Ia) / (Ia Ib): its sign from the differences, its root
    # as |w| sqrt|I - Ib| / sqrt(Ia) * sqrt|I - Ia| / sqrt(Ib), which overflows only when the
    # rate itself is beyond double precision (a product of the two would overflow far sooner).
    ik, ia, ib = (float(moments[j]) for j in (k, a, b))
    sign = np.sign(ik - ib) * np.sign(ik - ia)
    rate = (
        abs(w)
        * (math.sqrt(abs(ik - ib)) / math.sqrt(ia))
        * (math.sqrt(abs(ik - ia)) / math.sqrt(ib))
    )
    if not math.isfinite(rate):
        raise ArgumentError(
            "The linearised rate near the axis of omega0 is beyond double precision for these "
            f"moments {moments.tolist()} and omega0.",
            argument="body",
        )
    linearized = {
        "axis": k,
        "kind": "oscillation" if sign >= 0 else "growth",
        "rate": rate,
    }
    return Analysis(
        moments=moments,
        omega=omega,
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
    )
