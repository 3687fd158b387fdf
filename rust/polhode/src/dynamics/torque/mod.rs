//! External torques, in body axes: the [`Torque`] trait, the [`Segment`] a step lies in, and
//! the models evaluated in Rust (re-exported here from `models`).

use nalgebra::{UnitQuaternion, Vector3};

use crate::error::finite;
use crate::{Error, Result};

mod models;

pub use models::*;

/// An interval of time `[start, end]` with no discontinuity of the torque inside, in which an
/// integration step lies (see [`Torque::try_torque_body_in`]).
///
/// The driver [`super::integrate`] ends every step at each of the torque's
/// [`Torque::discontinuities`], so each step lies in one segment between consecutive
/// discontinuities (or output times); the single-step functions take the step itself,
/// [`Segment::of_step`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// First time of the segment (may be `-inf`).
    pub start: f64,
    /// Last time of the segment, `>= start` (may be `+inf`).
    pub end: f64,
}

impl Segment {
    /// The segment between `a` and `b`, in either order.
    #[must_use]
    pub fn new(a: f64, b: f64) -> Self {
        if b < a {
            Self { start: b, end: a }
        } else {
            Self { start: a, end: b }
        }
    }

    /// The segment covered by one step from `t` over `h` (of either sign).
    #[must_use]
    pub fn of_step(t: f64, h: f64) -> Self {
        Self::new(t, t + h)
    }

    /// A time inside the segment, where a switched torque is in the state it has on the whole
    /// segment: the midpoint (`start` for an empty segment; a finite time beyond the finite end
    /// of a half-infinite one; 0 for the whole line).
    #[must_use]
    pub fn midpoint(&self) -> f64 {
        let (a, b) = (self.start, self.end);
        match (a.is_finite(), b.is_finite()) {
            _ if a == b => a,
            (true, true) => 0.5 * a + 0.5 * b,
            (true, false) => (a + a.abs().max(1.0)).min(f64::MAX),
            (false, true) => (b - b.abs().max(1.0)).max(-f64::MAX),
            (false, false) => 0.0,
        }
    }
}

/// An external torque about the centre of mass (or the fixed pivot), in body axes.
///
/// Integrators call [`Torque::try_torque_body_in`], which by default is
/// [`Torque::try_torque_body`]; a model that cannot fail implements only
/// [`Torque::torque_body`]. A torque that fails (for instance a Python callable that raised)
/// returns an error from `try_torque_body`, and the integration stops and returns that error.
///
/// A torque that switches (jumps, or a derivative jumps) at some times reports them in
/// [`Torque::discontinuities`] and overrides [`Torque::try_torque_body_in`] so that, within a
/// step, it stays in the state it has on the step's segment between two switches (see
/// [`Window`]).
pub trait Torque: Sync {
    /// The torque in body axes at time `t`, for the body angular velocity `omega` and the
    /// body-to-space `orientation`.
    fn torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64>;

    /// The fallible path the integrators use; by default `Ok(torque_body(..))`.
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        Ok(self.torque_body(t, omega, orientation))
    }

    /// The torque at the stage time `t` of a step that lies in `segment`, a segment with no
    /// discontinuity of the torque inside (the path every integrator uses); by default
    /// `try_torque_body(t, ..)`.
    ///
    /// A torque that switches at its [`Torque::discontinuities`] takes, whatever `t`, the state
    /// it has inside `segment` (e.g. at [`Segment::midpoint`]): a stage at the end of a step
    /// that ends where a window opens, or a stage of a composition of order 4 or 6 (whose
    /// sub-steps go backwards and forwards, to times outside the step), must not see the
    /// torque of the next segment, or the method loses its order. Its smooth part is still
    /// evaluated at `t`, so that each step integrates the smooth torque of its segment.
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        let _ = segment;
        self.try_torque_body(t, omega, orientation)
    }

    /// Whether the torque depends on the orientation. If not, the angular velocity can be
    /// integrated alone.
    fn depends_on_orientation(&self) -> bool {
        true
    }

    /// Whether the torque depends on the angular velocity. If not, a torque kick of the
    /// splitting method is explicit.
    fn depends_on_omega(&self) -> bool {
        true
    }

    /// Times at which the torque (or a derivative) jumps, e.g. the ends of a [`Window`]
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
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        (**self).torque_body(t, omega, orientation)
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        (**self).try_torque_body(t, omega, orientation)
    }
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        (**self).try_torque_body_in(segment, t, omega, orientation)
    }
    fn depends_on_orientation(&self) -> bool {
        (**self).depends_on_orientation()
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
        orientation: &UnitQuaternion<f64>,
    ) -> Vector3<f64> {
        (**self).torque_body(t, omega, orientation)
    }
    fn try_torque_body(
        &self,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        (**self).try_torque_body(t, omega, orientation)
    }
    fn try_torque_body_in(
        &self,
        segment: &Segment,
        t: f64,
        omega: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Result<Vector3<f64>> {
        (**self).try_torque_body_in(segment, t, omega, orientation)
    }
    fn depends_on_orientation(&self) -> bool {
        (**self).depends_on_orientation()
    }
    fn depends_on_omega(&self) -> bool {
        (**self).depends_on_omega()
    }
    fn discontinuities(&self) -> Vec<f64> {
        (**self).discontinuities()
    }
}

/// Checks that the components of `v` are finite; `name` names the vector in the error.
fn finite_vector(name: &str, v: &Vector3<f64>) -> Result<()> {
    for i in 0..3 {
        finite(&format!("{name}[{i}]"), v[i])?;
    }
    Ok(())
}

/// `v / |v|` for a direction given as a finite, non-zero vector of any size (an error naming
/// `name` otherwise). It is scaled by a power of two first, exactly: the same bits as `v / |v|`
/// where that neither under- nor overflows, and a direction of 1e-300 or 1e300 is still one
/// (its norm underflowed to 0 or overflowed, and it was refused as "non-zero vector").
pub(crate) fn unit_vector(name: &str, v: &Vector3<f64>) -> Result<Vector3<f64>> {
    finite_vector(name, v)?;
    let largest = v.amax();
    if largest == 0.0 {
        return Err(Error::InvalidArgument {
            name: name.into(),
            reason: format!("expected a non-zero vector, got {:?}.", v.as_slice()),
        });
    }
    let (scaled, _) = of_size_one(v);
    Ok(scaled / scaled.norm())
}

/// `v 2^-k` and `k`, the power of two that brings its largest entry to [0.5, 1) (exactly, but
/// for entries far below the largest); zero stays zero (`k = 0`).
pub(crate) fn of_size_one(v: &Vector3<f64>) -> (Vector3<f64>, i32) {
    let k = crate::eigen::exponent(v.amax());
    (v.map(|x| crate::eigen::ldexp(x, -k)), k)
}

/// `|v|` without overflow or underflow of its squares: the bits of the plain norm wherever
/// those neither under- nor overflow (a rate of 2e155 has a norm; its square overflows).
pub(crate) fn norm_of_any_size(v: &Vector3<f64>) -> f64 {
    let (scaled, k) = of_size_one(v);
    crate::eigen::ldexp(scaled.norm(), k)
}

/// Errors if `torque` depends on the orientation (for the angular-velocity-only integrators).
pub(crate) fn require_orientation_free<T: Torque + ?Sized>(torque: &T) -> Result<()> {
    if torque.depends_on_orientation() {
        Err(Error::InvalidArgument {
            name: "torque".into(),
            reason: "the torque depends on the orientation: integrate the orientation too.".into(),
        })
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_midpoint_is_inside() {
        assert_eq!(
            Segment::new(3.0, 1.0),
            Segment {
                start: 1.0,
                end: 3.0
            }
        );
        assert_eq!(Segment::of_step(2.0, -0.5).midpoint(), 1.75);
        assert_eq!(Segment::new(2.0, 2.0).midpoint(), 2.0);
        for (a, b) in [
            (5.0, f64::INFINITY),
            (-5.0, f64::INFINITY),
            (f64::MAX, f64::INFINITY),
            (f64::NEG_INFINITY, 5.0),
            (f64::NEG_INFINITY, -f64::MAX),
            (f64::NEG_INFINITY, f64::INFINITY),
            (-f64::MAX, f64::MAX),
        ] {
            let m = Segment::new(a, b).midpoint();
            assert!(m.is_finite() && a <= m && m <= b, "{a} {b}: {m}");
            let extreme = (m == a && a == f64::MAX) || (m == b && b == -f64::MAX);
            assert!((a < m && m < b) || extreme, "{a} {b}: {m}");
        }
    }
}
