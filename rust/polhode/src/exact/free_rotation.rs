//! The torque-free motion of a rigid body in closed form.
//!
//! Euler's equations in principal axes, `I1 w1' + (I3 - I2) w2 w3 = 0` and cyclic, with the
//! orientation `q' = q (x) (0, w) / 2` (body to space). For body angular momentum `m = I w`,
//! `G = |m|`, `2T = sum m_i^2 / I_i` and `Delta_j = G^2 - 2 T I_j` (`Delta_1` and `Delta_3`
//! as sums of terms of one sign, in double-double; `Delta_2 = I_lo w_lo^2 (I_lo - I_mid) +
//! I_hi w_hi^2 (I_hi - I_mid)` exactly, so that its sign is the regime and it vanishes exactly
//! on the separatrix, with no band of rounding in between):
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
//! Where the nome `q = exp(-pi K'/K)` is at most 0.5, `J` is instead Jacobi's form of the integral
//! of the third kind (Whittaker & Watson 22.74), `J(w) = A w + B arg theta_4(pi w / 2K + i beta)`
//! on `|w| <= K`: a few terms of a theta series with constants formed once per motion
//! ([`ThetaJ`]), the same function to a few ulp of `J(K)` (one `sin_cos`, one `atan2` and up to
//! ten terms per time instead of the duplication steps of `R_J`).
//!
//! The phase `lambda t + u0`, the quarter period `K` and the per-period gains are carried in
//! double-double, so the only error that grows with `t` is the rounding of `t` itself.
//!
//! **Range.** The invariants are formed from the exact products `I_i w_i` in double-double with
//! an exponent of its own ([`Xd`]), so no square underflows or overflows: a component of 1e-170
//! (or a subnormal one) next to one of 1, or moments from 1e-150 to 1e150, keep their digits.
//! The evaluation works in units that are powers of two (momenta in units of about `max |I w|`,
//! moments of `max I`, time of their ratio: exact scalings), and each amplitude and moment that
//! would leave the range of doubles in those units carries its own exponent ([`Sd`]), applied
//! once to each output. When `|Delta_2|` is so small that `k' = sqrt(mc)` is below `2^-54`
//! (`mc` itself may underflow), `K = pi / (2 AGM(1, k'))` is formed from `sqrt(k')`, the
//! functions on `|v| <= K/2` are the hyperbolic ones of `v` in double-double (their corrections
//! are at most `k'/4 < eps/4` relative, DLMF 22.10.4-6; below `k' = 2^-27` the first-order
//! corrections are added, the next being `O(k'^2)`, and one Newton step makes `u0` as accurate),
//! near `u = K` the shifted forms
//! `cn(K + v) = -k' sinh v`, `dn(K + v) = k' cosh v` carry `k'` as a factor with its exponent,
//! and `J(w) = (|w| - atan(sqrt(nu) |sn w|)/sqrt(nu)) / (1 + nu)` away from `w = 0` (`O(k')`).
//!
//! **The separatrix.** `sech u = 2 e / (1 + e^2)` and `tanh u = (1 - e^2)/(1 + e^2)` with
//! `e = exp(-|u|)` in double-double (mantissa and exponent), `u = lambda t + u0` in double-double
//! and `u0 = ln((G + s2 m2) / hypot(m1, m3))` (or `ln(hypot(m1, m3) / (G - s2 m2))` when
//! `s2 m2 < 0`, which does not cancel): the decaying components keep their relative accuracy
//! until they underflow.
//!
//! **The time bound.** A double `t` carries its phase only while one ulp of `t` (at most
//! `2^-52 |t|`) turns the fastest angle of the motion by less than a quarter turn: `|t| <=
//! 2^50 2 pi / R`, where `R` is the largest angular rate (the rotation rate `|w|` of a steady
//! rotation; `G / I_t` and `|Omega|` of a symmetric top; `2 pi / T` and the largest precession
//! rate `|phi'| <= |G / I_x| + |C| lambda / (1 + nu)` otherwise). Beyond it
//! [`FreeRotation::try_state`] returns [`Error::InvalidArgument`] for `t`; below it the phase
//! (carried in double-double) keeps its error to a few ulp and the reductions modulo the
//! period are exact.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

use super::carlson::{carlson_rf, carlson_rj};
use super::dd::{agm1, cel, cel_many, Dd};
use super::elliptic::{ellipf, ellipk_dd, Landen};
use super::xd::{asinh_xd, exact_sum_a_b2_diff, exp_dd, ldexp, Sd, Xd};
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

/// Where double precision ends for the time: one ulp of `t` turns the fastest angle of the
/// motion by a quarter turn at `|t| = 2^50 2 pi / R`.
const PHASE_TURNS: f64 = 1_125_899_906_842_624.0; // 2^50

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
    /// The largest time (in magnitude) at which the phase keeps digits.
    t_max: f64,
    /// The fastest angular rate of the motion (rad per unit time).
    max_rate: f64,
}

#[derive(Debug, Clone)]
enum Motion {
    /// Constant `omega` (rest, sphere, steady rotation about a principal axis):
    /// `q(t) = q0 (x) exp(omega t / 2)`; `rate = |omega|` per unit of `tau = t 2^rho`.
    Steady {
        axis: Vector3<f64>,
        rate: Dd,
        rho: i32,
    },
    Symmetric(Symmetric),
    Elliptic(Box<Elliptic>),
    Separatrix(Box<Separatrix>),
}

/// `q(t) = q0 (x) exp(m0 t / (2 I_t)) (x) exp(-Omega t e_s / 2)`, `omega` turning about `e_s`
/// at `Omega`. Rates per unit of `tau = t 2^rho`.
#[derive(Debug, Clone)]
struct Symmetric {
    axis: usize,
    rho: i32,
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

    fn to_canonical_sd(self, v: &[Sd; 3]) -> [Sd; 3] {
        [0, 1, 2].map(|i| {
            let s = v[self.index[i]];
            Sd {
                x: self.sign[i] * s.x,
                e: s.e,
            }
        })
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
///
/// Units: momenta `2^mu`, moments `2^iota`, time `2^-rho` with `rho = mu - iota` (so that
/// `tau = t 2^rho` and rates are per unit of `tau`).
#[derive(Debug, Clone)]
struct Common {
    frame: Frame,
    /// Canonical moments, in units of `2^iota`.
    moments: [Sd; 3],
    /// Amplitudes `B1, B2, B3`, in units of `2^mu`.
    b: [Sd; 3],
    /// `s1` (separatrix only), `s2`, `s3`.
    s: [f64; 3],
    rho: i32,
    /// `lambda`, per unit of `tau`.
    lambda: Dd,
    /// The phase at `t = 0` is `u0 + u0_q K` (elliptic): a `u0` near a quarter period keeps
    /// the digits of its distance to it.
    u0: Dd,
    u0_q: i64,
    /// Euler frame: `true` if it is `(2, 3, 1)` of the canonical frame, else `(1, 2, 3)`.
    euler_cyclic: bool,
    /// `G / I_x`, per unit of `tau`.
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
    /// `k'`, or its mantissa (with exponent `kp_exp`) when `k' < 2^-54`.
    kp: f64,
    kp_exp: i32,
    /// How `sn, cn, dn` are evaluated (module doc).
    functions: Functions,
    /// The Landen chain of `mc` (for [`Functions::Landen`]).
    landen: Landen,
    k: Dd,
    /// `1 / K` and `1 / 2K`, rounded: the reductions' first guesses of the quotients.
    inv_k: f64,
    inv_k2: f64,
    /// `J` over a half period `2K` of `u`: `2 cel(k', 1 + nu, 0, 1)`.
    j_half: Dd,
    /// `Jc(K) = int_0^K cn^2 / (1 + nu sn^2) = cel(k', 1 + nu, 1, 0)`.
    jc_quarter: Dd,
    /// `J` in theta-function form, where the nome is small enough ([`ThetaJ`]).
    theta: Option<ThetaJ>,
}

/// The largest nome `q = exp(-pi K'/K)` at which `J` is summed as a theta series (`1 - m` down
/// to about 2e-6; at most 10 terms, the last below `q^(n (n - 1)) < 1e-18`).
const Q_THETA: f64 = 0.5;

/// `J(w) = A w + B arg theta_4(z + i beta)`, `z = pi w / (2K)`, for `|w| <= K` (Jacobi's form of
/// the integral of the third kind, Whittaker & Watson 22.74, with the parameter `i alpha`,
/// `sc(alpha | 1 - m) = sqrt(nu / m)`, `beta = pi alpha / (2K)`), where
/// `theta_4(z + i beta) = 1 + sum_n a_n cos 2nz - i sum_n b_n sin 2nz`,
/// `a_n, b_n = (-1)^n q^(n^2) (e^(2 n beta) +- e^(-2 n beta))`. `A = J(2K)/2K` is the mean
/// slope, `B` makes `J'(0) = 0`. The terms are formed from `gamma = K' - alpha =
/// F(atan(1/sqrt(nu)) | 1 - m)` (each exponent a sum of positive terms) and the `b_n` for small
/// `alpha` from `sinh`, so that no constant cancels; near `z = 0` the real part is
/// `(1 + a_1) - 2 a_1 sin^2 z + ...` with `1 + a_1 = -expm1(-pi gamma / K) - e_1^-`.
#[derive(Debug, Clone)]
struct ThetaJ {
    n: usize,
    a: [f64; 10],
    b: [f64; 10],
    /// `1 + a_1`.
    r0: f64,
    /// `pi / K`: `2z = pi w / K`.
    z_scale: f64,
    slope: Dd,
    b_coef: f64,
}

impl ThetaJ {
    /// The constants for parameter `1 - mc` (`2^-54 <= sqrt(mc)`), quarter period `k`, `nu > 0`
    /// and `J(2K) = j_half`; `None` if the nome is above [`Q_THETA`] or a constant is not finite.
    fn new(mc: f64, k: Dd, nu: f64, j_half: Dd) -> Option<ThetaJ> {
        if !(nu > 0.0 && nu.is_finite() && mc > 0.0 && mc < 1.0) {
            return None;
        }
        let m = Dd::sum(1.0, -mc);
        let kp = ellipk_dd(m);
        let pk = (Dd::PI * kp / k).to_f64(); // pi K'/K = -ln q
        if (-pk).exp() > Q_THETA {
            return None;
        }
        let z_scale = (Dd::PI / k).to_f64();
        let mf = m.to_f64();
        // gamma = K' - alpha and alpha, each from its own F (no cancellation), times pi/K.
        let g = ellipf((1.0 / nu.sqrt()).atan(), mf) * z_scale;
        let al = ellipf((nu / mf).sqrt().atan(), mf) * z_scale;
        let mut a = [0.0; 10];
        let mut b = [0.0; 10];
        let mut n = 0;
        let mut r0 = 0.0;
        for i in 1..=10usize {
            let x = i as f64;
            let e_plus = (-(x * (x - 1.0) * pk + x * g)).exp();
            let e_minus = (-(x * (x + 1.0) * pk - x * g)).exp();
            let sign = if i % 2 == 1 { -1.0 } else { 1.0 };
            let bn = if x * al < 0.5 {
                2.0 * (-(x * x) * pk).exp() * (x * al).sinh()
            } else {
                e_plus - e_minus
            };
            a[i - 1] = sign * (e_plus + e_minus);
            b[i - 1] = sign * bn;
            if i == 1 {
                r0 = -(-g).exp_m1() - e_minus;
            }
            n = i;
            if e_plus < 1e-18 {
                break;
            }
        }
        // B from J'(0) = 0: A + B (pi/2K) (-sum 2n b_n) / Re(0) = 0.
        let re0 = r0 + a[1..n].iter().sum::<f64>();
        let db: f64 = (0..n).map(|i| 2.0 * (i + 1) as f64 * b[i]).sum();
        let slope = j_half / (k * 2.0);
        let b_coef = slope.to_f64() * re0 * 2.0 / (z_scale * db);
        let ok = a.iter().chain(&b).all(|x| x.is_finite())
            && r0.is_finite()
            && b_coef.is_finite()
            && re0 > 0.0;
        ok.then_some(ThetaJ {
            n,
            a,
            b,
            r0,
            z_scale,
            slope,
            b_coef,
        })
    }

    /// `J(w)` for `|w| <= K`.
    #[inline]
    fn j(&self, w: Dd) -> Dd {
        let z = 0.5 * self.z_scale * w.to_f64();
        let (sz, cz) = z.sin_cos();
        let (s1, c1) = (2.0 * sz * cz, (cz - sz) * (cz + sz));
        let mut re = self.r0 - 2.0 * self.a[0] * sz * sz;
        let mut im = -self.b[0] * s1;
        let (mut c, mut s) = (c1, s1);
        for i in 1..self.n {
            (c, s) = (c * c1 - s * s1, s * c1 + c * s1);
            re += self.a[i] * c;
            im -= self.b[i] * s;
        }
        self.slope * w + self.b_coef * im.atan2(re)
    }
}

/// The evaluation of `sn, cn, dn` on `|v| <= K/2`, by `k'`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Functions {
    /// `k' >= 2^-27`: the descending Landen transformation.
    Landen,
    /// `2^-54 <= k' < 2^-27`: the hyperbolic functions of `v` (double-double) with their
    /// first-order corrections in `k'^2` (DLMF 22.10.4-6; the next are `O(k'^2)` relative).
    Corrected,
    /// `k' < 2^-54`: the hyperbolic functions of `v` (double-double), corrections below
    /// `k'/4`.
    Hyperbolic,
}

#[derive(Debug, Clone)]
struct Separatrix {
    c: Common,
}

/// `x` reduced into `[-pi, pi]`, from a double-double angle.
fn wrap(x: Dd) -> f64 {
    // The quotient by 2 pi rounded from a double product (a few turns off at most when |x| is
    // large), then once more from the remainder, which is small: exact.
    let inv = 1.0 / std::f64::consts::TAU;
    let r = x - Dd::TAU * super::dd::round(x.hi * inv);
    let j = super::dd::round(r.hi * inv);
    if j == 0.0 {
        r.to_f64()
    } else {
        (r - Dd::TAU * j).to_f64()
    }
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
fn theta_psi(e: [Sd; 3]) -> (f64, f64) {
    (
        Sd::atan2(Sd::hypot(e[0], e[1]), e[2]),
        Sd::atan2(e[0], e[1]),
    )
}

/// `qz(phi) qx(theta) qz(psi)` for the z-x-z Euler angles `(theta, psi)` of `e` (as
/// [`theta_psi`] gives them) and `phi`, without forming `theta` and `psi`: their half angles
/// from `G +- e_z` and `h +- e_y` (`h = hypot(e_x, e_y)`, `G = hypot(h, e_z)`), each from the
/// sum without cancellation and the other from `sin x = 2 sin(x/2) cos(x/2)`, on the same
/// branches (`theta/2` in `[0, pi/2]`, `psi/2` in `(-pi/2, pi/2]`). `None` if `h` is zero or
/// not finite.
fn zxz_half_angles(e: [f64; 3], phi: f64) -> Option<UnitQuaternion<f64>> {
    let h = e[0].hypot(e[1]);
    if !(h > 0.0 && h.is_finite()) {
        return None;
    }
    let g = h.hypot(e[2]);
    let (ct, st) = if e[2] >= 0.0 {
        let c = ((g + e[2]) / (2.0 * g)).sqrt();
        (c, h / (2.0 * g * c))
    } else {
        let s = ((g - e[2]) / (2.0 * g)).sqrt();
        (h / (2.0 * g * s), s)
    };
    let (cp, sp) = if e[1] >= 0.0 {
        let c = ((h + e[1]) / (2.0 * h)).sqrt();
        (c, e[0] / (2.0 * h * c))
    } else {
        let s = ((h - e[1]) / (2.0 * h)).sqrt().copysign(e[0]);
        (e[0] / (2.0 * h * s), s)
    };
    let (sf, cf) = (0.5 * phi).sin_cos();
    let (c_sum, s_sum) = (cf * cp - sf * sp, sf * cp + cf * sp);
    let (c_diff, s_diff) = (cf * cp + sf * sp, sf * cp - cf * sp);
    Some(UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
        ct * c_sum,
        st * c_diff,
        st * s_diff,
        ct * s_sum,
    )))
}

/// `(tanh u, sech u)` without overflow (double precision; for the small-`u` branch of `J`).
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

/// `(tanh u, sech u / 2^k, k)` of a double-double `u`, from `e = exp(-|u|) = m 2^k`:
/// `tanh u = (1 - e^2)/(1 + e^2)`, `sech u = 2 e / (1 + e^2)`, each rounded once.
fn tanh_sech_dd(u: Dd) -> (f64, f64, i32) {
    let a = u.abs();
    let sg = if u.hi < 0.0 { -1.0 } else { 1.0 };
    if a.hi < 1e-9 {
        let a2 = a * a;
        let th = a * (Dd::ONE - a2 / 3.0);
        return (sg * th.to_f64(), (Dd::ONE - a2 * 0.5).to_f64(), 0);
    }
    let (m, k) = exp_dd(-a);
    if m.hi == 0.0 {
        return (sg, 0.0, 0);
    }
    if k < -56 {
        // e^2 below 2^-110: 1 +- e^2 = 1 in double-double.
        return (sg, (m * 2.0).to_f64(), k);
    }
    let e2 = (m * m).ldexp(2 * k);
    let inv = Dd::ONE / (Dd::ONE + e2);
    (
        sg * ((Dd::ONE - e2) * inv).to_f64(),
        (m * 2.0 * inv).to_f64(),
        k,
    )
}

/// The hyperbolic functions of a double-double `v`, from `e = exp(-|v|) = m 2^k`:
/// `(tanh v, sech v / 2^k, sinh v 2^k, cosh v 2^k, k)`, each rounded once.
fn hyperbolic(v: Dd) -> (f64, f64, f64, f64, i32) {
    let a = v.abs();
    let sg = if v.hi < 0.0 { -1.0 } else { 1.0 };
    if a.hi < 1e-9 {
        // Series (the next terms are below 1e-36 relative).
        let a2 = a * a;
        let th = a * (Dd::ONE - a2 / 3.0);
        let sh = a * (Dd::ONE + a2 / 6.0);
        let ch = Dd::ONE + a2 * 0.5;
        let sech = Dd::ONE - a2 * 0.5;
        return (
            sg * th.to_f64(),
            sech.to_f64(),
            sg * sh.to_f64(),
            ch.to_f64(),
            0,
        );
    }
    let (m, k) = exp_dd(-a);
    if m.hi == 0.0 {
        return (sg, 0.0, sg * f64::INFINITY, f64::INFINITY, 0);
    }
    // e^2 = m^2 2^(2k): below 2^-110 it does not change 1 +- e^2 in double-double.
    let (one_p, one_m) = if k < -56 {
        (Dd::ONE, Dd::ONE)
    } else {
        let e2 = (m * m).ldexp(2 * k);
        (Dd::ONE + e2, Dd::ONE - e2)
    };
    let (inv, inv_2m) = (Dd::ONE / one_p, Dd::ONE / (m * 2.0));
    let th = one_m * inv;
    let sech = m * 2.0 * inv;
    let sh = one_m * inv_2m;
    let ch = one_p * inv_2m;
    (
        sg * th.to_f64(),
        sech.to_f64(),
        sg * sh.to_f64(),
        ch.to_f64(),
        k,
    )
}

/// An even exponent near `log2 |x|` (scaling by its power of two, and by the square root of
/// that, is exact).
fn even_exponent(x: Xd) -> i32 {
    x.e - x.e.rem_euclid(2)
}

fn too_wide(what: &str) -> Error {
    Error::InvalidArgument {
        name: "omega0".into(),
        reason: format!(
            "the {what} of this motion span more than the range of doubles (with these moments)."
        ),
    }
}

/// `x` as a double-double, or an error if it is not a normal double-double.
fn checked_dd(x: Xd, what: &str) -> Result<Dd> {
    let d = x.to_dd();
    if x.is_zero() || (d.hi.is_finite() && d.hi.abs() >= f64::MIN_POSITIVE) {
        Ok(d)
    } else {
        Err(too_wide(what))
    }
}

impl FreeRotation {
    /// The motion with principal `moments` (any order, `> 0`, equal ones allowed), body angular
    /// velocity `omega0` and orientation `orientation0` (body to space) at `t = 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::NonPositive`] for a bad moment, [`Error::NonFinite`]
    /// for a non-finite `omega0` component, [`Error::InvalidArgument`] for a non-finite
    /// orientation, an angular momentum or kinetic energy outside the range of doubles, or rates
    /// of the motion that span more than it.
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
        // T = sum I w^2 / 2 and |L|, from the exact products (no square underflows).
        let mx = [0, 1, 2].map(|i| Xd::prod(moments[i], omega0[i]));
        let energy = [0, 1, 2]
            .map(|i| mx[i].mul_f64(omega0[i]))
            .iter()
            .fold(Xd::ZERO, |a, x| a + *x)
            .mul_f64(0.5)
            .to_f64();
        if !energy.is_finite() {
            return Err(Error::InvalidArgument {
                name: "omega0".into(),
                reason: "the kinetic energy of `omega0` with these moments overflows double \
                         precision."
                    .into(),
            });
        }
        let momentum = mx.iter().fold(Xd::ZERO, |a, x| a + *x * *x).sqrt().to_f64();
        let (regime, motion, rate) = Self::classify(&moments, &omega0, &mx, &orientation0)?;
        let t_max = if rate.is_zero() {
            f64::INFINITY
        } else {
            (Xd::from_dd(Dd::TAU * PHASE_TURNS) / rate).to_f64()
        };
        Ok(FreeRotation {
            moments,
            omega0,
            orientation0,
            energy,
            momentum,
            regime,
            motion,
            t_max,
            max_rate: rate.to_f64(),
        })
    }

    /// The regime, the motion and its fastest angular rate.
    fn classify(
        moments: &Vector3<f64>,
        omega0: &Vector3<f64>,
        mx: &[Xd; 3],
        q0: &UnitQuaternion<f64>,
    ) -> Result<(Regime, Motion, Xd)> {
        if omega0.iter().all(|w| *w == 0.0) {
            let (motion, rate) = steady(omega0);
            return Ok((Regime::Rest, motion, rate));
        }
        let (i0, i1, i2) = (moments[0], moments[1], moments[2]);
        if i0 == i1 && i1 == i2 {
            let (motion, rate) = steady(omega0);
            return Ok((Regime::Spherical, motion, rate));
        }
        if i0 == i1 || i1 == i2 || i0 == i2 {
            return Ok(symmetric(moments, omega0, mx));
        }
        let mut order = [0usize, 1, 2];
        order.sort_by(|a, b| moments[*a].total_cmp(&moments[*b]));
        let mid = order[1];
        let zeros = omega0.iter().filter(|x| **x == 0.0).count();
        if zeros == 2 {
            let axis = (0..3).find(|i| omega0[*i] != 0.0).unwrap_or(mid);
            let regime = if axis == mid {
                Regime::SteadyIntermediate
            } else {
                Regime::AboutAxis(axis)
            };
            let (motion, rate) = steady(omega0);
            return Ok((regime, motion, rate));
        }
        let asymmetric = Asymmetric::new(moments, omega0, mx, q0, order)?;
        let mc_x = asymmetric.mc_x;
        if asymmetric.delta2.is_zero() || mc_x.is_zero() || mc_x.is_negative() {
            return Ok(asymmetric.separatrix());
        }
        Ok(asymmetric.elliptic())
    }

    /// Body angular velocity at time `t` (NaN beyond [`FreeRotation::max_time`]: use
    /// [`FreeRotation::try_omega`] for an error there).
    pub fn omega(&self, t: f64) -> Vector3<f64> {
        self.try_omega(t)
            .unwrap_or_else(|_| Vector3::repeat(f64::NAN))
    }

    /// Body angular velocity and orientation (body to space) at time `t` (NaN beyond
    /// [`FreeRotation::max_time`]: use [`FreeRotation::try_state`] for an error there).
    pub fn state(&self, t: f64) -> (Vector3<f64>, UnitQuaternion<f64>) {
        self.try_state(t).unwrap_or_else(|_| {
            (
                Vector3::repeat(f64::NAN),
                UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
                    f64::NAN,
                    f64::NAN,
                    f64::NAN,
                    f64::NAN,
                )),
            )
        })
    }

    /// The largest `|t|` at which the phase of the motion keeps digits in double precision:
    /// there one ulp of `t` turns the fastest angle of the motion by a quarter turn (module
    /// doc); `inf` at rest.
    pub fn max_time(&self) -> f64 {
        self.t_max
    }

    /// An error for a non-finite time or one beyond the bound.
    fn check_time(&self, t: f64) -> Result<()> {
        if !t.is_finite() {
            return finite("t", t).map(|_| ());
        }
        if t.abs() > self.t_max {
            return Err(Error::InvalidArgument {
                name: "t".into(),
                reason: format!(
                    "|t| = {:e} is beyond {:e}, the largest time at which the phase of this \
                     motion keeps digits in double precision (there one ulp of t turns its \
                     fastest angle, {:e} rad per unit time, by a quarter turn).",
                    t.abs(),
                    self.t_max,
                    self.max_rate
                ),
            });
        }
        Ok(())
    }

    /// Body angular velocity at time `t`: at `t = 0`, `omega0` itself.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `t`, [`Error::InvalidArgument`] for
    /// `|t| >` [`FreeRotation::max_time`].
    pub fn try_omega(&self, t: f64) -> Result<Vector3<f64>> {
        self.check_time(t)?;
        if t == 0.0 {
            // The initial state itself: the closed form rebuilds it from the invariants and
            // the phase, each rounded (omega0 = (0.01, 1, 5) with moments (1, 2, 3) came back
            // as (0.009999999999999997, 0.9999999999999996, 5)).
            return Ok(self.omega0);
        }
        Ok(match &self.motion {
            Motion::Steady { .. } => self.omega0,
            Motion::Symmetric(s) => s.omega(&self.omega0, t),
            Motion::Elliptic(e) => {
                let (sn, cn, dn, _, kappa) = e.phase::<false>(e.c.u(t));
                e.c.omega([cn, sn, dn], kappa)
            }
            Motion::Separatrix(s) => {
                let u = s.c.u(t);
                let (th, sech, kappa) = tanh_sech_dd(u);
                s.c.omega([sech, th, sech], kappa)
            }
        })
    }

    /// Body angular velocity and orientation (body to space) at time `t`: at `t = 0`, `omega0`
    /// and `orientation0` themselves.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `t`, [`Error::InvalidArgument`] for
    /// `|t| >` [`FreeRotation::max_time`].
    pub fn try_state(&self, t: f64) -> Result<(Vector3<f64>, UnitQuaternion<f64>)> {
        self.check_time(t)?;
        if t == 0.0 {
            // The initial state itself (see `try_omega`): the orientation was rebuilt through
            // the frames of L and of the canonical axes, q0 = q_l q_euler q_e^-1, to rounding.
            return Ok((self.omega0, self.orientation0));
        }
        Ok(match &self.motion {
            Motion::Steady { axis, rate, rho } => (
                self.omega0,
                self.orientation0 * q_axis(axis, wrap(*rate * (0.5 * ldexp(t, *rho)))),
            ),
            Motion::Symmetric(s) => {
                let w = s.omega(&self.omega0, t);
                let e_s = Vector3::ith(s.axis, 1.0);
                let tau = ldexp(t, s.rho);
                let q = self.orientation0
                    * q_axis(&s.m_dir, wrap(s.nutation_rate * (0.5 * tau)))
                    * q_axis(&e_s, wrap(-(s.body_rate * (0.5 * tau))));
                (w, q)
            }
            Motion::Elliptic(e) => {
                let u = e.c.u(t);
                let (sn, cn, dn, j, kappa) = e.phase::<true>(u);
                e.c.state(t, [cn, sn, dn], kappa, j)
            }
            Motion::Separatrix(s) => {
                let u = s.c.u(t);
                let (th, sech, kappa) = tanh_sech_dd(u);
                s.c.state(t, [sech, th, sech], kappa, s.j(u))
            }
        })
    }

    /// The kind of motion.
    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// Period of the body angular velocity: `4 K / lambda` for three distinct moments,
    /// `2 pi / |Omega|` for a symmetric top; `None` if the motion is not periodic (rest, steady
    /// rotation, separatrix) or its period is beyond the range of doubles.
    pub fn period(&self) -> Option<f64> {
        let p = match &self.motion {
            Motion::Steady { .. } | Motion::Separatrix(_) => None,
            Motion::Symmetric(s) => {
                let (a, b) = ((s.axis + 1) % 3, (s.axis + 2) % 3);
                let perp = self.omega0[a] != 0.0 || self.omega0[b] != 0.0;
                if s.body_rate.hi == 0.0 || !perp {
                    None
                } else {
                    Some(Xd::from_dd(Dd::TAU / s.body_rate.abs()).ldexp(-s.rho))
                }
            }
            Motion::Elliptic(e) => {
                if e.c.b[0].x == 0.0 {
                    None
                } else {
                    Some(Xd::from_dd(e.k * 4.0 / e.c.lambda).ldexp(-e.c.rho))
                }
            }
        };
        p.map(|x| x.to_f64()).filter(|x| x.is_finite() && *x > 0.0)
    }

    /// The mean rate at which the body turns about `L` in space (rad per unit time): the mean
    /// rate of the azimuth about `L` of the axis the motion circulates about (the symmetry axis
    /// of a symmetric top, else the axis of the smallest or the largest moment, as
    /// [`Regime::AboutAxis`] says), always positive about `+L`.
    ///
    /// - A symmetric top: `|L| / I_t` (`I_t` the transverse moment; Landau-Lifshitz par. 33).
    /// - Three distinct moments: the azimuth is the precession angle `phi` of the z-x-z Euler
    ///   angles with space z along `L` and body z along that axis `p` (module doc). Over one
    ///   period `P` of omega it gains `phi(P) - phi(0) = G P / I_x + C (J(u0 + 4K) - J(u0))`,
    ///   and `J` gains `2 cel(k', 1 + nu, 0, 1)` per `2K` (the complete elliptic integral of
    ///   the third kind in Bulirsch's form): mean rate `G / I_x + C lambda cel(k', 1 + nu, 0, 1)
    ///   / K`. When the evaluation uses the other extreme axis `a` as its polar axis (better
    ///   conditioned), `m` does not wind about `a`, and the azimuth of `p` gains one turn more
    ///   (p the largest moment) or less (the smallest) per period than that of `a`:
    ///   `+- 2 pi / P` is added.
    /// - A steady rotation about the axis `p` of the smallest or the largest moment: the limit
    ///   of the motions about it, `|w| (1 +- sqrt((I_p - I_a)(I_p - I_b) / (I_a I_b)))` (`+` for
    ///   the largest), which for `I_a = I_b` is `|L| / I_t`; a sphere turns at `|w|`.
    /// - `None` at rest, on the separatrix and in steady rotation about the intermediate axis
    ///   (no mean: the motion is not periodic about an axis).
    pub fn precession_rate_space(&self) -> Option<f64> {
        let rate = match &self.motion {
            Motion::Steady { .. } => match self.regime {
                Regime::Spherical => self.momentum / self.moments[0],
                Regime::AboutAxis(p) => {
                    let (ia, ib, ip) = (
                        self.moments[(p + 1) % 3],
                        self.moments[(p + 2) % 3],
                        self.moments[p],
                    );
                    let root = ((ip - ia) / ia * ((ip - ib) / ib)).sqrt();
                    let sign = if ip > ia { 1.0 } else { -1.0 };
                    self.omega0[p].abs() * (1.0 + sign * root)
                }
                _ => return None,
            },
            Motion::Symmetric(s) => Xd::from_dd(s.nutation_rate).ldexp(s.rho).to_f64(),
            Motion::Elliptic(e) => {
                let c = &e.c;
                let mut rate = c.base_rate + c.coef * c.lambda * e.j_half / (e.k * 2.0);
                if c.euler_cyclic {
                    // sign(I3 - I2) in the canonical frame = s2 s3.
                    rate = rate + Dd::PI * c.lambda / e.k * (0.5 * c.s[1] * c.s[2]);
                }
                Xd::from_dd(rate).ldexp(c.rho).to_f64()
            }
            Motion::Separatrix(_) => return None,
        };
        Some(rate).filter(|r| r.is_finite())
    }

    /// The range `(min, max)` of the nutation angle: the angle between `L` and the axis the
    /// motion circulates about (as [`FreeRotation::precession_rate_space`] names it; its
    /// direction as given, so an angle above `pi/2` means `L` is nearer its negative end).
    ///
    /// A symmetric top nutates at a constant angle, `cos theta = I_s w_s / |L|`. With three
    /// distinct moments, `m_p = s3 B3 dn u` swings between `B3` (where `m` has the component
    /// `B1` across it) and `k' B3` (across it `B2`): `theta` from `atan2(B1, B3)` to
    /// `atan2(B2, k' B3)`. A steady rotation about the axis of the smallest or the largest
    /// moment: 0 (or pi). `None` at rest, for a sphere, on the separatrix and in steady
    /// rotation about the intermediate axis.
    pub fn nutation_angle(&self) -> Option<(f64, f64)> {
        use std::f64::consts::PI;
        match &self.motion {
            Motion::Steady { .. } => match self.regime {
                Regime::AboutAxis(p) => {
                    let theta = if self.omega0[p] > 0.0 { 0.0 } else { PI };
                    Some((theta, theta))
                }
                _ => None,
            },
            Motion::Symmetric(s) => {
                let m = &s.m_dir;
                let (a, b) = ((s.axis + 1) % 3, (s.axis + 2) % 3);
                let theta = m[a].hypot(m[b]).atan2(m[s.axis]);
                Some((theta, theta))
            }
            Motion::Elliptic(e) => {
                let c = &e.c;
                let [b1, b2, b3] = c.b;
                let lo = Sd::atan2(b1, b3);
                let hi = Sd::atan2(b2, b3.mul(Sd::new(e.kp, e.kp_exp)));
                if c.frame.sign[2] * c.s[2] > 0.0 {
                    Some((lo, hi))
                } else {
                    Some((PI - hi, PI - lo))
                }
            }
            Motion::Separatrix(_) => None,
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

impl Symmetric {
    fn omega(&self, omega0: &Vector3<f64>, t: f64) -> Vector3<f64> {
        let (a, b) = ((self.axis + 1) % 3, (self.axis + 2) % 3);
        let (s, c) = wrap(self.body_rate * ldexp(t, self.rho)).sin_cos();
        let mut w = *omega0;
        w[a] = c * omega0[a] - s * omega0[b];
        w[b] = s * omega0[a] + c * omega0[b];
        w
    }
}

impl Common {
    fn u(&self, t: f64) -> Dd {
        self.lambda * ldexp(t, self.rho) + self.u0
    }

    /// Body angular velocity from `(cn, sn, dn)`-like factors of the three canonical
    /// components, the first and the third times `2^kappa`.
    fn omega(&self, f: [f64; 3], kappa: i32) -> Vector3<f64> {
        let w = [0, 1, 2].map(|i| {
            let k = if i == 1 { 0 } else { kappa };
            let x = self.s[i] * self.b[i].x * f[i] / self.moments[i].x;
            ldexp(x, self.rho + self.b[i].e - self.moments[i].e + k)
        });
        self.frame.to_body(w)
    }

    /// The canonical momenta (units of `2^mu`), with their exponents.
    fn canonical_m(&self, f: [f64; 3], kappa: i32) -> [Sd; 3] {
        [0, 1, 2].map(|i| {
            let k = if i == 1 { 0 } else { kappa };
            Sd::new(self.s[i] * self.b[i].x * f[i], self.b[i].e + k)
        })
    }

    fn state(&self, t: f64, f: [f64; 3], kappa: i32, j: Dd) -> (Vector3<f64>, UnitQuaternion<f64>) {
        let m = self.canonical_m(f, kappa);
        let euler = if self.euler_cyclic {
            [m[1], m[2], m[0]]
        } else {
            m
        };
        let phi = wrap(self.base_rate * ldexp(t, self.rho) + self.coef * (j - self.j0));
        let e = if euler[0].e == euler[1].e && euler[1].e == euler[2].e {
            zxz_half_angles([euler[0].x, euler[1].x, euler[2].x], phi)
        } else {
            None
        };
        let q_euler = e.unwrap_or_else(|| {
            let (theta, psi) = theta_psi(euler);
            qz(phi) * qx(theta) * qz(psi)
        });
        (self.omega(f, kappa), self.q_l * q_euler * self.q_e_inv)
    }
}

impl Elliptic {
    /// `u = q K + v` with `|v| <= K/2` (up to rounding), in double-double (exact for `|u|` up
    /// to about `2^50 K`): the quotient from a double product, corrected by one where it is off.
    fn reduce_quarter(&self, u: Dd) -> (i64, Dd) {
        let k = self.k;
        let mut q = super::dd::round(u.hi * self.inv_k);
        let mut v = u - k * q;
        for _ in 0..2 {
            if v.hi > 0.5 * k.hi {
                q += 1.0;
            } else if v.hi < -0.5 * k.hi {
                q -= 1.0;
            } else {
                break;
            }
            v = u - k * q;
        }
        (q as i64, v)
    }

    /// `u + u0_q K = 2 K j + w`, `|w| <= K`; `w = q K + v`, `|v| <= K/2`: `(j, q, v, w)`.
    fn reduce(&self, u: Dd) -> (f64, i64, Dd, Dd) {
        if self.c.u0_q == 0 {
            let k2 = self.k * 2.0;
            let mut j = super::dd::round(u.hi * self.inv_k2);
            let mut w = u - k2 * j;
            for _ in 0..2 {
                if w.hi > self.k.hi {
                    j += 1.0;
                } else if w.hi < -self.k.hi {
                    j -= 1.0;
                } else {
                    break;
                }
                w = u - k2 * j;
            }
            let (q, v) = self.reduce_quarter(w);
            (j, q, v, w)
        } else {
            // The quarters of u0 are added as an integer, so that v keeps its digits.
            let (qr, v) = self.reduce_quarter(u);
            let qt = qr + self.c.u0_q;
            let (j, q) = if qt.rem_euclid(2) == 0 {
                (qt.div_euclid(2), 0)
            } else if v.hi >= 0.0 {
                ((qt + 1).div_euclid(2), -1)
            } else {
                ((qt - 1).div_euclid(2), 1)
            };
            (j as f64, q, v, self.k * (q as f64) + v)
        }
    }

    /// `(sn, cn, dn)` and (if `WITH_J`, else zero) `J` at the phase `u + u0_q K`, with `cn`
    /// and `dn` in units of `2^kappa`.
    fn phase<const WITH_J: bool>(&self, u: Dd) -> (f64, f64, f64, Dd, i32) {
        let (j, q, v, w) = self.reduce(u);
        let (s, c, d, kappa, jw) = match self.functions {
            Functions::Hyperbolic => self.reduced_hyperbolic(q, v, w),
            Functions::Landen => {
                let (s, c, d) = self.landen.quarter(q, v.to_f64(), self.kp);
                let jw = if !WITH_J {
                    Dd::ZERO
                } else if let Some(theta) = &self.theta {
                    theta.j(w)
                } else {
                    self.j_reduced(w, s, c, d)
                };
                (s, c, d, 0, jw)
            }
            Functions::Corrected => {
                let (s, c, d) = self.corrected(q, v);
                let jw = if WITH_J {
                    self.j_reduced(w, s, c, d)
                } else {
                    Dd::ZERO
                };
                (s, c, d, 0, jw)
            }
        };
        let jj = if WITH_J {
            self.j_half * j + jw
        } else {
            Dd::ZERO
        };
        let sg = if j.rem_euclid(2.0) == 1.0 { -1.0 } else { 1.0 };
        (sg * s, sg * c, d, jj, kappa)
    }

    /// `sn, cn, dn (q K + v)` for `2^-54 <= k' < 2^-27`, `|v| <= K/2`: with `a = k'^2/4`,
    /// `sn v = tanh v + a (tanh v - v sech^2 v)`, `cn v = sech v - a tanh v (sinh v - v sech v)`,
    /// `dn v = sech v + a tanh v (sinh v + v sech v)` (DLMF 22.10.4-6; the corrections are at most
    /// `k'/4` relative, the next terms `O(k'^2)`), then the shifts by `K` (DLMF 22.4.3).
    fn corrected(&self, q: i64, v: Dd) -> (f64, f64, f64) {
        let (th, sech, sh, _, k) = hyperbolic(v);
        let (sech, sh, z) = (ldexp(sech, k), ldexp(sh, -k), v.to_f64());
        let a = 0.25 * self.mc;
        let s = th + a * (th - z * sech * sech);
        let c = sech - a * th * (sh - z * sech);
        let d = sech + a * th * (sh + z * sech);
        let kp = self.kp;
        match q.rem_euclid(4) {
            0 => (s, c, d),
            1 => (c / d, -kp * s / d, kp / d),
            2 => (-s, -c, d),
            _ => (-c / d, kp * s / d, kp / d),
        }
    }

    /// `k' < 2^-54`: `(sn, cn / 2^kappa, dn / 2^kappa, kappa, J)` of `|w| <= K` from the
    /// hyperbolic functions of `v`, `w = q K + v`, `|v| <= K/2` (module doc; the corrections are
    /// `O(k')` relative).
    fn reduced_hyperbolic(&self, q: i64, v: Dd, w: Dd) -> (f64, f64, f64, i32, Dd) {
        let (th, sech, sh, ch, k) = hyperbolic(v);
        let (s, c, d, kappa) = match q.rem_euclid(4) {
            0 => (th, sech, sech, k),
            2 => (-th, -sech, sech, k),
            // sn(K + v) = cn v / dn v = 1, cn(K + v) = -k' sn v / dn v, dn(K + v) = k' / dn v.
            1 => (1.0, -self.kp * sh, self.kp * ch, self.kp_exp - k),
            _ => (-1.0, self.kp * sh, self.kp * ch, self.kp_exp - k),
        };
        let nu = self.c.nu;
        let s2 = s * s;
        let j = if s2 * (2.0 + nu) <= 1.0 {
            // |w| well inside the quarter: cn, dn = O(1).
            let (c, d) = (ldexp(c, kappa), ldexp(d, kappa));
            Dd::new(s * s2 / 3.0 * carlson_rj(c * c, d * d, 1.0, 1.0 + nu * s2))
        } else {
            // J(w) = (|w| - Jc(|w|)) / (1 + nu), Jc(w) = atan(sqrt(nu) |sn w|) / sqrt(nu).
            let r = nu.sqrt();
            let jc = if r > 0.0 {
                (r * s.abs()).atan() / r
            } else {
                s.abs()
            };
            let jabs = (w.abs() - jc) / (self.c.nu_dd + 1.0);
            if w.hi < 0.0 {
                -jabs
            } else {
                jabs
            }
        };
        (s, c, d, kappa, j)
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

/// The steady rotation of `omega0` (a body at rest, a sphere, a spin about a principal axis)
/// and its rate.
fn steady(omega0: &Vector3<f64>) -> (Motion, Xd) {
    let norm = omega0
        .iter()
        .fold(Xd::ZERO, |a, w| a + Xd::prod(*w, *w))
        .sqrt();
    if norm.is_zero() {
        let motion = Motion::Steady {
            axis: Vector3::zeros(),
            rate: Dd::ZERO,
            rho: 0,
        };
        return (motion, Xd::ZERO);
    }
    let rho = norm.e;
    let rate = norm.ldexp(-rho).to_dd();
    let axis = omega0.map(|w| ldexp(w, -rho) / rate.hi);
    (Motion::Steady { axis, rate, rho }, norm)
}

/// The symmetric top (two equal moments): its regime, motion and fastest rate.
fn symmetric(moments: &Vector3<f64>, omega0: &Vector3<f64>, mx: &[Xd; 3]) -> (Regime, Motion, Xd) {
    let (i0, i1, i2) = (moments[0], moments[1], moments[2]);
    let s = if i0 == i1 {
        2
    } else if i1 == i2 {
        0
    } else {
        1
    };
    let it = moments[(s + 1) % 3];
    let is = moments[s];
    let g = mx.iter().fold(Xd::ZERO, |acc, x| acc + *x * *x).sqrt();
    let nutation = g / it;
    let body = Xd::sum(is, -it).mul_f64(omega0[s]) / it;
    // Time in units of the faster of the two rates (the slower one, if below 2^-1022 of
    // it, turns by nothing within the time bound and is dropped).
    let rate = if nutation.abs_lt(body) {
        body.abs()
    } else {
        nutation
    };
    let rho = rate.e;
    // m0 / G, each component rounded once.
    let m_dir = Vector3::from_fn(|i, _| ldexp(mx[i].m.to_f64() / g.m.hi, mx[i].e - g.e));
    let normal = |x: Dd| {
        if x.hi.abs() < f64::MIN_POSITIVE {
            Dd::ZERO
        } else {
            x
        }
    };
    let sym = Symmetric {
        axis: s,
        rho,
        nutation_rate: normal(nutation.ldexp(-rho).to_dd()),
        m_dir,
        body_rate: normal(body.ldexp(-rho).to_dd()),
    };
    (Regime::Symmetric { axis: s }, Motion::Symmetric(sym), rate)
}

/// An asymmetric body's motion in its canonical frame, before the separatrix and the
/// elliptic regimes part: what both need.
struct Asymmetric {
    common: Common,
    /// `Delta_2`: its sign is the regime, zero on the separatrix.
    delta2: Xd,
    /// The complementary parameter `m_c`.
    mc_x: Xd,
    /// `|L|`, its exponent `mu`, and the momenta in the canonical frame (exact products).
    g: Xd,
    mu: i32,
    n: [Xd; 3],
    /// The canonical momenta and the amplitudes `B1, B2`, in units of `2^mu`.
    m: [Sd; 3],
    b1: Sd,
    b2: Sd,
    i2: f64,
    i3: f64,
    s3: f64,
    lambda: Xd,
    nu_dd: Dd,
    /// The largest precession rate.
    phi_rate: Xd,
    polar: usize,
}

impl Asymmetric {
    /// The canonical frame of an asymmetric body (moments ascending at `order`), its
    /// amplitudes, rates and the constants of the precession.
    fn new(
        moments: &Vector3<f64>,
        omega0: &Vector3<f64>,
        mx: &[Xd; 3],
        q0: &UnitQuaternion<f64>,
        order: [usize; 3],
    ) -> Result<Self> {
        let [lo, mid, hi] = order;
        // Units: momenta 2^mu (about the largest |I_i w_i|), moments 2^iota (about the largest
        // moment), both even powers; time 2^-rho, rho = mu - iota.
        let mmax = mx
            .iter()
            .copied()
            .fold(Xd::ZERO, |a, x| if a.abs_lt(x) { x.abs() } else { a });
        let mu = even_exponent(mmax);
        let iota = even_exponent(Xd::new(moments.max()));
        let rho = mu - iota;
        // The double products I_i w_i (rounded once), in units of 2^mu.
        let mh = [0, 1, 2].map(|i| {
            if omega0[i] == 0.0 {
                Sd::new(moments[i] * omega0[i], 0) // a zero with its sign
            } else {
                Sd::new(mx[i].m.to_f64(), mx[i].e - mu)
            }
        });
        let ih = |i: usize| Xd::new(moments[i]);
        // Delta_2 = m_lo^2 (I_lo - I_mid)/I_lo + m_hi^2 (I_hi - I_mid)/I_hi
        //         = I_lo w_lo^2 (I_lo - I_mid) + I_hi w_hi^2 (I_hi - I_mid), exactly: its sign
        // is the regime and it is zero exactly on the separatrix.
        let delta2 = exact_sum_a_b2_diff(&[
            (moments[lo], omega0[lo], moments[lo], moments[mid]),
            (moments[hi], omega0[hi], moments[hi], moments[mid]),
        ]);
        let (polar, other) = if delta2.is_negative() {
            (lo, hi)
        } else {
            (hi, lo)
        };
        let frame = Frame::new([other, mid, polar]);
        let mc3 = frame.to_canonical_sd(&mh);
        let [i1, i2, i3] = frame.index.map(|i| moments[i]);
        let ic = frame.index.map(|i| ih(i).to_sd(iota));
        let [m1, m2, m3] = mc3;
        let d21 = Xd::sum(i2, -i1);
        let d31 = Xd::sum(i3, -i1);
        let d32 = Xd::sum(i3, -i2);
        let [n1, n2, n3] = [0, 1, 2].map(|i| mx[frame.index[i]]);
        let sq = |x: Xd| x * x;
        let delta1 = sq(n2) * d21 / i2 + sq(n3) * d31 / i3;
        let mdelta3 = sq(n1) * d31 / i1 + sq(n2) * d32 / i2;
        let g = (sq(n1) + sq(n2) + sq(n3)).sqrt();
        let lambda = (delta1 * d32 / Xd::new(i1).mul_f64(i2).mul_f64(i3)).sqrt();
        // Amplitudes, as hypotenuses (no cancellation, no overflow).
        let r = |x: Xd| x.to_sd(0).sqrt();
        let b1 = Sd::hypot(m1, m2.mul(r(Xd::new(i1) * d32 / d31.mul_f64(i2))));
        let b2 = Sd::hypot(m1.mul(r(Xd::new(i2) * d31 / d32.mul_f64(i1))), m2);
        let b3 = Sd::hypot(m2.mul(r(Xd::new(i3) * d21 / d31.mul_f64(i2))), m3);
        let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
        let s3 = sign(m3.x);
        // Euler polar axis: canonical axis 1 or 3, so that the other one, x, has 1/I_x
        // closest to 1/I2: then phi' = G/I_x + G (1/I2 - 1/I_x) (weight in [0, 1]) has the
        // smallest varying part (never more than a factor 2 of cancellation).
        let polar_c1 = {
            let [j1, j2, j3] = ic.map(|x| x.to_f64());
            if ic.iter().all(|x| x.e == 0) {
                (1.0 / j2 - 1.0 / j3).abs() <= (1.0 / j2 - 1.0 / j1).abs()
            } else {
                // |1/I2 - 1/I3| <= |1/I2 - 1/I1|  <=>  |I3 - I2| I1 <= |I2 - I1| I3.
                !(d21.abs().mul_f64(i3)).abs_lt(d32.abs().mul_f64(i1))
            }
        };
        let i_x = if polar_c1 { i3 } else { i1 };
        let base_rate = g / i_x;
        // C = G (1/I2 - 1/I_x) (B2/Bh)^2 / lambda and nu, Bh = B3 or B1.
        let dxm = Xd::sum(i_x, -i2) / Xd::new(i2).mul_f64(i_x);
        let (ratio, nu) = if polar_c1 {
            // G^2 - m1^2 = B3^2 + B1^2 sn^2: nu = B1^2/B3^2 = I1 (-Delta3) / (I3 Delta1).
            (
                Xd::new(i2) * mdelta3 * d31 / (d32.mul_f64(i3) * delta1),
                Xd::new(i1) * mdelta3 / delta1.mul_f64(i3),
            )
        } else {
            // G^2 - m3^2 = B1^2 + m B3^2 sn^2: nu = m B3^2/B1^2 = I3 (I2 - I1) / (I1 (I3 - I2)).
            (
                Xd::new(i2) * d31 / d32.mul_f64(i1),
                Xd::new(i3) * d21 / d32.mul_f64(i1),
            )
        };
        let coef = g * dxm * ratio / lambda;
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
        let nu_dd = nu.to_dd();
        let lambda_dd = checked_dd(lambda.ldexp(-rho), "rates")?;
        let base_dd = checked_dd(base_rate.ldexp(-rho), "rates")?;
        let coef_dd = coef.to_dd();
        if !(coef_dd.hi.is_finite() && nu_dd.hi.is_finite()) {
            return Err(too_wide("rates"));
        }
        // The largest precession rate, |G/I_x| + |C| lambda / (1 + nu).
        let phi_rate = base_rate.abs() + coef.abs() * lambda / (Xd::new(1.0) + nu);
        let common = Common {
            frame,
            moments: ic,
            b: [b1, b2, b3],
            s: [sign(m1.x), s3 * sign(i3 - i2), s3],
            rho,
            lambda: lambda_dd,
            u0: Dd::ZERO,
            u0_q: 0,
            euler_cyclic: polar_c1,
            base_rate: base_dd,
            coef: coef_dd,
            nu: nu_dd.to_f64(),
            nu_dd,
            j0: Dd::ZERO,
            q_l,
            q_e_inv: q_e.inverse(),
        };
        let mc_x = delta2 * d31 / (delta1 * d32);
        Ok(Self {
            common,
            delta2,
            mc_x,
            g,
            mu,
            n: [n1, n2, n3],
            m: [m1, m2, m3],
            b1,
            b2,
            i2,
            i3,
            s3,
            lambda,
            nu_dd,
            phi_rate,
            polar,
        })
    }

    /// The separatrix (tanh/sech form).
    fn separatrix(self) -> (Regime, Motion, Xd) {
        let Self {
            mut common,
            g,
            mu,
            n: [n1, n2, n3],
            i2,
            i3,
            s3,
            phi_rate,
            ..
        } = self;
        let frame = common.frame;
        let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
        let sq = |x: Xd| x * x;
        // Separatrix: s2 = s1 s3 sign(I3 - I2); e^u0 = (G + s2 m2) / hypot(m1, m3).
        common.s[1] = common.s[0] * s3 * sign(i3 - i2);
        common.b[1] = g.to_sd(mu);
        let y = n2.mul_f64(common.s[1] * frame.sign[1]);
        let h = (sq(n1) + sq(n3)).sqrt();
        let e0 = if y.is_negative() {
            h / (g - y)
        } else {
            (g + y) / h
        };
        let u0 = e0.ln();
        common.u0 = u0;
        let mut sep = Separatrix { c: common };
        sep.c.j0 = sep.j(u0);
        (
            Regime::Separatrix,
            Motion::Separatrix(Box::new(sep)),
            phi_rate,
        )
    }

    /// The elliptic regime: about the axis of the smallest or the largest moment.
    fn elliptic(self) -> (Regime, Motion, Xd) {
        let kp_x = self.mc_x.sqrt();
        let mut ell = if kp_x.e >= -54 {
            self.elliptic_functions(kp_x)
        } else {
            self.hyperbolic_functions(kp_x)
        };
        let Self {
            m: [m1, m2, _],
            b1,
            b2,
            lambda,
            phi_rate,
            polar,
            ..
        } = self;
        if ell.functions == Functions::Corrected {
            // One Newton step on u0 with the accurate functions (u0 from R_F is good to eps |u0|,
            // which a decaying cn or dn would feel as a relative error): on cn where
            // |cn| <= |sn| (well conditioned there, cn(K - v) = k' sd v), on sn elsewhere.
            let c0 = m1.div(b1).to_f64();
            let s0 = m2.mul_f64(ell.c.s[1]).div(b2).to_f64();
            let (s, c, d, _, _) = ell.phase::<false>(ell.c.u(0.0));
            let delta = if c0.abs() <= s0.abs() {
                (c - c0) / (s * d)
            } else {
                (s0 - s) / (c * d)
            };
            ell.c.u0 = ell.c.u0 + delta;
        }
        ell.c.j0 = ell.phase::<true>(ell.c.u(0.0)).3;
        // The fastest angle: the precession or the phase of omega, 2 pi lambda / 4K.
        let omega_rate = (lambda * Xd::from_dd(Dd::TAU)) / Xd::from_dd(ell.k * 4.0);
        let rate = if phi_rate.abs_lt(omega_rate) {
            omega_rate
        } else {
            phi_rate
        };
        (
            Regime::AboutAxis(polar),
            Motion::Elliptic(Box::new(ell)),
            rate,
        )
    }

    /// The elliptic regime with `k' >= 2^-54`: Jacobi's functions of `m_c`.
    fn elliptic_functions(&self, kp_x: Xd) -> Elliptic {
        let mut common = self.common.clone();
        let (mc_x, nu_dd, b1, b2) = (self.mc_x, self.nu_dd, self.b1, self.b2);
        let [m1, m2, _] = self.m;
        let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
        // Elliptic: the sign of m1 is carried by cn.
        common.s[0] = 1.0;
        let mc_dd = mc_x.to_dd();
        let mc = mc_dd.to_f64();
        let k = ellipk_dd(mc_dd);
        let kp_dd = mc_dd.sqrt();
        let [half, jc_quarter] = cel_many(
            kp_dd,
            nu_dd + 1.0,
            [(Dd::ZERO, Dd::ONE), (Dd::ONE, Dd::ZERO)],
        );
        let j_half = half * 2.0;
        // u0 from cn u0 = m1/B1, sn u0 = s2 m2/B2: u0 = F(am u0) = s R_F(c^2, c^2 + mc s^2, 1),
        // reflected about K when cn < 0. In the outer half (c^2 < k'/(1 + k') = cn^2(K/2)),
        // u0 = +-(K - v) with y = sd v = |c| / k' (cn(K - v) = k' sd v):
        // v = y R_F(1 - c^2, 1, 1 + k^2 y^2) (DLMF 19.25.5 with sn^2 = y^2/(1 + k^2 y^2)), so
        // that a small cn keeps its digits.
        let c0 = m1.div(b1).to_f64().clamp(-1.0, 1.0);
        let s0 = m2.mul_f64(common.s[1]).div(b2).to_f64().clamp(-1.0, 1.0);
        let kp = kp_dd.to_f64();
        if c0 * c0 < kp / (1.0 + kp) {
            let y = c0.abs() / kp;
            let v = y * carlson_rf(1.0 - c0 * c0, 1.0, 1.0 + (1.0 - mc) * (y * y));
            // u0 = sign(s0) (K -+ v), -+ as cn >= 0 or < 0.
            common.u0_q = sign(s0) as i64;
            common.u0 = Dd::new(v * -sign(s0) * sign(c0));
        } else {
            let f = s0 * carlson_rf(c0 * c0, c0 * c0 + mc * s0 * s0, 1.0);
            common.u0 = if c0 >= 0.0 {
                Dd::new(f)
            } else {
                k * (2.0 * sign(s0)) - f
            };
        }
        let functions = if kp_x.e >= -27 {
            Functions::Landen
        } else {
            Functions::Corrected
        };
        let theta = if functions == Functions::Landen {
            ThetaJ::new(mc, k, common.nu, j_half)
        } else {
            None
        };
        Elliptic {
            c: common,
            mc,
            kp,
            kp_exp: 0,
            functions,
            theta,
            landen: Landen::new(mc),
            k,
            inv_k: 1.0 / k.hi,
            inv_k2: 0.5 / k.hi,
            j_half,
            jc_quarter,
        }
    }

    /// The elliptic regime with `k' < 2^-54`: `K` by the AGM, the functions hyperbolic.
    fn hyperbolic_functions(&self, kp_x: Xd) -> Elliptic {
        let mut common = self.common.clone();
        let (nu_dd, b1, b2) = (self.nu_dd, self.b1, self.b2);
        let [m1, m2, _] = self.m;
        let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
        // Elliptic: the sign of m1 is carried by cn.
        common.s[0] = 1.0;
        // k' < 2^-54: K = pi / (2 AGM((1 + k')/2, sqrt(k'))), the rest hyperbolic.
        let kp = kp_x.to_sd(0);
        let a1 = (Dd::ONE + kp_x.to_dd()) * 0.5;
        let k = Dd::PI / (a1 * agm1(kp_x.sqrt().to_dd() / a1) * 2.0);
        let jc_quarter = cel(
            Dd::new(kp_x.to_f64().max(1e-300)),
            nu_dd + 1.0,
            Dd::ONE,
            Dd::ZERO,
        );
        let j_half = (k - jc_quarter) * 2.0 / (nu_dd + 1.0);
        let c0 = m1.div(b1);
        let s0 = m2.mul_f64(common.s[1]).div(b2).to_f64().clamp(-1.0, 1.0);
        let ca = Xd::new(c0.x.abs()).ldexp(c0.e);
        if (ca * ca).abs_lt(kp_x) {
            // Near u = K: cn(K - v) = k' sinh v; u0 = sign(s0) (K -+ v).
            let v = asinh_xd(ca / kp_x);
            common.u0_q = sign(s0) as i64;
            common.u0 = v * (-sign(s0) * sign(c0.x));
        } else {
            // sinh u = sn / cn.
            let f = asinh_xd(Xd::new(s0.abs()) / ca) * sign(s0);
            if c0.x >= 0.0 {
                common.u0 = f;
            } else {
                common.u0_q = 2 * sign(s0) as i64;
                common.u0 = -f;
            }
        }
        Elliptic {
            c: common,
            mc: 0.0,
            kp: kp.x,
            kp_exp: kp.e,
            functions: Functions::Hyperbolic,
            theta: None,
            landen: Landen::new(1.0),
            k,
            inv_k: 1.0 / k.hi,
            inv_k2: 0.5 / k.hi,
            j_half,
            jc_quarter,
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
            let c = f.to_canonical_sd(&[0, 1, 2].map(|i| Sd::new(v[i], 0)));
            let c = c.map(|x| x.to_f64());
            let back = f.to_body(c);
            assert_eq!(back, v);
            // The canonical components are the components in the rotated frame.
            let w = r.inverse() * v;
            assert!((Vector3::from(c) - w).norm() < 1e-15);
        }
    }

    #[test]
    fn half_angles_are_the_euler_product() {
        // Against qz(phi) qx(theta) qz(psi) from the angles, on every branch: e_z and e_y of
        // both signs, e_x = +-0 on the negative y axis (psi = +-pi), theta near 0 and pi.
        let cases = [
            [0.3, 0.5, 0.8],
            [-0.3, 0.5, -0.8],
            [0.3, -0.5, 0.8],
            [-0.3, -0.5, -0.8],
            [0.0, -0.5, 0.1],
            [-0.0, -0.5, 0.1],
            [1e-9, 2e-9, 1.0],
            [1e-9, -2e-9, -1.0],
            [2.0, 0.0, 0.0],
        ];
        for e in cases {
            for phi in [0.0, 1.0, -3.0, std::f64::consts::PI] {
                let sd = e.map(|x| Sd::new(x, 0));
                let (theta, psi) = theta_psi(sd);
                let want = qz(phi) * qx(theta) * qz(psi);
                let got = zxz_half_angles(e, phi).unwrap();
                assert!(
                    (got.coords - want.coords).norm() <= 4.0 * EPS,
                    "{e:?} {phi}: {got:?} vs {want:?}"
                );
            }
        }
        assert!(zxz_half_angles([0.0, 0.0, 1.0], 0.3).is_none());
    }

    #[test]
    fn theta_series_of_j_agrees_with_carlson() {
        // J in theta-function form against the Carlson path (R_J; itself checked against
        // mpmath through the motion's tests) over a period and far out, from m ~ 0.02 to the
        // largest nome the series takes (q ~ 0.5, 1 - m ~ 2e-6), nu from 1e-6 to 1e6.
        let q = UnitQuaternion::identity();
        let mut used = 0;
        for (moments, omega0) in [
            ([1.0, 2.0, 3.0], [0.3, 0.5, 0.8]),
            ([1.0, 2.0, 3.0], [0.8, 0.5, 0.3]),
            ([2.0, 3.0, 6.0], [1.5, 0.2, 0.52]),
            ([2.0, 3.0, 6.0], [1.5, 0.2, 0.500_5]),
            ([2.0, 3.0, 6.0], [1.5, 0.2, 0.500_000_5]),
            ([1.0, 1.000_001, 3.0], [0.3, 0.5, 0.8]),
            ([1.0, 2.999_999, 3.0], [0.3, 0.5, 0.8]),
            ([1.0, 1e3, 1e6], [0.3, 1e-3, 1e-6]),
        ] {
            let fr = FreeRotation::new(Vector3::from(moments), Vector3::from(omega0), q).unwrap();
            let Motion::Elliptic(e) = &fr.motion else {
                panic!("{moments:?}")
            };
            if e.theta.is_none() {
                continue;
            }
            used += 1;
            let mut carlson = (**e).clone();
            carlson.theta = None;
            let scale = (e.j_half * 0.5).to_f64().abs();
            for i in -40..=40 {
                let u = e.k * (0.05 * f64::from(i)) + e.k * 1e4;
                let a = e.phase::<true>(u).3 - e.j_half * 5e3;
                let b = carlson.phase::<true>(u).3 - e.j_half * 5e3;
                assert!(
                    (a - b).to_f64().abs() <= 8.0 * EPS * scale,
                    "{moments:?} {omega0:?} {i}: {a:?} vs {b:?}"
                );
            }
        }
        assert!(used >= 4, "{used}");
    }

    #[test]
    fn wrap_reduces_double_double_angles() {
        let x = Dd::TAU * 1e12 + 0.25;
        assert!((wrap(x) - 0.25).abs() < 1e-15);
        assert!((wrap(Dd::new(-4.0)) - (-4.0 + std::f64::consts::TAU)).abs() < 1e-15);
        // Far out, where the double quotient by 2 pi can be off by one: the remainder is still
        // in [-pi, pi] and exact to the rounding of x.
        for k in [1e14, 1e15, 3e15] {
            let near_pi = std::f64::consts::PI - 1e-12;
            for r in [near_pi, -near_pi, 3.0, -3.1, 0.5] {
                let x = Dd::TAU * k + r;
                let w = wrap(x);
                assert!(w.abs() <= std::f64::consts::PI, "{k} {r}: {w}");
                assert!((w - r).abs() < 1e-14, "{k} {r}: {w}");
            }
        }
    }

    const EPS: f64 = f64::EPSILON;

    #[test]
    fn hyperbolic_functions_keep_relative_accuracy() {
        // sech(700.5) = 1.196039223727958241282421466099...e-304 (mpmath, 40 digits).
        let (th, sech, sh, ch, k) = hyperbolic(Dd::new(700.5));
        assert_eq!(th, 1.0);
        assert_eq!(tanh_sech_dd(Dd::new(700.5)), (th, sech, k));
        for u in [1e-10, 0.3, -2.5, 40.0] {
            let (a, b, c, _, k) = hyperbolic(Dd::new(u));
            let (x, y, z) = tanh_sech_dd(Dd::new(u));
            assert!(
                (a - x).abs() <= EPS && (b - y).abs() <= EPS * b && z == k,
                "{u}"
            );
            assert!((a - u.tanh()).abs() <= 2.0 * EPS && c.is_finite());
        }
        let got = ldexp(sech, k);
        assert!((got - 1.196_039_223_727_958_3e-304).abs() <= 1.2e-304 * f64::EPSILON);
        assert!((ldexp(ch, -k) * got - 1.0).abs() <= 2.0 * f64::EPSILON);
        assert!((ldexp(sh, -k) * got - 1.0).abs() <= 2.0 * f64::EPSILON);
        let (th, sech, _, _, k) = hyperbolic(Dd::new(-1e-12));
        assert_eq!((th, sech, k), (-1e-12, 1.0, 0));
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
