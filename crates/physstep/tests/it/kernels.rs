//! The fused particle kernels give bitwise what the staged step gives, for every method and
//! force mix, in every dimension, serial and parallel; and a step that fails inside a call
//! of `step(n)` is rolled back to exactly the state before it and named, as the staged step
//! does it; a recording of every step (the small-world kernel included) is the staged one.
//!
//! `World::step_logged` always takes the staged step (one method recipe over the whole
//! state, the per-step checkpoint): it is the reference here.

use physstep::forces::{Endpoint, Force};
use physstep::integrators::{registry, StageLog};
use physstep::prelude::*;

/// A world of `n` particles in `dim` dimensions with `forces`, deterministic pseudo-random
/// state and masses (all 1.5 when `equal`: the kernels' uniform-mass path), one static
/// particle when `with_static`.
pub(super) fn world(
    method: &str,
    dim: usize,
    n: usize,
    forces: &[Force],
    with_static: bool,
    equal: bool,
) -> World {
    let mut w = World::new(WorldParams { dim, method: method.into(), dt: 1.0 / 120.0, ..Default::default() })
        .unwrap();
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let x: Vec<f64> = (0..n * dim).map(|_| 4.0 * rnd()).collect();
    let v: Vec<f64> = (0..n * dim).map(|_| 2.0 * rnd()).collect();
    let m: Vec<f64> = (0..n).map(|_| if equal { 1.5 } else { 1.0 + rnd() }).collect();
    w.add_particles(&x, Some(&v), Some(&m), false).unwrap();
    if with_static {
        w.add_particle(&vec![0.5; dim], &vec![0.0; dim], 1.0, true).unwrap();
    }
    for f in forces {
        w.add_force(*f).unwrap();
    }
    w
}

/// Steps `w` one staged step at a time until one fails: the good steps and the error.
pub(super) fn staged_failure(w: &mut World, what: &str) -> (u64, physstep::Error) {
    let mut log = StageLog::default();
    let mut good = 0;
    loop {
        match w.step_logged(w.dt(), &mut log) {
            Ok(()) => good += 1,
            Err(e) => return (good, e),
        }
        assert!(good < 100_000, "{what}: never diverged");
    }
}

pub(super) fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The force mixes: the element-wise kernel's (gravity and linear drag, either alone), and the
/// per-particle ones that take the tile kernel (quadratic drag, central gravity, springs to
/// anchors, with and without rest length and damping).
fn mixes() -> Vec<(&'static str, Vec<Force>)> {
    let g = Force::Gravity { g: [0.3, -9.81, 1.5] };
    let lin = Force::Drag { linear: 0.4, quadratic: 0.0 };
    let quad = Force::Drag { linear: 0.1, quadratic: 0.05 };
    let central = Force::CentralGravity { center: [0.1, 0.2, 0.3], gm: 2.0 };
    let anchor = |i, rest, damping| Force::Spring {
        i,
        j: Endpoint::Anchor([1.0, -1.0, 0.5]),
        stiffness: 3.0,
        rest_length: rest,
        damping,
    };
    vec![
        ("none", vec![]),
        ("gravity", vec![g]),
        ("drag", vec![lin]),
        ("gravity+drag", vec![g, lin]),
        ("quadratic drag", vec![g, quad]),
        ("central", vec![central]),
        (
            "anchors",
            vec![g, anchor(0, 0.0, 0.2), anchor(0, 1.5, 0.3), anchor(2, 0.7, 0.0), anchor(5, 0.0, 0.0)],
        ),
    ]
}

/// Steps `a` with `step(n)` (the kernel) and `b` step by step through `step_logged` (the staged
/// step); both must agree bitwise on the state, the accelerations, time and evaluations.
/// (An implicit method whose Newton iteration fails must fail the same way in both.)
pub(super) fn agree(a: &mut World, b: &mut World, steps: u64, what: &str) {
    let ra = a.step(steps);
    let mut log = StageLog::default();
    let rb = (0..steps).try_for_each(|_| b.step_logged(b.dt(), &mut log));
    assert_eq!(ra.as_ref().map_err(ToString::to_string), rb.as_ref().map_err(ToString::to_string), "{what}");
    assert_eq!(bits(a.positions()), bits(b.positions()), "{what}: positions");
    assert_eq!(bits(a.velocities()), bits(b.velocities()), "{what}: velocities");
    assert_eq!(bits(a.accelerations().unwrap()), bits(b.accelerations().unwrap()), "{what}: accelerations");
    assert_eq!(a.time().to_bits(), b.time().to_bits(), "{what}: time");
    assert_eq!(a.evals(), b.evals(), "{what}: evaluations");
    assert_eq!(a.state_hash(), b.state_hash(), "{what}: hash");
}

#[test]
fn kernels_match_the_staged_step_bitwise() {
    for info in registry::INFOS.iter() {
        for (name, forces) in mixes() {
            for dim in 1..=3 {
                for (n, with_static, equal) in [
                    (1, false, false),
                    (7, true, false),
                    (37, false, false),
                    (37, false, true),
                    (9, true, true),
                ] {
                    if forces.len() > 2 && n < 6 {
                        continue; // springs name particles up to 5
                    }
                    let mut a = world(info.name, dim, n, &forces, with_static, equal);
                    let mut b = a.clone();
                    let what = format!("{} on {name}, dim {dim}, n {n}", info.name);
                    agree(&mut a, &mut b, 25, &what);
                    // Calls of several sizes continue the same trajectory.
                    agree(&mut a, &mut b, 1, &what);
                    agree(&mut a, &mut b, 3, &what);
                }
            }
        }
    }
}

#[test]
fn parallel_kernels_match_the_staged_step_bitwise() {
    // Above the kernels' parallel threshold (65,536 particles), with partial tiles and blocks.
    let n = 4 * 16384 + 5;
    for method in ["symplectic-euler", "velocity-verlet", "rk4", "explicit-euler", "heun", "yoshida4"] {
        for (name, forces) in mixes() {
            if !matches!(name, "gravity+drag" | "quadratic drag" | "anchors") {
                continue;
            }
            // Masses that differ, equal ones with a static particle (not all the same), and
            // all the same (the element-wise kernel reads one inverse mass then).
            for (equal, with_static) in [(false, true), (true, true), (true, false)] {
                let mut a = world(method, 3, n, &forces, with_static, equal);
                let mut b = a.clone();
                agree(&mut a, &mut b, 3, &format!("{method} on {name}, n {n}"));
            }
        }
    }
}

#[test]
fn the_kernels_see_a_change_of_mass_between_calls() {
    // Equal masses (one inverse mass for all), then one changed, then put back, then a
    // particle of another mass added, then it removed: each call continues the staged
    // trajectory bitwise, in a small world and a parallel one.
    let forces = [Force::Gravity { g: [0.0, -9.81, 0.5] }, Force::Drag { linear: 0.6, quadratic: 0.0 }];
    for n in [37, 4 * 16384 + 5] {
        let mut a = world("symplectic-euler", 3, n, &forces, false, true);
        let mut b = a.clone();
        let what = format!("n {n}");
        agree(&mut a, &mut b, 2, &what);
        for w in [&mut a, &mut b] {
            w.set_mass(n / 2, 0.25).unwrap();
        }
        agree(&mut a, &mut b, 2, &format!("{what}, a mass changed"));
        for w in [&mut a, &mut b] {
            w.set_mass(n / 2, 1.5).unwrap();
        }
        agree(&mut a, &mut b, 2, &format!("{what}, the mass put back"));
        for w in [&mut a, &mut b] {
            w.add_particle(&[0.0, 1.0, 2.0], &[0.5, 0.0, 0.0], 0.2, false).unwrap();
        }
        agree(&mut a, &mut b, 2, &format!("{what}, a lighter particle added"));
        for w in [&mut a, &mut b] {
            let id = w.particle_id(n).unwrap();
            w.remove_particles(&[id]).unwrap();
        }
        agree(&mut a, &mut b, 2, &format!("{what}, it removed"));
    }
}

#[test]
fn kernels_do_not_depend_on_the_thread_count() {
    let n = 5 * 16384 + 3;
    let forces = [Force::Gravity { g: [0.0, 0.0, -9.81] }, Force::Drag { linear: 0.1, quadratic: 0.02 }];
    for method in ["symplectic-euler", "rk4"] {
        let hashes: Vec<u64> = [1, 2, 3]
            .iter()
            .map(|&threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| {
                    let mut w = world(method, 3, n, &forces, false, true);
                    w.step(20).unwrap();
                    w.state_hash()
                })
            })
            .collect();
        assert!(hashes.windows(2).all(|p| p[0] == p[1]), "{method}: {hashes:?}");
    }
}

/// A spring so stiff that explicit Euler at this dt grows by `1 + (omega dt)^2` per step:
/// past the runaway limit within a known number of steps.
fn exploding(method: &str) -> World {
    let mut w = world(method, 2, 5, &[], false, false);
    w.add_force(Force::Spring {
        i: 3,
        j: Endpoint::Anchor([0.0; 3]),
        stiffness: 1e9,
        rest_length: 0.0,
        damping: 0.0,
    })
    .unwrap();
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    w
}

/// Drag so strong that every method here overshoots: `|1 - c dt / m| >> 1` (the element-wise
/// kernel's case).
fn exploding_drag(method: &str) -> World {
    let forces = [Force::Gravity { g: [0.0, -9.81, 0.0] }, Force::Drag { linear: 1e5, quadratic: 0.0 }];
    world(method, 2, 5, &forces, false, false)
}

/// Builds a world for a method.
type Maker = fn(&str) -> World;

#[test]
fn a_failing_step_inside_a_call_is_rolled_back_and_named() {
    let cases: [(&str, Maker, &str); 2] =
        [("stiff spring", exploding, "particle 3"), ("strong drag", exploding_drag, "particle")];
    for ((case, make, named), method) in cases
        .into_iter()
        .flat_map(|c| ["explicit-euler", "symplectic-euler", "velocity-verlet", "rk4"].map(|m| (c, m)))
    {
        let method = &format!("{method} ({case})");
        let make = |_: &str| make(method.split(' ').next().unwrap_or_default());
        // Where the staged step fails, one step at a time.
        let mut staged = make(method);
        let (good, staged_err) = staged_failure(&mut staged, method);
        // The kernel, in one call that passes the failure.
        let mut w = make(method);
        let err = w.step(good + 50).unwrap_err();
        assert_eq!(err.to_string(), staged_err.to_string(), "{method}");
        assert!(err.to_string().contains(named), "{method}: {err}");
        assert_eq!(w.steps(), good, "{method}: the good steps stay taken");
        assert_eq!(w.state_hash(), staged.state_hash(), "{method}: state before the failing step");
        assert_eq!(w.evals(), staged.evals(), "{method}: evaluations");
        assert_eq!(bits(w.accelerations().unwrap()), bits(staged.accelerations().unwrap()), "{method}");
    }
}

/// A spring to an anchor stiff enough that every method here diverges, slowly: after
/// about a hundred steps at dt = 1/120, so that a game loop of one step per call goes past the
/// point where the kernel keeps its rollback afresh (every 64 steps).
fn slowly_exploding(method: &str) -> World {
    let mut w = world(method, 2, 5, &[Force::Gravity { g: [0.0, -9.81, 0.0] }], false, false);
    w.add_force(Force::Spring {
        i: 3,
        j: Endpoint::Anchor([0.0; 3]),
        stiffness: 2e5,
        rest_length: 0.0,
        damping: 0.0,
    })
    .unwrap();
    w
}

/// Changes by hand a game might make between steps, at step 5: velocities nudged (1), the
/// fixed dt changed (2), the method switched (3). Each must make the kernel keep its rollback
/// afresh: a failure must not replay steps from before the change.
fn change_by_hand(w: &mut World, change: u8) {
    if w.steps() != 5 {
        return;
    }
    match change {
        1 => {
            let v: Vec<f64> = w.velocities().iter().map(|v| v * 1.000_001).collect();
            w.set_velocities(&v).unwrap();
        }
        2 => w.set_dt(1.0 / 110.0).unwrap(),
        3 => {
            let other = if w.integrator().info().name == "rk4" { "velocity-verlet" } else { "rk4" };
            w.set_method(other).unwrap();
        }
        _ => {}
    }
}

#[test]
fn a_game_loop_of_one_step_per_call_rolls_back_a_failure_bitwise() {
    // The kernel reuses the rollback an earlier call kept (no copy of the state per call) and
    // replays the good steps since on a failure: it must give the staged step's failure, state
    // and evaluations, over many fresh rollbacks (slowly diverging) and after changes by hand
    // between the calls (diverging within the 64 steps of one rollback).
    let mut longest = 0;
    let methods = ["explicit-euler", "symplectic-euler", "velocity-verlet", "rk4"];
    for (method, change) in methods.into_iter().flat_map(|m| (0..4).map(move |c| (m, c))) {
        let what = format!("{method} (change by hand {change})");
        let make = if change == 0 { slowly_exploding } else { exploding };
        let mut staged = make(method);
        let mut log = StageLog::default();
        let staged_err = loop {
            change_by_hand(&mut staged, change);
            if let Err(e) = staged.step_logged(staged.dt(), &mut log) {
                break e;
            }
            assert!(staged.steps() < 100_000, "{what}: never diverged");
        };
        let mut w = make(method);
        let err = loop {
            change_by_hand(&mut w, change);
            if let Err(e) = w.step(1) {
                break e;
            }
            assert!(w.steps() <= staged.steps(), "{what}: went past the staged failure");
        };
        assert_eq!(err.to_string(), staged_err.to_string(), "{what}");
        assert_eq!(w.steps(), staged.steps(), "{what}: the good steps stay taken");
        assert_eq!(w.state_hash(), staged.state_hash(), "{what}: state before the failing step");
        assert_eq!(w.evals(), staged.evals(), "{what}: evaluations");
        assert_eq!(bits(w.accelerations().unwrap()), bits(staged.accelerations().unwrap()), "{what}");
        // And it goes on from there as the staged step does.
        w.set_dt(1e-9).unwrap();
        staged.set_dt(1e-9).unwrap();
        w.step(3).unwrap();
        for _ in 0..3 {
            staged.step_logged(1e-9, &mut log).unwrap();
        }
        assert_eq!(w.state_hash(), staged.state_hash(), "{what}: continued");
        if change == 0 {
            longest = longest.max(staged.steps());
        } else {
            let steps = staged.steps() - 3;
            assert!(
                (6..64).contains(&steps),
                "{what}: failed at step {steps}, not after the change within a rollback"
            );
        }
    }
    assert!(longest > 128, "no failure came after two fresh rollbacks ({longest} steps)");
}

/// A stiff spring between two particles (not per-particle: the staged step takes it).
fn exploding_pair(method: &str) -> World {
    let mut w = world(method, 3, 6, &[Force::Gravity { g: [0.0, -9.81, 0.0] }], false, false);
    w.add_force(Force::Spring {
        i: 1,
        j: Endpoint::Particle(4),
        stiffness: 1e9,
        rest_length: 0.5,
        damping: 0.0,
    })
    .unwrap();
    w
}

#[test]
fn a_failing_staged_step_inside_a_call_is_rolled_back_and_named() {
    // The staged step keeps one checkpoint per call of several steps and replays on failure.
    for method in ["explicit-euler", "symplectic-euler-alternating", "verlet", "leapfrog", "rk4", "heun"] {
        let mut staged = exploding_pair(method);
        let (good, staged_err) = staged_failure(&mut staged, method);
        let mut w = exploding_pair(method);
        w.step(3).unwrap();
        let err = w.step(good + 20).unwrap_err();
        assert_eq!(err.to_string(), staged_err.to_string(), "{method}");
        assert_eq!(w.steps(), good, "{method}: the good steps stay taken");
        assert_eq!(w.state_hash(), staged.state_hash(), "{method}: state before the failing step");
        assert_eq!(w.evals(), staged.evals(), "{method}: evaluations");
        // And it goes on from there as the staged step does.
        w.set_dt(1e-9).unwrap();
        staged.set_dt(1e-9).unwrap();
        w.step(5).unwrap();
        let mut log = StageLog::default();
        for _ in 0..5 {
            staged.step_logged(1e-9, &mut log).unwrap();
        }
        assert_eq!(w.state_hash(), staged.state_hash(), "{method}: continued");
    }
}

#[test]
fn a_failure_in_one_parallel_task_rolls_back_every_task() {
    // One light particle deep in a large world overshoots under drag; every other particle is
    // fine. Its task fails, the others ran ahead: all go back to the call's checkpoint.
    for method in ["symplectic-euler", "heun"] {
        let make = || {
            let mut w =
                world(method, 3, 4 * 16384 + 77, &[Force::Drag { linear: 1.0, quadratic: 0.0 }], false, true);
            w.add_particle(&[1.0, 2.0, 3.0], &[1.0, 0.0, 0.0], 1e-6, false).unwrap();
            w.add_force(Force::Gravity { g: [0.0, 0.0, -9.81] }).unwrap();
            w
        };
        let mut staged = make();
        let (good, staged_err) = staged_failure(&mut staged, method);
        let mut w = make();
        let err = w.step(good + 10).unwrap_err();
        assert_eq!(err.to_string(), staged_err.to_string(), "{method}");
        assert!(err.to_string().contains(&format!("particle {}", 4 * 16384 + 77)), "{method}: {err}");
        assert_eq!(w.steps(), good, "{method}");
        assert_eq!(w.state_hash(), staged.state_hash(), "{method}: every task back at the failing step");
    }
}

#[test]
fn a_recording_taken_inside_the_kernel_is_the_staged_one() {
    use physstep::record::{RecordParams, Recorder};
    for method in ["symplectic-euler", "rk4", "velocity-verlet", "heun"] {
        for scene in ["spring", "drag", "orbit"] {
            let build = || physstep::scenes::build(scene, &[], method, 0.01).unwrap().world;
            let params =
                RecordParams { dt: 0.01, until: 3.0, every: 1, stages: false, stop_on_diverge: false };
            let mut w = build();
            let mut rec = Recorder::new(&mut w, params).unwrap();
            while !rec.run(&mut w, 64).unwrap() {}
            let rec = rec.finish();
            // The staged reference: one logged step at a time, the row read from the world.
            let mut s = build();
            let mut log = StageLog::default();
            let (mut t, mut x, mut v, mut a, mut e, mut k) = (vec![], vec![], vec![], vec![], vec![], vec![]);
            for step in 0..=300 {
                if step > 0 {
                    s.step_logged(0.01, &mut log).unwrap();
                }
                t.push(s.time());
                x.extend_from_slice(s.positions());
                v.extend_from_slice(s.velocities());
                a.extend_from_slice(s.accelerations().unwrap());
                e.push(s.energy().unwrap());
                k.push(s.kinetic());
            }
            let what = format!("{method} on {scene}");
            assert_eq!(bits(&rec.t), bits(&t), "{what}: t");
            assert_eq!(bits(&rec.x), bits(&x), "{what}: x");
            assert_eq!(bits(&rec.v), bits(&v), "{what}: v");
            assert_eq!(bits(&rec.a), bits(&a), "{what}: a");
            assert_eq!(bits(&rec.energy), bits(&e), "{what}: energy");
            assert_eq!(bits(&rec.kinetic), bits(&k), "{what}: kinetic");
            assert_eq!(w.evals(), s.evals(), "{what}: evaluations");
        }
    }
}

/// Records `w` for `steps` steps of every row (stopping at a failure): the recording.
fn recorded(w: &mut World, steps: u64) -> physstep::record::Recording {
    use physstep::record::{RecordParams, Recorder};
    let until = steps as f64 * w.dt();
    let params = RecordParams { dt: w.dt(), until, every: 1, stages: false, stop_on_diverge: true };
    let mut rec = Recorder::new(w, params).unwrap();
    while !rec.run(w, 64).unwrap() {}
    rec.finish()
}

#[test]
fn a_recording_of_a_small_world_is_the_staged_one() {
    // The small-world kernel's forces (gravity, linear drag, zero-rest springs to anchors, at
    // most one per particle, a static particle among them) and its methods, and others that
    // take the tile kernel, in every dimension; and a stiff spring that fails a step.
    let g = Force::Gravity { g: [0.3, -9.81, 1.5] };
    let lin = Force::Drag { linear: 0.4, quadratic: 0.0 };
    let anchor = |i, stiffness, damping| Force::Spring {
        i,
        j: Endpoint::Anchor([1.0, -1.0, 0.5]),
        stiffness,
        rest_length: 0.0,
        damping,
    };
    let springs = vec![g, lin, anchor(0, 3.0, 0.2), anchor(2, 3.0, 0.0), anchor(5, 3.0, 0.1)];
    let stiff = vec![anchor(1, 3.0, 0.0), anchor(3, 1e7, 0.0)];
    let cases = [("springs", springs), ("drag", vec![lin]), ("gravity", vec![g]), ("stiff", stiff)];
    for (case, forces) in cases {
        for method in ["explicit-euler", "symplectic-euler", "velocity-verlet", "rk4"] {
            for dim in 1..=3 {
                let what = format!("{method} on {case} in {dim}D");
                let mut w = world(method, dim, 5, &forces, true, false);
                let rec = recorded(&mut w, 2000);
                // The staged reference: one logged step at a time, the row read from the world.
                let mut s = world(method, dim, 5, &forces, true, false);
                let mut log = StageLog::default();
                let (mut x, mut v, mut a, mut e, mut k) = (vec![], vec![], vec![], vec![], vec![]);
                let mut failure = None;
                for step in 0..=2000 {
                    if step > 0 {
                        if let Err(err) = s.step_logged(s.dt(), &mut log) {
                            failure = Some(err.to_string());
                            break;
                        }
                    }
                    x.extend_from_slice(s.positions());
                    v.extend_from_slice(s.velocities());
                    a.extend_from_slice(s.accelerations().unwrap());
                    e.push(s.energy().unwrap());
                    k.push(s.kinetic());
                }
                // A failed step leaves the state before it, recorded once more.
                let n = x.len() / (6 * dim);
                let rows = if failure.is_some() { rec.t.len() - 1 } else { rec.t.len() };
                assert_eq!(rows, n, "{what}: rows");
                assert_eq!(rec.diverged.as_ref().map(ToString::to_string), failure, "{what}: failure");
                assert_eq!(bits(&rec.x[..x.len()]), bits(&x), "{what}: x");
                assert_eq!(bits(&rec.v[..v.len()]), bits(&v), "{what}: v");
                assert_eq!(bits(&rec.a[..a.len()]), bits(&a), "{what}: a");
                assert_eq!(bits(&rec.energy[..n]), bits(&e), "{what}: energy");
                assert_eq!(bits(&rec.kinetic[..n]), bits(&k), "{what}: kinetic");
                assert_eq!(w.state_hash(), s.state_hash(), "{what}: the world at the end");
                assert_eq!(w.evals(), s.evals(), "{what}: evaluations");
            }
        }
    }
}
