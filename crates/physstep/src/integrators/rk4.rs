//! The classic fourth-order Runge-Kutta method.

use super::{axpy_to, flow_method, record, scratch, Info, Log, Method};
use crate::dynamics::Flow;
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
        doc: "classic Runge-Kutta: evaluation points xa, xb (half step), xc (full step), weights 1/6 1/3 1/3 1/6",
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
        let n = y.len();
        let stage = scratch(&mut self.stage, n);
        let ka = scratch(&mut self.ka, n);
        let kb = scratch(&mut self.kb, n);
        let kc = scratch(&mut self.kc, n);
        let th = t + 0.5 * h;
        axpy_to(stage, y, 0.5 * h, f);
        flow.deriv(th, stage, ka);
        record(&mut log, "xa", th, stage, ka);
        axpy_to(stage, y, 0.5 * h, ka);
        flow.deriv(th, stage, kb);
        record(&mut log, "xb", th, stage, kb);
        axpy_to(stage, y, h, kb);
        flow.deriv(t + h, stage, kc);
        record(&mut log, "xc", t + h, stage, kc);
        let h6 = h / 6.0;
        for i in 0..n {
            y[i] += h6 * (f[i] + 2.0 * ka[i] + 2.0 * kb[i] + kc[i]);
        }
        flow.deriv(t + h, y, f);
        Ok(())
    }
}
