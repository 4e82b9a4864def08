//! Solids of a [`World`]: rigid bodies with shapes that touch (see [`crate::contact`] and
//! docs/contact.md). A 2D world's solids live in the plane, a 3D world's in space; the
//! world's gravity pulls them; the Contact stage of the step advances them by the contact
//! solver (its own substeps of symplectic Euler) and checks them.

use super::step::StepContext;
use super::World;
use crate::contact::{
    ContactReport, JointId, JointParams, Plane, Settings, SolidForceId, SolidId, SolidMotion, SolidParams,
    SolidSpring, SolidSpringId, Solids, Space, Space3, Vect,
};
use crate::error::{Error, Result};
use crate::forces::Force;

/// The solids of a world of either dimension.
#[derive(Debug, Clone, Default)]
pub(crate) enum SolidSet {
    /// A 1D world's (none can be added).
    #[default]
    Empty,
    /// A 2D world's.
    Plane(Solids<Plane>),
    /// A 3D world's.
    Space(Solids<Space3>),
}

/// `$body` with `$s` the solids of whichever space, or `$none` without solids.
macro_rules! each {
    ($set:expr, $s:ident => $body:expr, $none:expr) => {
        match $set {
            SolidSet::Empty => $none,
            SolidSet::Plane($s) => $body,
            SolidSet::Space($s) => $body,
        }
    };
}

impl SolidSet {
    /// The empty set of a world of `dim` dimensions (none in 1D).
    pub(crate) fn for_dim(dim: usize) -> Self {
        match dim {
            2 => SolidSet::Plane(Solids::new()),
            3 => SolidSet::Space(Solids::new()),
            _ => SolidSet::Empty,
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        each!(self, s => s.is_empty(), true)
    }

    pub(crate) fn len(&self) -> usize {
        each!(self, s => s.len(), 0)
    }

    /// What a snapshot keeps of the solids (empty without solids).
    pub(crate) fn block(&self) -> Vec<f64> {
        if self.is_empty() {
            return Vec::new();
        }
        each!(self, s => s.block(), Vec::new())
    }

    /// Puts back a [`SolidSet::block`].
    ///
    /// # Errors
    /// What does not fit, in words.
    pub(crate) fn set_block(&mut self, data: &[f64]) -> std::result::Result<(), String> {
        each!(self, s => s.set_block(data), Err("this world has no solids".into()))
    }

    /// Keeps in `into` what a step changes (the solids' motion, their contacts and the warm
    /// starts), for a rollback.
    pub(crate) fn save(&self, into: &mut SolidSet) {
        match (self, &mut *into) {
            (SolidSet::Plane(a), SolidSet::Plane(b)) => a.save(b),
            (SolidSet::Space(a), SolidSet::Space(b)) => a.save(b),
            _ => into.clone_from(self),
        }
    }

    /// Whether a step of the solids depends on nothing but their state.
    pub(crate) fn replayable(&self) -> bool {
        each!(self, s => s.replayable(), true)
    }

    /// A fingerprint of the solids' drag and springs, `None` without either.
    pub(crate) fn forces_fingerprint(&self) -> Option<u64> {
        each!(self, s => s.forces_fingerprint(), None)
    }

    /// Forgets the loads applied by hand (a step took them).
    pub(crate) fn clear_applied(&mut self) {
        each!(self, s => s.clear_applied(), ());
    }

    /// Puts back what [`SolidSet::save`] kept.
    pub(crate) fn restore(&mut self, from: &SolidSet) {
        match (&mut *self, from) {
            (SolidSet::Plane(a), SolidSet::Plane(b)) => b.save(a),
            (SolidSet::Space(a), SolidSet::Space(b)) => b.save(a),
            _ => self.clone_from(from),
        }
    }
}

/// A solid's contact points as flat arrays (what [`World::contacts`] returns).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contacts {
    /// The two solids of each point, `a < b`.
    pub pairs: Vec<[usize; 2]>,
    /// The points, flat (`dim` a point), m.
    pub points: Vec<f64>,
    /// Unit normals from `a` to `b`, flat.
    pub normals: Vec<f64>,
    /// Penetration depths, m (negative: a speculative contact, not yet touching).
    pub depths: Vec<f64>,
    /// Normal impulses of the latest step, N s.
    pub normal_impulses: Vec<f64>,
    /// Sizes of the friction impulses of the latest step, N s.
    pub friction_impulses: Vec<f64>,
}

fn flatten<V: Vect>(reports: &[ContactReport<V>]) -> Contacts {
    let mut c = Contacts::default();
    for r in reports {
        c.pairs.push([r.pair.0, r.pair.1]);
        r.point.write(&mut c.points);
        r.normal.write(&mut c.normals);
        c.depths.push(r.depth);
        c.normal_impulses.push(r.normal_impulse);
        c.friction_impulses.push(r.friction_impulse);
    }
    c
}

fn gravity_of<S: Space>(m: &super::Model) -> S::V {
    let mut g = [0.0; 3];
    for f in m.forces().iter() {
        if let Force::Gravity { g: a } = f {
            for (gk, ak) in g.iter_mut().zip(a) {
                *gk += ak;
            }
        }
    }
    S::V::read(&g[..S::DIM])
}

/// Solids: adding, reading, the contact solver's settings, and the Contact stage.
impl World {
    /// Adds a solid (a rigid body with a shape that collides with the other solids); returns
    /// its index among the solids. A 2D world's solids move in the plane (an angle, a scalar
    /// inertia), a 3D world's in space.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`position`, `orientation`, `density`,
    /// `friction`, `restitution`, `kind`, a size of the shape) and the value, or `dim` for a
    /// 1D world or a world that is a flow; the world is unchanged.
    pub fn add_solid(&mut self, params: SolidParams) -> Result<usize> {
        if self.flow.is_some() || self.dim() == 1 {
            return Err(Error::invalid("dim", self.dim(), "2 or 3 (solids move in the plane or in space)"));
        }
        let i = each!(&mut self.solids, s => s.add(params), Err(Error::invalid("dim", 1, "2 or 3")))?;
        self.derivative = super::Derivative::Stale;
        Ok(i)
    }

    /// Adds a joint between two solids, or between a solid and the world (`b` = `None`);
    /// returns its index among the joints. Solved with the contacts, in the contact solver's
    /// substeps.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`a`, `b`, `anchor`, `axis`, a length, a
    /// limit, `hertz`, `max_motor`) and the value, or `dim` for a world without solids; the
    /// world is unchanged.
    pub fn add_joint(&mut self, params: JointParams) -> Result<usize> {
        let dim = self.dim();
        let i = each!(&mut self.solids, s => s.add_joint(params), Err(Error::invalid("dim", dim, "2 or 3 (joints join solids)")))?;
        self.derivative = super::Derivative::Stale;
        Ok(i)
    }

    /// The solids' ids ([`SolidId`]: given by [`World::add_solid`], never given again by this
    /// world), in their rows' order: the add order with the removed ones taken out.
    #[must_use]
    pub fn solid_ids(&self) -> Vec<SolidId> {
        each!(&self.solids, s => s.solid_ids(), Vec::new())
    }

    /// The joints' ids, in their rows' order.
    #[must_use]
    pub fn joint_ids(&self) -> Vec<JointId> {
        each!(&self.solids, s => s.joint_ids(), Vec::new())
    }

    /// The solid springs' ids, in their rows' order.
    #[must_use]
    pub fn solid_spring_ids(&self) -> Vec<SolidSpringId> {
        each!(&self.solids, s => s.spring_ids(), Vec::new())
    }

    /// The user forces on solids: their ids, in their rows' order.
    #[must_use]
    pub fn solid_force_ids(&self) -> Vec<SolidForceId> {
        each!(&self.solids, s => s.force_ids(), Vec::new())
    }

    /// The ids the next solid, joint, solid spring and user force on a solid get.
    #[must_use]
    pub fn next_solid_ids(&self) -> [u64; 4] {
        each!(&self.solids, s => s.next_ids(), [0; 4])
    }

    /// Sets the ids of the solids, joints, solid springs and user forces on solids with their
    /// counters (what a copy or pickle of a world carries), checked whole first.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid_ids`, `joint_ids`, `spring_ids` or
    /// `solid_force_ids`; the world is unchanged.
    pub fn set_solid_ids(&mut self, ids: [&[u64]; 4], next: [u64; 4]) -> Result<()> {
        let none = ids.iter().all(|i| i.is_empty()) && next == [0; 4];
        each!(&mut self.solids, s => s.set_ids(ids, next), if none { Ok(()) } else { Err(Error::invalid("solid_ids", "given", "none in a world without solids")) })
    }

    /// The row of solid `id` now (its index in [`World::solid_positions`] and the rest),
    /// `None` once removed.
    #[must_use]
    pub fn solid_row(&self, id: SolidId) -> Option<usize> {
        each!(&self.solids, s => s.solid_row(id), None)
    }

    /// The row of joint `id` now, `None` once removed.
    #[must_use]
    pub fn joint_row(&self, id: JointId) -> Option<usize> {
        each!(&self.solids, s => s.joint_row(id), None)
    }

    /// The row of solid spring `id` now, `None` once removed.
    #[must_use]
    pub fn solid_spring_row(&self, id: SolidSpringId) -> Option<usize> {
        each!(&self.solids, s => s.spring_row(id), None)
    }

    /// The row of user force `id` on a solid now, `None` once removed.
    #[must_use]
    pub fn solid_force_row(&self, id: SolidForceId) -> Option<usize> {
        each!(&self.solids, s => s.force_row(id), None)
    }

    /// What follows a change of the solids' structure by hand: the derivative and the
    /// frame's kept poses are no longer this world's.
    fn solids_changed(&mut self) {
        self.derivative = super::Derivative::Stale;
        self.prev_solids.clear();
    }

    /// Removes solid `id`, and with it the joints, solid springs and user forces that have it
    /// at one end (as Box2D's `b2DestroyBody` destroys a body's joints). The others keep their
    /// ids and their order; the rows after it move up one. Contacts' warm starts between
    /// the other solids are kept. Removed before any step, the world steps bitwise as one
    /// built without it.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid` when `id` is no solid of this world (removed,
    /// or never added); the world is unchanged.
    pub fn remove_solid(&mut self, id: SolidId) -> Result<()> {
        let no = || {
            Error::invalid(
                "solid",
                id,
                "the id of a solid of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.remove_solid(id), Err(no()))?;
        self.solids_changed();
        Ok(())
    }

    /// Removes joint `id`.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `joint` when `id` is no joint of this world; the world
    /// is unchanged.
    pub fn remove_joint(&mut self, id: JointId) -> Result<()> {
        let no = || {
            Error::invalid(
                "joint",
                id,
                "the id of a joint of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.remove_joint(id), Err(no()))?;
        self.derivative = super::Derivative::Stale;
        Ok(())
    }

    /// Removes solid spring `id`.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `spring` when `id` is no solid spring of this world; the
    /// world is unchanged.
    pub fn remove_solid_spring(&mut self, id: SolidSpringId) -> Result<()> {
        let no = || {
            Error::invalid(
                "spring",
                id,
                "the id of a solid spring of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.remove_spring(id), Err(no()))?;
        self.derivative = super::Derivative::Stale;
        Ok(())
    }

    /// Removes user force `id` from its solid; returns the row it had among the solid forces.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `force` when `id` is no user force on a solid of this
    /// world; the world is unchanged.
    pub fn remove_solid_force(&mut self, id: SolidForceId) -> Result<usize> {
        let no = || {
            Error::invalid(
                "force",
                id,
                "the id of a force on a solid of this world (it was removed, or never added here)",
            )
        };
        let k = each!(&mut self.solids, s => s.remove_force(id), Err(no()))?;
        self.derivative = super::Derivative::Stale;
        Ok(k)
    }

    /// Sets solid `id`'s position, orientation, velocity or angular velocity (the parts
    /// given; see [`SolidMotion`]), checked as [`World::add_solid`] checks them. A new pose
    /// forgets its contacts' warm starts and the frame's kept poses (render interpolation
    /// draws it where it is).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid` or the bad part and the value; the world is
    /// unchanged.
    pub fn set_solid_motion(&mut self, id: SolidId, motion: &SolidMotion) -> Result<()> {
        let no = || {
            Error::invalid(
                "solid",
                id,
                "the id of a solid of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.set_motion(id, motion), Err(no()))?;
        if motion.position.is_some() || motion.orientation.is_some() {
            self.prev_solids.clear();
        }
        self.derivative = super::Derivative::Stale;
        Ok(())
    }

    /// Sets joint `id`'s motor: speed (rad/s, or m/s for a slider) and the largest torque or
    /// force it applies (>= 0), checked as [`World::add_joint`] checks them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `joint`, `motor_speed` or `max_motor`; unchanged.
    pub fn set_joint_motor(&mut self, id: JointId, speed: f64, max_motor: f64) -> Result<()> {
        let no = || {
            Error::invalid(
                "joint",
                id,
                "the id of a joint of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.set_joint_motor(id, speed, max_motor), Err(no()))
    }

    /// Sets joint `id`'s limits (rad for a hinge, m for a slider; `None`: none that side).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `joint`, `lower` or `upper`; unchanged.
    pub fn set_joint_limits(&mut self, id: JointId, lower: Option<f64>, upper: Option<f64>) -> Result<()> {
        let no = || {
            Error::invalid(
                "joint",
                id,
                "the id of a joint of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.set_joint_limits(id, lower, upper), Err(no()))
    }

    /// Sets solid spring `id`'s stiffness (N/m), rest length (m) and damping (N s/m), each in
    /// [0, 1e12].
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `spring`, `stiffness`, `rest_length` or `damping`;
    /// unchanged.
    pub fn set_solid_spring(
        &mut self,
        id: SolidSpringId,
        stiffness: f64,
        rest_length: f64,
        damping: f64,
    ) -> Result<()> {
        let no = || {
            Error::invalid(
                "spring",
                id,
                "the id of a solid spring of this world (it was removed, or never added here)",
            )
        };
        each!(&mut self.solids, s => s.set_spring(id, stiffness, rest_length, damping), Err(no()))
    }

    /// Number of joints.
    #[must_use]
    pub fn joint_count(&self) -> usize {
        each!(&self.solids, s => s.joint_count(), 0)
    }

    /// Each joint as it was made.
    #[must_use]
    pub fn joint_params(&self) -> &[JointParams] {
        each!(&self.solids, s => s.joint_params(), &[])
    }

    /// Each joint's position error now, m (see [`Solids::joint_errors`]).
    #[must_use]
    pub fn joint_errors(&self) -> Vec<f64> {
        each!(&self.solids, s => s.joint_errors(), Vec::new())
    }

    /// Number of solids.
    #[must_use]
    pub fn solid_count(&self) -> usize {
        self.solids.len()
    }

    /// Each solid as it was added.
    #[must_use]
    pub fn solid_params(&self) -> &[SolidParams] {
        each!(&self.solids, s => s.params(), &[])
    }

    /// Origins of the solids' shapes, flat (`dim` a solid), m.
    #[must_use]
    pub fn solid_positions(&self) -> Vec<f64> {
        each!(&self.solids, s => s.positions(), Vec::new())
    }

    /// Orientations, flat: the angle (2D, rad) or the quaternion w, x, y, z (3D).
    #[must_use]
    pub fn solid_orientations(&self) -> Vec<f64> {
        each!(&self.solids, s => s.orientations(), Vec::new())
    }

    /// Velocities of the solids' centres of mass, flat, m/s.
    #[must_use]
    pub fn solid_velocities(&self) -> Vec<f64> {
        each!(&self.solids, s => s.velocities(), Vec::new())
    }

    /// Angular velocities, flat: one a solid in 2D, three in 3D, rad/s.
    #[must_use]
    pub fn solid_angular_velocities(&self) -> Vec<f64> {
        each!(&self.solids, s => s.angular_velocities(), Vec::new())
    }

    /// Kinetic energy of the dynamic solids, J.
    #[must_use]
    pub fn solid_kinetic_energy(&self) -> f64 {
        each!(&self.solids, s => s.kinetic_energy(), 0.0)
    }

    /// Potential energy of the solids: the dynamic ones' in the world's gravity and their
    /// springs', J.
    pub(super) fn solid_potential_energy(&self) -> f64 {
        fn u<S: Space>(m: &super::Model, s: &Solids<S>) -> f64 {
            s.gravity_energy(gravity_of::<S>(m)) + s.spring_energy()
        }
        each!(&self.solids, s => u(&self.model, s), 0.0)
    }

    /// Energy of the solids, J: kinetic (translation and rotation), potential in the world's
    /// gravity (0 at the origin) and in their springs. Conserved by the exact motion of
    /// solids that touch nothing, under gravity and undamped springs.
    #[must_use]
    pub fn solid_energy(&self) -> f64 {
        self.solid_kinetic_energy() + self.solid_potential_energy()
    }

    /// Adds a spring between a point of solid `a` and a point of solid `b` (each in its
    /// solid's frame, the frame its shape is given in), or a fixed point of the world (`b` =
    /// `None`, `point_b` in world coordinates): `F = k (|d| - rest) u + c (dv . u) u` on `a`'s
    /// point and `-F` on `b`'s, with their torques (`rest` 0: the linear `k d + c dv`),
    /// applied in each of the contact solver's substeps. Its rest length, when not given, is
    /// the distance between the ends now. Returns its index among the solid springs.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`a`, `b`, `point_a`, `point_b`,
    /// `stiffness`, `rest_length`, `damping`) and the value, or `dim` for a world without
    /// solids; the world is unchanged.
    pub fn add_solid_spring(&mut self, spring: SolidSpring) -> Result<usize> {
        let dim = self.dim();
        let i = each!(&mut self.solids, s => s.add_spring(spring), Err(Error::invalid("dim", dim, "2 or 3 (springs join solids)")))?;
        self.derivative = super::Derivative::Stale;
        Ok(i)
    }

    /// Adds a user force acting at `point` of solid `solid` (in its frame, the frame its
    /// shape is given in, m): the generator sees that point as one particle (its world
    /// position and velocity, `dim` numbers each) and returns the force on it, which also
    /// turns the solid about its centre. Evaluated once a step, at the step's start (time and
    /// state); the contact solver's substeps hold it constant over the step. Its potential,
    /// if it has one, joins [`World::energy`]; without one that energy is unknown. Returns
    /// its index among the solid forces.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid` or `point`, or `dim` for a world without
    /// solids; the world is unchanged.
    pub fn add_solid_force(
        &mut self,
        solid: usize,
        point: &[f64],
        generator: std::sync::Arc<dyn crate::forces::ForceGenerator>,
    ) -> Result<usize> {
        let dim = self.dim();
        let i = each!(&mut self.solids, s => s.add_force(solid, point, generator), Err(Error::invalid("dim", dim, "2 or 3 (a world that can hold solids)")))?;
        self.derivative = super::Derivative::Stale;
        Ok(i)
    }

    /// Number of user forces on solids.
    #[must_use]
    pub fn solid_force_count(&self) -> usize {
        each!(&self.solids, s => s.force_count(), 0)
    }

    /// The potential energy of the user forces on solids, J; `None` when one has none.
    pub(super) fn solid_user_potential(&self) -> Option<f64> {
        each!(&self.solids, s => s.user_potential(), Some(0.0))
    }

    /// Each solid spring's two ends now, world coordinates, flat (`dim` numbers each: the end
    /// on `a`, then the end on `b` or the anchor), m: what a game draws.
    #[must_use]
    pub fn solid_spring_ends(&self) -> Vec<f64> {
        each!(&self.solids, s => s.spring_ends(), Vec::new())
    }

    /// Each solid spring as it was made (its rest length resolved).
    #[must_use]
    pub fn solid_springs(&self) -> &[SolidSpring] {
        each!(&self.solids, s => s.springs(), &[])
    }

    /// Applies `force` (N, world frame: `dim` numbers) to solid `solid` for the next step, at
    /// the world point `point` (its centre of mass when `None`), which adds the torque of the
    /// force about the centre. Loads add up until the next step takes them (Box2D's
    /// `ApplyForce`), held constant over its substeps.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid`, `force` or `point`; the world is unchanged.
    pub fn apply_solid_force(&mut self, solid: usize, force: &[f64], point: Option<&[f64]>) -> Result<()> {
        let torque = vec![0.0; if self.dim() == 3 { 3 } else { 1 }];
        let dim = self.dim();
        each!(&mut self.solids, s => s.apply(solid, force, point, &torque), Err(Error::invalid("dim", dim, "2 or 3 (a world that can hold solids)")))
    }

    /// Applies `torque` (N m: one number in 2D, a world-frame vector in 3D) to solid `solid`
    /// for the next step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid` or `torque`; the world is unchanged.
    pub fn apply_solid_torque(&mut self, solid: usize, torque: &[f64]) -> Result<()> {
        let dim = self.dim();
        let force = vec![0.0; dim];
        each!(&mut self.solids, s => s.apply(solid, &force, None, torque), Err(Error::invalid("dim", dim, "2 or 3 (a world that can hold solids)")))
    }

    /// The contact points of the latest step.
    #[must_use]
    pub fn contacts(&self) -> Contacts {
        each!(&self.solids, s => flatten(&s.contacts()), Contacts::default())
    }

    /// The deepest penetration among the latest step's contacts, m.
    #[must_use]
    pub fn max_penetration(&self) -> f64 {
        each!(&self.solids, s => s.max_penetration(), 0.0)
    }

    /// The passes over the contacts the contact solver made in the latest step, counted as
    /// they ran (0 without solids or before a step).
    #[must_use]
    pub fn contact_passes(&self) -> u32 {
        each!(&self.solids, s => s.contact_passes(), 0)
    }

    /// The contact solver's settings (its name, substeps, iterations, stiffness).
    #[must_use]
    pub fn contact_settings(&self) -> Settings {
        each!(&self.solids, s => s.settings.clone(), Settings::default())
    }

    /// The settings of a world that can hold solids.
    fn solids_settings_mut(&mut self) -> Result<&mut Settings> {
        let dim = self.dim();
        each!(&mut self.solids, s => Ok(&mut s.settings), Err(Error::invalid("dim", dim, "2 or 3 (a world that can hold solids)")))
    }

    /// Sets every setting of the contact solver at once (its name, substeps, passes, the
    /// contacts' and joints' stiffness), checked whole first.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the first bad setting, [`Error::UnknownName`] for a
    /// solver that does not exist; the world is unchanged.
    pub fn set_contact_settings(&mut self, settings: Settings) -> Result<()> {
        let mut checked = Settings::default();
        checked.set_solver(settings.solver)?;
        checked.set_substeps(settings.substeps)?;
        checked.set_iterations(settings.iterations)?;
        settings.check()?;
        *self.solids_settings_mut()? = settings;
        Ok(())
    }

    /// Chooses the contact solver by name ([`crate::contact::SOLVERS`]).
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the solvers.
    pub fn set_contact_solver(&mut self, name: &str) -> Result<()> {
        self.solids_settings_mut()?.set_solver(name)
    }

    /// Sets the contact solver's substeps a step (1 to 1000).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `substeps`.
    pub fn set_substeps(&mut self, n: u32) -> Result<()> {
        self.solids_settings_mut()?.set_substeps(n)
    }

    /// Sets the contact solver's passes a substep (1 to 1000).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solver_iterations`.
    pub fn set_solver_iterations(&mut self, n: u32) -> Result<()> {
        self.solids_settings_mut()?.set_iterations(n)
    }

    /// Sets how long an island of solids must be slow before it falls asleep, s (0: never,
    /// the default; docs/contact.md, Sleeping). 0 wakes every sleeping solid at the next step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `sleep_time` unless it is finite and >= 0.
    pub fn set_sleep_time(&mut self, seconds: f64) -> Result<()> {
        let mut s = self.contact_settings();
        s.sleep_time = seconds;
        s.check()?;
        self.solids_settings_mut()?.sleep_time = seconds;
        Ok(())
    }

    /// Whether each solid is asleep (out of the contact solver until something reaches its
    /// island).
    #[must_use]
    pub fn solids_asleep(&self) -> Vec<bool> {
        each!(&self.solids, s => s.asleep(), Vec::new())
    }

    /// Contact: the solids advanced by the contact solver over the step, then checked.
    pub(super) fn contact(&mut self, ctx: &StepContext) -> Result<()> {
        fn run<S: Space>(g: S::V, s: &mut Solids<S>, ctx: &StepContext, method: &str) -> Result<()> {
            s.gather_loads(ctx.t)?;
            s.advance(ctx.h, g);
            s.forces.load.clear();
            match s.runaway() {
                Some(b) => Err(Error::Diverged {
                    method: format!("{} (contact solver {})", method, s.settings.solver),
                    step: ctx.step,
                    t: ctx.t,
                    index: b,
                    particle: None,
                    body: None,
                    solid: Some(b),
                }),
                None => Ok(()),
            }
        }
        let method = self.integrator.info().name;
        match &mut self.solids {
            SolidSet::Plane(s) if !s.is_empty() => run(gravity_of::<Plane>(&self.model), s, ctx, method),
            SolidSet::Space(s) if !s.is_empty() => run(gravity_of::<Space3>(&self.model), s, ctx, method),
            _ => Ok(()),
        }
    }
}
