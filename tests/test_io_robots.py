"""Robot descriptions: polhode.io.read_urdf, read_mjcf and audit.

References, none of them polhode:

- MuJoCo's compiler: ``body_mass``, ``body_ipos``, ``body_iquat`` and ``body_inertia`` of the
  models MuJoCo ships (``mujoco/testdata/model.xml``) and of gymnasium's MuJoCo models, whose
  inertials MuJoCo infers from capsules, spheres, cylinders, boxes, ellipsoids and meshes; of
  upkie_description's URDF; and of explicit inertials in every orientation MJCF has;
- the URDF's own XML read with ElementTree, its rpy turned into a matrix by scipy, and
  yourdfpy's parsed values;
- closed forms of boxes, cylinders and spheres;
- the fixtures in tests/data, whose numbers come from the textbook box formula.
"""

from __future__ import annotations

import glob
import importlib.util
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.errors import ArgumentError, FileFormatError, RobotFileWarning

mujoco = pytest.importorskip("mujoco")
yourdfpy = pytest.importorskip("yourdfpy")
trimesh = pytest.importorskip("trimesh")

EPS = np.finfo(float).eps
DATA = os.path.join(os.path.dirname(__file__), "data")
BROKEN_URDF = os.path.join(DATA, "broken_inertials.urdf")
BROKEN_MJCF = os.path.join(DATA, "broken_inertials.xml")


def mujoco_testdata(name):
    return os.path.join(os.path.dirname(mujoco.__file__), "testdata", name)


def gymnasium_models():
    spec = importlib.util.find_spec("gymnasium")  # located without importing gymnasium
    if spec is None or not spec.submodule_search_locations:
        return []
    folder = os.path.join(spec.submodule_search_locations[0], "envs", "mujoco", "assets")
    return sorted(glob.glob(os.path.join(folder, "*.xml")))


def upkie_urdf():
    upkie = pytest.importorskip("upkie_description")
    return upkie.URDF_PATH


def compiled_tensor(model, i):
    """Body i's inertia tensor in its body frame from MuJoCo's principal form."""
    w, x, y, z = model.body_iquat[i]
    r = Rotation.from_quat([x, y, z, w]).as_matrix()
    return r @ np.diag(model.body_inertia[i]) @ r.T


def relative_errors(body, mass, com, tensor):
    """Relative errors of mass, centre of mass (against the size of the body plus the distance
    from the origin) and tensor (Frobenius)."""
    size = np.sqrt(max(np.trace(tensor), 0.0) / mass) if mass > 0 else 0.0
    tiny = np.finfo(float).tiny  # a point mass at the origin: the errors are then absolute
    return (
        abs(body.mass - mass) / mass,
        np.linalg.norm(body.center_of_mass - com) / max(size + np.linalg.norm(com), tiny),
        np.linalg.norm(body.inertia - tensor) / max(np.linalg.norm(tensor), tiny),
    )


def compare_with_mujoco(bodies, model, scale=1.0, bound=64 * EPS, skip=()):
    """Every body MuJoCo gives a mass is read, with MuJoCo's values."""
    worst = np.zeros(3)
    for i in range(1, model.nbody):
        name = model.body(i).name or f"body {i}"
        if model.body_mass[i] == 0:
            assert name not in bodies
            continue
        if name in skip:
            continue
        errors = relative_errors(
            bodies[name],
            model.body_mass[i] / scale,
            model.body_ipos[i],
            compiled_tensor(model, i) / scale,
        )
        worst = np.maximum(worst, errors)
    assert np.all(worst <= bound), worst
    return worst


# --- MJCF against MuJoCo's compiler ----------------------------------------------------------


def test_mujoco_testdata_model_against_mujoco():
    # Ellipsoids with their own density, capsules, cylinders and boxes by fromto (a box's
    # fromto makes it square, as MuJoCo's compiler does), boxes turned by euler in degrees
    # with an explicit mass, and an inline mesh of vertices only (its convex hull), scaled.
    path = mujoco_testdata("model.xml")
    model = mujoco.MjSpec.from_file(path).compile()
    bodies = ph.io.read_mjcf(path)
    assert len(bodies) == model.nbody - 1
    compare_with_mujoco(bodies, model)


@pytest.mark.parametrize("path", gymnasium_models(), ids=os.path.basename)
# MuJoCo's parser warns (once per process) that half_cheetah's settotalmass is deprecated.
@pytest.mark.filterwarnings("ignore:compiler attribute 'settotalmass':UserWarning")
def test_gymnasium_models_against_mujoco(path):
    model = mujoco.MjSpec.from_file(path).compile()
    compare_with_mujoco(ph.io.read_mjcf(path), model)
    if "half_cheetah" in path:
        # settotalmass=14: MuJoCo rescales every mass and inertia by one factor, as read_mjcf
        # does; as written, the file's own masses.
        assert model.body_mass[1:].sum() == pytest.approx(14.0, rel=1e-14)
        written = ph.io.read_mjcf(path, as_written=True)
        factor = model.body_mass[1:].sum() / sum(b.mass for b in written.values())
        assert not factor == pytest.approx(1.0, rel=1e-3)
        compare_with_mujoco(written, model, scale=factor)


ORIENTATIONS = """<mujoco>
  <compiler angle="{angle}" eulerseq="{seq}"/>
  <worldbody>
    <body name="quat"><freejoint/>
      <inertial pos="0.1 -0.2 0.3" quat="0.8 0.1 -0.4 0.3" mass="2" diaginertia="0.3 0.4 0.5"/>
    </body>
    <body name="euler"><freejoint/>
      <inertial pos="0 0 0.1" euler="{e1} {e2} {e3}" mass="1.5" diaginertia="0.2 0.25 0.3"/>
    </body>
    <body name="axisangle"><freejoint/>
      <inertial pos="0 0 0" axisangle="1 2 3 {a}" mass="1" diaginertia="0.1 0.15 0.2"/>
    </body>
    <body name="xyaxes"><freejoint/>
      <inertial pos="0 0 0" xyaxes="1 1 0 -1 1 0.5" mass="1" diaginertia="0.1 0.15 0.2"/>
    </body>
    <body name="zaxis"><freejoint/>
      <inertial pos="0 0 0" zaxis="0.2 -1 0.4" mass="1" diaginertia="0.1 0.12 0.2"/>
    </body>
    <body name="fullinertia"><freejoint/>
      <inertial pos="1 2 3" mass="3" fullinertia="0.5 0.6 0.7 0.05 -0.04 0.03"/>
    </body>
    <body name="mesh" pos="0 0 1"><freejoint/>
      <geom type="mesh" mesh="wedge" pos="0.1 0 0" euler="{e1} 0 0"/>
    </body>
  </worldbody>
  <asset>
    <mesh name="wedge" scale="0.5 1 2" refpos="0.1 0.2 0.3" refquat="0.9 0.1 0.3 -0.2"
          inertia="exact"
          vertex="0 0 0  1 0 0  0 1 0  0 0 1  1 1 1"
          face="0 2 1  0 1 3  0 3 2  1 2 4  1 4 3  2 3 4"/>
  </asset>
</mujoco>
"""


@pytest.mark.parametrize(
    ("angle", "seq", "e", "a"),
    [("degree", "xyz", (20, -35, 50), 70), ("radian", "XYZ", (0.3, -0.6, 0.9), 1.2)],
)
def test_explicit_inertials_in_every_orientation_against_mujoco(tmp_path, angle, seq, e, a):
    path = tmp_path / "orientations.xml"
    path.write_text(ORIENTATIONS.format(angle=angle, seq=seq, e1=e[0], e2=e[1], e3=e[2], a=a))
    model = mujoco.MjSpec.from_file(str(path)).compile()
    bodies = ph.io.read_mjcf(path)
    assert sorted(bodies) == sorted(model.body(i).name for i in range(1, model.nbody))
    compare_with_mujoco(bodies, model, skip=("mesh",))
    # The mesh: MuJoCo diagonalises its inertia with an absolute threshold of 1e-12 on the
    # off-diagonal terms (mju_eig3's eigEPS = 1000 mjMINVAL), so its tensor carries ~4e-11
    # relative error here; trimesh integrates the same moved, turned, scaled wedge to
    # round-off.
    i = model.body("mesh").id
    body = bodies["mesh"]
    errors = relative_errors(
        body, model.body_mass[i], model.body_ipos[i], compiled_tensor(model, i)
    )
    assert max(errors) <= 1e-10
    vertices = np.array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1], float).reshape(-1, 3)
    faces = np.array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 4, 1, 4, 3, 2, 3, 4]).reshape(-1, 3)
    w, x, y, z = 0.9, 0.1, 0.3, -0.2
    ref = Rotation.from_quat([x, y, z, w]).as_matrix()
    vertices = ((vertices - [0.1, 0.2, 0.3]) @ ref) * [0.5, 1.0, 2.0]  # refpos, refquat, scale
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mesh.density = 1000.0
    geom = Rotation.from_euler("xyz" if angle == "degree" else "XYZ", [e[0], 0, 0],
                               degrees=angle == "degree").as_matrix()  # fmt: skip
    com = geom @ mesh.center_mass + [0.1, 0.0, 0.0]
    tensor = geom @ mesh.moment_inertia @ geom.T
    assert max(relative_errors(body, mesh.mass, com, tensor)) <= 64 * EPS


GEOMS = """<mujoco>
  <compiler angle="radian" meshdir="meshes" inertiagrouprange="0 2"/>
  <asset><mesh name="cube" file="cube.stl" scale="0.1 0.2 0.3" inertia="exact"/></asset>
  <worldbody>
    <body name="framed"><freejoint/>
      <frame pos="0.1 0 0" euler="0 0 0.7">
        <frame pos="0 0.2 0" quat="0.9 0.3 0.1 -0.2">
          <geom type="box" size="0.1 0.05 0.02" pos="0 0 0.1" euler="0.2 0.1 0" density="800"/>
        </frame>
        <geom type="ellipsoid" size="0.05 0.1 0.15" pos="0 0 -0.1"/>
      </frame>
    </body>
    <body name="shell"><freejoint/>
      <geom type="sphere" size="0.2" shellinertia="true" density="3"/>
      <geom type="capsule" size="0.02" fromto="0 0 0 0 0 0.5" mass="0"/>
      <geom type="cylinder" size="0.3 0.3" group="3"/>
    </body>
    <body name="stl" pos="1 0 0"><freejoint/>
      <geom type="mesh" mesh="cube" pos="0.05 0 0" quat="0.5 0.5 0.5 0.5" mass="2"/>
    </body>
  </worldbody>
</mujoco>
"""


def write_unit_cube_stl(path):
    """A binary STL of the unit cube [0, 1]^3 (12 triangles, outward)."""
    import struct

    v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    faces = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4), (1, 2, 6),
             (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]  # fmt: skip
    with open(path, "wb") as handle:
        handle.write(b"cube".ljust(80) + struct.pack("<I", len(faces)))
        for f in faces:
            handle.write(struct.pack("<3f", 0, 0, 0))
            for i in f:
                handle.write(struct.pack("<3f", *v[i]))
            handle.write(b"\0\0")


def test_frames_shells_groups_and_mesh_files_against_mujoco(tmp_path):
    # Geoms in nested frames, a spherical shell, a geom of mass 0 and one outside the inertia
    # group range (both left out, as MuJoCo does), a mesh file under the compiler's meshdir.
    (tmp_path / "meshes").mkdir()
    write_unit_cube_stl(tmp_path / "meshes" / "cube.stl")
    path = tmp_path / "geoms.xml"
    path.write_text(GEOMS)
    model = mujoco.MjSpec.from_file(str(path)).compile()
    bodies = ph.io.read_mjcf(path)
    compare_with_mujoco(bodies, model)
    # The shell alone, by its closed form: m = 3 x 4 pi r^2, I = 2/3 m r^2.
    m = 3 * 4 * np.pi * 0.04
    assert max(relative_errors(bodies["shell"], m, [0, 0, 0], np.eye(3) * m * 0.04 * 2 / 3)) < 1e-15


def test_non_convex_mesh_legacy_as_mujoco_and_exact_as_written(tmp_path):
    # An L-shaped prism (non-convex): MuJoCo's default mesh inertia ("legacy") overstates its
    # volume, and read_mjcf gives what MuJoCo simulates; as written, and with "exact", the
    # exact integrals, as trimesh's.
    outline = np.array([(0, 0), (3, 0), (3, 0.5), (0.5, 0.5), (0.5, 3), (0, 3)], float)
    triangles = np.array([(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)])
    prism = trimesh.creation.extrude_triangulation(outline, triangles, 1.0)
    assert prism.is_watertight and prism.volume == pytest.approx(2.75, rel=1e-15)
    stl = tmp_path / "L.stl"
    prism.export(stl)
    xml = (
        '<mujoco><asset><mesh name="L" file="L.stl" inertia="{kind}"/></asset><worldbody>'
        '<body name="b"><freejoint/><geom type="mesh" mesh="L"/></body></worldbody></mujoco>'
    )
    exact = trimesh.load_mesh(stl)
    exact.density = 1000.0
    for kind in ("legacy", "exact"):
        path = tmp_path / f"{kind}.xml"
        path.write_text(xml.format(kind=kind))
        written = ph.io.read_mjcf(path, as_written=True)["b"]
        assert (
            max(relative_errors(written, exact.mass, exact.center_mass, exact.moment_inertia))
            < 1e-14
        )
        model = mujoco.MjSpec.from_file(str(path)).compile()
        # MuJoCo's eigensolver stops at an off-diagonal of 1e-12 (eigEPS): ~1e-10 here.
        compare_with_mujoco(ph.io.read_mjcf(path), model, bound=1e-10)
        if kind == "legacy":
            assert model.body_mass[1] > 1.5 * exact.mass  # MuJoCo's legacy volume: 4.37, not 2.75
            found = ph.io.legacy_mesh_inertia(path)["b"]
            assert found.meshes == ("L",)
            assert found.legacy.mass == pytest.approx(model.body_mass[1], rel=1e-14)
            assert found.exact.mass == pytest.approx(exact.mass, rel=1e-14)
            assert found.mass_error == pytest.approx(model.body_mass[1] / exact.mass - 1, rel=1e-12)
        else:
            assert ph.io.legacy_mesh_inertia(path) == {}


def test_mjcf_density_mass_and_inertiafromgeom(tmp_path):
    xml = """<mujoco><compiler inertiafromgeom="{flag}"/><worldbody>
      <body name="declared"><inertial pos="0 0 0" mass="5" diaginertia="1 1 1"/>
        <geom type="sphere" size="1"/></body>
      <body name="ball"><geom type="sphere" size="0.1" density="500"/></body>
      <body name="brick"><geom type="box" size="0.1 0.2 0.3" mass="7"/></body>
    </worldbody></mujoco>"""
    path = tmp_path / "m.xml"
    path.write_text(xml.format(flag="auto"))
    v_ball, v_brick = 4 / 3 * np.pi * 0.1**3, 0.2 * 0.4 * 0.6
    bodies = ph.io.read_mjcf(path)  # the file's densities and masses
    assert bodies["ball"].mass == pytest.approx(500 * v_ball, rel=1e-15)
    assert bodies["brick"].mass == pytest.approx(7.0, rel=1e-15)
    # one density for the inferred bodies: the file's values replaced, so as written only
    with pytest.raises(ArgumentError) as caught:
        ph.io.read_mjcf(path, density=1000.0)
    assert caught.value.argument == "density"
    bodies = ph.io.read_mjcf(path, density=1000.0, as_written=True)
    assert bodies["declared"].mass == 5.0
    assert bodies["ball"].mass == pytest.approx(1000 * v_ball, rel=1e-15)
    assert bodies["brick"].mass == pytest.approx(1000 * v_brick, rel=1e-15)
    i_brick = 1000 * v_brick / 12 * np.diag([0.16 + 0.36, 0.04 + 0.36, 0.04 + 0.16])
    assert np.allclose(bodies["brick"].inertia, i_brick, rtol=1e-14, atol=0)
    bodies = ph.io.read_mjcf(path, mass=10.0, as_written=True)  # a total shared by volume
    assert bodies["ball"].mass + bodies["brick"].mass == pytest.approx(10.0, rel=1e-15)
    assert bodies["ball"].mass / bodies["brick"].mass == pytest.approx(v_ball / v_brick)
    path.write_text(xml.format(flag="false"))  # MuJoCo infers nothing: massless bodies
    bodies = ph.io.read_mjcf(path)
    assert list(bodies) == ["declared"] and list(bodies.frames) == ["ball", "brick"]
    assert list(ph.io.read_mjcf(path, as_written=True)) == ["declared"]


# --- URDF against its XML, yourdfpy and MuJoCo ------------------------------------------------


def urdf_by_hand(path):
    """{link: (mass, com, tensor in link axes)} from the XML, rpy by scipy (R = Rz Ry Rx)."""
    out = {}
    for link in ET.parse(path).getroot().iter("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        origin = inertial.find("origin")
        xyz = np.array(
            (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split(), float
        )
        rpy = np.array(
            (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split(), float
        )
        r = Rotation.from_euler("xyz", rpy).as_matrix()
        i = inertial.find("inertia")
        v = {k: float(i.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        tensor = np.array(
            [
                [v["ixx"], v["ixy"], v["ixz"]],
                [v["ixy"], v["iyy"], v["iyz"]],
                [v["ixz"], v["iyz"], v["izz"]],
            ]
        )
        out[link.get("name")] = (float(inertial.find("mass").get("value")), xyz, r @ tensor @ r.T)
    return out


def test_upkie_urdf_against_its_xml_and_yourdfpy():
    path = upkie_urdf()
    bodies = ph.io.read_urdf(path)
    expected = urdf_by_hand(path)
    assert list(bodies) == list(expected)  # every link has an inertial, in the file's order
    for name, (m, com, tensor) in expected.items():
        assert max(relative_errors(bodies[name], m, com, tensor)) <= 16 * EPS, name
    model = yourdfpy.URDF.load(path, build_scene_graph=False, load_meshes=False)
    for link in model.robot.links:
        origin = link.inertial.origin
        tensor = origin[:3, :3] @ link.inertial.inertia @ origin[:3, :3].T
        errors = relative_errors(bodies[link.name], link.inertial.mass, origin[:3, 3], tensor)
        assert max(errors) <= 16 * EPS, link.name


def test_upkie_urdf_against_mujoco():
    path = upkie_urdf()
    with open(path) as handle:
        text = handle.read()
    text = text.replace(
        '<robot name="upkie">',
        '<robot name="upkie"><mujoco><compiler fusestatic="false" discardvisual="true"/></mujoco>',
    )
    model = mujoco.MjSpec.from_string(text).compile()
    bodies = ph.io.read_urdf(path)
    assert model.nbody - 1 == len(bodies) == 41
    compare_with_mujoco(bodies, model)


def test_urdf_geometry_with_density_and_mass(tmp_path):
    rpy = (0.3, -0.2, 0.9)
    urdf = f"""<robot name="shapes">
      <link name="box"><collision><origin xyz="0.1 0.2 0.3" rpy="{" ".join(map(str, rpy))}"/>
        <geometry><box size="0.4 0.2 0.1"/></geometry></collision></link>
      <link name="cylinder"><collision><origin xyz="0 0 0.5"/>
        <geometry><cylinder radius="0.05" length="0.3"/></geometry></collision></link>
      <link name="two_spheres">
        <collision><origin xyz="-0.2 0 0"/><geometry><sphere radius="0.1"/></geometry></collision>
        <collision><origin xyz="0.2 0 0"/><geometry><sphere radius="0.1"/></geometry></collision>
      </link>
      <link name="visual_only">
        <visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual>
      </link>
      <link name="frame"/>
    </robot>"""
    path = tmp_path / "shapes.urdf"
    path.write_text(urdf)
    assert ph.io.read_urdf(path) == {}  # no inertials: every link massless
    rho = 1000.0
    bodies = ph.io.read_urdf(path, density=rho)
    assert list(bodies) == ["box", "cylinder", "two_spheres", "visual_only"]
    r = Rotation.from_euler("xyz", rpy).as_matrix()
    m = rho * 0.4 * 0.2 * 0.1
    box = m / 12 * np.diag([0.04 + 0.01, 0.16 + 0.01, 0.16 + 0.04])
    assert max(relative_errors(bodies["box"], m, [0.1, 0.2, 0.3], r @ box @ r.T)) <= 32 * EPS
    m = rho * np.pi * 0.05**2 * 0.3
    cylinder = np.diag([m * (3 * 0.05**2 + 0.09) / 12] * 2 + [m * 0.05**2 / 2])
    assert max(relative_errors(bodies["cylinder"], m, [0, 0, 0.5], cylinder)) <= 32 * EPS
    m1 = rho * 4 / 3 * np.pi * 0.1**3
    spheres = np.diag([2 * 0.4 * m1 * 0.01] * 3) + 2 * m1 * np.diag([0.0, 0.04, 0.04])
    assert max(relative_errors(bodies["two_spheres"], 2 * m1, [0, 0, 0], spheres)) <= 32 * EPS
    assert bodies["visual_only"].mass == pytest.approx(rho * 1e-3, rel=1e-14)
    # A total mass is shared in proportion to the volumes.
    shared = ph.io.read_urdf(path, mass=10.0)
    volumes = {k: b.mass / rho for k, b in bodies.items()}
    total = sum(volumes.values())
    for name, body in shared.items():
        assert body.mass == pytest.approx(10.0 * volumes[name] / total, rel=1e-14)
    # geometry="visual" ignores the collision shapes: only visual_only has a visual.
    assert list(ph.io.read_urdf(path, density=rho, geometry="visual")) == ["visual_only"]


def test_urdf_mesh_geometry_resolved_like_yourdfpy(tmp_path):
    # A mesh given as package://, found by yourdfpy's rules in the folders above the file.
    meshes = tmp_path / "pkg" / "meshes"
    meshes.mkdir(parents=True)
    (tmp_path / "pkg" / "urdf").mkdir()
    cube = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
        float,
    )
    faces = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4], [1, 2, 6],
             [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]  # fmt: skip
    lines = ["OFF", "8 12 0"] + [" ".join(map(str, v)) for v in cube]
    lines += ["3 " + " ".join(map(str, f)) for f in faces]
    (meshes / "cube.off").write_text("\n".join(lines) + "\n")
    urdf = tmp_path / "pkg" / "urdf" / "robot.urdf"
    urdf.write_text(
        '<robot name="r"><link name="cube"><collision><origin xyz="1 0 0"/><geometry>'
        '<mesh filename="package://pkg/meshes/cube.off" scale="0.1 0.2 0.3"/></geometry>'
        "</collision></link></robot>"
    )
    body = ph.io.read_urdf(urdf, density=1000.0)["cube"]
    m = 1000.0 * 0.1 * 0.2 * 0.3
    expected = m / 12 * np.diag([0.04 + 0.09, 0.01 + 0.09, 0.01 + 0.04])
    assert max(relative_errors(body, m, [1.05, 0.1, 0.15], expected)) <= 64 * EPS


# --- round trips: read -> write -> read ------------------------------------------------------


def urdf_of(bodies):
    links = "\n".join(
        f'<link name="{name}">{body.to_urdf_inertial()}</link>' for name, body in bodies.items()
    )
    return f'<robot name="round_trip">\n{links}\n</robot>\n'


def mjcf_of(bodies):
    inner = "\n".join(
        f'<body name="{name}"><freejoint/>{body.to_mjcf()}</body>' for name, body in bodies.items()
    )
    return f"<mujoco><worldbody>\n{inner}\n</worldbody></mujoco>\n"


def random_bodies(seed, count=40):
    """Bodies with random principal second moments c (moments tr(c) - c, physical by
    construction), symmetric tops, flat bodies (on the triangle inequality), principal frames
    at gimbal lock, random centres of mass."""
    rng = np.random.default_rng(seed)
    out = {}
    for k in range(count):
        c = rng.uniform(0.01, 1.0, 3)
        if k % 4 == 1:
            c[1] = c[0]  # a symmetric top
        if k % 4 == 2:
            c[2] = 0.0  # flat: I3 = I1 + I2
        turn = Rotation.random(random_state=rng.integers(1 << 31))
        if k % 8 == 3:  # a principal frame at gimbal lock (pitch = pi/2)
            turn = Rotation.from_euler("xyz", [rng.uniform(-3, 3), np.pi / 2, rng.uniform(-3, 3)])
        mass = float(rng.uniform(0.1, 10))
        body = ph.Body.from_inertia(mass, mass * (c.sum() * np.eye(3) - np.diag(c)))
        out[f"b{k}"] = body.rotated(turn).translated(rng.normal(size=3))
    return out


def round_trip_errors(first, second):
    worst = np.zeros(3)
    for name, body in first.items():
        errors = relative_errors(second[name], body.mass, body.center_of_mass, body.inertia)
        worst = np.maximum(worst, errors)
    return worst


def test_urdf_round_trip_of_random_bodies(tmp_path):
    bodies = random_bodies(1)
    path = tmp_path / "bodies.urdf"
    path.write_text(urdf_of(bodies))
    worst = round_trip_errors(bodies, ph.io.read_urdf(path))
    # The principal decomposition (residual <= 10 eps ||I||) and the rpy angles (to rounding)
    # each cost a few eps.
    assert np.all(worst <= 16 * EPS), worst / EPS


def test_mjcf_round_trip_of_random_bodies(tmp_path):
    bodies = random_bodies(2)
    path = tmp_path / "bodies.xml"
    path.write_text(mjcf_of(bodies))
    worst = round_trip_errors(bodies, ph.io.read_mjcf(path))
    assert np.all(worst <= 16 * EPS), worst / EPS


def test_upkie_read_write_read(tmp_path):
    first = ph.io.read_urdf(upkie_urdf())
    path = tmp_path / "again.urdf"
    path.write_text(urdf_of(first))
    worst = round_trip_errors(first, ph.io.read_urdf(path))
    assert np.all(worst <= 16 * EPS), worst / EPS


@pytest.mark.parametrize(
    "path",
    [mujoco_testdata("model.xml")] + [p for p in gymnasium_models() if "humanoid.xml" in p],
    ids=os.path.basename,
)
def test_mjcf_read_write_read_and_mujoco_agrees(tmp_path, path):
    first = ph.io.read_mjcf(path)
    again = tmp_path / "again.xml"
    again.write_text(mjcf_of(first))
    worst = round_trip_errors(first, ph.io.read_mjcf(again))
    assert np.all(worst <= 16 * EPS), worst / EPS
    # MuJoCo compiles the written inertials to what it infers from the original geoms.
    compare_with_mujoco(first, mujoco.MjSpec.from_file(str(again)).compile())


# --- audit -----------------------------------------------------------------------------------

URDF_EXPECTED = {
    "good_box": [("ok", "ok")],
    "plate_rounded": [("error", "triangle_inequality")],
    "not_positive_definite": [("error", "positive_definite")],
    "negative_mass": [("error", "mass")],
    "swapped_products": [("warning", "products_swapped")],
    "products_sign": [("warning", "products_sign")],
    "missing_parallel_axis": [("warning", "parallel_axis")],
    "about_origin": [("warning", "about_origin")],
    "far_origin": [("warning", "origin_far")],
    "point_mass": [("info", "point_mass")],  # a root: fixed to the world, or fused
    "needle": [("warning", "small_moment")],
    "massless_frame": [("info", "frame")],
}


def findings_by_link(findings):
    out = {}
    for f in findings:
        out.setdefault(f.link, []).append((f.severity, f.check))
    return out


def test_audit_of_the_urdf_fixture():
    findings = ph.io.audit(BROKEN_URDF)
    assert findings_by_link(findings) == URDF_EXPECTED
    swapped = next(f for f in findings if f.link == "swapped_products")
    assert "ixz is written as iyz" in swapped.message


def test_the_urdf_fixture_is_what_it_says():
    # Independently of polhode: each broken tensor is the textbook one with its mistake.
    links = {link.get("name"): link for link in ET.parse(BROKEN_URDF).getroot().iter("link")}

    def box(m, a, b, c):
        return m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])

    declared = urdf_by_hand(BROKEN_URDF)
    m, _, tensor = declared["swapped_products"]
    col = links["swapped_products"].find("collision/origin")
    r = Rotation.from_euler("xyz", np.array(col.get("rpy").split(), float)).as_matrix()
    true = r @ box(m, 0.3, 0.1, 0.05) @ r.T
    assert np.isclose(tensor[0, 2], true[1, 2], rtol=1e-15) and tensor[1, 2] == true[0, 2]
    m, _, tensor = declared["plate_rounded"]
    assert m == pytest.approx(7850 * 0.39 * 0.15 * 0.002, rel=1e-4)  # a steel plate
    exact = np.diag(box(m, 0.39, 0.15, 0.002))
    assert exact[0] + exact[1] >= exact[2]
    assert np.diag(tensor) == pytest.approx(exact, rel=5e-3)  # 3 significant digits
    assert tensor[0, 0] + tensor[1, 1] < tensor[2, 2]
    m, com, tensor = declared["missing_parallel_axis"]
    assert np.allclose(tensor, 2 * box(1.0, 0.1, 0.1, 0.1), rtol=1e-15, atol=0)


def test_audit_corrected_inertials_are_the_geometry():
    findings = {f.link: f for f in ph.io.audit(BROKEN_URDF) if f.corrected}
    for name, expected in [
        (
            "missing_parallel_axis",
            (2.0, [0.15, 0, 0], np.diag([1 / 300, 1 / 300 + 0.045, 1 / 300 + 0.045])),
        ),
        ("far_origin", (1.0, [0, 0, 0], np.eye(3) / 600)),
    ]:
        path_text = f'<robot name="r"><link name="{name}">{findings[name].corrected}</link></robot>'
        body = ph.io.read_urdf(_write(path_text))[name]
        # Rounded to six significant digits of each scale: half a unit of the sixth digit is at
        # most 5e-6 of the mass, the size, and the largest moment.
        assert max(relative_errors(body, *expected)) <= 5e-6, name
    # A link whose mass is unusable gets a correction only from a density.
    assert "negative_mass" not in findings
    with_density = {f.link: f for f in ph.io.audit(BROKEN_URDF, density=1000.0) if f.corrected}
    text = with_density["negative_mass"].corrected
    body = ph.io.read_urdf(_write(f'<robot name="r"><link name="n">{text}</link></robot>'))["n"]
    assert body.mass == pytest.approx(1.0, rel=1e-14)  # 1000 kg/m^3 x (0.1 m)^3


def _write(text, suffix=".urdf"):
    import tempfile

    handle = tempfile.NamedTemporaryFile("w", suffix=suffix, delete=False)
    with handle:
        handle.write(text)
    return handle.name


def test_audit_of_the_mjcf_fixture():
    assert findings_by_link(ph.io.audit(BROKEN_MJCF)) == {
        "good_box": [("ok", "ok")],
        "triangle": [("error", "triangle_inequality")],
        "not_positive_definite": [("error", "positive_definite")],
        "negative_mass": [("error", "mass")],
        "swapped_products": [("warning", "products_swapped")],
        "inferred": [("info", "no_inertial")],
    }
    # MuJoCo's compiler refuses the fixture (the reason the audit exists).
    with pytest.raises(ValueError, match="inertia|mass"):
        mujoco.MjSpec.from_file(BROKEN_MJCF).compile()


@pytest.mark.parametrize(
    "inertial",
    ['fullinertia="1 1 1 nan 0 0"', 'diaginertia="nan 1 1"', 'diaginertia="inf 1 1"'],
    ids=["nan-product", "nan-moment", "inf-moment"],
)
def test_audit_of_a_tensor_that_is_not_finite(inertial):
    """A NaN product passed every check (each comparison with NaN is False) and the verdict
    was 'ok, consistent'; a NaN or inf moment raised numpy's LinAlgError. Now an error
    finding; the readers refuse such a file."""
    path = _write(
        f'<mujoco><worldbody><body name="a"><inertial pos="0 0 0" mass="1" {inertial}/>'
        "</body></worldbody></mujoco>",
        ".xml",
    )
    assert findings_by_link(ph.io.audit(path)) == {"a": [("error", "non_finite")]}
    with pytest.raises(FileFormatError):
        ph.io.read_mjcf(path)


def test_moments_near_the_largest_double_are_read_as_declared():
    """(t + t^T) / 2 overflowed at 1e308: the file's moments were refused as inf, and the
    audit's triangle test overflowed its sum."""
    path = _write(
        '<mujoco><worldbody><body name="a"><inertial pos="0 0 0" mass="1" '
        'diaginertia="1e308 1e308 1e308"/></body></worldbody></mujoco>',
        ".xml",
    )
    np.testing.assert_array_equal(ph.io.read_mjcf(path)["a"].inertia, 1e308 * np.eye(3))
    assert findings_by_link(ph.io.audit(path)) == {"a": [("ok", "ok")]}


def test_an_unnamed_body_beside_one_named_like_it():
    """An unnamed body is "body K"; one named "body 1" took its key and the unnamed body was
    lost without a word. Against MuJoCo's masses (4 pi/3 0.1^3 and 0.2^3 at density 1000)."""
    path = _write(
        '<mujoco><worldbody><body><geom type="sphere" size="0.1"/></body>'
        '<body name="body 1"><geom type="sphere" size="0.2"/></body></worldbody></mujoco>',
        ".xml",
    )
    bodies = ph.io.read_mjcf(path)
    model = mujoco.MjModel.from_xml_path(path)
    assert list(bodies) == ["body 1 (unnamed)", "body 1"]
    assert bodies["body 1 (unnamed)"].mass == pytest.approx(model.body_mass[1], rel=1e-14)
    assert bodies["body 1"].mass == pytest.approx(model.body_mass[2], rel=1e-14)


@pytest.mark.parametrize(
    ("text", "suffix", "field", "fragment"),
    [
        (
            '<mujoco><worldbody><body name="a"><geom type="sphere" size="-0.1"/></body>'
            "</worldbody></mujoco>",
            ".xml",
            "geom[0].size",
            "sphere's sizes to be positive and finite, got [-0.1]",
        ),
        (
            '<mujoco><worldbody><body name="a"><geom type="box" size="0.1 0 0.1"/></body>'
            "</worldbody></mujoco>",
            ".xml",
            "geom[0].size",
            "box's sizes to be positive and finite",
        ),
        (
            '<mujoco><worldbody><body name="a"><geom type="sphere" size="1e200"/></body>'
            "</worldbody></mujoco>",
            ".xml",
            "geom[0].size",
            "volume at sizes [1e+200] is beyond double precision",
        ),
        (
            '<robot name="r"><link name="a"><collision><geometry><cylinder radius="1" '
            'length="-1"/></geometry></collision></link></robot>',
            ".urdf",
            "collision[0].geometry",
            "cylinder's sizes to be positive and finite, got [1.0, -1.0]",
        ),
    ],
    ids=["mjcf-negative-sphere", "mjcf-flat-box", "mjcf-huge-sphere", "urdf-negative-cylinder"],
)
def test_bad_geometry_sizes_are_named(text, suffix, field, fragment):
    """Were 'Expected `mass` to be positive, got -0.00419' (the volume passed as a mass), or
    a numpy warning and a mass of inf."""
    path = _write(text, suffix)
    if suffix == ".xml":
        with pytest.raises(FileFormatError) as error:
            ph.io.read_mjcf(path, density=1000.0, as_written=True)
    else:
        with pytest.raises(FileFormatError) as error:
            ph.io.read_urdf(path, density=1000.0, strict=True)
        # Read whole, the link is left out, named with the field in the file's one warning.
        with pytest.warns(RobotFileWarning) as caught:
            links = ph.io.read_urdf(path, density=1000.0)
        assert len(caught) == 1 and caught[0].message.links == links.left_out
        assert list(links) == [] and links.left_out["a"].startswith(field + ": ")
        assert fragment in links.left_out["a"]
    assert fragment in str(error.value) and error.value.field == field
    assert "`mass`" not in str(error.value)


@pytest.mark.parametrize(
    "body",
    [
        '<geom type="box" size=".1 .1 .1" pos="nan 0 0"/>',
        '<frame pos="nan 0 0"><geom type="box" size=".1 .1 .1"/></frame>',
    ],
    ids=["geom", "frame"],
)
def test_a_position_that_is_not_finite_names_the_body_and_geom(body):
    """Was "Expected `offset[0]` to be finite": an internal argument, no file or body."""
    path = _write(f'<mujoco><worldbody><body name="a">{body}</body></worldbody></mujoco>', ".xml")
    with pytest.raises(FileFormatError, match="expected a finite position") as error:
        ph.io.read_mjcf(path)
    assert error.value.link == "a" and error.value.field == "geom[0].pos"


@pytest.mark.parametrize(
    ("text", "link", "field"),
    [
        (
            '<robot name="r"><link name="a"><inertial><origin xyz="1,2,3"/><mass value="1"/>'
            '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>',
            "a",
            "inertial.origin.xyz",
        ),
        ('<robot><link name="a"/></robot>', None, "robot.name"),
    ],
    ids=["commas", "no-robot-name"],
)
def test_urdf_the_checker_refuses_what_yourdfpy_cannot_read(text, link, field):
    """Numbers with commas passed the checker and a robot without a name was not checked:
    yourdfpy then failed ("could not convert string to float", KeyError: 'name') and the
    error had neither the link nor the field. strict=True raises naming them; read whole,
    the link is left out (the commas), or the file read with a warning (no robot name)."""
    path = _write(text)
    with pytest.raises(FileFormatError) as error:
        ph.io.read_urdf(path, strict=True)
    assert error.value.link == link and error.value.field == field
    with pytest.warns(RobotFileWarning, match=field.replace(".", r"\.") if link else "no name"):
        links = ph.io.read_urdf(path)
    if link is not None:
        assert links.left_out[link].startswith(field + ": ") and link not in links
    else:
        assert links.left_out == {} and links.frames == {"a": "no <inertial>: the root"}


def test_audit_of_upkie():
    # The collision shapes are primitives and the inertials their textbook formulas: all agree
    # but the femurs and tibias, whose ixx = iyy = 5.17e-6 is that of a 0.026 m cylinder while
    # their collision cylinder is 0.26 m long (m (3 r^2 + L^2) / 12 with m = 0.056, r = 0.012);
    # the virtual links are point masses.
    findings = ph.io.audit(upkie_urdf())
    by_link = findings_by_link(findings)
    assert len(by_link) == 41 and not any(s == "error" for f in by_link.values() for s, _ in f)
    mismatched = sorted(k for k, v in by_link.items() if ("warning", "geometry") in v)
    assert mismatched == ["left_femur", "left_tibia", "right_femur", "right_tibia"]
    m, r = 0.056, 0.012
    declared = urdf_by_hand(upkie_urdf())["left_femur"][2]
    assert declared[0, 0] == pytest.approx(m * (3 * r * r + 0.026**2) / 12, rel=1e-12)
    assert declared[2, 2] == pytest.approx(m * r * r / 2, rel=1e-12)
    femur = ET.parse(upkie_urdf()).getroot().find("link[@name='left_femur']")
    assert float(femur.find("collision/geometry/cylinder").get("length")) == 0.26
    # Point masses on fixed joints and as the root: harmless once fused (info).
    points = sorted(k for k, v in by_link.items() if ("info", "point_mass") in v)
    assert len(points) == 8 and "base" in points
    assert sum(v == [("ok", "ok")] for v in by_link.values()) == 29


@pytest.mark.parametrize("path", gymnasium_models()[:3], ids=os.path.basename)
def test_audit_of_models_without_inertials(path):
    findings = ph.io.audit(path)
    assert {(f.severity, f.check) for f in findings} == {("info", "no_inertial")}


# --- broken files ----------------------------------------------------------------------------

GOOD_INERTIAL = (
    '<inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="1"/>'
    '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>'
)


@pytest.mark.parametrize(
    ("inner", "link", "field"),
    [
        ('<link name="a"><inertial><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/>'
         "</inertial></link>", "a", "inertial.mass"),
        ('<link name="a"><inertial><mass value="heavy"/><inertia ixx="1" ixy="0" ixz="0" '
         'iyy="1" iyz="0" izz="1"/></inertial></link>', "a", "inertial.mass"),
        ('<link name="a"><inertial><mass value="1"/><inertia ixy="0" ixz="0" iyy="1" iyz="0" '
         'izz="1"/></inertial></link>', "a", "inertial.inertia.ixx"),
        ('<link name="a"><inertial><mass value="1"/></inertial></link>', "a", "inertial.inertia"),
        ('<link name="a"><inertial><origin rpy="0 1"/><mass value="1"/><inertia ixx="1" '
         'ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>', "a", "inertial.origin.rpy"),
        ('<link name="a"><inertial><mass value="nan"/><inertia ixx="1" ixy="0" ixz="0" '
         'iyy="1" iyz="0" izz="1"/></inertial></link>', "a", "inertial.mass"),
        (f'<link name="a">{GOOD_INERTIAL}</link><link name="a">{GOOD_INERTIAL}</link>', "a",
         "link.name"),
        ('<link name="b"><collision><geometry><box/></geometry></collision></link>', "b",
         "collision[0].geometry.box.size"),
        ('<link name="b"><visual><geometry/></visual></link>', "b", "visual[0].geometry"),
        # Values that parse but are not an inertial: raised by the reader, found by audit.
        ('<link name="c"><inertial><mass value="-1"/><inertia ixx="1" ixy="0" ixz="0" '
         'iyy="1" iyz="0" izz="1"/></inertial></link>', "c", "inertial.mass"),
        ('<link name="c"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" '
         'iyy="1" iyz="0" izz="3"/></inertial></link>', "c", "inertial.inertia"),
    ],
)  # fmt: skip
def test_broken_urdf_names_the_file_link_and_field(tmp_path, inner, link, field):
    path = tmp_path / "broken.urdf"
    path.write_text(f'<robot name="r">{inner}</robot>')
    with pytest.raises(FileFormatError) as caught:
        ph.io.read_urdf(path, strict=True)
    error = caught.value
    assert (error.path, error.link, error.field) == (str(path), link, field)
    assert str(path) in str(error) and f"'{link}'" in str(error) and field in str(error)
    if field == "link.name":  # two links of one name: not a robot description
        with pytest.raises(FileFormatError):
            ph.io.read_urdf(path)
        return
    # Read whole: the link is left out, named with its field in the file's one warning (a
    # geometry that cannot be read matters only where the geometry is used).
    used = field.startswith(("collision", "visual"))
    with pytest.warns(RobotFileWarning) as warned:
        links = ph.io.read_urdf(path, density=1.0 if used else None)
    assert len(warned) == 1 and str(path) in str(warned[0].message)
    assert warned[0].message.links == links.left_out
    assert link not in links and links.left_out[link].startswith(field + ": ")


def test_urdf_missing_mesh_with_density(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r"><link name="m"><collision><geometry><mesh filename="nowhere.stl"/>'
        "</geometry></collision></link></robot>"
    )
    assert ph.io.read_urdf(path) == {}  # without density the geometry is not read
    with pytest.raises(FileFormatError) as caught:
        ph.io.read_urdf(path, density=1.0, strict=True)
    assert caught.value.link == "m" and caught.value.field == "collision[0].geometry.mesh.filename"
    with pytest.warns(RobotFileWarning, match="nowhere.stl"):
        links = ph.io.read_urdf(path, density=1.0)
    assert links == {} and links.left_out["m"].startswith("collision[0].geometry.mesh.filename")
    # The audit: a massless link, and a geometry it cannot compute.
    findings = ph.io.audit(path)
    assert [(f.severity, f.check) for f in findings] == [
        ("warning", "geometry_error"),  # a missing file: warning, once for the link
        ("info", "frame"),  # the root
    ]
    assert "nowhere.stl" in findings[0].message


@pytest.mark.parametrize(
    ("text", "match"),
    [("not xml at all", "not valid XML"), ("<mujoco/>", "expected a <robot>")],
)
def test_urdf_not_a_urdf(tmp_path, text, match):
    path = tmp_path / "x.urdf"
    path.write_text(text)
    with pytest.raises(FileFormatError, match=match) as caught:
        ph.io.read_urdf(path)
    assert caught.value.path == str(path)


@pytest.mark.parametrize(
    ("body", "link", "field"),
    [
        ('<body name="q"><inertial pos="0 0 0" quat="1 0 0 0" mass="1" fullinertia="1 1 1 0 0 0"/>'
         "</body>", "q", "inertial"),
        ('<body name="z"><inertial pos="0 0 0" quat="0 0 0 0" mass="1" diaginertia="1 1 1"/>'
         "</body>", "z", "inertial"),
        ('<body name="t"><inertial pos="0 0 0" mass="1" diaginertia="1 1 3"/></body>', "t",
         "inertial.diaginertia"),
        ('<body name="n"><inertial pos="0 0 0" mass="-1" diaginertia="1 1 1"/></body>', "n",
         "inertial.mass"),
        ('<body name="g"><geom type="box" size="0.1 -0.1 0.1"/></body>', "g", "geom[0].size"),
        ('<body name="h"><geom type="mesh" mesh="gone"/></body>', None, None),
        ('<body name="f"><geom type="box" mesh="m"/></body></worldbody><asset><mesh name="m" '
         'vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset><worldbody>', "f", "geom[0].mesh"),
    ],
)  # fmt: skip
@pytest.mark.parametrize("mode", ["as_written", "strict"])
def test_broken_mjcf_names_the_file_body_and_field(tmp_path, body, link, field, mode):
    """As written, every one raises; as MuJoCo compiles it, with strict=True, every one but
    the box fitted to a mesh (which MuJoCo compiles, and polhode reads)."""
    path = tmp_path / "broken.xml"
    path.write_text(f"<mujoco><worldbody>\n{body}\n</worldbody></mujoco>")
    if mode == "strict" and link == "f":
        assert ph.io.read_mjcf(path, strict=True)["f"].mass > 0
        return
    with pytest.raises(FileFormatError) as caught:
        ph.io.read_mjcf(path, **{mode: True})
    error = caught.value
    assert error.path == str(path) and str(path) in str(error)
    if link is not None:
        assert error.link == link and f"'{link}'" in str(error)
    if field is not None:
        assert error.field == field


@pytest.mark.parametrize(
    ("body", "name", "field", "fragment"),
    [
        ('<body name="t"><joint/><inertial pos="0 0 0" mass="1" diaginertia="1 1 3"/></body>',
         "t", "inertial.diaginertia", "triangle inequality"),
        ('<body name="g"><joint/><geom type="box" size="0.1 -0.1 0.1"/></body>', "g",
         "geom[0].size", "size 1 must be positive"),
        ('<body name="h"><joint/><geom type="mesh" mesh="gone"/></body>', "h", "geom[0].mesh",
         "no mesh asset named 'gone'"),
        ('<body name="m"><joint/></body>', "m", "inertial", "mjMINVAL"),
    ],
)  # fmt: skip
def test_bodies_mujoco_refuses_are_left_out_and_named(tmp_path, body, name, field, fragment):
    """Each refused by MuJoCo's compiler (checked); read_mjcf reads the rest of the file and
    names the body, the field and the reason in a RobotFileWarning."""
    path = tmp_path / "refused.xml"
    good = '<body name="ok"><joint/><geom type="sphere" size="0.1"/></body>'
    path.write_text(f"<mujoco><worldbody>{good}{body}</worldbody></mujoco>")
    with pytest.raises(ValueError):
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.warns(ph.RobotFileWarning) as caught:
        bodies = ph.io.read_mjcf(path)
    assert list(bodies) == ["ok"] and bodies.frames == {}
    assert list(bodies.left_out) == [name] and bodies.left_out[name].startswith(field)
    assert fragment in bodies.left_out[name]
    warning = caught[0].message
    assert warning.path == str(path) and list(warning.links) == [name]
    assert fragment in str(warning) and f"'{name}'" in str(warning)


def test_missing_robot_files(tmp_path):
    for read in (ph.io.read_urdf, ph.io.read_mjcf, ph.io.audit):
        with pytest.raises(FileNotFoundError):
            read(tmp_path / "nothing.xml")


@pytest.mark.parametrize(
    ("kwargs", "argument"),
    [({"density": 1.0, "mass": 1.0}, "mass"), ({"geometry": "both"}, "geometry")],
)
def test_bad_reader_arguments(kwargs, argument):
    with pytest.raises(ArgumentError) as caught:
        ph.io.read_urdf(BROKEN_URDF, **kwargs)
    assert caught.value.argument == argument


# --- the command line ------------------------------------------------------------------------


def run_cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "polhode", "audit", *args],
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_cli_audit_exit_status_and_table():
    result = run_cli(BROKEN_URDF)
    assert result.returncode == 1, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0].split() == ["link", "severity", "check", "message"]
    assert any(
        line.split()[:3] == ["plate_rounded", "error", "triangle_inequality"] for line in lines
    )
    assert "corrected inertial of swapped_products" in result.stdout
    assert "<inertia ixx=" in result.stdout
    assert "12 links: 3 errors, 6 warnings" in result.stdout
    ok = run_cli(upkie_urdf())
    assert ok.returncode == 0, ok.stderr
    assert "41 links: 0 errors, 4 warnings" in ok.stdout
    # The femurs' and tibias' tensors differ from their cylinders by 0.98: within --rtol 2.
    loose = run_cli(upkie_urdf(), "--rtol", "2")
    assert "41 links: 0 errors, 0 warnings" in loose.stdout


@pytest.mark.parametrize("name", ["missing.urdf", "not_xml.urdf"])
def test_cli_audit_bad_file(tmp_path, name):
    path = tmp_path / name
    if name == "not_xml.urdf":
        path.write_text("{}")
    result = run_cli(str(path))
    assert result.returncode == 2
    assert str(path) in result.stderr and "Traceback" not in result.stderr
