"""What a type checker sees of the trajectories (polhode ships ``py.typed``): mypy, run on a
user's script against the installed package, types every quantity of the core's table on a
``Trajectory`` (an ndarray of float64, or None where a run may lack it) and on a
``DaskTrajectory`` (a dask array), and flags an attribute that is not one. The fields are made
at run time from the table; ``polhode/_fields.pyi`` declares them (see polhode._quantities)."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from polhode import _core

pytest.importorskip("mypy")


def test_mypy_sees_every_quantity(tmp_path):
    names = [row["name"] for row in _core.QUANTITIES]
    lines = [
        "import polhode as ph",
        "import polhode.dask as phd",
        "sol = ph.simulate([1.0, 2.0, 3.0], [0.1, 1.0, 0.1], [0.0, 1.0])",
        "lazy = phd.simulate([1.0, 2.0, 3.0], [[0.1, 1.0, 0.1]], [0.0, 1.0])",
        *(f"reveal_type(sol.{name})" for name in names),
        *(f"reveal_type(lazy.{name})" for name in names),
        "reveal_type(sol.t)",
        "reveal_type(sol.moments)",
        "sol.omega_typo",
    ]
    script = tmp_path / "script.py"
    script.write_text("\n".join(lines) + "\n")
    done = subprocess.run(
        [sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path / "cache"),
         "--no-error-summary", "--follow-imports", "silent", str(script)],
        capture_output=True, text=True, cwd=tmp_path, timeout=600,
    )
    revealed = {}
    for line in done.stdout.splitlines():
        match = re.match(r".*script\.py:(\d+): note: Revealed type is \"(.*)\"", line)
        if match:
            revealed[lines[int(match.group(1)) - 1]] = match.group(2)
    # numpy writes its array type with or without the shape type, by version.
    array = r"numpy\.ndarray\[[^|]*, numpy\.dtype\[numpy\.float64\]\]"
    for row in _core.QUANTITIES:
        optional = r" \| None" if row["requires"] else ""
        got = revealed[f"reveal_type(sol.{row['name']})"]
        assert re.fullmatch(array + optional, got), (row["name"], got)
        got = revealed[f"reveal_type(lazy.{row['name']})"]
        assert re.fullmatch(r"dask\.array\.core\.Array" + optional, got), (row["name"], got)
    assert re.fullmatch(array, revealed["reveal_type(sol.t)"])
    assert re.fullmatch(array, revealed["reveal_type(sol.moments)"])
    assert re.search(r'"Trajectory" has no attribute "omega_typo"', done.stdout), done.stdout
