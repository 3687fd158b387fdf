"""`polhode spin --wheel ... --damper ...`: a body with internal rotors from the command line,
against scipy's DOP853 on the full system written apart from the core
(``reference_rotors.gyrostat``: the body's own axes, relative wheel rates, a mass matrix).

The report's drift of the total angular momentum is checked against the one computed here from
the CSV's columns (omega, the quaternion and the rotor rates, with the reference's formula for
the total ``H``), so a report that left the rotors out would fail.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
from reference_rotors import DamperRef, WheelRef, gyrostat
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode.cli import main


def _spin(argv, tmp_path, capsys):
    path = tmp_path / "run.csv"
    assert main(["spin", *argv, "--csv", str(path)]) == 0
    out = capsys.readouterr().out
    with path.open() as handle:
        rows = list(csv.reader(handle))
    return out, rows[0], np.array(rows[1:], dtype=float)


def _after(out, label):
    """The first number after ``label`` in the report."""
    return float(out.split(label)[1].split()[0].rstrip("),"))


def _final_rate(out, name):
    """The text after ``name`` among the report's rotor rates at the end time."""
    return out.split("rotor rates at t")[1].split(name)[1]


#: The CSV's columns of omega (moments given ascending: principal axes 1, 2, 3) and of the
#: quaternion.
OMEGA = ["omega_1 (rad/s)", "omega_2 (rad/s)", "omega_3 (rad/s)"]
QUATERNION = ["quaternion_x", "quaternion_y", "quaternion_z", "quaternion_w"]


def _columns(header, data, names):
    """The CSV's columns named ``names``, in that order (the CSV holds every quantity of the
    run, each found by its name)."""
    return data[:, [header.index(name) for name in names]]


def _damper(k):
    return [f"damper{k}_rate_{c} (rad/s)" for c in "123"]


def _total_momentum_space(moments, header, data, wheels, dampers):
    """H = I w + sum J W a + sum J_d (s - w) in body axes (I with the rotors locked), rotated
    into space by the CSV's quaternion."""
    omega, q = _columns(header, data, OMEGA), _columns(header, data, QUATERNION)
    h = omega * np.asarray(moments, dtype=float)
    for k, (axis, inertia) in enumerate(wheels, start=1):
        unit = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
        h = h + inertia * _columns(header, data, [f"wheel{k}_rate (rad/s)"]) * unit
    for k, inertia in enumerate(dampers, start=1):
        h = h + inertia * _columns(header, data, _damper(k))
    return Rotation.from_quat(q).apply(h)


def _drift(values, axis=None):
    first = values[0]
    if axis is None:
        return np.max(np.abs(values - first)) / abs(first)
    return np.max(np.linalg.norm(values - first, axis=1)) / np.linalg.norm(first)


def test_spin_with_a_wheel_and_a_damper_against_scipy(tmp_path, capsys):
    """A wheel on a skew axis with a constant motor torque and a damper, by dop853 and rk4:
    the CSV (omega, orientation, each rotor's rate) against scipy at every output time, and the
    report's final rotor rates and total energy against scipy's."""
    moments = (1.0, 2.0, 3.0)
    omega0 = (0.9, 0.1, -0.2)
    axis, j, rate0, g = (0.2, -0.3, 1.0), 0.05, 3.0, 0.02
    jd, c = 0.1, 0.05
    times = np.linspace(0.0, 8.0, 33)
    ref_omega, ref_q, ref_rates, ref_l, ref_t = gyrostat(
        np.diag(moments), omega0, [0.0, 0.0, 0.0, 1.0], times,
        [WheelRef(axis, j, rate0, lambda t, w, r: g), DamperRef(jd, c)],
    )
    unit = np.asarray(axis) / np.linalg.norm(axis)
    for method in (["--rtol", "1e-12"], ["--method", "rk4", "--dt", "2e-3"]):
        argv = [
            "--moments", "1", "2", "3", "--omega", *map(str, omega0), "--t", "8",
            "--points", "33", "--wheel", *map(str, axis), str(j), str(rate0), str(g),
            "--damper", str(jd), str(c), *method,
        ]
        out, header, data = _spin(argv, tmp_path, capsys)
        # The rotors' columns after the body's (the damper's rate in body axes, numbered as
        # omega's).
        rotors = header.index("wheel1_rate (rad/s)")
        assert header[rotors:] == ["wheel1_rate (rad/s)", *_damper(1)]
        assert data.shape == (33, len(header))
        # Measured against scipy (rtol 1e-12): dop853 at rtol 1e-12 within 5.5e-12 (omega),
        # 2.5e-11 (the rotor rates) and 2.2e-11 rad (the orientation); rk4 at dt = 2e-3 within
        # 1.3e-12. Bounds 2e-10 and 2e-9 rad.
        np.testing.assert_allclose(_columns(header, data, OMEGA), ref_omega, rtol=0, atol=2e-10)
        quaternion = _columns(header, data, QUATERNION)
        turn = Rotation.from_quat(quaternion) * Rotation.from_quat(ref_q).inv()
        assert np.max(turn.magnitude()) < 2e-9
        np.testing.assert_allclose(data[:, rotors], ref_rates[:, 0] @ unit, rtol=0, atol=2e-10)
        np.testing.assert_allclose(_columns(header, data, _damper(1)), ref_rates[:, 1], rtol=0,
                                   atol=2e-10)
        # The report: the final rates, T from start to end (the motor's work and the damper's
        # loss), and the drift of the totals, rotors included.
        wheel = float(_final_rate(out, "wheel 1").split()[0])
        assert wheel == pytest.approx(ref_rates[-1, 0] @ unit, rel=1e-8)
        damper = _final_rate(out, "damper 1").split("]")[0]
        np.testing.assert_allclose(np.array(damper.strip(" [").split(), dtype=float),
                                   ref_rates[-1, 1], atol=1e-6)  # printed to 6 decimals
        energy = out.split("energy T")[1].split("(")[0].split("->")
        assert float(energy[0]) == pytest.approx(ref_t[0], rel=1e-8)
        assert float(energy[1]) == pytest.approx(ref_t[-1], rel=1e-8)
        assert "the motor of wheel 1" in out and "damper 1" in out
        ell = _total_momentum_space(moments, header, data, [(axis, j)], [jd])
        np.testing.assert_allclose(ell, ref_l, rtol=0, atol=1e-9)
        assert "totals, rotors included" in out
        # The printed drift is the one of these columns (to round-off: it is 1e-14 for rk4,
        # and the two rotate H differently).
        printed = _after(out, "L in space")
        assert printed == pytest.approx(_drift(ell, axis=1), rel=0.01, abs=2e-15)
        norm = np.linalg.norm(ell, axis=1)
        assert _after(out, "|L|") == pytest.approx(_drift(norm), rel=0.01, abs=2e-15)
        # Without external torque the total L stays: dop853 to tens of rtol (measured 2.3e-11),
        # rk4 to O(dt^4) (measured 3e-14).
        assert printed < 1e-10


def test_spin_with_a_damper_shows_the_major_axis_rule(tmp_path, capsys):
    """A spin near the smallest axis with a damper: T falls monotonically at fixed |L| to
    |L|^2 / (2 I3), as scipy's integration of the same system says; the report's nutation rate
    is polhode.rotors.nutation_rate's."""
    moments = (1.0, 4.0, 5.0)
    omega0 = (2.0, 0.01, 0.01)
    times = np.linspace(0.0, 400.0, 401)
    argv = ["--moments", "1", "4", "5", "--omega", "2", "0.01", "0.01", "--t", "400",
            "--points", "401", "--damper", "0.2", "0.1", "--rtol", "1e-12"]
    out, header, data = _spin(argv, tmp_path, capsys)
    assert header[header.index(_damper(1)[0]):] == _damper(1)
    _, _, ref_rates, ref_l, ref_t = gyrostat(np.diag(moments), omega0, [0.0, 0.0, 0.0, 1.0],
                                             times, [DamperRef(0.2, 0.1)])
    ell = _total_momentum_space(moments, header, data, [], [0.2])
    ell2 = float(np.sum(ref_l[0] ** 2))
    energy = out.split("energy T")[1].split("(")[0].split("->")
    assert float(energy[0]) == pytest.approx(ref_t[0], rel=1e-14)
    # Measured: the end T within 2.7e-10 of scipy's, the damper's rates within 1.4e-9 over
    # the run (13 e-folding times of growth, then of decay, amplify the two integrations'
    # errors); bounds 1e-7.
    assert float(energy[1]) == pytest.approx(ref_t[-1], rel=1e-7)
    assert float(energy[1]) == pytest.approx(ell2 / (2 * 5.0), rel=1e-5)  # the largest axis
    assert _after(out, "between outputs") <= 1e-13  # T falls monotonically
    np.testing.assert_allclose(_columns(header, data, _damper(1)), ref_rates[:, 0], rtol=0,
                               atol=1e-7)
    # The total |L| and L in space, rotors included, kept to the tolerance (measured 1.2e-11
    # and 3.7e-11 over 400 s at rtol 1e-12).
    assert _after(out, "L in space") == pytest.approx(_drift(ell, axis=1), rel=0.01, abs=2e-15)
    assert _after(out, "L in space") < 1e-10
    rate = ph.rotors.nutation_rate(moments, omega0, ph.rotors.SphericalDamper(0.2, 0.1))
    assert _after(out, "nutation rate") == pytest.approx(rate, rel=1e-8)
    assert "grows, e-folding time" in out
    assert _after(out, "e-folding time") == pytest.approx(1 / rate, rel=1e-5)


@pytest.mark.parametrize(
    ("omega", "damping"), [(("1", "0.5", "0.1"), "0"), (("0", "0", "0"), "0.5")],
    ids=["no damping", "no spin"],
)
def test_spin_with_a_steady_damper(capsys, omega, damping):
    """A damper without damping, or a body at rest: the nutation rate is 0 and has no time
    constant; the report stopped there with an AssertionError and a traceback."""
    argv = ["spin", "--moments", "1", "2", "3", "--omega", *omega, "--t", "1",
            "--damper", "0.1", damping]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "nutation rate      0   (the damper's, linearised: steady)" in out


def test_spin_with_a_wheel_and_a_body(capsys):
    """--body with --wheel: the body's axes are its own; a wheel spun up from rest by its motor
    turns the body the other way, H = 0 throughout: w3 = -g t / (I3 - J) about the
    cylinder's axis, the wheel at g t (1/J + 1/(I3 - J))."""
    i3 = 0.5 * 1.0 * 0.1**2
    j, g = 0.001, 0.002
    argv = ["spin", "--body", "cylinder", "mass=1", "radius=0.1", "length=0.5",
            "--omega", "0", "0", "0", "--t", "2", "--wheel", "0", "0", "1", str(j), "0", str(g)]
    assert main(argv) == 0
    out = capsys.readouterr().out
    wheel = float(_final_rate(out, "wheel 1").split()[0])
    assert wheel == pytest.approx(g * 2 * (1 / j + 1 / (i3 - j)), rel=1e-9)
    omega = out.split("omega at t = 2")[1].split("]")[0].strip(" [").split()
    assert float(omega[2]) == pytest.approx(-g * 2 / (i3 - j), rel=1e-5)  # printed to 6 places
    assert "regime             rest (omega0 = 0)\n" in out  # not "stays at rest"
    assert "absolute where zero at t = 0" in out
    assert _after(out, "L in space") < 1e-15


def test_spin_rotors_without_damping_or_motor_keep_the_energy(capsys):
    """A free wheel (no motor) and a damper without damping: T is an invariant again, and the
    report gives its drift, not its change."""
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.3", "1", "0.2", "--t", "10",
            "--wheel", "0", "0", "1", "0.2", "1.5", "--damper", "0.1", "0", "--rtol", "1e-12"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "->" not in out.split("energy T")[1].split("\n")[0]
    assert _after(out, "energy T") < 1e-10
    assert "nutation rate" not in out  # a wheel besides the damper: no rate given


@pytest.mark.parametrize(
    ("extra", "fragment"),
    [
        (["--wheel", "0", "0", "0", "0.1"], "axis"),
        (["--wheel", "0", "0", "1", "0"], "inertia"),
        (["--wheel", "0", "0", "1", "-0.1"], "inertia"),
        (["--wheel", "0", "0", "1"], "4 to 6 numbers"),
        (["--wheel", "0", "0", "1", "0.1", "0", "0", "7"], "got 7"),
        (["--wheel", "0", "0", "1", "0.1", "x"], "--wheel"),
        (["--wheel", "0", "nan", "1", "0.1"], "--wheel"),
        (["--wheel", "0", "0", "1", "0.1", "inf"], "--wheel"),
        (["--wheel"], "--wheel"),
        (["--damper", "0"], "--damper"),
        (["--damper", "0", "0.1"], "inertia"),
        (["--damper", "0.1", "-1"], "damping"),
        (["--damper", "0.1", "0.1", "0.1"], "unrecognized"),
        (["--damper", "0.1", "0.1", "--method", "exact"], "--method"),
        (["--damper", "0.1", "0.1", "--method", "splitting", "--dt", "0.1"], "--method"),
        (["--wheel", "0", "0", "1", "0.1", "--method", "midpoint", "--dt", "0.1"], "--method"),
        (["--damper", "0.1", "0.1", "--method", "rk4"], "--dt"),
        (["--damper", "0.1", "0.1", "--method", "rk4", "--dt", "0.1", "--rtol", "1e-8"],
         "--rtol"),
    ],
)
def test_bad_rotors_exit_2_before_any_work(extra, fragment, capsys, monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("the run started before the arguments were checked")

    for name in ("simulate", "analyze"):
        monkeypatch.setattr(ph, name, refuse)
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "5"]
    assert main([*argv, *extra]) == 2
    err = capsys.readouterr().err
    assert "error" in err and fragment in err, err
    assert "Traceback" not in err
    if fragment == "--method":
        assert "dop853" in err and "rk4" in err  # what it takes instead


def test_rotors_that_do_not_fit_inside_the_body_name_the_option(capsys):
    """The rotors' spinning inertia must lie inside the body's (checked by the core at the run):
    the error names the option that gave them."""
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t", "5"]
    assert main([*argv, "--damper", "1.5", "0.1"]) == 2
    err = capsys.readouterr().err
    assert "--damper" in err and "positive definite" in err and "Traceback" not in err
    assert main([*argv, "--wheel", "1", "0", "0", "1.0", "--damper", "0.5", "0.1"]) == 2
    err = capsys.readouterr().err
    assert "--wheel and --damper" in err and "Traceback" not in err
