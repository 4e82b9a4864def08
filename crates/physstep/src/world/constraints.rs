//! A world's position constraints: adding them, the sweep count, the violation, and the
//! Relax stage of the step (see [`crate::constraints`] for the two solvers).

use super::step::StepContext;
use super::World;
use crate::constraints::{Constraint, Constraints, Mode, MAX_ITERATIONS};
use crate::dynamics::{SecondOrder, System};
use crate::error::{num, Error, Result};
use crate::forces::Endpoint;

impl World {
    /// Adds a constraint (checked against the world's particles; a plane's normal made
    /// unit). Returns its index among the constraints. The state is not moved: the first
    /// step's Relax stage meets it.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the bad field (see [`Constraint::checked`]);
    /// [`Error::Unsupported`] for a world that is a flow. The world is unchanged.
    pub fn add_constraint(&mut self, constraint: Constraint) -> Result<usize> {
        self.refuse_flow("a constraint")?;
        let c = constraint.checked(self.len(), self.dim())?;
        self.constraints.list.push(c);
        self.ids.constraints.push(1);
        Ok(self.constraints.list.len() - 1)
    }

    /// Adds `|x_i - x_j| = length` (m; `None`: the current distance) between particle `i`
    /// and particle or fixed point `j`, rigid (`compliance = 0`) or soft (`compliance` m/N,
    /// XPBD). Returns its index.
    ///
    /// # Errors
    /// As [`World::add_constraint`]; a `None` length where the two ends coincide names
    /// `length` with the distance, 0.
    pub fn add_distance_constraint(
        &mut self,
        i: usize,
        j: Endpoint,
        length: Option<f64>,
        compliance: f64,
    ) -> Result<usize> {
        let length = match length {
            Some(l) => l,
            None => {
                // Checked first, so the distance below reads valid indices.
                Constraint::Distance { i, j, length: 1.0, compliance }.checked(self.len(), self.dim())?;
                let r = crate::constraints::distance(self.dim(), self.positions(), i, j);
                if r == 0.0 || !r.is_finite() {
                    return Err(Error::invalid(
                        "length",
                        num(r),
                        "a finite number > 0 (it defaults to the current distance, and the ends coincide)",
                    ));
                }
                r
            }
        };
        self.add_constraint(Constraint::Distance { i, j, length, compliance })
    }

    /// Holds particle `i` at `point` (`dim` numbers, m). Returns the constraint's index.
    ///
    /// # Errors
    /// As [`World::add_constraint`], and `len(point)` other than `dim`.
    pub fn add_pin(&mut self, i: usize, point: &[f64]) -> Result<usize> {
        let p = self.vector3("point", point)?;
        self.add_constraint(Constraint::Pin { i, point: p })
    }

    /// A rope of `max_length` (m) from particle `i` to particle or point `j`: the distance
    /// may shrink, not grow past it. Returns the constraint's index.
    ///
    /// # Errors
    /// As [`World::add_constraint`].
    pub fn add_rope(&mut self, i: usize, j: Endpoint, max_length: f64) -> Result<usize> {
        self.add_constraint(Constraint::Limit { i, j, min: 0.0, max: max_length })
    }

    /// `min_length <= |x_i - x_j| <= max_length` (m): a joint limit. Returns its index.
    ///
    /// # Errors
    /// As [`World::add_constraint`].
    pub fn add_distance_limit(
        &mut self,
        i: usize,
        j: Endpoint,
        min_length: f64,
        max_length: f64,
    ) -> Result<usize> {
        self.add_constraint(Constraint::Limit { i, j, min: min_length, max: max_length })
    }

    /// The half-space `normal . x >= offset` (m) that every particle is kept in: a ground,
    /// or one wall of a box. `normal` (`dim` numbers, any nonzero length) points into the
    /// allowed side. Returns the constraint's index.
    ///
    /// # Errors
    /// As [`World::add_constraint`], and `len(normal)` other than `dim`.
    pub fn add_plane(&mut self, normal: &[f64], offset: f64) -> Result<usize> {
        let n = self.vector3("normal", normal)?;
        self.add_constraint(Constraint::Plane { normal: n, offset })
    }

    /// `v` (of `dim` numbers) as a 3-vector.
    fn vector3(&self, field: &str, v: &[f64]) -> Result<[f64; 3]> {
        let d = self.dim();
        if v.len() != d {
            return Err(Error::invalid(format!("len({field})"), v.len(), format!("{d}, the world's dim")));
        }
        let mut p = [0.0; 3];
        p[..d].copy_from_slice(v);
        Ok(p)
    }

    /// The constraints and the sweep count.
    #[must_use]
    pub fn constraints(&self) -> &Constraints {
        &self.constraints
    }

    /// Relaxation sweeps per step (default 16): exactly this many for projection, at most
    /// this many for SHAKE/RATTLE (which stop at the tolerance).
    #[must_use]
    pub fn constraint_iterations(&self) -> u32 {
        self.constraints.iterations
    }

    /// Sets the relaxation sweeps per step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `constraint_iterations` outside 1..=1,000,000; the
    /// world is unchanged.
    pub fn set_constraint_iterations(&mut self, iterations: u32) -> Result<()> {
        if !(1..=MAX_ITERATIONS).contains(&iterations) {
            return Err(Error::invalid(
                "constraint_iterations",
                iterations,
                "a whole number from 1 to 1000000",
            ));
        }
        self.constraints.iterations = iterations;
        Ok(())
    }

    /// What the relaxation sweeps did over the world's steps: the last step's sweeps, and
    /// the steps whose sweeps ended at the cap (`constraint_iterations`) with a constraint
    /// still off, with the largest violation they left.
    #[must_use]
    pub fn constraint_stats(&self) -> crate::constraints::SweepStats {
        self.constraints.stats
    }

    /// The largest violation of any constraint at the current positions, m (0 without
    /// constraints): `||x_i - x_j| - L|`, a limit's excess, a pinned particle's distance from
    /// its point, the deepest particle behind a plane. Constraints among static particles
    /// only are not counted (nothing can meet them).
    #[must_use]
    pub fn constraint_violation(&self) -> f64 {
        if self.constraints.is_empty() {
            return 0.0;
        }
        self.constraints.violation(self.dim(), &self.state.y[..self.model.len()], &self.model.inv_mass)
    }

    /// The solver the world's method takes (its [`Info::constraints`]): SHAKE/RATTLE for
    /// velocity Verlet and leapfrog, Jakobsen's projection for Verlet, projection with a
    /// velocity projection for the others.
    ///
    /// [`Info::constraints`]: crate::integrators::Info::constraints
    fn constraint_mode(&self) -> Mode {
        self.integrator.info().constraints
    }

    /// Keeps the positions at the start of the step (SHAKE's gradients), when there are
    /// constraints.
    pub(super) fn keep_start(&mut self) {
        if !self.constraints.is_empty() {
            let n = self.model.len();
            let start = &mut self.constraints.solver.start;
            start.clear();
            start.extend_from_slice(&self.state.y[..n]);
        }
    }

    /// Relax: the positions moved onto the constraints and the velocities given the motion
    /// that implies; then `f = deriv(y)` again. Verlet (Jakobsen): `v += dx / h`, the secant
    /// velocity. Projection: `v += dx / h`, then the velocities projected onto the rigid
    /// constraints' tangent (RATTLE's velocity step). RATTLE (velocity
    /// Verlet, leapfrog): the half-step velocity `v - a h / 2` gets `dx / h`, the final half
    /// kick is taken with the acceleration at the corrected positions, and the velocity is
    /// projected onto the constraints' tangent. A method whose memory carries the velocity
    /// (Verlet's previous positions, leapfrog's half-step velocity) restarts from the relaxed
    /// state, which is exactly Jakobsen's resync (`x_prev = x - v h`). Everything changed here
    /// is in the state or the method's memory, so the step's checkpoint covers it.
    pub(super) fn relax_constraints(&mut self, ctx: &StepContext) -> Result<()> {
        if self.constraints.is_empty() {
            return Ok(());
        }
        let (n, nx, dim) = (self.model.len(), self.nx(), self.dim());
        let mode = self.constraint_mode();
        let Constraints { list, iterations, solver, stats } = &mut self.constraints;
        let (xs, vs) = self.state.y.split_at_mut(nx);
        let (x, v) = (&mut xs[..n], &mut vs[..n]);
        stats.last_sweeps = solver.positions(list, *iterations, mode, dim, x, &self.model.inv_mass, ctx.h);
        if stats.last_sweeps == *iterations && solver.last_off {
            let left = solver.left(list, dim, x, &self.model.inv_mass);
            stats.capped_steps += 1;
            stats.capped_violation = stats.capped_violation.max(left);
        }
        solver.implied(x, v, ctx.inv_h);
        if mode == Mode::Project {
            // A method whose position step is not `x + h v_new` (explicit Euler, RK4, ...)
            // leaves a velocity into the constraints that `dx / h` does not cancel (`g h / 2`
            // for RK4 on a cloth at rest): RATTLE's velocity step removes it.
            solver.tangent(list, *iterations, dim, x, v);
        }
        if mode == Mode::Rattle {
            let a = &self.state.f[nx..nx + n];
            v.iter_mut().zip(a).for_each(|(vi, ai)| *vi -= 0.5 * ctx.h * ai);
        }
        if self.integrator.carries() {
            self.integrator.reset();
        }
        self.refresh_at(ctx.t_end)?;
        if mode == Mode::Rattle {
            let Constraints { list, iterations, solver, .. } = &mut self.constraints;
            let (xs, vs) = self.state.y.split_at_mut(nx);
            let (x, v) = (&xs[..n], &mut vs[..n]);
            let a = &self.state.f[nx..nx + n];
            v.iter_mut().zip(a).for_each(|(vi, ai)| *vi += 0.5 * ctx.h * ai);
            solver.tangent(list, *iterations, dim, x, v);
            // The particles' rate dX is their velocity.
            let (y, f) = (&self.state.y, &mut self.state.f);
            f[..n].copy_from_slice(&y[nx..nx + n]);
            if self.parts().velocity_dependent() {
                self.refresh_at(ctx.t_end)?;
            }
        }
        Ok(())
    }

    /// `f = deriv(t, y)` at time `t` (the end of the step being taken), counted as an
    /// evaluation; a value that runs away is left for the Check stage to name.
    fn refresh_at(&mut self, t: f64) -> Result<()> {
        let mut y = std::mem::take(&mut self.state.y);
        let mut f = std::mem::take(&mut self.state.f);
        self.parts().deriv(t, &y, &mut f);
        std::mem::swap(&mut self.state.y, &mut y);
        std::mem::swap(&mut self.state.f, &mut f);
        self.state.evals += 1;
        self.derivative = super::Derivative::Current;
        match self.model.failure.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

/// `[a, b]` of the first `dim` numbers, as messages show points.
fn shown(p: &[f64], dim: usize) -> String {
    let parts: Vec<String> = p[..dim].iter().map(|v| num(*v)).collect();
    format!("[{}]", parts.join(", "))
}

/// The distance between two points of `dim` numbers.
fn apart(a: &[f64; 3], b: &[f64; 3], dim: usize) -> f64 {
    (0..dim).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

impl World {
    /// What in the constraints cannot be met whatever the sweeps, one line each (empty when
    /// nothing is seen): a particle pinned to two points; two pinned balls closer than their
    /// radii; two opposite planes with no point between them; a pinned particle behind a
    /// plane; a distance or limit between two held ends (pinned, static or an anchor) at a
    /// distance it forbids; a distance whose ends coincide, which no sweep can push apart
    /// (no direction). A check of the constraints in pairs at the current positions, not a
    /// proof: three planes that leave no room between them are not seen.
    #[must_use]
    pub fn constraint_conflicts(&self) -> Vec<String> {
        self.conflicts(None)
    }

    /// [`World::constraint_conflicts`] that involve constraint `k` (the one just added).
    #[must_use]
    pub fn constraint_conflicts_of(&self, k: usize) -> Vec<String> {
        self.conflicts(Some(k))
    }

    fn conflicts(&self, only: Option<usize>) -> Vec<String> {
        let list = &self.constraints.list;
        let (dim, inv) = (self.dim(), &self.model.inv_mass);
        let x = &self.state.y[..self.model.len()];
        let at = |p: usize| {
            let mut q = [0.0; 3];
            q[..dim].copy_from_slice(&x[p * dim..(p + 1) * dim]);
            q
        };
        let wanted = |a: usize, b: usize| only.is_none_or(|k| k == a || k == b);
        let mut out = Vec::new();
        // Pins of movable particles, in order: (constraint, particle, point).
        let pins: Vec<(usize, usize, [f64; 3])> = list
            .iter()
            .enumerate()
            .filter_map(|(k, c)| match *c {
                Constraint::Pin { i, point } if inv[i] > 0.0 => Some((k, i, point)),
                _ => None,
            })
            .collect();
        let scan_pins = only
            .is_none_or(|k| matches!(list.get(k), Some(Constraint::Pin { .. } | Constraint::Plane { .. })));
        if scan_pins {
            for (a, &(ka, pa, qa)) in pins.iter().enumerate() {
                for &(kb, pb, qb) in &pins[a + 1..] {
                    if !wanted(ka, kb) {
                        continue;
                    }
                    let d = apart(&qa, &qb, dim);
                    if pa == pb && d > 0.0 {
                        out.push(format!(
                            "constraints {ka} and {kb} pin particle {pa} to two points, {} and {}",
                            shown(&qa, dim),
                            shown(&qb, dim)
                        ));
                    }
                    let (ra, rb) = (self.balls.radius_of(pa), self.balls.radius_of(pb));
                    if pa != pb && ra > 0.0 && rb > 0.0 && d < ra + rb {
                        out.push(format!(
                            "constraints {ka} and {kb} pin balls {pa} and {pb} {} m apart, closer than their radii add to ({})",
                            num(d),
                            num(ra + rb)
                        ));
                    }
                }
            }
        }
        // The point particle `p` is held at: its pin's, or where it is if static.
        let held = |p: usize| -> Option<[f64; 3]> {
            if inv[p] == 0.0 {
                return Some(at(p));
            }
            pins.iter().find(|(_, q, _)| *q == p).map(|(_, _, point)| *point)
        };
        let movable = inv.iter().any(|w| *w > 0.0);
        for (k, c) in list.iter().enumerate() {
            match *c {
                Constraint::Distance { i, j, .. } | Constraint::Limit { i, j, .. }
                    if only.is_none_or(|o| {
                        let pinned_by = |p: usize| pins.iter().any(|&(kp, q, _)| kp == o && q == p);
                        o == k || pinned_by(i) || matches!(j, Endpoint::Particle(j) if pinned_by(j))
                    }) =>
                {
                    let (lo, hi) = match *c {
                        Constraint::Distance { length, .. } => (length, length),
                        Constraint::Limit { min, max, .. } => (min, max),
                        _ => unreachable!(),
                    };
                    let other = match j {
                        Endpoint::Particle(j) => held(j),
                        Endpoint::Anchor(a) => Some(a),
                    };
                    if let (Some(a), Some(b)) = (held(i), other) {
                        let r = apart(&a, &b, dim);
                        let tol = 1e-12 * hi.max(r);
                        if r < lo - tol || r > hi + tol {
                            let want = if lo == hi {
                                format!("{} m", num(lo))
                            } else {
                                format!("{} to {} m", num(lo), num(hi))
                            };
                            out.push(format!(
                                "constraint {k}: its ends are held {} m apart (pinned, static or an anchor): {want} cannot be met",
                                num(r)
                            ));
                        }
                        continue;
                    }
                    let r = crate::constraints::distance(dim, x, i, j);
                    if r == 0.0 && lo > 0.0 {
                        out.push(format!(
                            "constraint {k}: the ends of a distance of {} m coincide (particle {i} at {}): no sweep can push them apart",
                            num(lo),
                            shown(&at(i), dim)
                        ));
                    }
                }
                Constraint::Plane { normal, offset } if movable => {
                    for (k2, c2) in list.iter().enumerate().skip(k + 1) {
                        let Constraint::Plane { normal: n2, offset: o2 } = *c2 else { continue };
                        let opposite = (0..3).all(|d| (normal[d] + n2[d]).abs() <= 1e-12);
                        let gap = offset + o2;
                        if wanted(k, k2) && opposite && gap > 1e-12 * (1.0 + offset.abs() + o2.abs()) {
                            out.push(format!(
                                "constraints {k} and {k2} are opposite planes with no point between them ({} m apart)",
                                num(gap)
                            ));
                        }
                    }
                    for &(kp, p, q) in &pins {
                        let s = (0..dim).map(|d| normal[d] * q[d]).sum::<f64>() - offset;
                        if wanted(k, kp) && s < -1e-12 * (1.0 + offset.abs()) {
                            out.push(format!(
                                "constraint {kp} pins particle {p} at {}, {} m behind the plane of constraint {k}",
                                shown(&q, dim),
                                num(-s)
                            ));
                        }
                    }
                }
                _ => {}
            }
        }
        out
    }
}
