//! Adding particles and forces to a [`World`]: the particles' checks (one line naming the
//! first bad entry), the state grown in place, the force set and the user's generators.

use super::{Model, World, MAX_MASS};
use crate::dynamics::SecondOrder;
use crate::error::{bounded, Error, Result};
use crate::forces::{Force, ForceId};
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
        self.ids.particles.push(k);
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

    /// Adds a built-in force; returns its id, the handle that reaches it while other forces
    /// come and go ([`World::force`], [`World::set_force`], [`World::remove_force`]).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the bad field (a missing particle index, a negative
    /// stiffness, a zero rod length, ...); the world is unchanged.
    pub fn add_force(&mut self, force: Force) -> Result<ForceId> {
        self.refuse_flow("a force")?;
        if matches!(force, Force::NBody { .. }) {
            // n-body gravity pulls with every mass: none may be infinite.
            crate::forces::finite_masses(&self.model.mass, 0)?;
        }
        // `add` validates before it inserts, so a rejected force leaves the set as it was.
        let id = self.model.forces.add(force, self.len(), self.dim())?;
        self.touch();
        Ok(id)
    }

    /// The built-in force of id `id`, as the world holds it (pairs ordered `i < j`,
    /// components beyond `dim` zero); `None` for an id removed, never given, or a user
    /// force's ([`World::is_user_force`]).
    #[must_use]
    pub fn force(&self, id: ForceId) -> Option<Force> {
        self.model.forces.get(id)
    }

    /// Whether `id` is a user force's ([`World::add_force_generator`]) still in the world.
    #[must_use]
    pub fn is_user_force(&self, id: ForceId) -> bool {
        self.model.user_ids.contains(&id)
    }

    /// The ids of every force of the world: the built-in ones in canonical order (the order
    /// [`Model::forces`] iterates), then the user forces in the order they were added.
    #[must_use]
    pub fn force_ids(&self) -> Vec<ForceId> {
        let set = self.model.forces.iter_ids().map(|(id, _)| id);
        set.chain(self.model.user_ids.iter().copied()).collect()
    }

    /// Replaces force `id` by `force` of the same kind (a spring's stiffness, rest length,
    /// damping or ends, gravity's `g`, drag's coefficients, ...), validated as
    /// [`World::add_force`] validates; the force keeps its id. The next step sees it, and
    /// the world steps bitwise as one that had this force from the start: like an added
    /// force, it restarts a method that carries memory (as [`World::add_force`] does).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `force` (an id this world holds no built-in force
    /// of), `kind` (another kind) or the bad field, as [`World::add_force`] (a rod's `length`
    /// must be the distance its ends have, as [`World::add_rod`] checks); the world is
    /// unchanged.
    pub fn set_force(&mut self, id: ForceId, force: Force) -> Result<()> {
        self.refuse_flow("a force")?;
        match force {
            Force::NBody { .. } => crate::forces::finite_masses(&self.model.mass, 0)?,
            // A rod holds the length its ends have, as `add_rod` checks.
            Force::Rod { i, j, length } if self.force(id).is_some_and(|f| f.kind() == "rod") => {
                self.rod_length(i, j, Some(length))?;
            }
            _ => {}
        }
        self.model.forces.replace(id, force, self.len(), self.dim())?;
        self.touch();
        Ok(())
    }

    /// Removes force `id` (built-in or user): the world then steps bitwise as one that never
    /// had it (restarting a method that carries memory, as adding a force does). The ids of
    /// the other forces do not change, and `id` is never given again.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `force` when the world holds no force of that id
    /// (removed already, or never added here); the world is unchanged.
    pub fn remove_force(&mut self, id: ForceId) -> Result<()> {
        if self.model.forces.remove(id).is_none() {
            let at = self.model.user_ids.iter().position(|&u| u == id);
            let at = at.ok_or_else(|| crate::forces::set::unknown(id))?;
            self.model.user.remove(at);
            self.model.user_ids.remove(at);
        }
        self.touch();
        Ok(())
    }

    /// Gives the world's forces the ids `ids` (one per force in the order of
    /// [`World::force_ids`]) and the id counter `next`: how a face that serialises a world
    /// as scene text, which carries no ids (a scene file's forces get ids in reading order),
    /// keeps its handles valid across the round trip (the Python pickle does).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `len(ids)` (not one per force) or `ids` (an id
    /// repeated or not below `next`); the world is unchanged.
    pub fn set_force_ids(&mut self, ids: &[ForceId], next: u64) -> Result<()> {
        let builtin = self.model.forces.len();
        crate::forces::set::check_ids(ids, builtin + self.model.user.len(), next)?;
        self.model.forces.set_ids(&ids[..builtin], next)?;
        self.model.user_ids = ids[builtin..].to_vec();
        Ok(())
    }

    /// The id the next force added will get.
    #[must_use]
    pub fn next_force_id(&self) -> ForceId {
        self.model.forces.next_id()
    }

    /// The force model (forces, masses, energies).
    #[must_use]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Adds a user force; returns its id (from the counter the built-in forces draw
    /// from), which [`World::remove_force`] takes.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a world that is a flow.
    pub fn add_force_generator(
        &mut self,
        generator: std::sync::Arc<dyn crate::forces::ForceGenerator>,
    ) -> Result<ForceId> {
        self.refuse_flow("a force")?;
        self.model.user.push(crate::forces::UserForce(generator));
        let id = self.model.forces.new_id();
        self.model.user_ids.push(id);
        self.touch();
        Ok(id)
    }

    /// The position of user force `id` among the user forces (the order they act in and
    /// were added in), `None` when it is not one.
    #[must_use]
    pub fn user_force_index(&self, id: ForceId) -> Option<usize> {
        self.model.user_ids.iter().position(|&u| u == id)
    }
}
