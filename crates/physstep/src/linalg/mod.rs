//! The sparse linear algebra of the implicit methods on large worlds: force Jacobians kept as
//! 3 x 3 blocks ([`Blocks`]) and the Newton matrix they make solved by preconditioned
//! conjugate gradients ([`cg`]).
//!
//! # The Newton system (Baraff and Witkin, "Large steps in cloth simulation", 1998)
//!
//! An implicit step solves `z = y0 + c f(z)` for `z = [x; v]`, `f = [v; a(x, v)]`. With the
//! residual `g = z - y0 - c f(z)`, a Newton update `[dx; dv]` solves
//!
//! ```text
//! [ I        -c I          ] [dx]     [g_x]
//! [ -c M^-1 K   I - c M^-1 D ] [dv] = - [g_v]      K = dF/dx, D = dF/dv
//! ```
//!
//! The first row gives `dx = c dv - g_x`; put in the second and multiplied by the masses:
//!
//! ```text
//! (M - c D - c^2 K) dv = -M g_v - c K g_x
//! ```
//!
//! one system in the velocities, with a block per particle and one per spring: its storage
//! grows with the number of particles and springs, not with its square. `M - c D - c^2 K`
//! is symmetric positive definite when `D` and `K` are symmetric negative semidefinite, so
//! conjugate gradients solve it. The blocks are kept so ([`Blocks`] says how): where a
//! force's true Jacobian is not (a compressed spring's sideways stiffness, the coupling of a
//! spring's damping to its direction), the Newton matrix drops that part. Only the matrix
//! changes, not the residual: the iteration converges to the same solution, in a few more
//! updates. A particle of infinite mass does not move (`dv = 0`): its row is the identity.
//!
//! Every sum runs in a fixed order, one thread: the bits never depend on the machine's
//! threads.

// Small dense blocks read best as the formulas index them.
#![allow(clippy::needless_range_loop)]

mod cg;
mod cholesky;
mod ic;
pub mod vector;

pub use cg::{cg, CgParams, CgResult, CgWork, Preconditioner};
pub use cholesky::FILL_LIMIT;

/// A 3 x 3 block, row-major (`dim < 3` uses its leading `dim x dim` part).
pub type Block = [[f64; 3]; 3];

/// The force Jacobians of a world of particles as 3 x 3 blocks, in force units (N/m and
/// N s/m): a diagonal block per particle and a block per pair force (a spring between two
/// particles), whose pattern on `(i, j)` is `[[B, -B], [-B, B]]`.
#[derive(Debug, Clone, Default)]
pub struct Blocks {
    /// Spatial dimensions, 1 to 3.
    pub dim: usize,
    /// Masses, kg (`inf` for a static particle: it does not move).
    pub mass: Vec<f64>,
    /// `dF_p/dx_p` of the forces on one particle (anchored springs, central gravity).
    pub kd: Vec<Block>,
    /// `dF_p/dv_p` of the forces on one particle (drag, anchored springs' damping).
    pub dd: Vec<Block>,
    /// Pair forces: `(i, j, dF_i/dx_i, dF_i/dv_i)`; the force on `j` is the opposite.
    pub pairs: Vec<(usize, usize, Block, Block)>,
    /// Whether the springs' blocks are their exact Jacobians, a compressed spring's sideways
    /// term kept (the matrix may then be indefinite); `false` (the default) leaves that term
    /// out, so every block is semidefinite.
    pub exact: bool,
}

impl Blocks {
    /// Empties the blocks for `n` particles of `dim` dimensions with masses `mass`
    /// (allocations kept).
    pub fn reset(&mut self, dim: usize, mass: &[f64]) {
        self.dim = dim;
        self.mass.clear();
        self.mass.extend_from_slice(mass);
        let n = mass.len();
        self.kd.clear();
        self.kd.resize(n, [[0.0; 3]; 3]);
        self.dd.clear();
        self.dd.resize(n, [[0.0; 3]; 3]);
        self.pairs.clear();
    }

    /// `max_p (|K|_p + |D|_p) / m_p`, the largest row sum of `|da/dx| + |da/dv|` (1/s^2 and
    /// 1/s, added as numbers: a bound on the size of the terms of the acceleration).
    #[must_use]
    pub fn rate_norm(&self) -> f64 {
        let rows = |b: &Block| (0..3).map(|r| b[r].iter().map(|e| e.abs()).sum::<f64>()).fold(0.0, f64::max);
        let mut sum: Vec<f64> = (0..self.mass.len()).map(|p| rows(&self.kd[p]) + rows(&self.dd[p])).collect();
        for &(i, j, ref k, ref d) in &self.pairs {
            // The pair's diagonal and off-diagonal blocks both sit in rows i and j.
            let s = 2.0 * (rows(k) + rows(d));
            sum[i] += s;
            sum[j] += s;
        }
        sum.iter().zip(&self.mass).filter(|(_, m)| m.is_finite()).map(|(s, m)| s / m).fold(0.0, f64::max)
    }

    /// Bytes held (what the sparse solve costs in memory: linear in particles and pairs).
    #[must_use]
    pub fn bytes(&self) -> usize {
        let block = std::mem::size_of::<Block>();
        self.mass.capacity() * 8
            + (self.kd.capacity() + self.dd.capacity()) * block
            + self.pairs.capacity() * std::mem::size_of::<(usize, usize, Block, Block)>()
    }
}

/// The Newton matrix `A = M - c D - c^2 K` of [`Blocks`] at step factor `c`, applied and
/// preconditioned without being assembled beyond its blocks.
#[derive(Debug, Clone, Default)]
pub struct NewtonMatrix {
    dim: usize,
    /// Whether a particle moves (finite mass).
    free: Vec<bool>,
    /// Diagonal blocks of `A` per particle (pair contributions included).
    diag: Vec<Block>,
    /// Inverses of `diag` (the block-Jacobi preconditioner).
    inv: Vec<Block>,
    /// `-(c D_s + c^2 K_s)` per pair, with its particles.
    pairs: Vec<(usize, usize, Block)>,
    /// The incomplete Cholesky factor, when it is the preconditioner.
    ic: ic::IncompleteCholesky,
    /// The complete factor, when it is the preconditioner.
    chol: cholesky::SparseCholesky,
    /// The preconditioner [`NewtonMatrix::precondition`] applies.
    used: Preconditioner,
}

impl NewtonMatrix {
    /// `A` of `b` at `c`, preconditioned by `pre` (block Jacobi where the incomplete
    /// Cholesky factorisation breaks down: [`NewtonMatrix::preconditioner`] says which);
    /// `false` when a diagonal block cannot be inverted (a mass or a Jacobian that is not
    /// finite, or a block that is singular).
    pub fn build(&mut self, b: &Blocks, c: f64, pre: Preconditioner) -> bool {
        self.rebuild(b, c, pre, true)
    }

    /// [`NewtonMatrix::build`], keeping the complete Cholesky factor of the latest build
    /// when `refactor` is `false` and it has one (on the same springs): the factor of a
    /// nearby matrix (the previous Newton update's) preconditions this one, and conjugate
    /// gradients take a few iterations instead of a factorisation.
    pub fn rebuild(&mut self, b: &Blocks, c: f64, pre: Preconditioner, refactor: bool) -> bool {
        if !self.assemble(b, c) {
            return false;
        }
        let keep = !refactor
            && pre == Preconditioner::Cholesky
            && self.used == Preconditioner::Cholesky
            && self.chol.same_pattern(&self.pairs, &self.free);
        if keep {
            return true;
        }
        self.used = Preconditioner::BlockJacobi;
        if pre == Preconditioner::Cholesky && self.chol.factor(&self.diag, &self.pairs, &self.free, self.dim)
        {
            self.used = Preconditioner::Cholesky;
        } else if pre != Preconditioner::BlockJacobi
            && self.ic.factor(&self.diag, &self.pairs, &self.free, self.dim)
        {
            self.used = Preconditioner::IncompleteCholesky;
        }
        true
    }

    /// `A` of `b` at `c` with its complete Cholesky factor, and `true`, where `A` is positive
    /// definite (every pivot of the factorisation positive) and the factor's pattern fits;
    /// else `false`, and the matrix is to be built again before it is used. The test of
    /// definiteness for blocks that may be indefinite ([`Blocks::exact`]): it costs one
    /// factorisation, cut short at the first pivot that is not positive.
    pub fn build_definite(&mut self, b: &Blocks, c: f64) -> bool {
        self.used = Preconditioner::BlockJacobi;
        if !self.assemble(b, c) || !self.chol.factor(&self.diag, &self.pairs, &self.free, self.dim) {
            return false;
        }
        self.used = Preconditioner::Cholesky;
        true
    }

    /// The blocks of `A` (each particle's diagonal with its pairs' parts, the pairs) and the
    /// block-Jacobi inverses; `false` when a diagonal block cannot be inverted.
    fn assemble(&mut self, b: &Blocks, c: f64) -> bool {
        let (n, c2) = (b.mass.len(), c * c);
        self.dim = b.dim;
        self.free.clear();
        self.free.extend(b.mass.iter().map(|m| m.is_finite()));
        self.diag.clear();
        self.diag.resize(n, [[0.0; 3]; 3]);
        for p in 0..n {
            let d = &mut self.diag[p];
            for r in 0..3 {
                for k in 0..3 {
                    d[r][k] = -c * b.dd[p][r][k] - c2 * b.kd[p][r][k];
                }
                d[r][r] += if r < b.dim { b.mass[p] } else { 1.0 };
            }
        }
        self.pairs.clear();
        for &(i, j, ref k, ref dv) in &b.pairs {
            let mut m = [[0.0; 3]; 3];
            for r in 0..3 {
                for col in 0..3 {
                    m[r][col] = -c * dv[r][col] - c2 * k[r][col];
                }
            }
            add(&mut self.diag[i], &m, 1.0);
            add(&mut self.diag[j], &m, 1.0);
            self.pairs.push((i, j, m));
        }
        self.inv.clear();
        for p in 0..n {
            let block = if self.free[p] { self.diag[p] } else { IDENTITY };
            match inverse(&block) {
                Some(inv) => self.inv.push(inv),
                None => return false,
            }
        }
        true
    }

    /// The preconditioner of the latest [`NewtonMatrix::build`].
    #[must_use]
    pub fn preconditioner(&self) -> Preconditioner {
        self.used
    }

    /// `y = A x` (rows of static particles: `y = x`).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        match self.dim {
            1 => self.apply_d::<1>(x, y),
            2 => self.apply_d::<2>(x, y),
            _ => self.apply_d::<3>(x, y),
        }
    }

    fn apply_d<const D: usize>(&self, x: &[f64], y: &mut [f64]) {
        for (p, (yp, xp)) in y.chunks_exact_mut(D).zip(x.chunks_exact(D)).enumerate() {
            let m = if self.free[p] { &self.diag[p] } else { &IDENTITY };
            for r in 0..D {
                let mut t = 0.0;
                for k in 0..D {
                    t += m[r][k] * xp[k];
                }
                // As `mul_into` (0 + 1 t: the sign of a zero as before).
                yp[r] = 0.0;
                yp[r] += 1.0 * t;
            }
        }
        for &(i, j, ref m) in &self.pairs {
            // Rows i and j get -B (x_j) and -B (x_i): the off-diagonal blocks.
            if self.free[i] && self.free[j] {
                let xi: [f64; D] = x[i * D..i * D + D].try_into().unwrap_or([0.0; D]);
                let xj: [f64; D] = x[j * D..j * D + D].try_into().unwrap_or([0.0; D]);
                for r in 0..D {
                    let (mut si, mut sj) = (0.0, 0.0);
                    for k in 0..D {
                        si += m[r][k] * xj[k];
                        sj += m[r][k] * xi[k];
                    }
                    y[i * D + r] -= si;
                    y[j * D + r] -= sj;
                }
            }
        }
    }

    /// `z = P^-1 r` with the preconditioner built ([`NewtonMatrix::preconditioner`]).
    pub fn precondition(&self, r: &[f64], z: &mut [f64]) {
        let d = self.dim;
        if self.used == Preconditioner::Cholesky {
            self.chol.solve(r, z, d);
            return;
        }
        if self.used == Preconditioner::IncompleteCholesky {
            match d {
                1 => self.ic.solve::<1>(r, z),
                2 => self.ic.solve::<2>(r, z),
                _ => self.ic.solve::<3>(r, z),
            }
            return;
        }
        for (p, (zp, rp)) in z.chunks_exact_mut(d).zip(r.chunks_exact(d)).enumerate() {
            mul_into(&self.inv[p], rp, zp, d);
        }
    }

    /// How many preconditioned solves cost as much as making the complete Cholesky factor
    /// of the latest build (0 without one): what keeping it across updates can save.
    #[must_use]
    pub fn factor_cost_in_solves(&self) -> f64 {
        if self.used == Preconditioner::Cholesky {
            self.chol.cost_in_solves()
        } else {
            0.0
        }
    }

    /// Blocks of the complete Cholesky factor held (its diagonal included; 0 unless
    /// [`NewtonMatrix::preconditioner`] is [`Preconditioner::Cholesky`]).
    #[must_use]
    pub fn factor_blocks(&self) -> usize {
        if self.used == Preconditioner::Cholesky {
            self.chol.blocks()
        } else {
            0
        }
    }

    /// Whether particle `p` moves.
    #[must_use]
    pub fn free(&self, p: usize) -> bool {
        self.free[p]
    }
}

const IDENTITY: Block = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn add(a: &mut Block, b: &Block, s: f64) {
    for r in 0..3 {
        for k in 0..3 {
            a[r][k] += s * b[r][k];
        }
    }
}

/// `y += s m x` on the leading `d` entries.
#[inline]
pub(crate) fn mul_add(m: &Block, x: &[f64], y: &mut [f64], d: usize, s: f64) {
    for r in 0..d {
        let mut t = 0.0;
        for k in 0..d {
            t += m[r][k] * x[k];
        }
        y[r] += s * t;
    }
}

/// `y = m x` on the leading `d` entries.
#[inline]
pub(crate) fn mul_into(m: &Block, x: &[f64], y: &mut [f64], d: usize) {
    y[..d].fill(0.0);
    mul_add(m, x, y, d, 1.0);
}

/// The inverse of a 3 x 3 block by its adjugate; `None` when it is singular or not finite.
fn inverse(m: &Block) -> Option<Block> {
    let c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    let c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    let c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    let det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let s = 1.0 / det;
    Some([
        [c00 * s, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * s, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * s],
        [c01 * s, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * s, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * s],
        [c02 * s, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * s, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * s],
    ])
}

#[cfg(test)]
mod tests;
