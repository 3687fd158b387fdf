//! Principal frames followed along a time series: the canonical frame of each tensor (moments
//! ascending, deterministic signs) re-ordered and re-signed so that every axis moves
//! continuously from frame to frame, without sign flips or swaps where two moments cross.
//!
//! Frames with distinct moments are matched to the frame before by the signed permutation of
//! their columns closest to it (one of the 48, always a proper one); inside a degenerate frame
//! (equal moments) the axes of each group of equal moments are the orthonormal basis of the
//! group's subspace closest to the previous frame's axes (an orthogonal Procrustes problem),
//! and the groups take the previous axes that project most on them.

use nalgebra::{Matrix2, Matrix3, Vector3};

use crate::Monitor;
use crate::{Principal, Result};

/// Frames between two looks at the monitor.
const LOOK_EVERY: usize = 1 << 14;

/// The six permutations of three axes, in the order ties are broken (the first wins).
const PERMUTATIONS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// A signed permutation `Q` acting on the columns of a frame: column `j` of `U Q` is
/// `signs[j] U[:, perm[j]]`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct SignedPermutation {
    perm: [usize; 3],
    signs: [f64; 3],
}

impl SignedPermutation {
    const IDENTITY: Self = Self {
        perm: [0, 1, 2],
        signs: [1.0, 1.0, 1.0],
    };

    /// `self * other`: column `j` of `U Q_self Q_other` is
    /// `s_other[j] s_self[p_other[j]] U[:, p_self[p_other[j]]]`.
    fn then(self, other: Self) -> Self {
        let mut out = Self::IDENTITY;
        for j in 0..3 {
            let k = other.perm[j];
            out.perm[j] = self.perm[k];
            out.signs[j] = other.signs[j] * self.signs[k];
        }
        out
    }

    /// The frame's columns permuted and signed (exactly: each entry is one of the frame's,
    /// negated or not).
    fn apply(self, frame: &Principal) -> Principal {
        let mut out = *frame;
        for j in 0..3 {
            let k = self.perm[j];
            out.moments[j] = frame.moments[k];
            out.multiplicity[j] = frame.multiplicity[k];
            for i in 0..3 {
                out.axes[(i, j)] = if self.signs[j] < 0.0 {
                    -frame.axes[(i, k)]
                } else {
                    frame.axes[(i, k)]
                };
            }
        }
        out
    }
}

/// `a[:, i] . b[:, j]`, summed in the order of the rows.
fn column_dot(a: &Matrix3<f64>, i: usize, b: &Matrix3<f64>, j: usize) -> f64 {
    a[(0, i)] * b[(0, j)] + a[(1, i)] * b[(1, j)] + a[(2, i)] * b[(2, j)]
}

/// The signed permutation `g` with `axes Q_g` closest to `reference`: the permutation
/// maximising `sum_j |r_j . a_p(j)|` (the first of [`PERMUTATIONS`] on a tie), signs making
/// each of those dot products >= 0 (a negative one flips its column).
///
/// The result is always proper: it maximises `tr(R^T A Q)` over the 48 signed permutations; an
/// improper `Q` would make `R^T A Q` an improper orthogonal matrix, whose trace is at most 1,
/// while a proper one (the octahedral group comes within about 63 degrees of any rotation)
/// gives at least `1 + 2 cos(63 deg) > 1.9`.
fn closest(reference: &Matrix3<f64>, axes: &Matrix3<f64>) -> SignedPermutation {
    let mut m = [[0.0; 3]; 3];
    for (i, row) in m.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            *entry = column_dot(reference, i, axes, j);
        }
    }
    let mut best = 0;
    let mut best_score = f64::NEG_INFINITY;
    for (index, perm) in PERMUTATIONS.iter().enumerate() {
        let score = m[0][perm[0]].abs() + m[1][perm[1]].abs() + m[2][perm[2]].abs();
        if score > best_score {
            best = index;
            best_score = score;
        }
    }
    let perm = PERMUTATIONS[best];
    let mut signs = [1.0; 3];
    for j in 0..3 {
        if m[j][perm[j]] < 0.0 {
            signs[j] = -1.0;
        }
    }
    SignedPermutation { perm, signs }
}

/// The orthogonal polar factor `U V^T` of `m` (the orthogonal matrix closest to it), for the
/// top-left `n x n` block, `n` in 1..=3.
fn polar(m: &Matrix3<f64>, n: usize) -> Matrix3<f64> {
    let mut out = Matrix3::zeros();
    match n {
        1 => out[(0, 0)] = if m[(0, 0)] < 0.0 { -1.0 } else { 1.0 },
        2 => {
            let block = Matrix2::new(m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)]);
            let svd = block.svd(true, true);
            let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
                unreachable!("both factors were asked for")
            };
            let q = u * v_t;
            out.fixed_view_mut::<2, 2>(0, 0).copy_from(&q);
        }
        _ => {
            let svd = m.svd(true, true);
            let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
                unreachable!("both factors were asked for")
            };
            out = u * v_t;
        }
    }
    out
}

/// A degenerate frame's axes closest to `previous`: each group of equal moments spans a
/// subspace; the slots (previous axes) go to the groups by the permutation with the largest
/// projected energy, and each group's basis is the orthonormal one closest to its slots'
/// previous axes (the orthogonal polar factor of `U_G^T W_J`).
///
/// The result is proper: it maximises `tr(W_prev^T W)` over the bases adapted to the groups
/// with that assignment, and among them is the rotation of `W_prev` that turns its axis
/// nearest the line of a single moment onto that line (by at most 54.7 degrees, so a trace
/// above 2), while an improper `W` would have a trace of at most 1.
fn procrustes(frame: &Principal, previous: &Matrix3<f64>) -> Principal {
    // Groups of exactly equal moments (the canonical solve returns equal moments equal), in
    // ascending order of their value.
    let mut group_of = [0usize; 3];
    let mut values: Vec<f64> = Vec::with_capacity(3);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| frame.moments[a].total_cmp(&frame.moments[b]));
    for &k in &order {
        if values.last() != Some(&frame.moments[k]) {
            values.push(frame.moments[k]);
        }
    }
    for (group, moment) in group_of.iter_mut().zip(frame.moments.iter()) {
        *group = values.iter().position(|v| v == moment).unwrap_or(0);
    }
    // energy[j][g]: how much of previous axis j lies in group g's subspace.
    let mut energy = [[0.0; 3]; 3];
    for (j, row) in energy.iter_mut().enumerate() {
        for m in 0..3 {
            let d = column_dot(&frame.axes, m, previous, j);
            row[group_of[m]] += d * d;
        }
    }
    let mut best = 0;
    let mut best_score = f64::NEG_INFINITY;
    for (index, perm) in PERMUTATIONS.iter().enumerate() {
        let score = energy[0][group_of[perm[0]]]
            + energy[1][group_of[perm[1]]]
            + energy[2][group_of[perm[2]]];
        if score > best_score {
            best = index;
            best_score = score;
        }
    }
    let perm = PERMUTATIONS[best];
    let mut out = *frame;
    for (j, &k) in perm.iter().enumerate() {
        out.moments[j] = frame.moments[k];
        out.multiplicity[j] = frame.multiplicity[k];
    }
    for g in 0..values.len() {
        let members: Vec<usize> = (0..3).filter(|&m| group_of[m] == g).collect();
        let slots: Vec<usize> = (0..3).filter(|&j| group_of[perm[j]] == g).collect();
        let n = members.len();
        let mut m = Matrix3::zeros();
        for (a, &member) in members.iter().enumerate() {
            for (b, &slot) in slots.iter().enumerate() {
                m[(a, b)] = column_dot(&frame.axes, member, previous, slot);
            }
        }
        let q = polar(&m, n);
        for (b, &slot) in slots.iter().enumerate() {
            let mut column = Vector3::zeros();
            for (a, &member) in members.iter().enumerate() {
                column += frame.axes.column(member) * q[(a, b)];
            }
            out.axes.set_column(slot, &column);
        }
    }
    out
}

/// Re-orders and re-signs the canonical principal frames of a series (as
/// [`crate::eigen::symmetric_eigen3`] returns them) in place, so that each axis follows its
/// own direction from frame 0 on: no sign flips, no swaps where two moments cross (the moments
/// and multiplicities then follow their axes).
///
/// A run of frames with distinct moments is matched to the frame before it, and within the run
/// each frame to the canonical frame before it, the signed permutations composed (exactly:
/// every output is a permuted, signed copy of its canonical frame). A degenerate frame (some
/// multiplicity above 1) is solved against the previous output (an orthogonal Procrustes
/// problem per group of equal moments). Looks at
/// `monitor` every 16384 frames.
pub fn follow_principal_frames(frames: &mut [Principal], monitor: Option<&Monitor>) -> Result<()> {
    follow(frames, monitor)
}

/// [`follow_principal_frames`] on the flat arrays of
/// [`crate::eigen::principal_batch_monitored`]: `moments` (T x 3), `axes` (T x 3 x 3, row
/// major: `axes[9 t + 3 i + j]` is component `i` of axis `j`) and `multiplicity` (T x 3).
pub fn follow_principal_batch(
    moments: &mut [f64],
    axes: &mut [f64],
    multiplicity: &mut [i64],
    monitor: Option<&Monitor>,
) -> Result<()> {
    let count = moments.len() / 3;
    if moments.len() != 3 * count || axes.len() != 9 * count || multiplicity.len() != 3 * count {
        return Err(crate::Error::Shape {
            name: "inertia".into(),
            expected: "(T, 3, 3)".into(),
            got: format!("{} moments and {} axis entries", moments.len(), axes.len()),
        });
    }
    follow(
        &mut Flat {
            moments,
            axes,
            multiplicity,
        },
        monitor,
    )
}

/// Frames read and written one at a time.
trait Frames {
    fn count(&self) -> usize;
    fn load(&self, t: usize) -> Principal;
    fn store(&mut self, t: usize, frame: Principal);
}

impl Frames for [Principal] {
    fn count(&self) -> usize {
        self.len()
    }
    fn load(&self, t: usize) -> Principal {
        self[t]
    }
    fn store(&mut self, t: usize, frame: Principal) {
        self[t] = frame;
    }
}

/// The flat arrays of a batch solve.
struct Flat<'a> {
    moments: &'a mut [f64],
    axes: &'a mut [f64],
    multiplicity: &'a mut [i64],
}

impl Frames for Flat<'_> {
    fn count(&self) -> usize {
        self.moments.len() / 3
    }
    fn load(&self, t: usize) -> Principal {
        Principal {
            moments: Vector3::from_fn(|k, _| self.moments[3 * t + k]),
            axes: Matrix3::from_fn(|i, j| self.axes[9 * t + 3 * i + j]),
            // The core's multiplicities are 1, 2 or 3.
            multiplicity: std::array::from_fn(|k| {
                u8::try_from(self.multiplicity[3 * t + k]).unwrap_or(1)
            }),
        }
    }
    fn store(&mut self, t: usize, frame: Principal) {
        for k in 0..3 {
            self.moments[3 * t + k] = frame.moments[k];
            self.multiplicity[3 * t + k] = i64::from(frame.multiplicity[k]);
            for j in 0..3 {
                self.axes[9 * t + 3 * k + j] = frame.axes[(k, j)];
            }
        }
    }
}

/// The loop of [`follow_principal_frames`].
fn follow<F: Frames + ?Sized>(frames: &mut F, monitor: Option<&Monitor>) -> Result<()> {
    let count = frames.count();
    if count < 2 {
        return Ok(());
    }
    let degenerate = |f: &Principal| f.multiplicity.iter().any(|&m| m > 1);
    // The canonical frame before the current one (its input form), the previous output, and
    // the signed permutation the last frame of a run was output with.
    let mut canonical_before = frames.load(0).axes;
    let mut previous_output = canonical_before;
    let mut composed = SignedPermutation::IDENTITY;
    let mut run_starts = true;
    for t in 1..count {
        if t % LOOK_EVERY == 0 {
            if let Some(monitor) = monitor {
                monitor.look()?;
            }
        }
        let canonical = frames.load(t);
        let output = if degenerate(&canonical) {
            run_starts = true;
            procrustes(&canonical, &previous_output)
        } else {
            composed = if run_starts {
                closest(&previous_output, &canonical.axes)
            } else {
                closest(&canonical_before, &canonical.axes).then(composed)
            };
            run_starts = false;
            composed.apply(&canonical)
        };
        canonical_before = canonical.axes;
        previous_output = output.axes;
        frames.store(t, output);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn frame(moments: [f64; 3], axes: Matrix3<f64>, multiplicity: [u8; 3]) -> Principal {
        Principal {
            moments: Vector3::from(moments),
            axes,
            multiplicity,
        }
    }

    #[test]
    fn composition_matches_the_matrices() {
        // Q_g Q_h as matrices equals the composed signed permutation.
        let matrix = |q: SignedPermutation| {
            Matrix3::from_fn(|i, j| if q.perm[j] == i { q.signs[j] } else { 0.0 })
        };
        for (a, pa) in PERMUTATIONS.iter().enumerate() {
            for (b, pb) in PERMUTATIONS.iter().enumerate() {
                let g = SignedPermutation {
                    perm: *pa,
                    signs: [1.0, -1.0, if a % 2 == 0 { 1.0 } else { -1.0 }],
                };
                let h = SignedPermutation {
                    perm: *pb,
                    signs: [if b % 3 == 0 { -1.0 } else { 1.0 }, 1.0, -1.0],
                };
                assert_eq!(matrix(g.then(h)), matrix(g) * matrix(h));
            }
        }
    }

    #[test]
    fn a_swapped_and_flipped_frame_is_put_back() {
        let r = Rotation3::from_euler_angles(0.3, -0.2, 0.1).into_inner();
        let first = frame([1.0, 2.0, 3.0], r, [1, 1, 1]);
        // The next frame: the same axes, columns 0 and 2 swapped and column 1 negated (a
        // proper signed permutation), moments swapped accordingly.
        let mut second_axes = r;
        second_axes.swap_columns(0, 2);
        second_axes.set_column(1, &(-r.column(1)));
        let second = frame([3.0, 2.0, 1.0], second_axes, [1, 1, 1]);
        let mut frames = vec![first, second];
        follow_principal_frames(&mut frames, None).unwrap();
        assert_eq!(frames[1].axes, r);
        assert_eq!(frames[1].moments, Vector3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn a_degenerate_frame_keeps_the_previous_axes_in_its_plane() {
        // Frame 0 turned by 0.4 rad about z; frame 1 symmetric about z (canonical: identity).
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.4).into_inner();
        let first = frame([1.0, 2.0, 3.0], r, [1, 1, 1]);
        let second = frame([1.5, 1.5, 3.0], Matrix3::identity(), [2, 2, 1]);
        let mut frames = vec![first, second];
        follow_principal_frames(&mut frames, None).unwrap();
        assert!((frames[1].axes - r).norm() < 1e-15, "{}", frames[1].axes);
        assert!((frames[1].axes.determinant() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn a_cancelled_monitor_stops_a_long_series() {
        let monitor = Monitor::new();
        monitor.cancel();
        let mut frames =
            vec![frame([1.0, 2.0, 3.0], Matrix3::identity(), [1, 1, 1]); LOOK_EVERY + 1];
        assert_eq!(
            follow_principal_frames(&mut frames, Some(&monitor)),
            Err(crate::Error::Interrupted)
        );
    }
}
