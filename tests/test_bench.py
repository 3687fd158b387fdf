"""polhode.bench measures what it says: its reference is the independent 30-digit one, its
errors are the right distances, its peers integrate the same motion, and its interpolation of
the cost to reach an error is right. (The timings themselves are not tested: the machine is
shared and noisy.)"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import polhode as ph
from polhode import bench
from polhode.bench import adapters, motion
from reference_motion import reference_motion


@pytest.mark.parametrize("name", list(bench.CASES))
def test_reference_constants_are_the_30_digit_reference(name):
    case = bench.CASES[name]
    omega, quat = reference_motion(case.moments, case.omega0, [0, 0, 0, 1], [case.t_end])
    w_ref, q_ref = bench.REFERENCE[name]
    np.testing.assert_allclose(w_ref, np.asarray(omega, dtype=float)[-1], rtol=0, atol=1e-16)
    np.testing.assert_allclose(q_ref, np.asarray(quat, dtype=float)[-1], rtol=0, atol=1e-16)


def test_import_polhode_does_not_import_the_benchmarks():
    import subprocess
    import sys

    code = (
        "import sys, polhode, polhode.cli; "
        "print(sorted(m for m in sys.modules if m.startswith('polhode.bench')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_hlw_case_starts_from_the_given_angular_momentum():
    case = bench.CASES["hlw"]
    m0 = np.array(case.moments) * np.array(case.omega0)
    np.testing.assert_allclose(m0, [math.cos(1.1), 0.0, math.sin(1.1)], rtol=1e-15, atol=1e-16)


def test_orientation_error_is_the_rotation_angle():
    rng = np.random.default_rng(3)
    for angle in (1e-12, 1e-6, 0.3, 2.5):
        a = Rotation.random(random_state=rng)
        axis = rng.normal(size=3)
        delta = Rotation.from_rotvec(angle * axis / np.linalg.norm(axis))
        b = a * delta
        # q and -q are one rotation.
        for sign in (1.0, -1.0):
            err = motion._orientation_error(sign * b.as_quat(), a.as_quat())
            assert err == pytest.approx(angle, rel=1e-9, abs=1e-15)


def test_cost_at_interpolates_on_the_pareto_front():
    series = bench.Series("s", False)
    series.points = [
        bench.Point("a", [1e-3], 1e-4, 0.0),
        bench.Point("dominated", [5e-3], 1e-3, 0.0),  # slower and worse: not on the front
        bench.Point("b", [1e-2], 1e-8, 0.0),
    ]
    # Halfway in log error is halfway in log time: sqrt(1e-3 * 1e-2).
    assert bench.cost_at(series, 1e-6) == pytest.approx(math.sqrt(1e-5), rel=1e-12)
    assert bench.cost_at(series, 1e-2) == pytest.approx(1e-3)  # the cheapest already gets there
    assert bench.cost_at(series, 1e-9) is None
    assert bench.cost_at(series, 1e-8) == pytest.approx(1e-2)


@pytest.fixture(scope="module")
def hlw():
    return bench.work_precision("hlw", quick=True, repeats=1, peers=False)


def test_exact_is_at_round_off_against_the_reference(hlw):
    p = hlw.get("polhode exact").points[0]
    assert p.error_omega < 1e-14 and p.error_orientation < 1e-13


def test_fixed_step_errors_fall_with_the_order(hlw):
    # dt 0.1 -> 0.02 -> 0.005 (factors 5 and 4): order p divides the error by about 5^p, 4^p.
    for name, order in (
        ("polhode rk4", 4),
        ("polhode splitting 4", 4),
        ("polhode splitting 2", 2),
        ("polhode midpoint", 2),
    ):
        errors = [p.error_omega for p in hlw.get(name).points]
        assert len(errors) == 3, name
        assert errors[0] / errors[1] > 0.4 * 5**order, (name, errors)
        assert errors[1] / errors[2] > 0.4 * 4**order, (name, errors)


def test_dop853_tracks_its_tolerance(hlw):
    points = hlw.get("polhode dop853").points
    for p in points:
        rtol = float(p.setting.split()[1])
        assert p.error_omega < 1e3 * rtol
    assert points[-1].error_omega < 1e-11


def test_peers_integrate_the_same_motion():
    pytest.importorskip("mujoco")
    case = bench.CASES["flip"]
    skipped: list[str] = []
    sweeps = {name: settings for name, _, settings in motion._sweeps(case, True, True, skipped)}
    assert not skipped
    reference = tuple(np.array(x) for x in bench.REFERENCE["flip"])
    # scipy's DOP853 at rtol 1e-9 and MuJoCo's RK4 at dt 0.005 are close to the reference; an
    # error in the right-hand side or in the frames would leave O(1) errors.
    run = dict(sweeps["scipy DOP853"])["rtol 1e-09"]
    e_w, e_q = motion._errors(*run(), reference)
    assert e_w < 1e-7 and e_q < 1e-6
    run = dict(sweeps["MuJoCo RK4"])["dt 0.005"]
    e_w, e_q = motion._errors(*run(), reference)
    assert e_w < 1e-10 and e_q < 1e-9
    # MuJoCo's Euler is first order: dt 0.02 -> 0.005 divides its error by about 4.
    euler = dict(sweeps["MuJoCo Euler"])
    coarse = motion._errors(*euler["dt 0.02"](), reference)[0]
    fine = motion._errors(*euler["dt 0.005"](), reference)[0]
    assert 3.0 < coarse / fine < 5.0


def test_drift_shows_what_each_method_conserves():
    result = bench.drift("flip", steps=20_000, samples=40)
    assert len(result.t) == len(result.errors["rk4"]["T"])
    for order in (2, 4, 6):
        errors = result.errors[f"splitting {order}"]
        assert errors["|L|"].max() < 1e-13 and errors["L"].max() < 1e-13
    assert result.errors["midpoint"]["T"].max() < 1e-12
    assert result.errors["midpoint"]["|L|"].max() < 1e-12
    # rk4 conserves nothing exactly: its energy error is above round-off.
    assert result.errors["rk4"]["T"].max() > 1e-13
    assert "splitting 4" in result.table()


def test_throughput_counts_the_work():
    result = bench.throughput(sizes=(1, 50), methods=("rk4", "exact"), work=2000, repeats=1)
    rows = {(m, a, n): work for m, a, n, work, _ in result.rows}
    assert rows[("rk4", True, 50)] == 50 * 40  # 2000 / 50 steps each
    assert rows[("exact", False, 1)] == 2000 // 8  # output times (an evaluation costs ~8 steps)
    assert all(r > 0 for r in result.rate("rk4", True).values())


def test_numpy_rk4_peer_is_rk4_and_timed_beside_polhode():
    """The batch peer integrates the same equations by the same method: its states agree with
    polhode's rk4 to round-off (the two differ only in the order of a few additions and in
    when the quaternion is renormalised), and the throughput gives each method's multiple of
    it at N >= 1e4."""
    rng = np.random.default_rng(4)
    moments = np.sort(rng.uniform(1.0, 2.0, (20, 3)), axis=1)
    omega0 = rng.normal(size=(20, 3))
    omega, quaternion = adapters.numpy_rk4(moments, omega0, 300, 0.01)
    sol = ph.simulate(moments, omega0, [0.0, 3.0], method="rk4", dt=0.01)
    np.testing.assert_allclose(omega, sol.omega[:, -1], rtol=0, atol=1e-13)
    assert quaternion is not None
    sign = np.sign(np.sum(quaternion * sol.quaternion[:, -1], axis=1))[:, None]
    np.testing.assert_allclose(sign * quaternion, sol.quaternion[:, -1], rtol=0, atol=1e-13)
    w_only, none = adapters.numpy_rk4(moments, omega0, 300, 0.01, orientation=False)
    assert none is None and np.array_equal(w_only, omega)
    result = bench.throughput(sizes=(10_000,), methods=("rk4",), work=1e5, repeats=1)
    rows = {(m, a, n): work for m, a, n, work, _ in result.rows}
    assert rows[(motion.NUMPY_RK4, True, 10_000)] == 10_000 * 10
    assert result.ratio("rk4", True)[10_000] > 0
    assert "x numpy rk4" in result.table()


def test_versus_and_tables_render():
    eig = bench.eigensolve(2000, repeats=1)
    assert len(eig) == 2 and all(v.ratio > 0 for v in eig)
    assert "worst residual" in eig[0].table()
    assert "agreement" in bench.point_masses(10_000, repeats=1).note


def test_plots_are_written(tmp_path, hlw):
    pytest.importorskip("matplotlib")
    from matplotlib.image import imread

    drift = bench.drift("flip", steps=2000, samples=20)
    throughput = bench.throughput(sizes=(1, 10), methods=("rk4",), work=200, repeats=1)
    for path in (
        bench.plot_work_precision(hlw, str(tmp_path / "wp.png")),
        bench.plot_drift(drift, str(tmp_path / "drift.png")),
        bench.plot_throughput(throughput, str(tmp_path / "tp.png")),
    ):
        image = imread(path)[..., :3]
        assert image.shape[0] > 300
        assert 0.01 < np.any(image < 0.9, axis=2).mean() < 0.9
