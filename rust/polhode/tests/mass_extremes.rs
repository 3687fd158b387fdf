//! Mass properties at the edges of double precision, bit for bit the same under any number of
//! threads, and stopped by a cancelled monitor.

use nalgebra::{Matrix3, Rotation3, Vector3};
use polhode::eigen::{principal_batch, principal_batch_monitored};
use polhode::Monitor;
use polhode::{symmetric_eigen3, Error, MassProperties};

const EPS: f64 = f64::EPSILON;

/// A deterministic pseudo-random number in [-1, 1) (a 64-bit LCG), so that the tests need no
/// random-number crate.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// `work` run on a pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(work)
}

/// Every number a body reports, as bits.
fn bits(body: &MassProperties) -> Vec<u64> {
    let p = body.principal();
    let mut out = vec![body.mass().to_bits()];
    out.extend(body.center_of_mass().iter().map(|x| x.to_bits()));
    out.extend(body.inertia().iter().map(|x| x.to_bits()));
    out.extend(body.second_moment().iter().map(|x| x.to_bits()));
    out.extend(p.moments.iter().map(|x| x.to_bits()));
    out.extend(p.axes.iter().map(|x| x.to_bits()));
    out
}

/// A closed torus of `nu * nv` quads (two triangles each), far from the origin.
fn torus(nu: usize, nv: usize) -> (Vec<[f64; 3]>, Vec<[i64; 3]>) {
    let mut vertices = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = std::f64::consts::TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let v = std::f64::consts::TAU * j as f64 / nv as f64;
            let ring = 3.0 + v.cos();
            vertices.push([ring * u.cos() + 1e3, ring * u.sin() - 2e3, v.sin() + 5e2]);
        }
    }
    let index = |i: usize, j: usize| ((i % nu) * nv + j % nv) as i64;
    let mut faces = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    (vertices, faces)
}

#[test]
fn mass_properties_are_bit_identical_for_any_number_of_threads() {
    let mut rng = Lcg(7);
    let n = 300_000; // ten chunks
    let masses: Vec<f64> = (0..n).map(|_| 1.1 + rng.next()).collect();
    let positions: Vec<[f64; 3]> = (0..n)
        .map(|_| [rng.next() + 1e3, 2.0 * rng.next(), 3.0 * rng.next() - 5e2])
        .collect();
    let (vertices, faces) = torus(300, 200);
    let tensors: Vec<f64> = (0..9 * 20_000).map(|_| rng.next()).collect();
    let run = || {
        let points = MassProperties::point_masses(&masses, &positions).unwrap();
        let solid = MassProperties::mesh(&vertices, &faces, Some(1.0), None, false, true).unwrap();
        let shell = MassProperties::mesh(&vertices, &faces, Some(1.0), None, true, false).unwrap();
        let m = tensors.len() / 9;
        let (mut moments, mut axes, mut multiplicity) =
            (vec![0.0; 3 * m], vec![0.0; 9 * m], vec![0i64; 3 * m]);
        // Symmetric tensors from the random numbers: the batch only reads the upper triangle's
        // mirror for the check, so symmetrise first.
        let mut symmetric = tensors.clone();
        for t in symmetric.chunks_mut(9) {
            for (r, c) in [(0, 1), (0, 2), (1, 2)] {
                t[3 * c + r] = t[3 * r + c];
            }
        }
        principal_batch(&symmetric, 0.0, &mut moments, &mut axes, &mut multiplicity).unwrap();
        let batch: Vec<u64> = moments.iter().chain(&axes).map(|x| x.to_bits()).collect();
        (bits(&points), bits(&solid), bits(&shell), batch)
    };
    let one = on_threads(1, run);
    for threads in [2, 3, 4] {
        assert!(
            on_threads(threads, run) == one,
            "{threads} threads differ from one"
        );
    }
}

#[test]
fn principal_is_right_and_keeps_multiplicities_at_every_scale() {
    let r = Rotation3::from_euler_angles(0.3, -1.1, 2.0);
    let a = r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.5)) * r.transpose();
    let a = (a + a.transpose()) * 0.5;
    let top = r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 2.0)) * r.transpose();
    let top = (top + top.transpose()) * 0.5;
    let base = symmetric_eigen3(&a).unwrap();
    for exponent in [-1000, -700, -300, 0, 300, 511, 700, 1000] {
        // A power of two: the exact eigenvalues are those of `a` times it.
        let s = 2f64.powi(exponent);
        let p = symmetric_eigen3(&(a * s)).unwrap();
        assert_eq!(p.multiplicity, [1, 1, 1], "2^{exponent}");
        for k in 0..3 {
            assert_eq!(p.moments[k], base.moments[k] * s, "2^{exponent}");
        }
        assert_eq!(p.axes, base.axes, "2^{exponent}");
        let q = symmetric_eigen3(&(top * s)).unwrap();
        assert_eq!(q.multiplicity, [2, 2, 1], "2^{exponent}");
    }
    // Subnormal entries: finite, within 10 eps ||A|| plus the spacing of subnormals.
    let tiny = a * 1e-310;
    let p = symmetric_eigen3(&tiny).unwrap();
    for k in 0..3 {
        let expected = base.moments[k] * 1e-310;
        assert!((p.moments[k] - expected).abs() <= 10.0 * EPS * 3.5e-310 + 4e-323);
    }
    // Moments beyond the largest double: a named error.
    let beyond = Matrix3::new(1e308, 0.9e308, 0.0, 0.9e308, 1e308, 0.0, 0.0, 0.0, 1e308);
    match symmetric_eigen3(&beyond) {
        Err(Error::InvalidArgument { name, reason }) => {
            assert_eq!(name, "inertia");
            assert!(reason.contains("overflow"), "{reason}");
        }
        other => panic!("expected an overflow error, got {other:?}"),
    }
}

#[test]
fn bodies_are_right_up_to_the_largest_double_and_named_beyond() {
    // from_inertia of 8e307 (the trace overflows 3 of them).
    let body = MassProperties::from_inertia(1.0, &(Matrix3::identity() * 8e307), &Vector3::zeros())
        .unwrap();
    assert!((body.inertia() - Matrix3::identity() * 8e307).amax() <= 8.0 * EPS * 8e307);
    // A composite whose shift term is 2^1023: right; at twice the distance: named.
    let sphere = MassProperties::sphere(2f64.powi(400), 1.0).unwrap();
    let near = sphere
        .try_add(
            &sphere
                .translated(&Vector3::new(2f64.powi(312), 0.0, 0.0))
                .unwrap(),
        )
        .unwrap();
    let i = near.inertia();
    assert!((i[(1, 1)] - 2f64.powi(1023)).abs() <= 4.0 * EPS * 2f64.powi(1023));
    let far = sphere
        .translated(&Vector3::new(2f64.powi(313), 0.0, 0.0))
        .unwrap();
    assert!(matches!(
        sphere.try_add(&far),
        Err(Error::InvalidArgument { name, .. }) if name == "other"
    ));
    // Solids: m r^2 must not overflow on the way.
    let r = (0.9 * f64::MAX).sqrt() / 0.4f64.sqrt();
    let big = MassProperties::sphere(1.0, r).unwrap();
    assert!((big.principal().moments[0] / (0.9 * f64::MAX) - 1.0).abs() <= 8.0 * EPS);
    assert!(matches!(
        MassProperties::sphere(1.0, 2.0 * r),
        Err(Error::InvalidArgument { name, .. }) if name == "radius"
    ));
    assert!(matches!(
        MassProperties::sphere(f64::MAX, 2.0),
        Err(Error::InvalidArgument { name, .. }) if name == "mass"
    ));
}

#[test]
fn a_cancelled_monitor_stops_the_long_paths() {
    let monitor = Monitor::new();
    monitor.cancel();
    let n = 100_000;
    let masses = vec![1.0; n];
    let positions: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.0, 1.0]).collect();
    assert_eq!(
        MassProperties::point_masses_monitored(&masses, &positions, Some(&monitor)).unwrap_err(),
        Error::Interrupted
    );
    let tensors: Vec<f64> = (0..9 * n)
        .map(|i| if i % 4 == 0 { 1.0 } else { 0.0 })
        .collect();
    let (mut m, mut x, mut u) = (vec![0.0; 3 * n], vec![0.0; 9 * n], vec![0i64; 3 * n]);
    assert_eq!(
        principal_batch_monitored(&tensors, 0.0, &mut m, &mut x, &mut u, Some(&monitor))
            .unwrap_err(),
        Error::Interrupted
    );
    // Not cancelled: the same as without a monitor.
    let fresh = Monitor::new();
    let watched =
        MassProperties::point_masses_monitored(&masses, &positions, Some(&fresh)).unwrap();
    let plain = MassProperties::point_masses(&masses, &positions).unwrap();
    assert_eq!(bits(&watched), bits(&plain));
}
