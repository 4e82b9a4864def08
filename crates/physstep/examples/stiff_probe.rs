//! Times a stiff scene under an implicit method (for profiling the sparse solve):
//!
//! `cargo run --release -p physstep --example stiff_probe -- [scene] [method] [steps] [key=value ...]`
//!
//! Defaults: the 32 x 32 `stiff-cloth` under `linearly-implicit-euler`, 300 steps after the
//! first (`halvings=N` sets `ImplicitParams::energy_halvings`). Prints the first step's time (it orders the sparse factor) and the time per step after it, the Newton updates and CG iterations per step, and the state hash (so a
//! change that should keep the bits can be checked).

mod probe_scene;

use physstep::integrators::ImplicitParams;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = args.first().map_or("stiff-cloth", String::as_str);
    let method = args.get(1).map_or("linearly-implicit-euler", String::as_str);
    let steps: u64 = args.get(2).map_or(300, |s| s.parse().expect("steps: a count"));
    // `halvings=N` sets ImplicitParams::energy_halvings; the other keys are the scene's.
    let (halvings, overrides): (Vec<String>, Vec<String>) =
        args.get(3..).unwrap_or_default().iter().cloned().partition(|kv| kv.starts_with("halvings="));
    let mut s = probe_scene::build(scene, Some(method), &overrides);
    if let Some(kv) = halvings.last() {
        let n = kv["halvings=".len()..].parse().expect("halvings: a count");
        s.world
            .set_implicit(ImplicitParams { energy_halvings: n, ..ImplicitParams::default() })
            .expect("settings");
    }
    let (mut redone, mut most) = (0, 0);
    let (mut newton, mut cg) = (0u64, 0u64);
    let mut e_rises = 0;
    let mut e_prev = s.world.energy().unwrap_or(f64::NAN);
    // The first step apart: it makes the factor's order and pattern (kept while the springs
    // stay the same).
    let first = Instant::now();
    s.world.step(1).expect("a step");
    let first = first.elapsed().as_secs_f64();
    let start = Instant::now();
    for _ in 0..steps {
        s.world.step(1).expect("a step");
        let st = s.world.integrator().solve_stats().expect("an implicit method");
        newton += st.newton as u64;
        redone += u32::from(method == "linearly-implicit-euler" && st.newton > 1);
        most = most.max(st.newton);
        cg += st.cg as u64;
        let e = s.world.energy().unwrap_or(f64::NAN);
        if e > e_prev {
            e_rises += 1;
        }
        e_prev = e;
    }
    let took = start.elapsed().as_secs_f64();
    println!(
        "{scene} / {method}: first step {:.1} ms, then {steps} steps, {:.4} ms a step, {:.2} Newton and {:.2} CG a step (at most {most} Newton; {redone} steps halved), energy rose on {e_rises} steps, hash {:#018x}",
        1e3 * first,
        1e3 * took / steps as f64,
        newton as f64 / steps as f64,
        cg as f64 / steps as f64,
        s.world.state_hash()
    );
}
