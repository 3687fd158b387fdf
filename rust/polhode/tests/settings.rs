//! Every tolerance, step and count is checked where the core receives it, each error naming
//! its argument; and the values a front end only converts (an angular velocity, a point, a
//! tolerance of the principal axes) are checked by the core's own functions.

use nalgebra::{UnitQuaternion, Vector3};
use polhode::dynamics::{Dop853Options, Method, MethodSettings, RotorSpec};
use polhode::settings::{count, Setting};
use polhode::simulation::{check_motion, simulate, Body, Simulation};
use polhode::MassProperties;

/// The argument an error names.
fn named<T: std::fmt::Debug>(result: polhode::Result<T>) -> String {
    result
        .expect_err("an error")
        .argument()
        .expect("a name")
        .to_string()
}

fn settings(rtol: f64) -> MethodSettings {
    MethodSettings {
        rtol,
        ..MethodSettings::default()
    }
}

#[test]
fn a_relative_tolerance_of_one_or_more_is_refused() {
    // dop853 at rtol 1 or 1e300 returned a motion whose |L| drifted by 37 and 1.6e21.
    for rtol in [1.0, 2.0, 1e300, f64::INFINITY, f64::NAN, 0.0, -1e-8, 1e-16] {
        for method in ["dop853", "auto", "rk4", "exact"] {
            let mut given = settings(rtol);
            given.dt = Some(0.1);
            assert_eq!(
                named(Method::from_name(method, &given)),
                "rtol",
                "{method} {rtol}"
            );
        }
        let run = Simulation::new(Method::Dop853(Dop853Options::with_rtol(rtol)));
        let result = simulate(
            &run,
            &[Body::Moments(Vector3::new(1.0, 2.0, 3.0))],
            &[Vector3::new(0.1, 1.0, 0.1)],
            &[UnitQuaternion::identity()],
            &[0.0, 10.0],
            None,
        );
        assert_eq!(named(result), "rtol", "{rtol}");
    }
    for rtol in [1e-15, 1e-10, 0.5, 1.0 - f64::EPSILON] {
        assert!(
            Method::from_name("dop853", &settings(rtol)).is_ok(),
            "{rtol}"
        );
    }
    let message = Setting::RelativeTolerance
        .check("rtol", 1.0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("expected rtol < 1") && message.ends_with("got 1."));
}

#[test]
fn every_setting_a_method_is_given_is_checked_whatever_the_method() {
    let cases: [(&str, MethodSettings); 5] = [
        (
            "dt",
            MethodSettings {
                dt: Some(-1.0),
                ..MethodSettings::default()
            },
        ),
        (
            "dt",
            MethodSettings {
                dt: Some(f64::NAN),
                ..MethodSettings::default()
            },
        ),
        (
            "order",
            MethodSettings {
                dt: Some(0.1),
                order: 5,
                ..MethodSettings::default()
            },
        ),
        (
            "atol",
            MethodSettings {
                dt: Some(0.1),
                atol: Some(0.0),
                ..MethodSettings::default()
            },
        ),
        (
            "atol",
            MethodSettings {
                dt: Some(0.1),
                atol: Some(f64::INFINITY),
                ..MethodSettings::default()
            },
        ),
    ];
    for method in ["auto", "exact", "splitting", "midpoint", "rk4", "dop853"] {
        for (name, given) in &cases {
            assert_eq!(named(Method::from_name(method, given)), *name, "{method}");
        }
    }
    // An unknown method is named before its settings.
    let bad = MethodSettings {
        dt: Some(-1.0),
        ..MethodSettings::default()
    };
    assert_eq!(named(Method::from_name("euler", &bad)), "method");
}

#[test]
fn counts_are_at_least_one() {
    for bad in [0, -1, i64::MIN] {
        let error = count("max_steps", bad).unwrap_err();
        assert_eq!(error.argument(), Some("max_steps"));
        assert_eq!(
            error.to_string(),
            format!("Invalid `max_steps`: expected at least 1, got {bad}.")
        );
    }
    assert_eq!(count("max_steps", 1), Ok(1));
    assert_eq!(count("max_steps", i64::MAX), Ok(i64::MAX as u64));
    let run = Simulation {
        max_steps: 0,
        ..Simulation::new(Method::Rk4 { dt: 0.1 })
    };
    let result = simulate(
        &run,
        &[Body::Moments(Vector3::new(1.0, 2.0, 3.0))],
        &[Vector3::new(0.1, 1.0, 0.1)],
        &[UnitQuaternion::identity()],
        &[0.0, 1.0],
        None,
    );
    assert_eq!(named(result), "max_steps");
}

#[test]
fn mass_properties_check_what_they_are_given() {
    let body = MassProperties::cuboid(2.0, Vector3::new(0.3, 0.2, 0.1)).unwrap();
    let nan = Vector3::new(0.0, f64::NAN, 1.0);
    assert_eq!(
        body.kinetic_energy(&nan).unwrap_err().to_string(),
        "Expected `omega[1]` to be finite, got NaN."
    );
    assert_eq!(named(body.angular_momentum_body(&nan)), "omega");
    // Finite, but the energy and the momentum overflow.
    let fast = Vector3::new(1e160, 0.0, 0.0);
    assert_eq!(named(body.kinetic_energy(&fast)), "omega");
    assert!(body
        .kinetic_energy(&fast)
        .unwrap_err()
        .to_string()
        .contains("kinetic energy overflows double precision"));
    let heavy = MassProperties::cuboid(1e10, Vector3::new(0.3, 0.2, 0.1)).unwrap();
    let faster = Vector3::new(1e302, 0.0, 0.0);
    assert_eq!(named(heavy.angular_momentum_body(&faster)), "omega");
    // The values themselves: T = w . I w / 2 and L = I w of a spin about z.
    let spin = Vector3::new(0.0, 0.0, 3.0);
    let izz = 2.0 * (0.09 + 0.04) / 12.0;
    assert!((body.kinetic_energy(&spin).unwrap() - 0.5 * izz * 9.0).abs() < 1e-15);
    assert!((body.angular_momentum_body(&spin).unwrap()[2] - 3.0 * izz).abs() < 1e-15);
    // A point that is not finite, one too far for the mass.
    let error = body
        .inertia_about(&Vector3::new(f64::INFINITY, 0.0, 0.0))
        .unwrap_err();
    assert_eq!(
        error.to_string(),
        "Expected `point[0]` to be finite, got inf."
    );
    assert_eq!(
        named(body.inertia_about(&Vector3::new(1e200, 0.0, 0.0))),
        "point"
    );
    let skew = nalgebra::Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    assert_eq!(
        named(body.inertia_about_in(&Vector3::zeros(), &skew)),
        "axes"
    );
    // The tolerance of equal moments: finite and >= 0.
    for rtol in [-1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(named(body.principal_with(rtol)), "rtol");
        let tensor = body.inertia();
        let flat: Vec<f64> = (0..9).map(|k| tensor[(k / 3, k % 3)]).collect();
        let (mut m, mut a, mut u) = (vec![0.0; 3], vec![0.0; 9], vec![0; 3]);
        let batch = polhode::eigen::principal_batch(&flat, rtol, &mut m, &mut a, &mut u);
        assert_eq!(named(batch), "rtol");
    }
    assert!(body.principal_with(0.0).is_ok());
}

#[test]
fn check_motion_makes_the_checks_of_a_run() {
    let body = Body::Moments(Vector3::new(1.0, 2.0, 3.0));
    let omega = Vector3::new(0.1, 1.0, 0.1);
    assert!(check_motion(&body, &omega, &[]).is_ok());
    // Each bad input as simulate names it.
    let run = |body: &Body, omega: &Vector3<f64>, rotors: &[RotorSpec]| {
        let sim = Simulation {
            rotors: rotors.to_vec(),
            ..Simulation::new(Method::Rk4 { dt: 1.0 })
        };
        simulate(
            &sim,
            &[*body],
            &[*omega],
            &[UnitQuaternion::identity()],
            &[0.0],
            None,
        )
        .map(|_| ())
    };
    let too_big = RotorSpec::SphericalDamper {
        inertia: 5.0,
        damping: 0.1,
    };
    let bad_rotor = RotorSpec::SphericalDamper {
        inertia: -1.0,
        damping: 0.1,
    };
    let cases: [(Body, Vector3<f64>, Vec<RotorSpec>); 5] = [
        (Body::Moments(Vector3::new(1.0, 0.0, 2.0)), omega, vec![]),
        (body, Vector3::new(f64::NAN, 0.0, 0.0), vec![]),
        (body, Vector3::new(1e200, 0.0, 0.0), vec![]),
        (body, omega, vec![too_big]),
        (body, omega, vec![bad_rotor]),
    ];
    for (body, omega, rotors) in &cases {
        // The same error (its message: NaN is not equal to itself).
        let checked = check_motion(body, omega, rotors).unwrap_err();
        let ran = run(body, omega, rotors).unwrap_err();
        assert_eq!(checked.to_string(), ran.to_string());
        assert_eq!(checked.argument(), ran.argument());
    }
}
