//! A body's run, prepared: from a body as a user gives it (principal moments, an inertia
//! tensor, mass properties) to its principal moments, its principal axes, its torque rotated
//! into them and its initial state there, each checked.
//!
//! Each body is integrated in its principal axes, where Euler's equations are diagonal: with
//! `V` the principal axes (columns, in body coordinates, a proper rotation),
//! `omega_p = V^T omega_b` and `R_p = R_b V`. A torque, given in body axes, is rotated into the
//! principal axes in one place ([`InFrame`]), whatever its model.

use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

use crate::dynamics::{BodyContext, Moments, Segment, State, Torque, TorqueSpec};
use crate::eigen::{symmetric_eigen3_with, DEFAULT_RTOL};
use crate::error::{finite, Short};
use crate::mass::{check_rotation, MassProperties};
use crate::{Error, Result};

/// A body as [`super::simulate`] takes it.
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

/// The principal axes of a body given in other axes: the columns of `matrix` (a rotation), and
/// the same rotation as a quaternion.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrincipalAxes {
    pub(crate) matrix: Matrix3<f64>,
    pub(crate) rotation: UnitQuaternion<f64>,
}

impl PrincipalAxes {
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
    frame: PrincipalAxes,
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

/// One body's run, prepared: its validated principal moments, its principal axes (`None`
/// when they are the body's own), its torque in those axes, and its initial state there.
pub(crate) struct Job {
    pub(crate) moments: Moments,
    pub(crate) frame: Option<PrincipalAxes>,
    pub(crate) torque: Option<Box<dyn Torque + Send>>,
    pub(crate) state: State,
}

const MOMENTS_REASON: &str = "expected positive principal moments (Euler's equations need I^-1; \
                              a rod or a point mass has a zero moment)";

/// The error of principal moments that are not all finite and positive.
fn bad_moments(m: &Vector3<f64>) -> Error {
    Error::InvalidArgument {
        name: "body".into(),
        reason: format!("{MOMENTS_REASON}, got {:?}.", [m[0], m[1], m[2]]),
    }
}

/// The principal moments and axes of `body` (about `pivot` for mass properties with one),
/// and what a torque model is built from.
fn principal_of(
    body: &Body,
    pivot: Option<Vector3<f64>>,
) -> Result<(Vector3<f64>, Matrix3<f64>, BodyContext)> {
    Ok(match body {
        Body::Moments(m) => {
            if !m.iter().all(|&x| x.is_finite() && x > 0.0) {
                return Err(bad_moments(m));
            }
            let context = BodyContext {
                inertia: Matrix3::from_diagonal(m),
                mass_about_pivot: None,
            };
            (*m, Matrix3::identity(), context)
        }
        Body::Inertia(tensor) => {
            let p = symmetric_eigen3_with(tensor, DEFAULT_RTOL, "body")?;
            let context = BodyContext {
                inertia: *tensor,
                mass_about_pivot: None,
            };
            (p.moments, p.axes, context)
        }
        Body::MassProperties(mp) => match pivot {
            Some(pivot) => {
                let inertia = mp.inertia_about_unchecked(&pivot);
                if !inertia.iter().all(|x| x.is_finite()) {
                    // The body's own inertia is finite: the pivot is too far from it.
                    return Err(Error::InvalidArgument {
                        name: "pivot".into(),
                        reason: format!(
                            "the body's inertia about the pivot ({}, {}, {}) overflows double \
                             precision (its mass times the squared distance).",
                            Short(pivot.x),
                            Short(pivot.y),
                            Short(pivot.z)
                        ),
                    });
                }
                let p = symmetric_eigen3_with(&inertia, DEFAULT_RTOL, "body")?;
                let context = BodyContext {
                    inertia,
                    mass_about_pivot: Some((mp.mass(), mp.center_of_mass() - pivot)),
                };
                (p.moments, p.axes, context)
            }
            None => {
                let p = mp.principal();
                let context = BodyContext {
                    inertia: mp.inertia(),
                    mass_about_pivot: None,
                };
                (p.moments, p.axes, context)
            }
        },
    })
}

impl Job {
    /// The job of `body` under `torque` (in body axes) from `omega0` (body axes) and
    /// `orientation0`: errors name `body`, `pivot`, the torque's fields or `omega0`.
    pub(crate) fn new(
        body: &Body,
        torque: Option<&TorqueSpec>,
        omega0: &Vector3<f64>,
        orientation0: &UnitQuaternion<f64>,
    ) -> Result<Self> {
        let pivot = torque.and_then(TorqueSpec::pivot);
        let (moments, axes, context) = principal_of(body, pivot)?;
        if !moments.iter().all(|&m| m.is_finite() && m > 0.0) {
            return Err(bad_moments(&moments));
        }
        let moments = Moments::new(moments).map_err(|e| e.map_name(|_| "body".into()))?;
        let frame = PrincipalAxes::of(&axes);
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
        let state = initial_state(&moments, frame.as_ref(), omega0, orientation0)?;
        Ok(Job {
            moments,
            frame,
            torque,
            state,
        })
    }

    /// The principal axes as a matrix (the identity when they are the body's own).
    pub(crate) fn axes(&self) -> Matrix3<f64> {
        self.frame.map_or_else(Matrix3::identity, |f| f.matrix)
    }
}

/// The initial state of one body in its principal axes, checked: `omega0` finite, its
/// kinetic energy too.
fn initial_state(
    moments: &Moments,
    frame: Option<&PrincipalAxes>,
    omega0: &Vector3<f64>,
    orientation0: &UnitQuaternion<f64>,
) -> Result<State> {
    for k in 0..3 {
        if !omega0[k].is_finite() {
            finite("omega0", omega0[k])?;
        }
    }
    let energy = moments.kinetic_energy(&match frame {
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
    Ok(match frame {
        // omega_p = V^T omega_b; R_p = R_b V.
        Some(frame) => State::new(frame.matrix.tr_mul(omega0), orientation0 * frame.rotation),
        None => State::new(*omega0, *orientation0),
    })
}

/// The splitting's axis order of `body` (what a block of bodies integrated together shares), or
/// `None` for a body whose preparation fails.
pub(crate) fn axis_order(body: &Body) -> Option<[usize; 3]> {
    let (moments, _, _) = principal_of(body, None).ok()?;
    if !moments.iter().all(|&m| m.is_finite() && m > 0.0) {
        return None;
    }
    Moments::new(moments).ok().map(|m| m.split_axes)
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
