"""The exceptions of polhode: one class per kind of bad input, each naming what is at fault.

Every class derives from :class:`PolhodeError`, itself a :class:`ValueError`, and carries:

- ``argument``: the argument at fault (``"omega0"``, ``"t"``, ``"body"``...), or None;
- ``body``: in a batch, the index of the body at fault, or None.

``str(error)`` is the message, prefixed with ``body K:`` in a batch. Wrong types raise
:class:`TypeError`; a run stopped by Ctrl-C raises :class:`KeyboardInterrupt`, and one stopped by
:func:`polhode.cancel_all` (on any thread) raises :class:`CancelledError`.

Examples
--------
>>> import polhode as ph
>>> try:
...     ph.simulate([[1.0, 2.0, 3.0], [1.0, 2.0, -3.0]], [[0, 1, 0], [0, 1, 0]], 1.0)
... except ph.PolhodeError as error:
...     print(type(error).__name__, error.argument, error.body)
ArgumentError body 1
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "ArgumentError",
    "CancelledError",
    "ConvergenceError",
    "FileFormatError",
    "InertiaError",
    "NonFiniteError",
    "NonPositiveError",
    "PolhodeError",
    "PolhodeWarning",
    "RobotFileWarning",
    "ShapeError",
]


def _rebuild(cls: type[PolhodeError], message: str, argument: str | None, body: int | None) -> Any:
    return cls(message, argument=argument, body=body)


class PolhodeError(ValueError):
    """Base class of polhode's errors about values (a ValueError).

    Parameters
    ----------
    message : str
        What was expected and what came.
    argument : str, optional
        The argument at fault.
    body : int, optional
        The index of the body at fault in a batch.

    Examples
    --------
    Every error about a value is a PolhodeError, and so a ValueError:

    >>> import polhode as ph
    >>> try:
    ...     ph.simulate([[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]], [[0, 1, 0], [0, float("inf"), 0]], 1.0)
    ... except ValueError as error:
    ...     print(isinstance(error, ph.PolhodeError), error.argument, error.body)
    ...     print(error)
    True omega0 1
    body 1: Expected `omega0` to be finite, got inf.
    """

    def __init__(self, message: str, *, argument: str | None = None, body: int | None = None):
        super().__init__(message)
        self.message = message
        self.argument = argument
        self.body = body

    def __str__(self) -> str:
        return self.message if self.body is None else f"body {self.body}: {self.message}"

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (type(self), self.message, self.argument, self.body))

    def for_body(self, body: int | None) -> PolhodeError:
        """The same error, about body ``body`` (e.g. renumbered from a block to a batch)."""
        return type(self)(self.message, argument=self.argument, body=body)


class ShapeError(PolhodeError):
    """An array of the wrong shape, or a batch whose sizes disagree.

    Examples
    --------
    >>> import polhode as ph
    >>> try:
    ...     ph.simulate([1.0, 2.0, 3.0], [0.0, 1.0], 1.0)
    ... except ph.ShapeError as error:
    ...     print(error.argument, "|", error)
    omega0 | Expected `omega0` to have shape (3,) or (N, 3), got (2,).
    """


class NonFiniteError(PolhodeError):
    """A NaN or an infinity where a finite number is needed.

    Examples
    --------
    >>> import polhode as ph
    >>> try:
    ...     ph.Body.sphere(float("nan"), 1.0)
    ... except ph.NonFiniteError as error:
    ...     print(error.argument, "|", error)
    mass | Expected `mass` to be finite, got NaN.
    """


class NonPositiveError(PolhodeError):
    """Zero or a negative number where a positive one is needed.

    Examples
    --------
    >>> import polhode as ph
    >>> try:
    ...     ph.Body.sphere(-1.0, 0.1)
    ... except ph.NonPositiveError as error:
    ...     print(error.argument, "|", error)
    mass | Expected `mass` to be positive, got -1.
    """


class InertiaError(PolhodeError):
    """A tensor that is not an inertia tensor (asymmetric, not positive semidefinite, or
    breaking the triangle inequality I1 + I2 >= I3).

    Examples
    --------
    No mass distribution has the moments (1, 1, 3):

    >>> import numpy as np
    >>> import polhode as ph
    >>> try:
    ...     ph.Body.from_inertia(1.0, np.diag([1.0, 1.0, 3.0]))
    ... except ph.InertiaError as error:
    ...     print(error.argument, "|", error)
    inertia | Expected `inertia` to be a valid inertia tensor: its principal moments 1e0, 1e0,
    3e0 break the triangle inequality I1 + I2 >= I3.

    The motion itself only needs positive moments (:func:`polhode.simulate` takes them).
    """


class ArgumentError(PolhodeError):
    """Any other invalid value: an unknown option, an inconsistent combination.

    Examples
    --------
    >>> import polhode as ph
    >>> try:
    ...     ph.simulate([1.0, 2.0, 3.0], [0.0, 1.0, 0.0], 1.0, method="euler")
    ... except ph.ArgumentError as error:
    ...     print(error.argument, "|", error)
    method | Invalid `method`: expected one of "auto", "exact", "splitting", "midpoint", "rk4",
    "dop853", got "euler".
    """


class ConvergenceError(PolhodeError):
    """An iterative method that did not converge (e.g. the implicit midpoint's Newton
    iteration on a step too large for the motion).

    Examples
    --------
    >>> import polhode as ph
    >>> try:
    ...     ph.simulate([1.0, 2.0, 3.0], [30.0, 40.0, 50.0], 10.0, method="midpoint", dt=0.2)
    ... except ph.ConvergenceError as error:
    ...     print(error)
    implicit midpoint (Newton) did not converge: no convergence in 50 Newton iterations with
    step 0.2; reduce dt (step from t = 0).
    """


class CancelledError(BaseException):
    """A run stopped by :func:`polhode.cancel_all`, raised in the thread that ran it.

    Ctrl-C raises :class:`KeyboardInterrupt` in the main thread only; :func:`polhode.cancel_all`
    is how it reaches polhode calls running on other threads (a thread pool, dask's workers).
    Like KeyboardInterrupt (and :class:`asyncio.CancelledError`) it derives from
    :class:`BaseException`, so that an ``except Exception`` around the call does not swallow
    it, while schedulers that stop on KeyboardInterrupt (dask.distributed's workers) treat it
    as the failure of one task.

    Examples
    --------
    >>> import polhode as ph
    >>> issubclass(ph.CancelledError, Exception), issubclass(ph.CancelledError, BaseException)
    (False, True)
    """


class FileFormatError(PolhodeError):
    """A file that cannot be read as what it claims to be: not a mesh, a mesh that is open or
    of zero volume, a robot description with a missing or malformed field, a link whose
    declared inertia is not one.

    Besides ``argument`` (``"path"``) it carries ``path`` (the file), ``link`` (the link or
    body at fault, or None) and ``field`` (the attribute or element at fault, e.g.
    ``"inertia"``, ``"mass"``, ``"origin.rpy"``, or None). The message names all three.

    Examples
    --------
    >>> from polhode.errors import FileFormatError
    >>> error = FileFormatError("robot.urdf: link 'arm': <mass value>: expected a number, "
    ...                         "got 'heavy'.", path="robot.urdf", link="arm", field="mass")
    >>> (error.path, error.link, error.field, error.argument)
    ('robot.urdf', 'arm', 'mass', 'path')
    """

    def __init__(
        self,
        message: str,
        *,
        argument: str | None = "path",
        body: int | None = None,
        path: str | None = None,
        link: str | None = None,
        field: str | None = None,
    ):
        super().__init__(message, argument=argument, body=body)
        self.path = path
        self.link = link
        self.field = field

    def __reduce__(self) -> tuple[Any, ...]:
        return (
            _rebuild_file_error,
            (self.message, self.argument, self.body, self.path, self.link, self.field),
        )

    def for_body(self, body: int | None) -> FileFormatError:
        """The same error, about body ``body``."""
        return FileFormatError(
            self.message,
            argument=self.argument,
            body=body,
            path=self.path,
            link=self.link,
            field=self.field,
        )


def _rebuild_file_error(
    message: str,
    argument: str | None,
    body: int | None,
    path: str | None,
    link: str | None,
    field: str | None,
) -> FileFormatError:
    return FileFormatError(
        message, argument=argument, body=body, path=path, link=link, field=field
    )


class PolhodeWarning(UserWarning):
    """Base class of polhode's warnings: something was read or computed, but not all of it, or
    not as asked. Filter them (``warnings.filterwarnings("ignore", category=...)``) or turn them
    into errors (``"error"``) like any warning.

    Examples
    --------
    >>> import polhode as ph
    >>> issubclass(ph.RobotFileWarning, ph.PolhodeWarning)
    True
    >>> issubclass(ph.PolhodeWarning, UserWarning)
    True
    """


class RobotFileWarning(PolhodeWarning):
    """A robot description (URDF, MJCF) read whole but for the parts named: a link whose
    inertial a simulator would refuse is left out of the result, and the warning names the
    file, each such link and the check it fails. ``strict=True`` on the readers raises the
    first of them as a :class:`FileFormatError` instead.

    Besides the message it carries ``path`` (the file) and ``links`` (``{link: reason}`` of
    the links left out).

    Examples
    --------
    >>> import warnings
    >>> from polhode.errors import RobotFileWarning
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn(RobotFileWarning("arm.urdf: 1 link left out", path="arm.urdf",
    ...                                    links={"tool": "its mass is -1"}))
    >>> caught[0].category.__name__, caught[0].message.links
    ('RobotFileWarning', {'tool': 'its mass is -1'})
    """

    def __init__(self, message: str, *, path: str | None = None, links: Any = None):
        super().__init__(message)
        self.path = path
        self.links = dict(links or {})
