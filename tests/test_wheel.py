"""The wheel installs and runs where there is no Rust, and the sdist builds.

``scripts/test.sh`` builds the wheel once (``pip wheel . -w dist``), installs it for the tests
and sets ``POLHODE_WHEEL`` to its path: this test installs that same wheel into a fresh
virtual environment whose PATH holds no cargo nor rustc and runs ``polhode demo --no-plots``
there. Without ``POLHODE_WHEEL`` it builds the wheel itself if ``POLHODE_BUILD_WHEEL=1`` (a
release compile of a few minutes), and is skipped otherwise, so that a local run of a few test
files stays quick. Installing numpy and scipy into the fresh environment needs PyPI or pip's
cache.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _run(command, **kwargs):
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    assert result.returncode == 0, (
        f"{' '.join(map(str, command))} failed ({result.returncode}):\n"
        f"{result.stdout[-4000:]}\n{result.stderr[-4000:]}"
    )
    return result


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    given = os.environ.get("POLHODE_WHEEL")
    if given:
        path = Path(given)
        assert path.is_file(), f"POLHODE_WHEEL={given} is not a file"
        return path
    if os.environ.get("POLHODE_BUILD_WHEEL") != "1":
        pytest.skip(
            "set POLHODE_WHEEL to a built wheel (scripts/test.sh does) or POLHODE_BUILD_WHEEL=1"
        )
    out = tmp_path_factory.mktemp("dist")
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--wheel-dir", str(out), str(ROOT)])
    (path,) = out.glob("polhode-*.whl")
    return path


def test_one_abi3_wheel_with_the_extension_and_the_package(wheel):
    # One wheel for every CPython >= 3.10: the stable ABI (pyo3's abi3-py310 feature).
    name = wheel.name
    assert name.startswith("polhode-0.1.0-cp310-abi3-"), name
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
    assert any(n.startswith("polhode/_core") and n.endswith(".abi3.so") for n in names), names
    # The package's modules and its subpackages (the front ends), the stubs and the marker.
    for module in (
        "__init__.py",
        "bodies.py",
        "io/__init__.py",
        "cli/__init__.py",
        "plot/__init__.py",
        "py.typed",
        "_core.pyi",
    ):
        assert f"polhode/{module}" in names
    assert not any(n.endswith(".rs") for n in names)  # no Rust source in a wheel


def test_wheel_installs_and_runs_the_demo_without_rust(wheel, tmp_path):
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)])
    bin_dir = venv / ("Scripts" if os.name == "nt" else "bin")
    # A PATH with the new environment and the system's programs, but no Rust toolchain.
    system = [p for p in ("/usr/local/bin", "/usr/bin", "/bin") if Path(p).is_dir()]
    path = os.pathsep.join([str(bin_dir), *system])
    for tool in ("cargo", "rustc"):
        found = shutil.which(tool, path=path)
        if found:
            pytest.skip(f"{tool} is installed system-wide ({found}): cannot hide it")
    env = {
        "PATH": path,
        "HOME": os.environ.get("HOME", str(tmp_path)),
        "PIP_DISABLE_PIP_VERSION_CHECK": "1",
        "MPLBACKEND": "Agg",
    }
    if "PIP_CACHE_DIR" in os.environ:
        env["PIP_CACHE_DIR"] = os.environ["PIP_CACHE_DIR"]
    python = bin_dir / "python"
    # --only-binary: nothing may be compiled, polhode least of all.
    _run([str(python), "-m", "pip", "install", "--quiet", "--only-binary", ":all:", str(wheel)],
         env=env, cwd=tmp_path)
    demo = _run([str(bin_dir / "polhode"), "demo", "--no-plots"], env=env, cwd=tmp_path)
    assert "tennis-racket" not in demo.stderr
    assert "T-handle spun at 10 rad/s about its intermediate axis" in demo.stdout
    assert "exact" in demo.stdout and "flips, every" in demo.stdout
    # The extension that ran is the wheel's, in the fresh environment.
    where = _run(
        [str(python), "-c", "import polhode._core as c; print(c.__file__)"], env=env, cwd=tmp_path
    ).stdout.strip()
    assert Path(where).is_relative_to(venv), where


def test_sdist_builds_and_holds_what_a_build_needs(tmp_path):
    maturin = shutil.which("maturin")
    if maturin is None:
        pytest.skip("maturin is not installed (it is in the test extra)")
    _run([maturin, "sdist", "--out", str(tmp_path)], cwd=ROOT)
    (sdist,) = tmp_path.glob("polhode-0.1.0.tar.gz")
    with tarfile.open(sdist) as archive:
        names = {n.split("/", 1)[1] for n in archive.getnames() if "/" in n}
    needed = {
        "pyproject.toml",
        "Cargo.toml",
        "Cargo.lock",
        "README.md",
        "rust/polhode/Cargo.toml",
        "rust/polhode/src/lib.rs",
        "rust/polhode-py/Cargo.toml",
        "rust/polhode-py/src/lib.rs",
        "python/polhode/__init__.py",
        "python/polhode/_core.pyi",
    }
    assert needed <= names, sorted(needed - names)
    # Every Rust and Python source of the two crates and the package, as git has them.
    tracked = _run(
        ["git", "ls-files", "rust/polhode/src", "rust/polhode-py/src", "python/polhode"],
        cwd=ROOT,
    ).stdout.split()
    missing = [f for f in tracked if f not in names]
    assert not missing, missing
