//! Solids that land, slide, stack and rest (the contact solver's closed forms and targets).

use glam::{DVec2, DVec3};
use physstep::contact::{Kind, Plane, Shape, SolidParams, Solids, Space3};

const G: f64 = 9.81;

fn ground2(s: &mut Solids<Plane>) -> usize {
    let mut p = SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0]);
    p.kind = Kind::Static;
    s.add(p).unwrap()
}

fn square(at: [f64; 2], half: f64) -> SolidParams {
    SolidParams::new(Shape::Box { half: vec![half, half] }, &at)
}

#[test]
fn a_box_dropped_on_the_ground_comes_to_rest_without_jitter() {
    let mut s = Solids::<Plane>::new();
    ground2(&mut s);
    let b = s.add(square([0.0, 2.0], 0.5)).unwrap();
    let dt = 1.0 / 60.0;
    let mut landing_energy = 0.0_f64;
    let mut landed_at = None;
    for k in 0..600 {
        s.step(dt, DVec2::new(0.0, -G)).unwrap();
        landing_energy = landing_energy.max(s.kinetic_energy());
        if landed_at.is_none() && !s.contacts().iter().all(|c| c.depth < 0.0) {
            landed_at = Some(k);
        }
    }
    let landed = landed_at.expect("the box lands");
    assert!(landed < 60, "landed at step {landed}");
    // 2 s after landing and later: at rest, barely in the ground.
    let e = s.kinetic_energy();
    assert!(e < 1e-8 * landing_energy, "kinetic energy {e} of {landing_energy}");
    assert!(s.max_penetration() < 0.005 * 1.0, "penetration {}", s.max_penetration());
    let y = s.positions()[2 * b + 1];
    assert!((y - 0.5).abs() < 0.005, "resting height {y}");
    assert!(s.orientations()[b].abs() < 1e-6, "it landed flat and stays flat: {}", s.orientations()[b]);
}

fn ramp(angle: f64, mu: f64, seconds: f64) -> (f64, f64) {
    // A long static plank tilted by `angle` and a box on it, both with friction `mu`.
    let mut s = Solids::<Plane>::new();
    let mut plank = SolidParams::new(Shape::Box { half: vec![100.0, 0.5] }, &[0.0, 0.0]);
    plank.kind = Kind::Static;
    plank.orientation = vec![angle];
    plank.friction = mu;
    s.add(plank).unwrap();
    // On the plank's top face, at rest.
    let (c, sn) = (angle.cos(), angle.sin());
    let up = 0.5 + 0.25;
    let mut b = SolidParams::new(Shape::Box { half: vec![0.25, 0.25] }, &[-sn * up, c * up]);
    b.orientation = vec![angle];
    b.friction = mu;
    s.add(b).unwrap();
    let dt = 1.0 / 60.0;
    let steps = (seconds / dt).round() as usize;
    let along = |s: &Solids<Plane>| {
        let p = s.positions();
        p[2] * c + p[3] * sn
    };
    let x0 = along(&s);
    for _ in 0..steps {
        s.step(dt, DVec2::new(0.0, -G)).unwrap();
    }
    let v = s.velocities();
    (along(&s) - x0, v[2] * c + v[3] * sn)
}

#[test]
fn on_a_ramp_a_box_sticks_above_the_friction_angle_and_slides_at_g_sin_minus_mu_cos_below() {
    let angle = 0.5_f64; // tan = 0.546
    let (moved, _) = ramp(angle, 0.6, 5.0);
    assert!(moved.abs() < 1e-3, "stuck box moved {moved}");
    let mu = 0.3;
    let (_, v) = ramp(angle, mu, 2.0);
    let a = v / 2.0;
    let exact = -G * (angle.sin() - mu * angle.cos());
    assert!(((a - exact) / exact).abs() < 0.01, "acceleration {a} against {exact}");
}

fn pyramid(rows: usize) -> Solids<Plane> {
    let mut s = Solids::<Plane>::new();
    ground2(&mut s);
    let h = 0.5;
    for row in 0..rows {
        let n = rows - row;
        for i in 0..n {
            let x = (i as f64 - (n - 1) as f64 / 2.0) * (2.0 * h + 0.01);
            let y = h + row as f64 * 2.0 * h;
            s.add(square([x, y], h)).unwrap();
        }
    }
    s
}

#[test]
fn a_pyramid_of_twenty_rows_stands_for_ten_seconds() {
    let mut s = pyramid(20);
    let top = s.len() - 1;
    let p0 = s.positions();
    let mut deepest = 0.0_f64;
    for _ in 0..600 {
        s.step(1.0 / 60.0, DVec2::new(0.0, -G)).unwrap();
        deepest = deepest.max(s.max_penetration());
    }
    let p = s.positions();
    let drift = ((p[2 * top] - p0[2 * top]).powi(2) + (p[2 * top + 1] - p0[2 * top + 1]).powi(2)).sqrt();
    assert!(drift < 0.01, "top box moved {drift} m");
    assert!(deepest < 0.01, "penetration {deepest} m");
}

#[test]
fn a_cube_dropped_on_a_plane_comes_to_rest_in_3d() {
    let mut s = Solids::<Space3>::new();
    let mut ground = SolidParams::new(Shape::Plane { normal: vec![0.0, 1.0, 0.0] }, &[0.0, 0.0, 0.0]);
    ground.kind = Kind::Static;
    s.add(ground).unwrap();
    let mut cube = SolidParams::new(Shape::Box { half: vec![0.5, 0.5, 0.5] }, &[0.0, 2.0, 0.0]);
    cube.orientation = vec![1.0, 0.1, 0.2, 0.05];
    s.add(cube).unwrap();
    let mut peak = 0.0_f64;
    for _ in 0..600 {
        s.step(1.0 / 60.0, DVec3::new(0.0, -G, 0.0)).unwrap();
        peak = peak.max(s.kinetic_energy());
    }
    assert!(s.kinetic_energy() < 1e-8 * peak, "kinetic energy {} of {peak}", s.kinetic_energy());
    assert!(s.max_penetration() < 0.005, "penetration {}", s.max_penetration());
    // It rests on a face: the centre half a side above the plane.
    assert!((s.positions()[4] - 0.5).abs() < 0.005, "height {}", s.positions()[4]);
}
