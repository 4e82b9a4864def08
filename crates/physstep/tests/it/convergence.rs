//! Observed order of accuracy of every registered method: on the notes' spring (undamped and
//! damped, through the world) and, for the flow methods, on first-order flows stepped by
//! [`Integrator::step_flow`].

use super::common::{slope, spring};
use physstep::prelude::*;

/// End time of every convergence run, s.
const T_END: f64 = 10.0;
/// How far the observed order may be from `INFO.order`.
const TOL: f64 = 0.15;

/// dt = 0.1 / 2^k for k = 0..4: 100, 200, 400 and 800 steps to t = 10 (all even, as the
/// alternating symplectic Euler needs).
fn dts() -> Vec<f64> {
    (0..4).map(|k| 0.1 / f64::from(1u32 << k)).collect()
}

/// Errors in short scientific notation, for failure messages.
fn sci(errors: &[f64]) -> String {
    errors.iter().map(|e| format!("{e:.3e}")).collect::<Vec<_>>().join(", ")
}

fn steps_for(dt: f64) -> u64 {
    let n = (T_END / dt).round() as u64;
    assert_eq!(n % 2, 0, "step counts stay even");
    n
}

/// Position errors at t = 10 of `method` on the spring with `overrides`, one per dt.
fn spring_errors(method: &str, overrides: &[(&str, f64)]) -> Vec<f64> {
    let exact = scenes::build("spring", overrides, method, 0.1).unwrap().exact(T_END).unwrap().0[0];
    dts()
        .iter()
        .map(|&dt| {
            let w = spring(method, dt, steps_for(dt), overrides);
            assert_eq!(w.steps(), steps_for(dt));
            assert!((w.time() - T_END).abs() < 1e-9, "{method}: t = {}", w.time());
            (w.positions()[0] - exact).abs()
        })
        .collect()
}

fn check_spring_orders(overrides: &[(&str, f64)]) {
    let mut failures = Vec::new();
    for info in &INFOS {
        let errors = spring_errors(info.name, overrides);
        assert!(errors.iter().all(|e| e.is_finite() && *e > 0.0), "{}: errors {errors:?}", info.name);
        let p = slope(&dts(), &errors);
        if (p - f64::from(info.order)).abs() > TOL {
            failures.push(format!(
                "{}: observed order {p:.3}, INFO.order {} (errors {})",
                info.name,
                info.order,
                sci(&errors)
            ));
        }
    }
    assert!(failures.is_empty(), "spring {overrides:?}:\n{}", failures.join("\n"));
}

#[test]
fn every_method_has_its_order_on_the_undamped_spring() {
    check_spring_orders(&[]);
}

#[test]
fn every_method_has_its_order_on_the_damped_spring() {
    // c = 1: zeta ~ 0.07, velocity-dependent force (the methods' `again` paths).
    check_spring_orders(&[("c", 1.0)]);
}

#[test]
fn the_slope_helper_recovers_a_known_order() {
    let d = dts();
    let e: Vec<f64> = d.iter().map(|h| 3.0 * h.powi(3)).collect();
    assert!((slope(&d, &e) - 3.0).abs() < 1e-12);
}

/// y' = -y + sin t, y(0) = 1: non-autonomous, no analytic Jacobian (the implicit methods use
/// finite differences). Exact y = 3/2 e^-t + (sin t - cos t) / 2.
struct Forced;

impl FirstOrder for Forced {
    fn len(&self) -> usize {
        1
    }
    fn deriv(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = -y[0] + t.sin();
    }
}

fn forced_exact(t: f64) -> Vec<f64> {
    vec![1.5 * (-t).exp() + 0.5 * (t.sin() - t.cos())]
}

/// The rotation y1' = y2, y2' = -y1 from (1, 0), with its analytic Jacobian. Exact
/// (cos t, -sin t).
struct Rotation;

impl FirstOrder for Rotation {
    fn len(&self) -> usize {
        2
    }
    fn deriv(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = -y[0];
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], j: &mut [f64]) -> bool {
        j.copy_from_slice(&[0.0, 1.0, -1.0, 0.0]);
        true
    }
}

fn rotation_exact(t: f64) -> Vec<f64> {
    vec![t.cos(), -t.sin()]
}

/// Runs `name` on `sys` from `y0` to t = 10 at `dt`; returns the final state.
fn run_flow<F: FirstOrder>(name: &str, sys: &mut F, y0: &[f64], dt: f64) -> State {
    let mut integ = Integrator::new(name).unwrap();
    let mut state = State::first(sys, 0.0, y0).unwrap();
    for _ in 0..steps_for(dt) {
        integ.step_flow(sys, &mut state, dt).unwrap();
    }
    assert_eq!(state.steps, steps_for(dt));
    state
}

fn flow_order<F: FirstOrder>(
    name: &str,
    mut make: impl FnMut() -> F,
    y0: &[f64],
    exact: fn(f64) -> Vec<f64>,
) -> (f64, Vec<f64>) {
    let want = exact(T_END);
    let errors: Vec<f64> = dts()
        .iter()
        .map(|&dt| {
            let s = run_flow(name, &mut make(), y0, dt);
            s.y.iter().zip(&want).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
        })
        .collect();
    (slope(&dts(), &errors), errors)
}

#[test]
fn flow_methods_have_their_order_on_first_order_flows() {
    let mut failures = Vec::new();
    for info in INFOS.iter().filter(|i| !i.split) {
        for (flow, (p, errors)) in [
            ("forced decay", flow_order(info.name, || Forced, &[1.0], forced_exact)),
            ("rotation", flow_order(info.name, || Rotation, &[1.0, 0.0], rotation_exact)),
        ] {
            if !(p - f64::from(info.order)).abs().le(&TOL) {
                failures.push(format!(
                    "{} on {flow}: observed {p:.3}, INFO.order {} ({})",
                    info.name,
                    info.order,
                    sci(&errors)
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn flow_steps_count_evaluations_and_keep_f_consistent() {
    for info in INFOS.iter().filter(|i| !i.split) {
        let mut sys = Rotation;
        let mut integ = Integrator::new(info.name).unwrap();
        let mut state = State::first(&mut sys, 0.0, &[1.0, 0.0]).unwrap();
        assert_eq!(state.evals, 1);
        for _ in 0..10 {
            integ.step_flow(&mut sys, &mut state, 0.1).unwrap();
        }
        assert_eq!(state.steps, 10);
        assert!((state.t - 1.0).abs() < 1e-12);
        // f is the derivative at the state's own (t, y).
        assert_eq!(state.f, vec![state.y[1], -state.y[0]], "{}", info.name);
        // The rotation is linear with an analytic Jacobian: the registry's count holds.
        assert_eq!(state.evals, 1 + 10 * u64::from(info.evals), "{}", info.name);
    }
}

#[test]
fn split_methods_refuse_first_order_flows() {
    for info in INFOS.iter().filter(|i| i.split) {
        let mut sys = Rotation;
        let mut integ = Integrator::new(info.name).unwrap();
        let mut state = State::first(&mut sys, 0.0, &[1.0, 0.0]).unwrap();
        let before = state.clone();
        let err = integ.step_flow(&mut sys, &mut state, 0.1).unwrap_err();
        match &err {
            Error::Unsupported { method, .. } => assert_eq!(method, info.name),
            other => panic!("{}: expected Unsupported, got {other:?}", info.name),
        }
        assert!(err.to_string().contains(info.name), "{err}");
        assert_eq!(state, before, "{}: state untouched", info.name);
    }
}

#[test]
fn flow_methods_reject_bad_dt_on_flows() {
    for info in INFOS.iter().filter(|i| !i.split) {
        let mut sys = Forced;
        let mut integ = Integrator::new(info.name).unwrap();
        let mut state = State::first(&mut sys, 0.0, &[1.0]).unwrap();
        for dt in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let err = integ.step_flow(&mut sys, &mut state, dt).unwrap_err();
            assert!(
                matches!(&err, Error::InvalidValue { field, .. } if field == "dt"),
                "{}: {err:?}",
                info.name
            );
        }
        assert_eq!(state.steps, 0);
    }
}
