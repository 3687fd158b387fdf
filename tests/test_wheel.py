"""The wheel installs and runs where there is no Rust, on every CPython it claims, and the sdist
builds.

``scripts/test.sh`` builds the wheel once (``pip wheel . -w dist``), installs it for the tests
and sets ``POLHODE_WHEEL`` to its path: these tests install that same wheel into fresh virtual
environments whose PATH holds no cargo nor rustc and run ``polhode demo --no-plots`` there, one
environment per CPython the wheel claims (``cp310-abi3``: 3.10 and every later one) that is on
the machine: the interpreter running the tests, pyenv's (``~/.pyenv/versions``) and the
``python3.X`` on the PATH. A version the machine does not have is skipped, saying so. Without
``POLHODE_WHEEL`` they build the wheel if ``POLHODE_BUILD_WHEEL=1`` (a release compile of a few
minutes), and are skipped otherwise, so that a local run of a few test files stays quick.
Installing numpy and scipy into the fresh environments needs PyPI or pip's cache.
"""

from __future__ import annotations

import os
import re
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


#: The CPython versions the wheel claims (its tag is cp310-abi3: 3.10 and later), as far as
#: this test names them; a later one found on the machine is tested too.
CLAIMED = ((3, 10), (3, 11), (3, 12), (3, 13))


def _version(python: str) -> tuple[int, int] | None:
    """(major, minor) of a CPython interpreter, None for another implementation or a failure."""
    try:
        done = subprocess.run(
            [python, "-c", "import sys; print(sys.implementation.name, *sys.version_info[:2])"],
            capture_output=True,
            text=True,
            timeout=30,
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    words = done.stdout.split()
    if done.returncode != 0 or len(words) != 3 or words[0] != "cpython":
        return None
    return int(words[1]), int(words[2])


def interpreters() -> dict[tuple[int, int], str]:
    """One CPython >= 3.10 per version found on the machine: the one running the tests first,
    then pyenv's, then ``python3.X`` on the PATH."""
    candidates = [sys.executable]
    pyenv = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv")) / "versions"
    candidates += [str(p) for p in sorted(pyenv.glob("3.*/bin/python3"))]
    candidates += [shutil.which(f"python3.{minor}") or "" for minor in range(10, 20)]
    found: dict[tuple[int, int], str] = {}
    for python in candidates:
        if python:
            version = _version(python)
            if version is not None and version >= (3, 10) and version not in found:
                found[version] = python
    return found


FOUND = interpreters()


@pytest.fixture(scope="module")
def expected_numbers() -> str:
    """The numbers the smoke test prints, from the wheel installed for the tests: every CPython
    runs the same compiled code (the stable ABI) and must print them bit for bit."""
    return _smoke_numbers(sys.executable, os.environ)


#: What the smoke test runs in each environment: a simulation and an analysis, printed as the
#: doubles' shortest round-trip decimals.
_SMOKE = (
    "import polhode as ph; "
    "sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], [0.0, 7.5, 30.0]); "
    "a = ph.analyze([1.0, 2.0, 3.0], [0.01, 1.0, 0.01]); "
    "print(*map(repr, [*sol.omega.ravel().tolist(), *sol.quaternion.ravel().tolist(), a.period]))"
)


def _smoke_numbers(python, env) -> str:
    return _run([str(python), "-c", _SMOKE], env=env).stdout.strip()


@pytest.mark.parametrize(
    "version",
    sorted(set(CLAIMED) | set(FOUND)),
    ids=lambda v: f"cpython{v[0]}.{v[1]}",
)
def test_wheel_installs_and_runs_the_demo_without_rust(wheel, tmp_path, version, expected_numbers):
    python_found = FOUND.get(version)
    if python_found is None:
        pytest.skip(f"no CPython {version[0]}.{version[1]} on this machine (pyenv install it)")
    venv = tmp_path / "venv"
    _run([python_found, "-m", "venv", str(venv)])
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
    assert _version(str(python)) == version
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
    assert where.endswith(".abi3.so"), where
    # The same numbers, bit for bit, as under the interpreter that runs the tests.
    assert _smoke_numbers(python, env) == expected_numbers


def test_the_wheel_declares_the_all_extra(wheel):
    with zipfile.ZipFile(wheel) as archive:
        (name,) = [n for n in archive.namelist() if n.endswith(".dist-info/METADATA")]
        metadata = archive.read(name).decode()
    assert "Provides-Extra: all" in metadata
    extra_all = re.compile(r"extra == ['\"]all['\"]")
    requires = [line for line in metadata.splitlines() if extra_all.search(line)]
    assert requires, metadata
    assert "polhode[" in requires[0] and all(
        e in requires[0] for e in ("plot", "progress", "dask", "mesh", "robots", "chem")
    ), requires


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
