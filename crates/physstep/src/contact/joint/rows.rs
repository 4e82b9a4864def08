//! How the soft step solves the joints: each step's arms and frames, the warm start, the
//! rows of the five kinds (solve with the joint's soft bias, relax without), and the optional
//! position projection after the step.

use super::{pose, Impulses, Joint, JointKind};
use crate::contact::points::{effective_mass, push, relative_velocity, two, Motion, Soft};
use crate::contact::space::{Space, Vect};
use crate::contact::Body;

/// Prepares every joint for a step of substeps `h`: the arms and frames where the step
/// begins, the springs' coefficients.
pub(crate) fn prepare<S: Space>(joints: &mut [Joint<S>], bodies: &[Body<S>], h: f64) {
    for j in joints {
        let (ca, qa) = pose(bodies, j.a);
        let (cb, qb) = pose(bodies, Some(j.b));
        j.ra = S::rotate(qa, j.local_a);
        j.rb = S::rotate(qb, j.local_b);
        j.delta_center = cb - ca;
        j.offset = S::offset(qa, qb, j.rel);
        j.slide_world = S::rotate(qa, j.slide);
        j.hinge_world = S::turn_axis(qa, j.hinge);
        j.spring = Soft::new(j.hertz, j.damping_ratio, h);
    }
}

/// Where a joint's ends are during a substep: the arms turned by each body's rotation
/// since the step began, and the anchors' separation.
fn arms<S: Space>(j: &Joint<S>, ma: &Motion<S>, mb: &Motion<S>) -> (S::V, S::V, S::V) {
    let ra = S::rotate_delta(ma.dq, j.ra);
    let rb = S::rotate_delta(mb.dq, j.rb);
    (ra, rb, mb.dp - ma.dp + rb - ra + j.delta_center)
}

fn turn<S: Space>(ma: &mut Motion<S>, mb: &mut Motion<S>, l: S::W) {
    ma.w -= S::apply(ma.inv_i, l);
    mb.w += S::apply(mb.inv_i, l);
}

fn angular_mass<S: Space>(ma: &Motion<S>, mb: &Motion<S>, u: S::W) -> f64 {
    let k = u.dot(S::apply(ma.inv_i, u)) + u.dot(S::apply(mb.inv_i, u));
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

/// Applies the accumulated impulses again (the warm start of a substep).
pub(crate) fn warm_start<S: Space>(joints: &[Joint<S>], motion: &mut [Motion<S>]) {
    let world = motion.len() - 1;
    for j in joints {
        let (a, b) = j.ends(world);
        let (ma, mb) = two(motion, a, b);
        let (ra, rb, d) = arms(j, ma, mb);
        let i = &j.impulses;
        let axial = i.axial + i.motor + i.lower - i.upper;
        match j.kind {
            JointKind::Ball | JointKind::Weld => push(ma, mb, ra, rb, i.linear),
            JointKind::Revolute => {
                push(ma, mb, ra, rb, i.linear);
                let mut l = j.hinge_world * axial;
                for (s, imp) in S::swing_axes(j.hinge_world).iter().zip(i.swing).take(S::SWINGS) {
                    l += *s * imp;
                }
                turn(ma, mb, l);
            }
            JointKind::Distance => {
                let len = d.dot(d).sqrt();
                if len > 0.0 {
                    push(ma, mb, ra, rb, d * (axial / len));
                }
            }
            JointKind::Prismatic => {
                let axis = S::rotate_delta(ma.dq, j.slide_world);
                push(ma, mb, ra + d, rb, i.linear + axis * axial);
            }
        }
        if matches!(j.kind, JointKind::Weld | JointKind::Prismatic) {
            turn(ma, mb, i.angular);
        }
    }
}

/// The coefficients of a row: `(bias velocity per unit error, mass scale, impulse scale)`.
fn coefficients(soft: Option<Soft>) -> (f64, f64, f64) {
    match soft {
        Some(s) => (s.bias_rate, s.mass_scale, s.impulse_scale),
        None => (0.0, 1.0, 0.0),
    }
}

/// One inequality row (a limit) of error `c` (>= 0 when within the limit), velocity `cdot`
/// and effective mass `mass`: its new accumulated impulse (>= 0) and the increment.
fn limit_row(c: f64, cdot: f64, mass: f64, old: f64, inv_h: f64, soft: Option<Soft>) -> (f64, f64) {
    let (bias, ms, is) = if c > 0.0 {
        // Not reached: speculative, the gap closed in this substep and no more.
        (c * inv_h, 1.0, 0.0)
    } else {
        let (rate, ms, is) = coefficients(soft);
        (rate * c, ms, is)
    };
    let new = (old - ms * mass * (cdot + bias) - is * old).max(0.0);
    (new, new - old)
}

/// A value `x` along `dir` (at arms `arm` of `a` and `rb` of `b`) kept within `lo..hi`
/// (either infinite: no limit): the two inequality rows of a slider's travel or a distance
/// joint's lengths.
#[allow(clippy::too_many_arguments)]
fn limits<S: Space>(
    ma: &mut Motion<S>,
    mb: &mut Motion<S>,
    (arm, rb, dir): (S::V, S::V, S::V),
    x: f64,
    (lo, hi): (f64, f64),
    mass: f64,
    imp: &mut Impulses<S>,
    inv_h: f64,
    soft: Option<Soft>,
) {
    let speed = |ma: &Motion<S>, mb: &Motion<S>| relative_velocity(ma, mb, arm, rb).dot(dir);
    if lo > f64::NEG_INFINITY {
        let (new, inc) = limit_row(x - lo, speed(ma, mb), mass, imp.lower, inv_h, soft);
        imp.lower = new;
        push(ma, mb, arm, rb, dir * inc);
    }
    if hi < f64::INFINITY {
        let (new, inc) = limit_row(hi - x, -speed(ma, mb), mass, imp.upper, inv_h, soft);
        imp.upper = new;
        push(ma, mb, arm, rb, dir * -inc);
    }
}

/// One pass over the joints: with `soft` (the joint stiffness; the solve pass) the errors
/// are pulled toward zero, without (the relax pass) only the velocities are constrained.
/// Springs act in both passes.
#[allow(clippy::too_many_lines)] // one match over the five kinds, each Box2D's rows
pub(crate) fn solve<S: Space>(joints: &mut [Joint<S>], motion: &mut [Motion<S>], h: f64, soft: Option<Soft>) {
    let world = motion.len() - 1;
    let inv_h = 1.0 / h;
    for j in joints {
        let (a, b) = j.ends(world);
        let (ma, mb) = two(motion, a, b);
        let (ra, rb, d) = arms(j, ma, mb);
        let (rate, ms, is) = coefficients(soft);
        let dw = |ma: &Motion<S>, mb: &Motion<S>| mb.w - ma.w;
        let imp = &mut j.impulses;
        // The angular rows first (a motor, limits, the hinge's swing; the weld's and the
        // slider's whole rotation), then the point or the line.
        if j.kind == JointKind::Revolute {
            let u = j.hinge_world;
            let mass = angular_mass(ma, mb, u);
            let err = S::rotation_error(j.offset, ma.dq, mb.dq);
            if j.max_motor > 0.0 {
                let cdot = dw(ma, mb).dot(u) - j.motor_speed;
                let most = h * j.max_motor;
                let new = (imp.motor - mass * cdot).clamp(-most, most);
                turn(ma, mb, u * (new - imp.motor));
                imp.motor = new;
            }
            let angle = err.dot(u);
            if j.lower > f64::NEG_INFINITY {
                let (new, inc) = limit_row(angle - j.lower, dw(ma, mb).dot(u), mass, imp.lower, inv_h, soft);
                imp.lower = new;
                turn(ma, mb, u * inc);
            }
            if j.upper < f64::INFINITY {
                let (new, inc) = limit_row(j.upper - angle, -dw(ma, mb).dot(u), mass, imp.upper, inv_h, soft);
                imp.upper = new;
                turn(ma, mb, u * -inc);
            }
            for (s, acc) in S::swing_axes(u).iter().zip(imp.swing.iter_mut()).take(S::SWINGS) {
                let m = angular_mass(ma, mb, *s);
                let inc = -ms * m * (dw(ma, mb).dot(*s) + rate * err.dot(*s)) - is * *acc;
                *acc += inc;
                turn(ma, mb, *s * inc);
            }
        }
        if matches!(j.kind, JointKind::Weld | JointKind::Prismatic) {
            let err = S::rotation_error(j.offset, ma.dq, mb.dq);
            let (rate, ms, is) = if j.kind == JointKind::Weld && j.hertz > 0.0 {
                coefficients(Some(j.spring))
            } else {
                (rate, ms, is)
            };
            let x = S::angular_solve(ma.inv_i, mb.inv_i, dw(ma, mb) + err * rate);
            let inc = x * -ms - imp.angular * is;
            imp.angular += inc;
            turn(ma, mb, inc);
        }
        match j.kind {
            JointKind::Ball | JointKind::Revolute | JointKind::Weld => {
                let (rate, ms, is) = if j.kind == JointKind::Weld && j.hertz > 0.0 {
                    coefficients(Some(j.spring))
                } else {
                    (rate, ms, is)
                };
                let cdot = relative_velocity(ma, mb, ra, rb);
                let x =
                    S::point_solve((ma.inv_mass, ma.inv_i, ra), (mb.inv_mass, mb.inv_i, rb), cdot + d * rate);
                let inc = x * -ms - imp.linear * is;
                imp.linear += inc;
                push(ma, mb, ra, rb, inc);
            }
            JointKind::Distance => {
                let len = d.dot(d).sqrt();
                if len == 0.0 {
                    continue;
                }
                let n = d * (1.0 / len);
                let mass = effective_mass(ma, mb, ra, rb, n);
                let vn = |ma: &Motion<S>, mb: &Motion<S>| relative_velocity(ma, mb, ra, rb).dot(n);
                if j.min_length < j.max_length {
                    if j.hertz > 0.0 {
                        let (rate, ms, is) = coefficients(Some(j.spring));
                        let inc = -ms * mass * (vn(ma, mb) + rate * (len - j.length)) - is * imp.axial;
                        imp.axial += inc;
                        push(ma, mb, ra, rb, n * inc);
                    }
                    let lo = if j.min_length > 0.0 { j.min_length } else { f64::NEG_INFINITY };
                    limits(ma, mb, (ra, rb, n), len, (lo, j.max_length), mass, imp, inv_h, soft);
                } else {
                    let inc = -ms * mass * (vn(ma, mb) + rate * (len - j.length)) - is * imp.axial;
                    imp.axial += inc;
                    push(ma, mb, ra, rb, n * inc);
                }
            }
            JointKind::Prismatic => {
                let axis = S::rotate_delta(ma.dq, j.slide_world);
                let arm = ra + d;
                let along = |ma: &Motion<S>, mb: &Motion<S>| relative_velocity(ma, mb, arm, rb).dot(axis);
                let mass = effective_mass(ma, mb, arm, rb, axis);
                let travel = d.dot(axis);
                if j.max_motor > 0.0 {
                    let most = h * j.max_motor;
                    let new = (imp.motor - mass * (along(ma, mb) - j.motor_speed)).clamp(-most, most);
                    push(ma, mb, arm, rb, axis * (new - imp.motor));
                    imp.motor = new;
                }
                limits(ma, mb, (arm, rb, axis), travel, (j.lower, j.upper), mass, imp, inv_h, soft);
                // Across the axis: the rows along the axis' normals, their impulses kept as
                // one vector (so a turning frame of normals loses nothing).
                let across = S::tangents(axis);
                for t in across.iter().take(S::TANGENTS) {
                    let t = *t;
                    let m = effective_mass(ma, mb, arm, rb, t);
                    let old = imp.linear.dot(t);
                    let inc =
                        -ms * m * (relative_velocity(ma, mb, arm, rb).dot(t) + rate * d.dot(t)) - is * old;
                    imp.linear += t * inc;
                    push(ma, mb, arm, rb, t * inc);
                }
            }
        }
    }
}

/// After the substeps, `passes` sweeps that move the jointed solids so their anchors meet
/// (a non-linear Gauss-Seidel pass on positions, as Box2D v2 ended its step). A velocity
/// constraint keeps two points moving together only to first order: on a solid turning at
/// `w` a point leaves its partner by about `w^2 r h^2 / 2` a substep, which the soft bias
/// pulls back only over later substeps (a whipping chain's links 4-8 mm apart at 60 Hz). The
/// projection moves positions and orientations, not velocities, each in proportion to its
/// inverse mass and inertia.
pub(crate) fn project<S: Space>(joints: &[Joint<S>], bodies: &mut [Body<S>], passes: u32) {
    let still = Motion::<S>::fixed();
    let motion = |bodies: &[Body<S>], i: Option<usize>| match i {
        Some(i) => Motion {
            moves: bodies[i].inv_mass > 0.0,
            inv_mass: bodies[i].inv_mass,
            inv_i: S::world_inverse_inertia(bodies[i].q, bodies[i].inv_i_local),
            ..still
        },
        None => still,
    };
    for _ in 0..passes {
        for j in joints {
            let (ca, qa) = pose(bodies, j.a);
            let (cb, qb) = pose(bodies, Some(j.b));
            let (ma, mb) = (motion(bodies, j.a), motion(bodies, Some(j.b)));
            let (ra, rb) = (S::rotate(qa, j.local_a), S::rotate(qb, j.local_b));
            let d = cb + rb - ca - ra;
            let (arm, p) = match j.kind {
                JointKind::Ball | JointKind::Revolute | JointKind::Weld => {
                    (ra, -S::point_solve((ma.inv_mass, ma.inv_i, ra), (mb.inv_mass, mb.inv_i, rb), d))
                }
                JointKind::Prismatic => {
                    let axis = S::rotate(qa, j.slide);
                    let mut p = S::V::default();
                    for t in S::tangents(axis).iter().take(S::TANGENTS) {
                        p -= *t * (effective_mass(&ma, &mb, ra + d, rb, *t) * d.dot(*t));
                    }
                    (ra + d, p)
                }
                JointKind::Distance => {
                    let len = d.dot(d).sqrt();
                    let c = if len < j.min_length {
                        len - j.min_length
                    } else if len > j.max_length {
                        len - j.max_length
                    } else {
                        0.0
                    };
                    if c == 0.0 || len == 0.0 {
                        continue;
                    }
                    let n = d * (1.0 / len);
                    (ra, n * -(effective_mass(&ma, &mb, ra, rb, n) * c))
                }
            };
            if let Some(a) = j.a {
                let b = &mut bodies[a];
                b.c -= p * ma.inv_mass;
                b.q = S::turn(b.q, S::no_delta(), -S::apply(ma.inv_i, S::cross_vv(arm, p)), 1.0).0;
            }
            let b = &mut bodies[j.b];
            b.c += p * mb.inv_mass;
            b.q = S::turn(b.q, S::no_delta(), S::apply(mb.inv_i, S::cross_vv(rb, p)), 1.0).0;
        }
    }
}
