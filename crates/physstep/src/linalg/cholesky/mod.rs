//! The sparse Cholesky factorisation of a [`super::NewtonMatrix`] on its 3 x 3 blocks, in a
//! fill-reducing order: the exact solve, as a preconditioner (conjugate gradients then
//! converge in one iteration, two where the rounding of the first is above their tolerance).
//!
//! `P A P^T = L L^T`, `L` block lower triangular. The order `P` is a nested dissection of the
//! springs' graph ([`dissect`]: halves before the separators that join them), each stage in
//! minimum-degree order (the particle with the fewest neighbours eliminated first, its
//! neighbours then joined to each other: the fill; ties to the particle whose neighbours
//! changed longest ago, then to the lowest index), which on a chain adds almost no fill and
//! on a cloth's grid keeps the factor within a few times the matrix (about 19 blocks a
//! particle on a 32 x 32 cloth with shear springs, 32 on 100 x 100, against the matrix's 5).
//! The elimination that finds the order writes the pattern of `L` as it goes; both are kept
//! while the springs stay the same: the order depends on the springs alone, never on the
//! state. The numeric factorisation is left-looking (George and Liu's: each column gathers the
//! updates of the columns that reach it, found by linked lists, into a dense block row), on
//! the AVX2 path where the CPU has it (the same bits: `crate::simd`). Past [`SPLIT_MIN`] block
//! products, two subtrees of the elimination tree of about equal work (from the root down, the
//! heaviest subtree replaced by its children while it holds more than half) are factored at
//! once on two threads, each with its own lists and dense row, then their common ancestors,
//! each taking the first subtree's updates, the second's, then the rest's: every sum in an
//! order fixed by the pattern, so the same bits on one thread or two (on a 100 x 100 cloth
//! the two subtrees hold about three quarters of the work: 1.8x faster on two cores).
//!
//! A grid's factor grows like `n log n` blocks and its work like `n^1.5`: where the pattern
//! would hold more than [`FILL_LIMIT`] blocks a particle (a dense or three-dimensional network
//! of springs), or a pivot block is not positive definite, [`SparseCholesky::factor`] returns
//! `false` and the caller preconditions otherwise.

use super::Block;

mod dissect;
mod order;

/// A block of `L` as the factorisation keeps it: 3 x 3 with each row padded to 4 (the
/// fourth entry 0), so that a row is one 4-wide vector.
type Wide = [[f64; 4]; 3];

/// Most blocks of `L` a moving particle may hold (a block is kept in 96 bytes: 19 kB a
/// particle).
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
    /// Column `j` of `L` below its diagonal: `row[span[j].0..span[j].1]`, ascending column
    /// numbers `> j`, and `dest` the same rows as particle indices. The columns are stored in
    /// slot order (`slot[j]`): the first part's, the second's, then the rest's (below).
    span: Vec<(usize, usize)>,
    row: Vec<u32>,
    dest: Vec<u32>,
    /// Each column's place in the storage, and the columns of the three parts in order: two
    /// independent subtrees of the elimination tree, factored at once on two threads, then
    /// their common ancestors.
    slot: Vec<u32>,
    parts: [Vec<u32>; 3],
    /// Where the second part's and the rest's blocks begin in `l`.
    l_split: [usize; 2],
    /// The matrix's off-diagonal blocks by column: `(row, pair)`, `A_{row, col} = -m_pair`.
    a_start: Vec<usize>,
    a_entry: Vec<(u32, u32)>,
    /// Numeric factor: the blocks of `L` (as `row`) and the inverses of its diagonal blocks.
    l: Vec<Wide>,
    dinv: Vec<Block>,
    /// Scratch of the factorisation: a dense block row and the heads of the linked lists of
    /// the columns waiting on each row, per part; each column's link and where it has got to
    /// (by slot).
    w: [Vec<Wide>; 2],
    /// Whether a dense row may hold a value (the latest factorisation broke down).
    dirty: bool,
    head: [Vec<u32>; 3],
    link: Vec<u32>,
    pos: Vec<usize>,
}

/// A factorisation with fewer block products than this runs as one part (the same bits as the
/// two parts would give on one thread or two: the split depends on the pattern alone).
const SPLIT_MIN: usize = 50_000;

/// What a part of the factorisation reads.
struct Shared<'a> {
    diag: &'a [Block],
    pairs: &'a [(usize, usize, Block)],
    perm: &'a [u32],
    span: &'a [(usize, usize)],
    row: &'a [u32],
    slot: &'a [u32],
    a_start: &'a [usize],
    a_entry: &'a [(u32, u32)],
}

/// What a part of the factorisation writes: its slices of the factor and scratch (`l` from
/// block `l_base`, the per-slot arrays from slot `s_base`).
struct Part<'a> {
    l: &'a mut [Wide],
    l_base: usize,
    dinv: &'a mut [Block],
    link: &'a mut [u32],
    pos: &'a mut [usize],
    s_base: usize,
    head: &'a mut [u32],
    w: &'a mut [Wide],
}

impl SparseCholesky {
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
        match dim {
            1 => self.numeric::<1>(diag, pairs),
            2 => self.numeric::<2>(diag, pairs),
            _ => self.numeric::<3>(diag, pairs),
        }
    }

    fn numeric<const D: usize>(&mut self, diag: &[Block], pairs: &[(usize, usize, Block)]) -> bool {
        const ZERO: Wide = [[0.0; 4]; 3];
        let m = self.perm.len();
        // The dense rows start at zero (a column leaves the rows it used at zero: only a
        // factorisation that broke down leaves them dirty) and the lists empty. The factor's
        // blocks, links and places are written before they are read: not cleared.
        for w in &mut self.w {
            if self.dirty || w.len() != m {
                w.clear();
                w.resize(m, ZERO);
            }
        }
        for h in &mut self.head {
            h.clear();
            h.resize(m, NONE);
        }
        self.link.resize(m, NONE);
        self.pos.resize(m, 0);
        self.l.resize(self.row.len(), ZERO);
        self.dinv.resize(m, [[0.0; 3]; 3]);
        self.dirty = true;
        let sh = Shared {
            diag,
            pairs,
            perm: &self.perm,
            span: &self.span,
            row: &self.row,
            slot: &self.slot,
            a_start: &self.a_start,
            a_entry: &self.a_entry,
        };
        let (n0, n1) = (self.parts[0].len(), self.parts[1].len());
        let [h0, h1, h2] = &mut self.head;
        let [w0, w1] = &mut self.w;
        {
            // The two subtrees at once: each writes its own columns' blocks and reads only
            // its own; their updates of the common ancestors wait in their own lists.
            let (l0, rest) = self.l.split_at_mut(self.l_split[0]);
            let l1 = &mut rest[..self.l_split[1] - self.l_split[0]];
            let (d0, rest) = self.dinv.split_at_mut(n0);
            let (k0, krest) = self.link.split_at_mut(n0);
            let (q0, qrest) = self.pos.split_at_mut(n0);
            let mut p0 = Part { l: l0, l_base: 0, dinv: d0, link: k0, pos: q0, s_base: 0, head: h0, w: w0 };
            let mut p1 = Part {
                l: l1,
                l_base: self.l_split[0],
                dinv: &mut rest[..n1],
                link: &mut krest[..n1],
                pos: &mut qrest[..n1],
                s_base: n0,
                head: h1,
                w: w1,
            };
            let (c0, c1) = (&self.parts[0], &self.parts[1]);
            let (a, b) = if n0 + n1 > 0 {
                // Called from outside the pool (a step), the calling thread factors the first
                // part and a worker the second: a `join` would hand both to one worker and
                // wait, and the second part often ran after the first on that worker (the
                // other asleep). 32 x 32 cloth, linearly implicit step: 2.7-3.0 -> 2.4-2.5 ms.
                if rayon::current_thread_index().is_none() && rayon::current_num_threads() > 1 {
                    let mut b = true;
                    let a = rayon::in_place_scope(|s| {
                        s.spawn(|_| b = run_part::<D>(&sh, &mut p1, c1, &[]));
                        run_part::<D>(&sh, &mut p0, c0, &[])
                    });
                    (a, b)
                } else {
                    rayon::join(
                        || run_part::<D>(&sh, &mut p0, c0, &[]),
                        || run_part::<D>(&sh, &mut p1, c1, &[]),
                    )
                }
            } else {
                (true, true)
            };
            if !(a && b) {
                return false; // `dirty` stays set
            }
        }
        // Their common ancestors, each taking the first part's updates, the second's, then
        // its own part's (a fixed order, whatever ran first).
        let mut top = Part {
            l: &mut self.l,
            l_base: 0,
            dinv: &mut self.dinv,
            link: &mut self.link,
            pos: &mut self.pos,
            s_base: 0,
            head: h2,
            w: w0,
        };
        let done = run_part::<D>(&sh, &mut top, &self.parts[2], &[h0, h1]);
        self.dirty = !done;
        done
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
            let y = mul_vec::<D>(&self.dinv[self.slot[j] as usize], &b);
            z[o..o + D].copy_from_slice(&y);
            let (s, end) = self.span[j];
            for e in s..end {
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
            let (s, end) = self.span[j];
            for e in s..end {
                let (l, d) = (&self.l[e], self.dest[e] as usize * D);
                for c in 0..D {
                    let mut s = 0.0;
                    for a in 0..D {
                        s += l[a][c] * z[d + a];
                    }
                    b[c] -= s;
                }
            }
            let inv = &self.dinv[self.slot[j] as usize];
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

/// Factors the columns `cols` of a part, in order (on the AVX2 path where the CPU has it:
/// the same bits, crate::simd), each first taking the updates waiting in the lists `extra`;
/// `false` at a pivot that is not positive definite.
fn run_part<const D: usize>(sh: &Shared<'_>, p: &mut Part<'_>, cols: &[u32], extra: &[&[u32]]) -> bool {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        return unsafe { run_part_avx2::<D>(sh, p, cols, extra) };
    }
    cols.iter().all(|&j| column::<D>(sh, p, j as usize, extra))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_part_avx2<const D: usize>(
    sh: &Shared<'_>,
    p: &mut Part<'_>,
    cols: &[u32],
    extra: &[&[u32]],
) -> bool {
    cols.iter().all(|&j| column::<D>(sh, p, j as usize, extra))
}

/// Column `j` of `L`: `A`'s column, less the updates of the columns `k < j` with a block in
/// row `j` (from the lists `extra`, then the part's own), their blocks from row `j` down
/// gathered into the dense row `w`; then divided by the diagonal's factor.
#[inline(always)]
fn column<const D: usize>(sh: &Shared<'_>, p: &mut Part<'_>, j: usize, extra: &[&[u32]]) -> bool {
    let mut d = sh.diag[sh.perm[j] as usize];
    for &(r, s) in &sh.a_entry[sh.a_start[j]..sh.a_start[j + 1]] {
        sub::<D>(&mut p.w[r as usize], &sh.pairs[s as usize].2);
    }
    for list in 0..=extra.len() {
        let mut k = if list < extra.len() { extra[list][j] } else { std::mem::replace(&mut p.head[j], NONE) };
        while k != NONE {
            let ku = k as usize;
            let sk = sh.slot[ku] as usize - p.s_base;
            let next = p.link[sk];
            let (at, end) = (p.pos[sk], sh.span[ku].1);
            let ljk = p.l[at - p.l_base];
            sub_aat::<D>(&mut d, &ljk);
            let lt = transpose(&ljk);
            let blocks = &p.l[at + 1 - p.l_base..end - p.l_base];
            for (&r, le) in sh.row[at + 1..end].iter().zip(blocks) {
                sub_at::<D>(&mut p.w[r as usize], le, &lt);
            }
            p.pos[sk] = at + 1;
            if at + 1 < end {
                let r = sh.row[at + 1] as usize;
                p.link[sk] = p.head[r];
                p.head[r] = k;
            }
            k = next;
        }
    }
    let Some(inv) = lower_inverse::<D>(&d) else { return false };
    let sj = sh.slot[j] as usize - p.s_base;
    p.dinv[sj] = inv;
    let (s, end) = sh.span[j];
    for e in s..end {
        let i = sh.row[e] as usize;
        p.l[e - p.l_base] = mul_abt::<D>(&p.w[i], &inv);
        p.w[i] = [[0.0; 4]; 3];
    }
    if s < end {
        p.pos[sj] = s;
        let r = sh.row[s] as usize;
        p.link[sj] = p.head[r];
        p.head[r] = j as u32;
    }
    true
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
