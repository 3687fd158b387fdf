//! # polhode
//!
//! The rotation of rigid bodies, in pure Rust (nalgebra, thiserror, rayon): the core of the
//! Python package `polhode`, which is a thin binding over it. It does three things.
//!
//! **Mass properties** ([`MassProperties`], [`mass`], [`eigen`]): point masses, analytic
//! solids, closed triangle meshes, their compositions and shifts, and the principal axes.
//!
//! ```
//! use polhode::MassProperties;
//! // A 2 kg solid cylinder of radius 0.1 m and length 0.5 m (symmetry axis z).
//! let cylinder = MassProperties::cylinder(2.0, 0.1, 0.5)?;
//! let principal = cylinder.principal();
//! // I_z = m r^2 / 2 = 0.01 kg m^2 is the smallest moment; I_x = I_y = m (3 r^2 + L^2) / 12.
//! assert!((principal.moments[0] - 0.01).abs() < 1e-15);
//! assert!((principal.moments[2] - 2.0 * (3.0 * 0.01 + 0.25) / 12.0).abs() < 1e-15);
//! # Ok::<(), polhode::Error>(())
//! ```
//!
//! **Motion** ([`dynamics`], [`simulation`]): Euler's equations with the orientation, by the
//! exact solution of the torque-free body or by integrators (Lie-Poisson splitting, implicit
//! midpoint, rk4, dop853), under torques and with internal rotors; one body, or a batch whose
//! outputs are the rows of one table of quantities ([`simulation::Quantity`]).
//!
//! ```
//! use nalgebra::{UnitQuaternion, Vector3};
//! use polhode::dynamics::{integrate, Method, Options, SplittingOrder, State};
//!
//! // 10 s of a free body by the order-4 splitting: L in space is kept to round-off.
//! let moments = Vector3::new(1.0, 2.0, 3.0);
//! let state0 = State::new(Vector3::new(0.1, 1.0, 0.1), UnitQuaternion::identity());
//! let method = Method::Splitting { dt: 1e-3, order: SplittingOrder::Four };
//! let out = integrate(&method, &moments, &state0, &[10.0], &Options::default())?;
//! let l = |q: &UnitQuaternion<f64>, w: &Vector3<f64>| q * moments.component_mul(w);
//! let l10 = l(&out.orientation.unwrap()[0], &out.omega[0]);
//! assert!((l10 - l(&state0.orientation, &state0.omega)).norm() < 1e-14);
//! # Ok::<(), polhode::Error>(())
//! ```
//!
//! **Analysis** ([`exact`]): the torque-free motion in closed form, its regime, period,
//! precession in space and nutation, any time in O(1).
//!
//! ```
//! use nalgebra::{UnitQuaternion, Vector3};
//! use polhode::exact::{FreeRotation, Regime};
//!
//! // Near the intermediate axis: the tennis-racket flip, periodic.
//! let motion = FreeRotation::new(
//!     Vector3::new(3.0, 5.0, 9.0),
//!     Vector3::new(0.0, 0.4, 1e-3),
//!     UnitQuaternion::identity(),
//! )?;
//! assert_eq!(motion.regime(), Regime::AboutAxis(2));
//! let period = motion.period().unwrap();
//! assert!(motion.omega(0.5 * period).y < -0.39);
//! # Ok::<(), polhode::Error>(())
//! ```
//!
//! Every value a function receives is checked where it is received ([`settings`] for the
//! tolerances, steps and counts): bad input is an [`Error`] naming the argument, never a panic
//! or a silent NaN. Long computations report to a [`Monitor`] (progress, cancellation).
//!
//! Conventions, stated once (the repository's `docs/architecture.md` has them all):
//! - any consistent units; mass or density is always explicit;
//! - the inertia tensor is the full symmetric 3x3, products of inertia as tensor elements
//!   (`I_xy = -sum m x y`);
//! - principal moments ascending, principal axes the columns of a proper rotation (det = +1);
//! - orientation maps body to space (`x_space = R x_body`);
//! - angular velocity is in body axes unless a name says `_space`.
#![warn(missing_docs)]

pub mod dynamics;
pub mod eigen;
mod error;
pub mod exact;
pub mod mass;
pub mod memory;
mod monitor;
pub mod series;
pub mod settings;
mod simd;
pub mod simulation;

pub use eigen::{symmetric_eigen3, Principal};
pub use error::{Error, Result, Short};
pub use mass::MassProperties;
pub use monitor::Monitor;

/// The crate's README (its examples), run as doctests so that it stays true.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct CrateReadmeDoctests;

/// The repository README's Rust examples ("Using the Rust core alone"), run as doctests so
/// that they stay true. (The file lies outside the packaged crate: these doctests run from the
/// repository.)
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
