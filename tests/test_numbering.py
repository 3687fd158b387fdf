"""One numbering of the principal axes wherever a person reads: 1, 2, 3 in ascending order of
moment (I1 <= I2 <= I3), x, y, z for the coordinates of a frame that is not principal, Python
indices only as indexing expressions or ``axis=`` (docs/architecture.md, Conventions).

The scan reads what a person reads: the help of every command, the reports of ``polhode
spin`` (principal moments, a body, rotors), ``polhode inertia`` (a mesh, a robot description,
a molecule), ``polhode audit`` and the demo, the headers of every CSV the command line writes,
the errors about axes, and the documentation's pages (docs/*.md, docs/guide/*.md). It looks for
the old numberings: an axis, a moment or a column numbered 0 in words ("axis 0", "(0)",
"moment_0"), ``omega1`` without its underscore, rotors counted from 0, omega in principal axes
labelled x, y, z.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest

import polhode as ph
from polhode.cli import main

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

#: The old numberings: (pattern, what it is).
OLD = [
    (r"\b(?:axis|axes|moments?|columns?|principal axis)\s+0(?![.\d])", "an axis numbered 0"),
    (r"\b(?:axis|axes|moment)\s*\(\s*\d\s*\)", "an axis numbered in parentheses"),
    (r"\(0\)\s*\(1\)\s*\(2\)", "axes (0)(1)(2)"),
    (r"\bomega[123]\b", "omega1 without its underscore"),
    (r"\b(?:moment|axis|omega)_0\b", "a column numbered from 0"),
    (r"\bnumbered 0\b", "a numbering from 0"),
    (r"\bI0\b", "a moment I0"),
    (r"(?<!--)\b(?:wheel|damper) ?0(?![.\d])", "a rotor counted from 0"),
]


def old_numberings(text: str) -> list[str]:
    """Each old numbering found in ``text``, with the line it is on."""
    found = []
    for line in text.splitlines():
        for pattern, what in OLD:
            match = re.search(pattern, line)
            if match:
                found.append(f"{what}: {match.group(0)!r} in {line.strip()!r}")
    return found


def test_the_scan_finds_the_old_numberings():
    """What the scan looks for, as it was written before (the conventions page, the polhode
    plot's labels, the frames CSV, the perturbation guide)."""
    for old in (
        "- **Axes are numbered 0, 1, 2** (the index into the ascending moments)",
        "L, smallest axis (0)",
        "frame,moment_0,moment_1,moment_2,axis_0_x",
        "omega0 = [1.0, 0.01, -0.02]   # spin about the smallest axis (0), nudged",
        "['omega1', 'omega2', 'omega3']",
        "the largest-magnitude component of columns 0 and 1 is positive",
        "wheel0_rate",
        "the damper 0 of the list",
    ):
        assert old_numberings(old), old
    for new in (
        "principal axes 1, 2, 3 (I1 <= I2 <= I3); perturbation(axis=0), moments[0], axes[:, 0]",
        "omega0 = [1.0, 0.01, -0.02]; the axis 0.3 rad off the vertical; T(0); frame 0",
        "t (s),omega_1 (rad/s),omega_2 (rad/s),omega_3 (rad/s),qx,qy,qz,qw,wheel1_rate (rad/s)",
        "--wheel 0 0 1 0.1 --damper 0.2 0.1",
    ):
        assert not old_numberings(new), old_numberings(new)


def run(argv, capsys, status=0):
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == status, (argv, out, err)
    return out + err


def header(path):
    with open(path, newline="") as handle:
        return next(csv.reader(handle))


def test_the_help_of_every_command(capsys):
    texts = [run(["--help"], capsys)]
    for command in ("demo", "spin", "inertia", "audit", "bench"):
        texts.append(run([command, "--help"], capsys))
    text = "\n".join(texts)
    assert not old_numberings(text), old_numberings(text)
    assert "numbered 1, 2, 3 in ascending order of moment" in texts[0]
    spin = texts[2]
    # The names of the API: the solids' keys as Body gives them, omega0 in body axes.
    assert "cuboid mass size=X,Y,Z" in spin and "ellipsoid mass semi_axes=X,Y,Z" in spin
    assert "omega0, the angular velocity at t = 0, in body axes x, y, z (rad/s)" in " ".join(
        spin.split()
    )
    # What spin takes: rotors, and no external torque (it has no option for one).
    assert "--torque" not in spin and "free of external torques" in " ".join(spin.split())
    assert "--wheel" in spin and "--damper" in spin
    # polhode bench says orientation, as the conventions page does.
    assert "attitude" not in text.lower()


def test_spin_reports_and_csv_headers(tmp_path, capsys):
    omega = ["--omega", "0.01", "5", "0.01", "--t", "10", "--points", "11"]
    # Principal moments in ascending order: omega is in principal axes 1, 2, 3.
    path = tmp_path / "moments.csv"
    out = run(["spin", "--moments", "1", "2", "3", *omega, "--csv", str(path)], capsys)
    assert "(rad/s, principal axes 1, 2, 3)" in out and "Spun about axis 2" in out
    assert header(path)[:4] == ["t (s)", "omega_1 (rad/s)", "omega_2 (rad/s)", "omega_3 (rad/s)"]
    texts = [out, ",".join(header(path))]
    # Moments not ascending: the body's axes are x, y, z (principal, but not 1, 2, 3).
    path = tmp_path / "descending.csv"
    out = run(["spin", "--moments", "3", "2", "1", *omega, "--csv", str(path)], capsys)
    assert "(rad/s, body axes x, y, z)" in out
    assert header(path)[1:4] == ["omega_x (rad/s)", "omega_y (rad/s)", "omega_z (rad/s)"]
    texts += [out, ",".join(header(path))]
    # A body whose own axes are not principal: x, y, z, and its principal axes printed in them.
    path = tmp_path / "cylinder.csv"
    argv = ["spin", "--body", "cylinder", "mass=1", "radius=0.1", "length=0.5", *omega]
    out = run([*argv, "--csv", str(path)], capsys)
    assert "principal axes     1: [0 0 1]  2: [1 0 0]  3: [0 1 0]   (in body axes x, y, z)" in out
    assert header(path)[1:4] == ["omega_x (rad/s)", "omega_y (rad/s)", "omega_z (rad/s)"]
    texts += [out, ",".join(header(path))]
    # A body whose own axes are its principal axes in ascending order: 1, 2, 3.
    path = tmp_path / "cuboid.csv"
    argv = ["spin", "--body", "cuboid", "mass=1", "size=0.5,0.2,0.1", *omega]
    out = run([*argv, "--csv", str(path)], capsys)
    assert header(path)[1:4] == ["omega_1 (rad/s)", "omega_2 (rad/s)", "omega_3 (rad/s)"]
    assert "principal axes  " not in out
    texts += [out, ",".join(header(path))]
    # Rotors: counted from 1 with their option's name, in the report and the columns.
    path = tmp_path / "rotors.csv"
    out = run(["spin", "--moments", "1", "4", "5", "--omega", "2", "0.01", "0.01", "--t", "4",
               "--points", "5", "--wheel", "0", "0", "1", "0.1", "--wheel", "1", "0", "0", "0.1",
               "--damper", "0.2", "0.1", "--csv", str(path)], capsys)
    assert "wheel 1" in out and "wheel 2" in out and "damper 1" in out
    # The rotors' columns come last (the CSV holds every quantity of the run); a damper's
    # rate is in body axes, numbered as omega's (principal axes 1, 2, 3 here).
    columns = header(path)
    assert columns[columns.index("wheel1_rate (rad/s)"):] == [
        "wheel1_rate (rad/s)", "wheel2_rate (rad/s)", "damper1_rate_1 (rad/s)",
        "damper1_rate_2 (rad/s)", "damper1_rate_3 (rad/s)"]
    texts += [out, ",".join(header(path))]
    # A bad second wheel is "wheel 2", named with its option.
    err = run(["spin", "--moments", "1", "2", "3", *omega, "--wheel", "0", "0", "1", "0.1",
               "--wheel", "0", "0", "0", "0.1"], capsys, status=2)
    assert "argument --wheel: wheel 2 (--wheel 0 0 0 0.1): " in err
    texts.append(err)
    text = "\n".join(texts)
    assert not old_numberings(text), old_numberings(text)


def test_inertia_audit_and_the_frames_csv(tmp_path, capsys):
    pytest.importorskip("trimesh")
    pytest.importorskip("yourdfpy")
    pytest.importorskip("ase")
    import trimesh
    from ase.build import molecule
    from ase.io import write

    texts = []
    stl = tmp_path / "part.stl"
    trimesh.creation.box(extents=[0.4, 0.2, 0.1]).export(stl)
    texts.append(run(["inertia", str(stl), "--density", "1000", "--point", "1", "0", "0"], capsys))
    assert "(the columns: axes 1, 2, 3, in the file's axes)" in texts[-1]
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(
        '<robot name="arm"><link name="forearm"><inertial><origin xyz="0 0 0.1" rpy="0 0 0"/>'
        '<mass value="1.2"/><inertia ixx="0.004" ixy="0" ixz="0" iyy="0.004" iyz="0" '
        'izz="0.0001"/></inertial><collision><geometry><box size="0.05 0.05 0.2"/></geometry>'
        "</collision></link></robot>",
        encoding="utf-8",
    )
    texts.append(run(["inertia", str(urdf)], capsys))
    texts.append(run(["audit", str(urdf)], capsys))
    # A molecule turning: every frame's principal moments and axes.
    atoms = molecule("CH3CH2OH")
    frames = []
    for angle in np.linspace(0.0, 1.0, 5):
        turned = atoms.copy()
        turned.rotate(np.degrees(angle), "z")
        frames.append(turned)
    xyz = tmp_path / "ethanol.xyz"
    write(xyz, frames)
    path = tmp_path / "frames.csv"
    texts.append(run(["inertia", str(xyz), "--frames", str(path)], capsys))
    assert header(path) == [
        "frame",
        "moment_1 (u angstrom^2)",
        "moment_2 (u angstrom^2)",
        "moment_3 (u angstrom^2)",
        *(f"axis_{k}_{c}" for k in (1, 2, 3) for c in "xyz"),
    ]
    texts.append(",".join(header(path)))
    text = "\n".join(texts)
    assert not old_numberings(text), old_numberings(text)


def test_the_demo(capsys):
    out = run(["demo", "--no-plots"], capsys)
    assert "principal axes 1, 2, 3" in out and "Spun about axis 2 (I2" in out
    assert not old_numberings(out), old_numberings(out)


def test_errors_about_axes_name_the_index_as_python_does():
    """A Python error names an axis by the argument that holds its index, ``axis=1``."""
    texts = []
    for args in (
        ([1.0, 2.0, 3.0], [0.0, 1.0, 0.1], 1.0, {"axis": 0}),  # no spin about axis=0
        ([1.0, 2.0, 3.0], [1.0, 0.9, 0.1], 1.0, {"axis": 0}),  # too far from it
        ([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 1e3, {"axis": 1}),  # grows too large
    ):
        moments, omega0, t, kwargs = args
        with pytest.raises(ph.PolhodeError) as error:
            ph.perturbation(moments, omega0, np.linspace(0.0, t, 5), **kwargs)
        assert f"`axis={kwargs['axis']}`" in str(error.value)
        texts.append(str(error.value))
    text = "\n".join(texts)
    assert not old_numberings(text), old_numberings(text)


def doc_pages() -> list[Path]:
    return sorted([*DOCS.glob("*.md"), *(DOCS / "guide").glob("*.md")])


@pytest.mark.skipif(not DOCS.is_dir(), reason="not run from the repository")
def test_the_documentation_pages():
    found = []
    for page in doc_pages():
        text = page.read_text(encoding="utf-8")
        found += [f"{page.relative_to(ROOT)}: {f}" for f in old_numberings(text)]
        # omega_x only as what it is, the coordinates of axes that are not principal: beside
        # omega_1, the name in principal axes.
        for paragraph in text.split("\n\n"):
            if "omega_x" in paragraph and "omega_1" not in paragraph:
                found.append(f"{page.relative_to(ROOT)}: omega_x without omega_1: {paragraph!r}")
    assert not found, "\n".join(found)
    conventions = (DOCS / "architecture.md").read_text(encoding="utf-8")
    assert "**Principal axes are numbered 1, 2, 3**" in conventions
