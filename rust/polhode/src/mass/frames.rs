//! Inertia tensors of the frames of a point-mass trajectory (molecular dynamics): one tensor
//! per frame, each about that frame's own centre of mass.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::error::{finite, Error, Result};
use crate::memory::{self, Purpose};
use crate::Monitor;

/// Points per parallel chunk of [`point_masses_inertia`] (whole frames; at least one frame):
/// the unit of parallel work and of the looks at the monitor.
pub const FRAME_POINTS_CHUNK: usize = 1 << 15;

/// A position as three coordinates: `[f64; 3]`, `[f32; 3]` (single-precision trajectories, read
/// without a converted copy; every `f32` is exactly a double) or `Vector3<f64>`.
pub trait Position: Copy + Send + Sync {
    /// The coordinates as doubles.
    fn xyz(self) -> [f64; 3];
}

impl Position for [f64; 3] {
    #[inline(always)]
    fn xyz(self) -> [f64; 3] {
        self
    }
}

impl Position for [f32; 3] {
    #[inline(always)]
    fn xyz(self) -> [f64; 3] {
        [f64::from(self[0]), f64::from(self[1]), f64::from(self[2])]
    }
}

impl Position for Vector3<f64> {
    #[inline(always)]
    fn xyz(self) -> [f64; 3] {
        [self[0], self[1], self[2]]
    }
}

/// The inertia tensor of each frame of point masses, about that frame's centre of mass.
///
/// `masses` (N) are shared by every frame; `positions` holds T frames of N points, frame after
/// frame (numpy's (T, N, 3) layout); `inertia` receives T row-major 3x3 tensors (`9 T` values,
/// `I = tr(C) 1 - C` with `C = sum m (r - r_cm)(r - r_cm)^T`, products of inertia as tensor
/// elements).
///
/// Each frame is centred first: the centre of mass is found relative to the frame's first
/// point, and the second moments are summed over the centred offsets (plain sums, not the
/// square-root form of [`MassProperties::point_masses`](super::MassProperties::point_masses):
/// an element's error is about N eps of the largest moment).
///
/// Frames are independent and each is computed on its own, so the result does not depend on
/// the number of threads. Errors name the first bad value: `masses[n]` (not finite and
/// positive), `positions[t, n, k]` (not finite), or `positions` (a frame whose inertia
/// overflows double precision).
///
/// ```
/// use polhode::mass::point_masses_inertia;
/// // Carbon monoxide at two instants, along z then along x: I = mu d^2 about the centre.
/// let masses = [12.0, 16.0];
/// let positions = [
///     [0.0, 0.0, 0.0], [0.0, 0.0, 1.128],
///     [5.0, 0.0, 0.0], [6.128, 0.0, 0.0],
/// ];
/// let mut inertia = [0.0; 18];
/// point_masses_inertia(&masses, &positions, &mut inertia).unwrap();
/// let mu_d2 = 12.0 * 16.0 / 28.0 * 1.128 * 1.128;
/// assert!((inertia[0] - mu_d2).abs() < 1e-14 * mu_d2); // I_xx of the first frame
/// assert!(inertia[8].abs() < 1e-14 * mu_d2); // I_zz of the first frame
/// assert!(inertia[9].abs() < 1e-14 * mu_d2); // I_xx of the second frame
/// ```
pub fn point_masses_inertia<P: Position>(
    masses: &[f64],
    positions: &[P],
    inertia: &mut [f64],
) -> Result<()> {
    point_masses_inertia_monitored(masses, positions, inertia, None)
}

/// [`point_masses_inertia`] watched by `monitor`: a look ([`Monitor::look`]) before each chunk
/// of about [`FRAME_POINTS_CHUNK`] points, so that a cancelled monitor stops the work within a
/// chunk, with [`Error::Interrupted`].
pub fn point_masses_inertia_monitored<P: Position>(
    masses: &[f64],
    positions: &[P],
    inertia: &mut [f64],
    monitor: Option<&Monitor>,
) -> Result<()> {
    let n = masses.len();
    if n == 0 {
        return Err(Error::Shape {
            name: "masses".into(),
            expected: "(N,) with N >= 1".into(),
            got: "(0,)".into(),
        });
    }
    let frames = positions.len() / n;
    if positions.len() != frames * n || inertia.len() != 9 * frames {
        return Err(Error::Shape {
            name: "positions".into(),
            expected: format!("(T, {n}, 3) to match `masses`"),
            got: format!("{} points", positions.len()),
        });
    }
    if let Some(i) = masses.iter().position(|m| !(m.is_finite() && *m > 0.0)) {
        let name = format!("masses[{i}]");
        finite(&name, masses[i])?;
        return Err(Error::NonPositive {
            name,
            value: masses[i],
        });
    }
    let total: f64 = masses.iter().sum();
    if !total.is_finite() {
        return Err(Error::InvalidArgument {
            name: "masses".into(),
            reason: format!(
                "their sum overflows double precision (beyond the largest double, {:e}).",
                f64::MAX
            ),
        });
    }
    let masses = Masses {
        values: masses,
        total,
    };
    let per_chunk = (FRAME_POINTS_CHUNK / n).max(1);
    let outcomes: Vec<Result<()>> = memory::collect_parallel(
        positions
            .par_chunks(per_chunk * n)
            .zip(inertia.par_chunks_mut(per_chunk * 9))
            .enumerate()
            .map(|(chunk, (points, out))| {
                if let Some(monitor) = monitor {
                    monitor.look()?;
                }
                // The blocks' buffers, reused from frame to frame of the chunk.
                let mut block = Block::new(n)?;
                for (j, (frame, tensor)) in points.chunks(n).zip(out.chunks_mut(9)).enumerate() {
                    let t = chunk * per_chunk + j;
                    let c = frame_second_moment(&masses, frame, t, &mut block)?;
                    // I = tr(C) 1 - C with each diagonal element the sum of the two other second
                    // moments (not tr(C) - C_kk, which loses a needle's small moment).
                    let values = [
                        c[3] + c[5],
                        -c[1],
                        -c[2],
                        -c[1],
                        c[0] + c[5],
                        -c[4],
                        -c[2],
                        -c[4],
                        c[0] + c[3],
                    ];
                    if !values.iter().all(|x| x.is_finite()) {
                        return Err(frame_overflow(t));
                    }
                    tensor.copy_from_slice(&values);
                }
                Ok(())
            }),
        Purpose::FrameTensors,
    )?;
    outcomes.into_iter().collect()
}

/// The masses shared by every frame, checked, with their sum.
struct Masses<'a> {
    values: &'a [f64],
    total: f64,
}

/// Independent partial sums per dot product: they break the chain of dependent additions and
/// fill the SIMD lanes; element i goes to lane i mod 8 (the rest of the division to lane 0),
/// and the lanes are added in order, so the result depends on nothing but the input.
const LANES: usize = 8;

/// Points per block of a frame: the offsets are made a block at a time, in six vectors of at
/// most this many doubles per thread (768 KiB, within the L2 cache), so that a frame of any size
/// needs a bounded working memory (six vectors of the whole frame per thread took 1.4 GB for a
/// frame of 3e7 points, and ran 10x slower out of cache). A frame of at most this many points
/// (every molecule) is one block, its offsets made once. A multiple of [`LANES`]: the lanes of
/// every block but the last are full, so each lane adds the same products in the same order as
/// over the whole frame at once.
const BLOCK: usize = 1 << 14;

/// A block's offsets from the frame's first point, coordinate by coordinate, then from its
/// centre of mass, and the same times the masses (buffers reused from frame to frame of a
/// chunk).
struct Block {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    mx: Vec<f64>,
    my: Vec<f64>,
    mz: Vec<f64>,
}

impl Block {
    /// Buffers for the blocks of frames of `n` points.
    fn new(n: usize) -> Result<Self> {
        let buffer = || memory::zeros::<f64>(n.min(BLOCK), Purpose::FrameTensors);
        Ok(Self {
            x: buffer()?,
            y: buffer()?,
            z: buffer()?,
            mx: buffer()?,
            my: buffer()?,
            mz: buffer()?,
        })
    }

    /// The offsets of `points` (at most [`BLOCK`]) from `origin`.
    #[inline(always)]
    fn offsets<P: Position>(&mut self, points: &[P], origin: [f64; 3]) {
        for (((&p, x), y), z) in points
            .iter()
            .zip(&mut self.x)
            .zip(&mut self.y)
            .zip(&mut self.z)
        {
            let p = p.xyz();
            *x = p[0] - origin[0];
            *y = p[1] - origin[1];
            *z = p[2] - origin[2];
        }
    }
}

/// The second moments `sum m c c^T` of one frame about its centre of mass, as the six numbers
/// xx, xy, xz, yy, yz, zz.
///
/// Each product is formed as `(m x) y`: if an intermediate left the range of doubles, so would
/// the result (or the result is below the smallest normal double itself), so no scaling is
/// needed; a result that overflows is reported by the caller.
fn frame_second_moment<P: Position>(
    masses: &Masses<'_>,
    frame: &[P],
    t: usize,
    block: &mut Block,
) -> Result<[f64; 6]> {
    let (first, c) = moments(masses.values, masses.total, frame, block);
    if !first.iter().all(|x| x.is_finite()) {
        return Err(bad_frame(frame, t));
    }
    Ok(c)
}

/// The first moment about the first point and the second moments about the centre of mass,
/// with the widest vector instructions the CPU has (`crate::simd::dispatch`: the same IEEE
/// operations either way, so the result does not depend on it).
fn moments<P: Position>(
    masses: &[f64],
    total: f64,
    frame: &[P],
    block: &mut Block,
) -> ([f64; 3], [f64; 6]) {
    crate::simd::dispatch(
        #[inline(always)]
        || moments_generic(masses, total, frame, block),
    )
}

/// Two passes over the frame, a [`BLOCK`] of points at a time, each dot product in [`LANES`]
/// partial sums carried from block to block: the numbers of the same sums over the whole frame.
/// A frame of one block (the common case: a molecule's atoms) makes its offsets once.
#[inline(always)]
fn moments_generic<P: Position>(
    m: &[f64],
    total: f64,
    frame: &[P],
    b: &mut Block,
) -> ([f64; 3], [f64; 6]) {
    let origin = frame[0].xyz();
    let one_block = frame.len() <= BLOCK;
    if one_block {
        b.offsets(frame, origin);
    }
    // Pass 1: the first moment about the first point.
    let mut first = [[0.0f64; LANES]; 3];
    for (points, m) in frame.chunks(BLOCK).zip(m.chunks(BLOCK)) {
        let len = points.len();
        if !one_block {
            b.offsets(points, origin);
        }
        add_products(&mut first[0], m, &b.x[..len]);
        add_products(&mut first[1], m, &b.y[..len]);
        add_products(&mut first[2], m, &b.z[..len]);
    }
    let first = first.map(|sums| sums.iter().sum::<f64>());
    let center = first.map(|v| v / total);
    // Pass 2: the centred offsets, times the masses, and the six sums (m x) y.
    let mut c = [[0.0f64; LANES]; 6];
    for (points, m) in frame.chunks(BLOCK).zip(m.chunks(BLOCK)) {
        let len = points.len();
        if !one_block {
            b.offsets(points, origin);
        }
        for (v, mv, c) in [
            (&mut b.x, &mut b.mx, center[0]),
            (&mut b.y, &mut b.my, center[1]),
            (&mut b.z, &mut b.mz, center[2]),
        ] {
            for ((v, mv), &m) in v[..len].iter_mut().zip(&mut mv[..len]).zip(m) {
                *v -= c;
                *mv = m * *v;
            }
        }
        add_products(&mut c[0], &b.mx[..len], &b.x[..len]);
        add_products(&mut c[1], &b.mx[..len], &b.y[..len]);
        add_products(&mut c[2], &b.mx[..len], &b.z[..len]);
        add_products(&mut c[3], &b.my[..len], &b.y[..len]);
        add_products(&mut c[4], &b.my[..len], &b.z[..len]);
        add_products(&mut c[5], &b.mz[..len], &b.z[..len]);
    }
    (first, c.map(|sums| sums.iter().sum::<f64>()))
}

/// `sums[i mod LANES] += a_i b_i` over `a` in order, the rest of the division by [`LANES`] to
/// lane 0 after the full lanes (only a frame's last block has one); the lanes are added in
/// order at the end, by the caller.
#[inline(always)]
fn add_products(sums: &mut [f64; LANES], a: &[f64], b: &[f64]) {
    let (a_lanes, a_rest) = a.as_chunks::<LANES>();
    let (b_lanes, b_rest) = b[..a.len()].as_chunks::<LANES>();
    for (a, b) in a_lanes.iter().zip(b_lanes) {
        for l in 0..LANES {
            sums[l] += a[l] * b[l];
        }
    }
    for (a, b) in a_rest.iter().zip(b_rest) {
        sums[0] += a * b;
    }
}

/// The error for frame `t` whose sums are not finite: its first non-finite coordinate, or else
/// offsets beyond the range of double precision.
fn bad_frame<P: Position>(frame: &[P], t: usize) -> Error {
    for (i, &p) in frame.iter().enumerate() {
        for (k, &x) in p.xyz().iter().enumerate() {
            if let Err(error) = finite(&format!("positions[{t}, {i}, {k}]"), x) {
                return error;
            }
        }
    }
    frame_overflow(t)
}

/// The error for frame `t` whose inertia overflows double precision.
fn frame_overflow(t: usize) -> Error {
    Error::InvalidArgument {
        name: "positions".into(),
        reason: format!(
            "the inertia of frame {t} overflows double precision (beyond the largest double, \
             {:e}).",
            f64::MAX
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame's tensor from the textbook sums about the centre of mass, in f64.
    fn reference(masses: &[f64], frame: &[[f64; 3]]) -> [f64; 9] {
        let total: f64 = masses.iter().sum();
        let mut com = [0.0; 3];
        for (m, p) in masses.iter().zip(frame) {
            for k in 0..3 {
                com[k] += m * p[k] / total;
            }
        }
        let mut out = [0.0; 9];
        for (m, p) in masses.iter().zip(frame) {
            let r = [p[0] - com[0], p[1] - com[1], p[2] - com[2]];
            let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
            for i in 0..3 {
                for j in 0..3 {
                    let delta = if i == j { r2 } else { 0.0 };
                    out[3 * i + j] += m * (delta - r[i] * r[j]);
                }
            }
        }
        out
    }

    #[test]
    fn frames_match_the_textbook_sums_and_single_precision_input() {
        let masses = [1.0, 2.0, 3.5, 0.25];
        let frames: Vec<[f64; 3]> = (0..4 * 5)
            .map(|i| {
                let x = i as f64;
                [(x * 0.7).sin() * 2.0, (x * 1.3).cos(), 0.25 * x - 1.0]
            })
            .collect();
        let mut out = vec![0.0; 9 * 5];
        point_masses_inertia(&masses, &frames, &mut out).unwrap();
        for t in 0..5 {
            let expected = reference(&masses, &frames[4 * t..4 * t + 4]);
            let scale = expected[0] + expected[4] + expected[8];
            for k in 0..9 {
                assert!((out[9 * t + k] - expected[k]).abs() <= 1e-14 * scale);
            }
        }
        // Single precision: the same as its exact conversion to double.
        let single: Vec<[f32; 3]> = frames
            .iter()
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32])
            .collect();
        let widened: Vec<[f64; 3]> = single
            .iter()
            .map(|p| [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])])
            .collect();
        let mut a = vec![0.0; 9 * 5];
        let mut b = vec![0.0; 9 * 5];
        point_masses_inertia(&masses, &single, &mut a).unwrap();
        point_masses_inertia(&masses, &widened, &mut b).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn far_and_extreme_frames_keep_their_digits() {
        // A cloud 1e12 from the origin (its coordinates stay exact there: multiples of 1/2),
        // and the same cloud scaled by 2^-500 and 2^+500 (exact scalings: the tensors scale by
        // 2^-1000 and 2^1000).
        let masses = [1.0, 2.0, 3.0];
        let base = [[0.0, 0.0, 0.0], [1.0, 0.5, 0.0], [0.0, 1.0, 2.0]];
        let mut expected = [0.0; 9];
        point_masses_inertia(&masses, &base, &mut expected).unwrap();
        let trace = expected[0] + expected[4] + expected[8];
        let far: Vec<[f64; 3]> = base
            .iter()
            .map(|p| [p[0] + 1e12, p[1] - 1e12, p[2] + 1e12])
            .collect();
        let mut out = [0.0; 9];
        point_masses_inertia(&masses, &far, &mut out).unwrap();
        for k in 0..9 {
            assert!((out[k] - expected[k]).abs() <= 1e-15 * trace, "{k}");
        }
        for s in [-500, 500] {
            let scale = 2f64.powi(s);
            let scaled: Vec<[f64; 3]> = base
                .iter()
                .map(|p| [p[0] * scale, p[1] * scale, p[2] * scale])
                .collect();
            point_masses_inertia(&masses, &scaled, &mut out).unwrap();
            for k in 0..9 {
                let want = expected[k] * scale * scale;
                assert!(
                    (out[k] - want).abs() <= 1e-15 * trace * scale * scale,
                    "{s}: {k}"
                );
            }
        }
    }

    #[test]
    fn a_cancelled_monitor_stops_the_frames() {
        let masses = [1.0, 2.0];
        let frames = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]].repeat(40_000);
        let mut out = vec![0.0; 9 * 40_000];
        let monitor = Monitor::new();
        point_masses_inertia_monitored(&masses, &frames, &mut out, Some(&monitor)).unwrap();
        assert!((out[9 * 39_999 + 4] - 2.0 / 3.0).abs() < 1e-15); // I_yy = mu d^2
        monitor.cancel();
        let error =
            point_masses_inertia_monitored(&masses, &frames, &mut out, Some(&monitor)).unwrap_err();
        assert_eq!(error, Error::Interrupted);
    }

    #[test]
    fn bad_input_is_named() {
        let mut out = [0.0; 18];
        let frames = [[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], [f64::NAN, 0.0, 0.0]];
        let error = point_masses_inertia(&[1.0, 1.0], &frames, &mut out).unwrap_err();
        assert!(matches!(error, Error::NonFinite { ref name, .. } if name == "positions[1, 1, 0]"));
        let error = point_masses_inertia(&[1.0, 0.0], &frames, &mut out).unwrap_err();
        assert!(matches!(error, Error::NonPositive { ref name, .. } if name == "masses[1]"));
        let error = point_masses_inertia(&[], &frames, &mut out).unwrap_err();
        assert!(matches!(error, Error::Shape { ref name, .. } if name == "masses"));
        let error = point_masses_inertia(&[1.0, 1.0, 1.0], &frames, &mut out).unwrap_err();
        assert!(matches!(error, Error::Shape { ref name, .. } if name == "positions"));
        let huge = [[-1e300, 0.0, 0.0], [1e300, 0.0, 0.0]];
        let error = point_masses_inertia(&[1.0, 1.0], &huge, &mut out[..9]).unwrap_err();
        assert!(matches!(error, Error::InvalidArgument { ref name, .. } if name == "positions"));
        let wide = [[-1e200, 0.0, 0.0], [1e200, 0.0, 0.0]];
        let error = point_masses_inertia(&[1.0, 1.0], &wide, &mut out[..9]).unwrap_err();
        assert!(matches!(error, Error::InvalidArgument { ref name, .. } if name == "positions"));
    }
}
