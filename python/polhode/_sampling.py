"""The output times of a run to an end time: enough of them to draw its motion.

``polhode.simulate(body, omega0, t_end)`` (and ``polhode.dask.simulate``) samples the run at
:data:`PER_TURN` output times per turn at the fastest rate of its motion, and at least
:data:`FEWEST` over it. The fastest rate is the core's (``polhode._core.fastest_rate``), from each
body's state at t0, in its principal axes: the largest of the frequency of omega in the body,
``2 pi / P``; the mean precession about L in space; the body's spin, ``|omega|`` at its largest
along the torque-free motion; with rotors, ``|L| / I_min`` of the whole (a fast wheel makes the
body nutate at about ``h / I``); with a torque, the rate it turns L at t0, ``|tau| / |L|`` (from
rest, the spin it adds over the run). Over a batch, the fastest body's: one grid for all.

How the times are placed depends on the method:

- the exact solution: evenly spaced (each output time costs the same, wherever it is);
- a fixed-step method (``splitting``, ``midpoint``, ``rk4``): every ``stride``-th of the steps
  the run takes to the end time (``ceil((t_end - t0) / dt)`` equal steps, the core's count), the
  largest stride that keeps :data:`PER_TURN` per turn: the outputs are the run's own states and
  its steps those of the run to the end time alone (a ``dt`` coarser than that gives every step).
  Far from t0, where an ulp of t exceeds the slack the core allows the count of steps between
  two output times (1e-12 of the interval), an interval of exactly ``stride`` steps of ``dt``
  would be split into one step more: there the inner times are moved earlier by a few ulps of
  t per interval (the steps shorter by as much), which leaves at most one step more in all
  (``stats["sampling"]["extra_steps"]``, which ``max_steps`` does not count);
- ``dop853``: evenly spaced (its dense output reaches them between its steps), and for one body
  the end of every accepted step as well, in time order (unless capped, below): where the
  motion is fast the steps are dense, and the grid resolves the rest.

The times are bounded: a body gets at most :data:`MOST` output times, and a batch of N bodies at
most :data:`MOST_OUTPUTS` / N each (but :data:`FEWEST` at least), so that a long run or a fast
one does not fill the memory by default (a body's outputs at :data:`MOST` times take 13.6 MB).
A run that reaches the bound has fewer than :data:`PER_TURN` per turn; its summary says so
(``capped``) and how many it has per turn: such a run, like one whose rates change later than
t0 (a torque that grows, a damper that moves the spin to another axis, which are not foreseen),
asks for the output times it needs (``t`` as an array, or ``polhode.dask`` for many).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from polhode import _display

__all__ = ["FEWEST", "MOST", "MOST_OUTPUTS", "PER_TURN", "describe", "resolving_times"]

#: Output times per turn at the fastest rate of the motion (a polyline through 48 points per
#: turn of a circle strays from it by 0.2% of its radius).
PER_TURN = 48

#: The fewest output times of a run to an end time (as many as one turn at the fastest rate).
FEWEST = PER_TURN + 1

_EPS = float(np.finfo(np.float64).eps)

#: The most output times of one body's run to an end time.
MOST = 100_001

#: The most outputs (bodies x output times) of a batch's run to an end time.
MOST_OUTPUTS = 1_000_000


def resolving_times(
    t0: float, t_end: float, rate: dict[str, Any], bodies: int | None
) -> tuple[NDArray[np.float64], dict[str, Any]]:
    """The output times of a run from ``t0`` to ``t_end`` whose fastest rate is ``rate`` (the
    dict of ``polhode._core.fastest_rate``) for one body (``bodies`` None) or a batch of
    ``bodies``, and how they were chosen (``stats["sampling"]``): ``per_turn`` (output
    intervals per turn at the fastest rate: :data:`PER_TURN`, fewer where ``capped``),
    ``rate`` (rad/s), ``pace`` (what sets it), ``body`` (in a batch, the fastest one),
    ``stride`` (a fixed-step method's steps per output), ``every_step`` (dop853's accepted
    steps reported too: one body), ``capped`` (the times bounded by :data:`MOST` or
    :data:`MOST_OUTPUTS`) and ``extra_steps`` (the steps a fixed-step run takes to these
    times beyond those of the run to ``t_end`` alone, which ``max_steps`` does not count)."""
    span = t_end - t0
    sampling: dict[str, Any] = {
        "per_turn": float(PER_TURN),
        "rate": float(rate["rate"]),
        "pace": rate["pace"],
        "body": None if bodies is None else int(rate["body"]),
        "stride": None,
        "every_step": rate["method"] == "dop853" and bodies is None,
        "capped": False,
        "extra_steps": 0,
    }
    if span == 0.0:
        return np.array([t0]), sampling
    # Intervals between output times: PER_TURN per turn, at least FEWEST - 1 over the run, at
    # most MOST - 1 (a batch: MOST_OUTPUTS over its bodies).
    turns = span * sampling["rate"] / (2.0 * math.pi)
    most = MOST if bodies is None else max(FEWEST, min(MOST, MOST_OUTPUTS // max(bodies, 1)))
    wanted = PER_TURN * turns
    intervals = max(FEWEST - 1, math.ceil(wanted) if wanted < most else most - 1)
    if intervals < wanted:
        # dop853's accepted steps too would be unbounded: the grid alone.
        sampling.update(capped=True, per_turn=intervals / turns, every_step=False)
    steps = rate["steps"]
    if steps is None:
        times = np.linspace(t0, t_end, intervals + 1)
    else:
        steps = max(int(steps), 1)
        # Every stride-th step: at least `intervals` of them (PER_TURN per turn), or at most
        # (capped).
        stride = -(-steps // intervals) if sampling["capped"] else max(1, steps // intervals)
        sampling["stride"] = stride
        taken = np.arange(0, steps, stride, dtype=np.float64)
        times = np.empty(taken.size + 1)
        # The run's own steps k h, h = span / steps: t0 + span (k / steps), t_end itself last.
        np.multiply(taken / steps, span, out=times[:-1])
        times[:-1] += t0
        times[-1] = t_end
        times[0] = t0
        extra = _extra_steps(times, steps, rate["dt"])
        if extra:
            # Far from t0 the round-off of the times splits intervals of exactly `stride` steps
            # of dt into one more: the inner times a little earlier instead, each interval
            # shorter by more than that round-off, the last one longer by their sum (less than
            # a step: at most one step more in all).
            h = span / steps
            shrink = 8.0 * _EPS * (max(abs(t0), abs(t_end)) + stride * h) / (stride * h)
            np.multiply(taken / steps, span * (1.0 - shrink), out=times[:-1])
            times[:-1] += t0
            times[0] = t0
            extra = _extra_steps(times, steps, rate["dt"])
        sampling["extra_steps"] = extra
    times[0] = t0
    return times, sampling


def _substeps(before: Any, after: Any, dt: float) -> Any:
    """The steps a fixed-step run takes between output times (the core's count, substeps in
    dynamics/loops.rs: equal steps no longer than dt but for the round-off of the times)."""
    interval = after - before
    slack = np.minimum(4.0 * _EPS * (1.0 + np.maximum(abs(after), abs(before)) / interval), 1e-12)
    return np.maximum(np.ceil((interval / dt) * (1.0 - slack)), 1.0)


def _extra_steps(times: NDArray[np.float64], steps: int, dt: float) -> int:
    """The steps the run takes to ``times`` beyond the ``steps`` of the run to the end time
    alone: none but where an interval of ``stride`` steps of exactly dt lies so far from t0
    that the round-off of its ends (an ulp of t) exceeds the slack of the core's count (1e-12
    of the interval), which then splits it into one step more."""
    return max(0, int(np.sum(_substeps(times[:-1], times[1:], dt))) - steps)


def describe(sampling: dict[str, Any]) -> str:
    """How the times were chosen, in a few words (the trajectory's summary)."""
    if sampling["rate"] == 0.0:
        text = f"{FEWEST} over the run, at rest"
    else:
        pace = {
            "spin": "the spin",
            "period": "omega's period in the body",
            "precession": "the precession",
            "torque": "the torque",
            "rotors": "the rotors",
        }[sampling["pace"]]
        if sampling["body"] is not None:
            pace += f" of the batch's body {sampling['body']}"
        rate = _display.number(sampling["rate"])
        per_turn = _display.number(float(f"{sampling['per_turn']:.3g}"))
        text = f"{per_turn} per turn of {pace}, {rate} rad/s"
        if sampling["capped"]:
            text = f"capped: {text}"
    if sampling["stride"] is not None:
        text += f"; every {sampling['stride']} steps" if sampling["stride"] > 1 else "; every step"
    if sampling["every_step"]:
        text += "; and every dop853 step"
    return text
