//! Joints in XPBD form, for the `xpbd` contact solver (`contact/xpbd.rs`): each substep, one
//! pass of position corrections (Mueller et al. 2020, section 3.3: a correction along the
//! error's direction `n` of `-c / (w_a + w_b)`, `w = 1/m + (r x n) . I^-1 (r x n)` for a point,
//! `n . I^-1 n` for an angle), every one rigid (compliance 0: these joints have none).
//!
//! ```text
//! ball, revolute  the anchors together; in space a hinge's axis too (the rotation error
//!                 across its axis, one correction a swing direction)   (no limit, no motor)
//! weld            the anchors together and the relative rotation        (hertz 0)
//! distance        the anchors `length` apart                            (rigid: min = max)
//! ```
//!
//! A revolute joint with a limit or a motor, a prismatic joint, a distance joint that is a
//! spring or a rope and a soft weld keep their velocity rows (`rows.rs`), which the xpbd
//! step solves with the soft bias before its drift and without after its velocity update.

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
        if j.kind == JointKind::Revolute {
            let u = j.hinge_world;
            for (k, s) in S::swing_axes(u).iter().enumerate().take(S::SWINGS) {
                let (ma, mb) = (&motion[ends.0], &motion[ends.1]);
                let err = S::rotation_error(j.offset, ma.dq, mb.dq).dot(*s);
                let w = angular_weight(ma, *s) + angular_weight(mb, *s);
                if err == 0.0 || w == 0.0 {
                    continue;
                }
                let l = -err / w;
                j.impulses.swing[k] += l * inv_h;
                twist(bodies, motion, ends, *s * l);
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
        let len = d.dot(d).sqrt();
        if len == 0.0 {
            continue;
        }
        let n = d * (1.0 / len);
        let c = if j.kind == JointKind::Distance { len - j.length } else { len };
        let w = weight(ma, ra, n) + weight(mb, rb, n);
        if c == 0.0 || w == 0.0 {
            continue;
        }
        let lambda = -c / w;
        if j.kind == JointKind::Distance {
            j.impulses.axial += lambda * inv_h;
        } else {
            j.impulses.linear += n * (lambda * inv_h);
        }
        apart(bodies, motion, ends, (ra, rb), n * lambda);
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
