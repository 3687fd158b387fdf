//! `fastest_rate`: how fast a run's bodies turn, for the output times of `polhode.simulate`
//! with an end time. Converts the arguments as `simulate` does and calls the core.

use numpy::PyReadonlyArrayDyn;
use polhode::simulation::{fastest_rate as core_fastest_rate, fixed_steps, Simulation};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::CoreError;
use crate::motion::{motion, run_settings, Motion};
use crate::torque::calls_python;
use crate::watch::Call;

/// The fastest rate (rad per unit time) of the motions of `body` from `omega0` at `t0` until
/// `t_end`, with the arguments of `simulate` (one body, or N): a dict with `rate`, `pace`
/// (what sets it: `"rest"`, `"spin"`, `"period"`, `"precession"`, `"torque"`, `"rotors"`),
/// `body` (the index of the fastest body), `steps` (the steps a fixed-step method takes from
/// `t0` to `t_end`, None for the others) and `method` (its name, `"auto"` resolved). The errors
/// are `simulate`'s for the output times `[t0, t_end]`. A Python torque function is called once
/// per body, at `t0`.
#[pyfunction]
#[pyo3(signature = (
    body, omega0, t_end, *, orientation0=None, t0=0.0, method="auto", dt=None, order=4,
    rtol=1e-10, atol=None, torque=None, rotors=None
))]
#[allow(clippy::too_many_arguments)]
pub fn fastest_rate<'py>(
    py: Python<'py>,
    body: &Bound<'py, PyAny>,
    omega0: PyReadonlyArrayDyn<'py, f64>,
    t_end: f64,
    orientation0: Option<PyReadonlyArrayDyn<'py, f64>>,
    t0: f64,
    method: &str,
    dt: Option<f64>,
    order: i64,
    rtol: f64,
    atol: Option<f64>,
    torque: Option<Bound<'py, PyAny>>,
    rotors: Option<Vec<Bound<'py, PyAny>>>,
) -> PyResult<Bound<'py, PyDict>> {
    let Motion {
        bodies,
        omega0,
        orientation0,
        ..
    } = motion(body, &omega0, orientation0)?;
    // Ctrl-C and the first exception of a Python torque or motor stop it as they stop
    // `simulate` (one cancellation path: `watch::Call`).
    let call = Call::new(None, 1, 0.0);
    let (spec, rotors, method) = run_settings(
        torque.as_ref(),
        rotors,
        method,
        (dt, order, rtol, atol),
        &call,
    )?;
    // Bodies in parallel but with a Python torque or motor (called with the GIL, one body
    // after another), the GIL released as `simulate` releases it.
    let serial = spec.as_ref().is_some_and(calls_python) || rotors.iter().any(|r| r.has_function());
    let run = Simulation {
        method,
        t0,
        with_orientation: true,
        max_steps: 1,
        torque: spec,
        parallel: omega0.len() > 1 && !serial,
        rotors,
    };
    let rate = py.detach(|| core_fastest_rate(&run, &bodies, &omega0, &orientation0, t_end));
    if let Some(error) = call.take_raised() {
        return Err(error);
    }
    let rate = rate.map_err(CoreError)?;
    let out = PyDict::new(py);
    out.set_item("rate", rate.rate)?;
    out.set_item("pace", rate.pace.name())?;
    out.set_item("body", rate.body)?;
    out.set_item("steps", fixed_steps(&run.method, t0, t_end))?;
    out.set_item("method", run.method.name())?;
    Ok(out)
}
