//! Removing particles, bodies and constraints from a [`World`] by id ([`super::ids`]).
//!
//! A removal deletes the entity's rows keeping the order of the rest (so the arrays hold the
//! add order with the removed rows taken out), removes what hangs on it, as Box2D's
//! `b2DestroyBody` destroys the joints on a body (for a particle: the springs and rods with
//! an end on it, the body springs to it, the constraints that name it), and remaps the
//! particle indices stored in what stays (spring and rod ends, constraint ends, the balls'
//! radii). Like a write of the positions, it restarts a method that carries memory and the
//! derivative is evaluated again before the next step, so the world then steps bitwise as one
//! built without the entity from the start.

use super::ids::{unknown, BodyForceId, BodyId, BodySpringId, ConstraintId, ParticleId};
use super::World;
use crate::dynamics::SecondOrder;
use crate::error::{Error, Result};
use crate::forces::{Endpoint, ForceId};

/// What a particle removal took with it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Removed {
    /// The forces (springs and rods) that had an end on the particle.
    pub forces: Vec<ForceId>,
    /// The constraints that named it.
    pub constraints: Vec<ConstraintId>,
    /// The body springs that ended on it.
    pub body_springs: Vec<BodySpringId>,
}

/// The particle rows that stay after a removal, renumbered: `new[p]` is row `p`'s row after
/// it (`None` for a removed row).
struct Renumbering {
    new: Vec<Option<usize>>,
}

impl Renumbering {
    /// The rows `gone` marks taken out of `0..gone.len()`, the order of the rest kept.
    fn of(gone: &[bool]) -> Self {
        let mut next = 0;
        let new = gone
            .iter()
            .map(|&g| {
                (!g).then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect();
        Self { new }
    }

    fn gone(&self, p: usize) -> bool {
        self.new[p].is_none()
    }

    /// Row `p` (one that stays) after the removal.
    fn row(&self, p: usize) -> usize {
        self.new[p].unwrap_or(p)
    }

    fn end(&self, j: Endpoint) -> Endpoint {
        match j {
            Endpoint::Particle(p) => Endpoint::Particle(self.row(p)),
            anchor @ Endpoint::Anchor(_) => anchor,
        }
    }

    fn end_gone(&self, j: Endpoint) -> bool {
        matches!(j, Endpoint::Particle(p) if self.gone(p))
    }
}

impl World {
    /// Removes particle `id` (a ball with its radius), and with it the springs and rods with
    /// an end on it, the body springs to it and the constraints that name it (their ids are
    /// never given again). The particles after it move up one row, keeping their order and
    /// their ids; indices stored elsewhere (spring, rod and constraint ends) follow. A method
    /// that carries memory restarts, as after [`World::set_positions`]; the world then steps
    /// bitwise as one built without the particle (and what hung on it) from the start.
    /// User forces ([`World::add_force_generator`]) stay, and see one particle fewer.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `particle` when the world
    /// holds no particle of that id (removed already, or never added here); the world is
    /// unchanged.
    pub fn remove_particle(&mut self, id: ParticleId) -> Result<Removed> {
        self.remove_particles(&[id])
    }

    /// Removes the particles `ids` at once, as [`World::remove_particle`] removes one (the
    /// world then is the one removing them one by one leaves, bitwise), in one pass over the
    /// world's rows whatever their number.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `particle` when an id is not of a particle of this
    /// world, or is listed twice; the world is unchanged.
    pub fn remove_particles(&mut self, ids: &[ParticleId]) -> Result<Removed> {
        if ids.is_empty() {
            // Nothing removed: the method's memory is not restarted either.
            return Ok(Removed::default());
        }
        let n = self.model.mass.len();
        let mut gone = vec![false; n];
        for id in ids {
            let row = self.ids.particles.row(id.0).ok_or_else(|| unknown("particle", id.0))?;
            if std::mem::replace(&mut gone[row], true) {
                return Err(Error::invalid("particle", id.0, "listed once"));
            }
        }
        let map = Renumbering::of(&gone);
        let d = self.dim();
        let (coords, nx) = (self.model.len(), self.nx());
        // y = [x, bodies' X; v, bodies' V]: each half's particle rows compacted in place.
        let y = &mut self.state.y;
        let mut w = 0;
        for r in 0..y.len() {
            let i = if r < nx { r } else { r - nx };
            if i >= coords || !gone[i / d] {
                y[w] = y[r];
                w += 1;
            }
        }
        y.truncate(w);
        self.state.f.truncate(w);
        if self.prev_x.len() == coords {
            let mut row = 0;
            self.prev_x.retain(|_| {
                row += 1;
                !gone[(row - 1) / d]
            });
        } else {
            self.prev_x.clear();
        }
        crate::ids::retain_by(&mut self.model.mass, &gone);
        self.model.inv_mass.retain_by(&gone);
        let forces = self.model.forces.remove_particles(&map);
        let dropped: Vec<bool> = self.bodies.springs.iter().map(|s| map.end_gone(s.other)).collect();
        crate::ids::retain_by(&mut self.bodies.springs, &dropped);
        let body_springs = self.ids.body_springs.take_rows(&dropped).into_iter().map(BodySpringId).collect();
        for s in &mut self.bodies.springs {
            s.other = map.end(s.other);
        }
        let constraints = self.constraints_without(&map);
        let radii = self.balls.radius.len().min(n);
        crate::ids::retain_by(&mut self.balls.radius, &gone[..radii]);
        self.balls.index.retain(|&p| !map.gone(p));
        for p in &mut self.balls.index {
            *p = map.row(*p);
        }
        // The resting contacts' warm starts name the balls' slots, which this renumbers: the
        // next step starts them afresh.
        self.balls.warm.clear();
        self.ids.particles.retain_rows(&gone);
        self.touch();
        Ok(Removed { forces, constraints, body_springs })
    }

    /// Drops the constraints that name a removed particle and renumbers the rest; returns
    /// the ids of the dropped ones.
    fn constraints_without(&mut self, map: &Renumbering) -> Vec<ConstraintId> {
        use crate::constraints::Constraint;
        let dropped: Vec<bool> = self
            .constraints
            .list
            .iter()
            .map(|c| c.particles().iter().any(|p| p.is_some_and(|p| map.gone(p))))
            .collect();
        crate::ids::retain_by(&mut self.constraints.list, &dropped);
        let ids = self.ids.constraints.take_rows(&dropped).into_iter().map(ConstraintId).collect();
        for c in &mut self.constraints.list {
            *c = match *c {
                Constraint::Distance { i, j, length, compliance } => {
                    Constraint::Distance { i: map.row(i), j: map.end(j), length, compliance }
                }
                Constraint::Limit { i, j, min, max } => {
                    Constraint::Limit { i: map.row(i), j: map.end(j), min, max }
                }
                Constraint::Pin { i, point } => Constraint::Pin { i: map.row(i), point },
                plane @ Constraint::Plane { .. } => plane,
            };
        }
        ids
    }

    /// Removes body `id`, and with it the body springs and user forces at its points (the
    /// others keep their order and ids). The bodies after it move up one row, keeping their
    /// order and ids. A method that carries memory restarts; the world then steps bitwise as
    /// one built without the body from that state. Returns the rows the body forces that
    /// went with it had (before the removal, ascending: a face that keeps something per body
    /// force drops the same ones) and the ids of the body springs that went.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body` when the world holds
    /// no body of that id; the world is unchanged.
    pub fn remove_body(&mut self, id: BodyId) -> Result<(Vec<usize>, Vec<BodySpringId>)> {
        use crate::rigid::body::{V_LEN, X_LEN};
        let b = self.ids.bodies.row(id.0).ok_or_else(|| unknown("body", id.0))?;
        let (coords, nx, nb) = (self.model.len(), self.nx(), self.bodies.len());
        let v_at = nx + coords + b * V_LEN;
        self.state.y.drain(v_at..v_at + V_LEN);
        let x_at = coords + b * X_LEN;
        self.state.y.drain(x_at..x_at + X_LEN);
        self.state.f.truncate(self.state.y.len());
        let bodies = &mut self.bodies;
        bodies.mass.remove(b);
        bodies.inertia.remove(b);
        bodies.inv_inertia.remove(b);
        bodies.frame.remove(b);
        bodies.offset.remove(b);
        bodies.pinned.remove(b);
        bodies.angular_drag.remove(b);
        bodies.reference.remove(b);
        bodies.force.remove(b);
        bodies.torque.remove(b);
        let mut springs = Vec::new();
        for k in (0..bodies.springs.len()).rev() {
            if bodies.springs[k].body == b {
                bodies.springs.remove(k);
                springs.push(BodySpringId(self.ids.body_springs.id(k).unwrap_or_default()));
                self.ids.body_springs.remove(k);
            }
        }
        springs.reverse();
        bodies.springs.iter_mut().for_each(|s| s.body = crate::ids::shift(s.body, b));
        let forces: Vec<usize> = (0..bodies.forces.len()).filter(|&k| bodies.forces[k].body == b).collect();
        for &k in forces.iter().rev() {
            bodies.forces.remove(k);
            self.ids.body_forces.remove(k);
        }
        bodies.forces.iter_mut().for_each(|f| f.body = crate::ids::shift(f.body, b));
        self.body_params.remove(b);
        if self.prev_q.len() == nb {
            self.prev_q.remove(b);
        } else {
            self.prev_q.clear();
        }
        self.ids.bodies.remove(b);
        self.touch();
        Ok((forces, springs))
    }

    /// Removes body spring `id`; the others keep their order and ids. The world then steps
    /// bitwise as one that never had it (a method that carries memory restarts).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body_spring` when the
    /// world holds no body spring of that id; the world is unchanged.
    pub fn remove_body_spring(&mut self, id: BodySpringId) -> Result<()> {
        let k = self.ids.body_springs.row(id.0).ok_or_else(|| unknown("body_spring", id.0))?;
        self.bodies.springs.remove(k);
        self.ids.body_springs.remove(k);
        self.touch();
        Ok(())
    }

    /// Changes body spring `id`'s stiffness, rest length or damping (`None` keeps one),
    /// checked as [`World::add_body_spring`] checks them; the world then steps as one built
    /// with the new values, and a method that carries memory restarts (as adding a spring).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body_spring` (no such spring), `stiffness`,
    /// `rest_length` or `damping` (each a number in [0, 1e12]); the world is unchanged.
    pub fn set_body_spring(
        &mut self,
        id: BodySpringId,
        stiffness: Option<f64>,
        rest_length: Option<f64>,
        damping: Option<f64>,
    ) -> Result<()> {
        let k = self.ids.body_springs.row(id.0).ok_or_else(|| unknown("body_spring", id.0))?;
        for (name, v) in [("stiffness", stiffness), ("rest_length", rest_length), ("damping", damping)] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && (0.0..=crate::limits::PARAM_MAX).contains(v))) {
                return Err(Error::invalid(name, crate::error::num(v), "a number in [0, 1e12]"));
            }
        }
        let s = &mut self.bodies.springs[k];
        s.stiffness = stiffness.unwrap_or(s.stiffness);
        s.rest_length = rest_length.unwrap_or(s.rest_length);
        s.damping = damping.unwrap_or(s.damping);
        self.touch();
        Ok(())
    }

    /// Removes the user force at a body point of id `id`; returns the place it had among the
    /// body forces (a face keeping something per body force drops it there). The world
    /// then steps bitwise as one that never had it.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body_force` when the world
    /// holds no body force of that id; the world is unchanged.
    pub fn remove_body_force(&mut self, id: BodyForceId) -> Result<usize> {
        let k = self.ids.body_forces.row(id.0).ok_or_else(|| unknown("body_force", id.0))?;
        self.bodies.forces.remove(k);
        self.ids.body_forces.remove(k);
        self.touch();
        Ok(k)
    }

    /// Body spring `id` as the world holds it (its point from the body's reference point in
    /// the principal frame), `None` when there is none.
    #[must_use]
    pub fn body_spring(&self, id: BodySpringId) -> Option<crate::rigid::body::BodySpring> {
        self.body_spring_row(id).map(|k| self.bodies.springs[k])
    }

    /// Removes constraint `id`; the others keep their order (the sweep order) and ids. The
    /// next step relaxes without it.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `constraint` when the
    /// world holds no constraint of that id; the world is unchanged.
    pub fn remove_constraint(&mut self, id: ConstraintId) -> Result<()> {
        let k = self.ids.constraints.row(id.0).ok_or_else(|| unknown("constraint", id.0))?;
        self.constraints.list.remove(k);
        self.ids.constraints.remove(k);
        // A method whose memory a relaxation resynced restarts, as after adding one.
        self.touch();
        Ok(())
    }

    /// The constraint of id `id` as the world holds it, `None` when there is none.
    #[must_use]
    pub fn constraint(&self, id: ConstraintId) -> Option<crate::constraints::Constraint> {
        self.constraint_row(id).map(|k| self.constraints.list[k])
    }
}

/// A particle removal in the force set.
impl crate::forces::ForceSet {
    /// Removes the forces with an end on a removed particle and renumbers the other ends;
    /// returns the ids removed, in the set's order. The order stays canonical (the
    /// renumbering keeps every comparison of the keys), so the set steps as one built
    /// without those particles.
    fn remove_particles(&mut self, map: &Renumbering) -> Vec<ForceId> {
        use crate::forces::Force;
        let touches = |f: &Force| match *f {
            Force::Spring { i, j, .. } | Force::Rod { i, j, .. } => map.gone(i) || map.end_gone(j),
            _ => false,
        };
        let gone: Vec<ForceId> = self.iter_ids().filter(|(_, f)| touches(f)).map(|(id, _)| id).collect();
        self.retain_renumbered(
            |f| !touches(f),
            |f| match f {
                Force::Spring { i, j, stiffness, rest_length, damping } => {
                    Force::Spring { i: map.row(i), j: map.end(j), stiffness, rest_length, damping }
                }
                Force::Rod { i, j, length } => Force::Rod { i: map.row(i), j: map.end(j), length },
                other => other,
            },
        );
        gone
    }
}
