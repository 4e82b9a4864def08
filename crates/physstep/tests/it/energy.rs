//! Energy signatures on the notes' undamped spring (m = 10, k = 5, x0 = 20: E0 = 1000 J)
//! over 10,000 steps of dt = 0.1 (about 112 periods).

use physstep::prelude::*;

const DT: f64 = 0.1;
const STEPS: usize = 10_000;

/// E / E0 before the first step and after each of `STEPS` steps (`STEPS + 1` values).
fn energy_ratios(method: &str) -> Vec<f64> {
    let mut scene = scenes::build("spring", &[], method, DT).unwrap();
    let w = &mut scene.world;
    let e0 = w.energy().unwrap();
    assert_eq!(e0, 1000.0);
    let mut out = Vec::with_capacity(STEPS + 1);
    out.push(1.0);
    for _ in 0..STEPS {
        w.step(1).unwrap_or_else(|e| panic!("{method}: {e}"));
        out.push(w.energy().unwrap() / e0);
    }
    out
}

fn mean(xs: &[f64]) -> f64 {
    xs.iter().sum::<f64>() / xs.len() as f64
}

#[test]
fn explicit_euler_gains_energy_every_step() {
    let r = energy_ratios("explicit-euler");
    // E[n+1] = (1 + (w dt)^2) E[n] exactly in exact arithmetic: (w dt)^2 = 0.005.
    for (n, pair) in r.windows(2).enumerate() {
        assert!(pair[1] > pair[0], "step {n}: {} -> {}", pair[0], pair[1]);
        assert!((pair[1] / pair[0] - 1.005).abs() < 1e-9, "step {n}: ratio {}", pair[1] / pair[0]);
    }
    let last = r[STEPS];
    assert!(last.is_finite() && last > 100.0, "final E/E0 = {last}");
    // 1.005^10000 = e^49.9: large but far from overflow at dt = 0.1.
    assert!((last.ln() - 10_000.0 * 1.005f64.ln()).abs() < 1e-6 * last.ln(), "final E/E0 = {last:e}");
}

#[test]
fn explicit_euler_overflow_is_reported_and_rolled_back() {
    // At dt = 1 the energy grows by 1.5 per step and overflows within 10,000 steps.
    let mut scene = scenes::build("spring", &[], "explicit-euler", 1.0).unwrap();
    let w = &mut scene.world;
    let mut taken = 0u64;
    let err = loop {
        let before = (w.state_hash(), w.positions().to_vec(), w.velocities().to_vec(), w.time(), w.evals());
        match w.step(1) {
            Ok(()) => taken += 1,
            Err(e) => {
                // The state is rolled back bitwise (the evaluation counter keeps counting the
                // work done by the failed attempt).
                assert_eq!(w.state_hash(), before.0, "bitwise rollback");
                assert_eq!(w.positions(), before.1.as_slice());
                assert_eq!(w.velocities(), before.2.as_slice());
                assert_eq!(w.time().to_bits(), before.3.to_bits());
                assert_eq!(w.evals(), before.4 + 1);
                break e;
            }
        }
        assert!(taken < 10_000, "explicit Euler at dt = 1 should overflow");
    };
    assert_eq!(w.steps(), taken);
    // The run is stopped where it runs away (|x| past 1e100), before its energy, quadratic
    // in the state, could overflow (issue 7, item 10: it used to reach an infinite energy
    // at t = 1737 in silence).
    assert!(w.positions()[0].abs() <= 1e100 && w.velocities()[0].abs() <= 1e100);
    assert!(w.accelerations().unwrap()[0].is_finite());
    assert!(w.energy().unwrap().is_finite());
    match &err {
        Error::Diverged { method, step, t, .. } => {
            assert_eq!(method, "explicit-euler");
            assert_eq!(*step, taken);
            assert_eq!(*t, taken as f64);
        }
        other => panic!("expected Diverged, got {other:?}"),
    }
    assert!(err.to_string().contains("explicit-euler") && err.to_string().contains("rolled back"), "{err}");
    // The failing step keeps failing, and keeps the state.
    let h = w.state_hash();
    assert!(matches!(w.step(1), Err(Error::Diverged { .. })));
    assert_eq!(w.state_hash(), h);
    assert_eq!(w.steps(), taken);
}

#[test]
fn midpoint_and_heun_gain_energy() {
    // Both have |R(i w dt)|^2 = 1 + (w dt)^4 / 4 per step: E/E0 -> e^0.0625 = 1.0645.
    for method in ["midpoint", "heun"] {
        let r = energy_ratios(method);
        for (n, pair) in r.windows(2).enumerate() {
            assert!(pair[1] > pair[0], "{method} step {n}: {} -> {}", pair[0], pair[1]);
        }
        let last = r[STEPS];
        assert!(last > 1.05 && last < 1.08, "{method}: final E/E0 = {last}");
    }
}

#[test]
fn backward_euler_and_predictor_corrector_lose_energy() {
    // Backward Euler: E[n+1] = E[n] / (1 + (w dt)^2); predictor-corrector:
    // |1 + i w dt - (w dt)^2|^2 = 1 - (w dt)^2 + (w dt)^4 per step.
    for method in ["backward-euler", "predictor-corrector"] {
        let r = energy_ratios(method);
        // Strictly decreasing while the state is well above the Newton tolerance's absolute
        // floor (tol * (1 + max|z|)), below which backward Euler accepts its explicit guess.
        for (n, pair) in r.windows(2).enumerate().filter(|(_, p)| p[0] > 1e-12) {
            assert!(pair[1] < pair[0], "{method} step {n}: {} -> {}", pair[0], pair[1]);
        }
        let last = r[STEPS];
        assert!(last > 0.0 && last < 0.01, "{method}: final E/E0 = {last:e}");
    }
    let r = energy_ratios("backward-euler");
    assert!((r[1] - 1.0 / 1.005).abs() < 1e-12, "one backward-Euler step: {}", r[1]);
}

#[test]
fn rk4_loses_a_little_energy() {
    let r = energy_ratios("rk4");
    let last = r[STEPS];
    assert!(last < 1.0, "rk4 decays: final E/E0 = {last}");
    assert!(last > 1.0 - 1e-3, "rk4 stays within 1e-3: final E/E0 = {last}");
    // Monotone: |R|^2 = 1 - (w dt)^6 / 72 + (w dt)^8 / 576 < 1 every step.
    assert!(r.windows(2).all(|p| p[1] <= p[0]), "rk4 energy never rises");
}

#[test]
fn symplectic_methods_keep_energy_bounded_without_drift() {
    let symplectic: Vec<&Info> = INFOS.iter().filter(|i| i.symplectic).collect();
    assert!(symplectic.len() >= 7, "{symplectic:?}");
    for info in symplectic {
        let r = energy_ratios(info.name);
        let dev: Vec<f64> = r.iter().map(|e| e - 1.0).collect();
        let worst = dev.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        assert!(worst < 0.1, "{}: max |E/E0 - 1| = {worst}", info.name);
        let (first, last) = (mean(&dev[1..=1000]), mean(&dev[STEPS - 999..=STEPS]));
        assert!(
            (first - last).abs() < 1e-3,
            "{}: mean E/E0 - 1 drifts from {first:e} to {last:e}",
            info.name
        );
    }
}

#[test]
fn non_symplectic_methods_drift() {
    // The drift check above is not vacuous: every non-symplectic method fails it.
    for info in INFOS.iter().filter(|i| !i.symplectic) {
        let r = energy_ratios(info.name);
        let dev: Vec<f64> = r.iter().map(|e| e - 1.0).collect();
        let (first, last) = (mean(&dev[1..=1000]), mean(&dev[STEPS - 999..=STEPS]));
        assert!((first - last).abs() > 1e-5, "{}: no drift ({first:e} vs {last:e})", info.name);
    }
}

#[test]
fn implicit_midpoint_conserves_the_quadratic_energy() {
    let r = energy_ratios("implicit-midpoint");
    let worst = r.iter().fold(0.0f64, |m, e| m.max((e - 1.0).abs()));
    assert!(worst < 1e-9, "implicit-midpoint: max |E/E0 - 1| = {worst:e}");
}

/// The notes' yardstick: a 20-minute level at 120 updates per second is 144,000 updates. On
/// the Kepler ellipse (e = 0.6) at dt = 1/120 every symplectic method keeps the energy
/// bounded with no secular drift for all of them; explicit Euler does not.
#[test]
fn symplectic_methods_last_144000_updates_on_the_kepler_ellipse() {
    const STEPS: usize = 144_000;
    const WINDOW: usize = 12_000;
    for info in INFOS.iter().filter(|i| i.symplectic && !i.implicit) {
        let mut scene = scenes::build("kepler", &[], info.name, 1.0 / 120.0).unwrap();
        let w = &mut scene.world;
        let e0 = w.energy().unwrap();
        let mut rel = Vec::with_capacity(STEPS);
        for _ in 0..STEPS {
            w.step(1).unwrap();
            rel.push((w.energy().unwrap() - e0) / e0.abs());
        }
        let max = rel.iter().fold(0.0f64, |m, r| m.max(r.abs()));
        let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len() as f64;
        let drift = (mean(&rel[STEPS - WINDOW..]) - mean(&rel[..WINDOW])).abs();
        assert!(max < 0.05, "{}: max relative energy error {max}", info.name);
        assert!(drift < 0.1 * max.max(1e-12), "{}: drift {drift} vs max {max}", info.name);
    }
    let mut scene = scenes::build("kepler", &[], "explicit-euler", 1.0 / 120.0).unwrap();
    let e0 = scene.world.energy().unwrap();
    scene.world.step(STEPS as u64).unwrap();
    assert!(
        scene.world.energy().unwrap() > 0.5 * e0,
        "explicit Euler gains energy: {} vs {e0}",
        scene.world.energy().unwrap()
    );
}
