//! The scenes that break contact and joint solvers, from Catto's Solver2D (2024): the same
//! scene far from the origin, high mass ratios, friction on a ramp, warm starting under a
//! heavy load, a rush to a point, dominos falling both ways, a grid and chains of joints
//! pulled apart, and a crowd of ragdolls. Their facts (sizes, masses, counts) are
//! Solver2D's unless a builder's doc says otherwise; counts are scaled so that 10 s at 60 Hz
//! takes a few seconds in a release build.
//!
//! They reuse the builders of the other contact scenes (the pyramid, the dominos, the
//! chain, the ragdoll) with an origin where a scene is moved.

use super::jointed::{hinged_chain, ragdoll};
use super::solids::{big_on_small, count, dominos, gravity, pyramid_at};
use super::{Exact, Param, Result};
use crate::contact::{JointKind, JointParams, Kind, Shape, SolidParams, SolidSpring};
use crate::error::{num, Error};
use crate::world::World;

/// The farthest a scene may be moved from the origin, m (the spacing of f64 there, 1.2e-7 m,
/// is still far below the contacts' 5 mm slop).
const MAX_OFFSET: f64 = 1e9;

/// The origin `offset` m out along x and down along y (Solver2D's far scenes are out along
/// both, tens of km), or the error naming `offset`.
fn far(v: &Param<'_>) -> Result<[f64; 2]> {
    let d = v("offset");
    if d.abs() > MAX_OFFSET {
        return Err(Error::invalid("offset", num(d), "at most 1e9 m either way"));
    }
    Ok([d, -d])
}

fn solid(shape: Shape, at: [f64; 2]) -> SolidParams {
    SolidParams::new(shape, &at)
}

fn fixed(shape: Shape, at: [f64; 2], angle: f64, friction: f64) -> SolidParams {
    let mut p = solid(shape, at);
    p.kind = Kind::Static;
    p.orientation = vec![angle];
    p.friction = friction;
    p
}

fn bx(hx: f64, hy: f64) -> Shape {
    Shape::Box { half: vec![hx, hy] }
}

fn revolute(w: &mut World, a: usize, b: Option<usize>, at: [f64; 2]) -> Result<usize> {
    w.add_joint(JointParams::new(JointKind::Revolute, a, b, &at))
}

/// `far-pyramid`: the `pyramid` scene's ground and `rows` (10, Solver2D's far pyramid's
/// base) rows of unit boxes, moved `offset` (30 km) out along x and down along y. Solver2D
/// starts its boxes 25 cm apart and lets them fall; here they rest 1 cm apart as in
/// `pyramid`, so that the far scene and the near one can be compared box for box.
///
/// # Errors
/// As [`World::add_solid`]; `offset` beyond 1e9 m, too many boxes.
pub(super) fn far_pyramid(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let rows = count(v, "rows", 1)?;
    if rows.saturating_mul(rows + 1) / 2 > super::solids::MAX_SOLIDS {
        return Err(Error::invalid("rows", rows, "at most 100000 boxes in all"));
    }
    let origin = far(v)?;
    gravity(w, v("g"))?;
    pyramid_at(w, rows, origin)?;
    Ok(None)
}

/// `far-ragdoll-pile`: Solver2D's ragdoll pile moved `offset` (30 km): a V of two static
/// boards (20 m x 1 m, tilted 0.15 pi either way, their middles 5 m either side and 2 m up
/// from the origin) and six `ragdoll-bodies` ragdolls above its bottom in Solver2D's
/// arrangement (one, two, two, one), spread to this ragdoll's size (1 m apart across, 2 m a
/// level; Solver2D's overlap at the start), falling into the V and piling up.
///
/// # Errors
/// As [`World::add_solid`]; `offset` beyond 1e9 m.
pub(super) fn far_ragdoll_pile(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let o = far(v)?;
    gravity(w, v("g"))?;
    let tilt = 0.15 * std::f64::consts::PI;
    for side in [-1.0, 1.0] {
        w.add_solid(fixed(bx(10.0, 0.5), [o[0] + 5.0 * side, o[1] + 1.0], side * tilt, 0.6))?;
    }
    for (x, level) in [(0.0, 0.0), (-0.5, 1.0), (0.5, 1.0), (-1.0, 2.0), (1.0, 2.0), (0.0, 3.0)] {
        ragdoll(w, [o[0] + x, o[1] + 0.5 + 2.0 * level], 0.0, 0.0)?;
    }
    Ok(None)
}

/// `high-mass-ratio`: Solver2D's three high mass ratio samples by `variant`:
///
/// 1. three pyramids of 2 m boxes (bases of 10, 55 boxes each, touching), each top box 100,
///    200 and 300 times as dense as the rest and dropped from 2 m above its place, on a
///    ground of friction 0.5;
/// 2. a 20 m box dropped from 15 m onto two unit boxes 18 m apart, all of density 1 (the
///    big box 400 times as heavy as each small one), on a thin ground (a segment);
/// 3. the same on a thick ground (a box 80 m x 4 m).
///
/// # Errors
/// As [`World::add_solid`]; `variant` other than 1, 2 or 3.
pub(super) fn high_mass_ratio(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let variant = v("variant");
    if !(1.0..=3.0).contains(&variant) {
        return Err(Error::invalid("variant", num(variant), "1, 2 or 3 (Solver2D's three samples)"));
    }
    gravity(w, v("g"))?;
    if variant == 3.0 {
        w.add_solid(fixed(bx(40.0, 2.0), [0.0, -2.0], 0.0, 0.6))?;
    } else {
        let friction = if variant == 1.0 { 0.5 } else { 0.6 };
        let half = if variant == 1.0 { 66.0 } else { 20.0 };
        let ground = Shape::Segment { a: vec![-half, 0.0], b: vec![half, 0.0], radius: 0.0 };
        w.add_solid(fixed(ground, [0.0, 0.0], 0.0, friction))?;
    }
    if variant != 1.0 {
        big_on_small(w, 1.0, 16.0)?;
        return Ok(None);
    }
    for j in 0..3 {
        let offset = -20.0 + 22.0 * j as f64;
        let mut y = 1.0;
        for n in (1..=10).rev() {
            for i in 0..n {
                let x = 2.0 * (i as f64 - 0.5 * n as f64) + offset;
                let mut b = solid(bx(1.0, 1.0), [x, if n == 1 { y + 2.0 } else { y }]);
                if n == 1 {
                    b.density = 100.0 * (j + 1) as f64;
                }
                w.add_solid(b)?;
            }
            y += 2.0;
        }
    }
    Ok(None)
}

/// The friction coefficients of `friction-ramp`'s five boxes, Solver2D's.
const RAMP_FRICTIONS: [f64; 5] = [0.75, 0.5, 0.35, 0.1, 0.0];

/// `friction-ramp`: Solver2D's: three static boards 26 m long tilted 0.25 rad, zigzagging
/// down with a stop at the low end of the upper two, over a ground; five unit boxes of
/// density 25 and the frictions [`RAMP_FRICTIONS`] dropped onto the top board from 28 m.
/// A pair's friction is the geometric mean of its two: against the boards' `ramp_friction`
/// (0.2) the first three (0.39, 0.32, 0.26) are above tan 0.25 = 0.255 and slow down once
/// landed (the first two stop on the top board; the third, barely above, slides off it
/// first), the last two (0.14, 0) speed up and slide down.
///
/// # Errors
/// As [`World::add_solid`].
pub(super) fn friction_ramp(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let mu = v("ramp_friction");
    gravity(w, v("g"))?;
    let ground = Shape::Segment { a: vec![-40.0, 0.0], b: vec![40.0, 0.0], radius: 0.0 };
    w.add_solid(fixed(ground, [0.0, 0.0], 0.0, mu))?;
    for (at, angle) in [([-4.0, 22.0], -0.25), ([4.0, 14.0], 0.25), ([-4.0, 6.0], -0.25)] {
        w.add_solid(fixed(bx(13.0, 0.25), at, angle, mu))?;
    }
    for at in [[10.5, 19.0], [-10.5, 11.0]] {
        w.add_solid(fixed(bx(0.25, 1.0), at, 0.0, mu))?;
    }
    for (i, f) in RAMP_FRICTIONS.iter().enumerate() {
        let mut b = solid(bx(0.5, 0.5), [-15.0 + 4.0 * i as f64, 28.0]);
        b.density = 25.0;
        b.friction = *f;
        w.add_solid(b)?;
    }
    Ok(None)
}

/// `warm-start-energy`: Solver2D's: three balls of radius 0.5 m stacked on a ground, the
/// top one `ratio` (100) times as dense as the two below. Solver2D removes the heavy ball
/// at 2 s: the light ones, pressed by it, must not jump when it goes (a solver that warm
/// starts them with its impulses throws them up). A scene cannot remove a solid as it
/// runs: remove solid 3 by hand (`World::remove_solid`) to see it.
///
/// # Errors
/// As [`World::add_solid`]; `ratio` outside [0.001, 10000].
pub(super) fn warm_start_energy(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let ratio = v("ratio");
    if !(1e-3..=1e4).contains(&ratio) {
        return Err(Error::invalid("ratio", num(ratio), "from 0.001 to 10000"));
    }
    gravity(w, v("g"))?;
    let ground = Shape::Segment { a: vec![-10.0, 0.0], b: vec![10.0, 0.0], radius: 0.0 };
    w.add_solid(fixed(ground, [0.0, 0.0], 0.0, 0.6))?;
    for (y, density) in [(0.5, 1.0), (1.5, 1.0), (2.5, ratio)] {
        let mut b = solid(Shape::Circle { radius: 0.5 }, [0.0, y]);
        b.density = density;
        w.add_solid(b)?;
    }
    Ok(None)
}

/// `rush`: Solver2D's: `n` (400) circles of radius 0.5 m (density 100, friction 0.2) on a
/// spiral from 5 m out (0.2 rad and 5 cm farther each), without gravity, pulled toward a
/// static circle at the origin. Solver2D pulls each with a constant 1000 N; here a spring
/// of stiffness `k` (100 N/m, 1000 N at 10 m) from each centre to the origin pulls them (a
/// spring is what a scene file keeps).
///
/// # Errors
/// As [`World::add_solid`]; `n` above 10000.
pub(super) fn rush(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    if n > 10_000 {
        return Err(Error::invalid("n", n, "at most 10000"));
    }
    let k = v("k");
    let circle = || Shape::Circle { radius: 0.5 };
    w.add_solid(fixed(circle(), [0.0, 0.0], 0.0, 0.2))?;
    let (mut r, mut angle) = (5.0_f64, 0.0_f64);
    for _ in 0..n {
        let mut b = solid(circle(), [r * angle.cos(), r * angle.sin()]);
        b.density = 100.0;
        b.friction = 0.2;
        let i = w.add_solid(b)?;
        w.add_solid_spring(SolidSpring {
            rest_length: Some(0.0),
            ..SolidSpring::to_world(i, &[0.0, 0.0], &[0.0, 0.0], k)
        })?;
        angle += 0.2;
        r += 0.05;
    }
    Ok(None)
}

/// `double-domino`: the `domino` row (Solver2D's "double domino": `n` (15) dominos 25 cm x
/// 1 m, 1 m apart), pushed at both ends: two waves meet in the middle, where the dominos
/// are pressed from both sides.
///
/// # Errors
/// As [`World::add_solid`]; `n` above the solids' bound.
pub(super) fn double_domino(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    gravity(w, v("g"))?;
    dominos(w, n, true)?;
    Ok(None)
}

/// `joint-grid`: Solver2D's: an `n` x `n` (30 x 30; Solver2D's is 100 x 100) grid of
/// circles of radius 0.4 m, 1 m apart, each hinged to its right and lower neighbours at the
/// midpoint between them; the 7 circles in the middle of the top row are static (pins). It
/// falls under `g` (2 x 9.81, Solver2D's gravity scale 2) and hangs. Solver2D's circles do
/// not collide; here they do, but for hinged neighbours (none touch at the start).
///
/// # Errors
/// As [`World::add_solid`]; `n` above 300.
pub(super) fn joint_grid(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    if n > 300 {
        return Err(Error::invalid("n", n, "at most 300 (90000 circles)"));
    }
    gravity(w, v("g"))?;
    let mut ids = vec![0; n * n];
    let pinned = |k: usize| k + 3 >= n / 2 && k <= n / 2 + 3;
    for k in 0..n {
        for i in 0..n {
            let at = [k as f64, -(i as f64)];
            let mut c = solid(Shape::Circle { radius: 0.4 }, at);
            if i == 0 && pinned(k) {
                c.kind = Kind::Static;
            }
            let b = w.add_solid(c)?;
            ids[k * n + i] = b;
            if i > 0 {
                revolute(w, ids[k * n + i - 1], Some(b), [at[0], at[1] + 0.5])?;
            }
            // Two pins need no joint (neither could move).
            if k > 0 && !(i == 0 && pinned(k) && pinned(k - 1)) {
                revolute(w, ids[(k - 1) * n + i], Some(b), [at[0] - 0.5, at[1]])?;
            }
        }
    }
    Ok(None)
}

/// `stretched-chain`: Solver2D's: `n` (40) circles of radius 0.2 m hanging from a fixed
/// point, hinged 1 m apart (0.5 m above and below each centre), but started 2 m apart: every
/// joint 1 m open, the chain twice its length. The last circle is `ratio` (1, Solver2D's)
/// times as dense as the others: a heavy end pulls the chain long. The circles touch
/// nothing (Solver2D's do not collide; these are too far apart to).
///
/// # Errors
/// As [`World::add_solid`]; `n` above 10000, `ratio` outside [0.001, 10000].
pub(super) fn stretched_chain(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    if n > 10_000 {
        return Err(Error::invalid("n", n, "at most 10000"));
    }
    let ratio = v("ratio");
    if !(1e-3..=1e4).contains(&ratio) {
        return Err(Error::invalid("ratio", num(ratio), "from 0.001 to 10000"));
    }
    gravity(w, v("g"))?;
    let top = n as f64;
    let mut prev: Option<usize> = None;
    for i in 0..n {
        let y = top - 2.0 - 2.0 * i as f64;
        let mut c = solid(Shape::Circle { radius: 0.2 }, [0.0, y]);
        if i + 1 == n {
            c.density = ratio;
        }
        let b = w.add_solid(c)?;
        let mut j = JointParams::new(JointKind::Revolute, b, prev, &[0.0, y + 0.5]);
        // Each end where it is on its own solid: the joint starts open.
        j.anchor_b = Some(vec![0.0, if i == 0 { top - 0.5 } else { y + 1.5 }]);
        w.add_joint(j)?;
        prev = Some(b);
    }
    Ok(None)
}

/// `far-chain`: Solver2D's: `n` (40) capsule links 20 cm long and 5 cm thick (density 20)
/// hinged end to end from a fixed point, laid level, falling and swinging, moved `offset`
/// (30 km) out along x and down along y (the `ball-chain` chain, smaller and without its
/// ball).
///
/// # Errors
/// As [`World::add_solid`]; `offset` beyond 1e9 m, `n` above the solids' bound.
pub(super) fn far_chain(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    let o = far(v)?;
    gravity(w, v("g"))?;
    hinged_chain(w, [o[0], o[1] + 0.1 * n as f64], n, 0.2, 0.025)?;
    Ok(None)
}

/// Solver2D's ragdoll-stress container, m: a closed outline (a funnel at the bottom) of
/// capsule walls of radius 0.5 m.
const CONTAINER: [[f64; 2]; 20] = [
    [-16.8672504, 31.088623],
    [16.8672485, 31.088623],
    [16.8672485, 17.1978741],
    [8.26824951, 11.906374],
    [16.8672485, 11.906374],
    [16.8672485, -0.661376953],
    [8.26824951, -5.953125],
    [16.8672485, -5.953125],
    [16.8672485, -13.229126],
    [3.63799858, -23.151123],
    [3.63799858, -31.088623],
    [-3.63800049, -31.088623],
    [-3.63800049, -23.151123],
    [-16.8672504, -13.229126],
    [-16.8672504, -5.953125],
    [-8.26825142, -5.953125],
    [-16.8672504, -0.661376953],
    [-16.8672504, 11.906374],
    [-8.26825142, 11.906374],
    [-16.8672504, 17.1978741],
];

/// `ragdoll-stress`: Solver2D's container (a closed outline of capsule walls, friction 0.2,
/// with shelves and a funnel) and three paddles 12 m x 1 m (friction 0.1, restitution 1)
/// hinged at their middles at heights 14, 0 and -14 m to motors turning them at 5 rad/s,
/// alternately either way; `n` (32) `ragdoll-bodies` ragdolls in rows of eight across the
/// top, falling through. Solver2D drops a ragdoll every 0.5 s, up to 32 at once, and
/// removes those that reach the funnel; here all 32 start at once and stay. Solver2D's paddles weigh
/// about 20 of its ragdolls: these weigh 20 of these 70 kg ragdolls (density 117), their
/// motors' 200 N m scaled with the density.
///
/// # Errors
/// As [`World::add_solid`]; `n` above 32.
pub(super) fn ragdoll_stress(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = count(v, "n", 1)?;
    if n > 32 {
        return Err(Error::invalid("n", n, "at most 32 (four rows of eight above the top paddle)"));
    }
    gravity(w, v("g"))?;
    for (i, a) in CONTAINER.iter().enumerate() {
        let b = CONTAINER[(i + 1) % CONTAINER.len()];
        let wall = Shape::Segment { a: a.to_vec(), b: b.to_vec(), radius: 0.5 };
        w.add_solid(fixed(wall, [0.0, 0.0], 0.0, 0.2))?;
    }
    let density = 20.0 * 70.0 / 12.0;
    for (y, sign) in [(14.0, 1.0), (0.0, -1.0), (-14.0, 1.0)] {
        let mut p = solid(bx(6.0, 0.5), [0.0, y]);
        p.density = density;
        p.friction = 0.1;
        p.restitution = 1.0;
        let b = w.add_solid(p)?;
        let mut j = JointParams::new(JointKind::Revolute, b, None, &[0.0, y]);
        j.motor_speed = 5.0 * sign;
        j.max_motor = 200.0 * density;
        w.add_joint(j)?;
    }
    for k in 0..n {
        let (row, col) = (k / 8, k % 8);
        let x = -14.0 + 4.0 * col as f64;
        ragdoll(w, [x, 26.0 - 2.5 * row as f64], 0.0, 0.0)?;
    }
    Ok(None)
}
