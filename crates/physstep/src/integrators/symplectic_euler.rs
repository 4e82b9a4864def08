//! Symplectic (semi-implicit) Euler in both orders, and the two alternated.

use super::{axpy_to, scratch, ConstraintMode, Info, Method, Sizes};
use crate::dynamics::{Element, Ops, Step, System};
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
    /// Scratch: the velocities before the closing kick.
    v_old: Vec<f64>,
}

/// Velocity-first step: kick, drift, then `A` at the new state.
#[inline(always)]
fn velocity_first<O: Ops>(s: &mut O) {
    let (t, h) = (s.t(), s.h());
    s.kick_drift(h);
    s.eval(t + h);
}

/// Position-first step; with velocity-dependent forces the kick uses `a(x[n+1], v[n])` and
/// the acceleration is evaluated once more at the new state. With `predict` (the alternating
/// method, whose odd step is the closing kick of a velocity-Verlet step of `2 dt`; the
/// buffer keeps `v[n]`), the kick instead uses the acceleration at the predicted
/// `v[n] + a(x[n+1], v[n]) dt`, as velocity Verlet does, which keeps the pair second order.
#[inline]
fn position_first<S: System + ?Sized>(s: &mut Step<'_, S>, predict: Option<&mut Vec<f64>>) {
    let (t, h) = (s.t, s.h);
    let again = s.velocity_dependent();
    s.drift(h);
    s.eval(t + h);
    match predict {
        Some(buf) if again => {
            let v_old = scratch(buf, s.vel_len());
            v_old.copy_from_slice(s.xva().1);
            s.kick(h);
            s.eval(t + h);
            let (_, v, a) = s.xva();
            axpy_to(v, v_old, h, a);
        }
        _ => s.kick(h),
    }
    if again {
        s.eval(t + h);
    }
    s.sync();
}

impl Method for SymplecticEuler {
    const INFO: Info = Info {
        name: "symplectic-euler",
        order: 1,
        symplectic: true,
        implicit: false,
        evals: 1,
        split: true,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "v += a dt, then x += v dt with the new v (semi-implicit Euler); bounded energy",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        velocity_first(s);
        Ok(())
    }

    #[inline(always)]
    fn element_step<A: Fn(f64, f64) -> f64>(&self, e: &mut Element<A>) -> bool {
        velocity_first(e);
        true
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
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "x += v dt, then v += a(x_new) dt (the other order of symplectic Euler)",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        position_first(s, None);
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
        vector_positions: false,
        local: false,
        constraints: ConstraintMode::Project,
        period: 2,
        doc: "the two symplectic Euler orders alternated (velocity first on even steps); a pair of steps is velocity Verlet at 2 dt",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        if self.odd {
            position_first(s, Some(&mut self.v_old));
        } else {
            velocity_first(s);
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

    fn recall(&mut self, m: &[f64], _sizes: Sizes) -> bool {
        let [odd] = m else { return false };
        if *odd != 0.0 && *odd != 1.0 {
            return false;
        }
        self.odd = *odd == 1.0;
        true
    }
}
