//! Rigid bodies as a part of a world: their parameters (structure of arrays) and what a
//! kick, a drift, a rate and a projection mean for them.
//!
//! A body's state lives in the world's flat state: its position (the centre of mass, m) and
//! orientation (a unit quaternion `(w, x, y, z)` from the body's principal frame to the
//! world) among the positions `X`, 7 numbers; its linear momentum `P` (kg m/s) and angular
//! momentum `L` (kg m^2/s, world frame) among the velocities `V`, 6 numbers. What a kick
//! adds to `V` per second is the force and the torque. The drift moves the centre by
//! `P / m h` and the orientation by the body's [`Rule`] with `L` held.

use glam::{DQuat, DVec3};

use super::orientation::{self, Rule};

/// Numbers of a body among the positions: centre (3), orientation (4).
pub const X_LEN: usize = 7;
/// Numbers of a body among the velocities: momentum (3), angular momentum (3).
pub const V_LEN: usize = 6;

/// The parameters of a world's rigid bodies (their state is in the world's state vector).
#[derive(Debug, Clone, Default)]
pub struct Bodies {
    /// Masses, kg.
    pub(crate) mass: Vec<f64>,
    /// Principal moments of inertia about the centre of mass, kg m^2.
    pub(crate) inertia: Vec<DVec3>,
    /// Their inverses, 1/(kg m^2).
    pub(crate) inv_inertia: Vec<DVec3>,
    /// The rotation from a body's principal frame to the frame its shape was given in.
    pub(crate) frame: Vec<DQuat>,
    /// The shape's centre of mass in the shape's frame, m.
    pub(crate) center: Vec<DVec3>,
    /// Forces applied by hand for the next step, N (world frame).
    pub(crate) force: Vec<DVec3>,
    /// Torques applied by hand for the next step, N m (world frame).
    pub(crate) torque: Vec<DVec3>,
    /// How a drift moves orientations.
    pub(crate) rule: Rule,
}

/// Reads three numbers as a vector.
#[inline]
pub(crate) fn vec3(s: &[f64]) -> DVec3 {
    DVec3::new(s[0], s[1], s[2])
}

/// Reads `(w, x, y, z)` as a quaternion.
#[inline]
pub(crate) fn quat(s: &[f64]) -> DQuat {
    DQuat::from_xyzw(s[1], s[2], s[3], s[0])
}

/// Writes a quaternion as `(w, x, y, z)`.
#[inline]
pub(crate) fn put_quat(s: &mut [f64], q: DQuat) {
    s[0] = q.w;
    s[1] = q.x;
    s[2] = q.y;
    s[3] = q.z;
}

/// Writes a vector.
#[inline]
pub(crate) fn put_vec3(s: &mut [f64], v: DVec3) {
    s[0] = v.x;
    s[1] = v.y;
    s[2] = v.z;
}

/// The loads the world's forces put on bodies, gathered once per evaluation.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Loads {
    /// Uniform gravity, m/s^2.
    pub g: DVec3,
    /// Linear drag coefficient, N s/m.
    pub linear: f64,
    /// Quadratic drag coefficient, N s^2/m^2.
    pub quadratic: f64,
}

impl Bodies {
    /// Number of bodies.
    #[must_use]
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// The orientation rule of drifts.
    #[must_use]
    pub fn rule(&self) -> Rule {
        self.rule
    }

    /// Masses, kg.
    #[must_use]
    pub fn mass(&self) -> &[f64] {
        &self.mass
    }

    /// The principal moments of inertia of body `b`, kg m^2.
    #[must_use]
    pub fn inertia(&self, b: usize) -> [f64; 3] {
        self.inertia[b].to_array()
    }

    /// `A` of the bodies (force and torque per body) at positions `x` and momenta `w`.
    pub(crate) fn accel(&self, loads: &Loads, x: &[f64], w: &[f64], a: &mut [f64]) {
        let _ = x;
        for (b, (wb, ab)) in w.chunks_exact(V_LEN).zip(a.chunks_exact_mut(V_LEN)).enumerate() {
            let m = self.mass[b];
            let p = vec3(&wb[..3]);
            let mut f = self.force[b] + loads.g * m;
            if loads.linear != 0.0 || loads.quadratic != 0.0 {
                let v = p / m;
                f -= v * (loads.linear + loads.quadratic * v.length());
            }
            put_vec3(&mut ab[..3], f);
            put_vec3(&mut ab[3..], self.torque[b]);
        }
    }

    /// Drift: centres by `P / m h`, orientations by the rule with `L` held.
    pub(crate) fn drift(&self, x: &mut [f64], w: &[f64], h: f64) {
        for (b, (xb, wb)) in x.chunks_exact_mut(X_LEN).zip(w.chunks_exact(V_LEN)).enumerate() {
            let c = vec3(&xb[..3]) + vec3(&wb[..3]) * (h / self.mass[b]);
            put_vec3(&mut xb[..3], c);
            let q = orientation::drift(self.rule, quat(&xb[3..]), self.inv_inertia[b], vec3(&wb[3..]), h);
            put_quat(&mut xb[3..], q);
        }
    }

    /// Rates of the positions: `P / m` and `q' = (0, omega) q / 2`.
    pub(crate) fn rate(&self, x: &[f64], v: &[f64], dx: &mut [f64]) {
        for (b, ((xb, vb), db)) in
            x.chunks_exact(X_LEN).zip(v.chunks_exact(V_LEN)).zip(dx.chunks_exact_mut(X_LEN)).enumerate()
        {
            put_vec3(&mut db[..3], vec3(&vb[..3]) / self.mass[b]);
            let q = quat(&xb[3..]);
            let omega = orientation::omega(q.normalize(), self.inv_inertia[b], vec3(&vb[3..]));
            let dq = DQuat::from_xyzw(omega.x, omega.y, omega.z, 0.0) * q * 0.5;
            put_quat(&mut db[3..], dq);
        }
    }

    /// Renormalises every orientation (after a flow method moved `q` off the unit sphere)
    /// and the rates with it.
    pub(crate) fn project(&self, x: &mut [f64], v: &[f64], dx: &mut [f64]) {
        for xb in x.chunks_exact_mut(X_LEN) {
            let q = quat(&xb[3..]).normalize();
            put_quat(&mut xb[3..], q);
        }
        self.rate(x, v, dx);
    }

    /// Kinetic energy of momenta `v` at positions `x`: `P^2 / 2m + L . omega / 2`, J.
    pub(crate) fn kinetic(&self, x: &[f64], v: &[f64]) -> f64 {
        x.chunks_exact(X_LEN)
            .zip(v.chunks_exact(V_LEN))
            .enumerate()
            .map(|(b, (xb, vb))| {
                let p = vec3(&vb[..3]);
                p.length_squared() / (2.0 * self.mass[b])
                    + orientation::kinetic(quat(&xb[3..]), self.inv_inertia[b], vec3(&vb[3..]))
            })
            .sum()
    }

    /// Gravitational potential energy `-m g . x` of the bodies at positions `x`, J.
    pub(crate) fn potential(&self, loads: &Loads, x: &[f64]) -> f64 {
        x.chunks_exact(X_LEN).enumerate().map(|(b, xb)| -self.mass[b] * loads.g.dot(vec3(&xb[..3]))).sum()
    }
}
