"""Mesh files: Body.from_file and polhode.io.read_mesh.

References: the closed forms of a box (mass rho a b c, I = m/12 diag(b^2+c^2, ...), turned by a
rotation R as R I R^T) and of a thin-walled cube (I = 5 m a^2 / 18); trimesh's own mass
properties of real STL files no one here wrote (upkie_description's meshes). The ascii files
(STL, OBJ, PLY, OFF) and the binary STL are written by the tests themselves, byte by byte;
glTF/GLB by trimesh's exporter (polhode reads them through trimesh's loaders).
"""

from __future__ import annotations

import os
import pickle
import struct
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.errors import ArgumentError, FileFormatError, NonPositiveError, ShapeError

trimesh = pytest.importorskip("trimesh")

EPS = np.finfo(float).eps

# A unit cube [0, 1]^3: 8 vertices, 12 triangles wound counter-clockwise seen from outside.
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


def box_vertices(size, rotation=None, offset=(0.0, 0.0, 0.0)):
    """The cube's vertices stretched to ``size``, centred, turned and moved."""
    v = (CUBE_V - 0.5) * np.asarray(size, dtype=float)
    if rotation is not None:
        v = v @ np.asarray(rotation).T
    return v + np.asarray(offset, dtype=float)


def box_reference(size, density, rotation=None, offset=(0.0, 0.0, 0.0)):
    """Mass, centre of mass and inertia tensor of a solid box, from the textbook formula."""
    a, b, c = size
    m = density * a * b * c
    inertia = m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    if rotation is not None:
        r = np.asarray(rotation)
        inertia = r @ inertia @ r.T
    return m, np.asarray(offset, dtype=float), inertia


def assert_body(body, mass, com, inertia, rtol=64 * EPS):
    scale = max(np.linalg.norm(inertia), 1e-300)
    assert abs(body.mass - mass) <= rtol * mass
    size = np.sqrt(np.trace(inertia) / mass)
    assert np.linalg.norm(body.center_of_mass - com) <= rtol * (size + np.linalg.norm(com))
    assert np.linalg.norm(body.inertia - inertia) <= rtol * scale


# --- writers, independent of trimesh ---------------------------------------------------------


def write_stl_ascii(path, vertices, faces, name="part"):
    lines = [f"solid {name}"]
    for f in faces:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {' '.join(repr(float(x)) for x in vertices[i])}" for i in f]
        lines += ["endloop", "endfacet"]
    lines.append(f"endsolid {name}")
    with open(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


def write_stl_binary(path, vertices, faces):
    with open(path, "wb") as handle:
        handle.write(b"binary stl written by test_io_mesh".ljust(80, b" "))
        handle.write(struct.pack("<I", len(faces)))
        for f in faces:
            handle.write(struct.pack("<3f", 0, 0, 0))
            for i in f:
                handle.write(struct.pack("<3f", *vertices[i]))
            handle.write(b"\0\0")


def write_gltf(path, scene):
    """A trimesh scene as .glb or .gltf (with its buffers beside it), by trimesh's exporter."""
    if str(path).endswith(".glb"):
        path.write_bytes(trimesh.exchange.gltf.export_glb(scene))
        return
    for name, data in trimesh.exchange.gltf.export_gltf(scene).items():
        (path.parent / (path.name if name == "model.gltf" else name)).write_bytes(data)


def write_obj(path, objects):
    """objects: list of (name, vertices, faces); one 'o' block each, indices from 1."""
    lines, base = [], 1
    for name, v, f in objects:
        lines.append(f"o {name}")
        lines += [f"v {' '.join(repr(float(x)) for x in row)}" for row in v]
        lines += [f"f {' '.join(str(i + base) for i in row)}" for row in f]
        base += len(v)
    with open(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


def write_off(path, vertices, faces):
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [" ".join(repr(float(x)) for x in row) for row in vertices]
    lines += ["3 " + " ".join(str(i) for i in row) for row in faces]
    with open(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


def write_ply(path, vertices, faces):
    lines = [
        "ply",
        "format ascii 1.0",
        f"element vertex {len(vertices)}",
        "property double x",
        "property double y",
        "property double z",
        f"element face {len(faces)}",
        "property list uchar int vertex_indices",
        "end_header",
    ]
    lines += [" ".join(repr(float(x)) for x in row) for row in vertices]
    lines += ["3 " + " ".join(str(i) for i in row) for row in faces]
    with open(path, "w") as handle:
        handle.write("\n".join(lines) + "\n")


# --- every format against the closed form ---------------------------------------------------

TURN = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
SIZE = (0.3, 0.2, 0.1)
OFFSET = (0.5, -0.25, 2.0)


@pytest.mark.parametrize("fmt", ["stl", "stl_ascii", "obj", "off", "ply", "glb", "gltf"])
def test_every_format_gives_the_closed_form_box(tmp_path, fmt):
    # Binary STL and glTF store float32: there the box is axis-aligned with dyadic sizes and
    # offset (exact in float32); the text formats carry a turned box to full precision.
    binary = fmt in ("stl", "glb", "gltf")
    size, turn = ((0.375, 0.25, 0.125), None) if binary else (SIZE, TURN)
    v = box_vertices(size, turn, OFFSET)
    if binary:
        assert np.array_equal(v.astype(np.float32), v)
    name = {"stl_ascii": "box.stl"}.get(fmt, f"box.{fmt}")
    path = tmp_path / name
    if fmt == "stl":
        write_stl_binary(path, v, CUBE_F)
    elif fmt == "stl_ascii":
        write_stl_ascii(path, v, CUBE_F)
    elif fmt == "obj":
        write_obj(path, [("box", v, CUBE_F)])
    elif fmt == "off":
        write_off(path, v, CUBE_F)
    elif fmt == "ply":
        write_ply(path, v, CUBE_F)
    else:
        write_gltf(path, trimesh.Scene(trimesh.Trimesh(v, CUBE_F, process=False)))
    body = ph.Body.from_file(path, density=2700.0)
    m, com, inertia = box_reference(size, 2700.0, turn, OFFSET)
    assert_body(body, m, com, inertia)


def test_stl_triangle_soup_is_merged_into_a_closed_mesh(tmp_path):
    # Binary STL repeats every vertex in every triangle (36 vertices for a cube): without
    # merging the mesh is 12 loose triangles and could not be a closed solid.
    path = tmp_path / "cube.stl"
    write_stl_binary(path, CUBE_V, CUBE_F)
    (part,) = ph.io.read_mesh(path, mass=1.0).values()
    assert_body(part, 1.0, [0.5, 0.5, 0.5], np.eye(3) / 6)


def test_mass_instead_of_density(tmp_path):
    path = tmp_path / "box.off"
    write_off(path, box_vertices(SIZE), CUBE_F)
    body = ph.Body.from_file(path, mass=3.0)
    m, com, inertia = box_reference(SIZE, 3.0 / np.prod(SIZE))
    assert_body(body, 3.0, com, inertia)


@pytest.mark.parametrize(
    "scale", [0.001, (2.0, 0.5, 3.0), (-1.0, 1.0, 1.0), (-2.0, -0.5, 3.0)], ids=str
)
def test_scale_per_axis_and_mirrors(tmp_path, scale):
    path = tmp_path / "box.obj"
    write_obj(path, [("box", box_vertices(SIZE, TURN, OFFSET), CUBE_F)])
    body = ph.Body.from_file(path, density=1000.0, scale=scale)
    factor = np.broadcast_to(np.asarray(scale, dtype=float), (3,))
    # The reference: the scaled vertices as a polyhedron (a mirror turns the winding over).
    v = box_vertices(SIZE, TURN, OFFSET) * factor
    faces = CUBE_F if np.prod(factor) > 0 else CUBE_F[:, ::-1]
    reference = ph.Body.mesh(v, faces, density=1000.0)
    # and, independently, its mass: |det| times the box's, its centre the scaled centre
    m, com, _ = box_reference(SIZE, 1000.0, TURN, OFFSET)
    assert abs(body.mass - m * abs(np.prod(factor))) <= 64 * EPS * body.mass
    assert np.allclose(body.center_of_mass, com * factor, rtol=64 * EPS, atol=0)
    assert_body(body, reference.mass, reference.center_of_mass, reference.inertia)
    if isinstance(scale, float):  # a uniform scale: I scales as s^5 at a fixed density
        _, _, inertia = box_reference(SIZE, 1000.0, TURN)
        assert np.allclose(body.inertia, inertia * scale**5, rtol=1e-13, atol=0)


def test_hollow_cube_shell(tmp_path):
    # A thin-walled cube of side a: I = 5 m a^2 / 18 about any axis through its centre.
    path = tmp_path / "cube.ply"
    write_ply(path, CUBE_V * 2.0, CUBE_F)
    body = ph.Body.from_file(path, mass=6.0, shell=True)
    assert_body(body, 6.0, [1.0, 1.0, 1.0], np.eye(3) * 5 * 6.0 * 4.0 / 18)


# --- several meshes in one file --------------------------------------------------------------


def two_part_scene():
    """A glTF scene: a box node moved and turned, and a mirrored box node (vertices of dyadic
    sizes, exact in glTF's float32; the node transforms are JSON numbers)."""
    scene = trimesh.Scene()
    a = trimesh.Trimesh(box_vertices(ARM), CUBE_F, process=False)
    b = trimesh.Trimesh(box_vertices(POST), CUBE_F, process=False)
    move = np.eye(4)
    move[:3, :3] = TURN
    move[:3, 3] = [1.0, 2.0, 3.0]
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    mirror[:3, 3] = [-1.0, 0.0, 0.5]
    scene.add_geometry(a, node_name="arm", geom_name="arm_mesh", transform=move)
    scene.add_geometry(b, node_name="post", geom_name="post_mesh", transform=mirror)
    return scene


ARM, POST = (0.5, 0.25, 0.125), (0.125, 0.125, 0.375)


@pytest.mark.parametrize("extension", ["glb", "gltf"])
def test_gltf_nodes_are_parts_and_the_body_their_composite(tmp_path, extension):
    path = tmp_path / f"scene.{extension}"
    write_gltf(path, two_part_scene())
    parts = ph.io.read_mesh(path, density=500.0)
    assert sorted(parts) == ["arm", "post"]
    m_a, com_a, i_a = box_reference(ARM, 500.0, TURN, (1.0, 2.0, 3.0))
    m_b, com_b, i_b = box_reference(POST, 500.0, None, (-1.0, 0.0, 0.5))
    assert_body(parts["arm"], m_a, com_a, i_a)
    assert_body(parts["post"], m_b, com_b, i_b)  # mirrored: still a positive volume
    # The composite, by the parallel-axis theorem written here.
    body = ph.Body.from_file(path, density=500.0)
    m = m_a + m_b
    com = (m_a * com_a + m_b * com_b) / m
    inertia = np.zeros((3, 3))
    for mi, ci, ii in ((m_a, com_a, i_a), (m_b, com_b, i_b)):
        d = ci - com
        inertia += ii + mi * (d @ d * np.eye(3) - np.outer(d, d))
    assert_body(body, m, com, inertia, rtol=1e-14)


def test_total_mass_is_shared_by_volume(tmp_path):
    path = tmp_path / "two.obj"
    small = box_vertices((0.1, 0.1, 0.1))
    large = box_vertices((0.2, 0.2, 0.2), offset=(1.0, 0.0, 0.0))
    write_obj(path, [("small", small, CUBE_F), ("large", large, CUBE_F)])
    parts = ph.io.read_mesh(path, mass=9.0)
    assert sorted(parts) == ["large", "small"]
    assert parts["small"].mass == pytest.approx(1.0, rel=1e-14)  # volumes 1 : 8
    assert parts["large"].mass == pytest.approx(8.0, rel=1e-14)
    assert ph.Body.from_file(path, mass=9.0).mass == pytest.approx(9.0, rel=1e-15)


@pytest.mark.parametrize("scale", [1e-150, 1e-100, 1e-64, 1e62, 1e100, 1e150], ids=str)
def test_total_mass_at_far_scales_against_the_closed_form(tmp_path, scale):
    """The parts were integrated at unit density in the scaled units and then given their
    share of the mass: their volumes underflowed below scale ~1e-60 (a cube of mass 1 at
    scale 1e-64 was 0.2% off, at 1e-100 its inertia was 0, at 1e-105 the error named
    `mass_scale`) and overflowed above 1e61. Each part against the textbook box of its share
    of the mass, at its scaled size and place."""
    path = tmp_path / "two.obj"
    sizes = {"small": (0.1, 0.2, 0.3), "large": (0.2, 0.4, 0.6)}  # volumes 1 : 8
    offsets = {"small": (0.0, 0.0, 0.0), "large": (1.0, -2.0, 0.5)}
    write_obj(path, [(k, box_vertices(sizes[k], TURN, offsets[k]), CUBE_F) for k in sizes])
    parts = ph.io.read_mesh(path, mass=9.0, scale=scale)
    for name, mass in (("small", 1.0), ("large", 8.0)):
        a, b, c = (x * scale for x in sizes[name])
        # The textbook box of this mass (its volume is beyond double precision at 1e150).
        inertia = TURN @ (mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b]))
        inertia = inertia @ TURN.T
        body = parts[name]
        assert body.mass == pytest.approx(mass, rel=1e-14)
        com = np.asarray(offsets[name]) * scale
        assert np.abs(body.center_of_mass - com).max() <= 1e-14 * scale * 3
        # Entrywise (a norm would square entries of 1e299).
        assert np.abs(body.inertia - inertia).max() <= 1e-14 * np.abs(inertia).max()
    total = ph.Body.from_file(path, mass=9.0, scale=scale)
    assert total.mass == pytest.approx(9.0, rel=1e-15)
    # A cube of the same file read directly by Body.mesh (which takes the mass itself).
    direct = ph.Body.mesh(box_vertices(sizes["small"], TURN) * scale, CUBE_F, mass=1.0)
    difference = np.abs(parts["small"].inertia - direct.inertia).max()
    assert difference <= 1e-14 * np.abs(direct.inertia).max()


def test_total_mass_beyond_double_precision_names_the_scale_and_the_file(tmp_path):
    """The box of mass 1 at scale 1e160 overflows where the file's own box does not: the
    scale's fault (an ArgumentError naming it), the file and the reason in the message."""
    path = tmp_path / "box.off"
    write_off(path, box_vertices(SIZE), CUBE_F)
    overflow = "this scale, the moments of inertia overflow"
    with pytest.raises(ph.ArgumentError, match=overflow) as info:
        ph.Body.from_file(path, mass=1.0, scale=1e160)
    assert info.value.argument == "scale" and str(path) in str(info.value), info.value


def test_ascii_stl_with_two_solids(tmp_path):
    path = tmp_path / "two.stl"
    write_stl_ascii(path, CUBE_V, CUBE_F, "first")
    with open(path, "a") as handle:
        second = tmp_path / "second.stl"
        write_stl_ascii(second, CUBE_V + [2.0, 0.0, 0.0], CUBE_F, "second")
        handle.write(second.read_text())
    parts = ph.io.read_mesh(path, density=1.0)
    assert sorted(parts) == ["first", "second"]
    assert_body(parts["second"], 1.0, [2.5, 0.5, 0.5], np.eye(3) / 6)


# --- real files no one here wrote ------------------------------------------------------------

UPKIE_CLOSED = ["qdd100_rotor.stl", "qdd100_horn.stl", "wheel_hub.stl", "camera_support.stl"]


@pytest.mark.parametrize("name", UPKIE_CLOSED)
def test_real_stl_against_trimesh(name):
    upkie = pytest.importorskip("upkie_description")
    found = [
        os.path.join(root, f)
        for root, _, files in os.walk(upkie.MESHES_PATH)
        for f in files
        if f == name
    ]
    (path,) = found
    body = ph.Body.from_file(path, density=1240.0)
    mesh = trimesh.load_mesh(path)
    assert mesh.is_watertight and mesh.is_winding_consistent
    mesh.density = 1240.0
    # trimesh's integrals (its own code) of the same triangles: agreement to round-off.
    assert body.mass == pytest.approx(mesh.mass, rel=1e-13)
    assert np.linalg.norm(body.center_of_mass - mesh.center_mass) <= 1e-13 * np.linalg.norm(
        mesh.extents
    )
    assert np.linalg.norm(body.inertia - mesh.moment_inertia) <= 1e-13 * np.linalg.norm(
        mesh.moment_inertia
    )


def test_real_stl_with_inconsistent_winding_is_refused():
    # upkie's knee_stator.stl is closed but some triangles are wound the wrong way round
    # (trimesh: watertight, not winding-consistent): its volume integrals would be wrong.
    upkie = pytest.importorskip("upkie_description")
    path = os.path.join(upkie.MESHES_PATH, "knee_stator.stl")
    mesh = trimesh.load_mesh(path)
    assert mesh.is_watertight and not mesh.is_winding_consistent
    with pytest.raises(FileFormatError) as caught:
        ph.Body.from_file(path, density=1.0)
    assert caught.value.path == path and "knee_stator.stl" in str(caught.value)
    assert caught.value.field == "faces"


# --- broken files and bad arguments ----------------------------------------------------------


def test_missing_file(tmp_path):
    path = tmp_path / "nothing.stl"
    with pytest.raises(FileNotFoundError) as caught:
        ph.Body.from_file(path, density=1.0)
    assert caught.value.filename == str(path)


def test_folder(tmp_path):
    folder = tmp_path / "dir.stl"
    folder.mkdir()
    with pytest.raises(FileFormatError, match="folder"):
        ph.Body.from_file(folder, density=1.0)


def test_not_a_mesh(tmp_path):
    path = tmp_path / "notes.stl"
    path.write_text("these are not triangles\n")
    with pytest.raises(FileFormatError) as caught:
        ph.Body.from_file(path, density=1.0)
    assert str(path) in str(caught.value) and caught.value.path == str(path)
    path = tmp_path / "garbage.glb"
    path.write_bytes(b"\x00\x01\x02 not a glb")
    with pytest.raises(FileFormatError, match="garbage.glb"):
        ph.Body.from_file(path, density=1.0)


def test_unknown_extension(tmp_path):
    path = tmp_path / "part.step"
    path.write_text("ISO-10303-21;")
    with pytest.raises(FileFormatError, match=r"\.stl.*got \.step"):
        ph.Body.from_file(path, density=1.0)


def test_open_mesh_names_the_file_part_and_field(tmp_path):
    path = tmp_path / "open.obj"
    write_obj(path, [("lid_missing", CUBE_V, CUBE_F[:-2])])
    with pytest.raises(FileFormatError) as caught:
        ph.Body.from_file(path, density=1.0)
    error = caught.value
    assert (error.path, error.link, error.field, error.argument) == (
        str(path),
        "lid_missing",
        "faces",
        "path",
    )
    assert "not closed" in str(error) and "open.obj" in str(error)
    # ... and as a shell it is fine: five faces of the unit cube, area 5.
    assert ph.Body.from_file(path, density=1.0, shell=True).mass == pytest.approx(5.0)


def test_zero_volume_mesh(tmp_path):
    # A closed tetrahedron whose four distinct vertices lie in one plane.
    path = tmp_path / "flat.off"
    flat = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=float)
    write_off(path, flat, np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))
    with pytest.raises(FileFormatError) as caught:
        ph.Body.from_file(path, density=1.0)
    assert "flat.off" in str(caught.value) and "zero" in str(caught.value)
    assert caught.value.field == "vertices"


def test_inside_out_mesh_and_fix_winding(tmp_path):
    path = tmp_path / "inside_out.off"
    write_off(path, CUBE_V, CUBE_F[:, ::-1])
    with pytest.raises(FileFormatError, match="inside out"):
        ph.Body.from_file(path, density=1.0)
    body = ph.Body.from_file(path, density=1.0, fix_winding=True)
    assert_body(body, 1.0, [0.5, 0.5, 0.5], np.eye(3) / 6)


def test_empty_scene(tmp_path):
    path = tmp_path / "empty.obj"
    path.write_text("# nothing\nv 0 0 0\n")
    with pytest.raises(FileFormatError, match="no triangle mesh"):
        ph.Body.from_file(path, density=1.0)


@pytest.mark.parametrize(
    ("kwargs", "error", "argument"),
    [
        ({}, ArgumentError, "density"),
        ({"density": 1.0, "mass": 1.0}, ArgumentError, "mass"),
        ({"density": -1.0}, NonPositiveError, "density"),
        ({"mass": 0.0}, NonPositiveError, "mass"),
        ({"density": 1.0, "scale": 0.0}, ArgumentError, "scale"),
        ({"density": 1.0, "scale": (1.0, 2.0)}, ShapeError, "scale"),
    ],
)
def test_bad_arguments(tmp_path, kwargs, error, argument):
    path = tmp_path / "box.off"
    write_off(path, CUBE_V, CUBE_F)
    with pytest.raises(error) as caught:
        ph.Body.from_file(path, **kwargs)
    assert caught.value.argument == argument


def test_wrong_types(tmp_path):
    with pytest.raises(TypeError, match="path"):
        ph.Body.from_file(3, density=1.0)
    path = tmp_path / "box.off"
    write_off(path, CUBE_V, CUBE_F)
    with pytest.raises(TypeError, match="shell"):
        ph.Body.from_file(path, density=1.0, shell="yes")
    with pytest.raises(TypeError, match="density"):
        ph.Body.from_file(path, density="dense")


def test_file_format_error_pickles_with_its_fields():
    error = FileFormatError("f.urdf: link 'a': mass: bad.", path="f.urdf", link="a", field="mass")
    again = pickle.loads(pickle.dumps(error))
    assert type(again) is FileFormatError and str(again) == str(error)
    assert (again.path, again.link, again.field, again.argument) == ("f.urdf", "a", "mass", "path")
    assert isinstance(again, ph.PolhodeError) and isinstance(again, ValueError)
    renumbered = error.for_body(3)
    assert str(renumbered).startswith("body 3: ") and renumbered.field == "mass"


# --- the command line ------------------------------------------------------------------------


def run_cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "polhode", *args], capture_output=True, text=True, timeout=120
    )


def test_cli_spins_a_mesh_file(tmp_path):
    path = tmp_path / "box.stl"
    write_stl_ascii(path, box_vertices((0.3, 0.2, 0.1)), CUBE_F)
    result = run_cli(
        "spin", "--body", "mesh", f"path={path}", "mass=6", "--omega", "1", "0", "0", "--t", "1"
    )
    assert result.returncode == 0, result.stderr
    line = next(x for x in result.stdout.splitlines() if x.startswith("principal moments"))
    moments = np.array(line.split("[")[1].split("]")[0].split(), dtype=float)
    # m/12 (b^2 + c^2) ... for a = 0.3, b = 0.2, c = 0.1, m = 6, ascending.
    expected = np.sort(6.0 / 12 * np.array([0.05, 0.10, 0.13]))
    assert np.allclose(moments, expected, rtol=1e-5)


@pytest.mark.parametrize(
    ("words", "message"),
    [
        (["mesh", "density=1"], "missing path"),
        (["mesh", "path=PATH"], "exactly one of density and mass"),
        (["mesh", "path=PATH", "density=1", "mass=2"], "exactly one of density and mass"),
        (["mesh", "path=PATH", "density=x"], "density=NUMBER"),
        (["mesh", "path=PATH", "density=1", "colour=red"], "unknown key 'colour'"),
        (["mesh", "path=PATH", "density=1", "shell=maybe"], "shell=true or shell=false"),
        (["mesh", "path=MISSING", "density=1"], "No such file"),
        (["mesh", "path=OPEN", "density=1"], "not closed"),
    ],
)
def test_cli_mesh_errors(tmp_path, words, message):
    box = tmp_path / "box.off"
    write_off(box, CUBE_V, CUBE_F)
    open_mesh = tmp_path / "open.off"
    write_off(open_mesh, CUBE_V, CUBE_F[:-1])
    words = [
        w.replace("PATH", str(box))
        .replace("MISSING", str(tmp_path / "missing.stl"))
        .replace("OPEN", str(open_mesh))
        for w in words
    ]
    result = run_cli("spin", "--body", *words, "--omega", "1", "0", "0", "--t", "1")
    assert result.returncode == 2
    assert "--body" in result.stderr and message in result.stderr
    assert "Traceback" not in result.stderr
