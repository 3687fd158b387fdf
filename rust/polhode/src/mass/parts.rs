//! The stored parts of a [`MassProperties`], out and back in: what a serialised body (Python's
//! pickle) is made of. A round trip gives the same body bit for bit, since the parts are the
//! stored numbers themselves, not the tensor materialised from them.

use nalgebra::{Matrix3, Vector3};

use super::factor::SecondMoment;
use super::{two_sum, MassProperties};
use crate::error::{finite, positive, Error, Result};

/// The numbers a [`MassProperties`] keeps: its mass, its centre of mass as an unevaluated sum
/// `center_of_mass + center_of_mass_low` (a renormalised double-double), and its second moment
/// about the centre of mass in square-root form, `C = isotropic 1 + factor^T factor`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parts {
    /// The total mass (finite, > 0).
    pub mass: f64,
    /// The centre of mass, rounded to doubles.
    pub center_of_mass: Vector3<f64>,
    /// What the rounding of the centre of mass left out: `fl(high + low) == high` for each
    /// component.
    pub center_of_mass_low: Vector3<f64>,
    /// The isotropic part `c >= 0` of the second moment.
    pub isotropic: f64,
    /// The factor `F` of the anisotropic part, `F^T F`.
    pub factor: Matrix3<f64>,
}

impl MassProperties {
    /// The stored numbers of this body, for [`Self::from_parts`].
    pub fn parts(&self) -> Parts {
        Parts {
            mass: self.mass,
            center_of_mass: self.center_of_mass,
            center_of_mass_low: self.center_of_mass_low,
            isotropic: self.second_moment.isotropic,
            factor: self.second_moment.factor,
        }
    }

    /// A body from the numbers [`Self::parts`] gave: the same body, bit for bit.
    ///
    /// Checked as any constructor's input is: a finite positive mass, finite vectors, a
    /// renormalised double-double centre of mass (each low part below half an ulp of its high
    /// part, so that `high + low` rounds to `high`), a finite isotropic part `>= 0`, a finite
    /// factor, and every quantity the body reports within the range of double precision. Each
    /// failure is an error naming the part (`center_of_mass_low[1]`, `isotropic`, ...).
    ///
    /// ```
    /// use nalgebra::Vector3;
    /// use polhode::MassProperties;
    /// let body = MassProperties::cuboid(2.0, Vector3::new(0.1, 0.2, 0.3)).unwrap()
    ///     .translated(&Vector3::new(1e8, 0.1, 0.0)).unwrap();
    /// let again = MassProperties::from_parts(body.parts()).unwrap();
    /// assert_eq!(again, body);
    /// ```
    pub fn from_parts(parts: Parts) -> Result<Self> {
        positive("mass", parts.mass)?;
        for k in 0..3 {
            let (high, low) = (parts.center_of_mass[k], parts.center_of_mass_low[k]);
            finite(&format!("center_of_mass[{k}]"), high)?;
            finite(&format!("center_of_mass_low[{k}]"), low)?;
            if two_sum(high, low) != (high, low) {
                return Err(Error::InvalidArgument {
                    name: format!("center_of_mass_low[{k}]"),
                    reason: format!(
                        "expected the rounding error of center_of_mass[{k}] = {high:e} (at most \
                         half an ulp of it), got {low:e}."
                    ),
                });
            }
        }
        finite("isotropic", parts.isotropic)?;
        if parts.isotropic < 0.0 {
            return Err(Error::InvalidArgument {
                name: "isotropic".into(),
                reason: format!("expected a number >= 0, got {:e}.", parts.isotropic),
            });
        }
        for (index, &x) in parts.factor.iter().enumerate() {
            // nalgebra stores column by column.
            finite(&format!("factor[{}, {}]", index % 3, index / 3), x)?;
        }
        let body = Self {
            mass: parts.mass,
            center_of_mass: parts.center_of_mass,
            center_of_mass_low: parts.center_of_mass_low,
            second_moment: SecondMoment {
                isotropic: parts.isotropic,
                factor: parts.factor,
            },
        };
        body.in_range(&[("factor", 0.0)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits(body: &MassProperties) -> Vec<u64> {
        let p = body.parts();
        let mut out = vec![p.mass.to_bits(), p.isotropic.to_bits()];
        out.extend(p.center_of_mass.iter().map(|x| x.to_bits()));
        out.extend(p.center_of_mass_low.iter().map(|x| x.to_bits()));
        out.extend(p.factor.iter().map(|x| x.to_bits()));
        out
    }

    #[test]
    fn round_trip_is_bit_exact() {
        let needle = MassProperties::cylinder(1.0, 1e-8, 1.0).unwrap();
        let far = MassProperties::cuboid(3.0, Vector3::new(0.1, 0.2, 0.3))
            .unwrap()
            .rotated(&nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 0.9).into_inner())
            .unwrap()
            .translated(&Vector3::new(1e8 + 0.1, -3.3, 1e-9))
            .unwrap();
        let points = MassProperties::point_masses(
            &[1.0, 2.0, 1e-12],
            &[[0.1, 0.2, 0.3], [-1.0, 0.5, 2.0], [1e3, 0.0, 0.0]],
        )
        .unwrap();
        let composite = needle + far + points;
        for body in [needle, far, points, composite] {
            let again = MassProperties::from_parts(body.parts()).unwrap();
            assert_eq!(bits(&again), bits(&body));
            assert_eq!(again, body);
        }
        // The composite far from the origin keeps a low part: the round trip is not trivial.
        assert!(composite
            .parts()
            .center_of_mass_low
            .iter()
            .any(|&x| x != 0.0));
    }

    #[test]
    fn bad_parts_are_errors_naming_the_part() {
        let good = MassProperties::sphere(1.0, 0.5).unwrap().parts();
        let name = |parts: Parts| match MassProperties::from_parts(parts) {
            Err(error) => {
                let mut name = String::new();
                let _ = error.map_name(|n| {
                    name.clone_from(&n);
                    n
                });
                name
            }
            Ok(_) => "accepted".into(),
        };
        assert_eq!(name(Parts { mass: 0.0, ..good }), "mass");
        assert_eq!(
            name(Parts {
                mass: f64::NAN,
                ..good
            }),
            "mass"
        );
        let mut high = good;
        high.center_of_mass[1] = f64::INFINITY;
        assert_eq!(name(high), "center_of_mass[1]");
        let mut low = good;
        low.center_of_mass = Vector3::new(1.0, 0.0, 0.0);
        low.center_of_mass_low = Vector3::new(f64::EPSILON, 0.0, 0.0); // a whole ulp of 1
        assert_eq!(name(low), "center_of_mass_low[0]");
        assert_eq!(
            name(Parts {
                isotropic: -1e-300,
                ..good
            }),
            "isotropic"
        );
        assert_eq!(
            name(Parts {
                isotropic: f64::INFINITY,
                ..good
            }),
            "isotropic"
        );
        let mut factor = good;
        factor.factor[(2, 1)] = f64::NAN;
        assert_eq!(name(factor), "factor[2, 1]");
        let mut huge = good;
        huge.factor[(0, 0)] = 1e200;
        assert_eq!(name(huge), "factor");
    }
}
