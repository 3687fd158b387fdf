//! The loops over output times that every system shares: the fixed-step loop of a
//! [`Stepper`] and the adaptive loop of `dop853`, for a rigid body ([`super::driver`]) and for a
//! body with rotors ([`super::rotors`]); the segments between output times and the torque's
//! discontinuities; the checks of the outputs.

use nalgebra::{Quaternion, SVector, UnitQuaternion, Vector3, Vector4};

use super::dop853::{self, Settings, Stamp, Tolerance};
use super::method::{Dop853Options, Options, Stats};
use super::stepper::Stepper;
use super::system::System;
use super::torque::{Segment, Torque};
use crate::error::Short;
use crate::monitor::{Monitor, Progress};
use crate::{Error, Result};

/// Number of equal substeps covering `[t_prev, t]`, none longer than `dt` by more than the
/// round-off of the times (at most 1e-12 relative): an interval that is a whole number of `dt`
/// up to that round-off is not given an extra step.
pub(crate) fn substeps(t_prev: f64, t: f64, dt: f64) -> f64 {
    let interval = t - t_prev;
    if interval <= 0.0 {
        return 0.0;
    }
    let slack = (4.0 * f64::EPSILON * (1.0 + t.abs().max(t_prev.abs()) / interval)).min(1e-12);
    ((interval / dt) * (1.0 - slack)).ceil().max(1.0)
}

/// Calls `f(end, output)` for each segment of `[t0, times[-1]]`, ending at every output time
/// (`output = Some(k)`) and every break strictly between (`None`).
pub(crate) fn segments(
    t0: f64,
    times: &[f64],
    breaks: &[f64],
    mut f: impl FnMut(f64, Option<usize>) -> Result<()>,
) -> Result<()> {
    let mut b = breaks.iter().copied().filter(|&x| x > t0).peekable();
    for (k, &t) in times.iter().enumerate() {
        while let Some(x) = b.next_if(|&x| x < t) {
            f(x, None)?;
        }
        f(t, Some(k))?;
    }
    Ok(())
}

/// The sorted, finite discontinuities of `torque` (if any) and of `more` (a gyrostat's motor
/// schedules): where a step must end.
pub(crate) fn breaks(torque: Option<&dyn Torque>, more: Vec<f64>) -> Vec<f64> {
    let mut breaks = torque.map(Torque::discontinuities).unwrap_or_default();
    breaks.extend(more);
    breaks.retain(|t| t.is_finite());
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    breaks
}

/// The ends of the solves of an adaptive run from `t0` to the last output time: the `breaks`
/// strictly inside the run, then the last output time.
pub(crate) fn segment_ends(t0: f64, times: &[f64], breaks: &[f64]) -> Vec<f64> {
    let t_last = times.last().copied().unwrap_or(t0);
    let mut ends: Vec<f64> = breaks
        .iter()
        .copied()
        .filter(|&b| b > t0 && b < t_last)
        .collect();
    ends.push(t_last);
    ends
}

/// The number of steps of a fixed-step run with step `dt` (see [`substeps`]), or an error
/// naming `dt` if it exceeds `options.max_steps`.
pub(crate) fn fixed_total(
    dt: f64,
    times: &[f64],
    breaks: &[f64],
    options: &Options,
) -> Result<f64> {
    let mut total = 0.0;
    let mut prev = options.t0;
    segments(options.t0, times, breaks, |t, _| {
        total += substeps(prev, t, dt);
        prev = t;
        Ok(())
    })?;
    if total > options.max_steps as f64 {
        return Err(Error::InvalidArgument {
            name: "dt".into(),
            reason: format!(
                "dt = {} needs {} steps, more than max_steps = {}.",
                Short(dt),
                Short(total),
                options.max_steps
            ),
        });
    }
    Ok(total)
}

/// The fixed-step loop of `stepper` from `y0` at `options.t0`: `n = ceil(interval / dt)` equal
/// substeps between successive output times and `breaks` (the discontinuities of the torques),
/// so that each step lies in an interval between two of those times, free of discontinuities;
/// `out(k, stepper, y)` gets the variables at `times[k]`. The one fixed-step loop of every
/// system (a rigid body's steppers, a gyrostat's rk4), reporting to the monitor every
/// [`Monitor::CHECK_EVERY`] steps.
pub(crate) fn fixed_loop<S: Stepper>(
    mut stepper: S,
    dt: f64,
    y0: S::Vars,
    times: &[f64],
    breaks: &[f64],
    options: &Options,
    mut out: impl FnMut(usize, &S, &S::Vars) -> Result<()>,
) -> Result<Stats> {
    let total = fixed_total(dt, times, breaks, options)?;
    let mut y = y0;
    stepper.start(&y);
    let progress = Progress::new(options.monitor, options.t0, Monitor::CHECK_EVERY);
    let mut prev = options.t0;
    segments(options.t0, times, breaks, |t, k| {
        let n = substeps(prev, t, dt);
        if n > 0.0 {
            let h = (t - prev) / n;
            let segment = Segment::new(prev, t);
            // Runs of steps between looks, so that the loop over steps is the same as without.
            let (n, mut j) = (n as u64, 0);
            while j < n {
                let end = n.min(j + u64::from(progress.budget()));
                // On a local copy, which the compiler keeps in registers.
                let mut local = y;
                for i in j..end {
                    let t = prev + i as f64 * h;
                    stepper
                        .step(&segment, t, &mut local, h)
                        .map_err(|e| stepper.at_time(e, t))?;
                    stepper.restore(&mut local);
                }
                y = local;
                progress.spend((end - j) as u32, || prev + end as f64 * h)?;
                j = end;
            }
        }
        prev = t;
        match k {
            Some(k) => out(k, &stepper, &y),
            None => Ok(()),
        }
    })?;
    progress.finish(prev);
    let steps = total as u64;
    Ok(Stats {
        steps,
        rejected_steps: 0,
        rhs_evaluations: stepper.evaluations(steps),
    })
}

/// A vector field that ticks a [`Progress`] at each evaluation (for `Dop853`, whose loop
/// lives in [`super::dop853`]); it returns exactly what `sys` returns.
struct Watched<'s, 'p, S> {
    sys: &'s S,
    progress: &'s Progress<'p>,
}

impl<S: System<N>, const N: usize> System<N> for Watched<'_, '_, S> {
    #[inline]
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        self.progress.spend(1, || t)?;
        self.sys.rhs(segment, t, y)
    }
}

/// `dop853` from `options.t0` over the output `times`, one solve per segment ending at each
/// of `ends` (see [`segment_ends`]), restarting the method there with the last step size;
/// `out(Stamp::Output(k), y)` gets the state at `times[k]`, `out(Stamp::Step(t), y)` the state
/// at the end of each accepted step (after the output times it covers). The one adaptive
/// loop of every system (a rigid body, a gyrostat), reporting each evaluation to the monitor.
#[allow(clippy::too_many_arguments)]
pub(crate) fn dop853_segments<S: System<N>, const N: usize>(
    sys: &S,
    y0: SVector<f64, N>,
    times: &[f64],
    options: &Options,
    o: &Dop853Options,
    tol: Tolerance<N>,
    ends: &[f64],
    renormalize: impl Fn(&mut SVector<f64, N>, &mut SVector<f64, N>) + Copy,
    mut out: impl FnMut(Stamp, &SVector<f64, N>) -> Result<()>,
) -> Result<Stats> {
    let mut settings = Settings {
        tol,
        first_step: o.first_step,
        max_step: o.max_step,
        max_steps: options.max_steps,
    };
    let mut stats = Stats::default();
    let progress = Progress::new(options.monitor, options.t0, Monitor::CHECK_EVERY);
    let watched = Watched {
        sys,
        progress: &progress,
    };
    let (mut t, mut y, mut first) = (options.t0, y0, 0);
    for &end in ends {
        let last = first + times[first..].partition_point(|&x| x <= end);
        let (y_end, h) = dop853::solve(
            &watched,
            t,
            &y,
            end,
            &times[first..last],
            &settings,
            renormalize,
            |stamp, y| match stamp {
                Stamp::Output(k) => out(Stamp::Output(first + k), y),
                step => out(step, y),
            },
            &mut stats,
        )?;
        settings.first_step = h;
        (t, y, first) = (end, y_end, last);
    }
    progress.finish(t);
    Ok(stats)
}

/// A torque-free field, homogeneous of degree 2 in its rates (the angular velocity, and a
/// gyrostat's free wheels), with the rates in units of `scale` (see
/// [`super::driver::omega_scale`]): the derivatives of `(w / scale, q, ...)` are `scale` times
/// the field's at them.
pub(crate) struct ScaledSystem<S> {
    pub(crate) system: S,
    pub(crate) scale: f64,
}

impl<S: System<N>, const N: usize> System<N> for ScaledSystem<S> {
    fn rhs(&self, segment: &Segment, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        Ok(self.system.rhs(segment, t, y)? * self.scale)
    }
}

/// The error of an output `what` that is not finite at `t`. It names `dt` for the fixed-step
/// methods (a step too long for the motion), `t` for the others (a motion that leaves double
/// precision before the times asked for).
#[cold]
fn blew_up(fixed_step: bool, what: String, t: f64, value: f64) -> Error {
    let (name, hint) = if fixed_step {
        (
            "dt",
            "reduce dt (a step too long for the rotation rate or the torque).",
        )
    } else {
        (
            "t",
            "the motion leaves double precision before the times asked for.",
        )
    };
    Error::BlewUp {
        name: name.into(),
        what,
        hint: hint.into(),
        t,
        value,
    }
}

/// Checks that the angular velocity output at `t` is finite.
#[inline]
pub(crate) fn check_omega_output(fixed_step: bool, t: f64, w: &Vector3<f64>) -> Result<()> {
    for i in 0..3 {
        if !w[i].is_finite() {
            return Err(blew_up(fixed_step, format!("omega[{i}]"), t, w[i]));
        }
    }
    Ok(())
}

/// The orientation output at `t` from the raw quaternion `q`: `q / |q|`, checked finite.
#[inline]
pub(crate) fn unit_output(
    fixed_step: bool,
    t: f64,
    q: &Vector4<f64>,
) -> Result<UnitQuaternion<f64>> {
    checked_unit(fixed_step, t, q / q.norm())
}

/// The orientation output at `t` from `unit = q / |q|` (computed by the caller as
/// [`unit_output`] does), checked finite.
#[inline]
pub(crate) fn checked_unit(
    fixed_step: bool,
    t: f64,
    unit: Vector4<f64>,
) -> Result<UnitQuaternion<f64>> {
    if !unit.iter().all(|c| c.is_finite()) {
        // The orientation can blow up while omega stays finite (a step far too large for the
        // rotation rate): an error, not NaN quaternions beside finite omega.
        let value = unit
            .iter()
            .copied()
            .find(|c| !c.is_finite())
            .unwrap_or(f64::NAN);
        return Err(blew_up(
            fixed_step,
            "the orientation (its quaternion)".into(),
            t,
            value,
        ));
    }
    Ok(UnitQuaternion::new_unchecked(Quaternion::from(unit)))
}
