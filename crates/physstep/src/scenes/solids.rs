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
    w.add_force(Force::Gravity { g: a }).map(|_| ())
}

pub(super) fn ground(w: &mut World, friction: f64) -> Result<usize> {
    ground_at(w, friction, [0.0, 0.0])
}

/// The ground with its top at `at` (2D: a static box 200 m wide and 2 m deep below `at`; 3D:
/// the plane y = 0, `at` unused).
pub(super) fn ground_at(w: &mut World, friction: f64, at: [f64; 2]) -> Result<usize> {
    let mut p = if w.dim() == 2 {
        SolidParams::new(Shape::Box { half: vec![100.0, 1.0] }, &[at[0], at[1] - 1.0])
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
    pyramid_at(w, rows, [0.0, 0.0])?;
    Ok(None)
}

/// The ground and `rows` rows of unit boxes 1 cm apart on it, centred on `origin` (the
/// middle of the ground's top): `pyramid`, and `far-pyramid` far from the world's origin.
pub(super) fn pyramid_at(w: &mut World, rows: usize, origin: [f64; 2]) -> Result<()> {
    ground_at(w, 0.6, origin)?;
    for row in 0..rows {
        let k = rows - row;
        for i in 0..k {
            let x = (i as f64 - (k - 1) as f64 / 2.0) * 1.01;
            unit_box(w, &[origin[0] + x, origin[1] + 0.5 + row as f64], 0.5)?;
        }
    }
    Ok(())
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

// The rest of Solver2D's contact scenes (Catto, Solver2D, 2024, and Box2D v3's samples, where
// the scene is named after one), at their parameters unless a scene's doc says otherwise.

/// `card-house`: Box2D v3's card house (from PEEL): `levels` (5) rows of cards 40 cm tall
/// and 2 mm thick, leaning in pairs at 25 degrees with a card laid flat across each pair's
/// top, friction 0.7, on a static ground box; stepped at 16 substeps of two passes.
///
/// # Errors
/// As [`World::add_solid`]; `levels` above 100.
pub(super) fn card_house(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let levels = count(v, "levels", 1)?;
    if levels > 100 {
        return Err(Error::invalid("levels", levels, "at most 100"));
    }
    gravity(w, v("g"))?;
    // Cards 2 mm thick, started (as Box2D places them) up to 2 mm into the ground and into
    // each other: at the default 8 substeps and one pass their contacts let the house creep
    // and fall at about 3 s; at 16 substeps and two passes it stands.
    w.set_substeps(16)?;
    w.set_solver_iterations(2)?;
    let mut ground =
        SolidParams::new(Shape::Box { half: vec![40.0 + 0.35 * levels as f64, 2.0] }, &[0.0, -2.0]);
    ground.kind = Kind::Static;
    ground.friction = 0.7;
    w.add_solid(ground)?;
    let (height, thickness) = (0.2, 0.001);
    let lean = 25.0_f64.to_radians();
    let card = |w: &mut World, x: f64, y: f64, angle: f64| {
        let mut c = SolidParams::new(Shape::Box { half: vec![thickness, height] }, &[x, y]);
        c.orientation = vec![angle];
        c.friction = 0.7;
        w.add_solid(c)
    };
    let (mut x0, mut y) = (0.0, height - 0.02);
    for row in 0..levels {
        let n = levels - row;
        let mut x = x0;
        for i in 0..n {
            if i + 1 != n {
                card(w, x + 0.25, y + height - 0.015, std::f64::consts::FRAC_PI_2)?;
            }
            card(w, x, y, -lean)?;
            x += 0.175;
            card(w, x, y, lean)?;
            x += 0.175;
        }
        y += 2.0 * height - 0.03;
        x0 += 0.175;
    }
    Ok(None)
}

/// `mass-ratio`: Solver2D's "high mass ratio 2": a 20 m box resting on two unit boxes 18 m
/// apart, `ratio` (100) times as heavy as each (Solver2D's is 400, dropped from 15 m: here
/// it starts resting on them, 1 cm above, so the scene asks whether the light boxes hold it).
///
/// # Errors
/// As [`World::add_solid`]; `ratio` outside [0.001, 10000].
pub(super) fn mass_ratio(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let ratio = v("ratio");
    if !(1e-3..=1e4).contains(&ratio) {
        return Err(Error::invalid("ratio", crate::error::num(ratio), "from 0.001 to 10000"));
    }
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    big_on_small(w, ratio / 400.0, 1.01)?;
    Ok(None)
}

/// Solver2D's big box on small boxes: two unit boxes on the ground at x = -9 and 9 and a
/// 20 m box of `density` (the small ones' 1) with its bottom `bottom` m up, centred.
pub(super) fn big_on_small(w: &mut World, density: f64, bottom: f64) -> Result<()> {
    for x in [-9.0, 9.0] {
        unit_box(w, &[x, 0.5], 0.5)?;
    }
    let mut big = SolidParams::new(Shape::Box { half: vec![10.0, 10.0] }, &[0.0, bottom + 10.0]);
    big.density = density;
    w.add_solid(big)?;
    Ok(())
}

/// Solver2D's arch: the inner and outer curves of its stones (before its scale of 0.25).
const ARCH_INNER: [[f64; 2]; 9] = [
    [16.0, 0.0],
    [14.93803712795643, 5.133601056842984],
    [13.79871746027416, 10.24928069555078],
    [12.56252963284711, 15.34107019122473],
    [11.20040987372525, 20.39856541571217],
    [9.66521217819836, 25.40369899225096],
    [7.87179930638133, 30.3179337000085],
    [5.635199558196225, 35.03820717801641],
    [2.405937953536585, 39.09554102558315],
];
const ARCH_OUTER: [[f64; 2]; 9] = [
    [24.0, 0.0],
    [22.33619528222415, 6.02299846205841],
    [20.54936888969905, 12.00964361211476],
    [18.60854610798073, 17.9470321677465],
    [16.46769273811807, 23.81367936585418],
    [14.05325025774858, 29.57079353071012],
    [11.23551045834022, 35.13775818285372],
    [7.752568160730571, 40.30450679009583],
    [3.016931552701656, 44.28891593799322],
];

/// `arch`: Solver2D's arch: 17 stones (convex quadrilaterals, each side's 8 and the keystone)
/// between two curves, 4 boxes (4 m x 1 m) stacked on the keystone, all of `friction` (0.6)
/// on a static ground box. It stands by friction alone (at 0 it collapses).
///
/// # Errors
/// As [`World::add_solid`].
pub(super) fn arch(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let mu = v("friction");
    gravity(w, v("g"))?;
    ground(w, mu)?;
    let s = 0.25;
    let (p1, p2) = (ARCH_INNER.map(|p| [s * p[0], s * p[1]]), ARCH_OUTER.map(|p| [s * p[0], s * p[1]]));
    let stone = |w: &mut World, corners: [[f64; 2]; 4]| {
        let mut st = SolidParams::new(Shape::Polygon { points: corners.concat() }, &[0.0, 0.0]);
        st.friction = mu;
        w.add_solid(st)
    };
    let m = |p: [f64; 2]| [-p[0], p[1]];
    for i in 0..8 {
        stone(w, [p1[i], p2[i], p2[i + 1], p1[i + 1]])?;
    }
    for i in 0..8 {
        stone(w, [m(p2[i]), m(p1[i]), m(p1[i + 1]), m(p2[i + 1])])?;
    }
    stone(w, [p1[8], p2[8], m(p2[8]), m(p1[8])])?;
    for i in 0..4 {
        let mut b = SolidParams::new(Shape::Box { half: vec![2.0, 0.5] }, &[0.0, 0.5 + p2[8][1] + i as f64]);
        b.friction = mu;
        w.add_solid(b)?;
    }
    Ok(None)
}

/// `domino`: Solver2D's "double domino": `n` (15) dominos 25 cm x 1 m, 1 m apart, friction
/// 0.6; the first is pushed at its top (Solver2D's impulse of 0.2 N s along x, given as the
/// velocity and spin it makes) and each knocks over the next.
///
/// # Errors
/// As [`World::add_solid`]; `n` above [`MAX_SOLIDS`].
pub(super) fn domino(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    gravity(w, v("g"))?;
    dominos(w, n, false)?;
    Ok(None)
}

/// `n` dominos 1 m apart on a floor, the first pushed at its top toward the others, and the
/// last toward them too when `both`.
pub(super) fn dominos(w: &mut World, n: usize, both: bool) -> Result<()> {
    let reach = 0.5 * n as f64 + 10.0;
    let mut floor = SolidParams::new(Shape::Box { half: vec![reach.max(100.0), 1.0] }, &[0.0, -1.0]);
    floor.kind = Kind::Static;
    floor.friction = 0.6;
    w.add_solid(floor)?;
    let (hx, hy, density) = (0.125, 0.5, 1.0);
    let mass = density * 4.0 * hx * hy;
    let inertia = mass * (4.0 * hx * hx + 4.0 * hy * hy) / 12.0;
    // The impulse J = (0.2, 0) at the top, r = (0, hy) from the centre: dv = J / m,
    // dw = (r x J) / I = -hy J / I.
    let j = 0.2;
    let mut x = -0.5 * n as f64;
    for i in 0..n {
        let mut d = SolidParams::new(Shape::Box { half: vec![hx, hy] }, &[x, hy]);
        d.friction = 0.6;
        d.density = density;
        if i == 0 {
            d.velocity = vec![j / mass, 0.0];
            d.angular_velocity = vec![-hy * j / inertia];
        } else if both && i + 1 == n {
            d.velocity = vec![-j / mass, 0.0];
            d.angular_velocity = vec![hy * j / inertia];
        }
        w.add_solid(d)?;
        x += 1.0;
    }
    Ok(())
}

/// `confined`: Box2D v3's and Solver2D's confined circles: `n` x `n` (25 x 25) circles of
/// radius 0.5 m on a grid 18/n m apart (overlapping: more circles than the box holds) in a
/// closed 20 m box of capsule walls, without gravity. Each contact pushes its pair apart at
/// most at the push speed (a row of overlaps adds them up: the first circles leave at up to
/// 32 m/s); they hit the walls, jam and come to rest.
///
/// # Errors
/// As [`World::add_solid`]; `n` above 30 (the circles' area 1.8 times the box's).
pub(super) fn confined(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    if n > 30 {
        return Err(Error::invalid("n", n, "at most 30 (900 circles of 0.5 m in a 20 m box)"));
    }
    for (a, b) in [
        ([-10.5, 0.0], [10.5, 0.0]),
        ([-10.5, 0.0], [-10.5, 20.5]),
        ([10.5, 0.0], [10.5, 20.5]),
        ([-10.5, 20.5], [10.5, 20.5]),
    ] {
        let mut wall =
            SolidParams::new(Shape::Segment { a: a.to_vec(), b: b.to_vec(), radius: 0.5 }, &[0.0, 0.0]);
        wall.kind = Kind::Static;
        w.add_solid(wall)?;
    }
    let step = 18.0 / n as f64;
    for col in 0..n {
        for row in 0..n {
            let at = [-8.75 + col as f64 * step, 1.5 + row as f64 * step];
            w.add_solid(SolidParams::new(Shape::Circle { radius: 0.5 }, &at))?;
        }
    }
    Ok(None)
}

/// `overlap-recovery`: Solver2D's: a pyramid of `base` (4) rows of unit boxes started
/// overlapping their neighbours by `overlap` (0.25) of a side, on the ground; the contacts
/// push them apart (at most at the push speed, 3 m/s) and they come to rest.
///
/// # Errors
/// As [`World::add_solid`]; `overlap` above 0.5, too many boxes.
pub(super) fn overlap_recovery(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let base = count(v, "base", 1)?;
    if base.saturating_mul(base + 1) / 2 > MAX_SOLIDS {
        return Err(Error::invalid("base", base, format!("at most {MAX_SOLIDS} boxes in all")));
    }
    let overlap = v("overlap");
    if overlap > 0.5 {
        return Err(Error::invalid("overlap", crate::error::num(overlap), "from 0 to 0.5 of a side"));
    }
    gravity(w, v("g"))?;
    ground(w, 0.6)?;
    let (extent, fraction) = (0.5, 1.0 - overlap);
    let mut y = extent;
    for i in 0..base {
        let mut x = fraction * extent * (i as f64 - base as f64);
        for _ in i..base {
            unit_box(w, &[x, y], extent)?;
            x += 2.0 * fraction * extent;
        }
        y += 2.0 * fraction * extent;
    }
    Ok(None)
}

/// The spinning top of `top-on-floor`, in its own frame (y its axis, the middle of its foot
/// at the origin): the convex hull of a square foot of half side `foot` (a point, the tip,
/// at 0), a rim of `TOP_SIDES` points of radius 10 cm 5 cm up and a crown of radius 6 cm
/// 8 cm up.
const TOP_SIDES: usize = 16;

fn top_points(foot: f64) -> Vec<f64> {
    let mut p = if foot > 0.0 {
        vec![-foot, 0.0, -foot, foot, 0.0, -foot, foot, 0.0, foot, -foot, 0.0, foot]
    } else {
        vec![0.0, 0.0, 0.0]
    };
    for (r, y) in [(0.1, 0.05), (0.06, 0.08)] {
        for k in 0..TOP_SIDES {
            let a = std::f64::consts::TAU * k as f64 / TOP_SIDES as f64;
            p.extend([r * a.cos(), y, r * a.sin()]);
        }
    }
    p
}

/// `top-on-floor` (3D): a spinning top (a convex hull: a cone from a square foot of half
/// side `foot` to a 20 cm rim, and a crown) standing on its foot on a plane, tilted by
/// `tilt` and spun at `spin` about its axis, friction 0.3; friction at the foot's corners
/// slows it down until it stops.
///
/// # Errors
/// As [`World::add_solid`]; `foot` above 5 cm, `tilt` above 1.2 rad or `spin` above 1000
/// rad/s either way.
pub(super) fn top_on_floor(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (foot, tilt, spin) = (v("foot"), v("tilt"), v("spin"));
    if foot > 0.05 {
        return Err(Error::invalid("foot", crate::error::num(foot), "from 0 to 0.05 m"));
    }
    if tilt > 1.2 {
        return Err(Error::invalid("tilt", crate::error::num(tilt), "from 0 to 1.2 rad"));
    }
    if spin.abs() > 1000.0 {
        return Err(Error::invalid("spin", crate::error::num(spin), "at most 1000 rad/s either way"));
    }
    gravity(w, v("g"))?;
    ground(w, 0.3)?;
    let q = glam::DQuat::from_rotation_z(tilt);
    let axis = q * glam::DVec3::Y;
    // Tilted about the foot's edge at -x, which stays on the plane.
    let pivot = glam::DVec3::new(-foot, 0.0, 0.0);
    let at = pivot - q * pivot;
    let mut top = SolidParams::new(Shape::Polygon { points: top_points(foot) }, &at.to_array());
    top.orientation = vec![q.w, q.x, q.y, q.z];
    top.angular_velocity = (axis * spin).to_array().to_vec();
    top.friction = 0.3;
    top.density = 1000.0;
    w.add_solid(top)?;
    Ok(None)
}
