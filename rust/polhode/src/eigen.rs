//! The symmetric 3x3 eigensolve behind principal axes.
//!
//! Inertia tensors are degenerate or nearly so whenever a body has a symmetry, and closed-form
//! (Cardano) solvers lose half the digits there. This module uses cyclic Jacobi rotations on the
//! tensor shifted by `trace/3` (backward stable: residual of a few eps ||A|| on every input) and a
//! one-sided (Hestenes) Jacobi SVD for the square-root factors kept by
//! [`MassProperties`](crate::MassProperties). Both then go through one canonicalisation: moments
//! ascending, axes a proper rotation with deterministic signs, and inside a degenerate subspace
//! the frame closest to the body's own axes.

// Lane loops (`for l in 0..L`) index several arrays by the same lane on purpose: that is the
// shape LLVM vectorises.
#![allow(clippy::needless_range_loop)]

use std::sync::atomic::{AtomicUsize, Ordering};

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::memory::{self, Purpose};
use crate::Monitor;

/// Default relative tolerance under which two principal moments count as equal.
///
/// Relative to the accuracy scale of the representation (`||A||_F` for a plain tensor, the
/// anisotropic part for a [`MassProperties`](crate::MassProperties)); at `8 eps` the moments of
/// a group are replaced by their mean and the canonical axes chosen, which keeps the residual
/// `||A V - V diag(I)||` within `10 eps ||A||`.
pub const DEFAULT_RTOL: f64 = 8.0 * f64::EPSILON;

/// Most Jacobi sweeps; a 3x3 converges quadratically in 4 to 6.
const MAX_SWEEPS: usize = 64;

/// Principal moments and axes.
///
/// ```
/// use nalgebra::Matrix3;
/// // A 1 kg m^2 tensor with a product of inertia in the xy plane.
/// let inertia = Matrix3::new(2.0, -0.5, 0.0, -0.5, 2.0, 0.0, 0.0, 0.0, 3.0);
/// let p = polhode::symmetric_eigen3(&inertia).unwrap();
/// assert!((p.moments[0] - 1.5).abs() < 1e-15 && (p.moments[1] - 2.5).abs() < 1e-15);
/// assert!((p.axes.determinant() - 1.0).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Principal {
    /// Principal moments, ascending.
    pub moments: Vector3<f64>,
    /// Principal axes as the columns of a proper rotation (det = +1): column k belongs to
    /// `moments[k]`. Maps principal coordinates to the body's coordinates.
    pub axes: Matrix3<f64>,
    /// For each moment, how many moments (itself included) are equal to it within the tolerance:
    /// `[1, 1, 1]` for an asymmetric body, `[2, 2, 1]` or `[1, 2, 2]` for a symmetric one,
    /// `[3, 3, 3]` for a spherical one.
    pub multiplicity: [u8; 3],
}

/// Eigen-decomposition of a symmetric 3x3 tensor with the default tolerance.
///
/// Only the lower triangle's mirror is checked: the tensor must be symmetric to `64 eps` of its
/// largest entry and finite; it is symmetrised before the solve.
pub fn symmetric_eigen3(tensor: &Matrix3<f64>) -> Result<Principal> {
    symmetric_eigen3_with(tensor, DEFAULT_RTOL, "inertia")
}

/// [`symmetric_eigen3`] with an explicit relative tolerance for equal moments (finite and
/// `>= 0`: an error naming `rtol` otherwise); `name` is the argument named in errors.
///
/// Any finite symmetric tensor is accepted, from subnormal to the largest doubles: the tensor is
/// scaled by a power of two before the solve and the moments scaled back (exactly, unless they
/// are subnormal). Moments beyond the range of double precision (a tensor near `f64::MAX` whose
/// largest eigenvalue exceeds it) are an [`Error::InvalidArgument`] naming `name`.
pub fn symmetric_eigen3_with(tensor: &Matrix3<f64>, rtol: f64, name: &str) -> Result<Principal> {
    crate::settings::Setting::MergeTolerance.check("rtol", rtol)?;
    let a = checked_symmetric(tensor, name)?;
    eigen_symmetric_unchecked(&a, rtol, name)
}

/// `2^k` for `-1022 <= k <= 1023` (a normal number).
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `x 2^k` with a single rounding whenever `x 2^(k/2)` is a normal number: exact unless the
/// result is subnormal, 0 or infinite. `k` is clamped to `[-2044, 2046]`, beyond which every
/// finite non-zero `x` over- or underflows anyway.
pub(crate) fn ldexp(x: f64, k: i32) -> f64 {
    let k = k.clamp(-2044, 2046);
    let half = k / 2;
    x * pow2(half) * pow2(k - half)
}

/// The binary exponent `e` of `x` with `|x| = f 2^e`, `0.5 <= f < 1` (C's `frexp`), subnormals
/// included; 0 for 0 and for non-finite `x`.
pub(crate) fn exponent(x: f64) -> i32 {
    if x == 0.0 || !x.is_finite() {
        return 0;
    }
    let biased = ((x.to_bits() >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal: scale into the normal range first (exactly).
        exponent(x * pow2(64)) - 64
    } else {
        biased - 1022
    }
}

/// A number in short scientific notation, for values known only as `x 2^k` (which may lie
/// beyond the range of double precision): `3.1e+310`.
pub(crate) fn scientific(x: f64, k: i32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let log10 = x.abs().log10() + f64::from(k) * std::f64::consts::LOG10_2;
    let mut power = log10.floor();
    let mut mantissa = 10f64.powf(log10 - power);
    if mantissa >= 9.95 {
        mantissa /= 10.0;
        power += 1.0;
    }
    let sign = if x < 0.0 { "-" } else { "" };
    format!(
        "{sign}{mantissa:.1}e{}{}",
        if power < 0.0 { "-" } else { "+" },
        power.abs()
    )
}

/// The error for principal moments beyond the range of double precision; the largest moment is
/// `largest 2^k`.
fn moments_overflow(name: &str, largest: f64, k: i32) -> Error {
    Error::InvalidArgument {
        name: name.to_owned(),
        reason: format!(
            "its principal moments overflow double precision (the largest is about {}, beyond \
             the largest double, {:e}).",
            scientific(largest, k),
            f64::MAX
        ),
    }
}

/// Checks finiteness and symmetry and returns the symmetrised tensor.
pub(crate) fn checked_symmetric(tensor: &Matrix3<f64>, name: &str) -> Result<Matrix3<f64>> {
    let mut largest = 0.0_f64;
    for r in 0..3 {
        for c in 0..3 {
            let v = tensor[(r, c)];
            if !v.is_finite() {
                return Err(Error::NonFinite {
                    name: format!("{name}[{r}, {c}]"),
                    value: v,
                });
            }
            largest = largest.max(v.abs());
        }
    }
    for (r, c) in [(0, 1), (0, 2), (1, 2)] {
        let (upper, lower) = (tensor[(r, c)], tensor[(c, r)]);
        if (upper - lower).abs() > 64.0 * f64::EPSILON * largest {
            return Err(Error::InvalidInertia {
                name: name.to_owned(),
                reason: format!(
                    "it must be symmetric, but [{r}, {c}] = {upper:e} and [{c}, {r}] = {lower:e}."
                ),
            });
        }
    }
    // The mean of the two mirrors, without overflow near f64::MAX (and exact for subnormals,
    // where halving first would round): the same expression both ways, so exactly symmetric.
    let mean = |x: f64, y: f64| {
        let sum = x + y;
        if sum.is_finite() {
            sum * 0.5
        } else {
            x * 0.5 + y * 0.5
        }
    };
    Ok(Matrix3::from_fn(|r, c| {
        mean(tensor[(r, c)], tensor[(c, r)])
    }))
}

/// Eigen-decomposition of a symmetric, finite tensor (not checked); an error naming `name` if
/// its moments exceed the range of double precision.
pub(crate) fn eigen_symmetric_unchecked(
    a: &Matrix3<f64>,
    rtol: f64,
    name: &str,
) -> Result<Principal> {
    let (mut p, k) = eigen_symmetric_scaled(a, rtol);
    let moments = p.moments.map(|x| ldexp(x, k));
    if !moments.iter().all(|x| x.is_finite()) {
        return Err(moments_overflow(name, p.moments.abs().max(), k));
    }
    p.moments = moments;
    Ok(p)
}

/// The eigen-decomposition of `a 2^-k` (entries of size below 1) and `k`: the moments of `a` are
/// those returned times `2^k`, which may lie beyond the range of double precision.
pub(crate) fn eigen_symmetric_scaled(a: &Matrix3<f64>, rtol: f64) -> (Principal, i32) {
    let mut lanes = Lanes::<1>::default();
    lanes.load(&[row_major(a)]);
    lanes.solve();
    let p = lanes.canonical(rtol);
    (p.principal(0), lanes.exponent[0] as i32)
}

/// The nine entries of `m`, row by row.
fn row_major(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)],
    ]
}

/// `L` numbers side by side, one per lane (a SIMD register's worth, or two).
type Lane<const L: usize> = [f64; L];

/// `[f(0), f(1), f(2)]`, inlined (unlike `[T; 3]::map`, whose copy would run without the
/// dispatched instructions).
#[inline(always)]
fn three<T>(mut f: impl FnMut(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

/// `f(l)` for every lane.
#[inline(always)]
fn lanes<const L: usize>(f: impl FnMut(usize) -> f64) -> Lane<L> {
    each(f)
}

/// `[f(0), f(1), ..., f(L - 1)]` with a plain loop: `std::array::from_fn` is not always inlined
/// (it was not for 12 lanes), and out of line it runs without the dispatched instructions and
/// with the lanes in memory.
#[inline(always)]
fn each<T: Copy + Default, const L: usize>(mut f: impl FnMut(usize) -> T) -> [T; L] {
    let mut out = [T::default(); L];
    for l in 0..L {
        out[l] = f(l);
    }
    out
}

/// A condition lane by lane: all ones where it holds, zero where not (what a vector compare
/// produces; `[bool; L]` would be packed to bytes and widened again at every use).
type Mask<const L: usize> = [u64; L];

/// The mask of `f(l)`.
#[inline(always)]
fn mask<const L: usize>(mut f: impl FnMut(usize) -> bool) -> Mask<L> {
    each(|l| u64::from(f(l)).wrapping_neg())
}

/// Whether any lane of `mask` is set.
#[inline(always)]
fn any<const L: usize>(mask: &Mask<L>) -> bool {
    mask.iter().fold(0, |acc, &m| acc | m) != 0
}

/// `if mask { yes } else { no }`, lane by lane.
#[inline(always)]
fn select<const L: usize>(mask: &Mask<L>, yes: &Lane<L>, no: &Lane<L>) -> Lane<L> {
    // On the bits, so that it compiles to a blend in registers (not a masked store).
    lanes(|l| f64::from_bits((yes[l].to_bits() & mask[l]) | (no[l].to_bits() & !mask[l])))
}

/// `2^k` lane by lane, `-1022 <= k <= 1023` (a normal number; built from its bits, so that it
/// vectorises).
#[inline(always)]
fn pow2_lanes<const L: usize>(k: &[i64; L]) -> Lane<L> {
    lanes(|l| f64::from_bits(((k[l] + 1023) as u64) << 52))
}

/// The two powers of two whose product [`ldexp`] multiplies by, lane by lane.
#[inline(always)]
fn ldexp_factors<const L: usize>(k: &[i64; L]) -> (Lane<L>, Lane<L>) {
    let k: [i64; L] = each(|l| k[l].clamp(-2044, 2046));
    let half: [i64; L] = each(|l| k[l] / 2);
    let rest: [i64; L] = each(|l| k[l] - half[l]);
    (pow2_lanes(&half), pow2_lanes(&rest))
}

/// [`exponent`] lane by lane, for finite `x >= 0`.
#[inline(always)]
fn exponent_lanes<const L: usize>(x: &Lane<L>) -> [i64; L] {
    each(|l| {
        let subnormal = x[l] < f64::MIN_POSITIVE;
        // Subnormals scaled into the normal range first (exactly).
        let y = if subnormal { x[l] * pow2(64) } else { x[l] };
        let biased = ((y.to_bits() >> 52) & 0x7ff) as i64;
        let e = biased - 1022 - if subnormal { 64 } else { 0 };
        if x[l] == 0.0 {
            0
        } else {
            e
        }
    })
}

/// `(x, y, z) / |(x, y, z)|` with one division, lane by lane.
#[inline(always)]
fn unit<const L: usize>(v: [Lane<L>; 3]) -> [Lane<L>; 3] {
    let inverse: Lane<L> =
        lanes(|l| 1.0 / (v[0][l] * v[0][l] + v[1][l] * v[1][l] + v[2][l] * v[2][l]).sqrt());
    three(|k| lanes(|l| v[k][l] * inverse[l]))
}

/// The vector with the sign that makes its largest-magnitude component (the first on a tie)
/// positive, lane by lane.
#[inline(always)]
fn signed<const L: usize>(v: [Lane<L>; 3]) -> [Lane<L>; 3] {
    let size = three(|k| lanes::<L>(|l| v[k][l].abs()));
    let is1: Mask<L> = mask(|l| size[1][l] > size[0][l]);
    let largest = select(&is1, &v[1], &v[0]);
    let size01 = select(&is1, &size[1], &size[0]);
    let is2: Mask<L> = mask(|l| size[2][l] > size01[l]);
    let largest = select(&is2, &v[2], &largest);
    let negative: Mask<L> = mask(|l| largest[l] < 0.0);
    let sign = select(&negative, &[-1.0; L], &[1.0; L]);
    three(|k| lanes(|l| v[k][l] * sign[l]))
}

/// `a x b`, lane by lane.
#[inline(always)]
fn cross<const L: usize>(a: &[Lane<L>; 3], b: &[Lane<L>; 3]) -> [Lane<L>; 3] {
    [
        lanes(|l| a[1][l] * b[2][l] - a[2][l] * b[1][l]),
        lanes(|l| a[2][l] * b[0][l] - a[0][l] * b[2][l]),
        lanes(|l| a[0][l] * b[1][l] - a[1][l] * b[0][l]),
    ]
}

/// `L` symmetric tensors solved side by side, structure of arrays (`a[r][c][lane]`): every lane
/// performs the same IEEE operations in the same order as a lone tensor would (a rotation a
/// lane does not need leaves it untouched, bit for bit), so a tensor's result does not depend
/// on its neighbours, on `L`, or on whether the code was vectorised.
#[derive(Clone, Copy)]
struct Lanes<const L: usize> {
    a: [[Lane<L>; 3]; 3],
    v: [[Lane<L>; 3]; 3],
    /// The diagonal of the tensor before its shift: `2^-exponent` times the one loaded.
    diagonal: [Lane<L>; 3],
    shift: Lane<L>,
    scale: Lane<L>,
    norm: Lane<L>,
    /// The lane holds its tensor times `2^-exponent`.
    exponent: [i64; L],
}

impl<const L: usize> Default for Lanes<L> {
    fn default() -> Self {
        Self {
            a: [[[0.0; L]; 3]; 3],
            v: [[[0.0; L]; 3]; 3],
            diagonal: [[0.0; L]; 3],
            shift: [0.0; L],
            scale: [1.0; L],
            norm: [0.0; L],
            exponent: [0; L],
        }
    }
}

/// The canonical principal frames of `L` lanes (scaled moments: times `2^exponent`).
struct CanonicalLanes<const L: usize> {
    moments: [Lane<L>; 3],
    /// `axes[r][c]`: row `r` of column (axis) `c`.
    axes: [[Lane<L>; 3]; 3],
    /// Each moment's multiplicity, 1 to 3.
    multiplicity: [[u64; L]; 3],
}

impl<const L: usize> CanonicalLanes<L> {
    fn principal(&self, l: usize) -> Principal {
        Principal {
            moments: Vector3::new(self.moments[0][l], self.moments[1][l], self.moments[2][l]),
            axes: Matrix3::from_fn(|r, c| self.axes[r][c][l]),
            multiplicity: [0, 1, 2].map(|k| self.multiplicity[k][l] as u8),
        }
    }
}

impl<const L: usize> Lanes<L> {
    /// Loads `L` symmetric, finite tensors (row by row; not checked), each shifted by trace/3
    /// and scaled to entries of size <= 1: lane `l` holds `tensors[l] 2^-exponent[l]`, and its
    /// moments come out in units of `2^exponent[l]`.
    ///
    /// The power of two first brings the largest entry to [0.5, 1), exactly (but for
    /// subnormal entries far below the largest, whose rounding is far below eps of it): the
    /// trace, the norm and the squares of the Jacobi rotations then can neither overflow (a
    /// tensor of 1e154) nor underflow (a subnormal one), and in the normal range the
    /// arithmetic is that of the unscaled tensor times the same power of two.
    #[inline(always)]
    fn load(&mut self, tensors: &[[f64; 9]; L]) {
        let mut m = [[[0.0; L]; 3]; 3];
        for r in 0..3 {
            for c in 0..3 {
                m[r][c] = lanes(|l| tensors[l][3 * r + c]);
            }
        }
        let mut largest = [0.0f64; L];
        for row in &m {
            for x in row {
                largest = lanes(|l| largest[l].max(x[l].abs()));
            }
        }
        let k = exponent_lanes(&largest);
        let minus: [i64; L] = each(|l| -k[l]);
        let (f1, f2) = ldexp_factors(&minus);
        for row in &mut m {
            for x in row {
                *x = lanes(|l| x[l] * f1[l] * f2[l]);
            }
        }
        let shift: Lane<L> = lanes(|l| (m[0][0][l] + m[1][1][l] + m[2][2][l]) / 3.0);
        let mut x = m;
        for (k, row) in x.iter_mut().enumerate() {
            row[k] = lanes(|l| row[k][l] - shift[l]);
        }
        let mut largest = [0.0f64; L];
        let mut squares = [0.0; L];
        for c in 0..3 {
            for r in 0..3 {
                largest = lanes(|l| largest[l].max(x[r][c][l].abs()));
                squares = lanes(|l| squares[l] + m[r][c][l] * m[r][c][l]);
            }
        }
        // An anisotropic part below the smallest normal number (subnormal entries, far below
        // eps of the tensor's own entries near 1) is left unscaled: its reciprocal would
        // overflow. No rotation then exceeds the threshold, and the moments are the diagonal.
        let normal: Mask<L> = mask(|l| largest[l] >= f64::MIN_POSITIVE);
        let scale = select(&normal, &largest, &[1.0; L]);
        let inverse: Lane<L> = lanes(|l| 1.0 / scale[l]);
        for r in 0..3 {
            for c in 0..3 {
                self.a[r][c] = lanes(|l| x[r][c][l] * inverse[l]);
                self.v[r][c] = [if r == c { 1.0 } else { 0.0 }; L];
            }
        }
        self.diagonal = three(|k| m[k][k]);
        self.shift = shift;
        self.scale = scale;
        self.norm = lanes(|l| squares[l].sqrt());
        self.exponent = k;
    }

    /// Cyclic Jacobi (Golub & Van Loan 8.5.2, symmetric Schur rotations with the smaller root so
    /// the angle is at most pi/4) until every off-diagonal entry of every lane is below
    /// `eps/16` of the (unit-scaled) matrix: dropping them is a backward error far inside the
    /// solver's own rounding, and quadratic convergence gets there one sweep after `eps`. A
    /// rotation whose entry is already negligible is skipped lane by lane (its lane keeps its
    /// values), so the sweeps another lane still needs change nothing in this one.
    #[inline(always)]
    fn solve(&mut self) {
        let negligible = f64::EPSILON / 16.0;
        for _ in 0..MAX_SWEEPS {
            let a = &self.a;
            let mut converged = true;
            for l in 0..L {
                converged &= a[0][1][l].abs() <= negligible
                    && a[0][2][l].abs() <= negligible
                    && a[1][2][l].abs() <= negligible;
            }
            if converged {
                break;
            }
            // Each rotation with constant indices, so that the entries stay in registers.
            self.rotate::<0, 1, 2>(negligible);
            self.rotate::<0, 2, 1>(negligible);
            self.rotate::<1, 2, 0>(negligible);
        }
    }

    /// One Jacobi rotation in the (p, q) plane (`r` the third index), lane by lane; a lane
    /// whose entry is negligible keeps its values.
    #[inline(always)]
    fn rotate<const P: usize, const Q: usize, const R: usize>(&mut self, negligible: f64) {
        let (p, q, r) = (P, Q, R);
        let a = &mut self.a;
        let apq = a[p][q];
        let active: Mask<L> = mask(|l| apq[l].abs() > negligible);
        // t = tan(theta) = sign(tau) / (|tau| + sqrt(1 + tau^2)) with tau = d / e,
        // multiplied through by |e|: one division fewer on the critical path. Entries
        // are <= 1 after scaling, so d^2 + e^2 cannot overflow, and |e| > eps/8 keeps it
        // from vanishing (an inactive lane computes with e = 1 and is not updated).
        let e = select(&active, &lanes(|l| 2.0 * apq[l]), &[1.0; L]);
        let d: Lane<L> = lanes(|l| a[q][q][l] - a[p][p][l]);
        let t: Lane<L> = lanes(|l| {
            1.0f64.copysign(d[l]) * e[l] / (d[l].abs() + (d[l] * d[l] + e[l] * e[l]).sqrt())
        });
        let c: Lane<L> = lanes(|l| 1.0 / (1.0 + t[l] * t[l]).sqrt());
        let s: Lane<L> = lanes(|l| t[l] * c[l]);
        let app = lanes(|l| a[p][p][l] - t[l] * apq[l]);
        a[p][p] = select(&active, &app, &a[p][p]);
        let aqq = lanes(|l| a[q][q][l] + t[l] * apq[l]);
        a[q][q] = select(&active, &aqq, &a[q][q]);
        let zero = [0.0; L];
        a[p][q] = select(&active, &zero, &apq);
        a[q][p] = a[p][q];
        let (arp, arq) = (a[r][p], a[r][q]);
        let rp = lanes(|l| c[l] * arp[l] - s[l] * arq[l]);
        let rq = lanes(|l| s[l] * arp[l] + c[l] * arq[l]);
        a[r][p] = select(&active, &rp, &arp);
        a[r][q] = select(&active, &rq, &arq);
        a[p][r] = a[r][p];
        a[q][r] = a[r][q];
        for row in &mut self.v {
            let (vp, vq) = (row[p], row[q]);
            let np = lanes(|l| c[l] * vp[l] - s[l] * vq[l]);
            let nq = lanes(|l| s[l] * vp[l] + c[l] * vq[l]);
            row[p] = select(&active, &np, &vp);
            row[q] = select(&active, &nq, &vq);
        }
    }

    /// The canonical principal frames (moments in units of `2^exponent`); equal moments within
    /// `rtol ||A||_F`.
    ///
    /// A moment is its rotated diagonal entry plus the shift, but where no rotation touched its
    /// axis (still exactly a coordinate axis: a diagonal tensor, or an axis decoupled from the
    /// other two) it is the tensor's own diagonal entry, exact. Shifted and shifted back, a
    /// small moment beside large ones lost its digits below eps of the trace: `diag(1e-20, 1,
    /// 1)` gave 0, and a body built from it was refused for a zero moment.
    #[inline(always)]
    fn canonical(&self, rtol: f64) -> CanonicalLanes<L> {
        let v = &self.v;
        let values = three(
            #[inline(always)]
            |k| {
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                let untouched: Mask<L> =
                    mask(|l| v[k][k][l] == 1.0 && v[i][k][l] == 0.0 && v[j][k][l] == 0.0);
                let rotated = lanes(|l| self.a[k][k][l] * self.scale[l] + self.shift[l]);
                select(&untouched, &self.diagonal[k], &rotated)
            },
        );
        let tolerance = lanes(|l| rtol * self.norm[l]);
        canonical_lanes(values, self.v, &tolerance)
    }
}

/// Sorts, groups equal moments (gap `<= tolerance`, an absolute number already scaled by the
/// caller), and fixes the frame: deterministic signs, det = +1, and inside a degenerate subspace
/// the axes closest to the body's own; lane by lane (`vectors[r][c]`: row `r` of column `c`).
#[inline(always)]
fn canonical_lanes<const L: usize>(
    values: [Lane<L>; 3],
    vectors: [[Lane<L>; 3]; 3],
    tolerance: &Lane<L>,
) -> CanonicalLanes<L> {
    // A three-element sorting network on the moments and their columns.
    let mut m = values;
    let mut col = three(|c| [vectors[0][c], vectors[1][c], vectors[2][c]]);
    for (i, j) in [(0, 1), (1, 2), (0, 1)] {
        let swap: Mask<L> = mask(|l| m[j][l] < m[i][l]);
        let (mi, mj) = (m[i], m[j]);
        m[i] = select(&swap, &mj, &mi);
        m[j] = select(&swap, &mi, &mj);
        for r in 0..3 {
            let (ci, cj) = (col[i][r], col[j][r]);
            col[i][r] = select(&swap, &cj, &ci);
            col[j][r] = select(&swap, &ci, &cj);
        }
    }
    let low: Mask<L> = mask(|l| m[1][l] - m[0][l] <= tolerance[l]);
    let high: Mask<L> = mask(|l| m[2][l] - m[1][l] <= tolerance[l]);

    // Distinct moments: Gram-Schmidt once (the accumulated rotations leave columns orthogonal
    // only to a few eps per rotation). Skipped when no lane has distinct moments (every lane's
    // axes are then replaced below; a batch of symmetric tops saves the work).
    let distinct: Mask<L> = each(|l| !(low[l] | high[l]));
    let mut axes = if any(&distinct) {
        let a0 = unit(signed(col[0]));
        let dot: Lane<L> =
            lanes(|l| a0[0][l] * col[1][0][l] + a0[1][l] * col[1][1][l] + a0[2][l] * col[1][2][l]);
        let a1 = unit(signed(three(|r| {
            lanes(|l| col[1][r][l] - a0[r][l] * dot[l])
        })));
        let a2 = cross(&a0, &a1);
        [a0, a1, a2]
    } else {
        col
    };
    let mut moments = m;

    let pair: Mask<L> = each(|l| low[l] ^ high[l]);
    if any(&pair) {
        // A symmetric body: one unique axis `u` and a plane of equal moments.
        let unique = three(|r| select(&low, &col[2][r], &col[0][r]));
        let u = unit(signed(unique));
        // In the plane: the projection of the body axis most perpendicular to `u` (the first
        // such axis on a tie), then the axis that completes a right-handed frame.
        let size = three(|k| lanes::<L>(|l| u[k][l].abs()));
        let is1: Mask<L> = mask(|l| size[1][l] < size[0][l]);
        let smallest = select(&is1, &size[1], &size[0]);
        let is2: Mask<L> = mask(|l| size[2][l] < smallest[l]);
        // That axis is j = 2 where is2, else 1 where is1, else 0.
        let is = [
            each(|l| !(is1[l] | is2[l])),
            each(|l| is1[l] & !is2[l]),
            is2,
        ];
        let uj = select(&is2, &u[2], &select(&is1, &u[1], &u[0]));
        let p1 = three(|k| {
            let x = lanes::<L>(|l| -u[k][l] * uj[l]);
            select(&is[k], &lanes(|l| x[l] + 1.0), &x)
        });
        let p1 = unit(p1);
        let p2 = cross(&u, &p1);
        // low: (p1, p2, u), high: (u, p1, p2).
        let columns = [
            three(|r| select(&low, &p1[r], &u[r])),
            three(|r| select(&low, &p2[r], &p1[r])),
            three(|r| select(&low, &u[r], &p2[r])),
        ];
        let low_mean: Lane<L> = lanes(|l| 0.5 * (m[0][l] + m[1][l]));
        let high_mean: Lane<L> = lanes(|l| 0.5 * (m[1][l] + m[2][l]));
        let paired = [
            select(&low, &low_mean, &m[0]),
            select(&low, &low_mean, &high_mean),
            select(&low, &m[2], &high_mean),
        ];
        for k in 0..3 {
            for r in 0..3 {
                axes[k][r] = select(&pair, &columns[k][r], &axes[k][r]);
            }
            moments[k] = select(&pair, &paired[k], &moments[k]);
        }
    }
    // A spherical body: the moments' mean and the body's own axes.
    let sphere: Mask<L> = each(|l| low[l] & high[l]);
    if any(&sphere) {
        let mean: Lane<L> = lanes(|l| (m[0][l] + m[1][l] + m[2][l]) / 3.0);
        for k in 0..3 {
            moments[k] = select(&sphere, &mean, &moments[k]);
            for r in 0..3 {
                let identity = [if r == k { 1.0 } else { 0.0 }; L];
                axes[k][r] = select(&sphere, &identity, &axes[k][r]);
            }
        }
    }
    // [1, 1, 1] distinct, [2, 2, 1] low, [1, 2, 2] high, [3, 3, 3] a sphere.
    let (low, high, sphere): ([u64; L], [u64; L], [u64; L]) = (
        each(|l| low[l] & 1),
        each(|l| high[l] & 1),
        each(|l| sphere[l] & 1),
    );
    let multiplicity = [
        each(|l| 1 + low[l] + sphere[l]),
        each(|l| 1 + (low[l] | high[l]) + sphere[l]),
        each(|l| 1 + high[l] + sphere[l]),
    ];
    CanonicalLanes {
        moments,
        axes: three(|r| three(|c| axes[c][r])),
        multiplicity,
    }
}

/// One-sided (Hestenes) Jacobi SVD of a 3x3 factor `f`: the singular values and the right
/// singular vectors (columns of `V`, `f^T f = V diag(s^2) V^T`).
///
/// Columns of `f V` are orthogonalised pairwise until every pair is orthogonal to `eps` of its
/// norms (Demmel & Veselic 1992), which gives small singular values to high relative accuracy
/// when the columns are well scaled: the needle's smallest moment survives.
pub(crate) fn right_singular(f: &Matrix3<f64>) -> ([f64; 3], Matrix3<f64>) {
    let mut g = [
        [f[(0, 0)], f[(1, 0)], f[(2, 0)]],
        [f[(0, 1)], f[(1, 1)], f[(2, 1)]],
        [f[(0, 2)], f[(1, 2)], f[(2, 2)]],
    ]; // g[col][row]
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // v[col][row]
    let dot = |x: &[f64; 3], y: &[f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    for _ in 0..MAX_SWEEPS {
        let mut rotated = false;
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            let alpha = dot(&g[p], &g[p]);
            let beta = dot(&g[q], &g[q]);
            let gamma = dot(&g[p], &g[q]);
            if gamma == 0.0 || gamma.abs() <= f64::EPSILON * (alpha.sqrt() * beta.sqrt()) {
                continue;
            }
            rotated = true;
            let zeta = (beta - alpha) / (2.0 * gamma);
            let t = if zeta.abs() > 1e150 {
                0.5 / zeta
            } else {
                zeta.signum() / (zeta.abs() + (1.0 + zeta * zeta).sqrt())
            };
            let c = 1.0 / (1.0 + t * t).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (gp, gq) = (g[p][k], g[q][k]);
                g[p][k] = c * gp - s * gq;
                g[q][k] = s * gp + c * gq;
                let (vp, vq) = (v[p][k], v[q][k]);
                v[p][k] = c * vp - s * vq;
                v[q][k] = s * vp + c * vq;
            }
        }
        if !rotated {
            break;
        }
    }
    let norm = |x: &[f64; 3]| x[0].hypot(x[1]).hypot(x[2]);
    let values = [norm(&g[0]), norm(&g[1]), norm(&g[2])];
    let vectors = Matrix3::new(
        v[0][0], v[1][0], v[2][0], v[0][1], v[1][1], v[2][1], v[0][2], v[1][2], v[2][2],
    );
    (values, vectors)
}

/// Sorts, groups equal moments (gap `<= tolerance`, an absolute number already scaled by the
/// caller), and fixes the frame: deterministic signs, det = +1, and inside a degenerate subspace
/// the axes closest to the body's own.
pub(crate) fn canonical(values: [f64; 3], vectors: Matrix3<f64>, tolerance: f64) -> Principal {
    let vectors = [0, 1, 2].map(|r| [0, 1, 2].map(|c| [vectors[(r, c)]]));
    canonical_lanes::<1>(values.map(|v| [v]), vectors, &[tolerance]).principal(0)
}

/// Principal moments and axes of a batch of tensors, in parallel on all cores.
///
/// `tensors` holds row-major 3x3 tensors (`tensors[9 i + 3 r + c]`, numpy's (N, 3, 3) layout);
/// `moments` receives `3 N` values, `axes` `9 N` (row-major, columns are the axes) and
/// `multiplicity` `3 N` (as `i64`, numpy's default integer, so that no conversion pass is
/// needed). Errors name the first bad tensor as `inertia[i]`. Each tensor is solved on its own,
/// so the results do not depend on the number of threads.
pub fn principal_batch(
    tensors: &[f64],
    rtol: f64,
    moments: &mut [f64],
    axes: &mut [f64],
    multiplicity: &mut [i64],
) -> Result<()> {
    principal_batch_monitored(tensors, rtol, moments, axes, multiplicity, None)
}

/// Tensors per chunk of [`principal_batch_monitored`] (about a millisecond of work): the unit of
/// parallel work and of the looks at the monitor.
pub const BATCH_CHUNK: usize = 4096;

/// [`principal_batch`] watched by `monitor`: a look ([`Monitor::look`]) before each chunk of
/// [`BATCH_CHUNK`] tensors, so that a cancelled monitor stops the batch within a chunk, with
/// [`Error::Interrupted`].
///
/// Of several bad tensors, the error is the first's (in the batch's order), whatever the number
/// of threads, as [`Error::Body`] with its index.
pub fn principal_batch_monitored(
    tensors: &[f64],
    rtol: f64,
    moments: &mut [f64],
    axes: &mut [f64],
    multiplicity: &mut [i64],
    monitor: Option<&Monitor>,
) -> Result<()> {
    crate::settings::Setting::MergeTolerance.check("rtol", rtol)?;
    let n = tensors.len() / 9;
    if tensors.len() != 9 * n
        || moments.len() != 3 * n
        || axes.len() != 9 * n
        || multiplicity.len() != 3 * n
    {
        return Err(Error::Shape {
            name: "inertia".into(),
            expected: "(N, 3, 3)".into(),
            got: format!("{} values", tensors.len()),
        });
    }
    const CHUNK: usize = BATCH_CHUNK;
    // The first chunk known to have failed: later chunks are skipped (they cannot hold the
    // first error), earlier ones never are, so the error reported does not depend on timing.
    let first_failure = AtomicUsize::new(usize::MAX);
    let outcomes: Vec<Result<()>> = memory::collect_parallel(
        tensors
            .par_chunks(9 * CHUNK)
            .zip(moments.par_chunks_mut(3 * CHUNK))
            .zip(axes.par_chunks_mut(9 * CHUNK))
            .zip(multiplicity.par_chunks_mut(3 * CHUNK))
            .enumerate()
            .map(|(chunk, (((t, m), x), u))| {
                if chunk > first_failure.load(Ordering::Relaxed) {
                    return Ok(());
                }
                let outcome = match monitor {
                    Some(monitor) => monitor.look(),
                    None => Ok(()),
                }
                .and_then(|()| solve_chunk(t, m, x, u, rtol, chunk * CHUNK));
                if outcome.is_err() {
                    first_failure.fetch_min(chunk, Ordering::Relaxed);
                }
                outcome
            }),
        Purpose::PrincipalAxes,
    )?;
    // The first error in the batch's order: an interruption only if no tensor before it was bad.
    outcomes.into_iter().collect()
}

/// Tensors per Jacobi group: twelve, three AVX2 registers of four doubles (six SSE2 ones) per
/// entry. A rotation is a chain of dependent square roots and divisions (tau, t, c) whose
/// latency, not the arithmetic, bounds a group: with three independent registers side by side
/// three chains overlap. Measured with a scratch bench (one thread, a chunk of 6144 tensors,
/// random / rotated diag(1, 1, 2), ns per tensor): 4 lanes 127 / 84, 8 lanes 141 / 104 (LLVM
/// leaves much of 4 and 8 lanes scalar), 16 lanes 85 / 74, 12 lanes 73 / 54; 24 spills and
/// runs ~3x slower.
const LANES: usize = 12;

/// The tail of a chunk (fewer than [`LANES`] tensors) in groups of this many, then one by one.
const TAIL_LANES: usize = 4;

/// One chunk of the batch, with the widest vector instructions the CPU has
/// ([`crate::simd::dispatch`]: the same IEEE operations either way, so results do not depend on
/// it).
fn solve_chunk(
    t: &[f64],
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
    offset: usize,
) -> Result<()> {
    let tensors = t.as_chunks::<9>().0;
    // Each group size in a function of its own: the kernel's registers are then allocated for
    // its loop alone (inlined together, the 12-lane loop ran ~1.5x slower).
    let done = crate::simd::dispatch(
        #[inline(always)]
        || solve_groups::<LANES>(tensors, 0, m, x, u, rtol, offset),
    )?;
    let done = crate::simd::dispatch(
        #[inline(always)]
        || solve_groups::<TAIL_LANES>(&tensors[done..], done, m, x, u, rtol, offset),
    )?;
    for (l, tensor) in tensors[done..].iter().enumerate() {
        solve_one(tensor, done + l, m, x, u, rtol, offset)?;
    }
    Ok(())
}

/// Solves the tensors of `tensors` in groups of `L` (the first is tensor `first` of the chunk)
/// and returns the index of the first tensor left (`first` plus a multiple of `L`), or the
/// first error.
#[inline(always)]
fn solve_groups<const L: usize>(
    tensors: &[[f64; 9]],
    first: usize,
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
    offset: usize,
) -> Result<usize> {
    let (groups, _) = tensors.as_chunks::<L>();
    for (g, group) in groups.iter().enumerate() {
        let start = first + g * L;
        if !solve_group::<L>(group, start, m, x, u, rtol) {
            // A bad tensor in the group: one by one, in order, for the first error.
            for (l, tensor) in group.iter().enumerate() {
                solve_one(tensor, start + l, m, x, u, rtol, offset)?;
            }
        }
    }
    Ok(first + groups.len() * L)
}

/// Tensor `i` of the chunk on its own, or its error (as body `offset + i`).
#[inline(always)]
fn solve_one(
    tensor: &[f64; 9],
    i: usize,
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
    offset: usize,
) -> Result<()> {
    if !solve_group::<1>(std::array::from_ref(tensor), i, m, x, u, rtol) {
        let tensor = Matrix3::from_row_slice(tensor);
        let error = match checked_symmetric(&tensor, "inertia") {
            Err(e) => e,
            Ok(a) => {
                let (p, k) = eigen_symmetric_scaled(&a, rtol);
                moments_overflow("inertia", p.moments.abs().max(), k)
            }
        };
        return Err(error.in_body(offset + i));
    }
    Ok(())
}

/// Solves `L` tensors (row by row) into entries `first..first + L` of the outputs; false (and
/// the outputs of the group unspecified) if one of them is not finite or not symmetric (see
/// [`checked_symmetric`], whose arithmetic this repeats lane by lane) or its moments overflow.
#[inline(always)]
fn solve_group<const L: usize>(
    tensors: &[[f64; 9]; L],
    first: usize,
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
) -> bool {
    let mut good = [true; L];
    let mut largest = [0.0f64; L];
    for e in 0..9 {
        for l in 0..L {
            let v = tensors[l][e];
            good[l] &= v.is_finite();
            largest[l] = largest[l].max(v.abs());
        }
    }
    let mut sym = *tensors;
    for (r, c) in [(0, 1), (0, 2), (1, 2)] {
        for l in 0..L {
            let (upper, lower) = (tensors[l][3 * r + c], tensors[l][3 * c + r]);
            good[l] &= (upper - lower).abs() <= 64.0 * f64::EPSILON * largest[l];
            // The mean of the two mirrors, as in `checked_symmetric`.
            let sum = upper + lower;
            let mean = if sum.is_finite() {
                sum * 0.5
            } else {
                upper * 0.5 + lower * 0.5
            };
            sym[l][3 * r + c] = mean;
            sym[l][3 * c + r] = mean;
        }
    }
    if !good.iter().all(|&g| g) {
        return false;
    }
    let mut lanes = Lanes::<L>::default();
    lanes.load(&sym);
    lanes.solve();
    let p = lanes.canonical(rtol);
    let (f1, f2) = ldexp_factors(&lanes.exponent);
    let moments: [Lane<L>; 3] = three(|k| self::lanes(|l| p.moments[k][l] * f1[l] * f2[l]));
    let mut finite = true;
    for v in &moments {
        for l in 0..L {
            finite &= v[l].is_finite();
        }
    }
    if !finite {
        return false;
    }
    for l in 0..L {
        let i = first + l;
        for k in 0..3 {
            m[3 * i + k] = moments[k][l];
            u[3 * i + k] = p.multiplicity[k][l] as i64;
        }
        for r in 0..3 {
            for c in 0..3 {
                x[9 * i + 3 * r + c] = p.axes[r][c][l];
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn residual(a: &Matrix3<f64>, p: &Principal) -> f64 {
        (a * p.axes - p.axes * Matrix3::from_diagonal(&p.moments)).norm() / a.norm()
    }

    #[test]
    fn nearly_diagonal_tensors_keep_a_small_residual() {
        // nalgebra issue #1109: a deflated 2x2 block mis-rotated eigenvectors of such tensors.
        for off in [1e-10, 1e-14, 1e-17, 1e-300] {
            let a = Matrix3::new(1.0, off, 0.0, off, 2.0, off, 0.0, off, 3.0);
            let p = symmetric_eigen3(&a).unwrap();
            assert!(residual(&a, &p) <= 10.0 * f64::EPSILON, "off = {off}");
        }
    }

    #[test]
    fn degenerate_rotated_tensor_gives_canonical_frame() {
        let r = Rotation3::from_euler_angles(0.3, -1.1, 2.0);
        let a = r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 2.0)) * r.transpose();
        let p = symmetric_eigen3(&a).unwrap();
        assert_eq!(p.multiplicity, [2, 2, 1]);
        assert_eq!(p.moments[0], p.moments[1]);
        let unique = r.matrix().column(2).into_owned();
        assert!(p.axes.column(2).dot(&unique).abs() > 1.0 - 1e-14);
        assert!((p.axes.determinant() - 1.0).abs() < 1e-14);
        assert!(residual(&a, &p) <= 10.0 * f64::EPSILON);
    }

    #[test]
    fn an_anisotropic_part_below_the_smallest_normal_is_a_sphere() {
        // Scaled to entries near 1, the products of inertia were subnormal: their reciprocal
        // overflowed, and the tensor was refused for moments beyond double precision.
        for off in [1e-308, 1e-310, 3e-320] {
            let a = Matrix3::new(1.0, off, 0.0, off, 1.0, 0.0, 0.0, 0.0, 1.0);
            let p = symmetric_eigen3(&a).unwrap();
            assert_eq!(p.moments, Vector3::new(1.0, 1.0, 1.0), "off = {off}");
            assert_eq!(p.multiplicity, [3, 3, 3]);
            assert_eq!(p.axes, Matrix3::identity());
        }
    }

    #[test]
    fn hestenes_svd_resolves_tiny_singular_values() {
        let f = Matrix3::new(3.0, 0.0, 0.0, 0.0, 1e-9, 0.0, 0.0, 0.0, 1e-12);
        let r = Rotation3::from_euler_angles(0.4, 0.2, -0.7);
        let (s, v) = right_singular(&(f * r.transpose()));
        let mut s = s;
        s.sort_by(f64::total_cmp);
        assert!((s[0] - 1e-12).abs() <= 1e-12 * 1e-3);
        assert!((s[1] - 1e-9).abs() <= 1e-9 * 1e-6);
        assert!((v.transpose() * v - Matrix3::identity()).norm() < 1e-15);
    }
}
