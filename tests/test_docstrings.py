"""The examples in the docstrings and in the user guide run, and say what they print.

Every docstring of every module of the installed package is run with :mod:`doctest` (with
``filterwarnings = error``, a warning fails it), and every public function and class of the
API reference (:func:`polhode._api.objects`) has an Examples section with at least one
example. The Python blocks of each page of the user guide (``docs/guide/*.md``) run in order in
one namespace, as a reader would paste them.
"""

from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

import polhode
from polhode import _api

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "guide"

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def module_names():
    """Every module of the installed package but ``__main__`` (importing it runs the CLI)."""
    names = ["polhode"]
    for info in pkgutil.walk_packages(polhode.__path__, "polhode."):
        if not info.name.endswith("__main__"):
            names.append(info.name)
    return names


def docstring_examples():
    finder = doctest.DocTestFinder(exclude_empty=True)
    found = {}
    for name in module_names():
        module = importlib.import_module(name)
        for test in finder.find(module, name):
            if test.examples:
                found[test.name] = test
    return found


EXAMPLES = docstring_examples()


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_docstring_example(name):
    test = EXAMPLES[name]
    test.globs = dict(test.globs)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    report = []
    runner.run(test, out=report.append)
    failed, attempted = runner.summarize(verbose=False)
    assert attempted > 0
    assert failed == 0, "".join(report)


def test_every_public_function_and_class_has_an_example():
    objects = _api.objects()
    assert len(objects) >= 38  # the API of this writing; new names only add to it
    missing = []
    for name, obj in objects:
        doc = inspect.getdoc(obj) or ""
        section = doc.split("Examples\n--------", 1)
        if len(section) != 2 or ">>> " not in section[1]:
            missing.append(name)
    assert not missing, f"no Examples section with an example: {missing}"


def test_every_public_name_is_documented_where_it_is_defined_or_re_exported():
    names = _api.public_names()
    assert set(names["polhode"]) == {
        n for n in polhode.__all__ if not inspect.ismodule(getattr(polhode, n))
    }
    # The modules of polhode.__all__ appear with their own names (none re-exported).
    for module in ("polhode.torque", "polhode.plot"):
        assert set(names[module]) == set(importlib.import_module(module).__all__)
    assert "polhode.errors" not in names  # every error is at the top level
    assert not any(m in names for m in _api.NOT_API)


def guide_pages():
    return sorted(GUIDE.glob("*.md")) if GUIDE.is_dir() else []


@pytest.mark.skipif(not guide_pages(), reason="the user guide (docs/guide) is not here")
@pytest.mark.parametrize("page", guide_pages(), ids=lambda p: p.name)
def test_guide_code_runs(page, capsys):
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S)
    namespace: dict = {}
    for k, block in enumerate(blocks):
        code = compile(block, f"{page.name}, block {k + 1}", "exec")
        exec(code, namespace)  # noqa: S102  (the guide's own code)


def test_every_solid_says_where_its_origin_is():
    from polhode._shapes import SOLIDS

    for name in SOLIDS:
        doc = inspect.getdoc(getattr(polhode.Body, name)) or ""
        assert "origin" in doc, name
        assert "height" not in doc, name  # one word along an axis: length
