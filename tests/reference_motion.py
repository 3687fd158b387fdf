"""Independent high-precision reference for the torque-free motion of a rigid body.

Euler's equations in principal axes, ``I1 w1' = (I2 - I3) w2 w3`` (and cyclic), with the
attitude quaternion ``q' = q (x) (0, w) / 2`` (body to space, scalar-last ``[x, y, z, w]`` as in
scipy), integrated by a Taylor-series method of order 40 in exact fixed-point integer arithmetic
(Python integers scaled by ``2**P``); the Taylor coefficients of this quadratic system follow
from Cauchy products, so no derivative is approximated. The step is chosen from the decay of the
last coefficients so the truncation stays below ``10**-dps``. Nothing here uses the Rust code or
elliptic functions for the motion itself.

For long times (``method="periodic"``) the motion is reduced with the exact quasi-periodicity of
free rotation: ``omega(t + T) = omega(t)`` and ``q(t + T) = Q (x) q(t)`` with ``Q`` a fixed
rotation about the space angular momentum (``Q = q(T) (x) q(0)^-1`` from one integrated period),
so ``q(N T + tau) = Q^N (x) q(tau)``. The period ``T = 4 K(m) / lambda`` comes from the closed
form (mpmath's ``ellipk``) and is validated by checking ``omega(T) = omega(0)`` on the integrated
trajectory; :func:`closed_form_motion` gives the classical closed form with ``mpmath.ellipfun``
and ``mpmath.ellippi`` (validated against the integration in :func:`self_check`).

Precision: the integration runs with ``dps`` digits plus the digits the motion's sensitivity
costs (near the separatrix, ``log10(G^2 / |G^2 - 2 T I2|)``), plus guard digits. Exactly on the
separatrix it runs with twice the digits and, once the other components have decayed below
``10**-(dps + 8)``, continues with the steady rotation about the intermediate axis.

Cost: well under a second per call for ordinary bodies, a few seconds next to the separatrix
(one period is integrated whatever the times); bodies whose period is very long compared with
their spin (near-symmetric, slow nutation) cost in proportion to one period.

Command line: ``python3 tests/reference_motion.py`` cross-checks the three paths;
``--rust-fixtures`` and ``--rust-elliptic-tables`` print the reference constants of
``rust/polhode/tests/exact.rs``.
"""

from __future__ import annotations

import math
from fractions import Fraction
from operator import mul

import mpmath as mp
import numpy as np

__all__ = [
    "reference_motion",
    "closed_form_motion",
    "motion_constants",
    "rel_errors",
    "self_check",
]

ORDER = 40


def _exact(x) -> Fraction:
    return Fraction(float(x))


def _dyadic(x: Fraction) -> Fraction:
    """x rounded down to a multiple of 2^-48 (keeps the time sums exact and small)."""
    return Fraction(math.floor(x * (1 << 48)), 1 << 48)


def _conv(a, b, k):
    """sum_{l=0..k} a[l] b[k-l] (exact integers)."""
    return sum(map(mul, a[: k + 1], b[k::-1]))


class _Taylor:
    """Fixed-point Taylor integrator of Euler's equations plus the attitude quaternion."""

    def __init__(self, moments, omega0, quat0_xyzw, dps):
        self.dps = dps
        self.bits = int(dps * 3.33) + 16
        self.P = self.bits + 40
        i1, i2, i3 = (_exact(v) for v in moments)
        w = [_exact(v) for v in omega0]
        scale = max(abs(v) for v in w)
        if scale == 0:
            scale = Fraction(1)
        # Time unit 1/scale (a power of two near max |omega|): omega ~ 1.
        e = math.floor(math.log2(scale))
        self.wscale = Fraction(2) ** e
        self.a = [(i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3]
        one = 1 << self.P
        self.one = one
        self.w = [self._fx(v / self.wscale) for v in w]
        q = [_exact(v) for v in quat0_xyzw]
        self.q = [self._fx(v) for v in q]  # x, y, z, s
        self.t = Fraction(0)  # in scaled time
        self.h = Fraction(1, 8)
        self.steady = None
        self.sep_axis = None
        self.sep_w2 = None
        self.sep_bits = None
        self.t_eval = self.t

    def _steady_value(self):
        """Past the separatrix horizon: steady rotation about the intermediate axis,
        ``q(t) = q(t1) (x) exp(w t / 2)``, ``w = G / I_mid`` along it (its other components
        are below the working precision)."""
        t1, w, q = self.steady
        with mp.workprec(self.P + 20):
            sc = mp.mpf(1) / (1 << self.P)
            ws = mp.mpf(self.wscale.numerator) / self.wscale.denominator
            k = self.sep_axis
            wk = mp.sqrt(_mpf(self.sep_w2)) * (1 if w[k] > 0 else -1)
            omega = [mp.mpf(0)] * 3
            omega[k] = wk
            qq = [mp.mpf(v) * sc for v in q]
            dt = _mpf(self.t_eval - t1) / ws
            half = wk * dt / 2
            e = [mp.mpf(0)] * 3
            e[k] = mp.sin(half)
            step = e + [mp.cos(half)]
            return omega, _qmul(qq, step)

    def _fx(self, x: Fraction) -> int:
        return (x.numerator << self.P) // x.denominator

    def _coeffs(self, h: Fraction):
        """Scaled Taylor coefficients W_k = w_k h^k, Q_k = q_k h^k, k = 0..ORDER."""
        P = self.P
        ah = [self._fx(a * h) for a in self.a]
        hh = self._fx(h / 2)
        W = [[self.w[0]], [self.w[1]], [self.w[2]]]
        X, Y, Z, S = ([self.q[0]], [self.q[1]], [self.q[2]], [self.q[3]])
        for k in range(ORDER):
            w0, w1, w2 = W
            c0 = _conv(w1, w2, k) >> P
            c1 = _conv(w2, w0, k) >> P
            c2 = _conv(w0, w1, k) >> P
            # q' = q (x) (0, w) / 2 with q = (s, v): s' = -v.w/2, v' = (s w + v x w)/2.
            sw = [_conv(S, w0, k), _conv(S, w1, k), _conv(S, w2, k)]
            xw = [_conv(X, w0, k), _conv(X, w1, k), _conv(X, w2, k)]
            yw = [_conv(Y, w0, k), _conv(Y, w1, k), _conv(Y, w2, k)]
            zw = [_conv(Z, w0, k), _conv(Z, w1, k), _conv(Z, w2, k)]
            ds = -(xw[0] + yw[1] + zw[2]) >> P
            dx = (sw[0] + yw[2] - zw[1]) >> P
            dy = (sw[1] + zw[0] - xw[2]) >> P
            dz = (sw[2] + xw[1] - yw[0]) >> P
            kk = k + 1
            w0.append((c0 * ah[0] >> P) // kk)
            w1.append((c1 * ah[1] >> P) // kk)
            w2.append((c2 * ah[2] >> P) // kk)
            X.append((dx * hh >> P) // kk)
            Y.append((dy * hh >> P) // kk)
            Z.append((dz * hh >> P) // kk)
            S.append((ds * hh >> P) // kk)
        return W + [X, Y, Z, S]

    def _tail(self, C):
        return max(max(abs(c[ORDER]), abs(c[ORDER - 1])) for c in C)

    def step(self, t_max: Fraction):
        """One step, not beyond scaled time t_max."""
        tol = self.one >> self.bits
        planned = self.h
        h = min(planned, t_max - self.t)
        shrunk = False
        while True:
            C = self._coeffs(h)
            tail = self._tail(C)
            if tail <= tol:
                break
            # Shrink using the observed size of the tail.
            ratio = min((tol / tail) ** (1.0 / ORDER) * 0.9, 0.5)
            h = _dyadic(h * Fraction(ratio))
            shrunk = True
        self.w = [sum(c) for c in C[:3]]
        self.q = [sum(c) for c in C[3:]]
        self.t += h
        grow = (tol / tail) ** (1.0 / ORDER) * 0.9 if tail > 0 else 2.0
        grow = min(max(grow, 0.5), 2.0)
        if shrunk or h == planned:
            self.h = max(_dyadic(h * Fraction(grow)), Fraction(1, 1 << 40))

    def advance(self, t: Fraction):
        """Integrate to scaled time t (>= current); on the separatrix, stop integrating once
        the body has reached the intermediate axis to the working precision."""
        if self.steady is not None:
            self.t_eval = t
            return
        while self.t < t:
            self.step(t)
            if self.sep_axis is not None:
                off = max(abs(v) for i, v in enumerate(self.w) if i != self.sep_axis)
                if off < self.one >> self.sep_bits:
                    self.steady = (self.t, list(self.w), list(self.q))
                    self.t_eval = t
                    return
        self.t_eval = self.t

    def value(self):
        if self.steady is not None:
            return self._steady_value()
        with mp.workprec(self.P + 20):
            sc = mp.mpf(1) / (1 << self.P)
            ws = mp.mpf(self.wscale.numerator) / self.wscale.denominator
            w = [mp.mpf(v) * sc * ws for v in self.w]
            q = [mp.mpf(v) * sc for v in self.q]
        return w, q


def motion_constants(moments, omega0):
    """Exact invariants and the period, as a dict (mpmath numbers at the current precision).

    Keys: ``G2`` (|L|^2), ``T2`` (2T), ``delta2`` (G^2 - 2 T I_mid, exact), ``kind``
    (``"rest" | "steady" | "symmetric" | "general" | "separatrix"``), ``period`` (period of
    omega or None), ``m`` (parameter), ``lam`` (rate).
    """
    mom = [_exact(v) for v in moments]
    w = [_exact(v) for v in omega0]
    m = [a * b for a, b in zip(mom, w, strict=True)]
    G2 = sum(x * x for x in m)
    T2 = sum(a * b for a, b in zip(m, w, strict=True))
    out = {"G2": G2, "T2": T2, "delta2": None, "period": None, "m": None, "lam": None}
    if G2 == 0:
        out["kind"] = "rest"
        return out
    if len(set(mom)) == 1:
        out["kind"] = "steady"
        return out
    if len(set(mom)) == 2:
        s = [i for i in range(3) if mom.count(mom[i]) == 1][0]
        it = mom[(s + 1) % 3]
        Om = w[s] * (mom[s] - it) / it
        perp = sum(x * x for i, x in enumerate(w) if i != s)
        out["kind"] = "symmetric"
        if Om != 0 and perp != 0:
            out["period"] = 2 * mp.pi / abs(mp.mpf(Om.numerator) / Om.denominator)
        return out
    order = sorted(range(3), key=lambda i: mom[i])
    lo, mid, hi = order
    if sum(1 for x in m if x == 0) == 2:
        out["kind"] = "steady"
        return out
    d2 = G2 - T2 * mom[mid]
    out["delta2"] = d2
    if d2 == 0:
        out["kind"] = "separatrix"
        I1, I2, I3 = mom[lo], mom[mid], mom[hi]
        D1 = G2 - T2 * I1
        out["lam"] = mp.sqrt(_mpf(D1 * (I3 - I2) / (I1 * I2 * I3)))
        return out
    out["kind"] = "general"
    if d2 > 0:
        I1, I2, I3 = mom[lo], mom[mid], mom[hi]
    else:
        I1, I2, I3 = mom[hi], mom[mid], mom[lo]
    D1 = G2 - T2 * I1
    D3 = G2 - T2 * I3
    k2 = (I2 - I1) * (-D3) / ((I3 - I2) * D1)
    lam2 = D1 * (I3 - I2) / (I1 * I2 * I3)
    extra = max(0, math.ceil(math.log10(float(G2 / abs(d2)) + 1)))
    with mp.extradps(extra + 10):
        lam = mp.sqrt(_mpf(lam2))
        K = mp.ellipk(_mpf(k2))
        period = 4 * K / lam
    out.update(m=k2, lam=+lam, period=+period)
    return out


def turns_over_exact(moments, omega) -> bool:
    """Whether L spends more than half of each period within 45 degrees of the intermediate
    axis, in exact arithmetic: with L_2 = A sn(u | m), |sn| >= s0 = |L| / (sqrt(2) A) for more
    than half of a quarter period iff s0^2 < 1 / (1 + sqrt(1 - m)), i.e.
    2 A^2 / |L|^2 - 1 > sqrt(1 - m)."""
    i = [Fraction(float(x)) for x in moments]
    w = [Fraction(float(x)) for x in omega]
    g2 = sum((a * b) ** 2 for a, b in zip(i, w, strict=True))  # |L|^2
    t2 = sum(a * b * b for a, b in zip(i, w, strict=True))  # 2 T
    i1, i2, i3 = sorted(i)
    if g2 - t2 * i2 > 0:  # about axis 3: L_1 = 0 at the largest L_2
        a2 = (t2 - g2 / i3) / (1 / i2 - 1 / i3)
        m = (i2 - i1) * (t2 * i3 - g2) / ((i3 - i2) * (g2 - t2 * i1))
    elif g2 - t2 * i2 < 0:  # about axis 1: L_3 = 0 at the largest L_2
        a2 = (t2 - g2 / i1) / (1 / i2 - 1 / i1)
        m = (i3 - i2) * (g2 - t2 * i1) / ((i2 - i1) * (t2 * i3 - g2))
    else:
        return False
    lhs = 2 * a2 / g2 - 1
    return lhs > 0 and lhs * lhs > 1 - m


def _mpf(x: Fraction):
    return mp.mpf(x.numerator) / x.denominator


def _qmul(a, b):
    """Hamilton product of scalar-last quaternions."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]


def _qpow(Q, n):
    """Q^n for a unit quaternion (n integer), via its axis and angle."""
    x, y, z, w = Q
    s = mp.sqrt(x * x + y * y + z * z)
    if s == 0:
        return [mp.mpf(0), mp.mpf(0), mp.mpf(0), mp.mpf(1) if (w > 0 or n % 2 == 0) else mp.mpf(-1)]
    half = mp.atan2(s, w)
    a = half * n
    f = mp.sin(a) / s
    return [x * f, y * f, z * f, mp.cos(a)]


def midpoint_step_mp(moments, omega0, quat0_xyzw, h, dps=50, torque_body=(0.0, 0.0, 0.0)):
    """One step of the implicit midpoint rule from the definition, at ``dps`` digits: the
    midpoint ``w_m`` solving ``w_m = w0 + h/2 f(w_m)`` (Euler's equations, with a constant
    torque ``torque_body`` in body axes) by Newton's method with the analytic Jacobian,
    ``w1 = 2 w_m - w0``; and ``q1`` solving the linear midpoint equation
    ``q1 = q0 + h (q0 + q1)/2 (x) (0, w_m) / 2`` as a 4x4 linear system (not by the Cayley
    formula), divided by its norm (the integrator renormalises each step). Returns
    ``(w1, q1)`` as mpmath numbers."""
    with mp.workdps(dps):
        i1, i2, i3 = (mp.mpf(float(m)) for m in moments)
        c = [(i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3]
        w0 = [mp.mpf(float(x)) for x in omega0]
        k = mp.mpf(float(h)) / 2
        g = [mp.mpf(float(x)) / i for x, i in zip(torque_body, (i1, i2, i3), strict=True)]

        def f(w):
            return [
                c[0] * w[1] * w[2] + g[0],
                c[1] * w[2] * w[0] + g[1],
                c[2] * w[0] * w[1] + g[2],
            ]

        w = list(w0)
        for _ in range(200):
            fw = f(w)
            r = mp.matrix([w0[i] + k * fw[i] - w[i] for i in range(3)])
            jac = mp.matrix(
                [
                    [0, c[0] * w[2], c[0] * w[1]],
                    [c[1] * w[2], 0, c[1] * w[0]],
                    [c[2] * w[1], c[2] * w[0], 0],
                ]
            )
            d = mp.lu_solve(mp.eye(3) - k * jac, r)
            w = [w[i] + d[i] for i in range(3)]
            if max(abs(x) for x in d) <= mp.mpf(10) ** (-dps + 5) * max(abs(x) for x in w):
                break
        else:
            raise RuntimeError("midpoint_step_mp: Newton did not converge")
        w1 = [2 * w[i] - w0[i] for i in range(3)]
        q0 = [mp.mpf(float(x)) for x in quat0_xyzw]
        # q1 - (h/4) q1 (x) (0, w_m) = q0 + (h/4) q0 (x) (0, w_m): column j of the product's
        # matrix is e_j (x) (0, w_m).
        wq = [w[0], w[1], w[2], mp.mpf(0)]
        cols = [_qmul([1 if i == j else 0 for i in range(4)], wq) for j in range(4)]
        m = mp.matrix(4, 4)
        for i in range(4):
            for j in range(4):
                m[i, j] = (1 if i == j else 0) - mp.mpf(float(h)) / 4 * cols[j][i]
        rhs = mp.matrix([q0[i] + mp.mpf(float(h)) / 4 * _qmul(q0, wq)[i] for i in range(4)])
        q1 = mp.lu_solve(m, rhs)
        n = mp.sqrt(sum(q1[i] ** 2 for i in range(4)))
        return w1, [q1[i] / n for i in range(4)]


def _work_dps(dps, moments, omega0):
    c = motion_constants(moments, omega0)
    extra = 0
    if c["delta2"] not in (None, 0):
        extra = max(0, math.ceil(math.log10(float(c["G2"] / abs(c["delta2"])) + 1)))
    if c["kind"] == "separatrix":
        # The deviation from the separatrix grows like exp(lambda t) while the motion decays
        # onto the intermediate axis like exp(-lambda t): twice the digits.
        extra = dps + 30
    return dps + extra + 10, c


def _direct(moments, omega0, quat0_xyzw, times, wdps, constants=None):
    """Integrate through the sorted times; returns lists of mpf per time."""
    tay = _Taylor(moments, omega0, quat0_xyzw, wdps)
    if constants is not None and constants["kind"] == "separatrix":
        mom = [_exact(v) for v in moments]
        mid = sorted(range(3), key=lambda i: mom[i])[1]
        tay.sep_axis = mid
        # |w_mid| at the end: G / I_mid (exact square).
        tay.sep_w2 = constants["G2"] / mom[mid] ** 2
        # Switch to the asymptote once the other components are below 10^-(dps + 8).
        tay.sep_bits = int((wdps - 10) / 2 * 3.33) + 26
    order = sorted(range(len(times)), key=lambda i: times[i])
    res_w = [None] * len(times)
    res_q = [None] * len(times)
    for i in order:
        t = Fraction(times[i]) * tay.wscale
        if t < tay.t:
            raise ValueError("negative times are not supported")
        tay.advance(t)
        res_w[i], res_q[i] = tay.value()
    return res_w, res_q


def reference_motion(moments, omega0, quat0_xyzw, times, dps=30, method="auto"):
    """Body angular velocity and attitude at ``times`` (>= 0) for the torque-free body.

    ``moments``: principal moments (any order, > 0); ``omega0``: body angular velocity at t = 0;
    ``quat0_xyzw``: attitude at t = 0 (body to space, scalar last); ``times``: (M,) floats.
    Inputs are taken as the exact binary values of the doubles. Returns ``(omega (M, 3),
    quat_xyzw (M, 4))`` as float64 arrays (and, with ``method`` ending in ``"+mp"``, the mpmath
    values too). ``method``: ``"direct"`` integrates to every time; ``"periodic"`` integrates one
    period and uses ``q(N T + tau) = Q^N q(tau)``; ``"auto"`` is direct up to 2 periods (or for
    a non-periodic motion) and periodic beyond. The two agree to the working precision (see
    :func:`self_check`); the periodic path costs one period of integration whatever the times.
    """
    want_mp = method.endswith("+mp")
    method = method.replace("+mp", "")
    times = [float(t) for t in np.atleast_1d(np.asarray(times, dtype=float))]
    wdps, c = _work_dps(dps, moments, omega0)
    with mp.workdps(wdps):
        c = motion_constants(moments, omega0)
        period = c["period"]
        if method == "auto":
            method = "periodic" if period is not None and max(times) > 2 * period else "direct"
        if method == "direct" or period is None:
            ws, qs = _direct(moments, omega0, quat0_xyzw, times, wdps, c)
        else:
            T = period
            Ns, taus = [], []
            for t in times:
                N = int(mp.floor(mp.mpf(t) / T))
                tau = mp.mpf(t) - N * T
                Ns.append(N)
                taus.append(tau)
            # Integrate [0, T] once, stopping at every tau and at T.
            tay = _Taylor(moments, omega0, quat0_xyzw, wdps)
            targets = sorted(set(range(len(times))), key=lambda i: taus[i])
            vals = {}
            prec_bits = tay.P + 20

            def frac(x):
                # Exact enough rational for an mpf at the working precision.
                man, exp = mp.mpf(x).man_exp
                return Fraction(int(man)) * (Fraction(2) ** int(exp))

            with mp.workprec(prec_bits):
                for i in targets:
                    tay.advance(frac(taus[i]) * tay.wscale)
                    vals[i] = tay.value()
                tay.advance(frac(T) * tay.wscale)
                wT, qT = tay.value()
            w0 = [_mpf(_exact(v)) for v in omega0]
            q0 = [_mpf(_exact(v)) for v in quat0_xyzw]
            n0 = mp.sqrt(sum(v * v for v in w0))
            err = mp.sqrt(sum((a - b) ** 2 for a, b in zip(wT, w0, strict=True))) / n0
            if err > mp.mpf(10) ** (-(dps + 3)):
                raise RuntimeError(f"omega(T) != omega(0): relative {mp.nstr(err, 5)}")
            q0inv = [-q0[0], -q0[1], -q0[2], q0[3]]
            Q = _qmul(qT, q0inv)
            ws, qs = [], []
            for i in range(len(times)):
                w, q = vals[i]
                ws.append(w)
                qs.append(_qmul(_qpow(Q, Ns[i]), q))
        out_w = np.array([[float(x) for x in w] for w in ws])
        out_q = np.array([[float(x) for x in q] for q in qs])
        if want_mp:
            return out_w, out_q, ws, qs
        return out_w, out_q


def closed_form_motion(moments, omega0, quat0_xyzw, times, dps=30):
    """The classical closed form (three distinct moments, off the separatrix), with
    ``mpmath.ellipfun`` for omega and ``mpmath.ellippi`` for the precession (z-x-z Euler angles
    about the axis the angular momentum circulates about:
    ``phi = G t / I3 + c (Pi(am u; n | m) - Pi(am u0; n | m))``). Only for cross-checks.
    """
    times = [float(t) for t in np.atleast_1d(np.asarray(times, dtype=float))]
    wdps, _ = _work_dps(dps, moments, omega0)
    with mp.workdps(wdps):
        mom = [_mpf(_exact(v)) for v in moments]
        w0 = [_mpf(_exact(v)) for v in omega0]
        q0 = [_mpf(_exact(v)) for v in quat0_xyzw]
        m0 = [a * b for a, b in zip(mom, w0, strict=True)]
        G = mp.sqrt(sum(x * x for x in m0))
        T2 = sum(a * b for a, b in zip(m0, w0, strict=True))
        order = sorted(range(3), key=lambda i: mom[i])
        lo, mid, hi = order
        d2 = G * G - T2 * mom[mid]
        if d2 > 0:
            idx = [lo, mid, hi]
        else:
            idx = [hi, mid, lo]
        # Right-handed canonical frame: flip axis 3 for an odd permutation.
        even = idx in ([0, 1, 2], [1, 2, 0], [2, 0, 1])
        sg = [1, 1, 1 if even else -1]
        I1, I2, I3 = (mom[i] for i in idx)
        m1, m2, m3 = (sg[k] * m0[idx[k]] for k in range(3))
        D1 = G * G - T2 * I1
        D3 = G * G - T2 * I3
        B1 = mp.sqrt(I1 * (-D3) / (I3 - I1))
        B2 = mp.sqrt(I2 * (-D3) / (I3 - I2))
        B3 = mp.sqrt(I3 * D1 / (I3 - I1))
        lam = mp.sqrt(D1 * (I3 - I2) / (I1 * I2 * I3))
        k2 = (I2 - I1) * (-D3) / ((I3 - I2) * D1)
        s3 = 1 if m3 > 0 else -1
        s2 = s3 * (1 if I3 > I2 else -1)
        K = mp.ellipk(k2)
        # u0 from sn, cn; am u0 = atan2(sn, cn).
        phi0 = mp.atan2(s2 * m2 / B2, m1 / B1)
        u0 = mp.ellipf(phi0, k2)
        n = -I3 * (I2 - I1) / (I1 * (I3 - I2))
        cc = G * (I3 - I1) / (I1 * I3 * lam)
        # Euler frame = canonical frame (polar axis 3); L-frame fixed from the data at t = 0.
        theta0 = mp.atan2(mp.sqrt(m1 * m1 + m2 * m2), m3)
        psi0 = mp.atan2(m1, m2)
        P = mp.matrix(3, 3)
        for k in range(3):
            P[idx[k], k] = sg[k]
        qE = _quat_from_matrix(P)

        def qz(a):
            return [mp.mpf(0), mp.mpf(0), mp.sin(a / 2), mp.cos(a / 2)]

        def qx(a):
            return [mp.sin(a / 2), mp.mpf(0), mp.mpf(0), mp.cos(a / 2)]

        qL = _qmul(_qmul(_qmul(q0, qE), qz(-psi0)), qx(-theta0))
        qEinv = [-qE[0], -qE[1], -qE[2], qE[3]]

        def am(u):
            j = mp.nint(u / (2 * K))
            w = u - 2 * j * K
            return j * mp.pi + mp.atan2(mp.ellipfun("sn", w, m=k2), mp.ellipfun("cn", w, m=k2))

        Pi0 = mp.ellippi(n, phi0, k2)
        ws, qs = [], []
        for t in times:
            t = mp.mpf(t)
            u = lam * t + u0
            sn, cn, dn = (mp.ellipfun(f, u, m=k2) for f in ("sn", "cn", "dn"))
            mc = [B1 * cn, s2 * B2 * sn, s3 * B3 * dn]
            wb = [0, 0, 0]
            for k in range(3):
                wb[idx[k]] = sg[k] * mc[k] / [I1, I2, I3][k]
            theta = mp.atan2(mp.sqrt(mc[0] ** 2 + mc[1] ** 2), mc[2])
            psi = mp.atan2(mc[0], mc[1])
            phi = G * t / I3 + cc * (mp.ellippi(n, am(u), k2) - Pi0)
            q = _qmul(_qmul(_qmul(_qmul(qL, qz(phi)), qx(theta)), qz(psi)), qEinv)
            ws.append(wb)
            qs.append(q)
        return (
            np.array([[float(x) for x in w] for w in ws]),
            np.array([[float(x) for x in q] for q in qs]),
        )


def _quat_from_matrix(R):
    """Scalar-last unit quaternion of a proper rotation matrix (mpmath)."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    if tr > 0:
        s = mp.sqrt(tr + 1) * 2
        return [(R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s, s / 4]
    i = max(range(3), key=lambda k: R[k, k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = mp.sqrt(R[i, i] - R[j, j] - R[k, k] + 1) * 2
    q = [0, 0, 0, 0]
    q[i] = s / 4
    q[j] = (R[j, i] + R[i, j]) / s
    q[k] = (R[k, i] + R[i, k]) / s
    q[3] = (R[k, j] - R[j, k]) / s
    return q


def rel_errors(omega, quat, omega_ref, quat_ref):
    """Per-time relative errors: |w - w_ref| / |w_ref| and min over sign |q -+ q_ref| / |q_ref|."""
    omega, quat = np.asarray(omega), np.asarray(quat)
    ew = np.linalg.norm(omega - omega_ref, axis=-1) / np.linalg.norm(omega_ref, axis=-1)
    eq = np.minimum(
        np.linalg.norm(quat - quat_ref, axis=-1), np.linalg.norm(quat + quat_ref, axis=-1)
    ) / np.linalg.norm(quat_ref, axis=-1)
    return ew, eq


def self_check(verbose=True):
    """Cross-check the three paths (direct, periodic, closed form) on a few bodies."""
    cases = [
        ((3.0, 5.0, 9.0), (0.1, 0.4, 0.01 / 9), (0.1, -0.2, 0.3, 0.9273618495495703)),
        ((2.0, 1.0, 2.0 / 3.0), (math.cos(1.1) / 2, 0.0, math.sin(1.1) * 1.5), (0, 0, 0, 1)),
        ((1.0, 2.0, 3.0), (-0.3, 0.5, 0.2), (0.5, 0.5, 0.5, 0.5)),
    ]
    worst = 0.0
    for mom, w, q in cases:
        q = np.asarray(q, float)
        q = q / np.linalg.norm(q)
        c = motion_constants(mom, w)
        T = float(c["period"])
        ts = [0.0, 0.3 * T, 1.7 * T, 3.2 * T]
        wd, qd = reference_motion(mom, w, q, ts, method="direct")
        wp, qp = reference_motion(mom, w, q, ts, method="periodic")
        wc, qc = closed_form_motion(mom, w, q, ts)
        e = [max(np.max(x) for x in rel_errors(a, b, wd, qd)) for a, b in ((wp, qp), (wc, qc))]
        worst = max(worst, *e)
        if verbose:
            print(mom, w, f"periodic vs direct {e[0]:.1e}, closed vs direct {e[1]:.1e}")
    return worst


def _fixture_cases():
    """The cases hard-coded in rust/polhode/tests/exact.rs: (name, moments, omega0, quat0,
    times in units of the period, or absolute times if the motion is aperiodic)."""
    q0 = (0.1, -0.2, 0.3, 0.9)
    I359 = (3.0, 5.0, 9.0)

    def L(v, mom):
        return tuple(float(a) / float(b) for a, b in zip(v, mom, strict=True))

    per = [0.0, 0.37, 1.0, 10.5, 57.123, 99.7]
    return [
        (
            "HLW",
            (2.0, 1.0, 2.0 / 3.0),
            (math.cos(1.1) / 2.0, 0.0, math.sin(1.1) * 1.5),
            q0,
            ("abs", [0.0, 1.0, 7.5, 33.3, 100.0]),
        ),
        (
            "KROGH",
            (1.0 / 1.51, 1.0, 0.5),
            (0.0, 1.0, 2.0 / 0.7),
            q0,
            ("abs", [0.0, 0.5, 10.0, 55.5, 100.0]),
        ),
        ("SEP_0_2_1E_2", I359, L((0.0, 2.0, 0.01), I359), q0, ("per", per)),
        ("SEP_0_2_1E_6", I359, L((0.0, 2.0, 1e-6), I359), q0, ("per", per)),
        ("SEP_0_2_1E_12", I359, L((0.0, 2.0, 1e-12), I359), q0, ("per", per)),
        ("SEP_1E_6_2_1E_6", I359, L((1e-6, -2.0, 1e-6), I359), q0, ("per", per)),
        ("SEP_1E_12_2_1E_12", I359, L((-1e-12, 2.0, 1e-12), I359), q0, ("per", per)),
        ("SEP_ROUNDED", I359, L((0.5, 2.0, 0.5 * math.sqrt(1.5)), I359), q0, ("per", per)),
        (
            "SEP_EXACT",
            (2.0, 3.0, 6.0),
            (-1.5, -2.0, -0.5),
            q0,
            ("abs", [0.0, 1.0, 3.0, 10.0, 40.0, 300.0]),
        ),
        (
            "SEP_EXACT_2",
            (6.0, 2.0, 3.0),
            (0.5, 1.5, 0.3),
            q0,
            ("abs", [0.0, 0.7, 2.0, 10.0, 100.0]),
        ),
        ("NEARSYM_1E_8", (1.0, 1.0 + 1e-8, 2.0), (0.3, -0.4, 0.5), q0, ("per", per)),
        ("NEARSYM_1E_12", (1.0, 1.0 + 1e-12, 2.0), (0.3, -0.4, 0.5), q0, ("per", per)),
        (
            "NEARSYM_1E_8_LO",
            (1.0, 1.0 + 1e-8, 2.0),
            (0.6, -0.4, 1e-5),
            q0,
            ("abs", [0.0, 10.0, 300.0, 2000.0]),
        ),
        (
            "NEARSYM_1E_12_LO",
            (1.0, 1.0 + 1e-12, 2.0),
            (0.6, -0.4, 1e-5),
            q0,
            ("abs", [0.0, 10.0, 300.0, 2000.0]),
        ),
        (
            "NEARSYM_HI_1E_8",
            (1.0, 2.0 - 1e-8, 2.0),
            (1e-5, -0.4, 0.5),
            q0,
            ("abs", [0.0, 10.0, 300.0, 2000.0]),
        ),
        ("SYM_223", (2.0, 2.0, 3.0), (0.3, -0.4, 0.5), q0, ("per", per)),
        ("SYM_233", (2.0, 3.0, 3.0), (0.3, -0.4, 0.5), q0, ("per", per)),
        ("UNSORTED_953", (9.0, 5.0, 3.0), (-0.05, 0.4, 0.1), q0, ("per", per)),
        ("UNSORTED_395", (3.0, 9.0, 5.0), (0.1, -0.05, -0.4), q0, ("per", per)),
        (
            "LONG_359",
            I359,
            L((0.3, 2.0, -0.5), I359),
            q0,
            ("per", [100.3, 1000.7, 10000.1, 1e5 + 0.5, 1e6 + 0.25, 1e9 + 0.6]),
        ),
        (
            "LONG_NEARSEP",
            I359,
            L((0.0, 2.0, 1e-6), I359),
            q0,
            ("per", [100.3, 1000.7, 10000.1, 1e5 + 0.5, 1e6 + 0.25]),
        ),
    ]


def rust_fixtures(out=None):
    """Print the Rust constants of rust/polhode/tests/exact.rs (reference states)."""
    import sys

    out = out or sys.stdout
    w = out.write
    w("// Generated by `python3 tests/reference_motion.py --rust-fixtures` (mpmath Taylor\n")
    w("// integration at 30+ digits; the periodic path beyond 2 periods).\n")
    w("// (moments, omega0, quat0 [x, y, z, w], [(t, omega, quat [x, y, z, w])], period or 0)\n")
    for name, mom, om, q, (kind, ts) in _fixture_cases():
        q = np.asarray(q, float) / np.linalg.norm(np.asarray(q, float))
        q = tuple(float(v) for v in q)
        c = motion_constants(mom, om)
        T = c["period"]
        with mp.workdps(60):
            c = motion_constants(mom, om)
            T = c["period"]
            if kind == "per":
                times = [float(mp.mpf(x) * T) for x in ts]
            else:
                times = [float(x) for x in ts]
        wr, qr = reference_motion(mom, om, q, times)
        Tf = float(T) if T is not None else 0.0

        def fm(v):
            return "[" + ", ".join(repr(float(x)) for x in v) + "]"

        w(f"const {name}: Fixture = Fixture {{\n")
        w(f"    moments: {fm(mom)},\n    omega0: {fm(om)},\n    quat0: {fm(q)},\n")
        w(f"    period: {Tf!r},\n    states: &[\n")
        for t, a, b in zip(times, wr, qr, strict=True):
            w(f"        ({t!r}, {fm(a)}, {fm(b)}),\n")
        w("    ],\n};\n")
        out.flush()


def rust_elliptic_tables():
    """Print the elliptic-function reference tables of rust/polhode/tests/exact.rs (mpmath at
    50 + log10(1/mc) digits)."""

    def dps_for(mc):
        return 50 + (int(-math.log10(mc)) if mc > 0 else 0)

    def f(x):
        return repr(float(x))

    print("// Generated by `python3 tests/reference_motion.py --rust-elliptic-tables`.")
    print("// (u, mc, sn, cn, dn)")
    print("const JACOBI: &[(f64, f64, f64, f64, f64)] = &[")
    for mc in [1.0, 0.75, 0.5, 0.1, 1e-3, 1e-8, 1e-16, 1e-40, 1e-150, 1e-300]:
        with mp.workdps(dps_for(mc)):
            m = 1 - mp.mpf(mc)
            K = mp.ellipk(m)
            for frac in [0.1, 0.49, 0.999, 1.37, 2.5, 3.9, -0.7, 10.3]:
                u = float(frac * K)
                s, c, d = (mp.ellipfun(n, mp.mpf(u), m=m) for n in ("sn", "cn", "dn"))
                print(f"    ({f(u)}, {f(mc)}, {f(s)}, {f(c)}, {f(d)}),")
    print("];")
    print("// (mc, K)")
    print("const ELLIPK: &[(f64, f64)] = &[")
    for mc in [1.0, 0.9, 0.5, 0.1, 1e-3, 1e-8, 1e-16, 1e-50, 1e-300, 1 - 2.0**-30]:
        with mp.workdps(dps_for(mc)):
            print(f"    ({f(mc)}, {f(mp.ellipk(1 - mp.mpf(mc)))}),")
    print("];")
    mp.mp.dps = 50
    print("// (x, y, z, R_F)")
    print("const RF: &[(f64, f64, f64, f64)] = &[")
    rf_args = [
        (1, 2, 0),
        (0.5, 1, 2),
        (1e-10, 1, 1),
        (3, 3, 3),
        (1e-300, 1e-300, 1),
        (2, 1e5, 7e-5),
        (1e20, 1e21, 3e19),
    ]
    for x, y, z in rf_args:
        print(f"    ({f(x)}, {f(y)}, {f(z)}, {f(mp.elliprf(x, y, z))}),")
    print("];")
    print("// (x, y, p, R_C)")
    print("const RC: &[(f64, f64, f64)] = &[")
    rc_args = [(0, 0.25), (2.25, 2), (0.25, 2), (1, 1 + 1e-9), (1e6, 1e-6), (1, -2), (0.3, -1e-7)]
    for x, y in rc_args:
        print(f"    ({f(x)}, {f(y)}, {f(mp.elliprc(x, y))}),")
    print("];")
    print("// (x, y, z, R_D)")
    print("const RD: &[(f64, f64, f64, f64)] = &[")
    for x, y, z in [(0, 2, 1), (2, 3, 4), (1e-8, 1, 1e-8), (0.5, 0.5, 1e6)]:
        print(f"    ({f(x)}, {f(y)}, {f(z)}, {f(mp.elliprd(x, y, z))}),")
    print("];")
    print("// (x, y, z, p, R_J)")
    print("const RJ: &[(f64, f64, f64, f64, f64)] = &[")
    rj_args = [
        (0, 1, 2, 3),
        (2, 3, 4, 5),
        (0.25, 0.5, 1, 1e8),
        (1, 2, 3, 1e-8),
        (0.2, 1, 1, 1 + 1e-12),
        (1e-12, 0.4, 1, 2.5),
        (5, 1e-3, 1, 0.01),
    ]
    for x, y, z, p in rj_args:
        print(f"    ({f(x)}, {f(y)}, {f(z)}, {f(p)}, {f(mp.elliprj(x, y, z, p))}),")
    print("];")
    print("// (phi, n, mc, Pi(phi; n | 1 - mc))")
    print("const PI3: &[(f64, f64, f64, f64)] = &[")
    pi_args = [
        (0.7, -1.5, 0.5),
        (1.4, -0.3, 1e-8),
        (1.5707, -4, 0.2),
        (2.9, 0.5, 0.7),
        (-4.0, -1.0, 0.1),
        (0.3, 0.9, 1e-12),
        (7.0, -1e-6, 0.9),
    ]
    for phi, n, mc in pi_args:
        with mp.workdps(dps_for(mc)):
            print(f"    ({f(phi)}, {f(n)}, {f(mc)}, {f(mp.ellippi(n, phi, 1 - mp.mpf(mc)))}),")
    print("];")
    print("// (n, mc, Pi(n | 1 - mc))")
    print("const PI3C: &[(f64, f64, f64)] = &[")
    pic_args = [(-1.5, 0.5), (-1e8, 0.3), (0.5, 1e-10), (-0.3, 1e-200), (0.999, 0.9), (0.0, 0.25)]
    for n, mc in pic_args:
        with mp.workdps(dps_for(mc)):
            print(f"    ({f(n)}, {f(mc)}, {f(mp.ellippi(n, 1 - mp.mpf(mc)))}),")
    print("];")
    print("// (phi, mc, F(phi | 1 - mc))")
    print("const F1: &[(f64, f64, f64)] = &[")
    for phi, mc in [(0.5, 0.5), (1.5, 1e-10), (1.5, 1e-300), (-5.0, 0.3), (12.0, 0.99), (1.0, 0.0)]:
        with mp.workdps(dps_for(mc)):
            print(f"    ({f(phi)}, {f(mc)}, {f(mp.ellipf(phi, 1 - mp.mpf(mc)))}),")
    print("];")


if __name__ == "__main__":
    import sys

    if "--rust-fixtures" in sys.argv:
        rust_fixtures()
    elif "--rust-elliptic-tables" in sys.argv:
        rust_elliptic_tables()
    else:
        print("worst", self_check())


# ---------------------------------------------------------------------------------------------
# Closed forms at any scale
#
# For inputs the fixed-point integration cannot hold (a component 1e-170 or subnormal next to
# one of 1, moments spanning 1e300, the exact separatrix far out in t): the invariants are exact
# rationals and the working precision grows with every cancellation the motion implies (the
# distance to the separatrix, the smallest component, the moment ratio, the phase at the
# largest time), so nothing is converted to a float before the end.
# ---------------------------------------------------------------------------------------------


def _mlog10(x) -> float:
    """log10 |x| of a non-zero rational or mpf (mpf exponents are unbounded; no float overflow)."""
    if isinstance(x, Fraction):
        with mp.workdps(20):
            x = mp.mpf(x.numerator) / x.denominator
    with mp.workdps(15):
        return float(mp.log10(abs(x)))


def _sign(x) -> int:
    return -1 if x < 0 else 1


def _qz(a):
    return [mp.mpf(0), mp.mpf(0), mp.sin(a / 2), mp.cos(a / 2)]


def _qx(a):
    return [mp.sin(a / 2), mp.mpf(0), mp.mpf(0), mp.cos(a / 2)]


def _q_axis(axis, angle):
    """exp(angle axis / 2) for a unit axis (scalar last)."""
    s = mp.sin(angle / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, mp.cos(angle / 2)]


_TAIL_INTEGRALS: dict = {}


def _pi_at_m1(u, n, tail):
    """Pi(gd u; n | 1) = int_0^u dx / (1 - n tanh^2 x), by quadrature (the integrand is
    1 / (1 - n) beyond ``tail`` to the working precision; the integral up to ``tail`` is
    computed once per precision)."""
    a = abs(u)

    def f(x):
        return 1 / (1 - n * mp.tanh(x) ** 2)

    def quad(b):
        return mp.quad(f, mp.linspace(0, b, max(2, int(b) + 2)))

    if a <= tail:
        val = quad(a)
    else:
        key = (n, tail, mp.mp.prec)
        if key not in _TAIL_INTEGRALS:
            _TAIL_INTEGRALS[key] = quad(tail)
        val = _TAIL_INTEGRALS[key] + (a - tail) / (1 - n)
    return val if u >= 0 else -val


def exact_closed_form(moments, omega0, quat0_xyzw, times, dps=30, want_mp=False):
    """The torque-free motion in closed form, for any positive moments and finite ``omega0``, to
    ``dps`` digits (relative, componentwise for omega at t = 0 and normwise elsewhere).

    - rest, three equal moments, or omega0 along a principal axis of three distinct moments:
      ``q(t) = q0 (x) exp(omega0 t / 2)``;
    - two equal moments: regular precession, ``R(t) = Rot(L, G t / I_t) R0 Rot(e_s, -Omega t)``,
      ``omega(t) = Rot(e_s, Omega t) omega0``, ``Omega = w_s (I_s - I_t) / I_t``;
    - three distinct moments off the separatrix: Jacobi's functions and the precession
      ``phi = G t / I3 + c (Pi(am u; n | m) - Pi(am u0; n | m))`` in the frame of
      :func:`closed_form_motion`, from exact invariants;
    - on the separatrix (``G^2 = 2 T I_mid`` exactly): ``m = (s1 B1 sech u, s2 G tanh u,
      s3 B3 sech u)`` in the frame (smallest, intermediate, largest), ``s2`` fixed by Euler's
      equation ``m1' = (1/I3 - 1/I2) m2 m3``, ``sinh u0 = s2 m2 / hypot(m1, m3)``, and the same
      precession with ``Pi(gd u; n | 1) = int_0^u dx / (1 - n tanh^2 x)`` by quadrature.

    Inputs are the exact binary values of the doubles; ``times`` may be negative. Returns
    ``(omega (M, 3), quat_xyzw (M, 4))`` floats (subnormal or zero where the value is), and the
    mpmath values too with ``want_mp``. Checked against :func:`reference_motion` in
    ``tests/test_exact_extremes.py``.
    """
    mom = [_exact(v) for v in moments]
    w = [_exact(v) for v in omega0]
    q0f = [_exact(v) for v in quat0_xyzw]
    ts = [Fraction(float(t)) for t in np.atleast_1d(np.asarray(times, dtype=float))]
    m = [a * b for a, b in zip(mom, w, strict=True)]
    G2 = sum(x * x for x in m)
    T2 = sum(a * b for a, b in zip(m, w, strict=True))
    distinct = len(set(mom)) == 3
    extra = 12 + _mlog10(max(mom) / min(mom))
    if G2 > 0:
        # Every rate is below G / I_min; the smallest non-zero component sets the digits a
        # component keeps.
        tmax = max(abs(t) for t in ts)
        if tmax > 0:
            extra += max(0.0, 0.5 * _mlog10(G2) - _mlog10(min(mom)) + _mlog10(tmax))
        extra += max(0.5 * _mlog10(G2) - _mlog10(x) for x in m if x != 0)
    order = sorted(range(3), key=lambda i: mom[i])
    lo, mid, hi = order
    d2 = G2 - T2 * mom[mid] if distinct else None
    if d2:
        extra += max(0.0, _mlog10(G2 / abs(d2)))
    wdps = int(dps + extra)
    with mp.workdps(wdps):
        f = _mpf
        q0 = [f(x) for x in q0f]
        wm = [f(x) for x in w]
        ws, qs = [], []
        steady = G2 == 0 or len(set(mom)) == 1 or (distinct and sum(x == 0 for x in w) == 2)
        if steady:
            norm = mp.sqrt(sum(x * x for x in wm))
            axis = [x / norm for x in wm] if norm > 0 else [mp.mpf(0)] * 3
            for t in ts:
                ws.append(list(wm))
                qs.append(_qmul(q0, _q_axis(axis, norm * f(t))))
        elif not distinct:
            s = [i for i in range(3) if mom.count(mom[i]) == 1][0]
            a, b = (s + 1) % 3, (s + 2) % 3
            it, i_s = mom[a], mom[s]
            om = f(w[s] * (i_s - it) / it)
            G = mp.sqrt(f(G2))
            mm = [f(x) for x in m]
            conj = [-q0[0], -q0[1], -q0[2], q0[3]]
            ls = _qmul(_qmul(q0, [mm[0], mm[1], mm[2], mp.mpf(0)]), conj)[:3]
            axis = [x / G for x in ls]
            es = [mp.mpf(0)] * 3
            es[s] = mp.mpf(1)
            for t in ts:
                tt = f(t)
                q = _qmul(_qmul(_q_axis(axis, G * tt / f(it)), q0), _q_axis(es, -om * tt))
                c, sn = mp.cos(om * tt), mp.sin(om * tt)
                wt = list(wm)
                wt[a] = c * wm[a] - sn * wm[b]
                wt[b] = sn * wm[a] + c * wm[b]
                ws.append(wt)
                qs.append(q)
        else:
            sep = d2 == 0
            idx = [lo, mid, hi] if d2 >= 0 else [hi, mid, lo]
            even = idx in ([0, 1, 2], [1, 2, 0], [2, 0, 1])
            sg = [1, 1, 1 if even else -1]
            I1, I2, I3 = (mom[i] for i in idx)
            m1, m2, m3 = (sg[k] * m[idx[k]] for k in range(3))
            D1 = G2 - T2 * I1
            D3 = G2 - T2 * I3
            G = mp.sqrt(f(G2))
            B1 = mp.sqrt(f(I1 * (-D3) / (I3 - I1)))
            B2 = G if sep else mp.sqrt(f(I2 * (-D3) / (I3 - I2)))
            B3 = mp.sqrt(f(I3 * D1 / (I3 - I1)))
            lam = mp.sqrt(f(D1 * (I3 - I2) / (I1 * I2 * I3)))
            n = f(-I3 * (I2 - I1) / (I1 * (I3 - I2)))
            cc = G * f((I3 - I1) / (I1 * I3)) / lam
            if sep:
                s1, s3 = _sign(m1), _sign(m3)
                # m1' = -s1 B1 lam sech tanh = (1/I3 - 1/I2) (s2 G tanh)(s3 B3 sech)
                s2 = -s1 * s3 * _sign(Fraction(1) / I3 - Fraction(1) / I2)
                u0 = mp.asinh(s2 * f(m2) / mp.sqrt(f(m1 * m1 + m3 * m3)))
                tail = (wdps * mp.log(10) + mp.log(abs(n) + 2)) / 2 + 3

                def comps(u):
                    return [s1 * B1 * mp.sech(u), s2 * G * mp.tanh(u), s3 * B3 * mp.sech(u)]

                def pi_(u):
                    return _pi_at_m1(u, n, tail)

            else:
                k2 = f((I2 - I1) * (-D3) / ((I3 - I2) * D1))
                s3 = _sign(m3)
                s2 = s3 * _sign(I3 - I2)
                K = mp.ellipk(k2)
                u0 = mp.ellipf(mp.atan2(s2 * f(m2) / B2, f(m1) / B1), k2)

                def comps(u):
                    sn, cn, dn = (mp.ellipfun(x, u, m=k2) for x in ("sn", "cn", "dn"))
                    return [B1 * cn, s2 * B2 * sn, s3 * B3 * dn]

                def pi_(u):
                    j = mp.nint(u / (2 * K))
                    r = u - 2 * j * K
                    am = j * mp.pi + mp.atan2(
                        mp.ellipfun("sn", r, m=k2), mp.ellipfun("cn", r, m=k2)
                    )
                    return mp.ellippi(n, am, k2)

            P = mp.matrix(3, 3)
            for k in range(3):
                P[idx[k], k] = sg[k]
            qE = _quat_from_matrix(P)
            qEinv = [-qE[0], -qE[1], -qE[2], qE[3]]
            c0 = [f(m1), f(m2), f(m3)]
            theta0 = mp.atan2(mp.sqrt(c0[0] ** 2 + c0[1] ** 2), c0[2])
            psi0 = mp.atan2(c0[0], c0[1])
            qL = _qmul(_qmul(_qmul(q0, qE), _qz(-psi0)), _qx(-theta0))
            pi0 = pi_(u0)
            inertia = [f(I1), f(I2), f(I3)]
            for t in ts:
                tt = f(t)
                u = lam * tt + u0
                mc = comps(u) if tt != 0 else c0
                wb = [mp.mpf(0)] * 3
                for k in range(3):
                    wb[idx[k]] = sg[k] * mc[k] / inertia[k]
                theta = mp.atan2(mp.sqrt(mc[0] ** 2 + mc[1] ** 2), mc[2])
                psi = mp.atan2(mc[0], mc[1])
                phi = G * tt / inertia[2] + cc * (pi_(u) - pi0)
                q = _qmul(_qmul(_qmul(_qmul(qL, _qz(phi)), _qx(theta)), _qz(psi)), qEinv)
                ws.append(wb)
                qs.append(q)
        out_w = np.array([[float(x) for x in v] for v in ws])
        out_q = np.array([[float(x) for x in v] for v in qs])
        if want_mp:
            return out_w, out_q, ws, qs
        return out_w, out_q


def exact_period(moments, omega0, dps=30):
    """The period of omega, ``4 K(m) / lambda`` (three distinct moments) or ``2 pi / |Omega|``
    (symmetric top), from exact invariants at the digits the parameter needs (any scale); None if
    the motion is not periodic."""
    mom = [_exact(v) for v in moments]
    w = [_exact(v) for v in omega0]
    m = [a * b for a, b in zip(mom, w, strict=True)]
    G2 = sum(x * x for x in m)
    T2 = sum(a * b for a, b in zip(m, w, strict=True))
    if G2 == 0 or len(set(mom)) == 1:
        return None
    with mp.workdps(dps + 10 + _mlog10(max(mom) / min(mom))):
        if len(set(mom)) == 2:
            s = [i for i in range(3) if mom.count(mom[i]) == 1][0]
            it = mom[(s + 1) % 3]
            om = w[s] * (mom[s] - it) / it
            if om == 0 or all(w[i] == 0 for i in range(3) if i != s):
                return None
            return 2 * mp.pi / abs(_mpf(om))
        lo, mid, hi = sorted(range(3), key=lambda i: mom[i])
        d2 = G2 - T2 * mom[mid]
        if d2 == 0 or sum(x == 0 for x in w) == 2:
            return None
        I1, I2, I3 = (mom[i] for i in ([lo, mid, hi] if d2 > 0 else [hi, mid, lo]))
        D1 = G2 - T2 * I1
        mc = d2 * (I3 - I1) / (D1 * (I3 - I2))
        with mp.extradps(max(0.0, -_mlog10(mc))):
            K = mp.ellipk(1 - _mpf(mc))
            return 4 * K / mp.sqrt(_mpf(D1 * (I3 - I2) / (I1 * I2 * I3)))
