//! # polhode
//!
//! The rotation of rigid bodies: mass properties and principal axes, and the integration of
//! Euler's equations (with orientation) by an exact solution and structure-preserving
//! integrators.
//!
//! This is the pure-Rust core (nalgebra only). The Python package `polhode` is a thin binding
//! over it; a Rust user depends on this crate alone.
//!
//! Conventions, stated once (the repository's `docs/architecture.md` has them all):
//! - any consistent units; mass or density is always explicit;
//! - the inertia tensor is the full symmetric 3x3, products of inertia as tensor elements
//!   (`I_xy = -sum m x y`);
//! - principal moments ascending, principal axes the columns of a proper rotation (det = +1);
//! - orientation maps body to space (`x_space = R x_body`);
//! - angular velocity is in body axes unless a name says `_space`.
//!
//! ```
//! use polhode::MassProperties;
//! // A 2 kg solid cylinder of radius 0.1 m and length 0.5 m (symmetry axis z).
//! let cylinder = MassProperties::cylinder(2.0, 0.1, 0.5).unwrap();
//! let principal = cylinder.principal();
//! // I_z = m r^2 / 2 = 0.01 kg m^2 is the smallest moment; I_x = I_y = m (3 r^2 + L^2) / 12.
//! assert!((principal.moments[0] - 0.01).abs() < 1e-15);
//! assert!((principal.moments[2] - 2.0 * (3.0 * 0.01 + 0.25) / 12.0).abs() < 1e-15);
//! ```
#![warn(missing_docs)]

pub mod dynamics;
pub mod eigen;
mod error;
pub mod exact;
pub mod mass;
mod memory;
mod monitor;
pub mod settings;
mod simd;
pub mod simulation;

pub use eigen::{symmetric_eigen3, Principal};
pub use error::{Error, Result, Short};
pub use mass::MassProperties;
pub use monitor::Monitor;

/// The README's Rust example, run as a doctest so that it stays true.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
