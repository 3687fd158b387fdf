"""The domain of the perturbation expansion: each of its edges against a closed form, with the
expansion still finite (and right) just inside and a typed error naming the culprit just
outside; outside the domain never a numpy warning, a NaN or an overflowed value."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.special import ellipk

import polhode as ph
from polhode.perturbation import EPS_MAX, perturbation

EPS = np.finfo(np.float64).eps
LOG_MAX = math.log(np.finfo(np.float64).max)
MOMENTS = np.array([1.0, 2.0, 3.0])
INSIDE, OUTSIDE = 1 - 1e-9, 1 + 1e-9


def limit_in(message: str) -> float:
    """The time up to which the message says the expansion holds."""
    return float(re.search(r"holds for \|t\| <= ([0-9.e+-]+)", message).group(1).rstrip("."))


def test_a_pure_spin_is_the_steady_rotation_at_any_time():
    # Even about the unstable axis and at times where e^(lambda t) overflows: no perturbation,
    # nothing grows.
    t = [0.0, 1e3, 1e300]
    for order in (0, 1, 2):
        omega = perturbation(MOMENTS, [0.0, -2.0, 0.0], t, order=order)
        np.testing.assert_array_equal(omega, [[0.0, -2.0, 0.0]] * 3)


def test_no_spin_about_the_axis_is_outside():
    with pytest.raises(ph.ArgumentError, match="no spin") as error:
        perturbation(MOMENTS, [1.0, 0.0, 0.0], [0.0, 1.0], axis=2)
    assert error.value.argument == "omega0"


def test_the_small_parameter_edge_on_a_sphere():
    # All moments equal: omega is constant, the expansion exact at every order, and the only
    # edge is eps = |omega_perp| / |W| = EPS_MAX.
    t = np.linspace(-5.0, 5.0, 11)
    omega = perturbation([2.0, 2.0, 2.0], [0.0, EPS_MAX, 1.0], t, axis=2)
    np.testing.assert_array_equal(omega, [[0.0, EPS_MAX, 1.0]] * 11)
    with pytest.raises(ph.ArgumentError, match="eps") as error:
        perturbation([2.0, 2.0, 2.0], [0.0, EPS_MAX * OUTSIDE, 1.0], t, axis=2)
    assert error.value.argument == "omega0"


def test_the_symmetric_top_edges():
    # Moments (1, 1, 2) spun at W = 1 about the symmetry axis: omega_perp turns at
    # Omega = W (I3 - I1) / I1 = 1 keeping its size, (-b sin t, b cos t, W); the order-1 term is
    # exactly that, the order-2 term is zero (I1 = I2). Size edge: b = EPS_MAX.
    t = np.linspace(0.0, 1e3, 101)
    b = EPS_MAX
    expected = np.column_stack([-b * np.sin(t), b * np.cos(t), np.ones_like(t)])
    omega = perturbation([1.0, 1.0, 2.0], [0.0, b, 1.0], t, order=2)
    np.testing.assert_allclose(omega, expected, rtol=0, atol=1e3 * 4 * EPS)
    with pytest.raises(ph.ArgumentError) as error:
        perturbation([1.0, 1.0, 2.0], [0.0, b * OUTSIDE, 1.0], t)
    assert error.value.argument == "omega0"
    # The expansion's frequency is the motion's: only the rounding of the phase w t, 4 eps w t,
    # limits the times, to 0.5 / (4 eps) = 5.6e14.
    limit = EPS_MAX / (4 * EPS)
    assert np.all(np.isfinite(perturbation([1.0, 1.0, 2.0], [0.0, 0.1, 1.0], [0.0, 0.9 * limit])))
    with pytest.raises(ph.ArgumentError, match="phases") as error:
        perturbation([1.0, 1.0, 2.0], [0.0, 0.1, 1.0], [0.0, 1.1 * limit])
    assert error.value.argument == "t"


def test_the_oscillation_size_edge():
    # About the smallest axis of (1, 2, 3) with omega0 = (W, 0, b): Omega_1 = W (I1 - I3) / I2
    # = -W, Omega_2 = W (I1 - I2) / I3 = -W / 3, w = W / sqrt(3); omega_2 = b cos wt and
    # omega_1 = sqrt(3) b sin wt, largest sqrt(3) b: the edge is b = EPS_MAX W / sqrt(3),
    # though eps = b / W is only 0.29 there.
    w_spin = 2.0
    edge = EPS_MAX * w_spin / math.sqrt(3)
    t = np.linspace(0.0, 1.0, 5)
    omega = perturbation(MOMENTS, [w_spin, 0.0, edge * INSIDE], t, axis=0, order=1)
    w = w_spin / math.sqrt(3)
    np.testing.assert_allclose(omega[:, 1], math.sqrt(3) * edge * np.sin(w * t), rtol=1e-8)
    np.testing.assert_allclose(omega[:, 2], edge * np.cos(w * t), rtol=1e-8)
    with pytest.raises(ph.ArgumentError, match="oscillates") as error:
        perturbation(MOMENTS, [w_spin, 0.0, edge * OUTSIDE], t, axis=0)
    assert error.value.argument == "omega0"


def test_the_phase_edge_against_the_exact_period():
    # Near the smallest axis of (1, 2, 3): the expansion oscillates at w = sqrt(Omega_1 Omega_2),
    # the motion at 2 pi / P with P = 4 K(k^2) / lambda (L^2 < 2 T I2: L circulates about the
    # smallest axis, Delta_j = L^2 - 2 T I_j, lambda = sqrt(Delta_3 (I2 - I1) / (I1 I2 I3)),
    # k^2 = (I3 - I2) Delta_1 / ((I2 - I1) (-Delta_3))... with the roles of 1 and 3 swapped
    # from the largest-axis case). Their phases part by |w - 2 pi / P| t (+ 4 eps w t).
    i = MOMENTS
    w0 = np.array([1.0, 0.02, -0.01])
    l2, t2 = np.sum((i * w0) ** 2), np.sum(i * w0**2)
    d1, d3 = l2 - t2 * i[0], l2 - t2 * i[2]
    lam = np.sqrt(-d3 * (i[1] - i[0]) / np.prod(i))
    k2 = (i[2] - i[1]) * d1 / ((i[1] - i[0]) * (-d3))
    motion = 2 * np.pi / (4 * ellipk(k2) / lam)
    w = math.sqrt((i[0] - i[2]) / i[1] * (i[0] - i[1]) / i[2])
    limit = EPS_MAX / (abs(w - motion) + 4 * EPS * w)
    assert 1e3 < limit < 1e5  # many periods (about 2000), not forever
    inside = perturbation(MOMENTS, w0, [0.0, limit * (1 - 1e-6)], axis=0)
    assert np.all(np.isfinite(inside))
    with pytest.raises(ph.ArgumentError, match="phases") as error:
        perturbation(MOMENTS, w0, [0.0, limit * (1 + 1e-6)], axis=0)
    assert error.value.argument == "t"
    assert limit_in(str(error.value)) == pytest.approx(limit, rel=1e-5)


def growth_case(c: float, w_spin: float = 2.0):
    """About the intermediate axis of (1, 2, 3) from (0, W, c): lambda = W sqrt((I2 - I1)
    (I3 - I2) / (I1 I3)) = W / sqrt(3), omega_3 = c cosh(lambda t) and omega_1 =
    -sqrt(3) c sinh(lambda t) (from I1 omega_1' = (I2 - I3) omega_2 omega_3)."""
    lam = w_spin * math.sqrt((2.0 - 1.0) * (3.0 - 2.0) / (1.0 * 3.0))
    return [0.0, w_spin, c], lam


def test_the_growth_edge_near_the_unstable_axis():
    w_spin, c = 2.0, 1e-6
    omega0, lam = growth_case(c, w_spin)
    # Size c sqrt(cosh^2 + 3 sinh^2) = c sqrt(1 + 4 sinh^2) reaches EPS_MAX W at
    # sinh(lambda t) = sqrt((EPS_MAX W / c)^2 - 1) / 2.
    edge = math.asinh(math.sqrt((EPS_MAX * w_spin / c) ** 2 - 1) / 2) / lam
    t = np.array([0.0, edge * INSIDE])
    omega = perturbation(MOMENTS, omega0, t, order=1)
    np.testing.assert_allclose(omega[:, 2], c * np.cosh(lam * t), rtol=1e-12)
    np.testing.assert_allclose(omega[:, 0], -math.sqrt(3) * c * np.sinh(lam * t), rtol=1e-12)
    np.testing.assert_array_equal(omega[:, 1], w_spin)
    assert np.all(np.isfinite(perturbation(MOMENTS, omega0, t, order=2)))
    for end in (edge * OUTSIDE, -edge * OUTSIDE, 1e3, 1e300):
        with pytest.raises(ph.ArgumentError, match="unstable") as error:
            perturbation(MOMENTS, omega0, [0.0, end], order=2)
        assert error.value.argument == "t"
        assert limit_in(str(error.value)) == pytest.approx(edge, rel=1e-8)


def test_the_growth_factor_overflow_edge():
    # A perturbation of 1e-300 would stay small until e^(lambda t) ~ 1e300, but the second
    # order holds sinh(2 lambda t), finite only while 2 lambda t <= log(max float).
    c = 1e-300
    omega0, lam = growth_case(c)
    edge = LOG_MAX / (2 * lam)
    t = np.array([0.0, edge * INSIDE])
    omega = perturbation(MOMENTS, omega0, t, order=2)
    assert np.all(np.isfinite(omega))
    np.testing.assert_allclose(omega[:, 2], c * np.cosh(lam * t), rtol=1e-10)
    with pytest.raises(ph.ArgumentError, match="overflows") as error:
        perturbation(MOMENTS, omega0, [0.0, edge * OUTSIDE], order=2)
    assert error.value.argument == "t"
    assert limit_in(str(error.value)) == pytest.approx(edge, rel=1e-8)


def test_the_linear_drift_edge_when_the_axis_shares_its_moment():
    # Moments (1, 2, 2) spun about the third axis: Omega_1 = W (I3 - I2) / I1 = 0 and
    # Omega_2 = W (I3 - I1) / I2 = W / 2, so from (a, 0, W) omega_1 = a and omega_2 = W a t / 2:
    # size a sqrt(1 + (W t / 2)^2) reaches EPS_MAX W at t = 2 sqrt((EPS_MAX W / a)^2 - 1) / W.
    moments, w_spin, a = [1.0, 2.0, 2.0], 1.0, 0.1
    edge = 2 * math.sqrt((EPS_MAX * w_spin / a) ** 2 - 1) / w_spin
    t = np.array([-edge * INSIDE, 0.0, edge * INSIDE])
    omega = perturbation(moments, [a, 0.0, w_spin], t, axis=2, order=1)
    np.testing.assert_allclose(omega[:, 0], a, rtol=1e-15)
    np.testing.assert_allclose(omega[:, 1], w_spin * a * t / 2, rtol=1e-14)
    for end in (edge * OUTSIDE, -edge * OUTSIDE):
        with pytest.raises(ph.ArgumentError, match="linearly") as error:
            perturbation(moments, [a, 0.0, w_spin], [0.0, end], axis=2)
        assert error.value.argument == "t"


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize(
    ("moments", "omega0", "t", "kwargs", "error", "argument"),
    [
        # the unstable intermediate axis at long times (e^(lambda t) overflowed: 1e248, NaN)
        (MOMENTS, [0.01, 1.0, 0.01], [0.0, 100.0, 1000.0], {}, ph.ArgumentError, "t"),
        # huge times about a stable axis (the phase was lost; 2 w t overflowed: NaN)
        (MOMENTS, [0.01, 0.01, 1.0], [0.0, 1e308], {}, ph.ArgumentError, "t"),
        (MOMENTS, [0.01, 0.01, 1.0], [0.0, 1e300], {}, ph.ArgumentError, "t"),
        # omega0 far from the axis
        (MOMENTS, [1.0, 1.0, 1.0], [0.0, 1.0], {}, ph.ArgumentError, "omega0"),
        (MOMENTS, [0.9, 0.0, 1.0], [0.0, 1.0], {"axis": 2}, ph.ArgumentError, "omega0"),
        # zero spin about the axis asked for
        (MOMENTS, [1.0, 0.0, 0.0], [0.0, 1.0], {"axis": 2}, ph.ArgumentError, "omega0"),
        (MOMENTS, [0.0, 0.0, 0.0], [0.0, 1.0], {"axis": 1}, ph.ArgumentError, "omega0"),
        (MOMENTS, [0.0, 0.0, 0.0], [0.0, 1.0], {}, ph.ArgumentError, "omega0"),
        # equal moments: a zero rate, the perturbation drifts linearly without bound
        ([1.0, 2.0, 2.0], [0.01, 0.01, 1.0], [0.0, 1e6], {}, ph.ArgumentError, "t"),
        # magnitudes whose rates overflow
        ([1e-300, 1.0, 1e300], [0.01, 0.01, 1.0], [0.0, 1.0], {}, ph.NonFiniteError, "omega0"),
        (MOMENTS, [1e307, 1e308, 1e306], [0.0, 1.0], {}, ph.PolhodeError, None),
        # non-finite input
        (MOMENTS, [0.01, 1.0, 0.01], [0.0, np.inf], {}, ph.NonFiniteError, "t"),
        (MOMENTS, [0.01, np.inf, 0.01], [0.0, 1.0], {}, ph.NonFiniteError, "omega0"),
    ],
)
@pytest.mark.parametrize("order", [0, 1, 2])
def test_outside_the_domain_a_typed_error_never_a_warning(
    moments, omega0, t, kwargs, error, argument, order
):
    with pytest.raises(error) as raised:
        perturbation(moments, omega0, t, order=order, **kwargs)
    if argument is not None:
        assert raised.value.argument == argument
    assert str(raised.value)  # says why
