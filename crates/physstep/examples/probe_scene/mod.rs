//! What the scene probes (`solids_probe`, `stiff_probe`) share: a scene built from its name,
//! a method (its own by default) and `key=value` parameter overrides from the command line.

use physstep::scenes::{self, Scene};

/// Scene `name` under `method` (the scene's own when `None`) at its own dt, its parameters
/// overridden by `overrides` (`key=value` each); panics with what was wrong (a probe, not a
/// user-facing command).
pub fn build(name: &str, method: Option<&str>, overrides: &[String]) -> Scene {
    let params: Vec<(&str, f64)> = overrides
        .iter()
        .map(|kv| {
            let (k, v) = kv.split_once('=').expect("parameters as key=value");
            (k, v.parse().expect("a number"))
        })
        .collect();
    let spec = scenes::spec(name).expect("a scene");
    scenes::build(name, &params, method.unwrap_or(spec.method), spec.dt).expect("the scene builds")
}
