//! Methods are written once against parts: a part none of them was written for runs under
//! every method that applies to it, at the method's order, and the others refuse it.
//!
//! The part is a planar rotor on a torsion spring (a pendulum in disguise): its position is
//! an orientation stored as the unit complex number `(cos q, sin q)` (two numbers, not a
//! vector space: a drift rotates it, `project` renormalises it), its velocity is the angular
//! momentum `L` (one number), and a kick adds the torque `-k sin q`. So `X` and `V` have
//! different lengths and a drift is not `x += h v`, as for the rigid bodies to come.

use physstep::dynamics::System;
use physstep::prelude::*;

/// The rotor: inertia `i`, torque `-k sin q`.
struct Rotor {
    i: f64,
    k: f64,
}

impl System for Rotor {
    fn dim(&self) -> usize {
        3
    }
    fn split(&self) -> Option<usize> {
        Some(2)
    }
    fn jacobian(&mut self, _t: f64, _y: &[f64], _j: &mut [f64], _work: &mut Vec<f64>) -> bool {
        false
    }
    fn accel(&mut self, _t: f64, x: &[f64], _w: &[f64], a: &mut [f64]) {
        a[0] = -self.k * x[1];
    }
    fn drift(&mut self, x: &mut [f64], w: &[f64], h: f64) {
        let (s, c) = (h * w[0] / self.i).sin_cos();
        let (x0, x1) = (x[0], x[1]);
        x[0] = c * x0 - s * x1;
        x[1] = s * x0 + c * x1;
    }
    fn rate(&self, x: &[f64], v: &[f64], dx: &mut [f64]) {
        let omega = v[0] / self.i;
        dx[0] = -omega * x[1];
        dx[1] = omega * x[0];
    }
    fn velocity_dependent(&self) -> bool {
        false
    }
    fn vector_positions(&self) -> bool {
        false
    }
    fn project(&mut self, y: &mut [f64]) -> bool {
        let r = y[0].hypot(y[1]);
        y[0] /= r;
        y[1] /= r;
        r != 1.0
    }
}

impl Rotor {
    fn energy(&self, y: &[f64]) -> f64 {
        0.5 * y[2] * y[2] / self.i - self.k * y[0]
    }
}

const ROTOR: Rotor = Rotor { i: 2.0, k: 3.0 };
const Q0: f64 = 1.2;
const L0: f64 = 0.5;

/// The rotor's state at angle `Q0` and momentum `L0`, with its derivative.
fn start(sys: &mut Rotor) -> State {
    let y = vec![Q0.cos(), Q0.sin(), L0];
    let mut f = vec![0.0; 3];
    sys.deriv(0.0, &y, &mut f);
    State { t: 0.0, y, f, steps: 0, evals: 1 }
}

/// The angle after `n` steps of `dt` with `method`.
fn run(method: &str, dt: f64, n: u64) -> (f64, State) {
    let mut sys = Rotor { ..ROTOR };
    let mut integ = Integrator::new(method).unwrap();
    let mut state = start(&mut sys);
    for _ in 0..n {
        integ.advance(&mut sys, &mut state, dt, None).unwrap();
        integ.check(&state, physstep::integrators::registry::Layout::First).unwrap();
        state.t += dt;
    }
    (state.y[1].atan2(state.y[0]), state)
}

#[test]
fn every_method_that_applies_runs_the_rotor_at_its_order() {
    let t_end = 4.0;
    let (exact, _) = run("rk4", t_end / 64_000.0, 64_000);
    let mut failures = Vec::new();
    for info in INFOS.iter().filter(|i| !i.vector_positions) {
        let dts: Vec<f64> = (0..3).map(|k| 0.05 / f64::from(1u32 << k)).collect();
        let errors: Vec<f64> = dts
            .iter()
            .map(|&dt| {
                let n = (t_end / dt).round() as u64;
                let (q, state) = run(info.name, dt, n);
                let unit = state.y[0].hypot(state.y[1]);
                assert!((unit - 1.0).abs() < 1e-14, "{}: |x| = {unit}", info.name);
                (q - exact).abs()
            })
            .collect();
        let p = (errors[0] / errors[2]).log2() / 2.0;
        if (p - f64::from(info.order)).abs() > 0.2 {
            failures.push(format!("{}: order {p:.3}, expected {} ({errors:?})", info.name, info.order));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The largest energy error over the first and over the last tenth of `n` steps of `dt`.
fn energy_drift(method: &str, dt: f64, n: u64) -> (f64, f64) {
    let mut sys = Rotor { ..ROTOR };
    let mut integ = Integrator::new(method).unwrap();
    let mut state = start(&mut sys);
    let e0 = sys.energy(&state.y);
    let (mut early, mut late) = (0.0f64, 0.0f64);
    for k in 0..n {
        integ.advance(&mut sys, &mut state, dt, None).unwrap();
        state.t += dt;
        let de = (sys.energy(&state.y) - e0).abs();
        if k < n / 10 {
            early = early.max(de);
        } else if k >= n - n / 10 {
            late = late.max(de);
        }
    }
    (early, late)
}

#[test]
fn symplectic_split_methods_keep_the_rotors_energy_bounded() {
    for info in INFOS.iter().filter(|i| i.split && !i.vector_positions) {
        let (early, late) = energy_drift(info.name, 0.05, 20_000);
        assert!(late < 1.5 * early, "{}: energy error {early:.2e} early, {late:.2e} late", info.name);
    }
    // The contrast that shows the check can fail: explicit Euler's error grows.
    let (early, late) = energy_drift("explicit-euler", 0.05, 20_000);
    assert!(late > 3.0 * early, "explicit-euler: {early:.2e} early, {late:.2e} late");
}

#[test]
fn a_method_that_needs_vector_positions_refuses_the_rotor_before_moving_it() {
    let mut sys = Rotor { ..ROTOR };
    let mut integ = Integrator::new("verlet").unwrap();
    let mut state = start(&mut sys);
    let before = state.clone();
    let err = integ.advance(&mut sys, &mut state, 0.1, None).unwrap_err();
    assert!(matches!(err, Error::Unsupported { .. }), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("verlet") && msg.contains("vectors"), "{msg}");
    assert_eq!(state, before);
    assert!(integ.applies(&sys).is_err());
    assert!(Integrator::new("velocity-verlet").unwrap().applies(&sys).is_ok());
}
