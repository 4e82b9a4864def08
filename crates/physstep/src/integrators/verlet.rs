//! Velocityless (Stormer) Verlet and velocity Verlet.

use super::{
    axpy_to, carried_memory, drift, kick, scratch, split_method, sync_f, xva, Carried, Info, Log, Method,
};
use crate::dynamics::{SecondOrder, Split};
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
        doc: "velocityless Stormer Verlet x' = 2x - x_prev + a dt^2, x_prev = x0 - v0 dt; v by backward difference",
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
        let (x, v, a) = xva(y, f);
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
        sys.accel(t + h, x, v, a);
        sync_f(y, f);
        self.prev.keep(h);
        Ok(())
    }

    carried_memory!(prev);
}

/// Velocity Verlet: `v += a dt/2; x += v dt; a = a(x); v += a dt/2`. Second order,
/// symplectic, one evaluation per step.
#[derive(Debug, Clone, Default)]
pub struct VelocityVerlet;

/// One velocity-Verlet substep of `h` (kick, drift, kick); shared with Yoshida's composition.
///
/// Velocity-dependent forces: the second kick needs `a(x[n+1], v[n+1])`, an implicit
/// equation in `v[n+1]` (which keeps the step symmetric). It is solved by `corrections`
/// fixed-point passes from `v[n+1/2]`: each evaluates the acceleration at the latest
/// prediction `v[n+1/2] + a dt/2`, and each gains one power of `dt` in the kick. One pass is
/// enough for velocity Verlet's second order (kicking with `a(x[n+1], v[n+1/2])` alone
/// would make it first order); Yoshida's composition needs the step symmetric to
/// `O(dt^5)`, three passes. The acceleration is then evaluated once more at the new state.
/// Velocity-independent forces take one evaluation whatever `corrections` is.
#[inline]
pub(crate) fn velocity_verlet<S: SecondOrder + ?Sized>(
    sys: &mut Split<'_, S>,
    t: f64,
    h: f64,
    y: &mut [f64],
    f: &mut [f64],
    corrections: u32,
) {
    let again = sys.sys.velocity_dependent();
    let n = y.len() / 2;
    let (x, v) = y.split_at_mut(n);
    // f[..n] (the dx part) is free until sync_f: it holds v[n+1/2] meanwhile.
    let (v_half, a) = f.split_at_mut(n);
    kick(v, a, 0.5 * h);
    drift(x, v, h);
    sys.accel(t + h, x, v, a);
    if again {
        v_half.copy_from_slice(v);
        for _ in 0..corrections {
            axpy_to(v, v_half, 0.5 * h, a);
            sys.accel(t + h, x, v, a);
        }
        axpy_to(v, v_half, 0.5 * h, a);
        sys.accel(t + h, x, v, a);
    } else {
        kick(v, a, 0.5 * h);
    }
    sync_f(y, f);
}

impl Method for VelocityVerlet {
    const INFO: Info = Info {
        name: "velocity-verlet",
        order: 2,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        doc: "v += a dt/2; x += v dt; a = a(x); v += a dt/2",
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
        velocity_verlet(sys, t, h, y, f, 1);
        Ok(())
    }
}
