//! One cancellation path per call ([`Call`]): Ctrl-C, [`cancel_all`], an exception of
//! `progress` and the first exception of a Python callback (a torque function, a wheel's motor
//! torque) all stop the whole call through its [`Monitor`], and the first of them is raised
//! once the core has stopped.
//!
//! Every [`POLL`] of a long run, the calling thread looks for Ctrl-C (`check_signals`) and
//! reports progress ([`Watch`]); at each look of the run, on whichever thread, the watch also
//! compares the process-wide cancellation epoch with the one the call started in. A Python
//! callback looks at the call before each of its calls into Python ([`Call::call_back`]): once
//! the call is stopping it calls no more, and it checks the signals and the epoch itself, so
//! that Ctrl-C, `cancel_all` or another callback's exception stops a run that calls Python at
//! every step within one call, not at the next look (thousands of calls later).
//!
//! Python delivers signals to the main thread only: a call running on another thread (a
//! `ThreadPoolExecutor`, dask's workers) cannot see Ctrl-C, so [`cancel_all`] is how the main
//! thread's KeyboardInterrupt reaches it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{sync_channel, RecvTimeoutError, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::ThreadId;
use std::time::{Duration, Instant};

use polhode::Monitor;
use pyo3::prelude::*;

pyo3::import_exception!(polhode.errors, CancelledError);

/// The process-wide cancellation epoch: [`cancel_all`] advances it, and every watched call
/// stops once it differs from the value it read when it started. A count, not a flag: a
/// cancel reaches the calls running when it is made, never a later one.
static CANCEL_EPOCH: AtomicU64 = AtomicU64::new(0);

/// Cancels every polhode call running in this process, on any thread: each stops at its next
/// look (within milliseconds) and raises `polhode.errors.CancelledError` in its own thread.
/// Calls started afterwards run normally.
///
/// Ctrl-C raises KeyboardInterrupt in the main thread only, and stops a polhode call running
/// there; a call on another thread (a thread pool, dask's workers) runs on until this is
/// called, e.g. in the main thread's `except KeyboardInterrupt:`. `polhode.dask` calls it
/// when its compute is interrupted.
#[pyfunction]
pub fn cancel_all() {
    CANCEL_EPOCH.fetch_add(1, Ordering::SeqCst);
}

/// The number of [`cancel_all`] calls so far in this process: a loop of short calls (each too
/// short to be watched) reads it when it starts and stops once it has changed.
#[pyfunction]
pub fn cancel_epoch() -> u64 {
    CANCEL_EPOCH.load(Ordering::SeqCst)
}

/// How often a long run looks for Ctrl-C and reports progress.
const POLL: Duration = Duration::from_millis(50);

/// How long the calling thread waits for a batch without sleeping: a short batch then
/// returns without the ~10 us of a sleep and a wake-up.
const SPIN: Duration = Duration::from_micros(100);

/// One call's cancellation path: the monitor the core looks at, and the watch that trips it.
/// Cloned into the call's Python callbacks (an `Arc`).
#[derive(Clone)]
pub(crate) struct Call(Arc<Shared>);

struct Shared {
    monitor: Monitor,
    watch: Watch,
}

impl Call {
    /// A call of `n` bodies over `span` (for the fraction done), reporting to `progress`.
    pub(crate) fn new(progress: Option<Py<PyAny>>, n: usize, span: f64) -> Self {
        Self(Arc::new_cyclic(|shared: &std::sync::Weak<Shared>| {
            let shared = shared.clone();
            Shared {
                // At each look of the run, on its thread: the watch (it holds no reference
                // back, so the two are freed together).
                monitor: Monitor::with_on_look(move |monitor| {
                    if let Some(shared) = shared.upgrade() {
                        shared.watch.poll(monitor, false);
                    }
                }),
                watch: Watch::new(progress, n, span),
            }
        }))
    }

    /// What the core looks at.
    pub(crate) fn monitor(&self) -> &Monitor {
        &self.0.monitor
    }

    pub(crate) fn watch(&self) -> &Watch {
        &self.0.watch
    }

    /// The first exception that stopped the call (Ctrl-C, `cancel_all`, `progress`, a
    /// callback), to raise once the core has returned.
    pub(crate) fn take_raised(&self) -> Option<PyErr> {
        self.0.watch.take_raised()
    }

    /// Calls into Python for the core (`call(py)`), as one step of the call: nothing once the
    /// call is stopping (the core gets [`polhode::Error::Interrupted`]); Ctrl-C and
    /// `cancel_all` looked for first, cheaply (a flag each); an exception of `call` kept (the
    /// first) and stopping the whole call, the core getting `failed(message)` for it (the body
    /// whose run it stops is then the one named with the exception).
    pub(crate) fn call_back<T>(
        &self,
        call: impl FnOnce(Python<'_>) -> PyResult<T>,
        failed: impl FnOnce(String) -> polhode::Error,
    ) -> polhode::Result<T> {
        if self.0.monitor.is_cancelled() {
            return Err(polhode::Error::Interrupted);
        }
        Python::attach(|py| {
            if let Err(error) = self.0.watch.interrupted(py) {
                self.0.watch.stop(&self.0.monitor, error);
                return Err(polhode::Error::Interrupted);
            }
            call(py).map_err(|error| {
                let message = error.to_string();
                self.0.watch.stop(&self.0.monitor, error);
                failed(message)
            })
        })
    }
}

/// The watch over a run: every [`POLL`] the calling thread attaches, checks the signals
/// (Ctrl-C raises KeyboardInterrupt there) and calls `progress(fraction)`; at every look, on
/// any thread, the epoch of [`cancel_all`] is compared with the call's. An exception, or a
/// moved epoch (`CancelledError`), is kept to be raised, and cancels the monitor: the run
/// stops at its next look.
pub(crate) struct Watch {
    caller: ThreadId,
    /// [`CANCEL_EPOCH`] when the call started.
    epoch: u64,
    pub(crate) progress: Option<Py<PyAny>>,
    /// Bodies, and the span `t_end - t0` of each.
    n: usize,
    span: f64,
    last_poll: Mutex<Instant>,
    raised: Mutex<Option<PyErr>>,
}

impl Watch {
    pub(crate) fn new(progress: Option<Py<PyAny>>, n: usize, span: f64) -> Self {
        Self {
            caller: std::thread::current().id(),
            epoch: CANCEL_EPOCH.load(Ordering::SeqCst),
            progress,
            n,
            span,
            last_poll: Mutex::new(Instant::now()),
            raised: Mutex::new(None),
        }
    }

    /// The fraction done: the time integrated over all bodies' spans, or the bodies finished.
    fn fraction(&self, monitor: &Monitor) -> f64 {
        let done = if self.span > 0.0 {
            monitor.elapsed() / (self.n as f64 * self.span)
        } else {
            monitor.finished() as f64 / self.n as f64
        };
        done.clamp(0.0, 1.0)
    }

    /// Ctrl-C (on the main thread) or a [`cancel_all`] since the call started, as the exception
    /// to raise: a flag each, cheap enough before every call into Python.
    fn interrupted(&self, py: Python<'_>) -> PyResult<()> {
        if CANCEL_EPOCH.load(Ordering::Relaxed) != self.epoch {
            return Err(CancelledError::new_err(
                "polhode.cancel_all() stopped this run.",
            ));
        }
        py.check_signals()
    }

    /// Cancels the run if [`cancel_all`] was called since it started; then polls if on the
    /// calling thread and [`POLL`] has passed since the last poll (or `force`). Called at each
    /// look of a run (every few thousand steps), on any thread.
    pub(crate) fn poll(&self, monitor: &Monitor, force: bool) {
        if monitor.is_cancelled() {
            return;
        }
        if CANCEL_EPOCH.load(Ordering::Relaxed) != self.epoch {
            self.stop(
                monitor,
                CancelledError::new_err("polhode.cancel_all() stopped this run."),
            );
            return;
        }
        if std::thread::current().id() != self.caller {
            return;
        }
        let now = Instant::now();
        if let Ok(mut last) = self.last_poll.lock() {
            if !force && now.duration_since(*last) < POLL {
                return;
            }
            *last = now;
        }
        let fraction = self.fraction(monitor);
        let polled = Python::attach(|py| -> PyResult<()> {
            py.check_signals()?;
            // 1.0 is reported once, by the caller when the run has returned: a batch whose
            // bodies have all finished can still be polled before its result arrives.
            if let Some(progress) = self.progress.as_ref().filter(|_| fraction < 1.0) {
                progress.call1(py, (fraction,))?;
            }
            Ok(())
        });
        if let Err(error) = polled {
            self.stop(monitor, error);
        }
    }

    /// Keeps `error` to be raised (the first one, if several threads stop the run at once) and
    /// cancels the monitor.
    pub(crate) fn stop(&self, monitor: &Monitor, error: PyErr) {
        if let Ok(mut slot) = self.raised.lock() {
            slot.get_or_insert(error);
        }
        monitor.cancel();
    }

    fn take_raised(&self) -> Option<PyErr> {
        self.raised.lock().ok().and_then(|mut slot| slot.take())
    }
}

/// Runs `work` (a parallel batch) on the rayon pool while the calling thread, the GIL
/// released, waits for it and polls `watch` every [`POLL`]: a batch's threads cannot check
/// the signals, only the main thread can. The result comes back through a channel, so that
/// the wait ends as soon as it is sent.
pub(crate) fn run_on_pool<T: Send>(call: &Call, work: impl FnOnce() -> T + Send) -> Option<T> {
    let (monitor, watch) = (call.monitor(), call.watch());
    rayon::in_place_scope(|scope| {
        let (sender, receiver) = sync_channel(1);
        scope.spawn(move |_| {
            // The receiver outlives the scope's jobs: the send cannot fail.
            let _ = sender.send(work());
        });
        let start = Instant::now();
        loop {
            match receiver.try_recv() {
                Ok(value) => return Some(value),
                Err(TryRecvError::Disconnected) => return None,
                Err(TryRecvError::Empty) if start.elapsed() < SPIN => std::thread::yield_now(),
                Err(TryRecvError::Empty) => break,
            }
        }
        loop {
            match receiver.recv_timeout(POLL) {
                Ok(value) => return Some(value),
                // `work` panicked: the scope re-raises its panic when it ends.
                Err(RecvTimeoutError::Disconnected) => return None,
                // On an exception the monitor is cancelled; the work ends at its next look.
                Err(RecvTimeoutError::Timeout) => watch.poll(monitor, true),
            }
        }
    })
}
