//! The exact torque-free motion: Jacobi elliptic functions and the free rotation.
//!
//! - [`sncndn`], [`am`], [`ellipk`], [`ellipf`], [`ellippi`], [`ellippi_complete`]: Jacobi's
//!   elliptic functions and Legendre's integrals as functions of the complementary parameter
//!   `mc = 1 - m`, accurate up to `mc -> 0`;
//! - [`carlson_rf`], [`carlson_rc`], [`carlson_rd`], [`carlson_rj`]: Carlson's symmetric
//!   integrals by duplication (Carlson 1995);
//! - [`FreeRotation`]: the torque-free motion of a rigid body in closed form, any time in O(1)
//!   up to [`FreeRotation::max_time`], where double precision ends for the phase (beyond it
//!   [`FreeRotation::try_state`] is an error), for any positive moments and finite angular
//!   velocity (an error when the momentum, the energy or the rates are beyond the range of
//!   doubles).
//!
//! ```
//! use nalgebra::{UnitQuaternion, Vector3};
//! use polhode::exact::{FreeRotation, Regime};
//!
//! // A body spinning near its intermediate axis: it flips, periodically.
//! let moments = Vector3::new(3.0, 5.0, 9.0);
//! let omega0 = Vector3::new(0.0, 0.4, 1e-3);
//! let motion = FreeRotation::new(moments, omega0, UnitQuaternion::identity()).unwrap();
//! assert_eq!(motion.regime(), Regime::AboutAxis(2));
//! let period = motion.period().unwrap();
//! let (omega, orientation) = motion.state(0.5 * period);
//! assert!(omega.y < -0.39); // half a period later it spins the other way round
//! // L = R(q) I omega is constant in space.
//! let l0 = moments.component_mul(&omega0);
//! assert!((orientation * moments.component_mul(&omega) - l0).norm() < 1e-14);
//! ```

mod carlson;
mod dd;
mod elliptic;
mod free_rotation;
mod xd;

pub use carlson::{carlson_rc, carlson_rd, carlson_rf, carlson_rj};
pub use elliptic::{am, ellipf, ellipk, ellippi, ellippi_complete, sncndn};
pub use free_rotation::{FreeRotation, Regime};
