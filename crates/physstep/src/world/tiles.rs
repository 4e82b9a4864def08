//! The kernels' inner loops: a run of `n` steps of particles under per-particle forces, one
//! tile of particles at a time, all `n` steps of a tile while it sits in L1 (the particles
//! do not interact, so the order of the work changes nothing in the bits). Each tile is read
//! from memory and written back once per run instead of once per step.
//!
//! Two kinds of tile: the method's own recipe on a tile [`System`] (any local method, any
//! per-particle force), and the same recipe on one element at a time ([`super::flat`], for
//! methods with an element-wise form under gravity and linear drag). Both run compiled
//! for AVX2 where the CPU has it (run-time dispatch) and for the baseline target otherwise;
//! only `+ - * / sqrt` of IEEE doubles are used and no multiply-add is fused (Rust never
//! contracts), so the two paths give bitwise the same results.

use rayon::prelude::*;

use super::flat::{self, Flat, Masses};
use super::Epoch;
use crate::dynamics::{Second, SecondOrder, Step};
use crate::forces::local::{AnchorSpring, Local};
use crate::integrators::Method;
use crate::limits::any_runaway as runaway;
use crate::simd::avx2;

/// Particles per tile of the recipe kernel: the tile's stage buffers (`2 * TILE * dim`
/// values each) stay in L1, with a length known at compile time.
const TILE: usize = 16;
/// Particles per parallel task.
pub(super) const TASK: usize = 16384;
/// From this many particles on, tasks run in parallel.
pub(super) const PARALLEL_MIN: usize = 4 * TASK;

/// What a run needs of the world's forces.
#[derive(Clone, Copy)]
pub(super) struct Forces<'a> {
    pub local: &'a Local,
    /// Whether the accelerations depend on the velocities.
    pub velocity: bool,
}

/// The steps of a run: step `k` of it starts at `epoch.time(steps + k)`.
#[derive(Clone, Copy)]
pub(super) struct Run {
    pub epoch: Epoch,
    pub steps: u64,
    pub h: f64,
    /// Steps to take.
    pub n: u64,
    /// Whether the state at the start is written into the checkpoint as it is read (else the
    /// call's rollback is one kept by an earlier call, which a failure replays from).
    pub save: bool,
}

impl Run {
    /// Time at the start of step `k` of the run.
    #[inline]
    fn t(self, k: u64) -> f64 {
        self.epoch.time(self.steps + k).unwrap_or(f64::NAN)
    }
}

/// One tile of particles under per-particle forces, a [`SecondOrder`] system (a `System`
/// through [`Second`], as a world's particles are).
struct Tile<'a, const D: usize> {
    local: &'a Local,
    /// Index of the tile's first particle.
    p0: usize,
    inv_mass: &'a [f64],
    springs: &'a [AnchorSpring],
    velocity: bool,
}

impl<const D: usize> SecondOrder for Tile<'_, D> {
    #[inline]
    fn len(&self) -> usize {
        D * self.inv_mass.len()
    }
    #[inline]
    fn accel(&mut self, _t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.local.accel::<D>(self.p0, x, v, self.inv_mass, self.springs, a);
    }
    #[inline]
    fn velocity_dependent(&self) -> bool {
        self.velocity
    }
}

/// The run over particles `p0..` (positions `x`, velocities `v`, flat, `D` per particle)
/// with `method`, tile by tile; returns the first step at which a new value or acceleration
/// ran away (or `run.n`), and the evaluations a step takes.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn recipe_task<const D: usize, M: Method>(
    method: &mut M,
    forces: Forces<'_>,
    p0: usize,
    inv_mass: &[f64],
    (x, v): (&mut [f64], &mut [f64]),
    (sx, sv): (&mut [f64], &mut [f64]),
    run: Run,
) -> (u64, u64) {
    let (mut good, mut evals) = (run.n, 0);
    let full = inv_mass.len() / TILE * TILE;
    let m = TILE * D;
    for q in (0..full).step_by(TILE) {
        let (a, b) = (q * D, q * D + m);
        let (xt, vt, st) =
            ((&mut x[a..b], &mut v[a..b]), (&mut sx[a..b], &mut sv[a..b]), Run { n: good, ..run });
        (good, evals) = tile::<D, M, { 2 * TILE * 3 }>(
            method,
            forces,
            p0 + q,
            &inv_mass[q..q + TILE],
            xt,
            vt,
            st,
            &mut |_, _, _| true,
        )
        .0;
    }
    // The last particles (fewer than a tile, a small world) in fours: smaller buffers.
    for q in (full..inv_mass.len()).step_by(4) {
        let e = (q + 4).min(inv_mass.len());
        let (a, b) = (q * D, e * D);
        let (xt, vt, st) =
            ((&mut x[a..b], &mut v[a..b]), (&mut sx[a..b], &mut sv[a..b]), Run { n: good, ..run });
        (good, evals) = tile::<D, M, { 2 * 4 * 3 }>(
            method,
            forces,
            p0 + q,
            &inv_mass[q..e],
            xt,
            vt,
            st,
            &mut |_, _, _| true,
        )
        .0;
    }
    (good, evals)
}

/// The run on one tile, its state in buffers of `L` values (at least `2 * particles * D`):
/// read once (and kept in `sx`, `sv`, the call's checkpoint, when `run.save`), all steps,
/// written once;
/// returns the first step that ran away (or `run.n`) and the evaluations a step takes.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn tile<const D: usize, M: Method, const L: usize>(
    method: &mut M,
    forces: Forces<'_>,
    q0: usize,
    im: &[f64],
    (xt, vt): (&mut [f64], &mut [f64]),
    (sx, sv): (&mut [f64], &mut [f64]),
    run: Run,
    on_step: &mut impl FnMut(u64, &[f64], &[f64]) -> bool,
) -> ((u64, u64), bool) {
    if run.save {
        sx.copy_from_slice(xt);
        sv.copy_from_slice(vt);
    }
    let mut y = [0.0; L];
    let mut f = [0.0; L];
    let m = xt.len();
    let springs = forces.local.anchors(q0, q0 + im.len());
    let mut tile =
        Tile::<D> { local: forces.local, p0: q0, inv_mass: im, springs, velocity: forces.velocity };
    let (y, f) = (&mut y[..2 * m], &mut f[..2 * m]);
    y[..m].copy_from_slice(xt);
    y[m..].copy_from_slice(vt);
    f[..m].copy_from_slice(vt);
    tile.accel(run.t(0), xt, vt, &mut f[m..]);
    let mut sys = Second(&mut tile);
    let mut evals = 0;
    let mut good = run.n;
    let mut halted = false;
    for k in 0..run.n {
        let mut e = 0;
        let r = method.step(&mut Step::new(&mut sys, run.t(k), run.h, y, f, &mut e, None));
        evals = e;
        if r.is_err() | runaway(y) | runaway(&f[m..]) {
            good = k;
            break;
        }
        if !on_step(k, y, f) {
            (good, halted) = (k + 1, true);
            break;
        }
    }
    xt.copy_from_slice(&y[..m]);
    vt.copy_from_slice(&y[m..]);
    ((good, evals), halted)
}

/// Particles a world may have for [`observed`] (one tile).
pub(super) const OBSERVED_MAX: usize = TILE;

/// A run of a small world (at most [`OBSERVED_MAX`] particles, one tile) through `method`'s
/// own recipe, `on_step(k, y, f)` called after each good step `k` with the state `[x; v]` and
/// its derivative `[v; a]` there (return `false` to stop after it); the steps taken, the
/// evaluations a step takes, and whether `on_step` stopped the run.
pub(super) fn observed<const D: usize, M: Method>(
    method: &mut M,
    forces: Forces<'_>,
    inv_mass: &[f64],
    y: &mut [f64],
    saved: &mut [f64],
    run: Run,
    on_step: &mut impl FnMut(u64, &[f64], &[f64]) -> bool,
) -> ((u64, u64), bool) {
    debug_assert!(inv_mass.len() <= OBSERVED_MAX);
    let (xv, s) = (halves::<D>(y, inv_mass), halves::<D>(saved, inv_mass));
    tile::<D, M, { 2 * TILE * 3 }>(method, forces, 0, inv_mass, xv, s, run, on_step)
}

/// The positions and velocities of a particle state `y = [x; v]`.
fn halves<'a, const D: usize>(y: &'a mut [f64], inv_mass: &[f64]) -> (&'a mut [f64], &'a mut [f64]) {
    y.split_at_mut(inv_mass.len() * D)
}

/// Fixed tasks of [`TASK`] particles, in parallel: the task's index, its particles'
/// positions, velocities and their places in the checkpoint (of `n` particles).
#[allow(clippy::type_complexity)]
fn tasks<'a, const D: usize>(
    n: usize,
    y: &'a mut [f64],
    saved: &'a mut [f64],
) -> impl IndexedParallelIterator<Item = (usize, (&'a mut [f64], &'a mut [f64], &'a mut [f64], &'a mut [f64]))>
{
    let ((x, v), (sx, sv)) = (y.split_at_mut(n * D), saved.split_at_mut(n * D));
    let c = TASK * D;
    (x.par_chunks_mut(c), v.par_chunks_mut(c), sx.par_chunks_mut(c), sv.par_chunks_mut(c))
        .into_par_iter()
        .enumerate()
}

/// Particles `k * TASK..` of `n`, up to a task's.
fn task_range(k: usize, n: usize) -> (usize, usize) {
    (k * TASK, ((k + 1) * TASK).min(n))
}

/// A run of every particle (state `y = [x; v]`) through `method`'s own recipe, the state at
/// its start kept in `saved`; the first step that ran away (or `run.n`) and the evaluations
/// a step takes.
pub(super) fn recipe<const D: usize, M: Method + Clone + Send + Sync>(
    method: &mut M,
    forces: Forces<'_>,
    inv_mass: &[f64],
    y: &mut [f64],
    saved: &mut [f64],
    run: Run,
) -> (u64, u64) {
    let task =
        |m: &mut M, p0: usize, im: &[f64], xv: (&mut [f64], &mut [f64]), s: (&mut [f64], &mut [f64])| {
            #[cfg(target_arch = "x86_64")]
            if avx2() {
                // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
                // `target_feature` function.
                return unsafe { recipe_avx2::<D, M>(m, forces, p0, im, xv, s, run) };
            }
            recipe_task::<D, M>(m, forces, p0, im, xv, s, run)
        };
    if inv_mass.len() < PARALLEL_MIN {
        let ((x, v), (sx, sv)) = (halves::<D>(y, inv_mass), halves::<D>(saved, inv_mass));
        return task(method, 0, inv_mass, (x, v), (sx, sv));
    }
    let proto = &*method;
    tasks::<D>(inv_mass.len(), y, saved)
        .map_init(
            || proto.clone(),
            |m, (k, (x, v, sx, sv))| {
                let (a, b) = task_range(k, inv_mass.len());
                task(m, a, &inv_mass[a..b], (x, v), (sx, sv))
            },
        )
        .reduce(|| (run.n, 0), |a, b| (a.0.min(b.0), a.1.max(b.1)))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn recipe_avx2<const D: usize, M: Method>(
    method: &mut M,
    forces: Forces<'_>,
    p0: usize,
    inv_mass: &[f64],
    xv: (&mut [f64], &mut [f64]),
    saved: (&mut [f64], &mut [f64]),
    run: Run,
) -> (u64, u64) {
    recipe_task::<D, M>(method, forces, p0, inv_mass, xv, saved, run)
}

/// A run of every particle (state `y = [x; v]`) by `method`'s element-wise form
/// ([`super::flat`]), the state at its start kept in `saved`; the first step that ran away
/// (or `run.n`).
#[allow(clippy::too_many_arguments)]
pub(super) fn elementwise<const D: usize, M: Method + Sync>(
    method: &M,
    k: Flat,
    velocity: bool,
    masses: Masses<'_>,
    y: &mut [f64],
    saved: &mut [f64],
    run: Run,
) -> u64 {
    let task = |im: Masses<'_>, xv: (&mut [f64], &mut [f64]), s: (&mut [f64], &mut [f64])| {
        #[cfg(target_arch = "x86_64")]
        if avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            return unsafe { elementwise_avx2::<D, M>(method, k, velocity, run, im, xv, s) };
        }
        flat::run::<D, M>(method, k, velocity, run, im, xv, s)
    };
    let n = masses.len();
    if n < PARALLEL_MIN {
        let ((x, v), (sx, sv)) = (y.split_at_mut(n * D), saved.split_at_mut(n * D));
        return task(masses, (x, v), (sx, sv));
    }
    tasks::<D>(n, y, saved)
        .map(|(k, (x, v, sx, sv))| {
            let (a, b) = task_range(k, n);
            task(masses.range(a, b), (x, v), (sx, sv))
        })
        .reduce(|| run.n, u64::min)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn elementwise_avx2<const D: usize, M: Method>(
    method: &M,
    k: Flat,
    velocity: bool,
    run: Run,
    masses: Masses<'_>,
    xv: (&mut [f64], &mut [f64]),
    saved: (&mut [f64], &mut [f64]),
) -> u64 {
    flat::run::<D, M>(method, k, velocity, run, masses, xv, saved)
}

/// One step of every particle (state `y = [x; v]`) by `method`'s element-wise form from the
/// accelerations `a` at its start ([`flat::given`]): the state at the start kept in `saved`,
/// whether no new value ran away.
pub(super) fn given<M: Method + Sync>(
    method: &M,
    h: f64,
    y: &mut [f64],
    a: &[f64],
    saved: &mut [f64],
) -> bool {
    from_start(y, a, saved, |xv, a, s| {
        #[cfg(target_arch = "x86_64")]
        if avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            return unsafe { given_avx2::<M>(method, h, xv, a, s) };
        }
        flat::given::<M>(method, h, xv, a, s)
    })
}

/// Where a [`flat::one_eval`] method evaluates the forces, for every particle (state `y`) from
/// the stored accelerations `a` ([`flat::given_point`]), written over `y`; the start kept in
/// `saved`.
pub(super) fn given_point<M: Method + Sync>(method: &M, h: f64, y: &mut [f64], a: &[f64], saved: &mut [f64]) {
    from_start(y, a, saved, |xv, a, s| {
        #[cfg(target_arch = "x86_64")]
        if avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            unsafe { given_point_avx2::<M>(method, h, xv, a, s) };
            return true;
        }
        flat::given_point::<M>(method, h, xv, a, s);
        true
    });
}

/// `task` on the particles' positions and velocities (`y`), stored accelerations `a` and the
/// start they keep (`saved`), in parallel tasks of [`TASK`] particles in a large world
/// (elements are independent: any split of them gives the same bits); whether every task
/// said yes.
fn from_start<F>(y: &mut [f64], a: &[f64], saved: &mut [f64], task: F) -> bool
where
    F: Fn((&mut [f64], &mut [f64]), &[f64], (&mut [f64], &mut [f64])) -> bool + Sync,
{
    let n = a.len();
    let ((x, v), (sx, sv)) = (y.split_at_mut(n), saved.split_at_mut(n));
    let c = TASK * 3;
    if n < PARALLEL_MIN * 3 {
        return task((x, v), a, (sx, sv));
    }
    (x.par_chunks_mut(c), v.par_chunks_mut(c), a.par_chunks(c), sx.par_chunks_mut(c), sv.par_chunks_mut(c))
        .into_par_iter()
        .map(|(x, v, a, sx, sv)| task((x, v), a, (sx, sv)))
        .reduce(|| true, |p, q| p & q)
}

/// The end of a [`flat::one_eval`] method's step for every particle ([`flat::given_end`]):
/// from the start kept in `saved` and its accelerations `a`, given `a_end` evaluated at
/// [`given_point`]'s point, written to `y`; whether no new value ran away.
pub(super) fn given_end<M: Method + Sync>(
    method: &M,
    h: f64,
    y: &mut [f64],
    (a, a_end): (&[f64], &[f64]),
    saved: &[f64],
) -> bool {
    let task = |xv: (&mut [f64], &mut [f64]), aa: (&[f64], &[f64]), s: (&[f64], &[f64])| {
        #[cfg(target_arch = "x86_64")]
        if avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            return unsafe { given_end_avx2::<M>(method, h, xv, aa, s) };
        }
        flat::given_end::<M>(method, h, xv, aa, s)
    };
    let n = a.len();
    let ((x, v), (sx, sv)) = (y.split_at_mut(n), saved.split_at(n));
    let c = TASK * 3;
    if n < PARALLEL_MIN * 3 {
        return task((x, v), (a, a_end), (sx, sv));
    }
    (
        x.par_chunks_mut(c),
        v.par_chunks_mut(c),
        a.par_chunks(c),
        a_end.par_chunks(c),
        sx.par_chunks(c),
        sv.par_chunks(c),
    )
        .into_par_iter()
        .map(|(x, v, a, a_end, sx, sv)| task((x, v), (a, a_end), (sx, sv)))
        .reduce(|| true, |p, q| p & q)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn given_point_avx2<M: Method>(
    method: &M,
    h: f64,
    xv: (&mut [f64], &mut [f64]),
    a: &[f64],
    saved: (&mut [f64], &mut [f64]),
) {
    flat::given_point::<M>(method, h, xv, a, saved);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn given_end_avx2<M: Method>(
    method: &M,
    h: f64,
    xv: (&mut [f64], &mut [f64]),
    aa: (&[f64], &[f64]),
    saved: (&[f64], &[f64]),
) -> bool {
    flat::given_end::<M>(method, h, xv, aa, saved)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn given_avx2<M: Method>(
    method: &M,
    h: f64,
    xv: (&mut [f64], &mut [f64]),
    a: &[f64],
    saved: (&mut [f64], &mut [f64]),
) -> bool {
    flat::given::<M>(method, h, xv, a, saved)
}
