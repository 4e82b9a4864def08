//! Joints between solids, and between a solid and the world, solved in the contact solver's
//! substeps beside the contacts (Box2D v3's joints, soft as its contacts are):
//!
//! ```text
//! ball        the two anchors held together (a point: 2 rows in the plane, 3 in space)
//! revolute    a ball that turns only about its axis (the plane's normal in 2D; `axis` in
//!             3D), with angle limits `lower..upper` and a motor (`motor_speed`, at most
//!             `max_motor` N m)
//! distance    the anchors kept `length` apart: rigidly (hertz 0), or a spring of `hertz`
//!             and `damping_ratio`, between `min_length` and `max_length` (a rope: hertz 0,
//!             min 0)
//! weld        the two glued: the point and the relative orientation (soft with `hertz`)
//! prismatic   a slider along `axis`: no turning, no motion across the axis, with limits
//!             `lower..upper` of the travel and a motor (at most `max_motor` N)
//! ```
//!
//! Each row is Box2D's: with the bias (the solve pass) a soft constraint of the joint's
//! stiffness ([`super::Settings::joint_hertz`], damping ratio
//! [`super::Settings::joint_damping_ratio`]) pulls the error to zero; without it (the relax
//! pass) only the velocity is constrained. A limit not yet reached is speculative (the gap
//! closed in one substep, no more). Angles and travel are measured from the pose the joint
//! was made in. The accumulated impulses warm-start the next step and are in the snapshot.
//!
//! Here: what a joint is (its kind, its parameters as made and their checks, its anchors and
//! frames in its solids, its impulses in a snapshot); in `rows.rs`: how the soft step solves
//! it; in `positions.rs`: the joints the `xpbd` solver corrects positionally.

mod positions;
mod rows;

pub(crate) use positions::{average_positional, clear_positional, solve_positions};
pub(crate) use rows::{prepare, project, solve, warm_start};

use super::points::Soft;
use super::space::{Space, Vect};
use super::Body;
use crate::error::{num, Error, Result};

/// What a joint holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// A point shared by the two solids.
    Ball,
    /// A hinge: a shared point, turning about one axis, with limits and a motor.
    Revolute,
    /// Two points kept at a distance (rigid, a spring, a rope).
    Distance,
    /// The two solids glued together.
    Weld,
    /// A slider along an axis, with limits and a motor.
    Prismatic,
}

/// Every joint kind's name, in order.
pub const JOINT_KINDS: &[&str] = &["ball", "revolute", "distance", "weld", "prismatic"];

impl JointKind {
    /// The kind by name ([`JOINT_KINDS`]; `hinge` is `revolute`).
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the kinds.
    pub fn by_name(name: &str) -> Result<JointKind> {
        Ok(match name {
            "ball" => JointKind::Ball,
            "revolute" | "hinge" => JointKind::Revolute,
            "distance" => JointKind::Distance,
            "weld" => JointKind::Weld,
            "prismatic" => JointKind::Prismatic,
            _ => {
                return Err(Error::UnknownName {
                    kind: "joint kind".into(),
                    name: name.into(),
                    valid: JOINT_KINDS.iter().map(|s| (*s).to_string()).collect(),
                })
            }
        })
    }

    /// The kind's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        JOINT_KINDS[self as usize]
    }
}

/// A joint as it is made: what a scene file keeps. Points and axes are in world coordinates
/// at the moment the joint is added; angles and travel count from that pose.
#[derive(Debug, Clone, PartialEq)]
pub struct JointParams {
    /// Ball, revolute, distance, weld or prismatic.
    pub kind: JointKind,
    /// The first solid.
    pub a: usize,
    /// The second solid, or `None`: the world (fixed).
    pub b: Option<usize>,
    /// The shared point (the end on `a` for a distance joint), m.
    pub anchor: Vec<f64>,
    /// A distance joint's end on `b` (default: `anchor`), m.
    pub anchor_b: Option<Vec<f64>>,
    /// A revolute joint's axis in 3D, or a prismatic joint's direction of travel (default:
    /// the z axis for a hinge, the x axis for a slider).
    pub axis: Option<Vec<f64>>,
    /// A distance joint's rest length (default: the distance when made), m.
    pub length: Option<f64>,
    /// A distance joint's shortest (default: `length` when rigid, 0 for a spring), m.
    pub min_length: Option<f64>,
    /// A distance joint's longest (default: `length` when rigid, unbounded for a spring), m.
    pub max_length: Option<f64>,
    /// A distance joint's spring, or a weld's softness, Hz (0: rigid).
    pub hertz: f64,
    /// That spring's damping ratio.
    pub damping_ratio: f64,
    /// The lowest angle (revolute, rad) or travel (prismatic, m); `None`: no limit.
    pub lower: Option<f64>,
    /// The highest angle or travel; `None`: no limit.
    pub upper: Option<f64>,
    /// The motor's target speed, rad/s (revolute) or m/s (prismatic).
    pub motor_speed: f64,
    /// The motor's largest torque (N m) or force (N); 0: no motor.
    pub max_motor: f64,
    /// Whether the two solids still collide with each other (default: no).
    pub collide: bool,
}

impl JointParams {
    /// A joint of `kind` between `a` and `b` (`None`: the world) at `anchor`, with no limit,
    /// no motor, rigid.
    #[must_use]
    pub fn new(kind: JointKind, a: usize, b: Option<usize>, anchor: &[f64]) -> Self {
        Self {
            kind,
            a,
            b,
            anchor: anchor.to_vec(),
            anchor_b: None,
            axis: None,
            length: None,
            min_length: None,
            max_length: None,
            hertz: 0.0,
            damping_ratio: 1.0,
            lower: None,
            upper: None,
            motor_speed: 0.0,
            max_motor: 0.0,
            collide: false,
        }
    }
}

/// Accumulated impulses of one joint (its warm start), by row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Impulses<S: Space> {
    /// The point (ball, revolute, weld) or across the axis (prismatic).
    linear: S::V,
    /// The relative rotation (weld, prismatic).
    angular: S::W,
    /// Across a hinge's axis (3D).
    swing: [f64; 2],
    /// Along the line (distance) or the axis: the rigid row or the spring.
    axial: f64,
    motor: f64,
    lower: f64,
    upper: f64,
}

impl<S: Space> Default for Impulses<S> {
    fn default() -> Self {
        Self {
            linear: S::V::default(),
            angular: S::W::default(),
            swing: [0.0; 2],
            axial: 0.0,
            motor: 0.0,
            lower: 0.0,
            upper: 0.0,
        }
    }
}

impl<S: Space> Impulses<S> {
    /// The number of values [`Impulses::write`] writes.
    pub(crate) fn width() -> usize {
        S::DIM + if S::DIM == 3 { 3 } else { 1 } + 6
    }

    fn write(&self, out: &mut Vec<f64>) {
        self.linear.write(out);
        self.angular.write(out);
        out.extend_from_slice(&[
            self.swing[0],
            self.swing[1],
            self.axial,
            self.motor,
            self.lower,
            self.upper,
        ]);
    }

    fn read(c: &[f64]) -> Self {
        let (d, a) = (S::DIM, if S::DIM == 3 { 3 } else { 1 });
        let r = &c[d + a..];
        Self {
            linear: S::V::read(&c[..d]),
            angular: S::W::read(&c[d..d + a]),
            swing: [r[0], r[1]],
            axial: r[2],
            motor: r[3],
            lower: r[4],
            upper: r[5],
        }
    }
}

/// A joint as the solver keeps it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Joint<S: Space> {
    kind: JointKind,
    /// The first end; `None`: the world (a joint to the world has the world first, so that
    /// its angle, travel and motor are the solid's own).
    a: Option<usize>,
    b: usize,
    /// The anchors in each body's frame about its centre of mass (the world's: the point).
    local_a: S::V,
    local_b: S::V,
    /// A slider's direction in `a`'s frame (unit).
    slide: S::V,
    /// A hinge's axis in `a`'s frame (unit; `1` in the plane).
    hinge: S::W,
    /// `b`'s orientation seen from `a` when the joint was made.
    rel: S::Rot,
    length: f64,
    min_length: f64,
    max_length: f64,
    hertz: f64,
    damping_ratio: f64,
    lower: f64,
    upper: f64,
    motor_speed: f64,
    max_motor: f64,
    pub(crate) impulses: Impulses<S>,
    // What a step prepares.
    ra: S::V,
    rb: S::V,
    delta_center: S::V,
    offset: S::Rot,
    slide_world: S::V,
    hinge_world: S::W,
    spring: Soft,
}

/// The pose of a joint's end: a body's, or the world's.
fn pose<S: Space>(bodies: &[Body<S>], i: Option<usize>) -> (S::V, S::Rot) {
    match i {
        Some(i) => (bodies[i].c, bodies[i].q),
        None => (S::V::default(), S::identity()),
    }
}

fn vector<S: Space>(field: &str, v: &[f64]) -> Result<S::V> {
    if v.len() != S::DIM {
        return Err(Error::invalid(format!("len({field})"), v.len(), format!("{}", S::DIM)));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(Error::invalid(format!("{field}[{i}]"), num(v[i]), "finite"));
    }
    Ok(S::V::read(v))
}

fn unit<S: Space>(field: &str, v: &[f64]) -> Result<S::V> {
    let a = vector::<S>(field, v)?;
    let n = a.dot(a).sqrt();
    if n > 0.0 && n.is_finite() {
        Ok(a * (1.0 / n))
    } else {
        Err(Error::invalid(field, "[0, ...]", "a non-zero direction"))
    }
}

fn optional(field: &str, v: Option<f64>) -> Result<()> {
    match v {
        Some(x) if !x.is_finite() => Err(Error::invalid(field, num(x), "finite")),
        _ => Ok(()),
    }
}

impl<S: Space> Joint<S> {
    /// Checks `p` against `bodies` (the solids now) and makes the joint.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field: `b` the same solid as `a`, a solid that
    /// does not exist, an anchor or axis of the wrong length or not finite, a zero axis, a
    /// negative length, `min_length > max_length`, `lower > upper`, a negative `hertz`,
    /// `damping_ratio` or `max_motor`, or two solids neither of which moves.
    pub(crate) fn new(p: &JointParams, bodies: &[Body<S>]) -> Result<Self> {
        let n = bodies.len();
        if p.a >= n {
            return Err(Error::invalid(
                "a",
                p.a,
                format!("an existing solid (0 to {})", n.saturating_sub(1) as i64),
            ));
        }
        if let Some(b) = p.b {
            if b >= n {
                return Err(Error::invalid(
                    "b",
                    b,
                    format!("an existing solid (0 to {}) or None: the world", n - 1),
                ));
            }
            if b == p.a {
                return Err(Error::invalid("b", b, "a solid other than a (a joint joins two solids)"));
            }
        }
        let moves = |i: Option<usize>| i.is_some_and(|i| bodies[i].inv_mass > 0.0);
        if !moves(Some(p.a)) && !moves(p.b) {
            return Err(Error::invalid(
                "a",
                p.a,
                "a dynamic solid on one side (neither end of this joint can move)",
            ));
        }
        let anchor = vector::<S>("anchor", &p.anchor)?;
        let anchor_b = match &p.anchor_b {
            Some(v) => vector::<S>("anchor_b", v)?,
            None => anchor,
        };
        // A slider's default direction is x; a 3D hinge's default axis z (the plane's normal).
        let default_axis: &[f64] =
            if p.kind == JointKind::Prismatic || S::DIM == 2 { &[1.0, 0.0, 0.0] } else { &[0.0, 0.0, 1.0] };
        let axis = unit::<S>("axis", p.axis.as_deref().unwrap_or(&default_axis[..S::DIM]))?;
        for (f, v) in [("length", p.length), ("min_length", p.min_length), ("max_length", p.max_length)] {
            optional(f, v)?;
            if let Some(x) = v {
                if x < 0.0 {
                    return Err(Error::invalid(f, num(x), ">= 0"));
                }
            }
        }
        optional("lower", p.lower)?;
        optional("upper", p.upper)?;
        for (f, v) in [("hertz", p.hertz), ("damping_ratio", p.damping_ratio), ("max_motor", p.max_motor)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(f, num(v), "finite and >= 0"));
            }
        }
        if !p.motor_speed.is_finite() {
            return Err(Error::invalid("motor_speed", num(p.motor_speed), "finite"));
        }
        let (lower, upper) = (p.lower.unwrap_or(f64::NEG_INFINITY), p.upper.unwrap_or(f64::INFINITY));
        if lower > upper {
            return Err(Error::invalid("lower", num(lower), format!("<= upper ({})", num(upper))));
        }
        // To the world: the world is the first end, the solid the second.
        let (a, b, anchor, anchor_b) = match p.b {
            Some(b) => (Some(p.a), b, anchor, anchor_b),
            None => (None, p.a, anchor_b, anchor),
        };
        let (ca, qa) = pose(bodies, a);
        let (cb, qb) = pose(bodies, Some(b));
        let gap = anchor_b - anchor;
        let here = gap.dot(gap).sqrt();
        let length = p.length.unwrap_or(here);
        let (lo, hi) = if p.hertz > 0.0 { (0.0, f64::INFINITY) } else { (length, length) };
        let (min_length, max_length) = (p.min_length.unwrap_or(lo), p.max_length.unwrap_or(hi));
        let length = if min_length == max_length { min_length } else { length };
        if min_length > max_length {
            return Err(Error::invalid(
                "min_length",
                num(min_length),
                format!("<= max_length ({})", num(max_length)),
            ));
        }
        if p.kind == JointKind::Distance && p.hertz == 0.0 && min_length == max_length && min_length == 0.0 {
            return Err(Error::invalid("length", 0, "> 0 for a rigid distance joint (use a ball joint)"));
        }
        // The hinge axis in a's frame (in the plane, the plane's normal).
        let hinge = if S::DIM == 2 {
            S::W::read(&[1.0])
        } else {
            let mut c = Vec::with_capacity(3);
            S::unrotate(qa, axis).write(&mut c);
            S::W::read(&c)
        };
        Ok(Self {
            kind: p.kind,
            a,
            b,
            local_a: S::unrotate(qa, anchor - ca),
            local_b: S::unrotate(qb, anchor_b - cb),
            slide: S::unrotate(qa, axis),
            hinge,
            rel: S::relative(qa, qb),
            length,
            min_length,
            max_length,
            hertz: p.hertz,
            damping_ratio: p.damping_ratio,
            lower,
            upper,
            motor_speed: p.motor_speed,
            max_motor: p.max_motor,
            impulses: Impulses::default(),
            ra: S::V::default(),
            rb: S::V::default(),
            delta_center: S::V::default(),
            offset: S::identity(),
            slide_world: S::V::default(),
            hinge_world: S::W::default(),
            spring: Soft::new(0.0, 0.0, 1.0),
        })
    }

    /// The pair of solids whose contacts the joint turns off (`None` if it does not).
    pub(crate) fn no_collide(&self, p: &JointParams) -> Option<(u32, u32)> {
        match (p.collide, self.a) {
            (false, Some(a)) => Some((a.min(self.b) as u32, a.max(self.b) as u32)),
            _ => None,
        }
    }

    /// Its two solids (`None`: the world).
    pub(crate) fn solids(&self) -> (Option<usize>, usize) {
        (self.a, self.b)
    }

    /// Whether solid `k` is one of its ends.
    pub(crate) fn joins(&self, k: usize) -> bool {
        self.a == Some(k) || self.b == k
    }

    /// Its ends renumbered after solid `k` (not one of them) was removed.
    pub(crate) fn shift(&mut self, k: usize) {
        self.a = self.a.map(|a| crate::ids::shift(a, k));
        self.b = crate::ids::shift(self.b, k);
    }

    /// Sets the motor (speed, largest force or torque), checked as [`Joint::new`] checks them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `motor_speed` or `max_motor`; the joint is unchanged.
    pub(crate) fn set_motor(&mut self, speed: f64, max: f64) -> Result<()> {
        if !speed.is_finite() {
            return Err(Error::invalid("motor_speed", num(speed), "finite"));
        }
        if !(max.is_finite() && max >= 0.0) {
            return Err(Error::invalid("max_motor", num(max), "finite and >= 0"));
        }
        self.motor_speed = speed;
        self.max_motor = max;
        Ok(())
    }

    /// Sets the limits (`None`: none on that side), checked as [`Joint::new`] checks them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `lower` or `upper`; the joint is unchanged.
    pub(crate) fn set_limits(&mut self, lower: Option<f64>, upper: Option<f64>) -> Result<()> {
        optional("lower", lower)?;
        optional("upper", upper)?;
        let (lower, upper) = (lower.unwrap_or(f64::NEG_INFINITY), upper.unwrap_or(f64::INFINITY));
        if lower > upper {
            return Err(Error::invalid("lower", num(lower), format!("<= upper ({})", num(upper))));
        }
        self.lower = lower;
        self.upper = upper;
        Ok(())
    }

    fn ends(&self, world: usize) -> (u32, u32) {
        (self.a.unwrap_or(world) as u32, self.b as u32)
    }

    /// The joint's position error now, m (the anchors apart, or off the rest length for a
    /// rigid distance joint); what the tests and the lab read.
    pub(crate) fn error(&self, bodies: &[Body<S>]) -> f64 {
        let (ca, qa) = pose(bodies, self.a);
        let (cb, qb) = pose(bodies, Some(self.b));
        let gap = cb + S::rotate(qb, self.local_b) - ca - S::rotate(qa, self.local_a);
        let d = gap.dot(gap).sqrt();
        match self.kind {
            JointKind::Distance => {
                if d < self.min_length {
                    self.min_length - d
                } else if d > self.max_length {
                    d - self.max_length
                } else {
                    0.0
                }
            }
            JointKind::Prismatic => {
                let s = S::rotate(qa, self.slide);
                let along = gap.dot(s);
                let across = gap - s * along;
                across.dot(across).sqrt()
            }
            _ => d,
        }
    }
}

/// The joints' accumulated impulses, flat (a snapshot's), `Impulses::width()` a joint.
pub(crate) fn write<S: Space>(joints: &[Joint<S>], out: &mut Vec<f64>) {
    out.push(joints.len() as f64);
    for j in joints {
        j.impulses.write(out);
    }
}

/// Reads what [`write`] wrote for these joints, checked; returns the values used.
pub(crate) fn read<S: Space>(
    joints: &[Joint<S>],
    data: &[f64],
) -> std::result::Result<Vec<Impulses<S>>, String> {
    let w = Impulses::<S>::width();
    let count = data.first().copied().unwrap_or(-1.0);
    if count != joints.len() as f64 || data.len() != 1 + joints.len() * w {
        return Err(format!("the snapshot's joints ({count}) do not fit this world's {}", joints.len()));
    }
    if data.iter().any(|x| !x.is_finite()) {
        return Err("a joint's impulse is not finite".into());
    }
    Ok(data[1..].chunks_exact(w).map(Impulses::read).collect())
}
