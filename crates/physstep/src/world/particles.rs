//! Adding particles and forces to a [`World`]: the particles' checks (one line naming the
//! first bad entry), the state grown in place, the force set and the user's generators.

use super::{Model, World, MAX_MASS};
use crate::dynamics::SecondOrder;
use crate::error::{bounded, Error, Result};
use crate::forces::Force;
use crate::limits::RUNAWAY;

impl World {
    /// Adds one particle; `mass = inf` or `is_static` makes it immovable (inverse mass 0,
    /// velocity held at 0). Returns its index. Each call moves the velocity half of the state
    /// (O(n)); add many particles with [`World::add_particles`] (the Python face batches
    /// `add_particle` calls itself).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `position`, `velocity` or `mass` (> 0 unless static,
    /// NaN never); the world is unchanged.
    pub fn add_particle(
        &mut self,
        position: &[f64],
        velocity: &[f64],
        mass: f64,
        is_static: bool,
    ) -> Result<usize> {
        let i = self.len();
        self.add_particles(position, Some(velocity), Some(&[mass]), is_static)?;
        Ok(i)
    }

    /// Adds `k` particles from flat `positions` (`k * dim`), optional `velocities` (zero when
    /// `None`) and `masses` (1 kg when `None`). Returns the index of the first.
    ///
    /// # Errors
    /// As [`World::add_particle`], naming the first bad entry (`positions[5]`); the world is
    /// unchanged.
    pub fn add_particles(
        &mut self,
        positions: &[f64],
        velocities: Option<&[f64]>,
        masses: Option<&[f64]>,
        is_static: bool,
    ) -> Result<usize> {
        self.refuse_flow("particles")?;
        self.check_particles(positions, velocities, masses)?;
        let d = self.dim();
        let k = positions.len() / d;
        let first = self.len();
        let n_old = self.model.len();
        // y = [x, bodies' X; v, bodies' V] grows in place: the new positions go after the
        // old particles' positions, the new velocities after the old particles' velocities.
        let mut vel = Vec::with_capacity(k * d);
        for p in 0..k {
            let m = masses.map_or(1.0, |m| m[p]);
            let fixed = is_static || m.is_infinite();
            match velocities {
                Some(v) if !fixed => vel.extend_from_slice(&v[p * d..(p + 1) * d]),
                _ => vel.extend(std::iter::repeat_n(0.0, d)),
            }
            self.model.mass.push(m);
            self.model.inv_mass.push(if fixed { 0.0 } else { 1.0 / m });
        }
        self.state.y.splice(n_old..n_old, positions.iter().copied());
        let at = self.nx() + n_old;
        self.state.y.splice(at..at, vel);
        self.state.f.resize(self.state.y.len(), 0.0);
        self.touch();
        Ok(first)
    }

    /// Checks particles as [`World::add_particles`] would, without adding them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the first bad entry: `position[i]`, `velocity[i]`
    /// (flat indices into the given arrays), `mass` / `mass[i]` (> 0, NaN never; finite when
    /// n-body gravity is on), or a length that does not fit `dim`.
    pub fn check_particles(
        &self,
        positions: &[f64],
        velocities: Option<&[f64]>,
        masses: Option<&[f64]>,
    ) -> Result<()> {
        self.refuse_flow("particles")?;
        let d = self.dim();
        if positions.len() % d != 0 {
            return Err(Error::invalid(
                "len(positions)",
                positions.len(),
                format!("a multiple of dim = {d}"),
            ));
        }
        let k = positions.len() / d;
        bounded("position", positions, RUNAWAY)?;
        if let Some(v) = velocities {
            if v.len() != positions.len() {
                return Err(Error::invalid(
                    "len(velocity)",
                    v.len(),
                    format!("{}, like the positions", positions.len()),
                ));
            }
            bounded("velocity", v, RUNAWAY)?;
        }
        if let Some(m) = masses {
            if m.len() != k {
                return Err(Error::invalid("len(mass)", m.len(), format!("{k}, one per particle")));
            }
            for (i, &mi) in m.iter().enumerate() {
                let field = if k == 1 { "mass".to_string() } else { format!("mass[{i}]") };
                // 1/m must be finite (a subnormal mass has an infinite inverse), and so must m v
                // for every velocity a state may hold (|v| <= 1e100).
                let finite_ok = mi.is_finite() && mi > 0.0 && (1.0 / mi).is_finite() && mi <= MAX_MASS;
                if !(finite_ok || mi == f64::INFINITY) {
                    return Err(Error::invalid(
                        field,
                        crate::error::num(mi),
                        "> 0 with a finite inverse 1/m (about 5.6e-309 or more), at most 1e100 (inf for a static particle)",
                    ));
                }
            }
            // Forces that need finite masses (n-body) must accept the new particles too;
            // named by the index they would get in the world.
            if self.model.forces.needs_finite_masses() {
                crate::forces::finite_masses(m, self.len())?;
            }
        }
        Ok(())
    }

    /// Adds a force generator.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the bad field (a missing particle index, a negative
    /// stiffness, a zero rod length, ...); the world is unchanged.
    pub fn add_force(&mut self, force: Force) -> Result<()> {
        self.refuse_flow("a force")?;
        if matches!(force, Force::NBody { .. }) {
            // n-body gravity pulls with every mass: none may be infinite.
            crate::forces::finite_masses(&self.model.mass, 0)?;
        }
        // `add` validates before it inserts, so a rejected force leaves the set as it was.
        self.model.forces.add(force, self.len(), self.dim())?;
        self.touch();
        Ok(())
    }

    /// The force model (forces, masses, energies).
    #[must_use]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Adds a user force; returns its index among the user forces.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a world that is a flow.
    pub fn add_force_generator(
        &mut self,
        generator: std::sync::Arc<dyn crate::forces::ForceGenerator>,
    ) -> Result<usize> {
        self.refuse_flow("a force")?;
        self.model.user.push(crate::forces::UserForce(generator));
        self.touch();
        Ok(self.model.user.len() - 1)
    }
}
