"""Medians, spreads and interleaved timing, shared by the suites."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Sequence
from typing import Any


def median(seconds: Sequence[float]) -> float:
    return float(statistics.median(seconds))


def spread(seconds: Sequence[float]) -> str:
    """min-max in milliseconds."""
    return f"{min(seconds) * 1e3:.3g}-{max(seconds) * 1e3:.3g}"


def interleaved(
    runs: dict[str, Callable[[], Any]], repeats: int
) -> tuple[dict[str, list[float]], dict[str, Any]]:
    """Times each call ``repeats`` times, all calls in turn in every repeat; returns the times
    and the last result of each."""
    times: dict[str, list[float]] = {name: [] for name in runs}
    results: dict[str, Any] = {}
    for _ in range(repeats):
        for name, fn in runs.items():
            start = time.perf_counter()
            results[name] = fn()
            times[name].append(time.perf_counter() - start)
    return times, results
