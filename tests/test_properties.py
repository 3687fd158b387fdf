"""Property tests (hypothesis): random clouds and solids, random rotations and translations.

Bounds are norm-wise, in eps, with a term for the centre of mass's own resolution where one
enters: a centre stored in float64 is defined only to ~eps |r|, and the inertia about a point
delta away differs by M delta^2 (second order) or, in a composition, by ~2 M delta d.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, note
from hypothesis import strategies as st

import polhode as ph
import reference as ref
from conftest import (
    assert_close_normwise,
    check_eigen,
    clouds,
    norm2,
    positive,
    rotations,
    solid_specs,
    vectors,
)
from reference import EPS


@st.composite
def bodies(draw):
    """(polhode Body, reference MassProperties, largest coordinate magnitude involved)."""
    if draw(st.booleans()):
        masses, positions = draw(clouds())
        expected = ref.point_mass_properties_exact(masses, positions)
        return ph.Body.point_masses(masses, positions), expected, float(np.max(np.abs(positions)))
    name, mass, params = draw(solid_specs())
    body = getattr(ph.Body, name)(mass, *params)
    expected = ref.SOLIDS[name](mass, *params)
    reach = float(max(np.max(np.abs(np.asarray(p, dtype=float))) for p in params))
    if draw(st.booleans()):
        rotation = draw(rotations())
        body, expected = body.rotated(rotation), ref.rotate(expected, rotation)
    if draw(st.booleans()):
        offset = draw(vectors(10.0))
        body, expected = body.translated(offset), ref.translate(expected, offset)
        reach += float(np.max(np.abs(offset)))
    return body, expected, reach


SUBNORMAL = float(np.finfo(float).smallest_subnormal)


def com_resolution_term(mass, reach):
    """M (eps reach)^2: the inertia change for moving the reference point by the centre of
    mass's own resolution."""
    return 4 * mass * (EPS * reach) ** 2


@given(clouds(max_size=30))
def test_point_masses_match_exact(cloud):
    # Summation of N terms: worst case N eps; at least 16 eps for the few roundings per term.
    masses, positions = cloud
    body = ph.Body.point_masses(masses, positions)
    exact = ref.point_mass_properties_exact(masses, positions)
    n = len(masses)
    reach = float(np.max(np.abs(positions)))
    k = max(16, n) * EPS
    assert abs(body.mass - exact.mass) <= k * exact.mass
    assert_close_normwise(body.center_of_mass, exact.center_of_mass, k, scale=max(reach, 1e-300))
    scale = norm2(exact.inertia) + com_resolution_term(exact.mass, reach) / k
    assert_close_normwise(body.inertia, exact.inertia, k, scale=scale, what="inertia")


@given(bodies())
def test_body_matches_reference(case):
    # Solids: closed form, rotated (R I R^T, 9 products) and translated in the reference too.
    body, expected, reach = case
    assert_close_normwise(
        body.inertia,
        expected.inertia,
        32 * EPS,
        scale=norm2(expected.inertia) + com_resolution_term(body.mass, reach) / (32 * EPS),
        what="inertia",
    )
    assert_close_normwise(
        body.center_of_mass, expected.center_of_mass, 32 * EPS, scale=max(reach, 1e-300), what="com"
    )


@given(bodies())
def test_principal_reconstructs_the_tensor(case):
    # residual (10 eps) + orthogonality (10 eps) + the product's rounding (3 eps) -> 24 eps
    body, _, _ = case
    p = body.principal()
    i = np.asarray(body.inertia)
    check_eigen(i, p.moments, p.axes)
    recon = p.axes @ np.diag(p.moments) @ p.axes.T
    assert norm2(recon - i) <= 24 * EPS * norm2(i)
    # valid inertia: non-negative moments and the triangle inequality (to round-off)
    assert p.moments[0] >= -16 * EPS * p.moments[2]
    assert p.moments[0] + p.moments[1] >= p.moments[2] * (1 - 32 * EPS)


@given(bodies(), rotations(), vectors(10.0))
def test_moments_invariant_under_rotation_and_translation(case, rotation, offset):
    # Rotating perturbs the tensor by a few eps ||I||; each eigensolve adds <= 10 eps ||I||:
    # Weyl's inequality gives 32 eps ||I||. A translation must not touch the inertia at all
    # (about the centre of mass), beyond one rounding (2 eps).
    body, _, _ = case
    base = body.principal().moments
    scale = norm2(body.inertia)
    moved = body.rotated(rotation).translated(offset)
    np.testing.assert_allclose(moved.principal().moments, base, rtol=0, atol=32 * EPS * scale)
    shifted = body.translated(offset)
    assert_close_normwise(shifted.inertia, body.inertia, 2 * EPS, scale=scale)
    np.testing.assert_allclose(shifted.principal().moments, base, rtol=0, atol=4 * EPS * scale)


@given(bodies(), rotations())
def test_rotated_axes_follow_the_rotation(case, rotation):
    # Non-degenerate moments: the axes of the rotated body are R times the axes, column by
    # column up to sign, to (32 eps ||I||) / gap (Davis-Kahan).
    body, _, _ = case
    p = body.principal()
    scale = norm2(body.inertia)
    gaps = np.diff(p.moments)
    assume(scale > 0 and np.min(gaps) > 1e-3 * scale)
    r = rotation.as_matrix()
    q = body.rotated(rotation).principal()
    for k in range(3):
        gap = min(abs(p.moments[k] - p.moments[j]) for j in range(3) if j != k)
        assert ref.axis_angle(q.axes[:, k], r @ p.axes[:, k]) <= 32 * EPS * scale / gap


@given(bodies(), vectors(20.0))
def test_parallel_axis_relation(case, point):
    # I_p = I_cm + M (|d|^2 1 - d d^T), d = r_cm - p: a few roundings of each term,
    # 8 eps (||I_cm|| + M |d|^2). And the reference's own error: it has the centre rounded to
    # a double, c + delta with |delta| <= eps |c| / 2 (polhode keeps the centre's low part:
    # a translated cone's centre is not a double), and d = c - p carries delta whole, so
    # M (|d|^2 1 - d d^T) is off by up to 4 M |d| |delta| <= 2 eps M |d| |c|: with |c| = 2.0125
    # and |d| = 0.0125 that is 37 eps of the first scale (polhode and the reference differed
    # by 15 eps there). 8 eps (M |d| |c| / 2) covers it twice.
    body, _, _ = case
    i = np.asarray(body.inertia)
    c = np.asarray(body.center_of_mass)
    d = c - point
    expected = ref.parallel_axis(i, body.mass, c, point)
    scale = (
        norm2(i)
        + body.mass * float(d @ d)
        + body.mass * float(np.linalg.norm(d)) * float(np.linalg.norm(c)) / 2
    )
    assert_close_normwise(body.inertia_about(point), expected, 8 * EPS, scale=scale)


@given(clouds(max_size=20), vectors(20.0))
def test_inertia_about_point_matches_exact(cloud, point):
    masses, positions = cloud
    body = ph.Body.point_masses(masses, positions)
    exact = ref.point_inertia_about(masses, positions, point)
    reach = float(max(np.max(np.abs(positions)), np.max(np.abs(point))))
    k = max(16, len(masses)) * EPS
    scale = norm2(exact) + com_resolution_term(body.mass, reach) / k
    # Below the normal range every rounding is absolute, a step of the smallest subnormal that
    # no relative bound holds (a point mass 8 at 2.1e-156 from the point: I = 3.5e-311, one
    # step off): the floor allows 8 steps per eps of the bound, as the other tests here do.
    scale = max(scale, 8 * SUBNORMAL / EPS)
    assert_close_normwise(body.inertia_about(point), exact, k, scale=scale)


def _composition_scale(parts, total, k, reach=0.0):
    """||I_total|| + M R D (+ the resolution term / k): the centre of mass is resolved to eps R
    (R the largest centre coordinate, or the largest coordinate ``reach`` the parts were made
    from: a part's own centre is only resolved to eps of the coordinates it was computed from),
    and an error delta in it moves a part's parallel-axis term by ~2 m delta D (D the largest
    distance of a part's centre from the composite's), and the tensor itself by M delta^2
    (which is all there is when the parts coincide)."""
    com = np.asarray(total.center_of_mass)
    big_r = max([reach, *(float(np.max(np.abs(p.center_of_mass))) for p in parts)])
    big_d = max(float(np.linalg.norm(np.asarray(p.center_of_mass) - com)) for p in parts)
    scale = norm2(total.inertia) + total.mass * big_r * big_d
    scale += com_resolution_term(total.mass, big_r) / k
    # Second moments below the normal range (parts 1e-156 apart) are subnormal: there every
    # rounding is absolute, and a square root of a subnormal keeps only its few bits, so the
    # error is a number of subnormal spacings (37 seen), not of relative eps. The floor allows
    # 64 spacings per eps of the bound: still 1e-320 at most, nothing in the normal range.
    return max(scale, 64 * SUBNORMAL / EPS), big_r


@given(bodies(), bodies(), bodies())
def test_composition_associative_and_commutative(a, b, c):
    # 16 eps of the composition scale (see _composition_scale).
    a, b, c = a[0], b[0], c[0]
    left = (a + b) + c
    right = a + (b + c)
    swapped = c + (b + a)
    scale, big_r = _composition_scale([a, b, c], left, 16 * EPS)
    for other in (right, swapped):
        assert abs(other.mass - left.mass) <= 4 * EPS * left.mass
        assert_close_normwise(
            other.center_of_mass, left.center_of_mass, 16 * EPS, scale=max(big_r, 1e-300)
        )
        assert_close_normwise(other.inertia, left.inertia, 16 * EPS, scale=scale)
    assert_close_normwise(
        (a + b).inertia,
        (b + a).inertia,
        16 * EPS,
        scale=_composition_scale([a, b], a + b, 16 * EPS)[0],
    )


@given(bodies(), bodies())
def test_composition_matches_reference(a, b):
    # Scaled by the parts' reach, not only their centres: two point masses 1.1 and 77 at z = 1.625
    # and 0 have their centre at 0.0229, resolved to 0.12 eps of 1.625 (test_point_masses_match_
    # exact) but 57 eps of 0.0229; the thorough profile found it with the centres alone.
    (body_a, ref_a, reach_a), (body_b, ref_b, reach_b) = a, b
    total = body_a + body_b
    expected = ref.compose([ref_a, ref_b])
    scale, big_r = _composition_scale(
        [body_a, body_b], total, 32 * EPS, reach=max(reach_a, reach_b)
    )
    assert_close_normwise(
        total.center_of_mass, expected.center_of_mass, 32 * EPS, scale=max(big_r, 1e-300)
    )
    assert_close_normwise(total.inertia, expected.inertia, 32 * EPS, scale=scale)


@given(clouds(min_size=2, max_size=10))
def test_cloud_equals_sum_of_its_points(cloud):
    masses, positions = cloud
    together = ph.Body.point_masses(masses, positions)
    parts = [ph.Body.point_masses([m], [r]) for m, r in zip(masses, positions, strict=True)]
    summed = sum(parts)
    k = 8 * len(masses) * EPS  # one composition step per point
    scale, big_r = _composition_scale(parts, together, k)
    assert_close_normwise(summed.center_of_mass, together.center_of_mass, k, scale=big_r)
    assert_close_normwise(summed.inertia, together.inertia, k, scale=scale)


@given(clouds(max_size=10), st.integers(-60, 60), st.integers(-60, 60))
def test_power_of_two_scaling(cloud, mass_exponent, length_exponent):
    # Scaling masses by 2^a and lengths by 2^b scales the inertia by 2^(a + 2b) and the centre
    # by 2^b without any new rounding (no absolute thresholds): 2 eps. Exception: a
    # square-root representation (rows sqrt(m) (r - r_cm)) takes sqrt(2^a m), which for odd a
    # is rounded differently from 2^(a/2) sqrt(m): eps/2 per factor, ~eps per product, plus
    # the solve's few roundings: 8 eps.
    masses, positions = cloud
    note(f"masses={masses.tolist()!r} positions={positions.tolist()!r}")
    base = ph.Body.point_masses(masses, positions)
    sm, sl = 2.0**mass_exponent, 2.0**length_exponent
    # Exactness needs normal numbers: keep the tensors well away from the subnormal range
    # (< 2.2e-308), where every product loses bits to gradual underflow.
    size = norm2(base.inertia)
    assume(size == 0 or min(size, size * sm * sl * sl) > 1e-250)
    scaled = ph.Body.point_masses(masses * sm, positions * sl)
    k = 2 * EPS if mass_exponent % 2 == 0 else 8 * EPS
    assert_close_normwise(
        scaled.inertia / (sm * sl * sl), base.inertia, k, scale=max(norm2(base.inertia), 1e-300)
    )
    assert_close_normwise(
        scaled.principal().moments / (sm * sl * sl),
        base.principal().moments,
        k,
        scale=max(norm2(base.inertia), 1e-300),
    )
    assert_close_normwise(
        scaled.center_of_mass / sl,
        base.center_of_mass,
        2 * EPS,
        scale=max(float(np.max(np.abs(positions))), 1e-300),
    )


@given(bodies(), vectors(5.0))
def test_angular_momentum_and_energy(case, omega):
    body, _, _ = case
    i = np.asarray(body.inertia)
    momentum = body.angular_momentum_body(omega)
    energy = body.kinetic_energy(omega)
    # Products that fall below the normal range are rounded in absolute steps of the smallest
    # subnormal: each of the (at most 5) roundings of a component or of the energy adds up to
    # one such step, which no relative bound can hold (a scale of 1e-300 * 1e-200 is 0).
    floor = 8 * SUBNORMAL / EPS
    scale = max(norm2(i) * float(omega @ omega), floor)
    assert_close_normwise(
        momentum, i @ omega, 8 * EPS, scale=max(norm2(i) * norm2(omega), floor)
    )
    assert abs(energy - 0.5 * float(omega @ momentum)) <= 8 * EPS * scale
    assert energy >= -8 * EPS * scale


@given(bodies())
def test_principal_matches_numpy_eigh(case):
    # The moments against LAPACK's (numpy.linalg.eigh, a peer): each solver is backward stable
    # to 10 eps ||I|| (conftest.check_eigen), so by Weyl's inequality the moments agree to
    # 20 eps ||I||; the axes of a moment separated from the others by a gap agree up to sign
    # to 20 eps ||I|| / gap (Davis-Kahan), compared where that bound says something.
    body, _, _ = case
    i = np.asarray(body.inertia)
    scale = norm2(i)
    p = body.principal()
    moments, axes = np.linalg.eigh(i)
    np.testing.assert_allclose(p.moments, moments, rtol=0, atol=20 * EPS * scale)
    for k in range(3):
        gap = min(abs(moments[k] - moments[j]) for j in range(3) if j != k)
        if gap > 1e-6 * scale:
            assert ref.axis_angle(p.axes[:, k], axes[:, k]) <= 20 * EPS * scale / gap


@st.composite
def motions(draw):
    """(moments, omega0, times) of a torque-free motion: any positive moments (two or three
    equal at times), omega0 of any size, near an axis, near the separatrix (a spin about the
    intermediate axis, slightly perturbed) or at rest, and up to 8 times within about 100
    turns."""
    moments = np.array([draw(positive) for _ in range(3)])
    shape = draw(st.sampled_from(["any", "symmetric", "spherical"]))
    if shape == "symmetric":
        moments[draw(st.integers(0, 2))] = moments[draw(st.integers(0, 2))]
    elif shape == "spherical":
        moments[:] = moments[0]
    scale = 2.0 ** draw(st.integers(-20, 20))
    kind = draw(st.sampled_from(["any", "axis", "separatrix", "rest"]))
    if kind == "any":
        omega = draw(vectors(1.0))
    elif kind == "rest":
        omega = np.zeros(3)
    else:
        axis = int(np.argsort(moments)[1]) if kind == "separatrix" else draw(st.integers(0, 2))
        omega = draw(vectors(1e-6)) * draw(st.sampled_from([1.0, 1e-6]))
        omega[axis] = draw(st.sampled_from([1.0, -1.0]))
    omega = omega * scale
    rate = float(np.linalg.norm(omega)) or 1.0
    times = np.sort(
        np.array(draw(st.lists(st.floats(0.0, 600.0), min_size=1, max_size=8)))
    ) / rate
    return moments, omega, np.concatenate([[0.0], times])


@given(motions())
def test_the_exact_solution_keeps_the_invariants(motion):
    # T, |L| and L in space are constants of every torque-free motion. The closed form gives
    # each output time on its own (no error accumulates with steps): omega componentwise to a
    # few eps, the orientation to the rounding of its phases. Measured: 14 eps (T), 7 eps (|L|),
    # 10 eps (L in space) over 3000 random motions up to 100 turns; bound 64 eps, a value at t0
    # of zero (a body at rest) compared absolutely (relative_drift's convention) with zero.
    moments, omega, times = motion
    note(f"moments={moments.tolist()!r} omega={omega.tolist()!r} times={times.tolist()!r}")
    sol = ph.simulate(moments, omega, times, method="exact")
    drift = ph.invariants.relative_drift(sol)
    for name, values in drift.items():
        assert float(np.max(values)) <= 64 * EPS, (name, float(np.max(values)) / EPS)
    # And the splitting keeps |L| and L in space exactly, to the rounding of its rotations:
    # a few eps per step (64 steps here).
    split = ph.simulate(moments, omega, times[-1], method="splitting",
                        dt=max(times[-1], 1e-300) / 64)
    drift = ph.invariants.relative_drift(split)
    for name in ("angular_momentum_norm", "angular_momentum_space"):
        assert float(np.max(drift[name])) <= 64 * 16 * EPS, (name, drift[name].max() / EPS)


@pytest.mark.parametrize(
    ("mass_scale", "omega"),
    [
        # Found by test_angular_momentum_and_energy: an energy of 4e-313 (subnormal) was 290
        # units of the smallest subnormal off (omega_z^2 formed as a subnormal first).
        (1.0, (0.0, 0.0, 1.5697050156479287e-158)),
        (1.0, (3e-160, -2e-159, 1.1e-158)),
        (1.0, (1e-170, 0.0, 0.0)),
        # |omega|^2 overflows, the energy does not (it was reported as an overflow).
        (1e-12, (0.0, 2e154, -1e154)),
    ],
)
def test_kinetic_energy_near_the_ends_of_the_range(mass_scale, omega):
    # 0.5 w . I w in exact rationals from the materialised tensor (componentwise accurate to
    # an ulp): the energy within 4 eps of it plus one unit of the smallest subnormal.
    from fractions import Fraction

    masses = mass_scale * np.array([67.0, 67.0, 67.0, 67.0])
    positions = np.array([[1.0, 2.0, 3.0], [-2.0, 5.0, 1.0], [4.0, -1.0, 2.0], [0.5, 3.0, -6.0]])
    body = ph.Body.point_masses(masses, positions)
    inertia = [[Fraction(float(x)) for x in row] for row in np.asarray(body.inertia)]
    w = [Fraction(x) for x in omega]
    exact = sum(inertia[i][j] * w[i] * w[j] for i in range(3) for j in range(3)) / 2
    energy = body.kinetic_energy(omega)
    assert abs(Fraction(energy) - exact) <= 4 * Fraction(EPS) * exact + Fraction(SUBNORMAL), (
        energy, float(exact)
    )
