"""Principal axes followed along a series: the cost per frame of ``continuous=True``, for
distinct moments and for a symmetric top (every frame degenerate), against the solve alone.

    python -m benchmarks.bench_follow [--frames T] [--repeats R]

T frames (default 1e6) of a body tumbling smoothly (its axis turned by a random walk of about
0.6 degrees per frame); medians of R calls (default 5) in ns per frame, wall time. The
following runs in Rust after the solve (polhode::series): matching each frame's signed
permutation, or a Procrustes problem for a degenerate frame. When it was Python's, a symmetric
top cost 104-138 us per frame; distinct moments about 0.6 us.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.spatial.transform import Rotation

import polhode as ph


def series(frames: int, moments: tuple[float, float, float]) -> np.ndarray:
    rng = np.random.default_rng(1)
    turns = Rotation.from_rotvec(np.cumsum(rng.normal(scale=0.01, size=(frames, 3)), axis=0))
    r = turns.as_matrix()
    tensors = r @ np.diag(moments) @ r.transpose(0, 2, 1)
    return (tensors + tensors.transpose(0, 2, 1)) / 2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    print(f"{args.frames} frames, median of {args.repeats} (ns per frame, wall)")
    print(f"{'body':<16}{'solve':>10}{'continuous':>12}{'following':>12}")
    for name, moments in [("distinct", (1.0, 2.0, 3.0)), ("symmetric top", (1.0, 1.0, 3.0))]:
        tensors = series(args.frames, moments)
        ph.principal(tensors)  # page faults of the first call
        medians = []
        for continuous in (False, True):
            times = []
            for _ in range(args.repeats):
                started = time.perf_counter()
                ph.principal(tensors, continuous=continuous)
                times.append(time.perf_counter() - started)
            medians.append(1e9 * statistics.median(times) / args.frames)
        print(f"{name:<16}{medians[0]:>10.0f}{medians[1]:>12.0f}{medians[1] - medians[0]:>12.0f}")


if __name__ == "__main__":
    main()
