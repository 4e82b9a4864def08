//! Balls and walls: two-ball collisions against the closed-form outgoing velocities (1D
//! head-on, 2D oblique, 3D, unequal masses and radii), conservation over a scene, the broad
//! phase's pair tests growing linearly with N, rollback, bad input, every method.

use super::common::{close, max_pair_overlap, resign, world};
use physstep::forces::ForceGenerator;
use physstep::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn kinetic(w: &World) -> f64 {
    w.kinetic()
}

fn momentum(w: &World) -> Vec<f64> {
    w.momentum()
}

/// Two balls `a`, `b` (position, velocity, radius, mass) in free flight: the time they touch
/// and the outgoing velocities by the formula along the line of centres at that moment.
#[allow(clippy::type_complexity)]
fn closed_form(
    a: (&[f64], &[f64], f64, f64),
    b: (&[f64], &[f64], f64, f64),
    e: f64,
) -> (f64, Vec<f64>, Vec<f64>) {
    let d0: Vec<f64> = b.0.iter().zip(a.0).map(|(x, y)| x - y).collect();
    let w: Vec<f64> = b.1.iter().zip(a.1).map(|(x, y)| x - y).collect();
    let r = a.2 + b.2;
    let (qa, qb, qc) = (dot(&w, &w), 2.0 * dot(&d0, &w), dot(&d0, &d0) - r * r);
    let t = (-qb - (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
    let n: Vec<f64> = d0.iter().zip(&w).map(|(d, w)| (d + w * t) / r).collect();
    let (ua, ub) = (dot(a.1, &n), dot(b.1, &n));
    let (ma, mb) = (a.3, b.3);
    // 1D collision of the normal components; the tangential ones are kept.
    let ua2 = (ma * ua + mb * ub + mb * e * (ub - ua)) / (ma + mb);
    let ub2 = (ma * ua + mb * ub + ma * e * (ua - ub)) / (ma + mb);
    let va = a.1.iter().zip(&n).map(|(v, n)| v + (ua2 - ua) * n).collect();
    let vb = b.1.iter().zip(&n).map(|(v, n)| v + (ub2 - ub) * n).collect();
    (t, va, vb)
}

/// Steps two balls through their collision and checks velocities, positions, momentum and
/// kinetic energy against the closed form.
fn two_balls(a: (&[f64], &[f64], f64, f64), b: (&[f64], &[f64], f64, f64), e: f64, method: &str) {
    let d = a.0.len();
    let (h, steps) = (0.01, 100);
    let mut w = world(d, method, h);
    w.set_restitution(e).unwrap();
    assert_eq!(w.add_ball(a.0, a.1, a.2, a.3).unwrap(), 0);
    assert_eq!(w.add_ball(b.0, b.1, b.2, b.3).unwrap(), 1);
    let (p0, k0) = (momentum(&w), kinetic(&w));
    w.step(steps).unwrap();
    let (t, va, vb) = closed_form(a, b, e);
    assert!(t > 0.0 && t < 1.0, "contact at {t}");
    let v = w.velocities().to_vec();
    close(&v[..d], &va, 1e-13);
    close(&v[d..], &vb, 1e-13);
    let end = h * steps as f64;
    let xa: Vec<f64> = (0..d).map(|k| a.0[k] + a.1[k] * t + va[k] * (end - t)).collect();
    let xb: Vec<f64> = (0..d).map(|k| b.0[k] + b.1[k] * t + vb[k] * (end - t)).collect();
    let x = w.positions();
    close(&x[..d], &xa, 1e-12);
    close(&x[d..], &xb, 1e-12);
    close(&momentum(&w), &p0, 1e-14);
    if e == 1.0 {
        // Verlet's velocity is a backward difference of positions: it rounds on its own.
        let tol = if method == "verlet" { 1e-12 } else { 4.0 * f64::EPSILON };
        assert!((kinetic(&w) - k0).abs() <= tol * k0, "{method}: {} vs {k0}", kinetic(&w));
    } else {
        assert!(kinetic(&w) < k0);
    }
    assert_eq!(w.collisions().count, 1);
    assert!(w.collisions().max_overlap <= 1e-12);
}

#[test]
fn head_on_1d_unequal_masses_and_radii() {
    two_balls((&[0.0], &[2.0], 0.5, 1.0), (&[3.0], &[-1.0], 0.25, 3.0), 1.0, "symplectic-euler");
    // The textbook numbers: v1' = ((m1 - m2) v1 + 2 m2 v2) / (m1 + m2) = -2.5, v2' = 0.5.
    let mut w = world(1, "symplectic-euler", 0.01);
    w.add_ball(&[0.0], &[2.0], 0.5, 1.0).unwrap();
    w.add_ball(&[3.0], &[-1.0], 0.25, 3.0).unwrap();
    w.step(100).unwrap();
    close(w.velocities(), &[-2.5, 0.5], 1e-14);
    close(w.positions(), &[0.875, 2.375], 1e-13);
}

#[test]
fn head_on_1d_with_restitution() {
    two_balls((&[0.0], &[2.0], 0.5, 1.0), (&[3.0], &[-1.0], 0.25, 3.0), 0.5, "symplectic-euler");
}

#[test]
fn oblique_2d() {
    two_balls(
        (&[0.0, 0.0], &[1.0, 0.0], 0.3, 2.0),
        (&[1.0, 0.2], &[0.0, 0.0], 0.2, 1.0),
        1.0,
        "symplectic-euler",
    );
    two_balls((&[0.0, 0.0], &[1.5, 0.3], 0.3, 1.0), (&[1.2, 0.4], &[-0.5, 0.0], 0.3, 1.0), 1.0, "rk4");
}

#[test]
fn oblique_3d() {
    two_balls(
        (&[0.0, 0.0, 0.0], &[1.0, 0.5, 0.0], 0.5, 1.0),
        (&[2.0, 0.6, 0.3], &[-1.0, 0.0, 0.0], 0.5, 4.0),
        1.0,
        "velocity-verlet",
    );
}

#[test]
fn every_method_keeps_the_closed_form() {
    for method in physstep::integrators::registry::names() {
        two_balls((&[0.0, 0.0], &[1.0, 0.0], 0.3, 2.0), (&[1.0, 0.2], &[0.0, 0.0], 0.2, 1.0), 1.0, method);
    }
}

#[test]
fn static_ball_reflects() {
    let mut w = world(1, "symplectic-euler", 0.01);
    w.add_ball(&[0.0], &[1.0], 0.5, 1.0).unwrap();
    w.add_ball(&[2.0], &[0.0], 0.5, f64::INFINITY).unwrap();
    w.step(200).unwrap();
    close(w.velocities(), &[-1.0, 0.0], 1e-15);
    close(w.positions(), &[0.0, 2.0], 1e-13);
}

#[test]
fn walls_reflect_and_hold() {
    let mut w = world(2, "symplectic-euler", 0.01);
    w.add_walls(&[0.0, 0.0], &[1.0, 1.0]).unwrap();
    w.add_ball(&[0.5, 0.5], &[3.0, -2.0], 0.1, 1.0).unwrap();
    let k0 = kinetic(&w);
    w.step(1000).unwrap();
    let x = w.positions().to_vec();
    assert!(x.iter().all(|c| (0.1..=0.9).contains(c)), "{x:?}");
    assert!((kinetic(&w) - k0).abs() <= 4.0 * f64::EPSILON * k0);
    // 10 s at 3 m/s, 0.4 m to the first wall and 0.8 m between: 1 + 37 bounces; at 2 m/s,
    // 1 + 24.
    assert_eq!(w.collisions().count, 38 + 25);
}

#[test]
fn bouncing_under_gravity_stays_in_the_box() {
    let mut w = world(2, "velocity-verlet", 1.0 / 120.0);
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    w.add_walls(&[0.0, 0.0], &[1.0, 2.0]).unwrap();
    w.add_ball(&[0.5, 1.0], &[0.7, 0.0], 0.1, 1.0).unwrap();
    let e0 = w.energy().unwrap();
    for _ in 0..1200 {
        w.step(1).unwrap();
        let x = w.positions();
        assert!(x[0] >= 0.1 - 1e-12 && x[0] <= 0.9 + 1e-12 && x[1] >= 0.1 - 1e-12, "{x:?}");
    }
    // The chord of the parabola: an energy error of order m g (g h^2) per bounce, not a drift.
    let e = w.energy().unwrap();
    assert!((e - e0).abs() < 1e-2 * e0, "{e} vs {e0}");
}

fn scene(n: usize, dim: usize, fraction: f64, method: &str) -> World {
    let (n, dim) = (n as f64, dim as f64);
    scenes::build("balls", &[("n", n), ("dim", dim), ("fraction", fraction)], method, 1.0 / 120.0)
        .unwrap()
        .world
}

#[test]
fn scene_keeps_energy_no_overlap_inside() {
    // The sparse ones spread over more cells than 4 N: the grid's hashed table.
    for (dim, fraction) in [(1, 0.3), (2, 0.3), (3, 0.2), (2, 0.002), (3, 0.001)] {
        let mut w = scene(150, dim, fraction, "symplectic-euler");
        let k0 = kinetic(&w);
        let walls = w.walls().unwrap();
        for _ in 0..300 {
            w.step(1).unwrap();
            assert!(max_pair_overlap(&w) <= 1e-6 * 0.05, "dim {dim}: {}", max_pair_overlap(&w));
            let (x, d) = (w.positions(), w.dim());
            for (i, c) in x.iter().enumerate() {
                let k = i % d;
                assert!(*c - 0.05 >= walls.lo[k] - 1e-12 && *c + 0.05 <= walls.hi[k] + 1e-12);
            }
        }
        let drift = (kinetic(&w) - k0).abs() / k0;
        assert!(drift < 1e-12, "dim {dim}: drift {drift}");
        let least = if fraction < 0.01 { 1 } else { 100 };
        assert!(w.collisions().count >= least, "dim {dim}: {} collisions", w.collisions().count);
        assert!(w.collisions().max_overlap <= 1e-6 * 0.05);
    }
}

/// The full check of the issue: N = 2000, 2D, 10,000 steps of 1/120 s, restitution 1 (about
/// 4 s with the test profile's opt-level 2).
#[test]
fn scene_2000_balls_10000_steps() {
    let mut w = scene(2000, 2, 0.1, "symplectic-euler");
    let k0 = kinetic(&w);
    let mut worst = 0.0_f64;
    for _ in 0..10_000 {
        w.step(1).unwrap();
        worst = worst.max(w.collisions().max_overlap);
    }
    let drift = (kinetic(&w) - k0).abs() / k0;
    eprintln!("N = 2000: drift {drift:e}, overlap {worst:e} m, {:?}", w.collisions());
    assert!(drift < 1e-9, "drift {drift}");
    assert!(worst <= 1e-6 * 0.05, "overlap {worst}");
    let x = w.positions();
    assert!(x.iter().all(|c| *c >= 0.05 && *c <= w.walls().unwrap().hi[0] - 0.05));
}

#[test]
fn pair_tests_grow_linearly_with_n() {
    let mut per_ball = Vec::new();
    for n in [250, 1000, 4000] {
        let mut w = scene(n, 2, 0.3, "symplectic-euler");
        w.step(5).unwrap();
        per_ball.push(w.collisions().pair_tests as f64 / (5.0 * n as f64));
    }
    eprintln!("pair tests per ball per step, N = 250, 1000, 4000: {per_ball:?}");
    // N^2 would multiply the tests per ball by 16 from 250 to 4000 balls.
    assert!(per_ball[2] < 1.5 * per_ball[0], "{per_ball:?}");
    assert!(per_ball.iter().all(|p| *p < 20.0), "{per_ball:?}");
}

#[test]
fn same_bits_whatever_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut w = scene(3000, 2, 0.3, "rk4");
            w.step(20).unwrap();
            w.state_hash()
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn balls_bypass_the_fused_kernel_with_the_same_bits() {
    let mut a = scene(100, 2, 0.3, "symplectic-euler");
    let mut b = a.clone();
    a.step(50).unwrap();
    for _ in 0..50 {
        b.step(1).unwrap();
    }
    assert_eq!(a.state_hash(), b.state_hash());
    assert_eq!(a.collisions(), b.collisions());
    assert!(a.collisions().count > 0);
}

struct Bomb(AtomicBool);

impl ForceGenerator for Bomb {
    fn add_forces(&self, _t: f64, _x: &[f64], _v: &[f64], f: &mut [f64]) -> Result<(), String> {
        if self.0.load(Ordering::Relaxed) {
            f[0] = f64::NAN;
        }
        Ok(())
    }
}

#[test]
fn failed_step_rolls_back_the_collisions() {
    let mut w = scene(100, 2, 0.3, "leapfrog");
    let bomb = Arc::new(Bomb(AtomicBool::new(false)));
    w.add_force_generator(bomb.clone()).unwrap();
    w.step(30).unwrap();
    let (hash, stats, t) = (w.state_hash(), w.collisions(), w.time());
    bomb.0.store(true, Ordering::Relaxed);
    assert!(w.step(1).is_err());
    assert_eq!((w.state_hash(), w.collisions(), w.time()), (hash, stats, t));
    bomb.0.store(false, Ordering::Relaxed);
    let mut twin = w.clone();
    w.step(10).unwrap();
    twin.step(10).unwrap();
    assert_eq!(w.state_hash(), twin.state_hash());
}

#[test]
fn methods_with_memory_keep_energy() {
    for method in ["verlet", "leapfrog", "velocity-verlet", "symplectic-euler-alternating", "backward-euler"]
    {
        let mut w = scene(100, 2, 0.3, method);
        let k0 = kinetic(&w);
        w.step(300).unwrap();
        assert!(w.collisions().count > 50, "{method}");
        let drift = (kinetic(&w) - k0).abs() / k0;
        assert!(drift < 1e-9, "{method}: drift {drift}");
        assert!(w.collisions().max_overlap <= 1e-6 * 0.05, "{method}");
    }
}

fn message(r: Result<impl std::fmt::Debug>) -> String {
    let e = r.expect_err("must be refused");
    let m = e.to_string();
    assert!(!m.contains('\n'), "{m}");
    m
}

#[test]
fn bad_input_is_named_and_leaves_the_world() {
    let mut w = world(2, "symplectic-euler", 0.01);
    w.add_walls(&[0.0, 0.0], &[4.0, 4.0]).unwrap();
    w.add_ball(&[1.0, 1.0], &[0.0, 0.0], 0.5, 1.0).unwrap();
    let (hash, n) = (w.state_hash(), w.len());
    let m = message(w.add_ball(&[3.0, 3.0], &[0.0, 0.0], -0.1, 1.0));
    assert!(m.contains("radius = -0.1"), "{m}");
    let m = message(w.add_ball(&[3.0, 3.0], &[0.0, 0.0], f64::NAN, 1.0));
    assert!(m.contains("radius = NaN"), "{m}");
    let m = message(w.add_ball(&[1.5, 1.0], &[0.0, 0.0], 0.5, 1.0));
    assert!(m.contains("position = [1.5, 1]") && m.contains("ball 0"), "{m}");
    let m = message(w.add_ball(&[3.8, 2.0], &[0.0, 0.0], 0.5, 1.0));
    assert!(m.contains("position[0] = 3.8") && m.contains("walls"), "{m}");
    let m = message(w.add_walls(&[0.0, 2.0], &[4.0, 1.0]));
    assert!(m.contains("hi[1] = 1") && m.contains("lo[1] = 2"), "{m}");
    let m = message(w.add_walls(&[0.0, 0.0], &[1.2, 4.0]));
    assert!(m.contains("ball 0"), "{m}");
    let m = message(w.add_balls(&[3.0, 3.0, 3.2, 3.0], None, &[0.3, 0.3], None));
    assert!(m.contains("position[1]") && m.contains("position[0]"), "{m}");
    let m = message(w.set_restitution(1.5));
    assert!(m.contains("restitution = 1.5"), "{m}");
    assert_eq!((w.state_hash(), w.len(), w.walls().unwrap().hi[0]), (hash, n, 4.0));
    let m = message(scenes::build("balls", &[("n", 100.0), ("fraction", 0.9)], "rk4", 0.01));
    assert!(m.contains("fraction = 0.9"), "{m}");
    let m = message(scenes::build("balls", &[("dim", 4.0)], "rk4", 0.01));
    assert!(m.contains("dim = 4"), "{m}");
}

#[test]
fn snapshots_hold_the_balls() {
    let mut w = scene(200, 2, 0.3, "leapfrog");
    w.step(20).unwrap();
    let snap = w.snapshot();
    let hash = w.state_hash();
    w.step(30).unwrap();
    let (after, stats) = (w.state_hash(), w.collisions());
    w.restore(&snap).unwrap();
    assert_eq!(w.state_hash(), hash);
    w.step(30).unwrap();
    assert_eq!((w.state_hash(), w.collisions()), (after, stats));
    // Another world of the same particles whose balls differ is refused, unchanged.
    let mut other = scene(200, 2, 0.3, "leapfrog");
    other.set_restitution(0.5).unwrap();
    let before = other.state_hash();
    assert_ne!(before, scene(200, 2, 0.3, "leapfrog").state_hash(), "restitution is in the hash");
    let m = message(other.restore(&snap));
    assert!(m.contains("balls"), "{m}");
    assert_eq!(other.state_hash(), before);
}

#[test]
fn stacks_at_rest_under_gravity_stay_at_any_restitution() {
    // A column of touching balls on the floor: each step's fall is handed down the column to
    // the floor; at restitution < 1 a ball hit twice at one instant bounces elastically (else
    // an endless sequence of ever smaller impulses: an inelastic collapse).
    for (e, n) in [(0.0, 2), (0.5, 5), (1.0, 5), (0.0, 20), (0.9, 20), (1.0, 20)] {
        let mut w = world(1, "symplectic-euler", 1.0 / 120.0);
        w.set_restitution(e).unwrap();
        w.add_walls(&[0.0], &[1000.0]).unwrap();
        let x: Vec<f64> = (0..n).map(|i| 0.5 + i as f64).collect();
        w.add_balls(&x, None, &vec![0.5; n], None).unwrap();
        w.add_force(Force::Gravity { g: [-9.81, 0.0, 0.0] }).unwrap();
        w.step(600).unwrap();
        let top = w.positions()[n - 1];
        assert!((top - x[n - 1]).abs() < 1e-3, "e {e}, n {n}: top at {top}");
        assert!(w.positions().windows(2).all(|p| p[1] - p[0] >= 1.0 - 1e-12), "e {e}, n {n}");
        assert!(w.collisions().max_overlap <= 1e-12);
    }
}

#[test]
fn a_pile_settles_under_gravity() {
    // Elastic: events only, no overlap at any step. Below 1: the resting contacts hold the
    // pile (overlaps of a rounding's size where it rests; see the pile tests below).
    for e in [1.0, 0.9] {
        let mut w = scenes::build(
            "balls",
            &[("n", 300.0), ("fraction", 0.3), ("restitution", e)],
            "velocity-verlet",
            1.0 / 120.0,
        )
        .unwrap()
        .world;
        w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
        let e0 = w.energy().unwrap();
        for k in 0..1200 {
            if let Err(err) = w.step(1) {
                panic!("e {e} step {k}: {err}");
            }
            if e == 1.0 {
                assert!(max_pair_overlap(&w) <= 1e-6 * 0.05, "e {e}: {}", max_pair_overlap(&w));
            }
        }
        let slack = if e == 1.0 { 1e-12 } else { 1e-3 * 0.05 };
        assert!(max_pair_overlap(&w) <= slack, "e {e}: {}", max_pair_overlap(&w));
        let (x, hi) = (w.positions(), w.walls().unwrap().hi);
        assert!(x.iter().enumerate().all(|(i, c)| *c >= 0.05 - slack && *c <= hi[i % 2] - 0.05 + slack));
        let e1 = w.energy().unwrap();
        eprintln!("e {e}: energy {e0} -> {e1}, {:?}", w.collisions());
        if e < 1.0 {
            assert!(e1 < 0.5 * e0, "e {e}: {e0} -> {e1}");
        }
    }
}

/// A 2D pile of `rows` rows of `cols` touching balls of radius 0.05 (hexagonal packing) at
/// rest on the floor of a box, under gravity.
fn packed_pile(cols: usize, rows: usize, e: f64, method: &str) -> World {
    let r = 0.05;
    let mut w = world(2, method, 1.0 / 120.0);
    w.set_restitution(e).unwrap();
    w.add_walls(&[0.0, 0.0], &[2.0 * r * cols as f64 + 2.0 * r, 10.0]).unwrap();
    let mut x = Vec::new();
    for j in 0..rows {
        for i in 0..cols {
            x.push(r + 2.0 * r * (1.0 + 1e-12) * i as f64 + if j % 2 == 1 { r } else { 0.0 });
            x.push(r + j as f64 * r * 3f64.sqrt() * (1.0 + 1e-12));
        }
    }
    w.add_balls(&x, None, &vec![r; cols * rows], None).unwrap();
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    w
}

#[test]
fn contacts_that_do_not_end_fail_the_step_and_roll_back() {
    // Elastic balls packed at rest: each step's fall is handed through all their contacts as
    // events (elastic contacts keep their exact times of impact), more than the budget.
    let mut w = packed_pile(30, 20, 1.0, "velocity-verlet");
    let (hash, stats, t) = (w.state_hash(), w.collisions(), w.time());
    let e = w.step(1).expect_err("an elastic pile packed at rest exceeds the budget");
    assert!(matches!(e, Error::Contacts { .. }) && e.is_step_failure(), "{e}");
    assert!(e.to_string().contains("did not end within 39424 collisions"), "{e}");
    assert_eq!((w.state_hash(), w.collisions(), w.time()), (hash, stats, t));
}

#[test]
fn a_packed_pile_rests_below_restitution_one() {
    // The same pile as above at restitution 0.5 (failed at its first step before resting
    // contacts): it stays at rest, no overlap, no error. (Velocity Verlet keeps a velocity
    // of g h / 2 into the floor at rest: docs/collisions.md.)
    let mut w = packed_pile(30, 20, 0.5, "symplectic-euler");
    // (The odd rows' last balls have half a ball of room beside them: they slide down into
    // it, frictionless, and the pile settles again.)
    w.step(1200).unwrap();
    eprintln!("kinetic {:e}, overlap {:e}", w.kinetic(), max_pair_overlap(&w));
    assert!(max_pair_overlap(&w) < 1e-3 * 0.05, "{}", max_pair_overlap(&w));
    assert!(w.kinetic() < 1e-6, "{}", w.kinetic());
}

/// The resting contacts' warm starts (each contact's push at the end of the step before's
/// first position pass) are state: in the hash, the snapshot and the rollback, so a restored
/// or rolled-back pile goes on bitwise; a damaged block of them is refused.
#[test]
fn a_resting_pile_keeps_its_warm_starts_in_snapshots_and_rollbacks() {
    let build = || {
        let mut w = packed_pile(30, 20, 0.5, "symplectic-euler");
        let bomb = Arc::new(Bomb(AtomicBool::new(false)));
        w.add_force_generator(bomb.clone()).unwrap();
        (w, bomb)
    };
    let (mut w, bomb) = build();
    w.step(60).unwrap();
    let (snap, hash) = (w.snapshot(), w.state_hash());
    // Forgotten (radii set: slots may renumber), the pushes leave the hash and the next step.
    let mut cold = w.clone();
    cold.set_radii(&w.radii()).unwrap();
    assert_ne!(cold.state_hash(), hash);
    let mut warm = w.clone();
    warm.step(1).unwrap();
    cold.step(1).unwrap();
    assert_ne!(warm.positions(), cold.positions());
    // Restored onto the same pile, it goes on as the original.
    let (mut twin, _) = build();
    twin.restore(&snap).unwrap();
    assert_eq!(twin.state_hash(), hash);
    w.step(30).unwrap();
    twin.step(30).unwrap();
    assert_eq!(twin.state_hash(), w.state_hash());
    // A failed step puts them back with the rest.
    let before = (w.state_hash(), w.collisions(), w.time());
    bomb.0.store(true, Ordering::Relaxed);
    assert!(w.step(1).is_err());
    bomb.0.store(false, Ordering::Relaxed);
    assert_eq!((w.state_hash(), w.collisions(), w.time()), before);
    w.step(10).unwrap();
    twin.step(10).unwrap();
    assert_eq!(twin.state_hash(), w.state_hash());
    // Damaged: the last push (the last f64 before the checksum) negative; one entry short.
    let n = snap.len();
    let mut negative = snap.clone();
    negative[n - 16..n - 8].copy_from_slice(&(-1.0_f64).to_le_bytes());
    let mut short = snap.clone();
    short.drain(n - 8 - 24..n - 8);
    let before = twin.state_hash();
    for (bytes, want) in [(negative, "is a push of -1"), (short, "entries for a count of")] {
        let e = twin.restore(&resign(bytes)).unwrap_err();
        assert!(matches!(e, Error::Corrupt { .. }) && e.to_string().contains(want), "{want}: {e}");
        assert_eq!(twin.state_hash(), before, "{want}");
    }
}

/// The `pile` scene at restitution `e` under symplectic Euler to t = 10 s: the peak and final
/// kinetic energy and the overlap at the end.
fn pile_run(e: f64) -> (f64, f64, World) {
    let mut w = scenes::build("pile", &[("restitution", e)], "symplectic-euler", 1.0 / 120.0).unwrap().world;
    let mut peak = 0.0_f64;
    for k in 0..1200 {
        if let Err(err) = w.step(1) {
            panic!("e {e} step {k}: {err}");
        }
        peak = peak.max(w.kinetic());
    }
    (peak, w.kinetic(), w)
}

#[test]
fn the_pile_comes_to_rest_at_any_restitution() {
    // 1,000 balls dropped into a box under gravity: before resting contacts, restitution 0.5
    // failed 1.4 s into the fall (the contact budget), and 0 and 0.9 the same way.
    for e in [0.5, 0.0, 0.9] {
        let (peak, end, w) = pile_run(e);
        let overlap = max_pair_overlap(&w);
        eprintln!("e {e}: kinetic {end:e} of peak {peak:e} ({:e}), overlap {overlap:e}", end / peak);
        assert!(end < 1e-6 * peak, "e {e}: kinetic {end} of peak {peak}");
        assert!(overlap < 1e-3 * 0.05, "e {e}: overlap {overlap}");
        let (x, hi) = (w.positions(), w.walls().unwrap().hi);
        let slack = 1e-3 * 0.05;
        assert!(x.iter().enumerate().all(|(i, c)| *c >= 0.05 - slack && *c <= hi[i % 2] - 0.05 + slack));
    }
}

#[test]
fn the_pile_is_the_same_on_one_and_two_threads() {
    // 17,000 balls: the scan runs on the pool (above 16,384); the resting contacts are serial.
    let run = |threads: usize, n: f64, steps: u64| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut w = scenes::build("pile", &[("n", n)], "symplectic-euler", 1.0 / 120.0).unwrap().world;
            w.step(steps).unwrap();
            (w.state_hash(), w.collisions())
        })
    };
    assert_eq!(run(1, 17000.0, 40), run(2, 17000.0, 40));
    let (a, b) = (run(1, 1000.0, 240), run(2, 1000.0, 240));
    assert_eq!(a, b);
    assert!(a.1.count > 1000, "{:?}", a.1);
}

/// Positions set by hand are checked as `add_ball` checks a ball (issue 25, item 10): no
/// overlap deeper than the state's, no ball out of the walls; the world unchanged.
#[test]
fn positions_set_by_hand_keep_balls_apart_and_inside() {
    let mut w = world(2, "symplectic-euler", 0.01);
    w.add_walls(&[0.0, 0.0], &[4.0, 4.0]).unwrap();
    w.add_ball(&[1.0, 1.0], &[0.0, 0.0], 0.5, 1.0).unwrap();
    w.add_ball(&[3.0, 3.0], &[0.0, 0.0], 0.5, 1.0).unwrap();
    let hash = w.state_hash();
    let m = w.set_positions(&[1.0, 1.0, 1.5, 1.0]).unwrap_err().to_string();
    assert!(m.starts_with("invalid positions[1] = [1.5, 1]: must be clear of ball 0 at [1, 1]"), "{m}");
    let m = w.set_positions(&[1.0, 1.0, 3.8, 3.0]).unwrap_err().to_string();
    assert!(m.starts_with("invalid positions[1][0] = 3.8: must be inside the walls"), "{m}");
    assert_eq!(w.state_hash(), hash);
    w.set_positions(&[1.0, 1.0, 2.0, 1.0]).unwrap(); // touching
}

#[test]
fn a_first_order_method_loses_energy_at_every_bounce() {
    // docs/collisions.md: the bounce's energy error does not accumulate under a second-order
    // method, and does under symplectic Euler (40% lost in 10 s at dt = 1/120).
    let bounce = |method: &str| {
        let mut w = world(2, method, 1.0 / 120.0);
        w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
        w.add_walls(&[0.0, 0.0], &[1.0, 2.0]).unwrap();
        w.add_ball(&[0.5, 1.0], &[0.7, 0.0], 0.1, 1.0).unwrap();
        let e0 = w.energy().unwrap();
        w.step(1200).unwrap();
        (w.energy().unwrap() - e0) / e0
    };
    let lost = bounce("symplectic-euler");
    assert!((-0.42..-0.38).contains(&lost), "{lost}");
    for method in ["velocity-verlet", "leapfrog", "rk4"] {
        assert!(bounce(method).abs() < 1e-12, "{method}: {}", bounce(method));
    }
}

#[test]
fn one_fast_ball_that_hits_the_walls_too_often_is_not_called_a_pile() {
    // One ball at 1e6 m/s in a 1 m box hits the walls about 1e4 times in a step of 1/120 s:
    // past the budget (64 N + 1024). The message says what can cause that, not "packed at
    // rest", and the step is rolled back.
    let mut w = world(2, "symplectic-euler", 1.0 / 120.0);
    w.add_walls(&[0.0, 0.0], &[1.0, 1.0]).unwrap();
    w.add_ball(&[0.5, 0.5], &[1e6, 3e5], 0.1, 1.0).unwrap();
    let before = w.state_hash();
    let e = w.step(1).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("did not end within 1088 collisions"), "{text}");
    assert!(
        text.contains("a ball fast enough to hit the walls that often in one step")
            && !text.contains("at rest")
    );
    assert_eq!((w.steps(), w.state_hash()), (0, before));
}
