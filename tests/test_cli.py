"""The command line: the demo runs, `spin` reports what the exact solution says, and bad
arguments end with a message and a non-zero status, never a traceback."""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.special import ellipk

import polhode as ph
from polhode import _core
from polhode.cli import main
from polhode.invariants import max_relative_drift


def test_demo_prints_the_flip_prediction_and_observation(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path / "demo")]) == 0
    out = capsys.readouterr().out
    assert "T-handle" in out and "predicted" in out
    # Both the exact solution and the splitting observe flips at the predicted interval.
    predicted = float(out.split("a flip every ")[1].split(" s")[0])
    # The description says it too, rounded to 4 digits.
    assert f"turns over every {predicted:.4g} s" in out.replace("\n" + " " * 18, " ")
    observed = [
        float(line.split("every ")[1].split(" s;")[0])
        for line in out.splitlines()
        if line.startswith(("  exact ", "  splitting "))
    ]
    assert len(observed) == 2
    for interval in observed:
        assert abs(interval / predicted - 1) < 1e-3  # sampled on a 20001-point grid


def test_demo_shows_the_major_axis_rule(capsys):
    """The damped spin about the smallest axis ends about the largest: T falls to
    L^2 / (2 I3) with |L| fixed (moments 1, 4, 5; w0 = (2, 0.01, 0.01))."""
    assert main(["demo", "--no-plots"]) == 0
    out = capsys.readouterr().out.split("spherical damper")[1]
    ell2 = (1.0 * 2.0) ** 2 + (4.0 * 0.01) ** 2 + (5.0 * 0.01) ** 2
    final = float(out.split("T ")[1].split("-> ")[1].split(";")[0])
    assert final == pytest.approx(ell2 / (2 * 5.0), abs=1e-4)
    assert float(out.split("|L| fixed to ")[1].split(";")[0]) < 1e-8
    rate = float(out.split("grows at ")[1].split()[0])
    expected = ph.rotors.nutation_rate((1.0, 4.0, 5.0), (2.0, 0.01, 0.01),
                                       ph.rotors.SphericalDamper(0.2, 0.1))
    assert rate == pytest.approx(expected, abs=1e-4)
    time_constant = float(out.split("e-folding time ")[1].split()[0])
    assert time_constant == pytest.approx(1 / expected, abs=0.05)


def test_demo_writes_its_plots_into_the_output_folder(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    from matplotlib.image import imread

    out = tmp_path / "nested" / "demo"
    assert main(["demo", "--out", str(out)]) == 0
    written = sorted(p.name for p in out.glob("*.png"))
    assert {"flip_omega.png", "flip_polhode.png", "flip_herpolhode.png"} <= set(written)
    assert {"flip_drift_splitting.png", "perturbation_error.png"} <= set(written)
    assert {"damper_energy.png", "damper_polhode.png"} <= set(written)
    for name in written:
        image = imread(out / name)[..., :3]
        assert image.shape[0] > 200 and image.shape[1] > 200
        assert np.any(image < 0.5)  # something was drawn, not a blank canvas
    assert str(out) in capsys.readouterr().out


def test_demo_without_plots_writes_nothing(tmp_path):
    assert main(["demo", "--no-plots", "--out", str(tmp_path / "demo")]) == 0
    assert not (tmp_path / "demo").exists()


def test_spin_plot_writes_a_png(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    path = tmp_path / "spin.png"
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "30"]
    assert main([*argv, "--method", "rk4", "--dt", "0.01", "--plot", str(path)]) == 0
    assert path.stat().st_size > 20_000
    assert str(path) in capsys.readouterr().out


def test_bench_rejects_zero_repeats(capsys):
    assert main(["bench", "--repeats", "0"]) == 2
    assert "--repeats" in capsys.readouterr().err


def test_spin_reports_the_period_and_writes_the_trajectory(tmp_path, capsys):
    path = tmp_path / "run.csv"
    code = main(
        [
            "spin",
            "--moments",
            "1",
            "2",
            "3",
            "--omega",
            "0.01",
            "1",
            "0.01",
            "--t",
            "50",
            "--points",
            "11",
            "--csv",
            str(path),
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    # Independent period: L^2 > 2 T I2 here (L circulates about the largest axis), so with
    # Delta_j = L^2 - 2 T I_j: T = 4 K(k^2) / lambda, lambda = sqrt(Delta_1 (I3 - I2) / (I1 I2 I3)),
    # k^2 = (I2 - I1)(-Delta_3) / ((I3 - I2) Delta_1).
    i = np.array([1.0, 2.0, 3.0])
    w = np.array([0.01, 1.0, 0.01])
    l2, t2 = np.sum((i * w) ** 2), np.sum(i * w**2)
    d1, d3 = l2 - t2 * i[0], l2 - t2 * i[2]
    lam = np.sqrt(d1 * (i[2] - i[1]) / np.prod(i))
    k2 = (i[1] - i[0]) * (-d3) / ((i[2] - i[1]) * d1)
    period = 4 * ellipk(k2) / lam
    printed = float(out.split("period")[1].split()[0])
    assert abs(printed / period - 1) < 1e-9
    with path.open() as handle:
        rows = list(csv.reader(handle))
    # The output times, then every quantity of the core's table (none needs rotors here), in
    # its order, named by component (a vector in principal axes 1, 2, 3 here, the moments
    # ascending; in space x, y, z; the quaternion x, y, z, w), each with its unit.
    header = rows[0]
    expected = ["t (s)"]
    for row in _core.QUANTITIES:
        if "rotors" in row["requires"]:
            continue
        unit = "" if row["unit"] == "1" else f" ({row['unit']})"
        components = {(): [""], (3,): ["_1", "_2", "_3"] if row["frame"] == "body" else
                      ["_x", "_y", "_z"], (4,): ["_x", "_y", "_z", "_w"]}[row["shape"]]
        expected += [f"{row['name']}{c}{unit}" for c in components]
    assert header == expected
    for name in ("omega_1 (rad/s)", "omega_3 (rad/s)", "quaternion_w", "energy (J)",
                 "angular_momentum_space_z (kg m^2/s)", "angular_momentum_body_2 (kg m^2/s)"):
        assert name in header
    data = np.array(rows[1:], dtype=float)
    assert data.shape == (11, len(header))
    omega = data[:, [header.index(f"omega_{k} (rad/s)") for k in "123"]]
    quaternion = data[:, [header.index(f"quaternion_{c}") for c in "xyzw"]]
    np.testing.assert_allclose(omega[0], w, rtol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(quaternion, axis=1), 1.0, rtol=1e-14)
    # The other columns are the trajectory's own numbers, written to round-trip.
    sol = ph.simulate([1.0, 2.0, 3.0], w, np.linspace(0.0, 50.0, 11))
    energy = data[:, header.index("energy (J)")]
    assert energy.tolist() == sol.energy.tolist()
    space = data[:, [header.index(f"angular_momentum_space_{c} (kg m^2/s)") for c in "xyz"]]
    assert space.tolist() == sol.angular_momentum_space.tolist()


@pytest.mark.parametrize("method", ["exact", "dop853", "rk4"])
def test_spin_writes_the_output_times_of_an_end_time_by_default(tmp_path, capsys, method):
    # Without --points: polhode.simulate's times for the end time (48 per turn), the CSV rows
    # its numbers; the drift printed is over every one of them.
    path = tmp_path / "dense.csv"
    options = ["--method", method] + (["--dt", "0.01"] if method == "rk4" else [])
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "100"]
    assert main([*argv, *options, "--csv", str(path)]) == 0
    out = capsys.readouterr().out
    sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 100.0, **(
        {"method": method, "dt": 0.01} if method == "rk4" else {"method": method}
    ))
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert data[:, 0].tolist() == sol.t.tolist() and sol.t.size > 800
    assert data[:, 1:4].tolist() == sol.omega.tolist()
    drift = max_relative_drift(sol)["energy"]
    printed = float(out.split("energy T")[1].split()[0])
    assert printed == pytest.approx(drift, rel=5e-3, abs=0.0)


def test_spin_accepts_a_solid(capsys):
    code = main(
        [
            "spin",
            "--body",
            "cylinder",
            "mass=1",
            "radius=0.1",
            "length=0.5",
            "--omega",
            "0",
            "1",
            "5",
            "--t",
            "2",
            "--method",
            "splitting",
            "--dt",
            "1e-3",
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "symmetric" in out
    # Symmetric top: Omega = w_s (I_s - I_t) / I_t with I_s = m r^2 / 2, I_t = m (3 r^2 + L^2)/12.
    i_s, i_t = 0.01 / 2, (3 * 0.01 + 0.25) / 12
    expected = 5.0 * (i_s - i_t) / i_t
    printed = float(out.split("precession (body)")[1].split()[0])
    assert abs(printed / expected - 1) < 1e-8
    # In space the axis cones about L at |L| / I_t, at the nutation angle arccos(I_s w_s / |L|).
    momentum = math.hypot(i_t * 1.0, i_s * 5.0)
    printed = float(out.split("precession (space)")[1].split()[0])
    assert abs(printed / (momentum / i_t) - 1) < 1e-8
    printed = float(out.split("nutation angle")[1].split()[0])
    assert printed == pytest.approx(math.degrees(math.acos(i_s * 5.0 / momentum)), rel=1e-5)


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["spin", "--moments", "1", "2", "0", "--omega", "1", "1", "1", "--t", "5"], "moments"),
        (
            [
                "spin",
                "--moments",
                "1",
                "2",
                "3",
                "--omega",
                "1",
                "1",
                "1",
                "--t",
                "5",
                "--method",
                "rk4",
            ],
            "dt",
        ),
        (["spin", "--body", "pyramid", "mass=1", "--omega", "1", "1", "1", "--t", "5"], "body"),
        (["spin", "--body", "cylinder", "mass=1", "--omega", "1", "1", "1", "--t", "5"], "body"),
        (
            [
                "spin",
                "--body",
                "sphere",
                "mass=x",
                "radius=1",
                "--omega",
                "1",
                "1",
                "1",
                "--t",
                "5",
            ],
            "body",
        ),
        (["spin", "--moments", "1", "2", "3", "--omega", "nan", "1", "1", "--t", "5"], "omega0"),
    ],
)
def test_bad_arguments_exit_with_status_2_and_a_message(argv, fragment, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "error" in err and fragment in err
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "argv",
    [
        ["spin", "--moments", "1", "2", "--omega", "1", "1", "1", "--t", "5"],
        ["spin", "--omega", "1", "1", "1", "--t", "5"],
        ["spin", "--moments", "1", "2", "3", "--omega", "1", "1", "1", "--t", "x"],
        ["spin", "--moments", "1", "2", "3", "--omega", "1", "1", "1", "--t", "5", "--points", "1"],
        ["frobnicate"],
    ],
)
def test_argparse_errors_are_messages_not_tracebacks(argv):
    result = subprocess.run(
        [sys.executable, "-m", "polhode", *argv], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert "error" in result.stderr


def test_a_reader_that_goes_away_ends_the_run_quietly():
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "1", "1", "1", "--t", "1"]
    # `polhode ... | head`: the pipe's reader is gone before polhode writes.
    read, write = os.pipe()
    os.close(read)
    try:
        result = subprocess.run(
            [sys.executable, "-m", "polhode", *argv],
            stdout=write,
            stderr=subprocess.PIPE,
            text=True,
            timeout=60,
        )
    finally:
        os.close(write)
    assert result.returncode == 141
    assert result.stderr == ""


def test_version_prints_the_package_version(capsys):
    import polhode

    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"polhode {polhode.__version__}\n"
    result = subprocess.run(
        [sys.executable, "-m", "polhode", "--version"], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 0 and result.stdout == f"polhode {polhode.__version__}\n"


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("method", ["auto", "splitting", "midpoint", "rk4", "dop853"])
def test_spin_reports_rest_as_rest(method, capsys):
    dt = ["--dt", "0.1"] if method in ("splitting", "midpoint", "rk4") else []
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0", "0", "0", "--t", "10"]
    assert main([*argv, "--method", method, *dt]) == 0
    captured = capsys.readouterr()
    out = captured.out
    assert "rest" in out and "nan" not in out.lower()
    assert "absolute" in out  # against zero reference values the drift is absolute
    for name in ("energy T", "|L|", "L in space"):
        assert float(out.split(name)[1].split()[0]) == 0.0
    assert captured.err == ""


def test_spin_notes_moments_no_body_has(capsys):
    omega = ["--omega", "0.01", "1", "0.01", "--t", "10"]
    assert main(["spin", "--moments", "1", "1", "3", *omega]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "note" in err and "I1 + I2 >= I3" in err
    assert main(["spin", "--moments", "3", "1", "1.0000001", *omega]) == 0  # any order
    assert "I1 + I2 >= I3" in capsys.readouterr().err
    # A flat lamina (I1 + I2 = I3) and every solid are bodies: no note.
    for argv in (
        ["spin", "--moments", "1", "2", "3", *omega],
        ["spin", "--moments", "0.1", "0.2", "0.3", *omega],
        ["spin", "--body", "cylinder", "mass=1", "radius=0.1", "length=0.5", *omega],
    ):
        assert main(argv) == 0
        assert capsys.readouterr().err == ""


def test_spin_passes_order_and_rtol_to_their_methods(capsys):
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "5"]
    assert main([*argv, "--method", "splitting", "--dt", "0.01", "--order", "6"]) == 0
    assert "method splitting" in capsys.readouterr().out
    assert main([*argv, "--method", "dop853", "--rtol", "1e-6"]) == 0
    assert "method dop853" in capsys.readouterr().out
    assert main([*argv[:-1], "0"]) == 0  # an end time of 0 is a run of no length


def test_spin_imports_neither_scipy_nor_matplotlib_and_times_only_the_run(tmp_path):
    # What the run's reported time could include: nothing is left to import during it.
    script = """
import sys
import polhode
import polhode as ph
from polhode import _core
from polhode.cli import main

seen = {}
simulate = polhode.simulate

def watched(*args, **kwargs):
    seen["loaded"] = sorted(m for m in sys.modules if m.split(".")[0] in ("scipy", "matplotlib"))
    return simulate(*args, **kwargs)

polhode.simulate = watched
argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "10"]
assert main(argv + sys.argv[1:]) == 0
after = sorted(m for m in sys.modules if m.split(".")[0] in ("scipy", "matplotlib"))
print("RESULT", seen["loaded"] == after, bool(after), "matplotlib.figure" in seen["loaded"])
"""
    plain = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert plain.returncode == 0, plain.stderr
    # Nothing of scipy or matplotlib, before the run or during it.
    assert plain.stdout.split("RESULT")[1].split() == ["True", "False", "False"]
    pytest.importorskip("matplotlib")
    plotted = subprocess.run(
        [sys.executable, "-c", script, "--plot", str(tmp_path / "run.png")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert plotted.returncode == 0, plotted.stderr
    # With --plot, matplotlib is imported while the arguments are checked, before the run.
    assert plotted.stdout.split("RESULT")[1].split()[2] == "True"


def test_a_bare_polhode_prints_its_help_and_writes_nothing(tmp_path, capsys, monkeypatch):
    """It ran the whole demo and wrote eight files into ./polhode-demo."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(ph, "simulate", lambda *a, **k: pytest.fail("no run"))
    assert main([]) == 2
    out, err = capsys.readouterr()
    assert out.startswith("usage: polhode") and "{demo,spin,audit,inertia,bench}" in out
    assert "numbered 1, 2, 3 in ascending order of moment" in " ".join(out.split())
    assert err == "polhode: error: no command given (`polhode demo` runs the demo)\n"
    assert list(tmp_path.iterdir()) == []
    done = subprocess.run([sys.executable, "-m", "polhode"], capture_output=True, text=True,
                          cwd=tmp_path, timeout=120)
    assert done.returncode == 2 and done.stdout == out and list(tmp_path.iterdir()) == []
