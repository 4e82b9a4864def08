//! The rules of building a world that every face shares: springs and rods between checked
//! ends (a rest length by default the current distance; a rod the length it has), and
//! particles added in batches (amortised O(1) per particle from a spawn loop).

use super::World;
use crate::error::{Error, Result};
use crate::forces::{Endpoint, Force, ForceId};

/// Particles checked and waiting to be added in one go: growing a world's `[x; v]` state one
/// particle at a time moves the velocity half every time, which is quadratic in a spawn
/// loop. Push them here, then [`ParticleBatch::commit`] them (before the world is read or
/// stepped).
#[derive(Debug, Clone, Default)]
pub struct ParticleBatch {
    x: Vec<f64>,
    v: Vec<f64>,
    mass: Vec<f64>,
    fixed: Vec<bool>,
}

impl ParticleBatch {
    /// Particles waiting.
    #[must_use]
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// Whether none waits.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// Checks one particle against `world` as [`World::add_particle`] would and keeps it;
    /// returns the index it will have.
    ///
    /// # Errors
    /// As [`World::add_particle`]; nothing is kept.
    pub fn push(
        &mut self,
        world: &mut World,
        position: &[f64],
        velocity: &[f64],
        mass: f64,
        is_static: bool,
    ) -> Result<usize> {
        if !mass.is_finite() {
            // An infinite mass may clash with n-body gravity, whose error names the index the
            // particle would get: count the waiting ones in first.
            self.commit(world)?;
        }
        world.check_particles(position, Some(velocity), Some(&[mass]))?;
        let i = world.len() + self.len();
        self.x.extend_from_slice(position);
        self.v.extend_from_slice(velocity);
        self.mass.push(mass);
        self.fixed.push(is_static);
        Ok(i)
    }

    /// Adds the waiting particles to `world`, in runs of equal `static` flag.
    ///
    /// # Errors
    /// As [`World::add_particles`] (not expected: each was checked when pushed).
    pub fn commit(&mut self, world: &mut World) -> Result<()> {
        let d = world.dim();
        let mut start = 0;
        while start < self.len() {
            let flag = self.fixed[start];
            let end = (start..self.len()).find(|&i| self.fixed[i] != flag).unwrap_or(self.len());
            let (xs, vs) = (&self.x[start * d..end * d], &self.v[start * d..end * d]);
            world.add_particles(xs, Some(vs), Some(&self.mass[start..end]), flag)?;
            start = end;
        }
        *self = Self::default();
        Ok(())
    }
}

impl World {
    /// The distance from particle `i` to `j` (a particle or an anchor), after checking both:
    /// `i` and a particle `j` in range and distinct, an anchor finite.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `i` or `j_or_anchor`.
    pub fn distance(&self, i: usize, j: Endpoint) -> Result<f64> {
        let (n, d) = (self.len(), self.dim());
        if i >= n {
            return Err(Error::invalid("i", i, format!("a particle index < {n}")));
        }
        let x = self.positions();
        let xj: Vec<f64> = match j {
            Endpoint::Particle(j) if j < n && j != i => x[j * d..(j + 1) * d].to_vec(),
            Endpoint::Particle(j) => {
                return Err(Error::invalid(
                    "j_or_anchor",
                    j,
                    format!("a particle index < {n} other than i = {i}, or an anchor point"),
                ))
            }
            Endpoint::Anchor(p) => {
                crate::error::all_finite("j_or_anchor", &p[..d])?;
                p[..d].to_vec()
            }
        };
        Ok(x[i * d..(i + 1) * d].iter().zip(&xj).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt())
    }

    /// Adds a damped spring from particle `i` to `j` (a particle or an anchor); the rest
    /// length defaults to the current distance. Returns its id ([`World::set_force`] changes
    /// its stiffness, rest length or damping).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `i`, `j_or_anchor`, `stiffness`, `rest_length` or
    /// `damping`; the world is unchanged.
    pub fn add_spring(
        &mut self,
        i: usize,
        j_or_anchor: Endpoint,
        stiffness: f64,
        rest_length: Option<f64>,
        damping: f64,
    ) -> Result<ForceId> {
        let r = self.distance(i, j_or_anchor)?;
        let rest_length = rest_length.unwrap_or(r);
        self.add_force(Force::Spring { i, j: j_or_anchor, stiffness, rest_length, damping })
    }

    /// Adds the notes' force-based rod from particle `i` to `j` (a particle or an anchor). It
    /// holds the length the particles have: `length` defaults to it and, when given, must
    /// equal it (to 1e-9 relative). Returns its id.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `i`, `j_or_anchor` or `length`; the world is unchanged.
    pub fn add_rod(&mut self, i: usize, j_or_anchor: Endpoint, length: Option<f64>) -> Result<ForceId> {
        let length = self.rod_length(i, j_or_anchor, length)?;
        self.add_force(Force::Rod { i, j: j_or_anchor, length })
    }

    /// The length of a rod from `i` to `j_or_anchor`: the distance they have, which
    /// `length`, when given, must equal (to 1e-9 relative).
    pub(super) fn rod_length(&self, i: usize, j_or_anchor: Endpoint, length: Option<f64>) -> Result<f64> {
        let r = self.distance(i, j_or_anchor)?;
        Ok(match length {
            None => r,
            Some(l) if !(l.is_finite() && l > 0.0) => {
                return Err(Error::invalid("length", crate::error::num(l), "a finite number > 0"))
            }
            Some(l) if (r - l).abs() > 1e-9 * l => {
                return Err(Error::invalid(
                    "length",
                    crate::error::num(l),
                    format!("the current distance {r} between the rod's ends (move the particle first)"),
                ))
            }
            Some(l) => l,
        })
    }
}
