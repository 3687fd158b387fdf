#!/usr/bin/env bash
# Build, install and test polhode: the Rust core, the bindings, the Python layer and the
# documentation site. Run it inside a virtual environment; CI (.ci/run) runs exactly this in a
# fresh one.
#
# Each crate is compiled as few times as it can be: the extension once, in release, as the
# wheel that is installed for the tests (and that tests/test_wheel.py installs again into a
# fresh environment without Rust); the core's tests and doctests once, in the light `ci`
# profile of Cargo.toml; clippy's check on its own (a check cannot reuse a build's artifacts).
# The wheel's release build runs beside clippy and the Rust tests, in its own target directory
# (target/wheel) so that neither waits for the other's lock, while pip installs the test and
# docs dependencies: on 2 cores that hides most of the release build.
set -euo pipefail
cd "$(dirname "$0")/.."

timings=()
step_name=""
step_start=$SECONDS
step() {
  if [[ -n "$step_name" ]]; then
    timings+=("$(printf '%4ds  %s' $((SECONDS - step_start)) "$step_name")")
  fi
  step_name="$*"
  step_start=$SECONDS
  printf '\n== %s\n' "$*"
}

logs=$(mktemp -d)
background=()
# A background job runs in its own session so that it can be stopped with its children.
cleanup() {
  for pid in "${background[@]}"; do kill -- "-$pid" 2>/dev/null || true; done
  rm -rf "$logs"
}
trap cleanup EXIT

# Waits for a background job; on failure prints its output and stops.
finish() {
  local pid=$1 name=$2
  if ! wait "$pid"; then
    printf '\n== FAILED: %s\n' "$name"
    cat "$logs/$name.log"
    exit 1
  fi
}

step "in the background: pip wheel (the release build of the extension), pip install of the dependencies"
rm -f dist/polhode-*.whl
setsid bash -c 'CARGO_TARGET_DIR=target/wheel python -m pip wheel --quiet --no-deps --wheel-dir dist .' \
  >"$logs/wheel.log" 2>&1 &
wheel_pid=$!
background+=("$wheel_pid")
# The extras' requirements, read from pyproject.toml (tomllib: Python >= 3.11; on 3.10 they are
# installed with the wheel below instead).
python - >"$logs/requirements.txt" <<'EOF' || true
import tomllib

with open("pyproject.toml", "rb") as file:
    project = tomllib.load(file)["project"]
extras = project["optional-dependencies"]
print("\n".join(project["dependencies"] + extras["test"] + extras["docs"]))
EOF
setsid python -m pip install --quiet -r "$logs/requirements.txt" >"$logs/dependencies.log" 2>&1 &
dependencies_pid=$!
background+=("$dependencies_pid")

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy -D warnings"
# The benchmark crate (criterion) is left out: it is compiled by `cargo bench -p polhode-bench`
# (benchmarks/report.py --criterion) and would add criterion's dependencies to every run.
# In the `ci` profile, like the tests: the proc macros and build scripts it compiles are then
# reused by `cargo test --profile ci` (a check cannot reuse a build's artifacts, but those are
# built in full by both).
cargo clippy --profile ci --workspace --exclude polhode-bench --all-targets -- -D warnings

step "cargo test (the core crate, its doctests and the README's Rust examples)"
cargo test --profile ci

step "wait for the wheel and the dependencies; install the wheel with the test and docs extras"
finish "$dependencies_pid" dependencies
finish "$wheel_pid" wheel
wheel=$(ls dist/polhode-*.whl)
export POLHODE_WHEEL="$PWD/$wheel"
echo "$wheel ($(du -k "$wheel" | cut -f1) kB)"
python -m pip install --quiet --force-reinstall --no-deps "$wheel"
python -m pip install --quiet "$wheel[test,docs]"

step "ruff check"
ruff check python tests benchmarks docs

step "mypy.stubtest polhode._core"
python -m mypy.stubtest polhode._core

step "pytest"
# From the repository root, pytest imports the installed package (python/ is not on the path).
python -m pytest tests -q -n auto --durations=5

step "docs (scripts/docs.sh: Sphinx, warnings as errors)"
bash scripts/docs.sh

step "done"
printf '\n== time per step (s)\n'
printf '%s\n' "${timings[@]}"
printf '%4ds  total\n' "$SECONDS"
