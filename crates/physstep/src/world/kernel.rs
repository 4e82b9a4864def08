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

use super::flat::{Flat, Recipe};
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
    /// The element-wise recipe and forces, when they apply.
    flat: Option<(Recipe, Flat)>,
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

impl<const D: usize> Visit for Fused<'_, D> {
    type Out = (u64, Option<Stop>);

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> (u64, Option<Stop>) {
        let Self { forces, flat, inv_mass, y, saved, t, steps, evals, epoch, h, n } = self;
        // Time as t0 + k h (see `World::context`), and it must move at every step.
        let mut prev = *t;
        let mut movable = n;
        for k in 0..n {
            let t_end = epoch.time(*steps + k + 1).unwrap_or(f64::NAN);
            if !(t_end > prev && t_end.is_finite()) {
                movable = k;
                break;
            }
            prev = t_end;
        }
        let run = Run { epoch, steps: *steps, h, n: movable };
        let (good, e) = match flat {
            Some((r, k)) => (
                tiles::elementwise::<D>(r, k, forces.velocity, inv_mass, y, saved, run),
                r.evals(forces.velocity),
            ),
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

impl World {
    /// A fresh instance of the world's method when the fused kernel applies: particles only
    /// (no bodies, no flow), every force per-particle, no user force, a local method.
    pub(super) fn fused(&self) -> Option<Integrator> {
        let m = &self.model;
        if self.flow.is_some()
            || !self.bodies.is_empty()
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
        let flat = Recipe::of(method.info().name).zip(local.element_wise().map(|(s, g)| Flat { s, g }));
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
    /// waits for it (a step consumes those).
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
        self.refresh()?;
        let layout = self.layout();
        self.call.save(&self.state, &self.integrator, layout);
        let start = (self.state.t, self.state.steps, self.state.evals, self.epoch);
        for k in 0..n {
            if self.step_unsaved(h).is_ok() {
                continue;
            }
            self.call.restore(&mut self.state, &mut self.integrator, layout);
            (self.state.t, self.state.steps, self.state.evals, self.epoch) = start;
            for _ in 0..k {
                self.step_unsaved(h)?;
            }
            // Fails as before, now with its own checkpoint (or, were it to pass, goes on).
            self.step_inner(h, None)?;
            return self.run_staged(n - k - 1, h);
        }
        Ok(())
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
