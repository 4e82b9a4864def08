//! Rigid bodies in a world: the free body's invariants, torques from off-centre forces,
//! gravity on the centre of mass, orientations that stay rotations, refusals, snapshots.

use physstep::prelude::*;
use physstep::rigid::body::AngularForm;
use physstep::rigid::inertia::Shape;
use physstep::rigid::orientation::Rule;
use physstep::scenes;
use physstep::world::BodyParams;

fn world(method: &str, dt: f64) -> World {
    World::new(WorldParams { dim: 3, method: method.into(), dt, ..WorldParams::default() }).unwrap()
}

/// A box whose principal moments are 1 : 2 : 3 to 1e-4 (a thin plate), spun mostly about
/// its intermediate axis: the tennis-racket flip.
fn racket(method: &str, rule: Rule) -> World {
    let mut w = world(method, 1.0 / 120.0);
    w.set_orientation_rule(rule);
    let s = 0.5;
    w.add_body(&BodyParams {
        shape: Shape::Box { half_extents: [2f64.sqrt() * s, s, 0.005 * s] },
        mass: Some(12.0),
        angular_velocity: [0.01, 2.0, 0.01],
        ..BodyParams::default()
    })
    .unwrap();
    w
}

fn norm(v: [f64; 3]) -> f64 {
    v.iter().map(|c| c * c).sum::<f64>().sqrt()
}

#[test]
fn the_free_racket_keeps_its_angular_momentum_exactly_and_its_energy_bounded() {
    let mut w = racket("symplectic-euler", Rule::Splitting);
    let l0 = w.angular_momentum();
    let e0 = w.energy().unwrap();
    let mut max_de = 0.0f64;
    let mut flips = 0;
    let mut last_sign = w.body_angular_velocity(0).unwrap();
    for _ in 0..144 {
        w.step(100).unwrap();
        let de = (w.energy().unwrap() - e0).abs() / e0;
        max_de = max_de.max(de);
        // The spin axis flips: the angular velocity's component along the body's
        // intermediate axis changes sign every half period.
        let omega = w.body_angular_velocity(0).unwrap();
        let q = w.body_orientation(0).unwrap();
        let along = body_y(q, omega);
        if along * body_y(q, last_sign) < 0.0 {
            flips += 1;
        }
        last_sign = omega;
    }
    let l = w.angular_momentum();
    let dl = norm([l[0] - l0[0], l[1] - l0[1], l[2] - l0[2]]) / norm(l0);
    assert!(dl < 1e-12, "|L| drift {dl:e}");
    // Measured 2.4e-6 (bounded: the splitting is symplectic).
    assert!(max_de < 1e-5, "energy error {max_de:e}");
    assert!(flips >= 2, "the intermediate axis flipped {flips} times in 120 s");
    let q = w.body_orientation(0).unwrap();
    let unit = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    assert!((unit - 1.0).abs() < 1e-12, "|q| = {unit}");
}

/// The component of `omega` along the shape's y axis (the intermediate one).
fn body_y(q: [f64; 4], omega: [f64; 3]) -> f64 {
    let [w, x, y, z] = q;
    // The world direction of the body's y axis: the second column of R(q).
    let axis = [2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)];
    axis.iter().zip(omega).map(|(a, o)| a * o).sum()
}

#[test]
fn the_notes_quaternion_rule_drifts_where_the_splitting_does_not() {
    let energy_error = |rule| {
        let mut w = racket("symplectic-euler", rule);
        let e0 = w.energy().unwrap();
        w.step(14_400).unwrap();
        (w.energy().unwrap() - e0).abs() / e0
    };
    let splitting = energy_error(Rule::Splitting);
    let notes = energy_error(Rule::Quaternion);
    // Measured: quaternion 0.87, splitting 1.3e-9.
    assert!(notes > 1e3 * splitting, "quaternion {notes:e}, splitting {splitting:e}");
}

#[test]
fn an_off_centre_force_makes_the_torque_r_cross_f_and_one_through_the_centre_none() {
    let mut w = world("symplectic-euler", 0.01);
    w.add_body(&BodyParams {
        shape: Shape::Sphere { radius: 0.5 },
        mass: Some(2.0),
        position: [1.0, 2.0, 3.0],
        ..BodyParams::default()
    })
    .unwrap();
    let f = [0.0, 4.0, 0.0];
    w.apply_force(0, f, Some([1.5, 2.0, 3.0])).unwrap();
    w.step(1).unwrap();
    // r = (0.5, 0, 0): tau = r x F = (0, 0, 2); L after one step = tau h.
    let l = w.body_angular_momentum(0).unwrap();
    assert!((l[2] - 0.02).abs() < 1e-15 && l[0] == 0.0 && l[1] == 0.0, "{l:?}");
    let v = w.body_velocity(0).unwrap();
    assert!((v[1] - 4.0 * 0.01 / 2.0).abs() < 1e-15, "{v:?}");
    // The load was for one step: the next one adds nothing.
    w.step(1).unwrap();
    assert_eq!(w.body_angular_momentum(0).unwrap(), l);

    let mut w = world("symplectic-euler", 0.01);
    w.add_body(&BodyParams { shape: Shape::Box { half_extents: [1.0, 0.5, 0.2] }, ..BodyParams::default() })
        .unwrap();
    w.apply_force(0, [3.0, -1.0, 2.0], None).unwrap();
    w.step(5).unwrap();
    assert_eq!(w.body_angular_momentum(0).unwrap(), [0.0; 3]);
    assert_eq!(w.body_orientation(0).unwrap(), [1.0, 0.0, 0.0, 0.0]);
}

#[test]
fn gravity_moves_a_bodys_centre_like_a_particle() {
    let mut w = world("velocity-verlet", 0.1);
    w.add_force(Force::Gravity { g: [0.0, 0.0, -9.81] }).unwrap();
    w.add_body(&BodyParams {
        shape: Shape::Cylinder { radius: 0.3, height: 1.0 },
        density: Some(500.0),
        velocity: [1.0, 0.0, 5.0],
        angular_velocity: [0.3, -0.2, 1.0],
        ..BodyParams::default()
    })
    .unwrap();
    let e0 = w.energy().unwrap();
    w.step(10).unwrap();
    let c = w.body_position(0).unwrap();
    assert!((c[0] - 1.0).abs() < 1e-12 && (c[2] - (5.0 - 0.5 * 9.81)).abs() < 1e-12, "{c:?}");
    let de = (w.energy().unwrap() - e0).abs() / e0.abs();
    assert!(de < 1e-3, "energy error {de:e}");
}

#[test]
fn flow_methods_keep_orientations_unit_and_converge_on_the_free_body() {
    for method in ["rk4", "midpoint", "heun", "explicit-euler"] {
        let mut w = racket(method, Rule::Splitting);
        w.step(1200).unwrap();
        let q = w.body_orientation(0).unwrap();
        let unit = q.iter().map(|c| c * c).sum::<f64>().sqrt();
        assert!((unit - 1.0).abs() < 1e-12, "{method}: |q| = {unit}");
    }
    // rk4 and the splitting agree on the orientation after 10 s (both accurate at dt = 1/120).
    let mut a = racket("rk4", Rule::Splitting);
    let mut b = racket("velocity-verlet", Rule::Splitting);
    a.step(1200).unwrap();
    b.step(1200).unwrap();
    let (qa, qb) = (a.body_orientation(0).unwrap(), b.body_orientation(0).unwrap());
    let dot: f64 = qa.iter().zip(qb).map(|(x, y)| x * y).sum();
    assert!(dot.abs() > 1.0 - 1e-6, "rk4 {qa:?} vs splitting {qb:?}");
}

#[test]
fn verlet_is_refused_for_bodies_when_configured() {
    let mut w = world("verlet", 0.01);
    let err = w.add_body(&BodyParams::default()).unwrap_err();
    assert!(matches!(err, Error::Unsupported { .. }) && err.to_string().contains("vectors"), "{err}");
    assert_eq!(w.bodies().len(), 0);
    let mut w = world("rk4", 0.01);
    w.add_body(&BodyParams::default()).unwrap();
    let err = w.set_method("verlet").unwrap_err();
    assert!(err.to_string().contains("verlet"), "{err}");
    assert_eq!(w.integrator().info().name, "rk4");
}

#[test]
fn bad_bodies_are_refused_naming_the_field() {
    let mut w = world("rk4", 0.01);
    let cases: [(BodyParams, &str); 5] = [
        (BodyParams { mass: Some(-1.0), ..BodyParams::default() }, "mass"),
        (BodyParams { orientation: [0.0; 4], ..BodyParams::default() }, "orientation"),
        (BodyParams { shape: Shape::Sphere { radius: 0.0 }, ..BodyParams::default() }, "radius"),
        (BodyParams { velocity: [f64::NAN, 0.0, 0.0], ..BodyParams::default() }, "velocity"),
        (BodyParams { position: [0.0, f64::INFINITY, 0.0], ..BodyParams::default() }, "position"),
    ];
    for (p, field) in cases {
        let msg = w.add_body(&p).unwrap_err().to_string();
        assert!(msg.contains(field) && !msg.contains('\n'), "{field}: {msg}");
    }
    assert_eq!(w.bodies().len(), 0);
    let mut flat = World::new(WorldParams { dim: 2, ..WorldParams::default() }).unwrap();
    assert!(flat.add_body(&BodyParams::default()).unwrap_err().to_string().contains("dim"));
    assert!(w.body_position(0).unwrap_err().to_string().contains("body"));
}

#[test]
fn particles_and_bodies_share_a_world_and_a_snapshot_continues_bitwise() {
    let mut w = racket("leapfrog", Rule::Splitting);
    w.add_particle(&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], 1.0, false).unwrap();
    w.add_force(Force::Spring {
        i: 0,
        j: Endpoint::Anchor([0.0; 3]),
        stiffness: 1.0,
        rest_length: 0.0,
        damping: 0.0,
    })
    .unwrap();
    w.step(50).unwrap();
    assert_eq!(w.positions().len(), 3);
    assert_eq!(w.velocities().len(), 3);
    let snap = w.snapshot();
    let mut copy = w.clone();
    w.step(200).unwrap();
    copy.step(7).unwrap();
    copy.restore(&snap).unwrap();
    copy.step(200).unwrap();
    assert_eq!(w.state_hash(), copy.state_hash());
    // The particle is a unit-frequency oscillator: x = cos t.
    let t = w.time();
    assert!((w.positions()[0] - t.cos()).abs() < 1e-3, "{} vs {}", w.positions()[0], t.cos());
}

fn l_norm(w: &World) -> f64 {
    norm(w.angular_momentum())
}

#[test]
fn the_velocity_form_without_gyroscopic_term_never_flips() {
    use physstep::rigid::body::AngularForm;
    let run = |form| {
        let mut w = racket("symplectic-euler", Rule::Splitting);
        w.set_angular_form(form);
        let l0 = l_norm(&w);
        let mut min_along = f64::INFINITY;
        for _ in 0..60 {
            w.step(120).unwrap();
            let omega = w.body_angular_velocity(0).unwrap();
            min_along = min_along.min(body_y(w.body_orientation(0).unwrap(), omega));
        }
        ((l_norm(&w) - l0).abs() / l0, min_along)
    };
    let (dl_momentum, along_momentum) = run(AngularForm::Momentum);
    let (_, along_velocity) = run(AngularForm::Velocity);
    let (dl_gyro, along_gyro) = run(AngularForm::VelocityGyroscopic);
    assert!(dl_momentum < 1e-13, "momentum form |L| error {dl_momentum:e}");
    // Without the gyroscopic term omega is frozen: the body turns steadily about it and the
    // spin about the intermediate axis never reverses (wrong physics that conserves |L|).
    assert!(along_velocity > 0.0, "the velocity form flipped ({along_velocity})");
    assert!(along_momentum < 0.0 && along_gyro < 0.0, "no flip: {along_momentum}, {along_gyro}");
    assert!(dl_gyro > 1e3 * dl_momentum.max(1e-16), "gyroscopic velocity form |L| error {dl_gyro:e}");
}

#[test]
fn switching_the_angular_form_keeps_the_state_and_rk4_agrees_in_both() {
    use physstep::rigid::body::AngularForm;
    let mut a = racket("rk4", Rule::Splitting);
    let mut b = racket("rk4", Rule::Splitting);
    b.set_angular_form(AngularForm::VelocityGyroscopic);
    let (la, lb) = (a.angular_momentum(), b.angular_momentum());
    for k in 0..3 {
        assert!((la[k] - lb[k]).abs() < 1e-12 * norm(la), "{la:?} vs {lb:?}");
    }
    a.step(1200).unwrap();
    b.step(1200).unwrap();
    let (qa, qb) = (a.body_orientation(0).unwrap(), b.body_orientation(0).unwrap());
    let dot: f64 = qa.iter().zip(qb).map(|(x, y)| x * y).sum();
    assert!(dot.abs() > 1.0 - 1e-8, "{qa:?} vs {qb:?}");
}

#[test]
fn a_spring_from_a_particle_to_a_body_point_conserves_total_momentum() {
    let mut w = world("velocity-verlet", 0.01);
    w.add_body(&BodyParams {
        shape: Shape::Box { half_extents: [0.5, 0.2, 0.1] },
        mass: Some(3.0),
        velocity: [0.1, 0.0, 0.0],
        ..BodyParams::default()
    })
    .unwrap();
    w.add_particle(&[2.0, 1.0, 0.0], &[0.0, -0.5, 0.3], 0.7, false).unwrap();
    w.add_body_spring(0, [0.5, 0.2, 0.0], Endpoint::Particle(0), 20.0, Some(1.0), 0.5).unwrap();
    let p0 = w.momentum();
    let e0 = w.energy().unwrap();
    w.step(2000).unwrap();
    let p = w.momentum();
    for k in 0..3 {
        assert!((p[k] - p0[k]).abs() < 1e-12, "momentum {p0:?} -> {p:?}");
    }
    // The body turned: the spring pulled off its centre.
    assert!(norm(w.body_angular_velocity(0).unwrap()) > 1e-3);
    // Damped: the energy went down, never up.
    assert!(w.energy().unwrap() < e0);
    let undamped = {
        let mut w = world("velocity-verlet", 0.001);
        w.add_body(&BodyParams {
            shape: Shape::Sphere { radius: 0.3 },
            mass: Some(2.0),
            ..BodyParams::default()
        })
        .unwrap();
        w.add_body_spring(0, [0.3, 0.0, 0.0], Endpoint::Anchor([1.0, 0.5, 0.0]), 10.0, Some(0.2), 0.0)
            .unwrap();
        let e0 = w.energy().unwrap();
        w.step(5000).unwrap();
        (w.energy().unwrap() - e0).abs() / e0
    };
    assert!(undamped < 1e-4, "energy error of an undamped body spring {undamped:e}");
}

#[test]
fn a_pinned_top_keeps_its_tip_and_precesses_at_the_gyroscopic_rate() {
    // A cylinder (r = 0.1, h = 0.4, m = 1) pinned at the centre of its bottom face, tilted
    // 0.3 rad from vertical, spun fast about its axis. Fast-top precession rate:
    // Omega = m g l / (I3 omega3), l = 0.2 the pin-to-centre distance.
    let (r, h, m, g, spin, tilt) = (0.1, 0.4, 1.0, 9.81, 200.0, 0.3f64);
    let mut w = world("velocity-verlet", 1e-4);
    w.add_force(Force::Gravity { g: [0.0, 0.0, -g] }).unwrap();
    let q = [(tilt / 2.0).cos(), (tilt / 2.0).sin(), 0.0, 0.0]; // about x
    let axis = [0.0, -tilt.sin(), tilt.cos()];
    w.add_body(&BodyParams {
        shape: Shape::Cylinder { radius: r, height: h },
        mass: Some(m),
        orientation: q,
        angular_velocity: [spin * axis[0], spin * axis[1], spin * axis[2]],
        pivot: Some([0.0, 0.0, -h / 2.0]),
        // The shape's origin where the pin ends up at the world's origin.
        position: [0.0, -tilt.sin() * h / 2.0, tilt.cos() * h / 2.0],
        ..BodyParams::default()
    })
    .unwrap();
    let e0 = w.energy().unwrap();
    let c0 = w.body_position(0).unwrap();
    let t_end = 0.5;
    w.step((t_end / 1e-4) as u64).unwrap();
    let c = w.body_position(0).unwrap();
    // The centre stays at l = 0.2 from the pin (the origin).
    assert!((norm(c) - h / 2.0).abs() < 1e-9, "|c| = {}", norm(c));
    let i3 = 0.5 * m * r * r;
    let omega_p = m * g * (h / 2.0) / (i3 * spin);
    let azimuth = |c: [f64; 3]| c[1].atan2(c[0]);
    let turned = (azimuth(c) - azimuth(c0)).rem_euclid(std::f64::consts::TAU);
    let expected = omega_p * t_end;
    assert!((turned - expected).abs() < 0.05 * expected, "precessed {turned}, fast-top theory {expected}");
    let de = (w.energy().unwrap() - e0).abs() / e0;
    assert!(de < 1e-6, "energy error {de:e}");
}

/// The complete elliptic integral of the first kind K(k), by the arithmetic-geometric mean.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    for _ in 0..60 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

#[test]
fn the_racket_flips_at_the_exact_period_for_144000_steps_with_l_exact_energy_bounded_q_unit() {
    // Euler's equations of the free body have Jacobi elliptic solutions: with moments
    // I1 < I2 < I3, energy E and |L| = L, when L^2 < 2 E I2 the body-frame angular velocity
    // has period T = 4 K(k) / lambda with
    //   lambda = sqrt((I2 - I1)(2 E I3 - L^2) / (I1 I2 I3)),
    //   k^2 = (I3 - I2)(L^2 - 2 E I1) / ((I2 - I1)(2 E I3 - L^2))
    // (Landau & Lifshitz, Mechanics, section 37; the other case swaps I1 and I3), and the
    // intermediate component changes sign twice per period.
    let mut scene = scenes::build("racket", &[], "symplectic-euler", 1.0 / 120.0).unwrap();
    let w = &mut scene.world;
    let [i1, i2, i3] = w.bodies().inertia(0);
    let s = w.body_spin(0).unwrap();
    let e = 0.5 * (i1 * s[0] * s[0] + i2 * s[1] * s[1] + i3 * s[2] * s[2]);
    let l2 = (i1 * s[0]).powi(2) + (i2 * s[1]).powi(2) + (i3 * s[2]).powi(2);
    let (lambda, k2) = if l2 < 2.0 * e * i2 {
        (
            ((i2 - i1) * (2.0 * e * i3 - l2) / (i1 * i2 * i3)).sqrt(),
            (i3 - i2) * (l2 - 2.0 * e * i1) / ((i2 - i1) * (2.0 * e * i3 - l2)),
        )
    } else {
        (
            ((i3 - i2) * (l2 - 2.0 * e * i1) / (i1 * i2 * i3)).sqrt(),
            (i2 - i1) * (2.0 * e * i3 - l2) / ((i3 - i2) * (l2 - 2.0 * e * i1)),
        )
    };
    let period = 4.0 * elliptic_k(k2.sqrt()) / lambda;
    let mut crossings = Vec::new();
    let mut last = s[1];
    let e0 = w.energy().unwrap();
    let (mut early, mut late) = (0.0f64, 0.0f64);
    for k in 0..144_000 {
        w.step(1).unwrap();
        let de = (w.energy().unwrap() - e0).abs() / e0;
        if k < 14_400 {
            early = early.max(de);
        } else if k >= 129_600 {
            late = late.max(de);
        }
        let now = w.body_spin(0).unwrap()[1];
        if now * last < 0.0 {
            // Linear interpolation of the crossing time within the step.
            crossings.push(w.time() - w.dt() * now / (now - last));
        }
        last = now;
    }
    assert!(crossings.len() >= 10, "{} flips in 1200 s", crossings.len());
    let half = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    // Measured at dt = 1/120: 21.95589 s against the exact 21.95578 s (5e-6).
    assert!((2.0 * half - period).abs() < 1e-4 * period, "measured period {}, exact {period}", 2.0 * half);
    let l = w.angular_momentum();
    assert!((norm(l) - l2.sqrt()).abs() < 1e-12 * l2.sqrt());
    // Bounded, not drifting: the last tenth of the run is no worse than the first.
    assert!(
        late < 1e-5 && late < 1.5 * early,
        "energy error {early:e} in the first tenth, {late:e} in the last"
    );
    let q = w.body_orientation(0).unwrap();
    let unit = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    assert!((unit - 1.0).abs() < 1e-12, "|q| = {unit} after 144,000 steps");
}

#[test]
fn angular_drag_slows_a_spinning_sphere_exponentially() {
    // A sphere (I = 2/5 m r^2 about every axis) with angular drag c: omega = omega0 exp(-c t / I).
    let (m, r, c) = (2.0, 0.5, 0.3);
    let i = 0.4 * m * r * r;
    let mut w = world("rk4", 0.01);
    w.add_body(&BodyParams {
        shape: Shape::Sphere { radius: r },
        mass: Some(m),
        angular_velocity: [1.0, -2.0, 0.5],
        angular_drag: c,
        ..BodyParams::default()
    })
    .unwrap();
    w.step(300).unwrap();
    let decay = (-c * w.time() / i).exp();
    let omega = w.body_angular_velocity(0).unwrap();
    for (got, start) in omega.iter().zip([1.0, -2.0, 0.5]) {
        assert!((got - start * decay).abs() < 1e-9, "{omega:?} vs decay {decay}");
    }
    let msg =
        w.add_body(&BodyParams { angular_drag: -1.0, ..BodyParams::default() }).unwrap_err().to_string();
    assert!(msg.contains("angular_drag"), "{msg}");
}

/// A zero-rest spring to an anchor written as a user force at a body point.
struct Tether {
    anchor: [f64; 3],
    k: f64,
}

impl physstep::forces::ForceGenerator for Tether {
    fn name(&self) -> &str {
        "tether"
    }
    fn add_forces(&self, _t: f64, x: &[f64], _v: &[f64], f: &mut [f64]) -> std::result::Result<(), String> {
        if x[0].abs() > 100.0 {
            return Err("the tether snapped".into());
        }
        for k in 0..3 {
            f[k] += self.k * (self.anchor[k] - x[k]);
        }
        Ok(())
    }
    fn velocity_dependent(&self) -> bool {
        false
    }
    fn potential(&self, x: &[f64]) -> Option<f64> {
        Some(0.5 * self.k * (0..3).map(|k| (x[k] - self.anchor[k]).powi(2)).sum::<f64>())
    }
}

#[test]
fn a_user_force_at_a_body_point_acts_like_the_same_built_in_spring() {
    let body = || BodyParams {
        shape: Shape::Box { half_extents: [0.3, 0.2, 0.1] },
        mass: Some(1.5),
        angular_velocity: [0.2, 0.0, 0.5],
        ..BodyParams::default()
    };
    let (anchor, point, k) = ([1.0, 0.5, 0.0], [0.3, 0.2, 0.1], 8.0);
    let mut a = world("velocity-verlet", 0.01);
    a.add_body(&body()).unwrap();
    a.add_body_spring(0, point, Endpoint::Anchor(anchor), k, Some(0.0), 0.0).unwrap();
    let mut b = world("velocity-verlet", 0.01);
    b.add_body(&body()).unwrap();
    b.add_body_force(0, point, std::sync::Arc::new(Tether { anchor, k })).unwrap();
    assert!((a.energy().unwrap() - b.energy().unwrap()).abs() < 1e-12);
    a.step(500).unwrap();
    b.step(500).unwrap();
    for (pa, pb) in a.body_position(0).unwrap().iter().zip(b.body_position(0).unwrap()) {
        assert!((pa - pb).abs() < 1e-12, "{pa} vs {pb}");
    }
    assert!((a.energy().unwrap() - b.energy().unwrap()).abs() < 1e-12);
    // A failing force fails the step, names itself, and leaves the world as it was.
    let mut c = world("rk4", 0.01);
    c.add_body(&BodyParams { position: [150.0, 0.0, 0.0], ..body() }).unwrap();
    c.add_body_force(0, point, std::sync::Arc::new(Tether { anchor, k })).unwrap();
    let before = (c.state_hash(), c.body_position(0).unwrap());
    let err = c.step(1).unwrap_err();
    assert!(matches!(&err, Error::Force { name, .. } if name == "tether"), "{err}");
    assert!(err.to_string().contains("snapped"), "{err}");
    assert_eq!((c.state_hash(), c.body_position(0).unwrap()), before);
}

#[test]
fn catto_implicit_gyroscopic_form_is_stable_where_the_explicit_one_diverges_and_dissipates() {
    use physstep::rigid::body::AngularForm;
    let mut explicit = racket("symplectic-euler", Rule::Splitting);
    explicit.set_angular_form(AngularForm::VelocityGyroscopic);
    let err = explicit.step(144_000).unwrap_err();
    assert!(matches!(err, Error::Diverged { body: Some(0), .. }), "{err}");
    // The call went back to its start, replayed the good steps and stopped before the bad one:
    // the world is where single steps leave it.
    let Error::Diverged { step, .. } = err else { unreachable!() };
    assert_eq!(explicit.steps(), step);
    let mut single = racket("symplectic-euler", Rule::Splitting);
    single.set_angular_form(AngularForm::VelocityGyroscopic);
    single.step(step).unwrap();
    assert_eq!(single.state_hash(), explicit.state_hash());
    let mut implicit = racket("symplectic-euler", Rule::Splitting);
    implicit.set_angular_form(AngularForm::VelocityImplicit);
    let e0 = implicit.energy().unwrap();
    let mut last = e0;
    for _ in 0..144 {
        implicit.step(1000).unwrap();
        let e = implicit.energy().unwrap();
        // Dissipative: the energy never grows (beyond rounding) from one sample to the next.
        assert!(e <= last * (1.0 + 1e-12), "energy rose from {last} to {e}");
        last = e;
    }
    assert!(last < 0.5 * e0, "kept {} of the energy", last / e0);
}

#[test]
fn a_call_of_many_steps_leaves_the_same_state_and_derivative_as_single_steps() {
    // A call of several steps leaves the bodies' rates (q') out of the derivative until
    // asked: a flow method stepping afterwards (RK4 reads the whole derivative as its first
    // stage) must see exactly what it sees after single steps. With a particle beside the body.
    let build = || {
        let mut w = racket("symplectic-euler", Rule::Splitting);
        w.add_particle(&[1.0, 2.0, 3.0], &[0.5, 0.0, -0.5], 2.0, false).unwrap();
        w.add_force(Force::Gravity { g: [0.0, 0.0, -9.81] }).unwrap();
        w
    };
    let forms = [AngularForm::Momentum, AngularForm::VelocityImplicit, AngularForm::VelocityGyroscopic];
    let methods =
        ["symplectic-euler", "symplectic-euler-alternating", "velocity-verlet", "leapfrog", "yoshida4"];
    for (method, form) in methods.into_iter().flat_map(|m| forms.map(|f| (m, f))) {
        let (mut a, mut b) = (build(), build());
        for w in [&mut a, &mut b] {
            w.set_method(method).unwrap();
            w.set_angular_form(form);
        }
        a.step(50).unwrap();
        for _ in 0..50 {
            b.step(1).unwrap();
        }
        assert_eq!(a.state_hash(), b.state_hash(), "{method} {form:?}");
        for w in [&mut a, &mut b] {
            w.set_method("rk4").unwrap();
            w.step(10).unwrap();
        }
        assert_eq!(a.state_hash(), b.state_hash(), "{method} {form:?} then rk4");
        assert_eq!(a.evals(), b.evals(), "{method}: evaluations counted alike");
        assert_eq!(a.accelerations().unwrap(), b.accelerations().unwrap());
    }
}
