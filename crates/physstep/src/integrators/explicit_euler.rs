//! Explicit (forward) Euler, as in the notes' code: `x += v dt; v += a dt`, both from the
//! old state.

use super::{axpy, ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Explicit Euler: `y[n+1] = y[n] + dt f(t[n], y[n])`. First order; gains energy on every
/// oscillator at every dt.
#[derive(Debug, Clone, Default)]
pub struct ExplicitEuler;

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
        doc: "x += v dt; v += a dt, both from the old state (the notes' code); gains energy",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        axpy(s.y, h, s.f);
        s.refresh(t + h);
        Ok(())
    }
}
