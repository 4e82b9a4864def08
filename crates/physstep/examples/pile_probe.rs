//! Times the `pile` scene (1,000 balls dropped into a box under gravity, settling on their
//! resting contacts), for profiling the resting-contact solver:
//!
//! `cargo run --release -p physstep --example pile_probe -- [restitution] [steps]`
//!
//! Defaults: restitution 0.5, 1200 steps (10 s) of symplectic Euler at dt = 1/120. Prints ms a
//! step, the state hash at the end (a change of bits shows), the kinetic energy at the end over
//! its peak and the deepest overlap of two balls.
use physstep::scenes;
use std::time::Instant;

fn main() {
    let e: f64 = std::env::args().nth(1).map_or(0.5, |s| s.parse().expect("restitution"));
    let steps: u64 = std::env::args().nth(2).map_or(1200, |s| s.parse().expect("steps"));
    let mut w =
        scenes::build("pile", &[("restitution", e)], "symplectic-euler", 1.0 / 120.0).expect("pile").world;
    let t = Instant::now();
    let mut peak = 0.0_f64;
    for _ in 0..steps {
        w.step(1).expect("a step");
        peak = peak.max(w.kinetic());
    }
    let ms = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
    // The deepest overlap of two balls at the end (every pair: a probe, not a hot path).
    let (x, r) = (w.positions(), w.radii());
    let d = w.dim();
    let mut deep = 0.0_f64;
    for i in 0..r.len() {
        for j in i + 1..r.len() {
            let dd: f64 = (0..d).map(|k| (x[i * d + k] - x[j * d + k]).powi(2)).sum();
            deep = deep.max(r[i] + r[j] - dd.sqrt());
        }
    }
    println!(
        "{ms:.2} ms a step, hash {:#018x}, kinetic {:e} of its peak, deepest overlap {deep:e} m",
        w.state_hash(),
        w.kinetic() / peak
    );
}
