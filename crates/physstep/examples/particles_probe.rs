//! Times one step per call of many particles (the game loop's pattern, for profiling the fused
//! particle kernel) beside the memory floor measured in the same process:
//!
//! `cargo run --release -p physstep --example particles_probe -- [n] [calls] [masses]`
//!
//! Defaults: 1,000,000 particles in 3D under gravity and linear drag 0.1, symplectic Euler at
//! dt = 1/120, 200 calls of `World::step(1)`; `masses` = `unit` (every mass 1 kg) or `mixed`
//! (1 to 2 kg). The floor is a parallel read-modify-write of the same positions and
//! velocities (rayon, no physics), alone and reading the inverse masses too. Prints ns per
//! particle-step of each round, the fastest rounds' ratios (this machine's timings swing by
//! 30%: compare fastest rounds), and the state hash (so a change that should keep the bits
//! can be checked at this size).

use physstep::forces::Force;
use physstep::world::{World, WorldParams};
use rayon::prelude::*;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().map_or(1_000_000, |s| s.parse().expect("n: a count"));
    let calls: u32 = args.get(1).map_or(200, |s| s.parse().expect("calls: a count"));
    let mixed = args.get(2).is_some_and(|s| s == "mixed");
    let params = WorldParams { dim: 3, dt: 1.0 / 120.0, ..WorldParams::default() };
    let mut w = World::new(params).expect("a world");
    // A fixed pseudo-random start (an LCG), so the hash is the same from run to run.
    let mut seed = 1u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let x: Vec<f64> = (0..3 * n).map(|_| next()).collect();
    let v: Vec<f64> = (0..3 * n).map(|_| next()).collect();
    let m: Vec<f64> = (0..n).map(|i| if mixed { 1.0 + (i % 7) as f64 / 7.0 } else { 1.0 }).collect();
    w.add_particles(&x, Some(&v), Some(&m), false).expect("particles");
    w.add_force(Force::Gravity { g: [0.0, 0.0, -9.81] }).expect("gravity");
    w.add_force(Force::Drag { linear: 0.1, quadratic: 0.0 }).expect("drag");
    w.step(1).expect("a step");
    let (mut fx, mut fv) = (x.clone(), v.clone());
    // The floor: a read-modify-write of x and v; with `masses`, reading the inverse masses
    // too (what the kernel reads).
    let floor = |fx: &mut [f64], fv: &mut [f64], masses: bool| {
        let tasks = fx.par_chunks_mut(3 * 16384).zip(fv.par_chunks_mut(3 * 16384)).zip(m.par_chunks(16384));
        tasks.for_each(|((a, b), w)| {
            for ((p, q), w) in a.chunks_mut(3).zip(b.chunks_mut(3)).zip(w) {
                let s = if masses { 1e-9 * w } else { 1e-9 };
                for k in 0..3 {
                    q[k] += s;
                    p[k] += q[k];
                }
            }
        });
    };
    floor(&mut fx, &mut fv, true);
    let per = 1e9 / (f64::from(calls) * n as f64);
    let mut best = [f64::INFINITY; 3];
    for round in 0..7 {
        let start = Instant::now();
        for _ in 0..calls {
            w.step(1).expect("a step");
        }
        let engine = start.elapsed().as_secs_f64() * per;
        let mut bare = [0.0; 2];
        for (b, masses) in bare.iter_mut().zip([false, true]) {
            let start = Instant::now();
            for _ in 0..calls {
                floor(&mut fx, &mut fv, masses);
            }
            *b = start.elapsed().as_secs_f64() * per;
        }
        for (b, t) in best.iter_mut().zip([engine, bare[0], bare[1]]) {
            *b = b.min(t);
        }
        println!(
            "round {round}: World::step(1) {engine:.3} ns/particle-step, floor {:.3} (with the masses {:.3})",
            bare[0], bare[1]
        );
    }
    println!(
        "fastest round: World::step(1) {:.3} ns/particle-step, {:.2}x the floor, {:.2}x the floor with the masses",
        best[0],
        best[0] / best[1],
        best[0] / best[2]
    );
    println!("hash {:#018x} after {} steps", w.state_hash(), 1 + 7 * calls);
}
