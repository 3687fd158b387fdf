"""Results that resolve the motion: the output times of an end time,
dense output, batches indexed like arrays, the state at t0, and trajectories equal by value."""

from __future__ import annotations

import copy
import math
import pickle

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.special import ellipk

import polhode as ph
from polhode.invariants import max_relative_drift

PER_TURN = 48
MOMENTS = np.array([1.0, 2.0, 3.0])
OMEGA0 = np.array([0.01, 1.0, 5.0])
DAMPER = ph.rotors.SphericalDamper(0.05, 0.1)
PUSH = ph.torque.BodyFixed([0.0, 0.0, 0.01])

#: Every method, and the runs with a torque and with rotors (name: keywords).
RUNS = {
    "exact": {"method": "exact"},
    "splitting": {"method": "splitting", "dt": 0.01},
    "midpoint": {"method": "midpoint", "dt": 0.01},
    "rk4": {"method": "rk4", "dt": 0.01},
    "dop853": {"method": "dop853"},
    "dop853 torque": {"method": "dop853", "torque": PUSH},
    "rk4 torque": {"method": "rk4", "dt": 0.01, "torque": PUSH},
    "dop853 rotors": {"method": "dop853", "rotors": [DAMPER]},
    "rk4 rotors": {"method": "rk4", "dt": 0.01, "rotors": [DAMPER]},
}


def omega_period(moments, omega0):
    """The period of omega in the body (three distinct moments), written apart from the core:
    P = 4 K(m) / lambda (Landau and Lifshitz, section 37)."""
    i1, i2, i3 = moments
    w = np.asarray(omega0)
    two_t = float(np.sum(moments * w * w))
    l2 = float(np.sum((moments * w) ** 2))
    if l2 > two_t * i2:  # about the largest axis
        lam = math.sqrt((i3 - i2) * (l2 - two_t * i1) / (i1 * i2 * i3))
        m = (i2 - i1) * (two_t * i3 - l2) / ((i3 - i2) * (l2 - two_t * i1))
    else:
        lam = math.sqrt((i2 - i1) * (two_t * i3 - l2) / (i1 * i2 * i3))
        m = (i3 - i2) * (l2 - two_t * i1) / ((i2 - i1) * (two_t * i3 - l2))
    return 4.0 * float(ellipk(m)) / lam


def turn_angles(quaternion):
    """The angle the body turns through between successive output times (scipy)."""
    r = Rotation.from_quat(quaternion)
    return (r[:-1].inv() * r[1:]).magnitude()


# ---------------------------------------------------------------------------------------------
# An end time: output times that resolve the motion
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(RUNS))
def test_an_end_time_gives_48_samples_per_turn_of_the_fastest_motion(name):
    span = 20.0
    sol = ph.simulate(MOMENTS, OMEGA0, span, **RUNS[name])
    t = sol.t
    assert t[0] == 0.0 and t[-1] == span and np.all(np.diff(t) > 0)
    # At least 48 per period of omega in the body (the closed form, scipy's K(m))...
    assert t.size - 1 >= PER_TURN * span / omega_period(MOMENTS, OMEGA0)
    # ... and the body turns by at most 1/48 of a turn between two of them (scipy; with a
    # torque the spin grows over the run, 0.2 rad/s of 5.1: 5% at most).
    slack = 1.05 if "torque" in name else 1.0 + 1e-9
    assert np.max(turn_angles(sol.quaternion)) <= slack * 2.0 * np.pi / PER_TURN
    # The same numbers as the times given as an array (the sampling only chooses them).
    again = ph.simulate(MOMENTS, OMEGA0, t, **RUNS[name])
    assert again == sol
    assert "sampling" not in again.stats and "per turn" in repr(sol)
    assert "per turn" not in repr(again)


def test_the_fixed_step_methods_sample_their_own_steps():
    sol = ph.simulate(MOMENTS, OMEGA0, 20.0, method="rk4", dt=0.001)
    stride = sol.stats["sampling"]["stride"]
    assert sol.t.size - 1 == math.ceil(20000 / stride) and stride > 1
    # The output times are every stride-th of the 20000 steps of 1 ms (to rounding), and the
    # run takes the 20000 steps of the run to t = 20 alone.
    np.testing.assert_allclose(sol.t[:-1], 0.001 * stride * np.arange(sol.t.size - 1), 0, 1e-12)
    alone = ph.simulate(MOMENTS, OMEGA0, [0.0, 20.0], method="rk4", dt=0.001)
    assert sol.stats["steps"] == alone.stats["steps"] == 20000
    np.testing.assert_allclose(sol.omega[-1], alone.omega[-1], rtol=0, atol=1e-12)


def test_dop853_reports_every_accepted_step_as_well():
    sol = ph.simulate(MOMENTS, OMEGA0, 20.0, method="dop853")
    grid = np.linspace(0.0, 20.0, math.ceil(PER_TURN * 20.0 * sol.stats["sampling"]["rate"]
                                            / (2 * np.pi)) + 1)
    assert sol.stats["sampling"]["every_step"]
    assert np.isin(grid, sol.t).all()  # the grid...
    steps = np.setdiff1d(sol.t, grid)  # ... and the end of every accepted step (the last at 20)
    assert steps.size == sol.stats["steps"] - 1
    # dop853 alone to 20 takes the same steps (dense output reaches the grid between them).
    alone = ph.simulate(MOMENTS, OMEGA0, [0.0, 20.0], method="dop853")
    assert alone.stats["steps"] == sol.stats["steps"]
    assert ph.simulate(MOMENTS, OMEGA0, sol.t, method="dop853").omega.tobytes() == (
        sol.omega.tobytes()
    )


def test_an_array_of_times_keeps_its_meaning():
    for t in ([0.0, 20.0], np.array([5.0]), (0.0, 1.0, 1.0, 7.0)):
        sol = ph.simulate(MOMENTS, OMEGA0, t)
        assert sol.t.tolist() == list(np.atleast_1d(t)) and "sampling" not in sol.stats
    # An end time equal to t0: the one output time t0.
    assert ph.simulate(MOMENTS, OMEGA0, 2.0, t0=2.0).t.tolist() == [2.0]


def test_a_long_run_is_capped_and_says_so():
    sol = ph.simulate(MOMENTS, OMEGA0, 1e5, orientation=False)
    assert sol.t.size == 100_001 and sol.stats["sampling"]["capped"]
    assert "capped" in repr(sol)
    batch = ph.simulate(MOMENTS, np.tile(OMEGA0, (50, 1)), 1e5, orientation=False)
    assert batch.t.size == 1_000_000 // 50 and batch.stats["sampling"]["capped"]


def test_the_drift_is_seen_at_every_output_time():
    sol = ph.simulate(MOMENTS, [0.01, 1.0, 0.01], 100.0, method="rk4", dt=0.05)
    energy = sol.energy
    expected = np.max(np.abs(energy - energy[0])) / abs(energy[0])  # numpy, written apart
    assert max_relative_drift(sol)["energy"] == pytest.approx(expected, rel=1e-12)
    ends = ph.simulate(MOMENTS, [0.01, 1.0, 0.01], [0.0, 100.0], method="rk4", dt=0.05)
    # The two ends alone miss most of it (rk4's energy error swings with each flip).
    assert max_relative_drift(ends)["energy"] < 0.5 * expected


# ---------------------------------------------------------------------------------------------
# Dense output of the exact solution
# ---------------------------------------------------------------------------------------------


def test_the_exact_solution_at_other_times_is_simulate_at_them():
    q0 = Rotation.from_euler("ZXZ", [0.3, 0.7, -1.1])
    sol = ph.simulate(MOMENTS, OMEGA0, 30.0, orientation0=q0)
    times = np.linspace(3.0, 4.0, 333)
    assert sol(times) == ph.simulate(MOMENTS, OMEGA0, times, orientation0=q0)
    assert sol(sol.t) == sol and sol(12.5) == ph.simulate(
        MOMENTS, OMEGA0, [12.5], orientation0=q0
    )
    body = ph.Body.cuboid(2.0, [0.3, 0.1, 0.02])
    batch = ph.simulate(body, np.array([OMEGA0, [1.0, 0.1, 0.0]]), 10.0)
    assert batch(times) == ph.simulate(body, np.array([OMEGA0, [1.0, 0.1, 0.0]]), times)
    assert batch[1](times) == ph.simulate(body, [1.0, 0.1, 0.0], times)
    assert pickle.loads(pickle.dumps(sol))(times) == sol(times)
    with pytest.raises(TypeError, match="only the exact solution"):
        ph.simulate(MOMENTS, OMEGA0, 1.0, method="dop853")(0.5)


# ---------------------------------------------------------------------------------------------
# Batches like arrays
# ---------------------------------------------------------------------------------------------


def bodies(n=5):
    rng = np.random.default_rng(29)
    moments = rng.uniform(1.0, 3.0, (n, 3))
    omega0 = rng.normal(size=(n, 3))
    q = rng.normal(size=(n, 4))
    return moments, omega0, q / np.linalg.norm(q, axis=1)[:, None]


@pytest.mark.parametrize("name", list(RUNS))
@pytest.mark.parametrize("end", [4.0, np.linspace(0.0, 4.0, 9)], ids=["end time", "times"])
def test_a_batchs_body_is_that_body_simulated_alone(name, end):
    moments, omega0, q0 = bodies()
    options = RUNS[name]
    sweep = ph.simulate(moments, omega0, end, orientation0=q0, **options)
    assert len(sweep) == 5
    for k in range(-5, 5):
        alone = ph.simulate(moments[k], omega0[k], sweep.t, orientation0=q0[k], **options)
        assert sweep[k] == alone, (name, k)
        assert sweep[np.int64(k)] == alone
    picked = ph.simulate(moments[1:4], omega0[1:4], sweep.t, orientation0=q0[1:4], **options)
    assert sweep[1:4] == picked and len(sweep[1:4]) == 3
    assert sweep[[1, 2, 3]] == picked
    assert sweep[np.array([False, True, True, True, False])] == picked
    assert sweep[::-2] == ph.simulate(
        moments[::-2], omega0[::-2], sweep.t, orientation0=q0[::-2], **options
    )
    assert sweep[1:4][1] == sweep[2]


def test_a_batch_of_one_shared_body_and_its_errors():
    body = ph.Body.cylinder(1.0, 0.1, 0.5)
    omega0 = np.array([[0.1, 0.2, 3.0], [1.0, 0.0, 0.1], [0.0, 2.0, 0.1]])
    sweep = ph.simulate(body, omega0, 3.0)
    assert sweep[2] == ph.simulate(body, omega0[2], sweep.t)
    one = sweep[0]
    with pytest.raises(TypeError, match="no batch"):
        len(one)
    with pytest.raises(TypeError, match="no batch"):
        one[0]
    with pytest.raises(IndexError, match="out of range"):
        sweep[3]
    with pytest.raises(IndexError):
        sweep[[0, 5]]
    with pytest.raises(IndexError):
        sweep[np.array([True, False])]
    for bad in (1.0, "0", np.zeros((1, 1), dtype=int), None):
        with pytest.raises(TypeError, match="index a batch"):
            sweep[bad]


# ---------------------------------------------------------------------------------------------
# The state at t0 is the state given
# ---------------------------------------------------------------------------------------------


def unit_quaternions():
    """Quaternions that are unit in doubles whichever way the norm is summed (the core
    normalizes what it is given: an ulp off the unit sphere, the quaternion at t0 is its
    normalization)."""
    return [
        np.array([0.5, 0.5, 0.5, -0.5]),
        np.array([0.0, 1.0, 0.0, 0.0]),
        np.array([0.0, 0.0, -0.6, 0.8]),
        np.array([0.8, 0.0, 0.0, 0.6]),
    ]


@pytest.mark.parametrize("name", list(RUNS))
def test_the_outputs_at_t0_are_the_inputs_bit_for_bit(name):
    # A batch too (the fixed-step methods run it in SIMD lanes).
    omegas = np.array([OMEGA0, [0.3, -1.7, 0.2], [-2.5, 1e-3, 0.7], [1.0, 2.0, 3.0]])
    batch = ph.simulate(MOMENTS, omegas, 1.0, t0=0.25, **RUNS[name])
    assert batch.omega[:, 0].tobytes() == omegas.tobytes()
    for omega0 in (OMEGA0, np.array([0.3, -1.7, 0.2]), np.array([-2.5, 1e-3, 0.7])):
        for q0 in [None, *unit_quaternions()]:
            sol = ph.simulate(MOMENTS, omega0, 2.0, orientation0=q0, t0=0.5, **RUNS[name])
            assert sol.omega[0].tobytes() == omega0.tobytes(), (name, omega0)
            expected = np.array([0.0, 0.0, 0.0, 1.0]) if q0 is None else q0
            assert sol.quaternion[0].tobytes() == expected.tobytes(), (name, q0)


# ---------------------------------------------------------------------------------------------
# Equality by value
# ---------------------------------------------------------------------------------------------


def test_trajectories_are_equal_by_value():
    t = np.linspace(0.0, 5.0, 11)
    a = ph.simulate(MOMENTS, OMEGA0, t, method="rk4", dt=0.01)
    b = ph.simulate(MOMENTS, OMEGA0, t.copy(), method="rk4", dt=0.01)
    assert a == b and not a != b and a.stats["wall_time"] != b.stats["wall_time"] or a == b
    assert a == pickle.loads(pickle.dumps(a)) == copy.deepcopy(a)
    assert a != ph.simulate(MOMENTS, OMEGA0, t, method="rk4", dt=0.005)  # other numbers
    assert a != ph.simulate(MOMENTS, OMEGA0, t, method="rk4", dt=0.01, orientation=False)
    assert a != ph.simulate(MOMENTS, OMEGA0, t[:-1], method="rk4", dt=0.01)
    assert a != ph.simulate(MOMENTS, np.tile(OMEGA0, (1, 1)), t, method="rk4", dt=0.01)
    assert (a == "a trajectory") is False
    with pytest.raises(TypeError):
        hash(a)
    # One number changed in a copy is seen.
    changed = copy.deepcopy(a)
    changed.energy[3] = np.nextafter(changed.energy[3], np.inf)
    assert changed != a
