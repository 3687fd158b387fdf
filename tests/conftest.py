"""Shared pytest configuration, tolerances, assertion helpers and hypothesis strategies."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from reference import EPS


def pytest_configure(config):
    # filterwarnings = error is on; when a hypothesis test fails, its reporting introspects
    # types and triggers mypy_extensions' own DeprecationWarning inside a pytest hook, which
    # then aborts the whole run with INTERNALERROR instead of reporting the failure.
    config.addinivalue_line(
        "filterwarnings", "ignore:mypy_extensions.TypedDict is deprecated:DeprecationWarning"
    )


# Deadlines off: the first call into the extension and the exact rational references vary in
# cost; a property is about correctness, never timing (benchmarks live in benchmarks/).
settings.register_profile(
    "polhode", deadline=None, max_examples=100, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(
    "polhode-thorough", parent=settings.get_profile("polhode"), max_examples=2000
)
# CI (CI=true) runs four times the examples of a local run: about a minute on 2 cores.
settings.register_profile("polhode-ci", parent=settings.get_profile("polhode"), max_examples=400)
# benchmarks/fuzz_thorough.py, outside CI: POLHODE_FUZZ_EXAMPLES examples per property.
settings.register_profile(
    "polhode-fuzz",
    parent=settings.get_profile("polhode"),
    max_examples=int(os.environ.get("POLHODE_FUZZ_EXAMPLES", "20000")),
)
_DEFAULT_PROFILE = "polhode-ci" if os.environ.get("CI", "").lower() in ("1", "true") else "polhode"
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", _DEFAULT_PROFILE))

# `rtol` that merges no two distinct moments: the tests of near-degenerate tensors ask for the
# individual axes of moments that differ by far less than any default merging tolerance.
NO_MERGE_RTOL = 0.0


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240611)


# ---------------------------------------------------------------------------------------------
# Assertions
# ---------------------------------------------------------------------------------------------


def norm2(a) -> float:
    """Spectral norm (the ||A|| of the eigen-error bounds)."""
    return float(np.linalg.norm(np.asarray(a, dtype=float), 2))


def assert_close_normwise(actual, expected, rtol: float, scale: float | None = None, what=""):
    """max |actual - expected| <= rtol * scale, scale = max |expected| unless given.

    A norm-wise bound is the right one for tensors: a rounding error of eps relative in the
    large entries shows up as an absolute error of eps * ||I|| in the small ones (products of
    inertia that should be 0), which an element-wise relative bound would reject.
    """
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    if scale is None:
        scale = float(np.max(np.abs(expected))) if expected.size else 0.0
    err = float(np.max(np.abs(actual - expected))) if expected.size else 0.0
    assert err <= rtol * scale, (
        f"{what}: max error {err:.3e} > bound {rtol * scale:.3e} "
        f"(= {err / scale if scale else float('inf'):.3e} relative, "
        f"{err / (EPS * scale) if EPS * scale else float('inf'):.1f} eps; allowed {rtol:.1e})"
    )


def check_eigen(inertia, moments, axes, residual_eps: float = 10.0, what=""):
    """The backward-stability checks every principal() result must pass.

    ||A V - V diag(I)|| <= 10 eps ||A|| (the project's bound; a backward-stable 3x3 solver such
    as Jacobi or implicit QR is accurate to a small multiple of eps ||A||: numpy.linalg.eigh
    measures <= 9.2 eps, typically 1.3, over 2e4 random inertia tensors; Cardano-type solvers
    miss it by orders of magnitude).
    ||V^T V - 1|| <= 16 eps and |det V - 1| <= 16 eps: LAPACK's orthogonality bound is O(n) eps
    with an unstated constant; eigh itself measures up to 9.5 eps on the same 2e4 tensors, so
    10 eps would reject LAPACK; each of the ~10 rotations of a 3x3 Jacobi solve adds ~1-2 eps.
    """
    a = np.asarray(inertia, dtype=float)
    v = np.asarray(axes, dtype=float)
    w = np.asarray(moments, dtype=float)
    assert v.shape == (3, 3) and w.shape == (3,), what
    assert v.dtype == np.float64 and w.dtype == np.float64, what
    scale = norm2(a)
    residual = norm2(a @ v - v * w)
    assert residual <= residual_eps * EPS * scale, (
        f"{what}: residual ||AV - VD|| = {residual:.3e} = {residual / (EPS * scale):.1f} eps ||A||"
        f" > {residual_eps} eps ||A||"
    )
    ortho = norm2(v.T @ v - np.eye(3))
    assert ortho <= 16 * EPS, f"{what}: ||V^T V - 1|| = {ortho / EPS:.1f} eps > 16 eps"
    det = float(np.linalg.det(v))
    assert abs(det - 1) <= 16 * EPS, f"{what}: det V = {det!r}, expected +1"
    assert np.all(np.diff(w) >= 0), f"{what}: moments not ascending: {w}"


def check_sign_convention(axes, what=""):
    """Non-degenerate sign convention: the largest-magnitude component of columns 0 and 1 is
    positive; column 2 = column 0 x column 1 (to round-off: both are unit vectors)."""
    v = np.asarray(axes, dtype=float)
    for k in range(2):
        i = int(np.argmax(np.abs(v[:, k])))
        # A tie between two components of equal magnitude (to round-off) leaves the sign free.
        tie = np.sort(np.abs(v[:, k]))[-2] >= abs(v[i, k]) - 8 * EPS
        assert tie or v[i, k] > 0, f"{what}: column {k} = {v[:, k]}: largest component negative"
    cross = np.cross(v[:, 0], v[:, 1])
    assert np.max(np.abs(cross - v[:, 2])) <= 8 * EPS, f"{what}: column 2 != col0 x col1"


# ---------------------------------------------------------------------------------------------
# Hypothesis strategies
# ---------------------------------------------------------------------------------------------

finite_unit = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)


@st.composite
def rotations(draw) -> Rotation:
    """Proper rotations from a quaternion drawn in the unit ball shell (uniform enough)."""
    q = np.array([draw(finite_unit) for _ in range(4)])
    n = np.linalg.norm(q)
    if n < 0.1:
        q = np.array([0.0, 0.0, 0.0, 1.0])
        n = 1.0
    return Rotation.from_quat(q / n)


def vectors(bound: float = 10.0):
    x = st.floats(-bound, bound, allow_nan=False, allow_infinity=False, allow_subnormal=False)
    return st.tuples(x, x, x).map(lambda t: np.array(t, dtype=float))


positive = st.floats(0.05, 20.0, allow_nan=False, allow_infinity=False)


@st.composite
def clouds(draw, min_size: int = 1, max_size: int = 12, bound: float = 10.0):
    """(masses, positions) of a random point cloud."""
    n = draw(st.integers(min_size, max_size))
    masses = np.array([draw(st.floats(0.01, 100.0)) for _ in range(n)])
    positions = np.array([draw(vectors(bound)) for _ in range(n)]).reshape(n, 3)
    return masses, positions


@st.composite
def solid_specs(draw):
    """(name, mass, params) of a random solid with sensible parameters."""
    name = draw(
        st.sampled_from(
            [
                "sphere",
                "spherical_shell",
                "cuboid",
                "cylinder",
                "tube",
                "cone",
                "ellipsoid",
                "rod",
                "disk",
                "torus",
                "capsule",
            ]
        )
    )
    mass = draw(positive)
    if name in ("sphere", "spherical_shell", "rod", "disk"):
        params = (draw(positive),)
    elif name in ("cuboid", "ellipsoid"):
        params = ((draw(positive), draw(positive), draw(positive)),)
    elif name in ("cylinder", "capsule", "cone"):
        params = (draw(positive), draw(positive))
    elif name == "tube":
        inner = draw(positive)
        params = (inner, inner * draw(st.floats(1.01, 5.0)), draw(positive))
    else:  # torus: minor radius strictly below the major one
        major = draw(positive)
        params = (major, major * draw(st.floats(0.01, 0.99)))
    return name, mass, params
