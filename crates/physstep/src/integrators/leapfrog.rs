//! Leapfrog: half-step velocities kept inside, synchronised velocity reported.

use super::{
    axpy_to, carried_memory, drift, kick, scratch, split_method, sync_f, xva, Carried, Info, Log, Method,
};
use crate::dynamics::{SecondOrder, Split};
use crate::error::Result;

/// Leapfrog: `v[n+1/2] = v[n-1/2] + a[n] dt; x[n+1] = x[n] + v[n+1/2] dt`.
///
/// The half-step velocity lives inside the integrator; the state's velocity is the
/// synchronised `v[n+1] = v[n+1/2] + a[n+1] dt/2`. The first step (and the first after a
/// reset or a change of dt) starts the half-step velocity from the synchronised state:
/// `v[n+1/2] = v[n] + a[n] dt/2`, so a change of dt costs nothing in accuracy beyond a
/// restart. Velocity-dependent forces are evaluated at the half-step velocity, then at the
/// predicted synchronised velocity.
#[derive(Debug, Clone, Default)]
pub struct Leapfrog {
    half: Carried,
}

impl Method for Leapfrog {
    const INFO: Info = Info {
        name: "leapfrog",
        order: 2,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        doc: "v_half += a dt; x += v_half dt (half-step velocity inside; synchronised v reported)",
    };

    split_method!();

    fn step_split<S: SecondOrder + ?Sized>(
        &mut self,
        sys: &mut Split<'_, S>,
        t: f64,
        h: f64,
        y: &mut [f64],
        f: &mut [f64],
        _log: Log<'_>,
    ) -> Result<()> {
        let again = sys.sys.velocity_dependent();
        let (x, v, a) = xva(y, f);
        let half = scratch(&mut self.half.v, x.len());
        if !self.half.started || h != self.half.h {
            axpy_to(half, v, 0.5 * h, a);
        }
        drift(x, half, h);
        sys.accel(t + h, x, half, a);
        if again {
            axpy_to(v, half, 0.5 * h, a);
            sys.accel(t + h, x, v, a);
        }
        axpy_to(v, half, 0.5 * h, a);
        kick(half, a, h);
        sync_f(y, f);
        self.half.keep(h);
        Ok(())
    }

    carried_memory!(half);
}
