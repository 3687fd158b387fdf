//! The one error type of the core crate.

/// Everything that can go wrong in the core, each variant naming the argument at fault.
///
/// Messages follow the form ``Expected `name` to ..., got ...``, so that the Python layer can
/// pass them on unchanged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A number that must be finite is NaN or infinite.
    #[error("Expected `{name}` to be finite, got {}.", Short(*value))]
    NonFinite {
        /// The argument (or element, e.g. `positions[3]`) at fault.
        name: String,
        /// The offending value.
        value: f64,
    },
    /// A number that must be strictly positive is zero or negative.
    #[error("Expected `{name}` to be positive, got {}.", Short(*value))]
    NonPositive {
        /// The argument at fault.
        name: String,
        /// The offending value.
        value: f64,
    },
    /// An array has the wrong length or shape.
    #[error("Expected `{name}` to have shape {expected}, got {got}.")]
    Shape {
        /// The argument at fault.
        name: String,
        /// The shape that was expected, e.g. `(N, 3)`.
        expected: String,
        /// The shape that came.
        got: String,
    },
    /// A tensor that is not a valid inertia tensor (asymmetric, not positive semidefinite, or
    /// breaking the triangle inequality `I1 + I2 >= I3`).
    #[error("Expected `{name}` to be a valid inertia tensor: {reason}")]
    InvalidInertia {
        /// The argument at fault.
        name: String,
        /// What is wrong, with the numbers.
        reason: String,
    },
    /// Any other invalid argument.
    #[error("Invalid `{name}`: {reason}")]
    InvalidArgument {
        /// The argument at fault.
        name: String,
        /// What is wrong, with the numbers.
        reason: String,
    },
    /// An iterative method did not converge within its bounded number of iterations.
    #[error("{method} did not converge: {reason}")]
    NoConvergence {
        /// The method that failed.
        method: String,
        /// The argument that is the way out (`dt` of a fixed-step method, `max_steps`, or `t`
        /// for a solution that cannot be continued to the times asked for).
        name: String,
        /// What happened.
        reason: String,
    },
    /// The solution left double precision: a step far too long for the motion, or a motion
    /// that overflows.
    #[error("The solution blew up at t = {}: {what} is {}; {hint}", Short(*t), Short(*value))]
    BlewUp {
        /// The argument that is the way out (`dt` of a fixed-step method, else `t`).
        name: String,
        /// The output that is not finite, e.g. `omega[0]` or `the orientation`.
        what: String,
        /// What to do about it.
        hint: String,
        /// The time of that output.
        t: f64,
        /// Its value.
        value: f64,
    },
    /// The run was cancelled through its [`crate::Monitor`].
    #[error("The integration was interrupted (its monitor was cancelled).")]
    Interrupted,
    /// Memory whose size comes from the input could not be allocated (see
    /// [`crate::memory`]).
    #[error(
        "Cannot allocate {bytes:.3e} bytes for {}: {}",
        .purpose.what(),
        .purpose.instead()
    )]
    OutOfMemory {
        /// The size of the allocation (of all the outputs, for [`Purpose::Outputs`]).
        bytes: f64,
        /// What the memory was for.
        purpose: Purpose,
    },
    /// The error of one body of a batch.
    #[error("body {body}: {error}")]
    Body {
        /// The body's index in the batch.
        body: usize,
        /// What went wrong with it.
        error: Box<Error>,
    },
}

impl Error {
    /// The same error with the argument it names rewritten by `f` (e.g. to add an index or a
    /// body number); [`Error::Interrupted`] and [`Error::OutOfMemory`], which name nothing,
    /// are returned as they are.
    #[must_use]
    pub fn map_name(self, f: impl FnOnce(String) -> String) -> Self {
        match self {
            Error::NonFinite { name, value } => Error::NonFinite {
                name: f(name),
                value,
            },
            Error::NonPositive { name, value } => Error::NonPositive {
                name: f(name),
                value,
            },
            Error::Shape {
                name,
                expected,
                got,
            } => Error::Shape {
                name: f(name),
                expected,
                got,
            },
            Error::InvalidInertia { name, reason } => Error::InvalidInertia {
                name: f(name),
                reason,
            },
            Error::InvalidArgument { name, reason } => Error::InvalidArgument {
                name: f(name),
                reason,
            },
            Error::NoConvergence {
                method,
                name,
                reason,
            } => Error::NoConvergence {
                method,
                name: f(name),
                reason,
            },
            Error::BlewUp {
                name,
                what,
                hint,
                t,
                value,
            } => Error::BlewUp {
                name: f(name),
                what,
                hint,
                t,
                value,
            },
            Error::Interrupted => Error::Interrupted,
            Error::OutOfMemory { bytes, purpose } => Error::OutOfMemory { bytes, purpose },
            Error::Body { body, error } => Error::Body {
                body,
                error: Box::new(error.map_name(f)),
            },
        }
    }

    /// The error of body `body` of a batch ([`Error::Interrupted`] and
    /// [`Error::OutOfMemory`], which concern the whole run, are returned as they are).
    #[must_use]
    pub fn in_body(self, body: usize) -> Self {
        match self {
            Error::Interrupted | Error::OutOfMemory { .. } => self,
            error => Error::Body {
                body,
                error: Box::new(error),
            },
        }
    }

    /// The argument at fault: the name up to its first index, field, list or note (`t` for
    /// `t[3]`, `omega0` for `omega0[1]`, `start` for `start, end`), or `None` for an error
    /// that names none.
    #[must_use]
    pub fn argument(&self) -> Option<&str> {
        let name = match self {
            Error::NonFinite { name, .. }
            | Error::NonPositive { name, .. }
            | Error::Shape { name, .. }
            | Error::InvalidInertia { name, .. }
            | Error::InvalidArgument { name, .. }
            | Error::NoConvergence { name, .. }
            | Error::BlewUp { name, .. } => name,
            Error::Body { error, .. } => return error.argument(),
            Error::Interrupted | Error::OutOfMemory { .. } => return None,
        };
        let end = name.find(['[', ' ', '.', '(', ',']).unwrap_or(name.len());
        Some(&name[..end])
    }
}

/// A number in a message: the shortest decimal that reads back as it, in scientific notation
/// when it is very large or very small (`1e300`, not 301 digits).
#[derive(Clone, Copy, Debug)]
pub struct Short(pub f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if v != 0.0 && v.is_finite() && !(1e-5..1e16).contains(&v.abs()) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}

/// `Result` with the core [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Checks that `value` is finite.
pub(crate) fn finite(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NonFinite {
            name: name.to_owned(),
            value,
        })
    }
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &str, value: f64) -> Result<f64> {
    finite(name, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(Error::NonPositive {
            name: name.to_owned(),
            value,
        })
    }
}

/// What memory that could not be allocated was for: the error names it and says what to ask
/// for instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Purpose {
    /// The outputs of a simulation (every quantity at every output time of every body).
    Outputs,
    /// A batch's bodies, initial angular velocities and orientations, as the core reads them.
    Bodies,
    /// The principal moments, axes and multiplicities of a batch of tensors.
    PrincipalAxes,
    /// The inertia tensors of the frames of a point-mass trajectory.
    FrameTensors,
    /// The partial sums of many point masses.
    PointMasses,
    /// The working memory of a mesh's mass properties and of its closedness check (a copy of
    /// the vertices, the directed edges, the merged vertices).
    Mesh,
    /// The merged vertices and renumbered faces of a mesh file.
    MergedMesh,
    /// A C-contiguous copy of an input array given with other strides.
    Input,
}

impl Purpose {
    /// What the memory is for, as the error says it.
    #[must_use]
    pub fn what(self) -> &'static str {
        match self {
            Purpose::Outputs => "the outputs",
            Purpose::Bodies => "the bodies of the batch",
            Purpose::PrincipalAxes => "the principal moments, axes and multiplicities",
            Purpose::FrameTensors => "the inertia tensors of the frames",
            Purpose::PointMasses => "the sums of the point masses",
            Purpose::Mesh => "the working memory of the mesh",
            Purpose::MergedMesh => "the merged vertices and faces of the mesh",
            Purpose::Input => "a C-contiguous copy of the input",
        }
    }

    /// What to ask for instead, as the error says it.
    #[must_use]
    pub fn instead(self) -> &'static str {
        match self {
            Purpose::Outputs => {
                "ask for fewer output times or bodies, without the orientation, or in chunks \
                 (polhode.dask)."
            }
            Purpose::Bodies => "simulate fewer bodies at a time, or in chunks (polhode.dask).",
            Purpose::PrincipalAxes => "pass fewer tensors at a time (slices of the batch).",
            Purpose::FrameTensors => "pass fewer frames at a time (slices of the trajectory).",
            Purpose::PointMasses => "pass the points in parts and add their bodies (Body + Body).",
            Purpose::Mesh | Purpose::MergedMesh => {
                "use a mesh with fewer faces and vertices (decimated), or free memory."
            }
            Purpose::Input => {
                "pass C-contiguous float64 arrays (numpy.ascontiguousarray), or a smaller input."
            }
        }
    }

    /// The error for an allocation of `bytes` for this purpose.
    #[must_use]
    pub fn error(self, bytes: f64) -> Error {
        Error::OutOfMemory {
            bytes,
            purpose: self,
        }
    }
}
