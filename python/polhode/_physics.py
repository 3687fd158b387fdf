"""Two numbers the front ends read off a motion and its inputs (the command line only formats
them): whether principal moments break the triangle inequality, and a wheel's rate about its
axis."""

from __future__ import annotations

import numpy as np

from polhode.rotors import Wheel

__all__ = ["breaks_triangle_inequality", "wheel_rate"]


def breaks_triangle_inequality(moments: np.ndarray) -> bool:
    """Whether I1 + I2 >= I3 fails beyond rounding (the tolerance of Body.from_inertia)."""
    half_trace = float(np.sum(moments)) / 2
    return half_trace - float(np.max(moments)) < -16 * np.finfo(float).eps * half_trace


def wheel_rate(wheel: Wheel, rate: np.ndarray) -> np.ndarray:
    """A wheel's rate about its axis from its ``rotor_rates`` vector ``W a`` (a the unit axis),
    by the largest component of ``a`` (W itself for an axis along a body axis)."""
    axis = wheel.axis / np.linalg.norm(wheel.axis)
    k = int(np.argmax(np.abs(axis)))
    return np.asarray(rate[..., k] / axis[k])
