"""The perturbation expansion near a principal axis: the order-n truncation's error at a
fixed time falls like eps^(n+1), against an independent tight scipy integration."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import polhode as ph
from polhode.perturbation import perturbation
from reference import euler_rhs

MOMENTS = np.array([1.0, 2.0, 3.0])


def reference(moments, omega0, t):
    sol = solve_ivp(euler_rhs(moments), (0.0, t), omega0, method="DOP853", rtol=1e-13, atol=1e-16)
    return sol.y[:, -1]


@pytest.mark.parametrize("axis", [0, 1, 2], ids=["smallest", "intermediate", "largest"])
def test_order_n_error_falls_like_eps_to_the_n_plus_1(axis):
    t = 1.5
    epsilons = 2e-2 / 2.0 ** np.arange(7)  # down to 3e-4: well inside the asymptotic range
    errors = {n: [] for n in (0, 1, 2)}
    for eps in epsilons:
        omega0 = eps * np.array([0.7, -0.4, 0.5])
        omega0[axis] = 1.0
        exact = reference(MOMENTS, omega0, t)
        for n in (0, 1, 2):
            approx = perturbation(MOMENTS, omega0, [t], axis=axis, order=n)[0]
            errors[n].append(np.linalg.norm(approx - exact))
    for n in (0, 1, 2):
        slopes = np.log2(np.array(errors[n][:-1]) / np.array(errors[n][1:]))
        # Asymptotically n + 1; the last halving must be within 0.15 of it.
        assert abs(slopes[-1] - (n + 1)) < 0.15, (n, slopes)


def test_first_order_rates_match_analyze_and_the_motion():
    # Near the largest axis: oscillation at sqrt(Omega1 Omega2); near the intermediate one,
    # growth at sqrt(-Omega1 Omega2), with Omega1 = w3 (I3 - I2)/I1, Omega2 = w3 (I3 - I1)/I2.
    w3 = 2.0
    oscillating = np.sqrt(w3 * (3 - 2) / 1 * w3 * (3 - 1) / 2)
    a = ph.analyze(MOMENTS, [1e-4, 0.0, w3])
    assert a.linearized["kind"] == "oscillation"
    assert abs(a.linearized["rate"] / oscillating - 1) < 1e-14
    t = np.linspace(0.0, 2 * np.pi / oscillating, 5)
    omega = perturbation(MOMENTS, [1e-4, 0.0, w3], t, order=1)
    # One period later the perturbation is back where it started.
    np.testing.assert_allclose(omega[-1], omega[0], rtol=0, atol=1e-15)
    growing = ph.analyze(MOMENTS, [0.0, w3, 1e-6])
    assert growing.linearized["kind"] == "growth"
    rate = growing.linearized["rate"]
    omega = perturbation(MOMENTS, [0.0, w3, 1e-6], [0.0, 3.0], order=1)
    # e^{lambda t} growth of the off-axis part (the cosh/sinh mix tends to it).
    ratio = np.linalg.norm(omega[1, [0, 2]]) / np.linalg.norm(omega[0, [0, 2]])
    assert 0.3 * np.exp(rate * 3.0) < ratio < 3 * np.exp(rate * 3.0)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"order": 3}, "order"),
        ({"axis": 5}, "axis"),
        ({"moments": [1.0, 0.0, 2.0]}, "moments"),
        ({"omega0": [np.nan, 1.0, 0.0]}, "omega0"),
    ],
)
def test_bad_arguments(kwargs, fragment):
    args = {"moments": MOMENTS, "omega0": [0.01, 1.0, 0.0], "t": [0.0, 1.0]}
    args.update(kwargs)
    with pytest.raises(ph.PolhodeError, match=fragment):
        perturbation(args.pop("moments"), args.pop("omega0"), args.pop("t"), **args)


@pytest.mark.parametrize(
    ("kwargs", "error", "argument"),
    [
        # omega0 is made of eps there: an eps outside the expansion's domain is named as eps
        # (it was named `omega0`, an argument the caller never gave), an order as `orders`.
        ({"eps": [1e-3, 0.9]}, ph.ArgumentError, "eps"),
        ({"orders": [3]}, ph.ArgumentError, "orders"),
        ({"orders": [1, -1]}, ph.ArgumentError, "orders"),
        ({"orders": ["1"]}, TypeError, "orders"),
        ({"orders": [1.0]}, TypeError, "orders"),
        ({"orders": 2}, TypeError, "orders"),
    ],
)
def test_perturbation_errors_name_their_own_arguments(kwargs, error, argument):
    pytest.importorskip("matplotlib")
    args = {"eps": [1e-3, 1e-2], "orders": (1, 2)}
    args.update(kwargs)
    for function in (ph.plot.perturbation_errors, ph.plot.perturbation_error):
        with pytest.raises(error) as info:
            function(MOMENTS, 2, args["eps"], args["orders"], 1.0)
        if error is TypeError:
            assert f"`{argument}`" in str(info.value)
        else:
            assert info.value.argument == argument, str(info.value)
