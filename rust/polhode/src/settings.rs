//! The one check of every tolerance, step and count a computation takes, where the core
//! receives it: each error names the argument (`rtol`, `atol`, `dt`, `max_steps`, ...).
//!
//! ```
//! use polhode::settings::{count, Setting};
//!
//! assert_eq!(Setting::RelativeTolerance.check("rtol", 1e-10), Ok(1e-10));
//! // A relative tolerance of 1 asks for no digit at all.
//! let error = Setting::RelativeTolerance.check("rtol", 1.0).unwrap_err();
//! assert_eq!(error.argument(), Some("rtol"));
//! assert!(Setting::Step.check("dt", f64::NAN).is_err());
//! assert_eq!(count("max_steps", 1000), Ok(1000));
//! assert!(count("max_steps", 0).is_err());
//! ```

use crate::error::{positive, Short};
use crate::{Error, Result};

/// The smallest relative tolerance of an integration: below it, double precision cannot
/// deliver (a step's own round-off is about 1e-16).
pub const MIN_RTOL: f64 = 1e-15;

/// What a setting may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// A step or a span of time (`dt`, `first_step`, `max_step`): finite and positive.
    Step,
    /// The relative tolerance of an adaptive integration (`rtol` of `dop853`): finite, at
    /// least [`MIN_RTOL`] and below 1 (a tolerance of 1 or more asks for no correct digit:
    /// such runs returned motions whose `|L|` drifted by 37 or 1.6e21).
    RelativeTolerance,
    /// An absolute tolerance (`atol` of `dop853`, in the units of what it bounds): finite and
    /// positive.
    AbsoluteTolerance,
    /// A tolerance that merges what it does not tell apart (`rtol` of the principal axes:
    /// moments whose gap is within it count as equal): finite and `>= 0`.
    MergeTolerance,
}

impl Setting {
    /// `value`, checked as this setting of the argument `name`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN or an infinity, [`Error::NonPositive`] for a step or a
    /// tolerance that must be positive, [`Error::InvalidArgument`] for a value out of its range;
    /// each naming `name`.
    pub fn check(self, name: &str, value: f64) -> Result<f64> {
        match self {
            Setting::Step | Setting::AbsoluteTolerance => positive(name, value),
            Setting::RelativeTolerance => {
                positive(name, value)?;
                if value < MIN_RTOL {
                    return Err(Error::InvalidArgument {
                        name: name.into(),
                        reason: format!(
                            "expected {name} >= {} (double precision), got {}.",
                            Short(MIN_RTOL),
                            Short(value)
                        ),
                    });
                }
                if value >= 1.0 {
                    return Err(Error::InvalidArgument {
                        name: name.into(),
                        reason: format!(
                            "expected {name} < 1 (the error allowed relative to the solution: \
                             1e-6 asks for about six digits), got {}.",
                            Short(value)
                        ),
                    });
                }
                Ok(value)
            }
            Setting::MergeTolerance => {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(Error::InvalidArgument {
                        name: name.into(),
                        reason: format!("expected a finite number >= 0, got {}.", Short(value)),
                    });
                }
                Ok(value)
            }
        }
    }
}

/// A count of the argument `name` (`max_steps`): an integer at least 1, as the unsigned count
/// the core runs with.
///
/// # Errors
/// [`Error::InvalidArgument`] naming `name` for a count below 1.
pub fn count(name: &str, value: i64) -> Result<u64> {
    u64::try_from(value)
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| Error::InvalidArgument {
            name: name.into(),
            reason: format!("expected at least 1, got {value}."),
        })
}

/// [`count`] of a count already unsigned.
pub(crate) fn count_u64(name: &str, value: u64) -> Result<u64> {
    if value == 0 {
        return count(name, 0);
    }
    Ok(value)
}

/// One of the integers `choices` for the argument `name` (the splitting's `order`: 2, 4 or 6),
/// `what` saying what takes it.
///
/// # Errors
/// [`Error::InvalidArgument`] naming `name` for another value.
pub fn choice(name: &str, value: i64, choices: &[i64], what: &str) -> Result<i64> {
    if choices.contains(&value) {
        return Ok(value);
    }
    let listed: Vec<String> = choices.iter().map(i64::to_string).collect();
    let listed = match listed.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    };
    Err(Error::InvalidArgument {
        name: name.into(),
        reason: format!("expected {listed} for {what}, got {value}."),
    })
}
