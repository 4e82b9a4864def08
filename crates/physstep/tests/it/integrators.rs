//! The integrators behind their one interface: the registry, input validation, stateful
//! methods across changes of dt and resets, evaluation counts, stage logs, divergence
//! handling and determinism.

use super::common;
use super::common::spring;
use physstep::integrators::registry::{self, State};
use physstep::integrators::StageLog;
use physstep::prelude::*;

fn names() -> Vec<&'static str> {
    INFOS.iter().map(|i| i.name).collect()
}

fn is_kebab(s: &str) -> bool {
    !s.is_empty()
        && s.split('-')
            .all(|w| !w.is_empty() && w.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit()))
        && s.as_bytes()[0].is_ascii_lowercase()
}

// ---------------------------------------------------------------- registry

#[test]
fn every_info_is_well_formed() {
    let mut seen = std::collections::HashSet::new();
    for info in &INFOS {
        assert!(is_kebab(info.name), "{:?} is not kebab-case", info.name);
        assert!(seen.insert(info.name), "duplicate name {}", info.name);
        assert!(!info.doc.trim().is_empty(), "{}: empty doc", info.name);
        assert!(info.order >= 1, "{}: order {}", info.name, info.order);
        assert!(info.evals >= 1, "{}: evals {}", info.name, info.evals);
        // The name finds the method, and the method says it is that name.
        let integ = Integrator::new(info.name).unwrap();
        assert_eq!(integ.info(), info);
        assert_eq!(registry::info(info.name).unwrap(), info);
        // The implicit methods are flow methods (Newton on y = [x; v]).
        if info.implicit {
            assert!(!info.split, "{}", info.name);
        }
    }
    assert_eq!(seen.len(), 15);
    assert_eq!(registry::names().collect::<Vec<_>>(), names());
    assert!(
        !is_kebab("Rk4") && !is_kebab("rk_4") && !is_kebab("-rk4") && !is_kebab("rk--4") && !is_kebab("4rk")
    );
}

#[test]
fn unknown_method_lists_every_name() {
    let err = Integrator::new("nope").unwrap_err();
    match &err {
        Error::UnknownName { kind, name, valid } => {
            assert_eq!(kind, "method");
            assert_eq!(name, "nope");
            assert_eq!(valid, &names());
        }
        other => panic!("expected UnknownName, got {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.contains("'nope'"), "{msg}");
    for name in names() {
        assert!(msg.contains(name), "message lacks {name}: {msg}");
    }
    // Names are exact: no case folding, no surrounding space.
    for bad in ["RK4", " rk4", "rk4 ", "", "velocity_verlet"] {
        assert!(matches!(Integrator::new(bad), Err(Error::UnknownName { .. })), "{bad:?} accepted");
    }
    assert!(matches!(scenes::build("spring", &[], "nope", 0.1), Err(Error::UnknownName { .. })));
}

// ---------------------------------------------------------------- dt validation

fn assert_dt_error(r: Result<()>, context: &str) {
    let err = r.expect_err(context);
    match &err {
        Error::InvalidValue { field, .. } => assert_eq!(field, "dt", "{context}"),
        other => panic!("{context}: expected InvalidValue, got {other:?}"),
    }
    assert!(err.to_string().contains("dt"), "{context}: {err}");
}

#[test]
fn bad_dt_is_rejected_naming_dt() {
    let bad = [0.0, -0.0, -0.1, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
    for info in &INFOS {
        let mut scene = scenes::build("spring", &[], info.name, 0.1).unwrap();
        let w = &mut scene.world;
        w.step(3).unwrap();
        let hash = w.state_hash();
        for dt in bad {
            let ctx = format!("{} dt = {dt}", info.name);
            assert_dt_error(w.set_dt(dt), &ctx);
            assert_dt_error(w.step_by(dt), &ctx);
            assert_dt_error(w.step_logged(dt, &mut StageLog::default()), &ctx);
            assert!(matches!(
                scenes::build("spring", &[], info.name, dt),
                Err(Error::InvalidValue { ref field, .. }) if field == "dt"
            ));
            let mut sys = w.model().clone();
            let mut state = State::second(&mut sys, 0.0, &[1.0], &[0.0]).unwrap();
            let before = state.clone();
            assert_dt_error(Integrator::new(info.name).unwrap().step(&mut sys, &mut state, dt), &ctx);
            assert_eq!(state, before);
        }
        // Nothing moved, and the fixed dt is still the good one.
        assert_eq!(w.state_hash(), hash, "{}", info.name);
        assert_eq!(w.dt(), 0.1);
        assert_eq!(w.steps(), 3);
    }
}

// ---------------------------------------------------------------- stateful methods

fn spring_error(w: &World, scene: &Scene) -> f64 {
    (w.positions()[0] - scene.exact(w.time()).unwrap().0[0]).abs()
}

/// Runs `method` on the spring: `n1` steps of `dt1`, then `set_dt(dt2)` and `n2` steps;
/// returns the position error at the end.
fn switched(method: &str, dt1: f64, n1: u64, dt2: f64, n2: u64) -> f64 {
    let mut scene = scenes::build("spring", &[], method, dt1).unwrap();
    scene.world.step(n1).unwrap();
    scene.world.set_dt(dt2).unwrap();
    assert_eq!(scene.world.dt(), dt2);
    scene.world.step(n2).unwrap();
    assert!((scene.world.time() - (n1 as f64 * dt1 + n2 as f64 * dt2)).abs() < 1e-9);
    spring_error(&scene.world, &scene)
}

#[test]
fn stateful_methods_survive_a_change_of_dt() {
    for method in ["verlet", "leapfrog"] {
        let coarse =
            spring_error(&spring(method, 0.1, 100, &[]), &scenes::build("spring", &[], method, 0.1).unwrap());
        let fine = spring_error(
            &spring(method, 0.05, 200, &[]),
            &scenes::build("spring", &[], method, 0.05).unwrap(),
        );
        assert!(fine < coarse);
        // Halving dt at t = 5: between the fine and the coarse run's errors at t = 10.
        let halved = switched(method, 0.1, 50, 0.05, 100);
        assert!(
            halved <= coarse && halved >= 0.5 * fine,
            "{method}: halved {halved:e}, coarse {coarse:e}, fine {fine:e}"
        );
        // Doubling it: no worse than the coarse run either.
        let doubled = switched(method, 0.05, 100, 0.1, 50);
        assert!(
            doubled <= coarse && doubled >= 0.5 * fine,
            "{method}: doubled {doubled:e}, coarse {coarse:e}, fine {fine:e}"
        );
        // Several changes back and forth: Leapfrog restarts its half-step velocity from the
        // synchronised state, which costs nothing at second order, so it stays as accurate as
        // the coarse run. Verlet keeps its backward-difference velocity, a v[n - dt/2] that
        // after the change stands for v[n - dt'/2]: an O(dt) kick at each change, like the
        // one its start makes, so the error stays first order but with its own constant.
        let err = several_changes(method, 1.0);
        let bound = if method == "verlet" { 2.0 * coarse } else { coarse };
        assert!(err <= bound, "{method}: several changes {err:e}, coarse {coarse:e}");
    }
}

/// The spring to t = 10 through a schedule of five step sizes (the coarsest `0.1 * scale`);
/// returns the position error.
fn several_changes(method: &str, scale: f64) -> f64 {
    let mut scene = scenes::build("spring", &[], method, 0.1 * scale).unwrap();
    for (dt, n) in [(0.1, 20.0), (0.05, 40.0), (0.1, 10.0), (0.025, 80.0), (0.1, 30.0)] {
        scene.world.set_dt(dt * scale).unwrap();
        scene.world.step((n / scale).round() as u64).unwrap();
    }
    assert!((scene.world.time() - 10.0).abs() < 1e-9);
    spring_error(&scene.world, &scene)
}

#[test]
fn stateful_methods_keep_their_order_across_changes_of_dt() {
    for method in ["verlet", "leapfrog"] {
        let scales = [1.0, 0.5, 0.25, 0.125];
        let errors: Vec<f64> = scales.iter().map(|s| several_changes(method, *s)).collect();
        let order = f64::from(registry::info(method).unwrap().order);
        let p = common::slope(&scales, &errors);
        assert!((p - order).abs() < 0.15, "{method}: observed order {p} across dt changes ({errors:?})");
    }
}

#[test]
fn stateful_methods_without_the_dt_fix_would_fail_the_check() {
    // The bound above is tight enough to notice a stale memory: a Verlet that keeps
    // x[n-1] from the old dt sees its velocity doubled, i.e. a wrong start of about
    // v dt, far above the coarse run's error. Emulated: a fresh run from a state
    // whose velocity is doubled.
    let scene = scenes::build("spring", &[], "verlet", 0.1).unwrap();
    let coarse = spring_error(&spring("verlet", 0.1, 100, &[]), &scene);
    let w = spring("verlet", 0.1, 50, &[]);
    let (x, v) = (w.positions()[0], w.velocities()[0]);
    let mut bad = scenes::build("spring", &[("x0", x), ("v0", 2.0 * v)], "verlet", 0.05).unwrap();
    bad.world.step(100).unwrap();
    let good = scene.exact(10.0).unwrap().0[0];
    assert!((bad.world.positions()[0] - good).abs() > 5.0 * coarse);
}

#[test]
fn set_velocities_restarts_every_method_cleanly() {
    // After set_velocities (which resets the integrator), the run continues exactly as a
    // fresh run started from that state (the spring is autonomous).
    for info in &INFOS {
        let mut scene = scenes::build("spring", &[], info.name, 0.1).unwrap();
        let w = &mut scene.world;
        w.step(37).unwrap();
        let x = w.positions()[0];
        let v = 3.0;
        w.set_velocities(&[v]).unwrap();
        w.step(50).unwrap();
        let fresh = spring(info.name, 0.1, 50, &[("x0", x), ("v0", v)]);
        assert_eq!(w.positions()[0].to_bits(), fresh.positions()[0].to_bits(), "{}", info.name);
        assert_eq!(w.velocities()[0].to_bits(), fresh.velocities()[0].to_bits(), "{}", info.name);
        assert_eq!(w.integrator().memory(), fresh.integrator().memory(), "{}", info.name);
    }
}

#[test]
fn integrator_reset_forgets_the_memory() {
    for method in ["verlet", "leapfrog", "symplectic-euler-alternating"] {
        let mut sys = spring(method, 0.1, 0, &[]).model().clone();
        let mut integ = Integrator::new(method).unwrap();
        let mut state = State::second(&mut sys, 0.0, &[20.0], &[0.0]).unwrap();
        for _ in 0..7 {
            integ.step(&mut sys, &mut state, 0.1).unwrap();
        }
        // Move the system by hand, reset, and step: as a fresh integrator from there.
        state = State::second(&mut sys, 0.0, &[-4.0], &[1.5]).unwrap();
        let mut fresh_state = state.clone();
        integ.reset();
        let mut fresh = Integrator::new(method).unwrap();
        for _ in 0..20 {
            integ.step(&mut sys, &mut state, 0.1).unwrap();
            fresh.step(&mut sys, &mut fresh_state, 0.1).unwrap();
        }
        assert_eq!(state, fresh_state, "{method}");
        assert_eq!(integ.memory(), fresh.memory(), "{method}");
    }
}

#[test]
fn verlet_without_a_reset_would_remember_the_old_position() {
    // The counter-check of the reset test: skipping reset() after moving the system by hand
    // gives a different trajectory for Verlet (its x[n-1] is stale).
    let mut sys = spring("verlet", 0.1, 0, &[]).model().clone();
    let mut integ = Integrator::new("verlet").unwrap();
    let mut state = State::second(&mut sys, 0.0, &[20.0], &[0.0]).unwrap();
    integ.step(&mut sys, &mut state, 0.1).unwrap();
    state = State::second(&mut sys, 0.0, &[-4.0], &[1.5]).unwrap();
    let mut fresh_state = state.clone();
    integ.step(&mut sys, &mut state, 0.1).unwrap();
    Integrator::new("verlet").unwrap().step(&mut sys, &mut fresh_state, 0.1).unwrap();
    assert_ne!(state.y, fresh_state.y);
}

// ---------------------------------------------------------------- evaluation counts

#[test]
fn evaluation_counts_match_the_registry() {
    for info in &INFOS {
        let mut scene = scenes::build("spring", &[], info.name, 0.1).unwrap();
        let w = &mut scene.world;
        w.step(1).unwrap(); // the first step also evaluates the initial acceleration
        let before = w.evals();
        w.step(100).unwrap();
        let per_step = (w.evals() - before) as f64 / 100.0;
        assert_eq!(per_step, f64::from(info.evals), "{}", info.name);
    }
}

#[test]
fn evaluation_counts_on_the_damped_spring() {
    // Velocity-dependent forces cost extra evaluations where a method re-evaluates at a
    // new velocity, never fewer than the registry's count.
    for info in &INFOS {
        let mut scene = scenes::build("spring", &[("c", 1.0)], info.name, 0.1).unwrap();
        let w = &mut scene.world;
        w.step(1).unwrap();
        let before = w.evals();
        w.step(100).unwrap();
        let total = w.evals() - before;
        assert_eq!(total % 100, 0, "{}: {total} evaluations in 100 steps", info.name);
        assert!(total / 100 >= u64::from(info.evals), "{}: {} per step", info.name, total / 100);
    }
}

// ---------------------------------------------------------------- stage logs

#[test]
fn midpoint_logs_its_half_step() {
    let mut scene = scenes::build("spring", &[], "midpoint", 0.1).unwrap();
    let w = &mut scene.world;
    w.step(3).unwrap();
    let (t, x, v, a) = (w.time(), w.positions()[0], w.velocities()[0], w.accelerations().unwrap()[0]);
    assert!(v != 0.0);
    let dt = 0.25;
    let mut log = StageLog::default();
    w.step_logged(dt, &mut log).unwrap();
    assert_eq!(log.rows.len(), 1, "{log:?}");
    let row = &log.rows[0];
    assert_eq!(row.stage, "half");
    assert_eq!(row.t, t + dt / 2.0);
    assert_eq!(row.y, vec![x + v * (dt / 2.0), v + a * (dt / 2.0)]);
    // The derivative there: [v_half, a(x_half)] with a = -(k/m) x = -x / 2.
    assert_eq!(row.f[0], row.y[1]);
    assert!((row.f[1] + 0.5 * row.y[0]).abs() < 1e-12, "{row:?}");
    // The step used it: x += v_half dt, v += a_half dt.
    assert_eq!(w.positions()[0], x + dt * row.f[0]);
    assert_eq!(w.velocities()[0], v + dt * row.f[1]);
    assert_eq!(w.steps(), 4);
}

#[test]
fn rk4_logs_xa_xb_xc_as_computed_by_hand() {
    // x0 = 20, v0 = 0, a = -x/2, dt = 1.
    // k1 = (0, -10); xa = y + k1/2 = (20, -5), f(xa) = (-5, -10);
    // xb = y + f(xa)/2 = (17.5, -5), f(xb) = (-5, -8.75);
    // xc = y + f(xb) = (15, -8.75), f(xc) = (-8.75, -7.5);
    // y1 = y + (k1 + 2 f(xa) + 2 f(xb) + f(xc)) / 6 = (20 - 28.75/6, -55/6).
    let mut scene = scenes::build("spring", &[], "rk4", 1.0).unwrap();
    let w = &mut scene.world;
    let mut log = StageLog::default();
    w.step_logged(1.0, &mut log).unwrap();
    let want: [(&str, f64, [f64; 2], [f64; 2]); 3] = [
        ("xa", 0.5, [20.0, -5.0], [-5.0, -10.0]),
        ("xb", 0.5, [17.5, -5.0], [-5.0, -8.75]),
        ("xc", 1.0, [15.0, -8.75], [-8.75, -7.5]),
    ];
    assert_eq!(log.rows.len(), 3, "{log:?}");
    for (row, (stage, t, y, f)) in log.rows.iter().zip(want) {
        assert_eq!(row.stage, stage);
        assert_eq!(row.t, t, "{stage}");
        for k in 0..2 {
            assert!((row.y[k] - y[k]).abs() < 1e-12, "{stage} y: {:?} vs {y:?}", row.y);
            assert!((row.f[k] - f[k]).abs() < 1e-12, "{stage} f: {:?} vs {f:?}", row.f);
        }
    }
    assert!((w.positions()[0] - (20.0 - 28.75 / 6.0)).abs() < 1e-12, "{}", w.positions()[0]);
    assert!((w.velocities()[0] + 55.0 / 6.0).abs() < 1e-12, "{}", w.velocities()[0]);
    assert!((w.accelerations().unwrap()[0] + 0.5 * w.positions()[0]).abs() < 1e-12);
    // A second logged step logs three fresh rows, at t = 1.5, 1.5, 2.
    let mut log = StageLog::default();
    w.step_logged(1.0, &mut log).unwrap();
    assert_eq!(
        log.rows.iter().map(|r| (r.stage, r.t)).collect::<Vec<_>>(),
        [("xa", 1.5), ("xb", 1.5), ("xc", 2.0)]
    );
}

#[test]
fn logged_and_plain_steps_agree() {
    for info in &INFOS {
        let mut a = scenes::build("spring", &[("c", 0.5)], info.name, 0.1).unwrap().world;
        let mut b = a.clone();
        for _ in 0..25 {
            a.step(1).unwrap();
            b.step_logged(0.1, &mut StageLog::default()).unwrap();
        }
        assert_eq!(a.state_hash(), b.state_hash(), "{}", info.name);
    }
}

// ---------------------------------------------------------------- divergence

#[test]
fn stiff_explicit_euler_diverges_and_rolls_back() {
    let mut scene = scenes::build("spring", &[("k", 1e12)], "explicit-euler", 1.0).unwrap();
    let w = &mut scene.world;
    let mut good_steps = 0;
    let err = loop {
        let (hash, x, v, t) = (w.state_hash(), w.positions().to_vec(), w.velocities().to_vec(), w.time());
        match w.step(1) {
            Ok(()) => good_steps += 1,
            Err(e) => {
                assert_eq!(w.state_hash(), hash);
                assert_eq!(w.positions()[0].to_bits(), x[0].to_bits());
                assert_eq!(w.velocities()[0].to_bits(), v[0].to_bits());
                assert_eq!(w.time().to_bits(), t.to_bits());
                break e;
            }
        }
        assert!(good_steps < 20, "no divergence");
    };
    // omega dt = 3e5: the state grows about 3e5-fold per step and runs away past 1e100.
    assert!(good_steps >= 5, "{good_steps}");
    match &err {
        Error::Diverged { method, step, .. } => {
            assert_eq!(method, "explicit-euler");
            assert_eq!(*step, good_steps);
        }
        other => panic!("expected Diverged, got {other:?}"),
    }
    assert!(err.to_string().contains("explicit-euler"), "{err}");
    assert_eq!(w.steps(), good_steps);
    // Recovers with a dt it can take.
    w.set_dt(1e-9).unwrap();
    w.step(1).unwrap();
}

/// A spring whose acceleration turns NaN once `poison` is set.
#[derive(Clone)]
struct Poisoned {
    poison: bool,
}

impl SecondOrder for Poisoned {
    fn len(&self) -> usize {
        1
    }
    fn accel(&mut self, _t: f64, x: &[f64], _v: &[f64], a: &mut [f64]) {
        a[0] = if self.poison { f64::NAN } else { -0.5 * x[0] };
    }
    fn velocity_dependent(&self) -> bool {
        false
    }
}

fn bits(s: &State) -> (u64, Vec<u64>, Vec<u64>, u64) {
    (
        s.t.to_bits(),
        s.y.iter().map(|v| v.to_bits()).collect(),
        s.f.iter().map(|v| v.to_bits()).collect(),
        s.steps,
    )
}

#[test]
fn a_nan_force_fails_the_step_and_leaves_the_state_bitwise_unchanged() {
    for info in &INFOS {
        let mut sys = Poisoned { poison: false };
        let mut integ = Integrator::new(info.name).unwrap();
        let mut state = State::second(&mut sys, 0.0, &[20.0], &[0.0]).unwrap();
        for _ in 0..5 {
            integ.step(&mut sys, &mut state, 0.1).unwrap();
        }
        let before = bits(&state);
        let memory = integ.memory();
        // A twin that never sees the failed step.
        let mut twin = integ.clone();
        let mut twin_state = state.clone();
        sys.poison = true;
        let err = integ.step(&mut sys, &mut state, 0.1).unwrap_err();
        assert_eq!(bits(&state), before, "{}: state changed", info.name);
        match &err {
            Error::Diverged { method, step, t, .. } => {
                assert_eq!(method, info.name);
                assert_eq!(*step, 5);
                assert_eq!(t.to_bits(), f64::from_bits(before.0).to_bits());
            }
            // Newton meets the NaN residual first.
            Error::NotConverged { method, .. } if info.implicit => assert_eq!(method, info.name),
            other => panic!("{}: expected Diverged, got {other:?}", info.name),
        }
        assert!(err.to_string().contains(info.name), "{err}");
        // The method's memory is rolled back bitwise too (on a World: tests/it/restore_and_rollback.rs).
        let mem_bits = |m: Vec<f64>| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(mem_bits(integ.memory()), mem_bits(memory), "{}: memory changed", info.name);
        // Un-poisoned, the next step goes on exactly as an uninterrupted run would.
        sys.poison = false;
        integ.step(&mut sys, &mut state, 0.1).unwrap();
        twin.step(&mut sys, &mut twin_state, 0.1).unwrap();
        assert_eq!(bits(&state), bits(&twin_state), "{}", info.name);
    }
}

#[test]
fn explicit_methods_report_a_nan_force_as_diverged() {
    for info in INFOS.iter().filter(|i| !i.implicit) {
        let mut sys = Poisoned { poison: false };
        let mut state = State::second(&mut sys, 0.0, &[20.0], &[0.0]).unwrap();
        sys.poison = true;
        let err = Integrator::new(info.name).unwrap().step(&mut sys, &mut state, 0.1).unwrap_err();
        assert!(matches!(&err, Error::Diverged { method, step: 0, .. } if method == info.name), "{err:?}");
    }
}

/// y' = -y, except that the derivative is NaN at the times in `bad` (a stage time inside a
/// step); counts how often a NaN was returned.
struct PoisonedTimes {
    bad: Vec<f64>,
    nans: u32,
}

impl FirstOrder for PoisonedTimes {
    fn len(&self) -> usize {
        1
    }
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        if self.bad.iter().any(|b| (t - b).abs() < 1e-12) {
            self.nans += 1;
            dy[0] = f64::NAN;
        } else {
            dy[0] = -y[0];
        }
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], j: &mut [f64]) -> bool {
        j[0] = -1.0;
        true
    }
}

#[test]
fn a_step_that_met_a_nan_never_succeeds() {
    // The NaN hides inside the step (at its middle, or at its end): whatever the method,
    // a step that evaluated a non-finite derivative must fail and roll back, not return a
    // finite but meaningless state.
    for bad in [0.05, 0.1] {
        for info in INFOS.iter().filter(|i| !i.split) {
            let mut sys = PoisonedTimes { bad: vec![bad], nans: 0 };
            let mut integ = Integrator::new(info.name).unwrap();
            let mut state = State::first(&mut sys, 0.0, &[1.0]).unwrap();
            let before = bits(&state);
            let r = integ.step_flow(&mut sys, &mut state, 0.1);
            if sys.nans > 0 {
                let err = r
                    .expect_err(&format!("{} met {} NaN(s) at t = {bad} and succeeded", info.name, sys.nans));
                assert!(err.to_string().contains(info.name), "{err}");
                assert_eq!(bits(&state), before, "{}", info.name);
            } else {
                r.unwrap();
                assert!((state.y[0] - (-0.1f64).exp()).abs() < 0.01, "{}", info.name);
            }
        }
    }
}

// ---------------------------------------------------------------- determinism

#[test]
fn runs_are_bitwise_deterministic() {
    for info in &INFOS {
        for overrides in [&[][..], &[("c", 0.7)][..]] {
            let a = spring(info.name, 0.05, 1000, overrides);
            let b = spring(info.name, 0.05, 1000, overrides);
            assert_eq!(a.positions()[0].to_bits(), b.positions()[0].to_bits(), "{}", info.name);
            assert_eq!(a.velocities()[0].to_bits(), b.velocities()[0].to_bits(), "{}", info.name);
            assert_eq!(a.state_hash(), b.state_hash());
            assert_eq!(a.evals(), b.evals());
        }
    }
    // A many-body scene (parallel force loops) too, with an explicit and an implicit method.
    for method in ["velocity-verlet", "rk4", "yoshida4", "backward-euler"] {
        let run = || {
            let mut s = scenes::build("nbody", &[("n", 24.0)], method, 0.005).unwrap();
            s.world.step(50).unwrap();
            s.world.positions().iter().map(|p| p.to_bits()).collect::<Vec<_>>()
        };
        assert_eq!(run(), run(), "{method}");
    }
}
