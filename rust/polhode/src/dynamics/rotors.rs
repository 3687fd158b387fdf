//! Internal rotors: reaction wheels and spherical (Kane) dampers inside a rigid body, the
//! gyrostat equations with each rotor's own equation, and their integration by `rk4` and
//! `dop853`.
//!
//! **Convention.** The body's inertia `I` (its principal moments, in whose axes everything
//! here is written) is that of the whole system with its rotors locked: it includes each
//! rotor's mass and all of its inertia. `A = I - sum_wheels J a a^T - sum_dampers J 1` is then
//! the inertia of the body with the rotors' spinning inertia taken out (it must be positive
//! definite). A rotor at rest relative to the body leaves the motion that of the rigid body
//! `I` (Hughes, *Spacecraft Attitude Dynamics*, 1986; Hall, J. Guidance 19(5), 1996).
//!
//! **Variables**, in body axes: the angular velocity `w`, the orientation `q`, and per rotor
//! - a wheel on the body-fixed unit axis `a` with axial inertia `J`, spinning at `W` relative
//!   to the body and driven by the motor torque `g` (on the wheel, about `a`): its axial
//!   angular momentum `h = J (a . w + W)`;
//! - a spherical damper (a sphere of inertia `J` in a spherical cavity, viscous coupling `c`):
//!   its absolute angular velocity `s`.
//!
//! **Equations** (derived in `docs/rotors.md`; the wheel's bearings pass only transverse
//! torques):
//! - `h' = g`;
//! - `J (s' + w x s) = -c (s - w)`, the sphere's Euler equation in the rotating frame;
//! - `A w' = (A w + sum h a) x w - sum g a + sum c (s - w) + tau`, the body (without the
//!   rotors' spinning inertia) under the motors' reactions, the dampers' viscous torques and
//!   the external torque `tau`. (The dampers' own momentum `J s` drops out of the body's
//!   gyroscopic term: its `w x J s` is balanced inside the sphere's equation.)
//!
//! Then the total angular momentum `H = A w + sum h a + sum J s` obeys `H' + w x H = tau`:
//! without external torque `R(q) H` is constant in space, whatever the motors and dampers do.
//! The total kinetic energy is `T = w . A w / 2 + sum h^2 / (2 J) + sum J |s|^2 / 2`; with a
//! damper it decreases at `-sum c |s - w|^2`, the motors' power added.

use std::sync::Arc;

use nalgebra::{Matrix3, Quaternion, SVector, UnitQuaternion, Vector3, Vector4};

use super::dop853::{Stamp, Tolerance};
use super::driver::omega_scale;
use super::loops::{breaks, dop853_segments, fixed_loop, segment_ends, ScaledSystem};
use super::method::{check_method, check_times, Method, Options, Stats};
use super::state::{quaternion_rate, State};
use super::stepper::Stepper;
use super::system::System;
use super::torque::{unit_vector, Segment, Torque};
use crate::error::{finite, positive, Short};
use crate::memory::{self, Purpose};
use crate::{Error, Result};

/// The largest number of rotor variables (a wheel has one, a damper three).
pub const MAX_ROTOR_VARIABLES: usize = 24;

/// A motor torque function `(t, omega_body, rate) -> torque`: the body's angular velocity in
/// its own axes and the wheel's rate relative to the body.
pub type MotorFn = dyn Fn(f64, &Vector3<f64>, f64) -> Result<f64> + Send + Sync;

/// The torque a wheel's motor applies to the wheel, about its axis (the body feels the
/// opposite).
#[derive(Clone)]
pub enum MotorTorque {
    /// A constant torque.
    Constant(f64),
    /// A piecewise constant torque: `values[k]` from `times[k]` to `times[k + 1]` (the last
    /// one onwards), zero before `times[0]`; `times` finite and increasing.
    Schedule {
        /// When each value starts.
        times: Vec<f64>,
        /// The torques.
        values: Vec<f64>,
    },
    /// A function of the time, the body's angular velocity (its own axes) and the wheel's
    /// rate; an `Err` stops the integration with that error.
    Function(Arc<MotorFn>),
}

impl std::fmt::Debug for MotorTorque {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MotorTorque::Constant(g) => write!(f, "Constant({g})"),
            MotorTorque::Schedule { times, values } => f
                .debug_struct("Schedule")
                .field("times", times)
                .field("values", values)
                .finish(),
            MotorTorque::Function(_) => write!(f, "Function(..)"),
        }
    }
}

impl MotorTorque {
    fn check(&self) -> Result<()> {
        match self {
            MotorTorque::Constant(g) => finite("torque", *g).map(|_| ()),
            MotorTorque::Schedule { times, values } => {
                if times.is_empty() || times.len() != values.len() {
                    return Err(Error::Shape {
                        name: "torque".into(),
                        expected: "(K, 2) (time, torque) pairs, K >= 1".into(),
                        got: format!("{} times and {} torques", times.len(), values.len()),
                    });
                }
                for (k, (&t, &g)) in times.iter().zip(values).enumerate() {
                    finite(&format!("torque[{k}] (its time)"), t)?;
                    finite(&format!("torque[{k}] (its value)"), g)?;
                    if k > 0 && t <= times[k - 1] {
                        return Err(Error::InvalidArgument {
                            name: "torque".into(),
                            reason: format!(
                                "expected increasing times in the schedule, got {} after {}.",
                                Short(t),
                                Short(times[k - 1])
                            ),
                        });
                    }
                }
                Ok(())
            }
            MotorTorque::Function(_) => Ok(()),
        }
    }

    /// The torque in a step lying in `segment` (a schedule in the piece holding the segment),
    /// at the stage time `t`.
    fn value(
        &self,
        segment: &Segment,
        t: f64,
        omega_body: impl FnOnce() -> Vector3<f64>,
        rate: impl FnOnce() -> f64,
    ) -> Result<f64> {
        match self {
            MotorTorque::Constant(g) => Ok(*g),
            MotorTorque::Schedule { times, values } => {
                let k = times.partition_point(|&x| x <= segment.midpoint());
                Ok(if k == 0 { 0.0 } else { values[k - 1] })
            }
            MotorTorque::Function(f) => {
                let g = f(t, &omega_body(), rate())?;
                if g.is_finite() {
                    Ok(g)
                } else {
                    Err(Error::NonFinite {
                        name: format!("torque at t = {}", Short(t)),
                        value: g,
                    })
                }
            }
        }
    }

    /// The largest torque a schedule or a constant gives (0 for a function).
    fn largest(&self) -> f64 {
        match self {
            MotorTorque::Constant(g) => g.abs(),
            MotorTorque::Schedule { values, .. } => values.iter().fold(0.0, |a, g| a.max(g.abs())),
            MotorTorque::Function(_) => 0.0,
        }
    }
}

/// A rotor as data, in the body's own axes: what a caller hands to
/// [`crate::simulation::simulate`].
#[derive(Clone, Debug)]
pub enum RotorSpec {
    /// A wheel on a body-fixed axis.
    Wheel {
        /// Its axis, body axes (non-zero; normalised).
        axis: Vector3<f64>,
        /// Its axial moment of inertia `J > 0`.
        inertia: f64,
        /// Its rate relative to the body at `t0`, about `axis`.
        rate0: f64,
        /// The motor's torque on the wheel.
        torque: MotorTorque,
    },
    /// A sphere of inertia `J` in a spherical cavity, coupled to the body by the viscous
    /// torque `c (w - s)`; it starts turning with the body.
    SphericalDamper {
        /// The sphere's moment of inertia `J > 0`.
        inertia: f64,
        /// The viscous coefficient `c >= 0` (torque per relative rate).
        damping: f64,
    },
}

/// A rotor's named fields as a front end holds them: what [`RotorSpec::from_fields`] reads.
pub trait RotorFields {
    /// The front end's error.
    type Error;
    /// A core error as the front end's.
    fn error(error: Error) -> Self::Error;
    /// The number in field `name` (`None` when it holds none).
    fn number(&self, name: &str) -> std::result::Result<Option<f64>, Self::Error>;
    /// The vector (x, y, z) in field `name` (`None` when it holds none).
    fn vector(&self, name: &str) -> std::result::Result<Option<Vector3<f64>>, Self::Error>;
    /// The motor torque in field `name` (a number, a schedule or a function).
    fn motor(&self, name: &str) -> std::result::Result<MotorTorque, Self::Error>;
}

impl RotorSpec {
    /// The rotor of kind `kind` (`"Wheel"`, `"SphericalDamper"`) from its fields, named as in
    /// the variants.
    pub fn from_fields<F: RotorFields>(
        kind: &str,
        fields: &F,
    ) -> std::result::Result<Self, F::Error> {
        let missing = |name: &str| {
            F::error(Error::InvalidArgument {
                name: name.into(),
                reason: format!("a {kind} needs `{name}`."),
            })
        };
        let number = |name: &str| fields.number(name)?.ok_or_else(|| missing(name));
        Ok(match kind {
            "Wheel" => RotorSpec::Wheel {
                axis: fields.vector("axis")?.ok_or_else(|| missing("axis"))?,
                inertia: number("inertia")?,
                rate0: number("rate0")?,
                torque: fields.motor("torque")?,
            },
            "SphericalDamper" => RotorSpec::SphericalDamper {
                inertia: number("inertia")?,
                damping: number("damping")?,
            },
            other => {
                return Err(F::error(Error::InvalidArgument {
                    name: "rotors".into(),
                    reason: format!(
                        "expected a rotor (Wheel or SphericalDamper), got kind {other:?}."
                    ),
                }))
            }
        })
    }

    /// Checks the rotor's own parameters, each error naming its field.
    pub fn check(&self) -> Result<()> {
        match self {
            RotorSpec::Wheel {
                axis,
                inertia,
                rate0,
                torque,
            } => {
                unit_vector("axis", axis)?;
                positive("inertia", *inertia)?;
                finite("rate0", *rate0)?;
                torque.check()
            }
            RotorSpec::SphericalDamper { inertia, damping } => {
                positive("inertia", *inertia)?;
                finite("damping", *damping)?;
                if *damping < 0.0 {
                    return Err(Error::InvalidArgument {
                        name: "damping".into(),
                        reason: format!(
                            "expected a non-negative viscous coefficient, got {}.",
                            Short(*damping)
                        ),
                    });
                }
                Ok(())
            }
        }
    }

    /// Its number of variables: 1 for a wheel, 3 for a damper.
    #[must_use]
    pub fn variables(&self) -> usize {
        match self {
            RotorSpec::Wheel { .. } => 1,
            RotorSpec::SphericalDamper { .. } => 3,
        }
    }

    /// Whether its motor torque is a function (a front end may need to call it serially).
    #[must_use]
    pub fn has_function(&self) -> bool {
        matches!(
            self,
            RotorSpec::Wheel {
                torque: MotorTorque::Function(_),
                ..
            }
        )
    }
}

/// A rotor in the principal axes the body is integrated in.
#[derive(Clone, Debug)]
enum Rotor {
    Wheel {
        axis: Vector3<f64>,
        inertia: f64,
        rate0: f64,
        motor: MotorTorque,
    },
    Damper {
        inertia: f64,
        damping: f64,
    },
}

/// A body with rotors, in its principal axes: the gyrostat's equations and its totals.
#[derive(Clone, Debug)]
pub struct Gyrostat {
    /// The principal axes in the body's own coordinates (columns): `x_body = frame x_p`.
    frame: Matrix3<f64>,
    /// `A = I - sum J a a^T - sum J 1`, principal axes.
    a: Matrix3<f64>,
    a_inv: Matrix3<f64>,
    rotors: Vec<Rotor>,
    variables: usize,
}

impl Gyrostat {
    /// The gyrostat of a body with principal moments `moments` (the rotors locked), whose
    /// principal axes are the columns of `frame` in its own coordinates, and `rotors` given in
    /// its own axes.
    ///
    /// # Errors
    /// A rotor's bad parameter (named `rotors[k].field`), more than
    /// [`MAX_ROTOR_VARIABLES`] variables, or rotors whose spinning inertia is not inside the
    /// body's (`A` not positive definite), each naming `rotors`.
    pub fn new(moments: &Vector3<f64>, frame: &Matrix3<f64>, rotors: &[RotorSpec]) -> Result<Self> {
        let variables: usize = rotors.iter().map(RotorSpec::variables).sum();
        if variables > MAX_ROTOR_VARIABLES {
            return Err(Error::InvalidArgument {
                name: "rotors".into(),
                reason: format!(
                    "expected at most {MAX_ROTOR_VARIABLES} rotor variables (a wheel has 1, a \
                     damper 3), got {variables}."
                ),
            });
        }
        let mut a = Matrix3::from_diagonal(moments);
        let mut inside = Vec::with_capacity(rotors.len());
        for (k, spec) in rotors.iter().enumerate() {
            spec.check()
                .map_err(|e| e.map_name(|name| format!("rotors[{k}].{name}")))?;
            inside.push(match spec {
                RotorSpec::Wheel {
                    axis,
                    inertia,
                    rate0,
                    torque,
                } => {
                    let axis = frame.tr_mul(&unit_vector("axis", axis)?);
                    a -= axis * axis.transpose() * *inertia;
                    Rotor::Wheel {
                        axis,
                        inertia: *inertia,
                        rate0: *rate0,
                        motor: torque.clone(),
                    }
                }
                RotorSpec::SphericalDamper { inertia, damping } => {
                    a -= Matrix3::identity() * *inertia;
                    Rotor::Damper {
                        inertia: *inertia,
                        damping: *damping,
                    }
                }
            });
        }
        let a = (a + a.transpose()) * 0.5;
        let smallest = crate::symmetric_eigen3(&a)
            .map(|p| p.moments.min())
            .unwrap_or(f64::NAN);
        let scale = moments.max();
        let a_inv = a.try_inverse();
        match a_inv {
            Some(a_inv) if smallest > 1e-12 * scale && a_inv.iter().all(|x| x.is_finite()) => {
                Ok(Self {
                    frame: *frame,
                    a,
                    a_inv,
                    rotors: inside,
                    variables,
                })
            }
            _ => Err(Error::InvalidArgument {
                name: "rotors".into(),
                reason: format!(
                    "the rotors' spinning inertia must lie inside the body's: the body's inertia \
                     includes its rotors (locked), so I - sum J a a^T (wheels) - sum J 1 \
                     (dampers) must be positive definite, its smallest eigenvalue above 1e-12 \
                     times the largest principal moment ({}); it is {} with principal moments \
                     {:?}.",
                    Short(1e-12 * scale),
                    Short(smallest),
                    moments.as_slice()
                ),
            }),
        }
    }

    /// The number of rotor variables.
    #[must_use]
    pub fn variables(&self) -> usize {
        self.variables
    }

    /// The number of rotors.
    #[must_use]
    pub fn rotors(&self) -> usize {
        self.rotors.len()
    }

    /// The rotor variables at the start, for the body's angular velocity `omega` (principal
    /// axes): each wheel's `h = J (a . w + rate0)`, each damper's `s = w`.
    #[must_use]
    pub fn initial_variables(&self, omega: &Vector3<f64>) -> Vec<f64> {
        let mut v = Vec::with_capacity(self.variables);
        for rotor in &self.rotors {
            match rotor {
                Rotor::Wheel {
                    axis,
                    inertia,
                    rate0,
                    ..
                } => v.push(inertia * (axis.dot(omega) + rate0)),
                Rotor::Damper { .. } => v.extend_from_slice(omega.as_slice()),
            }
        }
        v
    }

    /// The rotor variables at the start ([`Gyrostat::initial_variables`]) for the body's
    /// angular velocity `omega` (principal axes), checked: an error naming `rotors` if they or
    /// the total kinetic energy overflow double precision.
    pub(crate) fn start(&self, omega: &Vector3<f64>) -> Result<Vec<f64>> {
        let vars = self.initial_variables(omega);
        let energy = self.energy(omega, &vars);
        if !(energy.is_finite() && vars.iter().all(|v| v.is_finite())) {
            return Err(Error::InvalidArgument {
                name: "rotors".into(),
                reason: "the rotors' angular momentum or kinetic energy at the start overflows \
                         double precision."
                    .into(),
            });
        }
        Ok(vars)
    }

    /// The total angular momentum `H = A w + sum h a + sum J s`, principal axes.
    #[must_use]
    pub fn angular_momentum(&self, omega: &Vector3<f64>, vars: &[f64]) -> Vector3<f64> {
        let mut h = self.a * omega;
        let mut slot = 0;
        for rotor in &self.rotors {
            match rotor {
                Rotor::Wheel { axis, .. } => {
                    h += axis * vars[slot];
                    slot += 1;
                }
                Rotor::Damper { inertia, .. } => {
                    h += Vector3::from_column_slice(&vars[slot..slot + 3]) * *inertia;
                    slot += 3;
                }
            }
        }
        h
    }

    /// The total kinetic energy `T = w . A w / 2 + sum h^2 / (2 J) + sum J |s|^2 / 2`.
    #[must_use]
    pub fn energy(&self, omega: &Vector3<f64>, vars: &[f64]) -> f64 {
        let mut t = 0.5 * omega.dot(&(self.a * omega));
        let mut slot = 0;
        for rotor in &self.rotors {
            match rotor {
                Rotor::Wheel { inertia, .. } => {
                    t += 0.5 * vars[slot] * vars[slot] / inertia;
                    slot += 1;
                }
                Rotor::Damper { inertia, .. } => {
                    t += 0.5
                        * inertia
                        * Vector3::from_column_slice(&vars[slot..slot + 3]).norm_squared();
                    slot += 3;
                }
            }
        }
        t
    }

    /// Whether the rotors are wheels without motor torque (no dampers): the equations are then
    /// homogeneous of degree 2 in the body's and the wheels' rates.
    fn is_free(&self) -> bool {
        self.rotors.iter().all(|rotor| {
            matches!(
                rotor,
                Rotor::Wheel {
                    motor: MotorTorque::Constant(g),
                    ..
                } if *g == 0.0
            )
        })
    }

    /// Each rotor's angular velocity relative to the body, principal axes: `W a` for a wheel,
    /// `s - w` for a damper.
    #[must_use]
    pub fn rotor_rates(&self, omega: &Vector3<f64>, vars: &[f64]) -> Vec<Vector3<f64>> {
        let mut out = Vec::with_capacity(self.rotors.len());
        let mut slot = 0;
        for rotor in &self.rotors {
            match rotor {
                Rotor::Wheel { axis, inertia, .. } => {
                    out.push(axis * (vars[slot] / inertia - axis.dot(omega)));
                    slot += 1;
                }
                Rotor::Damper { .. } => {
                    out.push(Vector3::from_column_slice(&vars[slot..slot + 3]) - omega);
                    slot += 3;
                }
            }
        }
        out
    }

    /// The times at which a motor's schedule switches.
    fn discontinuities(&self) -> Vec<f64> {
        let mut times = Vec::new();
        for rotor in &self.rotors {
            if let Rotor::Wheel {
                motor: MotorTorque::Schedule { times: t, .. },
                ..
            } = rotor
            {
                times.extend_from_slice(t);
            }
        }
        times
    }

    /// The derivative of `(w, q, variables)` at `t`, for a step lying in `segment`.
    #[inline]
    fn rate<const N: usize>(
        &self,
        torque: Option<&dyn Torque>,
        segment: &Segment,
        t: f64,
        y: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        let w = Vector3::new(y[0], y[1], y[2]);
        let q = Vector4::new(y[3], y[4], y[5], y[6]);
        let mut out = SVector::<f64, N>::zeros();
        // sum h a, and the rotors' torques on the body.
        let mut h = Vector3::zeros();
        let mut on_body = Vector3::zeros();
        let mut slot = 7;
        for rotor in &self.rotors {
            match rotor {
                Rotor::Wheel {
                    axis,
                    inertia,
                    motor,
                    ..
                } => {
                    let hj = y[slot];
                    h += axis * hj;
                    let g = motor.value(
                        segment,
                        t,
                        || self.frame * w,
                        || hj / inertia - axis.dot(&w),
                    )?;
                    on_body -= axis * g;
                    out[slot] = g;
                    slot += 1;
                }
                Rotor::Damper { inertia, damping } => {
                    let s = Vector3::new(y[slot], y[slot + 1], y[slot + 2]);
                    let relative = s - w;
                    on_body += relative * *damping;
                    let ds = -w.cross(&s) - relative * (damping / inertia);
                    out[slot] = ds[0];
                    out[slot + 1] = ds[1];
                    out[slot + 2] = ds[2];
                    slot += 3;
                }
            }
        }
        if let Some(torque) = torque {
            let orientation = UnitQuaternion::new_unchecked(Quaternion::from(q / q.norm()));
            on_body += torque.try_torque_body_in(segment, t, &w, &orientation)?;
        }
        let dw = self.a_inv * ((self.a * w + h).cross(&w) + on_body);
        let dq = quaternion_rate(&q, &w);
        for i in 0..3 {
            out[i] = dw[i];
        }
        for i in 0..4 {
            out[3 + i] = dq[i];
        }
        Ok(out)
    }
}

/// The gyrostat's vector field on `(w, q, variables, padding)`.
struct Field<'a> {
    gyrostat: &'a Gyrostat,
    torque: Option<&'a dyn Torque>,
}

impl<const N: usize> System<N> for Field<'_> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        self.gyrostat.rate(self.torque, segment, t, y)
    }
}

/// The states of a body with rotors at the output times (principal axes).
#[derive(Clone, Debug, PartialEq)]
pub struct GyrostatTrajectory {
    /// The body's angular velocity at each output time.
    pub omega: Vec<Vector3<f64>>,
    /// Its orientation at each output time.
    pub orientation: Vec<UnitQuaternion<f64>>,
    /// The rotor variables at each output time ([`Gyrostat::variables`] numbers each, in the
    /// rotors' order: a wheel's `h`, a damper's `s`).
    pub variables: Vec<f64>,
    /// What the integration cost.
    pub stats: Stats,
}

/// Integrates a body with rotors by `rk4` or `dop853` from `state0` (principal axes) at
/// `options.t0`, its rotor variables starting at [`Gyrostat::initial_variables`], returning
/// the states at each of `times`. The orientation is always integrated (and returned).
///
/// # Errors
/// As [`super::integrate`]; a method other than `rk4` and `dop853` is an error naming
/// `rotors`.
pub fn integrate_gyrostat(
    method: &Method,
    gyrostat: &Gyrostat,
    state0: &State,
    times: &[f64],
    options: &Options,
) -> Result<GyrostatTrajectory> {
    // Room for every output time: the pushes below never grow the vectors.
    let variables = times.len().checked_mul(gyrostat.variables).ok_or_else(|| {
        Purpose::Outputs.error(times.len() as f64 * gyrostat.variables as f64 * 8.0)
    })?;
    let mut out = GyrostatTrajectory {
        omega: memory::with_capacity(times.len(), Purpose::Outputs)?,
        orientation: memory::with_capacity(times.len(), Purpose::Outputs)?,
        variables: memory::with_capacity(variables, Purpose::Outputs)?,
        stats: Stats::default(),
    };
    out.stats = run_gyrostat(
        method,
        gyrostat,
        state0,
        times,
        options,
        &mut |_, w, q, v| {
            out.omega.push(*w);
            out.orientation.push(*q);
            out.variables.extend_from_slice(v);
            Ok(())
        },
    )?;
    Ok(out)
}

/// Where a gyrostat's run sends its outputs: `sink(k, omega, q, variables)` at each output
/// time `times[k]`, in order, every number finite (principal axes). An error from it stops the
/// run with that error.
pub(crate) type GyrostatSink<'a> =
    dyn FnMut(usize, &Vector3<f64>, &UnitQuaternion<f64>, &[f64]) -> Result<()> + 'a;

/// Where a gyrostat's `dop853` run sends its state at the end of each accepted step (see
/// [`run_gyrostat_with_steps`]): `steps(t, omega, q, variables)`.
pub(crate) type GyrostatStepSink<'a> =
    dyn FnMut(f64, &Vector3<f64>, &UnitQuaternion<f64>, &[f64]) -> Result<()> + 'a;

/// [`integrate_gyrostat`] with its outputs sent to `sink` as they come, rather than collected.
pub(crate) fn run_gyrostat(
    method: &Method,
    gyrostat: &Gyrostat,
    state0: &State,
    times: &[f64],
    options: &Options,
    sink: &mut GyrostatSink,
) -> Result<Stats> {
    run_gyrostat_with_steps(method, gyrostat, state0, times, options, sink, None)
}

/// [`run_gyrostat`], and for `dop853` the state at the end of each accepted step sent to
/// `steps` if given (in time order with the output times: a step's after those it covers).
pub(crate) fn run_gyrostat_with_steps<'a>(
    method: &Method,
    gyrostat: &Gyrostat,
    state0: &State,
    times: &[f64],
    options: &Options,
    sink: &mut GyrostatSink<'a>,
    steps: Option<&mut GyrostatStepSink<'a>>,
) -> Result<Stats> {
    if let Some(monitor) = options.monitor {
        monitor.check()?;
    }
    check_rotor_method(method)?;
    check_method(method, options)?;
    state0.check_finite("state0")?;
    check_times(times, options.t0)?;
    match gyrostat.variables {
        0..=3 => run::<10>(method, gyrostat, state0, times, options, sink, steps),
        4..=6 => run::<13>(method, gyrostat, state0, times, options, sink, steps),
        7..=12 => run::<19>(method, gyrostat, state0, times, options, sink, steps),
        _ => run::<31>(method, gyrostat, state0, times, options, sink, steps),
    }
}

/// Rotors are integrated by `rk4` and `dop853` only.
pub(crate) fn check_rotor_method(method: &Method) -> Result<()> {
    let why = match method {
        Method::Rk4 { .. } | Method::Dop853(_) => return Ok(()),
        Method::Exact => "the exact solution is that of a free rigid body",
        Method::Splitting { .. } => {
            "the splitting's exact sub-flows are those of a rigid body's Euler equations"
        }
        Method::Midpoint { .. } => {
            "the midpoint rule's Newton iteration is written for a rigid body"
        }
    };
    Err(Error::InvalidArgument {
        name: "rotors".into(),
        reason: format!(
            "a body with rotors is integrated by \"dop853\" (what \"auto\" picks) or \"rk4\", not \
             by {:?}: {why}.",
            method.name()
        ),
    })
}

fn run<'a, const N: usize>(
    method: &Method,
    gyrostat: &Gyrostat,
    state0: &State,
    times: &[f64],
    options: &Options,
    sink: &mut GyrostatSink<'a>,
    mut steps: Option<&mut GyrostatStepSink<'a>>,
) -> Result<Stats> {
    let k = gyrostat.variables;
    let mut y0 = SVector::<f64, N>::zeros();
    let q0 = state0.orientation.coords / state0.orientation.coords.norm();
    for i in 0..3 {
        y0[i] = state0.omega[i];
    }
    for i in 0..4 {
        y0[3 + i] = q0[i];
    }
    let vars0 = gyrostat.start(&state0.omega)?;
    // Without a torque, motors or dampers the equations are homogeneous of degree 2 in the
    // rates (w and the wheels' momenta): far from 1 they are integrated in units of a power of
    // two, as a rigid body's (see `driver::omega_scale`); at |w| ~ 1e-160 the products of the
    // rates underflowed and w stayed constant. Otherwise the unit is 1 (the same bits).
    let rates = gyrostat.rotor_rates(&state0.omega, &vars0);
    let size = rates
        .iter()
        .fold(state0.omega.amax(), |a, r| a.max(r.amax()));
    let scale = if options.torque.is_none() && gyrostat.is_free() {
        omega_scale(&Vector3::new(size, 0.0, 0.0)).unwrap_or(1.0)
    } else {
        1.0
    };
    for i in 0..3 {
        y0[i] /= scale;
    }
    for (i, v) in vars0.into_iter().enumerate() {
        y0[7 + i] = v / scale;
    }
    // The state at `t` in the body's units, checked finite: (w, q, variables).
    let unpack = |t: f64, y: &SVector<f64, N>| -> Result<SVector<f64, N>> {
        let mut y = *y;
        for i in (0..3).chain(7..7 + k) {
            y[i] *= scale;
        }
        if let Some((i, v)) = y.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFinite {
                name: format!(
                    "{} at t = {} (the solution blew up: reduce dt or rtol)",
                    match i {
                        0..=2 => "omega",
                        3..=6 => "orientation",
                        _ => "rotor_rates",
                    },
                    Short(t)
                ),
                value: *v,
            });
        }
        Ok(y)
    };
    let unit = |y: &SVector<f64, N>| {
        let q = Vector4::new(y[3], y[4], y[5], y[6]);
        UnitQuaternion::new_unchecked(Quaternion::from(q / q.norm()))
    };
    let mut push = |j: usize, y: &SVector<f64, N>| -> Result<()> {
        let y = unpack(times[j], y)?;
        sink(
            j,
            &Vector3::new(y[0], y[1], y[2]),
            &unit(&y),
            &y.as_slice()[7..7 + k],
        )
    };
    let mut push_step = |t: f64, y: &SVector<f64, N>| -> Result<()> {
        let Some(steps) = steps.as_mut() else {
            return Ok(());
        };
        let y = unpack(t, y)?;
        steps(
            t,
            &Vector3::new(y[0], y[1], y[2]),
            &unit(&y),
            &y.as_slice()[7..7 + k],
        )
    };
    let field = ScaledSystem {
        system: Field {
            gyrostat,
            torque: options.torque,
        },
        scale,
    };
    let breaks = breaks(options.torque, gyrostat.discontinuities());
    match *method {
        Method::Rk4 { dt } => {
            let stepper = Rk4 { sys: &field };
            fixed_loop(stepper, dt, y0, times, &breaks, options, |j, _, y| {
                push(j, y)
            })
        }
        Method::Dop853(mut o) => {
            o.atol = o.atol.map(|atol| atol / scale);
            let tolerance = tolerance(gyrostat, &field, &y0, times, options, &o, &breaks)?;
            let ends = segment_ends(options.t0, times, &breaks);
            dop853_segments(
                &field,
                y0,
                times,
                options,
                &o,
                tolerance,
                &ends,
                renormalize,
                |stamp, y| match stamp {
                    Stamp::Output(j) => push(j, y),
                    Stamp::Step(t) => push_step(t, y),
                },
            )
        }
        _ => Err(check_rotor_method(method).unwrap_err()),
    }
}

/// Renormalises the quaternion part of `y` (and of its derivative `f`, by the same factor).
#[inline]
fn renormalize<const N: usize>(y: &mut SVector<f64, N>, f: &mut SVector<f64, N>) {
    let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
    for i in 3..7 {
        y[i] /= n;
        f[i] /= n;
    }
}

/// Classic RK4 on the gyrostat's `(w, q, variables)`, the quaternion renormalised after each
/// step.
struct Rk4<'a, S, const N: usize> {
    sys: &'a S,
}

impl<S: System<N>, const N: usize> Stepper for Rk4<'_, S, N> {
    type Vars = SVector<f64, N>;

    #[inline]
    fn step(&mut self, segment: &Segment, t: f64, y: &mut Self::Vars, h: f64) -> Result<()> {
        let sys = self.sys;
        let half = 0.5 * h;
        let k1 = sys.rhs(segment, t, y)?;
        let k2 = sys.rhs(segment, t + half, &(*y + k1 * half))?;
        let k3 = sys.rhs(segment, t + half, &(*y + k2 * half))?;
        let k4 = sys.rhs(segment, t + h, &(*y + k3 * h))?;
        *y += (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0);
        Ok(())
    }

    #[inline]
    fn restore(&mut self, y: &mut Self::Vars) {
        let mut unused = SVector::<f64, N>::zeros();
        renormalize(y, &mut unused);
    }

    fn evaluations(&self, steps: u64) -> u64 {
        4 * steps
    }
}

/// The absolute tolerances of `dop853`: `atol` (default `rtol` times the largest rate at the
/// start: of the body, or of a rotor relative to it; for a start at rest, the rate the
/// torques would reach over the span) on the angular velocity and the dampers' rates, `J`
/// times it on a wheel's momentum, `rtol` on the quaternion.
fn tolerance<S: System<N>, const N: usize>(
    gyrostat: &Gyrostat,
    sys: &S,
    y0: &SVector<f64, N>,
    times: &[f64],
    options: &Options,
    o: &super::Dop853Options,
    breaks: &[f64],
) -> Result<Tolerance<N>> {
    let omega0 = Vector3::new(y0[0], y0[1], y0[2]);
    let vars: Vec<f64> = y0.as_slice()[7..7 + gyrostat.variables].to_vec();
    let atol_w = match o.atol {
        Some(atol) => atol,
        None => {
            let rates = gyrostat.rotor_rates(&omega0, &vars);
            let mut scale = rates.iter().fold(omega0.norm(), |a, r| a.max(r.norm()));
            if scale == 0.0 {
                let span = times.last().map_or(0.0, |t| t - options.t0);
                let end = breaks
                    .iter()
                    .copied()
                    .find(|&b| b > options.t0)
                    .unwrap_or(options.t0 + span);
                let f0 = sys.rhs(&Segment::new(options.t0, end), options.t0, y0)?;
                let mut rate = Vector3::new(f0[0], f0[1], f0[2]).norm();
                for rotor in &gyrostat.rotors {
                    if let Rotor::Wheel { inertia, motor, .. } = rotor {
                        rate = rate.max(motor.largest() / inertia);
                    }
                }
                scale = rate * span;
            }
            o.rtol * scale
        }
    };
    let mut atol = SVector::<f64, N>::repeat(o.rtol);
    for i in 0..3 {
        atol[i] = atol_w;
    }
    let mut slot = 7;
    for rotor in &gyrostat.rotors {
        match rotor {
            Rotor::Wheel { inertia, .. } => {
                atol[slot] = atol_w * inertia;
                slot += 1;
            }
            Rotor::Damper { .. } => {
                for i in 0..3 {
                    atol[slot + i] = atol_w;
                }
                slot += 3;
            }
        }
    }
    Ok(Tolerance {
        atol,
        rtol: SVector::<f64, N>::repeat(o.rtol),
    })
}
