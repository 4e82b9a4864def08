//! Balls and walls of a [`World`]: adding and reading them, and the Collide stage of the
//! step (see [`crate::collide`] and docs/collisions.md).

use super::step::StepContext;
use super::World;
use crate::collide::{self, CollisionStats, Input, Push, Walls};
use crate::error::{num, Error, Result};

fn point(x: &[f64]) -> String {
    let parts: Vec<String> = x.iter().map(|v| num(*v)).collect();
    format!("[{}]", parts.join(", "))
}

impl World {
    /// Adds one ball: a particle with a radius (forces, methods and the loop apply to it as
    /// to any particle), which collides with the other balls and the walls. Returns its
    /// particle index. `mass = inf` makes it immovable.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `radius` (finite, > 0), `position`, `velocity` or `mass`
    /// as [`World::add_particle`], `position` when the ball would overlap another (touching
    /// is allowed) or stick out of the walls; the world is unchanged.
    pub fn add_ball(&mut self, position: &[f64], velocity: &[f64], radius: f64, mass: f64) -> Result<usize> {
        self.check_ball(position, velocity, radius, mass)?;
        if let Some(w) = &self.balls.walls {
            collide::check_inside("position", position, radius, w)?;
        }
        let d = self.dim();
        for &p in &self.balls.index {
            let (xp, rp) = (&self.state.y[p * d..(p + 1) * d], self.balls.radius[p]);
            let dist = xp.iter().zip(position).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
            // Touching within a rounding (a relative 1e-9, as the resting contacts count
            // it) is touching: a pile at rest written to a scene file reads back.
            if dist < (rp + radius) * (1.0 - 1e-9) {
                return Err(Error::invalid(
                    "position",
                    point(position),
                    format!(
                        "clear of ball {p} at {} (distance {} < radius + {} = {}): balls may not overlap",
                        point(xp),
                        num(dist),
                        num(rp),
                        num(rp + radius)
                    ),
                ));
            }
        }
        let i = self.add_particle(position, velocity, mass, false)?;
        self.mark_ball(i, radius);
        Ok(i)
    }

    /// The checks of [`World::add_ball`] that do not depend on the other balls or walls.
    fn check_ball(&self, position: &[f64], velocity: &[f64], radius: f64, mass: f64) -> Result<()> {
        collide::check_radius("radius", radius)?;
        self.check_particles(position, Some(velocity), Some(&[mass]))?;
        if position.len() != self.dim() {
            return Err(Error::invalid(
                "len(position)",
                position.len(),
                format!("{}, the dimension", self.dim()),
            ));
        }
        Ok(())
    }

    /// [`World::add_ball`] taking the ball where it is: neither its overlap with the other
    /// balls nor the walls are checked. For a world rebuilt from its own structure, the
    /// snapshot then restored onto it (`scenes::file::parse_structure`): a run leaves
    /// touching balls a rounding closer than their radii, which `add_ball` refuses.
    ///
    /// # Errors
    /// As [`World::add_ball`] for `radius`, `position`, `velocity` and `mass` themselves.
    pub(crate) fn add_ball_as_found(
        &mut self,
        position: &[f64],
        velocity: &[f64],
        radius: f64,
        mass: f64,
    ) -> Result<usize> {
        self.check_ball(position, velocity, radius, mass)?;
        let i = self.add_particle(position, velocity, mass, false)?;
        self.mark_ball(i, radius);
        Ok(i)
    }

    /// Adds `k` balls from flat `positions` (`k * dim`), `radii` (`k`), optional `velocities`
    /// and `masses` (as [`World::add_particles`]). Returns the index of the first.
    ///
    /// # Errors
    /// As [`World::add_ball`], naming the first bad entry (`radius[3]`, `position[5]`); the
    /// world is unchanged.
    pub fn add_balls(
        &mut self,
        positions: &[f64],
        velocities: Option<&[f64]>,
        radii: &[f64],
        masses: Option<&[f64]>,
    ) -> Result<usize> {
        self.check_particles(positions, velocities, masses)?;
        let d = self.dim();
        let k = positions.len() / d;
        if radii.len() != k {
            return Err(Error::invalid("len(radius)", radii.len(), format!("{k}, one per ball")));
        }
        for (b, r) in radii.iter().enumerate() {
            collide::check_radius(&format!("radius[{b}]"), *r)?;
            if let Some(w) = &self.balls.walls {
                collide::check_inside(&format!("position[{b}]"), &positions[b * d..(b + 1) * d], *r, w)?;
            }
        }
        let first = self.len();
        let (mut x, mut r) = (Vec::new(), Vec::new());
        for &p in &self.balls.index {
            x.extend_from_slice(&self.state.y[p * d..(p + 1) * d]);
            r.push(self.balls.radius[p]);
        }
        let old = r.len();
        x.extend_from_slice(positions);
        r.extend_from_slice(radii);
        if let Some((i, j, dist)) = collide::first_overlap(&x, d, &r) {
            let who = |s: usize| {
                if s < old {
                    format!("ball {}", self.balls.index[s])
                } else {
                    format!("position[{}]", s - old)
                }
            };
            let field = format!("position[{}]", j - old);
            return Err(Error::invalid(
                field,
                point(&x[j * d..(j + 1) * d]),
                format!(
                    "clear of {} at {} (distance {} < {}): balls may not overlap",
                    who(i),
                    point(&x[i * d..(i + 1) * d]),
                    num(dist),
                    num(r[i] + r[j])
                ),
            ));
        }
        self.add_particles(positions, velocities, masses, false)?;
        for (b, radius) in radii.iter().enumerate() {
            self.mark_ball(first + b, *radius);
        }
        Ok(first)
    }

    /// Checks that the positions `x` (flat, as [`World::set_positions`] takes them) keep
    /// the balls clear of each other and inside the walls, as adding them does; no deeper
    /// overlap than the current state already has is refused (a state a run left, where
    /// touching balls are a rounding closer than their radii, can be set back as it is).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `positions[p]` (`positions[p][k]` for a wall).
    pub(super) fn check_ball_positions(&self, x: &[f64]) -> Result<()> {
        let index = &self.balls.index;
        if index.is_empty() {
            return Ok(());
        }
        let d = self.dim();
        let gather = |src: &[f64]| -> Vec<f64> {
            index.iter().flat_map(|&p| src[p * d..(p + 1) * d].to_vec()).collect()
        };
        let (old, new) = (gather(&self.state.y), gather(x));
        let r: Vec<f64> = index.iter().map(|&p| self.balls.radius[p]).collect();
        let walls = self.balls.walls.as_ref();
        let slack = collide::deepest_overlap(&old, d, &r, walls);
        if let Some(w) = walls {
            for (s, &p) in index.iter().enumerate() {
                collide::check_inside_by(
                    &format!("positions[{p}]"),
                    &new[s * d..(s + 1) * d],
                    r[s],
                    w,
                    slack,
                )?;
            }
        }
        if let (Some((i, j, dist)), _) = collide::overlaps(&new, d, &r, slack) {
            return Err(Error::invalid(
                format!("positions[{}]", index[j]),
                point(&new[j * d..(j + 1) * d]),
                format!(
                    "clear of ball {} at {} (distance {} < radius + {} = {}): balls may not overlap",
                    index[i],
                    point(&new[i * d..(i + 1) * d]),
                    num(dist),
                    num(r[i]),
                    num(r[i] + r[j])
                ),
            ));
        }
        Ok(())
    }

    fn mark_ball(&mut self, p: usize, radius: f64) {
        if self.balls.radius.len() <= p {
            self.balls.radius.resize(p + 1, 0.0);
        }
        self.balls.radius[p] = radius;
        self.balls.index.push(p);
    }

    /// Makes the particles balls of the given radii (`0`: not a ball), one per particle, as
    /// a world rebuilt from its parts needs: the positions are taken as they are (balls that
    /// touch may be closer than the sum of their radii by a rounding, and stay so).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `radius[i]` (0, or finite and > 0) or `len(radius)`; the
    /// world is unchanged.
    pub fn set_radii(&mut self, radii: &[f64]) -> Result<()> {
        if radii.len() != self.len() {
            return Err(Error::invalid(
                "len(radius)",
                radii.len(),
                format!("{}, one per particle", self.len()),
            ));
        }
        for (p, &rp) in radii.iter().enumerate() {
            if rp != 0.0 {
                collide::check_radius(&format!("radius[{p}]"), rp)?;
            }
        }
        self.balls.radius = radii.to_vec();
        self.balls.index = (0..radii.len()).filter(|p| radii[*p] != 0.0).collect();
        // The warm starts name slots, which this renumbers.
        self.balls.warm.clear();
        Ok(())
    }

    /// Puts the balls in an axis-aligned box `lo`..`hi` (`dim` entries each), replacing any
    /// walls before.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `lo`, `hi` (`hi[k] > lo[k]`, finite) or a ball already
    /// outside the box; the world is unchanged.
    pub fn add_walls(&mut self, lo: &[f64], hi: &[f64]) -> Result<()> {
        self.refuse_flow("walls")?;
        let w = collide::check_walls(lo, hi, self.dim())?;
        let d = self.dim();
        for &p in &self.balls.index {
            collide::check_inside(
                &format!("position of ball {p}"),
                &self.state.y[p * d..(p + 1) * d],
                self.balls.radius[p],
                &w,
            )?;
        }
        self.balls.walls = Some(w);
        Ok(())
    }

    /// [`World::add_walls`] leaving the balls where they are (a ball resting on a wall is a
    /// rounding past it after a run): for a world rebuilt from its own structure, as
    /// [`World::add_ball_as_found`].
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `lo` or `hi`, as [`World::add_walls`].
    pub(crate) fn add_walls_as_found(&mut self, lo: &[f64], hi: &[f64]) -> Result<()> {
        self.refuse_flow("walls")?;
        self.balls.walls = Some(collide::check_walls(lo, hi, self.dim())?);
        Ok(())
    }

    /// Sets the coefficient of restitution of every contact: 1 elastic (kinetic energy kept),
    /// 0 the normal velocity absorbed.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `restitution` outside [0, 1].
    pub fn set_restitution(&mut self, e: f64) -> Result<()> {
        if !(0.0..=1.0).contains(&e) {
            return Err(Error::invalid("restitution", num(e), "between 0 and 1 (1: elastic)"));
        }
        self.balls.restitution = e;
        Ok(())
    }

    /// The coefficient of restitution.
    #[must_use]
    pub fn restitution(&self) -> f64 {
        self.balls.restitution
    }

    /// The radius of every particle, m (0 for a particle that is not a ball).
    #[must_use]
    pub fn radii(&self) -> Vec<f64> {
        (0..self.len()).map(|p| self.balls.radius_of(p)).collect()
    }

    /// The walls, if any.
    #[must_use]
    pub fn walls(&self) -> Option<Walls> {
        self.balls.walls
    }

    /// Number of balls.
    #[must_use]
    pub fn ball_count(&self) -> usize {
        self.balls.index.len()
    }

    /// What the contacts came to: count, deepest overlap, pairs tested.
    #[must_use]
    pub fn collisions(&self) -> CollisionStats {
        self.balls.stats
    }

    /// The first particle of the balls when they are consecutive particles (the Collide
    /// stage then reads them in place), else `None` (it gathers them by slot).
    fn balls_run(&self) -> Option<usize> {
        let idx = &self.balls.index;
        let first = *idx.first()?;
        (idx[idx.len() - 1] - first + 1 == idx.len()).then_some(first)
    }

    /// Before a step: the start-of-step positions and velocities of the balls (the Collide
    /// stage reads them).
    pub(super) fn balls_begin(&mut self) {
        if self.balls.is_empty() {
            return;
        }
        let (d, nx, run) = (self.dim(), self.nx(), self.balls_run());
        let b = &mut self.balls;
        let s = &mut b.scratch;
        s.x0.clear();
        s.v0.clear();
        if let Some(p0) = run {
            let len = b.index.len() * d;
            s.x0.extend_from_slice(&self.state.y[p0 * d..p0 * d + len]);
            s.v0.extend_from_slice(&self.state.y[nx + p0 * d..nx + p0 * d + len]);
            return;
        }
        for &p in &b.index {
            s.x0.extend_from_slice(&self.state.y[p * d..(p + 1) * d]);
            s.v0.extend_from_slice(&self.state.y[nx + p * d..nx + (p + 1) * d]);
        }
    }

    /// The Collide stage: every contact of the step resolved at its time of impact; then the
    /// derivative evaluated again (f = deriv(y)) and the method's memory resynchronised for
    /// the balls that were hit (Verlet's previous positions `x - v h`, leapfrog's half-step
    /// velocities moved by the same impulse). Balls that are consecutive particles are read
    /// in place (no copy of the state).
    pub(super) fn collide_balls(&mut self, ctx: &StepContext) -> Result<()> {
        if self.balls.is_empty() {
            return Ok(());
        }
        let (d, nx, nb, run) = (self.dim(), self.nx(), self.balls.index.len(), self.balls_run());
        let name = self.integrator.info().name;
        let b = &mut self.balls;
        let y = &mut self.state.y;
        if run.is_none() {
            b.x1.clear();
            b.v1.clear();
            for &p in &b.index {
                b.x1.extend_from_slice(&y[p * d..(p + 1) * d]);
                b.v1.extend_from_slice(&y[nx + p * d..nx + (p + 1) * d]);
            }
        }
        let p0 = run.unwrap_or(0);
        // Radii and inverse masses by slot: slices of the particles' when the balls are
        // consecutive (and every particle has a radius entry), else gathered.
        let in_place = run.is_some() && b.radius.len() >= p0 + nb;
        if !in_place {
            b.slot_radius.clear();
            b.slot_inv_mass.clear();
            for &p in &b.index {
                b.slot_radius.push(b.radius[p]);
                b.slot_inv_mass.push(self.model.inv_mass[p]);
            }
        }
        let (radius, inv_mass) = if in_place {
            (&b.radius[p0..p0 + nb], &self.model.inv_mass[p0..p0 + nb])
        } else {
            (&b.slot_radius[..], &b.slot_inv_mass[..])
        };
        let (x1, v1) = if run.is_some() {
            (&y[p0 * d..(p0 + nb) * d], &y[nx + p0 * d..nx + (p0 + nb) * d])
        } else {
            (&b.x1[..], &b.v1[..])
        };
        let inp = Input { d, h: ctx.h, e: b.restitution, radius, inv_mass, walls: b.walls.as_ref(), x1, v1 };
        let out = b.scratch.resolve(&inp, &mut b.warm).map_err(|contacts| Error::Contacts {
            method: name.into(),
            step: ctx.step,
            t: ctx.t,
            contacts,
        })?;
        b.stats.count += out.contacts;
        b.stats.pair_tests += out.tests;
        let s = &b.scratch;
        // The overlaps at the end of the step before (its positions are this step's start),
        // measured by the scan; those at the end of a call's last step measured now.
        let mut depth = s.start_overlap;
        if ctx.last {
            depth = depth.max(s.overlap(&inp));
        }
        b.stats.max_overlap = b.stats.max_overlap.max(depth);
        if out.contacts == 0 {
            return Ok(());
        }
        // The end of the hit balls' new paths, and their velocities, written back; their
        // velocities before the stage kept (leapfrog's memory moves by the same impulse).
        b.v1.resize(nb * d, 0.0);
        for &slot in s.touched() {
            let slot = slot as usize;
            let p = run.map_or_else(|| b.index[slot], |p0| p0 + slot);
            for k in 0..d {
                let (x, v) = s.end(slot, k, d);
                b.v1[slot * d + k] = y[nx + p * d + k];
                y[p * d + k] = x;
                y[nx + p * d + k] = v;
            }
        }
        self.resync_memory(ctx.h);
        self.refresh_hits()
    }

    /// After the contacts, the derivative `f = deriv(y)` again: only the entries of the balls
    /// that were hit when each particle's acceleration depends on its own state alone (every
    /// force per particle: gravity, drag, central gravity, springs to anchors; no user force,
    /// no bodies), the same bits as the whole evaluation; else the whole.
    fn refresh_hits(&mut self) -> Result<()> {
        let local = self.model.forces.local();
        if !(local.all && self.model.user.is_empty() && self.bodies.is_empty() && self.flow.is_none()) {
            self.derivative = super::Derivative::Stale;
            return self.refresh();
        }
        let (d, nx, run) = (self.dim(), self.nx(), self.balls_run());
        let (y, f) = (&self.state.y, &mut self.state.f);
        let mut finite = true;
        for &slot in self.balls.scratch.touched() {
            let p = run.map_or_else(|| self.balls.index[slot as usize], |p0| p0 + slot as usize);
            let (i, im) = (p * d..(p + 1) * d, &self.model.inv_mass[p..=p]);
            let springs = local.anchors(p, p + 1);
            f[i.clone()].copy_from_slice(&y[nx + i.start..nx + i.end]);
            let (x, v, a) = (&y[i.clone()], &y[nx + i.start..nx + i.end], &mut f[nx + i.start..nx + i.end]);
            match d {
                1 => local.accel::<1>(p, x, v, im, springs, a),
                2 => local.accel::<2>(p, x, v, im, springs, a),
                _ => local.accel::<3>(p, x, v, im, springs, a),
            }
            finite &= !crate::limits::any_runaway(a);
        }
        if !finite {
            // The whole evaluation names the entry and the value.
            self.derivative = super::Derivative::Stale;
            return self.refresh();
        }
        self.state.evals += 1;
        Ok(())
    }

    /// The method's memory after the balls that were hit changed velocity: each hit ball's
    /// coordinates handed to [`Method::velocities_changed`](crate::integrators::Method::velocities_changed)
    /// (Verlet's previous positions `x - v h`, leapfrog's half-step velocities moved by the
    /// same impulse; nothing for a method without memory).
    fn resync_memory(&mut self, h: f64) {
        if !self.integrator.carries() {
            return;
        }
        let (d, nx) = (self.dim(), self.nx());
        let (b, y) = (&self.balls, &self.state.y);
        for &slot in b.scratch.touched() {
            let (slot, p) = (slot as usize, b.index[slot as usize]);
            let i = p * d..(p + 1) * d;
            let (x, v) = (&y[i.clone()], &y[nx + i.start..nx + i.end]);
            self.integrator.velocities_changed(i.start, x, v, &b.v1[slot * d..(slot + 1) * d], h);
        }
    }
}

/// Entries of [`World::balls_block`] before the radii.
const BLOCK_HEAD: usize = 11;

impl World {
    /// What a snapshot and the state hash hold of the balls (nothing in a world without):
    /// restitution, whether there are walls, their corners (3 + 3), the contact statistics
    /// (count, deepest overlap, pairs tested), every particle's radius, then the resting
    /// contacts' warm starts ([`Push::block`]: nothing when there are none).
    pub(super) fn balls_block(&self) -> Vec<f64> {
        if self.balls.is_empty() {
            return Vec::new();
        }
        let b = &self.balls;
        let w = b.walls.unwrap_or(Walls { lo: [0.0; 3], hi: [0.0; 3] });
        let mut out = vec![b.restitution, f64::from(u8::from(b.walls.is_some()))];
        out.extend_from_slice(&w.lo);
        out.extend_from_slice(&w.hi);
        let s = b.stats;
        out.extend([s.count as f64, s.max_overlap, s.pair_tests as f64]);
        out.extend(self.radii());
        out.extend(Push::block(&b.warm));
        out
    }

    /// The length of [`World::balls_block`] without its warm starts.
    pub(super) fn balls_block_fixed(&self) -> usize {
        if self.balls.is_empty() {
            0
        } else {
            BLOCK_HEAD + self.len()
        }
    }

    /// Checks a snapshot's balls block against this world's (`ours`): the same radii, walls
    /// and restitution; returns the statistics and warm starts to restore.
    ///
    /// # Errors
    /// [`crate::Error::Corrupt`] when they differ.
    pub(super) fn balls_check(
        &self,
        theirs: &[f64],
        ours: &[f64],
    ) -> Result<Option<(CollisionStats, Vec<Push>)>> {
        if ours.is_empty() {
            return Ok(None);
        }
        let fixed = self.balls_block_fixed();
        let same = theirs.len() >= fixed
            && theirs[..BLOCK_HEAD - 3].iter().zip(ours).all(|(a, b)| a.to_bits() == b.to_bits())
            && theirs[BLOCK_HEAD..fixed]
                .iter()
                .zip(&ours[BLOCK_HEAD..fixed])
                .all(|(a, b)| a.to_bits() == b.to_bits());
        if !same {
            return Err(Error::Corrupt {
                reason: "the snapshot's balls (radii, walls or restitution) differ from this world's".into(),
            });
        }
        let [count, depth, tests] = [theirs[8], theirs[9], theirs[10]];
        let whole = |v: f64| v.fract() == 0.0 && (0.0..=9.0e15).contains(&v);
        if !(whole(count) && whole(tests) && depth.is_finite() && depth >= 0.0) {
            return Err(Error::Corrupt { reason: "contact statistics out of range".into() });
        }
        let warm = Push::from_block(&theirs[fixed..], self.balls.index.len(), self.dim())
            .map_err(|reason| Error::Corrupt { reason })?;
        Ok(Some((CollisionStats { count: count as u64, max_overlap: depth, pair_tests: tests as u64 }, warm)))
    }
}
