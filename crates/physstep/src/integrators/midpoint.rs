//! The explicit midpoint method (RK2) with its half-step state written out, as the notes do.

use super::{axpy, scratch, ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Midpoint: `x_half = x + v dt/2, v_half = v + a dt/2, a_half = a(x_half, v_half)`, then
/// `x += v_half dt, v += a_half dt`. Second order, two evaluations per step.
#[derive(Debug, Clone, Default)]
pub struct Midpoint {
    y_half: Vec<f64>,
    f_half: Vec<f64>,
}

impl Method for Midpoint {
    const INFO: Info = Info {
        name: "midpoint",
        order: 2,
        symplectic: false,
        implicit: false,
        evals: 2,
        split: false,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "x_half = x + v dt/2, v_half = v + a dt/2; x += v_half dt, v += a(x_half, v_half) dt (RK2)",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let y_half = scratch(&mut self.y_half, s.y.len());
        let f_half = scratch(&mut self.f_half, s.y.len());
        s.stage(0.5, None, y_half, f_half);
        s.record("half", t + 0.5 * h, y_half, f_half);
        axpy(s.y, h, f_half);
        s.refresh(t + h);
        Ok(())
    }
}
