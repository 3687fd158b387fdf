"""Principal axes and point-mass assembly against numpy, in one run.

    python -m benchmarks.bench_principal [--quick] [--repeats R]

1. The batch eigensolve `polhode.principal` against `numpy.linalg.eigh` on 1e6 random
   symmetric tensors and on 1e6 inertia-like (degenerate) ones: median time, the ratio, and
   the worst relative residual ||A V - V diag(w)|| / ||A|| of each.
2. `Body.point_masses` against a numpy reference (centre, then the second-moment matrix and the
   inertia tensor) on 1e7 points.
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np
from scipy.spatial.transform import Rotation

import polhode as ph
from benchmarks._common import interleaved, machine, summary


def random_tensors(n: int, rng: np.random.Generator) -> np.ndarray:
    a = rng.normal(size=(n, 3, 3))
    return 0.5 * (a + a.transpose(0, 2, 1))


def degenerate_tensors(n: int, rng: np.random.Generator) -> np.ndarray:
    """Rotated symmetric-top tensors R diag(1, 1, 2) R^T: every one has a double moment."""
    r = Rotation.random(n, random_state=rng).as_matrix()
    d = np.array([1.0, 1.0, 2.0])
    return np.einsum("nij,j,nkj->nik", r, d, r)


def worst_residual(a: np.ndarray, w: np.ndarray, v: np.ndarray) -> float:
    r = a @ v - v * w[:, None, :]
    return float(np.max(np.linalg.norm(r, axis=(1, 2)) / np.linalg.norm(a, axis=(1, 2))))


def bench_eigen(n: int, repeats: int) -> None:
    rng = np.random.default_rng(0)
    eps = np.finfo(float).eps
    for label, tensors in [
        ("random symmetric", random_tensors(n, rng)),
        ("degenerate (rotated diag(1, 1, 2))", degenerate_tensors(n, rng)),
    ]:
        times, results = interleaved(
            {
                "numpy.linalg.eigh": lambda t=tensors: np.linalg.eigh(t),
                "polhode.principal": lambda t=tensors: tuple(ph.principal(t)),
            },
            repeats,
        )
        ratio = statistics.median(times["numpy.linalg.eigh"]) / statistics.median(
            times["polhode.principal"]
        )
        print(f"\n{label}, N = {n:.0e}")
        for name in times:
            w, v = results[name]
            res = worst_residual(tensors, w, v) / eps
            print(f"  {name:20s} {summary(times[name])}   worst residual {res:5.2f} eps ||A||")
        print(f"  speed-up of polhode over eigh: {ratio:.1f}x")


def numpy_point_masses(m: np.ndarray, r: np.ndarray) -> np.ndarray:
    """The numpy reference: centre of mass, centred second moments, inertia tensor."""
    com = m @ r / m.sum()
    d = r - com
    c = (d * m[:, None]).T @ d
    return np.trace(c) * np.eye(3) - c


def bench_points(n: int, repeats: int) -> None:
    rng = np.random.default_rng(1)
    m = rng.uniform(0.5, 2.0, n)
    r = rng.normal(size=(n, 3)) * [1.0, 2.0, 3.0]
    times, results = interleaved(
        {
            "numpy reference": lambda: numpy_point_masses(m, r),
            "Body.point_masses": lambda: ph.Body.point_masses(m, r).inertia,
        },
        repeats,
    )
    ratio = statistics.median(times["numpy reference"]) / statistics.median(
        times["Body.point_masses"]
    )
    diff = np.abs(results["numpy reference"] - results["Body.point_masses"]).max()
    scale = np.abs(results["numpy reference"]).max()
    print(f"\npoint-mass assembly, N = {n:.0e}")
    for name in times:
        print(f"  {name:20s} {summary(times[name])}")
    print(
        f"  speed-up of polhode over numpy: {ratio:.2f}x   (agreement {diff / scale:.1e} relative)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1e5 tensors, 1e6 points")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    n_eig, n_pts = (100_000, 1_000_000) if args.quick else (1_000_000, 10_000_000)
    print(f"# bench_principal ({machine()})")
    bench_eigen(n_eig, args.repeats)
    bench_points(n_pts, args.repeats)


if __name__ == "__main__":
    main()
