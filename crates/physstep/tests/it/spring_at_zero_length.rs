//! A damped spring of rest length zero: its damping acts at zero length too (the force is
//! -k d - c w across d = 0), so a run from x0 = 0 keeps each method's order.

use super::common;
use physstep::prelude::*;

#[test]
fn a_zero_length_spring_keeps_its_damping_at_zero_length() {
    // Spring scene (rest length 0): at x = 0 with v = 1 the force is -c v, not 0.
    let mut s = scenes::build("spring", &[("c", 1.0), ("x0", 0.0), ("v0", 1.0)], "rk4", 0.1).unwrap();
    assert_eq!(s.world.accelerations().unwrap(), &[-0.1]);
    // In 2D the linear form F = -k d - c w holds in every direction, also across d = 0.
    let mut w = World::new(WorldParams { dim: 2, ..Default::default() }).unwrap();
    w.add_particle(&[0.0, 0.0], &[1.0, -2.0], 2.0, false).unwrap();
    w.add_force(Force::Spring {
        i: 0,
        j: Endpoint::Anchor([0.0; 3]),
        stiffness: 3.0,
        rest_length: 0.0,
        damping: 0.5,
    })
    .unwrap();
    assert_eq!(w.accelerations().unwrap(), &[-0.25, 0.5]);
}

#[test]
fn convergence_from_x0_zero_keeps_each_methods_order() {
    // From x0 = 0 every method used to drop to order 1 (the damping vanished at the first
    // evaluation). Velocity Verlet and RK4 keep 2 and 4.
    for (method, order) in [("velocity-verlet", 2.0), ("rk4", 4.0), ("heun", 2.0)] {
        let err = |dt: f64| {
            let mut s = scenes::build("spring", &[("c", 1.0), ("x0", 0.0), ("v0", 1.0)], method, dt).unwrap();
            // The largest error over the run: a final error can cross zero.
            let mut worst = 0.0f64;
            for _ in 0..(3.0 / dt).round() as u64 {
                s.world.step(1).unwrap();
                worst = worst.max((s.world.positions()[0] - s.exact(s.world.time()).unwrap().0[0]).abs());
            }
            worst
        };
        let dts = [0.05, 0.025, 0.0125];
        let errs: Vec<f64> = dts.iter().map(|d| err(*d)).collect();
        let p = common::slope(&dts, &errs);
        assert!((p - order).abs() < 0.15, "{method}: order {p}");
    }
}
