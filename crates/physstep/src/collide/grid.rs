//! The broad phase: a uniform grid of cubic cells, kept as one sorted list of
//! `(cell key, ball)` so it is rebuilt every pass without allocation (the buffers keep their
//! capacity) and read in a deterministic order.
//!
//! A ball's cell is `floor((p - lo) / cell)` per axis; the key is the cell's linear index
//! with one empty cell of margin on every side, so the neighbours `-1..=1` of any cell have
//! keys too. The cells `(c0 - 1 ..= c0 + 1, c1 + dy, c2 + dz)` of one row are consecutive
//! keys: a ball finds its neighbours with one binary search per row (3 in 2D, 9 in 3D).
//! Each pair is found once, from its lower slot.

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
        self.keys.sort_unstable();
    }

    /// Calls `pair(i, j)` for every slot `j > i` in the cells around slot `i`'s (the pairs
    /// a narrow phase tests), in a fixed order.
    pub fn neighbours(&self, i: usize, d: usize, mut pair: impl FnMut(usize)) {
        let c = self.cells[i];
        let rows = |k: usize| if k < d { 3 } else { 1 };
        for dz in 0..rows(2) {
            for dy in 0..rows(1) {
                let mut first = c;
                let mut last = c;
                first[0] -= 1;
                last[0] += 1;
                if d > 1 {
                    first[1] = c[1] + dy - 1;
                    last[1] = first[1];
                }
                if d > 2 {
                    first[2] = c[2] + dz - 1;
                    last[2] = first[2];
                }
                let (k0, k1) = (self.key(first), self.key(last));
                let start = self.keys.partition_point(|(k, _)| *k < k0);
                for &(k, j) in &self.keys[start..] {
                    if k > k1 {
                        break;
                    }
                    if j as usize > i {
                        pair(j as usize);
                    }
                }
            }
        }
    }
}
