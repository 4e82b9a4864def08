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
        /// The rigid body that entry belongs to.
        body: Option<usize>,
        /// The solid (a body of the contact solver) that diverged.
        solid: Option<usize>,
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
    /// A quantity derived from a finite state (the energy) is not finite: the run cannot be
    /// reported faithfully past this point.
    NonFinite {
        /// The method.
        method: String,
        /// What is not finite (`energy`).
        quantity: String,
        /// Its value.
        value: f64,
        /// Steps taken when it was seen.
        step: u64,
        /// Time then, s.
        t: f64,
    },
    /// A user force failed (its own error, or a wrong shape or a non-finite value); the step
    /// that asked was rolled back.
    Force {
        /// The force's name.
        name: String,
        /// What went wrong.
        reason: String,
        /// Whether the force returned a non-finite value (the state ran away under it: a
        /// divergence) rather than failing by itself (an error, a wrong shape).
        non_finite: bool,
    },
    /// The contacts of a step did not end within the stage's budget of collisions (balls
    /// pressed together, or one so fast it hits the walls that often in a step); the step
    /// was rolled back.
    Contacts {
        /// The method.
        method: String,
        /// Index of the step.
        step: u64,
        /// Simulation time at the start of the step, s.
        t: f64,
        /// The budget of collisions that was used up.
        contacts: u64,
    },
    /// A stop was requested ([`crate::interrupt::request`], Ctrl-C) while a call took its
    /// steps: the step under way was rolled back, the steps before it stay taken.
    Interrupted {
        /// Steps taken by the world when it stopped.
        step: u64,
    },
    /// Serialised state that cannot be read back (snapshot from another world or corrupted).
    Corrupt {
        /// What was wrong.
        reason: String,
    },
    /// A scene file that cannot be loaded: where, which field, and what was expected.
    SceneFile {
        /// The file as the user named it.
        file: String,
        /// Line of the bad value (1-based; 0 when the file could not be read at all).
        line: usize,
        /// The field, as a path into the file (`particles[2].mass`).
        field: String,
        /// What is wrong and what was expected, with the value.
        reason: String,
    },
}

impl Error {
    /// Shorthand for [`Error::InvalidValue`]. A value that is a number written in more than
    /// 17 characters (`1e308` displayed as 309 digits) is shown as [`num`] shows it, with an
    /// exponent.
    #[must_use]
    pub fn invalid(field: impl Into<String>, value: impl fmt::Display, expected: impl Into<String>) -> Self {
        let mut value = value.to_string();
        if value.len() > 17 {
            if let Ok(v) = value.parse::<f64>() {
                value = num(v);
            }
        }
        Self::InvalidValue { field: field.into(), value, expected: expected.into() }
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

impl Error {
    /// Whether this is a step that failed (diverged, did not converge, or left a non-finite
    /// derived quantity), as opposed to bad input.
    #[must_use]
    pub fn is_step_failure(&self) -> bool {
        matches!(
            self,
            Self::Diverged { .. }
                | Self::NotConverged { .. }
                | Self::Contacts { .. }
                | Self::NonFinite { .. }
                | Self::Force { non_finite: true, .. }
        )
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidValue { field, value, expected } => {
                write!(f, "invalid {} = {}: must be {expected}", one_line(field), one_line(value))
            }
            Self::UnknownName { kind, name, valid } => {
                // Escaped, so a name with a newline or a quote still makes one line.
                write!(f, "unknown {kind} '{}'; valid {kind}s: {}", one_line(name), valid.join(", "))
            }
            Self::Unsupported { method, reason } => write!(f, "method '{method}' {reason}"),
            Self::Diverged { method, step, t, index, particle, body, solid } => {
                write!(f, "method '{method}' diverged at step {step} (t = {}): ", num(*t))?;
                if let Some(s) = solid {
                    return write!(
                        f,
                        "solid {s} became non-finite or ran away (|value| > 1e100); state rolled back"
                    );
                }
                match (particle, body) {
                    (Some(p), _) => write!(
                        f,
                        "particle {p} became non-finite or ran away (|value| > 1e100); state rolled back"
                    ),
                    (None, Some(b)) => write!(
                        f,
                        "body {b} became non-finite or ran away (|value| > 1e100); state rolled back"
                    ),
                    (None, None) => write!(
                        f,
                        "coordinate {index} became non-finite or ran away (|value| > 1e100); state rolled back"
                    ),
                }
            }
            Self::NotConverged { method, iterations, residual } => write!(
                f,
                "method '{method}': Newton iteration did not converge in {iterations} iterations (residual {residual:e}); state rolled back"
            ),
            Self::NonFinite { method, quantity, value, step, t } => write!(
                f,
                "method '{method}' diverged: the {quantity} is {} after step {step} (t = {}); the run stops there",
                num(*value),
                num(*t)
            ),
            Self::Force { name, reason, .. } => {
                write!(f, "force '{}' failed: {}; step rolled back", one_line(name), one_line(reason))
            }
            Self::Contacts { method, step, t, contacts } => write!(
                f,
                "method '{method}': the contacts of step {step} (t = {}) did not end within {contacts} collisions (balls pressed together, or a ball fast enough to hit the walls that often in one step: try a smaller dt); state rolled back",
                num(*t)
            ),
            Self::Interrupted { step } => {
                write!(f, "interrupted after step {step}; the step under way was rolled back")
            }
            Self::Corrupt { reason } => write!(f, "corrupt snapshot: {reason}"),
            Self::SceneFile { file, line, field, reason } => {
                let at = if *line > 0 { format!(":{line}") } else { String::new() };
                let field = if field.is_empty() { String::new() } else { format!(" {}:", one_line(field)) };
                write!(f, "scene file {}{at}:{field} {}", one_line(file), one_line(reason))
            }
        }
    }
}

impl std::error::Error for Error {}

/// Result with the engine's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// `s` on one line: control characters (a newline in a name) shown as escapes (`\n`), the
/// rest as it is, so every message stays one line.
#[must_use]
pub fn one_line(s: &str) -> String {
    s.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

/// A number as messages show it: plain where that is short (`0.25`, `-3`, `1000`), with an
/// exponent where plain digits would run long (`1e-300`, `2.5e20`), NaN and inf as words.
#[must_use]
pub fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Checks that `value` is finite, naming `field` otherwise.
///
/// # Errors
/// [`Error::InvalidValue`] when `value` is NaN or infinite.
pub fn finite(field: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::invalid(field, num(value), "finite"))
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
        Err(Error::invalid(field, num(value), "a finite number > 0"))
    }
}

/// Checks that every entry of `values` is finite, naming `field[i]` of the first that is not.
///
/// # Errors
/// [`Error::InvalidValue`] for the first non-finite entry.
pub fn all_finite(field: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::invalid(format!("{field}[{i}]"), num(values[i]), "finite")),
    }
}

/// Checks that every entry of `values` is finite and at most `limit` in magnitude, naming
/// `field[i]` of the first that is not.
///
/// # Errors
/// [`Error::InvalidValue`] for the first entry out of range.
pub fn bounded(field: &str, values: &[f64], limit: f64) -> Result<()> {
    match values.iter().position(|v| v.is_nan() || v.abs() > limit) {
        None => Ok(()),
        Some(i) => Err(Error::invalid(
            format!("{field}[{i}]"),
            num(values[i]),
            format!("finite, at most {} in magnitude", num(limit)),
        )),
    }
}
