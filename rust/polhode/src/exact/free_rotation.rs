//! The torque-free motion of a rigid body in closed form.
//!
//! Euler's equations in principal axes, `I1 w1' + (I3 - I2) w2 w3 = 0` and cyclic, with the
//! orientation `q' = q (x) (0, w) / 2` (body to space). For body angular momentum `m = I w`,
//! `G = |m|`, `2T = sum m_i^2 / I_i` and `Delta_j = G^2 - 2 T I_j` (computed without
//! cancellation, in double-double):
//!
//! - the polhode circulates about the axis `p` of the largest moment if `Delta_2 > 0` and of
//!   the smallest if `Delta_2 < 0`. In a right-handed *canonical* frame `(1, 2, 3) = (a, mid, p)`
//!   (one axis sign flipped when the relabelling is an odd permutation), with moments monotone
//!   either way, `m1 = B1 cn u`, `m2 = s2 B2 sn u`, `m3 = s3 B3 dn u`, `u = lambda t + u0`,
//!   `lambda > 0`, where `B1^2 = I1 (-Delta_3)/(I3 - I1)`, `B2^2 = I2 (-Delta_3)/(I3 - I2)`,
//!   `B3^2 = I3 Delta_1 / (I3 - I1)`, `lambda^2 = Delta_1 (I3 - I2) / (I1 I2 I3)`,
//!   `m = (I2 - I1)(-Delta_3) / ((I3 - I2) Delta_1)`, `mc = Delta_2 (I3 - I1) / (Delta_1 (I3 - I2))`,
//!   `s3 = sign m3(0)` and `s2 = s3 sign(I3 - I2)` (substituting into Euler's equations, which
//!   fixes every sign including the sense of `u`);
//! - on the separatrix `Delta_2 = 0` (canonical frame with `p` the largest moment):
//!   `m1 = s1 B1 sech u`, `m2 = s2 G tanh u`, `m3 = s3 B3 sech u` with independent
//!   `s1 = sign m1(0)`, `s3 = sign m3(0)` and `s2 = s1 s3`;
//! - orientation: z-x-z Euler angles with space z along `L` and body polar axis `z` = canonical
//!   axis 1 or 3 (neither is ever reached by `m` off the steady states), `cos theta = m_z / G`,
//!   `tan psi = m_x / m_y`, `phi' = G (m_x^2/I_x + m_y^2/I_y)/(m_x^2 + m_y^2)`. With `x` the
//!   other of the two (3 or 1) and `2` the intermediate axis,
//!   `phi' = G/I_x + G (1/I2 - 1/I_x) m2^2 / (m2^2 + m_x^2)`, and the polar axis is chosen so
//!   that `|1/I2 - 1/I_x|` is the smaller: the varying part is then the smallest possible and
//!   cancels by at most a factor 2. With `m2^2/(m2^2 + m_x^2) = (B2/Bx)^2 sn^2 u/(1 + nu sn^2 u)`,
//!   polar 1: `Bx = B3, nu = B1^2/B3^2 = I1 (-Delta_3)/(I3 Delta_1)`; polar 3: `Bx = B1,
//!   nu = m B3^2/B1^2 = I3 (I2 - I1)/(I1 (I3 - I2))`. So `phi(t) = G t / I_x + C (J(u) - J(u0))`,
//!   `C = G (1/I2 - 1/I_x) (B2/Bx)^2 / lambda`,
//!   `J(u) = int_0^u sn^2/(1 + nu sn^2) = (s^3/3) R_J(c^2, d^2, 1, 1 + nu s^2)` (s, c, d = sn, cn,
//!   dn of u, DLMF 19.25.14), which gains `2 cel(k', 1 + nu, 0, 1)` per `2K` of `u`; on the
//!   separatrix `J(u) = (u - atan(sqrt(nu) tanh u)/sqrt(nu)) / (1 + nu)`. (Derived here and
//!   checked against the integration in `tests/reference_motion.py`; the textbook form
//!   `G t/I3 + c (Pi(am u; n | m) - Pi(am u0; n | m))`, `c = G (I3 - I1)/(I1 I3 lambda)`, is the
//!   same motion with polar axis `p`, but `Pi = F + n J` cancels for `n << -1`.)
//!
//! The phase `lambda t + u0`, the quarter period `K` and the per-period gains are carried in
//! double-double, so the only error that grows with `t` is the rounding of `t` itself.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use super::carlson::{carlson_rf, carlson_rj};
use super::dd::{cel, Dd};
use super::elliptic::{ellipk_dd, reduce_quarter, sncndn_quarter};
use crate::error::{finite, positive};
use crate::{Error, Result};

/// The kind of torque-free motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// Zero angular velocity.
    Rest,
    /// Three equal moments: steady rotation about the initial angular velocity.
    Spherical,
    /// Exactly two equal moments: `omega` precesses about the symmetry axis in the body at
    /// `Omega = w_s (I_s - I_t) / I_t`, the body precesses steadily about `L` in space.
    Symmetric {
        /// Index (into the caller's moments) of the symmetry axis, the one distinct moment.
        axis: usize,
    },
    /// Three distinct moments; the angular momentum circulates in the body about the axis of
    /// the smallest or the largest moment (index into the caller's moments); includes steady
    /// rotation about that axis.
    AboutAxis(usize),
    /// Three distinct moments, exactly on the separatrix `L^2 = 2 T I_mid` (not at rest on the
    /// intermediate axis): the motion tends to rotation about the intermediate axis.
    Separatrix,
    /// Steady rotation about the axis of the intermediate moment (unstable).
    SteadyIntermediate,
}

/// The torque-free motion of a rigid body, evaluated in closed form at any time: O(1) per
/// evaluation, no stepping.
#[derive(Debug, Clone)]
pub struct FreeRotation {
    moments: Vector3<f64>,
    omega0: Vector3<f64>,
    orientation0: UnitQuaternion<f64>,
    energy: f64,
    momentum: f64,
    regime: Regime,
    motion: Motion,
}

#[derive(Debug, Clone)]
enum Motion {
    /// Constant `omega` (rest, sphere, steady rotation about a principal axis):
    /// `q(t) = q0 (x) exp(omega t / 2)`.
    Steady {
        axis: Vector3<f64>,
        rate: Dd,
    },
    Symmetric(Symmetric),
    Elliptic(Box<Elliptic>),
    Separatrix(Box<Separatrix>),
}

/// `q(t) = q0 (x) exp(m0 t / (2 I_t)) (x) exp(-Omega t e_s / 2)`, `omega` turning about `e_s`
/// at `Omega`.
#[derive(Debug, Clone)]
struct Symmetric {
    axis: usize,
    /// `G / I_t`.
    nutation_rate: Dd,
    /// `m0 / G`.
    m_dir: Vector3<f64>,
    /// `Omega = w_s (I_s - I_t) / I_t`.
    body_rate: Dd,
}

/// The canonical frame: canonical axis `i` is `sign[i] * e_{index[i]}` of the body.
#[derive(Debug, Clone, Copy)]
struct Frame {
    index: [usize; 3],
    sign: [f64; 3],
}

impl Frame {
    /// A right-handed frame on the body axes `index`, the third one flipped if the permutation
    /// is odd.
    fn new(index: [usize; 3]) -> Frame {
        let even = matches!(index, [0, 1, 2] | [1, 2, 0] | [2, 0, 1]);
        Frame {
            index,
            sign: [1.0, 1.0, if even { 1.0 } else { -1.0 }],
        }
    }

    fn to_canonical(self, v: &Vector3<f64>) -> [f64; 3] {
        [0, 1, 2].map(|i| self.sign[i] * v[self.index[i]])
    }

    fn to_body(self, c: [f64; 3]) -> Vector3<f64> {
        let mut v = Vector3::zeros();
        for i in 0..3 {
            v[self.index[i]] = self.sign[i] * c[i];
        }
        v
    }

    /// The rotation whose columns are the frame's axes in body coordinates (frame to body).
    fn quaternion(self) -> UnitQuaternion<f64> {
        let mut m = Matrix3::zeros();
        for i in 0..3 {
            m[(self.index[i], i)] = self.sign[i];
        }
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
    }
}

/// Shared by the elliptic and separatrix motions: the frames, scales and the orientation at 0.
#[derive(Debug, Clone)]
struct Common {
    frame: Frame,
    /// Canonical moments, scaled by `moment_scale`.
    moments: [f64; 3],
    /// Amplitudes `B1, B2, B3`, scaled by `momentum_scale`.
    b: [f64; 3],
    /// `s1` (separatrix only), `s2`, `s3`.
    s: [f64; 3],
    /// Body angular velocity = scaled momentum / scaled moment * `rate_scale`.
    rate_scale: f64,
    /// `lambda` (unscaled, per unit time).
    lambda: Dd,
    u0: Dd,
    /// Euler frame: `true` if it is `(2, 3, 1)` of the canonical frame, else `(1, 2, 3)`.
    euler_cyclic: bool,
    /// `G / I_hi` (unscaled).
    base_rate: Dd,
    /// `C` of the module doc.
    coef: Dd,
    nu: f64,
    /// `nu` in double-double (it sets the precession per period).
    nu_dd: Dd,
    /// `J(u0)`.
    j0: Dd,
    /// `q0 (x) q_E (x) qz(-psi0) (x) qx(-theta0)`.
    q_l: UnitQuaternion<f64>,
    /// `q_E^-1`.
    q_e_inv: UnitQuaternion<f64>,
}

#[derive(Debug, Clone)]
struct Elliptic {
    c: Common,
    mc: f64,
    kp: f64,
    k: Dd,
    /// `J` over a half period `2K` of `u`: `2 cel(k', 1 + nu, 0, 1)`.
    j_half: Dd,
    /// `Jc(K) = int_0^K cn^2 / (1 + nu sn^2) = cel(k', 1 + nu, 1, 0)`.
    jc_quarter: Dd,
}

#[derive(Debug, Clone)]
struct Separatrix {
    c: Common,
}

/// An even power of two near `v > 0` (1 for 0 or non-finite).
fn pow2_near(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        let e = v.log2().floor().clamp(-1000.0, 1000.0) as i32;
        2f64.powi(e - e.rem_euclid(2))
    } else {
        1.0
    }
}

/// `x` reduced into `[-pi, pi]`, from a double-double angle.
fn wrap(x: Dd) -> f64 {
    let j = (x / Dd::TAU).round();
    (x - Dd::TAU * j.hi - Dd::TAU * j.lo).to_f64()
}

fn qz(angle: f64) -> UnitQuaternion<f64> {
    let (s, c) = (0.5 * angle).sin_cos();
    UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(c, 0.0, 0.0, s))
}

fn qx(angle: f64) -> UnitQuaternion<f64> {
    let (s, c) = (0.5 * angle).sin_cos();
    UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(c, s, 0.0, 0.0))
}

/// `exp(axis * angle / 2)` for a unit `axis`, the half angle given reduced.
fn q_axis(axis: &Vector3<f64>, half_angle: f64) -> UnitQuaternion<f64> {
    let (s, c) = half_angle.sin_cos();
    UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
        c,
        s * axis.x,
        s * axis.y,
        s * axis.z,
    ))
}

/// Euler angles `(theta, psi)` of `m` in the Euler frame (z-x-z, `m = G (sin theta sin psi,
/// sin theta cos psi, cos theta)`).
fn theta_psi(e: [f64; 3]) -> (f64, f64) {
    (e[0].hypot(e[1]).atan2(e[2]), e[0].atan2(e[1]))
}

/// `|v|` of a vector of doubles, in double-double.
fn norm_dd(v: &Vector3<f64>) -> Dd {
    (Dd::prod(v.x, v.x) + Dd::prod(v.y, v.y) + Dd::prod(v.z, v.z)).sqrt()
}

impl FreeRotation {
    /// The motion with principal `moments` (any order, `> 0`, equal ones allowed), body angular
    /// velocity `omega0` and orientation `orientation0` (body to space) at `t = 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::NonPositive`] for a bad moment, [`Error::NonFinite`]
    /// for a non-finite `omega0` component, [`Error::InvalidArgument`] for a non-finite
    /// orientation or momenta/rates outside the range of doubles.
    pub fn new(
        moments: Vector3<f64>,
        omega0: Vector3<f64>,
        orientation0: UnitQuaternion<f64>,
    ) -> Result<Self> {
        // The names are formatted only on failure: this runs once per body of a batch.
        for i in 0..3 {
            if !(moments[i].is_finite() && moments[i] > 0.0) {
                positive(&format!("moments[{i}]"), moments[i])?;
            }
            if !omega0[i].is_finite() {
                finite(&format!("omega0[{i}]"), omega0[i])?;
            }
        }
        if !orientation0.coords.iter().all(|x| x.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "orientation0".into(),
                reason: format!(
                    "expected a finite unit quaternion, got {:?}",
                    orientation0.coords
                ),
            });
        }
        let m = moments.component_mul(&omega0);
        if !m.iter().all(|x| x.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "omega0".into(),
                reason: format!("the angular momentum I * omega0 = {m:?} overflows"),
            });
        }
        let energy = 0.5 * m.dot(&omega0);
        let momentum = m.norm();
        let (regime, motion) = Self::classify(&moments, &omega0, &m, &orientation0);
        Ok(FreeRotation {
            moments,
            omega0,
            orientation0,
            energy,
            momentum,
            regime,
            motion,
        })
    }

    fn classify(
        moments: &Vector3<f64>,
        omega0: &Vector3<f64>,
        m: &Vector3<f64>,
        q0: &UnitQuaternion<f64>,
    ) -> (Regime, Motion) {
        let steady = || {
            let rate = norm_dd(omega0);
            let axis = if rate.hi > 0.0 {
                omega0 / rate.hi
            } else {
                Vector3::zeros()
            };
            Motion::Steady { axis, rate }
        };
        if omega0.iter().all(|w| *w == 0.0) {
            return (Regime::Rest, steady());
        }
        let (i0, i1, i2) = (moments[0], moments[1], moments[2]);
        if i0 == i1 && i1 == i2 {
            return (Regime::Spherical, steady());
        }
        if i0 == i1 || i1 == i2 || i0 == i2 {
            let s = if i0 == i1 {
                2
            } else if i1 == i2 {
                0
            } else {
                1
            };
            let it = moments[(s + 1) % 3];
            let is = moments[s];
            let g = [0, 1, 2]
                .map(|i| Dd::prod(moments[i], omega0[i]))
                .iter()
                .fold(Dd::ZERO, |acc, x| acc + *x * *x)
                .sqrt();
            let sym = Symmetric {
                axis: s,
                nutation_rate: g / it,
                m_dir: m / g.hi,
                body_rate: Dd::sum(is, -it) * omega0[s] / it,
            };
            return (Regime::Symmetric { axis: s }, Motion::Symmetric(sym));
        }
        let mut order = [0usize, 1, 2];
        order.sort_by(|a, b| moments[*a].total_cmp(&moments[*b]));
        let [lo, mid, hi] = order;
        let zeros = m.iter().filter(|x| **x == 0.0).count();
        if zeros == 2 {
            let axis = (0..3).find(|i| m[*i] != 0.0).unwrap_or(mid);
            let regime = if axis == mid {
                Regime::SteadyIntermediate
            } else {
                Regime::AboutAxis(axis)
            };
            return (regime, steady());
        }
        // Scale momenta and moments by powers of two (exact).
        let ms = pow2_near(m.amax());
        let is = pow2_near(moments.max());
        let mh = m / ms;
        // The exact products I_i w_i (double-double), scaled.
        let mdd: [Dd; 3] = [0, 1, 2].map(|i| Dd::prod(moments[i], omega0[i]) * (1.0 / ms));
        let ih = moments / is;
        let rate_scale = ms / is;
        // Delta_2 = m_lo^2 (I_lo - I_mid)/I_lo + m_hi^2 (I_hi - I_mid)/I_hi, in double-double.
        let delta2 = mdd[lo] * mdd[lo] * Dd::sum(ih[lo], -ih[mid]) / ih[lo]
            + mdd[hi] * mdd[hi] * Dd::sum(ih[hi], -ih[mid]) / ih[hi];
        let (polar, other) = if delta2.hi < 0.0 { (lo, hi) } else { (hi, lo) };
        let frame = Frame::new([other, mid, polar]);
        let mc3 = frame.to_canonical(&mh);
        let ic = frame.index.map(|i| ih[i]);
        let [i1, i2, i3] = ic;
        let [m1, m2, m3] = mc3;
        let d21 = Dd::sum(i2, -i1);
        let d31 = Dd::sum(i3, -i1);
        let d32 = Dd::sum(i3, -i2);
        let [n1, n2, n3] = [0, 1, 2].map(|i| mdd[frame.index[i]]);
        let sq = |x: Dd| x * x;
        let delta1 = sq(n2) * d21 / i2 + sq(n3) * d31 / i3;
        let mdelta3 = sq(n1) * d31 / i1 + sq(n2) * d32 / i2;
        let g = (sq(n1) + sq(n2) + sq(n3)).sqrt();
        let lambda = (delta1 * d32 / (Dd::new(i1) * i2 * i3)).sqrt() * rate_scale;
        // Amplitudes, as hypotenuses (no cancellation, no overflow).
        let r = |x: Dd| x.to_f64().sqrt();
        let b1 = m1.hypot(m2 * r(Dd::new(i1) * d32 / (d31 * i2)));
        let b2 = (m1 * r(Dd::new(i2) * d31 / (d32 * i1))).hypot(m2);
        let b3 = (m2 * r(Dd::new(i3) * d21 / (d31 * i2))).hypot(m3);
        let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
        let s3 = sign(m3);
        // Euler polar axis: canonical axis 1 or 3, so that the other one, x, has 1/I_x
        // closest to 1/I2: then phi' = G/I_x + G (1/I2 - 1/I_x) (weight in [0, 1]) has the
        // smallest varying part (never more than a factor 2 of cancellation).
        let polar_c1 = (1.0 / i2 - 1.0 / i3).abs() <= (1.0 / i2 - 1.0 / i1).abs();
        let i_x = if polar_c1 { i3 } else { i1 };
        let base_rate = g / i_x * rate_scale;
        // C = G (1/I2 - 1/I_x) (B2/Bh)^2 / lambda and nu, Bh = B3 or B1.
        let dxm = Dd::sum(i_x, -i2) / (Dd::new(i2) * i_x);
        let (ratio, nu) = if polar_c1 {
            // G^2 - m1^2 = B3^2 + B1^2 sn^2: nu = B1^2/B3^2 = I1 (-Delta3) / (I3 Delta1).
            (
                Dd::new(i2) * mdelta3 * d31 / (d32 * i3 * delta1),
                Dd::new(i1) * mdelta3 / (delta1 * i3),
            )
        } else {
            // G^2 - m3^2 = B1^2 + m B3^2 sn^2: nu = m B3^2/B1^2 = I3 (I2 - I1) / (I1 (I3 - I2)).
            (
                Dd::new(i2) * d31 / (d32 * i1),
                Dd::new(i3) * d21 / (d32 * i1),
            )
        };
        let coef = g * dxm * ratio / lambda * rate_scale;
        // The Euler frame: the canonical frame or its cyclic shift (2, 3, 1).
        let euler_frame = if polar_c1 {
            Frame {
                index: [frame.index[1], frame.index[2], frame.index[0]],
                sign: [frame.sign[1], frame.sign[2], frame.sign[0]],
            }
        } else {
            frame
        };
        let q_e = euler_frame.quaternion();
        let euler = if polar_c1 { [m2, m3, m1] } else { [m1, m2, m3] };
        let (theta0, psi0) = theta_psi(euler);
        let q_l = q0 * q_e * qz(-psi0) * qx(-theta0);
        let mut common = Common {
            frame,
            moments: ic,
            b: [b1, b2, b3],
            s: [sign(m1), s3 * sign(i3 - i2), s3],
            rate_scale,
            lambda,
            u0: Dd::ZERO,
            euler_cyclic: polar_c1,
            base_rate,
            coef,
            nu: nu.to_f64(),
            nu_dd: nu,
            j0: Dd::ZERO,
            q_l,
            q_e_inv: q_e.inverse(),
        };
        let mc_dd = delta2 * d31 / (delta1 * d32);
        if delta2.hi == 0.0 || mc_dd.hi <= 0.0 {
            // Separatrix: s2 = s1 s3 sign(I3 - I2); sinh u0 = s2 m2 / hypot(m1, m3).
            common.s[1] = common.s[0] * s3 * sign(i3 - i2);
            common.b[1] = g.to_f64();
            let u0 = (common.s[1] * m2 / m1.hypot(m3)).asinh();
            common.u0 = Dd::new(u0);
            let mut sep = Separatrix { c: common };
            sep.c.j0 = sep.j(Dd::new(u0));
            return (Regime::Separatrix, Motion::Separatrix(Box::new(sep)));
        }
        // Elliptic: the sign of m1 is carried by cn.
        common.s[0] = 1.0;
        let mc = mc_dd.to_f64();
        let k = ellipk_dd(mc_dd);
        let kp_dd = mc_dd.sqrt();
        let j_half = cel(kp_dd, nu + 1.0, Dd::ZERO, Dd::ONE) * 2.0;
        let jc_quarter = cel(kp_dd, nu + 1.0, Dd::ONE, Dd::ZERO);
        // u0 from cn u0 = m1/B1, sn u0 = s2 m2/B2: u0 = F(am u0) = s R_F(c^2, c^2 + mc s^2, 1),
        // reflected about K when cn < 0.
        let c0 = (m1 / b1).clamp(-1.0, 1.0);
        let s0 = (common.s[1] * m2 / b2).clamp(-1.0, 1.0);
        let f = s0 * carlson_rf(c0 * c0, c0 * c0 + mc * s0 * s0, 1.0);
        let u0 = if c0 >= 0.0 {
            Dd::new(f)
        } else {
            k * (2.0 * sign(s0)) - f
        };
        common.u0 = u0;
        let mut ell = Elliptic {
            c: common,
            mc,
            kp: kp_dd.to_f64(),
            k,
            j_half,
            jc_quarter,
        };
        ell.c.j0 = ell.phase(u0).3;
        (Regime::AboutAxis(polar), Motion::Elliptic(Box::new(ell)))
    }

    /// Body angular velocity at time `t`.
    pub fn omega(&self, t: f64) -> Vector3<f64> {
        match &self.motion {
            Motion::Steady { .. } => self.omega0,
            Motion::Symmetric(s) => s.omega(&self.omega0, t),
            Motion::Elliptic(e) => {
                let (sn, cn, dn, _) = e.phase(e.c.u(t));
                e.c.omega([cn, sn, dn])
            }
            Motion::Separatrix(s) => {
                let u = s.c.u(t);
                let (th, sech) = tanh_sech(u.to_f64());
                s.c.omega([sech, th, sech])
            }
        }
    }

    /// Body angular velocity and orientation (body to space) at time `t`.
    pub fn state(&self, t: f64) -> (Vector3<f64>, UnitQuaternion<f64>) {
        match &self.motion {
            Motion::Steady { axis, rate } => (
                self.omega0,
                self.orientation0 * q_axis(axis, wrap(*rate * (0.5 * t))),
            ),
            Motion::Symmetric(s) => {
                let w = s.omega(&self.omega0, t);
                let e_s = Vector3::ith(s.axis, 1.0);
                let q = self.orientation0
                    * q_axis(&s.m_dir, wrap(s.nutation_rate * (0.5 * t)))
                    * q_axis(&e_s, wrap(-(s.body_rate * (0.5 * t))));
                (w, q)
            }
            Motion::Elliptic(e) => {
                let u = e.c.u(t);
                let (sn, cn, dn, j) = e.phase(u);
                e.c.state(t, [cn, sn, dn], j)
            }
            Motion::Separatrix(s) => {
                let u = s.c.u(t);
                let (th, sech) = tanh_sech(u.to_f64());
                s.c.state(t, [sech, th, sech], s.j(u))
            }
        }
    }

    /// The kind of motion.
    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// Period of the body angular velocity: `4 K / lambda` for three distinct moments,
    /// `2 pi / |Omega|` for a symmetric top; `None` if the motion is not periodic (rest, steady
    /// rotation, separatrix).
    pub fn period(&self) -> Option<f64> {
        match &self.motion {
            Motion::Steady { .. } | Motion::Separatrix(_) => None,
            Motion::Symmetric(s) => {
                let ws = self.omega0[s.axis];
                let perp = self.omega0.norm_squared() - ws * ws;
                if s.body_rate.hi == 0.0 || perp.is_nan() || perp <= 0.0 {
                    None
                } else {
                    Some((Dd::TAU / s.body_rate.abs()).to_f64())
                }
            }
            Motion::Elliptic(e) => {
                if e.c.b[0] == 0.0 {
                    None
                } else {
                    Some((e.k * 4.0 / e.c.lambda).to_f64())
                }
            }
        }
    }

    /// Kinetic energy `T = omega . I omega / 2` (constant).
    pub fn energy(&self) -> f64 {
        self.energy
    }

    /// `|L| = |I omega|` (constant).
    pub fn angular_momentum_norm(&self) -> f64 {
        self.momentum
    }

    /// The principal moments, as given.
    pub fn moments(&self) -> Vector3<f64> {
        self.moments
    }

    /// The angular momentum in space axes, `L = R(q0) I omega0` (constant).
    pub fn angular_momentum_space(&self) -> Vector3<f64> {
        self.orientation0 * self.moments.component_mul(&self.omega0)
    }
}

/// `(tanh u, sech u)` without overflow.
fn tanh_sech(u: f64) -> (f64, f64) {
    let a = u.abs();
    let sech = if a > 700.0 {
        0.0
    } else {
        let e = (-a).exp();
        2.0 * e / (1.0 + e * e)
    };
    (u.tanh(), sech)
}

impl Symmetric {
    fn omega(&self, omega0: &Vector3<f64>, t: f64) -> Vector3<f64> {
        let (a, b) = ((self.axis + 1) % 3, (self.axis + 2) % 3);
        let (s, c) = wrap(self.body_rate * t).sin_cos();
        let mut w = *omega0;
        w[a] = c * omega0[a] - s * omega0[b];
        w[b] = s * omega0[a] + c * omega0[b];
        w
    }
}

impl Common {
    fn u(&self, t: f64) -> Dd {
        self.lambda * t + self.u0
    }

    /// Body angular velocity from `(cn, sn, dn)`-like factors of the three canonical components.
    fn omega(&self, f: [f64; 3]) -> Vector3<f64> {
        let mc = self.canonical_m(f);
        let w = [0, 1, 2].map(|i| mc[i] / self.moments[i] * self.rate_scale);
        self.frame.to_body(w)
    }

    fn canonical_m(&self, f: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|i| self.s[i] * self.b[i] * f[i])
    }

    fn state(&self, t: f64, f: [f64; 3], j: Dd) -> (Vector3<f64>, UnitQuaternion<f64>) {
        let m = self.canonical_m(f);
        let w = [0, 1, 2].map(|i| m[i] / self.moments[i] * self.rate_scale);
        let euler = if self.euler_cyclic {
            [m[1], m[2], m[0]]
        } else {
            m
        };
        let (theta, psi) = theta_psi(euler);
        let phi = wrap(self.base_rate * t + self.coef * (j - self.j0));
        let q = self.q_l * qz(phi) * qx(theta) * qz(psi) * self.q_e_inv;
        (self.frame.to_body(w), q)
    }
}

impl Elliptic {
    /// `(sn, cn, dn)(u)` and `J(u)` for the phase `u`.
    fn phase(&self, u: Dd) -> (f64, f64, f64, Dd) {
        let k2 = self.k * 2.0;
        let j = (u / k2).round();
        let w = u - k2 * j.hi - k2 * j.lo;
        let (q, v) = reduce_quarter(w, self.k);
        let (s, c, d) = sncndn_quarter(q, v, self.mc, self.kp);
        let jw = self.j_reduced(w, s, c, d);
        let jj = self.j_half * j.hi + self.j_half * j.lo + jw;
        let sg = if j.to_f64().rem_euclid(2.0) == 1.0 {
            -1.0
        } else {
            1.0
        };
        (sg * s, sg * c, d, jj)
    }

    /// `J(w)` for `|w| <= K` from `s, c, d = sn, cn, dn (w)`.
    ///
    /// Near `sn^2 = 0` directly, `(s^3/3) R_J(c^2, d^2, 1, 1 + nu s^2)` (small). Elsewhere
    /// `J(w) = (|w| - Jc(|w|)) / (1 + nu)` (odd in `w`), with `Jc(w) = int_0^w cn^2/(1 + nu sn^2)`
    /// bounded, `Jc(w) = Jc(K) - mc R(K - w)` and
    /// `R(a) = int_0^a sn^2/(dn^2 + nu cn^2) = (s_a^3/3) R_J(c_a^2, d_a^2, 1, (d_a^2 + nu c_a^2)/(1 + nu)) / (1 + nu)`
    /// (since `cn^2(K - y) = mc sn^2 y / dn^2 y`): the part of `J` that grows with `w` (long
    /// near the separatrix, where the body lingers by the intermediate axis) is carried in
    /// double-double. `(s_a, c_a, d_a) = (c/d, k' s/d, k'/d)` (DLMF 22.4.3).
    fn j_reduced(&self, w: Dd, s: f64, c: f64, d: f64) -> Dd {
        let nu = self.c.nu;
        let s2 = s * s;
        if s2 * (2.0 + nu) <= 1.0 {
            // Here (1 + nu) s^2 / (1 + nu s^2) <= 1/2: J is small and R_J exact enough.
            return Dd::new(s * s2 / 3.0 * carlson_rj(c * c, d * d, 1.0, 1.0 + nu * s2));
        }
        let (sa, ca, da) = (c / d, self.kp * s.abs() / d, self.kp / d);
        let p = (da * da + nu * ca * ca) / (1.0 + nu);
        let r = sa * sa * sa / 3.0 * carlson_rj(ca * ca, da * da, 1.0, p) / (1.0 + nu);
        let jabs = (w.abs() - self.jc_quarter + self.mc * r) / (self.c.nu_dd + 1.0);
        if w.hi < 0.0 {
            -jabs
        } else {
            jabs
        }
    }
}

impl Separatrix {
    /// `J(u) = int_0^u tanh^2 / (1 + nu tanh^2)`.
    fn j(&self, u: Dd) -> Dd {
        let nu = self.c.nu;
        let x = u.to_f64();
        if x.abs() <= 1.0 {
            let (s, c) = tanh_sech(x);
            Dd::new(s * s * s / 3.0 * carlson_rj(c * c, c * c, 1.0, 1.0 + nu * s * s))
        } else {
            let r = nu.sqrt();
            let at = if r > 0.0 {
                (r * x.tanh()).atan() / r
            } else {
                x.tanh()
            };
            (u - at) / (self.c.nu_dd + 1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_right_handed() {
        for index in [
            [0, 1, 2],
            [1, 2, 0],
            [2, 0, 1],
            [0, 2, 1],
            [2, 1, 0],
            [1, 0, 2],
        ] {
            let f = Frame::new(index);
            let r = f.quaternion().to_rotation_matrix();
            assert!((r.matrix().determinant() - 1.0).abs() < 1e-15);
            let v = Vector3::new(0.3, -1.2, 2.5);
            let back = f.to_body(f.to_canonical(&v));
            assert_eq!(back, v);
            // The canonical components are the components in the rotated frame.
            let c = f.to_canonical(&v);
            let w = r.inverse() * v;
            assert!((Vector3::from(c) - w).norm() < 1e-15);
        }
    }

    #[test]
    fn wrap_reduces_double_double_angles() {
        let x = Dd::TAU * 1e12 + 0.25;
        assert!((wrap(x) - 0.25).abs() < 1e-15);
        assert!((wrap(Dd::new(-4.0)) - (-4.0 + std::f64::consts::TAU)).abs() < 1e-15);
    }

    #[test]
    fn regimes() {
        let q = UnitQuaternion::identity();
        let i = Vector3::new(1.0, 2.0, 3.0);
        let r = |w: Vector3<f64>| FreeRotation::new(i, w, q).unwrap().regime();
        assert_eq!(r(Vector3::new(0.1, 0.1, 1.0)), Regime::AboutAxis(2));
        assert_eq!(r(Vector3::new(1.0, 0.1, 0.1)), Regime::AboutAxis(0));
        // Delta_2 = m1^2 (1 - 2)/1 + m3^2 (3 - 2)/3 = 0 for m3 = sqrt(3) m1: use exact ones.
        let i = Vector3::new(2.0, 3.0, 6.0);
        let sep = FreeRotation::new(i, Vector3::new(1.5, 0.2, 0.5), q).unwrap();
        assert_eq!(sep.regime(), Regime::Separatrix);
    }
}
