//! Yoshida's fourth-order symplectic composition of velocity Verlet (Forest-Ruth).

use super::verlet::velocity_verlet;
use super::{ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Three velocity-Verlet substeps of `w1 dt, w0 dt, w1 dt` with
/// `w1 = 1 / (2 - 2^(1/3))`, `w0 = -2^(1/3) / (2 - 2^(1/3))` (Yoshida 1990): the odd-order
/// error terms of the symmetric composition cancel, giving fourth order. The middle substep
/// runs backwards in time. With velocity-dependent forces each substep solves its closing
/// kick with three fixed-point passes, so the substep stays symmetric to the order the
/// composition needs (see `velocity_verlet`).
#[derive(Debug, Clone)]
pub struct Yoshida4 {
    w: [f64; 3],
    /// Scratch of the substeps' velocity corrections.
    v_half: Vec<f64>,
}

impl Default for Yoshida4 {
    fn default() -> Self {
        let c = 2f64.cbrt();
        let w1 = 1.0 / (2.0 - c);
        Self { w: [w1, -c * w1, w1], v_half: Vec::new() }
    }
}

impl Method for Yoshida4 {
    const INFO: Info = Info {
        name: "yoshida4",
        order: 4,
        symplectic: true,
        implicit: false,
        evals: 3,
        split: true,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc:
            "velocity Verlet composed over w1 dt, w0 dt, w1 dt (Yoshida / Forest-Ruth), 4th order symplectic",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let mut ts = s.t;
        for w in self.w {
            velocity_verlet(s, ts, w * s.h, 3, &mut self.v_half);
            ts += w * s.h;
        }
        Ok(())
    }
}
