"""Bodies with internal rotors (polhode.rotors) against independent references.

- every case against scipy's DOP853 (rtol 1e-12) on the full system written apart from the core
  (``reference_rotors.gyrostat``: the body's own axes, relative wheel rates, a mass matrix);
- the total angular momentum in space conserved without external torque (to the method's
  error: dop853's tolerance, rk4's O(dt^4));
- a damper: the energy falls monotonically (dT/dt = -c |s - w|^2) and a spin about the smallest
  axis ends about the largest, with |L| fixed: T = |L|^2 / (2 I3);
- a wheel spun up by its motor turns a body at rest by -J/I times the wheel's turn relative to
  it (H = 0 throughout).
"""

from __future__ import annotations

import numpy as np
import pytest
from reference_rotors import DamperRef, WheelRef, gyrostat
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.rotors import SphericalDamper, Wheel

# A body given by its tensor in its own (non-principal) axes.
TENSOR = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix() @ np.diag([2.0, 3.0, 4.0])
TENSOR = TENSOR @ Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix().T
Q0 = Rotation.from_rotvec([0.1, 0.7, -0.4])


def _compare(sol, ref, scale, rtol=1e-9):
    omega, q, rates, l_space, energy = ref
    np.testing.assert_allclose(sol.omega, omega, rtol=0, atol=rtol * scale)
    # q and -q are one rotation: compare the rotations.
    turn = Rotation.from_quat(sol.quaternion) * Rotation.from_quat(q).inv()
    assert np.max(turn.magnitude()) < rtol * 10
    np.testing.assert_allclose(sol.rotor_rates, rates, rtol=0, atol=rtol * scale)
    np.testing.assert_allclose(sol.angular_momentum_space, l_space, rtol=0,
                               atol=rtol * np.max(np.abs(l_space)))
    np.testing.assert_allclose(sol.energy, energy, rtol=rtol)


CASES = {
    "wheel, constant motor": (
        [Wheel([0.2, -0.3, 1.0], 0.05, rate0=3.0, torque=0.02)],
        [WheelRef([0.2, -0.3, 1.0], 0.05, 3.0, lambda t, w, r: 0.02)],
        None,
    ),
    "damper, near the smallest axis": (
        [SphericalDamper(0.1, 0.05)],
        [DamperRef(0.1, 0.05)],
        None,
    ),
    "two wheels (schedule, function), a damper, a torque": (
        [
            Wheel([1.0, 0.0, 0.0], 0.04, rate0=-2.0, torque=[(1.0, 0.03), (4.0, -0.01)]),
            SphericalDamper(0.08, 0.3),
            Wheel([0.0, 1.0, 1.0], 0.03, torque=lambda t, w, rate: -0.01 * rate + 0.002 * w[0]),
        ],
        [
            WheelRef([1.0, 0.0, 0.0], 0.04, -2.0,
                     lambda t, w, r: 0.0 if t < 1.0 else (0.03 if t < 4.0 else -0.01)),
            DamperRef(0.08, 0.3),
            WheelRef([0.0, 1.0, 1.0], 0.03, 0.0, lambda t, w, r: -0.01 * r + 0.002 * w[0]),
        ],
        ph.torque.BodyFixed([0.01, -0.02, 0.005]),
    ),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_against_scipy(case, method):
    rotors, reference, torque = CASES[case]
    omega0 = np.array([0.9, 0.1, -0.2])
    times = np.linspace(0.0, 8.0, 33)
    options = {"rtol": 1e-12} if method == "dop853" else {"dt": 2e-3}
    sol = ph.simulate(TENSOR, omega0, times, orientation0=Q0, rotors=rotors, torque=torque,
                      method=method, **options)
    assert sol.stats["method"] == method
    assert sol.rotor_rates.shape == (33, len(rotors), 3)
    tau = None if torque is None else (lambda t, w, q: torque.torque)
    ref = gyrostat(TENSOR, omega0, Q0.as_quat(), times, reference, torque=tau,
                   breaks=(1.0, 4.0))
    # Measured: dop853 (rtol 1e-12) and rk4 (dt = 2e-3) agree with scipy (rtol 1e-12) to at most
    # 6e-11 relative (the rotor rates; omega, L and T to 3e-12); bound 2e-10.
    _compare(sol, ref, scale=np.max(np.abs(ref[2])) + 1.0, rtol=2e-10)


def _momentum_drift(method, **options):
    rotors = [
        Wheel([0.2, -0.3, 1.0], 0.05, rate0=3.0, torque=[(0.0, 0.02), (5.0, -0.02)]),
        SphericalDamper(0.1, 0.05),
    ]
    times = np.linspace(0.0, 20.0, 201)
    sol = ph.simulate(TENSOR, [0.9, 0.1, -0.2], times, orientation0=Q0, rotors=rotors,
                      method=method, **options)
    ell = sol.angular_momentum_space
    # The rotors did exchange momentum with the body: L in the body moved.
    body = sol.angular_momentum_body
    assert np.max(np.linalg.norm(body - body[0], axis=1)) > 0.1 * np.linalg.norm(body[0])
    return np.max(np.linalg.norm(ell - ell[0], axis=1)) / np.linalg.norm(ell[0])


@pytest.mark.parametrize("rtol", [1e-12, 1e-10, 1e-8])
def test_total_angular_momentum_in_space_is_conserved_by_dop853(rtol):
    """Without external torque the total L in space is constant whatever the motors and the
    damper do. dop853 does not conserve it by construction: it keeps it to its tolerance, the
    local errors of a few dozen steps adding up (measured 11 to 15 rtol over 20 time units;
    bound 50 rtol)."""
    assert _momentum_drift("dop853", rtol=rtol) <= 50 * rtol


def test_total_angular_momentum_in_space_is_conserved_by_rk4_to_fourth_order():
    """rk4 keeps L to O(dt^4): halving dt divides the drift by 16 (measured 15.9 to 16.3)."""
    coarse, fine = _momentum_drift("rk4", dt=1e-2), _momentum_drift("rk4", dt=5e-3)
    assert coarse <= 5e-11
    assert 12 <= coarse / fine <= 20, coarse / fine


def test_damper_takes_a_minor_axis_spin_to_the_major_axis():
    moments = np.array([1.0, 2.0, 3.0])
    omega0 = np.array([1.0, 0.05, 0.05])
    damper = SphericalDamper(0.05, 0.02)
    times = np.linspace(0.0, 3000.0, 6001)
    sol = ph.simulate(moments, omega0, times, rotors=[damper], rtol=1e-11)
    energy = sol.energy
    # dT/dt = -c |s - w|^2 <= 0: monotone, to the integration's error on T (~1e-11 T).
    assert np.all(np.diff(energy) <= 1e-11 * energy[0])
    assert energy[-1] < 0.4 * energy[0]
    ell = np.linalg.norm(sol.angular_momentum_space, axis=1)
    # dop853 keeps |L| to its tolerance per step; over ~1e4 steps at rtol 1e-11 the local errors
    # add up to 1.9e-10 (measured): bound 100 rtol.
    np.testing.assert_allclose(ell, ell[0], rtol=1e-9)
    # The end: rotation about the largest axis with the sphere along, T = |L|^2 / (2 I3).
    assert energy[-1] == pytest.approx(ell[0] ** 2 / (2 * moments[2]), rel=1e-6)
    w = sol.omega[-1]
    assert abs(w[2]) == pytest.approx(ell[0] / moments[2], rel=1e-6)
    assert np.hypot(w[0], w[1]) < 1e-3 * abs(w[2])
    np.testing.assert_allclose(sol.rotor_rates[-1], 0.0, atol=1e-5)


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_wheel_spun_up_turns_the_body(method):
    """A body at rest, its wheel on the axis of largest moment spun up by a motor for 1 s then
    coasting: H = 0 throughout, so I3 w3 + J W = 0 and the body turns by -J/I3 times the
    wheel's turn relative to it; the closed form of that turn is
    -(g / (I3 - J)) (T1^2 / 2 + T1 (t - T1))."""
    moments = (1.0, 2.0, 3.0)
    j, g, t1 = 0.1, 0.05, 1.0
    wheel = Wheel([0.0, 0.0, 1.0], j, torque=[(0.0, g), (t1, 0.0)])
    times = np.linspace(0.0, 3.0, 31)
    options = {"rtol": 1e-12} if method == "dop853" else {"dt": 1e-3}
    sol = ph.simulate(moments, [0.0, 0.0, 0.0], times, rotors=[wheel], method=method, **options)
    a33 = moments[2] - j
    turn = np.where(times < t1, times**2 / 2, t1**2 / 2 + t1 * (times - t1)) * g / a33
    angles = sol.euler_angles("ZYX")
    np.testing.assert_allclose(angles[:, 0], -turn, atol=1e-12)
    np.testing.assert_allclose(angles[:, 1:], 0.0, atol=1e-14)
    # The wheel's own turn relative to the body, from its rate: W = h (1/J + 1/A33).
    rate = sol.rotor_rates[:, 0, 2]
    h = np.where(times < t1, g * times, g * t1)
    np.testing.assert_allclose(rate, h * (1 / j + 1 / a33), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(sol.omega[:, 2], -h / a33, atol=1e-14)
    # The ratio of the turns is -J / I3 (I3 the locked moment).
    wheel_turn = turn * a33 * (1 / j + 1 / a33)
    np.testing.assert_allclose(-turn[1:] / wheel_turn[1:], -j / moments[2], rtol=1e-12)
    # Zero but for round-off: A w + h a cancels terms of size h = 0.05 (1e-17 each), over up to
    # 3000 rk4 steps: 5e-14.
    np.testing.assert_allclose(sol.angular_momentum_space, 0.0, atol=5e-14)
    # The energy is the motor's work: the integral of g W.
    assert sol.energy[10] == pytest.approx(0.5 * h[10] ** 2 * (1 / j + 1 / a33), rel=1e-12)


def test_a_wheel_at_rest_is_part_of_the_rigid_body():
    """Locked convention: the body's inertia includes the wheel. A wheel without motor on a
    principal axis of a steady spin never turns relative to the body: the motion, L and T are
    those of the rigid body I."""
    times = np.linspace(0.0, 10.0, 11)
    steady = ph.simulate((1.0, 2.0, 3.0), [0.0, 0.0, 2.0], times, rtol=1e-12,
                         rotors=[Wheel([0.0, 0.0, 1.0], 0.2)])
    np.testing.assert_allclose(steady.omega, [[0.0, 0.0, 2.0]] * 11, atol=1e-13)
    np.testing.assert_allclose(steady.rotor_rates, 0.0, atol=1e-13)
    np.testing.assert_allclose(steady.energy, 0.5 * 3.0 * 4.0, rtol=1e-13)
    np.testing.assert_allclose(steady.angular_momentum_body, [[0.0, 0.0, 6.0]] * 11, rtol=1e-13)
    # Off the steady spin the wheel (constant axial momentum, no motor) is dragged relative to
    # the body, but the totals start as the rigid body's: the same L in space throughout.
    omega0 = [0.3, 1.0, 0.2]
    rigid = ph.simulate(TENSOR, omega0, times, orientation0=Q0, method="exact")
    wheel = ph.simulate(TENSOR, omega0, times, orientation0=Q0, rtol=1e-12,
                        rotors=[Wheel([0.0, 0.0, 1.0], 0.2)])
    # dop853 at rtol 1e-12 keeps L to 50 rtol (test above).
    scale = np.linalg.norm(rigid.angular_momentum_space[0])
    np.testing.assert_allclose(wheel.angular_momentum_space, rigid.angular_momentum_space,
                               rtol=0, atol=50e-12 * scale)
    assert wheel.energy[0] == pytest.approx(rigid.energy[0], rel=1e-15)


def test_a_batch_is_each_body_alone():
    rotors = [Wheel([0.0, 1.0, 0.0], 0.05, rate0=1.0), SphericalDamper(0.05, 0.1)]
    omega0 = np.array([[1.0, 0.1, 0.1], [0.1, 1.0, 0.3], [0.2, 0.1, 1.0]])
    times = np.linspace(0.0, 5.0, 6)
    batch = ph.simulate((1.0, 2.0, 3.0), omega0, times, rotors=rotors)
    assert batch.rotor_rates.shape == (3, 6, 2, 3)
    for k in range(3):
        alone = ph.simulate((1.0, 2.0, 3.0), omega0[k], times, rotors=rotors)
        np.testing.assert_array_equal(batch.omega[k], alone.omega)
        np.testing.assert_array_equal(batch.rotor_rates[k], alone.rotor_rates)
        np.testing.assert_array_equal(batch.energy[k], alone.energy)


@pytest.mark.parametrize("k", [-1000, -600, 400])
def test_free_wheels_at_rates_far_from_one_are_the_scaled_run(k):
    """Free wheels (no motor torque, no damper, no torque) keep the equations homogeneous:
    (I, s w, s W) at t is s times (I, w, W) at s t. rk4 gives the same bits (every product the
    exact image by a power of two), dop853 the same to its tolerance; before, the products of
    the rates underflowed below about 1e-154 and w stayed constant."""
    s = 2.0**k
    t = np.linspace(0.0, 20.0, 5)
    w0 = np.array([0.3, 1.0, 0.2])

    def run(scale, method):
        wheel = Wheel([1.0, 1.0, 0.0], inertia=0.1, rate0=0.5 * scale)
        return ph.simulate(
            [1.0, 2.0, 3.0], w0 * scale, t / scale, rotors=[wheel], method=method,
            dt=0.01 / scale,
        )

    base, a = run(1.0, "rk4"), run(s, "rk4")
    np.testing.assert_array_equal(a.omega / s, base.omega)
    np.testing.assert_array_equal(a.rotor_rates / s, base.rotor_rates)
    np.testing.assert_array_equal(a.quaternion, base.quaternion)
    base, a = run(1.0, "dop853"), run(s, "dop853")
    assert np.abs(a.omega / s - base.omega).max() <= 1e-8
    assert np.abs(a.rotor_rates / s - base.rotor_rates).max() <= 1e-8


def test_without_rotors_there_are_no_rotor_rates():
    sol = ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0)
    assert sol.rotor_rates is None
    sol = ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0, rotors=[])
    assert sol.rotor_rates is None and sol.stats["method"] == "exact"


@pytest.mark.parametrize("method", ["exact", "splitting", "midpoint"])
def test_methods_that_cannot_take_rotors(method):
    with pytest.raises(ph.ArgumentError, match="rotors") as error:
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0, method=method, dt=0.1,
                    rotors=[SphericalDamper(0.1, 0.1)])
    assert error.value.argument == "rotors"
    assert "dop853" in str(error.value)


@pytest.mark.parametrize(("make", "argument", "kind"), [
    (lambda: Wheel([0.0, 0.0, 0.0], 0.1), "axis", ph.ArgumentError),
    (lambda: Wheel([0.0, np.nan, 1.0], 0.1), "axis", ph.NonFiniteError),
    (lambda: Wheel([0.0, 0.0, 1.0], 0.0), "inertia", ph.NonPositiveError),
    (lambda: Wheel([0.0, 0.0, 1.0], 0.1, rate0=np.inf), "rate0", ph.NonFiniteError),
    (lambda: Wheel([0.0, 0.0, 1.0], 0.1, torque=np.nan), "torque", ph.NonFiniteError),
    (lambda: Wheel([0.0, 0.0, 1.0], 0.1, torque=[(1.0, 0.1), (0.5, 0.2)]), "torque",
     ph.ArgumentError),
    (lambda: Wheel([0.0, 0.0, 1.0], 0.1, torque=[1.0, 2.0, 3.0]), "torque", ph.ShapeError),
    (lambda: SphericalDamper(-1.0, 0.1), "inertia", ph.NonPositiveError),
    (lambda: SphericalDamper(1.0, -0.1), "damping", ph.ArgumentError),
])
def test_bad_rotors_fail_where_they_are_made(make, argument, kind):
    with pytest.raises(kind) as error:
        make()
    assert error.value.argument == argument


def test_rotor_inertia_must_lie_inside_the_body():
    with pytest.raises(ph.ArgumentError, match="positive definite") as error:
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[Wheel([1.0, 0.0, 0.0], 1.0)])
    assert error.value.argument == "rotors"
    with pytest.raises(ph.ArgumentError, match="positive definite"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[SphericalDamper(0.6, 0.1), SphericalDamper(0.5, 0.1)])
    # Positive but below the threshold, which the message states (it read as a contradiction:
    # "must be positive definite; its smallest eigenvalue is 9.99e-16").
    with pytest.raises(ph.ArgumentError, match=r"above 1e-12 times the largest .* \(3e-12\)"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[Wheel([1.0, 0.0, 0.0], 1.0 - 1e-15)])


def test_wrong_types_and_raising_functions():
    with pytest.raises(TypeError, match="rotors"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0, rotors=[ph.torque.BodyFixed([0, 0, 1])])
    with pytest.raises(TypeError, match="rotors"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0, rotors="wheel")

    class Boom(Exception):
        pass

    def motor(t, w, rate):
        if t > 0.5:
            raise Boom("motor failed")
        return 0.0

    with pytest.raises(Boom, match="motor failed"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[Wheel([0.0, 0.0, 1.0], 0.1, torque=motor)])
    with pytest.raises(TypeError, match="number"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[Wheel([0.0, 0.0, 1.0], 0.1, torque=lambda t, w, r: "x")])
    with pytest.raises(ph.NonFiniteError, match="torque"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[Wheel([0.0, 0.0, 1.0], 0.1, torque=lambda t, w, r: np.inf)])
    # Not real numbers: TypeError naming the torque (were a bare ValueError or float()'s own
    # TypeError); an integer beyond double precision is not finite (was OverflowError).
    for value in (np.array("a"), np.array(1j), np.array(None, dtype=object), 1j, True):
        with pytest.raises(TypeError, match="torque"):
            ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                        rotors=[Wheel([0.0, 0.0, 1.0], 0.1, torque=lambda t, w, r, v=value: v)])
    with pytest.raises(ph.NonFiniteError, match="torque"):
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0,
                    rotors=[Wheel([0.0, 0.0, 1.0], 0.1, torque=lambda t, w, r: 10**400)])
    with pytest.raises(TypeError, match="torque"):
        Wheel([0.0, 0.0, 1.0], 0.1, torque=True)


@pytest.mark.parametrize("axis", [(0.0, 0.0, 1e-300), (1e300, 1e300, 0.0), (0.0, 0.0, 5e-324)])
def test_a_wheel_axis_is_a_direction_of_any_size(axis):
    """The axis is normalised: one of 1e-300 (its norm underflowed) or 1e300 (overflowed) was
    refused as 'expected a non-zero vector'. The same bits as the unit axis."""
    unit = tuple(float(np.sign(x)) for x in axis)
    runs = [
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], [0.0, 1.0],
                    rotors=[Wheel(a, 0.1, rate0=2.0)])
        for a in (axis, unit)
    ]
    np.testing.assert_array_equal(runs[0].omega, runs[1].omega)
    np.testing.assert_array_equal(runs[0].rotor_rates, runs[1].rotor_rates)


def test_overflowing_rotors_and_progress():
    for rate0, inertia in [(1e308, 10.0), (1e200, 0.1)]:
        with pytest.raises(ph.ArgumentError, match="overflows") as error:
            ph.simulate((100.0, 200.0, 300.0), [0.1, 1.0, 0.1], 1.0,
                        rotors=[Wheel([0.0, 0.0, 1.0], inertia, rate0=rate0)])
        assert error.value.argument == "rotors"
    with pytest.raises(ph.ArgumentError, match="at most 24") as error:
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], 1.0, rotors=[SphericalDamper(0.01, 0.1)] * 9)
    assert error.value.argument == "rotors"
    # Progress is reported every 50 ms of a run and at its end (2e6 rk4 steps take well over
    # 100 ms; the dop853 run may be quicker than one report).
    for method, options, reports in [("rk4", {"dt": 0.01}, 3), ("dop853", {}, 1)]:
        seen = []
        ph.simulate((1.0, 2.0, 3.0), [0.1, 1.0, 0.1], [0.0, 2e4], method=method,
                    rotors=[SphericalDamper(0.1, 0.01)], progress=seen.append, **options)
        assert seen[-1] == 1.0 and len(seen) >= reports and np.all(np.diff(seen) >= 0)


def test_rotors_are_immutable_values():
    wheel = Wheel([0.0, 0.0, 2.0], 0.1, torque=[(0.0, 1.0)])
    with pytest.raises(AttributeError):
        wheel.inertia = 2.0  # type: ignore[misc]
    with pytest.raises(ValueError):
        wheel.axis[0] = 1.0
    with pytest.raises(ValueError):
        wheel.torque[0, 0] = 1.0
    assert "Wheel([0.0, 0.0, 2.0]" in repr(wheel)


def _fitted_nutation_rate(moments, omega0, damper, t_end, axis):
    """Half the slope of log |2 T I_k - |L|^2| (a quadratic in the nutation amplitude, zero on
    the steady spin) over the last 80% of a run, the sphere's fast transient gone."""
    times = np.linspace(0.0, t_end, 4001)
    sol = ph.simulate(moments, omega0, times, rotors=[damper], rtol=1e-12)
    ell2 = np.sum(sol.angular_momentum_space**2, axis=1)
    gap = np.abs(2 * sol.energy * sorted(moments)[axis] - ell2)
    late = times > 0.2 * t_end
    return 0.5 * np.polyfit(times[late], np.log(gap[late]), 1)[0]


@pytest.mark.parametrize(("label", "moments", "omega0", "axis", "rtol"), [
    # Decay about the largest axis: the gap falls from 2e-5 to 5e-8 of |L|^2, deep in the
    # linear regime (measured agreement 1e-6).
    ("symmetric, largest axis", (2.0, 2.0, 3.0), (0.01, 0.0, 1.0), 2, 1e-4),
    ("asymmetric, largest axis", (1.0, 2.0, 3.0), (0.01, 0.0, 1.0), 2, 1e-4),
    ("asymmetric, largest axis, both", (1.5, 2.0, 3.0), (0.01, 0.01, 1.0), 2, 1e-4),
    # Growth about the smallest axis: the gap grows from 2e-6 to 8e-4 of |L|^2 over the run,
    # and the nonlinear terms of that order bend the fit (measured 2e-4).
    ("symmetric, smallest axis", (1.0, 2.0, 2.0), (1.0, 0.001, 0.0), 0, 2e-3),
    ("asymmetric, smallest axis", (1.0, 2.0, 3.0), (1.0, 0.001, 0.0), 0, 2e-3),
])
def test_nutation_rate_against_the_simulation(label, moments, omega0, axis, rtol):
    damper = SphericalDamper(0.05, 0.02)
    rate = ph.rotors.nutation_rate(moments, omega0, damper)
    assert (rate < 0) == (axis == 2)
    fitted = _fitted_nutation_rate(moments, omega0, damper, 3 / abs(rate), axis)
    assert fitted == pytest.approx(rate, rel=rtol)


@pytest.mark.parametrize("inertia", [3.0, 3.5, 3.9])
def test_nutation_rate_with_a_heavy_sphere(inertia):
    """A sphere of J above about 2 I_t - I_s: the sphere's own mode decays slower than the
    nutation, and the rate is its. The closed form took the nutation's root (-0.909 for J =
    3.9, a time constant of 1.1 s against 8.6 s simulated) while the linearisation of a body
    1e-9 from symmetric gave the slower one."""
    damper = SphericalDamper(inertia, 0.1)
    rate = ph.rotors.nutation_rate((4.0, 4.0, 5.0), (0.0, 0.0, 2.0), damper)
    nearly = ph.rotors.nutation_rate((4.0, 4.0 + 4e-9, 5.0), (0.0, 0.0, 2.0), damper)
    assert nearly == pytest.approx(rate, rel=1e-6)
    if inertia == 3.9:
        # The two modes far apart (-0.116 and -0.909): the late slope is the slower one's
        # (at J = 3.5, -0.095 and -0.133 still mix over the run).
        fitted = _fitted_nutation_rate(
            (4.0, 4.0, 5.0), (0.01, 0.0, 2.0), damper, 3 / abs(rate), 2
        )
        assert fitted == pytest.approx(rate, rel=0.01)


def test_nutation_rate_closed_form_limits():
    """The symmetric closed form: continuous with the linearisation of a nearly symmetric body,
    the energy-sink estimate -c (A_s - A_t) / (A_s A_t) for weak coupling, and the damper
    locked (no decay) for strong coupling."""
    damper = SphericalDamper(0.05, 0.02)
    symmetric = ph.rotors.nutation_rate((2.0, 2.0, 3.0), (0.01, 0.0, 1.0), damper)
    nearly = ph.rotors.nutation_rate((2.0, 2.0 + 1e-9, 3.0), (0.01, 0.0, 1.0), damper)
    assert nearly == pytest.approx(symmetric, rel=1e-8)
    weak = SphericalDamper(0.05, 1e-6)
    a_t, a_s = 2.0 - 0.05, 3.0 - 0.05
    assert ph.rotors.nutation_rate((2.0, 2.0, 3.0), (0.0, 0.0, 1.0), weak) == pytest.approx(
        -1e-6 * (a_s - a_t) / (a_s * a_t), rel=1e-6)
    locked = ph.rotors.nutation_rate((2.0, 2.0, 3.0), (0.0, 0.0, 1.0), SphericalDamper(0.05, 1e6))
    assert -1e-6 < locked < 0
    free = SphericalDamper(0.05, 0.0)
    assert ph.rotors.nutation_rate((2.0, 2.0, 3.0), (0.0, 0.0, 1.0), free) == 0
    with pytest.raises(ph.PolhodeError) as error:
        ph.rotors.nutation_rate((1.0, 2.0, 3.0), (0.0, 0.0, 1.0), SphericalDamper(1.5, 0.1))
    assert error.value.argument == "damper"
    with pytest.raises(TypeError, match="damper"):
        ph.rotors.nutation_rate((1.0, 2.0, 3.0), (0.0, 0.0, 1.0), Wheel([0, 0, 1], 0.1))


def test_dissipation_plot_draws_the_energy_sink():
    """plot.dissipation: T and |L| relative to t = 0, and the levels of the separatrix and of
    the spin about the largest axis, L^2 / (2 I2) and L^2 / (2 I3) over T0."""
    moments, omega0 = (1.0, 4.0, 5.0), (2.0, 0.01, 0.01)
    times = np.linspace(0.0, 300.0, 301)
    sol = ph.simulate(moments, omega0, times, rotors=[SphericalDamper(0.2, 0.1)])
    ax = ph.plot.dissipation(sol)
    lines = {line.get_gid(): line for line in ax.get_lines()}
    ell2 = sum((i * w) ** 2 for i, w in zip(moments, omega0, strict=True))
    t0 = 0.5 * sum(i * w * w for i, w in zip(moments, omega0, strict=True))
    np.testing.assert_allclose(lines["dissipation:energy"].get_ydata(), sol.energy / t0)
    assert lines["dissipation:energy"].get_ydata()[-1] == pytest.approx(ell2 / (2 * 5.0) / t0,
                                                                        rel=1e-3)
    np.testing.assert_allclose(lines["dissipation:angular_momentum"].get_ydata(), 1.0,
                               rtol=1e-8)
    assert lines["dissipation:separatrix"].get_ydata()[0] == pytest.approx(ell2 / 8.0 / t0)
    assert lines["dissipation:largest_axis"].get_ydata()[0] == pytest.approx(ell2 / 10.0 / t0)
    # The polhode of the same run: the total L in the body, on the sphere |L| = const, ends
    # on the largest axis.
    ax = ph.plot.polhode(traj=sol)
    path = [line for line in ax.get_lines() if line.get_gid() == "trajectory"][0]
    x, y, z = path.get_data_3d()
    assert abs(x[0]) > 0.99 * np.sqrt(ell2) and abs(z[-1]) > 0.999 * np.sqrt(ell2)


@pytest.mark.parametrize(("moments", "omega0", "axis"), [
    # Damped about the largest axis: nutation_time_constant is the time constant -1 / rate.
    ((1.0, 2.0, 3.0), (0.01, 0.0, 1.0), 2),
    ((2.0, 2.0, 3.0), (0.01, 0.0, 1.0), 2),
    # Tipped over from the smallest axis: nutation_time_constant is the growth time 1 / rate.
    ((1.0, 2.0, 3.0), (1.0, 0.001, 0.0), 0),
])
def test_analyze_gives_the_damper_time_constant_of_the_simulation(moments, omega0, axis):
    """analyze(rotors=[damper]): the nutation rate and its e-folding time against the rate
    fitted from simulate (as test_nutation_rate_against_the_simulation: 1e-4 for decay, 2e-3
    for growth, where the fit reaches the nonlinear regime)."""
    damper = SphericalDamper(0.05, 0.02)
    a = ph.analyze(moments, omega0, rotors=[damper])
    assert a.nutation_rate == ph.rotors.nutation_rate(moments, omega0, damper)
    fitted = _fitted_nutation_rate(moments, omega0, damper, 3 / abs(a.nutation_rate), axis)
    rtol = 1e-4 if axis == 2 else 2e-3
    assert a.nutation_rate == pytest.approx(fitted, rel=rtol)
    assert a.nutation_time_constant == pytest.approx(1 / abs(fitted), rel=rtol)
    assert (a.nutation_rate < 0) == (axis == 2)
    assert f"nutation_time_constant={a.nutation_time_constant:.6g}" in repr(a)
    # The free-body entries are those of the body with the damper locked.
    free = ph.analyze(moments, omega0)
    assert (free.regime, free.period) == (a.regime, a.period)
    assert free.nutation_rate is None and "nutation_rate" not in repr(free)


def test_analyze_with_rotors_in_the_body_own_axes():
    """A tensor in non-principal axes: the same rate as nutation_rate of its principal
    moments with omega0 in those axes; wheels or two dampers give no rate; a damper or a wheel
    that does not fit is an error naming rotors; no damping, no time constant."""
    damper = SphericalDamper(0.05, 0.02)
    omega0 = np.array([0.05, 0.1, 1.0])
    p = ph.principal(TENSOR)
    a = ph.analyze(TENSOR, omega0, rotors=[damper])
    expected = ph.rotors.nutation_rate(p.moments, p.axes.T @ omega0, damper)
    assert a.nutation_rate == pytest.approx(expected, rel=1e-12)
    assert a.nutation_rate == ph.rotors.nutation_rate(TENSOR, omega0, damper)
    for rotors in ([damper, damper], [damper, Wheel([0, 0, 1], 0.1)], [Wheel([0, 0, 1], 0.1)]):
        b = ph.analyze(TENSOR, omega0, rotors=rotors)
        assert b.nutation_rate is None and b.nutation_time_constant is None
    loose = ph.analyze(TENSOR, omega0, rotors=[SphericalDamper(0.05, 0.0)])
    assert loose.nutation_rate == 0.0 and loose.nutation_time_constant is None
    for rotors in ([SphericalDamper(2.5, 0.1)], [Wheel([1, 0, 0], 3.0)]):
        with pytest.raises(ph.ArgumentError, match="positive definite") as error:
            ph.analyze(TENSOR, omega0, rotors=rotors)
        assert error.value.argument == "rotors"
    with pytest.raises(TypeError, match="rotors"):
        ph.analyze(TENSOR, omega0, rotors="damper")
