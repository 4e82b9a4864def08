//! Resting contact: below restitution 1, the contacts of balls that touch at the start of the
//! step are solved together as non-penetration constraints (positions projected, velocities
//! given the implied motion, then a velocity pass for restitution), not one by one as events.
//! See docs/collisions.md, "Balls that rest".
//!
//! A pair (or a ball and a wall) is *in contact* when at the start of the step its gap is at
//! most the distance the forces of the step can close: `2 h (q_a + q_b)` with `q` each ball's
//! velocity change over the step from the forces (`|v1 - v0|`: `g h` under gravity), plus a
//! relative 1e-9 of the radii. The event loop skips the events of such pairs (the same test,
//! the same bits); every other contact keeps its exact time of impact. After the events:
//!
//! 1. positions: the overlaps of the contacts removed by Gauss-Seidel sweeps (split by
//!    inverse mass; where the forces of the step point one way, gravity, the upper ball takes
//!    more the more vertical the contact, all of it on a vertical one: shock propagation, so
//!    a stack is lifted out of the floor in one sweep instead of sagging), each ball moved
//!    given the implied motion `dx / h` as velocity (for symplectic Euler exactly the velocity
//!    of its corrected path, so a pile at rest has velocity 0);
//! 2. a fifth of an overlap left from before removed by positions alone;
//! 3. a velocity pass (accumulated impulses clamped at 0, the same sweeps):
//!    a touching contact's normal velocity at least `-e vn` where it approached at
//!    `-vn > 2 (q_a + q_b)` before the stage (a bounce), else at least 0 (it rests, Box2D's
//!    restitution threshold in units of the step's own velocity change); a contact still
//!    apart by `gap` at most `gap / h` of approach (a speculative contact).
//!
//! The first position pass is warm-started: each contact that pushed at the end of the
//! previous step's first pass ([`Push`], kept by the world: in its snapshot, state hash and
//! rollback) starts from that push, applied before the sweeps. A pile at rest needs the same
//! pushes step after step (each ball falls `g h^2` and is put back), so its passes start at
//! their answer. Every pass ends once its largest change in a sweep is at most [`TOL`] of the
//! displacement the forces give a ball over the step (`h max q`), or after [`SWEEPS`].
//!
//! Everything is serial and in a fixed order (contacts sorted by height, then slots): the
//! same bits whatever the thread count.

// `k` indexes the positions, velocities and normals alike.
#![allow(clippy::needless_range_loop)]

use super::super::grid::{Grid, ANY};
use super::{largest, Input, Scratch, WALL};

/// Gauss-Seidel sweeps of the position and of the velocity pass, at most.
const SWEEPS: usize = 64;

/// A pass ends after a sweep whose largest change (a displacement, or a velocity times `h`)
/// is at most this fraction of the largest displacement the forces give a ball over the
/// step, `h max q` (under gravity `g h^2`: 6.8e-7 m at 120 Hz).
const TOL: f64 = 1e-3;

/// The fraction of an overlap left from before that a step removes (with the velocity of
/// that motion: Baumgarte's factor).
const BETA: f64 = 0.2;

/// A contact of the set: slots `a < b`, or `a` and wall `b >= WALL`; `key` its order (the
/// lower ball's height, or the wall contact's point).
#[derive(Debug, Clone, Copy)]
struct Contact {
    a: u32,
    b: u32,
    key: f64,
}

/// A resting contact's accumulated push at the end of a step's first position pass (slots
/// `a < b`, or `a` and wall `b >= WALL`; `push > 0`, m): where the next step starts that
/// contact's pass (warm starting). A world keeps them sorted by `(a, b)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Push {
    pub a: u32,
    pub b: u32,
    pub push: f64,
}

impl Push {
    fn key(&self) -> (u32, u32) {
        (self.a, self.b)
    }

    /// `warm` as a snapshot and the state hash hold it: nothing when it is empty, else its
    /// length, then `a`, `b` and `push` of each.
    pub fn block(warm: &[Push]) -> Vec<f64> {
        if warm.is_empty() {
            return Vec::new();
        }
        let mut out = Vec::with_capacity(1 + 3 * warm.len());
        out.push(warm.len() as f64);
        for p in warm {
            out.extend([f64::from(p.a), f64::from(p.b), p.push]);
        }
        out
    }

    /// The pushes of a [`Push::block`], for `nb` balls in `d` dimensions.
    ///
    /// # Errors
    /// What is wrong with them, in words.
    pub fn from_block(data: &[f64], nb: usize, d: usize) -> Result<Vec<Push>, String> {
        let Some((&len, rest)) = data.split_first() else { return Ok(Vec::new()) };
        if !(len >= 1.0 && len.fract() == 0.0 && rest.len() as f64 == 3.0 * len) {
            return Err(format!("the balls' warm starts: {} entries for a count of {len}", rest.len()));
        }
        let slot =
            |v: f64, below: u64| (v.fract() == 0.0 && v >= 0.0 && v < below as f64).then_some(v as u32);
        let mut out: Vec<Push> = Vec::with_capacity(rest.len() / 3);
        for (i, e) in rest.chunks_exact(3).enumerate() {
            let a = slot(e[0], nb as u64);
            let b = slot(e[1], nb as u64)
                .filter(|&b| a.is_some_and(|a| a < b))
                .or_else(|| slot(e[1] - f64::from(WALL), 2 * d as u64).map(|w| WALL + w));
            let (Some(a), Some(b)) = (a, b) else {
                return Err(format!("the balls' warm start {i} is between slots {} and {}", e[0], e[1]));
            };
            let push = Push { a, b, push: e[2] };
            if !(push.push.is_finite() && push.push > 0.0) {
                return Err(format!("the balls' warm start {i} is a push of {}", e[2]));
            }
            if out.last().is_some_and(|q| q.key() >= push.key()) {
                return Err(format!("the balls' warm start {i} is out of order"));
            }
            out.push(push);
        }
        Ok(out)
    }
}

/// The resting-contact solver's state within a step (kept for its buffers).
#[derive(Debug, Clone, Default)]
pub(crate) struct Rest {
    /// Whether this step solves resting contacts (restitution below 1).
    pub on: bool,
    h: f64,
    /// Start-of-step positions (by slot) and each ball's velocity change from the forces.
    x0: Vec<f64>,
    v0: Vec<f64>,
    q: Vec<f64>,
    contacts: Vec<Contact>,
    /// Each contact's normal and least relative normal velocity in the pass under way.
    normals: Vec<[f64; 3]>,
    /// Each contact's accumulated push (a relative normal velocity, >= 0).
    lambda: Vec<f64>,
    targets: Vec<f64>,
    /// The positions before the first pass.
    x_before: Vec<f64>,
    /// Whether each contact acted in the step.
    active: Vec<bool>,
    /// The end of the step: positions and velocities.
    xe: Vec<f64>,
    ve: Vec<f64>,
    moved: Vec<bool>,
    /// The slots whose state the stage changed: the events' hits, then the others moved here.
    touched: Vec<u32>,
    /// The unit "up" (against the forces of the step) when they point one way.
    up: Option<[f64; 3]>,
    /// The deepest overlap of a contact of the set at the end of the step.
    pub end_overlap: f64,
    grid: Grid,
}

impl Rest {
    /// The margin of slot `a`: the gap the forces of the step can close.
    #[inline]
    fn margin(&self, a: usize) -> f64 {
        2.0 * self.h * self.q[a]
    }

    /// Whether slots `a` and `b` are in contact at the start of the step (the set's test and
    /// the event loop's filter: the same bits).
    #[inline]
    fn pair_in<const D: usize>(&self, a: usize, b: usize, inp: &Input<'_>) -> bool {
        let r = (inp.radius[a] + inp.radius[b]) * (1.0 + 1e-9) + self.margin(a) + self.margin(b);
        let (mut dd, mut dv) = (0.0, 0.0);
        for k in 0..D {
            let c = self.x0[b * D + k] - self.x0[a * D + k];
            dd += c * c;
            dv += c * (self.v0[b * D + k] - self.v0[a * D + k]);
        }
        // Close, and not approaching faster than twice what the forces of the step give
        // (`dv` is the approach times the distance, at most `r`).
        dd <= r * r && dv >= -2.0 * (self.q[a] + self.q[b]) * r
    }

    /// Whether slot `a` is in contact with wall `k` (`side` 1: the upper) at the start.
    #[inline]
    fn wall_in<const D: usize>(&self, a: usize, k: usize, side: u32, inp: &Input<'_>) -> bool {
        let Some(w) = inp.walls else { return false };
        let r = inp.radius[a];
        let x = self.x0[a * D + k];
        let (gap, vn) = if side == 0 {
            (x - r - w.lo[k], self.v0[a * D + k])
        } else {
            (w.hi[k] - r - x, -self.v0[a * D + k])
        };
        gap <= r * 1e-9 + self.margin(a) && vn >= -2.0 * self.q[a]
    }

    /// Whether the event loop leaves the event of `a` and `b` (a wall when `b >= WALL`) to
    /// this solver.
    pub fn skips<const D: usize>(&self, a: usize, b: u32, inp: &Input<'_>) -> bool {
        if b >= WALL {
            let w = b - WALL;
            self.wall_in::<D>(a, (w / 2) as usize, w % 2, inp)
        } else {
            self.pair_in::<D>(a, b as usize, inp)
        }
    }

    /// Before the events: the start state kept, each ball's velocity change, the contact set
    /// and its order.
    pub fn begin<const D: usize>(&mut self, x0: &[f64], v0: &[f64], inp: &Input<'_>) {
        let nb = inp.radius.len();
        self.on = true;
        self.h = inp.h;
        self.x0.clear();
        self.x0.extend_from_slice(x0);
        self.v0.clear();
        self.v0.extend_from_slice(v0);
        self.q.clear();
        let (mut sum, mut total) = ([0.0; 3], 0.0);
        for b in 0..nb {
            let mut q2 = 0.0;
            for k in 0..D {
                let dv = inp.v1[b * D + k] - v0[b * D + k];
                q2 += dv * dv;
                if inp.inv_mass[b] > 0.0 {
                    sum[k] += dv;
                }
            }
            let q = q2.sqrt();
            self.q.push(if q.is_finite() { q } else { 0.0 });
            if inp.inv_mass[b] > 0.0 {
                total += self.q[b];
            }
        }
        // The forces point one way when their velocity changes add up to at least half their
        // sizes (gravity: all of it); "up" is against them.
        let len = sum.iter().map(|s| s * s).sum::<f64>().sqrt();
        self.up = (total > 0.0 && len >= 0.5 * total && len.is_finite()).then(|| sum.map(|s| -s / len));
        let height = |x: &[f64]| self.up.map_or(0.0, |u| (0..D).map(|k| x[k] * u[k]).sum::<f64>());
        // Pairs: the grid's half shell with cells wide enough for the widest contact.
        let rmax = largest(inp.radius);
        let qmax = largest(&self.q);
        let mut contacts = std::mem::take(&mut self.contacts);
        contacts.clear();
        let cell = ((2.0 * rmax) * (1.0 + 1e-9) + 4.0 * self.h * qmax) * (1.0 + 1e-9);
        let mut grid = std::mem::take(&mut self.grid);
        grid.build(&self.x0, D, cell);
        let mut spans = [(0u32, 0u32, 0u64); 14];
        for i in 0..nb {
            let count = grid.partners(i, D, &mut spans);
            for &(lo, hi, key) in &spans[..count] {
                for t in lo as usize..hi.max(lo) as usize {
                    if key != ANY && grid.key_at(t) != key {
                        continue;
                    }
                    let j = grid.order()[t] as usize;
                    let (a, b) = (i.min(j), i.max(j));
                    if inp.inv_mass[a] + inp.inv_mass[b] > 0.0 && self.pair_in::<D>(a, b, inp) {
                        let key = height(&self.x0[a * D..]).min(height(&self.x0[b * D..]));
                        contacts.push(Contact { a: a as u32, b: b as u32, key });
                    }
                }
            }
        }
        self.grid = grid;
        if inp.walls.is_some() {
            for a in (0..nb).filter(|&a| inp.inv_mass[a] > 0.0) {
                for k in 0..D {
                    for side in 0..2 {
                        if self.wall_in::<D>(a, k, side, inp) {
                            let key = height(&self.x0[a * D..]) - inp.radius[a];
                            contacts.push(Contact { a: a as u32, b: WALL + 2 * k as u32 + side, key });
                        }
                    }
                }
            }
        }
        contacts.sort_unstable_by(|c, d| c.key.total_cmp(&d.key).then(c.a.cmp(&d.a)).then(c.b.cmp(&d.b)));
        self.contacts = contacts;
    }

    /// The end state of slot `b`, coordinate `k`: position and velocity.
    #[inline]
    pub fn end(&self, b: usize, k: usize, d: usize) -> (f64, f64) {
        (self.xe[b * d + k], self.ve[b * d + k])
    }

    /// The slots whose state the stage changed.
    pub fn touched(&self) -> &[u32] {
        &self.touched
    }

    /// Moves slot `a` by `c` along `n`.
    #[inline]
    fn shift<const D: usize>(&mut self, a: usize, c: f64, n: &[f64; D]) {
        for k in 0..D {
            self.xe[a * D + k] += c * n[k];
        }
        self.moved[a] = true;
    }

    /// Changes slot `a`'s velocity by `c` along `n`.
    #[inline]
    fn kick<const D: usize>(&mut self, a: usize, c: f64, n: &[f64; D]) {
        for k in 0..D {
            self.ve[a * D + k] += c * n[k];
        }
        self.moved[a] = true;
    }

    /// The unit normal from `a` to `b` at the end positions and their distance.
    #[inline]
    fn normal<const D: usize>(&self, a: usize, b: usize) -> ([f64; D], f64) {
        let mut n = [0.0; D];
        let mut dd = 0.0;
        for k in 0..D {
            n[k] = self.xe[b * D + k] - self.xe[a * D + k];
            dd += n[k] * n[k];
        }
        let dist = dd.sqrt();
        if dist == 0.0 {
            n = [0.0; D];
            n[0] = 1.0;
        } else {
            n.iter_mut().for_each(|c| *c /= dist);
        }
        (n, dist)
    }

    /// A wall contact's unit normal into the box and the ball's gap to the wall at the end.
    #[inline]
    fn wall_normal<const D: usize>(&self, a: usize, w: u32, inp: &Input<'_>) -> ([f64; D], f64) {
        let (k, side) = ((w / 2) as usize, w % 2);
        let walls = inp.walls.expect("a wall contact has walls");
        let (x, r) = (self.xe[a * D + k], inp.radius[a]);
        let mut n = [0.0; D];
        let gap = if side == 0 {
            n[k] = 1.0;
            x - r - walls.lo[k]
        } else {
            n[k] = -1.0;
            walls.hi[k] - r - x
        };
        (n, gap)
    }

    /// Height of the end position of slot `a` (0 without an "up").
    #[inline]
    fn height<const D: usize>(&self, a: usize) -> f64 {
        self.up.map_or(0.0, |u| (0..D).map(|k| self.xe[a * D + k] * u[k]).sum())
    }

    /// The shares of a correction along `n` (from `a` to `b`) that `a` and `b` take: split by
    /// inverse mass; with an "up", the upper ball takes more as the contact is more vertical
    /// (`c = |n . up|`: all of it on a vertical contact, shock propagation; the split on a
    /// level one), never a ball that cannot move.
    #[inline]
    fn shares<const D: usize>(&self, a: usize, b: usize, n: &[f64; D], inp: &Input<'_>) -> (f64, f64) {
        let (wa, wb) = (inp.inv_mass[a], inp.inv_mass[b]);
        let w = wa + wb;
        let (fa, fb) = (wa / w, wb / w);
        let Some(up) = self.up else { return (fa, fb) };
        let c = (0..D).map(|k| n[k] * up[k]).sum::<f64>().abs().min(1.0);
        if self.height::<D>(b) >= self.height::<D>(a) {
            let upper = if wb > 0.0 { c + (1.0 - c) * fb } else { 0.0 };
            (1.0 - upper, upper)
        } else {
            let upper = if wa > 0.0 { c + (1.0 - c) * fa } else { 0.0 };
            (upper, 1.0 - upper)
        }
    }

    /// Contact `i`'s unit normal (from `a` to `b`, or into the box) and gap at the end
    /// positions as they are now.
    #[inline]
    fn geometry<const D: usize>(&self, i: usize, inp: &Input<'_>) -> ([f64; D], f64) {
        let c = self.contacts[i];
        let a = c.a as usize;
        if c.b >= WALL {
            return self.wall_normal::<D>(a, c.b - WALL, inp);
        }
        let b = c.b as usize;
        let (n, dist) = self.normal::<D>(a, b);
        (n, dist - inp.radius[a] - inp.radius[b])
    }

    /// Contact `i`'s gap at the start of the step.
    fn start_gap<const D: usize>(&self, i: usize, inp: &Input<'_>) -> f64 {
        let c = self.contacts[i];
        let a = c.a as usize;
        if c.b >= WALL {
            let (w, k, side) = (c.b - WALL, ((c.b - WALL) / 2) as usize, (c.b - WALL) % 2);
            let _ = w;
            let walls = inp.walls.expect("a wall contact has walls");
            let (x, r) = (self.x0[a * D + k], inp.radius[a]);
            return if side == 0 { x - r - walls.lo[k] } else { walls.hi[k] - r - x };
        }
        let b = c.b as usize;
        let mut dd = 0.0;
        for k in 0..D {
            let c = self.x0[b * D + k] - self.x0[a * D + k];
            dd += c * c;
        }
        dd.sqrt() - inp.radius[a] - inp.radius[b]
    }

    /// Contact `i`'s relative normal velocity along `n`, of `v` (by slot).
    #[inline]
    fn vn<const D: usize>(&self, i: usize, n: &[f64; D], v: &[f64]) -> f64 {
        let c = self.contacts[i];
        let a = c.a as usize;
        let mut vn = 0.0;
        for k in 0..D {
            let vb = if c.b >= WALL { 0.0 } else { v[c.b as usize * D + k] };
            vn += (vb - v[a * D + k]) * n[k];
        }
        if c.b >= WALL {
            -vn
        } else {
            vn
        }
    }

    /// The sum of the two radii of contact `i` (the radius for a wall) and the velocity the
    /// forces of the step give its balls.
    #[inline]
    fn size(&self, i: usize, inp: &Input<'_>) -> (f64, f64) {
        let c = self.contacts[i];
        let a = c.a as usize;
        if c.b >= WALL {
            (inp.radius[a], self.q[a])
        } else {
            let b = c.b as usize;
            (inp.radius[a] + inp.radius[b], self.q[a] + self.q[b])
        }
    }

    /// Moves contact `i`'s relative normal velocity along its normal toward its target: its
    /// accumulated push `lambda` (a relative velocity) changed by the shortfall and clamped at
    /// 0 (a contact pushes, never pulls), shared as [`Rest::shares`] says. Returns the change
    /// times `h` (0: none).
    fn push<const D: usize>(&mut self, i: usize, inp: &Input<'_>) -> f64 {
        let (n, t) = (self.normals[i], self.targets[i]);
        let n: [f64; D] = n[..D].try_into().expect("D entries");
        let next = (self.lambda[i] + (t - self.vn::<D>(i, &n, &self.ve))).max(0.0);
        let dv = next - self.lambda[i];
        if dv == 0.0 {
            return 0.0;
        }
        self.lambda[i] = next;
        let c = self.contacts[i];
        let a = c.a as usize;
        if c.b >= WALL {
            self.kick::<D>(a, dv, &n);
            return dv * self.h;
        }
        let b = c.b as usize;
        let (fa, fb) = self.shares::<D>(a, b, &n, inp);
        if fa != 0.0 {
            self.kick::<D>(a, -dv * fa, &n);
        }
        if fb != 0.0 {
            self.kick::<D>(b, dv * fb, &n);
        }
        dv * self.h
    }

    /// Moves contact `i`'s balls apart (positions only) until its gap is at least its target
    /// (`targets[i]`), shared as [`Rest::shares`] says. Returns the displacement (0: none).
    fn project<const D: usize>(&mut self, i: usize, inp: &Input<'_>) -> f64 {
        let (n, gap) = self.geometry::<D>(i, inp);
        // The contact's accumulated displacement: clamped at 0, so a contact pushed apart
        // too far (its lower ball moved since) is pulled back, never past where it began.
        let next = (self.lambda[i] + (self.targets[i] - gap)).max(0.0);
        let short = next - self.lambda[i];
        if short != 0.0 {
            self.lambda[i] = next;
            self.separate::<D>(i, short, &n, inp);
        }
        short
    }

    /// Moves contact `i`'s balls apart by `by` along `n` (positions only), shared as
    /// [`Rest::shares`] says.
    fn separate<const D: usize>(&mut self, i: usize, by: f64, n: &[f64; D], inp: &Input<'_>) {
        let c = self.contacts[i];
        let a = c.a as usize;
        if c.b >= WALL {
            self.shift::<D>(a, by, n);
            return;
        }
        let b = c.b as usize;
        let (fa, fb) = self.shares::<D>(a, b, n, inp);
        if fa != 0.0 {
            self.shift::<D>(a, -by * fa, n);
        }
        if fb != 0.0 {
            self.shift::<D>(b, by * fb, n);
        }
    }

    /// The warm start of the first position pass: each contact that pushed at the end of the
    /// previous step's (`warm`, sorted by slots) starts from that push, applied in the
    /// contacts' order along its normal as it is then.
    fn warm_start<const D: usize>(&mut self, warm: &[Push], inp: &Input<'_>, active: &mut [bool]) {
        if warm.is_empty() {
            return;
        }
        for i in 0..self.contacts.len() {
            let c = self.contacts[i];
            let Ok(j) = warm.binary_search_by(|p| p.key().cmp(&(c.a, c.b))) else { continue };
            let push = warm[j].push;
            let (n, _) = self.geometry::<D>(i, inp);
            self.lambda[i] = push;
            self.separate::<D>(i, push, &n, inp);
            active[i] = true;
        }
    }

    /// Runs `f` (which returns its change: a displacement, or a velocity times `h`) on every
    /// contact, at most `SWEEPS` times: in order of height with an "up" (from the floor up),
    /// else alternating direction. Marks the contacts that changed anything. A sweep whose
    /// largest change is at most `tol` ends the pass (one that changed nothing: the state is
    /// then a fixed point of every contact).
    fn sweeps(&mut self, mut f: impl FnMut(&mut Self, usize) -> f64, tol: f64, active: &mut [bool]) {
        let m = self.contacts.len();
        for sweep in 0..SWEEPS {
            let mut most = 0.0_f64;
            for j in 0..m {
                let i = if sweep % 2 == 0 || self.up.is_some() { j } else { m - 1 - j };
                let change = f(self, i).abs();
                most = most.max(change);
                active[i] |= change != 0.0;
            }
            if most <= tol {
                return;
            }
        }
    }
}

impl Scratch {
    /// After the events: the resting contacts solved on the end state of every ball, the
    /// first position pass warm-started from `warm` (the previous step's pushes), which is
    /// then replaced by this step's. Returns how many contacts acted.
    pub(super) fn rest_finish<const D: usize>(&mut self, inp: &Input<'_>, warm: &mut Vec<Push>) -> u64 {
        let nb = inp.radius.len();
        let mut rest = std::mem::take(&mut self.rest);
        rest.xe.clear();
        rest.xe.extend_from_slice(inp.x1);
        rest.ve.clear();
        rest.ve.extend_from_slice(inp.v1);
        for &b in &self.hits {
            let b = b as usize;
            for k in 0..D {
                let i = b * D + k;
                rest.xe[i] = self.p[i] + (1.0 - self.tau[b]) * self.u[i];
                rest.ve[i] = self.vel[i];
            }
        }
        rest.moved.clear();
        rest.moved.resize(nb, false);
        let m = rest.contacts.len();
        let mut active = std::mem::take(&mut rest.active);
        active.clear();
        active.resize(m, false);
        // 1. Positions, with the velocities of their motion: each contact's balls moved apart
        // until it ends no deeper than it began (touching, for a contact that began apart or
        // touching), and every ball moved gets the velocity of that motion, `dx / h` (so a
        // pile at rest, whose fall in the step is undone, has velocity 0).
        rest.normals.clear();
        rest.targets.clear();
        rest.lambda.clear();
        rest.lambda.resize(m, 0.0);
        for i in 0..m {
            let floor = rest.start_gap::<D>(i, inp).min(0.0);
            rest.normals.push([0.0; 3]);
            rest.targets.push(floor);
        }
        let mut x_start = std::mem::take(&mut rest.x_before);
        x_start.clear();
        x_start.extend_from_slice(&rest.xe);
        let tol = TOL * rest.h * largest(&rest.q);
        rest.warm_start::<D>(warm, inp, &mut active);
        rest.sweeps(|r, i| r.project::<D>(i, inp), tol, &mut active);
        warm.clear();
        for (c, &push) in rest.contacts.iter().zip(&rest.lambda) {
            if push > 0.0 {
                warm.push(Push { a: c.a, b: c.b, push });
            }
        }
        warm.sort_unstable_by_key(Push::key);
        let inv_h = 1.0 / rest.h;
        for b in 0..nb {
            if rest.moved[b] {
                for k in 0..D {
                    let i = b * D + k;
                    rest.ve[i] += (rest.xe[i] - x_start[i]) * inv_h;
                }
            }
        }
        rest.x_before = x_start;
        // 2. An overlap left from before: a fraction of it removed by positions alone (as a
        // velocity it would become motion).
        for i in 0..m {
            rest.targets[i] = (1.0 - BETA) * rest.geometry::<D>(i, inp).1.min(0.0);
            rest.lambda[i] = 0.0;
        }
        rest.sweeps(|r, i| r.project::<D>(i, inp), tol, &mut active);
        // 3. Velocities: a contact that touches at the end does not approach, or bounces at
        // `-e vn_pre` where it approached before the stage faster than twice the velocity the
        // forces of the step give its balls (Box2D's restitution threshold, in units of the
        // step); one apart by `gap` closes it within the next step at most.
        for i in 0..m {
            let (n, gap) = rest.geometry::<D>(i, inp);
            let (r, q) = rest.size(i, inp);
            let pre = rest.vn::<D>(i, &n, inp.v1);
            let t = if gap <= r * 1e-9 && -pre > 2.0 * q { -inp.e * pre } else { f64::NEG_INFINITY };
            rest.normals[i][..D].copy_from_slice(&n);
            rest.targets[i] = t;
            rest.lambda[i] = 0.0;
        }
        rest.sweeps(|r, i| r.push::<D>(i, inp), tol, &mut active);
        // The deepest overlap of a contact at the end.
        let mut deep = 0.0_f64;
        for i in 0..m {
            deep = deep.max(-rest.geometry::<D>(i, inp).1);
        }
        rest.end_overlap = deep;
        rest.touched.clear();
        rest.touched.extend_from_slice(&self.hits);
        for b in 0..nb {
            if rest.moved[b] && !self.hit(b) {
                rest.touched.push(b as u32);
            }
        }
        let acted = active.iter().filter(|a| **a).count() as u64;
        rest.active = active;
        self.rest = rest;
        acted
    }
}
