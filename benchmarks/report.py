"""Regenerates docs/benchmarks.md and its plots (docs/img/*.png) from one run of the suite.

    python -m benchmarks.report [--quick] [--criterion] [--out docs/benchmarks.md]

Runs every benchmark of polhode.bench (work-precision on three cases, invariant drift, batch
throughput, eigensolve, point masses, meshes, the kernels against the hardware) in this
process and, with ``--criterion``, the Rust kernels' criterion benches (`cargo bench -p
polhode-bench --bench kernels`). Every number and every sentence that carries one in the
document is written by this script: regenerate it, do not edit it by hand. The full run takes
about ten minutes on 2 cores.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
from collections.abc import Sequence
from pathlib import Path

from polhode import bench

TARGET_SCIPY = 100.0  # the target: at least 100x scipy DOP853 at matching error
TARGET_RK4_RATE = 3e7  # body-steps per second, rk4 with orientation, N >= 1e4
TARGET_EIGH = 10.0
LEVELS = (1e-6, 1e-8, 1e-10, 1e-12)


def _block(text: str) -> str:
    return f"```\n{text}\n```\n"


def _ratios(
    result: bench.WorkPrecision, ours: str | None, peer: str, which: str
) -> list[tuple[float, str, float | None]]:
    """(level, polhode's series, ratio peer/polhode or None where either does not reach it)."""
    peer_series = result.get(peer)
    out: list[tuple[float, str, float | None]] = []
    for level in LEVELS:
        if ours is None:
            best = bench.best_at(result, level, peer=False, which=which)
            name, cost = (best[0][8:], best[1]) if best else ("-", None)
        else:
            series = result.get(ours)
            cost = None if series is None else bench.cost_at(series, level, which)
            name = ours[8:]
        theirs = None if peer_series is None else bench.cost_at(peer_series, level, which)
        out.append((level, name, None if cost is None or theirs is None else theirs / cost))
    return out


def _reading_work_precision(result: bench.WorkPrecision) -> list[str]:
    lines = []
    for which in ("omega", "orientation"):
        lines.append(f"- Error of the {which}:")
        dop = _ratios(result, "polhode dop853", "scipy DOP853", which)
        reached = [(lv, r) for lv, _, r in dop if r is not None]
        if reached:
            low = min(r for _, r in reached)
            high = max(r for _, r in reached)
            missed = [f"{lv:.0e}" for lv, r in reached if r < TARGET_SCIPY]
            verdict = (
                f"below the {TARGET_SCIPY:.0f}x target at {', '.join(missed)}"
                if missed
                else f"the {TARGET_SCIPY:.0f}x target met at each"
            )
            span = f"{low:.0f}x" if f"{low:.0f}" == f"{high:.0f}" else f"{low:.0f}x to {high:.0f}x"
            lines.append(
                f"  - polhode's dop853 against scipy's DOP853 at matching error: {span} faster "
                f"at {', '.join(f'{lv:.0e}' for lv, _ in reached)}; {verdict}."
            )
        unreached = [f"{lv:.0e}" for lv, _, r in dop if r is None]
        if unreached:
            lines.append(
                f"  - Not compared at {', '.join(unreached)}: scipy's DOP853 (rtol >= 1e-12, "
                "within the time budget) or polhode's dop853 does not get there."
            )
        best = _ratios(result, None, "scipy DOP853", which)
        fastest = [f"{lv:.0e} {name} {r:.0f}x" for lv, name, r in best if r is not None]
        if fastest:
            lines.append(
                "  - polhode's fastest method at each level against scipy's DOP853: "
                + "; ".join(fastest)
                + "."
            )
        mujoco = [(lv, n, r) for lv, n, r in _ratios(result, None, "MuJoCo RK4", which) if r]
        if mujoco:
            slower = [f"{lv:.0e}" for lv, _, r in mujoco if r < 1.0]
            lines.append(
                "  - polhode's fastest method against MuJoCo's RK4: "
                + "; ".join(f"{lv:.0e} {name} {r:.0f}x" for lv, name, r in mujoco)
                + (f"; slower at {', '.join(slower)}." if slower else ".")
            )
    exact = result.get("polhode exact")
    if exact and exact.points:
        p = exact.points[0]
        lines.append(
            f"- The exact solution: {p.median * 1e3:.3f} ms per call, with errors "
            f"{p.error_omega:.1e} (omega) and {p.error_orientation:.1e} rad (orientation) "
            "against the "
            "30-digit reference."
        )
    return lines


def _reading_drift(result: bench.Drift) -> list[str]:
    lines = []
    for name, errors in result.errors.items():
        half = len(result.t) // 2
        grows = {
            k: float(errors[k][half:].max() / max(errors[k][:half].max(), 1e-300)) for k in errors
        }
        lines.append(
            f"- {name}: largest relative error of T {errors['T'].max():.1e}, of |L| "
            f"{errors['|L|'].max():.1e}, of L in space {errors['L'].max():.1e}; "
            f"second half against first (growth factor) T {grows['T']:.2g}, "
            f"L in space {grows['L']:.2g}."
        )
    return lines


def _reading_throughput(result: bench.Throughput) -> list[str]:
    lines = []
    rate = result.rate("rk4", True)
    big = {n: r for n, r in rate.items() if n >= 10_000}
    if big:
        worst = min(big.values())
        best = max(big.values())
        lines.append(
            f"- rk4 with orientation, N >= 1e4: {worst:.3g} to {best:.3g} body-steps per second "
            f"(target {TARGET_RK4_RATE:.0e}): "
            + ("met." if worst >= TARGET_RK4_RATE else "**not met at every N**.")
        )
    for method in dict.fromkeys(row[0] for row in result.rows):
        for orientation in (True, False):
            r = result.rate(method, orientation)
            if r:
                unit = "evaluations" if method == "exact" else "body-steps"
                lines.append(
                    f"- {method} ({'with' if orientation else 'without'} orientation): "
                    f"{min(r.values()):.3g} to {max(r.values()):.3g} {unit} per second "
                    f"(N = {min(r)} to {max(r)}); at N = 1: {r.get(1, float('nan')):.3g}."
                )
    return lines


def _kernels_section(quick: bool, repeats: int) -> list[str]:
    """The "Kernels against the hardware" section: the roofline table of
    :mod:`polhode.bench.kernels` and the rows that miss their target."""
    from polhode.bench import kernels

    result = kernels.run(quick=quick, repeats=repeats)
    sizes = "a tenth of the sizes below (meshes of 20,480 faces)" if quick else "these sizes"
    missed = [row.kernel for row in result.rows if not row.met]
    return [
        "## Kernels against the hardware",
        "",
        "`python -m benchmarks.bench_kernels" + (" --quick" if quick else "") + "` or "
        "`polhode bench --kernels" + (" --quick" if quick else "") + "`. Each kernel "
        f"at {sizes}: batch eigensolve of 1e6 random and 1e6 degenerate tensors against "
        "`numpy.linalg.eigh`, a mesh of 327,680 faces against trimesh, 1e7 point masses "
        "against the numpy reference, the exact solution per output time (full state and "
        "omega alone, 2e5 times) against `scipy.special.ellipj` at as many arguments, batch "
        "rk4, splitting and midpoint (1e5 bodies, 200 steps, with orientation) against a numpy "
        "structure-of-arrays rk4, and one small call (`simulate` of one body at 2 times, "
        "`analyze`) against `Rotation.from_rotvec(...).as_matrix()`. Ratio: the peer's time "
        "over polhode's, medians of interleaved repeats in this run; the target is the ratio "
        "to reach. Flops and bytes per element are counts written in "
        "`python/polhode/bench/kernels.py` (the bytes the compulsory traffic); the fraction of "
        "the limit is the roofline's time, max(flops / peak, bytes / bandwidth), over the "
        "time measured, '-' where the work has no meaningful flop count (transcendental "
        "functions, iterations, a Python call).",
        "",
        result.table(),
        "",
        (
            f"- Targets met: {len(result.rows) - len(missed)} of {len(result.rows)}"
            + (f"; not met: {', '.join(missed)}." if missed else ".")
        ),
        "",
    ]


def _criterion(out: list[str]) -> None:
    """Runs the criterion benches and appends the median of each to ``out``."""
    root = Path(__file__).resolve().parent.parent
    subprocess.run(
        [
            "cargo",
            "bench",
            "-p",
            "polhode-bench",
            "--bench",
            "kernels",
            "--",
            "--warm-up-time",
            "0.5",
            "--measurement-time",
            "2",
        ],
        cwd=root,
        check=True,
        stdout=subprocess.DEVNULL,
    )
    out.append("| kernel | median | 95% interval |")
    out.append("|---|---|---|")
    for estimates in sorted((root / "target" / "criterion").glob("*/*/new/estimates.json")):
        data = json.loads(estimates.read_text())
        median = data["median"]
        bench_json = json.loads((estimates.parent / "benchmark.json").read_text())
        name = bench_json.get("full_id", f"{estimates.parts[-4]}/{estimates.parts[-3]}")

        def ns(x: float) -> str:
            return f"{x / 1e3:.3g} us" if x >= 1e3 else f"{x:.3g} ns"

        ci = median["confidence_interval"]
        # A bench over a batch declares its elements: quote the time per element.
        per = float((bench_json.get("throughput") or {}).get("Elements", 1))
        suffix = f" (batch of {per:.0f}, per element)" if per > 1 else ""
        out.append(
            f"| {name}{suffix} | {ns(median['point_estimate'] / per)} | "
            f"{ns(ci['lower_bound'] / per)} to {ns(ci['upper_bound'] / per)} |"
        )


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the quick settings (a draft)")
    parser.add_argument("--criterion", action="store_true", help="also run cargo bench")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--out", default="docs/benchmarks.md")
    args = parser.parse_args(argv)
    out_path = Path(args.out)
    img = out_path.parent / "img"
    img.mkdir(parents=True, exist_ok=True)
    quick = args.quick
    repeats = 3 if quick else args.repeats
    command = "python -m benchmarks.report" + (" --quick" if quick else "")
    command += " --criterion" if args.criterion else ""
    doc: list[str] = [
        "# Benchmarks",
        "",
        "Generated by `" + command + "` on "
        f"{datetime.date.today().isoformat()}: do not edit by hand, regenerate. Machine: "
        f"{bench.machine()}; {bench.peers()}.",
        "",
        "Every figure comes from `polhode.bench`, which runs polhode and its peers in the same "
        "process, alternating between them in each repeat, and keeps every repeat: the tables "
        f"give the median of {repeats} and the spread (min-max). The machine is a shared "
        "2-core VM whose timings vary by about 20% from one minute to the next. Errors of the "
        "motion are against a 30-digit reference computed by an independent exact-arithmetic "
        "Taylor integrator (`tests/reference_motion.py`), not against another double-precision "
        "solver. Each section names the script that reproduces it alone.",
        "",
    ]

    print("work-precision ...", flush=True)
    doc += [
        "## Work-precision: one body, torque-free",
        "",
        "`python -m benchmarks.bench_workprecision --case all --plot docs/img`. Wall time of the "
        "whole Python call (argument checks and outputs included) against the error at the end "
        "time: the relative error of omega and the angle (rad) between the orientation and the "
        "reference. polhode's methods sweep rtol (dop853) or dt (the fixed-step ones); scipy's "
        "`solve_ivp` integrates the 7 equations of omega and the quaternion with a numpy "
        "right-hand side and atol = rtol |omega0|; MuJoCo integrates a free body with gravity "
        "off, its angular velocity in body axes, by `mujoco.rollout` (no Python loop per "
        "step). A series stops at the first setting whose call exceeds its time budget. The "
        "'cost to reach' tables interpolate each series' cheapest settings (log-log) to the "
        "error level; '-' means the series does not reach it.",
        "",
    ]
    for case in bench.CASES:
        result = bench.work_precision(
            case, quick=quick, repeats=repeats, budget=1.0 if quick else 3.0
        )
        png = bench.plot_work_precision(result, str(img / f"work_precision_{case}.png"))
        doc += [
            f"### {result.case.label}",
            "",
            f"![work-precision {case}](img/{Path(png).name})",
            "",
        ]
        doc += [_block(result.table())]
        for which in ("omega", "orientation"):
            doc += [f"Cost to reach each error of the {which} (ms) and the ratios:", ""]
            doc += [_block(bench.targets(result, which=which))]
        doc += _reading_work_precision(result) + [""]
        print(f"  {case} done", flush=True)

    print("drift ...", flush=True)
    drift = bench.drift("flip", steps=100_000 if quick else 1_000_000)
    png = bench.plot_drift(drift, str(img / "drift.png"))
    doc += [
        "## Invariant drift over a long run",
        "",
        "`python -m benchmarks.bench_drift --plot docs/img`. Relative errors of the energy T, "
        "of |L| and of L in space (|L(t) - L(0)| / |L(0)|) at log-spaced times, for each "
        "fixed-step method with dt = 0.01, and dop853 at rtol 1e-10 over the same span.",
        "",
        f"![drift](img/{Path(png).name})",
        "",
        _block(drift.table()),
    ]
    doc += _reading_drift(drift) + [""]
    doc += [
        "What the methods promise (and the tests check): the splittings keep |L| and L in space "
        "exactly, up to round-off, and their energy error stays bounded; the implicit midpoint "
        "rule keeps T and |L| exactly, but its orientation update does not keep L in space; RK4 "
        "and DOP853 keep nothing exactly, and drift. A growth factor near 1 is a bounded "
        "error; at the 1e-13 level and below it measures round-off accumulating, not the "
        "method.",
        "",
    ]

    print("throughput ...", flush=True)
    if quick:
        tp = bench.throughput(
            sizes=(1, 100, 10_000, 100_000), methods=("rk4", "exact"), work=2e6, repeats=repeats
        )
    else:
        tp = bench.throughput(repeats=3)
    png = bench.plot_throughput(tp, str(img / "throughput.png"))
    doc += [
        "## Batch throughput",
        "",
        "`python -m benchmarks.bench_throughput --plot docs/img`. N random bodies on all cores, "
        "about 2e7 rk4 body-steps per call (at least 10 steps each; midpoint a half, the "
        "splitting a quarter, dop853 an eighth as many), dt = 0.01 (dop853: rtol 1e-8); the "
        "exact method on an eighth as many output times. Whole Python call.",
        "",
        f"![throughput](img/{Path(png).name})",
        "",
        _block(tp.table()),
    ]
    doc += _reading_throughput(tp) + [""]

    print("mass properties ...", flush=True)
    doc += [
        "## Principal axes and mass properties",
        "",
        "`python -m benchmarks.bench_principal` and `python -m benchmarks.bench_mesh`.",
        "",
    ]
    versus = bench.eigensolve(100_000 if quick else 1_000_000, repeats)
    versus.append(bench.point_masses(1_000_000 if quick else 10_000_000, repeats))
    m = bench.mesh(5 if quick else 7, repeats if quick else 11)
    if m is not None:
        versus.append(m)
    for v in versus:
        doc.append(_block(v.table()))
    eig = [v.ratio for v in versus[:2]]
    doc += [
        f"- Eigensolve: {min(eig):.1f}x and {max(eig):.1f}x numpy.linalg.eigh (target "
        f"{TARGET_EIGH:.0f}x: {'met' if min(eig) >= TARGET_EIGH else '**not met on both**'}).",
        f"- Point masses: {versus[2].ratio:.1f}x the numpy reference.",
    ]
    if m is not None:
        doc.append(f"- Meshes: {m.ratio:.1f}x trimesh.")
    doc += [
        "",
        "Far from the origin: the icosphere moved by d (1, -0.5, 0.25), relative error of the "
        "inertia about the centre of mass against the unmoved mesh:",
        "",
        _block(bench.mesh_offset(5)),
    ]

    print("kernels ...", flush=True)
    doc += _kernels_section(quick, args.repeats)

    if args.criterion:
        print("criterion ...", flush=True)
        doc += [
            "## The kernels in Rust (criterion)",
            "",
            "`cargo bench -p polhode-bench --bench kernels -- --warm-up-time 0.5 "
            "--measurement-time 2` (the batch kernels use both cores).",
            "",
        ]
        _criterion(doc)
        doc.append("")

    out_path.write_text("\n".join(doc).rstrip() + "\n")
    print(f"wrote {out_path} and {img}/*.png")


if __name__ == "__main__":
    os.environ.setdefault("MPLBACKEND", "Agg")
    main()
