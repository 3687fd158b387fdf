"""The boundary between Python and the core: a shape has one meaning, models are stateless,
torques on bodies in non-principal axes are rotated right, errors are typed with attributes.

References are independent of polhode: scipy integrations of Euler's equations in the body's
own axes with the full inertia tensor (tests/reference.py), and single-body runs for batches.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from reference import rigid_body, rotate_by_quaternion

METHODS = {
    "exact": {},
    "splitting": {"dt": 1e-2},
    "midpoint": {"dt": 1e-2},
    "rk4": {"dt": 1e-2},
    "dop853": {"rtol": 1e-12},
}

# ---------------------------------------------------------------------------------------------
# omega0's shape decides: (N, 3) is N bodies for every N, 3 included
# ---------------------------------------------------------------------------------------------

THREE = np.array([[3.0, 1.0, 1.5], [1.0, 3.0, 2.0], [1.2, 1.1, 3.0]])
OMEGA3 = np.array([[0.3, 1.0, 0.2], [1.0, -0.4, 0.5], [0.1, 0.2, 2.0]])


@pytest.mark.parametrize("method", METHODS)
def test_three_bodies_are_three_bodies(method):
    """Rows of a (3, 3) `body` with (3, 3) `omega0` are three bodies' principal moments, not
    one inertia tensor: each row equals its body run alone, bit for bit."""
    t = np.linspace(0.0, 2.0, 5)
    batch = ph.simulate(THREE, OMEGA3, t, method=method, **METHODS[method])
    assert batch.omega.shape == (3, 5, 3)
    np.testing.assert_array_equal(batch.moments, THREE)
    for k in range(3):
        alone = ph.simulate(THREE[k], OMEGA3[k], t, method=method, **METHODS[method])
        for name in ("omega", "quaternion", "angular_momentum_space", "energy", "moments"):
            np.testing.assert_array_equal(getattr(batch, name)[k], getattr(alone, name))


def test_the_issue_example_is_three_bodies():
    ones = np.ones((3, 3))
    sol = ph.simulate([[3, 1, 1], [1, 3, 1], [1, 1, 3]], ones, [0, 1])
    np.testing.assert_array_equal(sol.moments, [[3, 1, 1], [1, 3, 1], [1, 1, 3]])
    # As one inertia tensor it would have been moments (2, 2, 5) for all three.
    assert not np.allclose(sol.moments, [2.0, 2.0, 5.0])


def test_a_tensor_is_one_body_only():
    tensor = [[3.0, 1.0, 0.0], [1.0, 3.0, 0.0], [0.0, 0.0, 5.0]]
    one = ph.simulate(tensor, [0.1, 0.2, 0.3], 1.0)
    np.testing.assert_allclose(one.moments, [2.0, 4.0, 5.0], rtol=1e-15)
    with pytest.raises(ph.ShapeError) as info:
        ph.simulate(tensor, np.ones((4, 3)), 1.0)
    assert info.value.argument == "body"
    with pytest.raises(ph.ShapeError) as info:
        ph.simulate(THREE[:2], [0.1, 0.2, 0.3], 1.0)
    assert info.value.argument == "body" and "(N, 3)" in str(info.value)


def test_one_body_shared_by_n_rows_of_omega0():
    body = ph.Body.cuboid(1.0, (1.0, 2.0, 3.0)).rotated(Rotation.from_rotvec([0.2, 0.3, 0.1]))
    sweep = ph.simulate(body, OMEGA3, [0.0, 1.0])
    for k in range(3):
        alone = ph.simulate(body, OMEGA3[k], [0.0, 1.0])
        np.testing.assert_array_equal(sweep.omega[k], alone.omega)
    bodies = [body, body.translated([1.0, 0.0, 0.0]), ph.Body.sphere(1.0, 1.0)]
    listed = ph.simulate(bodies, OMEGA3, [0.0, 1.0])
    for k in range(3):
        alone = ph.simulate(bodies[k], OMEGA3[k], [0.0, 1.0])
        np.testing.assert_array_equal(listed.quaternion[k], alone.quaternion)


def test_a_batch_of_one_keeps_its_axis():
    sol = ph.simulate(THREE[:1], OMEGA3[:1], [0.0, 1.0])
    assert sol.omega.shape == (1, 2, 3) and sol.stats["steps"].shape == (1,)


def test_dask_blocks_of_three_rows():
    phd = pytest.importorskip("polhode.dask")
    da = pytest.importorskip("dask.array")
    rng = np.random.default_rng(3)
    moments = np.sort(rng.uniform(1.0, 3.0, (9, 3)), axis=1)
    omega0 = rng.normal(size=(9, 3))
    expected = ph.simulate(moments, omega0, [0.0, 0.5, 1.0], method="rk4", dt=0.01)
    for chunks in (3, 1):
        lazy = phd.simulate(
            da.from_array(moments, chunks=chunks),
            da.from_array(omega0, chunks=chunks),
            [0.0, 0.5, 1.0],
            method="rk4",
            dt=0.01,
        )
        got = lazy.compute(scheduler="sync")
        np.testing.assert_array_equal(got.omega, expected.omega)
        np.testing.assert_array_equal(got.moments, moments)


# ---------------------------------------------------------------------------------------------
# Torques on a body in non-principal axes, for every model, against an independent integration
# in the body's own axes with the full tensor
# ---------------------------------------------------------------------------------------------

ROTATION = Rotation.from_rotvec([0.4, -0.7, 0.5])
TILT = Rotation.from_rotvec([0.3, 0.2, -0.1]).as_quat()
TIMES = np.linspace(0.0, 2.0, 9)


def _gravity_gradient(n, normal, radial0, inertia):
    k = np.asarray(normal, float) / np.linalg.norm(normal)
    r0 = np.asarray(radial0, float)
    r0 = r0 - k * (k @ r0)
    r0 /= np.linalg.norm(r0)
    along = np.cross(k, r0)

    def tau(t, w, q):
        r_space = r0 * np.cos(n * t) + along * np.sin(n * t)
        r = rotate_by_quaternion(q * [-1, -1, -1, 1], r_space)  # R^T r_space
        return 3.0 * n * n * np.cross(r, inertia @ r)

    return tau


def _cases():
    """(name, torque model, independent torque(t, w, q, inertia), breaks)."""
    v = np.array([0.3, -0.2, 0.5])
    s = np.array([-0.1, 0.4, 0.2])
    return [
        ("BodyFixed", ph.torque.BodyFixed(v), lambda t, w, q, i: v, ()),
        (
            "SpaceFixed",
            ph.torque.SpaceFixed(s),
            lambda t, w, q, i: rotate_by_quaternion(q * [-1, -1, -1, 1], s),
            (),
        ),
        (
            "GravityGradient",
            ph.torque.GravityGradient(1.3, orbit_normal=(0.1, 0.2, 1.0), radial0=(1.0, 0.3, 0.0)),
            lambda t, w, q, i: _gravity_gradient(1.3, (0.1, 0.2, 1.0), (1.0, 0.3, 0.0), i)(t, w, q),
            (),
        ),
        (
            "Window",
            ph.torque.Window(ph.torque.BodyFixed(v), 0.5, 1.25),
            lambda t, w, q, i: v if 0.5 <= t < 1.25 else np.zeros(3),
            (0.5, 1.25),
        ),
        (
            "Sum",
            ph.torque.BodyFixed(v) + ph.torque.SpaceFixed(s),
            lambda t, w, q, i: v + rotate_by_quaternion(q * [-1, -1, -1, 1], s),
            (),
        ),
        (
            "Function",
            ph.torque.Function(lambda t, w, q: -0.2 * np.asarray(w) + [0.0, 0.1 * t, 0.0]),
            lambda t, w, q, i: -0.2 * w + np.array([0.0, 0.1 * t, 0.0]),
            (),
        ),
    ]


@pytest.mark.parametrize("method", ["dop853", "rk4", "splitting", "midpoint"])
@pytest.mark.parametrize("case", _cases(), ids=lambda c: c[0])
def test_torque_in_body_axes(case, method):
    name, model, reference_torque, breaks = case
    body = ph.Body.cuboid(2.0, (1.0, 1.6, 2.5)).rotated(ROTATION)
    inertia = body.inertia
    assert np.abs(inertia - np.diag(np.diag(inertia))).max() > 0.05  # truly non-principal
    omega0 = np.array([0.4, -0.9, 0.6])
    settings = {"dop853": {"rtol": 1e-12}}.get(method, {"dt": 1e-3})
    sol = ph.simulate(body, omega0, TIMES, orientation0=TILT, torque=model, method=method,
                      **settings)
    w_ref, q_ref = rigid_body(
        inertia, omega0, TILT, TIMES, lambda t, w, q: reference_torque(t, w, q, inertia), breaks
    )
    # Each method's own error at these settings (order 2 for the midpoint rule); a torque
    # left unrotated, or rotated the wrong way, is off by about 0.1.
    bound = {"dop853": 1e-8, "rk4": 1e-9, "splitting": 1e-8, "midpoint": 1e-6}[method]
    scale = np.abs(w_ref).max()
    assert np.abs(sol.omega - w_ref).max() <= bound * scale, name
    aligned = np.sign(np.sum(sol.quaternion * q_ref, axis=1))[:, None]
    assert np.abs(sol.quaternion - aligned * q_ref).max() <= bound, name


def test_heavy_top_in_non_principal_axes():
    """Gravity on a Body with a pivot: the moments about the pivot, the mass and centre of mass
    from the body, all in its own (non-principal) axes."""
    body = (ph.Body.cone(1.0, 0.3, 1.0) + ph.Body.sphere(0.5, 0.1).translated([0.2, 0.0, 0.4]))
    body = body.rotated(ROTATION)
    pivot = np.array([0.05, -0.1, 0.0])
    g = np.array([0.0, 0.0, -9.81])
    model = ph.torque.Gravity(g, pivot=pivot)
    omega0 = np.array([0.5, -0.3, 8.0])
    sol = ph.simulate(body, omega0, TIMES, orientation0=TILT, torque=model, rtol=1e-12)
    inertia = body.inertia_about(pivot)
    r = body.center_of_mass - pivot

    def tau(t, w, q):
        return np.cross(r, body.mass * rotate_by_quaternion(q * [-1, -1, -1, 1], g))

    w_ref, q_ref = rigid_body(inertia, omega0, TILT, TIMES, tau)
    assert np.abs(sol.omega - w_ref).max() <= 1e-8 * np.abs(w_ref).max()


# ---------------------------------------------------------------------------------------------
# Models are stateless values
# ---------------------------------------------------------------------------------------------


def test_a_reused_gravity_equals_a_fresh_one():
    heavy = ph.Body.cone(1.0, 0.3, 1.0)
    light = ph.Body.cylinder(0.2, 0.05, 0.6).translated([0.0, 0.0, 0.3])
    shared = ph.torque.Gravity(pivot=[0.0, 0.0, 0.0])
    kwargs = {"orientation0": TILT, "rtol": 1e-10}
    ph.simulate(heavy, [0.0, 0.0, 20.0], [0.0, 1.0], torque=shared, **kwargs)
    again = ph.simulate(light, [0.0, 0.0, 20.0], [0.0, 1.0], torque=shared, **kwargs)
    fresh = ph.simulate(
        light, [0.0, 0.0, 20.0], [0.0, 1.0], torque=ph.torque.Gravity(pivot=[0.0, 0.0, 0.0]),
        **kwargs,
    )
    np.testing.assert_array_equal(again.omega, fresh.omega)
    # With bare moments the earlier body's mass must not be used: mass and centre of mass
    # are required.
    with pytest.raises(ph.ArgumentError) as info:
        ph.simulate([1.0, 1.0, 0.5], [0.0, 0.0, 20.0], 1.0, torque=shared)
    assert info.value.argument == "torque" and "center_of_mass" in str(info.value)


def test_models_are_immutable():
    g = ph.torque.Gravity()
    with pytest.raises(AttributeError):
        g.mass = 3.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        g.gravity[2] = 1.0


def test_bad_model_parameters_fail_where_made():
    with pytest.raises(ph.NonFiniteError) as info:
        ph.torque.Gravity([0.0, np.nan, -9.81])
    assert info.value.argument == "gravity"
    with pytest.raises(ph.ArgumentError) as info:
        ph.torque.GravityGradient(1.0, orbit_normal=(0, 0, 1), radial0=(0, 0, 2))
    assert info.value.argument == "radial0"


# ---------------------------------------------------------------------------------------------
# Structured errors
# ---------------------------------------------------------------------------------------------


def test_errors_carry_argument_and_body():
    omega = np.ones((4, 3))
    omega[2, 1] = np.nan
    with pytest.raises(ph.NonFiniteError) as info:
        ph.simulate(np.tile([1.0, 2.0, 3.0], (4, 1)), omega, 1.0)
    error = info.value
    assert (error.argument, error.body) == ("omega0", 2)
    assert str(error).startswith("body 2: ")
    with pytest.raises(ph.NonFiniteError) as info:
        ph.simulate([1.0, 2.0, 3.0], [1.0, np.nan, 0.0], 1.0)
    assert (info.value.argument, info.value.body) == ("omega0", None)
    with pytest.raises(ph.ArgumentError) as info:
        ph.simulate([1.0, 2.0, 3.0], [1.0, 0.0, 0.0], [0.0, 2.0, 1.0])
    assert info.value.argument == "t"


def test_errors_pickle_with_their_attributes():
    error = ph.NonPositiveError("Expected `dt` to be positive, got 0.", argument="dt", body=7)
    back = pickle.loads(pickle.dumps(error))
    assert type(back) is ph.NonPositiveError
    assert (back.argument, back.body, str(back)) == ("dt", 7, str(error))


def test_a_failed_newton_iteration_is_a_convergence_error():
    with pytest.raises(ph.ConvergenceError) as info:
        ph.simulate([1.0, 2.0, 3.0], [30.0, 40.0, 50.0], 10.0, method="midpoint", dt=0.2)
    assert isinstance(info.value, ph.PolhodeError)
