//! First-order flows as a part of the world (issue 8): the attractors through the flow
//! methods, the split methods refused at configuration, user flows.

use physstep::flows::{Flow, FlowGenerator};
use physstep::prelude::*;
use std::sync::Arc;

#[test]
fn lorenz_converges_under_rk4() {
    // rk4 at dt = 1e-3 and 5e-4 agree to 1e-6 up to t = 5 (error ~ dt^4 times the growth of
    // perturbations, e^{0.9 t}).
    let run = |dt: f64| {
        let mut s = scenes::build("lorenz", &[], "rk4", dt).unwrap();
        let mut out = Vec::new();
        for _ in 0..10 {
            s.world.step((0.5 / dt).round() as u64).unwrap();
            out.push(s.world.positions().to_vec());
        }
        (s.world.time(), out)
    };
    let (ta, a) = run(1e-3);
    let (tb, b) = run(5e-4);
    assert!((ta - 5.0).abs() < 1e-12 && (tb - 5.0).abs() < 1e-12);
    for (pa, pb) in a.iter().zip(&b) {
        for (x, y) in pa.iter().zip(pb) {
            assert!((x - y).abs() < 1e-6, "{x} vs {y}");
        }
    }
}

#[test]
fn split_methods_are_refused_when_the_world_is_configured() {
    let e = scenes::build("rossler", &[], "leapfrog", 0.01).unwrap_err();
    assert_eq!(
        e.to_string(),
        "method 'leapfrog' needs a second-order system (positions and velocities); use a flow method such as rk4"
    );
    let mut s = scenes::build("thomas", &[], "rk4", 0.05).unwrap();
    assert!(s.world.set_method("velocity-verlet").is_err());
    assert_eq!(s.world.integrator().info().name, "rk4");
    assert!(s.world.add_particle(&[0.0, 0.0, 0.0], &[0.0, 0.0, 0.0], 1.0, false).is_err());
}

/// Exponential decay y' = -y, failing once y is small.
struct Decay;

impl FlowGenerator for Decay {
    fn deriv(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), String> {
        if y[0] < 0.5 {
            return Err("below one half".into());
        }
        dy[0] = -y[0];
        Ok(())
    }
}

#[test]
fn a_user_flow_steps_and_its_failure_rolls_back() {
    let flow = Flow::User { n: 1, generator: Arc::new(Decay) };
    let params = WorldParams { method: "rk4".into(), dt: 0.1, ..Default::default() };
    let mut w = World::with_flow(flow, &[1.0], params).unwrap();
    w.step(5).unwrap();
    assert!((w.positions()[0] - (-0.5f64).exp()).abs() < 1e-6);
    let e = loop {
        let h = w.state_hash();
        match w.step(1) {
            Ok(()) => {}
            Err(e) => {
                assert_eq!(w.state_hash(), h);
                break e;
            }
        }
    };
    assert!(e.to_string().contains("below one half"), "{e}");
}
