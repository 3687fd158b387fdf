//! Criterion benchmarks of the kernels, without Python in the way:
//! `cargo bench -p polhode-bench --bench kernels`.
//!
//! One step of each integrator (with and without orientation), the driver `integrate` per step
//! of each method (with and without orientation and torque), one exact evaluation and one
//! construction of the exact solution, one eigensolve (single and per tensor in a batch), the
//! point-mass assembly per point, and the batch path `simulate` (exact, lanes, scalar, rotors).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use polhode::dynamics::{
    dop853_step, integrate, midpoint_step, rk4_step, rk4_step_omega, splitting_step,
    splitting_step_omega, BodyFixed, Dop853Options, Method, Moments, Options, SplittingOrder,
    State, Torque,
};
use polhode::exact::FreeRotation;
use polhode::MassProperties;

fn steps(c: &mut Criterion) {
    let body = Moments::new(Vector3::new(1.0, 2.0, 3.0)).unwrap();
    let state = State::new(Vector3::new(0.01, 1.0, 0.01), UnitQuaternion::identity());
    let h = 1e-2;
    let mut group = c.benchmark_group("step");
    group.bench_function("rk4 omega", |b| {
        b.iter(|| rk4_step_omega(&body, black_box(&state.omega), h))
    });
    group.bench_function("rk4 orientation", |b| {
        b.iter(|| rk4_step(&body, black_box(&state), h))
    });
    for (name, order) in [
        ("splitting2", SplittingOrder::Two),
        ("splitting4", SplittingOrder::Four),
        ("splitting6", SplittingOrder::Six),
    ] {
        group.bench_function(format!("{name} omega"), |b| {
            b.iter(|| splitting_step_omega(&body, black_box(&state.omega), h, order))
        });
        group.bench_function(format!("{name} orientation"), |b| {
            b.iter(|| splitting_step(&body, black_box(&state), h, order))
        });
    }
    group.bench_function("midpoint orientation", |b| {
        b.iter(|| midpoint_step(&body, black_box(&state), h).unwrap())
    });
    group.bench_function("dop853 orientation (one fixed step)", |b| {
        b.iter(|| dop853_step(&body, black_box(&state), h))
    });
    group.finish();
}

/// The driver over 10^4 steps of `dt = 1e-3` (for `Dop853`, over the same span), per step.
fn driver(c: &mut Criterion) {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let state = State::new(Vector3::new(0.01, 1.0, 0.01), UnitQuaternion::identity());
    let torque = BodyFixed::new(Vector3::new(0.01, -0.02, 0.03)).unwrap();
    let steps = 10_000;
    let dt = 1e-3;
    let times = [steps as f64 * dt];
    let methods = [
        (
            "splitting4",
            Method::Splitting {
                dt,
                order: SplittingOrder::Four,
            },
        ),
        ("midpoint", Method::Midpoint { dt }),
        ("rk4", Method::Rk4 { dt }),
        ("dop853", Method::Dop853(Dop853Options::default())),
    ];
    let mut group = c.benchmark_group("integrate");
    group.throughput(Throughput::Elements(steps));
    for (name, method) in methods {
        for with_orientation in [false, true] {
            for torqued in [false, true] {
                let options = Options {
                    with_orientation,
                    torque: torqued.then_some(&torque as &dyn Torque),
                    ..Options::default()
                };
                let label = format!(
                    "{name} {} {}",
                    if with_orientation {
                        "orientation"
                    } else {
                        "omega"
                    },
                    if torqued { "torqued" } else { "free" }
                );
                group.bench_function(label, |b| {
                    b.iter(|| integrate(&method, &moments, black_box(&state), &times, &options))
                });
            }
        }
    }
    group.finish();
}

fn exact(c: &mut Criterion) {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let omega0 = Vector3::new(0.01, 1.0, 0.01);
    let free = FreeRotation::new(moments, omega0, UnitQuaternion::identity()).unwrap();
    let mut group = c.benchmark_group("exact");
    group.bench_function("new", |b| {
        b.iter(|| FreeRotation::new(black_box(moments), omega0, UnitQuaternion::identity()))
    });
    group.bench_function("omega(t = 1e3)", |b| b.iter(|| free.omega(black_box(1e3))));
    group.bench_function("state(t = 1e3)", |b| b.iter(|| free.state(black_box(1e3))));
    group.bench_function("state(t = 1e12)", |b| {
        b.iter(|| free.state(black_box(1e12)))
    });
    group.finish();
}

fn eigen(c: &mut Criterion) {
    let r = Rotation3::from_euler_angles(0.3, -1.1, 2.0);
    let tensor = r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 2.5, 3.0)) * r.transpose();
    let mut group = c.benchmark_group("eigen");
    group.bench_function("symmetric_eigen3", |b| {
        b.iter(|| polhode::symmetric_eigen3(black_box(&tensor)).unwrap())
    });
    let n = 4096;
    let tensors: Vec<f64> = (0..n)
        .flat_map(|i| {
            let r = Rotation3::from_euler_angles(0.1 * i as f64, 0.7, -0.03 * i as f64);
            let d = Vector3::new(1.0, 1.5 + (i % 7) as f64, 4.0);
            let t = r.matrix() * Matrix3::from_diagonal(&d) * r.transpose();
            (0..9).map(move |k| t[(k / 3, k % 3)])
        })
        .collect();
    let (mut moments, mut axes, mut multiplicity) =
        (vec![0.0; 3 * n], vec![0.0; 9 * n], vec![0i64; 3 * n]);
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function("principal_batch per tensor", |b| {
        b.iter(|| {
            polhode::eigen::principal_batch(
                black_box(&tensors),
                polhode::eigen::DEFAULT_RTOL,
                &mut moments,
                &mut axes,
                &mut multiplicity,
            )
            .unwrap()
        })
    });
    group.finish();
}

fn points(c: &mut Criterion) {
    let n = 100_000;
    let masses: Vec<f64> = (0..n).map(|i| 1.0 + (i % 5) as f64).collect();
    let positions: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let x = i as f64;
            [(0.37 * x).sin(), (1.3 * x).cos(), 0.001 * x]
        })
        .collect();
    let mut group = c.benchmark_group("mass");
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function("point_masses per point", |b| {
        b.iter(|| MassProperties::point_masses(black_box(&masses), &positions).unwrap())
    });
    group.finish();
}

/// The batch path (`polhode::simulation::simulate`, on the calling thread): one body by the
/// exact solution at 2e4 output times; 1000 bodies by rk4 (SIMD lanes), splitting and dop853
/// over 200 steps of 0.01; one body with a spherical damper by dop853. Per output time, or per
/// body.
fn simulation(c: &mut Criterion) {
    use polhode::dynamics::RotorSpec;
    use polhode::simulation::{simulate, Body, Simulation};
    let q0 = [UnitQuaternion::identity()];
    let mut group = c.benchmark_group("simulate");
    let body = [Body::Moments(Vector3::new(1.0, 2.0, 3.0))];
    let omega0 = [Vector3::new(0.01, 1.0, 0.01)];
    let m = 20_000;
    let t: Vec<f64> = (0..m).map(|k| 200.0 * k as f64 / (m - 1) as f64).collect();
    group.throughput(Throughput::Elements(m as u64));
    for (name, with_orientation) in [("exact full state", true), ("exact omega", false)] {
        let run = Simulation {
            with_orientation,
            parallel: false,
            ..Simulation::new(Method::Exact)
        };
        group.bench_function(format!("{name} per output time"), |b| {
            b.iter(|| simulate(&run, &body, black_box(&omega0), &q0, &t, None).unwrap())
        });
    }
    let n = 1000;
    let bodies: Vec<Body> = (0..n)
        .map(|i| {
            let x = i as f64;
            Body::Moments(Vector3::new(
                1.0 + (0.37 * x).sin().abs(),
                2.0 + (1.3 * x).cos(),
                3.5,
            ))
        })
        .collect();
    let omegas: Vec<Vector3<f64>> = (0..n)
        .map(|i| Vector3::new(0.1 + 0.001 * i as f64, 1.0, -0.2))
        .collect();
    let span = [0.0, 2.0];
    group.throughput(Throughput::Elements(n as u64));
    let methods = [
        ("rk4", Method::Rk4 { dt: 0.01 }),
        (
            "splitting4",
            Method::Splitting {
                dt: 0.01,
                order: SplittingOrder::Four,
            },
        ),
        ("dop853", Method::Dop853(Dop853Options::default())),
    ];
    for (name, method) in methods {
        let run = Simulation {
            parallel: false,
            ..Simulation::new(method)
        };
        group.bench_function(format!("batch {name} per body"), |b| {
            b.iter(|| simulate(&run, &bodies, black_box(&omegas), &q0, &span, None).unwrap())
        });
    }
    group.throughput(Throughput::Elements(1));
    let run = Simulation {
        parallel: false,
        rotors: vec![RotorSpec::SphericalDamper {
            inertia: 0.2,
            damping: 0.1,
        }],
        ..Simulation::new(Method::Dop853(Dop853Options::default()))
    };
    group.bench_function("rotors dop853 one body", |b| {
        b.iter(|| simulate(&run, &body, black_box(&omega0), &q0, &[0.0, 100.0], None).unwrap())
    });
    group.finish();
}

criterion_group!(kernels, steps, driver, exact, eigen, points, simulation);
criterion_main!(kernels);
