//! The implicit methods' settings ([`ImplicitParams`], what a user sets) and what a step's
//! solve reports ([`SolveStats`]); the iteration that uses them is `newton.rs`.

use crate::linalg::CgParams;

/// Settings of the implicit methods' Newton iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImplicitParams {
    /// Converged, after at least one Newton update, when the residual of `z = y0 + c f(z)`
    /// is at most `tol` times the size of its terms (max norms of `z`, `y0`, `c f(z)`, and
    /// `c |df/dz| |z|`, the terms that cancel inside a stiff `f`: a spring of k / m = 1e7
    /// evaluates its force from positions of size 1 to 1e-9, and no iteration gets below
    /// that): relative at every scale, so a state of size 1e-15 is solved as well as one of
    /// size 1. The default, 1e-11, is still 1e5 times that rounding floor; a folding stiff
    /// cloth (springs compressed near buckling, where the sparse solve converges slowly:
    /// see [`crate::linalg`]) stalled above 1e-12 in one of its first 100 steps.
    pub tol: f64,
    /// Iterations before giving up with [`crate::error::Error::NotConverged`] (default 500: the sparse
    /// solve's updates are cheap, and a folding cloth took up to 338 in a step).
    pub max_iter: u32,
    /// The conjugate-gradient solve of each Newton update on a large world (see
    /// [`crate::linalg`]): its relative tolerance and iteration cap.
    pub cg: CgParams,
    /// Largest system (unknowns: x and v of every coordinate) solved densely when the
    /// sparse solve is available (default [`DENSE_UP_TO`]); 0 always takes the sparse one,
    /// `usize::MAX` never.
    pub dense_up_to: usize,
    /// Whether the sparse solve's updates take a secant line search on the incremental
    /// potential's slope (default `true`; `false` takes every update whole, as before the
    /// search: with [`crate::linalg::Preconditioner::BlockJacobi`] that is the earlier solve,
    /// bit for bit). The dense solve and the linearly implicit step take whole updates.
    pub line_search: bool,
    /// Whether the sparse solve of backward Euler and implicit midpoint tries the exact
    /// Jacobian first (default `true`):
    /// each Newton update factors the matrix with the springs' exact blocks (a compressed
    /// spring's sideways term kept, [`crate::linalg::Blocks::exact`]) and, where that matrix
    /// is positive definite, takes the exact Newton update whole (quadratic convergence);
    /// where it is not (the factorisation meets a pivot that is not positive), that update
    /// takes the semidefinite matrix and the line search, as with `false`. The iteration
    /// then starts from `x + h v, v` (no acceleration), where the exact updates converge,
    /// not from the explicit guess. Only with [`crate::linalg::Preconditioner::Cholesky`];
    /// `false` gives the earlier iteration bit for bit. The linearly implicit step keeps the
    /// semidefinite matrix (with the exact one its energy rose on more steps).
    pub exact_jacobian: bool,
    /// The linearly implicit step only: how many times a step may be halved where it would
    /// raise the energy. Where the system states its energy (kinetic plus potential:
    /// [`crate::dynamics::SecondOrder::energy`]; a world without user forces that lack a
    /// potential, and without rigid bodies), a step whose energy comes out higher than it went
    /// in, by more than [`ENERGY_ROUNDING`] of the energies' sizes, is taken again as two
    /// steps of half the size, each checked the same way, down to steps of
    /// `dt / 2^energy_halvings`, the last kept whatever its energy. Default 4 (a step then
    /// takes at most 31 linear solves: 1 + 2 + 4 + 8 + 16); 0 takes one linear solve a step
    /// always, Baraff and Witkin's step as it is. At most [`MAX_ENERGY_HALVINGS`].
    pub energy_halvings: u32,
}

/// Most halvings of a linearly implicit step ([`ImplicitParams::energy_halvings`]): steps of
/// `dt / 65,536`.
pub const MAX_ENERGY_HALVINGS: u32 = 16;

/// The energy rise a linearly implicit step is allowed before it is halved
/// ([`ImplicitParams::energy_halvings`]), relative to the sum of the sizes of the kinetic and
/// potential energies before and after it: far above the rounding of those sums (a few
/// 1e-16 of their terms), far below a rise of the step itself (a folding stiff cloth's rose
/// by 1e-3 to 0.1 of its energy).
pub const ENERGY_ROUNDING: f64 = 1e-10;

impl Default for ImplicitParams {
    fn default() -> Self {
        Self {
            tol: 1e-11,
            max_iter: 500,
            cg: CgParams::default(),
            dense_up_to: DENSE_UP_TO,
            line_search: true,
            exact_jacobian: true,
            energy_halvings: 4,
        }
    }
}

/// What the latest solve of an implicit step did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolveStats {
    /// Newton updates taken.
    pub newton: u32,
    /// Conjugate-gradient iterations over all of them (0 for the dense solve).
    pub cg: u32,
    /// The final Newton residual, relative to the size of its terms.
    pub residual: f64,
    /// Whether the sparse solve (blocks and conjugate gradients) was used.
    pub sparse: bool,
}

/// Largest system (unknowns: x and v of every coordinate) solved densely when the sparse
/// solve is available (measured on stiff-chain, `bench/bench_stiff.py`'s `run`, with the
/// sparse solve's inexact updates: the dense LU 0.025 ms a step against 0.035 at 44
/// unknowns, 0.067 against 0.069 at 68, 0.087 against 0.082 at 76).
pub const DENSE_UP_TO: usize = 64;
