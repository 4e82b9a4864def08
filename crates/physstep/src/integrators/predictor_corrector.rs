//! Explicit predictor, implicit corrector (the notes' way around solving backward Euler).

use super::{axpy_to, flow_method, record, scratch, Info, Log, Method};
use crate::dynamics::Flow;
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
        doc: "explicit Euler predictor y* = y + f dt fed into backward Euler: y += f(y*) dt",
    };

    flow_method!();

    fn step_flow<F: Flow>(
        &mut self,
        flow: &mut F,
        t: f64,
        h: f64,
        y: &mut [f64],
        f: &mut [f64],
        mut log: Log<'_>,
    ) -> Result<()> {
        let y_p = scratch(&mut self.y_p, y.len());
        let f_p = scratch(&mut self.f_p, y.len());
        axpy_to(y_p, y, h, f);
        flow.deriv(t + h, y_p, f_p);
        record(&mut log, "predicted", t + h, y_p, f_p);
        for (yi, fp) in y.iter_mut().zip(f_p.iter()) {
            *yi += h * fp;
        }
        flow.deriv(t + h, y, f);
        Ok(())
    }
}
