//! Position constraints on particles, relaxed after the method's step (the Relax stage):
//! distances (rigid, or soft with a compliance, XPBD), pins, distance limits (ropes, joint
//! limits) and planes (half-spaces: a ground, the walls of a box).
//!
//! Two solvers share the constraints (`solve.rs`), chosen by the world's method:
//!
//! - **Projection** (Jakobsen; Muller et al.'s PBD, Macklin et al.'s XPBD for a compliance):
//!   `iterations` Gauss-Seidel sweeps move the positions onto the constraints along their
//!   gradients at the current positions; the velocity gets the position change over `h`
//!   (for Verlet, whose previous position carries the velocity, that memory is resynced).
//!   First order, as the notes' cloth.
//! - **SHAKE/RATTLE** (Ryckaert et al. 1977, Andersen 1983) for velocity Verlet and leapfrog:
//!   rigid distances are met to [`TOLERANCE`] along their gradients at the step's *start*
//!   positions, the half-step velocity gets the correction over `h`, the final half kick is
//!   taken with the forces at the corrected positions, and the velocities are projected onto
//!   the constraints' tangent. That is RATTLE exactly: symplectic, second order, the rod
//!   length kept to the tolerance and the energy error bounded.
//!
//! Constraints carry no state from step to step (XPBD's multipliers start at zero each
//! step), so a world's rollback, checkpoint and snapshot need nothing of them; they are
//! configuration, as forces are.

mod solve;

pub(crate) use solve::{Mode, Solver};

use crate::error::{num, Error, Result};
use crate::forces::Endpoint;

/// Relative tolerance of SHAKE/RATTLE: a rigid distance `L` is met to `|d| - L` within
/// `TOLERANCE * L`, a velocity along it to `TOLERANCE` of the speed scale; the sweeps of
/// either solver also stop early once no constraint is off by more than this.
pub const TOLERANCE: f64 = 1e-13;

/// The default number of relaxation sweeps ([`crate::world::World::constraint_iterations`]).
pub const DEFAULT_ITERATIONS: u32 = 16;

/// The most relaxation sweeps a step may take.
pub const MAX_ITERATIONS: u32 = 1_000_000;

/// One position constraint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Constraint {
    /// `|x_i - x_j| = length` (m). `compliance` (m/N, the inverse of a stiffness) 0 is
    /// rigid; above 0 the constraint is soft, XPBD style (`alpha / h^2` in the update), and
    /// independent of the number of sweeps.
    Distance {
        /// First particle.
        i: usize,
        /// Second particle or a fixed point.
        j: Endpoint,
        /// Rest length, m (> 0).
        length: f64,
        /// Inverse stiffness, m/N (>= 0).
        compliance: f64,
    },
    /// `min <= |x_i - x_j| <= max` (m): a rope (`min = 0`) or a joint limit.
    Limit {
        /// First particle.
        i: usize,
        /// Second particle or a fixed point.
        j: Endpoint,
        /// Shortest distance, m (>= 0).
        min: f64,
        /// Longest distance, m (> 0, >= min).
        max: f64,
    },
    /// `x_i = point` (m): the particle is held there, and other constraints see it as fixed.
    Pin {
        /// The particle.
        i: usize,
        /// Where it is held, m (components beyond `dim` are 0).
        point: [f64; 3],
    },
    /// `normal . x >= offset` for every particle: the half-space on the side the unit
    /// `normal` points to (a ground `y >= 0` is normal `(0, 1)`, offset 0).
    Plane {
        /// Unit normal (normalised when added).
        normal: [f64; 3],
        /// Signed distance of the plane from the origin along the normal, m.
        offset: f64,
    },
}

impl Constraint {
    /// The constraint checked against a world of `n` particles in `dim` dimensions, as it is
    /// stored (a plane's normal made unit, coordinates beyond `dim` zeroed).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field: `i` or `j` not a particle (or `j == i`), a
    /// length, limit or compliance that is negative, zero where it must be > 0, NaN or
    /// infinite, a point or normal that is not finite, a zero normal.
    pub fn checked(self, n: usize, dim: usize) -> Result<Self> {
        let particle = |field: &str, i: usize| -> Result<()> {
            if i < n {
                Ok(())
            } else {
                Err(Error::invalid(field, i, format!("a particle index < {n}")))
            }
        };
        let end = |i: usize, j: Endpoint| -> Result<Endpoint> {
            particle("i", i)?;
            match j {
                Endpoint::Particle(j) if j >= n || j == i => {
                    Err(Error::invalid("j", j, format!("a particle index < {n} other than i = {i}")))
                }
                Endpoint::Particle(_) => Ok(j),
                Endpoint::Anchor(c) => Ok(Endpoint::Anchor(point("anchor", c, dim)?)),
            }
        };
        let positive = |field: &str, v: f64| -> Result<f64> {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(Error::invalid(field, num(v), "a finite number > 0"))
            }
        };
        let nonneg = |field: &str, v: f64| -> Result<f64> {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(Error::invalid(field, num(v), "a finite number >= 0"))
            }
        };
        Ok(match self {
            Self::Distance { i, j, length, compliance } => Self::Distance {
                j: end(i, j)?,
                i,
                length: positive("length", length)?,
                compliance: nonneg("compliance", compliance)?,
            },
            Self::Limit { i, j, min, max } => {
                let j = end(i, j)?;
                let min = nonneg("min_length", min)?;
                let max = positive("max_length", max)?;
                if max < min {
                    return Err(Error::invalid(
                        "max_length",
                        num(max),
                        format!(">= min_length = {}", num(min)),
                    ));
                }
                Self::Limit { i, j, min, max }
            }
            Self::Pin { i, point: p } => {
                particle("i", i)?;
                Self::Pin { i, point: point("point", p, dim)? }
            }
            Self::Plane { normal, offset } => {
                let mut c = point("normal", normal, dim)?;
                let mut len = c.iter().map(|v| v * v).sum::<f64>().sqrt();
                // A normal so short (or long) that its squares leave the range of doubles
                // (`[1e-300, 0]`) is a direction all the same: scaled by its largest entry
                // first. (Lengths in range are normalised as before: the same bits.)
                if !(1e-150..=1e150).contains(&len) {
                    let big = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    if big == 0.0 {
                        let shown = c[..dim].iter().map(|v| num(*v)).collect::<Vec<_>>().join(", ");
                        return Err(Error::invalid("normal", format!("({shown})"), "a nonzero vector"));
                    }
                    c = c.map(|v| v / big);
                    len = c.iter().map(|v| v * v).sum::<f64>().sqrt();
                }
                if !(offset.is_finite() && offset.abs() <= crate::limits::RUNAWAY) {
                    return Err(Error::invalid("offset", num(offset), "finite, at most 1e100 in magnitude"));
                }
                // A normal already unit to rounding is kept as given, so that a constraint
                // read back and added again (a pickle) is bitwise the same.
                let normal = if (len - 1.0).abs() <= 4.0 * f64::EPSILON { c } else { c.map(|v| v / len) };
                Self::Plane { normal, offset }
            }
        })
    }

    /// How far the constraint is from being met at positions `x`, m (0 when it is met); a
    /// plane's is its deepest dynamic particle's. `movable` says whether a particle can move.
    #[must_use]
    pub fn violation(&self, dim: usize, x: &[f64], movable: &dyn Fn(usize) -> bool) -> f64 {
        let moves = |i: usize, j: Endpoint| movable(i) || matches!(j, Endpoint::Particle(j) if movable(j));
        match *self {
            Self::Distance { i, j, length, .. } if moves(i, j) => (distance(dim, x, i, j) - length).abs(),
            Self::Limit { i, j, min, max } if moves(i, j) => {
                let r = distance(dim, x, i, j);
                (r - max).max(min - r).max(0.0)
            }
            Self::Pin { i, point } if movable(i) => {
                (0..dim).map(|k| (x[i * dim + k] - point[k]).powi(2)).sum::<f64>().sqrt()
            }
            Self::Plane { normal, offset } => (0..x.len() / dim)
                .filter(|p| movable(*p))
                .map(|p| offset - (0..dim).map(|k| normal[k] * x[p * dim + k]).sum::<f64>())
                .fold(0.0, f64::max),
            _ => 0.0,
        }
    }

    /// The particles the constraint names (a plane names none: it acts on all).
    #[must_use]
    pub fn particles(&self) -> [Option<usize>; 2] {
        let other = |j: Endpoint| match j {
            Endpoint::Particle(j) => Some(j),
            Endpoint::Anchor(_) => None,
        };
        match *self {
            Self::Distance { i, j, .. } | Self::Limit { i, j, .. } => [Some(i), other(j)],
            Self::Pin { i, .. } => [Some(i), None],
            Self::Plane { .. } => [None, None],
        }
    }

    /// The constraint's numbers, for a fingerprint: a kind tag, then its fields' bits.
    pub(crate) fn words(&self) -> [u64; 7] {
        let end = |j: Endpoint| match j {
            Endpoint::Particle(j) => [0, j as u64, 0, 0],
            Endpoint::Anchor(c) => [1, c[0].to_bits(), c[1].to_bits(), c[2].to_bits()],
        };
        match *self {
            Self::Distance { i, j, length, compliance } => {
                let e = end(j);
                [1, i as u64, e[0], e[1], e[2] ^ e[3].rotate_left(17), length.to_bits(), compliance.to_bits()]
            }
            Self::Limit { i, j, min, max } => {
                let e = end(j);
                [2, i as u64, e[0], e[1], e[2] ^ e[3].rotate_left(17), min.to_bits(), max.to_bits()]
            }
            Self::Pin { i, point } => {
                [3, i as u64, point[0].to_bits(), point[1].to_bits(), point[2].to_bits(), 0, 0]
            }
            Self::Plane { normal, offset } => {
                [4, 0, normal[0].to_bits(), normal[1].to_bits(), normal[2].to_bits(), offset.to_bits(), 0]
            }
        }
    }
}

/// `p`'s first `dim` components checked finite (at most 1e100), the rest zeroed.
fn point(field: &str, p: [f64; 3], dim: usize) -> Result<[f64; 3]> {
    crate::error::bounded(field, &p[..dim], crate::limits::RUNAWAY)?;
    let mut c = p;
    c[dim..].fill(0.0);
    Ok(c)
}

/// `|x_i - x_j|` (or to the anchor).
pub(crate) fn distance(dim: usize, x: &[f64], i: usize, j: Endpoint) -> f64 {
    (0..dim)
        .map(|k| {
            let xj = match j {
                Endpoint::Particle(j) => x[j * dim + k],
                Endpoint::Anchor(c) => c[k],
            };
            (x[i * dim + k] - xj).powi(2)
        })
        .sum::<f64>()
        .sqrt()
}

/// A world's constraints, in the order they were added (the order of the sweeps), with the
/// number of sweeps and the solver's scratch.
#[derive(Debug, Clone)]
pub struct Constraints {
    pub(crate) list: Vec<Constraint>,
    pub(crate) iterations: u32,
    pub(crate) solver: Solver,
    pub(crate) stats: SweepStats,
}

/// What the relaxation sweeps did: a diagnostic of the world's steps (not state: neither
/// hashed, nor saved, nor rolled back).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SweepStats {
    /// Sweeps the last step took (at most the world's `constraint_iterations`).
    pub last_sweeps: u32,
    /// Steps whose sweeps ended at the cap with a constraint still off by more than
    /// [`TOLERANCE`] (relative): SHAKE or the projection stopped short.
    pub capped_steps: u64,
    /// The largest violation (m, as [`crate::world::World::constraint_violation`]) one of
    /// those steps left after its sweeps; 0 when none was capped.
    pub capped_violation: f64,
}

impl Default for Constraints {
    fn default() -> Self {
        Self {
            list: Vec::new(),
            iterations: DEFAULT_ITERATIONS,
            solver: Solver::default(),
            stats: SweepStats::default(),
        }
    }
}

impl Constraints {
    /// The constraints, in the order they were added.
    #[must_use]
    pub fn list(&self) -> &[Constraint] {
        &self.list
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The relaxation sweeps per step.
    #[must_use]
    pub fn iterations(&self) -> u32 {
        self.iterations
    }

    /// A 64-bit fingerprint of the constraints and the sweep count (FNV-1a over their bits).
    #[must_use]
    pub fn fingerprint(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let words = self.list.iter().flat_map(Constraint::words).chain([u64::from(self.iterations)]);
        for w in words {
            for b in w.to_le_bytes() {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        h
    }

    /// The largest violation at positions `x`, m: see [`Constraint::violation`].
    #[must_use]
    pub fn violation(&self, dim: usize, x: &[f64], inv_mass: &[f64]) -> f64 {
        let movable = |p: usize| inv_mass[p] > 0.0;
        self.list.iter().map(|c| c.violation(dim, x, &movable)).fold(0.0, f64::max)
    }
}
