//! The implicit midpoint rule: symplectic, second order, stable at every dt.

use super::newton::Newton;
use super::{ConstraintMode, ImplicitParams, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Implicit midpoint: `y[n+1] = y[n] + dt f(t + dt/2, (y[n] + y[n+1]) / 2)`. Solved for the
/// midpoint `m = y[n] + dt/2 f(t + dt/2, m)` (a backward-Euler half step) by Newton
/// iteration, then `y[n+1] = 2 m - y[n]`. Conserves quadratic invariants exactly: the
/// spring's energy up to the Newton tolerance.
#[derive(Debug, Clone, Default)]
pub struct ImplicitMidpoint {
    newton: Newton,
}

impl ImplicitMidpoint {
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

impl Method for ImplicitMidpoint {
    const INFO: Info = Info {
        name: "implicit-midpoint",
        order: 2,
        symplectic: true,
        implicit: true,
        evals: 3,
        split: false,
        vector_positions: false,
        local: false,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "y += f((y + y_new)/2) dt, solved by Newton iteration; symplectic, stable at any dt",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let (y, f, mut flow) = s.flow();
        self.newton.solve(&mut flow, Self::INFO.name, t + 0.5 * h, 0.5 * h, y, f)?;
        for (yi, m) in s.y.iter_mut().zip(self.newton.z.iter()) {
            *yi = 2.0 * m - *yi;
        }
        s.refresh(t + h);
        Ok(())
    }

    fn solve_stats(&self) -> Option<super::SolveStats> {
        Some(self.stats())
    }
}
