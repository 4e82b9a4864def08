//! Snapshots, restores, state hashes and the phase vector of a [`World`].
//!
//! A snapshot is `MAGIC`, five little-endian words (dim, particles, method-name length,
//! steps, evaluations), the method name, then f64s: time, the clock's balance (two), the
//! epoch (time, steps, dt), the memory length, `[x; v]`, the integrator's memory, the
//! previous positions and the static mask (1 for a static particle); in a world with balls
//! their block ([`World::balls_block`]: restitution, walls, contact statistics, radii, the
//! resting contacts' warm starts); with
//! constraints, their fingerprint (a u64); once an entity was removed, its ids' fingerprint
//! (a u64, `ids.rs`); and last an FNV-1a checksum of everything before
//! it. [`World::restore`] checks all of it before it changes
//! anything.

use super::{Epoch, World};
use crate::dynamics::SecondOrder;
use crate::error::{Error, Result};

const MAGIC: &[u8; 8] = b"PHSTEP02";
/// Steps are counted exactly as f64 integers up to this (time is `t0 + k dt`).
const MAX_STEPS: u64 = 1 << 53;

/// FNV-1a over `bytes`, continuing from `h`.
fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

fn corrupt(reason: impl Into<String>) -> Error {
    Error::Corrupt { reason: reason.into() }
}

impl World {
    /// The whole dynamic state as bytes: time, steps, positions, velocities, the
    /// integrator's memory, the clock's accumulator and a checksum. [`World::restore`] puts
    /// it back bitwise, so a restored run continues exactly as an uninterrupted one.
    #[must_use]
    pub fn snapshot(&self) -> Vec<u8> {
        let memory = self.integrator.memory();
        let mut out = Vec::with_capacity(80 + 8 * (2 * self.state.y.len() + memory.len()));
        out.extend_from_slice(MAGIC);
        let name = self.integrator.info().name.as_bytes();
        for word in
            [self.dim() as u64, self.len() as u64, name.len() as u64, self.state.steps, self.state.evals]
        {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out.extend_from_slice(name);
        let [hi, lo] = self.clock.balance();
        // Before the first step (or after particles were added) there are no previous
        // positions of this particle count; the current ones interpolate the same way.
        let prev_x = if self.prev_x.len() == self.coords() { &self.prev_x[..] } else { self.positions() };
        let e = self.epoch;
        let mask = self.model.inv_mass.iter().map(|w| if *w == 0.0 { 1.0 } else { 0.0 });
        for v in [self.state.t, hi, lo, e.t, e.steps as f64, e.dt, memory.len() as f64]
            .into_iter()
            .chain(self.state.y.iter().copied())
            .chain(memory.iter().copied())
            .chain(prev_x.iter().copied())
            .chain(mask)
            .chain(self.balls_block())
        {
            out.extend_from_slice(&v.to_le_bytes());
        }
        // A world with solids: their block, then its length.
        if !self.solids.is_empty() {
            let block = self.solids.block();
            for v in block.iter().chain([&(block.len() as f64)]) {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        // A world with constraints ends with their fingerprint: a restore checks it.
        if !self.constraints.is_empty() {
            out.extend_from_slice(&self.constraints.fingerprint().to_le_bytes());
        }
        // A world that removed an entity ends with its ids' fingerprint: a restore checks it.
        if let Some(print) = self.ids.fingerprint() {
            out.extend_from_slice(&print.to_le_bytes());
        }
        let sum = fnv1a(FNV_START, &out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Restores a [`World::snapshot`] of this world (same dimensions, particles, static
    /// particles and method).
    ///
    /// # Errors
    /// [`Error::Corrupt`] when the bytes are not such a snapshot: a bad checksum, another
    /// layout or method, a static mask that differs, a non-finite value, a step count or
    /// epoch that does not add up, integrator memory that does not fit. The world is then
    /// unchanged.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<()> {
        let body = bytes
            .strip_prefix(MAGIC.as_slice())
            .ok_or_else(|| corrupt("not a physstep snapshot (or one of another version)"))?;
        if body.len() < 48 {
            return Err(corrupt("truncated"));
        }
        let (body, sum) = body.split_at(body.len() - 8);
        let sum = u64::from_le_bytes(sum.try_into().map_err(|_| corrupt("truncated"))?);
        if fnv1a(fnv1a(FNV_START, MAGIC), body) != sum {
            return Err(corrupt("checksum mismatch: the bytes were damaged or edited"));
        }
        let body = self.ids_checked(body)?;
        let body = self.constraints_checked(body)?;
        let (body, solids) = self.solids_split(body)?;
        let word = |i: usize| -> Result<u64> {
            body.get(i * 8..i * 8 + 8)
                .map(|b| u64::from_le_bytes(b.try_into().unwrap_or_default()))
                .ok_or_else(|| corrupt("truncated header"))
        };
        let (dim, n, name_len, steps, evals) = (word(0)?, word(1)?, word(2)?, word(3)?, word(4)?);
        if dim != self.dim() as u64 || n != self.len() as u64 {
            return Err(corrupt(format!(
                "snapshot has {n} particles in {dim}D, this world {} in {}D",
                self.len(),
                self.dim()
            )));
        }
        let rest = &body[40..];
        let name_len = usize::try_from(name_len).map_err(|_| corrupt("bad method name"))?;
        let name = rest.get(..name_len).ok_or_else(|| corrupt("truncated method name"))?;
        if name != self.integrator.info().name.as_bytes() {
            return Err(corrupt(format!(
                "snapshot was taken with method '{}', this world uses '{}'",
                crate::error::one_line(&String::from_utf8_lossy(name)),
                self.integrator.info().name
            )));
        }
        let rest = &rest[name_len..];
        if rest.len() % 8 != 0 {
            return Err(corrupt("truncated data"));
        }
        let floats: Vec<f64> =
            rest.chunks_exact(8).map(|c| f64::from_le_bytes(c.try_into().unwrap_or_default())).collect();
        let nx = self.coords();
        let ny = self.state.y.len();
        let np = self.len();
        let [t, hi, lo, et, es, edt, nm, data @ ..] = floats.as_slice() else {
            return Err(corrupt("truncated data"));
        };
        // The memory length is what is left after the state, the previous positions, the mask
        // and the balls' block, whose warm starts vary in number: the stored length must
        // agree with what is left without them, or leave room for them (a damaged one, huge
        // or NaN, must not overflow).
        let ours = self.balls_block();
        let room = data.len().checked_sub(ny + nx + np + self.balls_block_fixed());
        let nm = room
            .filter(|&m| *nm >= 0.0 && *nm <= m as f64 && nm.fract() == 0.0)
            .map(|_| *nm as usize)
            .filter(|&m| self.balls_block_fixed() > 0 || Some(m) == room)
            .ok_or_else(|| corrupt("data length does not match the world"))?;
        let (y, rest) = data.split_at(ny);
        let (memory, rest) = rest.split_at(nm);
        let (prev_x, rest) = rest.split_at(nx);
        let (mask, balls) = rest.split_at(np);
        let stats = self.balls_check(balls, &ours)?;
        for (what, v) in [("time", t), ("accumulator", hi), ("accumulator", lo), ("epoch time", et)] {
            if !v.is_finite() {
                return Err(corrupt(format!("{what} is {v}")));
            }
        }
        if let Some(i) = y.iter().chain(prev_x).position(|v| !v.is_finite()) {
            return Err(corrupt(format!("state entry {i} is not finite")));
        }
        if steps > MAX_STEPS {
            return Err(corrupt(format!("step count {steps} is more than 2^53")));
        }
        if !(es.fract() == 0.0 && *es >= 0.0 && *es <= steps as f64) {
            return Err(corrupt(format!("epoch step {es} is not a step count <= {steps}")));
        }
        if !(*edt == 0.0 || (edt.is_finite() && *edt > 0.0)) {
            return Err(corrupt(format!("epoch dt = {edt}")));
        }
        let epoch = Epoch { t: *et, steps: *es as u64, dt: *edt };
        if epoch.time(steps) != Some(*t) {
            return Err(corrupt(format!("time {t} does not follow from the epoch and {steps} steps")));
        }
        for (p, (flag, w)) in mask.iter().zip(&self.model.inv_mass).enumerate() {
            if *flag != f64::from(u8::from(*w == 0.0)) {
                return Err(corrupt(format!(
                    "particle {p} is {} in the snapshot, {} in this world",
                    if *flag == 1.0 { "static" } else { "dynamic" },
                    if *w == 0.0 { "static" } else { "dynamic" }
                )));
            }
            let v = &y[self.nx() + p * self.dim()..self.nx() + (p + 1) * self.dim()];
            if *w == 0.0 && v.iter().any(|c| *c != 0.0) {
                return Err(corrupt(format!("static particle {p} has a velocity")));
            }
        }
        let mut integrator = self.integrator.clone();
        integrator.recall(memory, self.layout().sizes(ny))?;
        let mut solid_set = self.solids.clone();
        if let Some(block) = &solids {
            solid_set.set_block(block).map_err(corrupt)?;
        }
        // Everything checked: commit.
        self.solids = solid_set;
        self.integrator = integrator;
        self.state.t = *t;
        self.epoch = epoch;
        self.state.steps = steps;
        self.state.evals = evals;
        self.state.y.copy_from_slice(y);
        self.prev_x = prev_x.to_vec();
        // (The bodies' and solids' poses before the frame's last step are not in a snapshot:
        // they are drawn as they are until the next frame.)
        self.prev_q.clear();
        self.prev_solids.clear();
        self.clock.restore_balance([*hi, *lo]);
        if let Some((stats, warm)) = stats {
            self.balls.stats = stats;
            self.balls.warm = warm;
        }
        // The derivative is a function of the state: recompute it without counting it, so
        // the evaluation count matches an uninterrupted run.
        self.derivative = super::Derivative::Stale;
        let r = self.refresh();
        self.state.evals = evals;
        r
    }

    /// `body` without the solids' block at its end, and the block, when the world has solids.
    fn solids_split<'a>(&self, body: &'a [u8]) -> Result<(&'a [u8], Option<Vec<f64>>)> {
        if self.solids.is_empty() {
            return Ok((body, None));
        }
        let f = |b: &[u8]| f64::from_le_bytes(b.try_into().unwrap_or_default());
        let split = body.len().checked_sub(8).ok_or_else(|| corrupt("truncated"))?;
        let len = f(&body[split..]);
        let bytes = (len >= 0.0 && len.fract() == 0.0 && len < 1e15).then(|| len as usize * 8);
        let start = bytes.and_then(|b| split.checked_sub(b)).ok_or_else(|| {
            corrupt("the solids' block does not fit (a snapshot of a world without solids?)")
        })?;
        let block = body[start..split].chunks_exact(8).map(f).collect();
        Ok((&body[..start], Some(block)))
    }

    /// `body` without its trailing ids' fingerprint, which must be this world's, when this
    /// world removed an entity (its ids are no longer `0..n`).
    fn ids_checked<'a>(&self, body: &'a [u8]) -> Result<&'a [u8]> {
        let Some(ours) = self.ids.fingerprint() else {
            return Ok(body);
        };
        let split = body.len().checked_sub(8).ok_or_else(|| corrupt("truncated"))?;
        let (rest, tail) = body.split_at(split);
        if u64::from_le_bytes(tail.try_into().map_err(|_| corrupt("truncated"))?) != ours {
            return Err(corrupt(
                "the snapshot was taken with other particles, bodies or constraints than this world's (one was removed or added since): a snapshot restores only into a world with the same entities",
            ));
        }
        Ok(rest)
    }

    /// `body` without its trailing constraint fingerprint, which must be this world's, when
    /// the world has constraints.
    fn constraints_checked<'a>(&self, body: &'a [u8]) -> Result<&'a [u8]> {
        if self.constraints.is_empty() {
            return Ok(body);
        }
        let split = body.len().checked_sub(8).ok_or_else(|| corrupt("truncated"))?;
        let (rest, tail) = body.split_at(split);
        let print = u64::from_le_bytes(tail.try_into().map_err(|_| corrupt("truncated"))?);
        if print != self.constraints.fingerprint() {
            return Err(corrupt(
                "the snapshot was taken with other constraints (or none) than this world's: restore it into a world built with the same constraints and constraint_iterations",
            ));
        }
        Ok(rest)
    }

    /// A 64-bit hash of the dynamic state (time, positions, velocities, integrator memory,
    /// the constraints with their sweep count when there are any, the solids' drag and
    /// springs when there are any):
    /// equal for bitwise-equal states, different after any change.
    #[must_use]
    pub fn state_hash(&self) -> u64 {
        let mut h = FNV_START;
        let mut eat = |v: f64| h = fnv1a(h, &v.to_bits().to_le_bytes());
        eat(self.state.t);
        self.state.y.iter().for_each(|v| eat(*v));
        self.integrator.memory().iter().for_each(|v| eat(*v));
        self.balls_block().iter().for_each(|v| eat(*v));
        self.solids.block().iter().for_each(|v| eat(*v));
        // The solids' drag and springs shape every later step (none: the hash as before).
        if let Some(print) = self.solids.forces_fingerprint() {
            h = fnv1a(h, &print.to_le_bytes());
        }
        // Constraints shape every later step: a world with others is another world (none
        // leave the hash as it was before they existed).
        if !self.constraints.is_empty() {
            h = fnv1a(h, &self.constraints.fingerprint().to_le_bytes());
        }
        // The entities' ids once one was removed (never: the hash as before ids existed).
        if let Some(print) = self.ids.fingerprint() {
            h = fnv1a(h, &print.to_le_bytes());
        }
        h
    }

    /// The vector the step map acts on: `[x; v]` followed by the vector part of the
    /// integrator's memory (Verlet's previous positions, leapfrog's half-step velocities;
    /// nothing for the other methods, or before a stateful method's first step). A
    /// linearisation of the step (the lab's amplification matrix) perturbs all of it.
    #[must_use]
    pub fn phase(&self) -> Vec<f64> {
        let mut z = self.state.y.clone();
        z.extend_from_slice(&self.integrator.memory()[self.memory_flags()..]);
        z
    }

    /// Sets what [`World::phase`] returns, keeping the integrator's flags and step size (it is
    /// not restarted, unlike after [`World::set_positions`]).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `phase` for a wrong length or a non-finite entry, or a
    /// static particle given a velocity; the world is unchanged.
    pub fn set_phase(&mut self, z: &[f64]) -> Result<()> {
        let ny = self.state.y.len();
        let mut memory = self.integrator.memory();
        let flags = self.memory_flags();
        let want = ny + memory.len() - flags;
        if z.len() != want {
            return Err(Error::invalid("len(phase)", z.len(), format!("{want}")));
        }
        crate::error::all_finite("phase", z)?;
        let (np, nx) = (self.model.len(), self.nx());
        let d = self.dim();
        if let Some(i) = (0..np).find(|&i| self.model.inv_mass[i / d] == 0.0 && z[nx + i] != 0.0) {
            return Err(Error::invalid(
                format!("phase[{}]", nx + i),
                z[nx + i],
                "0 (the velocity of a static particle)",
            ));
        }
        memory[flags..].copy_from_slice(&z[ny..]);
        self.integrator.recall(&memory, self.layout().sizes(ny))?;
        self.state.y.copy_from_slice(&z[..ny]);
        self.derivative = super::Derivative::Stale;
        self.refresh()
    }

    fn memory_flags(&self) -> usize {
        self.integrator.memory_flags().min(self.integrator.memory().len())
    }
}
