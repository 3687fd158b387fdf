"""Motion: Euler's equations with orientation, by the exact solution or an integrator."""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from polhode import _core, _display
from polhode._chunks import spans
from polhode._coerce import as_flag, as_integer, as_scalar
from polhode._coerce import as_float_array as _as_float_array
from polhode._equality import equal, fields_equal
from polhode._euler import euler_angles
from polhode._fields import Fields
from polhode._inputs import core_body as _body
from polhode._quantities import QUANTITIES, attribute_docs, numbers_per_time
from polhode._sampling import describe, resolving_times
from polhode.errors import ArgumentError, NonFiniteError
from polhode.rotors import as_rotors
from polhode.torque import as_torque

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = ["Trajectory", "simulate"]

#: The methods of :func:`simulate` (the core parses the name).
METHODS = tuple(_core.METHODS)

#: The default ``max_steps`` of :func:`simulate`.
MAX_STEPS = 100_000_000


@dataclass(frozen=True, repr=False, eq=False)
class Trajectory(Fields[NDArray[np.float64]]):
    """The motion at the output times.

    A batch keeps its leading N: ``omega`` is (N, M, 3) for N bodies, (M, 3) for one.

    Attributes
    ----------
    t : (M,) numpy.ndarray
        Output times (s).
{quantities}
    moments : (..., 3) numpy.ndarray
        The principal moments the motion was integrated with (about the pivot for a heavy top).
    stats : dict
        ``steps``, ``rejected_steps``, ``evaluations`` (per body), ``wall_time`` (s), ``method``.

    The quantities (every field but ``t``, ``moments`` and ``stats``) are those of the core's
    table, ``polhode._core.QUANTITIES``, each in SI units.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], np.linspace(0.0, 100.0, 201))
    >>> sol.omega.shape, sol.quaternion.shape, sol.energy.shape
    ((201, 3), (201, 4), (201,))
    >>> sol.orientation[-1].apply([0.0, 1.0, 0.0]).shape  # the body's y axis in space at t = 100
    (3,)
    >>> print(repr(sol).split(", wall_time")[0])
    Trajectory(bodies=1, times=201 in [0, 100], method='exact', moments=[1, 2, 3],
               orientation=yes, energy_t0=1.0002, steps=0

    A batch keeps its leading dimension:

    >>> batch = ph.simulate([1.0, 2.0, 3.0], np.eye(3), [0.0, 1.0], orientation=False)
    >>> batch.omega.shape, batch.quaternion
    ((3, 2, 3), None)
    """

    moments: NDArray[np.float64]
    stats: dict[str, Any]

    # What the exact solution needs to be evaluated at other times (see __call__), beside the
    # fields: neither one of them nor compared.
    __slots__ = ("_motion",)

    def __eq__(self, other: object) -> bool:
        """Equal trajectories: the same output times, quantities (None where the other has
        None) and moments, and the same method and costs, each exactly as ``polhode._equality``
        compares results; the wall time and the account of how the times were chosen are not
        compared."""
        if type(other) is not type(self):
            return NotImplemented
        assert isinstance(other, Trajectory)
        return fields_equal(self, other, ("t", *OUTPUTS)) and equal(
            _compared(self.stats), _compared(other.stats)
        )

    __hash__ = None  # type: ignore[assignment]  # equal by value, and mutable arrays

    def __getstate__(self) -> tuple[dict[str, Any], dict[str, Any] | None]:
        """The fields, and the exact solution's inputs where it has them (pickle, copy)."""
        motion = getattr(self, "_motion", None)
        return dict(self.__dict__), None if motion is None else {"_motion": motion}

    def __setstate__(self, state: Any) -> None:
        """The fields set as ``simulate`` sets them (the dataclass is frozen), at once."""
        fields, slots = state if isinstance(state, tuple) else (state, None)
        self.__dict__.update(fields)
        for name, value in (slots or {}).items():
            object.__setattr__(self, name, value)

    def __len__(self) -> int:
        """The number of bodies of a batch (TypeError for one body's trajectory)."""
        return _bodies(self, "len()")

    def __getitem__(self, key: Any) -> Trajectory:
        """Bodies of a batch, as numpy indexes its leading axis: ``sweep[k]`` (an integer,
        negative from the end) is body k's trajectory, equal to that body simulated alone at
        the same output times; ``sweep[a:b]``, a list or an array of indices or a boolean mask
        is a batch of those bodies. The arrays are numpy's views of the batch's."""
        n = _bodies(self, "indexing")
        single = isinstance(key, int | np.integer) and not isinstance(key, bool | np.bool_)
        if single:
            if not -n <= int(key) < n:
                raise IndexError(f"body {int(key)} is out of range for a batch of {n} bodies.")
            key = int(key)
        elif not isinstance(key, slice):
            key = np.asarray(key)
            if key.ndim != 1 or key.dtype.kind not in "biu" or (key.size == 0 and n == 0):
                raise TypeError(
                    "Expected a body's index, a slice, or a 1-D array of indices or of bools to "
                    f"index a batch Trajectory, got {type(key).__name__}"
                    + (f" of shape {key.shape} and dtype {key.dtype}." if key.ndim else ".")
                )
            np.zeros(n)[key]  # numpy's IndexError for an index out of range or a bad mask
        fields: dict[str, Any] = {
            name: None if getattr(self, name) is None else getattr(self, name)[key]
            for name in OUTPUTS
        }
        stats = {k: v for k, v in self.stats.items() if k != "wall_time"}
        for name in ("steps", "rejected_steps", "evaluations"):
            if name in stats:
                stats[name] = int(stats[name][key]) if single else stats[name][key]
        part = object.__new__(Trajectory)
        part.__dict__.update({"t": self.t, **fields, "stats": stats})
        motion = getattr(self, "_motion", None)
        if motion is not None:
            object.__setattr__(part, "_motion", motion.bodies(key, n))
        return part

    def __call__(self, t: Any) -> Trajectory:
        """The motion at other output times ``t`` (a time or an array of them, each >= t0):
        the exact solution's dense output, for a trajectory of ``method="exact"``.

        The closed form at any time: ``traj(t)`` is ``polhode.simulate`` of the same inputs at
        the times ``t`` (one time gives M = 1), bit for bit; each output depends on its time
        alone but the quaternion's sign, kept continuous along the times asked for. Another
        method has no dense output here: simulate again at the times needed (TypeError).

        Examples
        --------
        >>> import numpy as np
        >>> import polhode as ph
        >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 100.0)
        >>> fine = sol(np.linspace(40.0, 41.0, 1001))  # a millisecond apart near t = 40
        >>> fine.omega.shape, bool(np.array_equal(sol(sol.t).omega, sol.omega))
        ((1001, 3), True)
        """
        motion = getattr(self, "_motion", None)
        if motion is None:
            raise TypeError(
                f"This Trajectory (method {self.stats.get('method')!r}) cannot be evaluated at "
                "other times: only the exact solution has a dense output here. Simulate again "
                "with the output times you need: polhode.simulate(..., t=times)."
            )
        times = _as_float_array("t", t)
        if times.ndim == 0:
            times = times.reshape(1)
        return simulate(
            motion.body,
            motion.omega0,
            times,
            orientation0=motion.orientation0,
            t0=motion.t0,
            method="exact",
            orientation=motion.orientation,
        )

    @property
    def orientation(self) -> Rotation | list[Rotation] | None:
        """Body-to-space orientation as a scipy Rotation of M rotations (a list for a batch)."""
        from scipy.spatial.transform import Rotation

        if self.quaternion is None:
            return None
        if self.quaternion.ndim == 2:
            return Rotation.from_quat(self.quaternion)
        return [Rotation.from_quat(q) for q in self.quaternion]

    def _summary(self) -> list[tuple[str, str]]:
        """(name, value) pairs of the short summary: sizes and settings, never whole arrays."""
        single = np.ndim(self.omega) == 2
        bodies = 1 if single else int(np.shape(self.omega)[0])
        times = (
            f"{self.t.size} in [{_display.number(self.t[0])}, {_display.number(self.t[-1])}]"
            if self.t.size
            else "0"
        )
        if "sampling" in self.stats:
            # An end time was given: how its output times were chosen (polhode._sampling).
            times += f" ({describe(self.stats['sampling'])})"
        steps = self.stats.get("steps")
        rows = [
            ("bodies", str(bodies)),
            ("times", times),
            ("method", repr(self.stats.get("method"))),
            (
                "moments",
                _display.vector(self.moments) if single else _display.shape(self.moments),
            ),
            ("orientation", "yes" if self.quaternion is not None else "no"),
        ]
        if single and self.t.size:
            rows.append(("energy_t0", _display.number(self.energy[0])))
        if steps is not None:
            rows.append(("steps", _display.number(int(np.sum(steps)))))
        if "wall_time" in self.stats:
            rows.append(("wall_time", f"{_display.number(self.stats['wall_time'])} s"))
        return rows

    def __repr__(self) -> str:
        return "Trajectory(" + ", ".join(f"{k}={v}" for k, v in self._summary()) + ")"

    def _repr_html_(self) -> str:
        rows = self._summary()
        for name in OUTPUTS:
            if name == "moments":
                continue  # in the summary
            value = getattr(self, name)
            rows.append((name, "None" if value is None else _display.shape(value)))
        return _display.html_table("Trajectory", rows)

    def euler_angles(self, seq: str = "ZXZ", degrees: bool = False) -> NDArray[np.float64]:
        """The orientation as Euler angles, continuous in time: (..., M, 3).

        ``seq`` as in scipy's ``Rotation.as_euler``: three axes, upper case for intrinsic
        rotations (``"ZXZ"``, the default: precession, nutation, spin), lower case for
        extrinsic ones; proper Euler (``"ZXZ"``, ``"ZYZ"``...) or Tait-Bryan (``"ZYX"``...)
        angles. Each frame is scipy's ``as_euler``; the first and third angles are then
        unwrapped along time (``np.unwrap``: no 2 pi jumps, so a body that keeps turning gives
        angles that keep growing), which needs output times close enough that no angle moves by
        pi or more between two of them. The middle angle stays in scipy's range ([0, pi] for
        proper Euler angles, [-pi/2, pi/2] for Tait-Bryan ones), where each rotation has one
        set of angles.

        Gimbal lock: where the middle angle is at an end of its range (within scipy's
        threshold, about 1e-7 rad), only the sum of the first and third angles (or their
        difference, by the end and the sequence) is defined. There the third angle keeps its
        value from the previous output time (0 at the first) and the first angle carries the
        rest. Near a lock the split between the two is ill-conditioned (they may swing by about
        pi between output times, or jump by pi where the motion crosses the lock), while the
        sum or difference that sets the rotation stays continuous: within pi/8 of an end it is
        kept free of 2 pi jumps too, assuming it moves by less than pi between output times.
        scipy's gimbal-lock warning is not raised.

        Parameters
        ----------
        seq : str
            The axes, as in ``scipy.spatial.transform.Rotation.as_euler`` (default ``"ZXZ"``).
        degrees : bool
            Angles in degrees (default radians).

        Returns
        -------
        (..., M, 3) numpy.ndarray
            The angles of each output time, a batch keeping its leading N.
        """
        if not isinstance(seq, str):
            raise TypeError(
                f"Expected `seq` to be a string such as 'ZXZ', got {type(seq).__name__}."
            )
        degrees = as_flag("degrees", degrees)
        if self.quaternion is None:
            raise ArgumentError(
                "The trajectory has no orientation (simulated with orientation=False): no Euler "
                "angles.",
                argument="orientation",
            )
        quaternion = self.quaternion
        if quaternion.size == 0:
            # An empty batch: no angles, but the axes still checked.
            euler_angles(np.array([[0.0, 0.0, 0.0, 1.0]]), seq)
            return np.zeros(quaternion.shape[:-1] + (3,))
        if quaternion.ndim == 2:
            angles = euler_angles(quaternion, seq)
        else:
            # Each body's angles straight into the batch's array (chunk by chunk: Ctrl-C).
            angles = np.empty(quaternion.shape[:-1] + (3,))
            rows = angles.reshape(-1, *angles.shape[-2:])
            for k, q in enumerate(quaternion.reshape(-1, *quaternion.shape[-2:])):
                one = euler_angles(q, seq)
                for span in spans(len(one)):
                    rows[k, span] = one[span]
        if degrees:
            flat = angles.reshape(-1)
            for span in spans(flat.size):
                np.degrees(flat[span], out=flat[span])
        return angles


def _bodies(trajectory: Trajectory, what: str) -> int:
    """The number of bodies of a batch trajectory; TypeError naming ``what`` for one body."""
    if np.ndim(trajectory.omega) == 2:
        raise TypeError(
            f"{what} of one body's Trajectory: it is no batch (its omega is (M, 3)); "
            "len(traj.t) is its number of output times."
        )
    return int(np.shape(trajectory.omega)[0])


def _compared(stats: dict[str, Any]) -> dict[str, Any]:
    """What equal trajectories share of their stats: not the wall time, nor the account of how
    the times were chosen (a batch's body and the body simulated alone at its times)."""
    return {k: v for k, v in stats.items() if k not in ("wall_time", "sampling")}


class _Motion(NamedTuple):
    """The inputs of an exact run, to evaluate it at other times (Trajectory.__call__)."""

    body: Any
    omega0: NDArray[np.float64]
    orientation0: NDArray[np.float64] | None
    t0: float
    orientation: bool

    def bodies(self, key: Any, n: int) -> _Motion:
        """The inputs of the bodies ``key`` of a batch of ``n``: what is given per body (N
        moments or Bodies, N orientations) taken as numpy indexes it, what is shared kept."""
        picked = np.arange(n)[key]
        body = self.body
        if isinstance(body, list):
            body = body[int(picked)] if np.ndim(picked) == 0 else [body[k] for k in picked]
        elif isinstance(body, np.ndarray) and body.ndim == 2:
            body = body[key]
        q = self.orientation0
        if q is not None and q.ndim >= 2 and q.shape[0] == n and q.shape != (3, 3):
            q = q[key]
        return self._replace(body=body, omega0=self.omega0[key], orientation0=q)


Trajectory.__doc__ = (Trajectory.__doc__ or "").replace(
    "{quantities}", attribute_docs("numpy.ndarray")
)

#: The Trajectory fields computed by the core, by name (all but ``t`` and ``stats``): the
#: quantities of the core's table, and ``moments``.
OUTPUTS = (*(q.name for q in QUANTITIES), "moments")


def _available_memory() -> int | None:
    """Bytes of memory available to a new allocation (Linux: MemAvailable), or None."""
    try:
        with open("/proc/meminfo", encoding="ascii") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):
        return None


#: Output sizes (bytes) that :func:`_check_fits` takes as fitting without asking the system.
_ALWAYS_FITS = 64 * 2**20

#: Output times of one body without rotors that :func:`simulate` takes as fitting without
#: :func:`_check_fits`: all of their outputs fit in :data:`_ALWAYS_FITS` (asserted here, for
#: the quantities of the core's table).
_ONE_BODY_FITS = 100_000
assert _ONE_BODY_FITS * numbers_per_time(True, 0) * 8 <= _ALWAYS_FITS


def _check_fits(
    omega0: NDArray[np.float64], times: NDArray[np.float64], orientation: bool, rotors: int = 0
) -> None:
    """MemoryError before the work if the outputs cannot fit in this machine's memory.

    Outputs up to :data:`_ALWAYS_FITS` bytes are not checked (reading /proc/meminfo would be
    most of a small call); should even they not fit, the core's allocation fails cleanly with
    MemoryError."""
    n = omega0.shape[0] if omega0.ndim == 2 else 1
    per_time = numbers_per_time(orientation, rotors)
    size = float(n) * float(times.size) * per_time * 8
    if size <= _ALWAYS_FITS:
        return
    available = _available_memory()
    if available is not None and size > available:
        raise MemoryError(
            f"The outputs of {n} bodies at {times.size} output times take {size:.3g} bytes, "
            f"more than the {available:.3g} bytes available: ask for fewer output times `t` or "
            "bodies, orientation=False, or run in chunks (polhode.dask)."
        )


def _orientation0(orientation0: Any) -> NDArray[np.float64] | None:
    """Quaternions (..., 4) xyzw or matrices (..., 3, 3); the core checks them.

    A scipy Rotation is recognised without importing scipy (whoever made one has imported it):
    an array never pays for that import, nor does the run's ``wall_time``."""
    if orientation0 is None:
        return None
    transform = sys.modules.get("scipy.spatial.transform")
    if transform is not None and isinstance(orientation0, transform.Rotation):
        return np.ascontiguousarray(orientation0.as_quat())
    return _as_float_array("orientation0", orientation0)


def _check_progress(progress: Any) -> None:
    if not (progress is None or isinstance(progress, bool | np.bool_) or callable(progress)):
        raise TypeError(
            "Expected `progress` to be a bool or a callable taking the fraction done, "
            f"got {type(progress).__name__}."
        )


def _progress(progress: Any) -> tuple[Callable[[float], object] | None, Any]:
    """The callback handed to the core for ``progress`` and the tqdm bar to close, or None."""
    if progress is None or isinstance(progress, bool | np.bool_):
        if not progress:
            return None, None
        try:
            from tqdm.auto import tqdm
        except ImportError as error:
            raise ImportError(
                "simulate(progress=True) shows a tqdm progress bar, but tqdm is not installed: "
                "pip install tqdm (or polhode[progress]), or pass a callable."
            ) from error
        bar = tqdm(
            total=1.0,
            desc="polhode.simulate",
            bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]",
        )

        def update(fraction: float) -> None:
            if fraction > bar.n:
                bar.update(fraction - bar.n)

        return update, bar
    return progress, None


def _settings(
    t0: float,
    method: str,
    dt: Any,
    order: Any,
    rtol: Any,
    atol: Any,
    torque: Any,
    rotors: Any,
) -> dict[str, Any]:
    """The keywords of a run that the core's simulate and fastest_rate share, converted."""
    return {
        "t0": t0,
        "method": method,
        "dt": None if dt is None else as_scalar("dt", dt),
        "order": as_integer("order", order),
        "rtol": rtol if type(rtol) is float else as_scalar("rtol", rtol),
        "atol": None if atol is None else as_scalar("atol", atol),
        "torque": None if torque is None else as_torque(torque),
        "rotors": rotors,
    }


def fastest_rate(
    body: Any,
    omega0: Any,
    t_end: float,
    *,
    orientation0: Any = None,
    method: str = "auto",
    dt: float | None = None,
    order: int = 4,
    rtol: float = 1e-10,
    atol: float | None = None,
    torque: Any = None,
    t0: float = 0.0,
    rotors: Any = None,
    **unused: Any,
) -> dict[str, Any]:
    """The fastest rate of the run :func:`simulate` makes of these arguments to the end time
    ``t_end`` (``polhode._core.fastest_rate``'s dict: ``rate``, ``pace``, ``body``, ``steps``,
    ``method``; and ``dt``), which sets its output times (polhode._sampling); the keywords
    that do not change it (``orientation``, ``max_steps``, ``progress``) are taken and left
    alone. For :mod:`polhode.dask`, which asks it of each block of a batch."""
    t0 = as_scalar("t0", t0)
    rate = dict(
        _core.fastest_rate(
            _body(body),
            _as_float_array("omega0", omega0),
            as_scalar("t", t_end),
            orientation0=None if orientation0 is None else _orientation0(orientation0),
            **_settings(
                t0,
                method,
                dt,
                order,
                rtol,
                atol,
                torque,
                None if rotors is None else as_rotors(rotors),
            ),
        )
    )
    rate["dt"] = None if dt is None else as_scalar("dt", dt)
    return rate


def simulate(
    body: Any,
    omega0: Any,
    t: Any,
    *,
    orientation0: Any = None,
    method: str = "auto",
    dt: float | None = None,
    order: int = 4,
    rtol: float = 1e-10,
    atol: float | None = None,
    torque: Any = None,
    t0: float = 0.0,
    orientation: bool = True,
    max_steps: int = MAX_STEPS,
    progress: bool | Callable[[float], object] = False,
    rotors: Any = None,
) -> Trajectory:
    """The rotation of a rigid body (or a batch), torque-free or with a torque.

    Parameters
    ----------
    body : Body, (3,) moments, (3, 3) tensor; (N, 3) moments or N Bodies for a batch
        ``omega0``'s shape decides how many bodies there are: with ``omega0`` of shape (3,),
        one body (a Body, principal moments (3,) or an inertia tensor (3, 3)); with (N, 3), N
        bodies, for every N including 3 (principal moments (N, 3), a list of N Bodies, or one
        Body or (3,) moments shared by all). A body in non-principal axes is integrated in
        principal axes and reported back in its own axes. Every principal moment must be
        positive (Euler's equations need I^-1); the moments may break I1 + I2 >= I3, which no
        mass distribution does, since Euler's equations hold for any positive moments.
    omega0 : (3,) or (N, 3) array_like
        Initial angular velocity in body axes at ``t0``: one body, or N.
    t : float or (M,) array_like
        Output times (non-decreasing, >= t0), or an end time: then output times from t0 to t
        that resolve the motion, 48 per turn at its fastest rate (omega's period in the body,
        the precession, the spin, a torque's or the rotors' rate at t0), at least 49 and at
        most 100001 (a batch: 10^6 outputs in all); a fixed-step method's every so many steps,
        and ``dop853`` (one body) the end of each accepted step as well. How they were chosen
        is ``stats["sampling"]`` (see ``polhode._sampling``), and the trajectory's repr says it.
    orientation0 : optional
        Initial body-to-space orientation: scipy Rotation, (3, 3) matrix, xyzw quaternion, or N
        of them (default identity).
    method : {"auto", "exact", "splitting", "midpoint", "rk4", "dop853"}
        ``auto`` is ``exact`` (the closed form: no steps, O(1) per output time) without a torque
        or rotors and ``dop853`` with them. ``splitting`` (Lie-Poisson, symplectic; ``|L|`` and L
        in space exact), ``midpoint`` (implicit; T and ``|L|`` exact) and ``rk4`` take a fixed
        ``dt``.
    dt : float, optional
        Largest step of the fixed-step methods (between output times the steps are equal).
    order : {2, 4, 6}
        Order of the splitting method (default 4).
    rtol, atol : float
        Tolerances of ``dop853`` (atol defaults to ``rtol * |omega0|``; with rotors, ``rtol``
        times the largest of ``|omega0|`` and the rotors' initial rates, a wheel's momentum
        taking ``J atol``).
    torque : polhode.torque model or callable, optional
        See :mod:`polhode.torque`.
    rotors : sequence of polhode.rotors rotors, optional
        Reaction wheels and spherical dampers inside the body (each body of a batch has the
        same), in the body's own axes; see :mod:`polhode.rotors`. The body's inertia includes
        them, locked. Integrated by ``dop853`` (``auto``) or ``rk4``: each rotor's rate is
        returned in ``rotor_rates``, and the angular momentum and energy are the totals, rotors
        included (conserved without external torque and damping; a damper lowers the energy at
        fixed angular momentum). A wheel driven by a Python function runs the bodies one after
        another.
    orientation : bool
        Integrate the orientation (default True). False integrates omega alone (cheaper) unless
        the torque depends on the orientation; the trajectory then has no quaternion.
    progress : bool or callable
        True shows a tqdm progress bar on stderr (tqdm is optional: ``pip install tqdm`` or
        the ``progress`` extra; without it True raises ImportError). A callable is called with
        the fraction done, in [0, 1] and non-decreasing (the time integrated over all bodies'
        spans), from the calling thread every 50 ms of a long run and with 1.0 at the end; an
        exception it raises stops the run and propagates. Default False.

        Whatever ``progress`` is, Ctrl-C interrupts a long run (single or batch) with
        KeyboardInterrupt within about 50 ms plus the time of a few thousand steps; watching
        costs the integration nothing measurable. Ctrl-C reaches the main thread only: a run
        on another thread stops when :func:`polhode.cancel_all` is called, and raises
        :class:`polhode.CancelledError` there.

    Returns
    -------
    Trajectory

    Examples
    --------
    Five tennis-racket flips of I = (1, 2, 3) by the exact solution; the angular velocity at
    t = 100 agrees with a 30-digit reference (:data:`polhode.bench.REFERENCE`,
    0.009550413196755434, -1.0000043947942285, 0.009852417507542):

    >>> import numpy as np
    >>> import polhode as ph
    >>> sol = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], [0.0, 100.0])
    >>> [round(float(w), 12) for w in sol.omega[-1]]
    [0.009550413197, -1.000004394794, 0.009852417508]

    The same by the order-4 splitting: ``|L|`` and L in space kept to rounding, T to about
    1e-9:

    >>> from polhode.invariants import max_relative_drift
    >>> split = ph.simulate([1.0, 2.0, 3.0], [0.01, 1.0, 0.01], 100.0, method="splitting",
    ...                     dt=0.01)
    >>> drift = max_relative_drift(split)
    >>> bool(drift["angular_momentum_space"] < 1e-14), bool(drift["energy"] < 1e-9)
    (True, True)

    A body in its own axes, a torque, and a batch of four bodies sharing one Body:

    >>> bar = ph.Body.cuboid(1.0, [0.3, 0.1, 0.02])
    >>> push = ph.torque.BodyFixed([0.0, 0.0, 0.01])
    >>> ph.simulate(bar, [0.0, 0.0, 1.0], 2.0, torque=push).stats["method"]
    'dop853'
    >>> ph.simulate(bar, np.ones((4, 3)), np.linspace(0.0, 1.0, 11)).omega.shape
    (4, 11, 3)
    """
    started = time.perf_counter()
    if not isinstance(method, str):
        raise TypeError(f"Expected `method` to be a string, got {type(method).__name__}.")
    if progress is not False:
        _check_progress(progress)
    # A float or an int needs no conversion (what as_scalar and as_integer return for one):
    # a small call skips those calls for the defaults.
    if type(t0) is not float:
        t0 = as_scalar("t0", t0)
    times = _as_float_array("t", t)
    end = None
    if times.shape == (1,) and np.ndim(t) == 0:
        end = float(times[0])
        if not math.isfinite(end):
            shown = "NaN" if math.isnan(end) else f"{end}"
            raise NonFiniteError(f"Expected `t` to be finite, got {shown}.", argument="t")
        if end < t0 and math.isfinite(t0):
            # As the end time it is, not as t[1] of the times (t0, t) made of it.
            raise ArgumentError(
                f"Invalid `t`: expected an end time >= t0 = {t0:g}, got {end:g}.", argument="t"
            )
    elif times is t:
        # The trajectory's own times, not a view the caller may change afterwards.
        times = times.copy()
    omega = _as_float_array("omega0", omega0)
    rotors = None if rotors is None else as_rotors(rotors)
    if type(orientation) is not bool:
        orientation = as_flag("orientation", orientation)
    core_body = _body(body)
    start = None if orientation0 is None else _orientation0(orientation0)
    settings = _settings(t0, method, dt, order, rtol, atol, torque, rotors)
    sampling = None
    if end is not None:
        # An end time: output times that resolve the motion (polhode._sampling).
        rate = _core.fastest_rate(core_body, omega, end, orientation0=start, **settings)
        rate["dt"] = settings["dt"]
        times, sampling = resolving_times(
            t0, end, rate, None if omega.ndim == 1 else omega.shape[0]
        )
    # One body at up to 10^5 output times fits in _ALWAYS_FITS (see _ONE_BODY_FITS).
    if rotors is not None or omega.ndim != 1 or times.size > _ONE_BODY_FITS:
        _check_fits(omega, times, orientation, 0 if rotors is None else len(rotors))
    callback, bar = (None, None) if progress is False else _progress(progress)
    try:
        outputs = _core.simulate(
            core_body,
            omega,
            times,
            orientation0=start,
            orientation=orientation,
            max_steps=as_integer("max_steps", max_steps)
            + (0 if sampling is None else sampling["extra_steps"]),
            progress=callback,
            every_step=sampling is not None and sampling["every_step"],
            **settings,
        )
    finally:
        if bar is not None:
            bar.close()
    # The core returns every field by name, in order (``t`` is ``times``; ``stats`` lacks only
    # the wall time): the same object as ``Trajectory(**outputs)``, its fields set in one step
    # (a frozen dataclass's ``__init__`` sets each through ``object.__setattr__``).
    if sampling is not None:
        outputs["stats"]["sampling"] = sampling
    outputs["stats"]["wall_time"] = time.perf_counter() - started
    trajectory = object.__new__(Trajectory)
    trajectory.__dict__.update(outputs)
    if outputs["stats"]["method"] == "exact":
        # What the exact solution needs to be evaluated at other times (Trajectory.__call__):
        # the inputs, copied (the caller may change its arrays afterwards).
        if isinstance(core_body, np.ndarray):
            given = core_body.copy()
        else:  # a Body, or N of them: as given (simulate takes them again)
            given = list(body) if isinstance(body, list | tuple) else body
        object.__setattr__(trajectory, "_motion", _Motion(
            given,
            omega.copy(),
            None if start is None else start.copy(),
            t0,
            orientation,
        ))
    return trajectory
