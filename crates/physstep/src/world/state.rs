//! What a world holds now: positions, velocities, the derivative (evaluated when the state
//! changed, and checked), time, energy and momentum, and setting the state by hand.

use super::World;
use crate::dynamics::{FirstOrder, SecondOrder, System};
use crate::error::{bounded, Error, Result};
use crate::integrators::registry::RUNAWAY;

impl World {
    /// Positions to draw: `previous + alpha * (current - previous)`, between the state
    /// before the latest step and the current one.
    #[must_use]
    pub fn interpolated_positions(&self) -> Vec<f64> {
        let alpha = self.alpha();
        let x = self.positions();
        if self.prev_x.len() != x.len() {
            return x.to_vec();
        }
        self.prev_x.iter().zip(x).map(|(p, c)| p + alpha * (c - p)).collect()
    }

    /// Positions, m (flat, `n * dim`).
    #[must_use]
    pub fn positions(&self) -> &[f64] {
        &self.state.y[..self.coords()]
    }

    /// Velocities, m/s (flat, `n * dim`).
    #[must_use]
    pub fn velocities(&self) -> &[f64] {
        if self.flow.is_some() {
            // A flow's velocity is its derivative at the current state.
            return &self.state.f;
        }
        let (np, nx) = (self.model.len(), self.nx());
        &self.state.y[nx..nx + np]
    }

    /// Accelerations at the current state, m/s^2 (flat, `n * dim`).
    ///
    /// # Errors
    /// [`Error::Force`] when a user force fails.
    pub fn accelerations(&mut self) -> Result<&[f64]> {
        self.refresh()?;
        if self.flow.is_some() {
            return Ok(&[]);
        }
        let (np, nx) = (self.model.len(), self.nx());
        Ok(&self.state.f[nx..nx + np])
    }

    /// Sets every position (flat, `n * dim`).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a wrong length or a non-finite entry; nothing changes.
    pub fn set_positions(&mut self, x: &[f64]) -> Result<()> {
        let n = self.coords();
        if x.len() != n {
            return Err(Error::invalid("len(positions)", x.len(), format!("{n}")));
        }
        bounded("position", x, RUNAWAY)?;
        self.state.y[..n].copy_from_slice(x);
        self.touch();
        Ok(())
    }

    /// Sets every velocity (flat, `n * dim`); static particles keep velocity 0.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a wrong length or a non-finite entry; nothing changes.
    pub fn set_velocities(&mut self, v: &[f64]) -> Result<()> {
        self.refuse_flow("velocities")?;
        let n = self.model.len();
        if v.len() != n {
            return Err(Error::invalid("len(velocities)", v.len(), format!("{n}")));
        }
        bounded("velocity", v, RUNAWAY)?;
        let d = self.dim();
        let nx = self.nx();
        for (i, (dst, src)) in self.state.y[nx..nx + n].iter_mut().zip(v).enumerate() {
            *dst = if self.model.inv_mass[i / d] > 0.0 { *src } else { 0.0 };
        }
        self.touch();
        Ok(())
    }

    /// Physics time, s.
    #[must_use]
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// Steps taken.
    #[must_use]
    pub fn steps(&self) -> u64 {
        self.state.steps
    }

    /// Force (acceleration) evaluations made.
    #[must_use]
    pub fn evals(&self) -> u64 {
        self.state.evals
    }

    /// Kinetic plus potential energy, J; `None` when a user force has no potential (the
    /// energy is then unknown, not the built-in forces' part of it).
    #[must_use]
    pub fn energy(&self) -> Option<f64> {
        if self.flow.is_some() {
            return None;
        }
        let particles = self.model.kinetic(self.velocities()) + self.model.potential(self.positions())?;
        if self.bodies.is_empty() {
            return Some(particles);
        }
        let (bx, bv) = self.body_state();
        let loads = super::parts::loads(&self.model);
        let np = self.model.len();
        let springs: f64 =
            self.bodies.springs.iter().map(|s| s.potential(np, &self.state.y[..self.nx()])).sum();
        let (x, v) = self.state.y.split_at(self.nx());
        let mut users = 0.0;
        for g in &self.bodies.forces {
            let (p, _, _) = self.bodies.point(g.body, g.point, np, x, v);
            users += g.generator.0.potential(&p.to_array())?;
        }
        Some(
            particles + self.bodies.kinetic(bx, bv) + self.bodies.potential(&loads, bx, bv) + springs + users,
        )
    }

    /// Kinetic energy, J: the dynamic particles' and the bodies' (translation and rotation).
    #[must_use]
    pub fn kinetic(&self) -> f64 {
        if self.flow.is_some() {
            return 0.0;
        }
        let (bx, bv) = self.body_state();
        self.model.kinetic(self.velocities()) + self.bodies.kinetic(bx, bv)
    }

    /// Total momentum of the dynamic particles, kg m/s (`dim` components).
    #[must_use]
    pub fn momentum(&self) -> Vec<f64> {
        let d = self.dim();
        let mut p = vec![0.0; d];
        if self.flow.is_some() {
            return p; // a flow has no particles
        }
        for (i, vi) in self.velocities().iter().enumerate() {
            if self.model.inv_mass[i / d] > 0.0 {
                p[i % d] += self.model.mass[i / d] * vi;
            }
        }
        for pb in self.body_state().1.chunks_exact(crate::rigid::body::V_LEN) {
            for (pk, bk) in p.iter_mut().zip(pb) {
                *pk += bk;
            }
        }
        p
    }

    /// Re-evaluates the acceleration if anything changed since the last step.
    ///
    /// # Errors
    /// [`Error::Force`] when a user force fails; the derivative stays stale.
    pub(super) fn refresh(&mut self) -> Result<()> {
        if let (true, Some(flow)) = (self.stale, self.flow.as_mut()) {
            let (y, f, t) = (&self.state.y, &mut self.state.f, self.state.t);
            flow.deriv(t, y, f);
            self.state.evals += 1;
            if let Some(e) = flow.failure.take() {
                return Err(e);
            }
            self.derivative_finite()?;
            self.stale = false;
        }
        if self.stale || self.deferred {
            let mut y = std::mem::take(&mut self.state.y);
            let mut f = std::mem::take(&mut self.state.f);
            let t = self.state.t;
            self.parts().deriv(t, &y, &mut f);
            std::mem::swap(&mut self.state.y, &mut y);
            std::mem::swap(&mut self.state.f, &mut f);
            if self.stale {
                self.state.evals += 1;
            }
            self.deferred = false;
            if let Some(e) = self.model.failure.take() {
                return Err(e);
            }
            self.derivative_finite()?;
            self.stale = false;
        }
        Ok(())
    }

    /// [`Error::NonFinite`] when the derivative just evaluated at the current state holds a
    /// NaN, an infinity or a runaway value: forces the world accepted can still overflow at a
    /// state (a particle at a central mass, a tiny mass on a spring), and that must not leave
    /// as a number.
    fn derivative_finite(&self) -> Result<()> {
        match self.integrator.check(&self.state, self.layout()) {
            Ok(()) => Ok(()),
            Err(Error::Diverged { index, .. }) => {
                let skip = self.layout().skip(&self.state);
                let bad = |v: &f64| v.is_nan() || v.abs() > RUNAWAY;
                let value = self.state.y.get(index).copied().filter(bad);
                let value = value
                    .unwrap_or_else(|| self.state.f[skip..].iter().copied().find(bad).unwrap_or(f64::NAN));
                Err(Error::NonFinite {
                    method: self.integrator.info().name.into(),
                    quantity: if self.flow.is_some() { "derivative".into() } else { "acceleration".into() },
                    value,
                    step: self.state.steps,
                    t: self.state.t,
                })
            }
            Err(e) => Err(e),
        }
    }
}
