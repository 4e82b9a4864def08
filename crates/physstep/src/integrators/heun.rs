//! Heun's method: the trapezoid rule with an explicit-Euler predictor (RK2).

use super::{axpy_to, flow_method, scratch, Info, Log, Method};
use crate::dynamics::Flow;
use crate::error::Result;

/// Heun: `y_p = y + dt f(y)`, then `y += dt (f(y) + f(y_p)) / 2`. Second order.
#[derive(Debug, Clone, Default)]
pub struct Heun {
    y_p: Vec<f64>,
    f_p: Vec<f64>,
}

impl Method for Heun {
    const INFO: Info = Info {
        name: "heun",
        order: 2,
        symplectic: false,
        implicit: false,
        evals: 2,
        split: false,
        doc: "Euler predictor y_p = y + f dt, then y += (f(y) + f(y_p)) dt/2 (trapezoid RK2)",
    };

    flow_method!();

    fn step_flow<F: Flow>(
        &mut self,
        flow: &mut F,
        t: f64,
        h: f64,
        y: &mut [f64],
        f: &mut [f64],
        _log: Log<'_>,
    ) -> Result<()> {
        let y_p = scratch(&mut self.y_p, y.len());
        let f_p = scratch(&mut self.f_p, y.len());
        axpy_to(y_p, y, h, f);
        flow.deriv(t + h, y_p, f_p);
        let h2 = 0.5 * h;
        for ((yi, fi), fp) in y.iter_mut().zip(f.iter()).zip(f_p.iter()) {
            *yi += h2 * (fi + fp);
        }
        flow.deriv(t + h, y, f);
        Ok(())
    }
}
