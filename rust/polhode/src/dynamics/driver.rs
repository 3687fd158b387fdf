//! Integration over a list of output times: the loops that run the methods (fixed-step,
//! adaptive, the closed form) and the driver [`integrate`] of one rigid body.

use nalgebra::{Quaternion, SVector, UnitQuaternion, Vector3, Vector4};

use super::dop853::{self, Settings, Tolerance};
use super::method::{check_method, check_times, Dop853Options, Method, Options, Stats};
use super::midpoint::Midpoint;
use super::rk4::Rk4;
use super::splitting::Splitting;
use super::state::{Moments, State};
use super::stepper::{Stepper, Vars};
use super::system::{pack, Field, Load, NoTorque, System};
use super::torque::{norm_of_any_size, Segment};
use crate::error::Short;
use crate::exact::FreeRotation;
use crate::monitor::{Monitor, Progress};
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

/// Number of equal substeps covering `[t_prev, t]`, none longer than `dt` by more than the
/// round-off of the times (at most 1e-12 relative): an interval that is a whole number of `dt`
/// up to that round-off is not given an extra step.
pub(crate) fn substeps(t_prev: f64, t: f64, dt: f64) -> f64 {
    let interval = t - t_prev;
    if interval <= 0.0 {
        return 0.0;
    }
    let slack = (4.0 * f64::EPSILON * (1.0 + t.abs().max(t_prev.abs()) / interval)).min(1e-12);
    ((interval / dt) * (1.0 - slack)).ceil().max(1.0)
}

/// Collects the outputs, checking that they are finite.
struct Collector {
    omega: Vec<Vector3<f64>>,
    orientation: Option<Vec<UnitQuaternion<f64>>>,
    /// The argument an error names when the solution blows up: `dt` for the fixed-step
    /// methods (a step too long for the motion), `t` for the others (a motion that leaves
    /// double precision before the times asked for).
    fixed_step: bool,
}

impl Collector {
    fn new(n: usize, with_orientation: bool, fixed_step: bool) -> Self {
        Self {
            omega: Vec::with_capacity(n),
            orientation: with_orientation.then(|| Vec::with_capacity(n)),
            fixed_step,
        }
    }

    /// The output at `t`: `w`, and the raw quaternion `q` normalised (kept only if the
    /// orientation is returned).
    #[inline]
    fn push(&mut self, t: f64, w: &Vector3<f64>, q: Option<&Vector4<f64>>) -> Result<()> {
        self.push_omega(t, w)?;
        if let (Some(att), Some(q)) = (self.orientation.as_mut(), q) {
            att.push(unit_output(self.fixed_step, t, q)?);
        }
        Ok(())
    }

    #[inline]
    fn push_omega(&mut self, t: f64, w: &Vector3<f64>) -> Result<()> {
        check_omega_output(self.fixed_step, t, w)?;
        self.omega.push(*w);
        Ok(())
    }
}

/// The error of an output `what` that is not finite at `t`. It names `dt` for the fixed-step
/// methods (a step too long for the motion), `t` for the others (a motion that leaves double
/// precision before the times asked for).
#[cold]
fn blew_up(fixed_step: bool, what: String, t: f64, value: f64) -> Error {
    let (name, hint) = if fixed_step {
        (
            "dt",
            "reduce dt (a step too long for the rotation rate or the torque).",
        )
    } else {
        (
            "t",
            "the motion leaves double precision before the times asked for.",
        )
    };
    Error::BlewUp {
        name: name.into(),
        what,
        hint: hint.into(),
        t,
        value,
    }
}

/// Checks that the angular velocity output at `t` is finite.
#[inline]
pub(crate) fn check_omega_output(fixed_step: bool, t: f64, w: &Vector3<f64>) -> Result<()> {
    for i in 0..3 {
        if !w[i].is_finite() {
            return Err(blew_up(fixed_step, format!("omega[{i}]"), t, w[i]));
        }
    }
    Ok(())
}

/// The orientation output at `t` from the raw quaternion `q`: `q / |q|`, checked finite.
#[inline]
pub(crate) fn unit_output(
    fixed_step: bool,
    t: f64,
    q: &Vector4<f64>,
) -> Result<UnitQuaternion<f64>> {
    checked_unit(fixed_step, t, q / q.norm())
}

/// The orientation output at `t` from `unit = q / |q|` (computed by the caller as
/// [`unit_output`] does), checked finite.
#[inline]
pub(crate) fn checked_unit(
    fixed_step: bool,
    t: f64,
    unit: Vector4<f64>,
) -> Result<UnitQuaternion<f64>> {
    if !unit.iter().all(|c| c.is_finite()) {
        // The orientation can blow up while omega stays finite (a step far too large for the
        // rotation rate): an error, not NaN quaternions beside finite omega.
        let value = unit
            .iter()
            .copied()
            .find(|c| !c.is_finite())
            .unwrap_or(f64::NAN);
        return Err(blew_up(
            fixed_step,
            "the orientation (its quaternion)".into(),
            t,
            value,
        ));
    }
    Ok(UnitQuaternion::new_unchecked(Quaternion::from(unit)))
}

/// Calls `f(end, output)` for each segment of `[t0, times[-1]]`, ending at every output time
/// (`output = Some(k)`) and every break strictly between (`None`).
pub(crate) fn segments(
    t0: f64,
    times: &[f64],
    breaks: &[f64],
    mut f: impl FnMut(f64, Option<usize>) -> Result<()>,
) -> Result<()> {
    let mut b = breaks.iter().copied().filter(|&x| x > t0).peekable();
    for (k, &t) in times.iter().enumerate() {
        while let Some(x) = b.next_if(|&x| x < t) {
            f(x, None)?;
        }
        f(t, Some(k))?;
    }
    Ok(())
}

/// The sorted discontinuities of the torque (empty without torque).
fn breaks_of(options: &Options) -> Vec<f64> {
    let mut breaks = options
        .torque
        .map(|t| t.discontinuities())
        .unwrap_or_default();
    breaks.retain(|t| t.is_finite());
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    breaks
}

/// The number of steps of a fixed-step run with step `dt` (see [`substeps`]), or an error
/// naming `dt` if it exceeds `options.max_steps`.
pub(crate) fn fixed_total(
    dt: f64,
    times: &[f64],
    breaks: &[f64],
    options: &Options,
) -> Result<f64> {
    let mut total = 0.0;
    let mut prev = options.t0;
    segments(options.t0, times, breaks, |t, _| {
        total += substeps(prev, t, dt);
        prev = t;
        Ok(())
    })?;
    if total > options.max_steps as f64 {
        return Err(Error::InvalidArgument {
            name: "dt".into(),
            reason: format!(
                "dt = {} needs {} steps, more than max_steps = {}.",
                Short(dt),
                Short(total),
                options.max_steps
            ),
        });
    }
    Ok(total)
}

/// The fixed-step loop of `stepper`: `n = ceil(interval / dt)` equal substeps between
/// successive output times (and torque discontinuities), so that each step lies in an interval
/// between two of those times, free of discontinuities.
fn fixed_loop<S: Stepper>(
    mut stepper: S,
    dt: f64,
    state0: &State,
    times: &[f64],
    options: &Options,
    col: &mut Collector,
) -> Result<Stats> {
    let breaks = breaks_of(options);
    let total = fixed_total(dt, times, &breaks, options)?;
    let mut y = stepper.vars(state0);
    stepper.start(&y);
    let progress = Progress::new(options.monitor, options.t0, Monitor::CHECK_EVERY);
    let mut prev = options.t0;
    segments(options.t0, times, &breaks, |t, k| {
        let n = substeps(prev, t, dt);
        if n > 0.0 {
            let h = (t - prev) / n;
            let segment = Segment::new(prev, t);
            // Runs of steps between looks, so that the loop over steps is the same as without.
            let (n, mut j) = (n as u64, 0);
            while j < n {
                let end = n.min(j + u64::from(progress.budget()));
                // On a local copy, which the compiler keeps in registers.
                let mut local = y;
                for i in j..end {
                    let t = prev + i as f64 * h;
                    stepper
                        .step(&segment, t, &mut local, h)
                        .map_err(|e| stepper.at_time(e, t))?;
                    stepper.restore(&mut local);
                }
                y = local;
                progress.spend((end - j) as u32, || prev + end as f64 * h)?;
                j = end;
            }
        }
        prev = t;
        match k {
            Some(k) => col.push(times[k], &stepper.omega(&y), Some(&y.1)),
            None => Ok(()),
        }
    })?;
    progress.finish(prev);
    let steps = total as u64;
    Ok(Stats {
        steps,
        rejected_steps: 0,
        rhs_evaluations: stepper.evaluations(steps),
    })
}

#[inline]
fn output<const N: usize>(col: &mut Collector, t: f64, y: &SVector<f64, N>) -> Result<()> {
    let w = Vector3::new(y[0], y[1], y[2]);
    if N == 7 {
        let q = Vector4::new(y[3], y[4], y[5], y[6]);
        col.push(t, &w, Some(&q))
    } else {
        col.push(t, &w, None)
    }
}

/// A vector field that ticks a [`Progress`] at each evaluation (for `Dop853`, whose loop
/// lives in [`super::dop853`]); it returns exactly what `sys` returns.
struct Watched<'s, 'p, S> {
    sys: &'s S,
    progress: &'s Progress<'p>,
}

impl<S: System<N>, const N: usize> System<N> for Watched<'_, '_, S> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        self.progress.spend(1, || t)?;
        self.sys.rhs(segment, t, y)
    }
}

/// The adaptive loop of `Dop853` on the system `sys` from `y0`.
///
/// The angular velocity is integrated in units of `scale` (a power of two, 1 but for a
/// torque-free run scaled by [`run_free`]): `y0`'s and `o.atol` are divided by it, the outputs'
/// multiplied.
fn run_dop853<S: System<N>, const N: usize>(
    sys: &S,
    y0: SVector<f64, N>,
    times: &[f64],
    options: &Options,
    o: &Dop853Options,
    scale: f64,
    col: &mut Collector,
) -> Result<Stats> {
    // One solve per segment between torque discontinuities (restarting the method there).
    let breaks = breaks_of(options);
    let t_last = times.last().copied().unwrap_or(options.t0);
    let mut ends: Vec<f64> = breaks
        .into_iter()
        .filter(|&b| b > options.t0 && b < t_last)
        .collect();
    ends.push(t_last);
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
        |k, y| {
            if scale == 1.0 {
                output(col, times[k], y)
            } else {
                let mut y = *y;
                for i in 0..3 {
                    y[i] *= scale;
                }
                output(col, times[k], &y)
            }
        },
    )
}

/// `dop853` from `options.t0` over the output `times`, one solve per segment ending at each
/// of `ends` (the discontinuities inside the run, then the last output time), restarting the
/// method there with the last step size; `out(k, y)` gets the state at `times[k]`. The one
/// adaptive loop of the rigid body ([`run_dop853`]) and of the gyrostat
/// ([`super::rotors::integrate_gyrostat`]), reporting each evaluation to the monitor.
#[allow(clippy::too_many_arguments)]
pub(crate) fn dop853_segments<S: System<N>, const N: usize>(
    sys: &S,
    y0: SVector<f64, N>,
    times: &[f64],
    options: &Options,
    o: &Dop853Options,
    tol: Tolerance<N>,
    ends: &[f64],
    renormalize: impl Fn(&mut SVector<f64, N>, &mut SVector<f64, N>) + Copy,
    mut out: impl FnMut(usize, &SVector<f64, N>) -> Result<()>,
) -> Result<Stats> {
    let mut settings = Settings {
        tol,
        first_step: o.first_step,
        max_step: o.max_step,
        max_steps: options.max_steps,
    };
    let mut stats = Stats::default();
    let progress = Progress::new(options.monitor, options.t0, Monitor::CHECK_EVERY);
    let watched = Watched {
        sys,
        progress: &progress,
    };
    let (mut t, mut y, mut first) = (options.t0, y0, 0);
    for &end in ends {
        let last = first + times[first..].partition_point(|&x| x <= end);
        let (y_end, h) = dop853::solve(
            &watched,
            t,
            &y,
            end,
            &times[first..last],
            &settings,
            renormalize,
            |k, y| out(first + k, y),
            &mut stats,
        )?;
        settings.first_step = h;
        (t, y, first) = (end, y_end, last);
    }
    progress.finish(t);
    Ok(stats)
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
    col: &mut Collector,
) -> Result<Stats> {
    let free = FreeRotation::new(*body.moments(), state0.omega, state0.orientation)?;
    exact_range(&free, times, 0..times.len(), options, |_, w, q| {
        // Checked finite by `exact_range`.
        col.omega.push(*w);
        if let (Some(list), Some(q)) = (col.orientation.as_mut(), q) {
            list.push(*q);
        }
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
/// each `j` in `range`, in order, `omega` checked finite. Looks at the monitor every
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
    mut out: impl FnMut(usize, &Vector3<f64>, Option<&UnitQuaternion<f64>>),
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
            out(j, &w, Some(&q));
        } else {
            let w = free.try_omega(t - options.t0)?;
            check_omega_output(false, t, &w)?;
            out(j, &w, None);
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
    col: &mut Collector,
) -> Result<Stats> {
    match *method {
        Method::Splitting { dt, order } => {
            let stepper = Splitting::<L, ORIENTATION>::new(body, load, order);
            fixed_loop(stepper, dt, state0, times, options, col)
        }
        Method::Midpoint { dt } => {
            let stepper = Midpoint::<L, ORIENTATION>::new(body, load);
            fixed_loop(stepper, dt, state0, times, options, col)
        }
        Method::Rk4 { dt } => {
            let stepper = Rk4::<L, ORIENTATION>::new(body, load);
            fixed_loop(stepper, dt, state0, times, options, col)
        }
        Method::Dop853(o) => {
            let field = Field { body, load };
            if ORIENTATION {
                run_dop853(&field, pack(state0), times, options, &o, 1.0, col)
            } else {
                run_dop853(&field, state0.omega, times, options, &o, 1.0, col)
            }
        }
        Method::Exact => run_exact(body, state0, times, options, col),
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
    col: &mut Collector,
) -> Result<Stats> {
    let scale = match (method, omega_scale(&state0.omega)) {
        (Method::Rk4 { .. } | Method::Midpoint { .. } | Method::Dop853(_), Some(scale)) => scale,
        _ => return run::<_, ORIENTATION>(method, body, NoTorque, state0, times, options, col),
    };
    let scaled = State {
        omega: state0.omega / scale,
        orientation: state0.orientation,
    };
    match *method {
        Method::Rk4 { dt } => {
            let inner = Rk4::<NoTorque, ORIENTATION>::new(body, NoTorque);
            let stepper = Scaled { inner, scale };
            fixed_loop(stepper, dt, &scaled, times, options, col)
        }
        Method::Midpoint { dt } => {
            let inner = Midpoint::<NoTorque, ORIENTATION>::new(body, NoTorque);
            let stepper = Scaled { inner, scale };
            fixed_loop(stepper, dt, &scaled, times, options, col)
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
                run_dop853(&field, pack(&scaled), times, options, &o, scale, col)
            } else {
                run_dop853(&field, scaled.omega, times, options, &o, scale, col)
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

impl<S: Stepper> Stepper for Scaled<S> {
    fn vars(&self, state: &State) -> Vars {
        // The state given is already in units of the scale (see `run_free`).
        self.inner.vars(state)
    }

    fn omega(&self, y: &Vars) -> Vector3<f64> {
        self.inner.omega(y) * self.scale
    }

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

/// A torque-free field, homogeneous of degree 2 in its rates (the angular velocity, and a
/// gyrostat's free wheels), with the rates in units of `scale` (see [`omega_scale`]): the
/// derivatives of `(w / scale, q, ...)` are `scale` times the field's at them.
pub(crate) struct ScaledSystem<S> {
    pub(crate) system: S,
    pub(crate) scale: f64,
}

impl<S: System<N>, const N: usize> System<N> for ScaledSystem<S> {
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        Ok(self.system.rhs(segment, t, y)? * self.scale)
    }
}

/// Integrates Euler's equations (with the orientation if `options.with_orientation`) from
/// `state0` at `options.t0`, returning the states at each of `times`.
///
/// `moments`: principal moments (any order, finite, `> 0`). `times`: output times (named `t`
/// in errors), finite, non-decreasing and `>= t0` (an output time equal to `t0` returns the
/// initial state, to round-off for `Exact`). The fixed-step methods take
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
/// initial state, the times), and its initial state with the quaternion renormalised.
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
    if options.max_steps == 0 {
        return Err(Error::NonPositive {
            name: "max_steps".into(),
            value: 0.0,
        });
    }
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
    let state0 = &start(method, state0, times, options)?;
    // The orientation is integrated if returned or if the torque depends on it.
    let orientation =
        options.with_orientation || options.torque.is_some_and(|t| t.depends_on_orientation());
    let fixed_step = matches!(
        method,
        Method::Splitting { .. } | Method::Midpoint { .. } | Method::Rk4 { .. }
    );
    let mut collector = Collector::new(times.len(), options.with_orientation, fixed_step);
    let col = &mut collector;
    let stats = match (options.torque, orientation) {
        (None, false) => run_free::<false>(method, body, state0, times, options, col),
        (None, true) => run_free::<true>(method, body, state0, times, options, col),
        (Some(torque), false) => run::<_, false>(method, body, torque, state0, times, options, col),
        (Some(torque), true) => run::<_, true>(method, body, torque, state0, times, options, col),
    }?;
    Ok(Trajectory {
        omega: collector.omega,
        orientation: collector.orientation,
        stats,
    })
}
