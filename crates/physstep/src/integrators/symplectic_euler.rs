//! Symplectic (semi-implicit) Euler in both orders, and the two alternated.

use super::{axpy_to, drift, kick, kick_drift, split_method, sync_f, Info, Log, Method};
use crate::dynamics::{SecondOrder, Split};
use crate::error::Result;

/// Velocity first: `v[n+1] = v[n] + a[n] dt; x[n+1] = x[n] + v[n+1] dt`.
#[derive(Debug, Clone, Default)]
pub struct SymplecticEuler;

/// Position first: `x[n+1] = x[n] + v[n] dt; v[n+1] = v[n] + a(x[n+1]) dt`.
#[derive(Debug, Clone, Default)]
pub struct SymplecticEulerX;

/// The two orders alternated: velocity first on even steps, position first on odd ones.
/// Each pair of steps is kick, drift, drift, kick, i.e. one velocity-Verlet step of `2 dt`,
/// so the state after an even number of steps is second-order accurate.
#[derive(Debug, Clone, Default)]
pub struct SymplecticEulerAlternating {
    odd: bool,
}

/// Velocity-first step on `(x, v, a)`, leaving `a` at the new state.
#[inline]
fn velocity_first<S: SecondOrder + ?Sized>(
    sys: &mut Split<'_, S>,
    t: f64,
    h: f64,
    y: &mut [f64],
    f: &mut [f64],
) {
    let n = y.len() / 2;
    let (x, v) = y.split_at_mut(n);
    let (dx, a) = f.split_at_mut(n);
    kick_drift(x, v, dx, a, h);
    sys.accel(t + h, x, v, a);
}

/// Position-first step; with velocity-dependent forces the kick uses `a(x[n+1], v[n])` and
/// the acceleration is evaluated once more at the new state. With `predict` (the alternating
/// method, whose odd step is the closing kick of a velocity-Verlet step of `2 dt`), the kick
/// instead uses the acceleration at the predicted `v[n] + a(x[n+1], v[n]) dt`, as velocity
/// Verlet does, which keeps the pair second order.
#[inline]
fn position_first<S: SecondOrder + ?Sized>(
    sys: &mut Split<'_, S>,
    t: f64,
    h: f64,
    y: &mut [f64],
    f: &mut [f64],
    predict: bool,
) {
    let again = sys.sys.velocity_dependent();
    let n = y.len() / 2;
    let (x, v) = y.split_at_mut(n);
    // f[..n] (the dx part) is free until sync_f: it holds v[n] meanwhile.
    let (v_old, a) = f.split_at_mut(n);
    drift(x, v, h);
    sys.accel(t + h, x, v, a);
    if again && predict {
        v_old.copy_from_slice(v);
        kick(v, a, h);
        sys.accel(t + h, x, v, a);
        axpy_to(v, v_old, h, a);
    } else {
        kick(v, a, h);
    }
    if again {
        sys.accel(t + h, x, v, a);
    }
    sync_f(y, f);
}

impl Method for SymplecticEuler {
    const INFO: Info = Info {
        name: "symplectic-euler",
        order: 1,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        doc: "v += a dt, then x += v dt with the new v (semi-implicit Euler); bounded energy",
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
        velocity_first(sys, t, h, y, f);
        Ok(())
    }
}

impl Method for SymplecticEulerX {
    const INFO: Info = Info {
        name: "symplectic-euler-x",
        order: 1,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        doc: "x += v dt, then v += a(x_new) dt (the other order of symplectic Euler)",
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
        position_first(sys, t, h, y, f, false);
        Ok(())
    }
}

impl Method for SymplecticEulerAlternating {
    const INFO: Info = Info {
        name: "symplectic-euler-alternating",
        order: 2,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        doc: "the two symplectic Euler orders alternated (velocity first on even steps); a pair of steps is velocity Verlet at 2 dt",
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
        if self.odd {
            position_first(sys, t, h, y, f, true);
        } else {
            velocity_first(sys, t, h, y, f);
        }
        self.odd = !self.odd;
        Ok(())
    }

    fn reset(&mut self) {
        self.odd = false;
    }

    const MEMORY_FLAGS: usize = 1;

    fn memory(&self, out: &mut Vec<f64>) {
        out.push(if self.odd { 1.0 } else { 0.0 });
    }

    fn recall(&mut self, m: &[f64], _n: usize) -> bool {
        let [odd] = m else { return false };
        if *odd != 0.0 && *odd != 1.0 {
            return false;
        }
        self.odd = *odd == 1.0;
        true
    }
}
