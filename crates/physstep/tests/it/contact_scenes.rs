//! The rest of Solver2D's contact scenes, built as the command line builds them: each does
//! what it is there to show (stands, falls in order, recovers, jams without exploding,
//! spins down at Coulomb's rate), and its size parameters are refused before any work.

use physstep::prelude::*;

const G: f64 = 9.81;

fn build(name: &str, params: &[(&str, f64)]) -> World {
    let spec = scenes::spec(name).unwrap();
    scenes::build(name, params, "symplectic-euler", spec.dt).unwrap().world
}

fn point(w: &World, i: usize) -> Vec<f64> {
    let d = w.dim();
    w.solid_positions()[i * d..(i + 1) * d].to_vec()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt()
}

/// The solid whose origin is highest.
fn topmost(w: &World) -> usize {
    let (d, p) = (w.dim(), w.solid_positions());
    (0..w.solid_count()).max_by(|&a, &b| p[a * d + 1].total_cmp(&p[b * d + 1])).unwrap()
}

/// Steps `n` times; the deepest penetration seen.
fn run(w: &mut World, n: usize) -> f64 {
    let mut deepest = 0.0_f64;
    for _ in 0..n {
        w.step(1).unwrap();
        deepest = deepest.max(w.max_penetration());
    }
    deepest
}

#[test]
fn the_card_house_stands_for_ten_seconds() {
    let mut w = build("card-house", &[]);
    assert_eq!(w.solid_count(), 1 + 40);
    let s = w.contact_settings();
    assert_eq!((s.substeps, s.iterations), (16, 2));
    // Box2D's cards start 2 mm into each other and the ground and 6 mm apart at the tops of
    // a pair: the first 2 s the house settles (its top card 3.3 cm down) and then stands.
    run(&mut w, 120);
    let top = topmost(&w);
    let (at, heights) = (point(&w, top), w.solid_positions());
    let deepest = run(&mut w, 480);
    let drift = distance(&point(&w, top), &at);
    assert!(drift < 0.01, "the top card moved {drift} m from 2 s to 10 s");
    // 1% of a card's 40 cm (all of its 2 mm thickness: the cards rest crossed at their tops).
    assert!(deepest < 0.004, "penetration {deepest} m");
    let p = w.solid_positions();
    for i in 1..w.solid_count() {
        assert!(p[2 * i + 1] > heights[2 * i + 1] - 0.01, "card {i} fell to {}", p[2 * i + 1]);
    }
}

#[test]
fn at_a_mass_ratio_of_100_the_light_boxes_hold_the_heavy_one() {
    let mut w = build("mass-ratio", &[]);
    assert_eq!(w.solid_count(), 4);
    let deepest = run(&mut w, 60); // it starts 1 cm above the small boxes and lands
    let at = point(&w, 3);
    let deepest = deepest.max(run(&mut w, 540));
    let drift = distance(&point(&w, 3), &at);
    assert!(drift < 0.01, "the big box moved {drift} m from 1 s to 10 s");
    assert!(deepest < 0.01, "penetration {deepest} m: 1% of a small box is 1 cm");
    assert!(w.solid_orientations()[3].abs() < 1e-3, "tilted {}", w.solid_orientations()[3]);
    assert!((point(&w, 3)[1] - 11.0).abs() < 0.01, "the big box sank to {}", point(&w, 3)[1]);
    // The ratio is what presses: 400 (Solver2D's) sinks the small boxes deeper.
    let mut heavy = build("mass-ratio", &[("ratio", 400.0)]);
    assert!(run(&mut heavy, 120) > 2.0 * deepest);
}

#[test]
fn the_arch_stands_by_friction_and_falls_without_it() {
    let mut w = build("arch", &[]);
    assert_eq!(w.solid_count(), 1 + 17 + 4);
    let (top, start) = (topmost(&w), w.solid_positions());
    let deepest = run(&mut w, 60); // the stones settle into each other (7-8 cm at the top)
    let at = point(&w, top);
    assert!(distance(&at, &start[2 * top..2 * top + 2]) < 0.1, "settled {:?}", at);
    let deepest = deepest.max(run(&mut w, 540));
    let drift = distance(&point(&w, top), &at);
    assert!(drift < 0.01, "the top box moved {drift} m from 1 s to 10 s");
    assert!(deepest < 0.01, "penetration {deepest} m");
    let mut slippery = build("arch", &[("friction", 0.0)]);
    run(&mut slippery, 300);
    let y = point(&slippery, top)[1];
    assert!(y < start[2 * top + 1] - 1.0, "without friction the arch stands: top at {y}");
}

#[test]
fn the_dominos_fall_one_after_another_to_the_last() {
    let mut w = build("domino", &[]);
    let n = w.solid_count() - 1;
    assert_eq!(n, 15);
    let mut fell = vec![None; n];
    let mut deepest = 0.0_f64;
    for k in 0..600 {
        w.step(1).unwrap();
        deepest = deepest.max(w.max_penetration());
        for (i, a) in w.solid_orientations()[1..].iter().enumerate() {
            if fell[i].is_none() && a.abs() > 0.5 {
                fell[i] = Some(k);
            }
        }
    }
    let fell: Vec<usize> = fell.iter().map(|f| f.expect("every domino falls")).collect();
    assert!(fell.windows(2).all(|p| p[0] < p[1]), "in order: {fell:?}");
    let last = w.solid_orientations()[n];
    assert!(last.abs() > 1.0, "the last domino is at {last} rad");
    assert!(deepest < 0.02, "penetration {deepest} m");
}

#[test]
fn confined_circles_push_apart_and_jam_without_exploding() {
    // Solver2D's 25 x 25 circles of 0.5 m hold 491 m^2 in a box of 390: they cannot all
    // come apart, and the first step pushes along whole rows of overlaps.
    let mut w = build("confined", &[]);
    assert_eq!(w.solid_count(), 4 + 625);
    let mut peak = 0.0_f64;
    let mut deepest = 0.0_f64;
    for k in 0..600 {
        w.step(1).unwrap();
        peak = peak.max(w.solid_kinetic_energy());
        deepest = deepest.max(w.max_penetration());
        let p = w.solid_positions();
        let inside = p[8..].chunks(2).all(|c| (-10.0..=10.0).contains(&c[0]) && (0.5..=20.0).contains(&c[1]));
        assert!(inside, "a circle left the box at step {k}");
        if k >= 60 {
            let v = w.solid_velocities();
            let fastest = v.chunks(2).map(|c| c[0].hypot(c[1])).fold(0.0, f64::max);
            assert!(fastest < 3.0, "{fastest} m/s at step {k}, past the push speed");
        }
    }
    let e = w.solid_kinetic_energy();
    assert!(e < 1e-4 * peak, "kinetic energy {e} J of a {peak} J peak");
    assert!(deepest < 0.8, "penetration {deepest} m");
    // 20 x 20 have room: they come apart to within 6 cm and rest (5.4 cm measured; 4.9 with
    // the pairs in pair order, before the passes took them by colour).
    let mut roomy = build("confined", &[("n", 20.0)]);
    run(&mut roomy, 600);
    assert!(roomy.max_penetration() < 0.06, "penetration {} m", roomy.max_penetration());
    assert!(roomy.solid_kinetic_energy() < 1e-9, "{}", roomy.solid_kinetic_energy());
}

#[test]
fn overlapping_boxes_separate_no_faster_than_the_push_speed_and_rest() {
    let mut w = build("overlap-recovery", &[]);
    assert_eq!(w.solid_count(), 1 + 10);
    assert!((w.max_penetration() - 0.0).abs() < 1e-12); // no step yet
    let push = w.contact_settings().push_speed;
    let mut separated = None;
    let mut fastest_apart = 0.0_f64;
    let mut history = Vec::new();
    for k in 0..300 {
        w.step(1).unwrap();
        if separated.is_none() && w.max_penetration() < 0.005 {
            separated = Some(k);
        }
        // How fast each touching pair moves apart along its normal, at the contact point.
        let (c, x, v, om) =
            (w.contacts(), w.solid_positions(), w.solid_velocities(), w.solid_angular_velocities());
        for (m, [a, b]) in c.pairs.iter().enumerate() {
            if c.depths[m] < 0.0 {
                continue; // apart already: pushed by other contacts, not this one
            }
            let at = |i: usize| {
                let r = [c.points[2 * m] - x[2 * i], c.points[2 * m + 1] - x[2 * i + 1]];
                [v[2 * i] - om[i] * r[1], v[2 * i + 1] + om[i] * r[0]]
            };
            let (va, vb) = (at(*a), at(*b));
            let apart = (vb[0] - va[0]) * c.normals[2 * m] + (vb[1] - va[1]) * c.normals[2 * m + 1];
            fastest_apart = fastest_apart.max(apart);
        }
        history.push(w.solid_positions());
    }
    let k = separated.expect("the boxes separate");
    assert!(k < 20, "separated after {k} steps"); // 16 here: 0.27 s
                                                  // Read at the step's end, after 8 substeps of gravity (0.16 m/s) and the turns the pushes
                                                  // give. The push speed bounds what one contact's bias asks; a box pushed from both sides,
                                                  // or carried by its neighbour's push, moves apart from a third faster: 5.6 m/s here at a
                                                  // push speed of 3 with the pairs solved by colour (3.3 in pair order, where each solid's
                                                  // pairs came one after the other).
    assert!(fastest_apart < 2.0 * push, "a pair moved apart at {fastest_apart} m/s (push speed {push})");
    let e = w.solid_kinetic_energy();
    assert!(e < 1e-4, "kinetic energy {e} J at 5 s");
    let still = distance(&history[299], &history[239]);
    assert!(still < 1e-3, "moved {still} m in the last second");
    assert!(w.max_penetration() < 0.005, "penetration {} m", w.max_penetration());
}

#[test]
fn the_top_spins_on_its_foot_and_slows_at_coulombs_rate() {
    let (spin, foot, mu) = (60.0, 0.02, 0.3);
    let mut w = build("top-on-floor", &[]);
    assert_eq!(w.solid_count(), 2);
    // The top's mass from its hull (parry's, as the solid's); its inertia about the axis from
    // the energy of the pure spin it starts with: the friction at the foot's four corners,
    // mu m g / 4 each at foot sqrt 2 from the axis, slows it at mu m g r / I.
    let mut pts = vec![[-foot, 0.0, -foot], [foot, 0.0, -foot], [foot, 0.0, foot], [-foot, 0.0, foot]];
    for (r, y) in [(0.1_f64, 0.05), (0.06, 0.08)] {
        for k in 0..16 {
            let a = std::f64::consts::TAU * f64::from(k) / 16.0;
            pts.push([r * a.cos(), y, r * a.sin()]);
        }
    }
    let pts: Vec<glam::DVec3> = pts.iter().map(|p| glam::DVec3::from_array(*p)).collect();
    let mass = parry3d_f64::shape::SharedShape::convex_hull(&pts).unwrap().mass_properties(1000.0).mass();
    let inertia = 2.0 * w.solid_kinetic_energy() / (spin * spin);
    let rate = mu * mass * G * foot * std::f64::consts::SQRT_2 / inertia;
    let stop = spin / rate;
    let start = point(&w, 1);
    let mut deepest = 0.0_f64;
    let mut samples = Vec::new();
    for k in 1..=600 {
        w.step(1).unwrap();
        deepest = deepest.max(w.max_penetration());
        let q = &w.solid_orientations()[4..8];
        // The axis (the top's y) stays vertical: its y component 1 - 2 (x^2 + z^2).
        let up = 1.0 - 2.0 * (q[1] * q[1] + q[3] * q[3]);
        assert!(up > 1.0 - 1e-6, "tilted at step {k}: axis y = {up}");
        samples.push((k as f64 / 60.0, w.solid_angular_velocities()[4]));
    }
    for &(t, wy) in samples.iter().filter(|(t, _)| *t < 0.9 * stop) {
        let want = spin - rate * t;
        assert!((wy - want).abs() < 0.03 * spin, "spin {wy} at {t} s, Coulomb's {want}");
    }
    let late = samples.iter().find(|(t, _)| *t > 1.1 * stop).unwrap();
    assert!(late.1.abs() < 1e-3, "still spinning at {} rad/s at {} s (stops at {stop} s)", late.1, late.0);
    assert!(deepest < 0.002, "penetration {deepest} m: 1% of its 20 cm");
    assert!(distance(&point(&w, 1), &start) < 1e-3, "it wandered to {:?}", point(&w, 1));
}

#[test]
fn contact_scene_sizes_are_refused_before_any_work() {
    let refused = |name: &str, p: (&str, f64), want: &str| {
        let e = scenes::build(name, &[p], "symplectic-euler", 1.0 / 60.0).unwrap_err().to_string();
        assert_eq!(e, want, "{name} {p:?}");
    };
    refused("card-house", ("levels", 101.0), "invalid levels = 101: must be at most 100");
    refused("mass-ratio", ("ratio", 1e5), "invalid ratio = 100000: must be from 0.001 to 10000");
    refused("mass-ratio", ("ratio", 1e-4), "invalid ratio = 0.0001: must be from 0.001 to 10000");
    refused(
        "confined",
        ("n", 31.0),
        "invalid n = 31: must be at most 30 (900 circles of 0.5 m in a 20 m box)",
    );
    refused("domino", ("n", 200_000.0), "invalid n = 200000: must be at most 100000 solids (1 a unit)");
    refused("overlap-recovery", ("overlap", 0.6), "invalid overlap = 0.6: must be from 0 to 0.5 of a side");
    refused("overlap-recovery", ("base", 1000.0), "invalid base = 1000: must be at most 100000 boxes in all");
    refused("top-on-floor", ("foot", 0.1), "invalid foot = 0.1: must be from 0 to 0.05 m");
    refused("top-on-floor", ("tilt", 2.0), "invalid tilt = 2: must be from 0 to 1.2 rad");
    refused("top-on-floor", ("spin", -2000.0), "invalid spin = -2000: must be at most 1000 rad/s either way");
    // Zero and negative sizes are the parameter rules' (as for every scene).
    refused("mass-ratio", ("ratio", 0.0), "invalid ratio = 0: must be a number in [1e-12, 1e12]");
    refused("arch", ("friction", -0.1), "invalid friction = -0.1: must be 0 or a number in [1e-12, 1e12]");
    refused("confined", ("n", 0.0), "invalid n = 0: must be a whole number from 1 to 1000000");
}
