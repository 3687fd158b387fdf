//! The methods by name and their settings, the options common to all, the cost of a run, and
//! the checks of those settings.

use super::splitting::SplittingOrder;
use super::torque::Torque;
use crate::error::{finite, Short};
use crate::settings::{choice, count_u64, Setting};
use crate::{Error, Monitor, Result};

/// An integration method and its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Lie-Poisson splitting (see [`super::splitting`]) with fixed step `dt`.
    Splitting {
        /// Largest step.
        dt: f64,
        /// Order of the composition.
        order: SplittingOrder,
    },
    /// Implicit midpoint rule (see [`super::midpoint`]) with fixed step `dt`.
    Midpoint {
        /// Largest step.
        dt: f64,
    },
    /// Classic RK4 (see [`super::rk4`]) with fixed step `dt`.
    Rk4 {
        /// Largest step.
        dt: f64,
    },
    /// Adaptive Dormand-Prince 8(5,3) (see [`super::dop853`]).
    Dop853(Dop853Options),
    /// The exact solution of the torque-free body ([`crate::exact::FreeRotation`]) evaluated at each output
    /// time: no steps, torque-free only.
    Exact,
}

/// How a method steps: what choosing it by name needs ([`Method::from_name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stepping {
    /// The exact solution without a torque, `dop853` with one.
    Auto,
    /// A closed form: no step.
    Exact,
    /// A fixed step `dt`.
    Fixed,
    /// Adaptive, to `rtol` and `atol`.
    Adaptive,
}

impl Stepping {
    /// Its name, as [`METHODS`] lists it for a user (`"fixed"`, ...).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Stepping::Auto => "auto",
            Stepping::Exact => "exact",
            Stepping::Fixed => "fixed",
            Stepping::Adaptive => "adaptive",
        }
    }
}

/// Every method by the name a user gives it, and how it steps. Adding a method is its module
/// (a `Stepper`), a variant of [`Method`] with its arm in the driver, and its row here and in
/// [`Method::from_name`] and [`Method::name`].
pub const METHODS: &[(&str, Stepping)] = &[
    ("auto", Stepping::Auto),
    ("exact", Stepping::Exact),
    ("splitting", Stepping::Fixed),
    ("midpoint", Stepping::Fixed),
    ("rk4", Stepping::Fixed),
    ("dop853", Stepping::Adaptive),
];

/// What a method chosen by name may take: the step of a fixed-step method, the splitting's
/// order, the adaptive method's tolerances, and whether a torque or rotors are applied
/// (`"auto"` then picks `dop853`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodSettings {
    /// Largest step of a fixed-step method (required by them).
    pub dt: Option<f64>,
    /// Order of the splitting: 2, 4 or 6.
    pub order: i64,
    /// Relative tolerance of `dop853`.
    pub rtol: f64,
    /// Absolute tolerance of `dop853` (see [`Dop853Options::atol`]).
    pub atol: Option<f64>,
    /// Whether a torque is applied.
    pub torque: bool,
    /// Whether the body has rotors (`"auto"` then picks `dop853` too).
    pub rotors: bool,
}

impl Default for MethodSettings {
    fn default() -> Self {
        Self {
            dt: None,
            order: 4,
            rtol: Dop853Options::default().rtol,
            atol: None,
            torque: false,
            rotors: false,
        }
    }
}

impl MethodSettings {
    /// Checks every value given, for the method named `method` (a row of [`METHODS`]): `dt`
    /// (required by a fixed-step method; a step: [`Setting::Step`]), `order` (2, 4 or 6),
    /// `rtol` ([`Setting::RelativeTolerance`]) and `atol` ([`Setting::AbsoluteTolerance`]),
    /// whatever the method uses: a value a method does not use is still a value given.
    ///
    /// # Errors
    /// The first bad value's, naming it.
    pub fn check(&self, method: &str) -> Result<()> {
        match self.dt {
            Some(dt) => {
                Setting::Step.check("dt", dt)?;
            }
            None if METHODS.contains(&(method, Stepping::Fixed)) => {
                return Err(Error::InvalidArgument {
                    name: "dt".into(),
                    reason: format!(
                        "expected `dt` (the largest step) for method {method:?}, got None."
                    ),
                });
            }
            None => {}
        }
        choice("order", self.order, &[2, 4, 6], "method \"splitting\"")?;
        Setting::RelativeTolerance.check("rtol", self.rtol)?;
        if let Some(atol) = self.atol {
            Setting::AbsoluteTolerance.check("atol", atol)?;
        }
        Ok(())
    }
}

impl Method {
    /// The method a user names (a row of [`METHODS`]) with its settings, each checked where
    /// it is received ([`MethodSettings::check`]). Errors name `method`, `dt`, `order`,
    /// `rtol` or `atol`.
    pub fn from_name(name: &str, settings: &MethodSettings) -> Result<Self> {
        if !METHODS.iter().any(|(n, _)| *n == name) {
            let names: Vec<String> = METHODS.iter().map(|(n, _)| format!("{n:?}")).collect();
            return Err(Error::InvalidArgument {
                name: "method".into(),
                reason: format!("expected one of {}, got {name:?}.", names.join(", ")),
            });
        }
        settings.check(name)?;
        let dt = settings.dt.unwrap_or(f64::NAN);
        let dop853 = Method::Dop853(Dop853Options {
            rtol: settings.rtol,
            atol: settings.atol,
            ..Dop853Options::default()
        });
        Ok(match name {
            "auto" if settings.torque || settings.rotors => dop853,
            "splitting" => Method::Splitting {
                dt,
                order: match settings.order {
                    2 => SplittingOrder::Two,
                    6 => SplittingOrder::Six,
                    _ => SplittingOrder::Four,
                },
            },
            "midpoint" => Method::Midpoint { dt },
            "rk4" => Method::Rk4 { dt },
            "dop853" => dop853,
            _ => Method::Exact,
        })
    }

    /// The method's name, a row of [`METHODS`].
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Splitting { .. } => "splitting",
            Method::Midpoint { .. } => "midpoint",
            Method::Rk4 { .. } => "rk4",
            Method::Dop853(_) => "dop853",
        }
    }
}

/// Settings of the adaptive [`Method::Dop853`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dop853Options {
    /// Relative tolerance, in `[1e-15, 1)` (default `1e-10`).
    pub rtol: f64,
    /// Absolute tolerance on the angular velocity, in its units (default `rtol |omega0|`, or
    /// for a body starting at rest `rtol |omega'(t0)| (t_end - t0)`). The quaternion
    /// components (dimensionless, `|q| = 1`) use `rtol` as absolute tolerance.
    pub atol: Option<f64>,
    /// First step (default: Hairer's estimate).
    pub first_step: Option<f64>,
    /// Largest step (default: the whole span). Steps always end at the torque's
    /// [`Torque::discontinuities`].
    pub max_step: Option<f64>,
}

impl Default for Dop853Options {
    fn default() -> Self {
        Self {
            rtol: 1e-10,
            atol: None,
            first_step: None,
            max_step: None,
        }
    }
}

impl Dop853Options {
    /// The defaults with relative tolerance `rtol`.
    #[must_use]
    pub fn with_rtol(rtol: f64) -> Self {
        Self {
            rtol,
            ..Self::default()
        }
    }
}

/// Settings common to all methods.
#[derive(Clone, Copy)]
pub struct Options<'a> {
    /// Initial time: the state given is at `t0`; every output time is `>= t0` (default 0).
    pub t0: f64,
    /// Whether to integrate and return the orientation (default `true`). When `false` only the
    /// angular velocity is integrated (cheaper), unless the torque depends on the orientation, in
    /// which case the orientation is integrated but not returned.
    pub with_orientation: bool,
    /// External torque in body axes (default none).
    pub torque: Option<&'a dyn Torque>,
    /// Largest number of steps (accepted and rejected), an error if exceeded (default `1e8`).
    pub max_steps: u64,
    /// Progress record and cancel flag, looked at every [`Monitor::CHECK_EVERY`] steps (every
    /// 256 output times for [`Method::Exact`]; default none).
    pub monitor: Option<&'a Monitor>,
}

impl Default for Options<'_> {
    fn default() -> Self {
        Self {
            t0: 0.0,
            with_orientation: true,
            torque: None,
            max_steps: 100_000_000,
            monitor: None,
        }
    }
}

/// The cost of an integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Steps taken (accepted steps for `Dop853`, none for `Exact`).
    pub steps: u64,
    /// Steps rejected by the error control (`Dop853` only).
    pub rejected_steps: u64,
    /// Evaluations of the vector field (for the splitting: of the torque only, the free
    /// sub-flows being exact; for the midpoint rule: its fixed-point and Newton iterations
    /// and torque evaluations; for `Exact`: evaluations of the closed form, one per output
    /// time).
    pub rhs_evaluations: u64,
}

pub(crate) fn check_times(times: &[f64], t0: f64) -> Result<()> {
    finite("t0", t0)?;
    let mut prev = t0;
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            finite(&format!("t[{k}]"), t)?;
        }
        if t < prev {
            return Err(Error::InvalidArgument {
                name: "t".into(),
                reason: if k == 0 {
                    format!("expected t[0] >= t0 = {}, got {}.", Short(t0), Short(t))
                } else {
                    format!(
                        "expected non-decreasing t, got t[{}] = {} > t[{k}] = {}.",
                        k - 1,
                        Short(prev),
                        Short(t)
                    )
                },
            });
        }
        prev = t;
    }
    Ok(())
}

/// Checks a run's method and options: the method's steps and tolerances (each through
/// [`Setting`]), `max_steps` (a [`count`](crate::settings::count)), and no torque for the
/// exact solution.
pub(crate) fn check_method(method: &Method, options: &Options) -> Result<()> {
    match method {
        Method::Splitting { dt, .. } | Method::Midpoint { dt } | Method::Rk4 { dt } => {
            Setting::Step.check("dt", *dt)?;
        }
        Method::Dop853(o) => {
            Setting::RelativeTolerance.check("rtol", o.rtol)?;
            if let Some(a) = o.atol {
                Setting::AbsoluteTolerance.check("atol", a)?;
            }
            if let Some(h) = o.first_step {
                Setting::Step.check("first_step", h)?;
            }
            if let Some(h) = o.max_step {
                Setting::Step.check("max_step", h)?;
            }
        }
        Method::Exact => {
            if options.torque.is_some() {
                return Err(Error::InvalidArgument {
                    name: "torque".into(),
                    reason: "the exact solution is torque-free; use dop853 or another integrator."
                        .into(),
                });
            }
        }
    }
    count_u64("max_steps", options.max_steps)?;
    Ok(())
}
