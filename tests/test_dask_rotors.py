"""polhode.dask.simulate with rotors: the same wheels and dampers in every body; each body's
result is the very numbers of polhode.simulate of that body alone, and one body agrees with
scipy's DOP853 on the full system written apart from the core (reference_rotors.gyrostat)."""

from __future__ import annotations

import numpy as np
import pytest
from reference_rotors import DamperRef, WheelRef, gyrostat

da = pytest.importorskip("dask.array")

import polhode as ph  # noqa: E402
import polhode.dask as phd  # noqa: E402
from polhode.rotors import SphericalDamper, Wheel  # noqa: E402

N = 24
T = np.linspace(0.0, 4.0, 9)
ROTORS = [
    Wheel([0.2, 1.0, 0.0], 0.05, rate0=1.0, torque=[(0.0, 0.02), (2.0, -0.01)]),
    SphericalDamper(0.05, 0.1),
]
FIELDS = ("omega", "quaternion", "angular_momentum_space", "angular_momentum_body", "energy",
          "rotor_rates")


@pytest.fixture(scope="module")
def bodies():
    rng = np.random.default_rng(16)
    moments = np.sort(rng.uniform(1.0, 4.0, (N, 3)), axis=1)
    omega0 = rng.normal(size=(N, 3))
    return moments, omega0


@pytest.mark.parametrize(("method", "options"), [("auto", {"rtol": 1e-9}),
                                                 ("rk4", {"dt": 0.01})])
def test_each_body_is_simulate_of_that_body_alone(bodies, method, options):
    moments, omega0 = bodies
    lazy = phd.simulate(da.from_array(moments, chunks=7), omega0, T, rotors=ROTORS,
                        method=method, **options)
    assert isinstance(lazy.rotor_rates, da.Array)
    assert lazy.rotor_rates.shape == (N, len(T), 2, 3)
    assert lazy.rotor_rates.chunks[0] == (7, 7, 7, 3)
    sol = lazy.compute(scheduler="threads")
    assert sol.stats["method"] == ("dop853" if method == "auto" else "rk4")
    for k in range(N):
        alone = ph.simulate(moments[k], omega0[k], T, rotors=ROTORS, method=method, **options)
        for name in FIELDS:
            assert np.array_equal(getattr(sol, name)[k], getattr(alone, name)), (k, name)
        assert sol.stats["steps"][k] == alone.stats["steps"]
    # The rotor rates computed on their own: the same numbers.
    np.testing.assert_array_equal(lazy.rotor_rates.compute(scheduler="sync"), sol.rotor_rates)


def test_one_body_against_scipy(bodies):
    moments, omega0 = bodies
    sol = phd.simulate(moments, omega0, T, rotors=ROTORS, rtol=1e-12, chunks=5).compute()
    k = 11
    ref_omega, _, ref_rates, ref_l, ref_t = gyrostat(
        np.diag(moments[k]), omega0[k], [0.0, 0.0, 0.0, 1.0], T,
        [WheelRef([0.2, 1.0, 0.0], 0.05, 1.0, lambda t, w, r: 0.02 if t < 2.0 else -0.01),
         DamperRef(0.05, 0.1)],
        breaks=(2.0,),
    )
    # Measured: within 2e-12 of scipy (rtol 1e-12) for the rotor rates (up to 1.7), 6.5e-14
    # for omega, 4e-15 relative for L and T; bound 2e-10 of the largest value, as in
    # tests/test_rotors.py.
    scale = np.max(np.abs(ref_rates)) + np.max(np.abs(ref_omega))
    np.testing.assert_allclose(sol.omega[k], ref_omega, rtol=0, atol=2e-10 * scale)
    np.testing.assert_allclose(sol.rotor_rates[k], ref_rates, rtol=0, atol=2e-10 * scale)
    np.testing.assert_allclose(sol.angular_momentum_space[k], ref_l, rtol=0,
                               atol=2e-10 * np.max(np.abs(ref_l)))
    np.testing.assert_allclose(sol.energy[k], ref_t, rtol=2e-10)


def test_rotors_that_do_not_fit_a_body_name_it(bodies):
    moments, omega0 = bodies
    small = moments.copy()
    small[9] = [0.04, 1.0, 1.0]  # the damper's J = 0.05 does not fit
    with pytest.raises(ph.ArgumentError, match=r"^body 9: .*`rotors`") as info:
        phd.simulate(small, omega0, T, rotors=ROTORS)  # numpy moments: at once
    assert (info.value.argument, info.value.body) == ("rotors", 9)
    lazy = phd.simulate(da.from_array(small, chunks=4), omega0, T, rotors=ROTORS)
    with pytest.raises(ph.ArgumentError, match=r"^body 9: .*`rotors`") as info:
        lazy.compute(scheduler="sync")
    assert (info.value.argument, info.value.body) == ("rotors", 9)
    with pytest.raises(ph.ArgumentError, match="rotors"):
        phd.simulate(moments, omega0, T, rotors=ROTORS, method="exact")
    with pytest.raises(TypeError, match="rotors"):
        phd.simulate(moments, omega0, T, rotors="wheel")


def test_without_rotors_there_are_no_rotor_rates(bodies):
    moments, omega0 = bodies
    assert phd.simulate(moments, omega0, T).rotor_rates is None


def test_analyze_with_a_damper_equals_analyze_per_body(bodies):
    moments, omega0 = bodies
    damper = SphericalDamper(0.05, 0.02)
    got = phd.analyze(da.from_array(moments, chunks=10), omega0, rotors=[damper]).compute()
    for k in range(N):
        a = ph.analyze(moments[k], omega0[k], rotors=[damper])
        assert got.nutation_rate[k] == a.nutation_rate
        assert got.nutation_time_constant[k] == a.nutation_time_constant
        assert got.regime[k] == a.regime
    plain = phd.analyze(moments, omega0).compute()
    assert np.isnan(plain.nutation_rate).all() and np.isnan(plain.nutation_time_constant).all()
    # Wheels give no rate: NaN, as None in polhode.Analysis.
    wheels = phd.analyze(moments, omega0, rotors=ROTORS[:1]).compute()
    assert np.isnan(wheels.nutation_rate).all()
    small = moments.copy()
    small[4] = [0.04, 1.0, 1.0]
    with pytest.raises(ph.ArgumentError, match=r"^body 4: .*`rotors`"):
        phd.analyze(small, omega0, rotors=[damper])
