//! Newton iteration for the implicit methods: solves `z = y0 + c f(tau, z)`.

use super::{axpy_to, scratch};
use crate::dynamics::{Counted, System};
use crate::error::{Error, Result};

/// Settings of the implicit methods' Newton iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImplicitParams {
    /// Converged, after at least one Newton update, when the residual of `z = y0 + c f(z)`
    /// is at most `tol` times the size of its terms (max norms of `z`, `y0` and `c f(z)`):
    /// relative at every scale, so a state of size 1e-15 is solved as well as one of size 1.
    pub tol: f64,
    /// Iterations before giving up with [`Error::NotConverged`].
    pub max_iter: u32,
}

impl Default for ImplicitParams {
    fn default() -> Self {
        Self { tol: 1e-12, max_iter: 50 }
    }
}

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
}

impl Newton {
    /// A solver with the given settings.
    pub fn new(params: ImplicitParams) -> Self {
        Self { params, ..Self::default() }
    }

    /// Solves `z = y0 + c f(tau, z)` from the explicit guess `y0 + c f0`.
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
        axpy_to(z, y0, c, f0);
        let mut residual = f64::INFINITY;
        // One more pass than updates: the last one only checks the final update.
        for iter in 0..=self.params.max_iter {
            flow.deriv(tau, z, fz);
            residual = 0.0;
            let mut scale = 0.0f64;
            for i in 0..n {
                let cf = c * fz[i];
                g[i] = z[i] - y0[i] - cf;
                residual = residual.max(g[i].abs());
                scale = scale.max(z[i].abs()).max(y0[i].abs()).max(cf.abs());
            }
            // f64::max skips NaN: a NaN in f(z) would otherwise pass for a zero residual and
            // be accepted as converged.
            if g.iter().any(|gi| gi.is_nan()) {
                residual = f64::NAN;
            }
            if !residual.is_finite() {
                break;
            }
            // The explicit guess is never accepted as it is: at least one update is taken.
            // The floor keeps the test meaningful where the state decays into subnormal numbers
            // (whose rounding is absolute, not relative).
            if iter > 0 && residual <= self.params.tol * scale.max(SCALE_FLOOR) {
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
