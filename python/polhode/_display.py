"""Short text and HTML summaries of the result types (``repr`` and ``_repr_html_``).

A summary shows numbers to 6 significant digits and arrays of a batch by their shape only, so
that printing a trajectory of a million bodies prints a few lines, not its arrays.
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from typing import Any

import numpy as np

#: Significant digits of the numbers in a summary.
DIGITS = 6


def number(value: Any) -> str:
    """A number to :data:`DIGITS` significant digits (``None`` as is, integers exactly)."""
    if value is None:
        return "None"
    if isinstance(value, int | np.integer) and not isinstance(value, bool):
        return str(int(value))
    x = float(value)
    return "0" if x == 0 else f"{x:.{DIGITS}g}"  # never "-0"


def shape(array: Any) -> str:
    """A shape as numpy writes it: ``(3,)``, ``(1000, 3)``."""
    dims = np.shape(array)
    return "(" + ", ".join(str(d) for d in dims) + (",)" if len(dims) == 1 else ")")


def vector(values: Any) -> str:
    """A short array with its numbers to :data:`DIGITS` digits, nested like the array."""
    array = np.asarray(values)
    if array.ndim == 0:
        return number(array[()])
    return "[" + ", ".join(vector(v) for v in array) + "]"


def html_table(title: str, rows: Sequence[tuple[str, str]]) -> str:
    """An HTML table with ``title`` as its caption and one (name, value) row per entry.

    Names and values are text, escaped here; a value given as :class:`Markup` is inserted as
    HTML (a nested matrix).
    """
    body = "".join(
        f"<tr><th style='text-align:left'>{html.escape(name)}</th>"
        f"<td style='text-align:left'>{value if isinstance(value, Markup) else html.escape(value)}"
        "</td></tr>"
        for name, value in rows
    )
    return (
        f"<table class='polhode-summary'><caption style='text-align:left'><b>"
        f"{html.escape(title)}</b></caption>{body}</table>"
    )


class Markup(str):
    """A string that :func:`html_table` inserts as HTML, not as text."""


def html_matrix(values: Any) -> Markup:
    """A small matrix as a nested HTML table of its numbers."""
    rows = "".join(
        "<tr>" + "".join(f"<td>{number(x)}</td>" for x in row) + "</tr>"
        for row in np.atleast_2d(values)
    )
    return Markup(f"<table>{rows}</table>")
