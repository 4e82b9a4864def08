//! Forces on solids: drag, springs between points, loads by hand (docs/contact.md, "Forces
//! on solids"), against their closed forms.

use physstep::contact::{Kind, Shape, SolidParams, SolidSpring};
use physstep::forces::Force;
use physstep::world::{World, WorldParams};

const DT: f64 = 1.0 / 60.0;

fn world(dim: usize, g: f64) -> World {
    let mut w = World::new(WorldParams { dim, dt: DT, ..WorldParams::default() }).unwrap();
    if g != 0.0 {
        let mut a = [0.0; 3];
        a[1] = -g;
        w.add_force(Force::Gravity { g: a }).unwrap();
    }
    w
}

/// A disc (2D) or ball (3D) of radius 0.5 at `at`.
fn ball(dim: usize, at: &[f64]) -> SolidParams {
    assert_eq!(at.len(), dim);
    SolidParams::new(Shape::Circle { radius: 0.5 }, at)
}

fn mass_of_ball(dim: usize, rho: f64) -> f64 {
    let r = 0.5_f64;
    if dim == 2 {
        rho * std::f64::consts::PI * r * r
    } else {
        rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
    }
}

/// The mass of solid `i`, a ball of radius 0.5 (a disc in 2D).
fn mass(w: &World, i: usize) -> f64 {
    mass_of_ball(w.dim(), w.solid_params()[i].density)
}

#[test]
fn drag_decays_speed_and_spin_as_exp_minus_c_t() {
    for dim in [2, 3] {
        let mut w = world(dim, 0.0);
        let mut p = ball(dim, &vec![0.0; dim]);
        p.velocity[0] = 2.0;
        let spin = if dim == 3 { 2 } else { 0 };
        p.angular_velocity[spin] = 3.0;
        p.linear_damping = 0.5;
        p.angular_damping = 0.3;
        w.add_solid(p).unwrap();
        let steps = 120; // 2 s
        w.step(steps).unwrap();
        let t = steps as f64 * DT;
        let v = w.solid_velocities()[0];
        let om = w.solid_angular_velocities()[spin];
        // Box2D's form: each substep v /= 1 + h c, so (1 + h c)^-N exactly, and exp(-c t) to 1%.
        let h = DT / f64::from(w.contact_settings().substeps);
        let n = (steps * u64::from(w.contact_settings().substeps)) as i32;
        assert!((v / (2.0 * (1.0 + h * 0.5).powi(-n)) - 1.0).abs() < 1e-12, "{dim}D v {v}");
        assert!((om / (3.0 * (1.0 + h * 0.3).powi(-n)) - 1.0).abs() < 1e-12, "{dim}D w {om}");
        assert!((v / (2.0 * (-0.5 * t).exp()) - 1.0).abs() < 0.01, "{dim}D v {v}");
        assert!((om / (3.0 * (-0.3 * t).exp()) - 1.0).abs() < 0.01, "{dim}D w {om}");
    }
}

#[test]
fn drag_is_refused_when_negative_or_not_finite_and_the_world_is_unchanged() {
    let mut w = world(2, 9.81);
    w.add_solid(ball(2, &[0.0, 0.0])).unwrap();
    let before = w.state_hash();
    for (field, bad) in
        [("linear_damping", -1.0), ("angular_damping", f64::NAN), ("linear_damping", f64::INFINITY)]
    {
        let mut p = ball(2, &[3.0, 0.0]);
        if field == "linear_damping" {
            p.linear_damping = bad;
        } else {
            p.angular_damping = bad;
        }
        let e = w.add_solid(p).unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
        assert!(e.contains(&format!("{bad}")) || e.contains("NaN") || e.contains("inf"), "{e}");
    }
    assert_eq!(w.solid_count(), 1);
    assert_eq!(w.state_hash(), before);
}

#[test]
fn drag_and_springs_are_in_the_state_hash_and_nothing_else_changes_it() {
    let make = |c: f64, k: f64| {
        let mut w = world(2, 9.81);
        let mut p = ball(2, &[0.0, 0.0]);
        p.linear_damping = c;
        w.add_solid(p).unwrap();
        if k > 0.0 {
            w.add_solid_spring(SolidSpring::to_world(0, &[0.0, 0.0], &[0.0, 2.0], k)).unwrap();
        }
        w.state_hash()
    };
    assert_eq!(make(0.0, 0.0), make(0.0, 0.0));
    assert_ne!(make(0.0, 0.0), make(0.1, 0.0));
    assert_ne!(make(0.0, 0.0), make(0.0, 10.0));
    assert_ne!(make(0.0, 10.0), make(0.0, 20.0));
}

/// A ball hanging on a spring from a fixed point above it, pulled down `pull` m from where
/// it rests, let go; `(omega from the half periods, largest |E - E0|, E0 - E at rest)`.
fn hanging(dim: usize, k: f64, steps: u64) -> (f64, f64, f64, f64) {
    let g = 9.81;
    let mut w = world(dim, g);
    // Rest length 2 from y = 1: at rest at y = -1 - m g / k; let go 0.2 m below that.
    let (rest, pull) = (2.0, 0.2);
    let m = mass_of_ball(dim, 1.0);
    let mut at = vec![0.0; dim];
    at[1] = 1.0 - rest - m * g / k - pull;
    w.add_solid(ball(dim, &at)).unwrap();
    let mut top = vec![0.0; dim];
    top[1] = 1.0;
    let mut s = SolidSpring::to_world(0, &vec![0.0; dim], &top, k);
    s.rest_length = Some(rest);
    w.add_solid_spring(s).unwrap();
    let e0 = w.solid_energy();
    assert_eq!(Some(e0), w.energy(), "the world's energy is the solids'");
    let mut worst: f64 = 0.0;
    let mut crossings = Vec::new();
    let mut last = w.solid_velocities()[1];
    for k in 1..=steps {
        w.step(1).unwrap();
        worst = worst.max((w.solid_energy() - e0).abs());
        let v = w.solid_velocities()[1];
        if (last < 0.0) != (v < 0.0) && k > 1 {
            // Where the velocity crossed zero, linearly between the two steps.
            crossings.push((k as f64 - 1.0 + last / (last - v)) * DT);
        }
        last = v;
    }
    let half = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let omega = std::f64::consts::PI / half;
    let amplitude_energy = 0.5 * k * pull * pull;
    (omega, (k / m).sqrt(), worst, amplitude_energy)
}

#[test]
fn a_solid_on_a_spring_oscillates_at_sqrt_k_over_m_and_keeps_its_energy() {
    for dim in [2, 3] {
        let (omega, exact, worst, e_osc) = hanging(dim, 40.0, 10_000);
        assert!((omega / exact - 1.0).abs() < 0.01, "{dim}D: omega {omega}, sqrt(k/m) {exact}");
        // Symplectic Euler in the substeps (h = dt / 8): the energy oscillates by about
        // h omega / 2 of the oscillation's energy (0.9% here) and does not drift. Bound over
        // 10,000 steps: h omega of it.
        let h = DT / 8.0;
        assert!(worst < h * exact * e_osc, "{dim}D: energy off by {worst} J of {e_osc} J");
    }
}

#[test]
fn two_solids_on_a_spring_keep_their_momentum_and_angular_momentum() {
    for dim in [2, 3] {
        let mut w = world(dim, 0.0);
        let mut a = ball(dim, &vec![0.0; dim]);
        a.velocity[1] = 0.3;
        let mut at = vec![0.0; dim];
        at[0] = 4.0;
        let mut b = ball(dim, &at);
        b.density = 3.0;
        b.velocity[0] = -0.7;
        b.angular_velocity[0] = 0.4;
        w.add_solid(a).unwrap();
        w.add_solid(b).unwrap();
        let mut pa = vec![0.0; dim];
        pa[1] = 0.3;
        let mut pb = vec![0.0; dim];
        pb[0] = -0.2;
        pb[1] = 0.1;
        let s = SolidSpring {
            a: 0,
            point_a: pa,
            b: Some(1),
            point_b: pb,
            stiffness: 50.0,
            rest_length: Some(3.5),
            damping: 0.5,
        };
        w.add_solid_spring(s).unwrap();
        let masses = [mass(&w, 0), mass(&w, 1)];
        let momentum = |w: &World| {
            let v = w.solid_velocities();
            (0..dim).map(|k| masses[0] * v[k] + masses[1] * v[dim + k]).collect::<Vec<_>>()
        };
        let p0 = momentum(&w);
        let scale = masses[0] * 0.3 + masses[1] * 0.7;
        let e0 = w.solid_energy();
        let mut touched = false;
        for _ in 0..600 {
            w.step(1).unwrap();
            touched |= !w.contacts().depths.is_empty();
        }
        assert!(!touched, "{dim}D: they came near each other");
        let p1 = momentum(&w);
        for k in 0..dim {
            assert!((p1[k] - p0[k]).abs() < 1e-13 * scale * 600.0, "{dim}D p[{k}] {} -> {}", p0[k], p1[k]);
        }
        // Damping along the line took energy, but none of the centre of mass's motion; and
        // it turned them (the spring is off their centres).
        let e = w.solid_energy();
        let e_cm = p0.iter().map(|p| p * p).sum::<f64>() / (2.0 * (masses[0] + masses[1]));
        assert!(e < e0 && e > e_cm, "{dim}D: {e0} J -> {e} J (centre of mass {e_cm} J)");
        let spin = w.solid_angular_velocities();
        assert!(spin[0] != 0.0, "{spin:?}");
    }
}

#[test]
fn a_damped_spring_decays_as_exp_minus_c_t_over_2m() {
    // No gravity, a spring to a fixed point: the amplitude's envelope exp(-c t / 2m).
    let mut w = world(2, 0.0);
    w.add_solid(ball(2, &[1.2, 0.0])).unwrap();
    let m = mass(&w, 0);
    let (k, c) = (30.0, 0.2);
    let s = SolidSpring {
        a: 0,
        point_a: vec![0.0, 0.0],
        b: None,
        point_b: vec![0.0, 0.0],
        stiffness: k,
        rest_length: Some(1.0),
        damping: c,
    };
    w.add_solid_spring(s).unwrap();
    let e0 = w.solid_energy();
    let t = 3.0;
    w.step((t / DT).round() as u64).unwrap();
    // The energy of a lightly damped oscillator decays as exp(-c t / m) (averaged over a
    // period; 3 s is a whole number of periods within a few %, so compare near a crest of
    // the energy: at a turning point the energy is all the spring's).
    let e = w.solid_energy();
    let want = e0 * (-c * t / m).exp();
    assert!((e / want - 1.0).abs() < 0.05, "energy {e}, exp(-c t / m) gives {want}");
}

#[test]
fn springs_are_refused_with_the_field_and_the_value_and_the_world_is_unchanged() {
    let mut w = world(2, 9.81);
    w.add_solid(ball(2, &[0.0, 0.0])).unwrap();
    w.add_solid(ball(2, &[2.0, 0.0])).unwrap();
    let good = SolidSpring {
        a: 0,
        point_a: vec![0.0, 0.0],
        b: Some(1),
        point_b: vec![0.0, 0.0],
        stiffness: 10.0,
        rest_length: None,
        damping: 0.0,
    };
    let before = w.state_hash();
    let cases: Vec<(SolidSpring, &str, &str)> = vec![
        (SolidSpring { a: 5, ..good.clone() }, "a", "5"),
        (SolidSpring { b: Some(7), ..good.clone() }, "b", "7"),
        (SolidSpring { b: Some(0), ..good.clone() }, "b", "0"),
        (SolidSpring { stiffness: -1.0, ..good.clone() }, "stiffness", "-1"),
        (SolidSpring { damping: -0.5, ..good.clone() }, "damping", "-0.5"),
        (SolidSpring { rest_length: Some(-2.0), ..good.clone() }, "rest_length", "-2"),
        (SolidSpring { rest_length: Some(f64::NAN), ..good.clone() }, "rest_length", "NaN"),
        (SolidSpring { stiffness: f64::INFINITY, ..good.clone() }, "stiffness", "inf"),
        (SolidSpring { point_a: vec![0.0, 0.0, 0.0], ..good.clone() }, "len(point_a)", "3"),
        (SolidSpring { point_b: vec![0.0, f64::NAN], ..good.clone() }, "point_b[1]", "NaN"),
    ];
    for (s, field, value) in cases {
        let e = w.add_solid_spring(s).unwrap_err().to_string();
        assert!(e.starts_with(&format!("invalid {field} = ")), "{field}: {e}");
        assert!(e.contains(value), "{value}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
    assert!(w.solid_springs().is_empty());
    assert_eq!(w.state_hash(), before);
    let mut one_d = world(1, 0.0);
    let e = one_d.add_solid_spring(good.clone()).unwrap_err().to_string();
    assert!(e.starts_with("invalid dim"), "{e}");
    // The rest length defaults to the distance now, and is kept as a number.
    assert_eq!(w.add_solid_spring(good).unwrap(), 0);
    assert_eq!(w.solid_springs()[0].rest_length, Some(2.0));
}

#[test]
fn a_force_applied_by_hand_acts_for_one_step_and_turns_the_solid_at_a_point() {
    for dim in [2, 3] {
        let mut w = world(dim, 0.0);
        w.add_solid(ball(dim, &vec![0.0; dim])).unwrap();
        let m = mass(&w, 0);
        let mut f = vec![0.0; dim];
        f[0] = 3.0;
        let mut at = vec![0.0; dim];
        at[1] = 0.5;
        w.apply_solid_force(0, &f, Some(&at)).unwrap();
        w.step(1).unwrap();
        let v = w.solid_velocities()[0];
        assert!((v - 3.0 * DT / m).abs() < 1e-15, "{dim}D v {v}");
        // r x F = (0, 0.5) x (3, 0) = -1.5 about z; I = m r^2 / 2 (disc) or 2 m r^2 / 5 (ball).
        let i = if dim == 2 { m * 0.25 / 2.0 } else { 2.0 * m * 0.25 / 5.0 };
        let wz = *w.solid_angular_velocities().last().unwrap();
        assert!((wz + 1.5 * DT / i).abs() < 1e-12, "{dim}D w {wz}");
        w.step(1).unwrap();
        assert_eq!(w.solid_velocities()[0], v, "the load acts for one step only");
        let torque = if dim == 2 { vec![2.0] } else { vec![0.0, 0.0, 2.0] };
        w.apply_solid_torque(0, &torque).unwrap();
        w.step(1).unwrap();
        let wz2 = *w.solid_angular_velocities().last().unwrap();
        assert!((wz2 - wz - 2.0 * DT / i).abs() < 1e-12, "{dim}D w {wz2}");
        let e = w.apply_solid_force(3, &f, None).unwrap_err().to_string();
        assert!(e.starts_with("invalid solid = 3"), "{e}");
        let e = w.apply_solid_force(0, &[f64::NAN; 2][..dim.min(2)], None).unwrap_err().to_string();
        assert!(e.contains("force"), "{e}");
        let e = w.apply_solid_torque(0, &[1.0, 2.0]).unwrap_err().to_string();
        assert!(e.starts_with("invalid len(torque) = 2"), "{e}");
    }
}

#[test]
fn drag_and_springs_go_through_scene_files_and_step_the_same() {
    for dim in [2, 3] {
        let mut w = world(dim, 9.81);
        let mut ground = SolidParams::new(Shape::Box { half: vec![5.0; dim] }, &{
            let mut at = vec![0.0; dim];
            at[1] = -10.0;
            at
        });
        ground.kind = Kind::Static;
        w.add_solid(ground).unwrap();
        let mut p = ball(dim, &vec![0.0; dim]);
        p.linear_damping = 0.25;
        p.angular_damping = 0.125;
        w.add_solid(p).unwrap();
        let mut at = vec![0.0; dim];
        at[0] = 1.5;
        w.add_solid(ball(dim, &at)).unwrap();
        let mut pa = vec![0.0; dim];
        pa[1] = 0.25;
        w.add_solid_spring(SolidSpring {
            a: 1,
            point_a: pa,
            b: Some(2),
            point_b: vec![0.0; dim],
            stiffness: 20.0,
            rest_length: None,
            damping: 0.75,
        })
        .unwrap();
        let mut top = vec![0.0; dim];
        top[1] = 3.0;
        w.add_solid_spring(SolidSpring::to_world(1, &vec![0.0; dim], &top, 35.0)).unwrap();
        let text = physstep::scenes::file::export(&w, "sprung", None).unwrap();
        assert!(text.contains("[[solid_springs]]") && text.contains("linear_damping = 0.25"), "{text}");
        let mut back = physstep::scenes::file::parse(&text, "sprung.toml").unwrap().world;
        assert_eq!(back.solid_springs(), w.solid_springs());
        assert_eq!(back.state_hash(), w.state_hash());
        w.step(200).unwrap();
        back.step(200).unwrap();
        assert_eq!(back.state_hash(), w.state_hash(), "{dim}D");
        // One thread or two: the same bits.
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let mut c = physstep::scenes::file::parse(&text, "sprung.toml").unwrap().world;
            pool.install(|| c.step(200).unwrap());
            c.state_hash()
        };
        assert_eq!(run(1), run(2));
        assert_eq!(run(1), w.state_hash());
    }
}

#[test]
fn scene_files_refuse_bad_solid_springs_naming_the_table() {
    let text = "dimension = 2\n[[solids]]\nshape = { kind = \"circle\", radius = 0.5 }\nposition = [0, 0]\n\n[[solid_springs]]\na = 0\npoint_a = [0, 0]\nb = 0\npoint_b = [0, 0]\nstiffness = 3\n";
    let e = physstep::scenes::file::parse(text, "bad.toml").unwrap_err().to_string();
    assert!(e.contains("solid_springs[0]") && e.contains('b'), "{e}");
    let text = text.replace("b = 0\n", "").replace("stiffness = 3", "stiffness = 3\nwobble = 1");
    let e = physstep::scenes::file::parse(&text, "bad.toml").unwrap_err().to_string();
    assert!(e.contains("wobble"), "{e}");
}

/// A user force at a solid's point: a zero-rest spring to the origin, failing (or giving a
/// NaN) on the call numbered `fail_at` when set.
struct Pull {
    k: f64,
    calls: std::sync::atomic::AtomicUsize,
    fail_at: Option<(usize, bool)>,
}

impl physstep::forces::ForceGenerator for Pull {
    fn name(&self) -> &str {
        "pull"
    }

    fn add_forces(&self, _t: f64, x: &[f64], _v: &[f64], f: &mut [f64]) -> Result<(), String> {
        let n = self.calls.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        if let Some((k, nan)) = self.fail_at {
            if n == k {
                if nan {
                    f[0] = f64::NAN;
                    return Ok(());
                }
                return Err("the wind stopped".into());
            }
        }
        for (fi, xi) in f.iter_mut().zip(x) {
            *fi -= self.k * xi;
        }
        Ok(())
    }

    fn potential(&self, x: &[f64]) -> Option<f64> {
        Some(0.5 * self.k * x.iter().map(|c| c * c).sum::<f64>())
    }
}

/// Where `point` (in solid 0's frame: a ball's, its centre its origin) is now.
fn point_now(w: &World, point: &[f64]) -> Vec<f64> {
    let c = w.solid_positions();
    let q = w.solid_orientations();
    if w.dim() == 2 {
        let (s, co) = q[0].sin_cos();
        vec![c[0] + co * point[0] - s * point[1], c[1] + s * point[0] + co * point[1]]
    } else {
        let q = glam::DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
        let p = q * glam::DVec3::from_slice(point);
        vec![c[0] + p.x, c[1] + p.y, c[2] + p.z]
    }
}

fn pull(fail_at: Option<(usize, bool)>) -> std::sync::Arc<Pull> {
    std::sync::Arc::new(Pull { k: 20.0, calls: 0.into(), fail_at })
}

#[test]
fn a_user_force_at_a_point_is_held_over_the_step_and_its_failures_roll_the_step_back() {
    for dim in [2, 3] {
        // Once a step at its start: the same bits as applying its value by hand.
        let mut at = vec![0.0; dim];
        at[0] = 1.0;
        let mut point = vec![0.0; dim];
        point[1] = 0.25;
        let mut by_user = world(dim, 0.0);
        let mut by_hand = world(dim, 0.0);
        by_user.add_solid(ball(dim, &at)).unwrap();
        by_hand.add_solid(ball(dim, &at)).unwrap();
        assert_eq!(by_user.add_solid_force(0, &point, pull(None)).unwrap(), 0);
        assert_eq!(by_user.solid_force_count(), 1);
        for _ in 0..30 {
            // The point now: where the user force saw it.
            let x = point_now(&by_hand, &point);
            let f: Vec<f64> = x.iter().map(|xi| -20.0 * xi).collect();
            by_hand.apply_solid_force(0, &f, Some(&x)).unwrap();
            by_hand.step(1).unwrap();
            by_user.step(1).unwrap();
        }
        assert_eq!(by_user.solid_velocities(), by_hand.solid_velocities(), "{dim}D");
        assert_eq!(by_user.solid_angular_velocities(), by_hand.solid_angular_velocities(), "{dim}D");
        // Its potential joins the world's energy.
        let e = by_user.energy().unwrap();
        let u: f64 = point_now(&by_user, &point).iter().map(|x| 10.0 * x * x).sum();
        assert!((e - by_user.solid_energy() - u).abs() < 1e-12 * e.abs(), "{dim}D: {e}, {u}");

        for nan in [false, true] {
            let mut w = world(dim, 9.81);
            w.add_solid(ball(dim, &at)).unwrap();
            w.add_solid_force(0, &point, pull(Some((3, nan)))).unwrap();
            w.step(3).unwrap();
            let h = w.state_hash();
            let e = w.step(2).unwrap_err();
            assert_eq!(w.steps(), 3, "{dim}D: the failing step is rolled back");
            assert_eq!(w.state_hash(), h);
            let msg = e.to_string();
            assert!(msg.contains("pull"), "{msg}");
            assert!(msg.contains(if nan { "NaN is not finite" } else { "the wind stopped" }), "{msg}");
            assert_eq!(e.is_step_failure(), nan, "{msg}");
        }
        let mut w = world(dim, 0.0);
        w.add_solid(ball(dim, &at)).unwrap();
        let e = w.add_solid_force(2, &point, pull(None)).unwrap_err().to_string();
        assert!(e.starts_with("invalid solid = 2"), "{e}");
        let e = w.add_solid_force(0, &[0.0; 4], pull(None)).unwrap_err().to_string();
        assert!(e.starts_with("invalid len(point) = 4"), "{e}");
        assert_eq!(w.solid_force_count(), 0);
        // A file cannot hold it.
        w.add_solid_force(0, &point, pull(None)).unwrap();
        assert!(physstep::scenes::file::export(&w, "t", None).is_err());
    }
}
