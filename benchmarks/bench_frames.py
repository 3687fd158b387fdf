"""Principal axes over a trajectory: polhode against MDAnalysis's per-frame principal_axes().

    python -m benchmarks.bench_frames [--frames T] [--atoms N] [--repeats R] [--quick]

A protein-sized cloud (N atoms, default 3,000: H, C, N, O and S in a protein's proportions, an
asymmetric Gaussian blob of 24 x 16 x 10 angstrom) tumbles smoothly through T frames (default
1e4; the rotation turns by about 2 degrees per frame about a slowly wandering axis) with
0.3-angstrom thermal jitter in every frame, stored as float32 (T, N, 3) as MD trajectories are.

Timed, each from the same array in memory:

- MDAnalysis: ``for ts in u.trajectory: ag.principal_axes()`` over a Universe whose
  MemoryReader holds that array (the per-frame loop its users write);
- polhode: ``ph.principal(ph.point_masses_inertia(masses, xyz), continuous=True)``.

They take turns, R rounds (default 3); the table gives the median wall and CPU times (all
threads; polhode runs on every core) and the ratio of the wall times. Then the
flips: a frame whose axis has a negative dot product with the same axis in the previous frame
(the motion is smooth, so every flip is spurious), per axis, for both; and the largest angle
between the two libraries' axes (after matching MDAnalysis's descending rows to polhode's
columns), which checks that they computed the same axes.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import polhode as ph

# Atoms of a protein by element (about 50% H, 32% C, 9% N, 9.6% O, 0.4% S), their masses in u.
_ELEMENTS = {
    "H": (0.50, 1.008),
    "C": (0.32, 12.011),
    "N": (0.085, 14.007),
    "O": (0.091, 15.999),
    "S": (0.004, 32.06),
}


def trajectory(frames: int, atoms: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(masses (N,), positions (T, N, 3) float32) of the tumbling, jittering cloud."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    share = np.array([v[0] for v in _ELEMENTS.values()])
    kind = rng.choice(len(share), size=atoms, p=share / share.sum())
    masses = np.array([v[1] for v in _ELEMENTS.values()])[kind]
    cloud = rng.normal(size=(atoms, 3)) * [12.0, 8.0, 5.0]
    # Angular velocity: 2 degrees per frame about an axis that wanders slowly.
    t = np.arange(frames)
    axis = np.stack([np.cos(t / 900.0), np.sin(t / 900.0), 0.5 * np.cos(t / 1700.0)], axis=1)
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    steps = Rotation.from_rotvec(np.radians(2.0) * axis)
    orientation = [Rotation.identity()]
    for step in steps[1:]:
        orientation.append(step * orientation[-1])
    matrices = Rotation.concatenate(orientation).as_matrix()
    positions = np.empty((frames, atoms, 3), dtype=np.float32)
    for start in range(0, frames, 500):
        block = slice(start, min(start + 500, frames))
        moved = np.einsum("tij,nj->tni", matrices[block], cloud)
        moved += rng.normal(scale=0.3, size=moved.shape)
        positions[block] = moved + [30.0, -10.0, 55.0]
    return masses, positions


def flips(axes: np.ndarray) -> np.ndarray:
    """Per axis, the frames whose axis has a negative dot product with the previous frame's;
    ``axes`` (T, 3, 3) with the axes as columns."""
    dots = np.einsum("tik,tik->tk", axes[1:], axes[:-1])
    return (dots < 0).sum(axis=0)


def main() -> None:
    import MDAnalysis as mda
    from MDAnalysis.coordinates.memory import MemoryReader

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000)
    parser.add_argument("--atoms", type=int, default=3_000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="1,000 frames, 2 rounds")
    args = parser.parse_args()
    if args.quick:
        args.frames, args.repeats = 1_000, 2
    masses, xyz = trajectory(args.frames, args.atoms)
    universe = mda.Universe.empty(args.atoms, trajectory=False)
    universe.add_TopologyAttr("masses", masses)
    universe.load_new(xyz, format=MemoryReader, order="fac")
    group = universe.atoms

    def run_mdanalysis() -> np.ndarray:
        out = np.empty((len(universe.trajectory), 3, 3))
        for i, _ in enumerate(universe.trajectory):
            out[i] = group.principal_axes()
        return out

    def run_polhode() -> ph.Principal:
        return ph.principal(ph.point_masses_inertia(masses, xyz), continuous=True)

    times: dict[str, list[float]] = {"MDAnalysis": [], "polhode": []}
    cpu: dict[str, list[float]] = {"MDAnalysis": [], "polhode": []}
    results: dict[str, object] = {}
    for _ in range(args.repeats):
        for name, run in (("MDAnalysis", run_mdanalysis), ("polhode", run_polhode)):
            started, cpu_started = time.perf_counter(), time.process_time()
            results[name] = run()
            times[name].append(time.perf_counter() - started)
            cpu[name].append(time.process_time() - cpu_started)
    # The two parts of polhode's call, once each.
    started = time.perf_counter()
    inertia = ph.point_masses_inertia(masses, xyz)
    t_inertia = time.perf_counter() - started
    started = time.perf_counter()
    ph.principal(inertia, continuous=True)
    t_follow = time.perf_counter() - started

    mda_rows = results["MDAnalysis"]
    assert isinstance(mda_rows, np.ndarray)
    mda_axes = mda_rows.transpose(0, 2, 1)[:, :, ::-1]  # rows, descending -> columns, ascending
    p = results["polhode"]
    assert isinstance(p, ph.Principal)
    angle = np.degrees(
        np.arccos(np.clip(np.abs(np.einsum("tik,tik->tk", p.axes, mda_axes)), 0.0, 1.0))
    )
    median = {name: statistics.median(v) for name, v in times.items()}
    print(
        f"# bench_frames: {args.frames} frames of {args.atoms} atoms (float32), "
        f"median of {args.repeats} rounds"
    )
    print(
        f"{'':12s} {'time (s)':>9s} {'per frame (us)':>15s} {'CPU (s)':>9s} {'flips per axis':>16s}"
    )
    for name, axes in (("MDAnalysis", mda_axes), ("polhode", p.axes)):
        per = 1e6 * median[name] / args.frames
        used = statistics.median(cpu[name])
        print(
            f"{name:12s} {median[name]:9.3f} {per:15.1f} {used:9.3f} "
            f"{str(flips(axes).tolist()):>16s}"
        )
    print(f"ratio (MDAnalysis / polhode): {median['MDAnalysis'] / median['polhode']:.1f}x")
    print(
        f"polhode parts: point_masses_inertia {t_inertia:.3f} s, "
        f"principal(continuous=True) {t_follow:.3f} s"
    )
    print(f"largest angle between the two libraries' axes: {angle.max():.2e} degrees")
    spread = max((max(v) - min(v)) / statistics.median(v) for v in times.values())
    print(f"(times spread up to {100 * spread:.0f}% of the median)")


if __name__ == "__main__":
    main()
