#!/usr/bin/env bash
# Build, install and test polhode: the Rust core, the bindings and the Python layer.
# Run it inside a virtual environment; CI (.ci/run) runs exactly this in a fresh one.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n== %s\n' "$*"; }

step "pip install '.[test]' (release build of the Rust extension)"
python -m pip install --quiet '.[test]'

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy -D warnings"
cargo clippy --workspace --all-targets -- -D warnings

step "cargo test (the core crate, with its doctests)"
cargo test --release

step "ruff check"
ruff check python tests benchmarks

step "mypy.stubtest polhode._core"
python -m mypy.stubtest polhode._core

step "pytest"
# Run from tests/ so that the installed package is imported, not the source tree.
python -m pytest tests -q
