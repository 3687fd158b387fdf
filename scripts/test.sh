#!/usr/bin/env bash
# Build, install and test polhode: the Rust core, the bindings, the Python layer and the
# documentation site. Run it inside a virtual environment; CI (.ci/run) runs exactly this in a
# fresh one.
#
# Each crate is compiled as few times as possible: the extension once, in release, as the
# wheel that is then installed for the tests (and installed again by tests/test_wheel.py into a
# fresh environment without Rust); the core's tests and doctests once, in the `test` profile
# (see Cargo.toml); clippy's check on its own (it cannot share a build's artifacts).
set -euo pipefail
cd "$(dirname "$0")/.."

timings=()
step_name=""
step_start=$SECONDS
step() {
  if [[ -n "$step_name" ]]; then timings+=("$(printf '%4ds  %s' $((SECONDS - step_start)) "$step_name")"); fi
  step_name="$*"
  step_start=$SECONDS
  printf '\n== %s\n' "$*"
}

step "pip wheel: the release build of the extension, once"
rm -f dist/polhode-*.whl
python -m pip wheel --quiet --no-deps --wheel-dir dist .
wheel=$(ls dist/polhode-*.whl)
export POLHODE_WHEEL="$PWD/$wheel"
echo "$wheel ($(du -k "$wheel" | cut -f1) kB)"

step "pip install the wheel with the test and docs extras"
python -m pip install --quiet --force-reinstall --no-deps "$wheel"
python -m pip install --quiet "$wheel[test,docs]"

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy -D warnings"
cargo clippy --workspace --all-targets -- -D warnings

step "cargo test (the core crate, its doctests and the README's Rust examples)"
cargo test --profile ci

step "ruff check"
ruff check python tests benchmarks docs

step "mypy.stubtest polhode._core"
python -m mypy.stubtest polhode._core

step "pytest"
# Run from tests/ so that the installed package is imported, not the source tree.
python -m pytest tests -q -n auto

step "docs (scripts/docs.sh: Sphinx, warnings as errors)"
bash scripts/docs.sh

step "done"
printf '\n== time per step (s)\n'
printf '%s\n' "${timings[@]}"
printf '%4ds  total\n' "$SECONDS"
