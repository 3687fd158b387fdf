"""Files given as arguments: paths, their existence, and the optional libraries that read them.

Shared by the readers of the core layer (:meth:`polhode.Body.from_file`) and of
:mod:`polhode.io`.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import signal
import sys
import threading
from collections.abc import Iterator
from typing import Any

from polhode.errors import ArgumentError, FileFormatError

__all__ = ["SWALLOWING", "existing", "fspath", "keeping_interrupts", "require", "writable"]


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


def writable(path: str, name: str = "path") -> str:
    """``path`` if a file can be written there, checked before the work that writes it:
    ArgumentError naming ``name`` for an empty name or a folder, FileNotFoundError (naming
    ``name``) where its folder does not exist."""
    if not path:
        raise ArgumentError(f"Expected `{name}` to be a file name, got ''.", argument=name)
    if os.path.isdir(path):
        raise ArgumentError(
            f"Expected `{name}` to be a file name, got the folder {path!r}.", argument=name
        )
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(2, f"No such folder to write `{name}` in", folder)
    return path


def require(module: str, extra: str) -> Any:
    """Import an optional dependency, or say which extra installs it (Ctrl-C during the import
    is never lost: :func:`keeping_interrupts`)."""
    try:
        with keeping_interrupts(module.split(".")[0]):
            return importlib.import_module(module)
    except ImportError as error:
        raise ImportError(
            f"Reading this file needs {module}: pip install 'polhode[{extra}]'."
        ) from error


#: Libraries that catch BaseException around imports of their own parts (placeholders for the
#: parts that failed): modules of theirs imported during an interrupted block are forgotten
#: too, whatever imported them (yourdfpy imports trimesh).
SWALLOWING = ("trimesh",)


class _Interrupts:
    """What :func:`keeping_interrupts` saw: the exception the SIGINT handler raised, and
    whether the code that ran went on after it (swallowed it)."""

    def __init__(self) -> None:
        self.raised: BaseException | None = None
        self.swallowed = False

    # An import finder first in sys.meta_path: once an interrupt has been swallowed, every new
    # import raises it again, so the rest of an interrupted import is quick.
    def find_spec(self, name: str, path: Any = None, target: Any = None) -> None:
        if self.raised is not None:
            self.swallowed = True
            raise self.raised


@contextlib.contextmanager
def keeping_interrupts(*packages: str) -> Iterator[None]:
    """Ctrl-C inside code that swallows it is raised when that code is left, never lost.

    trimesh imports its optional parts and parses some fields inside ``except BaseException``,
    which swallows the KeyboardInterrupt of a Ctrl-C: ``Body.from_file`` signalled during
    trimesh's import went on to read the whole file and returned a Body (4 of 4 tries on a 200
    MB STL). Here the SIGINT handler in place (Python's, or the user's) still runs at once; what
    it raises is remembered, every new import raises it again while the block runs (the rest of
    an interrupted import takes milliseconds), and it is raised when the block ends if the code
    inside did not let it out. Modules of ``packages`` (and of :data:`SWALLOWING`) imported
    during the block are then forgotten (``sys.modules``): they may hold placeholders for the
    parts whose import was interrupted, and the next import makes them whole.

    Only in the main thread (the one Python runs signal handlers in) and while the SIGINT
    handler is a Python callable; elsewhere the block runs as it is.
    """
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or not callable(previous):
        yield
        return
    state = _Interrupts()

    def handler(signum: int, frame: Any) -> Any:
        try:
            return previous(signum, frame)
        except BaseException as error:  # what the handler raises is kept, then re-raised
            if state.raised is None:
                state.raised = error
            raise

    before = set(sys.modules)
    signal.signal(signal.SIGINT, handler)
    sys.meta_path.insert(0, state)  # type: ignore[arg-type]
    try:
        yield
    except BaseException as error:
        if state.raised is not None and error is not state.raised:
            state.swallowed = True  # something else came out after the interrupt
        raise
    else:
        if state.raised is not None:
            state.swallowed = True
    finally:
        with contextlib.suppress(ValueError):
            sys.meta_path.remove(state)  # type: ignore[arg-type]
        if signal.getsignal(signal.SIGINT) is handler:
            signal.signal(signal.SIGINT, previous)
        if state.swallowed:
            for name in set(sys.modules) - before:
                if name.split(".")[0] in packages + SWALLOWING:
                    del sys.modules[name]
            raise state.raised  # type: ignore[misc]
