//! Torque models from their Python objects (`polhode.torque`), read by their named fields into
//! the core's [`TorqueSpec`]; the core validates, builds and rotates them.

use std::sync::Arc;

use nalgebra::{UnitQuaternion, Vector3};
use polhode::dynamics::{Fields, FunctionSpec, TorqueSpec};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::errors::CoreError;
use crate::watch::Call;

/// A Python model's fields (a `polhode.torque` model or a `polhode.rotors` rotor), read by
/// name for the core: the one reader behind [`Fields`] and `RotorFields`.
pub(crate) struct PyFields<'a, 'py> {
    pub(crate) obj: &'a Bound<'py, PyAny>,
    /// The call the model's Python functions are called back in.
    pub(crate) call: &'a Call,
}

impl PyFields<'_, '_> {
    /// A number field, None when it holds None.
    pub(crate) fn read_number(&self, name: &str) -> PyResult<Option<f64>> {
        self.obj.getattr(name)?.extract()
    }

    /// A 3-vector field, None when it holds None.
    pub(crate) fn read_vector(&self, name: &str) -> PyResult<Option<Vector3<f64>>> {
        let value: Option<[f64; 3]> = self.obj.getattr(name)?.extract()?;
        Ok(value.map(Vector3::from))
    }
}

/// The `kind` of a model (its class name), or a TypeError saying what was `expected`, with the
/// object's type.
pub(crate) fn kind_of(obj: &Bound<'_, PyAny>, expected: &str) -> PyResult<String> {
    obj.getattr("kind").and_then(|k| k.extract()).map_err(|_| {
        let name = obj
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default();
        PyTypeError::new_err(format!("Expected {expected}, got {name}."))
    })
}

impl Fields for PyFields<'_, '_> {
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

    fn model(&self, name: &str) -> PyResult<TorqueSpec> {
        torque_spec(&self.obj.getattr(name)?, self.call)
    }

    fn models(&self, name: &str) -> PyResult<Vec<TorqueSpec>> {
        let models: Vec<Bound<'_, PyAny>> = self.obj.getattr(name)?.extract()?;
        models.iter().map(|m| torque_spec(m, self.call)).collect()
    }
}

/// The spec of a `polhode.torque` model, dispatched on its `kind` (its class name); its Python
/// function, if any, is called back in `call`.
pub(crate) fn torque_spec(obj: &Bound<'_, PyAny>, call: &Call) -> PyResult<TorqueSpec> {
    let kind = kind_of(obj, "`torque` to be a polhode.torque model or a callable")?;
    Ok(match kind.as_str() {
        "Function" => {
            // `_call(t, omega, quaternion)` calls the user's function and checks what it
            // returned; its first exception stops the whole call and is raised as it was.
            let method = obj.getattr("_call")?.unbind();
            let call = call.clone();
            let function = move |t: f64, w: &Vector3<f64>, q: &UnitQuaternion<f64>| {
                call.call_back(
                    |py| {
                        method
                            .call1(py, (t, [w.x, w.y, w.z], [q.i, q.j, q.k, q.w]))
                            .and_then(|value| value.extract::<[f64; 3]>(py))
                            .map(Vector3::from)
                    },
                    |message| polhode::Error::InvalidArgument {
                        name: "torque".into(),
                        reason: format!("the function raised {message}"),
                    },
                )
            };
            TorqueSpec::Function(FunctionSpec {
                function: Arc::new(function),
                depends_on_orientation: obj.getattr("depends_on_orientation")?.extract()?,
                depends_on_omega: obj.getattr("depends_on_omega")?.extract()?,
                discontinuities: obj.getattr("discontinuities")?.extract()?,
            })
        }
        other => TorqueSpec::from_fields(other, &PyFields { obj, call })?,
    })
}

/// Whether the spec calls into Python (then the bodies run one after another).
pub(crate) fn calls_python(spec: &TorqueSpec) -> bool {
    match spec {
        TorqueSpec::Function(_) => true,
        TorqueSpec::Window { torque, .. } => calls_python(torque),
        TorqueSpec::Sum(terms) => terms.iter().any(calls_python),
        _ => false,
    }
}

/// Checks a torque model's own parameters (called by its constructor).
#[pyfunction]
pub fn check_torque(torque: &Bound<'_, PyAny>) -> PyResult<()> {
    let spec = torque_spec(torque, &Call::new(None, 1, 0.0))?;
    spec.check().map_err(CoreError)?;
    Ok(())
}
