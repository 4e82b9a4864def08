//! The state of an integrated system: time, the flat state `y` and its derivative `f`, the
//! step and evaluation counts.

use crate::dynamics::{First, FirstOrder, Second, SecondOrder, System};
use crate::error::{Error, Result};

/// Time and state of an integrated system, advanced by [`Integrator::step`](super::Integrator::step).
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time, s.
    pub t: f64,
    /// The state vector: `[x; v]` for a second-order system.
    pub y: Vec<f64>,
    /// The derivative at `(t, y)`: `[v; a]` for a second-order system.
    pub f: Vec<f64>,
    /// Steps taken.
    pub steps: u64,
    /// Derivative (force) evaluations made, initial one included.
    pub evals: u64,
}

impl State {
    /// The state of a second-order system at `t` from positions and velocities, evaluating
    /// the acceleration once.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] when the lengths disagree with the system or a value is not
    /// finite.
    pub fn second<S: SecondOrder + ?Sized>(sys: &mut S, t: f64, x: &[f64], v: &[f64]) -> Result<Self> {
        let n = sys.len();
        crate::error::finite("t", t)?;
        if x.len() != n {
            return Err(Error::invalid("len(x)", x.len(), format!("{n}, the system's coordinate count")));
        }
        if v.len() != n {
            return Err(Error::invalid("len(v)", v.len(), format!("{n}, the system's coordinate count")));
        }
        crate::error::all_finite("x", x)?;
        crate::error::all_finite("v", v)?;
        let mut y = Vec::with_capacity(2 * n);
        y.extend_from_slice(x);
        y.extend_from_slice(v);
        let mut f = vec![0.0; 2 * n];
        Second(sys).deriv(t, &y, &mut f);
        Ok(Self { t, y, f, steps: 0, evals: 1 })
    }

    /// The state of a first-order flow at `t`, evaluating the derivative once.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] when the length disagrees with the flow or a value is not
    /// finite.
    pub fn first<F: FirstOrder + ?Sized>(sys: &mut F, t: f64, y: &[f64]) -> Result<Self> {
        crate::error::finite("t", t)?;
        if y.len() != sys.len() {
            return Err(Error::invalid(
                "len(y)",
                y.len(),
                format!("{}, the flow's coordinate count", sys.len()),
            ));
        }
        crate::error::all_finite("y", y)?;
        let mut f = vec![0.0; y.len()];
        First(sys).deriv(t, y, &mut f);
        Ok(Self { t, y: y.to_vec(), f, steps: 0, evals: 1 })
    }

    /// Positions of a second-order state.
    #[must_use]
    pub fn x(&self) -> &[f64] {
        &self.y[..self.y.len() / 2]
    }

    /// Velocities of a second-order state.
    #[must_use]
    pub fn v(&self) -> &[f64] {
        &self.y[self.y.len() / 2..]
    }

    /// Accelerations of a second-order state.
    #[must_use]
    pub fn a(&self) -> &[f64] {
        &self.f[self.f.len() / 2..]
    }
}
