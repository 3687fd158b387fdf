"""Meshes as real exporters write them: repeated vertices (triangle soups), a 0 written as 3e-17
in the next facet, and real gaps; what the "not closed" error says; a trimesh mesh's own density.

References: the closed form of a box (m = rho a b c, I = m/12 diag(b^2 + c^2, ...)); the
tolerance 2^-40 x the bounding-box diagonal computed here with math.hypot and math.ldexp;
trimesh's own mass properties for Body.from_trimesh. The files are written by the tests.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import polhode as ph
from polhode.errors import FileFormatError, NonPositiveError, PolhodeError

trimesh = pytest.importorskip("trimesh")

EPS = np.finfo(float).eps

CUBE_V = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
CUBE_F = np.array(
    [
        [0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
        [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7],
    ]
)  # fmt: skip


def soup(vertices, faces):
    """Every triangle with its own three corners, as STL writes them."""
    return vertices[faces].reshape(-1, 3).copy(), np.arange(3 * len(faces)).reshape(-1, 3)


def assert_cube(body, side, density=1.0, rtol=64 * EPS):
    m = density * side**3
    assert abs(body.mass - m) <= rtol * m
    assert np.allclose(body.center_of_mass, [side / 2] * 3, rtol=rtol, atol=0)
    scale = m * side**2
    assert np.allclose(body.inertia, scale / 6 * np.eye(3), rtol=rtol, atol=rtol * scale)


def tolerance_of(side):
    """2^-40 of the cube's bounding-box diagonal, computed apart from polhode."""
    return math.ldexp(math.hypot(side, side, side), -40)


def nudged_soup(side, delta):
    """The soup of the cube [0, side]^3 with one corner of one triangle moved by delta in x.
    Triangle 2 is (4, 5, 6): its first corner is vertex 4 = (0, 0, side)."""
    v, f = soup(CUBE_V * side, CUBE_F)
    v[6, 0] += delta
    return v, f


def test_a_triangle_soup_is_the_closed_cube():
    v, f = soup(CUBE_V, CUBE_F)
    v[v == 0.0] = -0.0  # signed zeros are the same position
    assert_cube(ph.Body.mesh(v, f, density=2.0), 1.0, 2.0)


@pytest.mark.parametrize("side", [0.03, 1.0, 400.0])
def test_the_tolerance_both_ways(side):
    tolerance = tolerance_of(side)
    for delta in (0.99 * tolerance, -0.99 * tolerance):
        # The integrals use the corner where it is: moving one corner by delta changes the
        # volume by at most |delta| times the area of its triangles (<= side^2), and the
        # moments alike, so the cube's values hold to |delta| / side more.
        rtol = 64 * EPS + 4 * abs(delta) / side
        assert_cube(ph.Body.mesh(*nudged_soup(side, delta), density=1.0), side, rtol=rtol)
    with pytest.raises(PolhodeError, match="not closed.*cracks") as caught:
        ph.Body.mesh(*nudged_soup(side, 1.01 * tolerance), density=1.0)
    assert caught.value.argument == "faces"
    assert "use shell=True" not in str(caught.value)


def test_the_issues_examples_1e17_on_3_cm_merges_a_1e3_gap_does_not():
    assert_cube(ph.Body.mesh(*nudged_soup(0.03, 1e-17), density=1.0), 0.03, rtol=64 * EPS)
    with pytest.raises(PolhodeError, match="not closed"):
        ph.Body.mesh(*nudged_soup(0.03, 1e-3), density=1.0)


def write_stl_ascii(path, triangles):
    lines = ["solid part"]
    for t in triangles:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {' '.join(repr(float(x)) for x in corner)}" for corner in t]
        lines += ["endloop", "endfacet"]
    path.write_text("\n".join(lines + ["endsolid part"]) + "\n")


def test_a_file_that_writes_0_as_3e17_in_the_next_facet(tmp_path):
    # A 30 mm cube in metres whose corner (0, 0, 0.03) is written as (3e-17, -2e-17, 0.03)
    # in every other facet that uses it, as CAD exporters do.
    side = 0.03
    triangles = (CUBE_V * side)[CUBE_F].copy()
    uses = 0
    for t in triangles:
        for corner in t:
            if np.array_equal(corner, [0.0, 0.0, side]):
                uses += 1
                if uses % 2 == 0:
                    corner[:2] = [3e-17, -2e-17]
    assert uses >= 4
    path = tmp_path / "noisy.stl"
    write_stl_ascii(path, triangles)
    (part,) = ph.io.read_mesh(path, density=1000.0).values()
    assert_cube(part, side, 1000.0)
    assert_cube(ph.Body.from_file(path, density=1000.0), side, 1000.0)
    # The same corner 1 mm off: a real gap, refused.
    triangles[triangles == 3e-17] = 1e-3
    write_stl_ascii(path, triangles)
    with pytest.raises(FileFormatError, match="not closed") as caught:
        ph.io.read_mesh(path, density=1000.0)
    assert caught.value.field == "faces" and "noisy.stl" in str(caught.value)


def test_an_open_box_says_where_and_how_big_and_suggests_shell():
    # Without its top (z = 1, faces 2 and 3): one square opening of length 4, 0.5 wide.
    with pytest.raises(PolhodeError) as caught:
        ph.Body.mesh(CUBE_V, np.delete(CUBE_F, [2, 3], axis=0), density=1.0)
    text = str(caught.value)
    assert "4 edges" in text and "1 opening of total length 4 " in text, text
    assert "is 0.5 wide" in text and "at (0, 0, 1)" in text, text
    assert "use shell=True" in text, text
    # As a shell it is five faces of the unit cube.
    body = ph.Body.mesh(CUBE_V, np.delete(CUBE_F, [2, 3], axis=0), density=1.0, shell=True)
    assert body.mass == pytest.approx(5.0, rel=1e-15)


def test_a_crack_is_named_a_crack():
    # Face x = 0 split at the midpoint of its edge (0, 0, 0)-(0, 0, 1), the neighbouring face
    # y = 0 not: a T-junction, closed to the eye, not connected.
    v = np.vstack([CUBE_V, [[0.0, 0.0, 0.5]]])
    f = np.vstack([CUBE_F[CUBE_F[:, 0] != 3], [[3, 0, 8], [3, 8, 4], [3, 4, 7]]])
    assert len(f) == 13
    with pytest.raises(PolhodeError, match="not closed.*cracks") as caught:
        ph.Body.mesh(v, f, density=1.0)
    assert "is 0 wide" in str(caught.value)
    assert "use shell=True" not in str(caught.value)


def test_from_trimesh_takes_the_meshes_own_density():
    box = trimesh.creation.box(extents=[0.2, 0.1, 0.05])
    box.density = 2700.0
    body = ph.Body.from_trimesh(box)
    reference = box.mass_properties  # trimesh's own integrals, at its density
    assert body.mass == pytest.approx(reference.mass, rel=1e-14)
    np.testing.assert_allclose(body.center_of_mass, reference.center_mass, atol=1e-16)
    np.testing.assert_allclose(body.inertia, reference.inertia, rtol=1e-13, atol=1e-18)
    # Unset, trimesh's default (1.0), as trimesh's own mass properties.
    sphere = trimesh.creation.icosphere(subdivisions=2)
    assert ph.Body.from_trimesh(sphere).mass == pytest.approx(sphere.mass, rel=1e-14)
    # An argument wins over the mesh's own.
    assert ph.Body.from_trimesh(box, density=1.0).mass == pytest.approx(1e-3, rel=1e-14)
    assert ph.Body.from_trimesh(box, mass=5.0).mass == 5.0


def test_from_trimesh_without_a_usable_density():
    box = trimesh.creation.box()
    box.density = 0.0
    with pytest.raises(NonPositiveError, match=r"mesh\.density") as caught:
        ph.Body.from_trimesh(box)
    assert caught.value.argument == "density"

    class Plain:  # vertices and faces, no density
        vertices, faces = CUBE_V, CUBE_F

    with pytest.raises(PolhodeError, match="neither") as caught:
        ph.Body.from_trimesh(Plain())
    assert caught.value.argument == "density"
    # A shell's density is per area: trimesh's (per volume) is not taken.
    with pytest.raises(PolhodeError, match="neither"):
        ph.Body.from_trimesh(trimesh.creation.box(), shell=True)
