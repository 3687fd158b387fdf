//! Euler's equations as first-order systems for the Runge-Kutta methods: `N = 3` (angular
//! velocity only) or `N = 7` (angular velocity, then the orientation quaternion `(x, y, z, w)`).

use nalgebra::{Quaternion, SVector, UnitQuaternion, Vector3, Vector4};

use super::state::{quaternion_rate, Moments, State};
use super::torque::{Segment, Torque};
use crate::Result;

/// A right-hand side `y' = f(t, y)`, evaluated for a step lying in `segment` (free of
/// discontinuities of the torque; see [`Torque::try_torque_body_in`]).
pub(crate) trait System<const N: usize> {
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>>;
}

/// Splits a 7-vector into angular velocity and raw quaternion.
#[inline]
pub(crate) fn parts(y: &SVector<f64, 7>) -> (Vector3<f64>, Vector4<f64>) {
    (
        Vector3::new(y[0], y[1], y[2]),
        Vector4::new(y[3], y[4], y[5], y[6]),
    )
}

#[inline]
pub(crate) fn join(w: &Vector3<f64>, q: &Vector4<f64>) -> SVector<f64, 7> {
    SVector::<f64, 7>::from([w[0], w[1], w[2], q[0], q[1], q[2], q[3]])
}

#[inline]
pub(crate) fn pack(state: &State) -> SVector<f64, 7> {
    join(&state.omega, &state.orientation.coords)
}

/// Rescales the quaternion part of `y` to unit norm; returns the factor applied.
#[inline]
pub(crate) fn normalize7(y: &mut SVector<f64, 7>) -> f64 {
    let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
    let s = 1.0 / n;
    for i in 3..7 {
        y[i] *= s;
    }
    s
}

#[inline]
pub(crate) fn unpack(y: &SVector<f64, 7>) -> State {
    let (w, q) = parts(y);
    State {
        omega: w,
        orientation: UnitQuaternion::new_normalize(Quaternion::from(q)),
    }
}

/// The torque-free body.
pub(crate) struct Free<'a> {
    pub body: &'a Moments,
}

impl System<3> for Free<'_> {
    #[inline]
    fn rhs(&self, _: &Segment, _t: f64, y: &SVector<f64, 3>) -> Result<SVector<f64, 3>> {
        Ok(self.body.euler_rhs(y))
    }
}

impl System<7> for Free<'_> {
    #[inline]
    fn rhs(&self, _: &Segment, _t: f64, y: &SVector<f64, 7>) -> Result<SVector<f64, 7>> {
        let (w, q) = parts(y);
        Ok(join(&self.body.euler_rhs(&w), &quaternion_rate(&q, &w)))
    }
}

/// The body under a torque. With `N = 3` the torque sees the identity orientation (the caller
/// ensures that it does not depend on the orientation).
pub(crate) struct Torqued<'a, T: ?Sized> {
    pub body: &'a Moments,
    pub torque: &'a T,
}

impl<T: Torque + ?Sized> System<3> for Torqued<'_, T> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, 3>) -> Result<SVector<f64, 3>> {
        let tau = self
            .torque
            .try_torque_body_in(segment, t, y, &UnitQuaternion::identity())?;
        Ok(self.body.euler_rhs_torqued(y, &tau))
    }
}

impl<T: Torque + ?Sized> System<7> for Torqued<'_, T> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, 7>) -> Result<SVector<f64, 7>> {
        let (w, q) = parts(y);
        let orientation = UnitQuaternion::new_unchecked(Quaternion::from(q / q.norm()));
        let tau = self
            .torque
            .try_torque_body_in(segment, t, &w, &orientation)?;
        Ok(join(
            &self.body.euler_rhs_torqued(&w, &tau),
            &quaternion_rate(&q, &w),
        ))
    }
}
