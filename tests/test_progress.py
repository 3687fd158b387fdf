"""simulate(progress=...): a tqdm bar or a callable fed the fraction done.

The fraction is checked against what it must be (non-decreasing, in [0, 1], ending at 1.0,
with values in between for a long run); watching must not change a single bit of the results;
Ctrl-C: tests/test_interrupt.py.
"""

from __future__ import annotations

import sys
import time

import numpy as np
import pytest

import polhode as ph

MOMENTS = (1.0, 2.0, 3.0)
W = (0.01, 1.0, 0.01)


def batch(n):
    rng = np.random.default_rng(7)
    return rng.uniform(1.0, 3.0, (n, 3)), rng.normal(size=(n, 3))


def check_fractions(fractions):
    assert fractions, "progress was never called"
    assert all(0.0 <= f <= 1.0 for f in fractions), fractions
    assert all(a <= b for a, b in zip(fractions, fractions[1:], strict=False)), fractions
    assert fractions[-1] == 1.0
    assert fractions.count(1.0) == 1, "1.0 is reported once, at the end"


@pytest.mark.parametrize("kind", ["single", "batch"])
def test_a_long_run_reports_non_decreasing_fractions_ending_at_one(kind):
    fractions = []
    if kind == "single":
        # 4e6 rk4 steps with the orientation: ~0.2 s, polled every 50 ms.
        ph.simulate(MOMENTS, W, 400.0, method="rk4", dt=1e-4, progress=fractions.append)
    else:
        # 1e8 body-steps: ~0.4 s for the lanes' 2.7e8 body-steps/s (1e7 took 40 ms, and ended
        # before the first poll at 50 ms).
        moments, omega0 = batch(200)
        ph.simulate(moments, omega0, 100.0, method="rk4", dt=2e-4, progress=fractions.append)
    check_fractions(fractions)
    assert any(0.0 < f < 1.0 for f in fractions), fractions


def test_a_short_run_reports_one_only():
    fractions = []
    ph.simulate(MOMENTS, W, [0.0, 1.0, 2.0], progress=fractions.append)
    assert fractions == [1.0]


def run_both(method, moments, omega0, t, **options):
    plain = ph.simulate(moments, omega0, t, method=method, **options)
    fractions = []
    watched = ph.simulate(moments, omega0, t, method=method, progress=fractions.append, **options)
    check_fractions(fractions)
    return plain, watched


@pytest.mark.parametrize("method", ["exact", "splitting", "midpoint", "rk4", "dop853"])
@pytest.mark.parametrize("kind", ["single", "batch"])
def test_progress_changes_no_bit_of_the_result(method, kind):
    # 2e4 steps a body: the runs look at their monitor (every 4096 steps) several times; 5000
    # output times for the closed form (it looks every 256).
    options = {"dt": 5e-4} if method in ("splitting", "midpoint", "rk4") else {}
    t = np.linspace(0.0, 10.0, 5001)
    moments, omega0 = batch(4) if kind == "batch" else (MOMENTS, W)
    plain, watched = run_both(method, moments, omega0, t, **options)
    np.testing.assert_array_equal(watched.omega, plain.omega)
    np.testing.assert_array_equal(watched.quaternion, plain.quaternion)
    np.testing.assert_array_equal(watched.stats["steps"], plain.stats["steps"])
    if method != "exact":
        torque = ph.torque.BodyFixed([0.0, 0.0, 0.01])
        plain, watched = run_both(method, moments, omega0, t, torque=torque, **options)
        np.testing.assert_array_equal(watched.omega, plain.omega)
        np.testing.assert_array_equal(watched.quaternion, plain.quaternion)


def test_a_callable_torque_still_works_with_progress():
    torque = ph.torque.Function(lambda t, w, q: (0.0, 0.0, 0.01))
    plain, watched = run_both("rk4", MOMENTS, W, 50.0, dt=5e-3, torque=torque)
    np.testing.assert_array_equal(watched.omega, plain.omega)


def test_progress_true_draws_a_tqdm_bar_on_stderr(capsys):
    pytest.importorskip("tqdm")
    sol = ph.simulate(MOMENTS, W, 10.0, method="rk4", dt=1e-2, progress=True)
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "polhode.simulate" in captured.err and "100%" in captured.err, captured.err
    assert sol.omega.shape == (sol.t.size, 3) and sol.t.size >= 49


def test_progress_true_without_tqdm_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    with pytest.raises(ImportError, match="pip install tqdm"):
        ph.simulate(MOMENTS, W, 1.0, progress=True)
    ph.simulate(MOMENTS, W, 1.0, progress=False)


@pytest.mark.parametrize("bad", [1, 0.5, "yes", [0.1]])
def test_progress_of_a_wrong_type_is_a_type_error(bad):
    with pytest.raises(TypeError, match="`progress`"):
        ph.simulate(MOMENTS, W, 1.0, progress=bad)


@pytest.mark.parametrize("kind", ["single", "batch"])
def test_an_exception_in_progress_stops_the_run(kind):
    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop(fraction)

    # Minutes of work unless stopped at the first report (after 50 ms).
    moments, omega0 = batch(1000) if kind == "batch" else (MOMENTS, W)
    start = time.perf_counter()
    with pytest.raises(Stop):
        ph.simulate(moments, omega0, 1e6, method="rk4", dt=1e-3, max_steps=10**12, progress=stop)
    assert time.perf_counter() - start < 5.0
