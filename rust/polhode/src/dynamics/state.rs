//! The state of a rotating body, its validated principal moments, and Euler's vector field.

use nalgebra::{UnitQuaternion, Vector3, Vector4};

use crate::error::{finite, positive, Error};
use crate::Result;

/// The state of a rigid body: angular velocity in body axes and orientation.
///
/// The orientation maps body to space, `x_space = R(orientation) x_body`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State {
    /// Angular velocity in body (principal) axes.
    pub omega: Vector3<f64>,
    /// Body-to-space rotation.
    pub orientation: UnitQuaternion<f64>,
}

impl State {
    /// A state from an angular velocity (body axes) and an orientation.
    #[must_use]
    pub fn new(omega: Vector3<f64>, orientation: UnitQuaternion<f64>) -> Self {
        Self { omega, orientation }
    }

    /// A state with the body axes aligned with the space axes (identity orientation).
    #[must_use]
    pub fn from_omega(omega: Vector3<f64>) -> Self {
        Self {
            omega,
            orientation: UnitQuaternion::identity(),
        }
    }

    /// Angular momentum in space axes, `L = R(q) I w`: constant without torque.
    #[must_use]
    pub fn angular_momentum_space(&self, moments: &Moments) -> Vector3<f64> {
        self.orientation * moments.angular_momentum(&self.omega)
    }

    /// Checks that every component is finite; `name` names the argument in the error.
    pub(crate) fn check_finite(&self, name: &str) -> Result<()> {
        // The names are formatted only on failure: this runs once per body of a batch.
        for i in 0..3 {
            if !self.omega[i].is_finite() {
                finite(&format!("{name}.omega[{i}]"), self.omega[i])?;
            }
        }
        for i in 0..4 {
            if !self.orientation.coords[i].is_finite() {
                finite(
                    &format!("{name}.orientation[{i}]"),
                    self.orientation.coords[i],
                )?;
            }
        }
        Ok(())
    }
}

/// Validated principal moments of inertia `(I1, I2, I3)`, in any order, all finite and `> 0`,
/// with the quantities the integrators need precomputed.
///
/// Euler's equations in principal axes (Landau-Lifshitz par. 36),
/// `I1 w1' = (I2 - I3) w2 w3 + tau1` and cyclic, are stored as
/// `w' = c * (w2 w3, w3 w1, w1 w2) + tau / I` with
/// `c = ((I2 - I3)/I1, (I3 - I1)/I2, (I1 - I2)/I3)`;
/// the differences are formed from the moments directly, so equal moments give exact zeros.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Moments {
    moments: Vector3<f64>,
    inverse: Vector3<f64>,
    euler: Vector3<f64>,
    /// Splitting order of the axes: outer, inner, middle (see `splitting`).
    pub(crate) split_axes: [usize; 3],
}

impl Moments {
    /// Validates the principal moments: each must be finite and strictly positive (the
    /// integrators need `I^-1`; a zero moment is a singular body).
    pub fn new(moments: Vector3<f64>) -> Result<Self> {
        // The names are formatted only on failure: this runs once per body of a batch.
        for i in 0..3 {
            if !(moments[i].is_finite() && moments[i] > 0.0) {
                positive(&format!("moments[{i}]"), moments[i])?;
            }
        }
        let [i1, i2, i3] = [moments[0], moments[1], moments[2]];
        let inverse = Vector3::new(1.0 / i1, 1.0 / i2, 1.0 / i3);
        for i in 0..3 {
            if !inverse[i].is_finite() {
                return Err(Error::InvalidArgument {
                    name: format!("moments[{i}]"),
                    reason: format!(
                        "the moment {:e} is too small for Euler's equations, which need its \
                         reciprocal: it overflows double precision below about 5.6e-309 \
                         (express the moments in larger units).",
                        moments[i]
                    ),
                });
            }
        }
        let euler = Vector3::new((i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3);
        Ok(Self {
            moments,
            inverse,
            euler,
            split_axes: axis_order(&moments),
        })
    }

    /// The principal moments `(I1, I2, I3)`.
    #[must_use]
    pub fn moments(&self) -> &Vector3<f64> {
        &self.moments
    }

    /// `(1/I1, 1/I2, 1/I3)`.
    #[must_use]
    pub fn inverse(&self) -> &Vector3<f64> {
        &self.inverse
    }

    /// `((I2 - I3)/I1, (I3 - I1)/I2, (I1 - I2)/I3)`, the coefficients of Euler's equations.
    #[must_use]
    pub(crate) fn euler(&self) -> &Vector3<f64> {
        &self.euler
    }

    /// Body angular momentum `m = I w`.
    #[must_use]
    pub fn angular_momentum(&self, omega: &Vector3<f64>) -> Vector3<f64> {
        self.moments.component_mul(omega)
    }

    /// Kinetic energy `T = 1/2 sum I_i w_i^2`.
    #[must_use]
    pub fn kinetic_energy(&self, omega: &Vector3<f64>) -> f64 {
        0.5 * (self.moments[0] * omega[0] * omega[0]
            + self.moments[1] * omega[1] * omega[1]
            + self.moments[2] * omega[2] * omega[2])
    }

    /// The torque-free Euler vector field `w' = I^-1 ((I w) x w)`.
    #[must_use]
    #[inline]
    pub fn euler_rhs(&self, omega: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            self.euler[0] * omega[1] * omega[2],
            self.euler[1] * omega[2] * omega[0],
            self.euler[2] * omega[0] * omega[1],
        )
    }

    /// Euler's vector field with a torque in body axes, `w' = I^-1 ((I w) x w + tau)`.
    #[must_use]
    #[inline]
    pub fn euler_rhs_torqued(&self, omega: &Vector3<f64>, torque: &Vector3<f64>) -> Vector3<f64> {
        self.euler_rhs(omega) + self.inverse.component_mul(torque)
    }

    /// Jacobian of the torque-free field, `d(w')/dw`.
    #[inline]
    pub(crate) fn euler_jacobian(&self, w: &Vector3<f64>) -> [[f64; 3]; 3] {
        let c = &self.euler;
        [
            [0.0, c[0] * w[2], c[0] * w[1]],
            [c[1] * w[2], 0.0, c[1] * w[0]],
            [c[2] * w[1], c[2] * w[0], 0.0],
        ]
    }
}

/// `q' = 1/2 q (x) (0, w)` on raw quaternion coordinates `(x, y, z, w)`: half of
/// [`quaternion_rate2`] (exactly: a product by 1/2).
#[inline]
pub(crate) fn quaternion_rate(q: &Vector4<f64>, omega: &Vector3<f64>) -> Vector4<f64> {
    quaternion_rate2(q, omega) * 0.5
}

/// `2 q' = q (x) (0, w)` on raw quaternion coordinates `(x, y, z, w)`: the rate without its
/// factor 1/2, which an integrator folds into its step's coefficients (rk4: four products
/// fewer a stage).
#[inline]
pub(crate) fn quaternion_rate2(q: &Vector4<f64>, omega: &Vector3<f64>) -> Vector4<f64> {
    let (x, y, z, s) = (q[0], q[1], q[2], q[3]);
    let (a, b, c) = (omega[0], omega[1], omega[2]);
    // (v, s) (x) (w, 0) = (s w + v x w, -v.w)
    Vector4::new(
        s * a + y * c - z * b,
        s * b + z * a - x * c,
        s * c + x * b - y * a,
        -(x * a + y * b + z * c),
    )
}

/// The splitting's order of the axes `[outer, inner, middle]` (see `splitting`): the smallest
/// moment outermost, the largest in the middle (ties broken by index). A property of the
/// moments, kept with them ([`Moments`] holds it).
pub(crate) fn axis_order(moments: &Vector3<f64>) -> [usize; 3] {
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| moments[a].total_cmp(&moments[b]));
    [idx[0], idx[1], idx[2]]
}
