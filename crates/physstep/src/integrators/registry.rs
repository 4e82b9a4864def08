//! Names to methods: the one place that lists every integrator.

pub use super::state::State;
use super::*;
use crate::dynamics::{First, FirstOrder, Second, SecondOrder, Step, System};
use crate::error::{Error, Result};

/// The registry: one line per method, in registry order (the order of the notes, then the
/// extras), giving its type (whose file holds its name, [`Info`] and recipe) and how it is
/// made from the implicit methods' settings. It generates [`INFOS`], the closed dispatch
/// (`Kind` and `dispatch!`), the constructor by name and the fresh instance of a local
/// method: adding a method is its file and a line here.
///
/// (`$d` is a `$` handed to the inner `dispatch!`, whose own variables a nested
/// `macro_rules!` could not otherwise write.)
macro_rules! registry {
    ($d:tt $($m:ident: $make:expr,)*) => {
        /// Every method's [`Info`], in registry order (the order of the notes, then the extras).
        pub const INFOS: [Info; [$(stringify!($m)),*].len()] = [$(<$m as Method>::INFO),*];

        #[derive(Debug, Clone)]
        enum Kind {
            $($m($m),)*
        }

        /// Runs `$body` with `$x` bound to the concrete method inside `$kind`.
        macro_rules! dispatch {
            ($d kind:expr, $d x:ident => $d body:expr) => {
                match $d kind {
                    $(Kind::$m($d x) => $d body,)*
                }
            };
        }

        impl Kind {
            /// The method registered as `name`, made with `params`; `None` for an unknown name.
            fn named(name: &str, params: ImplicitParams) -> Option<Self> {
                $(
                    if name == <$m as Method>::INFO.name {
                        let make: fn(ImplicitParams) -> $m = $make;
                        return Some(Self::$m(make(params)));
                    }
                )*
                None
            }

            /// A fresh instance of the same method when it is local ([`Info::local`]).
            fn fresh_local(&self) -> Option<Self> {
                match self {
                    $(Self::$m(_) => <$m as Method>::INFO.local.then(|| {
                        let make: fn(ImplicitParams) -> $m = $make;
                        Self::$m(make(ImplicitParams::default()))
                    }),)*
                }
            }
        }
    };
}

registry! {$
    ExplicitEuler: |_| ExplicitEuler,
    SymplecticEuler: |_| SymplecticEuler,
    SymplecticEulerX: |_| SymplecticEulerX,
    SymplecticEulerAlternating: |_| SymplecticEulerAlternating::default(),
    Verlet: |_| Verlet::default(),
    VelocityVerlet: |_| VelocityVerlet::default(),
    Leapfrog: |_| Leapfrog::default(),
    Midpoint: |_| Midpoint::default(),
    Heun: |_| Heun::default(),
    Rk4: |_| Rk4::default(),
    BackwardEuler: BackwardEuler::with_params,
    PredictorCorrector: |_| PredictorCorrector::default(),
    ImplicitMidpoint: ImplicitMidpoint::with_params,
    Yoshida4: |_| Yoshida4::default(),
    LinearlyImplicitEuler: LinearlyImplicitEuler::with_params,
}

/// The registry names, in order.
pub fn names() -> impl Iterator<Item = &'static str> {
    INFOS.iter().map(|i| i.name)
}

/// The [`Info`] of a method by name.
///
/// # Errors
/// [`Error::UnknownName`] listing the valid names.
pub fn info(name: &str) -> Result<&'static Info> {
    INFOS.iter().find(|i| i.name == name).ok_or_else(|| Error::unknown("method", name, names()))
}

/// Any integrator, dispatched by `match` (closed dispatch on the hot path), with the
/// bookkeeping every method shares: validation of `dt`, rollback of a step that fails or
/// produces a non-finite value.
#[derive(Debug, Clone)]
pub struct Integrator {
    kind: Kind,
    checkpoint: Checkpoint,
}

/// Work generic over the concrete method, for [`Integrator::visit`].
pub(crate) trait Visit {
    /// What the work gives.
    type Out;
    /// The work on method `m`.
    fn visit<M: Method + Clone + Send + Sync>(self, m: &mut M) -> Self::Out;
}

use crate::limits::first_runaway as first_non_finite;
pub use crate::limits::RUNAWAY;

/// Whether the method `info` applies to `sys` (see [`Integrator::applies`]).
///
/// # Errors
/// As [`Integrator::applies`].
pub fn applies<S: System + ?Sized>(info: &Info, sys: &S) -> Result<()> {
    applies_to(info, sys.split().is_some(), sys.vector_positions())
}

/// Whether the method `info` applies to a system with (`split`) or without a split view,
/// whose positions are or are not vectors.
///
/// # Errors
/// As [`Integrator::applies`].
pub(crate) fn applies_to(info: &Info, split: bool, vector_positions: bool) -> Result<()> {
    if info.split && !split {
        return Err(split_only(info));
    }
    if info.vector_positions && !vector_positions {
        return Err(vectors_only(info));
    }
    Ok(())
}

impl Integrator {
    /// The integrator registered as `name`, with default settings.
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the valid names.
    pub fn new(name: &str) -> Result<Self> {
        Self::with_params(name, ImplicitParams::default())
    }

    /// The integrator registered as `name`; `params` set the implicit methods' Newton
    /// iteration.
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the valid names; [`Error::InvalidValue`] for a bad
    /// `tol`, `max_iter`, `cg_tol`, `cg_max_iter` or `energy_halvings`.
    pub fn with_params(name: &str, params: ImplicitParams) -> Result<Self> {
        crate::error::positive("tol", params.tol)?;
        if params.max_iter == 0 {
            return Err(Error::invalid("max_iter", 0, "at least 1"));
        }
        crate::error::positive("cg_tol", params.cg.tol)?;
        if params.cg.max_iter == 0 {
            return Err(Error::invalid("cg_max_iter", 0, "at least 1"));
        }
        if params.energy_halvings > super::MAX_ENERGY_HALVINGS {
            let most = format!("at most {}", super::MAX_ENERGY_HALVINGS);
            return Err(Error::invalid("energy_halvings", params.energy_halvings, most));
        }
        let kind = Kind::named(name, params).ok_or_else(|| Error::unknown("method", name, names()))?;
        Ok(Self { kind, checkpoint: Checkpoint::default() })
    }

    /// What this integrator is.
    #[must_use]
    pub fn info(&self) -> &'static Info {
        fn of<M: Method>(_: &M) -> &'static Info {
            &M::INFO
        }
        dispatch!(&self.kind, m => of(m))
    }

    /// A fresh instance of this method when its step is *local* ([`Info::local`]): element by
    /// element over particles (no sum across them, no solve of the whole state) and with no
    /// memory from step to step, so running it on any part of the particles at a time gives
    /// bitwise what running it on all of them gives. `None` for Verlet and leapfrog (memory),
    /// the alternating symplectic Euler (a flag that flips per step) and the implicit methods
    /// (one Newton solve of the whole state). The fused particle kernels run these.
    #[must_use]
    pub fn fresh_local(&self) -> Option<Self> {
        let kind = self.kind.fresh_local()?;
        Some(Self { kind, checkpoint: Checkpoint::default() })
    }

    /// Runs `v` on the concrete method: a kernel dispatches once and then calls the
    /// method's recipe statically (inlined), tile after tile.
    pub(crate) fn visit<V: Visit>(&mut self, v: V) -> V::Out {
        dispatch!(&mut self.kind, m => v.visit(m))
    }

    /// Forgets internal state (Verlet's previous position, leapfrog's half-step velocity):
    /// call it after moving the system by hand.
    pub fn reset(&mut self) {
        dispatch!(&mut self.kind, m => m.reset());
    }

    /// The method's internal state (Verlet's previous position, ...) for a snapshot.
    #[must_use]
    pub fn memory(&self) -> Vec<f64> {
        let mut out = Vec::new();
        dispatch!(&self.kind, m => m.memory(&mut out));
        out
    }

    /// How many leading entries of [`Integrator::memory`] are flags and settings; the rest
    /// is a vector of the state's kind (see [`Method::MEMORY_FLAGS`]).
    #[must_use]
    pub fn memory_flags(&self) -> usize {
        fn of<M: Method>(_: &M) -> usize {
            M::MEMORY_FLAGS
        }
        dispatch!(&self.kind, m => of(m))
    }

    /// Whether the method's memory holds a vector of the state's kind (Verlet's previous
    /// positions, leapfrog's half-step velocities; see [`Method::carries`]), without
    /// building the memory.
    #[must_use]
    pub fn carries(&self) -> bool {
        dispatch!(&self.kind, m => m.carries())
    }

    /// Tells the method that a stage outside it changed the velocities at `at..` from
    /// `before` to `v` (positions `x`, step `h`), so it brings its memory into line (see
    /// [`Method::velocities_changed`]).
    pub(crate) fn velocities_changed(&mut self, at: usize, x: &[f64], v: &[f64], before: &[f64], h: f64) {
        dispatch!(&mut self.kind, m => m.velocities_changed(at, x, v, before, h));
    }

    /// Restores what [`Integrator::memory`] returned for a state of the given sizes.
    ///
    /// # Errors
    /// [`Error::Corrupt`] when `memory` does not fit this method and state size.
    pub fn recall(&mut self, memory: &[f64], sizes: Sizes) -> Result<()> {
        if dispatch!(&mut self.kind, m => m.recall(memory, sizes)) {
            Ok(())
        } else {
            Err(Error::Corrupt {
                reason: format!("integrator memory does not fit method '{}'", self.info().name),
            })
        }
    }

    /// Advances a second-order system's `state` by `dt` seconds.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for `dt` not finite and > 0; [`Error::Diverged`] when the step
    /// produced a non-finite value and [`Error::NotConverged`] when an implicit solve failed:
    /// in both cases `state` is as it was before the step.
    pub fn step<S: SecondOrder + ?Sized>(&mut self, sys: &mut S, state: &mut State, dt: f64) -> Result<()> {
        self.step_logged(sys, state, dt, None)
    }

    /// [`Integrator::step`] that also records the intermediate evaluation points in `log`.
    ///
    /// # Errors
    /// As [`Integrator::step`].
    pub fn step_logged<S: SecondOrder + ?Sized>(
        &mut self,
        sys: &mut S,
        state: &mut State,
        dt: f64,
        log: Log<'_>,
    ) -> Result<()> {
        self.step_system(&mut Second(sys), state, dt, log, Layout::Second)
    }

    /// Advances a first-order flow's `state` by `dt` seconds.
    ///
    /// # Errors
    /// As [`Integrator::step`], and [`Error::Unsupported`] for the split methods.
    pub fn step_flow<F: FirstOrder + ?Sized>(
        &mut self,
        sys: &mut F,
        state: &mut State,
        dt: f64,
    ) -> Result<()> {
        self.step_system(&mut First(sys), state, dt, None, Layout::First)
    }

    /// One checked step of any system: validate `dt`, checkpoint, advance, check, and count
    /// the step or roll it back.
    fn step_system<S: System + ?Sized>(
        &mut self,
        sys: &mut S,
        state: &mut State,
        dt: f64,
        log: Log<'_>,
        layout: Layout,
    ) -> Result<()> {
        crate::error::positive("dt", dt)?;
        let mut checkpoint = std::mem::take(&mut self.checkpoint);
        checkpoint.save(state, self, layout);
        let r = self.advance(sys, state, dt, log).and_then(|()| self.check(state, layout));
        let r = self.finish(state, dt, r, &checkpoint, layout);
        self.checkpoint = checkpoint;
        r
    }

    /// What the latest step's implicit solve did (Newton and conjugate-gradient iterations,
    /// the final residual, dense or sparse); `None` for an explicit method.
    #[must_use]
    pub fn solve_stats(&self) -> Option<super::SolveStats> {
        dispatch!(&self.kind, m => m.solve_stats())
    }

    /// Whether this method applies to `sys`.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a split method on a system without positions and velocities
    /// (a first-order flow), or a method that does arithmetic on positions (Verlet) where
    /// positions are not vectors (orientations).
    pub fn applies<S: System + ?Sized>(&self, sys: &S) -> Result<()> {
        applies(self.info(), sys)
    }

    /// Runs the method once: `state.y` and `state.f` move to the end of the step (and onto
    /// the state space, by the system's `project`) and evaluations are counted, nothing else
    /// (no validation of `h`, no check, no rollback, time and step count untouched). The
    /// building block of a staged step: the caller checkpoints, checks and finishes (see
    /// [`Checkpoint`]).
    ///
    /// # Errors
    /// As [`Integrator::applies`] (nothing moved); [`Error::NotConverged`] when an implicit
    /// solve failed (the state is then partly moved: restore the checkpoint).
    pub fn advance<S: System + ?Sized>(
        &mut self,
        sys: &mut S,
        state: &mut State,
        h: f64,
        log: Log<'_>,
    ) -> Result<()> {
        self.applies(sys)?;
        let State { t, y, f, evals, .. } = state;
        let mut step = Step::new(sys, *t, h, y, f, evals, log);
        dispatch!(&mut self.kind, m => m.step(&mut step))?;
        if sys.project(y) {
            *evals += 1;
            sys.deriv(*t + h, y, f);
        }
        Ok(())
    }

    /// [`Error::Diverged`] when the state or its derivative holds a NaN, an infinity or a
    /// value past [`RUNAWAY`].
    ///
    /// # Errors
    /// As said.
    pub fn check(&self, state: &State, layout: Layout) -> Result<()> {
        // With bodies, `dX` is a function of `y` that no split method reads (a call leaves it
        // out, see `World::run`); a flow method's next stage carries a bad one into `y`.
        let skip = match layout {
            Layout::Mixed { x } => x,
            _ => layout.skip(state),
        };
        match first_non_finite(&state.y).or_else(|| first_non_finite(&state.f[skip..]).map(|i| i + skip)) {
            None => Ok(()),
            Some(i) => Err(Error::Diverged {
                method: self.info().name.into(),
                step: state.steps,
                t: state.t,
                index: i % state.y.len(),
                particle: None,
                body: None,
                solid: None,
            }),
        }
    }

    /// Counts a good step, or rolls a failed one back to `checkpoint`.
    fn finish(
        &mut self,
        state: &mut State,
        dt: f64,
        r: Result<()>,
        checkpoint: &Checkpoint,
        layout: Layout,
    ) -> Result<()> {
        match r {
            Ok(()) => {
                state.steps += 1;
                // t advances by repeated addition here; the World keeps t = t0 + k dt.
                state.t += dt;
                Ok(())
            }
            Err(e) => {
                checkpoint.restore(state, self, layout);
                Err(e)
            }
        }
    }
}

/// What a state's derivative holds: `f = [v; a]` of a second-order system (its first half a
/// copy of `v`, part of `y`) or the plain derivative of a first-order flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// `y = [x; v]`, `f = [v; a]`.
    Second,
    /// `y` and `f = y'`.
    First,
    /// `y = [X; V]` with `X` of length `x`, `f = [dX; A]` (no part of `f` a copy of `y`:
    /// particles with rigid bodies).
    Mixed {
        /// Length of `X`.
        x: usize,
    },
}

impl Layout {
    /// The sizes of the positions and velocities of a state of length `n`.
    #[must_use]
    pub fn sizes(self, n: usize) -> Sizes {
        match self {
            Self::Second => Sizes { x: n / 2, v: n / 2 },
            Self::First => Sizes { x: n, v: 0 },
            Self::Mixed { x } => Sizes { x, v: n - x },
        }
    }

    /// How much of `f` is a copy of `y` (and need not be kept or checked).
    #[must_use]
    pub fn skip(self, state: &State) -> usize {
        match self {
            Self::Second => state.y.len() / 2,
            Self::First | Self::Mixed { .. } => 0,
        }
    }
}

/// The state before a step and the method's memory, for a bitwise rollback: the one place
/// a failed step is undone, by the standalone [`Integrator::step`] and by the world's
/// staged step alike.
#[derive(Debug, Clone, Default)]
pub struct Checkpoint {
    y: Vec<f64>,
    f: Vec<f64>,
    memory: Vec<f64>,
}

impl Checkpoint {
    /// Keeps `state` (`y` and the part of `f` that is not a copy of `y`) and the memory of
    /// `integrator`, reusing the buffers.
    pub fn save(&mut self, state: &State, integrator: &Integrator, layout: Layout) {
        let skip = layout.skip(state);
        scratch(&mut self.y, state.y.len()).copy_from_slice(&state.y);
        scratch(&mut self.f, state.f.len() - skip).copy_from_slice(&state.f[skip..]);
        self.memory.clear();
        dispatch!(&integrator.kind, m => m.memory(&mut self.memory));
    }

    /// Puts back what [`Checkpoint::save`] kept, bitwise.
    pub fn restore(&self, state: &mut State, integrator: &mut Integrator, layout: Layout) {
        let skip = layout.skip(state);
        state.y.copy_from_slice(&self.y);
        state.f[skip..].copy_from_slice(&self.f);
        let n = state.y.len() - skip;
        state.f[..skip].copy_from_slice(&state.y[n..]);
        let restored =
            dispatch!(&mut integrator.kind, m => m.recall(&self.memory, layout.sizes(state.y.len())));
        debug_assert!(restored, "a method's own memory is always recallable");
        if !restored {
            integrator.reset();
        }
    }
}
