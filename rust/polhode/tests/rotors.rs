//! Bodies with rotors through the core's API: closed forms of momentum exchange, the damper's
//! energy sink, and the methods that cannot take rotors.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use polhode::dynamics::{
    integrate_gyrostat, Dop853Options, Gyrostat, Method, MotorTorque, Options, RotorSpec, State,
};
use polhode::simulation::{simulate, Body, Simulation};

fn wheel(torque: MotorTorque) -> RotorSpec {
    RotorSpec::Wheel {
        axis: Vector3::z(),
        inertia: 0.1,
        rate0: 0.0,
        torque,
    }
}

/// A body at rest whose wheel (on its axis of largest moment) is spun up: `H = 0`, so
/// `w3 = -h / (I3 - J)` with `h = g t` the motor's impulse, and the body turns by
/// `-(g / (I3 - J)) t^2 / 2`.
#[test]
fn a_wheel_spun_up_turns_the_body() {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let (g, j) = (0.05, 0.1);
    let gyrostat = Gyrostat::new(
        &moments,
        &Matrix3::identity(),
        &[wheel(MotorTorque::Constant(g))],
    )
    .unwrap();
    let times = [0.0, 0.5, 1.0, 2.0];
    for method in [
        Method::Rk4 { dt: 1e-3 },
        Method::Dop853(Dop853Options::with_rtol(1e-12)),
    ] {
        let run = integrate_gyrostat(
            &method,
            &gyrostat,
            &State::from_omega(Vector3::zeros()),
            &times,
            &Options::default(),
        )
        .unwrap();
        for (k, &t) in times.iter().enumerate() {
            let a33 = moments[2] - j;
            assert!((run.omega[k].z + g * t / a33).abs() <= 1e-14, "{method:?}");
            let angle = run.orientation[k].scaled_axis().z;
            assert!((angle + g / a33 * t * t / 2.0).abs() <= 1e-12, "{method:?}");
            // The wheel's momentum is the motor's impulse (summed over up to 2000 steps).
            assert!((run.variables[k] - g * t).abs() <= 2000.0 * f64::EPSILON * g * t);
        }
    }
}

/// A spin about the smallest axis with a damper ends about the largest, at fixed |L|.
#[test]
fn a_damper_takes_the_spin_to_the_largest_axis() {
    let mut run = Simulation::new(Method::Dop853(Dop853Options::with_rtol(1e-11)));
    run.rotors = vec![RotorSpec::SphericalDamper {
        inertia: 0.05,
        damping: 0.02,
    }];
    let omega0 = Vector3::new(1.0, 0.05, 0.05);
    let times = [0.0, 3000.0];
    let bodies = [Body::Moments(Vector3::new(1.0, 2.0, 3.0))];
    let out = simulate(
        &run,
        &bodies,
        &[omega0],
        &[UnitQuaternion::identity()],
        &times,
        None,
    )
    .unwrap();
    let energy = out.column("energy").unwrap();
    let l = out.column("angular_momentum_space").unwrap();
    let l0 = Vector3::from_column_slice(&l[..3]).norm();
    let l1 = Vector3::from_column_slice(&l[3..]).norm();
    assert!((l1 - l0).abs() <= 1e-9 * l0);
    assert!((energy[1] - l0 * l0 / 6.0).abs() <= 1e-6 * energy[1]);
    assert_eq!(out.column("rotor_rates").unwrap().len(), 2 * 3);
}

#[test]
fn methods_without_rotors_say_so() {
    for method in [Method::Exact, Method::Midpoint { dt: 0.1 }] {
        let mut run = Simulation::new(method);
        run.rotors = vec![wheel(MotorTorque::Constant(0.0))];
        let error = simulate(
            &run,
            &[Body::Moments(Vector3::new(1.0, 2.0, 3.0))],
            &[Vector3::new(0.1, 1.0, 0.1)],
            &[UnitQuaternion::identity()],
            &[0.0, 1.0],
            None,
        )
        .unwrap_err();
        assert_eq!(error.argument(), Some("rotors"), "{error}");
    }
    // A wheel's spinning inertia larger than the body's moment about its axis.
    let error = Gyrostat::new(
        &Vector3::new(1.0, 2.0, 3.0),
        &Matrix3::identity(),
        &[RotorSpec::Wheel {
            axis: Vector3::x(),
            inertia: 1.5,
            rate0: 0.0,
            torque: MotorTorque::Constant(0.0),
        }],
    )
    .unwrap_err();
    assert_eq!(error.argument(), Some("rotors"));
}
