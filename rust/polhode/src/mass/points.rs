//! Bodies made of point masses (a molecule, a sampled cloud).

use nalgebra::Vector3;
use rayon::prelude::*;

use super::factor::{RowAccumulator, SecondMoment};
use super::MassProperties;
use crate::error::{finite, Error, Result};

/// Points per parallel chunk: each chunk is factored on its own and the factors combined.
const CHUNK: usize = 1 << 15;

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
    pub fn point_masses<P>(masses: &[f64], positions: &[P]) -> Result<Self>
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
        for (i, (&m, &r)) in masses.iter().zip(positions).enumerate() {
            let r: Vector3<f64> = r.into();
            if !(m.is_finite() && m > 0.0) {
                finite(&format!("masses[{i}]"), m)?;
                return Err(Error::NonPositive {
                    name: format!("masses[{i}]"),
                    value: m,
                });
            }
            if !(r[0].is_finite() && r[1].is_finite() && r[2].is_finite()) {
                for k in 0..3 {
                    finite(&format!("positions[{i}, {k}]"), r[k])?;
                }
            }
        }
        let reference: Vector3<f64> = positions[0].into();
        let (mass, first_moment) = masses
            .par_chunks(CHUNK)
            .zip(positions.par_chunks(CHUNK))
            .map(|(m, r)| {
                m.iter()
                    .zip(r)
                    .fold((0.0, Vector3::zeros()), |(sm, sr), (&mi, ri)| {
                        (sm + mi, sr + ((*ri).into() - reference) * mi)
                    })
            })
            .reduce(|| (0.0, Vector3::zeros()), |a, b| (a.0 + b.0, a.1 + b.1));
        if !mass.is_finite() {
            return Err(Error::NonFinite {
                name: "sum(masses)".into(),
                value: mass,
            });
        }
        // The centre as a double-double, so that the rows below are centred exactly.
        let (center_of_mass, center_of_mass_low) =
            super::renormalised(reference, first_moment / mass);
        let factor = masses
            .par_chunks(CHUNK)
            .zip(positions.par_chunks(CHUNK))
            .map(|(m, r)| {
                let mut acc = RowAccumulator::new();
                for (&mi, ri) in m.iter().zip(r) {
                    let ri: Vector3<f64> = (*ri).into();
                    let d = ((ri - center_of_mass) - center_of_mass_low) * mi.sqrt();
                    acc.push([d[0], d[1], d[2]]);
                }
                acc.finish()
            })
            .reduce(nalgebra::Matrix3::zeros, |a, b| {
                let mut acc = RowAccumulator::new();
                acc.push_matrix(&a);
                acc.push_matrix(&b);
                acc.finish()
            });
        let second_moment = SecondMoment {
            isotropic: 0.0,
            factor,
        };
        if !factor.iter().all(|v| v.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "positions".into(),
                reason: "the second moments overflow double precision.".into(),
            });
        }
        Ok(Self {
            mass,
            center_of_mass,
            center_of_mass_low,
            second_moment,
        })
    }
}
