//! Torque models as data, built into a [`Torque`] for each body.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use super::torque::{
    BodyFixed, Function, Gravity, GravityGradient, SpaceFixed, Sum, Torque, Window,
};
use crate::error::{finite, positive};
use crate::{Error, Result};

fn finite_vector(name: &str, v: &Vector3<f64>) -> Result<()> {
    for k in 0..3 {
        finite(name, v[k])?;
    }
    Ok(())
}

/// A torque model as data, in body axes: what a caller hands to
/// [`crate::simulation::simulate`], which builds it into a [`Torque`] for each body (a
/// gravity-gradient torque needs the body's inertia, a heavy top its mass and centre of mass)
/// and rotates it into the body's principal axes.
#[derive(Clone)]
pub enum TorqueSpec {
    /// A constant torque in body axes ([`BodyFixed`]).
    BodyFixed(Vector3<f64>),
    /// A constant torque in space axes ([`SpaceFixed`]).
    SpaceFixed(Vector3<f64>),
    /// Uniform gravity on a body hinged at a fixed pivot ([`Gravity`]). With a body given as
    /// mass properties, the mass and centre of mass come from it and `pivot` (body axes,
    /// default its origin) sets the point it turns about; with principal moments or a tensor
    /// (already about the pivot), `mass` and `center_of_mass` (from the pivot, body axes) are
    /// required and `pivot` is not taken.
    Gravity {
        /// Gravitational acceleration, space axes.
        gravity: Vector3<f64>,
        /// The pivot in body coordinates (mass properties only).
        pivot: Option<Vector3<f64>>,
        /// The mass (principal moments or a tensor only).
        mass: Option<f64>,
        /// The centre of mass from the pivot, body axes (principal moments or a tensor only).
        center_of_mass: Option<Vector3<f64>>,
    },
    /// Gravity-gradient torque in a circular orbit ([`GravityGradient`]).
    GravityGradient {
        /// `n = sqrt(mu / a^3)`.
        mean_motion: f64,
        /// Orbit normal, space axes.
        orbit_normal: Vector3<f64>,
        /// Radial direction at `t = 0`, space axes.
        radial0: Vector3<f64>,
    },
    /// `torque` acting on `[start, end)` only ([`Window`]).
    Window {
        /// Opens.
        start: f64,
        /// Closes.
        end: f64,
        /// The torque inside.
        torque: Box<TorqueSpec>,
    },
    /// The sum of the terms ([`Sum`]).
    Sum(Vec<TorqueSpec>),
    /// A function of `(t, omega, orientation)` in body axes ([`Function`]).
    Function(FunctionSpec),
}

/// The closure of a [`TorqueSpec::Function`]: `(t, omega_body, orientation) -> tau_body`.
pub type TorqueFn =
    dyn Fn(f64, &Vector3<f64>, &UnitQuaternion<f64>) -> Result<Vector3<f64>> + Send + Sync;

/// A [`TorqueSpec::Function`]: the closure, what it depends on, when it jumps.
#[derive(Clone)]
pub struct FunctionSpec {
    /// The torque in body axes.
    pub function: std::sync::Arc<TorqueFn>,
    /// Whether it reads the orientation (a wrong `false` gives wrong results).
    pub depends_on_orientation: bool,
    /// Whether it reads the angular velocity.
    pub depends_on_omega: bool,
    /// The times at which it jumps.
    pub discontinuities: Vec<f64>,
}

impl TorqueSpec {
    /// The point the body turns about when the torque holds a [`TorqueSpec::Gravity`] (its
    /// pivot, default the origin of body coordinates), else `None`.
    #[must_use]
    pub fn pivot(&self) -> Option<Vector3<f64>> {
        match self {
            TorqueSpec::Gravity { pivot, .. } => Some(pivot.unwrap_or_else(Vector3::zeros)),
            TorqueSpec::Window { torque, .. } => torque.pivot(),
            TorqueSpec::Sum(terms) => terms.iter().find_map(TorqueSpec::pivot),
            _ => None,
        }
    }

    /// Checks the parameters that do not depend on the body (so that a bad model fails where
    /// it is made, not when it is used).
    pub fn check(&self) -> Result<()> {
        let unit = BodyContext {
            inertia: Matrix3::identity(),
            mass_about_pivot: None,
        };
        match self {
            TorqueSpec::Gravity {
                gravity,
                pivot,
                mass,
                center_of_mass,
            } => {
                finite_vector("gravity", gravity)?;
                if let Some(p) = pivot {
                    finite_vector("pivot", p)?;
                }
                if let Some(m) = mass {
                    positive("mass", *m)?;
                }
                if let Some(r) = center_of_mass {
                    finite_vector("center_of_mass", r)?;
                }
                Ok(())
            }
            TorqueSpec::Window { start, end, torque } => {
                torque.check()?;
                Window::new(BodyFixed::new(Vector3::zeros())?, *start, *end).map(|_| ())
            }
            TorqueSpec::Sum(terms) => terms.iter().try_for_each(TorqueSpec::check),
            other => other.build(&unit).map(|_| ()),
        }
    }

    /// The torque for one body.
    pub fn build(&self, body: &BodyContext) -> Result<Box<dyn Torque + Send>> {
        Ok(match self {
            TorqueSpec::BodyFixed(v) => Box::new(BodyFixed::new(*v)?),
            TorqueSpec::SpaceFixed(v) => Box::new(SpaceFixed::new(*v)?),
            TorqueSpec::Gravity {
                gravity,
                pivot,
                mass,
                center_of_mass,
            } => {
                let (m, r) = match (body.mass_about_pivot, mass, center_of_mass) {
                    (Some(about_pivot), None, None) => about_pivot,
                    (Some(_), _, _) => {
                        return Err(Error::InvalidArgument {
                            name: "torque".into(),
                            reason: "Gravity takes the mass and centre of mass of a Body from \
                                     the Body: give `mass` and `center_of_mass` only with \
                                     principal moments or a tensor."
                                .into(),
                        })
                    }
                    (None, Some(m), Some(r)) if pivot.is_none() => (*m, *r),
                    (None, _, _) if pivot.is_some() => {
                        return Err(Error::InvalidArgument {
                            name: "torque".into(),
                            reason: "Gravity's `pivot` is a point of a Body; with principal \
                                     moments or a tensor (taken about the pivot already), give \
                                     `mass` and `center_of_mass` from the pivot instead."
                                .into(),
                        })
                    }
                    (None, _, _) => {
                        return Err(Error::InvalidArgument {
                            name: "torque".into(),
                            reason: "expected `mass` and `center_of_mass` in Gravity(...) when \
                                     the body is given by its principal moments or a tensor \
                                     (or pass a polhode.Body)."
                                .into(),
                        })
                    }
                };
                Box::new(Gravity::new(r, m, *gravity)?)
            }
            TorqueSpec::GravityGradient {
                mean_motion,
                orbit_normal,
                radial0,
            } => Box::new(GravityGradientIn {
                orbit: GravityGradient::new(
                    Vector3::repeat(1.0),
                    *mean_motion,
                    *orbit_normal,
                    *radial0,
                )?,
                mean_motion: *mean_motion,
                inertia: body.inertia,
            }),
            TorqueSpec::Window { start, end, torque } => {
                Box::new(Window::new(torque.build(body)?, *start, *end)?)
            }
            TorqueSpec::Sum(terms) => {
                let mut sum = Sum::new();
                for term in terms {
                    sum.push(term.build(body)?);
                }
                Box::new(sum)
            }
            TorqueSpec::Function(spec) => {
                for &t in &spec.discontinuities {
                    finite("discontinuities", t)?;
                }
                let function = std::sync::Arc::clone(&spec.function);
                Box::new(
                    Function::with_dependencies(
                        move |t: f64, w: &Vector3<f64>, q: &UnitQuaternion<f64>| function(t, w, q),
                        spec.depends_on_orientation,
                        spec.depends_on_omega,
                    )
                    .with_discontinuities(spec.discontinuities.clone()),
                )
            }
        })
    }
}

/// What a torque model may need of the body it acts on (see [`TorqueSpec::build`]).
#[derive(Clone, Copy, Debug)]
pub struct BodyContext {
    /// The inertia tensor the body is integrated with, in its own axes (about the pivot of a
    /// heavy top).
    pub inertia: Matrix3<f64>,
    /// Mass and centre of mass seen from the pivot, in body axes, when the body was given as
    /// mass properties and the torque has a pivot.
    pub mass_about_pivot: Option<(f64, Vector3<f64>)>,
}

/// [`GravityGradient`] with the full inertia tensor of the axes it is evaluated in:
/// `3 n^2 r x (I r)`.
struct GravityGradientIn {
    orbit: GravityGradient,
    mean_motion: f64,
    inertia: Matrix3<f64>,
}

impl Torque for GravityGradientIn {
    fn torque_body(
        &self,
        t: f64,
        _omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        let r = orientation.inverse_transform_vector(&self.orbit.radial_space(t));
        let n2 = self.mean_motion * self.mean_motion;
        (3.0 * n2) * r.cross(&(self.inertia * r))
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}
