//! The relaxation sweeps: projection (PBD / XPBD, Jakobsen's relaxation) here, SHAKE/RATTLE's
//! updates in [`rattle`], both taken in the sweeps of [`Solver::positions`].
//!
//! Everything here works on flat particle slices (`x`, `v`, `a` of `n * dim`) and runs
//! serially, constraint after constraint in the order they were added (Gauss-Seidel), so the
//! bits never depend on the thread count.

use super::{Constraint, TOLERANCE};
use crate::forces::Endpoint;
use rattle::rigid;

mod rattle;

/// Which solver a step uses: the world's method's [`Info::constraints`](crate::integrators::Info::constraints).
pub(crate) use crate::integrators::ConstraintMode as Mode;

/// The solver's scratch: reused from step to step, never state (rebuilt every step).
#[derive(Debug, Clone, Default)]
pub(crate) struct Solver {
    /// Positions at the start of the step (SHAKE's gradients).
    pub start: Vec<f64>,
    /// Positions after the method, before the sweeps.
    pub moved: Vec<f64>,
    /// Per particle: the inverse mass, 0 for a pinned particle.
    w: Vec<f64>,
    /// XPBD multipliers of this step, one per constraint (the packed links keep theirs).
    lambda: Vec<f64>,
    /// Whether the last sweep of [`Solver::positions`] found a constraint off by more than
    /// [`TOLERANCE`] (relative): true when the sweeps ended at their cap with one still off.
    pub last_off: bool,
    /// The sweep's program: the constraints in order, runs of rigid links packed.
    plan: Plan,
}

/// A rigid distance between two particles under projection, packed for the sweeps: the
/// hot loop of a cloth (no enum to match, no anchor to test, the dimension fixed).
#[derive(Debug, Clone, Copy)]
struct Link {
    i: usize,
    j: usize,
    length: f64,
    /// Its compliance, 0 (or -0: the sign of XPBD's `alpha lambda` term is kept).
    zero: f64,
    /// Its XPBD multiplier this step. With `alpha = 0` it only ever sets the sign of a zero
    /// correction; kept so that the update is XPBD's to the bit.
    lambda: f64,
}

/// One item of a sweep: a run of packed links, or a constraint taken the general way.
#[derive(Debug, Clone, Copy)]
enum Item {
    /// `links[from..to]`.
    Links { from: usize, to: usize },
    /// `list[k]`.
    General(usize),
    /// `list[k]`, a pin: set before the sweeps, which pass it by.
    Pin(usize),
}

/// The sweep's program for a list of constraints, rebuilt when the list grows (constraints
/// are only ever appended) or the solver changes between projection and SHAKE.
#[derive(Debug, Clone, Default)]
struct Plan {
    /// The list's length and whether it was planned for SHAKE (`None`: not planned).
    key: Option<(usize, bool)>,
    items: Vec<Item>,
    links: Vec<Link>,
    /// Tests only: take every constraint the general way (the reference the packed links
    /// are checked against, bit for bit).
    general_only: bool,
}

impl Plan {
    /// Plans `list` for `mode`: consecutive rigid particle-particle distances under
    /// projection packed into runs of [`Link`]s, pins marked (a sweep passes them by).
    fn update(&mut self, list: &[Constraint], mode: Mode) {
        let key = (list.len(), mode == Mode::Rattle);
        if self.key == Some(key) {
            return;
        }
        self.items.clear();
        self.links.clear();
        for (k, c) in list.iter().enumerate() {
            match *c {
                Constraint::Distance { i, j: Endpoint::Particle(j), length, compliance }
                    if compliance == 0.0 && mode != Mode::Rattle && !self.general_only =>
                {
                    let at = self.links.len();
                    self.links.push(Link { i, j, length, zero: compliance, lambda: 0.0 });
                    match self.items.last_mut() {
                        Some(Item::Links { to, .. }) if *to == at => *to = at + 1,
                        _ => self.items.push(Item::Links { from: at, to: at + 1 }),
                    }
                }
                Constraint::Pin { .. } => self.items.push(Item::Pin(k)),
                _ => self.items.push(Item::General(k)),
            }
        }
        self.key = Some(key);
    }
}

/// The other end's position component `k` (a particle's or the anchor's).
#[inline]
fn at(x: &[f64], dim: usize, j: Endpoint, k: usize) -> f64 {
    match j {
        Endpoint::Particle(j) => x[j * dim + k],
        Endpoint::Anchor(c) => c[k],
    }
}

/// `x_i - x_j` over `dim` components.
#[inline]
fn sep(x: &[f64], dim: usize, i: usize, j: Endpoint) -> [f64; 3] {
    let mut d = [0.0; 3];
    for (k, dk) in d.iter_mut().enumerate().take(dim) {
        *dk = x[i * dim + k] - at(x, dim, j, k);
    }
    d
}

#[inline]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// One Gauss-Seidel pass over a run of rigid links in `D` dimensions: for each, XPBD's
/// update with `alpha = 0` exactly as [`Solver::xpbd`] takes it (`dl = (-C - 0 lambda) / w`,
/// `x_i += w_i (dl / r) d`, `x_j -= w_j (dl / r) d`), inlined. `off` says whether a
/// constraint of this sweep was already found off by more than [`TOLERANCE`]; the relative
/// correction `|dl w| / L` (a division) is measured only until one is. Returns the new `off`.
///
/// Every link waits on the one before it (a cloth's links share particles), so what counts
/// is the chain of dependent operations: the first end of the last link is kept in
/// registers (a cloth's next link often starts there; reading it back from memory would
/// wait on the store), and `-C / w` is taken as `C / -w` (the same number: rounding is
/// symmetric in sign), which keeps a negation off the chain.
#[inline(never)]
fn links_sweep<const D: usize>(links: &mut [Link], x: &mut [f64], w: &[f64], mut off: bool) -> bool {
    // The last link's first particle and where it left it (`usize::MAX`: none yet).
    let (mut last, mut at) = (usize::MAX, [0.0; D]);
    for l in links {
        let (i, j) = (l.i, l.j);
        let (wi, wj) = (w[i], w[j]);
        let wsum = wi + wj;
        let xi: [f64; D] = if i == last { at } else { std::array::from_fn(|k| x[i * D + k]) };
        let xj: [f64; D] = std::array::from_fn(|k| x[j * D + k]);
        let d: [f64; D] = std::array::from_fn(|k| xi[k] - xj[k]);
        // `dot` sums left to right from the first square (no `0 +` ahead of it: that add
        // would sit on the chain).
        let mut dd = d[0] * d[0];
        for dk in &d[1..] {
            dd += dk * dk;
        }
        let r = dd.sqrt();
        if wsum == 0.0 || r == 0.0 {
            continue;
        }
        let c = r - l.length;
        // `-c - alpha lambda` is `-c` but for the sign of a zero: taken only where c is 0.
        let dl = if c == 0.0 { zero_update(c, l.zero * l.lambda, wsum) } else { c / -wsum };
        l.lambda += dl;
        let s = dl / r;
        let (si, sj) = (wi * s, wj * s);
        at = std::array::from_fn(|k| xi[k] + si * d[k]);
        last = i;
        x[i * D..i * D + D].copy_from_slice(&at);
        for k in 0..D {
            x[j * D + k] = xj[k] - sj * d[k];
        }
        if !off {
            off = (dl * wsum).abs() / l.length > TOLERANCE;
        }
    }
    off
}

/// Whether `|fl(sqrt(dd)) - length|` is certainly at most `worst`, from `dd` alone: `dd`
/// inside `[(length - worst)^2, (length + worst)^2]` narrowed by 1e-15 (relative, about 5
/// ulps) at each end for the roundings, so a link it passes could not have raised the max.
/// (`fl(sqrt)` and `fl(r - L)` are monotone and `worst` is a double: a root within
/// `[L - worst, L + worst]` gives a difference within `worst`.) False for a NaN `dd`.
#[inline]
fn within(dd: f64, length: f64, worst: f64) -> bool {
    let lo = (length - worst) * (1.0 + 1e-15);
    let hi = (length + worst) * (1.0 - 1e-15);
    let above = lo <= 0.0 || dd >= lo * lo * (1.0 + 1e-15);
    worst > 0.0 && above && dd <= hi * hi * (1.0 - 1e-15)
}

/// `(-c - alpha_lambda) / wsum` where `c` is 0: the signed zero XPBD's update gives, off
/// the links' hot path.
#[cold]
#[inline(never)]
fn zero_update(c: f64, alpha_lambda: f64, wsum: f64) -> f64 {
    (-c - alpha_lambda) / wsum
}

impl Solver {
    /// Inverse mass of the other end (0 for an anchor).
    #[inline]
    fn w_of(&self, j: Endpoint) -> f64 {
        match j {
            Endpoint::Particle(j) => self.w[j],
            Endpoint::Anchor(_) => 0.0,
        }
    }

    /// Moves `x_i` by `wi s g` and `x_j` by `-wj s g`.
    #[inline]
    fn apply(&self, x: &mut [f64], dim: usize, i: usize, j: Endpoint, s: f64, g: &[f64; 3]) {
        let wi = self.w[i];
        for (k, gk) in g.iter().enumerate().take(dim) {
            x[i * dim + k] += wi * s * gk;
        }
        if let Endpoint::Particle(j) = j {
            let wj = self.w[j];
            for (k, gk) in g.iter().enumerate().take(dim) {
                x[j * dim + k] -= wj * s * gk;
            }
        }
    }

    /// The weights of this step: inverse masses, 0 for pinned particles (held where their
    /// pin is; a static particle is not moved by its pin).
    fn weigh(&mut self, list: &[Constraint], plan: &Plan, inv_mass: &[f64]) {
        self.w.clear();
        self.w.extend_from_slice(inv_mass);
        for item in &plan.items {
            if let Item::Pin(k) = *item {
                if let Constraint::Pin { i, .. } = list[k] {
                    self.w[i] = 0.0;
                }
            }
        }
    }

    /// Relaxes the positions `x` (after the method's step of `h`) onto the constraints: pins
    /// set, then up to `iterations` sweeps, stopping early once a sweep finds no constraint
    /// off by more than [`TOLERANCE`] (relative). The positions before the sweeps are kept
    /// in `moved`. Returns the sweeps taken.
    ///
    /// Each sweep follows the [`Plan`]: runs of rigid links go through [`links_sweep`]
    /// (the same arithmetic as [`Solver::xpbd`] with `alpha = 0`, so the same bits), the
    /// rest through [`Solver::general`].
    #[allow(clippy::too_many_arguments)]
    pub fn positions(
        &mut self,
        list: &[Constraint],
        iterations: u32,
        mode: Mode,
        dim: usize,
        x: &mut [f64],
        inv_mass: &[f64],
        h: f64,
    ) -> u32 {
        self.moved.clear();
        self.moved.extend_from_slice(x);
        let mut plan = std::mem::take(&mut self.plan);
        plan.update(list, mode);
        self.weigh(list, &plan, inv_mass);
        for item in &plan.items {
            if let Item::Pin(k) = *item {
                if let Constraint::Pin { i, point } = list[k] {
                    if inv_mass[i] > 0.0 {
                        x[i * dim..(i + 1) * dim].copy_from_slice(&point[..dim]);
                    }
                }
            }
        }
        self.lambda.clear();
        self.lambda.resize(list.len(), 0.0);
        plan.links.iter_mut().for_each(|l| l.lambda = 0.0);
        let inv_h2 = 1.0 / (h * h);
        let mut taken = iterations;
        for sweep in 0..iterations {
            let mut off = false;
            for item in &plan.items {
                match *item {
                    Item::Links { from, to } => {
                        let links = &mut plan.links[from..to];
                        off = match dim {
                            3 => links_sweep::<3>(links, x, &self.w, off),
                            2 => links_sweep::<2>(links, x, &self.w, off),
                            _ => links_sweep::<1>(links, x, &self.w, off),
                        };
                    }
                    Item::Pin(_) => {}
                    Item::General(k) => {
                        let r = self.general(&list[k], k, mode, dim, x, inv_h2);
                        // `r > TOLERANCE` is false for a NaN, as `max` skipped it before.
                        off |= r > TOLERANCE;
                    }
                }
            }
            self.last_off = off;
            if !off {
                taken = sweep + 1;
                break;
            }
        }
        self.plan = plan;
        taken
    }

    /// The largest violation (m) of the constraints at positions `x`, exactly as
    /// [`super::Constraints::violation`] gives it (the same values folded by `max` in the
    /// same order), the packed links measured in a tight loop: what a step whose sweeps
    /// were capped left. Reads the plan of the last [`Solver::positions`] over `list`.
    pub fn left(&self, list: &[Constraint], dim: usize, x: &[f64], inv_mass: &[f64]) -> f64 {
        let movable = |p: usize| inv_mass[p] > 0.0;
        if self.plan.key.map(|(n, _)| n) != Some(list.len()) {
            return list.iter().map(|c| c.violation(dim, x, &movable)).fold(0.0, f64::max);
        }
        let mut worst: f64 = 0.0;
        for item in &self.plan.items {
            match *item {
                Item::Links { from, to } => {
                    for l in &self.plan.links[from..to] {
                        if !(inv_mass[l.i] > 0.0 || inv_mass[l.j] > 0.0) {
                            continue; // its violation is 0, which `max` keeps out
                        }
                        let (a, b) = (&x[l.i * dim..(l.i + 1) * dim], &x[l.j * dim..(l.j + 1) * dim]);
                        let mut dd = (a[0] - b[0]) * (a[0] - b[0]);
                        for k in 1..dim {
                            dd += (a[k] - b[k]) * (a[k] - b[k]);
                        }
                        if within(dd, l.length, worst) {
                            continue; // `|sqrt(dd) - L| <= worst`: the root is not needed
                        }
                        worst = worst.max((dd.sqrt() - l.length).abs());
                    }
                }
                Item::General(k) | Item::Pin(k) => worst = worst.max(list[k].violation(dim, x, &movable)),
            }
        }
        worst
    }

    /// One update of constraint `list[k]` the general way (anything but a packed link);
    /// returns its relative correction or error.
    fn general(
        &mut self,
        c: &Constraint,
        k: usize,
        mode: Mode,
        dim: usize,
        x: &mut [f64],
        inv_h2: f64,
    ) -> f64 {
        match *c {
            Constraint::Distance { i, j, length, compliance } if rigid(compliance, mode) => {
                self.shake(x, dim, i, j, length)
            }
            Constraint::Distance { i, j, length, compliance } => {
                self.xpbd(x, dim, i, j, length, compliance * inv_h2, k)
            }
            Constraint::Limit { i, j, min, max } => {
                let r = sep(x, dim, i, j);
                let len = dot(&r, &r).sqrt();
                if len > max {
                    self.xpbd(x, dim, i, j, max, 0.0, k)
                } else if len < min && len > 0.0 {
                    self.xpbd(x, dim, i, j, min, 0.0, k)
                } else {
                    0.0
                }
            }
            Constraint::Pin { .. } => 0.0,
            Constraint::Plane { normal, offset } => self.plane(x, dim, &normal, offset),
        }
    }

    /// One XPBD update of `|x_i - x_j| = length` with `alpha = compliance / h^2` (0: rigid,
    /// plain PBD): `dl = (-C - alpha l) / (w_i + w_j + alpha)`, `x_i += w_i dl n`,
    /// `x_j -= w_j dl n` (Macklin, Muller, Chentanez 2016, eq. 18). Returns the correction
    /// relative to `length`.
    #[allow(clippy::too_many_arguments)]
    fn xpbd(
        &mut self,
        x: &mut [f64],
        dim: usize,
        i: usize,
        j: Endpoint,
        length: f64,
        alpha: f64,
        k: usize,
    ) -> f64 {
        let wsum = self.w[i] + self.w_of(j);
        let d = sep(x, dim, i, j);
        let r = dot(&d, &d).sqrt();
        if wsum == 0.0 || r == 0.0 {
            return 0.0;
        }
        let c = r - length;
        let dl = (-c - alpha * self.lambda[k]) / (wsum + alpha);
        self.lambda[k] += dl;
        self.apply(x, dim, i, j, dl / r, &d);
        (dl * wsum).abs() / length
    }

    /// Pushes every movable particle behind the plane `normal . x >= offset` onto it;
    /// returns the deepest penetration relative to `1 + |offset|`.
    fn plane(&self, x: &mut [f64], dim: usize, normal: &[f64; 3], offset: f64) -> f64 {
        let mut worst: f64 = 0.0;
        for (p, w) in self.w.iter().enumerate() {
            if *w == 0.0 {
                continue;
            }
            let xp = &mut x[p * dim..(p + 1) * dim];
            let s = xp.iter().zip(normal).map(|(a, b)| a * b).sum::<f64>() - offset;
            if s < 0.0 {
                xp.iter_mut().zip(normal).for_each(|(a, n)| *a -= s * n);
                worst = worst.max(-s / (1.0 + offset.abs()));
            }
        }
        worst
    }

    /// `v += (x - moved) / h`: the velocity the relaxation's position change implies.
    pub fn implied(&self, x: &[f64], v: &mut [f64], inv_h: f64) {
        for ((vi, xi), mi) in v.iter_mut().zip(x).zip(&self.moved) {
            *vi += (xi - mi) * inv_h;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (xorshift64*), uniform in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        }
        fn below(&mut self, n: usize) -> usize {
            (self.next() * n as f64) as usize % n
        }
    }

    /// A world-sized problem: positions, inverse masses and a constraint list mixing runs of
    /// rigid links with anchored, soft, limit, pin and plane constraints, coincident ends,
    /// links at exactly their length and -0.0 coordinates (where only the sign of XPBD's
    /// zero correction tells the two paths apart).
    fn problem(rng: &mut Rng, dim: usize) -> (Vec<f64>, Vec<f64>, Vec<Constraint>) {
        let n = 12;
        let mut x: Vec<f64> = (0..n * dim).map(|_| rng.next() - 0.5).collect();
        for v in x.iter_mut().step_by(3) {
            if rng.next() < 0.2 {
                *v = -0.0;
            }
        }
        x.copy_within(..dim, dim); // particles 0 and 1 coincide
        let inv: Vec<f64> = (0..n).map(|p| if p % 5 == 4 { 0.0 } else { 0.5 + rng.next() }).collect();
        let mut list = Vec::new();
        for _ in 0..40 {
            let i = rng.below(n);
            let j = (i + 1 + rng.below(n - 1)) % n;
            let r = crate::constraints::distance(dim, &x, i, Endpoint::Particle(j));
            let length = match rng.below(3) {
                0 if r > 0.0 => r, // met exactly: C = 0
                _ => 0.05 + rng.next(),
            };
            let mut anchor = [0.0; 3];
            anchor[..dim].iter_mut().for_each(|a| *a = rng.next());
            list.push(match rng.below(12) {
                0 => Constraint::Distance { i, j: Endpoint::Anchor(anchor), length, compliance: 0.0 },
                1 => Constraint::Distance { i, j: Endpoint::Particle(j), length, compliance: 1e-3 },
                2 => Constraint::Limit { i, j: Endpoint::Particle(j), min: 0.1, max: 0.3 },
                3 => Constraint::Pin { i, point: anchor },
                4 => {
                    let mut normal = [0.0; 3];
                    normal[dim - 1] = 1.0;
                    Constraint::Plane { normal, offset: -0.4 }
                }
                5 => Constraint::Distance { i, j: Endpoint::Particle(j), length, compliance: -0.0 },
                _ => Constraint::Distance { i, j: Endpoint::Particle(j), length, compliance: 0.0 },
            });
        }
        list.push(Constraint::Distance { i: 0, j: Endpoint::Particle(1), length: 0.1, compliance: 0.0 });
        (x, inv, list)
    }

    #[test]
    fn packed_links_give_the_general_updates_bits() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut runs = 0;
        for case in 0..600 {
            let dim = 1 + case % 3;
            let mode = if case % 2 == 0 { Mode::Project } else { Mode::Jakobsen };
            let (x0, inv, list) = problem(&mut rng, dim);
            let sweeps = 1 + (case % 7) as u32;
            let (mut packed, mut general) = (Solver::default(), Solver::default());
            general.plan.general_only = true;
            let (mut xa, mut xb) = (x0.clone(), x0.clone());
            for step in 0..3 {
                let ta = packed.positions(&list, sweeps, mode, dim, &mut xa, &inv, 0.01);
                let tb = general.positions(&list, sweeps, mode, dim, &mut xb, &inv, 0.01);
                assert_eq!(ta, tb, "case {case} step {step}: sweeps taken");
                assert_eq!(packed.last_off, general.last_off, "case {case} step {step}");
                let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&xa), bits(&xb), "case {case} step {step}: positions");
                let want = list.iter().map(|c| c.violation(dim, &xa, &|p| inv[p] > 0.0)).fold(0.0, f64::max);
                assert_eq!(packed.left(&list, dim, &xa, &inv).to_bits(), want.to_bits(), "case {case}");
            }
            runs += packed.plan.items.iter().filter(|i| matches!(i, Item::Links { .. })).count();
        }
        assert!(runs > 1000, "the cases exercise the packed runs ({runs})");
    }

    #[test]
    fn a_zero_correction_keeps_xpbds_sign_of_zero() {
        // A link from a static particle at (0, -0) to one at (start, -0): the first sweep
        // meets it exactly (C = 0 on the second) and leaves its multiplier negative (or
        // positive); the second sweep's correction is then XPBD's signed zero, which moves
        // the -0.0 coordinate to +0.0 (or not). The packed update does the same.
        for start in [2.0, 0.5] {
            let list =
                [Constraint::Distance { i: 1, j: Endpoint::Particle(0), length: 1.0, compliance: 0.0 }];
            let x0 = [0.0, -0.0, start, -0.0];
            let (mut packed, mut general) = (Solver::default(), Solver::default());
            general.plan.general_only = true;
            let (mut xa, mut xb) = (x0.to_vec(), x0.to_vec());
            let ta = packed.positions(&list, 4, Mode::Jakobsen, 2, &mut xa, &[0.0, 1.0], 0.01);
            let tb = general.positions(&list, 4, Mode::Jakobsen, 2, &mut xb, &[0.0, 1.0], 0.01);
            assert_eq!((ta, tb), (2, 2), "met on the first sweep, seen met on the second");
            let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&xa), bits(&xb), "start {start}");
        }
    }
}
