//! The classic fourth-order Runge-Kutta method on `(w, q)` (Hairer, Norsett & Wanner,
//! *Solving ODEs I*, II.1), the quaternion renormalised after each step.
//!
//! Explicit, order 4; neither `T` nor `|L|` is conserved (both drift by `O(h^4)` per unit time).

use nalgebra::{SVector, Vector3, Vector4};

use super::state::{quaternion_rate, Moments, State};
use super::system::{normalize7, pack, unpack, Free, System, Torqued};
use super::torque::{Segment, Torque};
use crate::Result;

/// One RK4 step of `y' = f(t, y)`, lying in `segment`.
#[inline]
pub(crate) fn rk4<S: System<N>, const N: usize>(
    sys: &S,
    segment: &Segment,
    t: f64,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<SVector<f64, N>> {
    let half = 0.5 * h;
    let k1 = sys.rhs(segment, t, y)?;
    let k2 = sys.rhs(segment, t + half, &(y + k1 * half))?;
    let k3 = sys.rhs(segment, t + half, &(y + k2 * half))?;
    let k4 = sys.rhs(segment, t + h, &(y + k3 * h))?;
    Ok(y + (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0))
}

/// One torque-free RK4 step of `(w, q)` on raw quaternion coordinates (not renormalised).
#[inline]
pub(crate) fn rk4_free_orientation(
    body: &Moments,
    w: &mut Vector3<f64>,
    q: &mut Vector4<f64>,
    h: f64,
) {
    let half = 0.5 * h;
    let (w0, q0) = (*w, *q);
    let (a1, b1) = (body.euler_rhs(&w0), quaternion_rate(&q0, &w0));
    let (w2, q2) = (w0 + a1 * half, q0 + b1 * half);
    let (a2, b2) = (body.euler_rhs(&w2), quaternion_rate(&q2, &w2));
    let (w3, q3) = (w0 + a2 * half, q0 + b2 * half);
    let (a3, b3) = (body.euler_rhs(&w3), quaternion_rate(&q3, &w3));
    let (w4, q4) = (w0 + a3 * h, q0 + b3 * h);
    let (a4, b4) = (body.euler_rhs(&w4), quaternion_rate(&q4, &w4));
    let sixth = h / 6.0;
    *w = w0 + (a1 + (a2 + a3) * 2.0 + a4) * sixth;
    *q = q0 + (b1 + (b2 + b3) * 2.0 + b4) * sixth;
}

/// One torque-free RK4 step of the angular velocity alone.
#[must_use]
pub fn rk4_step_omega(body: &Moments, omega: &Vector3<f64>, h: f64) -> Vector3<f64> {
    match rk4(&Free { body }, &Segment::of_step(0.0, h), 0.0, omega, h) {
        Ok(w) => w,
        Err(_) => unreachable!("the torque-free field cannot fail"),
    }
}

/// One torque-free RK4 step of the angular velocity and orientation (quaternion renormalised).
#[must_use]
pub fn rk4_step(body: &Moments, state: &State, h: f64) -> State {
    let mut y = match rk4(
        &Free { body },
        &Segment::of_step(0.0, h),
        0.0,
        &pack(state),
        h,
    ) {
        Ok(y) => y,
        Err(_) => unreachable!("the torque-free field cannot fail"),
    };
    normalize7(&mut y);
    unpack(&y)
}

/// One RK4 step of the angular velocity alone under `torque` from time `t`. The torque is
/// evaluated with the identity orientation: an orientation-dependent torque is an error. The
/// step is taken as free of the torque's discontinuities: a switched torque is in the state it
/// has at its midpoint (see [`Torque::try_torque_body_in`]).
pub fn rk4_step_omega_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    omega: &Vector3<f64>,
    h: f64,
) -> Result<Vector3<f64>> {
    super::torque::require_orientation_free(torque)?;
    rk4(
        &Torqued { body, torque },
        &Segment::of_step(t, h),
        t,
        omega,
        h,
    )
}

/// One RK4 step of the angular velocity and orientation under `torque` from time `t` (a step free
/// of the torque's discontinuities, as in [`rk4_step_omega_torqued`]).
pub fn rk4_step_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    state: &State,
    h: f64,
) -> Result<State> {
    let segment = Segment::of_step(t, h);
    let mut y = rk4(&Torqued { body, torque }, &segment, t, &pack(state), h)?;
    normalize7(&mut y);
    Ok(unpack(&y))
}
