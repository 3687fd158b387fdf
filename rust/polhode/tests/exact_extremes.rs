//! The exact solution on extreme input: components and moments far outside the range where
//! their squares are doubles, times where double precision ends, symmetric bodies in every
//! order. Accuracy against mpmath is checked in `tests/test_exact_extremes.py`; here, what
//! holds exactly: scaling by powers of two, the invariants, the typed errors, the regimes.

use nalgebra::{UnitQuaternion, Vector3};
use polhode::exact::{FreeRotation, Regime};
use polhode::Error;

const EPS: f64 = f64::EPSILON;

fn q0() -> UnitQuaternion<f64> {
    UnitQuaternion::from_euler_angles(0.3, -1.2, 2.0)
}

fn free(moments: [f64; 3], omega0: [f64; 3]) -> FreeRotation {
    FreeRotation::new(Vector3::from(moments), Vector3::from(omega0), q0()).unwrap()
}

/// Ordinary and extreme bodies of every regime.
fn bodies() -> Vec<([f64; 3], [f64; 3])> {
    vec![
        ([3.0, 5.0, 9.0], [0.1, 0.4, -0.05]),
        ([9.0, 3.0, 5.0], [-0.6, 0.1, 0.02]),
        ([2.0, 3.0, 6.0], [-1.5, -2.0, -0.5]), // on the separatrix
        ([3.0, 5.0, 9.0], [0.0, 0.4, 1e-7]),   // near it
        ([2.0, 2.0, 3.0], [0.3, -0.4, 0.5]),
        ([2.0, 3.0, 2.0], [0.3, -0.4, 0.5]),
        ([1.0, 2.0, 3.0], [0.0, -0.7, 0.0]),
        ([2.0, 2.0, 2.0], [0.1, 0.2, 0.3]),
        // a component of 1e-170: m^2 underflows, k' = 1e-170 (mc = 1e-340 is not a double)
        ([3.0, 5.0, 9.0], [1e-170, 0.4, 1e-170]),
        ([3.0, 5.0, 9.0], [1e-170, 0.4, 0.1]),
        // subnormal components
        ([3.0, 5.0, 9.0], [5e-320, 0.4, 0.0]),
        ([3.0, 5.0, 9.0], [5e-320, 0.4, 7e-321]),
        ([3.0, 5.0, 9.0], [1e-320, 1e-320, 0.4]),
        // a symmetric top at 1e-170
        ([2.0, 3.0, 2.0], [1e-170, 2e-170, 3e-170]),
        // moments spanning 1e300
        ([1e-150, 1.0, 1e150], [0.3, 0.4, 0.5]),
        ([1e-150, 1.0, 1e150], [1e75, 0.4, 1e-75]),
        // found by a random search: amplitudes whose products leave the range of doubles, a
        // symmetric top whose two rates are 1e300 apart, rates beyond the range (t = 0 only)
        (
            [
                1.5458084742856003e-7,
                2.883276601294495e219,
                5.344789793913978e224,
            ],
            [0.0, 1.8111243690432856e-304, 7.364358400390068e-94],
        ),
        (
            [
                1.3435324102989068e210,
                1.3435324102989068e210,
                4.598335050503912e-286,
            ],
            [0.0, 0.0, 5.7831713523951056e119],
        ),
        (
            [
                2.0041295353944397e113,
                5.27984433696196e-72,
                1.2742040960161077e-295,
            ],
            [5.962584953622087e50, 4.231685264682559e-16, 0.0],
        ),
    ]
}

/// Times within the bound: fractions of the period (or of 1/|omega|) and of the bound.
fn times(fr: &FreeRotation, omega0: [f64; 3]) -> Vec<f64> {
    let scale = fr
        .period()
        .unwrap_or(1.0 / omega0.iter().fold(0.0f64, |a, w| a.max(w.abs())));
    let mut ts: Vec<f64> = [0.0, 0.13, -0.5, 1.0, 3.7, 1e3]
        .iter()
        .map(|x| x * scale)
        .collect();
    if fr.max_time().is_finite() {
        ts.extend([0.3, -0.99, 1.0].map(|x| x * fr.max_time()));
    }
    ts.retain(|t| t.abs() <= fr.max_time());
    ts
}

fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

#[test]
fn scaling_the_moments_by_powers_of_four_changes_nothing() {
    // (s I, w) is the motion of (I, w), exactly: every scaled quantity is the same double.
    for (moments, omega0) in bodies() {
        let base = free(moments, omega0);
        for k in [-150, -20, 20, 150] {
            let s = 4f64.powi(k);
            let scaled = moments.map(|x| x * s);
            if scaled.iter().any(|x| !x.is_normal()) {
                continue;
            }
            let fr = free(scaled, omega0);
            assert_eq!(fr.regime(), base.regime());
            assert_eq!(fr.max_time(), base.max_time());
            for t in times(&base, omega0) {
                let (w1, q1) = base.try_state(t).unwrap();
                let (w2, q2) = fr.try_state(t).unwrap();
                assert_eq!(w1, w2, "{moments:?} {omega0:?} x{s} at {t}");
                assert_eq!(q1, q2, "{moments:?} {omega0:?} x{s} at {t}");
            }
        }
    }
}

#[test]
fn scaling_the_rates_by_powers_of_four_scales_time() {
    // (I, s w) at t is s times (I, w) at s t, exactly.
    for (moments, omega0) in bodies() {
        let base = free(moments, omega0);
        for k in [-100, -7, 7, 100] {
            let s = 4f64.powi(k);
            let scaled = omega0.map(|x| x * s);
            // Only exact scalings (no subnormal component loses bits, nothing overflows).
            if (0..3).any(|i| scaled[i] / s != omega0[i] || !scaled[i].is_finite()) {
                continue;
            }
            let Ok(fr) = FreeRotation::new(Vector3::from(moments), Vector3::from(scaled), q0())
            else {
                continue;
            };
            assert_eq!(fr.regime(), base.regime());
            assert_eq!(fr.max_time() * s, base.max_time());
            for t in times(&base, omega0) {
                let (w1, q1) = base.try_state(t).unwrap();
                let (w2, q2) = fr.try_state(t / s).unwrap();
                for i in 0..3 {
                    // The finer of the two, rounded once to the other's scale (a subnormal
                    // output holds fewer digits).
                    let ok = if s > 1.0 {
                        same(w2[i] / s, w1[i])
                    } else {
                        same(w1[i] * s, w2[i])
                    };
                    assert!(ok, "{moments:?} {omega0:?} x{s} at {t}: {w2} vs {w1}");
                }
                assert_eq!(q1, q2, "{moments:?} {omega0:?} x{s} at {t}");
            }
        }
    }
}

#[test]
fn extreme_inputs_keep_the_invariants() {
    for (moments, omega0) in bodies() {
        let fr = free(moments, omega0);
        let i = Vector3::from(moments);
        // In units where the largest |I w| is 1 (no square underflows).
        let unit = i
            .component_mul(&Vector3::from(omega0))
            .amax()
            .max(f64::MIN_POSITIVE);
        let l0 = q0() * i.component_mul(&Vector3::from(omega0)) / unit;
        for t in times(&fr, omega0) {
            let (w, q) = fr.try_state(t).unwrap();
            assert!(
                w.iter().all(|x| x.is_finite()),
                "{moments:?} {omega0:?} at {t}"
            );
            assert!((q.coords.norm() - 1.0).abs() <= 4.0 * EPS);
            let m = i.component_mul(&w) / unit;
            // |L| and L in space: a few ulp of |L| (each component rounded once, the rotation
            // a few more).
            assert!(
                (m.norm() - l0.norm()).abs() <= 8.0 * EPS * l0.norm(),
                "|L| {moments:?} {omega0:?} at {t}: {} vs {}",
                m.norm(),
                l0.norm()
            );
            assert!(
                (q * m - l0).norm() <= 16.0 * EPS * l0.norm(),
                "L {moments:?} {omega0:?} at {t}: {}",
                (q * m - l0).norm() / l0.norm()
            );
        }
    }
}

#[test]
fn tiny_components_are_not_the_separatrix() {
    // L0 = (3e-170, 2, 9e-170): Delta_2 = 9e-340 (-2/3) + 8.1e-339 (4/9) > 0, a flip about
    // the largest axis whose period is 4 K / lambda with K = ln(4 / k') ~ 393, not the
    // separatrix (whose squares underflow to Delta_2 = 0).
    let fr = free([3.0, 5.0, 9.0], [1e-170, 0.4, 1e-170]);
    assert_eq!(fr.regime(), Regime::AboutAxis(2));
    let p = fr.period().unwrap();
    assert!(p > 7000.0 && p < 7300.0, "{p}");
    // Half a period later it spins the other way round, and back after a period.
    let w = fr.omega(0.5 * p);
    assert!((w.y + 0.4).abs() < 1e-12, "{w}");
    let w = fr.omega(p);
    assert!((w.y - 0.4).abs() < 1e-12, "{w}");
    // A subnormal component, the other zero: the circulation is about the smallest axis.
    let fr = free([3.0, 5.0, 9.0], [5e-320, 0.4, 0.0]);
    assert_eq!(fr.regime(), Regime::AboutAxis(0));
    let w = fr.omega(0.5 * fr.period().unwrap());
    assert!((w.y + 0.4).abs() < 1e-12, "{w}");
    // At t = 0 the given components come back, tiny ones included.
    for omega0 in [
        [1e-170, 0.4, 0.1],
        [0.1, 0.4, 1e-200],
        [5e-320, 0.4, 7e-321],
        [-1e-170, 0.4, 3e-170],
    ] {
        let w = free([3.0, 5.0, 9.0], omega0).omega(0.0);
        for i in 0..3 {
            assert!(
                (w[i] - omega0[i]).abs() <= 2.0 * EPS * omega0[i].abs(),
                "{omega0:?}: {w}"
            );
        }
    }
}

#[test]
fn the_time_bound_is_a_typed_error() {
    for (moments, omega0) in bodies() {
        let fr = free(moments, omega0);
        let t_max = fr.max_time();
        // (0 when the rates themselves are beyond the range of doubles: only t = 0 is a time.)
        assert!(t_max >= 0.0);
        if !t_max.is_finite() {
            continue;
        }
        for t in [t_max, -t_max] {
            let (w, q) = fr.try_state(t).unwrap();
            assert!(w.iter().all(|x| x.is_finite()) && q.coords.iter().all(|x| x.is_finite()));
        }
        let beyond = [
            t_max * (1.0 + 2.0 * EPS),
            -t_max * (1.0 + 2.0 * EPS),
            1e90,
            -1e300,
        ];
        for t in beyond.into_iter().filter(|t| t.abs() > t_max) {
            match fr.try_state(t) {
                Err(Error::InvalidArgument { name, reason }) => {
                    assert_eq!(name, "t");
                    assert!(reason.contains(&format!("{t_max:e}")), "{reason}");
                }
                other => panic!("{moments:?} {omega0:?} at {t}: {other:?}"),
            }
            assert!(fr.try_omega(t).is_err());
            // The infallible forms give NaN there, never a number.
            assert!(fr.state(t).0.iter().all(|x| x.is_nan()));
            assert!(fr.state(t).1.coords.iter().all(|x| x.is_nan()));
            assert!(fr.omega(t).iter().all(|x| x.is_nan()));
        }
        assert!(matches!(
            fr.try_state(f64::NAN),
            Err(Error::NonFinite { ref name, .. }) if name == "t"
        ));
    }
    // Steady rotation: the fastest angle is the rotation itself, |w| t.
    let w: f64 = 0.75;
    let fr = free([1.0, 2.0, 3.0], [0.0, 0.0, w]);
    let want = std::f64::consts::TAU * 2f64.powi(50) / w;
    assert!((fr.max_time() - want).abs() <= 4.0 * EPS * want);
    // There one ulp of t turns it by at most a quarter turn.
    let ulp = fr.max_time() * EPS;
    assert!(ulp * w <= std::f64::consts::FRAC_PI_2 * (1.0 + 4.0 * EPS));
    // At rest nothing turns: every time is fine.
    let rest = free([1.0, 2.0, 3.0], [0.0; 3]);
    assert_eq!(rest.max_time(), f64::INFINITY);
    assert_eq!(rest.try_state(1e300).unwrap().1, q0());
}

#[test]
fn symmetric_axis_in_any_position() {
    // The one distinct moment is the symmetry axis wherever it sits.
    for (moments, axis) in [
        ([2.0, 2.0, 3.0], 2),
        ([2.0, 3.0, 2.0], 1),
        ([3.0, 2.0, 2.0], 0),
        ([1.0, 2.0, 2.0], 0),
        ([2.0, 1.0, 2.0], 1),
        ([2.0, 2.0, 1.0], 2),
    ] {
        let omega0 = [0.3, -0.4, 0.5];
        let fr = free(moments, omega0);
        assert_eq!(fr.regime(), Regime::Symmetric { axis });
        // omega_s is constant, the others turn at Omega = w_s (I_s - I_t) / I_t.
        let it = moments[(axis + 1) % 3];
        let big = omega0[axis] * (moments[axis] - it) / it;
        let p = fr.period().unwrap();
        assert!((p - std::f64::consts::TAU / big.abs()).abs() <= 4.0 * EPS * p);
        for t in [0.7, 13.0, 250.0] {
            let w = fr.omega(t);
            assert_eq!(w[axis], omega0[axis]);
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let (s, c) = (big * t).sin_cos();
            let want_a = c * omega0[a] - s * omega0[b];
            let want_b = s * omega0[a] + c * omega0[b];
            assert!((w[a] - want_a).abs() <= 1e-14 && (w[b] - want_b).abs() <= 1e-14);
        }
    }
}
