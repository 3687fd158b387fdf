//! `simulate` (every method, one body or a batch) and `free_rotation` (the exact solution's
//! invariants for `analyze`).
//!
//! Bodies arrive in principal axes (the Python layer rotates them there and back). Torques
//! arrive as a plain spec tree of tuples, parsed here with the GIL held into [`TorqueSpec`],
//! then built into a Rust torque per body (a gravity-gradient torque needs each body's moments)
//! inside the parallel loop.

use std::sync::{Arc, Mutex};

use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use numpy::ndarray::{Array2, Array3};
use numpy::{
    IntoPyArray, PyArray2, PyArray3, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use polhode::dynamics::{
    integrate, BodyConstantTorque, Dop853Options, FnTorque, GravityGradient, Method, Options,
    PivotGravity, SpaceConstantTorque, SplittingOrder, State, Torque, TorqueSum, Trajectory,
    Windowed,
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

/// One body's trajectory by the closed form, at each output time (`t0` shifts the origin).
fn exact_trajectory(
    moments: &Vector3<f64>,
    state: &State,
    times: &[f64],
    t0: f64,
    with_attitude: bool,
) -> polhode::Result<Trajectory> {
    let free = FreeRotation::new(*moments, state.omega, state.attitude)?;
    let mut omega = Vec::with_capacity(times.len());
    let mut attitude = with_attitude.then(|| Vec::with_capacity(times.len()));
    for &t in times {
        match attitude.as_mut() {
            Some(list) => {
                let (w, q) = free.state(t - t0);
                omega.push(w);
                list.push(q);
            }
            None => omega.push(free.omega(t - t0)),
        }
    }
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

/// Integrates N bodies (principal moments (N, 3), omega0 (N, 3), quaternion0 (N, 4) xyzw) to
/// the output times; returns omega (N, M, 3), quaternion (N, M, 4) or None, and stats (N, 3):
/// steps, rejected steps, evaluations.
#[pyfunction]
#[pyo3(signature = (
    moments, omega0, quaternion0, times, *, t0, method, dt, order, rtol, atol, torque,
    with_attitude, max_steps
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
) -> PyResult<(
    Bound<'py, PyArray3<f64>>,
    Option<Bound<'py, PyArray3<f64>>>,
    Bound<'py, PyArray2<u64>>,
)> {
    let moments = rows::<3>("moments", &moments, None)?;
    let n = moments.len();
    let omega0 = rows::<3>("omega0", &omega0, Some(n))?;
    let quaternion0 = rows::<4>("quaternion0", &quaternion0, Some(n))?;
    let times: Vec<f64> = times.as_array().to_vec();
    let method = parse_method(method, dt, order, rtol, atol)?;
    let spec = torque.as_ref().map(parse_torque).transpose()?;
    if method.is_none() && spec.is_some() {
        return Err(PolhodeError::new_err(
            "Expected no `torque` with method \"exact\" (the closed form is torque-free); use \
             \"dop853\" or another integrator.",
        ));
    }
    let serial = spec.as_ref().is_some_and(contains_callable);
    let raised: Raised = Arc::new(Mutex::new(None));
    let run = |i: usize| -> polhode::Result<Trajectory> {
        let m = Vector3::from(moments[i]);
        let q = quaternion0[i];
        let attitude = UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]));
        let state = State::new(Vector3::from(omega0[i]), attitude);
        let result = match (&method, &spec) {
            (None, _) => exact_trajectory(&m, &state, &times, t0, with_attitude),
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
    let results: Vec<polhode::Result<Trajectory>> = py.detach(|| {
        if serial {
            (0..n).map(run).collect()
        } else {
            (0..n).into_par_iter().map(run).collect()
        }
    });
    if let Some(error) = raised.lock().ok().and_then(|mut slot| slot.take()) {
        return Err(error);
    }
    let trajectories = results
        .into_iter()
        .collect::<polhode::Result<Vec<_>>>()
        .map_err(CoreError)?;
    let m = times.len();
    let mut omega = Array3::<f64>::zeros((n, m, 3));
    let mut quaternion = with_attitude.then(|| Array3::<f64>::zeros((n, m, 4)));
    let mut stats = Array2::<u64>::zeros((n, 3));
    for (i, trajectory) in trajectories.iter().enumerate() {
        for (k, w) in trajectory.omega.iter().enumerate() {
            for c in 0..3 {
                omega[[i, k, c]] = w[c];
            }
        }
        if let (Some(out), Some(list)) = (quaternion.as_mut(), trajectory.attitude.as_ref()) {
            for (k, q) in list.iter().enumerate() {
                let xyzw = [q.i, q.j, q.k, q.w];
                for c in 0..4 {
                    out[[i, k, c]] = xyzw[c];
                }
            }
        }
        let s = &trajectory.stats;
        stats[[i, 0]] = s.steps;
        stats[[i, 1]] = s.rejected_steps;
        stats[[i, 2]] = s.rhs_evaluations;
    }
    Ok((
        omega.into_pyarray(py),
        quaternion.map(|q| q.into_pyarray(py)),
        stats.into_pyarray(py),
    ))
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
