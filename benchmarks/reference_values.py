"""Prints polhode.bench.REFERENCE: the state at t_end of each work-precision case, from the
identity orientation, by the independent 30-digit reference of tests/reference_motion.py.

    python -m benchmarks.reference_values

tests/test_bench.py checks that the committed constants agree with it.
"""

from __future__ import annotations

import os
import sys

import numpy as np

from polhode import bench

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from reference_motion import reference_motion  # noqa: E402


def main() -> None:
    print("REFERENCE = {")
    for name, case in bench.CASES.items():
        omega, quat = reference_motion(case.moments, case.omega0, [0, 0, 0, 1], [case.t_end])
        w = np.asarray(omega, dtype=float)[-1].tolist()
        q = np.asarray(quat, dtype=float)[-1].tolist()
        print(f'    "{name}": (\n        {tuple(w)!r},\n        {tuple(q)!r},\n    ),')
    print("}")


if __name__ == "__main__":
    main()
