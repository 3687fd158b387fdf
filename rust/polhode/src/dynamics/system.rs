//! Euler's vector field with or without a torque, on `(w, q)` for the fixed-step methods and as a
//! first-order system `y' = f(t, y)` for `Dop853`: `N = 3` (angular velocity only) or `N = 7`
//! (angular velocity, then the orientation quaternion `(x, y, z, w)`).

use nalgebra::{Quaternion, SVector, UnitQuaternion, Vector3, Vector4};

use super::state::{quaternion_rate2, Moments, State};
use super::torque::{Segment, Torque};
use crate::Result;

/// The torque on the body, known from its type: none ([`NoTorque`]) or some `&T`. The
/// integrators match on [`Load::torque`]; for [`NoTorque`] the match is resolved at compile
/// time, so a torque-free run pays nothing for the torque's branch.
pub(crate) trait Load: Copy {
    /// The torque's type.
    type Torque: Torque + ?Sized;
    /// The torque, if any.
    fn torque(&self) -> Option<&Self::Torque>;
}

/// No torque: the free body.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NoTorque;

impl Load for NoTorque {
    type Torque = dyn Torque;
    #[inline(always)]
    fn torque(&self) -> Option<&Self::Torque> {
        None
    }
}

impl<T: Torque + ?Sized> Load for &T {
    type Torque = T;
    #[inline(always)]
    fn torque(&self) -> Option<&T> {
        Some(*self)
    }
}

/// Euler's vector field as `(w', 2 q')` at `(t, w, q)` under `load`, for a step lying in
/// `segment` (free of discontinuities of the torque; see [`Torque::try_torque_body_in`]): the
/// quaternion's rate without its factor 1/2 ([`quaternion_rate2`]). With `ORIENTATION` the
/// torque sees the orientation `q / |q|`; without, the identity (the caller ensures that the
/// torque does not depend on it) and `q'` is zero.
#[inline(always)]
pub(crate) fn rate<L: Load, const ORIENTATION: bool>(
    body: &Moments,
    load: L,
    segment: &Segment,
    t: f64,
    w: &Vector3<f64>,
    q: &Vector4<f64>,
) -> Result<(Vector3<f64>, Vector4<f64>)> {
    let dw = match load.torque() {
        None => body.euler_rhs(w),
        Some(torque) => {
            let tau = if ORIENTATION {
                let orientation = UnitQuaternion::new_unchecked(Quaternion::from(q / q.norm()));
                torque.try_torque_body_in(segment, t, w, &orientation)?
            } else {
                torque.try_torque_body_in(segment, t, w, &UnitQuaternion::identity())?
            };
            body.euler_rhs_torqued(w, &tau)
        }
    };
    let dq = if ORIENTATION {
        quaternion_rate2(q, w)
    } else {
        Vector4::zeros()
    };
    Ok((dw, dq))
}

/// A right-hand side `y' = f(t, y)`, evaluated for a step lying in `segment` (free of
/// discontinuities of the torque; see [`Torque::try_torque_body_in`]).
pub(crate) trait System<const N: usize> {
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>>;
}

/// Euler's equations under `load` as a first-order system ([`rate`]): of the angular velocity
/// alone (`N = 3`) or with the orientation (`N = 7`).
pub(crate) struct Field<'a, L> {
    pub body: &'a Moments,
    pub load: L,
}

impl<L: Load> System<3> for Field<'_, L> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, 3>) -> Result<SVector<f64, 3>> {
        let q = Vector4::new(0.0, 0.0, 0.0, 1.0);
        Ok(rate::<L, false>(self.body, self.load, segment, t, y, &q)?.0)
    }
}

impl<L: Load> System<7> for Field<'_, L> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, 7>) -> Result<SVector<f64, 7>> {
        let (w, q) = parts(y);
        let (dw, dq2) = rate::<L, true>(self.body, self.load, segment, t, &w, &q)?;
        // q' = (2 q') / 2: the bits of `quaternion_rate`.
        Ok(join(&dw, &(dq2 * 0.5)))
    }
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

/// The state returned by the single-step functions of the Runge-Kutta methods from the
/// 7-vector of a step: the quaternion rescaled to unit norm.
#[inline]
pub(crate) fn unit_state(mut y: SVector<f64, 7>) -> State {
    normalize7(&mut y);
    unpack(&y)
}

/// Rescales the quaternion part of `y` to unit norm; returns the factor applied.
#[inline]
fn normalize7(y: &mut SVector<f64, 7>) -> f64 {
    let n = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]).sqrt();
    let s = 1.0 / n;
    for i in 3..7 {
        y[i] *= s;
    }
    s
}

#[inline]
fn unpack(y: &SVector<f64, 7>) -> State {
    let (w, q) = parts(y);
    State {
        omega: w,
        orientation: UnitQuaternion::new_normalize(Quaternion::from(q)),
    }
}
