//! The world's parts as the one [`System`] methods see: particles first, then rigid bodies,
//! in `y = [x_particles, (c, q)_bodies; v_particles, (P, L)_bodies]`.

use glam::DVec3;

use super::Model;
use crate::dynamics::{Second, SecondOrder, System};
use crate::forces::Endpoint;
use crate::rigid::body::{AngularForm, Bodies, Loads, V_LEN, X_LEN};

/// Particles and bodies together.
pub(crate) struct Parts<'a> {
    pub model: &'a mut Model,
    pub bodies: &'a Bodies,
    pub loads: Loads,
    /// Particle coordinates.
    pub np: usize,
    /// Scratch: spring loads per body.
    pub extra: &'a mut Vec<(DVec3, DVec3)>,
    /// Bodies' `dX` (`c'`, `q'`) left out of `rate`: a split method never reads it, and a
    /// call of several steps computes it once, when it is asked for (`World::refresh`).
    pub lazy: bool,
}

impl Parts<'_> {
    fn nx(&self) -> usize {
        self.np + X_LEN * self.bodies.len()
    }
}

impl System for Parts<'_> {
    fn dim(&self) -> usize {
        2 * self.np + (X_LEN + V_LEN) * self.bodies.len()
    }

    fn split(&self) -> Option<usize> {
        Some(self.nx())
    }

    fn jacobian(&mut self, t: f64, y: &[f64], j: &mut [f64], work: &mut Vec<f64>) -> bool {
        // Bodies have no analytic Jacobian (implicit methods difference them).
        self.bodies.is_empty() && Second(&mut *self.model).jacobian(t, y, j, work)
    }

    fn accel(&mut self, t: f64, x: &[f64], w: &[f64], a: &mut [f64]) {
        let np = self.np;
        if np > 0 {
            self.model.accel(t, &x[..np], &w[..np], &mut a[..np]);
        }
        let (nx, bodies) = (self.nx(), self.bodies);
        if bodies.springs.is_empty() && bodies.forces.is_empty() {
            bodies.accel(&self.loads, &x[np..], &w[np..], &mut a[np..], &[]);
            return;
        }
        // Springs between body points and particles or anchors: the force on the particle
        // is an acceleration now; the body's share (force and torque about its reference
        // point) is added with its other loads.
        self.extra.clear();
        self.extra.resize(bodies.len(), (DVec3::ZERO, DVec3::ZERO));
        let (xs, vs) = (&x[..nx], w);
        for s in &bodies.springs {
            let (f, arm) = s.force(bodies, np, xs, vs);
            let e = &mut self.extra[s.body];
            e.0 += f;
            e.1 += arm.cross(f);
            if let Endpoint::Particle(i) = s.other {
                let k = self.model.inv_mass()[i];
                for (ak, fk) in a[3 * i..3 * i + 3].iter_mut().zip(f.to_array()) {
                    *ak -= k * fk;
                }
            }
        }
        for g in &bodies.forces {
            let (p, vp, arm) = bodies.point(g.body, g.point, np, xs, vs);
            let mut f = [0.0; 3];
            let r =
                g.generator.0.add_forces(t, &p.to_array(), &vp.to_array(), &mut f).map_err(|r| (r, false));
            let r = r.and_then(|()| match f.iter().position(|c| !c.is_finite()) {
                None => Ok(()),
                Some(k) => Err((format!("force[0][{k}] = {} is not finite", f[k]), true)),
            });
            if let Err((reason, non_finite)) = r {
                // Poisoned: the step fails and is rolled back, and the world reports this.
                if self.model.failure.is_none() {
                    let name = g.generator.0.name().to_string();
                    self.model.failure = Some(crate::Error::Force { name, reason, non_finite });
                }
                a.fill(f64::NAN);
                return;
            }
            let f = DVec3::from_array(f);
            let e = &mut self.extra[g.body];
            e.0 += f;
            e.1 += arm.cross(f);
        }
        bodies.accel(&self.loads, &x[np..], &w[np..], &mut a[np..], self.extra);
    }

    fn drift(&mut self, x: &mut [f64], w: &[f64], h: f64) {
        let np = self.np;
        crate::integrators::axpy(&mut x[..np], h, &w[..np]);
        self.bodies.drift(&mut x[np..], &w[np..], h);
    }

    fn rate(&self, x: &[f64], v: &[f64], dx: &mut [f64]) {
        let np = self.np;
        dx[..np].copy_from_slice(&v[..np]);
        if !self.lazy {
            self.bodies.rate(&x[np..], &v[np..], &mut dx[np..]);
        }
    }

    fn velocity_dependent(&self) -> bool {
        let b = self.bodies;
        self.model.velocity_dependent()
            || (!b.is_empty()
                && (self.loads.linear != 0.0
                    || self.loads.quadratic != 0.0
                    || b.springs.iter().any(|s| s.damping != 0.0)
                    || b.angular_drag.iter().any(|c| *c != 0.0)
                    || b.forces.iter().any(|g| g.generator.0.velocity_dependent())
                    || matches!(
                        b.form,
                        // Both gyroscopic terms depend on the angular velocity (Catto's too:
                        // it was missed here, and methods that skip re-evaluating A after a
                        // kick kept one from the old velocity in `f`).
                        AngularForm::VelocityGyroscopic | AngularForm::VelocityImplicit
                    )))
    }

    fn vector_positions(&self) -> bool {
        self.bodies.is_empty()
    }

    fn project(&mut self, y: &mut [f64]) -> bool {
        let (np, nx) = (self.np, self.nx());
        self.bodies.project(&mut y[np..nx])
    }
}

/// Particles and bodies of a world as one system.
pub(crate) fn of<'a>(
    model: &'a mut Model,
    bodies: &'a Bodies,
    extra: &'a mut Vec<(DVec3, DVec3)>,
) -> Parts<'a> {
    let loads = loads(model);
    let np = model.len();
    Parts { model, bodies, loads, np, extra, lazy: false }
}

/// The world's forces as they act on bodies: uniform gravity and drag on the centre of mass
/// (the other forces join particles only).
pub(crate) fn loads(model: &Model) -> Loads {
    let mut l = Loads::default();
    for f in model.forces.iter() {
        match *f {
            crate::forces::Force::Gravity { g } => l.g += glam::DVec3::from_array(g),
            crate::forces::Force::Drag { linear, quadratic } => {
                l.linear += linear;
                l.quadratic += quadratic;
            }
            _ => {}
        }
    }
    l
}
