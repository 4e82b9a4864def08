//! The fused particle kernels: a world of particles under per-particle forces (gravity,
//! drag, central gravity, springs to anchors) stepped by a local method (see
//! [`Integrator::fresh_local`]) takes the steps of a call of [`World::step`] through the
//! loops of [`super::tiles`]: the method's own recipe (or its element-wise form,
//! [`super::flat`]) on one tile of particles at a time, all the call's steps while the tile
//! sits in L1, the finiteness check a flag folded in registers, the accelerations not stored
//! (computed again on request, without counting an evaluation). Particles do not interact
//! under these forces, so neither the order of the work nor the thread count changes a bit:
//! the kernels and the staged step give bitwise the same trajectory.
//!
//! Rollback: one checkpoint per call instead of a copy per step. When step `k` of a call
//! fails, the world goes back to the checkpoint, replays the `k` good steps (the same
//! arithmetic, so the same bits) and takes step `k` the staged way, which fails the same
//! way, rolls back, and names the particle.

use super::flat::{self, Flat};
use super::small::{self, Elements};
use super::tiles::{self, Forces, Run};
use super::{Epoch, World};
use crate::dynamics::SecondOrder;
use crate::error::Result;
use crate::integrators::registry::{State, Visit};
use crate::integrators::{Integrator, Method};

/// Why a run of fused steps stopped before its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stop {
    /// A value or acceleration ran away: the step is to be rolled back.
    Bad,
    /// `dt` no longer moves the time.
    Time,
}

/// Up to `n` fused steps of every particle, as work for [`Integrator::visit`]: the method is
/// dispatched once for the whole run.
struct Fused<'a, const D: usize> {
    forces: Forces<'a>,
    /// The element-wise forces, when they apply.
    flat: Option<Flat>,
    inv_mass: &'a [f64],
    /// The state `[x; v]`.
    y: &'a mut [f64],
    /// Where the state at the start is kept (the call's checkpoint).
    saved: &'a mut [f64],
    t: &'a mut f64,
    steps: &'a mut u64,
    evals: &'a mut u64,
    epoch: Epoch,
    h: f64,
    n: u64,
}

/// How many of `n` steps from `steps` (at time `t`) move the time: time is `t0 + k h` (see
/// `World::context`), and it must move at every step.
fn movable(epoch: Epoch, steps: u64, t: f64, n: u64) -> u64 {
    let mut prev = t;
    for k in 0..n {
        let t_end = epoch.time(steps + k + 1).unwrap_or(f64::NAN);
        if !(t_end > prev && t_end.is_finite()) {
            return k;
        }
        prev = t_end;
    }
    n
}

impl<const D: usize> Visit for Fused<'_, D> {
    type Out = (u64, Option<Stop>);

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> (u64, Option<Stop>) {
        let Self { forces, flat, inv_mass, y, saved, t, steps, evals, epoch, h, n } = self;
        let movable = movable(epoch, *steps, *t, n);
        let run = Run { epoch, steps: *steps, h, n: movable };
        // The method's element-wise form where it has one and the forces are element-wise.
        let elementwise = flat.zip(flat::evals(method, forces.velocity));
        let (good, e) = match elementwise {
            Some((k, e)) => {
                (tiles::elementwise::<D, M>(method, k, forces.velocity, inv_mass, y, saved, run), e)
            }
            None => tiles::recipe::<D, M>(method, forces, inv_mass, y, saved, run),
        };
        *steps += good;
        *t = epoch.time(*steps).unwrap_or(f64::NAN);
        *evals += good * e;
        if good < movable {
            (good, Some(Stop::Bad))
        } else if movable < n {
            (good, Some(Stop::Time))
        } else {
            (good, None)
        }
    }
}

/// The state after a step, as [`World::run_observed`] hands it out.
pub(crate) struct Row<'a> {
    /// The forces and masses (for energies).
    pub model: &'a super::Model,
    /// Steps taken, this one included.
    pub steps: u64,
    /// Time, s.
    pub t: f64,
    /// Positions, velocities, accelerations (flat, `n * dim`).
    pub x: &'a [f64],
    pub v: &'a [f64],
    pub a: &'a [f64],
}

/// Up to `n` steps of a small world with a look at every one, as work for
/// [`Integrator::visit`].
struct Observe<'a, 'b, const D: usize, F> {
    forces: Forces<'a>,
    /// The element-wise forces, when they apply.
    small: Option<&'a Elements>,
    model: &'a super::Model,
    y: &'a mut [f64],
    saved: &'a mut [f64],
    t: &'a mut f64,
    steps: &'a mut u64,
    evals: &'a mut u64,
    epoch: Epoch,
    h: f64,
    n: u64,
    on_row: &'b mut F,
}

impl<const D: usize, F: FnMut(Row<'_>) -> bool> Visit for Observe<'_, '_, D, F> {
    type Out = (u64, Option<Stop>);

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> (u64, Option<Stop>) {
        let Self { forces, small, model, y, saved, t, steps, evals, epoch, h, n, on_row } = self;
        let movable = movable(epoch, *steps, *t, n);
        let steps0 = *steps;
        let run = Run { epoch, steps: steps0, h, n: movable };
        let mut look = |k: u64, y: &[f64], f: &[f64]| {
            let (m, s) = (y.len() / 2, steps0 + k + 1);
            let t = epoch.time(s).unwrap_or(f64::NAN);
            on_row(Row { model, steps: s, t, x: &y[..m], v: &y[m..], a: &f[m..] })
        };
        let elementwise =
            small.and_then(|k| small::observed(method, k, forces.velocity, h, movable, y, saved, &mut look));
        let ((good, e), halted) = match elementwise {
            Some(out) => out,
            None => tiles::observed::<D, M>(method, forces, &model.inv_mass, y, saved, run, &mut look),
        };
        *steps += good;
        *t = epoch.time(*steps).unwrap_or(f64::NAN);
        *evals += good * e;
        if halted || good == n {
            (good, None)
        } else if good < movable {
            (good, Some(Stop::Bad))
        } else {
            (good, Some(Stop::Time))
        }
    }
}

impl World {
    /// `n` steps of `h` seconds as [`World::run`] takes them, `on_row` called with the state
    /// after each good step (it stops the run after that step by returning `false`), when the
    /// world is small (one tile) and the fused kernel applies; `None` otherwise, nothing done.
    /// A recording of every step takes its rows this way, inside the kernel's loop (`on_row`
    /// compiled into it, not called through a pointer).
    pub(crate) fn run_observed<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        n: u64,
        h: f64,
        on_row: &mut F,
    ) -> Option<Result<()>> {
        let small = n > 0 && self.model.mass.len() <= tiles::OBSERVED_MAX;
        let mut method = self.fused().filter(|_| small)?;
        let mut saved = std::mem::take(&mut self.replay);
        let r = self.observe(&mut method, &mut saved, n, h, on_row);
        self.replay = saved;
        Some(r)
    }

    fn observe<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        method: &mut Integrator,
        saved: &mut Vec<f64>,
        n: u64,
        h: f64,
        on_row: &mut F,
    ) -> Result<()> {
        let ctx = self.context(h)?;
        if self.stale {
            self.refresh()?;
        }
        self.prev_x.clear();
        saved.resize(self.state.y.len(), 0.0);
        let start = (self.state.t, self.state.steps, self.state.evals, self.epoch);
        let local = self.model.forces.local();
        let forces = Forces { local, velocity: self.model.velocity_dependent() };
        let elements = Elements::of(local, self.model.dim, &self.model.inv_mass);
        let small = elements.as_ref();
        let model = &self.model;
        let State { t, y, steps, evals, .. } = &mut self.state;
        let (epoch, saved_slice) = (ctx.epoch, saved.as_mut_slice());
        let (good, stop) = match model.dim {
            1 => method.visit(Observe::<1, F> {
                forces,
                small,
                model,
                y,
                saved: saved_slice,
                t,
                steps,
                evals,
                epoch,
                h,
                n,
                on_row,
            }),
            2 => method.visit(Observe::<2, F> {
                forces,
                small,
                model,
                y,
                saved: saved_slice,
                t,
                steps,
                evals,
                epoch,
                h,
                n,
                on_row,
            }),
            _ => method.visit(Observe::<3, F> {
                forces,
                small,
                model,
                y,
                saved: saved_slice,
                t,
                steps,
                evals,
                epoch,
                h,
                n,
                on_row,
            }),
        };
        if good > 0 {
            self.epoch = epoch;
            self.deferred = true;
        }
        match stop {
            None => Ok(()),
            Some(Stop::Time) => self.context(h).map(|_| ()),
            Some(Stop::Bad) => {
                // As in `run_fused`: back to the checkpoint, the good steps again (no look:
                // their rows are taken), the failing one staged, which names the particle.
                self.state.y.copy_from_slice(saved);
                (self.state.t, self.state.steps, self.state.evals, self.epoch) = start;
                self.fused_steps(method, saved, epoch, good, h);
                self.step_inner(h, None)
            }
        }
    }

    /// A fresh instance of the world's method when the fused kernel applies: particles only
    /// (no bodies, no flow), every force per-particle, no user force, no constraint, a local
    /// method.
    pub(super) fn fused(&self) -> Option<Integrator> {
        let m = &self.model;
        if self.flow.is_some()
            || !self.constraints.is_empty()
            || !self.bodies.is_empty()
            || !self.balls.is_empty()
            || !m.user.is_empty()
            || m.mass.is_empty()
            || !m.forces.local().all
        {
            return None;
        }
        self.integrator.fresh_local()
    }

    /// Up to `n` fused steps of `h` with time kept from `epoch`; how many were taken, and why
    /// it stopped early.
    fn fused_steps(
        &mut self,
        method: &mut Integrator,
        saved: &mut [f64],
        epoch: Epoch,
        n: u64,
        h: f64,
    ) -> (u64, Option<Stop>) {
        match self.dim() {
            1 => self.fused_steps_d::<1>(method, saved, epoch, n, h),
            2 => self.fused_steps_d::<2>(method, saved, epoch, n, h),
            _ => self.fused_steps_d::<3>(method, saved, epoch, n, h),
        }
    }

    fn fused_steps_d<const D: usize>(
        &mut self,
        method: &mut Integrator,
        saved: &mut [f64],
        epoch: Epoch,
        n: u64,
        h: f64,
    ) -> (u64, Option<Stop>) {
        let local = self.model.forces.local();
        let forces = Forces { local, velocity: self.model.velocity_dependent() };
        let flat = local.element_wise().map(|(s, g)| Flat { s, g });
        let inv_mass = &self.model.inv_mass;
        let State { t, y, steps, evals, .. } = &mut self.state;
        let run = Fused::<D> { forces, flat, inv_mass, y, saved, t, steps, evals, epoch, h, n };
        let r = method.visit(run);
        if r.0 > 0 {
            self.epoch = epoch;
            self.deferred = true;
        }
        r
    }

    /// Takes `n` steps of `h` seconds: through the fused kernel when it applies, else the
    /// staged step one at a time. Either way a failing step is rolled back and reported, the
    /// steps before it stay taken.
    pub(super) fn run(&mut self, n: u64, h: f64) -> Result<()> {
        let Some(mut method) = self.fused().filter(|_| n > 0) else {
            return self.run_staged(n, h);
        };
        let ctx = self.context(h)?;
        if self.stale {
            // A state set by hand: its derivative is evaluated (and checked) now, as the staged
            // step would; a derivative the kernel did not store is not needed.
            self.refresh()?;
        }
        self.prev_x.clear();
        let mut saved = std::mem::take(&mut self.replay);
        let r = self.run_fused(&mut method, &mut saved, ctx.epoch, n, h);
        self.replay = saved;
        r
    }

    /// Whether a step can be taken again with the same result: no user code runs in it (a
    /// Python force could answer differently, or count its calls) and no load applied by hand
    /// waits for it (a step consumes those). Balls replay: their Collide stage is a function of
    /// the state (the same contacts in the same order, the same bits), and their contact
    /// statistics go back with the call's checkpoint.
    fn replayable(&self) -> bool {
        self.model.user.is_empty()
            && self.bodies.forces.is_empty()
            && self.bodies.force.iter().chain(&self.bodies.torque).all(|v| *v == glam::DVec3::ZERO)
    }

    /// `n` staged steps: with one checkpoint for the call when the steps can be replayed (on
    /// a failure: back to it, the good steps again, the failing one with its own checkpoint),
    /// else a checkpoint per step.
    fn run_staged(&mut self, n: u64, h: f64) -> Result<()> {
        if n < 2 || !self.replayable() {
            for _ in 0..n {
                self.step_inner(h, None)?;
            }
            return Ok(());
        }
        // Bodies' rates (q' needs omega: two rotations) are computed once when asked for,
        // not after every step: a split method never reads them.
        let lazy = !self.bodies.is_empty() && self.integrator.info().split;
        self.lazy_rate = lazy;
        let r = self.run_call(n, h);
        if lazy {
            self.lazy_rate = false;
            self.rates_owed = true;
        }
        r
    }

    /// The staged steps of a call with one checkpoint, replayed on a failure.
    fn run_call(&mut self, n: u64, h: f64) -> Result<()> {
        self.refresh()?;
        let layout = self.layout();
        self.call.save(&self.state, &self.integrator, layout);
        let start = (self.state.t, self.state.steps, self.state.evals, self.epoch);
        if self.lazy_rate && self.constraints.is_empty() && self.balls.is_empty() {
            let good = self.parts_loop(n, h);
            if good == n {
                return Ok(());
            }
            // As below: back, the good steps again (the same bits), the failing one staged.
            self.call.restore(&mut self.state, &mut self.integrator, layout);
            (self.state.t, self.state.steps, self.state.evals, self.epoch) = start;
            self.parts_loop(good, h);
            self.step_inner(h, None)?;
            return self.run_staged(n - good - 1, h);
        }
        let stats = self.balls.stats;
        for k in 0..n {
            if self.step_unsaved(h, k + 1 == n).is_ok() {
                continue;
            }
            self.call.restore(&mut self.state, &mut self.integrator, layout);
            (self.state.t, self.state.steps, self.state.evals, self.epoch) = start;
            self.balls.stats = stats;
            for i in 0..k {
                self.step_unsaved(h, i + 1 == k)?;
            }
            // Fails as before, now with its own checkpoint (or, were it to pass, goes on).
            self.step_inner(h, None)?;
            return self.run_staged(n - k - 1, h);
        }
        Ok(())
    }

    /// Up to `n` steps of a world with bodies under a split method, the parts built once and
    /// stepped in one loop: what `step_unsaved` does but its stages with nothing to do here
    /// (no hand loads or user code, [`World::replayable`]; no constraints, no balls), the
    /// same bits. Stops before the first step that fails (the state then part-way: the caller
    /// restores its checkpoint); returns the steps taken.
    fn parts_loop(&mut self, n: u64, h: f64) -> u64 {
        let Ok(ctx) = self.context(h) else { return 0 };
        let (epoch, layout) = (ctx.epoch, self.layout());
        self.prev_x.clear();
        let mut parts = super::parts::of(&mut self.model, &self.bodies, &mut self.body_loads);
        parts.lazy = true;
        let mut good = 0;
        while good < n {
            let t_end = epoch.time(self.state.steps + 1).unwrap_or(f64::NAN);
            if !(t_end > self.state.t && t_end.is_finite())
                || self.integrator.advance(&mut parts, &mut self.state, h, None).is_err()
                || self.integrator.check(&self.state, layout).is_err()
            {
                break;
            }
            self.state.steps += 1;
            self.state.t = t_end;
            good += 1;
        }
        if good > 0 {
            self.epoch = epoch;
        }
        good
    }

    /// The fused steps of [`World::run`], with the call's checkpoint in `saved`.
    fn run_fused(
        &mut self,
        method: &mut Integrator,
        saved: &mut Vec<f64>,
        epoch: Epoch,
        n: u64,
        h: f64,
    ) -> Result<()> {
        let mut epoch = epoch;
        let mut left = n;
        while left > 0 {
            // The kernels keep the state at the start in `saved` as they read it.
            saved.resize(self.state.y.len(), 0.0);
            let start = (self.state.t, self.state.steps, self.state.evals, self.epoch);
            let (taken, stop) = self.fused_steps(method, saved, epoch, left, h);
            left -= taken;
            match stop {
                None => {}
                // The error of a step that cannot move time, as the staged step gives it.
                Some(Stop::Time) => return self.context(h).map(|_| ()),
                Some(Stop::Bad) => {
                    // Back to the checkpoint, the good steps again (same arithmetic, same
                    // bits), then this step the staged way: it fails as the kernel did, rolls
                    // back and names the particle.
                    self.state.y.copy_from_slice(saved);
                    (self.state.t, self.state.steps, self.state.evals, self.epoch) = start;
                    self.fused_steps(method, saved, epoch, taken, h);
                    self.step_inner(h, None)?;
                    // (The staged step passed: the two agree bitwise, so this is not reached;
                    // were it, the run would go on from here.)
                    left -= 1;
                    epoch = self.epoch;
                }
            }
        }
        Ok(())
    }
}
