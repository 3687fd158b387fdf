"""What the commands share: UsageError, argparse's number types, checks of the files and
folders a command writes, and ``--body``'s specification of a body (a solid or a mesh file)."""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable
from typing import Any

import numpy as np

import polhode as ph
from polhode import _core


class UsageError(Exception):
    """A bad command line found after parsing: exit status 2 with a message naming ``option``."""

    def __init__(self, option: str, message: str):
        super().__init__(f"argument {option}: {message}")
        self.option = option


def number(
    what: str, *, minimum: float | None = None, positive: bool = False, below: float | None = None
) -> Callable[[str], float]:
    """An argparse type: a finite float, optionally >= minimum, > 0 or < below."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.") from None
        if (
            not math.isfinite(value)
            or (minimum is not None and value < minimum)
            or (positive and value <= 0)
            or (below is not None and value >= below)
        ):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.")
        return value

    return parse


def integer(what: str, minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """An argparse type: an integer in [minimum, maximum]."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.") from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}.")
        return value

    return parse


def check_file(option: str, path: str) -> None:
    """That ``path`` can be written (its folder exists and is writable, it is not a folder),
    by creating it now; a file that did not exist is removed again."""
    if not path:
        raise UsageError(option, "expected a file name, got ''.")
    existed = os.path.lexists(path)
    if os.path.isdir(path):
        raise UsageError(option, f"{path!r} is a folder, expected a file name.")
    try:
        with open(path, "a"):
            pass
    except OSError as error:
        raise UsageError(option, f"cannot write {path!r}: {error.strerror}.") from None
    if not existed:
        os.remove(path)


def check_folder(option: str, path: str) -> None:
    """That the folder ``path`` exists and is writable, or can be created."""
    if not path:
        raise UsageError(option, "expected a folder name, got ''.")
    folder = os.path.abspath(path)
    while not os.path.exists(folder):
        folder = os.path.dirname(folder)
    if not os.path.isdir(folder):
        raise UsageError(option, f"cannot create the folder {path!r}: {folder!r} is a file.")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UsageError(option, f"cannot write into {folder!r} (permission denied).")


def scenes_available() -> bool:
    """Whether plotly imports (polhode.plot.scene's figures)."""
    try:
        import plotly.graph_objects  # noqa: F401
    except ImportError:
        return False
    return True


def vector(values: Any, digits: int = 6) -> str:
    """A vector as the reports print it: ``[1 0.5 -2.5e-07]``, ``digits`` significant digits,
    never ``-0``."""
    return "[" + " ".join(f"{float(x) + 0.0:.{digits}g}" for x in np.ravel(values)) + "]"


def axes_words(axes: Any) -> str:
    """Principal axes (the columns of ``axes``) as the reports print them, numbered as their
    moments ascend: ``1: [0 0 1]  2: [1 0 0]  3: [0 1 0]``."""
    return "  ".join(f"{k}: {vector(axis)}" for k, axis in enumerate(np.asarray(axes).T, 1))


def json_numbers(value: Any) -> Any:
    """``value`` (dicts, lists, floats) with every ``-0.0`` made ``0.0``: json writes each
    float as its shortest round-trip decimal, and a negative zero as ``-0.0``."""
    if isinstance(value, dict):
        return {k: json_numbers(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_numbers(v) for v in value]
    if isinstance(value, float):
        return value + 0.0
    return value


def plots_available() -> bool:
    """Whether matplotlib imports (imported now, so that no run times its import)."""
    try:
        import matplotlib.figure  # noqa: F401
    except ImportError:
        return False
    return True


#: The solids ``--body`` takes and their keys, from the core's table: ``mass``, then each
#: parameter under the name :meth:`polhode.Body.solid` gives it (a cuboid's ``size``, an
#: ellipsoid's ``semi_axes``); a vector parameter takes three comma-separated numbers
#: (``size=0.1,0.2,0.5``).
SOLIDS = {kind: ("mass", *(name for name, _ in p)) for kind, p in _core.SOLIDS.items()}


def _key_form(kind: str, key: str) -> str:
    """How ``--body``'s help and errors show a key: ``size=X,Y,Z`` for a vector."""
    width = dict(_core.SOLIDS[kind]).get(key, 1)
    return f"{key}=X,Y,Z" if width == 3 else f"{key}=NUMBER"


def solid_forms() -> str:
    """Each solid and its keys, as ``--body``'s help lists them: a number's key bare, a
    vector's as ``size=X,Y,Z``."""
    def form(kind: str, key: str) -> str:
        return _key_form(kind, key) if dict(_core.SOLIDS[kind]).get(key, 1) > 1 else key

    return "; ".join(
        f"{kind} {' '.join(form(kind, k) for k in keys)}" for kind, keys in SOLIDS.items()
    )


#: ``--body mesh``: the file, exactly one of density and mass, and optionally scale and shell.
MESH_KEYS = ("path", "density", "mass", "scale", "shell")


def _key_values(
    pairs: list[str], allowed: Any, kind: str, takes: str, form: str
) -> dict[str, str]:
    """``--body``'s ``NAME=VALUE`` words as a dict: each name one of ``allowed``, once."""
    values: dict[str, str] = {}
    for pair in pairs:
        name, equals, value = pair.partition("=")
        if not equals:
            raise UsageError("--body", f"expected {form}, got {pair!r}; {takes}.")
        if name not in allowed:
            raise UsageError("--body", f"unknown key {name!r} for {kind}; {takes}.")
        if name in values:
            raise UsageError("--body", f"{name} is given twice; {takes}.")
        values[name] = value
    return values


def _mesh(pairs: list[str]) -> ph.Body:
    """A body from a mesh file: ``mesh path=FILE density=D`` (or ``mass=M``), optionally
    ``scale=S`` and ``shell=true``."""
    takes = "mesh takes path=FILE and density=NUMBER or mass=NUMBER, optionally scale=NUMBER "
    takes += "and shell=true"
    values = _key_values(pairs, MESH_KEYS, "mesh", takes, "NAME=VALUE")
    if "path" not in values:
        raise UsageError("--body", f"missing path; {takes}.")
    if ("density" in values) == ("mass" in values):
        given = "both" if "density" in values else "neither"
        raise UsageError("--body", f"give exactly one of density and mass, got {given}; {takes}.")
    numbers: dict[str, float] = {}
    for name in ("density", "mass", "scale"):
        if name in values:
            try:
                numbers[name] = float(values[name])
            except ValueError:
                raise UsageError(
                    "--body", f"expected {name}=NUMBER, got {name}={values[name]}; {takes}."
                ) from None
    shell = values.get("shell", "false").lower()
    if shell not in ("true", "false"):
        raise UsageError("--body", f"expected shell=true or shell=false, got shell={shell}.")
    try:
        return ph.Body.from_file(
            values["path"],
            density=numbers.get("density"),
            mass=numbers.get("mass"),
            scale=numbers.get("scale", 1.0),
            shell=shell == "true",
        )
    except (ph.PolhodeError, OSError, ImportError) as error:
        raise UsageError("--body", f"mesh: {error}") from None


def body_of(words: list[str]) -> ph.Body:
    """A solid from ``KIND NAME=VALUE ...``, e.g. ``cylinder mass=1 radius=0.1 length=0.5`` or
    ``cuboid mass=1 size=0.1,0.2,0.5``, or a mesh file, ``mesh path=part.stl density=2700``."""
    kind, *pairs = words
    if kind == "mesh":
        return _mesh(pairs)
    if kind not in SOLIDS:
        raise UsageError("--body", f"expected one of {', '.join(SOLIDS)} or mesh, got {kind!r}.")
    expected = SOLIDS[kind]
    takes = f"{kind} takes {' '.join(_key_form(kind, k) for k in expected)}"
    widths = dict(_core.SOLIDS[kind])
    values: dict[str, Any] = {}
    for name, value in _key_values(pairs, expected, kind, takes, "NAME=VALUE").items():
        width = widths.get(name, 1)
        words = value.split(",")
        try:
            numbers = [float(w) for w in words]
        except ValueError:
            numbers = []
        if len(numbers) != width:
            form = _key_form(kind, name)
            what = "three comma-separated numbers" if width == 3 else "a number"
            raise UsageError(
                "--body", f"expected {form} ({what}), got {f'{name}={value}'!r}; {takes}."
            )
        values[name] = numbers[0] if width == 1 else numbers
    missing = [n for n in expected if n not in values]
    if missing:
        raise UsageError("--body", f"missing {', '.join(missing)}; {takes}.")
    parameters = {name: values[name] for name, _ in _core.SOLIDS[kind]}
    try:
        return ph.Body.solid(kind, values["mass"], **parameters)
    except ph.PolhodeError as error:
        message = str(error)
        for name, width in _core.SOLIDS[kind]:  # a vector's component as typed: X, Y or Z
            for k in range(width if width > 1 else 0):
                message = message.replace(f"`{name}[{k}]`", f"{'XYZ'[k]} of {name}=X,Y,Z")
        raise UsageError("--body", f"{kind}: {message}") from None
