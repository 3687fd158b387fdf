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
                      "records"]


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
