//! Python bindings for the polhode core crate: convert, release the GIL, call the core.
//!
//! Nothing here does physics. Arrays arrive as float64 (the Python layer coerces types) and
//! are checked for shape here, so that no input can panic across the FFI; values are
//! validated by the core, once.

mod convert;
mod errors;
mod frames;
mod mass;
mod motion;
mod rotors;
mod sampling;
mod torque;
mod watch;

/// The compiled core of polhode. Use the `polhode` package, not this module.
#[pyo3::pymodule]
mod _core {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::frames::point_masses_inertia;

    #[pymodule_export]
    use crate::mass::{merge_vertices, principal, PyMassProperties};

    #[pymodule_export]
    use crate::motion::{check_motion, free_rotation, simulate};

    #[pymodule_export]
    use crate::rotors::check_rotor;

    #[pymodule_export]
    use crate::sampling::fastest_rate;

    #[pymodule_export]
    use crate::torque::check_torque;

    #[pymodule_export]
    use crate::watch::{cancel_all, cancel_epoch};

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("SOLIDS", crate::mass::solids(m.py())?)?;
        m.add("METHODS", crate::motion::methods(m.py())?)?;
        m.add("QUANTITIES", crate::motion::quantities(m.py())?)
    }
}
