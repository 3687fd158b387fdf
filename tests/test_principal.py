"""principal(): backward stability, conventions (order, det, signs, canonical degenerate frames),
multiplicity flags, batches, and agreement with numpy.linalg.eigh."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
import reference as ref
from conftest import NO_MERGE_RTOL, check_eigen, check_sign_convention, norm2
from reference import EPS

E_X, E_Y, E_Z = np.eye(3)


def random_valid_tensors(rng, n):
    """Inertia tensors R diag(I) R^T with random moments obeying the triangle inequality:
    generic, two equal, three equal, nearly equal, planar, collinear, wide dynamic range."""
    out = []
    for k in range(n):
        kind = k % 7
        c = rng.uniform(0.1, 1.0, 3)  # second-moment eigenvalues >= 0 -> a valid tensor
        if kind == 1:
            c[1] = c[0]
        elif kind == 2:
            c[:] = c[0]
        elif kind == 3:
            c[1] = c[0] * (1 + 1e-9)
        elif kind == 4:
            c[2] = 0.0  # planar
        elif kind == 5:
            c[1:] = 0.0  # collinear
        elif kind == 6:
            c *= 10.0 ** rng.uniform(-6, 6, 3)
        moments = c.sum() - c
        r = ref.random_rotation(rng)
        a = r @ np.diag(moments) @ r.T
        out.append(0.5 * (a + a.T))
    return out


def test_result_shapes_types_and_unpacking():
    a = np.diag([3.0, 1.0, 2.0])
    result = ph.principal(a)
    moments, axes = result
    assert moments is result.moments or np.array_equal(moments, result.moments)
    assert result.moments.shape == (3,) and result.moments.dtype == np.float64
    assert result.axes.shape == (3, 3) and result.axes.dtype == np.float64
    assert result.multiplicity.shape == (3,)
    assert np.issubdtype(np.asarray(result.multiplicity).dtype, np.integer)
    np.testing.assert_allclose(result.moments, [1.0, 2.0, 3.0], rtol=4 * EPS)
    # diag(3, 1, 2): ascending (e_y, e_z, e_x); col2 = e_y x e_z = e_x
    np.testing.assert_allclose(result.axes, np.stack([E_Y, E_Z, E_X], axis=1), atol=2 * EPS)
    body_result = ph.Body.from_inertia(1.0, a).principal()
    assert isinstance(body_result.rotation, Rotation)
    np.testing.assert_allclose(body_result.rotation.as_matrix(), body_result.axes, atol=4 * EPS)


@pytest.mark.parametrize(
    ("diagonal", "columns"),
    [
        ((1.0, 2.0, 3.0), (E_X, E_Y, E_Z)),
        ((2.0, 1.0, 3.0), (E_Y, E_X, -E_Z)),
        ((3.0, 2.0, 1.5), (E_Z, E_Y, -E_X)),
        ((2.0, 3.0, 1.5), (E_Z, E_X, E_Y)),
    ],
)
def test_diagonal_tensors_give_signed_body_axes(diagonal, columns):
    # Exactly diagonal input: the axes are the body axes, signs by the contract (largest
    # component of columns 0 and 1 positive, column 2 their cross product).
    p = ph.principal(np.diag(diagonal))
    np.testing.assert_allclose(p.moments, sorted(diagonal), rtol=4 * EPS)
    np.testing.assert_allclose(p.axes, np.stack(columns, axis=1), atol=2 * EPS)
    np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])


def test_backward_stability_on_random_tensors(rng):
    for a in random_valid_tensors(rng, 700):
        p = ph.principal(a)
        check_eigen(a, p.moments, p.axes, what=np.array2string(a))


def test_agrees_with_numpy_eigh(rng):
    # Both solvers are backward stable (<= 10 eps ||A|| each, Weyl), so the moments agree to
    # 20 eps ||A||; each axis to (residual sum) / gap by Davis-Kahan, checked where the
    # relative gap exceeds 1e-6 (inside smaller gaps only the subspace is determined).
    for a in random_valid_tensors(rng, 700):
        p = ph.principal(a, rtol=NO_MERGE_RTOL)
        w, v = ref.principal_eigh(a)
        scale = norm2(a)
        np.testing.assert_allclose(p.moments, w, rtol=0, atol=20 * EPS * scale)
        for k in range(3):
            gap = min(abs(w[k] - w[j]) for j in range(3) if j != k)
            if gap > 1e-6 * scale:
                assert ref.axis_angle(p.axes[:, k], v[:, k]) <= 20 * EPS * scale / gap


def test_sign_convention_on_non_degenerate_tensors(rng):
    for a in random_valid_tensors(rng, 300):
        w = np.linalg.eigvalsh(a)
        if min(np.diff(w)) < 1e-6 * norm2(a):
            continue
        p = ph.principal(a)
        np.testing.assert_array_equal(p.multiplicity, [1, 1, 1])
        check_sign_convention(p.axes, what=np.array2string(a))
        # and so the columns equal eigh's after the same normalisation
        _, v = ref.principal_eigh(a)
        np.testing.assert_allclose(p.axes, v, atol=1e-9)


def test_results_are_deterministic(rng):
    for a in random_valid_tensors(rng, 50):
        first, second = ph.principal(a), ph.principal(a.copy())
        np.testing.assert_array_equal(first.moments, second.moments)
        np.testing.assert_array_equal(first.axes, second.axes)


def test_batch_equals_per_matrix_results(rng):
    tensors = np.array(random_valid_tensors(rng, 210))
    batch = ph.principal(tensors)
    assert batch.moments.shape == (210, 3)
    assert batch.axes.shape == (210, 3, 3)
    assert np.asarray(batch.multiplicity).shape == (210, 3)
    # the same deterministic algorithm per matrix: identical bits whether batched or not
    for k, a in enumerate(tensors):
        single = ph.principal(a)
        np.testing.assert_array_equal(batch.moments[k], single.moments)
        np.testing.assert_array_equal(batch.axes[k], single.axes)
        np.testing.assert_array_equal(batch.multiplicity[k], single.multiplicity)
    moments, axes = ph.principal(list(tensors[:2]))  # array-likes, unpacking
    assert moments.shape == (2, 3) and axes.shape == (2, 3, 3)


# ---------------------------------------------------------------------------------------------
# Degenerate moments: multiplicity and canonical frames
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("body", "multiplicity", "columns"),
    [
        (ph.Body.sphere(2.0, 1.0), (3, 3, 3), (E_X, E_Y, E_Z)),
        (ph.Body.spherical_shell(2.0, 1.0), (3, 3, 3), (E_X, E_Y, E_Z)),
        (ph.Body.cuboid(2.0, (1.0, 1.0, 1.0)), (3, 3, 3), (E_X, E_Y, E_Z)),
        # long cylinder: I_z smallest -> (e_z, e_x, e_y) as in the contract
        (ph.Body.cylinder(2.0, 0.1, 0.5), (1, 2, 2), (E_Z, E_X, E_Y)),
        (ph.Body.rod(2.0, 1.0), (1, 2, 2), (E_Z, E_X, E_Y)),
        (ph.Body.capsule(2.0, 0.1, 1.0), (1, 2, 2), (E_Z, E_X, E_Y)),
        # flat cylinder, disc, torus: I_z largest -> (e_x, e_y, e_z)
        (ph.Body.cylinder(2.0, 2.0, 0.1), (2, 2, 1), (E_X, E_Y, E_Z)),
        (ph.Body.disk(2.0, 1.0), (2, 2, 1), (E_X, E_Y, E_Z)),
        (ph.Body.torus(2.0, 1.0, 0.3), (2, 2, 1), (E_X, E_Y, E_Z)),
        # square prisms along the other axes (I_x = m (b^2 + c^2) / 12, cyclic)
        (ph.Body.cuboid(2.0, (1.0, 1.0, 2.0)), (1, 2, 2), (E_Z, E_X, E_Y)),
        (ph.Body.cuboid(2.0, (2.0, 2.0, 1.0)), (2, 2, 1), (E_X, E_Y, E_Z)),
        (ph.Body.cuboid(2.0, (3.0, 1.0, 1.0)), (1, 2, 2), (E_X, E_Y, E_Z)),
        (ph.Body.cuboid(2.0, (1.0, 3.0, 3.0)), (2, 2, 1), (E_Y, E_Z, E_X)),
        (ph.Body.cuboid(2.0, (0.5, 3.0, 3.0)), (2, 2, 1), (E_Y, E_Z, E_X)),
        (ph.Body.cuboid(2.0, (2.0, 1.0, 1.0)), (1, 2, 2), (E_X, E_Y, E_Z)),
        # distinct moments: the sign convention (column 2 = column 0 x column 1)
        (ph.Body.cuboid(2.0, (1.0, 2.0, 3.0)), (1, 1, 1), (E_Z, E_Y, -E_X)),
        (ph.Body.ellipsoid(2.0, (3.0, 2.0, 1.0)), (1, 1, 1), (E_X, E_Y, E_Z)),
    ],
    ids=[
        "sphere",
        "shell",
        "cube",
        "long-cylinder",
        "rod",
        "capsule",
        "flat-cylinder",
        "disk",
        "torus",
        "box-1-1-2",
        "box-2-2-1",
        "box-3-1-1",
        "box-1-3-3",
        "box-0.5-3-3",
        "box-2-1-1",
        "box-1-2-3",
        "ellipsoid-3-2-1",
    ],
)
def test_multiplicity_and_canonical_frames(body, multiplicity, columns):
    p = body.principal()
    check_eigen(body.inertia, p.moments, p.axes)
    np.testing.assert_array_equal(p.multiplicity, multiplicity)
    # Body-aligned bodies: the canonical frame is made of body axes exactly.
    np.testing.assert_allclose(p.axes, np.stack(columns, axis=1), atol=4 * EPS)


@pytest.mark.parametrize(
    ("size", "unique_column", "unique_axis", "pair_axes"),
    [((1.0, 2.0, 1.0), 0, E_Y, (E_X, E_Z)), ((2.0, 1.0, 2.0), 2, E_Y, (E_X, E_Z))],
    ids=["y-smallest", "y-largest"],
)
def test_degenerate_pair_around_the_y_axis(size, unique_column, unique_axis, pair_axes):
    # The pair (x, z) in body order with the unique y axis cannot all keep + signs and det +1;
    # the contract fixes the subspaces and the order; we check those, det = +1, and that every
    # column is a signed body axis.
    p = ph.Body.cuboid(2.0, size).principal()
    expected_multiplicity = [2, 2, 2]
    expected_multiplicity[unique_column] = 1
    np.testing.assert_array_equal(p.multiplicity, expected_multiplicity)
    assert ref.axis_angle(p.axes[:, unique_column], unique_axis) <= 4 * EPS
    pair = [k for k in range(3) if k != unique_column]
    for k, axis in zip(pair, pair_axes, strict=True):
        assert ref.axis_angle(p.axes[:, k], axis) <= 4 * EPS
    assert np.linalg.det(p.axes) == pytest.approx(1.0, abs=8 * EPS)
    np.testing.assert_allclose(np.abs(p.axes).sum(axis=0), [1, 1, 1], atol=8 * EPS)


def test_isotropic_cylinder_is_spherical():
    # L = sqrt(3) r: I_x = m (3 r^2 + 3 r^2) / 12 = m r^2 / 2 = I_z, equal up to round-off.
    body = ph.Body.cylinder(2.0, 1.0, math.sqrt(3.0))
    p = body.principal()
    np.testing.assert_array_equal(p.multiplicity, [3, 3, 3])
    np.testing.assert_allclose(p.axes, np.eye(3), atol=4 * EPS)


@pytest.mark.parametrize("seed", range(20))
def test_rotated_degenerate_tensors_as_subspaces(seed):
    # R diag(a, b, b) R^T (and a, a, b): the unique axis is R e_k to (10 eps ||A||) / gap; the
    # pair only as a subspace (its individual vectors are arbitrary), same bound.
    rng = np.random.default_rng(seed)
    r = ref.random_rotation(rng)
    for moments, unique, mult in [
        ((1.0, 2.0, 2.0), 0, [1, 2, 2]),
        ((1.5, 1.5, 2.0), 2, [2, 2, 1]),
        ((0.0, 1.0, 1.0), 0, [1, 2, 2]),
    ]:
        a = r @ np.diag(moments) @ r.T
        a = 0.5 * (a + a.T)
        p = ph.principal(a)
        check_eigen(a, p.moments, p.axes)
        np.testing.assert_array_equal(p.multiplicity, mult)
        gap = abs(moments[2] - moments[0])
        bound = 16 * EPS * norm2(a) / gap
        assert ref.axis_angle(p.axes[:, unique], r[:, unique]) <= bound
        pair = [k for k in range(3) if k != unique]
        assert ref.subspace_distance(p.axes[:, pair], r[:, pair]) <= bound
    # three equal moments: any frame spans everything; canonical = the body axes
    p = ph.principal(r @ np.diag([2.0, 2.0, 2.0]) @ r.T)
    np.testing.assert_array_equal(p.multiplicity, [3, 3, 3])
    np.testing.assert_allclose(p.axes, np.eye(3), atol=4 * EPS)


def test_rtol_decides_what_is_degenerate():
    # Moments 1, 1 + 1e-12, 2: distinct for a tiny rtol, a pair for rtol = 1e-9.
    r = Rotation.from_rotvec([0.3, -0.8, 0.5]).as_matrix()
    a = r @ np.diag([1.0, 1.0 + 1e-12, 2.0]) @ r.T
    a = 0.5 * (a + a.T)
    merged = ph.principal(a, rtol=1e-9)
    np.testing.assert_array_equal(merged.multiplicity, [2, 2, 1])
    split = ph.principal(a, rtol=1e-14)
    np.testing.assert_array_equal(split.multiplicity, [1, 1, 1])
    # Merged moments may be returned equal (their mean): that moves each by half the 1e-12 gap,
    # so the merged result's residual is 10 eps ||A|| + 0.5e-12 (what rtol = 1e-9 asked for).
    check_eigen(a, merged.moments, merged.axes, residual_eps=10 + 0.5e-12 / (EPS * norm2(a)))
    check_eigen(a, split.moments, split.axes)
    for p in (merged, split):
        assert ref.subspace_distance(p.axes[:, :2], r[:, :2]) <= 16 * EPS * 2 / 1.0
    body = ph.Body.from_inertia(1.0, a)
    np.testing.assert_array_equal(body.principal(rtol=1e-9).multiplicity, [2, 2, 1])
    np.testing.assert_array_equal(body.principal(rtol=1e-14).multiplicity, [1, 1, 1])


def test_body_principal_reconstructs_the_tensor(rng):
    for _ in range(20):
        masses = rng.uniform(0.1, 2.0, 8)
        body = ph.Body.point_masses(masses, rng.normal(size=(8, 3)))
        p = body.principal()
        i = np.asarray(body.inertia)
        # V diag(I) V^T - I = (A V - V D) V^T + A (V V^T - 1) + rounding: 10 + 10 + 3 eps.
        recon = p.axes @ np.diag(p.moments) @ p.axes.T
        assert norm2(recon - i) <= 24 * EPS * norm2(i)
