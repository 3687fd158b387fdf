//! The torque models evaluated in Rust. A new model is a type here implementing [`Torque`];
//! `super` re-exports every public item of this file.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use super::{finite_vector, of_size_one, unit_vector, Segment, Torque};
use crate::error::{finite, positive, Short};
use crate::{Error, Result};

/// A torque constant in body axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyFixed {
    torque: Vector3<f64>,
}

impl BodyFixed {
    /// A constant torque `torque` in body axes (finite).
    pub fn new(torque: Vector3<f64>) -> Result<Self> {
        finite_vector("torque", &torque)?;
        Ok(Self { torque })
    }
}

impl Torque for BodyFixed {
    fn torque_body(
        &self,
        _t: f64,
        _omega: &Vector3<f64>,
        _orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        self.torque
    }
    fn depends_on_orientation(&self) -> bool {
        false
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}

/// A torque constant in space axes: `tau_body = R(q)^T tau_space`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpaceFixed {
    torque_space: Vector3<f64>,
}

impl SpaceFixed {
    /// A constant `torque` in space axes (finite; an error names `torque`, as the model's
    /// field in Python).
    pub fn new(torque: Vector3<f64>) -> Result<Self> {
        finite_vector("torque", &torque)?;
        Ok(Self {
            torque_space: torque,
        })
    }
}

impl Torque for SpaceFixed {
    fn torque_body(
        &self,
        _t: f64,
        _omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        orientation.inverse_transform_vector(&self.torque_space)
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}

/// Gravity on a body hinged at a fixed pivot (the heavy top, Goldstein par. 5.7).
///
/// `tau_body = r x (R(q)^T m g)` with `r` the centre of mass relative to the pivot in body
/// axes and `g` the gravity vector in space axes; the potential energy is
/// `V = -m g . (R(q) r)`. Integrate with the principal moments ABOUT THE PIVOT
/// (`I_pivot = I_cm + m (|r|^2 1 - r r^T)`, diagonal in the chosen body axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity {
    center_of_mass: Vector3<f64>,
    weight: Vector3<f64>,
}

impl Gravity {
    /// `center_of_mass`: position of the centre of mass relative to the pivot, body axes;
    /// `mass > 0`; `gravity`: gravitational acceleration in space axes (e.g. `(0, 0, -9.81)`).
    pub fn new(center_of_mass: Vector3<f64>, mass: f64, gravity: Vector3<f64>) -> Result<Self> {
        finite_vector("center_of_mass", &center_of_mass)?;
        positive("mass", mass)?;
        finite_vector("gravity", &gravity)?;
        Ok(Self {
            center_of_mass,
            weight: mass * gravity,
        })
    }

    /// The potential energy `V = -m g . (R(q) r)` (zero with the centre of mass at the pivot
    /// height).
    #[must_use]
    pub fn potential_energy(&self, orientation: &UnitQuaternion<f64>) -> f64 {
        -self.weight.dot(&(orientation * self.center_of_mass))
    }
}

impl Torque for Gravity {
    fn torque_body(
        &self,
        _t: f64,
        _omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        self.center_of_mass
            .cross(&orientation.inverse_transform_vector(&self.weight))
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}

/// Gravity-gradient torque on a satellite in a circular orbit (Hughes, *Spacecraft Attitude
/// Dynamics*, ch. 8): `tau_body = 3 n^2 r x (I r)`, with `n` the orbital mean motion and `r`
/// the unit radial (nadir-to-zenith; the sign does not matter) direction in body axes,
/// `r = R(q)^T (cos(n t) r0 + sin(n t) (k x r0))` with `k` the unit orbit normal and `r0` the
/// radial direction at `t = 0`, both in space axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GravityGradient {
    /// The inertia tensor in the axes the torque is evaluated in (diagonal in principal axes).
    inertia: Matrix3<f64>,
    mean_motion: f64,
    radial0: Vector3<f64>,
    along0: Vector3<f64>,
}

impl GravityGradient {
    /// `moments`: principal moments (the same ones the body is integrated with);
    /// `mean_motion`: `n = sqrt(mu / a^3)` (finite, any sign: negative reverses the orbit);
    /// `orbit_normal` and `radial0` in space axes: non-zero and not parallel; `radial0` is
    /// projected onto the orbit plane and both are normalised.
    pub fn new(
        moments: Vector3<f64>,
        mean_motion: f64,
        orbit_normal: Vector3<f64>,
        radial0: Vector3<f64>,
    ) -> Result<Self> {
        for i in 0..3 {
            positive(&format!("moments[{i}]"), moments[i])?;
        }
        finite("mean_motion", mean_motion)?;
        let k = unit_vector("orbit_normal", &orbit_normal)?;
        finite_vector("radial0", &radial0)?;
        // Its direction only (1e-300 and 1e300 are directions too).
        let (radial, _) = of_size_one(&radial0);
        let r_norm = radial.norm();
        let in_plane = radial - k * k.dot(&radial);
        let p_norm = in_plane.norm();
        if !(r_norm > 0.0 && p_norm > 1e-8 * r_norm) {
            return Err(Error::InvalidArgument {
                name: "radial0".into(),
                reason: format!(
                    "expected a non-zero vector not parallel to `orbit_normal` {orbit_normal:?}, \
                     got {radial0:?}."
                ),
            });
        }
        let radial0 = in_plane / p_norm;
        Ok(Self {
            inertia: Matrix3::from_diagonal(&moments),
            mean_motion,
            radial0,
            along0: k.cross(&radial0),
        })
    }

    /// The unit radial direction in space axes at time `t`.
    #[must_use]
    pub fn radial_space(&self, t: f64) -> Vector3<f64> {
        let (s, c) = (self.mean_motion * t).sin_cos();
        self.radial0 * c + self.along0 * s
    }
}

impl Torque for GravityGradient {
    fn torque_body(
        &self,
        t: f64,
        _omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        let r = orientation.inverse_transform_vector(&self.radial_space(t));
        let n2 = self.mean_motion * self.mean_motion;
        (3.0 * n2) * r.cross(&(self.inertia * r))
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}

/// A torque active only on the half-open window `[start, end)` of time, zero elsewhere.
///
/// `start` and `end` are reported by [`Torque::discontinuities`], so the driver ends a step at
/// each and no step straddles a switch. Within a step, [`Torque::try_torque_body_in`] decides
/// on or off once for the step's segment (at its midpoint) and evaluates the inner torque at
/// each stage time, even a stage time past a window end (a step ending at `start` is off
/// throughout, a step starting there on throughout): each step integrates the smooth inner
/// torque, or none, and every method keeps its order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window<T> {
    inner: T,
    start: f64,
    end: f64,
}

impl<T: Torque> Window<T> {
    /// `inner` active on `[start, end)`; `start <= end`, neither NaN (infinite bounds allowed).
    pub fn new(inner: T, start: f64, end: f64) -> Result<Self> {
        if start.is_nan() || end.is_nan() || start > end {
            return Err(Error::InvalidArgument {
                name: "start, end".into(),
                reason: format!(
                    "expected start <= end, neither NaN, got start = {start}, end = {end}."
                ),
            });
        }
        Ok(Self { inner, start, end })
    }

    fn active(&self, t: f64) -> bool {
        self.start <= t && t < self.end
    }
}

impl<T: Torque> Torque for Window<T> {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        if self.active(t) {
            self.inner.torque_body(t, omega, orientation)
        } else {
            Vector3::zeros()
        }
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        if self.active(t) {
            self.inner.try_torque_body(t, omega, orientation)
        } else {
            Ok(Vector3::zeros())
        }
    }
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        if self.active(segment.midpoint()) {
            self.inner
                .try_torque_body_in(segment, t, omega, orientation)
        } else {
            Ok(Vector3::zeros())
        }
    }
    fn depends_on_orientation(&self) -> bool {
        self.inner.depends_on_orientation()
    }
    fn depends_on_omega(&self) -> bool {
        self.inner.depends_on_omega()
    }
    fn discontinuities(&self) -> Vec<f64> {
        let mut times = self.inner.discontinuities();
        times.retain(|&t| self.active(t));
        times.extend([self.start, self.end].into_iter().filter(|t| t.is_finite()));
        times
    }
}

/// The sum of several torques.
#[derive(Default)]
pub struct Sum {
    terms: Vec<Box<dyn Torque + Send>>,
}

impl Sum {
    /// An empty sum (zero torque).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a term.
    #[must_use]
    pub fn with(mut self, term: impl Torque + Send + 'static) -> Self {
        self.terms.push(Box::new(term));
        self
    }

    /// Adds a boxed term.
    pub fn push(&mut self, term: Box<dyn Torque + Send>) {
        self.terms.push(term);
    }

    /// The number of terms.
    #[must_use]
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// Whether there is no term.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }
}

impl Torque for Sum {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        self.terms
            .iter()
            .map(|term| term.torque_body(t, omega, orientation))
            .sum()
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let mut total = Vector3::zeros();
        for term in &self.terms {
            total += term.try_torque_body(t, omega, orientation)?;
        }
        Ok(total)
    }
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let mut total = Vector3::zeros();
        for term in &self.terms {
            total += term.try_torque_body_in(segment, t, omega, orientation)?;
        }
        Ok(total)
    }
    fn depends_on_orientation(&self) -> bool {
        self.terms.iter().any(|term| term.depends_on_orientation())
    }
    fn depends_on_omega(&self) -> bool {
        self.terms.iter().any(|term| term.depends_on_omega())
    }
    fn discontinuities(&self) -> Vec<f64> {
        self.terms
            .iter()
            .flat_map(|term| term.discontinuities())
            .collect()
    }
}

/// A torque given by a closure `f(t, omega, orientation) -> Result<tau_body>` (body axes).
///
/// An `Err` returned by the closure stops the integration, which returns that error. A binding
/// that calls into another language keeps the foreign exception aside (e.g. in a
/// `Mutex<Option<..>>` captured by the closure), returns any `Err` here, and raises the kept
/// exception when the integration returns. The infallible [`Torque::torque_body`] of this type
/// returns NaN components on error; integrators never call it.
pub struct Function<F> {
    f: F,
    orientation: bool,
    omega: bool,
    breaks: Vec<f64>,
}

impl<F> Function<F>
where
    F: Fn(f64, &Vector3<f64>, &UnitQuaternion<f64>) -> Result<Vector3<f64>> + Sync,
{
    /// A closure torque, assumed to depend on both the orientation and the angular velocity.
    pub fn new(f: F) -> Self {
        Self {
            f,
            orientation: true,
            omega: true,
            breaks: Vec::new(),
        }
    }

    /// A closure torque with declared dependencies (a wrong `false` gives wrong results).
    pub fn with_dependencies(f: F, depends_on_orientation: bool, depends_on_omega: bool) -> Self {
        Self {
            f,
            orientation: depends_on_orientation,
            omega: depends_on_omega,
            breaks: Vec::new(),
        }
    }

    /// Declares the times at which the closure's torque jumps (see
    /// [`Torque::discontinuities`]).
    ///
    /// Within a step, the closure is then asked only for times inside the step's piece between
    /// two declared times: a stage time at or beyond one is moved just inside (by one ulp), so a
    /// step ending at a declared time sees the closure's torque from before it, whichever side
    /// the closure gives the time itself. A closure cannot be continued smoothly past its
    /// piece: the stages of the order-4 and order-6 splittings that reach beyond a declared time
    /// (their sub-steps go backwards and forwards) see the value at the end of the piece, which
    /// costs those two methods some order in the steps next to it. A smooth closure switched
    /// on and off keeps every order as the inner torque of a [`Window`].
    #[must_use]
    pub fn with_discontinuities(mut self, times: Vec<f64>) -> Self {
        self.breaks = times;
        self
    }
}

impl<F> Torque for Function<F>
where
    F: Fn(f64, &Vector3<f64>, &UnitQuaternion<f64>) -> Result<Vector3<f64>> + Sync,
{
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        (self.f)(t, omega, orientation).unwrap_or_else(|_| Vector3::repeat(f64::NAN))
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let tau = (self.f)(t, omega, orientation)?;
        for i in 0..3 {
            if !tau[i].is_finite() {
                return Err(Error::NonFinite {
                    name: format!("torque[{i}] at t = {t}"),
                    value: tau[i],
                });
            }
        }
        Ok(tau)
    }
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        if self.breaks.is_empty() {
            return self.try_torque_body(t, omega, orientation);
        }
        // The piece (lo, hi) of the declared times that holds the segment.
        let mid = segment.midpoint();
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for &b in &self.breaks {
            if b <= mid {
                lo = lo.max(b);
            } else if b > mid {
                hi = hi.min(b);
            }
        }
        let inside = t.max(lo.next_up()).min(hi.next_down());
        self.try_torque_body(inside, omega, orientation)
    }
    fn depends_on_orientation(&self) -> bool {
        self.orientation
    }
    fn depends_on_omega(&self) -> bool {
        self.omega
    }
    fn discontinuities(&self) -> Vec<f64> {
        self.breaks.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on_at(torque: &dyn Torque, segment: Segment, t: f64) -> f64 {
        let w = Vector3::zeros();
        torque
            .try_torque_body_in(&segment, t, &w, &UnitQuaternion::identity())
            .unwrap()[2]
    }

    /// A switched torque is decided once for the segment, through every wrapper; the inner
    /// torque is evaluated at the stage time, even outside the segment.
    #[test]
    fn switched_torques_take_the_state_of_their_segment() {
        let ramp = Function::with_dependencies(
            |t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| Ok(Vector3::new(0.0, 0.0, t)),
            false,
            false,
        );
        let window = Window::new(ramp, 1.0, 2.0).unwrap();
        let boxed: Box<dyn Torque + Send> =
            Box::new(Window::new(BodyFixed::new(Vector3::z()).unwrap(), 1.0, 2.0).unwrap());
        let sum = Sum::new()
            .with(Window::new(BodyFixed::new(Vector3::z()).unwrap(), 1.0, 2.0).unwrap())
            .with(
                Window::new(
                    Window::new(BodyFixed::new(Vector3::z() * 10.0).unwrap(), 0.0, 1.5).unwrap(),
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                )
                .unwrap(),
            );
        let before = Segment::new(0.5, 1.0);
        let inside = Segment::new(1.0, 1.5);
        let after = Segment::new(1.5, 2.0);
        // Stage times at and beyond the ends of the segment.
        for t in [0.4, 1.0, 1.6] {
            assert_eq!(on_at(&window, before, t), 0.0);
            assert_eq!(on_at(&window, inside, t), t);
            assert_eq!(on_at(&&window, inside, t), t);
            assert_eq!(on_at(&boxed, before, t), 0.0);
            assert_eq!(on_at(&boxed, inside, t), 1.0);
            assert_eq!(on_at(&sum, before, t), 10.0);
            assert_eq!(on_at(&sum, inside, t), 11.0);
            assert_eq!(on_at(&sum, after, t), 1.0);
        }
        // The plain evaluation keeps the half-open window.
        let w = Vector3::zeros();
        let q = UnitQuaternion::identity();
        assert_eq!(window.try_torque_body(1.0, &w, &q).unwrap()[2], 1.0);
        assert_eq!(window.try_torque_body(2.0, &w, &q).unwrap()[2], 0.0);
    }

    /// A closure with declared discontinuities is asked only about times inside the piece
    /// holding the segment (moved in by one ulp), whichever side it gives the switch itself.
    #[test]
    fn closures_are_asked_only_inside_their_piece() {
        let closure = Function::new(|t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            Ok(Vector3::new(0.0, 0.0, t))
        })
        .with_discontinuities(vec![2.0, 1.0]);
        let inside = Segment::new(1.0, 1.5);
        assert_eq!(on_at(&closure, inside, 1.25), 1.25);
        assert_eq!(on_at(&closure, inside, 0.5), 1.0f64.next_up());
        assert_eq!(on_at(&closure, inside, 2.5), 2.0f64.next_down());
        assert_eq!(
            on_at(&closure, Segment::new(2.0, 3.0), 1.0),
            2.0f64.next_up()
        );
        assert_eq!(
            on_at(&closure, Segment::new(0.0, 1.0), 1.0),
            1.0f64.next_down()
        );
        // Without declared discontinuities, the stage time as it is.
        let smooth = Function::new(|t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            Ok(Vector3::new(0.0, 0.0, t))
        });
        assert_eq!(on_at(&smooth, inside, 2.5), 2.5);
    }
}

// ---------------------------------------------------------------------------------------------
// The models as data (what a caller such as a binding hands to `simulation::simulate`).
// ---------------------------------------------------------------------------------------------

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

/// A torque model's named fields as a front end holds them (a Python object, a parsed file):
/// what [`TorqueSpec::from_fields`] reads. `E` is the front end's error type.
pub trait Fields {
    /// The front end's error.
    type Error;
    /// A core error as the front end's.
    fn error(error: Error) -> Self::Error;
    /// The number in field `name` (`None` when it holds none).
    fn number(&self, name: &str) -> std::result::Result<Option<f64>, Self::Error>;
    /// The vector (x, y, z) in field `name` (`None` when it holds none).
    fn vector(&self, name: &str) -> std::result::Result<Option<Vector3<f64>>, Self::Error>;
    /// The model in field `name`.
    fn model(&self, name: &str) -> std::result::Result<TorqueSpec, Self::Error>;
    /// The models in the list in field `name`.
    fn models(&self, name: &str) -> std::result::Result<Vec<TorqueSpec>, Self::Error>;
}

impl TorqueSpec {
    /// The model of kind `kind` (its name: `"BodyFixed"`, `"SpaceFixed"`, `"Gravity"`,
    /// `"GravityGradient"`, `"Window"`, `"Sum"`) from its fields, named as in the variants.
    /// A [`TorqueSpec::Function`] holds a closure, which a front end builds itself. Adding a
    /// model is its type above, its variant, and its arm here, in `check` and in `build`.
    pub fn from_fields<F: Fields>(kind: &str, fields: &F) -> std::result::Result<Self, F::Error> {
        let required = |name: &str, value: Option<Vector3<f64>>| {
            value.ok_or_else(|| F::error(missing(kind, name)))
        };
        let number = |name: &str| {
            fields
                .number(name)?
                .ok_or_else(|| F::error(missing(kind, name)))
        };
        Ok(match kind {
            "BodyFixed" => TorqueSpec::BodyFixed(required("torque", fields.vector("torque")?)?),
            "SpaceFixed" => TorqueSpec::SpaceFixed(required("torque", fields.vector("torque")?)?),
            "Gravity" => TorqueSpec::Gravity {
                gravity: required("gravity", fields.vector("gravity")?)?,
                pivot: fields.vector("pivot")?,
                mass: fields.number("mass")?,
                center_of_mass: fields.vector("center_of_mass")?,
            },
            "GravityGradient" => TorqueSpec::GravityGradient {
                mean_motion: number("mean_motion")?,
                orbit_normal: required("orbit_normal", fields.vector("orbit_normal")?)?,
                radial0: required("radial0", fields.vector("radial0")?)?,
            },
            "Window" => TorqueSpec::Window {
                start: number("start")?,
                end: number("end")?,
                torque: Box::new(fields.model("torque")?),
            },
            "Sum" => TorqueSpec::Sum(fields.models("terms")?),
            other => {
                return Err(F::error(Error::InvalidArgument {
                    name: "torque".into(),
                    reason: format!(
                        "expected a torque model (BodyFixed, SpaceFixed, Gravity, \
                         GravityGradient, Window, Sum or Function), got kind {other:?}."
                    ),
                }))
            }
        })
    }

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
            TorqueSpec::Sum(terms) => {
                terms.iter().try_for_each(TorqueSpec::check)?;
                // One body, one pivot: the moments are taken about the first Gravity's, so a
                // second pivot made the sum depend on the order of its terms.
                let mut pivots = Vec::new();
                self.pivots(&mut pivots);
                match pivots.iter().find(|p| **p != pivots[0]) {
                    Some(other) => Err(Error::InvalidArgument {
                        name: "pivot".into(),
                        reason: format!(
                            "a sum of torques turns the body about one pivot, but its Gravity \
                             terms have pivots ({}, {}, {}) and ({}, {}, {}).",
                            Short(pivots[0].x),
                            Short(pivots[0].y),
                            Short(pivots[0].z),
                            Short(other.x),
                            Short(other.y),
                            Short(other.z)
                        ),
                    }),
                    None => Ok(()),
                }
            }
            other => other.build(&unit).map(|_| ()),
        }
    }

    /// The pivot of every [`TorqueSpec::Gravity`] in the torque, in order.
    fn pivots(&self, out: &mut Vec<Vector3<f64>>) {
        match self {
            TorqueSpec::Gravity { pivot, .. } => out.push(pivot.unwrap_or_else(Vector3::zeros)),
            TorqueSpec::Window { torque, .. } => torque.pivots(out),
            TorqueSpec::Sum(terms) => terms.iter().for_each(|t| t.pivots(out)),
            _ => {}
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
            } => Box::new(GravityGradient {
                inertia: body.inertia,
                ..GravityGradient::new(Vector3::repeat(1.0), *mean_motion, *orbit_normal, *radial0)?
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

/// The error for a field a model of `kind` needs and does not hold.
fn missing(kind: &str, name: &str) -> Error {
    Error::InvalidArgument {
        name: name.into(),
        reason: format!("a {kind} torque needs `{name}`."),
    }
}
