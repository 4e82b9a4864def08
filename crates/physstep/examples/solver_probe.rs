//! Each contact solver on the box drop, the ramp and the 20-row pyramid (release numbers).
use glam::DVec2;
use physstep::contact::{Kind, Plane, Shape, SolidParams, Solids, SOLVERS};
const G: f64 = 9.81;
fn ground2(s: &mut Solids<Plane>) {
    let mut p = SolidParams::new(Shape::Box { half: vec![50.0, 1.0] }, &[0.0, -1.0]);
    p.kind = Kind::Static;
    s.add(p).unwrap();
}
fn square(at: [f64; 2], half: f64) -> SolidParams {
    SolidParams::new(Shape::Box { half: vec![half, half] }, &at)
}
fn main() {
    let rows: usize = std::env::args().nth(1).map_or(20, |a| a.parse().unwrap());
    for info in SOLVERS {
        let solver = info.name;
        // box
        let mut s = Solids::<Plane>::new();
        s.settings.set_solver(solver).unwrap();
        ground2(&mut s);
        let b = s.add(square([0.0, 2.0], 0.5)).unwrap();
        let mut peak = 0.0_f64;
        for _ in 0..600 {
            s.step(1.0 / 60.0, DVec2::new(0.0, -G)).unwrap();
            peak = peak.max(s.kinetic_energy());
        }
        println!(
            "{solver:12} box: ke {:.2e} of peak, pen {:.2e}, y {:.5}, angle {:.1e}",
            s.kinetic_energy() / peak,
            s.max_penetration(),
            s.positions()[2 * b + 1],
            s.orientations()[b]
        );
        // ramp
        for (mu, secs) in [(0.6, 1.0), (0.6, 5.0), (0.8, 5.0), (0.3, 2.0)] {
            let angle = 0.5_f64;
            let mut s = Solids::<Plane>::new();
            s.settings.set_solver(solver).unwrap();
            let mut plank = SolidParams::new(Shape::Box { half: vec![100.0, 0.5] }, &[0.0, 0.0]);
            plank.kind = Kind::Static;
            plank.orientation = vec![angle];
            plank.friction = mu;
            s.add(plank).unwrap();
            let (c, sn) = (angle.cos(), angle.sin());
            let mut bx = SolidParams::new(Shape::Box { half: vec![0.25, 0.25] }, &[-sn * 0.75, c * 0.75]);
            bx.orientation = vec![angle];
            bx.friction = mu;
            s.add(bx).unwrap();
            let x0 = s.positions()[2] * c + s.positions()[3] * sn;
            let steps = (secs * 60.0_f64).round() as usize;
            for _ in 0..steps {
                s.step(1.0 / 60.0, DVec2::new(0.0, -G)).unwrap();
            }
            let v = s.velocities();
            let moved = s.positions()[2] * c + s.positions()[3] * sn - x0;
            let a = (v[2] * c + v[3] * sn) / secs;
            let exact = -G * (angle.sin() - mu * angle.cos());
            println!("{solver:12} ramp mu {mu}: moved {moved:.2e}, a err {:.2e}", (a - exact) / exact);
        }
        // pyramid
        let mut s = Solids::<Plane>::new();
        s.settings.set_solver(solver).unwrap();
        ground2(&mut s);
        for row in 0..rows {
            let n = rows - row;
            for i in 0..n {
                let x = (i as f64 - (n - 1) as f64 / 2.0) * 1.01;
                s.add(square([x, 0.5 + row as f64], 0.5)).unwrap();
            }
        }
        let top = s.len() - 1;
        let p0 = s.positions();
        let mut deep = 0.0_f64;
        let t = std::time::Instant::now();
        let mut err = None;
        for k in 0..600 {
            if let Err(e) = s.step(1.0 / 60.0, DVec2::new(0.0, -G)) {
                err = Some((k, e));
                break;
            }
            deep = deep.max(s.max_penetration());
        }
        let ms = t.elapsed().as_secs_f64() * 1e3 / 600.0;
        let p = s.positions();
        let drift = ((p[2 * top] - p0[2 * top]).powi(2) + (p[2 * top + 1] - p0[2 * top + 1]).powi(2)).sqrt();
        println!(
            "{solver:12} pyramid {rows}: drift {drift:.4} m, deepest {deep:.4} m, {ms:.2} ms/step {err:?}"
        );
    }
}
