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
    /// The centre of mass is found relative to the first point, then the second moments are
    /// factored from the centred rows `sqrt(m_i) (r_i - r_cm)` by Householder QR (in parallel
    /// chunks): nothing is summed about a far origin, and nothing is squared, so the cloud can be
    /// 1e8 away from the origin or nearly collinear.
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
