//! Sleeping (docs/contact.md, "Sleeping"): islands of solids at rest leave the contact solver,
//! stay exactly where they rested, and wake whole when something reaches them; the state is in
//! the hash, the snapshot and the rollback.

use glam::DVec2;
use physstep::contact::{Kind, Plane, Shape, SolidMotion, SolidParams, Solids, SLEEP_SPEED};
use physstep::prelude::*;

const DT: f64 = 1.0 / 60.0;
const G: DVec2 = DVec2::new(0.0, -9.81);

/// A static ground (top at y = 0) and a stack of `n` unit boxes on it, sleeping after
/// `sleep_time` of rest.
fn stack(n: usize, sleep_time: f64) -> Solids<Plane> {
    let mut s = Solids::<Plane>::new();
    s.settings.sleep_time = sleep_time;
    let mut ground = SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0]);
    ground.kind = Kind::Static;
    s.add(ground).unwrap();
    for k in 0..n {
        s.add(SolidParams::new(Shape::Box { half: vec![0.5, 0.5] }, &[0.0, 0.5 + k as f64])).unwrap();
    }
    s
}

/// Steps until every dynamic solid is asleep; returns the steps taken.
fn until_asleep(s: &mut Solids<Plane>, most: usize) -> usize {
    for k in 1..=most {
        s.step(DT, G).unwrap();
        if s.asleep()[1..].iter().all(|a| *a) {
            return k;
        }
    }
    panic!("not asleep after {most} steps: {:?}", s.asleep());
}

#[test]
fn a_stack_at_rest_falls_asleep_whole_and_then_does_not_move() {
    let mut s = stack(5, 0.5);
    let k = until_asleep(&mut s, 120);
    // Half a second of rest, and no sooner: the stack settles in its first steps.
    assert!(k >= 30, "asleep after {k} steps");
    let (x, q) = (s.positions(), s.orientations());
    assert!(s.velocities().iter().chain(&s.angular_velocities()).all(|v| *v == 0.0));
    assert_eq!(s.kinetic_energy(), 0.0);
    for _ in 0..300 {
        s.step(DT, G).unwrap();
    }
    assert_eq!((s.positions(), s.orientations()), (x.clone(), q));
    // Where it fell asleep is where it rests awake, within the solver's own settling.
    let mut awake = stack(5, 0.0);
    for _ in 0..k + 300 {
        awake.step(DT, G).unwrap();
    }
    assert!(awake.asleep().iter().all(|a| !a));
    for (a, b) in x.iter().zip(awake.positions()) {
        assert!((a - b).abs() < 1e-3, "{a} asleep, {b} awake");
    }
}

#[test]
fn a_box_dropped_on_a_sleeping_stack_wakes_it_before_it_lands() {
    let mut s = stack(3, 0.5);
    until_asleep(&mut s, 120);
    let top = s.positions()[2 * 3 + 1];
    let dropped = s.add(SolidParams::new(Shape::Box { half: vec![0.5, 0.5] }, &[0.0, top + 3.0])).unwrap();
    let mut woke_at = None;
    for k in 0..240 {
        let before = s.asleep();
        s.step(DT, G).unwrap();
        let asleep = s.asleep();
        if woke_at.is_none() && !asleep[1..=3].iter().any(|a| *a) {
            woke_at = Some(k);
        }
        // No contact of the dropped box is with a solid asleep through the step (static to
        // it): the stack was woken first.
        for c in s.contacts().iter().filter(|c| c.pair.1 == dropped && c.depth >= 0.0) {
            let i = c.pair.0;
            assert!(!(before[i] && asleep[i]), "step {k}: box {i} asleep under the dropped one");
        }
    }
    assert!(woke_at.is_some(), "the stack did not wake");
    // It lands on the stack and all of it rests again, asleep.
    until_asleep(&mut s, 240);
    let y = s.positions()[2 * dropped + 1];
    assert!((y - (top + 1.0)).abs() < 0.01, "the dropped box rests at {y}, the top at {top}");
}

#[test]
fn a_motion_set_or_a_load_applied_by_hand_wakes_the_island_at_once() {
    let mut s = stack(3, 0.5);
    until_asleep(&mut s, 120);
    let ids = s.solid_ids();
    let mut pushed = s.clone();
    pushed.apply(2, &[50.0, 0.0], None, &[0.0]).unwrap();
    assert_eq!(pushed.asleep(), [false; 4]);
    let mut moved = s.clone();
    moved.set_motion(ids[3], &SolidMotion { velocity: Some(vec![1.0, 0.0]), ..Default::default() }).unwrap();
    assert_eq!(moved.asleep(), [false; 4]);
    moved.step(DT, G).unwrap();
    assert!(moved.velocities()[6] > 0.5, "the top box was not stepped awake");
    // Gravity that changes wakes everything.
    let mut tilted = s.clone();
    tilted.step(DT, DVec2::new(3.0, -9.81)).unwrap();
    assert!(tilted.asleep().iter().all(|a| !a));
    assert!(tilted.velocities()[2] > 0.0);
}

#[test]
fn the_sleep_threshold_is_box2ds() {
    assert_eq!(SLEEP_SPEED, 0.05);
    // A box sliding slower than it on frictionless ice keeps its idle time growing but is
    // asleep only once the whole island was slow for the sleep time; one faster never.
    for (v, asleep) in [(0.04, true), (0.06, false)] {
        let mut s = Solids::<Plane>::new();
        s.settings.sleep_time = 0.5;
        let mut ice = SolidParams::new(Shape::Box { half: vec![500.0, 1.0] }, &[0.0, -1.0]);
        (ice.kind, ice.friction) = (Kind::Static, 0.0);
        s.add(ice).unwrap();
        let mut b = SolidParams::new(Shape::Box { half: vec![0.5, 0.5] }, &[0.0, 0.5]);
        (b.velocity, b.friction) = (vec![v, 0.0], 0.0);
        s.add(b).unwrap();
        for _ in 0..60 {
            s.step(DT, G).unwrap();
        }
        assert_eq!(s.asleep()[1], asleep, "sliding at {v} m/s");
    }
}

fn dice(sleep_time: f64) -> World {
    let mut w = scenes::build("dice", &[("n", 40.0)], "symplectic-euler", DT).unwrap().world;
    w.set_sleep_time(sleep_time).unwrap();
    w
}

#[test]
fn sleep_is_in_the_hash_the_snapshot_and_the_rollback_and_the_same_on_any_thread_count() {
    let mut w = dice(0.5);
    w.step(150).unwrap();
    let asleep = w.solids_asleep().iter().filter(|a| **a).count();
    assert!(asleep > 10, "{asleep} asleep");
    let (snap, hash) = (w.snapshot(), w.state_hash());
    // Woken by hand (the same velocity, zero): another state.
    let mut woken = w.clone();
    let sleeper = w.solids_asleep().iter().position(|a| *a).unwrap();
    let id = w.solid_ids()[sleeper];
    woken.set_solid_motion(id, &SolidMotion { velocity: Some(vec![0.0; 3]), ..Default::default() }).unwrap();
    assert_ne!(woken.state_hash(), hash);
    let mut twin = dice(0.5);
    twin.restore(&snap).unwrap();
    assert_eq!(twin.state_hash(), hash);
    w.step(60).unwrap();
    twin.step(60).unwrap();
    assert_eq!(twin.state_hash(), w.state_hash());
    // A snapshot taken while sleeping is on does not fit a world with it off.
    let mut off = dice(0.0);
    let before = off.state_hash();
    assert!(matches!(off.restore(&snap), Err(Error::Corrupt { .. })));
    assert_eq!(off.state_hash(), before);
    // One thread or two.
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut c = dice(0.5);
        pool.install(|| c.step(200).unwrap());
        c.state_hash()
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_failed_step_puts_the_sleep_back() {
    // Two particles on a spring far too stiff for the step: a step diverges while dice land,
    // rest and fall asleep (their idle times, flags and islands are in the hash), and is
    // rolled back with the solids.
    let mut w = dice(0.5);
    w.add_particle(&[50.0, 5.0, 0.0], &[0.0; 3], 1.0, false).unwrap();
    w.add_particle(&[51.0, 5.0, 0.0], &[0.0; 3], 1.0, false).unwrap();
    w.add_force(Force::Spring {
        i: 0,
        j: Endpoint::Particle(1),
        stiffness: 1e9,
        rest_length: 0.5,
        damping: 0.0,
    })
    .unwrap();
    for k in 0..400 {
        let (hash, asleep) = (w.state_hash(), w.solids_asleep());
        if let Err(e) = w.step(1) {
            assert!(matches!(e, Error::Diverged { .. }), "{e}");
            assert_eq!((w.state_hash(), w.solids_asleep()), (hash, asleep), "step {k}");
            return;
        }
    }
    panic!("the spring did not diverge");
}

#[test]
fn sleep_time_is_checked_and_goes_through_scene_files() {
    let mut w = dice(0.0);
    let hash = w.state_hash();
    for (bad, shown) in [(-1.0, "-1"), (f64::NAN, "NaN"), (f64::INFINITY, "inf")] {
        let m = w.set_sleep_time(bad).unwrap_err().to_string();
        assert!(m.contains(&format!("sleep_time = {shown}")) && m.contains(">= 0"), "{m}");
        assert!(!m.contains('\n'));
    }
    assert_eq!((w.state_hash(), w.contact_settings().sleep_time), (hash, 0.0));
    w.set_sleep_time(0.75).unwrap();
    let text = physstep::scenes::file::export(&w, "dice", None).unwrap();
    assert!(text.contains("sleep_time = 0.75"), "{text}");
    let mut back = physstep::scenes::file::parse(&text, "dice.toml").unwrap().world;
    assert_eq!(back.contact_settings().sleep_time, 0.75);
    w.step(120).unwrap();
    back.step(120).unwrap();
    assert_eq!(back.state_hash(), w.state_hash());
    let bad = text.replace("sleep_time = 0.75", "sleep_time = -2");
    let m = physstep::scenes::file::parse(&bad, "dice.toml").unwrap_err().to_string();
    assert!(m.contains("sleep_time") && m.contains("-2"), "{m}");
}
