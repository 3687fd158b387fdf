//! `simulate` (every method, one body or a batch) and `free_rotation` (the exact solution's
//! invariants for `analyze`).
//!
//! Bodies arrive in principal axes (the Python layer rotates them there and back). Torques
//! arrive as a plain spec tree of tuples, parsed here with the GIL held into [`TorqueSpec`],
//! then built into a Rust torque per body (a gravity-gradient torque needs each body's moments)
//! inside the parallel loop.
//!
//! Every [`POLL`] of a long run, the calling thread looks for Ctrl-C (`check_signals`) and
//! reports progress ([`Watch`]); on an exception it cancels the run through its [`Monitor`]
//! and raises once the run has stopped.

use std::sync::mpsc::{sync_channel, RecvTimeoutError, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::ThreadId;
use std::time::{Duration, Instant};

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use numpy::ndarray::{Array2, Array3};
use numpy::{
    IntoPyArray, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use polhode::dynamics::{
    integrate, BodyConstantTorque, Dop853Options, FnTorque, GravityGradient, Method, Monitor,
    Options, PivotGravity, SpaceConstantTorque, SplittingOrder, State, Torque, TorqueSum,
    Trajectory, Windowed,
};
use polhode::exact::{FreeRotation, Regime};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use rayon::prelude::*;

use crate::convert::bad_shape;
use crate::errors::{CoreError, PolhodeError};

/// A torque model as plain data.
enum TorqueSpec {
    Body(Vector3<f64>),
    Space(Vector3<f64>),
    PivotGravity {
        mass: f64,
        center_of_mass: Vector3<f64>,
        gravity: Vector3<f64>,
    },
    GravityGradient {
        mean_motion: f64,
        orbit_normal: Vector3<f64>,
        radial0: Vector3<f64>,
    },
    Window {
        start: f64,
        end: f64,
        inner: Box<TorqueSpec>,
    },
    Sum(Vec<TorqueSpec>),
    Callable {
        function: Py<PyAny>,
        attitude: bool,
        omega: bool,
        breaks: Vec<f64>,
    },
}

fn vec3(item: &Bound<'_, PyAny>) -> PyResult<Vector3<f64>> {
    let v: [f64; 3] = item.extract()?;
    Ok(Vector3::new(v[0], v[1], v[2]))
}

fn parse_torque(spec: &Bound<'_, PyAny>) -> PyResult<TorqueSpec> {
    let tuple = spec.cast::<PyTuple>().map_err(|_| {
        PyTypeError::new_err("Expected `torque` to be a polhode.torque model or a callable.")
    })?;
    let kind: String = tuple.get_item(0)?.extract()?;
    let item = |k: usize| tuple.get_item(k);
    Ok(match kind.as_str() {
        "body" => TorqueSpec::Body(vec3(&item(1)?)?),
        "space" => TorqueSpec::Space(vec3(&item(1)?)?),
        "pivot_gravity" => TorqueSpec::PivotGravity {
            mass: item(1)?.extract()?,
            center_of_mass: vec3(&item(2)?)?,
            gravity: vec3(&item(3)?)?,
        },
        "gravity_gradient" => TorqueSpec::GravityGradient {
            mean_motion: item(1)?.extract()?,
            orbit_normal: vec3(&item(2)?)?,
            radial0: vec3(&item(3)?)?,
        },
        "window" => TorqueSpec::Window {
            start: item(1)?.extract()?,
            end: item(2)?.extract()?,
            inner: Box::new(parse_torque(&item(3)?)?),
        },
        "sum" => {
            let terms: Vec<Bound<'_, PyAny>> = item(1)?.extract()?;
            TorqueSpec::Sum(terms.iter().map(parse_torque).collect::<PyResult<_>>()?)
        }
        "callable" => TorqueSpec::Callable {
            function: item(1)?.unbind(),
            attitude: item(2)?.extract()?,
            omega: item(3)?.extract()?,
            breaks: item(4)?.extract()?,
        },
        other => {
            return Err(PyValueError::new_err(format!(
                "Unknown torque kind {other:?}."
            )));
        }
    })
}

fn contains_callable(spec: &TorqueSpec) -> bool {
    match spec {
        TorqueSpec::Callable { .. } => true,
        TorqueSpec::Window { inner, .. } => contains_callable(inner),
        TorqueSpec::Sum(terms) => terms.iter().any(contains_callable),
        _ => false,
    }
}

/// The first Python exception raised by a callable torque, kept to re-raise as it was.
type Raised = Arc<Mutex<Option<PyErr>>>;

fn build_torque(
    spec: &TorqueSpec,
    moments: &Vector3<f64>,
    raised: &Raised,
) -> polhode::Result<Box<dyn Torque + Send>> {
    Ok(match spec {
        TorqueSpec::Body(v) => Box::new(BodyConstantTorque::new(*v)?),
        TorqueSpec::Space(v) => Box::new(SpaceConstantTorque::new(*v)?),
        TorqueSpec::PivotGravity {
            mass,
            center_of_mass,
            gravity,
        } => Box::new(PivotGravity::new(*center_of_mass, *mass, *gravity)?),
        TorqueSpec::GravityGradient {
            mean_motion,
            orbit_normal,
            radial0,
        } => Box::new(GravityGradient::new(
            *moments,
            *mean_motion,
            *orbit_normal,
            *radial0,
        )?),
        TorqueSpec::Window { start, end, inner } => Box::new(Windowed::new(
            build_torque(inner, moments, raised)?,
            *start,
            *end,
        )?),
        TorqueSpec::Sum(terms) => {
            let mut sum = TorqueSum::new();
            for term in terms {
                sum.push(build_torque(term, moments, raised)?);
            }
            Box::new(sum)
        }
        TorqueSpec::Callable {
            function,
            attitude,
            omega,
            breaks,
        } => {
            let function = Python::attach(|py| function.clone_ref(py));
            let raised = Arc::clone(raised);
            let call = move |t: f64, w: &Vector3<f64>, q: &UnitQuaternion<f64>| {
                Python::attach(|py| -> polhode::Result<Vector3<f64>> {
                    let quaternion = [q.i, q.j, q.k, q.w];
                    let result = function
                        .call1(py, (t, [w.x, w.y, w.z], quaternion))
                        .and_then(|value| value.extract::<[f64; 3]>(py));
                    match result {
                        Ok(v) => Ok(Vector3::new(v[0], v[1], v[2])),
                        Err(error) => {
                            let message = error.to_string();
                            if let Ok(mut slot) = raised.lock() {
                                slot.get_or_insert(error);
                            }
                            Err(polhode::Error::InvalidArgument {
                                name: "torque".into(),
                                reason: format!("the callable raised {message}"),
                            })
                        }
                    }
                })
            };
            Box::new(
                FnTorque::with_dependencies(call, *attitude, *omega)
                    .with_discontinuities(breaks.clone()),
            )
        }
    })
}

fn rows<const K: usize>(
    name: &str,
    a: &PyReadonlyArray2<'_, f64>,
    n: Option<usize>,
) -> PyResult<Vec<[f64; K]>> {
    let shape = a.shape();
    if shape[1] != K || n.is_some_and(|n| shape[0] != n) {
        let expected = match n {
            Some(n) => format!("({n}, {K})"),
            None => format!("(N, {K})"),
        };
        return Err(bad_shape(name, &expected, shape));
    }
    Ok(a.as_array()
        .rows()
        .into_iter()
        .map(|r| std::array::from_fn(|k| r[k]))
        .collect())
}

fn parse_method(
    method: &str,
    dt: Option<f64>,
    order: u32,
    rtol: f64,
    atol: Option<f64>,
) -> PyResult<Option<Method>> {
    let need_dt = |name: &str| -> PyResult<f64> {
        dt.ok_or_else(|| {
            PolhodeError::new_err(format!(
                "Expected `dt` (the largest step) for method {name:?}, got None."
            ))
        })
    };
    Ok(Some(match method {
        "exact" => return Ok(None),
        "splitting" => Method::Splitting {
            dt: need_dt(method)?,
            order: match order {
                2 => SplittingOrder::Two,
                4 => SplittingOrder::Four,
                6 => SplittingOrder::Six,
                other => {
                    return Err(PolhodeError::new_err(format!(
                        "Expected `order` to be 2, 4 or 6 for method \"splitting\", got {other}."
                    )))
                }
            },
        },
        "midpoint" => Method::Midpoint {
            dt: need_dt(method)?,
        },
        "rk4" => Method::Rk4 {
            dt: need_dt(method)?,
        },
        "dop853" => Method::Dop853(Dop853Options {
            rtol,
            atol,
            ..Dop853Options::default()
        }),
        other => {
            return Err(PolhodeError::new_err(format!(
                "Expected `method` to be one of \"auto\", \"exact\", \"splitting\", \"midpoint\", \
                 \"rk4\", \"dop853\", got {other:?}."
            )))
        }
    }))
}

/// Output times of the closed form between two looks at the monitor.
const EXACT_CHECK_EVERY: usize = 256;

/// One body's trajectory by the closed form, at each output time (`t0` shifts the origin),
/// reporting to `monitor` as the integrators do.
fn exact_trajectory(
    moments: &Vector3<f64>,
    state: &State,
    times: &[f64],
    t0: f64,
    with_attitude: bool,
    monitor: &Monitor,
) -> polhode::Result<Trajectory> {
    monitor.check()?;
    let free = FreeRotation::new(*moments, state.omega, state.attitude)?;
    let mut omega = Vec::with_capacity(times.len());
    let mut attitude = with_attitude.then(|| Vec::with_capacity(times.len()));
    let mut reported = t0;
    let mut report = |t: f64| {
        if t > reported {
            monitor.add_elapsed(t - reported);
            reported = t;
        }
    };
    for (k, &t) in times.iter().enumerate() {
        if k % EXACT_CHECK_EVERY == EXACT_CHECK_EVERY - 1 {
            report(t);
            monitor.check()?;
        }
        match attitude.as_mut() {
            Some(list) => {
                let (w, q) = free.state(t - t0);
                omega.push(w);
                list.push(q);
            }
            None => omega.push(free.omega(t - t0)),
        }
    }
    report(times.last().copied().unwrap_or(t0));
    monitor.add_finished();
    let stats = polhode::dynamics::Stats {
        steps: 0,
        rejected_steps: 0,
        rhs_evaluations: times.len() as u64,
    };
    Ok(Trajectory {
        omega,
        attitude,
        stats,
    })
}

/// How often a long run looks for Ctrl-C and reports progress.
const POLL: Duration = Duration::from_millis(50);

/// How long the calling thread waits for a batch without sleeping: a short batch then
/// returns without the ~10 us of a sleep and a wake-up.
const SPIN: Duration = Duration::from_micros(100);

/// The calling thread's watch over a run: every [`POLL`] it attaches, checks the signals
/// (Ctrl-C raises KeyboardInterrupt there) and calls `progress(fraction)`. An exception from
/// either is kept to be raised, and cancels the monitor: the run stops at its next look.
struct Watch {
    caller: ThreadId,
    progress: Option<Py<PyAny>>,
    /// Bodies, and the span `t_end - t0` of each.
    n: usize,
    span: f64,
    last_poll: Mutex<Instant>,
    raised: Mutex<Option<PyErr>>,
}

impl Watch {
    fn new(progress: Option<Py<PyAny>>, n: usize, span: f64) -> Self {
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
    fn poll(&self, monitor: &Monitor, force: bool) {
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
            if let Some(progress) = &self.progress {
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

    fn take_raised(&self) -> Option<PyErr> {
        self.raised.lock().ok().and_then(|mut slot| slot.take())
    }
}

/// Runs `work` (a parallel batch) on the rayon pool while the calling thread, the GIL
/// released, waits for it and polls `watch` every [`POLL`]: a batch's threads cannot check
/// the signals, only the main thread can. The result comes back through a channel, so that
/// the wait ends as soon as it is sent.
fn run_on_pool<T: Send>(
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

/// Integrates N bodies (principal moments (N, 3); omega0 (N, 3) and quaternion0 (N, 4) xyzw in
/// the body's own axes, whose principal axes are the columns of `axes`, a rotation, or the
/// identity if None) to the output times.
///
/// Returns, in the body's own axes: omega (N, M, 3), the quaternion (N, M, 4) (continuous in
/// time: q and -q are one rotation) or None, the angular momentum in space (N, M, 3) or None,
/// the angular momentum in body axes (N, M, 3), the kinetic energy (N, M), and stats (N, 3):
/// steps, rejected steps, evaluations. The conversions run here, in parallel, rather than in
/// numpy: they cost a single-body call more than its integration did.
///
/// `progress`, if given, is called with the fraction of the work done (in [0, 1],
/// non-decreasing) every 50 ms of a long run and with 1.0 at the end, on the calling thread.
/// Ctrl-C interrupts the run (within 50 ms plus a few thousand steps) with KeyboardInterrupt;
/// an exception raised by `progress` also stops it, and is raised.
///
/// A single body (or a serial run with a callable torque) runs on the calling thread, which
/// polls at the run's looks at its monitor: a short call never attaches the GIL, nor hands
/// work to another thread. A batch runs on the rayon pool (see [`run_on_pool`]).
#[pyfunction]
#[pyo3(signature = (
    moments, omega0, quaternion0, times, *, t0, method, dt, order, rtol, atol, torque,
    with_attitude, max_steps, progress=None, axes=None
))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn simulate<'py>(
    py: Python<'py>,
    moments: PyReadonlyArray2<'py, f64>,
    omega0: PyReadonlyArray2<'py, f64>,
    quaternion0: PyReadonlyArray2<'py, f64>,
    times: PyReadonlyArray1<'py, f64>,
    t0: f64,
    method: &str,
    dt: Option<f64>,
    order: u32,
    rtol: f64,
    atol: Option<f64>,
    torque: Option<Bound<'py, PyAny>>,
    with_attitude: bool,
    max_steps: u64,
    progress: Option<Bound<'py, PyAny>>,
    axes: Option<PyReadonlyArray2<'py, f64>>,
) -> PyResult<Outputs<'py>> {
    let moments = rows::<3>("moments", &moments, None)?;
    let n = moments.len();
    let omega0 = rows::<3>("omega0", &omega0, Some(n))?;
    let quaternion0 = rows::<4>("quaternion0", &quaternion0, Some(n))?;
    let frame = axes.map(|a| Frame::new(&a)).transpose()?;
    let times: Vec<f64> = times.as_array().to_vec();
    if times.is_empty() {
        return Err(bad_shape("times", "(M,) with M >= 1", &[0]));
    }
    let method = parse_method(method, dt, order, rtol, atol)?;
    let spec = torque.as_ref().map(parse_torque).transpose()?;
    if method.is_none() && spec.is_some() {
        return Err(PolhodeError::new_err(
            "Expected no `torque` with method \"exact\" (the closed form is torque-free); use \
             \"dop853\" or another integrator.",
        ));
    }
    if let Some(progress) = progress.as_ref().filter(|p| !p.is_callable()) {
        return Err(PyTypeError::new_err(format!(
            "Expected `progress` to be a callable taking the fraction done, or None, got {}.",
            progress.get_type().name()?
        )));
    }
    let progress = progress.map(Bound::unbind);
    let serial = spec.as_ref().is_some_and(contains_callable);
    let raised: Raised = Arc::new(Mutex::new(None));
    let span = times.last().map_or(0.0, |&t| t - t0);
    let watch = Arc::new(Watch::new(progress, n, span));
    let monitor = Monitor::with_on_look({
        let watch = Arc::clone(&watch);
        move |monitor| watch.poll(monitor, false)
    });
    let run = |i: usize| -> polhode::Result<Trajectory> {
        let m = Vector3::from(moments[i]);
        let q = quaternion0[i];
        let attitude = UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]));
        let omega = Vector3::from(omega0[i]);
        let state = match &frame {
            // omega_p = V^T omega_b; R_p = R_b V.
            Some(f) => State::new(f.matrix.transpose() * omega, attitude * f.rotation),
            None => State::new(omega, attitude),
        };
        let result = match (&method, &spec) {
            (None, _) => exact_trajectory(&m, &state, &times, t0, with_attitude, &monitor),
            (Some(method), spec) => {
                let built = spec
                    .as_ref()
                    .map(|s| build_torque(s, &m, &raised))
                    .transpose()?;
                let options = Options {
                    t0,
                    with_attitude,
                    torque: built.as_deref().map(|t| t as &dyn Torque),
                    max_steps,
                    monitor: Some(&monitor),
                };
                integrate(method, &m, &state, &times, &options)
            }
        };
        result.map_err(|e| {
            if n > 1 {
                e.map_name(|name| format!("{name} (body {i})"))
            } else {
                e
            }
        })
    };
    // Inline on the calling thread: one body, a callable torque (serial: it attaches the GIL),
    // or a call from a thread of the pool itself (a callable torque running a simulation,
    // which could otherwise wait for a job queued behind its own thread).
    let inline = n == 1 || serial || rayon::current_thread_index().is_some();
    let m = times.len();
    let mut outputs = Assembled::zeros(n, m, with_attitude);
    // Each body is integrated and written to its rows of the outputs in one task: no
    // trajectory outlives its task. The first failure by body index is the one reported.
    let failed: Mutex<Option<(usize, polhode::Error)>> = Mutex::new(None);
    let one = |i: usize, rows: Rows<'_>| match run(i) {
        Ok(trajectory) => write_body(&trajectory, &moments[i], frame.as_ref(), rows),
        Err(error) => {
            if let Ok(mut slot) = failed.lock() {
                if slot.as_ref().is_none_or(|(k, _)| i < *k) {
                    *slot = Some((i, error));
                }
            }
        }
    };
    let finished = py.detach(|| {
        if inline {
            outputs
                .rows()
                .enumerate()
                .for_each(|(i, rows)| one(i, rows));
            Some(())
        } else {
            let chunks = outputs.par_rows();
            run_on_pool(&monitor, &watch, || {
                chunks.enumerate().for_each(|(i, rows)| one(i, rows));
            })
        }
    });
    if let Some(error) = watch.take_raised() {
        return Err(error);
    }
    if finished.is_none() {
        unreachable!("a panic of the batch is re-raised by its scope");
    }
    if let Some(error) = raised.lock().ok().and_then(|mut slot| slot.take()) {
        return Err(error);
    }
    if let Some((_, error)) = failed.into_inner().ok().flatten() {
        return Err(CoreError(error).into());
    }
    if let Some(progress) = &watch.progress {
        progress.call1(py, (1.0,))?;
    }
    let m = times.len();
    let bad = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
    let shape = |data: Vec<f64>, k: usize| {
        Array3::from_shape_vec((n, m, k), data)
            .map(|a| a.into_pyarray(py))
            .map_err(bad)
    };
    Ok((
        shape(outputs.omega, 3)?,
        outputs.quaternion.map(|q| shape(q, 4)).transpose()?,
        outputs.l_space.map(|l| shape(l, 3)).transpose()?,
        shape(outputs.l_body, 3)?,
        Array2::from_shape_vec((n, m), outputs.energy)
            .map_err(bad)?
            .into_pyarray(py),
        Array2::from_shape_vec((n, 3), outputs.stats)
            .map_err(bad)?
            .into_pyarray(py),
    ))
}

/// What `simulate` returns (see there).
type Outputs<'py> = (
    Bound<'py, PyArray3<f64>>,
    Option<Bound<'py, PyArray3<f64>>>,
    Option<Bound<'py, PyArray3<f64>>>,
    Bound<'py, PyArray3<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u64>>,
);

/// The body's principal axes: the columns of `matrix` (a rotation), as a quaternion too.
struct Frame {
    matrix: Matrix3<f64>,
    rotation: UnitQuaternion<f64>,
}

impl Frame {
    fn new(axes: &PyReadonlyArray2<'_, f64>) -> PyResult<Self> {
        if axes.shape() != [3, 3] {
            return Err(bad_shape("axes", "(3, 3)", axes.shape()));
        }
        let a = axes.as_array();
        let matrix = Matrix3::from_fn(|r, c| a[[r, c]]);
        let defect = (matrix.transpose() * matrix - Matrix3::identity()).norm();
        if !(defect <= 1e-9 && matrix.determinant() > 0.0) {
            return Err(PolhodeError::new_err(
                "Expected `axes` to be a rotation matrix (orthonormal, det +1).",
            ));
        }
        let rotation =
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(matrix));
        Ok(Self { matrix, rotation })
    }
}

/// The outputs in the body's own axes, flat and row-major (see `simulate`).
struct Assembled {
    omega: Vec<f64>,
    quaternion: Option<Vec<f64>>,
    l_space: Option<Vec<f64>>,
    l_body: Vec<f64>,
    energy: Vec<f64>,
    stats: Vec<u64>,
    /// Output times per body.
    m: usize,
}

/// One body's rows of [`Assembled`]: omega, L in body axes, energy, quaternion, L in space
/// (the last two empty without the attitude), stats.
type Rows<'a> = (
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [u64],
);

impl Assembled {
    fn zeros(n: usize, m: usize, with_attitude: bool) -> Self {
        Self {
            omega: vec![0.0; n * m * 3],
            quaternion: with_attitude.then(|| vec![0.0; n * m * 4]),
            l_space: with_attitude.then(|| vec![0.0; n * m * 3]),
            l_body: vec![0.0; n * m * 3],
            energy: vec![0.0; n * m],
            stats: vec![0; n * 3],
            m,
        }
    }

    /// Each body's [`Rows`], in order (on the calling thread).
    fn rows(&mut self) -> impl Iterator<Item = Rows<'_>> {
        let (m, n) = (self.m, self.stats.len() / 3);
        let (q_rows, ls_rows) = attitude_rows(&mut self.quaternion, &mut self.l_space, m, n);
        self.omega
            .chunks_mut(3 * m)
            .zip(self.l_body.chunks_mut(3 * m))
            .zip(self.energy.chunks_mut(m))
            .zip(q_rows)
            .zip(ls_rows)
            .zip(self.stats.chunks_mut(3))
            .map(|(((((w, lb), e), q), ls), st)| (w, lb, e, q, ls, st))
    }

    /// [`Assembled::rows`] in parallel (rayon).
    fn par_rows(&mut self) -> impl IndexedParallelIterator<Item = Rows<'_>> {
        let (m, n) = (self.m, self.stats.len() / 3);
        let (q_rows, ls_rows) = attitude_rows(&mut self.quaternion, &mut self.l_space, m, n);
        self.omega
            .par_chunks_mut(3 * m)
            .zip(self.l_body.par_chunks_mut(3 * m))
            .zip(self.energy.par_chunks_mut(m))
            .zip(q_rows.into_par_iter())
            .zip(ls_rows.into_par_iter())
            .zip(self.stats.par_chunks_mut(3))
            .map(|(((((w, lb), e), q), ls), st)| (w, lb, e, q, ls, st))
    }
}

/// The rows of the quaternion and of L in space, one per body; without the attitude (no
/// buffers) one empty row per body, which keeps the zips over the bodies aligned.
#[allow(clippy::type_complexity)]
fn attitude_rows<'a>(
    quaternion: &'a mut Option<Vec<f64>>,
    l_space: &'a mut Option<Vec<f64>>,
    m: usize,
    n: usize,
) -> (Vec<&'a mut [f64]>, Vec<&'a mut [f64]>) {
    fn rows<'a>(data: &'a mut Option<Vec<f64>>, k: usize, n: usize) -> Vec<&'a mut [f64]> {
        match data.as_deref_mut() {
            Some(values) => values.chunks_mut(k).collect(),
            None => (0..n).map(|_| -> &'a mut [f64] { &mut [] }).collect(),
        }
    }
    (rows(quaternion, 4 * m, n), rows(l_space, 3 * m, n))
}

/// Writes one body's outputs in its own axes from its principal-axes trajectory.
fn write_body(traj: &Trajectory, moments: &[f64; 3], frame: Option<&Frame>, rows: Rows<'_>) {
    let (w_out, lb_out, e_out, q_out, ls_out, s_out) = rows;
    let inertia = Vector3::from(*moments);
    let mut previous: Option<Quaternion<f64>> = None;
    for (j, w) in traj.omega.iter().enumerate() {
        let l = inertia.component_mul(w);
        e_out[j] = 0.5 * (w[0] * l[0] + w[1] * l[1] + w[2] * l[2]);
        let (wb, lb) = match frame {
            Some(f) => (f.matrix * w, f.matrix * l),
            None => (*w, l),
        };
        w_out[3 * j..3 * j + 3].copy_from_slice(wb.as_slice());
        lb_out[3 * j..3 * j + 3].copy_from_slice(lb.as_slice());
        if let (Some(attitude), false) = (traj.attitude.as_ref(), q_out.is_empty()) {
            let qp = attitude[j];
            let ls = qp * l;
            ls_out[3 * j..3 * j + 3].copy_from_slice(ls.as_slice());
            // R_b = R_p V^T.
            let mut q = match frame {
                Some(f) => (qp * f.rotation.inverse()).into_inner(),
                None => qp.into_inner(),
            };
            // One sign per trajectory: continuous in time.
            if previous.is_some_and(|p| p.coords.dot(&q.coords) < 0.0) {
                q = -q;
            }
            previous = Some(q);
            q_out[4 * j..4 * j + 4].copy_from_slice(&[q.i, q.j, q.k, q.w]);
        }
    }
    let st = &traj.stats;
    s_out.copy_from_slice(&[st.steps, st.rejected_steps, st.rhs_evaluations]);
}

/// The torque-free motion's invariants: a dict with energy, angular_momentum_norm, regime,
/// axis (index or None), period (or None).
#[pyfunction]
pub fn free_rotation<'py>(
    py: Python<'py>,
    moments: [f64; 3],
    omega0: [f64; 3],
) -> PyResult<Bound<'py, PyDict>> {
    let free = FreeRotation::new(
        Vector3::from(moments),
        Vector3::from(omega0),
        UnitQuaternion::identity(),
    )
    .map_err(CoreError)?;
    let out = PyDict::new(py);
    let (regime, axis) = match free.regime() {
        Regime::Rest => ("rest", None),
        Regime::Spherical => ("spherical", None),
        Regime::Symmetric { axis } => ("symmetric", Some(axis)),
        Regime::AboutAxis(axis) => ("about_axis", Some(axis)),
        Regime::Separatrix => ("separatrix", None),
        Regime::SteadyIntermediate => ("steady_intermediate", None),
        #[allow(unreachable_patterns)]
        _ => ("unknown", None),
    };
    out.set_item("regime", regime)?;
    out.set_item("axis", axis)?;
    out.set_item("period", free.period())?;
    out.set_item("energy", free.energy())?;
    out.set_item("angular_momentum_norm", free.angular_momentum_norm())?;
    Ok(out)
}
