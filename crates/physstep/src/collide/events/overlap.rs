//! The check after the contacts of a step: the deepest overlap at its end of the balls that
//! were hit. See docs/collisions.md.

use super::super::grid::each_in_rows;
use super::{Input, Scratch, MARGIN};

impl Scratch {
    /// The end-of-step position of slot `b` along `k`: on its new path if it was hit, else as
    /// integrated.
    #[inline(always)]
    pub fn end(&self, b: usize, k: usize, inp: &Input<'_>) -> f64 {
        let i = b * inp.d + k;
        if self.hit(b) {
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
        match inp.d {
            1 => self.overlap_d::<1>(inp),
            2 => self.overlap_d::<2>(inp),
            _ => self.overlap_d::<3>(inp),
        }
    }

    #[allow(clippy::needless_range_loop)] // k indexes the positions and the walls alike
    fn overlap_d<const D: usize>(&self, inp: &Input<'_>) -> f64 {
        let (grid, aux, mut worst) = (&self.grid, &self.aux, 0.0_f64);
        let (order, sorted) = (grid.order(), grid.sorted());
        let at = |q: usize| -> [f64; D] { sorted[q * D..(q + 1) * D].try_into().expect("D entries") };
        let end = |b: usize| -> [f64; D] { std::array::from_fn(|k| self.end(b, k, inp)) };
        let (mut rows, mut spans) = ([(0u32, 0u32); 9], [(0u32, 0u32, 0u64); 27]);
        for &b in &self.hits {
            let b = b as usize;
            let q = grid.pos_of(b);
            let (eb, pb, rb) = (end(b), at(q), aux[q]);
            let mut test = |t: usize| {
                // Each ends within `ext` of the position the grid holds: farther apart there
                // than `r + ext_b + ext_j`, they do not overlap.
                let pj = at(t);
                let mut far = 0.0;
                for k in 0..D {
                    far += (pj[k] - pb[k]) * (pj[k] - pb[k]);
                }
                let reach = (rb[1] + aux[t][1]) * MARGIN;
                if far > reach * reach || t == q {
                    return;
                }
                let (ej, r) = (end(order[t] as usize), rb[0] + aux[t][0]);
                let mut dist2 = 0.0;
                for k in 0..D {
                    dist2 += (ej[k] - eb[k]) * (ej[k] - eb[k]);
                }
                // Farther than r (by more than a rounding of the square): no overlap.
                if dist2 < r * r * (1.0 + 1e-12) {
                    worst = worst.max(r - dist2.sqrt());
                }
            };
            // The shell: rows of cells as one run in a dense table; cells, whose places must
            // have the key, in a hashed one.
            if grid.dense() {
                let count = grid.shell_dense(q, D, &mut rows);
                each_in_rows(&rows[..count], D, test);
            } else {
                let count = grid.shell(b, D, &mut spans);
                for &(lo, hi, key) in &spans[..count] {
                    for t in (lo as usize..hi.max(lo) as usize).filter(|&t| grid.key_at(t) == key) {
                        test(t);
                    }
                }
            }
            if let Some(w) = inp.walls {
                for k in 0..D {
                    worst = worst.max(w.lo[k] - (eb[k] - rb[0])).max(eb[k] + rb[0] - w.hi[k]);
                }
            }
        }
        worst
    }
}
