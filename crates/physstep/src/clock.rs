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
mod tests {
    use super::*;

    const DT: f64 = 1.0 / 120.0;

    fn clock(mode: LoopMode) -> Clock {
        Clock::new(ClockParams { mode, ..ClockParams::default() }).unwrap()
    }

    /// Tiny deterministic generator (xorshift64*), uniform in [0, 1).
    struct XorShift(u64);

    impl XorShift {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
            #[allow(clippy::cast_precision_loss)]
            let u = (r >> 11) as f64 / (1u64 << 53) as f64;
            u
        }
    }

    /// Frame times summing to `total` (up to the rounding of a naive sum): random in
    /// [2 ms, 50 ms], the last one taking the remainder.
    fn jittered(seed: u64, total: f64) -> Vec<f64> {
        let mut rng = XorShift(seed);
        let mut frames = Vec::new();
        let mut sum = 0.0;
        loop {
            let f = 0.002 + 0.048 * rng.next();
            if sum + f >= total {
                frames.push(total - sum);
                return frames;
            }
            frames.push(f);
            sum += f;
        }
    }

    /// Runs `frames` through an accumulator clock and a toy oscillator stepped as planned;
    /// checks the per-frame invariants and returns (steps, final state bits).
    fn run(frames: &[f64]) -> (u64, [u64; 2]) {
        let mut c = clock(LoopMode::Accumulator);
        let (mut x, mut v) = (1.0_f64, 0.0_f64);
        for &f in frames {
            let plan = c.frame(f).unwrap();
            assert_eq!(plan.dt.to_bits(), DT.to_bits(), "accumulator steps are exactly dt");
            assert_eq!(plan.dropped, 0.0);
            for _ in 0..plan.steps {
                v -= x * plan.dt;
                x += v * plan.dt;
            }
            let a = c.alpha();
            assert!((0.0..1.0).contains(&a), "alpha {a}");
            assert!(c.leftover() < DT);
        }
        (c.stats().steps, [x.to_bits(), v.to_bits()])
    }

    #[test]
    fn two_frames_of_dt_take_two_steps() {
        let mut c = clock(LoopMode::Accumulator);
        assert_eq!(c.frame(DT).unwrap().steps, 1);
        assert_eq!(c.frame(DT).unwrap().steps, 1);
        assert_eq!(c.stats().steps, 2);
        assert_eq!(c.alpha(), 0.0);
    }

    #[test]
    fn one_second_at_120_hz_is_120_steps() {
        let mut c = clock(LoopMode::Accumulator);
        for _ in 0..120 {
            assert_eq!(c.frame(1.0 / 120.0).unwrap().steps, 1);
        }
        assert_eq!(c.stats().steps, 120);
        assert!(c.leftover() < 1e-12);
    }

    #[test]
    fn frame_rates_agree_on_steps_and_state() {
        // T = 2 s = 240 steps exactly, reached at 30, 60, 144 Hz and with jitter.
        let total = 240.0 * DT;
        let rates: Vec<Vec<f64>> = vec![
            vec![1.0 / 30.0; 60],
            vec![1.0 / 60.0; 120],
            vec![1.0 / 144.0; 288],
            jittered(0x9E37_79B9_7F4A_7C15, total),
            jittered(42, total),
        ];
        let reference = run(&vec![DT; 240]);
        assert_eq!(reference.0, 240);
        for frames in &rates {
            assert!(frames.len() > 10);
            assert_eq!(run(frames), reference, "{} frames", frames.len());
        }
    }

    #[test]
    fn off_boundary_total_floors_and_leaves_alpha() {
        // T = 100.5 steps: 100 steps, half a step left to interpolate.
        for frames in [vec![100.5 * DT / 67.0; 67], jittered(7, 100.5 * DT)] {
            let mut c = clock(LoopMode::Accumulator);
            for f in frames {
                c.frame(f).unwrap();
            }
            assert_eq!(c.stats().steps, 100);
            assert!((c.alpha() - 0.5).abs() < 1e-9, "alpha {}", c.alpha());
        }
    }

    #[test]
    fn long_runs_do_not_drift() {
        // 100 000 frames at 144 Hz = 83 333 + 1/3 steps.
        let mut c = clock(LoopMode::Accumulator);
        for _ in 0..100_000 {
            c.frame(1.0 / 144.0).unwrap();
        }
        assert_eq!(c.stats().steps, 83_333);
        assert!((c.alpha() - 1.0 / 3.0).abs() < 1e-9, "alpha {}", c.alpha());
    }

    #[test]
    fn accumulator_carries_leftover() {
        let mut c = clock(LoopMode::Accumulator);
        // 0.02 s = 2.4 steps.
        assert_eq!(c.frame(0.02).unwrap().steps, 2);
        assert!((c.alpha() - 0.4).abs() < 1e-9);
        assert_eq!(c.frame(0.02).unwrap().steps, 2);
        assert!((c.alpha() - 0.8).abs() < 1e-9);
        assert_eq!(c.frame(0.02).unwrap().steps, 3);
        assert!((c.alpha() - 0.2).abs() < 1e-9);
        assert_eq!(c.frame(0.0).unwrap().steps, 0);
    }

    #[test]
    fn spiral_of_death_is_capped_and_dropped_time_reported() {
        let mut c = clock(LoopMode::Accumulator);
        let mut total = 0.0;
        // 0.1 s = 12 steps per frame, 8 allowed: 4 dropped every frame.
        for _ in 0..50 {
            let plan = c.frame(0.1).unwrap();
            total += 0.1;
            assert_eq!(plan.steps, 8);
            assert_eq!(plan.dropped, 4.0 * DT);
            assert!(c.leftover() < DT);
        }
        // Half a step over: the fraction is kept, only whole steps are dropped.
        let plan = c.frame(0.1 - 0.5 * DT).unwrap();
        total += 0.1 - 0.5 * DT;
        assert_eq!((plan.steps, plan.dropped), (8, 3.0 * DT));
        assert!((c.alpha() - 0.5).abs() < 1e-9);
        // No time lost or created: steps + dropped + leftover is all the frame time.
        let s = c.stats();
        #[allow(clippy::cast_precision_loss)]
        let accounted = s.steps as f64 * DT + s.dropped + c.leftover();
        assert!((accounted - total).abs() < 1e-12, "{accounted} vs {total}");
        assert_eq!(s.frames, 51);
        assert_eq!(s.steps, 51 * 8);
    }

    #[test]
    fn long_frame_is_clamped() {
        let mut c = clock(LoopMode::Accumulator);
        let plan = c.frame(5.0).unwrap();
        assert!((plan.clamped - 4.9).abs() < 1e-12);
        assert_eq!(plan.steps, 8);
        assert_eq!(plan.dropped, 4.0 * DT);
        assert!((c.stats().clamped - 4.9).abs() < 1e-12);
        assert_eq!(c.frame(0.1).unwrap().clamped, 0.0);
    }

    #[test]
    fn step_per_frame_takes_one_step_of_dt() {
        let mut c = clock(LoopMode::StepPerFrame);
        for f in [0.0, 0.005, 0.05, 3.0] {
            let plan = c.frame(f).unwrap();
            assert_eq!((plan.steps, plan.dt, plan.dropped), (1, DT, 0.0));
        }
        assert_eq!(c.alpha(), 0.0);
        assert_eq!(c.stats().steps, 4);
    }

    #[test]
    fn steps_per_frame_takes_n_substeps() {
        let mut c = clock(LoopMode::StepsPerFrame(4));
        let plan = c.frame(1.0 / 30.0).unwrap();
        assert_eq!((plan.steps, plan.dt, plan.dropped), (4, DT / 4.0, 0.0));
        // More substeps than the cap: the rest is dropped.
        let mut c = clock(LoopMode::StepsPerFrame(20));
        let plan = c.frame(1.0 / 60.0).unwrap();
        assert_eq!((plan.steps, plan.dt), (8, DT / 20.0));
        assert_eq!(plan.dropped, 12.0 * (DT / 20.0));
    }

    #[test]
    fn frame_time_mode_steps_by_the_frame() {
        let mut c = clock(LoopMode::FrameTime);
        let plan = c.frame(0.02).unwrap();
        assert_eq!((plan.steps, plan.dt), (1, 0.02));
        let plan = c.frame(5.0).unwrap();
        assert_eq!((plan.steps, plan.dt), (1, 0.1));
        assert!((plan.clamped - 4.9).abs() < 1e-12);
        let plan = c.frame(0.0).unwrap();
        assert_eq!(plan.steps, 0);
        assert!(plan.dt > 0.0);
        assert_eq!(c.alpha(), 0.0);
    }

    #[test]
    fn consume_frame_overshoots_and_discards() {
        let mut c = clock(LoopMode::ConsumeFrame);
        // 4 steps exactly (1/30 is a few ulps off 4 * (1/120); the tolerance absorbs it).
        assert_eq!(c.frame(1.0 / 30.0).unwrap().steps, 4);
        // 2.4 steps: `while timespan > 0` takes 3, and nothing is carried over.
        let plan = c.frame(0.02).unwrap();
        assert_eq!((plan.steps, plan.dt), (3, DT));
        assert_eq!((c.leftover(), c.alpha()), (0.0, 0.0));
        assert_eq!(c.frame(0.02).unwrap().steps, 3);
        assert_eq!(c.frame(0.0).unwrap().steps, 0);
        // 0.1 s = 12 steps, capped to 8.
        let plan = c.frame(0.1).unwrap();
        assert_eq!((plan.steps, plan.dropped), (8, 4.0 * DT));
    }

    #[test]
    fn validation_names_field_and_value() {
        let bad = [
            (ClockParams { dt: -1.0, ..ClockParams::default() }, "dt", "-1"),
            (ClockParams { dt: 0.0, ..ClockParams::default() }, "dt", "0"),
            (ClockParams { max_frame_time: f64::NAN, ..ClockParams::default() }, "max_frame_time", "NaN"),
            (ClockParams { max_steps_per_frame: 0, ..ClockParams::default() }, "max_steps_per_frame", "0"),
            (
                ClockParams { mode: LoopMode::StepsPerFrame(0), ..ClockParams::default() },
                "steps_per_frame",
                "0",
            ),
        ];
        for (params, field, value) in bad {
            let msg = Clock::new(params).unwrap_err().to_string();
            assert!(msg.contains(&format!("{field} = {value}")), "{msg}");
        }
        assert!(ClockParams::default().validate().is_ok());

        let mut c = clock(LoopMode::Accumulator);
        c.frame(0.5 * DT).unwrap();
        for f in [-1.0, f64::INFINITY, f64::NAN] {
            let msg = c.frame(f).unwrap_err().to_string();
            assert!(msg.contains(&format!("frame_time = {f}")), "{msg}");
        }
        let msg = c.retime(-1.0).unwrap_err().to_string();
        assert!(msg.contains("dt = -1"), "{msg}");
        // Failed calls change nothing.
        assert_eq!(c.stats().frames, 1);
        assert_eq!(c.params().dt, DT);
        assert!((c.alpha() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn retime_keeps_the_accumulator() {
        let mut c = clock(LoopMode::Accumulator);
        c.frame(0.5 * DT).unwrap();
        c.retime(DT / 4.0).unwrap();
        assert_eq!(c.params().dt, DT / 4.0);
        assert!((c.leftover() - 0.5 * DT).abs() < 1e-15);
        // The carried half step is two new steps.
        let plan = c.frame(0.0).unwrap();
        assert_eq!((plan.steps, plan.dt), (2, DT / 4.0));
        assert!(c.alpha() < 1e-9);
    }

    #[test]
    fn reset_empties_everything() {
        let mut c = clock(LoopMode::Accumulator);
        c.frame(5.0).unwrap();
        c.frame(0.5 * DT).unwrap();
        c.reset();
        assert_eq!(c.stats(), ClockStats::default());
        assert_eq!((c.leftover(), c.alpha()), (0.0, 0.0));
        assert_eq!(c.frame(DT).unwrap().steps, 1);
    }

    #[test]
    fn smallest_dt_still_progresses_every_frame() {
        // The smallest dt accepted: a frame's steps are still counted exactly, and the loop
        // takes its capped steps frame after frame with a finite dropped time.
        let dt = 0.1 / MAX_FRAME_STEPS;
        let mut c = Clock::new(ClockParams { dt, ..ClockParams::default() }).unwrap();
        for _ in 0..3 {
            let plan = c.frame(0.1).unwrap();
            assert_eq!(plan.steps, 8);
            assert!(plan.dropped > 0.09 && plan.dropped.is_finite());
            assert!(c.alpha() < 1.0);
        }
    }

    #[test]
    fn a_dt_whose_frames_cannot_be_counted_is_refused() {
        // Issue 7, item 18: dt = 1e-310 took 8 steps, then none ever again (dropped = inf).
        for dt in [1e-310, 1e-300, 0.1 / MAX_FRAME_STEPS / 2.0] {
            let e = Clock::new(ClockParams { dt, ..ClockParams::default() }).unwrap_err();
            assert!(e.to_string().starts_with("invalid dt = "), "{e}");
            assert!(e.to_string().contains("max_frame_time / 2^53"), "{e}");
        }
    }
}
