//! Mass properties and principal axes against closed forms and brute-force sums, plus
//! property tests (proptest): invariance under rotation and translation, exact parallel-axis
//! relations, reconstruction.

use nalgebra::{Matrix3, Rotation3, Vector3};
use polhode::{symmetric_eigen3, MassProperties};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

/// Inertia of point masses about the origin by the textbook sum, I = sum m (r^2 1 - r r^T).
fn brute_inertia(masses: &[f64], positions: &[Vector3<f64>]) -> Matrix3<f64> {
    masses
        .iter()
        .zip(positions)
        .fold(Matrix3::zeros(), |acc, (&m, r)| {
            acc + (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * m
        })
}

#[test]
fn cube_about_a_corner_has_the_textbook_moments() {
    // A uniform cube of side a about a corner: M a^2 (1/6, 11/12, 11/12), the unique axis
    // along the body diagonal.
    let (m, a) = (3.0, 0.5);
    let cube = MassProperties::cuboid(m, Vector3::repeat(a)).unwrap();
    let p = symmetric_eigen3(&cube.inertia_about(&Vector3::repeat(-a / 2.0)).unwrap()).unwrap();
    let expected = [1.0 / 6.0, 11.0 / 12.0, 11.0 / 12.0].map(|k| k * m * a * a);
    for (k, value) in expected.iter().enumerate() {
        assert!(
            rel(p.moments[k], *value) < 4.0 * EPS,
            "{k}: {}",
            p.moments[k]
        );
    }
    assert_eq!(p.multiplicity, [1, 2, 2]);
    let diagonal = Vector3::repeat(1.0).normalize();
    assert!((p.axes.column(0).dot(&diagonal) - 1.0).abs() < 4.0 * EPS);
}

#[test]
fn cylinder_moments_match_the_closed_form() {
    let (m, a, l) = (2.5, 0.3, 1.7);
    let p = MassProperties::cylinder(m, a, l).unwrap().principal();
    let transverse = m / 4.0 * (a * a + l * l / 3.0);
    assert!(rel(p.moments[0], m * a * a / 2.0) < 2.0 * EPS);
    assert!(rel(p.moments[1], transverse) < 2.0 * EPS);
    assert!(rel(p.moments[2], transverse) < 2.0 * EPS);
    // Canonical frame: the symmetry axis z first, then x and y in order.
    assert_eq!(
        p.axes,
        Matrix3::new(0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0)
    );
}

#[test]
fn solids_match_point_clouds_sampled_on_a_grid() {
    // A midpoint grid over the bounding box approximates each solid's second moments to
    // O(h^2) (interior cells) plus O(h) from the boundary; 1e-2 at 120^3 cells.
    fn grid(inside: impl Fn(Vector3<f64>) -> bool, half: Vector3<f64>) -> MassProperties {
        let n = 120;
        let (mut masses, mut points) = (Vec::new(), Vec::new());
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let f = |idx: usize, h: f64| -h + (idx as f64 + 0.5) * 2.0 * h / n as f64;
                    let p = Vector3::new(f(i, half.x), f(j, half.y), f(k, half.z));
                    if inside(p) {
                        masses.push(1.0);
                        points.push(p);
                    }
                }
            }
        }
        let total = masses.len() as f64;
        let masses: Vec<f64> = masses.iter().map(|m| m / total).collect();
        MassProperties::point_masses(&masses, &points).unwrap()
    }
    let cases: Vec<(MassProperties, MassProperties)> = vec![
        (
            MassProperties::torus(1.0, 1.0, 0.4).unwrap(),
            grid(
                |p| {
                    let rho = (p.x * p.x + p.y * p.y).sqrt();
                    (rho - 1.0).powi(2) + p.z * p.z <= 0.16
                },
                Vector3::new(1.4, 1.4, 0.4),
            ),
        ),
        (
            MassProperties::capsule(1.0, 0.3, 1.0).unwrap(),
            grid(
                |p| {
                    let z = (p.z.abs() - 0.5).max(0.0);
                    p.x * p.x + p.y * p.y + z * z <= 0.09
                },
                Vector3::new(0.3, 0.3, 0.8),
            ),
        ),
        (
            MassProperties::cone(1.0, 0.5, 1.2).unwrap(),
            grid(
                |p| {
                    let z = p.z + 0.6; // grid centred at the middle of the height
                    (0.0..=1.2).contains(&z)
                        && (p.x * p.x + p.y * p.y).sqrt() <= 0.5 * (1.0 - z / 1.2)
                },
                Vector3::new(0.5, 0.5, 0.6),
            )
            .translated(&Vector3::new(0.0, 0.0, 0.6))
            .unwrap(),
        ),
    ];
    for (exact, sampled) in cases {
        let (a, b) = (exact.inertia(), sampled.inertia());
        assert!((a - b).norm() < 1e-2 * a.norm(), "{a} vs {b}");
        assert!((exact.center_of_mass() - sampled.center_of_mass()).norm() < 1e-2);
    }
}

#[test]
fn general_origin_shift_formula_holds() {
    // For r' = r + R: I'_ij = I_ij + M (R^2 d_ij - R_i R_j) + M (2 r_cm.R d_ij - r_cm_i R_j - R_i r_cm_j),
    // with I and r_cm about the old origin.
    let masses = [1.0, 2.0, 0.5, 3.0];
    let points = [
        Vector3::new(0.1, 0.2, -0.3),
        Vector3::new(-1.0, 0.4, 0.0),
        Vector3::new(0.3, -0.7, 1.1),
        Vector3::new(0.0, 0.5, 0.25),
    ];
    let shift = Vector3::new(0.7, -1.3, 2.1);
    let body = MassProperties::point_masses(&masses, &points).unwrap();
    let total: f64 = masses.iter().sum();
    let r_cm = body.center_of_mass();
    let old = body.inertia_about(&Vector3::zeros()).unwrap();
    let formula = old
        + (Matrix3::identity() * shift.norm_squared() - shift * shift.transpose()) * total
        + (Matrix3::identity() * (2.0 * r_cm.dot(&shift))
            - r_cm * shift.transpose()
            - shift * r_cm.transpose())
            * total;
    // The same body seen from an origin at -R (every point at r + R).
    let new = body.inertia_about(&(-shift)).unwrap();
    let shifted: Vec<_> = points.iter().map(|p| p + shift).collect();
    let brute = brute_inertia(&masses, &shifted);
    assert!((new - formula).norm() < 1e-14 * new.norm());
    assert!((new - brute).norm() < 1e-14 * new.norm());
}

#[test]
fn far_cube_corners_keep_moments_exactly_four() {
    let offset = Vector3::repeat(1e8);
    let corners: Vec<_> = (0..8)
        .map(|i| {
            Vector3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) + offset
        })
        .collect();
    let cloud = MassProperties::point_masses(&[1.0; 8], &corners).unwrap();
    let composite = corners
        .iter()
        .map(|c| MassProperties::point(1.0).unwrap().translated(c).unwrap())
        .reduce(|a, b| a + b)
        .unwrap();
    for body in [cloud, composite] {
        let p = body.principal();
        for k in 0..3 {
            assert!(rel(p.moments[k], 4.0) <= 1e-12, "{}", p.moments[k]);
        }
    }
}

#[test]
fn heavy_sphere_with_a_speck_keeps_its_small_axis() {
    let direction = Vector3::new(0.3, -0.5, 0.8).normalize();
    let body = MassProperties::sphere(1e6, 1.0).unwrap()
        + MassProperties::point(1e-6)
            .unwrap()
            .translated(&direction)
            .unwrap();
    let p = body.principal();
    assert_eq!(p.multiplicity, [1, 2, 2]);
    let angle = p.axes.column(0).cross(&direction).norm();
    assert!(angle <= 1e-12, "{angle}");
}

#[test]
fn nearly_collinear_cloud_keeps_its_smallest_moment() {
    // 1000 masses on a line with 1e-8 lateral jitter. Reference from the exact coordinates
    // (t, a, b) in the line's frame (u, e1, e2), with no cancellation: the two small moments of
    // C sum to the trace of the Schur complement C_ll - c c^T / C_tt (the lateral block minus
    // the tilt of the best-fit line), exact up to O(C_ll^2 / C_tt), 1e-15 relative here.
    let u = Vector3::new(1.0, 2.0, -2.0) / 3.0;
    let e1 = Vector3::new(2.0, 1.0, 2.0) / 3.0;
    let e2 = u.cross(&e1);
    let mut state = 7_u64;
    let mut jitter = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2e-8
    };
    let (mut points, mut coordinates) = (Vec::new(), Vec::new());
    for i in 0..1000 {
        let (t, a, b) = (i as f64 / 999.0, jitter(), jitter());
        coordinates.push([t, a, b]);
        points.push(u * t + e1 * a + e2 * b);
    }
    let mean = |k: usize| coordinates.iter().map(|c| c[k]).sum::<f64>() / 1000.0;
    let (mt, ma, mb) = (mean(0), mean(1), mean(2));
    let sum = |f: &dyn Fn(&[f64; 3]) -> f64| coordinates.iter().map(f).sum::<f64>();
    let c_tt = sum(&|c| (c[0] - mt).powi(2));
    let c_ta = sum(&|c| (c[0] - mt) * (c[1] - ma));
    let c_tb = sum(&|c| (c[0] - mt) * (c[2] - mb));
    let c_ll = sum(&|c| (c[1] - ma).powi(2) + (c[2] - mb).powi(2));
    let expected = c_ll - (c_ta * c_ta + c_tb * c_tb) / c_tt;
    let p = MassProperties::point_masses(&[1.0; 1000], &points)
        .unwrap()
        .principal();
    assert!(
        rel(p.moments[0], expected) <= 1e-6,
        "{} vs {expected}",
        p.moments[0]
    );
}

#[test]
fn scaling_by_extreme_factors_scales_results_exactly() {
    let base = MassProperties::cylinder(2.0, 0.3, 1.1).unwrap()
        + MassProperties::cuboid(1.0, Vector3::new(0.2, 0.5, 0.9))
            .unwrap()
            .rotated(Rotation3::from_euler_angles(0.3, 0.2, 0.1).matrix())
            .unwrap()
            .translated(&Vector3::new(0.4, -0.2, 0.3))
            .unwrap();
    let p = base.principal();
    for scale in [1e-12, 1e12] {
        let scaled = base.scaled(scale, scale).unwrap().principal();
        for k in 0..3 {
            assert!(rel(scaled.moments[k], p.moments[k] * scale.powi(3)) < 8.0 * EPS);
        }
        assert!((scaled.axes - p.axes).norm() < 1e-14);
    }
}

#[test]
fn validity_checks_reject_bad_tensors_and_accept_planar_and_collinear_ones() {
    let zero = Vector3::zeros();
    // Planar (I1 + I2 = I3) and collinear (a zero moment) bodies are valid.
    let planar = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
    let rod = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.0));
    let r = Rotation3::from_euler_angles(0.7, -0.4, 1.9);
    for t in [planar, rod] {
        let rotated = r.matrix() * t * r.transpose();
        assert!(MassProperties::from_inertia(1.0, &rotated, &zero).is_ok());
    }
    let broken = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0 + 1e-9));
    assert!(matches!(
        MassProperties::from_inertia(1.0, &broken, &zero),
        Err(polhode::Error::InvalidInertia { .. })
    ));
    let asymmetric = Matrix3::new(1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert!(MassProperties::from_inertia(1.0, &asymmetric, &zero).is_err());
    assert!(MassProperties::sphere(-1.0, 1.0).is_err());
    assert!(MassProperties::sphere(1.0, f64::NAN).is_err());
    assert!(MassProperties::point_masses(&[1.0, 0.0], &[zero, zero]).is_err());
    // The cone's third argument is its length along the axis.
    assert!(matches!(
        MassProperties::cone(1.0, 0.5, 0.0),
        Err(polhode::Error::NonPositive { name, .. }) if name == "length"
    ));
}

fn arb_rotation() -> impl Strategy<Value = Rotation3<f64>> {
    (-3.1..3.1f64, -1.5..1.5f64, -3.1..3.1f64)
        .prop_map(|(a, b, c)| Rotation3::from_euler_angles(a, b, c))
}

fn arb_cloud() -> impl Strategy<Value = (Vec<f64>, Vec<Vector3<f64>>)> {
    prop::collection::vec(
        (0.1..10.0f64, -5.0..5.0f64, -5.0..5.0f64, -5.0..5.0f64),
        1..40,
    )
    .prop_map(|v| {
        let masses = v.iter().map(|t| t.0).collect();
        let points = v.iter().map(|t| Vector3::new(t.1, t.2, t.3)).collect();
        (masses, points)
    })
}

proptest! {
    #[test]
    fn point_masses_match_the_brute_sum((masses, points) in arb_cloud()) {
        let body = MassProperties::point_masses(&masses, &points).unwrap();
        let brute = brute_inertia(&masses, &points);
        let about_origin = body.inertia_about(&Vector3::zeros()).unwrap();
        prop_assert!((about_origin - brute).norm() <= 1e-12 * brute.norm());
    }

    #[test]
    fn moments_are_invariant_under_rotation_and_translation(
        (masses, points) in arb_cloud(), r in arb_rotation(),
        t in (-100.0..100.0f64, -100.0..100.0f64, -100.0..100.0f64),
    ) {
        let body = MassProperties::point_masses(&masses, &points).unwrap();
        let moved = body.rotated(r.matrix()).unwrap().translated(&Vector3::new(t.0, t.1, t.2)).unwrap();
        let (p, q) = (body.principal(), moved.principal());
        let scale = p.moments[2];
        for k in 0..3 {
            prop_assert!((p.moments[k] - q.moments[k]).abs() <= 1e-13 * scale);
        }
        // The inertia tensor rotates as R I R^T.
        let rotated = r.matrix() * body.inertia() * r.transpose();
        prop_assert!((moved.inertia() - rotated).norm() <= 1e-13 * scale);
    }

    #[test]
    fn principal_frame_reconstructs_the_tensor((masses, points) in arb_cloud(), r in arb_rotation()) {
        let body = MassProperties::point_masses(&masses, &points).unwrap().rotated(r.matrix()).unwrap();
        for p in [body.principal(), symmetric_eigen3(&body.inertia()).unwrap()] {
            let inertia = body.inertia();
            let rebuilt = p.axes * Matrix3::from_diagonal(&p.moments) * p.axes.transpose();
            prop_assert!((rebuilt - inertia).norm() <= 10.0 * EPS * inertia.norm());
            prop_assert!((p.axes.determinant() - 1.0).abs() <= 1e-14);
            prop_assert!(p.moments[0] <= p.moments[1] && p.moments[1] <= p.moments[2]);
        }
    }

    #[test]
    fn composites_follow_the_parallel_axis_theorem(
        (ma, pa) in arb_cloud(), (mb, pb) in arb_cloud(), r in arb_rotation(),
    ) {
        let a = MassProperties::point_masses(&ma, &pa).unwrap();
        let b = MassProperties::point_masses(&mb, &pb).unwrap().rotated(r.matrix()).unwrap();
        let sum = a + b;
        let about = |body: &MassProperties| body.inertia_about(&Vector3::new(1.0, -2.0, 0.5)).unwrap();
        let expected = about(&a) + about(&b);
        prop_assert!((about(&sum) - expected).norm() <= 1e-12 * expected.norm());
        prop_assert!(((a + b).inertia() - (b + a).inertia()).norm() <= 1e-13 * expected.norm());
    }

    #[test]
    fn eigensolve_is_backward_stable_on_any_symmetric_tensor(
        d in (-1e3..1e3f64, -1e3..1e3f64, -1e3..1e3f64), r in arb_rotation(), exponent in -200..200i32,
    ) {
        let scale = 2f64.powi(exponent);
        let a = r.matrix() * Matrix3::from_diagonal(&Vector3::new(d.0, d.1, d.2)) * r.transpose() * scale;
        let a = (a + a.transpose()) * 0.5;
        let p = symmetric_eigen3(&a).unwrap();
        let residual = (a * p.axes - p.axes * Matrix3::from_diagonal(&p.moments)).norm();
        prop_assert!(residual <= 10.0 * EPS * a.norm());
        prop_assert!((p.axes.transpose() * p.axes - Matrix3::identity()).norm() <= 8.0 * EPS);
    }
}

/// The table of solids builds each by name, as its own constructor does; an unknown name or a
/// wrong number of parameters is an error naming it.
#[test]
fn every_solid_is_built_by_name() {
    use polhode::mass::SOLIDS;
    for solid in SOLIDS {
        let width: usize = solid.parameters.iter().map(|&(_, w)| w).sum();
        // Distinct lengths, in increasing order (a tube's inner radius below its outer, a
        // torus's minor radius below its major: the minor listed second, so reversed).
        let mut values: Vec<f64> = (0..width).map(|i| 0.5 + 0.25 * i as f64).collect();
        if solid.name == "torus" {
            values.reverse();
        }
        let body = MassProperties::solid(solid.name, 2.0, &values).unwrap();
        assert_eq!(body.mass(), 2.0, "{}", solid.name);
        let wrong = MassProperties::solid(solid.name, 2.0, &[1.0; 7]).unwrap_err();
        assert_eq!(wrong.argument(), Some("parameters"), "{}", solid.name);
    }
    let expected = MassProperties::tube(2.0, 0.5, 0.75, 1.0).unwrap();
    assert_eq!(
        MassProperties::solid("tube", 2.0, &[0.5, 0.75, 1.0]).unwrap(),
        expected
    );
    let unknown = MassProperties::solid("blob", 1.0, &[]).unwrap_err();
    assert_eq!(unknown.argument(), Some("kind"));
}
