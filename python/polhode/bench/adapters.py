"""The peers, called as their own users would call them: scipy's ``solve_ivp`` on Euler's
equations and the quaternion, a numpy structure-of-arrays RK4 over a batch of bodies, MuJoCo's
free body, numpy's point-mass inertia and trimesh's mesh integrals. What each returns is in
polhode's conventions: omega in body axes, the body-to-space orientation as a scalar-last
(x, y, z, w) quaternion.

scipy is a dependency; MuJoCo and trimesh are optional (the ``bench`` extra) and are imported
inside the functions that need them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: A call returning omega and the xyzw quaternion at the end time.
Runner = Callable[[], tuple[Array, Array]]


# --------------------------------------------------------------------------------------------
# scipy


def euler_rhs(moments: Sequence[float]) -> Callable[[float, Array], Array]:
    """Euler's equations and q' = q (0, omega) / 2 (xyzw), written as a user would in numpy."""
    i1, i2, i3 = moments
    a1, a2, a3 = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3

    def rhs(_t: float, y: Array) -> Array:
        w1, w2, w3, x, yq, z, s = y
        return 0.5 * np.array(
            [
                2.0 * a1 * w2 * w3,
                2.0 * a2 * w3 * w1,
                2.0 * a3 * w1 * w2,
                s * w1 + yq * w3 - z * w2,
                s * w2 + z * w1 - x * w3,
                s * w3 + x * w2 - yq * w1,
                -(x * w1 + yq * w2 + z * w3),
            ]
        )

    return rhs


def numpy_rk4(
    moments: Array, omega0: Array, steps: int, dt: float, orientation: bool = True
) -> tuple[Array, Array | None]:
    """N torque-free bodies by classic RK4 in numpy, structure of arrays (each component an
    (N,) array), from the identity orientation: ``steps`` steps of ``dt`` on Euler's equations and
    q' = q (0, omega) / 2, the quaternion renormalised at the end. The batch peer of
    :func:`polhode.bench.throughput`; returns omega (N, 3) and the xyzw quaternion (N, 4), or
    None without ``orientation``."""
    moments = np.asarray(moments, dtype=float)
    i1, i2, i3 = (np.ascontiguousarray(moments[:, k]) for k in range(3))
    c = ((i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3)
    n = len(i1)
    w = [np.array(omega0[:, k], dtype=float) for k in range(3)]
    q = [np.zeros(n), np.zeros(n), np.zeros(n), np.ones(n)]

    def rate(w: list[Array], q: list[Array]) -> tuple[list[Array], list[Array]]:
        a, b, cz = w
        dw = [c[0] * b * cz, c[1] * cz * a, c[2] * a * b]
        if not orientation:
            return dw, []
        x, y, z, s = q
        dq = [
            0.5 * (s * a + y * cz - z * b),
            0.5 * (s * b + z * a - x * cz),
            0.5 * (s * cz + x * b - y * a),
            -0.5 * (x * a + y * b + z * cz),
        ]
        return dw, dq

    def axpy(y: list[Array], k: list[Array], h: float) -> list[Array]:
        # Without the orientation, q is not integrated (k is empty).
        return [yi + h * ki for yi, ki in zip(y, k, strict=True)] if k else y

    half, sixth = 0.5 * dt, dt / 6.0
    for _ in range(steps):
        a1, b1 = rate(w, q)
        a2, b2 = rate(axpy(w, a1, half), axpy(q, b1, half))
        a3, b3 = rate(axpy(w, a2, half), axpy(q, b2, half))
        a4, b4 = rate(axpy(w, a3, dt), axpy(q, b3, dt))
        w = [
            wi + sixth * (k1 + 2.0 * (k2 + k3) + k4)
            for wi, k1, k2, k3, k4 in zip(w, a1, a2, a3, a4, strict=True)
        ]
        if orientation:
            q = [
                qi + sixth * (k1 + 2.0 * (k2 + k3) + k4)
                for qi, k1, k2, k3, k4 in zip(q, b1, b2, b3, b4, strict=True)
            ]
    omega = np.stack(w, axis=1)
    if not orientation:
        return omega, None
    quaternion = np.stack(q, axis=1)
    return omega, quaternion / np.linalg.norm(quaternion, axis=1, keepdims=True)


#: scipy refuses rtol below 100 eps.
SCIPY_MIN_RTOL = 1e-12


def scipy_runner(
    moments: Sequence[float], omega0: Sequence[float], t_end: float, method: str, rtol: float
) -> Runner:
    """``solve_ivp`` with ``method`` from the identity orientation, ``atol = rtol |omega0|``."""
    from scipy.integrate import solve_ivp

    rhs = euler_rhs(moments)
    w0 = np.asarray(omega0, dtype=np.float64)
    y0 = np.concatenate([w0, [0.0, 0.0, 0.0, 1.0]])
    scale = float(np.linalg.norm(w0))

    def run() -> tuple[Array, Array]:
        sol = solve_ivp(rhs, (0.0, t_end), y0, method=method, rtol=rtol, atol=rtol * scale)
        return sol.y[:3, -1], sol.y[3:, -1]

    return run


# --------------------------------------------------------------------------------------------
# MuJoCo


def mujoco_installed() -> bool:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return False
    return True


def mujoco_rejects(moments: Sequence[float]) -> bool:
    """MuJoCo refuses moments that break I1 + I2 >= I3 (and writes MUJOCO_LOG.TXT)."""
    i = sorted(moments)
    return i[0] + i[1] < i[2]


def mujoco_model(moments: Sequence[float], integrator: str) -> Any:
    """A free body with gravity off and these principal moments in its body axes."""
    import mujoco

    i1, i2, i3 = moments
    xml = (
        f'<mujoco><option gravity="0 0 0" integrator="{integrator}"/><worldbody><body><freejoint/>'
        f'<inertial pos="0 0 0" mass="1" diaginertia="{i1!r} {i2!r} {i3!r}"/></body></worldbody>'
        "</mujoco>"
    )
    return mujoco.MjModel.from_xml_string(xml)


def mujoco_runner(
    moments: Sequence[float], omega0: Sequence[float], t_end: float, integrator: str, dt: float
) -> Runner:
    """``round(t_end / dt)`` steps of ``integrator`` with ``mujoco.rollout``, from identity
    orientation."""
    import mujoco
    from mujoco import rollout

    model = mujoco_model(moments, integrator)
    model.opt.timestep = dt
    data = mujoco.MjData(model)
    nstep = int(round(t_end / dt))
    full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    size = mujoco.mj_stateSize(model, full)

    def run() -> tuple[Array, Array]:
        mujoco.mj_resetData(model, data)
        data.qvel[3:] = omega0  # a free joint's angular velocity is in body axes
        state0 = np.empty(size)
        mujoco.mj_getState(model, data, state0, full)
        states, _ = rollout.rollout(model, data, state0, nstep=nstep)
        last = states[0, -1]  # time, qpos (position, wxyz quaternion), qvel (linear, angular)
        quat_wxyz = last[4:8]
        return last[11:14].copy(), np.array([*quat_wxyz[1:], quat_wxyz[0]])

    return run


# --------------------------------------------------------------------------------------------
# numpy


def point_mass_inertia(m: Array, r: Array) -> Array:
    """The inertia tensor of point masses about their centre, written as a user would in numpy:
    centre, centred second moments, tr(C) 1 - C."""
    com = m @ r / m.sum()
    d = r - com
    c = (d * m[:, None]).T @ d
    return np.trace(c) * np.eye(3) - c


# --------------------------------------------------------------------------------------------
# trimesh


def trimesh_version() -> str | None:
    """trimesh's version, None if it is not installed."""
    try:
        import trimesh
    except ImportError:
        return None
    return str(trimesh.__version__)


def icosphere(subdivisions: int) -> tuple[Array, NDArray[np.int64]] | None:
    """trimesh's unit icosphere of 20 * 4^S triangles, its vertices rounded to a 2^-24 grid (so
    that the shifts of :func:`polhode.bench.mass.mesh_offset` are exact); None without
    trimesh."""
    try:
        import trimesh
    except ImportError:
        return None
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
    vertices = np.round(np.asarray(sphere.vertices) * 2.0**24) / 2.0**24
    faces = np.ascontiguousarray(sphere.faces, dtype=np.int64)
    return vertices, faces


def trimesh_mass_properties(triangles: Array) -> Any:
    """``trimesh.triangles.mass_properties`` at density 1 (its ``.inertia`` is about the centre
    of mass)."""
    import trimesh

    return trimesh.triangles.mass_properties(triangles, density=1.0)
