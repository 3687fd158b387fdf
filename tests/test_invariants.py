"""polhode.invariants: the drift of T, |L| and L in space, against closed forms written here
(trajectory-like objects built by hand) and against a direct computation on simulated motion."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.invariants import angular_momentum_space, max_relative_drift, relative_drift

T = np.linspace(0.0, 2.0, 9)
KEYS = ["energy", "angular_momentum_norm", "angular_momentum_space"]


def drifting_body(c: float):
    """T = 3 (1 + c t), |L| = 5 (1 - c t / 2) with L in body axes turning about z, and L in space
    of constant norm 2 tilted by the angle c t. The relative drifts are c t, c t / 2 and
    |2 e(ct) - 2 e(0)| / 2 = 2 sin(c t / 2)."""
    energy = 3.0 * (1.0 + c * T)
    unit = np.column_stack([0.6 * np.cos(T), 0.6 * np.sin(T), np.full_like(T, 0.8)])
    l_body = 5.0 * (1.0 - 0.5 * c * T)[:, None] * unit
    l_space = 2.0 * np.column_stack([np.sin(c * T), np.zeros_like(T), np.cos(c * T)])
    expected = {
        "energy": c * T,
        "angular_momentum_norm": 0.5 * c * T,
        "angular_momentum_space": 2.0 * np.sin(0.5 * c * T),
    }
    return energy, l_body, l_space, expected


def spun_up_from_rest(alpha: float, inertia: float = 2.0):
    """A body at rest spun up about its principal axis x by a constant torque: L = (I alpha t,
    0, 0) in both frames, T = I alpha^2 t^2 / 2. Every invariant starts at zero, so the drifts
    are the absolute errors: T itself, |L| and |L|."""
    energy = 0.5 * inertia * alpha**2 * T**2
    l_vec = np.column_stack([inertia * alpha * T, np.zeros_like(T), np.zeros_like(T)])
    expected = {
        "energy": energy,
        "angular_momentum_norm": inertia * alpha * T,
        "angular_momentum_space": inertia * alpha * T,
    }
    return energy, l_vec, l_vec, expected


def trajectory(energy, l_body, l_space):
    return SimpleNamespace(
        energy=energy, angular_momentum_body=l_body, angular_momentum_space=l_space
    )


def assert_drifts(got, expected):
    assert list(got) == list(expected)
    for key in expected:
        assert got[key].shape == np.shape(expected[key]), key
        np.testing.assert_allclose(got[key], expected[key], rtol=1e-13, atol=1e-15, err_msg=key)


def test_one_body_against_the_closed_form():
    energy, l_body, l_space, expected = drifting_body(0.25)
    got = relative_drift(trajectory(energy, l_body, l_space))
    assert_drifts(got, expected)
    assert all(got[key][0] == 0.0 for key in KEYS)
    # L in space keeps its norm here: its drift is that of the vector, not of the norm.
    assert got["angular_momentum_space"][-1] == pytest.approx(2.0 * np.sin(0.25))
    biggest = max_relative_drift(trajectory(energy, l_body, l_space))
    assert biggest == pytest.approx(
        {"energy": 0.5, "angular_momentum_norm": 0.25, "angular_momentum_space": 2 * np.sin(0.25)},
        rel=1e-13,
    )
    assert all(isinstance(v, float) for v in biggest.values())


def test_a_decrease_counts_as_much_as_an_increase():
    energy, l_body, l_space, expected = drifting_body(-0.25)
    expected = {key: np.abs(value) for key, value in expected.items()}
    assert_drifts(relative_drift(trajectory(energy, l_body, l_space)), expected)


def test_zero_initial_value_gives_the_absolute_error():
    energy, l_body, l_space, expected = spun_up_from_rest(0.5)
    assert_drifts(relative_drift(trajectory(energy, l_body, l_space)), expected)
    # A body at rest throughout: zero drift, without a division by zero (warnings are errors).
    rest = trajectory(np.zeros(4), np.zeros((4, 3)), np.zeros((4, 3)))
    for key, values in relative_drift(rest).items():
        np.testing.assert_array_equal(values, np.zeros(4), err_msg=key)


def test_batch_body_by_body():
    bodies = [drifting_body(0.25), drifting_body(-0.1), spun_up_from_rest(0.5)]
    energy, l_body, l_space = (np.stack([b[k] for b in bodies]) for k in range(3))
    assert energy.shape == (3, len(T)) and l_space.shape == (3, len(T), 3)
    expected = {key: np.abs(np.stack([b[3][key] for b in bodies])) for key in KEYS}
    traj = trajectory(energy, l_body, l_space)
    assert_drifts(relative_drift(traj), expected)
    biggest = max_relative_drift(traj)
    assert biggest == pytest.approx({key: expected[key].max() for key in KEYS}, rel=1e-13)


def test_without_orientation_the_space_entry_is_left_out():
    energy, l_body, _, expected = drifting_body(0.25)
    del expected["angular_momentum_space"]
    traj = trajectory(energy, l_body, None)
    assert angular_momentum_space(traj) is None
    assert_drifts(relative_drift(traj), expected)
    assert list(max_relative_drift(traj)) == ["energy", "angular_momentum_norm"]


@pytest.mark.parametrize("orientation", [True, False])
def test_simulated_batch_against_a_direct_computation(orientation):
    moments = [[1.0, 2.0, 3.0], [2.0, 2.5, 4.0]]
    omega0 = [[0.1, 1.0, 0.2], [1.0, -0.3, 0.5]]
    times = np.linspace(0.0, 20.0, 201)
    traj = ph.simulate(moments, omega0, times, method="rk4", dt=0.05, orientation=orientation)
    got = relative_drift(traj)
    for k in range(2):
        w = np.asarray(traj.omega[k])
        i = np.asarray(moments[k])
        # T and L from omega and the moments, not from the trajectory's own fields
        energy = 0.5 * (w * w) @ i
        l_body = w * i
        norm = np.sqrt((l_body**2).sum(axis=1))
        np.testing.assert_allclose(
            got["energy"][k], np.abs(energy / energy[0] - 1.0), rtol=1e-9, atol=1e-15
        )
        np.testing.assert_allclose(
            got["angular_momentum_norm"][k], np.abs(norm / norm[0] - 1.0), rtol=1e-9, atol=1e-15
        )
        if orientation:
            l_space = Rotation.from_quat(traj.quaternion[k]).apply(l_body)
            want = np.sqrt(((l_space - l_space[0]) ** 2).sum(axis=1)) / norm[0]
            np.testing.assert_allclose(
                got["angular_momentum_space"][k], want, rtol=1e-6, atol=1e-15
            )
        else:
            assert "angular_momentum_space" not in got
    # rk4 conserves nothing exactly: the drift is real, not round-off
    assert max_relative_drift(traj)["energy"] > 1e-10


def test_an_empty_batch_drifts_by_nothing():
    """max_relative_drift of a batch of no bodies raised numpy's 'zero-size array to reduction
    operation maximum'."""
    traj = ph.simulate([1.0, 2.0, 3.0], np.zeros((0, 3)), 1.0)
    assert max_relative_drift(traj) == {
        "energy": 0.0,
        "angular_momentum_norm": 0.0,
        "angular_momentum_space": 0.0,
    }
