//! The broad phase: a uniform grid of cubic cells, the balls counting-sorted into a table of
//! cells, rebuilt every pass in O(n) without allocation (the buffers keep their capacity) and
//! read in a deterministic order.
//!
//! A ball's cell is `floor((p - lo) / cell)` per axis; the key is the cell's linear index
//! with two empty cells of margin on every side, so the neighbours `-2..=2` of any cell have
//! keys too (a wide shell, [`Grid::shell_within`], reaches two cells out). The cells `(c0 - 1 ..= c0 + 1, c1 + dy, c2 + dz)` of one row are consecutive
//! keys. Each pair is found once, from the ball whose cell comes first in key order (the
//! half shell: the rest of its own cell, the next cell of its row, the next row, in 3D the
//! next layer).
//!
//! When the box of the balls has few cells (at most `4 n + 4096`, as in any box that the
//! balls fill to a useful density) the table has an entry per cell and a row of cells is one
//! range; else (balls spread thin over a large space) an entry per hash of a cell, in a table
//! of at least `2 n` entries, whose readers keep the balls of the cell they asked for.

/// At most this many cells per axis (the keys of three axes fit a `u64`).
const MAX_CELLS: f64 = (1u64 << 20) as f64;

/// The grid and its scratch.
#[derive(Debug, Clone, Default)]
pub(crate) struct Grid {
    /// The cell key of each slot (the build's scratch), and of each place of `order`.
    slot_keys: Vec<u64>,
    keys: Vec<u64>,
    /// Cells per axis with the margins.
    m: [u64; 3],
    /// Where each table entry's balls start in `order` (`entries + 1` values).
    start: Vec<u32>,
    /// The balls entry by entry, and each slot's place in it.
    order: Vec<u32>,
    pos: Vec<u32>,
    /// The positions in the order of `order` (`d` per ball), read by the narrow phase.
    sorted: Vec<f64>,
    /// Whether the table has an entry per cell (else per hash of a cell, `64 - shift` bits).
    dense: bool,
    shift: u32,
}

impl Grid {
    fn key(&self, c: [u64; 3]) -> u64 {
        c[0] + self.m[0] * (c[1] + self.m[1] * c[2])
    }

    /// The cell coordinates of slot `i` (with the margins of two).
    fn cell_of(&self, i: usize) -> [u64; 3] {
        let k = self.keys[self.pos[i] as usize];
        [k % self.m[0], k / self.m[0] % self.m[1], k / (self.m[0] * self.m[1])]
    }

    /// Sorts the `n` balls at positions `p` (`n * d`, flat) into cells of at least `cell`
    /// metres (larger when the balls spread over more than 2^20 cells on an axis).
    pub fn build(&mut self, p: &[f64], d: usize, cell: f64) {
        match d {
            1 => self.build_d::<1>(p, cell),
            2 => self.build_d::<2>(p, cell),
            _ => self.build_d::<3>(p, cell),
        }
    }

    fn build_d<const D: usize>(&mut self, p: &[f64], cell: f64) {
        let n = p.len() / D;
        let (lo, hi) = bounds::<D>(p);
        let mut cell = cell;
        for k in 0..D {
            cell = cell.max((hi[k] - lo[k]) / (MAX_CELLS - 6.0));
        }
        let inv = 1.0 / cell;
        self.m = [1; 3];
        for k in 0..D {
            // Cells 2..=count + 1 hold balls; two empty cells on either side are the margins
            // (a wide shell reaches two cells out).
            self.m[k] = ((hi[k] - lo[k]) * inv) as u64 + 5;
        }
        let total = self.m[0] * self.m[1] * self.m[2];
        self.dense = total <= 4 * n as u64 + 4096;
        // Counting sort by table entry: the cell itself in a dense table, else the cell's
        // hash in a table of 2^k >= 2 n buckets (a bucket may hold balls of several cells:
        // the reader keeps those of the cell it asked for). Each slot is placed in ascending
        // order (a bucket's balls by slot), which leaves `start[e]` at the end of entry e:
        // shifted back by one.
        self.shift = if self.dense { 0 } else { 64 - (2 * n).next_power_of_two().max(16).trailing_zeros() };
        let entries = if self.dense { total as usize } else { 1usize << (64 - self.shift) };
        self.start.clear();
        self.start.resize(entries + 1, 0);
        self.slot_keys.resize(n, 0);
        if self.dense {
            self.sort::<D, true>(p, lo, inv, entries);
        } else {
            self.sort::<D, false>(p, lo, inv, entries);
        }
    }

    /// The counting sort of the build, for a table with an entry per cell (`DENSE`) or per
    /// hash of a cell.
    #[inline(always)]
    fn sort<const D: usize, const DENSE: bool>(&mut self, p: &[f64], lo: [f64; D], inv: f64, entries: usize) {
        let (n, m, shift) = (p.len() / D, self.m, self.shift);
        let entry = |key: u64| if DENSE { key as usize } else { hashed(key, shift) };
        let start = &mut self.start[..];
        for (slot_key, x) in self.slot_keys.iter_mut().zip(p.chunks_exact(D)) {
            // The key `c0 + m0 (c1 + m1 c2)`, each `c` through i64 (one conversion:
            // `x - lo >= 0`, the same cell as `as u64`).
            let mut key = 0;
            for k in (0..D).rev() {
                let c = (((x[k] - lo[k]) * inv) as i64 as u64).min(m[k] - 5) + 2;
                key = key * m[k] + c;
            }
            *slot_key = key;
            start[entry(key) + 1] += 1;
        }
        // The running sum in a register (no chain through memory).
        let mut sum = 0;
        for c in &mut start[1..] {
            sum += *c;
            *c = sum;
        }
        self.order.resize(n, 0);
        self.pos.resize(n, 0);
        self.keys.resize(n, 0);
        self.sorted.resize(n * D, 0.0);
        let (order, keys, sorted) = (&mut self.order[..], &mut self.keys[..], &mut self.sorted[..]);
        let slots = p.chunks_exact(D).zip(self.pos.iter_mut().zip(&self.slot_keys));
        for (i, (x, (pos, &key))) in slots.enumerate() {
            let e = entry(key);
            let at = start[e] as usize;
            order[at] = i as u32;
            *pos = at as u32;
            keys[at] = key;
            sorted[at * D..(at + 1) * D].copy_from_slice(x);
            start[e] += 1;
        }
        start.copy_within(0..entries, 1);
        start[0] = 0;
    }

    /// The table entry of cell `key`: the key itself (dense) or its hash.
    #[inline]
    fn entry(&self, key: u64) -> usize {
        if self.dense {
            key as usize
        } else {
            hashed(key, self.shift)
        }
    }

    /// The balls, cell by cell (and by slot within a cell).
    #[inline]
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The positions the grid was built from, in the order of [`Grid::order`].
    #[inline]
    pub fn sorted(&self) -> &[f64] {
        &self.sorted
    }

    /// Whether the table has an entry per cell (the ranges of [`Grid::partners`] and
    /// [`Grid::shell`] then hold only the cells asked for).
    #[inline]
    pub fn dense(&self) -> bool {
        self.dense
    }

    /// The place of slot `b` in [`Grid::order`].
    #[inline]
    pub fn pos_of(&self, b: usize) -> usize {
        self.pos[b] as usize
    }

    /// In a dense table, the ranges of [`Grid::order`] that hold the half shell of the ball at
    /// place `q` of the order (as [`Grid::partners`]): the rest of its cell and the next cell
    /// of its row as one range, the three cells of the next row as one, in 3D the three rows
    /// of the next layer. Returns how many of `out` were filled.
    #[inline(always)]
    pub fn half_dense(&self, q: usize, d: usize, out: &mut [(u32, u32); 5]) -> usize {
        let key = self.keys[q] as usize;
        let (m0, m01) = (self.m[0] as usize, (self.m[0] * self.m[1]) as usize);
        out[0] = (q as u32 + 1, self.start[key + 2]);
        if d == 1 {
            return 1;
        }
        let row = |k: usize| (self.start[k - 1], self.start[k + 2]);
        out[1] = row(key + m0);
        if d == 2 {
            return 2;
        }
        out[2] = row(key + m01 - m0);
        out[3] = row(key + m01);
        out[4] = row(key + m01 + m0);
        5
    }

    /// In a dense table, the ranges of [`Grid::order`] that hold the full shell of the ball at
    /// place `q` of the order (as [`Grid::shell`]): each row of three cells around its cell as
    /// one range (`3^(d-1)` of them, the ball among them). Returns how many of `out` were
    /// filled.
    #[inline]
    pub fn shell_dense(&self, q: usize, d: usize, out: &mut [(u32, u32); 9]) -> usize {
        let key = self.keys[q] as usize;
        let (m0, m01) = (self.m[0] as usize, (self.m[0] * self.m[1]) as usize);
        let row = |k: usize| (self.start[k - 1], self.start[k + 2]);
        match d {
            1 => {
                out[0] = row(key);
                1
            }
            2 => {
                [out[0], out[1], out[2]] = [row(key - m0), row(key), row(key + m0)];
                3
            }
            _ => {
                for (z, k) in [key - m01, key, key + m01].into_iter().enumerate() {
                    [out[3 * z], out[3 * z + 1], out[3 * z + 2]] = [row(k - m0), row(k), row(k + m0)];
                }
                9
            }
        }
    }

    /// The ranges of [`Grid::order`] that hold the balls of the cells around slot `i` and its
    /// own (the full shell: `3^d` cells), each with the cell key its balls must have ([`ANY`]
    /// in a dense table, where a row of three cells is one range). Slot `i` is among them.
    /// Returns how many of `out` were filled.
    #[inline]
    pub fn shell(&self, i: usize, d: usize, out: &mut [(u32, u32, u64); 27]) -> usize {
        let mut n = 0;
        self.shell_within(i, d, 1, |lo, hi, key| {
            out[n] = (lo, hi, key);
            n += 1;
        });
        n
    }

    /// Calls `f` with the ranges of [`Grid::order`] that hold the balls of the cells within `w`
    /// (1 or 2) cells of slot `i`'s on every axis (`(2 w + 1)^d` cells, slot `i` among them),
    /// each with the cell key its balls must have ([`ANY`] in a dense table, where a row of
    /// cells is one range).
    pub fn shell_within(&self, i: usize, d: usize, w: u64, mut f: impl FnMut(u32, u32, u64)) {
        let c = self.cell_of(i);
        let (ys, zs) = match d {
            1 => (c[1]..=c[1], c[2]..=c[2]),
            2 => (c[1] - w..=c[1] + w, c[2]..=c[2]),
            _ => (c[1] - w..=c[1] + w, c[2] - w..=c[2] + w),
        };
        for z in zs {
            for y in ys.clone() {
                let (k0, k1) = (self.key([c[0] - w, y, z]), self.key([c[0] + w, y, z]));
                if self.dense {
                    f(self.start[k0 as usize], self.start[k1 as usize + 1], ANY);
                } else {
                    for k in k0..=k1 {
                        let e = self.entry(k);
                        f(self.start[e], self.start[e + 1], k);
                    }
                }
            }
        }
    }

    /// The cell key of the ball at place `q` of [`Grid::order`].
    #[inline]
    pub fn key_at(&self, q: usize) -> u64 {
        self.keys[q]
    }

    /// The ranges of [`Grid::order`] that hold the partners of slot `i` to test, each pair
    /// once (the half shell): the balls after `i` in its own cell, then those in the
    /// neighbouring cells that come after its cell in key order (`+x` in its row; the three
    /// cells of the next row; in 3D the nine of the next layer). Each range comes with the
    /// cell key its balls must have ([`ANY`] in a dense table, where a range holds only the
    /// cells asked for). Returns how many of `out` were filled.
    #[inline]
    pub fn partners(&self, i: usize, d: usize, out: &mut [(u32, u32, u64); 14]) -> usize {
        let c = self.cell_of(i);
        let own = self.key(c);
        let mut n = 0;
        let mut push = |lo: [u64; 3], hi: [u64; 3], first: Option<u32>| {
            let (k0, k1) = (self.key(lo), self.key(hi));
            if self.dense {
                let a = first.unwrap_or(self.start[k0 as usize]);
                out[n] = (a, self.start[k1 as usize + 1], ANY);
                n += 1;
            } else {
                for k in k0..=k1 {
                    let e = self.entry(k);
                    let a = if k == own { first.unwrap_or(self.start[e]) } else { self.start[e] };
                    out[n] = (a, self.start[e + 1], k);
                    n += 1;
                }
            }
        };
        // The rest of the own cell, then the next cell along x.
        push(c, c, Some(self.pos[i] + 1));
        let next = [c[0] + 1, c[1], c[2]];
        push(next, next, None);
        if d > 1 {
            push([c[0] - 1, c[1] + 1, c[2]], [c[0] + 1, c[1] + 1, c[2]], None);
        }
        if d > 2 {
            for y in [c[1] - 1, c[1], c[1] + 1] {
                push([c[0] - 1, y, c[2] + 1], [c[0] + 1, y, c[2] + 1], None);
            }
        }
        n
    }
}

/// Calls `f` with every place of the rows of a dense shell ([`Grid::shell_dense`]: `3^(d-1)`
/// of them), as one run.
#[inline(always)]
pub(crate) fn each_in_rows(rows: &[(u32, u32)], d: usize, f: impl FnMut(usize)) {
    match d {
        1 => Run::<1>::each(rows, f),
        2 => Run::<3>::each(rows, f),
        _ => Run::<9>::each(rows, f),
    }
}

/// Ranges of places read as one run: one loop over them all, so one loop exit to predict
/// rather than one per range (the ranges hold a ball or two each: their exits are a coin
/// toss). The run has `total` places; the `i`-th is [`Run::place`].
pub(crate) struct Run<const K: usize> {
    /// Where each range ends in the run (ranges past those given end at `total`).
    ends: [usize; K],
    /// What turns an index of the run into a place, range by range (`lo - start`, wrapping).
    base: [usize; K],
    pub total: usize,
}

impl<const K: usize> Run<K> {
    /// The run of `ranges` (at most `K`; an inverted range is empty).
    #[inline(always)]
    pub fn new(ranges: &[(u32, u32)]) -> Self {
        let (mut ends, mut base, mut total) = ([0; K], [0; K], 0usize);
        for r in 0..K {
            let (lo, hi) = ranges.get(r).map_or((0, 0), |&(lo, hi)| (lo as usize, hi.max(lo) as usize));
            base[r] = lo.wrapping_sub(total);
            total += hi - lo;
            ends[r] = total;
        }
        Self { ends, base, total }
    }

    /// Calls `f` with every place of `ranges` (at most `K`), as one run.
    #[inline(always)]
    pub fn each(ranges: &[(u32, u32)], mut f: impl FnMut(usize)) {
        let run = Self::new(ranges);
        for i in 0..run.total {
            f(run.place(i));
        }
    }

    /// The place of index `i < total` of the run: in the range after those that end at or
    /// before `i` (counted without a branch).
    #[inline(always)]
    pub fn place(&self, i: usize) -> usize {
        let r: usize = self.ends.iter().map(|&e| usize::from(e <= i)).sum();
        self.base[r].wrapping_add(i)
    }
}

/// The lower and upper corners of the points `p` (`D` entries each; a NaN is passed over),
/// in eight lanes: no chain of dependent comparisons.
fn bounds<const D: usize>(p: &[f64]) -> ([f64; D], [f64; D]) {
    let (mut lo, mut hi) = ([[f64::INFINITY; D]; 8], [[f64::NEG_INFINITY; D]; 8]);
    let mut fold = |l: usize, c: &[f64]| {
        for k in 0..D {
            lo[l][k] = if c[k] < lo[l][k] { c[k] } else { lo[l][k] };
            hi[l][k] = if c[k] > hi[l][k] { c[k] } else { hi[l][k] };
        }
    };
    let chunks = p.chunks_exact(8 * D);
    let rest = chunks.remainder();
    for c in chunks {
        for l in 0..8 {
            fold(l, &c[l * D..(l + 1) * D]);
        }
    }
    for (l, c) in rest.chunks_exact(D).enumerate() {
        fold(l, c);
    }
    let (mut a, mut b) = (lo[0], hi[0]);
    for l in 1..8 {
        for k in 0..D {
            a[k] = if lo[l][k] < a[k] { lo[l][k] } else { a[k] };
            b[k] = if hi[l][k] > b[k] { hi[l][k] } else { b[k] };
        }
    }
    (a, b)
}

/// The bucket of cell `key` in a hashed table of `64 - shift` bits (Fibonacci hashing).
#[inline]
fn hashed(key: u64, shift: u32) -> usize {
    (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> shift) as usize
}

/// The cell key of a range that holds only the cells asked for.
pub(crate) const ANY: u64 = u64::MAX;
