"""The fields that :class:`polhode.Trajectory` and :class:`polhode.dask.DaskTrajectory` share:
the output times ``t``, then every quantity of the core's table (:mod:`polhode._quantities`), in
its order, as arrays of one type (numpy arrays, dask arrays).

Made here at import from the table; ``_fields.pyi``, generated from the same table, declares
them to type checkers (``Fields[NDArray[np.float64]]``: ``traj.omega`` is an ndarray,
``traj.quaternion`` an ndarray or None).
"""

from __future__ import annotations

import dataclasses
from typing import Generic, TypeVar

from polhode._quantities import QUANTITIES

__all__ = ["Fields"]

_A = TypeVar("_A")

Fields = dataclasses.make_dataclass(
    "Fields",
    [("t", "NDArray[np.float64]")]
    + [(q.name, "_A | None" if q.requires else "_A") for q in QUANTITIES],
    bases=(Generic[_A],),
    namespace={
        "__doc__": "The output times ``t`` and the core's quantities (see polhode._fields).",
    },
    frozen=True,
    eq=False,
    repr=False,
)
Fields.__module__ = __name__  # make_dataclass's `module=` is Python 3.12's
