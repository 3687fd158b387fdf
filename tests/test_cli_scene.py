"""Poinsot's construction from the command line: ``polhode spin ... --html FILE`` writes the
scene of the run (the page :func:`polhode.plot.scene` writes for the same trajectory), refuses
what the scene refuses before any work, and the demo writes ``poinsot.html`` (the T-handle's
flip) beside its plots; a headless Chromium renders the demo's page."""

from __future__ import annotations

import os
import re
import sys

import numpy as np
import pytest

import polhode
import polhode as ph
from polhode.cli import main

pytest.importorskip("plotly")

SPIN = ["spin", "--moments", "1", "2", "3", "--omega", "0.01", "5", "0.01", "--t", "6"]


def page(path) -> str:
    """The HTML with plotly's random ids of the figure's div made one."""
    html = path.read_text(encoding="utf-8")
    ids = set(re.findall(r'id="([0-9a-f-]{36})"', html))
    assert len(ids) == 1, ids
    return html.replace(ids.pop(), "FIGURE")


def refuse(*args, **kwargs):
    raise AssertionError("no work may start before the arguments are checked")


def test_spin_html_is_the_scene_of_the_run(tmp_path, capsys):
    path = tmp_path / "run.html"
    assert main([*SPIN, "--html", str(path)]) == 0
    out, err = capsys.readouterr()
    assert f"Poinsot's construction written to {path}" in out and err == ""
    # The same motion through the API (the end time: the output times polhode.simulate takes
    # for it, as spin's default): the page is the same but for plotly's random div id.
    sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 5.0, 0.01], 6.0)
    ph.plot.scene(sol, path=str(tmp_path / "api.html"))
    assert page(path) == page(tmp_path / "api.html")
    html = path.read_text(encoding="utf-8")
    assert "<script src=" not in html  # plotly.js inlined: opens offline


def test_spin_html_of_a_body_draws_that_body(tmp_path, capsys):
    argv = ["spin", "--body", "cuboid", "mass=1", "size=0.3,0.1,0.02", "--omega", "0.05", "5",
            "0.05", "--t", "6", "--points", "601"]
    path = tmp_path / "bar.html"
    assert main([*argv, "--html", str(path)]) == 0
    bar = ph.Body.cuboid(1.0, [0.3, 0.1, 0.02])
    sol = ph.simulate(bar, [0.05, 5.0, 0.05], np.linspace(0.0, 6.0, 601))
    ph.plot.scene(sol, bar, path=str(tmp_path / "api.html"))
    assert page(path) == page(tmp_path / "api.html")


def test_spin_html_with_too_few_output_times_says_to_raise_points(tmp_path, capsys):
    path = tmp_path / "few.html"
    assert main([*SPIN, "--points", "5", "--html", str(path)]) == 0
    err = capsys.readouterr().err
    assert err.startswith("polhode spin: note: --html: ") and "--points" in err
    assert path.stat().st_size > 1e6


@pytest.mark.parametrize(
    "extra, fragment",
    [
        (["--damper", "0.1", "0.1"], "not with --damper"),
        (["--wheel", "0", "0", "1", "0.1"], "not with --wheel"),
        (["--wheel", "0", "0", "1", "0.1", "--damper", "0.1", "0.1"], "--wheel and --damper"),
    ],
)
def test_spin_html_refuses_rotors_before_any_work(tmp_path, capsys, monkeypatch, extra, fragment):
    monkeypatch.setattr(polhode, "simulate", refuse)
    monkeypatch.setattr(polhode, "analyze", refuse)
    path = tmp_path / "rotors.html"
    assert main([*SPIN, *extra, "--html", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("polhode spin: error: argument --html: Poinsot's construction")
    assert fragment in err and not path.exists()


def test_spin_html_refuses_a_body_at_rest_and_a_file_written_twice(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(polhode, "simulate", refuse)
    rest = ["spin", "--moments", "1", "2", "3", "--omega", "0", "0", "0", "--t", "1"]
    assert main([*rest, "--html", str(tmp_path / "rest.html")]) == 2
    assert "argument --html: the body is at rest" in capsys.readouterr().err
    same = str(tmp_path / "same")
    assert main([*SPIN, "--csv", same, "--html", same]) == 2
    assert "argument --html: " in capsys.readouterr().err
    assert main([*SPIN, "--html", str(tmp_path / "missing" / "x.html")]) == 2
    assert "argument --html: cannot write" in capsys.readouterr().err


def test_spin_html_without_plotly_names_the_extra(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "plotly", None)
    monkeypatch.setitem(sys.modules, "plotly.graph_objects", None)
    monkeypatch.setattr(polhode, "simulate", refuse)
    assert main([*SPIN, "--html", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err
    assert "argument --html: needs plotly: pip install 'polhode[plot]'" in err


def test_the_demo_writes_poinsots_construction_of_the_flip(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    out = tmp_path / "demo"
    assert main(["demo", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    path = out / "poinsot.html"
    assert f"Poinsot's construction of the flip (open it in a browser): {path}" in printed
    html = path.read_text(encoding="utf-8")
    assert "<script src=" not in html
    # The T-handle's flip, turned so that L points up: the title says the regime, and the body
    # turns over (the marked end points toward L at the start and away from it later).
    meta = re.search(r'"meta":\s*(\{.*?\})', html)
    assert meta is not None
    assert '"mark":1' in meta.group(1).replace(" ", "")  # the axis it was spun about: I2's
    chromium = os.environ.get("CI") or _has_chromium()
    if chromium:
        _renders(path)


def _has_chromium() -> bool:
    from browser import find_chromium

    return find_chromium() is not None


def _renders(path):
    """The page in a headless Chromium: plotly draws a WebGL scene that is not blank."""
    from browser import Chromium, find_chromium

    binary = find_chromium()
    if binary is None:
        pytest.fail("CI is set but no Chromium is on the PATH (.ci/run installs chromium)")
    graph = "document.querySelector('.plotly-graph-div')"
    drawn = (
        f"(() => {{ const gd = {graph}; return !!(gd && gd._fullLayout && gd._fullLayout.scene"
        " && gd._fullLayout.scene._scene && gd.querySelector('canvas')); })()"
    )
    with Chromium(binary) as browser:
        browser.open(path.as_uri(), width=1000, height=750)
        browser.wait_for(drawn)
        browser.evaluate(
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))", True
        )
        image = browser.screenshot()
        frames = browser.evaluate(f"{graph}._transitionData._frames.length")
    h, w, _ = image.shape
    scene = image[int(0.12 * h) : int(0.8 * h), int(0.3 * w) : w]
    assert len(np.unique(scene.reshape(-1, 3), axis=0)) > 300  # shaded meshes, not blank
    assert frames == 120
