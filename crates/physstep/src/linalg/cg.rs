//! Preconditioned conjugate gradients on a [`NewtonMatrix`].

use super::NewtonMatrix;

/// Settings of the conjugate-gradient solve inside each Newton update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgParams {
    /// Converged when the residual's 2-norm is at most `tol` times the right-hand side's.
    pub tol: f64,
    /// Iterations before the solve gives up (the Newton update then fails).
    pub max_iter: u32,
    /// The preconditioner (default [`Preconditioner::Cholesky`]).
    pub preconditioner: Preconditioner,
}

impl Default for CgParams {
    fn default() -> Self {
        Self { tol: 1e-10, max_iter: 1000, preconditioner: Preconditioner::default() }
    }
}

/// The preconditioner of the conjugate-gradient solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Preconditioner {
    /// The inverse of each particle's diagonal block: cheap, blind along the springs (the
    /// iterations grow with a chain's length).
    BlockJacobi,
    /// Block incomplete Cholesky, IC(0), on the springs' pattern: exact on a chain, and where
    /// it breaks down (a pivot not positive definite) block Jacobi for that matrix.
    IncompleteCholesky,
    /// The complete sparse Cholesky factorisation in a fill-reducing (minimum-degree) order:
    /// the exact solve, so conjugate gradients converge in one iteration (two where the
    /// first's rounding is above their tolerance) whatever the network. Where its factor
    /// would hold more than [`crate::linalg::FILL_LIMIT`] blocks a particle, or it breaks
    /// down, incomplete Cholesky for that matrix (and block Jacobi after it).
    #[default]
    Cholesky,
}

impl Preconditioner {
    /// The names [`Preconditioner::named`] takes.
    pub const NAMES: [&'static str; 3] = ["cholesky", "incomplete-cholesky", "block-jacobi"];

    /// The preconditioner named `name` (one of [`Preconditioner::NAMES`]).
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "incomplete-cholesky" => Some(Self::IncompleteCholesky),
            "cholesky" => Some(Self::Cholesky),
            "block-jacobi" => Some(Self::BlockJacobi),
            _ => None,
        }
    }

    /// Its name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::IncompleteCholesky => "incomplete-cholesky",
            Self::Cholesky => "cholesky",
            Self::BlockJacobi => "block-jacobi",
        }
    }
}

/// What a solve did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CgResult {
    /// Iterations taken.
    pub iterations: u32,
    /// The final residual's 2-norm relative to the right-hand side's.
    pub residual: f64,
    /// Whether it met the tolerance.
    pub converged: bool,
}

/// Scratch of a solve, kept between solves.
#[derive(Debug, Clone, Default)]
pub struct CgWork {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves `A x = b` from `x = 0` by conjugate gradients with the preconditioner `A` was built
/// with; `x` holds the solution (or the last iterate when it did not converge).
/// A direction of non-positive curvature (`A` not positive definite) ends the solve as not
/// converged.
pub fn cg(a: &NewtonMatrix, b: &[f64], x: &mut [f64], params: CgParams, w: &mut CgWork) -> CgResult {
    let n = b.len();
    for v in [&mut w.r, &mut w.z, &mut w.p, &mut w.q] {
        v.clear();
        v.resize(n, 0.0);
    }
    x.fill(0.0);
    w.r.copy_from_slice(b);
    let norm_b = dot(b, b).sqrt();
    if norm_b == 0.0 {
        return CgResult { iterations: 0, residual: 0.0, converged: true };
    }
    a.precondition(&w.r, &mut w.z);
    w.p.copy_from_slice(&w.z);
    let mut rz = dot(&w.r, &w.z);
    let mut residual = 1.0;
    for it in 1..=params.max_iter {
        // Ctrl-C (crate::interrupt): unconverged, the step fails and is rolled back.
        if crate::interrupt::stop() {
            return CgResult { iterations: it, residual, converged: false };
        }
        a.apply(&w.p, &mut w.q);
        let curvature = dot(&w.p, &w.q);
        if curvature.is_nan() || curvature <= 0.0 || !rz.is_finite() {
            return CgResult { iterations: it, residual, converged: false };
        }
        let alpha = rz / curvature;
        for i in 0..n {
            x[i] += alpha * w.p[i];
            w.r[i] -= alpha * w.q[i];
        }
        residual = dot(&w.r, &w.r).sqrt() / norm_b;
        if residual <= params.tol {
            return CgResult { iterations: it, residual, converged: true };
        }
        a.precondition(&w.r, &mut w.z);
        let rz_new = dot(&w.r, &w.z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            w.p[i] = w.z[i] + beta * w.p[i];
        }
    }
    CgResult { iterations: params.max_iter, residual, converged: false }
}
