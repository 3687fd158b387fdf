"""`polhode inertia FILE`: the mass properties of a mesh file, of a robot description's links
and of a molecule, and the principal axes of a molecule's frames over time.

References, none of them polhode:

- trimesh's mass properties of the same mesh (``Trimesh.mass_properties``,
  ``moment_inertia_frame`` about a point), and closed forms of boxes (solid and thin shell);
- MuJoCo's compiled model of the MJCF MuJoCo ships (``body_mass``, ``body_ipos``, and the
  tensor from ``body_iquat`` and ``body_inertia``); a URDF written here, its rpy turned into a
  matrix by scipy;
- ASE's ``get_moments_of_inertia`` with the AME 2020 isotope masses written below, the
  rotational constants ``h / (8 pi^2 I)`` from scipy's CODATA constants, Ray's kappa from
  them, and carbon monoxide's measured ``B_e``;
- the spatial inertia assembled here from the peers' numbers (Featherstone's blocks);
- for the frames, numpy's ``eigh`` of each frame's tensor summed here, and the closed form of a
  planar molecule whose two moments cross.
"""

from __future__ import annotations

import csv
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy import constants as sc
from scipy.spatial.transform import Rotation

from polhode.cli import main

trimesh = pytest.importorskip("trimesh")
mujoco = pytest.importorskip("mujoco")
pytest.importorskip("ase")
import ase  # noqa: E402
import ase.build  # noqa: E402
import ase.io  # noqa: E402

EPS = np.finfo(float).eps
DATA = os.path.join(os.path.dirname(__file__), "data")

# AME 2020 atomic masses (u) of the most abundant isotopes (M. Wang et al., Chinese Phys. C 45,
# 030003 (2021)); periodictable rounds them to 10 significant digits, hence bounds of 1e-9 on
# what depends on the masses. CIAAW 2021 standard atomic weights.
ISOTOPE = {"H": 1.007825031898, "C": 12.0, "N": 14.003074004251, "O": 15.994914619257}
MASS_RTOL = 1e-9
AVERAGE = {"H": 1.008, "C": 12.011, "N": 14.007, "O": 15.999}


def inertia_json(capsys, *argv):
    """Run `polhode inertia ... --json` and return the parsed output."""
    status = main(["inertia", *map(str, argv), "--json"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    return json.loads(captured.out)


def cross(c):
    return np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])


def featherstone(mass, com, inertia_about_point, point):
    """Featherstone's spatial inertia [[I_p, m [c]], [m [c]^T, m 1]], c = com - point."""
    c = cross(np.asarray(com) - np.asarray(point))
    return np.block([[inertia_about_point, mass * c], [mass * c.T, mass * np.eye(3)]])


def close(a, b, scale, bound=64 * EPS):
    """Every element of a and b within bound times scale."""
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) <= bound * scale


# --- meshes -----------------------------------------------------------------------------------


def lopsided_mesh():
    """A closed mesh with no symmetry: a box and an icosphere fused, turned and moved."""
    box = trimesh.creation.box(extents=[0.4, 0.2, 0.1])
    ball = trimesh.creation.icosphere(subdivisions=2, radius=0.08)
    ball.apply_translation([0.25, 0.05, 0.0])
    mesh = trimesh.util.concatenate([box, ball])  # two closed shells: their volumes add
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    turn[:3, 3] = [1.0, -2.0, 0.5]
    mesh.apply_transform(turn)
    return mesh


@pytest.mark.parametrize("extension", ["stl", "obj", "ply", "off", "glb"])
def test_mesh_file_against_trimesh(tmp_path, capsys, extension):
    mesh = lopsided_mesh()
    path = tmp_path / f"part.{extension}"
    mesh.export(path)
    density = 2700.0
    point = [0.3, -0.1, 0.2]
    got = inertia_json(
        capsys, path, "--density", density, "--point", *point, "--spatial", "featherstone"
    )
    mesh = trimesh.load(path, force="mesh")  # as stored: STL keeps float32, OBJ 8 decimals
    mesh.density = density
    props = mesh.mass_properties
    scale = float(np.abs(props["inertia"]).max())
    assert got["kind"] == "mesh"
    assert got["mass"] == pytest.approx(props["mass"], rel=1e-12)
    assert close(got["center_of_mass"], props["center_mass"], 1.0, 1e-12)
    assert close(got["inertia"], props["inertia"], scale, 1e-10)
    # The principal moments are the eigenvalues of trimesh's tensor (numpy), the axes its
    # eigenvectors, forming a proper rotation.
    moments = np.linalg.eigvalsh(props["inertia"])
    assert close(got["principal_moments"], moments, scale, 1e-10)
    axes = np.array(got["principal_axes"])
    assert close(np.array(props["inertia"]) @ axes, axes * moments, scale, 1e-9)
    assert np.linalg.det(axes) == pytest.approx(1.0, abs=1e-12)
    # About a point: trimesh's inertia in a frame at that point.
    frame = np.eye(4)
    frame[:3, 3] = point
    about = mesh.moment_inertia_frame(frame)
    big = float(np.abs(about).max())
    assert got["inertia_about_point"]["point"] == point
    assert close(got["inertia_about_point"]["inertia"], about, big, 1e-10)
    spatial = got["spatial_inertia"]
    assert spatial["convention"] == "featherstone" and spatial["point"] == point
    expected = featherstone(props["mass"], props["center_mass"], about, point)
    assert close(spatial["matrix"], expected, float(np.abs(expected).max()), 1e-10)


def test_mesh_mass_scale_and_shell_against_closed_forms(tmp_path, capsys):
    path = tmp_path / "bracket.stl"
    trimesh.creation.box(extents=[40.0, 20.0, 10.0]).export(path)  # millimetres
    got = inertia_json(capsys, path, "--mass", 0.5, "--scale", 0.001)
    a, b, c = 0.040, 0.020, 0.010
    solid = 0.5 / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    assert got["mass"] == pytest.approx(0.5, rel=1e-14)
    assert close(got["inertia"], solid, float(solid.max()), 1e-12)
    cube = tmp_path / "cube.off"
    trimesh.creation.box(extents=[2.0, 2.0, 2.0]).export(cube)
    shell = inertia_json(capsys, cube, "--mass", 3.0, "--shell")
    # A thin cubic shell of side s: I = 5/18 m s^2 about every axis.
    assert np.allclose(shell["principal_moments"], 5 / 18 * 3.0 * 4.0, rtol=1e-13, atol=0)
    density = inertia_json(capsys, cube, "--density", 0.25, "--shell")
    assert density["mass"] == pytest.approx(0.25 * 24.0, rel=1e-14)  # the area, 6 s^2


def test_mesh_file_of_several_parts_against_trimesh(tmp_path, capsys):
    scene = trimesh.Scene()
    box = trimesh.creation.box(extents=[1.0, 0.5, 0.25])
    scene.add_geometry(
        box, node_name="box", transform=trimesh.transformations.translation_matrix([1.0, 0.0, 0.0])
    )
    cylinder = trimesh.creation.cylinder(radius=0.2, height=0.6, sections=64)
    turn = trimesh.transformations.rotation_matrix(0.7, [1, 1, 0], [0.0, 0.5, 0.3])
    scene.add_geometry(cylinder, node_name="cylinder", transform=turn)
    path = tmp_path / "assembly.glb"
    scene.export(path)
    got = inertia_json(capsys, path, "--density", 1000.0)
    assert sorted(got["parts"]) == ["box", "cylinder"]
    whole = trimesh.load(path).to_mesh()  # as stored (float32), both parts placed
    whole.density = 1000.0
    props = whole.mass_properties
    assert got["mass"] == pytest.approx(props["mass"], rel=1e-12)
    assert close(got["center_of_mass"], props["center_mass"], 1.0, 1e-12)
    assert close(got["inertia"], props["inertia"], float(np.abs(props["inertia"]).max()), 1e-10)
    assert sum(p["mass"] for p in got["parts"].values()) == pytest.approx(props["mass"], rel=1e-13)


def test_mesh_text_output(tmp_path, capsys):
    path = tmp_path / "bracket.stl"
    trimesh.creation.box(extents=[40.0, 20.0, 10.0]).export(path)
    assert main(["inertia", str(path), "--density", "2700", "--scale", "0.001"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{path}: mesh")
    assert float(out.split("mass")[1].split()[0]) == pytest.approx(0.0216, rel=1e-9)
    moments = [float(x) for x in out.split("principal moments")[1].split()[:3]]
    m, a, b, c = 0.0216, 0.04, 0.02, 0.01
    expected = sorted(m / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b]))
    assert moments == pytest.approx(expected, rel=1e-8)  # printed to 9 digits


def test_inside_out_mesh_with_fix_winding_and_text_of_parts(tmp_path, capsys):
    box = trimesh.creation.box(extents=[1.0, 2.0, 3.0])
    inside_out = tmp_path / "inside_out.ply"
    trimesh.Trimesh(box.vertices, box.faces[:, ::-1], process=False).export(inside_out)
    status, err = run([inside_out, "--density", 1], capsys)
    assert status == 2 and str(inside_out) in err and "inside out" in err
    got = inertia_json(capsys, inside_out, "--density", 1, "--fix-winding")
    assert got["mass"] == pytest.approx(6.0, rel=1e-14)
    scene = trimesh.Scene()
    scene.add_geometry(box, node_name="left")
    scene.add_geometry(
        box,
        node_name="right",
        transform=trimesh.transformations.translation_matrix([3.0, 0.0, 0.0]),
    )
    path = tmp_path / "pair.glb"
    scene.export(path)
    assert main(["inertia", str(path), "--mass", "4"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{path}: mesh, 2 parts (their sum)")
    for name, x in (("left", 0.0), ("right", 3.0)):
        line = next(line for line in out.splitlines() if line.startswith(f"part {name}"))
        assert float(line.split("mass ")[1].split(",")[0]) == pytest.approx(2.0, rel=1e-9)
        assert float(line.split("centre of mass ")[1].split()[0]) == pytest.approx(x, abs=1e-9)
    assert float(out.split("centre of mass")[1].split()[0]) == pytest.approx(1.5, rel=1e-9)


# --- robot descriptions -------------------------------------------------------------------------


def compiled_tensor(model, i):
    w, x, y, z = model.body_iquat[i]
    r = Rotation.from_quat([x, y, z, w]).as_matrix()
    return r @ np.diag(model.body_inertia[i]) @ r.T


def test_mjcf_links_against_mujoco(capsys):
    path = os.path.join(os.path.dirname(mujoco.__file__), "testdata", "model.xml")
    model = mujoco.MjSpec.from_file(path).compile()
    point = [0.1, 0.2, -0.3]
    got = inertia_json(capsys, path, "--point", *point, "--spatial", "pinocchio")
    assert got["kind"] == "mjcf"
    links = got["links"]
    checked = 0
    for i in range(1, model.nbody):
        name = model.body(i).name or f"body {i}"
        mass = model.body_mass[i]
        if mass == 0:
            assert name not in links
            continue
        link = links[name]
        tensor = compiled_tensor(model, i)
        scale = float(np.abs(tensor).max())
        com = model.body_ipos[i]
        assert link["mass"] == pytest.approx(mass, rel=64 * EPS)
        assert close(link["center_of_mass"], com, 1.0 + np.abs(com).max())
        assert close(link["inertia"], tensor, scale)
        # About the point, by the parallel-axis theorem; the spatial inertia linear first.
        d = com - np.array(point)
        about = tensor + mass * (d @ d * np.eye(3) - np.outer(d, d))
        big = float(np.abs(about).max())
        assert close(link["inertia_about_point"]["inertia"], about, big, 256 * EPS)
        f = featherstone(mass, com, about, point)
        pinocchio = np.block([[f[3:, 3:], f[3:, :3]], [f[:3, 3:], f[:3, :3]]])
        matrix = link["spatial_inertia"]["matrix"]
        assert close(matrix, pinocchio, float(np.abs(f).max()), 256 * EPS)
        checked += 1
    assert checked == len(links) >= 10


URDF = """<robot name="arm">
  <link name="base"/>
  <link name="forearm"><inertial>
    <origin xyz="0.01 -0.02 0.1" rpy="0.3 -0.2 0.5"/><mass value="1.2"/>
    <inertia ixx="0.004" ixy="0.0002" ixz="-0.0001" iyy="0.005" iyz="0.0003" izz="0.002"/>
  </inertial></link>
  <joint name="elbow" type="revolute"><parent link="base"/><child link="forearm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def test_urdf_links_against_the_declared_inertial(tmp_path, capsys):
    path = tmp_path / "arm.urdf"
    path.write_text(URDF)
    got = inertia_json(capsys, path, "--spatial", "drake")
    assert list(got["links"]) == ["forearm"]  # base has no inertial: massless in URDF
    link = got["links"]["forearm"]
    # URDF's rpy is fixed-axis x, y, z: R = Rz(y) Ry(p) Rx(r), scipy's extrinsic "xyz".
    r = Rotation.from_euler("xyz", [0.3, -0.2, 0.5]).as_matrix()
    declared = np.array(
        [[0.004, 0.0002, -0.0001], [0.0002, 0.005, 0.0003], [-0.0001, 0.0003, 0.002]]
    )
    tensor = r @ declared @ r.T
    com = np.array([0.01, -0.02, 0.1])
    assert link["mass"] == 1.2
    assert link["center_of_mass"] == pytest.approx(com, rel=EPS, abs=0)
    assert close(link["inertia"], tensor, 0.005)
    about_origin = tensor + 1.2 * (com @ com * np.eye(3) - np.outer(com, com))
    expected = featherstone(1.2, com, about_origin, np.zeros(3))
    assert close(link["spatial_inertia"]["matrix"], expected, 1.2)
    # The text table: one row per link, the six tensor elements in ixx iyy izz ixy ixz iyz,
    # then the link's spatial inertia.
    assert main(["inertia", str(path), "--spatial", "drake"]) == 0
    text = capsys.readouterr().out
    lines = text.splitlines()
    spatial = text.split("\nforearm\n")[1].splitlines()
    assert spatial[0].startswith("spatial inertia")
    shown = np.array([[float(x) for x in line[21:].split()] for line in spatial[:6]])
    assert close(shown, expected, 1.2, 1e-8)
    assert "(drake: angular block first; about 0 0 0, in the link's frame)" in spatial[6]
    assert lines[1].split() == [
        "link",
        "mass",
        "com_x",
        "com_y",
        "com_z",
        "ixx",
        "iyy",
        "izz",
        "ixy",
        "ixz",
        "iyz",
    ]
    row = lines[2].split()
    assert row[0] == "forearm"
    values = [float(x) for x in row[1:]]
    expected_row = [
        1.2,
        *com,
        tensor[0, 0],
        tensor[1, 1],
        tensor[2, 2],
        tensor[0, 1],
        tensor[0, 2],
        tensor[1, 2],
    ]
    assert values == pytest.approx(expected_row, rel=1e-8, abs=1e-12)


def test_urdf_links_without_inertial_from_their_geometry(tmp_path, capsys):
    path = tmp_path / "boxes.urdf"
    path.write_text("""<robot name="r"><link name="plate"><collision>
        <origin xyz="0 0 0.05" rpy="0 0 0"/><geometry><box size="0.3 0.2 0.1"/></geometry>
      </collision></link></robot>""")
    got = inertia_json(capsys, path, "--density", 1000.0)
    plate = got["links"]["plate"]
    m = 1000.0 * 0.3 * 0.2 * 0.1
    assert plate["mass"] == pytest.approx(m, rel=1e-14)
    assert plate["center_of_mass"] == pytest.approx([0, 0, 0.05], abs=1e-17)
    box = m / 12 * np.diag([0.2**2 + 0.1**2, 0.3**2 + 0.1**2, 0.3**2 + 0.2**2])
    assert close(plate["inertia"], box, float(box.max()))


# --- molecules ----------------------------------------------------------------------------------


def rotational_constants_by_hand(moments_u_a2, unit):
    """h / (8 pi^2 I), I in u angstrom^2, in MHz, GHz or cm-1 (CODATA through scipy)."""
    kg_m2 = np.asarray(moments_u_a2) * sc.physical_constants["atomic mass constant"][0] * 1e-20
    hertz = sc.h / (8 * math.pi**2 * kg_m2)
    return hertz / {"MHz": 1e6, "GHz": 1e9, "cm-1": 100 * sc.c}[unit]


@pytest.mark.parametrize("masses", ["most_abundant", "average"])
def test_molecule_against_ase(tmp_path, capsys, masses):
    atoms = ase.build.molecule("CH3CH2OH")
    atoms.rotate(40, "x")
    atoms.rotate(-25, "z")
    atoms.translate([3.0, -1.0, 2.0])
    path = tmp_path / "ethanol.xyz"
    ase.io.write(path, atoms)
    got = inertia_json(capsys, path, "--masses", masses, "--unit", "GHz", "--point", 0, 0, 0)
    atoms = ase.io.read(path)  # as stored: 8 decimals
    table = ISOTOPE if masses == "most_abundant" else AVERAGE
    atoms.set_masses([table[s] for s in atoms.get_chemical_symbols()])
    assert got["kind"] == "molecule" and got["atoms"] == 9 and got["formula"] == "C2H6O"
    assert got["masses"] == masses and "periodictable" in got["mass_source"]
    assert got["mass"] == pytest.approx(float(atoms.get_masses().sum()), rel=MASS_RTOL)
    assert close(got["center_of_mass"], atoms.get_center_of_mass(), 4.0, MASS_RTOL)
    moments = atoms.get_moments_of_inertia()  # ASE: ascending eigenvalues, u angstrom^2
    assert got["principal_moments"] == pytest.approx(moments, rel=MASS_RTOL)
    # About the origin: sum m (|r|^2 1 - r r^T) summed here.
    r, m = atoms.get_positions(), atoms.get_masses()
    about = sum(mi * (ri @ ri * np.eye(3) - np.outer(ri, ri)) for mi, ri in zip(m, r, strict=True))
    scale = float(np.abs(about).max())
    assert close(got["inertia_about_point"]["inertia"], about, scale, MASS_RTOL)
    constants = got["rotational_constants"]
    assert constants["unit"] == "GHz"
    a, b, c = rotational_constants_by_hand(moments, "GHz")
    expected = pytest.approx([a, b, c], rel=MASS_RTOL)
    assert [constants["A"], constants["B"], constants["C"]] == expected
    assert got["asymmetry"] == pytest.approx((2 * b - a - c) / (a - c), rel=1e-8)
    assert got["rotor_type"] == "asymmetric"


def test_molecule_constants_against_measured_ones(tmp_path, capsys):
    """Carbon monoxide at its equilibrium bond length, 1.128323 angstrom: B_e = 1.93128 cm-1
    (Huber and Herzberg, Constants of Diatomic Molecules, 1979); a linear rotor, no A."""
    path = tmp_path / "co.xyz"
    path.write_text("2\ncarbon monoxide\nC 0 0 0\nO 0 0 1.128323\n")
    got = inertia_json(capsys, path, "--unit", "cm-1")
    constants = got["rotational_constants"]
    assert constants["A"] is None and constants["B"] == constants["C"]
    assert constants["B"] == pytest.approx(1.93128, abs=5e-6)
    assert got["rotor_type"] == "linear" and got["asymmetry"] == -1.0
    assert main(["inertia", str(path), "--unit", "cm-1"]) == 0
    out = capsys.readouterr().out
    assert "A - (linear)" in out and "rotor type           linear" in out
    assert float(out.split(" B ")[1].split()[0]) == pytest.approx(1.93128, abs=5e-6)


@pytest.mark.parametrize(
    ("name", "kind"), [("NH3", "oblate"), ("CH4", "spherical"), ("CH3Cl", "prolate")]
)
def test_molecule_rotor_types(tmp_path, capsys, name, kind):
    path = tmp_path / f"{name}.pdb"
    ase.io.write(path, ase.build.molecule(name))
    got = inertia_json(capsys, path)
    assert got["rotor_type"] == kind
    if kind == "spherical":
        assert got["asymmetry"] is None  # 0/0
        assert main(["inertia", str(path)]) == 0
        assert "undefined (a spherical top)" in capsys.readouterr().out
    else:
        assert got["asymmetry"] == pytest.approx(1.0 if kind == "oblate" else -1.0, abs=1e-3)


def test_single_atom_has_no_rotational_constants(tmp_path, capsys):
    path = tmp_path / "argon.xyz"
    path.write_text("1\nargon\nAr 1 2 3\n")
    got = inertia_json(capsys, path)
    assert got["rotational_constants"] is None and got["rotor_type"] is None
    assert got["mass"] == pytest.approx(39.9623831220, rel=MASS_RTOL)  # 40Ar, AME 2020
    assert main(["inertia", str(path)]) == 0
    assert "none (all moments zero" in capsys.readouterr().out


def test_format_names_ases_reader(tmp_path, capsys):
    path = tmp_path / "co.txt"
    path.write_text("2\ncarbon monoxide\nC 0 0 0\nO 0 0 1.128323\n")
    status, err = run([path], capsys)  # .txt: no reader of ASE's by that extension
    assert status == 2 and str(path) in err and "--format" in err
    got = inertia_json(capsys, path, "--format", "xyz", "--unit", "cm-1")
    assert got["rotational_constants"]["B"] == pytest.approx(1.93128, abs=5e-6)


# --- frames over time ---------------------------------------------------------------------------


def read_frames_csv(path):
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    assert header[:4] == ["frame", "moment_1 (u angstrom^2)", "moment_2 (u angstrom^2)",
                          "moment_3 (u angstrom^2)"]
    assert header[4:] == [f"axis_{k}_{c}" for k in (1, 2, 3) for c in "xyz"]
    assert np.array_equal(body[:, 0], np.arange(len(body)))
    return body[:, 1:4], body[:, 4:].reshape(-1, 3, 3).transpose(0, 2, 1)  # axes as columns


def tensors_by_hand(masses, positions):
    out = []
    for r in positions:
        r = r - masses @ r / masses.sum()
        terms = (m * (x @ x * np.eye(3) - np.outer(x, x)) for m, x in zip(masses, r, strict=True))
        out.append(sum(terms))
    return np.array(out)


def test_frames_follow_the_axes_where_eigh_flips(tmp_path, capsys):
    """Ethanol turning and drifting: each frame's axes are eigenvectors of the frame's tensor
    (numpy's eigh), and none flips or swaps between frames, where eigh's signs jump."""
    atoms = ase.build.molecule("CH3CH2OH")
    turns = Rotation.from_rotvec(np.outer(np.linspace(0, 9, 300), [0.3, 1.0, 0.2]))
    frames = []
    for k, turn in enumerate(turns):
        frame = atoms.copy()
        frame.positions = turn.apply(atoms.positions) + [0.01 * k, 0.0, -0.02 * k]
        frames.append(frame)
    path = tmp_path / "trajectory.xyz"
    ase.io.write(path, frames)
    out = tmp_path / "axes.csv"
    got = inertia_json(capsys, path, "--frames", out)
    assert got["frames"] == {"count": 300, "csv": str(out)}
    moments, axes = read_frames_csv(out)
    masses = np.array([ISOTOPE[s] for s in atoms.get_chemical_symbols()])
    stored = np.array([f.positions for f in ase.io.read(path, index=":")])  # 8 decimals
    tensors = tensors_by_hand(masses, stored)
    values, vectors = np.linalg.eigh(tensors)
    # The moments are eigh's eigenvalues, the axes its eigenvectors (to the masses' rounding).
    assert np.allclose(moments, values, rtol=MASS_RTOL, atol=0)
    residual = np.einsum("tij,tjk->tik", tensors, axes) - axes * moments[:, None, :]
    assert np.abs(residual).max() < MASS_RTOL * values.max()
    assert np.allclose(np.linalg.det(axes), 1.0, atol=1e-12)
    # No flip, no swap: each axis moves little from a frame to the next (0.03 rad a frame).
    steps = np.einsum("tik,tik->tk", axes[1:], axes[:-1])
    assert steps.min() > 0.99
    # eigh's own axes, frame by frame, do flip sign along the same motion.
    eigh_steps = np.einsum("tik,tik->tk", vectors[1:], vectors[:-1])
    assert (eigh_steps < 0).any()
    # Frame 0 is the molecule as the file has it (the text output's first frame).
    assert np.allclose(got["principal_moments"], moments[0], rtol=1e-12, atol=0)


def test_frames_through_a_crossing_of_two_moments(tmp_path, capsys):
    """Four carbon atoms in a plane, the arm along x growing while the arm along y shrinks: the
    moments about x and y cross at frame 20, where they are equal (a degenerate frame). Each
    column keeps its axis and its moment follows it (closed form: about x, 2 m b^2 from the
    atoms on y; about y, 2 m a^2 from those on x)."""
    t = np.linspace(0.0, 1.0, 41)  # t[20] = 0.5: a = b = 1.5
    a, b = 1.0 + t, 2.0 - t
    positions = np.zeros((len(t), 4, 3))
    positions[:, 0, 0], positions[:, 1, 0] = a, -a
    positions[:, 2, 1], positions[:, 3, 1] = b, -b
    path = tmp_path / "stretch.xyz"
    ase.io.write(path, [ase.Atoms("C4", positions=p) for p in positions])
    out = tmp_path / "axes.csv"
    inertia_json(capsys, path, "--frames", out)
    moments, axes = read_frames_csv(out)
    about_x, about_y = 2 * 12.0 * b**2, 2 * 12.0 * a**2
    # Frame 0 is ascending: about y (2 m) < about x (8 m) < about z (10 m); then followed.
    assert np.allclose(moments[0], [about_y[0], about_x[0], about_x[0] + about_y[0]], rtol=1e-15)
    for k in range(len(t)):  # column 0 stays along y, column 1 along x, through the crossing
        assert abs(axes[k, 1, 0]) == pytest.approx(1.0, abs=1e-12)
        assert abs(axes[k, 0, 1]) == pytest.approx(1.0, abs=1e-12)
    assert np.allclose(moments[:, 0], about_y, rtol=1e-14, atol=0)
    assert np.allclose(moments[:, 1], about_x, rtol=1e-14, atol=0)
    assert moments[-1, 0] > moments[-1, 1]  # no longer ascending: the moments followed
    assert (np.einsum("tik,tik->tk", axes[1:], axes[:-1]) > 0.999).all()
    assert np.allclose(np.linalg.det(axes), 1.0, atol=1e-12)


# --- bad input ----------------------------------------------------------------------------------


def run(argv, capsys):
    status = main(["inertia", *map(str, argv)])
    captured = capsys.readouterr()
    return status, captured.err


def test_missing_and_unreadable_files_exit_2_naming_the_file(tmp_path, capsys):
    missing = tmp_path / "missing.xyz"
    status, err = run([missing], capsys)
    assert status == 2 and str(missing) in err and "no such file" in err
    garbage = tmp_path / "garbage.xyz"
    garbage.write_text("this is not\nan xyz file\n")
    status, err = run([garbage], capsys)
    assert status == 2 and str(garbage) in err and "could not read a molecule" in err
    status, err = run([tmp_path], capsys)
    assert status == 2 and "folder" in err
    not_xml = tmp_path / "robot.urdf"
    not_xml.write_text("{}")
    status, err = run([not_xml], capsys)
    assert status == 2 and str(not_xml) in err and "not valid XML" in err
    broken = os.path.join(DATA, "broken_inertials.urdf")
    status, err = run([broken, "--strict"], capsys)
    assert status == 2 and broken in err and "link 'plate_rounded'" in err
    assert "inertial.inertia" in err and "polhode audit" in err
    # Read whole: the links a simulator refuses are left out, named in a warning.
    status, err = run([broken], capsys)
    assert status == 0 and broken in err and "warning" in err and "'plate_rounded'" in err
    assert "inertial.inertia" in err and "polhode audit" in err
    dummy = tmp_path / "dummy.xyz"
    dummy.write_text("2\nan unknown element\nXx 0 0 0\nC 0 0 1\n")
    status, err = run([dummy], capsys)
    assert status == 2 and str(dummy) in err


def test_broken_meshes_exit_2_naming_the_file(tmp_path, capsys):
    open_mesh = tmp_path / "open.stl"
    box = trimesh.creation.box()
    trimesh.Trimesh(box.vertices, box.faces[:-1]).export(open_mesh)
    status, err = run([open_mesh, "--density", 1], capsys)
    assert status == 2 and str(open_mesh) in err and "not closed" in err
    not_stl = tmp_path / "part.stl"
    not_stl.write_text("solid nothing\nthis is not an stl\n")
    status, err = run([not_stl, "--density", 1], capsys)
    assert status == 2 and str(not_stl) in err


def test_frames_of_other_atoms_exit_2(tmp_path, capsys):
    path = tmp_path / "mixed.xyz"
    ase.io.write(path, [ase.build.molecule("H2O"), ase.build.molecule("NH3")])
    status, err = run([path, "--frames", tmp_path / "out.csv"], capsys)
    assert status == 2 and str(path) in err and "frame 1" in err
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.parametrize(
    ("argv", "option"),
    [
        (["{stl}"], "--density"),  # a mesh needs a density or a mass
        (["{stl}", "--density", "1", "--scale", "0"], "--scale"),
        (["{stl}", "--density", "1", "--frames", "{tmp}/out.csv"], "--frames"),
        (["{stl}", "--density", "1", "--masses", "average"], "--masses"),
        (["{stl}", "--density", "1", "--unit", "GHz"], "--unit"),
        (["{urdf}", "--scale", "2"], "--scale"),
        (["{urdf}", "--shell"], "--shell"),
        (["{xyz}", "--density", "1"], "--density"),
        (["{xyz}", "--frames", "{tmp}"], "--frames"),  # a folder
        (["{xyz}", "--frames", "{xyz}"], "--frames"),  # the file read
        (["{xyz}", "--frames", "{tmp}/nowhere/out.csv"], "--frames"),
        (["{xyz}", "--density", "1", "--mass", "2"], "--mass"),
        (["{xyz}", "--masses", "heaviest"], "--masses"),
        (["{xyz}", "--unit", "Hz"], "--unit"),
        (["{xyz}", "--spatial", "roy"], "--spatial"),
        (["{xyz}", "--point", "0", "0"], "--point"),
        (["{xyz}", "--point", "0", "0", "nan"], "--point"),
        (["{stl}", "--density", "-1"], "--density"),
    ],
)
def test_bad_options_exit_2_naming_the_option(tmp_path, capsys, argv, option):
    stl = tmp_path / "cube.stl"
    trimesh.creation.box().export(stl)
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(URDF)
    xyz = tmp_path / "co.xyz"
    xyz.write_text("2\n\nC 0 0 0\nO 0 0 1.128\n")
    names = {"stl": stl, "urdf": urdf, "xyz": xyz, "tmp": tmp_path}
    status, err = run([a.format(**names) for a in argv], capsys)
    assert status == 2
    assert option in err and "Traceback" not in err


@pytest.mark.parametrize(
    ("module", "extra", "name"), [("trimesh", "mesh", "cube.stl"), ("ase", "chem", "co.xyz")]
)
def test_a_missing_extra_names_it(tmp_path, capsys, monkeypatch, module, extra, name):
    path = tmp_path / name
    if name.endswith(".stl"):
        trimesh.creation.box().export(path)
    else:
        path.write_text("2\n\nC 0 0 0\nO 0 0 1.128\n")
    for loaded in [m for m in sys.modules if m == module or m.startswith(module + ".")]:
        monkeypatch.setitem(sys.modules, loaded, None)  # import raises ImportError
    status, err = run([path, "--density", 1] if extra == "mesh" else [path], capsys)
    assert status == 2 and f"polhode[{extra}]" in err


def test_through_python_m_polhode_without_traceback(tmp_path):
    path = tmp_path / "garbage.xyz"
    path.write_text("not a molecule\n")
    result = subprocess.run(
        [sys.executable, "-m", "polhode", "inertia", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 2
    assert str(path) in result.stderr and "Traceback" not in result.stderr
