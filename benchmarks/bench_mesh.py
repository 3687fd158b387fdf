"""Mesh mass properties against trimesh, in one run.

    python -m benchmarks.bench_mesh [--subdivisions S] [--repeats R]

1. Speed: `Body.mesh` (validation of closedness and winding included) against
   `trimesh.triangles.mass_properties` on an icosphere with 20 * 4^S triangles (S = 7:
   327,680), median times and the ratio. trimesh is given its triangles array ready-made.
2. Far-offset accuracy: the same icosphere (vertices on a 2^-24 grid, so the shift is exact)
   moved by d = 1e0 ... 1e8; the relative error of the inertia tensor about the centre of mass
   against the unshifted mesh, for both.
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

import polhode as ph
from benchmarks._common import interleaved, machine, summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--subdivisions", type=int, default=7)
    parser.add_argument("--repeats", type=int, default=21)
    args = parser.parse_args()
    import trimesh

    print(machine() + f", trimesh {trimesh.__version__}")
    mesh = trimesh.creation.icosphere(subdivisions=args.subdivisions, radius=1.0)
    vertices = np.round(np.asarray(mesh.vertices) * 2.0**24) / 2.0**24
    faces = np.ascontiguousarray(mesh.faces, dtype=np.int64)
    triangles = vertices[faces]
    print(f"icosphere: {len(faces):,} triangles, {len(vertices):,} vertices")

    times, results = interleaved(
        {
            "polhode Body.mesh": lambda: ph.Body.mesh(vertices, faces, density=1.0),
            "trimesh mass_properties": lambda: trimesh.triangles.mass_properties(
                triangles, density=1.0
            ),
        },
        args.repeats,
    )
    for name, seconds in times.items():
        print(f"  {name:26s} {summary(seconds)}")
    ratio = statistics.median(times["trimesh mass_properties"]) / statistics.median(
        times["polhode Body.mesh"]
    )
    print(f"  speed-up (median trimesh / median polhode): {ratio:.1f}x")
    body = results["polhode Body.mesh"]
    props = results["trimesh mass_properties"]
    agree = np.linalg.norm(body.inertia - props.inertia) / np.linalg.norm(props.inertia)
    print(f"  agreement at the origin: |I_polhode - I_trimesh| / |I| = {agree:.2e}")

    print("far offset d * (1, -0.5, 0.25): relative error of the inertia about the centre")
    print(f"  {'d':>6s} {'polhode':>10s} {'trimesh':>10s}")
    base = body.inertia
    for exponent in range(0, 9):
        d = 10.0**exponent
        moved = vertices + np.array([d, -0.5 * d, 0.25 * d])
        ours = ph.Body.mesh(moved, faces, density=1.0).inertia
        theirs = trimesh.triangles.mass_properties(moved[faces], density=1.0).inertia
        err = [np.linalg.norm(x - base) / np.linalg.norm(base) for x in (ours, theirs)]
        print(f"  1e{exponent:<4d} {err[0]:10.2e} {err[1]:10.2e}")


if __name__ == "__main__":
    main()
