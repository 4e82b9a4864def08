//! Recording a run: the rows of `(t, x, v, a, energy)` that `simulate`, the command line and
//! the lab read, taken every `every` steps of a [`World`].
//!
//! A [`Recorder`] is driven in slices ([`Recorder::run`] takes at most a given number of
//! steps), so a caller can look up between slices (the Python face checks for Ctrl-C there)
//! without the recording loop living in the bindings.

use crate::error::{Error, Result};
use crate::integrators::StageLog;
use crate::world::World;

/// Most values one recording may hold (t, x, v, a and energy of every row): 4 GB of f64.
pub const MAX_RECORDED: u64 = 500_000_000;
/// Most steps one recording may take.
pub const MAX_STEPS: f64 = 1e9;

/// One recorded evaluation point inside a step: step index, stage name, t, x, v, a.
pub type StageRow = (u64, &'static str, f64, Vec<f64>, Vec<f64>, Vec<f64>);

/// What a run recorded.
#[derive(Debug, Clone, Default)]
pub struct Recording {
    /// Times of the rows, s.
    pub t: Vec<f64>,
    /// Positions, row-major (rows x coordinates).
    pub x: Vec<f64>,
    /// Velocities, row-major.
    pub v: Vec<f64>,
    /// Accelerations, row-major.
    pub a: Vec<f64>,
    /// Energy of every row, J; empty when the energy is unknown (a user force without a
    /// potential).
    pub energy: Vec<f64>,
    /// Kinetic energy of every row, J (the scale of the energy error where the total energy
    /// is near zero); empty when the recorder deferred it ([`Recorder::deferring_kinetic`]).
    pub kinetic: Vec<f64>,
    /// Total angular momentum about the origin of every row (3 per row), kg m^2/s, where
    /// the world has rigid bodies; empty otherwise.
    pub angular_momentum: Vec<f64>,
    /// Every body's angular velocity in its principal frame (3 per body per row), rad/s,
    /// where the world has rigid bodies: the tennis-racket flips are seen here.
    pub body_spin: Vec<f64>,
    /// The intermediate evaluation points, when asked for.
    pub stages: Vec<StageRow>,
    /// The failure that ended the run early (with `stop_on_diverge`).
    pub diverged: Option<Error>,
    /// Force evaluations made by the steps (not the initial one).
    pub evals: u64,
}

/// How to record a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordParams {
    /// Step, s.
    pub dt: f64,
    /// End time, s: the run takes `until / dt` steps, rounded down (a quotient within 1e-9
    /// of a whole number counts as that number).
    pub until: f64,
    /// One row every this many steps (the last step is always recorded).
    pub every: u64,
    /// Record the intermediate evaluation points of each step.
    pub stages: bool,
    /// End the run at a failed step and report it in [`Recording::diverged`] instead of
    /// returning the error.
    pub stop_on_diverge: bool,
}

/// Steps of `dt` that fit in `until` (rounded down, forgiving the rounding of a quotient that
/// should be whole).
///
/// # Errors
/// [`Error::InvalidValue`] naming `until` when it is not a finite number >= 0 or asks for
/// more than 1e9 steps.
pub(crate) fn steps_until(dt: f64, until: f64) -> Result<u64> {
    if !(until.is_finite() && until >= 0.0) {
        return Err(Error::invalid("until", until, "a finite number >= 0"));
    }
    crate::error::positive("dt", dt)?;
    let ratio = until / dt;
    let steps =
        if (ratio - ratio.round()).abs() <= 1e-9 * ratio.max(1.0) { ratio.round() } else { ratio.floor() };
    if steps.is_nan() || steps > MAX_STEPS {
        return Err(Error::invalid(
            "until",
            until,
            format!("at most 1e9 steps of dt = {dt} (until / dt = {ratio:e})"),
        ));
    }
    Ok(steps as u64)
}

/// Drives a [`World`] through a recorded run, in slices.
#[derive(Debug)]
pub struct Recorder {
    params: RecordParams,
    steps: u64,
    next: u64,
    /// The world's steps when the recording started.
    steps0: u64,
    evals0: u64,
    done: bool,
    log: StageLog,
    rec: Recording,
    /// Where the kinetic energies of the rows go while the energies are computed when the
    /// recording defers them (a scratch column, reused), else `None`.
    deferred: Option<Vec<f64>>,
}

impl Recorder {
    /// Starts a recording of `world` and records its first row.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `until`, `dt` or `every` for a run that is malformed or
    /// would not fit in memory (refused before anything is allocated).
    pub fn new(world: &mut World, params: RecordParams) -> Result<Self> {
        Self::start(world, params, false)
    }

    /// [`Recorder::new`] that leaves [`Recording::kinetic`] empty in a world of particles
    /// alone (no bodies, not a flow), for a caller that computes it only if it is read: row
    /// by row from the recorded velocities with [`crate::world::Model::kinetic`], the same
    /// bits. The energies are recorded as before (the kinetic energy of each row is
    /// computed for them, not kept). Elsewhere the same as [`Recorder::new`].
    ///
    /// # Errors
    /// As [`Recorder::new`].
    pub fn deferring_kinetic(world: &mut World, params: RecordParams) -> Result<Self> {
        let particles_alone = world.bodies().is_empty() && world.flow().is_none();
        Self::start(world, params, particles_alone)
    }

    fn start(world: &mut World, params: RecordParams, defer: bool) -> Result<Self> {
        let steps = steps_until(params.dt, params.until)?;
        if params.every == 0 {
            return Err(Error::invalid("every", 0, "at least 1"));
        }
        let n = world.positions().len() as u64;
        let rows = steps / params.every + 2;
        let nb = world.bodies().len() as u64;
        let per_row = 3 * n + 2 + if nb > 0 { 3 + 3 * nb } else { 0 };
        let values = rows.saturating_mul(per_row);
        if values > MAX_RECORDED {
            let (field, value) = if params.every == 1 {
                ("until", params.until.to_string())
            } else {
                ("every", params.every.to_string())
            };
            return Err(Error::invalid(
                field,
                value,
                format!(
                    "such that the recording fits in memory: {rows} rows of {n} coordinates would be \
                     {values} values (more than {MAX_RECORDED}); record fewer rows (a larger every) or \
                     a shorter run"
                ),
            ));
        }
        let cap = usize::try_from(rows).unwrap_or(usize::MAX);
        let n = n as usize;
        let mut rec = Recording {
            t: Vec::with_capacity(cap),
            x: Vec::with_capacity(cap * n),
            v: Vec::with_capacity(cap * n),
            a: Vec::with_capacity(cap * n),
            energy: Vec::with_capacity(cap),
            kinetic: if defer { Vec::new() } else { Vec::with_capacity(cap) },
            ..Recording::default()
        };
        record(world, &mut rec, defer)?;
        let evals0 = world.evals();
        let deferred = defer.then(Vec::new);
        let log = StageLog::default();
        let steps0 = world.steps();
        Ok(Self { params, steps, next: 1, steps0, evals0, done: steps == 0, log, rec, deferred })
    }

    /// Steps the run takes in all.
    #[must_use]
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Whether the run is over (all steps taken, or stopped at a failure).
    #[must_use]
    pub fn done(&self) -> bool {
        self.done
    }

    /// Takes up to `max_steps` more steps, recording as asked; returns whether the run is
    /// over.
    ///
    /// # Errors
    /// A failed step ([`Error::Diverged`], [`Error::NotConverged`], [`Error::NonFinite`])
    /// unless `stop_on_diverge`, which records the state at the failure and ends the run;
    /// [`Error::Interrupted`] (a stop requested: [`crate::interrupt`]), after which `run`
    /// may be called again and goes on from the first step not taken.
    pub fn run(&mut self, world: &mut World, max_steps: u64) -> Result<bool> {
        let n = world.positions().len();
        let dt = self.params.dt;
        let end = self.steps.min(self.next.saturating_add(max_steps).saturating_sub(1));
        while !self.done && self.next <= end {
            let mut k = self.next;
            // Whether the rows up to step k are recorded already.
            let mut recorded = false;
            let r = if self.params.stages {
                self.log.rows.clear();
                let r = world.step_logged(dt, &mut self.log);
                let flow = world.flow().is_some();
                for row in &self.log.rows {
                    // A flow's stage is its state and derivative (as its rows are: x = y, v = dy).
                    let (x, v, a) = if flow {
                        (row.y.clone(), row.f.clone(), Vec::new())
                    } else {
                        (row.y[..n].to_vec(), row.y[n..].to_vec(), row.f[n..].to_vec())
                    };
                    self.rec.stages.push((k - 1, row.stage, row.t, x, v, a));
                }
                r
            } else if let Some((r, last)) = self.observed(world, k, end) {
                // Every step recorded from inside the kernel's loop.
                recorded = true;
                k = last;
                r
            } else {
                // The steps up to the next recorded one in one call: the fused kernels take
                // them together. `k` becomes the last step taken.
                let every = self.params.every;
                let last = (k.div_ceil(every) * every).min(self.steps).min(end);
                let before = world.steps();
                let r = world.step_n_by(last - k + 1, dt);
                let taken = world.steps() - before;
                if r.is_ok() {
                    k = last;
                } else {
                    k += taken;
                }
                r
            };
            let r = r.and_then(|()| {
                if !recorded && (k % self.params.every == 0 || k == self.steps) {
                    record(world, &mut self.rec, self.deferred.is_some())
                } else {
                    Ok(())
                }
            });
            self.next = k + 1;
            if let Err(e @ Error::Interrupted { .. }) = r {
                // Stopped (Ctrl-C) with the failed step rolled back: the run can go on from
                // the first step not taken.
                self.next = world.steps() - self.steps0 + 1;
                return Err(e);
            }
            if let Err(e) = r {
                if self.params.stop_on_diverge && e.is_step_failure() {
                    self.done = true;
                    if !matches!(e, Error::NonFinite { .. }) {
                        // The world was rolled back to the last good state: record it.
                        record(world, &mut self.rec, self.deferred.is_some())?;
                    }
                    self.rec.diverged = Some(e);
                    break;
                }
                self.done = true;
                return Err(e);
            }
            if k == self.steps {
                self.done = true;
            }
        }
        self.rec.evals = world.evals() - self.evals0;
        Ok(self.done)
    }

    /// Steps `first..=end` of a recording of every step of a small world through the fused
    /// kernel, each row taken inside its loop ([`World::run_observed`]); the outcome (a failed
    /// step, or a row whose energy is not finite) and the index of the last step it concerns
    /// (the failed step, or the last one taken). `None` when the kernel does not apply
    /// (nothing done).
    fn observed(&mut self, world: &mut World, first: u64, end: u64) -> Option<(Result<()>, u64)> {
        if self.params.every != 1 {
            return None;
        }
        let (before, n) = (world.steps(), end - first + 1);
        let (r, failed) = if world.model().energy_bounded() {
            // No energy can overflow: the rows are the state alone, their energies computed
            // after the loop in one pass over the columns.
            let from = self.rec.t.len();
            let rec = &mut self.rec;
            let r = world.run_observed(n, self.params.dt, &mut |r| push_state(&r, rec))?;
            let n = world.positions().len();
            let (xs, vs) = (&rec.x[from * n..], &rec.v[from * n..]);
            // Deferred, the kinetic energies go to a scratch column (in cache: at most one
            // slice of rows), read back for the energies and dropped.
            let kinetic = match self.deferred.as_mut() {
                Some(scratch) => {
                    scratch.clear();
                    scratch
                }
                None => &mut rec.kinetic,
            };
            world.model().energy_rows(xs, vs, kinetic, &mut rec.energy);
            (r, None)
        } else {
            let method = world.integrator().info().name;
            let rec = &mut self.rec;
            let defer = self.deferred.is_some();
            let mut failed = None;
            let mut row = |r: crate::world::Row<'_>| match push_row(&r, method, rec, defer) {
                Ok(()) => true,
                Err(e) => {
                    failed = Some(e);
                    false
                }
            };
            (world.run_observed(n, self.params.dt, &mut row)?, failed)
        };
        let taken = world.steps() - before;
        Some(match (r, failed) {
            (Err(e), _) => (Err(e), first + taken),
            (Ok(()), Some(e)) => (Err(e), first + taken - 1),
            (Ok(()), None) => (Ok(()), first + taken - 1),
        })
    }

    /// The recording so far.
    #[must_use]
    pub fn finish(self) -> Recording {
        self.rec
    }
}

/// Appends a row handed out by the kernel, as [`record`] would take it from the world (a
/// world of particles only); its kinetic energy unless `defer`.
fn push_row(r: &crate::world::Row<'_>, method: &str, rec: &mut Recording, defer: bool) -> Result<()> {
    let kinetic = r.model.kinetic(r.v);
    let e = r.model.potential(r.x).map(|u| kinetic + u);
    if let Some(e) = e.filter(|e| !e.is_finite()) {
        return Err(Error::NonFinite {
            method: method.into(),
            quantity: "energy".into(),
            value: e,
            step: r.steps,
            t: r.t,
        });
    }
    push_state(r, rec);
    if let Some(e) = e {
        rec.energy.push(e);
    }
    if !defer {
        rec.kinetic.push(kinetic);
    }
    Ok(())
}

/// Appends the time and state of a row handed out by the kernel (not its energies); returns
/// `true` (the run goes on).
#[inline(always)]
fn push_state(r: &crate::world::Row<'_>, rec: &mut Recording) -> bool {
    // Rows of a small world: element by element, not a copy call per few numbers (the
    // columns have room for the whole run: a push is a store).
    rec.t.push(r.t);
    r.x.iter().for_each(|&c| rec.x.push(c));
    r.v.iter().for_each(|&c| rec.v.push(c));
    r.a.iter().for_each(|&c| rec.a.push(c));
    true
}

/// Appends the world's current row (its kinetic energy unless `defer`); a non-finite energy
/// (the state is finite, its energy overflowed) ends the run as a failure rather than a
/// silent infinity.
fn record(w: &mut World, rec: &mut Recording, defer: bool) -> Result<()> {
    let e = w.energy();
    if let Some(e) = e.filter(|e| !e.is_finite()) {
        return Err(Error::NonFinite {
            method: w.integrator().info().name.into(),
            quantity: "energy".into(),
            value: e,
            step: w.steps(),
            t: w.time(),
        });
    }
    rec.a.extend_from_slice(w.accelerations()?);
    rec.t.push(w.time());
    rec.x.extend_from_slice(w.positions());
    rec.v.extend_from_slice(w.velocities());
    if let Some(e) = e {
        rec.energy.push(e);
    }
    if !defer {
        rec.kinetic.push(w.kinetic());
    }
    if !w.bodies().is_empty() {
        rec.angular_momentum.extend_from_slice(&w.angular_momentum());
        for b in 0..w.bodies().len() {
            rec.body_spin.extend_from_slice(&w.body_spin(b)?);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(scene: &str, method: &str, every: u64, defer: bool) -> Recording {
        let mut w = crate::scenes::build(scene, &[], method, 0.01).unwrap().world;
        let p = RecordParams { dt: 0.01, until: 1.0, every, stages: false, stop_on_diverge: false };
        let mut r =
            if defer { Recorder::deferring_kinetic(&mut w, p) } else { Recorder::new(&mut w, p) }.unwrap();
        while !r.run(&mut w, 7).unwrap() {}
        r.finish()
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// A deferred kinetic energy is left out, and computed from the velocity rows it is the
    /// recorded one bit for bit; nothing else changes (the small-world kernel and the staged
    /// path, every row and every 3rd).
    #[test]
    fn deferred_kinetic_energy_is_the_recorded_one_from_the_rows() {
        for (scene, method, every) in
            [("spring", "symplectic-euler", 1), ("spring", "rk4", 3), ("chain", "leapfrog", 1)]
        {
            let (eager, lazy) = (run(scene, method, every, false), run(scene, method, every, true));
            assert!(lazy.kinetic.is_empty(), "{scene} {method}");
            assert_eq!(bits(&eager.energy), bits(&lazy.energy), "{scene} {method}");
            assert_eq!(bits(&eager.x), bits(&lazy.x));
            assert_eq!(bits(&eager.v), bits(&lazy.v));
            let w = crate::scenes::build(scene, &[], method, 0.01).unwrap().world;
            let n = w.positions().len();
            let k: Vec<f64> = lazy.v.chunks_exact(n).map(|v| w.model().kinetic(v)).collect();
            assert_eq!(bits(&eager.kinetic), bits(&k), "{scene} {method}");
        }
    }
}
