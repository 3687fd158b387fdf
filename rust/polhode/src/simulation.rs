//! Trajectories of one body or a batch, reported in each body's own axes: the one path from a
//! body as a user gives it (principal moments, an inertia tensor, mass properties) to the
//! outputs a user reads (angular velocity, orientation, angular momentum, energy).
//!
//! Each body is integrated in its principal axes, where Euler's equations are diagonal: with
//! `V` the principal axes (columns, in body coordinates, a proper rotation),
//! `omega_p = V^T omega_b` and `R_p = R_b V`. A torque, given in body axes, is rotated into the
//! principal axes in one place (`InFrame`), whatever its model. The outputs are turned back
//! into body axes, quaternions kept continuous in time (`q` and `-q` are one rotation).
//!
//! ```
//! use nalgebra::{UnitQuaternion, Vector3};
//! use polhode::dynamics::Method;
//! use polhode::simulation::{simulate, Body, Simulation};
//!
//! // Two bodies at once, by the exact solution, at t = 0 and t = 10.
//! let bodies = [Body::Moments(Vector3::new(1.0, 2.0, 3.0)), Body::Moments(Vector3::new(2.0, 2.0, 5.0))];
//! let omega0 = [Vector3::new(0.1, 1.0, 0.1), Vector3::new(0.3, 0.0, 1.0)];
//! let run = Simulation::new(Method::Exact);
//! let out = simulate(&run, &bodies, &omega0, &[UnitQuaternion::identity()], &[0.0, 10.0], None)?;
//! let energy = out.column("energy").unwrap();
//! // Two bodies x two times; T is conserved.
//! assert!((energy[1] - energy[0]).abs() <= 1e-15 * energy[0]);
//! # Ok::<(), polhode::Error>(())
//! ```

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};
use rayon::prelude::*;

use crate::dynamics::lanes;
use crate::dynamics::{
    exact_range, integrate_body, integrate_gyrostat, BodyContext, Gyrostat, Method, Moments,
    Options, RotorSpec, Segment, State, Stats, Torque, TorqueSpec,
};
use crate::error::{finite, Short};
use crate::exact::FreeRotation;
use crate::mass::{check_rotation, MassProperties};
use crate::{Error, Monitor, Result};

/// A body as [`simulate`] takes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Body {
    /// Principal moments (any order, each positive): the body's axes are its principal axes.
    Moments(Vector3<f64>),
    /// An inertia tensor in the body's axes (about the pivot, for a heavy top).
    Inertia(Matrix3<f64>),
    /// Mass properties: integrated about the centre of mass, or about the pivot of a
    /// [`TorqueSpec::Gravity`], which then takes the mass and centre of mass from here.
    MassProperties(MassProperties),
}

/// The settings of a run, shared by every body.
#[derive(Clone)]
pub struct Simulation {
    /// The method (with [`Method::Exact`], the closed form; torque-free only).
    pub method: Method,
    /// The time of the initial state.
    pub t0: f64,
    /// Whether to report the orientation (and L in space).
    pub with_orientation: bool,
    /// Largest number of steps per body.
    pub max_steps: u64,
    /// External torque, in body axes.
    pub torque: Option<TorqueSpec>,
    /// Run the bodies on the rayon pool (true) or one after another on the calling thread.
    pub parallel: bool,
    /// Internal rotors (reaction wheels, spherical dampers; see [`crate::dynamics::rotors`]),
    /// in each body's own axes, shared by every body; integrated by `rk4` or `dop853`. The
    /// body's inertia includes them, locked.
    pub rotors: Vec<RotorSpec>,
}

impl Simulation {
    /// A torque-free run from `t0 = 0` with the orientation, in parallel.
    #[must_use]
    pub fn new(method: Method) -> Self {
        Self {
            method,
            t0: 0.0,
            with_orientation: true,
            max_steps: Options::default().max_steps,
            torque: None,
            parallel: true,
            rotors: Vec::new(),
        }
    }
}

/// A quantity reported at each output time, in the body's own axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Angular velocity, body axes (3).
    Omega,
    /// Body-to-space orientation, scalar-last quaternion `(x, y, z, w)`, continuous in time (4).
    Quaternion,
    /// Angular momentum in space axes (3): conserved without torque. With rotors, the total
    /// (body and rotors).
    AngularMomentumSpace,
    /// Angular momentum in body axes (3); with rotors, the total.
    AngularMomentumBody,
    /// Rotational kinetic energy (1); with rotors, the total.
    Energy,
    /// Each rotor's angular velocity relative to the body, body axes (rotors x 3; only with
    /// rotors).
    RotorRates,
}

impl Quantity {
    /// Every quantity, in the order of [`Outputs::columns`].
    pub const ALL: [Quantity; 6] = [
        Quantity::Omega,
        Quantity::Quaternion,
        Quantity::AngularMomentumSpace,
        Quantity::AngularMomentumBody,
        Quantity::Energy,
        Quantity::RotorRates,
    ];

    /// The name users read (the Python `Trajectory` attribute).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Omega => "omega",
            Quantity::Quaternion => "quaternion",
            Quantity::AngularMomentumSpace => "angular_momentum_space",
            Quantity::AngularMomentumBody => "angular_momentum_body",
            Quantity::Energy => "energy",
            Quantity::RotorRates => "rotor_rates",
        }
    }

    /// The shape of its numbers at one output time, for a run with `rotors` rotors (empty for
    /// a scalar, which has no trailing axis).
    #[must_use]
    pub fn shape(self, rotors: usize) -> Vec<usize> {
        match self {
            Quantity::Quaternion => vec![4],
            Quantity::Energy => vec![],
            Quantity::RotorRates => vec![rotors, 3],
            _ => vec![3],
        }
    }

    /// Numbers per output time, for a run with `rotors` rotors (1 for a scalar).
    #[must_use]
    pub fn width(self, rotors: usize) -> usize {
        // The product of `shape`, without its allocation: this runs per output and body.
        match self {
            Quantity::Quaternion => 4,
            Quantity::Energy => 1,
            Quantity::RotorRates => 3 * rotors,
            _ => 3,
        }
    }

    /// Whether it needs the orientation (absent without it).
    #[must_use]
    pub fn needs_orientation(self) -> bool {
        matches!(self, Quantity::Quaternion | Quantity::AngularMomentumSpace)
    }

    /// Whether it needs rotors (absent without them).
    #[must_use]
    pub fn needs_rotors(self) -> bool {
        matches!(self, Quantity::RotorRates)
    }
}

/// One body's state at one output time, in its principal axes, with what the quantities need.
struct Sample<'a> {
    body: &'a Prepared,
    omega: &'a Vector3<f64>,
    orientation: Option<&'a UnitQuaternion<f64>>,
    /// The gyrostat and its rotor variables, with rotors.
    rotors: Option<(&'a Gyrostat, &'a [f64])>,
}

impl Sample<'_> {
    /// The angular momentum in principal axes.
    fn momentum(&self) -> Vector3<f64> {
        match self.rotors {
            Some((gyrostat, vars)) => gyrostat.angular_momentum(self.omega, vars),
            None => self.body.moments.moments().component_mul(self.omega),
        }
    }

    /// Every quantity of the sample but the rotors' rates, each computed once: the angular
    /// velocity and momentum in the body's axes, the energy, and with the orientation, the
    /// angular momentum in space and the body's quaternion, its sign continuous with
    /// `previous` (the last quaternion written, updated).
    fn values(&self, previous: &mut Option<Quaternion<f64>>) -> Values {
        let l = self.momentum();
        let (omega, momentum) = match &self.body.frame {
            Some(frame) => (frame.matrix * self.omega, frame.matrix * l),
            None => (*self.omega, l),
        };
        let energy = match self.rotors {
            Some((gyrostat, vars)) => gyrostat.energy(self.omega, vars),
            None => 0.5 * self.omega.dot(&l),
        };
        let oriented = self.orientation.map(|q| {
            // R_b = R_p V^T.
            let mut body = match &self.body.frame {
                Some(frame) => (q * frame.rotation.inverse()).into_inner(),
                None => q.into_inner(),
            };
            // One sign per trajectory: continuous in time.
            if previous.is_some_and(|p| p.coords.dot(&body.coords) < 0.0) {
                body = -body;
            }
            *previous = Some(body);
            (q * l, [body.i, body.j, body.k, body.w])
        });
        Values {
            omega,
            momentum,
            energy,
            oriented,
        }
    }

    /// The rotors' rates relative to the body, in the body's axes, into `out` (3 per rotor).
    fn write_rotor_rates(&self, out: &mut [f64]) {
        if let Some((gyrostat, vars)) = self.rotors {
            for (k, rate) in gyrostat.rotor_rates(self.omega, vars).iter().enumerate() {
                let rate = match &self.body.frame {
                    Some(frame) => frame.matrix * rate,
                    None => *rate,
                };
                out[3 * k..3 * k + 3].copy_from_slice(rate.as_slice());
            }
        }
    }
}

/// A sample's quantities (see [`Sample::values`]).
struct Values {
    omega: Vector3<f64>,
    momentum: Vector3<f64>,
    energy: f64,
    /// With the orientation: the angular momentum in space and the quaternion (x, y, z, w).
    oriented: Option<(Vector3<f64>, [f64; 4])>,
}

impl Values {
    /// 0 if every number is finite, NaN if not (`x * 0` is 0 for a finite `x` only).
    fn probe(&self) -> f64 {
        let mut probe = (self.omega + self.momentum).sum() * 0.0 + self.energy * 0.0;
        if let Some((space, q)) = &self.oriented {
            probe += space.sum() * 0.0 + (q[0] + q[1] + q[2] + q[3]) * 0.0;
        }
        probe
    }
}

/// One body's rows of every column, written output time by output time.
struct Rows<'a> {
    /// Each quantity present (the first `count`), the start of the body's rows in its column
    /// and its width (numbers per output time), found once per body.
    targets: [(Quantity, Column, usize); Quantity::ALL.len()],
    count: usize,
    /// The output times.
    t: &'a [f64],
    /// The last quaternion written (one sign per trajectory).
    previous: Option<Quaternion<f64>>,
}

impl<'a> Rows<'a> {
    /// Body `i`'s rows of `columns` (each with its numbers per body in `shared`), for `rotors`
    /// rotors and the output times `t`.
    ///
    /// # Safety
    /// No other `Rows` of the same body `i` is alive (the bodies' ranges are disjoint), and
    /// each column holds the rows of body `i`.
    unsafe fn new(
        i: usize,
        columns: &[Quantity],
        shared: &[(Column, usize)],
        rotors: usize,
        t: &'a [f64],
    ) -> Self {
        let mut targets = [(Quantity::Omega, Column(std::ptr::null_mut()), 0); Quantity::ALL.len()];
        for (target, (&q, &(column, len))) in targets.iter_mut().zip(columns.iter().zip(shared)) {
            // SAFETY: body i's range, by the caller's contract.
            let start = unsafe { column.rows(i, len) }.as_mut_ptr();
            *target = (q, Column(start), q.width(rotors));
        }
        Self {
            targets,
            count: columns.len().min(Quantity::ALL.len()),
            t,
            previous: None,
        }
    }

    /// Writes every quantity of `sample`, the state at output time `j`.
    ///
    /// # Safety
    /// No other `Rows` of the same body `i` is alive (the bodies' ranges are disjoint).
    unsafe fn write(&mut self, j: usize, sample: &Sample) -> Result<()> {
        let values = sample.values(&mut self.previous);
        // Every number is written, then checked finite at once (`x * 0` is 0 for a finite
        // `x`, NaN otherwise): the columns are looked through only for an error's name.
        let mut probe = values.probe();
        for &(quantity, start, w) in &self.targets[..self.count] {
            // SAFETY: output time j of body i's rows, by the caller's contract.
            let at = unsafe { start.0.add(j * w) };
            // SAFETY: the row has the quantity's width; each fixed-size write fills it.
            unsafe {
                match (quantity, &values.oriented) {
                    (Quantity::Omega, _) => at.cast::<[f64; 3]>().write(values.omega.into()),
                    (Quantity::AngularMomentumBody, _) => {
                        at.cast::<[f64; 3]>().write(values.momentum.into());
                    }
                    (Quantity::Energy, _) => at.write(values.energy),
                    (Quantity::AngularMomentumSpace, Some((space, _))) => {
                        at.cast::<[f64; 3]>().write((*space).into());
                    }
                    (Quantity::Quaternion, Some((_, q))) => at.cast::<[f64; 4]>().write(*q),
                    (Quantity::AngularMomentumSpace | Quantity::Quaternion, None) => {}
                    (Quantity::RotorRates, _) => {
                        let out = start.rows(j, w);
                        sample.write_rotor_rates(out);
                        for x in out.iter() {
                            probe += x * 0.0;
                        }
                    }
                }
            }
        }
        if probe == 0.0 {
            return Ok(());
        }
        for &(quantity, start, w) in &self.targets[..self.count] {
            // SAFETY: as above.
            let out = unsafe { start.rows(j, w) };
            // omega is finite (the integration checks it), but I omega and T can
            // overflow beside it (a torque that drives the motion beyond doubles).
            if let Some(&value) = out.iter().find(|x| !x.is_finite()) {
                return Err(Error::BlewUp {
                    name: "t".into(),
                    what: format!("`{}`", quantity.name()),
                    hint: "the motion leaves double precision before the times asked for.".into(),
                    t: self.t[j],
                    value,
                });
            }
        }
        Ok(())
    }
}

/// The outputs of [`simulate`]: for each [`Quantity`] present, N x M x width numbers,
/// body-major, then the principal moments (N x 3) and the cost per body.
#[derive(Clone, Debug, PartialEq)]
pub struct Outputs {
    /// Bodies.
    pub n: usize,
    /// Output times.
    pub m: usize,
    /// Rotors (the widths of [`Quantity::RotorRates`]).
    pub rotors: usize,
    /// The quantities present (those needing the orientation only with it) and their numbers.
    pub columns: Vec<(Quantity, Vec<f64>)>,
    /// The principal moments each body was integrated with (about the pivot for a heavy top),
    /// N x 3, ascending for a body given by a tensor or mass properties.
    pub moments: Vec<f64>,
    /// What each body cost.
    pub stats: Vec<Stats>,
}

impl Outputs {
    /// The numbers of the quantity named `name`, if present.
    #[must_use]
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(q, _)| q.name() == name)
            .map(|(_, data)| data.as_slice())
    }
}

/// The principal axes of a body given in other axes: the columns of `matrix` (a rotation), and
/// the same rotation as a quaternion.
#[derive(Clone, Copy, Debug)]
struct Frame {
    matrix: Matrix3<f64>,
    rotation: UnitQuaternion<f64>,
}

impl Frame {
    /// `None` for the identity (a body already in principal axes).
    fn of(axes: &Matrix3<f64>) -> Option<Self> {
        (*axes != Matrix3::identity()).then(|| Self {
            matrix: *axes,
            rotation: UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                *axes,
            )),
        })
    }
}

/// A torque given in body axes, seen from the principal axes it is integrated in:
/// `tau_p(t, w_p, R_p) = V^T tau_b(t, V w_p, R_p V^T)`.
struct InFrame<T> {
    inner: T,
    frame: Frame,
}

impl<T: Torque> Torque for InFrame<T> {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        let (w, q) = self.to_body(omega, orientation);
        self.frame.matrix.tr_mul(&self.inner.torque_body(t, &w, &q))
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let (w, q) = self.to_body(omega, orientation);
        Ok(self
            .frame
            .matrix
            .tr_mul(&self.inner.try_torque_body(t, &w, &q)?))
    }
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let (w, q) = self.to_body(omega, orientation);
        let tau = self.inner.try_torque_body_in(segment, t, &w, &q)?;
        Ok(self.frame.matrix.tr_mul(&tau))
    }
    fn depends_on_orientation(&self) -> bool {
        self.inner.depends_on_orientation()
    }
    fn depends_on_omega(&self) -> bool {
        self.inner.depends_on_omega()
    }
    fn discontinuities(&self) -> Vec<f64> {
        self.inner.discontinuities()
    }
}

impl<T> InFrame<T> {
    fn to_body(
        &self,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> (Vector3<f64>, UnitQuaternion<f64>) {
        (
            self.frame.matrix * omega,
            orientation * self.frame.rotation.inverse(),
        )
    }
}

/// A body ready to integrate: validated principal moments, its frame, its torque.
struct Prepared {
    moments: Moments,
    frame: Option<Frame>,
    torque: Option<Box<dyn Torque + Send>>,
}

const MOMENTS_REASON: &str = "expected positive principal moments (Euler's equations need I^-1; \
                              a rod or a point mass has a zero moment)";

fn prepare(body: &Body, torque: Option<&TorqueSpec>) -> Result<Prepared> {
    let pivot = torque.and_then(TorqueSpec::pivot);
    let (moments, axes, context) = match body {
        Body::Moments(m) => {
            for k in 0..3 {
                if !(m[k].is_finite() && m[k] > 0.0) {
                    return Err(Error::InvalidArgument {
                        name: "body".into(),
                        reason: format!("{MOMENTS_REASON}, got {:?}.", [m[0], m[1], m[2]]),
                    });
                }
            }
            let context = BodyContext {
                inertia: Matrix3::from_diagonal(m),
                mass_about_pivot: None,
            };
            (*m, Matrix3::identity(), context)
        }
        Body::Inertia(tensor) => {
            let p =
                crate::eigen::symmetric_eigen3_with(tensor, crate::eigen::DEFAULT_RTOL, "body")?;
            let context = BodyContext {
                inertia: *tensor,
                mass_about_pivot: None,
            };
            (p.moments, p.axes, context)
        }
        Body::MassProperties(mp) => {
            let (p, context) = match pivot {
                Some(pivot) => {
                    let inertia = mp.inertia_about(&pivot);
                    if !inertia.iter().all(|x| x.is_finite()) {
                        // The body's own inertia is finite: the pivot is too far from it.
                        return Err(Error::InvalidArgument {
                            name: "pivot".into(),
                            reason: format!(
                                "the body's inertia about the pivot ({}, {}, {}) overflows \
                                 double precision (its mass times the squared distance).",
                                Short(pivot.x),
                                Short(pivot.y),
                                Short(pivot.z)
                            ),
                        });
                    }
                    let p = crate::eigen::symmetric_eigen3_with(
                        &inertia,
                        crate::eigen::DEFAULT_RTOL,
                        "body",
                    )?;
                    let context = BodyContext {
                        inertia,
                        mass_about_pivot: Some((mp.mass(), mp.center_of_mass() - pivot)),
                    };
                    (p, context)
                }
                None => (
                    mp.principal(),
                    BodyContext {
                        inertia: mp.inertia(),
                        mass_about_pivot: None,
                    },
                ),
            };
            (p.moments, p.axes, context)
        }
    };
    if !moments.iter().all(|&m| m.is_finite() && m > 0.0) {
        return Err(Error::InvalidArgument {
            name: "body".into(),
            reason: format!(
                "{MOMENTS_REASON}, got {:?}.",
                [moments[0], moments[1], moments[2]]
            ),
        });
    }
    let moments = Moments::new(moments).map_err(|e| e.map_name(|_| "body".into()))?;
    let frame = Frame::of(&axes);
    let torque = match torque {
        None => None,
        Some(spec) => {
            let built = spec.build(&context)?;
            Some(match frame {
                Some(frame) => Box::new(InFrame {
                    inner: built,
                    frame,
                }) as Box<dyn Torque + Send>,
                None => built,
            })
        }
    };
    Ok(Prepared {
        moments,
        frame,
        torque,
    })
}

/// The initial state of one body in its principal axes, checked.
fn initial_state(
    body: &Prepared,
    omega0: &Vector3<f64>,
    orientation0: &UnitQuaternion<f64>,
) -> Result<State> {
    for k in 0..3 {
        if !omega0[k].is_finite() {
            finite("omega0", omega0[k])?;
        }
    }
    let energy = body.moments.kinetic_energy(&match &body.frame {
        Some(frame) => frame.matrix.tr_mul(omega0),
        None => *omega0,
    });
    if !energy.is_finite() {
        return Err(Error::InvalidArgument {
            name: "omega0".into(),
            reason: "the kinetic energy of `omega0` with these moments overflows double precision."
                .into(),
        });
    }
    Ok(match &body.frame {
        // omega_p = V^T omega_b; R_p = R_b V.
        Some(frame) => State::new(frame.matrix.tr_mul(omega0), orientation0 * frame.rotation),
        None => State::new(*omega0, *orientation0),
    })
}

/// A quaternion `(x, y, z, w)` as an orientation: finite and non-zero, normalised.
pub fn orientation_from_quaternion(name: &str, q: [f64; 4]) -> Result<UnitQuaternion<f64>> {
    for (k, v) in q.iter().enumerate() {
        if !v.is_finite() {
            finite(&format!("{name}[{k}]"), *v)?;
        }
    }
    let mut q = Quaternion::new(q[3], q[0], q[1], q[2]);
    if !(q.norm() > 0.0 && q.norm().is_finite()) {
        // Components whose squares over- or underflow (1e300, 1e-300): brought near 1 by a
        // power of two first, the direction they give unchanged.
        let largest = q.coords.amax();
        if largest == 0.0 {
            return Err(Error::InvalidArgument {
                name: name.into(),
                reason: "expected a non-zero quaternion (x, y, z, w), got 0.".into(),
            });
        }
        let e = crate::eigen::exponent(largest);
        q = Quaternion::from(q.coords.map(|x| crate::eigen::ldexp(x, -e)));
    }
    Ok(UnitQuaternion::from_quaternion(q))
}

/// A rotation matrix as an orientation: a proper rotation to `1e-9`.
pub fn orientation_from_matrix(name: &str, r: &Matrix3<f64>) -> Result<UnitQuaternion<f64>> {
    check_rotation(name, r)?;
    Ok(UnitQuaternion::from_rotation_matrix(
        &Rotation3::from_matrix_unchecked(*r),
    ))
}

/// Outputs written between two looks at the monitor (a few hundred microseconds).
const OUTPUT_LOOK_EVERY: usize = 4096;

/// `len` zeros, or [`Error::OutOfMemory`] (the whole output being `bytes`) if the allocation
/// fails, rather than an abort.
///
/// Allocated zeroed (`calloc`): a large block comes as fresh zero pages from the system, not
/// written here, so an output of gigabytes costs nothing before the run (writing the zeros
/// took seconds that Ctrl-C could not interrupt) and its pages are touched once, by the run.
fn zeros(len: usize, bytes: f64) -> Result<Vec<f64>> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f64>(len).map_err(|_| Error::OutOfMemory { bytes })?;
    // SAFETY: `layout` has a non-zero size; all-zero bits are the f64 0.0.
    let data = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if data.is_null() {
        return Err(Error::OutOfMemory { bytes });
    }
    // SAFETY: allocated by the global allocator with the layout of `len` f64s, all initialised.
    Ok(unsafe { Vec::from_raw_parts(data, len, len) })
}

/// A slice of an output column handed to one body; the bodies' ranges are disjoint.
#[derive(Clone, Copy)]
struct Column(*mut f64);
// SAFETY: each body writes only its own range of a column (see `Column::rows`).
unsafe impl Send for Column {}
unsafe impl Sync for Column {}

impl Column {
    /// Body `i`'s rows, `len` numbers from `i * len`.
    ///
    /// # Safety
    /// The column holds at least `(i + 1) * len` numbers and no two live slices share a body.
    #[allow(clippy::mut_from_ref)]
    unsafe fn rows<'a>(self, i: usize, len: usize) -> &'a mut [f64] {
        // SAFETY: in bounds and disjoint, by the caller's contract.
        unsafe { std::slice::from_raw_parts_mut(self.0.add(i * len), len) }
    }
}

/// Output times of one body evaluated together by the exact solution: the unit of its work
/// on the rayon pool (about a millisecond).
const EXACT_CHUNK: usize = 4096;

/// Whether [`simulate`] (with [`Simulation::parallel`]) spreads the output times of each body
/// over the rayon pool: for the exact solution at more than a few thousand output times
/// (each output depends on its time alone, so the numbers are the same bit for bit).
#[must_use]
pub fn spreads_times(method: &Method, m: usize) -> bool {
    matches!(method, Method::Exact) && m > EXACT_CHUNK
}

/// One body's rows of the columns of a torque-free run by the exact solution (no rotors):
/// each a pointer to the body's first number.
struct ExactColumns {
    omega: Column,
    quaternion: Option<Column>,
    momentum_space: Option<Column>,
    momentum_body: Column,
    energy: Column,
}

impl ExactColumns {
    /// Body `i`'s rows of `columns` (as [`simulate`] lays them out).
    fn new(i: usize, columns: &[Quantity], shared: &[(Column, usize)]) -> Self {
        let find = |quantity: Quantity| {
            columns
                .iter()
                .zip(shared)
                .find(|(q, _)| **q == quantity)
                // SAFETY: body i's rows start at i * len, inside the column.
                .map(|(_, &(column, len))| Column(unsafe { column.0.add(i * len) }))
        };
        let required = |quantity: Quantity| {
            find(quantity).unwrap_or_else(|| unreachable!("{} is always reported", quantity.name()))
        };
        Self {
            omega: required(Quantity::Omega),
            quaternion: find(Quantity::Quaternion),
            momentum_space: find(Quantity::AngularMomentumSpace),
            momentum_body: required(Quantity::AngularMomentumBody),
            energy: required(Quantity::Energy),
        }
    }
}

impl Column {
    /// `count` numbers from `start` (a body's pointer, see [`ExactColumns`]).
    ///
    /// # Safety
    /// In bounds of the body's rows, and no two live slices overlap.
    #[allow(clippy::mut_from_ref)]
    unsafe fn span<'a>(self, start: usize, count: usize) -> &'a mut [f64] {
        // SAFETY: by the caller's contract.
        unsafe { std::slice::from_raw_parts_mut(self.0.add(start), count) }
    }
}

/// The error of an output `quantity` that is not finite at `t` (as [`Rows::write`] gives it).
#[cold]
fn not_finite(quantity: Quantity, t: f64, value: f64) -> Error {
    Error::BlewUp {
        name: "t".into(),
        what: format!("`{}`", quantity.name()),
        hint: "the motion leaves double precision before the times asked for.".into(),
        t,
        value,
    }
}

/// A torque-free body by the exact solution: its outputs at the times `t` written straight
/// into its rows of the columns, in chunks of [`EXACT_CHUNK`] times (on the rayon pool if
/// `parallel`), each number as [`Sample::write`] forms it. The quaternions are made
/// continuous in time afterwards, in one pass in order (looking at the monitor as the writing
/// of outputs does): the same signs as written one time after another. The numbers do not depend on the chunks nor on the threads. The error is
/// that of the first time whose evaluation fails (a cancelled monitor, a time beyond the
/// solution's reach), else of the first output that is not finite, as when the whole
/// trajectory is evaluated before it is written.
fn exact_body(
    body: &Prepared,
    state: &State,
    t: &[f64],
    options: &Options,
    out: &ExactColumns,
    parallel: bool,
) -> Result<Stats> {
    let state0 = crate::dynamics::start(&Method::Exact, state, t, options)?;
    let moments = *body.moments.moments();
    let free = FreeRotation::new(moments, state0.omega, state0.orientation)?;
    let frame = body.frame.map(|f| (f.matrix, f.rotation.inverse()));
    let orientation = options.with_orientation;
    // One chunk: the first error of an evaluation, or else of an output.
    let chunk = |start: usize| -> (Option<Error>, Option<Error>) {
        let count = EXACT_CHUNK.min(t.len() - start);
        // SAFETY: this chunk's rows of the body's columns (chunks are disjoint).
        let (omega, momentum_body, energy) = unsafe {
            (
                out.omega.span(3 * start, 3 * count),
                out.momentum_body.span(3 * start, 3 * count),
                out.energy.span(start, count),
            )
        };
        let (quaternion, momentum_space) = match (out.quaternion, out.momentum_space) {
            // SAFETY: as above.
            (Some(q), Some(l)) if orientation => unsafe {
                (q.span(4 * start, 4 * count), l.span(3 * start, 3 * count))
            },
            _ => (&mut [][..], &mut [][..]),
        };
        let mut failed: Option<Error> = None;
        let evaluated = exact_range(&free, t, start..start + count, options, |j, w, q| {
            if failed.is_some() {
                return Ok(());
            }
            let k = j - start;
            // As `Sample::write`: L = I omega and T in principal axes, then into body axes.
            let l = moments.component_mul(w);
            let (wb, lb) = match &frame {
                Some((matrix, _)) => (matrix * w, matrix * l),
                None => (*w, l),
            };
            omega[3 * k..3 * k + 3].copy_from_slice(wb.as_slice());
            momentum_body[3 * k..3 * k + 3].copy_from_slice(lb.as_slice());
            energy[k] = 0.5 * w.dot(&l);
            if let Some(q) = q {
                // R_b = R_p V^T; the sign is settled afterwards.
                let qb = match &frame {
                    Some((_, inverse)) => (q * inverse).into_inner(),
                    None => q.into_inner(),
                };
                quaternion[4 * k..4 * k + 4].copy_from_slice(&[qb.i, qb.j, qb.k, qb.w]);
                momentum_space[3 * k..3 * k + 3].copy_from_slice((q * l).as_slice());
            }
            // All finite (the rule): one sum, finite unless a term is not (or the sum
            // overflows); the first culprit is looked for only then.
            let mut sum = energy[k];
            for x in [&omega, &momentum_body] {
                sum += x[3 * k] + x[3 * k + 1] + x[3 * k + 2];
            }
            if let (Some(q), Some(l)) = (
                quaternion.get(4 * k..4 * k + 4),
                momentum_space.get(3 * k..3 * k + 3),
            ) {
                sum += q[0] + q[1] + q[2] + q[3] + l[0] + l[1] + l[2];
            }
            if sum.is_finite() {
                return Ok(());
            }
            let rows: [(Quantity, &[f64]); 5] = [
                (Quantity::Omega, &omega[3 * k..3 * k + 3]),
                (
                    Quantity::Quaternion,
                    quaternion.get(4 * k..4 * k + 4).unwrap_or(&[]),
                ),
                (
                    Quantity::AngularMomentumSpace,
                    momentum_space.get(3 * k..3 * k + 3).unwrap_or(&[]),
                ),
                (
                    Quantity::AngularMomentumBody,
                    &momentum_body[3 * k..3 * k + 3],
                ),
                (Quantity::Energy, &energy[k..=k]),
            ];
            for (quantity, values) in rows {
                if let Some(&value) = values.iter().find(|x| !x.is_finite()) {
                    failed = Some(not_finite(quantity, t[j], value));
                    return Ok(());
                }
            }
            Ok(())
        });
        (evaluated.err(), failed)
    };
    let starts: Vec<usize> = (0..t.len()).step_by(EXACT_CHUNK).collect();
    let results: Vec<(Option<Error>, Option<Error>)> = if parallel && starts.len() > 1 {
        starts.par_iter().map(|&s| chunk(s)).collect()
    } else {
        starts.iter().map(|&s| chunk(s)).collect()
    };
    let mut output_error = None;
    for (evaluation, output) in results {
        if let Some(error) = evaluation {
            return Err(error);
        }
        output_error = output_error.or(output);
    }
    if let Some(error) = output_error {
        return Err(error);
    }
    // The run is done; its outputs are settled as written ones are, looking at the monitor.
    if let Some(monitor) = options.monitor {
        monitor.add_finished();
    }
    if let Some(q) = out.quaternion.filter(|_| orientation) {
        // One sign per trajectory: continuous in time (as `Sample::write`, in order).
        // SAFETY: the body's quaternion rows, no chunk alive.
        let rows = unsafe { q.span(0, 4 * t.len()) };
        let mut previous: Option<Quaternion<f64>> = None;
        for (j, row) in rows.chunks_exact_mut(4).enumerate() {
            if j % OUTPUT_LOOK_EVERY == OUTPUT_LOOK_EVERY - 1 {
                if let Some(monitor) = options.monitor {
                    monitor.look()?;
                }
            }
            let mut q = Quaternion::new(row[3], row[0], row[1], row[2]);
            if previous.is_some_and(|p| p.coords.dot(&q.coords) < 0.0) {
                q = -q;
                row.copy_from_slice(&[q.i, q.j, q.k, q.w]);
            }
            previous = Some(q);
        }
    }
    Ok(Stats {
        steps: 0,
        rejected_steps: 0,
        rhs_evaluations: t.len() as u64,
    })
}

/// A block of bodies integrated together: their indices, ascending, and how many there are.
type Block = ([usize; lanes::LANES], usize);

/// The blocks of at most [`lanes::LANES`] bodies integrated together, in the order of their
/// indices: consecutive bodies, except for the splitting, whose bodies are grouped by their
/// axis order (`axes(i)`; `None` for a body that fails before its run), which a block shares.
fn lane_blocks(
    n: usize,
    method: &Method,
    parallel: bool,
    axes: impl Fn(usize) -> Option<[usize; 3]> + Sync,
) -> Vec<Block> {
    let chunks = |indices: &mut dyn Iterator<Item = usize>, blocks: &mut Vec<Block>| {
        let mut block: Block = ([0; lanes::LANES], 0);
        for i in indices {
            block.0[block.1] = i;
            block.1 += 1;
            if block.1 == lanes::LANES {
                blocks.push(block);
                block.1 = 0;
            }
        }
        if block.1 > 0 {
            blocks.push(block);
        }
    };
    let mut blocks = Vec::with_capacity(n.div_ceil(lanes::LANES));
    if !matches!(method, Method::Splitting { .. }) {
        chunks(&mut (0..n), &mut blocks);
        return blocks;
    }
    let keys: Vec<Option<[usize; 3]>> = if parallel {
        (0..n).into_par_iter().map(&axes).collect()
    } else {
        (0..n).map(axes).collect()
    };
    let mut groups: Vec<(Option<[usize; 3]>, Vec<usize>)> = Vec::new();
    for (i, key) in keys.into_iter().enumerate() {
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, members)) => members.push(i),
            None => groups.push((key, vec![i])),
        }
    }
    for (_, members) in groups {
        chunks(&mut members.into_iter(), &mut blocks);
    }
    blocks
}

/// The cost of each body, written by the body's block alone.
#[derive(Clone, Copy)]
struct StatsColumn(*mut Stats);
// SAFETY: each body's entry is written by one block (see `StatsColumn::set`).
unsafe impl Send for StatsColumn {}
unsafe impl Sync for StatsColumn {}

impl StatsColumn {
    /// # Safety
    /// `i` is in bounds and no other thread writes entry `i`.
    unsafe fn set(self, i: usize, stats: Stats) {
        // SAFETY: in bounds and unshared, by the caller's contract.
        unsafe { *self.0.add(i) = stats };
    }
}

/// Integrates N bodies from their initial angular velocities (body axes) and orientations to
/// the output times `t` (finite, non-decreasing, `>= run.t0`), each in its principal axes,
/// and reports every [`Quantity`] in its own axes.
///
/// `bodies` and `orientation0` hold one entry shared by all or one per body (`omega0` sets N).
/// Each body is integrated on its own, so a body's numbers are the same bit for bit alone or
/// in a batch of any size, whatever the number of threads. On failure, the error of the first
/// failing body by index, wrapped in [`Error::Body`] when N > 1. A cancelled `monitor` stops
/// the run with [`Error::Interrupted`].
pub fn simulate(
    run: &Simulation,
    bodies: &[Body],
    omega0: &[Vector3<f64>],
    orientation0: &[UnitQuaternion<f64>],
    t: &[f64],
    monitor: Option<&Monitor>,
) -> Result<Outputs> {
    let n = omega0.len();
    for (name, len) in [("body", bodies.len()), ("orientation0", orientation0.len())] {
        if len != 1 && len != n {
            return Err(Error::Shape {
                name: name.into(),
                expected: format!("one, or one per body ({n})"),
                got: len.to_string(),
            });
        }
    }
    if t.is_empty() {
        return Err(Error::Shape {
            name: "t".into(),
            expected: "(M,) with M >= 1".into(),
            got: "(0,)".into(),
        });
    }
    // The settings shared by every body, checked once here (and so even for N = 0).
    crate::dynamics::check_times(t, run.t0)?;
    crate::dynamics::check_method(&run.method, &Options::default())?;
    if run.max_steps == 0 {
        return Err(Error::NonPositive {
            name: "max_steps".into(),
            value: 0.0,
        });
    }
    if let (Method::Exact, Some(_)) = (&run.method, &run.torque) {
        return Err(Error::InvalidArgument {
            name: "torque".into(),
            reason: "the exact solution is torque-free; use dop853 or another integrator.".into(),
        });
    }
    if let Some(torque) = &run.torque {
        torque.check()?;
    }
    let rotors = run.rotors.len();
    if rotors > 0 {
        crate::dynamics::check_rotor_method(&run.method)?;
        // The rotors' own parameters, once for all bodies (the body is checked with each).
        for (k, rotor) in run.rotors.iter().enumerate() {
            rotor
                .check()
                .map_err(|e| e.map_name(|name| format!("rotors[{k}].{name}")))?;
        }
    }
    let m = t.len();
    let columns: Vec<Quantity> = Quantity::ALL
        .into_iter()
        .filter(|q| run.with_orientation || !q.needs_orientation())
        .filter(|q| rotors > 0 || !q.needs_rotors())
        .collect();
    let per_time: usize = columns.iter().map(|q| q.width(rotors)).sum();
    let bytes = (n as f64) * (m as f64) * (per_time as f64) * 8.0;
    let mut data: Vec<Vec<f64>> = Vec::with_capacity(columns.len());
    for quantity in &columns {
        data.push(zeros(n * m * quantity.width(rotors), bytes)?);
    }
    let mut moments = zeros(3 * n, bytes)?;
    let shared: Vec<(Column, usize)> = data
        .iter_mut()
        .zip(&columns)
        .map(|(d, q)| (Column(d.as_mut_ptr()), m * q.width(rotors)))
        .collect();
    let moments_column = Column(moments.as_mut_ptr());
    let one = |i: usize| -> Result<Stats> {
        let at = |len: usize| if len == 1 { 0 } else { i };
        let body = prepare(&bodies[at(bodies.len())], run.torque.as_ref())?;
        let state = initial_state(&body, &omega0[i], &orientation0[at(orientation0.len())])?;
        let options = Options {
            t0: run.t0,
            with_orientation: run.with_orientation,
            torque: body.torque.as_deref().map(|t| t as &dyn Torque),
            max_steps: run.max_steps,
            monitor,
        };
        // SAFETY: body i's ranges; every i is visited once.
        let mut rows = unsafe { Rows::new(i, &columns, &shared, rotors, t) };
        // SAFETY: body i's ranges; every i is visited once.
        unsafe { moments_column.rows(i, 3) }.copy_from_slice(body.moments.moments().as_slice());
        let mut write = |j: usize, sample: Sample| -> Result<()> {
            // Writing millions of outputs takes a while: looks at the monitor as a run does.
            if j % OUTPUT_LOOK_EVERY == OUTPUT_LOOK_EVERY - 1 {
                if let Some(monitor) = monitor {
                    monitor.look()?;
                }
            }
            // SAFETY: body i's rows, written by this call alone.
            unsafe { rows.write(j, &sample) }
        };
        if rotors == 0 && matches!(run.method, Method::Exact) {
            let columns = ExactColumns::new(i, &columns, &shared);
            return exact_body(&body, &state, t, &options, &columns, run.parallel);
        }
        if rotors > 0 {
            let frame = body.frame.map_or_else(Matrix3::identity, |f| f.matrix);
            let gyrostat = Gyrostat::new(body.moments.moments(), &frame, &run.rotors)?;
            let trajectory = integrate_gyrostat(&run.method, &gyrostat, &state, t, &options)?;
            let k = gyrostat.variables();
            for (j, omega) in trajectory.omega.iter().enumerate() {
                let sample = Sample {
                    body: &body,
                    omega,
                    orientation: Some(&trajectory.orientation[j]),
                    rotors: Some((&gyrostat, &trajectory.variables[j * k..(j + 1) * k])),
                };
                write(j, sample)?;
            }
            return Ok(trajectory.stats);
        }
        let trajectory = integrate_body(&run.method, &body.moments, &state, t, &options)?;
        for (j, omega) in trajectory.omega.iter().enumerate() {
            let sample = Sample {
                body: &body,
                omega,
                orientation: trajectory.orientation.as_ref().map(|o| &o[j]),
                rotors: None,
            };
            write(j, sample)?;
        }
        Ok(trajectory.stats)
    };
    let lane_options = Options {
        t0: run.t0,
        with_orientation: run.with_orientation,
        torque: None,
        max_steps: run.max_steps,
        monitor,
    };
    let lane_path =
        n > 1 && rotors == 0 && run.torque.is_none() && lanes::applies(&run.method, &lane_options);
    let stats = if lane_path {
        // Torque-free fixed-step runs: blocks of bodies integrated in SIMD lanes, each body
        // with the numbers it has alone. The settings shared by the bodies were checked above:
        // each body's own checks remain, in the order of a run alone.
        let prepared = |i: usize| -> Result<(Prepared, State)> {
            let at = |len: usize| if len == 1 { 0 } else { i };
            let body = prepare(&bodies[at(bodies.len())], None)?;
            let state = initial_state(&body, &omega0[i], &orientation0[at(orientation0.len())])?;
            if let Some(monitor) = monitor {
                monitor.check()?;
            }
            Ok((body, crate::dynamics::start_state(&state)?))
        };
        let mut stats = vec![Stats::default(); n];
        let stats_column = StatsColumn(stats.as_mut_ptr());
        // Runs a block; returns the error of its first failing body by index, if any.
        let block = |&(members, count): &Block| -> Option<(usize, Error)> {
            let mut first: Option<(usize, Error)> = None;
            let mut fail = |i: usize, error: Error| {
                if first.as_ref().is_none_or(|(f, _)| i < *f) {
                    first = Some((i, error));
                }
            };
            // The bodies that start, in lanes 0..k.
            let mut ready: [Option<(usize, Prepared, State)>; lanes::LANES] = Default::default();
            let mut k = 0;
            for &i in &members[..count] {
                match prepared(i) {
                    // An angular velocity outside [2^-256, 2^256]: integrated in units of a
                    // power of two by the run alone (`driver::run_free`), the same numbers.
                    Ok((_, state))
                        if !matches!(run.method, Method::Splitting { .. })
                            && crate::dynamics::omega_scale(&state.omega).is_some() =>
                    {
                        match one(i) {
                            // SAFETY: body i's entry, written by its block alone.
                            Ok(stats) => unsafe { stats_column.set(i, stats) },
                            Err(error) => fail(i, error),
                        }
                    }
                    Ok((body, state)) => {
                        ready[k] = Some((i, body, state));
                        k += 1;
                    }
                    Err(error) => fail(i, error),
                }
            }
            if k == 0 {
                return first;
            }
            let lane = |l: usize| ready[l.min(k - 1)].as_ref().expect("a body in lanes 0..k");
            let mut rows: [Option<Rows>; lanes::LANES] = std::array::from_fn(|l| {
                (l < k).then(|| {
                    let (i, body, _) = lane(l);
                    // SAFETY: body i's ranges; every i is in one block, once.
                    unsafe { moments_column.rows(*i, 3) }
                        .copy_from_slice(body.moments.moments().as_slice());
                    // SAFETY: as above.
                    unsafe { Rows::new(*i, &columns, &shared, rotors, t) }
                })
            });
            // A body's first output that overflows: its error, unless its run fails.
            let mut pending: [Option<Error>; lanes::LANES] = Default::default();
            let moments: [Moments; lanes::LANES] = std::array::from_fn(|l| lane(l).1.moments);
            let states: [State; lanes::LANES] = std::array::from_fn(|l| lane(l).2);
            let output = |j: usize, outputs: &lanes::LaneOutputs| -> Result<()> {
                if j % OUTPUT_LOOK_EVERY == OUTPUT_LOOK_EVERY - 1 {
                    if let Some(monitor) = monitor {
                        monitor.look()?;
                    }
                }
                for l in 0..k {
                    if pending[l].is_some() {
                        continue;
                    }
                    let (Some((omega, q)), Some(rows)) = (&outputs[l], &mut rows[l]) else {
                        continue;
                    };
                    let sample = Sample {
                        body: &lane(l).1,
                        omega,
                        orientation: q.as_ref(),
                        rotors: None,
                    };
                    // SAFETY: the body's rows, written by its lane alone.
                    if let Err(error) = unsafe { rows.write(j, &sample) } {
                        pending[l] = Some(error);
                    }
                }
                Ok(())
            };
            let mut ran = lanes::integrate_lanes(
                &run.method,
                &moments[..k],
                &states[..k],
                t,
                &lane_options,
                output,
            );
            for l in 0..k {
                let i = lane(l).0;
                let result = ran[l].take().expect("a result per lane");
                match result.and_then(|stats| pending[l].take().map_or(Ok(stats), Err)) {
                    // SAFETY: body i's entry, written by its block alone.
                    Ok(stats) => unsafe { stats_column.set(i, stats) },
                    Err(error) => fail(i, error),
                }
            }
            first
        };
        // The splitting's blocks share an axis order: only the moments decide it.
        let shared_axes = (bodies.len() == 1)
            .then(|| prepare(&bodies[0], None).ok().map(|b| b.moments.split_axes));
        let blocks = lane_blocks(n, &run.method, run.parallel, |i| match shared_axes {
            Some(axes) => axes,
            None => prepare(&bodies[i], None)
                .ok()
                .map(|body| body.moments.split_axes),
        });
        let first = if run.parallel {
            blocks.par_iter().filter_map(block).min_by_key(|(i, _)| *i)
        } else {
            blocks.iter().filter_map(block).min_by_key(|(i, _)| *i)
        };
        if let Some((i, error)) = first {
            return Err(error.in_body(i));
        }
        stats
    } else {
        let results: Vec<Result<Stats>> = if run.parallel && n > 1 {
            (0..n).into_par_iter().map(one).collect()
        } else {
            (0..n).map(one).collect()
        };
        let mut stats = Vec::with_capacity(n);
        for (i, result) in results.into_iter().enumerate() {
            match result {
                Ok(s) => stats.push(s),
                Err(error) if n > 1 => return Err(error.in_body(i)),
                Err(error) => return Err(error),
            }
        }
        stats
    };
    Ok(Outputs {
        n,
        m,
        rotors,
        columns: columns.into_iter().zip(data).collect(),
        moments,
        stats,
    })
}
