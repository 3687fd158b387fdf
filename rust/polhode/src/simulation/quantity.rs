//! The outputs of [`super::simulate`]: one table of quantities, each with its name, shape,
//! unit, frame, description and the computation of its numbers from a body's state at one
//! output time.
//!
//! Adding an output is its row here (an associated constant of [`Quantity`], with its
//! computation from a [`Sample`], and its name in the `table!`), and a test: the runner writes
//! every quantity of the table, and the Python binding builds its output dict and
//! `polhode._core.QUANTITIES` from it.

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use super::job::Job;
use crate::dynamics::Gyrostat;

/// A dimension of a quantity's shape at one output time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// A fixed size.
    Fixed(usize),
    /// The number of rotors of the run.
    Rotors,
}

impl Dim {
    /// Its size in a run with `rotors` rotors.
    #[must_use]
    pub fn size(self, rotors: usize) -> usize {
        match self {
            Dim::Fixed(n) => n,
            Dim::Rotors => rotors,
        }
    }
}

/// The axes a quantity's components are in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// The body's own axes (those it was given in), rotating with it.
    Body,
    /// The inertial (space) axes.
    Space,
    /// None: a scalar, or a rotation (the quaternion maps body to space).
    None,
}

impl Frame {
    /// Its name: `"body"`, `"space"` or `"none"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Frame::Body => "body",
            Frame::Space => "space",
            Frame::None => "none",
        }
    }
}

/// A quantity reported at each output time: a row of the table [`Quantity::ALL`].
#[derive(Clone, Copy)]
pub struct Quantity {
    name: &'static str,
    shape: &'static [Dim],
    unit: &'static str,
    frame: Frame,
    description: &'static str,
    needs_orientation: bool,
    needs_rotors: bool,
    /// Writes its numbers at one output time (its width of them) from a sample, and returns
    /// their sum (see [`put`]).
    write: fn(&Sample, &mut [f64]) -> f64,
}

impl Quantity {
    /// Angular velocity in the body's axes.
    pub const OMEGA: Quantity = Quantity {
        name: "omega",
        shape: &[Dim::Fixed(3)],
        unit: "rad/s",
        frame: Frame::Body,
        description: "angular velocity, body axes",
        needs_orientation: false,
        needs_rotors: false,
        write: |s, out| put(out, s.omega.as_slice()),
    };

    /// Body-to-space orientation as a scalar-last quaternion `(x, y, z, w)`, continuous in
    /// time (`q` and `-q` are one rotation: the sign follows the previous output).
    pub const QUATERNION: Quantity = Quantity {
        name: "quaternion",
        shape: &[Dim::Fixed(4)],
        unit: "1",
        frame: Frame::None,
        description: "body-to-space orientation, scalar-last quaternion (x, y, z, w), its sign continuous in time",
        needs_orientation: true,
        needs_rotors: false,
        write: |s, out| match &s.quaternion {
            Some(q) => put(out, &[q.i, q.j, q.k, q.w]),
            None => 0.0,
        },
    };

    /// Angular velocity in space (inertial) axes: `R omega`.
    pub const OMEGA_SPACE: Quantity = Quantity {
        name: "omega_space",
        shape: &[Dim::Fixed(3)],
        unit: "rad/s",
        frame: Frame::Space,
        description: "angular velocity, space axes",
        needs_orientation: true,
        needs_rotors: false,
        // R_b omega_b = R_p omega_p: the same vector, from the principal axes' state.
        write: |s, out| match s.orientation_p {
            Some(q) => put(out, (q * s.omega_p).as_slice()),
            None => 0.0,
        },
    };

    /// Angular momentum in space axes: conserved without torque. With rotors, the total.
    pub const ANGULAR_MOMENTUM_SPACE: Quantity = Quantity {
        name: "angular_momentum_space",
        shape: &[Dim::Fixed(3)],
        unit: "kg m^2/s",
        frame: Frame::Space,
        description:
            "angular momentum, space axes (conserved without torque); with rotors, the total",
        needs_orientation: true,
        needs_rotors: false,
        write: |s, out| match &s.momentum_space {
            Some(l) => put(out, l.as_slice()),
            None => 0.0,
        },
    };

    /// Angular momentum in the body's axes; with rotors, the total.
    pub const ANGULAR_MOMENTUM_BODY: Quantity = Quantity {
        name: "angular_momentum_body",
        shape: &[Dim::Fixed(3)],
        unit: "kg m^2/s",
        frame: Frame::Body,
        description: "angular momentum, body axes; with rotors, the total",
        needs_orientation: false,
        needs_rotors: false,
        write: |s, out| put(out, s.momentum.as_slice()),
    };

    /// Rotational kinetic energy; with rotors, the total.
    pub const ENERGY: Quantity = Quantity {
        name: "energy",
        shape: &[],
        unit: "J",
        frame: Frame::None,
        description: "rotational kinetic energy; with rotors, the total (their spin included)",
        needs_orientation: false,
        needs_rotors: false,
        write: |s, out| put(out, &[s.energy]),
    };

    /// Each rotor's angular velocity relative to the body, in the body's axes (only with
    /// rotors).
    pub const ROTOR_RATES: Quantity = Quantity {
        name: "rotor_rates",
        shape: &[Dim::Rotors, Dim::Fixed(3)],
        unit: "rad/s",
        frame: Frame::Body,
        description: "each rotor's angular velocity relative to the body, body axes (a wheel's along its axis)",
        needs_orientation: false,
        needs_rotors: true,
        write: |s, out| {
            let mut sum = 0.0;
            if let Some((gyrostat, vars)) = s.rotors {
                for (k, rate) in gyrostat.rotor_rates(s.omega_p, vars).iter().enumerate() {
                    let rate = match &s.job.frame {
                        Some(frame) => frame.matrix * rate,
                        None => *rate,
                    };
                    sum += put(&mut out[3 * k..3 * k + 3], rate.as_slice());
                }
            }
            sum
        },
    };

    /// The name users read (the Python `Trajectory` attribute).
    #[must_use]
    pub fn name(self) -> &'static str {
        self.name
    }

    /// Its shape at one output time, with the number of rotors as [`Dim::Rotors`] (empty for
    /// a scalar).
    #[must_use]
    pub fn dims(self) -> &'static [Dim] {
        self.shape
    }

    /// Its SI unit (`"1"` for a dimensionless quantity).
    #[must_use]
    pub fn unit(self) -> &'static str {
        self.unit
    }

    /// The axes its components are in.
    #[must_use]
    pub fn frame(self) -> Frame {
        self.frame
    }

    /// What it is, in one line.
    #[must_use]
    pub fn description(self) -> &'static str {
        self.description
    }

    /// The shape of its numbers at one output time, for a run with `rotors` rotors (empty for
    /// a scalar, which has no trailing axis).
    #[must_use]
    pub fn shape(self, rotors: usize) -> Vec<usize> {
        self.shape.iter().map(|d| d.size(rotors)).collect()
    }

    /// Numbers per output time, for a run with `rotors` rotors (1 for a scalar).
    #[must_use]
    #[inline]
    pub fn width(&self, rotors: usize) -> usize {
        self.shape.iter().map(|d| d.size(rotors)).product()
    }

    /// Whether it needs the orientation (absent without it).
    #[must_use]
    #[inline]
    pub fn needs_orientation(&self) -> bool {
        self.needs_orientation
    }

    /// Whether it needs rotors (absent without them).
    #[must_use]
    #[inline]
    pub fn needs_rotors(&self) -> bool {
        self.needs_rotors
    }
}

/// The table: every quantity, in the order of [`super::Outputs::columns`] (and of the fields
/// of Python's `Trajectory`). It defines [`Quantity::ALL`] and the writing of a row of every
/// quantity present ([`write_row`]), unrolled at compile time over the table.
macro_rules! table {
    ($($quantity:ident),* $(,)?) => {
        impl Quantity {
            /// Every quantity, in the order of [`super::Outputs::columns`] (and of the
            /// fields of Python's `Trajectory`).
            pub const ALL: [Quantity; [$(stringify!($quantity)),*].len()] =
                [$(Quantity::$quantity),*];
        }

        /// Writes every quantity of the table present in a run with or without the
        /// orientation and with or without rotors (`rotors` of them) at row `row` of
        /// `columns` (those of the quantities present, in order), and returns the sum of the
        /// numbers written: finite if every one is (unless the sum overflows). Unrolled
        /// over the table, each quantity's computation inlined with its width known: the
        /// stores of hand-written code.
        #[inline(always)]
        pub(crate) fn write_row<const ORIENTATION: bool, const ROTORS: bool>(
            sample: &Sample,
            columns: &mut [&mut [f64]],
            row: usize,
            rotors: usize,
        ) -> f64 {
            let mut column = 0;
            let mut probe = 0.0;
            $(
                probe += write_one::<ORIENTATION, ROTORS>(
                    &Quantity::$quantity, sample, columns, &mut column, row, rotors,
                );
            )*
            probe
        }
    };
}

table!(
    OMEGA,
    OMEGA_SPACE,
    QUATERNION,
    ANGULAR_MOMENTUM_SPACE,
    ANGULAR_MOMENTUM_BODY,
    ENERGY,
    ROTOR_RATES,
);

/// [`write_row`] for one quantity: written into `columns[*column]` (then the next column) if
/// the run has it.
#[inline(always)]
fn write_one<const ORIENTATION: bool, const ROTORS: bool>(
    quantity: &Quantity,
    sample: &Sample,
    columns: &mut [&mut [f64]],
    column: &mut usize,
    row: usize,
    rotors: usize,
) -> f64 {
    if (quantity.needs_orientation && !ORIENTATION) || (quantity.needs_rotors && !ROTORS) {
        return 0.0;
    }
    let w = quantity.width(rotors);
    let out = &mut columns[*column][row * w..(row + 1) * w];
    *column += 1;
    (quantity.write)(sample, out)
}

/// Writes `values` into `out` and returns their sum, formed from the values themselves (not
/// read back from the outputs, which would wait for the output's memory): finite if every
/// value is, unless the sum overflows.
#[inline(always)]
fn put(out: &mut [f64], values: &[f64]) -> f64 {
    out.copy_from_slice(values);
    values.iter().sum()
}

impl PartialEq for Quantity {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl Eq for Quantity {}

impl std::fmt::Debug for Quantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Quantity({:?})", self.name)
    }
}

/// One body's state at one output time, with what the quantities are computed from: the
/// state in the principal axes it was integrated in, and the values most quantities share,
/// each computed once (in the body's own axes).
pub(crate) struct Sample<'a> {
    /// The body's job (its moments and principal axes).
    pub(crate) job: &'a Job,
    /// The angular velocity, principal axes.
    pub(crate) omega_p: &'a Vector3<f64>,
    /// The principal axes' orientation, with the orientation.
    pub(crate) orientation_p: Option<&'a UnitQuaternion<f64>>,
    /// The gyrostat and its rotor variables, with rotors.
    pub(crate) rotors: Option<(&'a Gyrostat, &'a [f64])>,
    /// The angular velocity, body axes.
    pub(crate) omega: Vector3<f64>,
    /// The angular momentum (with rotors, the total), body axes.
    pub(crate) momentum: Vector3<f64>,
    /// The kinetic energy (with rotors, the total).
    pub(crate) energy: f64,
    /// With the orientation: the body's quaternion, its sign continuous with the previous
    /// output's (when the writer keeps track of it).
    pub(crate) quaternion: Option<Quaternion<f64>>,
    /// With the orientation: the angular momentum in space.
    pub(crate) momentum_space: Option<Vector3<f64>>,
}

impl<'a> Sample<'a> {
    /// The sample of `job` at `(omega_p, orientation_p)` (principal axes), with the rotors'
    /// variables if any. The quaternion's sign follows `previous` (the last quaternion
    /// written, updated) if given; without it the sign is settled afterwards.
    #[inline(always)]
    pub(crate) fn new(
        job: &'a Job,
        omega_p: &'a Vector3<f64>,
        orientation_p: Option<&'a UnitQuaternion<f64>>,
        rotors: Option<(&'a Gyrostat, &'a [f64])>,
        previous: Option<&mut Option<Quaternion<f64>>>,
    ) -> Self {
        // L in principal axes.
        let l = match rotors {
            Some((gyrostat, vars)) => gyrostat.angular_momentum(omega_p, vars),
            None => job.moments.moments().component_mul(omega_p),
        };
        let (omega, momentum) = match &job.frame {
            Some(frame) => (frame.matrix * omega_p, frame.matrix * l),
            None => (*omega_p, l),
        };
        let energy = match rotors {
            Some((gyrostat, vars)) => gyrostat.energy(omega_p, vars),
            None => 0.5 * omega_p.dot(&l),
        };
        let (quaternion, momentum_space) = match orientation_p {
            Some(q) => {
                // R_b = R_p V^T.
                let mut body = match &job.frame {
                    Some(frame) => (q * frame.rotation.inverse()).into_inner(),
                    None => q.into_inner(),
                };
                if let Some(previous) = previous {
                    // One sign per trajectory: continuous in time.
                    if previous.is_some_and(|p| p.coords.dot(&body.coords) < 0.0) {
                        body = -body;
                    }
                    *previous = Some(body);
                }
                (Some(body), Some(q * l))
            }
            None => (None, None),
        };
        Self {
            job,
            omega_p,
            orientation_p,
            rotors,
            omega,
            momentum,
            energy,
            quaternion,
            momentum_space,
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Quaternion, Rotation3, UnitQuaternion, Vector3};

    use crate::dynamics::Method;
    use crate::simulation::{simulate, Body, Simulation};

    #[test]
    fn omega_space_is_the_body_rate_turned_into_space() {
        // A tensor in non-principal axes, a torque-free run by the exact solution and by rk4:
        // omega_space = R(q) omega at every output time, from the outputs themselves.
        let r = Rotation3::from_euler_angles(0.3, -0.7, 1.1);
        let tensor =
            r.matrix() * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.5)) * r.transpose();
        let t: Vec<f64> = (0..=20).map(|k| 0.5 * f64::from(k)).collect();
        for method in [Method::Exact, Method::Rk4 { dt: 1e-3 }] {
            let out = simulate(
                &Simulation::new(method),
                &[Body::Inertia(tensor)],
                &[Vector3::new(0.2, 1.0, -0.3)],
                &[UnitQuaternion::identity()],
                &t,
                None,
            )
            .unwrap();
            let (w, q, ws) = (
                out.column("omega").unwrap(),
                out.column("quaternion").unwrap(),
                out.column("omega_space").unwrap(),
            );
            for j in 0..t.len() {
                let q = UnitQuaternion::from_quaternion(Quaternion::new(
                    q[4 * j + 3],
                    q[4 * j],
                    q[4 * j + 1],
                    q[4 * j + 2],
                ));
                let want = q * Vector3::from_column_slice(&w[3 * j..3 * j + 3]);
                let got = Vector3::from_column_slice(&ws[3 * j..3 * j + 3]);
                assert!(
                    (got - want).norm() <= 1e-14 * want.norm(),
                    "{method:?} t[{j}]"
                );
            }
        }
    }
}
