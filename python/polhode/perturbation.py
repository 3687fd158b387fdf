r"""Rotation near a principal axis, expanded in the size of the perturbation.

Spin about principal axis ``k`` at rate ``W`` with small components ``a``, ``b`` about the other
two axes (taken in cyclic order ``k -> i -> j``, so that Euler's equations keep their sign).
Writing :math:`\omega_i = \sum \epsilon^n u_n`, :math:`\omega_j = \sum \epsilon^n v_n` and
:math:`\omega_k = W + \sum \epsilon^n \eta_n` and collecting Euler's equations order by order
(Landau-Lifshitz par. 37):

- order 1: :math:`u_1' = -\Omega_i v_1`, :math:`v_1' = \Omega_j u_1`, :math:`\eta_1' = 0`, with
  :math:`\Omega_i = W (I_k - I_j)/I_i` and :math:`\Omega_j = W (I_k - I_i)/I_j`: an oscillation at
  :math:`\sqrt{\Omega_i \Omega_j}` when they share a sign (the axis of the largest or smallest
  moment), exponential growth at :math:`\sqrt{-\Omega_i \Omega_j}` otherwise (the intermediate
  axis: the tennis-racket flip);
- order 2: :math:`I_k \eta_2' + (I_j - I_i) u_1 v_1 = 0`, integrated in closed form; the
  corrections :math:`u_2, v_2` obey the homogeneous order-1 system with zero initial values, so
  they vanish (all of the initial condition is carried at order 1).

The order-n expansion is exact to :math:`O(\epsilon^{n+1})` at any fixed time, and valid while
the perturbation stays small: for the oscillating axes over many periods, for the intermediate
axis only until the growth :math:`e^{\lambda t}` makes it large.

Domain
------
:func:`perturbation` answers only where the expansion means something, and raises
:class:`~polhode.errors.ArgumentError` (``argument`` ``"omega0"`` or ``"t"``) elsewhere, saying
which condition fails; with ``T = max |t|`` and the bound ``EPS_MAX = 1/2``:

- a spin about the axis, ``W != 0``, and a small parameter
  ``eps = |(a, b)| / |W| <= EPS_MAX``;
- the first-order perturbation stays at most ``EPS_MAX |W|`` up to ``T``: for an oscillation,
  its largest size over a period, the square root of the largest eigenvalue of
  ``[[a^2 + b^2, b q - a p], [b q - a p, p^2 + q^2]]`` (``p = Omega_i b / w``,
  ``q = Omega_j a / w``); for growth, ``|(|a| cosh + |p| |sinh|, |b| cosh + |q| |sinh|)|``
  at ``lambda T`` (the size of the terms whose difference is the perturbation, which bounds
  both it and its rounding); for a zero rate (the spin axis shares its moment with another
  axis), the polynomial motion at the ends of the span of the times, 0 included;
- for growth, a finite growth factor: ``2 lambda T <= log(max float)`` (the second order
  holds ``sinh(2 lambda t)``);
- for an oscillation, a phase still in step with the motion: the expansion oscillates at
  ``w``, the motion at ``2 pi / P`` (``P`` its exact period), so after ``T`` the phases differ
  by ``|w - 2 pi / P| T``; that, plus the rounding of the phase ``4 eps_machine w T``, must be
  at most ``EPS_MAX`` radians.

An input whose expansion would still overflow double precision (rates of 1e300) raises
:class:`~polhode.errors.NonFiniteError`. A pure spin (``a = b = 0``) is the steady rotation,
returned for any times.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core
from polhode._chunks import spans
from polhode._coerce import as_array, as_integer
from polhode._coerce import as_float_array as _as_float_array
from polhode.errors import ArgumentError, NonFiniteError, ShapeError

__all__ = ["EPS_MAX", "perturbation"]

#: The largest relative size of the perturbation, ``|omega_perp| / |W|``, at which the expansion
#: is used (at the initial time and, as described in the module docstring, over the times).
EPS_MAX = 0.5

#: log of the largest double: the growth factor e^(2 lambda t) of the second order must stay below.
_LOG_MAX = math.log(np.finfo(np.float64).max)

#: Relative rounding of the computed phase w t, in units of the machine epsilon.
_PHASE_ROUNDING = 4.0 * np.finfo(np.float64).eps


def perturbation(moments: Any, omega0: Any, t: Any, *, axis: int | None = None, order: int = 2):
    """The angular velocity near a principal axis, by the expansion to ``order`` (0, 1 or 2).

    Parameters
    ----------
    moments : (3,) array_like
        Principal moments (positive), in the body's principal axes.
    omega0 : (3,) array_like
        Initial angular velocity in those axes; the component about ``axis`` is the spin ``W``,
        the other two are the perturbation.
    t : (M,) array_like
        Times (the initial time is 0).
    axis : int, optional
        The principal axis spun about (default: the largest component of ``omega0``).
    order : {0, 1, 2}

    Returns
    -------
    (M, 3) numpy.ndarray
        omega at each time.

    Raises
    ------
    ArgumentError
        Outside the expansion's domain (see the module docstring): no spin about ``axis``, a
        perturbation above ``EPS_MAX`` times the spin (``argument="omega0"``), or times at
        which it has grown beyond that, its growth factor overflows or its phase has drifted
        from the motion's (``argument="t"``); the message says which and, for the times, up
        to when the expansion holds.
    NonFiniteError
        Non-finite input, or an expansion that overflows double precision.

    Examples
    --------
    Near the axis of the smallest moment the perturbation oscillates; the first order is off
    by about eps^2 and the second by about eps^3 (eps = 0.022 here):

    >>> import numpy as np
    >>> import polhode as ph
    >>> moments, omega0 = [1.0, 2.0, 3.0], [1.0, 0.01, -0.02]
    >>> t = np.linspace(0.0, 10.0, 101)
    >>> exact = ph.simulate(moments, omega0, t).omega
    >>> first = ph.perturbation(moments, omega0, t, order=1)
    >>> second = ph.perturbation(moments, omega0, t, order=2)
    >>> print(f"{abs(first - exact).max():.1e} {abs(second - exact).max():.1e}")
    6.0e-04 4.2e-05

    Near the intermediate axis it grows, and the expansion says when it stops holding:

    >>> try:
    ...     ph.perturbation(moments, [0.001, 1.0, 0.001], [0.0, 20.0])
    ... except ph.ArgumentError as error:
    ...     print(error.argument)
    t
    """
    inertia = as_array("moments", moments, (3,))
    omega = as_array("omega0", omega0, (3,))
    times = np.atleast_1d(_as_float_array("t", t))
    if times.ndim != 1:
        raise ShapeError(
            f"Expected `t` to have shape (M,), got {times.shape}.", argument="t"
        )
    if not (np.all(np.isfinite(inertia)) and np.all(inertia > 0)):
        raise ArgumentError(
            f"Expected positive finite `moments`, got {inertia.tolist()}.", argument="moments"
        )
    if not np.all(np.isfinite(omega)):
        raise NonFiniteError(f"Expected finite `omega0`, got {omega.tolist()}.", argument="omega0")
    if not all(np.isfinite(times[span]).all() for span in spans(times.size)):
        raise NonFiniteError("Expected finite `t`.", argument="t")
    order = as_integer("order", order, allowed=(0, 1, 2))
    if axis is None:
        k = int(np.argmax(np.abs(omega)))
    else:
        k = as_integer("axis", axis, allowed=(0, 1, 2))
    i, j = (k + 1) % 3, (k + 2) % 3  # cyclic, so the signs of Euler's equations hold
    ii, ij, ik = inertia[i], inertia[j], inertia[k]
    spin, a, b = omega[k], omega[i], omega[j]
    result = np.empty((times.size, 3))
    # Every overflow and invalid operation below is either excluded by the domain checks or
    # turned into a NonFiniteError at the end: none reaches the caller as a warning.
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        _check_domain(inertia, omega, k, times)
        # For a pure spin, the steady rotation about the axis, exactly.
        steady = order == 0 or (a == 0.0 and b == 0.0)
        omega_i = spin * (ik - ij) / ii
        omega_j = spin * (ik - ii) / ij
        finite = True
        # Time by time, in chunks (polhode._chunks): Ctrl-C is not held up by a sine of 5e7
        # times, and each time's numbers are those of the whole array at once.
        for span in spans(times.size):
            out = result[span]
            out[:, k] = spin
            if steady:
                out[:, i] = 0.0
                out[:, j] = 0.0
                continue
            u, v, uv_integral = _first_order(a, b, omega_i, omega_j, times[span])
            out[:, i] = u
            out[:, j] = v
            if order == 2:
                out[:, k] += (ii - ij) / ik * uv_integral
            if not np.isfinite(out).all():
                finite = False
                break
    if not finite:
        raise NonFiniteError(
            "The perturbation expansion overflows double precision with these `moments` and "
            f"`omega0` ({inertia.tolist()}, {omega.tolist()}).",
            argument="omega0",
        )
    return result


def _check_domain(
    inertia: NDArray[np.float64], omega: NDArray[np.float64], k: int, times: NDArray[np.float64]
) -> None:
    """Raise ArgumentError where the expansion about axis ``k`` means nothing (module docstring)."""
    i, j = (k + 1) % 3, (k + 2) % 3
    spin, a, b = float(omega[k]), float(omega[i]), float(omega[j])
    where = f"about `axis={k}` with omega0 = {omega.tolist()}"
    if spin == 0.0:
        raise ArgumentError(
            f"Invalid `omega0`: no spin {where}; the expansion is in |omega_perp| / |W| with W "
            "the spin about the axis, which must not be zero.",
            argument="omega0",
        )
    if a == 0.0 and b == 0.0:
        return  # the steady rotation: exact at any time
    scale = abs(spin)
    eps = math.hypot(a, b) / scale
    if not eps <= EPS_MAX:
        raise ArgumentError(
            f"Invalid `omega0`: the perturbation {where} is eps = |omega_perp| / |W| = "
            f"{eps:.3g}, above {EPS_MAX} (the expansion is in powers of eps); spin closer to "
            "the axis or integrate with polhode.simulate.",
            argument="omega0",
        )
    omega_i = spin * (inertia[k] - inertia[j]) / inertia[i]
    omega_j = spin * (inertia[k] - inertia[i]) / inertia[j]
    product = float(omega_i * omega_j)
    if not math.isfinite(product):
        raise NonFiniteError(
            f"The perturbation expansion {where} overflows double precision: its rates "
            f"W (I_k - I_j) / I_i are {float(omega_i):.3g} and {float(omega_j):.3g} with "
            f"moments {inertia.tolist()}.",
            argument="omega0",
        )
    # max |t| without the temporary array of |t| (5e7 times: 0.4 GB and 0.2 s).
    span = max(float(np.max(times, initial=0.0)), -float(np.min(times, initial=0.0))) + 0.0
    if product > 0:
        _check_oscillation(inertia, omega, k, span, scale, a, b, omega_i, omega_j)
    elif product < 0:
        _check_growth(k, span, scale, a, b, omega_i, omega_j)
    else:
        # u = a - Omega_i b t, v = b + Omega_j a t: |(u, v)|^2 is convex in t, largest at an
        # end of the span of the times (0 included).
        ends = (float(np.min(times, initial=0.0)), float(np.max(times, initial=0.0)))
        size = max(math.hypot(a - omega_i * b * x, b + omega_j * a * x) / scale for x in ends)
        if not size <= EPS_MAX:
            raise ArgumentError(
                f"Invalid `t`: `axis={k}` shares its moment with another, so the perturbation "
                f"drifts linearly in t, reaching {size:.3g} |W| within the times, above "
                f"{EPS_MAX} |W| (the expansion is in powers of it).",
                argument="t",
            )


def _check_oscillation(
    inertia: NDArray[np.float64],
    omega: NDArray[np.float64],
    k: int,
    span: float,
    scale: float,
    a: float,
    b: float,
    omega_i: float,
    omega_j: float,
) -> None:
    """Near a stable axis: the size of the oscillation, and its phase against the motion's."""
    w = math.sqrt(omega_i * omega_j)
    p, q = omega_i * b / w, omega_j * a / w
    # |(u, v)|^2 = [c s] M [c s]^T on the circle (c, s) = (cos wt, sin wt): its largest value
    # is M's largest eigenvalue.
    m11, m22, m12 = a * a + b * b, p * p + q * q, b * q - a * p
    size = math.sqrt((m11 + m22 + math.hypot(m11 - m22, 2 * m12)) / 2) / scale
    if not size <= EPS_MAX:
        raise ArgumentError(
            f"Invalid `omega0`: near the stable `axis={k}` the perturbation of {omega.tolist()} "
            f"oscillates with a size up to {size:.3g} |W|, above {EPS_MAX} |W| (the expansion "
            "is in powers of it); spin closer to the axis or integrate with polhode.simulate.",
            argument="omega0",
        )
    info = _core.free_rotation(
        (float(inertia[0]), float(inertia[1]), float(inertia[2])),
        (float(omega[0]), float(omega[1]), float(omega[2])),
    )
    if info["regime"] not in ("about_axis", "symmetric") or info["axis"] != k:
        raise ArgumentError(
            f"Invalid `omega0`: the motion from {omega.tolist()} does not circulate about "
            f"`axis={k}` (regime {info['regime']}, about `axis={info['axis']}`).",
            argument="omega0",
        )
    motion = 2 * math.pi / info["period"]
    drift_rate = abs(w - motion) + _PHASE_ROUNDING * w
    if not drift_rate * span <= EPS_MAX:
        raise ArgumentError(
            f"Invalid `t`: near the stable `axis={k}` the expansion oscillates at {w:.15g} and the "
            f"motion at 2 pi / period = {motion:.15g}; by |t| = {span:.6g} their phases differ "
            f"by {drift_rate * span:.3g} rad (rounding included), above {EPS_MAX}: the "
            f"expansion holds for |t| <= {EPS_MAX / drift_rate:.9g}.",
            argument="t",
        )


def _check_growth(
    k: int, span: float, scale: float, a: float, b: float, omega_i: float, omega_j: float
) -> None:
    """Near the unstable axis: a finite growth factor, and a perturbation still small."""
    rate = math.sqrt(-omega_i * omega_j)
    p, q = omega_i * b / rate, omega_j * a / rate
    grows = f"near the unstable `axis={k}` the perturbation grows like e^(lambda t), " + (
        f"lambda = {rate:.9g}"
    )
    overflow = _LOG_MAX / (2 * rate)  # beyond, e^(2 lambda t) overflows

    def size(x: float) -> float:
        """The terms of u = a cosh - p sinh and v = b cosh + q sinh, in size, over |W|."""
        c, s = math.cosh(rate * x), math.sinh(rate * x)
        return math.hypot(abs(a) * c + abs(p) * s, abs(b) * c + abs(q) * s) / scale

    reached = size(min(span, overflow))  # increasing in |t|
    if not reached <= EPS_MAX:
        low, high = 0.0, min(span, overflow)  # bisect for where it reaches EPS_MAX
        for _ in range(100):
            middle = (low + high) / 2
            low, high = (middle, high) if size(middle) <= EPS_MAX else (low, middle)
        raise ArgumentError(
            f"Invalid `t`: {grows}, and reaches {reached:.3g} |W| by |t| = "
            f"{min(span, overflow):.6g}, above {EPS_MAX} |W| (the expansion is in powers of it): "
            f"the expansion holds for |t| <= {low:.9g}.",
            argument="t",
        )
    if span > overflow:
        raise ArgumentError(
            f"Invalid `t`: {grows}; at |t| = {span:.6g} the growth factor e^(2 lambda t) of "
            "the second order overflows double precision: the expansion holds for "
            f"|t| <= {overflow:.9g}.",
            argument="t",
        )


def _first_order(
    a: float, b: float, omega_i: float, omega_j: float, t: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """u, v solving u' = -Omega_i v, v' = Omega_j u from (a, b), and the integral of u v."""
    product = omega_i * omega_j
    if product > 0:
        w = np.sqrt(product)
        p, q = omega_i * b / w, omega_j * a / w
        c, s = np.cos(w * t), np.sin(w * t)
        u, v = a * c - p * s, b * c + q * s
        # u v = ab c^2 + (a q - p b) c s - p q s^2, integrated from 0.
        cc = t / 2 + np.sin(2 * w * t) / (4 * w)
        cs = s * s / (2 * w)
        ss = t / 2 - np.sin(2 * w * t) / (4 * w)
    elif product < 0:
        w = np.sqrt(-product)
        p, q = omega_i * b / w, omega_j * a / w
        c, s = np.cosh(w * t), np.sinh(w * t)
        u, v = a * c - p * s, b * c + q * s
        cc = t / 2 + np.sinh(2 * w * t) / (4 * w)
        cs = s * s / (2 * w)
        ss = -t / 2 + np.sinh(2 * w * t) / (4 * w)
    else:
        # A zero rate: u' = -Omega_i v, v' = Omega_j u with one of them zero is polynomial.
        u = a - omega_i * b * t
        v = b + omega_j * a * t
        return (
            u,
            v,
            a * b * t
            + (a * omega_j * a - omega_i * b * b) * t**2 / 2
            - (omega_i * omega_j * a * b * t**3 / 3),
        )
    return u, v, a * b * cc + (a * q - p * b) * cs - p * q * ss
