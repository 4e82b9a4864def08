//! Explicit predictor, implicit corrector (the notes' way around solving backward Euler).

use super::{scratch, ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Predict the end of the step with explicit Euler, `y* = y + dt f(y)`, then plug the
/// prediction into the right-hand side of the backward-Euler equations:
/// `x[n+1] = x[n] + v* dt`, `v[n+1] = v[n] + a(x*, v*) dt`, i.e. `y[n+1] = y + dt f(y*)`.
/// One fixed-point sweep of backward Euler: first order, two evaluations, stable on the
/// undamped spring only for `omega dt <= 1`.
#[derive(Debug, Clone, Default)]
pub struct PredictorCorrector {
    y_p: Vec<f64>,
    f_p: Vec<f64>,
}

impl Method for PredictorCorrector {
    const INFO: Info = Info {
        name: "predictor-corrector",
        order: 1,
        symplectic: false,
        implicit: false,
        evals: 2,
        split: false,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "explicit Euler predictor y* = y + f dt fed into backward Euler: y += f(y*) dt",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let y_p = scratch(&mut self.y_p, s.y.len());
        let f_p = scratch(&mut self.f_p, s.y.len());
        s.stage(1.0, None, y_p, f_p);
        s.record("predicted", t + h, y_p, f_p);
        for (yi, fp) in s.y.iter_mut().zip(f_p.iter()) {
            *yi += h * fp;
        }
        s.refresh(t + h);
        Ok(())
    }
}
