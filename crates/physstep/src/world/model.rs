//! The force model: masses and forces, what the integrators see as a second-order system.

use super::awake::Awake;
use crate::dynamics::SecondOrder;
use crate::error::Error;
use crate::forces::{ForceSet, UserForce};
use crate::limits::RUNAWAY;

/// Inverse masses, 1/kg (0 for static particles), one a particle, and whether they are all
/// the same (then the fused kernel reads one number, not the array: worlds of equal particles
/// are common, and the array is a stream of memory as long as a third of the state's). It
/// reads as a slice; every change goes through its methods, which keep that answer true.
#[derive(Debug, Clone, Default)]
pub(super) struct InvMass {
    values: Vec<f64>,
    /// `Some(Some(w))`: every value is `w` (bitwise); `Some(None)`: they differ (or there are
    /// none); `None`: not known since the last change.
    all: Option<Option<f64>>,
}

impl std::ops::Deref for InvMass {
    type Target = [f64];
    #[inline]
    fn deref(&self) -> &[f64] {
        &self.values
    }
}

impl<'a> IntoIterator for &'a InvMass {
    type Item = &'a f64;
    type IntoIter = std::slice::Iter<'a, f64>;
    fn into_iter(self) -> Self::IntoIter {
        self.values.iter()
    }
}

impl InvMass {
    /// Appends one particle's.
    pub(super) fn push(&mut self, w: f64) {
        self.all = match self.all {
            _ if self.values.is_empty() => Some(Some(w)),
            Some(Some(u)) if u.to_bits() == w.to_bits() => Some(Some(w)),
            Some(_) => Some(None),
            None => None,
        };
        self.values.push(w);
    }

    /// Sets particle `i`'s.
    pub(super) fn set(&mut self, i: usize, w: f64) {
        self.values[i] = w;
        self.all = None;
    }

    /// Keeps the particles not `gone`.
    pub(super) fn retain_by(&mut self, gone: &[bool]) {
        crate::ids::retain_by(&mut self.values, gone);
        self.all = None;
    }

    /// The one value every particle has (bitwise), if they all have the same and there is at
    /// least one; found by a scan after a change, then remembered.
    pub(super) fn all(&mut self) -> Option<f64> {
        *self.all.get_or_insert_with(|| {
            let w = *self.values.first()?;
            self.values.iter().all(|u| u.to_bits() == w.to_bits()).then_some(w)
        })
    }
}

/// The force model: what the integrators see as a [`SecondOrder`] system.
#[derive(Debug, Clone, Default)]
pub struct Model {
    pub(super) dim: usize,
    pub(super) mass: Vec<f64>,
    pub(super) inv_mass: InvMass,
    pub(super) forces: ForceSet,
    /// The user's force generators, in the order they were added.
    pub(super) user: Vec<UserForce>,
    /// The id of each user force, in the same order.
    pub(super) user_ids: Vec<crate::forces::ForceId>,
    pub(super) scratch: Vec<f64>,
    pub(super) user_f: Vec<f64>,
    /// The first failure of a user force during the current step (the accelerations were
    /// set to NaN so the step fails and is rolled back; the world reports this instead).
    pub(super) failure: Option<Error>,
    /// Whether the user forces' latest call outlasted [`super::awake::AWAKE_AT_MOST`] (the
    /// next is not waited for awake).
    pub(super) slow_call: bool,
}

impl SecondOrder for Model {
    #[inline]
    fn len(&self) -> usize {
        self.mass.len() * self.dim
    }

    #[inline]
    fn accel(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
        self.accel_with(t, x, v, a);
    }

    fn velocity_dependent(&self) -> bool {
        self.forces.velocity_dependent() || self.user.iter().any(|u| u.0.velocity_dependent())
    }

    fn energy(&self, x: &[f64], v: &[f64]) -> Option<(f64, f64)> {
        Some((self.kinetic(v), self.potential(x)?))
    }

    fn jacobian(&mut self, t: f64, x: &[f64], v: &[f64], dadx: &mut [f64], dadv: &mut [f64]) -> bool {
        if !self.forces.jacobian(self.dim, t, x, v, &self.inv_mass, dadx, dadv) {
            return false;
        }
        if self.user.is_empty() {
            return true;
        }
        // da/dx = M^-1 dF/dx row by row; the generators add into zeroed blocks of their own.
        let n = x.len();
        let (mut fx, mut fv) = (vec![0.0; n * n], vec![0.0; n * n]);
        for u in &self.user {
            if !u.0.jacobian(t, x, v, &mut fx, &mut fv) {
                return false;
            }
        }
        for row in 0..n {
            let w = self.inv_mass[row / self.dim];
            for col in 0..n {
                dadx[row * n + col] += w * fx[row * n + col];
                dadv[row * n + col] += w * fv[row * n + col];
            }
        }
        true
    }

    fn blocks(&mut self, _t: f64, x: &[f64], v: &[f64], out: &mut crate::linalg::Blocks) -> bool {
        if !self.user.is_empty() {
            return false;
        }
        out.reset(self.dim, &self.mass);
        for (m, im) in out.mass.iter_mut().zip(&self.inv_mass) {
            if *im == 0.0 {
                *m = f64::INFINITY;
            }
        }
        self.forces.blocks(x, v, out)
    }
}

impl Model {
    /// [`SecondOrder::accel`], and whether an entry of `a` ran away when the user forces' pass
    /// (the last to write every entry) saw every new value (`None`: no user force).
    fn accel_with(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) -> Option<bool> {
        let n = x.len();
        if self.scratch.len() != n {
            self.scratch.resize(n, 0.0);
        }
        // With no built-in force, the user forces' sum is written over `a` rather than added
        // to the zeros the built-in forces would leave there (the same bits: `0 + w (0 + f)`).
        let fresh = self.forces.is_empty() && !self.user.is_empty();
        if !fresh {
            self.forces.accel(self.dim, t, x, v, &self.mass, &self.inv_mass, &mut self.scratch, a);
        }
        (!self.user.is_empty()).then(|| self.add_user(t, x, v, a, fresh))
    }

    /// [`SecondOrder::accel`] and whether any entry of `a` ran away
    /// ([`crate::limits::runaway`]; a failing user force leaves NaN: yes), checked in the
    /// pass that sums the user forces where there are any.
    pub(super) fn accel_ran_away(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64]) -> bool {
        self.accel_with(t, x, v, a).unwrap_or_else(|| crate::limits::any_runaway(a))
    }

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

    /// Inverse masses, 1/kg (0 for static particles).
    #[must_use]
    pub fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }

    /// How many user forces ([`crate::forces::ForceGenerator`]s) act.
    #[must_use]
    pub fn user_forces(&self) -> usize {
        self.user.len()
    }

    /// Potential energy of positions `x`, J; `None` when a user force has no potential.
    #[must_use]
    pub fn potential(&self, x: &[f64]) -> Option<f64> {
        let mut u = self.forces.potential(self.dim, x, &self.mass);
        for g in &self.user {
            u += g.0.potential(x)?;
        }
        Some(u)
    }

    /// Adds the user forces' accelerations to `a`; whether an entry of the new `a` ran away.
    /// A failing generator (or one that returns a non-finite force) poisons `a` with NaN, so
    /// the step fails and is rolled back, and leaves its error in `failure` for the world to
    /// report.
    ///
    /// One generator (the common case) hands its forces over once
    /// ([`crate::forces::ForceGenerator::forces_to`]): checked and added in one pass, the
    /// same sum as the general path's (its forces added to zeros, then scaled). Several are
    /// summed in `user_f` first, the sum checked after each.
    fn add_user(&mut self, t: f64, x: &[f64], v: &[f64], a: &mut [f64], fresh: bool) -> bool {
        let dim = self.dim;
        let mut ran = false;
        let one = self.inv_mass.all();
        let mut awake = Awake::during(x.len() / dim, self.slow_call);
        let failed = if let [g] = self.user.as_slice() {
            let w = (&self.inv_mass[..], one);
            let mut handed = None;
            let r = g.0.forces_to(t, x, v, &mut self.user_f, &mut |f| {
                // (The force is computed: the pass reading it runs on the workers kept awake.)
                awake.end();
                handed =
                    Some(if f.len() == a.len() { Ok(add_accel(dim, w, f, a, fresh)) } else { Err(f.len()) });
            });
            match (r, handed) {
                (Err(reason), _) => Some((g, reason, false)),
                (Ok(()), None) => Some((g, "handed no forces".into(), false)),
                (Ok(()), Some(Err(len))) => {
                    Some((g, format!("handed {len} force components, not {}", a.len()), false))
                }
                (Ok(()), Some(Ok(Ok(r)))) => {
                    ran = r;
                    None
                }
                (Ok(()), Some(Ok(Err((i, c))))) => {
                    Some((g, format!("force[{}][{}] = {c} is not finite", i / dim, i % dim), true))
                }
            }
        } else {
            let f = &mut self.user_f;
            f.clear();
            f.resize(x.len(), 0.0);
            let failed = self.user.iter().find_map(|g| match g.0.add_forces(t, x, v, f) {
                Err(reason) => Some((g, reason, false)),
                Ok(()) => f
                    .iter()
                    .position(|c| !c.is_finite())
                    .map(|i| (g, format!("force[{}][{}] = {} is not finite", i / dim, i % dim, f[i]), true)),
            });
            awake.end();
            if failed.is_none() {
                let r = add_accel(dim, (&self.inv_mass[..], one), f, a, fresh);
                debug_assert!(r.is_ok(), "the sum was checked finite");
                ran = r.unwrap_or(true);
            }
            failed
        };
        // (The first end counts: the call's, not this.)
        self.slow_call = awake.end();
        if let Some((g, reason, non_finite)) = failed {
            if self.failure.is_none() {
                self.failure = Some(Error::Force { name: g.0.name().to_string(), reason, non_finite });
            }
            a.fill(f64::NAN);
            return true;
        }
        ran
    }

    /// Kinetic energy of velocities `v`, J (static particles excluded).
    #[must_use]
    pub fn kinetic(&self, v: &[f64]) -> f64 {
        match self.dim {
            1 => self.kinetic_d::<1>(v),
            2 => self.kinetic_d::<2>(v),
            _ => self.kinetic_d::<3>(v),
        }
    }

    /// [`Model::kinetic`] in `D` dimensions.
    #[inline(always)]
    fn kinetic_d<const D: usize>(&self, v: &[f64]) -> f64 {
        debug_assert_eq!(v.len(), self.len());
        let mut e = 0.0;
        for ((m, w), vp) in self.mass.iter().zip(&self.inv_mass).zip(v.chunks_exact(D)) {
            if *w > 0.0 {
                e += 0.5 * m * vp.iter().map(|c| c * c).sum::<f64>();
            }
        }
        e
    }

    /// Whether the energy of every state within [`RUNAWAY`] (each coordinate and velocity
    /// component at most that in size, as after every accepted step) is finite: then a
    /// recording need not check it row by row. Holds where there are particles, no user force,
    /// no force that grows without bound (central gravity, n-body), and the bounds of the kinetic
    /// and potential energies at that reach sum to at most 1e300 (far from overflow, whatever
    /// the rounding of the sums).
    pub(crate) fn energy_bounded(&self) -> bool {
        if !self.user.is_empty() || self.mass.is_empty() {
            return false;
        }
        // The largest |x| or |v| of a particle.
        let reach = RUNAWAY * (self.dim as f64).sqrt();
        let moving = self.mass.iter().zip(&self.inv_mass).filter(|(_, w)| **w > 0.0);
        let kinetic: f64 = moving.map(|(m, _)| 0.5 * m * reach * reach).sum();
        let potential = self.forces.potential_bound(reach, &self.mass);
        potential.is_some_and(|u| kinetic + u <= 1e300)
    }

    /// Appends the kinetic energy ([`Model::kinetic`]) and the energy (that plus
    /// [`Model::potential`]) of every row of positions `xs` and velocities `vs` (flat rows of
    /// `len()` values) to `kinetic` and `energy`, bit for bit as row by row. The forces'
    /// potentials only: for a model without user forces.
    pub(crate) fn energy_rows(&self, xs: &[f64], vs: &[f64], kinetic: &mut Vec<f64>, energy: &mut Vec<f64>) {
        match self.dim {
            1 => self.energy_rows_d::<1>(xs, vs, kinetic, energy),
            2 => self.energy_rows_d::<2>(xs, vs, kinetic, energy),
            _ => self.energy_rows_d::<3>(xs, vs, kinetic, energy),
        }
    }

    /// [`Model::energy_rows`] in `D` dimensions.
    fn energy_rows_d<const D: usize>(
        &self,
        xs: &[f64],
        vs: &[f64],
        kinetic: &mut Vec<f64>,
        energy: &mut Vec<f64>,
    ) {
        debug_assert!(self.user.is_empty());
        let (from, n) = (energy.len(), self.len());
        kinetic.extend(vs.chunks_exact(n).map(|v| self.kinetic_d::<D>(v)));
        energy.resize(from + xs.len() / n, 0.0);
        let e = &mut energy[from..];
        self.forces.potential_rows(D, xs, &self.mass, e);
        for (e, k) in e.iter_mut().zip(&kinetic[kinetic.len() - vs.len() / n..]) {
            // u + k: IEEE addition commutes, the bits of k + u.
            *e += k;
        }
    }
}

/// `a += w f` particle by particle (`w` the inverse masses; each force added to zero first, as
/// the sum of the forces of several generators starts: the same bits), in one pass that also
/// checks `f` and the new `a`: `Ok(whether an entry of a ran away)`, or the first non-finite
/// entry of `f` (`a` is then not all written). With `fresh`, `a = 0 + w f` over whatever `a`
/// held (no built-in force wrote it: the bits of zeros plus the sum, without the pass that
/// zeroes it). Large worlds are summed in parallel tasks of [`super::tiles::TASK`] particles
/// (each entry is its own sum: any split gives the same bits), with AVX2 where the CPU has it.
fn add_accel(
    dim: usize,
    (w, one): (&[f64], Option<f64>),
    f: &[f64],
    a: &mut [f64],
    fresh: bool,
) -> Result<bool, (usize, f64)> {
    use super::tiles::{PARALLEL_MIN, TASK};
    use rayon::prelude::*;
    /// Particles whose inverse masses are spread over their entries at a time.
    const CHUNK: usize = 64;
    /// `(all of f finite, some new a ran away)`; `one`, the inverse mass of every particle
    /// where they all have the same (then `w` is not read).
    #[inline(always)]
    fn add<const D: usize, const FRESH: bool>(
        w: &[f64],
        one: Option<f64>,
        f: &[f64],
        a: &mut [f64],
    ) -> (bool, bool) {
        let (mut bad, mut ran) = (false, false);
        // Each entry's inverse mass, so that the sum runs over entries (vectorised).
        let mut we = [one.unwrap_or(0.0); CHUNK * 3];
        for (p, (ac, fc)) in a.chunks_mut(CHUNK * D).zip(f.chunks(CHUNK * D)).enumerate() {
            if one.is_none() {
                for (wd, wp) in we.chunks_exact_mut(D).zip(&w[p * CHUNK..]) {
                    wd.fill(*wp);
                }
            }
            for ((ak, fk), wk) in ac.iter_mut().zip(fc).zip(&we) {
                bad |= !fk.is_finite();
                *ak = if FRESH { 0.0 } else { *ak } + wk * (0.0 + fk);
                ran |= crate::limits::runaway(*ak);
            }
        }
        (!bad, ran)
    }
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn add_avx2<const D: usize, const FRESH: bool>(
        w: &[f64],
        one: Option<f64>,
        f: &[f64],
        a: &mut [f64],
    ) -> (bool, bool) {
        add::<D, FRESH>(w, one, f, a)
    }
    fn task<const D: usize, const FRESH: bool>(
        w: &[f64],
        one: Option<f64>,
        f: &[f64],
        a: &mut [f64],
    ) -> (bool, bool) {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            return unsafe { add_avx2::<D, FRESH>(w, one, f, a) };
        }
        add::<D, FRESH>(w, one, f, a)
    }
    fn all<const D: usize, const FRESH: bool>(
        w: &[f64],
        one: Option<f64>,
        f: &[f64],
        a: &mut [f64],
    ) -> (bool, bool) {
        if w.len() < PARALLEL_MIN {
            return task::<D, FRESH>(w, one, f, a);
        }
        (w.par_chunks(TASK), f.par_chunks(TASK * D), a.par_chunks_mut(TASK * D))
            .into_par_iter()
            .map(|(w, f, a)| task::<D, FRESH>(w, one, f, a))
            .reduce(|| (true, false), |p, q| (p.0 & q.0, p.1 | q.1))
    }
    let (finite, ran) = match (dim, fresh) {
        (1, false) => all::<1, false>(w, one, f, a),
        (2, false) => all::<2, false>(w, one, f, a),
        (_, false) => all::<3, false>(w, one, f, a),
        (1, true) => all::<1, true>(w, one, f, a),
        (2, true) => all::<2, true>(w, one, f, a),
        (_, true) => all::<3, true>(w, one, f, a),
    };
    if finite {
        return Ok(ran);
    }
    Err(f.iter().position(|c| !c.is_finite()).map_or((0, f64::NAN), |i| (i, f[i])))
}

#[cfg(test)]
mod tests {
    use super::InvMass;

    #[test]
    fn the_one_inverse_mass_follows_every_change() {
        let mut w = InvMass::default();
        assert_eq!(w.all(), None, "no particle");
        for _ in 0..3 {
            w.push(0.5);
        }
        assert_eq!(w.all(), Some(0.5));
        w.push(0.25);
        assert_eq!(w.all(), None, "a different one added");
        w.retain_by(&[false, false, false, true]);
        assert_eq!(w.all(), Some(0.5), "it removed");
        w.set(1, 0.0);
        assert_eq!(w.all(), None, "one made static");
        w.set(1, 0.5);
        assert_eq!(w.all(), Some(0.5), "put back");
        w.push(-0.0 + 0.5);
        w.set(2, 0.0);
        w.set(0, -0.0);
        w.set(1, 0.0);
        w.set(3, 0.0);
        assert_eq!(w.all(), None, "-0 and 0 differ in bits");
        assert_eq!(&*w, &[-0.0, 0.0, 0.0, 0.0]);
    }
}
