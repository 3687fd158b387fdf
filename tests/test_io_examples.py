"""The Examples sections of polhode.io, Body.from_file, Body.spatial_inertia,
Body.from_spatial_inertia and FileFormatError run as written (doctest)."""

from __future__ import annotations

import doctest

import pytest

import polhode as ph
import polhode.io

pytest.importorskip("trimesh")
pytest.importorskip("yourdfpy")
pytest.importorskip("mujoco")

OBJECTS = [
    polhode.io,
    polhode.io.read_mesh,
    polhode.io.read_urdf,
    polhode.io.read_mjcf,
    polhode.io.audit,
    ph.Body.from_file,
    ph.Body.spatial_inertia,
    ph.Body.from_spatial_inertia,
    ph.errors.FileFormatError,
]


@pytest.mark.parametrize("obj", OBJECTS, ids=lambda o: getattr(o, "__qualname__", o.__name__))
def test_examples_run(obj):
    finder = doctest.DocTestFinder(recurse=False)
    tests = finder.find(obj, globs={})
    assert tests and any(t.examples for t in tests), "no Examples section"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0
