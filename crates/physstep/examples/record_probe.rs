//! Times a recording of every step of the `spring` scene (what `physstep.simulate` does, less
//! the hand-over to numpy), for profiling the recorder:
//!
//! `cargo run --release -p physstep --example record_probe -- [steps] [runs]`
//!
//! Defaults: 144,000 steps of symplectic Euler at dt = 1/120, 40 runs. Prints ns per recorded
//! step (the fastest run) and the last energy's bits.

use physstep::record::{RecordParams, Recorder};
use physstep::scenes;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let steps: u32 = args.first().map_or(144_000, |s| s.parse().expect("steps: a count"));
    let runs: u32 = args.get(1).map_or(40, |s| s.parse().expect("runs: a count"));
    let dt = 1.0 / 120.0;
    let mut best = f64::INFINITY;
    let mut last = 0.0;
    for _ in 0..runs {
        let mut s = scenes::build("spring", &[], "symplectic-euler", dt).expect("the scene builds");
        let params = RecordParams {
            dt,
            until: f64::from(steps) * dt,
            every: 1,
            stages: false,
            stop_on_diverge: false,
        };
        let start = Instant::now();
        let mut r = Recorder::deferring_kinetic(&mut s.world, params).expect("a recorder");
        while !r.run(&mut s.world, 4096).expect("a run") {}
        let rec = r.finish();
        best = best.min(start.elapsed().as_secs_f64());
        last = *rec.energy.last().expect("rows");
    }
    println!(
        "{:.2} ns a recorded step (fastest of {runs}), last energy {:#018x}",
        best * 1e9 / f64::from(steps),
        last.to_bits()
    );
}
