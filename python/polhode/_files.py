"""Files given as arguments: paths, their existence, and the optional libraries that read them.

Shared by the readers of the core layer (:meth:`polhode.Body.from_file`) and of
:mod:`polhode.io`.
"""

from __future__ import annotations

import importlib
import os
from typing import Any

from polhode.errors import FileFormatError

__all__ = ["existing", "fspath", "require"]


def fspath(path: Any, name: str = "path") -> str:
    """A path as a str (TypeError for anything that is not a str or os.PathLike)."""
    if isinstance(path, bytes) or not isinstance(path, str | os.PathLike):
        raise TypeError(f"Expected `{name}` to be a path (str or os.PathLike), got {type(path)}.")
    return os.fspath(path)


def existing(path: str) -> str:
    """``path`` if it is a file; FileNotFoundError (naming it) or FileFormatError (a folder)."""
    if not os.path.exists(path):
        raise FileNotFoundError(2, "No such file", path)
    if os.path.isdir(path):
        raise FileFormatError(f"{path}: is a folder, expected a file.", path=path)
    return path


def require(module: str, extra: str) -> Any:
    """Import an optional dependency, or say which extra installs it."""
    try:
        return importlib.import_module(module)
    except ImportError as error:
        raise ImportError(
            f"Reading this file needs {module}: pip install 'polhode[{extra}]'."
        ) from error
