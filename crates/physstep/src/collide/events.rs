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

/// The scratch of the stage, kept from step to step (no allocation once warm).
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    /// Start-of-step positions and velocities, by slot (`x0` is taken over as the paths'
    /// origins `p` by [`Scratch::resolve`]: refilled before every step).
    pub x0: Vec<f64>,
    pub v0: Vec<f64>,
    /// Each ball's position `p` at its own time `tau`, its path `u` (displacement over a
    /// whole step) and its velocity `vel` (end-of-step velocity with the impulses so far).
    pub p: Vec<f64>,
    pub u: Vec<f64>,
    pub vel: Vec<f64>,
    pub tau: Vec<f64>,
    ver: Vec<u32>,
    /// When each ball was last hit in this step (-1: not yet).
    last: Vec<f64>,
    /// Whether the ball was hit this step.
    pub hit: Vec<bool>,
    /// How far each ball gets by the end of the step, on its current path, from the position
    /// the grid was built from (at most `rem`: the paths are within the bound).
    ext: Vec<f64>,
    /// Radius and path left of each ball in the grid's order (the scan's).
    aux: Vec<[f64; 2]>,
    heap: BinaryHeap<Reverse<Event>>,
    grid: Grid,
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
    fn advance(&mut self, b: usize, s: f64, d: usize) {
        let dt = s - self.tau[b];
        if dt != 0.0 {
            for k in 0..d {
                self.p[b * d + k] += dt * self.u[b * d + k];
            }
        }
        self.tau[b] = s;
    }

    fn push(&mut self, s: f64, a: usize, b: u32) {
        let s = if s <= 0.0 { 0.0 } else { s };
        let vb = if b >= WALL { 0 } else { self.ver[b as usize] };
        self.heap.push(Reverse(Event { s: s.to_bits(), a: a as u32, b, va: self.ver[a], vb }));
    }

    /// The earliest impact of slots `a < b` from the later of their times, if in the step.
    fn predict_pair(&mut self, a: usize, b: usize, inp: &Input<'_>) {
        let d = inp.d;
        let s0 = self.tau[a].max(self.tau[b]);
        let (mut dd, mut dw, mut ww) = (0.0, 0.0, 0.0);
        for k in 0..d {
            let pa = self.p[a * d + k] + (s0 - self.tau[a]) * self.u[a * d + k];
            let pb = self.p[b * d + k] + (s0 - self.tau[b]) * self.u[b * d + k];
            let (dk, wk) = (pb - pa, self.u[b * d + k] - self.u[a * d + k]);
            dd += dk * dk;
            dw += dk * wk;
            ww += wk * wk;
        }
        if dw >= 0.0 {
            return;
        }
        let r = inp.radius[a] + inp.radius[b];
        let c = dd - r * r;
        let s = if c <= 0.0 {
            s0
        } else {
            let disc = dw * dw - ww * c;
            if disc < 0.0 {
                return;
            }
            // The smaller root of ww s^2 + 2 dw s + c, in the form without cancellation.
            s0 + c / (-dw + disc.sqrt())
        };
        if s <= 1.0 {
            self.push(s, a, b as u32);
        }
    }

    fn predict_walls(&mut self, a: usize, inp: &Input<'_>) {
        let Some(w) = inp.walls else { return };
        let (d, r) = (inp.d, inp.radius[a]);
        for k in 0..d {
            let (pk, uk) = (self.p[a * d + k], self.u[a * d + k]);
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
    fn vel_at(&self, b: usize, k: usize, s: f64, inp: &Input<'_>) -> f64 {
        let i = b * inp.d + k;
        self.vel[i] - (1.0 - s) * (inp.v1[i] - self.v0[i])
    }

    /// The restitution of a contact of `a` and `b`: the world's for a ball's first contact in
    /// the step, 1 once either ball was already hit in it. Inelastic contacts among balls that
    /// touch (a pile at rest under gravity) converge only geometrically, an endless sequence
    /// of ever smaller impulses (an inelastic collapse); elastic ones end. So energy is taken
    /// at most once per ball per step (Luding and McNamara's TC model, with the step as the
    /// contact duration).
    fn restitution(&self, a: usize, b: usize, inp: &Input<'_>) -> f64 {
        if self.last[a] >= 0.0 || self.last[b] >= 0.0 {
            1.0
        } else {
            inp.e
        }
    }

    /// The impulse between slots `a` and `b` at `s`: `J = -(1 + e) (v_b - v_a).n / (w_a + w_b)`
    /// along the unit line of centres `n` (from `a` to `b`), when they approach.
    #[allow(clippy::needless_range_loop)] // k indexes n, the state and the input alike
    fn collide_pair(&mut self, a: usize, b: usize, s: f64, inp: &Input<'_>) {
        let d = inp.d;
        self.advance(a, s, d);
        self.advance(b, s, d);
        let (wa, wb) = (inp.inv_mass[a], inp.inv_mass[b]);
        if wa + wb == 0.0 {
            return;
        }
        let mut n = [0.0; 3];
        let mut len2 = 0.0;
        for k in 0..d {
            n[k] = self.p[b * d + k] - self.p[a * d + k];
            len2 += n[k] * n[k];
        }
        if len2 == 0.0 {
            n = [1.0, 0.0, 0.0];
        } else {
            let inv = 1.0 / len2.sqrt();
            n.iter_mut().for_each(|c| *c *= inv);
        }
        let mut rel = 0.0;
        for k in 0..d {
            rel += (self.vel_at(b, k, s, inp) - self.vel_at(a, k, s, inp)) * n[k];
        }
        let j = if rel < 0.0 { -(1.0 + self.restitution(a, b, inp)) * rel / (wa + wb) } else { 0.0 };
        let mut ur = 0.0;
        for k in 0..d {
            self.vel[a * d + k] -= j * wa * n[k];
            self.vel[b * d + k] += j * wb * n[k];
            self.u[a * d + k] -= j * wa * inp.h * n[k];
            self.u[b * d + k] += j * wb * inp.h * n[k];
            ur += (self.u[b * d + k] - self.u[a * d + k]) * n[k];
        }
        // The paths must part even where the velocities already do (a force that changed
        // the relative velocity within the step; balls resting on each other under gravity,
        // whose velocities at impact are 0 while their chords approach): the approach of the
        // paths along n is reflected, split by inverse mass (an elastic exchange of path, not
        // of velocity: no energy moves). Only reflecting ends such chains: removing the
        // approach alone would hand half of it back and forth without end (Zeno).
        if ur < 0.0 {
            let c = -2.0 * ur / (wa + wb);
            for k in 0..d {
                self.u[a * d + k] -= c * wa * n[k];
                self.u[b * d + k] += c * wb * n[k];
            }
        }
    }

    /// The bounce of slot `a` off wall `k` (`side` 1: the upper) at `s`.
    fn collide_wall(&mut self, a: usize, k: usize, side: u32, s: f64, inp: &Input<'_>) {
        self.advance(a, s, inp.d);
        if inp.inv_mass[a] == 0.0 {
            return;
        }
        let i = a * inp.d + k;
        let w = self.vel_at(a, k, s, inp);
        if (side == 0 && w < 0.0) || (side == 1 && w > 0.0) {
            let delta = -(1.0 + self.restitution(a, a, inp)) * w;
            self.vel[i] += delta;
            self.u[i] += delta * inp.h;
        }
        if (side == 0 && self.u[i] < 0.0) || (side == 1 && self.u[i] > 0.0) {
            self.u[i] = 0.0;
        }
    }

    fn speed2(&self, b: usize, d: usize) -> f64 {
        self.u[b * d..(b + 1) * d].iter().map(|c| c * c).sum()
    }

    /// The narrow phase of a pass: the grid built from the balls at their positions at the
    /// pass's start `tg` (cells wide enough for every pair that can meet while no path is
    /// longer than the bound: `reach = r_a + r_b + 2 rem`), and each pair of the half shell
    /// that can meet on the current paths (`|x_b - x_a| <= r_a + r_b + (1 - tg)(|u_a| + |u_b|)`,
    /// with a relative margin of 1e-9 over the rounding of the prediction) predicted at once.
    /// Counts the pairs tested.
    fn scan(&mut self, inp: &Input<'_>, rem: f64, tests: &mut u64) {
        let d = inp.d;
        let rmax = inp.radius.iter().copied().fold(0.0, f64::max);
        self.grid.build(&self.p, d, 2.0 * rmax + 2.0 * rem);
        // The grid is read while the predictions push events: moved out for the scan.
        let grid = std::mem::take(&mut self.grid);
        // Radius and path left of each ball, in the grid's order.
        let order = grid.order();
        let mut aux = std::mem::take(&mut self.aux);
        aux.clear();
        aux.extend(order.iter().map(|&b| [inp.radius[b as usize], self.ext[b as usize]]));
        *tests += match d {
            1 => self.scan_d::<1>(&grid, &aux, inp),
            2 => self.scan_d::<2>(&grid, &aux, inp),
            _ => self.scan_d::<3>(&grid, &aux, inp),
        };
        self.aux = aux;
        self.grid = grid;
    }

    #[allow(clippy::needless_range_loop)] // a place indexes the order and the positions alike
    fn scan_d<const D: usize>(&mut self, grid: &Grid, aux: &[[f64; 2]], inp: &Input<'_>) -> u64 {
        let (order, sorted) = (grid.order(), grid.sorted());
        let at = |q: usize| -> [f64; D] { sorted[q * D..(q + 1) * D].try_into().expect("D entries") };
        let mut found = 0u64;
        let test = |me: &mut Self, i: usize, q: usize, t: usize| {
            let (pi, pj) = (at(q), at(t));
            let mut dist2 = 0.0;
            for k in 0..D {
                dist2 += (pj[k] - pi[k]) * (pj[k] - pi[k]);
            }
            let reach = (aux[q][0] + aux[t][0] + aux[q][1] + aux[t][1]) * MARGIN;
            if dist2 <= reach * reach {
                let j = order[t] as usize;
                me.predict_pair(i.min(j), i.max(j), inp);
            }
        };
        if grid.dense() {
            let mut ranges = [(0u32, 0u32); 5];
            for q in 0..order.len() {
                let i = order[q] as usize;
                let count = grid.half_dense(q, D, &mut ranges);
                for &(lo, hi) in &ranges[..count] {
                    found += u64::from(hi.saturating_sub(lo));
                    for t in lo as usize..hi as usize {
                        test(self, i, q, t);
                    }
                }
            }
        } else {
            let mut spans = [(0u32, 0u32, 0u64); 14];
            for i in 0..order.len() {
                let q = grid.pos_of(i);
                let count = grid.partners(i, D, &mut spans);
                for &(lo, hi, key) in &spans[..count] {
                    for t in lo as usize..hi.max(lo) as usize {
                        if key == super::grid::ANY || grid.key_of(order[t] as usize) == key {
                            found += 1;
                            test(self, i, q, t);
                        }
                    }
                }
            }
        }
        found
    }

    /// Whether slot `b` (at its position at the pass's start) is within `r + rem` of a wall:
    /// only such a ball can reach one within the pass (its path left is at most `rem`).
    fn near_wall(&self, b: usize, rem: f64, inp: &Input<'_>) -> bool {
        let Some(w) = inp.walls else { return false };
        let (d, r) = (inp.d, inp.radius[b]);
        (0..d).any(|k| {
            let pk = self.p[b * d + k];
            pk - r - w.lo[k] <= rem || w.hi[k] - r - pk <= rem
        })
    }

    /// The next events of slot `b`: against the walls, and against the balls of the full
    /// shell of its cell that it can still meet: `|P_b - P_j| <= r_b + r_j + ext_b + ext_j`,
    /// `P` the positions the grid was built from and `ext` how far a ball gets from its `P`
    /// by the end of the step on its current path (with the scan's margin).
    fn predict(&mut self, b: usize, inp: &Input<'_>) {
        self.predict_walls(b, inp);
        match inp.d {
            1 => self.predict_d::<1>(b, inp),
            2 => self.predict_d::<2>(b, inp),
            _ => self.predict_d::<3>(b, inp),
        }
    }

    #[allow(clippy::needless_range_loop)] // a place indexes the order and the positions alike
    fn predict_d<const D: usize>(&mut self, b: usize, inp: &Input<'_>) {
        let grid = std::mem::take(&mut self.grid);
        let (order, sorted) = (grid.order(), grid.sorted());
        let at = |q: usize| -> [f64; D] { sorted[q * D..(q + 1) * D].try_into().expect("D entries") };
        let pb = at(grid.pos_of(b));
        let rb = inp.radius[b] + self.ext[b];
        let mut spans = [(0u32, 0u32, 0u64); 27];
        let count = grid.shell(b, D, &mut spans);
        for &(lo, hi, key) in &spans[..count] {
            for t in lo as usize..hi.max(lo) as usize {
                let j = order[t] as usize;
                if j == b || (key != super::grid::ANY && grid.key_of(j) != key) {
                    continue;
                }
                let pj = at(t);
                let mut dist2 = 0.0;
                for k in 0..D {
                    dist2 += (pj[k] - pb[k]) * (pj[k] - pb[k]);
                }
                let reach = (rb + inp.radius[j] + self.ext[j]) * MARGIN;
                if dist2 <= reach * reach {
                    self.predict_pair(b.min(j), b.max(j), inp);
                }
            }
        }
        self.grid = grid;
    }

    /// After a contact of slot `b` at `s`: how far it gets from the position the grid was
    /// built from by the end of the step, `|p(s) - P| + (1 - s) |u|`.
    fn extent(&mut self, b: usize, s: f64, d: usize) {
        let q = self.grid.pos_of(b);
        let from = &self.grid.sorted()[q * d..(q + 1) * d];
        let gone: f64 = (0..d).map(|k| (self.p[b * d + k] - from[k]).powi(2)).sum();
        self.ext[b] = gone.sqrt() + (1.0 - s) * self.speed2(b, d).sqrt();
    }

    /// The end-of-step position of slot `b` along `k`: on its new path if it was hit, else as
    /// integrated.
    #[inline]
    pub fn end(&self, b: usize, k: usize, inp: &Input<'_>) -> f64 {
        let i = b * inp.d + k;
        if self.hit[b] {
            self.p[i] + (1.0 - self.tau[b]) * self.u[i]
        } else {
            inp.x1[i]
        }
    }

    /// The deepest overlap at the end of the step of the balls that were hit, with the balls
    /// within reach of them (every pair that can overlap: the paths are within the bound) and
    /// with the walls. A ball that was not hit kept its integrated straight path, on which no
    /// contact was found: it overlaps nothing that was not hit (the tests check all pairs
    /// independently).
    pub fn overlap(&self, inp: &Input<'_>) -> f64 {
        let d = inp.d;
        let (grid, mut worst) = (&self.grid, 0.0_f64);
        let sorted = grid.sorted();
        let mut spans = [(0u32, 0u32, 0u64); 27];
        for b in (0..self.hit.len()).filter(|&b| self.hit[b]) {
            let (mut eb, q) = ([0.0; 3], grid.pos_of(b));
            for (k, e) in eb.iter_mut().enumerate().take(d) {
                *e = self.end(b, k, inp);
            }
            let count = grid.shell(b, d, &mut spans);
            for &(lo, hi, key) in &spans[..count] {
                for t in lo as usize..hi.max(lo) as usize {
                    let j = grid.order()[t] as usize;
                    if j == b || (key != super::grid::ANY && grid.key_of(j) != key) {
                        continue;
                    }
                    let r = inp.radius[b] + inp.radius[j];
                    // Each ends within `ext` of the position the grid holds: farther apart
                    // there than `r + ext_b + ext_j`, they do not overlap.
                    let far: f64 = (0..d).map(|k| (sorted[t * d + k] - sorted[q * d + k]).powi(2)).sum();
                    let reach = (r + self.ext[b] + self.ext[j]) * MARGIN;
                    if far > reach * reach {
                        continue;
                    }
                    let dist2: f64 = (0..d).map(|k| (self.end(j, k, inp) - eb[k]).powi(2)).sum();
                    // Farther than r (by more than a rounding of the square): no overlap.
                    if dist2 < r * r * (1.0 + 1e-12) {
                        worst = worst.max(r - dist2.sqrt());
                    }
                }
            }
            if let Some(w) = inp.walls {
                for (k, &xk) in eb.iter().enumerate().take(d) {
                    let r = inp.radius[b];
                    worst = worst.max(w.lo[k] - (xk - r)).max(xk + r - w.hi[k]);
                }
            }
        }
        worst
    }

    /// Resolves every contact of the step; the balls that were hit end at `p + (1 - tau) u`
    /// with velocity `vel` (the caller writes them back).
    ///
    /// # Errors
    /// The budget of events, `64 nb + 1024`, when the contacts do not end within it (balls
    /// packed at rest).
    pub fn resolve(&mut self, inp: &Input<'_>) -> Result<Outcome, u64> {
        let (d, nb) = (inp.d, inp.radius.len());
        self.u.clear();
        self.u.extend(inp.x1.iter().zip(&self.x0).map(|(x1, x0)| x1 - x0));
        // The start positions are the paths' origins: taken over (the next step refills x0).
        std::mem::swap(&mut self.p, &mut self.x0);
        self.vel.clear();
        self.vel.extend_from_slice(inp.v1);
        self.tau.clear();
        self.tau.resize(nb, 0.0);
        self.ver.clear();
        self.ver.resize(nb, 0);
        self.hit.clear();
        self.hit.resize(nb, false);
        self.last.clear();
        self.last.resize(nb, -1.0);
        let mut out = Outcome::default();
        let cap = 64 * nb as u64 + 1024;
        let mut tg = 0.0;
        'pass: loop {
            // Every ball at tg (the first pass starts where they all are, at 0), and the
            // path each has left: `ext`, how far it gets from there by the end of the step.
            self.ext.resize(nb, 0.0);
            let mut most = 0.0_f64;
            for b in 0..nb {
                if tg != 0.0 {
                    self.advance(b, tg, d);
                }
                let s2 = self.speed2(b, d);
                most = most.max(s2);
                self.ext[b] = (1.0 - tg) * s2.sqrt();
            }
            let umax = most.sqrt();
            // A path may grow in a collision: between equal masses to at most sqrt(2) times the
            // longer of the two (|v'|^2 <= |v_a|^2 + |v_b|^2), more when a light ball is struck
            // by a heavy one. The pairs are chosen for paths up to 1.5 times the longest, and
            // found again (from the time of that contact) when one grows past that.
            let bound = 1.5 * umax;
            let rem = bound * (1.0 - tg);
            self.heap.clear();
            self.scan(inp, rem, &mut out.tests);
            for b in 0..nb {
                if self.near_wall(b, rem, inp) {
                    self.predict_walls(b, inp);
                }
            }
            while let Some(Reverse(ev)) = self.heap.pop() {
                let (a, s) = (ev.a as usize, f64::from_bits(ev.s));
                if self.ver[a] != ev.va || (ev.b < WALL && self.ver[ev.b as usize] != ev.vb) {
                    continue;
                }
                out.contacts += 1;
                if out.contacts > cap {
                    return Err(cap);
                }
                self.ver[a] = self.ver[a].wrapping_add(1);
                self.hit[a] = true;
                let mut moved = [a, a];
                if ev.b >= WALL {
                    let w = ev.b - WALL;
                    self.collide_wall(a, (w / 2) as usize, w % 2, s, inp);
                } else {
                    let b = ev.b as usize;
                    self.collide_pair(a, b, s, inp);
                    self.ver[b] = self.ver[b].wrapping_add(1);
                    self.hit[b] = true;
                    self.last[b] = s;
                    moved[1] = b;
                }
                self.last[a] = s;
                if moved.iter().any(|&m| self.speed2(m, d) > bound * bound) {
                    tg = s;
                    continue 'pass;
                }
                self.extent(a, s, d);
                if moved[1] != a {
                    self.extent(moved[1], s, d);
                }
                self.predict(a, inp);
                if moved[1] != a {
                    self.predict(moved[1], inp);
                }
            }
            return Ok(out);
        }
    }
}
