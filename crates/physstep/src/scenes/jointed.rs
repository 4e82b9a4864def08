//! The jointed contact scenes of Catto's Solver2D set: a bridge of planks, a chain with a
//! heavy ball, a ragdoll of bodies (solids joined by revolute joints, solved with the
//! contacts).

use super::solids::{count, gravity, ground};
use super::{Exact, Param, Result};
use crate::contact::{JointKind, JointParams, Shape, SolidParams};
use crate::world::World;

/// A revolute joint with friction (a motor holding still with at most `friction` N m).
fn hinge(w: &mut World, a: usize, b: Option<usize>, at: [f64; 2], friction: f64) -> Result<usize> {
    let mut j = JointParams::new(JointKind::Revolute, a, b, &at);
    j.max_motor = friction;
    w.add_joint(j)
}

/// `bridge`: `n` planks 1 m long (half height 0.125 m, density 20) hinged end to end, the
/// ends hinged to two fixed points `span` times the planks' length apart (Solver2D's has
/// 160 planks spanning their length, which no chain of rigid links can do: it hangs by the
/// joints' stretch; this one has slack), laid on a circular arc and swinging into its
/// catenary; joint friction (50 N m; Box2D's bridge has 200) lets it settle.
///
/// # Errors
/// As [`World::add_solid`]; `n` above the solids' bound.
pub(super) fn bridge(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    gravity(w, v("g"))?;
    // Each plank a chord of 1 m of a circle, each turning the arc by phi; the n chords span
    // sin(n phi / 2) / sin(phi / 2) = span * n (bisection on phi, from straight to a half
    // circle).
    let goal = v("span") * n as f64;
    let spans =
        |phi: f64| if phi == 0.0 { n as f64 } else { (n as f64 * phi / 2.0).sin() / (phi / 2.0).sin() };
    let least = spans(std::f64::consts::PI / n as f64) / n as f64;
    if v("span") < least {
        return Err(crate::error::Error::invalid(
            "span",
            crate::error::num(v("span")),
            format!("at least {least:.3} (a half circle) and below 1 (taut)"),
        ));
    }
    let (mut lo, mut hi) = (0.0, std::f64::consts::PI / n as f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if spans(mid) > goal {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let phi = 0.5 * (lo + hi);
    // The first chord points down by (n - 1) phi / 2 below level, each next one phi less.
    let mut at = [-goal / 2.0, 0.0];
    let mut prev: Option<usize> = None;
    for i in 0..n {
        let angle = -((n - 1) as f64) * phi / 2.0 + i as f64 * phi;
        let (sn, c) = angle.sin_cos();
        let mut p =
            SolidParams::new(Shape::Box { half: vec![0.5, 0.125] }, &[at[0] + 0.5 * c, at[1] + 0.5 * sn]);
        p.orientation = vec![angle];
        p.density = 20.0;
        let b = w.add_solid(p)?;
        hinge(w, prev.unwrap_or(b), prev.map(|_| b), at, 50.0)?;
        at = [at[0] + c, at[1] + sn];
        prev = Some(b);
    }
    if let Some(last) = prev {
        hinge(w, last, None, at, 50.0)?;
    }
    Ok(None)
}

/// `ball-chain`: `n` capsule links 1 m long hinged end to end from a point 20 m up, laid out
/// level, with a heavy ball (radius 2 m) on the free end: they fall and swing (Solver2D's
/// ball and chain; a whip with a 1:200 mass ratio along it).
///
/// # Errors
/// As [`World::add_solid`]; `n` above the solids' bound.
pub(super) fn ball_chain(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    let (y, r) = (20.0 + v("radius"), v("radius"));
    let prev = hinged_chain(w, [0.0, y], n, 1.0, 0.125)?;
    let mut ball = SolidParams::new(Shape::Circle { radius: r }, &[n as f64 + r, y]);
    ball.density = 20.0;
    let b = w.add_solid(ball)?;
    match prev {
        Some(a) => hinge(w, a, Some(b), [n as f64, y], 0.0)?,
        None => hinge(w, b, None, [0.0, y], 0.0)?,
    };
    Ok(None)
}

/// `n` capsule links `link` m long and `radius` thick (density 20), laid level toward +x
/// from `pivot`, hinged end to end and the first to the world at `pivot`, without joint
/// friction: `ball-chain`'s chain and `far-chain`. Returns the last link (`None` when `n`
/// is 0).
pub(super) fn hinged_chain(
    w: &mut World,
    pivot: [f64; 2],
    n: usize,
    link: f64,
    radius: f64,
) -> Result<Option<usize>> {
    let level = -std::f64::consts::FRAC_PI_2;
    let mut prev: Option<usize> = None;
    for i in 0..n {
        let x = pivot[0] + (i as f64 + 0.5) * link;
        let shape = Shape::Capsule { half_height: link / 2.0 - radius, radius };
        let mut p = SolidParams::new(shape, &[x, pivot[1]]);
        p.orientation = vec![level];
        p.density = 20.0;
        let b = w.add_solid(p)?;
        let at = [pivot[0] + i as f64 * link, pivot[1]];
        match prev {
            None => hinge(w, b, None, at, 0.0)?,
            Some(a) => hinge(w, a, Some(b), at, 0.0)?,
        };
        prev = Some(b);
    }
    Ok(prev)
}

/// One limb of the ragdoll: a capsule from `top` down to `top - length` (upright), hinged
/// to `parent` at `top` with the angle limits `lower..upper` and a little joint friction.
fn limb(
    w: &mut World,
    parent: usize,
    top: [f64; 2],
    length: f64,
    radius: f64,
    limits: (f64, f64),
) -> Result<usize> {
    let b = w.add_solid(part(
        Shape::Capsule { half_height: length / 2.0 - radius, radius },
        &[top[0], top[1] - length / 2.0],
    ))?;
    joint(w, parent, b, top, limits)?;
    Ok(b)
}

/// A revolute joint with limits and a little friction (a motor holding still with 5 N m,
/// as Box2D's ragdoll has).
fn joint(w: &mut World, a: usize, b: usize, at: [f64; 2], limits: (f64, f64)) -> Result<usize> {
    let mut j = JointParams::new(JointKind::Revolute, a, Some(b), &at);
    (j.lower, j.upper) = (Some(limits.0), Some(limits.1));
    j.max_motor = 5.0;
    w.add_joint(j)
}

/// A part of the ragdoll: 200 kg/m^2 (a body 20 cm deep of water's density), so that it
/// weighs about 70 kg.
fn part(shape: Shape, at: &[f64]) -> SolidParams {
    let mut p = SolidParams::new(shape, at);
    p.density = 200.0;
    p
}

/// `ragdoll-bodies`: a 1.8 m ragdoll of 11 capsules and a ball (head, torso, upper and lower
/// arms and legs, feet) joined by revolute joints with human angle limits and a little joint
/// friction, standing, pushed at the chest and spun: it falls onto the ground and comes to
/// rest. Left and right limbs stand apart (solids of one ragdoll collide with each other,
/// except where joined).
///
/// # Errors
/// As [`World::add_solid`].
pub(super) fn ragdoll_bodies(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    ragdoll(w, [0.0, v("height")], v("push"), v("spin"))?;
    Ok(None)
}

/// One ragdoll of `ragdoll-bodies`, standing with its feet at `feet` (the middle between
/// them, their soles), its torso given the horizontal speed `push` and the angular velocity
/// `spin`: 12 solids (torso, head, then each side's upper arm, forearm, thigh, shin and
/// foot) and 11 joints. Returns its torso.
///
/// # Errors
/// As [`World::add_solid`].
pub(super) fn ragdoll(w: &mut World, feet: [f64; 2], push: f64, spin: f64) -> Result<usize> {
    let (x0, y0) = (feet[0], feet[1]);
    // Proportions of a 1.8 m person, from the feet up.
    let (shin, thigh, torso, upper_arm, forearm, head) = (0.45, 0.45, 0.6, 0.3, 0.3, 0.25);
    let hip = y0 + shin + thigh;
    let neck = hip + torso;
    let mut t =
        part(Shape::Capsule { half_height: torso / 2.0 - 0.15, radius: 0.15 }, &[x0, hip + torso / 2.0]);
    t.velocity = vec![push, 0.0];
    t.angular_velocity = vec![spin];
    let torso_i = w.add_solid(t)?;
    let head_i = w.add_solid(part(Shape::Circle { radius: head / 2.0 }, &[x0, neck + head / 2.0]))?;
    joint(w, torso_i, head_i, [x0, neck], (-0.5, 0.5))?;
    for side in [-1.0, 1.0] {
        let arm = limb(w, torso_i, [x0 + 0.25 * side, neck - 0.05], upper_arm, 0.06, (-2.5, 2.5))?;
        limb(w, arm, [x0 + 0.25 * side, neck - 0.05 - upper_arm], forearm, 0.05, (-2.5, 0.0))?;
        let leg = limb(w, torso_i, [x0 + 0.1 * side, hip], thigh, 0.09, (-0.5, 1.5))?;
        let shin_i = limb(w, leg, [x0 + 0.1 * side, hip - thigh], shin - 0.08, 0.07, (-2.0, 0.0))?;
        let heel = [x0 + 0.1 * side, y0 + 0.08];
        let mut foot =
            part(Shape::Capsule { half_height: 0.08, radius: 0.04 }, &[heel[0] + 0.08 * side, y0 + 0.04]);
        foot.orientation = vec![std::f64::consts::FRAC_PI_2];
        let foot_i = w.add_solid(foot)?;
        joint(w, shin_i, foot_i, heel, (-0.5, 0.5))?;
    }
    Ok(torso_i)
}
