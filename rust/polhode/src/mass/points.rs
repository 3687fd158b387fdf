//! Bodies made of point masses (a molecule, a sampled cloud).

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::factor::{RowAccumulator, SecondMoment};
use super::MassProperties;
use crate::dynamics::Monitor;
use crate::eigen::{exponent, ldexp};
use crate::error::{finite, Error, Result};

/// Points per parallel chunk: each chunk is factored on its own and the factors combined, in
/// order. Fixed, so that the result does not depend on the number of threads.
pub const POINT_CHUNK: usize = 1 << 15;
const CHUNK: usize = POINT_CHUNK;

impl MassProperties {
    /// Point masses `masses[i]` at `positions[i]` (body coordinates).
    ///
    /// One pass over the points: the offsets `d_i = r_i - r_0` from a reference point (the
    /// centre of mass of the first 256 points) are formed, and the rows `[sqrt(m_i), sqrt(m_i) d_i]` factored by Householder QR (in parallel chunks,
    /// blocks of 256 rows, vectorised): with the mass column first, the lower-right 3x3 block of
    /// the factor is the square root of the second moments about the centre of mass (the Schur
    /// complement `S2 - S1 S1^T / M`, formed without subtracting squares). Nothing is summed
    /// about a far origin, and nothing is squared, so the cloud can be 1e8 away from the origin
    /// or nearly collinear. Masses or offsets near the ends of the range of double precision
    /// take a second pass, scaled by powers of two.
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
        let chunks: Vec<Result<(Scan, [[f64; 4]; 4])>> = masses
            .par_chunks(CHUNK)
            .zip(positions.par_chunks(CHUNK))
            .enumerate()
            .map(|(chunk, (m, r))| {
                look()?;
                crate::simd::dispatch(
                    #[inline(always)]
                    || one_pass_chunk(m, r, &reference, chunk * CHUNK),
                )
            })
            .collect();
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
        let reference: Vector3<f64> = positions[0].into();
        // Pass 1, per chunk: the first bad value; the mass and first moment about the first
        // point, unscaled; the largest mass and offset (the scales if a second pass is needed).
        let scans: Vec<Result<Scan>> = masses
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
            })
            .collect();
        let mut total = Scan::default();
        for scan in scans {
            let scan = scan?;
            total.mass += scan.mass;
            total.first += scan.first;
            total.heaviest = total.heaviest.max(scan.heaviest);
            total.farthest = total.farthest.max(scan.farthest);
        }
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
            // Pass 2, per chunk: the same sums, scaled, added in order.
            let sums: Vec<Result<(f64, Vector3<f64>)>> = masses
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
                })
                .collect();
            let (mut mass, mut first_moment) = (0.0, Vector3::zeros());
            for sum in sums {
                let (m, r) = sum?;
                mass += m;
                first_moment += r;
            }
            (mass, first_moment)
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
        let factors: Vec<Result<Matrix3<f64>>> = masses
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
            })
            .collect();
        let mut acc = RowAccumulator::new();
        for factor in factors {
            acc.push_matrix(&factor?);
        }
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
