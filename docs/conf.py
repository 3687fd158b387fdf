"""Sphinx configuration of the polhode documentation site (built by ``bash scripts/docs.sh``).

The API reference is generated from the installed package: ``api/index.rst`` is written here
from :func:`polhode._api.public_names` (every name of ``polhode.__all__`` and of the public
submodules' ``__all__``), and autosummary writes one page per name from its docstring. The
Markdown pages (the user guide, ``architecture.md``, ``benchmarks.md``, the README) are read by
myst-parser; the gallery's examples (``examples/plot_*.py``) run at build time.
"""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path

import polhode
from polhode import _api

HERE = Path(__file__).resolve().parent

project = "polhode"
author = "the polhode developers"
copyright = "the polhode developers"  # noqa: A001  (Sphinx's name)
version = release = polhode.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "examples", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "**/*.md5", "**/*.pickle"]
templates_path = ["_templates"]

# --- API reference ------------------------------------------------------------------------------

autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"  # the numpydoc Parameters say the types, in words
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False


def _title(module: str) -> str:
    return "Top level: ``polhode``" if module == "polhode" else f"``{module}``"


def write_api_index() -> None:
    """``api/index.rst``: one section per module of :func:`polhode._api.public_names`."""
    lines = [
        "API reference",
        "=============",
        "",
        "Every public name: those of ``polhode.__all__`` at the top level, then each public",
        "module's own. Each page is generated from the docstring, and every function and class",
        "has an Examples section that the tests run (``tests/test_docstrings.py``).",
        "Not listed: "
        + "; ".join(f"``{name}``, {why}" for name, why in _api.NOT_API.items())
        + ".",
        "",
    ]
    for module, names in _api.public_names().items():
        title = _title(module)
        lines += [title, "-" * len(title), ""]
        if module != "polhode":
            summary = (importlib.import_module(module).__doc__ or "").strip().splitlines()
            if summary:
                lines += [summary[0], ""]
        lines += [
            f".. currentmodule:: {module}",
            "",
            ".. autosummary::",
            "   :toctree: generated",
            "   :nosignatures:",
            "",
        ]
        lines += [f"   {name}" for name in names]
        lines += [""]
    target = HERE / "api" / "index.rst"
    target.parent.mkdir(exist_ok=True)
    text = "\n".join(lines)
    if not target.exists() or target.read_text() != text:
        target.write_text(text)


write_api_index()

# --- Markdown -----------------------------------------------------------------------------------

myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3


# --- Gallery ------------------------------------------------------------------------------------

os.environ.setdefault("MPLBACKEND", "Agg")
sphinx_gallery_conf = {
    "examples_dirs": "examples",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "matplotlib_animations": (True, "jshtml"),
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "show_memory": False,
    "capture_repr": (),  # print() shows what an example means to show; no stray reprs
}

# --- HTML ---------------------------------------------------------------------------------------

html_theme = "pydata_sphinx_theme"
html_title = f"polhode {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    "secondary_sidebar_items": ["page-toc"],
}
html_static_path: list[str] = []
html_show_sourcelink = False

sys.dont_write_bytecode = True


def _hide_internal_constructor(app, what, name, obj, options, signature, return_annotation):
    """``Body(core, shape)`` is built by its constructors (``Body.sphere``...), not called."""
    if what == "class" and name == "polhode.Body":
        return "", return_annotation
    return None


def setup(app):
    app.connect("autodoc-process-signature", _hide_internal_constructor)
