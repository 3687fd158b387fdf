"""Motion: Euler's equations with orientation, by the exact solution or an integrator."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from polhode import _core
from polhode._coerce import as_integer, as_scalar, check_rotation_matrices
from polhode.bodies import Body
from polhode.principal_axes import principal
from polhode.torque import Gravity, Torque, as_torque

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = ["Trajectory", "simulate"]

METHODS = ("auto", "exact", "splitting", "midpoint", "rk4", "dop853")


@dataclass(frozen=True)
class Trajectory:
    """The motion at the requested times.

    A batch keeps its leading N: ``omega`` is (N, M, 3) for N bodies, (M, 3) for one.

    Attributes
    ----------
    t : (M,) numpy.ndarray
        Output times.
    omega : (..., M, 3) numpy.ndarray
        Angular velocity in body axes.
    quaternion : (..., M, 4) numpy.ndarray or None
        Body-to-space orientation, scalar-last (x, y, z, w); None with ``orientation=False``.
    angular_momentum : (..., M, 3) numpy.ndarray or None
        Angular momentum in space axes (conserved without torque); None without orientation.
    angular_momentum_body : (..., M, 3) numpy.ndarray
        Angular momentum in body axes.
    energy : (..., M) numpy.ndarray
        Rotational kinetic energy.
    moments : (..., 3) numpy.ndarray
        The principal moments the motion was integrated with (about the pivot for a heavy top).
    stats : dict
        ``steps``, ``rejected_steps``, ``evaluations`` (per body), ``wall_time`` (s), ``method``.
    """

    t: NDArray[np.float64]
    omega: NDArray[np.float64]
    quaternion: NDArray[np.float64] | None
    angular_momentum: NDArray[np.float64] | None
    angular_momentum_body: NDArray[np.float64]
    energy: NDArray[np.float64]
    moments: NDArray[np.float64]
    stats: dict[str, Any]

    @property
    def orientation(self) -> Rotation | list[Rotation] | None:
        """Body-to-space orientation as a scipy Rotation of M rotations (a list for a batch)."""
        from scipy.spatial.transform import Rotation

        if self.quaternion is None:
            return None
        if self.quaternion.ndim == 2:
            return Rotation.from_quat(self.quaternion)
        return [Rotation.from_quat(q) for q in self.quaternion]


def _as_float_array(name: str, value: Any) -> NDArray[np.float64]:
    if value is None or isinstance(value, str | bytes):
        raise TypeError(f"Expected `{name}` to be an array of numbers, got {type(value).__name__}.")
    try:
        return np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise TypeError(
            f"Expected `{name}` to be an array of numbers, got {type(value).__name__}."
        ) from error


def _shape(shape: tuple[int, ...]) -> str:
    return f"({shape[0]},)" if len(shape) == 1 else "(" + ", ".join(map(str, shape)) + ")"


_IDENTITY = np.eye(3)
_IDENTITY.flags.writeable = False
_NO_ROTATION = np.array([[0.0, 0.0, 0.0, 1.0]])
_NO_ROTATION.flags.writeable = False


def _resolve_body(
    body: Any, gravity: Gravity | None
) -> tuple[NDArray[np.float64], NDArray[np.float64], bool]:
    """Principal moments (N, 3), the principal axes of a single body (3, 3) and whether the
    input was a batch. A heavy top is integrated about its pivot."""
    if isinstance(body, Body):
        if gravity is not None:
            pivot = np.zeros(3) if gravity.pivot is None else gravity.pivot
            p = principal(body.inertia_about(pivot))
            r_cm = body.center_of_mass - pivot
            gravity._resolved = (body.mass, r_cm)
        else:
            p = body.principal()
        return p.moments[None, :], p.axes, False
    array = _as_float_array("body", body)
    if array.shape == (3,):
        return array[None, :], _IDENTITY, False
    if array.shape == (3, 3):
        p = principal(array)
        return p.moments[None, :], p.axes, False
    if array.ndim == 2 and array.shape[1] == 3:
        return array, _IDENTITY, True
    raise _core.PolhodeError(
        "Expected `body` to be a polhode.Body, principal moments (3,), an inertia tensor (3, 3) "
        f"or a batch of principal moments (N, 3), got shape {_shape(array.shape)}."
    )


def _times(t: Any, t0: float) -> NDArray[np.float64]:
    times = _as_float_array("t", t)
    if np.ndim(t) == 0:
        times = np.array([t0, float(times.reshape(-1)[0])])
    if times.ndim != 1 or times.size == 0:
        raise _core.PolhodeError(
            "Expected `t` to be an end time or output times of shape (M,), "
            f"got {_shape(times.shape)}."
        )
    if not np.isfinite(times).all():
        raise _core.PolhodeError(f"Expected `t` to be finite, got {times[~np.isfinite(times)][0]}.")
    decreasing = times[1:] < times[:-1]
    if decreasing.any():
        k = int(np.argmax(decreasing))
        raise _core.PolhodeError(
            f"Expected `t` to be non-decreasing, got t[{k}] = {times[k]} > "
            f"t[{k + 1}] = {times[k + 1]}."
        )
    if times[0] < t0:
        raise _core.PolhodeError(
            f"Expected every output time `t` >= t0 = {t0} (the initial time), got {times[0]}."
        )
    return times


def _orientation(orientation0: Any, n: int) -> NDArray[np.float64]:
    """Initial body-to-space quaternions (n, 4), xyzw."""
    from scipy.spatial.transform import Rotation

    if orientation0 is None:
        return _NO_ROTATION if n == 1 else np.tile(_NO_ROTATION, (n, 1))
    if isinstance(orientation0, Rotation):
        q = orientation0.as_quat().reshape(-1, 4)
    else:
        array = _as_float_array("orientation0", orientation0)
        if not np.all(np.isfinite(array)):
            raise _core.PolhodeError("Expected `orientation0` to be finite.")
        if array.shape[-2:] == (3, 3) and array.ndim <= 3:
            check_rotation_matrices("orientation0", array)
            q = Rotation.from_matrix(array).as_quat().reshape(-1, 4)
        elif array.shape[-1:] == (4,) and array.ndim <= 2:
            norms = np.linalg.norm(array.reshape(-1, 4), axis=1)
            if np.any(norms == 0):
                raise _core.PolhodeError("Expected `orientation0` to be a non-zero quaternion.")
            q = array.reshape(-1, 4) / norms[:, None]
        else:
            raise _core.PolhodeError(
                "Expected `orientation0` to be a scipy Rotation, a (3, 3) matrix or an "
                f"(x, y, z, w) quaternion (or N of them), got shape {_shape(array.shape)}."
            )
    if q.shape[0] == 1:
        q = np.tile(q, (n, 1))
    if q.shape[0] != n:
        raise _core.PolhodeError(
            f"Expected `orientation0` to hold 1 or {n} rotations, got {q.shape[0]}."
        )
    return np.ascontiguousarray(q)


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
    max_steps: int = 100_000_000,
    progress: bool | Callable[[float], object] = False,
) -> Trajectory:
    """The rotation of a rigid body (or a batch), torque-free or with a torque.

    Parameters
    ----------
    body : Body, (3,) moments, (3, 3) tensor, or (N, 3) principal moments of N bodies
        A body in non-principal axes is integrated in principal axes and reported back in its
        own axes. Every principal moment must be positive (Euler's equations need I^-1).
    omega0 : (3,) or (N, 3) array_like
        Initial angular velocity in body axes at ``t0``; one row is shared by all N bodies.
    t : float or (M,) array_like
        Output times (non-decreasing, >= t0), or an end time (outputs at t0 and t).
    orientation0 : optional
        Initial body-to-space orientation: scipy Rotation, (3, 3) matrix, xyzw quaternion, or N
        of them (default identity).
    method : {"auto", "exact", "splitting", "midpoint", "rk4", "dop853"}
        ``auto`` is ``exact`` (the closed form: no steps, O(1) per output time) without a torque
        and ``dop853`` with one. ``splitting`` (Lie-Poisson, symplectic; |L| and L in space
        exact), ``midpoint`` (implicit; T and |L| exact) and ``rk4`` take a fixed ``dt``.
    dt : float, optional
        Largest step of the fixed-step methods (between output times the steps are equal).
    order : {2, 4, 6}
        Order of the splitting method (default 4).
    rtol, atol : float
        Tolerances of ``dop853`` (atol defaults to ``rtol * |omega0|``).
    torque : polhode.torque model or callable, optional
        See :mod:`polhode.torque`.
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
        costs the integration nothing measurable.

    Returns
    -------
    Trajectory
    """
    started = time.perf_counter()
    if not isinstance(method, str):
        raise TypeError(f"Expected `method` to be a string, got {type(method).__name__}.")
    if method not in METHODS:
        raise _core.PolhodeError(
            f"Expected `method` to be one of {', '.join(map(repr, METHODS))}, got {method!r}."
        )
    _check_progress(progress)
    torque_model: Torque | None = None if torque is None else as_torque(torque)
    gravity = None if torque_model is None else torque_model._gravity()
    moments, axes, batch = _resolve_body(body, gravity)
    if not np.isfinite(moments).all():
        raise _core.PolhodeError("Expected the principal moments of `body` to be finite.")
    if (moments <= 0).any():
        raise _core.PolhodeError(
            "Expected `body` to have positive principal moments (Euler's equations need I^-1; "
            f"a rod or a point mass has a zero moment), got {moments[moments <= 0][0]}."
        )
    omega = _as_float_array("omega0", omega0)
    if omega.shape not in ((3,),) and not (omega.ndim == 2 and omega.shape[1] == 3):
        raise _core.PolhodeError(
            f"Expected `omega0` to have shape (3,) or (N, 3), got {_shape(omega.shape)}."
        )
    if not np.isfinite(omega).all():
        raise _core.PolhodeError(f"Expected `omega0` to be finite, got {omega.tolist()}.")
    batch = batch or omega.ndim == 2
    omega2 = omega.reshape(-1, 3)
    n = max(moments.shape[0], omega2.shape[0])
    if moments.shape[0] not in (1, n) or omega2.shape[0] not in (1, n):
        raise _core.PolhodeError(
            f"Expected `omega0` to have shape (3,) or ({moments.shape[0]}, 3) to match `body`, "
            f"got {_shape(omega.shape)}."
        )
    if moments.shape[0] != n:
        moments = np.ascontiguousarray(np.broadcast_to(moments, (n, 3)))
    omega_body0 = omega2 if omega2.shape[0] == n else np.tile(omega2, (n, 1))
    t0 = as_scalar("t0", t0)
    if not math.isfinite(t0):
        raise _core.PolhodeError(f"Expected `t0` to be finite, got {t0}.")
    order = as_integer("order", order, allowed=(2, 4, 6))
    max_steps = as_integer("max_steps", max_steps, minimum=1)
    identity = axes is _IDENTITY
    omega_p0 = omega_body0 if identity else omega_body0 @ axes
    energy0 = 0.5 * np.sum(moments * omega_p0**2, axis=1)
    if not np.isfinite(energy0).all():
        raise _core.PolhodeError(
            "Expected `omega0` and the moments of `body` to give a finite kinetic energy; "
            "it overflows double precision."
        )
    times = _times(t, t0)
    if dt is not None:
        dt = as_scalar("dt", dt)
        if not (math.isfinite(dt) and dt > 0):
            raise _core.PolhodeError(f"Expected `dt` to be positive and finite, got {dt}.")
    rtol = as_scalar("rtol", rtol)
    if not (math.isfinite(rtol) and rtol > 0):
        raise _core.PolhodeError(f"Expected `rtol` to be positive and finite, got {rtol}.")
    if atol is not None:
        atol = as_scalar("atol", atol)
        if not (math.isfinite(atol) and atol > 0):
            raise _core.PolhodeError(f"Expected `atol` to be positive and finite, got {atol}.")
    if method == "auto":
        method = "exact" if torque_model is None else "dop853"
    q_body0 = _orientation(orientation0, n)
    spec = None if torque_model is None else torque_model._spec(axes)
    callback, bar = _progress(progress)
    try:
        # The core converts to principal axes and back, and computes L and T (in parallel).
        omega_body, quaternion, l_space, l_body, energy, stats = _core.simulate(
            moments,
            omega_body0,
            q_body0,
            times,
            t0=t0,
            method=method,
            dt=dt,
            order=order,
            rtol=rtol,
            atol=atol,
            torque=spec,
            with_attitude=bool(orientation),
            max_steps=max_steps,
            progress=callback,
            axes=None if identity else np.ascontiguousarray(axes),
        )
    finally:
        if bar is not None:
            bar.close()
    info = {
        "method": method,
        "steps": stats[:, 0],
        "rejected_steps": stats[:, 1],
        "evaluations": stats[:, 2],
        "wall_time": time.perf_counter() - started,
    }
    if not batch:
        info.update({k: int(v[0]) for k, v in info.items() if isinstance(v, np.ndarray)})

    def pick(array: Any) -> Any:
        """A batch keeps its leading N; a single body drops it."""
        return array if batch or array is None else array[0]

    return Trajectory(
        t=times,
        omega=pick(omega_body),
        quaternion=pick(quaternion),
        angular_momentum=pick(l_space),
        angular_momentum_body=pick(l_body),
        energy=pick(energy),
        moments=pick(moments),
        stats=info,
    )
