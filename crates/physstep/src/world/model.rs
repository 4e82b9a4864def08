//! The force model: masses and forces, what the integrators see as a second-order system.

use crate::dynamics::SecondOrder;
use crate::forces::ForceSet;

/// The force model: what the integrators see as a [`SecondOrder`] system.
#[derive(Debug, Clone, Default)]
pub struct Model {
    pub(super) dim: usize,
    pub(super) mass: Vec<f64>,
    pub(super) inv_mass: Vec<f64>,
    pub(super) forces: ForceSet,
    pub(super) scratch: Vec<f64>,
}

impl SecondOrder for Model {
    #[inline]
    fn len(&self) -> usize {
        self.mass.len() * self.dim
    }

    #[inline]
    fn accel(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        let n = x.len();
        if self.scratch.len() != n {
            self.scratch.resize(n, 0.0);
        }
        self.forces.accel(self.dim, t, x, v, &self.mass, &self.inv_mass, &mut self.scratch, a);
    }

    fn velocity_dependent(&self) -> bool {
        self.forces.velocity_dependent()
    }

    fn jacobian(&mut self, t: f64, x: &[f64], v: &[f64], dadx: &mut [f64], dadv: &mut [f64]) -> bool {
        self.forces.jacobian(self.dim, t, x, v, &self.inv_mass, dadx, dadv)
    }
}

impl Model {
    /// Masses, kg (infinite for static particles).
    #[must_use]
    pub fn mass(&self) -> &[f64] {
        &self.mass
    }

    /// The forces.
    #[must_use]
    pub fn forces(&self) -> &ForceSet {
        &self.forces
    }

    /// Potential energy of positions `x`, J.
    #[must_use]
    pub fn potential(&self, x: &[f64]) -> f64 {
        self.forces.potential(self.dim, x, &self.mass)
    }

    /// Kinetic energy of velocities `v`, J (static particles excluded).
    #[must_use]
    pub fn kinetic(&self, v: &[f64]) -> f64 {
        let mut e = 0.0;
        for (p, (m, w)) in self.mass.iter().zip(&self.inv_mass).enumerate() {
            if *w > 0.0 {
                let vp = &v[p * self.dim..(p + 1) * self.dim];
                e += 0.5 * m * vp.iter().map(|c| c * c).sum::<f64>();
            }
        }
        e
    }
}
