"""Mesh bodies (Body.mesh, Body.from_trimesh) against closed forms, exact rational integrals,
convergence on icospheres, far offsets, trimesh, and every kind of bad mesh.

Tolerances are norm-wise relative; the exact references are evaluated in rational arithmetic
(fractions.Fraction) from the float64 vertices themselves, so any difference is polhode's.
"""

from __future__ import annotations

from fractions import Fraction
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph

BOX_FACES = np.array(
    [
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ]
)


def box_mesh(size, center=(0.0, 0.0, 0.0)):
    """A box with full sides ``size`` as 12 outward triangles (vertex k: bits x, y, z)."""
    k = np.arange(8)
    signs = np.stack([(k >> b) & 1 for b in range(3)], axis=1) - 0.5
    return np.asarray(center) + signs * np.asarray(size), BOX_FACES.copy()


def octahedron(r):
    v = np.array([[r, 0, 0], [-r, 0, 0], [0, r, 0], [0, -r, 0], [0, 0, r], [0, 0, -r]], float)
    f = np.array(
        [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    )
    return v, f


def icosphere(levels, radius=1.0):
    """An icosahedron subdivided ``levels`` times, projected on the sphere."""
    t = (1 + 5**0.5) / 2
    v = [
        [-1, t, 0],
        [1, t, 0],
        [-1, -t, 0],
        [1, -t, 0],
        [0, -1, t],
        [0, 1, t],
        [0, -1, -t],
        [0, 1, -t],
        [t, 0, -1],
        [t, 0, 1],
        [-t, 0, -1],
        [-t, 0, 1],
    ]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ]
    for _ in range(levels):
        cache: dict[tuple[int, int], int] = {}

        def mid(a, b, cache=cache):
            key = (min(a, b), max(a, b))
            if key not in cache:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                cache[key] = len(verts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        faces = new
    return np.array(verts) * radius, np.array(faces)


def exact_mesh(vertices, faces, density=1):
    """(mass, centre, second moment about the centre) of a closed mesh, in exact rationals.

    Signed tetrahedra with the origin (exact arithmetic makes the origin irrelevant):
    int x x^T = det/120 (sum v v^T + s s^T).
    """
    v = [[Fraction(float(x)) for x in p] for p in vertices]
    vol = Fraction(0)
    first = [Fraction(0)] * 3
    second = [[Fraction(0)] * 3 for _ in range(3)]
    for i, j, k in faces:
        a, b, c = v[i], v[j], v[k]
        det = (
            a[0] * (b[1] * c[2] - b[2] * c[1])
            - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
        )
        s = [a[n] + b[n] + c[n] for n in range(3)]
        vol += det / 6
        for n in range(3):
            first[n] += det * s[n] / 24
            for m in range(3):
                q = a[n] * a[m] + b[n] * b[m] + c[n] * c[m] + s[n] * s[m]
                second[n][m] += det * q / 120
    rho = Fraction(density)
    com = [f / vol for f in first]
    centred = [[rho * (second[n][m] - vol * com[n] * com[m]) for m in range(3)] for n in range(3)]
    return float(rho * vol), np.array([float(c) for c in com]), np.array(centred, dtype=float)


def inertia_of(second):
    return np.trace(second) * np.eye(3) - second


def rel(a, b):
    return float(np.linalg.norm(np.asarray(a) - b) / np.linalg.norm(b))


# ---------------------------------------------------------------------------------------------
# Exact polyhedra
# ---------------------------------------------------------------------------------------------


def test_box_matches_the_closed_form():
    a, b, c = 0.3, 1.1, 2.5
    body = ph.Body.mesh(*box_mesh((a, b, c), (0.4, -1.3, 2.0)), density=2.7)
    m = 2.7 * a * b * c
    assert body.mass == pytest.approx(m, rel=1e-15)
    np.testing.assert_allclose(body.center_of_mass, [0.4, -1.3, 2.0], rtol=0, atol=1e-15)
    expected = np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * m / 12
    assert rel(body.inertia, expected) <= 1e-14


@pytest.mark.parametrize("seed", range(5))
def test_rotated_box_matches_exact_rational_integrals(seed):
    rotation = Rotation.random(random_state=seed).as_matrix()
    v, f = box_mesh((0.5, 1.0, 2.0))
    v = v @ rotation.T + np.array([0.3, -0.2, 0.9])
    mass, com, second = exact_mesh(v, f)
    body = ph.Body.mesh(v, f, density=1.0)
    assert body.mass == pytest.approx(mass, rel=1e-15)
    np.testing.assert_allclose(body.center_of_mass, com, rtol=0, atol=1e-15)
    assert rel(body.second_moment, second) <= 1e-14
    assert rel(body.inertia, inertia_of(second)) <= 1e-14
    # Products of inertia: I_xy = -sum m x y, and the tensor is R diag R^T.
    diag = np.diag([1.0**2 + 2.0**2, 0.5**2 + 2.0**2, 0.5**2 + 1.0**2]) * 1.0 / 12
    assert rel(body.inertia, rotation @ diag @ rotation.T) <= 1e-14


@pytest.mark.parametrize(
    ("unused", "offset"),
    [
        ((1e8, 0.0, 0.0), 0.0),
        ((1e20, 0.0, 0.0), 0.0),
        ((0.0, 0.0, 0.0), 1e15),
        ((3e5, -2e5, 1e7), 7.0),
    ],
)
def test_a_vertex_no_face_uses_changes_nothing(unused, offset):
    """Mesh files often carry vertices no face uses. They once set the reference point and the
    scale of the integrals: a unit cube with an unused vertex at 1e8 had its centre of mass
    off by 3e-3 and I_xx twice I_yy; at 1e20 it was "degenerate", at a 1e15 offset with an
    unused vertex at the origin "inside out". The exact rational integrals of the cube alone
    are the reference."""
    v, f = box_mesh((1.0, 1.0, 1.0), (offset, offset, offset))
    mass, com, second = exact_mesh(v, f)
    body = ph.Body.mesh(np.vstack([v, [unused]]), f, density=1.0)
    assert body.mass == pytest.approx(mass, rel=1e-15)
    np.testing.assert_allclose(body.center_of_mass, com, rtol=4e-16, atol=1e-15)
    assert rel(body.inertia, inertia_of(second)) <= 1e-14


def test_corner_tetrahedron_matches_the_closed_form():
    # Vertices 0, a e1, b e2, c e3: C_xx = 3/80 M a^2, C_xy = -M a b / 80.
    a, b, c = 1.5, 0.5, 2.0
    v = np.array([[0, 0, 0], [a, 0, 0], [0, b, 0], [0, 0, c]], float)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    body = ph.Body.mesh(v, f, mass=3.0)
    lengths = np.array([a, b, c])
    second = -3.0 * np.outer(lengths, lengths) / 80
    np.fill_diagonal(second, 9.0 * lengths**2 / 80)
    assert body.mass == 3.0
    np.testing.assert_allclose(body.center_of_mass, lengths / 4, rtol=1e-15)
    assert rel(body.second_moment, second) <= 1e-14
    assert rel(body.inertia, inertia_of(second)) <= 1e-14


def test_octahedron_matches_the_closed_form():
    r = 1.7
    body = ph.Body.mesh(*octahedron(r), density=1.0)
    m = 4 * r**3 / 3
    assert body.mass == pytest.approx(m, rel=1e-15)
    assert rel(body.inertia, np.eye(3) * m * r * r / 5) <= 1e-14


def test_hollow_box_sums_nested_shells_with_their_signs():
    vo, fo = box_mesh((2.0, 3.0, 4.0))
    vi, fi = box_mesh((1.0, 1.0, 1.0))
    v = np.vstack([vo, vi])
    f = np.vstack([fo, fi[:, ::-1] + 8])
    body = ph.Body.mesh(v, f, density=1.0)
    assert body.mass == pytest.approx(23.0, rel=1e-15)
    second = np.diag(24 * np.array([4.0, 9.0, 16.0]) / 12 - np.ones(3) / 12)
    assert rel(body.second_moment, second) <= 1e-14


# ---------------------------------------------------------------------------------------------
# Convergence and far offsets
# ---------------------------------------------------------------------------------------------


def test_icosphere_converges_at_second_order():
    r = 1.3
    errors = []
    for level in range(2, 6):
        body = ph.Body.mesh(*icosphere(level, r), mass=2.0)
        errors.append(abs(body.principal().moments[2] - 0.4 * 2.0 * r * r) / (0.8 * r * r))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.8) & (ratios < 4.2)), (errors, ratios)


def snapped_icosphere(levels):
    """Vertices on a 2^-24 grid, so that an integer shift up to 1e8 is exact."""
    v, f = icosphere(levels)
    return np.round(v * 2.0**24) / 2.0**24, f


@pytest.mark.parametrize("exponent", range(2, 9))
def test_far_offset_keeps_the_moments(exponent):
    v, f = snapped_icosphere(3)
    base = ph.Body.mesh(v, f, density=1.0)
    d = 10.0**exponent
    shift = np.array([d, -0.5 * d, 0.25 * d])
    moved = v + shift
    np.testing.assert_array_equal(moved - shift, v)  # the shift itself is exact
    body = ph.Body.mesh(moved, f, density=1.0)
    assert body.mass == pytest.approx(base.mass, rel=1e-13)
    assert rel(body.inertia, base.inertia) <= 1e-12
    assert np.linalg.norm(body.center_of_mass - shift - base.center_of_mass) <= 1e-15 * d


def bipyramid(n, h=0.7):
    """A closed bipyramid over an irregular n-gon: 2n outward triangles (2 mod 4 for odd n, so
    that the last row of four lanes is partial), vertices on a 2^-20 grid."""
    rng = np.random.default_rng(n)
    angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    radius = rng.uniform(0.8, 1.2, n)
    ring = np.stack([radius * np.cos(angles), radius * np.sin(angles), rng.uniform(-0.1, 0.1, n)])
    v = np.vstack([ring.T, [[0.0, 0.0, h], [0.0, 0.0, -h]]])
    v = np.round(v * 2.0**20) / 2.0**20
    i = np.arange(n)
    j = (i + 1) % n
    top, bottom = np.full(n, n), np.full(n, n + 1)
    return v, np.vstack([np.stack([i, j, top], 1), np.stack([j, i, bottom], 1)])


@pytest.mark.parametrize("offset", [0.0, 1e6])
@pytest.mark.parametrize("n", [3, 5, 2051])
def test_partial_lanes_and_chunks_match_exact_rational_integrals(n, offset):
    # 6 and 10 triangles: one block, its last row of lanes partial; 4102: a whole chunk of
    # 4096 and a tail of six. The offset (exact on the grid) moves the mesh far away.
    v, f = bipyramid(n)
    v = v + np.array([offset, -offset, 0.5 * offset])
    mass, com, second = exact_mesh(v, f)
    body = ph.Body.mesh(v, f, density=1.0)
    assert body.mass == pytest.approx(mass, rel=1e-14)
    np.testing.assert_allclose(body.center_of_mass, com, rtol=1e-15, atol=1e-15)
    assert rel(body.second_moment, second) <= (1e-14 if offset == 0 else 1e-12)


@pytest.mark.parametrize("n", [3, 2051])
def test_open_shell_with_an_odd_count_matches_a_numpy_reference(n):
    # A bipyramid without its last face: 2n - 1 triangles (an odd tail of lanes).
    v, f = bipyramid(n)
    f = f[:-1]
    a, b, c = (v[f[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    s = a + b + c
    total = area.sum()
    com = (area[:, None] * s).sum(0) / (3 * total)
    outer = sum(np.einsum("n,ni,nj->ij", area, x, x) for x in (a, b, c, s)) / 12
    second = outer / total - np.outer(com, com)
    body = ph.Body.mesh(v, f, mass=1.0, shell=True)
    np.testing.assert_allclose(body.center_of_mass, com, rtol=0, atol=1e-14)
    assert rel(body.second_moment, second) <= 1e-13


# ---------------------------------------------------------------------------------------------
# Thin shells
# ---------------------------------------------------------------------------------------------


def test_spherical_shell_converges_to_two_thirds():
    r = 0.7
    errors = []
    for level in range(2, 6):
        body = ph.Body.mesh(*icosphere(level, r), mass=2.0, shell=True)
        exact = ph.Body.spherical_shell(2.0, r).inertia[0, 0]
        errors.append(abs(body.principal().moments[2] - exact) / exact)
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.8) & (ratios < 4.2)), (errors, ratios)


def test_box_shell_matches_the_closed_form():
    s = np.array([0.5, 1.2, 2.0])
    body = ph.Body.mesh(*box_mesh(s, (1.0, 2.0, 3.0)), mass=3.0, shell=True)
    sigma = 3.0 / (2 * (s[0] * s[1] + s[1] * s[2] + s[2] * s[0]))

    def c(a, b, cc):
        return sigma * (a**3 * (b + cc) / 6 + a * a * b * cc / 2)

    second = np.diag([c(*s), c(s[1], s[2], s[0]), c(s[2], s[0], s[1])])
    assert rel(body.second_moment, second) <= 1e-14
    np.testing.assert_allclose(body.center_of_mass, [1.0, 2.0, 3.0], rtol=1e-15)


def test_shell_needs_no_closed_mesh():
    v, f = box_mesh((1.0, 1.0, 1.0))
    open_box = ph.Body.mesh(v, f[2:], density=1.0, shell=True)  # no bottom
    assert open_box.mass == pytest.approx(5.0, rel=1e-15)


# ---------------------------------------------------------------------------------------------
# trimesh
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["icosphere", "box", "capsule", "torus"])
def test_agrees_with_trimesh(kind):
    trimesh = pytest.importorskip("trimesh")
    mesh = {
        "icosphere": lambda: trimesh.creation.icosphere(subdivisions=3, radius=1.3),
        "box": lambda: trimesh.creation.box(extents=(0.3, 1.1, 2.5)),
        "capsule": lambda: trimesh.creation.capsule(height=1.0, radius=0.4),
        "torus": lambda: trimesh.creation.torus(major_radius=1.0, minor_radius=0.3),
    }[kind]()
    rotation = np.eye(4)
    rotation[:3, :3] = Rotation.random(random_state=1).as_matrix()
    mesh.apply_transform(rotation)
    mesh.apply_translation([0.1, -0.2, 0.3])
    assert mesh.is_watertight and mesh.is_winding_consistent
    props = trimesh.triangles.mass_properties(mesh.triangles, density=2.0)
    body = ph.Body.from_trimesh(mesh, density=2.0)
    assert body.mass == pytest.approx(props.mass, rel=1e-12)
    np.testing.assert_allclose(body.center_of_mass, props.center_mass, rtol=0, atol=1e-12)
    assert rel(body.inertia, props.inertia) <= 1e-12


def test_from_trimesh_is_duck_typed():
    v, f = octahedron(1.0)
    body = ph.Body.from_trimesh(SimpleNamespace(vertices=v, faces=f), mass=1.0)
    assert rel(body.inertia, np.eye(3) / 5) <= 1e-14
    with pytest.raises(TypeError, match="mesh"):
        ph.Body.from_trimesh(object(), mass=1.0)


# ---------------------------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------------------------


def flipped_face():
    v, f = box_mesh((1.0, 2.0, 3.0))
    f[3] = f[3][::-1]
    return v, f


def inside_out():
    v, f = box_mesh((1.0, 2.0, 3.0))
    return v, f[:, ::-1]


def out_of_range():
    v, f = box_mesh((1.0, 2.0, 3.0))
    f[5, 1] = 8
    return v, f


def negative_index():
    v, f = box_mesh((1.0, 2.0, 3.0))
    f[5, 1] = -1
    return v, f


def nan_vertex():
    v, f = box_mesh((1.0, 2.0, 3.0))
    v[2, 1] = np.nan
    return v, f


def open_mesh():
    v, f = box_mesh((1.0, 2.0, 3.0))
    return v, f[:-1]


def flat_mesh():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    return v, np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (open_mesh, r"`faces`.*not closed"),
        (flipped_face, r"`faces`.*inconsistent"),
        (inside_out, r"`faces`.*inside out.*faces\[:, ::-1\].*fix_winding"),
        (out_of_range, r"`faces\[5, 1\]`.*out of range"),
        (negative_index, r"`faces\[5, 1\]`.*out of range"),
        (nan_vertex, r"`vertices\[2, 1\]`.*finite"),
        (flat_mesh, r"`vertices`.*degenerate"),
        (lambda: (box_mesh((1, 1, 1))[0], BOX_FACES[:3]), r"`faces`.*at least 4"),
    ],
)
def test_bad_meshes_raise_naming_the_argument(make, match):
    v, f = make()
    with pytest.raises(ph.PolhodeError, match=match):
        ph.Body.mesh(v, f, density=1.0)


def test_the_first_bad_row_is_named_across_parallel_chunks():
    # 20480 faces and 10242 vertices: five chunks of 4096 each, scanned in parallel.
    v, f = icosphere(5)
    bad = f.copy()
    bad[15000, 0] = -1
    bad[9000, 1] = len(v)
    with pytest.raises(ph.PolhodeError, match=r"`faces\[9000, 1\]`.*out of range"):
        ph.Body.mesh(v, bad, density=1.0)
    bad = f.copy()
    bad[13000] = [7, 7, 8]
    bad[12000] = [5, 6, 5]
    with pytest.raises(ph.PolhodeError, match=r"`faces\[12000\]`.*repeats a vertex"):
        ph.Body.mesh(v, bad, density=1.0)
    nan = v.copy()
    nan[9000, 0] = np.inf
    nan[5000, 2] = np.nan
    with pytest.raises(ph.PolhodeError, match=r"`vertices\[5000, 2\]`.*finite"):
        ph.Body.mesh(nan, f, density=1.0)


def test_fix_winding_reverses_an_inside_out_mesh():
    v, f = inside_out()
    fixed = ph.Body.mesh(v, f, density=1.0, fix_winding=True)
    right = ph.Body.mesh(v, f[:, ::-1], density=1.0)
    np.testing.assert_array_equal(fixed.inertia, right.inertia)
    assert fixed.mass == right.mass == 6.0


def test_density_and_mass_exactly_one():
    v, f = box_mesh((1.0, 2.0, 3.0))
    with pytest.raises(ph.PolhodeError, match="exactly one.*both"):
        ph.Body.mesh(v, f, density=1.0, mass=1.0)
    with pytest.raises(ph.PolhodeError, match="exactly one.*neither"):
        ph.Body.mesh(v, f)
    with pytest.raises(ph.PolhodeError, match="`density`.*positive"):
        ph.Body.mesh(v, f, density=-1.0)
    with pytest.raises(ph.PolhodeError, match="`mass`.*positive"):
        ph.Body.mesh(v, f, mass=0.0)


def test_shapes_and_types_are_checked():
    v, f = box_mesh((1.0, 2.0, 3.0))
    with pytest.raises(ph.PolhodeError, match=r"`vertices`.*\(N, 3\)"):
        ph.Body.mesh(v[:, :2], f, density=1.0)
    with pytest.raises(ph.PolhodeError, match=r"`faces`.*\(M, 3\)"):
        ph.Body.mesh(v, f.ravel(), density=1.0)
    with pytest.raises(TypeError, match="`faces`.*integers"):
        ph.Body.mesh(v, f.astype(float), density=1.0)
    with pytest.raises(TypeError, match="`shell`"):
        ph.Body.mesh(v, f, density=1.0, shell="yes")
    # Any integer dtype and non-contiguous views are accepted.
    a = ph.Body.mesh(v, f.astype(np.int32)[:, [0, 1, 2]], density=1.0)
    b = ph.Body.mesh(np.asfortranarray(v), f.astype(np.uint16), density=1.0)
    np.testing.assert_array_equal(a.inertia, b.inertia)


# ---------------------------------------------------------------------------------------------
# Inertia in engine formats (MuJoCo fullinertia / MJCF, URDF/SDF <inertia>)
# ---------------------------------------------------------------------------------------------


def asymmetric_mesh_body():
    """A rotated, shifted box mesh: every product of inertia non-zero, three distinct moments."""
    v, f = box_mesh((0.5, 1.0, 2.0))
    rotation = Rotation.from_euler("xyz", [0.3, -0.7, 1.9]).as_matrix()
    return ph.Body.mesh(v @ rotation.T + [0.3, -0.2, 0.9], f, mass=1.7)


def test_six_number_orders_and_signs():
    tensor = np.array([[2.0, -0.1, -0.2], [-0.1, 3.0, -0.3], [-0.2, -0.3, 4.0]])
    body = ph.Body.from_inertia(1.0, tensor)
    # The body keeps a factored form: the elements come back to a few eps of ||I||.
    np.testing.assert_allclose(
        body.to_fullinertia(), [2, 3, 4, -0.1, -0.2, -0.3], rtol=0, atol=1e-14
    )
    urdf = body.to_urdf_inertia()
    assert list(urdf) == ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]
    np.testing.assert_allclose(list(urdf.values()), [2, -0.1, -0.2, 3, -0.3, 4], rtol=0, atol=1e-14)
    # Products are tensor elements: two unit masses at +-(1, 1, 0) give I_xy = -sum m x y = -2.
    pair = ph.Body.point_masses([1.0, 1.0], [[1.0, 1.0, 0.0], [-1.0, -1.0, 0.0]])
    assert pair.to_fullinertia()[3] == pytest.approx(-2.0, rel=1e-15)
    assert pair.to_urdf_inertia()["ixy"] == pytest.approx(-2.0, rel=1e-15)


def test_six_number_forms_round_trip():
    body = asymmetric_mesh_body()
    com = body.center_of_mass
    back = ph.Body.from_fullinertia(body.mass, body.to_fullinertia(), com)
    assert rel(back.inertia, body.inertia) <= 1e-15
    back = ph.Body.from_urdf_inertia(body.mass, **body.to_urdf_inertia(), center_of_mass=com)
    assert rel(back.inertia, body.inertia) <= 1e-15
    np.testing.assert_array_equal(back.center_of_mass, com)
    with pytest.raises(ph.PolhodeError, match=r"`fullinertia`.*\(6,\)"):
        ph.Body.from_fullinertia(1.0, [1.0, 1.0, 1.0])


def test_urdf_inertial_snippet_rebuilds_the_tensor():
    import xml.etree.ElementTree as ET

    body = asymmetric_mesh_body()
    element = ET.fromstring(body.to_urdf_inertial())
    origin = element.find("origin")
    inertia = element.find("inertia")
    mass = element.find("mass")
    assert origin is not None and inertia is not None and mass is not None
    np.testing.assert_allclose(
        [float(x) for x in origin.get("xyz", "").split()], body.center_of_mass
    )
    rpy = [float(x) for x in origin.get("rpy", "").split()]
    # URDF: fixed-axis roll, pitch, yaw, R = Rz(yaw) Ry(pitch) Rx(roll).
    r = Rotation.from_euler("xyz", rpy).as_matrix()
    values = {k: float(inertia.get(k, "nan")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    diag = np.array(
        [
            [values["ixx"], values["ixy"], values["ixz"]],
            [values["ixy"], values["iyy"], values["iyz"]],
            [values["ixz"], values["iyz"], values["izz"]],
        ]
    )
    assert rel(r @ diag @ r.T, body.inertia) <= 1e-14
    assert float(mass.get("value", "nan")) == body.mass


def mujoco_body(inertial: str):
    mujoco = pytest.importorskip("mujoco")
    xml = (
        '<mujoco><option gravity="0 0 0"/><worldbody><body name="b"><freejoint/>'
        f"{inertial}</body></worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(xml)
    w, x, y, z = model.body_iquat[1]
    r = Rotation.from_quat([x, y, z, w]).as_matrix()
    tensor = r @ np.diag(model.body_inertia[1]) @ r.T
    return float(model.body_mass[1]), np.array(model.body_ipos[1]), tensor


def test_mjcf_snippet_loads_into_mujoco():
    body = asymmetric_mesh_body()
    mass, com, tensor = mujoco_body(body.to_mjcf())
    assert mass == body.mass
    np.testing.assert_allclose(com, body.center_of_mass, rtol=0, atol=1e-15)
    assert rel(tensor, body.inertia) <= 1e-12


def test_fullinertia_loads_into_mujoco():
    body = asymmetric_mesh_body()
    full = " ".join(repr(float(v)) for v in body.to_fullinertia())
    pos = " ".join(repr(float(v)) for v in body.center_of_mass)
    mass, com, tensor = mujoco_body(
        f'<inertial pos="{pos}" mass="{body.mass!r}" fullinertia="{full}"/>'
    )
    assert mass == body.mass
    np.testing.assert_allclose(com, body.center_of_mass, rtol=0, atol=1e-15)
    assert rel(tensor, body.inertia) <= 1e-12
