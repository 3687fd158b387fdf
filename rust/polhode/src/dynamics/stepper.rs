//! The interface of the fixed-step integrators, through which the one fixed-step loop runs them
//! and their single-step functions take one step.
//!
//! A new fixed-step method is a type implementing [`Stepper`] and [`BodyStepper`] in its own
//! module (with its single-step functions, thin wrappers over [`Stepper::step`]), a
//! [`super::Method`] variant mapped to it in the driver's dispatch, and its re-exports in
//! `dynamics`.

use nalgebra::{Vector3, Vector4};

use super::state::State;
use super::torque::Segment;
use crate::{Error, Result};

/// The variables of a fixed-step method: a 3-vector (the angular velocity, or what the method
/// integrates instead, see [`BodyStepper::omega`]) and the raw orientation quaternion
/// `(x, y, z, w)`, left untouched by a method that does not integrate the orientation.
pub(crate) type Vars = (Vector3<f64>, Vector4<f64>);

/// A fixed-step integrator of some equations on their variables [`Stepper::Vars`], run by the
/// one fixed-step loop ([`super::loops::fixed_loop`]).
///
/// Each rigid-body method implements it once, for a body under a [`super::system::Load`] (no
/// torque or a torque, known from the type) with or without the orientation (a
/// `const ORIENTATION: bool`), with [`BodyStepper`]; a gyrostat's rk4 implements it on its
/// first-order system. The single-step functions call [`Stepper::step`] alone; a run of the loop
/// calls [`Stepper::start`] once, then [`Stepper::step`] and [`Stepper::restore`] for each step.
pub(crate) trait Stepper {
    /// The variables it steps.
    type Vars: Copy;

    /// One step of the method from `t` over `h`, lying in `segment` (free of discontinuities
    /// of the torque; see [`super::Torque::try_torque_body_in`]).
    fn step(&mut self, segment: &Segment, t: f64, y: &mut Self::Vars, h: f64) -> Result<()>;

    /// A run of the loop starts from `y`; by default nothing to prepare.
    #[inline(always)]
    fn start(&mut self, y: &Self::Vars) {
        let _ = y;
    }

    /// After each step of a run of the loop: restores what round-off erodes over many steps
    /// (exact in exact arithmetic: the results change by round-off only); by default nothing.
    #[inline(always)]
    fn restore(&mut self, y: &mut Self::Vars) {
        let _ = y;
    }

    /// The error of a step of a run from `t`, with the time added where the method's own
    /// message lacks it; by default the error as it is.
    #[cold]
    fn at_time(&self, error: Error, t: f64) -> Error {
        let _ = t;
        error
    }

    /// Evaluations of the vector field in the `steps` steps taken so far (see
    /// [`super::Stats::rhs_evaluations`]).
    fn evaluations(&self, steps: u64) -> u64;
}

/// A rigid body's fixed-step integrator, on [`Vars`]: the angular velocity (or what the method
/// integrates instead) and the raw quaternion.
pub(crate) trait BodyStepper: Stepper<Vars = Vars> {
    /// The variables of `state`; by default `(omega, q)`.
    #[inline(always)]
    fn vars(&self, state: &State) -> Vars {
        (state.omega, state.orientation.coords)
    }

    /// The angular velocity of the variables `y`; by default `y.0`.
    #[inline(always)]
    fn omega(&self, y: &Vars) -> Vector3<f64> {
        y.0
    }

    /// The angular velocity reported for `state` itself (an output at t0, before any step):
    /// by default its omega, exactly as given.
    #[inline(always)]
    fn omega_of(&self, state: &State) -> Vector3<f64> {
        state.omega
    }
}
