//! Rigid bodies in a world: adding them, reading their state, loads applied by hand, and
//! the orientation rule of drifts.

use glam::{DMat3, DQuat, DVec3};

use super::World;
use crate::dynamics::SecondOrder;
use crate::error::{bounded, Error, Result};
use crate::limits::RUNAWAY;
use crate::rigid::body::{put_quat, put_vec3, quat, vec3, AngularForm, BodySpring, V_LEN, X_LEN};
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
    /// A point of the shape (shape frame, m) pinned to the world where it starts: a ball
    /// joint to the world, a top on its tip. The body then turns about it (its velocity
    /// follows from its spin: `velocity` must be zero).
    pub pivot: Option<[f64; 3]>,
    /// Angular drag: a torque `-c omega`, N m s (0 for none), like a game engine's per-body
    /// angular damping; the world's `Drag` force acts on the centre's velocity.
    pub angular_drag: f64,
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
            pivot: None,
            angular_drag: 0.0,
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
        if !(p.angular_drag.is_finite() && (0.0..=crate::limits::PARAM_MAX).contains(&p.angular_drag)) {
            return Err(Error::invalid(
                "angular_drag",
                crate::error::num(p.angular_drag),
                "a number in [0, 1e12]",
            ));
        }
        let mut inertia_m = props.inertia;
        let center_s = DVec3::from_array(props.center);
        let reference = match p.pivot {
            None => center_s,
            Some(pin) => {
                bounded("pivot", &pin, RUNAWAY)?;
                if p.velocity.iter().any(|v| *v != 0.0) {
                    return Err(Error::invalid(
                        "velocity",
                        format!("{:?}", p.velocity),
                        "[0, 0, 0] for a pinned body (its centre moves with its spin)",
                    ));
                }
                // Inertia about the pin: I_c + m (|d|^2 1 - d d^T), d from the pin to the centre.
                let d = center_s - DVec3::from_array(pin);
                let (da, m) = (d.to_array(), props.mass);
                for (i, row) in inertia_m.iter_mut().enumerate() {
                    for (j, e) in row.iter_mut().enumerate() {
                        *e += m * (if i == j { d.length_squared() } else { 0.0 } - da[i] * da[j]);
                    }
                }
                DVec3::from_array(pin)
            }
        };
        let (moments, axes) = crate::rigid::inertia::symmetric_eigen(&inertia_m);
        let frame_m = DMat3::from_cols(
            DVec3::from_array(axes[0]),
            DVec3::from_array(axes[1]),
            DVec3::from_array(axes[2]),
        );
        let frame = DQuat::from_mat3(&frame_m).normalize();
        let q = (user * frame).normalize();
        let inertia = DVec3::from_array(moments);
        if !(inertia.min_element() > 0.0 && inertia.is_finite()) {
            return Err(Error::invalid("inertia", format!("{moments:?}"), "positive principal moments"));
        }
        let offset = frame.inverse() * (center_s - reference);
        let origin = user * reference + DVec3::from_array(p.position);
        let momentum =
            if p.pivot.is_some() { DVec3::ZERO } else { DVec3::from_array(p.velocity) * props.mass };
        let omega = DVec3::from_array(p.angular_velocity);
        // L = R diag(I) R^T omega (about the reference point).
        let l = q * (inertia * (q.inverse() * omega));
        let b = &mut self.bodies;
        b.mass.push(props.mass);
        b.inertia.push(inertia);
        b.inv_inertia.push(inertia.recip());
        b.frame.push(frame);
        b.reference.push(reference);
        b.offset.push(offset);
        b.pinned.push(p.pivot.is_some());
        b.angular_drag.push(p.angular_drag);
        b.force.push(DVec3::ZERO);
        b.torque.push(DVec3::ZERO);
        let slot = b.slot(b.form, b.len() - 1, q, l);
        let mut xb = [0.0; X_LEN];
        put_vec3(&mut xb[..3], origin);
        put_quat(&mut xb[3..], q);
        let mut vb = [0.0; V_LEN];
        put_vec3(&mut vb[..3], momentum);
        put_vec3(&mut vb[3..], slot);
        let at = self.nx() - X_LEN;
        self.state.y.splice(at..at, xb);
        self.state.y.extend_from_slice(&vb);
        self.state.f.resize(self.state.y.len(), 0.0);
        self.body_params.push(p.clone());
        self.ids.bodies.push(1);
        self.touch();
        Ok(self.bodies.len() - 1)
    }

    /// Each body's parameters as it was added (its shape, mass, initial pose and velocities).
    #[must_use]
    pub fn body_params(&self) -> &[BodyParams] {
        &self.body_params
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
        Ok(self.body_center(b)?.0.to_array())
    }

    /// Centre of mass of body `b` and its velocity.
    fn body_center(&self, b: usize) -> Result<(DVec3, DVec3)> {
        self.body_index(b)?;
        let (x, v) = self.body_state();
        Ok(self.bodies.center(b, &x[b * X_LEN..], &v[b * V_LEN..]))
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

    /// Sets the state of body `b` by hand (a teleport): its centre of mass `position` (m),
    /// the `velocity` of its centre (m/s), the `orientation` of its shape frame (a quaternion
    /// `(w, x, y, z)`, normalised as [`World::add_body`] normalises it) and its
    /// `angular_velocity` (rad/s, world frame); `None` keeps that part as it is (a new
    /// orientation keeps the angular velocity, not the angular momentum). Validated as
    /// [`World::add_body`]; as [`World::set_positions`] does, it restarts a method that
    /// carries memory and the derivative is evaluated again before the next step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body` (out of range), `position`, `velocity`,
    /// `angular_velocity` (not finite, or past 1e100), `orientation` (not finite, or of
    /// length below 1e-12), or, for a pinned body (which turns about its pin), a `position`
    /// or a nonzero `velocity`; the world is unchanged.
    pub fn set_body_state(
        &mut self,
        b: usize,
        position: Option<[f64; 3]>,
        velocity: Option<[f64; 3]>,
        orientation: Option<[f64; 4]>,
        angular_velocity: Option<[f64; 3]>,
    ) -> Result<()> {
        self.body_index(b)?;
        let pinned = self.bodies.pinned[b];
        if let Some(x) = position {
            bounded("position", &x, RUNAWAY)?;
            if pinned {
                return Err(Error::invalid(
                    "position",
                    format!("{x:?}"),
                    "left as it is for a pinned body (it turns about its pin: set its orientation)",
                ));
            }
        }
        if let Some(v) = velocity {
            bounded("velocity", &v, RUNAWAY)?;
            if pinned && v.iter().any(|c| *c != 0.0) {
                return Err(Error::invalid(
                    "velocity",
                    format!("{v:?}"),
                    "[0, 0, 0] for a pinned body (its centre moves with its spin)",
                ));
            }
        }
        if let Some(w) = angular_velocity {
            bounded("angular_velocity", &w, RUNAWAY)?;
        }
        let user = orientation.map(|q| orientation::validate_quaternion("orientation", q)).transpose()?;
        let omega = match angular_velocity {
            Some(w) => Some(DVec3::from_array(w)),
            None if user.is_some() => Some(DVec3::from_array(self.body_angular_velocity(b)?)),
            None => None,
        };
        // Everything checked: write.
        let (np, nx) = (self.model.len(), self.nx());
        let xb = np + b * X_LEN;
        let vb = nx + np + b * V_LEN;
        let mut q = quat(&self.state.y[xb + 3..]);
        if let Some(user) = user {
            q = (user * self.bodies.frame[b]).normalize();
            put_quat(&mut self.state.y[xb + 3..xb + X_LEN], q);
        }
        if let Some(x) = position {
            put_vec3(&mut self.state.y[xb..xb + 3], DVec3::from_array(x));
        }
        if let (Some(v), false) = (velocity, pinned) {
            put_vec3(&mut self.state.y[vb..vb + 3], DVec3::from_array(v) * self.bodies.mass[b]);
        }
        if let Some(omega) = omega {
            // L = R diag(I) R^T omega, as `add_body` sets it.
            let l = q * (self.bodies.inertia[b] * (q.inverse() * omega));
            let slot = self.bodies.slot(self.bodies.form, b, q, l);
            put_vec3(&mut self.state.y[vb + 3..vb + V_LEN], slot);
        }
        // The body as a scene file would add it now.
        let (center, _) = self.body_center(b)?;
        let user_q = q * self.bodies.frame[b].inverse();
        let reference = self.bodies.reference[b];
        let p = &mut self.body_params[b];
        if let Some(q) = orientation {
            p.orientation = q;
        }
        if !pinned {
            p.position = (center - user_q * reference).to_array();
        }
        if let Some(v) = velocity {
            p.velocity = v;
        }
        if let Some(w) = omega {
            p.angular_velocity = w.to_array();
        }
        self.touch();
        Ok(())
    }

    /// Velocity of body `b`'s centre of mass, m/s.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_velocity(&self, b: usize) -> Result<[f64; 3]> {
        Ok(self.body_center(b)?.1.to_array())
    }

    /// Angular momentum of body `b` about its reference point (its centre of mass, or its
    /// pin), kg m^2/s, world frame.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_angular_momentum(&self, b: usize) -> Result<[f64; 3]> {
        self.body_index(b)?;
        let (x, v) = self.body_state();
        let q = quat(&x[b * X_LEN + 3..]);
        Ok(self.bodies.momentum(b, q, vec3(&v[b * V_LEN + 3..])).to_array())
    }

    /// Angular velocity of body `b`, rad/s, world frame.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_angular_velocity(&self, b: usize) -> Result<[f64; 3]> {
        self.body_index(b)?;
        let (x, v) = self.body_state();
        let q = quat(&x[b * X_LEN + 3..]);
        Ok(self.bodies.omega(b, q, vec3(&v[b * V_LEN + 3..])).to_array())
    }

    /// Angular velocity of body `b` in its principal frame (the axes of its principal moments,
    /// ascending), rad/s.
    ///
    /// # Errors
    /// As [`World::body_position`].
    pub fn body_spin(&self, b: usize) -> Result<[f64; 3]> {
        let omega = DVec3::from_array(self.body_angular_velocity(b)?);
        let q = quat(&self.body_state().0[b * X_LEN + 3..]);
        Ok((q.conjugate() * omega).to_array())
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
        for (b, (xb, vb)) in x.chunks_exact(X_LEN).zip(v.chunks_exact(V_LEN)).enumerate() {
            // About the origin: L about the reference point plus the reference point's arm
            // times the momentum of the centre (m v_c; P for a free body).
            let q = quat(&xb[3..]);
            let (_, vc) = self.bodies.center(b, xb, vb);
            total += self.bodies.momentum(b, q, vec3(&vb[3..])) + vec3(xb).cross(vc * self.bodies.mass[b]);
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
        self.derivative = super::Derivative::Stale;
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
        self.derivative = super::Derivative::Stale;
        Ok(())
    }

    /// Drops the loads applied by hand (after a step took them).
    pub(super) fn clear_loads(&mut self) {
        if self.bodies.force.iter().chain(&self.bodies.torque).any(|v| *v != DVec3::ZERO) {
            self.bodies.force.fill(DVec3::ZERO);
            self.bodies.torque.fill(DVec3::ZERO);
            self.derivative = super::Derivative::Stale;
        }
    }

    /// Chooses what the angular slot of bodies holds and so what kicks integrate (see
    /// [`AngularForm`]); the bodies' state is converted (their angular momentum kept).
    pub fn set_angular_form(&mut self, form: AngularForm) {
        let np = self.model.len();
        let nx = self.nx();
        for b in 0..self.bodies.len() {
            let q = quat(&self.state.y[np + b * X_LEN + 3..]);
            let at = nx + np + b * V_LEN + 3;
            let l = self.bodies.momentum(b, q, vec3(&self.state.y[at..]));
            put_vec3(&mut self.state.y[at..at + 3], self.bodies.slot(form, b, q, l));
        }
        self.bodies.form = form;
        self.touch();
    }

    /// Adds a damped spring from `point` of body `body` (in the shape's frame, m) to
    /// `other` (a particle or a fixed point): the force `k (|d| - rest) u + c (w . u) u` on
    /// the point, its opposite on the other end (`rest = 0`: the linear `k d + c w`).
    /// `rest_length` defaults to the current distance.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body`, `point`, `other`, `stiffness`, `rest_length`
    /// or `damping`; the world is unchanged.
    pub fn add_body_spring(
        &mut self,
        body: usize,
        point: [f64; 3],
        other: crate::forces::Endpoint,
        stiffness: f64,
        rest_length: Option<f64>,
        damping: f64,
    ) -> Result<()> {
        self.body_index(body)?;
        bounded("point", &point, RUNAWAY)?;
        match other {
            crate::forces::Endpoint::Particle(i) if i >= self.len() => {
                return Err(Error::invalid("other", i, format!("a particle index below {}", self.len())));
            }
            crate::forces::Endpoint::Anchor(a) => bounded("other", &a, RUNAWAY)?,
            crate::forces::Endpoint::Particle(_) => {}
        }
        for (name, v) in [("stiffness", stiffness), ("damping", damping)] {
            if !(v.is_finite() && (0.0..=crate::limits::PARAM_MAX).contains(&v)) {
                return Err(Error::invalid(name, crate::error::num(v), "a number in [0, 1e12]"));
            }
        }
        let arm = self.bodies.arm(body, point);
        let mut spring = BodySpring { body, point: arm, other, stiffness, rest_length: 0.0, damping };
        let np = self.model.len();
        let x = &self.state.y[..self.nx()];
        let rest = match rest_length {
            Some(r) => r,
            None => spring.length(np, x),
        };
        if !(rest.is_finite() && (0.0..=crate::limits::PARAM_MAX).contains(&rest)) {
            return Err(Error::invalid("rest_length", crate::error::num(rest), "a number in [0, 1e12]"));
        }
        spring.rest_length = rest;
        self.bodies.springs.push(spring);
        self.ids.body_springs.push(1);
        self.touch();
        Ok(())
    }

    /// Gives the body spring added last the arm `arm` (from its body's reference point, in
    /// the principal frame, m), as a scene file written by `scenes::file::structure` holds it:
    /// the point in the shape's frame, rotated there and back, may differ in the last bit.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `arm` when there is no body spring or it is not finite
    /// and bounded.
    pub(crate) fn set_last_body_spring_arm(&mut self, arm: [f64; 3]) -> Result<()> {
        bounded("arm", &arm, RUNAWAY)?;
        let Some(spring) = self.bodies.springs.last_mut() else {
            return Err(Error::invalid("arm", "given", "on a body spring"));
        };
        spring.point = DVec3::from_array(arm);
        self.touch();
        Ok(())
    }

    /// Adds a user force acting at `point` of body `body` (in the shape's frame, m): the
    /// generator sees that point as one particle (its world position and velocity) and
    /// returns the force on it, which also turns the body (`arm x F`). Its potential, if it
    /// has one, joins the energy; without one the energy is unknown. Returns its index
    /// among the body forces.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `body` or `point`; the world is unchanged.
    pub fn add_body_force(
        &mut self,
        body: usize,
        point: [f64; 3],
        generator: std::sync::Arc<dyn crate::forces::ForceGenerator>,
    ) -> Result<usize> {
        self.body_index(body)?;
        bounded("point", &point, RUNAWAY)?;
        let arm = self.bodies.arm(body, point);
        let generator = crate::forces::UserForce(generator);
        self.bodies.forces.push(crate::rigid::body::BodyForce { body, point: arm, generator });
        self.ids.body_forces.push(1);
        self.touch();
        Ok(self.bodies.forces.len() - 1)
    }

    /// Body orientations to draw, `(w, x, y, z)`: slerped between the state before the last
    /// step of the latest `advance` and the current one by `alpha`.
    #[must_use]
    pub fn interpolated_body_orientations(&self) -> Vec<[f64; 4]> {
        let alpha = self.alpha();
        (0..self.bodies.len())
            .map(|b| {
                let now = self.body_orientation(b).unwrap_or([1.0, 0.0, 0.0, 0.0]);
                let Some(before) = self.prev_q.get(b).filter(|_| self.prev_q.len() == self.bodies.len())
                else {
                    return now;
                };
                let q = orientation::slerp(quat(before), quat(&now), alpha);
                [q.w, q.x, q.y, q.z]
            })
            .collect()
    }

    /// Keeps the body orientations before a frame's last step (for interpolation).
    pub(super) fn keep_orientations(&mut self) {
        self.prev_q.clear();
        for b in 0..self.bodies.len() {
            let q = self.body_orientation(b).unwrap_or([1.0, 0.0, 0.0, 0.0]);
            self.prev_q.push(q);
        }
    }

    /// Chooses how drifts move orientations (split methods; flow methods integrate
    /// `q' = (0, omega) q / 2` and renormalise).
    pub fn set_orientation_rule(&mut self, rule: Rule) {
        self.bodies.rule = rule;
        self.integrator.reset();
    }
}
