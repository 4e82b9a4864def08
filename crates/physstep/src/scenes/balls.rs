//! The `balls` scene: N balls of one radius and mass in a box, placed without overlap by a
//! seeded generator, with random velocities, colliding with each other and the walls.

use super::{Exact, Param, Result, SplitMix};
use crate::error::{num, Error};
use crate::world::World;

/// The parameters of the `balls` scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallsParams {
    /// Number of balls.
    pub n: usize,
    /// Radius of each ball, m.
    pub radius: f64,
    /// Spatial dimensions, 1 to 3.
    pub dim: usize,
    /// Seed of the generator.
    pub seed: u64,
    /// Coefficient of restitution in [0, 1].
    pub restitution: f64,
    /// Fraction of the box's length, area or volume the balls fill.
    pub fraction: f64,
    /// Each velocity component is uniform in [-speed, speed], m/s.
    pub speed: f64,
}

/// The side of the cubic box `[0, L]^dim` and the balls' positions and velocities.
///
/// The box holds `m^dim >= n` lattice cells of side `L / m` (`m = ceil(n^(1/dim))`), the box
/// side such that the balls fill `fraction` of it; ball `b` sits in cell `b` (in row order)
/// at a random offset from the cell's centre that keeps it inside the cell: no two overlap,
/// none sticks out of the box.
///
/// # Errors
/// [`Error::InvalidValue`] naming `fraction` when the balls do not fit their cells.
pub fn layout(p: &BallsParams) -> Result<(f64, Vec<f64>, Vec<f64>)> {
    let (n, d, r) = (p.n, p.dim, p.radius);
    let unit = match d {
        1 => 2.0 * r,
        2 => std::f64::consts::PI * r * r,
        _ => 4.0 / 3.0 * std::f64::consts::PI * r * r * r,
    };
    let side = (n as f64 * unit / p.fraction).powf(1.0 / d as f64);
    let mut m = 1usize;
    while m.pow(d as u32) < n {
        m += 1;
    }
    let cell = side / m as f64;
    let jitter = (0.5 * cell - r) * (1.0 - 1e-9);
    if p.fraction <= 0.0 || jitter.is_nan() || jitter < 0.0 {
        let most = n as f64 * unit / ((2.0 * r * m as f64).powi(d as i32));
        return Err(Error::invalid(
            "fraction",
            num(p.fraction),
            format!("> 0 and at most {} for {n} balls on a lattice in {d}D", num(most)),
        ));
    }
    let mut rng = SplitMix(p.seed);
    let (mut x, mut v) = (Vec::with_capacity(n * d), Vec::with_capacity(n * d));
    for b in 0..n {
        let mut c = b;
        for _ in 0..d {
            let centre = ((c % m) as f64 + 0.5) * cell;
            x.push(centre + jitter * (2.0 * rng.unit() - 1.0));
            c /= m;
        }
        for _ in 0..d {
            v.push(p.speed * (2.0 * rng.unit() - 1.0));
        }
    }
    Ok((side, x, v))
}

/// Builds the scene into `w` (a world of `p.dim` dimensions).
///
/// # Errors
/// As [`layout`] and [`World::add_balls`].
pub fn build(p: &BallsParams, w: &mut World) -> Result<()> {
    let (side, x, v) = layout(p)?;
    let d = p.dim;
    w.set_restitution(p.restitution)?;
    w.add_walls(&vec![0.0; d], &vec![side; d])?;
    w.add_balls(&x, Some(&v), &vec![p.radius; p.n], None)?;
    Ok(())
}

/// The `balls` scene from its parameter values (the world made in its `dim`).
///
/// # Errors
/// As [`build`].
pub(super) fn scene(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let p = BallsParams {
        n: v("n") as usize,
        radius: v("radius"),
        dim: v("dim") as usize,
        seed: v("seed") as u64,
        restitution: v("restitution"),
        fraction: v("fraction"),
        speed: v("speed"),
    };
    build(&p, w)?;
    Ok(None)
}

/// The parameters of the `pile` scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PileParams {
    /// Number of balls.
    pub n: usize,
    /// Coefficient of restitution in [0, 1].
    pub restitution: f64,
    /// Radius of each ball, m.
    pub radius: f64,
    /// Seed of the generator.
    pub seed: u64,
    /// Gravity, m/s^2 (along -y).
    pub g: f64,
}

/// The `pile`'s box `[0, W] x [0, H]` and the balls' positions and velocities: `m =
/// ceil(sqrt(n))` columns of cells of side `3 r` (so `W = 3 r m`), the balls in row order from
/// the bottom, each at a random offset of at most `r / 2` from its cell's centre (no two
/// overlap) and a random velocity of at most `0.5` m/s per component; `H` twice the height
/// of the rows, room to bounce.
#[must_use]
pub fn pile_layout(p: &PileParams) -> ([f64; 2], Vec<f64>, Vec<f64>) {
    let (n, r) = (p.n, p.radius);
    let mut m = 1usize;
    while m * m < n {
        m += 1;
    }
    let rows = n.div_ceil(m);
    let cell = 3.0 * r;
    let jitter = 0.5 * r * (1.0 - 1e-9);
    let mut rng = SplitMix(p.seed);
    let (mut x, mut v) = (Vec::with_capacity(2 * n), Vec::with_capacity(2 * n));
    for b in 0..n {
        for c in [b % m, b / m] {
            x.push((c as f64 + 0.5) * cell + jitter * (2.0 * rng.unit() - 1.0));
        }
        for _ in 0..2 {
            v.push(0.5 * (2.0 * rng.unit() - 1.0));
        }
    }
    ([cell * m as f64, 2.0 * cell * rows as f64], x, v)
}

/// The `pile` scene from its parameter values: `n` balls falling under gravity into a box,
/// where they come to rest (2D).
///
/// # Errors
/// [`Error::InvalidValue`] naming `restitution` outside [0, 1].
pub(super) fn pile(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let p = PileParams {
        n: v("n") as usize,
        restitution: v("restitution"),
        radius: v("radius"),
        seed: v("seed") as u64,
        g: v("g"),
    };
    let (side, x, vel) = pile_layout(&p);
    w.set_restitution(p.restitution)?;
    w.add_walls(&[0.0, 0.0], &side)?;
    w.add_balls(&x, Some(&vel), &vec![p.radius; p.n], None)?;
    w.add_force(crate::forces::Force::Gravity { g: [0.0, -p.g, 0.0] })?;
    Ok(None)
}
