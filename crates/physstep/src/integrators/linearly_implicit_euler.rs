//! Linearly implicit Euler: backward Euler's equation linearised at the start of the step and
//! solved once (Baraff and Witkin, "Large steps in cloth simulation", 1998).

use super::newton::Newton;
use super::{ConstraintMode, ImplicitParams, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Linearly implicit (semi-implicit, Rosenbrock-Euler) Euler: one Newton update of backward
/// Euler's `y[n+1] = y[n] + dt f(t[n+1], y[n+1])` from `y[n]`, with the Jacobian `J` at
/// `y[n]`: `y[n+1] = y[n] + (I - dt J)^-1 dt f(y[n])`. For a second-order system it is Baraff
/// and Witkin's step, `(M - dt D - dt^2 K) dv = dt (F + dt K v)`, `x += dt (v + dv)`, solved
/// by the same sparse conjugate gradients as backward Euler on large worlds.
///
/// One linear solve a step, where backward Euler iterates to [`ImplicitParams::tol`]: on
/// linear forces the two are the same step (exact arithmetic aside); on nonlinear forces it is
/// not the converged implicit step, and gives up its guarantees there (it is still first
/// order). Stable at any dt on linear springs and drains energy like backward Euler.
#[derive(Debug, Clone)]
pub struct LinearlyImplicitEuler {
    newton: Newton,
}

impl Default for LinearlyImplicitEuler {
    fn default() -> Self {
        Self::with_params(ImplicitParams::default())
    }
}

impl LinearlyImplicitEuler {
    /// With the given linear-solver settings (the Newton tolerance and iteration cap are not
    /// used: one update is taken).
    #[must_use]
    pub fn with_params(params: ImplicitParams) -> Self {
        let mut newton = Newton::new(params);
        newton.linear = true;
        Self { newton }
    }

    /// What the latest step's solve did (one update; the residual is that of backward
    /// Euler's equation at the new state, for information).
    #[must_use]
    pub fn stats(&self) -> super::SolveStats {
        self.newton.stats
    }
}

impl Method for LinearlyImplicitEuler {
    const INFO: Info = Info {
        name: "linearly-implicit-euler",
        order: 1,
        symplectic: false,
        implicit: true,
        evals: 2,
        split: false,
        vector_positions: false,
        local: false,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "backward Euler linearised at the step's start: one linear solve (Baraff-Witkin); stable on linear springs",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        self.newton.euler_step(s, Self::INFO.name)
    }

    fn solve_stats(&self) -> Option<super::SolveStats> {
        Some(self.stats())
    }
}
