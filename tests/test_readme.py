"""The README's first ten minutes: its first command installs what its examples use, its
Python examples run as written, and its Rust examples are whole programs with the nalgebra
version that the crate uses (``cargo test`` compiles and runs them as doctests).
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    tomllib = pytest.importorskip("tomli")

pytestmark = pytest.mark.skipif(not README.is_file(), reason="not run from the repository")


def blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README.read_text(encoding="utf-8"), re.S)


def requirement_name(requirement: str) -> str:
    return re.split(r"[\[<>=!~; ]", requirement.strip(), maxsplit=1)[0].lower()


#: What an example needs beyond its imports: a keyword or a command and the package behind it.
IMPLIED = {r"progress=True": "tqdm", r"polhode demo": "matplotlib"}

#: Import names whose package has another name.
PACKAGE_OF = {"polhode.dask": "dask", "polhode.plot": "matplotlib"}


def test_first_command_installs_what_the_examples_use():
    first = blocks("sh")[0].strip()
    match = re.fullmatch(r"pip install '\.\[([a-z,]+)\]' && polhode demo", first)
    assert match, f"the first command is one install and the demo: {first!r}"
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    project = pyproject["project"]
    installed = {requirement_name(r) for r in project["dependencies"]}
    for extra in match.group(1).split(","):
        installed |= {requirement_name(r) for r in project["optional-dependencies"][extra]}

    needed = set()
    text = README.read_text(encoding="utf-8")
    for code in blocks("python"):
        for node in ast.walk(ast.parse(code)):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            for name in names:
                if name in PACKAGE_OF:
                    needed.add(PACKAGE_OF[name])
                elif name.split(".")[0] not in {"polhode", *sys.stdlib_module_names}:
                    needed.add(name.split(".")[0])
    needed |= {package for pattern, package in IMPLIED.items() if re.search(pattern, text)}
    assert {"numpy", "scipy", "dask", "tqdm", "matplotlib"} <= needed  # the parse found them
    assert needed <= installed, f"the first command leaves out {sorted(needed - installed)}"


@pytest.mark.parametrize("index", range(len(blocks("python")) if README.is_file() else 0))
def test_python_example_runs(index, capsys):
    pytest.importorskip("dask")
    pytest.importorskip("tqdm")
    exec(compile(blocks("python")[index], f"README.md python block {index + 1}", "exec"), {})


def test_rust_examples_are_whole_programs_with_the_crates_nalgebra():
    rust = blocks("rust")
    assert len(rust) >= 2
    for code in rust:
        assert "fn main() -> Result<(), polhode::Error> {" in code, code[:200]
        assert not re.search(r"^\s*# ", code, re.M)  # no line hidden from the reader by rustdoc
    (toml,) = blocks("toml")
    wanted = tomllib.loads(toml)["dependencies"]
    workspace = tomllib.loads((ROOT / "Cargo.toml").read_text(encoding="utf-8"))
    ours = workspace["workspace"]["dependencies"]["nalgebra"]
    # The version the crate is built with (its features are the crate's own business).
    assert wanted["nalgebra"] == (ours["version"] if isinstance(ours, dict) else ours)
    assert wanted["polhode"]["path"].endswith("rust/polhode")
    # The crate runs them as doctests.
    lib = (ROOT / "rust" / "polhode" / "src" / "lib.rs").read_text(encoding="utf-8")
    assert 'include_str!("../../../README.md")' in lib
