//! The contact scenes (solids on the ground; the standard set of Catto's Solver2D, as far as
//! physstep has them): a box landing, a stack, a pyramid, a box on a ramp, dice thrown onto a
//! plane, a stack of cubes.

use super::{Exact, Param, Result};
use crate::contact::{Kind, Shape, SolidParams};
use crate::error::Error;
use crate::forces::Force;
use crate::world::World;

/// The most solids a contact scene builds (the broad phase and the solver are O(n) a step;
/// this bounds a step's time and memory the way `MAX_PARTICLES` does for particles).
pub const MAX_SOLIDS: usize = 100_000;

pub(super) fn count(v: &Param<'_>, name: &str, per: usize) -> Result<usize> {
    let n = v(name) as usize;
    if n.saturating_mul(per) > MAX_SOLIDS {
        return Err(Error::invalid(name, n, format!("at most {MAX_SOLIDS} solids ({per} a unit)")));
    }
    Ok(n)
}

pub(super) fn gravity(w: &mut World, g: f64) -> Result<()> {
    let mut a = [0.0; 3];
    a[1] = -g;
    w.add_force(Force::Gravity { g: a })
}

pub(super) fn ground(w: &mut World, friction: f64) -> Result<usize> {
    let mut p = if w.dim() == 2 {
        SolidParams::new(Shape::Box { half: vec![100.0, 1.0] }, &[0.0, -1.0])
    } else {
        SolidParams::new(Shape::Plane { normal: vec![0.0, 1.0, 0.0] }, &[0.0, 0.0, 0.0])
    };
    p.kind = Kind::Static;
    p.friction = friction;
    w.add_solid(p)
}

fn unit_box(w: &mut World, at: &[f64], half: f64) -> Result<usize> {
    let shape = Shape::Box { half: vec![half; w.dim()] };
    w.add_solid(SolidParams::new(shape, at))
}

/// `single-box`: a unit box dropped from `height` onto the ground.
///
/// # Errors
/// As [`World::add_solid`].
pub(super) fn single_box(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    unit_box(w, &[0.0, 0.5 + v("height")], 0.5)?;
    Ok(None)
}

/// `stack` (2D) and `box-stack` (3D): `n` unit boxes, one on another, resting on the
/// ground (a static box in 2D, a plane in 3D).
///
/// # Errors
/// As [`World::add_solid`]; `n` above [`MAX_SOLIDS`].
pub(super) fn stack(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    for i in 0..n {
        let mut at = vec![0.0; w.dim()];
        at[1] = 0.5 + i as f64;
        unit_box(w, &at, 0.5)?;
    }
    Ok(None)
}

/// `pyramid`: `rows` rows of unit boxes (`rows (rows + 1) / 2` of them), 1 cm apart.
///
/// # Errors
/// As [`World::add_solid`]; too many boxes.
pub(super) fn pyramid(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let rows = count(v, "rows", 1)?;
    if rows.saturating_mul(rows + 1) / 2 > MAX_SOLIDS {
        return Err(Error::invalid("rows", rows, format!("at most {MAX_SOLIDS} boxes in all")));
    }
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    for row in 0..rows {
        let k = rows - row;
        for i in 0..k {
            let x = (i as f64 - (k - 1) as f64 / 2.0) * 1.01;
            unit_box(w, &[x, 0.5 + row as f64], 0.5)?;
        }
    }
    Ok(None)
}

/// `ramp`: a box at rest on a plank tilted by `angle`, both of friction `friction`: it
/// sticks where `friction > tan(angle)`, else slides at `g (sin a - mu cos a)`.
///
/// # Errors
/// As [`World::add_solid`].
pub(super) fn ramp(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (a, mu) = (v("angle"), v("friction"));
    gravity(w, v("g"))?;
    let mut plank = SolidParams::new(Shape::Box { half: vec![100.0, 0.5] }, &[0.0, 0.0]);
    plank.kind = Kind::Static;
    plank.orientation = vec![a];
    plank.friction = mu;
    w.add_solid(plank)?;
    let up = 0.75;
    let mut b = SolidParams::new(Shape::Box { half: vec![0.25, 0.25] }, &[-a.sin() * up, a.cos() * up]);
    b.orientation = vec![a];
    b.friction = mu;
    w.add_solid(b)?;
    Ok(None)
}

/// `dice` (3D): `n` cubes thrown spinning onto a plane from a grid above it.
///
/// # Errors
/// As [`World::add_solid`]; too many dice.
pub(super) fn dice(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    let side = (n as f64).sqrt().ceil() as usize;
    let mut rng = super::SplitMix(v("seed") as u64);
    for i in 0..n {
        let (gx, gz) = ((i % side) as f64, (i / side) as f64);
        let mut d = SolidParams::new(
            Shape::Box { half: vec![0.1; 3] },
            &[0.5 * (gx - side as f64 / 2.0), 1.0 + 0.1 * (i % 3) as f64, 0.5 * (gz - side as f64 / 2.0)],
        );
        let q = glam::DQuat::from_euler(
            glam::EulerRot::XYZ,
            6.0 * rng.unit(),
            6.0 * rng.unit(),
            6.0 * rng.unit(),
        );
        d.orientation = vec![q.w, q.x, q.y, q.z];
        d.velocity = vec![2.0 * rng.unit() - 1.0, 0.0, 2.0 * rng.unit() - 1.0];
        d.angular_velocity = (0..3).map(|_| 20.0 * rng.unit() - 10.0).collect();
        d.density = 1000.0;
        d.restitution = 0.2;
        w.add_solid(d)?;
    }
    Ok(None)
}
