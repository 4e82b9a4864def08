//! The step of a world: the public calls that take steps ([`World::step`], [`World::advance`]
//! and the rest), and one step as named stages over a [`StepContext`]:
//!
//! ```text
//! ctx        = StepContext::new(...)   // h validated once, here; t + h must move time
//! Integrate    the method runs its recipe; forces are evaluated inside it
//! Relax        position constraints projected; velocities and method memory resynced
//! Collide      contacts of balls found by the grid and resolved at their time of impact
//! Check        a non-finite or runaway state is a divergence: which part, which index
//! Finish       t = t0 + k h; or, on any failure, the world restored from its checkpoint
//! ```

use super::{Epoch, Frame, World};
use crate::clock::Clock;
use crate::dynamics::{First, Second, SecondOrder};
use crate::error::{Error, Result};
use crate::integrators::Log;

/// What every stage of one step sees, validated once when the step starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepContext {
    /// Time at the start of the step, s.
    pub t: f64,
    /// The step, s (finite, > 0).
    pub h: f64,
    /// `1 / h`, 1/s (velocity from a position change, as Verlet-style stages need).
    pub inv_h: f64,
    /// Index of this step (steps taken before it).
    pub step: u64,
    /// Time at the end of the step: `t0 + k h` since the last change of `h`.
    pub t_end: f64,
    pub(super) epoch: Epoch,
    /// Whether this is the last step of its call: the Collide stage then measures the
    /// balls' overlaps at its end itself (else the next step's scan of the grid does).
    pub(super) last: bool,
}

/// The stages of a step, named in failures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The method's recipe (forces inside).
    Integrate,
    /// Position constraints.
    Relax,
    /// Contacts.
    Collide,
    /// The divergence check.
    Check,
}

/// The stepping API: calls of steps and frames of the game loop.
impl World {
    /// Takes `n` steps of the fixed dt.
    ///
    /// # Errors
    /// [`Error::Diverged`] or [`Error::NotConverged`]: the failing step is rolled back, the
    /// steps before it stay taken.
    pub fn step(&mut self, n: u64) -> Result<()> {
        self.run(n, self.dt())
    }

    /// `n` steps of `dt` seconds (not necessarily the fixed one), as [`World::step`] takes
    /// them: a failing step is rolled back, the steps before it stay taken.
    ///
    /// # Errors
    /// As [`World::step_by`].
    pub fn step_n_by(&mut self, n: u64, dt: f64) -> Result<()> {
        self.run(n, dt)
    }

    /// One step of `dt` seconds (not necessarily the fixed one).
    ///
    /// # Errors
    /// As [`World::step`], and [`Error::InvalidValue`] for a bad `dt`.
    pub fn step_by(&mut self, dt: f64) -> Result<()> {
        self.run(1, dt)
    }

    /// [`World::step_by`] that records the intermediate evaluation points (midpoint's half
    /// step, RK4's xa, xb, xc).
    ///
    /// # Errors
    /// As [`World::step_by`].
    pub fn step_logged(&mut self, dt: f64, log: &mut crate::integrators::StageLog) -> Result<()> {
        self.step_inner(dt, Some(log))
    }

    /// Runs one frame of the game loop: `frame_time` seconds of wall time become fixed steps
    /// as the loop mode says, with the frame-time clamp and the steps-per-frame cap.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a bad `frame_time`; a failing step as [`World::step`].
    pub fn advance(&mut self, frame_time: f64) -> Result<Frame> {
        let plan = self.clock.frame(frame_time)?;
        if plan.steps > 0 {
            self.run(u64::from(plan.steps) - 1, plan.dt)?;
            // The state before the frame's last step, for render interpolation; the buffer
            // is reused from frame to frame.
            let mut prev = std::mem::take(&mut self.prev_x);
            prev.clear();
            prev.extend_from_slice(self.positions());
            self.keep_orientations();
            self.run(1, plan.dt)?;
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
}

impl World {
    /// The context of the next step of `h` seconds.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `dt` when `h` is not a finite number > 0 or too small
    /// to move the current time.
    pub(super) fn context(&self, h: f64) -> Result<StepContext> {
        crate::error::positive("dt", h)?;
        let epoch = if h == self.epoch.dt {
            self.epoch
        } else {
            Epoch { t: self.state.t, steps: self.state.steps, dt: h }
        };
        // Time as t0 + k h since the last change of h: no drift from repeated addition, so
        // t = 10 after 100 steps of 0.1. Time must move: a step below the resolution of t
        // would step forever in place.
        let t_end = epoch.time(self.state.steps + 1).unwrap_or(f64::NAN);
        if !(t_end > self.state.t && t_end.is_finite()) {
            return Err(Error::invalid(
                "dt",
                crate::error::num(h),
                format!("large enough to advance the time t = {} (t + dt == t)", self.state.t),
            ));
        }
        Ok(StepContext {
            t: self.state.t,
            h,
            inv_h: 1.0 / h,
            step: self.state.steps,
            t_end,
            epoch,
            last: true,
        })
    }

    /// One step of `h` seconds, stage by stage; a failure leaves the world exactly as it was
    /// before the step (state, time, the method's memory) and is reported once.
    pub(super) fn step_inner(&mut self, h: f64, log: Log<'_>) -> Result<()> {
        let ctx = self.context(h)?;
        self.refresh()?;
        self.checkpoint.save(&self.state, &self.integrator, self.layout());
        // Interpolation is between the last two states of a frame of `advance`; outside it
        // the current positions are drawn as they are.
        self.prev_x.clear();
        self.balls_begin();
        let r = self
            .integrate(&ctx, log)
            .and_then(|()| self.relax(&ctx))
            .and_then(|()| self.collide(&ctx))
            .and_then(|()| self.check(&ctx));
        self.finish(&ctx, r)
    }

    /// One step of `h` seconds without a checkpoint of its own, for a call that keeps one
    /// checkpoint for all its steps ([`World::run`]): on failure the world is left part-way
    /// and the caller restores its checkpoint. `last`: the call's last step.
    pub(super) fn step_unsaved(&mut self, h: f64, last: bool) -> Result<()> {
        let ctx = StepContext { last, ..self.context(h)? };
        self.refresh()?;
        self.prev_x.clear();
        self.balls_begin();
        self.integrate(&ctx, None)
            .and_then(|()| self.relax(&ctx))
            .and_then(|()| self.collide(&ctx))
            .and_then(|()| self.check(&ctx))?;
        self.finish(&ctx, Ok(()))
    }

    /// Integrate: the method's recipe over the world's parts.
    fn integrate(&mut self, ctx: &StepContext, log: Log<'_>) -> Result<()> {
        self.keep_start();
        if let Some(flow) = self.flow.as_mut() {
            let r = self.integrator.advance(&mut First(flow), &mut self.state, ctx.h, log);
            return match flow.failure.take() {
                Some(e) => Err(e),
                None => r,
            };
        }
        let r = if self.bodies.is_empty() {
            self.integrator.advance(&mut Second(&mut self.model), &mut self.state, ctx.h, log)
        } else {
            let mut parts = super::parts::of(&mut self.model, &self.bodies, &mut self.body_loads);
            parts.lazy = self.lazy_rate;
            self.integrator.advance(&mut parts, &mut self.state, ctx.h, log)
        };
        // A user force that failed poisoned the accelerations; its own error is the news.
        match self.model.failure.take() {
            Some(e) => Err(e),
            None => r,
        }
    }

    /// Relax: position constraints projected, velocities and method memory resynced
    /// (`world/constraints.rs`).
    fn relax(&mut self, ctx: &StepContext) -> Result<()> {
        self.relax_constraints(ctx)
    }

    /// Collide: contacts of balls with balls and walls, at their time of impact
    /// (`world/balls.rs`).
    fn collide(&mut self, ctx: &StepContext) -> Result<()> {
        self.collide_balls(ctx)
    }

    /// Check: a NaN, an infinity or a runaway value anywhere is a divergence, named by the
    /// particle or body it belongs to.
    fn check(&self, ctx: &StepContext) -> Result<()> {
        self.integrator.check(&self.state, self.layout()).map_err(|e| match e {
            Error::Diverged { method, index, .. } => {
                let (particle, body) = self.owner(index);
                Error::Diverged { method, step: ctx.step, t: ctx.t, index, particle, body }
            }
            other => other,
        })
    }

    /// The particle or body entry `index` of the state belongs to.
    fn owner(&self, index: usize) -> (Option<usize>, Option<usize>) {
        use crate::rigid::body::{V_LEN, X_LEN};
        if self.flow.is_some() {
            return (None, None);
        }
        let (np, nx) = (self.model.len(), self.nx());
        let (j, per) = if index < nx { (index, X_LEN) } else { (index - nx, V_LEN) };
        if j < np {
            (Some(j / self.dim()), None)
        } else {
            (None, Some((j - np) / per))
        }
    }

    /// Finish: count the step and set the time once; or restore the checkpoint.
    pub(super) fn finish(&mut self, ctx: &StepContext, r: Result<()>) -> Result<()> {
        match r {
            Ok(()) => {
                self.clear_loads();
                self.epoch = ctx.epoch;
                self.state.steps += 1;
                self.state.t = ctx.t_end;
                Ok(())
            }
            Err(e) => {
                let layout = self.layout();
                self.checkpoint.restore(&mut self.state, &mut self.integrator, layout);
                self.balls.stats = self.balls.saved;
                Err(e)
            }
        }
    }
}
