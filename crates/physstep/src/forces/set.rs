//! The forces of a world as one set in canonical order: what the integrators evaluate
//! (accelerations in four phases), the potential energy and the analytic Jacobians.

use super::local::Local;
use super::{central, drag, finite_masses, gravity, nbody, rod, spring, Endpoint, Force};
use crate::error::{Error, Result};

/// A force's handle in its world: a number given when it is added (by
/// [`ForceSet::add`], [`crate::world::World::add_force`] and every `add_*` of a force),
/// never given again by that world, that stays the force's while other forces come and go
/// (their canonical order moves the forces' indices, never their ids). Built-in forces and
/// the user's generators draw from the same counter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ForceId(pub u64);

impl std::fmt::Display for ForceId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// The forces of a world, kept in canonical order, each with its [`ForceId`].
///
/// Two sets are equal when they hold the same forces in the same order (so step the same
/// bits), whatever their ids.
#[derive(Debug, Clone, Default)]
pub struct ForceSet {
    forces: Vec<Force>,
    /// The id of each force of `forces`, in the same order.
    ids: Vec<ForceId>,
    /// The id the next force gets (ids are never given twice).
    next: u64,
    /// What the list holds, kept on `add` so the hot path does not scan for it.
    kinds: Kinds,
    /// The per-particle forces, gathered on `add`.
    local: Local,
    /// The springs between two particles, in canonical order: `(i, j, [k, rest, c])`,
    /// gathered on `add` (the loops of [`ForceSet::accel`] and of the Jacobian blocks,
    /// without matching every force).
    springs: Vec<(usize, usize, [f64; 3])>,
}

impl PartialEq for ForceSet {
    fn eq(&self, other: &Self) -> bool {
        self.forces == other.forces && self.kinds == other.kinds && self.local == other.local
    }
}

/// No force of id `id`.
pub(crate) fn unknown(id: ForceId) -> Error {
    Error::invalid("force", id, "the id of a force of this world (it was removed, or never added here)")
}

/// Checks `ids` as the ids of `len` forces under the counter `next`: one per force, distinct,
/// each below `next`.
pub(crate) fn check_ids(ids: &[ForceId], len: usize, next: u64) -> Result<()> {
    if ids.len() != len {
        return Err(Error::invalid("len(ids)", ids.len(), format!("{len}, one per force")));
    }
    let mut seen = std::collections::HashSet::new();
    for id in ids {
        if id.0 >= next || !seen.insert(*id) {
            return Err(Error::invalid("ids", id, format!("distinct ids below next = {next}")));
        }
    }
    Ok(())
}

/// Which phases of [`ForceSet::accel`] have work, and whether any force reads velocity.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Kinds {
    /// Springs between two particles.
    pairs: bool,
    rods: bool,
    velocity: bool,
    nbody: bool,
}

impl Kinds {
    /// These kinds and those of `f`.
    fn with(self, f: &Force) -> Self {
        let mut k = self;
        match *f {
            Force::Spring { damping, j, .. } => {
                k.pairs |= matches!(j, Endpoint::Particle(_));
                k.velocity |= damping != 0.0;
            }
            Force::Drag { linear, quadratic } => {
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
    /// [`Error::InvalidValue`](crate::Error::InvalidValue) naming the field: `dim`; `i`, `j` (a particle index `< n`, and
    /// `j != i`); `stiffness`, `rest_length`, `damping`, `linear`, `quadratic`, `softening`
    /// (finite, >= 0); `length` (finite, > 0); `gm`, `g` (finite); `g`, `center`, `anchor`
    /// (every component within `dim` finite).
    pub fn add(&mut self, force: Force, n: usize, dim: usize) -> Result<ForceId> {
        let force = force.normalised(n, dim)?;
        let id = self.new_id();
        self.insert(force, id);
        self.kinds = self.kinds.with(&force);
        self.local.add(&force, self.forces.iter());
        if let Some(spring) = particle_spring(&force) {
            let key = force.key();
            let at = self.springs.partition_point(|&(i, j, p)| spring_force(i, j, p).key() <= key);
            self.springs.insert(at, spring);
        }
        Ok(id)
    }

    /// A new id (for a force the set holds, or a user generator beside it).
    pub(crate) fn new_id(&mut self) -> ForceId {
        let id = ForceId(self.next);
        self.next += 1;
        id
    }

    /// The id the next force will get.
    #[must_use]
    pub fn next_id(&self) -> ForceId {
        ForceId(self.next)
    }

    /// Inserts a normalised force at its canonical place, with `id`.
    fn insert(&mut self, force: Force, id: ForceId) {
        let key = force.key();
        let at = self.forces.partition_point(|f| f.key() <= key);
        self.forces.insert(at, force);
        self.ids.insert(at, id);
    }

    /// Where force `id` sits in the canonical order.
    fn position(&self, id: ForceId) -> Option<usize> {
        self.ids.iter().position(|&i| i == id)
    }

    /// The force of id `id`, as normalised when it was added (`None` when the set holds
    /// none of that id: never added, removed, or a user generator).
    #[must_use]
    pub fn get(&self, id: ForceId) -> Option<Force> {
        self.position(id).map(|at| self.forces[at])
    }

    /// The forces with their ids, in canonical order.
    pub fn iter_ids(&self) -> impl Iterator<Item = (ForceId, &Force)> {
        self.ids.iter().copied().zip(&self.forces)
    }

    /// Removes force `id` and returns it (`None`, the set unchanged, when it holds no such
    /// force). What is left steps bitwise as a set that never held it: the derived
    /// per-particle forces and kinds are gathered again over the canonical order.
    pub fn remove(&mut self, id: ForceId) -> Option<Force> {
        let at = self.position(id)?;
        let force = self.forces.remove(at);
        self.ids.remove(at);
        self.rebuild();
        Some(force)
    }

    /// Puts `force` in place of force `id`, validated as [`ForceSet::add`] validates (for `n`
    /// particles in `dim` dimensions) and of the same kind; it keeps the id and moves to its
    /// canonical place, and the set steps bitwise as one that had it from the start.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `force` (no force of that id here), `kind` (another
    /// kind of force) or the bad field as [`ForceSet::add`]; the set is unchanged.
    pub fn replace(&mut self, id: ForceId, force: Force, n: usize, dim: usize) -> Result<()> {
        let Some(at) = self.position(id) else {
            return Err(unknown(id));
        };
        let old = self.forces[at];
        if old.rank() != force.rank() {
            return Err(Error::invalid(
                "kind",
                force.kind(),
                format!("'{}', the kind of force {id} (remove it and add the other instead)", old.kind()),
            ));
        }
        let force = force.normalised(n, dim)?;
        self.forces.remove(at);
        self.ids.remove(at);
        self.insert(force, id);
        self.rebuild();
        Ok(())
    }

    /// Gives the forces (in canonical order) the ids `ids` and the counter `next`, as a face
    /// that keeps its own handles across a round trip through scene text (the Python pickle)
    /// restores them.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `ids` (not one per force, or one repeated, or one
    /// `>= next`); the set is unchanged.
    pub fn set_ids(&mut self, ids: &[ForceId], next: u64) -> Result<()> {
        check_ids(ids, self.forces.len(), next)?;
        self.ids = ids.to_vec();
        self.next = next;
        Ok(())
    }

    /// Keeps the forces `keep` says yes to (their order and ids with them), each mapped by
    /// `f` (particle ends renumbered after a removal, keeping every comparison of the keys,
    /// so the order stays canonical); the derived forces gathered again once.
    pub(crate) fn retain_renumbered(&mut self, keep: impl Fn(&Force) -> bool, f: impl Fn(Force) -> Force) {
        let gone: Vec<bool> = self.forces.iter().map(|force| !keep(force)).collect();
        crate::ids::retain_by(&mut self.forces, &gone);
        crate::ids::retain_by(&mut self.ids, &gone);
        for force in &mut self.forces {
            *force = f(*force);
        }
        self.rebuild();
    }

    /// The kinds and per-particle forces gathered again over the whole set, in canonical
    /// order (what adding the forces one by one gives: the same sums, in the same order).
    fn rebuild(&mut self) {
        self.kinds = self.forces.iter().fold(Kinds::default(), |k, f| k.with(f));
        self.local = Local::default();
        for f in &self.forces {
            self.local.add(f, self.forces.iter());
        }
        self.springs = self.forces.iter().filter_map(particle_spring).collect();
    }

    /// The springs between two particles, `(i, j, [k, rest, c])` in canonical order.
    pub(super) fn springs(&self) -> &[(usize, usize, [f64; 3])] {
        &self.springs
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
    /// [`Error::InvalidValue`](crate::Error::InvalidValue) naming `mass[i]` of the first offending particle.
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

    /// The per-particle forces (gravity, drag, central gravity, springs to anchors).
    pub(crate) fn local(&self) -> &Local {
        &self.local
    }

    /// Fills `a` (length `n * dim`, m/s^2) with the total acceleration at time `t` (s),
    /// positions `x` (m) and velocities `v` (m/s). `mass` (kg) and `inv_mass` (1/kg, 0 for
    /// static particles) have length `n`; `f` is scratch of length `n * dim`. Allocates
    /// nothing.
    ///
    /// The per-particle forces come first, particle by particle, as the fused kernels compute
    /// them (`forces::local`); then the springs between particles (`a += F / m`), n-body gravity,
    /// and the rods, each in canonical order.
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

        let springs = self.local.anchors(0, inv_mass.len());
        match dim {
            1 => self.local.accel::<1>(0, x, v, inv_mass, springs, a),
            2 => self.local.accel::<2>(0, x, v, inv_mass, springs, a),
            _ => self.local.accel::<3>(0, x, v, inv_mass, springs, a),
        }
        if self.kinds.pairs {
            f.fill(0.0);
            match dim {
                1 => particle_springs::<1>(&self.springs, x, v, f),
                2 => particle_springs::<2>(&self.springs, x, v, f),
                _ => particle_springs::<3>(&self.springs, x, v, f),
            }
            for ((ap, fp), &im) in a.chunks_exact_mut(dim).zip(f.chunks_exact(dim)).zip(inv_mass) {
                for (ak, fk) in ap.iter_mut().zip(fp) {
                    *ak += fk * im;
                }
            }
        }
        if self.kinds.nbody {
            for force in &self.forces {
                if let Force::NBody { g, softening } = *force {
                    nbody::accel(dim, g, softening, x, mass, inv_mass, a);
                }
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
        debug_assert_eq!(x.len(), mass.len() * dim);
        if mass.is_empty() {
            // No particles: every term is 0 (and there are no rows to split x into).
            return 0.0;
        }
        let mut u = [0.0];
        self.potential_rows(dim, x, mass, &mut u);
        u[0]
    }

    /// [`ForceSet::potential`] of every row of `xs` (flat rows of `mass.len() * dim`
    /// positions, at least one particle) added to `u`, one entry per row: each force matched
    /// once for all the rows, each row's terms added in the forces' order.
    #[inline]
    pub(crate) fn potential_rows(&self, dim: usize, xs: &[f64], mass: &[f64], u: &mut [f64]) {
        let w = mass.len() * dim;
        for force in &self.forces {
            let rows = xs.chunks_exact(w).zip(u.iter_mut());
            match *force {
                Force::Gravity { g } => rows.for_each(|(x, u)| *u += gravity::potential(dim, g, x, mass)),
                Force::Spring { i, j, stiffness, rest_length, .. } => {
                    rows.for_each(|(x, u)| *u += spring::potential(dim, x, i, j, stiffness, rest_length))
                }
                Force::CentralGravity { center, gm } => {
                    rows.for_each(|(x, u)| *u += central::potential(dim, center, gm, x, mass));
                }
                Force::NBody { g, softening } => {
                    rows.for_each(|(x, u)| *u += nbody::potential(dim, g, softening, x, mass));
                }
                Force::Drag { .. } | Force::Rod { .. } => rows.for_each(|(_, u)| *u += 0.0),
            }
        }
    }

    /// A bound on `|potential|` over every position whose coordinates are at most `reach`
    /// from the origin (particles of masses `mass`); `None` where none holds (central gravity
    /// and n-body grow without bound as particles meet).
    pub(crate) fn potential_bound(&self, reach: f64, mass: &[f64]) -> Option<f64> {
        let m: f64 = mass.iter().filter(|m| m.is_finite()).sum();
        let norm = |v: [f64; 3]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
        let mut bound = 0.0;
        for force in &self.forces {
            bound += match *force {
                // |m g . x| <= m |g| |x|.
                Force::Gravity { g } => m * norm(g) * reach,
                // | |d| - rest | <= |x_i| + |x_j or anchor| + rest (stiffness >= 0, checked
                // when the force is added).
                Force::Spring { j, stiffness, rest_length, .. } => {
                    let far = match j {
                        Endpoint::Particle(_) => reach,
                        Endpoint::Anchor(at) => norm(at),
                    };
                    let e = reach + far + rest_length;
                    0.5 * stiffness * e * e
                }
                Force::CentralGravity { .. } | Force::NBody { .. } => return None,
                Force::Drag { .. } | Force::Rod { .. } => 0.0,
            };
        }
        Some(bound)
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

/// A spring between two particles as `(i, j, [k, rest, c])`.
fn particle_spring(force: &Force) -> Option<(usize, usize, [f64; 3])> {
    match *force {
        Force::Spring { i, j: Endpoint::Particle(j), stiffness, rest_length, damping } => {
            Some((i, j, [stiffness, rest_length, damping]))
        }
        _ => None,
    }
}

/// The force of [`particle_spring`]'s triple.
fn spring_force(i: usize, j: usize, [stiffness, rest_length, damping]: [f64; 3]) -> Force {
    Force::Spring { i, j: Endpoint::Particle(j), stiffness, rest_length, damping }
}

/// The springs' forces added to `f`, in order, on particles of `D` coordinates (the same
/// arithmetic as `spring::force` at any `dim`: the same bits).
#[inline(never)]
fn particle_springs<const D: usize>(
    springs: &[(usize, usize, [f64; 3])],
    x: &[f64],
    v: &[f64],
    f: &mut [f64],
) {
    for &(i, j, p) in springs {
        spring::force(D, x, v, i, Endpoint::Particle(j), p, f);
    }
}
