//! Linearly implicit Euler: backward Euler's equation linearised at the start of the step and
//! solved once (Baraff and Witkin, "Large steps in cloth simulation", 1998).

use super::newton::Newton;
use super::{ConstraintMode, ImplicitParams, Info, Method, ENERGY_ROUNDING};
use crate::dynamics::{Counted, Step, System};
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
///
/// On nonlinear springs the one solve can raise the energy (a folding stiff cloth's rose by
/// up to 7 J in a step while springs buckled). Where the system states its energy
/// ([`crate::dynamics::SecondOrder::energy`]), a step that raises it by more than
/// [`super::ENERGY_ROUNDING`] is taken again as two steps of half the size, each checked the
/// same way, at most [`ImplicitParams::energy_halvings`] times over (default 4); the solve
/// statistics then count every linear solve. Two halves fell where the whole step rose on
/// every such step of the 32 x 32 cloth's fold, so the energy never rises there; with
/// `energy_halvings: 0` the step is Baraff and Witkin's as it is, one solve always.
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

/// The linear solves and CG iterations a step took, its halves' included.
#[derive(Default)]
struct Taken {
    solves: u32,
    cg: u32,
}

impl LinearlyImplicitEuler {
    /// A step of `h` from `(t, y0, f0)`, its end left in the Newton solver's `z` and `fz`: one
    /// linear solve, or, where that raises the energy `e0` (by more than [`ENERGY_ROUNDING`])
    /// and `halvings` allow, two steps of `h / 2` in its place, each taken the same way.
    #[allow(clippy::too_many_arguments)]
    fn advance<S: System + ?Sized>(
        &mut self,
        flow: &mut Counted<'_, S>,
        t: f64,
        h: f64,
        y0: &[f64],
        f0: &[f64],
        e0: Option<(f64, f64)>,
        halvings: u32,
        taken: &mut Taken,
    ) -> Result<()> {
        self.newton.solve(flow, Self::INFO.name, t + h, h, y0, f0)?;
        taken.solves += 1;
        taken.cg += self.newton.stats.cg;
        let Some(e0) = e0.filter(|_| halvings > 0) else { return Ok(()) };
        let Some(e1) = flow.energy(&self.newton.z) else { return Ok(()) };
        let size = e0.0.abs() + e0.1.abs() + e1.0.abs() + e1.1.abs();
        // (A step whose energy is not finite is the world's to roll back and report.)
        if !size.is_finite() || (e1.0 + e1.1) - (e0.0 + e0.1) <= ENERGY_ROUNDING * size {
            return Ok(());
        }
        let half = 0.5 * h;
        self.advance(flow, t, half, y0, f0, Some(e0), halvings - 1, taken)?;
        let (ym, fm) = (self.newton.z.clone(), self.newton.fz.clone());
        let em = flow.energy(&ym);
        self.advance(flow, t + half, half, &ym, &fm, em, halvings - 1, taken)
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
        doc: "backward Euler linearised at the step's start: one linear solve (Baraff-Witkin), halved where it would raise the energy; stable on linear springs",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let halvings = self.newton.params.energy_halvings;
        let mut taken = Taken::default();
        {
            let (y, f, mut flow) = s.flow();
            let e0 = if halvings > 0 { flow.energy(y) } else { None };
            self.advance(&mut flow, t, h, y, f, e0, halvings, &mut taken)?;
        }
        s.y.copy_from_slice(&self.newton.z);
        s.f.copy_from_slice(&self.newton.fz);
        self.newton.stats.newton = taken.solves;
        self.newton.stats.cg = taken.cg;
        Ok(())
    }

    fn solve_stats(&self) -> Option<super::SolveStats> {
        Some(self.stats())
    }
}
