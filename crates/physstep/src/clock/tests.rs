//! Unit tests of the clock: every loop variant, the guards, the exact accumulator.
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
        (ClockParams { mode: LoopMode::StepsPerFrame(0), ..ClockParams::default() }, "steps_per_frame", "0"),
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
