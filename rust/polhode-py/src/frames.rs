//! The inertia tensors of the frames of a point-mass trajectory: `point_masses_inertia`.

use numpy::ndarray::Array;
use numpy::{
    Element, IntoPyArray, PyArrayDyn, PyReadonlyArray1, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use polhode::mass::Position;
use polhode::memory::Purpose;
use pyo3::prelude::*;

use crate::convert::bad_shape;
use crate::errors::CoreError;
use crate::watch::{run_on_pool, Call};

/// Inertia tensors (3, 3) of one frame (N, 3) of point masses, or (T, 3, 3) of a trajectory
/// (T, N, 3), each about its frame's centre of mass, in parallel with the GIL released.
/// `positions` is float64 or float32 (read as it is, uncopied), C-contiguous.
#[pyfunction]
pub fn point_masses_inertia<'py>(
    py: Python<'py>,
    masses: PyReadonlyArray1<'py, f64>,
    positions: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(p) = positions.extract::<PyReadonlyArrayDyn<'py, f64>>() {
        inertia_of::<f64>(py, &masses, &p)
    } else if let Ok(p) = positions.extract::<PyReadonlyArrayDyn<'py, f32>>() {
        inertia_of::<f32>(py, &masses, &p)
    } else {
        Err(pyo3::exceptions::PyTypeError::new_err(
            "Expected `positions` to be a numpy array of float64 or float32.",
        ))
    }
}

fn inertia_of<'py, F>(
    py: Python<'py>,
    masses: &PyReadonlyArray1<'py, f64>,
    positions: &PyReadonlyArrayDyn<'py, F>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>>
where
    F: Element + Copy + Send + Sync,
    [F; 3]: Position,
{
    let shape = positions.shape().to_vec();
    let n = masses.len();
    let single = shape.len() == 2;
    let points_ok = match shape.as_slice() {
        [rows, 3] | [_, rows, 3] => *rows == n,
        _ => false,
    };
    if !points_ok {
        let expected = format!("({n}, 3) or (T, {n}, 3) to match `masses`");
        return Err(bad_shape("positions", &expected, &shape));
    }
    let frames = if single { 1 } else { shape[0] };
    let (masses, positions) = match (masses.as_slice(), positions.as_slice()) {
        (Ok(m), Ok(p)) => (m, p.as_chunks::<3>().0),
        _ => {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "Expected C-contiguous `masses` and `positions`.",
            ))
        }
    };
    let mut inertia =
        polhode::memory::zeros::<f64>(9 * frames, Purpose::FrameTensors).map_err(CoreError)?;
    let long = positions.len() > 2 * polhode::mass::FRAME_POINTS_CHUNK
        && rayon::current_thread_index().is_none();
    let result = if long {
        let call = Call::new(None, 1, 0.0);
        let result = py.detach(|| {
            run_on_pool(&call, || {
                polhode::mass::point_masses_inertia_monitored(
                    masses,
                    positions,
                    &mut inertia,
                    Some(call.monitor()),
                )
            })
        });
        if let Some(error) = call.take_raised() {
            return Err(error);
        }
        result.unwrap_or_else(|| unreachable!("a panic of the work is re-raised by its scope"))
    } else {
        py.detach(|| polhode::mass::point_masses_inertia(masses, positions, &mut inertia))
    };
    result.map_err(|e| {
        let e = if single {
            e.map_name(|name| name.replacen("positions[0, ", "positions[", 1))
        } else {
            e
        };
        PyErr::from(CoreError(e))
    })?;
    let shape = if single {
        vec![3, 3]
    } else {
        vec![frames, 3, 3]
    };
    Ok(Array::from_shape_vec(shape, inertia)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?
        .into_pyarray(py))
}
