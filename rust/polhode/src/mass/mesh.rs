//! Bodies from closed triangle meshes: exact integrals over signed tetrahedra (or, for a thin
//! shell, over the triangles themselves).
//!
//! Each outward-wound triangle `(a, b, c)` spans a signed tetrahedron with a reference point `p`
//! near the mesh (the vertex mean, never a far origin); with `a, b, c` taken relative to `p`,
//! its volume is `det / 6` (`det = a . (b x c)`), its first moment `det (a + b + c) / 24` and its
//! second moment `det (a a^T + b b^T + c c^T + s s^T) / 120` with `s = a + b + c` (Tonon 2004;
//! Eberly, "Polyhedral mass properties (revisited)"). A triangle of area `A` carries
//! `A (a + b + c) / 3` and `A (a a^T + b b^T + c c^T + s s^T) / 12`. The sums are compensated
//! (plain sums over blocks of 16 triangles, the blocks added with TwoSum, chunks combined in
//! parallel), and the shift from `p` to the centre of mass is small: a mesh 1e8 away from the
//! origin keeps its digits (docs/architecture.md, Numerics). The check that a solid mesh is
//! closed and consistently wound runs beside the integration (`rayon::join`).

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use super::factor::SecondMoment;
use super::{out_of_range, renormalised, two_sum, MassProperties, OutOfRange};
use crate::dynamics::Monitor;
use crate::eigen::{self, exponent, ldexp, scientific};
use crate::error::{positive, Error, Result};

/// Triangles per parallel chunk of the integrals.
const CHUNK: usize = 1 << 12;

/// Triangles (or vertices) between two looks at the monitor in
/// [`MassProperties::mesh_monitored`] (a millisecond or less of work): a mesh of more than two
/// such blocks is worth watching.
pub const MESH_CHUNK: usize = 1 << 16;

/// A look at `monitor`, if any.
fn look(monitor: Option<&Monitor>) -> Result<()> {
    monitor.map_or(Ok(()), Monitor::look)
}

/// Triangles summed plainly before a compensated add.
const BLOCK: usize = 16;

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

    /// Adds a block's plain sums `terms` (and its `sum |w|`) with TwoSum.
    #[inline]
    fn add(&mut self, terms: &[f64; 10], abs_weight: f64) {
        for ((hi, lo), &t) in self.hi.iter_mut().zip(&mut self.lo).zip(terms) {
            let (s, e) = two_sum(*hi, t);
            *hi = s;
            *lo += e;
        }
        self.abs_weight += abs_weight;
    }

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

/// `w [1, s, q]` for a simplex with vertices `0, a, b, c` (or `a, b, c`), `s = a + b + c`,
/// `q = a a^T + b b^T + c c^T + s s^T` (upper triangle).
#[inline]
fn terms(w: f64, a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> [f64; 10] {
    let s = a + b + c;
    let q = |i: usize, j: usize| a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j];
    [
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
    ]
}

fn invalid(name: impl Into<String>, reason: String) -> Error {
    Error::InvalidArgument {
        name: name.into(),
        reason,
    }
}

/// Every vertex finite, every index in range (and, for a solid, no face repeating a vertex).
fn check_input(vertices: &[[f64; 3]], faces: &[[i64; 3]], shell: bool) -> Result<()> {
    // A parallel scan for the first bad row, then the message for it.
    let first_bad_vertex = vertices
        .par_iter()
        .with_min_len(CHUNK)
        .position_first(|v| !v.iter().all(|x| x.is_finite()))
        .unwrap_or(vertices.len());
    for (i, v) in vertices.iter().enumerate().skip(first_bad_vertex) {
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
    let bad_face = |f: &[i64; 3]| {
        f.iter().any(|&index| index < 0 || index as u64 >= n as u64)
            || (!shell && (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]))
    };
    let first_bad_face = faces
        .par_iter()
        .with_min_len(CHUNK)
        .position_first(bad_face)
        .unwrap_or(faces.len());
    for (i, f) in faces.iter().enumerate().skip(first_bad_face) {
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

/// A closed, consistently wound mesh: every directed edge `u -> v` is used by exactly one face
/// and its reverse `v -> u` by exactly one other.
///
/// Each directed edge is filed under its smaller vertex `min(u, v)` as `max(u, v)` plus one bit
/// for its direction (a counting sort, O(faces + vertices)); each small bucket is then sorted and
/// must consist of pairs `(w, forward), (w, backward)`. Faces repeat no vertex and indices are in
/// range (checked before).
fn check_closed(faces: &[[i64; 3]], vertex_count: usize, monitor: Option<&Monitor>) -> Result<()> {
    let edges = |f: &[i64; 3]| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])];
    let mut offsets = vec![0u32; vertex_count + 1];
    for block in faces.chunks(MESH_CHUNK) {
        look(monitor)?;
        for f in block {
            for (u, v) in edges(f) {
                offsets[u.min(v) as usize + 1] += 1;
            }
        }
    }
    for i in 0..vertex_count {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut entries = vec![0u32; 3 * faces.len()];
    for block in faces.chunks(MESH_CHUNK) {
        look(monitor)?;
        for f in block {
            for (u, v) in edges(f) {
                let slot = &mut cursor[u.min(v) as usize];
                entries[*slot as usize] = ((u.max(v) as u32) << 1) | u32::from(u > v);
                *slot += 1;
            }
        }
    }
    drop(cursor);
    // Disjoint ranges of vertices (with their entries), checked in parallel.
    let ranges = 4 * rayon::current_num_threads().max(1);
    let step = vertex_count.div_ceil(ranges).max(1);
    let mut parts: Vec<(usize, &mut [u32])> = Vec::with_capacity(ranges);
    let mut rest: &mut [u32] = &mut entries;
    let mut first = 0;
    while first < vertex_count {
        let last = (first + step).min(vertex_count);
        let len = (offsets[last] - offsets[first]) as usize;
        let (part, tail) = rest.split_at_mut(len);
        parts.push((first, part));
        rest = tail;
        first = last;
    }
    // Per range: the first directed edge used twice, and the first edge without its reverse.
    type Found = (Option<(u64, u64)>, Option<(u64, u64)>);
    let found: Vec<Result<Found>> = parts
        .into_par_iter()
        .map(|(first, part)| {
            let (mut repeated, mut unpaired) = (None, None);
            let mut start = 0usize;
            let base = offsets[first] as usize;
            let mut u = first;
            while start < part.len() {
                if (u - first) % MESH_CHUNK == 0 {
                    look(monitor)?;
                }
                let end = offsets[u + 1] as usize - base;
                let bucket = &mut part[start..end];
                bucket.sort_unstable();
                let directed = |key: u32| {
                    let (w, backward) = (u64::from(key >> 1), key & 1 == 1);
                    if backward {
                        (w, u as u64)
                    } else {
                        (u as u64, w)
                    }
                };
                let mut i = 0;
                while i < bucket.len() {
                    let key = bucket[i];
                    let paired = i + 1 < bucket.len() && bucket[i + 1] == key ^ 1 && key & 1 == 0;
                    if i + 1 < bucket.len() && bucket[i + 1] == key {
                        repeated = repeated.or(Some(directed(key)));
                    }
                    if paired {
                        i += 2;
                        // A third use of the same undirected edge repeats one direction.
                        if i < bucket.len() && bucket[i] >> 1 == key >> 1 {
                            repeated = repeated.or(Some(directed(bucket[i])));
                        }
                    } else {
                        if !(i + 1 < bucket.len() && bucket[i + 1] >> 1 == key >> 1) {
                            unpaired = unpaired.or(Some(directed(key)));
                        }
                        i += 1;
                    }
                }
                if repeated.is_some() {
                    break;
                }
                start = end;
                u += 1;
            }
            Ok((repeated, unpaired))
        })
        .collect();
    let found = found.into_iter().collect::<Result<Vec<Found>>>()?;
    if let Some((u, v)) = found.iter().find_map(|f| f.0) {
        return Err(invalid(
            "faces",
            format!(
                "the directed edge {u} -> {v} is used by more than one face: the winding is \
                 inconsistent (a flipped face) or the edge is shared by more than two faces \
                 (a non-manifold mesh). Every edge must be traversed once in each direction."
            ),
        ));
    }
    if let Some((u, v)) = found.iter().find_map(|f| f.1) {
        return Err(invalid(
            "faces",
            format!(
                "the mesh is not closed: the edge {u} -> {v} has no face traversing it back \
                 ({v} -> {u}), a hole or a boundary. Use shell=True for an open surface."
            ),
        ));
    }
    Ok(())
}

/// The compensated sums over all triangles, about the vertex mean, in units of `2^k`, with
/// that reference point and `k` (vertices are taken as `(v - reference) 2^-k`, of size at most
/// 1); `None` if the vertices span more than the range of double precision. Looks at `monitor`
/// before each chunk of triangles.
///
/// Every parallel sum is a fixed tree: per chunk of [`CHUNK`] items, the chunks' sums then added
/// in order on one thread, so the result does not depend on the number of threads.
fn integrate(
    vertices: &[[f64; 3]],
    faces: &[[i64; 3]],
    shell: bool,
    monitor: Option<&Monitor>,
) -> Result<Option<(Sums, Vector3<f64>, i32)>> {
    // The reference point: the vertex mean, summed relative to a vertex of the mesh, in units of
    // the mesh's extent (so that neither the differences nor their sum overflow).
    let anchor = Vector3::from(vertices[faces[0][0] as usize]);
    let extent = vertices
        .par_chunks(CHUNK)
        .map(|chunk| {
            chunk.iter().fold(0.0_f64, |m, v| {
                (0..3).fold(m, |m, k| m.max((v[k] - anchor[k]).abs()))
            })
        })
        .reduce(|| 0.0, f64::max);
    if !extent.is_finite() {
        return Ok(None);
    }
    let e = exponent(extent);
    let spreads: Vec<Vector3<f64>> = vertices
        .par_chunks(CHUNK)
        .map(|chunk| {
            chunk.iter().fold(Vector3::zeros(), |acc, v| {
                acc + (Vector3::from(*v) - anchor).map(|x| ldexp(x, -e))
            })
        })
        .collect();
    let spread = spreads.iter().fold(Vector3::zeros(), |acc, s| acc + s);
    let reference = anchor + (spread / vertices.len() as f64).map(|x| ldexp(x, e));
    // |v - reference| <= 2 extent: vertices in units of 2^k have entries of size <= 1.
    let k = e + 1;
    let reference_scaled = reference.map(|x| ldexp(x, -k));

    let vertex =
        |i: i64| Vector3::from(vertices[i as usize]).map(|x| ldexp(x, -k)) - reference_scaled;
    let chunks: Vec<Result<Sums>> = faces
        .par_chunks(CHUNK)
        .map(|chunk| {
            look(monitor)?;
            let mut sums = Sums::ZERO;
            // Plain sums over short blocks (error ~ BLOCK eps of the block's own terms),
            // blocks added with TwoSum.
            for block in chunk.chunks(BLOCK) {
                let mut local = [0.0; 10];
                let mut abs_weight = 0.0;
                for f in block {
                    let (a, b, c) = (vertex(f[0]), vertex(f[1]), vertex(f[2]));
                    let w = if shell {
                        (b - a).cross(&(c - a)).norm()
                    } else {
                        a.dot(&b.cross(&c))
                    };
                    for (l, t) in local.iter_mut().zip(terms(w, &a, &b, &c)) {
                        *l += t;
                    }
                    abs_weight += w.abs();
                }
                sums.add(&local, abs_weight);
            }
            Ok(sums)
        })
        .collect();
    let mut sums = Sums::ZERO;
    for chunk in chunks {
        sums = sums.merge(chunk?);
    }
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
    /// exactly one face and `v -> u` by exactly one other. Nested closed shells (a hollow body,
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
    /// of [`MESH_CHUNK`] triangles of the closedness check and each chunk of the integrals,
    /// so that a cancelled monitor stops the work within a block, with
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
        check_input(vertices, faces, shell)?;
        let (closed, integrated) = rayon::join(
            || {
                if shell {
                    Ok(())
                } else {
                    check_closed(faces, vertices.len(), monitor)
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

        // In units of 2^k for lengths: volume 2^3k (area 2^2k), first moment one more k, second
        // two more.
        let mut t = sums.value();
        if !t.iter().all(|x| x.is_finite()) {
            return Err(invalid(
                "vertices",
                "the mesh integrals overflow double precision.".into(),
            ));
        }
        // (weight -> measure, first, second) divisors: volume 6, 24, 120; area 2, 6, 24.
        let (d0, d1, d2) = if shell {
            (2.0, 6.0, 24.0)
        } else {
            (6.0, 24.0, 120.0)
        };
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
