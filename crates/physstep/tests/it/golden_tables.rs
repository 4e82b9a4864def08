//! The notes' spring tables (tests/golden/*.csv, copied from the course material) reproduced
//! row for row at their printed precision.

use super::common::round_half_away;
use physstep::prelude::*;

fn check(file: &str, method: &str, dt: f64) {
    let text =
        std::fs::read_to_string(format!("{}/tests/golden/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let mut scene = scenes::build("spring", &[], method, dt).unwrap();
    let w = &mut scene.world;
    let mut rows = 0;
    for (n, line) in text.lines().skip(1).enumerate() {
        let cols: Vec<&str> = line.split(',').collect();
        if n > 0 {
            w.step(1).unwrap();
        }
        let t: f64 = cols[0].parse().unwrap();
        assert_eq!(n as f64 * dt, t, "{file} row {n}: time");
        let (x, v, a) = (w.positions()[0], w.velocities()[0], w.accelerations().unwrap()[0]);
        let norm = |s: &str| if s == "-0.0" { "0.0".to_string() } else { s.to_string() };
        let got = [round_half_away(x, 1), round_half_away(v, 1), round_half_away(a, 1)].map(|s| norm(&s));
        let want = [cols[1], cols[2], cols[3]].map(norm);
        assert_eq!(got, want, "{file} row {n} (t = {t}): {method}");
        rows += 1;
    }
    assert!(rows > 5, "{file} has rows");
}

#[test]
fn explicit_euler_dt1() {
    check("spring_euler_dt1.csv", "explicit-euler", 1.0);
}

#[test]
fn explicit_euler_dt_half() {
    check("spring_euler_dt0.5.csv", "explicit-euler", 0.5);
}

#[test]
fn explicit_euler_dt_quarter() {
    check("spring_euler_dt0.25.csv", "explicit-euler", 0.25);
}

#[test]
fn symplectic_euler_dt1() {
    check("spring_symplectic_dt1.csv", "symplectic-euler", 1.0);
}

#[test]
fn verlet_dt1() {
    check("spring_verlet_dt1.csv", "verlet", 1.0);
}

#[test]
fn rounding_is_half_away_from_zero_on_the_exact_double() {
    assert_eq!(round_half_away(16.25, 1), "16.3");
    assert_eq!(round_half_away(-8.75, 1), "-8.8");
    assert_eq!(round_half_away(0.15, 1), "0.1"); // 0.1499999999999999944...
    assert_eq!(round_half_away(9.96, 1), "10.0");
    assert_eq!(round_half_away(-0.04, 1), "0.0");
}
