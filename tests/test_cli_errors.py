"""Bad command lines: every one ends with a message naming the option at fault and exit status
2, never a traceback, and the checks that need no run are made before any work."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import polhode
from polhode.cli import main

SPIN = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "5"]
OMEGA_T = ["--omega", "0.01", "1", "0.01", "--t", "5"]
RK4 = [*SPIN, "--method", "rk4", "--dt", "0.01"]

# (command line, a fragment the message must hold, checked before any work); "{tmp}" is a
# fresh folder, "{file}" an existing file in it.
BAD = [
    # --moments: missing values, wrong types, non-finite, not positive, with --body
    (["spin", "--moments", "1", "2", *OMEGA_T], "--moments", True),
    (["spin", "--moments", "1", "2", "x", *OMEGA_T], "--moments", True),
    (["spin", "--moments", "1", "2", "0", *OMEGA_T], "--moments", True),
    (["spin", "--moments", "1", "2", "-3", *OMEGA_T], "--moments", True),
    (["spin", "--moments", "1", "2", "inf", *OMEGA_T], "--moments", True),
    (["spin", "--moments", "1", "nan", "3", *OMEGA_T], "--moments", True),
    (["spin", *OMEGA_T], "--moments", True),
    ([*SPIN, "--body", "sphere", "mass=1", "radius=1"], "--body", True),
    # --body: unknown kind or key, missing or repeated keys, bad numbers, impossible solids
    (["spin", "--body", "pyramid", "mass=1", *OMEGA_T], "--body", True),
    (
        ["spin", "--body", "cylinder", "mass=1", "radius=0.1", "lenght=0.5", *OMEGA_T],
        "lenght",
        True,
    ),
    (["spin", "--body", "cylinder", "mass=1", "radius=0.1", *OMEGA_T], "length", True),
    (["spin", "--body", "sphere", "mass=x", "radius=1", *OMEGA_T], "--body", True),
    (["spin", "--body", "sphere", "mass=1", "radius=1", "mass=2", *OMEGA_T], "twice", True),
    (["spin", "--body", "sphere", "mass1", "radius=1", *OMEGA_T], "--body", True),
    (["spin", "--body", "sphere", "mass=inf", "radius=1", *OMEGA_T], "--body", True),
    (["spin", "--body", "sphere", "mass=1", "radius=-1", *OMEGA_T], "--body", True),
    (
        [
            "spin",
            "--body",
            "tube",
            "mass=1",
            "inner_radius=2",
            "outer_radius=1",
            "length=1",
            *OMEGA_T,
        ],
        "--body",
        True,
    ),
    (["spin", "--body", "--omega", "1", "1", "1", "--t", "5"], "--body", True),
    # --body's vector keys: three comma-separated numbers under the name Body gives them
    (["spin", "--body", "cuboid", "mass=1", "size=0.1,0.2", *OMEGA_T], "size=X,Y,Z", True),
    (["spin", "--body", "cuboid", "mass=1", "size=0.1,x,0.2", *OMEGA_T], "size=X,Y,Z", True),
    (["spin", "--body", "cuboid", "mass=1", "a=1", "b=2", "c=3", *OMEGA_T], "'a'", True),
    (["spin", "--body", "cuboid", "mass=1", *OMEGA_T], "missing size", True),
    (["spin", "--body", "ellipsoid", "mass=1", "semi_axes=1", *OMEGA_T], "semi_axes=X,Y,Z",
     True),
    (["spin", "--body", "sphere", "mass=1,2", "radius=1", *OMEGA_T], "mass=NUMBER", True),
    (["spin", "--body", "cuboid", "mass=1", "size=0.1,-0.2,0.3", *OMEGA_T],
     "Y of size=X,Y,Z to be positive", True),
    # --omega
    (["spin", "--moments", "1", "2", "3", "--omega", "1", "1", "--t", "5"], "--omega", True),
    (["spin", "--moments", "1", "2", "3", "--omega", "nan", "1", "1", "--t", "5"], "omega0", True),
    (["spin", "--moments", "1", "2", "3", "--omega", "inf", "1", "1", "--t", "5"], "--omega", True),
    (["spin", "--moments", "1", "2", "3", "--omega", "a", "b", "c", "--t", "5"], "--omega", True),
    (
        ["spin", "--moments", "1", "2", "3", "--omega", "1e200", "1", "1", "--t", "5"],
        "--omega",
        False,
    ),
    (["spin", "--moments", "1", "2", "3", "--t", "5"], "--omega", True),
    # --t
    ([*SPIN[:-1], "x"], "--t", True),
    ([*SPIN[:-1], "inf"], "--t", True),
    ([*SPIN[:-1], "-inf"], "--t", True),
    ([*SPIN[:-1], "nan"], "--t", True),
    ([*SPIN[:-1], "-1"], "--t", True),
    ([*SPIN[:-1], "1e999"], "--t", True),
    (SPIN[:-1], "--t", True),
    (SPIN[:-2], "--t", True),
    # --points
    ([*SPIN, "--points", "1"], "--points", True),
    ([*SPIN, "--points", "2.5"], "--points", True),
    ([*SPIN, "--points", "-5"], "--points", True),
    ([*SPIN, "--points", "100000000000"], "--points", True),
    ([*SPIN, "--points"], "--points", True),
    # --method and what goes with it
    ([*SPIN, "--method", "euler"], "--method", True),
    ([*SPIN, "--method", "rk4"], "--dt", True),
    ([*SPIN, "--dt", "0.1"], "--dt", True),
    ([*SPIN, "--method", "exact", "--dt", "0.1"], "--dt", True),
    ([*SPIN, "--method", "dop853", "--dt", "0.1"], "--dt", True),
    ([*SPIN, "--method", "rk4", "--dt", "0"], "--dt", True),
    ([*SPIN, "--method", "rk4", "--dt", "-1"], "--dt", True),
    ([*SPIN, "--method", "rk4", "--dt", "inf"], "--dt", True),
    ([*SPIN, "--method", "rk4", "--dt", "x"], "--dt", True),
    ([*SPIN, "--method", "rk4", "--dt", "1e-300"], "--dt", False),
    ([*SPIN, "--method", "splitting", "--dt", "0.01", "--order", "3"], "--order", True),
    ([*SPIN, "--method", "splitting", "--dt", "0.01", "--order", "x"], "--order", True),
    ([*RK4, "--order", "4"], "--order", True),
    ([*SPIN, "--rtol", "1e-8"], "--rtol", True),
    ([*SPIN, "--method", "exact", "--rtol", "1e-8"], "--rtol", True),
    ([*SPIN, "--method", "dop853", "--rtol", "0"], "--rtol", True),
    ([*SPIN, "--method", "dop853", "--rtol", "-1"], "--rtol", True),
    ([*SPIN, "--method", "dop853", "--rtol", "nan"], "--rtol", True),
    ([*SPIN, "--method", "dop853", "--rtol", "2"], "--rtol", True),
    ([*SPIN, "--frobnicate"], "--frobnicate", True),
    # output paths, checked before the run
    ([*SPIN, "--csv", "{tmp}/missing/run.csv"], "--csv", True),
    ([*SPIN, "--csv", "{tmp}"], "--csv", True),
    ([*SPIN, "--csv", "{file}/run.csv"], "--csv", True),
    ([*SPIN, "--csv", ""], "--csv", True),
    ([*SPIN, "--csv"], "--csv", True),
    ([*SPIN, "--plot", "{tmp}/run.xyz"], "--plot", True),
    ([*SPIN, "--plot", "{tmp}/run"], "--plot", True),
    ([*SPIN, "--plot", "{tmp}/missing/run.png"], "--plot", True),
    ([*SPIN, "--plot", "{file}/run.png"], "--plot", True),
    ([*SPIN, "--plot", "{tmp}"], "--plot", True),
    ([*SPIN, "--csv", "{tmp}/run.png", "--plot", "{tmp}/run.png"], "--plot", True),
    # demo
    (["demo", "--out", "{file}"], "--out", True),
    (["demo", "--out", "{file}/plots"], "--out", True),
    (["demo", "--out", ""], "--out", True),
    (["demo", "--out"], "--out", True),
    (["demo", "--frobnicate"], "--frobnicate", True),
    # bench
    (["bench", "--repeats", "0"], "--repeats", True),
    (["bench", "--repeats", "-3"], "--repeats", True),
    (["bench", "--repeats", "x"], "--repeats", True),
    (["bench", "--repeats", "2.5"], "--repeats", True),
    (["bench", "--repeats"], "--repeats", True),
    (["bench", "--quick", "--frobnicate"], "--frobnicate", True),
    # commands
    (["frobnicate"], "frobnicate", True),
    (["--frobnicate"], "--frobnicate", True),
]


def test_the_table_is_large():
    assert len(BAD) >= 40


@pytest.fixture
def paths(tmp_path):
    (tmp_path / "file.txt").write_text("not a folder\n")
    return {"tmp": str(tmp_path), "file": str(tmp_path / "file.txt")}


def fill(argv, paths):
    return [word.format(**paths) for word in argv]


def refuse(*args, **kwargs):
    raise AssertionError("the run started before the arguments were checked")


@pytest.mark.parametrize(
    ("argv", "fragment", "before_work"),
    BAD,
    ids=[" ".join(argv) or "(empty)" for argv, _, _ in BAD],
)
def test_bad_command_lines_exit_2_naming_the_option(
    argv, fragment, before_work, paths, capsys, monkeypatch
):
    if before_work:
        for name in ("simulate", "analyze"):
            monkeypatch.setattr(polhode, name, refuse)
        monkeypatch.setattr(polhode.Body, "principal", refuse)
        monkeypatch.setattr("polhode.bench.run", refuse, raising=False)
    before = sorted(p.name for p in Path(paths["tmp"]).iterdir())
    assert main(fill(argv, paths)) == 2
    err = capsys.readouterr().err
    assert "error" in err and fragment in err, err
    assert "Traceback" not in err
    after = sorted(p.name for p in Path(paths["tmp"]).iterdir())
    assert after == before  # nothing written, not even an empty file


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["spin", "--moments", "1", "2", "3", "--omega", "1", "1", "1", "--t", "inf"], "--t"),
        ([*SPIN, "--dt", "0.1"], "--dt"),
        (["spin", "--body", "cylinder", "mass=1", "radius=0.1", "lenght=0.5", *OMEGA_T], "lenght"),
        ([*SPIN, "--csv", "/nonexistent-polhode-folder/run.csv"], "--csv"),
        (["bench", "--repeats", "0"], "--repeats"),
    ],
)
def test_bad_command_lines_through_python_m_polhode(argv, fragment):
    result = subprocess.run(
        [sys.executable, "-m", "polhode", *argv], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 2
    assert "error" in result.stderr and fragment in result.stderr
    assert "Traceback" not in result.stderr
    assert result.stdout == ""  # no output: nothing ran


def test_plot_without_matplotlib_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    monkeypatch.setattr(polhode, "simulate", refuse)
    monkeypatch.setattr(polhode, "analyze", refuse)
    assert main([*SPIN, "--plot", str(tmp_path / "run.png")]) == 2
    err = capsys.readouterr().err
    assert "--plot" in err and "matplotlib" in err
    assert not (tmp_path / "run.png").exists()
