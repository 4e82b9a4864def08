//! The classic fourth-order Runge-Kutta method.

use super::{scratch, ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
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
        doc: "classic Runge-Kutta: evaluation points xa, xb (half step), xc (full step), weights 1/6 1/3 1/3 1/6",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let n = s.y.len();
        let stage = scratch(&mut self.stage, n);
        let ka = scratch(&mut self.ka, n);
        let kb = scratch(&mut self.kb, n);
        let kc = scratch(&mut self.kc, n);
        let th = t + 0.5 * h;
        s.stage(0.5, None, stage, ka);
        s.record("xa", th, stage, ka);
        s.stage(0.5, Some(ka), stage, kb);
        s.record("xb", th, stage, kb);
        s.stage(1.0, Some(kb), stage, kc);
        s.record("xc", t + h, stage, kc);
        let h6 = h / 6.0;
        for i in 0..n {
            s.y[i] += h6 * (s.f[i] + 2.0 * ka[i] + 2.0 * kb[i] + kc[i]);
        }
        s.refresh(t + h);
        Ok(())
    }
}
