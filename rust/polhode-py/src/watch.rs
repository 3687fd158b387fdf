//! The calling thread's watch over a long run: Ctrl-C and progress, polled while the core
//! works with the GIL released.
//!
//! Every [`POLL`] of a long run, the calling thread looks for Ctrl-C (`check_signals`) and
//! reports progress ([`Watch`]); on an exception it cancels the run through its [`Monitor`]
//! and raises once the run has stopped.

use std::sync::mpsc::{sync_channel, RecvTimeoutError, TryRecvError};
use std::sync::Mutex;
use std::thread::ThreadId;
use std::time::{Duration, Instant};

use polhode::dynamics::Monitor;
use pyo3::prelude::*;

/// How often a long run looks for Ctrl-C and reports progress.
const POLL: Duration = Duration::from_millis(50);

/// How long the calling thread waits for a batch without sleeping: a short batch then
/// returns without the ~10 us of a sleep and a wake-up.
const SPIN: Duration = Duration::from_micros(100);

/// The calling thread's watch over a run: every [`POLL`] it attaches, checks the signals
/// (Ctrl-C raises KeyboardInterrupt there) and calls `progress(fraction)`. An exception from
/// either is kept to be raised, and cancels the monitor: the run stops at its next look.
pub(crate) struct Watch {
    caller: ThreadId,
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

    /// Polls if on the calling thread and [`POLL`] has passed since the last poll (or
    /// `force`). Called at each look of a run (every few thousand steps), on any thread.
    pub(crate) fn poll(&self, monitor: &Monitor, force: bool) {
        if std::thread::current().id() != self.caller || monitor.is_cancelled() {
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
            if let Ok(mut slot) = self.raised.lock() {
                slot.get_or_insert(error);
            }
            monitor.cancel();
        }
    }

    pub(crate) fn take_raised(&self) -> Option<PyErr> {
        self.raised.lock().ok().and_then(|mut slot| slot.take())
    }
}

/// Runs `work` (a parallel batch) on the rayon pool while the calling thread, the GIL
/// released, waits for it and polls `watch` every [`POLL`]: a batch's threads cannot check
/// the signals, only the main thread can. The result comes back through a channel, so that
/// the wait ends as soon as it is sent.
pub(crate) fn run_on_pool<T: Send>(
    monitor: &Monitor,
    watch: &Watch,
    work: impl FnOnce() -> T + Send,
) -> Option<T> {
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
