"""The core's table of output quantities (``polhode._core.QUANTITIES``): what each quantity is
(its name, shape, SI unit and frame, written here from the physics, not read from polhode), that
``simulate`` returns exactly those quantities with those shapes, and that the binding's fields
follow the table."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

import polhode as ph
from polhode import _core, _quantities, simulation

#: What each output is, from the physics: (shape per output time, SI unit, frame).
EXPECTED = {
    "omega": ((3,), "rad/s", "body"),
    "omega_space": ((3,), "rad/s", "space"),
    "quaternion": ((4,), "1", "none"),
    "angular_momentum_space": ((3,), "kg m^2/s", "space"),
    "angular_momentum_body": ((3,), "kg m^2/s", "body"),
    "energy": ((), "J", "none"),
    "rotor_rates": (("rotors", 3), "rad/s", "body"),
}


def test_the_table_describes_every_output():
    rows = {row["name"]: row for row in _core.QUANTITIES}
    assert list(rows) == list(EXPECTED)
    for name, (shape, unit, frame) in EXPECTED.items():
        row = rows[name]
        assert row["shape"] == shape, name
        assert row["unit"] == unit, name
        assert row["frame"] == frame, name
        assert row["description"] and "\n" not in row["description"], name
    assert rows["quaternion"]["requires"] == ("orientation",)
    assert rows["omega_space"]["requires"] == ("orientation",)
    assert rows["angular_momentum_space"]["requires"] == ("orientation",)
    assert rows["rotor_rates"]["requires"] == ("rotors",)
    assert rows["omega"]["requires"] == ()


def test_the_trajectory_fields_follow_the_table():
    fields = [f.name for f in dataclasses.fields(ph.Trajectory)]
    names = [row["name"] for row in _core.QUANTITIES]
    assert fields == ["t", *names, "moments", "stats"]


@pytest.mark.parametrize("orientation", [True, False])
@pytest.mark.parametrize("rotors", [0, 2])
@pytest.mark.parametrize("n", [None, 3])
def test_simulate_returns_the_table_with_its_shapes(orientation, rotors, n):
    wheels = [ph.rotors.Wheel((1.0, 0.0, 0.0), 0.01, 0.0) for _ in range(rotors)]
    omega0 = np.array([0.1, 1.0, 0.2]) if n is None else np.tile([0.1, 1.0, 0.2], (n, 1))
    t = np.linspace(0.0, 1.0, 5)
    sol = ph.simulate(
        [1.0, 2.0, 3.0], omega0, t, orientation=orientation, rotors=wheels or None,
        method="dop853" if rotors else "exact",
    )
    lead = () if n is None else (n,)
    for row in _core.QUANTITIES:
        value = getattr(sol, row["name"])
        present = ("orientation" not in row["requires"] or orientation) and (
            "rotors" not in row["requires"] or rotors
        )
        if not present:
            assert value is None, row["name"]
            continue
        shape = tuple(rotors if d == "rotors" else d for d in row["shape"])
        assert value.shape == (*lead, t.size, *shape), row["name"]
        assert np.isfinite(value).all(), row["name"]


def test_the_core_simulate_takes_its_settings_by_keyword():
    with pytest.raises(TypeError):
        _core.simulate(np.array([1.0, 2.0, 3.0]), np.array([0.1, 1.0, 0.1]), np.zeros(2), None)
    out = _core.simulate(
        np.array([1.0, 2.0, 3.0]), np.array([0.1, 1.0, 0.1]), np.zeros(2), method="exact"
    )
    assert out["stats"]["method"] == "exact"


def test_the_typed_fields_are_the_table():
    # _fields.pyi, which type checkers read for the trajectories' fields, is generated from the
    # table: regenerate it with `python scripts/fields_stub.py`.
    assert _quantities.STUB.read_text(encoding="utf-8") == _quantities.stub()
    for row in _core.QUANTITIES:
        optional = " | None" if row["requires"] else ""
        assert f"\n    {row['name']}: _A{optional}\n" in _quantities.stub(), row["name"]


def test_the_dask_trajectory_fields_follow_the_table():
    phd = pytest.importorskip("polhode.dask")
    fields = [f.name for f in dataclasses.fields(phd.DaskTrajectory)]
    names = [row["name"] for row in _core.QUANTITIES]
    assert fields == ["t", *names, "moments", "steps", "rejected_steps", "evaluations", "method",
                      "records", "sampling", "single"]


@pytest.mark.parametrize("kind", ["Trajectory", "DaskTrajectory"])
def test_the_docs_describe_every_quantity(kind):
    if kind == "Trajectory":
        doc, array, lead = ph.Trajectory.__doc__, "numpy.ndarray", "..."
    else:
        doc = pytest.importorskip("polhode.dask").DaskTrajectory.__doc__
        array, lead = "dask.array.Array", "N"
    text = " ".join(doc.split())
    for row in _core.QUANTITIES:
        dims = ", ".join(["M", *("R" if d == "rotors" else str(d) for d in row["shape"])])
        kind_text = f"{array} or None" if row["requires"] else array
        entry = f"{row['name']} : ({lead}, {dims}) {kind_text}"
        assert entry in text, entry
        after = text.split(entry)[1]
        description = row["description"][:1].upper() + row["description"][1:]
        assert after.startswith(f" {description}"), row["name"]
        if row["unit"] != "1":
            assert after.split(" : ")[0].count(f"({row['unit']})"), row["name"]


@pytest.mark.parametrize("orientation", [True, False])
@pytest.mark.parametrize("rotors", [0, 2])
def test_the_memory_check_counts_every_output(orientation, rotors, monkeypatch):
    # The memory check's estimate is the bytes of the outputs a run returns, whatever they are.
    wheels = [ph.rotors.Wheel((1.0, 0.0, 0.0), 0.01, 0.0) for _ in range(rotors)]
    omega0 = np.tile([0.1, 1.0, 0.2], (4, 1))
    t = np.linspace(0.0, 1.0, 7)
    sol = ph.simulate([1.0, 2.0, 3.0], omega0, t, orientation=orientation, rotors=wheels or None)
    returned = sum(
        getattr(sol, row["name"]).nbytes
        for row in _core.QUANTITIES
        if getattr(sol, row["name"]) is not None
    )
    assert _quantities.numbers_per_time(orientation, rotors) * 8 * 4 * 7 == returned
    estimated = []
    monkeypatch.setattr(simulation, "_ALWAYS_FITS", 0)
    monkeypatch.setattr(simulation, "_available_memory", lambda: estimated.append(1) or 1)
    with pytest.raises(MemoryError, match=re.escape(f"take {float(returned):.3g} bytes")):
        ph.simulate([1.0, 2.0, 3.0], omega0, t, orientation=orientation, rotors=wheels or None)
    assert estimated == [1]


#: Runs of every kind: each method, a body in non-principal axes, a torque, rotors.
OMEGA_SPACE_RUNS = {
    "exact": {"method": "exact"},
    "splitting": {"method": "splitting", "dt": 1e-3},
    "midpoint": {"method": "midpoint", "dt": 1e-3},
    "rk4": {"method": "rk4", "dt": 1e-3},
    "dop853": {"method": "dop853"},
    "torque": {"torque": ph.torque.SpaceFixed([0.0, 0.002, 0.001])},
    "rotors": {"rotors": [ph.rotors.Wheel([0.0, 0.0, 1.0], 0.001, 5.0),
                          ph.rotors.SphericalDamper(0.0005, 0.0005)]},
}


@pytest.mark.parametrize("run", sorted(OMEGA_SPACE_RUNS))
@pytest.mark.parametrize("batch", [False, True])
def test_omega_space_is_omega_turned_into_space(run, batch):
    """omega_space, the angular velocity in space axes, is R(q) omega at every output time:
    scipy's rotation of the run's own omega by its own orientation (to rounding), for a body
    given in its own, non-principal axes, one or a batch."""
    from scipy.spatial.transform import Rotation

    turn = Rotation.from_euler("xyz", [0.3, -0.5, 1.1])
    body = ph.Body.cuboid(1.0, [0.3, 0.2, 0.1]).rotated(turn)
    omega0 = np.array([0.3, 1.0, -0.2])
    if batch:
        omega0 = np.array([omega0, [1.0, 0.1, 0.2], [-0.2, 0.3, 2.0]])
    t = np.linspace(0.0, 3.0, 13)
    sol = ph.simulate(body, omega0, t, orientation0=[0.1, 0.2, 0.3, 0.9],
                      **OMEGA_SPACE_RUNS[run])
    quaternion = sol.quaternion.reshape(-1, 4)
    expected = Rotation.from_quat(quaternion).apply(sol.omega.reshape(-1, 3))
    got = sol.omega_space.reshape(-1, 3)
    scale = np.linalg.norm(expected, axis=1, keepdims=True)
    assert np.all(np.abs(got - expected) <= 8 * np.finfo(float).eps * scale)
    assert sol.omega_space.shape == sol.omega.shape
    # Without the orientation there is none.
    bare = ph.simulate(body, omega0, t, orientation=False, **OMEGA_SPACE_RUNS[run])
    assert bare.omega_space is None


def test_omega_space_is_everywhere_a_quantity_is(tmp_path, capsys):
    """A quantity added to the core's table reaches every place that follows the table: the
    Trajectory, DaskTrajectory (bit for bit the Trajectory's), the memory check, the CSV of
    polhode spin and the docs."""
    from polhode.cli import main

    t = np.linspace(0.0, 5.0, 11)
    sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.2], t)
    assert sol.omega_space.shape == (11, 3)
    phd = pytest.importorskip("polhode.dask")
    lazy = phd.simulate([1.0, 2.0, 3.0], [[0.01, 1.0, 0.2], [0.3, 0.2, 1.0]], t, chunks=1)
    alone = ph.simulate([1.0, 2.0, 3.0], [[0.01, 1.0, 0.2], [0.3, 0.2, 1.0]], t)
    assert lazy.omega_space.shape == (2, 11, 3)
    assert np.array_equal(lazy.omega_space.compute(), alone.omega_space)
    assert np.array_equal(lazy.compute().omega_space, alone.omega_space)
    # omega, omega_space, the quaternion, L in space and in the body, T: 3 + 3 + 4 + 3 + 3 + 1.
    assert _quantities.numbers_per_time(True, 0) == 17
    assert _quantities.numbers_per_time(False, 0) == 7
    path = tmp_path / "run.csv"
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "1", "0.2", "--t", "5",
            "--points", "11", "--csv", str(path)]
    assert main(argv) == 0
    capsys.readouterr()
    with path.open() as handle:
        header = handle.readline().rstrip("\n").split(",")
    columns = [f"omega_space_{c} (rad/s)" for c in "xyz"]
    assert header[4:7] == columns  # after omega, in the table's order
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert data[:, 4:7].tolist() == sol.omega_space.tolist()
    for doc in (ph.Trajectory.__doc__, phd.DaskTrajectory.__doc__):
        assert "omega_space : (" in doc and "Angular velocity, space axes (rad/s)." in doc
