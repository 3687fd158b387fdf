//! Conversions between numpy arrays and nalgebra values, with shape checks that name the
//! argument. numpy is row-major and nalgebra column-major: matrices are built element by element.

use nalgebra::{Matrix3, Vector3};
use numpy::ndarray::{Array1, Array2, Dimension, IntoDimension};
use numpy::{
    Element, IntoPyArray, PyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyReadonlyArray1,
    PyReadonlyArray2, PyUntypedArrayMethods, ToNpyDims, PY_ARRAY_API,
};
use polhode::memory::Purpose;
use pyo3::prelude::*;

use crate::errors::CoreError;

/// A `ShapeError` naming the argument: ``Expected `name` to have shape (3,), got (2,).``
pub(crate) fn bad_shape(name: &str, expected: &str, shape: &[usize]) -> PyErr {
    let got: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let got = if got.len() == 1 {
        format!("({},)", got[0])
    } else {
        format!("({})", got.join(", "))
    };
    CoreError(polhode::Error::Shape {
        name: name.into(),
        expected: expected.into(),
        got,
    })
    .into()
}

/// A (3,) array as a vector.
pub(crate) fn vector3(name: &str, a: &PyReadonlyArray1<'_, f64>) -> PyResult<Vector3<f64>> {
    if a.shape() != [3] {
        return Err(bad_shape(name, "(3,)", a.shape()));
    }
    let v = a.as_array();
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// A (3, 3) array as a matrix.
pub(crate) fn matrix3(name: &str, a: &PyReadonlyArray2<'_, f64>) -> PyResult<Matrix3<f64>> {
    if a.shape() != [3, 3] {
        return Err(bad_shape(name, "(3, 3)", a.shape()));
    }
    let v = a.as_array();
    Ok(Matrix3::from_fn(|r, c| v[[r, c]]))
}

pub(crate) fn vector_to_py<'py>(py: Python<'py>, v: &Vector3<f64>) -> Bound<'py, PyArray1<f64>> {
    Array1::from_iter(v.iter().copied()).into_pyarray(py)
}

pub(crate) fn matrix_to_py<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_fn((3, 3), |(r, c)| m[(r, c)]).into_pyarray(py)
}

/// A zeroed C-contiguous numpy array of `shape` (numpy's own allocation, which asks the kernel
/// for huge pages for a large array), or `MemoryError` saying what it was for (`purpose`) and
/// what to ask for instead, with numpy's own error as its cause.
///
/// numpy's `PyArray::zeros` panics (`PyObject pointer is null`, a `PanicException` in Python)
/// when numpy cannot allocate: this is the same call, its failure checked.
pub(crate) fn zeros<'py, T, D>(
    py: Python<'py>,
    shape: impl IntoDimension<Dim = D>,
    purpose: Purpose,
) -> PyResult<Bound<'py, PyArray<T, D>>>
where
    T: Element,
    D: Dimension + ToNpyDims,
{
    let mut dims = shape.into_dimension();
    let bytes = dims.slice().iter().map(|&d| d as f64).product::<f64>() * size_of::<T>() as f64;
    // SAFETY: as `PyArray::zeros`: the dimensions' pointer is valid for `ndim` values for the
    // call, and `into_dtype_ptr` gives a new reference to the element type's descriptor, which
    // `PyArray_Zeros` steals.
    let made = unsafe {
        PY_ARRAY_API.PyArray_Zeros(
            py,
            dims.ndim_cint(),
            dims.as_dims_ptr(),
            T::get_dtype(py).into_dtype_ptr(),
            0,
        )
    };
    // SAFETY: `made` is a new reference, or null with numpy's exception set.
    let made = unsafe { Bound::from_owned_ptr_or_err(py, made) }.map_err(|numpy_error| {
        let error = PyErr::from(CoreError(purpose.error(bytes)));
        error.set_cause(py, Some(numpy_error));
        error
    })?;
    // SAFETY: numpy made an array of `T`'s descriptor with `D`'s number of dimensions.
    Ok(unsafe { made.cast_into_unchecked() })
}
