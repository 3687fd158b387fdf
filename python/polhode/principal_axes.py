"""Principal moments and axes: the result type and the batch eigensolve."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display
from polhode._coerce import as_float_array, as_scalar

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = ["Principal", "principal"]


class Principal:
    """Principal moments and axes of an inertia tensor.

    Unpacks as ``moments, axes = p``.

    Attributes
    ----------
    moments : (..., 3) numpy.ndarray
        Principal moments, ascending.
    axes : (..., 3, 3) numpy.ndarray
        Principal axes as the columns of a proper rotation (det = +1): column k belongs to
        ``moments[..., k]`` and maps principal coordinates to body coordinates,
        ``inertia = axes @ diag(moments) @ axes.T``.
    multiplicity : (..., 3) numpy.ndarray of int
        How many moments (itself included) equal each one within the tolerance: 1 1 1 for an
        asymmetric body, 2 2 1 or 1 2 2 for a symmetric one, 3 3 3 for a spherical one. Equal
        moments are returned exactly equal, with the canonical axes closest to the body's own.

    Examples
    --------
    A cylinder (m = 2, r = 0.1, L = 0.5) along z: m r^2 / 2 about its axis, m (3 r^2 + L^2) / 12
    across it.

    >>> import polhode as ph
    >>> p = ph.Body.cylinder(2.0, 0.1, 0.5).principal()
    >>> [round(float(m), 12) for m in p.moments]
    [0.01, 0.046666666667, 0.046666666667]
    >>> p.multiplicity.tolist()
    [1, 2, 2]
    >>> moments, axes = p
    >>> axes[:, 0].tolist()  # the symmetry axis
    [0.0, 0.0, 1.0]
    """

    __slots__ = ("axes", "moments", "multiplicity")

    def __init__(
        self,
        moments: NDArray[np.float64],
        axes: NDArray[np.float64],
        multiplicity: NDArray[np.int64],
    ) -> None:
        self.moments = moments
        self.axes = axes
        self.multiplicity = multiplicity

    @property
    def rotation(self) -> Rotation:
        """The principal frame as a scipy Rotation (principal to body coordinates)."""
        from scipy.spatial.transform import Rotation

        return Rotation.from_matrix(self.axes)

    def __iter__(self) -> Iterator[NDArray[np.float64]]:
        return iter((self.moments, self.axes))

    def __repr__(self) -> str:
        if np.ndim(self.moments) == 1:
            return (
                f"Principal(moments={_display.vector(self.moments)}, "
                f"multiplicity={_display.vector(self.multiplicity)}, "
                f"axes={_display.vector(self.axes)})"
            )
        return (
            f"Principal({self._batch()} tensors: moments {_display.shape(self.moments)}, "
            f"axes {_display.shape(self.axes)}, multiplicity {_display.shape(self.multiplicity)})"
        )

    def _batch(self) -> str:
        return " x ".join(str(d) for d in np.shape(self.moments)[:-1])

    def _repr_html_(self) -> str:
        if np.ndim(self.moments) == 1:
            rows = [
                ("moments (ascending)", _display.vector(self.moments)),
                ("multiplicity", _display.vector(self.multiplicity)),
                ("axes (columns)", _display.html_matrix(self.axes)),
            ]
        else:
            rows = [
                ("tensors", self._batch()),
                ("moments (ascending)", _display.shape(self.moments)),
                ("axes (columns)", _display.shape(self.axes)),
                ("multiplicity", _display.shape(self.multiplicity)),
            ]
        return _display.html_table("Principal", rows)


def principal(inertia: Any, rtol: float | None = None) -> Principal:
    """Principal moments (ascending) and axes of one tensor (3, 3) or a batch (N, 3, 3).

    A backward-stable cyclic Jacobi eigensolve on the tensor shifted by trace/3, run in Rust on
    all cores with the GIL released. The tensor must be finite and symmetric (to 64 eps of its
    largest entry); it need not be a physical inertia tensor.

    Parameters
    ----------
    inertia : (3, 3) or (N, 3, 3) array_like
        Symmetric tensors.
    rtol : float, optional
        Moments whose gap is at most ``rtol * ||inertia||_F`` count as equal (default 8 eps):
        they are returned equal, flagged in ``multiplicity``, with canonical axes. The residual
        ``||A V - V diag(w)||`` stays within 10 eps ||A|| at the default; a larger ``rtol``
        adds up to half of each merged gap to it.

    Returns
    -------
    Principal
        ``moments`` (3,) or (N, 3), ``axes`` (3, 3) or (N, 3, 3), ``multiplicity``.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> p = ph.principal([[2.0, -1.0, 0.0], [-1.0, 2.0, 0.0], [0.0, 0.0, 3.0]])
    >>> p.moments.tolist(), p.multiplicity.tolist()
    ([1.0, 3.0, 3.0], [1, 2, 2])
    >>> bool(np.allclose(p.axes[:, 0], [2**-0.5, 2**-0.5, 0.0], rtol=0, atol=1e-15))
    True

    A batch of N tensors gives N of each:

    >>> batch = ph.principal(np.stack([np.diag([3.0, 1.0, 2.0]), np.diag([1.0, 1.0, 2.0])]))
    >>> batch.moments.tolist(), batch.multiplicity.tolist()
    ([[1.0, 2.0, 3.0], [1.0, 1.0, 2.0]], [[1, 1, 1], [2, 2, 1]])
    >>> batch
    Principal(2 tensors: moments (2, 3), axes (2, 3, 3), multiplicity (2, 3))
    """
    array = as_float_array("inertia", inertia)
    tolerance = None if rtol is None else as_scalar("rtol", rtol)
    moments, axes, multiplicity = _core.principal(array, tolerance)
    return Principal(moments, axes, multiplicity)
