//! The Kepler scene's exact solution: Kepler's equation solved for every eccentricity and
//! time, and the exact orbit keeping its energy and angular momentum over many periods.

use physstep::prelude::*;
use physstep::scenes::eccentric_anomaly;

/// Kepler's equation by plain bisection on the unreduced mean anomaly: slow, simple, and
/// independent of the scene's solver.
fn kepler_by_bisection(e: f64, m: f64) -> f64 {
    let (mut lo, mut hi) = (m - 1.0, m + 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid - e * mid.sin() - m > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn keplers_equation_is_solved_for_every_e_and_t() {
    for e in [0.0, 0.3, 0.6, 0.8, 0.9, 0.95, 0.99] {
        for k in 0..=400 {
            let t = 0.37 * f64::from(k);
            let ours = eccentric_anomaly(e, t);
            let theirs = kepler_by_bisection(e, t);
            // Compare on the circle (ours is reduced to [-pi, pi]).
            let d = ((ours.cos() - theirs.cos()).powi(2) + (ours.sin() - theirs.sin()).powi(2)).sqrt();
            assert!(d < 1e-12, "e = {e}, t = {t}: {ours} vs {theirs}");
        }
    }
}

#[test]
fn the_exact_kepler_orbit_keeps_its_invariants_after_many_periods() {
    // Energy -1/2 (GM = a = 1) and angular momentum sqrt(1 - e^2) at every time: the old
    // solver broke them after the first period for e >= 0.8.
    for e in [0.8, 0.9, 0.99] {
        let s = scenes::build("kepler", &[("e", e)], "rk4", 0.01).unwrap();
        for k in 0..200 {
            let t = 0.731 * f64::from(k);
            let (x, v) = s.exact(t).unwrap();
            let r = x[0].hypot(x[1]);
            let energy = 0.5 * (v[0] * v[0] + v[1] * v[1]) - 1.0 / r;
            let l = x[0] * v[1] - x[1] * v[0];
            assert!((energy + 0.5).abs() < 1e-9, "e = {e}, t = {t}: energy {energy}");
            assert!((l - (1.0 - e * e).sqrt()).abs() < 1e-9, "e = {e}, t = {t}: L {l}");
        }
    }
}
