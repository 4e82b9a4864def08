//! Leapfrog: half-step velocities kept inside, synchronised velocity reported.

use super::{axpy, axpy_to, carried_memory, scratch, Carried, ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
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
        vector_positions: false,
        local: false,
        constraints: ConstraintMode::Rattle,
        period: 1,
        doc: "v_half += a dt; x += v_half dt (half-step velocity inside; synchronised v reported)",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let again = s.velocity_dependent();
        let half = scratch(&mut self.half.v, s.vel_len());
        if !self.half.started || h != self.half.h {
            let (_, v, a) = s.xva();
            axpy_to(half, v, 0.5 * h, a);
        }
        s.drift_by(half, h);
        s.eval_at(t + h, half);
        if again {
            let (_, v, a) = s.xva();
            axpy_to(v, half, 0.5 * h, a);
            s.eval(t + h);
        }
        let (_, v, a) = s.xva();
        axpy_to(v, half, 0.5 * h, a);
        axpy(half, h, a);
        s.sync();
        self.half.keep(h);
        Ok(())
    }

    carried_memory!(half, v);

    /// The half-step velocities of the changed entries moved by the same change
    /// (`v - before`), as an impulse moves both.
    fn velocities_changed(&mut self, at: usize, _x: &[f64], v: &[f64], before: &[f64], _h: f64) {
        if self.half.v.is_empty() {
            return;
        }
        for ((u, vi), bi) in self.half.v[at..at + v.len()].iter_mut().zip(v).zip(before) {
            *u += vi - bi;
        }
    }
}
