//! Fuzzing the scene-file parser (proptest): any text, and files put together from the
//! schema's own keys and values, either load or are refused with one `Error::SceneFile` line;
//! nothing panics, and a world that loads steps without panicking. Random worlds of particles
//! written out and read back are bitwise the same.
//!
//! `PHYSSTEP_FUZZ_CASES` sets the cases per property (default 64, well under a second);
//! `scripts/fuzz.sh` runs it long. A failure prints the shrunk input: add it to
//! `regressions_stay_fixed` below.

use physstep::prelude::*;
use physstep::scenes::file;
use proptest::prelude::*;

fn cases() -> u32 {
    std::env::var("PHYSSTEP_FUZZ_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(64)
}

/// A fixed seed, so CI runs the same cases every time; `PROPTEST_RNG_SEED` picks another
/// (scripts/fuzz.sh gives each round its own).
fn seed() -> proptest::test_runner::RngSeed {
    let s = std::env::var("PROPTEST_RNG_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(1);
    proptest::test_runner::RngSeed::Fixed(s)
}

/// Loads `text`; checks the contract whatever happens.
fn check(text: &str) {
    match file::parse(text, "fuzz.toml") {
        Ok(mut f) => {
            // A loaded world steps or fails with an error, never a panic.
            let _ = f.world.step(3);
        }
        Err(e) => {
            assert!(matches!(e, Error::SceneFile { .. }), "{e:?}");
            let msg = e.to_string();
            assert!(msg.starts_with("scene file fuzz.toml"), "{msg}");
            assert!(!msg.contains('\n'), "{msg}");
        }
    }
}

const KEYS: [&str; 24] = [
    "dimension",
    "dt",
    "method",
    "until",
    "mass",
    "i",
    "j",
    "anchor",
    "kind",
    "position",
    "velocity",
    "static",
    "radius",
    "stiffness",
    "length",
    "min",
    "max",
    "point",
    "normal",
    "g",
    "shape",
    "state",
    "half_extents",
    "restitution",
];
const VALUES: [&str; 22] = [
    "1",
    "2",
    "3",
    "0",
    "-1",
    "0.5",
    "1e300",
    "-1e-320",
    "inf",
    "-inf",
    "nan",
    "\"rk4\"",
    "\"pin\"",
    "\"gravity\"",
    "\"distance\"",
    "\"box\"",
    "[0.0, 1.0]",
    "[1, 2, 3]",
    "[]",
    "true",
    "{ kind = \"sphere\", radius = 1 }",
    "99999999999999999999",
];
const TABLES: [&str; 8] = [
    "[[particles]]",
    "[[springs]]",
    "[[constraints]]",
    "[[forces]]",
    "[[bodies]]",
    "[collisions]",
    "[flow]",
    "[loop]",
];

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..KEYS.len(), 0..VALUES.len()).prop_map(|(k, v)| format!("{} = {}", KEYS[k], VALUES[v])),
        (0..TABLES.len()).prop_map(|t| TABLES[t].to_string()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), rng_seed: seed(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn any_text_loads_or_is_one_line(text in "\\PC{0,200}") {
        check(&text);
    }

    #[test]
    fn schema_shaped_files_load_or_are_one_line(dim in 1usize..=3, lines in prop::collection::vec(line(), 0..14)) {
        check(&format!("dimension = {dim}\n{}\n", lines.join("\n")));
    }

    #[test]
    fn worlds_of_particles_round_trip_bitwise(
        dim in 1usize..=3,
        parts in prop::collection::vec((prop::array::uniform3(-1e6..1e6f64), prop::array::uniform3(any::<i32>()), 1e-6..1e6f64, any::<bool>()), 1..6),
        k in 0.0..1e4f64,
    ) {
        let mut w = World::new(WorldParams { dim, method: "velocity-verlet".into(), dt: 0.01, ..Default::default() }).unwrap();
        for (x, v, m, fixed) in &parts {
            let v: Vec<f64> = v.iter().map(|c| f64::from(*c) * 1e-3).collect();
            w.add_particles(&x[..dim], Some(&v[..dim]), Some(&[*m]), *fixed).unwrap();
        }
        if parts.len() > 1 {
            w.add_force(Force::Spring { i: 0, j: Endpoint::Particle(1), stiffness: k, rest_length: 0.5, damping: 0.1 }).unwrap();
        }
        w.add_force(Force::Gravity { g: [0.0, -9.81, 1.0] }).unwrap();
        let text = file::export(&w, "fuzz", None).unwrap();
        let mut back = file::parse(&text, "fuzz.toml").unwrap().world;
        prop_assert_eq!(back.state_hash(), w.state_hash());
        let (a, b) = (w.step(5), back.step(5));
        prop_assert_eq!(a.is_ok(), b.is_ok());
        prop_assert_eq!(back.state_hash(), w.state_hash());
    }
}

/// Inputs the fuzzers found that once misbehaved.
#[test]
fn regressions_stay_fixed() {
    for text in [
        // A huge integer where a count is expected.
        "dimension = 99999999999999999999",
        // An integer that does not fit a u32 for the constraint sweeps.
        "dimension = 2\n[[particles]]\nposition = [0, 0]\n[[constraints]]\nkind = \"plane\"\nnormal = [0, 1]\nconstraint_iterations = 5000000000",
        "dimension = 2\nconstraint_iterations = 5000000000",
    ] {
        check(text);
    }
}
