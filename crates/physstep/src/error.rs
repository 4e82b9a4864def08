//! The one error type of the engine.
//!
//! Every public entry validates its input and answers with an [`Error`] whose message names
//! the bad field and its value, so the Python face and the command line can show it as is.

use std::fmt;

/// Everything that can go wrong in physstep.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A value is out of its allowed range (dt <= 0, mass <= 0, NaN, ...).
    InvalidValue {
        /// The field, as the user named it (`dt`, `mass`, `position[2]`, ...).
        field: String,
        /// The offending value, formatted.
        value: String,
        /// What the value must be.
        expected: String,
    },
    /// A name that is not in a registry (method, scene, parameter, force).
    UnknownName {
        /// What kind of name (`method`, `scene`, `param`).
        kind: String,
        /// The name given.
        name: String,
        /// The valid names, in registry order.
        valid: Vec<String>,
    },
    /// A method that cannot integrate this kind of system (a split method on a first-order flow).
    Unsupported {
        /// The method name.
        method: String,
        /// Why.
        reason: String,
    },
    /// A step produced a non-finite value; the state was rolled back to before the step.
    Diverged {
        /// The method that diverged.
        method: String,
        /// Index of the step (0 for the first step taken by this state).
        step: u64,
        /// Simulation time at the start of the failed step, s.
        t: f64,
        /// Index of the first non-finite entry of the state vector (`[x; v]` for a
        /// second-order system).
        index: usize,
        /// The particle that entry belongs to, where the system is a world of particles.
        particle: Option<usize>,
    },
    /// An implicit method's Newton iteration did not converge; the state was rolled back.
    NotConverged {
        /// The method.
        method: String,
        /// Iterations tried.
        iterations: u32,
        /// Final residual (max norm).
        residual: f64,
    },
    /// Serialised state that cannot be read back (snapshot from another world or corrupted).
    Corrupt {
        /// What was wrong.
        reason: String,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidValue`].
    #[must_use]
    pub fn invalid(field: impl Into<String>, value: impl fmt::Display, expected: impl Into<String>) -> Self {
        Self::InvalidValue { field: field.into(), value: value.to_string(), expected: expected.into() }
    }

    /// Shorthand for [`Error::UnknownName`].
    #[must_use]
    pub fn unknown<S: AsRef<str>>(kind: &str, name: &str, valid: impl IntoIterator<Item = S>) -> Self {
        Self::UnknownName {
            kind: kind.into(),
            name: name.into(),
            valid: valid.into_iter().map(|s| s.as_ref().to_string()).collect(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidValue { field, value, expected } => {
                write!(f, "invalid {field} = {value}: must be {expected}")
            }
            Self::UnknownName { kind, name, valid } => {
                write!(f, "unknown {kind} '{name}'; valid {kind}s: {}", valid.join(", "))
            }
            Self::Unsupported { method, reason } => write!(f, "method '{method}' {reason}"),
            Self::Diverged { method, step, t, index, particle } => {
                write!(f, "method '{method}' diverged at step {step} (t = {t}): ")?;
                match particle {
                    Some(p) => write!(f, "particle {p} became non-finite; state rolled back"),
                    None => write!(f, "coordinate {index} became non-finite; state rolled back"),
                }
            }
            Self::NotConverged { method, iterations, residual } => write!(
                f,
                "method '{method}': Newton iteration did not converge in {iterations} iterations (residual {residual:e}); state rolled back"
            ),
            Self::Corrupt { reason } => write!(f, "corrupt snapshot: {reason}"),
        }
    }
}

impl std::error::Error for Error {}

/// Result with the engine's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Checks that `value` is finite, naming `field` otherwise.
///
/// # Errors
/// [`Error::InvalidValue`] when `value` is NaN or infinite.
pub fn finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "finite"))
    }
}

/// Checks that `value` is finite and strictly positive, naming `field` otherwise.
///
/// # Errors
/// [`Error::InvalidValue`] when `value` is not a finite number > 0.
pub fn positive(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::invalid(field, value, "a finite number > 0"))
    }
}

/// Checks that every entry of `values` is finite, naming `field[i]` of the first that is not.
///
/// # Errors
/// [`Error::InvalidValue`] for the first non-finite entry.
pub fn all_finite(field: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::invalid(format!("{field}[{i}]"), values[i], "finite")),
    }
}
