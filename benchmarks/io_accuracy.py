"""Accuracy of polhode.io on files no one here wrote, and of its round trips.

python -m benchmarks.io_accuracy

Prints, in units of eps = 2.2e-16 (relative errors: mass; centre of mass against the body's
radius of gyration plus its distance from the origin; tensor in the Frobenius norm):

- read_mjcf against MuJoCo's compiled body_mass/body_ipos/body_iquat/body_inertia, for the
  models MuJoCo ships (testdata/model.xml) and gymnasium's MuJoCo models (every installed
  MJCF corpus: benchmarks/io_mjcf_vs_mujoco.py);
- read_urdf of upkie_description's URDF against its XML read by hand (rpy by scipy), yourdfpy's
  values and MuJoCo's compile of the URDF;
- round trips read -> write (to_urdf_inertial / to_mjcf) -> read, on random bodies and on the
  real files;
- spatial inertia -> from_spatial_inertia, about the centre of mass and about the origin;
- the audit of upkie (collision and visual geometry), of gymnasium's models and of the fixtures
  in tests/data.

Needs the test extra (mujoco, yourdfpy, trimesh, upkie_description, gymnasium).
"""

from __future__ import annotations

import collections
import glob
import importlib.util
import os
import xml.etree.ElementTree as ET

import numpy as np
from scipy.spatial.transform import Rotation

import polhode as ph

EPS = np.finfo(float).eps
HERE = os.path.dirname(os.path.abspath(__file__))


def errors(body, mass, com, tensor):
    size = np.sqrt(max(np.trace(tensor), 0.0) / mass)
    tiny = np.finfo(float).tiny
    return np.array(
        [
            abs(body.mass - mass) / mass,
            np.linalg.norm(body.center_of_mass - com) / max(size + np.linalg.norm(com), tiny),
            np.linalg.norm(body.inertia - tensor) / max(np.linalg.norm(tensor), tiny),
        ]
    )


def against_mujoco(bodies, model, scale=1.0):
    worst = np.zeros(3)
    for i in range(1, model.nbody):
        if model.body_mass[i] == 0:
            continue
        w, x, y, z = model.body_iquat[i]
        r = Rotation.from_quat([x, y, z, w]).as_matrix()
        tensor = r @ np.diag(model.body_inertia[i]) @ r.T / scale
        name = model.body(i).name or f"body {i}"
        worst = np.maximum(
            worst, errors(bodies[name], model.body_mass[i] / scale, model.body_ipos[i], tensor)
        )
    return worst


def show(label, worst):
    e = np.asarray(worst) / EPS
    print(f"  {label:44s} mass {e[0]:6.2f}  com {e[1]:6.2f}  tensor {e[2]:6.2f}  (eps)")


def round_trip(first, read, text):
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "again.xml")
        with open(path, "w") as handle:
            handle.write(text)
        second = read(path)
    worst = np.zeros(3)
    for name, body in first.items():
        worst = np.maximum(
            worst, errors(second[name], body.mass, body.center_of_mass, body.inertia)
        )
    return worst


def urdf_of(bodies):
    links = "".join(f'<link name="{k}">{b.to_urdf_inertial()}</link>' for k, b in bodies.items())
    return f'<robot name="r">{links}</robot>'


def mjcf_of(bodies):
    inner = "".join(f'<body name="{k}"><freejoint/>{b.to_mjcf()}</body>' for k, b in bodies.items())
    return f"<mujoco><worldbody>{inner}</worldbody></mujoco>"


def random_bodies(seed, count=1000):
    rng = np.random.default_rng(seed)
    out = {}
    for k in range(count):
        c = rng.uniform(0.01, 1.0, 3)
        if k % 4 == 1:
            c[1] = c[0]
        if k % 4 == 2:
            c[2] = 0.0
        turn = Rotation.random(random_state=rng.integers(1 << 31))
        if k % 8 == 3:
            turn = Rotation.from_euler("xyz", [rng.uniform(-3, 3), np.pi / 2, rng.uniform(-3, 3)])
        m = float(rng.uniform(0.1, 10))
        body = ph.Body.from_inertia(m, m * (c.sum() * np.eye(3) - np.diag(c)))
        out[f"b{k}"] = body.rotated(turn).translated(rng.normal(size=3))
    return out


def main() -> None:
    import mujoco
    import upkie_description
    import yourdfpy

    testdata = os.path.join(os.path.dirname(mujoco.__file__), "testdata", "model.xml")
    spec = importlib.util.find_spec("gymnasium")
    assert spec is not None and spec.submodule_search_locations
    gym = sorted(
        glob.glob(
            os.path.join(spec.submodule_search_locations[0], "envs", "mujoco", "assets", "*.xml")
        )
    )
    print("read_mjcf against MuJoCo's compiled inertials (worst body of each model):")
    import warnings

    for path in [testdata, *gym]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # half_cheetah's settotalmass
            model = mujoco.MjSpec.from_file(path).compile()
            bodies = ph.io.read_mjcf(path)
        show(f"{os.path.basename(path)} ({len(bodies)} bodies)", against_mujoco(bodies, model))

    urdf = upkie_description.URDF_PATH
    bodies = ph.io.read_urdf(urdf)
    print(f"read_urdf of upkie_description ({len(bodies)} links):")
    worst_xml, worst_yourdfpy = np.zeros(3), np.zeros(3)
    for link in ET.parse(urdf).getroot().iter("link"):
        inertial = link.find("inertial")
        origin = inertial.find("origin")
        r = Rotation.from_euler("xyz", np.array(origin.get("rpy").split(), float)).as_matrix()
        i = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
        t = np.array(
            [
                [i["ixx"], i["ixy"], i["ixz"]],
                [i["ixy"], i["iyy"], i["iyz"]],
                [i["ixz"], i["iyz"], i["izz"]],
            ]
        )
        xyz = np.array(origin.get("xyz").split(), float)
        m = float(inertial.find("mass").get("value"))
        worst_xml = np.maximum(worst_xml, errors(bodies[link.get("name")], m, xyz, r @ t @ r.T))
    for link in yourdfpy.URDF.load(urdf, build_scene_graph=False, load_meshes=False).robot.links:
        o = link.inertial.origin
        worst_yourdfpy = np.maximum(
            worst_yourdfpy,
            errors(
                bodies[link.name],
                link.inertial.mass,
                o[:3, 3],
                o[:3, :3] @ link.inertial.inertia @ o[:3, :3].T,
            ),
        )
    with open(urdf) as handle:
        text = handle.read().replace(
            '<robot name="upkie">',
            '<robot name="upkie"><mujoco><compiler fusestatic="false" discardvisual="true"/>'
            "</mujoco>",
        )
    show("against its XML (rpy by scipy)", worst_xml)
    show("against yourdfpy's values", worst_yourdfpy)
    show(
        "against MuJoCo's compile of the URDF",
        against_mujoco(bodies, mujoco.MjSpec.from_string(text).compile()),
    )

    print("round trips read -> write -> read:")
    rnd = random_bodies(1)
    show("1000 random bodies, to_urdf_inertial", round_trip(rnd, ph.io.read_urdf, urdf_of(rnd)))
    show("1000 random bodies, to_mjcf", round_trip(rnd, ph.io.read_mjcf, mjcf_of(rnd)))
    show("upkie, to_urdf_inertial", round_trip(bodies, ph.io.read_urdf, urdf_of(bodies)))
    for path in [testdata] + [p for p in gym if p.endswith("humanoid.xml")]:
        first = ph.io.read_mjcf(path)
        show(
            f"{os.path.basename(path)}, to_mjcf", round_trip(first, ph.io.read_mjcf, mjcf_of(first))
        )
    worst_c, worst_o = np.zeros(3), np.zeros(3)
    for body in rnd.values():
        for point, acc in ((body.center_of_mass, "c"), (None, "o")):
            s = body.spatial_inertia(point, convention="pinocchio")
            again = ph.Body.from_spatial_inertia(s, point, convention="pinocchio")
            e = errors(again, body.mass, body.center_of_mass, body.inertia)
            if acc == "c":
                worst_c = np.maximum(worst_c, e)
            else:
                worst_o = np.maximum(worst_o, e)
    show("spatial inertia, about the centre of mass", worst_c)
    show("spatial inertia, about the origin (|c| ~ 1.6)", worst_o)

    print("audit (findings by severity and check):")
    data = os.path.join(HERE, "..", "tests", "data")
    for label, path, geometry in [
        ("upkie, collision geometry", urdf, "collision"),
        ("upkie, visual meshes", urdf, "visual"),
        (
            "tests/data/broken_inertials.urdf",
            os.path.join(data, "broken_inertials.urdf"),
            "collision",
        ),
        (
            "tests/data/broken_inertials.xml",
            os.path.join(data, "broken_inertials.xml"),
            "collision",
        ),
    ] + [(os.path.basename(p), p, "collision") for p in [testdata, *gym[:1]]]:
        findings = ph.io.audit(path, geometry=geometry)
        counts = collections.Counter(f"{f.severity}:{f.check}" for f in findings)
        links = len({f.link for f in findings})
        print(
            f"  {label} ({links} links): "
            + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
        )


if __name__ == "__main__":
    main()
