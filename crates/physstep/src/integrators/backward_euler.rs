//! Backward (implicit) Euler, solved by Newton iteration.

use super::newton::Newton;
use super::{ConstraintMode, ImplicitParams, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Backward Euler: `x[n+1] = x[n] + v[n+1] dt`, `v[n+1] = v[n] + a[n+1] dt`, i.e.
/// `y[n+1] = y[n] + dt f(t[n+1], y[n+1])`, solved by Newton iteration to
/// [`ImplicitParams::tol`]. First order, stable at every dt, and it drains energy from
/// every oscillator.
#[derive(Debug, Clone, Default)]
pub struct BackwardEuler {
    newton: Newton,
}

impl BackwardEuler {
    /// With the given Newton settings.
    #[must_use]
    pub fn with_params(params: ImplicitParams) -> Self {
        Self { newton: Newton::new(params) }
    }

    /// What the latest step's solve did.
    #[must_use]
    pub fn stats(&self) -> super::SolveStats {
        self.newton.stats
    }
}

impl Method for BackwardEuler {
    const INFO: Info = Info {
        name: "backward-euler",
        order: 1,
        symplectic: false,
        implicit: true,
        evals: 2,
        split: false,
        vector_positions: false,
        local: false,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "x += v_new dt; v += a_new dt, solved by Newton iteration; loses energy, stable at any dt",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        self.newton.euler_step(s, Self::INFO.name)
    }

    fn solve_stats(&self) -> Option<super::SolveStats> {
        Some(self.stats())
    }
}
