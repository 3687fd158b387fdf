//! Euler's equations with orientation: integrators and torques.
//!
//! State: the angular velocity `w` in body (principal) axes and the body-to-space orientation
//! quaternion `q` (`x_space = R(q) x_body`). Equations (Landau-Lifshitz par. 36):
//! `I1 w1' + (I3 - I2) w2 w3 = tau1` (and cyclic), `tau` in body axes, and
//! `q' = 1/2 q (x) (0, w)`. Without torque, `L_space = R(q) I w`, `|L|` and
//! `T = 1/2 sum I_i w_i^2` are constant.
//!
//! Methods, each as pure single-step functions (angular velocity alone, or with the orientation;
//! torque-free or under a [`Torque`]) and through the driver [`integrate`]:
//! - [`splitting`]: Lie-Poisson splitting into exact axis rotations, orders 2, 4, 6; `|L|` and
//!   `L_space` conserved to round-off, energy error bounded;
//! - [`midpoint`]: implicit midpoint rule; `T` and `|L|` conserved to round-off;
//! - [`rk4`]: classic explicit Runge-Kutta, order 4;
//! - [`dop853`]: adaptive Dormand-Prince 8(5,3) with dense output;
//! - [`Method::Exact`] (driver only): the closed form of the torque-free body,
//!   [`crate::exact::FreeRotation`], at each output time.
//!
//! A body with internal rotors (reaction wheels, spherical dampers: the gyrostat equations of
//! [`rotors`]) is integrated by [`integrate_gyrostat`], with `rk4` or `dop853`.
//!
//! ```
//! use nalgebra::Vector3;
//! use polhode::dynamics::{integrate, Method, Options, SplittingOrder, State};
//!
//! let moments = Vector3::new(1.0, 0.75, 0.25);
//! let state0 = State::from_omega(Vector3::new(1.0, 0.1, 0.2));
//! let times: Vec<f64> = (0..=10).map(|k| k as f64).collect();
//! let method = Method::Splitting { dt: 1e-3, order: SplittingOrder::Four };
//! let sol = integrate(&method, &moments, &state0, &times, &Options::default()).unwrap();
//! let orientation = sol.orientation.unwrap();
//! // L in space is conserved to round-off.
//! let l0 = state0.orientation * moments.component_mul(&state0.omega);
//! let l10 = orientation[10] * moments.component_mul(&sol.omega[10]);
//! assert!((l10 - l0).norm() <= 1e-13 * l0.norm());
//! ```

pub mod dop853;
mod driver;
pub(crate) mod lanes;
mod loops;
mod method;
pub mod midpoint;
pub mod rk4;
pub mod rotors;
pub mod splitting;
mod state;
mod stepper;
mod system;
pub mod torque;

pub use dop853::{dop853_step, dop853_step_omega, dop853_step_omega_torqued, dop853_step_torqued};
pub(crate) use driver::{
    exact_range, omega_scale, run_body, run_body_with_steps, start, start_state,
};
pub use driver::{integrate, integrate_body, Trajectory};
pub(crate) use loops::substeps;
pub(crate) use method::{check_method, check_times};
pub use method::{Dop853Options, Method, MethodSettings, Options, Stats, Stepping, METHODS};
pub use midpoint::{
    midpoint_step, midpoint_step_omega, midpoint_step_omega_torqued, midpoint_step_torqued,
};
pub use rk4::{rk4_step, rk4_step_omega, rk4_step_omega_torqued, rk4_step_torqued};
pub(crate) use rotors::{check_rotor_method, run_gyrostat, run_gyrostat_with_steps};
pub use rotors::{
    integrate_gyrostat, Gyrostat, GyrostatTrajectory, MotorFn, MotorTorque, RotorFields, RotorSpec,
    MAX_ROTOR_VARIABLES,
};
pub use splitting::{
    splitting_step, splitting_step_omega, splitting_step_omega_torqued, splitting_step_torqued,
    SplittingOrder,
};
pub use state::{Moments, State};
pub use torque::*;
