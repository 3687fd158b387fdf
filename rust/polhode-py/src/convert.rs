//! Conversions between numpy arrays and nalgebra values, with shape checks that name the
//! argument. numpy is row-major and nalgebra column-major: matrices are built element by element.

use nalgebra::{Matrix3, Vector3};
use numpy::ndarray::{Array1, Array2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
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
