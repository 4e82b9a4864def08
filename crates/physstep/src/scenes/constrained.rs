//! The constraint scenes: a cloth hanging from its top corners, a ragdoll falling onto the
//! ground (the notes' Verlet position-based physics).

use super::{Exact, Param, Result};
use crate::forces::{Endpoint, Force};
use crate::world::World;

/// The ragdoll's particles at rest, upright, feet at y = 0, m: head, neck, pelvis, left
/// elbow, left hand, right elbow, right hand, left knee, left foot, right knee, right foot.
const FIGURE: [[f64; 2]; 11] = [
    [0.0, 1.75],
    [0.0, 1.5],
    [0.0, 1.0],
    [-0.3, 1.3],
    [-0.55, 1.1],
    [0.3, 1.3],
    [0.55, 1.1],
    [-0.12, 0.5],
    [-0.15, 0.0],
    [0.12, 0.5],
    [0.15, 0.0],
];

/// The ragdoll's bones (rigid distances at their rest length).
const BONES: [(usize, usize); 10] =
    [(0, 1), (1, 2), (1, 3), (3, 4), (1, 5), (5, 6), (2, 7), (7, 8), (2, 9), (9, 10)];

/// The ragdoll's joint limits: `(i, j, min, max)` as fractions of the rest distance between
/// `i` and `j`, the two ends of a joint (elbows and knees bend one way only far enough to
/// fold, the head stays on its shoulders, the hips and shoulders keep a range).
const LIMITS: [(usize, usize, f64, f64); 8] = [
    (1, 4, 0.35, 1.0), // left elbow: shoulder to hand
    (1, 6, 0.35, 1.0), // right elbow
    (2, 8, 0.4, 1.0),  // left knee: hip to foot
    (2, 10, 0.4, 1.0), // right knee
    (0, 2, 0.9, 1.0),  // neck: head to pelvis
    (7, 9, 0.5, 3.0),  // hips: knee to knee
    (3, 2, 0.5, 1.3),  // left shoulder: elbow to pelvis
    (5, 2, 0.5, 1.3),  // right shoulder
];

use super::specs::MAX_PARTICLES;

/// A `W x H` grid in the x-y plane, row 0 at the top (y = 0) hanging down, particle
/// `(c, r)` at index `r W + c`; structural links to the right and below, shear links on both
/// diagonals; the top corners pinned.
pub(super) fn cloth(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (nw, nh, s) = (v("w") as usize, v("h") as usize, v("spacing"));
    // Each of w and h may be up to a million; their product is refused before it is built.
    if nw.saturating_mul(nh) > MAX_PARTICLES {
        return Err(crate::Error::invalid(
            "w x h",
            format!("{nw} x {nh}"),
            format!("at most {MAX_PARTICLES} particles"),
        ));
    }
    let x: Vec<f64> =
        (0..nh).flat_map(|r| (0..nw).flat_map(move |c| [c as f64 * s, -(r as f64) * s, 0.0])).collect();
    w.add_particles(&x, None, Some(&vec![v("m"); nw * nh]), false)?;
    w.add_force(Force::Gravity { g: [0.0, -v("g"), v("wind")] })?;
    if v("drag") > 0.0 {
        w.add_force(Force::Drag { linear: v("drag"), quadratic: 0.0 })?;
    }
    let compliance = v("compliance");
    let at = |c: usize, r: usize| r * nw + c;
    let mut link = |a: usize, b: usize, len: f64| {
        w.add_distance_constraint(a, Endpoint::Particle(b), Some(len), compliance).map(|_| ())
    };
    let diag = s * std::f64::consts::SQRT_2;
    for r in 0..nh {
        for c in 0..nw {
            if c + 1 < nw {
                link(at(c, r), at(c + 1, r), s)?;
            }
            if r + 1 < nh {
                link(at(c, r), at(c, r + 1), s)?;
            }
            if c + 1 < nw && r + 1 < nh {
                link(at(c, r), at(c + 1, r + 1), diag)?;
                link(at(c + 1, r), at(c, r + 1), diag)?;
            }
        }
    }
    w.add_pin(at(0, 0), &[0.0, 0.0, 0.0])?;
    if nw > 1 {
        w.add_pin(at(nw - 1, 0), &[(nw - 1) as f64 * s, 0.0, 0.0])?;
    }
    Ok(None)
}

/// The stick figure tilted by `tilt` about its pelvis, lifted so its lowest point is at
/// `height`, turning at `spin`; bones rigid, joints limited, the ground `y >= 0`.
pub(super) fn ragdoll(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (sn, cs) = v("tilt").sin_cos();
    let pivot = FIGURE[2];
    let turned: Vec<[f64; 2]> = FIGURE
        .iter()
        .map(|p| {
            let (dx, dy) = (p[0] - pivot[0], p[1] - pivot[1]);
            [cs * dx - sn * dy, sn * dx + cs * dy]
        })
        .collect();
    let low = turned.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let lift = v("height") - low;
    let om = v("spin");
    let mut x = Vec::with_capacity(2 * FIGURE.len());
    let mut vel = Vec::with_capacity(2 * FIGURE.len());
    for p in &turned {
        x.extend([p[0], p[1] + lift]);
        vel.extend([-om * p[1], om * p[0]]);
    }
    w.add_particles(&x, Some(&vel), Some(&[v("m"); FIGURE.len()]), false)?;
    w.add_force(Force::Gravity { g: [0.0, -v("g"), 0.0] })?;
    let rest = |a: usize, b: usize| (FIGURE[a][0] - FIGURE[b][0]).hypot(FIGURE[a][1] - FIGURE[b][1]);
    for (a, b) in BONES {
        w.add_distance_constraint(a, Endpoint::Particle(b), Some(rest(a, b)), 0.0)?;
    }
    for (a, b, lo, hi) in LIMITS {
        let r = rest(a, b);
        w.add_distance_limit(a, Endpoint::Particle(b), lo * r, hi * r)?;
    }
    w.add_plane(&[0.0, 1.0], 0.0)?;
    Ok(None)
}
