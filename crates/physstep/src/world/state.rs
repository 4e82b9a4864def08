//! What a world holds now: positions, velocities, the derivative (evaluated when the state
//! changed, and checked), time, energy and momentum, and setting the state by hand.

use super::{Derivative, World};
use crate::dynamics::{FirstOrder, SecondOrder, System};
use crate::error::{bounded, Error, Result};
use crate::limits::RUNAWAY;

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

    /// Gives the state new buffers holding the same values and returns the old ones, `[y, f]`,
    /// untouched: the memory [`World::positions`] and [`World::velocities`] pointed into. For
    /// a caller that lent that memory out (the Python face's zero-copy views) and must keep it
    /// alive across a call that reallocates the state.
    ///
    /// Only calls that change the state's layout reallocate it: adding particles or bodies.
    /// Steps (a failed step's rollback included), frames, setting positions, velocities or
    /// the phase, and restoring a snapshot write into the same buffers (tested below).
    pub fn detach_state(&mut self) -> [Vec<f64>; 2] {
        let (y, f) = (self.state.y.clone(), self.state.f.clone());
        [std::mem::replace(&mut self.state.y, y), std::mem::replace(&mut self.state.f, f)]
    }

    /// Accelerations at the current state, m/s^2 (flat, `n * dim`).
    ///
    /// # Errors
    /// [`Error::Force`] when a user force fails.
    pub fn accelerations(&mut self) -> Result<&[f64]> {
        // (Owing only the derivative's velocity half, the accelerations are current.)
        if self.derivative != Derivative::VelocityOwed {
            self.refresh()?;
        }
        if self.flow.is_some() {
            return Ok(&[]);
        }
        let (np, nx) = (self.model.len(), self.nx());
        Ok(&self.state.f[nx..nx + np])
    }

    /// Sets every position (flat, `n * dim`).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a wrong length or a non-finite entry, or positions that
    /// would make balls overlap or stick out of the walls (as [`World::add_ball`] refuses;
    /// an overlap the current state already has is kept allowed); nothing changes.
    pub fn set_positions(&mut self, x: &[f64]) -> Result<()> {
        let n = self.coords();
        if x.len() != n {
            return Err(Error::invalid("len(positions)", x.len(), format!("{n}")));
        }
        bounded("position", x, RUNAWAY)?;
        self.check_ball_positions(x)?;
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

    /// Sets particle `i`'s `position` (m) and `velocity` (m/s), each `dim` numbers; `None`
    /// keeps it. Validated as [`World::add_particle`] (finite, at most 1e100; a ball may not
    /// be moved into another or out of the walls, as [`World::set_positions`] refuses), and,
    /// as [`World::set_positions`] does, it restarts a method that carries memory (Verlet's
    /// previous positions: a teleport is not a velocity) and the derivative is evaluated
    /// again before the next step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `particle` (out of range), `len(position)`,
    /// `len(velocity)`, `position`, `velocity`, or `velocity` nonzero for a static particle;
    /// the world is unchanged.
    pub fn set_particle(
        &mut self,
        i: usize,
        position: Option<&[f64]>,
        velocity: Option<&[f64]>,
    ) -> Result<()> {
        self.refuse_flow("particles")?;
        self.particle_index(i)?;
        let d = self.dim();
        for (field, v) in [("position", position), ("velocity", velocity)] {
            if let Some(v) = v {
                if v.len() != d {
                    return Err(Error::invalid(
                        format!("len({field})"),
                        v.len(),
                        format!("{d}, the world's dim"),
                    ));
                }
                bounded(field, v, RUNAWAY)?;
            }
        }
        if let Some(v) = velocity {
            if self.model.inv_mass[i] == 0.0 && v.iter().any(|c| *c != 0.0) {
                return Err(Error::invalid(
                    "velocity",
                    format!("{v:?}"),
                    format!("zero for particle {i}, which is static"),
                ));
            }
        }
        if let Some(x) = position {
            if !self.balls.index.is_empty() {
                let mut all = self.positions().to_vec();
                all[i * d..(i + 1) * d].copy_from_slice(x);
                self.check_ball_positions(&all)?;
            }
            self.state.y[i * d..(i + 1) * d].copy_from_slice(x);
        }
        if let Some(v) = velocity {
            let at = self.nx() + i * d;
            self.state.y[at..at + d].copy_from_slice(v);
        }
        self.touch();
        Ok(())
    }

    /// Sets particle `i`'s mass, kg, validated as [`World::add_particle`] validates it
    /// (> 0 with a finite inverse, at most 1e100); the velocity is kept (the momentum
    /// changes with the mass). A static particle stays static (its mass may change, or be
    /// `inf`); a dynamic one takes a finite mass (whether a particle is static is fixed when
    /// it is added).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `particle` or `mass` (also `inf` for a dynamic
    /// particle, and an infinite mass under n-body gravity); the world is unchanged.
    pub fn set_mass(&mut self, i: usize, mass: f64) -> Result<()> {
        self.refuse_flow("particles")?;
        self.particle_index(i)?;
        let fixed = self.model.inv_mass[i] == 0.0;
        if self.model.forces.needs_finite_masses() {
            crate::forces::finite_masses(&[mass], i)?;
        }
        self.check_particles(&self.positions()[..self.dim()], None, Some(&[mass]))?;
        if !fixed && mass.is_infinite() {
            return Err(Error::invalid(
                "mass",
                crate::error::num(mass),
                format!("finite for particle {i}, which is dynamic (a particle is static or not from when it is added)"),
            ));
        }
        self.model.mass[i] = mass;
        self.model.inv_mass.set(i, if fixed { 0.0 } else { 1.0 / mass });
        self.touch();
        Ok(())
    }

    fn particle_index(&self, i: usize) -> Result<()> {
        let n = self.len();
        if i >= n {
            return Err(Error::invalid("particle", i, format!("an index below {n}")));
        }
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
        let particles = self.model.kinetic(self.velocities())
            + self.model.potential(self.positions())?
            + self.solid_kinetic_energy()
            + self.solid_potential_energy()
            + self.solid_user_potential()?;
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

    /// Kinetic energy, J: the dynamic particles', the bodies' and the solids' (translation and
    /// rotation).
    #[must_use]
    pub fn kinetic(&self) -> f64 {
        if self.flow.is_some() {
            return 0.0;
        }
        let (bx, bv) = self.body_state();
        self.model.kinetic(self.velocities()) + self.bodies.kinetic(bx, bv) + self.solid_kinetic_energy()
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
        match self.derivative {
            Derivative::Current => Ok(()),
            Derivative::RatesOwed => {
                // The split loop left the bodies' rates (c' = P / m, q' = (0, omega) q / 2) out
                // of `f`: they are a function of the state, computed now (the rest of `f` is
                // as the method left it, bit for bit as after single steps).
                let (np, nx) = (self.model.len(), self.nx());
                let (x, v) = self.state.y.split_at(nx);
                self.bodies.rate(&x[np..], &v[np..], &mut self.state.f[np..nx]);
                self.derivative = Derivative::Current;
                Ok(())
            }
            Derivative::VelocityOwed => {
                // The accelerations are current; the velocity half is `v` (particles only).
                let n = self.model.len();
                self.state.f[..n].copy_from_slice(&self.state.y[n..]);
                self.derivative = Derivative::Current;
                Ok(())
            }
            Derivative::Unstored => {
                // The kernel took the steps and checked the accelerations at this state:
                // computed again, without counting or checking.
                let n = self.model.len();
                let (y, f, t) = (&self.state.y, &mut self.state.f, self.state.t);
                f[..n].copy_from_slice(&y[n..]);
                self.model.accel(t, &y[..n], &y[n..], &mut f[n..]);
                self.derivative = Derivative::Current;
                Ok(())
            }
            Derivative::Stale => {
                // Evaluated, counted and checked; on a failure it stays stale.
                let t = self.state.t;
                self.state.evals += 1;
                if let Some(flow) = self.flow.as_mut() {
                    flow.deriv(t, &self.state.y, &mut self.state.f);
                    if let Some(e) = flow.failure.take() {
                        return Err(e);
                    }
                } else {
                    let mut y = std::mem::take(&mut self.state.y);
                    let mut f = std::mem::take(&mut self.state.f);
                    self.parts().deriv(t, &y, &mut f);
                    std::mem::swap(&mut self.state.y, &mut y);
                    std::mem::swap(&mut self.state.f, &mut f);
                    if let Some(e) = self.model.failure.take() {
                        return Err(e);
                    }
                }
                self.derivative_finite()?;
                self.derivative = Derivative::Current;
                Ok(())
            }
        }
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
                let bad = |v: &f64| crate::limits::runaway(*v);
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

#[cfg(test)]
mod tests {
    use super::World;
    use crate::flows::Flow;
    use crate::forces::Force;
    use crate::world::{BodyParams, WorldParams};

    /// Where `positions` and `velocities` live.
    fn buffers(w: &World) -> [*const f64; 2] {
        [w.positions().as_ptr(), w.velocities().as_ptr()]
    }

    /// Everything but adding parts writes the state in place: the contract the Python face's
    /// zero-copy views rest on. Every method, on particles, on particles with a body, and on
    /// a flow; a step that fails (and is rolled back) included.
    #[test]
    fn only_adding_parts_moves_the_state() {
        let (mut bodies, mut flows) = (0, 0);
        for method in crate::integrators::registry::names() {
            let params = |dim| WorldParams { dim, method: method.into(), ..WorldParams::default() };
            let mut worlds = Vec::new();
            let mut w = World::new(params(3)).unwrap();
            w.add_particles(&[0.0, 0.0, 1.0, 1.0, 0.0, 0.0], None, None, false).unwrap();
            w.add_force(Force::Gravity { g: [0.0, 0.0, -9.8] }).unwrap();
            worlds.push(w.clone());
            let spinning = BodyParams { angular_velocity: [0.1, 2.0, 0.3], ..BodyParams::default() };
            if w.add_body(&spinning).is_ok() {
                worlds.push(w);
                bodies += 1;
            }
            let lorenz = Flow::Lorenz { sigma: 10.0, rho: 28.0, beta: 8.0 / 3.0 };
            if let Ok(f) = World::with_flow(lorenz, &[1.0, 1.0, 1.0], params(3)) {
                worlds.push(f);
                flows += 1;
            }
            for mut w in worlds {
                let at = buffers(&w);
                let snap = w.snapshot();
                w.step(3).unwrap();
                w.advance(0.05).unwrap();
                w.restore(&snap).unwrap();
                let x = w.positions().to_vec();
                w.set_positions(&x).unwrap();
                if w.flow().is_none() {
                    let v = w.velocities().to_vec();
                    w.set_velocities(&v).unwrap();
                }
                w.set_phase(&w.phase()).unwrap();
                let _ = w.accelerations().unwrap();
                assert!(w.step_by(f64::NAN).is_err());
                let mut far = w.positions().to_vec();
                far[0] = 0.999e100;
                w.set_positions(&far).unwrap();
                // Velocities that carry x past the runaway bound (a flow runs away by itself).
                if w.flow().is_none() {
                    let v: Vec<f64> = w.velocities().iter().map(|_| 1e99).collect();
                    w.set_velocities(&v).unwrap();
                }
                assert!(w.step_by(1.0).is_err(), "{method}: a step past the runaway bound fails");
                assert_eq!(buffers(&w), at, "{method}: the state moved");
                let [y, _] = w.detach_state();
                assert_eq!(y.as_ptr(), at[0]);
                assert_ne!(buffers(&w)[0], at[0]);
            }
        }
        assert!(bodies > 5 && flows > 5, "{bodies} worlds with a body, {flows} flows");
    }
}
