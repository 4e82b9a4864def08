//! Explicit (forward) Euler, as in the notes' code: `x += v dt; v += a dt`, both from the
//! old state.

use super::{ConstraintMode, Info, Method};
use crate::dynamics::{Element, Ops, Step, System};
use crate::error::Result;

/// Explicit Euler: `y[n+1] = y[n] + dt f(t[n], y[n])`. First order; gains energy on every
/// oscillator at every dt.
#[derive(Debug, Clone, Default)]
pub struct ExplicitEuler;

/// The step: `y += h f`, then `f` at the new state.
#[inline(always)]
fn recipe<O: Ops>(s: &mut O) {
    let (t, h) = (s.t(), s.h());
    s.combine([], |y, f, []| y + h * f);
    s.refresh(t + h);
}

impl Method for ExplicitEuler {
    const INFO: Info = Info {
        name: "explicit-euler",
        order: 1,
        symplectic: false,
        implicit: false,
        evals: 1,
        split: false,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "x += v dt; v += a dt, both from the old state (the notes' code); gains energy",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        recipe(s);
        Ok(())
    }

    #[inline(always)]
    fn element_step<A: Fn(f64, f64) -> f64>(&self, e: &mut Element<A>) -> bool {
        recipe(e);
        true
    }
}
