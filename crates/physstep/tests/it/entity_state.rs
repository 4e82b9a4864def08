//! Setting one particle's or one body's state by hand (the per-entity views of the Python
//! face): what is set is what the next step takes, bitwise as a world built with it; bad
//! input is one line naming the field, the world unchanged.

use physstep::prelude::*;
use physstep::rigid::inertia::Shape;
use physstep::world::BodyParams;

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn particles(method: &str, x1: [f64; 2], v1: [f64; 2], m1: f64) -> World {
    let mut w =
        World::new(WorldParams { dim: 2, method: method.into(), dt: 0.01, ..Default::default() }).unwrap();
    w.add_particle(&[0.0, 0.0], &[0.0, 0.0], 1.0, true).unwrap();
    w.add_particle(&x1, &v1, m1, false).unwrap();
    w.add_particle(&[2.0, -0.3], &[0.0, 0.3], 0.5, false).unwrap();
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
    w.add_spring(1, physstep::forces::Endpoint::Particle(2), 40.0, Some(0.8), 0.2).unwrap();
    w.add_spring(1, physstep::forces::Endpoint::Particle(0), 10.0, Some(1.0), 0.0).unwrap();
    w
}

#[test]
fn a_particle_set_by_hand_is_the_state_the_next_step_takes() {
    for method in ["symplectic-euler", "velocity-verlet", "rk4", "verlet", "leapfrog", "backward-euler"] {
        let mut w = particles(method, [1.0, 0.2], [0.1, 0.0], 1.5);
        w.step(30).unwrap();
        let mut by_hand = particles(method, [1.0, 0.2], [0.1, 0.0], 1.5);
        by_hand.step(30).unwrap();
        by_hand.set_particle(1, Some(&[0.7, -0.4]), Some(&[1.0, 2.0])).unwrap();
        by_hand.set_mass(1, 3.0).unwrap();
        // A world built with that particle (positions of the others as they are now).
        let mut built = particles(method, [0.7, -0.4], [1.0, 2.0], 3.0);
        let mut x = w.positions().to_vec();
        let mut v = w.velocities().to_vec();
        x[2..4].copy_from_slice(&[0.7, -0.4]);
        v[2..4].copy_from_slice(&[1.0, 2.0]);
        built.set_positions(&x).unwrap();
        built.set_velocities(&v).unwrap();
        assert_eq!(bits(by_hand.positions()), bits(built.positions()));
        by_hand.step(50).unwrap();
        built.step(50).unwrap();
        assert_eq!(bits(by_hand.positions()), bits(built.positions()), "{method}");
        assert_eq!(bits(by_hand.velocities()), bits(built.velocities()), "{method}");
    }
}

#[test]
fn bad_particle_state_is_one_line_naming_the_field_and_changes_nothing() {
    let mut w = particles("velocity-verlet", [1.0, 0.2], [0.1, 0.0], 1.5);
    w.step(3).unwrap();
    let before = (w.state_hash(), bits(w.model().mass()));
    let e = |r: physstep::Result<()>| r.unwrap_err().to_string();
    assert_eq!(
        e(w.set_particle(3, Some(&[0.0, 0.0]), None)),
        "invalid particle = 3: must be an index below 3"
    );
    assert_eq!(
        e(w.set_particle(1, Some(&[0.0]), None)),
        "invalid len(position) = 1: must be 2, the world's dim"
    );
    assert!(e(w.set_particle(1, Some(&[0.0, f64::NAN]), None)).starts_with("invalid position[1] = NaN"));
    assert!(e(w.set_particle(1, None, Some(&[1e200, 0.0]))).starts_with("invalid velocity[0] = 1e200"));
    assert!(e(w.set_particle(0, None, Some(&[1.0, 0.0])))
        .starts_with("invalid velocity = [1.0, 0.0]: must be zero for particle 0, which is static"));
    assert!(e(w.set_mass(1, 0.0)).starts_with("invalid mass = 0: must be > 0"));
    assert!(e(w.set_mass(1, f64::NAN)).starts_with("invalid mass = NaN"));
    assert!(e(w.set_mass(1, f64::INFINITY))
        .starts_with("invalid mass = inf: must be finite for particle 1, which is dynamic"));
    assert!(e(w.set_mass(5, 1.0)).starts_with("invalid particle = 5"));
    w.add_force(Force::NBody { g: 1.0, softening: 0.1 }).unwrap();
    assert_eq!(
        e(w.set_mass(0, f64::INFINITY)),
        "invalid mass[0] = inf: must be finite when n-body gravity is on"
    );
    assert_eq!((w.state_hash(), bits(w.model().mass())), before);
    // A static particle stays static: a new mass, and velocity zero.
    w.set_mass(0, 7.0).unwrap();
    assert_eq!(w.model().inv_mass()[0], 0.0);
    w.set_particle(0, None, Some(&[0.0, 0.0])).unwrap();
}

fn body_world(method: &str, b: BodyParams) -> World {
    let mut w =
        World::new(WorldParams { dim: 3, method: method.into(), dt: 0.01, ..Default::default() }).unwrap();
    w.add_force(Force::Gravity { g: [0.0, 0.0, -9.81] }).unwrap();
    w.add_body(&b).unwrap();
    w.add_body(&BodyParams {
        shape: Shape::Sphere { radius: 0.3 },
        position: [3.0, 0.0, 0.0],
        ..Default::default()
    })
    .unwrap();
    w
}

fn plate() -> BodyParams {
    BodyParams {
        shape: Shape::Box { half_extents: [1.0, 0.5, 0.2] },
        mass: Some(2.0),
        angular_velocity: [0.1, 1.0, 0.2],
        ..Default::default()
    }
}

#[test]
fn a_bodys_state_set_by_hand_is_the_one_stepped() {
    let q = [0.9, 0.1, -0.3, 0.2];
    for method in ["symplectic-euler", "rk4", "velocity-verlet"] {
        let mut by_hand = body_world(method, plate());
        by_hand
            .set_body_state(0, Some([1.0, 2.0, 3.0]), Some([0.5, -1.0, 2.0]), Some(q), Some([2.0, 0.0, -1.0]))
            .unwrap();
        let mut built = body_world(
            method,
            BodyParams {
                position: [1.0, 2.0, 3.0],
                velocity: [0.5, -1.0, 2.0],
                orientation: q,
                angular_velocity: [2.0, 0.0, -1.0],
                ..plate()
            },
        );
        assert_eq!(bits(by_hand.positions()), bits(built.positions()), "{method}");
        assert_eq!(by_hand.body_params(), built.body_params(), "{method}");
        by_hand.step(40).unwrap();
        built.step(40).unwrap();
        assert_eq!(by_hand.state_hash(), built.state_hash(), "{method}");
        // A velocity set alone is what the next step moves the body by.
        let mut w = body_world("symplectic-euler", BodyParams { angular_velocity: [0.0; 3], ..plate() });
        w.set_body_state(0, None, Some([1.0, 0.0, 0.0]), None, None).unwrap();
        let x0 = w.body_position(0).unwrap();
        w.step(1).unwrap();
        let x1 = w.body_position(0).unwrap();
        assert!((x1[0] - x0[0] - 0.01).abs() < 1e-15, "{x0:?} -> {x1:?}");
    }
}

#[test]
fn bad_body_state_is_one_line_naming_the_field_and_changes_nothing() {
    let mut w = body_world("rk4", plate());
    w.add_body(&BodyParams { pivot: Some([0.0, 0.0, 1.0]), position: [0.0, 5.0, 0.0], ..plate() }).unwrap();
    let before = w.state_hash();
    let e = |r: physstep::Result<()>| r.unwrap_err().to_string();
    assert_eq!(e(w.set_body_state(3, None, None, None, None)), "invalid body = 3: must be an index below 3");
    assert!(e(w.set_body_state(0, Some([f64::NAN, 0.0, 0.0]), None, None, None))
        .starts_with("invalid position[0] = NaN"));
    assert!(e(w.set_body_state(0, None, Some([0.0, f64::INFINITY, 0.0]), None, None))
        .starts_with("invalid velocity[1] = inf"));
    assert!(e(w.set_body_state(0, None, None, Some([0.0; 4]), None))
        .starts_with("invalid orientation = [0, 0, 0, 0]: must be a quaternion"));
    assert!(e(w.set_body_state(0, None, None, None, Some([0.0, 0.0, 1e300])))
        .starts_with("invalid angular_velocity[2] = 1e300"));
    assert!(e(w.set_body_state(2, Some([0.0; 3]), None, None, None)).contains("pinned body"));
    assert!(e(w.set_body_state(2, None, Some([1.0, 0.0, 0.0]), None, None)).contains("pinned body"));
    // Refused as a whole: a good position with a bad orientation moves nothing.
    assert!(w.set_body_state(0, Some([9.0; 3]), None, Some([f64::NAN, 0.0, 0.0, 1.0]), None).is_err());
    assert_eq!(w.state_hash(), before);
    // An orientation is normalised, as add_body normalises it.
    w.set_body_state(0, None, None, Some([2.0, 0.0, 0.0, 0.0]), None).unwrap();
    let q = w.body_orientation(0).unwrap();
    assert!((q[0] - 1.0).abs() < 1e-15 && q[1..].iter().all(|c| c.abs() < 1e-15), "{q:?}");
}
