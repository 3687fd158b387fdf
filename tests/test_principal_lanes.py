"""The batch eigensolve solves tensors side by side in SIMD lanes, and point masses in one pass:
a tensor's result must not depend on its neighbours in a batch, and degenerate tensors (every
lane of a batch a symmetric top or a sphere) must give their closed-form moments and axes; a
point cloud whose first point is far from the rest must keep its digits."""

from __future__ import annotations

import numpy as np
import pytest

import polhode as ph
import reference as ref
from conftest import check_eigen, norm2
from reference import EPS


def bits(x):
    return np.ascontiguousarray(x).view(np.uint64)


def mixed_tensors(rng, n):
    """Tensors of every kind the lanes treat differently: distinct moments (many sweeps),
    diagonal (no sweep), symmetric tops with the pair below and above the unique moment,
    rotated spheres, exact spheres, nearly equal moments, a zero tensor, and extreme scales."""
    out = []
    for k in range(n):
        kind = k % 9
        r = ref.random_rotation(rng)
        a, b = rng.uniform(0.5, 2.0, 2)
        if kind == 0:
            t = rng.normal(size=(3, 3))
            t = t + t.T
        elif kind == 1:
            t = np.diag(rng.uniform(-1.0, 1.0, 3))
        elif kind == 2:
            t = r @ np.diag([a, a, a + b]) @ r.T
        elif kind == 3:
            t = r @ np.diag([a, a + b, a + b]) @ r.T
        elif kind == 4:
            t = r @ np.diag([a, a, a]) @ r.T
        elif kind == 5:
            t = a * np.eye(3)
        elif kind == 6:
            t = r @ np.diag([a, a * (1 + 1e-9), b]) @ r.T
        elif kind == 7:
            t = np.zeros((3, 3))
        else:
            t = rng.normal(size=(3, 3)) * 10.0 ** rng.choice([-300, 300])
            t = t + t.T
        out.append(0.5 * (t + t.T))
    return np.array(out)


@pytest.mark.parametrize("n", [1, 3, 4, 5, 37, 9 * 4 * 7 + 3])
def test_each_tensor_of_a_batch_equals_its_single_solve_bit_for_bit(rng, n):
    # Every lane performs the same IEEE operations as a lone tensor, and a rotation one lane
    # does not need leaves it untouched: so the bits of tensor k do not depend on the tensors
    # beside it, on its lane, or on the batch's tail (sizes not a multiple of the lanes).
    tensors = mixed_tensors(rng, n)
    batch = ph.principal(tensors)
    for k, a in enumerate(tensors):
        single = ph.principal(a)
        assert np.array_equal(bits(batch.moments[k]), bits(single.moments)), k
        assert np.array_equal(bits(batch.axes[k]), bits(single.axes)), k
        assert np.array_equal(batch.multiplicity[k], single.multiplicity), k
    # ... and a shuffled batch puts every tensor in another lane beside other neighbours.
    order = rng.permutation(n)
    shuffled = ph.principal(tensors[order])
    assert np.array_equal(bits(shuffled.moments), bits(batch.moments[order]))
    assert np.array_equal(bits(shuffled.axes), bits(batch.axes[order]))
    assert np.array_equal(shuffled.multiplicity, batch.multiplicity[order])


@pytest.mark.parametrize(
    "n",
    [
        12,  # one full group of 12 lanes
        12 + 4 + 3,  # a group of 12, a tail group of 4, three alone
        3 * 12 + 11,  # tail of 11: a group of 4 and seven alone
        4096 + 12 * 2 + 9,  # over a chunk boundary (4096 = 341 * 12 + 4: a tail of 4 per chunk)
    ],
)
def test_groups_of_twelve_and_their_tails_equal_single_solves_and_eigh(rng, n):
    # The batch runs groups of 12 tensors side by side (then groups of 4, then tensors alone
    # for the rest of each chunk of 4096). Lanes that converge after different numbers of
    # sweeps share a group (the mix below: diagonal tensors need none, random ones four or
    # five, symmetric tops two): each tensor's bits must still be those of its single solve,
    # and its moments those of numpy.linalg.eigh to 20 eps ||A|| (both backward stable).
    tensors = mixed_tensors(rng, n)
    tensors = tensors[rng.permutation(n)]
    batch = ph.principal(tensors)
    step = 1 if n < 1000 else 7
    for k in range(0, n, step):
        single = ph.principal(tensors[k])
        assert np.array_equal(bits(batch.moments[k]), bits(single.moments)), k
        assert np.array_equal(bits(batch.axes[k]), bits(single.axes)), k
        assert np.array_equal(batch.multiplicity[k], single.multiplicity), k
    for k in list(range(0, n, step)) + list(range(n - 24, n)):
        a = tensors[k]
        w, _ = ref.principal_eigh(a)
        scale = norm2(a)
        assert np.abs(batch.moments[k] - w).max() <= 20 * EPS * scale, k
        check_eigen(a, batch.moments[k], batch.axes[k], what=f"tensor {k} of {n}")


def test_batch_of_mixed_tensors_is_backward_stable(rng):
    tensors = mixed_tensors(rng, 9 * 40)
    p = ph.principal(tensors)
    for a, w, v in zip(tensors, p.moments, p.axes, strict=True):
        check_eigen(a, w, v, what=np.array2string(a))


@pytest.mark.parametrize("pair", ["low", "high"])
def test_symmetric_tops_in_every_lane_against_the_closed_form(rng, pair):
    # R diag(a, a, a + b) R^T (pair below) or R diag(a, a + b, a + b) R^T (pair above): the
    # moments are a and a + b exactly in exact arithmetic; forming the tensor rounds each entry
    # by eps of ||A||, so the solve must give them to 10 eps ||A|| (Weyl), the pair returned
    # exactly equal and flagged, and the unique axis along R's column to 10 eps ||A|| / b
    # (Davis-Kahan; b >= 0.5 here).
    n = 4 * 250 + 1
    a = rng.uniform(0.5, 2.0, n)
    b = rng.uniform(0.5, 2.0, n)
    rotations = np.array([ref.random_rotation(rng) for _ in range(n)])
    if pair == "low":
        diag = np.stack([a, a, a + b], axis=1)
        unique, flags = 2, [2, 2, 1]
    else:
        diag = np.stack([a, a + b, a + b], axis=1)
        unique, flags = 0, [1, 2, 2]
    tensors = np.einsum("nij,nj,nkj->nik", rotations, diag, rotations)
    tensors = 0.5 * (tensors + tensors.transpose(0, 2, 1))
    p = ph.principal(tensors)
    assert (p.multiplicity == flags).all()
    paired = [0, 1] if pair == "low" else [1, 2]
    assert np.array_equal(p.moments[:, paired[0]], p.moments[:, paired[1]])
    for k in range(n):
        scale = norm2(tensors[k])
        assert np.abs(p.moments[k] - diag[k]).max() <= 10 * EPS * scale, k
        bound = 10 * EPS * scale / b[k]
        assert ref.axis_angle(p.axes[k][:, unique], rotations[k][:, unique]) <= bound, k
        check_eigen(tensors[k], p.moments[k], p.axes[k], what=f"top {k}")


def test_spheres_in_every_lane_give_the_body_axes(rng):
    # c 1 rotated by R is c 1 up to the rounding of the product: the three moments are c to
    # 10 eps ||A||, returned equal, flagged 3 3 3, with the body's own axes (the identity).
    n = 4 * 100 + 2
    c = rng.uniform(0.5, 2.0, n) * 10.0 ** rng.integers(-100, 100, n)
    rotations = np.array([ref.random_rotation(rng) for _ in range(n)])
    tensors = np.einsum("nij,n,nkj->nik", rotations, c, rotations)
    tensors = 0.5 * (tensors + tensors.transpose(0, 2, 1))
    p = ph.principal(tensors)
    assert (p.multiplicity == 3).all()
    assert np.array_equal(p.axes, np.broadcast_to(np.eye(3), (n, 3, 3)))
    scale = np.linalg.norm(tensors, axis=(1, 2))
    assert (np.abs(p.moments - c[:, None]) <= 10 * EPS * scale[:, None]).all()


@pytest.mark.parametrize("outlier", [1e3, 1e6])
def test_point_masses_with_a_far_light_first_point(outlier):
    # The one-pass factor is accurate to eps of the offsets from its reference point, the
    # centre of mass of the first block of points: a light first point far from the rest (an
    # outlier) must not become that reference. Against exact rational arithmetic, rounded once:
    # the inertia to 64 eps of its norm.
    rng = np.random.default_rng(7)
    n = 2000
    masses = rng.uniform(0.5, 2.0, n)
    positions = rng.normal(size=(n, 3)) * [1.0, 2.0, 3.0] + [5.0, -3.0, 1.0]
    masses[0] = 1e-9
    positions[0] = [outlier, -outlier, 0.5 * outlier]
    body = ph.Body.point_masses(masses, positions)
    exact = ref.point_mass_properties_exact(masses, positions)
    scale = np.linalg.norm(exact.inertia)
    assert np.abs(body.inertia - exact.inertia).max() <= 64 * EPS * scale
    assert np.abs(body.center_of_mass - exact.center_of_mass).max() <= 8 * EPS * outlier


@pytest.mark.parametrize("n", [1, 7, 8, 9, 255, 256, 257, 1000])
def test_point_masses_of_every_block_shape_against_exact_arithmetic(n):
    # Block tails (the rows past the last full group of 8, the last partial block of 256): the
    # inertia about the centre of mass against exact rationals to 64 eps of its norm, far
    # from the origin (1e8: the offsets from the reference point are exact).
    rng = np.random.default_rng(n)
    masses = rng.uniform(0.5, 2.0, n)
    positions = np.round(rng.normal(size=(n, 3)) * 2.0**20) / 2.0**20 + [1e8, -2e8, 3e8]
    body = ph.Body.point_masses(masses, positions)
    exact = ref.point_mass_properties_exact(masses, positions)
    scale = max(np.linalg.norm(exact.inertia), np.finfo(float).tiny)
    assert np.abs(body.inertia - exact.inertia).max() <= 64 * EPS * scale
    assert body.mass == pytest.approx(exact.mass, rel=4 * EPS * n)
