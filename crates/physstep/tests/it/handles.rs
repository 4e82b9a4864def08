//! Forces by handle: every added force gets an id that stays its own while other forces come
//! and go; a removed force leaves the world stepping bitwise as one that never had it; a force
//! changed through its id is what the next step sees; bad ids and values are one line naming
//! the field, the world unchanged.

use physstep::forces::{Endpoint, ForceGenerator, ForceId};
use physstep::prelude::*;
use std::sync::Arc;

const METHODS: [&str; 6] =
    ["symplectic-euler", "velocity-verlet", "rk4", "leapfrog", "verlet", "backward-euler"];

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Four particles in 2D, the first static.
fn particles(method: &str) -> World {
    let mut w =
        World::new(WorldParams { dim: 2, method: method.into(), dt: 0.01, ..Default::default() }).unwrap();
    w.add_particle(&[0.0, 0.0], &[0.0, 0.0], 1.0, true).unwrap();
    w.add_particle(&[1.0, 0.2], &[0.1, 0.0], 1.5, false).unwrap();
    w.add_particle(&[2.0, -0.3], &[0.0, 0.3], 0.5, false).unwrap();
    w.add_particle(&[0.5, 1.0], &[-0.2, 0.1], 2.0, false).unwrap();
    w
}

fn gravity() -> Force {
    Force::Gravity { g: [0.0, -9.81, 0.0] }
}

fn drag() -> Force {
    Force::Drag { linear: 0.05, quadratic: 0.01 }
}

fn pair_spring() -> Force {
    spring(Endpoint::Particle(2), 40.0, 0.8, 0.2)
}

/// The pair spring from particle 1 with other ends or parameters.
fn spring(j: Endpoint, stiffness: f64, rest_length: f64, damping: f64) -> Force {
    Force::Spring { i: 1, j, stiffness, rest_length, damping }
}

fn anchor_spring() -> Force {
    Force::Spring {
        i: 3,
        j: Endpoint::Anchor([0.5, 2.0, 0.0]),
        stiffness: 25.0,
        rest_length: 0.5,
        damping: 0.1,
    }
}

fn central() -> Force {
    Force::CentralGravity { center: [5.0, 5.0, 0.0], gm: 3.0 }
}

fn run(w: &mut World, steps: u64) -> (Vec<u64>, Vec<u64>, u64) {
    w.step(steps).unwrap();
    (bits(w.positions()), bits(w.velocities()), w.state_hash())
}

#[test]
fn a_removed_force_leaves_the_world_stepping_bitwise_as_one_that_never_had_it() {
    // Each force in turn is the one removed: a pair spring (its removal makes every force
    // per-particle again, so the fused kernels take over), gravity (the uniform sums are
    // gathered again), an anchor spring, drag and central gravity.
    let all = [gravity(), pair_spring(), drag(), anchor_spring(), central()];
    for method in METHODS {
        for gone in 0..all.len() {
            let mut with = particles(method);
            let ids: Vec<ForceId> = all.iter().map(|f| with.add_force(*f).unwrap()).collect();
            with.remove_force(ids[gone]).unwrap();
            let mut without = particles(method);
            for (k, f) in all.iter().enumerate() {
                if k != gone {
                    without.add_force(*f).unwrap();
                }
            }
            // The set and what it derives (kinds, the per-particle forces) as if never added.
            assert_eq!(with.model().forces(), without.model().forces(), "{method}, force {gone}");
            assert_eq!(run(&mut with, 200), run(&mut without, 200), "{method}, force {gone}");
            assert_eq!(with.force(ids[gone]), None);
        }
    }
}

#[test]
fn a_force_removed_between_steps_is_gone_from_the_next_step_on() {
    // Removed mid-run: the next steps are those of a copy of the world (same state, same
    // restart of the method's memory) that never had the force.
    for method in METHODS {
        let mut w = particles(method);
        w.add_force(gravity()).unwrap();
        w.add_force(anchor_spring()).unwrap();
        let spring = w.add_force(pair_spring()).unwrap();
        w.step(50).unwrap();
        let mut copy = w.clone();
        w.remove_force(spring).unwrap();
        // The same world built anew from the state after 50 steps, without the spring.
        let mut fresh = particles(method);
        fresh.add_force(gravity()).unwrap();
        fresh.add_force(anchor_spring()).unwrap();
        fresh.restore(&copy.snapshot()).unwrap();
        // restore carries the method's memory: restart it as the removal did.
        fresh.set_method(method).unwrap();
        let a = run(&mut w, 100);
        let b = run(&mut fresh, 100);
        assert_eq!(a, b, "{method}");
        // And the world that kept the spring goes elsewhere.
        assert_ne!(run(&mut copy, 100).0, a.0, "{method}");
    }
}

#[test]
fn a_springs_stiffness_changed_through_its_id_changes_the_next_step() {
    for method in METHODS {
        let stiffer = spring(Endpoint::Particle(2), 90.0, 0.8, 0.2);
        let mut w = particles(method);
        w.add_force(gravity()).unwrap();
        let id = w.add_force(pair_spring()).unwrap();
        let mut before = w.clone();
        w.set_force(id, stiffer).unwrap();
        assert_eq!(w.force(id), Some(stiffer));
        let mut from_start = particles(method);
        from_start.add_force(gravity()).unwrap();
        from_start.add_force(stiffer).unwrap();
        assert_eq!(w.model().forces(), from_start.model().forces());
        let a = run(&mut w, 1);
        assert_eq!(a, run(&mut from_start, 1), "{method}");
        assert_ne!(a.0, run(&mut before, 1).0, "{method}: the change was not seen by the next step");
    }
}

#[test]
fn ids_stay_with_their_forces_while_others_come_and_go_and_are_never_given_twice() {
    let mut w = particles("rk4");
    let s = w.add_spring(1, Endpoint::Particle(2), 10.0, None, 0.0).unwrap();
    let g = w.add_force(gravity()).unwrap();
    let r = w.add_rod(3, Endpoint::Particle(1), None).unwrap();
    let d = w.add_force(drag()).unwrap();
    assert_eq!([s, g, r, d], [ForceId(0), ForceId(1), ForceId(2), ForceId(3)]);
    // Gravity sorts before the spring: indices move, ids do not.
    w.remove_force(g).unwrap();
    assert!(matches!(w.force(s), Some(Force::Spring { stiffness, .. }) if stiffness == 10.0));
    assert!(matches!(w.force(r), Some(Force::Rod { i: 1, j: Endpoint::Particle(3), .. })));
    assert_eq!(w.force(d), Some(drag()));
    assert_eq!(w.force(g), None);
    let g2 = w.add_force(gravity()).unwrap();
    assert_eq!(g2, ForceId(4));
    assert_eq!(w.force_ids(), vec![g2, s, d, r]);
    // A user force draws from the same counter and is removed by its id as well.
    let u = w.add_force_generator(Arc::new(Push)).unwrap();
    assert_eq!(u, ForceId(5));
    assert!(w.is_user_force(u) && w.force(u).is_none());
    assert_eq!(w.force_ids(), vec![g2, s, d, r, u]);
    w.remove_force(u).unwrap();
    assert_eq!(w.model().user_forces(), 0);
    assert_eq!(w.add_force(drag()).unwrap(), ForceId(6));
}

struct Push;

impl ForceGenerator for Push {
    fn add_forces(&self, _t: f64, _x: &[f64], v: &[f64], f: &mut [f64]) -> std::result::Result<(), String> {
        for (fk, vk) in f.iter_mut().zip(v) {
            *fk += 0.3 - 0.1 * vk;
        }
        Ok(())
    }
}

#[test]
fn a_removed_user_force_leaves_the_world_stepping_as_one_without_it() {
    let mut with = particles("rk4");
    with.add_force(gravity()).unwrap();
    let u = with.add_force_generator(Arc::new(Push)).unwrap();
    with.remove_force(u).unwrap();
    let mut without = particles("rk4");
    without.add_force(gravity()).unwrap();
    assert_eq!(run(&mut with, 100), run(&mut without, 100));
}

#[test]
fn bad_removals_and_changes_are_one_line_naming_the_field_and_change_nothing() {
    let mut w = particles("velocity-verlet");
    let g = w.add_force(gravity()).unwrap();
    let s = w.add_force(pair_spring()).unwrap();
    let before = (w.model().forces().clone(), w.force_ids(), w.state_hash());
    let msg = |e: physstep::Error| {
        let m = e.to_string();
        assert!(!m.contains('\n'), "{m}");
        m
    };
    assert_eq!(
        msg(w.remove_force(ForceId(9)).unwrap_err()),
        "invalid force = 9: must be the id of a force of this world (it was removed, or never added here)"
    );
    assert_eq!(
        msg(w.set_force(s, gravity()).unwrap_err()),
        "invalid kind = gravity: must be 'spring', the kind of force 1 (remove it and add the other instead)"
    );
    let bad = |f: &dyn Fn(f64) -> Force, v: f64| msg(w.clone().set_force(s, f(v)).unwrap_err());
    assert!(bad(&|k| spring(Endpoint::Particle(2), k, 0.8, 0.2), -1.0).starts_with("invalid stiffness = -1"));
    assert!(bad(&|k| spring(Endpoint::Particle(2), 40.0, k, 0.2), f64::NAN)
        .starts_with("invalid rest_length = NaN"));
    assert!(bad(&|k| spring(Endpoint::Particle(2), 40.0, 0.8, k), f64::INFINITY)
        .starts_with("invalid damping = inf"));
    assert!(
        bad(&|k| spring(Endpoint::Particle(k as usize), 40.0, 0.8, 0.2), 1.0).starts_with("invalid j = 1")
    );
    assert!(msg(w.set_force(g, Force::Gravity { g: [f64::NAN, 0.0, 0.0] }).unwrap_err())
        .starts_with("invalid g = "));
    assert!(msg(w.set_force(ForceId(7), gravity()).unwrap_err()).starts_with("invalid force = 7"));
    w.remove_force(g).unwrap();
    assert!(msg(w.remove_force(g).unwrap_err()).starts_with("invalid force = 0"));
    assert!(msg(w.set_force(g, gravity()).unwrap_err()).starts_with("invalid force = 0"));
    // Only the one good removal changed anything.
    let mut again = particles("velocity-verlet");
    again.add_force(pair_spring()).unwrap();
    assert_eq!(w.model().forces(), again.model().forces());
    assert_eq!(before.1[1..], w.force_ids());
    assert_eq!(before.2, w.state_hash());
}

#[test]
fn force_ids_survive_a_round_trip_through_scene_text_when_set_back() {
    let mut w = particles("rk4");
    let g = w.add_force(gravity()).unwrap();
    let s = w.add_force(pair_spring()).unwrap();
    let d = w.add_force(drag()).unwrap();
    w.remove_force(g).unwrap();
    let text = physstep::scenes::file::structure(&w).unwrap();
    let mut back =
        physstep::scenes::file::parse_structure(&text, "round trip", LoopMode::Accumulator).unwrap().world;
    // Scene text carries no ids: its forces get them in reading order.
    assert_eq!(back.force_ids().len(), 2);
    back.set_force_ids(&w.force_ids(), w.next_force_id().0).unwrap();
    assert_eq!(back.force(s), w.force(s));
    assert_eq!(back.force(d), Some(drag()));
    assert_eq!(back.add_force(gravity()).unwrap(), ForceId(3));
    // Bad ids: one line naming them, nothing changed.
    let ids = back.force_ids();
    let e = back.set_force_ids(&[s, s, d], 9).unwrap_err().to_string();
    assert_eq!(e, "invalid ids = 1: must be distinct ids below next = 9");
    let e = back.set_force_ids(&[s], 9).unwrap_err().to_string();
    assert_eq!(e, "invalid len(ids) = 1: must be 3, one per force");
    assert_eq!(back.force_ids(), ids);
}

#[test]
fn a_rod_changed_through_its_id_keeps_the_length_its_ends_have() {
    let mut w = particles("rk4");
    let r = w.add_rod(1, Endpoint::Particle(3), None).unwrap();
    let Some(Force::Rod { length, .. }) = w.force(r) else { panic!("not a rod") };
    let e = w.set_force(r, Force::Rod { i: 1, j: Endpoint::Particle(3), length: 2.0 * length }).unwrap_err();
    assert!(e.to_string().starts_with("invalid length = "), "{e}");
    assert!(e.to_string().contains("the current distance"), "{e}");
    // Its other end moved to another particle at the same distance is a rod all the same.
    let to_anchor = Force::Rod { i: 1, j: Endpoint::Anchor([1.0 + length, 0.2, 0.0]), length };
    w.set_force(r, to_anchor).unwrap();
    assert_eq!(w.force(r), Some(to_anchor));
}

#[test]
fn a_change_after_fused_steps_is_seen_by_the_next_step() {
    // Per-particle forces only: the fused kernels take the steps and keep a rollback for
    // the next call; a change through the id must reach the next step all the same.
    for method in ["symplectic-euler", "velocity-verlet", "rk4"] {
        let mut w = particles(method);
        let g = w.add_force(gravity()).unwrap();
        w.add_force(anchor_spring()).unwrap();
        for _ in 0..10 {
            w.step(1).unwrap();
        }
        let snapshot = w.snapshot();
        let pulled = Force::Gravity { g: [1.0, -3.0, 0.0] };
        w.set_force(g, pulled).unwrap();
        let mut fresh = particles(method);
        fresh.add_force(pulled).unwrap();
        fresh.add_force(anchor_spring()).unwrap();
        fresh.restore(&snapshot).unwrap();
        fresh.set_method(method).unwrap();
        for _ in 0..10 {
            w.step(1).unwrap();
            fresh.step(1).unwrap();
        }
        assert_eq!(bits(w.positions()), bits(fresh.positions()), "{method}");
        assert_eq!(bits(w.velocities()), bits(fresh.velocities()), "{method}");
    }
}
