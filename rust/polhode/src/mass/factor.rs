//! The square-root form of a second-moment matrix and its updates by Householder QR.
//!
//! A second-moment matrix `C = sum m r r^T` (about the centre of mass) is kept as
//! `C = isotropic * 1 + F^T F` with `F` a 3x3 factor. Spheres, cubes and the common part of all
//! three moments go into `isotropic` exactly; everything else is rows of `F`, each row a
//! `sqrt(m) r^T`. Adding bodies stacks rows and re-triangularises by Householder QR, which never
//! squares the data: the tiny anisotropy of a heavy sphere plus a speck and the tiny moments of a
//! needle both survive (docs/architecture.md, Numerics).

use nalgebra::{Matrix3, Vector3};

use crate::eigen::{exponent, ldexp};

/// `C = isotropic * 1 + factor^T factor`, with `isotropic >= 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SecondMoment {
    pub isotropic: f64,
    pub factor: Matrix3<f64>,
}

impl SecondMoment {
    /// The zero second moment (a point mass).
    pub const ZERO: Self = Self {
        isotropic: 0.0,
        factor: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// From principal second moments `c` (diagonal C) in the body axes: the common part to
    /// `isotropic`, the rest as the diagonal factor `sqrt(c - min c)`.
    pub fn diagonal(c: Vector3<f64>) -> Self {
        let isotropic = c.min().max(0.0);
        let d = c.map(|ck| (ck - isotropic).max(0.0).sqrt());
        Self {
            isotropic,
            factor: Matrix3::from_diagonal(&d),
        }
    }

    /// The full matrix `C`.
    pub fn matrix(&self) -> Matrix3<f64> {
        self.factor.tr_mul(&self.factor) + Matrix3::identity() * self.isotropic
    }

    /// `C -> Q C Q^T` for a rotation `Q`.
    pub fn rotated(&self, rotation: &Matrix3<f64>) -> Self {
        Self {
            isotropic: self.isotropic,
            factor: self.factor * rotation.transpose(),
        }
    }

    /// `C -> C m l^2` (masses times `m`, lengths times `l`, both positive), with the powers
    /// of two apart so that no intermediate product over- or underflows where the result does
    /// not.
    pub fn scaled(&self, m: f64, l: f64) -> Self {
        let (s, k) = self.normalised();
        // m = fm 2^em with em even (fm in [0.5, 2)), l = fl 2^el.
        let mut em = exponent(m);
        if em % 2 != 0 {
            em -= 1;
        }
        let fm = ldexp(m, -em);
        let el = exponent(l);
        let fl = ldexp(l, -el);
        let root = fm.sqrt() * fl;
        Self {
            isotropic: ldexp(s.isotropic * (fm * fl * fl), 2 * k + em + 2 * el),
            factor: s.factor.map(|x| ldexp(x * root, k + em / 2 + el)),
        }
    }

    /// The same second moment in units of `2^(2k)`, and `k`: the factor's entries below 1 and
    /// the isotropic part below 1 (one of them at least 1/4), exactly unless entries are far
    /// below the largest. Zero stays zero (`k = 0`).
    pub fn normalised(&self) -> (Self, i32) {
        let f = self.factor.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let mut k = None;
        if f > 0.0 && f.is_finite() {
            k = Some(exponent(f));
        }
        if self.isotropic > 0.0 && self.isotropic.is_finite() {
            // iso 2^-2k < 1 needs 2k >= exponent(iso).
            let ki = (exponent(self.isotropic) + 1).div_euclid(2);
            k = Some(k.map_or(ki, |kf: i32| kf.max(ki)));
        }
        let k = k.unwrap_or(0);
        if k == 0 {
            return (*self, 0);
        }
        (
            Self {
                isotropic: ldexp(self.isotropic, -2 * k),
                factor: self.factor.map(|x| ldexp(x, -k)),
            },
            k,
        )
    }

    /// `C = V diag(c 2^k) V^T` (the columns of `axes` are `V`) in square-root form: the common
    /// part of `c` to `isotropic`, the rest as the factor `diag(sqrt(c - min c)) V^T`. Negative
    /// entries of `c` (rounding) count as 0. The square roots are taken before the powers of two
    /// are applied, so subnormal moments keep their digits.
    pub fn principal_form(c: Vector3<f64>, k: i32, axes: &Matrix3<f64>) -> Self {
        // k = 2 h + r with r in {0, 1}: 2^r goes into c, 2^h out of the square roots.
        let h = k.div_euclid(2);
        let c = c.map(|x| ldexp(x, k - 2 * h));
        let scaled = Self::diagonal(c);
        Self {
            isotropic: ldexp(scaled.isotropic, 2 * h),
            factor: (scaled.factor * axes.transpose()).map(|x| ldexp(x, h)),
        }
    }
}

/// Accumulates rows into an upper-triangular 3x3 factor `R` with `R^T R = sum row row^T`.
///
/// Rows are buffered and folded in by Householder QR of `[R; rows]` (Golub & Van Loan 5.2),
/// which is backward stable: the result is the exact factor of rows perturbed by eps of their
/// own size.
#[derive(Debug, Clone)]
pub(crate) struct RowAccumulator {
    /// Column-major work block: `block[col][row]`, the first three rows hold R.
    block: [Vec<f64>; 3],
    len: usize,
}

/// Rows folded in at once: large enough to amortise the fold, small enough for L1.
const BLOCK_ROWS: usize = 256;

impl Default for RowAccumulator {
    fn default() -> Self {
        Self::new()
    }
}

impl RowAccumulator {
    pub fn new() -> Self {
        let col = || vec![0.0; 3 + BLOCK_ROWS];
        Self {
            block: [col(), col(), col()],
            len: 3,
        }
    }

    /// Adds one row `r` (contributing `r r^T`).
    #[inline]
    pub fn push(&mut self, row: [f64; 3]) {
        if self.len == 3 + BLOCK_ROWS {
            self.fold();
        }
        let n = self.len;
        self.block[0][n] = row[0];
        self.block[1][n] = row[1];
        self.block[2][n] = row[2];
        self.len += 1;
    }

    /// Adds every row of a 3x3 matrix.
    pub fn push_matrix(&mut self, m: &Matrix3<f64>) {
        for r in 0..3 {
            self.push([m[(r, 0)], m[(r, 1)], m[(r, 2)]]);
        }
    }

    /// Householder QR of the block in place; leaves R in the first three rows.
    fn fold(&mut self) {
        let n = self.len;
        if n <= 3 {
            return;
        }
        let [c0, c1, c2] = &mut self.block;
        householder_column(&mut c0[..n], &mut [&mut c1[..n], &mut c2[..n]], 0);
        householder_column(&mut c1[..n], &mut [&mut c2[..n]], 1);
        householder_column(&mut c2[..n], &mut [], 2);
        self.len = 3;
    }

    /// The upper-triangular factor `R`.
    pub fn finish(mut self) -> Matrix3<f64> {
        self.fold();
        let b = &self.block;
        Matrix3::new(
            b[0][0], b[1][0], b[2][0], 0.0, b[1][1], b[2][1], 0.0, 0.0, b[2][2],
        )
    }
}

/// One Householder reflection zeroing `col[j+1..]` below the diagonal entry `col[j]`, applied
/// to the `rest` columns; entries above `j` are untouched.
fn householder_column(col: &mut [f64], rest: &mut [&mut [f64]], j: usize) {
    let x = &mut col[j..];
    let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 || x.len() < 2 {
        // `max` skips NaN: a column of zeros and NaN must not lose its NaN below the diagonal
        // (only the first three rows are kept).
        if x.iter().any(|v| v.is_nan()) {
            x[0] = f64::NAN;
        }
        return;
    }
    let original_head = x[0];
    let inverse = 1.0 / scale;
    if inverse.is_finite() {
        for v in x.iter_mut() {
            *v *= inverse;
        }
    } else {
        // A subnormal column: its reciprocal overflows, so divide.
        for v in x.iter_mut() {
            *v /= scale;
        }
    }
    let tail: f64 = x[1..].iter().map(|v| v * v).sum();
    if tail == 0.0 {
        x[0] = original_head;
        return;
    }
    let head = x[0];
    let norm = (head * head + tail).sqrt();
    let alpha = if head > 0.0 { -norm } else { norm };
    // v = x/scale - alpha e1 (stored in x); H = 1 - 2 v v^T / (v^T v).
    x[0] = head - alpha;
    let vtv = x[0] * x[0] + tail;
    for other in rest.iter_mut() {
        let y = &mut other[j..];
        let dot: f64 = x.iter().zip(y.iter()).map(|(a, b)| a * b).sum();
        let f = 2.0 * dot / vtv;
        for (xi, yi) in x.iter().zip(y.iter_mut()) {
            *yi -= f * xi;
        }
    }
    x[0] = alpha * scale;
    for xi in &mut x[1..] {
        *xi = 0.0;
    }
}

/// `C_a + C_b + rows of `extra``, all in square-root form.
pub(crate) fn combine(a: &SecondMoment, b: &SecondMoment, extra: &[Vector3<f64>]) -> SecondMoment {
    let mut acc = RowAccumulator::new();
    acc.push_matrix(&a.factor);
    acc.push_matrix(&b.factor);
    for row in extra {
        acc.push([row[0], row[1], row[2]]);
    }
    SecondMoment {
        isotropic: a.isotropic + b.isotropic,
        factor: acc.finish(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accumulator_reproduces_the_gram_matrix() {
        let mut acc = RowAccumulator::new();
        let mut gram = Matrix3::zeros();
        for i in 0..1000 {
            let x = i as f64;
            let row = [(0.37 * x).sin(), (1.3 * x).cos() * 2.0, 0.01 * x - 3.0];
            let v = Vector3::from(row);
            gram += v * v.transpose();
            acc.push(row);
        }
        let r = acc.finish();
        assert!((r.tr_mul(&r) - gram).norm() <= 1e-13 * gram.norm());
    }
}
