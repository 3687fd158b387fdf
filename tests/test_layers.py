"""The package shows its layers: checked on the source of the installed package (``ast``).

- No module is over 800 lines.
- No import cycle among polhode's modules. Every import counts, inside functions and under
  ``if TYPE_CHECKING:`` too (the code itself, not the examples in docstrings), and an import of
  ``polhode.a.b`` also imports the package ``polhode.a``, as Python does, unless that package is
  one the importing module sits in (it is then already being imported). ``polhode._core``, the
  compiled extension, is a leaf.
- No module takes another module's private name: ``from polhode.x import _name`` (a private
  module, ``from polhode import _core``, is fine) or ``module._name`` on a polhode module bound
  by an import. A shared helper gets a public name in a private module instead.
- The core layer (everything but the front ends below, the package's ``__init__`` that gathers
  the public names, and ``polhode._api`` that lists them for the docs) never imports a front
  end, not even inside a function.
- No module imports the package ``polhode`` itself back, but the command line, which calls the
  public API through it as a user's script does (its tests replace ``polhode.simulate`` to see
  that nothing runs before the arguments are checked), and ``polhode._api``.
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TypeVar

import polhode

T = TypeVar("T")

PACKAGE = Path(polhode.__file__).resolve().parent

#: The longest a module may be.
MAX_LINES = 800

#: The front ends: files in (io), the command line, plots, Dask and the benchmarks. They sit on
#: the core API; the core never imports them.
FRONT_ENDS = ("polhode.io", "polhode.cli", "polhode.plot", "polhode.dask", "polhode.bench")

#: Modules that are neither core nor front end: the package's ``__init__`` (the public names,
#: it imports polhode.io and polhode.plot) and the list of those names for the docs.
GATHERING = ("polhode", "polhode._api", "polhode.__main__")

#: Modules that may import the package ``polhode`` itself, and why.
IMPORT_THE_PACKAGE = {
    "polhode.cli": "the command line calls the public API as ``ph.simulate``... (its tests "
    "replace polhode.simulate and polhode.analyze to see that nothing runs early)",
    "polhode._api": "the public names are those of the package",
}

#: The compiled extension: imports nothing of polhode.
LEAVES = ("polhode._core",)


def modules(package: Path = PACKAGE) -> dict[str, Path]:
    """``{dotted name: file}`` of every Python module of the package (a package by its
    ``__init__.py``)."""
    root = package.parent
    found = {}
    for path in sorted(package.rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def _within(name: str, prefix: str) -> bool:
    return name == prefix or name.startswith(prefix + ".")


def _parents(name: str) -> list[str]:
    parts = name.split(".")
    return [".".join(parts[:k]) for k in range(1, len(parts))]


class Imports:
    """What each module imports, read from its syntax tree."""

    def __init__(self, package: Path = PACKAGE):
        self.files = modules(package)
        self.known = set(self.files) | set(LEAVES)
        #: module -> [(imported module, line)]: the modules it names, each of their parent
        #: packages it does not sit in, and for ``from X import n`` the module X.n if n is one.
        self.edges: dict[str, list[tuple[str, int]]] = {}
        #: module -> [(where, name, line)]: private names taken from another module.
        self.private: dict[str, list[tuple[str, str, int]]] = {}
        for name, path in self.files.items():
            self._read(name, path)

    def _is_package(self, name: str) -> bool:
        return self.files.get(name, Path()).name == "__init__.py"

    def _absolute(self, module: str, node: ast.ImportFrom) -> str:
        if not node.level:
            return node.module or ""
        base = module.split(".")
        if not self._is_package(module):
            base = base[:-1]
        base = base[: len(base) - (node.level - 1)]
        return ".".join(base + ([node.module] if node.module else []))

    def _add(self, module: str, target: str, line: int, explicit: bool) -> None:
        """``module`` imports ``target`` (and so its parent packages)."""
        edges = self.edges[module]
        for parent in _parents(target):
            # A package the module sits in is already being imported: not an edge.
            if parent in self.known and not _within(module, parent):
                edges.append((parent, line))
        if target in self.known and target != module:
            if explicit or not _within(module, target):
                edges.append((target, line))

    def _read(self, module: str, path: Path) -> None:
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        self.edges[module] = []
        self.private[module] = []
        bound: dict[str, str] = {}  # local name -> polhode module it is bound to
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if not _within(alias.name, "polhode"):
                        continue
                    self._add(module, alias.name, node.lineno, explicit=True)
                    if alias.asname:
                        bound[alias.asname] = alias.name
                    else:
                        bound[alias.name.split(".")[0]] = alias.name.split(".")[0]
            elif isinstance(node, ast.ImportFrom):
                source = self._absolute(module, node)
                if not _within(source, "polhode"):
                    continue
                for alias in node.names:
                    full = f"{source}.{alias.name}"
                    if full in self.known:  # a module
                        self._add(module, full, node.lineno, explicit=True)
                        bound[alias.asname or alias.name] = full
                    else:  # a name of the module `source`
                        self._add(module, source, node.lineno, explicit=True)
                        if _private(alias.name) and source != module:
                            self.private[module].append((source, alias.name, node.lineno))
        # module._name on a module bound by an import (ph.molecule._UNITS).
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and _private(node.attr):
                owner = self._module_of(node.value, bound)
                if owner is not None and f"{owner}.{node.attr}" not in self.known:
                    self.private[module].append((owner, node.attr, node.lineno))

    def _module_of(self, node: ast.expr, bound: dict[str, str]) -> str | None:
        """The polhode module an expression such as ``ph.molecule`` names, if any."""
        if isinstance(node, ast.Name):
            return bound.get(node.id)
        if isinstance(node, ast.Attribute):
            owner = self._module_of(node.value, bound)
            if owner is not None and f"{owner}.{node.attr}" in self.known:
                return f"{owner}.{node.attr}"
        return None

    def cycles(self) -> list[list[str]]:
        """The strongly connected components of more than one module."""
        return cycles({m: sorted({t for t, _ in self.edges.get(m, [])}) for m in self.known})


def cycles(graph: Mapping[T, Iterable[T]]) -> list[list[T]]:
    """The strongly connected components of more than one node of ``graph`` (Tarjan), each
    sorted."""
    index: dict[T, int] = {}
    low: dict[T, int] = {}
    stack: list[T] = []
    on_stack: set[T] = set()
    found: list[list[T]] = []

    def visit(v: T) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))  # type: ignore[type-var]

    for v in sorted(graph):  # type: ignore[type-var]
        if v not in index:
            visit(v)
    return found


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _front_end(name: str) -> str | None:
    return next((f for f in FRONT_ENDS if _within(name, f)), None)


def long_modules(package: Path = PACKAGE) -> dict[str, int]:
    """``{module: lines}`` of the modules over :data:`MAX_LINES` lines."""
    found = {}
    for name, path in modules(package).items():
        count = len(path.read_text(encoding="utf-8").splitlines())
        if count > MAX_LINES:
            found[name] = count
    return found


def core_imports_of_front_ends(found: Imports) -> list[str]:
    """Where a core-layer module imports a front end."""
    out = []
    for module, edges in sorted(found.edges.items()):
        if _front_end(module) is not None or module in GATHERING:
            continue
        for target, line in edges:
            if _front_end(target) is not None:
                out.append(f"{module}:{line} imports {target}")
    return out


def imports_of_the_package(found: Imports) -> list[str]:
    """Where a module imports the package ``polhode`` itself (outside the allowed ones)."""
    out = []
    for module, edges in sorted(found.edges.items()):
        if any(_within(module, allowed) for allowed in IMPORT_THE_PACKAGE):
            continue
        out += [f"{module}:{line}" for target, line in edges if target == "polhode"]
    return out


def private_imports(found: Imports) -> list[str]:
    """Where a module takes another module's private name."""
    return [
        f"{module}:{line} takes {source}.{name}"
        for module, taken in sorted(found.private.items())
        for source, name, line in taken
    ]


IMPORTS = Imports()


def test_the_package_is_found_and_read():
    # The checks below see every module: the core API, the front ends and the private helpers.
    names = set(IMPORTS.files)
    assert {"polhode", "polhode.bodies", "polhode.simulation", "polhode.io", "polhode.cli",
            "polhode.plot", "polhode.dask", "polhode.bench"} <= names
    assert sum(len(edges) for edges in IMPORTS.edges.values()) > 50


def test_no_module_is_over_800_lines():
    assert long_modules() == {}


def test_no_import_cycle():
    assert IMPORTS.cycles() == []


def test_no_module_takes_another_module_s_private_names():
    assert private_imports(IMPORTS) == []


def test_the_core_never_imports_a_front_end():
    assert core_imports_of_front_ends(IMPORTS) == []


def test_no_module_imports_the_package_back():
    assert imports_of_the_package(IMPORTS) == []


def test_the_checker_sees_a_cycle_a_private_name_and_a_front_end(tmp_path):
    # The checker itself, on a package made to break each rule once.
    package = tmp_path / "polhode"
    (package / "io").mkdir(parents=True)
    (package / "__init__.py").write_text("from polhode import bodies\n")
    (package / "bodies.py").write_text(
        "def f():\n    from polhode.io.mesh import read\n    return read\n"
    )
    (package / "io" / "__init__.py").write_text("from polhode.io.mesh import read\n")
    (package / "io" / "mesh.py").write_text(
        '"""import polhode"""\nfrom polhode.bodies import _hidden\nfrom polhode import _core\n'
    )
    (package / "invariants.py").write_text("import polhode as ph\nx = ph.bodies._hidden\n")
    found = Imports(package)
    # bodies -> io (the package of io.mesh) -> io.mesh -> bodies; invariants imports the
    # package, which does not import it: no cycle, but an import of the package back.
    assert found.cycles() == [["polhode.bodies", "polhode.io", "polhode.io.mesh"]]
    assert private_imports(found) == [
        "polhode.invariants:2 takes polhode.bodies._hidden",
        "polhode.io.mesh:2 takes polhode.bodies._hidden",
    ]
    assert core_imports_of_front_ends(found) == [
        "polhode.bodies:2 imports polhode.io",
        "polhode.bodies:2 imports polhode.io.mesh",
    ]
    assert imports_of_the_package(found) == ["polhode.invariants:1"]
