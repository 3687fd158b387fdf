//! How fast a motion turns: the fastest rate (rad per unit time) a body's outputs change at,
//! from its state at `t0`, so that a front end can sample a run densely enough to draw it
//! (a few dozen output times per `2 pi / rate`).
//!
//! For each body, in its principal axes with its rotors locked: the rates of its torque-free
//! motion from `omega0` (the frequency `2 pi / P` of omega in the body, the mean precession
//! about `L` in space, and the largest `|omega|` the motion reaches, the body's spin); with
//! rotors, `|L| / I_min` of the whole (a fast wheel makes the body nutate at about `h / I`);
//! with a torque, the rate it turns `L` at `t0`, `|tau| / |L|`, or from rest the spin it adds
//! over the run, `|I^-1 tau| (t_end - t0)`. Rates that change later (a torque that grows, a
//! damper that moves the spin to another axis) are not foreseen: a run that needs them asks
//! for its own output times.

use nalgebra::{UnitQuaternion, Vector3};
use rayon::prelude::*;

use super::job::Job;
use super::{Body, Simulation};
use crate::dynamics::{substeps, Gyrostat, Method};
use crate::exact::FreeRotation;
use crate::memory::{self, Purpose};
use crate::Result;

/// What sets a motion's fastest rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pace {
    /// No motion: every rate is zero.
    Rest,
    /// The body's spin: the largest `|omega|` of its torque-free motion.
    Spin,
    /// The period of omega in the body.
    Period,
    /// The mean precession about `L` in space.
    Precession,
    /// The torque: the rate it turns `L` at `t0` (or spins the body up from rest).
    Torque,
    /// The rotors: `|L| / I_min` of the body with its rotors.
    Rotors,
}

impl Pace {
    /// Its name: `"rest"`, `"spin"`, `"period"`, `"precession"`, `"torque"`, `"rotors"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Pace::Rest => "rest",
            Pace::Spin => "spin",
            Pace::Period => "period",
            Pace::Precession => "precession",
            Pace::Torque => "torque",
            Pace::Rotors => "rotors",
        }
    }
}

/// The fastest rate of a run's bodies (see the module's doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rate {
    /// Radians per unit time (0 at rest).
    pub rate: f64,
    /// What sets it.
    pub pace: Pace,
    /// The body it is that of (the first of the fastest).
    pub body: usize,
}

/// The fastest rate of the motions of `bodies` from `omega0` and `orientation0` (one shared
/// by all, or one per body, as [`super::simulate`] takes them) at `run.t0` until `t_end`:
/// the largest over the bodies. Errors are those [`super::simulate`] gives for the same
/// arguments with output times `[t0, t_end]` (the settings, then the first failing body).
///
/// ```
/// use nalgebra::{UnitQuaternion, Vector3};
/// use polhode::dynamics::Method;
/// use polhode::simulation::{fastest_rate, Body, Pace, Simulation};
///
/// // A spin of 2 rad/s about the axis of the largest moment: steady, but a motion nudged
/// // from it precesses about L at |w| (1 + sqrt((I3 - I1)(I3 - I2) / (I1 I2))) = 4 rad/s.
/// let body = Body::Moments(Vector3::new(1.0, 2.0, 3.0));
/// let run = Simulation::new(Method::Exact);
/// let rate = fastest_rate(&run, &[body], &[Vector3::new(0.0, 0.0, 2.0)],
///                         &[UnitQuaternion::identity()], 10.0)?;
/// assert_eq!((rate.rate, rate.pace), (4.0, Pace::Precession));
/// // A sphere turns at its spin.
/// let ball = Body::Moments(Vector3::new(1.0, 1.0, 1.0));
/// let rate = fastest_rate(&run, &[ball], &[Vector3::new(0.0, 0.0, 2.0)],
///                         &[UnitQuaternion::identity()], 10.0)?;
/// assert_eq!((rate.rate, rate.pace), (2.0, Pace::Spin));
/// # Ok::<(), polhode::Error>(())
/// ```
pub fn fastest_rate(
    run: &Simulation,
    bodies: &[Body],
    omega0: &[Vector3<f64>],
    orientation0: &[UnitQuaternion<f64>],
    t_end: f64,
) -> Result<Rate> {
    let n = omega0.len();
    super::one_or_each(bodies.len(), orientation0.len(), n)?;
    run.check(&[run.t0, t_end])?;
    let at = |len: usize, i: usize| if len == 1 { 0 } else { i };
    let one = |i: usize| -> Result<Rate> {
        let job = Job::new(
            &bodies[at(bodies.len(), i)],
            run.torque.as_ref(),
            &omega0[i],
            &orientation0[at(orientation0.len(), i)],
        )?;
        let (rate, pace) = body_rate(run, &job, t_end)?;
        Ok(Rate {
            rate,
            pace,
            body: i,
        })
    };
    let fastest = |a: Rate, b: Rate| if b.rate > a.rate { b } else { a };
    let rest = Rate {
        rate: 0.0,
        pace: Pace::Rest,
        body: 0,
    };
    // One result per body (through `memory`: a batch's size is the input's).
    let result = if run.parallel && n > 1 {
        memory::collect_parallel(
            (0..n).into_par_iter().map(|i| one(i).map_err(|e| (i, e))),
            Purpose::Bodies,
        )?
    } else {
        memory::collect((0..n).map(|i| one(i).map_err(|e| (i, e))), Purpose::Bodies)?
    };
    let mut best = rest;
    for item in result {
        match item {
            Ok(rate) => best = fastest(best, rate),
            Err((i, error)) => return Err(if n > 1 { error.in_body(i) } else { error }),
        }
    }
    Ok(best)
}

/// The fastest rate of one body's motion and what sets it.
fn body_rate(run: &Simulation, job: &Job, t_end: f64) -> Result<(f64, Pace)> {
    let moments = *job.moments.moments();
    let omega = job.state.omega;
    let mut best = (0.0, Pace::Rest);
    let mut consider = |rate: f64, pace: Pace| {
        if rate.is_finite() && rate > best.0 {
            best = (rate, pace);
        }
    };
    consider(largest_spin(&moments, &omega), Pace::Spin);
    if let Ok(free) = FreeRotation::new(moments, omega, UnitQuaternion::identity()) {
        if let Some(period) = free.period() {
            consider(std::f64::consts::TAU / period, Pace::Period);
        }
        if let Some(rate) = free.precession_rate_space() {
            consider(rate.abs(), Pace::Precession);
        }
    }
    let smallest = moments.min();
    let mut momentum = moments.component_mul(&omega);
    if !run.rotors.is_empty() {
        let gyrostat = Gyrostat::new(&moments, &job.axes(), &run.rotors)?;
        let vars = gyrostat.start(&omega)?;
        momentum = gyrostat.angular_momentum(&omega, &vars);
        consider(momentum.norm() / smallest, Pace::Rotors);
    }
    if let Some(torque) = &job.torque {
        let tau = torque.try_torque_body(run.t0, &omega, &job.state.orientation)?;
        let turning = tau.norm() / momentum.norm();
        let spin_up = tau.component_div(&moments).norm() * (t_end - run.t0);
        consider(turning.min(spin_up), Pace::Torque);
    }
    Ok(best)
}

/// The largest `|omega|` of the torque-free motion from `omega` (principal axes, moments
/// any order): `|omega|^2 = sum w_i^2` is linear in the squares `x_i = w_i^2`, which lie on
/// the segment cut from `x >= 0` by `sum I_i x_i = 2T` and `sum I_i^2 x_i = L^2` (the motion
/// runs through all of it), so its largest value is at an end of the segment, where one
/// square is zero. Never below `|omega|`; `|omega|` itself when the segment is a point (a
/// steady spin) or the moments are not distinct enough to solve for its ends.
fn largest_spin(moments: &Vector3<f64>, omega: &Vector3<f64>) -> f64 {
    let x = omega.component_mul(omega);
    let two_t = moments.dot(&x);
    let l2 = moments.component_mul(moments).dot(&x);
    let mut largest = x.sum();
    // An end within rounding of the orthant's face is on it.
    let slack = -1e-9 * largest;
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let (a, b) = (moments[i], moments[j]);
        let det = a * b * (b - a);
        if det == 0.0 {
            continue;
        }
        // a x_i + b x_j = 2T, a^2 x_i + b^2 x_j = L^2 (x_k = 0), by Cramer's rule.
        let xi = (two_t * b * b - l2 * b) / det;
        let xj = (l2 * a - two_t * a * a) / det;
        if xi >= slack && xj >= slack && (xi + xj).is_finite() {
            largest = largest.max(xi.max(0.0) + xj.max(0.0));
        }
    }
    largest.sqrt()
}

/// The steps a fixed-step method (the splitting, the midpoint rule, rk4) takes from `t0` to
/// `t_end` with no output time between (`ceil((t_end - t0) / dt)`, up to the round-off of the
/// times: the driver's count), so that output times every so many of those steps keep them;
/// `None` for the other methods.
#[must_use]
pub fn fixed_steps(method: &Method, t0: f64, t_end: f64) -> Option<f64> {
    match *method {
        Method::Splitting { dt, .. } | Method::Midpoint { dt } | Method::Rk4 { dt } => {
            Some(substeps(t0, t_end, dt))
        }
        Method::Exact | Method::Dop853(_) => None,
    }
}
