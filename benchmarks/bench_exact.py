"""The exact solution per output time against scipy's ``ellipj`` at as many arguments.

    python -m benchmarks.bench_exact [--times N] [--repeats R]

Timed, interleaved, R rounds (default 7), N output times (default 2e5) on one body:

- ``ph.simulate(body, omega0, t, method="exact")``: the full state (omega and the attitude
  quaternion) at each time;
- the same with ``orientation=False``: omega alone;
- ``scipy.special.ellipj(u, m)`` on the N phases ``u = lambda t + u0`` of that motion (the
  parameter ``m`` of its polhode): sn, cn, dn alone, the peer that sets the targets.

Three bodies: a generic one (``m`` about 0.6), one near the separatrix (``1 - m`` about 1e-3,
where the nome ``q`` is large) and one within 1e-12 of it (``1 - m`` about 1e-12). The table
gives the median ns per output time and the ratios to ``ellipj`` measured in the same run.
Accuracy is not timed here: ``tests/test_exact_extremes.py`` and
``tests/test_motion_hard_cases.py`` compare the exact solution with 50-digit mpmath.
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

import polhode as ph
from polhode.bench._timing import interleaved

# (name, moments, omega0)
BODIES = (
    ("generic (m ~ 0.6)", (1.0, 2.0, 3.0), (0.3, 0.5, 0.8)),
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
            "full": lambda: ph.simulate(moments, omega0, t, method="exact"),
            "omega": lambda: ph.simulate(moments, omega0, t, method="exact", orientation=False),
            "ellipj": lambda: ellipj(u, m),
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--times", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    print(run(args.times, args.repeats))


if __name__ == "__main__":
    main()
