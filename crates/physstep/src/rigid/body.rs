//! Rigid bodies as a part of a world: their parameters (structure of arrays) and what a
//! kick, a drift, a rate and a projection mean for them.
//!
//! A body's state lives in the world's flat state: its position (the centre of mass, m) and
//! orientation (a unit quaternion `(w, x, y, z)` from the body's principal frame to the
//! world) among the positions `X`, 7 numbers; its linear momentum `P` (kg m/s) and angular
//! momentum `L` (kg m^2/s, world frame) among the velocities `V`, 6 numbers. What a kick
//! adds to `V` per second is the force and the torque. The drift moves the centre by
//! `P / m h` and the orientation by the body's [`Rule`] with `L` held.
//!
//! The angular slot of `V` holds what the world's [`AngularForm`] says: the angular momentum
//! `L` (the notes' form, the default) or the angular velocity `omega` (the velocity forms of
//! game engines, to compare). A pinned body (a top on its tip) holds a point fixed: its
//! position slot is that point, `P` stays zero, and `L` is taken about the point.

use glam::{DQuat, DVec3};

use super::orientation::{self, Rule};
use crate::error::{Error, Result};

/// What the angular slot of a body's velocities holds, and so what a kick integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AngularForm {
    /// The notes' form: angular momentum `L`, kicked by the torque (`L' = tau`); `omega` is
    /// derived from `L` at the current orientation, so gyroscopic motion is exact by
    /// construction. The default.
    #[default]
    Momentum,
    /// Angular velocity `omega`, kicked by `I^-1 tau` with the gyroscopic term ignored, as
    /// many game engines do: a free body spins about a fixed axis forever (no precession,
    /// no tennis-racket flip).
    Velocity,
    /// Angular velocity `omega`, kicked by `I^-1 (tau - omega x I omega)` (Euler's
    /// equations, the gyroscopic term explicit).
    VelocityGyroscopic,
    /// Angular velocity `omega` with the gyroscopic term implicit, as Catto's one Newton
    /// step does for semi-implicit Euler (Box2D, Bullet): in the body frame
    /// `d omega = -h J^-1 (omega x I omega)` with `J = I + h (skew(omega) I - skew(I omega))`
    /// at the world's step `h`. Stable at any spin, and it dissipates energy.
    VelocityImplicit,
}

/// Every angular form, in order.
pub const FORMS: [AngularForm; 4] = [
    AngularForm::Momentum,
    AngularForm::Velocity,
    AngularForm::VelocityGyroscopic,
    AngularForm::VelocityImplicit,
];

impl AngularForm {
    /// Its name: `momentum`, `velocity`, `velocity-gyroscopic`, `velocity-implicit`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Momentum => "momentum",
            Self::Velocity => "velocity",
            Self::VelocityGyroscopic => "velocity-gyroscopic",
            Self::VelocityImplicit => "velocity-implicit",
        }
    }

    /// The form named `name`.
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the valid names.
    pub fn from_name(name: &str) -> Result<Self> {
        FORMS
            .into_iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| Error::unknown("angular form", name, FORMS.iter().map(|f| f.name())))
    }

    /// One line on what it is.
    #[must_use]
    pub fn doc(self) -> &'static str {
        match self {
            Self::Momentum => "integrate L from torque, omega = I^-1 L (the notes; gyroscopic motion exact)",
            Self::Velocity => "integrate omega from I^-1 tau, gyroscopic term ignored (many engines)",
            Self::VelocityGyroscopic => "integrate omega from I^-1 (tau - omega x I omega), explicit",
            Self::VelocityImplicit => {
                "integrate omega, the gyroscopic term by one implicit Newton step (Catto; Box2D, Bullet)"
            }
        }
    }
}

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
    /// The centre of mass relative to the body's reference point (its position slot), in
    /// the principal frame: zero for a free body, the offset from the pin for a pinned one.
    pub(crate) offset: Vec<DVec3>,
    /// Whether the reference point is pinned to the world (a top on its tip).
    pub(crate) pinned: Vec<bool>,
    /// Angular drag coefficients: a torque `-c omega`, N m s.
    pub(crate) angular_drag: Vec<f64>,
    /// The body's reference point (its centre of mass, or its pin) in its shape's frame, m.
    pub(crate) reference: Vec<DVec3>,
    /// Forces applied by hand for the next step, N (world frame).
    pub(crate) force: Vec<DVec3>,
    /// Torques applied by hand for the next step, N m (world frame).
    pub(crate) torque: Vec<DVec3>,
    /// How a drift moves orientations.
    pub(crate) rule: Rule,
    /// What the angular slot holds.
    pub(crate) form: AngularForm,
    /// The world's fixed step, s: the implicit gyroscopic form takes its Newton step there
    /// (whatever step a method's kick makes).
    pub(crate) h: f64,
    /// Springs from body points to particles or anchors.
    pub(crate) springs: Vec<BodySpring>,
    /// User forces at body points.
    pub(crate) forces: Vec<BodyForce>,
}

/// A user force acting at a point of a body: the generator sees that point as one particle
/// (position and velocity, 3 numbers each) and returns the force on it.
#[derive(Debug, Clone)]
pub struct BodyForce {
    /// The body.
    pub body: usize,
    /// The point, from the body's reference point, in its principal frame, m.
    pub point: DVec3,
    /// The force law.
    pub generator: crate::forces::UserForce,
}

/// A damped spring from a point of a body to a particle or a fixed point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodySpring {
    /// The body.
    pub body: usize,
    /// The point, from the body's reference point, in its principal frame, m.
    pub point: DVec3,
    /// The other end.
    pub other: crate::forces::Endpoint,
    /// Stiffness, N/m.
    pub stiffness: f64,
    /// Rest length, m.
    pub rest_length: f64,
    /// Damping along the spring, N s/m.
    pub damping: f64,
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

    /// The world angular velocity of body `b` at orientation `q` with angular slot `w`.
    #[inline]
    pub(crate) fn omega(&self, b: usize, q: DQuat, w: DVec3) -> DVec3 {
        match self.form {
            AngularForm::Momentum => orientation::omega(q, self.inv_inertia[b], w),
            _ => w,
        }
    }

    /// The angular momentum of body `b` (about its reference point) at `q` with slot `w`.
    #[inline]
    pub(crate) fn momentum(&self, b: usize, q: DQuat, w: DVec3) -> DVec3 {
        match self.form {
            AngularForm::Momentum => w,
            _ => q * (self.inertia[b] * (q.conjugate() * w)),
        }
    }

    /// What the angular slot holds for angular momentum `l` at `q` under `form`.
    pub(crate) fn slot(&self, form: AngularForm, b: usize, q: DQuat, l: DVec3) -> DVec3 {
        match form {
            AngularForm::Momentum => l,
            _ => orientation::omega(q, self.inv_inertia[b], l),
        }
    }

    /// The centre of mass of body `b` whose position slot is `xb`, and its velocity.
    pub(crate) fn center(&self, b: usize, xb: &[f64], vb: &[f64]) -> (DVec3, DVec3) {
        let q = quat(&xb[3..]);
        let r = q * self.offset[b];
        let c = vec3(&xb[..3]) + r;
        let v = if self.pinned[b] {
            self.omega(b, q, vec3(&vb[3..])).cross(r)
        } else {
            vec3(&vb[..3]) / self.mass[b]
        };
        (c, v)
    }

    /// `A` of the bodies at positions `x` and velocities `w`: per body what a kick adds to
    /// `P` (the force; zero when pinned) and to the angular slot (the torque about the
    /// reference point, or what it makes of `omega`). `extra` holds loads from springs.
    pub(crate) fn accel(&self, loads: &Loads, x: &[f64], w: &[f64], a: &mut [f64], extra: &[(DVec3, DVec3)]) {
        for (b, ((xb, wb), ab)) in
            x.chunks_exact(X_LEN).zip(w.chunks_exact(V_LEN)).zip(a.chunks_exact_mut(V_LEN)).enumerate()
        {
            let m = self.mass[b];
            let q = quat(&xb[3..]);
            let mut f = self.force[b] + loads.g * m;
            if loads.linear != 0.0 || loads.quadratic != 0.0 {
                let v = self.center(b, xb, wb).1;
                f -= v * (loads.linear + loads.quadratic * v.length());
            }
            // Spring loads come with their torque about the reference point already.
            let (fs, ts) = extra.get(b).copied().unwrap_or_default();
            let mut tau = self.torque[b] + ts;
            if self.angular_drag[b] != 0.0 {
                tau -= self.omega(b, q, vec3(&wb[3..])) * self.angular_drag[b];
            }
            let fe = if self.pinned[b] {
                // The pin takes the forces; about it, those at the centre turn the body.
                tau += (q * self.offset[b]).cross(f);
                DVec3::ZERO
            } else {
                f + fs
            };
            put_vec3(&mut ab[..3], fe);
            let spin = vec3(&wb[3..]);
            let da = match self.form {
                AngularForm::Momentum => tau,
                AngularForm::Velocity => orientation::omega(q, self.inv_inertia[b], tau),
                AngularForm::VelocityGyroscopic => {
                    let l = self.momentum(b, q, spin);
                    orientation::omega(q, self.inv_inertia[b], tau - spin.cross(l))
                }
                AngularForm::VelocityImplicit => {
                    orientation::omega(q, self.inv_inertia[b], tau) + self.implicit_gyroscopic(b, q, spin)
                }
            };
            put_vec3(&mut ab[3..], da);
        }
    }

    /// Catto's implicit gyroscopic rate of body `b` at `q` with angular velocity `spin`
    /// (world frame): one Newton step on `I (w - w1) + h w x I w = 0` from `w1` in the body
    /// frame, `d w = -h J^-1 (w1 x I w1)` with `J = I + h (skew(w1) I - skew(I w1))`,
    /// divided by `h`, the world's step (before the first step `h = 0`: the explicit term).
    fn implicit_gyroscopic(&self, b: usize, q: DQuat, spin: DVec3) -> DVec3 {
        let i = glam::DMat3::from_diagonal(self.inertia[b]);
        q * orientation::implicit_gyroscopic_rate(i, q.conjugate() * spin, self.h)
    }

    /// Drift: reference points by `P / m h`, orientations by the rule with the angular
    /// momentum (momentum form) or the angular velocity (velocity forms) held.
    pub(crate) fn drift(&self, x: &mut [f64], w: &[f64], h: f64) {
        for (b, (xb, wb)) in x.chunks_exact_mut(X_LEN).zip(w.chunks_exact(V_LEN)).enumerate() {
            if !self.pinned[b] {
                let c = vec3(&xb[..3]) + vec3(&wb[..3]) * (h / self.mass[b]);
                put_vec3(&mut xb[..3], c);
            }
            let q = quat(&xb[3..]);
            let l = self.momentum(b, q, vec3(&wb[3..]));
            put_quat(&mut xb[3..], orientation::drift(self.drift_rule(), q, self.inv_inertia[b], l, h));
        }
    }

    /// Rates of the positions: `P / m` and `q' = (0, omega) q / 2`.
    pub(crate) fn rate(&self, x: &[f64], v: &[f64], dx: &mut [f64]) {
        for (b, ((xb, vb), db)) in
            x.chunks_exact(X_LEN).zip(v.chunks_exact(V_LEN)).zip(dx.chunks_exact_mut(X_LEN)).enumerate()
        {
            put_vec3(&mut db[..3], vec3(&vb[..3]) / self.mass[b]);
            let q = quat(&xb[3..]);
            // A flow method's stage leaves q off the unit sphere; omega is of the rotation.
            let unit = if (q.length_squared() - 1.0).abs() > 8.0 * f64::EPSILON { q.normalize() } else { q };
            let omega = self.omega(b, unit, vec3(&vb[3..]));
            let dq = DQuat::from_xyzw(omega.x, omega.y, omega.z, 0.0) * q * 0.5;
            put_quat(&mut db[3..], dq);
        }
    }

    /// Renormalises every orientation that left the unit sphere by more than rounding (a
    /// flow method's step; a drift's rules return unit quaternions, which are left alone:
    /// normalising is not idempotent in the last bit); whether any changed.
    pub(crate) fn project(&self, x: &mut [f64]) -> bool {
        let mut changed = false;
        for xb in x.chunks_exact_mut(X_LEN) {
            let q = quat(&xb[3..]);
            if (q.length_squared() - 1.0).abs() > 8.0 * f64::EPSILON {
                put_quat(&mut xb[3..], q.normalize());
                changed = true;
            }
        }
        changed
    }

    /// Kinetic energy at positions `x`, velocities `v`: `P^2 / 2m + L . omega / 2` (about the
    /// pin for a pinned body), J.
    pub(crate) fn kinetic(&self, x: &[f64], v: &[f64]) -> f64 {
        x.chunks_exact(X_LEN)
            .zip(v.chunks_exact(V_LEN))
            .enumerate()
            .map(|(b, (xb, vb))| {
                let q = quat(&xb[3..]);
                let w = vec3(&vb[3..]);
                let rot = 0.5 * self.omega(b, q, w).dot(self.momentum(b, q, w));
                vec3(&vb[..3]).length_squared() / (2.0 * self.mass[b]) + rot
            })
            .sum()
    }

    /// Gravitational potential energy `-m g . c` of the bodies' centres, J.
    pub(crate) fn potential(&self, loads: &Loads, x: &[f64], v: &[f64]) -> f64 {
        x.chunks_exact(X_LEN)
            .zip(v.chunks_exact(V_LEN))
            .enumerate()
            .map(|(b, (xb, vb))| -self.mass[b] * loads.g.dot(self.center(b, xb, vb).0))
            .sum()
    }

    /// The angular form.
    #[must_use]
    pub fn form(&self) -> AngularForm {
        self.form
    }

    /// The rule a drift uses: the chosen one, except that the splitting (a free-body motion
    /// in which `omega` changes) needs the momentum form; with `omega` held by a velocity
    /// form a drift is the exact rotation at that `omega` (the exponential map).
    #[must_use]
    pub fn drift_rule(&self) -> Rule {
        match (self.rule, self.form) {
            (Rule::Splitting, form) if form != AngularForm::Momentum => Rule::Exponential,
            (rule, _) => rule,
        }
    }
}

impl Bodies {
    /// A point of body `b` given in its shape's frame, as an arm from the body's reference
    /// point in its principal frame (what springs and forces at a point keep).
    pub(crate) fn arm(&self, b: usize, point: [f64; 3]) -> DVec3 {
        self.frame[b].inverse() * (DVec3::from_array(point) - self.reference[b])
    }

    /// World position and velocity of the point `point` (from body `b`'s reference point, in
    /// its principal frame) at the world's positions `x` and velocities `v` (`np` particle
    /// coordinates first), and its arm from the reference point.
    pub(crate) fn point(
        &self,
        b: usize,
        point: DVec3,
        np: usize,
        x: &[f64],
        v: &[f64],
    ) -> (DVec3, DVec3, DVec3) {
        let (xb, vb) = (&x[np + b * X_LEN..], &v[np + b * V_LEN..]);
        let q = quat(&xb[3..]);
        let arm = q * point;
        let v_ref = if self.pinned[b] { DVec3::ZERO } else { vec3(&vb[..3]) / self.mass[b] };
        (vec3(&xb[..3]) + arm, v_ref + self.omega(b, q, vec3(&vb[3..])).cross(arm), arm)
    }
}

impl BodySpring {
    /// The force on the body's point (its opposite acts on the other end) and the point's
    /// arm from the body's reference point, world frame, at positions `x` and velocities
    /// `v` of the whole world (`np` particle coordinates first, 3 per particle).
    pub(crate) fn force(&self, bodies: &Bodies, np: usize, x: &[f64], v: &[f64]) -> (DVec3, DVec3) {
        let (p, vp, arm) = bodies.point(self.body, self.point, np, x, v);
        let (xo, vo) = match self.other {
            crate::forces::Endpoint::Particle(i) => (vec3(&x[3 * i..]), vec3(&v[3 * i..])),
            crate::forces::Endpoint::Anchor(a) => (DVec3::from_array(a), DVec3::ZERO),
        };
        let (d, w) = (xo - p, vo - vp);
        let f = if self.rest_length == 0.0 {
            d * self.stiffness + w * self.damping
        } else {
            let r = d.length();
            if r == 0.0 {
                DVec3::ZERO
            } else {
                let u = d / r;
                u * (self.stiffness * (r - self.rest_length) + self.damping * w.dot(u))
            }
        };
        (f, arm)
    }

    /// Its length `|d|` at positions `x`, m.
    pub(crate) fn length(&self, np: usize, x: &[f64]) -> f64 {
        let xb = &x[np + self.body * X_LEN..];
        let p = vec3(&xb[..3]) + quat(&xb[3..]) * self.point;
        let xo = match self.other {
            crate::forces::Endpoint::Particle(i) => vec3(&x[3 * i..]),
            crate::forces::Endpoint::Anchor(a) => DVec3::from_array(a),
        };
        (xo - p).length()
    }

    /// Its potential energy `k (|d| - rest)^2 / 2` at positions `x`, J.
    pub(crate) fn potential(&self, np: usize, x: &[f64]) -> f64 {
        let stretch = self.length(np, x) - self.rest_length;
        0.5 * self.stiffness * stretch * stretch
    }
}
