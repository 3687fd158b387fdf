//! Bodies from closed triangle meshes: exact integrals over signed tetrahedra (or, for a thin
//! shell, over the triangles themselves).
//!
//! Each outward-wound triangle `(a, b, c)` spans a signed tetrahedron with a reference point `p`
//! near the mesh (the vertex mean, never a far origin); with `a, b, c` taken relative to `p`,
//! its volume is `det / 6` (`det = a . (b x c)`), its first moment `det (a + b + c) / 24` and its
//! second moment `det (a a^T + b b^T + c c^T + s s^T) / 120` with `s = a + b + c` (Tonon 2004;
//! Eberly, "Polyhedral mass properties (revisited)"). A triangle of area `A` carries
//! `A (a + b + c) / 3` and `A (a a^T + b b^T + c c^T + s s^T) / 12`. The vertices are taken
//! relative to `p` once, then the triangles run four at a time in vectorised lanes
//! (`crate::simd::dispatch`). The sums are compensated (plain sums over blocks of 16 triangles
//! per lane, the blocks added with TwoSum, fixed chunks combined in parallel and then in order,
//! lane by lane), and the shift from `p` to the centre of mass is small: a mesh 1e8 away from
//! the origin keeps its digits (docs/architecture.md, Numerics). The check that a solid mesh is
//! closed and consistently wound (`super::topology`: vertices at the same position, or within
//! `2^-40` of the mesh's size, are one vertex there) runs beside the integration
//! (`rayon::join`); the integrals use the vertices as given.

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::factor::SecondMoment;
use super::{invalid, look, out_of_range, renormalised, two_sum, MassProperties, OutOfRange};
use crate::eigen::{self, exponent, ldexp, scientific};
use crate::error::{positive, Error, Result};
use crate::memory::{self, Purpose};
use crate::Monitor;

/// Triangles per parallel chunk of the integrals (a multiple of `LANES * BLOCK`): the chunks
/// are fixed, whatever the number of threads.
const CHUNK: usize = 1 << 12;

/// Triangles side by side in the vectorised kernel (one per lane).
const LANES: usize = 4;

/// Triangles summed plainly in each lane before a compensated add.
const BLOCK: usize = 16;

/// One value per lane.
type Lanes = [f64; LANES];

/// `TwoSum`, inlined into the vectorised kernel.
#[inline(always)]
fn two_sum_inline(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The ten integrals `[w, w s, w q]` (weight, first moment, second moment xx yy zz xy xz yz)
/// as compensated sums `hi + lo`, plus `sum |w|` (the scale for the zero-volume test).
#[derive(Clone, Copy)]
struct Sums {
    hi: [f64; 10],
    lo: [f64; 10],
    abs_weight: f64,
}

impl Sums {
    const ZERO: Self = Self {
        hi: [0.0; 10],
        lo: [0.0; 10],
        abs_weight: 0.0,
    };

    fn merge(mut self, other: Self) -> Self {
        for k in 0..10 {
            let (s, e) = two_sum(self.hi[k], other.hi[k]);
            self.hi[k] = s;
            self.lo[k] += other.lo[k] + e;
        }
        self.abs_weight += other.abs_weight;
        self
    }

    fn value(&self) -> [f64; 10] {
        std::array::from_fn(|k| self.hi[k] + self.lo[k])
    }
}

/// [`Sums`] per lane: lane `l` holds the triangles `LANES j + l` of a chunk.
#[derive(Clone, Copy)]
struct LaneSums {
    hi: [Lanes; 10],
    lo: [Lanes; 10],
    abs_weight: Lanes,
}

impl LaneSums {
    const ZERO: Self = Self {
        hi: [[0.0; LANES]; 10],
        lo: [[0.0; LANES]; 10],
        abs_weight: [0.0; LANES],
    };

    /// Adds a block's plain sums `local` (the ten terms, then `sum |w|`) with TwoSum, lane by
    /// lane.
    #[inline(always)]
    fn add(&mut self, local: &[Lanes; 11]) {
        for ((hi, lo), terms) in self.hi.iter_mut().zip(&mut self.lo).zip(local) {
            for ((hi, lo), &t) in hi.iter_mut().zip(lo.iter_mut()).zip(terms) {
                let (s, e) = two_sum_inline(*hi, t);
                *hi = s;
                *lo += e;
            }
        }
        for (sum, &t) in self.abs_weight.iter_mut().zip(&local[10]) {
            *sum += t;
        }
    }

    /// Lane `l` as [`Sums`].
    fn lane(&self, l: usize) -> Sums {
        Sums {
            hi: std::array::from_fn(|k| self.hi[k][l]),
            lo: std::array::from_fn(|k| self.lo[k][l]),
            abs_weight: self.abs_weight[l],
        }
    }
}

/// The corners `a, b, c` of `LANES` triangles, coordinate by coordinate: `p[corner][axis][lane]`.
type Corners = [[Lanes; 3]; 3];

/// Adds `w [1, s, q]` and `|w|` of `LANES` triangles to `local`, lane by lane: `w` is the
/// determinant `a . (b x c)` (six times the signed volume of the tetrahedron `0, a, b, c`) or,
/// for a shell, `|(b - a) x (c - a)|` (twice the area), `s = a + b + c` and
/// `q = a a^T + b b^T + c c^T + s s^T` (upper triangle: xx yy zz xy xz yz).
#[inline(always)]
fn accumulate<const SHELL: bool>(p: &Corners, local: &mut [Lanes; 11]) {
    let [a, b, c] = p;
    for l in 0..LANES {
        let (ax, ay, az) = (a[0][l], a[1][l], a[2][l]);
        let (bx, by, bz) = (b[0][l], b[1][l], b[2][l]);
        let (cx, cy, cz) = (c[0][l], c[1][l], c[2][l]);
        let w = if SHELL {
            let (ux, uy, uz) = (bx - ax, by - ay, bz - az);
            let (vx, vy, vz) = (cx - ax, cy - ay, cz - az);
            let (nx, ny, nz) = (uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
            (nx * nx + ny * ny + nz * nz).sqrt()
        } else {
            ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
        };
        let s = [ax + bx + cx, ay + by + cy, az + bz + cz];
        let q = |i: usize, j: usize| {
            a[i][l] * a[j][l] + b[i][l] * b[j][l] + c[i][l] * c[j][l] + s[i] * s[j]
        };
        let terms = [
            w,
            w * s[0],
            w * s[1],
            w * s[2],
            w * q(0, 0),
            w * q(1, 1),
            w * q(2, 2),
            w * q(0, 1),
            w * q(0, 2),
            w * q(1, 2),
            w.abs(),
        ];
        for (sum, t) in local.iter_mut().zip(terms) {
            sum[l] += t;
        }
    }
}

/// The corners of the triangles `row` (at most `LANES`; missing lanes at the origin, which adds
/// nothing) gathered from `points`.
#[inline(always)]
fn gather(points: &[[f64; 3]], row: &[[i64; 3]]) -> Corners {
    let mut p = [[[0.0; LANES]; 3]; 3];
    if let Ok(row) = <&[[i64; 3]; LANES]>::try_from(row) {
        for (l, f) in row.iter().enumerate() {
            for (corner, &index) in f.iter().enumerate() {
                let v = points[index as usize];
                for axis in 0..3 {
                    p[corner][axis][l] = v[axis];
                }
            }
        }
    } else {
        for (l, f) in row.iter().enumerate() {
            for (corner, &index) in f.iter().enumerate() {
                let v = points[index as usize];
                for axis in 0..3 {
                    p[corner][axis][l] = v[axis];
                }
            }
        }
    }
    p
}

/// The lane sums of one chunk of triangles (corners indexing `points`): plain sums over
/// blocks of `BLOCK` triangles per lane (error ~ `BLOCK` eps of the block's own terms), the
/// blocks added with TwoSum. The same IEEE operations in the same order on every CPU (no FMA).
#[inline(always)]
fn chunk_sums<const SHELL: bool>(points: &[[f64; 3]], faces: &[[i64; 3]]) -> LaneSums {
    let mut sums = LaneSums::ZERO;
    for block in faces.chunks(LANES * BLOCK) {
        let mut local = [[0.0; LANES]; 11];
        for row in block.chunks(LANES) {
            accumulate::<SHELL>(&gather(points, row), &mut local);
        }
        sums.add(&local);
    }
    sums
}

/// Whether any entry of `values` is infinite or NaN (its exponent bits all set), without a
/// branch per entry.
#[inline(always)]
fn any_non_finite(values: &[f64]) -> bool {
    const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
    values.iter().fold(0u64, |bad, x| {
        bad | u64::from(x.to_bits() & EXPONENT == EXPONENT)
    }) != 0
}

/// Whether any triangle of `faces` has an index outside `0..n` or (`solid`) repeats a vertex,
/// without a branch per triangle.
#[inline(always)]
fn any_bad_face(faces: &[[i64; 3]], n: u64, solid: bool) -> bool {
    faces.iter().fold(0u64, |bad, f| {
        let range = f.iter().fold(0u64, |r, &i| r | u64::from(i as u64 >= n));
        let repeat = u64::from(f[0] == f[1]) | u64::from(f[1] == f[2]) | u64::from(f[2] == f[0]);
        bad | range | (repeat & u64::from(solid))
    }) != 0
}

/// Every vertex finite, every index in range (and, for a solid, no face repeating a vertex).
fn check_input(vertices: &[[f64; 3]], faces: &[[i64; 3]], shell: bool) -> Result<()> {
    // A parallel scan for the first chunk with a bad row, then the message for its first.
    let first_bad_chunk = vertices
        .par_chunks(CHUNK)
        .position_first(|chunk| {
            crate::simd::dispatch(
                #[inline(always)]
                || any_non_finite(chunk.as_flattened()),
            )
        })
        .unwrap_or(vertices.len().div_ceil(CHUNK));
    for (i, v) in vertices.iter().enumerate().skip(first_bad_chunk * CHUNK) {
        for (k, &x) in v.iter().enumerate() {
            if !x.is_finite() {
                return Err(Error::NonFinite {
                    name: format!("vertices[{i}, {k}]"),
                    value: x,
                });
            }
        }
    }
    let minimum = if shell { 1 } else { 4 };
    if faces.len() < minimum {
        return Err(invalid(
            "faces",
            format!(
                "expected at least {minimum} triangles{}, got {}.",
                if shell { "" } else { " (a closed mesh)" },
                faces.len()
            ),
        ));
    }
    if faces.len() > (u32::MAX / 3) as usize {
        return Err(invalid(
            "faces",
            format!("expected at most 2^32 / 3 triangles, got {}.", faces.len()),
        ));
    }
    let n = vertices.len();
    if n > i32::MAX as usize {
        return Err(invalid(
            "vertices",
            format!("expected at most 2^31 - 1 vertices, got {n}."),
        ));
    }
    let first_bad_chunk = faces
        .par_chunks(CHUNK)
        .position_first(|chunk| {
            crate::simd::dispatch(
                #[inline(always)]
                || any_bad_face(chunk, n as u64, !shell),
            )
        })
        .unwrap_or(faces.len().div_ceil(CHUNK));
    for (i, f) in faces.iter().enumerate().skip(first_bad_chunk * CHUNK) {
        for (k, &index) in f.iter().enumerate() {
            if index < 0 || index as u64 >= n as u64 {
                return Err(invalid(
                    format!("faces[{i}, {k}]"),
                    format!(
                        "vertex index {index} is out of range for {n} vertices (expected 0 <= \
                         index < {n})."
                    ),
                ));
            }
        }
        if !shell && (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) {
            return Err(invalid(
                format!("faces[{i}]"),
                format!(
                    "the triangle {:?} repeats a vertex (a degenerate face in a closed mesh).",
                    f
                ),
            ));
        }
    }
    Ok(())
}

/// The compensated sums over all triangles, about the mean of the vertices they use, in units
/// of `2^k`, with that reference point and `k` (vertices are taken as `(v - reference) 2^-k`,
/// of size at most 1 for those the faces use); `None` if those span more than the range of
/// double precision. Looks at `monitor` before each chunk of triangles.
///
/// Every parallel sum is a fixed tree: per chunk of [`CHUNK`] items (and per lane within a
/// chunk), the chunks' sums then added in order on one thread, lane by lane, and the lanes
/// last, so the result does not depend on the number of threads.
fn integrate(
    vertices: &[[f64; 3]],
    faces: &[[i64; 3]],
    shell: bool,
    monitor: Option<&Monitor>,
) -> Result<Option<(Sums, Vector3<f64>, i32)>> {
    // The reference point: the mean of the vertices the faces use, summed relative to one of
    // them, in units of their extent (so that neither the differences nor their sum overflow).
    // A vertex no face uses (common in files) must not move the reference or the scale: one
    // unused vertex at 1e8 moved the centre of mass of a unit cube by 3e-3.
    let mut used = memory::zeros::<bool>(vertices.len(), Purpose::Mesh)?;
    for f in faces {
        for &i in f {
            used[i as usize] = true;
        }
    }
    let anchor = Vector3::from(vertices[faces[0][0] as usize]);
    let (extent, count) = vertices
        .par_chunks(CHUNK)
        .zip(used.par_chunks(CHUNK))
        .map(|(chunk, used)| {
            chunk
                .iter()
                .zip(used)
                .fold((0.0_f64, 0usize), |(m, n), (v, u)| {
                    if *u {
                        let m = (0..3).fold(m, |m, k| m.max((v[k] - anchor[k]).abs()));
                        (m, n + 1)
                    } else {
                        (m, n)
                    }
                })
        })
        .reduce(|| (0.0, 0), |a, b| (a.0.max(b.0), a.1 + b.1));
    if !extent.is_finite() {
        return Ok(None);
    }
    let e = exponent(extent);
    let spreads = vertices
        .par_chunks(CHUNK)
        .zip(used.par_chunks(CHUNK))
        .map(|(chunk, used)| {
            chunk
                .iter()
                .zip(used)
                .fold(Vector3::zeros(), |acc, (v, u)| {
                    if *u {
                        acc + (Vector3::from(*v) - anchor).map(|x| ldexp(x, -e))
                    } else {
                        acc
                    }
                })
        });
    let spreads = memory::collect_parallel(spreads, Purpose::Mesh)?;
    let spread = spreads.iter().fold(Vector3::zeros(), |acc, s| acc + s);
    let reference = anchor + (spread / count as f64).map(|x| ldexp(x, e));
    // |v - reference| <= 2 extent: vertices in units of 2^k have entries of size <= 1.
    let k = e + 1;
    let reference_scaled = reference.map(|x| ldexp(x, -k));

    // Every vertex as `v 2^-k - reference 2^-k`, once (`ldexp(x, -k)` is `x` times two exact
    // powers of two: the same product here).
    let clamped = (-k).clamp(-2044, 2046);
    let (p1, p2) = (ldexp(1.0, clamped / 2), ldexp(1.0, clamped - clamped / 2));
    let r = [
        reference_scaled[0],
        reference_scaled[1],
        reference_scaled[2],
    ];
    let mut points = memory::zeros::<[f64; 3]>(vertices.len(), Purpose::Mesh)?;
    points
        .par_chunks_mut(CHUNK)
        .zip(vertices.par_chunks(CHUNK))
        .for_each(|(points, vertices)| {
            crate::simd::dispatch(
                #[inline(always)]
                || {
                    for (p, v) in points.iter_mut().zip(vertices) {
                        for axis in 0..3 {
                            p[axis] = v[axis] * p1 * p2 - r[axis];
                        }
                    }
                },
            );
        });

    let chunks = faces.par_chunks(CHUNK).map(|chunk| {
        look(monitor)?;
        Ok(if shell {
            crate::simd::dispatch(
                #[inline(always)]
                || chunk_sums::<true>(&points, chunk),
            )
        } else {
            crate::simd::dispatch(
                #[inline(always)]
                || chunk_sums::<false>(&points, chunk),
            )
        })
    });
    let chunks: Vec<Result<LaneSums>> = memory::collect_parallel(chunks, Purpose::Mesh)?;
    // The chunks in order, lane by lane; then the lanes in order.
    let mut lanes = [Sums::ZERO; LANES];
    for chunk in chunks {
        let chunk = chunk?;
        for (l, lane) in lanes.iter_mut().enumerate() {
            *lane = lane.merge(chunk.lane(l));
        }
    }
    let sums = lanes.into_iter().fold(Sums::ZERO, Sums::merge);
    Ok(Some((sums, reference, k)))
}

/// `x` as `(f, e)` with `x = f 2^e` and `0.5 <= |f| < 1` (0 as `(0, 0)`).
fn split(x: f64) -> (f64, i32) {
    let e = exponent(x);
    (ldexp(x, -e), e)
}

impl MassProperties {
    /// A uniform body bounded by a closed triangle mesh, or (`shell = true`) a thin shell of
    /// uniform surface density on any triangle mesh.
    ///
    /// `vertices` are points in body coordinates and `faces` index triples into them, wound
    /// counter-clockwise seen from outside (the right-hand normal points out). Exactly one of
    /// `density` (mass per volume, or per area for a shell) and `mass` is given.
    ///
    /// A solid mesh must be closed and consistently wound: every directed edge `u -> v` used by
    /// exactly one face and `v -> u` by exactly one other, where vertices at the same position,
    /// or within [`weld_tolerance`](super::weld_tolerance) (`2^-40` of the bounding-box
    /// diagonal) of each other, count as one vertex (files repeat vertices, and exporters write
    /// a 0 as 3e-17); the integrals use the vertices as given. Nested closed shells (a hollow body,
    /// the cavity wound inward) add with their signs. A negative total volume (an inside-out
    /// mesh) is an error unless `fix_winding` is set, which reverses every face. A shell needs
    /// neither closedness nor consistent winding.
    ///
    /// The integrals are exact for the polyhedron (Tonon 2004; Eberly), taken about the vertex
    /// mean with compensated sums, so a mesh far from the origin keeps its digits.
    ///
    /// ```
    /// use polhode::MassProperties;
    /// // The unit cube [0, 1]^3 as 12 outward triangles, density 1: I = 1/6 about its centre.
    /// let v = [
    ///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
    ///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
    /// ];
    /// let f = [
    ///     [0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
    ///     [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7],
    /// ];
    /// let cube = MassProperties::mesh(&v, &f, Some(1.0), None, false, false).unwrap();
    /// assert!((cube.mass() - 1.0).abs() < 1e-15);
    /// assert!((cube.principal().moments[0] - 1.0 / 6.0).abs() < 1e-15);
    /// ```
    pub fn mesh(
        vertices: &[[f64; 3]],
        faces: &[[i64; 3]],
        density: Option<f64>,
        mass: Option<f64>,
        shell: bool,
        fix_winding: bool,
    ) -> Result<Self> {
        Self::mesh_monitored(vertices, faces, density, mass, shell, fix_winding, None)
    }

    /// [`mesh`](Self::mesh) watched by `monitor`: a look ([`Monitor::look`]) before each block
    /// of [`MESH_CHUNK`](super::MESH_CHUNK) triangles of the closedness check and each chunk of
    /// the integrals, so that a cancelled monitor stops the work within a block, with
    /// [`Error::Interrupted`]. The result does not depend on the monitor.
    pub fn mesh_monitored(
        vertices: &[[f64; 3]],
        faces: &[[i64; 3]],
        density: Option<f64>,
        mass: Option<f64>,
        shell: bool,
        fix_winding: bool,
        monitor: Option<&Monitor>,
    ) -> Result<Self> {
        check_density_or_mass(density, mass)?;
        check_input(vertices, faces, shell)?;
        let (closed, integrated) = rayon::join(
            || {
                if shell {
                    Ok(())
                } else {
                    super::topology::check_closed(vertices, faces, monitor)
                }
            },
            || integrate(vertices, faces, shell, monitor),
        );
        closed?;
        let integrated = integrated?;
        // Which argument drives the size of the result (log2 of its contribution), for an
        // error: the mass or density, or the vertices' extent (to the fifth power with a
        // density, the second with a mass).
        let blame = |k: i32| -> [(&'static str, f64); 2] {
            match (density, mass) {
                (Some(d), _) => [("density", d.log2()), ("vertices", 5.0 * f64::from(k))],
                (_, m) => [
                    ("mass", m.unwrap_or(1.0).log2()),
                    ("vertices", 2.0 * f64::from(k)),
                ],
            }
        };
        let Some((sums, reference, k)) = integrated else {
            return Err(out_of_range(
                OutOfRange::Overflow,
                format!(
                    "the mesh spans more than the range of double precision ({:e}).",
                    f64::MAX
                ),
                &[("vertices", 0.0)],
            ));
        };

        let t = oriented_integrals(&sums, k, shell, fix_winding)?;
        // (weight -> measure, first, second) divisors: volume 6, 24, 120; area 2, 6, 24.
        let (d0, d1, d2) = if shell {
            (2.0, 6.0, 24.0)
        } else {
            (6.0, 24.0, 120.0)
        };
        let dimension = if shell { 2 } else { 3 };
        let measure = t[0] / d0;
        let first = Vector3::new(t[1], t[2], t[3]) / d1;
        let q = |k: usize| t[k] / d2;
        let about_reference = Matrix3::new(q(4), q(7), q(8), q(7), q(5), q(9), q(8), q(9), q(6));
        // The density as rho_f 2^rho_e, kept apart so that neither the mass nor the moments
        // overflow on the way where the result does not.
        let (rho_f, rho_e) = match (density, mass) {
            (Some(d), _) => split(d),
            (_, Some(m)) => {
                let (m_f, m_e) = split(m);
                let (r_f, r_e) = split(m_f / measure);
                (r_f, r_e + m_e - dimension * k)
            }
            _ => unreachable!("checked above"),
        };
        let body_mass = match (density, mass) {
            (_, Some(m)) => m,
            _ => ldexp(rho_f * measure, rho_e + dimension * k),
        };
        if !body_mass.is_finite() || body_mass == 0.0 {
            let kind = if body_mass == 0.0 {
                OutOfRange::Underflow
            } else {
                OutOfRange::Overflow
            };
            let (f, e) = split(rho_f * measure);
            let about = scientific(f, e + rho_e + dimension * k);
            let reason = if kind == OutOfRange::Overflow {
                format!(
                    "the mass overflows double precision (it is about {about}, beyond the \
                     largest double, {:e}).",
                    f64::MAX
                )
            } else {
                format!(
                    "the mass underflows double precision (it is about {about}, below the \
                     smallest double, {:e}).",
                    f64::from_bits(1)
                )
            };
            return Err(out_of_range(kind, reason, &blame(k)[..]));
        }
        // About the centre of mass: P - V c c^T with c = S / V, a small shift.
        let shift = first / measure;
        let centred = about_reference - first * shift.transpose();
        let centred = (centred + centred.transpose()) * (0.5 * rho_f);
        // Into the square-root form as from_inertia does: C = V diag(c) V^T, here in units of
        // 2^(kk + (dimension + 2) k + rho_e).
        let (p, kk) = eigen::eigen_symmetric_scaled(&centred, 0.0);
        let second_moment =
            SecondMoment::principal_form(p.moments, kk + (dimension + 2) * k + rho_e, &p.axes);
        let shift = shift.map(|x| ldexp(x, k));
        let (center_of_mass, center_of_mass_low) = renormalised(reference, shift);
        Self {
            mass: body_mass,
            center_of_mass,
            center_of_mass_low,
            second_moment,
        }
        .in_range(&blame(k)[..])
    }
}

/// Exactly one of `density` and `mass`, positive.
fn check_density_or_mass(density: Option<f64>, mass: Option<f64>) -> Result<()> {
    match (density, mass) {
        (Some(d), None) => {
            positive("density", d)?;
        }
        (None, Some(m)) => {
            positive("mass", m)?;
        }
        (d, _) => {
            return Err(invalid(
                if d.is_some() { "density" } else { "mass" },
                format!(
                    "give exactly one of `density` and `mass`, got {}.",
                    if d.is_some() { "both" } else { "neither" }
                ),
            ))
        }
    }
    Ok(())
}

/// The integrals of a mesh (`sums`, lengths in units of `2^k`) as values, the volume
/// positive: an error for integrals that overflow, a degenerate mesh, or a mesh inside out
/// (unless `fix_winding`, which turns it the right way out).
fn oriented_integrals(sums: &Sums, k: i32, shell: bool, fix_winding: bool) -> Result<[f64; 10]> {
    // In units of 2^k for lengths: volume 2^3k (area 2^2k), first moment one more k, second
    // two more.
    let mut t = sums.value();
    if !t.iter().all(|x| x.is_finite()) {
        return Err(invalid(
            "vertices",
            "the mesh integrals overflow double precision.".into(),
        ));
    }
    // The weight's divisor: volume 6, area 2.
    let d0 = if shell { 2.0 } else { 6.0 };
    let dimension = if shell { 2 } else { 3 };
    let what = if shell { "area" } else { "volume" };
    let shown = |x: f64| {
        let v = ldexp(x, dimension * k);
        if v.is_finite() && v != 0.0 {
            format!("{v:e}")
        } else {
            scientific(x, dimension * k)
        }
    };
    if t[0].abs() <= 64.0 * f64::EPSILON * sums.abs_weight || t[0] == 0.0 {
        return Err(invalid(
            "vertices",
            format!(
                "the mesh is degenerate: its total {what} {} is zero to rounding.",
                shown(t[0] / d0)
            ),
        ));
    }
    if t[0] < 0.0 {
        if !fix_winding {
            return Err(invalid(
                "faces",
                format!(
                    "the mesh is inside out (total volume {} < 0): its faces wind \
                         clockwise seen from outside. Reverse every face (faces[:, ::-1]) or \
                         pass fix_winding=True.",
                    shown(t[0] / d0)
                ),
            ));
        }
        for x in &mut t {
            *x = -*x;
        }
    }
    Ok(t)
}
