//! The closedness check of solid meshes on vertices as files write them: triangle soups, signed
//! zeros, exporters' last-place noise (merged: within `2^-40` of the bounding-box diagonal) and
//! real gaps (kept), and what the error says about an opening.

use nalgebra::Matrix3;
use polhode::mass::{merge_vertices, weld_tolerance, MESH_CHUNK, WELD_EXPONENT};
use polhode::Monitor;
use polhode::{Error, MassProperties};

type Mesh = (Vec<[f64; 3]>, Vec<[i64; 3]>);

/// The box `[0, s]^3` as 12 outward triangles.
fn cube(s: f64) -> Mesh {
    let v = (0..8)
        .map(|k| {
            let c = |bit: usize| if k >> bit & 1 == 1 { s } else { 0.0 };
            [c(0), c(1), c(2)]
        })
        .collect();
    let f = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    (v, f)
}

/// Every triangle with its own three vertices, as STL writes them.
fn soup(mesh: &Mesh) -> Mesh {
    let mut v = Vec::new();
    let mut f = Vec::new();
    for t in &mesh.1 {
        let base = v.len() as i64;
        for &i in t {
            v.push(mesh.0[i as usize]);
        }
        f.push([base, base + 1, base + 2]);
    }
    (v, f)
}

fn solid(mesh: &Mesh) -> Result<MassProperties, Error> {
    MassProperties::mesh(&mesh.0, &mesh.1, Some(1.0), None, false, false)
}

fn rel(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    (a - b).norm() / b.norm()
}

#[test]
fn a_triangle_soup_with_signed_zeros_is_the_closed_cube() {
    let shared = cube(1.0);
    let mut loose = soup(&shared);
    // A vertex at 0 written as -0.0 in some triangles (0.0 and -0.0 are the same position).
    for (k, v) in loose.0.iter_mut().enumerate() {
        if k % 3 == 1 {
            for x in v.iter_mut() {
                if *x == 0.0 {
                    *x = -0.0;
                }
            }
        }
    }
    let a = solid(&shared).unwrap();
    let b = solid(&loose).unwrap();
    // The same polyhedron: only the reference point of the sums (the mean of the 36 vertices
    // as given) differs, by round-off.
    assert!((a.mass() - 1.0).abs() <= 4.0 * f64::EPSILON);
    assert!((b.mass() - 1.0).abs() <= 4.0 * f64::EPSILON);
    assert!((a.center_of_mass() - b.center_of_mass()).norm() <= 4.0 * f64::EPSILON);
    assert!(rel(&a.second_moment(), &b.second_moment()) <= 8.0 * f64::EPSILON);
}

/// The soup of a cube of side `s` with one corner of one triangle moved by `delta` along x.
fn nudged(s: f64, delta: f64) -> Mesh {
    let mut mesh = soup(&cube(s));
    // Triangle 2 is [4, 5, 7]: its first corner is vertex 4 = (0, 0, s), moved off the cube's
    // face x = 0 (inwards for delta > 0).
    mesh.0[6][0] += delta;
    mesh
}

#[test]
fn the_tolerance_merges_exporter_noise_and_no_real_gap() {
    // The two cases the tolerance is chosen for: 1e-17 absolute on a 3 cm part merges, a 1e-3 gap does not.
    let part = solid(&nudged(0.03, 1e-17)).unwrap();
    assert!((part.mass() - 0.03f64.powi(3)).abs() <= 1e-15 * part.mass());
    let e = solid(&nudged(0.03, 1e-3)).unwrap_err();
    assert!(e.to_string().contains("not closed"), "{e}");

    // At the tolerance itself, 2^-40 of the bounding-box diagonal (in every coordinate): just
    // inside merges, just outside does not.
    assert_eq!(WELD_EXPONENT, -40);
    for s in [0.03, 1.0, 250.0] {
        let diagonal = s * 3f64.sqrt();
        let tolerance = weld_tolerance(diagonal);
        assert_eq!(tolerance, diagonal * 2f64.powi(-40));
        assert!(solid(&nudged(s, 0.99 * tolerance)).is_ok(), "{s}");
        assert!(solid(&nudged(s, -0.99 * tolerance)).is_ok(), "{s}");
        let e = solid(&nudged(s, 1.01 * tolerance)).unwrap_err();
        assert!(e.to_string().contains("not closed"), "{s}: {e}");
    }
}

#[test]
fn an_open_box_says_where_and_how_big_the_hole_is() {
    // The unit cube without its top (z = 1: triangles 2 and 3): one square opening, four edges,
    // length 4, half a unit wide (2 area / length = 2 / 4).
    let (v, mut f) = cube(1.0);
    f.drain(2..4);
    let e = solid(&(v, f)).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("4 edges") && text.contains("1 opening of total length 4 "),
        "{text}"
    );
    assert!(text.contains("is 0.5 wide"), "{text}");
    assert!(
        text.contains("passes through vertex 4 at (0, 0, 1)"),
        "{text}"
    );
    assert!(text.contains("use shell=True"), "{text}");
}

#[test]
fn a_crack_is_not_called_a_hole() {
    // The face x = 0 of the unit cube split at the midpoint m of its edge y = 0 (a T-junction:
    // the neighbouring face y = 0 still has the whole edge). Closed to the eye, open in its
    // connectivity: a slit of width zero, which merging cannot close.
    let (mut v, mut f) = cube(1.0);
    v.push([0.0, 0.0, 0.5]); // 8: on the edge 0 -> 4
                             // Face x = 0 was [0, 4, 6], [0, 6, 2]: now [0, 8, 6], [8, 4, 6], [0, 6, 2].
    f[8] = [0, 8, 6];
    f.push([8, 4, 6]);
    let e = solid(&(v, f)).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("not closed") && text.contains("cracks"),
        "{text}"
    );
    assert!(text.contains("is 0 wide"), "{text}");
    assert!(!text.contains("use shell=True"), "{text}");
}

#[test]
fn a_flipped_face_is_named_with_its_positions() {
    let (v, mut f) = soup(&cube(2.0));
    f[5].swap(1, 2);
    let text = solid(&(v, f)).unwrap_err().to_string();
    assert!(text.contains("used by more than one face"), "{text}");
    assert!(text.contains("from (") && text.contains(" to ("), "{text}");
}

#[test]
fn merge_vertices_keeps_the_first_and_drops_faces_of_no_area() {
    let v = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [-0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let (vertices, faces) = merge_vertices(&v, &[[0, 1, 2], [3, 4, 5], [1, 3, 5]], None).unwrap();
    assert_eq!(vertices, vec![v[0], v[1], v[2], v[5]]);
    assert_eq!(faces, vec![[0, 1, 2], [1, 0, 3]]); // [1, 3, 5] became [1, 1, 3]
    let e = merge_vertices(&v, &[[0, 1, 6]], None).unwrap_err();
    assert!(matches!(e, Error::InvalidArgument { ref name, .. } if name == "faces[0, 2]"));
}

/// An icosphere-like closed surface of many triangles: a subdivided octahedron.
fn sphere(levels: usize) -> Mesh {
    let mut v: Vec<[f64; 3]> = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut f: Vec<[i64; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..levels {
        let mut middle = std::collections::HashMap::new();
        let mut mid = |a: i64, b: i64, v: &mut Vec<[f64; 3]>| {
            *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                let m = [
                    (p[0] + q[0]) / 2.0,
                    (p[1] + q[1]) / 2.0,
                    (p[2] + q[2]) / 2.0,
                ];
                let r = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                v.push([m[0] / r, m[1] / r, m[2] / r]);
                v.len() as i64 - 1
            })
        };
        let mut next = Vec::with_capacity(4 * f.len());
        for [a, b, c] in f {
            let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        f = next;
    }
    (v, f)
}

#[test]
fn a_cancel_stops_the_merging_of_a_large_soup() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    // 131072 triangles as a soup of 393216 vertices: the first check fails, the merge and the
    // second check run, each in blocks of MESH_CHUNK with a look before each.
    let mesh = soup(&sphere(7));
    assert!(mesh.0.len() > 4 * MESH_CHUNK);
    let plain = solid(&mesh).unwrap();
    let looks = Arc::new(AtomicUsize::new(0));
    let counting = Monitor::with_on_look({
        let looks = Arc::clone(&looks);
        move |_| {
            looks.fetch_add(1, Ordering::Relaxed);
        }
    });
    let watched = MassProperties::mesh_monitored(
        &mesh.0,
        &mesh.1,
        Some(1.0),
        None,
        false,
        false,
        Some(&counting),
    )
    .unwrap();
    assert_eq!(watched.mass().to_bits(), plain.mass().to_bits());
    assert_eq!(watched.second_moment(), plain.second_moment());
    let total = looks.load(Ordering::Relaxed);
    for at in [1, total / 3, total / 2, total] {
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
            &mesh.0,
            &mesh.1,
            Some(1.0),
            None,
            false,
            false,
            Some(&monitor),
        );
        assert_eq!(
            result.unwrap_err(),
            Error::Interrupted,
            "look {at} of {total}"
        );
        let merged = merge_vertices(&mesh.0, &mesh.1, Some(&monitor));
        assert_eq!(merged.unwrap_err(), Error::Interrupted);
    }
}

#[test]
fn merging_is_the_same_for_any_number_of_threads() {
    // The noise of a soup: every corner moved by a few ulps, so that the exact merge leaves
    // the whole surface open and the tolerance closes it.
    let mut mesh = soup(&sphere(5));
    for (k, v) in mesh.0.iter_mut().enumerate() {
        for x in v.iter_mut() {
            *x += (k % 7) as f64 * 1e-16;
        }
    }
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| solid(&mesh).unwrap())
    };
    let one = run(1);
    for threads in [2, 3, 8] {
        let other = run(threads);
        assert_eq!(other.mass().to_bits(), one.mass().to_bits(), "{threads}");
        assert_eq!(other.second_moment(), one.second_moment(), "{threads}");
    }
}
