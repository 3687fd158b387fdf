//! Progress and cancellation of long computations (integrations, and the mass properties and
//! eigensolves of large inputs): the public [`Monitor`], and each run's reports to it.

use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;

use crate::{Error, Result};

/// Progress and cancellation shared with running computations: integrations (see
/// [`crate::dynamics::Options::monitor`]) and the chunked mass-property and eigensolve batches.
///
/// The integration loops look at it only every [`Monitor::CHECK_EVERY`] steps (or evaluations
/// of the vector field for `Dop853`, or 256 output times for `Exact`), so that watching costs
/// nothing measurable: they add the
/// time integrated since their last look to [`Monitor::elapsed`], and stop with
/// [`Error::Interrupted`] once [`Monitor::cancel`] has been called (from any thread). A
/// finished run adds the rest of its span and counts itself in [`Monitor::finished`]. One
/// monitor may watch many runs (a batch): `elapsed` is then their sum. A monitor built
/// [`Monitor::with_on_look`] also calls a function of yours at each look, on the thread of the
/// run (to show progress, or to decide to cancel).
///
/// ```
/// use nalgebra::Vector3;
/// use polhode::dynamics::{integrate, Method, Options, State};
/// use polhode::{Error, Monitor};
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

    /// `Err(Error::Interrupted)` if cancelled, or if this thread is running a body of a batch
    /// of [`crate::simulation::simulate`] after a body before it has failed (that body's error
    /// is the batch's: the rest of the batch stops early, without changing its result).
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() || after_a_failure() {
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
        self.add_elapsed_runs(time, 1);
    }

    /// Adds `time` for each of `runs` runs: `runs` additions in one atomic update (the numbers
    /// of `runs` calls of [`Monitor::add_elapsed`] with nothing between them).
    pub(crate) fn add_elapsed_runs(&self, time: f64, runs: u32) {
        // A compare-and-swap loop: there is no atomic f64 addition. Called rarely.
        let _ = self
            .elapsed
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |bits| {
                let mut elapsed = f64::from_bits(bits);
                for _ in 0..runs {
                    elapsed += time;
                }
                Some(elapsed.to_bits())
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
pub(crate) struct Progress<'a> {
    monitor: Option<&'a Monitor>,
    /// Steps (or evaluations, or outputs) between two looks.
    every: u32,
    countdown: Cell<u32>,
    reported: Cell<f64>,
    /// The runs advancing together (the live lanes of a block of bodies), 1 for one body.
    runs: Cell<u32>,
}

impl<'a> Progress<'a> {
    /// A run from `t0` looking at `monitor` (if any) every `every` steps.
    pub(crate) fn new(monitor: Option<&'a Monitor>, t0: f64, every: u32) -> Self {
        Self {
            monitor,
            every,
            countdown: Cell::new(every),
            reported: Cell::new(t0),
            runs: Cell::new(1),
        }
    }

    /// `runs` runs advancing together (the live lanes of a block of bodies): each look adds
    /// their time to [`Monitor::elapsed`] once per run, and the end counts each run finished.
    pub(crate) fn set_runs(&self, runs: u32) {
        self.runs.set(runs);
    }

    /// Steps (or evaluations) left before the next look.
    #[inline(always)]
    pub(crate) fn budget(&self) -> u32 {
        self.countdown.get()
    }

    /// `done <= budget()` steps (or evaluations) done; `t()`, the time reached, is only
    /// called at a look.
    #[inline(always)]
    pub(crate) fn spend(&self, done: u32, t: impl FnOnce() -> f64) -> Result<()> {
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
        self.countdown.set(self.every);
        match self.monitor {
            None if after_a_failure() => Err(Error::Interrupted),
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
            monitor.add_elapsed_runs(t - reported, self.runs.get());
            self.reported.set(t);
        }
    }

    /// A part of the run reached `t` (reported, but not counted finished).
    pub(crate) fn reach(&self, t: f64) {
        if let Some(monitor) = self.monitor {
            self.report(monitor, t);
        }
    }

    /// The run reached `t_end` successfully.
    pub(crate) fn finish(&self, t_end: f64) {
        if let Some(monitor) = self.monitor {
            self.report(monitor, t_end);
            monitor
                .finished
                .fetch_add(u64::from(self.runs.get()), Ordering::Relaxed);
        }
    }
}

/// The first failure of a batch of bodies, by body index, shared by its runs: the one
/// cancellation path that a body's error trips for the rest of its batch.
///
/// The batch's error is the first failing body's by index, whatever the order in time: so once
/// body `i` has failed, the bodies after it can no longer change the result and stop (those not
/// started are skipped, those running stop at their next look, through [`Monitor::check`] or a
/// look without a monitor), while the bodies before it run on (one of them may fail first).
/// The result is the same as if every body had run to its end, in any number of threads.
#[derive(Debug)]
pub(crate) struct Failures {
    first: AtomicUsize,
}

thread_local! {
    /// The batch whose body this thread is running, and that body (both `None` between
    /// bodies).
    static RUNNING: RefCell<(Option<Arc<Failures>>, Option<usize>)> =
        const { RefCell::new((None, None)) };
}

/// Whether this thread is running a body of a batch after that batch's first failure.
fn after_a_failure() -> bool {
    RUNNING.with_borrow(|(batch, body)| match (batch, body) {
        (Some(batch), Some(body)) => batch.stops(*body),
        _ => false,
    })
}

impl Failures {
    /// A batch with no failure yet.
    pub(crate) fn new() -> Arc<Self> {
        Arc::new(Self {
            first: AtomicUsize::new(usize::MAX),
        })
    }

    /// Body `body` has failed.
    pub(crate) fn fail(&self, body: usize) {
        self.first.fetch_min(body, Ordering::Relaxed);
    }

    /// Whether body `body` comes after a body that has failed (it cannot change the result).
    pub(crate) fn stops(&self, body: usize) -> bool {
        body > self.first.load(Ordering::Relaxed)
    }

    /// `f()` run as body `body` of this batch on this thread: its looks stop it once a body
    /// before it has failed. What the thread was running before (a body of this batch or of
    /// another, which rayon may have it run inside this one) is restored afterwards, also if `f`
    /// panics.
    pub(crate) fn run_as<T>(self: &Arc<Self>, body: usize, f: impl FnOnce() -> T) -> T {
        let _restore = RUNNING.with_borrow_mut(|(batch, running)| {
            let outer = running.replace(body);
            let batch = match batch {
                Some(batch) if Arc::ptr_eq(batch, self) => None,
                _ => Some(batch.replace(Arc::clone(self))),
            };
            Restore { batch, outer }
        });
        f()
    }
}

/// What [`Failures::run_as`] restores when its body ends.
struct Restore {
    /// The batch the thread ran before, if another (`None`: the same batch).
    batch: Option<Option<Arc<Failures>>>,
    /// The body the thread ran before (`None`: none, at the top level).
    outer: Option<usize>,
}

impl Drop for Restore {
    fn drop(&mut self) {
        RUNNING.with_borrow_mut(|(batch, running)| {
            *running = self.outer;
            // What the thread ran before is put back (at the top level, nothing): the thread
            // keeps no batch once its bodies are done.
            if let Some(replaced) = self.batch.take() {
                *batch = replaced;
            }
        });
    }
}

/// The batch and body this thread is running, to run part of that body's work on another
/// thread as the same body ([`Failures::run_as`]).
pub(crate) fn running() -> Option<(Arc<Failures>, usize)> {
    RUNNING.with_borrow(|(batch, body)| match (batch, body) {
        (Some(batch), Some(body)) => Some((Arc::clone(batch), *body)),
        _ => None,
    })
}
