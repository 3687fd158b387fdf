//! Mesh mass properties against closed forms of exact polyhedra, convergence on icospheres,
//! far-offset robustness and the validation of bad meshes.

use std::collections::HashMap;

use nalgebra::{Matrix3, Rotation3, Vector3};
use polhode::{Error, MassProperties};

type Mesh = (Vec<[f64; 3]>, Vec<[i64; 3]>);

/// Normwise relative difference of two matrices.
fn rel_m(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    (a - b).norm() / b.norm()
}

/// A box with full sides `size`, centred at `center`, as 12 outward triangles.
fn box_mesh(size: [f64; 3], center: [f64; 3]) -> Mesh {
    let mut v = Vec::new();
    for k in 0..8 {
        let s = |bit: usize, axis: usize| {
            let sign = if k >> bit & 1 == 1 { 0.5 } else { -0.5 };
            center[axis] + sign * size[axis]
        };
        v.push([s(0, 0), s(1, 1), s(2, 2)]);
    }
    // Vertex k has x bit 0, y bit 1, z bit 2.
    let f = vec![
        [0, 2, 3],
        [0, 3, 1], // z-
        [4, 5, 7],
        [4, 7, 6], // z+
        [0, 1, 5],
        [0, 5, 4], // y-
        [2, 6, 7],
        [2, 7, 3], // y+
        [0, 4, 6],
        [0, 6, 2], // x-
        [1, 3, 7],
        [1, 7, 5], // x+
    ];
    (v, f)
}

fn octahedron(r: f64) -> Mesh {
    let v = vec![
        [r, 0.0, 0.0],
        [-r, 0.0, 0.0],
        [0.0, r, 0.0],
        [0.0, -r, 0.0],
        [0.0, 0.0, r],
        [0.0, 0.0, -r],
    ];
    let mut f = Vec::new();
    for (x, y, z) in [
        (0, 2, 4),
        (2, 1, 4),
        (1, 3, 4),
        (3, 0, 4),
        (2, 0, 5),
        (1, 2, 5),
        (3, 1, 5),
        (0, 3, 5),
    ] {
        f.push([x, y, z]);
    }
    (v, f)
}

/// An icosahedron subdivided `levels` times, vertices projected on the sphere of `radius`.
fn icosphere(levels: usize, radius: f64) -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<Vector3<f64>> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vector3::from(*p).normalize())
    .collect();
    let mut f: Vec<[i64; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid: HashMap<(i64, i64), i64> = HashMap::new();
        let mut midpoint = |a: i64, b: i64, v: &mut Vec<Vector3<f64>>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                v.len() as i64 - 1
            })
        };
        let mut next = Vec::with_capacity(4 * f.len());
        for [a, b, c] in f {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    (v.iter().map(|p| (p * radius).into()).collect(), f)
}

fn solid(mesh: &Mesh, density: f64) -> MassProperties {
    MassProperties::mesh(&mesh.0, &mesh.1, Some(density), None, false, false).unwrap()
}

fn shell(mesh: &Mesh, mass: f64) -> MassProperties {
    MassProperties::mesh(&mesh.0, &mesh.1, None, Some(mass), true, false).unwrap()
}

#[test]
fn box_matches_the_closed_form() {
    let (a, b, c) = (0.3, 1.1, 2.5);
    let rho = 2.7;
    let mesh = box_mesh([a, b, c], [0.4, -1.3, 2.0]);
    let body = solid(&mesh, rho);
    let m = rho * a * b * c;
    assert!((body.mass() - m).abs() <= 1e-15 * m);
    assert!((body.center_of_mass() - Vector3::new(0.4, -1.3, 2.0)).norm() <= 1e-15 * 2.5);
    let expected = Matrix3::from_diagonal(&Vector3::new(
        m * (b * b + c * c) / 12.0,
        m * (a * a + c * c) / 12.0,
        m * (a * a + b * b) / 12.0,
    ));
    assert!(rel_m(&body.inertia(), &expected) <= 1e-14);
}

#[test]
fn rotated_box_has_the_rotated_tensor_with_the_right_product_signs() {
    let (a, b, c) = (0.5, 1.0, 2.0);
    let r = Rotation3::from_euler_angles(0.3, -0.7, 1.9);
    let (v, f) = box_mesh([a, b, c], [0.0; 3]);
    let v: Vec<[f64; 3]> = v.iter().map(|p| (r * Vector3::from(*p)).into()).collect();
    let body = solid(&(v, f), 1.0);
    let m = a * b * c;
    let diag = Matrix3::from_diagonal(&Vector3::new(
        m * (b * b + c * c) / 12.0,
        m * (a * a + c * c) / 12.0,
        m * (a * a + b * b) / 12.0,
    ));
    let expected = r.matrix() * diag * r.matrix().transpose();
    assert!(rel_m(&body.inertia(), &expected) <= 1e-14);
}

#[test]
fn corner_tetrahedron_matches_the_closed_form() {
    // Vertices 0, a e1, b e2, c e3: V = abc/6, centre (a, b, c)/4, and about it
    // C_xx = 3/80 M a^2, C_xy = -M a b / 80 (and cyclic).
    let (a, b, c) = (1.5, 0.5, 2.0);
    let v = vec![[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
    let f = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let body = solid(&(v, f), 3.0);
    let m = 3.0 * a * b * c / 6.0;
    assert!((body.mass() - m).abs() <= 1e-15 * m);
    assert!((body.center_of_mass() - Vector3::new(a, b, c) / 4.0).norm() <= 1e-15 * c);
    let l = [a, b, c];
    let second = Matrix3::from_fn(|i, j| {
        if i == j {
            3.0 * m * l[i] * l[i] / 80.0
        } else {
            -m * l[i] * l[j] / 80.0
        }
    });
    assert!(rel_m(&body.second_moment(), &second) <= 1e-14);
    let inertia = Matrix3::identity() * second.trace() - second;
    assert!(rel_m(&body.inertia(), &inertia) <= 1e-14);
}

#[test]
fn octahedron_matches_the_closed_form() {
    // |x| + |y| + |z| <= r: V = 4/3 r^3, I = M r^2 / 5 about every axis.
    let r = 1.7;
    let body = solid(&octahedron(r), 1.0);
    let m = 4.0 * r * r * r / 3.0;
    assert!((body.mass() - m).abs() <= 1e-15 * m);
    let expected = Matrix3::identity() * (m * r * r / 5.0);
    assert!(rel_m(&body.inertia(), &expected) <= 1e-14);
    assert!(body.center_of_mass().norm() <= 1e-15 * r);
}

#[test]
fn hollow_box_sums_the_nested_shells_with_their_signs() {
    let (mut v, mut f) = box_mesh([2.0, 3.0, 4.0], [0.0; 3]);
    let (vi, fi) = box_mesh([1.0, 1.0, 1.0], [0.0; 3]);
    let offset = v.len() as i64;
    v.extend(vi);
    f.extend(
        fi.iter()
            .map(|t| [t[0] + offset, t[2] + offset, t[1] + offset]),
    );
    let body = solid(&(v, f), 1.0);
    let (mo, mi) = (24.0, 1.0);
    assert!((body.mass() - (mo - mi)).abs() <= 1e-14 * mo);
    let c = |m: f64, s: [f64; 3]| Vector3::new(s[0] * s[0], s[1] * s[1], s[2] * s[2]) * m / 12.0;
    let second = c(mo, [2.0, 3.0, 4.0]) - c(mi, [1.0, 1.0, 1.0]);
    assert!(rel_m(&body.second_moment(), &Matrix3::from_diagonal(&second)) <= 1e-14);
}

#[test]
fn icosphere_converges_to_two_fifths_m_r_squared_at_second_order() {
    let r = 1.3;
    let mut errors = Vec::new();
    for level in 2..=5 {
        let body = solid(&icosphere(level, r), 1.0);
        let moments = body.principal().moments;
        let exact = 0.4 * body.mass() * r * r;
        errors.push((moments[2] - exact).abs() / exact);
        // Spherical: all three moments equal to round-off.
        assert!((moments[2] - moments[0]) <= 1e-13 * exact);
    }
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (3.8..4.2).contains(&ratio),
            "ratio {ratio}, errors {errors:?}"
        );
    }
}

#[test]
fn far_offset_icosphere_keeps_its_moments() {
    // Vertices on a 2^-24 grid, so that moving them by an integer up to 1e8 is exact: any
    // difference is the method's own error.
    let (v, f) = icosphere(3, 1.0);
    let snap = |x: f64| (x * 16_777_216.0).round() / 16_777_216.0;
    let v: Vec<[f64; 3]> = v.iter().map(|p| p.map(snap)).collect();
    let base = solid(&(v.clone(), f.clone()), 1.0);
    for e in 2..=8 {
        let d = 10f64.powi(e);
        let shift = Vector3::new(d, -0.5 * d, 0.25 * d);
        let moved: Vec<[f64; 3]> = v
            .iter()
            .map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]])
            .collect();
        for (p, q) in moved.iter().zip(&v) {
            for k in 0..3 {
                assert_eq!(p[k] - shift[k], q[k], "the shift must be exact");
            }
        }
        let body = solid(&(moved, f.clone()), 1.0);
        assert!((body.mass() - base.mass()).abs() <= 1e-13 * base.mass());
        let err = rel_m(&body.inertia(), &base.inertia());
        assert!(err <= 1e-12, "d = {d:e}: relative error {err:e}");
        let com = body.center_of_mass() - shift - base.center_of_mass();
        assert!(
            com.norm() <= 1e-15 * d + 1e-15,
            "d = {d:e}: centre off by {com}"
        );
    }
}

#[test]
fn spherical_shell_converges_to_two_thirds_m_r_squared() {
    let r = 0.7;
    let mut errors = Vec::new();
    for level in 2..=5 {
        let body = shell(&icosphere(level, r), 2.0);
        let exact = 2.0 / 3.0 * 2.0 * r * r;
        errors.push((body.principal().moments[2] - exact).abs() / exact);
    }
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (3.8..4.2).contains(&ratio),
            "ratio {ratio}, errors {errors:?}"
        );
    }
}

#[test]
fn box_shell_matches_the_closed_form() {
    // Surface density sigma: C_xx = sigma (a^3 b / 6 + a^2 b c / 2 + a^3 c / 6) and cyclic.
    let s = [0.5, 1.2, 2.0];
    let body = shell(&box_mesh(s, [1.0, 2.0, 3.0]), 3.0);
    let area = 2.0 * (s[0] * s[1] + s[1] * s[2] + s[2] * s[0]);
    let sigma = 3.0 / area;
    let c = |a: f64, b: f64, c: f64| sigma * (a.powi(3) * (b + c) / 6.0 + a * a * b * c / 2.0);
    let second = Matrix3::from_diagonal(&Vector3::new(
        c(s[0], s[1], s[2]),
        c(s[1], s[2], s[0]),
        c(s[2], s[0], s[1]),
    ));
    assert!(rel_m(&body.second_moment(), &second) <= 1e-14);
    assert!((body.center_of_mass() - Vector3::new(1.0, 2.0, 3.0)).norm() <= 1e-15 * 3.0);
}

fn error_of(mesh: &Mesh, density: Option<f64>, mass: Option<f64>) -> Error {
    MassProperties::mesh(&mesh.0, &mesh.1, density, mass, false, false).unwrap_err()
}

fn name_of(e: &Error) -> String {
    match e {
        Error::InvalidArgument { name, .. } | Error::NonFinite { name, .. } => name.clone(),
        other => panic!("unexpected error {other:?}"),
    }
}

#[test]
fn bad_meshes_are_rejected_naming_the_argument() {
    let good = box_mesh([1.0, 2.0, 3.0], [0.0; 3]);

    let mut open = good.clone();
    open.1.pop();
    let e = error_of(&open, Some(1.0), None);
    assert_eq!(name_of(&e), "faces");
    assert!(e.to_string().contains("not closed"), "{e}");

    let mut flipped = good.clone();
    flipped.1[3].swap(1, 2);
    let e = error_of(&flipped, Some(1.0), None);
    assert_eq!(name_of(&e), "faces");
    assert!(e.to_string().contains("inconsistent"), "{e}");

    let inside_out: Mesh = (
        good.0.clone(),
        good.1.iter().map(|t| [t[0], t[2], t[1]]).collect(),
    );
    let e = error_of(&inside_out, Some(1.0), None);
    assert_eq!(name_of(&e), "faces");
    assert!(e.to_string().contains("inside out"), "{e}");
    assert!(e.to_string().contains("fix_winding"), "{e}");
    let fixed =
        MassProperties::mesh(&inside_out.0, &inside_out.1, Some(1.0), None, false, true).unwrap();
    assert_eq!(fixed, solid(&good, 1.0));

    let mut out_of_range = good.clone();
    out_of_range.1[5][1] = 8;
    assert_eq!(
        name_of(&error_of(&out_of_range, Some(1.0), None)),
        "faces[5, 1]"
    );
    out_of_range.1[5][1] = -1;
    assert_eq!(
        name_of(&error_of(&out_of_range, Some(1.0), None)),
        "faces[5, 1]"
    );

    let mut nan = good.clone();
    nan.0[2][1] = f64::NAN;
    assert!(matches!(
        error_of(&nan, Some(1.0), None),
        Error::NonFinite { ref name, .. } if name == "vertices[2, 1]"
    ));

    let e = error_of(&good, Some(1.0), Some(1.0));
    assert!(e.to_string().contains("both"), "{e}");
    let e = error_of(&good, None, None);
    assert!(e.to_string().contains("neither"), "{e}");
    assert!(matches!(
        error_of(&good, Some(-1.0), None),
        Error::NonPositive { .. }
    ));

    let few: Mesh = (good.0.clone(), good.1[..3].to_vec());
    assert_eq!(name_of(&error_of(&few, Some(1.0), None)), "faces");

    let mut repeated = good.clone();
    repeated.1[0] = [0, 0, 3];
    assert_eq!(name_of(&error_of(&repeated, Some(1.0), None)), "faces[0]");

    // A flat closed mesh: a tetrahedron with four coplanar vertices has zero volume.
    let flat: Mesh = (
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    let e = error_of(&flat, Some(1.0), None);
    assert_eq!(name_of(&e), "vertices");
    assert!(e.to_string().contains("degenerate"), "{e}");
}

#[test]
fn mass_or_density_give_the_same_body() {
    let mesh = octahedron(1.0);
    let by_density = solid(&mesh, 3.0);
    let by_mass = MassProperties::mesh(
        &mesh.0,
        &mesh.1,
        None,
        Some(by_density.mass()),
        false,
        false,
    )
    .unwrap();
    assert!(rel_m(&by_mass.inertia(), &by_density.inertia()) <= 1e-15);
}

#[test]
fn errors_are_found_in_large_meshes_across_parallel_chunks() {
    let (v, f) = icosphere(5, 1.0); // 20480 faces: several chunks and vertex ranges
    let mut flipped = f.clone();
    flipped[15_000].swap(0, 1);
    let e = MassProperties::mesh(&v, &flipped, Some(1.0), None, false, false).unwrap_err();
    assert!(e.to_string().contains("inconsistent"), "{e}");
    let mut open = f.clone();
    open.remove(17_000);
    let e = MassProperties::mesh(&v, &open, Some(1.0), None, false, false).unwrap_err();
    assert!(e.to_string().contains("not closed"), "{e}");
    let mut out_of_range = f.clone();
    out_of_range[19_999][2] = v.len() as i64;
    let e = MassProperties::mesh(&v, &out_of_range, Some(1.0), None, false, false).unwrap_err();
    assert_eq!(name_of(&e), "faces[19999, 2]");
    let mut nan = v.clone();
    nan[10_000][0] = f64::INFINITY;
    let e = MassProperties::mesh(&nan, &f, Some(1.0), None, false, false).unwrap_err();
    assert_eq!(name_of(&e), "vertices[10000, 0]");
}

#[test]
fn two_boxes_sharing_an_edge_are_non_manifold() {
    // Two closed unit cubes touching along one edge: that edge has four faces.
    let (mut v, mut f) = box_mesh([1.0, 1.0, 1.0], [0.0; 3]);
    let (v2, f2) = box_mesh([1.0, 1.0, 1.0], [1.0, 1.0, 0.0]);
    // Reuse the shared edge's vertices (x = y = 0.5, z = +-0.5): corners 3 (x+ y+ z-) and
    // 7 (x+ y+ z+) of the first box are corners 0 (x- y- z-) and 4 (x- y- z+) of the second.
    let base = v.len() as i64;
    let map = |i: i64| match i {
        0 => 3,
        4 => 7,
        _ => base + i,
    };
    v.extend(v2);
    f.extend(f2.iter().map(|t| [map(t[0]), map(t[1]), map(t[2])]));
    let e = MassProperties::mesh(&v, &f, Some(1.0), None, false, false).unwrap_err();
    assert!(e.to_string().contains("non-manifold"), "{e}");
}

#[test]
fn a_cancel_stops_a_mesh_at_any_look_and_watching_changes_no_bit() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    use polhode::mass::MESH_CHUNK;
    use polhode::Monitor;

    // 81920 faces: two blocks of the closedness check, twenty chunks of the integrals.
    let (v, f) = icosphere(6, 1.0);
    assert!(f.len() > MESH_CHUNK);
    for shell in [false, true] {
        let plain = MassProperties::mesh(&v, &f, Some(1.0), None, shell, false).unwrap();
        // Counted: the looks of a whole call, which changes no bit of the result.
        let looks = Arc::new(AtomicUsize::new(0));
        let counting = Monitor::with_on_look({
            let looks = Arc::clone(&looks);
            move |_| {
                looks.fetch_add(1, Ordering::Relaxed);
            }
        });
        let watched =
            MassProperties::mesh_monitored(&v, &f, Some(1.0), None, shell, false, Some(&counting))
                .unwrap();
        assert_eq!(watched.mass().to_bits(), plain.mass().to_bits());
        assert_eq!(watched.center_of_mass(), plain.center_of_mass());
        assert_eq!(watched.second_moment(), plain.second_moment());
        let total = looks.load(Ordering::Relaxed);
        assert!(total >= 20, "{total} looks");
        // Cancelled at the first, a middle or the last look: interrupted, never a result.
        for at in [1, total / 2, total] {
            let seen = Arc::new(AtomicUsize::new(0));
            let monitor = Monitor::with_on_look({
                let seen = Arc::clone(&seen);
                move |monitor| {
                    if seen.fetch_add(1, Ordering::Relaxed) + 1 == at {
                        monitor.cancel();
                    }
                }
            });
            let result = MassProperties::mesh_monitored(
                &v,
                &f,
                Some(1.0),
                None,
                shell,
                false,
                Some(&monitor),
            );
            assert_eq!(
                result.unwrap_err(),
                Error::Interrupted,
                "shell {shell}, look {at}"
            );
        }
    }
}

#[test]
fn the_result_has_the_same_bits_for_any_number_of_threads() {
    // 81920 faces off the origin: twenty chunks of the integrals, each of sixteen-triangle
    // blocks in four lanes, and the closedness check's vertex ranges, on pools of 1, 2, 3 and
    // 8 threads.
    let (v, f) = icosphere(6, 1.3);
    let v: Vec<[f64; 3]> = v
        .iter()
        .map(|p| [p[0] + 1e3, p[1] - 2e3, p[2] + 0.5])
        .collect();
    for shell in [false, true] {
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| MassProperties::mesh(&v, &f, Some(1.0), None, shell, false).unwrap())
        };
        let one = run(1);
        for threads in [2, 3, 8] {
            let other = run(threads);
            assert_eq!(other.mass().to_bits(), one.mass().to_bits(), "{threads}");
            assert_eq!(other.center_of_mass(), one.center_of_mass(), "{threads}");
            assert_eq!(other.second_moment(), one.second_moment(), "{threads}");
        }
    }
}
