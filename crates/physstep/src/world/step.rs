//! The step of a world: the public calls that take steps ([`World::step`], [`World::advance`]
//! and the rest), and the one loop every call of steps runs ([`World::run`]), its stages
//! over a [`StepContext`]:
//!
//! ```text
//! ctx        = StepContext          h validated once per step; t0 + (k + 1) h must move time
//! Integrate    the method's recipe over the parts (forces inside), by the implementation
//!              chosen once for the call (`Integrate`): one staged step, one step from the
//!              stored derivative (particles under any forces, a method that reads only its
//!              start, or that evaluates forces ignoring v once at a point of its own), or
//!              every step left by the fused particle kernel or the split loop of bodies
//!              (these check their steps themselves: Relax and Collide have nothing to do in
//!              their worlds); the particle kernels' Integrate is in `kernel.rs`
//! Relax        position constraints projected; velocities and method memory resynced
//! Collide      contacts of balls found by the grid and resolved at their time of impact
//! Contact      solids advanced by the contact solver (its substeps; contacts, friction)
//! Check        a non-finite or runaway state is a divergence: which part, which index
//! Finish       steps += k, t = t0 + k h (`Epoch::time`); on a failure, the `Rollback`
//! ```
//!
//! A failure goes back to the call's [`Rollback`] when its steps can be replayed (no user code
//! ran, no load by hand waited), replays the good steps (the same bits) and takes the failing
//! step again staged with a rollback of its own, which fails the same way and names the
//! particle; else each step keeps its own rollback and a failure goes back to it.

use super::kernel::Row;
use super::rollback::{Epoch, Keep, Rollback};
use super::{Derivative, Frame, World};
use crate::clock::Clock;
use crate::dynamics::{First, Second, SecondOrder};
use crate::error::{Error, Result};
use crate::integrators::{Integrator, Log};

/// What every stage of one step sees, validated once when the step starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepContext {
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
    /// Whether the fused kernel keeps the state at its start in the rollback as it reads it
    /// (else the rollback is one an earlier fused call kept, reused).
    pub(super) save: bool,
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
        self.steps_as(Integrate::Staged, 1, dt, Checkpoints::Step, Some(log), None::<&mut NoRows>)
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
            self.keep_solid_poses();
            let (q, solids) = (std::mem::take(&mut self.prev_q), std::mem::take(&mut self.prev_solids));
            self.run(1, plan.dt)?;
            self.prev_x = prev;
            (self.prev_q, self.prev_solids) = (q, solids);
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

/// How the Integrate stage of a call takes its steps, chosen once per call ([`World::plan`]).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // a value of one call, on the stack: boxed, every call would allocate
enum Integrate {
    /// The fused particle kernel (`kernel.rs`) with a fresh local method: every step left in
    /// the call, tile by tile, each checked in registers.
    Fused(Integrator),
    /// Particles under any forces (a Python force, springs between them, n-body gravity) by
    /// a method whose step reads only the derivative at its start: one step a pass, the
    /// element-wise kernel from the stored accelerations (the state at the start kept as it
    /// is read, the new state checked in registers), then the forces evaluated at the end as
    /// the staged step evaluates them, into a derivative written beside the current one and
    /// swapped in on success; or by a method that evaluates forces that do not read the
    /// velocity once, at a point of its own (`GivenKind::Point`: the state put there first, the
    /// step's end after the evaluation) (`kernel.rs` `World::given`).
    Given(Integrator, super::kernel::GivenKind),
    /// Particles and bodies under a split method, nothing else to do (no constraint, ball,
    /// load by hand or user code): the parts built once for every step left, each checked;
    /// the bodies' `dX` left out of `f` (no split method reads it; computed when asked for).
    Split,
    /// The method's recipe over the parts, one step.
    Staged,
}

/// Where a failure goes back to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Checkpoints {
    /// To the call's start: the good steps are replayed, the failing one taken again staged
    /// with its own rollback (it fails the same way and names what failed).
    Call,
    /// To the failing step's start, kept before each step.
    Step,
    /// Nowhere: a replay of good steps, which take the same bits again.
    Replay,
}

/// A failed pass of the stages.
pub(super) enum Failure {
    /// The step after `good` good ones of the pass ran away (the fused kernel and the split
    /// loop do not name it): it is taken again staged.
    Again(u64),
    /// A stage's error.
    Error(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Self::Error(e)
    }
}

/// The row observer of calls that do not record (none is passed).
type NoRows = fn(Row<'_>) -> bool;

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
        let Some(t_end) = epoch.next(self.state.steps, self.state.t) else {
            return Err(Error::invalid(
                "dt",
                crate::error::num(h),
                format!("large enough to advance the time t = {} (t + dt == t)", self.state.t),
            ));
        };
        Ok(StepContext {
            t: self.state.t,
            h,
            inv_h: 1.0 / h,
            step: self.state.steps,
            t_end,
            epoch,
            last: true,
            save: true,
        })
    }

    /// How the Integrate stage of a call of `n` steps takes them: the fused kernel where it
    /// applies, the split loop for bodies under a split method with nothing else to do, else
    /// the staged step.
    fn plan(&self, n: u64) -> Integrate {
        if let Some(method) = self.fused() {
            return Integrate::Fused(method);
        }
        if let Some((method, from)) = self.given() {
            return Integrate::Given(method, from);
        }
        let split = !self.bodies.is_empty() && self.integrator.info().split;
        let alone = self.constraints.is_empty() && self.balls.is_empty() && self.solids.is_empty();
        if split && n >= 2 && self.replayable() && alone {
            return Integrate::Split;
        }
        Integrate::Staged
    }

    /// Whether a step can be taken again with the same result: no user code runs in it (a
    /// Python force could answer differently, or count its calls) and no load applied by hand
    /// waits for it (a step consumes those). Balls replay: their Collide stage is a function of
    /// the state (the same contacts in the same order, the same bits), and their contact
    /// statistics go back with the rollback.
    fn replayable(&self) -> bool {
        self.model.user.is_empty()
            && self.bodies.forces.is_empty()
            && self.bodies.force.iter().chain(&self.bodies.torque).all(|v| *v == glam::DVec3::ZERO)
            && self.solids.replayable()
    }

    /// Takes `n` steps of `h` seconds: a failing step is rolled back and reported, the steps
    /// before it stay taken.
    pub(super) fn run(&mut self, n: u64, h: f64) -> Result<()> {
        self.run_rows(n, h, None::<&mut NoRows>)
    }

    /// [`World::run`] with `on_row` called with the state after each good step (it stops the
    /// run after that step by returning `false`), when the world is small (one tile) and the
    /// fused kernel applies; `None` otherwise, nothing done. A recording of every step takes
    /// its rows this way, inside the kernel's loop (`on_row` compiled into it, not called
    /// through a pointer).
    pub(crate) fn run_observed<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        n: u64,
        h: f64,
        on_row: &mut F,
    ) -> Option<Result<()>> {
        let small = n > 0 && self.model.mass.len() <= super::tiles::OBSERVED_MAX;
        self.fused().filter(|_| small)?;
        Some(self.run_rows(n, h, Some(on_row)))
    }

    fn run_rows<F: FnMut(Row<'_>) -> bool>(&mut self, n: u64, h: f64, on_row: Option<&mut F>) -> Result<()> {
        if n == 0 {
            return Ok(());
        }
        let how = self.plan(n);
        let keep = match how {
            Integrate::Staged | Integrate::Given(..) if n < 2 || !self.replayable() => Checkpoints::Step,
            _ => Checkpoints::Call,
        };
        self.steps_as(how, n, h, keep, None, on_row)
    }

    /// The one step loop: `n` steps of `h` seconds, the Integrate stage taken `how`, passes
    /// of the stages until the steps are taken (or `on_row` stops the run), a failure handled
    /// as `keep` says.
    fn steps_as<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        mut how: Integrate,
        n: u64,
        h: f64,
        keep: Checkpoints,
        mut log: Log<'_>,
        mut on_row: Option<&mut F>,
    ) -> Result<()> {
        let start = self.state.steps;
        self.context(h)?;
        // A replay takes the bits of the run it replays: a stop requested meanwhile waits for
        // the steps after it.
        let _masked = (keep == Checkpoints::Replay).then(crate::interrupt::Masked::new);
        // The derivative, computed (and checked) first where the step reads it: the fused
        // kernel does not read it (only a state set by hand needs it computed), the step from
        // the stored derivative does not read its velocity half.
        let owed = match how {
            Integrate::Fused(_) => self.derivative == Derivative::Stale,
            Integrate::Given(..) => self.derivative != Derivative::VelocityOwed,
            _ => true,
        };
        if owed {
            let refreshed = self.refresh();
            if crate::interrupt::stop() {
                // The evaluation was cut short: computed again when next needed.
                self.derivative = Derivative::Stale;
                return Err(Error::Interrupted { step: self.state.steps });
            }
            refreshed?;
        }
        // Interpolation is between the last two states of a frame of `advance`; outside it
        // the current positions are drawn as they are.
        self.prev_x.clear();
        self.prev_q.clear();
        self.prev_solids.clear();
        let mut back = std::mem::take(&mut self.rollback);
        // The fused kernel keeps its rollback as it reads the state, at each pass; the others
        // keep the call's once, or each step's before it.
        let each_pass =
            keep == Checkpoints::Step || matches!(how, Integrate::Fused(_) | Integrate::Given(..));
        if keep == Checkpoints::Call && !each_pass {
            self.keep(&mut back, Keep::State);
        }
        let mut taken = 0;
        let failed = loop {
            if taken == n {
                break None;
            }
            // The fused kernel keeps the state as it reads it, unless it goes back to the
            // rollback an earlier call of it kept (a failure replays the steps since).
            let fused = matches!(how, Integrate::Fused(_));
            // (These two keep the positions as they read them.)
            let as_read = fused || matches!(how, Integrate::Given(..));
            let save = each_pass && !(fused && self.reusable(&back, h));
            let ctx = match self.context(h) {
                Ok(ctx) => StepContext { last: taken + 1 == n, save, ..ctx },
                Err(e) => break Some(Err(e)),
            };
            if save {
                self.keep(&mut back, if as_read { Keep::Positions } else { Keep::State });
            }
            let passed =
                self.pass(&ctx, &mut how, n - taken, &mut back, log.as_deref_mut(), on_row.as_deref_mut());
            if crate::interrupt::stop() && matches!(passed, Err(Failure::Error(_))) {
                // Ctrl-C, a stage cut short (n-body gravity poisons what it left unfinished):
                // back to the start of the pass, or of the call where it kept only that,
                // without a replay (it would take as long again), the work done counted. A
                // runaway in the kernel or the split loop goes the usual way (its replay does
                // not look); a pass that ended well keeps its steps (below). (The fused kernel,
                // whose rollback may be an earlier call's, fails only by running away: no
                // rollback here skips steps that a replay would have to take again.)
                debug_assert!(save || !fused, "an interrupted pass goes back to a rollback it did not keep");
                let evals = self.state.evals;
                self.roll_back(&back);
                self.state.evals = evals;
                self.rollback = back;
                return Err(Error::Interrupted { step: self.state.steps });
            }
            match passed {
                Ok((k, halted)) => {
                    taken += k;
                    if halted {
                        break None;
                    }
                    if taken < n && crate::interrupt::stop() {
                        self.rollback = back;
                        return Err(Error::Interrupted { step: self.state.steps });
                    }
                }
                // A replay takes the same bits as the run it replays: it does not fail (were it
                // to, the staged step after it would name the failure from there).
                Err(Failure::Again(_)) if keep == Checkpoints::Replay => break None,
                // The good steps, counted from the start of the world: the rollback may be
                // older than the pass (kept by the call, or by an earlier fused call).
                Err(Failure::Again(good)) => break Some(Ok(self.state.steps + good)),
                Err(Failure::Error(_)) if keep == Checkpoints::Call => break Some(Ok(self.state.steps)),
                Err(Failure::Error(e)) => {
                    if keep == Checkpoints::Step {
                        // The evaluations the failed attempt made stay counted (work done).
                        let evals = self.state.evals;
                        self.roll_back(&back);
                        self.state.evals = evals;
                    }
                    self.rollback = back;
                    return Err(e);
                }
            }
        };
        match failed {
            None => {
                self.rollback = back;
                Ok(())
            }
            // An error before a pass began (time no longer moves): the steps before it stay.
            Some(Err(e)) => {
                self.rollback = back;
                Err(e)
            }
            // Back to the rollback, the good steps since it again (the same arithmetic, the
            // same bits), then the failing step staged with its own rollback: it fails as
            // before, rolls back and names what failed. Were it to pass, the call goes on from
            // there.
            Some(Ok(good)) => {
                self.roll_back(&back);
                self.rollback = back;
                let replay = good - self.state.steps;
                self.steps_as(how, replay, h, Checkpoints::Replay, None, None::<&mut NoRows>)?;
                self.steps_as(Integrate::Staged, 1, h, Checkpoints::Step, None, None::<&mut NoRows>)?;
                let done = self.state.steps - start;
                self.run(n - done, h)
            }
        }
    }

    /// One pass of the stages: the Integrate stage takes one step, or every step left (`left`)
    /// when it is the fused kernel or the split loop; the good steps taken and whether the
    /// row observer stopped the run.
    fn pass<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        ctx: &StepContext,
        how: &mut Integrate,
        left: u64,
        back: &mut Rollback,
        log: Log<'_>,
        on_row: Option<&mut F>,
    ) -> std::result::Result<(u64, bool), Failure> {
        self.balls_begin();
        let (k, halted) = match how {
            Integrate::Fused(method) => self.integrate_fused(ctx, method, left, back, on_row)?,
            Integrate::Given(method, from) => (self.integrate_given(ctx, method, *from, back)?, false),
            Integrate::Split => (self.integrate_split(ctx, left)?, false),
            Integrate::Staged => {
                self.integrate(ctx, log)?;
                self.relax(ctx)?;
                self.collide(ctx)?;
                self.contact(ctx)?;
                self.check(ctx)?;
                (1, false)
            }
        };
        self.finish(ctx, k);
        Ok((k, halted))
    }

    /// Integrate, the split loop: up to `left` steps of the method over the parts built once,
    /// the bodies' `dX` left out, each step checked.
    fn integrate_split(&mut self, ctx: &StepContext, left: u64) -> std::result::Result<u64, Failure> {
        let layout = self.layout();
        let mut parts = super::parts::of(&mut self.model, &self.bodies, &mut self.body_loads);
        parts.lazy = true;
        let mut good = 0;
        while good < left {
            let Some(t_end) = ctx.epoch.next(ctx.step + good, self.state.t) else { break };
            if self.integrator.advance(&mut parts, &mut self.state, ctx.h, None).is_err()
                || self.integrator.check(&self.state, layout).is_err()
            {
                return Err(Failure::Again(good));
            }
            // The next step starts at this one's end (the time is set once more by Finish).
            self.state.t = t_end;
            good += 1;
        }
        self.derivative = Derivative::RatesOwed;
        Ok(good)
    }

    /// Integrate, one staged step: the method's recipe over the world's parts.
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
    pub(super) fn check(&self, ctx: &StepContext) -> Result<()> {
        self.integrator.check(&self.state, self.layout()).map_err(|e| match e {
            Error::Diverged { method, index, .. } => {
                let (particle, body) = self.owner(index);
                Error::Diverged { method, step: ctx.step, t: ctx.t, index, particle, body, solid: None }
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

    /// Finish: `k` steps counted and the time set once, `t = t0 + k h` (`Epoch::time`); the
    /// loads applied by hand consumed.
    fn finish(&mut self, ctx: &StepContext, k: u64) {
        if k == 0 {
            return;
        }
        self.clear_loads();
        self.solids.clear_applied();
        self.epoch = ctx.epoch;
        self.state.steps += k;
        self.state.t = ctx.epoch.time(self.state.steps).unwrap_or(f64::NAN);
    }
}
