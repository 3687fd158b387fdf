"""The fast paths of a small call give what the general paths give: the Trajectory and the
Analysis built field by field are the dataclasses their constructors build, arrays pass through
the coercion as numpy would convert them, the memory check is skipped only for outputs that
surely fit, and analyze's principal-axis values are those of numpy's product. (How fast they
are is measured by polhode.bench.kernels.small_calls, not here.)"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import polhode as ph
from polhode import _core, simulation
from polhode._coerce import as_float_array


def test_trajectory_is_the_dataclass_its_constructor_builds():
    traj = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], [0.0, 1.0, 2.0])
    rebuilt = dataclasses.replace(traj)  # through Trajectory.__init__
    assert list(vars(traj)) == list(vars(rebuilt)) == [f.name for f in dataclasses.fields(traj)]
    for f in dataclasses.fields(traj):
        a, b = getattr(traj, f.name), getattr(rebuilt, f.name)
        assert a is b
    assert repr(traj) == repr(rebuilt)
    with pytest.raises(dataclasses.FrozenInstanceError):
        traj.omega = None  # type: ignore[misc]
    no_attitude = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], [0.0, 1.0], orientation=False)
    assert no_attitude.quaternion is None and no_attitude.angular_momentum_space is None
    assert no_attitude.rotor_rates is None and no_attitude.t.tolist() == [0.0, 1.0]


def test_analysis_is_the_dataclass_its_constructor_builds():
    a = ph.analyze([1.0, 2.0, 3.0], [0.01, 1.0, 0.01])
    rebuilt = dataclasses.replace(a)
    assert list(vars(a)) == [f.name for f in dataclasses.fields(a)]
    assert repr(a) == repr(rebuilt)
    assert a.moments.dtype == np.float64 and a.omega.dtype == np.float64
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.regime = "rest"  # type: ignore[misc]


@pytest.mark.parametrize(
    "omega0",
    [[-0.0, -1.0, -1.0], [-0.0, 1.0, 0.5], [1.0, -0.0, 2.0], [0.3, -0.2, -0.0], [0.0, 0.0, -2.0]],
)
@pytest.mark.parametrize("moments", [[1.0, 2.0, 3.0], [3.0, 1.0, 2.0], [1.0, 1.0, 2.0]])
def test_analyze_omega_is_numpys_product_with_the_identity(moments, omega0):
    """Moments given as numbers: omega in principal axes is omega0 @ I (its zeros +0), the
    moments sorted; everything else as for the same motion given as a diagonal tensor."""
    a = ph.analyze(moments, omega0)
    order = np.argsort(moments, kind="stable")
    expected = (np.array(omega0) @ np.eye(3))[order]
    assert a.omega.tolist() == expected.tolist()
    assert not np.signbit(a.omega[a.omega == 0.0]).any()
    assert a.moments.tolist() == sorted(moments)


def test_analyze_checks_its_arguments_as_simulate_does():
    for body, omega0, error in (
        ([1.0, -2.0, 3.0], [0.0, 1.0, 0.0], ph.PolhodeError),
        ([1.0, 2.0, 3.0], [0.0, np.inf, 0.0], ph.NonFiniteError),
        ([1.0, 2.0, 3.0], [1e200, 1e200, 0.0], ph.PolhodeError),
        ([1.0, 2.0], [0.0, 1.0, 0.0], ph.ShapeError),
    ):
        with pytest.raises(error) as analyzed:
            ph.analyze(body, omega0)
        with pytest.raises(error) as simulated:
            ph.simulate(body, omega0, [0.0], method="exact", orientation=False)
        assert str(analyzed.value) == str(simulated.value)
        assert analyzed.value.argument == simulated.value.argument


def test_as_float_array_passes_float64_arrays_through_and_converts_the_rest():
    a = np.array([1.0, 2.0, 3.0])
    assert as_float_array("x", a) is a
    # Not C-contiguous, another dtype, a 0-d array: converted, as numpy's ascontiguousarray.
    for value in (np.arange(6.0)[::2], np.array([1, 2, 3]), np.array(5.0), [1, 2.5], (3,), 2.0):
        out = as_float_array("x", value)
        expected = np.ascontiguousarray(value, dtype=np.float64)
        assert out.dtype == np.float64 and out.flags.c_contiguous
        assert out.shape == expected.shape and out.tolist() == expected.tolist()
    assert as_float_array("x", np.array(5.0)).shape == (1,)


@pytest.mark.parametrize(
    ("value", "what"),
    [
        ([[1.0, 2.0], [3.0]], "list"),  # ragged: numpy cannot read it as an array
        ([1.0, 2j, 3.0], "list"),
        ([1.0, None, 3.0], "list"),
        (["1", "2", "3"], "list of <U1"),
        (np.array(["1.0", "2.0"]), "an array of dtype <U3"),
        (np.array([1 + 0j]), "an array of dtype complex128"),
        (None, "NoneType"),
    ],
)
def test_as_float_array_rejects_what_is_not_real_numbers(value, what):
    with pytest.raises(
        TypeError, match=f"Expected `omega0` to be an array of real numbers, got {what}"
    ):
        as_float_array("omega0", value)
    with pytest.raises(TypeError, match="`omega0`"):
        ph.simulate([1.0, 2.0, 3.0], value, [0.0, 1.0])


def test_a_scalar_end_time_as_a_0d_array_is_an_end_time():
    expected = np.linspace(1.0, 5.0, 49)  # FEWEST: a slow spin turns less than once in 4 s
    for t in (5.0, np.float64(5.0), np.array(5.0), 5):
        traj = ph.simulate([1.0, 2.0, 3.0], [0.01, 0.1, 0.01], t, t0=1.0)
        assert traj.t.tolist() == expected.tolist()


def numbers_per_time() -> int:
    """The numbers of one body's outputs at one time with the orientation and no rotors, from
    the core's table: each quantity's shape multiplied out."""
    return sum(
        int(np.prod(row["shape"])) for row in _core.QUANTITIES if "rotors" not in row["requires"]
    )


def test_memory_is_asked_only_for_outputs_that_may_not_fit(monkeypatch):
    asked = []

    def available():
        asked.append(True)
        return 10**15

    monkeypatch.setattr(simulation, "_available_memory", available)
    ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], [0.0, 1.0])
    assert asked == []
    # The numbers of every quantity at a time, 8 bytes each: one time more than _ALWAYS_FITS
    # holds is checked.
    times = np.zeros(simulation._ALWAYS_FITS // (numbers_per_time() * 8) + 1)
    simulation._check_fits(np.zeros(3), times, True)
    assert asked == [True]
    simulation._check_fits(np.zeros(3), times[:-1], True)
    assert asked == [True]
    # Not enough memory: MemoryError before the work.
    monkeypatch.setattr(simulation, "_available_memory", lambda: 1)
    with pytest.raises(MemoryError, match="bytes"):
        simulation._check_fits(np.zeros(3), times, True)


def test_order3_is_numpys_stable_argsort():
    from itertools import product

    from polhode.analysis import _order3

    for m in product([1.0, 2.0, 3.0], repeat=3):  # every order, with ties
        assert _order3(list(m)) == tuple(np.argsort(m, kind="stable").tolist())


@pytest.mark.parametrize(
    "omega0",
    [[1.0, 1.0, 1.0], [0.5, -1.0, 1.0], [-2.0, 2.0, 0.0], [0.0, 0.0, 0.0], [0.1, 0.3, -0.3]],
)
def test_linearized_axis_is_numpys_argmax(omega0):
    a = ph.analyze([1.0, 2.0, 3.0], omega0)
    assert a.linearized["axis"] == int(np.argmax(np.abs(omega0)))


def test_simulate_skips_the_memory_check_only_for_one_body_at_few_times(monkeypatch):
    # simulate skips _check_fits for one body without rotors at up to 10^5 output times: all
    # of those outputs fit in _ALWAYS_FITS, which _check_fits would not check either.
    assert 100_000 * numbers_per_time() * 8 <= simulation._ALWAYS_FITS
    calls = []
    real = simulation._check_fits

    def check_fits(*args):
        calls.append(args)
        return real(*args)

    monkeypatch.setattr(simulation, "_check_fits", check_fits)
    moments, omega0 = [1.0, 2.0, 3.0], [0.01, 1.0, 0.01]
    ph.simulate(moments, omega0, np.linspace(0.0, 1.0, 100_000), orientation=False)
    assert calls == []
    ph.simulate(moments, [omega0], [0.0, 1.0])  # a batch (of one)
    assert len(calls) == 1
    ph.simulate(moments, omega0, np.linspace(0.0, 1.0, 100_001), orientation=False)
    assert len(calls) == 2
    ph.simulate(moments, omega0, [0.0, 0.1], rotors=[ph.rotors.SphericalDamper(0.2, 0.1)])
    assert len(calls) == 3
    # Past the skip, a run that does not fit raises MemoryError before the work.
    monkeypatch.setattr(simulation, "_available_memory", lambda: 1)
    with pytest.raises(MemoryError, match="bytes"):
        ph.simulate(moments, np.zeros((600_000, 3)), [0.0, 1.0])


def test_trajectory_fields_from_the_core_in_order_for_every_kind_of_run():
    # The core returns every field of Trajectory by name, in order, None for those not
    # computed: one body and a batch, with and without orientation, with rotors.
    names = [f.name for f in dataclasses.fields(ph.Trajectory)]
    t = np.array([0.0, 0.5, 1.0])
    damper = ph.rotors.SphericalDamper(0.2, 0.1)
    for omega0, kwargs, absent in [
        ([0.01, 1.0, 0.01], {}, {"rotor_rates"}),
        ([0.01, 1.0, 0.01], {"orientation": False}, {"rotor_rates", "quaternion"}),
        (np.ones((2, 3)), {}, {"rotor_rates"}),
        (np.ones((2, 3)), {"rotors": [damper]}, set()),
        ([0.01, 1.0, 0.01], {"rotors": [damper], "orientation": False}, {"quaternion"}),
    ]:
        # And every quantity of the core's table that needs what the run lacks.
        for row in _core.QUANTITIES:
            if ("orientation" in row["requires"] and kwargs.get("orientation") is False) or (
                "rotors" in row["requires"] and "rotors" not in kwargs
            ):
                absent = absent | {row["name"]}
        traj = ph.simulate([1.0, 2.0, 3.0], omega0, t, **kwargs)
        assert list(vars(traj)) == names
        # Equal to the caller's times but not the caller's array (which may change later).
        assert traj.t is not t and np.array_equal(traj.t, t)
        assert {n for n in names if getattr(traj, n) is None} == absent
        assert list(traj.stats) == ["method", "steps", "rejected_steps", "evaluations", "wall_time"]
        batch = np.ndim(omega0) == 2
        assert isinstance(traj.stats["steps"], np.ndarray) == batch
        assert traj.omega.shape == ((2,) if batch else ()) + (3, 3)
        assert traj.moments.shape == ((2,) if batch else ()) + (3,)
        if traj.rotor_rates is not None:
            assert traj.rotor_rates.shape == ((2,) if batch else ()) + (3, 1, 3)
