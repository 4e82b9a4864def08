//! The world: particles, forces, an integrator and the fixed-timestep clock.
//!
//! State is structure of arrays on flat slices: `x`, `v` and `a` of length `n * dim`
//! (particle `p`, axis `k` at `p * dim + k`), kept apart from the per-particle parameters
//! (mass, inverse mass). [`World::step`] reads as its phases: integrate (which evaluates the
//! forces as often as the method needs), then diagnostics (a non-finite value rolls the step
//! back and is reported).

use crate::clock::{Clock, ClockParams, FramePlan, LoopMode};
use crate::dynamics::SecondOrder;
use crate::error::{all_finite, positive, Error, Result};
use crate::forces::{Force, ForceSet};
use crate::integrators::registry::State;
use crate::integrators::{ImplicitParams, Integrator};

/// How to build a [`World`].
#[derive(Debug, Clone, PartialEq)]
pub struct WorldParams {
    /// Spatial dimensions, 1 to 3.
    pub dim: usize,
    /// Registry name of the integrator.
    pub method: String,
    /// Fixed step, s.
    pub dt: f64,
    /// The loop variant of [`World::advance`].
    pub mode: LoopMode,
    /// At most this many steps per frame (spiral-of-death guard).
    pub max_steps_per_frame: u32,
    /// Frame times are clamped to this, s.
    pub max_frame_time: f64,
    /// Newton settings of the implicit methods.
    pub implicit: ImplicitParams,
}

impl Default for WorldParams {
    fn default() -> Self {
        let c = ClockParams::default();
        Self {
            dim: 2,
            method: "symplectic-euler".into(),
            dt: c.dt,
            mode: c.mode,
            max_steps_per_frame: c.max_steps_per_frame,
            max_frame_time: c.max_frame_time,
            implicit: ImplicitParams::default(),
        }
    }
}

/// The force model: what the integrators see as a [`SecondOrder`] system.
#[derive(Debug, Clone, Default)]
pub struct Model {
    dim: usize,
    mass: Vec<f64>,
    inv_mass: Vec<f64>,
    forces: ForceSet,
    scratch: Vec<f64>,
}

impl SecondOrder for Model {
    #[inline]
    fn len(&self) -> usize {
        self.mass.len() * self.dim
    }

    #[inline]
    fn accel(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        let n = x.len();
        if self.scratch.len() != n {
            self.scratch.resize(n, 0.0);
        }
        self.forces.accel(self.dim, t, x, v, &self.mass, &self.inv_mass, &mut self.scratch, a);
    }

    fn velocity_dependent(&self) -> bool {
        self.forces.velocity_dependent()
    }

    fn jacobian(&mut self, t: f64, x: &[f64], v: &[f64], dadx: &mut [f64], dadv: &mut [f64]) -> bool {
        self.forces.jacobian(self.dim, t, x, v, &self.inv_mass, dadx, dadv)
    }
}

impl Model {
    /// Masses, kg (infinite for static particles).
    #[must_use]
    pub fn mass(&self) -> &[f64] {
        &self.mass
    }

    /// The forces.
    #[must_use]
    pub fn forces(&self) -> &ForceSet {
        &self.forces
    }

    /// Potential energy of positions `x`, J.
    #[must_use]
    pub fn potential(&self, x: &[f64]) -> f64 {
        self.forces.potential(self.dim, x, &self.mass)
    }

    /// Kinetic energy of velocities `v`, J (static particles excluded).
    #[must_use]
    pub fn kinetic(&self, v: &[f64]) -> f64 {
        let mut e = 0.0;
        for (p, (m, w)) in self.mass.iter().zip(&self.inv_mass).enumerate() {
            if *w > 0.0 {
                let vp = &v[p * self.dim..(p + 1) * self.dim];
                e += 0.5 * m * vp.iter().map(|c| c * c).sum::<f64>();
            }
        }
        e
    }
}

/// What one call of [`World::advance`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The clock's plan: steps, their dt, time clamped and dropped.
    pub plan: FramePlan,
    /// Render interpolation factor after the frame, in [0, 1).
    pub alpha: f64,
}

/// Particles, forces, an integrator and a fixed-timestep clock.
#[derive(Debug, Clone)]
pub struct World {
    model: Model,
    integrator: Integrator,
    state: State,
    clock: Clock,
    /// Positions before the latest step, for render interpolation.
    prev_x: Vec<f64>,
    /// Whether `state.f` must be re-evaluated (after particles, forces or state changed).
    stale: bool,
    /// Time and step count at the latest change of dt.
    epoch: Epoch,
    /// Newton settings for implicit methods, kept across [`World::set_method`].
    implicit: ImplicitParams,
}

/// Where time was when dt last changed: `t = epoch.t + (steps - epoch.steps) * dt`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Epoch {
    t: f64,
    steps: u64,
    dt: f64,
}

const MAGIC: &[u8; 8] = b"PHSTEP01";

impl World {
    /// An empty world.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for `dim` outside 1..=3 or bad clock settings;
    /// [`Error::UnknownName`] for an unknown method.
    pub fn new(params: WorldParams) -> Result<Self> {
        if !(1..=3).contains(&params.dim) {
            return Err(Error::invalid("dim", params.dim, "1, 2 or 3"));
        }
        let integrator = Integrator::with_params(&params.method, params.implicit)?;
        let clock = Clock::new(ClockParams {
            dt: params.dt,
            mode: params.mode,
            max_steps_per_frame: params.max_steps_per_frame,
            max_frame_time: params.max_frame_time,
        })?;
        let model = Model { dim: params.dim, ..Model::default() };
        let state = State { t: 0.0, y: Vec::new(), f: Vec::new(), steps: 0, evals: 0 };
        Ok(Self {
            model,
            integrator,
            state,
            clock,
            prev_x: Vec::new(),
            stale: false,
            epoch: Epoch::default(),
            implicit: params.implicit,
        })
    }

    /// Spatial dimensions.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.model.dim
    }

    /// Number of particles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.model.mass.len()
    }

    /// Whether the world has no particles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.model.mass.is_empty()
    }

    /// Adds one particle; `mass = inf` or `is_static` makes it immovable (inverse mass 0,
    /// velocity held at 0). Returns its index. Each call moves the velocity half of the state
    /// (O(n)); add many particles with [`World::add_particles`] (the Python face batches
    /// `add_particle` calls itself).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `position`, `velocity` or `mass` (> 0 unless static,
    /// NaN never); the world is unchanged.
    pub fn add_particle(
        &mut self,
        position: &[f64],
        velocity: &[f64],
        mass: f64,
        is_static: bool,
    ) -> Result<usize> {
        let i = self.len();
        self.add_particles(position, Some(velocity), Some(&[mass]), is_static)?;
        Ok(i)
    }

    /// Adds `k` particles from flat `positions` (`k * dim`), optional `velocities` (zero when
    /// `None`) and `masses` (1 kg when `None`). Returns the index of the first.
    ///
    /// # Errors
    /// As [`World::add_particle`], naming the first bad entry (`positions[5]`); the world is
    /// unchanged.
    pub fn add_particles(
        &mut self,
        positions: &[f64],
        velocities: Option<&[f64]>,
        masses: Option<&[f64]>,
        is_static: bool,
    ) -> Result<usize> {
        self.check_particles(positions, velocities, masses)?;
        let d = self.dim();
        let k = positions.len() / d;
        let first = self.len();
        let n_old = self.model.len();
        // y = [x; v] and f = [v; a] grow in place: the new positions go between the old
        // positions and the velocities, so only the velocity half moves.
        self.state.y.splice(n_old..n_old, positions.iter().copied());
        for p in 0..k {
            let m = masses.map_or(1.0, |m| m[p]);
            let fixed = is_static || m.is_infinite();
            match velocities {
                Some(v) if !fixed => self.state.y.extend_from_slice(&v[p * d..(p + 1) * d]),
                _ => self.state.y.extend(std::iter::repeat_n(0.0, d)),
            }
            self.model.mass.push(m);
            self.model.inv_mass.push(if fixed { 0.0 } else { 1.0 / m });
        }
        self.state.f.resize(self.state.y.len(), 0.0);
        self.touch();
        Ok(first)
    }

    /// Checks particles as [`World::add_particles`] would, without adding them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the first bad entry: `position[i]`, `velocity[i]`
    /// (flat indices into the given arrays), `mass` / `mass[i]` (> 0, NaN never; finite when
    /// n-body gravity is on), or a length that does not fit `dim`.
    pub fn check_particles(
        &self,
        positions: &[f64],
        velocities: Option<&[f64]>,
        masses: Option<&[f64]>,
    ) -> Result<()> {
        let d = self.dim();
        if positions.len() % d != 0 {
            return Err(Error::invalid(
                "len(positions)",
                positions.len(),
                format!("a multiple of dim = {d}"),
            ));
        }
        let k = positions.len() / d;
        all_finite("position", positions)?;
        if let Some(v) = velocities {
            if v.len() != positions.len() {
                return Err(Error::invalid(
                    "len(velocity)",
                    v.len(),
                    format!("{}, like the positions", positions.len()),
                ));
            }
            all_finite("velocity", v)?;
        }
        if let Some(m) = masses {
            if m.len() != k {
                return Err(Error::invalid("len(mass)", m.len(), format!("{k}, one per particle")));
            }
            for (i, &mi) in m.iter().enumerate() {
                let field = if k == 1 { "mass".to_string() } else { format!("mass[{i}]") };
                if mi.is_nan() || mi <= 0.0 {
                    return Err(Error::invalid(field, mi, "> 0 (inf for a static particle)"));
                }
            }
            // Forces that need finite masses (n-body) must accept the new particles too;
            // named by the index they would get in the world.
            if self.model.forces.needs_finite_masses() {
                crate::forces::finite_masses(m, self.len())?;
            }
        }
        Ok(())
    }

    /// Adds a force generator.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the bad field (a missing particle index, a negative
    /// stiffness, a zero rod length, ...); the world is unchanged.
    pub fn add_force(&mut self, force: Force) -> Result<()> {
        if matches!(force, Force::NBody { .. }) {
            // n-body gravity pulls with every mass: none may be infinite.
            crate::forces::finite_masses(&self.model.mass, 0)?;
        }
        // `add` validates before it inserts, so a rejected force leaves the set as it was.
        self.model.forces.add(force, self.len(), self.dim())?;
        self.touch();
        Ok(())
    }

    /// The force model (forces, masses, energies).
    #[must_use]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Marks the derivative stale and restarts stateful integrators (the state was changed
    /// by hand).
    fn touch(&mut self) {
        self.stale = true;
        self.integrator.reset();
    }

    /// Re-evaluates the acceleration if anything changed since the last step.
    fn refresh(&mut self) {
        if self.stale {
            let n = self.model.len();
            let (x, v) = self.state.y.split_at(n);
            let (dx, a) = self.state.f.split_at_mut(n);
            dx.copy_from_slice(v);
            self.model.accel(self.state.t, x, v, a);
            self.state.evals += 1;
            self.stale = false;
        }
    }

    /// The integrator in use.
    #[must_use]
    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }

    /// Switches the integrator (implicit methods use the world's Newton settings).
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the valid names.
    pub fn set_method(&mut self, name: &str) -> Result<()> {
        self.integrator = Integrator::with_params(name, self.implicit)?;
        Ok(())
    }

    /// The fixed step, s.
    #[must_use]
    pub fn dt(&self) -> f64 {
        self.clock.params().dt
    }

    /// Changes the fixed step; stateful integrators handle the change as their docs say.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `dt`.
    pub fn set_dt(&mut self, dt: f64) -> Result<()> {
        self.clock.retime(dt)
    }

    /// Takes `n` steps of the fixed dt.
    ///
    /// # Errors
    /// [`Error::Diverged`] or [`Error::NotConverged`]: the failing step is rolled back, the
    /// steps before it stay taken.
    pub fn step(&mut self, n: u64) -> Result<()> {
        let dt = self.dt();
        for _ in 0..n {
            self.step_by(dt)?;
        }
        Ok(())
    }

    /// One step of `dt` seconds (not necessarily the fixed one).
    ///
    /// # Errors
    /// As [`World::step`], and [`Error::InvalidValue`] for a bad `dt`.
    pub fn step_by(&mut self, dt: f64) -> Result<()> {
        self.step_inner(dt, None)
    }

    /// [`World::step_by`] that records the intermediate evaluation points (midpoint's half
    /// step, RK4's xa, xb, xc).
    ///
    /// # Errors
    /// As [`World::step_by`].
    pub fn step_logged(&mut self, dt: f64, log: &mut crate::integrators::StageLog) -> Result<()> {
        self.step_inner(dt, Some(log))
    }

    fn step_inner(&mut self, dt: f64, log: crate::integrators::Log<'_>) -> Result<()> {
        positive("dt", dt)?;
        self.refresh();
        let n = self.model.len();
        if dt != self.epoch.dt {
            self.epoch = Epoch { t: self.state.t, steps: self.state.steps, dt };
        }
        let r = self.integrator.step_logged(&mut self.model, &mut self.state, dt, log);
        // Interpolation is between the last two states of a frame of `advance`; outside it
        // the current positions are drawn as they are.
        self.prev_x.clear();
        match r {
            // Time as t0 + k dt since the last change of dt: no drift from repeated addition,
            // so t = 10 after 100 steps of 0.1.
            Ok(()) => {
                self.state.t = self.epoch.t + (self.state.steps - self.epoch.steps) as f64 * dt;
                Ok(())
            }
            Err(mut e) => {
                if let Error::Diverged { index, particle, .. } = &mut e {
                    *particle = Some((*index % n.max(1)) / self.dim());
                }
                Err(e)
            }
        }
    }

    /// Runs one frame of the game loop: `frame_time` seconds of wall time become fixed steps
    /// as the loop mode says, with the frame-time clamp and the steps-per-frame cap.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a bad `frame_time`; a failing step as [`World::step`].
    pub fn advance(&mut self, frame_time: f64) -> Result<Frame> {
        let plan = self.clock.frame(frame_time)?;
        for k in 0..plan.steps {
            if k + 1 < plan.steps {
                self.step_inner(plan.dt, None)?;
                continue;
            }
            // The state before the frame's last step, for render interpolation; the buffer
            // is reused from frame to frame.
            let mut prev = std::mem::take(&mut self.prev_x);
            prev.clear();
            prev.extend_from_slice(self.positions());
            self.step_inner(plan.dt, None)?;
            self.prev_x = prev;
        }
        Ok(Frame { plan, alpha: self.clock.alpha() })
    }

    /// The clock (loop mode, stats).
    #[must_use]
    pub fn clock(&self) -> &Clock {
        &self.clock
    }

    /// Render interpolation factor in [0, 1) after the latest [`World::advance`].
    #[must_use]
    pub fn alpha(&self) -> f64 {
        self.clock.alpha()
    }

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
        &self.state.y[..self.model.len()]
    }

    /// Velocities, m/s (flat, `n * dim`).
    #[must_use]
    pub fn velocities(&self) -> &[f64] {
        &self.state.y[self.model.len()..]
    }

    /// Accelerations at the current state, m/s^2 (flat, `n * dim`).
    pub fn accelerations(&mut self) -> &[f64] {
        self.refresh();
        &self.state.f[self.model.len()..]
    }

    /// Sets every position (flat, `n * dim`).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a wrong length or a non-finite entry; nothing changes.
    pub fn set_positions(&mut self, x: &[f64]) -> Result<()> {
        let n = self.model.len();
        if x.len() != n {
            return Err(Error::invalid("len(positions)", x.len(), format!("{n}")));
        }
        all_finite("position", x)?;
        self.state.y[..n].copy_from_slice(x);
        self.touch();
        Ok(())
    }

    /// Sets every velocity (flat, `n * dim`); static particles keep velocity 0.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a wrong length or a non-finite entry; nothing changes.
    pub fn set_velocities(&mut self, v: &[f64]) -> Result<()> {
        let n = self.model.len();
        if v.len() != n {
            return Err(Error::invalid("len(velocities)", v.len(), format!("{n}")));
        }
        all_finite("velocity", v)?;
        let d = self.dim();
        for (i, (dst, src)) in self.state.y[n..].iter_mut().zip(v).enumerate() {
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

    /// Kinetic plus potential energy, J.
    #[must_use]
    pub fn energy(&self) -> f64 {
        self.model.kinetic(self.velocities()) + self.model.potential(self.positions())
    }

    /// Total momentum of the dynamic particles, kg m/s (`dim` components).
    #[must_use]
    pub fn momentum(&self) -> Vec<f64> {
        let d = self.dim();
        let mut p = vec![0.0; d];
        for (i, vi) in self.velocities().iter().enumerate() {
            if self.model.inv_mass[i / d] > 0.0 {
                p[i % d] += self.model.mass[i / d] * vi;
            }
        }
        p
    }

    /// The whole dynamic state as bytes: time, steps, positions, velocities, the
    /// integrator's memory and the clock's accumulator. [`World::restore`] puts it back
    /// bitwise, so a restored run continues exactly as an uninterrupted one.
    #[must_use]
    pub fn snapshot(&self) -> Vec<u8> {
        let memory = self.integrator.memory();
        let mut out = Vec::with_capacity(64 + 8 * (self.state.y.len() + memory.len()));
        out.extend_from_slice(MAGIC);
        let name = self.integrator.info().name.as_bytes();
        for word in
            [self.dim() as u64, self.len() as u64, name.len() as u64, self.state.steps, self.state.evals]
        {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(name);
        let [hi, lo] = self.clock.balance();
        // Before the first step (or after particles were added) there are no previous
        // positions of this particle count; the current ones interpolate the same way.
        let prev_x = if self.prev_x.len() == self.model.len() { &self.prev_x[..] } else { self.positions() };
        let e = self.epoch;
        for v in [self.state.t, hi, lo, e.t, e.steps as f64, e.dt, memory.len() as f64]
            .iter()
            .chain(&self.state.y)
            .chain(&memory)
            .chain(prev_x)
        {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out
    }

    /// Restores a [`World::snapshot`] of this world (same dimensions, particle count and
    /// method).
    ///
    /// # Errors
    /// [`Error::Corrupt`] when the bytes are not such a snapshot; the world is unchanged.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<()> {
        let corrupt = |reason: &str| Error::Corrupt { reason: reason.into() };
        let rest = bytes.strip_prefix(MAGIC.as_slice()).ok_or_else(|| corrupt("not a physstep snapshot"))?;
        let word = |i: usize| -> Result<u64> {
            rest.get(i * 8..i * 8 + 8)
                .map(|b| u64::from_le_bytes(b.try_into().unwrap_or_default()))
                .ok_or_else(|| corrupt("truncated header"))
        };
        let (dim, n, name_len, steps, evals) = (word(0)?, word(1)?, word(2)?, word(3)?, word(4)?);
        if dim != self.dim() as u64 || n != self.len() as u64 {
            return Err(corrupt(&format!(
                "snapshot has {n} particles in {dim}D, this world {} in {}D",
                self.len(),
                self.dim()
            )));
        }
        let rest = &rest[40..];
        let name_len = usize::try_from(name_len).map_err(|_| corrupt("bad method name"))?;
        let name = rest.get(..name_len).ok_or_else(|| corrupt("truncated method name"))?;
        if name != self.integrator.info().name.as_bytes() {
            return Err(corrupt(&format!(
                "snapshot was taken with method '{}', this world uses '{}'",
                String::from_utf8_lossy(name),
                self.integrator.info().name
            )));
        }
        let floats: Vec<f64> = rest[name_len..]
            .chunks(8)
            .map(|c| c.try_into().map(f64::from_le_bytes).map_err(|_| corrupt("truncated data")))
            .collect::<Result<_>>()?;
        let ny = 2 * self.model.len();
        let nx = self.model.len();
        let [t, hi, lo, et, es, edt, nm, data @ ..] = floats.as_slice() else {
            return Err(corrupt("truncated data"));
        };
        // The memory length is what is left after the state and the previous positions; the
        // stored length must agree (a damaged one, huge or NaN, must not overflow a sum).
        let nm = data
            .len()
            .checked_sub(ny + nx)
            .filter(|m| *m as f64 == *nm)
            .ok_or_else(|| corrupt("data length does not match the world"))?;
        let mut integrator = self.integrator.clone();
        integrator.recall(&data[ny..ny + nm])?;
        self.integrator = integrator;
        self.state.t = *t;
        self.epoch = Epoch { t: *et, steps: *es as u64, dt: *edt };
        self.state.steps = steps;
        self.state.evals = evals;
        self.state.y.copy_from_slice(&data[..ny]);
        self.prev_x = data[ny + nm..].to_vec();
        self.clock.restore_balance([*hi, *lo]);
        // The derivative is a function of the state: recompute it without counting it, so
        // the evaluation count matches an uninterrupted run.
        self.stale = true;
        self.refresh();
        self.state.evals = evals;
        Ok(())
    }

    /// A 64-bit hash of the dynamic state (time, positions, velocities, integrator memory):
    /// equal for bitwise-equal states, different after any change.
    #[must_use]
    pub fn state_hash(&self) -> u64 {
        // FNV-1a over the bit patterns.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |v: f64| {
            for b in v.to_bits().to_le_bytes() {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        eat(self.state.t);
        self.state.y.iter().for_each(|v| eat(*v));
        self.integrator.memory().iter().for_each(|v| eat(*v));
        h
    }
}
