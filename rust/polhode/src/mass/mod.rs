//! Mass properties: mass, centre of mass and inertia of point masses, solids and composites.
//!
//! [`MassProperties`] keeps the second-moment matrix about the centre of mass,
//! `C = sum m r r^T`, in a square-root form (`C = c 1 + F^T F`) rather than the inertia tensor
//! `I = tr(C) 1 - C`: composition and principal axes then never lose the small moments of a
//! needle or the tiny anisotropy of a heavy sphere with a speck on it (docs/architecture.md,
//! Numerics).

mod factor;
mod frames;
mod mesh;
mod parts;
mod points;
mod solids;
mod topology;

pub use frames::{
    point_masses_inertia, point_masses_inertia_monitored, Position, FRAME_POINTS_CHUNK,
};
pub use parts::Parts;
pub use points::POINT_CHUNK;
pub use solids::{Solid, SOLIDS};
pub use topology::{merge_vertices, weld_tolerance, Merged, WELD_EXPONENT};

use std::ops::Add;

use nalgebra::{Matrix3, Vector3};

use crate::eigen::{self, exponent, ldexp, scientific, Principal, DEFAULT_RTOL};
use crate::error::{finite, positive, Error, Result};
use crate::settings::Setting;
use factor::SecondMoment;

use crate::Monitor;

/// Triangles (or vertices) between two looks at the monitor in
/// [`MassProperties::mesh_monitored`] (a millisecond or less of work): a mesh of more than two
/// such blocks is worth watching.
pub const MESH_CHUNK: usize = 1 << 16;

/// A look at `monitor`, if any.
fn look(monitor: Option<&Monitor>) -> Result<()> {
    monitor.map_or(Ok(()), Monitor::look)
}

/// An [`Error::InvalidArgument`] naming `name`: a mesh's faces or vertices (`mesh.rs`,
/// `topology.rs`).
fn invalid(name: impl Into<String>, reason: String) -> Error {
    Error::InvalidArgument {
        name: name.into(),
        reason,
    }
}

/// A number as Python's `repr` would show it, roughly: positional between 1e-4 and 1e16,
/// scientific outside (never the hundreds of digits of `{}` for 1e300 or 1e-300).
pub(crate) fn number(x: f64) -> String {
    let size = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e16).contains(&size) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Which end of the range of double precision a body's quantities left.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OutOfRange {
    /// Something is beyond `f64::MAX`.
    Overflow,
    /// A positive quantity that must stay positive (a mesh's mass) rounds to zero.
    Underflow,
}

/// The error for a result out of the range of double precision, naming the argument that
/// contributes most to it: of `blame`'s `(name, log2 of its contribution)`, the largest for an
/// overflow, the smallest for an underflow.
pub(crate) fn out_of_range(kind: OutOfRange, reason: String, blame: &[(&str, f64)]) -> Error {
    let pick = blame.iter().copied().reduce(|a, b| {
        let b_wins = match kind {
            OutOfRange::Overflow => b.1 > a.1,
            OutOfRange::Underflow => b.1 < a.1,
        };
        if b_wins {
            b
        } else {
            a
        }
    });
    Error::InvalidArgument {
        name: pick.map_or("mass", |p| p.0).to_owned(),
        reason,
    }
}

/// The largest magnitude of an iterator of numbers, NaN if any is NaN.
fn largest(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, |m: f64, x| {
        if m.is_nan() || x.is_nan() {
            f64::NAN
        } else {
            m.max(x.abs())
        }
    })
}

/// Mass, centre of mass and second moments of a rigid body, in the body's own axes.
///
/// Immutable: [`translated`](Self::translated), [`rotated`](Self::rotated) and `+` return new
/// values.
///
/// ```
/// use nalgebra::Vector3;
/// use polhode::MassProperties;
/// // A 1 kg, 10 cm cube about one of its corners: moments m a^2 (1/6, 11/12, 11/12).
/// let cube = MassProperties::cuboid(1.0, Vector3::new(0.1, 0.1, 0.1)).unwrap();
/// let about_corner = cube.inertia_about(&Vector3::new(-0.05, -0.05, -0.05)).unwrap();
/// let p = polhode::symmetric_eigen3(&about_corner).unwrap();
/// assert!((p.moments[0] - 0.01 / 6.0).abs() < 1e-16);
/// assert!((p.moments[2] - 0.01 * 11.0 / 12.0).abs() < 1e-16);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    mass: f64,
    /// The centre of mass as an unevaluated sum `high + low` (double-double): far from the
    /// origin its rounding would otherwise leak, linearly, into the vectors between the parts
    /// of a composite and from there into the second moments.
    center_of_mass: Vector3<f64>,
    center_of_mass_low: Vector3<f64>,
    second_moment: SecondMoment,
}

/// `a + b` as `(s, e)` with `s = fl(a + b)` and `a + b = s + e` exactly (Knuth's TwoSum).
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `high + low` as a renormalised double-double vector.
pub(crate) fn renormalised(high: Vector3<f64>, low: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let mut h = Vector3::zeros();
    let mut l = Vector3::zeros();
    for k in 0..3 {
        (h[k], l[k]) = two_sum(high[k], low[k]);
    }
    (h, l)
}

impl MassProperties {
    /// A body from its mass, centre of mass and second moment, all validated by the caller.
    fn new(mass: f64, center_of_mass: Vector3<f64>, second_moment: SecondMoment) -> Self {
        Self {
            mass,
            center_of_mass,
            center_of_mass_low: Vector3::zeros(),
            second_moment,
        }
    }

    /// The vector from `point` to the centre of mass, to double-double accuracy before the last
    /// rounding.
    fn offset_of_center(&self, point: &Vector3<f64>) -> Vector3<f64> {
        (self.center_of_mass - point) + self.center_of_mass_low
    }

    /// A body from its mass, its inertia tensor about its centre of mass and that centre.
    ///
    /// The tensor must be finite, symmetric (to 64 eps), positive semidefinite and satisfy the
    /// triangle inequality `I1 + I2 >= I3`, each to a relative tolerance of
    /// `16 eps tr(I) / 2`; planar (`I1 + I2 = I3`) and collinear (a zero moment) bodies are
    /// valid.
    pub fn from_inertia(
        mass: f64,
        inertia: &Matrix3<f64>,
        center_of_mass: &Vector3<f64>,
    ) -> Result<Self> {
        positive("mass", mass)?;
        check_vector("center_of_mass", center_of_mass)?;
        let inertia = eigen::checked_symmetric(inertia, "inertia")?;
        // In units of 2^k (entries below 1), so that neither the trace nor anything after it
        // can overflow or underflow: a tensor of 8e307 or of 1e-310 is as good as one of 1.
        let (p, k) = eigen::eigen_symmetric_scaled(&inertia, 0.0);
        let shown = |x: f64| {
            let v = ldexp(x, k);
            if v.is_finite() && (v != 0.0 || x == 0.0) {
                format!("{v:e}")
            } else {
                scientific(x, k)
            }
        };
        let half_trace = 0.5 * p.moments.sum();
        let tolerance = 16.0 * f64::EPSILON * half_trace.abs();
        // Principal second moments c_k = tr(I)/2 - I_k = (I_i + I_j - I_k)/2; all must be >= 0
        // (the triangle inequality; it implies I >= 0). With the moments ascending, each is
        // formed as a difference of the larger two plus the other: c_2 = ((I1 - I2) + I0)/2,
        // the difference exact (I2 <= 2 I1); through tr(I)/2 a moment below eps of the trace
        // was lost (`diag(1e-20, 1, 1)` became a body with moments 0, 1, 1).
        let m = &p.moments;
        let c = Vector3::new(
            ((m[2] - m[0]) + m[1]) * 0.5,
            ((m[2] - m[1]) + m[0]) * 0.5,
            ((m[1] - m[2]) + m[0]) * 0.5,
        );
        if p.moments[0] < -tolerance {
            return Err(Error::InvalidInertia {
                name: "inertia".into(),
                reason: format!(
                    "it must be positive semidefinite, but its smallest principal moment is {}.",
                    shown(p.moments[0])
                ),
            });
        }
        if c.min() < -tolerance {
            return Err(Error::InvalidInertia {
                name: "inertia".into(),
                reason: format!(
                    "its principal moments {}, {}, {} break the triangle inequality \
                     I1 + I2 >= I3.",
                    shown(p.moments[0]),
                    shown(p.moments[1]),
                    shown(p.moments[2])
                ),
            });
        }
        // C = V diag(c) V^T = iso 1 + (D V^T)^T (D V^T), D = sqrt(c - iso).
        let second_moment = SecondMoment::principal_form(c, k, &p.axes);
        Self::new(mass, *center_of_mass, second_moment).in_range(&[("inertia", 0.0)])
    }

    /// The total mass.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The centre of mass, in body coordinates.
    pub fn center_of_mass(&self) -> Vector3<f64> {
        self.center_of_mass
    }

    /// The second-moment matrix `sum m r r^T` about the centre of mass.
    pub fn second_moment(&self) -> Matrix3<f64> {
        let (s, k) = self.second_moment.normalised();
        s.matrix().map(|x| ldexp(x, 2 * k))
    }

    /// The inertia tensor about the centre of mass, in body axes: `I = tr(C) 1 - C`.
    ///
    /// Componentwise accurate: each entry is formed from terms of one sign
    /// (`I_ii = 2 c + sum_{j != i} |F e_j|^2`, `I_ij = -(F e_i) . (F e_j)` for the second moment
    /// `c 1 + F^T F`), so a needle's or a plate's near-zero moment keeps its digits
    /// (`tr(C) - C_zz` lost them to cancellation). Formed in units of a power of two (exactly),
    /// so that no intermediate square or trace overflows or underflows where the tensor itself
    /// does not.
    pub fn inertia(&self) -> Matrix3<f64> {
        let (s, k) = self.second_moment.normalised();
        inertia_from_factor(s.isotropic, &s.factor).map(|x| ldexp(x, 2 * k))
    }

    /// The inertia tensor about `point` (body coordinates), in body axes:
    /// `I_p = I + M (|d|^2 1 - d d^T)` with `d` the centre of mass seen from `point`, each
    /// diagonal entry a sum of non-negative terms (`I_xx + M (d_y^2 + d_z^2)`), so that it is
    /// componentwise accurate like [`Self::inertia`].
    ///
    /// # Errors
    /// A coordinate of `point` that is not finite (named `point[k]`), or a tensor beyond the
    /// range of double precision (a point too far for the mass; named `point`).
    pub fn inertia_about(&self, point: &Vector3<f64>) -> Result<Matrix3<f64>> {
        finite_vector("point", point)?;
        within_range(
            "point",
            "inertia tensor about `point`",
            self.inertia_about_unchecked(point),
        )
    }

    /// The inertia tensor about `point` in the axes given by the columns of `axes` (a rotation
    /// whose columns are the new axes in body coordinates): `A^T I_p A`.
    ///
    /// The second moment's factor and the offset are rotated first (`F A`, `A^T d`) and the
    /// tensor formed from them as in [`Self::inertia_about`]: in axes where a moment is small,
    /// it is small to the rounding of the rotated factor's entries (`|F A - fl(F A)|`), not to
    /// the rounding of the whole tensor.
    ///
    /// # Errors
    /// As [`MassProperties::inertia_about`]; `axes` that are not a rotation (named `axes`).
    pub fn inertia_about_in(
        &self,
        point: &Vector3<f64>,
        axes: &Matrix3<f64>,
    ) -> Result<Matrix3<f64>> {
        finite_vector("point", point)?;
        check_rotation("axes", axes)?;
        let (s, k) = self.second_moment.normalised();
        let centre = inertia_from_factor(s.isotropic, &(s.factor * axes)).map(|x| ldexp(x, 2 * k));
        let d = axes.transpose() * self.offset_of_center(point);
        within_range(
            "point",
            "inertia tensor about `point`",
            centre + parallel_axis(self.mass, &d),
        )
    }

    /// [`MassProperties::inertia_about`] without its checks (the caller makes its own).
    pub(crate) fn inertia_about_unchecked(&self, point: &Vector3<f64>) -> Matrix3<f64> {
        let d = self.offset_of_center(point);
        self.inertia() + parallel_axis(self.mass, &d)
    }

    /// Principal moments (ascending) and axes about the centre of mass, with the default
    /// tolerance for equal moments.
    pub fn principal(&self) -> Principal {
        self.principal_unchecked(DEFAULT_RTOL)
    }

    /// Principal moments and axes; moments whose gap is at most `rtol` times the anisotropic part
    /// `tr(F^T F)` count as equal.
    ///
    /// The moments are `I_k = 2 c + sum_{j != k} s_j^2` with `s` the singular values of the
    /// factor `F` (a one-sided Jacobi SVD): no cancellation, so a needle's near-zero moment keeps
    /// its relative accuracy, and the axes are those of `F` alone, so the anisotropy of a heavy
    /// sphere plus a speck keeps its direction to round-off.
    ///
    /// Computed in units of a power of two (exactly), so that bodies from 1e-300 to 1e300 keep
    /// every digit; a body built by this crate has moments within the range of double precision
    /// (its constructors check).
    ///
    /// # Errors
    /// An `rtol` that is not finite and `>= 0` ([`Setting::MergeTolerance`], named `rtol`).
    pub fn principal_with(&self, rtol: f64) -> Result<Principal> {
        Setting::MergeTolerance.check("rtol", rtol)?;
        Ok(self.principal_unchecked(rtol))
    }

    /// [`MassProperties::principal_with`] of a tolerance known to be valid.
    fn principal_unchecked(&self, rtol: f64) -> Principal {
        let (mut p, k) = self.principal_scaled(rtol);
        p.moments = p.moments.map(|x| ldexp(x, k));
        p
    }

    /// The principal frame with the moments in units of `2^k`, and `k`.
    fn principal_scaled(&self, rtol: f64) -> (Principal, i32) {
        let (s, k) = self.second_moment.normalised();
        let (sv, axes) = eigen::right_singular(&s.factor);
        let sq = sv.map(|x| x * x);
        let iso2 = 2.0 * s.isotropic;
        let moments = [
            iso2 + (sq[1] + sq[2]),
            iso2 + (sq[0] + sq[2]),
            iso2 + (sq[0] + sq[1]),
        ];
        let p = eigen::canonical(moments, axes, rtol * (sq[0] + sq[1] + sq[2]));
        (p, 2 * k)
    }

    /// The body if every quantity it reports (mass, centre of mass, second moments, inertia
    /// tensor, principal moments) is within the range of double precision (moments below the
    /// smallest double round to 0, correctly); else an [`Error::InvalidArgument`] naming the argument of `blame`
    /// (`(name, log2 of its contribution)`) that contributes most.
    pub(crate) fn in_range(self, blame: &[(&str, f64)]) -> Result<Self> {
        match self.range_check() {
            Ok(()) => Ok(self),
            Err((kind, reason)) => Err(out_of_range(kind, reason, blame)),
        }
    }

    /// What is out of range, if anything (see [`Self::in_range`]).
    pub(crate) fn range_check(&self) -> std::result::Result<(), (OutOfRange, String)> {
        let overflow = |what: &str| {
            (
                OutOfRange::Overflow,
                format!(
                    "the {what} overflows double precision (beyond the largest double, {:e}).",
                    f64::MAX
                ),
            )
        };
        if !self.mass.is_finite() {
            return Err(overflow("mass"));
        }
        let com = self.center_of_mass + self.center_of_mass_low;
        if !com.iter().all(|x| x.is_finite()) {
            return Err(overflow("centre of mass"));
        }
        let s = &self.second_moment;
        let f = largest(s.factor.iter().copied());
        if !(f.is_finite() && s.isotropic.is_finite()) {
            return Err((
                OutOfRange::Overflow,
                format!(
                    "the moments of inertia overflow double precision (beyond the largest \
                     double, {:e}).",
                    f64::MAX
                ),
            ));
        }
        // Every reported number is at most 2 iso + ||F||^2 <= 2 iso + 9 max|F|^2: nothing to
        // compute below that.
        if s.isotropic <= 2f64.powi(1019) && f <= 2f64.powi(507) {
            return Ok(());
        }
        let (p, k) = self.principal_scaled(0.0);
        let top = p.moments.max();
        let reported = ldexp(top, k);
        let inertia = self.inertia();
        let second = self.second_moment();
        if !(reported.is_finite()
            && inertia.iter().all(|x| x.is_finite())
            && second.iter().all(|x| x.is_finite()))
        {
            return Err((
                OutOfRange::Overflow,
                format!(
                    "the moments of inertia overflow double precision (the largest is about \
                     {}, beyond the largest double, {:e}).",
                    scientific(top, k),
                    f64::MAX
                ),
            ));
        }
        Ok(())
    }

    /// The same body moved by `offset` (body coordinates).
    pub fn translated(&self, offset: &Vector3<f64>) -> Result<Self> {
        check_vector("offset", offset)?;
        let mut sum = Vector3::zeros();
        let mut error = Vector3::zeros();
        for k in 0..3 {
            (sum[k], error[k]) = two_sum(self.center_of_mass[k], offset[k]);
        }
        let (high, low) = renormalised(sum, self.center_of_mass_low + error);
        Self {
            center_of_mass: high,
            center_of_mass_low: low,
            ..*self
        }
        .in_range(&[("offset", 0.0)])
    }

    /// The same body rotated by the proper rotation `rotation` (`x_new = R x`) about the origin
    /// of the body coordinates.
    pub fn rotated(&self, rotation: &Matrix3<f64>) -> Result<Self> {
        check_rotation("rotation", rotation)?;
        let (high, low) = renormalised(
            rotation * self.center_of_mass,
            rotation * self.center_of_mass_low,
        );
        Self {
            mass: self.mass,
            center_of_mass: high,
            center_of_mass_low: low,
            second_moment: self.second_moment.rotated(rotation),
        }
        .in_range(&[("rotation", 0.0)])
    }

    /// Angular momentum `L = I w` about the centre of mass, `omega` in body axes.
    ///
    /// # Errors
    /// A component of `omega` that is not finite (named `omega[k]`), or a momentum beyond the
    /// range of double precision (named `omega`).
    pub fn angular_momentum_body(&self, omega: &Vector3<f64>) -> Result<Vector3<f64>> {
        finite_vector("omega", omega)?;
        let l = self.inertia() * omega;
        if !l.iter().all(|x| x.is_finite()) {
            return Err(overflows("omega", "angular momentum"));
        }
        Ok(l)
    }

    /// Kinetic energy of rotation `T = w . I w / 2`.
    ///
    /// Formed as `(2 c |w|^2 + sum_k |f_k x w|^2) / 2` over the rows `f_k` of the second
    /// moment's factor (`w . I w = sum_k |f_k|^2 |w|^2 - (f_k . w)^2` for `C = c 1 + F^T F`): a sum
    /// of non-negative terms, accurate to a few ulp even for a spin about a needle's axis, where
    /// `w . (I w)` kept only the rounding of the large moments.
    ///
    /// # Errors
    /// As [`MassProperties::angular_momentum_body`].
    pub fn kinetic_energy(&self, omega: &Vector3<f64>) -> Result<f64> {
        finite_vector("omega", omega)?;
        let (s, k) = self.second_moment.normalised();
        // omega in units of 2^e, its largest component in [0.5, 1): the squares are formed in
        // the normal range (an omega of 1e-158 squared to subnormals, losing hundreds of their
        // units once scaled back; one of 1e160 overflowed), and the scale is applied once, at
        // the end, exactly (a power of two), rounding only a result below the normal range.
        let e = exponent(omega.amax());
        let omega = omega.map(|x| ldexp(x, -e));
        let mut sum = 2.0 * s.isotropic * omega.norm_squared();
        for row in s.factor.row_iter() {
            sum += row.transpose().cross(&omega).norm_squared();
        }
        let energy = ldexp(sum, 2 * (k + e) - 1);
        if !energy.is_finite() {
            return Err(overflows("omega", "kinetic energy"));
        }
        Ok(energy)
    }

    /// The same body with every mass multiplied by `mass_scale` and every length by
    /// `length_scale`.
    pub fn scaled(&self, mass_scale: f64, length_scale: f64) -> Result<Self> {
        positive("mass_scale", mass_scale)?;
        positive("length_scale", length_scale)?;
        Self {
            mass: self.mass * mass_scale,
            center_of_mass: self.center_of_mass * length_scale,
            center_of_mass_low: self.center_of_mass_low * length_scale,
            second_moment: self.second_moment.scaled(mass_scale, length_scale),
        }
        .in_range(&[
            ("mass_scale", mass_scale.log2()),
            ("length_scale", 2.0 * length_scale.log2()),
        ])
    }

    /// `self + other` (see the `Add` impl), or an [`Error::InvalidArgument`] naming `other`
    /// if the composite's mass, centre or moments leave the range of double precision (`+`
    /// itself does not check).
    pub fn try_add(&self, other: &Self) -> Result<Self> {
        (self + other).in_range(&[("other", 0.0)])
    }
}

/// A composite: each part's second moment shifted to the combined centre of mass.
///
/// The shift terms of the two parts add up to one rank-one term `mu D D^T` with the reduced mass
/// `mu = m_a m_b / (m_a + m_b)` and `D` the vector between the two centres, so nothing is summed
/// about a far origin.
///
/// `+` does not check the range of double precision: a composite whose mass or moments overflow
/// comes out with infinities or NaN in them. [`MassProperties::try_add`] checks.
impl Add for MassProperties {
    type Output = MassProperties;

    fn add(self, other: MassProperties) -> MassProperties {
        let mass = self.mass + other.mass;
        let between = other.offset_of_center(&self.center_of_mass) - self.center_of_mass_low;
        let (high, low) = renormalised(
            self.center_of_mass,
            self.center_of_mass_low + between * (other.mass / mass),
        );
        let reduced = self.mass * (other.mass / mass);
        let row = between * reduced.sqrt();
        let second_moment = factor::combine(&self.second_moment, &other.second_moment, &[row]);
        MassProperties {
            mass,
            center_of_mass: high,
            center_of_mass_low: low,
            second_moment,
        }
    }
}

impl Add for &MassProperties {
    type Output = MassProperties;

    fn add(self, other: &MassProperties) -> MassProperties {
        *self + *other
    }
}

/// The inertia tensor `tr(C) 1 - C` of the second moment `C = isotropic 1 + F^T F`, each entry
/// formed from terms of one sign: `I_ii = 2 isotropic + sum_{j != i} |F e_j|^2` (non-negative
/// terms, so within `4 eps I_ii` of the value for these `isotropic` and `F`, however small
/// `I_ii` is against the trace) and `I_ij = -(F e_i) . (F e_j)` (within `3 eps |F e_i| |F e_j|
/// <= 3 eps sqrt(C_ii C_jj)`, and exactly 0 where the two columns share no non-zero row, as
/// for a body in its principal axes).
pub(crate) fn inertia_from_factor(isotropic: f64, factor: &Matrix3<f64>) -> Matrix3<f64> {
    let squares = Vector3::from_fn(|j, _| factor.column(j).norm_squared());
    let iso2 = 2.0 * isotropic;
    let mut i = Matrix3::from_diagonal(&Vector3::new(
        iso2 + (squares[1] + squares[2]),
        iso2 + (squares[0] + squares[2]),
        iso2 + (squares[0] + squares[1]),
    ));
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let product = -factor.column(a).dot(&factor.column(b));
        i[(a, b)] = product;
        i[(b, a)] = product;
    }
    i
}

/// `m (|d|^2 1 - d d^T)`, the parallel-axis term, with each diagonal entry `m (d_j^2 + d_k^2)`
/// formed from its own two squares (not `|d|^2 - d_i^2`, which cancels for `d` along an axis).
fn parallel_axis(mass: f64, d: &Vector3<f64>) -> Matrix3<f64> {
    let sq = d.component_mul(d);
    let mut p = Matrix3::from_diagonal(&Vector3::new(sq[1] + sq[2], sq[0] + sq[2], sq[0] + sq[1]));
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        p[(a, b)] = -(d[a] * d[b]);
        p[(b, a)] = p[(a, b)];
    }
    p * mass
}

fn check_vector(name: &str, v: &Vector3<f64>) -> Result<()> {
    for k in 0..3 {
        if !v[k].is_finite() {
            finite(&format!("{name}[{k}]"), v[k])?;
        }
    }
    Ok(())
}

/// Checks that every component of `v` is finite, naming `name[k]`.
fn finite_vector(name: &str, v: &Vector3<f64>) -> Result<()> {
    for k in 0..3 {
        if !v[k].is_finite() {
            finite(&format!("{name}[{k}]"), v[k])?;
        }
    }
    Ok(())
}

/// The error of a result (`what`, of the argument `name`) beyond the range of double
/// precision.
fn overflows(name: &str, what: &str) -> Error {
    Error::InvalidArgument {
        name: name.into(),
        reason: format!(
            "the {what} overflows double precision (beyond the largest double, {:e}).",
            f64::MAX
        ),
    }
}

/// `m` if every entry is finite, else the error of [`overflows`].
fn within_range(name: &str, what: &str, m: Matrix3<f64>) -> Result<Matrix3<f64>> {
    if m.iter().all(|x| x.is_finite()) {
        Ok(m)
    } else {
        Err(overflows(name, what))
    }
}

/// A proper rotation: finite, orthogonal and with det = +1, each to `1e-9` (a rotation typed
/// with ten digits passes; a scaled or reflected matrix does not).
pub fn check_rotation(name: &str, r: &Matrix3<f64>) -> Result<()> {
    for row in 0..3 {
        for col in 0..3 {
            if !r[(row, col)].is_finite() {
                finite(&format!("{name}[{row}, {col}]"), r[(row, col)])?;
            }
        }
    }
    let defect = (r.transpose() * r - Matrix3::identity()).norm();
    if defect > 1e-9 {
        return Err(Error::InvalidArgument {
            name: name.into(),
            reason: format!("expected an orthogonal matrix, but |R^T R - 1| = {defect:e}."),
        });
    }
    if r.determinant() < 0.0 {
        return Err(Error::InvalidArgument {
            name: name.into(),
            reason: "expected a proper rotation (det = +1), got a reflection (det = -1).".into(),
        });
    }
    Ok(())
}
