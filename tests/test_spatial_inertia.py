"""Body.spatial_inertia and Body.from_spatial_inertia.

References: the 6x6 matrix written here from its definition (the momentum of a rigid body
moving with (omega, v) at the reference point is (h, p) = (I_p omega + m c x v, m (v + omega x
c))), the kinetic energy of that motion from the centroidal form 1/2 m |v_c|^2 + 1/2 omega . I_c
omega, numpy's matrix inverse, and the values printed by Drake's own unit test of
SpatialInertia (mass 2.5, centre of mass (0.1, -0.2, 0.3), unit inertia moments (2.0, 2.3, 2.4)
and products (0.1, -0.1, 0.2) about the reference point).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.errors import ArgumentError, InertiaError, NonFiniteError, NonPositiveError, ShapeError

EPS = np.finfo(float).eps


def cross(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]], dtype=float)


def by_definition(mass, com, inertia_c, point):
    """Featherstone's matrix from the momentum of a rigid motion, column by column: the
    response (h, p) to a unit omega or a unit v at ``point``."""
    c = np.asarray(com, float) - np.asarray(point, float)
    out = np.empty((6, 6))
    for k in range(6):
        omega, v = np.zeros(3), np.zeros(3)
        (omega if k < 3 else v)[k % 3] = 1.0
        v_c = v + np.cross(omega, c)  # velocity of the centre of mass
        p = mass * v_c
        h = inertia_c @ omega + np.cross(c, p)  # angular momentum about the point
        out[:, k] = np.concatenate([h, p])
    return out


def sample_bodies():
    rng = np.random.default_rng(7)
    bodies = [
        ph.Body.cuboid(2.0, [0.3, 0.2, 0.1]),
        ph.Body.cylinder(1.5, 0.05, 0.4).rotated(Rotation.from_euler("xyz", [0.3, 0.2, 0.1])),
        ph.Body.cuboid(3.0, [0.1, 0.2, 0.3]).translated([0.1, 0.0, 0.2]),
    ]
    for _ in range(5):
        c = rng.uniform(0.05, 1.0, 3)
        m = float(rng.uniform(0.5, 5.0))
        body = ph.Body.from_inertia(m, m * (c.sum() * np.eye(3) - np.diag(c)))
        bodies.append(body.rotated(Rotation.random(random_state=rng.integers(1 << 31))))
        bodies[-1] = bodies[-1].translated(rng.normal(size=3))
    return bodies


@pytest.mark.parametrize("index", range(8))
@pytest.mark.parametrize("point", [None, (0.3, -0.2, 0.5), "com"])
def test_featherstone_and_drake_against_the_definition(index, point):
    body = sample_bodies()[index]
    p = np.zeros(3) if point is None else body.center_of_mass if point == "com" else point
    expected = by_definition(body.mass, body.center_of_mass, body.inertia, p)
    args = () if point is None else (p,)
    scale = np.abs(expected).max()
    for convention in ("featherstone", "drake"):
        s = body.spatial_inertia(*args, convention=convention)
        assert np.abs(s - expected).max() <= 16 * EPS * scale
        assert np.array_equal(s, s.T)


@pytest.mark.parametrize("index", range(8))
def test_pinocchio_is_linear_first(index):
    body = sample_bodies()[index]
    f = by_definition(body.mass, body.center_of_mass, body.inertia, np.zeros(3))
    # Pinocchio's (v, omega) order: the same matrix with the blocks exchanged.
    swap = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
    expected = swap @ f @ swap
    s = body.spatial_inertia(convention="pinocchio")
    assert np.abs(s - expected).max() <= 16 * EPS * np.abs(expected).max()
    # Pinocchio's layout: m 1 top left, -m [c] top right, m [c] bottom left.
    m, c = body.mass, body.center_of_mass
    assert np.allclose(s[:3, :3], m * np.eye(3), rtol=0, atol=0)
    assert np.allclose(s[:3, 3:], -m * cross(c), rtol=4 * EPS, atol=0)


@pytest.mark.parametrize("index", range(8))
def test_kinetic_energy(index):
    body = sample_bodies()[index]
    rng = np.random.default_rng(index)
    point = rng.normal(size=3)
    omega, v = rng.normal(size=3), rng.normal(size=3)
    c = body.center_of_mass - point
    v_c = v + np.cross(omega, c)
    energy = 0.5 * body.mass * v_c @ v_c + 0.5 * omega @ body.inertia @ omega
    s = body.spatial_inertia(point)
    twist = np.concatenate([omega, v])
    assert 0.5 * twist @ s @ twist == pytest.approx(energy, rel=1e-13)


def test_drakes_unit_test_values():
    # Drake's SpatialInertia test: mass 2.5, com (0.1, -0.2, 0.3) and unit inertia G about the
    # reference point P (moments 2.0, 2.3, 2.4; products Ixy 0.1, Ixz -0.1, Iyz 0.2), whose
    # CopyToFullMatrix6 is [[m G, m [com]], [m [com]^T, m 1]] and whose printed I is
    # [[5, 0.25, -0.25], [0.25, 5.75, 0.5], [-0.25, 0.5, 6]].
    mass, com = 2.5, np.array([0.1, -0.2, 0.3])
    printed = np.array([[5.0, 0.25, -0.25], [0.25, 5.75, 0.5], [-0.25, 0.5, 6.0]])
    about_com = printed - mass * (com @ com * np.eye(3) - np.outer(com, com))
    body = ph.Body.from_inertia(mass, about_com, com)
    s = body.spatial_inertia(convention="drake")
    expected = np.block([[printed, mass * cross(com)], [mass * cross(com).T, mass * np.eye(3)]])
    assert np.abs(s - expected).max() <= 16 * EPS * 6.0


@pytest.mark.parametrize("index", range(8))
@pytest.mark.parametrize("convention", ["featherstone", "drake", "pinocchio"])
def test_round_trip(index, convention):
    body = sample_bodies()[index]
    for point in (None, body.center_of_mass, np.array([1.0, -2.0, 0.5])):
        p = np.zeros(3) if point is None else point
        s = body.spatial_inertia(point, convention=convention)
        again = ph.Body.from_spatial_inertia(s, point, convention=convention)
        # I_c = I_p - m [c][c]^T: the error is eps ||I_p||, not eps ||I_c||.
        about_point = body.inertia_about(p)
        assert abs(again.mass - body.mass) <= 4 * EPS * body.mass
        d = np.linalg.norm(body.center_of_mass - p)
        assert np.linalg.norm(again.center_of_mass - body.center_of_mass) <= 8 * EPS * (
            d + np.linalg.norm(p)
        ) + 8 * EPS * np.linalg.norm(body.center_of_mass)
        assert np.abs(again.inertia - body.inertia).max() <= 32 * EPS * np.abs(about_point).max()
        if point is not None and point is body.center_of_mass:
            # About the centre of mass nothing cancels: exact to a few eps of I_c.
            assert (
                np.abs(again.inertia - body.inertia).max() <= 4 * EPS * np.abs(body.inertia).max()
            )


@pytest.mark.parametrize("index", range(8))
@pytest.mark.parametrize("convention", ["featherstone", "pinocchio"])
def test_inverse(index, convention):
    body = sample_bodies()[index]
    point = np.array([0.2, 0.1, -0.3])
    s = body.spatial_inertia(point, convention=convention)
    inverse = body.spatial_inertia(point, convention=convention, inverse=True)
    expected = np.linalg.inv(s)
    condition = np.linalg.cond(s)
    assert np.abs(inverse - expected).max() <= 64 * EPS * condition * np.abs(expected).max()
    assert np.abs(inverse @ s - np.eye(6)).max() <= 64 * EPS * condition


def test_inverse_of_a_rod_is_refused():
    with pytest.raises(InertiaError, match="singular"):
        ph.Body.rod(1.0, 1.0).spatial_inertia(inverse=True)


def good_matrix():
    return ph.Body.cuboid(2.0, [0.3, 0.2, 0.1]).translated([0.1, 0.2, 0.3]).spatial_inertia()


def test_errors_name_the_matrix():
    s = good_matrix()
    with pytest.raises(ShapeError) as caught:
        ph.Body.from_spatial_inertia(s[:5, :5])
    assert caught.value.argument == "matrix"
    bad = s.copy()
    bad[0, 4] += 1e-3
    with pytest.raises(InertiaError, match="symmetric") as caught:
        ph.Body.from_spatial_inertia(bad)
    assert caught.value.argument == "matrix"
    bad = s.copy()
    bad[3, 3] += 0.1
    with pytest.raises(InertiaError, match="mass block"):
        ph.Body.from_spatial_inertia(bad)
    bad = s.copy()
    bad[0, 3] = bad[3, 0] = 0.5  # the coupling block must be skew
    with pytest.raises(InertiaError, match="coupling"):
        ph.Body.from_spatial_inertia(bad)
    bad = s.copy()
    bad[3:, 3:] *= -1
    with pytest.raises(NonPositiveError):
        ph.Body.from_spatial_inertia(bad)
    bad = s.copy()
    bad[:3, :3] = np.diag([1.0, 1.0, 3.0])  # the implied I_c breaks the triangle inequality
    with pytest.raises(InertiaError, match="triangle") as caught:
        ph.Body.from_spatial_inertia(bad)
    assert caught.value.argument == "matrix"
    bad = s.copy()
    bad[:3, :3] = -np.eye(3)  # not positive semidefinite
    with pytest.raises(InertiaError):
        ph.Body.from_spatial_inertia(bad)
    bad = s.copy()
    bad[1, 1] = np.nan
    with pytest.raises(NonFiniteError):
        ph.Body.from_spatial_inertia(bad)
    with pytest.raises(ArgumentError) as caught:
        ph.Body.from_spatial_inertia(s, convention="roy")
    assert caught.value.argument == "convention"
    with pytest.raises(ArgumentError):
        ph.Body.cuboid(1.0, [1, 1, 1]).spatial_inertia(convention="angular_first")
    with pytest.raises(TypeError):
        ph.Body.from_spatial_inertia("matrix")


def _point_mass_spatial(c):
    """The textbook spatial inertia (Featherstone) of a unit point mass at c, by hand."""
    c = np.asarray(c, dtype=float)
    x = np.array([[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]])
    return np.block([[c @ c * np.eye(3) - np.outer(c, c), x], [x.T, np.eye(3)]])


@pytest.mark.parametrize(
    "make",
    [
        lambda: (_point_mass_spatial([0.1, 0.2, 0.3]), np.zeros((3, 3)), [0.1, 0.2, 0.3]),
        lambda: ph.Body.disk(1.0, 0.1).translated([1.0, 2.0, 3.0]),
        lambda: ph.Body.disk(1.0, 0.1).translated([1000.0, 0.0, 0.0]),
        lambda: ph.Body.point_masses([1.0, 1.0, 1.0], [[0, 0, 0], [1, 0, 0], [0, 1, 0]]).translated(
            [10.0, 10.0, 0.0]
        ),
    ],
    ids=["point-mass", "disk", "far-disk", "flat-points"],
)
def test_degenerate_bodies_away_from_the_point(make):
    """A point mass, a disk or a flat set of points away from the point: I_c recovered as
    I_p - m [c][c]^T lies within rounding (eps ||I_p||) of a zero moment or of the triangle
    inequality's equality, and was refused as "not an inertia tensor", even for the spatial
    inertia polhode itself wrote. The result: the body, to that rounding."""
    made = make()
    if isinstance(made, tuple):
        matrix, inertia, com = made
        mass = 1.0
    else:
        matrix = made.spatial_inertia()
        mass, inertia, com = made.mass, made.inertia, made.center_of_mass
    body = ph.Body.from_spatial_inertia(matrix)
    assert body.mass == mass
    np.testing.assert_allclose(body.center_of_mass, com, rtol=4 * EPS, atol=0)
    assert np.abs(body.inertia - inertia).max() <= 32 * EPS * np.abs(matrix).max()


def test_rtol_admits_rounded_matrices():
    s = good_matrix()
    rounded = np.round(s, 6)
    rounded = (rounded + rounded.T) / 2
    body = ph.Body.from_spatial_inertia(rounded, rtol=1e-5)
    assert body.mass == pytest.approx(2.0)
    lopsided = s.copy()
    lopsided[0, 4] += 1e-9
    with pytest.raises(InertiaError):
        ph.Body.from_spatial_inertia(lopsided)
    assert ph.Body.from_spatial_inertia(lopsided, rtol=1e-8).mass == pytest.approx(2.0)


@pytest.mark.parametrize(
    "make",
    [lambda: ph.Body.cylinder(1.0, 1e-160, 1.0), lambda: ph.Body.sphere(1.0, 1e-160)],
    ids=["needle", "speck"],
)
def test_an_inverse_beyond_double_precision_is_an_inertia_error(make):
    """Moments of 1e-321 have reciprocals beyond the largest double: the inverse was returned
    with inf and NaN entries (numpy warnings only); it is an InertiaError naming `inverse`,
    as for a rod's zero moment."""
    with pytest.raises(ph.InertiaError, match="overflows double precision") as info:
        make().spatial_inertia(inverse=True)
    assert info.value.argument == "inverse"
