"""The core's table of output quantities, read once: what :class:`polhode.Trajectory`,
:class:`polhode.dask.DaskTrajectory`, the memory check of :func:`polhode.simulate`, the command
line's CSV and the docs derive from.

The table is ``polhode._core.QUANTITIES`` (rust/polhode/src/simulation/quantity.rs): one row per
quantity reported at each output time, with its name, its shape at one output time (``"rotors"``
for the number of rotors), SI unit, frame (``"body"``, ``"space"`` or ``"none"``), description,
and what a run needs to report it (``"orientation"``, ``"rotors"``). A quantity added to the core
is a field of every trajectory, a column of the CSV and an entry of the docs with no change here.

Type checkers cannot run the table: ``_fields.pyi``, the typed fields of the trajectories, is
generated from it (``python scripts/fields_stub.py``, with the core built and installed;
``tests/test_quantities.py`` fails while the two differ).
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path

from polhode import _core

__all__ = ["QUANTITIES", "Quantity", "attribute_docs", "numbers_per_time", "stub"]


@dataclass(frozen=True)
class Quantity:
    """One row of the core's table of output quantities."""

    #: The attribute of a trajectory.
    name: str
    #: Its shape at one output time: sizes, and ``"rotors"`` for the number of rotors.
    shape: tuple[int | str, ...]
    #: Its SI unit, ``"1"`` for a dimensionless one.
    unit: str
    #: The axes its components are in: ``"body"``, ``"space"``, or ``"none"``.
    frame: str
    #: What it is, in one line.
    description: str
    #: What a run needs to report it: ``"orientation"``, ``"rotors"``.
    requires: tuple[str, ...]

    def present(self, orientation: bool, rotors: int) -> bool:
        """Whether a run with (or without) the orientation and ``rotors`` rotors reports it."""
        return ("orientation" not in self.requires or orientation) and (
            "rotors" not in self.requires or rotors > 0
        )

    def sizes(self, rotors: int) -> tuple[int, ...]:
        """Its shape at one output time in a run with ``rotors`` rotors."""
        return tuple(rotors if d == "rotors" else int(d) for d in self.shape)

    def width(self, rotors: int) -> int:
        """Its numbers at one output time in a run with ``rotors`` rotors."""
        return math.prod(self.sizes(rotors))


#: Every quantity, in the core's order (that of the trajectories' fields).
QUANTITIES = tuple(
    Quantity(
        name=row["name"],
        shape=tuple(row["shape"]),
        unit=row["unit"],
        frame=row["frame"],
        description=row["description"],
        requires=tuple(row["requires"]),
    )
    for row in _core.QUANTITIES
)


def numbers_per_time(orientation: bool, rotors: int) -> int:
    """The numbers every quantity of a run takes at one output time, for one body."""
    return sum(q.width(rotors) for q in QUANTITIES if q.present(orientation, rotors))


def _shape_text(quantity: Quantity, lead: str) -> str:
    """``(..., M, 3)``: the shape of the quantity in a trajectory, ``lead`` its leading axes."""
    dims = [lead, "M", *("R" if d == "rotors" else str(d) for d in quantity.shape)]
    return "(" + ", ".join(d for d in dims if d) + ")"


def _absent(quantity: Quantity) -> str:
    """When a trajectory has None for it."""
    without = {"orientation": "without the orientation (``orientation=False``)",
               "rotors": "without rotors"}
    return " and ".join(without[r] for r in quantity.requires)


def attribute_docs(array: str, lead: str = "...") -> str:
    """The entries of the quantities in a numpydoc ``Attributes`` section (indented by 4 and
    8), each array of type ``array`` with ``lead`` its leading axes."""
    lines = []
    for q in QUANTITIES:
        kind = f"{array} or None" if q.requires else array
        lines.append(f"    {q.name} : {_shape_text(q, lead)} {kind}")
        unit = "" if q.unit == "1" else f" ({q.unit})"
        text = q.description[:1].upper() + q.description[1:] + unit + "."
        if q.requires:
            text += f" None {_absent(q)}."
        if "rotors" in q.shape:
            text += " R is the number of rotors."
        lines += textwrap.wrap(text, 92, initial_indent=" " * 8, subsequent_indent=" " * 8)
    return "\n".join(lines)


#: The stub's text before the fields.
_STUB_HEAD = '''\
# Generated from polhode._core.QUANTITIES by `python scripts/fields_stub.py`: do not edit.
# The fields of polhode.Trajectory and polhode.dask.DaskTrajectory, for type checkers; at
# run time polhode._fields makes the same class from the same table.

from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

__all__ = ["Fields"]

_A = TypeVar("_A")

@dataclass(frozen=True, eq=False, repr=False)
class Fields(Generic[_A]):
    t: NDArray[np.float64]
'''


def stub() -> str:
    """The text of ``_fields.pyi``: the output times and each quantity, as arrays of type
    ``_A`` (``| None`` for those a run may lack), each with its description and unit."""
    lines = [_STUB_HEAD.rstrip("\n")]
    for q in QUANTITIES:
        lines.append(f"    {q.name}: _A{' | None' if q.requires else ''}")
        unit = "" if q.unit == "1" else f" ({q.unit})"
        text = f'"""{q.description[:1].upper()}{q.description[1:]}{unit}."""'
        lines += textwrap.wrap(text, 96, initial_indent=" " * 4, subsequent_indent=" " * 4)
    return "\n".join(lines) + "\n"


#: Where the stub is, beside its module (``scripts/fields_stub.py`` writes it).
STUB = Path(__file__).with_name("_fields.pyi")
