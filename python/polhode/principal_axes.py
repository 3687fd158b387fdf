"""Principal moments and axes: the result type, the batch eigensolve, axes followed along a
series (``continuous=True``), and the inertia tensors of a point-mass trajectory's frames."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display
from polhode._coerce import as_array, as_flag, as_float_array, as_scalar, unmasked
from polhode._equality import fields_equal
from polhode.errors import PolhodeError, ShapeError

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = ["Principal", "point_masses_inertia", "principal"]


class Principal:
    """Principal moments and axes of an inertia tensor.

    Unpacks as ``moments, axes = p``. Two are equal (``==``) when their moments, axes and
    multiplicities are, exactly (NaN equal to NaN in the same place): a Principal equals its
    copies and a repeated solve's; it is not hashable.

    Attributes
    ----------
    moments : (..., 3) numpy.ndarray
        Principal moments, ascending (except along a series followed with
        ``principal(..., continuous=True)``, where they follow their axes).
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

    def __eq__(self, other: object) -> Any:
        return fields_equal(self, other, self.__slots__)

    __hash__ = None  # type: ignore[assignment]  # arrays: equal by value, so not hashable

    def __reduce__(self) -> tuple[type[Principal], tuple[Any, ...]]:
        # Pickling and copying at every protocol (a class with __slots__ has no default below
        # protocol 2).
        return (type(self), (self.moments, self.axes, self.multiplicity))

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


def principal(inertia: Any, rtol: float | None = None, *, continuous: bool = False) -> Principal:
    """Principal moments (ascending) and axes of one tensor (3, 3) or a batch (N, 3, 3).

    A backward-stable cyclic Jacobi eigensolve on the tensor shifted by trace/3, run in Rust on
    all cores with the GIL released. The tensor must be finite and symmetric (to 64 eps of its
    largest entry); it need not be a physical inertia tensor.

    With ``continuous=True`` the batch is a series in time (T, 3, 3) (the frames of a
    trajectory, e.g. from :func:`point_masses_inertia`), and the axes are followed from frame
    to frame instead of being put in canonical form in each: frame 0 is canonical (ascending,
    deterministic signs); every later frame takes the signed permutation of its axes closest to
    the previous frame's (largest sum of ``|a_prev . a|``, signs making each dot product
    positive; that match is always a proper rotation, so det = +1 is kept). The axes then
    neither flip sign nor swap between consecutive frames of a smooth motion,
    and go through a crossing of two moments by continuity: ``axes[t, :, k]`` stays the same
    physical axis, and ``moments[t, k]`` and ``multiplicity[t, k]`` follow it, so the moments
    are **no longer ascending** after a crossing (``np.sort(p.moments, axis=-1)`` gives them
    ascending). In a frame whose moments are equal (``multiplicity`` > 1, within ``rtol``), the
    degenerate subspace has no preferred axes: they are the orthonormal basis of that subspace
    closest to the previous frame's axes (orthogonal Procrustes), so a symmetric top keeps its
    transverse axes from frame to frame and a spherical frame keeps the previous axes. Frames
    must be close enough that each axis moves less than about 45 degrees between them. The
    following runs in Rust after the solve (``polhode::series``), a few tens of nanoseconds
    per frame, degenerate or not, and Ctrl-C stops it.

    Parameters
    ----------
    inertia : (3, 3) or (N, 3, 3) array_like
        Symmetric tensors; (T, 3, 3) with ``continuous=True``.
    rtol : float, optional
        Moments whose gap is at most ``rtol * ||inertia||_F`` count as equal (default 8 eps):
        they are returned equal, flagged in ``multiplicity``, with canonical axes. The residual
        ``||A V - V diag(w)||`` stays within 10 eps ||A|| at the default; a larger ``rtol``
        adds up to half of each merged gap to it.
    continuous : bool, optional
        Follow the axes along the series (default False: each tensor on its own, canonical).

    Returns
    -------
    Principal
        ``moments`` (3,) or (N, 3), ``axes`` (3, 3) or (N, 3, 3), ``multiplicity``.

    Raises
    ------
    ShapeError
        ``inertia`` not (3, 3) or (N, 3, 3); a single (3, 3) tensor with ``continuous=True``.
    NonFiniteError, ArgumentError
        For a bad tensor (not finite, not symmetric, moments beyond the largest double),
        ``argument="inertia"`` and, in a batch, ``body`` the index of the first bad one; a
        negative ``rtol``.

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

    A body turning about z by 5 degrees per frame, its moments 1 and 2 crossing halfway:

    >>> from scipy.spatial.transform import Rotation
    >>> t = np.arange(40)
    >>> turn = Rotation.from_rotvec(np.outer(np.radians(5.0) * t, [0, 0, 1])).as_matrix()
    >>> a = np.linspace(1.0, 2.0, 40)
    >>> d = np.zeros((40, 3, 3))
    >>> d[:, 0, 0], d[:, 1, 1], d[:, 2, 2] = a, 3.0 - a, 4.0
    >>> inertia = turn @ d @ turn.transpose(0, 2, 1)
    >>> p = ph.principal(inertia, continuous=True)
    >>> bool(np.allclose(p.axes, turn))         # the axes follow the rotation, no flip
    True
    >>> bool(np.allclose(p.moments[:, 0], a))   # axes[:, :, 0] keeps its moment
    True
    """
    continuous = as_flag("continuous", continuous)
    array = as_float_array("inertia", inertia)
    if continuous and array.shape == (3, 3):
        raise ShapeError(
            "Expected `inertia` to have shape (T, 3, 3) (a series) with continuous=True, "
            "got (3, 3).",
            argument="inertia",
        )
    tolerance = None if rtol is None else as_scalar("rtol", rtol)
    try:
        moments, axes, multiplicity = _core.principal(array, tolerance, continuous)
    except PolhodeError as error:
        # The core solves one tensor as a batch of one: its error is about no batch's body.
        if array.ndim == 2 and error.body is not None:
            raise error.for_body(None) from None
        raise
    return Principal(moments, axes, multiplicity)


def point_masses_inertia(masses: Any, positions: Any) -> NDArray[np.float64]:
    """Inertia tensors of the frames of a point-mass trajectory, each about its own centre of
    mass.

    The tensor of each frame, ``I = sum m (|r|^2 1 - r r^T)`` with ``r`` the offset from that
    frame's centre of mass (products of inertia as tensor elements), computed in Rust on all
    cores with the GIL released. Each frame is centred first (its centre of mass found relative
    to its first point), so a molecule far from the origin keeps its digits; the sums are
    plain double-precision sums (an element's error is about N eps of the largest moment), not
    the square-root form of :meth:`Body.point_masses`, which one frame can use instead.
    Single-precision positions (as MD trajectories store them) are read as they are, without a
    converted copy; every float32 is exactly a double.

    Feed the result to :func:`principal` with ``continuous=True`` for principal axes that do
    not flip or swap between frames.

    Parameters
    ----------
    masses : (N,) array_like
        Positive masses, shared by every frame.
    positions : (T, N, 3) or (N, 3) array_like
        T frames of N points (float64 or float32), or one frame.

    Returns
    -------
    (T, 3, 3) or (3, 3) numpy.ndarray
        The inertia tensor of each frame about its centre of mass, in the frame's axes.

    Raises
    ------
    ShapeError
        ``positions`` not (T, N, 3) or (N, 3) with N = len(masses); no masses.
    NonFiniteError, NonPositiveError
        A non-finite position (naming ``positions[t, n, k]``), a mass that is not finite and
        positive (``masses[n]``).
    ArgumentError
        A frame whose inertia overflows double precision.

    Examples
    --------
    Carbon monoxide (12 u and 16 u, 1.128 angstrom apart) along z, then along x:

    >>> import numpy as np
    >>> import polhode as ph
    >>> positions = [[[0, 0, 0], [0, 0, 1.128]], [[5, 0, 0], [6.128, 0, 0]]]
    >>> inertia = ph.point_masses_inertia([12.0, 16.0], positions)
    >>> inertia.shape
    (2, 3, 3)
    >>> mu = 12.0 * 16.0 / 28.0
    >>> bool(np.allclose(np.diagonal(inertia, axis1=1, axis2=2),
    ...                  [[mu * 1.128**2, mu * 1.128**2, 0], [0, mu * 1.128**2, mu * 1.128**2]]))
    True

    Principal axes over an MDAnalysis trajectory, without flips (``order="fac"`` gives
    (frames, atoms, 3)):

    >>> # atoms = universe.select_atoms("protein")
    >>> # xyz = universe.trajectory.timeseries(atoms, order="fac")
    >>> # p = ph.principal(ph.point_masses_inertia(atoms.masses, xyz), continuous=True)
    """
    m = as_array("masses", masses, (None,))
    if isinstance(positions, np.ndarray) and positions.dtype == np.float32:
        r: NDArray[Any] = np.ascontiguousarray(unmasked("positions", positions))
    else:
        r = as_float_array("positions", positions)
    return _core.point_masses_inertia(m, r)
