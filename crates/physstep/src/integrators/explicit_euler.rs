//! Explicit (forward) Euler, as in the notes' code: `x += v dt; v += a dt`, both from the
//! old state.

use super::{axpy, flow_method, Info, Log, Method};
use crate::dynamics::Flow;
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
        doc: "x += v dt; v += a dt, both from the old state (the notes' code); gains energy",
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
        axpy(y, h, f);
        flow.deriv(t + h, y, f);
        Ok(())
    }
}
