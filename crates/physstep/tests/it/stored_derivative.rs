//! Steps from the stored derivative (`Integrate::Given`): particles under forces the fused
//! kernel cannot take (a user force, springs between particles, n-body gravity), stepped by
//! a method that reads only the derivative at its start, or by one that evaluates forces
//! ignoring the velocity once at a point of its own (velocity Verlet), give bitwise what the
//! staged step gives, for every method, serial and parallel; a failure inside a call of
//! `step(n)` (a failing user force, accelerations or a state past the limit) is the staged
//! step's, rolled back to the same bits. The helpers are `kernels.rs`'.

use super::kernels::{agree, bits, staged_failure, world};
use physstep::forces::{Endpoint, Force};
use physstep::integrators::{registry, StageLog};
use physstep::prelude::*;

/// A time-dependent, velocity-dependent user force (as a Python force is to the engine): it
/// fails at its `fail_at`-th call and blows a finite 1e150 N on entry 4 at its `blow_at`-th
/// (counted from 1; 0: never).
struct Wind {
    calls: std::sync::atomic::AtomicU64,
    fail_at: u64,
    blow_at: u64,
}

impl physstep::forces::ForceGenerator for Wind {
    fn name(&self) -> &str {
        "wind"
    }

    fn add_forces(&self, t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        let k = self.calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if k == self.fail_at {
            return Err(format!("gust {k}"));
        }
        for (i, ((fi, xi), vi)) in f.iter_mut().zip(x).zip(v).enumerate() {
            *fi += (3.0 * t + i as f64).sin() - 0.1 * vi + 0.01 * xi;
        }
        if k == self.blow_at {
            f[4] = 1e150;
        }
        Ok(())
    }
}

fn wind(fail_at: u64) -> std::sync::Arc<Wind> {
    std::sync::Arc::new(Wind { calls: 0.into(), fail_at, blow_at: 0 })
}

/// A time-dependent user force that does not read the velocity (so a method that evaluates
/// once at a point of its own, velocity Verlet, steps from the stored derivative under it);
/// failing and blowing as [`Wind`] does.
struct Swell(Wind);

impl physstep::forces::ForceGenerator for Swell {
    fn name(&self) -> &str {
        "swell"
    }

    fn add_forces(&self, t: f64, x: &[f64], _v: &[f64], f: &mut [f64]) -> Result<(), String> {
        let k = self.0.calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if k == self.0.fail_at {
            return Err(format!("surge {k}"));
        }
        for (i, (fi, xi)) in f.iter_mut().zip(x).enumerate() {
            *fi += (2.0 * t + i as f64).cos() - 0.7 * xi;
        }
        if k == self.0.blow_at {
            f[4] = 1e150;
        }
        Ok(())
    }

    fn velocity_dependent(&self) -> bool {
        false
    }
}

fn swell(fail_at: u64, blow_at: u64) -> std::sync::Arc<Swell> {
    std::sync::Arc::new(Swell(Wind { calls: 0.into(), fail_at, blow_at }))
}

/// Forces that are not per-particle (the fused kernel does not take them): springs between
/// particles, n-body gravity, a user force; each with gravity.
fn coupled(w: &mut World, which: &str) {
    let n = w.len();
    w.add_force(Force::Gravity { g: [0.3, -9.81, 1.5] }).unwrap();
    match which {
        "springs" => {
            for i in 0..n.saturating_sub(1) {
                let j = Endpoint::Particle(i + 1);
                w.add_force(Force::Spring { i, j, stiffness: 40.0, rest_length: 0.5, damping: 0.3 }).unwrap();
            }
        }
        "n-body" => {
            w.add_force(Force::NBody { g: 0.5, softening: 0.05 }).unwrap();
        }
        "user, position only" => {
            w.add_force_generator(swell(0, 0)).unwrap();
        }
        _ => {
            w.add_force_generator(wind(0)).unwrap();
        }
    }
}

/// Particles under forces that couple them or are the user's, stepped by a method whose step
/// reads only the derivative at its start (explicit and symplectic Euler: the element-wise
/// kernel from the stored accelerations, the forces evaluated at each step's end into a
/// derivative written beside the current one), agree bitwise with the staged step, as every
/// other method does; serial and parallel.
#[test]
fn steps_from_the_stored_derivative_match_the_staged_step_bitwise() {
    for info in registry::INFOS.iter() {
        for which in ["springs", "n-body", "user", "user, position only"] {
            for dim in 1..=3 {
                for (n, with_static) in [(1, false), (7, true), (37, false)] {
                    let mut a = world(info.name, dim, n, &[], with_static, false);
                    coupled(&mut a, which);
                    // (A clone shares the user force: its calls are counted together, and it
                    // reads only t, x and v.)
                    let mut b = a.clone();
                    let what = format!("{} under {which}, dim {dim}, n {n}", info.name);
                    agree(&mut a, &mut b, 25, &what);
                    agree(&mut a, &mut b, 1, &what);
                    agree(&mut a, &mut b, 3, &what);
                    // A staged step after them reads the whole derivative they left (explicit
                    // Euler's drift reads its velocity half).
                    let mut log = StageLog::default();
                    a.step_logged(a.dt(), &mut log).unwrap();
                    b.step_logged(b.dt(), &mut log).unwrap();
                    assert_eq!(bits(a.positions()), bits(b.positions()), "{what}: then staged");
                }
            }
        }
    }
    // Enough particles for the parallel tasks.
    for (method, which) in
        [("symplectic-euler", "user"), ("explicit-euler", "user"), ("velocity-verlet", "user, position only")]
    {
        let mut a = world(method, 3, 70_000, &[], false, false);
        coupled(&mut a, which);
        let mut b = a.clone();
        agree(&mut a, &mut b, 3, &format!("{method}, 70,000 particles"));
    }
}

/// After steps from the stored derivative (which leave the derivative's velocity half owed),
/// a switch to any other method steps on bitwise as a twin that took every step staged (the
/// staged methods read the whole derivative).
#[test]
fn any_method_after_steps_from_the_stored_derivative_steps_as_after_staged_ones() {
    for info in registry::INFOS.iter() {
        for which in ["user", "springs"] {
            let mut a = world("symplectic-euler", 2, 7, &[], true, false);
            coupled(&mut a, which);
            let mut b = a.clone();
            let what = format!("symplectic-euler then {} under {which}", info.name);
            agree(&mut a, &mut b, 5, &what);
            a.set_method(info.name).unwrap();
            b.set_method(info.name).unwrap();
            agree(&mut a, &mut b, 3, &format!("{what}: after the switch"));
        }
    }
}

/// A user force that fails or runs away, and a spring network that runs away, inside a call of `step(n)`
/// from the stored derivative: the failing step rolled back to the same bits, the same error,
/// as the staged step gives it.
#[test]
fn a_failure_stepping_from_the_stored_derivative_is_the_staged_one() {
    // Two of `make`'s world, one stepped by `step(n)`, one staged step by step, fail alike.
    let fails_alike = |make: &dyn Fn() -> World, n: u64, said: &str, what: &str| {
        let (mut a, mut b) = (make(), make());
        let ea = a.step(n).unwrap_err().to_string();
        let (good, eb) = staged_failure(&mut b, what);
        assert_eq!(ea, eb.to_string(), "{what}");
        assert!(ea.contains(said), "{what}: {ea}");
        assert_eq!((a.steps(), a.state_hash()), (good, b.state_hash()), "{what}");
        assert_eq!(bits(a.accelerations().unwrap()), bits(b.accelerations().unwrap()), "{what}");
    };
    for method in ["symplectic-euler", "explicit-euler"] {
        for fail_at in [1, 2, 6] {
            let make = || {
                let mut w = world(method, 2, 9, &[], false, false);
                w.add_force_generator(wind(fail_at)).unwrap();
                w
            };
            fails_alike(
                &make,
                10,
                "force 'wind' failed: gust",
                &format!("{method}, failing at call {fail_at}"),
            );
            // Accelerations past the runaway limit, found in the pass that sums them, with
            // equal and unequal masses.
            for equal in [true, false] {
                let make = || {
                    let mut w = world(method, 2, 9, &[], false, equal);
                    w.add_force_generator(std::sync::Arc::new(Wind {
                        calls: 0.into(),
                        fail_at: 0,
                        blow_at: fail_at,
                    }))
                    .unwrap();
                    w
                };
                let what = format!("{method}, running away at call {fail_at}, equal masses {equal}");
                fails_alike(&make, 10, "diverged", &what);
            }
        }
        let make = || {
            let mut w = world(method, 3, 12, &[], false, false);
            for i in 0..11 {
                let j = Endpoint::Particle(i + 1);
                w.add_force(Force::Spring { i, j, stiffness: 1e9, rest_length: 0.1, damping: 0.0 }).unwrap();
            }
            w
        };
        fails_alike(&make, 100_000, "diverged", &format!("{method}: the runaway"));
    }
    // Velocity Verlet under a force that does not read the velocity (from the point where it
    // evaluates): a failing force, accelerations past the limit, and (undamped stiff springs)
    // a state that runs away after the evaluation.
    for at in [1, 2, 6] {
        for (fail_at, blow_at, said) in [(at, 0, "force 'swell' failed: surge"), (0, at, "diverged")] {
            let make = || {
                let mut w = world("velocity-verlet", 2, 9, &[], false, false);
                w.add_force_generator(swell(fail_at, blow_at)).unwrap();
                w
            };
            fails_alike(
                &make,
                10,
                said,
                &format!("velocity-verlet, failing ({fail_at}) or blowing ({blow_at})"),
            );
        }
    }
    let make = || {
        let mut w = world("velocity-verlet", 3, 12, &[], false, false);
        for i in 0..11 {
            let j = Endpoint::Particle(i + 1);
            w.add_force(Force::Spring { i, j, stiffness: 1e9, rest_length: 0.1, damping: 0.0 }).unwrap();
        }
        w
    };
    fails_alike(&make, 100_000, "diverged", "velocity-verlet: the runaway");
}
