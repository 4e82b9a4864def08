//! The fused particle kernel: a world of particles under per-particle forces (gravity, drag,
//! central gravity, springs to anchors) stepped by a local method (see
//! [`Integrator::fresh_local`]) runs the method's own recipe on one tile of particles at a
//! time, the tile's state in L1-resident buffers: each particle's position and velocity are
//! read once and written once per step, forces are computed inside the recipe's passes over
//! the tile, the finiteness check is a flag folded over the tile while it is hot, and the
//! accelerations are not stored (they are computed again on request, without counting an
//! evaluation). Tiles are independent, so they run in parallel and the bits never depend on
//! the thread count; every per-particle operation is the one the staged step does, so the
//! kernel and the staged step give bitwise the same trajectory.
//!
//! Rollback: the kernel keeps one checkpoint per call of [`World::step`] instead of a copy
//! per step. When step `k` of a call fails, the world goes back to the checkpoint, replays
//! the `k` good steps (the same arithmetic, so the same bits) and takes step `k` the staged
//! way, which fails the same way, rolls back, and names the particle.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use super::flat::{self, Flat, Recipe};
use super::{Epoch, World};
use crate::dynamics::{SecondOrder, Step, System};
use crate::error::Result;
use crate::forces::local::{AnchorSpring, Local};
use crate::integrators::registry::Visit;
use crate::integrators::registry::{State, RUNAWAY};
use crate::integrators::{Integrator, Method};

/// Particles per tile: a full tile's stage buffers (`2 * TILE * dim` values each) have a
/// length known at compile time, so the recipe's passes over them unroll into registers.
const TILE: usize = 16;
/// Particles per parallel task.
const TASK: usize = 16384;
/// From this many particles on, tasks run in parallel.
const PARALLEL_MIN: usize = 4 * TASK;

/// Whether the kernels may take their AVX2 code path (see [`set_vector_paths`]).
static VECTOR_PATHS: AtomicBool = AtomicBool::new(true);

/// Allows (the default) or forbids the kernels' AVX2 code path, for the whole process. Both
/// paths give bitwise the same results (only IEEE `+ - * / sqrt`, no fused multiply-add);
/// this switch exists to check that, and to measure what the vector code gains.
pub fn set_vector_paths(enabled: bool) {
    VECTOR_PATHS.store(enabled, Ordering::Relaxed);
}

/// Whether the AVX2 path runs: the CPU has AVX2 and it is allowed.
#[cfg(target_arch = "x86_64")]
#[inline]
fn avx2() -> bool {
    VECTOR_PATHS.load(Ordering::Relaxed) && std::arch::is_x86_feature_detected!("avx2")
}

/// One tile of particles as a system: `y = [x; v]` of the tile, per-particle forces.
struct Tile<'a, const D: usize> {
    local: &'a Local,
    /// Index of the tile's first particle.
    p0: usize,
    inv_mass: &'a [f64],
    springs: &'a [AnchorSpring],
    velocity: bool,
}

impl<const D: usize> System for Tile<'_, D> {
    #[inline(always)]
    fn dim(&self) -> usize {
        2 * D * self.inv_mass.len()
    }
    #[inline(always)]
    fn split(&self) -> Option<usize> {
        Some(D * self.inv_mass.len())
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], _j: &mut [f64], _work: &mut Vec<f64>) -> bool {
        false
    }
    #[inline(always)]
    fn accel(&mut self, _t: f64, x: &[f64], w: &[f64], a: &mut [f64]) {
        self.local.accel::<D>(self.p0, x, w, self.inv_mass, self.springs, a);
    }
    #[inline(always)]
    fn drift(&mut self, x: &mut [f64], w: &[f64], h: f64) {
        crate::integrators::axpy(x, h, w);
    }
    #[inline(always)]
    fn rate(&self, _x: &[f64], v: &[f64], dx: &mut [f64]) {
        dx.copy_from_slice(v);
    }
    #[inline(always)]
    fn velocity_dependent(&self) -> bool {
        self.velocity
    }
    #[inline(always)]
    fn kick_drift(&mut self, x: &mut [f64], v: &mut [f64], dx: &mut [f64], a: &[f64], h: f64) {
        crate::integrators::kick_drift(x, v, dx, a, h);
    }
}

/// Whether any entry is NaN, infinite or past [`RUNAWAY`] (a flag folded without branches).
#[inline]
fn runaway(v: &[f64]) -> bool {
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    v.iter().fold(false, |acc, x| acc | !(x.abs() <= RUNAWAY))
}

/// What the kernel needs of the world's forces.
#[derive(Clone, Copy)]
struct Forces<'a> {
    local: &'a Local,
    velocity: bool,
}

/// Steps particles `p0..` (positions `x`, velocities `v`, flat, `D` per particle) by one
/// step of `h` from `t` with `method`, tile by tile; returns whether any new value or
/// acceleration ran away, and the evaluations a step took.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn task_body<const D: usize, M: Method>(
    method: &mut M,
    forces: Forces<'_>,
    p0: usize,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
    t: f64,
    h: f64,
) -> (bool, u64) {
    let (mut bad, mut evals) = (false, 0);
    let full = inv_mass.len() / TILE * TILE;
    let m = TILE * D;
    for q in (0..full).step_by(TILE) {
        let (xt, vt) = (&mut x[q * D..q * D + m], &mut v[q * D..q * D + m]);
        let r = tile::<D, M, { 2 * TILE * 3 }>(method, forces, p0 + q, &inv_mass[q..q + TILE], xt, vt, t, h);
        bad |= r.0;
        evals = r.1;
    }
    // The last particles (fewer than a tile, a small world) in fours: smaller buffers to set up.
    for q in (full..inv_mass.len()).step_by(4) {
        let e = (q + 4).min(inv_mass.len());
        let (xt, vt) = (&mut x[q * D..e * D], &mut v[q * D..e * D]);
        let r = tile::<D, M, { 2 * 4 * 3 }>(method, forces, p0 + q, &inv_mass[q..e], xt, vt, t, h);
        bad |= r.0;
        evals = r.1;
    }
    (bad, evals)
}

/// One tile of particles through the method's recipe, its state in buffers of `L` values
/// (at least `2 * particles * D`).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn tile<const D: usize, M: Method, const L: usize>(
    method: &mut M,
    forces: Forces<'_>,
    q0: usize,
    im: &[f64],
    xt: &mut [f64],
    vt: &mut [f64],
    t: f64,
    h: f64,
) -> (bool, u64) {
    let mut y = [0.0; L];
    let mut f = [0.0; L];
    let m = xt.len();
    let springs = forces.local.anchors(q0, q0 + im.len());
    let mut sys = Tile::<D> { local: forces.local, p0: q0, inv_mass: im, springs, velocity: forces.velocity };
    let (y, f) = (&mut y[..2 * m], &mut f[..2 * m]);
    y[..m].copy_from_slice(xt);
    y[m..].copy_from_slice(vt);
    f[..m].copy_from_slice(vt);
    sys.accel(t, xt, vt, &mut f[m..]);
    let mut n = 0;
    let r = method.step(&mut Step::new(&mut sys, t, h, y, f, &mut n, None));
    xt.copy_from_slice(&y[..m]);
    vt.copy_from_slice(&y[m..]);
    (r.is_err() | runaway(y) | runaway(&f[m..]), n)
}

/// [`task_body`] compiled for the CPU at hand: with AVX2 where the CPU has it (run-time
/// dispatch), else for the baseline target. Only `+ - * / sqrt` of IEEE doubles are used and
/// no multiply-add is fused (Rust never contracts), so both give bitwise the same results.
#[allow(clippy::too_many_arguments)]
fn task<const D: usize, M: Method>(
    method: &mut M,
    forces: Forces<'_>,
    p0: usize,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
    t: f64,
    h: f64,
) -> (bool, u64) {
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        return unsafe { task_avx2::<D, M>(method, forces, p0, inv_mass, x, v, t, h) };
    }
    task_body::<D, M>(method, forces, p0, inv_mass, x, v, t, h)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn task_avx2<const D: usize, M: Method>(
    method: &mut M,
    forces: Forces<'_>,
    p0: usize,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
    t: f64,
    h: f64,
) -> (bool, u64) {
    task_body::<D, M>(method, forces, p0, inv_mass, x, v, t, h)
}

/// One step of every particle by an element-wise recipe ([`super::flat`]), in parallel over
/// fixed tasks for large worlds, with AVX2 where the CPU has it.
fn flat_step<const D: usize>(
    r: Recipe,
    k: Flat,
    velocity: bool,
    h: f64,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
) -> bool {
    let run = |im: &[f64], x: &mut [f64], v: &mut [f64]| {
        #[cfg(target_arch = "x86_64")]
        if avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            return unsafe { flat_avx2::<D>(r, k, velocity, h, im, x, v) };
        }
        flat::step::<D>(r, k, velocity, h, im, x, v)
    };
    if inv_mass.len() < PARALLEL_MIN {
        return run(inv_mass, x, v);
    }
    x.par_chunks_mut(TASK * D)
        .zip(v.par_chunks_mut(TASK * D))
        .zip(inv_mass.par_chunks(TASK))
        .map(|((xc, vc), im)| run(im, xc, vc))
        .reduce(|| false, |a, b| a | b)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn flat_avx2<const D: usize>(
    r: Recipe,
    k: Flat,
    velocity: bool,
    h: f64,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
) -> bool {
    flat::step::<D>(r, k, velocity, h, inv_mass, x, v)
}

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
    x: &'a mut [f64],
    v: &'a mut [f64],
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
        let Self { forces, flat, inv_mass, x, v, t, steps, evals, epoch, h, n } = self;
        for k in 0..n {
            // Time as t0 + k h (see `World::context`), and it must move.
            let t_end = epoch.time(*steps + 1).unwrap_or(f64::NAN);
            if !(t_end > *t && t_end.is_finite()) {
                return (k, Some(Stop::Time));
            }
            let (bad, e) = match flat {
                Some((r, k)) => {
                    (flat_step::<D>(r, k, forces.velocity, h, inv_mass, x, v), r.evals(forces.velocity))
                }
                None => tiles::<D, M>(method, forces, inv_mass, x, v, *t, h),
            };
            if bad {
                return (k, Some(Stop::Bad));
            }
            *t = t_end;
            *steps += 1;
            *evals += e;
        }
        (n, None)
    }
}

/// One step of every particle through the method's recipe, tile by tile, in parallel over
/// fixed tasks for large worlds.
fn tiles<const D: usize, M: Method + Clone + Send + Sync>(
    method: &mut M,
    forces: Forces<'_>,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
    t: f64,
    h: f64,
) -> (bool, u64) {
    if inv_mass.len() < PARALLEL_MIN {
        return task::<D, M>(method, forces, 0, inv_mass, x, v, t, h);
    }
    let proto = &*method;
    x.par_chunks_mut(TASK * D)
        .zip(v.par_chunks_mut(TASK * D))
        .zip(inv_mass.par_chunks(TASK))
        .enumerate()
        .map_init(
            || proto.clone(),
            |m, (c, ((xc, vc), im))| task::<D, M>(m, forces, c * TASK, im, xc, vc, t, h),
        )
        .reduce(|| (false, 0), |a, b| (a.0 | b.0, a.1.max(b.1)))
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
    fn fused_steps(&mut self, method: &mut Integrator, epoch: Epoch, n: u64, h: f64) -> (u64, Option<Stop>) {
        match self.dim() {
            1 => self.fused_steps_d::<1>(method, epoch, n, h),
            2 => self.fused_steps_d::<2>(method, epoch, n, h),
            _ => self.fused_steps_d::<3>(method, epoch, n, h),
        }
    }

    fn fused_steps_d<const D: usize>(
        &mut self,
        method: &mut Integrator,
        epoch: Epoch,
        n: u64,
        h: f64,
    ) -> (u64, Option<Stop>) {
        let local = self.model.forces.local();
        let forces = Forces { local, velocity: self.model.velocity_dependent() };
        let flat = Recipe::of(method.info().name).zip(local.element_wise().map(|(s, g)| Flat { s, g }));
        let inv_mass = &self.model.inv_mass;
        let State { t, y, steps, evals, .. } = &mut self.state;
        let (x, v) = y.split_at_mut(inv_mass.len() * D);
        let run = Fused::<D> { forces, flat, inv_mass, x, v, t, steps, evals, epoch, h, n };
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
            saved.clone_from(&self.state.y);
            let start = (self.state.t, self.state.steps, self.state.evals, self.epoch);
            let (taken, stop) = self.fused_steps(method, epoch, left, h);
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
                    self.fused_steps(method, epoch, taken, h);
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
