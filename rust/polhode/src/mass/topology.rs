//! Whether a solid mesh is closed, with vertices that real files repeat as one vertex.
//!
//! A solid mesh must be closed and consistently wound: every directed edge `u -> v` used by
//! exactly one face and its reverse `v -> u` by exactly one other. Files do not share vertices
//! the way that check needs: an STL repeats every vertex in every triangle, OBJ and glTF split
//! them along texture seams, and CAD exporters write a vertex that is 0 in one facet as 3e-17 in
//! the next. So, for this check only (the integrals use the vertices as given):
//!
//! 1. the faces as indexed: most meshes pass here, at no further cost;
//! 2. vertices at the same position (`-0.0` and `0.0` alike) as one vertex ([`merge_exact`]:
//!    a hash table, O(vertices));
//! 3. the vertices on the boundary that is left, closer to each other than [`weld_tolerance`]
//!    (`2^-40` of the bounding-box diagonal, in every coordinate), as one vertex: a grid of
//!    cells of twice that size, each vertex compared with those of its own and the 26
//!    neighbouring cells, the pairs joined by union-find (a vertex's class is named by its
//!    smallest index, whatever the order of the work).
//!
//! Faces that step 2 or 3 reduce to a segment or a point (slivers of zero width) are left out of
//! the check: their edges cancel. What remains open is reported with where the holes are, how
//! long and how wide (a hole's vector area over its length), so that a crack between triangles
//! that do not share vertices is told from a missing face.
//!
//! **The tolerance.** Exporters' noise is a few units in the last place of the coordinates: of
//! 120 meshes of a robot collection refused as open, 55 close once vertices within `1e-14` of
//! the diagonal are merged (about 45 ulps of the largest coordinate) and none between that and
//! `1e-7` (a second cluster: vertices written once as float32 and once as float64). Real edges
//! are longer: the shortest edge of 886 robot meshes is above `2.6e-8` of the diagonal in 99% of
//! them and above `1e-9` in all but two (whose "edges" were themselves duplicates at `1e-17`).
//! `2^-40 = 9.1e-13` sits about two decades above the noise and three below the shortest real
//! edge: it merges `1e-17` on a 3 cm part and never a gap of `1e-3` (or of `1e-11` of the
//! diagonal).

use rayon::prelude::*;

use super::{invalid, look, MESH_CHUNK};
use crate::eigen::ldexp;
use crate::error::Result;
use crate::memory::{self, Purpose};
use crate::Monitor;

/// log2 of the tolerance (relative to the bounding-box diagonal) within which vertices are one
/// vertex for the closedness check.
pub const WELD_EXPONENT: i32 = -40;

/// A hole whose width (twice its vector area over its length) is at most this fraction of the
/// bounding-box diagonal is a crack between triangles, not a missing face.
const CRACK: f64 = 1e-6;

/// What a scan of the directed edges found: the first directed edge used twice (by vertex
/// range), and the edges without their reverse (all of them, or with `collect = false` at most
/// the first of each range).
struct Closure {
    repeated: Option<(u64, u64)>,
    unpaired: Vec<(u64, u64)>,
}

impl Closure {
    fn is_closed(&self) -> bool {
        self.repeated.is_none() && self.unpaired.is_empty()
    }
}

/// The directed edges of `faces` (indices below `vertex_count`, no face repeating a vertex)
/// paired up.
///
/// Each directed edge is filed under its smaller vertex `min(u, v)` as `max(u, v)` plus one bit
/// for its direction (a counting sort, O(faces + vertices)); each small bucket is then sorted and
/// must consist of pairs `(w, forward), (w, backward)`.
fn scan(
    faces: &[[i64; 3]],
    vertex_count: usize,
    collect: bool,
    monitor: Option<&Monitor>,
) -> Result<Closure> {
    let edges = |f: &[i64; 3]| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])];
    let mut offsets = memory::zeros::<u32>(vertex_count + 1, Purpose::Mesh)?;
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
    let mut cursor = memory::copied(&offsets, Purpose::Mesh)?;
    let mut entries = memory::zeros::<u32>(3 * faces.len(), Purpose::Mesh)?;
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
    // Per range: the first directed edge used twice, and the edges without their reverse.
    type Found = (Option<(u64, u64)>, Vec<(u64, u64)>);
    let found: Vec<Result<Found>> = parts
        .into_par_iter()
        .map(|(first, part)| {
            let (mut repeated, mut unpaired) = (None, Vec::new());
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
                        if !(i + 1 < bucket.len() && bucket[i + 1] >> 1 == key >> 1)
                            && (collect || unpaired.is_empty())
                        {
                            memory::push(&mut unpaired, directed(key), Purpose::Mesh)?;
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
    let mut closure = Closure {
        repeated: None,
        unpaired: Vec::new(),
    };
    for part in found {
        let (repeated, unpaired) = part?;
        closure.repeated = closure.repeated.or(repeated);
        memory::extend(&mut closure.unpaired, &unpaired, Purpose::Mesh)?;
    }
    Ok(closure)
}

/// The key of a position: its bits, with `-0.0` as `0.0`.
#[inline(always)]
fn key_of(v: &[f64; 3]) -> [u64; 3] {
    [
        (v[0] + 0.0).to_bits(),
        (v[1] + 0.0).to_bits(),
        (v[2] + 0.0).to_bits(),
    ]
}

/// A slot of a table of `2^bits` for `key` (multiplicative hashing: the high bits of a product
/// that mixes every bit of the three coordinates).
#[inline(always)]
fn slot_of(key: &[u64; 3], bits: u32) -> usize {
    let h = key[0].wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ key[1].rotate_left(21).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ key[2].rotate_left(42).wrapping_mul(0x1656_67B1_9E37_79F9);
    let h = (h ^ (h >> 31)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    (h >> (64 - bits)) as usize
}

/// For each vertex, the first vertex at the same position (itself if none comes before it):
/// an open-addressing hash table of vertex indices, filled in order, so the result does not
/// depend on anything but the vertices. Looks at `monitor` every [`MESH_CHUNK`] vertices.
pub(crate) fn merge_exact(vertices: &[[f64; 3]], monitor: Option<&Monitor>) -> Result<Vec<u32>> {
    const EMPTY: u32 = u32::MAX;
    let n = vertices.len();
    let bits = (2 * n).max(16).next_power_of_two().trailing_zeros();
    let mask = (1usize << bits) - 1;
    let mut table = memory::filled(1 << bits, EMPTY, Purpose::Mesh)?;
    // Room for one entry per vertex: the pushes below never grow it.
    let mut first = memory::with_capacity(n, Purpose::Mesh)?;
    for (b, block) in vertices.chunks(MESH_CHUNK).enumerate() {
        look(monitor)?;
        for (k, v) in block.iter().enumerate() {
            let i = (b * MESH_CHUNK + k) as u32;
            let key = key_of(v);
            let mut slot = slot_of(&key, bits);
            loop {
                let t = table[slot];
                if t == EMPTY {
                    table[slot] = i;
                    first.push(i);
                    break;
                }
                if key_of(&vertices[t as usize]) == key {
                    first.push(t);
                    break;
                }
                slot = (slot + 1) & mask;
            }
        }
    }
    Ok(first)
}

/// The vertices and faces of [`merge_vertices`].
pub type Merged = (Vec<[f64; 3]>, Vec<[i64; 3]>);

/// A file's vertices at the same position merged (the first of them kept, in the order of
/// first appearance) and the faces renumbered; faces that then repeat a vertex (of zero area)
/// are dropped. Looks at `monitor` every [`MESH_CHUNK`] vertices and faces.
///
/// This is for readers of files, which hand over triangle soups (STL); a mesh need not be
/// merged for [`MassProperties::mesh`](super::MassProperties::mesh), whose closedness check
/// merges by itself (and within a tolerance).
///
/// ```
/// use polhode::mass::merge_vertices;
/// // Two triangles of a square, each with its own three corners (as STL writes them).
/// let v = [
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0],
///     [0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [-0.0, 1.0, 0.0],
/// ];
/// let (vertices, faces) = merge_vertices(&v, &[[0, 1, 2], [3, 4, 5]], None).unwrap();
/// assert_eq!(vertices.len(), 4);
/// assert_eq!(faces, vec![[0, 1, 2], [0, 2, 3]]);
/// ```
pub fn merge_vertices(
    vertices: &[[f64; 3]],
    faces: &[[i64; 3]],
    monitor: Option<&Monitor>,
) -> Result<Merged> {
    let n = vertices.len();
    if n > u32::MAX as usize - 1 {
        return Err(invalid(
            "vertices",
            format!("expected at most 2^32 - 2 vertices, got {n}."),
        ));
    }
    for (i, f) in faces.iter().enumerate() {
        for (k, &index) in f.iter().enumerate() {
            if index < 0 || index as u64 >= n as u64 {
                return Err(invalid(
                    format!("faces[{i}, {k}]"),
                    format!("vertex index {index} is out of range for {n} vertices."),
                ));
            }
        }
    }
    let first = merge_exact(vertices, monitor)?;
    let mut number = memory::filled(n, u32::MAX, Purpose::MergedMesh)?;
    let kept = first
        .iter()
        .enumerate()
        .filter(|&(i, &f)| f as usize == i)
        .count();
    let mut merged = memory::with_capacity(kept, Purpose::MergedMesh)?;
    for (i, &f) in first.iter().enumerate() {
        if f as usize == i {
            number[i] = merged.len() as u32;
            merged.push(vertices[i]);
        }
    }
    let mut out = memory::with_capacity(faces.len(), Purpose::MergedMesh)?;
    for block in faces.chunks(MESH_CHUNK) {
        look(monitor)?;
        for f in block {
            let g = f.map(|i| i64::from(number[first[i as usize] as usize]));
            if g[0] != g[1] && g[1] != g[2] && g[2] != g[0] {
                out.push(g);
            }
        }
    }
    Ok((merged, out))
}

/// `faces` with each index `i` replaced by `into[i]`, those that then repeat a vertex left out.
fn renumbered(
    faces: &[[i64; 3]],
    into: &[u32],
    monitor: Option<&Monitor>,
) -> Result<Vec<[i64; 3]>> {
    let mut out = memory::with_capacity(faces.len(), Purpose::Mesh)?;
    for block in faces.chunks(MESH_CHUNK) {
        look(monitor)?;
        for f in block {
            let g = f.map(|i| i64::from(into[i as usize]));
            if g[0] != g[1] && g[1] != g[2] && g[2] != g[0] {
                out.push(g);
            }
        }
    }
    Ok(out)
}

/// The corner of the bounding box of the vertices `faces` use and its diagonal.
fn bounding_box(vertices: &[[f64; 3]], faces: &[[i64; 3]]) -> ([f64; 3], f64) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for f in faces {
        for &i in f {
            let v = vertices[i as usize];
            for a in 0..3 {
                lo[a] = lo[a].min(v[a]);
                hi[a] = hi[a].max(v[a]);
            }
        }
    }
    // The diagonal in units of its largest side, so that it neither overflows nor underflows.
    let side = (0..3).fold(0.0_f64, |m, a| m.max(hi[a] - lo[a]));
    if !(side.is_finite() && side > 0.0) {
        return (lo, side);
    }
    let s = (0..3)
        .map(|a| ((hi[a] - lo[a]) / side).powi(2))
        .sum::<f64>();
    (lo, side * s.sqrt())
}

/// The tolerance within which vertices are one vertex for the closedness check of a mesh of
/// bounding-box diagonal `diagonal`: `2^-40 diagonal` (see the module's documentation for its
/// derivation). Two vertices are one if they differ by at most this in every coordinate.
#[must_use]
pub fn weld_tolerance(diagonal: f64) -> f64 {
    ldexp(diagonal, WELD_EXPONENT)
}

/// A union-find over `0..n`, each set named by its smallest member.
struct Classes(Vec<u32>);

impl Classes {
    fn new(n: usize) -> Result<Self> {
        Ok(Self(memory::collect(0..n as u32, Purpose::Mesh)?))
    }

    fn find(&mut self, mut i: u32) -> u32 {
        while self.0[i as usize] != i {
            let up = self.0[self.0[i as usize] as usize];
            self.0[i as usize] = up;
            i = up;
        }
        i
    }

    fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            let (low, high) = (a.min(b), a.max(b));
            self.0[high as usize] = low;
        }
    }
}

/// The vertices of the edges `unpaired` within `tolerance` of each other (in every coordinate)
/// joined: `class[i]` becomes the smallest vertex of `i`'s class, for every vertex.
fn weld(
    vertices: &[[f64; 3]],
    class: &mut [u32],
    unpaired: &[(u64, u64)],
    corner: [f64; 3],
    tolerance: f64,
    monitor: Option<&Monitor>,
) -> Result<()> {
    let mut boundary: Vec<u32> = memory::with_capacity(2 * unpaired.len(), Purpose::Mesh)?;
    boundary.extend(unpaired.iter().flat_map(|&(u, v)| [u as u32, v as u32]));
    boundary.sort_unstable();
    boundary.dedup();
    // Cells of twice the tolerance: vertices within it of each other are in the same or
    // neighbouring cells, with room for the rounding of the division.
    let cell = 2.0 * tolerance;
    let key = |i: u32| -> [i64; 3] {
        let v = vertices[i as usize];
        std::array::from_fn(|a| ((v[a] - corner[a]) / cell).floor() as i64)
    };
    let mut order = memory::collect(boundary.iter().map(|&i| (key(i), i)), Purpose::Mesh)?;
    look(monitor)?;
    order.par_sort_unstable();
    let close = |i: u32, j: u32| {
        let (a, b) = (vertices[i as usize], vertices[j as usize]);
        (0..3).all(|k| (a[k] - b[k]).abs() <= tolerance)
    };
    let mut classes = Classes::new(order.len())?;
    for (c, chunk) in order.chunks(MESH_CHUNK).enumerate() {
        look(monitor)?;
        for (k, &(cell, i)) in chunk.iter().enumerate() {
            let j = (c * MESH_CHUNK + k) as u32;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let target = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                        if target < cell {
                            continue; // that pair is met from the other side
                        }
                        let mut m = order.partition_point(|e| e.0 < target);
                        while m < order.len() && order[m].0 == target {
                            if m as u32 > j && close(i, order[m].1) {
                                classes.join(j, m as u32);
                            }
                            m += 1;
                        }
                    }
                }
            }
        }
    }
    // Each class named by its smallest vertex index.
    let mut smallest = memory::filled(order.len(), u32::MAX, Purpose::Mesh)?;
    for (j, &(_, i)) in order.iter().enumerate() {
        let r = classes.find(j as u32) as usize;
        smallest[r] = smallest[r].min(i);
    }
    let mut welded = memory::zeros::<u32>(boundary.len(), Purpose::Mesh)?;
    for (j, &(_, i)) in order.iter().enumerate() {
        let r = classes.find(j as u32) as usize;
        welded[boundary
            .binary_search(&i)
            .unwrap_or_else(|_| unreachable!())] = smallest[r];
    }
    for block in class.chunks_mut(MESH_CHUNK) {
        look(monitor)?;
        for c in block {
            if let Ok(p) = boundary.binary_search(c) {
                *c = welded[p];
            }
        }
    }
    Ok(())
}

/// A number with four significant digits, compactly.
fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let size = x.abs();
    if (1e-3..1e5).contains(&size) {
        let decimals = (3 - size.log10().floor() as i32).max(0) as usize;
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            text
        }
    } else {
        format!("{x:.3e}")
    }
}

fn position(v: [f64; 3]) -> String {
    format!("({}, {}, {})", short(v[0]), short(v[1]), short(v[2]))
}

/// The boundary of an open mesh: its loops (the connected sets of unpaired edges) with their
/// edge count, length, vector area and a vertex on them.
struct Boundary {
    loops: usize,
    edges: usize,
    length: f64,
    /// The longest loop: its edges, length, width (2 |vector area| / length) and lowest vertex.
    longest: (usize, f64, f64, u64),
}

fn boundary(vertices: &[[f64; 3]], unpaired: &[(u64, u64)]) -> Result<Boundary> {
    let mut ends: Vec<u64> = memory::with_capacity(2 * unpaired.len(), Purpose::Mesh)?;
    ends.extend(unpaired.iter().flat_map(|&(u, v)| [u, v]));
    ends.sort_unstable();
    ends.dedup();
    let local = |i: u64| ends.binary_search(&i).unwrap_or_else(|_| unreachable!()) as u32;
    let mut classes = Classes::new(ends.len())?;
    for &(u, v) in unpaired {
        classes.join(local(u), local(v));
    }
    // Per loop (named by its smallest local vertex): edges, length, vector area about that
    // vertex (the loop's area vector does not depend on the point for a closed loop).
    let mut loops = memory::filled(ends.len(), (0usize, 0.0, [0.0; 3]), Purpose::Mesh)?;
    let mut length = 0.0;
    for &(u, v) in unpaired {
        let root = classes.find(local(u)) as usize;
        let p = vertices[ends[root] as usize];
        let (a, b) = (vertices[u as usize], vertices[v as usize]);
        let a: [f64; 3] = std::array::from_fn(|k| a[k] - p[k]);
        let b: [f64; 3] = std::array::from_fn(|k| b[k] - p[k]);
        let edge = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
        let entry = &mut loops[root];
        entry.0 += 1;
        entry.1 += edge;
        entry.2[0] += 0.5 * (a[1] * b[2] - a[2] * b[1]);
        entry.2[1] += 0.5 * (a[2] * b[0] - a[0] * b[2]);
        entry.2[2] += 0.5 * (a[0] * b[1] - a[1] * b[0]);
        length += edge;
    }
    let mut count = 0;
    let mut longest = (0, -1.0, 0.0, 0);
    for (root, &(edges, l, area)) in loops.iter().enumerate() {
        if edges == 0 {
            continue;
        }
        count += 1;
        if l > longest.1 {
            let a = (area[0] * area[0] + area[1] * area[1] + area[2] * area[2]).sqrt();
            let width = if l > 0.0 { 2.0 * a / l } else { 0.0 };
            longest = (edges, l, width, ends[root]);
        }
    }
    Ok(Boundary {
        loops: count,
        edges: unpaired.len(),
        length,
        longest,
    })
}

/// A solid mesh closed and consistently wound, vertices at the same position or within
/// [`weld_tolerance`] of each other counting as one (see the module's documentation); or the
/// error that says where it is open or which edge is used twice. Indices are in range and no
/// face repeats an index (checked before).
pub(super) fn check_closed(
    vertices: &[[f64; 3]],
    faces: &[[i64; 3]],
    monitor: Option<&Monitor>,
) -> Result<()> {
    let n = vertices.len();
    let mut closure = scan(faces, n, false, monitor)?;
    if closure.is_closed() {
        return Ok(());
    }
    let mut class = merge_exact(vertices, monitor)?;
    closure = scan(&renumbered(faces, &class, monitor)?, n, true, monitor)?;
    let (corner, diagonal) = bounding_box(vertices, faces);
    let tolerance = weld_tolerance(diagonal);
    if closure.repeated.is_none()
        && !closure.unpaired.is_empty()
        && tolerance.is_finite()
        && tolerance > 0.0
    {
        weld(
            vertices,
            &mut class,
            &closure.unpaired,
            corner,
            tolerance,
            monitor,
        )?;
        closure = scan(&renumbered(faces, &class, monitor)?, n, true, monitor)?;
    }
    if closure.is_closed() {
        return Ok(());
    }
    let merged = format!(
        "(Vertices within {} of each other, 2^{WELD_EXPONENT} of the bounding-box diagonal {}, \
         count as one vertex here.)",
        short(tolerance),
        short(diagonal)
    );
    if let Some((u, v)) = closure.repeated {
        let (a, b) = (vertices[u as usize], vertices[v as usize]);
        return Err(invalid(
            "faces",
            format!(
                "the directed edge {u} -> {v}, from {} to {}, is used by more than one face: the \
                 winding is inconsistent (a flipped face) or the edge is shared by more than two \
                 faces (a non-manifold mesh). Every edge must be traversed once in each \
                 direction. {merged}",
                position(a),
                position(b)
            ),
        ));
    }
    let b = boundary(vertices, &closure.unpaired)?;
    let (edges, length, width, at) = b.longest;
    let crack = width <= CRACK * diagonal;
    let (u, v) = closure.unpaired[0];
    let advice = if crack {
        format!(
            "The sides of every opening lie within {} of each other: cracks between triangles \
             that do not share their vertices (a vertex on another triangle's edge, or vertices \
             further apart than the tolerance), not missing faces. The surface is closed to that \
             width but not connected: repair the mesh (weld its vertices with a coarser \
             tolerance, or remesh it); shell=True would put the mass on the surface instead.",
            short(width)
        )
    } else {
        "If the body is a thin surface (a sheet, a shell), use shell=True; if it is a solid, \
         its file is missing faces there."
            .to_owned()
    };
    Err(invalid(
        "faces",
        format!(
            "the mesh is not closed: {} edge{} (the first {u} -> {v}) ha{} no face traversing \
             {} back, along {} opening{} of total length {} ({} of the bounding-box diagonal); \
             the longest opening, {edges} edge{} and {} long, passes through vertex {at} at {} \
             and is {} wide. {advice} {merged}",
            b.edges,
            if b.edges == 1 { "" } else { "s" },
            if b.edges == 1 { "s" } else { "ve" },
            if b.edges == 1 { "it" } else { "them" },
            b.loops,
            if b.loops == 1 { "" } else { "s" },
            short(b.length),
            short(b.length / diagonal),
            if edges == 1 { "" } else { "s" },
            short(length),
            position(vertices[at as usize]),
            short(width),
        ),
    ))
}
