//! The Dormand-Prince 8(5,3) method with step-size control and 7th-order dense output
//! (Hairer, Norsett & Wanner, *Solving ODEs I*, II.5 and II.10; Hairer's `dop853.f`, whose
//! coefficients, error estimator, controller and `contd8` are reproduced here).
//!
//! Error control: with `sc_i = atol_i + rtol max(|y_i|, |y'_i|)`, the step is accepted when
//! `err = |h| ||e5/sc||^2 / sqrt(n (||e5/sc||^2 + 0.01 ||e3/sc||^2)) <= 1` (RMS norms over the
//! `n` components); the next step is `h / max(1/6, min(3, err^(1/8) / 0.9))`, not growing right
//! after a rejection.

use nalgebra::{SVector, Vector3};

use super::method::Stats;
use super::state::{Moments, State};
use super::system::{pack, unit_state, Field, NoTorque, System};
use super::torque::{require_orientation_free, Segment, Torque};
use crate::{Error, Result, Short};

/// Per-component tolerances, `sc_i = atol_i + rtol_i max(|y_i|, |y'_i|)`.
pub(crate) struct Tolerance<const N: usize> {
    pub atol: SVector<f64, N>,
    pub rtol: SVector<f64, N>,
}

/// `e / sc` with `0 / 0 = 0`.
#[inline]
fn ratio(e: f64, sc: f64) -> f64 {
    if sc > 0.0 {
        e / sc
    } else if e == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// The stages `k_0 .. k_11` (k_0 given) and the 8th-order solution, for a step in `segment`.
#[inline]
fn stages<S: System<N>, const N: usize>(
    sys: &S,
    segment: &Segment,
    t: f64,
    y: &SVector<f64, N>,
    h: f64,
    k: &mut [SVector<f64, N>; 16],
    evals: &mut u64,
) -> Result<SVector<f64, N>> {
    for s in 1..12 {
        let mut acc = SVector::<f64, N>::zeros();
        for (j, &a) in A[s].iter().enumerate() {
            if a != 0.0 {
                acc += k[j] * a;
            }
        }
        k[s] = sys.rhs(segment, t + C[s] * h, &(y + acc * h))?;
        *evals += 1;
    }
    let mut acc = SVector::<f64, N>::zeros();
    for (j, &b) in A[12].iter().enumerate() {
        if b != 0.0 {
            acc += k[j] * b;
        }
    }
    Ok(y + acc * h)
}

/// Hairer's error measure of a step (`<= 1`: accept).
fn error_norm<const N: usize>(
    k: &[SVector<f64, N>; 16],
    y: &SVector<f64, N>,
    y_new: &SVector<f64, N>,
    h: f64,
    tol: &Tolerance<N>,
) -> f64 {
    let mut e5 = SVector::<f64, N>::zeros();
    let mut e3 = SVector::<f64, N>::zeros();
    for j in 0..12 {
        if E5[j] != 0.0 {
            e5 += k[j] * E5[j];
        }
        if E3[j] != 0.0 {
            e3 += k[j] * E3[j];
        }
    }
    let sc = |i: usize| tol.atol[i] + tol.rtol[i] * y[i].abs().max(y_new[i].abs());
    // Hairer's measure as it is where its squares are safe (ratios between 2^-500 and 2^500,
    // nearly always); otherwise scaled (see `scaled_error_norm`).
    let (mut err5, mut err3) = (0.0, 0.0);
    for i in 0..N {
        let s = sc(i);
        let (r5, r3) = (ratio(e5[i], s), ratio(e3[i], s));
        err5 += r5 * r5;
        err3 += r3 * r3;
    }
    // Squares that under- or overflowed (sums outside [2^-1000, 2^1000], or 0 from errors
    // that are not) need the scaling; nearly always they did not.
    let total = err5 + err3;
    const SAFE: f64 = 9.332636185032189e-302; // 2^-1000
    let overflowed = total.is_nan() || total > 1.0 / SAFE;
    if overflowed || (total < SAFE && (total != 0.0 || e5.amax() + e3.amax() != 0.0)) {
        return scaled_error_norm(&e5, &e3, h, &sc);
    }
    if total == 0.0 {
        return 0.0;
    }
    let mut deno = err5 + 0.01 * err3;
    if deno <= 0.0 {
        deno = 1.0;
    }
    h.abs() * err5 / (deno * N as f64).sqrt()
}

/// [`error_norm`] where its squares would under- or overflow. The measure is homogeneous of
/// degree 1 in (e5, e3): they are scaled by a power of two to a largest of about 1 before
/// they are divided by the tolerances, the ratios again before they are squared, and the
/// measure scaled back by both. Squared as they were, the ratios of a slow motion (rates of
/// 1e-180 against tolerances of 1e-10 over steps of 1e180) underflowed to 0 and every step
/// was accepted however large; those of a fast one (rates of 1e300 over steps of 1e-302)
/// overflowed and every step was refused.
#[cold]
fn scaled_error_norm<const N: usize>(
    e5: &SVector<f64, N>,
    e3: &SVector<f64, N>,
    h: f64,
    sc: &impl Fn(usize) -> f64,
) -> f64 {
    let binary = |x: f64| {
        if x.is_finite() {
            crate::eigen::exponent(x)
        } else {
            0
        }
    };
    let ke = binary(e5.amax().max(e3.amax()));
    let mut r5 = [0.0; N];
    let mut r3 = [0.0; N];
    let mut largest = 0.0_f64;
    for i in 0..N {
        let s = sc(i);
        r5[i] = ratio(crate::eigen::ldexp(e5[i], -ke), s);
        r3[i] = ratio(crate::eigen::ldexp(e3[i], -ke), s);
        largest = largest.max(r5[i].abs()).max(r3[i].abs());
    }
    let k = binary(largest);
    let (mut err5, mut err3) = (0.0, 0.0);
    for i in 0..N {
        err5 += crate::eigen::ldexp(r5[i], -k).powi(2);
        err3 += crate::eigen::ldexp(r3[i], -k).powi(2);
    }
    if err5 == 0.0 && err3 == 0.0 {
        return 0.0;
    }
    let mut deno = err5 + 0.01 * err3;
    if deno <= 0.0 {
        deno = 1.0;
    }
    crate::eigen::ldexp(h.abs() * err5 / (deno * N as f64).sqrt(), k + ke)
}

/// The 7th-order dense output on `[t, t + h]` (`contd8`).
struct Dense<const N: usize> {
    /// The step's start, as a time since the solve's start.
    tau: f64,
    h: f64,
    y: SVector<f64, N>,
    f: [SVector<f64, N>; 7],
}

impl<const N: usize> Dense<N> {
    /// Needs `k_0 .. k_12` (`k_12 = f(t + h, y_new)`); computes `k_13 .. k_15`. The step starts
    /// at time `t`, which [`Dense::eval`] measures as `tau` (the time since the solve's start).
    #[allow(clippy::too_many_arguments)]
    fn new<S: System<N>>(
        sys: &S,
        segment: &Segment,
        t: f64,
        tau: f64,
        y: &SVector<f64, N>,
        y_new: &SVector<f64, N>,
        h: f64,
        k: &mut [SVector<f64, N>; 16],
        evals: &mut u64,
    ) -> Result<Self> {
        for s in 13..16 {
            let mut acc = SVector::<f64, N>::zeros();
            for (j, &a) in A[s].iter().enumerate() {
                if a != 0.0 {
                    acc += k[j] * a;
                }
            }
            k[s] = sys.rhs(segment, t + C[s] * h, &(y + acc * h))?;
            *evals += 1;
        }
        let dy = y_new - y;
        let mut f = [SVector::<f64, N>::zeros(); 7];
        f[0] = dy;
        f[1] = k[0] * h - dy;
        f[2] = dy * 2.0 - (k[12] + k[0]) * h;
        for (i, row) in D.iter().enumerate() {
            let mut acc = SVector::<f64, N>::zeros();
            for (j, &d) in row.iter().enumerate() {
                if d != 0.0 {
                    acc += k[j] * d;
                }
            }
            f[3 + i] = acc * h;
        }
        Ok(Self { tau, h, y: *y, f })
    }

    /// The state at `tau`, a time since the solve's start.
    fn eval(&self, tau: f64) -> SVector<f64, N> {
        let s = (tau - self.tau) / self.h;
        let s1 = 1.0 - s;
        let f = &self.f;
        self.y
            + (f[0] + (f[1] + (f[2] + (f[3] + (f[4] + (f[5] + f[6] * s) * s1) * s) * s1) * s) * s1)
                * s
    }
}

/// Settings of the adaptive solver.
pub(crate) struct Settings<const N: usize> {
    pub tol: Tolerance<N>,
    pub first_step: Option<f64>,
    pub max_step: Option<f64>,
    pub max_steps: u64,
}

/// The Euclidean norm of `v`, scaled by its largest entry first: no square overflows (rates of
/// 1e300 against tolerances of 1e-10) or underflows.
fn scaled_norm<const N: usize>(v: &[f64; N]) -> f64 {
    let largest = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest * v.iter().map(|x| (x / largest).powi(2)).sum::<f64>().sqrt()
}

/// Hairer's `hinit`, with the absolute fallbacks relative to the span of integration. The norms
/// are taken scaled and the second derivative's size in logarithms, so that a motion whose
/// rates are far beyond its tolerances (omega 1e150 over 1e-160 s, a torque of 1e150) gets a
/// small first step instead of one of zero.
#[allow(clippy::too_many_arguments)]
fn initial_step<S: System<N>, const N: usize>(
    sys: &S,
    segment: &Segment,
    t: f64,
    y: &SVector<f64, N>,
    f0: &SVector<f64, N>,
    tol: &Tolerance<N>,
    hmax: f64,
    span: f64,
    evals: &mut u64,
) -> Result<f64> {
    let sk = |i: usize| tol.atol[i] + tol.rtol[i] * y[i].abs();
    let norm = |v: &SVector<f64, N>| {
        scaled_norm(&std::array::from_fn::<f64, N, _>(|i| ratio(v[i], sk(i))))
    };
    // The logarithm of `norm(v)` where that overflows: rates of 1e300 against tolerances of
    // 1e-10 (a fast motion over a span of 1e-300), whose first step was 0.
    let log_norm = |v: &SVector<f64, N>, direct: f64| {
        if direct.is_finite() {
            return direct.ln();
        }
        let largest = v.amax();
        if !largest.is_finite() {
            return f64::INFINITY;
        }
        let k = crate::eigen::exponent(largest);
        let scaled = v.map(|x| crate::eigen::ldexp(x, -k));
        norm(&scaled).ln() + f64::from(k) * std::f64::consts::LN_2
    };
    let dnf = norm(f0);
    let dny = norm(y);
    let (log_dnf, log_dny) = (log_norm(f0, dnf), log_norm(y, dny));
    let mut h = if dnf <= 1e-5 || dny <= 1e-5 {
        1e-6 * span
    } else if dnf.is_finite() {
        (dny / dnf) * 0.01
    } else {
        (log_dny - log_dnf + 0.01_f64.ln()).exp()
    };
    h = h.min(hmax);
    let f1 = sys.rhs(segment, t + h, &(y + f0 * h))?;
    *evals += 1;
    let difference = f1 - f0;
    let d2 = norm(&difference);
    // log of max(|f1 - f0| / h, |f0|) (scaled by the tolerances): d2 / h may overflow.
    let log_der12 = (log_norm(&difference, d2) - h.ln()).max(log_dnf);
    let h1 = if log_der12 <= 1e-15_f64.ln() {
        (1e-6 * span).max(h * 1e-3)
    } else {
        ((0.01_f64.ln() - log_der12) / 8.0).exp()
    };
    Ok((100.0 * h).min(h1).min(hmax))
}

/// The error of a solve that reached `max_steps` at `t` on its way to `t_end`.
#[cold]
fn too_many_steps(max_steps: u64, t_end: f64, t: f64) -> Error {
    Error::NoConvergence {
        method: "dop853".into(),
        name: "max_steps".into(),
        reason: format!(
            "more than max_steps = {max_steps} steps were needed to reach t = {} (at t = {}).",
            Short(t_end),
            Short(t)
        ),
    }
}

/// Where a solve's state goes to [`solve`]'s `out`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Stamp {
    /// At output time `times[k]`.
    Output(usize),
    /// At the end of an accepted step, at this time (after the output times it covers).
    Step(f64),
}

/// Integrates from `(t0, y0)` to `t_end` and calls `out(Stamp::Output(k), y(times[k]))` for
/// each output time (`times` non-decreasing, within `[t0, t_end]`) and
/// `out(Stamp::Step(t), y(t))` at the end of each accepted step; returns the final state and
/// the next step size. `[t0, t_end]` must be free of discontinuities of the torque: the system is evaluated
/// for the segment `[t0, t_end]`. `renormalize(y, f)` is applied after each accepted step to
/// the new state and its derivative.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve<S: System<N>, const N: usize>(
    sys: &S,
    t0: f64,
    y0: &SVector<f64, N>,
    t_end: f64,
    times: &[f64],
    settings: &Settings<N>,
    renormalize: impl Fn(&mut SVector<f64, N>, &mut SVector<f64, N>),
    mut out: impl FnMut(Stamp, &SVector<f64, N>) -> Result<()>,
    stats: &mut Stats,
) -> Result<(SVector<f64, N>, Option<f64>)> {
    let mut next = 0;
    while next < times.len() && times[next] <= t0 {
        out(Stamp::Output(next), y0)?;
        next += 1;
    }
    if t_end <= t0 {
        return Ok((*y0, settings.first_step));
    }
    let span = t_end - t0;
    let hmax = settings.max_step.unwrap_or(span).min(span);
    // The steps advance the time since t0, `tau`, and the state by the same `h`; the absolute
    // time t0 + tau (for the field and the messages) is rounded to the resolution of t0. Summed
    // as t + h it lost up to half an ulp of t per step: at t0 = 1e10 the motion was 6.6e-8
    // off after two time units, at t0 = 1e14 steps of 0.03 were refused as too small.
    let mut tau = 0.0;
    let mut t = t0;
    let mut y = *y0;
    let segment = Segment::new(t0, t_end);
    let mut k = [SVector::<f64, N>::zeros(); 16];
    k[0] = sys.rhs(&segment, t, &y)?;
    stats.rhs_evaluations += 1;
    let mut h = match settings.first_step {
        Some(h) => h.min(hmax),
        None => initial_step(
            sys,
            &segment,
            t,
            &y,
            &k[0],
            &settings.tol,
            hmax,
            span,
            &mut stats.rhs_evaluations,
        )?,
    };
    let mut rejected = false;
    loop {
        if stats.steps + stats.rejected_steps >= settings.max_steps {
            return Err(too_many_steps(settings.max_steps, t_end, t));
        }
        let h_before_clip = h;
        let last = tau + 1.01 * h >= span;
        if last {
            h = span - tau;
        }
        // The step to the end of the interval is taken whatever its size (an interval between a
        // torque discontinuity and an output time may be round-off small). Written as
        // `h <= 10 tau eps`, not `0.1 h <= tau eps`: a step of 5e-324 (the size carried from a
        // segment that short) times 0.1 is 0, and was refused at tau = 0.
        if h.is_nan() || (!last && h.abs() <= 10.0 * (tau.abs() * f64::EPSILON)) {
            return Err(Error::NoConvergence {
                method: "dop853".into(),
                name: "t".into(),
                reason: format!(
                    "step size {} too small at t = {} (non-finite or stiff solution?).",
                    Short(h),
                    Short(t)
                ),
            });
        }
        let y_new = stages(sys, &segment, t, &y, h, &mut k, &mut stats.rhs_evaluations)?;
        let reached = tau + h;
        k[12] = sys.rhs(&segment, t0 + reached, &y_new)?;
        let (tau_new, t_new) = if last {
            (span, t_end)
        } else {
            (reached, t0 + reached)
        };
        stats.rhs_evaluations += 1;
        let err = error_norm(&k, &y, &y_new, h, &settings.tol);
        if err <= 1.0 {
            stats.steps += 1;
            // Output times as times since t0 (rounded as t0 + tau is).
            let since = |j: usize| times[j] - t0;
            if next < times.len() && since(next) <= tau_new {
                let mut dense = None;
                while next < times.len() && since(next) <= tau_new {
                    if since(next) == tau_new {
                        out(Stamp::Output(next), &y_new)?;
                    } else {
                        if dense.is_none() {
                            dense = Some(Dense::new(
                                sys,
                                &segment,
                                t,
                                tau,
                                &y,
                                &y_new,
                                tau_new - tau,
                                &mut k,
                                &mut stats.rhs_evaluations,
                            )?);
                        }
                        if let Some(d) = &dense {
                            out(Stamp::Output(next), &d.eval(since(next)))?;
                        }
                    }
                    next += 1;
                }
            }
            // The step itself, after the output times it covers.
            out(Stamp::Step(t_new), &y_new)?;
            let mut y_acc = y_new;
            let mut f_acc = k[12];
            renormalize(&mut y_acc, &mut f_acc);
            if last {
                // The step proposed before clipping to the end of the interval.
                return Ok((y_acc, Some(h_before_clip)));
            }
            tau = tau_new;
            t = t_new;
            y = y_acc;
            k[0] = f_acc;
            let fac = (err.powf(0.125) / 0.9).clamp(1.0 / 6.0, 3.0);
            let mut h_new = h / fac;
            if rejected {
                h_new = h_new.min(h);
            }
            rejected = false;
            h = h_new.min(hmax);
        } else {
            stats.rejected_steps += 1;
            rejected = true;
            let fac = if err.is_finite() {
                (err.powf(0.125) / 0.9).min(3.0)
            } else {
                3.0
            };
            h /= fac;
        }
    }
}

/// An 8th-order Dormand-Prince step (no error control) of `y' = f(t, y)`.
fn fixed_step<S: System<N>, const N: usize>(
    sys: &S,
    t: f64,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<SVector<f64, N>> {
    let segment = Segment::of_step(t, h);
    let mut k = [SVector::<f64, N>::zeros(); 16];
    k[0] = sys.rhs(&segment, t, y)?;
    stages(sys, &segment, t, y, h, &mut k, &mut 0)
}

/// One torque-free 8th-order Dormand-Prince step (fixed `h`, no error control) of the angular
/// velocity alone.
#[must_use]
pub fn dop853_step_omega(body: &Moments, omega: &Vector3<f64>, h: f64) -> Vector3<f64> {
    let free = Field {
        body,
        load: NoTorque,
    };
    match fixed_step(&free, 0.0, omega, h) {
        Ok(w) => w,
        Err(_) => unreachable!("the torque-free field cannot fail"),
    }
}

/// One torque-free 8th-order Dormand-Prince step (fixed `h`, no error control) of the angular
/// velocity and orientation (quaternion renormalised).
#[must_use]
pub fn dop853_step(body: &Moments, state: &State, h: f64) -> State {
    let free = Field {
        body,
        load: NoTorque,
    };
    match fixed_step(&free, 0.0, &pack(state), h) {
        Ok(y) => unit_state(y),
        Err(_) => unreachable!("the torque-free field cannot fail"),
    }
}

/// One 8th-order Dormand-Prince step (fixed `h`) of the angular velocity alone under `torque`
/// from time `t`. The torque is evaluated with the identity orientation: an orientation-dependent
/// torque is an error. The step is taken as free of the torque's discontinuities: a switched
/// torque is in the state it has at its midpoint (see [`Torque::try_torque_body_in`]).
pub fn dop853_step_omega_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    omega: &Vector3<f64>,
    h: f64,
) -> Result<Vector3<f64>> {
    require_orientation_free(torque)?;
    fixed_step(&Field { body, load: torque }, t, omega, h)
}

/// One 8th-order Dormand-Prince step (fixed `h`) of the angular velocity and orientation under
/// `torque` from time `t` (a step free of the torque's discontinuities, as in
/// [`dop853_step_omega_torqued`]).
pub fn dop853_step_torqued<T: Torque + ?Sized>(
    body: &Moments,
    torque: &T,
    t: f64,
    state: &State,
    h: f64,
) -> Result<State> {
    let y = fixed_step(&Field { body, load: torque }, t, &pack(state), h)?;
    Ok(unit_state(y))
}

// Generated from scipy/integrate/_ivp/dop853_coefficients.py (Hairer's dop853.f, 2004).
pub(crate) const C: [f64; 16] = [
    0.0,
    0.05260015195876773,
    0.0789002279381516,
    0.1183503419072274,
    0.2816496580927726,
    0.3333333333333333,
    0.25,
    0.3076923076923077,
    0.6512820512820513,
    0.6,
    0.8571428571428571,
    1.0,
    1.0,
    0.1,
    0.2,
    0.7777777777777778,
];
/// Lower-triangular `a_ij`, row `i` holding `j < i`.
pub(crate) const A: [&[f64]; 16] = [
    &[],
    &[0.05260015195876773],
    &[0.0197250569845379, 0.0591751709536137],
    &[0.02958758547680685, 0.0, 0.08876275643042054],
    &[
        0.2413651341592667,
        0.0,
        -0.8845494793282861,
        0.924834003261792,
    ],
    &[
        0.037037037037037035,
        0.0,
        0.0,
        0.17082860872947386,
        0.12546768756682242,
    ],
    &[
        0.037109375,
        0.0,
        0.0,
        0.17025221101954405,
        0.06021653898045596,
        -0.017578125,
    ],
    &[
        0.03709200011850479,
        0.0,
        0.0,
        0.17038392571223998,
        0.10726203044637328,
        -0.015319437748624402,
        0.008273789163814023,
    ],
    &[
        0.6241109587160757,
        0.0,
        0.0,
        -3.3608926294469414,
        -0.868219346841726,
        27.59209969944671,
        20.154067550477894,
        -43.48988418106996,
    ],
    &[
        0.47766253643826434,
        0.0,
        0.0,
        -2.4881146199716677,
        -0.590290826836843,
        21.230051448181193,
        15.279233632882423,
        -33.28821096898486,
        -0.020331201708508627,
    ],
    &[
        -0.9371424300859873,
        0.0,
        0.0,
        5.186372428844064,
        1.0914373489967295,
        -8.149787010746927,
        -18.52006565999696,
        22.739487099350505,
        2.4936055526796523,
        -3.0467644718982196,
    ],
    &[
        2.273310147516538,
        0.0,
        0.0,
        -10.53449546673725,
        -2.0008720582248625,
        -17.9589318631188,
        27.94888452941996,
        -2.8589982771350235,
        -8.87285693353063,
        12.360567175794303,
        0.6433927460157636,
    ],
    &[
        0.054293734116568765,
        0.0,
        0.0,
        0.0,
        0.0,
        4.450312892752409,
        1.8915178993145003,
        -5.801203960010585,
        0.3111643669578199,
        -0.1521609496625161,
        0.20136540080403034,
        0.04471061572777259,
    ],
    &[
        0.056167502283047954,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.25350021021662483,
        -0.2462390374708025,
        -0.12419142326381637,
        0.15329179827876568,
        0.00820105229563469,
        0.007567897660545699,
        -0.008298,
    ],
    &[
        0.03183464816350214,
        0.0,
        0.0,
        0.0,
        0.0,
        0.028300909672366776,
        0.053541988307438566,
        -0.05492374857139099,
        0.0,
        0.0,
        -0.00010834732869724932,
        0.0003825710908356584,
        -0.00034046500868740456,
        0.1413124436746325,
    ],
    &[
        -0.42889630158379194,
        0.0,
        0.0,
        0.0,
        0.0,
        -4.697621415361164,
        7.683421196062599,
        4.06898981839711,
        0.3567271874552811,
        0.0,
        0.0,
        0.0,
        -0.0013990241651590145,
        2.9475147891527724,
        -9.15095847217987,
    ],
];
pub(crate) const E3: [f64; 12] = [
    -0.18980075407240762,
    0.0,
    0.0,
    0.0,
    0.0,
    4.450312892752409,
    1.8915178993145003,
    -5.801203960010585,
    -0.4226823213237919,
    -0.1521609496625161,
    0.20136540080403034,
    0.02265179219836082,
];
pub(crate) const E5: [f64; 12] = [
    0.01312004499419488,
    0.0,
    0.0,
    0.0,
    0.0,
    -1.2251564463762044,
    -0.4957589496572502,
    1.6643771824549864,
    -0.35032884874997366,
    0.3341791187130175,
    0.08192320648511571,
    -0.022355307863886294,
];
pub(crate) const D: [[f64; 16]; 4] = [
    [
        -8.428938276109013,
        0.0,
        0.0,
        0.0,
        0.0,
        0.5667149535193777,
        -3.0689499459498917,
        2.38466765651207,
        2.117034582445028,
        -0.871391583777973,
        2.2404374302607883,
        0.6315787787694688,
        -0.08899033645133331,
        18.148505520854727,
        -9.194632392478356,
        -4.436036387594894,
    ],
    [
        10.427508642579134,
        0.0,
        0.0,
        0.0,
        0.0,
        242.28349177525817,
        165.20045171727028,
        -374.5467547226902,
        -22.113666853125306,
        7.733432668472264,
        -30.674084731089398,
        -9.332130526430229,
        15.697238121770845,
        -31.139403219565178,
        -9.35292435884448,
        35.81684148639408,
    ],
    [
        19.985053242002433,
        0.0,
        0.0,
        0.0,
        0.0,
        -387.0373087493518,
        -189.17813819516758,
        527.8081592054236,
        -11.57390253995963,
        6.8812326946963,
        -1.0006050966910838,
        0.7777137798053443,
        -2.778205752353508,
        -60.19669523126412,
        84.32040550667716,
        11.99229113618279,
    ],
    [
        -25.69393346270375,
        0.0,
        0.0,
        0.0,
        0.0,
        -154.18974869023643,
        -231.5293791760455,
        357.6391179106141,
        93.40532418362432,
        -37.45832313645163,
        104.0996495089623,
        29.8402934266605,
        -43.53345659001114,
        96.32455395918828,
        -39.17726167561544,
        -149.72683625798564,
    ],
];
