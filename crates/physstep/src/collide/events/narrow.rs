//! The narrow phase of the events: the scan of a pass (each pair of the grid's half shell
//! that can meet on the current paths, predicted at once), a hit ball's re-query of the full
//! shell around it, and the deepest overlap at the end of the step. See docs/collisions.md.

use super::super::grid::{each_in_rows, Grid, ANY};
use super::{impact, Event, Input, Scratch, MARGIN};
use rayon::prelude::*;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Balls per chunk of the scan (fixed: the chunks never depend on the thread count).
const CHUNK: usize = 512;

/// Above this many balls the scan's chunks run on the rayon pool: below, handing them to the
/// pool and back costs more than the second thread saves (measured: 2 threads 5% slower at
/// 10,000 balls, 12% faster at 20,000).
const PARALLEL_BALLS: usize = 32 * CHUNK;

/// What a chunk of the scan finds: its events, the deepest overlap of a pair at the pass's
/// start; and its scratch, the pairs within reach.
#[derive(Debug, Clone, Default)]
pub(super) struct Chunk {
    events: Vec<Reverse<Event>>,
    deep: f64,
    pairs: Vec<[u32; 2]>,
    cand_q: Vec<u32>,
    cand_t: Vec<u32>,
}

/// What the scan reads: the grid, and each ball's path (`d` entries), radius and radius plus
/// path left, in the grid's order; the pass's start.
struct Near<'a> {
    grid: &'a Grid,
    paths: &'a [f64],
    aux: &'a [[f64; 2]],
    tg: f64,
}

impl Scratch {
    /// The narrow phase of a pass: the grid built from the balls at their positions at the
    /// pass's start `tg` (cells wide enough for every pair that can meet while no ball's
    /// radius plus path left grows past `rmax + left`: `2 rmax + 2 left` with the margin;
    /// see [`Scratch::predict`] for those that do), and each pair of the half shell
    /// that can meet on the current paths (`|x_b - x_a| <= r_a + r_b + (1 - tg)(|u_a| + |u_b|)`,
    /// with a relative margin of 1e-9 over the rounding of the prediction) predicted at once.
    /// Counts the pairs tested.
    pub(super) fn scan(&mut self, inp: &Input<'_>, tg: f64, rmax: f64, rem: f64, tests: &mut u64) {
        let d = inp.d;
        self.grid.build(&self.p, d, (2.0 * rmax + 2.0 * self.left) * MARGIN * MARGIN);
        // The grid is read while the chunks fill their lists: moved out for the scan.
        let grid = std::mem::take(&mut self.grid);
        let (mut paths, mut aux) = (std::mem::take(&mut self.paths), std::mem::take(&mut self.aux));
        let (found, deepest) = match d {
            1 => self.scan_d::<1>(&grid, &mut paths, &mut aux, inp, [tg, rem, rmax]),
            2 => self.scan_d::<2>(&grid, &mut paths, &mut aux, inp, [tg, rem, rmax]),
            _ => self.scan_d::<3>(&grid, &mut paths, &mut aux, inp, [tg, rem, rmax]),
        };
        *tests += found;
        if tg == 0.0 {
            self.start_overlap = deepest;
        }
        self.paths = paths;
        self.aux = aux;
        self.grid = grid;
    }

    /// The scan in fixed chunks of the grid's order (of slots in a hashed table), on the rayon
    /// pool above `PARALLEL_BALLS` balls, each into its own list of events; the lists are then heaped. The heap pops its
    /// events in their total order (time, slots, counters), whatever the order they were
    /// pushed in: the contacts do not depend on the chunks or the thread count. Returns the
    /// pairs tested and the deepest overlap of two balls, or of a ball past a wall, at the
    /// pass's start (every pair that overlaps is within reach).
    fn scan_d<const D: usize>(
        &mut self,
        grid: &Grid,
        paths: &mut Vec<f64>,
        aux: &mut Vec<[f64; 2]>,
        inp: &Input<'_>,
        [tg, rem, rmax]: [f64; 3],
    ) -> (u64, f64) {
        // What a pair's test reads of each ball, in the grid's order (next to its neighbours):
        // its path, radius, and radius plus path left; and the balls within `r + rem` of a
        // wall (only those can reach one within the pass: their path left is at most `rem`).
        let n = grid.order().len();
        paths.resize(n * D, 0.0);
        aux.resize(n, [0.0; 2]);
        // Within `r + rem` of a wall on some axis when outside the box shrunk by that much
        // (by `rmax + rem` with the margin: every such ball, and perhaps a few more, whose
        // walls are then predicted to no event); no ball is without walls.
        let reach = (rmax + rem) * MARGIN;
        for k in 0..D {
            self.inner[k] =
                inp.walls.map_or([f64::NEG_INFINITY, f64::INFINITY], |w| [w.lo[k] + reach, w.hi[k] - reach]);
        }
        let inner = self.inner;
        // Slot by slot (read in order, written to each slot's place); the balls near a wall
        // listed without a branch (each written, kept when near).
        let (u, ext, radius, p) = (&self.u[..n * D], &self.ext[..n], &inp.radius[..n], &self.p[..n * D]);
        let (walled, mut count) = (&mut self.walled, 0);
        walled.resize(n, 0);
        let slots = u.chunks_exact(D).zip(p.chunks_exact(D)).zip(ext.iter().zip(radius));
        for (b, ((ub, pb), (&e, &r))) in slots.enumerate() {
            let q = grid.pos_of(b);
            paths[q * D..(q + 1) * D].copy_from_slice(ub);
            aux[q] = [r, r + e];
            let near = (0..D).fold(false, |near, k| near | (pb[k] <= inner[k][0]) | (pb[k] >= inner[k][1]));
            walled[count] = b as u32;
            count += usize::from(near);
        }
        walled.truncate(count);
        // Only a ball near a wall can be past it.
        let mut deepest = 0.0_f64;
        if let Some(w) = inp.walls {
            for &b in walled.iter() {
                let (b, r) = (b as usize, radius[b as usize]);
                for k in 0..D {
                    deepest = deepest.max(w.lo[k] - (p[b * D + k] - r)).max(p[b * D + k] + r - w.hi[k]);
                }
            }
        }
        let near = &Near { grid, paths, aux, tg };
        let count = n.div_ceil(CHUNK).max(1);
        let mut chunks = std::mem::take(&mut self.chunks);
        chunks.resize_with(count, Chunk::default);
        let me = &*self;
        let run = |(c, out): (usize, &mut Chunk)| -> (u64, f64) {
            out.events.clear();
            out.deep = 0.0;
            let found = me.scan_span::<D>(near, c * CHUNK..((c + 1) * CHUNK).min(n), out);
            (found, out.deep)
        };
        // The deepest overlap is the same whatever the chunks: a maximum.
        let both = |a: (u64, f64), b: (u64, f64)| (a.0 + b.0, a.1.max(b.1));
        let (found, deep) = if n > PARALLEL_BALLS && rayon::current_num_threads() > 1 {
            chunks.par_iter_mut().enumerate().map(run).reduce(|| (0, 0.0), both)
        } else {
            chunks.iter_mut().enumerate().map(run).fold((0, 0.0), both)
        };
        let mut heap = std::mem::take(&mut self.heap).into_vec();
        heap.clear();
        for c in &chunks {
            heap.extend_from_slice(&c.events);
        }
        self.heap = BinaryHeap::from(heap);
        self.chunks = chunks;
        (found, deepest.max(deep))
    }

    /// The scan of the places `span` of the grid's order (of the slots `span` in a hashed
    /// table): their events pushed to `out.events`, the deepest overlap of a pair into
    /// `out.deep`; returns the pairs tested.
    #[inline(always)]
    fn scan_span<const D: usize>(
        &self,
        near: &Near<'_>,
        span: std::ops::Range<usize>,
        out: &mut Chunk,
    ) -> u64 {
        let grid = near.grid;
        if grid.dense() {
            return self.scan_dense::<D>(near, span, out);
        }
        let (mut spans, mut found) = ([(0u32, 0u32, 0u64); 14], 0u64);
        for i in span {
            let q = grid.pos_of(i);
            let count = grid.partners(i, D, &mut spans);
            for &(lo, hi, key) in &spans[..count] {
                for t in lo as usize..hi.max(lo) as usize {
                    if key == ANY || grid.key_at(t) == key {
                        found += 1;
                        if within::<D>(grid.sorted(), near.aux, q, t) {
                            let depth = self.predict_near::<D>(near, q, t, &mut out.events);
                            out.deep = out.deep.max(depth);
                        }
                    }
                }
            }
        }
        found
    }

    /// The scan of the places `span` in a dense table, each ball's half shell (the ranges of
    /// [`Grid::half_dense`]); returns the pairs tested.
    #[inline(always)]
    fn scan_dense<const D: usize>(
        &self,
        near: &Near<'_>,
        span: std::ops::Range<usize>,
        out: &mut Chunk,
    ) -> u64 {
        let grid = near.grid;
        let mut ranges = [(0u32, 0u32); 5];
        // Each ball's candidates listed first, without a branch on how many a range holds:
        // the first `W` places of a range written whatever its length and the cursor moved on
        // by the length (what lies past it is written over); a longer range's rest in a loop.
        // Then one loop over them all (its end always known to the branch predictor) keeps
        // those within reach, again without a branch (about one in eleven is).
        const W: usize = 4;
        let (cq, ct) = (&mut out.cand_q, &mut out.cand_t);
        let mut cur = 0;
        for q in span {
            let count = grid.half_dense(q, D, &mut ranges);
            let need = cur
                + ranges[..count]
                    .iter()
                    .map(|&(lo, hi)| (hi.saturating_sub(lo) as usize).max(W))
                    .sum::<usize>();
            if ct.len() < need {
                ct.resize(2 * need, 0);
                cq.resize(2 * need, 0);
            }
            for &(lo, hi) in &ranges[..count] {
                let len = hi.saturating_sub(lo) as usize;
                let (tw, qw) = (&mut ct[cur..cur + W], &mut cq[cur..cur + W]);
                for w in 0..W {
                    tw[w] = lo + w as u32;
                    qw[w] = q as u32;
                }
                for t in W..len {
                    ct[cur + t] = lo + t as u32;
                    cq[cur + t] = q as u32;
                }
                cur += len;
            }
        }
        let pairs = &mut out.pairs;
        if pairs.len() < cur {
            pairs.resize(cur, [0; 2]);
        }
        let mut kept = 0;
        let (sorted, aux) = (grid.sorted(), near.aux);
        for (&q, &t) in cq[..cur].iter().zip(&ct[..cur]) {
            let (qi, ti) = (q as usize, t as usize);
            let (pi, pj) = (&sorted[qi * D..(qi + 1) * D], &sorted[ti * D..(ti + 1) * D]);
            let mut dist2 = 0.0;
            for k in 0..D {
                dist2 += (pj[k] - pi[k]) * (pj[k] - pi[k]);
            }
            let reach = (aux[qi][1] + aux[ti][1]) * MARGIN;
            pairs[kept] = [q, t];
            kept += usize::from(dist2 <= reach * reach);
        }
        for &[q, t] in &pairs[..kept] {
            let depth = self.predict_near::<D>(near, q as usize, t as usize, &mut out.events);
            out.deep = out.deep.max(depth);
        }
        cur as u64
    }

    /// The impact of the balls at places `q` and `t` of the grid's order, pushed to `out`
    /// when within the step. Every ball is at the pass's start `tg`, where the grid took its
    /// position: the prediction reads the grid's positions and the paths in `near` alone
    /// (the bits of [`Scratch::pair_event`]). Returns how deep they overlap there (0 when
    /// apart or touching).
    #[inline(always)]
    fn predict_near<const D: usize>(
        &self,
        near: &Near<'_>,
        q: usize,
        t: usize,
        out: &mut Vec<Reverse<Event>>,
    ) -> f64 {
        let (sorted, paths, aux) = (near.grid.sorted(), near.paths, near.aux);
        let (mut dk, mut wk, mut dd) = ([0.0; D], [0.0; D], 0.0);
        for k in 0..D {
            dk[k] = sorted[t * D + k] - sorted[q * D + k];
            wk[k] = paths[t * D + k] - paths[q * D + k];
            dd += dk[k] * dk[k];
        }
        let r = aux[q][0] + aux[t][0];
        if let Some(s) = impact(dk, wk, r, near.tg) {
            let order = near.grid.order();
            let (i, j) = (order[q] as usize, order[t] as usize);
            out.push(Reverse(self.event(s, i.min(j), i.max(j) as u32)));
        }
        if dd < r * r {
            depth(r, dd)
        } else {
            0.0
        }
    }

    /// The next events of slot `b`: against the walls, and against the balls that it can
    /// still meet: `|P_b - P_j| <= r_b + r_j + ext_b + ext_j`, `P` the positions the grid was
    /// built from and `ext` how far a ball gets from its `P` by the end of the step on its
    /// current path (with the scan's margin). While both have grown no further than
    /// `rmax + left` (radius plus path left) they are in each other's full shell; a grown
    /// ball (at most `rmax + rem`, `rem` = 1.5 left: a path past the bound starts a new pass)
    /// looks two cells out, and every other ball checks the grown ones.
    pub(super) fn predict<const D: usize>(&mut self, b: usize, inp: &Input<'_>) {
        // Only a ball outside the pass's inner box can reach a wall (its path left from the
        // grid's position is at most `rem`).
        let q = self.grid.pos_of(b);
        let at = &self.grid.sorted()[q * D..(q + 1) * D];
        if (0..D).any(|k| at[k] <= self.inner[k][0] || at[k] >= self.inner[k][1]) {
            self.predict_walls::<D>(b, inp);
        }
        self.predict_d::<D>(b, inp);
    }

    #[allow(clippy::needless_range_loop)] // a place indexes the order and the positions alike
    fn predict_d<const D: usize>(&mut self, b: usize, inp: &Input<'_>) {
        // The events found, pushed once the shell is read (the heap is not borrowed meanwhile).
        let mut found = std::mem::take(&mut self.found);
        let grid = &self.grid;
        let (order, sorted) = (grid.order(), grid.sorted());
        let at = |q: usize| -> [f64; D] { sorted[q * D..(q + 1) * D].try_into().expect("D entries") };
        let q = grid.pos_of(b);
        let (pb, rb, aux) = (at(q), self.aux[q][1], &self.aux);
        let within = |t: usize| {
            let pj = at(t);
            let mut dist2 = 0.0;
            for k in 0..D {
                dist2 += (pj[k] - pb[k]) * (pj[k] - pb[k]);
            }
            let reach = (rb + aux[t][1]) * MARGIN;
            dist2 <= reach * reach
        };
        let mut predict = |j: usize| {
            if let Some(ev) = self.pair_event::<D>(b.min(j), b.max(j), inp) {
                found.push(Reverse(ev));
            }
        };
        if self.is_grown[b] {
            // Its radius plus path left is at most `rmax + rem`: every ball it can meet is
            // within two cells.
            grid.shell_within(b, D, 2, |lo, hi, key| {
                for t in lo as usize..hi.max(lo) as usize {
                    if t != q && (key == ANY || grid.key_at(t) == key) && within(t) {
                        predict(order[t] as usize);
                    }
                }
            });
        } else if grid.dense() {
            // The shell's rows as one run with the filter inline (about one ball in five is
            // within reach), then those predicted.
            let mut rows = [(0u32, 0u32); 9];
            let count = grid.shell_dense(q, D, &mut rows);
            let (mut near, mut kept) = ([0u32; 16], 0);
            each_in_rows(&rows[..count], D, |t| {
                if within(t) && t != q {
                    if kept == near.len() {
                        near.iter().for_each(|&t| predict(order[t as usize] as usize));
                        kept = 0;
                    }
                    near[kept] = t as u32;
                    kept += 1;
                }
            });
            near[..kept].iter().for_each(|&t| predict(order[t as usize] as usize));
        } else {
            let mut spans = [(0u32, 0u32, 0u64); 27];
            let count = grid.shell(b, D, &mut spans);
            for &(lo, hi, key) in &spans[..count] {
                for t in lo as usize..hi.max(lo) as usize {
                    let j = order[t] as usize;
                    if j != b && grid.key_at(t) == key && within(t) {
                        predict(j);
                    }
                }
            }
        }
        if !self.is_grown[b] {
            // The grown balls can meet it from beyond its shell (one in the shell is predicted
            // twice: the same event, the second stale once the first is resolved).
            for &g in &self.grown {
                if g as usize != b && within(grid.pos_of(g as usize)) {
                    predict(g as usize);
                }
            }
        }
        self.heap.extend(found.drain(..));
        self.found = found;
    }

    /// After a contact of slot `b` at `s`: how far it gets from the position the grid was
    /// built from by the end of the step, `|p(s) - P| + (1 - s) |u|`.
    pub(super) fn extent<const D: usize>(&mut self, b: usize, s: f64) {
        let q = self.grid.pos_of(b);
        let from = &self.grid.sorted()[q * D..(q + 1) * D];
        let gone: f64 = (0..D).map(|k| (self.p[b * D + k] - from[k]).powi(2)).sum();
        self.aux[q][1] = self.aux[q][0] + gone.sqrt() + (1.0 - s) * self.speed2::<D>(b).sqrt();
        if self.aux[q][1] > self.rmax + self.left && !self.is_grown[b] {
            self.is_grown[b] = true;
            self.grown.push(b as u32);
        }
    }
}

/// How deep two balls whose radii add to `r` overlap at the squared distance `dd < r^2`
/// (rare: out of the scan's loop).
#[cold]
#[inline(never)]
fn depth(r: f64, dd: f64) -> f64 {
    r - dd.sqrt()
}

/// Whether the balls at places `q` and `t` of the grid's order (positions `sorted`, radius
/// and radius plus path left `aux`) are within reach: `|x_t - x_q| <= r_q + ext_q + r_t +
/// ext_t` with the margin. The scan's dense loop and a re-query write it out (measured faster
/// inline).
#[inline(always)]
pub(super) fn within<const D: usize>(sorted: &[f64], aux: &[[f64; 2]], q: usize, t: usize) -> bool {
    let (pi, pj) = (&sorted[q * D..(q + 1) * D], &sorted[t * D..(t + 1) * D]);
    let mut dist2 = 0.0;
    for k in 0..D {
        dist2 += (pj[k] - pi[k]) * (pj[k] - pi[k]);
    }
    let reach = (aux[q][1] + aux[t][1]) * MARGIN;
    dist2 <= reach * reach
}
