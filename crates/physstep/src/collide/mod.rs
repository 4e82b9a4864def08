//! Balls and walls: particles with a radius that collide with each other and with the walls
//! of an axis-aligned box, by the collision formula along the line of centres with a
//! coefficient of restitution `e` (1: elastic), at their time of impact inside the step.
//!
//! - `grid`: the broad phase, a uniform grid kept as a sorted list (no allocation once
//!   warm, a deterministic order), so the pairs tested grow with N, not N^2;
//! - `events`: the contacts of a step resolved in time order (event-driven within the fixed
//!   step), so kinetic energy is kept to rounding when `e = 1` and balls neither overlap nor
//!   pass through each other.
//!
//! The scan of the grid runs in fixed chunks (on the rayon pool above 16,384 balls) whose
//! events are heaped, and the heap pops them in their total order (time, then slots): the
//! result never depends on the thread count. The rest of the stage is serial. See
//! docs/collisions.md.

mod events;
mod grid;

pub(crate) use events::{Input, Push, Scratch};

use crate::error::{num, Error, Result};

/// An axis-aligned box the balls stay inside: `lo[k] <= x[k] - r` and `x[k] + r <= hi[k]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Walls {
    /// Lower corner, m (entries past the world's dimension are 0).
    pub lo: [f64; 3],
    /// Upper corner, m.
    pub hi: [f64; 3],
}

/// What the contacts came to since the world was built (rolled back with a failed step).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CollisionStats {
    /// Contacts resolved (ball-ball and ball-wall).
    pub count: u64,
    /// The deepest overlap of two balls, or of a ball past a wall, at the end of any step, m.
    pub max_overlap: f64,
    /// Pairs the narrow phase tested (the broad phase's output: grows with N at a fixed
    /// density, not with N^2).
    pub pair_tests: u64,
}

/// The balls of a world: radii, walls, restitution, statistics and the stage's scratch.
#[derive(Debug, Clone)]
pub(crate) struct Balls {
    /// Radius of each particle, m; 0 for a particle that is not a ball (the vector may be
    /// shorter than the particles: the rest are not balls).
    pub radius: Vec<f64>,
    /// The particles that are balls, ascending.
    pub index: Vec<usize>,
    pub walls: Option<Walls>,
    /// Coefficient of restitution in [0, 1].
    pub restitution: f64,
    pub stats: CollisionStats,
    /// Radii and inverse masses by slot, and the end-of-integration state by slot, gathered
    /// only when the balls are not consecutive particles (else read in place); `v1` then
    /// holds the velocities before the stage of the balls that were hit (leapfrog's memory).
    pub slot_radius: Vec<f64>,
    pub slot_inv_mass: Vec<f64>,
    pub x1: Vec<f64>,
    pub v1: Vec<f64>,
    pub scratch: Scratch,
    /// The resting contacts' pushes at the end of the latest step's first position pass,
    /// sorted by slots: where the next step's pass starts (state: in snapshots, the state
    /// hash and rollbacks; forgotten when the balls change).
    pub warm: Vec<Push>,
}

impl Default for Balls {
    fn default() -> Self {
        Self {
            radius: Vec::new(),
            index: Vec::new(),
            walls: None,
            restitution: 1.0,
            stats: CollisionStats::default(),
            slot_radius: Vec::new(),
            slot_inv_mass: Vec::new(),
            x1: Vec::new(),
            v1: Vec::new(),
            scratch: Scratch::default(),
            warm: Vec::new(),
        }
    }
}

impl Balls {
    /// Whether the world has no balls.
    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// The radius of particle `p` (0 when it is not a ball).
    pub fn radius_of(&self, p: usize) -> f64 {
        self.radius.get(p).copied().unwrap_or(0.0)
    }
}

/// Checks a radius: finite and > 0.
///
/// # Errors
/// [`Error::InvalidValue`] naming `field`.
pub(crate) fn check_radius(field: &str, r: f64) -> Result<()> {
    if r.is_finite() && r > 0.0 && r <= crate::limits::RUNAWAY {
        Ok(())
    } else {
        Err(Error::invalid(field, num(r), "a finite number > 0"))
    }
}

/// Checks walls: `dim` finite entries each, `lo[k] < hi[k]`.
///
/// # Errors
/// [`Error::InvalidValue`] naming `lo`, `hi` or the entry.
pub(crate) fn check_walls(lo: &[f64], hi: &[f64], dim: usize) -> Result<Walls> {
    for (name, v) in [("lo", lo), ("hi", hi)] {
        if v.len() != dim {
            return Err(Error::invalid(format!("len({name})"), v.len(), format!("{dim}, the dimension")));
        }
        crate::error::bounded(name, v, crate::limits::RUNAWAY)?;
    }
    let mut w = Walls { lo: [0.0; 3], hi: [0.0; 3] };
    for k in 0..dim {
        if lo[k] >= hi[k] {
            return Err(Error::invalid(
                format!("hi[{k}]"),
                num(hi[k]),
                format!("> lo[{k}] = {}", num(lo[k])),
            ));
        }
        w.lo[k] = lo[k];
        w.hi[k] = hi[k];
    }
    Ok(w)
}

/// Checks that a ball of radius `r` at `x` is inside `walls`.
///
/// # Errors
/// [`Error::InvalidValue`] naming `field` and the coordinate.
pub(crate) fn check_inside(field: &str, x: &[f64], r: f64, walls: &Walls) -> Result<()> {
    check_inside_by(field, x, r, walls, 0.0)
}

/// [`check_inside`], a ball allowed `slack` m past a wall.
pub(crate) fn check_inside_by(field: &str, x: &[f64], r: f64, walls: &Walls, slack: f64) -> Result<()> {
    for (k, &xk) in x.iter().enumerate() {
        if xk - r < walls.lo[k] - slack || xk + r > walls.hi[k] + slack {
            return Err(Error::invalid(
                format!("{field}[{k}]"),
                num(xk),
                format!(
                    "inside the walls: between lo[{k}] + radius = {} and hi[{k}] - radius = {}",
                    num(walls.lo[k] + r),
                    num(walls.hi[k] - r)
                ),
            ));
        }
    }
    Ok(())
}

/// The first pair of balls (slots `i < j`) among `x` (by slot, `d` per ball) that overlap,
/// with their distance; touching (within a relative 1e-9, a rounding) is not overlapping.
pub(crate) fn first_overlap(x: &[f64], d: usize, radius: &[f64]) -> Option<(usize, usize, f64)> {
    overlaps(x, d, radius, 0.0).0
}

/// How deep the balls `x` (by slot, `d` per ball) overlap, m: the deepest pair, or ball past
/// a wall; 0 when nothing overlaps.
pub(crate) fn deepest_overlap(x: &[f64], d: usize, radius: &[f64], walls: Option<&Walls>) -> f64 {
    let mut deepest = overlaps(x, d, radius, 0.0).1;
    if let Some(w) = walls {
        for (b, r) in radius.iter().enumerate() {
            for k in 0..d {
                let xk = x[b * d + k];
                deepest = deepest.max(w.lo[k] - (xk - r)).max(xk + r - w.hi[k]);
            }
        }
    }
    deepest
}

/// The first pair of balls (slots `i < j`) that overlap by more than `slack` m, with their
/// distance, and the deepest overlap of any pair (0 when none overlaps).
pub(crate) fn overlaps(
    x: &[f64],
    d: usize,
    radius: &[f64],
    slack: f64,
) -> (Option<(usize, usize, f64)>, f64) {
    let mut grid = grid::Grid::default();
    let rmax = radius.iter().copied().fold(0.0, f64::max);
    grid.build(x, d, 2.0 * rmax);
    let mut found: Option<(usize, usize, f64)> = None;
    let mut deepest: f64 = 0.0;
    let mut spans = [(0u32, 0u32, 0u64); 14];
    for i in 0..radius.len() {
        let count = grid.partners(i, d, &mut spans);
        for &(a, b, key) in &spans[..count] {
            for t in a as usize..b.max(a) as usize {
                if key != grid::ANY && grid.key_at(t) != key {
                    continue;
                }
                let j = grid.order()[t];
                let (i, j) = (i.min(j as usize), i.max(j as usize));
                let dist = (0..d).map(|k| (x[j * d + k] - x[i * d + k]).powi(2)).sum::<f64>().sqrt();
                let sum = radius[i] + radius[j];
                if dist < sum {
                    deepest = deepest.max(sum - dist);
                }
                // Touching within a relative 1e-9 (a rounding) is not overlapping.
                let limit = (sum - slack).min(sum * (1.0 - 1e-9));
                if dist < limit && found.is_none_or(|f| (j, i) < (f.1, f.0)) {
                    found = Some((i, j, dist));
                }
            }
        }
    }
    (found, deepest)
}
