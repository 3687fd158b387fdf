//! Trajectories of one body or a batch, reported in each body's own axes: the one path from a
//! body as a user gives it (principal moments, an inertia tensor, mass properties) to the
//! outputs a user reads (angular velocity, orientation, angular momentum, energy).
//!
//! - [`job`](Body): each body becomes a prepared job, integrated in its principal axes
//!   (where Euler's equations are diagonal) with its torque rotated into them in one place;
//! - [`Quantity`]: the table of the outputs (name, shape, unit, frame, description and
//!   computation), each written in the body's own axes, quaternions kept continuous in time
//!   (`q` and `-q` are one rotation);
//! - the runner: one for every body and every system (a rigid body, a body with rotors), with
//!   the exact, scalar or lane strategy; the outputs written through safe slices, each body
//!   into its own.
//!
//! ```
//! use nalgebra::{UnitQuaternion, Vector3};
//! use polhode::dynamics::Method;
//! use polhode::simulation::{simulate, Body, Simulation};
//!
//! // Two bodies at once, by the exact solution, at t = 0 and t = 10.
//! let bodies = [Body::Moments(Vector3::new(1.0, 2.0, 3.0)), Body::Moments(Vector3::new(2.0, 2.0, 5.0))];
//! let omega0 = [Vector3::new(0.1, 1.0, 0.1), Vector3::new(0.3, 0.0, 1.0)];
//! let run = Simulation::new(Method::Exact);
//! let out = simulate(&run, &bodies, &omega0, &[UnitQuaternion::identity()], &[0.0, 10.0], None)?;
//! let energy = out.column("energy").unwrap();
//! // Two bodies x two times; T is conserved to a few ulp (at t = 0 the state given, at
//! // t = 10 the closed form's).
//! assert!((energy[1] - energy[0]).abs() <= 8.0 * f64::EPSILON * energy[0]);
//! # Ok::<(), polhode::Error>(())
//! ```

mod job;
mod output;
mod quantity;
mod runner;
mod sampling;

use nalgebra::{UnitQuaternion, Vector3};

pub use job::{orientation_from_matrix, orientation_from_quaternion, Body};
pub use output::Outputs;
pub use quantity::{Dim, Frame, Quantity};
pub use sampling::{fastest_rate, fixed_steps, Pace, Rate};

use crate::dynamics::{check_method, check_rotor_method, check_times, Gyrostat, Method, Options};
use crate::dynamics::{RotorSpec, TorqueSpec};
use crate::{Error, Monitor, Result};
use job::Job;
use output::Layout;
use runner::{Context, RigidBody, WithRotors, EXACT_CHUNK};

/// The settings of a run, shared by every body.
#[derive(Clone)]
pub struct Simulation {
    /// The method (with [`Method::Exact`], the closed form; torque-free only).
    pub method: Method,
    /// The time of the initial state.
    pub t0: f64,
    /// Whether to report the orientation (and L in space).
    pub with_orientation: bool,
    /// Largest number of steps per body (at least 1).
    pub max_steps: u64,
    /// External torque, in body axes.
    pub torque: Option<TorqueSpec>,
    /// Run the bodies on the rayon pool (true) or one after another on the calling thread.
    pub parallel: bool,
    /// Internal rotors (reaction wheels, spherical dampers; see [`crate::dynamics::rotors`]),
    /// in each body's own axes, shared by every body; integrated by `rk4` or `dop853`. The
    /// body's inertia includes them, locked.
    pub rotors: Vec<RotorSpec>,
}

impl Simulation {
    /// A torque-free run from `t0 = 0` with the orientation, in parallel.
    #[must_use]
    pub fn new(method: Method) -> Self {
        Self {
            method,
            t0: 0.0,
            with_orientation: true,
            max_steps: Options::default().max_steps,
            torque: None,
            parallel: true,
            rotors: Vec::new(),
        }
    }

    /// The checks of the settings shared by every body, once for all (and so even for no
    /// body): the output times `t`, the method's settings, `max_steps`, the torque, the
    /// rotors.
    fn check(&self, t: &[f64]) -> Result<()> {
        if t.is_empty() {
            return Err(Error::Shape {
                name: "t".into(),
                expected: "(M,) with M >= 1".into(),
                got: "(0,)".into(),
            });
        }
        check_times(t, self.t0)?;
        let options = Options {
            max_steps: self.max_steps,
            ..Options::default()
        };
        check_method(&self.method, &options)?;
        if let (Method::Exact, Some(_)) = (&self.method, &self.torque) {
            return Err(Error::InvalidArgument {
                name: "torque".into(),
                reason: "the exact solution is torque-free; use dop853 or another integrator."
                    .into(),
            });
        }
        if let Some(torque) = &self.torque {
            torque.check()?;
        }
        if !self.rotors.is_empty() {
            check_rotor_method(&self.method)?;
            check_rotors(&self.rotors)?;
        }
        Ok(())
    }
}

/// The rotors' own parameters, once for all bodies (the body is checked with each), each
/// error naming `rotors[k].field`.
fn check_rotors(rotors: &[RotorSpec]) -> Result<()> {
    for (k, rotor) in rotors.iter().enumerate() {
        rotor
            .check()
            .map_err(|e| e.map_name(|name| format!("rotors[{k}].{name}")))?;
    }
    Ok(())
}

/// Whether [`simulate`] (with [`Simulation::parallel`]) spreads the output times of each body
/// over the rayon pool: for the exact solution at more than a few thousand output times
/// (each output depends on its time alone, so the numbers are the same bit for bit).
#[must_use]
pub fn spreads_times(method: &Method, m: usize) -> bool {
    matches!(method, Method::Exact) && m > EXACT_CHUNK
}

/// Integrates N bodies from their initial angular velocities (body axes) and orientations to
/// the output times `t` (finite, non-decreasing, `>= run.t0`), each in its principal axes,
/// and reports every [`Quantity`] in its own axes.
///
/// `bodies` and `orientation0` hold one entry shared by all or one per body (`omega0` sets N).
/// Each body is integrated on its own, so a body's numbers are the same bit for bit alone or
/// in a batch of any size, whatever the number of threads. On failure, the error of the first
/// failing body by index, wrapped in [`Error::Body`] when N > 1. A cancelled `monitor` stops
/// the run with [`Error::Interrupted`].
pub fn simulate(
    run: &Simulation,
    bodies: &[Body],
    omega0: &[Vector3<f64>],
    orientation0: &[UnitQuaternion<f64>],
    t: &[f64],
    monitor: Option<&Monitor>,
) -> Result<Outputs> {
    let n = omega0.len();
    one_or_each(bodies.len(), orientation0.len(), n)?;
    run.check(t)?;
    let rotors = run.rotors.len();
    let layout = Layout::new(run.with_orientation, rotors, t);
    let mut outputs = Outputs::zeroed(n, &layout)?;
    let ctx = Context {
        run,
        bodies,
        omega0,
        orientation0,
        layout,
        monitor,
        failures: crate::monitor::Failures::new(),
    };
    if rotors == 0 {
        runner::run(&RigidBody, &ctx, &mut outputs)?;
    } else {
        runner::run(
            &WithRotors {
                rotors: &run.rotors,
            },
            &ctx,
            &mut outputs,
        )?;
    }
    Ok(outputs)
}

/// That `bodies` bodies and `orientations` orientations go with `n` initial angular
/// velocities: one shared by all, or one per body; a [`Error::Shape`] naming the argument.
pub(crate) fn one_or_each(bodies: usize, orientations: usize, n: usize) -> Result<()> {
    for (name, len) in [("body", bodies), ("orientation0", orientations)] {
        if len != 1 && len != n {
            return Err(Error::Shape {
                name: name.into(),
                expected: format!("one, or one per body ({n})"),
                got: len.to_string(),
            });
        }
    }
    Ok(())
}

/// [`simulate`] of one body by `dop853`, reporting it at the output times `t` and at the end
/// of every accepted step, in time order (a step that ends at an output time reported once):
/// the times, and the outputs at them. The steps are those of the run to `t`'s last time
/// (output times do not change them: `dop853` reaches them by its dense output), so the
/// outputs at the output times are [`simulate`]'s, bit for bit.
///
/// ```
/// use nalgebra::{UnitQuaternion, Vector3};
/// use polhode::dynamics::{Dop853Options, Method};
/// use polhode::simulation::{simulate, simulate_every_step, Body, Simulation};
///
/// let run = Simulation::new(Method::Dop853(Dop853Options::default()));
/// let body = Body::Moments(Vector3::new(1.0, 2.0, 3.0));
/// let (w0, q0) = (Vector3::new(0.1, 1.0, 0.1), UnitQuaternion::identity());
/// let (times, out) = simulate_every_step(&run, &body, &w0, &q0, &[0.0, 5.0], None)?;
/// assert!(times.len() > 2 && times[0] == 0.0 && times[times.len() - 1] == 5.0);
/// let ends = simulate(&run, &[body], &[w0], &[q0], &[0.0, 5.0], None)?;
/// let last = 3 * (times.len() - 1);
/// assert_eq!(&out.column("omega").unwrap()[last..], &ends.column("omega").unwrap()[3..]);
/// # Ok::<(), polhode::Error>(())
/// ```
///
/// # Errors
/// Those of [`simulate`]; a method other than `dop853` is an error naming `method`.
pub fn simulate_every_step(
    run: &Simulation,
    body: &Body,
    omega0: &Vector3<f64>,
    orientation0: &UnitQuaternion<f64>,
    t: &[f64],
    monitor: Option<&Monitor>,
) -> Result<(Vec<f64>, Outputs)> {
    run.check(t)?;
    if !matches!(run.method, Method::Dop853(_)) {
        return Err(Error::InvalidArgument {
            name: "method".into(),
            reason: format!(
                "every accepted step is reported for \"dop853\" only, not {:?} (a fixed-step \
                 method steps where its output times say).",
                run.method.name()
            ),
        });
    }
    let (bodies, omega0, orientation0) = ([*body], [*omega0], [*orientation0]);
    let ctx = Context {
        run,
        bodies: &bodies,
        omega0: &omega0,
        orientation0: &orientation0,
        layout: Layout::new(run.with_orientation, run.rotors.len(), t),
        monitor,
        failures: crate::monitor::Failures::new(),
    };
    if run.rotors.is_empty() {
        runner::every_step(&RigidBody, &ctx)
    } else {
        runner::every_step(
            &WithRotors {
                rotors: &run.rotors,
            },
            &ctx,
        )
    }
}

/// Checks one body, its initial angular velocity and its rotors as [`simulate`] checks them,
/// with the same errors, and computes nothing else: the body (its moments, or its tensor or
/// mass properties and their principal axes), a finite `omega0` with a finite kinetic
/// energy, the rotors' parameters and their spinning inertia inside the body's, and the
/// rotors' momentum and energy at the start.
///
/// ```
/// use nalgebra::Vector3;
/// use polhode::simulation::{check_motion, Body};
///
/// let body = Body::Moments(Vector3::new(1.0, 2.0, 3.0));
/// assert!(check_motion(&body, &Vector3::new(0.1, 1.0, 0.1), &[]).is_ok());
/// let rod = Body::Moments(Vector3::new(0.0, 1.0, 1.0));
/// assert_eq!(check_motion(&rod, &Vector3::new(0.1, 1.0, 0.1), &[]).unwrap_err().argument(), Some("body"));
/// ```
pub fn check_motion(body: &Body, omega0: &Vector3<f64>, rotors: &[RotorSpec]) -> Result<()> {
    check_rotors(rotors)?;
    let job = Job::new(body, None, omega0, &UnitQuaternion::identity())?;
    if !rotors.is_empty() {
        let gyrostat = Gyrostat::new(job.moments.moments(), &job.axes(), rotors)?;
        gyrostat.start(&job.state.omega)?;
    }
    Ok(())
}
