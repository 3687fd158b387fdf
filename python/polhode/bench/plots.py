"""The benchmark figures (matplotlib, the ``plot`` or ``bench`` extra), written to PNG files.

matplotlib is imported inside the functions, which select its headless Agg backend.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from polhode.bench.motion import Drift, Throughput, WorkPrecision

_STYLE = {
    "polhode exact": ("k", "*"),
    "polhode dop853": ("C0", "o"),
    "polhode rk4": ("C1", "o"),
    "polhode splitting 2": ("C2", "v"),
    "polhode splitting 4": ("C2", "o"),
    "polhode splitting 6": ("C2", "^"),
    "polhode midpoint": ("C4", "o"),
    "scipy RK45": ("C3", "s"),
    "scipy DOP853": ("C3", "D"),
    "scipy LSODA": ("C3", "x"),
    "MuJoCo Euler": ("C5", "s"),
    "MuJoCo RK4": ("C5", "D"),
}


def _figure(ncols: int = 1, width: float = 6.4) -> tuple[Any, Any]:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, ncols, figsize=(width * ncols, 4.8), squeeze=False)
    return fig, axes[0]


def _save(fig: Any, path: str) -> str:
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_work_precision(result: WorkPrecision, path: str, floor: float = 1e-17) -> str:
    """Two log-log panels (error of omega, error of the orientation) against the median wall time
    of the whole call, one line per series; polhode solid, peers dashed."""
    fig, axes = _figure(2)
    for ax, which, label in zip(
        axes,
        ("omega", "orientation"),
        ("relative error of omega at t_end", "orientation error at t_end (rad)"),
        strict=True,
    ):
        for s in result.series:
            if not s.points:
                continue
            x = np.array([p.median for p in s.points])
            y = np.maximum([p.error(which) for p in s.points], floor)
            color, marker = _STYLE.get(s.name, (None, "o"))
            ax.loglog(
                x,
                y,
                marker=marker,
                color=color,
                linestyle="--" if s.peer else "-",
                label=s.name,
                markersize=5,
            )
        ax.set_xlabel("wall time of the call (s)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title(result.case.label, fontsize=9, loc="left")
    axes[1].legend(fontsize=7, loc="upper right", ncol=2)
    return _save(fig, path)


def plot_drift(result: Drift, path: str, floor: float = 1e-17) -> str:
    """Three log-log panels: relative error of T, of |L| and of L in space against time."""
    fig, axes = _figure(3, width=4.6)
    for ax, key, label in zip(
        axes, ("T", "|L|", "L"), ("energy T", "|L|", "L in space"), strict=True
    ):
        for name, errors in result.errors.items():
            ax.loglog(result.t, np.maximum(errors[key], floor), label=name, linewidth=1)
        ax.set_xlabel("t")
        ax.set_title(f"relative error of {label}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    return _save(fig, path)


def plot_throughput(result: Throughput, path: str) -> str:
    """Body-steps (or exact evaluations) per second against N, log-log, with and without
    orientation."""
    fig, axes = _figure(1)
    ax = axes[0]
    methods = list(dict.fromkeys(row[0] for row in result.rows))
    for k, method in enumerate(methods):
        for orientation in (True, False):
            rate = result.rate(method, orientation)
            if not rate:
                continue
            ax.loglog(
                list(rate),
                list(rate.values()),
                color=f"C{k}",
                linestyle="-" if orientation else ":",
                marker="o",
                label=f"{method} ({'with' if orientation else 'no'} orientation)",
            )
    ax.set_xlabel("N bodies")
    ax.set_ylabel("body-steps per second (exact: evaluations per second)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return _save(fig, path)
