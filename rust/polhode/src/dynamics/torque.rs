//! External torques, in body axes, as a trait, with the models evaluated in Rust.

use nalgebra::{UnitQuaternion, Vector3};

use crate::error::{finite, positive};
use crate::{Error, Result};

/// An external torque about the centre of mass (or the fixed pivot), in body axes.
///
/// Integrators call [`Torque::try_torque_body`]; a model that cannot fail implements only
/// [`Torque::torque_body`]. A torque that fails (for instance a Python callable that raised)
/// returns an error from `try_torque_body`, and the integration stops and returns that error.
pub trait Torque: Sync {
    /// The torque in body axes at time `t`, for the body angular velocity `omega` and the
    /// body-to-space `attitude`.
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64>;

    /// The fallible path the integrators use; by default `Ok(torque_body(..))`.
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        Ok(self.torque_body(t, omega, attitude))
    }

    /// Whether the torque depends on the attitude. If not, the angular velocity can be
    /// integrated alone.
    fn depends_on_attitude(&self) -> bool {
        true
    }

    /// Whether the torque depends on the angular velocity. If not, a torque kick of the
    /// splitting method is explicit.
    fn depends_on_omega(&self) -> bool {
        true
    }

    /// Times at which the torque (or a derivative) jumps, e.g. the ends of a [`Windowed`]
    /// torque. The driver ends a step at each of them (and restarts `Dop853` there), so that
    /// no step straddles a switch and the methods keep their order.
    fn discontinuities(&self) -> Vec<f64> {
        Vec::new()
    }
}

impl<T: Torque + ?Sized> Torque for &T {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        (**self).torque_body(t, omega, attitude)
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        (**self).try_torque_body(t, omega, attitude)
    }
    fn depends_on_attitude(&self) -> bool {
        (**self).depends_on_attitude()
    }
    fn depends_on_omega(&self) -> bool {
        (**self).depends_on_omega()
    }
    fn discontinuities(&self) -> Vec<f64> {
        (**self).discontinuities()
    }
}

impl<T: Torque + ?Sized> Torque for Box<T> {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        (**self).torque_body(t, omega, attitude)
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        (**self).try_torque_body(t, omega, attitude)
    }
    fn depends_on_attitude(&self) -> bool {
        (**self).depends_on_attitude()
    }
    fn depends_on_omega(&self) -> bool {
        (**self).depends_on_omega()
    }
    fn discontinuities(&self) -> Vec<f64> {
        (**self).discontinuities()
    }
}

fn finite_vector(name: &str, v: &Vector3<f64>) -> Result<()> {
    for i in 0..3 {
        finite(&format!("{name}[{i}]"), v[i])?;
    }
    Ok(())
}

/// A torque constant in body axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyConstantTorque {
    torque: Vector3<f64>,
}

impl BodyConstantTorque {
    /// A constant torque `torque` in body axes (finite).
    pub fn new(torque: Vector3<f64>) -> Result<Self> {
        finite_vector("torque", &torque)?;
        Ok(Self { torque })
    }
}

impl Torque for BodyConstantTorque {
    fn torque_body(
        &self,
        _t: f64,
        _omega: &Vector3<f64>,
        _attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        self.torque
    }
    fn depends_on_attitude(&self) -> bool {
        false
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}

/// A torque constant in space axes: `tau_body = R(q)^T tau_space`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpaceConstantTorque {
    torque_space: Vector3<f64>,
}

impl SpaceConstantTorque {
    /// A constant torque `torque_space` in space axes (finite).
    pub fn new(torque_space: Vector3<f64>) -> Result<Self> {
        finite_vector("torque_space", &torque_space)?;
        Ok(Self { torque_space })
    }
}

impl Torque for SpaceConstantTorque {
    fn torque_body(
        &self,
        _t: f64,
        _omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        attitude.inverse_transform_vector(&self.torque_space)
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
pub struct PivotGravity {
    center_of_mass: Vector3<f64>,
    weight: Vector3<f64>,
}

impl PivotGravity {
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
    pub fn potential_energy(&self, attitude: &UnitQuaternion<f64>) -> f64 {
        -self.weight.dot(&(attitude * self.center_of_mass))
    }
}

impl Torque for PivotGravity {
    fn torque_body(
        &self,
        _t: f64,
        _omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        self.center_of_mass
            .cross(&attitude.inverse_transform_vector(&self.weight))
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
    moments: Vector3<f64>,
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
        finite_vector("orbit_normal", &orbit_normal)?;
        finite_vector("radial0", &radial0)?;
        let k_norm = orbit_normal.norm();
        if !(k_norm > 0.0 && k_norm.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "orbit_normal".into(),
                reason: format!("expected a non-zero vector, got {orbit_normal:?}."),
            });
        }
        let k = orbit_normal / k_norm;
        let r_norm = radial0.norm();
        let in_plane = radial0 - k * k.dot(&radial0);
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
            moments,
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
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        let r = attitude.inverse_transform_vector(&self.radial_space(t));
        let n2 = self.mean_motion * self.mean_motion;
        (3.0 * n2) * r.cross(&self.moments.component_mul(&r))
    }
    fn depends_on_omega(&self) -> bool {
        false
    }
}

/// A torque active only on the half-open window `[start, end)` of time, zero elsewhere.
///
/// `start` and `end` are reported by [`Torque::discontinuities`], so the driver ends a step at
/// each and no step straddles a switch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Windowed<T> {
    inner: T,
    start: f64,
    end: f64,
}

impl<T: Torque> Windowed<T> {
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

impl<T: Torque> Torque for Windowed<T> {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        if self.active(t) {
            self.inner.torque_body(t, omega, attitude)
        } else {
            Vector3::zeros()
        }
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        if self.active(t) {
            self.inner.try_torque_body(t, omega, attitude)
        } else {
            Ok(Vector3::zeros())
        }
    }
    fn depends_on_attitude(&self) -> bool {
        self.inner.depends_on_attitude()
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
pub struct TorqueSum {
    terms: Vec<Box<dyn Torque + Send>>,
}

impl TorqueSum {
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

impl Torque for TorqueSum {
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        self.terms
            .iter()
            .map(|term| term.torque_body(t, omega, attitude))
            .sum()
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let mut total = Vector3::zeros();
        for term in &self.terms {
            total += term.try_torque_body(t, omega, attitude)?;
        }
        Ok(total)
    }
    fn depends_on_attitude(&self) -> bool {
        self.terms.iter().any(|term| term.depends_on_attitude())
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

/// A torque given by a closure `f(t, omega, attitude) -> Result<tau_body>` (body axes).
///
/// An `Err` returned by the closure stops the integration, which returns that error. A binding
/// that calls into another language keeps the foreign exception aside (e.g. in a
/// `Mutex<Option<..>>` captured by the closure), returns any `Err` here, and raises the kept
/// exception when the integration returns. The infallible [`Torque::torque_body`] of this type
/// returns NaN components on error; integrators never call it.
pub struct FnTorque<F> {
    f: F,
    attitude: bool,
    omega: bool,
    breaks: Vec<f64>,
}

impl<F> FnTorque<F>
where
    F: Fn(f64, &Vector3<f64>, &UnitQuaternion<f64>) -> Result<Vector3<f64>> + Sync,
{
    /// A closure torque, assumed to depend on both the attitude and the angular velocity.
    pub fn new(f: F) -> Self {
        Self {
            f,
            attitude: true,
            omega: true,
            breaks: Vec::new(),
        }
    }

    /// A closure torque with declared dependencies (a wrong `false` gives wrong results).
    pub fn with_dependencies(f: F, depends_on_attitude: bool, depends_on_omega: bool) -> Self {
        Self {
            f,
            attitude: depends_on_attitude,
            omega: depends_on_omega,
            breaks: Vec::new(),
        }
    }

    /// Declares the times at which the closure's torque jumps (see
    /// [`Torque::discontinuities`]).
    #[must_use]
    pub fn with_discontinuities(mut self, times: Vec<f64>) -> Self {
        self.breaks = times;
        self
    }
}

impl<F> Torque for FnTorque<F>
where
    F: Fn(f64, &Vector3<f64>, &UnitQuaternion<f64>) -> Result<Vector3<f64>> + Sync,
{
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        (self.f)(t, omega, attitude).unwrap_or_else(|_| Vector3::repeat(f64::NAN))
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        attitude: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let tau = (self.f)(t, omega, attitude)?;
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
    fn depends_on_attitude(&self) -> bool {
        self.attitude
    }
    fn depends_on_omega(&self) -> bool {
        self.omega
    }
    fn discontinuities(&self) -> Vec<f64> {
        self.breaks.clone()
    }
}

/// Errors if `torque` depends on the attitude (for the angular-velocity-only integrators).
pub(crate) fn require_attitude_free<T: Torque + ?Sized>(torque: &T) -> Result<()> {
    if torque.depends_on_attitude() {
        Err(Error::InvalidArgument {
            name: "torque".into(),
            reason: "the torque depends on the attitude: integrate the attitude too.".into(),
        })
    } else {
        Ok(())
    }
}
