"""Frames over time: point_masses_inertia (per-frame inertia of a (T, N, 3) trajectory) and
principal(continuous=True) (axes followed from frame to frame), against numpy references
written here and in reference.py, closed forms (known rotations, a known crossing, a symmetric
top) and MDAnalysis's per-frame principal_axes()."""

from __future__ import annotations

import itertools

import MDAnalysis as mda
import numpy as np
import pytest
from MDAnalysis.coordinates.memory import MemoryReader
from scipy.spatial.transform import Rotation

import polhode as ph
import reference as ref
from reference import EPS


def asymmetric_cloud(rng, n=40):
    """Masses and positions of a clearly asymmetric cloud (moments well apart)."""
    masses = rng.uniform(1.0, 16.0, n)
    positions = rng.normal(size=(n, 3)) * [3.0, 2.0, 1.0]
    return masses, positions


def smooth_rotations(count, step_degrees=3.0, seed=1):
    """A smooth sequence of rotations: a fixed-size step about a slowly wandering axis."""
    t = np.arange(count)
    axis = np.stack([np.cos(t / 30.0), np.sin(t / 30.0), 0.6 + 0.4 * np.cos(t / 17.0)], axis=1)
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    steps = Rotation.from_rotvec(np.radians(step_degrees) * axis)
    start = Rotation.random(random_state=seed)
    out = [start]
    for step in steps[1:]:
        out.append(step * out[-1])
    return Rotation.concatenate(out).as_matrix()


def flips(axes):
    """Per axis, the frames whose axis has a negative dot product with the previous frame's."""
    return (np.einsum("tik,tik->tk", axes[1:], axes[:-1]) < 0).sum(axis=0)


# --- point_masses_inertia ---------------------------------------------------------------------


def test_point_masses_inertia_matches_the_numpy_reference_per_frame():
    rng = np.random.default_rng(0)
    masses, cloud = asymmetric_cloud(rng, 57)  # 57 atoms: lanes of 8 and a remainder
    frames = smooth_rotations(25)
    positions = np.einsum("tij,nj->tni", frames, cloud) + rng.normal(size=(25, 1, 3)) * 10.0
    inertia = ph.point_masses_inertia(masses, positions)
    assert inertia.shape == (25, 3, 3)
    for t in range(25):
        expected = ref.point_mass_properties(masses, positions[t]).inertia
        # Plain sums of N = 57 products: a few eps per term of the trace.
        assert np.abs(inertia[t] - expected).max() <= 64 * EPS * np.trace(expected)
    # One frame (N, 3) gives one tensor (3, 3).
    single = ph.point_masses_inertia(masses, positions[3])
    assert single.shape == (3, 3)
    np.testing.assert_array_equal(single, inertia[3])


def test_single_precision_positions_are_read_exactly():
    rng = np.random.default_rng(1)
    masses, cloud = asymmetric_cloud(rng, 30)
    positions = (np.einsum("tij,nj->tni", smooth_rotations(8), cloud) + 50.0).astype(np.float32)
    got = ph.point_masses_inertia(masses, positions)
    # The float32 values widened exactly to float64 give the same sums, bit for bit.
    np.testing.assert_array_equal(got, ph.point_masses_inertia(masses, positions.astype(float)))
    for t in range(8):
        expected = ref.point_mass_properties(masses, positions[t].astype(float)).inertia
        assert np.abs(got[t] - expected).max() <= 64 * EPS * np.trace(expected)


def test_a_cloud_far_from_the_origin_keeps_its_digits():
    # Each frame is centred on its own first point first: 1e9 away, a unit cloud's inertia
    # keeps its digits (a sum about the origin, shifted back, would lose all of them).
    rng = np.random.default_rng(2)
    masses = rng.uniform(1.0, 3.0, 12)
    cloud = np.round(rng.normal(size=(12, 3)) * 64) / 64  # exact in binary, also at 1e9
    positions = np.stack([cloud, cloud + 1e9])
    inertia = ph.point_masses_inertia(masses, positions)
    exact = ref.point_mass_properties_exact(masses, cloud).inertia
    for t in range(2):
        assert np.abs(inertia[t] - exact).max() <= 64 * EPS * np.trace(exact)


def test_a_needle_keeps_its_small_moment():
    # Points along x spread by 1e-9 across it: I_xx = sum m (y^2 + z^2) ~ 1e-18 next to
    # I_yy ~ 1; each diagonal element is formed from the two other second moments, so it keeps
    # its relative digits (tr(C) - C_xx would give 0).
    rng = np.random.default_rng(5)
    masses = rng.uniform(1.0, 2.0, 64)
    positions = np.zeros((64, 3))
    positions[:, 0] = np.linspace(-1.0, 1.0, 64)
    positions[:, 1:] = rng.normal(size=(64, 2)) * 1e-9
    inertia = ph.point_masses_inertia(masses, positions)
    exact = ref.point_mass_properties_exact(masses, positions).inertia
    assert inertia[0, 0] == pytest.approx(exact[0, 0], rel=1e-12)
    assert exact[0, 0] < 1e-16 * exact[1, 1]


def test_point_masses_inertia_names_bad_input():
    masses = np.array([1.0, 2.0, 3.0])
    positions = np.zeros((4, 3, 3))
    positions[:, 1, 0] = 1.0
    positions[:, 2, 1] = 1.0
    bad = positions.copy()
    bad[2, 1, 2] = np.nan
    with pytest.raises(ph.NonFiniteError, match=r"positions\[2, 1, 2\]") as error:
        ph.point_masses_inertia(masses, bad)
    assert error.value.argument == "positions"
    with pytest.raises(ph.NonFiniteError, match=r"positions\[1, 2\]"):
        ph.point_masses_inertia(masses, bad[2])
    with pytest.raises(ph.NonPositiveError, match=r"masses\[1\]") as error:
        ph.point_masses_inertia([1.0, 0.0, 1.0], positions)
    assert error.value.argument == "masses"
    with pytest.raises(ph.NonFiniteError, match=r"masses\[2\]"):
        ph.point_masses_inertia([1.0, 1.0, np.inf], positions)
    with pytest.raises(ph.ShapeError, match="positions") as error:
        ph.point_masses_inertia([1.0, 2.0], positions)
    assert error.value.argument == "positions"
    with pytest.raises(ph.ShapeError, match="positions"):
        ph.point_masses_inertia(masses, np.zeros((4, 3, 2)))
    with pytest.raises(ph.ShapeError, match="masses"):
        ph.point_masses_inertia([], np.zeros((4, 0, 3)))
    with pytest.raises(ph.ShapeError, match="masses"):
        ph.point_masses_inertia([[1.0]], positions)
    with pytest.raises(TypeError, match="positions"):
        ph.point_masses_inertia(masses, "positions")
    with pytest.raises(ph.ArgumentError, match="overflows") as error:
        ph.point_masses_inertia([1.0, 1.0], [[[-1e200, 0, 0], [1e200, 0, 0]]])
    assert error.value.argument == "positions"
    # No frames: no tensors.
    assert ph.point_masses_inertia(masses, np.zeros((0, 3, 3))).shape == (0, 3, 3)


# --- principal(continuous=True) ---------------------------------------------------------------


def test_axes_follow_a_smooth_rotation_of_an_asymmetric_cloud():
    rng = np.random.default_rng(3)
    masses, cloud = asymmetric_cloud(rng)
    frames = smooth_rotations(300)
    positions = np.einsum("tij,nj->tni", frames, cloud)
    inertia = ph.point_masses_inertia(masses, positions)
    p = ph.principal(inertia, continuous=True)
    # Frame 0 is the canonical frame (numpy's eigh, canonical signs: reference.py).
    moments0, axes0 = ref.principal_eigh(inertia[0])
    np.testing.assert_allclose(p.moments[0], moments0, rtol=1e-12)
    assert np.abs(p.axes[0] - axes0).max() < 1e-10
    # Every later frame: the same body axes carried by the known rotation, R_t R_0^T A_0.
    expected = frames @ frames[0].T @ p.axes[0]
    assert np.abs(p.axes - expected).max() < 1e-10
    np.testing.assert_allclose(p.moments, np.broadcast_to(moments0, (300, 3)), rtol=1e-12)
    np.testing.assert_allclose(np.linalg.det(p.axes), 1.0, atol=1e-12)
    assert flips(p.axes).tolist() == [0, 0, 0]
    # Without following, the canonical signs flip along the same motion (what is fixed here).
    assert flips(ph.principal(inertia).axes).sum() > 0


def reference_follow(tensors):
    """An independent, sequential reference: numpy's eigh per frame (ascending), then, frame by
    frame, the proper signed permutation (of the 24) maximising trace(W_prev^T U Q)."""
    proper = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1.0, -1.0), repeat=3):
            q = np.zeros((3, 3))
            q[list(perm), [0, 1, 2]] = signs
            if np.linalg.det(q) > 0:
                proper.append((np.array(perm), q))
    moments, axes = [], []
    for k, tensor in enumerate(tensors):
        w, u = ref.principal_eigh(tensor)
        if k > 0:
            perm, q = max(proper, key=lambda pq: np.trace(axes[-1].T @ u @ pq[1]))
            w, u = w[perm], u @ q
        moments.append(w)
        axes.append(u)
    return np.array(moments), np.array(axes)


def test_continuous_axes_match_a_sequential_brute_force_reference():
    # Random smooth tensor series whose moments cross each other (never exactly equal on the
    # grid): polhode's vectorised matching against the frame-by-frame brute force.
    count = 400
    frames = smooth_rotations(count, step_degrees=2.0, seed=5)
    s = np.linspace(0.0, 1.0, count)
    moments = np.stack(
        [2.0 + np.sin(7.1 * s + 0.3), 2.0 + np.cos(5.3 * s), 2.2 + 0.8 * np.sin(3.7 * s + 1.0)],
        axis=1,
    )
    tensors = frames @ (moments[:, :, None] * np.eye(3)) @ frames.transpose(0, 2, 1)
    p = ph.principal(tensors, continuous=True)
    ref_moments, ref_axes = reference_follow(tensors)
    assert np.abs(p.axes - ref_axes).max() < 1e-9
    np.testing.assert_allclose(p.moments, ref_moments, rtol=1e-12)
    # The moments crossed: no longer ascending, yet no flips and the same physical axes.
    assert (np.diff(p.moments, axis=1) < 0).any()
    assert flips(p.axes).tolist() == [0, 0, 0]
    assert np.abs(p.axes - frames @ frames[0].T @ p.axes[0]).max() < 1e-9


def test_a_crossing_of_two_moments_through_an_exactly_degenerate_frame():
    # I(t) = R(t) diag(a, 3 - a, 4) R(t)^T with a from 1 to 2: moments 0 and 1 cross at the
    # middle frame, where they are equal (a = 1.5 exactly) and flagged degenerate.
    count = 41
    frames = smooth_rotations(count, step_degrees=2.0, seed=6)
    a = np.linspace(1.0, 2.0, count)
    assert a[20] == 1.5
    diag = np.zeros((count, 3, 3))
    diag[:, 0, 0], diag[:, 1, 1], diag[:, 2, 2] = a, 3.0 - a, 4.0
    tensors = frames @ diag @ frames.transpose(0, 2, 1)
    p = ph.principal(tensors, continuous=True)
    assert p.multiplicity[20].tolist() == [2, 2, 1]
    # Axis k stays column k of R(t) (up to frame 0's signs) and keeps its moment: axis 0
    # carries a(t) throughout, so after the crossing the moments are descending.
    signs = np.sign(np.einsum("ik,ik->k", p.axes[0], frames[0]))
    expected = frames * signs
    others = [t for t in range(count) if t != 20]
    assert np.abs(p.axes[others] - expected[others]).max() < 1e-9
    np.testing.assert_allclose(p.moments[:, 0], a, rtol=1e-12)
    np.testing.assert_allclose(p.moments[:, 1], 3.0 - a, rtol=1e-12)
    # At the degenerate frame the pair is the basis of its plane closest to the previous
    # frame's axes: within the step's rotation (2 degrees) of R(t)'s columns.
    assert np.abs(p.axes[20] - expected[20]).max() < np.radians(2.0)
    assert ref.subspace_distance(p.axes[20][:, :2], frames[20][:, :2]) < 1e-12
    assert flips(p.axes).tolist() == [0, 0, 0]
    np.testing.assert_allclose(np.linalg.det(p.axes), 1.0, atol=1e-12)


def test_a_symmetric_top_keeps_its_axis_and_continuous_transverse_axes():
    # Every frame degenerate (moments 1, 1, 3): the symmetry axis follows R(t) e_z with one
    # sign, and the transverse pair moves no more than the rotation between frames.
    count = 200
    step = np.radians(3.0)
    frames = smooth_rotations(count, step_degrees=3.0, seed=7)
    tensors = frames @ np.diag([1.0, 1.0, 3.0]) @ frames.transpose(0, 2, 1)
    p = ph.principal(tensors, continuous=True)
    assert (p.multiplicity == [2, 2, 1]).all()
    np.testing.assert_allclose(p.moments, np.broadcast_to([1.0, 1.0, 3.0], (count, 3)))
    sign = np.sign(p.axes[0][:, 2] @ frames[0][:, 2])
    assert np.abs(p.axes[:, :, 2] - sign * frames[:, :, 2]).max() < 1e-12
    assert flips(p.axes).tolist() == [0, 0, 0]
    moved = np.linalg.norm(p.axes[1:] - p.axes[:-1], axis=1)  # per column, per frame
    assert moved.max() <= 2 * np.sin(step / 2) * (1 + 1e-9)
    # Still principal axes of each tensor, a proper rotation.
    residual = np.einsum("tij,tjk->tik", tensors, p.axes) - p.axes * p.moments[:, None, :]
    assert np.abs(residual).max() < 1e-13
    eye = np.einsum("tji,tjk->tik", p.axes, p.axes)
    assert np.abs(eye - np.eye(3)).max() < 1e-13
    np.testing.assert_allclose(np.linalg.det(p.axes), 1.0, atol=1e-12)


def test_a_spherical_frame_keeps_the_previous_axes():
    frames = smooth_rotations(5, seed=8)
    tensors = frames @ np.diag([1.0, 2.0, 3.0]) @ frames.transpose(0, 2, 1)
    tensors[2] = 2.0 * np.eye(3)
    p = ph.principal(tensors, continuous=True)
    assert p.multiplicity[2].tolist() == [3, 3, 3]
    np.testing.assert_allclose(p.axes[2], p.axes[1], atol=1e-15)
    assert flips(p.axes).tolist() == [0, 0, 0]


def test_continuous_agrees_with_mdanalysis_and_has_no_flips_where_it_has_some():
    rng = np.random.default_rng(9)
    masses, cloud = asymmetric_cloud(rng, 60)
    count = 300
    positions = np.einsum("tij,nj->tni", smooth_rotations(count, seed=10), cloud)
    positions += rng.normal(scale=0.05, size=positions.shape)
    universe = mda.Universe.empty(len(masses), trajectory=False)
    universe.add_TopologyAttr("masses", masses)
    universe.load_new(positions, format=MemoryReader, order="fac")
    rows = np.array([universe.atoms.principal_axes() for _ in universe.trajectory])
    mda_axes = rows.transpose(0, 2, 1)[:, :, ::-1]  # descending rows -> ascending columns
    p = ph.principal(ph.point_masses_inertia(masses, positions), continuous=True)
    # The same lines (MDAnalysis works in float32 positions: agreement to about 1e-6).
    dots = np.abs(np.einsum("tik,tik->tk", p.axes, mda_axes))
    assert (1.0 - dots).max() < 1e-9
    assert flips(mda_axes).sum() > 0
    assert flips(p.axes).tolist() == [0, 0, 0]


def test_continuous_needs_a_series_and_a_bool():
    with pytest.raises(ph.ShapeError, match=r"\(T, 3, 3\)") as error:
        ph.principal(np.eye(3), continuous=True)
    assert error.value.argument == "inertia"
    with pytest.raises(TypeError, match="continuous"):
        ph.principal(np.stack([np.eye(3)] * 2), continuous="yes")
    # Empty and one-frame series are returned as they are.
    assert ph.principal(np.zeros((0, 3, 3)), continuous=True).axes.shape == (0, 3, 3)
    one = ph.principal(np.diag([3.0, 1.0, 2.0])[None], continuous=True)
    np.testing.assert_array_equal(one.moments, [[1.0, 2.0, 3.0]])
