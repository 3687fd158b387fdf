"""What a person reads on the plots: the units of the labels and the numbering of the axes.

**Units.** Every plot takes ``units``, a mapping of the base units the trajectory and the body
were in, ``{"time": "s", "length": "m", "mass": "kg"}`` by default (SI); the labels derive the
others from them (omega in rad per time unit, L in mass length^2 per time, T in joules, or
mass length^2 per time^2 in other units).

**Axes.** The principal axes are numbered 1, 2, 3 in ascending order of moment (I1 <= I2 <= I3,
the textbooks' numbering) wherever a person reads them; Python indices (``axis=0..2``,
``moments[0]``) stay 0-based and are written as indexing expressions; coordinates in a frame
that is not principal (a body's own axes when they are not principal, space axes) are x, y, z.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from polhode.errors import ArgumentError

__all__ = [
    "AXIS_ROLES",
    "UNITS",
    "Units",
    "axis_name",
    "labelled",
    "subscripted",
    "units_of",
]

#: The principal axes by role, indexed 0, 1, 2 with the moments ascending (axes 1, 2, 3).
AXIS_ROLES = ("smallest", "intermediate", "largest")

#: The units the labels say by default (SI), by quantity.
UNITS = {"time": "s", "length": "m", "mass": "kg"}


@dataclass(frozen=True)
class Units:
    """The base units of a plot's labels, and those derived from them.

    ``square`` is how a square is written: ``"$^2$"`` (matplotlib's mathtext, the default) or
    ``"^2"`` (plain text, for plotly)."""

    time: str = "s"
    length: str = "m"
    mass: str = "kg"

    @property
    def si(self) -> bool:
        return (self.time, self.length, self.mass) == ("s", "m", "kg")

    @property
    def rate(self) -> str:
        """Angular velocity: radians per time unit."""
        return f"rad/{self.time}"

    def momentum(self, square: str = "$^2$") -> str:
        """Angular momentum: mass length^2 per time unit."""
        return f"{self.mass} {self.length}{square}/{self.time}"

    def energy(self, square: str = "$^2$") -> str:
        """Kinetic energy: J in SI, else mass length^2 per time^2."""
        if self.si:
            return "J"
        return f"{self.mass} {self.length}{square}/{self.time}{square}"


def units_of(units: Any) -> Units:
    """The units of the labels: SI, with those given in place. TypeError naming ``units`` for
    anything but a mapping of strings; ArgumentError for an unknown key or an empty name."""
    if units is None:
        return Units()
    if not isinstance(units, Mapping):
        raise TypeError(
            f"Expected `units` to be a dict such as {UNITS}, got {type(units).__name__}."
        )
    unknown = sorted(str(k) for k in units if k not in UNITS)
    if unknown:
        raise ArgumentError(
            f"Expected the keys of `units` among {sorted(UNITS)}, got {unknown}.", argument="units"
        )
    for key, value in units.items():
        if not isinstance(value, str):
            raise TypeError(
                f"Expected `units[{key!r}]` to be a unit's name (str), got {type(value).__name__}."
            )
        if not value.strip():
            raise ArgumentError(
                f"Expected `units[{key!r}]` to be a unit's name, got {value!r}.", argument="units"
            )
    return Units(**{k: str(v).strip() for k, v in units.items()})


def labelled(quantity: str, unit: str | None) -> str:
    """An axis label: the quantity and its unit in parentheses (none for a ratio)."""
    return quantity if unit is None else f"{quantity} ({unit})"


def subscripted(symbol: str, subscript: str | int) -> str:
    """A symbol (mathtext, e.g. ``"\\omega"``, ``"L"``) with a subscript: ``$\\omega_{1}$``."""
    return f"${symbol}_{{{subscript}}}$"


def axis_name(k: int) -> str:
    """Principal axis ``k`` (a 0-based index, moments ascending) as a person reads it: ``I_1
    axis (smallest moment)`` in mathtext."""
    return f"$I_{{{k + 1}}}$ axis ({AXIS_ROLES[k]} moment)"
