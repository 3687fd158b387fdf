"""The README's first ten minutes: its first command installs what the demo needs and no heavy
extra, the `all` extra what its examples use, its Python examples run as written, and its Rust
examples are whole programs with the nalgebra version that the crate uses (``cargo test``
compiles and runs them as doctests).
"""

from __future__ import annotations

import ast
import os
import re
import subprocess
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

#: The extras that must stay out of the first command: heavy, and not needed by the demo.
HEAVY = ("robots", "chem", "dask", "mesh")


def extra_requirements(project, extra: str) -> set[str]:
    """The distributions an extra names, the extras it names of polhode itself (``all``)
    expanded."""
    names = set()
    for requirement in project["optional-dependencies"][extra]:
        name = requirement_name(requirement)
        if name == "polhode":
            inner = re.search(r"\[([a-z,]+)\]", requirement)
            assert inner, requirement
            for other in inner.group(1).split(","):
                names |= extra_requirements(project, other)
        else:
            names.add(name)
    return names


def pyproject_project():
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def first_command_extras() -> list[str]:
    first = blocks("sh")[0].strip()
    match = re.fullmatch(r"pip install '\.\[([a-z,]+)\]' && polhode demo", first)
    assert match, f"the first command is one install and the demo: {first!r}"
    return match.group(1).split(",")


def test_first_command_installs_the_demo_and_no_heavy_extra():
    extras = first_command_extras()
    assert extras == ["plot"], extras
    project = pyproject_project()
    assert {"matplotlib", "plotly"} <= extra_requirements(project, "plot")
    heavy = set().union(*(extra_requirements(project, e) for e in HEAVY))
    light = {requirement_name(r) for r in project["dependencies"]}
    light |= extra_requirements(project, "plot")
    assert not heavy & light - {"matplotlib"}, heavy & light  # nothing heavy comes with it


def test_all_installs_what_the_examples_use_and_the_readme_says_so():
    project = pyproject_project()
    installed = {requirement_name(r) for r in project["dependencies"]}
    installed |= extra_requirements(project, "all")
    for extra in ("plot", "progress", *HEAVY):  # every feature, not the benchmarks' peers
        assert extra_requirements(project, extra) <= installed, extra
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
    assert {"numpy", "scipy", "dask", "tqdm", "matplotlib", "trimesh", "ase"} <= needed
    assert needed <= installed, f"the all extra leaves out {sorted(needed - installed)}"
    assert "pip install '.[all]'" in text


def _closure(names: set[str]) -> set[str]:
    """The installed distributions ``names`` need, their dependencies' included (markers of
    extras left out), normalised."""
    from importlib import metadata

    def norm(name: str) -> str:
        return re.sub(r"[-_.]+", "-", name).lower()

    seen: set[str] = set()
    todo = [norm(n) for n in names]
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        try:
            requires = metadata.requires(name) or []
        except metadata.PackageNotFoundError:
            continue
        for requirement in requires:
            if "extra ==" in requirement:
                continue
            todo.append(norm(requirement_name(requirement)))
    return seen


#: Run by ``python -c``: the demo with every top-level module named in argv[2:] unimportable
#: (as if not installed), then the files it wrote and the modules it imported.
_DEMO_WITHOUT = """
import sys
blocked = set(sys.argv[2:])

class Absent:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in blocked:
            raise ModuleNotFoundError(f"No module named {name!r} (not installed)", name=name)
        return None

sys.meta_path.insert(0, Absent())
from polhode.cli import main
assert main(["demo", "--out", sys.argv[1]]) == 0
print("MODULES", " ".join(sorted({m.split(".")[0] for m in sys.modules})))
"""


def test_the_demo_runs_with_only_what_the_first_command_installs(tmp_path):
    """The demo, with its plots, its animation and its scene, in a fresh interpreter where
    every package outside polhode's dependencies and the first command's extras (and what they
    depend on) cannot be imported, as in a fresh environment of the first command."""
    pytest.importorskip("matplotlib")
    pytest.importorskip("plotly")
    from importlib import metadata

    project = pyproject_project()
    allowed = {requirement_name(r) for r in project["dependencies"]}
    for extra in first_command_extras():
        allowed |= extra_requirements(project, extra)
    allowed = _closure(allowed) | {"polhode"}
    blocked = sorted(
        module
        for module, dists in metadata.packages_distributions().items()
        if not {re.sub(r"[-_.]+", "-", d).lower() for d in dists} & allowed
    )
    assert {"mujoco", "trimesh", "ase", "dask", "tqdm"} <= set(blocked)  # installed, blocked
    out = tmp_path / "demo"
    env = {**os.environ, "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "-c", _DEMO_WITHOUT, str(out), *blocked],
                          capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "skipped" not in done.stdout  # no plot and no scene left out
    written = {p.name for p in out.iterdir()}
    assert {"poinsot.html", "tennis_racket.gif", "flip_omega.png"} <= written, written
    assert len(written) == 9, written
    modules = set(done.stdout.split("MODULES ")[1].split())
    assert {"matplotlib", "plotly"} <= modules


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
