"""Bodies and every result object pickle and deep-copy, bit for bit, and go to other processes:
a ``multiprocessing`` pool (spawn) and a Dask cluster of two worker processes.

A Body pickles as its core's stored numbers (mass, the double-double centre of mass, the
square-root second moment: ``MassProperties.parts()``), never through the materialised tensor,
so a round trip changes no bit of anything it reports; loading checks them again
(``MassProperties.from_parts``), so a damaged pickle is a typed error, not a strange body.
The references are the objects themselves before pickling, compared bit for bit.
"""

from __future__ import annotations

import copy
import multiprocessing
import pickle

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode import _core

TIMES = np.linspace(0.0, 3.0, 7)
OMEGA = np.array([0.3, 1.0, -0.2])


def tetrahedron(scale: float = 1.0):
    vertices = scale * np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    return vertices, faces


def bodies() -> dict[str, ph.Body]:
    """Bodies of every kind of constructor, and the hard ones: a needle, a body far from the
    origin (whose centre of mass keeps a low part), a heavy sphere with a speck, subnormal and
    huge scales."""
    rng = np.random.default_rng(7)
    far = ph.Body.cuboid(2.0, (0.1, 0.2, 0.3)).rotated(Rotation.from_rotvec([0.3, -0.2, 0.9]))
    far = far.translated([1e8 + 0.1, -3.3, 1e-9])
    out = {
        "sphere": ph.Body.sphere(2.0, 0.5),
        "cylinder": ph.Body.cylinder(1.0, 0.1, 0.5),
        "needle": ph.Body.cylinder(1.0, 1e-8, 1.0),
        "cone": ph.Body.cone(0.1, 0.04, 0.03),
        "torus rotated": ph.Body.torus(1.0, 1.0, 0.2).rotated([0.1, 0.2, 0.3, 0.9]),
        "point masses": ph.Body.point_masses(rng.uniform(0.5, 2.0, 50), rng.normal(size=(50, 3))),
        "mesh": ph.Body.mesh(*tetrahedron(), density=3.0),
        "from_inertia": ph.Body.from_inertia(2.0, np.diag([1.0, 2.0, 2.5]), (0.1, 0.2, 0.3)),
        "molecule": ph.Body.from_atoms(
            ["O", "H", "H"], [[0, 0, 0.1173], [0, 0.7572, -0.4692], [0, -0.7572, -0.4692]]
        ),
        "far": far,
        "composite": far + ph.Body.sphere(1e-12, 1.0).translated([1e8, 0.0, 0.0]),
        "heavy sphere with a speck": ph.Body.sphere(1.0, 1.0)
        + ph.Body.point_masses([1e-12], [[1.0, 0.0, 0.0]]),
        "scaled to 1e-150": ph.Body.cuboid(1.0, (1.0, 2.0, 3.0)).scaled(1e-150, 1e-70),
        "scaled to 1e150": ph.Body.cuboid(1.0, (1.0, 2.0, 3.0)).scaled(1e150, 1e70),
    }
    return out


BODIES = bodies()


def bits(value) -> bytes:
    """The bytes of every float and int of a (nested) value: equal bits, not equal values."""
    if isinstance(value, tuple | list):
        return b"|".join(bits(v) for v in value)
    return np.asarray(value).tobytes()


def assert_same_body(again: ph.Body, body: ph.Body) -> None:
    assert type(again) is ph.Body
    assert bits(again._core.parts()) == bits(body._core.parts())
    for name in ("mass", "center_of_mass", "inertia", "second_moment"):
        assert bits(getattr(again, name)) == bits(getattr(body, name)), name
    assert bits(tuple(again.principal())) == bits(tuple(body.principal()))
    assert bits(again.inertia_about([1.0, -2.0, 0.5])) == bits(body.inertia_about([1.0, -2.0, 0.5]))
    assert again.kinetic_energy(OMEGA) == body.kinetic_energy(OMEGA)
    assert_same_shape(again._shape, body._shape)


def assert_same_shape(again, shape) -> None:
    if shape is None:
        assert again is None
        return
    assert len(again) == len(shape)
    for a, b in zip(again, shape, strict=True):
        assert a.kind == b.kind and sorted(a.params) == sorted(b.params)
        for key in a.params:
            assert bits(a.params[key]) == bits(b.params[key]), key
        assert bits(a.matrix) == bits(b.matrix) and bits(a.offset) == bits(b.offset)


@pytest.mark.parametrize("name", list(BODIES))
@pytest.mark.parametrize("protocol", range(pickle.HIGHEST_PROTOCOL + 1))
def test_body_pickles_bit_for_bit(name, protocol):
    body = BODIES[name]
    assert_same_body(pickle.loads(pickle.dumps(body, protocol=protocol)), body)


@pytest.mark.parametrize("name", list(BODIES))
def test_body_deep_and_shallow_copies(name):
    body = BODIES[name]
    assert_same_body(copy.deepcopy(body), body)
    assert_same_body(copy.copy(body), body)


def test_the_far_body_round_trip_keeps_the_low_part_of_its_centre():
    # Not a trivial round trip: the composite far from the origin has a non-zero low part,
    # which the tensor about a nearby point depends on.
    body = BODIES["composite"]
    assert any(x != 0.0 for x in body._core.parts()[2])
    again = pickle.loads(pickle.dumps(body))
    point = [1e8, 0.0, 0.0]
    assert bits(again.inertia_about(point)) == bits(body.inertia_about(point))


def test_a_body_in_a_container_and_a_composite_of_unpickled_parts():
    parts = list(BODIES.values())
    again = pickle.loads(pickle.dumps(parts))
    assert_same_body(sum(again[1:], again[0]), sum(parts[1:], parts[0]))


GOOD = BODIES["far"]._core.parts()


def with_part(index, value):
    parts = list(GOOD)
    parts[index] = value
    return tuple(parts)


@pytest.mark.parametrize(
    ("parts", "error", "argument"),
    [
        (with_part(0, 0.0), ph.NonPositiveError, "mass"),
        (with_part(0, -1.0), ph.NonPositiveError, "mass"),
        (with_part(0, float("nan")), ph.NonFiniteError, "mass"),
        (with_part(1, (float("inf"), 0.0, 0.0)), ph.NonFiniteError, "center_of_mass[0]"),
        (with_part(2, (0.0, float("nan"), 0.0)), ph.NonFiniteError, "center_of_mass_low[1]"),
        # A low part of a whole ulp of its high part: no renormalised double-double.
        (with_part(2, (16.0, 0.0, 0.0)), ph.ArgumentError, "center_of_mass_low[0]"),
        (with_part(3, -1e-300), ph.ArgumentError, "isotropic"),
        (with_part(3, float("inf")), ph.NonFiniteError, "isotropic"),
        (
            with_part(4, ((0.0, 0.0, 0.0), (0.0, float("nan"), 0.0), (0.0, 0.0, 0.0))),
            ph.NonFiniteError,
            "factor[1, 1]",
        ),
        (with_part(4, ((1e200, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))), ph.ArgumentError,
         "factor"),
    ],
)
def test_damaged_parts_are_typed_errors_naming_the_part(parts, error, argument):
    with pytest.raises(error) as info:
        _core.MassProperties.from_parts(*parts)
    # `argument` is the part; the message names the element.
    assert info.value.argument == argument.split("[")[0]
    assert f"`{argument}`" in str(info.value)


def test_parts_of_the_wrong_type_are_refused_naming_the_part():
    # The private loader's own conversions (pyo3's): a TypeError, or a ValueError for a tuple
    # of the wrong length, each naming the part.
    with pytest.raises(TypeError, match="mass"):
        _core.MassProperties.from_parts("heavy", *GOOD[1:])
    with pytest.raises(ValueError, match="center_of_mass"):
        _core.MassProperties.from_parts(GOOD[0], (1.0, 2.0), *GOOD[2:])


def test_a_damaged_pickle_is_a_typed_error():
    data = pickle.dumps(BODIES["sphere"], protocol=0)
    mass = repr(BODIES["sphere"].mass).encode()
    assert data.count(mass) == 1
    with pytest.raises(ph.NonPositiveError) as info:
        pickle.loads(data.replace(mass, b"-2.0"))
    assert info.value.argument == "mass"


# ---------------------------------------------------------------------------------------------
# Result objects and models
# ---------------------------------------------------------------------------------------------


def drag(t, omega, quaternion):
    """A torque function pickle can name (a lambda it cannot)."""
    return -0.1 * np.asarray(omega)


def motor(t, omega, rate):
    return 0.01 - 0.001 * rate


TQ = ph.torque
MODELS = {
    "BodyFixed": TQ.BodyFixed([0.0, 0.1, 0.2]),
    "SpaceFixed": TQ.SpaceFixed([0.1, 0.0, -0.2]),
    "Gravity": TQ.Gravity(pivot=[0.0, 0.0, 0.1]),
    "Gravity with mass": TQ.Gravity([0.0, 0.0, -1.0], mass=2.0, center_of_mass=[0.0, 0.0, 0.3]),
    "GravityGradient": TQ.GravityGradient(1.3, (0.1, 0.2, 1.0), (1.0, 0.3, 0.0)),
    "Window": TQ.Window(TQ.BodyFixed([0.0, 0.0, 1.0]), 0.5, 1.5),
    "Sum": TQ.BodyFixed([0.0, 0.0, 1.0]) + TQ.Function(drag, depends_on_orientation=False),
    "Function": TQ.Function(drag, discontinuities=[0.7]),
}
ROTORS = {
    "Wheel": ph.rotors.Wheel([0.0, 0.0, 1.0], 0.1, rate0=2.0, torque=0.01),
    "Wheel schedule": ph.rotors.Wheel([1.0, 0.0, 0.0], 0.1, torque=[(0.0, 0.05), (1.0, 0.0)]),
    "Wheel function": ph.rotors.Wheel([0.0, 1.0, 0.0], 0.1, torque=motor),
    "SphericalDamper": ph.rotors.SphericalDamper(0.2, 0.1),
}


def read_only_arrays(model) -> list[np.ndarray]:
    arrays = []
    for value in vars(model).values():
        if isinstance(value, np.ndarray):
            arrays.append(value)
        elif isinstance(value, TQ.Torque):
            arrays += read_only_arrays(value)
        elif isinstance(value, tuple):
            for term in value:
                if isinstance(term, TQ.Torque):
                    arrays += read_only_arrays(term)
    return arrays


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("how", ["pickle", "deepcopy"])
def test_torque_models_round_trip_and_stay_immutable(name, how):
    model = MODELS[name]
    again = pickle.loads(pickle.dumps(model)) if how == "pickle" else copy.deepcopy(model)
    assert type(again) is type(model) and repr(again) == repr(model)
    arrays = read_only_arrays(again)
    assert arrays or name == "Function"
    for array in arrays:  # numpy's pickles load writeable: a model's arrays stay read-only
        assert not array.flags.writeable
    # A Gravity with a mass goes with bare moments (about the pivot), the others with a Body.
    body = [1.0, 2.0, 2.5] if name == "Gravity with mass" else BODIES["from_inertia"]
    expected = ph.simulate(body, OMEGA, TIMES, torque=model, method="rk4", dt=0.01)
    got = ph.simulate(body, OMEGA, TIMES, torque=again, method="rk4", dt=0.01)
    assert bits(got.omega) == bits(expected.omega)


@pytest.mark.parametrize("name", list(ROTORS))
@pytest.mark.parametrize("how", ["pickle", "deepcopy"])
def test_rotors_round_trip_and_stay_immutable(name, how):
    rotor = ROTORS[name]
    again = pickle.loads(pickle.dumps(rotor)) if how == "pickle" else copy.deepcopy(rotor)
    assert type(again) is type(rotor) and repr(again) == repr(rotor)
    for value in vars(again).values():
        if isinstance(value, np.ndarray):
            assert not value.flags.writeable
    expected = ph.simulate([1.0, 2.0, 3.0], OMEGA, TIMES, rotors=[rotor], method="rk4", dt=0.01)
    got = ph.simulate([1.0, 2.0, 3.0], OMEGA, TIMES, rotors=[again], method="rk4", dt=0.01)
    assert bits(got.omega) == bits(expected.omega)


def test_an_unpickled_model_is_checked_by_the_core_again():
    data = pickle.dumps(TQ.GravityGradient(1.0), protocol=0)
    assert data.count(b"1.0") >= 1
    state = vars(TQ.GravityGradient(1.0)).copy()
    state["mean_motion"] = float("nan")
    broken = object.__new__(TQ.GravityGradient)
    with pytest.raises(ph.NonFiniteError) as info:
        broken.__setstate__(state)
    assert info.value.argument == "mean_motion"


def trajectories() -> dict[str, ph.Trajectory]:
    return {
        "one body": ph.simulate(BODIES["cylinder"], OMEGA, TIMES),
        "batch": ph.simulate([1.0, 2.0, 3.0], np.eye(3) + 0.1, TIMES, method="splitting", dt=0.1),
        "no orientation": ph.simulate([1.0, 2.0, 3.0], OMEGA, TIMES, orientation=False),
        "rotors": ph.simulate([1.0, 2.0, 3.0], OMEGA, TIMES, rotors=list(ROTORS.values())[:2]),
    }


def assert_same_trajectory(again, trajectory):
    assert type(again) is ph.Trajectory
    for name in trajectory.__dataclass_fields__:
        if name == "stats":
            assert again.stats.keys() == trajectory.stats.keys()
            for key, value in trajectory.stats.items():
                assert bits(again.stats[key]) == bits(value) if key != "method" else (
                    again.stats[key] == value)
            continue
        value = getattr(trajectory, name)
        assert (getattr(again, name) is None) if value is None else (
            bits(getattr(again, name)) == bits(value)), name
    assert repr(again) == repr(trajectory)


@pytest.mark.parametrize("name", ["one body", "batch", "no orientation", "rotors"])
def test_trajectories_round_trip(name):
    trajectory = trajectories()[name]
    for again in (pickle.loads(pickle.dumps(trajectory)), copy.deepcopy(trajectory)):
        assert_same_trajectory(again, trajectory)
        if trajectory.quaternion is not None:
            assert bits(again.euler_angles()) == bits(trajectory.euler_angles())


def test_principal_and_analysis_round_trip():
    single = BODIES["torus rotated"].principal()
    batch = ph.principal(np.stack([np.diag([3.0, 1.0, 2.0]), np.diag([1.0, 1.0, 2.0])]))
    for p in (single, batch):
        for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
            again = pickle.loads(pickle.dumps(p, protocol=protocol))
            assert type(again) is ph.Principal
            assert bits((again.moments, again.axes, again.multiplicity)) == bits(
                (p.moments, p.axes, p.multiplicity))
        deep = copy.deepcopy(p)
        assert bits(deep.axes) == bits(p.axes) and deep.axes is not p.axes
    analysis = ph.analyze([1.0, 2.0, 3.0], [0.01, 1.0, 0.01])
    for again in (pickle.loads(pickle.dumps(analysis)), copy.deepcopy(analysis)):
        assert type(again) is ph.Analysis and repr(again) == repr(analysis)
        for name in analysis.__dataclass_fields__:
            value = getattr(analysis, name)
            if isinstance(value, dict):
                assert again.linearized == value
            else:
                assert bits(getattr(again, name)) == bits(value), name


def test_shapes_and_errors_round_trip():
    body = BODIES["torus rotated"] + BODIES["mesh"] + BODIES["point masses"]
    from polhode import _shapes

    shape = _shapes.of(body)
    assert_same_shape(pickle.loads(pickle.dumps(shape)), shape)
    # A body without geometry is drawn as its equivalent ellipsoid, after a round trip too.
    plain = BODIES["from_inertia"]
    assert_same_shape(_shapes.of(pickle.loads(pickle.dumps(plain))), _shapes.of(plain))
    error = ph.InertiaError("Expected `inertia` ...", argument="inertia", body=3)
    again = pickle.loads(pickle.dumps(error))
    assert type(again) is ph.InertiaError and (again.argument, again.body) == ("inertia", 3)


# ---------------------------------------------------------------------------------------------
# Other processes: a multiprocessing pool (spawn) and a Dask cluster of two processes
# ---------------------------------------------------------------------------------------------


def work(body: ph.Body, model: TQ.Torque | None) -> tuple[ph.Body, ph.Trajectory, ph.Principal]:
    """What a worker process does with a body it was sent: a composite made of it, a run with
    the model, the principal axes; all sent back."""
    moved = body.translated([0.5, -0.25, 2.0]) + body
    return moved, ph.simulate(body, OMEGA, TIMES, torque=model, method="rk4", dt=0.01), (
        moved.principal())


# (body, torque): the needle torque-free (a drag about its axis of moment 5e-17 is stiff).
CASES = {
    "needle": None,
    "composite": MODELS["Sum"],
    "mesh": MODELS["Function"],
    "molecule": MODELS["Sum"],
    "point masses": MODELS["GravityGradient"],
}


def check_worker_results(results) -> None:
    for (name, model), (moved, trajectory, principal) in zip(CASES.items(), results, strict=True):
        expected = work(BODIES[name], model)
        assert_same_body(moved, expected[0])
        assert bits(trajectory.omega) == bits(expected[1].omega)
        assert bits(trajectory.quaternion) == bits(expected[1].quaternion)
        assert bits(tuple(principal)) == bits(tuple(expected[2]))


def test_a_spawned_multiprocessing_pool():
    context = multiprocessing.get_context("spawn")
    with context.Pool(2) as pool:
        results = pool.starmap(work, [(BODIES[name], model) for name, model in CASES.items()])
    check_worker_results(results)


def test_a_dask_cluster_of_two_processes():
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        # Each body to one of the two worker processes, in turn.
        workers = sorted(client.scheduler_info()["workers"])
        assert len(workers) == 2
        futures = [
            client.submit(work, BODIES[name], model, pure=False, workers=[workers[i % 2]])
            for i, (name, model) in enumerate(CASES.items())
        ]
        results = client.gather(futures)
        assert {w for ws in client.who_has(futures).values() for w in ws} == set(workers)
        # A body scattered once and used by a task on a worker, and a Trajectory sent back.
        [remote] = client.scatter([BODIES["far"]], broadcast=True)
        trajectory = client.submit(ph.simulate, remote, OMEGA, TIMES, pure=False).result()
    check_worker_results(results)
    assert bits(trajectory.omega) == bits(ph.simulate(BODIES["far"], OMEGA, TIMES).omega)


class Wheelbarrow(ph.Body):
    """A user's subclass of Body."""

    __slots__ = ()


def test_a_subclass_of_body_pickles_as_itself():
    body = Wheelbarrow.cylinder(3.0, 0.2, 0.1)
    assert type(body) is Wheelbarrow
    again = pickle.loads(pickle.dumps(body))
    assert type(again) is Wheelbarrow
    assert bits(again._core.parts()) == bits(body._core.parts())
    assert type(copy.deepcopy(body)) is Wheelbarrow
