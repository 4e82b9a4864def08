//! The rigid-body scenes: the tennis-racket flip, a top on its tip, a box pushed off centre.

use super::{Exact, Param, Result};
use crate::forces::Force;
use crate::rigid::inertia::Shape;
use crate::world::{BodyParams, World};

/// The `racket` scene: a thin plate of principal moments 1 : 2 : 3 spun about its intermediate axis.
///
/// # Errors
/// As [`World::add_body`].
pub(super) fn racket(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    // A thin plate: principal moments m/3 (hy^2, hx^2, hx^2 + hy^2) = 1 : 2 : 3 to
    // 3e-5 (the thickness), spun about the intermediate axis with a small wobble.
    let s = 0.5;
    w.add_body(&BodyParams {
        shape: Shape::Box { half_extents: [2f64.sqrt() * s, s, 0.005 * s] },
        mass: Some(12.0),
        angular_velocity: [v("wobble"), v("spin"), v("wobble")],
        ..BodyParams::default()
    })?;
    Ok(None)
}

/// The `top` scene: a cylinder pinned at its tip under gravity, tilted and spinning.
///
/// # Errors
/// As [`World::add_body`].
pub(super) fn top(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    // A cylinder pinned at the centre of its bottom face (the origin), tilted about x.
    let (r, h, tilt, spin) = (v("radius"), v("height"), v("tilt"), v("spin"));
    let (s, c) = tilt.sin_cos();
    w.add_force(Force::Gravity { g: [0.0, 0.0, -v("g")] })?;
    w.add_body(&BodyParams {
        shape: Shape::Cylinder { radius: r, height: h },
        mass: Some(v("m")),
        orientation: [(tilt / 2.0).cos(), (tilt / 2.0).sin(), 0.0, 0.0],
        position: [0.0, -s * h / 2.0, c * h / 2.0],
        angular_velocity: [0.0, -s * spin, c * spin],
        pivot: Some([0.0, 0.0, -h / 2.0]),
        ..BodyParams::default()
    })?;
    Ok(None)
}

/// The `tumble` scene: a box pushed up at a corner, tumbling as it flies under gravity.
///
/// # Errors
/// As [`World::add_body`].
pub(super) fn tumble(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    // A box given an upward impulse J at a top corner r: v0 = J / m and L0 = r x J
    // (omega0 = I^-1 L0, the box's axes being principal), then falling under gravity.
    let (hx, hy, hz, m, j) = (0.4, 0.2, 0.1, 2.0, v("impulse"));
    let inertia =
        [m / 3.0 * (hy * hy + hz * hz), m / 3.0 * (hx * hx + hz * hz), m / 3.0 * (hx * hx + hy * hy)];
    let l0 = [hy * j, -hx * j, 0.0]; // (hx, hy, hz) x (0, 0, j)
    w.add_force(Force::Gravity { g: [0.0, 0.0, -v("g")] })?;
    w.add_body(&BodyParams {
        shape: Shape::Box { half_extents: [hx, hy, hz] },
        mass: Some(m),
        velocity: [0.0, 0.0, j / m],
        angular_velocity: [l0[0] / inertia[0], l0[1] / inertia[1], 0.0],
        ..BodyParams::default()
    })?;
    Ok(None)
}
