"""The orientation of a trajectory as Euler angles, continuous in time (see
:meth:`polhode.Trajectory.euler_angles`)."""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import NDArray

from polhode import _chunks
from polhode._chunks import accumulate, spans, unwrap
from polhode.errors import ArgumentError

__all__ = ["euler_angles"]


def euler_angles(quaternion: NDArray[np.float64], seq: str) -> NDArray[np.float64]:
    """Euler angles (M, 3) of the orientations (M, 4), continuous in time (see
    :meth:`polhode.Trajectory.euler_angles`).

    In chunks of :data:`polhode._chunks.CHUNK` output times, the sequential steps (unwrapping,
    the running sums) carried from chunk to chunk, so that Ctrl-C stops a long series within
    a chunk's work (scipy's and numpy's calls hold the interpreter) with the bits of the whole
    series done at once."""
    from scipy.spatial.transform import Rotation

    m = len(quaternion)
    angles = np.empty((m, 3))
    # scipy's conversion takes about 0.1 us per row: a quarter chunk at a time (~30 ms).
    for span in spans(m, max(1, _chunks.CHUNK // 4)):
        try:
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", message="Gimbal lock", category=UserWarning)
                angles[span] = Rotation.from_quat(quaternion[span]).as_euler(seq)
        except ValueError as error:
            raise ArgumentError(
                f"Expected `seq` to be three axes as in scipy's as_euler (e.g. 'ZXZ', 'ZYX', "
                f"'xyz'), got {seq!r}: {error}",
                argument="seq",
            ) from None
    if m == 0:
        return angles
    # The two ends of the middle angle's range, and at each the combination first + sign *
    # third that the rotation depends on there (the other one is free): found by moving the
    # split both ways at a generic point of the end.
    proper = seq[0].lower() == seq[2].lower()
    ends = np.array([0.0, np.pi]) if proper else np.array([-np.pi / 2, np.pi / 2])
    probe = np.array([[0.3, end, 0.5] for end in ends])
    moved = probe + [0.2, 0.0, -0.2]
    keeps_sum = (
        Rotation.from_euler(seq, moved) * Rotation.from_euler(seq, probe).inv()
    ).magnitude()
    signs = np.where(keeps_sum < 1e-12, 1.0, -1.0)
    nearest = np.empty(m, dtype=np.intp)
    locked = np.empty(m, dtype=bool)
    for span in spans(m):
        a = angles[span]
        nearest[span] = np.argmin(np.abs(a[:, 1, None] - ends), axis=1)
        locked[span] = (a[:, 2] == 0.0) & (np.abs(a[:, 1] - ends[nearest[span]]) <= 1e-6)
    sign = np.empty(m)
    for span in spans(m):
        sign[span] = signs[nearest[span]]
    # At a lock scipy sets the third angle to zero and puts the combination into the first:
    # the third keeps its previous value instead (0 before any), the first takes the rest.
    if locked.any():
        third = unwrap(angles[:, 2])
        index = np.empty(m, dtype=np.intp)
        for span in spans(m):
            index[span] = np.where(~locked[span], np.arange(span.start, span.stop), -1)
        index = accumulate(np.maximum, index)
        for span in spans(m):
            here, at = locked[span], index[span]
            keep = np.where(at >= 0, third[np.maximum(at, 0)], 0.0)[here]
            a = angles[span]
            a[here, 0] -= sign[span][here] * keep
            a[here, 2] = keep
    angles = unwrap(angles)
    # Near a lock (the middle angle within pi/8 of an end) the first and third angles swing by
    # about pi and unwrapping them apart can leave a whole turn in the combination that sets
    # the rotation there, which moves by less than pi between two times: whole turns of the
    # first angle put it back.
    near = np.empty(m, dtype=bool)
    for span in spans(m):
        near[span] = np.abs(angles[span, 1] - ends[nearest[span]]) <= np.pi / 8
    turns = np.empty(m)
    for span in spans(m):
        start, stop = span.start, span.stop
        combination = angles[span, 0] + sign[span] * angles[span, 2]
        # previous[k] = angles[k - 1, 0] + sign[k] angles[k - 1, 2], 0 at k = 0.
        low = max(start - 1, 0)
        previous = angles[low : stop - 1, 0] + sign[max(start, 1) : stop] * angles[
            low : stop - 1, 2
        ]
        near_before = near[low : stop - 1]
        if start == 0:
            previous = np.concatenate([[0.0], previous])
            near_before = np.concatenate([[False], near_before])
        part = np.round((combination - previous) / (2 * np.pi))
        if start == 0:
            part[0] = 0.0
        part[~(near[span] | near_before)] = 0.0
        turns[span] = part
    total = accumulate(np.add, turns)
    for span in spans(m):
        angles[span, 0] -= 2 * np.pi * total[span]
    return angles
