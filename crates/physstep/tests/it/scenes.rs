//! The built-in scenes: every scene under every method, exact solutions, convergence orders
//! and parameter validation.

use super::common::slope;
use physstep::prelude::*;
use std::f64::consts::{PI, TAU};

fn max_err(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max)
}

fn msg<T: std::fmt::Debug>(r: Result<T>) -> String {
    r.unwrap_err().to_string()
}

#[test]
fn every_scene_builds_and_steps_under_every_method() {
    assert_eq!(scenes::SCENES.len(), 47);
    for spec in scenes::SCENES {
        for info in INFOS {
            if ["racket", "top", "tumble"].contains(&spec.name) {
                // Bodies: Verlet (arithmetic on positions) refuses when the world is
                // configured; every other method steps them, with orientations kept unit.
                match scenes::build(spec.name, &[], info.name, 1e-3) {
                    Err(e) => {
                        assert!(info.vector_positions, "{} / {}: {e}", spec.name, info.name);
                        assert!(e.to_string().contains("vectors"), "{e}");
                    }
                    Ok(mut scene) => {
                        assert!(!info.vector_positions, "{} / {}", spec.name, info.name);
                        let e0 = scene.world.energy().unwrap();
                        scene.world.step(10).unwrap();
                        let q = scene.world.body_orientation(0).unwrap();
                        let unit = q.iter().map(|c| c * c).sum::<f64>().sqrt();
                        assert!((unit - 1.0).abs() < 1e-12, "{} / {}: |q| = {unit}", spec.name, info.name);
                        let de = (scene.world.energy().unwrap() - e0).abs() / e0.abs().max(1.0);
                        assert!(de < 1e-2, "{} / {}: energy error {de:e}", spec.name, info.name);
                    }
                }
                continue;
            }
            let solids = ["single-box", "stack", "pyramid", "ramp", "dice", "box-stack"];
            let more = [
                "card-house",
                "mass-ratio",
                "arch",
                "domino",
                "confined",
                "overlap-recovery",
                "top-on-floor",
                "bridge",
                "ball-chain",
                "ragdoll-bodies",
                "far-pyramid",
                "far-ragdoll-pile",
                "high-mass-ratio",
                "friction-ramp",
                "warm-start-energy",
                "rush",
                "double-domino",
                "joint-grid",
                "stretched-chain",
                "far-chain",
                "ragdoll-stress",
            ];
            if solids.contains(&spec.name) || more.contains(&spec.name) {
                // Solids: the contact solver steps them whatever the method (which moves
                // the world's other parts): every method builds and steps them alike.
                let mut scene = scenes::build(spec.name, &[], info.name, 1e-3)
                    .unwrap_or_else(|e| panic!("{} / {}: {e}", spec.name, info.name));
                assert!(scene.world.solid_count() > 1, "{}", spec.name);
                let e0 = scene.world.energy().unwrap();
                scene.world.step(10).unwrap_or_else(|e| panic!("{} / {}: {e}", spec.name, info.name));
                let x = scene.world.solid_positions();
                assert!(x.iter().all(|c| c.is_finite()), "{} / {}", spec.name, info.name);
                let de = (scene.world.energy().unwrap() - e0).abs() / e0.abs().max(1.0);
                // Solids started overlapping are pushed apart, joints started open pulled
                // shut: energy given by design.
                let pushed = ["confined", "overlap-recovery", "stretched-chain"].contains(&spec.name);
                assert!(pushed || de < 1e-2, "{} / {}: energy moved by {de}", spec.name, info.name);
                continue;
            }
            if ["lorenz", "rossler", "thomas"].contains(&spec.name) {
                // Flows: the split methods refuse when the world is configured, the flow
                // methods step it; a flow has no energy.
                match scenes::build(spec.name, &[], info.name, 1e-3) {
                    Err(e) => {
                        assert!(info.split, "{} / {}: {e}", spec.name, info.name);
                        assert!(e.to_string().contains("needs a second-order system"), "{e}");
                    }
                    Ok(mut scene) => {
                        assert!(!info.split, "{} / {}", spec.name, info.name);
                        assert_eq!(scene.world.positions().len(), 3);
                        assert!(scene.world.energy().is_none());
                        scene.world.step(10).unwrap();
                        assert!(scene.world.positions().iter().all(|c| c.is_finite()));
                    }
                }
                continue;
            }
            let overrides: &[(&str, f64)] = match spec.name {
                "nbody" if info.implicit => &[("n", 4.0)],
                // A dense Newton solve of a 12 x 12 cloth's 432 coordinates is slow.
                "cloth" if info.implicit => &[("w", 4.0), ("h", 4.0)],
                // Stiff at their defaults by design (tests/it/stiff.rs): soft here, so every
                // method holds at 1 ms.
                "stiff-chain" | "stiff-cloth" => &[("n", 4.0), ("k", 100.0)],
                _ => &[],
            };
            let mut scene = scenes::build(spec.name, overrides, info.name, 1e-3)
                .unwrap_or_else(|e| panic!("{} / {}: {e}", spec.name, info.name));
            assert_eq!(scene.spec.name, spec.name);
            assert_eq!(scene.world.dim(), spec.dim);
            assert_eq!(scene.world.integrator().info().name, info.name);
            assert_eq!(scene.values.len(), spec.params.len());
            for (p, v) in spec.params.iter().zip(&scene.values) {
                let want = overrides.iter().find(|(n, _)| *n == p.name).map_or(p.default, |o| o.1);
                assert_eq!(*v, want, "{} {}", spec.name, p.name);
                assert_eq!(scene.param(p.name), Some(want));
            }
            assert_eq!(scene.param("nope"), None);
            assert!(!scene.world.is_empty());
            let e0 = scene.world.energy().unwrap();
            assert!(e0.is_finite(), "{} energy", spec.name);
            if let Some((x, v)) = scene.exact(0.0) {
                assert!(max_err(&x, scene.world.positions()) < 1e-15, "{}: exact(0) is the start", spec.name);
                assert!(max_err(&v, scene.world.velocities()) < 1e-15, "{}: exact(0) velocity", spec.name);
            }
            scene.world.step(10).unwrap_or_else(|e| panic!("{} / {}: {e}", spec.name, info.name));
            assert_eq!(scene.world.steps(), 10);
            let w = &scene.world;
            assert!(w.positions().iter().chain(w.velocities()).all(|x| x.is_finite()), "{}", spec.name);
            assert!(w.energy().unwrap().is_finite());
            // Short runs at dt = 1 ms stay close to the start energy.
            let de = (w.energy().unwrap() - e0).abs() / e0.abs().max(1.0);
            assert!(de < 1e-2, "{} / {}: energy moved by {de}", spec.name, info.name);
            if let Some((x, _)) = scene.exact(w.time()) {
                let err = max_err(&x, w.positions());
                assert!(err < 1e-3, "{} / {}: error {err} after 10 steps", spec.name, info.name);
            }
        }
    }
}

/// Methods exact (to rounding) for a constant acceleration, in position.
const BALLISTIC_EXACT: [&str; 8] = [
    "velocity-verlet",
    "leapfrog",
    "yoshida4",
    "midpoint",
    "heun",
    "rk4",
    "implicit-midpoint",
    // x-first and v-first Euler alternated: the two O(dt^2) errors cancel over every pair of
    // steps (200 steps is an even count).
    "symplectic-euler-alternating",
];

#[test]
fn projectile_is_exact_for_second_order_methods() {
    let mut report = Vec::new();
    for info in INFOS {
        let mut scene = scenes::build("projectile", &[], info.name, 0.01).unwrap();
        scene.world.step(200).unwrap();
        let (x, v) = scene.exact(2.0).unwrap();
        let err = max_err(&x, scene.world.positions());
        let verr = max_err(&v, scene.world.velocities());
        report.push(format!("{:<30} |x - exact| = {err:.3e}  |v - exact| = {verr:.3e}", info.name));
        if BALLISTIC_EXACT.contains(&info.name) {
            assert!(err < 1e-9, "{}: {err}", info.name);
        } else {
            assert!(err > 1e-6, "{} is not exact for constant acceleration, yet error {err}", info.name);
        }
    }
    eprintln!("projectile, dt = 0.01, t = 2:\n{}", report.join("\n"));
}

/// Position errors at `t_end` for `steps`, `2 steps`, ... of `scene` under `method`.
fn errors(scene: &str, method: &str, t_end: f64, steps: &[u64]) -> (Vec<f64>, Vec<f64>) {
    let mut dts = Vec::new();
    let mut errs = Vec::new();
    for &n in steps {
        let dt = t_end / n as f64;
        let mut s = scenes::build(scene, &[], method, dt).unwrap();
        s.world.step(n).unwrap();
        let (x, _) = s.exact(t_end).unwrap();
        dts.push(dt);
        errs.push(max_err(&x, s.world.positions()));
    }
    (dts, errs)
}

/// Checks the observed order (slope of log error against log dt, over the step counts
/// `steps_for` gives) against `want` (default: `INFO.order`) within 0.2, for every method.
fn check_orders(scene: &str, t_end: f64, steps_for: impl Fn(&Info) -> Vec<u64>, want: impl Fn(&Info) -> u32) {
    let mut report = Vec::new();
    let mut bad = Vec::new();
    for info in INFOS {
        let steps = steps_for(&info);
        let (dts, errs) = errors(scene, info.name, t_end, &steps);
        let p = slope(&dts, &errs);
        let errs: Vec<String> = errs.iter().map(|e| format!("{e:.2e}")).collect();
        let order = want(&info);
        report.push(format!("{:<30} order {order}  observed {p:.3}  errors {}", info.name, errs.join(" ")));
        if (p - f64::from(order)).abs() > 0.2 {
            bad.push(format!("{}: observed {p:.3}, expected {order} (INFO.order {})", info.name, info.order));
        }
    }
    eprintln!("{scene}:\n{}", report.join("\n"));
    assert!(bad.is_empty(), "{scene}: {bad:#?}");
}

#[test]
fn drag_converges_at_each_method_order() {
    // t = 2 with even step counts (symplectic-euler-alternating is second order at any
    // count, with an error constant that differs between odd and even ones). Yoshida4's error on drag is irregular below 40 steps (the composed velocity
    // Verlet is not symmetric for a velocity-dependent force), so the 4th-order methods
    // start there.
    check_orders(
        "drag",
        2.0,
        |info| if info.order >= 4 { vec![40, 80, 160, 320] } else { vec![20, 40, 80, 160] },
        |info| info.order,
    );
}

/// First-order methods that are not symplectic: at 200 steps per period their orbit error is
/// O(1) (explicit Euler 1.3, predictor-corrector 0.6), far from the asymptotic regime, and
/// backward Euler spirals into the centre.
fn coarse_first_order(info: &Info) -> bool {
    info.order == 1 && !info.symplectic
}

#[test]
fn orbit_converges_at_each_method_order() {
    // One period from dt = 2 pi / 200 (the non-symplectic first-order methods from 2 pi / 1600,
    // see `coarse_first_order`).
    //
    // The first-order symplectic methods (symplectic Euler in both orders, Verlet with its
    // Euler start) are conjugate to a second-order method through an O(dt) change of
    // variables that depends only on the state; after a whole period the orbit is back where
    // it started and that O(dt) offset cancels, so at t = 2 pi they converge at order 2. At
    // half a period (below) they show their order 1.
    check_orders(
        "orbit",
        TAU,
        |info| {
            let first = if coarse_first_order(info) { 1600 } else { 200 };
            (0..4).map(|k| first << k).collect()
        },
        |info| if info.order == 1 && info.symplectic { 2 } else { info.order },
    );
    check_orders(
        "orbit",
        PI,
        |info| {
            let first = if coarse_first_order(info) { 800 } else { 100 };
            (0..4).map(|k| first << k).collect()
        },
        |info| info.order,
    );
}

#[test]
fn backward_euler_spirals_into_the_centre_at_coarse_steps() {
    let n = 200;
    let mut scene = scenes::build("orbit", &[], "backward-euler", TAU / f64::from(n)).unwrap();
    let r = |w: &World| w.positions()[0].hypot(w.positions()[1]);
    let mut last = r(&scene.world);
    for _ in 0..150 {
        scene.world.step(1).unwrap();
        let now = r(&scene.world);
        assert!(now < last, "the radius only shrinks");
        last = now;
    }
    assert!(last < 0.6, "r = {last}");
}

/// `v^2/2 - 1/r` with GM = 1.
fn kepler_energy(x: &[f64], v: &[f64]) -> f64 {
    0.5 * (v[0] * v[0] + v[1] * v[1]) - 1.0 / x[0].hypot(x[1])
}

#[test]
fn kepler_exact_solution_is_right() {
    for e in [0.0, 0.3, 0.6, 0.9, 0.99] {
        let scene = scenes::build("kepler", &[("e", e)], "rk4", 0.01).unwrap();
        let (x0, v0) = scene.exact(0.0).unwrap();
        assert!(max_err(&x0, &[1.0 - e, 0.0]) < 1e-15, "e {e}: {x0:?}");
        assert!((v0[1] - ((1.0 + e) / (1.0 - e)).sqrt()).abs() < 1e-12 * v0[1], "e {e}: {v0:?}");
        let c0 = x0[0] * v0[1] - x0[1] * v0[0];
        for t in [0.1, 0.5, 1.0, 2.0, PI, 4.0, 5.5, TAU - 0.01, 10.0, 40.0] {
            let (x, v) = scene.exact(t).unwrap();
            let en = kepler_energy(&x, &v);
            assert!((en + 0.5).abs() < 1e-11 * (1.0 + v0[1] * v0[1]), "e {e} t {t}: energy {en}");
            // Angular momentum sqrt(1 - e^2) and the focus-directrix law r = 1 - e cos E.
            let c = x[0] * v[1] - x[1] * v[0];
            assert!((c - c0).abs() < 1e-11 * (1.0 + v0[1]), "e {e} t {t}: angular momentum {c} vs {c0}");
            assert!((c - (1.0 - e * e).sqrt()).abs() < 1e-11 * (1.0 + v0[1]), "e {e} t {t}");
            // On the ellipse ((x + e) / a)^2 + (y / b)^2 = 1.
            let b2 = 1.0 - e * e;
            if b2 > 0.0 {
                let q = (x[0] + e).powi(2) + x[1] * x[1] / b2;
                assert!((q - 1.0).abs() < 1e-10, "e {e} t {t}: {q}");
            }
        }
        // Back to the start after one period, and half way at the apocentre.
        let (x, v) = scene.exact(TAU).unwrap();
        assert!(max_err(&x, &x0) < 1e-12, "e {e}: {x:?}");
        assert!(max_err(&v, &v0) < 1e-9 * (1.0 + v0[1]), "e {e}: {v:?}");
        let (x, _) = scene.exact(PI).unwrap();
        assert!((x[0] + 1.0 + e).abs() < 1e-12 && x[1].abs() < 1e-12, "e {e}: apocentre {x:?}");
        // Periodic: t and t + 2 pi agree.
        let (xa, _) = scene.exact(1.3).unwrap();
        let (xb, _) = scene.exact(1.3 + TAU).unwrap();
        assert!(max_err(&xa, &xb) < 1e-12);
    }
}

#[test]
fn kepler_rk4_matches_the_exact_solution() {
    let n = 20_000;
    let mut scene = scenes::build("kepler", &[], "rk4", TAU / n as f64).unwrap();
    let mut worst: f64 = 0.0;
    for k in 1..=10 {
        scene.world.step(n / 10).unwrap();
        let (x, v) = scene.exact(TAU * f64::from(k) / 10.0).unwrap();
        worst = worst.max(max_err(&x, scene.world.positions())).max(max_err(&v, scene.world.velocities()));
    }
    assert!(worst < 1e-8, "rk4 vs exact: {worst}");
    let (x0, _) = scene.exact(0.0).unwrap();
    assert!(max_err(&x0, scene.world.positions()) < 1e-8);
    assert!((scene.world.energy().unwrap() + 0.5).abs() < 1e-9);
}

#[test]
fn pendulum_without_gravity_is_a_circle() {
    let (l, om, th) = (1.5, 1.0, 0.5);
    // The notes' rod force (rod = 0): smooth, so each method keeps its order on it (the
    // constraint version is tested in tests/it/constraints.rs).
    let over = [("g", 0.0), ("omega0", om), ("length", l), ("theta0", th), ("rod", 0.0)];
    let scene = scenes::build("pendulum", &over, "rk4", 0.01).unwrap();
    assert!(scene.has_exact());
    for t in [0.0, 0.3, 1.0, PI, 7.0] {
        let (x, v) = scene.exact(t).unwrap();
        let a = th + om * t;
        assert!(max_err(&x, &[l * a.sin(), -l * a.cos()]) < 1e-14, "t {t}");
        assert!(max_err(&v, &[l * om * a.cos(), l * om * a.sin()]) < 1e-14, "t {t}");
        assert!((x[0].hypot(x[1]) - l).abs() < 1e-14);
        assert!((x[0] * v[0] + x[1] * v[1]).abs() < 1e-14, "velocity is tangential");
    }
    let (x, _) = scene.exact(TAU / om).unwrap();
    assert!(max_err(&x, scene.world.positions()) < 1e-12);

    // rk4 follows the circle; the rod length stays within the integrator's error.
    // (method, dt, bound on the position error, bound on the rod-length drift); the
    // second-order methods see the rod's velocity-dependent constraint through their
    // velocity estimate and drift by ~0.02 dt^2 per unit time.
    let cases = [
        ("rk4", 0.01, 1e-8, 1e-10),
        ("rk4", 0.0025, 1e-10, 1e-13),
        ("yoshida4", 0.01, 1e-5, 1e-6),
        ("midpoint", 0.01, 1e-3, 1e-5),
        ("velocity-verlet", 0.0025, 2e-3, 5e-4),
        ("leapfrog", 0.0025, 2e-3, 5e-4),
    ];
    for (method, dt, tol, len_tol) in cases {
        let mut scene = scenes::build("pendulum", &over, method, dt).unwrap();
        let n = (10.0 / dt).round() as u64;
        let mut worst_len: f64 = 0.0;
        for _ in 0..10 {
            scene.world.step(n / 10).unwrap();
            let x = scene.world.positions();
            worst_len = worst_len.max((x[0].hypot(x[1]) - l).abs());
        }
        let (x, _) = scene.exact(scene.world.time()).unwrap();
        let err = max_err(&x, scene.world.positions());
        assert!(err < tol, "{method} dt {dt}: position error {err}");
        assert!(worst_len < len_tol, "{method} dt {dt}: rod length drift {worst_len}");
        // Halving dt shrinks the drift by at least 2^order / 2.
        let mut half = scenes::build("pendulum", &over, method, dt / 2.0).unwrap();
        half.world.step(2 * n).unwrap();
        let x = half.world.positions();
        let x_full = scene.world.positions();
        let (d_half, d_full) = ((x[0].hypot(x[1]) - l).abs(), (x_full[0].hypot(x_full[1]) - l).abs());
        let order = scene.world.integrator().info().order;
        assert!(
            d_full < 1e-12 || d_half * 2f64.powi(order as i32 - 1) <= d_full,
            "{method}: drift {d_full:e} at dt, {d_half:e} at dt / 2"
        );
    }

    // With gravity there is no exact solution.
    assert!(!scenes::build("pendulum", &[], "rk4", 0.01).unwrap().has_exact());
}

#[test]
fn unknown_names_list_the_valid_ones() {
    let all_scenes =
        "spring, projectile, drag, orbit, kepler, pendulum, nbody, chain, lorenz, rossler, thomas, stiff-chain, stiff-cloth, racket, top, tumble, cloth, ragdoll, balls, pile, bridge, ball-chain, ragdoll-bodies, single-box, stack, pyramid, ramp, dice, box-stack, card-house, mass-ratio, arch, domino, confined, overlap-recovery, top-on-floor, far-pyramid, far-ragdoll-pile, high-mass-ratio, friction-ramp, warm-start-energy, rush, double-domino, joint-grid, stretched-chain, far-chain, ragdoll-stress";
    assert_eq!(
        msg(scenes::build("bouncy", &[], "rk4", 0.01)),
        format!("unknown scene 'bouncy'; valid scenes: {all_scenes}")
    );
    assert_eq!(msg(scenes::spec("")), format!("unknown scene ''; valid scenes: {all_scenes}"));
    assert_eq!(
        msg(scenes::build("kepler", &[("a", 2.0)], "rk4", 0.01)),
        "unknown param 'a'; valid params: e"
    );
    assert_eq!(
        msg(scenes::build("spring", &[("k", 1.0), ("mass", 2.0)], "rk4", 0.01)),
        "unknown param 'mass'; valid params: m, k, c, x0, v0"
    );
    let m = msg(scenes::build("spring", &[], "rk5", 0.01));
    assert!(m.starts_with("unknown method 'rk5'; valid methods: explicit-euler,"), "{m}");
    for info in INFOS {
        assert!(m.contains(info.name), "{m}");
    }
    assert!(msg(scenes::build("spring", &[], "rk4", 0.0)).starts_with("invalid dt = 0"));
}

#[test]
fn bad_param_values_name_the_param() {
    let pos = "a number in [1e-12, 1e12]";
    let nonneg = "0 or a number in [1e-12, 1e12]";
    let any = "a number in [-1e12, 1e12]";
    let cases: [(&str, &str, f64, String); 16] = [
        ("spring", "m", 0.0, format!("invalid m = 0: must be {pos}")),
        ("projectile", "m", -1.0, format!("invalid m = -1: must be {pos}")),
        ("kepler", "e", 1.0, "invalid e = 1: must be in [0, 1)".into()),
        ("kepler", "e", -0.1, "invalid e = -0.1: must be in [0, 1)".into()),
        ("nbody", "n", 2.5, "invalid n = 2.5: must be a whole number from 1 to 1000000".into()),
        ("nbody", "n", 0.0, "invalid n = 0: must be a whole number from 1 to 1000000".into()),
        ("chain", "n", -3.0, "invalid n = -3: must be a whole number from 1 to 1000000".into()),
        ("nbody", "softening", -0.1, format!("invalid softening = -0.1: must be {nonneg}")),
        ("spring", "x0", f64::NAN, format!("invalid x0 = NaN: must be {any}")),
        ("pendulum", "length", 0.0, format!("invalid length = 0: must be {pos}")),
        ("orbit", "gm", f64::INFINITY, format!("invalid gm = inf: must be {pos}")),
        ("drag", "c", -1.0, format!("invalid c = -1: must be {nonneg}")),
        // Issue 7, item 11: values whose squares underflow or overflow drop physics in
        // silence (orbit r = 1e-300: r^2 = 0, gravity vanished, the error was NaN).
        ("orbit", "r", 1e-300, format!("invalid r = 1e-300: must be {pos}")),
        ("spring", "k", 1e300, format!("invalid k = 1e300: must be {nonneg}")),
        ("spring", "x0", -1e13, format!("invalid x0 = -10000000000000: must be {any}")),
        ("drag", "c", 1e-13, format!("invalid c = 1e-13: must be {nonneg}")),
    ];
    for (scene, name, value, want) in cases {
        assert_eq!(msg(scenes::build(scene, &[(name, value)], "rk4", 0.01)), want, "{scene}");
        let spec = scenes::spec(scene).unwrap();
        assert_eq!(msg(scenes::resolve(spec, &[(name, value)])), want);
    }
    // Every accepted extreme builds a scene whose forces and energy are finite and nonzero.
    for (scene, name, value) in
        [("orbit", "r", 1e-12), ("orbit", "r", 1e12), ("orbit", "gm", 1e-12), ("spring", "k", 1e12)]
    {
        let mut s = scenes::build(scene, &[(name, value)], "rk4", 0.01).unwrap();
        let a = s.world.accelerations().unwrap().to_vec();
        assert!(
            a.iter().all(|c| c.is_finite()) && a.iter().any(|c| *c != 0.0),
            "{scene} {name}={value}: {a:?}"
        );
        assert!(s.world.energy().unwrap().is_finite() && s.world.energy().unwrap() != 0.0);
    }
    // Good values pass, and the last override of a name wins.
    let spec = scenes::spec("kepler").unwrap();
    assert_eq!(scenes::resolve(spec, &[("e", 0.0)]).unwrap(), vec![0.0]);
    assert_eq!(scenes::resolve(spec, &[("e", 0.2), ("e", 0.5)]).unwrap(), vec![0.5]);
    let s = scenes::build("nbody", &[("n", 3.0)], "rk4", 0.01).unwrap();
    assert_eq!(s.world.len(), 3);
    let s = scenes::build("chain", &[("n", 1.0)], "rk4", 0.01).unwrap();
    assert_eq!(s.world.len(), 1);
}

#[test]
fn grids_past_a_million_particles_are_refused_before_they_are_built() {
    // stiff-cloth n = 100000 was 1e10 particles built with growing memory; each side is a
    // count up to a million, the grid is refused naming its size, at once.
    let e = scenes::build("stiff-cloth", &[("n", 100_000.0)], "backward-euler", 0.01).unwrap_err();
    assert_eq!(e.to_string(), "invalid n x n = 100000 x 100000: must be at most 1000000 particles");
    let e = scenes::build("cloth", &[("w", 2000.0), ("h", 1000.0)], "rk4", 0.01).unwrap_err();
    assert_eq!(e.to_string(), "invalid w x h = 2000 x 1000: must be at most 1000000 particles");
    // The bound is the grid's: 1000 x 1000 is the largest, 1001 x 1001 refused.
    let e = scenes::build("stiff-cloth", &[("n", 1001.0)], "backward-euler", 0.01).unwrap_err();
    assert_eq!(e.to_string(), "invalid n x n = 1001 x 1001: must be at most 1000000 particles");
}
