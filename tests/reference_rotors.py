"""Independent reference for bodies with internal rotors, by scipy's DOP853.

Written apart from the Rust core, in another form: in the body's own axes with the full inertia
tensor (no principal axes), with each wheel's rate relative to the body and each damper's
absolute angular velocity as variables, and all the accelerations solved together from a mass
matrix at each evaluation:

- the total angular momentum ``H = I w + sum J W a + sum J_d (s - w)`` (``I`` the inertia with
  the rotors locked) obeys Euler's law ``H' + w x H = tau`` in body axes;
- a wheel's axial angular momentum obeys ``J (a . w' + W') = g`` (its motor torque);
- a damper's sphere obeys ``J_d (s' + w x s) = -c (s - w)``;
- ``q' = q (x) (0, w) / 2`` (body to space, scalar-last).

So ``[[I - sum J_d, J a_j, J_d], [J a_j^T, J, 0], [0, 0, J_d]] (w', W', s')`` equals
``(tau - w x H, g, -J_d w x s - c (s - w))``. Nothing here imports polhode.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from reference import qmul


@dataclass
class WheelRef:
    axis: Any
    inertia: float
    rate0: float = 0.0
    # g(t, w, W) -> torque on the wheel about its axis
    torque: Any = field(default=lambda t, w, rate: 0.0)


@dataclass
class DamperRef:
    inertia: float
    damping: float


def gyrostat(inertia, omega0, quaternion0, times, rotors, torque=None, breaks=(), rtol=1e-12):
    """omega (M, 3), unit quaternions (M, 4), rotor rates relative to the body (M, R, 3), total
    angular momentum in space (M, 3) and total kinetic energy (M,) at ``times`` (from 0)."""
    inertia = np.asarray(inertia, dtype=float)
    wheels = [r for r in rotors if isinstance(r, WheelRef)]
    axes = [np.asarray(w.axis, float) / np.linalg.norm(w.axis) for w in wheels]
    dampers = [r for r in rotors if isinstance(r, DamperRef)]
    nw, nd = len(wheels), len(dampers)
    size = 3 + nw + 3 * nd
    mass = np.zeros((size, size))
    mass[:3, :3] = inertia - sum((d.inertia for d in dampers), 0.0) * np.eye(3)
    for j, (wheel, a) in enumerate(zip(wheels, axes, strict=True)):
        mass[:3, 3 + j] = wheel.inertia * a
        mass[3 + j, :3] = wheel.inertia * a
        mass[3 + j, 3 + j] = wheel.inertia
    for k, damper in enumerate(dampers):
        s = slice(3 + nw + 3 * k, 6 + nw + 3 * k)
        mass[:3, s] = damper.inertia * np.eye(3)
        mass[s, s] = damper.inertia * np.eye(3)
    solve = np.linalg.inv(mass)

    def unpack(y):
        w = y[:3]
        rates = y[7 : 7 + nw]
        spheres = y[7 + nw :].reshape(nd, 3)
        return w, y[3:7], rates, spheres

    def momentum(w, rates, spheres):
        h = inertia @ w
        for wheel, a, r in zip(wheels, axes, rates, strict=True):
            h = h + wheel.inertia * r * a
        for damper, s in zip(dampers, spheres, strict=True):
            h = h + damper.inertia * (s - w)
        return h

    def rhs_in(lo, hi):
        def rhs(t, y):
            tc = min(max(t, lo), hi)
            w, q, rates, spheres = unpack(y)
            unit = q / np.linalg.norm(q)
            tau = np.zeros(3) if torque is None else np.asarray(torque(tc, w, unit))
            b = np.empty(size)
            b[:3] = tau - np.cross(w, momentum(w, rates, spheres))
            for j, wheel in enumerate(wheels):
                b[3 + j] = wheel.torque(tc, w, rates[j])
            for k, (damper, s) in enumerate(zip(dampers, spheres, strict=True)):
                b[3 + nw + 3 * k : 6 + nw + 3 * k] = -damper.inertia * np.cross(
                    w, s
                ) - damper.damping * (s - w)
            x = solve @ b
            dq = 0.5 * qmul(q, np.array([w[0], w[1], w[2], 0.0]))
            return np.concatenate([x[:3], dq, x[3:]])

        return rhs

    omega0 = np.asarray(omega0, float)
    y = np.concatenate(
        [omega0, np.asarray(quaternion0, float), [w.rate0 for w in wheels], np.tile(omega0, nd)]
    )
    times = np.asarray(times, float)
    edges = [0.0, *sorted(b for b in breaks if 0.0 < b < times[-1]), float(times[-1])]
    out = np.empty((times.size, y.size))
    out[times == 0.0] = y
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        lo, hi = np.nextafter(a, b), np.nextafter(b, a)
        sol = solve_ivp(rhs_in(lo, hi), (a, b), y, method="DOP853", rtol=rtol,
                        atol=rtol * 1e-3, dense_output=True)
        inside = (times > a) & (times <= b)
        out[inside] = sol.sol(times[inside]).T
        y = sol.y[:, -1]
    omega = out[:, :3]
    q = out[:, 3:7] / np.linalg.norm(out[:, 3:7], axis=1)[:, None]
    rates = np.zeros((times.size, nw + nd, 3))
    momentum_space = np.empty((times.size, 3))
    energy = np.empty(times.size)
    for m in range(times.size):
        w, _, wheel_rates, spheres = unpack(out[m])
        rows = [r * a for r, a in zip(wheel_rates, axes, strict=True)]
        rows += [s - w for s in spheres]
        if rows:
            rates[m] = rows
        h = momentum(w, wheel_rates, spheres)
        x, y_, z, s = q[m]
        u = np.array([x, y_, z])
        momentum_space[m] = h + 2.0 * np.cross(u, np.cross(u, h) + s * h)
        # Body with every rotor locked, plus each rotor's spin relative to it.
        t = 0.5 * w @ inertia @ w
        for wheel, a, r in zip(wheels, axes, wheel_rates, strict=True):
            t += wheel.inertia * r * (a @ w) + 0.5 * wheel.inertia * r * r
        for damper, sphere in zip(dampers, spheres, strict=True):
            t += 0.5 * damper.inertia * (sphere @ sphere - w @ w)
        energy[m] = t
    # Wheels first, then dampers: reorder to the caller's order.
    order = [i for i, r in enumerate(rotors) if isinstance(r, WheelRef)]
    order += [i for i, r in enumerate(rotors) if isinstance(r, DamperRef)]
    rates_in_order = np.empty_like(rates)
    rates_in_order[:, order] = rates
    return omega, q, rates_in_order, momentum_space, energy
