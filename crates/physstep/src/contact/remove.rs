//! Ids, removal and changes by hand of the solids, joints, springs and user forces on solids
//! (docs/contact.md, "Handles and removal").
//!
//! Removing a solid removes what hangs on it, as Box2D's `b2DestroyBody` does: the joints,
//! springs and user forces with it at one end. The solid indices held elsewhere (joints'
//! and springs' ends, the pairs joints keep apart, the warm starts and latest contacts, the
//! broad phase's order) are renumbered; the warm starts of the pairs without it are kept.

use super::{JointId, SolidForceId, SolidId, SolidSpringId, Solids, Space, Vect};
use super::{FORCE, JOINT, SOLID, SPRING};
use crate::error::{num, Error, Result};
use crate::ids::{retain_by, shift, Ids};

/// What a solid's motion is set to by hand ([`Solids::set_motion`]); `None` keeps a part.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SolidMotion {
    /// The origin of its shape, m (`DIM` numbers).
    pub position: Option<Vec<f64>>,
    /// The angle (2D, rad) or a quaternion w, x, y, z (3D, normalised when set).
    pub orientation: Option<Vec<f64>>,
    /// The velocity of its centre of mass, m/s.
    pub velocity: Option<Vec<f64>>,
    /// The angular velocity, rad/s (one number in 2D).
    pub angular_velocity: Option<Vec<f64>>,
}

fn no_such(field: &str, what: &str, id: u64) -> Error {
    Error::invalid(
        field,
        id,
        format!("the id of a {what} of this world (it was removed, or never added here)"),
    )
}

fn numbers(field: &str, v: &[f64], n: usize) -> Result<()> {
    if v.len() != n {
        return Err(Error::invalid(format!("len({field})"), v.len(), format!("{n}")));
    }
    match v.iter().position(|x| !(x.is_finite() && x.abs() <= crate::limits::PARAM_MAX)) {
        Some(i) => Err(Error::invalid(format!("{field}[{i}]"), num(v[i]), "finite (at most 1e12 in size)")),
        None => Ok(()),
    }
}

impl<S: Space> Solids<S> {
    /// The solids' ids, in their rows' order.
    #[must_use]
    pub fn solid_ids(&self) -> Vec<SolidId> {
        self.ids[SOLID].all().iter().map(|i| SolidId(*i)).collect()
    }

    /// The joints' ids, in their rows' order.
    #[must_use]
    pub fn joint_ids(&self) -> Vec<JointId> {
        self.ids[JOINT].all().iter().map(|i| JointId(*i)).collect()
    }

    /// The solid springs' ids, in their rows' order.
    #[must_use]
    pub fn spring_ids(&self) -> Vec<SolidSpringId> {
        self.ids[SPRING].all().iter().map(|i| SolidSpringId(*i)).collect()
    }

    /// The user forces' ids, in their rows' order.
    #[must_use]
    pub fn force_ids(&self) -> Vec<SolidForceId> {
        self.ids[FORCE].all().iter().map(|i| SolidForceId(*i)).collect()
    }

    /// The counters: the id the next solid, joint, spring and user force gets.
    #[must_use]
    pub fn next_ids(&self) -> [u64; 4] {
        [0, 1, 2, 3].map(|k| self.ids[k].next())
    }

    /// The row of solid `id` now, `None` once removed.
    #[must_use]
    pub fn solid_row(&self, id: SolidId) -> Option<usize> {
        self.ids[SOLID].row(id.0)
    }

    /// The row of joint `id` now, `None` once removed.
    #[must_use]
    pub fn joint_row(&self, id: JointId) -> Option<usize> {
        self.ids[JOINT].row(id.0)
    }

    /// The row of spring `id` now, `None` once removed.
    #[must_use]
    pub fn spring_row(&self, id: SolidSpringId) -> Option<usize> {
        self.ids[SPRING].row(id.0)
    }

    /// The row of user force `id` now, `None` once removed.
    #[must_use]
    pub fn force_row(&self, id: SolidForceId) -> Option<usize> {
        self.ids[FORCE].row(id.0)
    }

    /// Solid `id`'s row, or the error naming it.
    pub(crate) fn solid_at(&self, id: SolidId) -> Result<usize> {
        self.solid_row(id).ok_or_else(|| no_such("solid", "solid", id.0))
    }

    /// Sets the ids of every kind (`ids[k]` under the counter `next[k]`: solids, joints,
    /// springs, user forces), checked whole first: what a copy or pickle of a world carries.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid_ids`, `joint_ids`, `spring_ids` or
    /// `solid_force_ids`: a wrong count, ids not increasing or not below their counter; the
    /// ids are then unchanged.
    pub fn set_ids(&mut self, ids: [&[u64]; 4], next: [u64; 4]) -> Result<()> {
        let mut new = self.ids.clone();
        let kinds = [
            ("solid_ids", "solid"),
            ("joint_ids", "joint"),
            ("spring_ids", "solid spring"),
            ("solid_force_ids", "force on a solid"),
        ];
        for (k, (field, per)) in kinds.into_iter().enumerate() {
            new[k].set(field, per, ids[k], next[k])?;
        }
        self.ids = new;
        Ok(())
    }

    /// Whether every kind's ids are its rows' indices (nothing was ever removed).
    pub(crate) fn ids_implicit(&self) -> bool {
        self.ids.iter().all(Ids::dense)
    }

    /// The ids of every kind with their counters, flat (a snapshot's tail, when not
    /// implicit).
    pub(crate) fn write_ids(&self, out: &mut Vec<f64>) {
        for ids in &self.ids {
            ids.write(out);
        }
    }

    /// Removes solid `id`, and the joints, springs and user forces with it at one end; the
    /// rest keep their order (and ids), their solid indices renumbered. The warm starts of
    /// contacts without it are kept.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid` when `id` is no solid of these; unchanged.
    pub fn remove_solid(&mut self, id: SolidId) -> Result<()> {
        let k = self.solid_at(id)?;
        // The islands are numbered by solid index, which this renumbers.
        self.wake_all();
        self.bodies.remove(k);
        self.shapes.remove(k);
        self.params.remove(k);
        self.ids[SOLID].remove(k);
        let joints: Vec<bool> = self.joints.iter().map(|j| j.joins(k)).collect();
        retain_by(&mut self.joints, &joints);
        retain_by(&mut self.joint_params, &joints);
        self.ids[JOINT].retain_rows(&joints);
        for (j, p) in self.joints.iter_mut().zip(&mut self.joint_params) {
            j.shift(k);
            p.a = shift(p.a, k);
            p.b = p.b.map(|b| shift(b, k));
        }
        self.rebuild_no_collide();
        let (springs, users) = self.forces.remove_solid(k);
        self.ids[SPRING].retain_rows(&springs);
        self.ids[FORCE].retain_rows(&users);
        self.solver.remove_solid(k);
        Ok(())
    }

    /// The pairs the joints keep from colliding, made again from the joints.
    fn rebuild_no_collide(&mut self) {
        let mut pairs: Vec<(u32, u32)> =
            self.joints.iter().zip(&self.joint_params).filter_map(|(j, p)| j.no_collide(p)).collect();
        pairs.sort_unstable();
        pairs.dedup();
        self.no_collide = pairs;
    }

    /// Removes joint `id` (its two solids collide again unless another joint keeps them
    /// apart).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `joint` when `id` is no joint of these; unchanged.
    pub fn remove_joint(&mut self, id: JointId) -> Result<()> {
        let k = self.joint_row(id).ok_or_else(|| no_such("joint", "joint", id.0))?;
        self.wake_ends(self.joints[k].solids());
        self.joints.remove(k);
        self.joint_params.remove(k);
        self.ids[JOINT].remove(k);
        self.rebuild_no_collide();
        Ok(())
    }

    /// Removes solid spring `id`.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `spring` when `id` is no spring of these; unchanged.
    pub fn remove_spring(&mut self, id: SolidSpringId) -> Result<()> {
        let k = self.spring_row(id).ok_or_else(|| no_such("spring", "solid spring", id.0))?;
        self.wake_ends(self.forces.springs[k].solids());
        self.forces.springs.remove(k);
        self.forces.spring_params.remove(k);
        self.ids[SPRING].remove(k);
        Ok(())
    }

    /// Removes user force `id`; returns the row it had.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `force` when `id` is no user force on these solids;
    /// unchanged.
    pub fn remove_force(&mut self, id: SolidForceId) -> Result<usize> {
        let k = self.force_row(id).ok_or_else(|| no_such("force", "force on a solid", id.0))?;
        self.wake(self.forces.users[k].solid);
        self.forces.users.remove(k);
        self.ids[FORCE].remove(k);
        Ok(k)
    }

    /// Sets joint `id`'s motor: its speed (rad/s or m/s) and largest torque or force.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `joint`, `motor_speed` or `max_motor`; unchanged.
    pub fn set_joint_motor(&mut self, id: JointId, speed: f64, max: f64) -> Result<()> {
        let k = self.joint_row(id).ok_or_else(|| no_such("joint", "joint", id.0))?;
        self.joints[k].set_motor(speed, max)?;
        self.wake_ends(self.joints[k].solids());
        let p = &mut self.joint_params[k];
        (p.motor_speed, p.max_motor) = (speed, max);
        Ok(())
    }

    /// Sets joint `id`'s limits (angle in rad, or travel in m; `None`: none that side).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `joint`, `lower` or `upper`; unchanged.
    pub fn set_joint_limits(&mut self, id: JointId, lower: Option<f64>, upper: Option<f64>) -> Result<()> {
        let k = self.joint_row(id).ok_or_else(|| no_such("joint", "joint", id.0))?;
        self.joints[k].set_limits(lower, upper)?;
        self.wake_ends(self.joints[k].solids());
        let p = &mut self.joint_params[k];
        (p.lower, p.upper) = (lower, upper);
        Ok(())
    }

    /// Sets spring `id`'s stiffness (N/m), rest length (m) and damping (N s/m), each in
    /// [0, 1e12].
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `spring`, `stiffness`, `rest_length` or `damping`;
    /// unchanged.
    pub fn set_spring(
        &mut self,
        id: SolidSpringId,
        stiffness: f64,
        rest_length: f64,
        damping: f64,
    ) -> Result<()> {
        let k = self.spring_row(id).ok_or_else(|| no_such("spring", "solid spring", id.0))?;
        self.forces.set_spring(k, stiffness, rest_length, damping)?;
        self.wake_ends(self.forces.springs[k].solids());
        Ok(())
    }

    /// Sets solid `id`'s position, orientation, velocity or angular velocity (the parts
    /// given), checked whole first as [`Solids::check`] checks them (a static solid keeps zero
    /// velocities). A new pose forgets the warm starts of its contacts (last step's impulses
    /// and friction anchors belong where it was); a new velocity keeps them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solid`, `position`, `orientation`, `velocity` or
    /// `angular_velocity` and the value; unchanged.
    pub fn set_motion(&mut self, id: SolidId, m: &SolidMotion) -> Result<()> {
        let k = self.solid_at(id)?;
        let (d, r, a) = (S::DIM, S::ROT, if S::DIM == 3 { 3 } else { 1 });
        let b = &self.bodies[k];
        if let Some(x) = &m.position {
            numbers("position", x, d)?;
        }
        if let Some(q) = &m.orientation {
            numbers("orientation", q, r)?;
            if r == 4 && q.iter().map(|x| x * x).sum::<f64>() == 0.0 {
                return Err(Error::invalid("orientation", "[0, 0, 0, 0]", "a non-zero quaternion"));
            }
        }
        let moving = |v: &Option<Vec<f64>>| v.as_ref().is_some_and(|v| v.iter().any(|x| *x != 0.0));
        for (field, v, n) in [("velocity", &m.velocity, d), ("angular_velocity", &m.angular_velocity, a)] {
            if let Some(v) = v {
                numbers(field, v, n)?;
            }
            if b.kind == super::Kind::Static && moving(v) {
                return Err(Error::invalid(
                    field,
                    "non-zero",
                    "zero for a static solid (make it kinematic to move it)",
                ));
            }
        }
        // Checked: commit.
        let b = &mut self.bodies[k];
        if m.position.is_some() || m.orientation.is_some() {
            let origin = m.position.as_ref().map_or_else(|| b.origin(), |x| S::V::read(x));
            if let Some(q) = &m.orientation {
                b.q = S::read_rot(q);
            }
            b.c = origin + S::rotate(b.q, b.com);
            self.solver.forget(k);
        }
        if let Some(v) = &m.velocity {
            b.v = S::V::read(v);
        }
        if let Some(w) = &m.angular_velocity {
            b.w = S::W::read(w);
        }
        self.wake(k);
        Ok(())
    }
}
