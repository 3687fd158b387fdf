//! A rigid body's runs over a list of output times: the one place that maps a [`Method`] to its
//! stepper or loop ([`super::loops`]), the torque-free runs in units of a power of two, the
//! closed form at each output time, and the driver [`integrate`].

use nalgebra::{Quaternion, SVector, UnitQuaternion, Vector3, Vector4};

use super::dop853::{Stamp, Tolerance};
use super::loops::{
    breaks, check_omega_output, dop853_segments, fixed_loop, segment_ends, unit_output,
    ScaledSystem,
};
use super::method::{check_method, check_times, Dop853Options, Method, Options, Stats};
use super::midpoint::Midpoint;
use super::rk4::Rk4;
use super::splitting::Splitting;
use super::state::{Moments, State};
use super::stepper::{BodyStepper, Stepper, Vars};
use super::system::{pack, Field, Load, NoTorque, System};
use super::torque::{norm_of_any_size, Segment};
use crate::exact::FreeRotation;
use crate::memory::{self, Purpose};
use crate::monitor::Progress;
use crate::{Error, Result};

/// The states at the output times.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// Angular velocity in body axes at each output time.
    pub omega: Vec<Vector3<f64>>,
    /// Body-to-space orientation at each output time (`None` unless `with_orientation`).
    pub orientation: Option<Vec<UnitQuaternion<f64>>>,
    /// What the integration cost.
    pub stats: Stats,
}

/// Where a rigid body's run sends its outputs: `sink(k, omega, q)` at each output time
/// `times[k]`, in order, `omega` (body axes) finite and `q` (with the orientation) a finite unit
/// quaternion. An error from it stops the run with that error.
pub(crate) type Sink<'a> =
    dyn FnMut(usize, &Vector3<f64>, Option<&UnitQuaternion<f64>>) -> Result<()> + 'a;

/// Where a rigid body's `dop853` run sends its state at the end of each accepted step (see
/// [`run_body_with_steps`]): `steps(t, omega, q)`, as a [`Sink`] gets the output times.
pub(crate) type StepSink<'a> =
    dyn FnMut(f64, &Vector3<f64>, Option<&UnitQuaternion<f64>>) -> Result<()> + 'a;

/// A run's outputs on their way to its [`Sink`]: the angular velocity checked finite, the raw
/// quaternion normalised and checked (only if the orientation is returned).
struct Checked<'s, 'a> {
    sink: &'s mut Sink<'a>,
    /// Where the state at each accepted step of `dop853` goes, if anywhere.
    steps: Option<&'s mut StepSink<'a>>,
    times: &'s [f64],
    with_orientation: bool,
    /// The argument an error names when the solution blows up: `dt` for the fixed-step
    /// methods (a step too long for the motion), `t` for the others (a motion that leaves
    /// double precision before the times asked for).
    fixed_step: bool,
}

impl Checked<'_, '_> {
    /// The output at `times[k]`: `w`, and the raw quaternion `q` normalised.
    #[inline]
    fn push(&mut self, k: usize, w: &Vector3<f64>, q: Option<&Vector4<f64>>) -> Result<()> {
        let t = self.times[k];
        check_omega_output(self.fixed_step, t, w)?;
        match q {
            Some(q) if self.with_orientation => {
                (self.sink)(k, w, Some(&unit_output(self.fixed_step, t, q)?))
            }
            _ => (self.sink)(k, w, None),
        }
    }

    /// The output of a first-order system's state: `(w)` or `(w, q)`, the angular velocity in
    /// units of `scale`.
    #[inline]
    fn push_state<const N: usize>(
        &mut self,
        k: usize,
        y: &SVector<f64, N>,
        scale: f64,
    ) -> Result<()> {
        let mut w = Vector3::new(y[0], y[1], y[2]);
        if scale != 1.0 {
            w *= scale;
        }
        if N == 7 {
            self.push(k, &w, Some(&Vector4::new(y[3], y[4], y[5], y[6])))
        } else {
            self.push(k, &w, None)
        }
    }

    /// The state at the end of an accepted step at `t`, to the step sink if there is one,
    /// checked as an output is.
    #[inline]
    fn push_step<const N: usize>(&mut self, t: f64, y: &SVector<f64, N>, scale: f64) -> Result<()> {
        let Some(steps) = self.steps.as_mut() else {
            return Ok(());
        };
        let w = Vector3::new(y[0], y[1], y[2]) * scale;
        check_omega_output(self.fixed_step, t, &w)?;
        if N == 7 && self.with_orientation {
            let q = unit_output(self.fixed_step, t, &Vector4::new(y[3], y[4], y[5], y[6]))?;
            steps(t, &w, Some(&q))
        } else {
            steps(t, &w, None)
        }
    }
}

/// The fixed-step loop of a rigid body's `stepper` from `state0`.
fn fixed<S: BodyStepper>(
    stepper: S,
    dt: f64,
    state0: &State,
    times: &[f64],
    breaks: &[f64],
    options: &Options,
    out: &mut Checked,
) -> Result<Stats> {
    let y0 = stepper.vars(state0);
    fixed_loop(stepper, dt, y0, times, breaks, options, |k, stepper, y| {
        // At t0 (no step taken) omega0 itself: a stepper's variables (the splitting's
        // I omega) give it back only to rounding.
        let omega = if times[k] == options.t0 {
            stepper.omega_of(state0)
        } else {
            stepper.omega(y)
        };
        out.push(k, &omega, Some(&y.1))
    })
}

/// The adaptive loop of `Dop853` on the system `sys` from `y0`.
///
/// The angular velocity is integrated in units of `scale` (a power of two, 1 but for a
/// torque-free run scaled by [`run_free`]): `y0`'s and `o.atol` are divided by it, the outputs'
/// multiplied.
#[allow(clippy::too_many_arguments)]
fn run_dop853<S: System<N>, const N: usize>(
    sys: &S,
    y0: SVector<f64, N>,
    times: &[f64],
    breaks: &[f64],
    options: &Options,
    o: &Dop853Options,
    scale: f64,
    out: &mut Checked,
) -> Result<Stats> {
    // One solve per segment between torque discontinuities (restarting the method there).
    let ends = segment_ends(options.t0, times, breaks);
    let t_last = times.last().copied().unwrap_or(options.t0);
    let atol_w = match o.atol {
        Some(atol) => atol / scale,
        None => {
            // rtol times the scale of w: |w0|, unless w0 is negligible (a body at rest, or
            // nearly) beside the change the torque makes over the run, |w'| (t_end - t0) with
            // |w'| the largest rate of the initial state (w0, q0) at a few times of each
            // segment. A torque that is zero at t0 (a ramp, a sine, a window opening later)
            // made this scale 0 from t0 alone, and the solver stopped at once. The samples are
            // the initial state at other times, not states of the motion: one the torque
            // refuses (an error, or not finite) is left out, and the run itself meets the
            // torque's errors at its own states. They used to be the body at rest, where a drag
            // -w / |w| is NaN: a valid run failed with an error at t = 0.
            let w0 = Vector3::new(y0[0], y0[1], y0[2]).norm();
            if options.torque.is_none() && w0 > 0.0 {
                // Torque-free and turning: w0 is the scale.
                o.rtol * w0
            } else {
                let mut rate = 0.0_f64;
                let mut start = options.t0;
                for &end in ends.iter().take(64) {
                    let segment = Segment::new(start, end);
                    for k in 0..4 {
                        let t = start + (end - start) * (f64::from(k) / 3.0);
                        if let Ok(f) = sys.rhs(&segment, t, &y0) {
                            // |w'| scaled by a power of two first: a rate of 2e155 squared
                            // overflows, and a size of inf was a refused sample (the bits of
                            // the plain norm otherwise).
                            let size = norm_of_any_size(&Vector3::new(f[0], f[1], f[2]));
                            if size.is_finite() {
                                rate = rate.max(size);
                            }
                        }
                    }
                    start = end;
                }
                let change = rate * (t_last - options.t0);
                o.rtol
                    * if w0 >= f64::EPSILON * change {
                        w0
                    } else {
                        change
                    }
            }
        }
    };
    let mut atol = SVector::<f64, N>::repeat(o.rtol);
    for i in 0..3 {
        atol[i] = atol_w;
    }
    let tol = Tolerance {
        atol,
        rtol: SVector::<f64, N>::repeat(o.rtol),
    };
    let renormalize = |y: &mut SVector<f64, N>, f: &mut SVector<f64, N>| {
        if N == 7 {
            let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
            for i in 3..N {
                y[i] /= n;
                f[i] /= n;
            }
        }
    };
    dop853_segments(
        sys,
        y0,
        times,
        options,
        o,
        tol,
        &ends,
        renormalize,
        |stamp, y| match stamp {
            Stamp::Output(k) => out.push_state(k, y, scale),
            Stamp::Step(t) => out.push_step(t, y, scale),
        },
    )
}

/// Output times between two looks at the monitor for [`Method::Exact`].
const EXACT_CHECK_EVERY: u32 = 256;

/// [`Method::Exact`]: the closed form at each output time, reporting to the monitor as the
/// integrators do.
fn run_exact(
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    sink: &mut Sink,
) -> Result<Stats> {
    let free = FreeRotation::new(*body.moments(), state0.omega, state0.orientation)?;
    // Checked finite by `exact_range`.
    exact_range(&free, times, 0..times.len(), options, |j, w, q| {
        sink(j, w, q)
    })?;
    if let Some(monitor) = options.monitor {
        monitor.add_finished();
    }
    Ok(Stats {
        steps: 0,
        rejected_steps: 0,
        rhs_evaluations: times.len() as u64,
    })
}

/// [`Method::Exact`] at the output times `times[range]` of the motion `free` (from
/// `options.t0`; the orientation only if `options.with_orientation`): `out(j, omega, q)` for
/// each `j` in `range`, in order, `omega` checked finite (an error from `out` stops the range). Looks at the monitor every
/// [`EXACT_CHECK_EVERY`] times and reports the time from `times[range.start - 1]` (`t0` for
/// the first) to the range's last, without counting the run finished: the ranges of a run
/// add up to it, evaluated in any order (each output depends on its time alone). The first
/// error stops the range: a cancelled monitor, a time beyond [`FreeRotation::max_time`], an
/// output that is not finite.
pub(crate) fn exact_range(
    free: &FreeRotation,
    times: &[f64],
    range: std::ops::Range<usize>,
    options: &Options,
    mut out: impl FnMut(usize, &Vector3<f64>, Option<&UnitQuaternion<f64>>) -> Result<()>,
) -> Result<()> {
    let from = match range.start {
        0 => options.t0,
        k => times[k - 1],
    };
    let progress = Progress::new(options.monitor, from, EXACT_CHECK_EVERY);
    for j in range.clone() {
        let t = times[j];
        progress.spend(1, || t)?;
        // The fallible forms: a time past double precision's reach is an error naming `t`.
        if options.with_orientation {
            let (w, q) = free.try_state(t - options.t0)?;
            check_omega_output(false, t, &w)?;
            out(j, &w, Some(&q))?;
        } else {
            let w = free.try_omega(t - options.t0)?;
            check_omega_output(false, t, &w)?;
            out(j, &w, None)?;
        }
    }
    if let Some(last) = range.last() {
        progress.reach(times[last]);
    }
    Ok(())
}

/// Runs `method` on the body under `load`, with or without the orientation: the one place
/// that maps a [`Method`] to its stepper (or loop).
fn run<L: Load, const ORIENTATION: bool>(
    method: &Method,
    body: &Moments,
    load: L,
    state0: &State,
    times: &[f64],
    options: &Options,
    out: &mut Checked,
) -> Result<Stats> {
    let breaks = &breaks(options.torque, Vec::new());
    match *method {
        Method::Splitting { dt, order } => {
            let stepper = Splitting::<L, ORIENTATION>::new(body, load, order);
            fixed(stepper, dt, state0, times, breaks, options, out)
        }
        Method::Midpoint { dt } => {
            let stepper = Midpoint::<L, ORIENTATION>::new(body, load);
            fixed(stepper, dt, state0, times, breaks, options, out)
        }
        Method::Rk4 { dt } => {
            let stepper = Rk4::<L, ORIENTATION>::new(body, load);
            fixed(stepper, dt, state0, times, breaks, options, out)
        }
        Method::Dop853(o) => {
            let field = Field { body, load };
            if ORIENTATION {
                run_dop853(&field, pack(state0), times, breaks, options, &o, 1.0, out)
            } else {
                run_dop853(&field, state0.omega, times, breaks, options, &o, 1.0, out)
            }
        }
        Method::Exact => run_exact(body, state0, times, options, out.sink),
    }
}

/// The power of two in whose units a torque-free run from `omega0` integrates its angular
/// velocity, if its size lies outside `[2^-256, 2^256]`; `None` inside, where the run is the
/// plain one.
///
/// Euler's equations without torque are homogeneous: `w(t) = s u(t)` where `u` solves
/// `u' = s E(u)` from `w0 / s` (`E` the right-hand side, quadratic) and the quaternion's rate
/// is `s` times that of `u`. With `s` a power of two, each operation of a step in these units
/// is the exact image of the plain step's (none under- or overflows); the plain step's
/// products `c w_j w_k` underflowed to 0 for `|w|` below about 1e-154, so that rk4, the
/// midpoint rule and dop853 kept `w` constant, and overflowed above about 1e154.
pub(crate) fn omega_scale(omega0: &Vector3<f64>) -> Option<f64> {
    let largest = omega0.amax();
    let k = crate::eigen::exponent(largest);
    (largest > 0.0 && !(-256..=256).contains(&k)).then(|| crate::eigen::ldexp(1.0, k))
}

/// A torque-free run: [`run`], or for an angular velocity outside the range of
/// [`omega_scale`] the same method in units of that scale (rk4, the midpoint rule, dop853;
/// the splitting's exact sub-flows and the closed form need none).
fn run_free<const ORIENTATION: bool>(
    method: &Method,
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    out: &mut Checked,
) -> Result<Stats> {
    let scale = match (method, omega_scale(&state0.omega)) {
        (Method::Rk4 { .. } | Method::Midpoint { .. } | Method::Dop853(_), Some(scale)) => scale,
        _ => return run::<_, ORIENTATION>(method, body, NoTorque, state0, times, options, out),
    };
    let scaled = State {
        omega: state0.omega / scale,
        orientation: state0.orientation,
    };
    match *method {
        Method::Rk4 { dt } => {
            let inner = Rk4::<NoTorque, ORIENTATION>::new(body, NoTorque);
            let stepper = Scaled { inner, scale };
            fixed(stepper, dt, &scaled, times, &[], options, out)
        }
        Method::Midpoint { dt } => {
            let inner = Midpoint::<NoTorque, ORIENTATION>::new(body, NoTorque);
            let stepper = Scaled { inner, scale };
            fixed(stepper, dt, &scaled, times, &[], options, out)
        }
        Method::Dop853(o) => {
            let field = ScaledSystem {
                system: Field {
                    body,
                    load: NoTorque,
                },
                scale,
            };
            if ORIENTATION {
                run_dop853(&field, pack(&scaled), times, &[], options, &o, scale, out)
            } else {
                run_dop853(&field, scaled.omega, times, &[], options, &o, scale, out)
            }
        }
        Method::Splitting { .. } | Method::Exact => unreachable!("run without a scale"),
    }
}

/// A torque-free fixed-step method with its angular velocity in units of `scale` (see
/// [`omega_scale`]): its variables hold `w / scale`, and a step over `h` is the method's step
/// over `h scale` on them.
struct Scaled<S> {
    inner: S,
    scale: f64,
}

impl<S: BodyStepper> Stepper for Scaled<S> {
    type Vars = Vars;

    fn step(&mut self, segment: &Segment, t: f64, y: &mut Vars, h: f64) -> Result<()> {
        self.inner.step(segment, t, y, h * self.scale)
    }

    fn start(&mut self, y: &Vars) {
        self.inner.start(y);
    }

    fn restore(&mut self, y: &mut Vars) {
        self.inner.restore(y);
    }

    fn at_time(&self, error: Error, t: f64) -> Error {
        self.inner.at_time(error, t)
    }

    fn evaluations(&self, steps: u64) -> u64 {
        self.inner.evaluations(steps)
    }
}

impl<S: BodyStepper> BodyStepper for Scaled<S> {
    fn vars(&self, state: &State) -> Vars {
        // The state given is already in units of the scale (see `run_free`).
        self.inner.vars(state)
    }

    fn omega(&self, y: &Vars) -> Vector3<f64> {
        self.inner.omega(y) * self.scale
    }

    fn omega_of(&self, state: &State) -> Vector3<f64> {
        // Back from units of the scale, a power of two: the omega given, exactly.
        self.inner.omega_of(state) * self.scale
    }
}

/// Integrates Euler's equations (with the orientation if `options.with_orientation`) from
/// `state0` at `options.t0`, returning the states at each of `times`.
///
/// `moments`: principal moments (any order, finite, `> 0`). `times`: output times (named `t`
/// in errors), finite, non-decreasing and `>= t0` (an output time equal to `t0` returns the
/// initial state: omega as given, the orientation normalized). The fixed-step methods take
/// `n = ceil((t_k - t_{k-1}) / dt)` equal substeps between successive output times, so every
/// output time is hit exactly and no step exceeds `dt`; `Dop853` steps freely and interpolates
/// (7th-order dense output); `Exact` evaluates the closed form at each output time.
/// Quaternions are returned normalised.
///
/// Errors: invalid arguments (non-finite state, non-positive moment, `dt`, `rtol`, `atol`,
/// decreasing times, a torque for `Exact`), too many steps, a failed Newton iteration, a torque
/// error, a solution that is no longer finite, or [`Error::Interrupted`] once
/// `options.monitor` is cancelled.
pub fn integrate(
    method: &Method,
    moments: &Vector3<f64>,
    state0: &State,
    times: &[f64],
    options: &Options,
) -> Result<Trajectory> {
    let body = Moments::new(*moments)?;
    integrate_body(method, &body, state0, times, options)
}

/// The checks of a run before its first step (a cancelled monitor, the method's settings, the
/// initial state, the times, `max_steps`), and its initial state with the quaternion
/// renormalised.
pub(crate) fn start(
    method: &Method,
    state0: &State,
    times: &[f64],
    options: &Options,
) -> Result<State> {
    if let Some(monitor) = options.monitor {
        monitor.check()?;
    }
    check_method(method, options)?;
    state0.check_finite("state0")?;
    check_times(times, options.t0)?;
    normalised(state0)
}

/// The checks of [`start`] that depend on the initial state, for a caller that has made the
/// others (the monitor, the method, the times, `max_steps`) once for many runs: the state
/// checked finite, the quaternion non-zero and renormalised.
pub(crate) fn start_state(state0: &State) -> Result<State> {
    state0.check_finite("state0")?;
    normalised(state0)
}

/// `state0` with its quaternion renormalised (in case it was built unchecked); an error if it
/// is zero.
fn normalised(state0: &State) -> Result<State> {
    let norm = state0.orientation.coords.norm();
    if norm == 0.0 {
        return Err(Error::InvalidArgument {
            name: "state0.orientation".into(),
            reason: "expected a non-zero quaternion, got 0.".into(),
        });
    }
    // Renormalised, in case it was built unchecked.
    Ok(State {
        omega: state0.omega,
        orientation: UnitQuaternion::new_unchecked(Quaternion::from(
            state0.orientation.coords / norm,
        )),
    })
}

/// [`integrate`] with validated moments.
pub fn integrate_body(
    method: &Method,
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
) -> Result<Trajectory> {
    // Room for every output time: the pushes below never grow the vectors.
    let mut omega = memory::with_capacity(times.len(), Purpose::Outputs)?;
    let mut orientation = if options.with_orientation {
        Some(memory::with_capacity(times.len(), Purpose::Outputs)?)
    } else {
        None
    };
    let stats = run_body(method, body, state0, times, options, &mut |_, w, q| {
        omega.push(*w);
        if let (Some(list), Some(q)) = (orientation.as_mut(), q) {
            list.push(*q);
        }
        Ok(())
    })?;
    Ok(Trajectory {
        omega,
        orientation,
        stats,
    })
}

/// [`integrate_body`] with its outputs sent to `sink` as they come, rather than collected.
pub(crate) fn run_body(
    method: &Method,
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    sink: &mut Sink,
) -> Result<Stats> {
    run_body_with_steps(method, body, state0, times, options, sink, None)
}

/// [`run_body`], and for `dop853` the state at the end of each accepted step sent to `steps`
/// if given (in time order with the output times: a step's after those it covers).
pub(crate) fn run_body_with_steps<'a>(
    method: &Method,
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    sink: &mut Sink<'a>,
    steps: Option<&mut StepSink<'a>>,
) -> Result<Stats> {
    let state0 = &start(method, state0, times, options)?;
    // The orientation is integrated if returned or if the torque depends on it.
    let orientation =
        options.with_orientation || options.torque.is_some_and(|t| t.depends_on_orientation());
    let fixed_step = matches!(
        method,
        Method::Splitting { .. } | Method::Midpoint { .. } | Method::Rk4 { .. }
    );
    let out = &mut Checked {
        sink,
        steps,
        times,
        with_orientation: options.with_orientation,
        fixed_step,
    };
    match (options.torque, orientation) {
        (None, false) => run_free::<false>(method, body, state0, times, options, out),
        (None, true) => run_free::<true>(method, body, state0, times, options, out),
        (Some(torque), false) => run::<_, false>(method, body, torque, state0, times, options, out),
        (Some(torque), true) => run::<_, true>(method, body, torque, state0, times, options, out),
    }
}
