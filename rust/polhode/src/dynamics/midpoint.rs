//! The implicit midpoint rule on `(w, q)` (Hairer, Lubich & Wanner, *Geometric Numerical
//! Integration*, IV.2 and VII.5; Austin, Krishnaprasad & Wang 1993).
//!
//! `w' = w + h f(t + h/2, w_m, q_m)`, `w_m = (w + w')/2`: the 3x3 equation for `w_m` is solved by
//! Newton's method to round-off, for the increment `z = w_m - w` (see `free_increment`). The midpoint rule conserves every quadratic invariant of the
//! free body, so `T = 1/2 sum I_i w_i^2` and `|L|^2 = sum I_i^2 w_i^2` are conserved to
//! round-off. The quaternion equation `q' = 1/2 q (x) (0, w_m)` is linear in `q`, and its
//! midpoint step is the Cayley transform `q' = q (x) (1 + a)(1 - a)^-1`, `a = (0, h w_m / 4)`,
//! i.e. `q' = q (x) ((1 - |a|^2), 2 a) / (1 + |a|^2)`: a unit quaternion exactly.
//!
//! With a torque the coupled system is solved for `w_m`, with `q_m = q (x) (1 + a)/|1 + a|` (the
//! normalised midpoint `(q + q')/2`); the Newton matrix holds the exact Jacobian of the free
//! field, plus a finite-difference Jacobian of the torque term when the iteration contracts
//! slowly (e.g. a damping torque).

use nalgebra::{Quaternion, UnitQuaternion, Vector3, Vector4};

use super::state::{Moments, State};
use super::stepper::{BodyStepper, Stepper, Vars};
use super::system::{Load, NoTorque};
use super::torque::{require_orientation_free, Segment, Torque};
use crate::{Error, Result, Short};

pub(crate) const MAX_ITERATIONS: usize = 50;

/// Why a Newton iteration that ran out of iterations failed.
pub(crate) const NO_CONVERGENCE: &str = "no convergence in 50 Newton iterations";

type Mat3 = [[f64; 3]; 3];

/// Solves `(1 - k J) x = b` by Cramer's rule; `None` if singular.
#[inline]
fn solve(j: &Mat3, k: f64, b: &Vector3<f64>) -> Option<Vector3<f64>> {
    let a = [
        [1.0 - k * j[0][0], -k * j[0][1], -k * j[0][2]],
        [-k * j[1][0], 1.0 - k * j[1][1], -k * j[1][2]],
        [-k * j[2][0], -k * j[2][1], 1.0 - k * j[2][2]],
    ];
    let (x, det) = cramer(&a, &[b[0], b[1], b[2]]);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some(Vector3::new(x[0], x[1], x[2]))
}

/// `a x = b` by Cramer's rule, and `det a` (the caller rejects a zero or non-finite one):
/// branch-free, so that the lanes (`lanes.rs`) run it for each lane in a vectorised loop with
/// the numbers of [`solve`].
#[inline(always)]
pub(crate) fn cramer(a: &[[f64; 3]; 3], b: &[f64; 3]) -> ([f64; 3], f64) {
    let c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    let c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    let c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    let det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    let inv = 1.0 / det;
    let c10 = a[0][2] * a[2][1] - a[0][1] * a[2][2];
    let c11 = a[0][0] * a[2][2] - a[0][2] * a[2][0];
    let c12 = a[0][1] * a[2][0] - a[0][0] * a[2][1];
    let c20 = a[0][1] * a[1][2] - a[0][2] * a[1][1];
    let c21 = a[0][2] * a[1][0] - a[0][0] * a[1][2];
    let c22 = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let x = [
        (c00 * b[0] + c10 * b[1] + c20 * b[2]) * inv,
        (c01 * b[0] + c11 * b[1] + c21 * b[2]) * inv,
        (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv,
    ];
    (x, det)
}

fn no_convergence(t: Option<f64>, h: f64, why: &str) -> Error {
    let at = t
        .map(|t| format!(" at t = {}", Short(t)))
        .unwrap_or_default();
    Error::NoConvergence {
        method: "implicit midpoint (Newton)".into(),
        name: "dt".into(),
        reason: format!("{why}{at} with step {}; reduce dt", Short(h)),
    }
}

/// Whether the Newton increment `d` is at round-off for the iterate `w` (or has stopped
/// decreasing there); `lanes` applies the same rule lane by lane.
#[inline]
fn converged(d: f64, prev: f64, scale: f64) -> bool {
    d <= 8.0 * f64::EPSILON * scale || (d >= prev && d <= 1e3 * f64::EPSILON * scale)
}

/// Fixed-point iterations `z <- k f(w0 + z)` that refine the explicit Euler guess of the
/// torque-free midpoint increment before Newton's method (see [`predictor`]).
pub(crate) const PREDICTOR_ITERATIONS: u64 = 3;

/// The torque-free field `f(w) = (c0 w1 w2, c1 w2 w0, c2 w0 w1)`, `c` = [`Moments::euler`]:
/// the numbers of [`Moments::euler_rhs`].
#[inline(always)]
fn field(c: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
    [c[0] * w[1] * w[2], c[1] * w[2] * w[0], c[2] * w[0] * w[1]]
}

/// `w0 + z`.
#[inline(always)]
pub(crate) fn add(w0: &[f64; 3], z: &[f64; 3]) -> [f64; 3] {
    [w0[0] + z[0], w0[1] + z[1], w0[2] + z[2]]
}

/// `k f(w)`.
#[inline(always)]
fn scaled_field(c: &[f64; 3], w: &[f64; 3], k: f64) -> [f64; 3] {
    let f = field(c, w);
    [f[0] * k, f[1] * k, f[2] * k]
}

/// The off-diagonal entries of the field's Jacobian at `w`, row by row.
#[inline(always)]
fn jacobian(c: &[f64; 3], w: &[f64; 3]) -> [[f64; 2]; 3] {
    [
        [c[0] * w[2], c[0] * w[1]],
        [c[1] * w[2], c[1] * w[0]],
        [c[2] * w[1], c[2] * w[0]],
    ]
}

/// `k |J|_inf` from the off-diagonal entries `j` of the Jacobian `J` (its diagonal is 0).
#[inline(always)]
fn contraction(j: &[[f64; 2]; 3], k: f64) -> f64 {
    let rows = [
        j[0][0].abs() + j[0][1].abs(),
        j[1][0].abs() + j[1][1].abs(),
        j[2][0].abs() + j[2][1].abs(),
    ];
    let m = if rows[0] > rows[1] { rows[0] } else { rows[1] };
    k * if m > rows[2] { m } else { rows[2] }
}

/// The first iterate for the torque-free midpoint increment `z = w_m - w0`, the root of
/// `z = k f(w0 + z)`: the explicit Euler guess `k f(w0)`, refined by [`PREDICTOR_ITERATIONS`]
/// fixed-point iterations where they contract (`k |J(w0)|_inf <= 1/4`; each gains that
/// factor). Newton's method then starts within about `(k |J|)^4 |z|` of the root, close enough
/// that one iteration reaches it by [`quadratic_done`] on ordinary steps, where the Euler
/// guess took three (the last only to see the increment vanish). Returns the iterate and
/// whether the iterations ran (counted as evaluations). Branch-free: the lanes (`lanes.rs`)
/// run it for each lane in a vectorised loop with the numbers of the scalar path.
#[inline(always)]
pub(crate) fn predictor(c: &[f64; 3], w0: &[f64; 3], k: f64) -> ([f64; 3], bool) {
    let euler = scaled_field(c, w0, k);
    let contracts = contraction(&jacobian(c, w0), k) <= 0.25;
    let mut z = euler;
    for _ in 0..PREDICTOR_ITERATIONS {
        z = scaled_field(c, &add(w0, &z), k);
    }
    (if contracts { z } else { euler }, contracts)
}

/// One Newton step for the torque-free midpoint increment `z = k f(w0 + z)` from `z`: the
/// correction `d` solving `(1 - k J(w)) d = k f(w) - z`, `w = w0 + z`, by [`cramer`], the
/// determinant (the caller rejects a zero or non-finite one) and `k |J(w)|_inf` (for
/// [`quadratic_done`]). Branch-free, shared by the scalar path and the lanes.
#[inline(always)]
pub(crate) fn newton_step(
    c: &[f64; 3],
    w0: &[f64; 3],
    z: &[f64; 3],
    k: f64,
) -> ([f64; 3], f64, f64) {
    let w = add(w0, z);
    let g = scaled_field(c, &w, k);
    let b = [g[0] - z[0], g[1] - z[1], g[2] - z[2]];
    let j = jacobian(c, &w);
    // The diagonal `1 - k J_ii` is exactly 1: `J_ii = 0` and `k = h/2` is finite and positive,
    // so `k * 0 = +0`. Written so, the products by it fold away (`x * 1 = x` exactly).
    let a = [
        [1.0, -k * j[0][0], -k * j[0][1]],
        [-k * j[1][0], 1.0, -k * j[1][1]],
        [-k * j[2][0], -k * j[2][1], 1.0],
    ];
    let (d, det) = cramer(&a, &b);
    (d, det, contraction(&j, k))
}

/// How close to the root [`quadratic_done`] asks the increment to be, relative to the largest
/// component of `w_m`: far below round-off, so that what is left is not a bias. (A remainder
/// of a quarter of an ulp, always of the same sign along a motion, drifted `T` by 2e-19 a
/// step, ten times the drift of round-off, measured on 4000 random bodies over 1e5 steps.)
const QUADRATIC_TOLERANCE: f64 = f64::EPSILON / (1u64 << 20) as f64;

/// Whether the iterate `z + d` after a Newton step of the torque-free midpoint equation is
/// its root to [`QUADRATIC_TOLERANCE`], from the step's size: the field is quadratic, so after
/// the step the residual is exactly `-k q(d)`, `q(d) = (c0 d1 d2, c1 d2 d0, c2 d0 d1)`, and
/// with `kj = k |J(w)|_inf`, `kc = k (|c0| + |c1| + |c2|)`, `dn = |d|_inf`, the mean-value
/// form `F(a) - F(b) = (1 - k J((a + b)/2)) (a - b)` (exact for a quadratic `F`) bounds the
/// distance to the root by `2 kc dn^2` while `kj + 4 kc dn <= 1/2`. The Newton step that would
/// follow could only confirm it.
#[inline(always)]
pub(crate) fn quadratic_done(kj: f64, kc: f64, dn: f64, scale: f64) -> bool {
    kj + 4.0 * kc * dn <= 0.5 && 2.0 * kc * dn * dn <= QUADRATIC_TOLERANCE * scale
}

/// The torque-free midpoint increment `z = w_m - w0` solving `z = h/2 f(w0 + z)`:
/// [`predictor`], then Newton's method until [`converged`] or [`quadratic_done`]. Solving for
/// the increment rather than for `w_m` (Hairer, Norsett & Wanner's round-off advice for
/// implicit Runge-Kutta methods) leaves one rounding of the size of `w` a step, that of
/// `w0 + 2 z`. Always inlined: called with a copy of `w0` just stored to memory, it would load
/// it back in overlapping pieces, which stalls the loads (store forwarding fails).
#[inline(always)]
fn free_increment(body: &Moments, w0: &Vector3<f64>, h: f64, evals: &mut u64) -> Result<[f64; 3]> {
    let k = 0.5 * h;
    let c = [body.euler()[0], body.euler()[1], body.euler()[2]];
    let kc = k * (c[0].abs() + c[1].abs() + c[2].abs());
    let w0 = [w0[0], w0[1], w0[2]];
    let (mut z, contracts) = predictor(&c, &w0, k);
    if contracts {
        *evals += PREDICTOR_ITERATIONS;
    }
    let mut prev = f64::INFINITY;
    for _ in 0..MAX_ITERATIONS {
        *evals += 1;
        let (d, det, kj) = newton_step(&c, &w0, &z, k);
        if det == 0.0 || !det.is_finite() {
            return Err(no_convergence(None, h, "singular Newton matrix"));
        }
        z = add(&z, &d);
        let dn = Vector3::from(d).amax();
        let scale = Vector3::from(add(&w0, &z)).amax();
        if converged(dn, prev, scale) || quadratic_done(kj, kc, dn, scale) {
            return Ok(z);
        }
        if !dn.is_finite() {
            break;
        }
        prev = dn;
    }
    Err(no_convergence(None, h, NO_CONVERGENCE))
}

/// The error of a torque-free midpoint step from `t` over `h` that failed for `why` (a
/// singular Newton matrix or [`NO_CONVERGENCE`]), as a run reports it.
#[cold]
pub(crate) fn free_failure(why: &str, t: f64, h: f64) -> Error {
    at_time(no_convergence(None, h, why), t)
}

/// `q (x) cay(h w_m)` with the Cayley transform written above, renormalised.
#[inline]
fn cayley_update(q: &Vector4<f64>, wm: &Vector3<f64>, h: f64) -> Vector4<f64> {
    Vector4::from(cayley(
        &[q[0], q[1], q[2], q[3]],
        &[wm[0], wm[1], wm[2]],
        0.25 * h,
    ))
}

/// `q (x) cay(h w_m)` on raw coordinates, `c = h/4`: with `a = c w_m`, the product
/// `q (x) (2 a, 1 - |a|^2)` divided by its norm, which is `(1 + |a|^2) |q|`: the Cayley factor
/// `(2 a, 1 - |a|^2) / (1 + |a|^2)` and the renormalisation of `q` in one division (a unit
/// quaternion to round-off). Branch-free, shared by the scalar path and the lanes.
#[inline(always)]
pub(crate) fn cayley(q: &[f64; 4], wm: &[f64; 3], c: f64) -> [f64; 4] {
    let a = [wm[0] * c, wm[1] * c, wm[2] * c];
    let a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    let pv = [a[0] * 2.0, a[1] * 2.0, a[2] * 2.0];
    let ps = 1.0 - a2;
    let (qv, qs) = ([q[0], q[1], q[2]], q[3]);
    let x = [
        qv[1] * pv[2] - qv[2] * pv[1],
        qv[2] * pv[0] - qv[0] * pv[2],
        qv[0] * pv[1] - qv[1] * pv[0],
    ];
    let out = [
        pv[0] * qs + qv[0] * ps + x[0],
        pv[1] * qs + qv[1] * ps + x[1],
        pv[2] * qs + qv[2] * ps + x[2],
        qs * ps - (qv[0] * pv[0] + qv[1] * pv[1] + qv[2] * pv[2]),
    ];
    let r =
        1.0 / ((out[0] * out[0] + out[2] * out[2]) + (out[1] * out[1] + out[3] * out[3])).sqrt();
    [out[0] * r, out[1] * r, out[2] * r, out[3] * r]
}

/// `q (x) (pv, ps)` on raw coordinates `(x, y, z, w)`.
#[inline]
fn mul(q: &Vector4<f64>, pv: &Vector3<f64>, ps: f64) -> Vector4<f64> {
    let qv = Vector3::new(q[0], q[1], q[2]);
    let v = pv * q[3] + qv * ps + qv.cross(pv);
    Vector4::new(v[0], v[1], v[2], q[3] * ps - qv.dot(pv))
}

/// The midpoint orientation `q (x) (1 + a)/|1 + a|`, `a = (0, h w_m / 4)`.
#[inline]
fn half_orientation(q: &Vector4<f64>, wm: &Vector3<f64>, h: f64) -> UnitQuaternion<f64> {
    let a = wm * (0.25 * h);
    let p = mul(q, &a, 1.0);
    UnitQuaternion::new_unchecked(Quaternion::from(p / p.norm()))
}

/// The torque term `I^-1 tau(t_m, w_m, q_m)`, for a step in `segment`.
#[inline]
#[allow(clippy::too_many_arguments)]
fn torque_term<T: Torque + ?Sized, const ATT: bool>(
    body: &Moments,
    torque: &T,
    segment: &Segment,
    tm: f64,
    q: &Vector4<f64>,
    w: &Vector3<f64>,
    h: f64,
    evals: &mut u64,
) -> Result<Vector3<f64>> {
    *evals += 1;
    let orientation = if ATT {
        half_orientation(q, w, h)
    } else {
        UnitQuaternion::identity()
    };
    Ok(body
        .inverse()
        .component_mul(&torque.try_torque_body_in(segment, tm, w, &orientation)?))
}

/// The midpoint increment `z = w_m - w0` under a torque, from `(w0, q)` at time `t`, for a
/// step lying in `segment` (solved for the increment, as [`free_increment`]).
#[allow(clippy::too_many_arguments)]
fn torqued_increment<T: Torque + ?Sized, const ATT: bool>(
    body: &Moments,
    torque: &T,
    segment: &Segment,
    t: f64,
    w0: &Vector3<f64>,
    q: &Vector4<f64>,
    h: f64,
    evals: &mut u64,
) -> Result<Vector3<f64>> {
    let k = 0.5 * h;
    let tm = t + k;
    let g0 = torque_term::<T, ATT>(body, torque, segment, t, q, w0, 0.0, evals)?;
    let mut z = (body.euler_rhs(w0) + g0) * k;
    let mut prev = f64::INFINITY;
    let mut torque_jacobian: Option<Mat3> = None;
    for iteration in 0..MAX_ITERATIONS {
        let w = w0 + z;
        let g = torque_term::<T, ATT>(body, torque, segment, tm, q, &w, h, evals)?;
        let r = (body.euler_rhs(&w) + g) * k - z;
        let mut jac = body.euler_jacobian(&w);
        if let Some(jt) = &torque_jacobian {
            for (row, jt_row) in jac.iter_mut().zip(jt) {
                for (x, y) in row.iter_mut().zip(jt_row) {
                    *x += y;
                }
            }
        }
        let d = solve(&jac, k, &r)
            .ok_or_else(|| no_convergence(Some(t), h, "singular Newton matrix"))?;
        z += d;
        let w = w0 + z;
        let dn = d.amax();
        if converged(dn, prev, w.amax().max(w0.amax())) {
            return Ok(z);
        }
        if !dn.is_finite() {
            break;
        }
        if torque_jacobian.is_none() && iteration >= 1 && dn > 0.1 * prev {
            // Slow contraction: the torque depends strongly on w. Add its Jacobian by forward
            // differences (3 evaluations).
            let g = torque_term::<T, ATT>(body, torque, segment, tm, q, &w, h, evals)?;
            let scale = w.amax().max(w0.amax()).max((g * h).amax());
            let mut jt = [[0.0; 3]; 3];
            for j in 0..3 {
                let mut wp = w;
                let e = f64::EPSILON.sqrt() * scale.max(f64::MIN_POSITIVE.sqrt());
                wp[j] += e;
                let e = wp[j] - w[j];
                let gp = torque_term::<T, ATT>(body, torque, segment, tm, q, &wp, h, evals)?;
                for (i, row) in jt.iter_mut().enumerate() {
                    row[j] = (gp[i] - g[i]) / e;
                }
            }
            torque_jacobian = Some(jt);
        }
        prev = dn;
    }
    Err(no_convergence(Some(t), h, NO_CONVERGENCE))
}

/// Adds the time to a Newton failure of the torque-free midpoint (which does not know it).
fn at_time(e: Error, t: f64) -> Error {
    match e {
        Error::NoConvergence {
            method,
            name,
            reason,
        } => Error::NoConvergence {
            method,
            name,
            reason: format!("{reason} (step from t = {}).", Short(t)),
        },
        other => other,
    }
}

/// The implicit midpoint rule under `L`, with or without the orientation.
pub(crate) struct Midpoint<'a, L, const ORIENTATION: bool> {
    body: &'a Moments,
    load: L,
    /// Fixed-point and Newton iterations, and torque evaluations.
    evals: u64,
}

impl<'a, L: Load, const ORIENTATION: bool> Midpoint<'a, L, ORIENTATION> {
    pub(crate) fn new(body: &'a Moments, load: L) -> Self {
        Self {
            body,
            load,
            evals: 0,
        }
    }
}

impl<L: Load, const ORIENTATION: bool> BodyStepper for Midpoint<'_, L, ORIENTATION> {}

impl<L: Load, const ORIENTATION: bool> Stepper for Midpoint<'_, L, ORIENTATION> {
    type Vars = Vars;

    #[inline(always)]
    fn step(&mut self, segment: &Segment, t: f64, y: &mut Vars, h: f64) -> Result<()> {
        let (w, q) = *y;
        let z = match self.load.torque() {
            None => Vector3::from(free_increment(self.body, &w, h, &mut self.evals)?),
            Some(torque) => torqued_increment::<_, ORIENTATION>(
                self.body,
                torque,
                segment,
                t,
                &w,
                &q,
                h,
                &mut self.evals,
            )?,
        };
        if ORIENTATION {
            y.1 = cayley_update(&q, &(w + z), h);
        }
        // One rounding of the size of w: the increment carries the step.
        y.0 = w + z * 2.0;
        Ok(())
    }

    fn at_time(&self, error: Error, t: f64) -> Error {
        match self.load.torque() {
            None => at_time(error, t),
            Some(_) => error,
        }
    }

    fn evaluations(&self, _steps: u64) -> u64 {
        self.evals
    }
}

/// One implicit midpoint step of `state` from `t` under `load`.
#[inline]
fn step<L: Load, const ORIENTATION: bool>(
    body: &Moments,
    load: L,
    t: f64,
    state: &State,
    h: f64,
) -> Result<State> {
    let mut stepper = Midpoint::<L, ORIENTATION>::new(body, load);
    let mut y = stepper.vars(state);
    stepper.step(&Segment::of_step(t, h), t, &mut y, h)?;
    Ok(State {
        omega: y.0,
        orientation: UnitQuaternion::new_unchecked(Quaternion::from(y.1)),
    })
}

/// One torque-free implicit midpoint step of the angular velocity alone.
pub fn midpoint_step_omega(body: &Moments, omega: &Vector3<f64>, h: f64) -> Result<Vector3<f64>> {
    Ok(step::<_, false>(body, NoTorque, 0.0, &State::from_omega(*omega), h)?.omega)
}

/// One torque-free implicit midpoint step of the angular velocity and orientation.
pub fn midpoint_step(body: &Moments, state: &State, h: f64) -> Result<State> {
    step::<_, true>(body, NoTorque, 0.0, state, h)
}

/// One implicit midpoint step of the angular velocity alone under `torque`, from time `t`. The
/// torque is evaluated with the identity orientation: an orientation-dependent torque is an
/// error. The step is taken as free of the torque's discontinuities: a switched torque is in
/// the state it has at its midpoint (see [`Torque::try_torque_body_in`]).
pub fn midpoint_step_omega_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    omega: &Vector3<f64>,
    h: f64,
) -> Result<Vector3<f64>> {
    require_orientation_free(torque)?;
    Ok(step::<_, false>(body, torque, t, &State::from_omega(*omega), h)?.omega)
}

/// One implicit midpoint step of the angular velocity and orientation under `torque`, from `t`
/// (a step free of the torque's discontinuities, as in [`midpoint_step_omega_torqued`]).
pub fn midpoint_step_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    state: &State,
    h: f64,
) -> Result<State> {
    step::<_, true>(body, torque, t, state, h)
}
