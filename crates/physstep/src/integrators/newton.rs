//! Newton iteration for the implicit methods: solves `z = y0 + c f(tau, z)`.

use super::implicit::{ImplicitParams, SolveStats};
use super::{axpy_to, scratch};
use crate::dynamics::{Counted, Step, System};
use crate::error::{Error, Result};
use crate::linalg::{cg, Blocks, CgWork, NewtonMatrix};

/// Newton's method with a dense LU solve, the Jacobian analytic where the flow has one and
/// by forward differences otherwise. The dense solve costs O(n^3) per iteration: the
/// implicit methods are meant for small stiff systems, not for large worlds.
#[derive(Debug, Clone, Default)]
pub(crate) struct Newton {
    pub params: ImplicitParams,
    /// The solution after [`Newton::solve`].
    pub z: Vec<f64>,
    /// `f(tau, z)` at the solution.
    pub fz: Vec<f64>,
    g: Vec<f64>,
    j: Vec<f64>,
    work: Vec<f64>,
    zp: Vec<f64>,
    fp: Vec<f64>,
    perm: Vec<usize>,
    /// What the latest solve did.
    pub stats: SolveStats,
    /// One update from `y0` and no more (the linearly implicit step), instead of iterating to
    /// the tolerance from the explicit guess.
    pub linear: bool,
    blocks: Blocks,
    matrix: NewtonMatrix,
    cg_work: CgWork,
    rhs: Vec<f64>,
    dv: Vec<f64>,
    /// The iterate before the latest update, and the update.
    z_old: Vec<f64>,
    step: Vec<f64>,
}

impl Newton {
    /// A solver with the given settings.
    pub fn new(params: ImplicitParams) -> Self {
        Self { params, ..Self::default() }
    }

    /// Solves `z = y0 + c f(tau, z)` from the explicit guess `y0 + c f0`; with
    /// [`Newton::linear`], takes one Newton update from `z = y0` with the Jacobian there (the
    /// equation linearised at the start of the step) and stops, whatever the residual.
    ///
    /// # Errors
    /// [`Error::Unsupported`] when the system is too large for the dense solver (refused
    /// before anything is allocated); [`Error::NotConverged`] when the iteration fails.
    pub fn solve<S: System + ?Sized>(
        &mut self,
        flow: &mut Counted<'_, S>,
        method: &str,
        tau: f64,
        c: f64,
        y0: &[f64],
        f0: &[f64],
    ) -> Result<()> {
        let n = y0.len();
        let nx = flow.split().filter(|&nx| 2 * nx == n && n > self.params.dense_up_to);
        if let Some(nx) = nx {
            // The semidefinite blocks at the start (the exact ones, where they are tried,
            // are made at the iteration's start in `solve_sparse`).
            self.blocks.exact = false;
            if flow.blocks(tau, y0, &mut self.blocks) {
                return self.solve_sparse(flow, method, tau, c, y0, f0, nx);
            }
        }
        self.stats = SolveStats::default();
        if n > MAX_DENSE {
            return Err(Error::Unsupported {
                method: method.into(),
                reason: format!(
                    "solves with a dense {n} x {n} Jacobian ({:.1} GB) for this system of {n} unknowns; \
                     the dense solver takes at most {MAX_DENSE} unknowns (x and v of {} coordinates): \
                     use an explicit method or a smaller system",
                    (n as f64).powi(2) * 8e-9,
                    MAX_DENSE / 2
                ),
            });
        }
        let z = scratch(&mut self.z, n);
        let fz = scratch(&mut self.fz, n);
        let g = scratch(&mut self.g, n);
        guess(z, y0, c, f0, Start::of(self.linear));
        let mut residual = f64::INFINITY;
        // c |df/dz| (max row sum), from the latest Jacobian.
        let mut stiffness = 0.0f64;
        // One more pass than updates: the last one only checks the final update.
        for iter in 0..=self.params.max_iter {
            // Ctrl-C (crate::interrupt): unconverged, the step fails and is rolled back.
            if crate::interrupt::stop() {
                break;
            }
            flow.deriv(tau, z, fz);
            let scale;
            (residual, scale) = measure(g, z, y0, fz, c, stiffness);
            if self.linear && iter == 1 {
                // The one update taken; a non-finite state is the Check stage's divergence.
                let relative = residual / scale.max(SCALE_FLOOR);
                self.stats = SolveStats { newton: 1, cg: 0, residual: relative, sparse: false };
                return Ok(());
            }
            if !residual.is_finite() {
                break;
            }
            // The explicit guess is never accepted as it is: at least one update is taken.
            // The floor keeps the test meaningful where the state decays into subnormal numbers
            // (whose rounding is absolute, not relative).
            if iter > 0 && residual <= self.params.tol * scale.max(SCALE_FLOOR) {
                self.stats = SolveStats {
                    newton: iter,
                    cg: 0,
                    residual: residual / scale.max(SCALE_FLOOR),
                    sparse: false,
                };
                return Ok(());
            }
            if iter == self.params.max_iter {
                break;
            }
            // J = I - c df/dz
            let j = scratch(&mut self.j, n * n);
            j.fill(0.0);
            if !flow.jacobian(tau, z, j, &mut self.work) {
                let zp = scratch(&mut self.zp, n);
                let fp = scratch(&mut self.fp, n);
                zp.copy_from_slice(z);
                for col in 0..n {
                    let d = f64::EPSILON.sqrt() * z[col].abs().max(1.0);
                    zp[col] = z[col] + d;
                    flow.deriv(tau, zp, fp);
                    zp[col] = z[col];
                    for row in 0..n {
                        j[row * n + col] = (fp[row] - fz[row]) / d;
                    }
                }
            }
            for e in j.iter_mut() {
                *e *= -c;
            }
            stiffness = j
                .chunks_exact(n.max(1))
                .map(|row| row.iter().map(|e| e.abs()).sum::<f64>())
                .fold(0.0, f64::max);
            for i in 0..n {
                j[i * n + i] += 1.0;
            }
            for gi in g.iter_mut() {
                *gi = -*gi;
            }
            if !lu_solve(j, n, g, &mut self.perm) {
                break;
            }
            for (zi, di) in z.iter_mut().zip(g.iter()) {
                *zi += di;
            }
        }
        Err(Error::NotConverged { method: method.into(), iterations: self.params.max_iter, residual })
    }

    /// A step of backward Euler's equation `y[n+1] = y[n] + h f(t + h, y[n+1])` (converged,
    /// or linearised at the start with [`Newton::linear`]): the new state and its derivative
    /// written into the step. `method` names the method in an error.
    ///
    /// # Errors
    /// As [`Newton::solve`].
    pub fn euler_step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>, method: &str) -> Result<()> {
        let (t, h) = (s.t, s.h);
        let (y, f, mut flow) = s.flow();
        self.solve(&mut flow, method, t + h, h, y, f)?;
        s.y.copy_from_slice(&self.z);
        s.f.copy_from_slice(&self.fz);
        Ok(())
    }

    /// [`Newton::solve`] on a second-order system (`nx` positions, as many velocities) whose
    /// force Jacobians come as blocks: each update solves the velocity system of
    /// [`crate::linalg`] by conjugate gradients.
    #[allow(clippy::too_many_arguments)]
    fn solve_sparse<S: System + ?Sized>(
        &mut self,
        flow: &mut Counted<'_, S>,
        method: &str,
        tau: f64,
        c: f64,
        y0: &[f64],
        f0: &[f64],
        nx: usize,
    ) -> Result<()> {
        let n = y0.len();
        let dim = self.blocks.dim;
        let z = scratch(&mut self.z, n);
        let fz = scratch(&mut self.fz, n);
        let g = scratch(&mut self.g, n);
        let rhs = scratch(&mut self.rhs, nx);
        let dv = scratch(&mut self.dv, nx);
        // The exact Jacobian first (ImplicitParams::exact_jacobian), from `x + c v, v`: the
        // blocks made again there, exact.
        let mut exact = !self.linear
            && self.params.exact_jacobian
            && self.params.cg.preconditioner == crate::linalg::Preconditioner::Cholesky;
        if exact {
            guess(z, y0, c, f0, Start::Coasting(nx));
            self.blocks.exact = true;
            exact = flow.blocks(tau, z, &mut self.blocks);
            if !exact {
                // (No blocks at the guess: the semidefinite iteration, as before.)
                self.blocks.exact = false;
                if !flow.blocks(tau, y0, &mut self.blocks) {
                    return Err(Error::NotConverged {
                        method: method.into(),
                        iterations: 0,
                        residual: f64::NAN,
                    });
                }
            }
        }
        if !exact {
            guess(z, y0, c, f0, Start::of(self.linear));
        }
        let mut residual = f64::INFINITY;
        let (mut cg_total, mut last_cg) = (0, 0);
        // |df/dz| of the latest blocks (made before the loop and at each update but the first).
        let mut rate_norm = self.blocks.rate_norm();
        // Whether the latest update was the exact one (it takes no line search).
        let mut exact_update = false;
        let mut previous = f64::INFINITY;
        let z_old = scratch(&mut self.z_old, n);
        let step = scratch(&mut self.step, n);
        // The slope of the incremental potential along the latest update, where it started.
        let mut pending: Option<f64> = None;
        for iter in 0..=self.params.max_iter {
            // Ctrl-C (crate::interrupt): unconverged, the step fails and is rolled back.
            if crate::interrupt::stop() {
                break;
            }
            flow.deriv(tau, z, fz);
            // c |df/dz|, as the dense solve measures it (from the blocks at z's start).
            let mut scale;
            (residual, scale) = measure(g, z, y0, fz, c, c * rate_norm);
            // A secant line search along the update: the slope of the incremental potential
            // (`M g_v . dv`, its gradient along the update) at the update's start and end,
            // interpolated to zero; the step taken to that point, within [LINE_MIN, LINE_MAX]
            // of the update. Where the semidefinite matrix makes the updates too short (springs
            // near buckling) it stretches them; where an update overshoots it shortens it.
            if let Some(slope0) = pending.take() {
                let slope1 = slope(&self.blocks.mass, &g[nx..], &step[nx..], dim);
                if slope1.is_finite()
                    && slope0 < 0.0
                    && !self.linear
                    && self.params.line_search
                    && !exact_update
                {
                    // A slope as steep or steeper at the end: no minimum in reach, the longest.
                    let alpha = if slope1 <= slope0 {
                        LINE_MAX
                    } else {
                        (slope0 / (slope0 - slope1)).clamp(LINE_MIN, LINE_MAX)
                    };
                    if alpha != 1.0 {
                        for k in 0..n {
                            z[k] = z_old[k] + alpha * step[k];
                        }
                        flow.deriv(tau, z, fz);
                        (residual, scale) = measure(g, z, y0, fz, c, c * rate_norm);
                    }
                }
            }
            // How much the last update shrank the residual (0 before the first).
            let rate = residual / previous;
            previous = residual;
            if self.linear && iter == 1 {
                // The one update taken; a non-finite state is the Check stage's divergence.
                let relative = residual / scale.max(SCALE_FLOOR);
                self.stats = SolveStats { newton: 1, cg: cg_total, residual: relative, sparse: true };
                return Ok(());
            }
            if !residual.is_finite() {
                break;
            }
            if iter > 0 && residual <= self.params.tol * scale.max(SCALE_FLOOR) {
                let relative = residual / scale.max(SCALE_FLOOR);
                self.stats = SolveStats { newton: iter, cg: cg_total, residual: relative, sparse: true };
                return Ok(());
            }
            if iter == self.params.max_iter {
                break;
            }
            // (M - c D - c^2 K) dv = -M g_v - c K g_x, then dx = c dv - g_x.
            if iter > 0 {
                self.blocks.exact = exact;
                if !flow.blocks(tau, z, &mut self.blocks) {
                    break;
                }
                rate_norm = self.blocks.rate_norm();
            }
            // The exact matrix where it is positive definite (its factor then solves it:
            // the exact Newton update); else the semidefinite one's blocks for this update.
            exact_update = exact && self.matrix.build_definite(&self.blocks, c);
            if exact && !exact_update {
                self.blocks.exact = false;
                if !flow.blocks(tau, z, &mut self.blocks) {
                    break;
                }
                rate_norm = self.blocks.rate_norm();
            }
            if !exact_update {
                // A complete factor is made at a step's first update and kept for the next
                // updates where it costs more than the conjugate-gradient iterations it then
                // takes (a grid's factor, not a chain's), while they stay within
                // REFACTOR_AFTER.
                let keep = self.matrix.factor_cost_in_solves() > KEEP_FACTOR_ABOVE;
                // (After an exact attempt that broke down there is no factor to keep.)
                let refactor = iter == 0 || last_cg > REFACTOR_AFTER || !keep;
                if !self.matrix.rebuild(&self.blocks, c, self.params.cg.preconditioner, refactor) {
                    break;
                }
                if exact && self.matrix.preconditioner() != crate::linalg::Preconditioner::Cholesky {
                    // No complete factor even of the semidefinite matrix (past the fill
                    // limit): the exact one is not tried again this step.
                    exact = false;
                }
            }
            let (gx, gv) = g.split_at(nx);
            let b = &self.blocks;
            for (p, m) in b.mass.iter().enumerate() {
                let range = p * dim..(p + 1) * dim;
                if !self.matrix.free(p) {
                    rhs[range].fill(0.0);
                    continue;
                }
                for k in range.clone() {
                    rhs[k] = -m * gv[k];
                }
                crate::linalg::mul_add(&b.kd[p], &gx[range.clone()], &mut rhs[range], dim, -c);
            }
            for &(i, j, ref k, _) in &b.pairs {
                // K g_x of a pair: rows i and j get K (g_x,i - g_x,j) and its opposite.
                let mut d = [0.0; 3];
                for a in 0..dim {
                    d[a] = gx[i * dim + a] - gx[j * dim + a];
                }
                let mut kd = [0.0; 3];
                crate::linalg::mul_add(k, &d[..dim], &mut kd[..dim], dim, 1.0);
                for a in 0..dim {
                    if self.matrix.free(i) {
                        rhs[i * dim + a] -= c * kd[a];
                    }
                    if self.matrix.free(j) {
                        rhs[j * dim + a] += c * kd[a];
                    }
                }
            }
            // An inexact Newton update (Eisenstat and Walker, 1996): solved no more
            // precisely than the iteration converges, down to `cg.tol` as it speeds up.
            let mut params = self.params.cg;
            params.tol = params.tol.max(FORCING.min(FORCING * rate));
            let solve = cg(&self.matrix, rhs, dv, params, &mut self.cg_work);
            cg_total += solve.iterations;
            last_cg = solve.iterations;
            if !solve.converged {
                return Err(Error::NotConverged {
                    method: method.into(),
                    iterations: self.params.cg.max_iter,
                    residual: solve.residual,
                });
            }
            pending = Some(slope(&self.blocks.mass, gv, dv, dim));
            z_old.copy_from_slice(z);
            let (sx, sv) = step.split_at_mut(nx);
            let (zx, zv) = z.split_at_mut(nx);
            for k in 0..nx {
                sx[k] = c * dv[k] - gx[k];
                sv[k] = dv[k];
                zx[k] += c * dv[k] - gx[k];
                zv[k] += dv[k];
            }
        }
        self.stats = SolveStats { newton: self.params.max_iter, cg: cg_total, residual, sparse: true };
        Err(Error::NotConverged { method: method.into(), iterations: self.params.max_iter, residual })
    }
}

/// Where the iteration starts.
#[derive(Debug, Clone, Copy)]
enum Start {
    /// The explicit guess `y0 + c f0`.
    Explicit,
    /// `y0` itself: the linearly implicit step (its one update is then
    /// `(I - c J(y0))^-1 c f(y0)`).
    State,
    /// `x0 + c v0, v0` on a second-order system of `nx` positions: the step without
    /// acceleration, where exact Newton updates converge (from the explicit guess they
    /// diverge on a stiff spring, whose `c a` is far from the step).
    Coasting(usize),
}

impl Start {
    /// The start of a converged solve, or of the linearly implicit step.
    fn of(linear: bool) -> Self {
        if linear {
            Self::State
        } else {
            Self::Explicit
        }
    }
}

/// `z` at the iteration's start.
fn guess(z: &mut [f64], y0: &[f64], c: f64, f0: &[f64], start: Start) {
    match start {
        Start::State => z.copy_from_slice(y0),
        Start::Explicit => axpy_to(z, y0, c, f0),
        Start::Coasting(nx) => {
            let (zx, zv) = z.split_at_mut(nx);
            let (x0, v0) = y0.split_at(nx);
            for k in 0..nx {
                zx[k] = x0[k] + c * v0[k];
            }
            zv.copy_from_slice(v0);
        }
    }
}

/// `sum_p m_p g_p . d_p` over the moving particles: the slope of the incremental potential
/// along the update `d` where `g` is the velocity residual.
fn slope(mass: &[f64], g: &[f64], d: &[f64], dim: usize) -> f64 {
    let mut s = 0.0;
    for (p, m) in mass.iter().enumerate() {
        if m.is_finite() {
            for k in p * dim..(p + 1) * dim {
                s += m * g[k] * d[k];
            }
        }
    }
    s
}

/// The shortest and longest step the line search takes, in updates (measured on the first
/// 90 steps of the folding 32 x 32 stiff cloth: [0.1, 4] and [0.1, 8] held it with both
/// preconditioners and a third fewer Newton updates; [0.1, 1], [0.1, 2] and [1, 4] each
/// failed with one of them).
const LINE_MIN: f64 = 0.1;
const LINE_MAX: f64 = 4.0;

/// Most conjugate-gradient iterations an update may take on a complete Cholesky factor kept
/// from an earlier update before the next update factors its own matrix.
const REFACTOR_AFTER: u32 = 8;

/// A complete factor that costs more than this many solves is kept across updates (a
/// chain's costs about 1, a 32 x 32 cloth's 8).
const KEEP_FACTOR_ABOVE: f64 = 2.0;

/// Largest relative tolerance of an update's conjugate-gradient solve.
const FORCING: f64 = 0.1;

/// The residual `g = z - y0 - c f(z)` into `g`, and `(max |g|, the size of its terms)`: the
/// max norms of `z`, `y0`, `c f(z)` and `stiffness |z|` (`stiffness` = `c |df/dz|`). A NaN in
/// `g` makes the residual NaN (`f64::max` skips NaN: it would pass for a zero residual).
fn measure(g: &mut [f64], z: &[f64], y0: &[f64], fz: &[f64], c: f64, stiffness: f64) -> (f64, f64) {
    let (mut residual, mut scale, mut z_max) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..g.len() {
        let cf = c * fz[i];
        g[i] = z[i] - y0[i] - cf;
        residual = residual.max(g[i].abs());
        scale = scale.max(z[i].abs()).max(y0[i].abs()).max(cf.abs());
        z_max = z_max.max(z[i].abs());
    }
    if g.iter().any(|gi| gi.is_nan()) {
        residual = f64::NAN;
    }
    (residual, scale.max(stiffness * z_max))
}

/// The smallest size of the terms the relative stopping test measures against: below it
/// (subnormal states) it is absolute.
const SCALE_FLOOR: f64 = 1e-290;

/// Most unknowns the dense solver takes: its n x n Jacobian is then 128 MiB.
pub const MAX_DENSE: usize = 4096;

/// Solves `A x = b` in place (`b` becomes `x`) by LU with partial pivoting; `false` when `A`
/// is singular.
fn lu_solve(a: &mut [f64], n: usize, b: &mut [f64], perm: &mut Vec<usize>) -> bool {
    perm.clear();
    perm.extend(0..n);
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs())).unwrap_or(k);
        if a[p * n + k] == 0.0 || !a[p * n + k].is_finite() {
            return false;
        }
        if p != k {
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
            b.swap(k, p);
            perm.swap(k, p);
        }
        let piv = a[k * n + k];
        for i in k + 1..n {
            let m = a[i * n + k] / piv;
            if m != 0.0 {
                a[i * n + k] = m;
                for c in k + 1..n {
                    a[i * n + c] -= m * a[k * n + c];
                }
                b[i] -= m * b[k];
            } else {
                a[i * n + k] = 0.0;
            }
        }
    }
    for k in (0..n).rev() {
        let mut s = b[k];
        for c in k + 1..n {
            s -= a[k * n + c] * b[c];
        }
        b[k] = s / a[k * n + k];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lu_solves_a_pivoting_system() {
        let mut a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let mut b = vec![5.0, 3.0, 5.0];
        let mut perm = Vec::new();
        assert!(lu_solve(&mut a, 3, &mut b, &mut perm));
        // x = (1, 2, 2) solves [[0,2,1],[1,1,0],[3,0,1]] x = (6,3,5)? check the residual instead
        let a0 = [0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        for r in 0..3 {
            let lhs: f64 = (0..3).map(|c| a0[r * 3 + c] * b[c]).sum();
            assert!((lhs - [5.0, 3.0, 5.0][r]).abs() < 1e-12);
        }
        let mut singular = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!lu_solve(&mut singular, 2, &mut [1.0, 1.0], &mut perm));
    }
}
