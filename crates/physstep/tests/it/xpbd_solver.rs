//! The `xpbd` contact solver (rigid-body XPBD, Mueller et al. 2020; contact/xpbd.rs): a box
//! that rests, the ramp's closed forms, the pyramid and the ball-and-chain beside the soft
//! step, the same bits on one and two threads and after a snapshot, dice in space.

use glam::{DVec2, DVec3};
use physstep::contact::{JointKind, JointParams, Kind, Plane, Shape, SolidParams, Solids, Space3};
use physstep::world::World;

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// `name` built at its defaults with `overrides`, stepped by `solver`.
fn scene(name: &str, overrides: &[(&str, f64)], solver: &str) -> World {
    let mut w = physstep::scenes::build(name, overrides, "symplectic-euler", DT).unwrap().world;
    w.set_contact_solver(solver).unwrap();
    w
}

#[test]
fn xpbd_is_a_solver_by_name_at_the_soft_steps_passes() {
    let info = physstep::contact::SOLVERS.iter().find(|i| i.name == "xpbd").expect("registered");
    assert_eq!(info.schedule, physstep::contact::Schedule::Xpbd);
    assert!(info.passes.starts_with("2 x substeps x solver_iterations"), "{}", info.passes);
}

#[test]
fn a_box_dropped_on_the_ground_comes_to_rest_under_xpbd() {
    let mut s = Solids::<Plane>::new();
    s.settings.set_solver("xpbd").unwrap();
    let mut ground = SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0]);
    ground.kind = Kind::Static;
    s.add(ground).unwrap();
    let b = s.add(SolidParams::new(Shape::Box { half: vec![0.5, 0.5] }, &[0.0, 2.0])).unwrap();
    let (mut landing_energy, mut landed_at, mut deepest) = (0.0_f64, None, 0.0_f64);
    let mut after = None;
    for k in 0..600 {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
        landing_energy = landing_energy.max(s.kinetic_energy());
        if landed_at.is_none() && !s.contacts().iter().all(|c| c.depth < 0.0) {
            landed_at = Some(k);
        }
        if landed_at.is_some_and(|l| k >= l + 120) {
            deepest = deepest.max(s.max_penetration());
            if after.is_none() {
                after = Some(s.kinetic_energy());
            }
        }
    }
    let landed = landed_at.expect("the box lands");
    let (e2, e) = (after.unwrap(), s.kinetic_energy());
    let (y, angle) = (s.positions()[2 * b + 1], s.orientations()[b]);
    eprintln!(
        "xpbd box: landed at step {landed}, kinetic energy 2 s after {e2:e}, at 10 s {e:e} of {landing_energy}; \
         deepest after 2 s {deepest:e} m, height {y}, angle {angle:e}"
    );
    assert!(landed < 60, "landed at step {landed}");
    assert!(e2 < 1e-8 * landing_energy, "2 s after landing: kinetic energy {e2} of {landing_energy}");
    assert!(e < 1e-8 * landing_energy, "kinetic energy {e} of {landing_energy}");
    assert!(deepest < 0.005, "penetration {deepest}");
    assert!((y - 0.5).abs() < 0.005, "resting height {y}");
    // One position pass a substep moves the two corners one after the other (as NGS does):
    // flat to 2e-5 rad (10 um across the box).
    assert!(angle.abs() < 2e-5, "it landed flat and stays flat: {angle}");
}

/// The ramp scene at `angle` and `friction` under xpbd for `seconds`: how far the box moved
/// down the plank and its speed along it.
fn ramp(angle: f64, mu: f64, seconds: f64) -> (f64, f64) {
    let mut w = scene("ramp", &[("angle", angle), ("friction", mu)], "xpbd");
    let (c, sn) = (angle.cos(), angle.sin());
    let along = |w: &World| {
        let p = w.solid_positions();
        p[2] * c + p[3] * sn
    };
    let x0 = along(&w);
    w.step((seconds / DT).round() as u64).unwrap();
    let v = w.solid_velocities();
    (along(&w) - x0, v[2] * c + v[3] * sn)
}

#[test]
fn on_the_ramp_xpbd_sticks_above_the_friction_angle_and_slides_at_g_sin_minus_mu_cos_below() {
    let angle = 0.5_f64; // tan = 0.546
    let (moved, _) = ramp(angle, 0.6, 5.0);
    let mu = 0.3;
    let (_, v) = ramp(angle, mu, 2.0);
    let a = v / 2.0;
    let exact = -G * (angle.sin() - mu * angle.cos());
    eprintln!("xpbd ramp: stuck box moved {moved:e} m in 5 s; sliding at {a} m/s^2 against {exact}");
    assert!(moved.abs() < 1e-3, "stuck box moved {moved}");
    assert!(((a - exact) / exact).abs() < 0.01, "acceleration {a} against {exact}");
}

/// The top box's drift and the deepest penetration of the `pyramid` scene (20 rows) over
/// 10 s under `solver`, and the time a step took, ms.
fn pyramid(solver: &str) -> (f64, f64, f64) {
    let mut w = scene("pyramid", &[], solver);
    let top = w.solid_count() - 1;
    let p0 = w.solid_positions();
    let mut deepest = 0.0_f64;
    let start = std::time::Instant::now();
    for _ in 0..600 {
        w.step(1).unwrap();
        deepest = deepest.max(w.max_penetration());
    }
    let ms = start.elapsed().as_secs_f64() * 1e3 / 600.0;
    let p = w.solid_positions();
    let drift = ((p[2 * top] - p0[2 * top]).powi(2) + (p[2 * top + 1] - p0[2 * top + 1]).powi(2)).sqrt();
    (drift, deepest, ms)
}

#[test]
fn the_pyramid_stands_under_xpbd_beside_the_soft_step() {
    let (soft_drift, soft_deep, soft_ms) = pyramid("soft-step");
    let (drift, deep, ms) = pyramid("xpbd");
    eprintln!(
        "pyramid, 20 rows, 10 s: soft-step {:.2} mm drift, {:.2} mm deep, {soft_ms:.2} ms a step; \
         xpbd {:.2} mm drift, {:.2} mm deep, {ms:.2} ms a step",
        soft_drift * 1e3,
        soft_deep * 1e3,
        drift * 1e3,
        deep * 1e3
    );
    // Measured: soft-step 8.48 mm and 0.90 mm, xpbd 4.35 mm and 1.61 mm.
    assert!(soft_drift < 0.01 && soft_deep < 0.0015, "soft step: {soft_drift} m, {soft_deep} m deep");
    assert!(drift < 0.0065 && deep < 0.0025, "xpbd: {drift} m, {deep} m deep");
}

/// The largest joint error of the `ball-chain` scene over 10 s under `solver`, m.
fn ball_chain(solver: &str) -> f64 {
    let mut w = scene("ball-chain", &[], solver);
    let mut worst = 0.0_f64;
    for _ in 0..600 {
        w.step(1).unwrap();
        worst = worst.max(w.joint_errors().into_iter().fold(0.0, f64::max));
    }
    worst
}

#[test]
fn the_ball_and_chain_keeps_its_joints_under_xpbd_and_the_soft_step() {
    let soft = ball_chain("soft-step");
    let xpbd = ball_chain("xpbd");
    eprintln!("ball-chain, 10 s: largest joint error soft-step {soft:e} m, xpbd {xpbd:e} m");
    // Measured: soft-step 25.0 mm, xpbd 16.1 mm (each hinge's point brought together whole,
    // K^-1 d; along the normal alone, as the paper's scalar corrections do, 72.7 mm).
    assert!(soft < 0.035, "soft-step: {soft} m of a 1 m link");
    assert!(xpbd < 0.025, "xpbd: {xpbd} m of a 1 m link");
}

#[test]
fn xpbd_gives_the_same_bits_on_one_and_two_threads() {
    let run = |threads: usize, name: &str| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut w = scene(name, &[], "xpbd");
            w.step(120).unwrap();
            (w.state_hash(), w.solid_positions(), w.solid_velocities())
        })
    };
    for name in ["pyramid", "ball-chain", "ragdoll-bodies", "dice"] {
        let (a, b) = (run(1, name), run(2, name));
        assert_eq!(a.0, b.0, "{name}");
        assert!(a.1.iter().zip(&b.1).all(|(x, y)| x.to_bits() == y.to_bits()), "{name}");
        assert!(a.2.iter().zip(&b.2).all(|(x, y)| x.to_bits() == y.to_bits()), "{name}");
    }
}

#[test]
fn a_snapshot_under_xpbd_continues_bitwise() {
    for name in ["ball-chain", "pyramid"] {
        let mut w = scene(name, &[], "xpbd");
        w.step(90).unwrap();
        let snap = w.snapshot();
        w.step(60).unwrap();
        let (x, h) = (w.solid_positions(), w.state_hash());
        let mut again = scene(name, &[], "xpbd");
        again.restore(&snap).unwrap();
        again.step(60).unwrap();
        assert_eq!(again.state_hash(), h, "{name}");
        assert!(again.solid_positions().iter().zip(&x).all(|(a, b)| a.to_bits() == b.to_bits()), "{name}");
    }
}

#[test]
fn dice_thrown_onto_a_plane_come_to_rest_under_xpbd() {
    let mut w = scene("dice", &[], "xpbd");
    let (mut peak, mut deepest) = (0.0_f64, 0.0_f64);
    for k in 0..600 {
        w.step(1).unwrap();
        peak = peak.max(w.solid_kinetic_energy());
        if k >= 300 {
            deepest = deepest.max(w.max_penetration());
        }
    }
    let e = w.solid_kinetic_energy();
    let y = w.solid_positions();
    // Each die (a 20 cm cube) rests on a face: its centre 10 cm above the plane.
    let worst = (1..w.solid_count()).map(|i| (y[3 * i + 1] - 0.1).abs()).fold(0.0, f64::max);
    eprintln!("xpbd dice, 10 s: kinetic energy {e:e} of {peak}, deepest after 5 s {deepest:e} m, heights off by {worst:e} m");
    // Measured: 8.8e-27 J of 1146 J, 14 um deep, 7 um off.
    assert!(e < 1e-8 * peak, "kinetic energy {e} of {peak}");
    assert!(deepest < 0.001, "penetration {deepest}");
    assert!(worst < 0.001, "a die not on a face: {worst} m off");
}

#[test]
fn overlapping_solids_are_pushed_apart_at_most_at_the_push_speed_under_xpbd() {
    // Boxes started deep in each other: the position pass removes at most `push_speed` h of
    // an overlap a substep, so they separate at about that speed rather than at overlap / h.
    let mut w = scene("overlap-recovery", &[], "xpbd");
    let (mut fastest, mut deepest) = (0.0_f64, 0.0_f64);
    for _ in 0..300 {
        w.step(1).unwrap();
        let v = w.solid_velocities();
        fastest = fastest.max(v.chunks(2).map(|c| (c[0] * c[0] + c[1] * c[1]).sqrt()).fold(0.0, f64::max));
        deepest = deepest.max(w.max_penetration());
    }
    let end = w.max_penetration();
    eprintln!("xpbd overlap-recovery: fastest {fastest} m/s, deepest {deepest} m, at 5 s {end} m deep");
    // Measured: 7.5 m/s at the fastest (several overlaps pushing one box), 0.2 mm deep at 5 s;
    // removing each overlap in one substep threw them at up to overlap / h (120 m/s).
    assert!(fastest < 10.0, "fastest {fastest} m/s");
    assert!(end < 0.001, "still {end} m deep");
}

#[test]
fn under_xpbd_a_3d_hinge_turns_only_about_its_axis_a_weld_holds_and_a_rod_keeps_its_length() {
    // The joints in XPBD form: a door on a hinge about y (its swing corrected positionally).
    let mut s = Solids::<Space3>::new();
    s.settings.set_solver("xpbd").unwrap();
    let door = s.add(SolidParams::new(Shape::Box { half: vec![0.5, 1.0, 0.05] }, &[0.5, 0.0, 0.0])).unwrap();
    let mut h = JointParams::new(JointKind::Revolute, door, None, &[0.0, 0.0, 0.0]);
    h.axis = Some(vec![0.0, 1.0, 0.0]);
    s.add_joint(h).unwrap();
    let (mut swung, mut worst) = (0.0_f64, 0.0_f64);
    for _ in 0..600 {
        s.step(DT, DVec3::new(0.0, -G, -G)).unwrap();
        swung = swung.max(s.orientations()[2].abs());
        worst = worst.max(s.joint_errors()[0]);
    }
    let q = s.orientations();
    eprintln!("xpbd 3D hinge: error {worst:e} m, off-axis quaternion {:e} {:e}", q[1], q[3]);
    assert!(worst < 1e-3, "hinge error {worst}");
    assert!(q[1].abs() < 1e-3 && q[3].abs() < 1e-3, "turned off the hinge's axis: {q:?}");
    assert!(swung > 0.5, "turned about it: {swung}");
    // A welded cantilever and a rigid rod (distance joint) in the plane.
    let (mut s, beam) = super::joints::cantilever_and_rod("xpbd");
    let mut worst = [0.0_f64; 2];
    for _ in 0..600 {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
        for (w, e) in worst.iter_mut().zip(s.joint_errors()) {
            *w = w.max(e);
        }
    }
    let tip = s.orientations()[beam];
    eprintln!("xpbd weld: sags {tip:e} rad, error {:e} m; rod error {:e} m", worst[0], worst[1]);
    assert!(tip.abs() < 0.01, "the welded beam sags by {tip} rad");
    assert!(worst[0] < 1e-3 && worst[1] < 1e-3, "joint errors {worst:?}");
}

#[test]
fn the_ragdoll_whose_hinges_keep_their_rows_falls_and_rests_under_xpbd() {
    // Hinges with limits and joint friction (a motor) keep their velocity rows under xpbd.
    let mut w = scene("ragdoll-bodies", &[], "xpbd");
    let (worst, peak, pen) = super::joints::run_600(&mut w);
    let e = w.solid_kinetic_energy();
    eprintln!("xpbd ragdoll: joints within {worst:e} m, kinetic energy {e:e} of {peak}, deepest {pen:e} m");
    assert!(e < 1e-8 * peak, "at rest after 10 s: kinetic energy {e} of {peak}");
    // Measured: 29.8 mm (the soft step's test asks for 1 cm: here the contacts' position
    // corrections move the limbs and only the rows' soft bias pulls the hinges back; with the
    // hinges' points corrected positionally as well it stayed within 9.3 mm but did not come
    // to rest, 1.2e-2 J of 167 J at 10 s), 5.3e-9 J of 241 J, 4.1 mm deep.
    assert!(worst < 0.045, "joints within 4.5 cm: {worst}");
    assert!(pen < 0.02, "penetration {pen}");
}

#[test]
fn under_xpbd_restitution_sends_a_ball_back_up_and_a_kinematic_platform_carries_a_box() {
    let mut s = Solids::<Plane>::new();
    s.settings.set_solver("xpbd").unwrap();
    let mut ground = SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0]);
    ground.kind = Kind::Static;
    s.add(ground).unwrap();
    let mut ball = SolidParams::new(Shape::Circle { radius: 0.5 }, &[0.0, 0.5 + 5.0]);
    ball.restitution = 0.5;
    let b = s.add(ball).unwrap();
    let (mut landing, mut leaving, mut prev) = (0.0_f64, 0.0_f64, 0.0);
    for _ in 0..240 {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
        let vy = s.velocities()[2 * b + 1];
        if prev < 0.0 && vy > 0.0 && landing == 0.0 {
            (landing, leaving) = (-prev, vy);
        }
        prev = vy;
    }
    // sqrt(2 g h) = 9.9 m/s at landing.
    eprintln!("xpbd bounce: landed at {landing} m/s, left at {leaving} m/s");
    assert!((landing - (2.0 * G * 5.0).sqrt()).abs() < 0.2, "landing speed {landing}");
    assert!((leaving / landing - 0.5).abs() < 0.05, "left at {leaving} after landing at {landing}");

    let mut s = Solids::<Plane>::new();
    s.settings.set_solver("xpbd").unwrap();
    let mut platform = SolidParams::new(Shape::Box { half: vec![2.0, 0.25] }, &[0.0, 0.0]);
    platform.kind = Kind::Kinematic;
    platform.velocity = vec![1.0, 0.0];
    platform.friction = 1.0;
    let k = s.add(platform).unwrap();
    let mut riding = SolidParams::new(Shape::Box { half: vec![0.5, 0.5] }, &[0.0, 0.75]);
    riding.velocity = vec![1.0, 0.0];
    let b = s.add(riding).unwrap();
    for _ in 0..120 {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
    }
    let (p, v) = (s.positions(), s.velocities());
    eprintln!("xpbd platform: at {}, box at {} moving {}", p[2 * k], p[2 * b], v[2 * b]);
    assert_eq!(&v[2 * k..2 * k + 2], &[1.0, 0.0]);
    assert!((p[2 * k] - 2.0).abs() < 1e-12, "platform at {}", p[2 * k]);
    assert!((v[2 * b] - 1.0).abs() < 1e-3, "box velocity {}", v[2 * b]);
    assert!((p[2 * b] - p[2 * k]).abs() < 0.01, "box slid to {} on a platform at {}", p[2 * b], p[2 * k]);
}
