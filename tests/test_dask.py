"""polhode.dask: block by block along N gives the very numbers of one polhode.simulate (or
polhode.analyze per body) call, in process and on a two-worker distributed cluster."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

da = pytest.importorskip("dask.array")
import dask  # noqa: E402
from dask.callbacks import Callback  # noqa: E402

import polhode as ph  # noqa: E402
import polhode.dask as phd  # noqa: E402

N = 300
T = np.linspace(0.0, 4.0, 9)
METHODS = {
    "exact": {},
    "rk4": {"dt": 0.01},
    "splitting": {"dt": 0.02, "order": 4},
    "dop853": {"rtol": 1e-9},
}
FIELDS = (
    "omega",
    "quaternion",
    "angular_momentum_space",
    "angular_momentum_body",
    "energy",
    "moments",
)
STATS = ("steps", "rejected_steps", "evaluations")


@pytest.fixture(scope="module")
def bodies():
    rng = np.random.default_rng(7)
    moments = np.sort(rng.uniform(1.0, 4.0, (N, 3)), axis=1)
    moments[:10, 1] = moments[:10, 0]  # symmetric tops
    omega0 = rng.normal(size=(N, 3))
    omega0[10:20] = [0.0, 1.0, 1e-3]  # near the intermediate axis: flips
    return moments, omega0


def assert_same_trajectory(actual, expected):
    """Bit for bit: every array of the trajectory and the per-body cost."""
    np.testing.assert_array_equal(actual.t, expected.t)
    for name in FIELDS:
        a, e = getattr(actual, name), getattr(expected, name)
        if e is None:
            assert a is None, name
        else:
            assert a.shape == e.shape and a.dtype == e.dtype, name
            assert np.array_equal(a, e), name
    for name in STATS:
        assert np.array_equal(actual.stats[name], expected.stats[name]), name
    assert actual.stats["method"] == expected.stats["method"]


@pytest.mark.parametrize("scheduler", ["sync", "threads"])
@pytest.mark.parametrize("method", list(METHODS))
def test_blocks_equal_one_batch_bitwise(bodies, method, scheduler):
    moments, omega0 = bodies
    expected = ph.simulate(moments, omega0, T, method=method, **METHODS[method])
    lazy = phd.simulate(moments, omega0, T, method=method, chunks=64, **METHODS[method])
    assert lazy.omega.chunks == ((64, 64, 64, 64, 44), (len(T),), (3,))
    assert lazy.quaternion.shape == (N, len(T), 4) and lazy.energy.shape == (N, len(T))
    assert_same_trajectory(lazy.compute(scheduler=scheduler), expected)
    # the lazy arrays computed on their own hold the same numbers
    omega, energy, steps = dask.compute(lazy.omega, lazy.energy, lazy.steps, scheduler=scheduler)
    assert np.array_equal(omega, expected.omega) and np.array_equal(energy, expected.energy)
    assert np.array_equal(steps, expected.stats["steps"])


class CountBlocks(Callback):
    def __init__(self):
        super().__init__()
        self.keys = []

    def _posttask(self, key, result, dsk, state, worker_id):
        if key[0].startswith("polhode-simulate"):
            self.keys.append(key)


def test_fields_share_one_run_per_block(bodies):
    moments, omega0 = bodies
    lazy = phd.simulate(moments, omega0, T, method="rk4", dt=0.05, chunks=100)
    with CountBlocks() as counter:
        dask.compute(lazy.omega, lazy.quaternion, lazy.energy, scheduler="sync")
    assert sorted(counter.keys) == sorted(set(counter.keys)) and len(counter.keys) == 3


def test_dask_inputs_keep_their_row_chunks_and_columns_are_merged(bodies):
    moments, omega0 = bodies
    # rows in uneven blocks, columns split in two: the columns are merged, the rows of
    # omega0 follow those of moments
    m = da.from_array(moments, chunks=((100, 150, 50), (2, 1)))
    w = da.from_array(omega0, chunks=(120, 1))
    lazy = phd.simulate(m, w, T, method="rk4", dt=0.01)
    assert lazy.omega.chunks[0] == (100, 150, 50)
    expected = ph.simulate(moments, omega0, T, method="rk4", dt=0.01)
    assert_same_trajectory(lazy.compute(scheduler="sync"), expected)
    # an integer `chunks` rechunks dask input too
    assert phd.simulate(m, w, T, chunks=128).energy.chunks[0] == (128, 128, 44)


def test_shared_row_orientations_and_no_orientation(bodies):
    moments, omega0 = bodies
    kwargs = {"method": "splitting", "dt": 0.02}
    # one row of moments for every body
    expected = ph.simulate(moments[0], omega0, T, **kwargs)
    assert_same_trajectory(
        phd.simulate(moments[0], omega0, T, chunks=50, **kwargs).compute(scheduler="sync"),
        expected,
    )
    # one orientation per body, as dask quaternions or numpy matrices, or one for all
    rotations = Rotation.random(N, random_state=3)
    for orientation0 in (
        da.from_array(rotations.as_quat(), chunks=(70, 4)),
        rotations.as_matrix(),
        rotations,
        Rotation.from_euler("xyz", [0.1, 0.2, 0.3]),
    ):
        shared = orientation0 if not isinstance(orientation0, da.Array) else rotations.as_quat()
        expected = ph.simulate(moments, omega0, T, orientation0=shared, **kwargs)
        lazy = phd.simulate(moments, omega0, T, orientation0=orientation0, chunks=90, **kwargs)
        assert_same_trajectory(lazy.compute(scheduler="sync"), expected)
    expected = ph.simulate(moments, omega0, T, orientation=False, **kwargs)
    lazy = phd.simulate(moments, omega0, T, orientation=False, chunks=90, **kwargs)
    assert lazy.quaternion is None and lazy.angular_momentum_space is None
    assert_same_trajectory(lazy.compute(scheduler="sync"), expected)


def test_end_time_t0_and_persist(bodies):
    moments, omega0 = bodies
    expected = ph.simulate(moments, omega0, 3.0, t0=1.0, method="dop853")
    lazy = phd.simulate(moments, omega0, 3.0, t0=1.0, method="dop853", chunks=128)
    # polhode.simulate's output times for the whole batch (dense: see test_sampling.py).
    np.testing.assert_array_equal(lazy.t, expected.t)
    assert lazy.t[0] == 1.0 and lazy.t[-1] == 3.0 and lazy.t.size >= 49
    assert lazy.sampling == expected.stats["sampling"]
    kept = lazy.persist(scheduler="sync")
    assert_same_trajectory(kept.compute(scheduler="sync"), expected)


def test_analyze_equals_analyze_per_body(bodies):
    moments, omega0 = bodies
    rows = np.concatenate([moments[:25], [[1.0, 2.0, 3.0]] * 3, [[2.0, 2.0, 2.0]]])
    omegas = np.concatenate([omega0[:25], [[0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]])
    omegas = np.concatenate([omegas, [[0.3, 0.0, 1.0]]])
    lazy = phd.analyze(da.from_array(rows, chunks=7), omegas)
    assert lazy.regime.chunks == ((7, 7, 7, 7, 1),)
    got = lazy.compute(scheduler="sync")
    regimes = set()
    for k in range(len(rows)):
        a = ph.analyze(rows[k], omegas[k])
        regimes.add(a.regime)
        assert np.array_equal(got.moments[k], a.moments)
        assert np.array_equal(got.omega[k], a.omega)
        assert got.energy[k] == a.energy and got.angular_momentum_norm[k] == a.angular_momentum_norm
        assert got.regime[k] == a.regime
        for name in ("period", "flip_interval", "precession_rate_body", "precession_rate_space"):
            value, got_value = getattr(a, name), getattr(got, name)[k]
            assert np.isnan(got_value) if value is None else got_value == value, name
        if a.nutation_angle is None:
            assert np.isnan(got.nutation_angle[k]).all()
        else:
            assert tuple(got.nutation_angle[k]) == a.nutation_angle
        assert tuple(got.axis_stability[k]) == a.axis_stability
        assert got.linearized_axis[k] == a.linearized["axis"]
        assert got.linearized_kind[k] == a.linearized["kind"]
        assert got.linearized_rate[k] == a.linearized["rate"]
    assert {"symmetric", "steady_intermediate", "rest", "spherical"} <= regimes


@pytest.mark.parametrize(
    ("call", "error", "fragment"),
    [
        (lambda m, w: phd.simulate(m[:, :2], w, T), ph.ShapeError, r"`body`.*\(N, 3\)"),
        (lambda m, w: phd.simulate(m, w[:10], T), ph.PolhodeError, "`omega0`"),
        (lambda m, w: phd.simulate("1 2 3", w, T), TypeError, "`body`"),
        (lambda m, w: phd.simulate(da.from_array(m.astype(complex)), w, T), TypeError, "body"),
        (lambda m, w: phd.simulate(m, w, T, method="euler"), ph.PolhodeError, "`method`"),
        (lambda m, w: phd.simulate(m, w, T, method="rk4"), ph.PolhodeError, "`dt`"),
        (lambda m, w: phd.simulate(m, w, T[::-1]), ph.PolhodeError, "`t`"),
        (lambda m, w: phd.simulate(m, w, T, chunks=0), ph.PolhodeError, "`chunks`"),
        (lambda m, w: phd.simulate(m, w, T, chunks=2.5), TypeError, "`chunks`"),
        (lambda m, w: phd.simulate(m, w, T, speed=2), TypeError, "speed"),
        (lambda m, w: phd.simulate(-m, w, T), ph.ArgumentError, r"^body 0: .*`body`"),
        (
            lambda m, w: phd.simulate(m, np.where(np.arange(N)[:, None] == 5, np.nan, w), T),
            ph.NonFiniteError,
            r"^body 5: .*`omega0`",
        ),
        (
            lambda m, w: phd.simulate(m, w, T, orientation0=np.ones((7, 4))),
            ph.PolhodeError,
            "`orientation0`",
        ),
        (
            lambda m, w: phd.simulate(m, w, T, orientation0=np.zeros((N, 4))),
            ph.PolhodeError,
            "`orientation0`",
        ),
        (lambda m, w: phd.analyze(m, w, rtol=-1.0), ph.PolhodeError, "`rtol`"),
        (lambda m, w: phd.analyze(m, w[:3]), ph.PolhodeError, "`omega0`"),
        (lambda m, w: phd.analyze(np.zeros_like(m), w), ph.PolhodeError, r"^body 0: .*`body`"),
    ],
)
def test_bad_input_raises_at_once(bodies, call, error, fragment):
    with pytest.raises(error, match=fragment):
        call(*bodies)


def test_bad_values_in_dask_input_raise_when_computed_naming_the_body(bodies):
    moments, omega0 = bodies
    bad = moments.copy()
    bad[203, 1] = -1.0
    lazy = phd.simulate(da.from_array(bad, chunks=100), omega0, T)  # lazy: no error yet
    with pytest.raises(ph.PolhodeError, match=r"^body 203: .*`body`.*-1\.0") as info:
        lazy.compute(scheduler="sync")
    assert (info.value.argument, info.value.body) == ("body", 203)
    with pytest.raises(ph.PolhodeError, match=r"^body 203: .*`body`") as info:
        phd.analyze(da.from_array(bad, chunks=100), omega0).compute(scheduler="sync")
    assert (info.value.argument, info.value.body) == ("body", 203)


def test_import_polhode_does_not_import_dask():
    code = "import sys, polhode; print('dask' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# -------------------------------------------------------------------------------------------------
# A real cluster: two worker processes, one thread each
# -------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    # The scheduler's HTTP server on a free port (":0"): distributed 2026.8 binds 8787 even
    # for dashboard_address=None, and two clusters at once (pytest -n 2 puts this module's
    # tests on both workers) gave "Port 8787 is already in use", an error under
    # filterwarnings = error.
    with (
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client


def test_cluster_gives_identical_numbers(client, bodies):
    moments, omega0 = bodies
    assert len(client.scheduler_info()["workers"]) == 2
    m = da.from_array(moments, chunks=75)
    for method in ("rk4", "dop853"):
        expected = ph.simulate(moments, omega0, T, method=method, **METHODS[method])
        lazy = phd.simulate(m, omega0, T, method=method, **METHODS[method])
        assert_same_trajectory(lazy.compute(), expected)  # the client's cluster by default
    got = phd.analyze(m[:40], omega0[:40]).compute()
    for k in (0, 15, 39):
        assert got.period[k] == ph.analyze(moments[k], omega0[k]).period
    # a worker's error comes back with its type and the global body index
    bad = moments.copy()
    bad[160, 2] = np.inf
    with pytest.raises(ph.PolhodeError, match=r"^body 160: ") as info:
        phd.simulate(da.from_array(bad, chunks=75), omega0, T).compute()
    assert (type(info.value), info.value.argument, info.value.body) == (
        ph.ArgumentError,
        "body",
        160,
    )


def test_ctrl_c_idles_the_cluster_workers(client):
    # The worker processes do not see this process's SIGINT: after the KeyboardInterrupt,
    # DaskTrajectory.compute runs polhode.cancel_all on every worker. Measured by the workers'
    # CPU time (psutil): they go idle, where before they ran their blocks to the end (about 8 s
    # of CPU each, one per worker). Helpers and bounds: tests/test_interrupt.py.
    psutil = pytest.importorskip("psutil")
    from test_interrupt import CPU_BOUND, cpu_until_idle, interrupt, sigint_raises

    workers = [psutil.Process(pid) for pid in client.run(os.getpid).values()]
    assert len(workers) == 2

    def cpu(worker) -> float:
        times = worker.cpu_times()
        return times.user + times.system

    rng = np.random.default_rng(11)
    moments, omega0 = rng.uniform(1.0, 3.0, (4, 3)), rng.normal(size=(4, 3))
    t = np.linspace(0.0, 2.0, 3)
    expected = ph.simulate(moments, omega0, t, method="rk4", dt=1e-2).omega

    def short_compute():
        return phd.simulate(moments, omega0, t, method="rk4", dt=1e-2, chunks=1).compute()

    # Both workers have imported polhode and run a block of it: their CPU from here on is
    # the long blocks'.
    np.testing.assert_array_equal(short_compute().omega, expected)
    lazy = phd.simulate(
        moments, omega0, [0.0, 2e5], method="rk4", dt=1e-3, max_steps=10**9, chunks=1
    )
    # The workers idle first (the shared cluster may still be finishing an earlier test's
    # work): the CPU they use from here on is this compute's, so that "under way" below means
    # that its blocks are running. Counted from before, a block that started only after the
    # cancel_all (a later call, which runs normally by design) made this test fail now and then.
    cpu_until_idle(lambda: sum(cpu(w) for w in workers))
    started = [cpu(w) for w in workers]

    def under_way(_: float) -> bool:  # each worker has run its block for 0.3 s of CPU
        return all(cpu(w) - c >= 0.3 for w, c in zip(workers, started, strict=True))

    with sigint_raises():
        record = interrupt(lambda: lazy.compute(), under_way)
    assert not record.returned and isinstance(record.raised, KeyboardInterrupt), record
    used, wall = cpu_until_idle(lambda: sum(cpu(w) for w in workers))
    assert used <= CPU_BOUND, f"the workers used {used:.2f} s CPU in the {wall:.2f} s until idle"
    # A later compute on the same workers runs normally.
    np.testing.assert_array_equal(short_compute().omega, expected)


@pytest.mark.parametrize(
    "options",
    [{"method": "exact"}, {"method": "rk4", "dt": 0.01}, {"method": "dop853"}],
    ids=["exact", "rk4", "dop853"],
)
def test_a_sweep_is_indexed_like_an_array_lazily(bodies, options):
    moments, omega0 = bodies
    moments, omega0 = moments[:10], omega0[:10]
    lazy = phd.simulate(da.from_array(moments, chunks=4), omega0, 3.0, chunks=4, **options)
    assert len(lazy) == 10
    # polhode.simulate's times for the whole batch, whichever bodies are then picked.
    whole = ph.simulate(moments, omega0, 3.0, **options)
    assert np.array_equal(lazy.t, whole.t)
    for k in (0, 3, 9, -1):
        one = lazy[k]
        assert isinstance(one.omega, da.Array) and one.omega.shape == (lazy.t.size, 3)
        with pytest.raises(TypeError, match="no batch"):
            len(one)
        alone = ph.simulate(moments[k % 10], omega0[k % 10], lazy.t, **options)
        assert one.compute(scheduler="sync") == alone
        assert one.persist(scheduler="sync").compute(scheduler="sync") == alone
    for key in (slice(2, 7), [1, 8, 3], np.arange(10) % 3 == 0):
        part = lazy[key]
        assert isinstance(part.omega, da.Array) and len(part) == len(np.arange(10)[key])
        picked = np.arange(10)[key]
        expected = ph.simulate(moments[picked], omega0[picked], lazy.t, **options)
        assert part.compute(scheduler="sync") == expected
    with pytest.raises(IndexError):
        lazy[10]
    with pytest.raises(TypeError, match="index a batch"):
        lazy[1.5]


def test_a_batch_analysis_is_indexed_like_an_array(bodies):
    moments, omega0 = bodies
    lazy = phd.analyze(da.from_array(moments[:12], chunks=5), omega0[:12])
    assert len(lazy) == 12
    computed = lazy.compute(scheduler="sync")
    for result in (lazy, computed):
        for k in (0, 5, 11, -2):
            one = result[k]
            if one is not computed[k]:
                one = one.compute(scheduler="sync") if isinstance(one.energy, da.Array) else one
            a = ph.analyze(moments[k % 12], omega0[k % 12])
            assert np.array_equal(one.moments, a.moments) and np.array_equal(one.omega, a.omega)
            assert one.energy == a.energy and one.regime == a.regime
            assert one.angular_momentum_norm == a.angular_momentum_norm
            for name in ("period", "flip_interval", "precession_rate_space"):
                value = getattr(a, name)
                got = float(getattr(one, name))  # NaN where polhode.analyze says None
                assert np.isnan(got) if value is None else got == value, name
            with pytest.raises(TypeError, match="no batch"):
                len(one)
        part = result[2:9:3]
        part = part.compute(scheduler="sync") if isinstance(part.energy, da.Array) else part
        assert len(part) == 3 and np.array_equal(part.energy, computed.energy[2:9:3])
        mask = result[np.arange(12) >= 10]
        mask = mask.compute(scheduler="sync") if isinstance(mask.energy, da.Array) else mask
        assert mask.regime.tolist() == computed.regime[10:].tolist()
