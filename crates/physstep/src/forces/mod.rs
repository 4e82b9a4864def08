//! Forces on the particles of a world: accelerations, potential energy and Jacobians.
//!
//! Particles are stored as flat slices: coordinate `k` of particle `p` is at `p * dim + k`,
//! `dim` in `1..=3`. A static particle has `mass = inf` and `inv_mass = 0`.
//!
//! A [`ForceSet`] keeps its forces sorted by a canonical key (kind, then the normalised
//! indices, then the bits of the parameters), so adding the same forces in any order gives
//! the same list and bitwise the same accelerations. The n-body sum is split over particles
//! with rayon, each particle summing over the others in index order, so its result does not
//! depend on the thread count either.
//!
//! [`ForceSet::accel`] runs in four phases:
//! 1. the per-particle forces (gravity, drag, central gravity, springs to anchors), particle
//!    by particle, by the same function the fused particle kernels run (`local.rs`):
//!    `a = (F_drag + F_springs) / m + g + a_central`;
//! 2. springs between particles accumulated into the scratch `f`, then `a += f / m`;
//! 3. n-body gravity added on dynamic particles;
//! 4. rod constraints, one at a time in canonical order.

pub use generator::{ForceGenerator, UserForce};
pub use set::{ForceId, ForceSet};

mod blocks;
mod central;
mod drag;
mod generator;
mod gravity;
pub(crate) mod local;
mod nbody;
mod rod;
pub(crate) mod set;
mod spring;

use crate::error::{Error, Result};

/// The other end of a spring or rod.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Endpoint {
    /// Another particle, by index.
    Particle(usize),
    /// A fixed point in space, m. Components beyond the world's `dim` are ignored (stored as 0).
    Anchor([f64; 3]),
}

/// One force acting on the particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Force {
    /// Uniform gravitational acceleration `g`, m/s^2, on every dynamic particle. It is an
    /// acceleration: static particles are unaffected and `mass = inf` gives no NaN.
    Gravity {
        /// The acceleration, m/s^2.
        g: [f64; 3],
    },
    /// Damped spring between particle `i` and `j`. With `d = x_i - x_j` (or `x_i - anchor`),
    /// `u = d / |d|` and `w = v_i - v_j` (or `v_i`), the force on `i` is
    /// `-k (|d| - rest) u - c (w . u) u`, and its opposite acts on `j`. At `|d| = 0` the force
    /// is `-k d` (zero) and the damping is zero. A zero rest length is the linear spring
    /// `-k d - c w` (no square root; its damping acts in every direction).
    Spring {
        /// First particle.
        i: usize,
        /// Second particle or an anchor.
        j: Endpoint,
        /// Stiffness `k`, N/m, >= 0.
        stiffness: f64,
        /// Rest length, m, >= 0.
        rest_length: f64,
        /// Damping `c` along the spring, N s/m, >= 0.
        damping: f64,
    },
    /// Drag `F = -c1 v - c2 |v| v` on every dynamic particle.
    Drag {
        /// Linear coefficient `c1`, N s/m, >= 0.
        linear: f64,
        /// Quadratic coefficient `c2`, N s^2/m^2, >= 0.
        quadratic: f64,
    },
    /// Central gravity: acceleration `-gm (x - c) / |x - c|^3` toward `center`, independent of
    /// the particle's mass; zero at `x = c`.
    CentralGravity {
        /// The attracting point `c`, m. Components beyond `dim` are ignored (stored as 0).
        center: [f64; 3],
        /// Gravitational parameter `G M`, m^3/s^2 (negative repels).
        gm: f64,
    },
    /// Softened n-body gravity between all particles:
    /// `a_i = sum_{j != i} G m_j (x_j - x_i) / (|x_j - x_i|^2 + eps^2)^(3/2)`.
    ///
    /// Needs every mass finite: call [`ForceSet::validate_masses`] whenever masses change (a
    /// static particle would give infinite accelerations). Coincident particles with `eps = 0`
    /// do not attract each other (the pair term is taken as zero).
    NBody {
        /// Gravitational constant `G`, m^3/(kg s^2).
        g: f64,
        /// Softening length `eps`, m, >= 0.
        softening: f64,
    },
    /// Rigid rod of fixed length between particle `i` and `j` or an anchor (the notes' dog tied
    /// to a tree), applied after all other forces as the radial constraint acceleration that
    /// keeps the length constant to first order: with `d = x_i - x_j`, `r = |d|`, `u = d / r`,
    /// relative velocity `w` and relative acceleration `a_rel` from everything before,
    /// `lambda = (-(w . w) / r - u . a_rel) / (1/m_i + 1/m_j)` and `a_i += lambda u / m_i`,
    /// `a_j -= lambda u / m_j` (an anchor has `1/m_j = 0`, `a_j = v_j = 0`). Skipped when both
    /// ends are static or `r = 0`.
    ///
    /// There is no position correction: length drift is the integrator's error. Rods are
    /// applied one at a time in canonical order, which is exact for at most one rod per
    /// particle; chains of rods sharing particles are only approximately satisfied.
    Rod {
        /// First particle.
        i: usize,
        /// Second particle or an anchor.
        j: Endpoint,
        /// Nominal length, m, > 0 (checked at `add`; the constraint holds the current length).
        length: f64,
    },
}

impl Force {
    /// The kind's name, as scene files and the Python handles spell it: `gravity`, `spring`,
    /// `drag`, `central-gravity`, `nbody`, `rod`.
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Gravity { .. } => "gravity",
            Self::Spring { .. } => "spring",
            Self::Drag { .. } => "drag",
            Self::CentralGravity { .. } => "central-gravity",
            Self::NBody { .. } => "nbody",
            Self::Rod { .. } => "rod",
        }
    }
}

/// Canonical sort key: kind rank, normalised indices, parameter bits.
type Key = [u64; 9];

impl Force {
    fn rank(&self) -> u64 {
        match self {
            Self::Gravity { .. } => 0,
            Self::Spring { .. } => 1,
            Self::Drag { .. } => 2,
            Self::CentralGravity { .. } => 3,
            Self::NBody { .. } => 4,
            Self::Rod { .. } => 5,
        }
    }

    fn key(&self) -> Key {
        fn end(j: &Endpoint) -> [u64; 4] {
            match j {
                Endpoint::Particle(j) => [0, *j as u64, 0, 0],
                Endpoint::Anchor(c) => [1, c[0].to_bits(), c[1].to_bits(), c[2].to_bits()],
            }
        }
        let r = self.rank();
        match self {
            Self::Gravity { g } => [r, g[0].to_bits(), g[1].to_bits(), g[2].to_bits(), 0, 0, 0, 0, 0],
            Self::Spring { i, j, stiffness, rest_length, damping } => {
                let e = end(j);
                let (k, l, c) = (stiffness.to_bits(), rest_length.to_bits(), damping.to_bits());
                [r, *i as u64, e[0], e[1], e[2], e[3], k, l, c]
            }
            Self::Drag { linear, quadratic } => [r, linear.to_bits(), quadratic.to_bits(), 0, 0, 0, 0, 0, 0],
            Self::CentralGravity { center: c, gm } => {
                [r, c[0].to_bits(), c[1].to_bits(), c[2].to_bits(), gm.to_bits(), 0, 0, 0, 0]
            }
            Self::NBody { g, softening } => [r, g.to_bits(), softening.to_bits(), 0, 0, 0, 0, 0, 0],
            Self::Rod { i, j, length } => {
                let e = end(j);
                [r, *i as u64, e[0], e[1], e[2], e[3], length.to_bits(), 0, 0]
            }
        }
    }

    /// Validates against `n` particles in `dim` dimensions and returns the normalised force
    /// (pairs stored with `i < j`, vector components beyond `dim` zeroed).
    fn normalised(self, n: usize, dim: usize) -> Result<Self> {
        if !(1..=3).contains(&dim) {
            return Err(Error::invalid("dim", dim, "1, 2 or 3"));
        }
        Ok(match self {
            Self::Gravity { g } => Self::Gravity { g: vector("g", g, dim)? },
            Self::Spring { i, j, stiffness, rest_length, damping } => {
                non_negative("stiffness", stiffness)?;
                non_negative("rest_length", rest_length)?;
                non_negative("damping", damping)?;
                let (i, j) = pair(i, j, n, dim)?;
                Self::Spring { i, j, stiffness, rest_length, damping }
            }
            Self::Drag { linear, quadratic } => {
                non_negative("linear", linear)?;
                non_negative("quadratic", quadratic)?;
                self
            }
            Self::CentralGravity { center, gm } => {
                crate::error::finite("gm", gm)?;
                Self::CentralGravity { center: vector("center", center, dim)?, gm }
            }
            Self::NBody { g, softening } => {
                crate::error::finite("g", g)?;
                non_negative("softening", softening)?;
                self
            }
            Self::Rod { i, j, length } => {
                crate::error::positive("length", length)?;
                let (i, j) = pair(i, j, n, dim)?;
                Self::Rod { i, j, length }
            }
        })
    }
}

fn non_negative(field: &str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, value, "a finite number >= 0"))
    }
}

/// The first `dim` components checked finite, the rest zeroed.
fn vector(field: &str, mut c: [f64; 3], dim: usize) -> Result<[f64; 3]> {
    if c[..dim].iter().any(|x| !x.is_finite()) {
        return Err(Error::invalid(field, format!("{c:?}"), "finite"));
    }
    c[dim..].fill(0.0);
    Ok(c)
}

/// Checks the indices of a spring or rod and orders a particle pair as `i < j`.
fn pair(i: usize, j: Endpoint, n: usize, dim: usize) -> Result<(usize, Endpoint)> {
    if i >= n {
        return Err(Error::invalid("i", i, format!("a particle index < {n}")));
    }
    match j {
        Endpoint::Particle(j) if j >= n || j == i => {
            Err(Error::invalid("j", j, format!("a particle index < {n} other than i")))
        }
        Endpoint::Particle(j) if j < i => Ok((j, Endpoint::Particle(i))),
        Endpoint::Particle(_) => Ok((i, j)),
        Endpoint::Anchor(c) => Ok((i, Endpoint::Anchor(vector("anchor", c, dim)?))),
    }
}

/// `x_i - x_j` (anchor: `x_i - anchor`), zero beyond `dim`.
#[inline]
fn separation(dim: usize, x: &[f64], i: usize, j: Endpoint) -> [f64; 3] {
    let mut d = [0.0; 3];
    for k in 0..dim {
        let xj = match j {
            Endpoint::Particle(j) => x[j * dim + k],
            Endpoint::Anchor(c) => c[k],
        };
        d[k] = x[i * dim + k] - xj;
    }
    d
}

/// `v_i - v_j` (anchor: `v_i`), zero beyond `dim`.
#[inline]
fn relative(dim: usize, v: &[f64], i: usize, j: Endpoint) -> [f64; 3] {
    let mut w = [0.0; 3];
    for k in 0..dim {
        w[k] = match j {
            Endpoint::Particle(j) => v[i * dim + k] - v[j * dim + k],
            Endpoint::Anchor(_) => v[i * dim + k],
        };
    }
    w
}

#[inline]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Checks that every mass (kg) is finite, as n-body gravity needs; `first` is the world index
/// of `mass[0]`, so the error names the particle as the world knows it.
///
/// # Errors
/// [`Error::InvalidValue`] naming `mass[i]` of the first infinite (or NaN) mass.
pub(crate) fn finite_masses(mass: &[f64], first: usize) -> Result<()> {
    match mass.iter().position(|m| !m.is_finite()) {
        None => Ok(()),
        Some(i) => {
            Err(Error::invalid(format!("mass[{}]", first + i), mass[i], "finite when n-body gravity is on"))
        }
    }
}

#[cfg(test)]
mod tests;
