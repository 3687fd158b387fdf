//! Bodies made of point masses (a molecule, a sampled cloud).

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::factor::{RowAccumulator, SecondMoment};
use super::MassProperties;
use crate::eigen::{exponent, ldexp};
use crate::error::{finite, Error, Result};
use crate::memory::{self, Purpose};
use crate::Monitor;

/// Points per parallel chunk: each chunk is factored on its own and the factors combined, in
/// order. Fixed, so that the result does not depend on the number of threads.
pub const POINT_CHUNK: usize = 1 << 15;
const CHUNK: usize = POINT_CHUNK;

impl MassProperties {
    /// Point masses `masses[i]` at `positions[i]` (body coordinates).
    ///
    /// One pass over the points: the offsets `d_i = r_i - r_0` from a reference point (the
    /// centre of mass of the first 256 points) are formed, and the square root of the second
    /// moments about the centre of mass is found block by block (256 points, in parallel
    /// chunks, vectorised): each block is centred on the running centre of mass and its rows
    /// `sqrt(m_i) (d_i - c)` factored together with the running factor and the parallel-axis
    /// row by modified Gram-Schmidt (see `gram_schmidt_chunk`); a chunk with a bad point or
    /// numbers near the ends of the safe range is redone by Householder QR of the rows
    /// `[sqrt(m_i), sqrt(m_i) d_i]` with scaled columns (the mass column first: the lower-right
    /// 3x3 block of the factor is that of the Schur complement `S2 - S1 S1^T / M`). Nothing is
    /// summed about a far origin, and nothing is squared before it is centred, so the cloud can
    /// be 1e8 away from the origin or nearly collinear. Masses or offsets near the ends of the
    /// range of double precision take a second pass, scaled by powers of two.
    ///
    /// ```
    /// use nalgebra::Vector3;
    /// use polhode::MassProperties;
    /// // Carbon monoxide: 12 u and 16 u, 112.8 pm apart: I = mu d^2 about the centre of mass.
    /// let co = MassProperties::point_masses(
    ///     &[12.0, 16.0],
    ///     &[Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 112.8)],
    /// ).unwrap();
    /// let mu = 12.0 * 16.0 / 28.0;
    /// let p = co.principal();
    /// assert_eq!(p.moments[0], 0.0);
    /// assert!((p.moments[2] - mu * 112.8 * 112.8).abs() < 1e-10 * p.moments[2]);
    /// ```
    ///
    /// `positions` may be `Vector3<f64>` or plain `[f64; 3]` rows (a numpy buffer, uncopied).
    ///
    /// The result is bit for bit the same for any number of threads: every sum is over fixed
    /// chunks of points, and the chunks' results are combined in order on one thread.
    pub fn point_masses<P>(masses: &[f64], positions: &[P]) -> Result<Self>
    where
        P: Copy + Sync + Into<Vector3<f64>>,
    {
        Self::point_masses_monitored(masses, positions, None)
    }

    /// [`point_masses`](Self::point_masses) watched by `monitor`: a look
    /// ([`Monitor::look`]) before each chunk of [`POINT_CHUNK`] points, so that a cancelled
    /// monitor stops the work within a chunk, with [`Error::Interrupted`].
    pub fn point_masses_monitored<P>(
        masses: &[f64],
        positions: &[P],
        monitor: Option<&Monitor>,
    ) -> Result<Self>
    where
        P: Copy + Sync + Into<Vector3<f64>>,
    {
        if masses.len() != positions.len() {
            return Err(Error::Shape {
                name: "positions".into(),
                expected: format!("({}, 3) to match `masses`", masses.len()),
                got: format!("({}, 3)", positions.len()),
            });
        }
        if masses.is_empty() {
            return Err(Error::Shape {
                name: "masses".into(),
                expected: "(N,) with N >= 1".into(),
                got: "(0,)".into(),
            });
        }
        let look = || monitor.map_or(Ok(()), Monitor::look);
        let reference = block_center(masses, positions);
        // One pass, per chunk: the first bad point, the sums about the reference, the largest
        // mass and offset, and the factor of the rows [sqrt(m), sqrt(m) (r - r0)].
        let chunks: Vec<Result<(Scan, [[f64; 4]; 4])>> = memory::collect_parallel(
            masses
                .par_chunks(CHUNK)
                .zip(positions.par_chunks(CHUNK))
                .enumerate()
                .map(|(chunk, (m, r))| {
                    look()?;
                    crate::simd::dispatch(
                        #[inline(always)]
                        || match gram_schmidt_chunk(m, r, &reference) {
                            Some(done) => Ok(done),
                            // A bad point, or numbers near the ends of the range: the chunk again
                            // by scaled Householder QR (which also names the first bad point).
                            None => one_pass_chunk(m, r, &reference, chunk * CHUNK),
                        },
                    )
                }),
            Purpose::PointMasses,
        )?;
        let mut total = Scan::default();
        let mut qr = Qr4::new();
        for chunk in chunks {
            let (scan, r) = chunk?;
            total.mass += scan.mass;
            total.first += scan.first;
            total.heaviest = total.heaviest.max(scan.heaviest);
            total.farthest = total.farthest.max(scan.farthest);
            for row in r {
                qr.push(row);
            }
        }
        let calm = |x: f64, limit: f64| x == 0.0 || (1.0 / limit..=limit).contains(&x);
        if calm(total.heaviest, 2f64.powi(400)) && calm(total.farthest, 2f64.powi(200)) {
            // Far inside the range (the common case): nothing to scale, and this pass was all.
            let r = qr.finish();
            let factor = Matrix3::from_fn(|i, j| r[1 + i][1 + j]);
            let offset = total.first / total.mass;
            let (center_of_mass, center_of_mass_low) = super::renormalised(reference, offset);
            return Self {
                mass: total.mass,
                center_of_mass,
                center_of_mass_low,
                second_moment: SecondMoment {
                    isotropic: 0.0,
                    factor,
                },
            }
            .in_range(&[
                ("masses", total.heaviest.log2()),
                ("positions", 2.0 * total.farthest.log2()),
            ]);
        }
        Self::point_masses_scaled(masses, positions, monitor)
    }

    /// [`point_masses_monitored`](Self::point_masses_monitored) for masses or offsets near the
    /// ends of the range of double precision: two passes over the data (the scales, then the
    /// factor of the centred rows in units of powers of two).
    fn point_masses_scaled<P>(
        masses: &[f64],
        positions: &[P],
        monitor: Option<&Monitor>,
    ) -> Result<Self>
    where
        P: Copy + Sync + Into<Vector3<f64>>,
    {
        let look = || monitor.map_or(Ok(()), Monitor::look);
        // The reference: the heaviest point (the first of equal ones). The centre comes out
        // as the reference plus the weighted mean of the rounded offsets, so a point's row
        // carries the rounding of its offset, eps |r_i - reference|, times sqrt(m_i): about the
        // first point, a mass of 1e130 beside one of 1 made I 7.7e96 instead of 0.81.
        let reference: Vector3<f64> = positions[heaviest(masses).min(positions.len() - 1)].into();
        let total = scan(masses, positions, &reference, &look)?;
        let (heaviest, farthest) = (total.heaviest, total.farthest);
        if !farthest.is_finite() {
            // Offsets beyond the range of double precision: the moments overflow.
            return Err(Self::points_overflow(heaviest, farthest));
        }
        // Masses in units of 2^a (a even, so that sqrt(m) is in units of 2^(a/2)), offsets in
        // units of 2^b. Far inside the range (the common case) a = b = 0 and pass 1's sums are
        // the answer; otherwise pass 2 redoes them scaled, so that every sum is of numbers of
        // size <= 1. In the normal range the scaled arithmetic is the unscaled one times powers
        // of two (exact), so either way the result is the same.
        let calm = |x: f64, limit: f64| x == 0.0 || (1.0 / limit..=limit).contains(&x);
        let (a, b) = if calm(heaviest, 2f64.powi(400)) && calm(farthest, 2f64.powi(200)) {
            (0, 0)
        } else {
            (
                2 * (exponent(heaviest) + 1).div_euclid(2),
                exponent(farthest),
            )
        };
        let (mass, first_moment) = if (a, b) == (0, 0) {
            (total.mass, total.first)
        } else {
            scaled_sums(masses, positions, &reference, (a, b), &look)?
        };
        let offset = (first_moment / mass).map(|x| ldexp(x, b));
        let mass = ldexp(mass, a);
        if !mass.is_finite() {
            return Err(Error::InvalidArgument {
                name: "masses".into(),
                reason: format!(
                    "their sum overflows double precision (beyond the largest double, {:e}).",
                    f64::MAX
                ),
            });
        }
        // The centre as a double-double, so that the rows below are centred exactly.
        let (center_of_mass, center_of_mass_low) = super::renormalised(reference, offset);
        let (scaled_center, scaled_low) = (
            center_of_mass.map(|x| ldexp(x, -b)),
            center_of_mass_low.map(|x| ldexp(x, -b)),
        );
        // Pass 3, per chunk: the factor of the centred rows sqrt(m_i) (r_i - r_cm), in units of
        // 2^(a/2 + b); the chunks' factors are then folded in order.
        let centre = (&scaled_center, &scaled_low);
        let acc = centred_factor(masses, positions, centre, (a, b), &look)?;
        let factor = acc.finish().map(|x| ldexp(x, a / 2 + b));
        Self {
            mass,
            center_of_mass,
            center_of_mass_low,
            second_moment: SecondMoment {
                isotropic: 0.0,
                factor,
            },
        }
        .in_range(&[
            ("masses", heaviest.log2()),
            ("positions", 2.0 * farthest.log2()),
        ])
    }

    /// The error for point masses whose offsets overflow.
    fn points_overflow(heaviest: f64, farthest: f64) -> Error {
        super::out_of_range(
            super::OutOfRange::Overflow,
            format!(
                "the positions span more than the range of double precision ({:e}), and the \
                 moments of inertia overflow it.",
                f64::MAX
            ),
            &[
                ("masses", heaviest.log2()),
                ("positions", 2.0 * farthest.log2()),
            ],
        )
    }
}

/// The reference point `r0` of the one-pass path: the centre of mass of the first block of
/// points (found relative to the first point), so that the offsets `r - r0` are of the size
/// of the cloud, not of a first point far out (the QR's error is eps of the offsets); the first
/// point itself if that block has a bad value (reported by the pass) or overflows.
fn block_center<P>(masses: &[f64], positions: &[P]) -> Vector3<f64>
where
    P: Copy + Into<Vector3<f64>>,
{
    let first: Vector3<f64> = positions[0].into();
    let (mut mass, mut moment) = (0.0, Vector3::zeros());
    for (&mi, &ri) in masses.iter().zip(positions).take(QR_BLOCK) {
        let ri: Vector3<f64> = ri.into();
        mass += mi;
        moment += (ri - first) * mi;
    }
    let center = first + moment / mass;
    if mass > 0.0 && center.iter().all(|x| x.is_finite()) {
        center
    } else {
        first
    }
}

/// Rows per block of the one-pass QR ([`Qr4`]): large enough to amortise a fold, small
/// enough for L1.
const QR_BLOCK: usize = 256;

/// Partial sums per reduction of the one-pass QR: element `i` of a sum goes to lane `i mod 8`
/// (the rest of the division to lane 0) and the lanes are added in order, so the result
/// depends on nothing but the input (and the order vectorises).
const SUM_LANES: usize = 8;

/// Accumulates rows `[sqrt(m), sqrt(m) (r - r0)]` into an upper-triangular 4x4 `R` with
/// `R^T R = sum row row^T`, by Householder QR of `[R; rows]` block by block (as
/// [`RowAccumulator`], with one more column). The mass column comes first, so the lower-right
/// 3x3 block of `R` factors the Schur complement `S2 - S1 S1^T / M`: the second moments about
/// the centre of mass, centred inside the QR (backward stable) rather than by subtracting squares.
struct Qr4 {
    /// Column-major: `cols[col][row]`, the first four rows hold `R`.
    cols: [[f64; 4 + QR_BLOCK]; 4],
    len: usize,
}

impl Qr4 {
    #[inline(always)]
    fn new() -> Self {
        Self {
            cols: [[0.0; 4 + QR_BLOCK]; 4],
            len: 4,
        }
    }

    /// Adds one row; folds when the block is full.
    #[inline(always)]
    fn push(&mut self, row: [f64; 4]) {
        if self.len == 4 + QR_BLOCK {
            self.fold();
        }
        for (col, x) in self.cols.iter_mut().zip(row) {
            col[self.len] = x;
        }
        self.len += 1;
    }

    /// Householder QR of the block in place; leaves `R` in the first four rows.
    #[inline(always)]
    fn fold(&mut self) {
        let n = self.len;
        if n <= 4 {
            return;
        }
        for j in 0..4 {
            let (done, rest) = self.cols.split_at_mut(j + 1);
            reflect(&mut done[j][..n], rest, n, j);
        }
        self.len = 4;
    }

    /// The upper-triangular `R`, row by row.
    #[inline(always)]
    fn finish(mut self) -> [[f64; 4]; 4] {
        self.fold();
        std::array::from_fn(|r| std::array::from_fn(|c| if r <= c { self.cols[c][r] } else { 0.0 }))
    }
}

/// `sum x_i y_i` in [`SUM_LANES`] partial sums.
#[inline(always)]
fn lane_dot(x: &[f64], y: &[f64]) -> f64 {
    let (xs, x_rest) = x.as_chunks::<SUM_LANES>();
    let (ys, y_rest) = y[..x.len()].as_chunks::<SUM_LANES>();
    let mut sums = [0.0f64; SUM_LANES];
    for (a, b) in xs.iter().zip(ys) {
        for l in 0..SUM_LANES {
            sums[l] += a[l] * b[l];
        }
    }
    for (a, b) in x_rest.iter().zip(y_rest) {
        sums[0] += a * b;
    }
    sums.iter().sum()
}

/// One Householder reflection zeroing `col[j+1..n]` below the diagonal entry `col[j]`, applied
/// to the columns `rest` (the columns after `j`). The column is first scaled by a power of two
/// (exactly) so that the squares neither overflow nor underflow.
#[inline(always)]
fn reflect(col: &mut [f64], rest: &mut [[f64; 4 + QR_BLOCK]], n: usize, j: usize) {
    let x = &mut col[j..n];
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return;
    }
    let k = exponent(scale);
    for v in x.iter_mut() {
        *v = ldexp(*v, -k);
    }
    let tail = lane_dot(&x[1..], &x[1..]);
    let head = x[0];
    if tail == 0.0 {
        x[0] = ldexp(head, k);
        return;
    }
    let norm = (head * head + tail).sqrt();
    let alpha = if head > 0.0 { -norm } else { norm };
    // v = x 2^-k - alpha e1 (stored in x); H = 1 - 2 v v^T / (v^T v).
    x[0] = head - alpha;
    let vtv = x[0] * x[0] + tail;
    for other in rest.iter_mut() {
        let y = &mut other[j..n];
        let f = 2.0 * lane_dot(x, y) / vtv;
        for (xi, yi) in x.iter().zip(y.iter_mut()) {
            *yi -= f * xi;
        }
    }
    x[0] = ldexp(alpha, k);
    let header = (4 - j).min(x.len());
    for xi in &mut x[1..header] {
        *xi = 0.0;
    }
}

/// One chunk of the one-pass path: its sums about `reference` and its 4x4 factor, or the
/// error for its first bad point (index `offset + j`).
#[inline(always)]
fn one_pass_chunk<P>(
    masses: &[f64],
    positions: &[P],
    reference: &Vector3<f64>,
    offset: usize,
) -> Result<(Scan, [[f64; 4]; 4])>
where
    P: Copy + Into<Vector3<f64>>,
{
    let mut qr = Qr4::new();
    let mut mass = [0.0f64; SUM_LANES];
    let mut first = [[0.0f64; SUM_LANES]; 3];
    let mut heaviest = [0.0f64; SUM_LANES];
    let mut farthest = [0.0f64; SUM_LANES];
    for (b, (mb, rb)) in masses
        .chunks(QR_BLOCK)
        .zip(positions.chunks(QR_BLOCK))
        .enumerate()
    {
        let n = mb.len();
        // The block's rows straight into the QR's columns (after the four rows of R), eight
        // at a time: lane l of every sum takes the rows l mod 8.
        let mut bad = [false; SUM_LANES];
        let (m8, m_rest) = mb.as_chunks::<SUM_LANES>();
        let (r8, r_rest) = rb.as_chunks::<SUM_LANES>();
        for (g, (m8, r8)) in m8.iter().zip(r8).enumerate() {
            let at = 4 + g * SUM_LANES;
            let p: [Vector3<f64>; SUM_LANES] = std::array::from_fn(|l| r8[l].into());
            let w: [f64; SUM_LANES] = std::array::from_fn(|l| m8[l].sqrt());
            for k in 0..3 {
                let d: [f64; SUM_LANES] = std::array::from_fn(|l| p[l][k] - reference[k]);
                let col: &mut [f64; SUM_LANES] = (&mut qr.cols[1 + k][at..at + SUM_LANES])
                    .try_into()
                    .unwrap_or_else(|_| unreachable!());
                for l in 0..SUM_LANES {
                    col[l] = w[l] * d[l];
                    first[k][l] += d[l] * m8[l];
                    farthest[l] = farthest[l].max(d[l].abs());
                    bad[l] |= !p[l][k].is_finite();
                }
            }
            qr.cols[0][at..at + SUM_LANES].copy_from_slice(&w);
            for l in 0..SUM_LANES {
                mass[l] += m8[l];
                heaviest[l] = heaviest[l].max(m8[l]);
                bad[l] |= !(m8[l].is_finite() & (m8[l] > 0.0));
            }
        }
        for (i, (&mi, &ri)) in m_rest.iter().zip(r_rest).enumerate() {
            let ri: Vector3<f64> = ri.into();
            let row = 4 + m8.len() * SUM_LANES + i;
            let w = mi.sqrt();
            qr.cols[0][row] = w;
            for k in 0..3 {
                let d = ri[k] - reference[k];
                qr.cols[1 + k][row] = w * d;
                first[k][i] += d * mi;
                farthest[i] = farthest[i].max(d.abs());
                bad[i] |= !ri[k].is_finite();
            }
            mass[i] += mi;
            heaviest[i] = heaviest[i].max(mi);
            bad[i] |= !(mi.is_finite() & (mi > 0.0));
        }
        let block_good = !bad.iter().any(|&b| b);
        if !block_good {
            for (i, (&mi, &ri)) in mb.iter().zip(rb).enumerate() {
                let ri: Vector3<f64> = ri.into();
                if !(mi.is_finite() && mi > 0.0 && ri.iter().all(|x| x.is_finite())) {
                    return Err(bad_point(offset + b * QR_BLOCK + i, mi, &ri));
                }
            }
        }
        qr.len = 4 + n;
        qr.fold();
    }
    let scan = Scan {
        mass: mass.iter().sum(),
        first: Vector3::new(
            first[0].iter().sum(),
            first[1].iter().sum(),
            first[2].iter().sum(),
        ),
        heaviest: heaviest.iter().fold(0.0, |a: f64, &b| a.max(b)),
        farthest: farthest.iter().fold(0.0, |a: f64, &b| a.max(b)),
    };
    Ok((scan, qr.finish()))
}

/// The weighted squares `m a^2` of the largest entry of a pivot column in
/// [`gram_schmidt_chunk`] must lie in `2^-SAFE..=2^SAFE` (or the column be zero) for unscaled
/// arithmetic: the large entries' squares are then normal doubles (>= 2^-900), so what
/// underflows is below eps of them, and no sum of a block overflows (<= 2^909).
const SAFE: i32 = 900;

/// `a` if `a > b`, else `b` (one vector instruction; NaN is caught elsewhere).
#[inline(always)]
fn fast_max(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// `a` if `a < b`, else `b`.
#[inline(always)]
fn fast_min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// Whether a pivot column of [`gram_schmidt_chunk`] with weighted squares summing to `sum`,
/// the largest `top`, is safe to use unscaled (see [`SAFE`]). A finite sum means that no term
/// was NaN or infinite (so `top` is the largest term, and no earlier product overflowed); a
/// top of 0 is safe only if the column is zero (its squares may have underflowed).
#[inline(always)]
fn pivot_safe(sum: f64, top: f64, column: &[f64]) -> bool {
    if !sum.is_finite() {
        return false;
    }
    if (ldexp(1.0, -SAFE)..=ldexp(1.0, SAFE)).contains(&top) {
        return true;
    }
    top == 0.0 && column.iter().all(|&x| x == 0.0)
}

/// The largest of `lanes`.
#[inline(always)]
fn lanes_max(lanes: &[f64]) -> f64 {
    lanes.iter().fold(0.0, |a, &b| fast_max(a, b))
}

/// The first `n` rows of the three coordinate columns and of the weights of
/// [`gram_schmidt_chunk`], each split into blocks of `L` lanes and the rest.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn in_blocks<'a, const L: usize>(
    cols: &'a [[f64; QR_BLOCK + 4]; 3],
    weight: &'a [f64; QR_BLOCK + 4],
    n: usize,
) -> ([&'a [[f64; L]]; 4], [&'a [f64]; 4]) {
    let (x8, x_rest) = cols[0][..n].as_chunks::<L>();
    let (y8, y_rest) = cols[1][..n].as_chunks::<L>();
    let (z8, z_rest) = cols[2][..n].as_chunks::<L>();
    let (m8, m_rest) = weight[..n].as_chunks::<L>();
    ([x8, y8, z8, m8], [x_rest, y_rest, z_rest, m_rest])
}

/// The fast path of one chunk: the same sums and 4x4 factor as [`one_pass_chunk`] (`R^T R` =
/// the sum of `row row^T` over the rows `[sqrt(m), sqrt(m) (r - r0)]`), or None when the
/// chunk has a bad point or numbers for which unscaled arithmetic is not safe (see [`SAFE`]);
/// the caller then runs [`one_pass_chunk`].
///
/// Block by block of [`QR_BLOCK`] points, the state is the mass `M`, the centre `c` (relative
/// to `reference`) and the upper-triangular factor `R` of the second moments about `c`. A block
/// is read once (its offsets and masses into columns, while it is in L1; its mass and first
/// moments); the new centre `c'` follows, and the offsets `d - c'` of its points (weight `m`),
/// the rows of `R` (weight 1) and the row `c - c'` (weight `M`: the parallel-axis term,
/// exactly) are factored by modified Gram-Schmidt with the weighted inner product
/// `sum m x y`, column by column over the block in L1 (centre; the first column's products;
/// project it out of the others, the second's products; project that out of the third, its
/// norm). Each loop either updates one column or only sums, in [`SUM_LANES`] fixed lanes, which
/// is the shape the compiler vectorises (fused loops that update and sum several columns at
/// once came out partly scalar, 20-30% slower). Gram-Schmidt's `R` is backward stable like
/// Householder's (Bjorck and Paige 1992: it is Householder QR of the rows under a zero block),
/// here of the rows `sqrt(m) (d - c')`, so the factor is accurate to eps of the centred rows
/// (columnwise): nothing is squared before it is centred. No square root per point: the
/// weights enter the products.
#[inline(always)]
fn gram_schmidt_chunk<P>(
    masses: &[f64],
    positions: &[P],
    reference: &Vector3<f64>,
) -> Option<(Scan, [[f64; 4]; 4])>
where
    P: Copy + Into<Vector3<f64>>,
{
    // Rows 0..n: the block's points; n..n + 3: the rows of R; n + 3: the parallel-axis row.
    let mut cols = [[0.0f64; QR_BLOCK + 4]; 3];
    let mut weight = [0.0f64; QR_BLOCK + 4];
    let mut r = [[0.0f64; 3]; 3];
    let (mut big_m, mut c) = (0.0f64, [0.0f64; 3]);
    let mut scan = Scan::default();
    for (mb, rb) in masses.chunks(QR_BLOCK).zip(positions.chunks(QR_BLOCK)) {
        let n = mb.len();
        let rows = n + 4;
        // The block's offsets from the reference into the columns, its masses as weights.
        for (i, &ri) in rb.iter().enumerate() {
            let ri: Vector3<f64> = ri.into();
            for k in 0..3 {
                cols[k][i] = ri[k] - reference[k];
            }
        }
        weight[..n].copy_from_slice(mb);
        // Its mass and first moments, largest and smallest mass, largest offset.
        let (s0, s1, heaviest, lightest, farthest) = block_sums(&cols, &weight, n);
        let block_mass: f64 = s0.iter().sum();
        let block_first: [f64; 3] = std::array::from_fn(|k| s1[k].iter().sum());
        // Every mass finite and positive and every offset finite (a NaN or an infinity reaches
        // the sums), and nothing overflowed: else the careful path.
        let lightest = lightest.iter().fold(f64::INFINITY, |a, &b| fast_min(a, b));
        if !(lightest > 0.0 && block_mass.is_finite() && block_first.iter().all(|x| x.is_finite()))
        {
            return None;
        }
        scan.mass += block_mass;
        scan.first += Vector3::from(block_first);
        scan.heaviest = fast_max(scan.heaviest, lanes_max(&heaviest));
        scan.farthest = fast_max(scan.farthest, lanes_max(&farthest));
        // The new centre, and the rows after the block's: R (weight 1), then c - c' (weight M).
        let total = big_m + block_mass;
        let centre: [f64; 3] = std::array::from_fn(|k| (big_m * c[k] + block_first[k]) / total);
        for k in 0..3 {
            for (i, row) in r.iter().enumerate() {
                cols[k][n + i] = row[k];
            }
            // (0 for the first block, of weight 0, so that a zero column stays zero)
            cols[k][n + 3] = if big_m > 0.0 { c[k] - centre[k] } else { 0.0 };
        }
        weight[n..rows].copy_from_slice(&[1.0, 1.0, 1.0, big_m]);
        big_m = total;
        c = centre;
        // Centre the block's points; the first column's products.
        for k in 0..3 {
            for x in &mut cols[k][..n] {
                *x -= centre[k];
            }
        }
        let (g0, top) = first_products(&cols, &weight, rows);
        let g0: [f64; 3] = std::array::from_fn(|k| g0[k].iter().sum());
        if !pivot_safe(g0[0], lanes_max(&top), &cols[0][..rows]) {
            return None;
        }
        let (r0, f1, f2) = if g0[0] > 0.0 {
            let r00 = g0[0].sqrt();
            (
                [r00, g0[1] / r00, g0[2] / r00],
                g0[1] / g0[0],
                g0[2] / g0[0],
            )
        } else {
            ([0.0; 3], 0.0, 0.0)
        };
        // Project the first column out of the others; the second column's products.
        {
            let [c0, c1, c2] = &mut cols;
            for (y, x) in c1[..rows].iter_mut().zip(&c0[..rows]) {
                *y -= f1 * x;
            }
            for (z, x) in c2[..rows].iter_mut().zip(&c0[..rows]) {
                *z -= f2 * x;
            }
        }
        let (g1, top) = second_products(&cols, &weight, rows);
        let g1: [f64; 2] = std::array::from_fn(|k| g1[k].iter().sum());
        if !pivot_safe(g1[0], lanes_max(&top), &cols[1][..rows]) {
            return None;
        }
        let (r1, f) = if g1[0] > 0.0 {
            let r11 = g1[0].sqrt();
            ([r11, g1[1] / r11], g1[1] / g1[0])
        } else {
            ([0.0; 2], 0.0)
        };
        // Project the second column out of the third; its norm.
        let (g2, top) = third_norm(&mut cols, &weight, rows, f);
        let g2: f64 = g2.iter().sum();
        if !pivot_safe(g2, lanes_max(&top), &cols[2][..rows]) {
            return None;
        }
        let r22 = g2.sqrt();
        r = [r0, [0.0, r1[0], r1[1]], [0.0, 0.0, r22]];
    }
    let root_m = big_m.sqrt();
    let factor = [
        [root_m, root_m * c[0], root_m * c[1], root_m * c[2]],
        [0.0, r[0][0], r[0][1], r[0][2]],
        [0.0, 0.0, r[1][1], r[1][2]],
        [0.0, 0.0, 0.0, r[2][2]],
    ];
    Some((scan, factor))
}

/// The index of the heaviest point (the first of equal ones; a mass that is not finite is
/// lightest): the reference the offsets are taken from.
fn heaviest(masses: &[f64]) -> usize {
    let weight = |m: f64| if m.is_finite() { m } else { f64::NEG_INFINITY };
    masses
        .par_iter()
        .enumerate()
        .map(|(i, &m)| (weight(m), i))
        .reduce(
            || (f64::NEG_INFINITY, usize::MAX),
            |x, y| {
                if y.0 > x.0 || (y.0 == x.0 && y.1 < x.1) {
                    y
                } else {
                    x
                }
            },
        )
        .1
}

/// Pass 1 of the point masses, per chunk: the first bad value; the mass and first moment
/// about `reference`, unscaled; the largest mass and offset (the scales if a second pass is
/// needed); the chunks' added in order.
fn scan<P>(
    masses: &[f64],
    positions: &[P],
    reference: &Vector3<f64>,
    look: &(dyn Fn() -> Result<()> + Sync),
) -> Result<Scan>
where
    P: Copy + Sync + Into<Vector3<f64>>,
{
    let scans: Vec<Result<Scan>> = memory::collect_parallel(
        masses
            .par_chunks(CHUNK)
            .zip(positions.par_chunks(CHUNK))
            .enumerate()
            .map(|(chunk, (m, r))| {
                look()?;
                let mut scan = Scan::default();
                for (j, (&mi, &ri)) in m.iter().zip(r).enumerate() {
                    let ri: Vector3<f64> = ri.into();
                    if !(mi.is_finite()
                        && mi > 0.0
                        && ri[0].is_finite()
                        && ri[1].is_finite()
                        && ri[2].is_finite())
                    {
                        return Err(bad_point(chunk * CHUNK + j, mi, &ri));
                    }
                    let d = ri - reference;
                    scan.mass += mi;
                    scan.first += d * mi;
                    scan.heaviest = scan.heaviest.max(mi);
                    scan.farthest = scan.farthest.max(d.amax());
                }
                Ok(scan)
            }),
        Purpose::PointMasses,
    )?;
    let mut total = Scan::default();
    for scan in scans {
        let scan = scan?;
        total.mass += scan.mass;
        total.first += scan.first;
        total.heaviest = total.heaviest.max(scan.heaviest);
        total.farthest = total.farthest.max(scan.farthest);
    }
    Ok(total)
}

/// Pass 2 of the point masses, per chunk: the mass and first moment about `reference` with the
/// masses in units of `2^a` and the offsets in units of `2^b`, the chunks' added in order.
fn scaled_sums<P>(
    masses: &[f64],
    positions: &[P],
    reference: &Vector3<f64>,
    (a, b): (i32, i32),
    look: &(dyn Fn() -> Result<()> + Sync),
) -> Result<(f64, Vector3<f64>)>
where
    P: Copy + Sync + Into<Vector3<f64>>,
{
    // Pass 2, per chunk: the same sums, scaled, added in order.
    let sums: Vec<Result<(f64, Vector3<f64>)>> = memory::collect_parallel(
        masses
            .par_chunks(CHUNK)
            .zip(positions.par_chunks(CHUNK))
            .map(|(m, r)| {
                look()?;
                Ok(m.iter()
                    .zip(r)
                    .fold((0.0, Vector3::zeros()), |(sm, sr), (&mi, ri)| {
                        let mi = ldexp(mi, -a);
                        let di = ((*ri).into() - reference).map(|x| ldexp(x, -b));
                        (sm + mi, sr + di * mi)
                    }))
            }),
        Purpose::PointMasses,
    )?;
    let (mut mass, mut first_moment) = (0.0, Vector3::zeros());
    for sum in sums {
        let (m, r) = sum?;
        mass += m;
        first_moment += r;
    }
    Ok((mass, first_moment))
}

/// Pass 3 of the point masses, per chunk: the factor of the centred rows
/// `sqrt(m_i) (r_i - r_cm)` in units of `2^(a/2 + b)` (`r_cm` in units of `2^b`, as a
/// double-double), the chunks' factors folded in order.
fn centred_factor<P>(
    masses: &[f64],
    positions: &[P],
    (scaled_center, scaled_low): (&Vector3<f64>, &Vector3<f64>),
    (a, b): (i32, i32),
    look: &(dyn Fn() -> Result<()> + Sync),
) -> Result<RowAccumulator>
where
    P: Copy + Sync + Into<Vector3<f64>>,
{
    let factors: Vec<Result<Matrix3<f64>>> = memory::collect_parallel(
        masses
            .par_chunks(CHUNK)
            .zip(positions.par_chunks(CHUNK))
            .map(|(m, r)| {
                look()?;
                let mut acc = RowAccumulator::new();
                if (a, b) == (0, 0) {
                    for (&mi, ri) in m.iter().zip(r) {
                        let ri: Vector3<f64> = (*ri).into();
                        let d = ((ri - scaled_center) - scaled_low) * mi.sqrt();
                        acc.push([d[0], d[1], d[2]]);
                    }
                } else {
                    for (&mi, ri) in m.iter().zip(r) {
                        let ri: Vector3<f64> = (*ri).into();
                        let d = (ri.map(|x| ldexp(x, -b)) - scaled_center) - scaled_low;
                        let d = d * ldexp(mi, -a).sqrt();
                        acc.push([d[0], d[1], d[2]]);
                    }
                }
                Ok(acc.finish())
            }),
        Purpose::PointMasses,
    )?;
    let mut acc = RowAccumulator::new();
    for factor in factors {
        acc.push_matrix(&factor?);
    }
    Ok(acc)
}

/// The lanes of [`gram_schmidt_chunk`]'s sums.
type Lanes = [f64; SUM_LANES];

/// A block's mass and first moments, largest and smallest mass, largest offset, in
/// [`SUM_LANES`] lanes (of the first `n` rows of `cols` and `weight`).
#[inline(always)]
#[allow(clippy::type_complexity)]
fn block_sums(
    cols: &[[f64; QR_BLOCK + 4]; 3],
    weight: &[f64; QR_BLOCK + 4],
    n: usize,
) -> (Lanes, [Lanes; 3], Lanes, Lanes, Lanes) {
    const L: usize = SUM_LANES;
    let mut s0 = [0.0f64; L];
    let mut s1 = [[0.0f64; L]; 3];
    let mut heaviest = [0.0f64; L];
    let mut lightest = [f64::INFINITY; L];
    let mut farthest = [0.0f64; L];
    {
        let ([x8, y8, z8, m8], [x_rest, y_rest, z_rest, m_rest]) = in_blocks::<L>(cols, weight, n);
        for (((x, y), z), m) in x8.iter().zip(y8).zip(z8).zip(m8) {
            for l in 0..L {
                s0[l] += m[l];
                s1[0][l] += m[l] * x[l];
                s1[1][l] += m[l] * y[l];
                s1[2][l] += m[l] * z[l];
                heaviest[l] = fast_max(heaviest[l], m[l]);
                lightest[l] = fast_min(lightest[l], m[l]);
                let far = fast_max(fast_max(x[l].abs(), y[l].abs()), z[l].abs());
                farthest[l] = fast_max(farthest[l], far);
            }
        }
        for (l, (((x, y), z), m)) in x_rest
            .iter()
            .zip(y_rest)
            .zip(z_rest)
            .zip(m_rest)
            .enumerate()
        {
            s0[l] += m;
            s1[0][l] += m * x;
            s1[1][l] += m * y;
            s1[2][l] += m * z;
            heaviest[l] = fast_max(heaviest[l], *m);
            lightest[l] = fast_min(lightest[l], *m);
            let far = fast_max(fast_max(x.abs(), y.abs()), z.abs());
            farthest[l] = fast_max(farthest[l], far);
        }
    }
    (s0, s1, heaviest, lightest, farthest)
}

/// The first column's weighted products with each column, and the largest of its terms, in
/// lanes (of the first `rows` rows).
#[inline(always)]
fn first_products(
    cols: &[[f64; QR_BLOCK + 4]; 3],
    weight: &[f64; QR_BLOCK + 4],
    rows: usize,
) -> ([Lanes; 3], Lanes) {
    const L: usize = SUM_LANES;
    let mut g0 = [[0.0f64; L]; 3];
    let mut top = [0.0f64; L];
    {
        let ([x8, y8, z8, m8], [x_rest, y_rest, z_rest, m_rest]) =
            in_blocks::<L>(cols, weight, rows);
        for (((x, y), z), m) in x8.iter().zip(y8).zip(z8).zip(m8) {
            let ma: [f64; L] = std::array::from_fn(|l| m[l] * x[l]);
            for l in 0..L {
                let t = ma[l] * x[l];
                g0[0][l] += t;
                top[l] = fast_max(top[l], t);
            }
            for l in 0..L {
                g0[1][l] += ma[l] * y[l];
            }
            for l in 0..L {
                g0[2][l] += ma[l] * z[l];
            }
        }
        for (l, (((x, y), z), m)) in x_rest
            .iter()
            .zip(y_rest)
            .zip(z_rest)
            .zip(m_rest)
            .enumerate()
        {
            let ma = m * x;
            let t = ma * x;
            g0[0][l] += t;
            g0[1][l] += ma * y;
            g0[2][l] += ma * z;
            top[l] = fast_max(top[l], t);
        }
    }
    (g0, top)
}

/// The second column's weighted products with the second and third, and the largest of its
/// terms, in lanes.
#[inline(always)]
fn second_products(
    cols: &[[f64; QR_BLOCK + 4]; 3],
    weight: &[f64; QR_BLOCK + 4],
    rows: usize,
) -> ([Lanes; 2], Lanes) {
    const L: usize = SUM_LANES;
    let mut g1 = [[0.0f64; L]; 2];
    let mut top = [0.0f64; L];
    {
        let [_, c1, c2] = &cols;
        let (y8, y_rest) = c1[..rows].as_chunks::<L>();
        let (z8, z_rest) = c2[..rows].as_chunks::<L>();
        let (m8, m_rest) = weight[..rows].as_chunks::<L>();
        for ((y, z), m) in y8.iter().zip(z8).zip(m8) {
            let mb: [f64; L] = std::array::from_fn(|l| m[l] * y[l]);
            for l in 0..L {
                let t = mb[l] * y[l];
                g1[0][l] += t;
                top[l] = fast_max(top[l], t);
            }
            for l in 0..L {
                g1[1][l] += mb[l] * z[l];
            }
        }
        for (l, ((y, z), m)) in y_rest.iter().zip(z_rest).zip(m_rest).enumerate() {
            let mb = m * y;
            let t = mb * y;
            g1[0][l] += t;
            g1[1][l] += mb * z;
            top[l] = fast_max(top[l], t);
        }
    }
    (g1, top)
}

/// Projects the second column (times `f`) out of the third; its weighted norm and largest
/// term, in lanes.
#[inline(always)]
fn third_norm(
    cols: &mut [[f64; QR_BLOCK + 4]; 3],
    weight: &[f64; QR_BLOCK + 4],
    rows: usize,
    f: f64,
) -> (Lanes, Lanes) {
    const L: usize = SUM_LANES;
    let mut g2 = [0.0f64; L];
    let mut top = [0.0f64; L];
    {
        let [_, c1, c2] = cols;
        let (y8, y_rest) = c1[..rows].as_chunks::<L>();
        let (z8, z_rest) = c2[..rows].as_chunks_mut::<L>();
        let (m8, m_rest) = weight[..rows].as_chunks::<L>();
        for ((y, z), m) in y8.iter().zip(z8).zip(m8) {
            for l in 0..L {
                let e = z[l] - f * y[l];
                z[l] = e;
                let t = m[l] * e * e;
                g2[l] += t;
                top[l] = fast_max(top[l], t);
            }
        }
        for (l, ((y, z), m)) in y_rest.iter().zip(z_rest).zip(m_rest).enumerate() {
            let e = *z - f * y;
            *z = e;
            let t = m * e * e;
            g2[l] += t;
            top[l] = fast_max(top[l], t);
        }
    }
    (g2, top)
}

/// One chunk's sums about the first point, unscaled, and its largest mass and offset.
#[derive(Default)]
struct Scan {
    mass: f64,
    first: Vector3<f64>,
    heaviest: f64,
    farthest: f64,
}

/// The error for point `i` (a mass that is not finite and positive, or a position that is not
/// finite), naming the first bad number.
fn bad_point(i: usize, mass: f64, position: &Vector3<f64>) -> Error {
    if let Err(error) = finite(&format!("masses[{i}]"), mass) {
        return error;
    }
    if mass <= 0.0 {
        return Error::NonPositive {
            name: format!("masses[{i}]"),
            value: mass,
        };
    }
    for k in 0..3 {
        if let Err(error) = finite(&format!("positions[{i}, {k}]"), position[k]) {
            return error;
        }
    }
    unreachable!("a bad point has a bad number")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Error;

    /// A deterministic generator of small integers in `-span..=span`.
    struct Ints(u64);

    impl Ints {
        fn next(&mut self, span: i64) -> i64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 33) % (2 * span as u64 + 1)) as i64 - span
        }
    }

    /// The second moments about the centre of mass of integer masses `m` at integer
    /// coordinates `p` (units of `2^-shift[k]` on axis k), exactly: `(M Q - S S^T) / M` in
    /// integers, rounded to double (two roundings).
    fn exact_second_moment(m: &[i64], p: &[[i64; 3]], shift: [i32; 3]) -> Matrix3<f64> {
        let mass: i128 = m.iter().map(|&x| x as i128).sum();
        let first: [i128; 3] = std::array::from_fn(|k| {
            m.iter()
                .zip(p)
                .map(|(&w, q)| w as i128 * q[k] as i128)
                .sum()
        });
        Matrix3::from_fn(|j, k| {
            let q: i128 = m
                .iter()
                .zip(p)
                .map(|(&w, r)| w as i128 * r[j] as i128 * r[k] as i128)
                .sum();
            let numerator = mass * q - first[j] * first[k];
            ldexp(numerator as f64 / mass as f64, -shift[j] - shift[k])
        })
    }

    /// Masses 1..=8 at integer coordinates: x within +-2^14, y and z within +-`lateral`, all in
    /// units of `2^-shift[k]`, plus `offset` (an integer, exact) on every axis.
    fn cloud(n: usize, lateral: i64, seed: u64) -> (Vec<i64>, Vec<[i64; 3]>) {
        let mut ints = Ints(seed);
        let m = (0..n).map(|_| 1 + ints.next(3) + 4).collect();
        let p = (0..n)
            .map(|_| [ints.next(1 << 14), ints.next(lateral), ints.next(lateral)])
            .collect();
        (m, p)
    }

    fn to_floats(
        m: &[i64],
        p: &[[i64; 3]],
        shift: [i32; 3],
        offset: f64,
    ) -> (Vec<f64>, Vec<[f64; 3]>) {
        (
            m.iter().map(|&x| x as f64).collect(),
            p.iter()
                .map(|q| std::array::from_fn(|k| ldexp(q[k] as f64, -shift[k]) + offset))
                .collect(),
        )
    }

    /// Every entry of `s` within `64 eps sqrt(S_jj S_kk)` of the exact `exact` (columnwise:
    /// each axis to eps of its own spread, however small next to the others).
    fn assert_columnwise(s: &Matrix3<f64>, exact: &Matrix3<f64>, what: &str) {
        for j in 0..3 {
            for k in 0..3 {
                let bound = 64.0 * f64::EPSILON * exact[(j, j)].sqrt() * exact[(k, k)].sqrt();
                assert!(
                    (s[(j, k)] - exact[(j, k)]).abs() <= bound,
                    "{what}: S[{j}, {k}] = {:e}, exact {:e}",
                    s[(j, k)],
                    exact[(j, k)]
                );
            }
        }
    }

    #[test]
    fn gram_schmidt_path_matches_exact_sums_for_every_block_shape() {
        // Block tails (past the last group of 8, the last partial block, the four rows of R
        // and the parallel-axis row in the lanes), far from the origin, against exact integer
        // arithmetic, each second moment to 64 eps of its axes' spreads.
        let shift = [10, 10, 10];
        for n in [
            1, 2, 7, 8, 9, 252, 255, 256, 257, 260, 261, 511, 512, 513, 1000, 3000,
        ] {
            let (m, p) = cloud(n, 1 << 12, n as u64);
            let (masses, positions) = to_floats(&m, &p, shift, 1048576.0);
            let reference = block_center(&masses, &positions);
            assert!(
                gram_schmidt_chunk(&masses, &positions, &reference).is_some(),
                "n = {n}"
            );
            let body = MassProperties::point_masses(&masses, &positions).unwrap();
            let exact = exact_second_moment(&m, &p, shift);
            assert_columnwise(&body.second_moment(), &exact, &format!("n = {n}"));
            let mass: i64 = m.iter().sum();
            assert_eq!(body.mass, mass as f64);
        }
    }

    #[test]
    fn tiny_lateral_spreads_take_the_scaled_path_and_keep_their_digits() {
        // A needle along x (spread ~2^4) whose y and z spreads are 2^-k: below 2^-450 the
        // weighted squares leave the range where unscaled Gram-Schmidt is safe (see SAFE), and
        // the chunk is factored by scaled Householder QR instead; either way each moment
        // matches exact integer arithmetic to 64 eps of its axes' spreads.
        for (k, fast) in [(300, true), (430, true), (460, false), (500, false)] {
            let shift = [10, k, k];
            let (m, p) = cloud(700, 5, k as u64);
            let (masses, positions) = to_floats(&m, &p, shift, 0.0);
            let reference = block_center(&masses, &positions);
            let routed = gram_schmidt_chunk(&masses, &positions, &reference).is_some();
            assert_eq!(routed, fast, "k = {k}");
            let body = MassProperties::point_masses(&masses, &positions).unwrap();
            let exact = exact_second_moment(&m, &p, shift);
            assert_columnwise(&body.second_moment(), &exact, &format!("k = {k}"));
        }
    }

    #[test]
    fn chunks_on_both_paths_merge_exactly_and_the_same_for_any_thread_count() {
        // Three chunks and a bit; z is 0 in all but the second chunk, where it spreads over
        // 2^-480 (weighted squares below the range of the unscaled path): that chunk alone is
        // factored by scaled Householder QR, the others by Gram-Schmidt, and the factors are
        // merged. Against exact integer arithmetic (z in units of 2^-480), each moment to 64 eps
        // of its axes' spreads (S_zz and the products with z come from the second chunk only),
        // and bit for bit the same on 1, 2 and 3 threads.
        let shift = [10, 10, 480];
        let n = 3 * CHUNK + 1000;
        let mut ints = Ints(17);
        let m: Vec<i64> = (0..n).map(|_| 5 + ints.next(3)).collect();
        let p: Vec<[i64; 3]> = (0..n)
            .map(|i| {
                let z = if (CHUNK..2 * CHUNK).contains(&i) {
                    ints.next(5)
                } else {
                    0
                };
                [ints.next(1 << 14), ints.next(1 << 12), z]
            })
            .collect();
        let (masses, positions) = to_floats(&m, &p, shift, 0.0);
        let reference = block_center(&masses, &positions);
        assert_eq!(reference[2], 0.0);
        let routes: Vec<bool> = masses
            .chunks(CHUNK)
            .zip(positions.chunks(CHUNK))
            .map(|(m, r)| gram_schmidt_chunk(m, r, &reference).is_some())
            .collect();
        assert_eq!(routes, [true, false, true, true]);
        let exact = exact_second_moment(&m, &p, shift);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| MassProperties::point_masses(&masses, &positions).unwrap())
        };
        let one = run(1);
        assert_columnwise(&one.second_moment(), &exact, "mixed chunks");
        for threads in [2, 3] {
            let other = run(threads);
            assert_eq!(other.mass.to_bits(), one.mass.to_bits());
            for (a, b) in other.center_of_mass.iter().zip(one.center_of_mass.iter()) {
                assert_eq!(a.to_bits(), b.to_bits());
            }
            let (a, b) = (other.second_moment(), one.second_moment());
            for (x, y) in a.iter().zip(b.iter()) {
                assert_eq!(x.to_bits(), y.to_bits(), "{threads} threads");
            }
        }
    }

    #[test]
    fn bad_points_are_named_first_to_last_across_blocks_and_chunks() {
        let n = 3 * CHUNK;
        let masses = vec![1.0; n];
        let positions: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.5, -0.25]).collect();
        let name = |masses: &[f64], positions: &[[f64; 3]]| match MassProperties::point_masses(
            masses, positions,
        ) {
            Err(Error::NonFinite { name, .. } | Error::NonPositive { name, .. }) => name,
            other => panic!("{:?}", other.map(|b| b.mass)),
        };
        let (mut m, mut p) = (masses.clone(), positions.clone());
        p[300][2] = f64::NAN;
        assert_eq!(name(&m, &p), "positions[300, 2]");
        m[299] = -1.0;
        assert_eq!(name(&m, &p), "masses[299]");
        let (mut m, mut p) = (masses.clone(), positions.clone());
        m[2 * CHUNK + 5] = 0.0;
        p[CHUNK + 700][0] = f64::INFINITY;
        assert_eq!(name(&m, &p), format!("positions[{}, 0]", CHUNK + 700));
    }
}
