//! The broad phase: a uniform grid of cubic cells, kept as one sorted list of
//! `(cell key, ball)` so it is rebuilt every pass without allocation (the buffers keep their
//! capacity) and read in a deterministic order.
//!
//! A ball's cell is `floor((p - lo) / cell)` per axis; the key is the cell's linear index
//! with one empty cell of margin on every side, so the neighbours `-1..=1` of any cell have
//! keys too. The cells `(c0 - 1 ..= c0 + 1, c1 + dy, c2 + dz)` of one row are consecutive
//! keys. Each pair is found once, from the ball whose cell comes first in key order (the
//! half shell: the rest of its own cell, the next cell of its row, the next row, in 3D the
//! next layer).
//!
//! When the box of the balls has few cells (at most `4 n + 4096`, as in any box that the
//! balls fill to a useful density) the list is made by a counting sort into a dense table
//! of cell starts instead, and a cell is found by its key directly: O(n), no search.

/// At most this many cells per axis (the keys of three axes fit a `u64`).
const MAX_CELLS: f64 = (1u64 << 20) as f64;

/// The grid and its scratch.
#[derive(Debug, Clone, Default)]
pub(crate) struct Grid {
    /// `(key, slot)` sorted: the balls cell by cell.
    keys: Vec<(u64, u32)>,
    /// Each slot's cell coordinates (with the margin of one).
    cells: Vec<[u64; 3]>,
    /// Cells per axis with the margins.
    m: [u64; 3],
    /// Dense table: where each cell's balls start in `order` (`cells + 1` entries), when used.
    start: Vec<u32>,
    /// The balls cell by cell, and each slot's place in it.
    order: Vec<u32>,
    pos: Vec<u32>,
    dense: bool,
}

impl Grid {
    fn key(&self, c: [u64; 3]) -> u64 {
        c[0] + self.m[0] * (c[1] + self.m[1] * c[2])
    }

    /// Sorts the `n` balls at positions `p` (`n * d`, flat) into cells of at least `cell`
    /// metres (larger when the balls spread over more than 2^20 cells on an axis).
    pub fn build(&mut self, p: &[f64], d: usize, cell: f64) {
        let n = p.len() / d;
        let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
        for k in 0..d {
            lo[k] = f64::INFINITY;
            hi[k] = f64::NEG_INFINITY;
        }
        for b in 0..n {
            for k in 0..d {
                lo[k] = p[b * d + k].min(lo[k]);
                hi[k] = p[b * d + k].max(hi[k]);
            }
        }
        let mut cell = cell;
        for k in 0..d {
            cell = cell.max((hi[k] - lo[k]) / (MAX_CELLS - 4.0));
        }
        let inv = 1.0 / cell;
        self.m = [1; 3];
        for k in 0..d {
            // Cells 1..=count hold balls; 0 and count + 1 are the margins.
            self.m[k] = ((hi[k] - lo[k]) * inv) as u64 + 3;
        }
        self.cells.clear();
        self.keys.clear();
        for b in 0..n {
            let mut c = [0u64; 3];
            for k in 0..d {
                c[k] = (((p[b * d + k] - lo[k]) * inv) as u64).min(self.m[k] - 3) + 1;
            }
            self.cells.push(c);
            self.keys.push((self.key(c), b as u32));
        }
        let total = self.m[0] * self.m[1] * self.m[2];
        self.dense = total <= 4 * n as u64 + 4096;
        self.pos.clear();
        self.pos.resize(n, 0);
        if !self.dense {
            self.keys.sort_unstable();
            self.order.clear();
            self.order.extend(self.keys.iter().map(|(_, b)| *b));
            for (at, b) in self.order.iter().enumerate() {
                self.pos[*b as usize] = at as u32;
            }
            return;
        }
        // Counting sort: counts, starts, then each slot placed in ascending order (a cell's
        // balls by slot), which leaves `start[k]` at the end of cell k: shifted back by one.
        let total = total as usize;
        self.start.clear();
        self.start.resize(total + 1, 0);
        for &(k, _) in &self.keys {
            self.start[k as usize + 1] += 1;
        }
        for k in 0..total {
            self.start[k + 1] += self.start[k];
        }
        self.order.clear();
        self.order.resize(n, 0);
        for &(k, b) in &self.keys {
            let at = &mut self.start[k as usize];
            self.order[*at as usize] = b;
            self.pos[b as usize] = *at;
            *at += 1;
        }
        for k in (1..=total).rev() {
            self.start[k] = self.start[k - 1];
        }
        self.start[0] = 0;
    }

    /// The index range in [`Grid::order`] of the cells with keys `k0..=k1`.
    fn span(&self, k0: u64, k1: u64) -> (u32, u32) {
        if self.dense {
            (self.start[k0 as usize], self.start[k1 as usize + 1])
        } else {
            let a = self.keys.partition_point(|(k, _)| *k < k0);
            let b = self.keys.partition_point(|(k, _)| *k <= k1);
            (a as u32, b as u32)
        }
    }

    /// The balls, cell by cell (and by slot within a cell).
    #[inline]
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The ranges of [`Grid::order`] that hold the partners of slot `i` to test, each pair
    /// once (the half shell): the balls after `i` in its own cell, then those in the
    /// neighbouring cells that come after its cell in key order (`+x` in its row; the three
    /// cells of the next row; in 3D the nine of the next layer). Returns how many of `out`
    /// were filled.
    #[inline]
    pub fn partners(&self, i: usize, d: usize, out: &mut [(u32, u32); 6]) -> usize {
        let c = self.cells[i];
        let own = self.key(c);
        let (_, end) = self.span(own, own);
        out[0] = (self.pos[i] + 1, end);
        let mut n = 1;
        let mut push = |lo: [u64; 3], hi: [u64; 3]| {
            out[n] = self.span(self.key(lo), self.key(hi));
            n += 1;
        };
        // The rest of the own row: the next cell along x.
        let next = [c[0] + 1, c[1], c[2]];
        push(next, next);
        if d > 1 {
            push([c[0] - 1, c[1] + 1, c[2]], [c[0] + 1, c[1] + 1, c[2]]);
        }
        if d > 2 {
            for y in [c[1] - 1, c[1], c[1] + 1] {
                push([c[0] - 1, y, c[2] + 1], [c[0] + 1, y, c[2] + 1]);
            }
        }
        n
    }
}
