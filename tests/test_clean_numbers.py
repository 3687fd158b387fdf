"""Clean numbers in what polhode writes and prints: every file holds each double as the shortest
decimal that reads back to it, and none holds a negative zero; the reports print no ``-0``.

The shortest decimal is checked against numpy's own (Dragon4, ``unique=True``), written apart
from Python's ``repr``; reading back against the double itself, bit for bit.
"""

from __future__ import annotations

import csv
import json
import re
import struct

import numpy as np
import pytest

import polhode as ph
from polhode import _core
from polhode._formats import fixed_axis_rpy, number
from polhode.cli import main

#: A negative zero as text: -0, -0., -0.0, -0e0 ..., standing alone (not -0.5, not 1e-05).
NEGATIVE_ZERO = re.compile(r"(?<![\w.])-0(?:\.0*)?(?:e[+-]?\d+)?(?![\w.])")


def digits(text: str) -> str:
    """The significant digits of a decimal ('1.25e-07' -> '125')."""
    mantissa = text.lower().split("e")[0].replace("-", "").replace(".", "")
    return mantissa.strip("0") or "0"


def shortest(value: float) -> str:
    """numpy's shortest round-trip digits of ``value``."""
    return digits(np.format_float_scientific(value, unique=True, trim="-"))


def same_double(text: str, value: float) -> bool:
    return struct.pack("<d", float(text)) == struct.pack("<d", value + 0.0)


def doubles(count: int = 20000) -> np.ndarray:
    rng = np.random.default_rng(29)
    bits = rng.integers(0, 2**63 - 1, size=count, dtype=np.int64).view(np.float64)
    places = rng.integers(0, 12, size=count)
    decimals = [round(float(x), int(k))
                for x, k in zip(rng.uniform(-1e3, 1e3, size=count), places, strict=True)]
    special = [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
               0.1, 0.010000000000000002, 5.000000000000002, 0.04000000000000001, 1e-5, 1e16,
               123456789012345680.0, -1.5]
    values = np.concatenate([bits, decimals, special])
    return values[np.isfinite(values)]


def test_a_written_number_is_the_shortest_decimal_of_the_same_double():
    for value in doubles():
        text = number(value)
        assert same_double(text, float(value)), (value, text)
        assert digits(text) == shortest(float(value)), (value, text)
        assert not NEGATIVE_ZERO.fullmatch(text), (value, text)
    assert number(-0.0) == "0.0" and number(np.float64(-0.0)) == "0.0"
    assert number(np.float32(0.1)) == "0.10000000149011612"  # the float32's own value


def attribute_numbers(xml: str) -> list[str]:
    return [word for value in re.findall(r'="([^"]*)"', xml) for word in value.split()]


BODIES = {
    "cuboid": ph.Body.cuboid(1.0, [0.1, 0.2, 0.5]),
    "cylinder": ph.Body.cylinder(1.0, 0.1, 0.5),
    "shifted ellipsoid": ph.Body.ellipsoid(2.0, [0.1, 0.2, 0.3]).translated([-1.0, 0.0, -0.5]),
    "T-handle": ph.Body.cylinder(0.3, 0.01, 0.2)
    + ph.Body.cylinder(0.2, 0.01, 0.12)
    .rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    .translated([0.0, 0.0, 0.1]),
}


@pytest.mark.parametrize("name", sorted(BODIES))
def test_engine_snippets_hold_the_doubles_in_shortest_form_without_negative_zero(name):
    body = BODIES[name]
    p = body.principal()
    mjcf, urdf = body.to_mjcf(), body.to_urdf_inertial()
    for xml in (mjcf, urdf):
        words = [w for w in attribute_numbers(xml) if w != "0"]  # URDF's literal products
        assert words
        for word in words:
            assert not NEGATIVE_ZERO.fullmatch(word), (name, xml)
            assert digits(word) == shortest(float(word)), (name, word)
    # The numbers are the body's, bit for bit.
    pos = re.search(r'pos="([^"]*)"', mjcf).group(1).split()
    assert all(same_double(w, v) for w, v in zip(pos, body.center_of_mass, strict=True))
    diag = re.search(r'diaginertia="([^"]*)"', mjcf).group(1).split()
    assert all(same_double(w, v) for w, v in zip(diag, p.moments, strict=True))
    rpy = re.search(r'rpy="([^"]*)"', urdf).group(1).split()
    assert all(same_double(w, v) for w, v in zip(rpy, fixed_axis_rpy(p.axes), strict=True))


def test_the_t_handles_centre_of_mass_is_written_as_the_double_it_is():
    """``pos="0.0 0.0 0.04000000000000001"``: not noise of the writer but the centre of mass of
    the float inputs, correctly rounded (0.2 kg at float(0.1) m over 0.5 kg is
    0.0400000000000000044... m, nearer the double 0.04000000000000001 than 0.04); written as
    the shortest decimal that reads back to it."""
    from fractions import Fraction

    exact = Fraction(0.2) * Fraction(0.1) / Fraction(0.5)
    assert float(exact) == 0.04000000000000001 != 0.04
    com = BODIES["T-handle"].center_of_mass
    assert com[2] == float(exact)
    assert 'pos="0.0 0.0 0.04000000000000001"' in BODIES["T-handle"].to_mjcf()


def test_the_cuboid_urdf_had_a_negative_zero():
    """Its roll was written ``-0.0`` (atan2(-0.0, 1.0)): now 0.0, the same rotation."""
    urdf = BODIES["cuboid"].to_urdf_inertial()
    assert 'rpy="0.0 -1.5707963267948966 0.0"' in urdf


def test_spin_csv_has_no_negative_zero(tmp_path, capsys):
    """About its intermediate axis exactly, the quaternion's x component is a signed zero at
    some output times; the CSV writes 0.0."""
    path = tmp_path / "run.csv"
    argv = ["spin", "--moments", "1", "2", "3", "--omega", "0", "-1", "0", "--t", "10"]
    assert main([*argv, "--points", "5", "--csv", str(path)]) == 0
    capsys.readouterr()
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    cells = [cell for row in rows[1:] for cell in row]
    assert not [c for c in cells if NEGATIVE_ZERO.fullmatch(c)], rows
    sol = ph.simulate([1.0, 2.0, 3.0], [0.0, -1.0, 0.0], np.linspace(0.0, 10.0, 5))
    # The CSV holds the output times and every quantity of the run, in the table's order.
    quantities = [getattr(sol, row["name"]) for row in _core.QUANTITIES]
    expected = np.column_stack([sol.t] + [q.reshape(5, -1) for q in quantities if q is not None])
    for row, values in zip(rows[1:], expected, strict=True):
        assert all(same_double(c, v) for c, v in zip(row, values, strict=True))
        assert all(digits(c) == shortest(float(c)) for c in row)


def test_inertia_json_has_no_negative_zero(tmp_path, capsys):
    trimesh = pytest.importorskip("trimesh")
    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=[0.4, 0.2, 0.1]).export(path)
    assert main(["inertia", str(path), "--density", "1000", "--json"]) == 0
    out = capsys.readouterr().out
    assert "-0.0" not in out.replace("e-0", "e_0")
    values = json.loads(out)
    body = ph.Body.from_file(str(path), density=1000.0)
    assert np.array_equal(values["inertia"], body.inertia)  # -0.0 == 0.0: the same numbers


def test_the_demo_prints_no_negative_zero(capsys):
    assert main(["demo", "--no-plots"]) == 0
    out = capsys.readouterr().out
    found = [line for line in out.splitlines() if NEGATIVE_ZERO.search(line)]
    assert not found, found
    # The cylinder's axes, which printed [ 0. -0.  1.] before.
    assert "axes            1: [0 0 1]  2: [1 0 0]  3: [0 1 0]" in out
