//! Contacts resolved at their time of impact inside one step (event-driven within the fixed
//! step).
//!
//! Within the step each ball moves on a straight path from its position at the start of the
//! step `x0` to the integrated one `x1`: at the fraction `s` of the step it is at
//! `x0 + s u` with `u = x1 - x0` (exact for a ball free of forces; under constant gravity the
//! chord of the parabola, at most `g h^2 / 8` from it). Its velocity at `s` is taken linear
//! between the start and end velocities, `v(s) = v1 - (1 - s)(v1 - v0)` (exact under any
//! constant acceleration). The contacts of the step are found as events in time order
//! (a heap of predicted impacts, stale ones recognised by a per-ball counter): at each, the
//! two balls (or the ball and the wall) are moved to `s`, the impulse along the line of
//! centres changes their velocities, the same change (times `h`) their paths, and their
//! next events are predicted. Every ball that was hit ends at the end of its new path.

mod narrow;
mod overlap;
mod rest;

pub(crate) use rest::Push;

use super::grid::Grid;
use super::Walls;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The relative margin of the filters before a pair's prediction, far above its rounding.
const MARGIN: f64 = 1.0 + 1e-9;

/// Second index of an event against a wall: `WALL + 2 axis + side` (side 1: the upper).
const WALL: u32 = u32::MAX - 8;

/// A predicted impact: at the fraction `s` of the step (its bits: `s >= 0`, so they order as
/// the numbers do), of slots `a < b` (or `a` and a wall), made when their counters were
/// `va`, `vb`. Ordered by time, then slots: a deterministic order of simultaneous events.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Event {
    s: u64,
    a: u32,
    b: u32,
    va: u32,
    vb: u32,
}

/// What the stage reads of the world.
pub(crate) struct Input<'a> {
    pub d: usize,
    pub h: f64,
    pub e: f64,
    /// Radius and inverse mass of each ball (slot order).
    pub radius: &'a [f64],
    pub inv_mass: &'a [f64],
    pub walls: Option<&'a Walls>,
    /// Positions and velocities at the end of the integration, by slot (`nb * d`).
    pub x1: &'a [f64],
    pub v1: &'a [f64],
}

/// The earliest time at which two balls at separation `dk` (from the first to the second)
/// with relative path `wk` (per step) at the time `s0` are `r` apart, if they approach and
/// meet within the step: the smaller root of `ww s^2 + 2 dw s + c` (`c = dd - r^2`; at once
/// when they already touch). The same bits whichever ball is first (`-x * -y = x * y`).
#[inline(always)]
pub(super) fn impact<const D: usize>(dk: [f64; D], wk: [f64; D], r: f64, s0: f64) -> Option<f64> {
    let (mut dd, mut dw, mut ww) = (0.0, 0.0, 0.0);
    for k in 0..D {
        dd += dk[k] * dk[k];
        dw += dk[k] * wk[k];
        ww += wk[k] * wk[k];
    }
    if dw >= 0.0 {
        return None;
    }
    let c = dd - r * r;
    let s = if c <= 0.0 {
        s0
    } else {
        let disc = dw * dw - ww * c;
        if disc < 0.0 {
            return None;
        }
        // The smaller root in the form without cancellation.
        s0 + c / (-dw + disc.sqrt())
    };
    (s <= 1.0).then_some(s)
}

/// The largest of `xs` and 0 (a NaN is passed over), in eight lanes: no chain of dependent
/// comparisons.
pub(super) fn largest(xs: &[f64]) -> f64 {
    let mut lanes = [0.0_f64; 8];
    let chunks = xs.chunks_exact(8);
    let rest = chunks.remainder();
    for c in chunks {
        for (l, &x) in lanes.iter_mut().zip(c) {
            *l = if x > *l { x } else { *l };
        }
    }
    for (l, &x) in lanes.iter_mut().zip(rest) {
        *l = if x > *l { x } else { *l };
    }
    lanes.iter().fold(0.0, |m, &l| if l > m { l } else { m })
}

/// The scratch of the stage, kept from step to step (no allocation once warm).
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    /// Start-of-step positions and velocities, by slot (`x0` is taken over as the paths'
    /// origins `p` by [`Scratch::resolve`]: refilled before every step).
    pub x0: Vec<f64>,
    pub v0: Vec<f64>,
    /// Each ball's position `p` at its own time `tau`, its path `u` (displacement over a
    /// whole step) and its velocity `vel` (end-of-step velocity with the impulses so far:
    /// taken from the input at its first contact, left from another step before).
    pub p: Vec<f64>,
    pub u: Vec<f64>,
    pub vel: Vec<f64>,
    pub tau: Vec<f64>,
    /// How many contacts each ball had in this step (stale events carry an older count; the
    /// budget of contacts keeps it far from wrapping).
    ver: Vec<u32>,
    /// The balls hit in this step, in the order of their first contact.
    hits: Vec<u32>,
    /// How far each ball gets by the end of the step, on its current path, from the position
    /// the grid was built from (at most `rem`: the paths are within the bound).
    ext: Vec<f64>,
    /// The path, and the radius and radius plus path left, of each ball in the grid's order
    /// (the scan's).
    paths: Vec<f64>,
    aux: Vec<[f64; 2]>,
    /// The balls within reach of a wall in the pass (found by the scan's gather): those
    /// outside the walls' box shrunk by `(rmax + rem)` with the margin, `inner` (per axis).
    walled: Vec<u32>,
    inner: [[f64; 2]; 3],
    heap: BinaryHeap<Reverse<Event>>,
    /// The events found by a ball's prediction.
    found: Vec<Reverse<Event>>,
    /// The events found by each chunk of the scan.
    chunks: Vec<narrow::Chunk>,
    /// The deepest overlap of two balls, or of a ball past a wall, at the start of the step
    /// (measured by the first pass's scan).
    pub start_overlap: f64,
    /// The pass's largest radius and longest path left at its start, `(1 - tg) umax`: the
    /// grid's cells hold every pair that can meet while no ball's radius plus path left
    /// (`aux[.][1]`) is more than `rmax + left`.
    rmax: f64,
    left: f64,
    /// The balls whose radius plus path left grew past that in the pass's contacts (by slot,
    /// and whether each is among them): a re-query looks two cells out around them, and
    /// checks them from every other ball.
    grown: Vec<u32>,
    is_grown: Vec<bool>,
    grid: Grid,
    /// The resting contacts of a step below restitution 1 (`rest.rs`).
    rest: rest::Rest,
}

/// What a step's contacts came to.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Outcome {
    /// Contacts resolved.
    pub contacts: u64,
    /// Pairs the narrow phase tested.
    pub tests: u64,
}

impl Scratch {
    fn advance<const D: usize>(&mut self, b: usize, s: f64) {
        let dt = s - self.tau[b];
        if dt != 0.0 {
            for k in 0..D {
                self.p[b * D + k] += dt * self.u[b * D + k];
            }
        }
        self.tau[b] = s;
    }

    fn push(&mut self, s: f64, a: usize, b: u32) {
        let ev = self.event(s, a, b);
        self.heap.push(Reverse(ev));
    }

    fn event(&self, s: f64, a: usize, b: u32) -> Event {
        let s = if s <= 0.0 { 0.0 } else { s };
        let vb = if b >= WALL { 0 } else { self.ver[b as usize] };
        Event { s: s.to_bits(), a: a as u32, b, va: self.ver[a], vb }
    }

    /// The earliest impact of slots `a < b` from the later of their times, if in the step.
    fn pair_event<const D: usize>(&self, a: usize, b: usize, inp: &Input<'_>) -> Option<Event> {
        let s0 = self.tau[a].max(self.tau[b]);
        let (mut dk, mut wk) = ([0.0; D], [0.0; D]);
        for k in 0..D {
            let pa = self.p[a * D + k] + (s0 - self.tau[a]) * self.u[a * D + k];
            let pb = self.p[b * D + k] + (s0 - self.tau[b]) * self.u[b * D + k];
            dk[k] = pb - pa;
            wk[k] = self.u[b * D + k] - self.u[a * D + k];
        }
        let s = impact(dk, wk, inp.radius[a] + inp.radius[b], s0)?;
        Some(self.event(s, a, b as u32))
    }

    fn predict_walls<const D: usize>(&mut self, a: usize, inp: &Input<'_>) {
        let Some(w) = inp.walls else { return };
        let r = inp.radius[a];
        for k in 0..D {
            let (pk, uk) = (self.p[a * D + k], self.u[a * D + k]);
            let (gap, side) = if uk < 0.0 {
                (pk - r - w.lo[k], 0)
            } else if uk > 0.0 {
                (w.hi[k] - r - pk, 1)
            } else {
                continue;
            };
            // Reached within the step when gap <= (1 - tau) |u| (tested before dividing).
            let left = 1.0 - self.tau[a];
            if gap <= left * uk.abs() {
                let s = self.tau[a] + if gap <= 0.0 { 0.0 } else { gap / uk.abs() };
                self.push(s.min(1.0), a, WALL + 2 * k as u32 + side);
            }
        }
    }

    /// The velocity of slot `b` along `k` at the fraction `s` of the step.
    fn vel_at<const D: usize>(&self, b: usize, k: usize, s: f64, inp: &Input<'_>) -> f64 {
        let i = b * D + k;
        self.vel[i] - (1.0 - s) * (inp.v1[i] - self.v0[i])
    }

    /// Before the first contact of slot `b` in the step: its velocity `vel` is the input's.
    fn first_contact<const D: usize>(&mut self, b: usize, inp: &Input<'_>) {
        if !self.hit(b) {
            self.vel[b * D..(b + 1) * D].copy_from_slice(&inp.v1[b * D..(b + 1) * D]);
        }
    }

    /// The restitution of a contact of `a` and `b`: the world's for a ball's first contact in
    /// the step, 1 once either ball was already hit in it. Inelastic contacts among balls that
    /// touch (a pile at rest under gravity) converge only geometrically, an endless sequence
    /// of ever smaller impulses (an inelastic collapse); elastic ones end. So energy is taken
    /// at most once per ball per step (Luding and McNamara's TC model, with the step as the
    /// contact duration).
    fn restitution(&self, a: usize, b: usize, inp: &Input<'_>) -> f64 {
        if self.hit(a) || self.hit(b) {
            1.0
        } else {
            inp.e
        }
    }

    /// The impulse between slots `a` and `b` at `s`: `J = -(1 + e) (v_b - v_a).n / (w_a + w_b)`
    /// along the unit line of centres `n` (from `a` to `b`), when they approach.
    #[allow(clippy::needless_range_loop)] // k indexes n, the state and the input alike
    fn collide_pair<const D: usize>(&mut self, a: usize, b: usize, s: f64, inp: &Input<'_>) {
        self.first_contact::<D>(a, inp);
        self.first_contact::<D>(b, inp);
        self.advance::<D>(a, s);
        self.advance::<D>(b, s);
        let (wa, wb) = (inp.inv_mass[a], inp.inv_mass[b]);
        if wa + wb == 0.0 {
            return;
        }
        let mut n = [0.0; D];
        let mut len2 = 0.0;
        for k in 0..D {
            n[k] = self.p[b * D + k] - self.p[a * D + k];
            len2 += n[k] * n[k];
        }
        if len2 == 0.0 {
            n = [0.0; D];
            n[0] = 1.0;
        } else {
            let inv = 1.0 / len2.sqrt();
            n.iter_mut().for_each(|c| *c *= inv);
        }
        let mut rel = 0.0;
        for k in 0..D {
            rel += (self.vel_at::<D>(b, k, s, inp) - self.vel_at::<D>(a, k, s, inp)) * n[k];
        }
        let j = if rel < 0.0 { -(1.0 + self.restitution(a, b, inp)) * rel / (wa + wb) } else { 0.0 };
        let mut ur = 0.0;
        for k in 0..D {
            self.vel[a * D + k] -= j * wa * n[k];
            self.vel[b * D + k] += j * wb * n[k];
            self.u[a * D + k] -= j * wa * inp.h * n[k];
            self.u[b * D + k] += j * wb * inp.h * n[k];
            ur += (self.u[b * D + k] - self.u[a * D + k]) * n[k];
        }
        // The paths must part even where the velocities already do (a force that changed
        // the relative velocity within the step; balls resting on each other under gravity,
        // whose velocities at impact are 0 while their chords approach): the approach of the
        // paths along n is reflected, split by inverse mass (an elastic exchange of path, not
        // of velocity: no energy moves). Only reflecting ends such chains: removing the
        // approach alone would hand half of it back and forth without end (Zeno).
        if ur < 0.0 {
            let c = -2.0 * ur / (wa + wb);
            for k in 0..D {
                self.u[a * D + k] -= c * wa * n[k];
                self.u[b * D + k] += c * wb * n[k];
            }
        }
    }

    /// The bounce of slot `a` off wall `k` (`side` 1: the upper) at `s`.
    fn collide_wall<const D: usize>(&mut self, a: usize, k: usize, side: u32, s: f64, inp: &Input<'_>) {
        self.first_contact::<D>(a, inp);
        self.advance::<D>(a, s);
        if inp.inv_mass[a] == 0.0 {
            return;
        }
        let i = a * D + k;
        let w = self.vel_at::<D>(a, k, s, inp);
        if (side == 0 && w < 0.0) || (side == 1 && w > 0.0) {
            let delta = -(1.0 + self.restitution(a, a, inp)) * w;
            self.vel[i] += delta;
            self.u[i] += delta * inp.h;
        }
        if (side == 0 && self.u[i] < 0.0) || (side == 1 && self.u[i] > 0.0) {
            self.u[i] = 0.0;
        }
    }

    /// Counts a contact of slot `b` (its events so far go stale).
    fn count(&mut self, b: usize) {
        if self.ver[b] == 0 {
            self.hits.push(b as u32);
        }
        self.ver[b] = self.ver[b].wrapping_add(1);
    }

    /// The slots whose state the stage changed: the events' hits, then (below restitution 1)
    /// the balls the resting contacts moved.
    #[inline]
    pub fn touched(&self) -> &[u32] {
        if self.rest.on {
            self.rest.touched()
        } else {
            &self.hits
        }
    }

    /// The end of the step of a touched slot `b`, coordinate `k` (`d` per ball): position and
    /// velocity.
    #[inline]
    pub fn end(&self, b: usize, k: usize, d: usize) -> (f64, f64) {
        if self.rest.on {
            self.rest.end(b, k, d)
        } else {
            let i = b * d + k;
            (self.p[i] + (1.0 - self.tau[b]) * self.u[i], self.vel[i])
        }
    }

    /// Whether slot `b` was hit in this step (so far).
    #[inline]
    pub fn hit(&self, b: usize) -> bool {
        self.ver[b] != 0
    }

    fn speed2<const D: usize>(&self, b: usize) -> f64 {
        self.u[b * D..(b + 1) * D].iter().map(|c| c * c).sum()
    }

    /// Each ball's path `u = x1 - p` and its length `ext`; returns the longest squared.
    fn paths_d<const D: usize>(&mut self, x1: &[f64]) -> f64 {
        let n = x1.len() / D;
        self.u.resize(n * D, 0.0);
        self.ext.resize(n, 0.0);
        for ((u, x1), p) in self.u.chunks_exact_mut(D).zip(x1.chunks_exact(D)).zip(self.p.chunks_exact(D)) {
            for k in 0..D {
                u[k] = x1[k] - p[k];
            }
        }
        for (e, u) in self.ext.iter_mut().zip(self.u.chunks_exact(D)) {
            *e = u.iter().fold(0.0, |s2, uk| s2 + uk * uk);
        }
        let most = largest(&self.ext);
        for e in &mut self.ext {
            *e = e.sqrt();
        }
        most
    }

    /// Resolves every contact of the step; the balls that were hit end at `p + (1 - tau) u`
    /// with velocity `vel` (the caller writes them back). Below restitution 1 the resting
    /// contacts' first position pass starts from `warm` (the pushes of the step before, sorted
    /// by slots) and leaves this step's there.
    ///
    /// # Errors
    /// The budget of events, `64 nb + 1024`, when the contacts do not end within it (balls
    /// packed at rest).
    pub fn resolve(&mut self, inp: &Input<'_>, warm: &mut Vec<Push>) -> Result<Outcome, u64> {
        match inp.d {
            1 => self.resolve_d::<1>(inp, warm),
            2 => self.resolve_d::<2>(inp, warm),
            _ => self.resolve_d::<3>(inp, warm),
        }
    }

    fn resolve_d<const D: usize>(&mut self, inp: &Input<'_>, warm: &mut Vec<Push>) -> Result<Outcome, u64> {
        let nb = inp.radius.len();
        self.rest.on = false;
        if inp.e < 1.0 {
            self.rest.begin::<D>(&self.x0, &self.v0, inp);
        }
        // The start positions are the paths' origins: taken over (the next step refills x0).
        std::mem::swap(&mut self.p, &mut self.x0);
        self.vel.resize(nb * D, 0.0);
        self.tau.clear();
        self.tau.resize(nb, 0.0);
        self.ver.clear();
        self.ver.resize(nb, 0);
        self.is_grown.resize(nb, false);
        self.hits.clear();
        // Each path, and the path left from the start, `ext` (the first pass's).
        let mut most = self.paths_d::<D>(inp.x1);
        let rmax = largest(inp.radius);
        let mut out = Outcome::default();
        let cap = 64 * nb as u64 + 1024;
        let mut tg = 0.0;
        'pass: loop {
            // Every ball at tg (the first pass starts where they all are, at 0), and the
            // path each has left: `ext`, how far it gets from there by the end of the step.
            if tg != 0.0 {
                most = 0.0;
                for b in 0..nb {
                    self.advance::<D>(b, tg);
                    let s2 = self.speed2::<D>(b);
                    most = most.max(s2);
                    self.ext[b] = (1.0 - tg) * s2.sqrt();
                }
            }
            let umax = most.sqrt();
            // A path may grow in a collision: between equal masses to at most sqrt(2) times the
            // longer of the two (|v'|^2 <= |v_a|^2 + |v_b|^2), more when a light ball is struck
            // by a heavy one. The grid's cells are sized for the longest path; a ball whose
            // path grows past it is met up to two cells out (`predict`), and up to 1.5 times
            // the longest: past that the pairs are found again from the time of that contact.
            let bound = 1.5 * umax;
            let rem = bound * (1.0 - tg);
            self.heap.clear();
            for &g in &self.grown {
                self.is_grown[g as usize] = false;
            }
            self.grown.clear();
            (self.rmax, self.left) = (rmax, umax * (1.0 - tg));
            self.scan(inp, tg, rmax, rem, &mut out.tests);
            for w in std::mem::take(&mut self.walled) {
                self.predict_walls::<D>(w as usize, inp);
            }
            while let Some(Reverse(ev)) = self.heap.pop() {
                let (a, s) = (ev.a as usize, f64::from_bits(ev.s));
                if self.ver[a] != ev.va || (ev.b < WALL && self.ver[ev.b as usize] != ev.vb) {
                    continue;
                }
                // Below restitution 1: a contact of balls that touched at the start is the
                // resting contacts' business, and so is a second contact among balls already
                // hit in the step (a cluster's inelastic contacts within a step would follow
                // each other without end: an inelastic collapse); each event then hits a
                // fresh ball, so a step takes at most as many events as balls and walls.
                if self.rest.on && self.rest.skips::<D>(a, ev.b, inp) {
                    continue;
                }
                out.contacts += 1;
                if out.contacts > cap {
                    if !self.rest.on {
                        return Err(cap);
                    }
                    // Below restitution 1 the contacts left (an inelastic collapse within the
                    // step) are the resting contacts' at the next step: the balls end on their
                    // paths as they are.
                    out.contacts -= 1;
                    self.heap.clear();
                    break;
                }
                let mut moved = [a, a];
                if ev.b >= WALL {
                    let w = ev.b - WALL;
                    self.collide_wall::<D>(a, (w / 2) as usize, w % 2, s, inp);
                } else {
                    let b = ev.b as usize;
                    self.collide_pair::<D>(a, b, s, inp);
                    self.count(b);
                    moved[1] = b;
                }
                self.count(a);
                if moved.iter().any(|&m| self.speed2::<D>(m) > bound * bound) {
                    tg = s;
                    continue 'pass;
                }
                self.extent::<D>(a, s);
                if moved[1] != a {
                    self.extent::<D>(moved[1], s);
                }
                self.predict::<D>(a, inp);
                if moved[1] != a {
                    self.predict::<D>(moved[1], inp);
                }
            }
            if self.rest.on {
                out.contacts += self.rest_finish::<D>(inp, warm);
            }
            return Ok(out);
        }
    }
}
