"""The materialised inertia tensor is accurate component by component, not only normwise.

A user reads components: ``body.inertia[2, 2]`` of a needle along z, ``to_urdf_inertia()["izz"]``,
the spatial inertia's angular block about a point on the axis, the energy of a spin about that
axis. Each of these is compared here with its exact value in rational arithmetic (``Fraction``
of the doubles given, so the reference is the body as specified, not as rounded by polhode).

The bound (docs/architecture.md, Numerics): with the second moment kept as ``C = c 1 + F^T F``,
``I_ii = 2 c + sum_{j != i} |F e_j|^2`` is a sum of non-negative terms, so each diagonal entry is
within a few eps of itself (``DIAGONAL`` below: the construction's roundings of ``c`` and ``F``
plus the sum's), however small against the trace; an off-diagonal entry is within
``3 eps sqrt(C_ii C_jj)`` and exactly 0 for a body in its own principal axes. The parallel-axis
term adds ``m (d_j^2 + d_k^2)`` to ``I_ii``, again terms of one sign.

Before this, ``Body.cylinder(1, 1e-8, 1).inertia[2, 2]`` was 5.55e-17 for an exact 5e-17 (11 %:
``tr(C) - C_zz`` cancelled), and an offset along the needle's axis added ``|d|^2 - d_z^2``, the
rounding of ``d_z^2``.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import polhode as ph
import reference as ref
from reference import EPS

#: Relative error allowed on a diagonal entry (and on the energy), from its exact value: the
#: solid's closed form (a few roundings), its square-root form and the materialisation (a sum
#: of at most 7 non-negative terms), each a few eps.
DIAGONAL = 16 * EPS

F = Fraction


def exact(x: float) -> Fraction:
    return Fraction(float(x))


def assert_relative(value: float, expected: Fraction, bound: float = DIAGONAL, what: str = ""):
    if expected == 0:
        assert value == 0.0, f"{what}: {value!r}, exactly 0 expected"
        return
    error = abs(Fraction(float(value)) - expected) / abs(expected)
    assert error <= bound, f"{what}: {value!r} for {float(expected)!r} ({float(error):.3g} rel)"


def cylinder_exact(m: float, r: float, length: float) -> list[Fraction]:
    m, r, length = exact(m), exact(r), exact(length)
    transverse = m * (3 * r * r + length * length) / 12
    return [transverse, transverse, m * r * r / 2]


NEEDLES = [
    (1.0, 1e-8, 1.0),
    (1.0, 2.0**-27, 1.0),
    (3.7, 1e-12, 0.3),
    (0.25, 1e-100, 7.0),
    (2.0, 3e-5, 1e3),
]


@pytest.mark.parametrize("m, r, length", NEEDLES)
def test_needle_keeps_its_axial_moment(m, r, length):
    body = ph.Body.cylinder(m, r, length)
    expected = cylinder_exact(m, r, length)
    inertia = body.inertia
    for i in range(3):
        assert_relative(inertia[i, i], expected[i], what=f"inertia[{i}, {i}]")
    assert inertia[0, 1] == inertia[0, 2] == inertia[1, 2] == 0.0
    urdf = body.to_urdf_inertia()
    assert_relative(urdf["izz"], expected[2], what="izz")
    assert urdf["ixy"] == urdf["ixz"] == urdf["iyz"] == 0.0
    assert_relative(body.to_fullinertia()[2], expected[2], what="fullinertia zz")
    # A spin about the axis: T = I_zz w^2 / 2.
    assert_relative(body.kinetic_energy([0.0, 0.0, 3.0]), expected[2] * 9 / 2, what="energy")
    assert_relative(body.angular_momentum_body([0.0, 0.0, 3.0])[2], expected[2] * 3, what="L_z")


@pytest.mark.parametrize("m, r, length", NEEDLES[:3])
def test_needle_about_points_on_its_axis(m, r, length):
    # Far along the axis (d = (0, 0, h)): I_zz about the point is still m r^2 / 2, not the
    # rounding of h^2; off the axis by s in x: I_zz + m s^2.
    body = ph.Body.cylinder(m, r, length).translated([0.0, 0.0, 1e8])
    expected = cylinder_exact(m, r, length)
    for point in ([0.0, 0.0, 0.0], [0.0, 0.0, 2e8], [0.0, 0.0, 1e8 + 5.0]):
        about = body.inertia_about(point)
        assert_relative(about[2, 2], expected[2], what=f"about {point}")
        assert about[0, 2] == about[1, 2] == 0.0
        s = body.spatial_inertia(point)
        assert_relative(s[2, 2], expected[2], what=f"spatial about {point}")
    s_off = 1e-6
    about = body.inertia_about([s_off, 0.0, 0.0])
    assert_relative(about[2, 2], expected[2] + exact(m) * exact(s_off) ** 2, what="off axis")


def test_needle_in_other_axes():
    # The needle along z seen in axes that put z first (an exact permutation rotation): the
    # small moment moves to [0, 0], accurately, with and without a point.
    m, r, length = 1.0, 1e-8, 1.0
    body = ph.Body.cylinder(m, r, length).translated([0.0, 0.0, 3.0])
    expected = cylinder_exact(m, r, length)
    axes = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])  # columns: z, x, y
    for point in ([0.0, 0.0, 0.0], [0.0, 0.0, 3.0]):
        seen = body.inertia_about(point, axes=axes)
        assert_relative(seen[0, 0], expected[2], what=f"in permuted axes about {point}")
        assert seen[0, 1] == seen[0, 2] == 0.0
    rotated = ph.Body.cylinder(m, r, length).rotated(axes.T)  # the axis now along x
    assert_relative(rotated.inertia[0, 0], expected[2], what="rotated needle")


def test_a_plate_and_a_thin_box():
    # A cuboid 1 x 1e-9 x 1e-9 (a square needle along x) and a plate 1 x 1 x 1e-9.
    m = 2.5
    for size in ([1.0, 1e-9, 1e-9], [1.0, 1.0, 1e-9], [1e-7, 3.0, 2e-7]):
        a, b, c = (exact(x) for x in size)
        expected = [exact(m) * (b * b + c * c) / 12, exact(m) * (a * a + c * c) / 12]
        expected.append(exact(m) * (a * a + b * b) / 12)
        inertia = ph.Body.cuboid(m, size).inertia
        for i in range(3):
            assert_relative(inertia[i, i], expected[i], what=f"cuboid {size} [{i}, {i}]")


def test_point_masses_just_off_the_axis():
    # Four unit masses 1e-8 off the z axis, symmetric so that the centre is the origin: the
    # exact I_zz = 4e-16 (as doubles: 4 * Fraction(1e-8)^2), which came out as 0 or garbage.
    e = 1e-8
    positions = [[e, 0.0, 1.0], [-e, 0.0, -1.0], [0.0, e, -1.0], [0.0, -e, 1.0]]
    body = ph.Body.point_masses([1.0] * 4, positions)
    izz = 4 * exact(e) ** 2
    assert_relative(body.inertia[2, 2], izz, what="point masses I_zz")
    # The products: I_xz = -sum x z = -(e + e) = -2e, I_yz = -sum y z = -(-e - e) = 2e.
    assert_relative(body.inertia[0, 2], -2 * exact(e), bound=4 * EPS, what="I_xz")
    assert_relative(body.inertia[1, 2], 2 * exact(e), bound=4 * EPS, what="I_yz")
    # Far from the origin (1e3 to 3e3 away, where 2^-20 off the axis is still held exactly by
    # the doubles given): the centre moves, the tensor does not. The reference is the exact
    # rational sum over the positions as given.
    e = 2.0**-20
    positions = [[e, 0.0, 1.0], [-e, 0.0, -1.0], [0.0, e, -1.0], [0.0, -e, 1.0]]
    shifted = np.array(positions) + [1024.0, -3072.0, 512.0]
    assert (shifted - [1024.0, -3072.0, 512.0] == positions).all()  # nothing lost in the input
    far = ph.Body.point_masses([1.0] * 4, shifted)
    reference = ref.point_mass_properties_exact([1.0] * 4, shifted)
    for i in range(3):
        assert_relative(far.inertia[i, i], exact(reference.inertia[i, i]), what=f"far [{i}, {i}]")
    assert_relative(far.inertia[2, 2], 4 * exact(e) ** 2, what="far cloud I_zz")


def test_simulate_of_a_needles_tensor_has_the_exact_energy():
    # simulate(body.inertia, ...) reads the materialised tensor: a spin about the needle's axis
    # has T = I_zz w^2 / 2 to a few ulp, the same as simulate(body, ...).
    body = ph.Body.cylinder(1.0, 1e-8, 1.0)
    expected = cylinder_exact(1.0, 1e-8, 1.0)[2] * 4 / 2
    for given in (body, body.inertia):
        sol = ph.simulate(given, [0.0, 0.0, 2.0], [0.0, 1.0])
        assert_relative(sol.energy[0], expected, what=f"energy of {type(given).__name__}")
