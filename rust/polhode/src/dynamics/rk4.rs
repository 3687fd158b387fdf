//! The classic fourth-order Runge-Kutta method on `(w, q)` (Hairer, Norsett & Wanner,
//! *Solving ODEs I*, II.1), the quaternion renormalised after each step.
//!
//! Explicit, order 4; neither `T` nor `|L|` is conserved (both drift by `O(h^4)` per unit time).

use nalgebra::Vector3;

use super::state::{Moments, State};
use super::stepper::{BodyStepper, Stepper, Vars};
use super::system::{join, rate, unit_state, Load, NoTorque};
use super::torque::{require_orientation_free, Segment, Torque};
use crate::Result;

/// Steps between two renormalisations of the quaternion in a torque-free run.
const RENORMALISE_EVERY: u32 = 64;

/// RK4 on `(w, q)` under `L`, with or without the orientation.
pub(crate) struct Rk4<'a, L, const ORIENTATION: bool> {
    body: &'a Moments,
    load: L,
    /// Steps since the quaternion was last renormalised (torque-free runs).
    since: u32,
}

impl<'a, L: Load, const ORIENTATION: bool> Rk4<'a, L, ORIENTATION> {
    pub(crate) fn new(body: &'a Moments, load: L) -> Self {
        Self {
            body,
            load,
            since: 0,
        }
    }
}

impl<L: Load, const ORIENTATION: bool> BodyStepper for Rk4<'_, L, ORIENTATION> {}

impl<L: Load, const ORIENTATION: bool> Stepper for Rk4<'_, L, ORIENTATION> {
    type Vars = Vars;

    #[inline(always)]
    fn step(&mut self, segment: &Segment, t: f64, (w, q): &mut Vars, h: f64) -> Result<()> {
        let (body, load) = (self.body, self.load);
        // `rate` gives 2 q' (`b`): its factor 1/2 is in the coefficients, `quarter` for `half`
        // and `twelfth` for `sixth` (the same numbers in the normal range: powers of two).
        let half = 0.5 * h;
        let quarter = 0.5 * half;
        let (w0, q0) = (*w, *q);
        let (a1, b1) = rate::<L, ORIENTATION>(body, load, segment, t, &w0, &q0)?;
        let (w2, q2) = (w0 + a1 * half, q0 + b1 * quarter);
        let (a2, b2) = rate::<L, ORIENTATION>(body, load, segment, t + half, &w2, &q2)?;
        let (w3, q3) = (w0 + a2 * half, q0 + b2 * quarter);
        let (a3, b3) = rate::<L, ORIENTATION>(body, load, segment, t + half, &w3, &q3)?;
        let (w4, q4) = (w0 + a3 * h, q0 + b3 * half);
        let (a4, b4) = rate::<L, ORIENTATION>(body, load, segment, t + h, &w4, &q4)?;
        let sixth = h / 6.0;
        let twelfth = 0.5 * sixth;
        // `m + m` is `2 m` exactly, an addition rather than a product.
        let m = a2 + a3;
        *w = w0 + (a1 + (m + m) + a4) * sixth;
        if ORIENTATION {
            let m = b2 + b3;
            *q = q0 + (b1 + (m + m) + b4) * twelfth;
        }
        Ok(())
    }

    /// Under a torque (which sees `q / |q|`), the quaternion is renormalised after each step
    /// (`|q|^2` summed in index order). Torque-free, its equation is linear in `q` and does not
    /// act back on `w`: RK4 maps `c q` to `c q'` exactly, so scaling `q` changes nothing but
    /// the round-off. Its norm drifts by `O(h^5)` per step; renormalising every so many steps
    /// (and at each output) keeps it near 1 without a square root and a division in every step.
    #[inline(always)]
    fn restore(&mut self, (_, q): &mut Vars) {
        if ORIENTATION {
            if self.load.torque().is_some() {
                *q /= (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
            } else {
                self.since += 1;
                if self.since == RENORMALISE_EVERY {
                    *q /= q.norm();
                    self.since = 0;
                }
            }
        }
    }

    fn evaluations(&self, steps: u64) -> u64 {
        4 * steps
    }
}

/// One RK4 step of `state` from `t` under `load` (it cannot fail without a torque).
#[inline]
fn step<L: Load, const ORIENTATION: bool>(
    body: &Moments,
    load: L,
    t: f64,
    state: &State,
    h: f64,
) -> Result<Vars> {
    let mut stepper = Rk4::<L, ORIENTATION>::new(body, load);
    let mut y = stepper.vars(state);
    stepper.step(&Segment::of_step(t, h), t, &mut y, h)?;
    Ok(y)
}

/// One torque-free RK4 step of the angular velocity alone.
#[must_use]
pub fn rk4_step_omega(body: &Moments, omega: &Vector3<f64>, h: f64) -> Vector3<f64> {
    match step::<_, false>(body, NoTorque, 0.0, &State::from_omega(*omega), h) {
        Ok((w, _)) => w,
        Err(_) => unreachable!("the torque-free field cannot fail"),
    }
}

/// One torque-free RK4 step of the angular velocity and orientation (quaternion renormalised).
#[must_use]
pub fn rk4_step(body: &Moments, state: &State, h: f64) -> State {
    match step::<_, true>(body, NoTorque, 0.0, state, h) {
        Ok((w, q)) => unit_state(join(&w, &q)),
        Err(_) => unreachable!("the torque-free field cannot fail"),
    }
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
    require_orientation_free(torque)?;
    Ok(step::<_, false>(body, torque, t, &State::from_omega(*omega), h)?.0)
}

/// One RK4 step of the angular velocity and orientation under `torque` from time `t` (a step
/// free of the torque's discontinuities, as in [`rk4_step_omega_torqued`]).
pub fn rk4_step_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    state: &State,
    h: f64,
) -> Result<State> {
    let (w, q) = step::<_, true>(body, torque, t, state, h)?;
    Ok(unit_state(join(&w, &q)))
}
