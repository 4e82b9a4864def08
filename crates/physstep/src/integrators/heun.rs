//! Heun's method: the trapezoid rule with an explicit-Euler predictor (RK2).

use super::{scratch, ConstraintMode, Info, Method};
use crate::dynamics::{Step, System};
use crate::error::Result;

/// Heun: `y_p = y + dt f(y)`, then `y += dt (f(y) + f(y_p)) / 2`. Second order.
#[derive(Debug, Clone, Default)]
pub struct Heun {
    y_p: Vec<f64>,
    f_p: Vec<f64>,
}

impl Method for Heun {
    const INFO: Info = Info {
        name: "heun",
        order: 2,
        symplectic: false,
        implicit: false,
        evals: 2,
        split: false,
        vector_positions: false,
        local: true,
        constraints: ConstraintMode::Project,
        period: 1,
        doc: "Euler predictor y_p = y + f dt, then y += (f(y) + f(y_p)) dt/2 (trapezoid RK2)",
    };

    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let y_p = scratch(&mut self.y_p, s.y.len());
        let f_p = scratch(&mut self.f_p, s.y.len());
        s.stage(1.0, None, y_p, f_p);
        let h2 = 0.5 * h;
        for ((yi, fi), fp) in s.y.iter_mut().zip(s.f.iter()).zip(f_p.iter()) {
            *yi += h2 * (fi + fp);
        }
        s.refresh(t + h);
        Ok(())
    }
}
