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
//! state.
//!
//! The numeric factorisation is supernodal and left-looking: consecutive columns whose
//! patterns nest (a separator of the dissection, whose particles the elimination has joined
//! to each other) are stored together as one dense column-major panel, a supernode; each
//! takes the updates of the supernodes below it that reach it, each update a dense product
//! ([`dense::syrk`]) scattered into its panel, found by linked lists (George and Liu's, over
//! supernodes), and is then factored as a dense matrix ([`dense::factor_panel`]). On a
//! 100 x 100 cloth nine tenths of the work is in supernodes of six particles or more, where
//! the products run at several times the speed of one 3 x 3 block at a time. Past
//! [`SPLIT_MIN`] block products, two subtrees of the elimination tree of about equal work
//! (from the root down, the heaviest subtree replaced by its children while it holds more
//! than half) are factored at once on two threads, each with its own lists and scratch, then
//! their common ancestors, each taking the first subtree's updates, the second's, then the
//! rest's, their large dense products split by columns between the two threads
//! ([`dense::syrk`]): every sum in an order fixed by the pattern, so the same bits on one
//! thread or two, and on the AVX2 and FMA path or not (`crate::simd`).
//!
//! A grid's factor grows like `n log n` blocks and its work like `n^1.5`: where the pattern
//! would hold more than [`FILL_LIMIT`] blocks a particle (a dense or three-dimensional network
//! of springs), or a pivot is not positive, [`SparseCholesky::factor`] returns `false` and
//! the caller preconditions otherwise.

use super::Block;

mod dense;
mod dissect;
mod order;

/// Most blocks of `L` a moving particle may hold (a block is kept in 72 bytes: 14 kB a
/// particle).
pub const FILL_LIMIT: usize = 200;

const NONE: u32 = u32::MAX;

/// A supernode: the columns `first..first + width` of `L`, their dense diagonal block and the
/// rows below it that any of them has (the same for all: the pattern of the last column,
/// `row[below.0..below.1]`).
#[derive(Debug, Clone, Copy, Default)]
struct Super {
    first: u32,
    width: u32,
    below: (usize, usize),
}

impl Super {
    /// The leading dimension of its panel for particles of `d` coordinates: its rows (the
    /// diagonal block's and those below) and [`dense::PAD`].
    fn ld(&self, d: usize) -> usize {
        d * (self.width as usize + self.below.1 - self.below.0) + dense::PAD
    }
}

/// The order, the pattern of `L` and its numeric panels.
#[derive(Debug, Clone, Default)]
pub(super) struct SparseCholesky {
    /// The springs the pattern was made for (as [`super::ic`]'s key) and which particles move.
    key: Vec<Option<(usize, usize)>>,
    moving: Vec<bool>,
    /// Whether the pattern is within [`FILL_LIMIT`].
    fits: bool,
    /// Block products of a numeric factorisation (`sum_j c_j (c_j + 1) / 2 + 1`, `c_j` the
    /// blocks below column `j`'s diagonal) and blocks of `L` (its diagonal included).
    products: usize,
    blocks: usize,
    /// The elimination order: the particle (its index) of each column.
    perm: Vec<u32>,
    /// The columns of the three parts, ascending: two independent subtrees of the
    /// elimination tree and their common ancestors.
    parts: [Vec<u32>; 3],
    /// The supernodes in storage order: the first part's, the second's, then the rest's
    /// (two independent subtrees of the elimination tree, factored at once on two threads,
    /// then their common ancestors), ascending columns within each; where the second part's
    /// and the rest's begin; the supernode of each column.
    sn: Vec<Super>,
    sn_split: [usize; 2],
    sn_of: Vec<u32>,
    /// The rows below the supernodes' diagonal blocks (column numbers, ascending), and the
    /// same rows as particle indices.
    row: Vec<u32>,
    dest: Vec<u32>,
    /// Most rows of a supernode's panel (in blocks).
    max_rows: usize,
    /// The matrix's off-diagonal blocks by column: `(row, pair)`, `A_{row, col} = -m_pair`.
    a_start: Vec<usize>,
    a_entry: Vec<(u32, u32)>,
    /// Numeric factor: each supernode's panel (`D width` columns of `D rows + PAD` doubles,
    /// its rows the diagonal block's then the rows below; the diagonal holds the reciprocals
    /// of `L`'s) at `off[q]` in `lx`, for the dimension `laid`; where the second part's and
    /// the rest's panels begin.
    lx: Vec<f64>,
    off: Vec<usize>,
    laid: usize,
    lx_split: [usize; 2],
    /// Scratch of the factorisation: the heads of the linked lists of the supernodes waiting
    /// on each supernode, per part; each supernode's link and the first of its rows below
    /// not yet sent; per thread, each column's row in the panel being factored and the
    /// update being scattered.
    head: [Vec<u32>; 3],
    link: Vec<u32>,
    pos: Vec<u32>,
    map: [Vec<u32>; 2],
    upd: [Vec<f64>; 2],
    runs: [Vec<(usize, usize, usize)>; 2],
}

/// A factorisation with fewer block products than this runs as one part (the same bits as the
/// two parts would give on one thread or two: the split depends on the pattern alone).
const SPLIT_MIN: usize = 50_000;

/// What a part of the factorisation reads.
struct Shared<'a> {
    diag: &'a [Block],
    pairs: &'a [(usize, usize, Block)],
    perm: &'a [u32],
    sn: &'a [Super],
    sn_of: &'a [u32],
    row: &'a [u32],
    off: &'a [usize],
    a_start: &'a [usize],
    a_entry: &'a [(u32, u32)],
}

/// What a part of the factorisation writes: its panels (`lx` from `lx_base`), its
/// supernodes' links and places (from supernode `s_base`), its lists' heads and scratch.
struct Part<'a> {
    lx: &'a mut [f64],
    lx_base: usize,
    link: &'a mut [u32],
    pos: &'a mut [u32],
    s_base: usize,
    head: &'a mut [u32],
    map: &'a mut [u32],
    upd: &'a mut Vec<f64>,
    runs: &'a mut Vec<(usize, usize, usize)>,
    /// Whether its large dense products may take the pool's second thread (the common
    /// ancestors, factored after the two subtrees, alone).
    two: bool,
}

impl SparseCholesky {
    /// Blocks of `L` held by the latest pattern (its diagonal included).
    #[must_use]
    pub(super) fn blocks(&self) -> usize {
        self.blocks
    }

    /// How many solves with the factor cost as much as making it (block products against
    /// the blocks a solve reads twice): about 1 on a chain, 6 on a 32 x 32 cloth.
    #[must_use]
    pub(super) fn cost_in_solves(&self) -> f64 {
        self.products as f64 / (2 * self.blocks()).max(1) as f64
    }

    /// Factors `A` given by its diagonal blocks `diag` and its springs' blocks (`A_ij = -m`);
    /// `false` when the pattern is past [`FILL_LIMIT`] or a pivot is not positive.
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

    /// The panels' places for particles of `D` coordinates (kept while the pattern and `D`
    /// stay the same).
    fn layout<const D: usize>(&mut self) {
        if self.laid == D && self.off.len() == self.sn.len() + 1 {
            return;
        }
        self.off.clear();
        let mut at = 0;
        for (q, sn) in self.sn.iter().enumerate() {
            if q == self.sn_split[0] {
                self.lx_split[0] = at;
            }
            if q == self.sn_split[1] {
                self.lx_split[1] = at;
            }
            self.off.push(at);
            at += D * sn.width as usize * sn.ld(D);
        }
        for (q, split) in self.sn_split.iter().enumerate() {
            if *split == self.sn.len() {
                self.lx_split[q] = at;
            }
        }
        self.off.push(at);
        self.lx.clear();
        self.lx.resize(at, 0.0);
        self.laid = D;
    }

    fn numeric<const D: usize>(&mut self, diag: &[Block], pairs: &[(usize, usize, Block)]) -> bool {
        self.layout::<D>();
        let (m, ns) = (self.perm.len(), self.sn.len());
        for h in &mut self.head {
            h.clear();
            h.resize(ns, NONE);
        }
        self.link.resize(ns, NONE);
        self.pos.resize(ns, 0);
        for map in &mut self.map {
            map.resize(m, 0);
        }
        let sh = Shared {
            diag,
            pairs,
            perm: &self.perm,
            sn: &self.sn,
            sn_of: &self.sn_of,
            row: &self.row,
            off: &self.off,
            a_start: &self.a_start,
            a_entry: &self.a_entry,
        };
        let [s0, s1] = self.sn_split;
        let [h0, h1, h2] = &mut self.head;
        let [m0, m1] = &mut self.map;
        let [u0, u1] = &mut self.upd;
        let [r0, r1] = &mut self.runs;
        {
            // The two subtrees at once: each writes its own panels and reads only its own;
            // their updates of the common ancestors wait in their own lists.
            let (l0, rest) = self.lx.split_at_mut(self.lx_split[0]);
            let l1 = &mut rest[..self.lx_split[1] - self.lx_split[0]];
            let (k0, krest) = self.link.split_at_mut(s0);
            let (q0, qrest) = self.pos.split_at_mut(s0);
            let mut p0 = Part {
                lx: l0,
                lx_base: 0,
                link: k0,
                pos: q0,
                s_base: 0,
                head: h0,
                map: m0,
                upd: u0,
                runs: r0,
                two: false,
            };
            let mut p1 = Part {
                lx: l1,
                lx_base: self.lx_split[0],
                link: &mut krest[..s1 - s0],
                pos: &mut qrest[..s1 - s0],
                s_base: s0,
                head: h1,
                map: m1,
                upd: u1,
                runs: r1,
                two: false,
            };
            let (a, b) = if s1 > 0 {
                // Called from outside the pool (a step), the calling thread factors the first
                // part and a worker the second: a `join` would hand both to one worker and
                // wait, and the second part often ran after the first on that worker (the
                // other asleep). 32 x 32 cloth, linearly implicit step: 2.7-3.0 -> 2.4-2.5 ms.
                if rayon::current_thread_index().is_none() && rayon::current_num_threads() > 1 {
                    let mut b = true;
                    let a = rayon::in_place_scope(|s| {
                        s.spawn(|_| b = run_part::<D>(&sh, &mut p1, s0..s1, &[]));
                        run_part::<D>(&sh, &mut p0, 0..s0, &[])
                    });
                    (a, b)
                } else {
                    rayon::join(
                        || run_part::<D>(&sh, &mut p0, 0..s0, &[]),
                        || run_part::<D>(&sh, &mut p1, s0..s1, &[]),
                    )
                }
            } else {
                (true, true)
            };
            if !(a && b) {
                return false;
            }
        }
        // Their common ancestors, each taking the first part's updates, the second's, then
        // its own part's (a fixed order, whatever ran first).
        let mut top = Part {
            lx: &mut self.lx,
            lx_base: 0,
            link: &mut self.link,
            pos: &mut self.pos,
            s_base: 0,
            head: h2,
            map: m0,
            upd: u0,
            runs: r0,
            two: rayon::current_num_threads() > 1,
        };
        run_part::<D>(&sh, &mut top, s1..ns, &[h0, h1])
    }

    /// `z = A^-1 r` on `dim`-dimensional particles (rows of particles that do not move:
    /// `z = r`).
    pub(super) fn solve(&self, r: &[f64], z: &mut [f64], dim: usize) {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::fma() {
            // SAFETY: as in `run_part`.
            return unsafe { self.solve_avx2(r, z, dim) };
        }
        self.solve_dim(r, z, dim);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
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

    /// Forward (`L y = P r`) and backward (`L^T x = y`) substitution, supernode by supernode:
    /// its own rows gathered, solved with its diagonal block, and the rows below updated
    /// (forward) or read (backward).
    #[inline(always)]
    fn solve_d<const D: usize>(&self, r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
        if self.laid != D {
            return; // no factor made (the preconditioner is then another)
        }
        let mut buf = vec![0.0; D * self.max_rows];
        for q in 0..self.sn.len() {
            let (sn, dest, panel, ld) = self.panel::<D>(q);
            let (ns, nb) = (D * sn.width as usize, D * dest.len());
            let (x, y) = buf.split_at_mut(ns);
            let y = &mut y[..nb];
            self.own_rows::<D>(sn, z, x, true);
            y.fill(0.0);
            for c in 0..ns {
                let col = &panel[c * ld..c * ld + ns + nb];
                let v = x[c] * col[c];
                x[c] = v;
                for (xi, li) in x[c + 1..].iter_mut().zip(&col[c + 1..ns]) {
                    *xi -= li * v;
                }
                for (yi, li) in y.iter_mut().zip(&col[ns..]) {
                    *yi += li * v;
                }
            }
            self.own_rows::<D>(sn, z, x, false);
            for (&p, yp) in dest.iter().zip(y.chunks_exact(D)) {
                let o = p as usize * D;
                for (zk, yk) in z[o..o + D].iter_mut().zip(yp) {
                    *zk -= yk;
                }
            }
        }
        for q in (0..self.sn.len()).rev() {
            let (sn, dest, panel, ld) = self.panel::<D>(q);
            let (ns, nb) = (D * sn.width as usize, D * dest.len());
            let (x, y) = buf.split_at_mut(ns);
            let y = &mut y[..nb];
            self.own_rows::<D>(sn, z, x, true);
            for (&p, yp) in dest.iter().zip(y.chunks_exact_mut(D)) {
                let o = p as usize * D;
                yp.copy_from_slice(&z[o..o + D]);
            }
            for c in (0..ns).rev() {
                let col = &panel[c * ld..c * ld + ns + nb];
                let t = dense::dot(&col[c + 1..ns], &x[c + 1..]) + dense::dot(&col[ns..], y);
                x[c] = (x[c] - t) * col[c];
            }
            self.own_rows::<D>(sn, z, x, false);
        }
    }

    /// Supernode `q`, the particles of its rows below, its panel and the panel's leading
    /// dimension.
    #[inline(always)]
    fn panel<const D: usize>(&self, q: usize) -> (Super, &[u32], &[f64], usize) {
        let sn = self.sn[q];
        let dest = &self.dest[sn.below.0..sn.below.1];
        let ld = sn.ld(D);
        (sn, dest, &self.lx[self.off[q]..self.off[q + 1]], ld)
    }

    /// The values of supernode `sn`'s own rows: `x` from `z` (`read`), or back.
    #[inline(always)]
    fn own_rows<const D: usize>(&self, sn: Super, z: &mut [f64], x: &mut [f64], read: bool) {
        for (jj, xj) in x.chunks_exact_mut(D).enumerate() {
            let o = self.perm[sn.first as usize + jj] as usize * D;
            if read {
                xj.copy_from_slice(&z[o..o + D]);
            } else {
                z[o..o + D].copy_from_slice(xj);
            }
        }
    }
}

/// Factors the supernodes `range` of a part, in order (on the AVX2 and FMA path where the CPU has them:
/// the same bits, crate::simd), each first taking the updates waiting in the lists `extra`;
/// `false` at a pivot that is not positive.
fn run_part<const D: usize>(
    sh: &Shared<'_>,
    p: &mut Part<'_>,
    range: std::ops::Range<usize>,
    extra: &[&[u32]],
) -> bool {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::fma() {
        // SAFETY: the CPU has AVX2 and FMA (checked by `fma`), the only requirement of a
        // `target_feature` function.
        return unsafe { run_part_avx2::<D>(sh, p, range, extra) };
    }
    range.into_iter().all(|q| supernode::<D>(sh, p, q, extra))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_part_avx2<const D: usize>(
    sh: &Shared<'_>,
    p: &mut Part<'_>,
    range: std::ops::Range<usize>,
    extra: &[&[u32]],
) -> bool {
    range.into_iter().all(|q| supernode::<D>(sh, p, q, extra))
}

/// Supernode `q`'s panel: `A`'s columns, less the updates of the supernodes before it with
/// rows in its columns (from the lists `extra`, then the part's own), each the product of
/// that supernode's rows from there down with those rows ([`dense::syrk`]) scattered into
/// the panel; then factored ([`dense::factor_panel`]) and linked to the supernode of its
/// first row below.
#[inline(always)]
fn supernode<const D: usize>(sh: &Shared<'_>, p: &mut Part<'_>, q: usize, extra: &[&[u32]]) -> bool {
    let sn = sh.sn[q];
    let (f, s) = (sn.first as usize, sn.width as usize);
    let below = &sh.row[sn.below.0..sn.below.1];
    let ns = D * s;
    let rows = ns + D * below.len();
    let ld = sn.ld(D);
    for jj in 0..s {
        p.map[f + jj] = jj as u32;
    }
    for (i, &r) in below.iter().enumerate() {
        p.map[r as usize] = (s + i) as u32;
    }
    let (done, rest) = p.lx.split_at_mut(sh.off[q] - p.lx_base);
    let panel = &mut rest[..ns * ld];
    // Each column from the diagonal down (the part above it is neither written nor read).
    for c in 0..ns {
        panel[c * ld + c..(c + 1) * ld].fill(0.0);
    }
    for jj in 0..s {
        let j = f + jj;
        let d = &sh.diag[sh.perm[j] as usize];
        for b in 0..D {
            for a in 0..D {
                panel[(D * jj + b) * ld + D * jj + a] = d[a][b];
            }
        }
        for &(r, e) in &sh.a_entry[sh.a_start[j]..sh.a_start[j + 1]] {
            let m = &sh.pairs[e as usize].2;
            let at = D * p.map[r as usize] as usize;
            for b in 0..D {
                for a in 0..D {
                    panel[(D * jj + b) * ld + at + a] -= m[a][b];
                }
            }
        }
    }
    for list in 0..=extra.len() {
        let mut k = if list < extra.len() { extra[list][q] } else { std::mem::replace(&mut p.head[q], NONE) };
        while k != NONE {
            let ku = k as usize;
            let kl = ku - p.s_base;
            let next = p.link[kl];
            let kn = sh.sn[ku];
            let kw = kn.width as usize;
            let kb = &sh.row[kn.below.0..kn.below.1];
            let at = p.pos[kl] as usize;
            let tail = &kb[at..];
            let nq = tail.iter().take_while(|&&r| (r as usize) < f + s).count();
            let (mt, nc) = (D * tail.len(), D * nq);
            let kld = kn.ld(D);
            if kw == 1 {
                // One particle's columns: each block's product straight into the panel (the
                // same sums as the product and scatter below, without their set-up, which
                // costs more than the product here: a 32 x 32 cloth's factor 1.65 -> 1.44 ms).
                let a = &done[sh.off[ku] - p.lx_base..sh.off[ku] - p.lx_base + D * kld];
                let r0 = D + D * at;
                // The tail's blocks, each row's `D` entries together (gathered once, read by
                // every column block they meet).
                let blocks = D * D * tail.len();
                if p.upd.len() < blocks {
                    p.upd.resize(blocks, 0.0);
                }
                let g = &mut p.upd[..blocks];
                for (t, gt) in g.chunks_exact_mut(D * D).enumerate() {
                    for (x, row) in gt.chunks_exact_mut(D).enumerate() {
                        for (tau, v) in row.iter_mut().enumerate() {
                            *v = a[tau * kld + r0 + D * t + x];
                        }
                    }
                }
                let g = &p.upd[..blocks];
                for ci in 0..nq {
                    let col = D * (tail[ci] as usize - f);
                    let bc = &g[D * D * ci..D * D * (ci + 1)];
                    for (t, &r) in tail.iter().enumerate().skip(ci) {
                        let rj = D * p.map[r as usize] as usize;
                        let bt = &g[D * D * t..D * D * (t + 1)];
                        for (b, bc) in bc.chunks_exact(D).enumerate() {
                            let dst = &mut panel[(col + b) * ld + rj..(col + b) * ld + rj + D];
                            for x in if t == ci { b } else { 0 }..D {
                                let mut acc = 0.0;
                                for tau in 0..D {
                                    acc = bt[D * x + tau].mul_add(bc[tau], acc);
                                }
                                dst[x] -= acc;
                            }
                        }
                    }
                }
            } else {
                if p.upd.len() < mt * nc {
                    p.upd.resize(mt * nc, 0.0);
                }
                let u = &mut p.upd[..mt * nc];
                let a = &done[sh.off[ku] - p.lx_base + D * (kw + at)..];
                dense::syrk::<false>(u, mt, a, kld, mt, nc, D * kw, p.two);
                // The tail's rows in runs that are consecutive in the panel too.
                p.runs.clear();
                let mut t = 0;
                while t < tail.len() {
                    let at = p.map[tail[t] as usize] as usize;
                    let mut e = t + 1;
                    while e < tail.len() && p.map[tail[e] as usize] as usize == at + e - t {
                        e += 1;
                    }
                    p.runs.push((t, e, at));
                    t = e;
                }
                for ci in 0..nq {
                    let col = D * (tail[ci] as usize - f);
                    let r0 = D * p.map[tail[ci] as usize] as usize;
                    for b in 0..D {
                        let src = &u[(D * ci + b) * mt..(D * ci + b + 1) * mt];
                        let dst = &mut panel[(col + b) * ld..(col + b + 1) * ld];
                        // The diagonal block's upper part is neither computed nor read.
                        for a in b..D {
                            dst[r0 + a] -= src[D * ci + a];
                        }
                        for &(t0, t1, at) in p.runs.iter() {
                            if t1 <= ci + 1 {
                                continue;
                            }
                            let from = t0.max(ci + 1);
                            let (len, to) = (D * (t1 - from), D * (at + from - t0));
                            for (d, s) in dst[to..to + len].iter_mut().zip(&src[D * from..D * from + len]) {
                                *d -= s;
                            }
                        }
                    }
                }
            }
            let at = at + nq;
            p.pos[kl] = at as u32;
            if at < kb.len() {
                let d = sh.sn_of[kb[at] as usize] as usize;
                p.link[kl] = p.head[d];
                p.head[d] = k;
            }
            k = next;
        }
    }
    if !dense::factor_panel(panel, ld, rows, ns, p.two) {
        return false;
    }
    if let Some(&r) = below.first() {
        let ql = q - p.s_base;
        p.pos[ql] = 0;
        let d = sh.sn_of[r as usize] as usize;
        p.link[ql] = p.head[d];
        p.head[d] = q as u32;
    }
    true
}
