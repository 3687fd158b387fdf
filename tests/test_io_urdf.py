"""URDF read whole (frames, links left out and named, strict) and merge_fixed (one body per
moving part).

References, none of them polhode: the composition of fixed joints and the parallel-axis sums
done by hand in mpmath at 40 digits, from the same decimal strings the files hold; MuJoCo's
compiled model of upkie_description's and cookie_description's URDFs (MuJoCo's URDF importer
fuses every link on a fixed joint into its parent: fusestatic); the closed forms of boxes.
"""

from __future__ import annotations

import os
import pickle
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.errors import FileFormatError, RobotFileWarning

mpmath = pytest.importorskip("mpmath")
pytest.importorskip("yourdfpy")

EPS = np.finfo(float).eps

INERTIA = '<inertia ixx="{}" ixy="{}" ixz="{}" iyy="{}" iyz="{}" izz="{}"/>'


def inertial(mass, moments=(0.02, 0.02, 0.01), xyz="0 0 0", rpy="0 0 0", products=(0, 0, 0)):
    ixx, iyy, izz = moments
    ixy, ixz, iyz = products
    return (
        f'<inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>'
        + INERTIA.format(ixx, ixy, ixz, iyy, iyz, izz)
        + "</inertial>"
    )


def joint(name, kind, parent, child, xyz="0 0 0", rpy="0 0 0"):
    extra = '<axis xyz="0 0 1"/>' if kind != "fixed" else ""
    if kind in ("revolute", "prismatic"):
        extra += '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/>{extra}</joint>'
    )


def write(tmp_path, body, name="robot.urdf", robot='name="r"'):
    path = tmp_path / name
    path.write_text(f"<robot {robot}>{body}</robot>")
    return path


def read_quietly(path, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotFileWarning)
        return ph.io.read_urdf(path, **kwargs)


def mujoco_urdfs():
    out = []
    for module in ("upkie_description", "cookie_description"):
        try:
            package = __import__(module)
        except ImportError:
            continue
        folder = os.path.dirname(package.__file__)
        for root, _, files in os.walk(folder):
            out += [os.path.join(root, f) for f in sorted(files) if f.endswith(".urdf")]
    return sorted(out)


# --- read whole ------------------------------------------------------------------------------

WHOLE = (
    '<link name="base"/>'  # the root, no inertial: a frame
    + f'<link name="arm">{inertial(2.0)}</link>'
    + '<link name="tool0"/>'  # fixed, no inertial: a frame
    + f'<link name="plate">{inertial(1.0, (1.0, 1.0, 3.0))}</link>'  # triangle inequality
    + f'<link name="ghost">{inertial(-1.0)}</link>'  # negative mass on a fixed joint
    + '<link name="idle"/>'  # moving, no inertial, nothing fixed to it: refused
    + '<link name="carrier"/>'  # moving, no inertial, a massive link fixed to it: a frame
    + f'<link name="payload">{inertial(0.5, xyz="0 0 0.1")}</link>'
    + f'<link name="pointlike">{inertial(0.1, (0, 0, 0))}</link>'  # a point mass, fixed
    + f'<link name="flange">{inertial(0.0, (0, 0, 0))}</link>'  # mass 0 on a fixed joint
    + joint("shoulder", "revolute", "base", "arm")
    + joint("tool", "fixed", "arm", "tool0", "0 0 0.3")
    + joint("plate_joint", "revolute", "arm", "plate")
    + joint("ghost_joint", "fixed", "arm", "ghost")
    + joint("idle_joint", "continuous", "arm", "idle")
    + joint("carrier_joint", "prismatic", "arm", "carrier")
    + joint("payload_joint", "fixed", "carrier", "payload", "0.1 0 0")
    + joint("point_joint", "fixed", "arm", "pointlike", "0 0.2 0")
    + joint("flange_joint", "fixed", "tool0", "flange")
)


def test_a_robot_is_read_whole_and_what_is_not_read_is_named(tmp_path):
    path = write(tmp_path, WHOLE)
    with pytest.warns(RobotFileWarning) as caught:
        links = ph.io.read_urdf(path)
    assert len(caught) == 1
    warning = caught[0].message
    assert warning.path == str(path) and str(path) in str(warning)
    assert list(links) == ["arm", "payload", "pointlike"]
    assert set(links.frames) == {"base", "tool0", "carrier", "flange"}
    assert links.frames["base"] == "no <inertial>: the root"
    assert links.frames["tool0"] == "no <inertial>: on a fixed joint to 'arm'"
    assert links.frames["flange"] == "mass 0: on a fixed joint to 'tool0'"
    assert "'payload'" in links.frames["carrier"]
    assert list(links.left_out) == ["plate", "ghost", "idle"]  # the file's order
    assert warning.links == links.left_out
    assert links.left_out["plate"].startswith("inertial.inertia: ")
    assert "triangle inequality" in links.left_out["plate"]
    assert links.left_out["ghost"].startswith("inertial.mass: ") and "negative" in str(warning)
    assert links.left_out["idle"].startswith("inertial: a moving link without mass")
    assert "mjMINVAL" in links.left_out["idle"]
    for name in links.left_out:
        assert f"'{name}'" in str(warning)
    # The point mass is one: mass 0.1 at the link origin, no inertia.
    assert links["pointlike"].mass == 0.1 and not np.any(links["pointlike"].inertia)
    assert links.merged == {}
    # strict=True raises the first, naming the file, the link and the field.
    with pytest.raises(FileFormatError) as error:
        ph.io.read_urdf(path, strict=True)
    assert (error.value.path, error.value.link, error.value.field) == (
        str(path),
        "plate",
        "inertial.inertia",
    )
    # The result is a dict; what it says about the rest pickles with it.
    assert isinstance(links, dict) and links == dict(links)
    empty = ph.io.read_urdf(write(tmp_path, '<link name="a"/>', "empty.urdf"))
    again = pickle.loads(pickle.dumps(empty))
    assert again == {} and again.frames == empty.frames and again.path == empty.path


def test_warnings_can_be_errors(tmp_path):
    path = write(tmp_path, WHOLE)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ph.PolhodeWarning)
        with pytest.raises(RobotFileWarning):
            ph.io.read_urdf(path)


def test_a_file_with_nothing_left_out_warns_nothing(tmp_path):
    path = write(tmp_path, f'<link name="a">{inertial(1.0)}</link><link name="b"/>'
                 + joint("j", "fixed", "a", "b"))  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        links = ph.io.read_urdf(path)
    assert list(links) == ["a"] and links.frames == {"b": "no <inertial>: on a fixed joint to 'a'"}


def test_two_inertials_are_an_error_naming_the_link_and_field(tmp_path):
    """A link with two <inertial> elements once silently took one."""
    path = write(tmp_path, f'<link name="arm">{inertial(1.0)}{inertial(2.0)}</link>')
    with pytest.raises(FileFormatError, match=r"2 <inertial> elements") as error:
        ph.io.read_urdf(path, strict=True)
    assert (error.value.link, error.value.field) == ("arm", "inertial")
    with pytest.warns(RobotFileWarning, match="arm"):
        links = ph.io.read_urdf(path)
    assert "arm" not in links and links.left_out["arm"].startswith("inertial: 2 <inertial>")


def test_an_inertial_without_an_inertia_is_left_out(tmp_path):
    # As airo-models' camera links write it: a mass, no tensor (MuJoCo and urdfdom refuse the
    # file; a point mass would be a guess).
    path = write(
        tmp_path,
        '<link name="base_link"/><link name="camera"><inertial><mass value="0.072"/>'
        "</inertial></link>" + joint("mount", "fixed", "base_link", "camera"),
    )
    with pytest.warns(RobotFileWarning, match="has no <inertia>"):
        links = ph.io.read_urdf(path)
    assert links == {} and links.left_out["camera"].startswith("inertial.inertia: ")


def test_undeclared_drake_prefixes_are_read(tmp_path):
    # Drake's extensions without xmlns:drake (invalid namespaces, well-formed XML): yourdfpy
    # and MuJoCo read such files, and so does polhode, with nothing to warn about.
    path = write(
        tmp_path,
        f'<link name="a">{inertial(1.0)}</link><link name="b">{inertial(1.0)}</link>'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<limit drake:acceleration="2.5" effort="1" lower="-1" upper="1" velocity="1"/></joint>'
        '<drake:collision_filter_group name="g"><drake:member link="a"/>'
        "</drake:collision_filter_group>",
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert list(ph.io.read_urdf(path)) == ["a", "b"]
        assert [f.severity for f in ph.io.audit(path)] == ["ok", "ok"]
    (path.parent / "bad.urdf").write_text('<robot name="r"><link name="a"></robot>')
    with pytest.raises(FileFormatError, match="not valid XML"):
        ph.io.read_urdf(path.parent / "bad.urdf")


def test_a_robot_without_a_name_is_read_with_a_warning(tmp_path):
    path = write(tmp_path, f'<link name="a">{inertial(1.0)}</link>', robot="")
    with pytest.warns(RobotFileWarning, match="no name") as caught:
        links = ph.io.read_urdf(path)
    assert list(links) == ["a"] and caught[0].message.links == {}
    with pytest.raises(FileFormatError) as error:
        ph.io.read_urdf(path, strict=True)
    assert error.value.field == "robot.name"


@pytest.mark.parametrize(
    ("joints", "field", "match"),
    [
        (joint("j", "fixed", "a", "nowhere"), "child.link", "no <link> is named 'nowhere'"),
        (joint("j", "fixed", "a", "b") + joint("k", "fixed", "a", "b"), "child.link",
         "already the child of 'j'"),
        (joint("j", "fixed", "a", "b") + joint("k", "fixed", "b", "a"), "parent.link", "cycle"),
        ('<joint name="j" type="fixed"><child link="b"/></joint>', "parent.link", "no <parent"),
    ],
    ids=["unknown-link", "two-parents", "cycle", "no-parent"],
)  # fmt: skip
def test_joints_that_make_no_tree_refuse_the_file(tmp_path, joints, field, match):
    path = write(tmp_path, f'<link name="a">{inertial(1.0)}</link><link name="b"/>' + joints)
    with pytest.raises(FileFormatError, match=match) as error:
        ph.io.read_urdf(path)
    assert error.value.field == field and "joint '" in str(error.value)


# --- merge_fixed against a composition by hand in mpmath -------------------------------------


def mp_rpy(rpy):
    """Rz(y) Ry(p) Rx(r) in mpmath."""
    r, p, y = rpy
    rx = mpmath.matrix([[1, 0, 0], [0, mpmath.cos(r), -mpmath.sin(r)], [0, mpmath.sin(r),
                        mpmath.cos(r)]])  # fmt: skip
    ry = mpmath.matrix([[mpmath.cos(p), 0, mpmath.sin(p)], [0, 1, 0], [-mpmath.sin(p), 0,
                        mpmath.cos(p)]])  # fmt: skip
    rz = mpmath.matrix([[mpmath.cos(y), -mpmath.sin(y), 0], [mpmath.sin(y), mpmath.cos(y), 0],
                        [0, 0, 1]])  # fmt: skip
    return rz * ry * rx


def random_tree(rng, count):
    """Links with random inertials (as decimal strings), each on a joint to an earlier link:
    fixed mostly, a few moving. Returns (xml, links {name: (mass, com, rpy, tensor) strings},
    joints {child: (parent, kind, xyz, rpy)})."""
    def fmt(x):
        return repr(float(x))

    links, joints, xml = {}, {}, []
    for k in range(count):
        name = f"l{k}"
        c = rng.uniform(0.01, 1.0, 3)  # principal second moments: always physical
        m = rng.uniform(0.1, 5.0)
        tensor = m * (c.sum() * np.eye(3) - np.diag(c))
        turn = Rotation.random(random_state=rng.integers(1 << 31)).as_matrix()
        tensor = turn @ tensor @ turn.T
        six = [tensor[0, 0], tensor[0, 1], tensor[0, 2], tensor[1, 1], tensor[1, 2], tensor[2, 2]]
        com = rng.normal(scale=0.2, size=3)
        rpy = rng.uniform(-3, 3, 3)
        entry = (fmt(m), [fmt(x) for x in com], [fmt(x) for x in rpy], [fmt(x) for x in six])
        links[name] = entry
        xml.append(
            f'<link name="{name}"><inertial><origin xyz="{" ".join(entry[1])}" '
            f'rpy="{" ".join(entry[2])}"/><mass value="{entry[0]}"/>'
            + INERTIA.format(*entry[3])
            + "</inertial></link>"
        )
        if k > 0:
            parent = f"l{rng.integers(0, k)}"
            kind = "revolute" if k % 5 == 0 else "fixed"
            xyz = [fmt(x) for x in rng.normal(scale=0.3, size=3)]
            jrpy = [fmt(x) for x in rng.uniform(-3, 3, 3)]
            joints[name] = (parent, kind, xyz, jrpy)
            xml.append(joint(f"j{k}", kind, parent, name, " ".join(xyz), " ".join(jrpy)))
    return "".join(xml), links, joints


def mp_parts(links, joints):
    """{part: (mass, com, tensor)} composed by hand in mpmath from the decimal strings."""
    mpf = mpmath.mpf

    def vec(strings):
        return mpmath.matrix([mpf(s) for s in strings])

    def placement(name):  # (R, p) of the link's frame in its part's first link's frame
        if name not in joints or joints[name][1] != "fixed":
            return name, mpmath.eye(3), mpmath.matrix([0, 0, 0])
        parent, _, xyz, rpy = joints[name]
        root, r1, p1 = placement(parent)
        r2, p2 = mp_rpy([mpf(s) for s in rpy]), vec(xyz)
        return root, r1 * r2, r1 * p2 + p1

    parts = {}
    for name, (m, com, rpy, six) in links.items():
        root, r, p = placement(name)
        ixx, ixy, ixz, iyy, iyz, izz = (mpf(s) for s in six)
        tensor = mpmath.matrix([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        ri = mp_rpy([mpf(s) for s in rpy])
        tensor = r * (ri * tensor * ri.T) * r.T  # into the link's axes, then the part's
        parts.setdefault(root, []).append((mpf(m), r * vec(com) + p, tensor))
    out = {}
    for root, items in parts.items():
        total = sum(m for m, _, _ in items)
        c = sum((m * x for m, x, _ in items), mpmath.matrix([0, 0, 0])) / total
        tensor = mpmath.zeros(3, 3)
        for m, x, t in items:
            d = x - c
            tensor += t + m * ((d.T * d)[0] * mpmath.eye(3) - d * d.T)
        out[root] = (total, c, tensor)
    return out


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_merge_fixed_against_a_composition_by_hand(tmp_path, seed):
    mpmath.mp.dps = 40
    rng = np.random.default_rng(seed)
    xml, links, joints = random_tree(rng, 24)
    path = write(tmp_path, xml)
    parts = ph.io.read_urdf(path, merge_fixed=True)
    expected = mp_parts(links, joints)
    assert list(parts) == list(expected)
    assert set(parts.merged) == {n for n, j in joints.items() if j[1] == "fixed"}
    for name, (m, c, t) in expected.items():
        body = parts[name]
        tensor = np.array(t.tolist(), dtype=float)
        size = float(mpmath.sqrt(sum(t[i, i] for i in range(3)) / m))
        assert abs(body.mass - float(m)) <= 8 * EPS * body.mass, name
        com = np.array(c.tolist(), dtype=float).ravel()
        assert np.linalg.norm(body.center_of_mass - com) <= 64 * EPS * (size + np.linalg.norm(com))
        # The sums of rotated tensors and parallel-axis terms, each a few eps of the largest.
        assert np.linalg.norm(body.inertia - tensor) <= 64 * EPS * np.linalg.norm(tensor), name
        # ... and with merge_fixed=False each link is in its own frame: the first link of each
        # part is the same body either way.
    single = ph.io.read_urdf(path)
    for name in expected:
        if not any(parent == name for parent, kind, _, _ in joints.values() if kind == "fixed"):
            assert np.array_equal(single[name].inertia, parts[name].inertia)


def strings_of(path):
    """(links, joints) of a URDF file as random_tree gives them: the decimal strings."""
    from lxml import etree

    links, joints = {}, {}
    for link in etree.parse(str(path)).getroot().findall("link"):
        i = link.find("inertial")
        o = i.find("origin")
        t = i.find("inertia")
        links[link.get("name")] = (
            i.find("mass").get("value"),
            (o.get("xyz") or "0 0 0").split(),
            (o.get("rpy") or "0 0 0").split(),
            [t.get(k) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")],
        )
    for j in etree.parse(str(path)).getroot().findall("joint"):
        o = j.find("origin")
        xyz = (o.get("xyz") if o is not None else None) or "0 0 0"
        rpy = (o.get("rpy") if o is not None else None) or "0 0 0"
        joints[j.find("child").get("link")] = (
            j.find("parent").get("link"),
            j.get("type"),
            xyz.split(),
            rpy.split(),
        )
    return links, joints


@pytest.mark.parametrize("path", mujoco_urdfs(), ids=os.path.basename)
def test_merge_fixed_of_real_robots_against_a_composition_by_hand(path):
    mpmath.mp.dps = 40
    links, joints = strings_of(path)
    parts = read_quietly(path, merge_fixed=True)
    expected = mp_parts(links, joints)
    assert list(parts) == list(expected)
    for name, (m, c, t) in expected.items():
        body = parts[name]
        tensor = np.array(t.tolist(), dtype=float)
        assert abs(body.mass - float(m)) <= 8 * EPS * body.mass, name
        com = np.array(c.tolist(), dtype=float).ravel()
        size = float(mpmath.sqrt(sum(t[i, i] for i in range(3)) / m))
        assert np.linalg.norm(body.center_of_mass - com) <= 64 * EPS * (size + np.linalg.norm(com))
        assert np.linalg.norm(body.inertia - tensor) <= 64 * EPS * np.linalg.norm(tensor), name
        moments = sorted(float(x) for x in mpmath.eigsy(t)[0])
        np.testing.assert_allclose(body.principal().moments, moments, rtol=8 * EPS, atol=0)


def test_merge_fixed_keeps_the_root_and_the_massless(tmp_path):
    # world (massless root) - fixed - base (2 kg box) - revolute - arm (1 kg) - fixed - tool0
    # (massless) - fixed - camera (0.3 kg point mass 0.1 m out).
    body = (
        '<link name="world"/>'
        + f'<link name="base">{inertial(2.0)}</link>'
        + f'<link name="arm">{inertial(1.0, xyz="0 0 0.2")}</link>'
        + '<link name="tool0"/>'
        + f'<link name="camera">{inertial(0.3, (0, 0, 0))}</link>'
        + joint("anchor", "fixed", "world", "base", "0 0 0.5")
        + joint("shoulder", "revolute", "base", "arm", "0 0 0.1")
        + joint("flange", "fixed", "arm", "tool0", "0 0 0.4", "0 1.5707963267948966 0")
        + joint("cam", "fixed", "tool0", "camera", "0 0 0.1")
    )
    parts = ph.io.read_urdf(write(tmp_path, body), merge_fixed=True)
    assert list(parts) == ["world", "arm"]
    assert parts.merged == {"base": "world", "tool0": "arm", "camera": "arm"}
    assert set(parts.frames) == {"world", "tool0"}
    # The root's part is base's box, 0.5 above the world frame.
    assert parts["world"].mass == 2.0
    np.testing.assert_allclose(parts["world"].center_of_mass, [0, 0, 0.5], atol=1e-16)
    # arm: 1 kg at z = 0.2, the camera at tool0's z axis (turned to arm's x) 0.1 beyond z = 0.4:
    # (0.1, 0, 0.4) in arm's frame.
    arm = parts["arm"]
    assert arm.mass == pytest.approx(1.3, rel=1e-15)
    np.testing.assert_allclose(
        arm.center_of_mass, [(0.3 * 0.1) / 1.3, 0, (1.0 * 0.2 + 0.3 * 0.4) / 1.3], rtol=1e-15
    )


# --- merge_fixed against MuJoCo's fused bodies -----------------------------------------------


@pytest.mark.parametrize("path", mujoco_urdfs(), ids=os.path.basename)
def test_merge_fixed_against_mujocos_fused_bodies(path):
    """MuJoCo's URDF importer fuses every link on a fixed joint into its parent (and the root's
    part into the world, so that it has no body there). Its bodies are then polhode's parts,
    to MuJoCo's own accuracy: its principal moments are within 80 eps of the 40-digit
    composition by hand on these files (polhode's within 2, the test above), and its tensor
    within ~1.5e-6 of the spread of the moments (its Jacobi sweeps stop at a rotation of
    1.4e-6 rad)."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(path)
    parts = read_quietly(path, merge_fixed=True)
    assert model.nbody - 1 == len(parts) - 1  # the root's part is fused into the world
    for i in range(1, model.nbody):
        name = model.body(i).name
        body = parts[name]
        w, x, y, z = model.body_iquat[i]
        r = Rotation.from_quat([x, y, z, w]).as_matrix()
        tensor = r @ np.diag(model.body_inertia[i]) @ r.T
        mass = model.body_mass[i]
        size = np.sqrt(np.trace(tensor) / mass)
        assert abs(body.mass - mass) <= 8 * EPS * mass, name
        assert np.linalg.norm(body.center_of_mass - model.body_ipos[i]) <= 64 * EPS * size
        moments = np.sort(model.body_inertia[i])
        np.testing.assert_allclose(body.principal().moments, moments, rtol=128 * EPS, atol=0)
        spread = moments[-1] - moments[0]
        assert np.linalg.norm(body.inertia - tensor) <= 1.5e-6 * spread + 64 * EPS * moments[-1]
