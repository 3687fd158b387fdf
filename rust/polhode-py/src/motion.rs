//! `simulate` and `free_rotation`: convert the arguments, call the core, convert the results.
//!
//! The physics (principal axes, frames, torques, the outputs, batching with per-body errors)
//! lives in `polhode::simulation`; here are only the shapes of the arguments, the method's
//! name, the GIL, Ctrl-C and progress.

use std::borrow::Cow;

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use numpy::ndarray::{Array1, Array2, Array3, ArrayD};
use numpy::{IntoPyArray, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use polhode::dynamics::{Method, MethodSettings, RotorSpec, TorqueSpec, METHODS};
use polhode::exact::{FreeRotation, Regime};
use polhode::memory::{self, Purpose};
use polhode::settings::count;
use polhode::simulation::{
    orientation_from_matrix, orientation_from_quaternion, spreads_times, Body, Dim, Outputs,
    Quantity, Simulation,
};
use pyo3::exceptions::PyTypeError;
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use crate::convert::bad_shape;
use crate::errors::CoreError;
use crate::mass::PyMassProperties;
use crate::rotors::rotor_spec;
use crate::torque::{calls_python, torque_spec};
use crate::watch::{run_on_pool, Call};

/// A float64 array of any shape, as (shape, row-major numbers). A contiguous array is copied
/// as one slice (iterating a dynamic-dimensional view costs ~20 ns a number: 0.2 s of output
/// times that Ctrl-C could not interrupt for 1e7).
/// A contiguous array is borrowed as it is, not copied (each copy an allocation of a small
/// call).
pub(crate) fn dense<'a>(
    a: &'a PyReadonlyArrayDyn<'_, f64>,
) -> PyResult<(&'a [usize], Cow<'a, [f64]>)> {
    let data = match a.as_slice() {
        Ok(slice) => Cow::Borrowed(slice),
        Err(_) => Cow::Owned(
            memory::collect(a.as_array().iter().copied(), Purpose::Input).map_err(CoreError)?,
        ),
    };
    Ok((a.shape(), data))
}

/// Rows of three numbers as vectors (the bodies' angular velocities or moments).
pub(crate) fn rows3(data: &[f64]) -> PyResult<Vec<Vector3<f64>>> {
    let rows = data.chunks_exact(3).map(Vector3::from_column_slice);
    Ok(memory::collect(rows, Purpose::Bodies).map_err(CoreError)?)
}

/// The bodies: `omega0`'s shape decides. (3,) is one body: principal moments (3,), a tensor
/// (3, 3) or mass properties. (N, 3) is N bodies, for every N: principal moments (N, 3), N
/// mass properties, or one body ((3,) moments or mass properties) shared by all.
pub(crate) fn bodies(body: &Bound<'_, PyAny>, n: Option<usize>) -> PyResult<Vec<Body>> {
    if let Ok(props) = body.cast::<PyMassProperties>() {
        return Ok(vec![Body::MassProperties(props.get().0)]);
    }
    if let Ok(list) = body.cast::<PyList>() {
        let mut parts = memory::with_capacity(list.len(), Purpose::Bodies).map_err(CoreError)?;
        for item in list.iter() {
            let props = item.cast::<PyMassProperties>().map_err(|_| {
                PyTypeError::new_err(
                    "Expected `body` to be a list of polhode.Body, got another item.",
                )
            })?;
            memory::push(
                &mut parts,
                Body::MassProperties(props.get().0),
                Purpose::Bodies,
            )
            .map_err(CoreError)?;
        }
        if n != Some(parts.len()) {
            let expected = match n {
                Some(n) => format!("({n},) to match `omega0`"),
                None => "one Body, since `omega0` has shape (3,)".into(),
            };
            return Err(bad_shape("body", &expected, &[parts.len()]));
        }
        return Ok(parts);
    }
    let array: PyReadonlyArrayDyn<'_, f64> = body.extract()?;
    let (shape, data) = dense(&array)?;
    match (n, shape) {
        (_, [3]) => Ok(vec![Body::Moments(Vector3::from_column_slice(&data))]),
        (None, [3, 3]) => Ok(vec![Body::Inertia(Matrix3::from_row_slice(&data))]),
        (Some(n), [rows, 3]) if *rows == n => {
            let moments = data
                .chunks_exact(3)
                .map(|row| Body::Moments(Vector3::from_column_slice(row)));
            Ok(memory::collect(moments, Purpose::Bodies).map_err(CoreError)?)
        }
        (None, _) => Err(bad_shape(
            "body",
            "(3,) principal moments or a (3, 3) tensor, since `omega0` has shape (3,) (one body; \
             for N bodies give `omega0` of shape (N, 3))",
            shape,
        )),
        (Some(n), _) => Err(bad_shape(
            "body",
            &format!(
                "({n}, 3) principal moments to match `omega0`, or (3,) moments shared by all \
                 (a (3, 3) tensor is one body: give `omega0` of shape (3,))"
            ),
            shape,
        )),
    }
}

/// Initial orientations: one (4,) quaternion (x, y, z, w) or (3, 3) matrix shared by all, or
/// (K, 4) / (K, 3, 3) for K = 1 or N bodies.
pub(crate) fn orientations(
    orientation0: Option<PyReadonlyArrayDyn<'_, f64>>,
) -> PyResult<Vec<UnitQuaternion<f64>>> {
    let Some(array) = orientation0 else {
        return Ok(vec![UnitQuaternion::identity()]);
    };
    let (shape, data) = dense(&array)?;
    let convert = |k: usize, item: polhode::Result<UnitQuaternion<f64>>| {
        item.map_err(|e| PyErr::from(CoreError(if k > 0 { e.in_body(k) } else { e })))
    };
    // One orientation per row, the first bad one's error.
    let each = |width: usize, make: &dyn Fn(&[f64]) -> polhode::Result<UnitQuaternion<f64>>| {
        let mut out =
            memory::with_capacity(data.len() / width, Purpose::Bodies).map_err(CoreError)?;
        for (k, row) in data.chunks_exact(width).enumerate() {
            out.push(convert(k, make(row))?);
        }
        Ok(out)
    };
    match shape {
        [4] | [_, 4] => each(4, &|q| {
            orientation_from_quaternion("orientation0", [q[0], q[1], q[2], q[3]])
        }),
        [3, 3] | [_, 3, 3] => each(9, &|r| {
            orientation_from_matrix("orientation0", &Matrix3::from_row_slice(r))
        }),
        _ => Err(bad_shape(
            "orientation0",
            "(4,) an (x, y, z, w) quaternion, (3, 3) a rotation matrix, or N of them",
            shape,
        )),
    }
}

/// What `simulate` and `fastest_rate` read of a run's bodies: `omega0`'s shape decides one
/// body (`n` None) or N, then the bodies and their orientations.
pub(crate) struct Motion {
    pub(crate) n: Option<usize>,
    pub(crate) bodies: Vec<Body>,
    pub(crate) omega0: Vec<Vector3<f64>>,
    pub(crate) orientation0: Vec<UnitQuaternion<f64>>,
}

/// The bodies, initial angular velocities and orientations of a run, as `simulate` reads them.
pub(crate) fn motion(
    body: &Bound<'_, PyAny>,
    omega0: &PyReadonlyArrayDyn<'_, f64>,
    orientation0: Option<PyReadonlyArrayDyn<'_, f64>>,
) -> PyResult<Motion> {
    let (omega_shape, omega_data) = dense(omega0)?;
    let n = match omega_shape {
        [3] => None,
        [n, 3] => Some(*n),
        _ => return Err(bad_shape("omega0", "(3,) or (N, 3)", omega_shape)),
    };
    Ok(Motion {
        n,
        bodies: bodies(body, n)?,
        omega0: rows3(&omega_data)?,
        orientation0: orientations(orientation0)?,
    })
}

/// The torque, the rotors (their Python callbacks through `call`) and the method of a run,
/// from `simulate`'s arguments (`dt`, `order`, `rtol`, `atol`), the method checked by the core.
pub(crate) fn run_settings(
    torque: Option<&Bound<'_, PyAny>>,
    rotors: Option<Vec<Bound<'_, PyAny>>>,
    method: &str,
    (dt, order, rtol, atol): (Option<f64>, i64, f64, Option<f64>),
    call: &Call,
) -> PyResult<(Option<TorqueSpec>, Vec<RotorSpec>, Method)> {
    let spec = torque.map(|t| torque_spec(t, call)).transpose()?;
    let rotors = rotors
        .unwrap_or_default()
        .iter()
        .map(|r| rotor_spec(r, call))
        .collect::<PyResult<Vec<_>>>()?;
    let settings = MethodSettings {
        dt,
        order,
        rtol,
        atol,
        torque: spec.is_some(),
        rotors: !rotors.is_empty(),
    };
    let method = Method::from_name(method, &settings).map_err(CoreError)?;
    Ok((spec, rotors, method))
}

/// Integrates one body (`omega0` of shape (3,)) or N bodies (`omega0` (N, 3)): see
/// `polhode.simulate`. Returns the fields of a `Trajectory` by name, in their order: `t` (the
/// array `t` itself), every quantity of `polhode::simulation::Quantity` (a single body without
/// the leading N; None for those not computed: those needing the orientation without
/// `orientation=True`, `rotor_rates` without rotors), `moments`, and `stats`, a dict of
/// `method`, `steps`, `rejected_steps` and `evaluations`. `rotors` is a sequence of
/// `polhode.rotors` rotors, shared by every body.
///
/// `progress`, if given, is called with the fraction of the work done (in [0, 1],
/// non-decreasing) every 50 ms of a long run and with 1.0 at the end, on the calling thread.
/// Ctrl-C interrupts the run (within 50 ms plus a few thousand steps) with KeyboardInterrupt;
/// an exception raised by `progress` also stops it, and is raised; `cancel_all()` (from any
/// thread) stops it with `polhode.errors.CancelledError`.
///
/// A single body (or a run with a Python torque function) runs on the calling thread, which
/// polls at the run's looks at its monitor: a short call never attaches the GIL, nor hands
/// work to another thread. A batch runs on the rayon pool (see [`run_on_pool`]).
///
/// `every_step=True` (one body, `dop853`) reports the motion at the end of every accepted step
/// too, in time order with the output times (`polhode::simulation::simulate_every_step`): `t`
/// in the result is then a new array of those times.
#[pyfunction]
#[pyo3(signature = (
    body, omega0, t, *, orientation0=None, t0=0.0, method="auto", dt=None, order=4,
    rtol=1e-10, atol=None, torque=None, orientation=true, max_steps=100_000_000, progress=None,
    rotors=None, every_step=false
))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    body: &Bound<'py, PyAny>,
    omega0: PyReadonlyArrayDyn<'py, f64>,
    t: PyReadonlyArrayDyn<'py, f64>,
    orientation0: Option<PyReadonlyArrayDyn<'py, f64>>,
    t0: f64,
    method: &str,
    dt: Option<f64>,
    order: i64,
    rtol: f64,
    atol: Option<f64>,
    torque: Option<Bound<'py, PyAny>>,
    orientation: bool,
    max_steps: i64,
    progress: Option<Bound<'py, PyAny>>,
    rotors: Option<Vec<Bound<'py, PyAny>>>,
    every_step: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let Motion {
        n,
        bodies,
        omega0,
        orientation0,
    } = motion(body, &omega0, orientation0)?;
    let (t_shape, times) = dense(&t)?;
    if t_shape.len() != 1 {
        return Err(bad_shape("t", "(M,)", t_shape));
    }
    // The call's one cancellation path: Ctrl-C, cancel_all, progress and the Python callbacks
    // of the torque and the rotors all stop it there.
    let span = times.last().map_or(0.0, |&t| t - t0);
    let call = Call::new(
        progress.as_ref().map(|p| p.clone().unbind()),
        omega0.len(),
        span,
    );
    let (spec, rotors, method) = run_settings(
        torque.as_ref(),
        rotors,
        method,
        (dt, order, rtol, atol),
        &call,
    )?;
    let max_steps = count("max_steps", max_steps).map_err(CoreError)?;
    if let Some(progress) = progress.as_ref().filter(|p| !p.is_callable()) {
        return Err(PyTypeError::new_err(format!(
            "Expected `progress` to be a callable taking the fraction done, or None, got {}.",
            progress.get_type().name()?
        )));
    }
    let serial = spec.as_ref().is_some_and(calls_python) || rotors.iter().any(|r| r.has_function());
    // Inline on the calling thread: one body (unless its output times are spread over the
    // pool: the exact solution at many times), a Python torque (it attaches the GIL), or a
    // call from a thread of the pool itself (a torque function running a simulation, which
    // could otherwise wait for a job queued behind its own thread).
    let one_thread = omega0.len() <= 1 && !spreads_times(&method, times.len());
    let inline = one_thread || serial || rayon::current_thread_index().is_some();
    let run = Simulation {
        method,
        t0,
        with_orientation: orientation,
        max_steps,
        torque: spec,
        parallel: !inline,
        rotors,
    };
    if every_step && (n.is_some() || bodies.len() != 1) {
        return Err(PyTypeError::new_err(
            "every_step=True reports the steps of one body: give `omega0` of shape (3,).",
        ));
    }
    let work = || {
        if every_step {
            polhode::simulation::simulate_every_step(
                &run,
                &bodies[0],
                &omega0[0],
                &orientation0[0],
                &times,
                Some(call.monitor()),
            )
            .map(|(times, outputs)| (Some(times), outputs))
        } else {
            polhode::simulation::simulate(
                &run,
                &bodies,
                &omega0,
                &orientation0,
                &times,
                Some(call.monitor()),
            )
            .map(|outputs| (None, outputs))
        }
    };
    let result = py
        .detach(|| {
            if inline {
                Some(work())
            } else {
                run_on_pool(&call, work)
            }
        })
        .unwrap_or_else(|| unreachable!("a panic of the batch is re-raised by its scope"));
    if let Some(error) = call.take_raised() {
        return Err(error);
    }
    let (stepped, outputs) = result.map_err(CoreError)?;
    if let Some(progress) = &progress {
        progress.call1((1.0,))?;
    }
    match stepped {
        Some(times) => {
            let times = times.into_pyarray(py);
            to_dict(py, outputs, n.is_none(), run.method.name(), times.as_any())
        }
        None => to_dict(py, outputs, n.is_none(), run.method.name(), t.as_any()),
    }
}

/// Checks one body, its initial angular velocity and its rotors as `simulate` checks them, with
/// the same errors, and computes nothing else (`polhode::simulation::check_motion`): what
/// `polhode.analyze` checks before its closed form.
#[pyfunction]
#[pyo3(signature = (body, omega0, *, rotors=None))]
pub fn check_motion(
    body: &Bound<'_, PyAny>,
    omega0: PyReadonlyArrayDyn<'_, f64>,
    rotors: Option<Vec<Bound<'_, PyAny>>>,
) -> PyResult<()> {
    let (omega_shape, omega_data) = dense(&omega0)?;
    if omega_shape != [3] {
        return Err(bad_shape("omega0", "(3,)", omega_shape));
    }
    let bodies = bodies(body, None)?;
    let call = Call::new(None, 1, 0.0);
    let rotors = rotors
        .unwrap_or_default()
        .iter()
        .map(|r| rotor_spec(r, &call))
        .collect::<PyResult<Vec<_>>>()?;
    let omega0 = Vector3::from_column_slice(&omega_data);
    polhode::simulation::check_motion(&bodies[0], &omega0, &rotors).map_err(CoreError)?;
    Ok(())
}

/// The quantities' names as Python strings, made once per process (in the order of
/// `Quantity::ALL`): a small call then neither builds nor hashes its keys anew, nor does the
/// Python layer reading them.
static QUANTITY_KEYS: PyOnceLock<Vec<Py<PyString>>> = PyOnceLock::new();

fn quantity_keys(py: Python<'_>) -> &Vec<Py<PyString>> {
    QUANTITY_KEYS.get_or_init(py, || {
        Quantity::ALL
            .iter()
            .map(|q| PyString::intern(py, q.name()).unbind())
            .collect()
    })
}

/// The fields of a `Trajectory` by name, in their order (what `polhode.simulate` sets in one
/// step): `t`, the outputs (None for those not computed; a single body drops the leading N),
/// `moments` and `stats`.
fn to_dict<'py>(
    py: Python<'py>,
    outputs: Outputs,
    single: bool,
    method: &str,
    t: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item(intern!(py, "t"), t)?;
    let (n, m) = (outputs.n, outputs.m);
    let lead = |mut shape: Vec<usize>| {
        if !single {
            shape.insert(0, n);
        }
        shape
    };
    let array = |shape: Vec<usize>, data: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        let shape = lead(shape);
        // Fixed dimensions where there are up to three (every output but a batch's rotor
        // rates): the same array, without the dynamic dimension's work per array.
        match *shape.as_slice() {
            [a] => Array1::from_shape_vec(a, data).map(|a| a.into_pyarray(py).into_any()),
            [a, b] => Array2::from_shape_vec((a, b), data).map(|a| a.into_pyarray(py).into_any()),
            [a, b, c] => {
                Array3::from_shape_vec((a, b, c), data).map(|a| a.into_pyarray(py).into_any())
            }
            _ => ArrayD::from_shape_vec(shape, data).map(|a| a.into_pyarray(py).into_any()),
        }
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))
    };
    // The columns come in the order of Quantity::ALL, the fields' order.
    let mut columns = outputs.columns.into_iter().peekable();
    for (quantity, key) in Quantity::ALL.iter().zip(quantity_keys(py)) {
        match columns.next_if(|(q, _)| q == quantity) {
            Some((_, data)) => {
                let mut shape = vec![m];
                shape.extend(quantity.shape(outputs.rotors));
                dict.set_item(key.bind(py), array(shape, data)?)?;
            }
            None => dict.set_item(key.bind(py), py.None())?,
        }
    }
    if columns.next().is_some() {
        return Err(pyo3::exceptions::PyRuntimeError::new_err(
            "the core's outputs are not in the order of its quantities",
        ));
    }
    dict.set_item(intern!(py, "moments"), array(vec![3], outputs.moments)?)?;
    let stats = PyDict::new(py);
    stats.set_item(intern!(py, "method"), method)?;
    type Count = fn(&polhode::dynamics::Stats) -> u64;
    let counts: [(&Bound<'py, PyString>, Count); 3] = [
        (intern!(py, "steps"), |s| s.steps),
        (intern!(py, "rejected_steps"), |s| s.rejected_steps),
        (intern!(py, "evaluations"), |s| s.rhs_evaluations),
    ];
    for (name, get) in counts {
        let values =
            memory::collect(outputs.stats.iter().map(get), Purpose::Outputs).map_err(CoreError)?;
        if single {
            stats.set_item(name, values[0])?;
        } else {
            stats.set_item(name, values.into_pyarray(py))?;
        }
    }
    dict.set_item(intern!(py, "stats"), stats)?;
    Ok(dict)
}

/// The torque-free motion's invariants: a dict with energy, angular_momentum_norm, regime,
/// axis (index or None), period, precession_rate_space and nutation_angle ((min, max)), each
/// or None.
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
    // Keys made once per process (`intern!`): neither built nor hashed anew per call.
    out.set_item(intern!(py, "regime"), regime)?;
    out.set_item(intern!(py, "axis"), axis)?;
    out.set_item(intern!(py, "period"), free.period())?;
    out.set_item(intern!(py, "energy"), free.energy())?;
    out.set_item(
        intern!(py, "angular_momentum_norm"),
        free.angular_momentum_norm(),
    )?;
    out.set_item(
        intern!(py, "precession_rate_space"),
        free.precession_rate_space(),
    )?;
    out.set_item(intern!(py, "nutation_angle"), free.nutation_angle())?;
    Ok(out)
}

/// The methods by name and how each steps (`"auto"`, `"exact"`, `"fixed"`, `"adaptive"`), in
/// the core's order: what `polhode.simulate` and the command line offer.
pub fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let table = PyDict::new(py);
    for (name, stepping) in METHODS {
        table.set_item(name, stepping.name())?;
    }
    Ok(table)
}

/// The output quantities, in the order of the `Trajectory`'s fields: a tuple of dicts with
/// `name`, `shape` (per output time; `"rotors"` for the number of rotors), `unit` (SI),
/// `frame` (`"body"`, `"space"` or `"none"`), `description` and `requires` (`"orientation"`,
/// `"rotors"`: what the run needs to report it). What `polhode` reads to know its outputs.
pub fn quantities(py: Python<'_>) -> PyResult<Bound<'_, PyTuple>> {
    let rows = Quantity::ALL
        .iter()
        .map(|q| -> PyResult<Bound<'_, PyDict>> {
            let row = PyDict::new(py);
            row.set_item("name", q.name())?;
            let shape: Vec<Bound<'_, PyAny>> = q
                .dims()
                .iter()
                .map(|d| match d {
                    Dim::Fixed(n) => n
                        .into_pyobject(py)
                        .map_or_else(|e| match e {}, Bound::into_any),
                    Dim::Rotors => PyString::new(py, "rotors").into_any(),
                })
                .collect();
            row.set_item("shape", PyTuple::new(py, shape)?)?;
            row.set_item("unit", q.unit())?;
            row.set_item("frame", q.frame().name())?;
            row.set_item("description", q.description())?;
            let mut requires = Vec::new();
            if q.needs_orientation() {
                requires.push("orientation");
            }
            if q.needs_rotors() {
                requires.push("rotors");
            }
            row.set_item("requires", PyTuple::new(py, requires)?)?;
            Ok(row)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyTuple::new(py, rows)
}
