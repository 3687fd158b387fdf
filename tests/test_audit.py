"""polhode.io.audit as an engineer needs it: severities that match the simulators, one finding
per link and check, the causes it names on deliberately broken files, and corrected inertials
rounded to the digits that matter.

References: MuJoCo's compiler (which links it refuses, one file per case); the closed form of a
box, I = m/12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2), turned as R I R^T; each broken file is the
good one with its mistake applied here, independently of polhode.
"""

from __future__ import annotations

import re
import sys
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
import polhode.io
from polhode.io._links import Note

pytest.importorskip("yourdfpy")

SIZE = (0.3, 0.1, 0.05)
TURN = (0.3, -0.5, 0.7)  # the collision box's rpy


def box_tensor(m, size=SIZE, rpy=TURN):
    a, b, c = size
    r = Rotation.from_euler("xyz", rpy).as_matrix()  # URDF rpy: fixed axes x, y, z
    return r @ (m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])) @ r.T


def inertial_xml(m, tensor, xyz=(0.0, 0.0, 0.0)):
    t = tensor
    six = dict(ixx=t[0, 0], ixy=t[0, 1], ixz=t[0, 2], iyy=t[1, 1], iyz=t[1, 2], izz=t[2, 2])
    attrs = " ".join(f'{k}="{float(v)!r}"' for k, v in six.items())
    x = " ".join(repr(float(v)) for v in xyz)
    return f'<inertial><origin xyz="{x}"/><mass value="{float(m)!r}"/><inertia {attrs}/></inertial>'


def collision(xyz=(0.0, 0.0, 0.0), size=SIZE, rpy=TURN):
    return (
        f'<collision><origin xyz="{" ".join(map(repr, xyz))}" rpy="{" ".join(map(repr, rpy))}"/>'
        f'<geometry><box size="{" ".join(map(repr, size))}"/></geometry></collision>'
    )


def robot(links, joints=""):
    """A root 'base' (a frame) and each link on its own revolute joint to it."""
    body = '<link name="base"/>'
    for name, inner in links.items():
        body += f'<link name="{name}">{inner}</link>'
        if f'child link="{name}"' not in joints:
            body += (
                f'<joint name="j_{name}" type="revolute"><parent link="base"/>'
                f'<child link="{name}"/><axis xyz="0 0 1"/>'
                '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
            )
    return f'<robot name="r">{body}{joints}</robot>'


def write(tmp_path, text, name="r.urdf"):
    path = tmp_path / name
    path.write_text(text)
    return path


def by_link(findings):
    out = {}
    for f in findings:
        out.setdefault(f.link, []).append((f.severity, f.check))
    return out


# --- causes on deliberately broken files -----------------------------------------------------

M = 1.2
COM = (0.05, 0.02, -0.01)
GOOD = box_tensor(M)


def swapped(t):
    out = t.copy()
    out[0, 2], out[1, 2] = t[1, 2], t[0, 2]
    out[2, 0], out[2, 1] = out[0, 2], out[1, 2]
    return out


def sign_flipped(t):
    return 2 * np.diag(np.diag(t)) - t


def mirrored_y(t):
    s = np.diag([1.0, -1.0, 1.0])
    return s @ t @ s  # ixy and iyz change sign


def about_origin(t):
    c = np.array(COM)
    return t + M * (c @ c * np.eye(3) - np.outer(c, c))


BROKEN = {
    # name: (mass, tensor, expected check)
    "good": (M, GOOD, "ok"),
    "swapped": (M, swapped(GOOD), "products_swapped"),
    "sign": (M, sign_flipped(box_tensor(M, (0.2, 0.15, 0.1), (0.3, -0.5, 0.7))), "products_sign"),
    "mirrored": (M, mirrored_y(GOOD), "mirrored"),
    "origin": (M, about_origin(GOOD), "about_origin"),
    "grams": (1000 * M, GOOD, "units"),  # the mass in grams, the tensor in kg m^2
    "grams_both": (1000 * M, 1000 * GOOD, "units"),  # mass and tensor in grams
    "tensor_grams": (M, 1000 * GOOD, "units"),  # the tensor in g m^2
    "millimetres": (M, 1e6 * GOOD, "units"),  # the tensor in kg mm^2
}


def test_each_cause_is_named_on_a_deliberately_broken_file(tmp_path):
    links = {
        name: inertial_xml(m, t, COM) + collision(COM) for name, (m, t, _) in BROKEN.items()
    }
    links["sign"] = inertial_xml(*BROKEN["sign"][:2], COM) + collision(COM, (0.2, 0.15, 0.1))
    # Flipped products can make a tensor impossible: an error, its cause named.
    links["impossible"] = inertial_xml(M, sign_flipped(GOOD), COM) + collision(COM)
    findings = ph.io.audit(write(tmp_path, robot(links)))
    found = by_link(findings)
    assert found.pop("base") == [("info", "frame")]
    for name, (_, _, check) in BROKEN.items():
        severity = "ok" if check == "ok" else "warning"
        assert found[name] == [(severity, check)], name
    assert found.pop("impossible") == [("error", "triangle_inequality")]
    messages = {f.link: f.message for f in findings}
    assert "The cause (products_sign)" in messages["impossible"]
    assert "ixz is written as iyz, iyz is written as ixz" in messages["swapped"]
    assert "xz plane (ixy and iyz of the wrong sign)" in messages["mirrored"]
    assert "the mass is in grams" in messages["grams"]
    assert "mass and the tensor are in grams" in messages["grams_both"]
    assert "g m^2" in messages["tensor_grams"] and "kg mm^2" in messages["millimetres"]
    # The corrected inertial of a mass in grams is at the mass in kilograms.
    corrected = {f.link: f.corrected for f in findings}
    assert re.search(r'<mass value="1\.2"/>', corrected["grams"])


def test_a_mesh_in_millimetres_without_its_scale(tmp_path):
    # A 300 x 100 x 50 mm box drawn in millimetres, referenced without scale="0.001": the
    # declared inertial is the real part's (kg, m).
    a, b, c = (300.0, 100.0, 50.0)
    v = np.array([[x, y, z] for z in (0, c) for y in (0, b) for x in (0, a)])
    v = v - [a / 2, b / 2, c / 2]
    faces = [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
             [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]]  # fmt: skip
    lines = ["OFF", "8 12 0"] + [" ".join(map(str, p)) for p in v]
    lines += [f"3 {i} {j} {k}" for i, j, k in faces]
    (tmp_path / "box.off").write_text("\n".join(lines) + "\n")
    tensor = box_tensor(M, rpy=(0, 0, 0))
    link = inertial_xml(M, tensor) + (
        '<collision><geometry><mesh filename="box.off"/></geometry></collision>'
    )
    path = write(tmp_path, robot({"part": link}))
    findings = {f.check: f for f in ph.io.audit(path) if f.link == "part"}
    assert list(findings) == ["units"], findings
    assert 'without scale="0.001"' in findings["units"].message
    # With the scale, the same file agrees.
    fixed = path.read_text().replace('filename="box.off"', 'filename="box.off" scale="0.001"')
    path.write_text(fixed)
    assert [f.check for f in ph.io.audit(path) if f.link == "part"] == ["ok"]


def test_parts_without_their_parallel_axis_terms(tmp_path):
    one = box_tensor(1.0, (0.1, 0.1, 0.1), (0, 0, 0))
    link = inertial_xml(2.0, 2 * one, (0.15, 0, 0)) + collision(
        (0.0, 0, 0), (0.1, 0.1, 0.1), (0, 0, 0)
    ) + collision((0.3, 0, 0), (0.1, 0.1, 0.1), (0, 0, 0))
    findings = ph.io.audit(write(tmp_path, robot({"pair": link})))
    assert by_link(findings)["pair"] == [("warning", "parallel_axis")]


# --- severities against the simulators --------------------------------------------------------

FIXED = '<joint name="f_{0}" type="fixed"><parent link="{1}"/><child link="{0}"/>{2}</joint>'


CASES = {
    # name: (links, joints, expected findings of the link `x`, MuJoCo compiles)
    "moving without inertial": ({"x": ""}, "", [("error", "no_inertial")], False),
    "moving, mass 0": ({"x": inertial_xml(0.0, np.zeros((3, 3)))}, "", [("error", "mass")],
                       False),
    "moving, mass on a fixed link": (
        {"x": "", "y": inertial_xml(1.0, box_tensor(1.0))},
        FIXED.format("y", "x", ""),
        [("info", "no_inertial")],
        True,
    ),
    "moving point mass": ({"x": inertial_xml(1.0, np.zeros((3, 3)))}, "",
                          [("error", "moving_part")], False),
    "moving rod": ({"x": inertial_xml(1.0, np.diag([0.0, 0.1, 0.1]))}, "",
                   [("error", "moving_part")], False),
    "moving point mass, inertia from a fixed link": (
        {"x": inertial_xml(1.0, np.zeros((3, 3))), "y": inertial_xml(1.0, box_tensor(1.0))},
        FIXED.format("y", "x", '<origin xyz="0.1 0 0"/>'),
        [("info", "point_mass")],
        True,
    ),
    "fixed massless": ({"x": "", "y": inertial_xml(1.0, box_tensor(1.0))},
                       FIXED.format("x", "y", ""), [("info", "frame")], True),
    "fixed point mass": ({"y": inertial_xml(1.0, box_tensor(1.0)),
                          "x": inertial_xml(0.1, np.zeros((3, 3)))},
                         FIXED.format("x", "y", '<origin xyz="0.1 0 0"/>'),
                         [("info", "point_mass")], True),
    "triangle inequality on a fixed link": (
        {"y": inertial_xml(1.0, box_tensor(1.0)), "x": inertial_xml(1.0, np.diag([1, 1, 3.0]))},
        FIXED.format("x", "y", ""),
        [("error", "triangle_inequality")],
        False,
    ),
    "not positive definite": ({"x": inertial_xml(1.0, np.diag([-0.1, 1, 1.0]))}, "",
                              [("error", "positive_definite")], False),
    "a needle": ({"x": inertial_xml(1.0, np.diag([1e-9, 0.1, 0.1]))}, "",
                 [("warning", "small_moment")], True),
}  # fmt: skip


@pytest.mark.parametrize("case", list(CASES), ids=lambda c: c.replace(" ", "-"))
def test_errors_are_what_mujoco_refuses(tmp_path, case):
    links, joints, expected, compiles = CASES[case]
    text = robot(links, joints)
    findings = by_link(ph.io.audit(write(tmp_path, text)))
    assert findings["x"] == expected
    others = [s for name, f in findings.items() if name != "x" for s, _ in f]
    assert "error" not in others
    # MuJoCo (its URDF importer: fixed links fused, the root fixed to the world) refuses the
    # model exactly where the audit says error.
    mujoco = pytest.importorskip("mujoco")
    if compiles:
        mujoco.MjModel.from_xml_string(text)
    else:
        with pytest.raises(ValueError, match="mass|inertia|eigenvalues|A \\+ B"):
            mujoco.MjModel.from_xml_string(text)
    assert (expected[0][0] == "error") == (not compiles)


# --- one finding per link and check; partial geometry ----------------------------------------


def test_one_finding_per_link_and_a_note_on_partial_geometry(tmp_path):
    meshes = "".join(
        f'<collision><geometry><mesh filename="missing_{k}.stl"/></geometry></collision>'
        for k in range(5)
    )
    tensor = box_tensor(M, rpy=(0, 0, 0))
    link = inertial_xml(M, 10 * tensor) + collision(rpy=(0, 0, 0)) + meshes
    findings = [f for f in ph.io.audit(write(tmp_path, robot({"arm": link}))) if f.link == "arm"]
    checks = [(f.severity, f.check) for f in findings]
    assert checks == [("warning", "geometry_error"), ("info", "geometry")]
    error, geometry = findings
    assert "5 of 6 geometry parts cannot be computed" in error.message
    assert "(and 2 more)" in error.message and "uses the other 1 only" in error.message
    assert "compared with 1 of 6 geometry parts only" in geometry.message
    assert geometry.corrected is None  # a part of the geometry is not the link's


def test_a_readers_notes_are_findings(tmp_path, monkeypatch):
    """The hook for what only a format's reader knows (MJCF: how MuJoCo's compiler changes a
    body's inertial): Link.notes become findings of their own."""
    path = write(
        tmp_path,
        '<mujoco><worldbody><body name="a"><freejoint/><inertial pos="0 0 0" mass="1" '
        'diaginertia="1 1 1"/></body></worldbody></mujoco>',
        "m.xml",
    )
    audit_module = sys.modules["polhode.io.audit"]  # polhode.io.audit is the function
    original = audit_module.mjcf_links

    def with_a_note(p):
        links, infer = original(p)
        links[0].notes.append(Note("warning", "legacy_inertia", "MuJoCo's legacy: +32 %."))
        return links, infer

    monkeypatch.setattr(audit_module, "mjcf_links", with_a_note)
    assert by_link(ph.io.audit(path)) == {"a": [("warning", "legacy_inertia")]}


# --- corrected inertials ----------------------------------------------------------------------


def test_corrected_inertials_have_the_digits_that_matter(tmp_path):
    # A thin plate (I1 + I2 = I3 within round-off), turned, declared with a swapped tensor; a
    # cube whose geometric centre is a round-off 1e-20 off the link origin.
    plate = (0.39, 0.15, 0.002)
    links = {
        "plate": inertial_xml(0.9185, swapped(box_tensor(0.9185, plate)))
        + collision(size=plate),
        "cube": inertial_xml(1.0, 10 * box_tensor(1.0, (0.1, 0.1, 0.1), (0, 0, 0)))
        + collision((1e-20, -3e-19, 0.0), (0.1, 0.1, 0.1), (0, 0, 0)),
    }
    path = write(tmp_path, robot(links))
    corrected = {f.link: f.corrected for f in ph.io.audit(path) if f.corrected}
    for name, text in corrected.items():
        numbers = re.findall(r'"([^"]+)"', text)
        for word in " ".join(numbers).split():
            mantissa = word.split("e")[0].lstrip("-").replace(".", "").lstrip("0")
            assert len(mantissa) <= 7, (name, word)  # six significant digits (and a sign)
        assert not re.search(r"e-(1[6-9]|2\d)", text), text
    assert 'xyz="0 0 0"' in corrected["cube"]
    # Read back, the plate's rounded moments are still a valid inertia (I1 + I2 >= I3).
    back = write(tmp_path, f'<robot name="b"><link name="p">{corrected["plate"]}</link></robot>',
                 "back.urdf")  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        body = ph.io.read_urdf(back)["p"]
    expected = box_tensor(0.9185, plate)
    assert np.linalg.norm(body.inertia - expected) <= 5e-6 * np.linalg.norm(expected)


def test_an_mjcf_body_whose_geoms_cannot_be_computed_is_not_called_massless(tmp_path):
    # MuJoCo infers the inertial from the geoms; polhode cannot compute a missing mesh, so the
    # body's mass is unknown here: a note, not an error (dm-control's meshes gave 390 of them).
    path = write(
        tmp_path,
        '<mujoco><asset><mesh name="m" file="gone.stl"/></asset><worldbody><body name="a">'
        '<freejoint/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>',
        "m.xml",
    )
    findings = by_link(ph.io.audit(path))
    assert findings == {"a": [("warning", "geometry_error"), ("info", "no_inertial")]}


def test_a_double_hyphen_in_a_comment_is_read(tmp_path):
    # Not well-formed XML, but read by tinyxml2 (MuJoCo, ROS's urdfdom): read here too.
    text = robot({"arm": inertial_xml(M, GOOD)}).replace(
        '<link name="base"/>', '<link name="base"/><!-- a -- comment -->'
    )
    path = write(tmp_path, text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert list(ph.io.read_urdf(path)) == ["arm"]
    truncated = write(tmp_path, text[:-20], "truncated.urdf")
    with pytest.raises(ph.FileFormatError, match="not valid XML"):
        ph.io.read_urdf(truncated)
