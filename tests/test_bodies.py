"""Mass properties of point masses, solids, moved and composite bodies, against tests/reference.py.

Tolerances are norm-wise (see conftest.assert_close_normwise) and in units of eps = 2.2e-16,
each justified by the number of roundings involved.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
import reference as ref
from conftest import assert_close_normwise, check_eigen, norm2
from reference import EPS

# (constructor name, mass, parameters): one ordinary instance of every solid, plus extreme aspect
# ratios where a formula could hide a wrong term behind a dominant one.
SOLID_CASES = [
    ("sphere", 2.7, (1.3,)),
    ("spherical_shell", 0.7, (0.7,)),
    ("cuboid", 2.7, ((0.3, 1.1, 2.5),)),
    ("cuboid", 5.0, ((1.0, 1.0, 1.0),)),
    ("cylinder", 2.0, (0.1, 0.5)),
    ("cylinder", 3.0, (2.0, 0.1)),
    ("tube", 1.7, (0.3, 0.5, 1.2)),
    ("tube", 1.7, (0.99, 1.0, 0.05)),
    ("cone", 2.3, (0.6, 1.9)),
    ("cone", 2.3, (3.0, 0.2)),
    ("ellipsoid", 1.1, ((0.5, 1.2, 2.0),)),
    ("rod", 0.8, (2.2,)),
    ("disk", 1.9, (0.9,)),
    ("torus", 4.1, (1.5, 0.4)),
    ("torus", 4.1, (1.0, 0.999)),
    ("capsule", 3.3, (0.35, 1.3)),
    ("capsule", 3.3, (1.0, 0.01)),
]
SOLID_IDS = [f"{name}-{i}" for i, (name, _, _) in enumerate(SOLID_CASES)]

# from_inertia(m, I).inertia need not return I's bits: a body may store its second moments in a
# factorised (square-root) form, and factor + product + trace cost ~4 roundings of ||I||.
ROUND_TRIP = 8 * EPS


def make(name, mass, params) -> ph.Body:
    return getattr(ph.Body, name)(mass, *params)


def size_of(name, params) -> float:
    """A length scale of the solid (for absolute centre-of-mass errors)."""
    return float(max(np.max(np.abs(np.asarray(p, dtype=float))) for p in params))


# ---------------------------------------------------------------------------------------------
# The closed forms themselves (reference only: no polhode in these two tests)
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "mass", "params"), SOLID_CASES, ids=SOLID_IDS)
def test_closed_form_equals_quadrature_of_the_solid(name, mass, params):
    # Gauss-Legendre x equally-spaced-ring quadrature is exact for these polynomial and
    # trigonometric integrands, so the cloud differs from the solid by round-off only: a few
    # hundred positive-weighted terms summed exactly (Fractions), nodes and weights each within
    # a few eps -> 16 eps norm-wise. A wrong coefficient in a closed form is off by >= 1e-3.
    closed = ref.SOLIDS[name](mass, *params)
    cloud = ref.point_mass_properties_exact(*ref.quadrature_cloud(name, mass, *params))
    assert cloud.mass == pytest.approx(mass, rel=4 * EPS)
    assert_close_normwise(cloud.inertia, closed.inertia, 16 * EPS, what=f"{name} inertia")
    assert_close_normwise(
        cloud.center_of_mass,
        closed.center_of_mass,
        16 * EPS,
        scale=size_of(name, params),
        what=f"{name} centre of mass",
    )


def _clamped_sqrt(x):
    return mpmath.sqrt(max(x, 0))


@pytest.mark.parametrize(
    ("name", "params", "rho_in", "rho_out", "breaks"),
    [
        (
            "torus",
            (1.5, 0.4),
            lambda z: 1.5 - _clamped_sqrt(0.16 - z * z),
            lambda z: 1.5 + _clamped_sqrt(0.16 - z * z),
            [-0.4, 0.4],
        ),
        ("cone", (0.6, 1.9), lambda z: 0, lambda z: 0.6 * (1 - z / 1.9), [0, 1.9]),
        (
            "capsule",
            (0.35, 1.3),
            lambda z: 0,
            lambda z: 0.35 if abs(z) <= 0.65 else _clamped_sqrt(0.35**2 - (abs(z) - 0.65) ** 2),
            [-1.0, -0.65, 0.65, 1.0],
        ),
        ("tube", (0.3, 0.5, 1.2), lambda z: 0.3, lambda z: 0.5, [-0.6, 0.6]),
        ("sphere", (1.3,), lambda z: 0, lambda z: _clamped_sqrt(1.69 - z * z), [-1.3, 1.3]),
    ],
    ids=["torus", "cone", "capsule", "tube", "sphere"],
)
def test_closed_form_equals_mpmath_quadrature(name, params, rho_in, rho_out, breaks):
    # A second, unrelated integration (tanh-sinh in z at 30 digits, the radial integrals in
    # closed form): the only float64 error left is the closed form's own few roundings (8 eps).
    volume, z_cm, iz, ix = ref.revolution_moments_mp(rho_in, rho_out, breaks)
    closed = ref.SOLIDS[name](1.0, *params)
    assert z_cm == pytest.approx(closed.center_of_mass[2], abs=8 * EPS * size_of(name, params))
    assert iz == pytest.approx(closed.inertia[2, 2], rel=8 * EPS)
    assert ix == pytest.approx(closed.inertia[0, 0], rel=8 * EPS)
    assert volume > 0


# ---------------------------------------------------------------------------------------------
# polhode's solids
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "mass", "params"), SOLID_CASES, ids=SOLID_IDS)
def test_solid_matches_closed_form(name, mass, params):
    # Each closed form is <= 20 floating-point operations (worst case 20 * eps/2 = 2.2e-15 for
    # any evaluation order); 1e-14 (45 eps) leaves room for an equivalent rearrangement.
    body = make(name, mass, params)
    closed = ref.SOLIDS[name](mass, *params)
    assert isinstance(body.mass, float)
    assert body.mass == pytest.approx(mass, rel=2 * EPS)
    com = np.asarray(body.center_of_mass)
    inertia = np.asarray(body.inertia)
    assert com.shape == (3,) and com.dtype == np.float64
    assert inertia.shape == (3, 3) and inertia.dtype == np.float64
    assert_close_normwise(inertia, closed.inertia, 1e-14, what=f"{name} inertia")
    assert_close_normwise(
        com, closed.center_of_mass, 1e-14, scale=size_of(name, params), what=f"{name} com"
    )


def test_every_solid_of_the_core_is_built_by_name_against_its_closed_form():
    # The core's table is the one list of solids (Body's constructors, Body.solid and the CLI
    # read it): each kind has a case above, and built by keyword from the table's parameter
    # names it equals the independent closed form.
    assert set(ph._core.SOLIDS) - {"point"} == {name for name, _, _ in SOLID_CASES}
    for name, mass, params in SOLID_CASES:
        names = [parameter for parameter, _ in ph._core.SOLIDS[name]]
        body = ph.Body.solid(name, mass, **dict(zip(names, params, strict=True)))
        closed = ref.SOLIDS[name](mass, *params)
        assert_close_normwise(body.inertia, closed.inertia, 1e-14, what=name)
    point = ph.Body.solid("point", 2.5)
    assert point.mass == 2.5
    assert not np.any(point.inertia)
    with pytest.raises(ph.errors.ArgumentError, match="one of point, sphere") as error:
        ph.Body.solid("blob", 1.0)
    assert error.value.argument == "kind"
    with pytest.raises(TypeError, match="takes radius, length; got height"):
        ph.Body.solid("cone", 1.0, radius=1.0, height=2.0)
    with pytest.raises(TypeError, match="needs `length`"):
        ph.Body.solid("cone", 1.0, radius=1.0)
    with pytest.raises(ph.errors.ShapeError) as shape:
        ph.Body.solid("cuboid", 1.0, size=[1.0, 2.0])
    assert shape.value.argument == "size"


@pytest.mark.parametrize(("name", "mass", "params"), SOLID_CASES, ids=SOLID_IDS)
def test_solid_matches_its_quadrature_point_cloud(name, mass, params):
    # polhode's own point-mass path on the exact quadrature cloud must reproduce polhode's solid.
    # Summing N <= 756 positive terms naively costs at most N eps/2 ~ 8e-14 relative; 1e-13 is
    # that worst case, still 10 orders below any error of formula or quadrature.
    masses, positions = ref.quadrature_cloud(name, mass, *params)
    cloud = ph.Body.point_masses(masses, positions)
    body = make(name, mass, params)
    assert cloud.mass == pytest.approx(body.mass, rel=1e-13)
    assert_close_normwise(cloud.inertia, body.inertia, 1e-13, what=f"{name} cloud vs solid")
    assert_close_normwise(
        cloud.center_of_mass,
        body.center_of_mass,
        1e-13,
        scale=size_of(name, params),
        what=f"{name} cloud com",
    )


def test_cone_centre_of_mass_is_a_quarter_up_from_the_base():
    body = ph.Body.cone(2.0, 0.5, 1.6)
    np.testing.assert_allclose(body.center_of_mass, [0.0, 0.0, 0.4], rtol=0, atol=2 * EPS)
    # About the apex (0, 0, h): 3/20 m r^2 + 3/5 m h^2 across the axis (textbook value).
    about_apex = body.inertia_about([0.0, 0.0, 1.6])
    expected = 2.0 * (3 / 20 * 0.25 + 3 / 5 * 1.6**2)
    assert about_apex[0, 0] == pytest.approx(expected, rel=8 * EPS)
    assert about_apex[1, 1] == pytest.approx(expected, rel=8 * EPS)


def test_rod_has_exactly_zero_axial_moment_and_disk_is_planar():
    rod = ph.Body.rod(3.0, 2.0)
    assert rod.inertia[2, 2] == 0.0
    assert rod.inertia[0, 0] == pytest.approx(1.0, rel=2 * EPS)
    disk = ph.Body.disk(3.0, 2.0)
    i = np.diag(disk.inertia)
    assert i[2] == pytest.approx(i[0] + i[1], rel=2 * EPS)


def test_inputs_accept_ints_lists_and_numpy_scalars():
    a = ph.Body.cuboid(2, [1, 2, 3])
    b = ph.Body.cuboid(np.float32(2.0), np.array([1.0, 2.0, 3.0], dtype=np.float32))
    c = ph.Body.cuboid(np.float64(2.0), (1.0, 2.0, 3.0))
    for body in (a, b, c):
        assert_close_normwise(body.inertia, ref.cuboid(2.0, (1, 2, 3)).inertia, 1e-14)
    cloud = ph.Body.point_masses([1, 2], [[0, 0, 0], [1, 0, 0]])
    assert cloud.mass == 3.0
    assert np.asarray(cloud.inertia).dtype == np.float64


# ---------------------------------------------------------------------------------------------
# Point masses
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("n", [1, 2, 3, 10, 100])
@pytest.mark.parametrize("offset", [0.0, 1e3, 1e6])
def test_point_masses_match_exact_reference(rng, n, offset):
    # The reference is exact (rational) then rounded once. A careful implementation (centre
    # first; r_k - r_cm is exact when both are within a factor 2) loses only the summation
    # rounding: at most N eps relative in the worst case, so the bound is max(16, N) eps.
    masses = rng.uniform(0.1, 10.0, n)
    positions = rng.uniform(-1.0, 1.0, (n, 3)) + offset * np.array([1.0, -0.7, 0.4])
    body = ph.Body.point_masses(masses, positions)
    exact = ref.point_mass_properties_exact(masses, positions)
    k = max(16, n) * EPS
    assert body.mass == pytest.approx(exact.mass, rel=k)
    assert_close_normwise(body.center_of_mass, exact.center_of_mass, k, what="com")
    # The inertia scale: its norm, or for one point (zero tensor) M * size^2.
    scale = max(norm2(exact.inertia), float(np.sum(masses)) * EPS)
    assert_close_normwise(body.inertia, exact.inertia, k, scale=scale, what="inertia")


def test_single_point_mass_has_zero_inertia():
    body = ph.Body.point_masses([2.5], [[1.0, -2.0, 3.0]])
    assert body.mass == 2.5
    np.testing.assert_array_equal(body.center_of_mass, [1.0, -2.0, 3.0])
    np.testing.assert_array_equal(body.inertia, np.zeros((3, 3)))
    # about another point it is a point mass: m (d^2 1 - d d^T)
    about = body.inertia_about([0.0, 0.0, 0.0])
    expected = ref.point_inertia_about([2.5], [[1.0, -2.0, 3.0]], [0, 0, 0])
    assert_close_normwise(about, expected, 4 * EPS)


def test_two_point_masses_are_collinear_with_reduced_mass():
    # I = mu d^2 across the line, 0 along it, mu = m1 m2 / (m1 + m2).
    body = ph.Body.point_masses([1.0, 3.0], [[0.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    mu = 3.0 / 4.0
    expected = np.diag([mu * 4, 0.0, mu * 4])
    assert_close_normwise(body.inertia, expected, 4 * EPS)
    p = body.principal()
    assert p.moments[0] == pytest.approx(0.0, abs=4 * EPS * 3)
    np.testing.assert_allclose(np.abs(p.axes[:, 0]), [0.0, 1.0, 0.0], atol=4 * EPS)


# ---------------------------------------------------------------------------------------------
# Textbook cases
# ---------------------------------------------------------------------------------------------

WATER = (15.9949146, 1.00782503, 1.00782503, 0.9584, math.radians(104.45))  # amu, angstrom


@pytest.mark.parametrize(
    "molecule",
    [WATER, (12.0, 1.0, 35.0, 1.1, math.radians(120.0)), (1.0, 2.0, 3.0, 2.0, math.radians(60.0))],
    ids=["water", "asymmetric", "generic"],
)
def test_planar_molecule_about_atom_and_centre_of_mass(molecule):
    m1, m2, m3, d, alpha = molecule
    masses, positions = ref.planar_molecule(*molecule)
    body = ph.Body.point_masses(masses, positions)
    scale = (m1 + m2 + m3) * d * d
    # About atom 1 (the given origin): the closed form, to a few roundings (16 eps of M d^2).
    at_atom = body.inertia_about(positions[0])
    assert_close_normwise(
        at_atom,
        ref.planar_molecule_inertia_at_atom1(*molecule),
        16 * EPS,
        scale=scale,
        what="about atom 1",
    )
    assert_close_normwise(
        at_atom, ref.point_inertia_about(masses, positions, positions[0]), 16 * EPS, scale=scale
    )
    # Principal moments and axes at atom 1 and at the centre of mass vs an mpmath eigensolve.
    for tensor, exact in [
        (at_atom, ref.point_inertia_about(masses, positions, positions[0])),
        (body.inertia, ref.point_mass_properties_exact(masses, positions).inertia),
    ]:
        moments, axes = ph.principal(tensor)
        check_eigen(tensor, moments, axes)
        values, vectors = ref.eigh_mp(exact)
        np.testing.assert_allclose(
            moments, [float(v) for v in values], rtol=0, atol=16 * EPS * scale
        )
        # planar: I3 = I1 + I2, the axis of I3 normal to the plane (z)
        assert moments[2] == pytest.approx(moments[0] + moments[1], abs=16 * EPS * scale)
        assert ref.axis_angle(axes[:, 2], [0, 0, 1]) <= 16 * EPS * scale / (moments[2] - moments[1])
        gap = min(np.diff([float(v) for v in values]))
        for k in range(3):
            # eigenvector error <= residual / gap (Davis-Kahan), residual <= 10 eps ||A||
            assert ref.axis_angle(axes[:, k], vectors[:, k]) <= 16 * EPS * norm2(exact) / gap


def test_water_principal_frame_is_exactly_the_textbook_one():
    # Symmetric triatomic: along the bisector I = 2 m_H d^2 sin^2(a/2); across it in the plane
    # 2 m_H m_O d^2 cos^2(a/2) / M; normal to the plane their sum. Water's ascending order is
    # (y, x, z); signs by the contract: columns e_y, e_x, then their cross product -e_z.
    m_o, m_h, _, d, alpha = WATER
    masses, positions = ref.planar_molecule(*WATER)
    p = ph.Body.point_masses(masses, positions).principal()
    expected = ref.symmetric_molecule_moments(m_o, m_h, d, alpha)
    np.testing.assert_allclose(p.moments, expected, rtol=16 * EPS)
    np.testing.assert_allclose(p.axes, [[0, 1, 0], [1, 0, 0], [0, 0, -1]], atol=16 * EPS)
    np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])


@pytest.mark.parametrize(("mass", "a"), [(1.0, 1.0), (3.0, 2.0), (0.25, 1e-3)])
def test_cube_about_a_corner(mass, a):
    # I about a corner of a uniform cube: M a^2 [[2/3, -1/4, -1/4], ...]; moments
    # M a^2 (1/6, 11/12, 11/12), the unique (smallest) axis along the body diagonal.
    cube = ph.Body.cuboid(mass, (a, a, a))
    corner = -0.5 * a * np.ones(3)
    expected = mass * a * a * (np.full((3, 3), -0.25) + np.eye(3) * (2 / 3 + 0.25))
    at_corner = cube.inertia_about(corner)
    assert_close_normwise(at_corner, expected, 16 * EPS)
    # the same through translated(): the cube moved so that the corner is at the origin
    assert_close_normwise(cube.translated(-corner).inertia_about(np.zeros(3)), expected, 16 * EPS)
    p = ph.principal(at_corner)
    check_eigen(at_corner, p.moments, p.axes)
    scale = mass * a * a
    np.testing.assert_allclose(
        p.moments, scale * np.array([1 / 6, 11 / 12, 11 / 12]), rtol=0, atol=16 * EPS * scale
    )
    np.testing.assert_array_equal(p.multiplicity, [1, 2, 2])
    gap = 0.75 * scale
    bound = 16 * EPS * norm2(at_corner) / gap
    diagonal = np.ones(3) / math.sqrt(3)
    assert ref.axis_angle(p.axes[:, 0], diagonal) <= bound
    assert p.axes[:, 0] @ diagonal > 0  # sign: every component (the largest too) positive
    # the degenerate pair spans the plane normal to the diagonal (a subspace, not two vectors)
    complement = np.linalg.qr(np.stack([diagonal, [1, -1, 0], [1, 1, -2]], axis=1))[0][:, 1:]
    assert ref.subspace_distance(p.axes[:, 1:], complement) <= bound


@pytest.mark.parametrize(
    ("mass", "radius", "length"), [(2.0, 0.1, 0.5), (3.0, 2.0, 0.1), (1.0, 1.0, math.sqrt(3.0))]
)
def test_cylinder_textbook_moments(mass, radius, length):
    # I1 = I2 = M/4 (a^2 + L^2/3) across the axis, I3 = M a^2 / 2 along it.
    body = ph.Body.cylinder(mass, radius, length)
    across = mass / 4 * (radius**2 + length**2 / 3)
    along = mass * radius**2 / 2
    np.testing.assert_allclose(np.diag(body.inertia), [across, across, along], rtol=1e-14)
    p = body.principal()
    np.testing.assert_allclose(p.moments, sorted([across, across, along]), rtol=1e-14)


def test_lib_doctest_cylinder_numbers():
    # The core crate's doctest example: 2 kg, r = 0.1 m, L = 0.5 m.
    p = ph.Body.cylinder(2.0, 0.1, 0.5).principal()
    assert abs(p.moments[0] - 0.01) < 1e-15
    assert abs(p.moments[2] - 2.0 * (3.0 * 0.01 + 0.25) / 12.0) < 1e-15


def _test_bodies():
    rng = np.random.default_rng(7)
    masses = rng.uniform(0.5, 2.0, 12)
    positions = rng.normal(size=(12, 3)) + [3.0, -1.0, 2.0]
    cloud = ph.Body.point_masses(masses, positions)
    composite = ph.Body.cylinder(2.0, 0.3, 1.5).rotated(
        Rotation.from_rotvec([0.3, -0.2, 0.9])
    ).translated([1.0, 2.0, -0.5]) + ph.Body.cuboid(1.0, (0.2, 0.4, 0.8)).translated(
        [-1.0, 0.5, 0.3]
    )
    return [("cloud", cloud, (masses, positions)), ("composite", composite, None)]


@pytest.mark.parametrize("shift", [[0.0, 0.0, 0.0], [1.0, -2.0, 0.5], [-30.0, 10.0, 70.0]])
def test_general_origin_shift(shift):
    # For new coordinates r' = r + R:
    # I'_ij = I_ij + M (R^2 d_ij - R_i R_j) + M (2 r_cm . R d_ij - r_cm_i R_j - R_i r_cm_j).
    # Bound: a few roundings of each of its terms, 16 eps (||I|| + M R^2 + 2 M |r_cm| R).
    big_r = np.asarray(shift)
    for label, body, cloud in _test_bodies():
        m, c = body.mass, np.asarray(body.center_of_mass)
        about_origin = body.inertia_about(np.zeros(3))
        formula = ref.shift_origin(about_origin, m, c, big_r)
        scale = norm2(about_origin) + m * big_r @ big_r + 2 * m * norm2(c) * norm2(big_r)
        # The new origin sits at r = -R in old coordinates; equivalently move the body by +R.
        assert_close_normwise(
            body.inertia_about(-big_r),
            formula,
            16 * EPS,
            scale=scale,
            what=f"{label} inertia_about(-R)",
        )
        assert_close_normwise(
            body.translated(big_r).inertia_about(np.zeros(3)),
            formula,
            16 * EPS,
            scale=scale,
            what=f"{label} translated(R)",
        )
        if cloud is not None:
            masses, positions = cloud
            exact = ref.point_inertia_about(masses, positions + big_r, np.zeros(3))
            assert_close_normwise(formula, exact, 16 * EPS, scale=scale, what="formula vs exact")


@pytest.mark.parametrize("seed", range(5))
def test_planar_bodies_have_i3_equal_i1_plus_i2(seed):
    # Any body in a plane: I3 = I1 + I2 with the I3 axis normal to the plane; the tensor is on
    # the boundary of validity and must be accepted back by from_inertia.
    rng = np.random.default_rng(seed)
    n = 20
    masses = rng.uniform(0.1, 3.0, n)
    flat = np.concatenate([rng.normal(size=(n, 2)) * [3.0, 0.5], np.zeros((n, 1))], axis=1)
    rotation = ref.random_rotation(rng)
    positions = flat @ rotation.T + rng.normal(size=3)
    body = ph.Body.point_masses(masses, positions)
    p = body.principal()
    check_eigen(body.inertia, p.moments, p.axes)
    # 16 eps: the eigenvalues of the float tensor are within 10 eps ||I|| of the exact ones.
    assert p.moments[2] == pytest.approx(p.moments[0] + p.moments[1], abs=16 * EPS * p.moments[2])
    normal = rotation[:, 2]
    assert ref.axis_angle(p.axes[:, 2], normal) <= 16 * EPS * p.moments[2] / (
        p.moments[2] - p.moments[1]
    )
    again = ph.Body.from_inertia(body.mass, body.inertia, body.center_of_mass)
    assert_close_normwise(again.inertia, body.inertia, ROUND_TRIP)
    for disk in (ph.Body.disk(2.0, 1.5), ph.Body.disk(2.0, 1.5).rotated(rotation)):
        moments = disk.principal().moments
        assert moments[2] == pytest.approx(moments[0] + moments[1], abs=16 * EPS * moments[2])


# ---------------------------------------------------------------------------------------------
# Moving bodies
# ---------------------------------------------------------------------------------------------


def test_translated_moves_only_the_centre_of_mass():
    body = ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)).rotated(Rotation.from_rotvec([0.1, 0.2, 0.3]))
    moved = body.translated([1.0, -2.0, 3.5])
    np.testing.assert_allclose(
        moved.center_of_mass, body.center_of_mass + [1.0, -2.0, 3.5], rtol=0, atol=4 * EPS * 3.5
    )
    # the inertia about the centre of mass does not change (at most one rounding, 2 eps)
    assert_close_normwise(moved.inertia, body.inertia, 2 * EPS)
    assert moved.mass == body.mass
    # immutable values: the original is unchanged
    before = np.array(body.center_of_mass)
    body.translated([10.0, 10.0, 10.0])
    np.testing.assert_array_equal(body.center_of_mass, before)


def test_rotation_convention_maps_body_points_forward():
    # x_new = R x: a point mass at +x rotated 90 degrees about +z goes to +y.
    body = ph.Body.point_masses([1.0, 1.0], [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    quarter = Rotation.from_euler("z", 90, degrees=True)
    moved = body.rotated(quarter)
    np.testing.assert_allclose(moved.center_of_mass, [0.0, 1.5, 0.0], atol=4 * EPS)
    # the line of masses now lies along y: zero moment about y
    assert abs(moved.inertia[1, 1]) <= 8 * EPS


def test_rotation_forms_agree():
    rotation = Rotation.from_rotvec([0.4, -1.1, 0.7])
    body = ph.Body.cuboid(2.0, (0.5, 1.0, 3.0)).translated([1.0, 2.0, 3.0])
    moved = ref.translate(ref.cuboid(2.0, (0.5, 1.0, 3.0)), [1.0, 2.0, 3.0])
    expected = ref.rotate(moved, rotation)
    for form in (
        rotation,
        rotation.as_matrix(),
        rotation.as_quat(),
        list(rotation.as_quat()),
        -rotation.as_quat(),
        3.0 * rotation.as_quat(),
    ):
        moved = body.rotated(form)
        # R I R^T: each element a sum of 9 products; the conversions add a few eps: 16 eps.
        assert_close_normwise(moved.inertia, expected.inertia, 16 * EPS)
        assert_close_normwise(moved.center_of_mass, expected.center_of_mass, 16 * EPS)


def test_moved_cloud_matches_exact_reference(rng):
    masses = rng.uniform(0.1, 5.0, 30)
    positions = rng.normal(size=(30, 3)) * [1.0, 2.0, 0.3]
    rotation = ref.random_rotation(rng)
    offset = np.array([5.0, -3.0, 8.0])
    body = ph.Body.point_masses(masses, positions).rotated(rotation).translated(offset)
    exact = ref.point_mass_properties_exact(masses, positions @ rotation.T + offset)
    assert_close_normwise(body.inertia, exact.inertia, 32 * EPS, what="inertia")
    assert_close_normwise(body.center_of_mass, exact.center_of_mass, 32 * EPS, what="com")


def test_inertia_about_with_axes_follows_a_transpose_i_a():
    # The columns of `axes` are the new axes in body coordinates: A^T I_point A.
    body = ph.Body.cuboid(2.0, (1.0, 2.0, 3.0))
    quarter = Rotation.from_euler("z", 90, degrees=True)  # new x = body y, new y = -body x
    i = np.asarray(body.inertia)
    turned = body.inertia_about(body.center_of_mass, axes=quarter)
    assert turned[0, 0] == pytest.approx(i[1, 1], rel=4 * EPS)
    assert turned[1, 1] == pytest.approx(i[0, 0], rel=4 * EPS)
    rotation = Rotation.from_rotvec([0.3, 0.5, -0.2])
    point = np.array([0.3, -0.4, 1.2])
    a = rotation.as_matrix()
    expected = a.T @ ref.parallel_axis(i, 2.0, body.center_of_mass, point) @ a
    for form in (rotation, a, rotation.as_quat()):
        assert_close_normwise(body.inertia_about(point, axes=form), expected, 16 * EPS)
    assert_close_normwise(
        body.inertia_about(point), ref.parallel_axis(i, 2.0, body.center_of_mass, point), 8 * EPS
    )


def test_angular_momentum_and_kinetic_energy():
    rotation = Rotation.from_rotvec([0.2, -0.4, 0.9])
    body = ph.Body.ellipsoid(3.0, (1.0, 2.0, 3.0)).rotated(rotation).translated([1.0, 1.0, 1.0])
    omega = np.array([0.3, -1.2, 2.5])
    i = np.asarray(body.inertia)
    momentum = np.asarray(body.angular_momentum_body(omega))
    assert momentum.shape == (3,) and momentum.dtype == np.float64
    # L = I w: 3 products per component, 8 eps of ||I|| |w|.
    assert_close_normwise(momentum, i @ omega, 8 * EPS, scale=norm2(i) * norm2(omega))
    energy = body.kinetic_energy(omega)
    assert isinstance(energy, float)
    assert energy == pytest.approx(0.5 * omega @ i @ omega, rel=16 * EPS)
    # in principal axes, T = 1/2 sum I_k w_k^2 and |L|^2 = sum I_k^2 w_k^2
    p = body.principal()
    w = p.axes.T @ omega
    assert energy == pytest.approx(0.5 * np.sum(p.moments * w * w), rel=32 * EPS)
    assert momentum @ momentum == pytest.approx(np.sum((p.moments * w) ** 2), rel=32 * EPS)


# ---------------------------------------------------------------------------------------------
# Composition
# ---------------------------------------------------------------------------------------------


def test_composite_matches_reference_composition():
    parts = [
        (ph.Body.rod(1.0, 2.0), ref.rod(1.0, 2.0)),
        (
            ph.Body.sphere(5.0, 0.3).translated([0, 0, 1.0]),
            ref.translate(ref.sphere(5.0, 0.3), [0, 0, 1.0]),
        ),
        (
            ph.Body.sphere(2.0, 0.2).translated([0, 0, -1.0]),
            ref.translate(ref.sphere(2.0, 0.2), [0, 0, -1.0]),
        ),
        (
            ph.Body.cone(1.5, 0.4, 0.9).rotated(Rotation.from_rotvec([1.0, 0.0, 0.0])),
            ref.rotate(ref.cone(1.5, 0.4, 0.9), Rotation.from_rotvec([1.0, 0.0, 0.0])),
        ),
    ]
    expected = ref.compose([r for _, r in parts])
    for total in (
        parts[0][0] + parts[1][0] + parts[2][0] + parts[3][0],
        sum(b for b, _ in parts),
        0 + parts[0][0] + (parts[1][0] + (parts[2][0] + parts[3][0])),
    ):
        assert total.mass == pytest.approx(expected.mass, rel=4 * EPS)
        assert_close_normwise(total.center_of_mass, expected.center_of_mass, 16 * EPS, scale=1.0)
        assert_close_normwise(total.inertia, expected.inertia, 16 * EPS)


def test_zero_plus_body_is_the_body():
    body = ph.Body.torus(1.0, 2.0, 0.5)
    same = 0 + body
    assert same.mass == body.mass
    np.testing.assert_array_equal(same.inertia, body.inertia)
    assert sum([body]).mass == body.mass


def test_composite_of_point_bodies_equals_point_masses(rng):
    masses = rng.uniform(0.1, 5.0, 10)
    positions = rng.normal(size=(10, 3))
    together = ph.Body.point_masses(masses, positions)
    summed = sum(ph.Body.point_masses([m], [r]) for m, r in zip(masses, positions, strict=True))
    exact = ref.point_mass_properties_exact(masses, positions)
    # 10 sequential two-body combinations, each a few roundings of terms <= ||I||: 32 eps.
    for body in (together, summed):
        assert_close_normwise(body.inertia, exact.inertia, 32 * EPS)
        assert_close_normwise(body.center_of_mass, exact.center_of_mass, 32 * EPS, scale=3.0)


def test_from_inertia_round_trip():
    rotation = Rotation.from_rotvec([0.5, 0.1, -0.3]).as_matrix()
    inertia = rotation @ np.diag([1.0, 2.0, 2.5]) @ rotation.T
    inertia = 0.5 * (inertia + inertia.T)
    body = ph.Body.from_inertia(3.0, inertia, [1.0, 2.0, 3.0])
    assert body.mass == 3.0
    np.testing.assert_allclose(body.center_of_mass, [1.0, 2.0, 3.0], rtol=0, atol=0)
    assert_close_normwise(body.inertia, inertia, ROUND_TRIP)
    default = ph.Body.from_inertia(3.0, np.diag([1.0, 2.0, 2.5]))
    np.testing.assert_array_equal(default.center_of_mass, np.zeros(3))


@pytest.mark.parametrize(
    "inertia",
    [
        np.diag([1.0, 2.0, 3.0]),
        np.diag([0.0, 1.0, 1.0]),
        np.zeros((3, 3)),
        np.diag([2.0, 2.0, 2.0]),
        np.diag([1.0, 1.0, 2.0 + 2 * EPS]),
    ],
    ids=["planar", "collinear", "point", "sphere", "planar-plus-round-off"],
)
def test_from_inertia_accepts_boundary_tensors(inertia):
    # Planar (I1 + I2 = I3) and collinear (a zero moment) bodies are valid, also after the
    # round-off of a rotation (the tolerance is ~16 eps tr/2).
    body = ph.Body.from_inertia(1.0, inertia)
    assert_close_normwise(body.inertia, inertia, ROUND_TRIP, scale=max(1.0, norm2(inertia)))
    rng = np.random.default_rng(3)
    for _ in range(50):
        r = ref.random_rotation(rng)
        ph.Body.from_inertia(1.0, r @ inertia @ r.T)


def test_inertia_is_exactly_symmetric():
    # The inertia is "the full symmetric 3x3": every body, however built, returns I == I^T to
    # the bit (a symmetric representation cannot produce anything else; users feed it to
    # symmetric solvers and compare I_xy with I_yx).
    rotation = Rotation.from_rotvec([0.7, -0.3, 1.9])
    rng = np.random.default_rng(11)
    bodies = [
        ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)).rotated(rotation),
        ph.Body.point_masses(rng.uniform(0.1, 1.0, 9), rng.normal(size=(9, 3))),
        ph.Body.cone(1.0, 0.5, 2.0).rotated(rotation) + ph.Body.torus(2.0, 1.0, 0.2),
        ph.Body.from_inertia(
            1.0, rotation.as_matrix() @ np.diag([1.0, 2.0, 2.5]) @ rotation.as_matrix().T
        ),
    ]
    for body in bodies:
        i = np.asarray(body.inertia)
        np.testing.assert_array_equal(i, i.T)
        about = body.inertia_about([1.0, -2.0, 0.5], axes=rotation)
        np.testing.assert_array_equal(about, about.T)
