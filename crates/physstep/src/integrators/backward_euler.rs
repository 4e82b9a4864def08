//! Backward (implicit) Euler, solved by Newton iteration.

use super::newton::Newton;
use super::{flow_method, ImplicitParams, Info, Log, Method};
use crate::dynamics::Flow;
use crate::error::Result;

/// Backward Euler: `x[n+1] = x[n] + v[n+1] dt`, `v[n+1] = v[n] + a[n+1] dt`, i.e.
/// `y[n+1] = y[n] + dt f(t[n+1], y[n+1])`, solved by Newton iteration to
/// [`ImplicitParams::tol`]. First order, stable at every dt, and it drains energy from
/// every oscillator.
#[derive(Debug, Clone, Default)]
pub struct BackwardEuler {
    newton: Newton,
}

impl BackwardEuler {
    /// With the given Newton settings.
    #[must_use]
    pub fn with_params(params: ImplicitParams) -> Self {
        Self { newton: Newton::new(params) }
    }
}

impl Method for BackwardEuler {
    const INFO: Info = Info {
        name: "backward-euler",
        order: 1,
        symplectic: false,
        implicit: true,
        evals: 2,
        split: false,
        doc: "x += v_new dt; v += a_new dt, solved by Newton iteration; loses energy, stable at any dt",
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
        self.newton.solve(flow, Self::INFO.name, t + h, h, y, f)?;
        y.copy_from_slice(&self.newton.z);
        f.copy_from_slice(&self.newton.fz);
        Ok(())
    }
}
