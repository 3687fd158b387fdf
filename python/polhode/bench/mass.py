"""Mass-property benchmarks: principal axes against ``numpy.linalg.eigh``, point masses against
a numpy reference, triangle meshes against trimesh, and the mesh integrals far from the origin.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from polhode.bench import adapters
from polhode.bench._timing import interleaved as _interleaved
from polhode.bench._timing import median as _median
from polhode.bench._timing import spread as _spread
from polhode.bodies import Body
from polhode.principal_axes import principal

Array = NDArray[np.float64]


@dataclass
class Versus:
    """polhode against a peer on the same input: times, agreement or residuals."""

    title: str
    peer: str
    peer_seconds: list[float]
    ours_seconds: list[float]
    note: str

    @property
    def ratio(self) -> float:
        return _median(self.peer_seconds) / _median(self.ours_seconds)

    def table(self) -> str:
        return (
            f"{self.title}\n"
            f"  {self.peer:26s} {_median(self.peer_seconds) * 1e3:10.2f} ms "
            f"(spread {_spread(self.peer_seconds)})\n"
            f"  {'polhode':26s} {_median(self.ours_seconds) * 1e3:10.2f} ms "
            f"(spread {_spread(self.ours_seconds)})\n"
            f"  polhode is {self.ratio:.1f}x faster; {self.note}"
        )


def _fresh_outputs(n: int) -> tuple[Array, Array, Array]:
    """New arrays of the shapes and types `polhode.principal` returns for N tensors, each
    written once: what any whole call pays for its 120 bytes of output per tensor (the
    kernel's page faults on fresh memory), on this machine and in this run."""
    out = (np.zeros((n, 3)), np.zeros((n, 3, 3)), np.zeros((n, 3), dtype=np.int64))
    for a in out:
        a.fill(1)
    return out


def _worst_residual(a: Array, w: Array, v: Array) -> float:
    r = a @ v - v * w[:, None, :]
    return float(np.max(np.linalg.norm(r, axis=(1, 2)) / np.linalg.norm(a, axis=(1, 2))))


def eigensolve(n: int = 1_000_000, repeats: int = 5) -> list[Versus]:
    """The batch `polhode.principal` against `numpy.linalg.eigh` on N random symmetric tensors
    and on N rotated diag(1, 1, 2) (every one with a double moment)."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(0)
    a = rng.normal(size=(n, 3, 3))
    random = 0.5 * (a + a.transpose(0, 2, 1))
    r = Rotation.random(n, random_state=rng).as_matrix()
    degenerate = np.einsum("nij,j,nkj->nik", r, np.array([1.0, 1.0, 2.0]), r)
    eps = np.finfo(float).eps
    out = []
    for label, tensors in (("random symmetric", random), ("degenerate diag(1, 1, 2)", degenerate)):
        times, results = _interleaved(
            {
                "eigh": lambda t=tensors: np.linalg.eigh(t),
                "polhode": lambda t=tensors: tuple(principal(t)),
                "outputs": lambda: _fresh_outputs(n),
            },
            repeats,
        )
        del results["outputs"]
        res = {k: _worst_residual(tensors, *results[k][:2]) / eps for k in results}
        floor = _median(times["outputs"]) / n * 1e9
        out.append(
            Versus(
                f"eigensolve, {label}, N = {n:.0e}",
                "numpy.linalg.eigh",
                times["eigh"],
                times["polhode"],
                f"worst residual {res['polhode']:.2f} eps (eigh {res['eigh']:.2f} eps); "
                f"its outputs alone, allocated and written once (one thread), {floor:.1f} ns "
                "per tensor",
            )
        )
    return out


def point_masses(n: int = 10_000_000, repeats: int = 5) -> Versus:
    """`Body.point_masses(m, r).inertia` against numpy: centre, centred second moments,
    inertia tensor."""
    rng = np.random.default_rng(1)
    m = rng.uniform(0.5, 2.0, n)
    r = rng.normal(size=(n, 3)) * [1.0, 2.0, 3.0]
    times, results = _interleaved(
        {
            "numpy": lambda: adapters.point_mass_inertia(m, r),
            "polhode": lambda: Body.point_masses(m, r).inertia,
        },
        repeats,
    )
    diff = np.abs(results["numpy"] - results["polhode"]).max() / np.abs(results["numpy"]).max()
    return Versus(
        f"point-mass assembly, N = {n:.0e}",
        "numpy reference",
        times["numpy"],
        times["polhode"],
        f"agreement {diff:.1e} relative",
    )


def mesh(subdivisions: int = 7, repeats: int = 11) -> Versus | None:
    """`Body.mesh` (with its closedness and winding check) against trimesh's
    `triangles.mass_properties` on an icosphere of 20 * 4^S triangles; None without trimesh."""
    sphere = adapters.icosphere(subdivisions)
    if sphere is None:
        return None
    vertices, faces = sphere
    triangles = vertices[faces]
    times, results = _interleaved(
        {
            "trimesh": lambda: adapters.trimesh_mass_properties(triangles),
            "polhode": lambda: Body.mesh(vertices, faces, density=1.0),
        },
        repeats,
    )
    theirs = results["trimesh"].inertia
    agree = np.linalg.norm(results["polhode"].inertia - theirs) / np.linalg.norm(theirs)
    return Versus(
        f"triangle mesh, icosphere of {len(faces):,} triangles",
        f"trimesh {adapters.trimesh_version()}",
        times["trimesh"],
        times["polhode"],
        f"agreement {agree:.1e} relative",
    )


def mesh_offset(subdivisions: int = 5, exponents: Sequence[int] = range(0, 9)) -> str:
    """The icosphere (vertices on a 2^-24 grid, so that the shift is exact) moved by
    d (1, -0.5, 0.25): the relative error of the inertia about the centre of mass against the
    unmoved mesh, for polhode and for trimesh (a one-line note instead without trimesh)."""
    sphere = adapters.icosphere(subdivisions)
    if sphere is None:
        return "(trimesh not installed: far-offset comparison left out)"
    vertices, faces = sphere
    base = Body.mesh(vertices, faces, density=1.0).inertia
    lines = [f"{'d':>6s} {'polhode':>10s} {'trimesh':>10s}"]
    for exponent in exponents:
        d = 10.0**exponent
        moved = vertices + np.array([d, -0.5 * d, 0.25 * d])
        ours = Body.mesh(moved, faces, density=1.0).inertia
        theirs = adapters.trimesh_mass_properties(moved[faces]).inertia
        err = [np.linalg.norm(x - base) / np.linalg.norm(base) for x in (ours, theirs)]
        lines.append(f"1e{exponent:<4d} {err[0]:10.2e} {err[1]:10.2e}")
    return "\n".join(lines)
