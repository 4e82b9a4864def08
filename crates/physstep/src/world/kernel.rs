//! The fused particle kernel: the Integrate stage of a call (see `World::run`) when the world
//! is particles under per-particle forces (gravity, drag, central gravity, springs to
//! anchors) stepped by a local method (see [`Integrator::fresh_local`]). It takes every step
//! left in the call through the loops of [`super::tiles`]: the method's own recipe (or its
//! element-wise form, [`super::flat`]) on one tile of particles at a time, all the steps while
//! the tile sits in L1, the finiteness check a flag folded in registers, the accelerations
//! not stored (computed again on request, without counting an evaluation). Particles do not
//! interact under these forces, so neither the order of the work nor the thread count changes
//! a bit: the kernel and the staged step give bitwise the same trajectory.
//!
//! Also here: [`World::given`], the other element-wise Integrate of particles, for a world
//! whose forces the fused kernel cannot take (user forces, springs between particles, n-body
//! gravity) under a method whose step reads only the derivative at its start: one step at a
//! time from the stored accelerations ([`tiles::given`]), the forces then evaluated at the
//! step's end as the staged step does (`World::integrate_given`, below); or, under
//! forces that do not read the velocity, a method that evaluates them once at a point of its
//! own (velocity Verlet): the state put there ([`tiles::given_point`]), the forces evaluated,
//! then the step's end from the start kept in the rollback ([`tiles::given_end`]).
//!
//! Rollback: the kernel writes the state at its start into the call's [`Rollback`](super::rollback::Rollback) as it
//! reads it, or, when an earlier call of the kernel kept it and nothing changed since
//! (`World::reusable`), writes nothing and leaves that one in place. When step `k` of its
//! run fails, the world goes back to the rollback, replays the good steps since (the same
//! arithmetic, so the same bits) and takes step `k` the staged way, which fails the same way,
//! rolls back, and names the particle (`World::run`).

use super::flat::{self, Flat, Masses};
use super::rollback::Rollback;
use super::small::{self, Elements};
use super::step::{Failure, StepContext};
use super::tiles::{self, Forces, Run};
use super::{Derivative, World};
use crate::dynamics::SecondOrder;
use crate::error::Error;
use crate::integrators::registry::{State, Visit};
use crate::integrators::{Integrator, Method};

/// How a fused run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Ran {
    /// Every step asked for was taken, or the observer stopped the run after the last one
    /// taken.
    All,
    /// The step after the good ones ran away: it is to be rolled back.
    Bad,
    /// The step after the good ones does not move the time.
    Time,
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

/// Up to `n` fused steps of every particle, as work for [`Integrator::visit`]: the method is
/// dispatched once for the whole run. The good steps and the evaluations each took.
struct Fused<'a, const D: usize> {
    forces: Forces<'a>,
    /// The element-wise forces, when they apply.
    flat: Option<Flat>,
    inv_mass: &'a [f64],
    /// The same, as the element-wise kernel reads them.
    masses: Masses<'a>,
    /// The state `[x; v]`.
    y: &'a mut [f64],
    /// Where the state at the start is kept (the call's rollback).
    saved: &'a mut [f64],
    run: Run,
}

impl<const D: usize> Visit for Fused<'_, D> {
    type Out = (u64, u64);

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> (u64, u64) {
        let Self { forces, flat, inv_mass, masses, y, saved, run } = self;
        // The method's element-wise form where it has one and the forces are element-wise.
        match flat.zip(flat::evals(method, forces.velocity)) {
            Some((k, e)) => {
                (tiles::elementwise::<D, M>(method, k, forces.velocity, masses, y, saved, run), e)
            }
            None => tiles::recipe::<D, M>(method, forces, inv_mass, y, saved, run),
        }
    }
}

/// How a step from the stored derivative takes its step ([`World::given`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum GivenKind {
    /// The method reads only the derivative at the start (explicit and symplectic Euler): the
    /// element-wise kernel steps from it ([`tiles::given`]), then the forces are evaluated at
    /// the end.
    Start,
    /// The method evaluates the forces once, at a point of its own (velocity Verlet, forces
    /// that do not read the velocity): the state put at that point ([`tiles::given_point`]),
    /// the forces evaluated there, then the step's end ([`tiles::given_end`]).
    Point,
}

/// Whether a method's step reads only the derivative at its start ([`flat::start_only`]), as
/// work for [`Integrator::visit`].
struct StartOnly;

impl Visit for StartOnly {
    type Out = bool;

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> bool {
        flat::start_only(method)
    }
}

/// Whether a method evaluates the forces once, at a point of its own ([`flat::one_eval`]), as
/// work for [`Integrator::visit`].
struct OneEval;

impl Visit for OneEval {
    type Out = bool;

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> bool {
        flat::one_eval(method)
    }
}

/// Where a [`flat::one_eval`] method evaluates the forces ([`tiles::given_point`]), as work
/// for [`Integrator::visit`].
struct GivenPoint<'a> {
    h: f64,
    y: &'a mut [f64],
    a: &'a [f64],
    saved: &'a mut [f64],
}

impl Visit for GivenPoint<'_> {
    type Out = ();

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) {
        let Self { h, y, a, saved } = self;
        tiles::given_point::<M>(method, h, y, a, saved);
    }
}

/// The end of a [`flat::one_eval`] method's step ([`tiles::given_end`]), as work for
/// [`Integrator::visit`]: whether no new value ran away.
struct GivenEnd<'a> {
    h: f64,
    y: &'a mut [f64],
    a: &'a [f64],
    a_end: &'a [f64],
    saved: &'a [f64],
}

impl Visit for GivenEnd<'_> {
    type Out = bool;

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> bool {
        let Self { h, y, a, a_end, saved } = self;
        tiles::given_end::<M>(method, h, y, (a, a_end), saved)
    }
}

/// One step of every particle from the stored accelerations ([`tiles::given`]), as work for
/// [`Integrator::visit`]: whether no new value ran away.
struct Given<'a> {
    h: f64,
    y: &'a mut [f64],
    a: &'a [f64],
    saved: &'a mut [f64],
}

impl Visit for Given<'_> {
    type Out = bool;

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> bool {
        let Self { h, y, a, saved } = self;
        tiles::given::<M>(method, h, y, a, saved)
    }
}

/// Up to `n` steps of a small world with a look at every one, as work for
/// [`Integrator::visit`]: the good steps, the evaluations each took, and whether the look
/// stopped the run.
struct Observe<'a, 'b, const D: usize, F> {
    forces: Forces<'a>,
    /// The element-wise forces, when they apply.
    small: Option<&'a Elements>,
    model: &'a super::Model,
    y: &'a mut [f64],
    saved: &'a mut [f64],
    run: Run,
    on_row: &'b mut F,
}

impl<const D: usize, F: FnMut(Row<'_>) -> bool> Visit for Observe<'_, '_, D, F> {
    type Out = ((u64, u64), bool);

    fn visit<M: Method + Clone + Send + Sync>(self, method: &mut M) -> ((u64, u64), bool) {
        let Self { forces, small, model, y, saved, run, on_row } = self;
        let mut look = |k: u64, y: &[f64], f: &[f64]| {
            let (m, s) = (y.len() / 2, run.steps + k + 1);
            let t = run.epoch.time(s).unwrap_or(f64::NAN);
            on_row(Row { model, steps: s, t, x: &y[..m], v: &y[m..], a: &f[m..] })
        };
        let elementwise =
            small.and_then(|k| small::observed(method, k, forces.velocity, run, y, saved, &mut look));
        match elementwise {
            Some(out) => out,
            None => tiles::observed::<D, M>(method, forces, &model.inv_mass, y, saved, run, &mut look),
        }
    }
}

impl World {
    /// A fresh instance of the world's method when the fused kernel applies: particles only
    /// (no bodies, no flow), every force per-particle, no user force, no constraint, no ball,
    /// a local method.
    pub(super) fn fused(&self) -> Option<Integrator> {
        let m = &self.model;
        if self.flow.is_some()
            || !self.constraints.is_empty()
            || !self.bodies.is_empty()
            || !self.balls.is_empty()
            || !self.solids.is_empty()
            || !m.user.is_empty()
            || m.mass.is_empty()
            || !m.forces.local().all
        {
            return None;
        }
        self.integrator.fresh_local()
    }

    /// A fresh instance of the world's method when its steps can be taken from the stored
    /// derivative by the element-wise kernels and the forces evaluated once a step as the
    /// staged step evaluates them: particles only (no bodies, flow, constraint, ball or
    /// solid), under any forces (user forces, springs between particles, n-body gravity), by a
    /// local method whose step reads only the derivative at its start ([`GivenKind::Start`]), or,
    /// under forces that do not read the velocity, one that evaluates them once at a point of
    /// its own ([`GivenKind::Point`]).
    pub(super) fn given(&self) -> Option<(Integrator, GivenKind)> {
        if self.flow.is_some()
            || !self.constraints.is_empty()
            || !self.bodies.is_empty()
            || !self.balls.is_empty()
            || !self.solids.is_empty()
            || self.model.mass.is_empty()
        {
            return None;
        }
        let mut method = self.integrator.fresh_local()?;
        if method.visit(StartOnly) {
            return Some((method, GivenKind::Start));
        }
        let point = !self.model.velocity_dependent() && method.visit(OneEval);
        point.then_some((method, GivenKind::Point))
    }

    /// Where a [`GivenKind::Point`] method evaluates the forces in a step of `h` from the stored
    /// accelerations, written into `y`; the state at the start in `saved`.
    pub(super) fn given_point(&mut self, method: &mut Integrator, h: f64, saved: &mut [f64]) {
        let State { y, f, .. } = &mut self.state;
        let n = y.len() / 2;
        method.visit(GivenPoint { h, y, a: &f[n..], saved });
    }

    /// The end of a [`GivenKind::Point`] method's step of `h` from the state kept in `saved` and
    /// the stored accelerations, given `a_end` evaluated at its point: the new state in `y`;
    /// whether no new value ran away.
    pub(super) fn given_end(
        &mut self,
        method: &mut Integrator,
        h: f64,
        saved: &[f64],
        a_end: &[f64],
    ) -> bool {
        let State { y, f, .. } = &mut self.state;
        let n = y.len() / 2;
        method.visit(GivenEnd { h, y, a: &f[n..], a_end, saved })
    }

    /// One step of `h` from the stored accelerations: the new state in `y`, the state at the
    /// start in `saved`; whether no new value ran away.
    pub(super) fn given_step(&mut self, method: &mut Integrator, h: f64, saved: &mut [f64]) -> bool {
        let State { y, f, .. } = &mut self.state;
        let n = y.len() / 2;
        method.visit(Given { h, y, a: &f[n..], saved })
    }

    /// Up to `n` fused steps of `ctx.h` from the current state, timed from `ctx.epoch`, the
    /// state at the start written into `saved` when `ctx.save`; `on_row` (a small world only) looks at each good step
    /// and may stop the run after it. The good steps (their evaluations counted; time and
    /// step count are the caller's) and how the run ended.
    pub(super) fn fused_run<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        method: &mut Integrator,
        saved: &mut [f64],
        ctx: &StepContext,
        n: u64,
        on_row: Option<&mut F>,
    ) -> (u64, Ran) {
        let movable = ctx.epoch.movable(self.state.steps, self.state.t, n);
        let run = Run { epoch: ctx.epoch, steps: self.state.steps, h: ctx.h, n: movable, save: ctx.save };
        let ((good, evals), halted) = match self.dim() {
            1 => self.fused_run_d::<1, F>(method, saved, run, on_row),
            2 => self.fused_run_d::<2, F>(method, saved, run, on_row),
            _ => self.fused_run_d::<3, F>(method, saved, run, on_row),
        };
        self.state.evals += good * evals;
        let ran = if halted || good == n {
            Ran::All
        } else if good < movable {
            Ran::Bad
        } else {
            Ran::Time
        };
        (good, ran)
    }

    fn fused_run_d<const D: usize, F: FnMut(Row<'_>) -> bool>(
        &mut self,
        method: &mut Integrator,
        saved: &mut [f64],
        run: Run,
        on_row: Option<&mut F>,
    ) -> ((u64, u64), bool) {
        // Whether every particle has the same inverse mass (a scan after a change of masses).
        let all = self.model.inv_mass.all();
        let model = &self.model;
        let local = model.forces.local();
        let forces = Forces { local, velocity: model.velocity_dependent() };
        let State { y, .. } = &mut self.state;
        match on_row {
            Some(on_row) => {
                let elements = Elements::of(local, model.dim, &model.inv_mass);
                let small = elements.as_ref();
                method.visit(Observe::<D, F> { forces, small, model, y, saved, run, on_row })
            }
            _ => {
                let flat = local.element_wise().map(|(s, g)| Flat { s, g });
                let inv_mass = &model.inv_mass;
                let masses = all.map_or(Masses::Each(inv_mass), |w| Masses::All(w, inv_mass.len()));
                (method.visit(Fused::<D> { forces, flat, inv_mass, masses, y, saved, run }), false)
            }
        }
    }
}

/// The Integrate stage of a pass taken by the element-wise kernels (chosen by `World::plan` in
/// `step.rs`).
impl World {
    /// Integrate, the fused kernel: up to `left` steps, the state at their start kept in
    /// `back` when `ctx.save` (else `back` is an earlier fused call's, reused).
    pub(super) fn integrate_fused<F: FnMut(Row<'_>) -> bool>(
        &mut self,
        ctx: &StepContext,
        method: &mut Integrator,
        left: u64,
        back: &mut Rollback,
        on_row: Option<&mut F>,
    ) -> std::result::Result<(u64, bool), Failure> {
        let (good, ran) = self.fused_run(method, &mut back.y, ctx, left, on_row);
        if good > 0 {
            self.derivative = Derivative::Unstored;
        }
        match ran {
            Ran::Bad => Err(Failure::Again(good)),
            // `Time`: the next pass's context says that time no longer moves.
            Ran::All | Ran::Time => Ok((good, ran == Ran::All && good < left)),
        }
    }

    /// Integrate from the stored derivative (`Integrate::Given`): one step, the state at its
    /// start kept in `back`, the forces evaluated at its end (counted, as the staged step
    /// counts them) into the accelerations written beside `state.f`'s, swapped in when they and
    /// the new state pass the check. The derivative's velocity half, a copy of `v`, is left
    /// owed (`Derivative::VelocityOwed`: no step from the stored derivative reads it). A
    /// failure leaves `state.f` as it was: the rollback puts back only `y`.
    pub(super) fn integrate_given(
        &mut self,
        ctx: &StepContext,
        method: &mut Integrator,
        from: GivenKind,
        back: &mut Rollback,
    ) -> std::result::Result<u64, Failure> {
        debug_assert!(
            matches!(self.derivative, Derivative::Current | Derivative::VelocityOwed),
            "refreshed before the pass"
        );
        let mut beside = std::mem::take(&mut back.beside);
        beside.resize(self.state.f.len(), 0.0);
        let n = self.state.y.len() / 2;
        let a_new = &mut beside[n..];
        let point = from == GivenKind::Point;
        if point {
            // The state where the method evaluates the forces.
            self.given_point(method, ctx.h, &mut back.y);
        } else if !self.given_step(method, ctx.h, &mut back.y) {
            back.beside = beside;
            // A new value ran away: the step is taken again staged (no force was evaluated
            // in this one), which fails the same way and names it.
            return Err(Failure::Again(0));
        }
        let (x, v) = self.state.y.split_at(n);
        let mut ran_away = self.model.accel_ran_away(ctx.t + ctx.h, x, v, a_new);
        self.state.evals += 1;
        if let Some(e) = self.model.failure.take() {
            back.beside = beside;
            return Err(Failure::Error(e));
        }
        if point {
            // The step's end from its start, given the forces at its point.
            ran_away |= !self.given_end(method, ctx.h, &back.y, &beside[n..]);
        }
        std::mem::swap(&mut self.state.f, &mut beside);
        let failed = match ran_away {
            false => None,
            // Ctrl-C cut the evaluation short (n-body gravity poisons what it left): the
            // step loop rolls back and reports the stop.
            true if crate::interrupt::stop() => {
                Some(Failure::Error(Error::Interrupted { step: self.state.steps }))
            }
            // Accelerations (or, from a point, a new state) past the limit: the staged step's
            // Check of the state and derivative it would hold names them (not taken again: a
            // user force would be called twice).
            true => Some(self.check(ctx).err().map_or(Failure::Again(0), Failure::Error)),
        };
        match failed {
            None => {
                back.beside = beside;
                self.derivative = Derivative::VelocityOwed;
                Ok(1)
            }
            Some(failure) => {
                std::mem::swap(&mut self.state.f, &mut beside);
                back.beside = beside;
                Err(failure)
            }
        }
    }
}
