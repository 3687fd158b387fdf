"""The core crate's structure, as docs/architecture.md states it: no function over 150 lines,
``unsafe`` only in the SIMD kernels and the fallible allocation (each with its ``SAFETY:``
comment), and no cycle among its modules (neither among the top-level modules nor among the
files of one folder).

The checks read the Rust source of the repository (rust/polhode/src) with a small scanner:
comments, strings and character literals are blanked first, so a brace or a word inside them
counts for nothing. Each check is also run on a synthetic crate that breaks it.
"""

from __future__ import annotations

import re
from collections import defaultdict
from pathlib import Path

import pytest
from test_layers import cycles

SOURCE = Path(__file__).resolve().parents[1] / "rust" / "polhode" / "src"

#: The longest function the core may hold, in lines from ``fn`` to its closing brace.
LONGEST = 150

#: The files that may hold ``unsafe``: the SIMD dispatch and lanes, the fallible allocation.
UNSAFE_FILES = {"simd.rs", "dynamics/lanes.rs", "memory.rs"}

_CHAR = re.compile(r"'(\\.|\\u\{[0-9a-fA-F]+\}|[^\\'\n])'")


def blank(text: str) -> str:
    """``text`` with its comments, strings and character literals replaced by spaces (newlines
    kept, so that offsets and line numbers stay)."""
    out: list[str] = []
    i, n = 0, len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.index("*/", i) + 2
        elif text[i] == '"' or (text[i] == "r" and re.match(r'r#*"', text[i:])):
            if text[i] == "r":
                hashes = re.match(r"r(#*)\"", text[i:]).group(1)  # type: ignore[union-attr]
                j = text.index('"' + hashes, i + len(hashes) + 2) + 1 + len(hashes)
            else:
                j = i + 1
                while text[j] != '"':
                    j += 2 if text[j] == "\\" else 1
                j += 1
        elif text[i] == "'" and (m := _CHAR.match(text, i)):
            j = m.end()
        else:
            out.append(text[i])
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", text[i:j]))
        i = j
    return "".join(out)


def functions(text: str) -> list[tuple[str, int, int]]:
    """Each function with a body in ``text``: its name, first line and length in lines."""
    code = blank(text)
    found = []
    for m in re.finditer(r"\bfn\s+(\w+)", code):
        brace, semicolon = code.find("{", m.end()), code.find(";", m.end())
        if brace < 0 or 0 <= semicolon < brace:
            continue  # a declaration without a body (a trait's)
        depth, j = 0, brace
        while True:
            depth += {"{": 1, "}": -1}.get(code[j], 0)
            if depth == 0:
                break
            j += 1
        first = code.count("\n", 0, m.start()) + 1
        found.append((m.group(1), first, code.count("\n", m.start(), j) + 1))
    return found


def unsafe_uses(text: str) -> list[tuple[int, bool]]:
    """Each ``unsafe`` in ``text``: its line, and whether a ``SAFETY:`` comment (or, for an
    ``unsafe fn``, a ``# Safety`` section of its docs) stands in the five lines above it."""
    code, lines = blank(text), text.split("\n")
    uses = []
    for m in re.finditer(r"\bunsafe\b", code):
        line = code.count("\n", 0, m.start())
        above = "\n".join(lines[max(0, line - 5) : line + 1])
        uses.append((line + 1, "SAFETY:" in above or "# Safety" in above))
    return uses


def _module(path: Path, root: Path) -> tuple[str, ...]:
    parts = path.relative_to(root).with_suffix("").parts
    return parts[:-1] if parts[-1] in ("mod", "lib") else parts


def _paths(tree: str) -> list[list[str]]:
    """The paths a ``use`` tree names: ``a::{b, c::d}`` gives ``[a, b]`` and ``[a, c, d]``."""
    tree = re.sub(r"\s+", "", tree)
    depth, start, items = 0, 0, []
    brace = tree.find("{")
    if brace < 0:
        return [[p for p in tree.split("::") if p and p != "self"]]
    head = [p for p in tree[:brace].split("::") if p]
    inner = tree[brace + 1 : tree.rindex("}")]
    for i, c in enumerate(inner + ","):
        depth += {"{": 1, "}": -1}.get(c, 0)
        if c == "," and depth == 0:
            if inner[start:i]:
                items.append(inner[start:i])
            start = i + 1
    return [head + rest for item in items for rest in _paths(item)]


def _trees(code: str) -> list[str]:
    """The ``crate::...`` and ``super::...`` paths of ``code``, each with its braces whole."""
    trees = []
    for m in re.finditer(r"\b(?:crate|super)::", code):
        j = m.end()
        while True:
            word = re.match(r"\w*(::)?", code[j:])
            j += word.end() if word else 0
            if j < len(code) and code[j] == "{":
                depth = 0
                while True:
                    depth += {"{": 1, "}": -1}.get(code[j], 0)
                    j += 1
                    if depth == 0:
                        break
            if not (word and word.group(1)):
                break
        trees.append(code[m.start() : j])
    return trees


def module_edges(root: Path) -> dict[tuple[str, ...], set[tuple[str, ...]]]:
    """Which module of the crate under ``root`` names which (``crate::`` and ``super::``
    paths, in ``use`` trees and in code), each path taken to its longest prefix that is a
    module."""
    files = {_module(p, root): p for p in root.rglob("*.rs")}
    # What the crate's root re-exports (``pub use error::{Error, Result}``): ``crate::Error``
    # is a use of the module that defines it.
    reexports: dict[str, tuple[str, ...]] = {}
    lib = blank((root / "lib.rs").read_text()) if (root / "lib.rs").exists() else ""
    for tree in re.findall(r"\bpub\s+use\s+([^;]+);", lib):
        for names in _paths(tree):
            for k in range(len(names) - 1, 0, -1):
                if tuple(names[:k]) in files:
                    reexports[names[-1]] = tuple(names[:k])
                    break
    edges: dict[tuple[str, ...], set[tuple[str, ...]]] = defaultdict(set)
    for module, path in files.items():
        code = blank(path.read_text())
        here = module if path.stem in ("mod", "lib") else module
        parent = here[:-1]
        for tree in _trees(code):
            base: tuple[str, ...] = () if tree.startswith("crate") else parent
            rest = tree.split("::", 1)[1]
            for names in _paths(rest):
                full = base + tuple(names)
                for k in range(len(full), 0, -1):
                    if full[:k] in files:
                        if full[:k] != module:
                            edges[module].add(full[:k])
                        break
                else:
                    if full and full[0] in reexports and reexports[full[0]] != module:
                        edges[module].add(reexports[full[0]])
    return edges


def module_cycles(root: Path) -> list[list[tuple[str, ...]]]:
    """Cycles among the top-level modules, and among the files of each folder."""
    edges = module_edges(root)
    top: dict[tuple[str, ...], set[tuple[str, ...]]] = defaultdict(set)
    siblings: dict[tuple[str, ...], set[tuple[str, ...]]] = defaultdict(set)
    for a, targets in edges.items():
        for b in targets:
            if a and b and a[0] != b[0]:
                top[a[:1]].add(b[:1])
            if len(a) == len(b) > 1 and a[:-1] == b[:-1]:
                siblings[a].add(b)
    return cycles(top) + cycles(siblings)


def _sources() -> list[Path]:
    sources = sorted(SOURCE.rglob("*.rs"))
    assert len(sources) > 30, f"the crate's source was not found under {SOURCE}"
    return sources


def test_no_function_is_over_150_lines():
    long = [
        f"{p.relative_to(SOURCE)}:{line} fn {name}: {n} lines"
        for p in _sources()
        for name, line, n in functions(p.read_text())
        if n > LONGEST
    ]
    assert not long, "\n".join(long)


def test_unsafe_only_in_the_simd_kernels_and_the_allocation_each_with_its_safety_comment():
    misplaced, unexplained, count = [], [], 0
    for p in _sources():
        name = p.relative_to(SOURCE).as_posix()
        for line, explained in unsafe_uses(p.read_text()):
            count += 1
            if name not in UNSAFE_FILES:
                misplaced.append(f"{name}:{line}")
            if not explained:
                unexplained.append(f"{name}:{line}")
    assert not misplaced, f"unsafe outside {sorted(UNSAFE_FILES)}: {misplaced}"
    assert not unexplained, f"unsafe without a SAFETY: comment: {unexplained}"
    assert count > 0  # the scanner sees the kernels' own


def test_no_module_cycle_in_the_crate():
    uses = {b[0] for a, targets in module_edges(SOURCE).items() if a[:1] == ("simulation",)
            for b in targets if b}
    assert uses >= {"dynamics", "mass", "exact"}  # the scanner sees the runner's imports
    assert not module_cycles(SOURCE)


def _crate(tmp_path: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    return tmp_path


def test_the_scanner_sees_a_long_function_an_unexplained_unsafe_and_cycles(tmp_path):
    body = "\n".join(f"    let x{i} = {i};" for i in range(LONGEST))
    text = f'fn long() {{\n{body}\n}}\nfn short() {{ let s = "}}}}{{"; }}\n'
    assert [(n, k > LONGEST) for n, _, k in functions(text)] == [("long", True), ("short", False)]
    assert unsafe_uses("// a word: unsafe\nfn f() { unsafe { g() } }\n") == [(2, False)]
    assert unsafe_uses("// SAFETY: g has no precondition.\nlet y = unsafe { g() };\n") == [
        (2, True)
    ]
    crate = _crate(
        tmp_path / "top",
        {
            "lib.rs": "mod a;\nmod b;\n",
            "a.rs": "use crate::b::thing;\n",
            "b/mod.rs": "mod c;\nmod d;\nuse crate::{a::{self, other}};\n",
            "b/c.rs": "use super::d::x;\n",
            "b/d.rs": "fn f() { super::c::y(); }\n",
        },
    )
    assert sorted(module_cycles(crate)) == [[("a",), ("b",)], [("b", "c"), ("b", "d")]]
    # A cycle through the root's re-exports: e names crate::Thing, which f defines; f uses e.
    crate = _crate(
        tmp_path / "reexport",
        {
            "lib.rs": "mod e;\nmod f;\npub use f::{Thing, Other};\n",
            "e.rs": "fn g() -> crate::Thing { todo!() }\n",
            "f.rs": "use crate::e::helper;\npub struct Thing;\n",
        },
    )
    assert module_cycles(crate) == [[("e",), ("f",)]]


@pytest.mark.parametrize("tree", ["a::{b, c::{d, e}}", "a::b"])
def test_use_trees_expand(tree):
    expected = {"a::{b, c::{d, e}}": [["a", "b"], ["a", "c", "d"], ["a", "c", "e"]]}
    assert _paths(tree) == expected.get(tree, [["a", "b"]])
