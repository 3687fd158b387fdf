//! The core's `Error` carried to Python as the typed exceptions of `polhode.errors`, with the
//! argument at fault (`argument`) and, in a batch, the body (`body`) as attributes.

use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The core's error, carried to Python.
pub(crate) struct CoreError(pub polhode::Error);

impl From<polhode::Error> for CoreError {
    fn from(error: polhode::Error) -> Self {
        Self(error)
    }
}

/// The class of `polhode.errors` for each kind of core error.
fn class_name(error: &polhode::Error) -> &'static str {
    use polhode::Error as E;
    match error {
        E::NonFinite { .. } | E::BlewUp { .. } => "NonFiniteError",
        E::NonPositive { .. } => "NonPositiveError",
        E::Shape { .. } => "ShapeError",
        E::InvalidInertia { .. } => "InertiaError",
        E::InvalidArgument { .. } => "ArgumentError",
        E::NoConvergence { .. } => "ConvergenceError",
        _ => "PolhodeError",
    }
}

fn raise(
    py: Python<'_>,
    class: &str,
    message: String,
    argument: Option<&str>,
    body: Option<usize>,
) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let class = py.import("polhode.errors")?.getattr(class)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("argument", argument)?;
        kwargs.set_item("body", body)?;
        Ok(PyErr::from_value(
            class.call((message.clone(),), Some(&kwargs))?,
        ))
    })();
    made.unwrap_or_else(|_| PyValueError::new_err(message))
}

impl From<CoreError> for PyErr {
    fn from(error: CoreError) -> PyErr {
        let (body, inner) = match error.0 {
            polhode::Error::Body { body, error } => (Some(body), *error),
            other => (None, other),
        };
        match inner {
            polhode::Error::Interrupted => return PyKeyboardInterrupt::new_err(inner.to_string()),
            polhode::Error::OutOfMemory { .. } => return PyMemoryError::new_err(inner.to_string()),
            _ => {}
        }
        Python::attach(|py| {
            raise(
                py,
                class_name(&inner),
                inner.to_string(),
                inner.argument(),
                body,
            )
        })
    }
}

/// An `ArgumentError` naming `name`, for what the binding itself parses (a method's name).
pub(crate) fn argument_error(name: &str, reason: &str) -> PyErr {
    CoreError(polhode::Error::InvalidArgument {
        name: name.into(),
        reason: reason.into(),
    })
    .into()
}

/// `Result` whose error converts to a Python exception.
pub(crate) type CoreResult<T> = Result<T, CoreError>;
