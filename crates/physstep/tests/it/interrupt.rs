//! A stop requested (`physstep::interrupt`, what Ctrl-C does through the bindings) is heard
//! inside a step of n-body gravity: the step is rolled back bitwise, the call answers
//! `Error::Interrupted`, and once the request is withdrawn the world steps on exactly as one
//! never stopped. The request is process-wide: the test runs in a process of its own, this
//! test harness started again on this one test.

use physstep::error::Error;
use physstep::scenes;

/// Set in the process that runs the test's body.
const ALONE: &str = "PHYSSTEP_TEST_ALONE";

#[test]
fn a_requested_stop_rolls_the_step_back_and_the_run_goes_on_bitwise() {
    if std::env::var_os(ALONE).is_none() {
        // This harness again, on this test alone (the path without the crate's name).
        let path = module_path!().split_once("::").map_or(module_path!(), |(_, p)| p);
        let name = format!("{path}::a_requested_stop_rolls_the_step_back_and_the_run_goes_on_bitwise");
        let out = std::process::Command::new(std::env::current_exe().unwrap())
            .args([name.as_str(), "--exact", "--test-threads=1"])
            .env(ALONE, "1")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
        assert!(stdout.contains("1 passed"), "the test did not run alone: {stdout}");
        return;
    }
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
