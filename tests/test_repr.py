"""Short reprs and HTML tables of Body, Principal, Analysis and Trajectory.

A repr is a few hundred characters whatever the size of the arrays (the README's heavy top
printed 14 kB before), holds no numpy ``array(`` dump, and its numbers are the object's values
to 6 significant digits; the HTML table has one row per summary entry with the same values.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser

import numpy as np
import pytest

import polhode as ph

MOMENTS = [3.0, 5.0, 9.0]
OMEGA0 = np.array([0.0, 2.0, 0.01]) / MOMENTS


class Rows(HTMLParser):
    """The (header, cell text) rows of the outer table of a summary, and its caption."""

    def __init__(self, text):
        super().__init__()
        self.rows, self.caption, self._cell, self._depth, self._in = [], "", [], 0, None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self._depth += 1
        elif self._depth == 1 and tag in ("th", "td", "caption"):
            self._in, self._cell = tag, []
        elif self._depth == 2 and tag == "td":
            self._cell.append(" ")

    def handle_endtag(self, tag):
        if tag == "table":
            self._depth -= 1
        elif self._depth == 1 and tag == self._in:
            text = "".join(self._cell).strip()
            if tag == "caption":
                self.caption = text
            elif tag == "th":
                self.rows.append([text])
            else:
                self.rows[-1].append(text)
            self._in = None

    def handle_data(self, data):
        if self._in:
            self._cell.append(data)


def numbers(text):
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]\d+)?", text)]


def assert_short(text, limit=400):
    assert len(text) <= limit, (len(text), text)
    assert "array(" not in text and "\n" not in text, text


def test_body():
    shaft = ph.Body.cylinder(0.3, 0.01, 0.2)
    bar = ph.Body.cylinder(0.2, 0.01, 0.12).rotated([[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    body = shaft + bar.translated([0.0, 0.0, 0.1])
    text = repr(body)
    assert_short(text)
    # Mass 0.5; centre of mass at z = 0.2 * 0.1 / 0.5 = 0.04, by hand.
    assert text.startswith("Body(mass=0.5, center_of_mass=[0, 0, 0.04], principal_moments=[")
    np.testing.assert_allclose(
        numbers(text.split("principal_moments")[1]), body.principal().moments, rtol=5e-6
    )
    rows = dict(Rows(body._repr_html_()).rows)
    assert float(rows["mass"]) == 0.5
    np.testing.assert_allclose(
        numbers(rows["inertia (about the centre of mass)"]),
        body.inertia.ravel(),
        rtol=5e-6,
        atol=1e-12,
    )
    np.testing.assert_allclose(
        numbers(rows["principal axes (columns)"]),
        body.principal().axes.ravel(),
        rtol=5e-6,
        atol=1e-12,
    )


def test_principal_single_and_batch():
    p = ph.principal(np.diag([1.0, 2.0, 2.0]))
    assert repr(p) == (
        "Principal(moments=[1, 2, 2], multiplicity=[1, 2, 2], "
        "axes=[[1, 0, 0], [0, 1, 0], [0, 0, 1]])"
    )
    batch = ph.principal(np.tile(np.diag([1.0, 2.0, 3.0]), (100_000, 1, 1)))
    text = repr(batch)
    assert_short(text)
    assert text == (
        "Principal(100000 tensors: moments (100000, 3), axes (100000, 3, 3), "
        "multiplicity (100000, 3))"
    )
    rows = dict(Rows(batch._repr_html_()).rows)
    assert rows["tensors"] == "100000" and rows["axes (columns)"] == "(100000, 3, 3)"
    rows = dict(Rows(p._repr_html_()).rows)
    assert numbers(rows["moments (ascending)"]) == [1, 2, 2]


def test_analysis():
    a = ph.analyze(MOMENTS, OMEGA0)
    text = repr(a)
    assert_short(text, 500)
    assert text.startswith("Analysis(regime='about_largest_axis', moments=[3, 5, 9], ")
    summary = dict(Rows(a._repr_html_()).rows)
    for name in ("energy", "angular_momentum_norm", "period", "flip_interval"):
        value = getattr(a, name)
        assert f"{name}={float(summary[name]):.6g}" in text
        assert float(summary[name]) == pytest.approx(value, rel=5e-6)
    # The flip interval of I = (3, 5, 9) spun near the intermediate axis: half the period.
    assert float(summary["flip_interval"]) == pytest.approx(a.period / 2, rel=5e-6)
    assert summary["precession_rate_body"] == "None"  # not a symmetric top
    assert float(summary["precession_rate_space"]) == pytest.approx(
        a.precession_rate_space, rel=5e-6
    )
    # It turns over: no nutation angle (the axis tumbles); a stable spin has one.
    assert summary["nutation_angle"] == "None" and "turns_over=True" in text
    stable = dict(Rows(ph.analyze(MOMENTS, [0.01, 0.02, 1.0])._repr_html_()).rows)
    assert stable["nutation_angle"].startswith("(") and stable["turns_over"] == "False"
    assert "axis_stability=('stable', 'unstable', 'stable')" in text
    assert "linearized={axis=1, kind='growth', rate=" in text


def test_trajectory_of_the_readme_heavy_top_is_one_line():
    top = ph.Body.cone(0.1, 0.04, 0.03)
    t = np.linspace(0, 2, 2001)
    sol = ph.simulate(
        top,
        [0, 0, -150.0],
        t,
        orientation0=[0.995, 0, 0, 0.0998],
        torque=ph.torque.Gravity(pivot=[0, 0, 0.03]),
    )
    text = repr(sol)
    assert_short(text)
    assert text.startswith("Trajectory(bodies=1, times=2001 in [0, 2], method='dop853', ")
    assert f"steps={sol.stats['steps']}," in text
    assert "orientation=yes" in text
    rows = dict(Rows(sol._repr_html_()).rows)
    assert float(rows["energy_t0"]) == pytest.approx(sol.energy[0], rel=5e-6)
    assert f"energy_t0={rows['energy_t0']}," in text
    assert rows["omega"] == "(2001, 3)" and rows["quaternion"] == "(2001, 4)"
    np.testing.assert_allclose(numbers(rows["moments"]), sol.moments, rtol=5e-6)


def test_trajectory_of_a_large_batch_prints_shapes_not_arrays():
    n = 100_000
    sol = ph.simulate(
        np.tile(MOMENTS, (n, 1)), np.tile(OMEGA0, (n, 1)), [0.0, 1.0], orientation=False
    )
    text = repr(sol)
    assert_short(text)
    assert "bodies=100000, times=2 in [0, 1], method='exact', moments=(100000, 3)" in text
    assert "orientation=no" in text and "energy" not in text
    rows = dict(Rows(sol._repr_html_()).rows)
    assert rows["quaternion"] == "None" and rows["energy"] == "(100000, 2)"
    assert Rows(sol._repr_html_()).caption == "Trajectory"
