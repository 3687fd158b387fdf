//! The symmetric 3x3 eigensolve behind principal axes.
//!
//! Inertia tensors are degenerate or nearly so whenever a body has a symmetry, and closed-form
//! (Cardano) solvers lose half the digits there. This module uses cyclic Jacobi rotations on the
//! tensor shifted by `trace/3` (backward stable: residual of a few eps ||A|| on every input) and a
//! one-sided (Hestenes) Jacobi SVD for the square-root factors kept by
//! [`MassProperties`](crate::MassProperties). Both then go through one canonicalisation: moments
//! ascending, axes a proper rotation with deterministic signs, and inside a degenerate subspace
//! the frame closest to the body's own axes.

use std::sync::atomic::{AtomicUsize, Ordering};

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use crate::dynamics::Monitor;
use crate::error::{Error, Result};

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

/// [`symmetric_eigen3`] with an explicit relative tolerance for equal moments; `name` is the
/// argument named in errors.
///
/// Any finite symmetric tensor is accepted, from subnormal to the largest doubles: the tensor is
/// scaled by a power of two before the solve and the moments scaled back (exactly, unless they
/// are subnormal). Moments beyond the range of double precision (a tensor near `f64::MAX` whose
/// largest eigenvalue exceeds it) are an [`Error::InvalidArgument`] naming `name`.
pub fn symmetric_eigen3_with(tensor: &Matrix3<f64>, rtol: f64, name: &str) -> Result<Principal> {
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
    let k = lanes.load(0, a);
    lanes.solve();
    (lanes.principal(0, rtol), k)
}

/// `L` symmetric tensors solved side by side (`a[r][c][lane]`), so that the divisions and
/// square roots of independent Jacobi rotations overlap in the pipeline (and in SIMD lanes).
#[derive(Clone, Copy)]
struct Lanes<const L: usize> {
    a: [[[f64; L]; 3]; 3],
    v: [[[f64; L]; 3]; 3],
    shift: [f64; L],
    scale: [f64; L],
    norm: [f64; L],
    /// The lane holds its tensor times `2^-exponent`.
    exponent: [i32; L],
}

impl<const L: usize> Default for Lanes<L> {
    fn default() -> Self {
        Self {
            a: [[[0.0; L]; 3]; 3],
            v: [[[0.0; L]; 3]; 3],
            shift: [0.0; L],
            scale: [1.0; L],
            norm: [0.0; L],
            exponent: [0; L],
        }
    }
}

impl<const L: usize> Lanes<L> {
    /// Loads tensor `m` into `lane`, shifted by trace/3 and scaled to entries of size <= 1;
    /// returns `k` with the lane holding `m 2^-k` (its moments come out in units of `2^k`).
    ///
    /// The power of two first brings the largest entry to [0.5, 1), exactly (but for
    /// subnormal entries far below the largest, whose rounding is far below eps of it): the
    /// trace, the norm and the squares of the Jacobi rotations then can neither overflow (a
    /// tensor of 1e154) nor underflow (a subnormal one), and in the normal range the
    /// arithmetic is that of the unscaled tensor times the same power of two.
    fn load(&mut self, lane: usize, m: &Matrix3<f64>) -> i32 {
        let largest = m.iter().fold(0.0_f64, |l, x| l.max(x.abs()));
        let k = exponent(largest);
        let m = &m.map(|x| ldexp(x, -k));
        let shift = (m[(0, 0)] + m[(1, 1)] + m[(2, 2)]) / 3.0;
        let mut largest = 0.0_f64;
        for r in 0..3 {
            for c in 0..3 {
                let x = if r == c { m[(r, c)] - shift } else { m[(r, c)] };
                largest = largest.max(x.abs());
            }
        }
        let scale = if largest > 0.0 { largest } else { 1.0 };
        let inverse = 1.0 / scale;
        for r in 0..3 {
            for c in 0..3 {
                let x = if r == c { m[(r, c)] - shift } else { m[(r, c)] };
                self.a[r][c][lane] = x * inverse;
                self.v[r][c][lane] = if r == c { 1.0 } else { 0.0 };
            }
        }
        self.shift[lane] = shift;
        self.scale[lane] = scale;
        self.norm[lane] = m.norm();
        self.exponent[lane] = k;
        k
    }

    /// Cyclic Jacobi (Golub & Van Loan 8.5.2, symmetric Schur rotations with the smaller root so
    /// the angle is at most pi/4) until every off-diagonal entry of every lane is below
    /// `eps/16` of the (unit-scaled) matrix: dropping them is a backward error far inside the
    /// solver's own rounding, and quadratic convergence gets there one sweep after `eps`.
    fn solve(&mut self) {
        let negligible = f64::EPSILON / 16.0;
        for _ in 0..MAX_SWEEPS {
            let mut converged = true;
            for l in 0..L {
                let a = &self.a;
                converged &= a[0][1][l].abs() <= negligible
                    && a[0][2][l].abs() <= negligible
                    && a[1][2][l].abs() <= negligible;
            }
            if converged {
                break;
            }
            for (p, q, r) in [(0, 1, 2), (0, 2, 1), (1, 2, 0)] {
                let mut c = [1.0; L];
                let mut s = [0.0; L];
                let mut t = [0.0; L];
                for l in 0..L {
                    let apq = self.a[p][q][l];
                    let active = apq.abs() > negligible;
                    // t = tan(theta) = sign(tau) / (|tau| + sqrt(1 + tau^2)) with
                    // tau = d / e, multiplied through by |e|: one division fewer on the
                    // critical path. Entries are <= 1 after scaling, so d^2 + e^2 cannot
                    // overflow, and |e| > eps/8 keeps it from vanishing.
                    let e = if active { 2.0 * apq } else { 1.0 };
                    let d = self.a[q][q][l] - self.a[p][p][l];
                    let root = d.signum() * e / (d.abs() + (d * d + e * e).sqrt());
                    t[l] = if active { root } else { 0.0 };
                    c[l] = 1.0 / (1.0 + t[l] * t[l]).sqrt();
                    s[l] = t[l] * c[l];
                }
                // Each update is its own loop over the lanes (contiguous), so that it vectorises.
                let a = &mut self.a;
                let mut apq = [0.0; L];
                apq.copy_from_slice(&a[p][q]);
                for l in 0..L {
                    a[p][p][l] -= t[l] * apq[l];
                    a[q][q][l] += t[l] * apq[l];
                    let keep = if t[l] == 0.0 { apq[l] } else { 0.0 };
                    a[p][q][l] = keep;
                    a[q][p][l] = keep;
                }
                for l in 0..L {
                    let (arp, arq) = (a[r][p][l], a[r][q][l]);
                    a[r][p][l] = c[l] * arp - s[l] * arq;
                    a[r][q][l] = s[l] * arp + c[l] * arq;
                    a[p][r][l] = a[r][p][l];
                    a[q][r][l] = a[r][q][l];
                }
                for row in &mut self.v {
                    for l in 0..L {
                        let (vp, vq) = (row[p][l], row[q][l]);
                        row[p][l] = c[l] * vp - s[l] * vq;
                        row[q][l] = s[l] * vp + c[l] * vq;
                    }
                }
            }
        }
    }

    /// The canonical principal frame of `lane`; equal moments within `rtol ||A||_F`.
    fn principal(&self, lane: usize, rtol: f64) -> Principal {
        let (shift, scale) = (self.shift[lane], self.scale[lane]);
        let values = [0, 1, 2].map(|k| self.a[k][k][lane] * scale + shift);
        let vectors = Matrix3::from_fn(|r, c| self.v[r][c][lane]);
        canonical(values, vectors, rtol * self.norm[lane])
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
    // A three-element sorting network: fewer unpredictable branches than a sort call.
    let mut order = [0usize, 1, 2];
    for (a, b) in [(0, 1), (1, 2), (0, 1)] {
        if values[order[b]] < values[order[a]] {
            order.swap(a, b);
        }
    }
    let mut moments = Vector3::new(values[order[0]], values[order[1]], values[order[2]]);
    let column = |k: usize| -> Vector3<f64> { vectors.column(order[k]).into_owned() };

    let low_equal = moments[1] - moments[0] <= tolerance;
    let high_equal = moments[2] - moments[1] <= tolerance;
    let (axes, multiplicity) = if low_equal && high_equal {
        moments.fill(moments.sum() / 3.0);
        (Matrix3::identity(), [3, 3, 3])
    } else if low_equal || high_equal {
        // A symmetric body: one unique axis `u` and a plane of equal moments.
        let (unique, first, second) = if low_equal { (2, 0, 1) } else { (0, 1, 2) };
        let mean = 0.5 * (moments[first] + moments[second]);
        moments[first] = mean;
        moments[second] = mean;
        let u = unit(signed(column(unique)));
        // In the plane: the projection of the body axis most perpendicular to `u` (the first
        // such axis on a tie), then the axis that completes a right-handed frame.
        let mut j = 0;
        for k in 1..3 {
            if u[k].abs() < u[j].abs() {
                j = k;
            }
        }
        let mut p1 = -u * u[j];
        p1[j] += 1.0;
        let p1 = unit(p1);
        let p2 = u.cross(&p1);
        let mut axes = Matrix3::zeros();
        axes.set_column(unique, &u);
        axes.set_column(first, &p1);
        axes.set_column(second, &p2);
        let mut multiplicity = [2, 2, 2];
        multiplicity[unique] = 1;
        (axes, multiplicity)
    } else {
        // Gram-Schmidt once: the accumulated rotations leave columns orthogonal only to a few
        // eps per rotation.
        let a0 = unit(signed(column(0)));
        let a1 = column(1);
        let a1 = unit(signed(a1 - a0 * a0.dot(&a1)));
        let a2 = a0.cross(&a1);
        (Matrix3::from_columns(&[a0, a1, a2]), [1, 1, 1])
    };
    Principal {
        moments,
        axes,
        multiplicity,
    }
}

/// `v / |v|` with one division.
#[inline]
fn unit(v: Vector3<f64>) -> Vector3<f64> {
    v * (1.0 / v.norm())
}

/// The vector with the sign that makes its largest-magnitude component (the first on a tie)
/// positive.
fn signed(v: Vector3<f64>) -> Vector3<f64> {
    let mut j = 0;
    for k in 1..3 {
        if v[k].abs() > v[j].abs() {
            j = k;
        }
    }
    if v[j] < 0.0 {
        -v
    } else {
        v
    }
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
    let outcomes: Vec<Result<()>> = tensors
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
        })
        .collect();
    // The first error in the batch's order: an interruption only if no tensor before it was bad.
    outcomes.into_iter().collect()
}

/// Tensors per Jacobi group: independent rotations side by side fill the SIMD lanes.
const LANES: usize = 8;

/// One chunk of the batch, with the widest vector instructions the CPU has (checked at run
/// time; the arithmetic is the same IEEE operations either way, so results do not depend on it).
fn solve_chunk(
    t: &[f64],
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
    offset: usize,
) -> Result<()> {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { solve_chunk_avx2(t, m, x, u, rtol, offset) };
        }
    }
    solve_chunk_generic(t, m, x, u, rtol, offset)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
unsafe fn solve_chunk_avx2(
    t: &[f64],
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
    offset: usize,
) -> Result<()> {
    solve_chunk_generic(t, m, x, u, rtol, offset)
}

#[inline(always)]
fn solve_chunk_generic(
    t: &[f64],
    m: &mut [f64],
    x: &mut [f64],
    u: &mut [i64],
    rtol: f64,
    offset: usize,
) -> Result<()> {
    let count = t.len() / 9;
    for first in (0..count).step_by(LANES) {
        let mut lanes = Lanes::<LANES>::default();
        let used = LANES.min(count - first);
        for l in 0..used {
            let i = first + l;
            let tensor = Matrix3::from_row_slice(&t[9 * i..9 * i + 9]);
            match checked_symmetric(&tensor, "inertia") {
                Ok(a) => {
                    lanes.load(l, &a);
                }
                Err(e) => return Err(e.in_body(offset + i)),
            }
        }
        lanes.solve();
        for l in 0..used {
            let i = first + l;
            let p = lanes.principal(l, rtol);
            let k = lanes.exponent[l];
            for (out, &x) in m[3 * i..3 * i + 3].iter_mut().zip(p.moments.iter()) {
                *out = ldexp(x, k);
            }
            if !m[3 * i..3 * i + 3].iter().all(|x| x.is_finite()) {
                return Err(
                    moments_overflow("inertia", p.moments.abs().max(), k).in_body(offset + i)
                );
            }
            for (k, &count) in p.multiplicity.iter().enumerate() {
                u[3 * i + k] = i64::from(count);
            }
            for r in 0..3 {
                for c in 0..3 {
                    x[9 * i + 3 * r + c] = p.axes[(r, c)];
                }
            }
        }
    }
    Ok(())
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
