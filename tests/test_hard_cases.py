"""The hard cases of the numerics (docs/architecture.md). Each must hold; the bounds are derived
in the comments, not tuned to the implementation."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
import reference as ref
from conftest import NO_MERGE_RTOL, assert_close_normwise, check_eigen, norm2
from reference import EPS

# ---------------------------------------------------------------------------------------------
# Far from the origin: eight unit masses at a unit cube's corners moved 1e8 away
# ---------------------------------------------------------------------------------------------

FAR_OFFSETS = [(1e8, 1e8, 1e8), (1e8, -2e8, 3e8), (0.0, 0.0, 1e8), (123456789.0, 0.0, -1e8)]


def _check_far_cube(body, offset, what):
    # Exact answer: mass 8, centre offset + 0.5 (representable), inertia 4 * 1 (each mass at
    # +-0.5 from the centre on every axis: 8 * (0.25 + 0.25) = 4). Summing second moments about
    # the far origin and shifting back loses eps (1e8)^2 = 2 in absolute terms (measured: the
    # smallest moment came out -6.98); centring first gets it exactly. Bound: 1e-12 relative.
    assert body.mass == 8.0
    expected_com = np.asarray(offset) + 0.5
    # the centre is representable; its computation may round once at |offset| (eps |offset|)
    assert_close_normwise(
        body.center_of_mass,
        expected_com,
        2 * EPS,
        scale=max(1.0, float(np.max(np.abs(expected_com)))),
        what=f"{what} com",
    )
    assert_close_normwise(body.inertia, 4.0 * np.eye(3), 1e-12, what=f"{what} inertia")
    p = body.principal()
    np.testing.assert_allclose(p.moments, [4.0, 4.0, 4.0], rtol=1e-12, err_msg=what)
    assert np.all(p.moments > 0), what


@pytest.mark.parametrize("offset", FAR_OFFSETS)
def test_far_cube_corners_as_point_masses(offset):
    masses, positions = ref.cube_corners(1.0, offset)
    assert np.all(positions - np.asarray(offset) == ref.cube_corners(1.0)[1])  # inputs exact
    body = ph.Body.point_masses(masses, positions)
    _check_far_cube(body, offset, "point_masses")
    # exactly isotropic in exact arithmetic, and every step can be exact: three equal moments
    np.testing.assert_array_equal(body.principal().multiplicity, [3, 3, 3])
    # and the inertia about the far origin itself, against the exact rational reference
    about_origin = body.inertia_about(np.zeros(3))
    exact = ref.point_inertia_about(masses, positions, np.zeros(3))
    assert_close_normwise(about_origin, exact, 4 * EPS)


@pytest.mark.parametrize("offset", FAR_OFFSETS)
def test_far_cube_corners_composed_pairwise(offset):
    # A balanced tree ((b1 + b2) + (b3 + b4)) + ...: every partial centre of mass is offset +
    # a multiple of 0.5, exactly representable, so the composite can be exact.
    masses, positions = ref.cube_corners(1.0, offset)
    bodies = [ph.Body.point_masses([m], [r]) for m, r in zip(masses, positions, strict=True)]
    while len(bodies) > 1:
        bodies = [bodies[k] + bodies[k + 1] for k in range(0, len(bodies), 2)]
    _check_far_cube(bodies[0], offset, "pairwise composition")


@pytest.mark.parametrize("offset", FAR_OFFSETS)
def test_far_cube_corners_composed_with_sum(offset):
    # sum() adds one corner at a time. The partial centres offset + k/3, k/5, k/7 are not
    # representable: stored as float64 they are off by up to eps |offset| / 2 ~ 7e-9, and the
    # next parallel-axis shift then errs by ~ 2 m delta d ~ 1e-8 unless the composite carries
    # that rounding along (e.g. a compensated centre of mass). The contract asks for
    # the same 1e-12 as the other routes; see the report if this fails.
    masses, positions = ref.cube_corners(1.0, offset)
    body = sum(ph.Body.point_masses([m], [r]) for m, r in zip(masses, positions, strict=True))
    _check_far_cube(body, offset, "sum()")


# ---------------------------------------------------------------------------------------------
# A 1e6 sphere plus a 1e-6 point: anisotropy 2.5e-12 of the moments
# ---------------------------------------------------------------------------------------------

DIRECTIONS = [(0.3, -0.5, 0.8), (-0.91, 0.12, 0.33), (1e-3, 1.0, -2e-3)]


@pytest.mark.parametrize("direction", DIRECTIONS)
@pytest.mark.parametrize("order", ["sphere+point", "point+sphere"])
def test_heavy_sphere_plus_tiny_point_mass(direction, order):
    # Exact: I = 0.4e6 1 + mu d^2 (1 - u u^T) about the combined centre (mu = M m / (M + m)),
    # so the smallest moment's axis is u, the direction of the point from the sphere's centre
    # (the combined centre lies on that line). In the assembled tensor the 1e-6 anisotropy sits
    # below ulp(4e5) = 5.8e-11 times 1e-5: eig(I) gets u only to ~1e-4 rad (measured). A split
    # (isotropic + deviatoric / square-root) representation gets it to ~eps: 1e-12 rad.
    u = np.asarray(direction) / np.linalg.norm(direction)
    point_position = 1.1 * u
    sphere = ph.Body.sphere(1e6, 1.0)
    point = ph.Body.point_masses([1e-6], [point_position])
    body = sphere + point if order == "sphere+point" else point + sphere
    p = body.principal()
    np.testing.assert_array_equal(p.multiplicity, [1, 2, 2])
    # the direction of the stored point, in high precision
    with mpmath.workdps(40):
        v = [mpmath.mpf(float(x)) for x in point_position]
        n = mpmath.sqrt(sum(x * x for x in v))
        axis = np.array([float(x / n) for x in v])
    angle = ref.axis_angle(p.axes[:, 0], axis)
    assert angle <= 1e-12, f"smallest-moment axis off by {angle:.3e} rad (bound 1e-12)"
    # Moments: I1 = 0.4e6 (4 eps); the gap mu d^2 = 1.21e-6 is resolved only to the spacing of
    # floats near 4e5 (ulp 5.8e-11): 4 ulp.
    mu = 1e6 * 1e-6 / (1e6 + 1e-6)
    d2 = float(point_position @ point_position)
    ulp = np.spacing(4e5)
    assert p.moments[0] == pytest.approx(4e5, rel=4 * EPS)
    assert p.moments[1] - p.moments[0] == pytest.approx(mu * d2, abs=4 * ulp)
    assert p.moments[2] - p.moments[0] == pytest.approx(mu * d2, abs=4 * ulp)
    # the pair spans the plane normal to u
    assert abs(p.axes[:, 1] @ axis) <= 1e-12 and abs(p.axes[:, 2] @ axis) <= 1e-12


# ---------------------------------------------------------------------------------------------
# A needle: 1000 collinear masses with 1e-8 lateral jitter
# ---------------------------------------------------------------------------------------------


def _needle(seed, jitter, n=1000):
    rng = np.random.default_rng(seed)
    u = np.array([0.48, -0.6, 0.64])
    u /= np.linalg.norm(u)
    e1 = np.cross(u, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    t = rng.uniform(-1.0, 1.0, n)
    lateral = jitter * (rng.normal(size=(n, 1)) * e1 + rng.normal(size=(n, 1)) * e2)
    positions = np.array([0.3, -0.2, 0.5]) + t[:, None] * u + lateral
    masses = rng.uniform(0.5, 2.0, n)
    return masses, positions, u


@pytest.mark.parametrize("seed", [1, 2])
def test_needle_smallest_moment(seed):
    # Smallest moment ~ sum m |jitter|^2 ~ 1e-13 against a largest ~ 3e2: a ratio of 3e-16, so
    # eig(I) returns noise (eps ||I|| ~ 7e-14). From the centred sqrt(m)(r - r_cm) (SVD/QR) it
    # is accurate: the singular values carry an absolute error ~ eps s1 = 4e-15 against
    # s3 ~ 3e-7, i.e. ~1e-8 relative. Bound: 1e-6 relative against an mpmath
    # eigensolve of the exactly centred second moments (50 digits).
    masses, positions, u = _needle(seed, 1e-8)
    body = ph.Body.point_masses(masses, positions)
    p = body.principal()
    exact_moments, exact_axes = ref.principal_cloud_mp(masses, positions)
    # the float64 SVD reference agrees with mpmath (sanity of the reference itself, 1e-6)
    svd_moments, _ = ref.principal_svd(masses, positions)
    assert svd_moments[0] == pytest.approx(exact_moments[0], rel=1e-6)
    rel = abs(p.moments[0] - exact_moments[0]) / exact_moments[0]
    assert rel <= 1e-6, (
        f"smallest moment {p.moments[0]!r} vs {exact_moments[0]!r}: relative error {rel:.3e}"
    )
    # The large moments are ordinary: 16 eps relative.
    np.testing.assert_allclose(p.moments[1:], exact_moments[1:], rtol=16 * EPS)
    # The needle's axis (gap ~ I3) to a few eps. The two large moments differ by c2 - c3 ~ 1e-14
    # on 3e2 (below their resolution), so the pair across the needle is only a subspace, which
    # orthonormality and the needle's axis already fix.
    assert ref.axis_angle(p.axes[:, 0], exact_axes[:, 0]) <= 16 * EPS


def test_exactly_collinear_needle_has_a_zero_smallest_moment():
    # Positions on a line up to their own rounding: the exact smallest moment is ~eps^2 I3. A
    # square-root (SVD-type) representation leaves an absolute error ~ (eps s1)^2 = eps^2 I3 in
    # it; eig(I) leaves eps I3 and, half the time, a negative moment (measured). Bound:
    # 0 <= I1 <= I1_exact + 100 eps^2 I3.
    masses, positions, _ = _needle(3, 0.0)
    p = ph.Body.point_masses(masses, positions).principal()
    exact_moments, _ = ref.principal_cloud_mp(masses, positions)
    assert p.moments[0] >= 0.0
    assert p.moments[0] <= exact_moments[0] + 100 * EPS**2 * exact_moments[2]


# ---------------------------------------------------------------------------------------------
# Scale invariance: no absolute thresholds
# ---------------------------------------------------------------------------------------------


def _pipeline(mass_scale, length_scale):
    rng = np.random.default_rng(5)
    masses = rng.uniform(0.5, 2.0, 20) * mass_scale
    positions = rng.normal(size=(20, 3)) * length_scale
    rotation = Rotation.from_rotvec([0.3, -0.7, 0.4])
    L = length_scale
    body = (
        ph.Body.point_masses(masses, positions)
        + ph.Body.cylinder(2.0 * mass_scale, 0.3 * L, 1.5 * L)
        .rotated(rotation)
        .translated(np.array([1.0, 2.0, -0.5]) * L)
        + ph.Body.cuboid(1.0 * mass_scale, np.array([0.2, 0.4, 0.8]) * L).translated(
            np.array([-1.0, 0.5, 0.3]) * L
        )
        + ph.Body.torus(0.7 * mass_scale, 0.5 * L, 0.1 * L).rotated(rotation.inv())
        + ph.Body.cone(0.4 * mass_scale, 0.2 * L, 0.6 * L).translated(np.array([0.0, 0.0, 2.0]) * L)
    )
    p = body.principal()
    return {
        "mass": np.array(body.mass),
        "center_of_mass": np.asarray(body.center_of_mass),
        "inertia": np.asarray(body.inertia),
        "inertia_about": np.asarray(body.inertia_about(np.array([0.5, -0.5, 1.0]) * L)),
        "moments": p.moments,
        "axes": p.axes,
    }


POWERS = [
    (2.0**-40, 1.0),
    (2.0**40, 1.0),
    (1.0, 2.0**-40),
    (1.0, 2.0**40),
    (2.0**-40, 2.0**-40),
    (2.0**40, 2.0**40),
    (2.0**40, 2.0**-40),
    (2.0**-40, 2.0**40),
]
DECIMALS = [
    (1e-12, 1.0),
    (1e12, 1.0),
    (1.0, 1e-12),
    (1.0, 1e12),
    (1e-12, 1e-12),
    (1e12, 1e12),
    (1e12, 1e-12),
    (1e-12, 1e12),
]
EXPONENTS = {
    "mass": (1, 0),
    "center_of_mass": (0, 1),
    "inertia": (1, 2),
    "inertia_about": (1, 2),
    "moments": (1, 2),
    "axes": (0, 0),
}


@pytest.mark.parametrize(("mass_scale", "length_scale"), POWERS)
def test_power_of_two_scaling_is_exact(mass_scale, length_scale):
    # Scaling by 2^k commutes with every rounding, so an algorithm without absolute thresholds
    # (and no over/underflow: moments here span 1e-36 .. 1e36) reproduces the unscaled results
    # times the scale exactly. 2 eps allows a single harmless non-homogeneous rounding.
    base = _pipeline(1.0, 1.0)
    scaled = _pipeline(mass_scale, length_scale)
    for key, (km, kl) in EXPONENTS.items():
        factor = mass_scale**km * length_scale**kl
        assert_close_normwise(scaled[key] / factor, base[key], 2 * EPS, what=key)


@pytest.mark.parametrize(("mass_scale", "length_scale"), DECIMALS)
def test_decimal_scaling(mass_scale, length_scale):
    # Decimal factors round every input once (eps/2 relative); the composite's moments are
    # well conditioned (norm-wise) and its moment gaps are > 5% of the largest, so the results
    # move by a few eps and the axes by a few eps / relative gap (<= 20 eps / 2 eps perturbation):
    # 1e-14 (45 eps).
    base = _pipeline(1.0, 1.0)
    scaled = _pipeline(mass_scale, length_scale)
    assert min(np.diff(base["moments"])) > 5e-2 * base["moments"][2]
    for key, (km, kl) in EXPONENTS.items():
        factor = mass_scale**km * length_scale**kl
        assert_close_normwise(scaled[key] / factor, base[key], 1e-14, what=key)


@pytest.mark.parametrize("scale", [2.0**-120, 2.0**120, 1e-36, 1e36])
def test_principal_is_scale_invariant(rng, scale):
    for a in [
        np.diag([1.0, 2.0, 3.0]) + 1e-10 * (np.ones((3, 3)) - np.eye(3)),
        np.diag([1.0, 1.0 + 1e-12, 2.0]),
    ] + [
        (lambda r: r @ np.diag([0.1, 0.7, 0.75]) @ r.T)(ref.random_rotation(rng)) for _ in range(5)
    ]:
        a = 0.5 * (a + a.T)
        base = ph.principal(a, rtol=NO_MERGE_RTOL)
        scaled = ph.principal(a * scale, rtol=NO_MERGE_RTOL)
        check_eigen(a * scale, scaled.moments, scaled.axes)
        exact = math.log2(scale).is_integer()
        tol = 2 * EPS if exact else 64 * EPS
        assert_close_normwise(scaled.moments / scale, base.moments, tol, what="moments")
        if exact:
            assert_close_normwise(scaled.axes, base.axes, 2 * EPS, scale=1.0, what="axes")


# ---------------------------------------------------------------------------------------------
# Nearly diagonal and nearly degenerate tensors (nalgebra #1109, #1210)
# ---------------------------------------------------------------------------------------------

OFF = np.ones((3, 3)) - np.eye(3)


def _sym(i, j, v):
    a = np.zeros((3, 3))
    a[i, j] = a[j, i] = v
    return a


NEARLY_DIAGONAL = {
    "diag123+1e-10": np.diag([1.0, 2.0, 3.0]) + 1e-10 * OFF,
    "diag123+1e-10(01)": np.diag([1.0, 2.0, 3.0]) + _sym(0, 1, 1e-10),
    "diag213+1e-10(12)": np.diag([2.0, 1.0, 2.5]) + _sym(1, 2, 1e-10),
    "diag312+1e-10(02)": np.diag([3.0, 1.0, 2.0]) + _sym(0, 2, 1e-10),
    "near-pair+1e-10": np.diag([1.0, 1.0 + 1e-10, 1.5]) + 1e-10 * OFF,
    "pair-split-by-1e-10": np.diag([1.0, 1.0, 1.5]) + _sym(0, 1, 1e-10),
    "pair-split-by-1e-10(12)": np.diag([1.5, 1.0, 1.0]) + _sym(1, 2, 1e-10),
    "isotropic+1e-10": np.eye(3) + 1e-10 * OFF,
    "isotropic+1e-10-mixed": np.eye(3) + _sym(0, 1, 1e-10) + _sym(1, 2, -3e-10) + _sym(0, 2, 2e-10),
    "diag123+1e-17": np.diag([1.0, 2.0, 3.0]) + 1e-17 * OFF,
    "diag123+1e-200": np.diag([1.0, 2.0, 3.0]) + 1e-200 * OFF,
    "diag-1e-5-spread": np.diag([1.0, 1.0 + 1e-5, 1.0 + 2e-5]) + 1e-10 * OFF,
    "root-7850": np.eye(3) + 0.01 * OFF,
    "block-deflation": np.array([[2.0, 1e-9, 0.0], [1e-9, 2.0 + 1e-9, 1e-12], [0.0, 1e-12, 3.0]]),
    "graded": np.diag([1e-6, 1.0, 1.0 + 1e-6]) + _sym(0, 1, 1e-12) + _sym(1, 2, 1e-9),
}


@pytest.mark.parametrize("name", list(NEARLY_DIAGONAL))
def test_nearly_diagonal_tensors(name):
    # Residual <= 10 eps ||A|| (backward stability); moments to 10 eps ||A|| of the exact
    # (mpmath, 50 digits) eigenvalues of the stored matrix (Weyl); each axis to
    # 16 eps ||A|| / gap (Davis-Kahan: residual / gap), which is meaningful where the gap is
    # larger than the noise and vacuous (> 1) where it is not.
    a = NEARLY_DIAGONAL[name]
    p = ph.principal(a, rtol=NO_MERGE_RTOL)
    check_eigen(a, p.moments, p.axes, what=name)
    values, vectors = ref.eigh_mp(a)
    values = np.array([float(v) for v in values])
    scale = norm2(a)
    np.testing.assert_allclose(p.moments, values, rtol=0, atol=10 * EPS * scale, err_msg=name)
    for k in range(3):
        gap = min(abs(values[k] - values[j]) for j in range(3) if j != k)
        if gap > 0:
            bound = 16 * EPS * scale / gap
            angle = ref.axis_angle(p.axes[:, k], vectors[:, k])
            assert angle <= bound, f"{name}: axis {k} off by {angle:.3e} > {bound:.3e}"


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("top", [2.0, 1.5])
def test_rotated_near_degenerate_pair(seed, top):
    # R diag(1, 1 + 1e-12, top) R^T: the pair's individual vectors are determined only to
    # eps / 1e-12 ~ 1e-4 (test the subspace), the third to 16 eps ||A|| / (top - 1).
    # (top = 2 is also exactly planar: I1 + I2 = I3 up to the 1e-12.)
    r = ref.random_rotation(np.random.default_rng(seed))
    a = r @ np.diag([1.0, 1.0 + 1e-12, top]) @ r.T
    a = 0.5 * (a + a.T)
    for p in (ph.principal(a), ph.principal(a, rtol=NO_MERGE_RTOL)):
        check_eigen(a, p.moments, p.axes)
        values, vectors = ref.eigh_mp(a)
        np.testing.assert_allclose(
            p.moments, [float(v) for v in values], rtol=0, atol=10 * EPS * norm2(a)
        )
        bound = 16 * EPS * norm2(a) / (top - 1.0)
        assert ref.subspace_distance(p.axes[:, :2], vectors[:, :2]) <= bound
        assert ref.axis_angle(p.axes[:, 2], vectors[:, 2]) <= bound
    if top == 2.0:
        ph.Body.from_inertia(1.0, a)  # a planar tensor after round-off: valid


@pytest.mark.parametrize("seed", range(6))
def test_trace_shift_large_isotropic_part(seed):
    # A = 1e8 1 + 1e-8 E: a tiny residual does not make the axes right (measured: up to 1.57 rad
    # wrong without the shift); after subtracting trace/3 (exact here: Sterbenz) the solver
    # sees entries ~1e-8 and the axes are right to ~eps ||A - s 1|| / gap. The reference is the
    # exact eigensystem of the stored (rounded) matrix in 50-digit mpmath.
    rng = np.random.default_rng(100 + seed)
    q = ref.random_rotation(rng)
    e = q @ np.diag([-5.0, 1.0, 7.0]) @ q.T  # eigenvalue gaps of 1e-8 E >= 4 ulp(1e8)
    a = 1e8 * np.eye(3) + 1e-8 * 0.5 * (e + e.T)
    values, vectors = ref.eigh_mp(a)
    values = np.array([float(v - mpmath.mpf(1e8)) for v in values])  # eigenvalues - 1e8
    gaps = np.diff(values)
    shifted_norm = norm2(a - np.trace(a) / 3 * np.eye(3))
    theory = 32 * EPS * shifted_norm / min(gaps)
    assert min(gaps) > 1e-8 and theory < 1e-12  # the case is well posed after the shift
    p = ph.principal(a, rtol=NO_MERGE_RTOL)
    check_eigen(a, p.moments, p.axes)
    np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])
    np.testing.assert_allclose(p.moments - 1e8, values, rtol=0, atol=4 * np.spacing(1e8))
    for k in range(3):
        angle = ref.axis_angle(p.axes[:, k], vectors[:, k])
        assert angle <= 1e-12, f"axis {k} off by {angle:.3e} rad (bound 1e-12)"


@pytest.mark.parametrize("small", [1e-20, 1e-12, 3e-300])
def test_a_decoupled_axis_keeps_its_moment_exactly(small):
    """A moment whose axis no rotation touches (a diagonal tensor, or an axis decoupled from a
    rotated block) is exactly its diagonal entry, however small beside the others (here an
    exact eigenvalue by construction). Shifted by trace/3 and back it lost its digits below eps
    of the trace: diag(1e-20, 1, 1) gave 0, and simulate refused the body for a zero moment;
    Body.from_inertia lost it in tr(I) / 2 as well."""
    p = ph.principal(np.diag([1.0, small, 2.0]))
    assert p.moments.tolist() == [small, 1.0, 2.0]
    np.testing.assert_array_equal(np.abs(p.axes), np.eye(3)[:, [1, 0, 2]])
    # A rotated 2x2 block in the xy plane and the small moment on z.
    c, s = math.cos(0.3), math.sin(0.3)
    r = np.array([[c, -s], [s, c]])
    a = np.zeros((3, 3))
    a[:2, :2] = r @ np.diag([1.0, 2.0]) @ r.T
    a[2, 2] = small
    a = 0.5 * (a + a.T)
    p = ph.principal(a)
    assert p.moments[0] == small
    np.testing.assert_array_equal(p.axes[:, 0] ** 2, [0.0, 0.0, 1.0])
    values, _ = ref.eigh_mp(a)
    np.testing.assert_allclose(p.moments[1:], [float(v) for v in values[1:]], atol=4 * EPS * 2)
    check_eigen(a, p.moments, p.axes)
    # A body built from the diagonal tensor keeps the small moment to round-off (its second
    # moments c_k = (I_i + I_j - I_k) / 2 no longer pass through tr(I) / 2, which lost it).
    body = ph.Body.from_inertia(1.0, np.diag([1.0, small, 1.0]))
    moments = body.principal().moments
    np.testing.assert_allclose(moments, [small, 1.0, 1.0], rtol=4 * EPS, atol=0)
    # A body given by the diagonal tensor moves as the one given by its moments.
    times = np.array([0.0, 1.0])
    by_tensor = ph.simulate(np.diag([small, 1.0, 1.0]), [1.0, 0.0, 0.1], times)
    by_moments = ph.simulate([small, 1.0, 1.0], [1.0, 0.0, 0.1], times)
    np.testing.assert_array_equal(by_tensor.omega, by_moments.omega)


@pytest.mark.parametrize("scale", [1.0, 1e300, 1e-300])
@pytest.mark.parametrize("off", [1e-308, 1e-310, 3e-320])
def test_an_anisotropic_part_below_the_smallest_normal_number(scale, off):
    """A nearly spherical tensor whose products of inertia are below the smallest normal
    number relative to its diagonal: its anisotropic part, scaled to entries near 1, was
    subnormal, and its reciprocal overflowed. principal refused such a tensor for moments that
    "overflow double precision (the largest is about 1.0e+0)", and Body.from_inertia refused
    the body. The exact moments are scale * (1 +- off / 1), equal to the last bit: a sphere."""
    a = scale * np.array([[1.0, off, 0.0], [off, 1.0, 0.0], [0.0, 0.0, 1.0]])
    for p in (ph.principal(a), ph.principal(a[None])):
        np.testing.assert_array_equal(np.reshape(p.moments, 3), [scale] * 3)
        np.testing.assert_array_equal(np.reshape(p.multiplicity, 3), [3, 3, 3])
        np.testing.assert_array_equal(np.reshape(p.axes, (3, 3)), np.eye(3))
    if scale == 1.0:
        body = ph.Body.from_inertia(1.0, a)
        np.testing.assert_array_equal(body.principal().moments, [1.0, 1.0, 1.0])
