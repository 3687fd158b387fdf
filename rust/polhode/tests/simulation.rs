//! The batch path: bodies as users give them, outputs in their own axes, per-body errors.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use polhode::dynamics::{
    integrate, Dop853Options, Method, Options, SplittingOrder, State, TorqueSpec,
};
use polhode::exact::FreeRotation;
use polhode::simulation::{simulate, Body, Quantity, Simulation};
use polhode::{Error, MassProperties, Monitor};

fn methods() -> Vec<Method> {
    vec![
        Method::Exact,
        Method::Splitting {
            dt: 1e-2,
            order: SplittingOrder::Four,
        },
        Method::Midpoint { dt: 1e-2 },
        Method::Rk4 { dt: 1e-2 },
        Method::Dop853(Dop853Options::with_rtol(1e-11)),
    ]
}

fn bodies() -> (Vec<Body>, Vec<Vector3<f64>>) {
    let moments = [
        Vector3::new(1.0, 2.0, 3.0),
        Vector3::new(3.0, 1.0, 1.5),
        Vector3::new(2.0, 2.0, 5.0),
        Vector3::new(0.5, 3.0, 1.0),
    ];
    let omega = [
        Vector3::new(0.1, 1.0, 0.2),
        Vector3::new(1.0, -0.3, 0.4),
        Vector3::new(0.2, 0.1, 2.0),
        Vector3::new(-0.4, 0.6, 0.1),
    ];
    (
        moments.iter().copied().map(Body::Moments).collect(),
        omega.to_vec(),
    )
}

const T: [f64; 4] = [0.0, 0.3, 1.0, 2.5];

#[test]
fn each_body_of_a_batch_is_integrated_alone() {
    let (bodies, omega) = bodies();
    let q0 = UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3);
    for method in methods() {
        let run = Simulation::new(method);
        let batch = simulate(&run, &bodies, &omega, &[q0], &T, None).unwrap();
        let serial = simulate(
            &Simulation {
                parallel: false,
                ..run.clone()
            },
            &bodies,
            &omega,
            &[q0],
            &T,
            None,
        )
        .unwrap();
        assert_eq!(batch, serial, "{method:?}: parallel and serial differ");
        let w = batch.column("omega").unwrap();
        let q = batch.column("quaternion").unwrap();
        for (i, body) in bodies.iter().enumerate() {
            let Body::Moments(m) = body else {
                unreachable!()
            };
            let alone = integrate(
                &method,
                m,
                &State::new(omega[i], q0),
                &T,
                &Options::default(),
            )
            .unwrap();
            for (j, wj) in alone.omega.iter().enumerate() {
                let k = (i * T.len() + j) * 3;
                assert_eq!(&w[k..k + 3], wj.as_slice(), "{method:?} body {i} time {j}");
                let qa = alone.orientation.as_ref().unwrap()[j];
                let k4 = (i * T.len() + j) * 4;
                let sign = if q[k4 + 3] * qa.w + q[k4] * qa.i < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                assert_eq!(
                    [q[k4], q[k4 + 1], q[k4 + 2], q[k4 + 3]],
                    [sign * qa.i, sign * qa.j, sign * qa.k, sign * qa.w]
                );
            }
        }
    }
}

#[test]
fn a_tensor_is_reported_in_its_own_axes() {
    let r = Rotation3::from_euler_angles(0.4, -0.7, 0.5);
    let tensor =
        r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.5)) * r.matrix().transpose();
    let omega0 = Vector3::new(0.3, -0.8, 0.6);
    let q0 = UnitQuaternion::from_euler_angles(0.2, 0.1, -0.3);
    for method in methods() {
        let out = simulate(
            &Simulation::new(method),
            &[Body::Inertia(tensor)],
            &[omega0],
            &[q0],
            &T,
            None,
        )
        .unwrap();
        let w = out.column("omega").unwrap();
        let lb = out.column("angular_momentum_body").unwrap();
        let ls = out.column("angular_momentum_space").unwrap();
        let q = out.column("quaternion").unwrap();
        let e = out.column("energy").unwrap();
        let l0 = q0 * (tensor * omega0);
        for j in 0..T.len() {
            let wj = Vector3::from_column_slice(&w[3 * j..3 * j + 3]);
            let lbj = Vector3::from_column_slice(&lb[3 * j..3 * j + 3]);
            let qj = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                q[4 * j + 3],
                q[4 * j],
                q[4 * j + 1],
                q[4 * j + 2],
            ));
            // L_body = I w in the body's own axes, L_space = R_b L_body = L(0).
            assert!(
                (lbj - tensor * wj).norm() <= 1e-14 * lbj.norm(),
                "{method:?}"
            );
            let lsj = Vector3::from_column_slice(&ls[3 * j..3 * j + 3]);
            assert!((lsj - qj * lbj).norm() <= 1e-14 * l0.norm(), "{method:?}");
            // Conserved to the method's own accuracy (order 2 for the midpoint rule).
            let bound = if let Method::Midpoint { .. } = method {
                1e-5
            } else {
                1e-8
            };
            assert!((lsj - l0).norm() <= bound * l0.norm(), "{method:?}");
            assert!((e[j] - 0.5 * wj.dot(&(tensor * wj))).abs() <= 1e-14 * e[j]);
        }
        // Initial values are the inputs.
        assert!((Vector3::from_column_slice(&w[..3]) - omega0).norm() <= 1e-15);
    }
}

#[test]
fn columns_without_the_orientation() {
    let (bodies, omega) = bodies();
    let run = Simulation {
        with_orientation: false,
        ..Simulation::new(Method::Exact)
    };
    let out = simulate(
        &run,
        &bodies,
        &omega,
        &[UnitQuaternion::identity()],
        &T,
        None,
    )
    .unwrap();
    let names: Vec<_> = out.columns.iter().map(|(q, _)| q.name()).collect();
    assert_eq!(names, ["omega", "angular_momentum_body", "energy"]);
    assert!(Quantity::ALL
        .iter()
        .all(|q| q.needs_orientation() || q.needs_rotors() || out.column(q.name()).is_some()));
}

#[test]
fn the_first_failing_body_is_named() {
    let (mut bodies, mut omega) = bodies();
    bodies[2] = Body::Moments(Vector3::new(1.0, 0.0, 2.0));
    omega[3] = Vector3::new(f64::NAN, 0.0, 0.0);
    let error = simulate(
        &Simulation::new(Method::Rk4 { dt: 0.1 }),
        &bodies,
        &omega,
        &[UnitQuaternion::identity()],
        &T,
        None,
    )
    .unwrap_err();
    match error {
        Error::Body { body, error } => {
            assert_eq!(body, 2);
            assert_eq!(error.argument(), Some("body"));
        }
        other => panic!("expected a body's error, got {other:?}"),
    }
}

#[test]
fn a_cancelled_run_is_interrupted_not_a_body_error() {
    let (bodies, omega) = bodies();
    let monitor = Monitor::new();
    monitor.cancel();
    let error = simulate(
        &Simulation::new(Method::Rk4 { dt: 1e-3 }),
        &bodies,
        &omega,
        &[UnitQuaternion::identity()],
        &T,
        Some(&monitor),
    )
    .unwrap_err();
    assert_eq!(error, Error::Interrupted);
}

#[test]
fn a_cancel_while_the_outputs_are_written_stops_the_run() {
    // The exact solution at 20 000 times: once the run has finished (`finished() == 1`), the
    // outputs are written in the body's own axes, looking at the monitor as the run did; a
    // cancel then still stops the call (writing 1e7 outputs takes a second).
    let monitor = Monitor::with_on_look(|monitor| {
        if monitor.finished() == 1 {
            monitor.cancel();
        }
    });
    let t: Vec<f64> = (0..20_000).map(|k| f64::from(k) * 1e-2).collect();
    let body = Body::Moments(Vector3::new(1.0, 2.0, 3.0));
    let omega0 = Vector3::new(0.3, 1.0, 0.2);
    let run = Simulation::new(Method::Exact);
    let q0 = [UnitQuaternion::identity()];
    let error = simulate(&run, &[body], &[omega0], &q0, &t, Some(&monitor)).unwrap_err();
    assert_eq!(error, Error::Interrupted);
    assert_eq!(monitor.finished(), 1);
    // Not cancelled: the same call completes, every output written.
    let out = simulate(&run, &[body], &[omega0], &q0, &t, Some(&Monitor::new())).unwrap();
    assert_eq!(out.m, t.len());
}

#[test]
fn gravity_takes_mass_and_centre_of_mass_from_a_body() {
    let top = MassProperties::cone(1.0, 0.3, 1.0).unwrap();
    let pivot = Vector3::new(0.0, 0.0, 0.0);
    let gravity = TorqueSpec::Gravity {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        pivot: Some(pivot),
        mass: None,
        center_of_mass: None,
    };
    let run = Simulation {
        torque: Some(gravity.clone()),
        ..Simulation::new(Method::Dop853(Dop853Options::with_rtol(1e-12)))
    };
    let q0 = UnitQuaternion::from_euler_angles(0.3, 0.0, 0.0);
    let omega0 = Vector3::new(0.0, 0.0, 30.0);
    let out = simulate(
        &run,
        &[Body::MassProperties(top)],
        &[omega0],
        &[q0],
        &T,
        None,
    )
    .unwrap();
    // The same top given by its moments about the pivot, with the mass and centre of mass.
    let about = top.inertia_about(&pivot).unwrap();
    let explicit = Simulation {
        torque: Some(TorqueSpec::Gravity {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            pivot: None,
            mass: Some(top.mass()),
            center_of_mass: Some(top.center_of_mass() - pivot),
        }),
        ..run.clone()
    };
    let again = simulate(
        &explicit,
        &[Body::Inertia(about)],
        &[omega0],
        &[q0],
        &T,
        None,
    )
    .unwrap();
    let (a, b) = (out.column("omega").unwrap(), again.column("omega").unwrap());
    for k in 0..a.len() {
        assert!(
            (a[k] - b[k]).abs() <= 1e-9 * 30.0,
            "{k}: {} vs {}",
            a[k],
            b[k]
        );
    }
    // Moments alone, without the mass, are refused.
    let bare = simulate(
        &run,
        &[Body::Moments(Vector3::new(1.0, 1.0, 0.5))],
        &[omega0],
        &[q0],
        &T,
        None,
    );
    assert!(matches!(bare, Err(Error::InvalidArgument { ref name, .. }) if name == "torque"));
}

/// Body `i`'s numbers of every column of a batch.
fn body_rows(out: &polhode::simulation::Outputs, i: usize) -> Vec<Vec<f64>> {
    out.columns
        .iter()
        .map(|(q, data)| {
            let len = out.m * q.width(out.rotors);
            data[i * len..(i + 1) * len].to_vec()
        })
        .collect()
}

#[test]
fn a_batch_with_a_torque_is_bitwise_each_body_alone_whatever_the_threads() {
    let n = 12;
    let bodies: Vec<Body> = (0..n)
        .map(|i| {
            let i = i as f64;
            Body::Moments(Vector3::new(
                1.0 + 0.01 * i,
                2.0 - 0.02 * i,
                2.5 + 0.005 * i,
            ))
        })
        .collect();
    let omega: Vec<Vector3<f64>> = (0..n)
        .map(|i| Vector3::new(0.1 * i as f64, 1.0, -0.3))
        .collect();
    let q0: Vec<UnitQuaternion<f64>> = (0..n)
        .map(|i| UnitQuaternion::from_euler_angles(0.01 * i as f64, 0.2, 0.0))
        .collect();
    let gravity = TorqueSpec::Gravity {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        pivot: None,
        mass: Some(1.0),
        center_of_mass: Some(Vector3::new(0.0, 0.0, 0.1)),
    };
    let t = [0.5, 1.0];
    for method in methods().into_iter().skip(1) {
        for torque in [None, Some(gravity.clone())] {
            let run = Simulation {
                torque,
                ..Simulation::new(method)
            };
            let alone: Vec<Vec<Vec<f64>>> = (0..n)
                .map(|i| {
                    let out = simulate(&run, &bodies[i..=i], &omega[i..=i], &q0[i..=i], &t, None)
                        .unwrap();
                    body_rows(&out, 0)
                })
                .collect();
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let batch = pool
                    .install(|| simulate(&run, &bodies, &omega, &q0, &t, None))
                    .unwrap();
                for (i, rows) in alone.iter().enumerate() {
                    assert_eq!(&body_rows(&batch, i), rows, "{method:?}, {threads} threads");
                }
            }
        }
    }
}

/// A batch reports the time integrated by all its bodies and the bodies finished (every
/// method, the exact solution included), and a cancelled monitor skips every body.
#[test]
fn a_batch_reports_its_progress_and_stops_when_cancelled() {
    let n = 5;
    let bodies = [Body::Moments(Vector3::new(2.0, 3.0, 4.0))];
    let omega = vec![Vector3::new(0.1, 1.0, 0.1); n];
    let t = [0.5, 20.0, 40.0];
    for method in methods() {
        let monitor = Monitor::new();
        let run = Simulation::new(method);
        let q0 = [UnitQuaternion::identity()];
        let out = simulate(&run, &bodies, &omega, &q0, &t, Some(&monitor)).unwrap();
        assert_eq!(out.n, n);
        assert!(
            (monitor.elapsed() - 40.0 * n as f64).abs() <= 1e-9,
            "{method:?}: {}",
            monitor.elapsed()
        );
        assert_eq!(monitor.finished(), n as u64, "{method:?}");
        monitor.cancel();
        let error = simulate(&run, &bodies, &omega, &q0, &t, Some(&monitor)).unwrap_err();
        assert_eq!(error, Error::Interrupted, "{method:?}");
        assert_eq!(
            monitor.finished(),
            n as u64,
            "{method:?}: no body ran once cancelled"
        );
    }
}

/// Every method by its name: the method of that name, `dt` required by the fixed-step ones,
/// `"auto"` the exact solution without a torque and dop853 with one; unknown names, a missing
/// `dt` and a wrong order are errors naming them.
#[test]
fn methods_by_name() {
    use polhode::dynamics::{MethodSettings, Stepping, METHODS};
    let with_dt = MethodSettings {
        dt: Some(0.1),
        ..MethodSettings::default()
    };
    for &(name, stepping) in METHODS {
        let method = Method::from_name(name, &with_dt).unwrap();
        match stepping {
            Stepping::Auto => assert_eq!(method, Method::Exact),
            _ => assert_eq!(method.name(), name),
        }
        let without = Method::from_name(name, &MethodSettings::default());
        if stepping == Stepping::Fixed {
            assert_eq!(without.unwrap_err().argument(), Some("dt"), "{name}");
        } else {
            assert!(without.is_ok(), "{name}");
        }
    }
    let torqued = MethodSettings {
        torque: true,
        rtol: 1e-8,
        ..MethodSettings::default()
    };
    assert_eq!(
        Method::from_name("auto", &torqued).unwrap(),
        Method::Dop853(Dop853Options::with_rtol(1e-8))
    );
    let order = MethodSettings {
        order: 3,
        ..with_dt
    };
    let error = Method::from_name("splitting", &order).unwrap_err();
    assert_eq!(error.argument(), Some("order"));
    let error = Method::from_name("euler", &with_dt).unwrap_err();
    assert_eq!(error.argument(), Some("method"));
}

/// Models read by kind from named fields, as a front end holds them; a missing field or an
/// unknown kind is an error naming it.
#[test]
fn torque_models_from_their_fields() {
    use polhode::dynamics::Fields;
    use std::collections::HashMap;
    struct Map(HashMap<&'static str, Vec<f64>>);
    impl Fields for Map {
        type Error = Error;
        fn error(error: Error) -> Error {
            error
        }
        fn number(&self, name: &str) -> Result<Option<f64>, Error> {
            Ok(self.0.get(name).map(|v| v[0]))
        }
        fn vector(&self, name: &str) -> Result<Option<Vector3<f64>>, Error> {
            Ok(self.0.get(name).map(|v| Vector3::new(v[0], v[1], v[2])))
        }
        fn model(&self, _: &str) -> Result<TorqueSpec, Error> {
            Ok(TorqueSpec::BodyFixed(Vector3::new(0.0, 0.0, 1.0)))
        }
        fn models(&self, name: &str) -> Result<Vec<TorqueSpec>, Error> {
            Ok(vec![self.model(name)?; 2])
        }
    }
    let fields = Map(HashMap::from([
        ("mean_motion", vec![0.5]),
        ("orbit_normal", vec![0.0, 0.0, 1.0]),
        ("radial0", vec![1.0, 0.0, 0.0]),
        ("start", vec![1.0]),
        ("end", vec![2.0]),
    ]));
    match TorqueSpec::from_fields("GravityGradient", &fields).unwrap() {
        TorqueSpec::GravityGradient {
            mean_motion,
            orbit_normal,
            radial0,
        } => {
            assert_eq!(mean_motion, 0.5);
            assert_eq!(orbit_normal, Vector3::z());
            assert_eq!(radial0, Vector3::x());
        }
        _ => panic!("not a gravity gradient"),
    }
    match TorqueSpec::from_fields("Window", &fields).unwrap() {
        TorqueSpec::Window { start, end, .. } => assert_eq!((start, end), (1.0, 2.0)),
        _ => panic!("not a window"),
    }
    assert!(matches!(
        TorqueSpec::from_fields("Sum", &fields).unwrap(),
        TorqueSpec::Sum(terms) if terms.len() == 2
    ));
    let argument = |kind| match TorqueSpec::from_fields(kind, &fields) {
        Err(error) => error.argument().map(str::to_owned),
        Ok(_) => None,
    };
    assert_eq!(argument("Gravity").as_deref(), Some("gravity"));
    assert_eq!(argument("Magnet").as_deref(), Some("torque"));
}

/// The exact solution at more output times than one chunk of its parallel work (4096): every
/// number the same bit for bit whatever the threads, serial or parallel, in a batch or alone,
/// and as each time evaluated alone (a one-time run, which has no earlier quaternion to
/// follow), the quaternions' signs those of the rule (each the sign whose dot product with
/// the one before is not negative).
#[test]
fn the_exact_solution_at_many_times_is_bitwise_each_time_alone_whatever_the_threads() {
    let r = Rotation3::from_euler_angles(0.4, -0.7, 0.5);
    let tensor =
        r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.5)) * r.matrix().transpose();
    let bodies = [
        Body::Moments(Vector3::new(1.0, 2.0, 3.0)),
        Body::Inertia(tensor),
        Body::Moments(Vector3::new(2.0, 2.0, 5.0)),
    ];
    let omega = [
        Vector3::new(0.3, 0.5, 0.8),
        Vector3::new(1.0, -0.3, 0.4),
        Vector3::new(0.2, 0.1, 2.0),
    ];
    let q0 = [UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3)];
    // 2.5 chunks, from t0 = 0.25, with repeated times and a jump.
    let mut t: Vec<f64> = (0..10_000).map(|k| 0.25 + f64::from(k) * 7e-3).collect();
    t[5000] = t[4999];
    for x in &mut t[8000..] {
        *x += 1e4;
    }
    for orientation in [true, false] {
        let run = Simulation {
            t0: 0.25,
            with_orientation: orientation,
            ..Simulation::new(Method::Exact)
        };
        let serial = Simulation {
            parallel: false,
            ..run.clone()
        };
        let batch = simulate(&serial, &bodies, &omega, &q0, &t, None).unwrap();
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let parallel = pool
                .install(|| simulate(&run, &bodies, &omega, &q0, &t, None))
                .unwrap();
            assert_eq!(parallel, batch, "{threads} threads");
        }
        for (i, body) in bodies.iter().enumerate() {
            let alone = simulate(
                &run,
                &[*body],
                &omega[i..=i],
                &q0,
                &t,
                Some(&Monitor::new()),
            )
            .unwrap();
            let rows = body_rows(&batch, i);
            assert_eq!(body_rows(&alone, 0), rows, "body {i} alone");
            if !orientation {
                continue;
            }
            let mut previous: Option<[f64; 4]> = None;
            for (j, &tj) in t.iter().enumerate() {
                let once = simulate(&serial, &[*body], &omega[i..=i], &q0, &[tj], None).unwrap();
                for ((quantity, data), row) in once.columns.iter().zip(&rows) {
                    let w = quantity.width(0);
                    let got = &row[j * w..(j + 1) * w];
                    if *quantity != Quantity::QUATERNION {
                        assert_eq!(got, &data[..], "body {i}, {quantity:?} at t[{j}]");
                        continue;
                    }
                    let dot = |p: &[f64; 4], q: &[f64]| {
                        p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3]
                    };
                    let flip = previous.is_some_and(|p| dot(&p, data) < 0.0);
                    let want: Vec<f64> = data.iter().map(|&x| if flip { -x } else { x }).collect();
                    assert_eq!(got, &want[..], "body {i}, quaternion at t[{j}]");
                    previous = Some([got[0], got[1], got[2], got[3]]);
                }
            }
        }
    }
}

/// The exact solution at many output times on several threads: its progress adds up to the
/// time span, once finished; a cancel during the run stops it; and a time beyond the
/// solution's reach is the error of the first such time, as evaluated alone.
#[test]
fn the_exact_solution_at_many_times_reports_progress_stops_and_fails_as_one_run() {
    let body = [Body::Moments(Vector3::new(1.0, 2.0, 3.0))];
    let omega = [Vector3::new(0.3, 0.5, 0.8)];
    let q0 = [UnitQuaternion::identity()];
    let t: Vec<f64> = (0..20_000).map(|k| 1.0 + f64::from(k) * 1e-2).collect();
    let run = Simulation {
        t0: 1.0,
        ..Simulation::new(Method::Exact)
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let monitor = Monitor::new();
    pool.install(|| simulate(&run, &body, &omega, &q0, &t, Some(&monitor)))
        .unwrap();
    let span = t[t.len() - 1] - 1.0;
    assert!(
        (monitor.elapsed() - span).abs() <= 1e-9 * span,
        "{}",
        monitor.elapsed()
    );
    assert_eq!(monitor.finished(), 1);

    // Cancelled once a fifth of the span is done: the run stops before its end.
    let looks = std::sync::atomic::AtomicUsize::new(0);
    let monitor = Monitor::with_on_look(move |monitor| {
        looks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if monitor.elapsed() > 0.2 * span {
            monitor.cancel();
        }
    });
    let error = pool
        .install(|| simulate(&run, &body, &omega, &q0, &t, Some(&monitor)))
        .unwrap_err();
    assert_eq!(error, Error::Interrupted);
    assert_eq!(monitor.finished(), 0);
    assert!(monitor.elapsed() < 0.9 * span, "{}", monitor.elapsed());

    // Beyond the reach of double precision from t[6000] on (the second chunk): the error of
    // that time, serial or parallel.
    let free = FreeRotation::new(Vector3::new(1.0, 2.0, 3.0), omega[0], q0[0]).unwrap();
    let mut far = t.clone();
    let beyond = 2.0 * free.max_time();
    for (k, x) in far[6000..].iter_mut().enumerate() {
        *x = beyond + k as f64 * 1e3;
    }
    let expected = free.try_state(far[6000] - 1.0).unwrap_err();
    for parallel in [false, true] {
        let run = Simulation {
            parallel,
            ..run.clone()
        };
        let error = pool
            .install(|| simulate(&run, &body, &omega, &q0, &far, None))
            .unwrap_err();
        assert_eq!(error, expected, "parallel: {parallel}");
    }
}

/// The lanes' batches (torque-free fixed steps) with bodies that fail before their runs (bad
/// moments, an `omega0` that is not finite or whose energy overflows) and during them (a
/// midpoint Newton iteration, rk4 blowing up), in several blocks and, for the splitting, axis
/// orders: the batch's error is the first failing body's, by index, as that body alone reports
/// it; and a batch without its failing bodies is unchanged by them, bit for bit.
#[test]
fn a_lane_batch_reports_its_first_failing_body_as_alone() {
    let fixed = [
        Method::Splitting {
            dt: 5e-2,
            order: SplittingOrder::Four,
        },
        Method::Midpoint { dt: 5e-2 },
        Method::Rk4 { dt: 5e-2 },
    ];
    let t = [0.0, 1.0, 20.0];
    let q0 = UnitQuaternion::from_euler_angles(0.3, 0.2, -0.1);
    // Eleven bodies, the moments in every order (six axis orders for the splitting).
    let orders = [
        [1.0, 2.0, 3.0],
        [3.0, 2.0, 1.0],
        [2.0, 1.0, 3.0],
        [1.0, 3.0, 2.0],
        [3.0, 1.0, 2.0],
        [2.0, 3.0, 1.0],
    ];
    let good: Vec<(Body, Vector3<f64>)> = (0..11)
        .map(|i| {
            let m = orders[i % 6];
            let s = 1.0 + 0.1 * i as f64;
            (
                Body::Moments(Vector3::new(m[0] * s, m[1], m[2])),
                Vector3::new(0.3 - 0.1 * i as f64, 1.0, 0.2 + 0.05 * i as f64),
            )
        })
        .collect();
    let bad_moments = (Body::Moments(Vector3::new(1.0, -2.0, 3.0)), good[0].1);
    let not_finite = (good[1].0, Vector3::new(0.1, f64::INFINITY, 0.3));
    let overflows = (good[2].0, Vector3::new(1e200, 0.0, 0.0));
    // Fails in its run: Newton for the midpoint rule, rk4 blows up (the splitting goes on).
    let fast = (good[3].0, Vector3::new(1e5, -2e5, 3e5));
    for method in fixed {
        let run = Simulation::new(method);
        let batch = |set: &[(Body, Vector3<f64>)]| {
            let (bodies, omega): (Vec<Body>, Vec<Vector3<f64>>) = set.iter().copied().unzip();
            simulate(&run, &bodies, &omega, &[q0], &t, None)
        };
        let alone = |(body, omega): (Body, Vector3<f64>)| {
            simulate(&run, &[body], &[omega], &[q0], &t, None).err()
        };
        let all = batch(&good).unwrap();
        for cases in [
            vec![(9, overflows), (4, not_finite), (6, bad_moments)],
            vec![(7, bad_moments), (8, fast), (10, not_finite)],
            vec![(2, fast), (5, overflows)],
            vec![(10, fast), (3, bad_moments)],
        ] {
            let mut set = good.clone();
            for &(i, case) in &cases {
                set[i] = case;
            }
            // The splitting does not fail on the fast body: then the others decide.
            let first = cases
                .iter()
                .filter_map(|&(i, case)| alone(case).map(|e| (i, e)))
                .min_by_key(|(i, _)| *i);
            let got = batch(&set);
            match &first {
                // Compared as printed: a blown-up value may be NaN.
                Some((i, error)) => assert_eq!(
                    format!("{:?}", got.unwrap_err()),
                    format!("{:?}", error.clone().in_body(*i)),
                    "{method:?}"
                ),
                None => {
                    // Only the fast body, which the splitting integrates: the others as before.
                    let got = got.unwrap();
                    let w = got.column("omega").unwrap();
                    let w_all = all.column("omega").unwrap();
                    for i in (0..11).filter(|i| !cases.iter().any(|(k, _)| k == i)) {
                        let r = i * t.len() * 3..(i + 1) * t.len() * 3;
                        assert_eq!(w[r.clone()], w_all[r], "{method:?} body {i}");
                    }
                }
            }
        }
    }
}

/// rk4 in a lane block with a body spinning about a principal axis far too fast for the step:
/// its angular velocity stays exact (Euler's right-hand side is zero) while its quaternion
/// overflows, an error of the orientation. The batch reports that body's error as alone, and
/// the quaternions of the others as alone.
#[test]
fn a_lane_block_reports_an_orientation_that_blows_up_as_alone() {
    let run = Simulation::new(Method::Rk4 { dt: 0.1 });
    let t = [0.0, 0.5, 10.0];
    let q0 = UnitQuaternion::from_euler_angles(0.3, 0.2, -0.1);
    let (mut bodies, mut omega) = bodies();
    bodies.push(Body::Moments(Vector3::new(1.0, 2.0, 3.0)));
    omega.push(Vector3::new(0.0, 0.0, 1e3));
    let spin = bodies.len() - 1;
    let alone = simulate(&run, &bodies[spin..], &omega[spin..], &[q0], &t, None).unwrap_err();
    assert!(
        format!("{alone}").contains("orientation"),
        "expected the orientation to blow up: {alone}"
    );
    let got = simulate(&run, &bodies, &omega, &[q0], &t, None).unwrap_err();
    assert_eq!(format!("{got:?}"), format!("{:?}", alone.in_body(spin)));
    let others = simulate(&run, &bodies[..spin], &omega[..spin], &[q0], &t, None).unwrap();
    for i in 0..spin {
        let one = simulate(&run, &bodies[i..=i], &omega[i..=i], &[q0], &t, None).unwrap();
        let q = others.column("quaternion").unwrap();
        assert_eq!(&q[i * 12..(i + 1) * 12], one.column("quaternion").unwrap());
    }
}

/// A body by `dop853` reported at every accepted step: its times are the output times and the
/// ends of its steps, in increasing order; its outputs at any of them are `simulate`'s at the
/// same times bit for bit (the steps do not depend on the output times), for a rigid body, a
/// torque and rotors, in principal axes and in a body's own axes.
#[test]
fn every_step_reports_the_steps_of_the_run_to_the_last_time() {
    use polhode::dynamics::{MotorTorque, RotorSpec};
    use polhode::simulation::simulate_every_step;
    let r = Rotation3::from_euler_angles(0.3, -0.7, 1.1);
    let tensor = r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.5)) * r.transpose();
    let grid: Vec<f64> = (0..=8).map(|k| 0.75 * f64::from(k)).collect();
    let q0 = UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3);
    let w0 = Vector3::new(0.2, 1.0, -0.3);
    let mut runs = Vec::new();
    for body in [
        Body::Moments(Vector3::new(1.0, 2.0, 3.0)),
        Body::Inertia(tensor),
    ] {
        let plain = Simulation::new(Method::Dop853(Dop853Options::with_rtol(1e-9)));
        let mut torqued = plain.clone();
        torqued.torque = Some(TorqueSpec::BodyFixed(Vector3::new(0.0, 0.05, 0.1)));
        let mut rotors = plain.clone();
        rotors.rotors = vec![
            RotorSpec::Wheel {
                axis: Vector3::z(),
                inertia: 0.1,
                rate0: 2.0,
                torque: MotorTorque::Constant(0.0),
            },
            RotorSpec::SphericalDamper {
                inertia: 0.05,
                damping: 0.02,
            },
        ];
        for run in [plain, torqued, rotors] {
            runs.push((body, run));
        }
    }
    for (body, run) in runs {
        let (times, out) = simulate_every_step(&run, &body, &w0, &q0, &grid, None).unwrap();
        assert!(times.windows(2).all(|w| w[0] < w[1]));
        assert!(grid.iter().all(|g| times.contains(g)));
        let steps = out.stats[0].steps as usize;
        // Each step's end is reported once; the last step ends at the last output time.
        assert_eq!(times.len(), grid.len() + steps - 1);
        let again = simulate(&run, &[body], &[w0], &[q0], &times, None).unwrap();
        assert_eq!(again.columns, out.columns);
        assert_eq!(again.stats[0].steps, out.stats[0].steps);
        let at_grid = simulate(&run, &[body], &[w0], &[q0], &grid, None).unwrap();
        for (quantity, data) in &at_grid.columns {
            let width = quantity.width(out.rotors);
            let all = out.column(quantity.name()).unwrap();
            for (j, g) in grid.iter().enumerate() {
                let k = times.iter().position(|t| t == g).unwrap();
                assert_eq!(
                    &all[k * width..(k + 1) * width],
                    &data[j * width..(j + 1) * width]
                );
            }
        }
    }
    // Another method has no accepted steps to report.
    let error = simulate_every_step(
        &Simulation::new(Method::Rk4 { dt: 0.01 }),
        &Body::Moments(Vector3::new(1.0, 2.0, 3.0)),
        &w0,
        &q0,
        &grid,
        None,
    )
    .unwrap_err();
    assert_eq!(error.argument(), Some("method"));
}

/// The fastest rate of a motion: for a rigid body the largest of 2 pi / P (omega's period in
/// the body), the precession about L and the largest |omega| along the motion (from the
/// exact solution at many times); with rotors |L| / I_min; with a torque from rest the spin it
/// adds over the run; over a batch the fastest body's.
#[test]
fn the_fastest_rate_is_that_of_the_motion() {
    use polhode::simulation::{fastest_rate, Pace};
    let q0 = [UnitQuaternion::identity()];
    let exact = Simulation::new(Method::Exact);
    let cases = [
        (Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.01, 1.0, 0.01)),
        (Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.3, 0.2, 1.0)),
        (Vector3::new(3.0, 1.0, 2.0), Vector3::new(0.2, 1.0, -0.3)),
        (Vector3::new(2.0, 2.0, 5.0), Vector3::new(0.3, -0.4, 1.0)),
        (Vector3::new(0.01, 1.0, 1.0), Vector3::new(0.0, 0.1, 1.0)),
    ];
    for (moments, omega) in cases {
        let rate = fastest_rate(&exact, &[Body::Moments(moments)], &[omega], &q0, 10.0).unwrap();
        let free = FreeRotation::new(moments, omega, UnitQuaternion::identity()).unwrap();
        let mut spin = 0.0_f64;
        let period = free.period();
        let span = period.unwrap_or(10.0);
        for k in 0..=20_000 {
            spin = spin.max(free.omega(span * f64::from(k) / 20_000.0).norm());
        }
        let expected = [
            period.map_or(0.0, |p| std::f64::consts::TAU / p),
            free.precession_rate_space().map_or(0.0, f64::abs),
        ]
        .into_iter()
        .fold(spin, f64::max);
        assert!(
            (rate.rate - expected).abs() <= 1e-6 * expected,
            "{moments:?} {omega:?}: {rate:?} against {expected}"
        );
        assert_ne!(rate.pace, Pace::Rest);
    }
    // A steady spin: its rate, or the precession of the motions about it (the limit the exact
    // solution gives, |w| (1 + sqrt((I3 - I1)(I3 - I2) / (I1 I2))) = 4 here); about the
    // smallest axis of a body whose other two moments are close, the spin.
    let steady = fastest_rate(
        &exact,
        &[Body::Moments(Vector3::new(1.0, 2.0, 3.0))],
        &[Vector3::new(0.0, 0.0, 2.0)],
        &q0,
        1.0,
    )
    .unwrap();
    assert_eq!((steady.rate, steady.pace), (4.0, Pace::Precession));
    let steady = fastest_rate(
        &exact,
        &[Body::Moments(Vector3::new(1.0, 2.0, 2.001))],
        &[Vector3::new(2.0, 0.0, 0.0)],
        &q0,
        1.0,
    )
    .unwrap();
    assert_eq!((steady.rate, steady.pace), (2.0, Pace::Spin));
    let rest = fastest_rate(
        &exact,
        &[Body::Moments(Vector3::new(1.0, 2.0, 3.0))],
        &[Vector3::zeros()],
        &q0,
        1.0,
    )
    .unwrap();
    assert_eq!((rest.rate, rest.pace), (0.0, Pace::Rest));
    // A batch: the fastest body, by index.
    let (bodies, omega) = bodies();
    let batch = fastest_rate(&exact, &bodies, &omega, &q0, 1.0).unwrap();
    let each: Vec<f64> = (0..4)
        .map(|i| {
            fastest_rate(&exact, &bodies[i..=i], &omega[i..=i], &q0, 1.0)
                .unwrap()
                .rate
        })
        .collect();
    let fastest = (0..4).fold(0, |a, i| if each[i] > each[a] { i } else { a });
    assert_eq!((batch.rate, batch.body), (each[fastest], fastest));
    // A torque on a body at rest: the spin it adds over the run, |I^-1 tau| (t_end - t0).
    let mut torqued = Simulation::new(Method::Dop853(Dop853Options::default()));
    torqued.torque = Some(TorqueSpec::BodyFixed(Vector3::new(0.0, 0.0, 0.3)));
    let body = [Body::Moments(Vector3::new(1.0, 2.0, 3.0))];
    let spun = fastest_rate(&torqued, &body, &[Vector3::zeros()], &q0, 4.0).unwrap();
    assert_eq!(spun.pace, Pace::Torque);
    assert!((spun.rate - 0.1 * 4.0).abs() <= 1e-15);
    // Rotors: |L| / I_min of the whole, a fast wheel's momentum included.
    let mut rotors = Simulation::new(Method::Dop853(Dop853Options::default()));
    rotors.rotors = vec![polhode::dynamics::RotorSpec::Wheel {
        axis: Vector3::z(),
        inertia: 0.1,
        rate0: 100.0,
        torque: polhode::dynamics::MotorTorque::Constant(0.0),
    }];
    let wheel = fastest_rate(&rotors, &body, &[Vector3::new(0.0, 0.0, 0.1)], &q0, 1.0).unwrap();
    assert_eq!(wheel.pace, Pace::Rotors);
    assert!((wheel.rate - (3.0 * 0.1 + 0.1 * 100.0)).abs() <= 1e-12);
    // The errors are simulate's: a bad body, in a batch by its index.
    let mut bad = bodies.clone();
    bad[2] = Body::Moments(Vector3::new(1.0, -2.0, 3.0));
    let error = fastest_rate(&exact, &bad, &omega, &q0, 1.0).unwrap_err();
    let expected = simulate(&exact, &bad, &omega, &q0, &[0.0, 1.0], None).unwrap_err();
    assert_eq!(error.to_string(), expected.to_string());
}

/// The first failing body of a batch stops the bodies after it (they cannot change the
/// batch's error, the first by index): in parallel they stop at their next look rather than
/// run to their end, as the bodies after it in order were never started. Body 0's torque
/// fails at its first call; the other 15 would make `per_body` calls each.
#[test]
fn a_failing_body_stops_the_bodies_after_it() {
    use polhode::dynamics::FunctionSpec;
    use std::sync::atomic::{AtomicU64, Ordering};
    use std::sync::Arc;

    let n = 16;
    let bodies: Vec<Body> = (0..n)
        .map(|i| Body::Moments(Vector3::new(1.0 + 0.1 * i as f64, 2.0, 3.0)))
        .collect();
    // Body 0 alone starts with omega.x = 7 (its torque fails there).
    let omega: Vec<Vector3<f64>> = (0..n)
        .map(|i| Vector3::new(if i == 0 { 7.0 } else { 0.1 }, 1.0, 0.2))
        .collect();
    let t = [0.0, 50.0];
    let q0 = [UnitQuaternion::identity()];
    for method in [
        Method::Rk4 { dt: 1e-3 },
        Method::Midpoint { dt: 1e-3 },
        Method::Splitting {
            dt: 1e-3,
            order: SplittingOrder::Four,
        },
        Method::Dop853(Dop853Options::with_rtol(1e-13)),
    ] {
        let calls = Arc::new(AtomicU64::new(0));
        let counted = Arc::clone(&calls);
        let function = move |_: f64, w: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            if w.x == 7.0 {
                return Err(Error::InvalidArgument {
                    name: "torque".into(),
                    reason: "body 0 fails".into(),
                });
            }
            counted.fetch_add(1, Ordering::Relaxed);
            Ok(Vector3::new(0.0, 0.0, 1e-3))
        };
        let mut run = Simulation::new(method);
        run.torque = Some(TorqueSpec::Function(FunctionSpec {
            function: Arc::new(function),
            depends_on_orientation: false,
            depends_on_omega: true,
            discontinuities: Vec::new(),
        }));
        simulate(&run, &bodies[1..2], &omega[1..2], &q0, &t, None).unwrap();
        let per_body = calls.swap(0, Ordering::Relaxed);
        for parallel in [false, true] {
            run.parallel = parallel;
            let error = simulate(&run, &bodies, &omega, &q0, &t, None).unwrap_err();
            assert!(
                matches!(error, Error::Body { body: 0, .. }),
                "{method:?}: {error:?}"
            );
            let made = calls.swap(0, Ordering::Relaxed);
            // Running to their end, the others would make 15 per_body calls.
            assert!(
                made < 2 * per_body,
                "{method:?}, parallel {parallel}: {made} calls, {per_body} a body"
            );
        }
    }
}
