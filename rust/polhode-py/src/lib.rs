//! Python bindings for the polhode core crate: convert, validate, release the GIL, call the core.
//!
//! Nothing here does physics. Arrays arrive as C-contiguous float64 (the Python layer coerces
//! them) and are still checked for shape here, so that no input can panic across the FFI.

mod convert;
mod errors;
mod mass;
mod motion;

/// The compiled core of polhode. Use the `polhode` package, not this module.
#[pyo3::pymodule]
mod _core {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::mass::{principal, PyMassProperties};

    #[pymodule_export]
    use crate::motion::{free_rotation, simulate};

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        crate::errors::register(m)
    }
}
