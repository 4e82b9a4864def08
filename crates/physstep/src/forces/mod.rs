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
//! 1. forces (springs, drag) accumulated into the scratch `f`;
//! 2. `a = f * inv_mass`;
//! 3. accelerations added directly on dynamic particles (gravity, central gravity, n-body);
//! 4. rod constraints, one at a time in canonical order.

pub use generator::{ForceGenerator, UserForce};

mod central;
mod drag;
mod generator;
mod gravity;
mod nbody;
mod rod;
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
pub fn finite_masses(mass: &[f64], first: usize) -> Result<()> {
    match mass.iter().position(|m| !m.is_finite()) {
        None => Ok(()),
        Some(i) => {
            Err(Error::invalid(format!("mass[{}]", first + i), mass[i], "finite when n-body gravity is on"))
        }
    }
}

/// The forces of a world, kept in canonical order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ForceSet {
    forces: Vec<Force>,
    /// What the list holds, kept on `add` so the hot path does not scan for it.
    kinds: Kinds,
}

/// Which phases of [`ForceSet::accel`] have work, and whether any force reads velocity.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Kinds {
    forces: bool,
    rods: bool,
    velocity: bool,
    nbody: bool,
}

impl Kinds {
    /// These kinds and those of `f`.
    fn with(self, f: &Force) -> Self {
        let mut k = self;
        match *f {
            Force::Spring { damping, .. } => {
                k.forces = true;
                k.velocity |= damping != 0.0;
            }
            Force::Drag { linear, quadratic } => {
                k.forces = true;
                k.velocity |= linear != 0.0 || quadratic != 0.0;
            }
            Force::Rod { .. } => {
                k.rods = true;
                k.velocity = true;
            }
            Force::NBody { .. } => k.nbody = true,
            Force::Gravity { .. } | Force::CentralGravity { .. } => {}
        }
        k
    }
}

impl ForceSet {
    /// An empty set.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Validates `force` for `n` particles in `dim` dimensions (1..=3) and inserts it in
    /// canonical order. Springs and rods between two particles are stored with `i < j`;
    /// vector components (gravity, center, anchor) beyond `dim` are stored as zero.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field: `dim`; `i`, `j` (a particle index `< n`, and
    /// `j != i`); `stiffness`, `rest_length`, `damping`, `linear`, `quadratic`, `softening`
    /// (finite, >= 0); `length` (finite, > 0); `gm`, `g` (finite); `g`, `center`, `anchor`
    /// (every component within `dim` finite).
    pub fn add(&mut self, force: Force, n: usize, dim: usize) -> Result<()> {
        let force = force.normalised(n, dim)?;
        let key = force.key();
        let at = self.forces.partition_point(|f| f.key() <= key);
        self.forces.insert(at, force);
        self.kinds = self.kinds.with(&force);
        Ok(())
    }

    /// Number of forces.
    #[must_use]
    pub fn len(&self) -> usize {
        self.forces.len()
    }

    /// Whether there are no forces.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.forces.is_empty()
    }

    /// The forces in canonical order, as normalised by [`ForceSet::add`].
    pub fn iter(&self) -> impl Iterator<Item = &Force> {
        self.forces.iter()
    }

    /// Checks the masses (kg) for forces that need them finite: with an n-body force, every
    /// particle's mass must be finite (no static particles).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `mass[i]` of the first offending particle.
    pub fn validate_masses(&self, mass: &[f64]) -> Result<()> {
        if self.needs_finite_masses() {
            finite_masses(mass, 0)?;
        }
        Ok(())
    }

    /// Whether every particle's mass must be finite (n-body gravity pulls with each mass).
    #[must_use]
    pub fn needs_finite_masses(&self) -> bool {
        self.kinds.nbody
    }

    /// Fills `a` (length `n * dim`, m/s^2) with the total acceleration at time `t` (s),
    /// positions `x` (m) and velocities `v` (m/s). `mass` (kg) and `inv_mass` (1/kg, 0 for
    /// static particles) have length `n`; `f` is scratch of length `n * dim` (left holding
    /// the accumulated spring and drag forces, N). Allocates nothing.
    #[allow(clippy::too_many_arguments)]
    pub fn accel(
        &self,
        dim: usize,
        _t: f64,
        x: &[f64],
        v: &[f64],
        mass: &[f64],
        inv_mass: &[f64],
        f: &mut [f64],
        a: &mut [f64],
    ) {
        let len = inv_mass.len() * dim;
        debug_assert!(x.len() == len && v.len() == len && f.len() == len && a.len() == len);
        debug_assert_eq!(mass.len(), inv_mass.len());

        if self.kinds.forces {
            f.fill(0.0);
            for force in &self.forces {
                match *force {
                    Force::Spring { i, j, stiffness, rest_length, damping } => {
                        spring::force(dim, x, v, i, j, [stiffness, rest_length, damping], f);
                    }
                    Force::Drag { linear, quadratic } => drag::force(dim, v, linear, quadratic, f),
                    _ => {}
                }
            }
            for ((ap, fp), &im) in a.chunks_exact_mut(dim).zip(f.chunks_exact(dim)).zip(inv_mass) {
                for (ak, fk) in ap.iter_mut().zip(fp) {
                    *ak = fk * im;
                }
            }
        }
        let mut accels = &self.forces[..];
        if !self.kinds.forces {
            // No forces, only accelerations: 0 * inv_mass is 0 for every particle. Gravity
            // sorts first; when present it writes 0 + g in the same pass instead of adding
            // to zeros in a second one.
            match self.forces.split_first() {
                Some((Force::Gravity { g }, rest)) => {
                    gravity::set(dim, *g, inv_mass, a);
                    accels = rest;
                }
                _ => a.fill(0.0),
            }
        }

        for force in accels {
            match *force {
                Force::Gravity { g } => gravity::accel(dim, g, inv_mass, a),
                Force::CentralGravity { center, gm } => central::accel(dim, center, gm, x, inv_mass, a),
                Force::NBody { g, softening } => nbody::accel(dim, g, softening, x, mass, inv_mass, a),
                _ => {}
            }
        }

        if self.kinds.rods {
            for force in &self.forces {
                if let Force::Rod { i, j, .. } = *force {
                    rod::apply(dim, i, j, x, v, inv_mass, a);
                }
            }
        }
    }

    /// Total potential energy, J, at positions `x` (m) with masses `mass` (kg): gravity
    /// `-m g . x` and central gravity `-gm m / r` over particles of finite mass (central: 0 at
    /// `r = 0`); springs `k (|d| - rest)^2 / 2`; n-body
    /// `-sum_{i<j} G m_i m_j / sqrt(r^2 + eps^2)`; drag and rods 0.
    #[must_use]
    pub fn potential(&self, dim: usize, x: &[f64], mass: &[f64]) -> f64 {
        let mut u = 0.0;
        for force in &self.forces {
            u += match *force {
                Force::Gravity { g } => gravity::potential(dim, g, x, mass),
                Force::Spring { i, j, stiffness, rest_length, .. } => {
                    spring::potential(dim, x, i, j, stiffness, rest_length)
                }
                Force::CentralGravity { center, gm } => central::potential(dim, center, gm, x, mass),
                Force::NBody { g, softening } => nbody::potential(dim, g, softening, x, mass),
                Force::Drag { .. } | Force::Rod { .. } => 0.0,
            };
        }
        u
    }

    /// Whether any force depends on velocity (drag, damped spring, rod).
    #[must_use]
    pub fn velocity_dependent(&self) -> bool {
        self.kinds.velocity
    }

    /// Adds the analytic Jacobians `da/dx` (1/s^2) and `da/dv` (1/s), row-major
    /// `(n dim) x (n dim)` and zeroed by the caller, and returns `true`; returns `false`
    /// without touching them when a force has no analytic Jacobian (n-body, rod), so the
    /// caller falls back to finite differences.
    #[allow(clippy::too_many_arguments)]
    pub fn jacobian(
        &self,
        dim: usize,
        _t: f64,
        x: &[f64],
        v: &[f64],
        inv_mass: &[f64],
        dadx: &mut [f64],
        dadv: &mut [f64],
    ) -> bool {
        if self.forces.iter().any(|f| matches!(f, Force::NBody { .. } | Force::Rod { .. })) {
            return false;
        }
        let len = inv_mass.len() * dim;
        debug_assert!(dadx.len() == len * len && dadv.len() == len * len);
        for force in &self.forces {
            match *force {
                Force::Spring { i, j, stiffness, rest_length, damping } => {
                    let jac = spring::Jacobian::new(dim, x, v, i, j, [stiffness, rest_length, damping]);
                    jac.add(dim, i, j, inv_mass, dadx, dadv);
                }
                Force::Drag { linear, quadratic } => {
                    drag::jacobian(dim, v, linear, quadratic, inv_mass, dadv)
                }
                Force::CentralGravity { center, gm } => central::jacobian(dim, center, gm, x, inv_mass, dadx),
                _ => {}
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test world: positions, velocities, masses.
    pub(super) struct W {
        pub dim: usize,
        pub x: Vec<f64>,
        pub v: Vec<f64>,
        pub m: Vec<f64>,
    }

    impl W {
        pub fn inv(&self) -> Vec<f64> {
            self.m.iter().map(|m| 1.0 / m).collect()
        }
        pub fn accel_at(&self, fs: &ForceSet, x: &[f64], v: &[f64]) -> Vec<f64> {
            let mut f = vec![0.0; x.len()];
            let mut a = vec![f64::NAN; x.len()];
            fs.accel(self.dim, 0.0, x, v, &self.m, &self.inv(), &mut f, &mut a);
            a
        }
        pub fn accel(&self, fs: &ForceSet) -> Vec<f64> {
            self.accel_at(fs, &self.x, &self.v)
        }
    }

    fn set(forces: &[Force], n: usize, dim: usize) -> ForceSet {
        let mut fs = ForceSet::new();
        for f in forces {
            fs.add(*f, n, dim).unwrap();
        }
        fs
    }

    fn close(a: f64, b: f64, rel: f64, scale: f64) -> bool {
        (a - b).abs() <= rel * scale.max(a.abs()).max(b.abs())
    }

    /// A pseudo-random world, deterministic.
    pub(super) fn world(n: usize, dim: usize, seed: u64) -> W {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let mut next = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        };
        let x = (0..n * dim).map(|_| 3.0 * next()).collect();
        let v = (0..n * dim).map(|_| next()).collect();
        let m = (0..n).map(|_| 1.5 + next()).collect();
        W { dim, x, v, m }
    }

    fn spring(i: usize, j: Endpoint, k: f64, rest: f64, c: f64) -> Force {
        Force::Spring { i, j, stiffness: k, rest_length: rest, damping: c }
    }

    #[test]
    fn spring_to_anchor_1d() {
        let w = W { dim: 1, x: vec![20.0], v: vec![0.0], m: vec![10.0] };
        let fs = set(&[spring(0, Endpoint::Anchor([0.0; 3]), 5.0, 0.0, 0.0)], 1, 1);
        assert_eq!(w.accel(&fs), vec![-10.0]);

        let w = W { v: vec![3.0], ..w };
        let fs = set(&[spring(0, Endpoint::Anchor([0.0; 3]), 5.0, 0.0, 2.0)], 1, 1);
        let a = w.accel(&fs)[0];
        let want = (-100.0 - 6.0) / 10.0;
        assert!(close(a, want, 1e-15, 0.0), "{a} vs {want}");
        assert!(fs.velocity_dependent());
    }

    #[test]
    fn spring_at_zero_length_is_zero() {
        let w = W { dim: 2, x: vec![1.0, 2.0, 1.0, 2.0], v: vec![1.0, 0.0, -1.0, 0.0], m: vec![1.0, 1.0] };
        let fs = set(&[spring(0, Endpoint::Particle(1), 5.0, 1.0, 2.0)], 2, 2);
        assert_eq!(w.accel(&fs), vec![0.0; 4]);
    }

    #[test]
    fn order_independent_bitwise() {
        let w = world(5, 3, 7);
        let forces = [
            Force::Gravity { g: [0.0, -9.81, 0.0] },
            spring(0, Endpoint::Particle(3), 4.0, 0.5, 0.3),
            spring(2, Endpoint::Particle(1), 7.0, 0.2, 0.1),
            spring(4, Endpoint::Anchor([1.0, 2.0, 3.0]), 2.0, 0.0, 0.7),
            Force::Drag { linear: 0.1, quadratic: 0.05 },
            Force::CentralGravity { center: [0.5, 0.5, 0.5], gm: 3.0 },
            Force::NBody { g: 0.3, softening: 0.1 },
            Force::Rod { i: 3, j: Endpoint::Particle(2), length: 1.0 },
            Force::Gravity { g: [0.1, 0.0, 0.2] },
        ];
        let swapped: Vec<Force> = forces
            .iter()
            .rev()
            .map(|f| match *f {
                Force::Spring { i, j: Endpoint::Particle(j), stiffness, rest_length, damping } => {
                    Force::Spring { i: j, j: Endpoint::Particle(i), stiffness, rest_length, damping }
                }
                Force::Rod { i, j: Endpoint::Particle(j), length } => {
                    Force::Rod { i: j, j: Endpoint::Particle(i), length }
                }
                f => f,
            })
            .collect();
        let a1 = w.accel(&set(&forces, 5, 3));
        let a2 = w.accel(&set(&swapped, 5, 3));
        let b1: Vec<u64> = a1.iter().map(|a| a.to_bits()).collect();
        let b2: Vec<u64> = a2.iter().map(|a| a.to_bits()).collect();
        assert_eq!(b1, b2);
        assert_eq!(set(&forces, 5, 3), set(&swapped, 5, 3));
    }

    /// `-grad U` by central differences against `m a`.
    fn check_potential(w: &W, fs: &ForceSet) {
        let a = w.accel(fs);
        let scale = a.iter().zip(0..).map(|(a, q)| (a * w.m[q / w.dim]).abs()).fold(0.0, f64::max);
        assert!(scale > 0.0);
        for q in 0..w.x.len() {
            let h = 1e-5;
            let mut xp = w.x.clone();
            xp[q] += h;
            let mut xm = w.x.clone();
            xm[q] -= h;
            let grad = (fs.potential(w.dim, &xp, &w.m) - fs.potential(w.dim, &xm, &w.m)) / (2.0 * h);
            let force = w.m[q / w.dim] * a[q];
            assert!(close(-grad, force, 1e-6, scale), "coordinate {q}: {} vs {force}", -grad);
        }
    }

    #[test]
    fn potential_gradient_matches_force() {
        for dim in [2, 3] {
            let w = W { v: vec![0.0; 4 * dim], ..world(4, dim, 11 + dim as u64) };
            let anchor = Endpoint::Anchor([0.3, -0.2, 0.1]);
            let cases = [
                vec![spring(0, Endpoint::Particle(1), 3.0, 0.7, 0.0), spring(2, anchor, 1.5, 0.4, 0.0)],
                vec![Force::CentralGravity { center: [4.0, 0.1, -4.0], gm: 5.0 }],
                vec![Force::NBody { g: 0.7, softening: 0.2 }],
                vec![Force::Gravity { g: [0.3, -9.81, 1.0] }],
            ];
            for forces in &cases {
                check_potential(&w, &set(forces, 4, dim));
            }
            let all: Vec<Force> = cases.concat();
            check_potential(&w, &set(&all, 4, dim));
        }
    }

    #[test]
    fn potential_values() {
        let w = W { dim: 1, x: vec![3.0, 1.0], v: vec![0.0; 2], m: vec![2.0, f64::INFINITY] };
        let fs = set(&[Force::Gravity { g: [-10.0, 0.0, 0.0] }], 2, 1);
        assert_eq!(fs.potential(1, &w.x, &w.m), 60.0);
        assert_eq!(w.accel(&fs), vec![-10.0, 0.0]);
        let fs = set(
            &[spring(0, Endpoint::Particle(1), 4.0, 1.0, 0.0), Force::Drag { linear: 1.0, quadratic: 0.0 }],
            2,
            1,
        );
        assert_eq!(fs.potential(1, &w.x, &w.m), 2.0);
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        for dim in [2, 3] {
            let n = 4;
            let w = world(n, dim, 3 + dim as u64);
            let forces = [
                spring(0, Endpoint::Particle(1), 3.0, 0.7, 0.4),
                spring(3, Endpoint::Particle(1), 2.0, 0.0, 0.9),
                spring(2, Endpoint::Anchor([0.3, -0.2, 0.1]), 1.5, 0.4, 0.6),
                Force::Drag { linear: 0.3, quadratic: 0.2 },
                Force::CentralGravity { center: [4.0, 0.1, -4.0], gm: 5.0 },
                Force::Gravity { g: [0.0, -9.81, 0.0] },
            ];
            let fs = set(&forces, n, dim);
            let len = n * dim;
            let mut dadx = vec![0.0; len * len];
            let mut dadv = vec![0.0; len * len];
            assert!(fs.jacobian(dim, 0.0, &w.x, &w.v, &w.inv(), &mut dadx, &mut dadv));
            for (jac, wrt_x) in [(&dadx, true), (&dadv, false)] {
                let scale = jac.iter().fold(0.0f64, |m, j| m.max(j.abs()));
                for q in 0..len {
                    let h = 1e-6;
                    let (mut xp, mut xm, mut vp, mut vm) =
                        (w.x.clone(), w.x.clone(), w.v.clone(), w.v.clone());
                    if wrt_x {
                        xp[q] += h;
                        xm[q] -= h;
                    } else {
                        vp[q] += h;
                        vm[q] -= h;
                    }
                    let ap = w.accel_at(&fs, &xp, &vp);
                    let am = w.accel_at(&fs, &xm, &vm);
                    for r in 0..len {
                        let fd = (ap[r] - am[r]) / (2.0 * h);
                        let an = jac[r * len + q];
                        assert!(close(fd, an, 1e-6, scale), "dim {dim} x {wrt_x} [{r},{q}]: {fd} vs {an}");
                    }
                }
            }
        }
    }

    #[test]
    fn jacobian_refused_for_nbody_and_rod() {
        let w = world(2, 2, 1);
        let mut dadx = vec![0.0; 16];
        let mut dadv = vec![0.0; 16];
        for f in [
            Force::NBody { g: 1.0, softening: 0.0 },
            Force::Rod { i: 0, j: Endpoint::Particle(1), length: 1.0 },
        ] {
            let fs = set(&[f, Force::Drag { linear: 1.0, quadratic: 0.0 }], 2, 2);
            assert!(!fs.jacobian(2, 0.0, &w.x, &w.v, &w.inv(), &mut dadx, &mut dadv));
            assert!(dadv.iter().all(|&d| d == 0.0));
        }
    }

    #[test]
    fn rod_gives_centripetal_acceleration() {
        let (l, s) = (2.5, 3.7);
        for (dim, theta) in [(2, 0.3), (3, 1.9), (2, -2.2)] {
            let (c, sn) = (f64::cos(theta), f64::sin(theta));
            let anchor = [1.0, -2.0, 0.5];
            let mut x = vec![anchor[0] + l * c, anchor[1] + l * sn];
            let mut v = vec![-s * sn, s * c];
            if dim == 3 {
                x.push(anchor[2]);
                v.push(0.0);
            }
            let w = W { dim, x, v, m: vec![2.0] };
            let fs = set(
                &[
                    Force::Gravity { g: [0.0, -9.81, 0.0] },
                    Force::Rod { i: 0, j: Endpoint::Anchor(anchor), length: l },
                ],
                1,
                dim,
            );
            let a = w.accel(&fs);
            let radial = (a[0] * c + a[1] * sn) / 1.0;
            let want = -s * s / l;
            assert!(close(radial, want, 1e-12, 0.0), "{radial} vs {want}");
        }
    }

    #[test]
    fn rod_between_particles_keeps_length() {
        let w = world(2, 3, 5);
        let fs = set(
            &[
                Force::Gravity { g: [0.0, 0.0, -9.81] },
                Force::Rod { i: 1, j: Endpoint::Particle(0), length: 1.0 },
            ],
            2,
            3,
        );
        let a = w.accel(&fs);
        // d^2 |d|^2 / dt^2 / 2 = w.w + d.a_rel = 0
        let (mut ww, mut da, mut dd) = (0.0, 0.0, 0.0);
        for k in 0..3 {
            let d = w.x[k] - w.x[3 + k];
            ww += (w.v[k] - w.v[3 + k]).powi(2);
            da += d * (a[k] - a[3 + k]);
            dd += d * d;
        }
        assert!(close(ww + da, 0.0, 1e-12, ww + dd));
        // momentum: the rod is internal
        let p: f64 = (0..3).map(|k| w.m[0] * a[k] + w.m[1] * a[3 + k]).sum();
        assert!((p - (w.m[0] + w.m[1]) * -9.81).abs() < 1e-12 * 10.0 * (w.m[0] + w.m[1]));
    }

    #[test]
    fn static_particles_stay_put() {
        let mut w = world(3, 2, 9);
        w.m[1] = f64::INFINITY;
        let fs = set(
            &[
                Force::Gravity { g: [0.0, -9.81, 0.0] },
                spring(0, Endpoint::Particle(1), 3.0, 0.5, 0.5),
                Force::Drag { linear: 0.3, quadratic: 0.2 },
                Force::CentralGravity { center: [0.0; 3], gm: 1.0 },
                Force::Rod { i: 1, j: Endpoint::Particle(2), length: 1.0 },
            ],
            3,
            2,
        );
        let a = w.accel(&fs);
        assert_eq!(&a[2..4], &[0.0, 0.0]);
        assert!(a.iter().all(|a| a.is_finite()));
    }

    #[test]
    fn validation_names_field_and_value() {
        let mut fs = ForceSet::new();
        let msg = |r: Result<()>| r.unwrap_err().to_string();
        let a0 = Endpoint::Anchor([0.0; 3]);
        assert_eq!(
            msg(fs.add(spring(1, Endpoint::Particle(7), 1.0, 0.0, 0.0), 3, 2)),
            "invalid j = 7: must be a particle index < 3 other than i"
        );
        assert_eq!(
            msg(fs.add(spring(1, Endpoint::Particle(1), 1.0, 0.0, 0.0), 3, 2)),
            "invalid j = 1: must be a particle index < 3 other than i"
        );
        assert_eq!(
            msg(fs.add(spring(3, a0, 1.0, 0.0, 0.0), 3, 2)),
            "invalid i = 3: must be a particle index < 3"
        );
        assert_eq!(
            msg(fs.add(spring(0, a0, -1.0, 0.0, 0.0), 3, 2)),
            "invalid stiffness = -1: must be a finite number >= 0"
        );
        assert!(msg(fs.add(spring(0, a0, 1.0, f64::NAN, 0.0), 3, 2)).starts_with("invalid rest_length = NaN"));
        assert!(
            msg(fs.add(spring(0, a0, 1.0, 0.0, f64::INFINITY), 3, 2)).starts_with("invalid damping = inf")
        );
        assert!(msg(fs.add(spring(0, Endpoint::Anchor([0.0, f64::NAN, 0.0]), 1.0, 0.0, 0.0), 3, 2))
            .starts_with("invalid anchor = [0.0, NaN, 0.0]"));
        // beyond dim: ignored
        fs.add(spring(0, Endpoint::Anchor([0.0, f64::NAN, 0.0]), 1.0, 0.0, 0.0), 3, 1).unwrap();
        assert_eq!(fs.iter().next(), Some(&spring(0, a0, 1.0, 0.0, 0.0)));
        assert!(msg(fs.add(Force::Drag { linear: -0.1, quadratic: 0.0 }, 3, 2))
            .starts_with("invalid linear = -0.1"));
        assert!(msg(fs.add(Force::Drag { linear: 0.0, quadratic: -2.0 }, 3, 2))
            .starts_with("invalid quadratic = -2"));
        assert!(msg(fs.add(Force::CentralGravity { center: [0.0; 3], gm: f64::NAN }, 3, 2))
            .starts_with("invalid gm = NaN"));
        assert!(msg(fs.add(Force::CentralGravity { center: [f64::INFINITY, 0.0, 0.0], gm: 1.0 }, 3, 2))
            .starts_with("invalid center = [inf"));
        assert!(msg(fs.add(Force::Gravity { g: [0.0, f64::NAN, 0.0] }, 3, 3))
            .starts_with("invalid g = [0.0, NaN"));
        assert!(
            msg(fs.add(Force::NBody { g: f64::NAN, softening: 0.0 }, 3, 2)).starts_with("invalid g = NaN")
        );
        assert!(
            msg(fs.add(Force::NBody { g: 1.0, softening: -1.0 }, 3, 2)).starts_with("invalid softening = -1")
        );
        assert_eq!(
            msg(fs.add(Force::Rod { i: 0, j: a0, length: 0.0 }, 3, 2)),
            "invalid length = 0: must be a finite number > 0"
        );
        assert!(msg(fs.add(Force::Rod { i: 0, j: Endpoint::Particle(0), length: 1.0 }, 3, 2))
            .starts_with("invalid j = 0"));
        assert!(msg(fs.add(Force::Gravity { g: [0.0; 3] }, 3, 4)).starts_with("invalid dim = 4"));
        assert_eq!(fs.len(), 1);

        fs.add(Force::NBody { g: 1.0, softening: 0.1 }, 3, 2).unwrap();
        assert_eq!(
            msg(fs.validate_masses(&[1.0, 2.0, f64::INFINITY])),
            "invalid mass[2] = inf: must be finite when n-body gravity is on"
        );
        fs.validate_masses(&[1.0, 2.0, 3.0]).unwrap();
        let no_nbody = set(&[Force::Gravity { g: [0.0; 3] }], 3, 2);
        no_nbody.validate_masses(&[1.0, f64::INFINITY, 3.0]).unwrap();
    }

    #[test]
    fn basics() {
        let mut fs = ForceSet::default();
        assert!(fs.is_empty());
        assert!(!fs.velocity_dependent());
        fs.add(Force::Gravity { g: [0.0, -1.0, 0.0] }, 1, 2).unwrap();
        fs.add(spring(0, Endpoint::Anchor([0.0; 3]), 1.0, 0.0, 0.0), 1, 2).unwrap();
        assert!(!fs.velocity_dependent());
        fs.add(Force::Drag { linear: 0.0, quadratic: 1.0 }, 1, 2).unwrap();
        assert!(fs.velocity_dependent());
        assert_eq!(fs.len(), 3);
        assert!(matches!(fs.iter().nth(1), Some(Force::Spring { .. })));
    }
}
