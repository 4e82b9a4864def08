//! Helpers shared by the integration tests.
#![allow(dead_code)]

use physstep::prelude::*;

/// `value` rounded to `places` decimals, half away from zero, on the exact double (the
/// notes' tables are printed this way).
pub fn round_half_away(value: f64, places: usize) -> String {
    // 80 fractional digits print every double in the tables' range exactly.
    let s = format!("{:.80}", value.abs());
    let (int, frac) = s.split_once('.').unwrap();
    let mut digits: Vec<u8> = int.bytes().chain(frac.bytes().take(places)).map(|b| b - b'0').collect();
    if frac.as_bytes()[places] >= b'5' {
        let mut i = digits.len();
        loop {
            if i == 0 {
                digits.insert(0, 1);
                break;
            }
            i -= 1;
            if digits[i] == 9 {
                digits[i] = 0;
            } else {
                digits[i] += 1;
                break;
            }
        }
    }
    let split = digits.len() - places;
    let text: String = digits.iter().map(|d| char::from(b'0' + d)).collect();
    let out = if places == 0 { text } else { format!("{}.{}", &text[..split], &text[split..]) };
    let zero = digits.iter().all(|d| *d == 0);
    if value.is_sign_negative() && !zero {
        format!("-{out}")
    } else {
        out
    }
}

/// The spring scene with `overrides`, stepped by `method` at `dt` for `steps` steps; returns
/// the world.
pub fn spring(method: &str, dt: f64, steps: u64, overrides: &[(&str, f64)]) -> World {
    let mut scene = scenes::build("spring", overrides, method, dt).unwrap();
    scene.world.step(steps).unwrap();
    scene.world
}

/// Least-squares slope of log(error) against log(dt): the observed order.
pub fn slope(dts: &[f64], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// The method a scene's recorded hash and exported file use: RK4 for the flows (split
/// methods refuse them), backward Euler for the stiff scenes (symplectic Euler diverges),
/// symplectic Euler otherwise.
pub fn recorded_method(scene: &str) -> &'static str {
    if ["lorenz", "rossler", "thomas"].contains(&scene) {
        "rk4"
    } else if scene.starts_with("stiff-") {
        "backward-euler"
    } else {
        "symplectic-euler"
    }
}

/// An empty world of `dim` dimensions stepped by `method` at `dt`.
pub fn world(dim: usize, method: &str, dt: f64) -> World {
    World::new(WorldParams { dim, method: method.into(), dt, ..Default::default() }).unwrap()
}

/// How deep the deepest pair of balls overlaps (all pairs: independent of the engine's grid),
/// m; negative when none does.
pub fn max_pair_overlap(w: &World) -> f64 {
    let (x, r, d) = (w.positions(), w.radii(), w.dim());
    let mut worst = f64::NEG_INFINITY;
    for i in 0..r.len() {
        for j in i + 1..r.len() {
            let dist = (0..d).map(|k| (x[i * d + k] - x[j * d + k]).powi(2)).sum::<f64>().sqrt();
            worst = worst.max(r[i] + r[j] - dist);
        }
    }
    worst
}

/// Asserts `got` is `want` entry by entry to `tol` relative (plus `tol` absolute).
pub fn close(got: &[f64], want: &[f64], tol: f64) {
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= tol * (1.0 + w.abs()), "got {got:?}, want {want:?}");
    }
}

/// FNV-1a, as the snapshot's checksum: re-signs an edited snapshot so the checks behind the
/// checksum are reached.
pub fn resign(mut bytes: Vec<u8>) -> Vec<u8> {
    bytes.truncate(bytes.len() - 8);
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in &bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    bytes.extend_from_slice(&h.to_le_bytes());
    bytes
}
