"""Timing helpers shared by the benchmarks: medians over repeats, peers interleaved."""

from __future__ import annotations

import os
import platform
import statistics
import time
from collections.abc import Callable
from typing import Any


def timed(fn: Callable[[], Any]) -> tuple[float, Any]:
    """Wall time of one call and its result."""
    start = time.perf_counter()
    result = fn()
    return time.perf_counter() - start, result


def interleaved(
    runs: dict[str, Callable[[], Any]], repeats: int
) -> tuple[dict[str, list[float]], dict[str, Any]]:
    """Times each callable `repeats` times, alternating between them so that machine noise
    falls on all alike; returns the times and the last result of each."""
    times: dict[str, list[float]] = {name: [] for name in runs}
    results: dict[str, Any] = {}
    for _ in range(repeats):
        for name, fn in runs.items():
            seconds, results[name] = timed(fn)
            times[name].append(seconds)
    return times, results


def summary(seconds: list[float]) -> str:
    """Median and spread (min to max) of a list of times."""
    med = statistics.median(seconds)
    return f"{med * 1e3:9.2f} ms (min {min(seconds) * 1e3:.2f}, max {max(seconds) * 1e3:.2f})"


def machine() -> str:
    """One line naming the machine and the versions."""
    import numpy as np

    import polhode

    return (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}, polhode {polhode.__version__}"
    )
