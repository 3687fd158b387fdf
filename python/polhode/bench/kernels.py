"""The kernels against the hardware: a roofline of each of polhode's batch kernels and small
calls, beside the peer each is measured against in the same run.

One function per kernel; each times polhode and its peer as a median of at least five
interleaved repeats (:func:`polhode.bench._timing.interleaved`, or the measurement functions of
:mod:`polhode.bench.mass`, which interleave the same way) and returns a :class:`Row`:

====================================  ===============================  ==============
kernel                                peer (same run, same input)      target ratio
====================================  ===============================  ==============
:func:`eigensolve` (random, degen.)   ``numpy.linalg.eigh``            >= 25x
:func:`mesh` (327,680 faces)          trimesh's ``mass_properties``    >= 25x
:func:`point_masses` (1e7 points)     a numpy reference                >= 10x
:func:`exact` (full state, omega)     ``scipy.special.ellipj``         >= 1x, >= 2x
:func:`batch` (rk4, splitting, mid.)  a numpy structure-of-arrays rk4  >= 30x (rk4)
:func:`small_calls`                   ``Rotation.from_rotvec``         >= 1x
====================================  ===============================  ==============

The ratio is the peer's time over polhode's (how many times faster polhode is; for the exact
solution and the small calls the targets say polhode costs at most the peer's time, or half
of it, so the ratio must reach 1 or 2).

Beside the ratio each row gives the flops and bytes per element, written below as constants
with the count that gives each, and the fraction of the machine's limit polhode reaches:
``max(flops / peak, bytes / bandwidth) / time`` per element, the roofline's bound over the
time measured (1 is the hardware's limit). :func:`machine_limits` measures the memory
bandwidth in the same run and derives the peak flop rate from the CPU's vector width. Where the
work has no flop count that means something (transcendental functions, iterations that vary,
one Python call), the flops are left out and so is the fraction.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode.analysis import analyze
from polhode.bench import adapters, mass
from polhode.bench._timing import interleaved as _interleaved
from polhode.bench._timing import median as _median
from polhode.simulation import simulate

Array = NDArray[np.float64]

__all__ = [
    "BYTES",
    "FLOPS",
    "TARGETS",
    "Kernels",
    "Limits",
    "Row",
    "batch",
    "eigensolve",
    "exact",
    "machine_limits",
    "mesh",
    "point_masses",
    "run",
    "small_calls",
]

# --------------------------------------------------------------------------------------------
# Work per element: flops and bytes, each with its count.

#: Flops per element of each kernel (None: no count that means something). A division and a
#: square root count as one flop each, as additions and multiplications do.
FLOPS: dict[str, float | None] = {
    # Cyclic Jacobi on a symmetric 3x3 (the algorithm of polhode's eigensolve), 4 sweeps of 3
    # rotations (double precision is reached in 3 to 5). One rotation of the (p, q) plane:
    #   theta = (a_qq - a_pp) / (2 a_pq)                                1 sub, 1 mul, 1 div
    #   t = sign(theta) / (|theta| + sqrt(theta^2 + 1))                1 mul, 2 add, 1 sqrt, 1 div
    #   c = 1 / sqrt(t^2 + 1), s = t c                                  2 mul, 1 add, 1 sqrt, 1 div
    #                                                                   = 13
    #   a_pp -= t a_pq, a_qq += t a_pq                                  2 mul, 2 add = 4
    #   the third row r: a_rp, a_rq = c a_rp - s a_rq, s a_rp + c a_rq   4 mul, 2 add = 6
    #   the eigenvectors, 3 rows of (v_p, v_q) turned the same way        12 mul, 6 add = 18
    # 41 flops a rotation, 3 a sweep, 4 sweeps: 492.
    "eigensolve": 4 * 3 * (13 + 4 + 6 + 18),
    "eigensolve_degenerate": 4 * 3 * (13 + 4 + 6 + 18),
    # Eberly's polyhedral mass properties (trimesh's algorithm, and the integrals polhode
    # sums), one triangle (v0, v1, v2):
    #   e1 = v1 - v0, e2 = v2 - v0                                      6 sub
    #   d = e1 x e2                                                     6 mul, 3 sub = 9
    #   per axis: s = w0 + w1, f1 = s + w2, w0^2, f2 = w0^2 + w1 s + w2 f1,
    #     f3 = w0 w0^2 + w1 f2' + w2 f2, g_i = f2 + w_i (f1 + w_i) (i = 0, 1, 2)
    #                                                                   21, three axes: 63
    #   the ten integrals: d0 f1x; d_k f2_k (3); d_k f3_k (3); three products
    #     d_k (w0 g0 + w1 g1 + w2 g2) of the next axis                   2 + 6 + 6 + 21 = 35
    # 6 + 9 + 63 + 35 = 113.
    "mesh": 6 + 9 + 63 + 35,
    # The centre then the centred second moments (two passes, as far-offset accuracy needs):
    #   sum m, sum m r                                                  1 + 3 mul + 3 add = 7
    #   d = r - c                                                       3
    #   m d                                                             3
    #   the 6 distinct products (m d_i) d_j, accumulated                12
    # 25 per point.
    "point_masses": 7 + 3 + 3 + 12,
    # Per output time the closed form evaluates Jacobi elliptic functions and a phase:
    # transcendental functions whose cost has no fixed flop count.
    "exact_full": None,
    "exact_omega": None,
    # Classic RK4 on Euler's equations and q' = q (0, omega) / 2, per body-step:
    #   a stage: w_j w_k times (I_j - I_k) / I_i (the ratios precomputed)   3 x 2 mul = 6
    #            the quaternion's rate: 4 components of 3 mul, 2 add        20
    #            (its factor 1/2 is folded into the coefficients)
    #            = 26, four stages                                          104
    #   the three stage states y + h k, 7 components                       3 x 7 x 2 = 42
    #   y + dt/6 (k1 + 2 (k2 + k3) + k4), 7 components: 5 add, 1 mul    7 x 6 = 42
    # 188 per body-step (an earlier count said ~220).
    "rk4": 4 * (6 + 20) + 3 * 7 * 2 + 7 * 6,
    # The splitting's exact sub-rotations take sines and cosines, the implicit midpoint rule
    # iterates to convergence: no fixed count.
    "splitting": None,
    "midpoint": None,
    # One Python call: interpreter work, not flops.
    "simulate": None,
    "analyze": None,
}

#: Bytes per element each kernel must move between memory and the cores at least (compulsory
#: traffic: every input read once, every output written once; all float64 but the faces).
BYTES: dict[str, float | None] = {
    # Read the (3, 3) tensor, write 3 moments and the (3, 3) axes: (9 + 3 + 9) x 8.
    "eigensolve": (9 + 3 + 9) * 8,
    "eigensolve_degenerate": (9 + 3 + 9) * 8,
    # Per face, its three int64 vertex indices (24), and its share of the vertices: a closed
    # triangle mesh has V = F/2 + 2, so about half a vertex (3 doubles) per face: 12.
    "mesh": 3 * 8 + 0.5 * 3 * 8,
    # Read a mass and a position: (1 + 3) x 8.
    "point_masses": (1 + 3) * 8,
    # Write omega (3), the quaternion (4), L in space (3), L in the body (3) and T (1) per time.
    "exact_full": (3 + 4 + 3 + 3 + 1) * 8,
    # Without the orientation: omega, L in the body and T.
    "exact_omega": (3 + 3 + 1) * 8,
    # A body's state stays in registers through its steps: per body its input (moments and
    # omega, 6 doubles) and its outputs at the run's 2 times (14 doubles each); a row divides
    # them by the run's steps (Row.per).
    "rk4": (6 + 2 * 14) * 8,
    "splitting": (6 + 2 * 14) * 8,
    "midpoint": (6 + 2 * 14) * 8,
    "simulate": None,
    "analyze": None,
}

#: The target of each row: the peer's time over polhode's it must reach.
TARGETS: dict[str, float] = {
    "eigensolve": 25.0,
    "eigensolve_degenerate": 25.0,
    "mesh": 25.0,
    "point_masses": 10.0,
    "exact_full": 1.0,  # full state <= 1x ellipj
    "exact_omega": 2.0,  # omega only <= 0.5x ellipj
    "rk4": 30.0,
    # Three times their throughput before this work, as a ratio to the same numpy rk4:
    # SPLITTING_BEFORE and MIDPOINT_BEFORE below.
    "splitting": 0.0,
    "midpoint": 0.0,
    "simulate": 1.0,
    "analyze": 1.0,
}

#: The splitting's (order 4) and the midpoint rule's throughput over the numpy rk4's before
#: the SIMD lanes (main at a6b3e80, 1e5 bodies, 200 steps with orientation, the workload of
#: :func:`batch`: ``python -m benchmarks.bench_throughput --sizes 100000 --methods rk4
#: splitting midpoint --repeats 5`` on that commit's core, at a load of about 1.2 on 2 cores):
#: their targets are three times these.
SPLITTING_BEFORE = 0.868
MIDPOINT_BEFORE = 3.49
TARGETS["splitting"] = 3.0 * SPLITTING_BEFORE
TARGETS["midpoint"] = 3.0 * MIDPOINT_BEFORE


# --------------------------------------------------------------------------------------------
# The machine's limits.


@dataclass(frozen=True)
class Limits:
    """The machine's limits: memory bandwidth (bytes/s, measured) and peak double-precision
    flop rate (flop/s, from the CPU's vector width), with how each was found."""

    bandwidth: float
    peak_flops: float
    how: str


def _cpu_flags() -> set[str]:
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as info:
            for line in info:
                if line.startswith("flags"):
                    return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


def _cpu_ghz() -> float | None:
    """The clock (GHz) the kernel reports for the first CPU (/proc/cpuinfo), or None."""
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as info:
            for line in info:
                if line.startswith("cpu MHz"):
                    return float(line.split(":", 1)[1]) / 1e3
    except (OSError, ValueError):
        pass
    return None


def peak_flops(cores: int | None = None, ghz: float | None = None) -> tuple[float, str]:
    """The peak double-precision flop rate without FMA, and how it is derived.

    cores x clock x lanes x 2: the widest vector the CPU has (AVX-512: 8 doubles, AVX2 or AVX:
    4, else SSE2: 2), two vector floating-point pipes per core (an addition and a
    multiplication each cycle, as on every x86 core since Haswell and Zen), one flop per lane
    per pipe: polhode's kernels use no FMA (the same bits on every CPU), so FMA's doubling is
    not theirs to reach. The clock is the one /proc/cpuinfo reports (3 GHz if none is given);
    a core that boosts above it makes this an underestimate."""
    cores = (os.cpu_count() or 1) if cores is None else cores
    flags = _cpu_flags()
    lanes = 8 if "avx512f" in flags else 4 if "avx" in flags else 2
    clock = _cpu_ghz() if ghz is None else ghz
    clock = 3.0 if clock is None else clock
    flops = cores * clock * 1e9 * lanes * 2
    how = (
        f"peak {flops / 1e9:.1f} Gflop/s = {cores} cores x {clock:.2f} GHz x {lanes} doubles "
        f"({'AVX-512' if lanes == 8 else 'AVX2' if lanes == 4 else 'SSE2'}) x 2 pipes, no FMA"
    )
    return flops, how


def bandwidth(size: int = 256 * 2**20, repeats: int = 5) -> float:
    """Memory bandwidth (bytes/s): the best of ``repeats`` sums of a ``size``-byte float64
    array, split over as many threads as there are cores (numpy releases the GIL in its
    reductions), each byte read once. The kernels read far more than they write, so this is
    their bound; a copy would count writes too."""
    cores = os.cpu_count() or 1
    data = np.ones(size // 8)
    parts = np.array_split(data, cores)
    best = math.inf
    with ThreadPoolExecutor(cores) as pool:
        for _ in range(repeats):
            start = time.perf_counter()
            list(pool.map(np.sum, parts))
            best = min(best, time.perf_counter() - start)
    return data.nbytes / best


def machine_limits(size: int = 256 * 2**20) -> Limits:
    """The bandwidth measured now (:func:`bandwidth` of a ``size``-byte array) and the peak
    flop rate (:func:`peak_flops`)."""
    bw = bandwidth(size)
    flops, how = peak_flops()
    return Limits(
        bw,
        flops,
        f"bandwidth {bw / 1e9:.1f} GB/s (numpy sum of {size / 2**20:.0f} MiB on "
        f"{os.cpu_count()} threads, best of 5); {how}",
    )


# --------------------------------------------------------------------------------------------
# Rows.


@dataclass
class Row:
    """One kernel: polhode's and the peer's seconds per call (every repeat), the elements a
    call does, the work per element and the target ratio."""

    kernel: str
    key: str  # the key of FLOPS, BYTES and TARGETS
    elements: int
    unit: str
    peer: str
    ours_seconds: list[float]
    peer_seconds: list[float]
    note: str = ""
    per: int = 1  # BYTES are per this many elements (a body's steps in the batch rows)

    @property
    def ours(self) -> float:
        """polhode's median seconds per element."""
        return _median(self.ours_seconds) / self.elements

    @property
    def theirs(self) -> float:
        """The peer's median seconds per element."""
        return _median(self.peer_seconds) / self.elements

    @property
    def ratio(self) -> float:
        """The peer's time over polhode's: how many times faster polhode is."""
        return _median(self.peer_seconds) / _median(self.ours_seconds)

    @property
    def target(self) -> float:
        return TARGETS[self.key]

    @property
    def met(self) -> bool:
        return self.ratio >= self.target

    @property
    def flops(self) -> float | None:
        return FLOPS[self.key]

    @property
    def bytes(self) -> float | None:
        work = BYTES[self.key]
        return None if work is None else work / self.per

    def limit(self, limits: Limits) -> float | None:
        """The roofline's time per element: the larger of the flops at the peak rate and the
        bytes at the bandwidth; None without a flop count."""
        if self.flops is None or self.bytes is None:
            return None
        return max(self.flops / limits.peak_flops, self.bytes / limits.bandwidth)

    def fraction(self, limits: Limits) -> float | None:
        """The fraction of the machine's limit polhode reaches (1: at the limit)."""
        limit = self.limit(limits)
        return None if limit is None else limit / self.ours


def _time(seconds: float) -> str:
    if seconds >= 1.0:
        return f"{seconds:.3g} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.3g} ms"
    if seconds >= 1e-6:
        return f"{seconds * 1e6:.3g} us"
    return f"{seconds * 1e9:.3g} ns"


@dataclass
class Kernels:
    """Every row measured in one run, the machine's limits and what was left out."""

    rows: list[Row]
    limits: Limits
    repeats: int
    skipped: list[str] = field(default_factory=list)

    def table(self) -> str:
        """A markdown table: the kernel, polhode's and the peer's median time per element,
        their ratio against the target, the work per element and the fraction of the limit."""
        lines = [
            "| kernel | polhode per element | peer | peer per element | ratio | target | met? "
            "| flops/elem | bytes/elem | fraction of the limit |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        ]
        for row in self.rows:
            fraction = row.fraction(self.limits)
            lines.append(
                f"| {row.kernel} | {_time(row.ours)} | {row.peer} | {_time(row.theirs)} | "
                f"{row.ratio:.3g}x | {row.target:.3g}x | {'yes' if row.met else '**no**'} | "
                f"{'-' if row.flops is None else f'{row.flops:.0f}'} | "
                f"{'-' if row.bytes is None else f'{row.bytes:.3g}'} | "
                f"{'-' if fraction is None else f'{fraction:.2g}'} |"
            )
        lines += ["", f"Median of {self.repeats} interleaved repeats; {self.limits.how}."]
        notes = [f"- {row.kernel}: {row.note}" for row in self.rows if row.note]
        if notes:
            lines += [""] + notes
        if self.skipped:
            lines += ["", f"Left out: {', '.join(self.skipped)}."]
        return "\n".join(lines)


def _from_versus(kernel: str, key: str, elements: int, unit: str, v: mass.Versus) -> Row:
    return Row(kernel, key, elements, unit, v.peer, v.ours_seconds, v.peer_seconds, v.note)


def eigensolve(n: int = 1_000_000, repeats: int = 5) -> list[Row]:
    """The batch principal-axes solve of N random symmetric tensors and of N rotated
    diag(1, 1, 2), against ``numpy.linalg.eigh`` (:func:`polhode.bench.mass.eigensolve`)."""
    random, degenerate = mass.eigensolve(n, repeats)
    return [
        _from_versus(f"batch eigensolve, {n:.0e} random", "eigensolve", n, "tensor", random),
        _from_versus(
            f"batch eigensolve, {n:.0e} degenerate",
            "eigensolve_degenerate",
            n,
            "tensor",
            degenerate,
        ),
    ]


def mesh(subdivisions: int = 7, repeats: int = 5) -> Row | None:
    """``Body.mesh`` of an icosphere of 20 x 4^S faces (327,680 for S = 7) against trimesh
    (:func:`polhode.bench.mass.mesh`); None without trimesh."""
    v = mass.mesh(subdivisions, repeats)
    if v is None:
        return None
    faces = 20 * 4**subdivisions
    return _from_versus(f"triangle mesh, {faces:,} faces", "mesh", faces, "face", v)


def point_masses(n: int = 10_000_000, repeats: int = 5) -> Row:
    """``Body.point_masses(m, r).inertia`` of N points against the numpy reference
    (:func:`polhode.bench.mass.point_masses`)."""
    v = mass.point_masses(n, repeats)
    return _from_versus(f"point masses, {n:.0e}", "point_masses", n, "point", v)


#: The body of :func:`exact`: three distinct moments, a motion about the largest axis.
EXACT_BODY = ((1.0, 2.0, 3.0), (0.3, 0.5, 0.8))


def elliptic_parameter(moments: Sequence[float], omega0: Sequence[float]) -> tuple[float, float]:
    """The parameter m of sn, cn, dn in the torque-free motion of three distinct moments, and
    the rate lambda of their argument (u = lambda t + u0), as a user of ``ellipj`` would form
    them: with ascending moments, Delta_j = |L|^2 - 2 T I_j, and the ends swapped when the
    motion circulates about the smallest axis (Landau and Lifshitz, section 37)."""
    i = np.sort(np.asarray(moments, dtype=float))
    w = np.asarray(omega0, dtype=float)[np.argsort(np.asarray(moments, dtype=float))]
    mw = i * w
    delta = float(mw @ mw) - float(mw @ w) * i
    if delta[1] < 0.0:
        i, delta = i[::-1], delta[::-1]
    i1, i2, i3 = i
    rate = math.sqrt(delta[0] * (i3 - i2) / (i1 * i2 * i3))
    return float((i2 - i1) * -delta[2] / ((i3 - i2) * delta[0])), rate


def exact(times: int = 200_000, repeats: int = 5) -> list[Row]:
    """The closed form at ``times`` output times of one body (:data:`EXACT_BODY`), the full
    state and omega alone, against ``scipy.special.ellipj`` on as many arguments (sn, cn and
    dn alone, at the parameter of that motion)."""
    from scipy.special import ellipj

    moments, omega0 = EXACT_BODY
    t = np.linspace(0.0, 200.0, times)
    m, rate = elliptic_parameter(moments, omega0)
    u = rate * t + 0.1
    seconds, _ = _interleaved(
        {
            "full": lambda: simulate(moments, omega0, t, method="exact"),
            "omega": lambda: simulate(moments, omega0, t, method="exact", orientation=False),
            "ellipj": lambda: ellipj(u, m),
        },
        repeats,
    )
    peer = "scipy.special.ellipj"
    note = f"m = {m:.3g}, {times:.0e} output times of one body"
    return [
        Row(
            "exact solution, full state per output time",
            "exact_full",
            times,
            "time",
            peer,
            seconds["full"],
            seconds["ellipj"],
            note,
        ),
        Row(
            "exact solution, omega only per output time",
            "exact_omega",
            times,
            "time",
            peer,
            seconds["omega"],
            seconds["ellipj"],
        ),
    ]


def batch(n: int = 100_000, repeats: int = 5, steps: int = 200) -> list[Row]:
    """N random bodies (:func:`polhode.bench.motion.random_bodies`), ``steps`` steps of 0.01
    with orientation on all cores, by rk4, the splitting (order 4) and the midpoint rule,
    against the numpy structure-of-arrays rk4 (:func:`polhode.bench.adapters.numpy_rk4`, one
    core) on the same bodies and steps. The element is a body-step; 200 steps is the
    workload of :func:`polhode.bench.motion.throughput` at 1e5 bodies, where the
    figures before the lanes were measured."""
    from polhode.bench.motion import random_bodies

    dt = 0.01
    moments, omega0 = random_bodies(n, np.random.default_rng(0))
    span = np.array([0.0, steps * dt])

    def ours(method: str) -> Callable[[], Any]:
        return lambda: simulate(moments, omega0, span, method=method, dt=dt)

    seconds, results = _interleaved(
        {
            "numpy": lambda: adapters.numpy_rk4(moments, omega0, steps, dt),
            "rk4": ours("rk4"),
            "splitting": ours("splitting"),
            "midpoint": ours("midpoint"),
        },
        repeats,
    )
    # The same integrator on the same bodies: their omegas agree to round-off.
    agree = float(np.max(np.abs(results["rk4"].omega[:, -1] - results["numpy"][0])))
    peer = "numpy SoA rk4 (1 core)"
    work = n * steps
    return [
        Row(
            f"batch rk4 with orientation, {n:.0e} bodies",
            "rk4",
            work,
            "body-step",
            peer,
            seconds["rk4"],
            seconds["numpy"],
            f"{work / _median(seconds['rk4']):.3g} body-steps/s; omega agrees with numpy's "
            f"to {agree:.1e}",
            steps,
        ),
        Row(
            f"batch splitting (order 4), {n:.0e} bodies",
            "splitting",
            work,
            "body-step",
            peer,
            seconds["splitting"],
            seconds["numpy"],
            f"{work / _median(seconds['splitting']):.3g} body-steps/s",
            steps,
        ),
        Row(
            f"batch midpoint, {n:.0e} bodies",
            "midpoint",
            work,
            "body-step",
            peer,
            seconds["midpoint"],
            seconds["numpy"],
            f"{work / _median(seconds['midpoint']):.3g} body-steps/s",
            steps,
        ),
    ]


def small_calls(calls: int = 200, repeats: int = 5) -> list[Row]:
    """One body: ``ph.simulate`` at 2 output times and ``ph.analyze``, against scipy's
    ``Rotation.from_rotvec(...).as_matrix()`` of one rotation vector; each repeat times
    ``calls`` calls of each in a loop (after one untimed call), the three in turn. The element
    is one call."""
    from scipy.spatial.transform import Rotation

    moments = np.array([1.0, 2.0, 3.0])
    omega0 = np.array([0.01, 1.0, 0.01])
    t = np.array([0.0, 100.0])
    rotvec = np.array([0.1, 0.2, 0.3])

    def loop(fn: Callable[[], Any]) -> Callable[[], Any]:
        def run() -> Any:
            for _ in range(calls):
                fn()

        fn()
        return run

    seconds, _ = _interleaved(
        {
            "rotvec": loop(lambda: Rotation.from_rotvec(rotvec).as_matrix()),
            "simulate": loop(lambda: simulate(moments, omega0, t)),
            "analyze": loop(lambda: analyze(moments, omega0)),
        },
        repeats,
    )
    peer = "Rotation.from_rotvec().as_matrix()"
    return [
        Row(
            "small call: simulate, 1 body, 2 times",
            "simulate",
            calls,
            "call",
            peer,
            seconds["simulate"],
            seconds["rotvec"],
        ),
        Row("small call: analyze", "analyze", calls, "call", peer, seconds["analyze"],
            seconds["rotvec"]),
    ]


#: Sizes of :func:`run`: (full, quick).
SIZES = {
    "eigensolve": (1_000_000, 100_000),
    "mesh": (7, 5),
    "point_masses": (10_000_000, 1_000_000),
    "exact": (200_000, 20_000),
    "batch": (100_000, 10_000),
}


#: Calls per repeat of :func:`small_calls` in :func:`run`.
SMALL_CALLS = 200


#: The groups of rows :func:`run` can be limited to (``only``), in the table's order.
GROUPS = ("eigensolve", "mesh", "point_masses", "exact", "batch", "small_calls")


def run(
    quick: bool = False,
    repeats: int = 5,
    limits_size: int | None = None,
    only: Sequence[str] | None = None,
) -> Kernels:
    """Every row, at the target sizes or (``quick``) at a tenth of them (meshes of 20,480
    faces), each a median of ``repeats`` (at least 5) interleaved repeats; the limits measured
    first (the bandwidth on ``limits_size`` bytes: 256 MiB, 64 MiB when ``quick``). ``only``:
    the groups of :data:`GROUPS` to run (all when None)."""
    from polhode.errors import ArgumentError

    chosen = GROUPS if only is None else tuple(only)
    unknown = sorted(set(chosen) - set(GROUPS))
    if unknown or not chosen:
        raise ArgumentError(
            f"only: unknown group(s) {unknown or chosen!r}; choose from {', '.join(GROUPS)}",
            argument="only",
        )
    repeats = max(5, repeats)
    pick = 1 if quick else 0
    if limits_size is None:
        limits_size = 64 * 2**20 if quick else 256 * 2**20
    limits = machine_limits(limits_size)
    rows: list[Row] = []
    skipped: list[str] = []
    if "eigensolve" in chosen:
        rows += eigensolve(SIZES["eigensolve"][pick], repeats)
    if "mesh" in chosen:
        m = mesh(SIZES["mesh"][pick], repeats)
        if m is None:
            skipped.append("the mesh row (trimesh is not installed)")
        else:
            rows.append(m)
    if "point_masses" in chosen:
        rows.append(point_masses(SIZES["point_masses"][pick], repeats))
    if "exact" in chosen:
        rows += exact(SIZES["exact"][pick], repeats)
    if "batch" in chosen:
        rows += batch(SIZES["batch"][pick], repeats)
    if "small_calls" in chosen:
        rows += small_calls(SMALL_CALLS, repeats)
    return Kernels(rows, limits, repeats, skipped)
