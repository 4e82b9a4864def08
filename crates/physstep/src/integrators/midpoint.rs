//! The explicit midpoint method (RK2) with its half-step state written out, as the notes do.

use super::{axpy, axpy_to, flow_method, record, scratch, Info, Log, Method};
use crate::dynamics::Flow;
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
        doc: "x_half = x + v dt/2, v_half = v + a dt/2; x += v_half dt, v += a(x_half, v_half) dt (RK2)",
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
        let y_half = scratch(&mut self.y_half, y.len());
        let f_half = scratch(&mut self.f_half, y.len());
        axpy_to(y_half, y, 0.5 * h, f);
        flow.deriv(t + 0.5 * h, y_half, f_half);
        record(&mut log, "half", t + 0.5 * h, y_half, f_half);
        axpy(y, h, f_half);
        flow.deriv(t + h, y, f);
        Ok(())
    }
}
