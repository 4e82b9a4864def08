//! Velocityless (Stormer) Verlet and velocity Verlet.

use super::{carried_memory, scratch, Carried, ConstraintMode, Info, Method};
use crate::dynamics::{Element, Ops, Step, System};
use crate::error::Result;

/// Velocityless Verlet: `x[n+1] = 2 x[n] - x[n-1] + a[n] dt^2`, started with
/// `x[-1] = x0 - v0 dt`; the reported velocity is the backward difference
/// `(x[n+1] - x[n]) / dt`.
///
/// With that start the method is algebraically symplectic Euler (the notes print identical
/// tables), hence first order. Velocity-dependent forces see the backward-difference
/// velocity. A change of dt rescales the stored previous position so the velocity estimate
/// `(x[n] - x[n-1]) / dt` is kept.
#[derive(Debug, Clone, Default)]
pub struct Verlet {
    prev: Carried,
}

impl Method for Verlet {
    const INFO: Info = Info {
        name: "verlet",
        order: 1,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        vector_positions: true,
        local: false,
        constraints: ConstraintMode::Jakobsen,
        period: 1,
        doc: "velocityless Stormer Verlet x' = 2x - x_prev + a dt^2, x_prev = x0 - v0 dt; v by backward difference",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let (x, v, a) = s.xva();
        let prev = scratch(&mut self.prev.v, x.len());
        if !self.prev.started {
            for ((p, xi), vi) in prev.iter_mut().zip(x.iter()).zip(v.iter()) {
                *p = xi - vi * h;
            }
        } else if h != self.prev.h {
            let s = h / self.prev.h;
            for (p, xi) in prev.iter_mut().zip(x.iter()) {
                *p = xi - (xi - *p) * s;
            }
        }
        let h2 = h * h;
        let inv_h = 1.0 / h;
        for (((xi, vi), ai), p) in x.iter_mut().zip(v.iter_mut()).zip(a.iter()).zip(prev.iter_mut()) {
            let next = 2.0 * *xi - *p + ai * h2;
            *p = *xi;
            *vi = (next - *xi) * inv_h;
            *xi = next;
        }
        s.eval(t + h);
        s.sync();
        self.prev.keep(h);
        Ok(())
    }

    carried_memory!(prev, x);

    /// The previous positions of the changed entries made `x - v h` again: the start of a
    /// step from `(x, v)`, so the backward-difference velocity is the new one.
    fn velocities_changed(&mut self, at: usize, x: &[f64], v: &[f64], _before: &[f64], h: f64) {
        if self.prev.v.is_empty() {
            return;
        }
        for ((p, xi), vi) in self.prev.v[at..at + x.len()].iter_mut().zip(x).zip(v) {
            *p = xi - vi * h;
        }
    }
}

/// Velocity Verlet: `v += a dt/2; x += v dt; a = a(x); v += a dt/2`. Second order,
/// symplectic, one evaluation per step.
#[derive(Debug, Clone, Default)]
pub struct VelocityVerlet {
    /// Scratch of the velocity correction.
    v_half: Vec<f64>,
}

/// One velocity-Verlet substep of `h` from time `t` (kick, drift, kick); shared with
/// Yoshida's composition, whose substeps have their own `t` and `h`.
///
/// Velocity-dependent forces: the second kick needs `a(x[n+1], v[n+1])`, an implicit
/// equation in `v[n+1]` (which keeps the step symmetric). It is solved by `corrections`
/// fixed-point passes from `v[n+1/2]` (kept in `v_half`): each evaluates the acceleration at
/// the latest prediction `v[n+1/2] + a dt/2`, and each gains one power of `dt` in the kick.
/// One pass is enough for velocity Verlet's second order (kicking with `a(x[n+1], v[n+1/2])`
/// alone would make it first order); Yoshida's composition needs the step symmetric to
/// `O(dt^5)`, three passes. The acceleration is then evaluated once more at the new state.
/// Velocity-independent forces take one evaluation whatever `corrections` is.
#[inline(always)]
pub(crate) fn velocity_verlet<O: Ops>(s: &mut O, t: f64, h: f64, corrections: u32, v_half: &mut O::V) {
    let again = s.velocity_dependent();
    s.kick(0.5 * h);
    s.drift(h);
    s.eval(t + h);
    if again {
        s.save_velocities(v_half);
        for _ in 0..=corrections {
            s.kick_from(v_half, 0.5 * h);
            s.eval(t + h);
        }
    } else {
        s.kick(0.5 * h);
    }
    s.sync();
}

impl Method for VelocityVerlet {
    const INFO: Info = Info {
        name: "velocity-verlet",
        order: 2,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Rattle,
        period: 1,
        doc: "v += a dt/2; x += v dt; a = a(x); v += a dt/2",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        velocity_verlet(s, s.t, s.h, 1, &mut self.v_half);
        Ok(())
    }

    #[inline(always)]
    fn element_step<A: Fn(f64, f64) -> f64>(&self, e: &mut Element<A>) -> bool {
        velocity_verlet(e, e.t, e.h, 1, &mut 0.0);
        true
    }
}
