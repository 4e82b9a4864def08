//! Times a contact scene's steps (for profiling the contact solver):
//!
//! `cargo run --release -p physstep --example solids_probe -- [scene] [steps] [key=value ...]`
//!
//! Defaults: the 20-row `pyramid`, 600 steps (10 s at 60 Hz). `sleep_time=s` among the
//! parameters turns sleeping on, `substeps=n` sets the soft step's substeps (neither is a scene
//! parameter). Prints the time per step, the
//! deepest penetration of the last step, the solids asleep at the end and the state hash (so a
//! change that should keep the bits can be checked on a large scene too).

mod probe_scene;

use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = args.first().map_or("pyramid", String::as_str);
    let steps: u64 = args.get(1).map_or(600, |s| s.parse().expect("steps: a count"));
    let (world_params, params): (Vec<String>, Vec<String>) = args
        .get(2..)
        .unwrap_or_default()
        .iter()
        .cloned()
        .partition(|a| a.starts_with("sleep_time=") || a.starts_with("substeps="));
    let mut s = probe_scene::build(scene, None, &params);
    for p in &world_params {
        if let Some(t) = p.strip_prefix("sleep_time=") {
            s.world.set_sleep_time(t.parse().expect("sleep_time: seconds")).expect("sleep_time");
        } else if let Some(n) = p.strip_prefix("substeps=") {
            s.world.set_substeps(n.parse().expect("substeps: a count")).expect("substeps");
        }
    }
    let start = Instant::now();
    for _ in 0..steps {
        s.world.step(1).expect("a step");
    }
    let took = start.elapsed().as_secs_f64();
    println!(
        "{scene}: {} solids, {} contact points, {steps} steps, {:.4} ms a step, max penetration {:.3e} m, {} asleep, hash {:#018x}",
        s.world.solid_count(),
        s.world.contacts().depths.len(),
        1e3 * took / steps as f64,
        s.world.max_penetration(),
        s.world.solids_asleep().iter().filter(|a| **a).count(),
        s.world.state_hash()
    );
}
