//! Stiff spring networks under the implicit methods: the sparse Newton solve (force
//! Jacobians as 3 x 3 blocks, conjugate gradients) against the dense one, stability at a game
//! step where explicit methods explode, and memory that grows with the particles.

use physstep::integrators::ImplicitParams;
use physstep::linalg::{Blocks, CgParams, Preconditioner};
use physstep::prelude::*;
use physstep::scenes;

/// `stiff-chain` of `n` moving particles under `method`, the sparse solve taken above
/// `dense_up_to` unknowns.
fn chain(n: usize, method: &str, dense_up_to: usize) -> World {
    chain_with(n, method, ImplicitParams { dense_up_to, ..ImplicitParams::default() })
}

fn chain_with(n: usize, method: &str, params: ImplicitParams) -> World {
    let mut w = scenes::build("stiff-chain", &[("n", n as f64)], method, 1.0 / 60.0).unwrap().world;
    w.set_implicit(params).unwrap();
    w
}

#[test]
fn newton_with_conjugate_gradients_agrees_with_the_dense_solve() {
    for method in ["backward-euler", "implicit-midpoint"] {
        // Both solved well below the agreement asked for.
        let tight = ImplicitParams {
            tol: 1e-15,
            cg: CgParams { tol: 1e-13, max_iter: 1000, ..CgParams::default() },
            ..ImplicitParams::default()
        };
        let mut sparse = chain_with(12, method, ImplicitParams { dense_up_to: 0, ..tight });
        let mut dense = chain_with(12, method, ImplicitParams { dense_up_to: usize::MAX, ..tight });
        // Implicit midpoint damps nothing, so the solves' differences (1e-15 relative) grow
        // along a long run: the first steps are compared.
        let steps = if method == "backward-euler" { 120 } else { 20 };
        for step in 0..steps {
            sparse.step(1).unwrap();
            dense.step(1).unwrap();
            assert!(sparse.integrator().solve_stats().unwrap().sparse);
            assert!(!dense.integrator().solve_stats().unwrap().sparse);
            for (a, b) in sparse.positions().iter().zip(dense.positions()) {
                assert!((a - b).abs() <= 1e-10, "{method} step {step}: {a} vs {b}");
            }
            for (a, b) in sparse.velocities().iter().zip(dense.velocities()) {
                assert!((a - b).abs() <= 1e-10 * 60.0, "{method} step {step}: {a} vs {b}");
            }
        }
    }
}

#[test]
fn the_choice_of_solver_is_automatic_by_size() {
    let mut small = chain(5, "backward-euler", physstep::integrators::DENSE_UP_TO);
    let mut large = chain(40, "backward-euler", physstep::integrators::DENSE_UP_TO);
    small.step(1).unwrap();
    large.step(1).unwrap();
    assert!(!small.integrator().solve_stats().unwrap().sparse);
    let s = large.integrator().solve_stats().unwrap();
    assert!(s.sparse && s.newton >= 1 && s.cg >= s.newton && s.residual <= 1e-12, "{s:?}");
}

#[test]
fn backward_euler_is_stable_on_the_stiff_chain_where_symplectic_euler_explodes() {
    // k / m = 1e7 1/s^2 on 100 links at dt = 1/60: omega dt ~ 53 (explicit methods need < 2).
    let mut w = chain(100, "backward-euler", physstep::integrators::DENSE_UP_TO);
    let mut e = w.energy().unwrap();
    for step in 0..120 {
        w.step(1).unwrap();
        let next = w.energy().unwrap();
        assert!(next <= e + 1e-9 * e.abs(), "step {step}: energy rose from {e} to {next}");
        e = next;
    }
    // The chain hangs: every link near its rest length (1 cm) under the weight below it.
    let x = w.positions();
    for i in 1..=100 {
        let d = ((x[2 * i] - x[2 * i - 2]).powi(2) + (x[2 * i + 1] - x[2 * i - 1]).powi(2)).sqrt();
        assert!((d - 0.01).abs() < 1e-4, "link {i}: {d}");
    }
    let mut se = chain(100, "symplectic-euler", physstep::integrators::DENSE_UP_TO);
    let err = se.step(600).unwrap_err();
    assert!(matches!(err, Error::Diverged { particle: Some(_), .. }), "{err}");
    assert!(err.to_string().contains("symplectic-euler"), "{err}");
}

#[test]
fn the_sparse_solve_holds_memory_linear_in_the_particles() {
    // The blocks of a chain of n and of 4n particles: four times the bytes, where the dense
    // Jacobian of the larger one alone would be (4 n dim 2)^2 doubles.
    let bytes = |n: usize| {
        let cg = CgParams { max_iter: 20_000, ..CgParams::default() };
        let mut w = chain_with(
            n,
            "backward-euler",
            ImplicitParams { dense_up_to: 0, cg, ..ImplicitParams::default() },
        );
        w.step(1).unwrap();
        let mut b = Blocks::default();
        let mass = vec![0.01; n + 1];
        b.reset(2, &mass);
        b.pairs.reserve(n);
        (b.bytes(), w.integrator().solve_stats().unwrap().sparse)
    };
    let (small, s1) = bytes(100);
    let (large, s2) = bytes(400);
    assert!(s1 && s2);
    let ratio = large as f64 / small as f64;
    assert!((3.5..4.5).contains(&ratio), "{ratio}");
    // About 300 bytes a particle (two blocks and a link each), against the 20 MB of the
    // dense Jacobian of 1604 unknowns.
    assert!(large < 400 * 400, "{large} bytes for 400 particles");
}

#[test]
fn an_empty_world_steps_under_the_implicit_methods() {
    // Found by the property tests: the dense solve's stiffness measure split an empty
    // Jacobian into rows of zero length (a panic).
    for method in ["backward-euler", "implicit-midpoint"] {
        let mut w =
            World::new(WorldParams { dim: 1, method: method.into(), ..WorldParams::default() }).unwrap();
        w.step(3).unwrap();
        assert_eq!(w.steps(), 3);
    }
}

/// Steps `stiff-cloth` (`n` x `n`, k = 1e5 N/m, 10 g particles, dt = 1/60 s) `steps` times
/// with backward Euler, asserting after each step that it converged and that the energy did
/// not rise.
fn cloth_falls_with_the_energy_decaying(n: usize, steps: u64) {
    let mut w = scenes::build("stiff-cloth", &[("n", n as f64)], "backward-euler", 1.0 / 60.0).unwrap().world;
    let mut e = w.energy().unwrap();
    for step in 0..steps {
        w.step(1).unwrap_or_else(|err| panic!("step {step}: {err}"));
        let next = w.energy().unwrap();
        assert!(next <= e + 1e-9 * e.abs(), "step {step}: energy rose from {e} to {next}");
        e = next;
    }
}

#[test]
fn backward_euler_folds_a_stiff_cloth_with_the_energy_falling_at_every_step() {
    // The first 90 steps of the 32 x 32 cloth: it falls and folds about its pinned corners,
    // springs compressed past buckling, the slowest part of the full run below.
    cloth_falls_with_the_energy_decaying(32, 90);
    let mut se = scenes::build("stiff-cloth", &[("n", 32.0)], "symplectic-euler", 1.0 / 60.0).unwrap().world;
    let err = se.step(600).unwrap_err();
    assert!(matches!(err, Error::Diverged { particle: Some(_), .. }), "{err}");
}

#[test]
fn the_exact_jacobian_folds_the_cloth_in_a_quarter_of_the_newton_updates() {
    // The 12 x 12 cloth's first 60 steps (it falls and folds about its pinned corners):
    // backward Euler with the exact Jacobian where it is positive definite (the default)
    // against the semidefinite matrix alone. Both solve the same equation to the same
    // tolerance, with the energy falling at every step; the exact updates converge
    // quadratically where the semidefinite ones crawl.
    let run = |exact_jacobian: bool| {
        let mut w = scenes::build("stiff-cloth", &[("n", 12.0)], "backward-euler", 1.0 / 60.0).unwrap().world;
        w.set_implicit(ImplicitParams { exact_jacobian, ..ImplicitParams::default() }).unwrap();
        let (mut newton, mut e) = (0, w.energy().unwrap());
        for step in 0..60 {
            w.step(1).unwrap_or_else(|err| panic!("exact {exact_jacobian}, step {step}: {err}"));
            newton += w.integrator().solve_stats().unwrap().newton;
            let next = w.energy().unwrap();
            assert!(next < e, "exact {exact_jacobian}, step {step}: energy rose from {e} to {next}");
            e = next;
        }
        (newton, w)
    };
    let (exact, a) = run(true);
    let (semidefinite, _) = run(false);
    assert!(
        4 * exact <= semidefinite,
        "{exact} Newton updates with the exact Jacobian, {semidefinite} without"
    );
    // One step from the same state, each way: the same step to within Newton's tolerance
    // (the default's relative residual 1e-11 leaves velocities about 1e-6 of their size from
    // the converged step's on these springs: docs/stiff.md; here 3e-8 apart).
    let (mut x, mut y) = (a.clone(), a);
    y.set_implicit(ImplicitParams { exact_jacobian: false, ..ImplicitParams::default() }).unwrap();
    x.step(1).unwrap();
    y.step(1).unwrap();
    let scale = x.velocities().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (p, q) in x.velocities().iter().zip(y.velocities()) {
        assert!((p - q).abs() <= 1e-6 * scale, "{p} against {q} (scale {scale})");
    }
}

/// The whole run: 10,000 steps (about 3 minutes in release).
#[test]
#[ignore = "10,000 steps of a 32 x 32 stiff cloth: run with cargo test --release -- --ignored"]
fn backward_euler_holds_a_stiff_cloth_for_ten_thousand_steps() {
    cloth_falls_with_the_energy_decaying(32, 10_000);
}

#[test]
fn linearly_implicit_euler_is_backward_euler_on_a_linear_spring() {
    // A linear force: the equation linearised at the step's start is the equation itself, so
    // the one solve is backward Euler's converged step (to the rounding of the solves), at
    // omega dt = 100, with one update a step.
    let tight = ImplicitParams { tol: 1e-15, ..ImplicitParams::default() };
    let build = |method: &str| {
        let mut w = scenes::build("spring", &[("k", 1e6), ("m", 1.0)], method, 0.1).unwrap().world;
        w.set_implicit(tight).unwrap();
        w
    };
    let (mut lie, mut be) = (build("linearly-implicit-euler"), build("backward-euler"));
    let mut e = lie.energy().unwrap();
    for step in 0..50 {
        lie.step(1).unwrap();
        be.step(1).unwrap();
        let s = lie.integrator().solve_stats().unwrap();
        assert_eq!(s.newton, 1, "step {step}: {s:?}");
        let scale = be.positions()[0].abs().max(be.velocities()[0].abs() * 0.1).max(1e-300);
        for (a, b) in lie.positions().iter().zip(be.positions()) {
            assert!((a - b).abs() <= 1e-12 * scale, "step {step}: x {a} vs {b}");
        }
        let next = lie.energy().unwrap();
        assert!(next <= e, "step {step}: energy rose from {e} to {next}");
        e = next;
    }
}

#[test]
fn linearly_implicit_euler_hangs_the_stiff_chain_where_backward_euler_does_with_one_solve_a_step() {
    // The stiff chain's springs have a rest length (nonlinear): the one solve is not backward
    // Euler's step, and as it is (no halvings) its energy is not monotone: it rises on two of
    // the first steps, by 0.08 J at most, while the links turn fast. Halved there (the
    // default), the energy never rises. Either way it is stable at omega dt ~ 53, one sparse
    // solve a step but where a step is halved, and hangs the chain at its links' rest length,
    // with the energy of backward Euler's hanging chain.
    let mut be = chain(100, "backward-euler", physstep::integrators::DENSE_UP_TO);
    for _ in 0..300 {
        be.step(1).unwrap();
    }
    for halvings in [0, ImplicitParams::default().energy_halvings] {
        let params = ImplicitParams { energy_halvings: halvings, ..ImplicitParams::default() };
        let mut w = chain_with(100, "linearly-implicit-euler", params);
        let e0 = w.energy().unwrap();
        let (mut rises, mut halved, mut e) = (0, 0, e0);
        for step in 0..300 {
            w.step(1).unwrap();
            let s = w.integrator().solve_stats().unwrap();
            assert!(s.sparse && s.cg >= s.newton, "halvings {halvings}, step {step}: {s:?}");
            assert!(s.newton == 1 || halvings > 0, "step {step}: {s:?}");
            halved += usize::from(s.newton > 1);
            let next = w.energy().unwrap();
            assert!(next <= e0 + 0.1, "step {step}: energy {next} J against {e0} J at the start");
            rises += usize::from(next > e + 1e-9 * e.abs());
            e = next;
        }
        if halvings == 0 {
            assert!((1..=5).contains(&rises), "as it is, the energy rose on {rises} steps");
        } else {
            assert_eq!(rises, 0, "halved where it would rise, the energy rose on {rises} steps");
            assert!((1..=30).contains(&halved), "{halved} of 300 steps halved");
        }
        // Near the rest length: the top link carries the weight of the chain, 9.8 N / 1e5
        // N/m = 1e-4 m of stretch, and the chain still swings a little.
        let x = w.positions();
        for i in 1..=100 {
            let d = ((x[2 * i] - x[2 * i - 2]).powi(2) + (x[2 * i + 1] - x[2 * i - 1]).powi(2)).sqrt();
            assert!((d - 0.01).abs() < 2e-4, "link {i}: {d}");
        }
        let (e, e_be) = (w.energy().unwrap(), be.energy().unwrap());
        assert!((e - e_be).abs() < 0.05 * e_be.abs(), "hanging: {e} J against backward Euler's {e_be} J");
    }
}

/// The 32 x 32 `stiff-cloth` (k = 1e5 N/m, dt = 1/60) under the linearly implicit step with
/// `energy_halvings` for `steps` steps from rest: asserts no divergence and the cloth within
/// reach of its pinned corners at every step; returns the steps on which the energy rose (by
/// more than 1e-9 of itself), the steps halved, the most linear solves in a step, and the
/// energies at the start and the end.
fn lie_cloth(halvings: u32, steps: u64) -> (usize, usize, u32, f64, f64) {
    let mut w =
        scenes::build("stiff-cloth", &[("n", 32.0)], "linearly-implicit-euler", 1.0 / 60.0).unwrap().world;
    w.set_implicit(ImplicitParams { energy_halvings: halvings, ..ImplicitParams::default() }).unwrap();
    let e0 = w.energy().unwrap();
    let reach = w.positions().iter().fold(0.0f64, |m, v| m.max(v.abs())) * 2.0 + 1.0;
    let (mut rises, mut halved, mut most, mut e) = (0, 0, 0, e0);
    for step in 0..steps {
        w.step(1).unwrap_or_else(|err| panic!("step {step}: {err}"));
        let solves = w.integrator().solve_stats().unwrap().newton;
        halved += usize::from(solves > 1);
        most = most.max(solves);
        let far = w.positions().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(far < reach, "step {step}: a particle {far} m out, past {reach} m");
        let next = w.energy().unwrap();
        rises += usize::from(next > e + 1e-9 * e.abs());
        e = next;
    }
    (rises, halved, most, e0, e)
}

#[test]
fn linearly_implicit_euler_holds_the_folding_stiff_cloth_with_the_energy_never_rising() {
    // Through the fold, where springs buckle: as it is, one solve a step, the energy rises on
    // steps 18 to 32 (by up to 7 J); halved there (the default), it never rises, at the price
    // of a few steps of three solves.
    let (rises, halved, most, _, _) = lie_cloth(0, 40);
    assert!(rises >= 5 && halved == 0 && most == 1, "as it is: rose on {rises} steps, {halved} halved");
    let (rises, halved, most, e0, e) = lie_cloth(ImplicitParams::default().energy_halvings, 300);
    assert_eq!(rises, 0, "halved where it would rise, the energy rose on {rises} steps");
    assert!((1..=60).contains(&halved) && most <= 5, "{halved} of 300 steps halved, at most {most} solves");
    assert!(e < e0 - 1.0, "{e} J against {e0} J");
}

/// The whole run for the linearly implicit step: 10,000 steps (about 20 s in release).
#[test]
#[ignore = "10,000 steps of a 32 x 32 stiff cloth: run with cargo test --release -- --ignored"]
fn linearly_implicit_euler_holds_a_stiff_cloth_for_ten_thousand_steps_with_the_energy_never_rising() {
    let (rises, halved, most, e0, e) = lie_cloth(ImplicitParams::default().energy_halvings, 10_000);
    assert_eq!(rises, 0, "the energy rose on {rises} steps");
    assert!(halved <= 100 && most <= 5, "{halved} steps halved, at most {most} solves");
    assert!(e < e0 - 1.0, "{e} J against {e0} J");
}

/// `stiff-chain` of `n` links under backward Euler with the default settings but for the
/// preconditioner: `(Newton updates, CG iterations)` over `steps` steps, each step asserted
/// to converge with the energy not rising.
fn chain_counts(n: usize, steps: u64, preconditioner: Preconditioner) -> (u64, u64) {
    let cg = CgParams { preconditioner, ..CgParams::default() };
    let mut w = chain_with(n, "backward-euler", ImplicitParams { cg, ..ImplicitParams::default() });
    let (mut newton, mut iterations) = (0, 0);
    let mut e = w.energy().unwrap();
    for step in 0..steps {
        w.step(1).unwrap_or_else(|err| panic!("n = {n}, step {step}: {err}"));
        let s = w.integrator().solve_stats().unwrap();
        assert!(s.sparse && s.residual <= ImplicitParams::default().tol, "n = {n}, step {step}: {s:?}");
        newton += u64::from(s.newton);
        iterations += u64::from(s.cg);
        let next = w.energy().unwrap();
        assert!(next <= e + 1e-9 * e.abs(), "n = {n}, step {step}: energy rose from {e} to {next}");
        e = next;
    }
    (newton, iterations)
}

#[test]
fn backward_euler_converges_at_every_step_of_a_thousand_and_a_two_thousand_link_chain() {
    // Block Jacobi's conjugate gradients hit their cap of 1,000 iterations within the first
    // 30 steps at n = 1000 (the iterations grow with the chain's length); the incomplete
    // Cholesky factor of a chain is exact, and the solve takes one iteration an update.
    for n in [1000, 2000] {
        let (newton, cg) = chain_counts(n, 120, Preconditioner::default());
        assert!(cg <= 2 * newton, "n = {n}: {cg} CG iterations in {newton} Newton updates");
    }
}

#[test]
fn cg_iterations_per_newton_update_grow_at_most_like_the_square_root_of_the_chain() {
    // From n = 100 to 1000 the iterations an update may grow by sqrt(10) at most. Block
    // Jacobi's grew 4.7x here (69 to 323 an update, measured with a larger cap).
    let per_update = |n: usize| {
        let (newton, cg) = chain_counts(n, 60, Preconditioner::default());
        cg as f64 / newton as f64
    };
    let (short, long) = (per_update(100), per_update(1000));
    assert!(long <= 10f64.sqrt() * short, "{short} CG iterations an update at n = 100, {long} at n = 1000");
}

#[test]
fn the_earlier_preconditioners_keep_the_earlier_trajectories_bitwise() {
    // The recorded hashes of stiff-chain and stiff-cloth (n = 6; tests/it/determinism.rs,
    // 1,000 steps) before the incomplete Cholesky preconditioner and the line search became
    // the default, given still by block Jacobi with whole updates; before the complete
    // Cholesky factor became the default, given still by incomplete Cholesky; and the
    // semidefinite iteration of before the exact Jacobian became the default, given still by
    // `exact_jacobian: false` (its hashes moved from 0x53523eddea729e20 and 0xcbdb57539fcfea7e
    // when the factorisation's multiply-adds were fused: other roundings of the same sums).
    for (scene, params, jacobi, ic, semidefinite) in [
        (
            "stiff-chain",
            [("n", 100.0)],
            0xc243_32ff_08e0_15c0_u64,
            0xb85d_f278_b95d_a399_u64,
            0x52f7_50bd_0a73_4fc9_u64,
        ),
        ("stiff-cloth", [("n", 6.0)], 0xdc5a_56c5_afc9_ca06, 0xa2c4_f095_4767_846b, 0xd957_3e60_3f70_56e2),
    ] {
        for (preconditioner, line_search, exact_jacobian, want) in [
            (Preconditioner::BlockJacobi, false, true, jacobi),
            (Preconditioner::IncompleteCholesky, true, true, ic),
            (Preconditioner::Cholesky, true, false, semidefinite),
        ] {
            let mut w = scenes::build(scene, &params, "backward-euler", 1.0 / 60.0).unwrap().world;
            let cg = CgParams { preconditioner, ..CgParams::default() };
            w.set_implicit(ImplicitParams { cg, line_search, exact_jacobian, ..ImplicitParams::default() })
                .unwrap();
            w.step(1000).unwrap();
            assert_eq!(w.state_hash(), want, "{scene}, {preconditioner:?}: {:#018x}", w.state_hash());
        }
    }
}

#[test]
fn energy_halvings_past_sixteen_are_refused_naming_the_field() {
    let mut w = chain(10, "linearly-implicit-euler", physstep::integrators::DENSE_UP_TO);
    let err =
        w.set_implicit(ImplicitParams { energy_halvings: 17, ..ImplicitParams::default() }).unwrap_err();
    assert_eq!(err.to_string(), "invalid energy_halvings = 17: must be at most 16");
    let most =
        ImplicitParams { energy_halvings: physstep::integrators::MAX_ENERGY_HALVINGS, ..Default::default() };
    w.set_implicit(most).unwrap();
    w.step(3).unwrap();
}
