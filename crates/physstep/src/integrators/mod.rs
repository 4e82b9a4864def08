//! Integrators: one file per method, all behind the [`Method`] trait, chosen by name through
//! the [`registry`].
//!
//! Every method advances a state by one step of `h` seconds through a
//! [`crate::dynamics::Step`]. The state keeps the derivative at its own time
//! (`f = [v; a]` for particles), so a method that needs the acceleration at the start of a
//! step reuses it instead of evaluating it again, and a table row `(t, x, v, a)` is always
//! self-consistent.
//!
//! Methods are written once against the parts of a world (see [`crate::dynamics`]):
//! - *flow* methods (explicit Euler, midpoint, Heun, RK4, backward Euler,
//!   predictor-corrector, implicit midpoint) integrate the flat state and its derivative, so
//!   they apply to every part, first-order flows included;
//! - *split* methods (the symplectic Eulers, Verlet, velocity Verlet, leapfrog, Yoshida) are
//!   recipes of eval, kick and drift, and need positions and velocities apart.

mod backward_euler;
mod explicit_euler;
mod heun;
mod implicit;
mod implicit_midpoint;
mod leapfrog;
mod linearly_implicit_euler;
mod midpoint;
mod newton;
mod predictor_corrector;
pub mod registry;
mod rk4;
mod state;
mod symplectic_euler;
mod verlet;
mod yoshida;

pub use backward_euler::BackwardEuler;
pub use explicit_euler::ExplicitEuler;
pub use heun::Heun;
pub use implicit::{ImplicitParams, SolveStats, DENSE_UP_TO, ENERGY_ROUNDING, MAX_ENERGY_HALVINGS};
pub use implicit_midpoint::ImplicitMidpoint;
pub use leapfrog::Leapfrog;
pub use linearly_implicit_euler::LinearlyImplicitEuler;
pub use midpoint::Midpoint;
pub use predictor_corrector::PredictorCorrector;
pub use registry::{Integrator, INFOS};
pub use rk4::Rk4;
pub use symplectic_euler::{SymplecticEuler, SymplecticEulerAlternating, SymplecticEulerX};
pub use verlet::{VelocityVerlet, Verlet};
pub use yoshida::Yoshida4;

use crate::dynamics::{Element, Step, System};
use crate::error::{Error, Result};

/// What a method is, read by the registry, the CLI's method list, Python's docs and the
/// README table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Info {
    /// Kebab-case registry name (`explicit-euler`, `rk4`, ...).
    pub name: &'static str,
    /// Global order of accuracy in position (error ~ dt^order).
    pub order: u32,
    /// Whether the method is symplectic (bounded energy error on conservative systems).
    pub symplectic: bool,
    /// Whether each step solves an implicit equation (Newton iteration).
    pub implicit: bool,
    /// Acceleration (force) evaluations per step for velocity-independent forces with an
    /// analytic Jacobian; implicit methods: for a linear force (one Newton update plus the
    /// converged check). The lab measures the real count.
    pub evals: u32,
    /// Whether the method needs positions and velocities apart (second-order systems only).
    pub split: bool,
    /// Whether the method does arithmetic on positions as vectors (Verlet's
    /// `2 x - x_prev`), so it applies to particles but not to orientations.
    pub vector_positions: bool,
    /// Whether a step is *local*: element by element over particles (no sum across them, no
    /// solve of the whole state) with no memory from step to step, so running it on any part
    /// of the particles at a time gives bitwise what running it on all of them gives. The
    /// fused particle kernels run these (see [`Integrator::fresh_local`]).
    pub local: bool,
    /// How the Relax stage meets position constraints under this method.
    pub constraints: ConstraintMode,
    /// Steps after which the method's step map repeats: 1, or 2 for a method that alternates
    /// two steps (symplectic Euler in both orders). The lab's amplification matrix is the map
    /// of one period.
    pub period: u32,
    /// One-line description with the update rule.
    pub doc: &'static str,
}

/// How a method's step meets position constraints (the Relax stage's solver; see
/// docs/constraints.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConstraintMode {
    /// Jakobsen's projection, the velocity the secant `(x - x_prev) / h`: a method whose
    /// velocity is a backward difference of positions (velocityless Verlet).
    Jakobsen,
    /// Projection, gradients at the current positions, `iterations` sweeps; `v += dx / h`,
    /// then the velocities projected onto the rigid constraints' tangent: most methods.
    Project,
    /// Rigid distances by SHAKE (gradients at the step's start positions, to the tolerance)
    /// and the velocities by RATTLE, the other constraints projected: a method whose step is
    /// a half kick, a drift and a half kick (velocity Verlet, leapfrog).
    Rattle,
}

pub use crate::dynamics::{Log, StageLog, StageRow};

/// One integration method: a recipe run on a [`Step`].
///
/// The step holds the state `y` at time `t` and its derivative `f`; the method advances both
/// to `t + h`. Methods keep any state of their own (Verlet's previous position, leapfrog's
/// half-step velocity) and drop it on [`Method::reset`].
pub trait Method {
    /// What the method is.
    const INFO: Info;

    /// One step. Split methods are run only on systems with a split view (the registry
    /// refuses the others), and Verlet-like ones only where positions are vectors.
    ///
    /// # Errors
    /// [`Error::NotConverged`] when an implicit method's Newton iteration fails;
    /// [`Error::Unsupported`] when the system is too large for the dense solver.
    fn step<S: System + ?Sized>(&mut self, s: &mut Step<'_, S>) -> Result<()>;

    /// One step of one element (see [`Element`]) by the same recipe as [`Method::step`], the
    /// recipe written once, generic over the storage it runs on
    /// ([`Ops`](crate::dynamics::Ops)); returns whether the method has that form (`false`,
    /// the default: `e` is left as it was). The element-wise kernels run it for methods that
    /// are local and keep no memory (see [`Integrator::fresh_local`]); `tests/it/kernels.rs`
    /// and `world/flat.rs`'s unit test hold it bitwise to the staged step.
    fn element_step<A: Fn(f64, f64) -> f64>(&self, e: &mut Element<A>) -> bool {
        let _ = e;
        false
    }

    /// Forgets internal state (after the user moved the system or a rollback); the next
    /// step starts afresh from `(x, v)`.
    fn reset(&mut self) {}

    /// How many leading entries of [`Method::memory`] are flags and settings (a started
    /// flag, the previous step size) rather than state: the rest is a vector of the state's
    /// kind (Verlet's previous position, leapfrog's half-step velocity), which a
    /// linearisation of the step map perturbs like the state itself.
    const MEMORY_FLAGS: usize = 0;

    /// Appends the method's internal state as numbers to `out` (for snapshots and the
    /// rollback of a failed step); nothing for stateless methods.
    fn memory(&self, out: &mut Vec<f64>) {
        let _ = out;
    }

    /// Restores what [`Method::memory`] returned for a state of the given `sizes`; `false`
    /// when `m` does not fit (wrong length, a flag that is not 0 or 1, a non-finite value).
    fn recall(&mut self, m: &[f64], sizes: Sizes) -> bool {
        let _ = sizes;
        m.is_empty()
    }

    /// Whether the memory holds a vector of the state's kind (Verlet's previous positions,
    /// leapfrog's half-step velocities: [`Method::memory`] longer than
    /// [`Method::MEMORY_FLAGS`]), which goes stale when a stage outside the method moves the
    /// state; `false` for a method without one.
    fn carries(&self) -> bool {
        false
    }

    /// A stage outside the method (a contact's impulse) changed the velocities at `at..` of
    /// the state's velocity vector (`at` counted in coordinates, the same place in the
    /// position vector) from `before` to `v`, the positions there being `x`, in a step of
    /// `h`: the method brings its carried memory into line (Verlet's previous positions
    /// `x - v h`, leapfrog's half-step velocities moved by `v - before`). Nothing for a
    /// method without memory.
    fn velocities_changed(&mut self, at: usize, x: &[f64], v: &[f64], before: &[f64], h: f64) {
        let _ = (at, x, v, before, h);
    }

    /// What the latest step's implicit solve did; `None` for an explicit method.
    fn solve_stats(&self) -> Option<SolveStats> {
        None
    }
}

/// The lengths of a state's positions and velocities (`y = [X; V]`), which a method's memory
/// vector must match: Verlet keeps a vector of positions, leapfrog one of velocities. A
/// first-order flow's state counts as positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sizes {
    /// Length of the positions `X`.
    pub x: usize,
    /// Length of the velocities `V`.
    pub v: usize,
}

/// The memory of a method that carries one vector from step to step (Verlet's previous
/// positions, leapfrog's half-step velocities): the vector, the step it was made with, and
/// whether it is started. As numbers (for snapshots and rollback): `[started, h, vector...]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Carried {
    /// The vector.
    pub v: Vec<f64>,
    /// The step the vector belongs to, s.
    pub h: f64,
    /// Whether `v` holds a value (false before the first step and after a reset).
    pub started: bool,
}

impl Carried {
    /// Forgets the vector.
    pub fn reset(&mut self) {
        self.started = false;
        self.v.clear();
    }

    /// Marks the vector as made with step `h`.
    pub fn keep(&mut self, h: f64) {
        self.started = true;
        self.h = h;
    }

    /// Appends `[started, h, vector...]` to `out`.
    pub fn memory(&self, out: &mut Vec<f64>) {
        out.push(if self.started { 1.0 } else { 0.0 });
        out.push(self.h);
        out.extend_from_slice(&self.v);
    }

    /// Restores what [`Carried::memory`] wrote for a system of `n` coordinates; `false` when
    /// `m` does not fit: a flag that is not exactly 0 or 1, a step that is not finite and
    /// >= 0, a vector that is not finite or not `n` long (or empty, before the first step).
    pub fn recall(&mut self, m: &[f64], n: usize) -> bool {
        match m {
            [s, h, rest @ ..]
                if (*s == 0.0 || *s == 1.0)
                    && h.is_finite()
                    && *h >= 0.0
                    && (rest.len() == n || (*s == 0.0 && rest.is_empty()))
                    && rest.iter().all(|v| v.is_finite()) =>
            {
                self.started = *s == 1.0;
                self.h = *h;
                self.v = rest.to_vec();
                true
            }
            _ => false,
        }
    }
}

/// Implements the memory items of [`Method`] for a method whose memory is the [`Carried`]
/// field `$field`, a vector as long as the state's `$kind` (`x` or `v` of [`Sizes`]).
macro_rules! carried_memory {
    ($field:ident, $kind:ident) => {
        const MEMORY_FLAGS: usize = 2;

        fn reset(&mut self) {
            self.$field.reset();
        }

        fn memory(&self, out: &mut Vec<f64>) {
            self.$field.memory(out);
        }

        fn recall(&mut self, m: &[f64], sizes: $crate::integrators::Sizes) -> bool {
            self.$field.recall(m, sizes.$kind)
        }

        fn carries(&self) -> bool {
            !self.$field.v.is_empty()
        }
    };
}
pub(crate) use carried_memory;

/// The answer of a split method asked to integrate a first-order flow.
pub(crate) fn split_only(info: &Info) -> Error {
    Error::Unsupported {
        method: info.name.into(),
        reason: "needs a second-order system (positions and velocities); use a flow method such as rk4"
            .into(),
    }
}

/// The answer of a method that does arithmetic on positions (Verlet) asked to move
/// orientations.
pub(crate) fn vectors_only(info: &Info) -> Error {
    Error::Unsupported {
        method: info.name.into(),
        reason: "does arithmetic on positions as vectors (2 x - x_prev), which orientations are not; use velocity-verlet or leapfrog".into(),
    }
}

pub(crate) use crate::linalg::vector::scratch;
pub use crate::linalg::vector::{axpy, axpy_to};
