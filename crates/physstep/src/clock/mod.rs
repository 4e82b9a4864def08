//! The fixed-timestep game loop of the notes ("Fix your timestep"), driven by numbers.
//!
//! A [`Clock`] never sleeps and never reads a real clock: the caller hands it each frame's
//! duration in seconds and gets back a [`FramePlan`] saying how many physics steps to take
//! and with which dt. The clock does not step physics itself, so it is tested with made-up
//! frame times.
//!
//! In the default [`LoopMode::Accumulator`] mode every step is exactly `dt` and the number
//! of steps taken after any sequence of frames depends only on the (exact) sum of their
//! durations, not on how that sum was split into frames, so a world reaches bitwise the same
//! state at the same physics time at 30, 60 or 144 frames per second.

use crate::error::{positive, Error, Result};

/// Relative tolerance, in units of dt, with which a step is considered due.
///
/// A step is taken when the accumulator holds at least `dt * (1 - STEP_TOLERANCE)`. Frame
/// times such as 1/30 s are not exactly four steps of 1/120 s once rounded to `f64`, so
/// without slack a frame sequence that should land on a step boundary could land a few ulps
/// short of it and take its last step one frame late. The accumulator itself is kept
/// (almost) exactly, so the only error the tolerance must absorb is the rounding of the
/// inputs, about 1e-16 of each frame time; 1e-9 covers that systematic bias for ~1e7 steps.
/// A step taken early leaves a tiny negative balance (a debt of at most `1e-9 * dt`) that is
/// kept, so no time is created.
const STEP_TOLERANCE: f64 = 1e-9;

/// The largest `f64` below 1, the upper bound of [`Clock::alpha`].
const BELOW_ONE: f64 = 1.0 - f64::EPSILON / 2.0;

/// Which loop variant of the notes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum LoopMode {
    /// One physics step of `dt` per frame, whatever the frame time (notes: "stepsize matching
    /// refresh rate").
    StepPerFrame,
    /// `n` steps of `dt / n` per frame (notes: "refresh rate x n").
    StepsPerFrame(u32),
    /// The (clamped) frame time itself is the dt of one step (notes: "use actual timestep").
    FrameTime,
    /// Fixed `dt` steps consume the frame time; the fractional leftover is dropped each frame
    /// (notes: "use smaller time step" as written: `while timespan > 0`), so a frame takes
    /// `ceil(frame_time / dt)` steps and may overshoot.
    ConsumeFrame,
    /// Separate physics and render clocks: fixed `dt` steps while physics time + dt <= render
    /// time; the leftover is carried to the next frame and `alpha = leftover / dt` is the
    /// render interpolation factor (notes: "separate time for display and physics"). The
    /// default.
    #[default]
    Accumulator,
}

impl LoopMode {
    /// The names of the variants, as `World(loop=...)` and scene files take them.
    pub const NAMES: [&'static str; 5] =
        ["accumulator", "step-per-frame", "steps-per-frame", "frame-time", "consume-frame"];

    /// The variant named `name` (`substeps` for `steps-per-frame`).
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the valid names.
    pub fn from_name(name: &str, substeps: u32) -> Result<Self> {
        Ok(match name {
            "accumulator" => Self::Accumulator,
            "step-per-frame" => Self::StepPerFrame,
            "steps-per-frame" => Self::StepsPerFrame(substeps),
            "frame-time" => Self::FrameTime,
            "consume-frame" => Self::ConsumeFrame,
            other => return Err(Error::unknown("loop", other, Self::NAMES)),
        })
    }

    /// The variant's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Accumulator => "accumulator",
            Self::StepPerFrame => "step-per-frame",
            Self::StepsPerFrame(_) => "steps-per-frame",
            Self::FrameTime => "frame-time",
            Self::ConsumeFrame => "consume-frame",
        }
    }
}

/// Configuration of a [`Clock`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClockParams {
    /// Fixed physics step, s. Default 1/120 s.
    pub dt: f64,
    /// Loop variant. Default [`LoopMode::Accumulator`].
    pub mode: LoopMode,
    /// Most physics steps one frame may ask for; the time of further steps is dropped
    /// (spiral-of-death guard). Default 8.
    pub max_steps_per_frame: u32,
    /// Longest frame time taken into account, s; longer frames (a breakpoint, a window drag)
    /// are clamped to it. Default 0.1 s.
    pub max_frame_time: f64,
}

impl Default for ClockParams {
    fn default() -> Self {
        Self { dt: 1.0 / 120.0, mode: LoopMode::Accumulator, max_steps_per_frame: 8, max_frame_time: 0.1 }
    }
}

impl ClockParams {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `dt` or `max_frame_time` when not a finite number > 0,
    /// `max_steps_per_frame` when 0, or `steps_per_frame` for [`LoopMode::StepsPerFrame`]`(0)`.
    pub fn validate(&self) -> Result<()> {
        positive("dt", self.dt)?;
        positive("max_frame_time", self.max_frame_time)?;
        // The accumulator counts a frame's steps as a float: past 2^53 steps per frame the
        // count is no longer exact (and a subnormal dt overflows it), so the loop could not
        // progress. The bound also keeps `dt / substeps` a usable step.
        let min_dt = self.max_frame_time / MAX_FRAME_STEPS;
        if self.dt < min_dt {
            return Err(Error::invalid(
                "dt",
                crate::error::num(self.dt),
                format!("at least max_frame_time / 2^53 = {min_dt:e} s, so a frame's steps can be counted"),
            ));
        }
        if self.max_steps_per_frame == 0 {
            return Err(Error::invalid("max_steps_per_frame", 0, "at least 1"));
        }
        if self.mode == LoopMode::StepsPerFrame(0) {
            return Err(Error::invalid("steps_per_frame", 0, "at least 1"));
        }
        Ok(())
    }
}

/// Most steps one frame's time may hold: 2^53, the last exact integer of an f64.
const MAX_FRAME_STEPS: f64 = 9_007_199_254_740_992.0;

/// What one frame asks of the physics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FramePlan {
    /// Number of physics steps to take this frame.
    pub steps: u32,
    /// Step size of each of those steps, s. Always > 0, also when `steps` is 0.
    pub dt: f64,
    /// Frame time removed by the clamp to `max_frame_time`, s.
    pub clamped: f64,
    /// Physics time dropped by the spiral-of-death guard (steps beyond
    /// `max_steps_per_frame`, times their dt), s.
    pub dropped: f64,
}

/// Totals of a [`Clock`] since creation or the last [`Clock::reset`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ClockStats {
    /// Frames planned.
    pub frames: u64,
    /// Physics steps planned.
    pub steps: u64,
    /// Frame time removed by the clamp, s.
    pub clamped: f64,
    /// Physics time dropped by the spiral-of-death guard, s.
    pub dropped: f64,
}

/// Error-free sum: `a + b == s + e` exactly (Knuth's two-sum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// The accumulator as an unevaluated sum `hi + lo` (double-double), so that adding frame
/// times and removing steps never loses time to rounding however long the game runs.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Ledger {
    hi: f64,
    lo: f64,
}

impl Ledger {
    fn value(self) -> f64 {
        self.hi + self.lo
    }

    fn add(&mut self, x: f64) {
        let (s, e) = two_sum(self.hi, x);
        let (hi, lo) = two_sum(s, e + self.lo);
        self.hi = hi;
        self.lo = lo;
    }

    /// Removes `n * dt`, with the product's rounding error recovered by a fused multiply-add.
    fn sub_steps(&mut self, n: f64, dt: f64) {
        let p = n * dt;
        let err = n.mul_add(dt, -p);
        self.add(-p);
        self.add(-err);
    }
}

/// The fixed-timestep loop: turns frame times into physics steps.
#[derive(Debug, Clone)]
pub struct Clock {
    params: ClockParams,
    acc: Ledger,
    stats: ClockStats,
}

impl Clock {
    /// A clock with an empty accumulator.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] when `params` does not pass [`ClockParams::validate`].
    pub fn new(params: ClockParams) -> Result<Self> {
        params.validate()?;
        Ok(Self { params, acc: Ledger::default(), stats: ClockStats::default() })
    }

    /// The configuration.
    #[must_use]
    pub fn params(&self) -> &ClockParams {
        &self.params
    }

    /// Plans one frame of `frame_time` seconds: clamps it to `max_frame_time`, adds it to the
    /// accumulator, and returns the number of steps to take (capped at `max_steps_per_frame`;
    /// the time of the excess steps is dropped and reported, so overload slows the game
    /// instead of freezing it) and their dt. Updates [`Clock::alpha`] and [`Clock::stats`].
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `frame_time` when it is not finite or is negative; the
    /// clock is then unchanged.
    pub fn frame(&mut self, frame_time: f64) -> Result<FramePlan> {
        // A frame longer than 1e9 s (31 years) is no frame: beyond it the clamped-time
        // total could overflow to infinity.
        if !(frame_time.is_finite() && (0.0..=1e9).contains(&frame_time)) {
            return Err(Error::invalid(
                "frame_time",
                crate::error::num(frame_time),
                "a number from 0 to 1e9 s",
            ));
        }
        let p = self.params;
        let (frame, clamped) = if frame_time > p.max_frame_time {
            (p.max_frame_time, frame_time - p.max_frame_time)
        } else {
            (frame_time, 0.0)
        };

        // Steps wanted (as f64: huge frame/dt ratios must not overflow) and their size.
        let (wanted, dt) = match p.mode {
            LoopMode::StepPerFrame => (1.0, p.dt),
            LoopMode::StepsPerFrame(n) => (f64::from(n), p.dt / f64::from(n)),
            LoopMode::FrameTime if frame > 0.0 => (1.0, frame),
            // Nothing to step; keep a valid dt for callers that validate it.
            LoopMode::FrameTime => (0.0, p.dt),
            LoopMode::ConsumeFrame => (((frame / p.dt) - STEP_TOLERANCE).ceil().max(0.0), p.dt),
            LoopMode::Accumulator => {
                self.acc.add(frame);
                (self.take_due_steps(), p.dt)
            }
        };

        let max = f64::from(p.max_steps_per_frame);
        let steps = wanted.min(max);
        let dropped = (wanted - steps) * dt;
        // `steps` is a whole number in [0, max_steps_per_frame].
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let plan = FramePlan { steps: steps as u32, dt, clamped, dropped };

        self.stats.frames += 1;
        self.stats.steps += u64::from(plan.steps);
        self.stats.clamped += clamped;
        self.stats.dropped += dropped;
        Ok(plan)
    }

    /// Removes every due step from the accumulator and returns how many (a whole number).
    ///
    /// The count is estimated by a division and then corrected against the exact balance, so
    /// the balance ends in `[-STEP_TOLERANCE * dt, dt - STEP_TOLERANCE * dt)`.
    fn take_due_steps(&mut self) -> f64 {
        let dt = self.params.dt;
        let due = dt - STEP_TOLERANCE * dt;
        let mut n = (self.acc.value() / dt + STEP_TOLERANCE).floor().max(0.0);
        self.acc.sub_steps(n, dt);
        // The estimate is off by at most one; the bounded loop also guards against ratios so
        // large that n + 1 == n.
        for _ in 0..2 {
            let left = self.acc.value();
            if left >= due {
                self.acc.sub_steps(1.0, dt);
                n += 1.0;
            } else if left < due - dt && n >= 1.0 {
                self.acc.add(dt);
                n -= 1.0;
            } else {
                break;
            }
        }
        n
    }

    /// Leftover time in the accumulator, s, in `[0, dt)` ([`LoopMode::Accumulator`]; 0 in
    /// the other modes). Right after [`Clock::retime`] to a smaller dt it may exceed the new
    /// dt until the next frame takes the due steps.
    #[must_use]
    pub fn leftover(&self) -> f64 {
        // A step taken within the tolerance leaves a tiny debt; it is not time to render.
        self.acc.value().max(0.0)
    }

    /// Render interpolation factor in `[0, 1)`: `leftover / dt` ([`LoopMode::Accumulator`];
    /// 0 in the other modes). Draw `previous + alpha * (current - previous)`.
    #[must_use]
    pub fn alpha(&self) -> f64 {
        (self.leftover() / self.params.dt).min(BELOW_ONE)
    }

    /// Totals since creation or the last [`Clock::reset`]: frames, steps planned, time
    /// clamped (s), time dropped (s).
    #[must_use]
    pub fn stats(&self) -> ClockStats {
        self.stats
    }

    /// The accumulator's exact balance as two floats (for snapshots).
    #[must_use]
    pub(crate) fn balance(&self) -> [f64; 2] {
        [self.acc.hi, self.acc.lo]
    }

    /// Restores a balance taken by [`Clock::balance`].
    pub(crate) fn restore_balance(&mut self, b: [f64; 2]) {
        self.acc.hi = b[0];
        self.acc.lo = b[1];
    }

    /// Empties the accumulator and zeroes the stats; the params are kept.
    pub fn reset(&mut self) {
        self.acc = Ledger::default();
        self.stats = ClockStats::default();
    }

    /// Changes the fixed step to `dt` seconds, keeping the accumulator (its time is spent in
    /// steps of the new dt from the next frame on).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `dt` when it is not a finite number > 0; the clock is
    /// then unchanged.
    pub fn retime(&mut self, dt: f64) -> Result<()> {
        let params = ClockParams { dt, ..self.params };
        params.validate()?;
        self.params = params;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
