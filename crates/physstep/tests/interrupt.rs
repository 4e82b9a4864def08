//! A stop requested (`physstep::interrupt`, what Ctrl-C does through the bindings) is heard
//! inside a step of n-body gravity: the step is rolled back bitwise, the call answers
//! `Error::Interrupted`, and once the request is withdrawn the world steps on exactly as one
//! never stopped. (Its own test binary: the request is process-wide.)

use physstep::error::Error;
use physstep::scenes;

#[test]
fn a_requested_stop_rolls_the_step_back_and_the_run_goes_on_bitwise() {
    let build = || scenes::build("nbody", &[("n", 300.0)], "leapfrog", 0.001).unwrap().world;
    let mut w = build();
    w.step(3).unwrap();
    let before = w.state_hash();
    physstep::interrupt::request();
    let r = w.step(5);
    assert!(physstep::interrupt::clear());
    assert_eq!(r, Err(Error::Interrupted { step: 3 }));
    assert_eq!(r.unwrap_err().to_string(), "interrupted after step 3; the step under way was rolled back");
    assert_eq!((w.steps(), w.state_hash()), (3, before));
    w.step(5).unwrap();
    let mut reference = build();
    reference.step(8).unwrap();
    assert_eq!(w.state_hash(), reference.state_hash());
    assert_eq!(w.positions(), reference.positions());
}
