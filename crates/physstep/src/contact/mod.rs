//! Solids: rigid bodies with shapes that touch, land, slide, stack and rest (docs/contact.md).
//!
//! A solid is a rigid body in the plane or in space ([`Space`]: [`Plane`], [`Space3`]) with a
//! collision [`Shape`], a [`Kind`] (dynamic, static, kinematic), friction and restitution.
//! Their step is the contact solver's: contacts found (a sweep-and-prune broad phase in a
//! fixed order, [`broad`], and parry's narrow phase, [`space`]), then the bodies advanced
//! and their contacts solved together by the solver chosen by name ([`solver`]; the default
//! is the soft step of Box2D v3: substeps of symplectic Euler with soft contact constraints,
//! warm starting and a relax pass).
//!
//! Why the solver integrates the solids itself: an impulse changes a velocity, and a contact
//! constraint holds only if the position update that follows uses the changed velocity; that
//! is symplectic Euler at each substep (velocity first, then position), which is why game
//! engines (Box2D, Rapier, Jolt) fix it. The world's method integrates everything else.

pub mod broad;
mod forces;
mod ids;
pub mod joint;
mod lanes;
mod params;
mod passes;
mod points;
mod remove;
mod settings;
mod shape;
mod sleep;
pub mod solver;
pub mod space;
mod toi;
mod xpbd;

pub use forces::SolidSpring;
pub use ids::{JointId, SolidForceId, SolidId, SolidSpringId};
pub use joint::{JointKind, JointParams, JOINT_KINDS};
pub use params::{Kind, SolidParams};
pub use remove::SolidMotion;
pub use settings::{Info, Schedule, Settings, SOLVERS};
pub use shape::Shape;
pub use sleep::SLEEP_SPEED;
pub use space::{Plane, Space, Space3, Swept, Touch, Vect};

use crate::error::{num, Error, Result};

/// One solid as the solver sees it: centre of mass and orientation, velocities, inverse mass
/// and inertia.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Body<S: Space> {
    /// Centre of mass, world, m.
    pub c: S::V,
    /// Orientation.
    pub q: S::Rot,
    /// Velocity of the centre of mass.
    pub v: S::V,
    /// Angular velocity.
    pub w: S::W,
    /// Inverse mass (0: static or kinematic).
    pub inv_mass: f64,
    /// Inverse inertia in the body's frame.
    pub inv_i_local: S::InvI,
    /// Inertia in the body's frame (zero for a solid that does not turn): kept so that the
    /// substeps' gyroscopic term does not invert it again and again.
    pub i_local: S::InvI,
    /// Centre of mass in the shape's frame.
    pub com: S::V,
    /// Dynamic, static or kinematic.
    pub kind: Kind,
    /// The shape's smallest extent (a box's smallest half extent, a ball's radius) and the
    /// radius about the centre of mass that holds it ([`Space::extents`]): what continuous
    /// collision measures a motion by.
    pub min_extent: f64,
    pub max_extent: f64,
    /// Swept by continuous collision against dynamic solids too ([`SolidParams::bullet`]).
    pub bullet: bool,
    /// Asleep (`sleep.rs`): out of the solver until something reaches its island.
    pub asleep: bool,
    /// How long it has been slow, s (awake; its island falls asleep when all of its solids
    /// have been slow for the sleep time).
    pub idle: f64,
    /// Its island's number while asleep (the island's lowest solid index).
    pub island: u32,
}

impl<S: Space> Body<S> {
    /// Where the shape's origin is.
    pub fn origin(&self) -> S::V {
        self.c - S::rotate(self.q, self.com)
    }
}

/// One contact point of the latest step, as [`Solids::contacts`] reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactReport<V> {
    /// The two solids (by index), `a < b`.
    pub pair: (usize, usize),
    /// The point (midway between the two surfaces), m.
    pub point: V,
    /// Unit normal from `a` to `b`.
    pub normal: V,
    /// Penetration depth, m (negative: apart, a speculative contact).
    pub depth: f64,
    /// Normal impulse of the step, N s.
    pub normal_impulse: f64,
    /// Size of the friction impulse of the step, N s.
    pub friction_impulse: f64,
}

/// The solids of a world, their contacts and the solver that steps them.
#[derive(Debug, Clone)]
pub struct Solids<S: Space> {
    pub(crate) bodies: Vec<Body<S>>,
    pub(crate) shapes: Vec<S::Shape>,
    pub(crate) params: Vec<SolidParams>,
    /// The solver and its settings.
    pub settings: Settings,
    pub(crate) solver: points::State<S>,
    pub(crate) joints: Vec<joint::Joint<S>>,
    pub(crate) joint_params: Vec<JointParams>,
    /// Pairs of solids a joint keeps from colliding, `(low, high)`, sorted.
    pub(crate) no_collide: Vec<(u32, u32)>,
    /// Drag, springs and loads ([`forces`]).
    pub(crate) forces: forces::Forces<S>,
    /// The ids of the solids, joints, springs and user forces, beside their rows ([`ids`]).
    pub(crate) ids: [crate::ids::Ids; 4],
    /// What the step in progress changes, as it was before it ([`Solids::step`] goes back to
    /// it when the step runs away); scratch, its buffers reused from step to step.
    before: Before<S>,
    /// Sleeping's scratch (`sleep.rs`).
    sleep: sleep::Scratch<S>,
}

/// The solids' motion, the solver's memory ([`points::State::save`]) and the joints before a
/// step.
#[derive(Debug)]
struct Before<S: Space> {
    bodies: Vec<Body<S>>,
    solver: points::State<S>,
    joints: Vec<joint::Joint<S>>,
}

impl<S: Space> Default for Before<S> {
    fn default() -> Self {
        Self { bodies: Vec::new(), solver: points::State::default(), joints: Vec::new() }
    }
}

/// Scratch: a copy starts with empty buffers.
impl<S: Space> Clone for Before<S> {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// Which of [`Solids::ids`].
pub(crate) const SOLID: usize = 0;
pub(crate) const JOINT: usize = 1;
pub(crate) const SPRING: usize = 2;
pub(crate) const FORCE: usize = 3;

impl<S: Space> Default for Solids<S> {
    fn default() -> Self {
        Self {
            bodies: Vec::new(),
            shapes: Vec::new(),
            params: Vec::new(),
            settings: Settings::default(),
            solver: points::State::default(),
            joints: Vec::new(),
            joint_params: Vec::new(),
            no_collide: Vec::new(),
            forces: forces::Forces::default(),
            ids: Default::default(),
            before: Before::default(),
            sleep: sleep::Scratch::default(),
        }
    }
}

fn finite(field: &str, v: &[f64]) -> Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(Error::invalid(format!("{field}[{i}]"), num(v[i]), "finite")),
        None => Ok(()),
    }
}

fn len(field: &str, v: &[f64], n: usize) -> Result<()> {
    if v.len() == n {
        Ok(())
    } else {
        Err(Error::invalid(format!("len({field})"), v.len(), format!("{n}")))
    }
}

impl<S: Space> Solids<S> {
    /// No solids, the default solver.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of solids.
    #[must_use]
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Each solid as it was added.
    #[must_use]
    pub fn params(&self) -> &[SolidParams] {
        &self.params
    }

    /// Checks a solid without adding it.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`position`, `density`, `friction`,
    /// `restitution`, `linear_damping`, `angular_damping`, `bullet`, `kind`, a size of the
    /// shape) and the value.
    pub fn check(p: &SolidParams) -> Result<()> {
        let (d, r) = (S::DIM, S::ROT);
        let a = if d == 3 { 3 } else { 1 };
        len("position", &p.position, d)?;
        finite("position", &p.position)?;
        len("orientation", &p.orientation, r)?;
        finite("orientation", &p.orientation)?;
        if r == 4 && p.orientation.iter().map(|x| x * x).sum::<f64>() == 0.0 {
            return Err(Error::invalid("orientation", "[0, 0, 0, 0]", "a non-zero quaternion"));
        }
        len("velocity", &p.velocity, d)?;
        finite("velocity", &p.velocity)?;
        len("angular_velocity", &p.angular_velocity, a)?;
        finite("angular_velocity", &p.angular_velocity)?;
        if !(p.density.is_finite() && p.density > 0.0) {
            return Err(Error::invalid("density", num(p.density), "finite and > 0"));
        }
        if !(p.friction.is_finite() && p.friction >= 0.0) {
            return Err(Error::invalid("friction", num(p.friction), "finite and >= 0"));
        }
        if !(0.0..=1.0).contains(&p.restitution) {
            return Err(Error::invalid("restitution", num(p.restitution), "in [0, 1]"));
        }
        forces::check_damping("linear_damping", p.linear_damping)?;
        forces::check_damping("angular_damping", p.angular_damping)?;
        if p.bullet && p.kind != Kind::Dynamic {
            return Err(Error::invalid("bullet", "true", format!("false for a {} solid", p.kind.name())));
        }
        if p.kind == Kind::Dynamic && p.shape.is_massless() {
            return Err(Error::invalid(
                "kind",
                "dynamic",
                format!("static or kinematic for a {} (it encloses no volume)", p.shape.name()),
            ));
        }
        if p.kind == Kind::Static
            && (p.velocity.iter().any(|x| *x != 0.0) || p.angular_velocity.iter().any(|x| *x != 0.0))
        {
            return Err(Error::invalid(
                "velocity",
                "non-zero",
                "zero for a static solid (make it kinematic to move it)",
            ));
        }
        p.shape.check(d)
    }

    /// Adds a solid; returns its index.
    ///
    /// # Errors
    /// As [`Solids::check`]; the solids are unchanged.
    pub fn add(&mut self, p: SolidParams) -> Result<usize> {
        Self::check(&p)?;
        let shape = S::build(&p.shape)?;
        let (mass, com, inv_i) = S::mass_properties(&shape, p.density);
        let dynamic = p.kind == Kind::Dynamic;
        if dynamic && !(mass.is_finite() && mass > 0.0) {
            return Err(Error::invalid(
                "density",
                num(p.density),
                "a density giving the shape a finite mass",
            ));
        }
        let q = S::read_rot(&p.orientation);
        let origin = S::V::read(&p.position);
        let (min_extent, max_extent) = S::extents(&shape, com);
        let body = Body::<S> {
            c: origin + S::rotate(q, com),
            q,
            v: S::V::read(&p.velocity),
            w: S::W::read(&p.angular_velocity),
            inv_mass: if dynamic { 1.0 / mass } else { 0.0 },
            inv_i_local: if dynamic { inv_i } else { S::no_inertia() },
            i_local: if dynamic { S::inertia(inv_i) } else { S::no_inertia() },
            com,
            kind: p.kind,
            min_extent,
            max_extent,
            bullet: p.bullet,
            asleep: false,
            idle: 0.0,
            island: 0,
        };
        self.bodies.push(body);
        self.shapes.push(shape);
        self.forces.push_solid(p.linear_damping, p.angular_damping);
        self.params.push(p);
        self.ids[SOLID].push(1);
        Ok(self.bodies.len() - 1)
    }

    /// Adds a joint between two solids (or a solid and the world); returns its index among
    /// the joints.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`a`, `b`, `anchor`, `axis`, a length, a
    /// limit, `hertz`, `max_motor`) and the value; the solids are unchanged.
    pub fn add_joint(&mut self, p: JointParams) -> Result<usize> {
        let j = joint::Joint::new(&p, &self.bodies)?;
        if let Some(pair) = j.no_collide(&p) {
            if let Err(k) = self.no_collide.binary_search(&pair) {
                self.no_collide.insert(k, pair);
            }
        }
        self.wake_ends(j.solids());
        self.joints.push(j);
        self.joint_params.push(p);
        self.ids[JOINT].push(1);
        Ok(self.joints.len() - 1)
    }

    /// Number of joints.
    #[must_use]
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Each joint as it was made.
    #[must_use]
    pub fn joint_params(&self) -> &[JointParams] {
        &self.joint_params
    }

    /// Each joint's position error now, m: how far apart its anchors are (ball, revolute,
    /// weld), off the axis (prismatic), or outside its lengths (distance).
    #[must_use]
    pub fn joint_errors(&self) -> Vec<f64> {
        self.joints.iter().map(|j| j.error(&self.bodies)).collect()
    }

    /// Adds a spring between a point of solid `a` and a point of solid `b` (or a fixed point
    /// of the world, `b` = `None`); returns its index among the solid springs. Its rest
    /// length, when not given, is the distance between the two ends now.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`a`, `b` a missing solid or `a` itself,
    /// `point_a`, `point_b` of the wrong length or not finite, `stiffness`, `damping`,
    /// `rest_length` negative or not finite) and the value; the solids are unchanged.
    pub fn add_spring(&mut self, p: SolidSpring) -> Result<usize> {
        let k = self.forces.add_spring(p, &self.bodies)?;
        self.wake_ends(self.forces.springs[k].solids());
        self.ids[SPRING].push(1);
        Ok(k)
    }

    /// Each solid spring as it was made (its rest length resolved).
    #[must_use]
    pub fn springs(&self) -> &[SolidSpring] {
        &self.forces.spring_params
    }

    /// Each solid spring's two ends now, world coordinates, flat (`DIM` numbers each: the end
    /// on `a`, then the end on `b` or the anchor).
    #[must_use]
    pub fn spring_ends(&self) -> Vec<f64> {
        self.forces.ends(&self.bodies)
    }

    /// Potential energy of the solid springs now, J.
    #[must_use]
    pub fn spring_energy(&self) -> f64 {
        self.forces.potential(&self.bodies)
    }

    /// Potential energy of the dynamic solids in the uniform gravity `g`, J (0 at the
    /// origin).
    #[must_use]
    pub fn gravity_energy(&self, g: S::V) -> f64 {
        self.bodies.iter().filter(|b| b.inv_mass > 0.0).map(|b| -g.dot(b.c) / b.inv_mass).sum()
    }

    /// Applies `force` (N, world frame) to solid `i` for the next step, at the world point
    /// `point` (its centre of mass when `None`: then no torque), and `torque` (N m; one number in
    /// 2D). Loads add up until a step takes them; they are held constant over its substeps.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid`, `force`, `point` or `torque` (a wrong length, not
    /// finite, or beyond 1e12 in size); the solids are unchanged.
    pub fn apply(&mut self, i: usize, force: &[f64], point: Option<&[f64]>, torque: &[f64]) -> Result<()> {
        forces::solid_index("solid", i, self.len())?;
        let a = if S::DIM == 3 { 3 } else { 1 };
        let check = |field: &str, v: &[f64], n: usize| -> Result<()> {
            len(field, v, n)?;
            match v.iter().position(|x| !(x.is_finite() && x.abs() <= crate::limits::PARAM_MAX)) {
                Some(k) => {
                    Err(Error::invalid(format!("{field}[{k}]"), num(v[k]), "finite (at most 1e12 in size)"))
                }
                None => Ok(()),
            }
        };
        check("force", force, S::DIM)?;
        check("torque", torque, a)?;
        let arm = match point {
            Some(at) => {
                check("point", at, S::DIM)?;
                S::V::read(at) - self.bodies[i].c
            }
            None => S::V::default(),
        };
        let n = self.len();
        self.forces.apply(n, i, S::V::read(force), arm, S::W::read(torque));
        self.wake(i);
        Ok(())
    }

    /// Whether a step of these solids depends on nothing but their state (no user force, no
    /// load applied by hand waiting).
    #[must_use]
    pub(crate) fn replayable(&self) -> bool {
        self.forces.replayable()
    }

    /// Forgets the loads applied by hand (a step took them).
    pub(crate) fn clear_applied(&mut self) {
        self.forces.clear_applied();
    }

    /// Adds a user force acting at `point` of solid `solid` (in its frame, the frame its
    /// shape is given in, m): the generator sees that point as one particle (its world
    /// position and velocity, `DIM` numbers each) and returns the force on it, which also
    /// turns the solid. Evaluated once a step, at its start; the substeps hold it. Returns
    /// its index among the solid forces.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid` or `point`; the solids are unchanged.
    pub fn add_force(
        &mut self,
        solid: usize,
        point: &[f64],
        generator: std::sync::Arc<dyn crate::forces::ForceGenerator>,
    ) -> Result<usize> {
        let k = self.forces.add_user(solid, point, generator, &self.bodies)?;
        self.ids[FORCE].push(1);
        Ok(k)
    }

    /// Number of user forces on the solids.
    #[must_use]
    pub fn force_count(&self) -> usize {
        self.forces.users.len()
    }

    /// The user forces' potential energy now, J; `None` when one of them has none.
    #[must_use]
    pub fn user_potential(&self) -> Option<f64> {
        self.forces.user_potential(&self.bodies)
    }

    /// This step's loads at time `t`: those applied by hand and the user forces'.
    ///
    /// # Errors
    /// [`Error::Force`] naming a user force that failed or gave a non-finite value.
    pub(crate) fn gather_loads(&mut self, t: f64) -> Result<()> {
        self.forces.gather(t, &self.bodies)
    }

    /// A fingerprint of the drag and springs, `None` without either (for the state hash).
    pub(crate) fn forces_fingerprint(&self) -> Option<u64> {
        self.forces.fingerprint()
    }

    /// Origins of the shapes, flat (`DIM` a solid).
    #[must_use]
    pub fn positions(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.len() * S::DIM);
        for b in &self.bodies {
            b.origin().write(&mut out);
        }
        out
    }

    /// Orientations, flat (the angle in 2D; w, x, y, z in 3D).
    #[must_use]
    pub fn orientations(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.len() * S::ROT);
        for b in &self.bodies {
            S::write_rot(b.q, &mut out);
        }
        out
    }

    /// Velocities of the centres of mass, flat.
    #[must_use]
    pub fn velocities(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.len() * S::DIM);
        for b in &self.bodies {
            b.v.write(&mut out);
        }
        out
    }

    /// Angular velocities, flat (one a solid in 2D, three in 3D).
    #[must_use]
    pub fn angular_velocities(&self) -> Vec<f64> {
        let mut out = Vec::new();
        for b in &self.bodies {
            b.w.write(&mut out);
        }
        out
    }

    /// Kinetic energy of the dynamic solids, J.
    #[must_use]
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|b| b.kind == Kind::Dynamic)
            .map(|b| {
                let i = S::world_inverse_inertia(b.q, b.inv_i_local);
                0.5 * b.v.dot(b.v) / b.inv_mass + 0.5 * S::spin_energy(i, b.w)
            })
            .sum()
    }

    /// The contact points of the latest step.
    #[must_use]
    pub fn contacts(&self) -> Vec<ContactReport<S::V>> {
        self.solver.report()
    }

    /// The deepest penetration among the latest step's contacts, m (0 without contacts).
    #[must_use]
    pub fn max_penetration(&self) -> f64 {
        self.solver.report().iter().map(|c| c.depth).fold(0.0, f64::max)
    }

    /// The passes over the contacts the latest step made, counted as they ran (solve, relax
    /// and position passes: `2 x substeps x iterations` for every solver; 0 before a step).
    #[must_use]
    pub fn contact_passes(&self) -> u32 {
        self.solver.passes
    }

    /// Advances the solids by `dt` under `gravity` (dynamic solids only), their drag, springs,
    /// user forces (evaluated at time 0: a standalone set of solids keeps no clock) and the
    /// loads applied by hand (which it then forgets, when it succeeds).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] for a bad `dt`; [`Error::Force`] for a user force that failed;
    /// [`Error::Diverged`] (naming the solid) when a value became non-finite or ran away, the
    /// solids then as before the step.
    pub fn step(&mut self, dt: f64, gravity: S::V) -> Result<()> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::invalid("dt", num(dt), "finite and > 0"));
        }
        self.gather_loads(0.0)?;
        let mut before = std::mem::take(&mut self.before);
        before.bodies.clone_from(&self.bodies);
        self.solver.save(&mut before.solver);
        before.joints.clone_from(&self.joints);
        self.advance(dt, gravity);
        self.forces.load.clear();
        if let Some(b) = self.runaway() {
            std::mem::swap(&mut self.bodies, &mut before.bodies);
            std::mem::swap(&mut self.joints, &mut before.joints);
            self.solver.restore(&before.solver);
            self.before = before;
            return Err(Error::Diverged {
                method: self.settings.solver.to_string(),
                step: 0,
                t: 0.0,
                index: b,
                particle: None,
                body: None,
                solid: Some(b),
            });
        }
        self.before = before;
        self.clear_applied();
        Ok(())
    }

    /// The contact solver's step of `dt` under `gravity` with this step's loads gathered:
    /// the sleeping islands something reaches woken and the others hidden from it, then the
    /// islands that came to rest put to sleep (`sleep.rs`; nothing of it while
    /// [`Settings::sleep_time`] is 0).
    pub(crate) fn advance(&mut self, dt: f64, gravity: S::V) {
        self.sleep_begin(dt, gravity);
        solver::step(self, dt, gravity);
        self.sleep_end(dt);
    }

    /// Copies into `into` what a step changes (motion, contacts, warm starts), reusing its
    /// buffers; the solids must be the same ones (a rollback of this world).
    pub(crate) fn save(&self, into: &mut Solids<S>) {
        if into.len() != self.len() {
            into.clone_from(self);
            return;
        }
        into.bodies.clone_from(&self.bodies);
        into.joints.clone_from(&self.joints);
        self.solver.save(&mut into.solver);
        into.settings.clone_from(&self.settings);
        into.sleep.gravity = self.sleep.gravity;
    }

    /// What a snapshot keeps of the solids: each one's centre of mass, orientation,
    /// velocity and angular velocity, then the warm starts (what the next step depends on),
    /// the joints' impulses, the ids once something was removed, and while sleeping is on
    /// each solid's sleep (asleep 0 or 1, idle time, island).
    pub(crate) fn block(&self) -> Vec<f64> {
        let mut out = vec![self.len() as f64];
        for b in &self.bodies {
            b.c.write(&mut out);
            S::write_rot(b.q, &mut out);
            b.v.write(&mut out);
            b.w.write(&mut out);
        }
        self.solver.write_warm(&mut out);
        if !self.joints.is_empty() {
            joint::write(&self.joints, &mut out);
        }
        // Once something was removed, the ids (a world with others is another world).
        if !self.ids_implicit() {
            self.write_ids(&mut out);
        }
        if self.settings.sleep_time > 0.0 {
            for b in &self.bodies {
                out.extend([f64::from(u8::from(b.asleep)), b.idle, f64::from(b.island)]);
            }
        }
        out
    }

    /// Puts back a [`Solids::block`], checked whole first.
    ///
    /// # Errors
    /// A message saying what does not fit (the count of solids, a length, a non-finite value).
    pub(crate) fn set_block(&mut self, data: &[f64]) -> std::result::Result<(), String> {
        let (d, r, a) = (S::DIM, S::ROT, if S::DIM == 3 { 3 } else { 1 });
        let per = 2 * d + r + a;
        let (data, sleep) = self.sleep_split(data)?;
        let n = data.first().copied().unwrap_or(-1.0);
        if n != self.len() as f64 {
            return Err(format!("the snapshot has {n} solids, this world {}", self.len()));
        }
        let bodies = data.get(1..1 + self.len() * per).ok_or("truncated solids")?;
        if let Some(i) = bodies.iter().position(|x| !x.is_finite()) {
            return Err(format!("solid state entry {i} is not finite"));
        }
        let rest = &data[1 + self.len() * per..];
        // The warm starts' length is in their first number; the joints' impulses follow.
        let warm_len = rest.first().map_or(0, |&c| {
            let w = 6 + 2 * d;
            if c >= 0.0 && c.fract() == 0.0 {
                (1 + c as usize * w).min(rest.len())
            } else {
                rest.len()
            }
        });
        let (rest, after) = rest.split_at(warm_len);
        // The joints' impulses (their count first), then the ids once something was removed.
        let joints_len = match after.first() {
            Some(&c) if !self.joints.is_empty() && c >= 0.0 && c.fract() == 0.0 => {
                (1 + c as usize * joint::Impulses::<S>::width()).min(after.len())
            }
            _ if self.joints.is_empty() => 0,
            _ => after.len(),
        };
        let (joints, ids) = after.split_at(joints_len);
        let impulses = if self.joints.is_empty() { Vec::new() } else { joint::read(&self.joints, joints)? };
        let mut own = Vec::new();
        if !self.ids_implicit() {
            self.write_ids(&mut own);
        }
        if ids.len() != own.len() || ids.iter().zip(&own).any(|(a, b)| a.to_bits() != b.to_bits()) {
            return Err(if ids.is_empty() || own.is_empty() {
                "the snapshot was taken of other solids, joints or springs than this world's (one of the two had some removed)".to_string()
            } else {
                "the snapshot was taken of other solids, joints or springs than this world's (their ids differ)".to_string()
            });
        }
        let warm = self.solver.read_warm(rest, self.len())?;
        for (b, c) in self.bodies.iter_mut().zip(bodies.chunks_exact(per)) {
            b.c = S::V::read(&c[..d]);
            b.q = S::read_rot_exact(&c[d..d + r]);
            b.v = S::V::read(&c[d + r..2 * d + r]);
            b.w = S::W::read(&c[2 * d + r..]);
        }
        self.solver.set_warm(warm);
        for (j, i) in self.joints.iter_mut().zip(impulses) {
            j.impulses = i;
        }
        for (b, s) in self.bodies.iter_mut().zip(sleep.chunks_exact(3)) {
            (b.asleep, b.idle, b.island) = (s[0] == 1.0, s[1], s[2] as u32);
        }
        Ok(())
    }

    /// The first solid whose state is non-finite or beyond 1e100.
    #[must_use]
    pub fn runaway(&self) -> Option<usize> {
        let mut buf = Vec::with_capacity(16);
        self.bodies.iter().position(|b| {
            buf.clear();
            b.c.write(&mut buf);
            b.v.write(&mut buf);
            b.w.write(&mut buf);
            S::write_rot(b.q, &mut buf);
            buf.iter().any(|x| !x.is_finite() || x.abs() > 1e100)
        })
    }
}
