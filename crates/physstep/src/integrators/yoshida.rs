//! Yoshida's fourth-order symplectic composition of velocity Verlet (Forest-Ruth).

use super::verlet::velocity_verlet;
use super::{split_method, Info, Log, Method};
use crate::dynamics::{SecondOrder, Split};
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
}

impl Default for Yoshida4 {
    fn default() -> Self {
        let c = 2f64.cbrt();
        let w1 = 1.0 / (2.0 - c);
        Self { w: [w1, -c * w1, w1] }
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
        doc:
            "velocity Verlet composed over w1 dt, w0 dt, w1 dt (Yoshida / Forest-Ruth), 4th order symplectic",
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
        let mut ts = t;
        for w in self.w {
            velocity_verlet(sys, ts, w * h, y, f, 3);
            ts += w * h;
        }
        Ok(())
    }
}
