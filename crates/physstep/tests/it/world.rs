//! The world: frame-rate independence of the fixed-timestep loop, the spiral-of-death guard,
//! snapshots, hashing, input validation, force-order independence and conservation laws.

use super::common;
use physstep::prelude::*;

const DT: f64 = 1.0 / 120.0;

/// Tiny deterministic generator (xorshift64*), uniform in [0, 1).
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let r = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (r >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Frame times summing to `total` (up to a naive sum's rounding): random in [2 ms, 50 ms],
/// the last one taking the remainder.
fn jittered(seed: u64, total: f64) -> Vec<f64> {
    let mut rng = XorShift(seed);
    let mut frames = Vec::new();
    let mut sum = 0.0;
    loop {
        let f = 0.002 + 0.048 * rng.next();
        if sum + f >= total {
            frames.push(total - sum);
            return frames;
        }
        frames.push(f);
        sum += f;
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// A 3D world by hand: two static anchors, five moving particles of different masses joined
/// by springs (one damped), gravity and quadratic + linear drag.
fn world3d(method: &str) -> World {
    let mut w = World::new(WorldParams { dim: 3, method: method.into(), ..WorldParams::default() }).unwrap();
    w.add_particle(&[0.0, 0.0, 2.0], &[0.0; 3], f64::INFINITY, false).unwrap();
    w.add_particle(&[1.0, 0.5, 2.0], &[0.0; 3], 3.0, true).unwrap();
    let x = [0.2, 0.1, 1.7, 0.5, -0.2, 1.5, 0.9, 0.3, 1.4, 0.4, 0.6, 1.2, -0.3, 0.2, 1.0];
    let v = [0.1, 0.0, 0.0, -0.2, 0.3, 0.1, 0.0, 0.0, -0.5, 0.3, 0.2, 0.0, 0.0, -0.1, 0.4];
    w.add_particles(&x, Some(&v), Some(&[0.5, 1.0, 0.7, 2.0, 0.3]), false).unwrap();
    for f in forces3d() {
        w.add_force(f).unwrap();
    }
    w
}

fn spring(i: usize, j: Endpoint, stiffness: f64, rest_length: f64, damping: f64) -> Force {
    Force::Spring { i, j, stiffness, rest_length, damping }
}

fn forces3d() -> Vec<Force> {
    use Endpoint::{Anchor, Particle};
    vec![
        Force::Gravity { g: [0.0, 0.0, -9.81] },
        spring(2, Particle(0), 40.0, 0.3, 0.0),
        spring(3, Particle(2), 25.0, 0.4, 0.2),
        spring(4, Particle(1), 30.0, 0.5, 0.0),
        spring(5, Particle(4), 15.0, 0.3, 0.1),
        spring(6, Particle(5), 20.0, 0.6, 0.0),
        spring(6, Anchor([0.0, 0.0, 1.0]), 5.0, 0.2, 0.0),
        spring(3, Particle(5), 10.0, 0.5, 0.0),
        Force::Drag { linear: 0.05, quadratic: 0.02 },
    ]
}

/// Runs `frames` through `advance`, checking the interpolation invariant after each frame.
fn run_frames(w: &mut World, frames: &[f64]) {
    for &f in frames {
        let before = w.positions().to_vec();
        let steps_before = w.steps();
        let frame = w.advance(f).unwrap();
        assert_eq!(frame.plan.dt.to_bits(), w.dt().to_bits(), "accumulator steps are exactly dt");
        assert_eq!(frame.plan.dropped, 0.0, "no frame here is long enough to drop time");
        assert_eq!(w.steps() - steps_before, u64::from(frame.plan.steps));
        let alpha = frame.alpha;
        assert!((0.0..1.0).contains(&alpha), "alpha {alpha}");
        assert_eq!(alpha, w.alpha());
        let interp = w.interpolated_positions();
        let cur = w.positions();
        assert_eq!(interp.len(), cur.len());
        if frame.plan.steps == 1 {
            // Exactly one step: the previous positions are those before the frame.
            for ((p, c), q) in before.iter().zip(cur).zip(&interp) {
                let want = p + alpha * (c - p);
                assert_eq!(q.to_bits(), want.to_bits());
            }
        }
    }
}

/// `interp` lies componentwise between `prev` and `cur`.
fn check_between(prev: &[f64], cur: &[f64], interp: &[f64]) {
    for (k, ((p, c), q)) in prev.iter().zip(cur).zip(interp).enumerate() {
        let (lo, hi) = if p <= c { (p, c) } else { (c, p) };
        assert!(lo <= q && q <= hi, "coordinate {k}: {q} not between {p} and {c}");
    }
}

#[test]
fn interpolated_positions_lie_between_previous_and_current() {
    for (name, mut w) in
        [("chain", scenes::build("chain", &[], "velocity-verlet", DT).unwrap().world), ("3d", world3d("rk4"))]
    {
        // No step yet: the current positions.
        assert_eq!(w.interpolated_positions(), w.positions());
        for f in jittered(5, 1.0) {
            // Step the frame by hand on a clone to learn the positions before the latest step.
            let mut probe = w.clone();
            let plan = probe.advance(f).unwrap().plan;
            let mut before_last = w.clone();
            if plan.steps > 0 {
                // Re-run the frame with one step fewer on a copy: all but the last step.
                before_last.step(u64::from(plan.steps) - 1).unwrap();
            }
            w.advance(f).unwrap();
            assert_eq!(bits(w.positions()), bits(probe.positions()), "{name}: advance is deterministic");
            let interp = w.interpolated_positions();
            if w.steps() > 0 && plan.steps > 0 {
                check_between(before_last.positions(), w.positions(), &interp);
                let a = w.alpha();
                for ((p, c), q) in before_last.positions().iter().zip(w.positions()).zip(&interp) {
                    assert_eq!(q.to_bits(), (p + a * (c - p)).to_bits(), "{name}");
                }
            }
        }
    }
}

#[test]
fn frame_rate_independence_is_bitwise() {
    // T = 2 s = 240 steps of 1/120 s at 30, 60, 144 Hz and with jitter.
    let total = 240.0 * DT;
    let rates: Vec<Vec<f64>> = vec![
        vec![1.0 / 30.0; 60],
        vec![1.0 / 60.0; 120],
        vec![1.0 / 144.0; 288],
        jittered(0x9E37_79B9_7F4A_7C15, total),
        jittered(42, total),
        jittered(2024, total),
    ];
    type Make = fn() -> World;
    let makers: [(&str, Make); 4] = [
        ("chain/symplectic-euler", || scenes::build("chain", &[], "symplectic-euler", DT).unwrap().world),
        ("chain/verlet", || scenes::build("chain", &[], "verlet", DT).unwrap().world),
        ("3d/velocity-verlet", || world3d("velocity-verlet")),
        ("3d/rk4", || world3d("rk4")),
    ];
    for (name, make) in makers {
        // Reference: one step at a time.
        let mut reference = make();
        reference.step(240).unwrap();
        let want = (reference.state_hash(), bits(reference.positions()), bits(reference.velocities()));
        assert!(reference.positions().iter().all(|x| x.is_finite()));
        for frames in &rates {
            let mut w = make();
            run_frames(&mut w, frames);
            assert_eq!(w.steps(), 240, "{name}, {} frames", frames.len());
            assert_eq!(w.time().to_bits(), reference.time().to_bits());
            let got = (w.state_hash(), bits(w.positions()), bits(w.velocities()));
            assert_eq!(got, want, "{name}, {} frames", frames.len());
            assert!(w.alpha() < 1e-6, "{name}: the frames end on a step boundary, alpha {}", w.alpha());
        }
    }
}

#[test]
fn spiral_of_death_caps_steps_and_reports_dropped_time() {
    // dt = 1 ms, at most 4 steps per frame, frames of 40 ms (10x what the cap allows) and
    // below the 0.1 s clamp.
    let dt = 1e-3;
    let params = WorldParams { dt, max_steps_per_frame: 4, method: "rk4".into(), ..WorldParams::default() };
    let mut w = scenes::build("chain", &[], "rk4", dt).unwrap().world;
    let mut w2 = World::new(params).unwrap();
    w2.add_particle(&[0.0, 0.0], &[1.0, 0.0], 1.0, false).unwrap();
    w2.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    let frame_time = 10.0 * 4.0 * dt;
    let mut dropped = 0.0;
    for i in 0..20 {
        let s0 = w2.steps();
        let frame = w2.advance(frame_time).unwrap();
        assert_eq!(frame.plan.steps, 4, "frame {i}");
        assert_eq!(w2.steps() - s0, 4, "frame {i}: never more than max_steps_per_frame");
        assert_eq!(frame.plan.clamped, 0.0);
        assert!(frame.plan.dropped > 0.0);
        assert!(
            (frame.plan.dropped - 36.0 * dt).abs() < 1.5 * dt,
            "frame {i}: dropped {}",
            frame.plan.dropped
        );
        assert!((0.0..1.0).contains(&frame.alpha));
        dropped += frame.plan.dropped;
    }
    assert_eq!(w2.steps(), 80);
    let stats = w2.clock().stats();
    assert_eq!(stats.steps, 80);
    assert!((stats.dropped - dropped).abs() < 1e-12);
    // No time created or lost: steps + dropped + leftover = wall time.
    let accounted = 80.0 * dt + stats.dropped + w2.clock().leftover();
    assert!((accounted - 20.0 * frame_time).abs() < 1e-12, "{accounted}");

    // The default world (dt = 1/120, 8 steps, 0.1 s clamp): a 5 s frame is clamped to 0.1 s.
    let s0 = w.steps();
    w.set_dt(DT).unwrap();
    let frame = w.advance(5.0).unwrap();
    assert_eq!(frame.plan.clamped, 4.9);
    assert_eq!(frame.plan.steps, 8);
    assert_eq!(w.steps() - s0, 8);
    assert!(frame.plan.dropped > 0.0);
    assert!((frame.plan.dropped - 4.0 * DT).abs() < 1e-12);
    assert!(w.positions().iter().all(|x| x.is_finite()));
}

/// A world for the snapshot test: springs, drag and gravity in 2D, every method.
fn snapshot_world(method: &str) -> World {
    let mut scene = scenes::build("chain", &[("n", 4.0), ("c", 0.3)], method, DT).unwrap();
    scene.world.add_force(Force::Drag { linear: 0.1, quadratic: 0.05 }).unwrap();
    scene.world
}

#[test]
fn snapshot_restore_continue_is_bitwise_for_every_method() {
    for info in INFOS {
        let mut w = snapshot_world(info.name);
        w.step(37).unwrap();
        let snap = w.snapshot();
        let at_snap = (w.state_hash(), bits(w.positions()), bits(w.velocities()), w.steps(), w.evals());
        w.step(50).unwrap();
        let want =
            (w.state_hash(), bits(w.positions()), bits(w.velocities()), w.steps(), w.evals(), w.time());

        // Restore into the same world after it moved on.
        w.restore(&snap).unwrap();
        assert_eq!(
            (w.state_hash(), bits(w.positions()), bits(w.velocities()), w.steps(), w.evals()),
            at_snap
        );
        w.step(50).unwrap();
        let got = (w.state_hash(), bits(w.positions()), bits(w.velocities()), w.steps(), w.evals(), w.time());
        assert_eq!(got, want, "{}: restored run differs", info.name);

        // Restore into a fresh world of the same shape.
        let mut fresh = snapshot_world(info.name);
        fresh.restore(&snap).unwrap();
        fresh.step(50).unwrap();
        let got = (fresh.state_hash(), bits(fresh.positions()), bits(fresh.velocities()), fresh.steps());
        assert_eq!(
            got,
            (want.0, want.1.clone(), want.2.clone(), want.3),
            "{}: fresh world differs",
            info.name
        );
    }
}

#[test]
fn snapshot_keeps_the_clock_accumulator() {
    for method in ["velocity-verlet", "leapfrog", "verlet", "symplectic-euler-alternating"] {
        let mut w = snapshot_world(method);
        for f in jittered(3, 0.4) {
            w.advance(f).unwrap();
        }
        let snap = w.snapshot();
        let alpha = w.alpha();
        let frames = jittered(11, 0.5);
        for &f in &frames {
            w.advance(f).unwrap();
        }
        let want = (w.state_hash(), w.steps(), w.alpha().to_bits(), bits(&w.interpolated_positions()));
        w.restore(&snap).unwrap();
        assert_eq!(w.alpha(), alpha);
        for &f in &frames {
            w.advance(f).unwrap();
        }
        let got = (w.state_hash(), w.steps(), w.alpha().to_bits(), bits(&w.interpolated_positions()));
        assert_eq!(got, want, "{method}");
    }
}

#[test]
fn snapshot_before_the_first_step_and_after_adding_particles() {
    for method in ["verlet", "leapfrog", "rk4"] {
        // Never stepped.
        let mut w = snapshot_world(method);
        let snap = w.snapshot();
        let mut reference = w.clone();
        reference.step(25).unwrap();
        w.step(7).unwrap();
        w.restore(&snap).unwrap();
        assert_eq!(w.steps(), 0);
        w.step(25).unwrap();
        assert_eq!(w.state_hash(), reference.state_hash(), "{method}: from step 0");

        // Stepped, then a particle added (the previous positions are of the old count).
        let mut w = snapshot_world(method);
        w.step(5).unwrap();
        w.add_particle(&[0.3, 0.4], &[1.0, 0.0], 0.2, false).unwrap();
        let snap = w.snapshot();
        assert_eq!(w.interpolated_positions(), w.positions());
        let mut reference = w.clone();
        reference.step(25).unwrap();
        w.step(3).unwrap();
        w.restore(&snap).unwrap();
        assert_eq!(w.interpolated_positions(), w.positions());
        w.step(25).unwrap();
        assert_eq!(w.state_hash(), reference.state_hash(), "{method}: after adding a particle");
    }
}

fn is_corrupt(r: Result<()>) -> bool {
    matches!(r, Err(Error::Corrupt { .. }))
}

#[test]
fn restore_rejects_other_worlds_and_garbage() {
    let mut src = snapshot_world("leapfrog");
    src.step(10).unwrap();
    let snap = src.snapshot();

    let check_unchanged = |w: &mut World, bytes: &[u8], what: &str| {
        let before = (w.state_hash(), bits(w.positions()), bits(w.velocities()), w.steps(), w.len());
        let r = w.restore(bytes);
        assert!(is_corrupt(r.clone()), "{what}: {r:?}");
        assert!(r.unwrap_err().to_string().starts_with("corrupt snapshot: "));
        let after = (w.state_hash(), bits(w.positions()), bits(w.velocities()), w.steps(), w.len());
        assert_eq!(before, after, "{what}: world changed");
        // And it still steps like an untouched copy.
        let mut copy = w.clone();
        copy.step(3).unwrap();
        w.step(3).unwrap();
        assert_eq!(w.state_hash(), copy.state_hash());
    };

    // Another particle count.
    let mut other = scenes::build("chain", &[("n", 5.0), ("c", 0.3)], "leapfrog", DT).unwrap().world;
    other.step(4).unwrap();
    check_unchanged(&mut other, &snap, "5 particles");
    let msg = other.restore(&snap).unwrap_err().to_string();
    assert!(msg.contains("4 particles") && msg.contains("5"), "{msg}");
    // Another method.
    for method in ["velocity-verlet", "verlet", "rk4"] {
        let mut other = snapshot_world(method);
        other.step(4).unwrap();
        check_unchanged(&mut other, &snap, method);
        let msg = other.restore(&snap).unwrap_err().to_string();
        assert!(msg.contains("leapfrog") && msg.contains(method), "{msg}");
    }
    // Another dimension, same particle count.
    let mut w3 =
        World::new(WorldParams { dim: 3, method: "leapfrog".into(), ..WorldParams::default() }).unwrap();
    w3.add_particles(&[0.0; 12], None, None, false).unwrap();
    check_unchanged(&mut w3, &snap, "3D");

    // Garbage, truncations, extensions, a damaged magic.
    let mut w = snapshot_world("leapfrog");
    w.step(5).unwrap();
    let mut rng = XorShift(99);
    let garbage: Vec<u8> = (0..snap.len()).map(|_| (rng.next() * 256.0) as u8).collect();
    check_unchanged(&mut w, &garbage, "garbage");
    check_unchanged(&mut w, &[], "empty");
    check_unchanged(&mut w, b"PHSTEP01", "magic only");
    for cut in [9, 20, 47, 48, 60, snap.len() - 8, snap.len() - 1] {
        check_unchanged(&mut w, &snap[..cut], &format!("truncated to {cut}"));
    }
    let mut longer = snap.clone();
    longer.extend_from_slice(&1.0f64.to_le_bytes());
    check_unchanged(&mut w, &longer, "one float too many");
    let mut bad_magic = snap.clone();
    bad_magic[0] ^= 1;
    check_unchanged(&mut w, &bad_magic, "bad magic");

    // A well-formed header with a damaged memory length (the float after t, hi, lo and the
    // time epoch t0, steps0, dt).
    let name_len = "leapfrog".len();
    let nm_at = 8 + 40 + name_len + 6 * 8;
    for nm in [1e300, f64::INFINITY, -5.0, 1e6, f64::NAN, 1.0] {
        let mut bad = snap.clone();
        bad[nm_at..nm_at + 8].copy_from_slice(&nm.to_le_bytes());
        check_unchanged(&mut w, &bad, &format!("memory length {nm}"));
    }
    // A huge method-name length.
    let mut bad = snap.clone();
    bad[8 + 16..8 + 24].copy_from_slice(&u64::MAX.to_le_bytes());
    check_unchanged(&mut w, &bad, "name length");

    // The good snapshot still restores.
    let mut fresh = snapshot_world("leapfrog");
    fresh.restore(&snap).unwrap();
    assert_eq!(fresh.state_hash(), src.state_hash());
}

#[test]
fn state_hash_tracks_every_change() {
    let mut a = world3d("velocity-verlet");
    let mut b = world3d("velocity-verlet");
    assert_eq!(a.state_hash(), b.state_hash());
    a.step(20).unwrap();
    b.step(20).unwrap();
    assert_eq!(a.state_hash(), b.state_hash());
    let h = a.state_hash();

    // One ulp on one velocity component of a moving particle.
    let n = a.velocities().len();
    for k in 6..n {
        let mut v = a.velocities().to_vec();
        v[k] = f64::from_bits(v[k].to_bits() + 1);
        let mut c = a.clone();
        c.set_velocities(&v).unwrap();
        assert_ne!(c.state_hash(), h, "velocity {k}");
        let mut v = a.velocities().to_vec();
        v[k] = f64::from_bits(v[k].to_bits() - 1);
        c.set_velocities(&v).unwrap();
        assert_ne!(c.state_hash(), h, "velocity {k} down");
        c.set_velocities(a.velocities()).unwrap();
        assert_eq!(c.state_hash(), h, "velocity {k} put back");
    }
    // One ulp on one position.
    for k in 0..a.positions().len() {
        let mut x = a.positions().to_vec();
        x[k] = f64::from_bits(x[k].to_bits() + 1);
        let mut c = a.clone();
        c.set_positions(&x).unwrap();
        assert_ne!(c.state_hash(), h, "position {k}");
    }
    // Time only: a snapshot with t changed by one ulp.
    let snap = a.snapshot();
    let t_at = 8 + 40 + "velocity-verlet".len();
    let t = f64::from_le_bytes(snap[t_at..t_at + 8].try_into().unwrap());
    assert_eq!(t, a.time());
    let mut bumped = snap.clone();
    bumped[t_at..t_at + 8].copy_from_slice(&f64::from_bits(t.to_bits() + 1).to_le_bytes());
    // An edited snapshot is refused (checksum), the world unchanged (issue 7, item 14).
    let mut c = a.clone();
    let e = c.restore(&bumped).unwrap_err();
    assert!(e.to_string().contains("checksum"), "{e}");
    assert_eq!(c.state_hash(), h);
    c.restore(&snap).unwrap();
    assert_eq!(c.state_hash(), h);
    // A step changes it; -0.0 versus 0.0 is a change of bits too.
    b.step(1).unwrap();
    assert_ne!(b.state_hash(), h);

    // Integrator memory counts: leapfrog's half-step velocity.
    let mut l1 = world3d("leapfrog");
    l1.step(5).unwrap();
    let mut l2 = l1.clone();
    l2.set_positions(l1.positions()).unwrap(); // resets the integrator's memory
    assert_eq!(bits(l1.positions()), bits(l2.positions()));
    assert_ne!(l1.state_hash(), l2.state_hash(), "leapfrog memory is part of the state");
}

fn msg<T: std::fmt::Debug>(r: Result<T>) -> String {
    r.unwrap_err().to_string()
}

#[test]
fn bad_input_names_field_and_value_and_changes_nothing() {
    let mut w = world3d("rk4");
    w.step(3).unwrap();
    let snapshot = |w: &World| (w.len(), w.state_hash(), w.model().forces().len(), bits(w.positions()));
    let before = snapshot(&w);

    assert_eq!(
        msg(w.add_particle(&[0.0, f64::NAN, 0.0], &[0.0; 3], 1.0, false)),
        "invalid position[1] = NaN: must be finite, at most 1e100 in magnitude"
    );
    assert_eq!(
        msg(w.add_particles(&[0.0, 0.0, 0.0, 1.0, 2.0, f64::NAN], None, None, false)),
        "invalid position[5] = NaN: must be finite, at most 1e100 in magnitude"
    );
    assert_eq!(
        msg(w.add_particle(&[0.0; 3], &[0.0, 0.0, f64::INFINITY], 1.0, false)),
        "invalid velocity[2] = inf: must be finite, at most 1e100 in magnitude"
    );
    assert!(
        msg(w.add_particle(&[0.0; 3], &[0.0; 3], -2.0, false)).starts_with("invalid mass = -2: must be > 0")
    );
    assert!(
        msg(w.add_particle(&[0.0; 3], &[0.0; 3], 0.0, false)).starts_with("invalid mass = 0: must be > 0")
    );
    assert!(msg(w.add_particle(&[0.0; 3], &[0.0; 3], f64::NAN, false)).starts_with("invalid mass = NaN"));
    assert!(msg(w.add_particle(&[0.0; 3], &[0.0; 3], f64::NEG_INFINITY, false))
        .starts_with("invalid mass = -inf"));
    assert!(
        msg(w.add_particles(&[0.0; 6], None, Some(&[1.0, -1.0]), false)).starts_with("invalid mass[1] = -1")
    );
    assert!(msg(w.add_particles(&[0.0; 5], None, None, false)).starts_with("invalid len(positions) = 5"));
    assert!(msg(w.add_particles(&[0.0; 6], Some(&[0.0; 3]), None, false))
        .starts_with("invalid len(velocity) = 3"));
    assert!(msg(w.add_particles(&[0.0; 6], None, Some(&[1.0]), false)).starts_with("invalid len(mass) = 1"));

    let n = w.len();
    assert_eq!(
        msg(w.add_force(spring(0, Endpoint::Particle(n), 1.0, 0.0, 0.0))),
        format!("invalid j = {n}: must be a particle index < {n} other than i")
    );
    assert_eq!(
        msg(w.add_force(spring(n + 3, Endpoint::Particle(0), 1.0, 0.0, 0.0))),
        format!("invalid i = {}: must be a particle index < {n}", n + 3)
    );
    assert_eq!(
        msg(w.add_force(Force::Rod { i: 2, j: Endpoint::Particle(3), length: 0.0 })),
        "invalid length = 0: must be a finite number > 0"
    );
    assert_eq!(
        msg(w.add_force(Force::Rod { i: 2, j: Endpoint::Anchor([0.0; 3]), length: -1.0 })),
        "invalid length = -1: must be a finite number > 0"
    );
    // n-body gravity needs finite masses: the two static particles forbid it.
    assert!(msg(w.add_force(Force::NBody { g: 1.0, softening: 0.1 })).starts_with("invalid mass[0] = inf"));
    assert!(msg(w.set_positions(&[0.0; 2])).starts_with("invalid len(positions) = 2"));
    let mut x = w.positions().to_vec();
    x[4] = f64::NAN;
    assert_eq!(
        msg(w.set_positions(&x)),
        "invalid position[4] = NaN: must be finite, at most 1e100 in magnitude"
    );
    assert!(msg(w.step_by(0.0)).starts_with("invalid dt = 0"));
    assert!(msg(w.step_by(-1.0)).starts_with("invalid dt = -1"));
    assert!(msg(w.advance(f64::NAN)).starts_with("invalid frame_time = NaN"));
    assert!(msg(w.set_dt(f64::INFINITY)).starts_with("invalid dt = inf"));
    assert!(msg(w.set_method("euler")).starts_with("unknown method 'euler'; valid methods: explicit-euler"));
    assert_eq!(w.integrator().info().name, "rk4");
    assert_eq!(snapshot(&w), before, "failed calls changed the world");

    // Dimensions outside 1..=3.
    for dim in [0, 4] {
        let r = World::new(WorldParams { dim, ..WorldParams::default() });
        assert_eq!(msg(r), format!("invalid dim = {dim}: must be 1, 2 or 3"));
    }
    assert!(msg(World::new(WorldParams { method: "nope".into(), ..WorldParams::default() }))
        .starts_with("unknown method 'nope'"));
    assert!(msg(World::new(WorldParams { dt: 0.0, ..WorldParams::default() })).starts_with("invalid dt = 0"));
    assert!(msg(World::new(WorldParams { max_steps_per_frame: 0, ..WorldParams::default() }))
        .starts_with("invalid max_steps_per_frame = 0"));
    assert!(msg(World::new(WorldParams { max_frame_time: -1.0, ..WorldParams::default() }))
        .starts_with("invalid max_frame_time = -1"));
}

#[test]
fn infinite_mass_is_static() {
    for method in ["explicit-euler", "velocity-verlet", "rk4", "backward-euler", "verlet", "leapfrog"] {
        let mut w =
            World::new(WorldParams { dim: 2, method: method.into(), ..WorldParams::default() }).unwrap();
        // Not flagged static, but infinite mass: accepted as static, its velocity dropped.
        let i = w.add_particle(&[1.0, 2.0], &[3.0, 4.0], f64::INFINITY, false).unwrap();
        let j = w.add_particle(&[0.0, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
        assert_eq!((i, j), (0, 1));
        assert_eq!(w.velocities()[..2], [0.0, 0.0]);
        w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
        w.add_force(spring(0, Endpoint::Particle(1), 10.0, 0.5, 0.1)).unwrap();
        w.add_force(Force::Drag { linear: 0.1, quadratic: 0.0 }).unwrap();
        w.set_velocities(&[5.0, 5.0, 0.0, 1.0]).unwrap();
        assert_eq!(w.velocities(), &[0.0, 0.0, 0.0, 1.0]);
        w.step(200).unwrap();
        assert_eq!(w.positions()[..2], [1.0, 2.0], "{method}");
        assert_eq!(w.velocities()[..2], [0.0, 0.0], "{method}");
        assert_ne!(w.positions()[2..], [0.0, 0.0], "{method}: the other particle moves");
        assert!(w.energy().unwrap().is_finite() && w.momentum().iter().all(|p| p.is_finite()));
        // The static particle carries no momentum.
        let p = w.momentum();
        assert_eq!(p, vec![w.velocities()[2], w.velocities()[3]]);
    }
}

#[test]
fn static_particle_added_after_nbody_is_rejected() {
    let mut w = World::new(WorldParams::default()).unwrap();
    w.add_particles(&[0.0, 0.0, 1.0, 0.0], None, None, false).unwrap();
    w.add_force(Force::NBody { g: 1.0, softening: 0.1 }).unwrap();
    let before = (w.len(), w.state_hash());
    let r = w.add_particle(&[0.0, 1.0], &[0.0; 2], f64::INFINITY, false);
    assert!(msg(r).starts_with("invalid mass[2] = inf"));
    let r = w.add_particles(&[0.0, 1.0, 0.0, 2.0], None, Some(&[1.0, f64::INFINITY]), false);
    assert!(msg(r).starts_with("invalid mass[3] = inf"));
    assert_eq!((w.len(), w.state_hash()), before);
    // A static particle of finite mass is a fixed attractor: allowed, as by add_force.
    w.add_particle(&[0.0, 1.0], &[0.0; 2], 1.0, true).unwrap();
    w.step(10).unwrap();
    assert_eq!(w.positions()[4..], [0.0, 1.0]);
    assert!(w.positions().iter().all(|x| x.is_finite()));
}

#[test]
fn force_order_does_not_matter() {
    for method in ["velocity-verlet", "rk4", "backward-euler", "leapfrog", "implicit-midpoint"] {
        let forces = forces3d();
        let mut a = world3d(method);
        let mut b =
            World::new(WorldParams { dim: 3, method: method.into(), ..WorldParams::default() }).unwrap();
        b.add_particle(&[0.0, 0.0, 2.0], &[0.0; 3], f64::INFINITY, false).unwrap();
        b.add_particle(&[1.0, 0.5, 2.0], &[0.0; 3], 3.0, true).unwrap();
        b.add_particles(&a.positions()[6..], Some(&a.velocities()[6..]), Some(&a.model().mass()[2..]), false)
            .unwrap();
        // Reversed, with the particle pairs of springs swapped.
        for f in forces.iter().rev() {
            let f = match *f {
                Force::Spring { i, j: Endpoint::Particle(j), stiffness, rest_length, damping } => {
                    spring(j, Endpoint::Particle(i), stiffness, rest_length, damping)
                }
                f => f,
            };
            b.add_force(f).unwrap();
        }
        // And the same forces rotated on a third world.
        let mut c =
            World::new(WorldParams { dim: 3, method: method.into(), ..WorldParams::default() }).unwrap();
        c.add_particle(&[0.0, 0.0, 2.0], &[0.0; 3], f64::INFINITY, false).unwrap();
        c.add_particle(&[1.0, 0.5, 2.0], &[0.0; 3], 3.0, true).unwrap();
        c.add_particles(&a.positions()[6..], Some(&a.velocities()[6..]), Some(&a.model().mass()[2..]), false)
            .unwrap();
        let mut c_forces = forces.clone();
        c_forces.rotate_left(4);
        for f in c_forces {
            c.add_force(f).unwrap();
        }
        assert_eq!(a.state_hash(), b.state_hash());
        for s in 0..100 {
            a.step(1).unwrap();
            b.step(1).unwrap();
            c.step(1).unwrap();
            assert_eq!(bits(a.positions()), bits(b.positions()), "{method} step {s}");
            assert_eq!(bits(a.velocities()), bits(b.velocities()), "{method} step {s}");
            assert_eq!(a.state_hash(), c.state_hash(), "{method} step {s}");
        }
        assert_eq!(a.state_hash(), b.state_hash());
        assert_eq!(a.energy().unwrap().to_bits(), b.energy().unwrap().to_bits());
    }
}

#[test]
fn nbody_conserves_momentum_and_bounds_energy() {
    let mut scene = scenes::build("nbody", &[], "velocity-verlet", 1e-3).unwrap();
    let w = &mut scene.world;
    let scale = |w: &World| -> f64 {
        let m = w.model().mass();
        w.velocities().iter().enumerate().map(|(i, v)| (m[i / 2] * v).abs()).sum()
    };
    let p0 = w.momentum();
    let s0 = scale(w);
    assert!(s0 > 0.1, "the bodies move: {s0}");
    assert!(p0.iter().all(|p| p.abs() <= 1e-14 * s0), "initial momentum {p0:?}");
    let e0 = w.energy().unwrap();
    assert!(e0.is_finite() && e0 < 0.0, "bound cluster, e0 {e0}");
    let mut max_de: f64 = 0.0;
    for _ in 0..100 {
        w.step(20).unwrap();
        let p = w.momentum();
        let s = scale(w);
        for (k, pk) in p.iter().enumerate() {
            assert!(
                (pk - p0[k]).abs() <= 1e-12 * s.max(s0),
                "t {}: momentum {k} {pk} vs {}",
                w.time(),
                p0[k]
            );
        }
        max_de = max_de.max(((w.energy().unwrap() - e0) / e0).abs());
    }
    assert!(max_de < 1e-3, "relative energy error {max_de}");
    eprintln!("nbody velocity-verlet dt 1e-3, 2 s: max |dE/E| = {max_de:e}");
}

#[test]
fn divergence_names_the_particle_and_rolls_back() {
    // Particle 2 sits on a spring far too stiff for explicit Euler at this dt: it blows up
    // first while particles 0 and 1 stay tame.
    let mut w =
        World::new(WorldParams { dim: 2, method: "explicit-euler".into(), dt: 0.5, ..Default::default() })
            .unwrap();
    for x in [0.0, 1.0, 2.0] {
        w.add_particle(&[x, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
    }
    w.add_force(Force::Spring {
        i: 2,
        j: Endpoint::Anchor([3.0, 1.0, 0.0]),
        stiffness: 1e6,
        rest_length: 0.0,
        damping: 0.0,
    })
    .unwrap();
    let err = loop {
        let before = (w.state_hash(), w.steps());
        match w.step(1) {
            Ok(()) => continue,
            Err(e) => {
                assert_eq!((w.state_hash(), w.steps()), before, "rolled back");
                break e;
            }
        }
    };
    assert!(matches!(err, Error::Diverged { particle: Some(2), .. }), "{err:?}");
    let msg = err.to_string();
    assert!(
        msg.contains("explicit-euler") && msg.contains("particle 2") && msg.contains("rolled back"),
        "{msg}"
    );
}

#[test]
fn time_is_steps_times_dt_without_drift() {
    let mut scene = physstep::scenes::build("spring", &[], "rk4", 0.1).unwrap();
    scene.world.step(100).unwrap();
    assert_eq!(scene.world.time(), 10.0);
    scene.world.set_dt(0.01).unwrap();
    scene.world.step(1000).unwrap();
    assert_eq!(scene.world.time(), 20.0);
}

#[test]
fn large_worlds_are_bitwise_the_same_on_one_or_two_threads() {
    // 40,000 particles in 3D: 120,000 coordinates, above the size where the kernels run
    // in parallel chunks.
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(|| {
            let mut w =
                World::new(WorldParams { dim: 3, method: "rk4".into(), dt: 0.01, ..Default::default() })
                    .unwrap();
            let x: Vec<f64> = (0..120_000u64).map(|i| ((i * 7919) % 1000) as f64 * 1e-3).collect();
            let v: Vec<f64> = (0..120_000u64).map(|i| ((i * 104_729) % 1000) as f64 * 1e-3 - 0.5).collect();
            w.add_particles(&x, Some(&v), None, false).unwrap();
            w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
            w.add_force(Force::Drag { linear: 0.1, quadratic: 0.01 }).unwrap();
            w.add_force(Force::CentralGravity { center: [0.5, 0.5, 0.5], gm: 0.1 }).unwrap();
            w.step(5).unwrap();
            (w.state_hash(), bits(w.positions()))
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn set_method_keeps_the_worlds_newton_settings() {
    // One Newton iteration cannot converge on a nonlinear orbit step: the setting must
    // survive a switch of method.
    let params = WorldParams {
        dim: 2,
        method: "rk4".into(),
        dt: 0.1,
        implicit: physstep::integrators::ImplicitParams { tol: 1e-12, max_iter: 1, ..Default::default() },
        ..Default::default()
    };
    let mut w = World::new(params).unwrap();
    w.add_particle(&[1.0, 0.0], &[0.0, 1.0], 1.0, false).unwrap();
    w.add_force(Force::CentralGravity { center: [0.0; 3], gm: 1.0 }).unwrap();
    w.set_method("backward-euler").unwrap();
    assert!(matches!(w.step(1), Err(Error::NotConverged { iterations: 1, .. })));
}

/// A world of one free solid moving and turning at constant rates (no gravity: nothing
/// changes them), a second one at rest.
fn drifting_solid(dim: usize) -> World {
    use physstep::contact::{Shape, SolidParams};
    let mut w = common::world(dim, "symplectic-euler", 0.01);
    let mut p = SolidParams::new(Shape::Circle { radius: 0.5 }, &vec![0.0; dim]);
    p.velocity = if dim == 3 { vec![2.0, -1.0, 0.5] } else { vec![2.0, -1.0] };
    // (A sphere's inertia is isotropic: it turns at a constant rate about a fixed axis.)
    p.angular_velocity = if dim == 3 { vec![0.0, 0.0, 3.0] } else { vec![3.0] };
    w.add_solid(p).unwrap();
    w.add_solid(SolidParams::new(
        Shape::Circle { radius: 0.5 },
        &if dim == 3 { vec![5.0, 0.0, 0.0] } else { vec![5.0, 0.0] },
    ))
    .unwrap();
    w
}

#[test]
fn solids_are_drawn_between_the_last_two_steps_of_a_frame() {
    for dim in [2, 3] {
        let mut w = drifting_solid(dim);
        // 2.5 steps: two steps, alpha 0.5 (the first frame's balance carried).
        w.advance(0.025).unwrap();
        let alpha = w.alpha();
        assert!((alpha - 0.5).abs() < 1e-9, "alpha {alpha}");
        let (x, q) = (w.solid_positions(), w.solid_orientations());
        let (xi, qi) = (w.interpolated_solid_positions(), w.interpolated_solid_orientations());
        assert_eq!((xi.len(), qi.len()), (x.len(), q.len()));
        // Constant velocity: the drawn pose is (1 - alpha) of a step behind.
        let back = (1.0 - alpha) * 0.01;
        let v = [2.0, -1.0, 0.5];
        for k in 0..dim {
            assert!((xi[k] - (x[k] - back * v[k])).abs() < 1e-12, "dim {dim} x[{k}]");
            assert_eq!(xi[dim + k].to_bits(), x[dim + k].to_bits(), "a solid at rest is drawn where it is");
        }
        if dim == 2 {
            assert!((qi[0] - (q[0] - back * 3.0)).abs() < 1e-12);
        } else {
            // Turned about z by 3 rad/s: the drawn quaternion is (cos, 0, 0, sin) of half
            // the angle (1 - alpha) of a step back.
            let angle = 3.0 * (w.time() - back);
            let want = [(angle / 2.0).cos(), 0.0, 0.0, (angle / 2.0).sin()];
            for k in 0..4 {
                assert!((qi[k] - want[k]).abs() < 1e-12, "q[{k}] {} vs {}", qi[k], want[k]);
            }
        }
        // Outside a frame (a step) and once a solid is added: drawn as they are.
        w.step(1).unwrap();
        assert_eq!(w.interpolated_solid_positions(), w.solid_positions());
        assert_eq!(w.interpolated_solid_orientations(), w.solid_orientations());
        w.advance(0.025).unwrap();
        assert_ne!(w.interpolated_solid_positions(), w.solid_positions());
        use physstep::contact::{Shape, SolidParams};
        w.add_solid(SolidParams::new(
            Shape::Circle { radius: 0.5 },
            &if dim == 3 { vec![9.0, 0.0, 0.0] } else { vec![9.0, 0.0] },
        ))
        .unwrap();
        assert_eq!(w.interpolated_solid_positions(), w.solid_positions());
    }
}
