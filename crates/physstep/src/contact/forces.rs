//! Forces on solids (docs/contact.md, "Forces on solids"): drag, springs between points,
//! loads applied by hand and the user's forces at points.
//!
//! ```text
//! drag      per solid, Box2D's form: in each substep v *= 1 / (1 + h c_lin),
//!           w *= 1 / (1 + h c_ang) (1/s; exact decay exp(-c t) as h -> 0)
//! springs   Hooke plus damping along the line between two solids' points (or a solid's point
//!           and a fixed anchor): F = k (|d| - rest) u + c (dv . u) u on a's point, -F on b's,
//!           and the torques of the two at their arms (rest 0: the linear k d + c dv)
//! loads     a force (at a point: its torque too) and a torque per solid, held constant over
//!           the step's substeps: what was applied by hand for this step, plus the user's
//!           forces evaluated once at the step's start
//! ```
//!
//! All of it acts in each substep's velocity integration, before gravity and the contact
//! passes ([`integrate`]): the springs' forces from the substep's positions and velocities
//! (every spring from the same state, then applied), then `v = v / (1 + h c) + h F / m`.
//! Nothing here runs for solids without them: such a world steps with the same bits as
//! before they existed.

use super::space::{Space, Vect};
use super::{Body, Kind};
use crate::error::{num, Error, Result};
use crate::limits::PARAM_MAX;

/// A spring between a point of solid `a` and a point of solid `b` (or a fixed point of the
/// world), as it was made: what a scene file keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct SolidSpring {
    /// The first solid.
    pub a: usize,
    /// Its end on `a`, in `a`'s frame (the frame its shape is given in), m.
    pub point_a: Vec<f64>,
    /// The second solid, or `None`: the world.
    pub b: Option<usize>,
    /// Its end on `b`, in `b`'s frame; with `b` = `None` a fixed point in world
    /// coordinates, m.
    pub point_b: Vec<f64>,
    /// Stiffness, N/m (>= 0).
    pub stiffness: f64,
    /// Rest length, m (>= 0); `None`: the distance between the two ends when it is added
    /// (then kept as a number).
    pub rest_length: Option<f64>,
    /// Damping along the line, N s/m (>= 0).
    pub damping: f64,
}

impl SolidSpring {
    /// A spring of `stiffness` from `point_a` of solid `a` to the world point `anchor`, its
    /// rest length the distance now, no damping.
    #[must_use]
    pub fn to_world(a: usize, point_a: &[f64], anchor: &[f64], stiffness: f64) -> Self {
        Self {
            a,
            point_a: point_a.to_vec(),
            b: None,
            point_b: anchor.to_vec(),
            stiffness,
            rest_length: None,
            damping: 0.0,
        }
    }
}

/// A spring as the substeps use it: arms from the centres of mass in the bodies' frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Spring<S: Space> {
    a: usize,
    b: Option<usize>,
    /// `a`'s end from its centre of mass, in its frame.
    arm_a: S::V,
    /// `b`'s end from its centre of mass in its frame, or the world anchor.
    arm_b: S::V,
    k: f64,
    rest: f64,
    c: f64,
}

/// One end of a spring (or a user force's point), in the world.
#[derive(Debug, Clone, Copy)]
struct End<S: Space> {
    /// The end's position.
    x: S::V,
    /// Its velocity.
    v: S::V,
    /// From the centre of mass, world frame.
    arm: S::V,
}

/// A user's force at a point of a solid (evaluated once a step, at its start).
#[derive(Debug, Clone)]
pub(crate) struct UserLoad<S: Space> {
    pub(crate) solid: usize,
    /// The point from the centre of mass, in the solid's frame.
    pub(crate) arm: S::V,
    pub(crate) generator: crate::forces::UserForce,
}

/// The forces on the solids: drag (per solid), springs, loads.
#[derive(Debug, Clone)]
pub(crate) struct Forces<S: Space> {
    /// Linear and angular drag of each solid, 1/s.
    pub(crate) damping: Vec<(f64, f64)>,
    /// Whether any solid has drag.
    pub(crate) any_damping: bool,
    pub(crate) springs: Vec<Spring<S>>,
    pub(crate) spring_params: Vec<SolidSpring>,
    /// Force and torque applied by hand for the next step (empty: none).
    pub(crate) applied: Vec<(S::V, S::W)>,
    pub(crate) users: Vec<UserLoad<S>>,
    /// This step's loads (applied and the users'), held over its substeps (empty: none).
    pub(crate) load: Vec<(S::V, S::W)>,
    /// The springs' forces of a substep, per solid.
    scratch: Vec<(S::V, S::W)>,
}

impl<S: Space> Default for Forces<S> {
    fn default() -> Self {
        Self {
            damping: Vec::new(),
            any_damping: false,
            springs: Vec::new(),
            spring_params: Vec::new(),
            applied: Vec::new(),
            users: Vec::new(),
            load: Vec::new(),
            scratch: Vec::new(),
        }
    }
}

/// Checks a drag coefficient (`linear_damping`, `angular_damping`), 1/s.
pub(crate) fn check_damping(field: &str, c: f64) -> Result<()> {
    if c.is_finite() && (0.0..=PARAM_MAX).contains(&c) {
        Ok(())
    } else {
        Err(Error::invalid(field, num(c), "a number in [0, 1e12] (1/s)"))
    }
}

fn vector<S: Space>(field: &str, v: &[f64]) -> Result<S::V> {
    if v.len() != S::DIM {
        return Err(Error::invalid(format!("len({field})"), v.len(), format!("{}", S::DIM)));
    }
    if let Some(i) = v.iter().position(|x| !(x.is_finite() && x.abs() <= PARAM_MAX)) {
        return Err(Error::invalid(format!("{field}[{i}]"), num(v[i]), "finite (at most 1e12 in size)"));
    }
    Ok(S::V::read(v))
}

/// A solid index below `n`, for `field`.
pub(crate) fn solid_index(field: &str, i: usize, n: usize) -> Result<()> {
    if i < n {
        Ok(())
    } else if n == 0 {
        Err(Error::invalid(field, i, "an existing solid (there are none)"))
    } else {
        Err(Error::invalid(field, i, format!("an existing solid (0 to {})", n - 1)))
    }
}

/// A point given in a solid's frame, from its centre of mass in that frame.
fn arm<S: Space>(b: &Body<S>, point: S::V) -> S::V {
    point - b.com
}

fn end<S: Space>(b: &Body<S>, v: S::V, w: S::W, arm: S::V) -> End<S> {
    let arm = S::rotate(b.q, arm);
    End { x: b.c + arm, v: v + S::cross_wv(w, arm), arm }
}

impl<S: Space> Spring<S> {
    /// Its two solids (`None`: a world anchor).
    pub(crate) fn solids(&self) -> (Option<usize>, usize) {
        (self.b, self.a)
    }

    /// Checks `p` against the solids and makes the spring (its rest length resolved).
    fn new(p: &SolidSpring, bodies: &[Body<S>]) -> Result<(Self, f64)> {
        let n = bodies.len();
        solid_index("a", p.a, n)?;
        if let Some(b) = p.b {
            solid_index("b", b, n)?;
            if b == p.a {
                return Err(Error::invalid("b", b, "a solid other than a (or None: the world)"));
            }
        }
        let pa = vector::<S>("point_a", &p.point_a)?;
        let pb = vector::<S>("point_b", &p.point_b)?;
        for (field, v) in [("stiffness", p.stiffness), ("damping", p.damping)] {
            if !(v.is_finite() && (0.0..=PARAM_MAX).contains(&v)) {
                return Err(Error::invalid(field, num(v), "a number in [0, 1e12]"));
            }
        }
        let arm_a = arm(&bodies[p.a], pa);
        let arm_b = match p.b {
            Some(b) => arm(&bodies[b], pb),
            None => pb,
        };
        let mut s = Self { a: p.a, b: p.b, arm_a, arm_b, k: p.stiffness, rest: 0.0, c: p.damping };
        let rest = match p.rest_length {
            Some(r) => r,
            None => s.length(bodies),
        };
        if !(rest.is_finite() && (0.0..=PARAM_MAX).contains(&rest)) {
            return Err(Error::invalid("rest_length", num(rest), "a number in [0, 1e12]"));
        }
        s.rest = rest;
        Ok((s, rest))
    }

    /// Its two ends, at rest (for lengths and energies) or moving with `v`, `w` of each solid.
    fn ends(&self, bodies: &[Body<S>], vw: impl Fn(usize) -> (S::V, S::W)) -> (End<S>, End<S>) {
        let (va, wa) = vw(self.a);
        let ea = end(&bodies[self.a], va, wa, self.arm_a);
        let eb = match self.b {
            Some(b) => {
                let (vb, wb) = vw(b);
                end(&bodies[b], vb, wb, self.arm_b)
            }
            None => End { x: self.arm_b, v: S::V::default(), arm: S::V::default() },
        };
        (ea, eb)
    }

    fn length(&self, bodies: &[Body<S>]) -> f64 {
        let (ea, eb) = self.ends(bodies, |_| (S::V::default(), S::W::default()));
        let d = eb.x - ea.x;
        d.dot(d).sqrt()
    }

    /// Potential energy, J.
    fn potential(&self, bodies: &[Body<S>]) -> f64 {
        let s = self.length(bodies) - self.rest;
        0.5 * self.k * s * s
    }

    /// The force on `a`'s end (its opposite on `b`'s), N.
    fn force(&self, ea: &End<S>, eb: &End<S>) -> S::V {
        let d = eb.x - ea.x;
        let dv = eb.v - ea.v;
        if self.rest == 0.0 {
            return d * self.k + dv * self.c;
        }
        let len = d.dot(d).sqrt();
        if len == 0.0 {
            // No direction to push along (the two ends meet): no force.
            return S::V::default();
        }
        let u = d * (1.0 / len);
        u * (self.k * (len - self.rest) + self.c * dv.dot(u))
    }
}

impl<S: Space> Forces<S> {
    /// A solid was added with drag `linear`, `angular` (checked).
    pub(crate) fn push_solid(&mut self, linear: f64, angular: f64) {
        self.damping.push((linear, angular));
        self.any_damping |= linear != 0.0 || angular != 0.0;
        if !self.applied.is_empty() {
            self.applied.push((S::V::default(), S::W::default()));
        }
    }

    /// Adds a spring (checked against `bodies`); its index.
    pub(crate) fn add_spring(&mut self, p: SolidSpring, bodies: &[Body<S>]) -> Result<usize> {
        let (s, rest) = Spring::new(&p, bodies)?;
        self.springs.push(s);
        self.spring_params.push(SolidSpring { rest_length: Some(rest), ..p });
        Ok(self.springs.len() - 1)
    }

    /// Takes solid `k` out: its drag and loads, the springs and user forces on it (their
    /// rows returned as masks: springs, users), the others renumbered.
    pub(crate) fn remove_solid(&mut self, k: usize) -> (Vec<bool>, Vec<bool>) {
        self.damping.remove(k);
        self.any_damping = self.damping.iter().any(|(l, a)| *l != 0.0 || *a != 0.0);
        for v in [&mut self.applied, &mut self.load] {
            if !v.is_empty() {
                v.remove(k);
            }
        }
        let springs: Vec<bool> = self.springs.iter().map(|s| s.a == k || s.b == Some(k)).collect();
        crate::ids::retain_by(&mut self.springs, &springs);
        crate::ids::retain_by(&mut self.spring_params, &springs);
        for (s, p) in self.springs.iter_mut().zip(&mut self.spring_params) {
            s.a = crate::ids::shift(s.a, k);
            s.b = s.b.map(|b| crate::ids::shift(b, k));
            p.a = s.a;
            p.b = s.b;
        }
        let users: Vec<bool> = self.users.iter().map(|u| u.solid == k).collect();
        crate::ids::retain_by(&mut self.users, &users);
        for u in &mut self.users {
            u.solid = crate::ids::shift(u.solid, k);
        }
        (springs, users)
    }

    /// Sets spring `k`'s stiffness, rest length and damping, checked as when it was added.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `stiffness`, `rest_length` or `damping`; unchanged.
    pub(crate) fn set_spring(
        &mut self,
        k: usize,
        stiffness: f64,
        rest_length: f64,
        damping: f64,
    ) -> Result<()> {
        for (field, v) in [("stiffness", stiffness), ("rest_length", rest_length), ("damping", damping)] {
            if !(v.is_finite() && (0.0..=PARAM_MAX).contains(&v)) {
                return Err(Error::invalid(field, num(v), "a number in [0, 1e12]"));
            }
        }
        let s = &mut self.springs[k];
        (s.k, s.rest, s.c) = (stiffness, rest_length, damping);
        let p = &mut self.spring_params[k];
        (p.stiffness, p.rest_length, p.damping) = (stiffness, Some(rest_length), damping);
        Ok(())
    }

    /// Each spring's two ends now, world coordinates, flat (`a`'s end, then `b`'s).
    pub(crate) fn ends(&self, bodies: &[Body<S>]) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.springs.len() * 2 * S::DIM);
        for s in &self.springs {
            let (ea, eb) = s.ends(bodies, |_| (S::V::default(), S::W::default()));
            ea.x.write(&mut out);
            eb.x.write(&mut out);
        }
        out
    }

    /// The springs' potential energy, J.
    pub(crate) fn potential(&self, bodies: &[Body<S>]) -> f64 {
        self.springs.iter().map(|s| s.potential(bodies)).sum()
    }

    /// Adds `force` at the arm `arm` (world frame, from the centre of mass) and `torque` to
    /// solid `i`'s loads for the next step.
    pub(crate) fn apply(&mut self, n: usize, i: usize, force: S::V, arm: S::V, torque: S::W) {
        if self.applied.is_empty() {
            self.applied.resize(n, (S::V::default(), S::W::default()));
        }
        let a = &mut self.applied[i];
        a.0 += force;
        a.1 += S::cross_vv(arm, force) + torque;
    }

    /// Adds a user's force at `point` (the solid's frame) of solid `solid`; its index.
    pub(crate) fn add_user(
        &mut self,
        solid: usize,
        point: &[f64],
        generator: std::sync::Arc<dyn crate::forces::ForceGenerator>,
        bodies: &[Body<S>],
    ) -> Result<usize> {
        solid_index("solid", solid, bodies.len())?;
        let p = vector::<S>("point", point)?;
        let arm = arm(&bodies[solid], p);
        self.users.push(UserLoad { solid, arm, generator: crate::forces::UserForce(generator) });
        Ok(self.users.len() - 1)
    }

    /// This step's loads, held over its substeps: those applied by hand, and each user
    /// force evaluated at time `t` on the solids as they are.
    ///
    /// # Errors
    /// [`Error::Force`] naming the force that failed or gave a value that is not finite;
    /// the loads are then left empty.
    pub(crate) fn gather(&mut self, t: f64, bodies: &[Body<S>]) -> Result<()> {
        self.load.clone_from(&self.applied);
        if self.users.is_empty() {
            return Ok(());
        }
        if self.load.is_empty() {
            self.load.resize(bodies.len(), (S::V::default(), S::W::default()));
        }
        let (mut x, mut v) = (Vec::with_capacity(3), Vec::with_capacity(3));
        for u in &self.users {
            let b = &bodies[u.solid];
            let e = end(b, b.v, b.w, u.arm);
            x.clear();
            v.clear();
            e.x.write(&mut x);
            e.v.write(&mut v);
            let mut f = vec![0.0; S::DIM];
            let r = u.generator.0.add_forces(t, &x, &v, &mut f).map_err(|r| (r, false));
            let r = r.and_then(|()| match f.iter().position(|c| !c.is_finite()) {
                None => Ok(()),
                Some(k) => Err((format!("force[0][{k}] = {} is not finite", f[k]), true)),
            });
            if let Err((reason, non_finite)) = r {
                self.load.clear();
                return Err(Error::Force { name: u.generator.0.name().to_string(), reason, non_finite });
            }
            let f = S::V::read(&f);
            let l = &mut self.load[u.solid];
            l.0 += f;
            l.1 += S::cross_vv(e.arm, f);
        }
        Ok(())
    }

    /// The user forces' potential energy at the solids as they are, `None` when one has none.
    pub(crate) fn user_potential(&self, bodies: &[Body<S>]) -> Option<f64> {
        let mut total = 0.0;
        let mut x = Vec::with_capacity(3);
        for u in &self.users {
            let b = &bodies[u.solid];
            x.clear();
            (b.c + S::rotate(b.q, u.arm)).write(&mut x);
            total += u.generator.0.potential(&x)?;
        }
        Some(total)
    }

    /// Whether a step depends on nothing but the state (no user code, no load by hand).
    pub(crate) fn replayable(&self) -> bool {
        self.users.is_empty() && self.applied.is_empty()
    }

    /// Forgets the loads applied by hand (a step took them).
    pub(crate) fn clear_applied(&mut self) {
        self.applied.clear();
    }

    /// Whether anything here acts in a substep.
    fn active(&self) -> bool {
        !self.springs.is_empty() || self.any_damping || !self.load.is_empty()
    }

    /// A 64-bit fingerprint of the drag and the springs (`None` without either), for the
    /// state hash.
    pub(crate) fn fingerprint(&self) -> Option<u64> {
        if !self.any_damping && self.springs.is_empty() {
            return None;
        }
        let mut words = Vec::new();
        for (l, a) in &self.damping {
            words.extend_from_slice(&[*l, *a]);
        }
        for s in &self.springs {
            words.push(s.a as f64);
            words.push(s.b.map_or(-1.0, |b| b as f64));
            s.arm_a.write(&mut words);
            s.arm_b.write(&mut words);
            words.extend_from_slice(&[s.k, s.rest, s.c]);
        }
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for w in words {
            for byte in w.to_bits().to_le_bytes() {
                h ^= u64::from(byte);
                h = h.wrapping_mul(0x0100_0000_01b3);
            }
        }
        Some(h)
    }
}

/// One substep's velocity integration of the forces here (before gravity and the contact
/// passes): the springs' forces from the substep's state, drag, and the step's loads, as
/// `v = v / (1 + h c) + h F / m` and `w = w / (1 + h c_ang) + h I^-1 T`. `motion[i]` holds
/// solid `i`'s velocities and world inverse inertia; only dynamic solids change.
pub(crate) fn integrate<S: Space>(
    f: &mut Forces<S>,
    bodies: &[Body<S>],
    motion: &mut [super::points::Motion<S>],
    h: f64,
) {
    if !f.active() {
        return;
    }
    let zero = (S::V::default(), S::W::default());
    f.scratch.clear();
    f.scratch.resize(bodies.len(), zero);
    for s in &f.springs {
        let (ea, eb) = s.ends(bodies, |i| (motion[i].v, motion[i].w));
        let force = s.force(&ea, &eb);
        let acc = &mut f.scratch[s.a];
        acc.0 += force;
        acc.1 += S::cross_vv(ea.arm, force);
        if let Some(b) = s.b {
            let acc = &mut f.scratch[b];
            acc.0 -= force;
            acc.1 -= S::cross_vv(eb.arm, force);
        }
    }
    for (i, (b, m)) in bodies.iter().zip(motion.iter_mut()).enumerate() {
        if b.kind != Kind::Dynamic {
            continue;
        }
        let (mut force, mut torque) = f.scratch[i];
        if let Some(l) = f.load.get(i) {
            force += l.0;
            torque += l.1;
        }
        let (cl, ca) = f.damping[i];
        if cl != 0.0 {
            m.v = m.v * (1.0 / (1.0 + h * cl));
        }
        if ca != 0.0 {
            m.w = m.w * (1.0 / (1.0 + h * ca));
        }
        m.v += force * (h * m.inv_mass);
        m.w += S::apply(m.inv_i, torque * h);
    }
}
