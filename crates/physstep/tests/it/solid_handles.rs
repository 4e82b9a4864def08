//! Stable ids and removal of solids, joints, solid springs and user forces on solids, and
//! setting a solid's motion by hand (docs/contact.md, "Handles and removal").

use physstep::contact::{
    JointId, JointKind, JointParams, Kind, Shape, SolidForceId, SolidId, SolidMotion, SolidParams,
    SolidSpring, SolidSpringId,
};
use physstep::forces::{Force, ForceGenerator};
use physstep::world::{World, WorldParams};
use std::sync::Arc;

const DT: f64 = 1.0 / 60.0;

fn world(dim: usize) -> World {
    let mut w = World::new(WorldParams { dim, dt: DT, ..WorldParams::default() }).unwrap();
    let mut g = [0.0; 3];
    g[1] = -9.81;
    w.add_force(Force::Gravity { g }).unwrap();
    w
}

/// A pile on the ground in `dim` dimensions: the ground (0), a pyramid of boxes (1..=6), a
/// ball hung from box 6 by a joint (7), springs from box 5 to the ball and from box 4 to the
/// world; box 3 with drag; a kinematic box far off, rising (8). Solid `skip` (a row of the
/// whole pile) is left out, with what hangs on it; the others keep their order.
fn pile(dim: usize, skip: Option<usize>) -> World {
    let mut w = world(dim);
    let mut rows = Vec::new();
    let mut add = |w: &mut World, k: usize, p: SolidParams| {
        if Some(k) == skip {
            rows.push(None);
        } else {
            rows.push(Some(w.add_solid(p).unwrap()));
        }
    };
    let mut ground = if dim == 2 {
        SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0])
    } else {
        SolidParams::new(Shape::Plane { normal: vec![0.0, 1.0, 0.0] }, &[0.0, 0.0, 0.0])
    };
    ground.kind = Kind::Static;
    add(&mut w, 0, ground);
    let mut k = 1;
    for row in 0..3 {
        for i in 0..3 - row {
            let x = (i as f64 - (2 - row) as f64 / 2.0) * 1.01;
            let mut at = vec![x, 0.5 + row as f64 * 1.001, 0.0];
            at.truncate(dim);
            let mut p = SolidParams::new(Shape::Box { half: vec![0.5; dim] }, &at);
            if k == 3 {
                p.linear_damping = 0.5;
                p.angular_damping = 0.25;
            }
            add(&mut w, k, p);
            k += 1;
        }
    }
    let mut at = vec![0.0, 4.5, 0.0];
    at.truncate(dim);
    add(&mut w, 7, SolidParams::new(Shape::Circle { radius: 0.25 }, &at));
    // A kinematic platform far off, rising.
    let mut far = vec![20.0, 0.5, 0.0];
    far.truncate(dim);
    let mut lift = SolidParams::new(Shape::Box { half: vec![0.5; dim] }, &far);
    lift.kind = Kind::Kinematic;
    lift.velocity = vec![0.0; dim];
    lift.velocity[1] = 0.5;
    add(&mut w, 8, lift);
    let row = |k: usize| rows[k];
    if let (Some(a), Some(b)) = (row(6), row(7)) {
        let mut anchor = vec![0.0, 3.5, 0.0];
        anchor.truncate(dim);
        let mut j = JointParams::new(JointKind::Distance, a, Some(b), &anchor);
        j.anchor_b = Some(at.clone());
        w.add_joint(j).unwrap();
    }
    let zero = vec![0.0; dim];
    if let (Some(a), Some(b)) = (row(5), row(7)) {
        let s = SolidSpring {
            a,
            point_a: zero.clone(),
            b: Some(b),
            point_b: zero.clone(),
            stiffness: 20.0,
            rest_length: None,
            damping: 0.5,
        };
        w.add_solid_spring(s).unwrap();
    }
    if let Some(a) = row(4) {
        let mut anchor = vec![-3.0, 2.0, 0.0];
        anchor.truncate(dim);
        w.add_solid_spring(SolidSpring::to_world(a, &zero, &anchor, 5.0)).unwrap();
    }
    w
}

/// Everything a step of the solids moves, bit for bit.
fn motion_bits(w: &World) -> Vec<u64> {
    let c = w.contacts();
    w.solid_positions()
        .into_iter()
        .chain(w.solid_orientations())
        .chain(w.solid_velocities())
        .chain(w.solid_angular_velocities())
        .chain(c.points)
        .chain(c.normal_impulses)
        .chain(c.pairs.iter().flatten().map(|i| *i as f64))
        .map(f64::to_bits)
        .collect()
}

/// A solid removed before any step leaves a world that steps bitwise as one built without it
/// (and without its joint, springs and drag), in 2D and 3D, with contacts under way: every
/// solid of the pile removed in turn.
#[test]
fn a_solid_removed_before_any_step_steps_bitwise_as_a_world_built_without_it() {
    for dim in [2, 3] {
        for k in 0..9 {
            let mut removed = pile(dim, None);
            removed.remove_solid(SolidId(k as u64)).unwrap();
            let mut built = pile(dim, Some(k));
            assert_eq!(removed.solid_count(), 8);
            assert_eq!(removed.joint_count(), built.joint_count(), "{dim}D, solid {k}");
            assert_eq!(removed.solid_springs(), built.solid_springs(), "{dim}D, solid {k}");
            assert_eq!(removed.joint_params(), built.joint_params(), "{dim}D, solid {k}");
            for step in 0..90 {
                removed.step(1).unwrap();
                built.step(1).unwrap();
                assert_eq!(motion_bits(&removed), motion_bits(&built), "{dim}D, solid {k}, step {step}");
            }
            assert!(!built.contacts().pairs.is_empty());
        }
    }
}

/// Removed mid-run, a solid leaves the contacts at once; the others keep their ids, which
/// reach their rows; the ground taken away, the pile falls and keeps stepping sanely.
#[test]
fn a_solid_removed_mid_run_leaves_the_contacts_and_the_others_keep_their_ids() {
    for dim in [2, 3] {
        let mut w = pile(dim, None);
        w.step(60).unwrap();
        let before = w.solid_positions();
        assert!(w.contacts().pairs.iter().any(|p| p[0] == 0));
        w.remove_solid(SolidId(0)).unwrap();
        assert_eq!(w.solid_ids(), [1, 2, 3, 4, 5, 6, 7, 8].map(SolidId));
        assert_eq!(w.solid_row(SolidId(5)), Some(4));
        assert_eq!(w.solid_row(SolidId(0)), None);
        // Rows after it moved up one, their state with them.
        assert_eq!(&w.solid_positions()[..], &before[dim..]);
        // The contacts of the latest step without it, renumbered: the boxes' among themselves.
        let pairs = w.contacts().pairs;
        assert!(!pairs.is_empty());
        let boxes: Vec<[usize; 2]> =
            pile_pairs(&before, dim).into_iter().map(|[a, b]| [a - 1, b - 1]).collect();
        assert!(pairs.iter().all(|p| boxes.contains(p)), "{pairs:?}");
        w.step(30).unwrap();
        let x = w.solid_positions();
        assert!(x.iter().all(|v| v.is_finite()));
        for id in 1..7 {
            let r = w.solid_row(SolidId(id)).unwrap();
            let (y0, y) = (before[id as usize * dim + 1], x[r * dim + 1]);
            assert!(y < y0 - 1.0, "{dim}D: box {id} fell from {y0} to {y}");
        }
        assert!(w.contacts().pairs.iter().all(|p| p[1] < 8));
    }
}

/// The pairs of boxes of the pile (rows 1..=6) whose centres are within 1.2 m: those that can
/// touch.
fn pile_pairs(x: &[f64], dim: usize) -> Vec<[usize; 2]> {
    let mut out = Vec::new();
    for a in 1..8 {
        for b in a + 1..8 {
            let d: f64 = (0..dim).map(|k| (x[a * dim + k] - x[b * dim + k]).powi(2)).sum::<f64>().sqrt();
            if d < 1.6 {
                out.push([a, b]);
            }
        }
    }
    out
}

struct Push;
impl ForceGenerator for Push {
    fn name(&self) -> &str {
        "push"
    }
    fn add_forces(&self, _t: f64, _x: &[f64], _v: &[f64], f: &mut [f64]) -> Result<(), String> {
        f[0] += 1.0;
        Ok(())
    }
}

/// Removing a solid removes the joints, springs and user forces that have it at one end; the
/// others keep their ids; a removed or never-given id is one error naming the field and the
/// value, the world unchanged.
#[test]
fn removal_takes_what_hangs_on_the_solid_and_a_dead_id_is_one_error() {
    let mut w = pile(2, None);
    w.add_solid_force(7, &[0.0, 0.0], Arc::new(Push)).unwrap();
    w.add_solid_force(1, &[0.0, 0.0], Arc::new(Push)).unwrap();
    assert_eq!(w.joint_ids(), [JointId(0)]);
    assert_eq!(w.solid_spring_ids(), [SolidSpringId(0), SolidSpringId(1)]);
    w.remove_solid(SolidId(7)).unwrap();
    assert_eq!(w.joint_ids(), []);
    assert_eq!(w.solid_spring_ids(), [SolidSpringId(1)]);
    assert_eq!(w.solid_force_ids(), [SolidForceId(1)]);
    assert_eq!(w.solid_springs()[0].a, 4);
    // Another solid added gets a new id, never 7 again.
    let row = w.add_solid(SolidParams::new(Shape::Circle { radius: 0.2 }, &[5.0, 5.0])).unwrap();
    assert_eq!((row, w.solid_ids()[row]), (8, SolidId(9)));
    let hash = w.state_hash();
    for (e, want) in [
        (
            w.remove_solid(SolidId(7)).unwrap_err(),
            "invalid solid = 7: must be the id of a solid of this world",
        ),
        (
            w.remove_joint(JointId(0)).unwrap_err(),
            "invalid joint = 0: must be the id of a joint of this world",
        ),
        (
            w.remove_solid_spring(SolidSpringId(0)).unwrap_err(),
            "invalid spring = 0: must be the id of a solid spring of this world",
        ),
        (
            w.remove_solid_force(SolidForceId(0)).unwrap_err(),
            "invalid force = 0: must be the id of a force on a solid of this world",
        ),
        (
            w.set_solid_motion(SolidId(99), &SolidMotion::default()).unwrap_err(),
            "invalid solid = 99: must be the id",
        ),
    ] {
        let e = e.to_string();
        assert!(e.starts_with(want), "{e}");
        assert!(!e.contains('\n'));
    }
    assert_eq!(w.state_hash(), hash);
    assert_eq!(w.remove_solid_force(SolidForceId(1)).unwrap(), 0);
    w.remove_solid_spring(SolidSpringId(1)).unwrap();
    assert!(w.solid_springs().is_empty());
    // A 1D world has no solids to remove.
    let mut line = World::new(WorldParams { dim: 1, ..WorldParams::default() }).unwrap();
    assert!(line.remove_solid(SolidId(0)).unwrap_err().to_string().starts_with("invalid solid = 0"));
}

/// A world where a joint was removed: its two solids collide again, and the joint's id is
/// not given again.
#[test]
fn a_removed_joint_lets_its_solids_collide_again() {
    let mut w = world(2);
    let mut ground = SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0]);
    ground.kind = Kind::Static;
    let g = w.add_solid(ground).unwrap();
    let b = w.add_solid(SolidParams::new(Shape::Box { half: vec![0.5, 0.5] }, &[0.0, 2.0])).unwrap();
    // A soft distance joint to the ground that lets the box fall through it.
    let mut j = JointParams::new(JointKind::Distance, b, Some(g), &[0.0, 2.0]);
    j.hertz = 1.0;
    j.anchor_b = Some(vec![0.0, -1.0]);
    j.min_length = Some(0.0);
    j.max_length = Some(100.0);
    let row = w.add_joint(j).unwrap();
    let id = w.joint_ids()[row];
    w.remove_joint(id).unwrap();
    w.step(120).unwrap();
    assert!(w.contacts().pairs.contains(&[0, 1]), "the box lands on the ground");
    let y = w.solid_positions()[3];
    assert!((y - 0.5).abs() < 0.05, "{y}");
    let j2 = JointParams::new(JointKind::Ball, b, None, &[0.0, 0.5]);
    let row = w.add_joint(j2).unwrap();
    assert_eq!(w.joint_ids()[row], JointId(1));
}

/// A snapshot of a world after a removal restores into it bitwise; a world with the same
/// solids but other ids (built without the solid instead of removing it) refuses it; the
/// state hash tells the two apart, and a world where nothing was removed hashes as before.
#[test]
fn snapshots_and_hashes_cover_the_ids_after_a_removal() {
    let mut w = pile(3, None);
    let untouched = pile(3, None);
    w.step(20).unwrap();
    w.remove_solid(SolidId(6)).unwrap();
    w.step(5).unwrap();
    let snap = w.snapshot();
    let mut copy = w.clone();
    w.step(30).unwrap();
    copy.step(7).unwrap();
    copy.restore(&snap).unwrap();
    copy.step(30).unwrap();
    assert_eq!(motion_bits(&copy), motion_bits(&w));
    assert_eq!(copy.state_hash(), w.state_hash());
    let mut built = pile(3, Some(6));
    let e = built.restore(&snap).unwrap_err().to_string();
    assert!(e.contains("other solids, joints or springs"), "{e}");
    // The same motion, other ids: another hash.
    let mut a = pile(2, None);
    a.remove_solid(SolidId(6)).unwrap();
    let b = pile(2, Some(6));
    assert_eq!(motion_bits(&a), motion_bits(&b));
    assert_ne!(a.state_hash(), b.state_hash());
    // Ids set to the removed world's: the same hash, and the snapshot restores.
    let mut c = pile(2, Some(6));
    let ids = |w: &World| -> [Vec<u64>; 4] {
        [
            w.solid_ids().iter().map(|i| i.0).collect(),
            w.joint_ids().iter().map(|i| i.0).collect(),
            w.solid_spring_ids().iter().map(|i| i.0).collect(),
            w.solid_force_ids().iter().map(|i| i.0).collect(),
        ]
    };
    let want = ids(&a);
    c.set_solid_ids([&want[0], &want[1], &want[2], &want[3]], a.next_solid_ids()).unwrap();
    assert_eq!(c.state_hash(), a.state_hash());
    a.step(3).unwrap();
    c.restore(&a.snapshot()).unwrap();
    assert_eq!(c.state_hash(), a.state_hash());
    // Bad ids: one error naming the field.
    let e = c.set_solid_ids([&[0, 1], &[], &[], &[]], [9, 1, 2, 0]).unwrap_err().to_string();
    assert!(e.starts_with("invalid len(solid_ids) = 2"), "{e}");
    let e = c
        .set_solid_ids([&[0, 1, 2, 3, 4, 5, 7, 9], &[], &[0, 1], &[]], [9, 0, 2, 0])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("invalid solid_ids = 9: must be ids below next = 9"), "{e}");
    let e = c
        .set_solid_ids([&[0, 1, 2, 3, 5, 4, 7, 8], &[], &[0, 1], &[]], [9, 0, 2, 0])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("invalid solid_ids = 4: must be increasing ids"), "{e}");
    // Nothing removed: the ids are implicit, the snapshot is as before ids.
    assert_eq!(untouched.snapshot(), pile(3, None).snapshot());
}

/// A solid's motion set by hand is the one stepped; a teleport forgets its contacts' warm
/// starts; a static solid keeps zero velocities; bad values are one error, the world
/// unchanged.
#[test]
fn a_solids_motion_set_by_hand_is_the_one_stepped_and_checked() {
    let mut w = pile(2, None);
    w.step(30).unwrap();
    let id = SolidId(7);
    let set = SolidMotion {
        velocity: Some(vec![3.0, 0.0]),
        angular_velocity: Some(vec![1.0]),
        ..Default::default()
    };
    w.set_solid_motion(id, &set).unwrap();
    assert_eq!(&w.solid_velocities()[14..16], &[3.0, 0.0]);
    assert_eq!(w.solid_angular_velocities()[7], 1.0);
    let teleport =
        SolidMotion { position: Some(vec![10.0, 5.0]), orientation: Some(vec![0.5]), ..Default::default() };
    w.set_solid_motion(SolidId(1), &teleport).unwrap();
    assert_eq!(&w.solid_positions()[2..4], &[10.0, 5.0]);
    assert_eq!(w.solid_orientations()[1], 0.5);
    let hash = w.state_hash();
    for (m, want) in [
        (
            SolidMotion { position: Some(vec![f64::NAN, 0.0]), ..Default::default() },
            "invalid position[0] = NaN",
        ),
        (
            SolidMotion { velocity: Some(vec![1.0]), ..Default::default() },
            "invalid len(velocity) = 1: must be 2",
        ),
        (
            SolidMotion { orientation: Some(vec![1e300]), ..Default::default() },
            "invalid orientation[0] = 1e300",
        ),
    ] {
        let e = w.set_solid_motion(SolidId(2), &m).unwrap_err().to_string();
        assert!(e.starts_with(want), "{e}");
    }
    let e = w
        .set_solid_motion(SolidId(0), &SolidMotion { velocity: Some(vec![1.0, 0.0]), ..Default::default() })
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("invalid velocity = non-zero: must be zero for a static solid"), "{e}");
    assert_eq!(w.state_hash(), hash);
    // The teleported box falls from where it was put.
    w.step(1).unwrap();
    let y = w.solid_positions()[3];
    assert!(y < 5.0 && y > 4.9, "{y}");
    // In 3D a quaternion is normalised.
    let mut s = pile(3, None);
    s.set_solid_motion(
        SolidId(7),
        &SolidMotion { orientation: Some(vec![2.0, 0.0, 0.0, 0.0]), ..Default::default() },
    )
    .unwrap();
    assert_eq!(&s.solid_orientations()[28..32], &[1.0, 0.0, 0.0, 0.0]);
}

/// A joint's motor and limits and a spring's parameters changed through their ids change the
/// next step; bad values are refused as the add call refuses them.
#[test]
fn joint_motor_and_limits_and_spring_parameters_set_by_id() {
    let wheel = || {
        let mut w = World::new(WorldParams { dim: 2, dt: DT, ..WorldParams::default() }).unwrap();
        w.add_solid(SolidParams::new(Shape::Circle { radius: 0.5 }, &[0.0, 0.0])).unwrap();
        let mut j = JointParams::new(JointKind::Revolute, 0, None, &[0.0, 0.0]);
        j.max_motor = 100.0;
        w.add_joint(j).unwrap();
        w
    };
    let mut w = wheel();
    w.set_joint_motor(JointId(0), 2.0, 100.0).unwrap();
    w.step(60).unwrap();
    assert!((w.solid_angular_velocities()[0] - 2.0).abs() < 1e-6);
    assert_eq!(w.joint_params()[0].motor_speed, 2.0);
    let e = w.set_joint_motor(JointId(0), 1.0, -1.0).unwrap_err().to_string();
    assert!(e.starts_with("invalid max_motor = -1: must be finite and >= 0"), "{e}");
    w.set_joint_limits(JointId(0), Some(-0.1), Some(0.1)).unwrap();
    w.set_joint_motor(JointId(0), 0.0, 0.0).unwrap();
    let e = w.set_joint_limits(JointId(0), Some(1.0), Some(0.0)).unwrap_err().to_string();
    assert!(e.starts_with("invalid lower = 1: must be <= upper (0)"), "{e}");
    assert_eq!((w.joint_params()[0].lower, w.joint_params()[0].upper), (Some(-0.1), Some(0.1)));
    // A spring made stiffer pulls harder at the next step.
    let pulled = |k: Option<f64>| {
        let mut w = pile(2, None);
        if let Some(k) = k {
            w.set_solid_spring(SolidSpringId(1), k, 0.5, 0.0).unwrap();
            assert_eq!(w.solid_springs()[1].stiffness, k);
            assert_eq!(w.solid_springs()[1].rest_length, Some(0.5));
        }
        w.step(1).unwrap();
        w.solid_velocities()[8]
    };
    assert!(pulled(Some(500.0)) < pulled(None));
    let mut w = pile(2, None);
    let e = w.set_solid_spring(SolidSpringId(0), -1.0, 1.0, 0.0).unwrap_err().to_string();
    assert!(e.starts_with("invalid stiffness = -1"), "{e}");
    assert_eq!(w.solid_springs()[0].stiffness, 20.0);
}
