//! First-order flows `y' = f(t, y)`: the notes' strange attractors and the user's own.
//!
//! A flow is the second part a world can hold (particles are the first): the flow methods
//! (Euler, midpoint, Heun, RK4, the implicit ones) integrate it, the split methods refuse it
//! when the world is configured. The attractors are a closed enum with analytic Jacobians;
//! a user flow is a [`FlowGenerator`] trait object.

use crate::dynamics::FirstOrder;
use crate::error::{Error, Result};
use std::fmt;
use std::sync::Arc;

/// A first-order flow written by the user.
pub trait FlowGenerator: Send + Sync {
    /// A name for messages.
    fn name(&self) -> &str {
        "user flow"
    }

    /// Fills `dy` with `f(t, y)`.
    ///
    /// # Errors
    /// Any message: the step that asked is rolled back and fails with [`Error::Force`]
    /// naming the flow.
    fn deriv(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String>;

    /// Fills `df/dy` (row-major, zeroed by the caller) and returns `true`; `false` (the
    /// default) lets the implicit methods use finite differences.
    fn jacobian(&self, t: f64, y: &[f64], dfdy: &mut [f64]) -> bool {
        let _ = (t, y, dfdy);
        false
    }
}

/// The flow of a world.
#[derive(Clone)]
pub enum Flow {
    /// Lorenz: `x' = sigma (y - x)`, `y' = x (rho - z) - y`, `z' = x y - beta z`.
    Lorenz {
        /// Prandtl number (10).
        sigma: f64,
        /// Rayleigh number (28).
        rho: f64,
        /// Geometry factor (8/3).
        beta: f64,
    },
    /// Rossler: `x' = -y - z`, `y' = x + a y`, `z' = b + z (x - c)`.
    Rossler {
        /// 0.2.
        a: f64,
        /// 0.2.
        b: f64,
        /// 5.7.
        c: f64,
    },
    /// Thomas: `x' = sin y - b x`, `y' = sin z - b y`, `z' = sin x - b z`.
    Thomas {
        /// Dissipation (0.208186).
        b: f64,
    },
    /// The user's flow on `n` coordinates.
    User {
        /// Its length.
        n: usize,
        /// The flow.
        generator: Arc<dyn FlowGenerator>,
    },
}

impl fmt::Debug for Flow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Lorenz { sigma, rho, beta } => write!(f, "Lorenz({sigma}, {rho}, {beta})"),
            Self::Rossler { a, b, c } => write!(f, "Rossler({a}, {b}, {c})"),
            Self::Thomas { b } => write!(f, "Thomas({b})"),
            Self::User { n, generator } => write!(f, "User({:?}, {n})", generator.name()),
        }
    }
}

impl Flow {
    /// Coordinates of the state.
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            Self::User { n, .. } => *n,
            _ => 3,
        }
    }

    /// Whether the flow has no coordinates.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Checks the flow's parameters.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming a parameter that is not finite, or a user flow of
    /// length 0.
    pub fn validate(&self) -> Result<()> {
        let fin = |name: &str, v: f64| crate::error::finite(name, v).map(|_| ());
        match self {
            Self::Lorenz { sigma, rho, beta } => {
                fin("sigma", *sigma)?;
                fin("rho", *rho)?;
                fin("beta", *beta)
            }
            Self::Rossler { a, b, c } => {
                fin("a", *a)?;
                fin("b", *b)?;
                fin("c", *c)
            }
            Self::Thomas { b } => fin("b", *b),
            Self::User { n, .. } if *n == 0 => Err(Error::invalid("len(y0)", 0, "at least 1")),
            Self::User { .. } => Ok(()),
        }
    }

    /// A name for messages.
    #[must_use]
    pub fn name(&self) -> &str {
        match self {
            Self::Lorenz { .. } => "lorenz",
            Self::Rossler { .. } => "rossler",
            Self::Thomas { .. } => "thomas",
            Self::User { generator, .. } => generator.name(),
        }
    }
}

/// A flow as the world integrates it: the [`FirstOrder`] system, with the first failure of
/// a user flow kept for the world to report (the derivative is poisoned with NaN so the step
/// fails and is rolled back).
#[derive(Debug, Clone)]
pub struct FlowModel {
    /// The flow.
    pub flow: Flow,
    pub(crate) failure: Option<Error>,
}

impl FlowModel {
    /// A model of `flow`.
    #[must_use]
    pub fn new(flow: Flow) -> Self {
        Self { flow, failure: None }
    }
}

impl FirstOrder for FlowModel {
    fn len(&self) -> usize {
        self.flow.len()
    }

    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        match &self.flow {
            Flow::Lorenz { sigma, rho, beta } => {
                dy[0] = sigma * (y[1] - y[0]);
                dy[1] = y[0] * (rho - y[2]) - y[1];
                dy[2] = y[0] * y[1] - beta * y[2];
            }
            Flow::Rossler { a, b, c } => {
                dy[0] = -y[1] - y[2];
                dy[1] = y[0] + a * y[1];
                dy[2] = b + y[2] * (y[0] - c);
            }
            Flow::Thomas { b } => {
                dy[0] = y[1].sin() - b * y[0];
                dy[1] = y[2].sin() - b * y[1];
                dy[2] = y[0].sin() - b * y[2];
            }
            Flow::User { generator, .. } => {
                let r = generator.deriv(t, y, dy).map_err(|reason| (reason, false)).and_then(|()| {
                    match dy.iter().position(|c| !c.is_finite()) {
                        None => Ok(()),
                        Some(i) => Err((format!("dy[{i}] = {} is not finite", dy[i]), true)),
                    }
                });
                if let Err((reason, non_finite)) = r {
                    if self.failure.is_none() {
                        let name = generator.name().to_string();
                        self.failure = Some(Error::Force { name, reason, non_finite });
                    }
                    dy.fill(f64::NAN);
                }
            }
        }
    }

    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64]) -> bool {
        let mut set = |rows: [[f64; 3]; 3]| {
            for (r, row) in rows.iter().enumerate() {
                j[r * 3..r * 3 + 3].copy_from_slice(row);
            }
            true
        };
        match &self.flow {
            Flow::Lorenz { sigma, rho, beta } => {
                set([[-sigma, *sigma, 0.0], [rho - y[2], -1.0, -y[0]], [y[1], y[0], -beta]])
            }
            Flow::Rossler { a, c, .. } => set([[0.0, -1.0, -1.0], [1.0, *a, 0.0], [y[2], 0.0, y[0] - c]]),
            Flow::Thomas { b } => set([[-b, y[1].cos(), 0.0], [0.0, -b, y[2].cos()], [y[0].cos(), 0.0, -b]]),
            Flow::User { generator, .. } => generator.jacobian(t, y, j),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attractor_jacobians_match_finite_differences() {
        let flows = [
            Flow::Lorenz { sigma: 10.0, rho: 28.0, beta: 8.0 / 3.0 },
            Flow::Rossler { a: 0.2, b: 0.2, c: 5.7 },
            Flow::Thomas { b: 0.208_186 },
        ];
        let y = [1.3, -0.7, 2.1];
        for flow in flows {
            let mut m = FlowModel::new(flow.clone());
            let mut j = [0.0; 9];
            assert!(m.jacobian(0.0, &y, &mut j));
            let mut f0 = [0.0; 3];
            m.deriv(0.0, &y, &mut f0);
            for col in 0..3 {
                let (mut yp, mut ym) = (y, y);
                let h = 1e-6;
                yp[col] += h;
                ym[col] -= h;
                let (mut fp, mut fm) = ([0.0; 3], [0.0; 3]);
                m.deriv(0.0, &yp, &mut fp);
                m.deriv(0.0, &ym, &mut fm);
                for row in 0..3 {
                    let fd = (fp[row] - fm[row]) / (2.0 * h);
                    assert!((fd - j[row * 3 + col]).abs() < 1e-6, "{flow:?} [{row}][{col}]");
                }
            }
        }
    }
}
