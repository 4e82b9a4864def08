//! The registries as one table each (issue 22): every method's line gives its name, its INFO,
//! its constructor and, when it is local, a fresh instance; what a stage asks of a method
//! (its constraint solver, whether its memory carries a vector, its solve statistics) comes
//! from the method, and no source outside the registry compares a method's name. Every
//! scene's line gives its name, its spec and its builder.

use std::path::{Path, PathBuf};

use physstep::integrators::{registry, ConstraintMode, ImplicitParams};
use physstep::prelude::*;

// ---------------------------------------------------------------- methods

#[test]
fn every_method_line_gives_its_name_info_and_constructor() {
    for (k, info) in INFOS.iter().enumerate() {
        assert_eq!(registry::names().nth(k), Some(info.name));
        assert_eq!(registry::info(info.name).unwrap().name, info.name);
        for m in [
            Integrator::new(info.name).unwrap(),
            Integrator::with_params(info.name, ImplicitParams::default()).unwrap(),
        ] {
            assert_eq!(m.info(), info, "{}", info.name);
            assert_eq!(m.memory().len(), m.memory_flags(), "{}: memory before a step", info.name);
            assert!(!m.carries(), "{}: carries a vector before a step", info.name);
            assert_eq!(m.solve_stats().is_some(), info.implicit, "{}: solve statistics", info.name);
            match m.fresh_local() {
                Some(fresh) => {
                    assert!(info.local, "{}: fresh_local of a method that is not local", info.name);
                    assert_eq!(fresh.info(), info);
                    assert!(fresh.memory().is_empty(), "{}: a local method has no memory", info.name);
                }
                None => assert!(!info.local, "{}: local without a fresh instance", info.name),
            }
        }
    }
}

/// The properties the stages used to read off the names (world/constraints.rs chose the
/// solver by name, the kernels' fresh_local listed the local methods), now in each INFO.
#[test]
fn the_infos_say_what_the_names_used_to() {
    for info in &INFOS {
        let mode = match info.name {
            "velocity-verlet" | "leapfrog" => ConstraintMode::Rattle,
            "verlet" => ConstraintMode::Jakobsen,
            _ => ConstraintMode::Project,
        };
        assert_eq!(info.constraints, mode, "{}", info.name);
        let local = !matches!(
            info.name,
            "symplectic-euler-alternating"
                | "verlet"
                | "leapfrog"
                | "backward-euler"
                | "implicit-midpoint"
                | "linearly-implicit-euler"
        );
        assert_eq!(info.local, local, "{}", info.name);
    }
}

/// A local method keeps nothing from step to step; a method whose memory carries a vector
/// says so once it has stepped, and forgets it on reset.
#[test]
fn memory_is_what_the_methods_say() {
    for info in &INFOS {
        let mut w = scenes::build("chain", &[("n", 3.0)], info.name, 1e-3).unwrap().world;
        w.step(3).unwrap();
        let m = w.integrator();
        if info.local {
            assert!(m.memory().is_empty(), "{}", info.name);
        }
        assert_eq!(m.carries(), m.memory().len() > m.memory_flags(), "{}", info.name);
        assert_eq!(m.carries(), matches!(info.name, "verlet" | "leapfrog"), "{}", info.name);
        let mut m = m.clone();
        m.reset();
        assert!(!m.carries(), "{}: carries after a reset", info.name);
    }
}

// ---------------------------------------------------------------- scenes

#[test]
fn every_scene_line_builds_its_own_scene() {
    for spec in scenes::SCENES {
        assert_eq!(scenes::spec(spec.name).unwrap(), spec);
        let scene = scenes::build(spec.name, &[], "rk4", spec.dt).unwrap();
        assert_eq!(scene.spec, spec, "{}", spec.name);
        assert_eq!(scene.world.dim(), spec.dim, "{}", spec.name);
        assert_eq!(scene.values, spec.params.iter().map(|p| p.default).collect::<Vec<_>>(), "{}", spec.name);
    }
}

// ---------------------------------------------------------------- no name checks

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// A stage asks a method's INFO or a method hook, never its name: no source of the engine or
/// the bindings compares a string with a registry name (`== "verlet"`, `"leapfrog" =>`, a
/// `|` of names in a match). The method files hold their names
/// as `name: "...",` in their INFO, which is not a comparison.
#[test]
fn no_method_name_is_compared_outside_the_registry() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = Vec::new();
    rust_files(&root.join("crates/physstep/src"), &mut files);
    rust_files(&root.join("crates/physstep-py/src"), &mut files);
    assert!(files.len() > 50, "found only {} sources under {}", files.len(), root.display());
    let mut found = Vec::new();
    for path in &files {
        let rel = path.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
        let text = std::fs::read_to_string(path).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for name in registry::names() {
                let q = format!("\"{name}\"");
                let compared = [
                    format!("== {q}"),
                    format!("!= {q}"),
                    format!("{q} =="),
                    format!("{q} !="),
                    format!("{q} =>"),
                    format!("{q} |"),
                    format!("| {q}"),
                ]
                .iter()
                .any(|p| code.contains(p.as_str()));
                if compared {
                    found.push(format!("{rel}:{}: {}", n + 1, line.trim()));
                }
            }
        }
    }
    assert!(found.is_empty(), "method names compared outside the registry:\n{}", found.join("\n"));
}
