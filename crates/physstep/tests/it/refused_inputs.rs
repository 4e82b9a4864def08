//! Inputs refused with one line naming the field and its value: a dt that cannot advance the
//! time, a mass whose inverse is not finite, a name holding a newline, a recording too large.

use physstep::prelude::*;
use physstep::record::{RecordParams, Recorder};

#[test]
fn a_dt_that_cannot_advance_time_is_refused() {
    let e = World::new(WorldParams { dt: 1e-310, ..Default::default() }).unwrap_err();
    assert!(e.to_string().starts_with("invalid dt = 1e-310: must be at least max_frame_time / 2^53"), "{e}");
    // A step below the resolution of the current time is refused, the world unchanged.
    let mut w = World::new(WorldParams { dim: 1, ..Default::default() }).unwrap();
    w.add_particle(&[0.0], &[1.0], 1.0, false).unwrap();
    w.step_by(1e9).unwrap();
    let hash = w.state_hash();
    let e = w.step_by(1e-9).unwrap_err();
    assert!(e.to_string().contains("large enough to advance the time t = 1000000000"), "{e}");
    assert_eq!(w.state_hash(), hash);
    assert_eq!(w.steps(), 1);
}

#[test]
fn masses_whose_inverse_is_not_finite_are_refused() {
    let mut w = World::new(WorldParams { dim: 1, ..Default::default() }).unwrap();
    for m in [5e-324, 1e-310] {
        let e = w.add_particle(&[0.0], &[0.0], m, false).unwrap_err();
        assert!(e.to_string().contains("with a finite inverse"), "{e}");
    }
    assert!(w.is_empty());
    w.add_particle(&[0.0], &[0.0], physstep::world::MIN_MASS, false).unwrap();
}

#[test]
fn a_name_with_a_newline_makes_a_one_line_error() {
    let e = Integrator::new("rk\n4").unwrap_err().to_string();
    assert!(!e.contains('\n') && e.contains("'rk\\n4'"), "{e}");
    let e = scenes::build("spring", &[("k\nx", 1.0)], "rk4", 0.1).unwrap_err().to_string();
    assert!(!e.contains('\n'), "{e}");
}

#[test]
fn a_recording_too_large_names_until_not_every() {
    let mut s = scenes::build("nbody", &[], "leapfrog", 0.001).unwrap();
    let params = RecordParams { dt: 0.001, until: 1e5, every: 1, stages: false, stop_on_diverge: false };
    let e = Recorder::new(&mut s.world, params).unwrap_err().to_string();
    assert!(e.starts_with("invalid until = 100000: must be such that the recording fits in memory"), "{e}");
    let params = RecordParams { dt: 0.001, until: 1e12, every: 1, stages: false, stop_on_diverge: false };
    let e = Recorder::new(&mut s.world, params).unwrap_err().to_string();
    assert!(e.starts_with("invalid until = 1000000000000: must be at most 1e9 steps"), "{e}");
}

#[test]
fn huge_numbers_in_messages_are_shown_with_an_exponent() {
    // `until = 1e308` was shown as 309 digits; the docs promise exponents.
    let mut w = physstep::scenes::build("spring", &[], "rk4", 0.1).unwrap().world;
    let rp = physstep::record::RecordParams {
        dt: 0.1,
        until: 1e308,
        every: 1,
        stages: false,
        stop_on_diverge: false,
    };
    let e = physstep::record::Recorder::new(&mut w, rp).err().unwrap().to_string();
    assert!(e.starts_with("invalid until = 1e308: "), "{e}");
    assert!(e.len() < 120, "{e}");
    // The time of a divergence too.
    let d = physstep::Error::Diverged {
        method: "rk4".into(),
        step: 3,
        t: 1e300,
        index: 0,
        particle: Some(0),
        body: None,
        solid: None,
    };
    assert!(d.to_string().starts_with("method 'rk4' diverged at step 3 (t = 1e300): "), "{d}");
    let nf = physstep::Error::NonFinite {
        method: "rk4".into(),
        quantity: "energy".into(),
        value: f64::INFINITY,
        step: 3,
        t: 2.5e20,
    };
    assert!(nf.to_string().contains("the energy is inf after step 3 (t = 2.5e20)"), "{nf}");
}
