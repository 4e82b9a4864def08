//! Joints in XPBD form, for the `xpbd` contact solver (`contact/xpbd.rs`): each substep, one
//! pass of position corrections (Mueller et al. 2020, section 3.3), every one rigid
//! (compliance 0: these joints have none):
//!
//! ```text
//! ball, revolute  the anchors brought together by the position impulse K^-1 d (the point's
//!                 effective mass: all its directions at once, where the paper corrects
//!                 along d alone); in space a hinge's axes too: the rotation a_b x a_a (the
//!                 axis as each solid carries it) shared by the two angular weights n .
//!                 I^-1 n                                               (no limit, no motor)
//! weld            the relative rotation (its rotation vector), then the anchors as above
//!                                                                       (hertz 0)
//! distance        the anchors `length` apart: -c / (w_a + w_b) along the line, w = 1/m +
//!                 (r x n) . I^-1 (r x n)                                (rigid: min = max)
//! ```
//!
//! A revolute joint with a limit or a motor, a prismatic joint, a distance joint that is a
//! spring or a rope and a soft weld keep their velocity rows (`rows.rs`), which the xpbd
//! step solves with the soft bias before its drift and without after its velocity update.
//! (Measured on the ball-chain: the point along `d` alone, as the paper's scalar
//! corrections, left the joints 72.7 mm apart at the worst; `K^-1 d`, 16.1 mm. A 3D hinge's
//! swing taken from its rotation vector's components across the axis left a door swinging
//! about 1 rad 2 cm off its pin (19 cm with the point along `d` alone); from the axes, 2e-9
//! m.)

use super::{Joint, JointKind};
use crate::contact::points::Motion;
use crate::contact::space::{Space, Vect};
use crate::contact::xpbd::{angular_weight, apart, turn_by, weight};
use crate::contact::Body;

impl<S: Space> Joint<S> {
    /// Whether the xpbd solver corrects this joint positionally (else it keeps its rows).
    pub(crate) fn positional(&self) -> bool {
        match self.kind {
            JointKind::Ball => true,
            JointKind::Revolute => {
                self.max_motor == 0.0 && self.lower == f64::NEG_INFINITY && self.upper == f64::INFINITY
            }
            JointKind::Weld => self.hertz == 0.0,
            JointKind::Distance => self.min_length == self.max_length,
            JointKind::Prismatic => false,
        }
    }
}

/// An angular position impulse `l`: `-l` to `a`, `l` to `b`.
fn twist<S: Space>(bodies: &mut [Body<S>], motion: &mut [Motion<S>], (a, b): (usize, usize), l: S::W) {
    if a < bodies.len() {
        turn_by(&mut bodies[a], &mut motion[a], -l);
    }
    turn_by(&mut bodies[b], &mut motion[b], l);
}

/// One pass of position corrections over the joints [`Joint::positional`] says are
/// positional (the others are left alone), from the motion since the step began; each
/// joint's impulses gain the pass's position impulses over `h` (the xpbd step divides them
/// by its substeps at the end: a soft step taking over warm-starts from them).
pub(crate) fn solve_positions<S: Space>(
    joints: &mut [Joint<S>],
    motion: &mut [Motion<S>],
    bodies: &mut [Body<S>],
    h: f64,
) {
    let world = motion.len() - 1;
    let inv_h = 1.0 / h;
    for j in joints.iter_mut().filter(|j| j.positional()) {
        let (a, b) = j.ends(world);
        let ends = (a as usize, b as usize);
        // The angular rows first (a hinge's swing in space, a weld's whole rotation), then the
        // point or the line.
        if j.kind == JointKind::Revolute && S::SWINGS > 0 {
            // In space, the hinge's axis as each solid carries it now, turned into line (the
            // paper's `a_a x a_b`): the rotation that takes `b`'s onto `a`'s, shared by
            // their angular weights.
            let q = |i: usize| if i < bodies.len() { bodies[i].q } else { S::identity() };
            let ua = vector::<S>(S::turn_axis(q(ends.0), j.hinge));
            let hinge_b = S::turn_axis(S::relative(j.rel, S::identity()), j.hinge);
            let ub = vector::<S>(S::turn_axis(q(ends.1), hinge_b));
            let e = S::cross_vv(ub, ua);
            let size = e.dot(e).sqrt();
            if size > 0.0 {
                let n = e * (1.0 / size);
                let (ma, mb) = (&motion[ends.0], &motion[ends.1]);
                let w = angular_weight(ma, n) + angular_weight(mb, n);
                if w > 0.0 {
                    let l = n * (size.min(1.0).asin() / w);
                    for (k, s) in S::swing_axes(j.hinge_world).iter().enumerate().take(S::SWINGS) {
                        j.impulses.swing[k] += l.dot(*s) * inv_h;
                    }
                    twist(bodies, motion, ends, l);
                }
            }
        }
        if j.kind == JointKind::Weld {
            let (ma, mb) = (&motion[ends.0], &motion[ends.1]);
            let err = S::rotation_error(j.offset, ma.dq, mb.dq);
            let size = err.dot(err).sqrt();
            if size > 0.0 {
                let n = err * (1.0 / size);
                let w = angular_weight(ma, n) + angular_weight(mb, n);
                if w > 0.0 {
                    let l = n * (-size / w);
                    j.impulses.angular += l * inv_h;
                    twist(bodies, motion, ends, l);
                }
            }
        }
        let (ma, mb) = (&motion[ends.0], &motion[ends.1]);
        let (ra, rb) = (S::rotate_delta(ma.dq, j.ra), S::rotate_delta(mb.dq, j.rb));
        let d = mb.dp - ma.dp + rb - ra + j.delta_center;
        if j.kind == JointKind::Distance {
            let len = d.dot(d).sqrt();
            if len == 0.0 {
                continue;
            }
            let n = d * (1.0 / len);
            let c = len - j.length;
            let w = weight(ma, ra, n) + weight(mb, rb, n);
            if c == 0.0 || w == 0.0 {
                continue;
            }
            let lambda = -c / w;
            j.impulses.axial += lambda * inv_h;
            apart(bodies, motion, ends, (ra, rb), n * lambda);
        } else {
            // The point: the position impulse that brings the anchors together, all three (two)
            // directions at once (`K^-1 d`, the point's 3 x 3 (2 x 2) effective mass).
            let p = -S::point_solve(solid(ma, ra), solid(mb, rb), d);
            j.impulses.linear += p * inv_h;
            apart(bodies, motion, ends, (ra, rb), p);
        }
    }
}

/// An angular direction as a vector of the space (in space both are three numbers; only
/// space has hinge swings).
fn vector<S: Space>(w: S::W) -> S::V {
    let mut c = Vec::with_capacity(3);
    w.write(&mut c);
    S::V::read(&c)
}

/// A solid as [`Space::point_solve`] takes it (one the solver does not move: no inverse
/// mass or inertia).
fn solid<S: Space>(m: &Motion<S>, r: S::V) -> (f64, S::InvI, S::V) {
    if m.moves {
        (m.inv_mass, m.inv_i, r)
    } else {
        (0.0, S::no_inertia(), r)
    }
}

/// Before an xpbd step: the positional joints' impulses cleared (the step sums its own).
pub(crate) fn clear_positional<S: Space>(joints: &mut [Joint<S>]) {
    for j in joints.iter_mut().filter(|j| j.positional()) {
        j.impulses = super::Impulses::default();
    }
}

/// After an xpbd step of `n` substeps: the positional joints' summed impulses made a
/// substep's mean (what a soft step's accumulated impulse is, should it take over).
pub(crate) fn average_positional<S: Space>(joints: &mut [Joint<S>], n: u32) {
    let f = 1.0 / f64::from(n);
    for j in joints.iter_mut().filter(|j| j.positional()) {
        let i = &mut j.impulses;
        i.linear = i.linear * f;
        i.angular = i.angular * f;
        i.swing = [i.swing[0] * f, i.swing[1] * f];
        i.axial *= f;
    }
}
