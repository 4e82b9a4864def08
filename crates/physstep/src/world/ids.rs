//! Stable ids of a world's particles, bodies and constraints: what a handle names while other
//! entities come and go.
//!
//! Each kind has a counter per [`World`] that never gives a value twice (shaped like
//! [`crate::forces::ForceId`]). Storage stays dense arrays; the world keeps, per kind, the ids
//! parallel to the rows, in increasing order: rows are appended in add order and a removal
//! deletes its row keeping the order of the rest (never a swap), so the array order after
//! removals is the add order with the removed rows taken out, and an id's row is a binary
//! search.
//!
//! While nothing of a kind was ever removed its ids are `0..n` (the counter equals the row
//! count): nothing of them enters a snapshot or a state hash, so a world that never removed
//! anything hashes and snapshots bitwise as before ids existed.

use super::World;
use crate::error::{Error, Result};
use crate::ids::{id_type, Ids};

id_type!(
    /// A particle's id in its world (balls are particles): given when it is added, never
    /// given again by that world; [`World::particle_row`] finds its current row.
    ParticleId
);
id_type!(
    /// A rigid body's id in its world ([`World::add_body`]); [`World::body_row`] finds its
    /// current row.
    BodyId
);
id_type!(
    /// A position constraint's id in its world ([`World::add_constraint`] and the `add_*`
    /// of constraints); [`World::constraint_row`] finds its current place in the sweep order.
    ConstraintId
);

id_type!(
    /// A body spring's id in its world ([`World::add_body_spring`]);
    /// [`World::body_spring_row`] finds its place among the body springs.
    BodySpringId
);
id_type!(
    /// A user force at a body point: its id in its world ([`World::add_body_force`]);
    /// [`World::body_force_row`] finds its place among the body forces.
    BodyForceId
);

/// The ids of a world's entities, by kind.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct EntityIds {
    pub(crate) particles: Ids,
    pub(crate) bodies: Ids,
    pub(crate) constraints: Ids,
    pub(crate) body_springs: Ids,
    pub(crate) body_forces: Ids,
}

impl EntityIds {
    /// A fingerprint of every kind's ids and counter, `None` while every kind is dense
    /// (nothing ever removed): snapshots and state hashes then carry nothing of them.
    pub(crate) fn fingerprint(&self) -> Option<u64> {
        let kinds = [&self.particles, &self.bodies, &self.constraints, &self.body_springs, &self.body_forces];
        if kinds.iter().all(|k| k.dense()) {
            return None;
        }
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for (tag, k) in kinds.iter().enumerate() {
            for w in std::iter::once(tag as u64).chain(k.words()) {
                for b in w.to_le_bytes() {
                    h ^= u64::from(b);
                    h = h.wrapping_mul(0x0000_0100_0000_01b3);
                }
            }
        }
        Some(h)
    }
}

/// `invalid {what} = {id}: must be the id of a {what} of this world ...`.
pub(crate) fn unknown(what: &str, id: u64) -> Error {
    let noun = what.replace('_', " ");
    Error::invalid(
        what,
        id,
        format!("the id of a {noun} of this world (it was removed, or never added here)"),
    )
}

impl World {
    /// The id of the particle in row `row` (`None` past the last row).
    #[must_use]
    pub fn particle_id(&self, row: usize) -> Option<ParticleId> {
        self.ids.particles.id(row).map(ParticleId)
    }

    /// The current row of particle `id` (its index in [`World::positions`]), `None` when
    /// the world holds no such particle (removed, or never added).
    #[must_use]
    pub fn particle_row(&self, id: ParticleId) -> Option<usize> {
        self.ids.particles.row(id.0)
    }

    /// The ids of the particles, row by row (increasing).
    #[must_use]
    pub fn particle_ids(&self) -> Vec<ParticleId> {
        self.ids.particles.all().iter().map(|&i| ParticleId(i)).collect()
    }

    /// The id the next particle added will get.
    #[must_use]
    pub fn next_particle_id(&self) -> ParticleId {
        ParticleId(self.ids.particles.next())
    }

    /// The id of body `row` (`None` past the last).
    #[must_use]
    pub fn body_id(&self, row: usize) -> Option<BodyId> {
        self.ids.bodies.id(row).map(BodyId)
    }

    /// The current row of body `id`, `None` when the world holds no such body.
    #[must_use]
    pub fn body_row(&self, id: BodyId) -> Option<usize> {
        self.ids.bodies.row(id.0)
    }

    /// The ids of the bodies, row by row (increasing).
    #[must_use]
    pub fn body_ids(&self) -> Vec<BodyId> {
        self.ids.bodies.all().iter().map(|&i| BodyId(i)).collect()
    }

    /// The id the next body added will get.
    #[must_use]
    pub fn next_body_id(&self) -> BodyId {
        BodyId(self.ids.bodies.next())
    }

    /// The id of constraint `row` (its place in [`crate::constraints::Constraints::list`]).
    #[must_use]
    pub fn constraint_id(&self, row: usize) -> Option<ConstraintId> {
        self.ids.constraints.id(row).map(ConstraintId)
    }

    /// The current place of constraint `id` in the sweep order, `None` when the world holds
    /// no such constraint.
    #[must_use]
    pub fn constraint_row(&self, id: ConstraintId) -> Option<usize> {
        self.ids.constraints.row(id.0)
    }

    /// The ids of the constraints, in sweep order (increasing).
    #[must_use]
    pub fn constraint_ids(&self) -> Vec<ConstraintId> {
        self.ids.constraints.all().iter().map(|&i| ConstraintId(i)).collect()
    }

    /// The id the next constraint added will get.
    #[must_use]
    pub fn next_constraint_id(&self) -> ConstraintId {
        ConstraintId(self.ids.constraints.next())
    }

    /// The ids of the body springs, in the order they act (increasing).
    #[must_use]
    pub fn body_spring_ids(&self) -> Vec<BodySpringId> {
        self.ids.body_springs.all().iter().map(|&i| BodySpringId(i)).collect()
    }

    /// The place of body spring `id` among the body springs, `None` when there is none.
    #[must_use]
    pub fn body_spring_row(&self, id: BodySpringId) -> Option<usize> {
        self.ids.body_springs.row(id.0)
    }

    /// The ids of the user forces at body points, in the order they act (increasing).
    #[must_use]
    pub fn body_force_ids(&self) -> Vec<BodyForceId> {
        self.ids.body_forces.all().iter().map(|&i| BodyForceId(i)).collect()
    }

    /// The place of body force `id` among the body forces, `None` when there is none.
    #[must_use]
    pub fn body_force_row(&self, id: BodyForceId) -> Option<usize> {
        self.ids.body_forces.row(id.0)
    }

    /// The ids the next body spring and the next body force will get.
    #[must_use]
    pub fn next_body_link_ids(&self) -> [u64; 2] {
        [self.ids.body_springs.next(), self.ids.body_forces.next()]
    }

    /// Gives the body springs and body forces the ids `springs` and `forces` with their
    /// counters `next`, as [`World::set_entity_ids`] does for the other kinds.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `len(body_spring_ids)`, `body_spring_ids`,
    /// `len(body_force_ids)` or `body_force_ids`; the world is unchanged.
    pub fn set_body_link_ids(
        &mut self,
        springs: &[BodySpringId],
        forces: &[BodyForceId],
        next: [u64; 2],
    ) -> Result<()> {
        let mut ids = self.ids.clone();
        let s: Vec<u64> = springs.iter().map(|i| i.0).collect();
        let f: Vec<u64> = forces.iter().map(|i| i.0).collect();
        ids.body_springs.set("body_spring_ids", "body spring", &s, next[0])?;
        ids.body_forces.set("body_force_ids", "body force", &f, next[1])?;
        self.ids = ids;
        Ok(())
    }

    /// Gives the particles, bodies and constraints the ids `particles`, `bodies` and
    /// `constraints` (row by row, increasing) with their counters `next` (particles, bodies,
    /// constraints): how a face that rebuilds a world from scene text, which carries no ids,
    /// keeps its handles valid across the round trip (the Python pickle does), before it
    /// restores the snapshot (which checks them).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `len(particle_ids)` (not one per row),
    /// `particle_ids` (not increasing, or not below the counter), and the same for bodies
    /// and constraints; the world is unchanged.
    pub fn set_entity_ids(
        &mut self,
        particles: &[ParticleId],
        bodies: &[BodyId],
        constraints: &[ConstraintId],
        next: [u64; 3],
    ) -> Result<()> {
        let mut ids = self.ids.clone();
        let p: Vec<u64> = particles.iter().map(|i| i.0).collect();
        let b: Vec<u64> = bodies.iter().map(|i| i.0).collect();
        let c: Vec<u64> = constraints.iter().map(|i| i.0).collect();
        ids.particles.set("particle_ids", "particle", &p, next[0])?;
        ids.bodies.set("body_ids", "body", &b, next[1])?;
        ids.constraints.set("constraint_ids", "constraint", &c, next[2])?;
        self.ids = ids;
        Ok(())
    }
}
