//! Torque-free fixed-step runs of several bodies at once, one body per SIMD lane.
//!
//! A block of up to [`LANES`] bodies sharing the output times and the method (`rk4`, the
//! splitting or the midpoint rule, without torque or rotors) is integrated as a
//! structure of arrays: each variable is an [`X`], one `f64` per body, and every step is the
//! scalar method's step written on [`X`], the same IEEE operations in the same order in each
//! lane (no FMA, see [`crate::simd`]). So each body's numbers are bit for bit those of
//! [`super::integrate_body`] alone, whatever the other bodies of its block: the tests compare
//! the two. The loops between two looks at the monitor run through [`crate::simd::dispatch`]
//! (AVX2 where the CPU has it), rk4's and the midpoint rule's through
//! [`crate::simd::dispatch_wide`] (AVX-512 where the CPU has it; see [`LaneStepper::WIDE`]).
//!
//! What differs between lanes is handled per lane: the implicit midpoint rule iterates until
//! every lane has met the scalar stopping rule, a converged lane keeping its value while the
//! others iterate; the splitting's rare large angles take the scalar library path in their lane
//! only; a lane that fails (a step that does not converge, an output that is not finite) gets
//! the error its body would get alone and leaves the block, which goes on with the others.

// Loops over the lanes index several arrays at once: the shape the compiler vectorises.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, Div, Mul, Neg, Sub};

use nalgebra::{UnitQuaternion, Vector3, Vector4};

use super::loops::{check_omega_output, checked_unit, fixed_total, segments, substeps};
use super::method::{Method, Options, Stats};
use super::midpoint;
use super::state::{Moments, State};
use crate::monitor::{Monitor, Progress};
use crate::{Error, Result};

/// Bodies integrated together: two 256-bit vectors (a multiple of 4). Measured on Zen 4 (one
/// thread, 1e5 bodies, per body-step) against 4 lanes: the splitting 33.6 vs 59.1 ns (two
/// independent chains of dependent rotations to overlap), rk4 5.0 vs 6.9 ns (AVX-512's
/// 512-bit vectors), the midpoint rule 20.8 vs 20.0 ns (each lane iterates as long as the
/// slowest of its block: two chains of Newton iterations overlap, a few more iterations).
pub(crate) const LANES: usize = 8;

/// A set of lanes, bit `l` for lane `l`.
type Mask = u32;

/// The storage of an [`X`]: on x86-64 256-bit vectors, which makes the compiler carry the state
/// from step to step as vectors (so that it vectorises each step's arithmetic, lane by lane,
/// rather than keeping scalars); the arithmetic itself is written on `[f64; LANES]`.
#[cfg(target_arch = "x86_64")]
type Raw = [std::arch::x86_64::__m256d; LANES / 4];
#[cfg(not(target_arch = "x86_64"))]
type Raw = [f64; LANES];

/// One `f64` per lane; arithmetic is lane by lane.
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub(crate) struct X(Raw);

impl X {
    #[inline(always)]
    fn from_lanes(v: [f64; LANES]) -> Self {
        // SAFETY: both are `LANES` f64, any bits valid.
        #[allow(clippy::useless_transmute)]
        X(unsafe { std::mem::transmute::<[f64; LANES], Raw>(v) })
    }

    /// The lanes.
    #[inline(always)]
    pub(crate) fn lanes(self) -> [f64; LANES] {
        // SAFETY: as in `from_lanes`.
        #[allow(clippy::useless_transmute)]
        unsafe {
            std::mem::transmute::<Raw, [f64; LANES]>(self.0)
        }
    }

    #[inline(always)]
    fn splat(v: f64) -> Self {
        X::from_lanes([v; LANES])
    }

    #[inline(always)]
    fn lane(self, l: usize) -> f64 {
        self.lanes()[l]
    }

    #[inline(always)]
    fn set_lane(&mut self, l: usize, v: f64) {
        let mut a = self.lanes();
        a[l] = v;
        *self = X::from_lanes(a);
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        let mut r = self.lanes();
        for v in &mut r {
            *v = f(*v);
        }
        X::from_lanes(r)
    }

    #[inline(always)]
    fn zip(self, o: X, f: impl Fn(f64, f64) -> f64) -> Self {
        let (mut r, o) = (self.lanes(), o.lanes());
        for l in 0..LANES {
            r[l] = f(r[l], o[l]);
        }
        X::from_lanes(r)
    }

    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }

    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f64::abs)
    }

    /// nalgebra's (simba's) `simd_max` of `f64`: `self` if `self >= o`, else `o`.
    #[inline(always)]
    fn simd_max(self, o: X) -> Self {
        self.zip(o, |a, b| if a >= b { a } else { b })
    }

    /// The lanes where `f` holds.
    #[inline(always)]
    fn mask(self, f: impl Fn(f64) -> bool) -> Mask {
        let a = self.lanes();
        let mut m = 0;
        for l in 0..LANES {
            m |= Mask::from(f(a[l])) << l;
        }
        m
    }

    /// The lanes where `f(self, o)` holds.
    #[inline(always)]
    fn mask2(self, o: X, f: impl Fn(f64, f64) -> bool) -> Mask {
        let (a, b) = (self.lanes(), o.lanes());
        let mut m = 0;
        for l in 0..LANES {
            m |= Mask::from(f(a[l], b[l])) << l;
        }
        m
    }

    /// `a` in the lanes of `mask`, `b` elsewhere.
    #[inline(always)]
    fn select(mask: Mask, a: X, b: X) -> Self {
        let (a, mut r) = (a.lanes(), b.lanes());
        for l in 0..LANES {
            if mask >> l & 1 != 0 {
                r[l] = a[l];
            }
        }
        X::from_lanes(r)
    }
}

macro_rules! lanewise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for X {
            type Output = X;
            #[inline(always)]
            fn $method(self, o: X) -> X {
                self.zip(o, |a, b| a $op b)
            }
        }
        impl $trait<f64> for X {
            type Output = X;
            #[inline(always)]
            fn $method(self, o: f64) -> X {
                self.map(|a| a $op o)
            }
        }
        impl $trait<X> for f64 {
            type Output = X;
            #[inline(always)]
            fn $method(self, o: X) -> X {
                o.map(|b| self $op b)
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for X {
    type Output = X;
    #[inline(always)]
    fn neg(self) -> X {
        self.map(|a| -a)
    }
}

type V3 = [X; 3];
type V4 = [X; 4];
/// The variables of a block: a 3-vector per lane (the angular velocity, or what the method
/// integrates instead) and the raw quaternions `(x, y, z, w)`.
type Vars = (V3, V4);

/// Per-lane vectors (`x(l)` to lane `l` for `l < n`), lanes past `n` repeating lane 0.
///
/// Filled as plain arrays and converted once: a lane set in a vector register's image
/// ([`X::set_lane`]) stores the whole vector and reloads it, a store-forwarding stall per entry
/// (8% of a one-step batch call).
fn gather3(n: usize, x: impl Fn(usize) -> Vector3<f64>) -> V3 {
    let mut v = [[0.0; LANES]; 3];
    for l in 0..LANES {
        let xl = x(if l < n { l } else { 0 });
        for i in 0..3 {
            v[i][l] = xl[i];
        }
    }
    v.map(X::from_lanes)
}

/// [`gather3`] for four components.
fn gather4(n: usize, x: impl Fn(usize) -> Vector4<f64>) -> V4 {
    let mut v = [[0.0; LANES]; 4];
    for l in 0..LANES {
        let xl = x(if l < n { l } else { 0 });
        for i in 0..4 {
            v[i][l] = xl[i];
        }
    }
    v.map(X::from_lanes)
}

/// The lanes of each component, as arrays (the shape of the loops over lanes).
#[inline(always)]
fn arrays3(v: &V3) -> [[f64; LANES]; 3] {
    [v[0].lanes(), v[1].lanes(), v[2].lanes()]
}

/// [`arrays3`] for a quaternion.
#[inline(always)]
fn arrays4(v: &V4) -> [[f64; LANES]; 4] {
    [v[0].lanes(), v[1].lanes(), v[2].lanes(), v[3].lanes()]
}

/// `(v0^2 + v1^2) + v2^2`: nalgebra's `norm_squared` of a 3-vector.
#[inline(always)]
fn norm_squared3(v: &V3) -> X {
    v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
}

/// `sqrt((v0^2 + v2^2) + (v1^2 + v3^2))`: nalgebra's `norm` of a 4-vector.
#[inline(always)]
fn norm4(v: &V4) -> X {
    ((v[0] * v[0] + v[2] * v[2]) + (v[1] * v[1] + v[3] * v[3])).sqrt()
}

/// `a x b` as nalgebra computes it.
#[inline(always)]
fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// nalgebra's `UnitQuaternion * Vector3` of the quaternion `(v, s)`: `t = 2 v x r`,
/// `(t s + v x t) + r`.
#[inline(always)]
fn rotate(v: &V3, s: X, r: &V3) -> V3 {
    let c = cross(v, r);
    let t = [c[0] * 2.0, c[1] * 2.0, c[2] * 2.0];
    let u = cross(v, &t);
    [
        (t[0] * s + u[0]) + r[0],
        (t[1] * s + u[1]) + r[1],
        (t[2] * s + u[2]) + r[2],
    ]
}

/// A fixed-step method on a block of lanes: the scalar [`super::stepper::Stepper`]'s step,
/// lane by lane.
pub(crate) trait LaneStepper {
    /// Whether the steps run through [`crate::simd::dispatch_wide`] (AVX-512's 32 registers
    /// where the CPU has them) rather than [`crate::simd::dispatch`]: measured per method.
    const WIDE: bool = false;

    /// The variables of the initial angular velocities and quaternions; by default themselves.
    #[inline(always)]
    fn vars(&self, w: V3, q: V4) -> Vars {
        (w, q)
    }

    /// The angular velocities of the variables; by default `y.0`.
    #[inline(always)]
    fn omega(&self, y: &Vars) -> V3 {
        y.0
    }

    /// A run starts from `y`.
    #[inline(always)]
    fn start(&mut self, y: &Vars) {
        let _ = y;
    }

    /// One step over `h` in every lane; returns the lanes of `live` whose step failed.
    fn step(&mut self, y: &mut Vars, h: f64, live: Mask) -> Mask;

    /// After each step, as the scalar method's `restore`.
    #[inline(always)]
    fn restore(&mut self, y: &mut Vars) {
        let _ = y;
    }

    /// The error of lane `l`'s failed step from `t` over `h`.
    #[cold]
    fn error(&self, l: usize, t: f64, h: f64) -> Error {
        let _ = (l, t, h);
        unreachable!("an explicit torque-free step cannot fail")
    }

    /// Evaluations of lane `l` in `steps` steps.
    fn evaluations(&self, steps: u64, l: usize) -> u64;
}

// ---------------------------------------------------------------------------------------------
// rk4 (see super::rk4)

/// Steps between two renormalisations of the quaternion (as `super::rk4`).
const RK4_RENORMALISE_EVERY: u32 = 64;

struct Rk4<const ATT: bool> {
    euler: V3,
    since: u32,
}

impl<const ATT: bool> LaneStepper for Rk4<ATT> {
    /// Measured on Zen 4: 1.3x faster per step at 4 lanes (the state, the four slopes and the
    /// constants fit in 32 registers, not in 16), and 8 lanes are one 512-bit vector.
    const WIDE: bool = true;

    /// Written as a loop over the lanes of the scalar step (`super::rk4`, `Moments::euler_rhs`,
    /// `quaternion_rate2`) on arrays, which the compiler vectorises as a whole.
    #[inline(always)]
    fn step(&mut self, (w, q): &mut Vars, h: f64, _live: Mask) -> Mask {
        let mut wa = arrays3(w);
        let mut qa = arrays4(q);
        let e = arrays3(&self.euler);
        let half = 0.5 * h;
        let quarter = 0.5 * half;
        let sixth = h / 6.0;
        let twelfth = 0.5 * sixth;
        for l in 0..LANES {
            let c = [e[0][l], e[1][l], e[2][l]];
            let rate = |w: &[f64; 3], q: &[f64; 4]| -> ([f64; 3], [f64; 4]) {
                let dw = [c[0] * w[1] * w[2], c[1] * w[2] * w[0], c[2] * w[0] * w[1]];
                if !ATT {
                    return (dw, [0.0; 4]);
                }
                let (x, y, z, s) = (q[0], q[1], q[2], q[3]);
                let (a, b, c) = (w[0], w[1], w[2]);
                // `quaternion_rate2`: 2 q', the factor 1/2 in the coefficients.
                let dq = [
                    s * a + y * c - z * b,
                    s * b + z * a - x * c,
                    s * c + x * b - y * a,
                    -(x * a + y * b + z * c),
                ];
                (dw, dq)
            };
            let w0 = [wa[0][l], wa[1][l], wa[2][l]];
            let q0 = [qa[0][l], qa[1][l], qa[2][l], qa[3][l]];
            let ax3 = |k: &[f64; 3], h: f64| [w0[0] + k[0] * h, w0[1] + k[1] * h, w0[2] + k[2] * h];
            let ax4 = |k: &[f64; 4], h: f64| {
                [
                    q0[0] + k[0] * h,
                    q0[1] + k[1] * h,
                    q0[2] + k[2] * h,
                    q0[3] + k[3] * h,
                ]
            };
            let (a1, b1) = rate(&w0, &q0);
            let (a2, b2) = rate(&ax3(&a1, half), &ax4(&b1, quarter));
            let (a3, b3) = rate(&ax3(&a2, half), &ax4(&b2, quarter));
            let (a4, b4) = rate(&ax3(&a3, h), &ax4(&b3, half));
            for i in 0..3 {
                let m = a2[i] + a3[i];
                wa[i][l] = w0[i] + (a1[i] + (m + m) + a4[i]) * sixth;
            }
            if ATT {
                for i in 0..4 {
                    let m = b2[i] + b3[i];
                    qa[i][l] = q0[i] + (b1[i] + (m + m) + b4[i]) * twelfth;
                }
            }
        }
        *w = [
            X::from_lanes(wa[0]),
            X::from_lanes(wa[1]),
            X::from_lanes(wa[2]),
        ];
        *q = [
            X::from_lanes(qa[0]),
            X::from_lanes(qa[1]),
            X::from_lanes(qa[2]),
            X::from_lanes(qa[3]),
        ];
        0
    }

    #[inline(always)]
    fn restore(&mut self, (_, q): &mut Vars) {
        if ATT {
            self.since += 1;
            if self.since == RK4_RENORMALISE_EVERY {
                let n = norm4(q);
                for v in q.iter_mut() {
                    *v = *v / n;
                }
                self.since = 0;
            }
        }
    }

    fn evaluations(&self, steps: u64, _l: usize) -> u64 {
        4 * steps
    }
}

// ---------------------------------------------------------------------------------------------
// The splitting (see super::splitting)

/// `(sin x, cos x - 1)` of `splitting::sin_cosm1`, lane by lane: the same Taylor polynomials
/// for `|x| <= 1/4`, the library in the lanes beyond.
#[inline(always)]
fn sin_cosm1(x: X) -> (X, X) {
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let s = x2
        * ((-1.0 / 6.0 + x2 * (1.0 / 120.0))
            + x4 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0))
            + x8 * (-1.0 / 39_916_800.0 + x2 * (1.0 / 6_227_020_800.0)));
    let cm1 = x2
        * ((-0.5 + x2 * (1.0 / 24.0))
            + x4 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0))
            + x8 * ((-1.0 / 3_628_800.0 + x2 * (1.0 / 479_001_600.0))
                + x4 * (-1.0 / 87_178_291_200.0)));
    let (mut s, mut cm1) = (x + x * s, cm1);
    let large = x.mask(|v| v.abs() > 0.25);
    if large != 0 {
        library_sin_cosm1(x, large, &mut s, &mut cm1);
    }
    (s, cm1)
}

/// The lanes of `large`: `cos x - 1 = -2 sin^2(x/2)`, as the scalar path beyond 1/4.
#[cold]
#[inline(never)]
fn library_sin_cosm1(x: X, large: Mask, s: &mut X, cm1: &mut X) {
    for l in 0..LANES {
        if large >> l & 1 != 0 {
            let (sh, ch) = (0.5 * x.lane(l)).sin_cos();
            s.set_lane(l, 2.0 * sh * ch);
            cm1.set_lane(l, -2.0 * sh * sh);
        }
    }
}

/// `splitting::axis_flow` on every lane, about the axis `A` shared by the block (a constant, so
/// that the variables stay in registers).
#[inline(always)]
fn axis_flow<const ATT: bool, const A: usize>(m: &mut V3, q: &mut V4, inverse: &V3, tau: f64) {
    let (a, b, c) = (A, (A + 1) % 3, (A + 2) % 3);
    let theta = m[a] * inverse[a] * tau;
    let (s, cm1) = if ATT {
        let (s2, c2m1) = sin_cosm1(0.5 * theta);
        let (qa, qb, qc, qw) = (q[a], q[b], q[c], q[3]);
        q[a] = (qa + c2m1 * qa) + s2 * qw;
        q[b] = (qb + c2m1 * qb) + s2 * qc;
        q[c] = (qc + c2m1 * qc) - s2 * qb;
        q[3] = (qw + c2m1 * qw) - s2 * qa;
        (2.0 * s2 * (1.0 + c2m1), -2.0 * s2 * s2)
    } else {
        sin_cosm1(theta)
    };
    let (mb, mc) = (m[b], m[c]);
    m[b] = (mb + cm1 * mb) + s * mc;
    m[c] = (mc + cm1 * mc) - s * mb;
}

/// Steps between two restorations of `|m|` without the orientation (as `super::splitting`).
const ANCHOR_EVERY: u32 = 16;

/// The splitting with the axis order `[A0, A1, A2]` (outer, inner, middle), the same for every
/// lane of the block.
struct Splitting<const ATT: bool, const A0: usize, const A1: usize, const A2: usize> {
    moments: V3,
    inverse: V3,
    weights: &'static [f64],
    /// With the orientation: the constant `L_space` of each lane.
    l_space: V3,
    /// Without: `|m|^2` of each lane, the lanes that restore it, and the steps taken.
    anchor: (X, Mask, u32),
}

impl<const ATT: bool, const A0: usize, const A1: usize, const A2: usize> LaneStepper
    for Splitting<ATT, A0, A1, A2>
{
    #[inline(always)]
    fn vars(&self, w: V3, q: V4) -> Vars {
        (
            [
                self.moments[0] * w[0],
                self.moments[1] * w[1],
                self.moments[2] * w[2],
            ],
            q,
        )
    }

    #[inline(always)]
    fn omega(&self, (m, _): &Vars) -> V3 {
        [
            m[0] * self.inverse[0],
            m[1] * self.inverse[1],
            m[2] * self.inverse[2],
        ]
    }

    fn start(&mut self, (m, q): &Vars) {
        if ATT {
            self.l_space = rotate(&[q[0], q[1], q[2]], q[3], m);
        } else {
            let g2 = norm_squared3(m);
            let on = g2.mask(|g| (1e-280..=1e280).contains(&g));
            self.anchor = (g2, on, 0);
        }
    }

    #[inline(always)]
    fn step(&mut self, (m, q): &mut Vars, h: f64, _live: Mask) -> Mask {
        // `splitting::free_flow`.
        let (inverse, g) = (&self.inverse, self.weights);
        axis_flow::<ATT, A0>(m, q, inverse, 0.5 * g[0] * h);
        for i in 0..g.len() {
            let hi = g[i] * h;
            axis_flow::<ATT, A1>(m, q, inverse, 0.5 * hi);
            axis_flow::<ATT, A2>(m, q, inverse, hi);
            axis_flow::<ATT, A1>(m, q, inverse, 0.5 * hi);
            let outer = if i + 1 < g.len() {
                g[i] + g[i + 1]
            } else {
                g[i]
            };
            axis_flow::<ATT, A0>(m, q, inverse, 0.5 * outer * h);
        }
        if ATT {
            let n = norm4(q);
            for v in q.iter_mut() {
                *v = *v / n;
            }
        }
        0
    }

    #[inline(always)]
    fn restore(&mut self, (m, q): &mut Vars) {
        if ATT {
            // m = R(q)^T L_space: the conjugate quaternion, as `inverse_transform_vector`.
            *m = rotate(&[-q[0], -q[1], -q[2]], q[3], &self.l_space);
        } else if self.anchor.1 != 0 {
            let (g2, on, count) = &mut self.anchor;
            *count = count.wrapping_add(1);
            if count.is_multiple_of(ANCHOR_EVERY) {
                let f = (*g2 / norm_squared3(m)).sqrt();
                for v in m.iter_mut() {
                    *v = X::select(*on, *v * f, *v);
                }
            }
        }
    }

    fn evaluations(&self, _steps: u64, _l: usize) -> u64 {
        0
    }
}

// ---------------------------------------------------------------------------------------------
// The implicit midpoint rule (see super::midpoint)

struct Midpoint<const ATT: bool> {
    euler: V3,
    /// `|c0| + |c1| + |c2|`, `c` = `euler` (`kc / k` of `midpoint::quadratic_done`).
    csum: X,
    /// Fixed-point and Newton iterations of each lane.
    evals: [u64; LANES],
    /// Why each failed lane failed.
    failure: [&'static str; LANES],
}

impl<const ATT: bool> Midpoint<ATT> {
    /// [`midpoint::predictor`] in every lane: the first increments, and the lanes where the
    /// fixed-point iterations ran. A loop over the lanes of the scalar arithmetic on arrays
    /// (as rk4's step), which the compiler vectorises lane by lane.
    #[inline(always)]
    fn predictor(&self, w0: &V3, k: f64) -> (V3, Mask) {
        let c = arrays3(&self.euler);
        let w0a = arrays3(w0);
        let mut wa = [[0.0; LANES]; 3];
        let mut ran = [0.0; LANES];
        for l in 0..LANES {
            let (w, contracts) = midpoint::predictor(
                &[c[0][l], c[1][l], c[2][l]],
                &[w0a[0][l], w0a[1][l], w0a[2][l]],
                k,
            );
            for i in 0..3 {
                wa[i][l] = w[i];
            }
            ran[l] = if contracts { 1.0 } else { 0.0 };
        }
        (
            [
                X::from_lanes(wa[0]),
                X::from_lanes(wa[1]),
                X::from_lanes(wa[2]),
            ],
            X::from_lanes(ran).mask(|r| r != 0.0),
        )
    }

    /// [`midpoint::newton_step`] in every lane: the corrections `d`, the lanes where the
    /// Newton matrix is singular, and `k |J(w)|_inf`. A loop over the lanes of the scalar
    /// arithmetic on arrays, which the compiler vectorises lane by lane (1.07x faster than the
    /// same operations on [`X`]s, measured).
    #[inline(always)]
    fn newton_step(&self, w0: &V3, z: &V3, k: f64) -> (V3, Mask, X) {
        let c = arrays3(&self.euler);
        let w0a = arrays3(w0);
        let za = arrays3(z);
        let mut da = [[0.0; LANES]; 3];
        let mut deta = [0.0; LANES];
        let mut kja = [0.0; LANES];
        for l in 0..LANES {
            let (d, det, kj) = midpoint::newton_step(
                &[c[0][l], c[1][l], c[2][l]],
                &[w0a[0][l], w0a[1][l], w0a[2][l]],
                &[za[0][l], za[1][l], za[2][l]],
                k,
            );
            for i in 0..3 {
                da[i][l] = d[i];
            }
            deta[l] = det;
            kja[l] = kj;
        }
        (
            [
                X::from_lanes(da[0]),
                X::from_lanes(da[1]),
                X::from_lanes(da[2]),
            ],
            X::from_lanes(deta).mask(|d| d == 0.0 || !d.is_finite()),
            X::from_lanes(kja),
        )
    }

    /// `midpoint::free_increment` in the lanes of `live`: each lane's Newton iteration stops
    /// where the scalar one would, keeping its value while the others go on. Returns the
    /// increments `w_m - w0` and the lanes that failed.
    #[inline(always)]
    fn free_increment(&mut self, w0: &V3, h: f64, live: Mask) -> (V3, Mask) {
        let k = 0.5 * h;
        let kc = self.csum * k;
        let (mut z, ran) = self.predictor(w0, k);
        self.count(ran & live, midpoint::PREDICTOR_ITERATIONS);
        let mut result = z;
        let mut prev = X::splat(f64::INFINITY);
        let mut pending = live;
        let mut failed = 0;
        for iteration in 0..midpoint::MAX_ITERATIONS {
            let started = pending;
            let (d, singular, kj) = self.newton_step(w0, &z, k);
            let singular = singular & pending;
            if singular != 0 {
                self.fail(singular, "singular Newton matrix");
                failed |= singular;
                pending &= !singular;
            }
            z = [z[0] + d[0], z[1] + d[1], z[2] + d[2]];
            // nalgebra's `amax`: |d0|, then simd_max with |d1|, |d2|.
            let dn = d[0].abs().simd_max(d[1].abs()).simd_max(d[2].abs());
            let w = [w0[0] + z[0], w0[1] + z[1], w0[2] + z[2]];
            let scale = w[0].abs().simd_max(w[1].abs()).simd_max(w[2].abs());
            // `midpoint::converged` or `midpoint::quadratic_done`, lane by lane.
            let (tight, loose) = ((8.0 * f64::EPSILON) * scale, (1e3 * f64::EPSILON) * scale);
            let mut quadratic = [0.0; LANES];
            let (kja, kca, dna, scalea) = (kj.lanes(), kc.lanes(), dn.lanes(), scale.lanes());
            for l in 0..LANES {
                let done = midpoint::quadratic_done(kja[l], kca[l], dna[l], scalea[l]);
                quadratic[l] = if done { 1.0 } else { 0.0 };
            }
            let converged = (dn.mask2(tight, |d, t| d <= t)
                | (dn.mask2(prev, |d, p| d >= p) & dn.mask2(loose, |d, l| d <= l))
                | X::from_lanes(quadratic).mask(|q| q != 0.0))
                & pending;
            for i in 0..3 {
                result[i] = X::select(converged, z[i], result[i]);
            }
            pending &= !converged;
            let diverged = dn.mask(|d| !d.is_finite()) & pending;
            if diverged != 0 {
                self.fail(diverged, midpoint::NO_CONVERGENCE);
                failed |= diverged;
                pending &= !diverged;
            }
            if pending != started {
                // Each lane that stops here has counted this iteration and those before.
                self.count(started & !pending, iteration as u64 + 1);
                if pending == 0 {
                    return (result, failed);
                }
            }
            prev = dn;
        }
        self.count(pending, midpoint::MAX_ITERATIONS as u64);
        self.fail(pending, midpoint::NO_CONVERGENCE);
        (result, failed | pending)
    }

    /// Adds `iterations` iterations (fixed-point or Newton) to the lanes of `lanes`.
    #[inline(always)]
    fn count(&mut self, lanes: Mask, iterations: u64) {
        for (l, evals) in self.evals.iter_mut().enumerate() {
            if lanes >> l & 1 != 0 {
                *evals += iterations;
            }
        }
    }

    #[cold]
    fn fail(&mut self, lanes: Mask, why: &'static str) {
        for l in 0..LANES {
            if lanes >> l & 1 != 0 {
                self.failure[l] = why;
            }
        }
    }
}

impl<const ATT: bool> LaneStepper for Midpoint<ATT> {
    /// Measured on Zen 4 (1e5 bodies, 2 threads): 6.4 vs 6.9 ns per body-step.
    const WIDE: bool = true;

    #[inline(always)]
    fn step(&mut self, y: &mut Vars, h: f64, live: Mask) -> Mask {
        let (w, q) = *y;
        let (z, failed) = self.free_increment(&w, h, live);
        if ATT {
            // `midpoint::cayley_update`: a loop over the lanes of `midpoint::cayley`, which
            // the compiler vectorises lane by lane (1.12x faster per step than the same
            // operations on `X`s, measured).
            let c = 0.25 * h;
            let wm = [w[0] + z[0], w[1] + z[1], w[2] + z[2]];
            let wa = arrays3(&wm);
            let mut qa = arrays4(&q);
            for l in 0..LANES {
                let out = midpoint::cayley(
                    &[qa[0][l], qa[1][l], qa[2][l], qa[3][l]],
                    &[wa[0][l], wa[1][l], wa[2][l]],
                    c,
                );
                for i in 0..4 {
                    qa[i][l] = out[i];
                }
            }
            y.1 = [
                X::from_lanes(qa[0]),
                X::from_lanes(qa[1]),
                X::from_lanes(qa[2]),
                X::from_lanes(qa[3]),
            ];
        }
        y.0 = [w[0] + z[0] * 2.0, w[1] + z[1] * 2.0, w[2] + z[2] * 2.0];
        failed
    }

    fn error(&self, l: usize, t: f64, h: f64) -> Error {
        midpoint::free_failure(self.failure[l], t, h)
    }

    fn evaluations(&self, _steps: u64, l: usize) -> u64 {
        self.evals[l]
    }
}

// ---------------------------------------------------------------------------------------------
// The driver

/// Whether [`integrate_lanes`] runs `method` under `options`: a fixed-step method without
/// torque.
pub(crate) fn applies(method: &Method, options: &Options) -> bool {
    options.torque.is_none()
        && matches!(
            method,
            Method::Rk4 { .. } | Method::Splitting { .. } | Method::Midpoint { .. }
        )
}

/// One output time of a block: for each lane, its angular velocity and (with the orientation)
/// its unit quaternion, checked finite; `None` for a lane that has failed or is not a body.
pub(crate) type LaneOutputs = [Option<(Vector3<f64>, Option<UnitQuaternion<f64>>)>; LANES];

/// Integrates up to [`LANES`] bodies (`bodies[l]` from `states[l]`, each started by
/// `driver::start`) to the output times, torque-free, with a method for which [`applies`]
/// holds: body `l`'s numbers and result (in entry `l`, the entries past the bodies `None`) are
/// those of [`super::integrate_body`] alone. `output(k, outputs)` receives every output time
/// `times[k]` in order; an error from it stops the block (every lane not failed yet then
/// returns it).
pub(crate) fn integrate_lanes(
    method: &Method,
    bodies: &[Moments],
    states: &[State],
    times: &[f64],
    options: &Options,
    output: impl FnMut(usize, &LaneOutputs) -> Result<()>,
) -> [Option<Result<Stats>>; LANES] {
    debug_assert!(!bodies.is_empty() && bodies.len() <= LANES && bodies.len() == states.len());
    let n = bodies.len();
    let per_lane = |f: &dyn Fn(&Moments) -> Vector3<f64>| gather3(n, |l| f(&bodies[l]));
    let w0 = gather3(n, |l| states[l].omega);
    let q0 = gather4(n, |l| states[l].orientation.coords);
    let y0 = (w0, q0);
    let att = options.with_orientation;
    macro_rules! run {
        ($dt:expr, $stepper:expr) => {
            run_lanes($stepper, $dt, y0, n, times, options, output)
        };
    }
    match *method {
        Method::Rk4 { dt } => {
            let euler = per_lane(&|b| *b.euler());
            if att {
                run!(dt, Rk4::<true> { euler, since: 0 })
            } else {
                run!(dt, Rk4::<false> { euler, since: 0 })
            }
        }
        Method::Splitting { dt, order } => {
            debug_assert!(bodies.iter().all(|b| b.split_axes == bodies[0].split_axes));
            let (moments, inverse) = (per_lane(&|b| *b.moments()), per_lane(&|b| *b.inverse()));
            let weights = order.weights();
            let zero = X::splat(0.0);
            let (l_space, anchor) = ([zero; 3], (zero, 0, 0));
            macro_rules! split {
                ($a0:literal, $a1:literal, $a2:literal) => {
                    if att {
                        let stepper = Splitting::<true, $a0, $a1, $a2> {
                            moments,
                            inverse,
                            weights,
                            l_space,
                            anchor,
                        };
                        run!(dt, stepper)
                    } else {
                        let stepper = Splitting::<false, $a0, $a1, $a2> {
                            moments,
                            inverse,
                            weights,
                            l_space,
                            anchor,
                        };
                        run!(dt, stepper)
                    }
                };
            }
            match bodies[0].split_axes {
                [0, 1, 2] => split!(0, 1, 2),
                [0, 2, 1] => split!(0, 2, 1),
                [1, 0, 2] => split!(1, 0, 2),
                [1, 2, 0] => split!(1, 2, 0),
                [2, 0, 1] => split!(2, 0, 1),
                _ => split!(2, 1, 0),
            }
        }
        Method::Midpoint { dt } => {
            let euler = per_lane(&|b| *b.euler());
            let csum = euler[0].abs() + euler[1].abs() + euler[2].abs();
            let (evals, failure) = ([0; LANES], [""; LANES]);
            if att {
                run!(
                    dt,
                    Midpoint::<true> {
                        euler,
                        csum,
                        evals,
                        failure
                    }
                )
            } else {
                run!(
                    dt,
                    Midpoint::<false> {
                        euler,
                        csum,
                        evals,
                        failure
                    }
                )
            }
        }
        Method::Dop853(_) | Method::Exact => {
            unreachable!("integrate_lanes runs the fixed-step methods only")
        }
    }
}

/// Steps `first..end` of `h` from `y` in the lanes of `live`; returns the step reached and the
/// lanes whose last step failed (the loop stops after a failure).
#[inline(always)]
fn steps<S: LaneStepper>(
    stepper: &mut S,
    y: &mut Vars,
    first: u64,
    end: u64,
    h: f64,
    live: Mask,
) -> (u64, Mask) {
    for i in first..end {
        let failed = stepper.step(y, h, live);
        stepper.restore(y);
        if failed != 0 {
            return (i, failed);
        }
    }
    (end, 0)
}

/// `driver::fixed_loop` on a block of `n` lanes.
fn run_lanes<S: LaneStepper>(
    mut stepper: S,
    dt: f64,
    y0: Vars,
    n: usize,
    times: &[f64],
    options: &Options,
    mut output: impl FnMut(usize, &LaneOutputs) -> Result<()>,
) -> [Option<Result<Stats>>; LANES] {
    let total = match fixed_total(dt, times, &[], options) {
        Ok(total) => total,
        Err(error) => return std::array::from_fn(|l| (l < n).then(|| Err(error.clone()))),
    };
    let mut errors: [Option<Error>; LANES] = Default::default();
    let mut live: Mask = (1 << n) - 1;
    let mut y = stepper.vars(y0.0, y0.1);
    stepper.start(&y);
    let progress = Progress::new(options.monitor, options.t0, Monitor::CHECK_EVERY);
    progress.set_runs(n as u32);
    // Set when every lane has failed: the run stops (with a stand-in error, not returned).
    let mut all_failed = false;
    let mut prev = options.t0;
    let run = segments(options.t0, times, &[], |t, k| {
        let steps_here = substeps(prev, t, dt);
        if steps_here > 0.0 {
            let h = (t - prev) / steps_here;
            let (n_steps, mut j) = (steps_here as u64, 0);
            while j < n_steps {
                let end = n_steps.min(j + u64::from(progress.budget()));
                let mut local = y;
                let mut i = j;
                while i < end {
                    let (at, failed) = if S::WIDE {
                        crate::simd::dispatch_wide(
                            #[inline(always)]
                            || steps(&mut stepper, &mut local, i, end, h, live),
                        )
                    } else {
                        crate::simd::dispatch(
                            #[inline(always)]
                            || steps(&mut stepper, &mut local, i, end, h, live),
                        )
                    };
                    if failed != 0 {
                        let t_step = prev + at as f64 * h;
                        for (l, error) in errors.iter_mut().enumerate() {
                            if failed >> l & 1 != 0 {
                                *error = Some(stepper.error(l, t_step, h));
                            }
                        }
                        live &= !failed;
                        progress.set_runs(live.count_ones());
                        if live == 0 {
                            all_failed = true;
                            return Err(Error::Interrupted);
                        }
                        i = at + 1;
                    } else {
                        i = at;
                    }
                }
                y = local;
                progress.spend((end - j) as u32, || prev + end as f64 * h)?;
                j = end;
            }
        }
        prev = t;
        let Some(k) = k else { return Ok(()) };
        // The lanes as arrays once (a lane read from a vector's image reloads the vector). At
        // t0 (no step taken) omega0 itself: a stepper's variables (the splitting's I omega)
        // give it back only to rounding.
        let omega = if times[k] == options.t0 {
            arrays3(&y0.0)
        } else {
            arrays3(&stepper.omega(&y))
        };
        // `driver::unit_output`'s `q / |q|`, in every lane at once.
        let n = norm4(&y.1);
        let unit = arrays4(&[y.1[0] / n, y.1[1] / n, y.1[2] / n, y.1[3] / n]);
        let mut outputs: LaneOutputs = [None; LANES];
        for (l, (out, error)) in outputs.iter_mut().zip(errors.iter_mut()).enumerate() {
            if live >> l & 1 == 0 {
                continue;
            }
            let w = Vector3::new(omega[0][l], omega[1][l], omega[2][l]);
            let checked = check_omega_output(true, times[k], &w).and_then(|()| {
                if options.with_orientation {
                    let q = Vector4::new(unit[0][l], unit[1][l], unit[2][l], unit[3][l]);
                    Ok(Some(checked_unit(true, times[k], q)?))
                } else {
                    Ok(None)
                }
            });
            match checked {
                Ok(q) => *out = Some((w, q)),
                Err(e) => {
                    *error = Some(e);
                    live &= !(1 << l);
                }
            }
        }
        progress.set_runs(live.count_ones());
        if live == 0 {
            all_failed = true;
            return Err(Error::Interrupted);
        }
        output(k, &outputs)
    });
    if run.is_ok() {
        progress.finish(prev);
    }
    let steps_taken = total as u64;
    let mut errors = errors.into_iter().enumerate();
    std::array::from_fn(|_| {
        let (l, error) = errors.next().expect("LANES errors");
        (l < n).then(|| match (error, &run) {
            (Some(error), _) => Err(error),
            (None, Err(stop)) => {
                debug_assert!(!all_failed);
                Err(stop.clone())
            }
            (None, Ok(())) => Ok(Stats {
                steps: steps_taken,
                rejected_steps: 0,
                rhs_evaluations: stepper.evaluations(steps_taken, l),
            }),
        })
    })
}
