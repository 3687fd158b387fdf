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
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode._coerce import as_float_array as _as_float_array
from polhode.errors import ArgumentError, NonFiniteError, ShapeError

__all__ = ["perturbation"]


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
    """
    inertia = _as_float_array("moments", moments)
    omega = _as_float_array("omega0", omega0)
    times = np.atleast_1d(_as_float_array("t", t))
    if inertia.shape != (3,) or omega.shape != (3,) or times.ndim != 1:
        raise ShapeError(
            "Expected `moments` and `omega0` of shape (3,) and `t` of shape (M,), got "
            f"{inertia.shape}, {omega.shape}, {times.shape}."
        )
    if not (np.all(np.isfinite(inertia)) and np.all(inertia > 0)):
        raise ArgumentError(
            f"Expected positive finite `moments`, got {inertia.tolist()}.", argument="moments"
        )
    if not (np.all(np.isfinite(omega)) and np.all(np.isfinite(times))):
        raise NonFiniteError("Expected finite `omega0` and `t`.")
    if isinstance(order, bool) or order not in (0, 1, 2):
        raise ArgumentError(f"Expected `order` to be 0, 1 or 2, got {order!r}.", argument="order")
    k = int(np.argmax(np.abs(omega))) if axis is None else axis
    if isinstance(k, bool) or k not in (0, 1, 2):
        raise ArgumentError(f"Expected `axis` to be 0, 1 or 2, got {axis!r}.", argument="axis")
    i, j = (k + 1) % 3, (k + 2) % 3  # cyclic, so the signs of Euler's equations hold
    ii, ij, ik = inertia[i], inertia[j], inertia[k]
    spin, a, b = omega[k], omega[i], omega[j]
    result = np.zeros((times.size, 3))
    result[:, k] = spin
    if order == 0:
        return result
    omega_i = spin * (ik - ij) / ii
    omega_j = spin * (ik - ii) / ij
    u, v, uv_integral = _first_order(a, b, omega_i, omega_j, times)
    result[:, i] = u
    result[:, j] = v
    if order == 2:
        result[:, k] += (ii - ij) / ik * uv_integral
    return result


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
