"""The exact solution per output time against scipy's ``ellipj`` at as many arguments.

    python -m benchmarks.bench_exact [--times N] [--repeats R] [--accuracy]

Timed, interleaved, R rounds (default 7), N output times (default 2e5) on one body:

- ``ph.simulate(body, omega0, t, method="exact")``: the full state (omega and the orientation
  quaternion) at each time;
- the same with ``orientation=False``: omega alone;
- ``scipy.special.ellipj(u, m)`` on the N phases ``u = lambda t + u0`` of that motion (the
  parameter ``m`` of its polhode): sn, cn, dn alone, the peer that sets the targets.

Three bodies: a generic one (``m`` about 0.6), one near the separatrix (``1 - m`` about 1e-3,
where the nome ``q`` is large) and one within 1e-12 of it (``1 - m`` about 1e-12). The table
gives the median ns per output time and the ratios to ``ellipj`` measured in the same run.

``--accuracy`` adds, for the same bodies at 64 times up to 1e4 periods, the largest error of
omega (normwise relative) and of the quaternion (up to sign), in units of eps, against the
50-digit closed form of ``tests/reference_motion.py`` (mpmath; what ``tests/test_exact_extremes.py``
and ``tests/test_motion_hard_cases.py`` assert, to 10 eps).
"""

from __future__ import annotations

import argparse
import functools
import os
import statistics
import sys

import numpy as np

import polhode as ph
from polhode.bench._timing import interleaved

# (name, moments, omega0)
BODIES = (
    ("generic (m ~ 0.16)", (1.0, 2.0, 3.0), (0.3, 0.5, 0.8)),
    ("near separatrix (1 - m ~ 1e-3)", (2.0, 3.0, 6.0), (1.5, 0.2, 0.5 * (1 + 1e-3))),
    ("within 1e-12 of it", (2.0, 3.0, 6.0), (1.5, 0.2, 0.5 * (1 + 1e-12))),
)


def _parameter(moments: tuple[float, ...], omega0: tuple[float, ...]) -> tuple[float, float]:
    """``(m, lambda)`` of the motion (the canonical frame of the module doc of the exact
    solution, in plain doubles: what a user of ``ellipj`` would form)."""
    i = np.asarray(moments, float)
    w = np.asarray(omega0, float)
    order = np.argsort(i)
    i, w = i[order], w[order]
    m = i * w
    g2 = float(m @ m)
    t2 = float(m @ w)
    d = g2 - t2 * i  # Delta_j
    if d[1] < 0:  # circulates about the smallest: swap the ends
        i, d = i[::-1], d[::-1]
    i1, i2, i3 = i
    lam = np.sqrt(d[0] * (i3 - i2) / (i1 * i2 * i3))
    param = (i2 - i1) * (-d[2]) / ((i3 - i2) * d[0])
    return float(param), float(lam)


def run(n: int, repeats: int) -> str:
    from scipy.special import ellipj

    t = np.linspace(0.0, 200.0, n)
    rows = []
    for name, moments, omega0 in BODIES:
        m, lam = _parameter(moments, omega0)
        u = lam * t + 0.1
        calls = {
            "full": functools.partial(ph.simulate, moments, omega0, t, method="exact"),
            "omega": functools.partial(
                ph.simulate, moments, omega0, t, method="exact", orientation=False
            ),
            "ellipj": functools.partial(ellipj, u, m),
        }
        times, _ = interleaved(calls, repeats)
        med = {k: statistics.median(v) / n * 1e9 for k, v in times.items()}
        rows.append(
            f"| {name} | {1 - m:.2g} | {med['full']:.0f} | {med['omega']:.0f} | "
            f"{med['ellipj']:.0f} | {med['full'] / med['ellipj']:.2f} | "
            f"{med['omega'] / med['ellipj']:.2f} |"
        )
    head = (
        f"{n} output times, median of {repeats} interleaved repeats, ns per output time\n\n"
        "| body | 1 - m | full state | omega only | ellipj | full / ellipj | omega / ellipj |\n"
        "| --- | --- | --- | --- | --- | --- | --- |"
    )
    return "\n".join([head, *rows])


def accuracy() -> str:
    """Largest errors of omega and the quaternion in eps against 50-digit mpmath."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
    from reference_motion import exact_closed_form

    eps = float(np.finfo(float).eps)
    q0 = np.array([0.1, -0.2, 0.3, 0.9])
    q0 = tuple(float(x) for x in q0 / np.linalg.norm(q0))
    rows = ["| body | omega error / eps | quaternion error / eps |", "| --- | --- | --- |"]
    for name, moments, omega0 in BODIES:
        period = ph.analyze(moments, omega0).period
        assert period is not None
        times = np.concatenate([[0.0], np.geomspace(1e-3, 1e4, 63) * period])
        sol = ph.simulate(moments, omega0, times, orientation0=q0, method="exact")
        w_ref, q_ref = exact_closed_form(moments, omega0, q0, times, dps=50)
        assert sol.quaternion is not None
        ew = np.linalg.norm(sol.omega - w_ref, axis=1) / np.linalg.norm(w_ref, axis=1)
        eq = np.minimum(
            np.linalg.norm(sol.quaternion - q_ref, axis=1),
            np.linalg.norm(sol.quaternion + q_ref, axis=1),
        )
        rows.append(f"| {name} | {ew.max() / eps:.2f} | {eq.max() / eps:.2f} |")
    return "\n".join(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--times", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--accuracy", action="store_true")
    args = parser.parse_args()
    print(run(args.times, args.repeats))
    if args.accuracy:
        print()
        print(accuracy())


if __name__ == "__main__":
    main()
