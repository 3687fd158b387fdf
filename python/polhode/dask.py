"""Sweeps over many bodies with Dask: :func:`simulate` and :func:`analyze` chunk by chunk.

The bodies (rows of ``body`` and ``omega0``) are split into blocks along N; each block is one
task that calls :func:`polhode.simulate` (or :func:`polhode.analyze` row by row) on its rows, so
the same code runs on a laptop (the threaded scheduler) or on a ``dask.distributed`` cluster, and
gives the same numbers bit for bit as one call on the whole batch: every body is integrated on
its own. Within a block :func:`polhode.simulate` uses all the cores of its worker.

On one machine whose memory holds the result, :func:`polhode.simulate` on the (N, 3) batch is
simpler and at least as fast; use this module when the sweep outgrows one machine's memory or
cores (``pip install 'polhode[dask]'``). ``import polhode`` never imports dask.

Results are lazy: each array of a :class:`DaskTrajectory` or :class:`DaskAnalysis` is a field of
one dask array of per-body records, so ``dask.compute(traj.omega, traj.energy)`` runs every
block once, and ``.compute()`` gives the numpy result in one pass.

Ctrl-C stops the blocks that are running, not only the wait for them. Python raises
KeyboardInterrupt in the main thread only, while the blocks run in dask's worker threads; so a
compute that ends in KeyboardInterrupt calls :func:`polhode.cancel_all`, and every polhode call
running in this process stops within milliseconds (raising :class:`polhode.CancelledError` in
its worker thread, where nobody waits for it). This holds for any compute on dask's local
schedulers (``dask.compute(traj.omega)`` included: importing this module registers a dask
callback that does nothing else), and for ``.compute()`` and ``.persist()`` of
:class:`DaskTrajectory` and :class:`DaskAnalysis` on a ``dask.distributed`` client, where it
also runs :func:`polhode.cancel_all` on every worker.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

try:
    import dask
    import dask.array as da
except ImportError as error:  # pragma: no cover - exercised only without the extra
    raise ImportError(
        "polhode.dask needs dask: pip install 'polhode[dask]' (dask[array] and distributed)."
    ) from error

from dask.callbacks import Callback

from polhode import _core, analysis, simulation
from polhode import _dask_inputs as _inputs
from polhode._coerce import as_integer, as_scalar
from polhode._fields import Fields
from polhode._quantities import attribute_docs
from polhode._sampling import resolving_times
from polhode.errors import ArgumentError, CancelledError, PolhodeError, ShapeError
from polhode.rotors import as_rotors
from polhode.simulation import OUTPUTS, Trajectory

__all__ = ["DaskAnalysis", "DaskTrajectory", "analyze", "simulate"]

#: One body's record must fit numpy's limit on an item (a C int of bytes).
_MAX_RECORD_BYTES = 2**31 - 1
#: Width of the string fields of :class:`DaskAnalysis` (the longest regime has 19 characters).
_REGIME_WIDTH = 32
#: Bodies an analyze block runs between two looks for :func:`polhode.cancel_all` (~5 ms).
_ANALYZE_LOOK_EVERY = 256

_T = TypeVar("_T")


# -------------------------------------------------------------------------------------------------
# Ctrl-C: stop the blocks, not only the wait
# -------------------------------------------------------------------------------------------------


class _CancelOnInterrupt(Callback):  # type: ignore[misc]
    """On dask's local schedulers: a compute that ends in KeyboardInterrupt cancels the polhode
    calls still running in its worker threads (see the module's docstring)."""

    def _finish(self, dsk: Any, state: Any, errored: bool) -> None:
        # Called from the scheduler's `finally`: the exception on its way out is visible here.
        if errored and isinstance(sys.exc_info()[1], KeyboardInterrupt):
            _core.cancel_all()


_CancelOnInterrupt().register()


def _distributed_client(scheduler: Any, collections: tuple[Any, ...]) -> Any:
    """The dask.distributed client that a compute with ``scheduler`` runs on, or None."""
    if "distributed" not in sys.modules:
        return None
    from distributed import Client

    if isinstance(scheduler, Client):
        return scheduler
    try:
        get = dask.base.get_scheduler(scheduler=scheduler, collections=list(collections))
    except Exception:  # no client where one was asked for: not ours to report here
        return None
    client = getattr(get, "__self__", None)
    return client if isinstance(client, Client) else None


def _interruptible(run: Callable[..., _T], *collections: Any, **kwargs: Any) -> _T:
    """``run(*collections, **kwargs)`` (dask.compute or dask.persist); on KeyboardInterrupt,
    :func:`polhode.cancel_all` here and, on a distributed client, on every worker."""
    try:
        return run(*collections, **kwargs)
    except KeyboardInterrupt:
        _core.cancel_all()
        client = _distributed_client(kwargs.get("scheduler"), collections)
        if client is not None:
            try:
                client.run(_core.cancel_all)
            except Exception:  # a cluster already gone: nothing runs there any more
                pass
        raise


@dataclass(frozen=True, eq=False)
class DaskTrajectory(Fields[da.Array]):
    """The motion of N bodies as lazy dask arrays, chunked along N like the input.

    Attributes
    ----------
    t : (M,) numpy.ndarray
        Output times (s).
{quantities}
    moments : (N, 3) dask.array.Array
        Principal moments.
    steps, rejected_steps, evaluations : (N,) dask.array.Array of uint64
        Per-body cost, as in ``Trajectory.stats``.
    method : str
        The method used (``"auto"`` resolved).
    records : (N,) dask.array.Array
        The per-body records every array above is a field of (structured dtype).
    sampling : dict or None
        For an end time ``t``: how the output times were chosen, as in ``Trajectory.stats``
        (see :func:`simulate`); None for times given as an array.
    single : bool
        One body's trajectory, ``sweep[k]``: its arrays without the leading N.

    ``len(sweep)`` is N and ``sweep[k]``, ``sweep[a:b]``, an index array or a boolean mask pick
    bodies lazily, as numpy indexes the leading axis.

    The quantities are those of :class:`polhode.Trajectory` (the core's table), each with the
    leading N.

    Examples
    --------
    >>> import numpy as np
    >>> import polhode.dask as phd
    >>> sweep = phd.simulate(np.ones((4, 3)) * [1.0, 2.0, 3.0], np.eye(4, 3), [0.0, 1.0])
    >>> sweep.method, sweep.energy.shape
    ('exact', (4, 2))
    >>> sweep.energy[:, 0].compute().tolist()  # T = I w^2 / 2 about each axis, 0 for the last
    [0.5, 1.0, 1.5, 0.0]
    """

    moments: da.Array
    steps: da.Array
    rejected_steps: da.Array
    evaluations: da.Array
    method: str
    records: da.Array
    sampling: dict[str, Any] | None = None
    single: bool = False

    def __len__(self) -> int:
        """The number of bodies N (TypeError for one body's: ``sweep[k]``)."""
        if self.single:
            raise TypeError("len() of one body's DaskTrajectory: it is no batch.")
        return int(self.records.shape[0])

    def __getitem__(self, key: Any) -> DaskTrajectory:
        """Bodies of the batch, lazily, as numpy indexes its leading axis: ``sweep[k]`` (an
        integer) is body k's trajectory (its arrays without the leading N; ``.compute()`` is
        the :class:`polhode.Trajectory` of that body simulated alone at ``t``), ``sweep[a:b]``,
        a list or array of indices or a boolean mask (numpy) a batch of those bodies."""
        n = len(self)
        if isinstance(key, int | np.integer) and not isinstance(key, bool | np.bool_):
            if not -n <= int(key) < n:
                raise IndexError(f"body {int(key)} is out of range for a batch of {n} bodies.")
            k = int(key) % n
            return _trajectory(self.records[k : k + 1], self.t, self.method, self.sampling, True)
        if not isinstance(key, slice):
            key = np.asarray(key)
            if key.ndim != 1 or key.dtype.kind not in "biu":
                raise TypeError(
                    "Expected a body's index, a slice, or a 1-D array of indices or of bools to "
                    f"index a batch DaskTrajectory, got {type(key).__name__}."
                )
            np.zeros(n)[key]  # numpy's IndexError for an index out of range or a bad mask
        return _trajectory(self.records[key], self.t, self.method, self.sampling)

    def compute(self, **kwargs: Any) -> Trajectory:
        """Run every block once and return the batch :class:`polhode.Trajectory` (numpy).

        Keywords go to :func:`dask.compute` (e.g. ``scheduler="threads"``). ``stats["wall_time"]``
        is the wall time of this call.
        """
        started = time.perf_counter()
        (records,) = _interruptible(dask.compute, self.records, **kwargs)

        def field(name: str) -> Any:
            if name not in records.dtype.names:
                return None
            value = records[name][0] if self.single else records[name]
            return np.ascontiguousarray(value)

        stats = {
            "method": self.method,
            "steps": field("steps"),
            "rejected_steps": field("rejected_steps"),
            "evaluations": field("evaluations"),
        }
        if self.single:  # one body's costs as numbers, as polhode.simulate gives them
            for name in ("steps", "rejected_steps", "evaluations"):
                stats[name] = int(records[name][0])
        if self.sampling is not None:
            stats["sampling"] = dict(self.sampling)
        stats["wall_time"] = time.perf_counter() - started
        return Trajectory(t=self.t, stats=stats, **{name: field(name) for name in OUTPUTS})

    def persist(self, **kwargs: Any) -> DaskTrajectory:
        """The same trajectory with its blocks computed and kept in (cluster) memory."""
        (records,) = _interruptible(dask.persist, self.records, **kwargs)
        return _trajectory(records, self.t, self.method, self.sampling, self.single)


DaskTrajectory.__doc__ = (DaskTrajectory.__doc__ or "").replace(
    "{quantities}", attribute_docs("dask.array.Array", lead="N")
)


@dataclass(frozen=True)
class DaskAnalysis:
    """:func:`polhode.analyze` of N bodies, one entry per body (dask or, computed, numpy arrays).

    ``None`` in :class:`polhode.Analysis` (no period, no flips, no precession) is NaN here; the
    ``linearized`` dict is split into ``linearized_axis``, ``linearized_kind`` and
    ``linearized_rate``.

    Attributes
    ----------
    moments, omega : (N, 3)
        Principal moments ascending, and the initial angular velocity in those axes.
    energy, angular_momentum_norm : (N,)
        T and ``|L|``.
    regime : (N,) str
    period, flip_interval, precession_rate_body, precession_rate_space : (N,) float, NaN where
        not defined
    nutation_angle : (N, 2) float, (min, max); NaN where not defined
    axis_stability : (N, 3) str
    linearized_axis : (N,) int64
    linearized_kind : (N,) str
    linearized_rate : (N,) float
    nutation_rate, nutation_time_constant : (N,) float
        With ``rotors=[damper]``, the damper's rate and time constant; NaN where not defined
        (without a damper, and as in :class:`polhode.Analysis`).

    ``len(result)`` is N; ``result[k]``, ``result[a:b]``, an index array or a boolean mask pick
    bodies, as numpy indexes the leading axis (lazily before ``.compute()``).

    Examples
    --------
    >>> import numpy as np
    >>> import polhode.dask as phd
    >>> omega0 = [[1.0, 0.01, 0.01], [0.01, 1.0, 0.01], [0.01, 0.01, 1.0]]
    >>> result = phd.analyze([1.0, 2.0, 3.0], omega0).compute()
    >>> result.regime.tolist()
    ['about_smallest_axis', 'about_largest_axis', 'about_largest_axis']
    >>> result.linearized_kind.tolist()
    ['oscillation', 'growth', 'oscillation']
    """

    moments: Any
    omega: Any
    energy: Any
    angular_momentum_norm: Any
    regime: Any
    period: Any
    flip_interval: Any
    precession_rate_body: Any
    precession_rate_space: Any
    nutation_angle: Any
    axis_stability: Any
    linearized_axis: Any
    linearized_kind: Any
    linearized_rate: Any
    nutation_rate: Any
    nutation_time_constant: Any

    def __len__(self) -> int:
        """The number of bodies N (TypeError for one body's, ``result[k]``)."""
        if np.ndim(self.energy) == 0:
            raise TypeError("len() of one body's DaskAnalysis: it is no batch.")
        return int(np.shape(self.energy)[0])

    def __getitem__(self, key: Any) -> DaskAnalysis:
        """Bodies of the batch, as numpy indexes its leading axis (lazily for dask arrays):
        ``result[k]`` is body k's analysis (each entry without the leading N: what
        :func:`polhode.analyze` gives for that body, None as NaN), ``result[a:b]``, a list or
        array of indices or a boolean mask (numpy) the analyses of those bodies."""
        n = len(self)
        if isinstance(key, int | np.integer) and not isinstance(key, bool | np.bool_):
            if not -n <= int(key) < n:
                raise IndexError(f"body {int(key)} is out of range for a batch of {n} bodies.")
            key = int(key) % n
        elif not isinstance(key, slice):
            key = np.asarray(key)
            if key.ndim != 1 or key.dtype.kind not in "biu":
                raise TypeError(
                    "Expected a body's index, a slice, or a 1-D array of indices or of bools to "
                    f"index a batch DaskAnalysis, got {type(key).__name__}."
                )
            np.zeros(n)[key]  # numpy's IndexError for an index out of range or a bad mask
        return DaskAnalysis(*(getattr(self, f.name)[key] for f in fields(self)))

    def compute(self, **kwargs: Any) -> DaskAnalysis:
        """The same analysis with numpy arrays (every block runs once)."""
        values = _interruptible(
            dask.compute, *(getattr(self, f.name) for f in fields(self)), **kwargs
        )
        return DaskAnalysis(
            *(np.asarray(v) if np.ndim(v) == 0 else np.ascontiguousarray(v) for v in values)
        )


# -------------------------------------------------------------------------------------------------
# simulate
# -------------------------------------------------------------------------------------------------


def _record_dtype(dry: Trajectory) -> np.dtype[Any]:
    m = dry.t.shape[0]
    items: list[tuple[str, Any, tuple[int, ...]]] = []
    for name in OUTPUTS:
        value = getattr(dry, name)
        if value is not None:
            items.append((name, value.dtype, tuple(value.shape[1:])))
    for name in ("steps", "rejected_steps", "evaluations"):
        items.append((name, dry.stats[name].dtype, ()))
    size = sum(np.dtype(t).itemsize * int(np.prod(s)) for _, t, s in items)
    if size > _MAX_RECORD_BYTES:
        raise ShapeError(
            f"Expected fewer output times `t` for polhode.dask: one body's trajectory at {m} "
            f"times takes {size} bytes, over numpy's limit of {_MAX_RECORD_BYTES} per record; "
            "split `t` into several runs.",
            argument="t",
        )
    return np.dtype(items)


def _simulate_block(
    rows: NDArray[np.int64],
    moments: NDArray[np.float64],
    omega0: NDArray[np.float64],
    *rest: Any,
    t: Any,
    record_dtype: np.dtype[Any],
    options: dict[str, Any],
    stack: bool = False,
) -> NDArray[Any]:
    options = _with_orientations(options, rest, stack)
    try:
        traj = simulation.simulate(moments, omega0, t, **options)
    except PolhodeError as error:
        raise _inputs.in_block(error, rows) from error
    records = np.empty(moments.shape[0], dtype=record_dtype)
    for name in record_dtype.names or ():
        records[name] = traj.stats[name] if name in traj.stats else getattr(traj, name)
    return records


def _with_orientations(
    options: dict[str, Any], rest: tuple[Any, ...], stack: bool
) -> dict[str, Any]:
    """A block's options with its bodies' orientations (``rest``: one per body, when given);
    ``stack``: they are the quaternions of the caller's Rotation, taken as they are (from_quat
    would normalize them again and change the last bits)."""
    if not rest:
        return options
    orientation0 = rest[0]
    if stack:
        from scipy.spatial.transform import Rotation

        orientation0 = Rotation(orientation0, normalize=False)
    return {**options, "orientation0": orientation0}


#: One block's fastest body (polhode._core.fastest_rate over its rows).
_RATE_DTYPE = np.dtype([("rate", np.float64), ("body", np.int64), ("pace", "U16")])


def _rate_block(
    rows: NDArray[np.int64],
    moments: NDArray[np.float64],
    omega0: NDArray[np.float64],
    *rest: Any,
    t_end: float,
    options: dict[str, Any],
    stack: bool = False,
) -> NDArray[Any]:
    """The fastest rate of a block's bodies, its body numbered in the whole batch: one record."""
    options = _with_orientations(options, rest, stack)
    try:
        rate = simulation.fastest_rate(moments, omega0, t_end, **options)
    except PolhodeError as error:
        raise _inputs.in_block(error, rows) from error
    found = np.empty(1, dtype=_RATE_DTYPE)
    found[0] = (rate["rate"], rows[rate["body"]] if rows.size else 0, rate["pace"])
    return found


def _end_time_grid(
    end: float, args: list[Any], n: int, options: dict[str, Any], stack: bool
) -> tuple[NDArray[np.float64], dict[str, Any]]:
    """The output times polhode.simulate takes for the end time ``end`` and the whole batch
    (polhode._sampling), from the fastest rate of each block's bodies (read once, no steps)."""
    rate = simulation.fastest_rate(np.zeros((0, 3)), np.zeros((0, 3)), end, **options)
    if n:
        blocks = da.blockwise(
            _rate_block,
            "i",
            *args,
            concatenate=True,
            adjust_chunks={"i": 1},
            token="polhode-fastest-rate",
            dtype=_RATE_DTYPE,
            meta=np.empty((0,), dtype=_RATE_DTYPE),
            t_end=end,
            options=options,
            stack=stack,
        )
        (found,) = _interruptible(dask.compute, blocks)
        # The first of the fastest, as the core picks over one batch.
        for block in found:
            if block["rate"] > rate["rate"]:
                rate.update(rate=float(block["rate"]), body=int(block["body"]))
                rate["pace"] = str(block["pace"])
    return resolving_times(as_scalar("t0", options.get("t0", 0.0)), end, rate, n)


def _field(records: da.Array, name: str) -> da.Array:
    """One field of the (N,) records as an (N, ...) dask array (a view of each block)."""
    base, shape = records.dtype[name].base, records.dtype[name].shape
    return records.map_blocks(
        _get_field,
        name,
        token=f"polhode-{name}",
        chunks=(records.chunks[0], *((d,) for d in shape)),
        new_axis=list(range(1, 1 + len(shape))) or None,
        dtype=base,
        meta=np.empty((0,) * (1 + len(shape)), dtype=base),
    )


def _get_field(records: NDArray[Any], name: str) -> NDArray[Any]:
    return records[name]


def _trajectory(
    records: da.Array,
    t: NDArray[np.float64],
    method: str,
    sampling: dict[str, Any] | None = None,
    single: bool = False,
) -> DaskTrajectory:
    """The trajectory of the bodies of ``records``; ``single``: of the one body it holds, its
    arrays without the leading N."""
    names = records.dtype.names or ()

    def field(name: str) -> da.Array | None:
        if name not in names:
            return None
        return _field(records, name)[0] if single else _field(records, name)

    return DaskTrajectory(
        t=t,
        **{name: field(name) for name in OUTPUTS},
        steps=field("steps"),
        rejected_steps=field("rejected_steps"),
        evaluations=field("evaluations"),
        method=method,
        records=records,
        sampling=sampling,
        single=single,
    )


def simulate(
    body: Any,
    omega0: Any,
    t: Any,
    *,
    orientation0: Any = None,
    chunks: int | None = None,
    rotors: Any = None,
    **options: Any,
) -> DaskTrajectory:
    """:func:`polhode.simulate` of N bodies, block by block along N (lazy).

    Parameters
    ----------
    body : (N, 3) or (3,) dask.array.Array or array_like
        Principal moments of each body (a (3,) row is shared by all).
    omega0 : (N, 3) dask.array.Array or array_like
        Initial angular velocity of each body, in principal axes: its rows set N.
    t : float or (M,) array_like
        Output times or an end time, as in :func:`polhode.simulate` (numpy, shared by all). An
        end time gives the output times ``polhode.simulate`` gives the whole batch (enough to
        resolve its fastest body's motion: see ``Trajectory.stats["sampling"]``); to find them,
        this call reads the inputs once, block by block (the fastest rate of each block's
        bodies at t0, no steps taken): with dask inputs, give ``t`` as an array to keep it from
        computing them.
    orientation0 : optional
        One orientation for every body (scipy Rotation, (3, 3) matrix, xyzw quaternion), or one
        per body: (N, 4) quaternions or (N, 3, 3) matrices (dask or numpy).
    chunks : int, optional
        Bodies per block. Default: the row chunks of the first dask input; for numpy inputs,
        blocks whose output is about dask's ``array.chunk-size`` (128 MiB).
    rotors : sequence of polhode.rotors rotors, optional
        The same wheels and dampers inside every body, as in :func:`polhode.simulate` (each
        body's moments include them, locked); the trajectory then has ``rotor_rates``, and its
        angular momentum and energy are the totals.
    **options
        Every other keyword of :func:`polhode.simulate` (``method``, ``dt``, ``order``, ``rtol``,
        ``atol``, ``torque``, ``t0``, ``orientation``, ``max_steps``).

    Returns
    -------
    DaskTrajectory
        Lazy (N, M, ...) arrays, always with the leading N; ``.compute()`` gives the
        :class:`polhode.Trajectory` that ``polhode.simulate`` returns for the whole batch, with
        identical numbers.

    Shapes, types, ``t`` and every keyword are checked at once, as are numpy values of
    ``body``, ``omega0`` and ``orientation0``; dask values are checked when their block runs
    (the error's ``body`` is the index in the whole batch).

    Examples
    --------
    >>> import dask.array as da
    >>> import numpy as np
    >>> import polhode as ph
    >>> import polhode.dask as phd
    >>> omega0 = da.from_array(np.outer(np.arange(1.0, 7.0), [0.01, 1.0, 0.01]), chunks=3)
    >>> sweep = phd.simulate([1.0, 2.0, 3.0], omega0, np.linspace(0.0, 10.0, 5))
    >>> sweep.omega.shape, sweep.omega.chunks[0]
    ((6, 5, 3), (3, 3))
    >>> sol = sweep.compute()
    >>> alone = ph.simulate([1.0, 2.0, 3.0], omega0.compute(), np.linspace(0.0, 10.0, 5))
    >>> bool(np.array_equal(sol.omega, alone.omega))  # the numbers of one call, bit for bit
    True

    The same damper inside every body: ``rotor_rates`` is a dask array too.

    >>> damper = ph.rotors.SphericalDamper(0.2, 0.1)
    >>> damped = phd.simulate([1.0, 4.0, 5.0], omega0, np.linspace(0.0, 10.0, 5),
    ...                       rotors=[damper])
    >>> damped.method, damped.rotor_rates.shape
    ('dop853', (6, 5, 1, 3))
    """
    moments = _inputs.as_input("body", body)
    omega0 = _inputs.as_input("omega0", omega0)
    n = _inputs.rows_of(moments, omega0)
    shared, per_body, stack = _inputs.orientation_input(orientation0, n)
    if rotors is not None:
        options = {**options, "rotors": as_rotors(rotors)}
    # The keywords and `t`: polhode.simulate on an empty batch checks them all for free.
    dry_orientation = shared if per_body is None else np.zeros((0, *per_body.shape[1:]))
    dry = simulation.simulate(
        np.zeros((0, 3)), np.zeros((0, 3)), t, orientation0=dry_orientation, **options
    )
    # Numpy values at once: each body at the initial time only (no steps).
    if any(isinstance(a, np.ndarray) for a in (moments, omega0, per_body)):
        t0 = options.get("t0", 0.0)
        per_body_now = per_body if isinstance(per_body, np.ndarray) and not stack else None
        rotors_now = options.get("rotors") if isinstance(moments, np.ndarray) else None
        simulation.simulate(
            moments if isinstance(moments, np.ndarray) else np.ones(3),
            omega0 if isinstance(omega0, np.ndarray) else np.zeros((n, 3)),
            [t0],
            orientation0=shared if per_body_now is None else per_body_now,
            t0=t0,
            # With rotors and numpy moments, that the rotors fit inside each body (dop853
            # takes no step to t0).
            method="dop853" if rotors_now else "exact",
            orientation=options.get("orientation", True),
            rotors=rotors_now,
        )
    block_options = options if per_body is not None else {**options, "orientation0": shared}

    def blocked(record_bytes: int) -> list[Any]:
        """The row indices and the inputs, in blocks of about dask's chunk size of output."""
        row_chunks = _inputs.row_chunks(chunks, n, record_bytes, moments, omega0, per_body)
        args: list[Any] = [
            da.arange(n, chunks=(row_chunks,)),
            "i",
            _inputs.blocked(moments, n, row_chunks),
            "ij",
            _inputs.blocked(omega0, n, row_chunks),
            "ij",
        ]
        if per_body is not None:
            args += [_inputs.blocked(per_body, n, row_chunks), "ikl"[: per_body.ndim]]
        return args

    sampling = None
    if np.ndim(t) == 0:
        # The output times of polhode.simulate for the whole batch: from the fastest body's
        # rate, which each block finds for its own (the inputs read once, no steps).
        t, sampling = _end_time_grid(
            float(dry.t[-1]), blocked(_record_dtype(dry).itemsize), n, block_options, stack
        )
        dry = simulation.simulate(
            np.zeros((0, 3)), np.zeros((0, 3)), t, orientation0=dry_orientation, **options
        )
        if sampling["extra_steps"]:
            # As polhode.simulate: max_steps bounds the steps of the run to the end time alone.
            most = as_integer("max_steps", options.get("max_steps", simulation.MAX_STEPS))
            block_options = {**block_options, "max_steps": most + sampling["extra_steps"]}
    dtype = _record_dtype(dry)
    args = blocked(dtype.itemsize)
    # Indices j, k, l (the columns) have one chunk each: concatenate hands over plain arrays.
    records = da.blockwise(
        _simulate_block,
        "i",
        *args,
        concatenate=True,
        token="polhode-simulate",
        dtype=dtype,
        meta=np.empty((0,), dtype=dtype),
        t=t,
        record_dtype=dtype,
        options=block_options,
        stack=stack,
    )
    return _trajectory(records, dry.t, dry.stats["method"], sampling)


# -------------------------------------------------------------------------------------------------
# analyze
# -------------------------------------------------------------------------------------------------

_ANALYSIS_DTYPE = np.dtype(
    [
        ("moments", np.float64, (3,)),
        ("omega", np.float64, (3,)),
        ("energy", np.float64),
        ("angular_momentum_norm", np.float64),
        ("regime", f"U{_REGIME_WIDTH}"),
        ("period", np.float64),
        ("flip_interval", np.float64),
        ("precession_rate_body", np.float64),
        ("precession_rate_space", np.float64),
        ("nutation_angle", np.float64, (2,)),
        ("axis_stability", f"U{_REGIME_WIDTH}", (3,)),
        ("linearized_axis", np.int64),
        ("linearized_kind", f"U{_REGIME_WIDTH}"),
        ("linearized_rate", np.float64),
        ("nutation_rate", np.float64),
        ("nutation_time_constant", np.float64),
    ]
)


def _analyze_block(
    rows: NDArray[np.int64],
    moments: NDArray[np.float64],
    omega0: NDArray[np.float64],
    *,
    rtol: float | None,
    rotors: Any,
) -> NDArray[Any]:
    records = np.empty(moments.shape[0], dtype=_ANALYSIS_DTYPE)
    # Many short calls, none long enough to be watched: the block looks for cancel_all itself.
    epoch = _core.cancel_epoch()
    for k in range(moments.shape[0]):
        if k % _ANALYZE_LOOK_EVERY == 0 and k and _core.cancel_epoch() != epoch:
            raise CancelledError("polhode.cancel_all() stopped this block.")
        try:
            a = analysis.analyze(moments[k], omega0[k], rtol, rotors=rotors)
        except PolhodeError as error:
            raise error.for_body(int(rows[k])) from error
        strings = (a.regime, a.linearized["kind"], *a.axis_stability)
        if max(map(len, strings)) > _REGIME_WIDTH:  # numpy would truncate silently
            raise AssertionError(f"polhode.dask: widen _REGIME_WIDTH for {strings}")
        records[k] = (
            a.moments,
            a.omega,
            a.energy,
            a.angular_momentum_norm,
            a.regime,
            np.nan if a.period is None else a.period,
            np.nan if a.flip_interval is None else a.flip_interval,
            np.nan if a.precession_rate_body is None else a.precession_rate_body,
            np.nan if a.precession_rate_space is None else a.precession_rate_space,
            (np.nan, np.nan) if a.nutation_angle is None else a.nutation_angle,
            a.axis_stability,
            a.linearized["axis"],
            a.linearized["kind"],
            a.linearized["rate"],
            np.nan if a.nutation_rate is None else a.nutation_rate,
            np.nan if a.nutation_time_constant is None else a.nutation_time_constant,
        )
    return records


def analyze(
    body: Any,
    omega0: Any,
    *,
    rtol: float | None = None,
    chunks: int | None = None,
    rotors: Any = None,
) -> DaskAnalysis:
    """:func:`polhode.analyze` of N bodies, block by block along N (lazy).

    ``body`` and ``omega0`` as in :func:`simulate` (``omega0`` (N, 3); ``body`` (N, 3) or a
    shared (3,) row; dask or numpy); ``rtol`` and ``rotors`` (the same in every body) as in
    :func:`polhode.analyze`. Each block
    analyzes its bodies one by one
    (Python per body, about 20 us), so spreading the blocks over processes pays off here even on
    one machine. ``chunks`` (bodies per block) as in :func:`simulate`.

    Returns
    -------
    DaskAnalysis

    Examples
    --------
    The flip interval goes as ``1/|omega|``: spun k times faster, the body flips k times as
    often.

    >>> import dask.array as da
    >>> import numpy as np
    >>> import polhode.dask as phd
    >>> omega0 = da.from_array(np.outer(np.arange(1.0, 7.0), [0.01, 1.0, 0.01]), chunks=3)
    >>> flips = phd.analyze([1.0, 2.0, 3.0], omega0).flip_interval.compute()
    >>> [round(float(f), 4) for f in flips * np.arange(1.0, 7.0)]
    [19.5529, 19.5529, 19.5529, 19.5529, 19.5529, 19.5529]
    """
    moments = _inputs.as_input("body", body)
    omega0 = _inputs.as_input("omega0", omega0)
    if rtol is not None:
        rtol = as_scalar("rtol", rtol)
        if not (np.isfinite(rtol) and rtol >= 0):
            raise ArgumentError(
                f"Expected `rtol` to be non-negative and finite, got {rtol}.", argument="rtol"
            )
    n = _inputs.rows_of(moments, omega0)
    rotors = None if rotors is None else as_rotors(rotors)
    if isinstance(moments, np.ndarray) and isinstance(omega0, np.ndarray):
        # Numpy values at once, as simulate checks them (no steps; the rotors inside each body).
        simulation.simulate(moments, omega0, [0.0], method="dop853" if rotors else "exact",
                         orientation=False, rotors=rotors)
    row_chunks = _inputs.row_chunks(chunks, n, _ANALYSIS_DTYPE.itemsize, moments, omega0)
    records = da.blockwise(
        _analyze_block,
        "i",
        da.arange(n, chunks=(row_chunks,)),
        "i",
        _inputs.blocked(moments, n, row_chunks),
        "ij",
        _inputs.blocked(omega0, n, row_chunks),
        "ij",
        concatenate=True,
        token="polhode-analyze",
        dtype=_ANALYSIS_DTYPE,
        meta=np.empty((0,), dtype=_ANALYSIS_DTYPE),
        rtol=rtol,
        rotors=rotors,
    )
    return DaskAnalysis(*(_field(records, f.name) for f in fields(DaskAnalysis)))
