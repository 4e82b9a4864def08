//! What methods see of a world: its parts as one [`System`], and a [`Step`] to run a recipe
//! on.
//!
//! A world's state is one flat vector `y` with its derivative `f`. Where the world is
//! mechanical, `y = [X; V]` splits into positions `X` (particles' x; later, bodies' x and
//! orientation) and velocities `V` (particles' v; bodies' momenta), and `f = [dX; A]` with
//! `A` what a kick adds to `V` per second (particles' accelerations; bodies' forces and
//! torques). Methods are written once against this view:
//!
//! - *split* methods (symplectic Euler, Verlet, leapfrog, velocity Verlet, Yoshida) are
//!   recipes of [`Step::eval`] (`A` at the current state), [`Step::kick`] (`V += h A`) and
//!   [`Step::drift`] (`X` moved by `V` over `h`, as each part defines it);
//! - *flow* methods (Euler, midpoint, Heun, RK4, the implicit ones) see the flat `y` and its
//!   derivative through [`Step::deriv`]; the system's [`System::project`] runs after every
//!   step (a quaternion renormalised).
//!
//! Users write a system as a [`SecondOrder`] (`x'' = a(t, x, v)`) or a [`FirstOrder`]
//! (`y' = f(t, y)`); [`Second`] and [`First`] make them [`System`]s.

/// A second-order system `x'' = a(t, x, v)` on `n` coordinates.
pub trait SecondOrder {
    /// Number of coordinates `n` (length of `x`, `v` and `a`).
    fn len(&self) -> usize;

    /// Whether the system has no coordinates.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Fills `a` (length `n`) with the acceleration at time `t` (s), positions `x` and
    /// velocities `v`.
    fn accel(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]);

    /// Whether `a` depends on `v`. Methods that evaluate the acceleration at a mid-step
    /// velocity skip re-evaluating it at the end-of-step velocity when this is `false`.
    fn velocity_dependent(&self) -> bool {
        true
    }

    /// Fills the Jacobians `da/dx` and `da/dv` (row-major `n x n`, zeroed by the caller) and
    /// returns `true`, or returns `false` when the system has no analytic Jacobian (the
    /// implicit methods then use finite differences).
    fn jacobian(&mut self, _t: f64, _x: &[f64], _v: &[f64], _dadx: &mut [f64], _dadv: &mut [f64]) -> bool {
        false
    }

    /// Fills `out` with the force Jacobians as 3 x 3 blocks (see [`crate::linalg`]) for the
    /// sparse Newton solve of the implicit methods and returns `true`, or returns `false`
    /// when the system has none (the dense solve is used).
    fn blocks(&mut self, _t: f64, _x: &[f64], _v: &[f64], _out: &mut crate::linalg::Blocks) -> bool {
        false
    }

    /// The kinetic and the potential energy at `(x, v)`, or `None` (the default) where the
    /// system has none it can state (a force without a potential). Where it has them, the
    /// linearly implicit step halves any step that would raise their sum
    /// ([`crate::integrators::ImplicitParams::energy_halvings`]).
    fn energy(&self, _x: &[f64], _v: &[f64]) -> Option<(f64, f64)> {
        None
    }
}

/// A first-order flow `y' = f(t, y)` on `n` coordinates (a strange attractor, a chemical
/// reaction, any ODE that is not F = ma).
pub trait FirstOrder {
    /// Number of coordinates `n`.
    fn len(&self) -> usize;

    /// Whether the flow has no coordinates.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Fills `dy` with `f(t, y)`.
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]);

    /// Fills the Jacobian `df/dy` (row-major `n x n`, zeroed by the caller) and returns
    /// `true`, or returns `false` to let the implicit methods use finite differences.
    fn jacobian(&mut self, _t: f64, _y: &[f64], _dfdy: &mut [f64]) -> bool {
        false
    }
}

/// A world's parts as one system, as methods see it (see the module docs).
///
/// The split view ([`System::split`], [`System::accel`], [`System::drift`],
/// [`System::rate`]) is used only when `split()` is `Some`; a first-order flow returns `None`
/// and split methods refuse it.
pub trait System {
    /// Length of the flat state `y` (and of `f`).
    fn dim(&self) -> usize;

    /// Length of the positions `X` where `y = [X; V]`; `None` for a first-order flow.
    fn split(&self) -> Option<usize>;

    /// Fills `dy = f(t, y)`. For a split system: `[dX; A]` from [`System::rate`] and
    /// [`System::accel`].
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.split().unwrap_or(0);
        let (x, v) = y.split_at(n);
        let (dx, a) = dy.split_at_mut(n);
        self.rate(x, v, dx);
        self.accel(t, x, v, a);
    }

    /// Fills `df/dy` (row-major, zeroed by the caller) and returns `true`, or `false` when
    /// there is no analytic one (the implicit methods then use finite differences). `work` is
    /// scratch the system may resize.
    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], work: &mut Vec<f64>) -> bool;

    /// The force Jacobians as blocks (see [`SecondOrder::blocks`]); `false` when there are
    /// none.
    fn blocks(&mut self, _t: f64, _y: &[f64], _out: &mut crate::linalg::Blocks) -> bool {
        false
    }

    /// The kinetic and potential energy at `y`, as [`SecondOrder::energy`]; `None` (the
    /// default) where there is none.
    fn energy(&self, _y: &[f64]) -> Option<(f64, f64)> {
        None
    }

    /// Fills `A` at time `t`, positions `x` and velocities `w`.
    fn accel(&mut self, t: f64, x: &[f64], w: &[f64], a: &mut [f64]);

    /// Moves positions `x` by velocities `w` over `h` (which may be negative): particles
    /// `x += h w`.
    fn drift(&mut self, x: &mut [f64], w: &[f64], h: f64);

    /// Fills `dx`, the rate of the positions at `(x, v)`: particles `dx = v`.
    fn rate(&self, x: &[f64], v: &[f64], dx: &mut [f64]);

    /// Whether `A` depends on `V` (methods skip re-evaluating it when it does not).
    fn velocity_dependent(&self) -> bool;

    /// A kick `v += h a`, a drift of `x` by the new `v` over `h`, and `dx` = the new rate:
    /// the whole of a symplectic Euler step but its evaluation. Parts fuse it into one pass
    /// over memory where they can; the result must be what the three would give.
    fn kick_drift(&mut self, x: &mut [f64], v: &mut [f64], dx: &mut [f64], a: &[f64], h: f64) {
        crate::linalg::vector::axpy(v, h, a);
        self.drift(x, v, h);
        self.rate(x, v, dx);
    }

    /// Whether the positions are plain vectors, so a method may do arithmetic on them
    /// (Verlet's `2 x - x_prev`); `false` for orientations.
    fn vector_positions(&self) -> bool {
        true
    }

    /// Brings `y` back onto the state space after a step (a quaternion renormalised) and
    /// says whether it changed anything (then the derivative is evaluated again there, so a
    /// state's `f` is always `f(t, y)`); nothing for particles and flows.
    fn project(&mut self, y: &mut [f64]) -> bool {
        let _ = y;
        false
    }
}

/// A [`SecondOrder`] system as a [`System`] on `y = [x; v]`.
pub struct Second<'a, S: ?Sized>(pub &'a mut S);

impl<S: SecondOrder + ?Sized> System for Second<'_, S> {
    #[inline]
    fn dim(&self) -> usize {
        2 * self.0.len()
    }
    #[inline]
    fn split(&self) -> Option<usize> {
        Some(self.0.len())
    }
    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], work: &mut Vec<f64>) -> bool {
        // d[v; a]/d[x; v] = [[0, I], [da/dx, da/dv]]
        let n = self.0.len();
        let (x, v) = y.split_at(n);
        work.clear();
        work.resize(2 * n * n, 0.0);
        let (dadx, dadv) = work.split_at_mut(n * n);
        if !self.0.jacobian(t, x, v, dadx, dadv) {
            return false;
        }
        let m = 2 * n;
        for i in 0..n {
            j[i * m + n + i] = 1.0;
            j[(n + i) * m..(n + i) * m + n].copy_from_slice(&dadx[i * n..(i + 1) * n]);
            j[(n + i) * m + n..(n + i + 1) * m].copy_from_slice(&dadv[i * n..(i + 1) * n]);
        }
        true
    }
    fn blocks(&mut self, t: f64, y: &[f64], out: &mut crate::linalg::Blocks) -> bool {
        let (x, v) = y.split_at(self.0.len());
        self.0.blocks(t, x, v, out)
    }
    fn energy(&self, y: &[f64]) -> Option<(f64, f64)> {
        let (x, v) = y.split_at(self.0.len());
        self.0.energy(x, v)
    }
    #[inline]
    fn accel(&mut self, t: f64, x: &[f64], w: &[f64], a: &mut [f64]) {
        self.0.accel(t, x, w, a);
    }
    #[inline]
    fn drift(&mut self, x: &mut [f64], w: &[f64], h: f64) {
        crate::linalg::vector::axpy(x, h, w);
    }
    #[inline]
    fn rate(&self, _x: &[f64], v: &[f64], dx: &mut [f64]) {
        dx.copy_from_slice(v);
    }
    #[inline]
    fn velocity_dependent(&self) -> bool {
        self.0.velocity_dependent()
    }
    #[inline]
    fn kick_drift(&mut self, x: &mut [f64], v: &mut [f64], dx: &mut [f64], a: &[f64], h: f64) {
        crate::linalg::vector::kick_drift(x, v, dx, a, h);
    }
}

/// A [`FirstOrder`] flow as a [`System`] (no split: split methods refuse it).
pub struct First<'a, F: ?Sized>(pub &'a mut F);

impl<F: FirstOrder + ?Sized> System for First<'_, F> {
    #[inline]
    fn dim(&self) -> usize {
        self.0.len()
    }
    #[inline]
    fn split(&self) -> Option<usize> {
        None
    }
    #[inline]
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.0.deriv(t, y, dy);
    }
    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], _work: &mut Vec<f64>) -> bool {
        self.0.jacobian(t, y, j)
    }
    // A flow has no split view; the registry never runs a split method on it.
    fn accel(&mut self, _t: f64, _x: &[f64], _w: &[f64], _a: &mut [f64]) {}
    fn drift(&mut self, _x: &mut [f64], _w: &[f64], _h: f64) {}
    fn rate(&self, _x: &[f64], _v: &[f64], _dx: &mut [f64]) {}
    fn velocity_dependent(&self) -> bool {
        true
    }
}

mod step;

pub use step::{Counted, Element, Log, Ops, StageLog, StageRow, Step};
