"""Bad input to simulate / analyze / the torque models raises at once, typed, naming the argument.

ValueError subclasses (polhode.PolhodeError) for shapes, non-finite numbers, non-positive values
and unknown options; TypeError for wrong types; a callable torque that raises propagates its own
exception. Never a panic (pyo3's PanicException is a BaseException), a hang, or a silent NaN.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import polhode as ph

NAN, INF = math.nan, math.inf
MOMENTS = (1.0, 2.0, 3.0)
W = (0.1, 0.2, 0.3)
FIXED = ["splitting", "midpoint", "rk4"]
ALL = ["exact", "splitting", "midpoint", "rk4", "dop853"]
ZERO = ph.torque.Function(lambda t, w, q: (0.0, 0.0, 0.0))


def raises(kind, fragment, call):
    """call() raises exactly `kind` (not a panic) with `fragment` in the message."""
    with pytest.raises(BaseException) as info:  # noqa: B017, PT011 - the type is checked below
        call()
    error = info.value
    assert isinstance(error, kind), f"expected {kind}, got {type(error).__name__}: {error}"
    assert isinstance(error, Exception), f"not an Exception (a panic?): {error!r}"
    message = str(error)
    fragments = fragment if isinstance(fragment, tuple) else (fragment,)
    assert any(f in message for f in fragments), f"message does not name {fragments}: {message!r}"
    return error


def test_polhode_error_is_a_value_error():
    assert issubclass(ph.PolhodeError, ValueError)


# ---------------------------------------------------------------------------------------------
# omega0
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ALL)
@pytest.mark.parametrize(
    "bad", [(NAN, 0.0, 0.0), (0.0, INF, 0.0), (0.0, 0.0, -INF)], ids=["nan", "inf", "-inf"]
)
def test_omega0_not_finite(method, bad):
    raises(ph.PolhodeError, "omega0", lambda: ph.simulate(MOMENTS, bad, 1.0, method=method, dt=0.1))


@pytest.mark.parametrize(
    "bad",
    [(1.0, 2.0), (1.0, 2.0, 3.0, 4.0), np.zeros((2, 2, 3)), np.zeros((2, 4)), 1.0],
    ids=["(2,)", "(4,)", "(2,2,3)", "(2,4)", "scalar"],
)
def test_omega0_wrong_shape(bad):
    raises(ph.PolhodeError, "omega0", lambda: ph.simulate(MOMENTS, bad, 1.0))


def test_omega0_batch_mismatch():
    moments = np.array([[1.0, 2.0, 3.0], [1.0, 2.0, 2.5]])
    raises(ph.PolhodeError, "omega0", lambda: ph.simulate(moments, np.ones((3, 3)), 1.0))


@pytest.mark.parametrize(
    "bad",
    ["abc", None, {"x": 1}, np.array([1, "a", 3], dtype=object)],
    ids=["str", "None", "dict", "object-array"],
)
def test_omega0_wrong_type(bad):
    raises(TypeError, "omega0", lambda: ph.simulate(MOMENTS, bad, 1.0))


# ---------------------------------------------------------------------------------------------
# dt, method, order, tolerances, max_steps
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", FIXED)
@pytest.mark.parametrize("dt", [0.0, -0.1, NAN, INF, -INF])
def test_dt_not_positive_or_not_finite(method, dt):
    raises(ph.PolhodeError, "dt", lambda: ph.simulate(MOMENTS, W, 1.0, method=method, dt=dt))


@pytest.mark.parametrize("big", [2**63, 2**64, -(2**70)])
@pytest.mark.parametrize(
    ("name", "kwargs"), [("max_steps", {}), ("order", {"method": "splitting", "dt": 0.1})]
)
def test_an_integer_beyond_64_bits_is_an_argument_error(name, kwargs, big):
    # Was an untyped OverflowError from the binding ("Python int too large to convert to C
    # long"), naming no argument.
    raises(ph.ArgumentError, name, lambda: ph.simulate(MOMENTS, W, 1.0, **kwargs, **{name: big}))


@pytest.mark.parametrize("method", FIXED)
def test_dt_missing_for_a_fixed_step_method(method):
    raises(ph.PolhodeError, ("dt", method), lambda: ph.simulate(MOMENTS, W, 1.0, method=method))


@pytest.mark.parametrize("dt", ["0.1", [0.1]], ids=["str", "list"])
def test_dt_wrong_type(dt):
    raises(TypeError, "dt", lambda: ph.simulate(MOMENTS, W, 1.0, method="rk4", dt=dt))


@pytest.mark.parametrize("method", ["euler", "RK4", "", "dop54"])
def test_unknown_method(method):
    raises(
        ph.PolhodeError,
        ("method", repr(method)),
        lambda: ph.simulate(MOMENTS, W, 1.0, method=method),
    )


@pytest.mark.parametrize("method", [3, None], ids=["int", "None"])
def test_method_wrong_type(method):
    raises(TypeError, "method", lambda: ph.simulate(MOMENTS, W, 1.0, method=method, dt=0.1))


@pytest.mark.parametrize("order", [1, 3, 8, 0, -2])
def test_splitting_order_not_2_4_6(order):
    raises(
        ph.PolhodeError,
        "order",
        lambda: ph.simulate(MOMENTS, W, 1.0, method="splitting", dt=0.1, order=order),
    )


def test_splitting_order_wrong_type():
    raises(
        TypeError,
        "order",
        lambda: ph.simulate(MOMENTS, W, 1.0, method="splitting", dt=0.1, order="four"),
    )


def test_splitting_order_not_an_integer():
    """4.5 must not be silently truncated to 4."""
    raises(
        (TypeError, ph.PolhodeError),
        "order",
        lambda: ph.simulate(MOMENTS, W, 1.0, method="splitting", dt=0.1, order=4.5),
    )


@pytest.mark.parametrize(
    ("name", "kw"),
    [
        ("rtol", {"rtol": 0.0}),
        ("rtol", {"rtol": -1e-8}),
        ("rtol", {"rtol": NAN}),
        ("rtol", {"rtol": 1e-20}),
        ("atol", {"atol": 0.0}),
        ("atol", {"atol": -1.0}),
        ("atol", {"atol": INF}),
    ],
)
def test_dop853_tolerances(name, kw):
    raises(ph.PolhodeError, name, lambda: ph.simulate(MOMENTS, W, 1.0, method="dop853", **kw))


@pytest.mark.parametrize("rtol", [1.0, 2.0, 1e300, INF], ids=["1", "2", "1e300", "inf"])
@pytest.mark.parametrize("method", ["dop853", "auto", "rk4", "exact"])
def test_a_relative_tolerance_of_one_or_more_is_refused(method, rtol):
    """Was accepted, and dop853 returned garbage (|L| drifted by 37 at rtol 1, by 1.6e21 at
    1e300). Checked where the core receives it, whatever the method (rk4 does not use it, but
    a user who gives it expects it to mean something)."""
    dt = {"dt": 0.1} if method == "rk4" else {}
    raises(
        ph.PolhodeError,
        "`rtol`",
        lambda: ph.simulate(MOMENTS, W, 1.0, method=method, rtol=rtol, **dt),
    )


def test_a_relative_tolerance_below_one_runs():
    """The largest tolerance below 1 is valid (it asks for little, but for something): the
    energy of a torque-free run is then still the initial one to the solver's few digits."""
    sol = ph.simulate(MOMENTS, W, [0.0, 1.0], method="dop853", rtol=0.5)
    energy = 0.5 * sum(i * w * w for i, w in zip(MOMENTS, W, strict=True))
    assert abs(sol.energy[-1] - energy) <= 0.5 * energy


@pytest.mark.parametrize(
    ("name", "kwargs"),
    [
        ("order", {"method": "rk4", "dt": 0.1, "order": 5}),
        ("dt", {"method": "dop853", "dt": -1.0}),
        ("dt", {"method": "exact", "dt": NAN}),
        ("atol", {"method": "rk4", "dt": 0.1, "atol": -1.0}),
    ],
)
def test_every_setting_given_is_checked_whatever_the_method(name, kwargs):
    """Was ignored by the methods that do not use it."""
    raises(ph.PolhodeError, f"`{name}`", lambda: ph.simulate(MOMENTS, W, 1.0, **kwargs))


def test_rtol_wrong_type():
    raises(TypeError, "rtol", lambda: ph.simulate(MOMENTS, W, 1.0, method="dop853", rtol="tight"))


@pytest.mark.parametrize("method", FIXED)
def test_too_many_fixed_steps_fail_before_integrating(method):
    raises(
        ph.PolhodeError,
        "max_steps",
        lambda: ph.simulate(MOMENTS, W, 1e3, method=method, dt=1e-3, max_steps=1000),
    )


def test_too_many_adaptive_steps():
    raises(
        (RuntimeError, ph.PolhodeError),
        "max_steps",
        lambda: ph.simulate(MOMENTS, W, 1e4, method="dop853", rtol=1e-12, max_steps=10),
    )


@pytest.mark.parametrize("max_steps", [0, -1])
def test_max_steps_not_positive(max_steps):
    raises(
        ph.PolhodeError,
        "max_steps",
        lambda: ph.simulate(MOMENTS, W, 1.0, method="rk4", dt=0.1, max_steps=max_steps),
    )


# ---------------------------------------------------------------------------------------------
# Output times and t0
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ALL)
def test_decreasing_times(method):
    raises(
        ph.PolhodeError,
        "t",
        lambda: ph.simulate(MOMENTS, W, [0.0, 2.0, 1.0], method=method, dt=0.1),
    )


@pytest.mark.parametrize("method", ALL)
def test_times_before_t0(method):
    raises(
        ph.PolhodeError,
        ("t0", "t"),
        lambda: ph.simulate(MOMENTS, W, [0.5, 1.0], t0=1.0, method=method, dt=0.1),
    )


@pytest.mark.parametrize(("end", "t0"), [(-1.0, 0.0), (1.0, 5.0)])
def test_end_time_before_t0(end, t0):
    """A scalar end time is named as such: before, the message spoke of t[1] and t[0], the
    times (t0, t) made of it, which the caller never wrote."""
    error = raises(
        ph.ArgumentError, "an end time", lambda: ph.simulate(MOMENTS, W, end, t0=t0)
    )
    assert error.argument == "t"
    assert f"t0 = {t0:g}" in str(error) and "t[" not in str(error)


@pytest.mark.parametrize("end", [NAN, INF, -INF])
def test_end_time_not_finite_names_t(end):
    error = raises(ph.NonFiniteError, "`t`", lambda: ph.simulate(MOMENTS, W, end))
    assert error.argument == "t" and "t[" not in str(error)


def test_the_trajectory_keeps_its_own_times():
    """Trajectory.t was the caller's array itself: changing it afterwards changed the
    trajectory's times."""
    t = np.linspace(0.0, 1.0, 5)
    sol = ph.simulate(MOMENTS, W, t)
    t[:] = -1.0
    np.testing.assert_array_equal(sol.t, np.linspace(0.0, 1.0, 5))


@pytest.mark.parametrize("flag", ["no", 0, 1, None, np.array([True])])
def test_flags_must_be_bools(flag):
    """bool("no") is True: a flag given as anything but a bool was read by its truth."""
    raises(TypeError, "orientation", lambda: ph.simulate(MOMENTS, W, 1.0, orientation=flag))
    sol = ph.simulate(MOMENTS, W, 1.0)
    raises(TypeError, "degrees", lambda: sol.euler_angles(degrees=flag))
    for name in ("depends_on_orientation", "depends_on_omega"):
        raises(
            TypeError,
            name,
            lambda name=name: ph.torque.Function(lambda t, w, q: (0.0, 0.0, 0.0), **{name: flag}),
        )


def test_numpy_bools_are_flags():
    a = ph.simulate(MOMENTS, W, 1.0, orientation=np.False_)
    assert a.quaternion is None
    sol = ph.simulate(MOMENTS, W, 1.0)
    np.testing.assert_array_equal(
        sol.euler_angles(degrees=np.True_), np.degrees(sol.euler_angles())
    )


@pytest.mark.parametrize(
    "times", [[0.0, NAN], [0.0, INF], INF, NAN], ids=["nan", "inf", "end-inf", "end-nan"]
)
def test_times_not_finite(times):
    raises(ph.PolhodeError, "t", lambda: ph.simulate(MOMENTS, W, times))


@pytest.mark.parametrize("times", [[[0.0, 1.0]], []], ids=["2d", "empty"])
def test_times_wrong_shape(times):
    raises(ph.PolhodeError, "t", lambda: ph.simulate(MOMENTS, W, times))


@pytest.mark.parametrize("times", ["abc", None], ids=["str", "None"])
def test_times_wrong_type(times):
    raises(TypeError, "t", lambda: ph.simulate(MOMENTS, W, times))


@pytest.mark.parametrize("t0", [NAN, INF, -INF])
def test_t0_not_finite(t0):
    raises(ph.PolhodeError, "t0", lambda: ph.simulate(MOMENTS, W, [1.0, 2.0], t0=t0))


def test_t0_wrong_type():
    raises(TypeError, "t0", lambda: ph.simulate(MOMENTS, W, 1.0, t0="now"))


# ---------------------------------------------------------------------------------------------
# Bodies and orientation0
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("method", ["auto", *ALL])
def test_rod_is_singular_for_every_method(method):
    rod = ph.Body.rod(1.0, 2.0)
    raises(
        ph.PolhodeError, ("body", "moment"), lambda: ph.simulate(rod, W, 1.0, method=method, dt=0.1)
    )


@pytest.mark.parametrize(
    "moments",
    [(0.0, 1.0, 1.0), (-1.0, 2.0, 3.0), (1.0, NAN, 3.0), (1.0, 2.0, INF)],
    ids=["zero", "negative", "nan", "inf"],
)
def test_bad_moments(moments):
    raises(ph.PolhodeError, "body", lambda: ph.simulate(moments, W, 1.0))


def test_bad_moment_in_a_batch():
    moments = np.array([[1.0, 2.0, 3.0], [1.0, 0.0, 3.0]])
    raises(ph.PolhodeError, "body", lambda: ph.simulate(moments, W, 1.0, method="rk4", dt=0.1))


@pytest.mark.parametrize(
    "body", [(1.0, 2.0), np.ones((2, 2)), np.ones((2, 3, 3))], ids=["(2,)", "(2,2)", "(2,3,3)"]
)
def test_body_wrong_shape(body):
    raises(ph.PolhodeError, "body", lambda: ph.simulate(body, W, 1.0))


@pytest.mark.parametrize("body", ["box", None], ids=["str", "None"])
def test_body_wrong_type(body):
    raises(TypeError, "body", lambda: ph.simulate(body, W, 1.0))


@pytest.mark.parametrize(
    "orientation0",
    [(1.0, 2.0), (0.0, 0.0, 0.0, 0.0), (NAN, 0, 0, 1), np.ones((3, 3)), np.diag([1.0, 1.0, -1.0])],
    ids=["(2,)", "zero-quaternion", "nan", "singular-matrix", "reflection"],
)
def test_bad_orientation0(orientation0):
    raises(
        ph.PolhodeError,
        "orientation0",
        lambda: ph.simulate(MOMENTS, W, 1.0, orientation0=orientation0),
    )


def test_orientation0_count_mismatch():
    moments = np.array([[1.0, 2.0, 3.0], [1.0, 2.0, 2.5]])
    q = np.tile([0.0, 0.0, 0.0, 1.0], (3, 1))
    omega = np.tile(W, (2, 1))
    raises(
        ph.PolhodeError, "orientation0", lambda: ph.simulate(moments, omega, 1.0, orientation0=q)
    )


# ---------------------------------------------------------------------------------------------
# Torques: models, exact with a torque, callables
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "torque",
    [ph.torque.BodyFixed((0.0, 0.0, 1.0)), ZERO, lambda t, w, q: (0.0, 0.0, 0.0)],
    ids=["model", "Function", "callable"],
)
def test_exact_with_a_torque(torque):
    raises(
        ph.PolhodeError,
        ("torque", "exact"),
        lambda: ph.simulate(MOMENTS, W, 1.0, method="exact", torque=torque),
    )


@pytest.mark.parametrize(
    "torque", [3, "gravity", (0.0, 0.0, 1.0), np.zeros(3)], ids=["int", "str", "tuple", "array"]
)
def test_torque_wrong_type(torque):
    raises(TypeError, "torque", lambda: ph.simulate(MOMENTS, W, 1.0, torque=torque))


BAD_MODELS = [
    ("BodyFixed-shape", lambda: ph.torque.BodyFixed((1.0, 2.0)), ph.PolhodeError, "torque"),
    (
        "BodyFixed-nan",
        lambda: ph.simulate(MOMENTS, W, 1.0, torque=ph.torque.BodyFixed((NAN, 0, 0))),
        ph.PolhodeError,
        "torque",
    ),
    (
        "SpaceFixed-inf",
        lambda: ph.simulate(MOMENTS, W, 1.0, torque=ph.torque.SpaceFixed((INF, 0, 0))),
        ph.PolhodeError,
        "torque",
    ),
    ("SpaceFixed-str", lambda: ph.torque.SpaceFixed("up"), TypeError, "torque"),
    (
        "Window-start-after-end",
        lambda: ph.simulate(MOMENTS, W, 1.0, torque=ph.torque.Window(ZERO, 2.0, 1.0)),
        ph.PolhodeError,
        ("start", "end"),
    ),
    (
        "Window-nan",
        lambda: ph.simulate(MOMENTS, W, 1.0, torque=ph.torque.Window(ZERO, NAN, 1.0)),
        ph.PolhodeError,
        "start",
    ),
    ("Window-str", lambda: ph.torque.Window(ZERO, "soon", 1.0), TypeError, "start"),
    ("Window-not-a-torque", lambda: ph.torque.Window(3, 0.0, 1.0), TypeError, "torque"),
    ("Function-not-callable", lambda: ph.torque.Function(3), TypeError, "torque"),
    (
        "Function-discontinuities",
        lambda: ph.torque.Function(lambda t, w, q: (0, 0, 0), discontinuities=["a"]),
        TypeError,
        "discontinuities",
    ),
    ("Sum-not-a-torque", lambda: ph.torque.Sum([ZERO, 3]), TypeError, "torque"),
    ("Gravity-shape", lambda: ph.torque.Gravity((0.0, -9.81)), ph.PolhodeError, "gravity"),
    (
        "Gravity-nan",
        lambda: ph.simulate(
            ph.Body.cone(1.0, 1.0, 1.0), W, 1.0, torque=ph.torque.Gravity((NAN, 0, 0))
        ),
        ph.PolhodeError,
        "gravity",
    ),
    (
        "Gravity-pivot-nan",
        lambda: ph.simulate(
            ph.Body.cone(1.0, 1.0, 1.0), W, 1.0, torque=ph.torque.Gravity(pivot=(NAN, 0, 0))
        ),
        ph.PolhodeError,
        "pivot",
    ),
    (
        "Gravity-moments-without-mass",
        lambda: ph.simulate(MOMENTS, W, 1.0, torque=ph.torque.Gravity()),
        ph.PolhodeError,
        "mass",
    ),
    (
        "Gravity-mass-negative",
        lambda: ph.simulate(
            MOMENTS, W, 1.0, torque=ph.torque.Gravity(mass=-1.0, center_of_mass=(0, 0, 1))
        ),
        ph.PolhodeError,
        "mass",
    ),
    (
        "Gravity-mass-str",
        lambda: ph.torque.Gravity(mass="heavy", center_of_mass=(0, 0, 1)),
        TypeError,
        "mass",
    ),
    (
        "Gravity-com-nan",
        lambda: ph.simulate(
            MOMENTS, W, 1.0, torque=ph.torque.Gravity(mass=1.0, center_of_mass=(0, 0, NAN))
        ),
        ph.PolhodeError,
        "center_of_mass",
    ),
    (
        # A body hinged at two points: the moments about the first pivot were used for both,
        # and the sum's motion depended on the order of its terms.
        "Gravity-two-pivots",
        lambda: ph.torque.Gravity(pivot=(0, 0, 0.03)) + ph.torque.Gravity(pivot=(0, 0, 0)),
        ph.ArgumentError,
        "pivot",
    ),
    (
        "Gravity-two-pivots-in-a-window",
        lambda: ph.torque.Sum(
            [
                ph.torque.Window(ph.torque.Gravity(pivot=(0, 0, 0.03)), 0.0, 1.0),
                ph.torque.Sum([ph.torque.BodyFixed((0, 0, 1)), ph.torque.Gravity()]),
            ]
        ),
        ph.ArgumentError,
        "pivot",
    ),
    (
        "GravityGradient-nan",
        lambda: ph.simulate(MOMENTS, W, 1.0, torque=ph.torque.GravityGradient(NAN)),
        ph.PolhodeError,
        "mean_motion",
    ),
    (
        "GravityGradient-normal-zero",
        lambda: ph.simulate(
            MOMENTS, W, 1.0, torque=ph.torque.GravityGradient(1.0, orbit_normal=(0, 0, 0))
        ),
        ph.PolhodeError,
        "orbit_normal",
    ),
    (
        "GravityGradient-radial-parallel",
        lambda: ph.simulate(
            MOMENTS, W, 1.0, torque=ph.torque.GravityGradient(1.0, radial0=(0, 0, 2))
        ),
        ph.PolhodeError,
        "radial0",
    ),
]


@pytest.mark.parametrize(
    ("label", "call", "kind", "name"), BAD_MODELS, ids=[b[0] for b in BAD_MODELS]
)
def test_bad_torque_model(label, call, kind, name):
    raises(kind, name, call)


@pytest.mark.parametrize(
    ("given", "unit"),
    [
        ({"orbit_normal": (0.0, 0.0, 1e-300)}, {"orbit_normal": (0.0, 0.0, 1.0)}),
        ({"radial0": (1e-300, 0.0, 0.0)}, {"radial0": (1.0, 0.0, 0.0)}),
        (
            {"radial0": (1e300, 0.0, 1e300), "orbit_normal": (0.0, 1e300, 0.0)},
            {"radial0": (1.0, 0.0, 1.0), "orbit_normal": (0.0, 1.0, 0.0)},
        ),
    ],
    ids=["normal-tiny", "radial-tiny", "huge"],
)
def test_gravity_gradient_directions_of_any_size(given, unit):
    """Directions are taken by their direction: a normal of 1e-300 (its norm underflowed) was
    refused as 'expected a non-zero vector'. The same bits as the unit vectors."""

    def run(kw):
        torque = ph.torque.GravityGradient(1e-3, **kw)
        return ph.simulate(MOMENTS, W, [0.0, 1.0], torque=torque).omega

    np.testing.assert_array_equal(run(given), run(unit))


def test_a_pivot_too_far_names_the_pivot():
    """A Body's inertia about a pivot of 1e200 overflows: the error named body[0, 0], NaN."""
    error = raises(
        ph.ArgumentError,
        "pivot",
        lambda: ph.simulate(
            ph.Body.cone(0.1, 0.04, 0.03),
            (1.0, 2.0, 5.0),
            [0.0, 1.0],
            torque=ph.torque.Gravity(pivot=(1e200, 0.0, 0.0)),
        ),
    )
    assert error.argument == "pivot"


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: ph.torque.Sum(ph.torque.BodyFixed((0.0, 0.0, 1.0))), "terms"),
        (lambda: ph.torque.Sum("ab"), "terms"),
        (
            lambda: ph.torque.Function(lambda t, w, q: (0.0, 0.0, 0.0), discontinuities=0.5),
            "discontinuities",
        ),
    ],
    ids=["Sum-of-one-torque", "Sum-of-str", "discontinuities-number"],
)
def test_sequences_that_are_not(call, name):
    """Were TypeErrors from Python's iteration ("'BodyFixed' object is not iterable")."""
    raises(TypeError, f"`{name}`", call)


def test_gravity_terms_with_one_pivot_add_up():
    """Two Gravity terms about the same pivot (the default's origin given or not) are one of
    twice the field."""
    top = ph.Body.cone(0.1, 0.04, 0.03)
    g = np.array([0.0, 0.0, -4.905])
    pair = ph.torque.Gravity(g, pivot=(0, 0, 0)) + ph.torque.Gravity(g)
    a = ph.simulate(top, (1.0, 2.0, 5.0), [0.0, 1.0], torque=pair, rtol=1e-12)
    b = ph.simulate(top, (1.0, 2.0, 5.0), [0.0, 1.0], torque=ph.torque.Gravity(2 * g), rtol=1e-12)
    np.testing.assert_allclose(a.omega, b.omega, rtol=1e-9, atol=1e-12)


def test_adding_a_non_torque():
    with pytest.raises(TypeError):
        ph.torque.BodyFixed((0.0, 0.0, 1.0)) + 3  # noqa: B018


class Boom(RuntimeError):
    """A user's own exception."""


def _boom(t, w, q):
    if t > 0.25:
        raise Boom("kaboom at t > 0.25")
    return (0.0, 0.0, 0.1)


@pytest.mark.parametrize("method", ["dop853", *FIXED])
def test_callable_that_raises_propagates(method):
    with pytest.raises(Boom, match="kaboom"):
        ph.simulate(MOMENTS, W, 1.0, method=method, dt=0.1, torque=_boom)


def test_callable_that_raises_in_a_batch_propagates():
    moments = np.array([[1.0, 2.0, 3.0], [1.5, 2.0, 3.0], [1.0, 2.5, 3.0], [1.0, 2.0, 2.5]])
    with pytest.raises(Boom, match="kaboom"):
        ph.simulate(moments, np.tile(W, (4, 1)), 1.0, method="rk4", dt=0.1, torque=_boom)


def test_callable_that_raises_on_a_body_in_non_principal_axes():
    from scipy.spatial.transform import Rotation

    box = ph.Body.cuboid(1.0, (1.0, 2.0, 3.0)).rotated(Rotation.from_rotvec([0.2, 0.3, 0.4]))
    with pytest.raises(Boom, match="kaboom"):
        ph.simulate(box, W, 1.0, method="dop853", torque=_boom)


def test_callable_that_raises_inside_a_window_and_a_sum():
    torque = ph.torque.Window(_boom, 0.0, 5.0) + ph.torque.BodyFixed((0.0, 0.0, 0.1))
    with pytest.raises(Boom, match="kaboom"):
        ph.simulate(MOMENTS, W, 1.0, method="rk4", dt=0.1, torque=torque)


def test_callable_with_the_wrong_signature_propagates_its_type_error():
    with pytest.raises(TypeError, match="positional argument"):
        ph.simulate(MOMENTS, W, 1.0, torque=lambda t: (0.0, 0.0, 0.0))


WRONG_SHAPES = [(0.0, 0.0), (0.0, 0.0, 0.0, 1.0), 1.0, np.zeros((2, 3))]


@pytest.mark.parametrize("value", WRONG_SHAPES, ids=["(2,)", "(4,)", "scalar", "(2,3)"])
def test_callable_returning_the_wrong_shape(value):
    raises(
        ph.PolhodeError,
        "torque",
        lambda: ph.simulate(MOMENTS, W, 1.0, method="rk4", dt=0.1, torque=lambda t, w, q: value),
    )


@pytest.mark.parametrize(
    "value",
    [
        None,
        "abc",
        {"x": 1},
        ["a", "b", "c"],
        # numpy's own conversion read these silently: the real part of complex numbers, digit
        # strings and dates as numbers, None as NaN ("got NaN"), the data under a mask.
        np.array([0.0, 0.0, 1j]),
        ["0", "0", "1"],
        np.array(["2020-01-01"] * 3, dtype="datetime64[D]"),
        [0.0, None, 1.0],
        np.ma.masked_array([0.0, 0.0, 1.0], mask=[False, True, False]),
    ],
    ids=["None", "str", "dict", "strs", "complex", "digits", "dates", "None-inside", "masked"],
)
def test_callable_returning_the_wrong_type(value):
    raises(TypeError, "torque", lambda: ph.simulate(MOMENTS, W, 1.0, torque=lambda t, w, q: value))


def test_callable_returning_real_numbers_of_any_kind():
    """Fractions, numpy scalars of any width, tuples and a mask with nothing masked are
    numbers: the same motion as floats."""
    from fractions import Fraction

    expected = ph.simulate(MOMENTS, W, 1.0, torque=lambda t, w, q: (0.5, 0.0, 0.25))
    for value in (
        [Fraction(1, 2), 0, Fraction(1, 4)],
        np.array([0.5, 0.0, 0.25], dtype=np.float32),
        np.ma.masked_array([0.5, 0.0, 0.25]),
    ):
        sol = ph.simulate(MOMENTS, W, 1.0, torque=lambda t, w, q, v=value: v)
        np.testing.assert_array_equal(sol.omega, expected.omega)


@pytest.mark.parametrize("method", ["dop853", *FIXED])
@pytest.mark.parametrize("value", [NAN, INF], ids=["nan", "inf"])
def test_callable_returning_non_finite(method, value):
    raises(
        ph.PolhodeError,
        "torque",
        lambda: ph.simulate(
            MOMENTS, W, 1.0, method=method, dt=0.1, torque=lambda t, w, q: (value, 0.0, 0.0)
        ),
    )


# ---------------------------------------------------------------------------------------------
# No silent NaN
# ---------------------------------------------------------------------------------------------


def test_fixed_step_blow_up_is_an_error():
    raises(
        ph.PolhodeError,
        ("blew up", "omega"),
        lambda: ph.simulate(MOMENTS, (10.0, 20.0, 30.0), 1e4, method="rk4", dt=10.0),
    )


def _explosive(t, w, q):
    with np.errstate(over="ignore", invalid="ignore"):
        return 1e10 * np.asarray(w) * np.abs(w)


@pytest.mark.parametrize("method", FIXED)
def test_torque_blow_up_is_an_error(method):
    """w' ~ 1e10 w|w| blows up in finite time: an error, not NaN in the output."""
    raises(
        (ph.PolhodeError, RuntimeError),
        ("torque", "omega", "converge"),
        lambda: ph.simulate(MOMENTS, W, [0.0, 10.0], method=method, dt=0.1, torque=_explosive),
    )


def test_adaptive_blow_up_is_an_error():
    raises(
        (RuntimeError, ph.PolhodeError),
        ("dop853", "step", "torque"),
        lambda: ph.simulate(MOMENTS, W, 10.0, method="dop853", torque=_explosive),
    )


@pytest.mark.parametrize("method", ALL)
def test_results_are_finite_on_valid_input(method):
    """Edge inputs that are valid: rest, a sphere, huge and tiny scales: finite results."""
    for moments, omega0 in [
        (MOMENTS, (0.0, 0.0, 0.0)),
        ((1.0, 1.0, 1.0), W),
        ((1e-30, 2e-30, 3e-30), W),
        ((1e30, 2e30, 3e30), (1e-20, 0, 1e-20)),
        (MOMENTS, (1e-150, 1e-150, 1e-150)),
    ]:
        sol = ph.simulate(moments, omega0, [0.0, 0.5, 1.0], method=method, dt=0.01)
        for name in ("omega", "quaternion", "angular_momentum_space", "energy"):
            assert np.all(np.isfinite(getattr(sol, name))), (method, moments, omega0, name)


# ---------------------------------------------------------------------------------------------
# analyze
# ---------------------------------------------------------------------------------------------

ANALYZE_ERRORS = [
    ("batch", lambda: ph.analyze(np.ones((2, 3)), W), ph.PolhodeError, "body"),
    ("omega-nan", lambda: ph.analyze(MOMENTS, (NAN, 0.0, 0.0)), ph.PolhodeError, "omega0"),
    ("omega-shape", lambda: ph.analyze(MOMENTS, (1.0, 0.0)), ph.PolhodeError, "omega0"),
    ("omega-batch", lambda: ph.analyze(MOMENTS, np.ones((2, 3))), ph.PolhodeError, "omega0"),
    ("omega-str", lambda: ph.analyze(MOMENTS, "abc"), TypeError, "omega0"),
    ("rod", lambda: ph.analyze(ph.Body.rod(1.0, 2.0), W), ph.PolhodeError, "body"),
    ("zero-moment", lambda: ph.analyze((0.0, 1.0, 1.0), W), ph.PolhodeError, "body"),
    ("body-str", lambda: ph.analyze("box", W), TypeError, "body"),
    ("body-shape", lambda: ph.analyze((1.0, 2.0), W), ph.PolhodeError, "body"),
]


@pytest.mark.parametrize(
    ("label", "call", "kind", "name"), ANALYZE_ERRORS, ids=[a[0] for a in ANALYZE_ERRORS]
)
def test_analyze_errors(label, call, kind, name):
    raises(kind, name, call)


@pytest.mark.parametrize("m", [3, 10_000])
@pytest.mark.parametrize("moments", [(1e308, 1e308, 1e308), (1e308, 0.5e308, 0.7e308)])
def test_an_exact_output_that_overflows_names_its_quantity_and_time(moments, m):
    # |L| = 1e308 along the body's x axis, turned half a turn about y: omega, L in body axes
    # and T are finite, L in space (2 v x L on the way, v the quaternion's vector part) is not.
    # 10 000 output times are evaluated in parallel chunks, 3 on the calling thread: the same
    # error, at the first time.
    t = np.linspace(0.0, 1.0, m)
    error = raises(
        ph.NonFiniteError,
        "`angular_momentum_space` is -inf",
        lambda: ph.simulate(
            moments, (1.0, 0.0, 0.0), t, method="exact", orientation0=(0.0, 1.0, 0.0, 0.0)
        ),
    )
    assert "t = 0:" in str(error)


@pytest.mark.parametrize("method", ["rk4", "midpoint", "dop853"])
@pytest.mark.parametrize("batch", [False, True])
def test_an_integrated_output_that_overflows_names_its_quantity_and_time(method, batch):
    # As for the exact solution: omega, L in body axes and T are finite, L in space is not.
    # The rows are written, then checked finite at once; the error still names the quantity
    # (the first non-finite one in column order), the time and, in a batch, the body.
    t = np.linspace(0.0, 0.01, 3)
    moments, omega0 = np.array([1e308, 1e308, 1e308]), np.array([1.0, 0.0, 0.0])
    if batch:
        moments = np.stack([(1.0, 2.0, 3.0), moments, (1.0, 2.0, 3.0)])
        omega0 = np.stack([omega0, omega0, omega0])
    error = raises(
        ph.NonFiniteError,
        "`angular_momentum_space` is -inf",
        lambda: ph.simulate(
            moments, omega0, t, method=method, dt=1e-3, orientation0=(0.0, 1.0, 0.0, 0.0)
        ),
    )
    assert "t = 0:" in str(error)
    assert (error.body == 1) if batch else (error.body is None)


@pytest.mark.parametrize("call", ["simulate", "analyze"])
def test_a_moment_without_a_reciprocal_is_named_as_too_small(call):
    # 1e-310 is finite and positive, but its reciprocal overflows: the error said the body
    # was not finite ("Expected `body` to be finite, got inf").
    moments, omega0 = (1e-310, 2.0, 3.0), (0.0, 0.0, 1.0)
    run = {
        "simulate": lambda: ph.simulate(moments, omega0, [0.0, 1.0]),
        "analyze": lambda: ph.analyze(moments, omega0),
    }[call]
    error = raises(ph.ArgumentError, "too small for Euler's equations", run)
    assert error.argument == "body"
