//! Rotors from their Python objects (`polhode.rotors`), read by their named fields into the
//! core's [`RotorSpec`]; the core validates them and integrates the gyrostat.

use std::sync::Arc;

use nalgebra::Vector3;
use numpy::PyReadonlyArrayDyn;
use polhode::dynamics::{MotorTorque, RotorFields, RotorSpec};
use polhode::memory::{self, Purpose};
use pyo3::prelude::*;

use crate::errors::CoreError;
use crate::torque::{kind_of, PyFields};
use crate::watch::Call;

/// A `polhode.rotors` rotor's fields, read by name for the core (the reader of the torque
/// models, plus the motor torque).
impl RotorFields for PyFields<'_, '_> {
    type Error = PyErr;

    fn error(error: polhode::Error) -> PyErr {
        CoreError(error).into()
    }

    fn number(&self, name: &str) -> PyResult<Option<f64>> {
        self.read_number(name)
    }

    fn vector(&self, name: &str) -> PyResult<Option<Vector3<f64>>> {
        self.read_vector(name)
    }

    /// A number (constant), a (K, 2) array of (time, torque) pairs (a schedule), or, when the
    /// field holds a callable, `_call_torque(t, omega, rate)` of the object, which calls it and
    /// checks what it returned; its first exception is kept and raised as it was.
    fn motor(&self, name: &str) -> PyResult<MotorTorque> {
        let value = self.obj.getattr(name)?;
        if value.is_callable() {
            let method = self.obj.getattr("_call_torque")?.unbind();
            let call = self.call.clone();
            let function = move |t: f64, w: &Vector3<f64>, rate: f64| {
                call.call_back(
                    |py| {
                        method
                            .call1(py, (t, [w.x, w.y, w.z], rate))
                            .and_then(|value| value.extract::<f64>(py))
                    },
                    |message| polhode::Error::InvalidArgument {
                        name: "rotors".into(),
                        reason: format!("a wheel's torque function raised {message}"),
                    },
                )
            };
            return Ok(MotorTorque::Function(Arc::new(function)));
        }
        if let Ok(g) = value.extract::<f64>() {
            return Ok(MotorTorque::Constant(g));
        }
        let array: PyReadonlyArrayDyn<'_, f64> = value.extract()?;
        let view = array.as_array();
        let shape = view.shape().to_vec();
        if shape.len() != 2 || shape[1] != 2 {
            return Err(crate::convert::bad_shape(
                name,
                "(K, 2) (time, torque) pairs",
                &shape,
            ));
        }
        let copy = |values: &mut dyn Iterator<Item = f64>| {
            memory::collect(values, Purpose::Input).map_err(CoreError)
        };
        let times = copy(&mut view.iter().step_by(2).copied())?;
        let values = copy(&mut view.iter().skip(1).step_by(2).copied())?;
        Ok(MotorTorque::Schedule { times, values })
    }
}

/// The spec of a `polhode.rotors` rotor, dispatched on its `kind` (its class name).
pub(crate) fn rotor_spec(obj: &Bound<'_, PyAny>, call: &Call) -> PyResult<RotorSpec> {
    let kind = kind_of(
        obj,
        "`rotors` to hold polhode.rotors rotors (Wheel, SphericalDamper)",
    )?;
    RotorSpec::from_fields(&kind, &PyFields { obj, call })
}

/// Checks a rotor's own parameters (called by its constructor).
#[pyfunction]
pub fn check_rotor(rotor: &Bound<'_, PyAny>) -> PyResult<()> {
    let spec = rotor_spec(rotor, &Call::new(None, 1, 0.0))?;
    spec.check().map_err(CoreError)?;
    Ok(())
}
