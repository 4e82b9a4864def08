//! A step in progress ([`Step`]): the state a method advances on a [`System`] and the
//! operations its recipe is made of, those operations as a trait over the storage they run on
//! ([`Ops`]: a `Step` over slices, an [`Element`] over one coordinate pair), and the log of a
//! step's evaluation points ([`StageLog`]).

use super::System;

/// The intermediate evaluation points of a step, as the notes print them (`half` for
/// midpoint; `xa`, `xb`, `xc` for RK4).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StageLog {
    /// Rows in the order they were evaluated.
    pub rows: Vec<StageRow>,
}

/// One evaluation point inside a step.
#[derive(Debug, Clone, PartialEq)]
pub struct StageRow {
    /// Stage name (`half`, `xa`, `xb`, `xc`).
    pub stage: &'static str,
    /// Time of the evaluation point, s.
    pub t: f64,
    /// The state there (`[x; v]` for a second-order system).
    pub y: Vec<f64>,
    /// The derivative there (`[v; a]` for a second-order system).
    pub f: Vec<f64>,
}

/// Where a method reports its stages; `None` on the hot path.
pub type Log<'a> = Option<&'a mut StageLog>;

/// One step in progress: the state a method advances, the system, and the operations a
/// recipe is made of. Every evaluation is counted; stages are logged when asked.
pub struct Step<'a, S: ?Sized> {
    /// Time at the start of the step, s.
    pub t: f64,
    /// The step, s.
    pub h: f64,
    /// The state at `t`, moved to `t + h` by the method.
    pub y: &'a mut [f64],
    /// The derivative at `(t, y)`; at the end of the step, at the new state.
    pub f: &'a mut [f64],
    sys: &'a mut S,
    evals: &'a mut u64,
    log: Log<'a>,
}

impl<'a, S: System + ?Sized> Step<'a, S> {
    /// A step of `h` from `(t, y, f)` of `sys`, counting evaluations in `evals`.
    pub fn new(
        sys: &'a mut S,
        t: f64,
        h: f64,
        y: &'a mut [f64],
        f: &'a mut [f64],
        evals: &'a mut u64,
        log: Log<'a>,
    ) -> Self {
        Self { t, h, y, f, sys, evals, log }
    }

    /// The system.
    pub fn system(&mut self) -> &mut S {
        self.sys
    }

    // ----- the flow view -----

    /// `dy = f(t, y)` at a state of the method's own (a stage), counted.
    #[inline]
    pub fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        *self.evals += 1;
        self.sys.deriv(t, y, dy);
    }

    /// A stage: `y_out = y + c h k` and `f_out = f(t + c h, y_out)`, counted; `k` is the
    /// state's own derivative `f` when `None` (an Euler stage).
    #[inline]
    pub fn stage(&mut self, c: f64, k: Option<&[f64]>, y_out: &mut [f64], f_out: &mut [f64]) {
        crate::linalg::vector::axpy_to(y_out, self.y, c * self.h, k.unwrap_or(self.f));
        self.deriv(self.t + c * self.h, y_out, f_out);
    }

    /// The derivative of the step's own state at `t`: `f = f(t, y)`, counted.
    #[inline]
    pub fn refresh(&mut self, t: f64) {
        *self.evals += 1;
        self.sys.deriv(t, self.y, self.f);
    }

    /// Records an intermediate evaluation point (the notes' `half`, `xa`, `xb`, `xc`).
    #[inline]
    pub fn record(&mut self, stage: &'static str, t: f64, y: &[f64], f: &[f64]) {
        if let Some(log) = self.log.as_deref_mut() {
            log.rows.push(StageRow { stage, t, y: y.to_vec(), f: f.to_vec() });
        }
    }

    /// The state, its derivative and the system as a counted flow, apart (for a solver that
    /// evaluates while it reads the state).
    pub fn flow(&mut self) -> (&[f64], &[f64], Counted<'_, S>) {
        (self.y, self.f, Counted { sys: self.sys, evals: self.evals })
    }

    // ----- the split view -----

    /// Positions, velocities and `A`: `(X, V, A)` of `y = [X; V]`, `f = [dX; A]`.
    #[inline]
    pub fn xva(&mut self) -> (&mut [f64], &mut [f64], &mut [f64]) {
        let n = self.split();
        let (x, v) = self.y.split_at_mut(n);
        (x, v, &mut self.f[n..])
    }

    /// Length of the velocities `V` (the size of a method's velocity memory).
    #[inline]
    #[must_use]
    pub fn vel_len(&self) -> usize {
        self.y.len() - self.split()
    }

    #[inline]
    fn split(&self) -> usize {
        self.sys.split().unwrap_or(0)
    }

    /// Whether `A` depends on the velocities.
    #[inline]
    pub fn velocity_dependent(&self) -> bool {
        self.sys.velocity_dependent()
    }

    /// Eval: `A = a(t, X, V)`, counted.
    #[inline]
    pub fn eval(&mut self, t: f64) {
        *self.evals += 1;
        let n = self.split();
        let (x, v) = self.y.split_at(n);
        self.sys.accel(t, x, v, &mut self.f[n..]);
    }

    /// `A = a(t, X, W)` at velocities `w` of the method's own (a half-step velocity), counted.
    #[inline]
    pub fn eval_at(&mut self, t: f64, w: &[f64]) {
        *self.evals += 1;
        let n = self.split();
        self.sys.accel(t, &self.y[..n], w, &mut self.f[n..]);
    }

    /// Kick: `V += h A`.
    #[inline]
    pub fn kick(&mut self, h: f64) {
        let (_, v, a) = self.xva();
        crate::linalg::vector::axpy(v, h, a);
    }

    /// Drift: `X` moved by `V` over `h`.
    #[inline]
    pub fn drift(&mut self, h: f64) {
        let n = self.split();
        let (x, v) = self.y.split_at_mut(n);
        self.sys.drift(x, v, h);
    }

    /// Kick then drift (`V += h A`, then `X` moved by the new `V` over `h`), `dX` synced:
    /// fused into one pass where the part can.
    #[inline]
    pub fn kick_drift(&mut self, h: f64) {
        let n = self.split();
        let (x, v) = self.y.split_at_mut(n);
        let (dx, a) = self.f.split_at_mut(n);
        self.sys.kick_drift(x, v, dx, a, h);
    }

    /// `X` moved by velocities `w` of the method's own over `h`.
    #[inline]
    pub fn drift_by(&mut self, w: &[f64], h: f64) {
        let n = self.split();
        self.sys.drift(&mut self.y[..n], w, h);
    }

    /// Restores `dX` (the first part of `f`) from the new `(X, V)` after a split recipe.
    #[inline]
    pub fn sync(&mut self) {
        let n = self.split();
        let (x, v) = self.y.split_at(n);
        self.sys.rate(x, v, &mut self.f[..n]);
    }
}

/// The operations a method's recipe is made of, over the storage it runs on: a [`Step`]
/// (slices of a whole system: the staged step and the tile kernels) or an [`Element`] (one
/// coordinate and its velocity component: the element-wise kernels). A method written once
/// as a function generic over `Ops` is the same arithmetic, operation for operation, on
/// either, so the fast paths give bitwise what the staged step gives.
///
/// The flow view (`y`, `f`): [`Ops::stage`], [`Ops::combine`], [`Ops::refresh`]; the split
/// view (`y = [X; V]`, `f = [dX; A]`): [`Ops::eval`], [`Ops::kick`], [`Ops::drift`],
/// [`Ops::kick_drift`], [`Ops::kick_from`], [`Ops::sync`]. As on a [`Step`], every
/// evaluation is counted.
pub trait Ops {
    /// A vector as long as the state (a stage, its derivative), sized by the storage.
    type Y;
    /// A vector as long as the velocities (a saved velocity), sized by the storage.
    type V;

    /// Time at the start of the step, s.
    fn t(&self) -> f64;
    /// The step, s.
    fn h(&self) -> f64;
    /// Whether `A` depends on the velocities.
    fn velocity_dependent(&self) -> bool;

    /// A stage: `y_out = y + c h k` and `f_out = f(t + c h, y_out)`, counted; `k` is the
    /// state's own derivative `f` when `None`.
    fn stage(&mut self, c: f64, k: Option<&Self::Y>, y_out: &mut Self::Y, f_out: &mut Self::Y);
    /// Records an intermediate evaluation point (nothing where there is no log).
    fn record(&mut self, stage: &'static str, t: f64, y: &Self::Y, f: &Self::Y);
    /// Each entry of the state replaced by `rule(y_i, f_i, [k_i, ...])` (a method's weighted
    /// sum of its stages).
    fn combine<const K: usize>(&mut self, ks: [&Self::Y; K], rule: impl Fn(f64, f64, [f64; K]) -> f64 + Sync);
    /// `f = f(t, y)` of the state itself, counted.
    fn refresh(&mut self, t: f64);

    /// `A = a(t, X, V)`, counted.
    fn eval(&mut self, t: f64);
    /// `V += h A`.
    fn kick(&mut self, h: f64);
    /// `X` moved by `V` over `h`.
    fn drift(&mut self, h: f64);
    /// A kick then a drift by the new `V`, `dX` synced (one pass where the part fuses it).
    fn kick_drift(&mut self, h: f64);
    /// `w = V` (sized by the storage).
    fn save_velocities(&mut self, w: &mut Self::V);
    /// `V = w + h A`: a kick from velocities `w` of the method's own.
    fn kick_from(&mut self, w: &Self::V, h: f64);
    /// `dX` from the new `(X, V)` after a split recipe.
    fn sync(&mut self);
}

impl<S: System + ?Sized> Ops for Step<'_, S> {
    type Y = Vec<f64>;
    type V = Vec<f64>;

    #[inline]
    fn t(&self) -> f64 {
        self.t
    }
    #[inline]
    fn h(&self) -> f64 {
        self.h
    }
    #[inline]
    fn velocity_dependent(&self) -> bool {
        Step::velocity_dependent(self)
    }
    #[inline]
    fn stage(&mut self, c: f64, k: Option<&Vec<f64>>, y_out: &mut Vec<f64>, f_out: &mut Vec<f64>) {
        let n = self.y.len();
        let (y_out, f_out) =
            (crate::linalg::vector::scratch(y_out, n), crate::linalg::vector::scratch(f_out, n));
        Step::stage(self, c, k.map(Vec::as_slice), y_out, f_out);
    }
    #[inline]
    fn record(&mut self, stage: &'static str, t: f64, y: &Vec<f64>, f: &Vec<f64>) {
        Step::record(self, stage, t, y, f);
    }
    #[inline]
    fn combine<const K: usize>(
        &mut self,
        ks: [&Vec<f64>; K],
        rule: impl Fn(f64, f64, [f64; K]) -> f64 + Sync,
    ) {
        let (y, f) = (&mut *self.y, &*self.f);
        let ks = ks.map(Vec::as_slice);
        if y.len() >= crate::linalg::vector::PAR_MIN {
            use rayon::prelude::*;
            let c = crate::linalg::vector::PAR_CHUNK;
            y.par_chunks_mut(c).enumerate().for_each(|(q, yc)| {
                combine_serial(yc, &f[q * c..], ks.map(|k| &k[q * c..]), &rule);
            });
        } else {
            combine_serial(y, f, ks, &rule);
        }
    }
    #[inline]
    fn refresh(&mut self, t: f64) {
        Step::refresh(self, t);
    }
    #[inline]
    fn eval(&mut self, t: f64) {
        Step::eval(self, t);
    }
    #[inline]
    fn kick(&mut self, h: f64) {
        Step::kick(self, h);
    }
    #[inline]
    fn drift(&mut self, h: f64) {
        Step::drift(self, h);
    }
    #[inline]
    fn kick_drift(&mut self, h: f64) {
        Step::kick_drift(self, h);
    }
    #[inline]
    fn save_velocities(&mut self, w: &mut Vec<f64>) {
        let w = crate::linalg::vector::scratch(w, self.vel_len());
        w.copy_from_slice(self.xva().1);
    }
    #[inline]
    fn kick_from(&mut self, w: &Vec<f64>, h: f64) {
        let (_, v, a) = self.xva();
        crate::linalg::vector::axpy_to(v, w, h, a);
    }
    #[inline]
    fn sync(&mut self) {
        Step::sync(self);
    }
}

/// `y_i = rule(y_i, f_i, [k_i, ...])` over `y` (the others at least as long).
#[inline(always)]
fn combine_serial<const K: usize>(
    y: &mut [f64],
    f: &[f64],
    ks: [&[f64]; K],
    rule: &impl Fn(f64, f64, [f64; K]) -> f64,
) {
    // All cut to one length first, so the loop indexes without bounds checks (and vectorises).
    let n = y.len();
    let (f, ks) = (&f[..n], ks.map(|k| &k[..n]));
    for i in 0..n {
        y[i] = rule(y[i], f[i], ks.map(|k| k[i]));
    }
}

/// One element of a particle system whose every acceleration component is a function of its
/// own coordinate and velocity component alone (gravity, linear drag, springs of zero rest
/// length to anchors): the coordinate `x` and velocity `v` as `y = [x, v]`, their rates
/// `f = [dx, a]`, and the acceleration `acc(x, v)`. A method's recipe run on it (see
/// [`crate::integrators::Method::element_step`]) is the recipe on the whole system, one
/// element at a time: the element-wise kernels hold the element in registers and the
/// compiler vectorises over elements. The forces are autonomous: `t` is not read.
#[derive(Debug, Clone, Copy)]
pub struct Element<A> {
    /// Time at the start of the step, s.
    pub t: f64,
    /// The step, s.
    pub h: f64,
    /// `[x, v]`.
    pub y: [f64; 2],
    /// `[dx, a]` at `y`.
    pub f: [f64; 2],
    /// Evaluations of `acc` counted.
    pub evals: u64,
    velocity: bool,
    acc: A,
}

impl<A: Fn(f64, f64) -> f64> Element<A> {
    /// The element at `y = [x, v]` with its rates `f = [dx, a]`, a step of `h` from `t`;
    /// `velocity` says whether `acc` reads `v`.
    #[inline(always)]
    pub fn new(t: f64, h: f64, y: [f64; 2], f: [f64; 2], velocity: bool, acc: A) -> Self {
        Self { t, h, y, f, evals: 0, velocity, acc }
    }

    /// The element at `y = [x, v]`, its rates evaluated (not counted: the state's own).
    #[inline(always)]
    pub fn at(t: f64, h: f64, y: [f64; 2], velocity: bool, acc: A) -> Self {
        let f = [y[1], acc(y[0], y[1])];
        Self::new(t, h, y, f, velocity, acc)
    }
}

impl<A: Fn(f64, f64) -> f64> Ops for Element<A> {
    type Y = [f64; 2];
    type V = f64;

    #[inline(always)]
    fn t(&self) -> f64 {
        self.t
    }
    #[inline(always)]
    fn h(&self) -> f64 {
        self.h
    }
    #[inline(always)]
    fn velocity_dependent(&self) -> bool {
        self.velocity
    }
    #[inline(always)]
    fn stage(&mut self, c: f64, k: Option<&[f64; 2]>, y_out: &mut [f64; 2], f_out: &mut [f64; 2]) {
        let (k, s) = (k.unwrap_or(&self.f), c * self.h);
        *y_out = [self.y[0] + s * k[0], self.y[1] + s * k[1]];
        self.evals += 1;
        *f_out = [y_out[1], (self.acc)(y_out[0], y_out[1])];
    }
    #[inline(always)]
    fn record(&mut self, _stage: &'static str, _t: f64, _y: &[f64; 2], _f: &[f64; 2]) {}
    #[inline(always)]
    fn combine<const K: usize>(
        &mut self,
        ks: [&[f64; 2]; K],
        rule: impl Fn(f64, f64, [f64; K]) -> f64 + Sync,
    ) {
        for i in 0..2 {
            self.y[i] = rule(self.y[i], self.f[i], ks.map(|k| k[i]));
        }
    }
    #[inline(always)]
    fn refresh(&mut self, _t: f64) {
        self.evals += 1;
        self.f = [self.y[1], (self.acc)(self.y[0], self.y[1])];
    }
    #[inline(always)]
    fn eval(&mut self, _t: f64) {
        self.evals += 1;
        self.f[1] = (self.acc)(self.y[0], self.y[1]);
    }
    #[inline(always)]
    fn kick(&mut self, h: f64) {
        self.y[1] += h * self.f[1];
    }
    #[inline(always)]
    fn drift(&mut self, h: f64) {
        self.y[0] += h * self.y[1];
    }
    #[inline(always)]
    fn kick_drift(&mut self, h: f64) {
        self.kick(h);
        self.drift(h);
        self.sync();
    }
    #[inline(always)]
    fn save_velocities(&mut self, w: &mut f64) {
        *w = self.y[1];
    }
    #[inline(always)]
    fn kick_from(&mut self, w: &f64, h: f64) {
        self.y[1] = w + h * self.f[1];
    }
    #[inline(always)]
    fn sync(&mut self) {
        self.f[0] = self.y[1];
    }
}

/// A system seen as a flow whose evaluations are counted: what a solver (Newton) calls.
pub struct Counted<'a, S: ?Sized> {
    sys: &'a mut S,
    evals: &'a mut u64,
}

impl<S: System + ?Sized> Counted<'_, S> {
    /// Length of `y`.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.sys.dim()
    }
    /// `dy = f(t, y)`, counted.
    #[inline]
    pub fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        *self.evals += 1;
        self.sys.deriv(t, y, dy);
    }
    /// `df/dy` as [`System::jacobian`].
    pub fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], work: &mut Vec<f64>) -> bool {
        self.sys.jacobian(t, y, j, work)
    }
    /// The force Jacobians as blocks, as [`System::blocks`].
    pub fn blocks(&mut self, t: f64, y: &[f64], out: &mut crate::linalg::Blocks) -> bool {
        self.sys.blocks(t, y, out)
    }
    /// Length of the positions of a split system (`None` for a flow).
    #[must_use]
    pub fn split(&self) -> Option<usize> {
        self.sys.split()
    }
    /// The kinetic and potential energy at `y`, as [`System::energy`] (not counted as an
    /// evaluation).
    #[must_use]
    pub fn energy(&self, y: &[f64]) -> Option<(f64, f64)> {
        self.sys.energy(y)
    }
}
