//! `FreeRotation::precession_rate_space` and `nutation_angle` against closed forms and against
//! the mean of the precession rate over a period computed by mpmath (quadrature over the
//! textbook Jacobi solution at 40 digits, `tests/test_precession.py::_reference`).

use nalgebra::{UnitQuaternion, Vector3};
use polhode::exact::FreeRotation;

fn motion(moments: [f64; 3], omega: [f64; 3]) -> FreeRotation {
    FreeRotation::new(
        Vector3::from(moments),
        Vector3::from(omega),
        UnitQuaternion::identity(),
    )
    .unwrap()
}

#[test]
fn symmetric_top_precesses_at_l_over_the_transverse_moment() {
    let (i_t, i_s) = (2.0, 3.0);
    let w = [0.3, -0.4, 0.5];
    let free = motion([i_t, i_t, i_s], w);
    let momentum = ((i_t * w[0]).powi(2) + (i_t * w[1]).powi(2) + (i_s * w[2]).powi(2)).sqrt();
    let rate = free.precession_rate_space().unwrap();
    assert!((rate - momentum / i_t).abs() <= 4.0 * f64::EPSILON * rate);
    let (lo, hi) = free.nutation_angle().unwrap();
    let theta = (i_t * 0.5f64).atan2(i_s * w[2]);
    assert_eq!(lo, hi);
    assert!((lo - theta).abs() <= 4.0 * f64::EPSILON);
}

#[test]
fn asymmetric_mean_rate_against_mpmath() {
    // (moments, omega, mean rate, nutation range): both extreme axes, each with the evaluation's
    // polar axis on either side.
    let cases = [
        (
            [1.0, 2.0, 3.0],
            [0.2, 0.3, 1.0],
            2.040310638121812,
            (0.11787288084805203, 0.2374245737770836),
        ),
        (
            [1.0, 1.2, 3.0],
            [0.2, 0.3, 1.0],
            2.7575133734420514,
            (0.12262834642824354, 0.14171830091504228),
        ),
        (
            [1.0, 2.0, 3.0],
            [1.0, 0.3, 0.2],
            0.5571984564755987,
            (0.6500295611063525, 0.7737692080397931),
        ),
        (
            [1.0, 1.2, 3.0],
            [1.0, 0.1, 0.05],
            0.6811242467242311,
            (0.15932752881298373, 0.32289004636079016),
        ),
    ];
    for (moments, omega, mean, (lo, hi)) in cases {
        let free = motion(moments, omega);
        let rate = free.precession_rate_space().unwrap();
        assert!(
            (rate - mean).abs() <= 8.0 * f64::EPSILON * mean,
            "{rate} {mean}"
        );
        let (a, b) = free.nutation_angle().unwrap();
        assert!(
            (a - lo).abs() <= 1e-14 && (b - hi).abs() <= 1e-14,
            "{a} {b}"
        );
    }
}

#[test]
fn no_mean_precession_without_circulation() {
    assert_eq!(
        motion([1.0, 2.0, 4.0], [0.0, 1.0, 0.0]).precession_rate_space(),
        None
    );
    assert_eq!(
        motion([1.0, 2.0, 4.0], [0.0, 0.0, 0.0]).nutation_angle(),
        None
    );
    // The separatrix: Delta_2 = 3 * 4 * (3 - 4) + 6 * 1 * (6 - 4) = 0.
    let sep = motion([3.0, 4.0, 6.0], [2.0, 0.7, 1.0]);
    assert_eq!(sep.precession_rate_space(), None);
    assert_eq!(sep.nutation_angle(), None);
}
