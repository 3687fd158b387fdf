//! The Python exceptions and the mapping from the core's `Error` to them.

use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    polhode,
    PolhodeError,
    PyValueError,
    "Base class of polhode's domain errors (a ValueError)."
);
create_exception!(
    polhode,
    InertiaError,
    PolhodeError,
    "An inertia tensor that is asymmetric, not positive semidefinite or breaks I1 + I2 >= I3."
);

/// Adds the exception types to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("PolhodeError", py.get_type::<PolhodeError>())?;
    m.add("InertiaError", py.get_type::<InertiaError>())?;
    Ok(())
}

/// The core's error, carried to Python.
pub(crate) struct CoreError(pub polhode::Error);

impl From<polhode::Error> for CoreError {
    fn from(error: polhode::Error) -> Self {
        Self(error)
    }
}

impl From<CoreError> for PyErr {
    fn from(error: CoreError) -> PyErr {
        let message = error.0.to_string();
        match error.0 {
            polhode::Error::InvalidInertia { .. } => InertiaError::new_err(message),
            polhode::Error::NoConvergence { .. } => PyRuntimeError::new_err(message),
            polhode::Error::Interrupted => PyKeyboardInterrupt::new_err(message),
            _ => PolhodeError::new_err(message),
        }
    }
}

/// `Result` whose error converts to a Python exception.
pub(crate) type CoreResult<T> = Result<T, CoreError>;
