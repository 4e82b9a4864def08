//! A world's time and what a failed step goes back to.
//!
//! Time is `t0 + k h` since the latest change of `h` ([`Epoch::time`], the one place it is
//! computed): no drift from repeated addition, so `t = 10` after 100 steps of 0.1. A step
//! must move it ([`Epoch::next`]): a step below the resolution of `t` would step forever in
//! place.
//!
//! A [`Rollback`] is the one checkpoint type of the step: the state (`y`, the part of `f`
//! that is not a copy of `y`, the method's memory), the step and evaluation counts, the time
//! and its epoch, and the balls' contact statistics and warm starts. A call keeps one for
//! all its steps when they can be replayed, else each step keeps its own (see `World::run`);
//! the fused kernel writes the positions and velocities into it as it reads them, so it costs
//! no pass of its own.
//!
//! The fused kernel's rollback outlives its call: the next call of the fused kernel reuses it
//! while nothing changed the world in between and fewer than [`REPLAY_MAX`] steps were taken
//! since ([`World::reusable`]). A failure then goes back to it and replays the good steps
//! since, the same arithmetic giving the same bits, so the game loop's one step per call pays
//! a copy of its state once in [`REPLAY_MAX`] steps instead of at every call.

use super::{Derivative, World};
use crate::collide::{CollisionStats, Push};
use crate::integrators::registry::Checkpoint;

/// Where time was when dt last changed: `t = epoch.t + (steps - epoch.steps) * dt`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Epoch {
    pub t: f64,
    pub steps: u64,
    pub dt: f64,
}

impl Epoch {
    /// World time after `steps` steps in all: `t + (steps - self.steps) dt`; `None` when
    /// `steps` is before the epoch, or after it while no dt was set yet.
    pub fn time(self, steps: u64) -> Option<f64> {
        let k = steps.checked_sub(self.steps)?;
        if self.dt == 0.0 {
            return (k == 0).then_some(self.t);
        }
        Some(self.t + k as f64 * self.dt)
    }

    /// The end of the step after `steps` steps taken at time `t`, when it moves the time
    /// (finite and later than `t`); `None` when it does not.
    #[inline]
    pub fn next(self, steps: u64, t: f64) -> Option<f64> {
        self.time(steps + 1).filter(|&t_end| t_end > t && t_end.is_finite())
    }

    /// How many of `n` steps after `steps` (at time `t`) move the time.
    pub fn movable(self, steps: u64, t: f64, n: u64) -> u64 {
        let mut prev = t;
        for k in 0..n {
            match self.next(steps + k, prev) {
                Some(t_end) => prev = t_end,
                None => return k,
            }
        }
        n
    }
}

/// Steps after which the fused kernel keeps a fresh rollback rather than reuse the one it
/// kept before: a failure replays at most this many steps plus those of its own call.
pub(super) const REPLAY_MAX: u64 = 64;

/// What rolls back with a failed step or call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Keep {
    /// The whole state: `y`, the derivative's own part and the method's memory.
    State,
    /// `y` only, written by the fused kernel as it reads it (the kernel's method is a fresh
    /// local one without memory, and it does not write `f`).
    Positions,
}

/// The state, counts, time and contact statistics at a point a failure goes back to.
#[derive(Debug, Clone, Default)]
pub(super) struct Rollback {
    state: Checkpoint,
    /// `y` at the start of a fused run (the kernel fills it).
    pub y: Vec<f64>,
    /// The derivative a step from the stored one writes beside `state.f` (`Integrate::Given`),
    /// swapped in on success: a failure leaves `state.f` as it was.
    pub beside: Vec<f64>,
    keep: Option<Keep>,
    t: f64,
    steps: u64,
    evals: u64,
    epoch: Epoch,
    stats: CollisionStats,
    /// The balls' resting contacts' warm starts.
    warm: Vec<Push>,
    /// The solids' motion and contacts.
    solids: super::solids::SolidSet,
    derivative: Derivative,
    /// The method the state was kept under (a fused rollback is reused by the same method only).
    method: &'static str,
}

impl World {
    /// Keeps in `r` what a failure goes back to; with [`Keep::Positions`] the buffer is only
    /// sized (the kernel fills it).
    pub(super) fn keep(&self, r: &mut Rollback, keep: Keep) {
        match keep {
            Keep::State => r.state.save(&self.state, &self.integrator, self.layout()),
            Keep::Positions => r.y.resize(self.state.y.len(), 0.0),
        }
        r.keep = Some(keep);
        (r.t, r.steps, r.evals, r.epoch) = (self.state.t, self.state.steps, self.state.evals, self.epoch);
        r.stats = self.balls.stats;
        r.warm.clone_from(&self.balls.warm);
        if !self.solids.is_empty() {
            self.solids.save(&mut r.solids);
        }
        r.derivative = self.derivative;
        r.method = self.integrator.info().name;
    }

    /// Whether the fused kernel's next pass of steps of `h` can go back to `r`, kept by an
    /// earlier fused pass, instead of keeping the state afresh: the steps since were all taken
    /// by the fused kernel with this method and this `h` (the derivative is still as the
    /// kernel left it: every change by hand, of the state, a force, a particle or dt, marks it
    /// stale, and any other step stores it), there are fewer than [`REPLAY_MAX`] of them, and
    /// the state has the length it had. Replaying them from `r` then gives the current state,
    /// bitwise.
    pub(super) fn reusable(&self, r: &Rollback, h: f64) -> bool {
        r.keep == Some(Keep::Positions)
            && self.derivative == Derivative::Unstored
            && r.method == self.integrator.info().name
            && r.epoch == self.epoch
            && self.epoch.dt == h
            && r.y.len() == self.state.y.len()
            && self.state.steps.checked_sub(r.steps).is_some_and(|k| k < REPLAY_MAX)
    }

    /// Puts back, bitwise, what [`World::keep`] kept.
    pub(super) fn roll_back(&mut self, r: &Rollback) {
        match r.keep {
            Some(Keep::State) => {
                let layout = self.layout();
                r.state.restore(&mut self.state, &mut self.integrator, layout);
            }
            Some(Keep::Positions) => self.state.y.copy_from_slice(&r.y),
            None => debug_assert!(false, "a rollback that kept nothing"),
        }
        (self.state.t, self.state.steps, self.state.evals, self.epoch) = (r.t, r.steps, r.evals, r.epoch);
        self.balls.stats = r.stats;
        self.balls.warm.clone_from(&r.warm);
        if !self.solids.is_empty() {
            self.solids.restore(&r.solids);
        }
        self.derivative = r.derivative;
    }
}
