//! Joints between solids: pendulums and chains that keep their links, limits and motors that
//! hold, sliders, welds, a bridge; errors that name the field.

use glam::{DVec2, DVec3};
use physstep::contact::{JointKind, JointParams, Kind, Plane, Shape, SolidParams, Solids, Space3};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

fn capsule2(at: [f64; 2], half: f64, radius: f64, angle: f64) -> SolidParams {
    let mut p = SolidParams::new(Shape::Capsule { half_height: half, radius }, &at);
    p.orientation = vec![angle];
    p
}

/// A chain of `n` capsules of length 1 (tip to tip), hanging from the world at the origin,
/// laid out level (so it swings down), joined by revolute joints.
fn chain2(n: usize) -> Solids<Plane> {
    let mut s = Solids::<Plane>::new();
    let level = -std::f64::consts::FRAC_PI_2;
    for i in 0..n {
        // A capsule along y turned by -pi/2 lies along +x.
        let b = s.add(capsule2([i as f64 + 0.5, 0.0], 0.4, 0.1, level)).unwrap();
        let (a, other) = if i == 0 { (b, None) } else { (b - 1, Some(b)) };
        s.add_joint(JointParams::new(JointKind::Revolute, a, other, &[i as f64, 0.0])).unwrap();
    }
    s
}

fn worst_error(s: &mut Solids<Plane>, steps: usize) -> f64 {
    let mut worst = 0.0_f64;
    for _ in 0..steps {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
        worst = worst.max(s.joint_errors().into_iter().fold(0.0, f64::max));
    }
    worst
}

#[test]
fn a_hinge_pendulum_of_bodies_keeps_its_joint_within_a_thousandth_of_a_link_over_10000_steps() {
    let mut s = chain2(1);
    let worst = worst_error(&mut s, 10_000);
    assert!(worst < 1e-3, "the worst joint error {worst} m of a 1 m link");
    assert!(s.positions()[1] < -0.3, "it hangs: {:?}", s.positions());
}

#[test]
fn a_double_pendulum_of_bodies_holds_its_joints_and_tighter_with_the_projection() {
    // Chaotic, whipping: a point on a link turning at w leaves its partner by w^2 r h^2 / 2
    // a substep before the soft joint pulls it back; the projection after the step closes it.
    let soft = worst_error(&mut chain2(2), 10_000);
    assert!(soft < 2e-3, "soft joints alone: {soft} m of a 1 m link");
    let mut s = chain2(2);
    s.settings.joint_projection = 4;
    let projected = worst_error(&mut s, 10_000);
    assert!(projected < 1e-4, "with 4 projection passes: {projected} m");
    assert!(projected < soft / 5.0, "the projection tightens the joints: {projected} vs {soft}");
}

#[test]
fn a_single_hinged_rod_swings_with_the_period_of_a_physical_pendulum() {
    // A thin rod (a capsule of tiny radius) pinned at one end, 0.1 rad from the vertical:
    // T = 2 pi sqrt(2 L / (3 g)) (1 + theta^2 / 16).
    let (l, th) = (1.0, 0.1_f64);
    let mut s = Solids::<Plane>::new();
    let b = s.add(capsule2([l / 2.0 * th.sin(), -l / 2.0 * th.cos()], l / 2.0, 1e-3, th)).unwrap();
    s.add_joint(JointParams::new(JointKind::Revolute, b, None, &[0.0, 0.0])).unwrap();
    let dt = 1.0 / 240.0;
    let (mut t, mut last, mut crossings) = (0.0, s.orientations()[b], Vec::new());
    while t < 10.0 {
        s.step(dt, DVec2::new(0.0, -G)).unwrap();
        t += dt;
        let a = s.orientations()[b];
        if last > 0.0 && a <= 0.0 {
            // Linear interpolation of the downward crossing.
            crossings.push(t - dt * a / (a - last));
        }
        last = a;
    }
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let exact = 2.0 * std::f64::consts::PI * (2.0 * l / (3.0 * G)).sqrt() * (1.0 + th * th / 16.0);
    assert!((period / exact - 1.0).abs() < 2e-3, "period {period} s, closed form {exact} s");
    assert!(s.joint_errors()[0] < 1e-4, "pin error {}", s.joint_errors()[0]);
}

#[test]
fn a_revolute_motor_turns_a_wheel_at_its_speed_and_limits_stop_an_arm() {
    let mut s = Solids::<Plane>::new();
    let wheel = s.add(SolidParams::new(Shape::Circle { radius: 0.5 }, &[0.0, 0.0])).unwrap();
    let mut motor = JointParams::new(JointKind::Revolute, wheel, None, &[0.0, 0.0]);
    motor.motor_speed = 3.0;
    motor.max_motor = 100.0;
    s.add_joint(motor).unwrap();
    let arm = s.add(capsule2([3.0, -0.5], 0.5, 0.05, 0.0)).unwrap();
    let mut limited = JointParams::new(JointKind::Revolute, arm, None, &[3.0, 0.0]);
    limited.lower = Some(-0.5);
    limited.upper = Some(0.25);
    s.add_joint(limited).unwrap();
    // Swing the arm hard toward the upper limit.
    for _ in 0..300 {
        s.step(DT, DVec2::new(20.0, -G)).unwrap();
    }
    let w = s.angular_velocities()[wheel];
    assert!((w - 3.0).abs() < 1e-6, "the motor holds 3 rad/s: {w}");
    let angle = s.orientations()[arm];
    assert!((angle - 0.25).abs() < 0.01, "pushed to its upper limit 0.25: {angle}");
}

#[test]
fn a_prismatic_joint_slides_along_its_axis_only_and_stops_at_its_limit() {
    let mut s = Solids::<Plane>::new();
    let b = s.add(SolidParams::new(Shape::Box { half: vec![0.2, 0.2] }, &[0.0, 0.0])).unwrap();
    let mut p = JointParams::new(JointKind::Prismatic, b, None, &[0.0, 0.0]);
    let (c, sn) = (0.5_f64.cos(), 0.5_f64.sin());
    p.axis = Some(vec![c, -sn]);
    p.lower = Some(-1.0);
    p.upper = Some(2.0);
    s.add_joint(p).unwrap();
    for _ in 0..600 {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
    }
    let x = s.positions();
    let travel = x[0] * c - x[1] * sn;
    let across = x[0] * sn + x[1] * c;
    assert!((travel - 2.0).abs() < 0.01, "it slid down its axis to the limit 2: {travel}");
    assert!(across.abs() < 1e-3, "and never off the axis: {across}");
    assert!(s.orientations()[b].abs() < 1e-6, "without turning: {}", s.orientations()[b]);
}

/// A 1 m beam welded to the world at its end, and a ball on a 1 m rigid rod (a distance
/// joint) to the world, under `solver`: the beam's index (its weld is joint 0, the rod 1).
pub(crate) fn cantilever_and_rod(solver: &str) -> (Solids<Plane>, usize) {
    let mut s = Solids::<Plane>::new();
    s.settings.set_solver(solver).unwrap();
    let beam = s.add(SolidParams::new(Shape::Box { half: vec![0.5, 0.05] }, &[0.5, 0.0])).unwrap();
    s.add_joint(JointParams::new(JointKind::Weld, beam, None, &[0.0, 0.0])).unwrap();
    let bob = s.add(SolidParams::new(Shape::Circle { radius: 0.1 }, &[3.0, -1.0])).unwrap();
    let mut rope = JointParams::new(JointKind::Distance, bob, None, &[3.0, -1.0]);
    rope.anchor_b = Some(vec![3.0, 0.0]);
    s.add_joint(rope).unwrap();
    (s, beam)
}

#[test]
fn a_weld_holds_a_cantilever_and_a_distance_joint_keeps_its_length() {
    let (mut s, beam) = cantilever_and_rod("soft-step");
    for _ in 0..600 {
        s.step(DT, DVec2::new(0.0, -G)).unwrap();
    }
    let tip = s.orientations()[beam];
    assert!(tip.abs() < 0.01, "the welded beam sags by {tip} rad");
    let e = s.joint_errors();
    assert!(e[1] < 1e-3, "the rod keeps its length: {}", e[1]);
}

#[test]
fn a_3d_hinge_turns_only_about_its_axis() {
    let mut s = Solids::<Space3>::new();
    let door = s.add(SolidParams::new(Shape::Box { half: vec![0.5, 1.0, 0.05] }, &[0.5, 0.0, 0.0])).unwrap();
    let mut h = JointParams::new(JointKind::Revolute, door, None, &[0.0, 0.0, 0.0]);
    h.axis = Some(vec![0.0, 1.0, 0.0]);
    s.add_joint(h).unwrap();
    // Gravity along -z pulls the door around its vertical hinge; along -y it must not sag.
    let mut swung = 0.0_f64;
    for _ in 0..600 {
        s.step(DT, DVec3::new(0.0, -G, -G)).unwrap();
        swung = swung.max(s.orientations()[2].abs());
    }
    let e = s.joint_errors()[0];
    assert!(e < 1e-3, "hinge error {e}");
    let q = s.orientations();
    // The rotation is about y only: x and z components of the quaternion vanish.
    assert!(q[1].abs() < 1e-3 && q[3].abs() < 1e-3, "turned off the hinge's axis: {q:?}");
    assert!(swung > 0.5, "turned about it: the largest y of the quaternion {swung}");
}

#[test]
fn a_bad_joint_names_its_field_and_leaves_the_solids_unchanged() {
    let mut s = Solids::<Plane>::new();
    let a = s.add(SolidParams::new(Shape::Circle { radius: 0.1 }, &[0.0, 0.0])).unwrap();
    let mut ground = SolidParams::new(Shape::Circle { radius: 0.1 }, &[1.0, 0.0]);
    ground.kind = Kind::Static;
    let g = s.add(ground).unwrap();
    let cases: Vec<(JointParams, &str)> = vec![
        (JointParams::new(JointKind::Ball, a, Some(a), &[0.0, 0.0]), "b"),
        (JointParams::new(JointKind::Ball, a, Some(7), &[0.0, 0.0]), "b"),
        (JointParams::new(JointKind::Ball, 9, None, &[0.0, 0.0]), "a"),
        (JointParams::new(JointKind::Ball, g, None, &[0.0, 0.0]), "a"),
        (JointParams::new(JointKind::Ball, a, None, &[0.0]), "len(anchor)"),
        (JointParams::new(JointKind::Ball, a, None, &[f64::NAN, 0.0]), "anchor[0]"),
        (
            JointParams {
                axis: Some(vec![0.0, 0.0]),
                ..JointParams::new(JointKind::Prismatic, a, None, &[0.0, 0.0])
            },
            "axis",
        ),
        (
            JointParams {
                lower: Some(1.0),
                upper: Some(0.0),
                ..JointParams::new(JointKind::Revolute, a, None, &[0.0, 0.0])
            },
            "lower",
        ),
        (JointParams { hertz: -1.0, ..JointParams::new(JointKind::Distance, a, None, &[0.0, 0.0]) }, "hertz"),
        (
            JointParams { length: Some(-1.0), ..JointParams::new(JointKind::Distance, a, None, &[0.0, 0.0]) },
            "length",
        ),
    ];
    for (p, field) in cases {
        let e = s.add_joint(p).unwrap_err().to_string();
        assert!(e.contains(field), "{e} names {field}");
        assert_eq!(s.joint_count(), 0);
    }
    assert!(JointKind::by_name("rope").unwrap_err().to_string().contains("revolute"));
}

fn scene(name: &str) -> physstep::world::World {
    physstep::scenes::build(name, &[], "symplectic-euler", DT).unwrap().world
}

#[test]
fn the_bridge_keeps_its_joints_within_a_thousandth_of_a_plank_and_comes_to_rest() {
    let mut w = scene("bridge");
    let (mut worst, mut peak) = (0.0_f64, 0.0_f64);
    for _ in 0..10_000 {
        w.step(1).unwrap();
        worst = worst.max(w.joint_errors().into_iter().fold(0.0, f64::max));
        peak = peak.max(w.solid_kinetic_energy());
    }
    assert!(worst < 1e-3, "the worst joint error {worst} m of a 1 m plank");
    let e = w.solid_kinetic_energy();
    assert!(e < 1e-8 * peak, "at rest: kinetic energy {e} of {peak}");
    // It sags below its ends (a catenary), symmetric.
    let y = w.solid_positions();
    let mid = y[2 * 20 + 1];
    assert!(mid < -3.0, "the middle hangs: {mid}");
}

/// 600 steps of `w`: the largest joint error, solid kinetic energy and penetration over them.
pub(crate) fn run_600(w: &mut physstep::world::World) -> (f64, f64, f64) {
    let (mut worst, mut peak, mut pen) = (0.0_f64, 0.0_f64, 0.0_f64);
    for _ in 0..600 {
        w.step(1).unwrap();
        worst = worst.max(w.joint_errors().into_iter().fold(0.0, f64::max));
        peak = peak.max(w.solid_kinetic_energy());
        pen = pen.max(w.max_penetration());
    }
    (worst, peak, pen)
}

#[test]
fn the_ragdoll_of_bodies_falls_and_rests_on_the_ground_with_its_joints_whole() {
    let mut w = scene("ragdoll-bodies");
    // Solid 0 is the ground, 1 the torso.
    let torso0 = w.solid_positions()[3];
    let (worst, peak, pen) = run_600(&mut w);
    let torso = w.solid_positions()[3];
    assert!(torso < 0.5 && torso0 > 1.0, "it fell: the torso from {torso0} m to {torso} m");
    let e = w.solid_kinetic_energy();
    assert!(e < 1e-8 * peak, "at rest after 10 s: kinetic energy {e} of {peak}");
    assert!(worst < 0.01, "joints within 1 cm: {worst}");
    assert!(pen < 0.02, "penetration {pen}");
}

#[test]
fn the_ball_and_chain_swings_without_coming_apart_or_gaining_energy() {
    let mut w = scene("ball-chain");
    let e0 = w.energy().unwrap();
    let (mut worst, mut most) = (0.0_f64, e0);
    for _ in 0..3_000 {
        w.step(1).unwrap();
        worst = worst.max(w.joint_errors().into_iter().fold(0.0, f64::max));
        most = most.max(w.energy().unwrap());
    }
    // A 1:200 mass ratio along a whipping chain: soft joints stretch, never tear, and the
    // chain gains no energy (it loses some to the soft joints and the ground).
    assert!(worst < 0.05, "the worst joint error {worst} m of a 1 m link");
    assert!(most <= e0 + 1e-6 * e0.abs(), "energy rose from {e0} to {most}");
    let e = w.energy().unwrap();
    assert!(e < e0 - 0.01 * e0.abs(), "and fell: {e} from {e0}");
}

#[test]
fn a_snapshot_of_a_jointed_world_continues_bitwise_and_joints_are_in_the_hash() {
    let mut w = scene("ball-chain");
    w.step(90).unwrap();
    let snap = w.snapshot();
    w.step(60).unwrap();
    let (x, h) = (w.solid_positions(), w.state_hash());
    let mut again = scene("ball-chain");
    again.restore(&snap).unwrap();
    again.step(60).unwrap();
    assert_eq!(again.state_hash(), h);
    assert!(again.solid_positions().iter().zip(&x).all(|(a, b)| a.to_bits() == b.to_bits()));
    // The snapshot carries the joints' warm starts: a world with another joint refuses it.
    let mut other = scene("ball-chain");
    other.add_joint(JointParams::new(JointKind::Ball, 3, None, &[3.0, 22.0])).unwrap();
    let e = other.restore(&snap).unwrap_err().to_string();
    assert!(e.contains("joints"), "{e}");
}

#[test]
fn jointed_scenes_give_the_same_bits_on_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut w = scene("ragdoll-bodies");
            w.step(120).unwrap();
            w.state_hash()
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_scene_file_carries_joints_and_refuses_a_bad_one_at_its_line() {
    let text = "dimension = 2\n\n[[solids]]\nshape = { kind = \"circle\", radius = 0.1 }\nposition = [1.0, 0.0]\n\n[[joints]]\nkind = \"distance\"\na = 0\nanchor = [1.0, 0.0]\nanchor_b = [0.0, 0.0]\n";
    let mut w = physstep::scenes::file::parse(text, "rod.toml").unwrap().world;
    assert_eq!(w.joint_count(), 1);
    w.step(600).unwrap();
    assert!(w.joint_errors()[0] < 1e-3, "a rigid rod of length 1: {:?}", w.joint_errors());
    let bad = text.replace("a = 0", "a = 0\nb = 0");
    let e = physstep::scenes::file::parse(&bad, "rod.toml").unwrap_err().to_string();
    assert!(e.contains("rod.toml:7") && e.contains("joints[0]") && e.contains("b = 0"), "{e}");
}
