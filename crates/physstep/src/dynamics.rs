//! The interface integrators see.
//!
//! A second-order system `x'' = a(t, x, v)` fills accelerations from `(t, x, v)`; a first-order
//! flow `y' = f(t, y)` fills `dy` from `(t, y)`. Both work on flat `f64` slices: how many
//! particles and dimensions hide behind a slice is the system's business, never the
//! integrator's.
//!
//! Integrators that do not need the split into position and velocity (Euler, midpoint, Heun,
//! RK4, the implicit methods) see a second-order system as the first-order flow of
//! `y = [x; v]`, `y' = [v; a(t, x, v)]` through [`Split`]; the split (symplectic) methods use
//! `accel` directly.

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

/// What the non-split integrators integrate: a flow on `y` that counts its evaluations.
pub trait Flow {
    /// Length of `y`.
    fn dim(&self) -> usize;
    /// Fills `dy = f(t, y)`.
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]);
    /// Fills `df/dy` (row-major, zeroed by the caller); `false` when there is no analytic one.
    /// `work` is scratch the flow may resize.
    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], work: &mut Vec<f64>) -> bool;
}

/// A [`FirstOrder`] flow seen as a [`Flow`], counting its evaluations.
pub struct Plain<'a, F: ?Sized> {
    /// The flow.
    pub sys: &'a mut F,
    /// Incremented on every evaluation of `f`.
    pub evals: &'a mut u64,
}

impl<F: FirstOrder + ?Sized> Flow for Plain<'_, F> {
    #[inline]
    fn dim(&self) -> usize {
        self.sys.len()
    }
    #[inline]
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        *self.evals += 1;
        self.sys.deriv(t, y, dy);
    }
    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], _work: &mut Vec<f64>) -> bool {
        self.sys.jacobian(t, y, j)
    }
}

/// A [`SecondOrder`] system seen as the flow of `y = [x; v]`, `y' = [v; a]`, counting its
/// acceleration evaluations.
pub struct Split<'a, S: ?Sized> {
    /// The system.
    pub sys: &'a mut S,
    /// Incremented on every evaluation of `a`.
    pub evals: &'a mut u64,
}

impl<S: SecondOrder + ?Sized> Split<'_, S> {
    /// Evaluates `a(t, x, v)`, counting it.
    #[inline]
    pub fn accel(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        *self.evals += 1;
        self.sys.accel(t, x, v, a);
    }
}

impl<S: SecondOrder + ?Sized> Flow for Split<'_, S> {
    #[inline]
    fn dim(&self) -> usize {
        2 * self.sys.len()
    }
    #[inline]
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        let n = self.sys.len();
        let (x, v) = y.split_at(n);
        let (dx, dv) = dy.split_at_mut(n);
        dx.copy_from_slice(v);
        self.accel(t, x, v, dv);
    }
    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], work: &mut Vec<f64>) -> bool {
        // d[v; a]/d[x; v] = [[0, I], [da/dx, da/dv]]
        let n = self.sys.len();
        let (x, v) = y.split_at(n);
        work.clear();
        work.resize(2 * n * n, 0.0);
        let (dadx, dadv) = work.split_at_mut(n * n);
        if !self.sys.jacobian(t, x, v, dadx, dadv) {
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
}
