"""Mesh mass properties against trimesh, in one run.

    python -m benchmarks.bench_mesh [--quick] [--subdivisions S] [--repeats R]

1. Speed: `Body.mesh` (with its closedness and winding check) against
   `trimesh.triangles.mass_properties` on an icosphere of 20 * 4^S triangles (S = 7: 327,680);
   trimesh is given its triangles array ready-made.
2. Far from the origin: the icosphere (vertices on a 2^-24 grid, so that the shift is exact)
   moved by d = 1e0 ... 1e8; the relative error of the inertia about the centre of mass
   against the unmoved mesh, for both.
"""

from __future__ import annotations

import argparse

from polhode import bench


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="S = 5 (20,480 triangles)")
    parser.add_argument("--subdivisions", type=int, default=None)
    parser.add_argument("--repeats", type=int, default=21)
    args = parser.parse_args()
    s = args.subdivisions if args.subdivisions is not None else (5 if args.quick else 7)
    print(f"# bench_mesh ({bench.machine()})")
    result = bench.mesh(s, args.repeats)
    if result is None:
        raise SystemExit("bench_mesh needs trimesh: pip install 'polhode[bench]'")
    print(result.table())
    print("far offset d (1, -0.5, 0.25): relative error of the inertia about the centre")
    print(bench.mesh_offset(min(s, 5)))


if __name__ == "__main__":
    main()
