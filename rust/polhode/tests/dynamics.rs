//! Integration tests of `polhode::dynamics` against closed forms and high-precision references.
//!
//! The long conservation runs take 1e6 steps in release mode (`cargo test --release`, as CI
//! runs) and 2e4 steps in debug mode, where they would otherwise take minutes.

// Reference values are quoted with all the digits mpmath printed.
#![allow(clippy::excessive_precision)]

use std::f64::consts::PI;

use nalgebra::{UnitQuaternion, Vector3};
use polhode::dynamics::*;
use polhode::{Error, Monitor};

/// Steps of the long conservation runs.
const LONG: usize = if cfg!(debug_assertions) {
    20_000
} else {
    1_000_000
};

fn run(
    method: Method,
    moments: Vector3<f64>,
    state0: &State,
    times: &[f64],
    options: &Options,
) -> Trajectory {
    integrate(&method, &moments, state0, times, options).unwrap()
}

fn fixed_methods(dt: f64) -> Vec<(&'static str, Method)> {
    vec![
        (
            "splitting2",
            Method::Splitting {
                dt,
                order: SplittingOrder::Two,
            },
        ),
        (
            "splitting4",
            Method::Splitting {
                dt,
                order: SplittingOrder::Four,
            },
        ),
        (
            "splitting6",
            Method::Splitting {
                dt,
                order: SplittingOrder::Six,
            },
        ),
        ("midpoint", Method::Midpoint { dt }),
        ("rk4", Method::Rk4 { dt }),
    ]
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

// ---------------------------------------------------------------------------------------------
// Krogh's rigid body: y' = (y2 y3, -y1 y3, -0.51 y1 y2), y(0) = (0, 1, 1),
// y = (sn, cn, dn)(t|0.51).
//
// Euler's equations w_i' = c_i w_j w_k with w_i = s_i y_i give c1 s2 s3 / s1 = 1,
// c2 s3 s1 / s2 = -1, c3 s1 s2 / s3 = -0.51, i.e. s3^2 = -1/(c1 c2), s2^2 = -0.51/(c1 c3),
// s1^2 = 0.51/(c2 c3), which needs I2 > I1 > I3. With I = (1, 2, 1/2): c = (3/2, -1/4, -2),
// s = (sqrt(1.02), sqrt(0.17), sqrt(8/3)).
// ---------------------------------------------------------------------------------------------

const KROGH_MOMENTS: [f64; 3] = [1.0, 2.0, 0.5];

fn krogh_scale() -> Vector3<f64> {
    Vector3::new(1.02f64.sqrt(), 0.17f64.sqrt(), (8.0f64 / 3.0).sqrt())
}

/// (t, sn, cn, dn) at m = 0.51, from
/// ```text
/// python3 -c "import mpmath as mp; mp.mp.dps = 30; [print(t, [mp.nstr(mp.ellipfun(k, t,
///   m=mp.mpf('0.51')), 20) for k in ('sn', 'cn', 'dn')]) for t in map(mp.mpf, ['0.5', '1',
///   '2', '5', '10', '20'])]"
/// ```
const KROGH_REFERENCE: [(f64, [f64; 3]); 6] = [
    (
        0.5,
        [
            0.47057739031516134827,
            0.88235872507964258839,
            0.9418407662972164363,
        ],
    ),
    (
        1.0,
        [
            0.80220075305636086038,
            0.59705439601078856953,
            0.81963511114145289907,
        ],
    ),
    (
        2.0,
        [
            0.99536621525617694157,
            -0.096156630174908009447,
            0.70336015649065803126,
        ],
    ),
    (
        5.0,
        [
            -0.91172904417333735016,
            -0.41079210071613191972,
            0.75898786321356553174,
        ],
    ),
    (
        10.0,
        [
            0.87789882041975277037,
            -0.47884617687270583056,
            0.77906339097910344877,
        ],
    ),
    (
        20.0,
        [
            -0.93965707987292039619,
            -0.34211777540007490653,
            0.74141265961999530078,
        ],
    ),
];

fn krogh_state0() -> State {
    let s = krogh_scale();
    State::from_omega(Vector3::new(0.0, s[1], s[2]))
}

fn krogh_exact(k: usize) -> Vector3<f64> {
    Vector3::from(KROGH_REFERENCE[k].1).component_mul(&krogh_scale())
}

fn krogh_times() -> Vec<f64> {
    KROGH_REFERENCE.iter().map(|r| r.0).collect()
}

#[test]
fn krogh_body_matches_jacobi_elliptic_functions() {
    let moments = Vector3::from(KROGH_MOMENTS);
    let times = krogh_times();
    let scale = krogh_state0().omega.norm();
    // (method, largest error relative to |w| over t in [0, 20]) at dt = 1e-2.
    let bounds = [3e-5, 2e-8, 3e-12, 6e-5, 2e-9];
    for ((name, method), bound) in fixed_methods(1e-2).into_iter().zip(bounds) {
        for with_orientation in [false, true] {
            let options = Options {
                with_orientation,
                ..Options::default()
            };
            let sol = run(method, moments, &krogh_state0(), &times, &options);
            assert_eq!(sol.orientation.is_some(), with_orientation);
            for (k, t) in times.iter().enumerate() {
                let err = (sol.omega[k] - krogh_exact(k)).norm() / scale;
                assert!(
                    err < bound,
                    "{name} orientation={with_orientation} t={t}: {err:e}"
                );
            }
        }
    }
    for with_orientation in [false, true] {
        let options = Options {
            with_orientation,
            ..Options::default()
        };
        let sol = run(
            Method::Dop853(Dop853Options::with_rtol(1e-13)),
            moments,
            &krogh_state0(),
            &times,
            &options,
        );
        for (k, t) in times.iter().enumerate() {
            let err = (sol.omega[k] - krogh_exact(k)).norm() / scale;
            assert!(err < 2e-12, "dop853 t={t}: {err:e}");
        }
    }
}

/// log2 of the error ratio when halving the step.
fn observed_order(err: impl Fn(f64) -> f64, dt: f64) -> f64 {
    (err(dt) / err(dt / 2.0)).log2()
}

#[test]
fn orders_of_convergence_on_krogh_body() {
    let moments = Vector3::from(KROGH_MOMENTS);
    let exact = krogh_exact(3); // t = 5
                                // (method, order, dt with the error well above round-off)
    let cases = [
        (SplittingOrder::Two, 2.0, 0.05),
        (SplittingOrder::Four, 4.0, 0.05),
        (SplittingOrder::Six, 6.0, 0.1),
    ];
    for (order, p, dt) in cases {
        for with_orientation in [false, true] {
            let options = Options {
                with_orientation,
                ..Options::default()
            };
            let err = |dt: f64| {
                let sol = run(
                    Method::Splitting { dt, order },
                    moments,
                    &krogh_state0(),
                    &[5.0],
                    &options,
                );
                (sol.omega[0] - exact).norm()
            };
            let q = observed_order(err, dt);
            assert!(
                (q - p).abs() < 0.1,
                "splitting {order:?}: observed order {q}"
            );
        }
    }
    for (name, method, p, dt) in [("midpoint", 0, 2.0, 0.05), ("rk4", 1, 4.0, 0.05)] {
        for with_orientation in [false, true] {
            let options = Options {
                with_orientation,
                ..Options::default()
            };
            let err = |dt: f64| {
                let m = if method == 0 {
                    Method::Midpoint { dt }
                } else {
                    Method::Rk4 { dt }
                };
                (run(m, moments, &krogh_state0(), &[5.0], &options).omega[0] - exact).norm()
            };
            let q = observed_order(err, dt);
            assert!((q - p).abs() < 0.1, "{name}: observed order {q}");
        }
    }
    // The 8th-order Dormand-Prince step, taken with a fixed step.
    let body = Moments::new(moments).unwrap();
    let err = |h: f64| {
        let mut w = krogh_state0().omega;
        for _ in 0..(5.0 / h).round() as usize {
            w = dop853_step_omega(&body, &w, h);
        }
        (w - exact).norm()
    };
    let q = observed_order(err, 0.5);
    assert!((q - 8.0).abs() < 0.5, "dop853: observed order {q}");
}

// ---------------------------------------------------------------------------------------------
// The free symmetric top (I1 = I2) in closed form, orientation included:
// m3 is constant and R(t) = exp(t |L|/I1 [l]) R0 exp(t (1/I3 - 1/I1) m3 [e3]), l = L/|L| in
// space (Landau-Lifshitz par. 33). Check: R^T R' = [(m/I1) + (1/I3 - 1/I1) m3 e3] = [w].
// ---------------------------------------------------------------------------------------------

fn symmetric_top_exact(moments: &Vector3<f64>, s0: &State, t: f64) -> State {
    let m = moments.component_mul(&s0.omega);
    let l = s0.orientation * m;
    let spin = (1.0 / moments[2] - 1.0 / moments[0]) * m[2];
    let space = UnitQuaternion::from_scaled_axis(l * (t / moments[0]));
    let body = UnitQuaternion::from_scaled_axis(Vector3::z() * (spin * t));
    let orientation = space * s0.orientation * body;
    State::new(
        moments.component_div(&(orientation.inverse() * l)),
        orientation,
    )
}

fn symmetric_top() -> (Vector3<f64>, State) {
    let moments = Vector3::new(1.0, 1.0, 0.4);
    let orientation = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7);
    (
        moments,
        State::new(Vector3::new(0.8, -0.3, 2.0), orientation),
    )
}

#[test]
fn symmetric_top_orientation_matches_closed_form_and_converges_at_the_right_order() {
    let (moments, s0) = symmetric_top();
    let t_end = 6.0;
    let exact = symmetric_top_exact(&moments, &s0, t_end);
    let mut methods = fixed_methods(0.0);
    methods.push(("dop853", Method::Dop853(Dop853Options::with_rtol(1e-13))));
    let orders = [2.0, 4.0, 6.0, 2.0, 4.0];
    for (k, (name, method)) in methods.into_iter().enumerate() {
        let err = |dt: f64| {
            let m = match method {
                Method::Splitting { order, .. } => Method::Splitting { dt, order },
                Method::Midpoint { .. } => Method::Midpoint { dt },
                Method::Rk4 { .. } => Method::Rk4 { dt },
                other => other,
            };
            let sol = run(m, moments, &s0, &[t_end], &Options::default());
            sol.orientation.unwrap()[0].angle_to(&exact.orientation)
        };
        if k < orders.len() {
            let dt = if k == 2 { 0.1 } else { 0.02 };
            let q = observed_order(err, dt);
            assert!(
                (q - orders[k]).abs() < 0.15,
                "{name}: observed orientation order {q}"
            );
        } else {
            let e = err(0.0);
            assert!(e < 1e-11, "{name}: orientation error {e:e}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Conservation over long runs.
// ---------------------------------------------------------------------------------------------

/// `(|L|, L_space, T)` relative errors along a run of `n` steps of `step`.
fn drift(
    moments: Vector3<f64>,
    s0: State,
    n: usize,
    mut step: impl FnMut(&State) -> State,
) -> (f64, f64, f64, f64, f64) {
    let l0 = s0.orientation * moments.component_mul(&s0.omega);
    let t0 = 0.5 * s0.omega.dot(&moments.component_mul(&s0.omega));
    let mut s = s0;
    let (mut dl, mut dls, mut dt_first, mut dt_last) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut dt_max = 0.0f64;
    for k in 0..n {
        s = step(&s);
        if k % 100 == 99 || k + 1 == n {
            let m = moments.component_mul(&s.omega);
            dl = dl.max(rel(m.norm(), l0.norm()));
            dls = dls.max((s.orientation * m - l0).norm() / l0.norm());
            let e = rel(0.5 * s.omega.dot(&m), t0);
            dt_max = dt_max.max(e);
            if k < n / 2 {
                dt_first = dt_first.max(e);
            } else {
                dt_last = dt_last.max(e);
            }
        }
    }
    (dl, dls, dt_max, dt_first, dt_last)
}

#[test]
fn splitting_conserves_angular_momentum_over_long_runs() {
    // A flat body (I1 = I2 + I3) and a generic one, starting near the largest axis.
    for moments in [Vector3::new(1.0, 0.75, 0.25), Vector3::new(1.0, 0.6, 0.3)] {
        let s0 = State::new(
            Vector3::new(1.0, 0.1, 0.2),
            UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
        );
        let body = Moments::new(moments).unwrap();
        let l0 = s0.angular_momentum_space(&body);
        let t0 = body.kinetic_energy(&s0.omega);
        for order in [
            SplittingOrder::Two,
            SplittingOrder::Four,
            SplittingOrder::Six,
        ] {
            // 1e6 Strang steps; as many stages for the compositions (3 and 7 stages a step).
            let n = LONG / [1, 3, 7][order.order() as usize / 2 - 1];
            // Through the driver, 1000 outputs.
            let (dt, per_output) = (0.01, n / 1000);
            let times: Vec<f64> = (1..=1000).map(|k| (k * per_output) as f64 * dt).collect();
            let sol = run(
                Method::Splitting { dt, order },
                moments,
                &s0,
                &times,
                &Options::default(),
            );
            assert_eq!(sol.stats.steps, 1000 * per_output as u64);
            let att = sol.orientation.unwrap();
            let (mut dl, mut dls, mut de_first, mut de_last) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for (k, (w, q)) in sol.omega.iter().zip(&att).enumerate() {
                let s = State::new(*w, *q);
                dl = dl.max(rel(body.angular_momentum(w).norm(), l0.norm()));
                dls = dls.max((s.angular_momentum_space(&body) - l0).norm() / l0.norm());
                let de = rel(body.kinetic_energy(w), t0);
                if k < 500 {
                    de_first = de_first.max(de);
                } else {
                    de_last = de_last.max(de);
                }
            }
            assert!(
                dl < 1e-12 && dls < 1e-12,
                "{moments:?} {order:?}: |L| {dl:e}, L_space {dls:e}"
            );
            // Energy error bounded, without secular growth.
            assert!(
                de_first < 1e-5,
                "{moments:?} {order:?}: energy {de_first:e}"
            );
            assert!(
                de_last <= 2.0 * de_first + 1e-13,
                "{order:?}: energy drifts: {de_first:e} then {de_last:e}"
            );
            // The single-step function, angular velocity only: |L| to round-off.
            let mut w = s0.omega;
            for _ in 0..n {
                w = splitting_step_omega(&body, &w, dt, order);
            }
            let e = rel(body.angular_momentum(&w).norm(), l0.norm());
            assert!(e < 1e-12, "{order:?}: |L| {e:e} after {n} steps");
        }
    }
}

#[test]
fn midpoint_conserves_energy_and_angular_momentum_over_long_runs() {
    let moments = Vector3::new(1.0, 0.75, 0.25);
    let s0 = State::new(Vector3::new(1.0, 0.1, 0.2), UnitQuaternion::identity());
    let body = Moments::new(moments).unwrap();
    let (dl, _dls, dt_max, _, _) = drift(moments, s0, LONG, |s| {
        midpoint_step(&body, s, 0.01).unwrap()
    });
    assert!(dl < 1e-12 && dt_max < 1e-12, "|L| {dl:e}, T {dt_max:e}");
    // The same through the driver, angular velocity only.
    let times: Vec<f64> = (1..=10).map(|k| k as f64 * LONG as f64 * 1e-3).collect();
    let sol = run(
        Method::Midpoint { dt: 0.01 },
        moments,
        &s0,
        &times,
        &Options {
            with_orientation: false,
            ..Options::default()
        },
    );
    assert_eq!(sol.stats.steps, LONG as u64);
    let t0 = body.kinetic_energy(&s0.omega);
    let l0 = body.angular_momentum(&s0.omega).norm();
    for w in &sol.omega {
        assert!(rel(body.kinetic_energy(w), t0) < 1e-12);
        assert!(rel(body.angular_momentum(w).norm(), l0) < 1e-12);
    }
}

#[test]
fn thin_rod_does_not_blow_up() {
    let moments = Vector3::new(6.58e-6, 1.7231e-4, 1.7243e-4);
    let s0 = State::new(Vector3::new(20.0, 1.0, -0.5), UnitQuaternion::identity());
    let body = Moments::new(moments).unwrap();
    let (t0, l0) = (
        body.kinetic_energy(&s0.omega),
        s0.angular_momentum_space(&body),
    );
    let times = [10.0];
    let mut methods = fixed_methods(1e-3);
    methods.push(("dop853", Method::Dop853(Dop853Options::default())));
    // Relative errors of T and L_space (the midpoint rule conserves |L| but not its direction).
    let bounds = [
        (1e-8, 1e-14),
        (1e-11, 1e-14),
        (1e-12, 1e-14),
        (1e-13, 1e-3),
        (1e-9, 1e-7),
        (1e-8, 1e-7),
    ];
    for ((name, method), (bound_t, bound_l)) in methods.into_iter().zip(bounds) {
        let sol = run(method, moments, &s0, &times, &Options::default());
        let s = State::new(sol.omega[0], sol.orientation.unwrap()[0]);
        let l = s.angular_momentum_space(&body);
        let (e_t, e_l) = (
            rel(body.kinetic_energy(&s.omega), t0),
            (l - l0).norm() / l0.norm(),
        );
        let e_norm = rel(l.norm(), l0.norm());
        assert!(
            e_t < bound_t && e_l < bound_l && e_norm < bound_l.max(1e-13),
            "{name}: T {e_t:e}, L {e_l:e}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// DOP853 near the separatrix: I = (3, 5, 9), L0 = (0, 2, 0.01).
// Reference: mpmath.odefun (Taylor series) at 30 digits:
// `import mpmath as mp; mp.mp.dps = 30; I = [3, 5, 9]; w0 = [0, mp.mpf(2)/5, mp.mpf('0.01')/9];
//  c = [mp.mpf(I[1]-I[2])/I[0], mp.mpf(I[2]-I[0])/I[1], mp.mpf(I[0]-I[1])/I[2]];
//  f = mp.odefun(lambda t, w: [c[0]*w[1]*w[2], c[1]*w[2]*w[0], c[2]*w[0]*w[1]], 0, w0);
//  [print(t, [mp.nstr(x, 22) for x in f(t)]) for t in [10, 25, 50, 75, 100]]`
// ---------------------------------------------------------------------------------------------

const SEPARATRIX_REFERENCE: [(f64, [f64; 3]); 5] = [
    (
        10.0,
        [
            -0.01184969858355836984427,
            0.399842001519513871702,
            0.004963580091167272313746,
        ],
    ),
    (
        25.0,
        [
            -0.2761903495169538815251,
            0.3022366651323637264896,
            0.112759712496459002061,
        ],
    ),
    (
        50.0,
        [
            -0.009583707551017957804982,
            -0.3998966582688818934411,
            0.004067244313431516121542,
        ],
    ),
    (
        75.0,
        [
            0.0436459520722273284848,
            -0.3978511377147713416772,
            0.01785299479871921673745,
        ],
    ),
    (
        100.0,
        [
            0.06969808760992535583711,
            0.3944970962189294146172,
            0.02847581085731138522721,
        ],
    ),
];

#[test]
fn dop853_near_the_separatrix_matches_high_precision_reference() {
    let moments = Vector3::new(3.0, 5.0, 9.0);
    let s0 = State::from_omega(Vector3::new(0.0, 2.0, 0.01).component_div(&moments));
    let times: Vec<f64> = SEPARATRIX_REFERENCE.iter().map(|r| r.0).collect();
    for with_orientation in [false, true] {
        let options = Options {
            with_orientation,
            ..Options::default()
        };
        let sol = run(
            Method::Dop853(Dop853Options::with_rtol(1e-12)),
            moments,
            &s0,
            &times,
            &options,
        );
        for (k, (t, w)) in SEPARATRIX_REFERENCE.iter().enumerate() {
            let err = (sol.omega[k] - Vector3::from(*w)).norm();
            assert!(
                err < 1e-10,
                "orientation={with_orientation} t={t}: {err:e} ({:?})",
                sol.stats
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Torques.
// ---------------------------------------------------------------------------------------------

/// The heavy symmetric top: E = T + V, L . g_hat (space) and L3 (body) are constant.
#[test]
fn heavy_symmetric_top_conserves_its_invariants() {
    let moments = Vector3::new(1.0, 1.0, 0.5); // about the pivot
    let gravity = Vector3::new(0.0, 0.0, -9.81);
    let top = Gravity::new(Vector3::new(0.0, 0.0, 0.1), 1.0, gravity).unwrap();
    let s0 = State::new(
        Vector3::new(0.5, 0.0, 20.0),
        UnitQuaternion::from_euler_angles(0.5, 0.0, 0.0),
    );
    let body = Moments::new(moments).unwrap();
    let energy = |s: &State| body.kinetic_energy(&s.omega) + top.potential_energy(&s.orientation);
    let lz = |s: &State| s.angular_momentum_space(&body).dot(&gravity.normalize());
    let l3 = |s: &State| moments[2] * s.omega[2];
    let (e0, lz0, l30) = (energy(&s0), lz(&s0), l3(&s0));
    let l_scale = body.angular_momentum(&s0.omega).norm();
    let times: Vec<f64> = (1..=20).map(|k| k as f64 * 0.5).collect();
    let options = Options {
        torque: Some(&top),
        ..Options::default()
    };
    let mut methods = fixed_methods(1e-3);
    methods.push(("dop853", Method::Dop853(Dop853Options::with_rtol(1e-12))));
    // Bounds (relative): energy, L_z, L_3. The splitting's kicks are torques normal to g in
    // space and its free flows keep L_space: L_z to round-off. Every method keeps w3 exactly
    // (w3' = 0 identically) but the splitting, whose axis rotations about e1, e2 move m3.
    let bounds = [
        [1e-7, 1e-13, 1e-7],
        [5e-12, 1e-13, 5e-12],
        [2e-13, 1e-13, 1e-13],
        [3e-8, 3e-6, 1e-15],
        [1e-12, 5e-11, 1e-15],
        [5e-13, 3e-11, 1e-15],
    ];
    for ((name, method), b) in methods.into_iter().zip(bounds) {
        let sol = run(method, moments, &s0, &times, &options);
        let att = sol.orientation.unwrap();
        let mut worst = [0.0f64; 3];
        for (w, q) in sol.omega.iter().zip(&att) {
            let s = State::new(*w, *q);
            worst[0] = worst[0].max((energy(&s) - e0).abs() / e0.abs());
            worst[1] = worst[1].max((lz(&s) - lz0).abs() / l_scale);
            worst[2] = worst[2].max((l3(&s) - l30).abs() / l_scale);
        }
        assert!(
            worst.iter().zip(&b).all(|(w, b)| w < b),
            "{name}: E, Lz, L3 {worst:?}"
        );
    }
}

/// I = (0.5, 2, 3), w0 = (1, 0, 0.9), torque 0.25 sin^2 t about body axis 3 on [3 pi, 4 pi].
/// Reference: mpmath.odefun at 30 digits, piecewise over [0, 3 pi], [3 pi, 4 pi], [4 pi, 20]
/// (the torque is C^1 at the switches):
/// `c = [(I2-I3)/I1, (I3-I1)/I2, (I1-I2)/I3]; free = lambda t, w: [c[0]*w[1]*w[2], ...];
///  forced adds 0.25 sin(t)^2 / I3 to w3'; f1 = mp.odefun(free, 0, w0); f2 = mp.odefun(forced,
///  3*mp.pi, f1(3*mp.pi)); f3 = mp.odefun(free, 4*mp.pi, f2(4*mp.pi))`, printed with 22 digits.
const TORQUED_REFERENCE: [(f64, [f64; 3]); 5] = [
    (
        5.0,
        [
            0.9716899970677550153147,
            0.1867795317989672177968,
            0.8922137426650541329158,
        ],
    ),
    (
        10.0,
        [
            0.8896590342181640462611,
            0.3609941159787126767976,
            0.8756003877860809300172,
        ],
    ),
    (
        12.0,
        [
            -0.9941191227758905890583,
            -0.08561238860152546970508,
            1.012724463713526532156,
        ],
    ),
    (
        15.0,
        [
            0.0890302911633593696832,
            0.7874299997679823343211,
            0.8888141820835497234592,
        ],
    ),
    (
        20.0,
        [
            -0.9011799837228600526072,
            0.3426684229481774946707,
            0.9955101169010664168852,
        ],
    ),
];

#[test]
fn windowed_torque_matches_high_precision_reference() {
    let moments = Vector3::new(0.5, 2.0, 3.0);
    let s0 = State::from_omega(Vector3::new(1.0, 0.0, 0.9));
    let pulse = Function::with_dependencies(
        |t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            Ok(Vector3::new(0.0, 0.0, 0.25 * t.sin().powi(2)))
        },
        false,
        false,
    );
    let torque = Window::new(pulse, 3.0 * PI, 4.0 * PI).unwrap();
    let times: Vec<f64> = TORQUED_REFERENCE.iter().map(|r| r.0).collect();
    let mut methods = fixed_methods(1e-3);
    methods.push(("dop853", Method::Dop853(Dop853Options::with_rtol(1e-13))));
    // Largest errors in w and (against a tight dop853) in the orientation, in radians.
    let bounds = [
        (3e-6, 3e-6),
        (5e-12, 5e-12),
        (2e-12, 3e-12),
        (5e-6, 5e-6),
        (3e-12, 3e-12),
        (1e-12, 0.0),
    ];
    let options = Options {
        torque: Some(&torque),
        ..Options::default()
    };
    let tight = run(
        Method::Dop853(Dop853Options::with_rtol(1e-14)),
        moments,
        &s0,
        &times,
        &options,
    )
    .orientation
    .unwrap();
    for ((name, method), (bound_w, bound_q)) in methods.into_iter().zip(bounds) {
        for with_orientation in [false, true] {
            let options = Options {
                torque: Some(&torque),
                with_orientation,
                ..Options::default()
            };
            let sol = run(method, moments, &s0, &times, &options);
            for (k, (t, w)) in TORQUED_REFERENCE.iter().enumerate() {
                let err = (sol.omega[k] - Vector3::from(*w)).norm();
                assert!(
                    err < bound_w,
                    "{name} orientation={with_orientation} t={t}: {err:e}"
                );
                if let (Some(att), true) = (&sol.orientation, bound_q > 0.0) {
                    let e = att[k].angle_to(&tight[k]);
                    assert!(e < bound_q, "{name} t={t}: orientation {e:e}");
                }
            }
        }
    }
}

#[test]
fn gravity_gradient_torque_has_its_closed_form() {
    // r = (cos a, 0, sin a) in body axes gives tau = (0, 3 n^2 (Ix - Iz) sin a cos a, 0).
    let moments = Vector3::new(2.0, 3.0, 5.0);
    let n = 1.3e-3;
    let gg = GravityGradient::new(moments, n, Vector3::z(), Vector3::x()).unwrap();
    for a in [0.0, 0.3, 1.0, 2.5] {
        // x_space = R x_body; radial (space x at t = 0) in body = R^T x = (cos a, 0, sin a).
        let orientation = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), a);
        let tau = gg.torque_body(0.0, &Vector3::zeros(), &orientation);
        let expected = Vector3::new(0.0, 3.0 * n * n * (2.0 - 5.0) * a.sin() * a.cos(), 0.0);
        assert!(
            (tau - expected).norm() <= 1e-15 * n * n * 10.0,
            "{a}: {tau:?} vs {expected:?}"
        );
    }
    // Radial direction: a quarter orbit later it points along k x r0.
    let r = gg.radial_space(PI / 2.0 / n);
    assert!((r - Vector3::y()).norm() < 1e-12);
}

#[test]
fn earth_pointing_satellite_is_a_relative_equilibrium() {
    // Body axes = (radial, along-track, orbit normal), spinning at the orbital rate: r stays on
    // a principal axis, the torque vanishes and the body keeps pointing at the Earth.
    let moments = Vector3::new(4.0, 5.0, 6.0);
    let n = 1.1e-3;
    let gg = GravityGradient::new(moments, n, Vector3::z(), Vector3::x()).unwrap();
    let s0 = State::from_omega(Vector3::new(0.0, 0.0, n));
    let period = 2.0 * PI / n;
    let times = [0.37 * period, 1.7 * period];
    let options = Options {
        torque: Some(&gg),
        ..Options::default()
    };
    let dt = period / 500.0;
    for (name, method, bound) in [
        (
            "splitting",
            Method::Splitting {
                dt,
                order: SplittingOrder::Two,
            },
            1e-12,
        ),
        ("rk4", Method::Rk4 { dt }, 1e-10),
        ("dop853", Method::Dop853(Dop853Options::default()), 1e-9),
        // Turning by 4 atan(h n / 4) instead of h n a step, it lags by 850 (h n)^3 / 48.
        ("midpoint", Method::Midpoint { dt }, 1e-4),
    ] {
        let sol = run(method, moments, &s0, &times, &options);
        let att = sol.orientation.unwrap();
        for k in 0..times.len() {
            let x_body_in_space = att[k] * Vector3::x();
            let e = (x_body_in_space - gg.radial_space(times[k])).norm();
            assert!(e < bound, "{name}: pointing error {e:e}");
            assert!(
                (sol.omega[k] - s0.omega).norm() < bound * n,
                "{name}: {:?}",
                sol.omega[k]
            );
        }
    }
}

#[test]
fn midpoint_turns_by_the_cayley_angle() {
    // Free spin about a principal axis: the midpoint rule turns by 4 atan(h w / 4) a step.
    let moments = Vector3::new(4.0, 5.0, 6.0);
    let w = 2.0;
    let s0 = State::from_omega(Vector3::new(0.0, w, 0.0));
    let (dt, steps) = (0.05, 123.0);
    let sol = run(
        Method::Midpoint { dt },
        moments,
        &s0,
        &[steps * dt],
        &Options::default(),
    );
    let angle = steps * 4.0 * (dt * w / 4.0).atan();
    let expected = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), angle);
    let e = sol.orientation.unwrap()[0].angle_to(&expected);
    assert!(e < 1e-13, "{e:e}");
    assert_eq!(sol.omega[0], s0.omega);
}

#[test]
fn constant_and_summed_torques() {
    // A body-axis torque on a sphere: w(t) = w0 + tau t / I.
    let moments = Vector3::new(2.0, 2.0, 2.0);
    let tau = Vector3::new(0.2, -0.4, 0.6);
    let half = BodyFixed::new(tau * 0.5).unwrap();
    let sum = Sum::new()
        .with(half)
        .with(BodyFixed::new(tau * 0.5).unwrap());
    assert!(!sum.depends_on_orientation() && !sum.depends_on_omega());
    let s0 = State::from_omega(Vector3::new(1.0, 2.0, 3.0));
    let options = Options {
        torque: Some(&sum),
        with_orientation: false,
        ..Options::default()
    };
    // The axis rotations of the splitting do not commute: for a sphere its free flow is exact
    // only up to O(dt^p); the other methods are exact here.
    let bounds = [1e-5, 1e-10, 1e-12, 1e-12, 1e-12, 1e-12];
    let methods = fixed_methods(1e-3)
        .into_iter()
        .chain([("dop853", Method::Dop853(Dop853Options::default()))]);
    for ((name, method), bound) in methods.zip(bounds) {
        let sol = run(method, moments, &s0, &[3.0], &options);
        let expected = s0.omega + tau * (3.0 / 2.0);
        assert!(
            (sol.omega[0] - expected).norm() < bound * expected.norm(),
            "{name}: {:?}",
            sol.omega[0]
        );
    }
    // A space-fixed torque on a sphere at rest: L_space(t) = tau_space t.
    let space = SpaceFixed::new(Vector3::new(0.0, 0.0, 0.5)).unwrap();
    let s0 = State::new(
        Vector3::zeros(),
        UnitQuaternion::from_euler_angles(0.4, 0.1, -0.3),
    );
    let options = Options {
        torque: Some(&space),
        ..Options::default()
    };
    let methods = fixed_methods(1e-3)
        .into_iter()
        .chain([("dop853", Method::Dop853(Dop853Options::default()))]);
    for ((name, method), bound) in methods.zip(bounds) {
        let sol = run(method, moments, &s0, &[4.0], &options);
        let l = sol.orientation.unwrap()[0] * moments.component_mul(&sol.omega[0]);
        assert!(
            (l - Vector3::new(0.0, 0.0, 2.0)).norm() < bound * 2.0,
            "{name}: {l:?}"
        );
    }
}

#[test]
fn a_failing_torque_stops_the_integration_with_its_error() {
    let failing = Function::new(|t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
        if t > 1.0 {
            Err(Error::InvalidArgument {
                name: "torque".into(),
                reason: "raised in the callable".into(),
            })
        } else {
            Ok(Vector3::new(0.0, 0.0, 0.1))
        }
    });
    let nan = Function::new(|t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
        Ok(Vector3::new(0.0, if t > 1.0 { f64::NAN } else { 0.0 }, 0.0))
    });
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let s0 = State::from_omega(Vector3::new(0.1, 0.2, 0.3));
    let mut methods = fixed_methods(0.01);
    methods.push(("dop853", Method::Dop853(Dop853Options::default())));
    for (name, method) in methods {
        for with_orientation in [false, true] {
            let options = Options {
                torque: Some(&failing),
                with_orientation,
                ..Options::default()
            };
            let err = integrate(&method, &moments, &s0, &[0.5, 2.0], &options).unwrap_err();
            assert!(
                matches!(&err, Error::InvalidArgument { reason, .. }
                    if reason == "raised in the callable"),
                "{name}: {err}"
            );
            let options = Options {
                torque: Some(&nan),
                with_orientation,
                ..Options::default()
            };
            let err = integrate(&method, &moments, &s0, &[0.5, 2.0], &options).unwrap_err();
            assert!(matches!(&err, Error::NonFinite { .. }), "{name}: {err}");
        }
    }
}

#[test]
fn invalid_arguments_are_rejected_with_named_errors() {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let s0 = State::from_omega(Vector3::new(0.1, 0.2, 0.3));
    let rk4 = Method::Rk4 { dt: 0.1 };
    let o = Options::default();
    let name_of = |e: Error| match e {
        Error::NonFinite { name, .. }
        | Error::NonPositive { name, .. }
        | Error::InvalidArgument { name, .. } => name,
        other => panic!("unexpected {other}"),
    };
    let bad_omega = State::from_omega(Vector3::new(0.0, f64::NAN, 0.0));
    assert_eq!(
        name_of(integrate(&rk4, &moments, &bad_omega, &[1.0], &o).unwrap_err()),
        "state0.omega[1]"
    );
    assert_eq!(
        name_of(integrate(&rk4, &Vector3::new(1.0, 0.0, 3.0), &s0, &[1.0], &o).unwrap_err()),
        "moments[1]"
    );
    assert_eq!(
        name_of(integrate(&rk4, &Vector3::new(1.0, 2.0, -3.0), &s0, &[1.0], &o).unwrap_err()),
        "moments[2]"
    );
    for dt in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        for m in [
            Method::Rk4 { dt },
            Method::Midpoint { dt },
            Method::Splitting {
                dt,
                order: SplittingOrder::Two,
            },
        ] {
            assert_eq!(
                name_of(integrate(&m, &moments, &s0, &[1.0], &o).unwrap_err()),
                "dt"
            );
        }
    }
    // The output times are named `t`.
    let decreasing = integrate(&rk4, &moments, &s0, &[1.0, 0.5], &o).unwrap_err();
    assert_eq!(
        decreasing.to_string(),
        "Invalid `t`: expected non-decreasing t, got t[0] = 1 > t[1] = 0.5."
    );
    assert_eq!(name_of(decreasing), "t");
    let nan = integrate(&rk4, &moments, &s0, &[1.0, f64::NAN], &o).unwrap_err();
    assert_eq!(nan.to_string(), "Expected `t[1]` to be finite, got NaN.");
    assert_eq!(name_of(nan), "t[1]");
    let late = Options {
        t0: 2.0,
        ..Options::default()
    };
    let early = integrate(&rk4, &moments, &s0, &[1.0], &late).unwrap_err();
    assert_eq!(
        early.to_string(),
        "Invalid `t`: expected t[0] >= t0 = 2, got 1."
    );
    assert_eq!(name_of(early), "t");
    let dop = |rtol, atol| {
        Method::Dop853(Dop853Options {
            rtol,
            atol,
            ..Dop853Options::default()
        })
    };
    assert_eq!(
        name_of(integrate(&dop(0.0, None), &moments, &s0, &[1.0], &o).unwrap_err()),
        "rtol"
    );
    assert_eq!(
        name_of(integrate(&dop(1e-20, None), &moments, &s0, &[1.0], &o).unwrap_err()),
        "rtol"
    );
    assert_eq!(
        name_of(integrate(&dop(1e-8, Some(-1.0)), &moments, &s0, &[1.0], &o).unwrap_err()),
        "atol"
    );
    let few = Options {
        max_steps: 10,
        ..Options::default()
    };
    assert!(integrate(&rk4, &moments, &s0, &[10.0], &few).is_err());
    assert!(matches!(
        integrate(&dop(1e-12, None), &moments, &s0, &[1e3], &few),
        Err(Error::NoConvergence { .. })
    ));
    assert!(Moments::new(Vector3::new(1.0, f64::INFINITY, 1.0)).is_err());
    // The angular-velocity-only steps refuse an orientation-dependent torque.
    let body = Moments::new(moments).unwrap();
    let gravity = Gravity::new(Vector3::z(), 1.0, -Vector3::z()).unwrap();
    assert!(rk4_step_omega_torqued(&body, &gravity, 0.0, &s0.omega, 0.1).is_err());
    assert!(GravityGradient::new(moments, 1.0, Vector3::z(), Vector3::z() * 2.0).is_err());
    assert!(Window::new(gravity, 2.0, 1.0).is_err());
}

#[test]
fn output_times_are_hit_exactly_and_steps_never_exceed_dt() {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let s0 = State::from_omega(Vector3::new(0.3, 0.2, 0.1));
    let body = Moments::new(moments).unwrap();
    // t0 = 1, outputs at t0 (initial state), twice at 1.25, and at 1.3: 3 + 0 + 1 steps of dt 0.1.
    let options = Options {
        t0: 1.0,
        ..Options::default()
    };
    let sol = run(
        Method::Rk4 { dt: 0.1 },
        moments,
        &s0,
        &[1.0, 1.25, 1.25, 1.3],
        &options,
    );
    assert_eq!(sol.stats.steps, 4);
    assert_eq!(sol.omega[0], s0.omega);
    assert_eq!(sol.orientation.as_ref().unwrap()[0], s0.orientation);
    assert_eq!(sol.omega[1], sol.omega[2]);
    let mut s = s0;
    for _ in 0..3 {
        s = rk4_step(&body, &s, 0.25 / 3.0);
    }
    assert!((sol.omega[1] - s.omega).norm() < 1e-15);
    assert!(sol.orientation.as_ref().unwrap()[1].angle_to(&s.orientation) < 1e-15);
    // A segment of round-off length between a torque switch and an output time.
    let kick = Window::new(BodyFixed::new(Vector3::x()).unwrap(), 1.0, 2.0).unwrap();
    let options = Options {
        torque: Some(&kick),
        ..Options::default()
    };
    let just_after = 1.0 + 4.0 * f64::EPSILON;
    for method in [
        Method::Dop853(Dop853Options::default()),
        Method::Rk4 { dt: 0.1 },
    ] {
        let sol = run(method, moments, &s0, &[just_after, 1.5], &options);
        assert!((sol.omega[0] - sol.omega[1]).norm() > 0.1);
    }
    // Output spacing a whole number of dt up to round-off gets no extra step.
    let times: Vec<f64> = (1..=1000).map(|k| k as f64 * 0.1).collect();
    let sol = run(
        Method::Splitting {
            dt: 0.01,
            order: SplittingOrder::Two,
        },
        moments,
        &s0,
        &times,
        &Options::default(),
    );
    assert_eq!(sol.stats.steps, 10_000);
}

#[test]
fn omega_only_and_with_orientation_agree() {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let s0 = State::new(
        Vector3::new(0.3, 1.2, 0.1),
        UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
    );
    let times = [1.0, 5.0];
    let mut methods = fixed_methods(0.01);
    methods.push(("dop853", Method::Dop853(Dop853Options::with_rtol(1e-12))));
    for (name, method) in methods {
        let a = run(
            method,
            moments,
            &s0,
            &times,
            &Options {
                with_orientation: false,
                ..Options::default()
            },
        );
        let b = run(method, moments, &s0, &times, &Options::default());
        assert!(a.orientation.is_none());
        // DOP853 controls the error of the quaternion too, so its steps differ.
        let bound = if name == "dop853" { 1e-10 } else { 1e-13 };
        for k in 0..2 {
            let e = (a.omega[k] - b.omega[k]).norm() / s0.omega.norm();
            assert!(e < bound, "{name}: {e:e}");
        }
    }
}

/// Scaling the moments by `a` and the angular velocity by `b` maps w(t) to b w(b t): every
/// method must give the same relative errors (no absolute threshold anywhere).
#[test]
fn results_are_invariant_under_scaling_of_moments_and_angular_velocity() {
    let base = Vector3::from(KROGH_MOMENTS);
    let s0 = krogh_state0();
    for (a, b) in [(1e12, 1e-12), (1e-12, 1e12), (1e-12, 1e-12), (1e12, 1e12)] {
        let scaled = State::new(s0.omega * b, s0.orientation);
        for (name, method) in fixed_methods(0.01)
            .into_iter()
            .chain([("dop853", Method::Dop853(Dop853Options::with_rtol(1e-10)))])
        {
            let scaled_method = match method {
                Method::Splitting { dt, order } => Method::Splitting { dt: dt / b, order },
                Method::Midpoint { dt } => Method::Midpoint { dt: dt / b },
                Method::Rk4 { dt } => Method::Rk4 { dt: dt / b },
                other => other,
            };
            let ref_sol = run(method, base, &s0, &[5.0], &Options::default());
            let sol = run(
                scaled_method,
                base * a,
                &scaled,
                &[5.0 / b],
                &Options::default(),
            );
            let e = (sol.omega[0] / b - ref_sol.omega[0]).norm() / s0.omega.norm();
            assert!(e < 1e-9, "{name} a={a:e} b={b:e}: {e:e}");
            let eq = sol.orientation.unwrap()[0].angle_to(&ref_sol.orientation.unwrap()[0]);
            assert!(eq < 1e-9, "{name} a={a:e} b={b:e}: orientation {eq:e}");
        }
    }
}

/// Time per step of each method; run with
/// `cargo test --release -p polhode --test dynamics -- --ignored --nocapture step_timings`.
#[test]
#[ignore = "timing report, not a check"]
fn step_timings() {
    use std::time::Instant;
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let s0 = State::new(
        Vector3::new(0.3, 1.2, 0.1),
        UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3),
    );
    let n = 200_000;
    let times = [n as f64 * 1e-3];
    let mut methods = fixed_methods(1e-3);
    methods.push((
        "dop853 rtol=1e-10",
        Method::Dop853(Dop853Options::with_rtol(1e-10)),
    ));
    for (name, method) in methods {
        for with_orientation in [false, true] {
            let options = Options {
                with_orientation,
                ..Options::default()
            };
            // The best of 7 runs, against the noise of a shared machine.
            let (mut ns, mut sol) = (f64::INFINITY, None);
            for _ in 0..7 {
                let start = Instant::now();
                let s = run(method, moments, &s0, &times, &options);
                ns = ns.min(start.elapsed().as_nanos() as f64 / s.stats.steps as f64);
                sol = Some(s);
            }
            let sol = sol.unwrap();
            println!(
                "{name:>18} orientation={with_orientation:<5}: {ns:7.1} ns/step ({:?})",
                sol.stats
            );
        }
    }
}

/// A damping torque proportional to the angular momentum, tau = -k I w, keeps the free motion
/// on a slowed clock: w(t) = exp(-k t) w_free(s), s = (1 - exp(-k t)) / k (the free field is
/// quadratic). With k = 0.1 and t = 10 ln 2, s = 5: w = krogh(5) / 2.
#[test]
fn omega_dependent_damping_matches_the_reparametrised_free_motion() {
    let moments = Vector3::from(KROGH_MOMENTS);
    let k = 0.1;
    let damping = Function::with_dependencies(
        move |_: f64, w: &Vector3<f64>, _: &UnitQuaternion<f64>| Ok(-k * moments.component_mul(w)),
        false,
        true,
    );
    let t = 10.0 * 2f64.ln();
    let exact = krogh_exact(3) * 0.5;
    let scale = exact.norm();
    let mut methods = fixed_methods(1e-2);
    methods.push(("dop853", Method::Dop853(Dop853Options::with_rtol(1e-12))));
    let bounds = [1e-5, 1e-9, 1e-13, 1e-5, 1e-10, 1e-12];
    for ((name, method), bound) in methods.into_iter().zip(bounds) {
        for with_orientation in [false, true] {
            let options = Options {
                torque: Some(&damping),
                with_orientation,
                ..Options::default()
            };
            let sol = run(method, moments, &krogh_state0(), &[t], &options);
            let err = (sol.omega[0] - exact).norm() / scale;
            assert!(
                err < bound,
                "{name} orientation={with_orientation}: {err:e}"
            );
        }
    }
    // The implicit kicks keep the splitting symmetric: orders 2 and 4 with this torque too.
    let options = Options {
        torque: Some(&damping),
        with_orientation: false,
        ..Options::default()
    };
    for (order, p) in [(SplittingOrder::Two, 2.0), (SplittingOrder::Four, 4.0)] {
        let err = |dt: f64| {
            let sol = run(
                Method::Splitting { dt, order },
                moments,
                &krogh_state0(),
                &[t],
                &options,
            );
            (sol.omega[0] - exact).norm()
        };
        let q = observed_order(err, 0.05);
        assert!((q - p).abs() < 0.15, "{order:?}: observed order {q}");
    }
    let err = |dt: f64| {
        (run(
            Method::Midpoint { dt },
            moments,
            &krogh_state0(),
            &[t],
            &options,
        )
        .omega[0]
            - exact)
            .norm()
    };
    let q = observed_order(err, 0.05);
    assert!((q - 2.0).abs() < 0.1, "midpoint: observed order {q}");
}

// ---------------------------------------------------------------------------------------------
// Torques that switch on and off: I = (0.5, 2, 3), w0 = (1, 0, 0.9), identity orientation, a torque
// about body axis 3 active on [3 pi, 4 pi): the constant 0.25 (a jump) and 0.25 sin^2 t (C^1).
// Reference: mpmath.odefun at 30 digits, on (w, q), q = (x, y, z, w), q' = q (x) (0, w) / 2,
// restarted at the window ends:
// `f1 = mp.odefun(free, 0, y0); f2 = mp.odefun(forced, 3*mp.pi, f1(3*mp.pi));
//  f3 = mp.odefun(free, 4*mp.pi, f2(4*mp.pi))`, each printed with 22 digits.
// ---------------------------------------------------------------------------------------------

const SWITCHED_TIMES: [f64; 5] = [5.0, 10.0, 12.0, 15.0, 20.0];

/// `(w, q)` at `SWITCHED_TIMES` under the constant torque 0.25 e3 on [3 pi, 4 pi).
const JUMP_REFERENCE: [[f64; 7]; 5] = [
    [
        0.9716899970677550153147,
        0.1867795317989672177968,
        0.8922137426650541329158,
        0.05503367325974799465456,
        0.03971006463660734344367,
        0.6017034128538884471864,
        -0.7958312688843526688591,
    ],
    [
        0.8801979427739728202391,
        0.3752095927082505878487,
        0.9173107648452702163098,
        -0.1299133310059963002301,
        -0.1234081456632575832479,
        -0.9442189220642962742089,
        0.276303426013180367562,
    ],
    [
        -0.9338506560165494984605,
        -0.2827575731274276409766,
        1.087829211799488011199,
        -0.08973645456209428418398,
        0.1578508687678329450479,
        -0.185324217906994885623,
        0.9657563907161195926928,
    ],
    [
        -0.6850778787721690402233,
        0.5759059710670143657063,
        1.087626709028963365638,
        0.01685463118246020848699,
        0.1714804535968037945606,
        0.9821975766824226505132,
        -0.07482176021127903004283,
    ],
    [
        -0.03353085567853023298845,
        -0.7901248642293292528669,
        1.032414651565960323949,
        -0.06639294220175979633445,
        0.2189199065507535128362,
        -0.9724663348576825836596,
        -0.04444411445927007955042,
    ],
];

/// `(w, q)` at `SWITCHED_TIMES` under the torque 0.25 sin^2(t) e3 on [3 pi, 4 pi).
const SIN2_REFERENCE: [[f64; 7]; 5] = [
    [
        0.9716899970677550153147,
        0.1867795317989672177968,
        0.8922137426650541329158,
        0.05503367325974799465456,
        0.03971006463660734344367,
        0.6017034128538884471864,
        -0.7958312688843526688591,
    ],
    [
        0.8896590342181640462611,
        0.3609941159787126767976,
        0.8756003877860809300172,
        -0.1315792051232167315119,
        -0.1253418721314345628611,
        -0.9454646645689044382372,
        0.2703199880166810382006,
    ],
    [
        -0.9941191227758905890583,
        -0.08561238860152546970508,
        1.012724463713526532156,
        -0.02652590872697701158474,
        0.1523263371740542088637,
        -0.2532173425698220674151,
        0.954973319308566762988,
    ],
    [
        0.0890302911633593696832,
        0.7874299997679823343211,
        0.8888141820835497234592,
        0.1200125734285594438048,
        0.2720371118722853170499,
        0.9429620577204471221551,
        0.1497175663803700113342,
    ],
    [
        -0.9011799837228600526072,
        0.3426684229481774946707,
        0.9955101169010664168852,
        -0.05524560929411468344785,
        -0.1728073965071584748773,
        -0.8370699473676756985293,
        -0.5161389634391269032663,
    ],
];

/// Largest error in `w` (relative to |w0|) and in the orientation (radians) over the outputs.
fn switched_error(sol: &Trajectory, reference: &[[f64; 7]; 5]) -> f64 {
    let scale = Vector3::new(1.0, 0.0, 0.9).norm();
    let mut err = 0.0f64;
    for (k, r) in reference.iter().enumerate() {
        err = err.max((sol.omega[k] - Vector3::new(r[0], r[1], r[2])).norm() / scale);
        if let Some(att) = &sol.orientation {
            let q =
                UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(r[6], r[3], r[4], r[5]));
            err = err.max(att[k].angle_to(&q));
        }
    }
    err
}

type BoxedTorque = Box<dyn Torque + Send>;

/// The constant torque and the sin^2 torque as `Window` torques, and the constant torque as a
/// closure that switches itself, with the switches declared.
fn switched_torques() -> Vec<(&'static str, BoxedTorque, &'static [[f64; 7]; 5])> {
    let (start, end) = (3.0 * PI, 4.0 * PI);
    let constant = BodyFixed::new(Vector3::new(0.0, 0.0, 0.25)).unwrap();
    let sin2 = Function::with_dependencies(
        |t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            Ok(Vector3::new(0.0, 0.0, 0.25 * t.sin().powi(2)))
        },
        false,
        false,
    );
    let closure = Function::with_dependencies(
        move |t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            let on = start <= t && t < end;
            Ok(Vector3::new(0.0, 0.0, if on { 0.25 } else { 0.0 }))
        },
        false,
        false,
    )
    .with_discontinuities(vec![start, end]);
    vec![
        (
            "windowed constant",
            Box::new(Window::new(constant, start, end).unwrap()),
            &JUMP_REFERENCE,
        ),
        (
            "windowed sin^2",
            Box::new(Window::new(sin2, start, end).unwrap()),
            &SIN2_REFERENCE,
        ),
        ("switching closure", Box::new(closure), &JUMP_REFERENCE),
    ]
}

/// Steps end at both switches; within a step the torque stays in the state it has on the step's
/// segment (a step ending where the window opens is off throughout, and the stages of the
/// order-4 and order-6 splittings that reach past a switch see the torque of their own
/// segment). Before, the splittings converged at orders 0.4, 1.0 and 5.1 (2, 4, 6) and RK4 at
/// 1.0 with the constant torque, order 6 at 4.9 with sin^2, and DOP853 rejected 28 steps.
#[test]
fn switched_torques_keep_the_order_of_every_method() {
    let moments = Vector3::new(0.5, 2.0, 3.0);
    let s0 = State::from_omega(Vector3::new(1.0, 0.0, 0.9));
    // (method, order, dt): errors well above round-off at dt / 2.
    let fixed = [
        ("splitting2", 2, 0.01),
        ("splitting4", 4, 0.02),
        ("splitting6", 6, 0.04),
        ("midpoint", 2, 0.01),
        ("rk4", 4, 0.02),
    ];
    for (label, torque, reference) in switched_torques() {
        for with_orientation in [false, true] {
            let options = Options {
                torque: Some(&*torque),
                with_orientation,
                ..Options::default()
            };
            for (name, p, dt) in fixed {
                let err = |dt: f64| {
                    let (_, method) = fixed_methods(dt).into_iter().find(|m| m.0 == name).unwrap();
                    let sol = run(method, moments, &s0, &SWITCHED_TIMES, &options);
                    switched_error(&sol, reference)
                };
                let (e1, e2) = (err(dt), err(dt / 2.0));
                let observed = (e1 / e2).log2();
                // A priori: (|w| dt)^p (|w| t), |w| <= 1.5.
                let bound = (1.5 * dt).powi(p) * 30.0;
                assert!(
                    (observed - f64::from(p)).abs() <= 0.25 && e1 <= bound,
                    "{label}, {name}, orientation {with_orientation}: errors {e1:.2e}, {e2:.2e}, \
                     observed order {observed:.2} (expected {p}), bound {bound:.1e}"
                );
            }
            let sol = run(
                Method::Dop853(Dop853Options::with_rtol(1e-12)),
                moments,
                &s0,
                &SWITCHED_TIMES,
                &options,
            );
            let err = switched_error(&sol, reference);
            assert!(
                err <= 1e-11 && sol.stats.rejected_steps <= 2,
                "{label}, dop853, orientation {with_orientation}: error {err:.2e}, {:?}",
                sol.stats
            );
        }
    }
}

/// The times a torque is asked for by every method, for steps ending exactly at a switch.
#[test]
fn a_step_ending_at_a_switch_never_sees_the_next_piece() {
    use std::sync::Mutex;
    let moments = Vector3::new(0.5, 2.0, 3.0);
    let s0 = State::from_omega(Vector3::new(1.0, 0.0, 0.9));
    let switch = 3.0 * PI;
    // Off before the switch, on from it: the closure fails if asked about the other piece.
    let asked = Mutex::new(Vec::new());
    let closure = Function::with_dependencies(
        |t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
            asked.lock().unwrap().push(t);
            Ok(Vector3::new(0.0, 0.0, if t >= switch { 0.25 } else { 0.0 }))
        },
        false,
        true,
    )
    .with_discontinuities(vec![switch]);
    let windowed = Window::new(
        Function::with_dependencies(
            |t: f64, _: &Vector3<f64>, _: &UnitQuaternion<f64>| {
                asked.lock().unwrap().push(t);
                Ok(Vector3::new(0.0, 0.0, 0.25))
            },
            false,
            true,
        ),
        switch,
        f64::INFINITY,
    )
    .unwrap();
    let mut methods = fixed_methods(0.1);
    methods.push(("dop853", Method::Dop853(Dop853Options::default())));
    for (name, method) in methods {
        // Up to the switch: the closure is asked only about times before it; the windowed
        // torque is never asked (its inner torque is evaluated only on).
        let options = Options {
            torque: Some(&closure),
            ..Options::default()
        };
        asked.lock().unwrap().clear();
        run(method, moments, &s0, &[switch], &options);
        let times = asked.lock().unwrap().clone();
        assert!(
            !times.is_empty() && times.iter().all(|&t| t < switch),
            "{name}: closure asked at {:?}",
            times.iter().filter(|&&t| t >= switch).collect::<Vec<_>>()
        );
        let options = Options {
            torque: Some(&windowed),
            ..Options::default()
        };
        asked.lock().unwrap().clear();
        run(method, moments, &s0, &[switch], &options);
        assert!(
            asked.lock().unwrap().is_empty(),
            "{name}: windowed torque on"
        );
        // From the switch on: only times at or after it.
        let options = Options {
            torque: Some(&closure),
            t0: switch,
            ..Options::default()
        };
        asked.lock().unwrap().clear();
        run(method, moments, &s0, &[switch + 1.0], &options);
        let times = asked.lock().unwrap().clone();
        // The orders 4 and 6 of the splitting reach back before the switch: moved inside.
        assert!(times.iter().all(|&t| t > switch), "{name}: {times:?}");
    }
    // The single-step functions take the step as the segment.
    let body = Moments::new(moments).unwrap();
    let h = 0.5;
    let t = switch - h;
    let w = s0.omega;
    asked.lock().unwrap().clear();
    rk4_step_omega_torqued(&body, &closure, t, &w, h).unwrap();
    dop853_step_omega_torqued(&body, &closure, t, &w, h).unwrap();
    midpoint_step_omega_torqued(&body, &closure, t, &w, h).unwrap();
    for order in [
        SplittingOrder::Two,
        SplittingOrder::Four,
        SplittingOrder::Six,
    ] {
        splitting_step_omega_torqued(&body, &closure, t, &w, h, order).unwrap();
    }
    assert!(asked.lock().unwrap().iter().all(|&x| x < switch));
}

/// Without the orientation, |L| = |m| is restored to its initial value (an exact invariant of the
/// method's rotations) and the rotations are unbiased: before, near the steady rotation about
/// the largest axis, |L| shrank by 1.3e-12, 4.2e-12, 2.2e-11 over 1e6 steps (orders 2, 4, 6)
/// and T drifted with it (order 2: 3e-13 over the first tenth, 2.6e-12 over the last).
#[test]
fn splitting_omega_only_keeps_the_norm_of_the_angular_momentum() {
    let moments = Vector3::new(1.0, 0.75, 0.25);
    let body = Moments::new(moments).unwrap();
    let dt = 0.01;
    let times: Vec<f64> = (0..=10_000)
        .map(|k| k as f64 * (LONG as f64 * dt / 1e4))
        .collect();
    for w0 in [Vector3::new(1.0, 0.01, 0.01), Vector3::new(1.0, 0.1, 0.2)] {
        let g0 = body.angular_momentum(&w0).norm();
        let t0 = body.kinetic_energy(&w0);
        for order in [
            SplittingOrder::Two,
            SplittingOrder::Four,
            SplittingOrder::Six,
        ] {
            let options = Options {
                with_orientation: false,
                ..Options::default()
            };
            let method = Method::Splitting { dt, order };
            let sol = run(method, moments, &State::from_omega(w0), &times, &options);
            assert_eq!(sol.stats.steps, LONG as u64);
            let dg = sol
                .omega
                .iter()
                .map(|w| rel(body.angular_momentum(w).norm(), g0))
                .fold(0.0, f64::max);
            let de: Vec<f64> = sol
                .omega
                .iter()
                .map(|w| rel(body.kinetic_energy(w), t0))
                .collect();
            let k = de.len() / 10;
            let first = de[..k].iter().copied().fold(0.0, f64::max);
            let last = de[de.len() - k..].iter().copied().fold(0.0, f64::max);
            // The round-off of ~5 rotations a Strang stage, as a random walk.
            let stages = [1.0, 3.0, 7.0][order.order() as usize / 2 - 1];
            let walk = f64::EPSILON * (5.0 * stages * LONG as f64).sqrt();
            assert!(
                dg <= 1e-13 && last <= 2.0 * first + walk,
                "{w0:?} {order:?}: |L| {dg:.2e}; T first tenth {first:.2e}, last {last:.2e}"
            );
            // The single-step function (nothing restored), near the steady rotation where the
            // angles repeat: a random walk, with the 6 roundings of m = I w and back a step.
            if w0[1] == 0.01 {
                let mut w = w0;
                for _ in 0..LONG {
                    w = splitting_step_omega(&body, &w, dt, order);
                }
                let e = rel(body.angular_momentum(&w).norm(), g0);
                let walk = f64::EPSILON * ((5.0 * stages + 6.0) * LONG as f64).sqrt();
                assert!(
                    e <= walk,
                    "{w0:?} {order:?}: single steps, |L| {e:.2e} > {walk:.1e}"
                );
            }
        }
    }
}

/// A monitor changes no result, records the time integrated and the runs finished, and a
/// cancelled one stops every method (and a batch) with `Error::Interrupted`, also mid-run.
#[test]
fn monitor_progress_and_cancel() {
    let moments = Vector3::new(2.0, 3.0, 4.0);
    let state0 = State::from_omega(Vector3::new(0.1, 1.0, 0.1));
    let times = [0.5, 20.0, 40.0];
    let torque = BodyFixed::new(Vector3::new(0.0, 0.0, 1e-3)).unwrap();
    let mut methods = fixed_methods(1e-3);
    methods.push(("dop853", Method::Dop853(Dop853Options::with_rtol(1e-12))));
    for (name, method) in &methods {
        for torque in [None, Some(&torque as &dyn Torque)] {
            let options = Options {
                torque,
                ..Options::default()
            };
            let plain = run(*method, moments, &state0, &times, &options);
            let monitor = Monitor::new();
            let watched = Options {
                monitor: Some(&monitor),
                ..options
            };
            let sol = run(*method, moments, &state0, &times, &watched);
            assert_eq!(sol, plain, "{name}");
            assert!((monitor.elapsed() - 40.0).abs() <= 1e-9, "{name}");
            assert_eq!(monitor.finished(), 1, "{name}");
            monitor.cancel();
            let result = integrate(method, &moments, &state0, &times, &watched);
            assert_eq!(result.unwrap_err(), Error::Interrupted, "{name}");
        }
    }
    // Cancelled from another thread while running (1e10 steps unless stopped), for a fixed
    // step and the adaptive method.
    for method in [
        Method::Rk4 { dt: 1e-6 },
        Method::Dop853(Dop853Options {
            max_step: Some(1e-6),
            ..Dop853Options::default()
        }),
    ] {
        let monitor = Monitor::new();
        let options = Options {
            monitor: Some(&monitor),
            max_steps: u64::MAX,
            ..Options::default()
        };
        let result = std::thread::scope(|scope| {
            let running = scope.spawn(|| integrate(&method, &moments, &state0, &[1e4], &options));
            while monitor.elapsed() == 0.0 {
                std::thread::yield_now();
            }
            monitor.cancel();
            running.join().unwrap()
        });
        assert_eq!(result.unwrap_err(), Error::Interrupted, "{method:?}");
        assert!(monitor.elapsed() > 0.0 && monitor.elapsed() < 1e4);
        assert_eq!(monitor.finished(), 0);
    }
    // A function called at each look (every CHECK_EVERY steps) may cancel: here at the third.
    let looks = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let monitor = Monitor::with_on_look({
        let looks = std::sync::Arc::clone(&looks);
        move |monitor| {
            if looks.fetch_add(1, std::sync::atomic::Ordering::Relaxed) == 2 {
                monitor.cancel();
            }
        }
    });
    let options = Options {
        monitor: Some(&monitor),
        ..Options::default()
    };
    let dt = 1e-3;
    let result = integrate(&Method::Rk4 { dt }, &moments, &state0, &[1e4], &options);
    assert_eq!(result.unwrap_err(), Error::Interrupted);
    assert_eq!(looks.load(std::sync::atomic::Ordering::Relaxed), 3);
    let looked = 3.0 * f64::from(Monitor::CHECK_EVERY) * dt;
    assert!((monitor.elapsed() - looked).abs() <= 1e-9 * looked);
}

/// `Method::Exact` is the closed form at each output time, bit for bit, from `t0`.
#[test]
fn exact_method_is_the_closed_form_at_the_output_times() {
    // A unit quaternion whose norm is exactly 1, so that the driver's renormalisation of the
    // initial state changes no bit.
    let q0 = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(0.5, 0.5, -0.5, 0.5));
    assert_eq!(q0.coords.norm(), 1.0);
    let bodies = [
        // Asymmetric, about the largest axis; near the separatrix; symmetric; a steady spin.
        (Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.1, 0.2, 1.0)),
        (Vector3::new(3.0, 5.0, 9.0), Vector3::new(1e-3, 0.4, 1e-3)),
        (Vector3::new(2.0, 2.0, 1.0), Vector3::new(0.3, -0.2, 1.5)),
        (Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.0, 0.7, 0.0)),
    ];
    let t0 = 1.25;
    // Repeated times, t0 itself, and more than 256 of them (the monitor's looks).
    let mut times: Vec<f64> = [1.25, 1.25, 1.5, 2.0, 10.0, 10.0, 123.4, 1e4]
        .into_iter()
        .chain((0..1000).map(|k| 2.0 + 0.37 * f64::from(k)))
        .collect();
    times.sort_by(f64::total_cmp);
    for (moments, omega0) in bodies {
        let free = polhode::exact::FreeRotation::new(moments, omega0, q0).unwrap();
        let state0 = State::new(omega0, q0);
        for with_orientation in [true, false] {
            let options = Options {
                t0,
                with_orientation,
                ..Options::default()
            };
            let sol = run(Method::Exact, moments, &state0, &times, &options);
            assert_eq!(
                sol.stats,
                Stats {
                    steps: 0,
                    rejected_steps: 0,
                    rhs_evaluations: times.len() as u64,
                }
            );
            assert_eq!(sol.omega.len(), times.len());
            for (k, &t) in times.iter().enumerate() {
                if with_orientation {
                    let (w, q) = free.state(t - t0);
                    assert_eq!(sol.omega[k], w, "{moments:?} t = {t}");
                    assert_eq!(
                        sol.orientation.as_ref().unwrap()[k],
                        q,
                        "{moments:?} t = {t}"
                    );
                } else {
                    assert_eq!(sol.omega[k], free.omega(t - t0), "{moments:?} t = {t}");
                }
            }
            assert_eq!(sol.orientation.is_some(), with_orientation);
        }
    }
}

/// `Method::Exact` is torque-free: a torque is an invalid argument, not silently ignored.
#[test]
fn exact_method_rejects_a_torque() {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let state0 = State::from_omega(Vector3::new(0.1, 1.0, 0.1));
    let torque = BodyFixed::new(Vector3::new(0.0, 0.0, 1e-3)).unwrap();
    for with_orientation in [true, false] {
        let options = Options {
            torque: Some(&torque),
            with_orientation,
            ..Options::default()
        };
        match integrate(&Method::Exact, &moments, &state0, &[1.0], &options).unwrap_err() {
            Error::InvalidArgument { name, reason } => {
                assert_eq!(name, "torque");
                assert!(reason.contains("torque-free"), "{reason}");
            }
            other => panic!("unexpected {other}"),
        }
    }
    // The other arguments are checked as for the integrators.
    let options = Options::default();
    let error = integrate(&Method::Exact, &moments, &state0, &[1.0, 0.5], &options).unwrap_err();
    assert!(matches!(error, Error::InvalidArgument { name, .. } if name == "t"));
}

/// `Method::Exact` reports to the monitor as the integrators do: a look every 256 output
/// times (where a cancelled monitor stops it), its span once finished.
#[test]
fn exact_method_reports_to_the_monitor() {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let state0 = State::from_omega(Vector3::new(0.1, 1.0, 0.1));
    let t0 = 0.5;
    let times: Vec<f64> = (1..=1000).map(|k| t0 + f64::from(k)).collect();
    let looks = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let monitor = Monitor::with_on_look({
        let looks = std::sync::Arc::clone(&looks);
        move |_| {
            looks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
    });
    let options = Options {
        t0,
        monitor: Some(&monitor),
        ..Options::default()
    };
    let sol = run(Method::Exact, moments, &state0, &times, &options);
    let plain = Options {
        t0,
        ..Options::default()
    };
    assert_eq!(sol, run(Method::Exact, moments, &state0, &times, &plain));
    // Looks at the outputs 256, 512 and 768 (times t0 + 256, ...), then the whole span.
    assert_eq!(looks.load(std::sync::atomic::Ordering::Relaxed), 3);
    assert_eq!(monitor.elapsed(), 1000.0);
    assert_eq!(monitor.finished(), 1);
    // Cancelled before the run: stops at once.
    monitor.cancel();
    let result = integrate(&Method::Exact, &moments, &state0, &times, &options);
    assert_eq!(result.unwrap_err(), Error::Interrupted);
    assert_eq!(monitor.finished(), 1);
    // Cancelled by the function called at the second look: stops there, the time up to it
    // reported.
    let looks = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let monitor = Monitor::with_on_look({
        let looks = std::sync::Arc::clone(&looks);
        move |monitor| {
            if looks.fetch_add(1, std::sync::atomic::Ordering::Relaxed) == 1 {
                monitor.cancel();
            }
        }
    });
    let options = Options {
        t0,
        monitor: Some(&monitor),
        ..Options::default()
    };
    let result = integrate(&Method::Exact, &moments, &state0, &times, &options);
    assert_eq!(result.unwrap_err(), Error::Interrupted);
    assert_eq!(looks.load(std::sync::atomic::Ordering::Relaxed), 2);
    assert_eq!(monitor.elapsed(), 512.0);
    assert_eq!(monitor.finished(), 0);
}
