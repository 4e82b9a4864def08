//! Determinism you can check: every built-in scene, at its default parameters and step (but
//! see [`params`]),
//! after 1,000 steps has the recorded state hash below, run on one rayon thread and on two.
//!
//! The method is the command line's default, symplectic Euler, except for the first-order
//! flows (lorenz, rossler, thomas), which a split method refuses: those run RK4; and the stiff
//! spring networks, built to make explicit methods explode at their step: those run backward
//! Euler (its Newton and conjugate-gradient iterations are in the hash too). A change of
//! any hash means a change of the trajectory's bits: docs/determinism.md says which changes
//! (compiler flags, fused multiply-add, the target CPU, libm) may do that, and how to record
//! the new table (`PHYSSTEP_PRINT_HASHES=1 cargo test -p physstep --lib it::determinism::`).

use super::common;
use physstep::prelude::*;

/// Steps taken before the hash is read.
const STEPS: u64 = 1000;

/// `(scene, hash after STEPS steps)`, in registry order.
const HASHES: &[(&str, u64)] = &[
    ("spring", 0x283e5130c3fd2cfe),
    ("projectile", 0xfe742e718de6e989),
    ("drag", 0x5904922d8dd79415),
    ("orbit", 0x07686ceb5dbdea0e),
    ("kepler", 0x60338ab2d6f46ef5),
    ("pendulum", 0xaf0e1c261d108a91),
    ("nbody", 0x964dcb1557bd91eb),
    ("chain", 0xd505b63cd74f8d89),
    ("lorenz", 0x5ea31c43455e0f20),
    ("rossler", 0x553296e14b32b8b6),
    ("thomas", 0x903e8b72ee279c63),
    // The stiff scenes' Newton updates are solved by conjugate gradients preconditioned by
    // the complete sparse Cholesky factor (kept across a step's updates on the cloth) and
    // taken with a secant line search since those became the defaults (they iterate
    // differently: the converged steps differ within Newton's tolerance). Incomplete Cholesky
    // with the line search still gives the hashes of before the complete factor,
    // 0xb85df278b95da399 and 0xa2c4f0954767846b, and block Jacobi with whole updates those of
    // before either, 0xc24332ff08e015c0 and 0xdc5a56c5afc9ca06 (tests/it/stiff.rs checks both).
    // The supernodal factorisation (dense panels: other sums, the same solve to rounding)
    // moved them from 0xb310cb367afa1370 and 0xd36b27b35ac1f812. Backward Euler's exact
    // Jacobian where it is positive definite (ImplicitParams::exact_jacobian, the default
    // since 2026-11-27: other updates from another start, the same equation solved to the
    // same tolerance) moved them from 0x53523eddea729e20 and 0xcbdb57539fcfea7e, which
    // `exact_jacobian: false` still gave (tests/it/stiff.rs). The factorisation's fused
    // multiply-adds (one rounding where a product and a sum had two, crate::simd) moved them
    // from 0x444c949a951d345d and 0xd250e2761fbdf1c1.
    ("stiff-chain", 0xc479a870ff35559f),
    ("stiff-cloth", 0x770edd1cddefba86),
    ("racket", 0x61739902e34aadf3),
    ("top", 0xb2a0192949590096),
    ("tumble", 0x12edbb6dd7caa1c9),
    ("cloth", 0x955a06a8492adc26),
    ("ragdoll", 0x1453c0f1cb06b77e),
    ("balls", 0x1679bc483ce3c327),
    // The resting contacts' first position pass warm-started from the step before's pushes
    // (in the hash) and every pass ended at a tolerance: 0x39b1d9f604d9b80d before.
    ("pile", 0x8d6f28d96da81a33),
    // Jointed solids: the joints' accumulated impulses (their warm starts) are in the hash.
    ("bridge", 0x546ef4e2042a9537),
    ("ball-chain", 0xa4506a5822a60bf5),
    ("ragdoll-bodies", 0xbebe073633565fea),
    // The solids: their state (centres, orientations, velocities) and the contact solver's
    // warm starts (impulses and friction anchors) are in the hash. The 3D ones (dice,
    // box-stack, top-on-floor) changed when the solver took the gyroscopic term (implicit,
    // in each substep): before it, 0x2f4d8d2fd0930ff6, 0x23fdd53fbff5ff8d, 0x4b68088eed394caa;
    // dice's again when restitution took the speed a point arrives at in the substeps
    // (0x11eeac663ba0b255 before). Continuous collision on by default changed the three whose
    // solids move farther than the speculative distance in a step: single-box (0x7434a003af25819b
    // before: it lands at 4.4 m/s and ends step 26 2 mm above the ground, within the slop, and
    // is put back to 5 mm), dice (0xe12d6aa0b54a00f3: dice landing at 4 m/s put back to where
    // they met the ground, and a bounce's speed counted where the point meets it: restitution
    // 0.2; 0xf67c2427b388e742 with continuous collision off) and overlap-recovery
    // (0x125bedddd2c5ecc7: boxes pushed apart at 3 m/s put back to half the slop deep in the
    // ground). Every other scene's hash is the same with it on and off. The Gauss-Seidel passes
    // and the warm start in the coloured order (contact/passes.rs `colour`: no two pairs of a
    // colour share a moving solid, so the plane's passes solve four pairs at a time,
    // contact/lanes/) changed every scene whose solids touch more than one other solid:
    // ball-chain 0x8d833ce58d7ed934, stack 0x2104be3682e52717, pyramid 0xb8f8fbb5a96c4ce9,
    // box-stack 0xbced14b6178996ce, card-house 0xcc71da5258508cad, arch 0xa734c3429a2ba7e8,
    // domino 0x0cf04112d3d344af, overlap-recovery 0x8dd36e7e049bb7b9, far-pyramid
    // 0x78278320699bc517, far-ragdoll-pile 0xb4f02bedb96ef8fc, warm-start-energy
    // 0x7f7e5b229e6d4a88, rush 0x379db5f02c16412e, double-domino 0x0a8d7680159b2b96,
    // stretched-chain 0x5b383962a9384e2f, ragdoll-stress 0x00198f03ccefe0b5 before; a scene
    // whose pairs all have the ground on one side (dice, single-box, ramp) kept its order.
    // Each point of a manifold a warm-start key of its own (contact/space/mod.rs `pack`: parry
    // gives both points where two boxes' faces meet in the plane the same pair of features, so one
    // point took the other's impulses and friction anchors) changed the plane's scenes with boxes:
    // single-box 0x123a5637dcd44b2c, stack 0x798eed07e0dbcac3, pyramid 0x41c9b3082ae0d5ba, ramp
    // 0xf36466dc6ac98179, card-house 0xa392014df5e3e8b6, mass-ratio 0x4e08a0c07fc13013, domino
    // 0x50432bdcc3a69633, overlap-recovery 0x5760714882974d00, far-pyramid 0xfef00d9cea5596ef,
    // high-mass-ratio 0x25413f71ea4bdd15, friction-ramp 0xbdb8916ef011cf02, double-domino
    // 0xcd53947c53dda832 before; the 3D scenes kept theirs. The gyroscopic term skipped for a
    // solid whose inertia is a multiple of the identity (contact/space/space3.rs: `w x I w` is
    // zero, w kept exactly where the Newton step gave it back with the roundings of two
    // rotations and a solve) changed the 3D scenes of cubes: dice 0xf47227f87f63b3b9, box-stack
    // 0x4c1b8096e82df1dc before (top-on-floor, not isotropic, kept its own).
    ("single-box", 0x054578c00ac3463a),
    ("stack", 0x089341fb9e91a210),
    ("pyramid", 0xf56bf326eeb5081c),
    ("ramp", 0xa222024510cadc80),
    ("dice", 0x316438ec3abb9dcb),
    ("box-stack", 0xe0a295f4899f4306),
    // The rest of Solver2D's contact scenes, and the top on the floor.
    ("card-house", 0x4abac865f20192d1),
    ("mass-ratio", 0x4e65ec2b80dd0374),
    ("arch", 0x8a86ed2e91139d04),
    ("domino", 0xb199199d439b8db6),
    ("confined", 0x3c90b23d6e53b116),
    ("overlap-recovery", 0x4efe17f6c6924f48),
    ("top-on-floor", 0x1bd57401a02cf40e),
    // Solver2D's scenes that break solvers (tests/it/breaking_scenes.rs).
    ("far-pyramid", 0x8dfbdab83a1f3435),
    ("far-ragdoll-pile", 0x79582665faa839c8),
    ("high-mass-ratio", 0x345be2ab1554cc95),
    ("friction-ramp", 0xdc2e185eb7f9f3ec),
    ("warm-start-energy", 0x8475c2d12f92772e),
    ("rush", 0xd840c58cfc2d7ce1),
    ("double-domino", 0x4b948f1159600117),
    ("joint-grid", 0x32ac77f293441d6e),
    ("stretched-chain", 0x298f12f6ce3a8e2e),
    ("far-chain", 0x7ba6c602c7779bd5),
    ("ragdoll-stress", 0xe78c4be35e6e93cb),
];

/// The parameters a scene's hash is recorded with: its defaults, but for stiff-cloth, whose
/// 12 x 12 default takes 12 s for 1,000 backward-Euler steps in the test profile (6 x 6: 1 s),
/// pile (200 balls), pyramid (10 rows, 55 boxes), confined (12 x 12 circles: 25 x 25 take
/// 4 s), and of the scenes that break solvers: high-mass-ratio's variant 2 (4 boxes, not
/// 166), rush (50 circles), joint-grid (10 x 10) and ragdoll-stress (4 ragdolls).
fn params(scene: &str) -> &'static [(&'static str, f64)] {
    if scene == "high-mass-ratio" {
        &[("variant", 2.0)]
    } else if scene == "rush" {
        &[("n", 50.0)]
    } else if scene == "joint-grid" {
        &[("n", 10.0)]
    } else if scene == "ragdoll-stress" {
        &[("n", 4.0)]
    } else if scene == "stiff-cloth" {
        &[("n", 6.0)]
    } else if scene == "pile" {
        &[("n", 200.0)]
    } else if scene == "pyramid" {
        &[("rows", 10.0)]
    } else if scene == "confined" {
        &[("n", 12.0)]
    } else {
        &[]
    }
}

/// The hash of `scene` after `STEPS` steps on a pool of `threads` rayon threads.
fn hash(scene: &str, threads: usize) -> u64 {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        let spec = scenes::spec(scene).unwrap();
        let mut s = scenes::build(scene, params(scene), common::recorded_method(scene), spec.dt).unwrap();
        s.world.step(STEPS).unwrap();
        assert_eq!(s.world.steps(), STEPS, "{scene}");
        s.world.state_hash()
    })
}

#[test]
fn the_table_names_every_scene_in_registry_order() {
    let names: Vec<&str> = scenes::SCENES.iter().map(|s| s.name).collect();
    let table: Vec<&str> = HASHES.iter().map(|(n, _)| *n).collect();
    assert_eq!(names, table);
}

#[test]
fn every_scene_has_its_recorded_hash_on_one_thread_and_on_two() {
    let print = std::env::var_os("PHYSSTEP_PRINT_HASHES").is_some();
    let mut wrong = Vec::new();
    for &(scene, want) in HASHES {
        let start = std::time::Instant::now();
        let one = hash(scene, 1);
        if print {
            eprintln!("{scene}: {:.2} s for {STEPS} steps", start.elapsed().as_secs_f64());
        }
        let two = hash(scene, 2);
        assert_eq!(one, two, "{scene}: one thread and two threads differ");
        if print {
            println!("    (\"{scene}\", {one:#018x}),");
        }
        if one != want {
            wrong.push(format!("{scene}: {one:#018x}, recorded {want:#018x}"));
        }
    }
    assert!(wrong.is_empty(), "hashes changed (see docs/determinism.md):\n{}", wrong.join("\n"));
}

#[test]
fn the_hash_sees_a_one_bit_change() {
    let mut a = scenes::build("chain", &[], "symplectic-euler", 1e-3).unwrap();
    let mut b = a.clone();
    let mut x = b.world.positions().to_vec();
    x[2] = f64::from_bits(x[2].to_bits() ^ 1);
    b.world.set_positions(&x).unwrap();
    a.world.step(100).unwrap();
    b.world.step(100).unwrap();
    assert_ne!(a.world.state_hash(), b.world.state_hash());
}

/// The scan of the balls runs its chunks on the rayon pool above 16,384 balls: 20,000 balls
/// take the same bits on one thread and on two.
#[test]
fn twenty_thousand_balls_take_the_same_bits_on_one_thread_and_on_two() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let p = [("n", 20_000.0), ("fraction", 0.3)];
            let mut s = scenes::build("balls", &p, "symplectic-euler", 1.0 / 120.0).unwrap();
            s.world.step(20).unwrap();
            assert!(s.world.collisions().count > 1000, "{:?}", s.world.collisions());
            s.world.state_hash()
        })
    };
    assert_eq!(run(1), run(2));
}
