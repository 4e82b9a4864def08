//! The check after the contacts of a call's last step: the deepest overlap at its end of the
//! balls that were hit. The ends of the other steps of a call are measured by the next step's
//! scan, which tests every pair within reach at its start (`narrow.rs`). See
//! docs/collisions.md.

use super::super::grid::{each_in_rows, ANY};
use super::narrow::within;
use super::{Input, Scratch};

impl Scratch {
    /// The deepest overlap at the end of the step of the balls that were hit, with the balls
    /// within reach of them (every pair that can overlap: the paths are within the bound) and
    /// with the walls. A ball that was not hit kept its integrated straight path, on which no
    /// contact was found: it overlaps nothing that was not hit (the tests check all pairs
    /// independently).
    pub fn overlap(&self, inp: &Input<'_>) -> f64 {
        let events = match inp.d {
            1 => self.overlap_d::<1>(inp),
            2 => self.overlap_d::<2>(inp),
            _ => self.overlap_d::<3>(inp),
        };
        // Below restitution 1, with the contacts the resting solver held.
        if self.rest.on {
            events.max(self.rest.end_overlap)
        } else {
            events
        }
    }

    /// The end-of-step position of slot `b`: on its new path if it was hit, else as
    /// integrated.
    #[allow(clippy::needless_range_loop)] // k indexes the state and the input alike
    #[inline(always)]
    fn end_d<const D: usize>(&self, b: usize, inp: &Input<'_>) -> [f64; D] {
        let (mut e, i) = ([0.0; D], b * D);
        if self.rest.on {
            // Below restitution 1 the resting contacts may have moved any ball.
            for k in 0..D {
                e[k] = self.rest.end(b, k, D).0;
            }
        } else if self.hit(b) {
            for k in 0..D {
                e[k] = self.p[i + k] + (1.0 - self.tau[b]) * self.u[i + k];
            }
        } else {
            e.copy_from_slice(&inp.x1[i..i + D]);
        }
        e
    }

    /// How deep the ball at place `t` of the grid's order overlaps the hit ball at place `q`
    /// (ending at `eb`) at the end of the step; 0 when they are apart or `t` is `q`.
    #[allow(clippy::needless_range_loop)] // k indexes the positions alike
    #[inline(always)]
    fn depth<const D: usize>(&self, inp: &Input<'_>, q: usize, t: usize, eb: &[f64; D]) -> f64 {
        let (grid, aux) = (&self.grid, &self.aux);
        // Each ends within `ext` of the position the grid holds: farther apart there than
        // `r + ext_b + ext_j`, they do not overlap.
        if t == q || !within::<D>(grid.sorted(), aux, q, t) {
            return 0.0;
        }
        let (ej, r) = (self.end_d::<D>(grid.order()[t] as usize, inp), aux[q][0] + aux[t][0]);
        let mut dist2 = 0.0;
        for k in 0..D {
            dist2 += (ej[k] - eb[k]) * (ej[k] - eb[k]);
        }
        // Farther than r (by more than a rounding of the square): no overlap.
        if dist2 < r * r * (1.0 + 1e-12) {
            r - dist2.sqrt()
        } else {
            0.0
        }
    }

    #[allow(clippy::needless_range_loop)] // k indexes the positions and the walls alike
    fn overlap_d<const D: usize>(&self, inp: &Input<'_>) -> f64 {
        let (grid, mut worst) = (&self.grid, 0.0_f64);
        let (mut rows, mut spans) = ([(0u32, 0u32); 9], [(0u32, 0u32, 0u64); 27]);
        for &b in &self.hits {
            let b = b as usize;
            let q = grid.pos_of(b);
            let eb = self.end_d::<D>(b, inp);
            // The balls a re-query reads (`Scratch::predict`, which keeps its own copy of this
            // walk: inline there, measured faster): a grown ball's two cells out; any other's
            // full shell (rows as one run in a dense table, cells whose places must have the
            // key in a hashed one) and the grown balls.
            if self.is_grown[b] {
                grid.shell_within(b, D, 2, |lo, hi, key| {
                    for t in
                        (lo as usize..hi.max(lo) as usize).filter(|&t| key == ANY || grid.key_at(t) == key)
                    {
                        worst = worst.max(self.depth::<D>(inp, q, t, &eb));
                    }
                });
            } else {
                if grid.dense() {
                    let count = grid.shell_dense(q, D, &mut rows);
                    each_in_rows(&rows[..count], D, |t| worst = worst.max(self.depth::<D>(inp, q, t, &eb)));
                } else {
                    let count = grid.shell(b, D, &mut spans);
                    for &(lo, hi, key) in &spans[..count] {
                        for t in (lo as usize..hi.max(lo) as usize).filter(|&t| grid.key_at(t) == key) {
                            worst = worst.max(self.depth::<D>(inp, q, t, &eb));
                        }
                    }
                }
                for &g in &self.grown {
                    worst = worst.max(self.depth::<D>(inp, q, grid.pos_of(g as usize), &eb));
                }
            }
            if let Some(w) = inp.walls {
                let r = self.aux[q][0];
                for k in 0..D {
                    worst = worst.max(w.lo[k] - (eb[k] - r)).max(eb[k] + r - w.hi[k]);
                }
            }
        }
        worst
    }
}
