//! Rotors from their Python objects (`polhode.rotors`), read by their named fields into the
//! core's [`RotorSpec`]; the core validates them and integrates the gyrostat.

use std::sync::Arc;

use nalgebra::Vector3;
use numpy::PyReadonlyArrayDyn;
use polhode::dynamics::{MotorTorque, RotorFields, RotorSpec};
use pyo3::prelude::*;

use crate::errors::CoreError;
use crate::torque::{kind_of, PyFields, Raised};

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
            let call = self.obj.getattr("_call_torque")?.unbind();
            let raised = Arc::clone(self.raised);
            let function = move |t: f64, w: &Vector3<f64>, rate: f64| {
                Python::attach(|py| -> polhode::Result<f64> {
                    let result = call
                        .call1(py, (t, [w.x, w.y, w.z], rate))
                        .and_then(|value| value.extract::<f64>(py));
                    result.map_err(|error| {
                        let message = error.to_string();
                        if let Ok(mut slot) = raised.lock() {
                            slot.get_or_insert(error);
                        }
                        polhode::Error::InvalidArgument {
                            name: "rotors".into(),
                            reason: format!("a wheel's torque function raised {message}"),
                        }
                    })
                })
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
        let pairs: Vec<f64> = view.iter().copied().collect();
        let times = pairs.iter().step_by(2).copied().collect();
        let values = pairs.iter().skip(1).step_by(2).copied().collect();
        Ok(MotorTorque::Schedule { times, values })
    }
}

/// The spec of a `polhode.rotors` rotor, dispatched on its `kind` (its class name).
pub(crate) fn rotor_spec(obj: &Bound<'_, PyAny>, raised: &Raised) -> PyResult<RotorSpec> {
    let kind = kind_of(
        obj,
        "`rotors` to hold polhode.rotors rotors (Wheel, SphericalDamper)",
    )?;
    RotorSpec::from_fields(&kind, &PyFields { obj, raised })
}

/// Checks a rotor's own parameters (called by its constructor).
#[pyfunction]
pub fn check_rotor(rotor: &Bound<'_, PyAny>) -> PyResult<()> {
    let raised: Raised = Arc::new(std::sync::Mutex::new(None));
    let spec = rotor_spec(rotor, &raised)?;
    spec.check().map_err(CoreError)?;
    Ok(())
}
