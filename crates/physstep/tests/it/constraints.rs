//! Position constraints (issue 11, the constraints half): the pendulum's rod under
//! SHAKE/RATTLE, the cloth's relaxation, the ragdoll on the ground, the memory and state
//! kept consistent, rollback, and bad input.

use physstep::constraints::Constraint;
use physstep::prelude::*;

fn world(method: &str, dim: usize) -> World {
    World::new(WorldParams { dim, method: method.into(), dt: 0.01, ..WorldParams::default() }).unwrap()
}

#[test]
fn pendulum_keeps_its_rod_under_rattle_for_144000_steps() {
    // The scene's default dt (0.01 s), velocity Verlet: RATTLE.
    let mut scene = scenes::build("pendulum", &[], "velocity-verlet", 0.01).unwrap();
    let w = &mut scene.world;
    assert_eq!(w.constraints().list().len(), 1);
    let e0 = w.energy().unwrap();
    let (mut worst_len, mut worst_v) = (0.0f64, 0.0f64);
    let mut tenths = [0.0f64; 10];
    for k in 0..1440 {
        w.step(100).unwrap();
        let (x, v) = (w.positions(), w.velocities());
        worst_len = worst_len.max((x[0].hypot(x[1]) - 1.0).abs());
        worst_v = worst_v.max((x[0] * v[0] + x[1] * v[1]).abs());
        let t = k / 144;
        tenths[t] = tenths[t].max((w.energy().unwrap() - e0).abs());
    }
    assert_eq!(w.steps(), 144_000);
    assert!(worst_len < 1e-9, "rod length error {worst_len:e}");
    assert!(worst_v < 1e-9, "velocity along the rod {worst_v:e}");
    // Bounded, no drift: second order (|dE| ~ dt^2 g L), the last tenth no worse than the first.
    let (first, last) = (tenths[0], tenths[9]);
    assert!(first < 1e-3 * e0.abs() && first > 0.0, "energy error {first:e} of {e0}");
    assert!(last <= 1.1 * first, "energy error drifts: first tenth {first:e}, last {last:e}");
    println!("pendulum: rod {worst_len:e}, v.d {worst_v:e}, |dE| first {first:e} last {last:e}");
}

#[test]
fn rattle_is_second_order_and_projection_first() {
    // Position error at t = 2 s against a run at dt / 64, for dt and dt / 2.
    let run = |method: &str, dt: f64| {
        let mut s = scenes::build("pendulum", &[], method, dt).unwrap();
        s.world.step((2.0 / dt).round() as u64).unwrap();
        s.world.positions().to_vec()
    };
    for (method, order) in [("velocity-verlet", 2.0), ("leapfrog", 2.0), ("symplectic-euler", 1.0)] {
        let truth = run(method, 0.02 / 64.0);
        let err = |dt: f64| {
            let x = run(method, dt);
            (x[0] - truth[0]).hypot(x[1] - truth[1])
        };
        let ratio = err(0.02) / err(0.01);
        let observed = ratio.log2();
        assert!((observed - order).abs() < 0.3, "{method}: observed order {observed}");
    }
}

#[test]
fn cloth_violation_falls_as_iterations_rise() {
    // One step from the same swinging cloth, relaxed with more and more sweeps.
    let over = [("w", 12.0), ("h", 12.0), ("wind", 3.0)];
    let mut base = scenes::build("cloth", &over, "verlet", 1.0 / 120.0).unwrap().world;
    base.set_constraint_iterations(4).unwrap();
    base.step(60).unwrap();
    let mut last = f64::INFINITY;
    let mut seen = Vec::new();
    for iterations in [1, 2, 4, 8, 16, 32, 64] {
        let mut w = base.clone();
        w.set_constraint_iterations(iterations).unwrap();
        w.step(1).unwrap();
        let v = w.constraint_violation();
        seen.push((iterations, v));
        assert!(v < last, "violation {v:e} at {iterations} iterations, {last:e} with fewer: {seen:?}");
        last = v;
    }
    assert!(seen[0].1 > 1.5 * last, "{seen:?}");
    println!("cloth 12x12 violation after one step by iterations: {seen:?}");
}

/// A 32 x 32 cloth hanging for `steps` steps of 1/120 s stays whole, its stretch bounded and
/// not growing, and comes to rest.
fn cloth_hangs(steps: u64) {
    let mut scene = scenes::build("cloth", &[("w", 32.0), ("h", 32.0)], "verlet", 1.0 / 120.0).unwrap();
    let w = &mut scene.world;
    let mut seen = Vec::new();
    for _ in 0..20 {
        w.step(steps / 20).unwrap();
        seen.push(w.constraint_violation());
    }
    let x = w.positions();
    assert!(x.iter().all(|c| c.is_finite() && c.abs() < 10.0));
    let worst = seen.iter().fold(0.0f64, |m, v| m.max(*v));
    assert!(worst < 0.2 * 0.1, "violation {worst:e} (spacing 0.1 m): {seen:?}");
    let (early, late) = (seen[1].max(seen[2]), seen[18].max(seen[19]));
    assert!(late <= 1.05 * early, "stretch grows: {seen:?}");
    let vmax = w.velocities().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(vmax < 0.05, "still moving at {vmax} m/s");
    println!("cloth 32x32, {steps} steps: violation {seen:?}, max speed {vmax:e}");
}

#[test]
fn cloth_32x32_hangs_for_a_while() {
    cloth_hangs(1_200);
}

/// The full 20 minutes at 120 Hz: run with `cargo test --release -- --ignored`.
#[test]
#[ignore = "144,000 steps of a 32 x 32 cloth: run in release"]
fn cloth_32x32_hangs_for_144000_steps() {
    cloth_hangs(144_000);
}

#[test]
fn ragdoll_lands_on_the_ground_in_one_piece() {
    for method in ["verlet", "velocity-verlet", "symplectic-euler"] {
        let mut scene = scenes::build("ragdoll", &[], method, 1.0 / 120.0).unwrap();
        let w = &mut scene.world;
        let mut lowest = f64::INFINITY;
        for _ in 0..360 {
            w.step(1).unwrap();
            lowest =
                lowest.min(w.positions().iter().skip(1).step_by(2).fold(f64::INFINITY, |m, y| m.min(*y)));
        }
        assert!(lowest > -1e-9, "{method}: a particle went {lowest} into the ground");
        assert!(w.constraint_violation() < 1e-2, "{method}: violation {}", w.constraint_violation());
        let top = w.positions().iter().skip(1).step_by(2).fold(f64::NEG_INFINITY, |m, y| m.max(*y));
        assert!(top < 1.0, "{method}: it lies on the ground (top at {top})");
    }
}

#[test]
fn verlet_memory_is_resynced_so_a_pin_holds_at_rest() {
    let mut w = world("verlet", 2);
    w.add_particle(&[0.0, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
    w.add_particle(&[1.0, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    w.add_pin(0, &[0.0, 0.0]).unwrap();
    w.add_distance_constraint(1, Endpoint::Particle(0), None, 0.0).unwrap();
    for _ in 0..500 {
        let before = w.positions().to_vec();
        w.step(1).unwrap();
        let (x, v) = (w.positions(), w.velocities());
        assert_eq!(&x[..2], &[0.0, 0.0]);
        // The state's velocity is the motion the step made (Jakobsen's implied velocity).
        for k in 0..4 {
            let implied = (x[k] - before[k]) / 0.01;
            assert!((v[k] - implied).abs() < 1e-9, "v[{k}] {} vs {implied}", v[k]);
        }
    }
    assert!((w.constraint_violation()) < 1e-6);
    // The memory restarts from the relaxed state (x_prev = x - v h on the next step): the
    // same as a world given that state by hand.
    let (x, v) = (w.positions().to_vec(), w.velocities().to_vec());
    let mut fresh = w.clone();
    fresh.set_positions(&x).unwrap();
    fresh.set_velocities(&v).unwrap();
    w.step(1).unwrap();
    fresh.step(1).unwrap();
    assert_eq!(w.positions(), fresh.positions());
    assert_eq!(w.velocities(), fresh.velocities());
}

#[test]
fn the_derivative_is_fresh_after_the_relax_stage() {
    for method in ["verlet", "velocity-verlet", "rk4", "leapfrog", "backward-euler"] {
        let mut scene = scenes::build("ragdoll", &[("height", 0.05)], method, 1.0 / 120.0).unwrap();
        scene.world.add_force(Force::Drag { linear: 0.3, quadratic: 0.1 }).unwrap();
        scene.world.step(40).unwrap();
        let a = scene.world.accelerations().unwrap().to_vec();
        let mut again = scene.world.clone();
        let x = again.positions().to_vec();
        again.set_positions(&x).unwrap();
        assert_eq!(again.accelerations().unwrap(), &a[..], "{method}");
    }
}

#[test]
fn many_steps_in_one_call_are_the_same_bits_as_one_at_a_time() {
    for method in ["verlet", "velocity-verlet", "rk4", "symplectic-euler"] {
        let mut a =
            scenes::build("cloth", &[("w", 6.0), ("h", 5.0), ("wind", 2.0)], method, 0.01).unwrap().world;
        let mut b = a.clone();
        a.step(50).unwrap();
        for _ in 0..50 {
            b.step(1).unwrap();
        }
        assert_eq!(a.state_hash(), b.state_hash(), "{method}");
        assert_eq!(a.positions(), b.positions());
    }
}

#[test]
fn a_diverging_step_rolls_back_with_its_constraints() {
    // A stiff spring under explicit Euler at a large dt runs away; a rope and a plane that
    // act on the way make the Relax stage part of every step.
    let build = || {
        let mut w = world("explicit-euler", 2);
        w.add_particle(&[0.0, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
        w.add_particle(&[1.5, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
        w.add_force(Force::Spring {
            i: 0,
            j: Endpoint::Particle(1),
            stiffness: 1e4,
            rest_length: 1.0,
            damping: 0.0,
        })
        .unwrap();
        w.add_rope(0, Endpoint::Anchor([0.0, 0.0, 0.0]), 1e60).unwrap();
        w.add_plane(&[0.0, 1.0], -1e60).unwrap();
        w
    };
    let mut one = build();
    let mut hashes = vec![one.state_hash()];
    let failed = loop {
        match one.step(1) {
            Ok(()) => hashes.push(one.state_hash()),
            Err(e) => break e,
        }
        assert!(hashes.len() < 10_000, "never diverged");
    };
    assert!(matches!(failed, Error::Diverged { .. }), "{failed:?}");
    assert_eq!(one.state_hash(), *hashes.last().unwrap(), "the failed step is rolled back");
    let mut call = build();
    assert!(call.step(100_000).is_err());
    assert_eq!(call.state_hash(), one.state_hash(), "a call's checkpoint and replay agree");
    assert_eq!(call.steps(), (hashes.len() - 1) as u64);
}

#[test]
fn state_hash_snapshot_and_clone_carry_the_constraints() {
    let mut a = scenes::build("ragdoll", &[], "velocity-verlet", 1.0 / 120.0).unwrap().world;
    let mut b = a.clone();
    b.add_plane(&[1.0, 0.0], -5.0).unwrap();
    assert_ne!(a.state_hash(), b.state_hash(), "constraints are part of the hash");
    b.set_constraint_iterations(3).unwrap();
    let mut c = a.clone();
    c.set_constraint_iterations(3).unwrap();
    assert_ne!(a.state_hash(), c.state_hash(), "so is the sweep count");
    a.step(30).unwrap();
    let snap = a.snapshot();
    let mut d = a.clone();
    a.step(30).unwrap();
    d.restore(&snap).unwrap();
    d.step(30).unwrap();
    assert_eq!(a.state_hash(), d.state_hash());
    // A snapshot goes only into a world with the same constraints.
    let before = b.state_hash();
    let m = msg(b.restore(&snap));
    assert!(m.contains("taken with other constraints"), "{m}");
    assert_eq!(b.state_hash(), before);
    let mut bare = World::new(WorldParams {
        method: "velocity-verlet".into(),
        dt: 1.0 / 120.0,
        ..WorldParams::default()
    })
    .unwrap();
    let x = a.positions().to_vec();
    bare.add_particles(&x, None, None, false).unwrap();
    assert!(bare.restore(&snap).is_err());
}

fn msg<T: std::fmt::Debug>(r: Result<T>) -> String {
    r.unwrap_err().to_string()
}

#[test]
fn bad_constraints_name_the_field_and_leave_the_world_unchanged() {
    let mut w = world("verlet", 2);
    w.add_particles(&[0.0, 0.0, 1.0, 0.0, 2.0, 0.0], None, None, false).unwrap();
    let p = Endpoint::Particle;
    let before = (w.state_hash(), w.constraints().fingerprint());
    let cases: Vec<(Result<usize>, &str)> = vec![
        (w.add_distance_constraint(3, p(0), None, 0.0), "invalid i = 3: must be a particle index < 3"),
        (w.add_distance_constraint(0, p(7), Some(1.0), 0.0), "invalid j = 7: must be a particle index < 3 other than i = 0"),
        (w.add_distance_constraint(1, p(1), None, 0.0), "invalid j = 1: must be a particle index < 3 other than i = 1"),
        (w.add_distance_constraint(0, p(1), Some(-1.0), 0.0), "invalid length = -1: must be a finite number > 0"),
        (w.add_distance_constraint(0, p(1), Some(f64::NAN), 0.0), "invalid length = NaN: must be a finite number > 0"),
        (w.add_distance_constraint(0, p(1), None, -0.5), "invalid compliance = -0.5: must be a finite number >= 0"),
        (w.add_distance_constraint(0, p(1), None, f64::NAN), "invalid compliance = NaN: must be a finite number >= 0"),
        (w.add_rope(0, p(1), 0.0), "invalid max_length = 0: must be a finite number > 0"),
        (w.add_rope(0, p(2), f64::INFINITY), "invalid max_length = inf: must be a finite number > 0"),
        (w.add_distance_limit(0, p(1), 2.0, 1.0), "invalid max_length = 1: must be >= min_length = 2"),
        (w.add_pin(5, &[0.0, 0.0]), "invalid i = 5: must be a particle index < 3"),
        (w.add_pin(0, &[0.0, f64::NAN]), "invalid point[1] = NaN: must be finite, at most 1e100 in magnitude"),
        (w.add_pin(0, &[0.0]), "invalid len(point) = 1: must be 2, the world's dim"),
        (w.add_plane(&[0.0, 0.0], 0.0), "invalid normal = (0, 0): must be a nonzero vector"),
        (w.add_plane(&[0.0, 1.0], f64::NAN), "invalid offset = NaN: must be finite, at most 1e100 in magnitude"),
        (
            w.add_distance_constraint(0, Endpoint::Anchor([0.0; 3]), None, 0.0),
            "invalid length = 0: must be a finite number > 0 (it defaults to the current distance, and the ends coincide)",
        ),
    ];
    for (r, want) in cases {
        assert_eq!(msg(r), want);
    }
    assert_eq!(
        msg(w.set_constraint_iterations(0)),
        "invalid constraint_iterations = 0: must be a whole number from 1 to 1000000"
    );
    assert_eq!(w.constraint_iterations(), physstep::constraints::DEFAULT_ITERATIONS);
    assert_eq!((w.state_hash(), w.constraints().fingerprint()), before);
    assert!(w.constraints().is_empty());
    // A flow takes none.
    let mut flow = World::with_flow(
        physstep::flows::Flow::Lorenz { sigma: 10.0, rho: 28.0, beta: 8.0 / 3.0 },
        &[1.0, 1.0, 1.0],
        WorldParams { method: "rk4".into(), ..WorldParams::default() },
    )
    .unwrap();
    assert!(msg(flow.add_constraint(Constraint::Plane { normal: [0.0, 0.0, 1.0], offset: 0.0 }))
        .contains("constraint"));
}

#[test]
fn soft_distances_stretch_by_their_compliance() {
    // A mass hanging on a soft link: XPBD's static stretch is m g * compliance, whatever the
    // number of sweeps.
    for iterations in [1, 4, 32] {
        let mut w = world("verlet", 2);
        w.add_particle(&[0.0, -1.0], &[0.0, 0.0], 2.0, false).unwrap();
        w.add_force(Force::Gravity { g: [0.0, -10.0, 0.0] }).unwrap();
        w.add_force(Force::Drag { linear: 2.0, quadratic: 0.0 }).unwrap();
        w.add_distance_constraint(0, Endpoint::Anchor([0.0; 3]), Some(1.0), 1e-3).unwrap();
        w.set_constraint_iterations(iterations).unwrap();
        w.step(3000).unwrap();
        let stretch = -w.positions()[1] - 1.0;
        assert!((stretch - 0.02).abs() < 2e-3, "{iterations}: stretch {stretch}");
    }
}

#[test]
fn projected_methods_leave_no_velocity_along_a_rod() {
    // Explicit Euler and RK4 move positions with other velocities than the one they end
    // with: after the projection, RATTLE's velocity step leaves none along the rod. Verlet
    // keeps Jakobsen's secant velocity (with a radial part of order h).
    for method in ["explicit-euler", "rk4", "midpoint", "backward-euler", "symplectic-euler"] {
        let mut scene = scenes::build("pendulum", &[], method, 0.01).unwrap();
        for _ in 0..50 {
            scene.world.step(7).unwrap();
            let (x, v) = (scene.world.positions(), scene.world.velocities());
            assert!(
                (x[0] * v[0] + x[1] * v[1]).abs() < 1e-12,
                "{method}: v . d = {}",
                x[0] * v[0] + x[1] * v[1]
            );
            assert!((x[0].hypot(x[1]) - 1.0).abs() < 1e-12, "{method}");
        }
    }
}
