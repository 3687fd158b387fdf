"""Principal axes and point-mass assembly against numpy, in one run.

    python -m benchmarks.bench_principal [--quick] [--repeats R]

1. The batch eigensolve `polhode.principal` against `numpy.linalg.eigh` on 1e6 random
   symmetric tensors and on 1e6 rotated diag(1, 1, 2) (degenerate): median times, the ratio,
   and the worst residual ||A V - V diag(w)|| / ||A||_F of each, in eps.
2. `Body.point_masses(m, r).inertia` against a numpy reference on 1e7 points.
"""

from __future__ import annotations

import argparse

from polhode import bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1e5 tensors, 1e6 points")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    n_eig, n_pts = (100_000, 1_000_000) if args.quick else (1_000_000, 10_000_000)
    print(f"# bench_principal ({bench.machine()})")
    for result in bench.eigensolve(n_eig, args.repeats):
        print(result.table())
    print(bench.point_masses(n_pts, args.repeats).table())


if __name__ == "__main__":
    main()
