//! The sparse Cholesky factorisation of a [`super::NewtonMatrix`] on its 3 x 3 blocks, in a
//! fill-reducing order: the exact solve, as a preconditioner (conjugate gradients then
//! converge in one iteration, two where the rounding of the first is above their tolerance).
//!
//! `P A P^T = L L^T`, `L` block lower triangular. The order `P` is the minimum-degree order of
//! the springs' graph (the particle with the fewest neighbours eliminated first, its
//! neighbours then joined to each other: the fill; ties to the particle whose neighbours
//! changed longest ago, then to the lowest index), which on a chain is the chain (no fill) and
//! on a cloth's grid keeps the factor within a few times the matrix (about 20 blocks a
//! particle on a 32 x 32 cloth with shear springs, 35 on 100 x 100, against the matrix's 5).
//! The elimination that finds the order writes the pattern of `L` as it goes; both are kept
//! while the springs stay the same: the order depends on the springs alone, never on the
//! state. The numeric factorisation
//! is left-looking (George and Liu's: each column gathers the updates of the columns that
//! reach it, found by linked lists, into a dense block row), every sum in a fixed order on one
//! thread.
//!
//! A grid's factor grows like `n log n` blocks and its work like `n^1.5`: where the pattern
//! would hold more than [`FILL_LIMIT`] blocks a particle (a dense or three-dimensional network
//! of springs), or a pivot block is not positive definite, [`SparseCholesky::factor`] returns
//! `false` and the caller preconditions otherwise.

use super::Block;

/// A block of `L` as the factorisation keeps it: 3 x 3 with each row padded to 4 (the
/// fourth entry 0), so that a row is one 4-wide vector.
type Wide = [[f64; 4]; 3];
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Most blocks of `L` a moving particle may hold (a block is 72 bytes: 14 kB a particle).
pub const FILL_LIMIT: usize = 200;

const NONE: u32 = u32::MAX;

/// The order, the pattern of `L` and its numeric blocks.
#[derive(Debug, Clone, Default)]
pub(super) struct SparseCholesky {
    /// The springs the pattern was made for (as [`super::ic`]'s key) and which particles move.
    key: Vec<Option<(usize, usize)>>,
    moving: Vec<bool>,
    /// Whether the pattern is within [`FILL_LIMIT`].
    fits: bool,
    /// Block products of a numeric factorisation (`sum_j c_j (c_j + 1) / 2 + 1`, `c_j` the
    /// blocks below column `j`'s diagonal).
    products: usize,
    /// The elimination order: the particle (its index) of each column.
    perm: Vec<u32>,
    /// Column `j` of `L` below its diagonal: `row[start[j]..start[j + 1]]`, ascending column
    /// numbers `> j`, and `dest` the same rows as particle indices.
    start: Vec<usize>,
    row: Vec<u32>,
    dest: Vec<u32>,
    /// The matrix's off-diagonal blocks by column: `(row, pair)`, `A_{row, col} = -m_pair`.
    a_start: Vec<usize>,
    a_entry: Vec<(u32, u32)>,
    /// Numeric factor: the blocks of `L` (as `row`) and the inverses of its diagonal blocks.
    l: Vec<Wide>,
    dinv: Vec<Block>,
    /// Scratch of the factorisation: a dense block row, and the linked lists of the columns
    /// waiting on each row with where each has got to.
    w: Vec<Wide>,
    head: Vec<u32>,
    link: Vec<u32>,
    pos: Vec<usize>,
}

impl SparseCholesky {
    /// Whether the pattern kept is that of the springs `pairs` with the particles `free`
    /// moving.
    pub(super) fn same_pattern(&self, pairs: &[(usize, usize, Block)], free: &[bool]) -> bool {
        self.moving == free
            && self.key.len() == pairs.len()
            && pairs.iter().zip(&self.key).all(|(&(i, j, _), k)| *k == super::ic::key(i, j, free))
    }

    /// Makes the order and pattern of the springs `pairs` on `n` particles (those whose ends
    /// both move), unless it is the one kept.
    fn pattern(&mut self, n: usize, pairs: &[(usize, usize, Block)], free: &[bool]) {
        if self.same_pattern(pairs, free) {
            return;
        }
        self.moving.clear();
        self.moving.extend_from_slice(free);
        self.key.clear();
        self.key.extend(pairs.iter().map(|&(i, j, _)| super::ic::key(i, j, free)));
        // The elimination graph: each moving particle's neighbours, ascending, no repeats.
        let mut adj: Vec<Vec<u32>> = vec![Vec::new(); n];
        for &(a, b) in self.key.iter().flatten() {
            adj[a].push(b as u32);
            adj[b].push(a as u32);
        }
        for list in &mut adj {
            list.sort_unstable();
            list.dedup();
        }
        // Ties go to the particle whose neighbours changed longest ago (then the lowest
        // index): on a 100 x 100 cloth a quarter fewer block products than the lowest index
        // first.
        let mut heap: BinaryHeap<Reverse<(usize, u64, u32)>> =
            (0..n).filter(|&p| free[p]).map(|p| Reverse((adj[p].len(), 0, p as u32))).collect();
        let mut changed = vec![0u64; n];
        let mut clock = 0u64;
        let mut done = vec![false; n];
        let mut column = vec![NONE; n];
        self.perm.clear();
        self.start.clear();
        self.start.push(0);
        // Rows as particles until the order is known.
        self.dest.clear();
        let budget = FILL_LIMIT.saturating_mul(heap.len());
        let mut merged = Vec::new();
        while let Some(Reverse((_, stamp, p))) = heap.pop() {
            let p = p as usize;
            if done[p] || changed[p] != stamp {
                continue;
            }
            done[p] = true;
            column[p] = self.perm.len() as u32;
            self.perm.push(p as u32);
            let nb = std::mem::take(&mut adj[p]);
            self.dest.extend_from_slice(&nb);
            self.start.push(self.dest.len());
            if self.dest.len() > budget {
                break;
            }
            // Each neighbour joins the others (and forgets p).
            for &u in &nb {
                let u = u as usize;
                merged.clear();
                let (a, b) = (&adj[u], &nb);
                let (mut i, mut k) = (0, 0);
                while i < a.len() || k < b.len() {
                    let next = match (a.get(i), b.get(k)) {
                        (Some(&x), Some(&y)) if x == y => {
                            i += 1;
                            k += 1;
                            x
                        }
                        (Some(&x), Some(&y)) if x < y => {
                            i += 1;
                            x
                        }
                        (Some(&x), None) => {
                            i += 1;
                            x
                        }
                        (_, Some(&y)) => {
                            k += 1;
                            y
                        }
                        (None, None) => break,
                    };
                    if next as usize != u && next as usize != p {
                        merged.push(next);
                    }
                }
                std::mem::swap(&mut adj[u], &mut merged);
                clock += 1;
                changed[u] = clock;
                heap.push(Reverse((adj[u].len(), clock, u as u32)));
            }
        }
        self.fits = self.dest.len() <= budget;
        if !self.fits {
            return;
        }
        self.products = self.start.windows(2).map(|w| (w[1] - w[0]) * (w[1] - w[0] + 1) / 2 + 1).sum();
        // Rows as columns, ascending within each column.
        self.row.clear();
        self.row.extend(self.dest.iter().map(|&p| column[p as usize]));
        for j in 0..self.perm.len() {
            let (s, e) = (self.start[j], self.start[j + 1]);
            self.row[s..e].sort_unstable();
            for k in s..e {
                self.dest[k] = self.perm[self.row[k] as usize];
            }
        }
        // The matrix's blocks by column (the lower of the two ends).
        let mut by_col: Vec<Vec<(u32, u32)>> = vec![Vec::new(); self.perm.len()];
        for (s, k) in self.key.iter().enumerate() {
            if let Some((a, b)) = *k {
                let (ca, cb) = (column[a], column[b]);
                by_col[ca.min(cb) as usize].push((ca.max(cb), s as u32));
            }
        }
        self.a_start.clear();
        self.a_entry.clear();
        self.a_start.push(0);
        for list in &by_col {
            self.a_entry.extend_from_slice(list);
            self.a_start.push(self.a_entry.len());
        }
    }

    /// Blocks of `L` held by the latest pattern (its diagonal included).
    #[must_use]
    pub(super) fn blocks(&self) -> usize {
        self.row.len() + self.perm.len()
    }

    /// How many solves with the factor cost as much as making it (block products against
    /// the blocks a solve reads twice): about 1 on a chain, 8 on a 32 x 32 cloth.
    #[must_use]
    pub(super) fn cost_in_solves(&self) -> f64 {
        self.products as f64 / (2 * self.blocks()).max(1) as f64
    }

    /// Factors `A` given by its diagonal blocks `diag` and its springs' blocks (`A_ij = -m`);
    /// `false` when the pattern is past [`FILL_LIMIT`] or a pivot is not positive definite.
    pub(super) fn factor(
        &mut self,
        diag: &[Block],
        pairs: &[(usize, usize, Block)],
        free: &[bool],
        dim: usize,
    ) -> bool {
        if diag.len() >= NONE as usize / 2 || pairs.len() >= NONE as usize {
            return false;
        }
        self.pattern(diag.len(), pairs, free);
        if !self.fits {
            return false;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function. The same bits as the baseline path (crate::simd).
            return unsafe { self.numeric_avx2(diag, pairs, dim) };
        }
        self.numeric_dim(diag, pairs, dim)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn numeric_avx2(&mut self, diag: &[Block], pairs: &[(usize, usize, Block)], dim: usize) -> bool {
        self.numeric_dim(diag, pairs, dim)
    }

    #[inline(always)]
    fn numeric_dim(&mut self, diag: &[Block], pairs: &[(usize, usize, Block)], dim: usize) -> bool {
        match dim {
            1 => self.numeric::<1>(diag, pairs),
            2 => self.numeric::<2>(diag, pairs),
            _ => self.numeric::<3>(diag, pairs),
        }
    }

    #[inline(always)]
    fn numeric<const D: usize>(&mut self, diag: &[Block], pairs: &[(usize, usize, Block)]) -> bool {
        let m = self.perm.len();
        self.w.clear();
        self.w.resize(m, [[0.0; 4]; 3]);
        self.head.clear();
        self.head.resize(m, NONE);
        self.link.clear();
        self.link.resize(m, NONE);
        self.pos.clear();
        self.pos.resize(m, 0);
        self.l.clear();
        self.l.resize(self.row.len(), [[0.0; 4]; 3]);
        self.dinv.clear();
        for j in 0..m {
            let mut d = diag[self.perm[j] as usize];
            for &(r, s) in &self.a_entry[self.a_start[j]..self.a_start[j + 1]] {
                sub::<D>(&mut self.w[r as usize], &pairs[s as usize].2);
            }
            // The columns k < j with a block in row j: their blocks from row j down.
            let mut k = self.head[j];
            while k != NONE {
                let ku = k as usize;
                let next = self.link[ku];
                let (p, end) = (self.pos[ku], self.start[ku + 1]);
                let ljk = self.l[p];
                sub_aat::<D>(&mut d, &ljk);
                let lt = transpose(&ljk);
                let w = &mut self.w;
                for (&r, le) in self.row[p + 1..end].iter().zip(&self.l[p + 1..end]) {
                    sub_at::<D>(&mut w[r as usize], le, &lt);
                }
                self.pos[ku] = p + 1;
                if p + 1 < end {
                    let r = self.row[p + 1] as usize;
                    self.link[ku] = self.head[r];
                    self.head[r] = k;
                }
                k = next;
            }
            let Some(inv) = lower_inverse::<D>(&d) else { return false };
            self.dinv.push(inv);
            let (s, end) = (self.start[j], self.start[j + 1]);
            for e in s..end {
                let i = self.row[e] as usize;
                self.l[e] = mul_abt::<D>(&self.w[i], &inv);
                self.w[i] = [[0.0; 4]; 3];
            }
            if s < end {
                self.pos[j] = s;
                let r = self.row[s] as usize;
                self.link[j] = self.head[r];
                self.head[r] = j as u32;
            }
        }
        true
    }

    /// `z = A^-1 r` on `dim`-dimensional particles (rows of particles that do not move:
    /// `z = r`).
    pub(super) fn solve(&self, r: &[f64], z: &mut [f64], dim: usize) {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: as in `factor`.
            return unsafe { self.solve_avx2(r, z, dim) };
        }
        self.solve_dim(r, z, dim);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn solve_avx2(&self, r: &[f64], z: &mut [f64], dim: usize) {
        self.solve_dim(r, z, dim);
    }

    #[inline(always)]
    fn solve_dim(&self, r: &[f64], z: &mut [f64], dim: usize) {
        match dim {
            1 => self.solve_d::<1>(r, z),
            2 => self.solve_d::<2>(r, z),
            _ => self.solve_d::<3>(r, z),
        }
    }

    #[inline(always)]
    fn solve_d<const D: usize>(&self, r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
        // Forward: L y = P r, column by column.
        for (j, &pj) in self.perm.iter().enumerate() {
            let o = pj as usize * D;
            let b: [f64; D] = z[o..o + D].try_into().unwrap_or([0.0; D]);
            let y = mul_vec::<D>(&self.dinv[j], &b);
            z[o..o + D].copy_from_slice(&y);
            for e in self.start[j]..self.start[j + 1] {
                let (l, d) = (&self.l[e], self.dest[e] as usize * D);
                for a in 0..D {
                    let mut s = 0.0;
                    for c in 0..D {
                        s += l[a][c] * y[c];
                    }
                    z[d + a] -= s;
                }
            }
        }
        // Backward: L^T x = y, columns in reverse.
        for j in (0..self.perm.len()).rev() {
            let o = self.perm[j] as usize * D;
            let mut b: [f64; D] = z[o..o + D].try_into().unwrap_or([0.0; D]);
            for e in self.start[j]..self.start[j + 1] {
                let (l, d) = (&self.l[e], self.dest[e] as usize * D);
                for c in 0..D {
                    let mut s = 0.0;
                    for a in 0..D {
                        s += l[a][c] * z[d + a];
                    }
                    b[c] -= s;
                }
            }
            let inv = &self.dinv[j];
            for c in 0..D {
                let mut s = 0.0;
                for a in 0..D {
                    s += inv[a][c] * b[a];
                }
                z[o + c] = s;
            }
        }
    }
}

/// `a -= b` on the leading `D x D` part.
#[inline]
fn sub<const D: usize>(a: &mut Wide, b: &Block) {
    for r in 0..D {
        for c in 0..D {
            a[r][c] -= b[r][c];
        }
    }
}

/// `a -= b b^T` on the leading `D x D` part, each entry `0 + b_r0 b_k0 + b_r1 b_k1 + ...`.
#[inline]
fn sub_aat<const D: usize>(a: &mut Block, b: &Wide) {
    for r in 0..D {
        for k in 0..D {
            let mut s = 0.0;
            for t in 0..D {
                s += b[r][t] * b[k][t];
            }
            a[r][k] -= s;
        }
    }
}

/// `a -= b c^T` given `ct = c^T` (padded: its rows' fourth entries 0), each entry summed as
/// [`sub_aat`] sums it (`0 + b_r0 c_k0 + b_r1 c_k1 + ...`), four at a time along a row.
#[inline]
fn sub_at<const D: usize>(a: &mut Wide, b: &Wide, ct: &Wide) {
    for r in 0..D {
        let mut s = [0.0; 4];
        for t in 0..D {
            let x = b[r][t];
            for k in 0..4 {
                s[k] += x * ct[t][k];
            }
        }
        for k in 0..4 {
            a[r][k] -= s[k];
        }
    }
}

fn transpose(b: &Wide) -> Wide {
    let mut t = [[0.0; 4]; 3];
    for r in 0..3 {
        for k in 0..3 {
            t[k][r] = b[r][k];
        }
    }
    t
}

/// `a b^T` on the leading `D x D` part.
#[inline]
fn mul_abt<const D: usize>(a: &Wide, b: &Block) -> Wide {
    let mut m = [[0.0; 4]; 3];
    for r in 0..D {
        for k in 0..D {
            let mut s = 0.0;
            for t in 0..D {
                s += a[r][t] * b[k][t];
            }
            m[r][k] = s;
        }
    }
    m
}

#[inline]
fn mul_vec<const D: usize>(m: &Block, x: &[f64; D]) -> [f64; D] {
    let mut y = [0.0; D];
    for r in 0..D {
        let mut s = 0.0;
        for c in 0..D {
            s += m[r][c] * x[c];
        }
        y[r] = s;
    }
    y
}

/// The inverse of the Cholesky factor of the leading `D x D` part of a symmetric block (lower
/// triangular, `L L^T = a`): `None` unless the block is positive definite (and finite).
fn lower_inverse<const D: usize>(a: &Block) -> Option<Block> {
    let mut l = [[0.0; 3]; 3];
    for i in 0..D {
        for j in 0..=i {
            let mut s = a[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            if i == j {
                if s.is_nan() || s <= 0.0 || !s.is_finite() {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    // Forward substitution on the identity, column by column.
    let mut inv = [[0.0; 3]; 3];
    for c in 0..D {
        for i in c..D {
            let mut s = if i == c { 1.0 } else { 0.0 };
            for k in c..i {
                s -= l[i][k] * inv[k][c];
            }
            inv[i][c] = s / l[i][i];
        }
    }
    inv.iter().flatten().all(|v| v.is_finite()).then_some(inv)
}
