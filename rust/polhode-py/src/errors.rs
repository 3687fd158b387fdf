//! The core's `Error` carried to Python as the typed exceptions of `polhode.errors`, with the
//! argument at fault (`argument`) and, in a batch, the body (`body`) as attributes.
//!
//! One match arm per kind of core error; the classes are imported from `polhode.errors` once
//! per process (a failed import is raised as it is, never replaced by another class).

use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyType};

/// The core's error, carried to Python.
pub(crate) struct CoreError(pub polhode::Error);

impl From<polhode::Error> for CoreError {
    fn from(error: polhode::Error) -> Self {
        Self(error)
    }
}

/// A class of `polhode.errors`, imported once per process.
struct Class {
    cell: PyOnceLock<Py<PyType>>,
    name: &'static str,
}

impl Class {
    const fn new(name: &'static str) -> Self {
        Self {
            cell: PyOnceLock::new(),
            name,
        }
    }

    /// `class(message, argument=..., body=...)` as a Python exception.
    fn raise(
        &self,
        py: Python<'_>,
        message: String,
        argument: Option<&str>,
        body: Option<usize>,
    ) -> PyErr {
        let made = (|| -> PyResult<PyErr> {
            let class = self.cell.import(py, "polhode.errors", self.name)?;
            let kwargs = PyDict::new(py);
            kwargs.set_item(pyo3::intern!(py, "argument"), argument)?;
            kwargs.set_item(pyo3::intern!(py, "body"), body)?;
            Ok(PyErr::from_value(class.call((message,), Some(&kwargs))?))
        })();
        made.unwrap_or_else(|error| error)
    }
}

static POLHODE_ERROR: Class = Class::new("PolhodeError");
static NON_FINITE_ERROR: Class = Class::new("NonFiniteError");
static NON_POSITIVE_ERROR: Class = Class::new("NonPositiveError");
static SHAPE_ERROR: Class = Class::new("ShapeError");
static INERTIA_ERROR: Class = Class::new("InertiaError");
static ARGUMENT_ERROR: Class = Class::new("ArgumentError");
static CONVERGENCE_ERROR: Class = Class::new("ConvergenceError");

impl From<CoreError> for PyErr {
    fn from(error: CoreError) -> PyErr {
        use polhode::Error as E;
        let (body, inner) = match error.0 {
            E::Body { body, error } => (Some(body), *error),
            other => (None, other),
        };
        let class = match &inner {
            E::Interrupted => return PyKeyboardInterrupt::new_err(inner.to_string()),
            E::OutOfMemory { .. } => return PyMemoryError::new_err(inner.to_string()),
            E::NonFinite { .. } | E::BlewUp { .. } => &NON_FINITE_ERROR,
            E::NonPositive { .. } => &NON_POSITIVE_ERROR,
            E::Shape { .. } => &SHAPE_ERROR,
            E::InvalidInertia { .. } => &INERTIA_ERROR,
            E::InvalidArgument { .. } => &ARGUMENT_ERROR,
            E::NoConvergence { .. } => &CONVERGENCE_ERROR,
            // `Body` is unwrapped above; a kind added to the core (the enum is
            // non-exhaustive) is the base class until it has its own.
            _ => &POLHODE_ERROR,
        };
        Python::attach(|py| class.raise(py, inner.to_string(), inner.argument(), body))
    }
}

/// `Result` whose error converts to a Python exception.
pub(crate) type CoreResult<T> = Result<T, CoreError>;
