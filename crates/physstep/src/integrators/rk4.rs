//! The classic fourth-order Runge-Kutta method.

use super::{ConstraintMode, Info, Method};
use crate::dynamics::{Element, Ops, Step, System};
use crate::error::Result;

/// RK4 with the notes' names for the evaluation points: `k1 = f(y)`, `xa = y + k1 dt/2`,
/// `xb = y + f(xa) dt/2`, `xc = y + f(xb) dt`, then
/// `y += dt (k1 + 2 f(xa) + 2 f(xb) + f(xc)) / 6`. This is the textbook method (fourth
/// order); the notes' later rows came from a variant that used the updated v, which is not.
#[derive(Debug, Clone, Default)]
pub struct Rk4 {
    stage: Vec<f64>,
    ka: Vec<f64>,
    kb: Vec<f64>,
    kc: Vec<f64>,
}

impl Method for Rk4 {
    const INFO: Info = Info {
        name: "rk4",
        order: 4,
        symplectic: false,
        implicit: false,
        evals: 4,
        split: false,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "classic Runge-Kutta: evaluation points xa, xb (half step), xc (full step), weights 1/6 1/3 1/3 1/6",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        recipe(s, [&mut self.stage, &mut self.ka, &mut self.kb, &mut self.kc]);
        Ok(())
    }

    #[inline(always)]
    fn element_step<A: Fn(f64, f64) -> f64>(&self, e: &mut Element<A>) -> bool {
        recipe(e, [&mut [0.0; 2], &mut [0.0; 2], &mut [0.0; 2], &mut [0.0; 2]]);
        true
    }
}

/// The step, its stage and the three slopes in the buffers given.
#[inline(always)]
fn recipe<O: Ops>(s: &mut O, [stage, ka, kb, kc]: [&mut O::Y; 4]) {
    let (t, h) = (s.t(), s.h());
    let th = t + 0.5 * h;
    s.stage(0.5, None, stage, ka);
    s.record("xa", th, stage, ka);
    s.stage(0.5, Some(ka), stage, kb);
    s.record("xb", th, stage, kb);
    s.stage(1.0, Some(kb), stage, kc);
    s.record("xc", t + h, stage, kc);
    let h6 = h / 6.0;
    s.combine([ka, kb, kc], |y, f, [a, b, c]| y + h6 * (f + 2.0 * a + 2.0 * b + c));
    s.refresh(t + h);
}
