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
