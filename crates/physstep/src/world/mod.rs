//! The world: particles, forces, an integrator and the fixed-timestep clock.
//!
//! State is structure of arrays on flat slices: `x`, `v` and `a` of length `n * dim`
//! (particle `p`, axis `k` at `p * dim + k`), kept apart from the per-particle parameters
//! (mass, inverse mass). [`World::step`] reads as its phases: integrate (which evaluates the
//! forces as often as the method needs), then diagnostics (a non-finite value rolls the step
//! back and is reported).

use crate::clock::{Clock, ClockParams, FramePlan, LoopMode};
use crate::dynamics::SecondOrder;
use crate::error::{all_finite, Error, Result};
use crate::flows::{Flow, FlowModel};
use crate::integrators::registry::{Layout, State};
use crate::integrators::{ImplicitParams, Integrator};
use rollback::Epoch;

mod awake;
mod balls;
mod bodies;
mod constraints;
mod flat;
mod ids;
mod interpolate;
mod kernel;
mod model;
mod particles;
mod parts;
mod removal;
mod rollback;
mod rules;
mod small;
mod snapshot;
mod solids;
mod state;
mod step;
mod tiles;

pub use crate::simd::set_vector_paths;
pub use bodies::BodyParams;
pub use ids::{BodyForceId, BodyId, BodySpringId, ConstraintId, ParticleId};
pub(crate) use kernel::Row;
pub use model::Model;
pub use removal::Removed;
pub use rules::ParticleBatch;
pub use solids::Contacts;

/// How to build a [`World`].
#[derive(Debug, Clone, PartialEq)]
pub struct WorldParams {
    /// Spatial dimensions, 1 to 3.
    pub dim: usize,
    /// Registry name of the integrator.
    pub method: String,
    /// Fixed step, s.
    pub dt: f64,
    /// The loop variant of [`World::advance`].
    pub mode: LoopMode,
    /// At most this many steps per frame (spiral-of-death guard).
    pub max_steps_per_frame: u32,
    /// Frame times are clamped to this, s.
    pub max_frame_time: f64,
    /// Newton settings of the implicit methods.
    pub implicit: ImplicitParams,
}

impl Default for WorldParams {
    fn default() -> Self {
        let c = ClockParams::default();
        Self {
            dim: 2,
            method: "symplectic-euler".into(),
            dt: c.dt,
            mode: c.mode,
            max_steps_per_frame: c.max_steps_per_frame,
            max_frame_time: c.max_frame_time,
            implicit: ImplicitParams::default(),
        }
    }
}

/// The largest finite mass, kg: momenta `m v` of any state (|v| <= 1e100) stay finite.
pub const MAX_MASS: f64 = 1e100;

/// A small mass whose inverse is finite, kg (the true limit is about 5.6e-309: any mass with
/// a finite `1/m` is accepted).
pub const MIN_MASS: f64 = 1e-300;

/// What one call of [`World::advance`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The clock's plan: steps, their dt, time clamped and dropped.
    pub plan: FramePlan,
    /// Render interpolation factor after the frame, in [0, 1).
    pub alpha: f64,
}

/// Particles, forces, an integrator and a fixed-timestep clock.
#[derive(Debug, Clone)]
pub struct World {
    model: Model,
    integrator: Integrator,
    state: State,
    clock: Clock,
    /// Positions before the latest step, for render interpolation.
    prev_x: Vec<f64>,
    /// What `state.f` holds against `state.y`.
    derivative: Derivative,
    /// What a failed step goes back to (kept by the call or by each step).
    rollback: rollback::Rollback,
    /// Time and step count at the latest change of dt.
    epoch: Epoch,
    /// Newton settings for implicit methods, kept across [`World::set_method`].
    implicit: ImplicitParams,
    /// A first-order flow, when the world is one (then it has no particles and `y` is the
    /// flow's state).
    flow: Option<FlowModel>,
    /// Rigid bodies (their state follows the particles' in `y`).
    bodies: crate::rigid::body::Bodies,
    /// Each body as it was added (what a scene file exports), apart from the bodies' data
    /// the step reads.
    body_params: Vec<BodyParams>,
    /// Scratch: spring loads on bodies during an evaluation.
    body_loads: Vec<(glam::DVec3, glam::DVec3)>,
    /// Body orientations before the latest step of a frame, for render interpolation.
    prev_q: Vec<[f64; 4]>,
    /// Solid positions then orientations before the latest step of a frame, for render
    /// interpolation (`interpolate.rs`).
    prev_solids: Vec<f64>,
    /// Position constraints on the particles (the Relax stage).
    constraints: crate::constraints::Constraints,
    /// Balls (particles with a radius), walls and the Collide stage's scratch.
    balls: crate::collide::Balls,
    /// Solids (rigid bodies with shapes that touch), their contacts and the contact solver
    /// (the Contact stage).
    solids: solids::SolidSet,
    /// The stable ids of the particles, bodies and constraints, parallel to their rows
    /// (`ids.rs`).
    ids: ids::EntityIds,
}

/// What the derivative `state.f` holds against the state `state.y`: the one cache of a
/// world's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Derivative {
    /// `f = deriv(y)`, evaluated, counted and checked.
    #[default]
    Current,
    /// The state, a force or a load changed by hand: `f` is evaluated, counted and checked
    /// before it is next used.
    Stale,
    /// The fused kernel took the steps and checked the accelerations but did not store them:
    /// computed again on request, not counted (the kernel counted them).
    Unstored,
    /// The split loop left the bodies' rates `dX` out of `f` (no split method reads them):
    /// computed from the state on request.
    RatesOwed,
    /// A step from the stored derivative (`Integrate::Given`: particles only) left the
    /// velocity half of `f`, a copy of `v`, unwritten (no such step reads it): copied from
    /// the state on request.
    VelocityOwed,
}

impl World {
    /// An empty world.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for `dim` outside 1..=3 or bad clock settings;
    /// [`Error::UnknownName`] for an unknown method.
    pub fn new(params: WorldParams) -> Result<Self> {
        if !(1..=3).contains(&params.dim) {
            return Err(Error::invalid("dim", params.dim, "1, 2 or 3"));
        }
        let integrator = Integrator::with_params(&params.method, params.implicit)?;
        let clock = Clock::new(ClockParams {
            dt: params.dt,
            mode: params.mode,
            max_steps_per_frame: params.max_steps_per_frame,
            max_frame_time: params.max_frame_time,
        })?;
        let model = Model { dim: params.dim, ..Model::default() };
        let state = State { t: 0.0, y: Vec::new(), f: Vec::new(), steps: 0, evals: 0 };
        Ok(Self {
            model,
            integrator,
            state,
            clock,
            prev_x: Vec::new(),
            derivative: Derivative::Current,
            rollback: rollback::Rollback::default(),
            epoch: Epoch::default(),
            implicit: params.implicit,
            flow: None,
            bodies: crate::rigid::body::Bodies { h: params.dt, ..Default::default() },
            body_params: Vec::new(),
            body_loads: Vec::new(),
            prev_q: Vec::new(),
            prev_solids: Vec::new(),
            constraints: crate::constraints::Constraints::default(),
            balls: crate::collide::Balls::default(),
            solids: solids::SolidSet::for_dim(params.dim),
            ids: ids::EntityIds::default(),
        })
    }

    /// A world whose part is the first-order flow `flow` from state `y0` (a strange
    /// attractor, the user's own ODE). Its positions are the flow's state (drawn as points
    /// of `dim = len(y0)` coordinates up to 3, else one coordinate each), its velocities the
    /// derivative; it has no particles and no energy.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a bad flow parameter, `y0` of the wrong length or not
    /// finite, or bad clock settings; [`Error::Unsupported`] for a split method.
    pub fn with_flow(flow: Flow, y0: &[f64], params: WorldParams) -> Result<Self> {
        flow.validate()?;
        if y0.len() != flow.len() {
            return Err(Error::invalid("len(y0)", y0.len(), format!("{}, the flow's length", flow.len())));
        }
        all_finite("y0", y0)?;
        let dim = if y0.len() <= 3 { y0.len() } else { 1 };
        let mut w = Self::new(WorldParams { dim, ..params })?;
        w.flow = Some(FlowModel::new(flow));
        w.refuse_method(w.integrator.info())?;
        w.state.y = y0.to_vec();
        w.state.f = vec![0.0; y0.len()];
        w.derivative = Derivative::Stale;
        Ok(w)
    }

    /// The flow, when the world is one.
    #[must_use]
    pub fn flow(&self) -> Option<&Flow> {
        self.flow.as_ref().map(|f| &f.flow)
    }

    /// Refuses a method that does not apply to the world's parts, when it is configured.
    fn refuse_method(&mut self, info: &crate::integrators::Info) -> Result<()> {
        use crate::dynamics::First;
        use crate::integrators::registry::applies;
        match self.flow.as_mut() {
            Some(flow) => applies(info, &First(flow)),
            None => applies(info, &self.parts()),
        }
    }

    /// Particles and bodies as the system methods see.
    fn parts(&mut self) -> parts::Parts<'_> {
        parts::of(&mut self.model, &self.bodies, &mut self.body_loads)
    }

    fn refuse_flow(&self, what: &str) -> Result<()> {
        match &self.flow {
            Some(f) => Err(Error::Unsupported {
                method: self.integrator.info().name.into(),
                reason: format!("cannot add {what} to a world that is the flow '{}'", f.flow.name()),
            }),
            None => Ok(()),
        }
    }

    /// The state's layout: `[x; v]` of particles, with bodies `[X; V]`, or a flow's `y`.
    fn layout(&self) -> Layout {
        if self.flow.is_some() {
            Layout::First
        } else if self.bodies.is_empty() {
            Layout::Second
        } else {
            Layout::Mixed { x: self.nx() }
        }
    }

    /// Length of the positions `X` of the state (particles' and bodies'); where the
    /// particles' velocities start.
    fn nx(&self) -> usize {
        self.model.len() + crate::rigid::body::X_LEN * self.bodies.len()
    }

    /// Coordinates of the positions (a flow's whole state).
    fn coords(&self) -> usize {
        if self.flow.is_some() {
            self.state.y.len()
        } else {
            self.model.len()
        }
    }

    /// Spatial dimensions.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.model.dim
    }

    /// Number of particles.
    #[must_use]
    pub fn len(&self) -> usize {
        self.model.mass.len()
    }

    /// Whether the world has no particles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.model.mass.is_empty()
    }

    /// Marks the derivative stale and restarts stateful integrators (the state was changed
    /// by hand).
    fn touch(&mut self) {
        self.derivative = Derivative::Stale;
        self.integrator.reset();
    }

    /// The integrator in use.
    #[must_use]
    pub fn integrator(&self) -> &Integrator {
        &self.integrator
    }

    /// Switches the integrator (implicit methods use the world's Newton settings).
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the valid names.
    pub fn set_method(&mut self, name: &str) -> Result<()> {
        let integrator = Integrator::with_params(name, self.implicit)?;
        self.refuse_method(integrator.info())?;
        self.integrator = integrator;
        Ok(())
    }

    /// The implicit methods' solver settings.
    #[must_use]
    pub fn implicit(&self) -> ImplicitParams {
        self.implicit
    }

    /// Sets the implicit methods' Newton and conjugate-gradient settings, and the size up to
    /// which they solve densely; the current method starts afresh with them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `tol`, `max_iter`, `cg_tol` or `cg_max_iter` (the world
    /// unchanged).
    pub fn set_implicit(&mut self, params: ImplicitParams) -> Result<()> {
        let integrator = Integrator::with_params(self.integrator.info().name, params)?;
        self.implicit = params;
        if integrator.info().implicit {
            self.integrator = integrator;
        }
        Ok(())
    }

    /// The fixed step, s.
    #[must_use]
    pub fn dt(&self) -> f64 {
        self.clock.params().dt
    }

    /// Changes the fixed step; stateful integrators handle the change as their docs say.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `dt`.
    pub fn set_dt(&mut self, dt: f64) -> Result<()> {
        self.clock.retime(dt)?;
        // The implicit gyroscopic form's Newton step is taken at the fixed step.
        self.bodies.h = dt;
        self.derivative = Derivative::Stale;
        Ok(())
    }
}
