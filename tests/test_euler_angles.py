"""Trajectory.euler_angles against scipy's per-frame Rotation.as_euler: equal modulo 2 pi, and
continuous in time (no 2 pi jumps), with the gimbal lock treated as documented."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode import _core
from polhode.simulation import Trajectory

SEQUENCES = ["ZXZ", "ZYZ", "XYX", "zxz", "ZYX", "XYZ", "xyz", "zyx"]


def _wrapped(x):
    return (x + np.pi) % (2 * np.pi) - np.pi


def _scipy(quaternion, seq):
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Gimbal lock", category=UserWarning)
        return Rotation.from_quat(quaternion).as_euler(seq)


@pytest.fixture(scope="module")
def tumbling():
    """An asymmetric body tumbling for many turns from a tilted orientation."""
    times = np.linspace(0.0, 60.0, 3001)
    return ph.simulate((1.0, 2.0, 3.0), (0.4, 1.0, 0.3), times,
                       orientation0=Rotation.from_rotvec([0.3, -0.2, 0.5]))


@pytest.mark.parametrize("seq", SEQUENCES)
def test_equal_to_scipy_modulo_two_pi_and_continuous(tumbling, seq):
    got = tumbling.euler_angles(seq)
    reference = _scipy(tumbling.quaternion, seq)
    assert got.shape == (3001, 3)
    # Away from a lock each frame has one set of angles (the middle one in scipy's range).
    np.testing.assert_allclose(_wrapped(got - reference), 0.0, atol=1e-12)
    np.testing.assert_allclose(got[:, 1], reference[:, 1], atol=1e-12)
    # Continuous: every step is far below pi (the body turns by about 0.04 rad a step).
    assert np.max(np.abs(np.diff(got, axis=0))) < 0.5
    # and not stuck in [-pi, pi]: the body keeps turning, so some angle leaves that range.
    assert np.max(np.abs(got)) > 4 * np.pi
    # The angles give back the orientation.
    back = Rotation.from_euler(seq, got)
    assert np.max((back * tumbling.orientation.inv()).magnitude()) < 1e-12
    np.testing.assert_allclose(tumbling.euler_angles(seq, degrees=True), np.degrees(got))


def test_zxz_about_l_are_precession_nutation_spin():
    """With space z along L, ZXZ angles of the body's largest axis: the first is the
    precession (mean rate precession_rate_space), the second the nutation (within
    nutation_angle), the third the spin."""
    moments, omega = (1.0, 2.0, 3.0), np.array([0.2, 0.3, 1.0])
    a = ph.analyze(moments, omega)
    ell = np.asarray(moments) * omega
    # An orientation taking L (body axes) to space z.
    turn, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [ell])
    times = np.linspace(0.0, 8 * a.period, 4001)
    sol = ph.simulate(moments, omega, times, orientation0=turn)
    np.testing.assert_allclose(sol.angular_momentum_space[:, :2], 0.0, atol=1e-12)
    phi, theta, _ = sol.euler_angles("ZXZ").T
    # At whole periods the precession has turned by the mean rate times the time.
    whole = np.arange(0, 4001, 500)
    np.testing.assert_allclose(phi[whole] - phi[0], a.precession_rate_space * times[whole],
                               rtol=1e-12, atol=1e-12)
    lo, hi = a.nutation_angle
    assert lo - 1e-12 <= theta.min() and theta.max() <= hi + 1e-12
    assert theta.min() < lo + 1e-4 and theta.max() > hi - 1e-4


def _trajectory(rotations: Rotation, times) -> Trajectory:
    # Only the orientation matters here: every other quantity of the core's table left out.
    others = {row["name"]: None for row in _core.QUANTITIES}
    return Trajectory(**{**others, "quaternion": rotations.as_quat()}, t=np.asarray(times),
                      moments=np.ones(3), stats={})


def test_steady_rotation_at_the_lock():
    """Turning about space z with body z along it: ZXZ is locked at every time. The third angle
    stays 0 and the first carries the whole turn, unwrapped."""
    times = np.linspace(0.0, 20.0, 401)
    sol = ph.simulate((1.0, 1.0, 2.0), (0.0, 0.0, 1.5), times)
    got = sol.euler_angles("ZXZ")
    np.testing.assert_allclose(got[:, 0], 1.5 * times, rtol=1e-13, atol=1e-13)
    assert np.all(got[:, 1] == 0.0) and np.all(got[:, 2] == 0.0)


@pytest.mark.parametrize("seq", ["ZXZ", "ZYX", "zyx", "XYX"])
@pytest.mark.parametrize("end", [0, 1])
def test_crossing_the_lock_keeps_the_combination_continuous(seq, end):
    """A motion through the lock at an output time: (a, b, c) smooth in time with b passing
    through an end of its range. Where locked, the third angle keeps its previous value; the
    combination that sets the rotation stays continuous through the lock and the angles give
    back the rotation everywhere."""
    times = np.linspace(-1.0, 1.0, 201)  # t = 0 is an output time
    proper = seq[0].lower() == seq[2].lower()
    lock = (0.0, np.pi)[end] if proper else (-np.pi / 2, np.pi / 2)[end]
    first, third = 0.4 + 3.0 * times, -1.1 + 2.0 * times
    middle = lock + 0.5 * times  # crosses the end at t = 0
    truth = Rotation.from_euler(seq, np.column_stack([first, middle, third]))
    got = _trajectory(truth, times).euler_angles(seq)
    assert np.max((Rotation.from_euler(seq, got) * truth.inv()).magnitude()) < 1e-9
    k = 100
    assert abs(got[k, 1] - lock) <= 1e-12
    assert got[k, 2] == got[k - 1, 2]  # held at the lock
    # The rotation at the lock depends on first + s third alone (s = +-1 by end and sequence).
    signs = [s for s in (1.0, -1.0)
             if np.max((Rotation.from_euler(seq, [[got[k, 0] + 0.3, lock, got[k, 2] - 0.3 * s]])
                        * truth[k].inv()).magnitude()) < 1e-9]
    assert len(signs) == 1
    combination = got[:, 0] + signs[0] * got[:, 2]
    # Its true rate is 3 +- 2; a step of 0.01 moves it by at most 0.05 (no turn anywhere).
    assert np.max(np.abs(np.diff(combination))) < 0.06
    # Each angle jumps by at most pi (the branch of scipy's range, at the crossing): no 2 pi.
    assert np.max(np.abs(np.diff(got, axis=0))) < np.pi + 0.1
    # Away from the lock each step is small.
    steps = np.abs(np.diff(got, axis=0)).max(axis=1)
    assert np.all(np.delete(steps, [k - 1, k]) < 0.06)


def test_near_the_lock_the_combination_stays_continuous():
    """Passing near the lock (nutation down to 1e-4 rad) without reaching it: the first and
    third angles swing by about pi within a few steps, their sum stays smooth."""
    times = np.linspace(-1.0, 1.0, 2001)
    middle = np.hypot(1e-4, 0.3 * times)  # min 1e-4 at t = 0, never locked
    first, third = 1.0 + np.arctan2(times, 1e-3), 0.5 - np.arctan2(times, 1e-3)
    truth = Rotation.from_euler("ZXZ", np.column_stack([first + times, middle, third]))
    got = _trajectory(truth, times).euler_angles("ZXZ")
    np.testing.assert_allclose(_wrapped(got - _scipy(truth.as_quat(), "ZXZ")), 0.0, atol=1e-9)
    total = got[:, 0] + got[:, 2]
    np.testing.assert_allclose(total - total[0], times - times[0], atol=1e-9)


def test_a_batch_keeps_its_leading_dimension():
    times = np.linspace(0.0, 5.0, 51)
    omega0 = [[0.1, 1.0, 0.2], [1.0, 0.1, 0.3]]
    sol = ph.simulate((1.0, 2.0, 3.0), omega0, times)
    got = sol.euler_angles("ZYX")
    assert got.shape == (2, 51, 3)
    for k in range(2):
        single = ph.simulate((1.0, 2.0, 3.0), omega0[k], times)
        np.testing.assert_array_equal(got[k], single.euler_angles("ZYX"))


def test_an_empty_batch_has_no_angles():
    """N = 0 bodies: angles of shape (0, M, 3) (np.stack of nothing raised), the axes still
    checked."""
    sol = ph.simulate((1.0, 2.0, 3.0), np.zeros((0, 3)), [0.0, 1.0])
    assert sol.euler_angles().shape == (0, 2, 3)
    with pytest.raises(ph.ArgumentError, match="seq"):
        sol.euler_angles("ABC")


def test_errors():
    sol = ph.simulate((1.0, 2.0, 3.0), (0.1, 1.0, 0.2), 1.0)
    with pytest.raises(ph.ArgumentError, match="seq") as error:
        sol.euler_angles("ZZX")
    assert error.value.argument == "seq"
    with pytest.raises(TypeError, match="seq"):
        sol.euler_angles(3)
    bare = ph.simulate((1.0, 2.0, 3.0), (0.1, 1.0, 0.2), 1.0, orientation=False)
    with pytest.raises(ph.ArgumentError, match="orientation") as error:
        bare.euler_angles()
    assert error.value.argument == "orientation"
