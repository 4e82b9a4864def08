//! Block incomplete Cholesky, IC(0), of a [`super::NewtonMatrix`]: the preconditioner that
//! sees along the springs.
//!
//! `A ~ (D + L) D^-1 (D + L^T)`, `L` strictly lower with `A`'s block pattern (one block per
//! spring joining two moving particles, no fill), `D` block diagonal: Gaussian elimination on
//! the 3 x 3 blocks in particle order, every update whose place is not in `A`'s pattern
//! dropped. On a chain (a path: no fill to drop) it is the exact factorisation, and conjugate
//! gradients converge in one iteration whatever the length; on a grid with shear springs it
//! drops the fill of the elimination, and the iterations still grow with the grid, more
//! slowly than block Jacobi's.
//!
//! The elimination's pattern (which updates land where) depends only on the springs, and is
//! kept while they stay the same. Every sum runs in a fixed order on one thread.

use super::{inverse, Block, IDENTITY};

/// The factor `D^-1` and the blocks of `L^T` (row `k` holds `(D + L^T)_{kj}`, `j > k`).
#[derive(Debug, Clone, Default)]
pub(super) struct IncompleteCholesky {
    /// The springs the pattern was made for (`(min, max)` per pair, `None` for a pair not
    /// in the matrix) and the particles' count.
    key: Vec<Option<(usize, usize)>>,
    n: usize,
    /// Row `k` of the upper pattern: `col[start[k]..start[k + 1]]`, ascending, `> k`.
    start: Vec<usize>,
    col: Vec<usize>,
    /// Per pair of the matrix: its entry in `col` (`usize::MAX`: not in the matrix).
    entry: Vec<usize>,
    /// The elimination's updates, by pivot `k` (`upd_start[k]..upd_start[k + 1]`):
    /// `(a, b, target)`: `W_target -= W_a^T D_k^-1 W_b`, `target == usize::MAX` for none
    /// (the diagonal of `col[a]` when `a == b`).
    upd_start: Vec<usize>,
    upd: Vec<(u32, u32, u32)>,
    /// Numeric factor: `W` (the upper blocks) and `D^-1`.
    w: Vec<Block>,
    dinv: Vec<Block>,
    diag: Vec<Block>,
    /// `D_k^-1 W_e` of the current pivot's row.
    t: Vec<Block>,
}

const NONE: u32 = u32::MAX;

impl IncompleteCholesky {
    /// Makes the pattern of the springs `pairs` (those whose ends both move) on `n`
    /// particles, unless it is the one kept.
    fn pattern(&mut self, n: usize, pairs: &[(usize, usize, Block)], free: &[bool]) {
        let same = self.n == n
            && self.key.len() == pairs.len()
            && pairs.iter().zip(&self.key).all(|(&(i, j, _), k)| *k == key(i, j, free));
        if same {
            return;
        }
        self.n = n;
        self.key.clear();
        self.key.extend(pairs.iter().map(|&(i, j, _)| key(i, j, free)));
        // Rows of the upper pattern, ascending and without repeats (two springs between
        // the same particles share a block).
        let mut rows: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &(a, b) in self.key.iter().flatten() {
            rows[a].push(b);
        }
        self.start.clear();
        self.col.clear();
        self.start.push(0);
        for row in &mut rows {
            row.sort_unstable();
            row.dedup();
            self.col.extend_from_slice(row);
            self.start.push(self.col.len());
        }
        self.entry.clear();
        for k in &self.key {
            self.entry.push(match *k {
                Some((a, b)) => self.find(a, b).unwrap_or(usize::MAX),
                None => usize::MAX,
            });
        }
        // The elimination's updates, with their places (or none: dropped).
        self.upd_start.clear();
        self.upd.clear();
        for k in 0..n {
            self.upd_start.push(self.upd.len());
            let (s, e) = (self.start[k], self.start[k + 1]);
            for a in s..e {
                self.upd.push((a as u32, a as u32, NONE));
                for b in a + 1..e {
                    if let Some(t) = self.find(self.col[a], self.col[b]) {
                        self.upd.push((a as u32, b as u32, t as u32));
                    }
                }
            }
        }
        self.upd_start.push(self.upd.len());
    }

    /// The entry of `(a, b)`, `a < b`, in the upper pattern.
    fn find(&self, a: usize, b: usize) -> Option<usize> {
        let (s, e) = (self.start[a], self.start[a + 1]);
        self.col[s..e].binary_search(&b).ok().map(|i| s + i)
    }

    /// Factors `A` given by its diagonal blocks `diag` (static particles' rows: the
    /// identity) and its springs' blocks (`A_ij = -m`); `false` when a pivot is not
    /// positive definite (the incomplete factorisation broke down: precondition otherwise).
    pub(super) fn factor(
        &mut self,
        diag: &[Block],
        pairs: &[(usize, usize, Block)],
        free: &[bool],
        dim: usize,
    ) -> bool {
        let n = diag.len();
        if self.col.len() >= u32::MAX as usize / 2 {
            return false;
        }
        self.pattern(n, pairs, free);
        self.diag.clear();
        self.diag.extend(diag.iter().zip(free).map(|(d, &f)| if f { *d } else { IDENTITY }));
        self.w.clear();
        self.w.resize(self.col.len(), [[0.0; 3]; 3]);
        for ((_, _, m), &e) in pairs.iter().zip(&self.entry) {
            if e != usize::MAX {
                sub(&mut self.w[e], m);
            }
        }
        self.dinv.clear();
        for k in 0..n {
            let d = self.diag[k];
            if !positive_definite(&d, dim) {
                return false;
            }
            let Some(inv) = inverse(&d) else { return false };
            self.dinv.push(inv);
            let (s, e) = (self.start[k], self.start[k + 1]);
            self.t.clear();
            for a in s..e {
                self.t.push(mul(&inv, &self.w[a]));
            }
            for u in self.upd_start[k]..self.upd_start[k + 1] {
                let (a, b, target) = self.upd[u];
                let (a, b) = (a as usize, b as usize);
                let m = mul_tn(&self.w[a], &self.t[b - s]);
                if target == NONE {
                    sub(&mut self.diag[self.col[a]], &m);
                } else {
                    sub(&mut self.w[target as usize], &m);
                }
            }
        }
        true
    }

    /// `z = (D + L^T)^-1 D (D + L)^-1 r` on `D`-dimensional particles.
    pub(super) fn solve<const D: usize>(&self, r: &[f64], z: &mut [f64]) {
        z.copy_from_slice(r);
        // Forward: y_k = D_k^-1 (r_k - sum_{i<k} W_ik^T y_i), scattered row by row.
        for k in 0..self.n {
            let t: [f64; D] = z[k * D..k * D + D].try_into().unwrap_or([0.0; D]);
            let inv = &self.dinv[k];
            let mut y = [0.0; D];
            for i in 0..D {
                let mut s = 0.0;
                for j in 0..D {
                    s += inv[i][j] * t[j];
                }
                y[i] = s;
            }
            z[k * D..k * D + D].copy_from_slice(&y);
            for e in self.start[k]..self.start[k + 1] {
                let (c, w) = (self.col[e], &self.w[e]);
                let zc = &mut z[c * D..c * D + D];
                for j in 0..D {
                    let mut s = 0.0;
                    for i in 0..D {
                        s += w[i][j] * y[i];
                    }
                    zc[j] -= s;
                }
            }
        }
        // Backward: z_k = y_k - D_k^-1 sum_{j>k} W_kj z_j.
        for k in (0..self.n).rev() {
            let mut s = [0.0; D];
            for e in self.start[k]..self.start[k + 1] {
                let (c, w) = (self.col[e], &self.w[e]);
                let zc: [f64; D] = z[c * D..c * D + D].try_into().unwrap_or([0.0; D]);
                for i in 0..D {
                    let mut a = 0.0;
                    for j in 0..D {
                        a += w[i][j] * zc[j];
                    }
                    s[i] += a;
                }
            }
            let inv = &self.dinv[k];
            for i in 0..D {
                let mut a = 0.0;
                for j in 0..D {
                    a += inv[i][j] * s[j];
                }
                z[k * D + i] -= a;
            }
        }
    }
}

/// A pair's place in the upper pattern, `None` when an end does not move (its row is the
/// identity) or it joins a particle to itself.
pub(super) fn key(i: usize, j: usize, free: &[bool]) -> Option<(usize, usize)> {
    (free[i] && free[j] && i != j).then(|| (i.min(j), i.max(j)))
}

fn sub(a: &mut Block, b: &Block) {
    for r in 0..3 {
        for k in 0..3 {
            a[r][k] -= b[r][k];
        }
    }
}

fn mul(a: &Block, b: &Block) -> Block {
    let mut m = [[0.0; 3]; 3];
    for r in 0..3 {
        for k in 0..3 {
            m[r][k] = a[r][0] * b[0][k] + a[r][1] * b[1][k] + a[r][2] * b[2][k];
        }
    }
    m
}

/// `a^T b`.
fn mul_tn(a: &Block, b: &Block) -> Block {
    let mut m = [[0.0; 3]; 3];
    for r in 0..3 {
        for k in 0..3 {
            m[r][k] = a[0][r] * b[0][k] + a[1][r] * b[1][k] + a[2][r] * b[2][k];
        }
    }
    m
}

/// Whether the leading `dim x dim` part of a (symmetric) block is positive definite, by its
/// leading minors.
fn positive_definite(b: &Block, dim: usize) -> bool {
    let m1 = b[0][0];
    let m2 = b[0][0] * b[1][1] - b[0][1] * b[1][0];
    let m3 = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
        - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
        + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    let ok = |x: f64| x > 0.0 && x.is_finite();
    ok(m1) && (dim < 2 || ok(m2)) && (dim < 3 || ok(m3))
}
