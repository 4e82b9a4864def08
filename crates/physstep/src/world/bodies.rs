//! Rigid bodies in a world: adding them, reading their state, loads applied by hand, and
//! the orientation rule of drifts.

use glam::{DMat3, DQuat, DVec3};

use super::World;
use crate::dynamics::SecondOrder;
use crate::error::{bounded, Error, Result};
use crate::integrators::registry::RUNAWAY;
use crate::rigid::body::{put_quat, put_vec3, quat, vec3, V_LEN, X_LEN};
use crate::rigid::inertia::Shape;
use crate::rigid::orientation::{self, Rule};

/// How to add a rigid body.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyParams {
    /// Its shape, in its own frame.
    pub shape: Shape,
    /// Mass, kg; `None` to take it from `density` (or density 1 when both are `None`).
    pub mass: Option<f64>,
    /// Density, kg/m^3, when `mass` is `None`.
    pub density: Option<f64>,
    /// Where the shape's origin is, m.
    pub position: [f64; 3],
    /// The shape frame's orientation as a quaternion `(w, x, y, z)` (normalised here).
    pub orientation: [f64; 4],
    /// Velocity of the centre of mass, m/s.
    pub velocity: [f64; 3],
    /// Angular velocity, rad/s, world frame.
    pub angular_velocity: [f64; 3],
}

impl Default for BodyParams {
    fn default() -> Self {
        Self {
            shape: Shape::Sphere { radius: 1.0 },
            mass: None,
            density: None,
            position: [0.0; 3],
            orientation: [1.0, 0.0, 0.0, 0.0],
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
        }
    }
}

impl World {
    /// Adds a rigid body (3D worlds only); returns its index. Its state is its centre of
    /// mass, its orientation, momentum and angular momentum; its principal frame is found
    /// from the shape's inertia.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field: a world that is not 3D, a bad shape, mass or
    /// density, a position or velocity not finite, a zero-length orientation;
    /// [`Error::Unsupported`] for a world that is a flow or a method that does not apply to
    /// bodies (Verlet). The world is unchanged.
    pub fn add_body(&mut self, p: &BodyParams) -> Result<usize> {
        self.refuse_flow("rigid bodies")?;
        if self.dim() != 3 {
            return Err(Error::invalid("dim", self.dim(), "3 for rigid bodies"));
        }
        crate::integrators::registry::applies_to(self.integrator.info(), true, false)?;
        let props = p.shape.mass_properties(p.mass, p.density)?;
        bounded("position", &p.position, RUNAWAY)?;
        bounded("velocity", &p.velocity, RUNAWAY)?;
        bounded("angular_velocity", &p.angular_velocity, RUNAWAY)?;
        let user = orientation::validate_quaternion("orientation", p.orientation)?;
        let axes = props.principal_axes;
        let frame_m = DMat3::from_cols(
            DVec3::from_array(axes[0]),
            DVec3::from_array(axes[1]),
            DVec3::from_array(axes[2]),
        );
        let frame = DQuat::from_mat3(&frame_m).normalize();
        let q = (user * frame).normalize();
        let inertia = DVec3::from_array(props.principal_moments);
        if !(inertia.min_element() > 0.0 && inertia.is_finite()) {
            return Err(Error::invalid(
                "inertia",
                format!("{:?}", props.principal_moments),
                "positive principal moments",
            ));
        }
        let center = user * DVec3::from_array(props.center) + DVec3::from_array(p.position);
        let momentum = DVec3::from_array(p.velocity) * props.mass;
        let omega = DVec3::from_array(p.angular_velocity);
        // L = R diag(I) R^T omega.
        let l = q * (inertia * (q.inverse() * omega));
        let b = &mut self.bodies;
        b.mass.push(props.mass);
        b.inertia.push(inertia);
        b.inv_inertia.push(inertia.recip());
        b.frame.push(frame);
        b.center.push(DVec3::from_array(props.center));
        b.force.push(DVec3::ZERO);
        b.torque.push(DVec3::ZERO);
        let mut xb = [0.0; X_LEN];
        put_vec3(&mut xb[..3], center);
        put_quat(&mut xb[3..], q);
        let mut vb = [0.0; V_LEN];
        put_vec3(&mut vb[..3], momentum);
        put_vec3(&mut vb[3..], l);
        let at = self.nx() - X_LEN;
        self.state.y.splice(at..at, xb);
        self.state.y.extend_from_slice(&vb);
        self.state.f.resize(self.state.y.len(), 0.0);
        self.touch();
        Ok(self.bodies.len() - 1)
    }

    /// The world's bodies (masses, inertia, the orientation rule).
    #[must_use]
    pub fn bodies(&self) -> &crate::rigid::body::Bodies {
        &self.bodies
    }

    /// The bodies' part of the state: positions `(c, q)` and momenta `(P, L)`, 7 and 6 per
    /// body.
    pub(super) fn body_state(&self) -> (&[f64], &[f64]) {
        let (np, nx) = (self.model.len(), self.nx());
        (&self.state.y[np..nx], &self.state.y[nx + np..])
    }

    fn body_index(&self, b: usize) -> Result<()> {
        if b >= self.bodies.len() {
            return Err(Error::invalid("body", b, format!("an index below {}", self.bodies.len())));
        }
        Ok(())
    }

    /// Centre of mass of body `b`, m.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body` for an index out of range.
    pub fn body_position(&self, b: usize) -> Result<[f64; 3]> {
        self.body_index(b)?;
        let x = &self.body_state().0[b * X_LEN..];
        Ok([x[0], x[1], x[2]])
    }

    /// Orientation of body `b`'s shape frame, `(w, x, y, z)`.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_orientation(&self, b: usize) -> Result<[f64; 4]> {
        self.body_index(b)?;
        let q = quat(&self.body_state().0[b * X_LEN + 3..]) * self.bodies.frame[b].inverse();
        Ok([q.w, q.x, q.y, q.z])
    }

    /// Velocity of body `b`'s centre of mass, m/s.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_velocity(&self, b: usize) -> Result<[f64; 3]> {
        self.body_index(b)?;
        let p = vec3(&self.body_state().1[b * V_LEN..]);
        Ok((p / self.bodies.mass[b]).to_array())
    }

    /// Angular momentum of body `b` about its centre of mass, kg m^2/s, world frame.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_angular_momentum(&self, b: usize) -> Result<[f64; 3]> {
        self.body_index(b)?;
        Ok(vec3(&self.body_state().1[b * V_LEN + 3..]).to_array())
    }

    /// Angular velocity of body `b`, rad/s, world frame.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_angular_velocity(&self, b: usize) -> Result<[f64; 3]> {
        self.body_index(b)?;
        let (x, v) = self.body_state();
        let q = quat(&x[b * X_LEN + 3..]);
        Ok(orientation::omega(q, self.bodies.inv_inertia[b], vec3(&v[b * V_LEN + 3..])).to_array())
    }

    /// Total angular momentum about the origin, kg m^2/s: particles' `m x x v` (3D worlds;
    /// zero otherwise) plus bodies' `c x P + L`.
    #[must_use]
    pub fn angular_momentum(&self) -> [f64; 3] {
        let mut total = DVec3::ZERO;
        if self.flow.is_none() && self.dim() == 3 {
            for (p, (x, v)) in
                self.positions().chunks_exact(3).zip(self.velocities().chunks_exact(3)).enumerate()
            {
                if self.model.inv_mass[p] > 0.0 {
                    total += vec3(x).cross(vec3(v)) * self.model.mass[p];
                }
            }
        }
        let (x, v) = self.body_state();
        for (xb, vb) in x.chunks_exact(X_LEN).zip(v.chunks_exact(V_LEN)) {
            total += vec3(xb).cross(vec3(vb)) + vec3(&vb[3..]);
        }
        total.to_array()
    }

    /// Applies `force` (N, world frame) to body `b` for the next step, at the world point
    /// `at` (the centre of mass when `None`), which adds the torque `(at - c) x force`.
    /// Loads add up until the next step takes them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body`, `force` or `at`.
    pub fn apply_force(&mut self, b: usize, force: [f64; 3], at: Option<[f64; 3]>) -> Result<()> {
        self.body_index(b)?;
        bounded("force", &force, RUNAWAY)?;
        let f = DVec3::from_array(force);
        let torque = match at {
            Some(at) => {
                bounded("at", &at, RUNAWAY)?;
                (DVec3::from_array(at) - DVec3::from_array(self.body_position(b)?)).cross(f)
            }
            None => DVec3::ZERO,
        };
        self.bodies.force[b] += f;
        self.bodies.torque[b] += torque;
        self.stale = true;
        Ok(())
    }

    /// Applies `torque` (N m, world frame) to body `b` for the next step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body` or `torque`.
    pub fn apply_torque(&mut self, b: usize, torque: [f64; 3]) -> Result<()> {
        self.body_index(b)?;
        bounded("torque", &torque, RUNAWAY)?;
        self.bodies.torque[b] += DVec3::from_array(torque);
        self.stale = true;
        Ok(())
    }

    /// Drops the loads applied by hand (after a step took them).
    pub(super) fn clear_loads(&mut self) {
        if self.bodies.force.iter().chain(&self.bodies.torque).any(|v| *v != DVec3::ZERO) {
            self.bodies.force.fill(DVec3::ZERO);
            self.bodies.torque.fill(DVec3::ZERO);
            self.stale = true;
        }
    }

    /// Chooses how drifts move orientations (split methods; flow methods integrate
    /// `q' = (0, omega) q / 2` and renormalise).
    pub fn set_orientation_rule(&mut self, rule: Rule) {
        self.bodies.rule = rule;
        self.integrator.reset();
    }
}
