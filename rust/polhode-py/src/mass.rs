//! `MassProperties` and the batch principal-axes solve.

use numpy::ndarray::Array;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1,
    PyReadonlyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use polhode::mass::SOLIDS;
use polhode::memory::Purpose;
use polhode::MassProperties;
use polhode::Monitor;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{bad_shape, matrix3, matrix_to_py, vector3, vector_to_py, zeros};
use crate::errors::{CoreError, CoreResult};
use crate::watch::{run_on_pool, Call};

/// Runs `work` (given a monitor to look at) with the GIL released. A long call (`long`) runs on
/// the rayon pool while this thread polls for Ctrl-C every 50 ms (see [`run_on_pool`]): Ctrl-C
/// cancels the monitor, the work stops at its next chunk and KeyboardInterrupt is raised. A
/// short call, or one from a thread of the pool itself, runs here. The work's result does not
/// depend on where it runs.
fn watched<T: Send>(
    py: Python<'_>,
    long: bool,
    work: impl FnOnce(Option<&Monitor>) -> polhode::Result<T> + Send,
) -> PyResult<T> {
    if !long || rayon::current_thread_index().is_some() {
        return Ok(py.detach(|| work(None)).map_err(CoreError)?);
    }
    let call = Call::new(None, 1, 0.0);
    let result = py.detach(|| run_on_pool(&call, || work(Some(call.monitor()))));
    if let Some(error) = call.take_raised() {
        return Err(error);
    }
    let result =
        result.unwrap_or_else(|| unreachable!("a panic of the work is re-raised by its scope"));
    Ok(result.map_err(CoreError)?)
}

/// The vertices (N, 3) and faces (M, 3) of [`merge_vertices`].
type MergedArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>);

/// A mesh's vertices and faces as rows of three.
type MeshRows<'a> = (&'a [[f64; 3]], &'a [[i64; 3]]);

/// A mesh's vertices (N, 3) and faces (M, 3) as rows, borrowed from the numpy buffers
/// (C-contiguous from the Python layer); a shape error naming the argument otherwise.
fn mesh_rows<'a>(
    vertices: &'a PyReadonlyArray2<'_, f64>,
    faces: &'a PyReadonlyArray2<'_, i64>,
) -> PyResult<MeshRows<'a>> {
    if vertices.shape()[1] != 3 {
        return Err(bad_shape("vertices", "(N, 3)", vertices.shape()));
    }
    if faces.shape()[1] != 3 {
        return Err(bad_shape("faces", "(M, 3)", faces.shape()));
    }
    match (vertices.as_slice(), faces.as_slice()) {
        (Ok(v), Ok(f)) => Ok((v.as_chunks::<3>().0, f.as_chunks::<3>().0)),
        _ => Err(pyo3::exceptions::PyValueError::new_err(
            "Expected C-contiguous `vertices` and `faces`.",
        )),
    }
}

/// A file's vertices at the same position merged (the first kept, in order of appearance), the
/// faces renumbered and those that then repeat a vertex dropped; a large mesh runs watched
/// (Ctrl-C stops it).
#[pyfunction]
pub fn merge_vertices<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'py, f64>,
    faces: PyReadonlyArray2<'py, i64>,
) -> PyResult<MergedArrays<'py>> {
    let (vertices, faces) = mesh_rows(&vertices, &faces)?;
    let long = vertices.len() > 2 * polhode::mass::MESH_CHUNK;
    let (merged, renumbered) = watched(py, long, |monitor| {
        polhode::mass::merge_vertices(vertices, faces, monitor)
    })?;
    let rows = (merged.len(), renumbered.len());
    let v = Array::from_shape_vec((rows.0, 3), merged.into_flattened())
        .unwrap_or_else(|_| unreachable!("3 numbers per row"));
    let f = Array::from_shape_vec((rows.1, 3), renumbered.into_flattened())
        .unwrap_or_else(|_| unreachable!("3 numbers per row"));
    Ok((v.into_pyarray(py), f.into_pyarray(py)))
}

/// Principal moments (3,), axes (3, 3) and multiplicities (3,) as numpy arrays.
type PrincipalArrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<i64>>,
);

/// Mass, centre of mass and second moments of a rigid body (immutable). Wrapped by
/// `polhode.Body`.
#[pyclass(frozen, module = "polhode._core", name = "MassProperties")]
#[derive(Clone)]
pub struct PyMassProperties(pub MassProperties);

fn wrap(result: polhode::Result<MassProperties>) -> CoreResult<PyMassProperties> {
    Ok(PyMassProperties(result?))
}

#[pymethods]
impl PyMassProperties {
    #[staticmethod]
    fn point_masses(
        py: Python<'_>,
        masses: PyReadonlyArray1<'_, f64>,
        positions: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Self> {
        if positions.shape()[1] != 3 {
            return Err(bad_shape("positions", "(N, 3)", positions.shape()));
        }
        // Borrow the numpy buffers (C-contiguous float64 from the Python layer) as rows.
        let (masses, positions) = match (masses.as_slice(), positions.as_slice()) {
            (Ok(m), Ok(p)) => (m, p.as_chunks::<3>().0),
            _ => {
                return Err(pyo3::exceptions::PyValueError::new_err(
                    "Expected C-contiguous `masses` and `positions`.",
                ))
            }
        };
        let long = masses.len() > 2 * polhode::mass::POINT_CHUNK;
        let body = watched(py, long, |monitor| {
            MassProperties::point_masses_monitored(masses, positions, monitor)
        })?;
        Ok(Self(body))
    }

    /// A solid bounded by a closed triangle mesh (or, with `shell`, a thin surface shell).
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, density=None, mass=None, shell=false, fix_winding=false))]
    fn mesh(
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        density: Option<f64>,
        mass: Option<f64>,
        shell: bool,
        fix_winding: bool,
    ) -> PyResult<Self> {
        let (vertices, faces) = mesh_rows(&vertices, &faces)?;
        // A large mesh runs watched: Ctrl-C stops it at its next chunk of faces.
        let long = faces.len() > 2 * polhode::mass::MESH_CHUNK;
        let body = watched(py, long, |monitor| {
            MassProperties::mesh_monitored(
                vertices,
                faces,
                density,
                mass,
                shell,
                fix_winding,
                monitor,
            )
        })?;
        Ok(Self(body))
    }

    /// The analytic solid `kind` (a row of the core's `SOLIDS`) of `mass`, its parameters by
    /// name: a float for a width of 1, a (3,) float64 array for a width of 3.
    #[staticmethod]
    #[pyo3(signature = (kind, mass, **parameters))]
    fn solid(kind: &str, mass: f64, parameters: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let Some(solid) = SOLIDS.iter().find(|s| s.name == kind) else {
            return Ok(wrap(MassProperties::solid(kind, mass, &[]))?);
        };
        let given = parameters.map_or(0, |p| p.len());
        let mut values = Vec::with_capacity(3 * solid.parameters.len());
        for &(name, width) in solid.parameters {
            let Some(value) = parameters.map(|p| p.get_item(name)).transpose()?.flatten() else {
                return Err(PyTypeError::new_err(format!(
                    "solid(): a {kind} needs `{name}`."
                )));
            };
            if width == 1 {
                values.push(value.extract::<f64>()?);
            } else {
                let array: PyReadonlyArray1<'_, f64> = value.extract()?;
                values.extend_from_slice(vector3(name, &array)?.as_slice());
            }
        }
        if given != solid.parameters.len() {
            let names: Vec<&str> = solid.parameters.iter().map(|&(n, _)| n).collect();
            return Err(PyTypeError::new_err(format!(
                "solid(): a {kind} takes {}; got {given} parameters.",
                if names.is_empty() {
                    "no parameters".into()
                } else {
                    names.join(", ")
                }
            )));
        }
        Ok(wrap(MassProperties::solid(kind, mass, &values))?)
    }

    #[staticmethod]
    fn from_inertia(
        mass: f64,
        inertia: PyReadonlyArray2<'_, f64>,
        center_of_mass: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let inertia = matrix3("inertia", &inertia)?;
        let center_of_mass = vector3("center_of_mass", &center_of_mass)?;
        Ok(wrap(MassProperties::from_inertia(
            mass,
            &inertia,
            &center_of_mass,
        ))?)
    }

    #[getter]
    fn mass(&self) -> f64 {
        self.0.mass()
    }

    #[getter]
    fn center_of_mass<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector_to_py(py, &self.0.center_of_mass())
    }

    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_to_py(py, &self.0.inertia())
    }

    #[getter]
    fn second_moment<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix_to_py(py, &self.0.second_moment())
    }

    #[pyo3(signature = (point, axes=None))]
    fn inertia_about<'py>(
        &self,
        py: Python<'py>,
        point: PyReadonlyArray1<'_, f64>,
        axes: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let point = vector3("point", &point)?;
        let tensor = match axes {
            None => self.0.inertia_about(&point),
            Some(axes) => self.0.inertia_about_in(&point, &matrix3("axes", &axes)?),
        }
        .map_err(CoreError)?;
        Ok(matrix_to_py(py, &tensor))
    }

    /// Returns (moments (3,), axes (3, 3), multiplicity (3,)).
    #[pyo3(signature = (rtol=None))]
    fn principal<'py>(&self, py: Python<'py>, rtol: Option<f64>) -> PyResult<PrincipalArrays<'py>> {
        let rtol = rtol.unwrap_or(polhode::eigen::DEFAULT_RTOL);
        let p = self.0.principal_with(rtol).map_err(CoreError)?;
        let multiplicity = Array::from_iter(p.multiplicity.iter().map(|&k| i64::from(k)));
        Ok((
            vector_to_py(py, &p.moments),
            matrix_to_py(py, &p.axes),
            multiplicity.into_pyarray(py),
        ))
    }

    fn translated(&self, offset: PyReadonlyArray1<'_, f64>) -> PyResult<Self> {
        Ok(wrap(self.0.translated(&vector3("offset", &offset)?))?)
    }

    fn rotated(&self, rotation: PyReadonlyArray2<'_, f64>) -> PyResult<Self> {
        Ok(wrap(self.0.rotated(&matrix3("rotation", &rotation)?))?)
    }

    fn scaled(&self, mass_scale: f64, length_scale: f64) -> CoreResult<Self> {
        wrap(self.0.scaled(mass_scale, length_scale))
    }

    fn combined(&self, other: &Self) -> CoreResult<Self> {
        wrap(self.0.try_add(&other.0))
    }

    fn angular_momentum_body<'py>(
        &self,
        py: Python<'py>,
        omega: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let l = self
            .0
            .angular_momentum_body(&vector3("omega", &omega)?)
            .map_err(CoreError)?;
        Ok(vector_to_py(py, &l))
    }

    fn kinetic_energy(&self, omega: PyReadonlyArray1<'_, f64>) -> PyResult<f64> {
        Ok(self
            .0
            .kinetic_energy(&vector3("omega", &omega)?)
            .map_err(CoreError)?)
    }

    /// The stored numbers, as Python floats: `(mass, center_of_mass, center_of_mass_low,
    /// isotropic, factor)`, the vectors as 3-tuples and the factor as 3 rows (see the core's
    /// `mass::Parts`). What pickling saves: `from_parts` gives the same body bit for bit.
    fn parts(&self) -> StoredParts {
        let p = self.0.parts();
        let v = |x: nalgebra::Vector3<f64>| (x[0], x[1], x[2]);
        let f = &p.factor;
        let row = |i: usize| (f[(i, 0)], f[(i, 1)], f[(i, 2)]);
        (
            p.mass,
            v(p.center_of_mass),
            v(p.center_of_mass_low),
            p.isotropic,
            (row(0), row(1), row(2)),
        )
    }

    /// The body of `parts()`'s numbers, checked by the core (`MassProperties::from_parts`).
    #[staticmethod]
    fn from_parts(
        mass: f64,
        center_of_mass: Triple,
        center_of_mass_low: Triple,
        isotropic: f64,
        factor: (Triple, Triple, Triple),
    ) -> CoreResult<Self> {
        let v = |x: Triple| nalgebra::Vector3::new(x.0, x.1, x.2);
        let (a, b, c) = factor;
        wrap(MassProperties::from_parts(polhode::mass::Parts {
            mass,
            center_of_mass: v(center_of_mass),
            center_of_mass_low: v(center_of_mass_low),
            isotropic,
            factor: nalgebra::Matrix3::new(a.0, a.1, a.2, b.0, b.1, b.2, c.0, c.1, c.2),
        }))
    }

    /// Pickling (and `copy.deepcopy`): `MassProperties.from_parts(*self.parts())`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, StoredParts)> {
        let from_parts = py.get_type::<Self>().getattr("from_parts")?;
        Ok((from_parts, self.parts()))
    }
}

/// Three numbers (a vector, a row).
type Triple = (f64, f64, f64);

/// What `MassProperties.parts()` returns.
type StoredParts = (f64, Triple, Triple, f64, (Triple, Triple, Triple));

/// Principal moments, axes and multiplicities of a tensor (3, 3) or a batch (N, 3, 3), in
/// parallel with the GIL released.
#[pyfunction]
#[pyo3(signature = (inertia, rtol=None, continuous=false))]
#[allow(clippy::type_complexity)]
pub fn principal<'py>(
    py: Python<'py>,
    inertia: PyReadonlyArrayDyn<'py, f64>,
    rtol: Option<f64>,
    continuous: bool,
) -> PyResult<(
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<i64>>,
)> {
    let rtol = rtol.unwrap_or(polhode::eigen::DEFAULT_RTOL);
    let shape = inertia.shape().to_vec();
    let single = shape == [3, 3];
    if !(single || (shape.len() == 3 && shape[1] == 3 && shape[2] == 3)) {
        return Err(bad_shape("inertia", "(3, 3) or (N, 3, 3)", &shape));
    }
    let n = if single { 1 } else { shape[0] };
    let data: Vec<f64>;
    let slice = match inertia.as_slice() {
        Ok(s) => s,
        Err(_) => {
            data = polhode::memory::collect(inertia.as_array().iter().copied(), Purpose::Input)
                .map_err(CoreError)?;
            &data
        }
    };
    let (moments_shape, axes_shape) = if single {
        (vec![3], vec![3, 3])
    } else {
        (vec![n, 3], vec![n, 3, 3])
    };
    // The outputs are numpy's own zeroed arrays, written in place: numpy asks the kernel for
    // huge pages for large arrays (madvise), so a batch of 1e6 tensors takes ~300 page faults
    // where vectors of ours took ~29000 (on the 2-core VM those faults cost as much system time
    // as the solve's own). MemoryError if they do not fit.
    let moments = zeros::<f64, _>(py, moments_shape.clone(), Purpose::PrincipalAxes)?;
    let axes = zeros::<f64, _>(py, axes_shape, Purpose::PrincipalAxes)?;
    let multiplicity = zeros::<i64, _>(py, moments_shape, Purpose::PrincipalAxes)?;
    {
        let mut moments_view = moments.readwrite();
        let mut axes_view = axes.readwrite();
        let mut multiplicity_view = multiplicity.readwrite();
        let contiguous =
            |e: numpy::AsSliceError| pyo3::exceptions::PyRuntimeError::new_err(e.to_string());
        let moments_out = moments_view.as_slice_mut().map_err(contiguous)?;
        let axes_out = axes_view.as_slice_mut().map_err(contiguous)?;
        let multiplicity_out = multiplicity_view.as_slice_mut().map_err(contiguous)?;
        let long = n > 2 * polhode::eigen::BATCH_CHUNK || (continuous && n > 1 << 14);
        watched(py, long, |monitor| {
            polhode::eigen::principal_batch_monitored(
                slice,
                rtol,
                moments_out,
                axes_out,
                multiplicity_out,
                monitor,
            )
            .map_err(|e| {
                if single {
                    e.map_name(|name| name.replacen("inertia[0]", "inertia", 1))
                } else {
                    e
                }
            })?;
            if continuous {
                polhode::series::follow_principal_batch(
                    moments_out,
                    axes_out,
                    multiplicity_out,
                    monitor,
                )?;
            }
            Ok(())
        })?;
    }
    Ok((moments, axes, multiplicity))
}

/// The analytic solids, `{name: ((parameter, width), ...)}` in the core's order: what
/// `polhode.Body`'s constructors and the command line read.
pub fn solids(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let table = PyDict::new(py);
    for solid in SOLIDS {
        table.set_item(
            solid.name,
            PyTuple::new(py, solid.parameters.iter().copied())?,
        )?;
    }
    Ok(table)
}
