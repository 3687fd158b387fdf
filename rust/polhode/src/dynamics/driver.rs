//! Integration over a list of output times, for one body or a batch of bodies.

use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use nalgebra::{Quaternion, SVector, UnitQuaternion, Vector3, Vector4};
use rayon::prelude::*;

use super::dop853::{self, Settings, Tolerance};
use super::midpoint::{cayley_update, free_midpoint, torqued_midpoint};
use super::rk4::{rk4, rk4_free_orientation};
use super::splitting::{free_flow, torqued_step, SplittingOrder};
use super::state::{Moments, State};
use super::system::{Free, System, Torqued};
use super::torque::{Segment, Torque};
use crate::error::{finite, positive, Short};
use crate::{Error, Result};

/// An integration method and its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// The closed form (torque-free only).
    Exact,
    /// Lie-Poisson splitting (see [`super::splitting`]) with fixed step `dt`.
    Splitting {
        /// Largest step.
        dt: f64,
        /// Order of the composition.
        order: SplittingOrder,
    },
    /// Implicit midpoint rule (see [`super::midpoint`]) with fixed step `dt`.
    Midpoint {
        /// Largest step.
        dt: f64,
    },
    /// Classic RK4 (see [`super::rk4`]) with fixed step `dt`.
    Rk4 {
        /// Largest step.
        dt: f64,
    },
    /// Adaptive Dormand-Prince 8(5,3) (see [`super::dop853`]).
    Dop853(Dop853Options),
}

/// Settings of the adaptive [`Method::Dop853`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dop853Options {
    /// Relative tolerance, `>= 1e-15` (default `1e-10`).
    pub rtol: f64,
    /// Absolute tolerance on the angular velocity, in its units (default `rtol |omega0|`, or
    /// for a body starting at rest `rtol |omega'(t0)| (t_end - t0)`). The quaternion
    /// components (dimensionless, `|q| = 1`) use `rtol` as absolute tolerance.
    pub atol: Option<f64>,
    /// First step (default: Hairer's estimate).
    pub first_step: Option<f64>,
    /// Largest step (default: the whole span). Steps always end at the torque's
    /// [`Torque::discontinuities`].
    pub max_step: Option<f64>,
}

impl Default for Dop853Options {
    fn default() -> Self {
        Self {
            rtol: 1e-10,
            atol: None,
            first_step: None,
            max_step: None,
        }
    }
}

impl Dop853Options {
    /// The defaults with relative tolerance `rtol`.
    #[must_use]
    pub fn with_rtol(rtol: f64) -> Self {
        Self {
            rtol,
            ..Self::default()
        }
    }
}

/// Progress and cancellation shared with running integrations (see [`Options::monitor`]).
///
/// The integration loops look at it only every [`Monitor::CHECK_EVERY`] steps (or evaluations
/// of the vector field for `Dop853`), so that watching costs nothing measurable: they add the
/// time integrated since their last look to [`Monitor::elapsed`], and stop with
/// [`Error::Interrupted`] once [`Monitor::cancel`] has been called (from any thread). A
/// finished run adds the rest of its span and counts itself in [`Monitor::finished`]. One
/// monitor may watch many runs (a batch): `elapsed` is then their sum. A monitor built
/// [`Monitor::with_on_look`] also calls a function of yours at each look, on the thread of the
/// run (to show progress, or to decide to cancel).
///
/// ```
/// use nalgebra::Vector3;
/// use polhode::dynamics::{integrate, Method, Monitor, Options, State};
/// use polhode::Error;
///
/// // A 2 kg m^2 / 3 / 4 body spinning at 1 rad/s, for 100 s in steps of 10 ms.
/// let moments = Vector3::new(2.0, 3.0, 4.0);
/// let state0 = State::from_omega(Vector3::new(0.1, 1.0, 0.1));
/// let method = Method::Rk4 { dt: 0.01 };
/// let monitor = Monitor::new();
/// let options = Options { monitor: Some(&monitor), ..Options::default() };
/// integrate(&method, &moments, &state0, &[100.0], &options).unwrap();
/// assert!((monitor.elapsed() - 100.0).abs() < 1e-9 && monitor.finished() == 1);
///
/// monitor.cancel();
/// let result = integrate(&method, &moments, &state0, &[100.0], &options);
/// assert_eq!(result.unwrap_err(), Error::Interrupted);
/// ```
#[derive(Default)]
pub struct Monitor {
    cancelled: AtomicBool,
    /// The `f64` bits of the time integrated so far, summed over the runs watched.
    elapsed: AtomicU64,
    finished: AtomicU64,
    on_look: Option<OnLook>,
}

/// A function called at each look (see [`Monitor::with_on_look`]).
type OnLook = Box<dyn Fn(&Monitor) + Send + Sync>;

impl std::fmt::Debug for Monitor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Monitor")
            .field("cancelled", &self.is_cancelled())
            .field("elapsed", &self.elapsed())
            .field("finished", &self.finished())
            .field("on_look", &self.on_look.is_some())
            .finish()
    }
}

impl Monitor {
    /// Steps (or `Dop853` evaluations of the vector field) between two looks at the monitor.
    pub const CHECK_EVERY: u32 = 4096;

    /// A monitor with nothing recorded and not cancelled.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A monitor that calls `on_look(&monitor)` at each look of a run, on the run's thread
    /// (so from several threads at once in a batch), after recording its progress and before
    /// checking for cancellation: `on_look` may call [`Monitor::cancel`]. It should be quick,
    /// or rate-limit itself (a few thousand steps can take microseconds).
    #[must_use]
    pub fn with_on_look(on_look: impl Fn(&Monitor) + Send + Sync + 'static) -> Self {
        Self {
            on_look: Some(Box::new(on_look)),
            ..Self::default()
        }
    }

    /// A look, as a run takes one every [`Monitor::CHECK_EVERY`] steps: calls the function
    /// given to [`Monitor::with_on_look`], then [`Monitor::check`]. For loops outside this
    /// crate that report to a monitor (with [`Monitor::add_elapsed`]).
    pub fn look(&self) -> Result<()> {
        if let Some(on_look) = &self.on_look {
            on_look(self);
        }
        self.check()
    }

    /// Asks every run watched to stop at its next look, with [`Error::Interrupted`]; runs
    /// not started yet stop at once.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Whether [`Monitor::cancel`] was called.
    #[must_use]
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// `Err(Error::Interrupted)` if cancelled.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    }

    /// The time integrated so far, summed over the runs watched (for N runs from `t0` to
    /// `t_end`, `N (t_end - t0)` once all have finished).
    #[must_use]
    pub fn elapsed(&self) -> f64 {
        f64::from_bits(self.elapsed.load(Ordering::Relaxed))
    }

    /// Adds `time` (the time a run advanced since it last reported) to [`Monitor::elapsed`].
    pub fn add_elapsed(&self, time: f64) {
        // A compare-and-swap loop: there is no atomic f64 addition. Called rarely.
        let _ = self
            .elapsed
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |bits| {
                Some((f64::from_bits(bits) + time).to_bits())
            });
    }

    /// The number of runs that finished successfully.
    #[must_use]
    pub fn finished(&self) -> u64 {
        self.finished.load(Ordering::Relaxed)
    }

    /// Counts one more run finished.
    pub fn add_finished(&self) {
        self.finished.fetch_add(1, Ordering::Relaxed);
    }
}

/// One run's reports to its monitor: a countdown of steps to the next look, and the time
/// already added to [`Monitor::elapsed`]. Cells, so that a vector field (`&self`) can tick it.
struct Progress<'a> {
    monitor: Option<&'a Monitor>,
    countdown: Cell<u32>,
    reported: Cell<f64>,
}

impl<'a> Progress<'a> {
    fn new(options: &Options<'a>) -> Self {
        Self {
            monitor: options.monitor,
            countdown: Cell::new(Monitor::CHECK_EVERY),
            reported: Cell::new(options.t0),
        }
    }

    /// Steps (or evaluations) left before the next look.
    #[inline(always)]
    fn budget(&self) -> u32 {
        self.countdown.get()
    }

    /// `done <= budget()` steps (or evaluations) done; `t()`, the time reached, is only
    /// called at a look.
    #[inline(always)]
    fn spend(&self, done: u32, t: impl FnOnce() -> f64) -> Result<()> {
        let left = self.countdown.get() - done;
        self.countdown.set(left);
        if left == 0 {
            self.look(t())
        } else {
            Ok(())
        }
    }

    #[cold]
    #[inline(never)]
    fn look(&self, t: f64) -> Result<()> {
        self.countdown.set(Monitor::CHECK_EVERY);
        match self.monitor {
            None => Ok(()),
            Some(monitor) => {
                self.report(monitor, t);
                monitor.look()
            }
        }
    }

    fn report(&self, monitor: &Monitor, t: f64) {
        let reported = self.reported.get();
        if t > reported {
            monitor.add_elapsed(t - reported);
            self.reported.set(t);
        }
    }

    /// The run reached `t_end` successfully.
    fn finish(&self, t_end: f64) {
        if let Some(monitor) = self.monitor {
            self.report(monitor, t_end);
            monitor.add_finished();
        }
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

/// Settings common to all methods.
#[derive(Clone, Copy)]
pub struct Options<'a> {
    /// Initial time: the state given is at `t0`; every output time is `>= t0` (default 0).
    pub t0: f64,
    /// Whether to integrate and return the orientation (default `true`). When `false` only the
    /// angular velocity is integrated (cheaper), unless the torque depends on the orientation, in
    /// which case the orientation is integrated but not returned.
    pub with_orientation: bool,
    /// External torque in body axes (default none).
    pub torque: Option<&'a dyn Torque>,
    /// Largest number of steps (accepted and rejected), an error if exceeded (default `1e8`).
    pub max_steps: u64,
    /// Progress record and cancel flag, looked at every [`Monitor::CHECK_EVERY`] steps
    /// (default none).
    pub monitor: Option<&'a Monitor>,
}

impl Default for Options<'_> {
    fn default() -> Self {
        Self {
            t0: 0.0,
            with_orientation: true,
            torque: None,
            max_steps: 100_000_000,
            monitor: None,
        }
    }
}

/// The cost of an integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Steps taken (accepted steps for `Dop853`).
    pub steps: u64,
    /// Steps rejected by the error control (`Dop853` only).
    pub rejected_steps: u64,
    /// Evaluations of the vector field (for the splitting: of the torque only, the free
    /// sub-flows being exact; for the midpoint rule: Newton iterations and torque evaluations).
    pub rhs_evaluations: u64,
}

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
fn substeps(t_prev: f64, t: f64, dt: f64) -> f64 {
    let interval = t - t_prev;
    if interval <= 0.0 {
        return 0.0;
    }
    let slack = (4.0 * f64::EPSILON * (1.0 + t.abs().max(t_prev.abs()) / interval)).min(1e-12);
    ((interval / dt) * (1.0 - slack)).ceil().max(1.0)
}

pub(crate) fn check_times(times: &[f64], t0: f64) -> Result<()> {
    finite("t0", t0)?;
    let mut prev = t0;
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            finite(&format!("t[{k}]"), t)?;
        }
        if t < prev {
            return Err(Error::InvalidArgument {
                name: "t".into(),
                reason: if k == 0 {
                    format!("expected t[0] >= t0 = {}, got {}.", Short(t0), Short(t))
                } else {
                    format!(
                        "expected non-decreasing t, got t[{}] = {} > t[{k}] = {}.",
                        k - 1,
                        Short(prev),
                        Short(t)
                    )
                },
            });
        }
        prev = t;
    }
    Ok(())
}

pub(crate) fn check_method(method: &Method) -> Result<()> {
    match method {
        Method::Exact => {}
        Method::Splitting { dt, .. } | Method::Midpoint { dt } | Method::Rk4 { dt } => {
            positive("dt", *dt)?;
        }
        Method::Dop853(o) => {
            positive("rtol", o.rtol)?;
            if o.rtol < 1e-15 {
                return Err(Error::InvalidArgument {
                    name: "rtol".into(),
                    reason: format!("expected rtol >= 1e-15 (double precision), got {}.", o.rtol),
                });
            }
            if let Some(a) = o.atol {
                positive("atol", a)?;
            }
            if let Some(h) = o.first_step {
                positive("first_step", h)?;
            }
            if let Some(h) = o.max_step {
                positive("max_step", h)?;
            }
        }
    }
    Ok(())
}

/// Collects the outputs, checking that they are finite.
struct Collector {
    omega: Vec<Vector3<f64>>,
    orientation: Option<Vec<UnitQuaternion<f64>>>,
}

impl Collector {
    fn new(n: usize, with_orientation: bool) -> Self {
        Self {
            omega: Vec::with_capacity(n),
            orientation: with_orientation.then(|| Vec::with_capacity(n)),
        }
    }

    #[inline]
    fn push(&mut self, t: f64, w: &Vector3<f64>, q: Option<&Vector4<f64>>) -> Result<()> {
        for i in 0..3 {
            if !w[i].is_finite() {
                return Err(Error::NonFinite {
                    name: format!("omega[{i}] at t = {} (the solution blew up)", Short(t)),
                    value: w[i],
                });
            }
        }
        if let (Some(att), Some(q)) = (self.orientation.as_mut(), q) {
            let unit = q / q.norm();
            if !unit.iter().all(|c| c.is_finite()) {
                // The orientation can blow up while omega stays finite (a step far too large
                // for the rotation rate): an error, not NaN quaternions beside finite omega.
                return Err(Error::NonFinite {
                    name: format!(
                        "orientation at t = {} (the solution blew up: reduce dt)",
                        Short(t)
                    ),
                    value: unit
                        .iter()
                        .copied()
                        .find(|c| !c.is_finite())
                        .unwrap_or(f64::NAN),
                });
            }
            att.push(UnitQuaternion::new_unchecked(Quaternion::from(unit)));
        }
        self.omega.push(*w);
        Ok(())
    }
}

/// Calls `f(end, output)` for each segment of `[t0, times[-1]]`, ending at every output time
/// (`output = Some(k)`) and every break strictly between (`None`).
fn segments(
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

/// The fixed-step loop: `n = ceil(interval / dt)` equal substeps between successive output
/// times (and torque discontinuities); `step(segment, t, y, h)` steps from `t` over `h`, in the
/// interval `segment` between two of those times (free of discontinuities).
fn fixed_loop<Y>(
    options: &Options,
    times: &[f64],
    dt: f64,
    y: &mut Y,
    mut step: impl FnMut(&Segment, f64, &mut Y, f64) -> Result<()>,
    mut out: impl FnMut(usize, &Y) -> Result<()>,
) -> Result<u64> {
    let breaks = breaks_of(options);
    let mut total = 0.0;
    let mut prev = options.t0;
    segments(options.t0, times, &breaks, |t, _| {
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
    let progress = Progress::new(options);
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
                for i in j..end {
                    step(&segment, prev + i as f64 * h, y, h)?;
                }
                progress.spend((end - j) as u32, || prev + end as f64 * h)?;
                j = end;
            }
        }
        prev = t;
        match k {
            Some(k) => out(k, y),
            None => Ok(()),
        }
    })?;
    progress.finish(prev);
    Ok(total as u64)
}

/// Steps between two restorations of `|m|` in the torque-free splitting without orientation.
const ANCHOR_EVERY: u32 = 16;

fn run_splitting<const ATT: bool>(
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    dt: f64,
    order: SplittingOrder,
    col: &mut Collector,
) -> Result<Stats> {
    let mut y = (
        body.angular_momentum(&state0.omega),
        state0.orientation.coords,
    );
    let mut evals = 0;
    let inverse = *body.inverse();
    let out = |k: usize, y: &(Vector3<f64>, Vector4<f64>)| {
        col.push(times[k], &y.0.component_mul(&inverse), ATT.then_some(&y.1))
    };
    // Torque-free with orientation: L_space = R(q) m is constant; recomputing m = R(q)^T L_space
    // after each step (exact in exact arithmetic) keeps the round-off of the axis rotations from
    // accumulating into a drift of L_space (~2e-18 a step otherwise, a bias not a random walk).
    let l_space = state0.orientation * y.0;
    // Without the orientation, |m| (an exact invariant of every sub-flow) is restored to its
    // initial value every few steps: the rotations are unbiased, but their round-off is a
    // random walk of |m| (up to 3e-13 over 1e6 steps of order 6 otherwise). This removes
    // round-off only; it is not the rescaling of a method that does not conserve |m|. Skipped
    // where |m|^2 would lose its relative precision (under- or overflow).
    let g2 = y.0.norm_squared();
    let anchor = !ATT && (1e-280..=1e280).contains(&g2);
    let mut count = 0u32;
    let steps = match options.torque {
        None => fixed_loop(
            options,
            times,
            dt,
            &mut y,
            |_, _, (m, q), h| {
                free_flow::<ATT>(body, m, q, h, order);
                if ATT {
                    *q /= q.norm();
                    *m = UnitQuaternion::new_unchecked(Quaternion::from(*q))
                        .inverse_transform_vector(&l_space);
                } else if anchor {
                    count = count.wrapping_add(1);
                    if count.is_multiple_of(ANCHOR_EVERY) {
                        *m *= (g2 / m.norm_squared()).sqrt();
                    }
                }
                Ok(())
            },
            out,
        )?,
        Some(torque) => fixed_loop(
            options,
            times,
            dt,
            &mut y,
            |segment, t, (m, q), h| {
                torqued_step::<dyn Torque, ATT>(
                    body, torque, segment, t, m, q, h, order, &mut evals,
                )?;
                if ATT {
                    *q /= q.norm();
                }
                Ok(())
            },
            out,
        )?,
    };
    Ok(Stats {
        steps,
        rejected_steps: 0,
        rhs_evaluations: evals,
    })
}

fn run_midpoint<const ATT: bool>(
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    dt: f64,
    col: &mut Collector,
) -> Result<Stats> {
    let mut y = (state0.omega, state0.orientation.coords);
    let mut evals = 0;
    let out =
        |k: usize, y: &(Vector3<f64>, Vector4<f64>)| col.push(times[k], &y.0, ATT.then_some(&y.1));
    let steps = fixed_loop(
        options,
        times,
        dt,
        &mut y,
        |segment, t, (w, q), h| {
            let wm = match options.torque {
                None => free_midpoint(body, w, h, &mut evals).map_err(|e| at_time(e, t))?,
                Some(torque) => torqued_midpoint::<dyn Torque, ATT>(
                    body, torque, segment, t, w, q, h, &mut evals,
                )?,
            };
            if ATT {
                *q = cayley_update(q, &wm, h);
            }
            *w = wm * 2.0 - *w;
            Ok(())
        },
        out,
    )?;
    Ok(Stats {
        steps,
        rejected_steps: 0,
        rhs_evaluations: evals,
    })
}

/// Adds the time to a Newton failure of the torque-free midpoint (which does not know it).
fn at_time(e: Error, t: f64) -> Error {
    match e {
        Error::NoConvergence { method, reason } => Error::NoConvergence {
            method,
            reason: format!("{reason} (step from t = {t})."),
        },
        other => other,
    }
}

fn run_rk4<S: System<N>, const N: usize>(
    sys: &S,
    y0: SVector<f64, N>,
    times: &[f64],
    options: &Options,
    dt: f64,
    col: &mut Collector,
) -> Result<Stats> {
    let mut y = y0;
    let steps = fixed_loop(
        options,
        times,
        dt,
        &mut y,
        |segment, t, y, h| {
            *y = rk4(sys, segment, t, y, h)?;
            if N == 7 {
                let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
                for i in 3..N {
                    y[i] /= n;
                }
            }
            Ok(())
        },
        |k, y| output(col, times[k], y),
    )?;
    Ok(Stats {
        steps,
        rejected_steps: 0,
        rhs_evaluations: 4 * steps,
    })
}

/// Steps between two renormalisations of the quaternion in the torque-free RK4.
const RENORMALISE_EVERY: u32 = 64;

fn run_rk4_free_orientation(
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
    dt: f64,
    col: &mut Collector,
) -> Result<Stats> {
    let mut y = (state0.omega, state0.orientation.coords);
    // Torque-free, the quaternion's equation is linear in q and does not act back on omega:
    // RK4 maps c q to c q' exactly, so scaling q changes nothing but the round-off. Its norm
    // drifts by O(h^5) per step; renormalising every so many steps (and at each output) keeps
    // it near 1 without a square root and a division in every step.
    let mut since = 0_u32;
    let steps = fixed_loop(
        options,
        times,
        dt,
        &mut y,
        |_, _, (w, q), h| {
            rk4_free_orientation(body, w, q, h);
            since += 1;
            if since == RENORMALISE_EVERY {
                *q /= q.norm();
                since = 0;
            }
            Ok(())
        },
        |k, (w, q)| col.push(times[k], w, Some(q)),
    )?;
    Ok(Stats {
        steps,
        rejected_steps: 0,
        rhs_evaluations: 4 * steps,
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

fn run_dop853<S: System<N>, const N: usize>(
    sys: &S,
    y0: SVector<f64, N>,
    times: &[f64],
    options: &Options,
    o: &Dop853Options,
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
        Some(atol) => atol,
        None => {
            // rtol times the scale of w: |w0|, or for a body at rest the change
            // |w'(t0)| (t_end - t0) that the torque would make.
            let w0 = Vector3::new(y0[0], y0[1], y0[2]).norm();
            if w0 > 0.0 {
                o.rtol * w0
            } else {
                let f0 = sys.rhs(&Segment::new(options.t0, ends[0]), options.t0, &y0)?;
                let span = times.last().map_or(0.0, |t| t - options.t0);
                o.rtol * Vector3::new(f0[0], f0[1], f0[2]).norm() * span
            }
        }
    };
    let mut atol = SVector::<f64, N>::repeat(o.rtol);
    for i in 0..3 {
        atol[i] = atol_w;
    }
    let mut settings = Settings {
        tol: Tolerance {
            atol,
            rtol: SVector::<f64, N>::repeat(o.rtol),
        },
        first_step: o.first_step,
        max_step: o.max_step,
        max_steps: options.max_steps,
    };
    let mut stats = Stats::default();
    let renormalize = |y: &mut SVector<f64, N>, f: &mut SVector<f64, N>| {
        if N == 7 {
            let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
            for i in 3..N {
                y[i] /= n;
                f[i] /= n;
            }
        }
    };
    let progress = Progress::new(options);
    let watched = Watched {
        sys,
        progress: &progress,
    };
    let (mut t, mut y, mut first) = (options.t0, y0, 0);
    for end in ends {
        let last = first + times[first..].partition_point(|&x| x <= end);
        let (y_end, h) = dop853::solve(
            &watched,
            t,
            &y,
            end,
            &times[first..last],
            &settings,
            renormalize,
            |k, y| output(col, times[first + k], y),
            &mut stats,
        )?;
        settings.first_step = h;
        (t, y, first) = (end, y_end, last);
    }
    progress.finish(t);
    Ok(stats)
}

/// Integrates Euler's equations (with the orientation if `options.with_orientation`) from
/// `state0` at `options.t0`, returning the states at each of `times`.
///
/// `moments`: principal moments (any order, finite, `> 0`). `times`: output times (named `t`
/// in errors), finite, non-decreasing and `>= t0` (an output time equal to `t0` returns the
/// initial state). The fixed-step methods take `n = ceil((t_k - t_{k-1}) / dt)` equal substeps
/// between successive output times, so every output time is hit exactly and no step exceeds
/// `dt`; `Dop853` steps freely and interpolates (7th-order dense output). Quaternions are
/// returned normalised.
///
/// Errors: invalid arguments (non-finite state, non-positive moment, `dt`, `rtol`, `atol`,
/// decreasing times), too many steps, a failed Newton iteration, a torque error, a solution
/// that is no longer finite, or [`Error::Interrupted`] once `options.monitor` is cancelled.
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

/// [`integrate`] with validated moments.
pub fn integrate_body(
    method: &Method,
    body: &Moments,
    state0: &State,
    times: &[f64],
    options: &Options,
) -> Result<Trajectory> {
    if let Some(monitor) = options.monitor {
        monitor.check()?;
    }
    check_method(method)?;
    state0.check_finite("state0")?;
    check_times(times, options.t0)?;
    if options.max_steps == 0 {
        return Err(Error::NonPositive {
            name: "max_steps".into(),
            value: 0.0,
        });
    }
    let norm = state0.orientation.coords.norm();
    if norm == 0.0 {
        return Err(Error::InvalidArgument {
            name: "state0.orientation".into(),
            reason: "expected a non-zero quaternion, got 0.".into(),
        });
    }
    // Renormalised, in case it was built unchecked.
    let state0 = &State {
        omega: state0.omega,
        orientation: UnitQuaternion::new_unchecked(Quaternion::from(
            state0.orientation.coords / norm,
        )),
    };
    let att =
        options.with_orientation || options.torque.is_some_and(|t| t.depends_on_orientation());
    let mut col = Collector::new(times.len(), options.with_orientation);
    let y3 = state0.omega;
    let y7 = super::system::pack(state0);
    if let Method::Exact = method {
        if options.torque.is_some() {
            return Err(Error::InvalidArgument {
                name: "torque".into(),
                reason: "the exact solution is torque-free; use dop853 or another integrator."
                    .into(),
            });
        }
        let free =
            crate::exact::FreeRotation::new(*body.moments(), state0.omega, state0.orientation)?;
        let progress = Progress::new(options);
        for (k, &t) in times.iter().enumerate() {
            if k % 256 == 255 {
                progress.look(t)?;
            }
            if options.with_orientation {
                let (w, q) = free.try_state(t - options.t0)?;
                col.push(t, &w, Some(&q.coords))?;
            } else {
                col.push(t, &free.try_omega(t - options.t0)?, None)?;
            }
        }
        progress.finish(times.last().copied().unwrap_or(options.t0));
        return Ok(Trajectory {
            omega: col.omega,
            orientation: col.orientation,
            stats: Stats {
                steps: 0,
                rejected_steps: 0,
                rhs_evaluations: times.len() as u64,
            },
        });
    }
    let stats = match (*method, att) {
        (Method::Exact, _) => unreachable!("returned above"),
        (Method::Splitting { dt, order }, true) => {
            run_splitting::<true>(body, state0, times, options, dt, order, &mut col)
        }
        (Method::Splitting { dt, order }, false) => {
            run_splitting::<false>(body, state0, times, options, dt, order, &mut col)
        }
        (Method::Midpoint { dt }, true) => {
            run_midpoint::<true>(body, state0, times, options, dt, &mut col)
        }
        (Method::Midpoint { dt }, false) => {
            run_midpoint::<false>(body, state0, times, options, dt, &mut col)
        }
        (Method::Rk4 { dt }, a) => match (options.torque, a) {
            (None, false) => run_rk4(&Free { body }, y3, times, options, dt, &mut col),
            (None, true) => run_rk4_free_orientation(body, state0, times, options, dt, &mut col),
            (Some(torque), false) => {
                run_rk4(&Torqued { body, torque }, y3, times, options, dt, &mut col)
            }
            (Some(torque), true) => {
                run_rk4(&Torqued { body, torque }, y7, times, options, dt, &mut col)
            }
        },
        (Method::Dop853(o), a) => match (options.torque, a) {
            (None, false) => run_dop853(&Free { body }, y3, times, options, &o, &mut col),
            (None, true) => run_dop853(&Free { body }, y7, times, options, &o, &mut col),
            (Some(torque), false) => {
                run_dop853(&Torqued { body, torque }, y3, times, options, &o, &mut col)
            }
            (Some(torque), true) => {
                run_dop853(&Torqued { body, torque }, y7, times, options, &o, &mut col)
            }
        },
    }?;
    Ok(Trajectory {
        omega: col.omega,
        orientation: col.orientation,
        stats,
    })
}

/// Integrates many bodies with the same method, output times and options, in parallel (rayon).
///
/// Each body's trajectory is bitwise identical to [`integrate`] on it alone, whatever the
/// number of threads. On failure, the error of the first failing body (by index) is returned,
/// its argument name suffixed with the body index. Once `options.monitor` is cancelled, the
/// bodies running stop at their next look and those not started are skipped: the result is
/// then [`Error::Interrupted`] (or an earlier body's error).
pub fn integrate_batch(
    method: &Method,
    moments: &[Vector3<f64>],
    states0: &[State],
    times: &[f64],
    options: &Options,
) -> Result<Vec<Trajectory>> {
    if moments.len() != states0.len() {
        return Err(Error::Shape {
            name: "states0".into(),
            expected: format!("({},)", moments.len()),
            got: format!("({},)", states0.len()),
        });
    }
    let results: Vec<Result<Trajectory>> = moments
        .par_iter()
        .zip(states0.par_iter())
        .map(|(m, s)| integrate(method, m, s, times, options))
        .collect();
    results
        .into_iter()
        .enumerate()
        .map(|(i, r)| r.map_err(|e| e.map_name(|name| format!("{name} (body {i})"))))
        .collect()
}
