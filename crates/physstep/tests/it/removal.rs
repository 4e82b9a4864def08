//! Removing particles and constraints by id: the ids of the others still reach them, the
//! arrays lose the rows, what hung on a removed particle goes with it, and the world then
//! steps bitwise as one built without it; snapshots and hashes cover the ids; bad ids are one
//! line naming the field, the world unchanged.

use physstep::constraints::Constraint;
use physstep::forces::Endpoint;
use physstep::prelude::*;
use physstep::world::{ConstraintId, ParticleId};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn world(method: &str, dim: usize) -> World {
    World::new(WorldParams { dim, method: method.into(), dt: 0.01, ..Default::default() }).unwrap()
}

/// Position, velocity, mass of the four particles of the removal worlds.
const P: [([f64; 2], [f64; 2], f64); 4] = [
    ([0.0, 0.0], [0.0, 0.1], 1.0),
    ([1.0, 0.2], [0.1, 0.0], 1.5),
    ([2.0, -0.3], [0.0, 0.3], 0.5),
    ([0.5, 1.0], [-0.2, 0.1], 2.0),
];

#[test]
fn three_particles_remove_the_second_the_third_still_reached_and_two_rows() {
    let mut w = world("symplectic-euler", 2);
    let ids: Vec<ParticleId> = (0..3)
        .map(|k| {
            let row = w.add_particle(&[k as f64, 0.0], &[0.0, k as f64], 1.0 + k as f64, false).unwrap();
            w.particle_id(row).unwrap()
        })
        .collect();
    assert_eq!(ids, [ParticleId(0), ParticleId(1), ParticleId(2)]);
    w.remove_particle(ids[1]).unwrap();
    assert_eq!(w.len(), 2);
    assert_eq!(w.positions(), &[0.0, 0.0, 2.0, 0.0]);
    assert_eq!(w.velocities(), &[0.0, 0.0, 0.0, 2.0]);
    assert_eq!(w.model().mass(), &[1.0, 3.0]);
    assert_eq!(w.particle_row(ids[2]), Some(1));
    assert_eq!(w.particle_row(ids[0]), Some(0));
    assert_eq!(w.particle_row(ids[1]), None);
    // A new particle gets a new id, never the removed one's.
    let row = w.add_particle(&[5.0, 0.0], &[0.0, 0.0], 1.0, false).unwrap();
    assert_eq!((row, w.particle_id(row)), (2, Some(ParticleId(3))));
    w.step(3).unwrap();
    assert_eq!(w.particle_ids(), [ParticleId(0), ParticleId(2), ParticleId(3)]);
}

#[test]
fn a_dead_or_foreign_particle_id_is_one_line_and_the_world_unchanged() {
    let mut w = world("rk4", 2);
    for (x, v, m) in P {
        w.add_particle(&x, &v, m, false).unwrap();
    }
    w.remove_particle(ParticleId(1)).unwrap();
    let hash = w.state_hash();
    for id in [1, 4, 99] {
        let e = w.remove_particle(ParticleId(id)).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "invalid particle = {id}: must be the id of a particle of this world (it was removed, or never added here)"
            )
        );
    }
    let e = w.remove_constraint(ConstraintId(0)).unwrap_err().to_string();
    assert!(e.starts_with("invalid constraint = 0: "), "{e}");
    assert_eq!((w.len(), w.state_hash()), (3, hash));
}

/// The world of `P` with every kind of force, particle 1 touched by a pair spring, a rod
/// and an anchor spring; `without`: particles 0, 2, 3 only, with what stays of the forces
/// (the rod's length as the full world's).
fn forces_world(method: &str, without: bool) -> World {
    let mut w = world(method, 2);
    for (k, (x, v, m)) in P.iter().enumerate() {
        if !(without && k == 1) {
            w.add_particle(x, v, *m, false).unwrap();
        }
    }
    // Row of original particle k.
    let r = |k: usize| if without && k > 1 { k - 1 } else { k };
    let rod_02 = ((P[2].0[0] - P[0].0[0]).powi(2) + (P[2].0[1] - P[0].0[1]).powi(2)).sqrt();
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    w.add_force(Force::Drag { linear: 0.05, quadratic: 0.01 }).unwrap();
    w.add_force(Force::CentralGravity { center: [5.0, 5.0, 0.0], gm: 3.0 }).unwrap();
    w.add_force(Force::NBody { g: 0.1, softening: 0.05 }).unwrap();
    let spring = |i, j| Force::Spring { i, j, stiffness: 40.0, rest_length: 0.8, damping: 0.2 };
    if !without {
        w.add_force(spring(0, Endpoint::Particle(1))).unwrap();
        w.add_force(spring(1, Endpoint::Anchor([0.0, 2.0, 0.0]))).unwrap();
        w.add_rod(1, Endpoint::Particle(3), None).unwrap();
    }
    w.add_force(spring(r(3), Endpoint::Particle(r(2)))).unwrap();
    w.add_force(spring(r(3), Endpoint::Anchor([0.5, 2.0, 0.0]))).unwrap();
    w.add_force(Force::Rod { i: r(0), j: Endpoint::Particle(r(2)), length: rod_02 }).unwrap();
    w
}

#[test]
fn a_removed_particle_leaves_the_world_stepping_bitwise_as_one_built_without_it() {
    for method in ["symplectic-euler", "velocity-verlet", "rk4", "leapfrog", "verlet", "backward-euler"] {
        // Removed before the first step: the same from the start.
        let mut a = forces_world(method, false);
        let removed = a.remove_particle(ParticleId(1)).unwrap();
        assert_eq!(removed.forces.len(), 3, "{method}: the springs and the rod on particle 1");
        let mut b = forces_world(method, true);
        assert_eq!(
            a.model().forces().iter().collect::<Vec<_>>(),
            b.model().forces().iter().collect::<Vec<_>>()
        );
        a.step(40).unwrap();
        b.step(40).unwrap();
        assert_eq!(bits(a.positions()), bits(b.positions()), "{method}");
        assert_eq!(bits(a.velocities()), bits(b.velocities()), "{method}");

        // Removed after steps: the rest steps as a world started from that state.
        let mut a = forces_world(method, false);
        a.step(25).unwrap();
        a.remove_particle(ParticleId(1)).unwrap();
        let mut b = forces_world(method, true);
        b.set_positions(a.positions()).unwrap();
        b.set_velocities(a.velocities()).unwrap();
        a.step(30).unwrap();
        b.step(30).unwrap();
        assert_eq!(bits(a.positions()), bits(b.positions()), "{method} after steps");
        assert_eq!(bits(a.velocities()), bits(b.velocities()), "{method} after steps");
    }
}

#[test]
fn removing_a_particle_takes_its_constraints_and_renumbers_the_rest() {
    let mut a = world("symplectic-euler", 2);
    for (x, v, m) in P {
        a.add_particle(&x, &v, m, false).unwrap();
    }
    a.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    a.add_distance_constraint(0, Endpoint::Particle(1), None, 0.0).unwrap();
    a.add_pin(0, &[0.0, 0.0]).unwrap();
    a.add_rope(2, Endpoint::Particle(3), 2.0).unwrap();
    a.add_distance_limit(1, Endpoint::Particle(3), 0.1, 3.0).unwrap();
    a.add_plane(&[0.0, 1.0], -5.0).unwrap();
    let removed = a.remove_particle(ParticleId(1)).unwrap();
    assert_eq!(removed.constraints, [ConstraintId(0), ConstraintId(3)]);
    assert_eq!(a.constraint_ids(), [ConstraintId(1), ConstraintId(2), ConstraintId(4)]);
    assert_eq!(
        a.constraint(ConstraintId(2)),
        Some(Constraint::Limit { i: 1, j: Endpoint::Particle(2), min: 0.0, max: 2.0 })
    );
    let mut b = world("symplectic-euler", 2);
    for (k, (x, v, m)) in P.iter().enumerate() {
        if k != 1 {
            b.add_particle(x, v, *m, false).unwrap();
        }
    }
    b.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    b.add_pin(0, &[0.0, 0.0]).unwrap();
    b.add_rope(1, Endpoint::Particle(2), 2.0).unwrap();
    b.add_plane(&[0.0, 1.0], -5.0).unwrap();
    a.step(30).unwrap();
    b.step(30).unwrap();
    assert_eq!(bits(a.positions()), bits(b.positions()));
    // Removing a constraint by id: the rest relax as a world without it.
    a.remove_constraint(ConstraintId(1)).unwrap();
    assert_eq!(a.constraint(ConstraintId(1)), None);
    assert!(a.remove_constraint(ConstraintId(1)).is_err());
    assert_eq!(a.constraint_row(ConstraintId(4)), Some(1));
}

#[test]
fn a_removed_ball_takes_its_radius_and_the_others_keep_theirs() {
    let mut a = world("velocity-verlet", 2);
    a.add_walls(&[-5.0, -5.0], &[5.0, 5.0]).unwrap();
    let radii = [0.3, 0.2, 0.4];
    for (k, r) in radii.iter().enumerate() {
        a.add_ball(&[k as f64 * 1.5 - 1.5, 0.0], &[1.0 - k as f64, 0.5], *r, 1.0).unwrap();
    }
    a.remove_particle(ParticleId(1)).unwrap();
    assert_eq!(a.radii(), vec![0.3, 0.4]);
    let mut b = world("velocity-verlet", 2);
    b.add_walls(&[-5.0, -5.0], &[5.0, 5.0]).unwrap();
    for k in [0usize, 2] {
        b.add_ball(&[k as f64 * 1.5 - 1.5, 0.0], &[1.0 - k as f64, 0.5], radii[k], 1.0).unwrap();
    }
    a.step(200).unwrap();
    b.step(200).unwrap();
    assert_eq!(bits(a.positions()), bits(b.positions()));
    assert!(a.collisions().count > 0, "the balls met a wall");
}

#[test]
fn snapshots_and_hashes_cover_the_ids() {
    let build = || {
        let mut w = world("velocity-verlet", 2);
        for (x, v, m) in P {
            w.add_particle(&x, &v, m, false).unwrap();
        }
        w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
        w
    };
    // Nothing removed: no ids in the hash (recorded hashes stay), none in the snapshot.
    let mut a = build();
    let before = a.snapshot();
    a.remove_particle(ParticleId(3)).unwrap();
    a.add_particle(&P[3].0, &P[3].1, P[3].2, false).unwrap();
    // Same rows, same numbers: only the ids differ, and the hash says so.
    let b = build();
    assert_eq!(bits(a.positions()), bits(b.positions()));
    assert_ne!(a.state_hash(), b.state_hash());
    // A snapshot from before the removal is refused in one line, the world unchanged.
    let hash = a.state_hash();
    let e = a.restore(&before).unwrap_err().to_string();
    assert!(e.contains("other particles, bodies or constraints"), "{e}");
    assert!(!e.contains('\n'));
    assert_eq!(a.state_hash(), hash);
    // A snapshot after it restores bitwise, and continues as the original.
    a.step(5).unwrap();
    let snap = a.snapshot();
    let mut c = a.clone();
    a.step(10).unwrap();
    c.step(3).unwrap();
    c.restore(&snap).unwrap();
    c.step(10).unwrap();
    assert_eq!(a.state_hash(), c.state_hash());
    // Into the same structure rebuilt with the ids given back (what a pickle does).
    let mut d = build();
    d.set_entity_ids(&a.particle_ids(), &[], &[], [5, 0, 0]).unwrap();
    d.restore(&snap).unwrap();
    d.step(10).unwrap();
    assert_eq!(d.state_hash(), a.state_hash());
    // Ids that do not fit are refused.
    let mut e = build();
    let bad = [ParticleId(0), ParticleId(2), ParticleId(1), ParticleId(4)];
    let msg = e.set_entity_ids(&bad, &[], &[], [5, 0, 0]).unwrap_err().to_string();
    assert!(msg.starts_with("invalid particle_ids = 1: "), "{msg}");
}

/// Two bodies and a particle in 3D, body 0 on a spring to the particle and body 1 on one to
/// an anchor; `without`: body 0 never added.
fn bodies_world(method: &str, without: bool) -> World {
    use physstep::rigid::inertia::Shape;
    use physstep::world::BodyParams;
    let mut w = world(method, 3);
    w.add_particle(&[0.0, 2.0, 0.0], &[0.1, 0.0, 0.0], 1.0, false).unwrap();
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    let body = |x: f64, spin: f64| BodyParams {
        shape: Shape::Box { half_extents: [0.5, 0.3, 0.2] },
        mass: Some(2.0),
        position: [x, 0.0, 0.0],
        angular_velocity: [spin, 1.0, 0.2],
        velocity: [0.0, 0.5, 0.0],
        ..BodyParams::default()
    };
    if !without {
        w.add_body(&body(-1.0, 3.0)).unwrap();
        w.add_body_spring(0, [0.5, 0.0, 0.0], Endpoint::Particle(0), 20.0, None, 0.1).unwrap();
    }
    let b = w.add_body(&body(1.0, -2.0)).unwrap();
    w.add_body_spring(b, [0.0, 0.3, 0.0], Endpoint::Anchor([1.0, 2.0, 0.0]), 30.0, Some(0.5), 0.2).unwrap();
    w
}

#[test]
fn a_removed_body_takes_its_springs_and_the_world_steps_as_one_without_it() {
    use physstep::world::{BodyId, BodySpringId};
    for method in ["symplectic-euler", "velocity-verlet", "rk4"] {
        let mut a = bodies_world(method, false);
        assert_eq!(a.body_ids(), [BodyId(0), BodyId(1)]);
        assert_eq!(a.remove_body(BodyId(0)).unwrap(), (vec![], vec![BodySpringId(0)]));
        assert_eq!(a.body_spring_ids(), [BodySpringId(1)]);
        assert_eq!((a.bodies().len(), a.body_row(BodyId(1))), (1, Some(0)));
        let mut b = bodies_world(method, true);
        a.step(50).unwrap();
        b.step(50).unwrap();
        assert_eq!(bits(a.positions()), bits(b.positions()), "{method}");
        assert_eq!(a.body_position(0).unwrap(), b.body_position(0).unwrap(), "{method}");
        assert_eq!(a.body_orientation(0).unwrap(), b.body_orientation(0).unwrap(), "{method}");
        assert_eq!(a.body_angular_velocity(0).unwrap(), b.body_angular_velocity(0).unwrap(), "{method}");
        let e = a.remove_body(BodyId(0)).unwrap_err().to_string();
        assert!(e.starts_with("invalid body = 0: must be the id of a body of this world"), "{e}");
        // Removing a particle takes the body spring that ended on it.
        assert_eq!(a.remove_particle(ParticleId(0)).unwrap().body_springs, []);
        let mut c = bodies_world(method, false);
        assert_eq!(c.remove_particle(ParticleId(0)).unwrap().body_springs, [BodySpringId(0)]);
        c.step(5).unwrap();
        assert_eq!(c.len(), 0);
        // A body spring by id: the other keeps its id; a second removal is one line.
        c.remove_body_spring(BodySpringId(1)).unwrap();
        assert!(c.body_spring(BodySpringId(1)).is_none() && c.body_spring_ids().is_empty());
        let e = c.remove_body_spring(BodySpringId(1)).unwrap_err().to_string();
        assert!(
            e.starts_with("invalid body_spring = 1: must be the id of a body spring of this world"),
            "{e}"
        );
    }
}

#[test]
fn a_body_springs_parameters_set_by_id_step_as_a_world_built_with_them() {
    use physstep::world::BodySpringId;
    let id = BodySpringId(0);
    let mut a = bodies_world("velocity-verlet", true);
    a.set_body_spring(id, Some(45.0), Some(0.8), Some(0.05)).unwrap();
    let s = a.body_spring(id).unwrap();
    assert_eq!((s.stiffness, s.rest_length, s.damping), (45.0, 0.8, 0.05));
    // Built with the new values from the start: the same bits after the change.
    let mut b = bodies_world("velocity-verlet", true);
    b.remove_body_spring(id).unwrap();
    b.add_body_spring(0, [0.0, 0.3, 0.0], Endpoint::Anchor([1.0, 2.0, 0.0]), 45.0, Some(0.8), 0.05).unwrap();
    a.step(40).unwrap();
    b.step(40).unwrap();
    assert_eq!(a.body_position(0).unwrap(), b.body_position(0).unwrap());
    assert_eq!(a.body_angular_velocity(0).unwrap(), b.body_angular_velocity(0).unwrap());
    // Refused values name the field; the spring is unchanged. A removed spring is one line.
    let before = a.state_hash();
    for (k, v) in [(0, -1.0), (1, f64::NAN), (2, 2e12)] {
        let mut p = [None; 3];
        p[k] = Some(v);
        let e = a.set_body_spring(id, p[0], p[1], p[2]).unwrap_err().to_string();
        let field = ["stiffness", "rest_length", "damping"][k];
        assert!(
            e.starts_with(&format!("invalid {field} = ")) && e.ends_with("must be a number in [0, 1e12]"),
            "{e}"
        );
    }
    assert_eq!(a.state_hash(), before);
    a.remove_body_spring(id).unwrap();
    let e = a.set_body_spring(id, Some(1.0), None, None).unwrap_err().to_string();
    assert!(e.starts_with("invalid body_spring = 0: must be the id of a body spring of this world"), "{e}");
}

/// Twelve particles (every third a ball) with gravity, a chain of springs, rods, an anchor
/// spring and constraints between them: what a batch removal has to renumber.
fn web() -> World {
    let mut w = world("velocity-verlet", 2);
    w.add_walls(&[-20.0, -20.0], &[20.0, 20.0]).unwrap();
    for k in 0..12 {
        let (x, v, m) = (
            [k as f64 * 0.7, (k % 3) as f64 * 0.4],
            [0.1 * (k % 2) as f64, -0.05 * k as f64],
            1.0 + 0.1 * k as f64,
        );
        if k % 3 == 0 {
            w.add_ball(&x, &v, 0.1, m).unwrap();
        } else {
            w.add_particle(&x, &v, m, false).unwrap();
        }
    }
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    for k in 0..11 {
        w.add_force(Force::Spring {
            i: k,
            j: Endpoint::Particle(k + 1),
            stiffness: 30.0,
            rest_length: 0.7,
            damping: 0.1,
        })
        .unwrap();
    }
    for k in (0..10).step_by(3) {
        w.add_rod(k, Endpoint::Particle(k + 2), None).unwrap();
    }
    w.add_force(Force::Spring {
        i: 7,
        j: Endpoint::Anchor([3.0, 3.0, 0.0]),
        stiffness: 5.0,
        rest_length: 1.0,
        damping: 0.0,
    })
    .unwrap();
    w.add_pin(0, &[0.0, 0.0]).unwrap();
    w.add_distance_limit(4, Endpoint::Particle(9), 0.5, 6.0).unwrap();
    w.add_rope(10, Endpoint::Particle(2), 7.0).unwrap();
    w.add_plane(&[0.0, 1.0], -10.0).unwrap();
    w
}

#[test]
fn particles_removed_at_once_leave_the_world_one_by_one_leaves() {
    for gone in [vec![5], vec![1, 4, 9], vec![11, 0, 6, 3, 7], (0..12).collect()] {
        let ids: Vec<ParticleId> = gone.iter().map(|&k| ParticleId(k)).collect();
        let (mut a, mut b) = (web(), web());
        a.step(7).unwrap();
        b.step(7).unwrap();
        let at_once = a.remove_particles(&ids).unwrap();
        let mut one_by_one = physstep::world::Removed::default();
        for id in &ids {
            let r = b.remove_particle(*id).unwrap();
            one_by_one.forces.extend(r.forces);
            one_by_one.constraints.extend(r.constraints);
        }
        let mut at_once = at_once;
        for r in [&mut at_once, &mut one_by_one] {
            r.forces.sort();
            r.constraints.sort();
        }
        assert_eq!(at_once, one_by_one, "{gone:?}");
        assert_eq!(a.len(), 12 - gone.len());
        assert_eq!((a.state_hash(), a.particle_ids()), (b.state_hash(), b.particle_ids()), "{gone:?}");
        assert_eq!(
            a.model().forces().iter().collect::<Vec<_>>(),
            b.model().forces().iter().collect::<Vec<_>>()
        );
        assert_eq!(a.radii(), b.radii());
        a.step(50).unwrap();
        b.step(50).unwrap();
        assert_eq!(
            (bits(a.positions()), bits(a.velocities())),
            (bits(b.positions()), bits(b.velocities())),
            "{gone:?}"
        );
    }
}

#[test]
fn a_batch_with_a_missing_or_repeated_id_is_one_line_and_the_world_unchanged() {
    let mut w = web();
    w.remove_particle(ParticleId(2)).unwrap();
    let hash = w.state_hash();
    for (ids, expected) in [
        (vec![1, 2, 3], "invalid particle = 2: must be the id of a particle of this world (it was removed, or never added here)"),
        (vec![4, 5, 4], "invalid particle = 4: must be listed once"),
    ] {
        let ids: Vec<ParticleId> = ids.into_iter().map(ParticleId).collect();
        assert_eq!(w.remove_particles(&ids).unwrap_err().to_string(), expected);
        assert_eq!((w.len(), w.state_hash()), (11, hash));
    }
}

#[test]
fn an_empty_batch_changes_nothing_not_even_a_methods_memory() {
    // The alternating symplectic Euler keeps its step's parity: a removal restarts it
    // (after an odd number of steps, another trajectory); removing no particle must not.
    let build = || {
        let mut w = world("symplectic-euler-alternating", 2);
        for (x, v, m) in P {
            w.add_particle(&x, &v, m, false).unwrap();
        }
        w.add_force(Force::Spring {
            i: 0,
            j: Endpoint::Particle(2),
            stiffness: 20.0,
            rest_length: 1.0,
            damping: 0.0,
        })
        .unwrap();
        w.step(11).unwrap();
        w
    };
    let (mut a, mut b, mut restarted) = (build(), build(), build());
    assert_eq!(a.remove_particles(&[]).unwrap(), physstep::world::Removed::default());
    let x = restarted.positions().to_vec();
    restarted.set_positions(&x).unwrap();
    for w in [&mut a, &mut b, &mut restarted] {
        w.step(20).unwrap();
    }
    assert_eq!(bits(a.positions()), bits(b.positions()));
    assert_ne!(bits(restarted.positions()), bits(b.positions()), "a restart shows in the bits");
}
