"""A hypothesis fuzz of the whole public API: any input gives a finite answer or a typed error.

Each entry point is called with arguments drawn from everything a user could pass (numbers
from the subnormal to the largest float, NaN and infinities, wrong shapes, wrong types). The
call must either return finite numbers (when its input was finite) or raise one of the
documented errors: a ``polhode.PolhodeError`` (a ValueError), a ``TypeError`` or a
``MemoryError``. A ``PanicException`` (a BaseException), any other exception, a NaN or an
infinity in the output of a finite input fails the test.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

import polhode as ph

ALLOWED = (ph.PolhodeError, TypeError, MemoryError)

# Numbers across the whole double range, the special values, and a few exact small ones.
FLOATS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-1e3, 1e3),
    st.sampled_from([0.0, -0.0, 1.0, -1.0, 5e-324, 1e-310, 1e-160, 1e160, 1.7e308]),
)
FINITE = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False),
    st.floats(-1e3, 1e3, allow_nan=False),
    st.sampled_from([0.0, 1.0, 5e-324, 1e-300, 1e-160, 1e160, 1e300]),
)
POSITIVE = st.one_of(
    st.floats(min_value=5e-324, max_value=1.7e308, allow_nan=False, allow_infinity=False),
    st.floats(0.01, 100.0),
)


def arrays(elements: st.SearchStrategy[float], shapes: st.SearchStrategy[tuple[int, ...]]):
    return shapes.flatmap(
        lambda shape: st.lists(
            elements, min_size=int(np.prod(shape)), max_size=int(np.prod(shape))
        ).map(lambda v: np.array(v, dtype=float).reshape(shape))
    )


SHAPES = st.sampled_from([(3,), (2,), (4,), (3, 3), (1, 3), (2, 3), (3, 4), (0, 3), (2, 2, 3), ()])
JUNK = st.sampled_from(
    ["abc", None, {"a": 1}, [1, "x", 3], 1 + 2j, np.array([1 + 1j] * 3), b"\x00"]
)


def anything(elements=FLOATS, shapes=SHAPES):
    """A value a user might pass where numbers are expected."""
    return st.one_of(arrays(elements, shapes), elements, JUNK)


def vector3(elements=FLOATS):
    return arrays(elements, st.just((3,)))


def is_finite_input(*values: Any) -> bool:
    """Whether every number in the values is finite (non-numbers count as not finite)."""
    for value in values:
        if np.iscomplexobj(value):
            return False
        try:
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            return False
        if not np.all(np.isfinite(array)):
            return False
    return True


def check_finite_output(result: Any, what: str) -> None:
    """Every float in the result (arrays, dataclass fields, dicts, tuples) is finite."""
    if result is None or isinstance(result, str | bool | int):
        return
    if isinstance(result, float):
        assert math.isfinite(result), f"{what}: {result}"
        return
    if isinstance(result, np.ndarray):
        if result.dtype.kind == "f":
            assert np.all(np.isfinite(result)), f"{what}: non-finite output"
        return
    if isinstance(result, dict):
        for k, v in result.items():
            check_finite_output(v, f"{what}[{k!r}]")
        return
    if isinstance(result, tuple | list):
        for k, v in enumerate(result):
            check_finite_output(v, f"{what}[{k}]")
        return
    if hasattr(result, "__dataclass_fields__"):
        for name in result.__dataclass_fields__:
            if name != "stats":
                check_finite_output(getattr(result, name), f"{what}.{name}")
        return
    if isinstance(result, ph.Body):
        check_finite_output((result.mass, result.center_of_mass, result.inertia), what)


def call(function, *args, finite_input: bool, what: str, **kwargs):
    """Calls; lets only the documented errors through; checks finite output of finite input."""
    note(f"{what}({args!r}, {kwargs!r})")
    try:
        result = function(*args, **kwargs)
    except ALLOWED:
        return None
    except BaseException as error:  # noqa: BLE001 - the point of the test
        pytest.fail(f"{what} raised {type(error).__name__}: {error}")
    if finite_input:
        check_finite_output(result, what)
    return result


FUZZ = settings(
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

SOLIDS = {
    "sphere": 1,
    "spherical_shell": 1,
    "cylinder": 2,
    "tube": 3,
    "cone": 2,
    "rod": 1,
    "disk": 1,
    "torus": 2,
    "capsule": 2,
}


@FUZZ
@given(st.sampled_from(sorted(SOLIDS)), FLOATS, st.lists(FLOATS, min_size=3, max_size=3))
def test_solids(name, mass, params):
    args = params[: SOLIDS[name]]
    body = call(getattr(ph.Body, name), mass, *args, finite_input=True, what=name)
    if body is not None:
        check_finite_output(body, name)


@FUZZ
@given(st.sampled_from(["cuboid", "ellipsoid"]), FLOATS, anything())
def test_vector_solids(name, mass, size):
    call(getattr(ph.Body, name), mass, size, finite_input=is_finite_input(size), what=name)


@FUZZ
@given(anything(shapes=st.sampled_from([(1,), (3,), (2,), (0,)])), anything())
def test_point_masses(masses, positions):
    finite = is_finite_input(masses, positions)
    call(ph.Body.point_masses, masses, positions, finite_input=finite, what="point_masses")


@FUZZ
@given(FLOATS, anything(), anything())
def test_from_inertia(mass, inertia, center):
    finite = is_finite_input(mass, inertia, center)
    call(ph.Body.from_inertia, mass, inertia, center, finite_input=finite, what="from_inertia")


def some_body():
    return st.sampled_from(
        [
            ph.Body.cylinder(1.0, 0.1, 0.5),
            ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)),
            ph.Body.sphere(1.0, 1.0) + ph.Body.rod(0.5, 2.0).translated([0.0, 0.0, 1.0]),
            ph.Body.point_masses([1.0, 2.0], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
        ]
    )


@FUZZ
@given(some_body(), anything(), anything(), FLOATS, FLOATS)
def test_body_methods(body, vector, matrix, a, b):
    finite = is_finite_input(vector)
    call(body.translated, vector, finite_input=finite, what="translated")
    call(body.rotated, matrix, finite_input=is_finite_input(matrix), what="rotated")
    call(body.inertia_about, vector, finite_input=finite, what="inertia_about")
    call(body.angular_momentum_body, vector, finite_input=finite, what="angular_momentum_body")
    call(body.kinetic_energy, vector, finite_input=finite, what="kinetic_energy")
    call(body.scaled, a, b, finite_input=is_finite_input(a, b), what="scaled")
    call(body.principal, a, finite_input=is_finite_input(a), what="principal")


@FUZZ
@given(anything(shapes=st.sampled_from([(3, 3), (2, 3, 3), (3,), (0, 3, 3), (3, 3, 3)])))
def test_principal(tensor):
    if isinstance(tensor, np.ndarray) and tensor.ndim >= 2:
        tensor = 0.5 * tensor + 0.5 * np.swapaxes(tensor, -1, -2)  # symmetric: reach the solver
    call(ph.principal, tensor, finite_input=is_finite_input(tensor), what="principal")


METHODS = st.sampled_from(["exact", "splitting", "midpoint", "rk4", "dop853", "auto", "euler"])


@FUZZ
@given(
    st.one_of(vector3(POSITIVE), vector3(FLOATS), anything()),
    st.one_of(vector3(FINITE), anything()),
    st.one_of(
        st.floats(0.0, 10.0),
        FLOATS,
        arrays(FLOATS, st.sampled_from([(1,), (2,), (3,)])),
        JUNK,
    ),
    METHODS,
    st.one_of(st.none(), st.floats(1e-3, 1.0), FLOATS),
)
def test_simulate(body, omega0, t, method, dt):
    finite = is_finite_input(body, omega0, t) and (dt is None or math.isfinite(dt))
    call(
        ph.simulate,
        body,
        omega0,
        t,
        method=method,
        dt=dt,
        max_steps=20_000,
        finite_input=finite,
        what=f"simulate[{method}]",
    )


@FUZZ
@given(st.one_of(vector3(POSITIVE), anything()), st.one_of(vector3(FINITE), anything()))
def test_analyze(body, omega0):
    call(ph.analyze, body, omega0, finite_input=is_finite_input(body, omega0), what="analyze")


@FUZZ
@given(
    vector3(POSITIVE),
    vector3(FINITE),
    st.one_of(st.floats(0.0, 100.0), FLOATS),
    st.sampled_from([0, 1, 2]),
)
def test_perturbation(moments, omega0, t, order):
    call(
        ph.perturbation,
        moments,
        omega0,
        [0.0, t],
        order=order,
        finite_input=is_finite_input(t),
        what="perturbation",
    )


TORQUES = st.sampled_from(["BodyFixed", "SpaceFixed", "Gravity", "GravityGradient", "Window"])


@FUZZ
@given(TORQUES, anything(), FLOATS, FLOATS)
def test_torque_models(kind, vector, a, b):
    make = {
        "BodyFixed": lambda: ph.torque.BodyFixed(vector),
        "SpaceFixed": lambda: ph.torque.SpaceFixed(vector),
        "Gravity": lambda: ph.torque.Gravity(vector, pivot=None, mass=a, center_of_mass=vector),
        "GravityGradient": lambda: ph.torque.GravityGradient(a, vector, (1.0, 0.0, 0.0)),
        "Window": lambda: ph.torque.Window(ph.torque.BodyFixed((0.0, 0.0, 1.0)), a, b),
    }[kind]
    model = call(make, finite_input=False, what=kind)
    if model is not None and kind != "Gravity":
        call(
            ph.simulate,
            [1.0, 2.0, 3.0],
            [0.1, 0.2, 0.3],
            [0.0, 0.5],
            method="rk4",
            dt=0.01,
            torque=model,
            finite_input=True,
            what=f"simulate[{kind}]",
        )
