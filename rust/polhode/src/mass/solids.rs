//! Closed-form mass properties of the standard solids, each about its centre of mass.
//!
//! Each solid is given by its principal second moments `C = diag(c)` (`c_x = sum m x^2`, ...),
//! from which `I = tr(C) 1 - C`; the sources are the standard tables (e.g. Fetter & Walecka
//! ch. 5), each checked against a quadrature in the tests.

use nalgebra::{Matrix3, Vector3};

use super::factor::SecondMoment;
use super::{number, out_of_range, MassProperties, OutOfRange};
use crate::eigen::{exponent, ldexp, scientific};
use crate::error::{positive, Error, Result};

/// A solid centred on the origin from its principal second moments `c(mass, lengths)`, which
/// must be homogeneous of degree 1 in the mass and 2 in the lengths.
///
/// `c` is evaluated on the mass and the lengths brought near 1 by powers of two and the result
/// scaled back (exactly, in the normal range), so that `m r^2` neither overflows nor underflows
/// on the way where the moments do not; moments beyond the range of double precision are an
/// error naming the argument that contributes most (`names` name the lengths).
fn solid<const N: usize>(
    mass: f64,
    names: [&str; N],
    lengths: [f64; N],
    c: impl Fn(f64, [f64; N]) -> Vector3<f64>,
) -> Result<MassProperties> {
    let longest = lengths.iter().fold(0.0_f64, |m, x| m.max(*x));
    let (el, em) = (exponent(longest), exponent(mass));
    let scaled = c(ldexp(mass, -em), lengths.map(|x| ldexp(x, -el)));
    let k = em + 2 * el;
    // The length that sets the size: the longest (the first on a tie).
    let mut j = 0;
    for (i, &x) in lengths.iter().enumerate() {
        if x > lengths[j] {
            j = i;
        }
    }
    let mut blame = vec![("mass", mass.log2())];
    if N > 0 {
        blame.push((names[j], 2.0 * lengths[j].log2()));
    }
    // The largest moment, I_k = c_i + c_j, still in units of 2^k: its size for the message.
    let largest = (scaled[0] + scaled[1])
        .max(scaled[0] + scaled[2])
        .max(scaled[1] + scaled[2]);
    if !ldexp(largest, k).is_finite() {
        return Err(out_of_range(
            OutOfRange::Overflow,
            format!(
                "the moments of inertia overflow double precision (the largest is about {}, \
                 beyond the largest double, {:e}).",
                scientific(largest, k),
                f64::MAX
            ),
            &blame,
        ));
    }
    let second_moment = SecondMoment::principal_form(scaled, k, &Matrix3::identity());
    MassProperties::new(mass, Vector3::zeros(), second_moment).in_range(&blame)
}

fn non_negative(name: &str, value: f64) -> Result<f64> {
    crate::error::finite(name, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidArgument {
            name: name.into(),
            reason: format!("expected a non-negative number, got {}.", number(value)),
        })
    }
}

impl MassProperties {
    /// A single point mass at the origin.
    pub fn point(mass: f64) -> Result<Self> {
        positive("mass", mass)?;
        Ok(Self::new(mass, Vector3::zeros(), SecondMoment::ZERO))
    }

    /// A solid sphere: `I = 2/5 m r^2`.
    pub fn sphere(mass: f64, radius: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("radius", radius)?;
        solid(mass, ["radius"], [radius], |m, [r]| {
            Vector3::repeat(m * r * r / 5.0)
        })
    }

    /// A thin spherical shell: `I = 2/3 m r^2`.
    pub fn spherical_shell(mass: f64, radius: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("radius", radius)?;
        solid(mass, ["radius"], [radius], |m, [r]| {
            Vector3::repeat(m * r * r / 3.0)
        })
    }

    /// A solid box (cuboid) with full edge lengths `size` along x, y, z:
    /// `I_x = m (b^2 + c^2) / 12` and cyclic.
    pub fn cuboid(mass: f64, size: Vector3<f64>) -> Result<Self> {
        positive("mass", mass)?;
        for k in 0..3 {
            positive(&format!("size[{k}]"), size[k])?;
        }
        solid(
            mass,
            ["size[0]", "size[1]", "size[2]"],
            [size[0], size[1], size[2]],
            |m, s| Vector3::from(s.map(|a| m * a * a / 12.0)),
        )
    }

    /// A solid cylinder, symmetry axis z: `I_z = m r^2 / 2`, `I_x = m (3 r^2 + L^2) / 12`.
    pub fn cylinder(mass: f64, radius: f64, length: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("radius", radius)?;
        positive("length", length)?;
        solid(mass, ["radius", "length"], [radius, length], |m, [r, l]| {
            let radial = m * r * r / 4.0;
            Vector3::new(radial, radial, m * l * l / 12.0)
        })
    }

    /// A thick-walled tube, axis z: `I_z = m (r1^2 + r2^2) / 2`,
    /// `I_x = m (3 (r1^2 + r2^2) + L^2) / 12`. `inner_radius` may be 0 (a cylinder).
    pub fn tube(mass: f64, inner_radius: f64, outer_radius: f64, length: f64) -> Result<Self> {
        positive("mass", mass)?;
        non_negative("inner_radius", inner_radius)?;
        positive("outer_radius", outer_radius)?;
        positive("length", length)?;
        if inner_radius >= outer_radius {
            return Err(Error::InvalidArgument {
                name: "inner_radius".into(),
                reason: format!(
                    "expected inner_radius < outer_radius, got {} >= {}.",
                    number(inner_radius),
                    number(outer_radius)
                ),
            });
        }
        solid(
            mass,
            ["inner_radius", "outer_radius", "length"],
            [inner_radius, outer_radius, length],
            |m, [r1, r2, l]| {
                let radial = m * (r1 * r1 + r2 * r2) / 4.0;
                Vector3::new(radial, radial, m * l * l / 12.0)
            },
        )
    }

    /// A solid right circular cone of base `radius` and `length` along the axis, with its base
    /// disc in the plane z = 0 centred on the z axis and its apex at z = `length`; the centre
    /// of mass is at z = L/4. About it: `I_z = 3/10 m r^2`, `I_x = 3/20 m r^2 + 3/80 m L^2`.
    pub fn cone(mass: f64, radius: f64, length: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("radius", radius)?;
        positive("length", length)?;
        let mut body = solid(mass, ["radius", "length"], [radius, length], |m, [r, l]| {
            let radial = 3.0 * m * r * r / 20.0;
            Vector3::new(radial, radial, 3.0 * m * l * l / 80.0)
        })?;
        body.center_of_mass = Vector3::new(0.0, 0.0, length / 4.0);
        Ok(body)
    }

    /// A solid ellipsoid with semi-axes (a, b, c) along x, y, z: `I_x = m (b^2 + c^2) / 5`.
    pub fn ellipsoid(mass: f64, semi_axes: Vector3<f64>) -> Result<Self> {
        positive("mass", mass)?;
        for k in 0..3 {
            positive(&format!("semi_axes[{k}]"), semi_axes[k])?;
        }
        solid(
            mass,
            ["semi_axes[0]", "semi_axes[1]", "semi_axes[2]"],
            [semi_axes[0], semi_axes[1], semi_axes[2]],
            |m, s| Vector3::from(s.map(|a| m * a * a / 5.0)),
        )
    }

    /// A thin rod along z: `I_x = I_y = m L^2 / 12`, `I_z = 0`.
    pub fn rod(mass: f64, length: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("length", length)?;
        solid(mass, ["length"], [length], |m, [l]| {
            Vector3::new(0.0, 0.0, m * l * l / 12.0)
        })
    }

    /// A thin disc in the xy plane: `I_z = m r^2 / 2`, `I_x = I_y = m r^2 / 4`.
    pub fn disk(mass: f64, radius: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("radius", radius)?;
        solid(mass, ["radius"], [radius], |m, [r]| {
            let radial = m * r * r / 4.0;
            Vector3::new(radial, radial, 0.0)
        })
    }

    /// A solid torus, symmetry axis z, tube radius `minor_radius` <= `major_radius`:
    /// `I_z = m (R^2 + 3 a^2 / 4)`, `I_x = m (R^2 / 2 + 5 a^2 / 8)`.
    pub fn torus(mass: f64, major_radius: f64, minor_radius: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("major_radius", major_radius)?;
        positive("minor_radius", minor_radius)?;
        if minor_radius > major_radius {
            return Err(Error::InvalidArgument {
                name: "minor_radius".into(),
                reason: format!(
                    "expected minor_radius <= major_radius (a ring or horn torus), got {} > {}.",
                    number(minor_radius),
                    number(major_radius)
                ),
            });
        }
        solid(
            mass,
            ["major_radius", "minor_radius"],
            [major_radius, minor_radius],
            |m, [major, minor]| {
                let (r2, a2) = (major * major, minor * minor);
                let radial = m * (r2 / 2.0 + 3.0 * a2 / 8.0);
                Vector3::new(radial, radial, m * a2 / 4.0)
            },
        )
    }

    /// A capsule: a cylinder of `length` (>= 0) and `radius` along z capped by two hemispheres,
    /// uniform density. With the cylinder's mass `m_c` and the hemispheres' `m_s` split by
    /// volume: `I_z = m_c r^2 / 2 + 2/5 m_s r^2`,
    /// `I_x = m_c (3 r^2 + h^2) / 12 + m_s (2 r^2 / 5 + h^2 / 4 + 3 h r / 8)`.
    pub fn capsule(mass: f64, radius: f64, length: f64) -> Result<Self> {
        positive("mass", mass)?;
        positive("radius", radius)?;
        non_negative("length", length)?;
        solid(mass, ["radius", "length"], [radius, length], |m, [r, h]| {
            // Volumes pi r^2 h and 4/3 pi r^3; the common pi r^2 cancels.
            let cylinder_share = h / (h + 4.0 * r / 3.0);
            let m_c = m * cylinder_share;
            let m_s = m - m_c;
            let radial = m_c * r * r / 4.0 + m_s * r * r / 5.0;
            // A hemisphere of radius r has its flat face at z = h/2: z^2 averages
            // h^2/4 + h (3 r / 8) + r^2 / 5 over it.
            let axial = m_c * h * h / 12.0 + m_s * (h * h / 4.0 + 3.0 * h * r / 8.0 + r * r / 5.0);
            Vector3::new(radial, radial, axial)
        })
    }
}

/// An analytic solid by name: what a binding or a command line needs to build any of them
/// through one entry, [`MassProperties::solid`]. Adding a solid is its constructor above and
/// one row of [`SOLIDS`].
#[derive(Clone, Copy, Debug)]
pub struct Solid {
    /// The constructor's name (`"sphere"`, ...).
    pub name: &'static str,
    /// Its parameters after the mass, in order: each a name and a width (1, or 3 for a
    /// vector along x, y, z).
    pub parameters: &'static [(&'static str, usize)],
    build: fn(f64, &[f64]) -> Result<MassProperties>,
}

/// `(x, y, z)` from the first three numbers.
fn xyz(p: &[f64]) -> Vector3<f64> {
    Vector3::new(p[0], p[1], p[2])
}

/// Every analytic solid of [`MassProperties`], by name.
pub const SOLIDS: &[Solid] = &[
    Solid {
        name: "point",
        parameters: &[],
        build: |m, _| MassProperties::point(m),
    },
    Solid {
        name: "sphere",
        parameters: &[("radius", 1)],
        build: |m, p| MassProperties::sphere(m, p[0]),
    },
    Solid {
        name: "spherical_shell",
        parameters: &[("radius", 1)],
        build: |m, p| MassProperties::spherical_shell(m, p[0]),
    },
    Solid {
        name: "cuboid",
        parameters: &[("size", 3)],
        build: |m, p| MassProperties::cuboid(m, xyz(p)),
    },
    Solid {
        name: "cylinder",
        parameters: &[("radius", 1), ("length", 1)],
        build: |m, p| MassProperties::cylinder(m, p[0], p[1]),
    },
    Solid {
        name: "tube",
        parameters: &[("inner_radius", 1), ("outer_radius", 1), ("length", 1)],
        build: |m, p| MassProperties::tube(m, p[0], p[1], p[2]),
    },
    Solid {
        name: "cone",
        parameters: &[("radius", 1), ("length", 1)],
        build: |m, p| MassProperties::cone(m, p[0], p[1]),
    },
    Solid {
        name: "ellipsoid",
        parameters: &[("semi_axes", 3)],
        build: |m, p| MassProperties::ellipsoid(m, xyz(p)),
    },
    Solid {
        name: "rod",
        parameters: &[("length", 1)],
        build: |m, p| MassProperties::rod(m, p[0]),
    },
    Solid {
        name: "disk",
        parameters: &[("radius", 1)],
        build: |m, p| MassProperties::disk(m, p[0]),
    },
    Solid {
        name: "torus",
        parameters: &[("major_radius", 1), ("minor_radius", 1)],
        build: |m, p| MassProperties::torus(m, p[0], p[1]),
    },
    Solid {
        name: "capsule",
        parameters: &[("radius", 1), ("length", 1)],
        build: |m, p| MassProperties::capsule(m, p[0], p[1]),
    },
];

impl MassProperties {
    /// The analytic solid named `name` (a row of [`SOLIDS`]) of `mass`, from the numbers of its
    /// parameters in order (a vector parameter gives three).
    ///
    /// ```
    /// # use polhode::MassProperties;
    /// let a = MassProperties::solid("cylinder", 2.0, &[0.5, 3.0])?;
    /// assert_eq!(a, MassProperties::cylinder(2.0, 0.5, 3.0)?);
    /// # Ok::<(), polhode::Error>(())
    /// ```
    pub fn solid(name: &str, mass: f64, parameters: &[f64]) -> Result<Self> {
        let Some(solid) = SOLIDS.iter().find(|s| s.name == name) else {
            let names: Vec<&str> = SOLIDS.iter().map(|s| s.name).collect();
            return Err(Error::InvalidArgument {
                name: "kind".into(),
                reason: format!("expected one of {}, got {name:?}.", names.join(", ")),
            });
        };
        let width: usize = solid.parameters.iter().map(|&(_, w)| w).sum();
        if parameters.len() != width {
            return Err(Error::Shape {
                name: "parameters".into(),
                expected: format!("({width},)"),
                got: format!("({},)", parameters.len()),
            });
        }
        (solid.build)(mass, parameters)
    }
}
