//! User forces through the `ForceGenerator` trait (issue 8).

use physstep::forces::ForceGenerator;
use physstep::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A zero-rest-length damped spring to the origin, written as a user force.
struct Spring {
    k: f64,
    c: f64,
}

impl ForceGenerator for Spring {
    fn add_forces(&self, _t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        for ((fi, xi), vi) in f.iter_mut().zip(x).zip(v) {
            *fi += -self.k * xi - self.c * vi;
        }
        Ok(())
    }

    fn potential(&self, x: &[f64]) -> Option<f64> {
        Some(0.5 * self.k * x.iter().map(|c| c * c).sum::<f64>())
    }

    fn jacobian(&self, _t: f64, x: &[f64], _v: &[f64], dfdx: &mut [f64], dfdv: &mut [f64]) -> bool {
        let n = x.len();
        for i in 0..n {
            dfdx[i * n + i] -= self.k;
            dfdv[i * n + i] -= self.c;
        }
        true
    }
}

fn world(method: &str, user: bool) -> World {
    let mut w =
        World::new(WorldParams { dim: 2, method: method.into(), dt: 0.1, ..Default::default() }).unwrap();
    w.add_particle(&[20.0, -3.0], &[0.0, 1.0], 10.0, false).unwrap();
    if user {
        w.add_force_generator(Arc::new(Spring { k: 5.0, c: 0.5 })).unwrap();
    } else {
        let spring = Force::Spring {
            i: 0,
            j: Endpoint::Anchor([0.0; 3]),
            stiffness: 5.0,
            rest_length: 0.0,
            damping: 0.5,
        };
        w.add_force(spring).unwrap();
    }
    w
}

#[test]
fn a_user_spring_gives_the_built_in_trajectory_for_every_method() {
    for info in &INFOS {
        let (mut a, mut b) = (world(info.name, false), world(info.name, true));
        a.step(300).unwrap();
        b.step(300).unwrap();
        for (p, q) in a.positions().iter().zip(b.positions()) {
            assert!((p - q).abs() <= 1e-12 * 20.0, "{}: {p} vs {q}", info.name);
        }
        let (ea, eb) = (a.energy().unwrap(), b.energy().unwrap());
        assert!((ea - eb).abs() <= 1e-12 * ea.abs(), "{}", info.name);
    }
}

/// Fails once `armed`.
struct Flaky(Arc<AtomicBool>);

impl ForceGenerator for Flaky {
    fn name(&self) -> &str {
        "flaky"
    }

    fn add_forces(&self, _t: f64, _x: &[f64], _v: &[f64], _f: &mut [f64]) -> Result<(), String> {
        if self.0.load(Ordering::Relaxed) {
            Err("sensor offline".into())
        } else {
            Ok(())
        }
    }
}

#[test]
fn a_failing_user_force_rolls_the_step_back_and_is_named() {
    for method in ["leapfrog", "rk4", "backward-euler"] {
        let mut w = world(method, true);
        let armed = Arc::new(AtomicBool::new(false));
        w.add_force_generator(Arc::new(Flaky(armed.clone()))).unwrap();
        w.step(5).unwrap();
        let (hash, steps) = (w.state_hash(), w.steps());
        armed.store(true, Ordering::Relaxed);
        let e = w.step(1).unwrap_err();
        assert_eq!(e.to_string(), "force 'flaky' failed: sensor offline; step rolled back", "{method}");
        assert_eq!((w.state_hash(), w.steps()), (hash, steps), "{method}");
        armed.store(false, Ordering::Relaxed);
        w.step(1).unwrap();
    }
}

#[test]
fn a_user_force_without_a_potential_leaves_the_energy_unknown() {
    let mut w = world("rk4", false);
    assert!(w.energy().is_some());
    w.add_force_generator(Arc::new(Flaky(Arc::new(AtomicBool::new(false))))).unwrap();
    assert!(w.energy().is_none());
}

/// Hands `forces_to` a slice of its own (as the Python forces do): `len` entries of `value`,
/// or nothing at all when `len` is `None`.
struct Handing {
    len: Option<usize>,
    value: f64,
}

impl ForceGenerator for Handing {
    fn name(&self) -> &str {
        "handing"
    }

    fn add_forces(&self, _t: f64, _x: &[f64], _v: &[f64], f: &mut [f64]) -> Result<(), String> {
        f.iter_mut().for_each(|c| *c += self.value);
        Ok(())
    }

    fn forces_to(
        &self,
        _t: f64,
        _x: &[f64],
        _v: &[f64],
        _scratch: &mut Vec<f64>,
        take: &mut dyn FnMut(&[f64]),
    ) -> Result<(), String> {
        if let Some(len) = self.len {
            take(&vec![self.value; len]);
        }
        Ok(())
    }
}

/// Always zero, with its (zero) jacobian: the implicit methods then use the spring's.
struct Nothing;

impl ForceGenerator for Nothing {
    fn add_forces(&self, _t: f64, _x: &[f64], _v: &[f64], _f: &mut [f64]) -> Result<(), String> {
        Ok(())
    }

    fn jacobian(&self, _t: f64, _x: &[f64], _v: &[f64], _dfdx: &mut [f64], _dfdv: &mut [f64]) -> bool {
        true
    }
}

#[test]
fn one_user_force_read_once_gives_the_bits_of_the_sum_of_several() {
    // One generator's forces are checked and added as handed (`forces_to`); two are summed
    // first. A zero force beside the spring leaves the sum, so the bits must agree.
    for info in &INFOS {
        let mut one = world(info.name, true);
        let mut two = world(info.name, true);
        two.add_force_generator(Arc::new(Nothing)).unwrap();
        one.step(50).unwrap();
        two.step(50).unwrap();
        assert_eq!(one.state_hash(), two.state_hash(), "{}", info.name);
    }
}

#[test]
fn a_user_force_that_hands_the_wrong_forces_fails_the_step_and_is_named() {
    let cases = [
        (Some(1), 1.0, "force 'handing' failed: handed 1 force components, not 2; step rolled back"),
        (None, 1.0, "force 'handing' failed: handed no forces; step rolled back"),
        (Some(2), f64::NAN, "force 'handing' failed: force[0][0] = NaN is not finite; step rolled back"),
    ];
    for (len, value, message) in cases {
        let mut w = World::new(WorldParams {
            dim: 2,
            method: "symplectic-euler".into(),
            dt: 0.1,
            ..Default::default()
        })
        .unwrap();
        w.add_particle(&[1.0, 2.0], &[0.0, 0.0], 1.0, false).unwrap();
        w.add_force_generator(Arc::new(Handing { len, value })).unwrap();
        let (hash, steps) = (w.state_hash(), w.steps());
        let e = w.step(3).unwrap_err();
        assert_eq!(e.to_string(), message);
        assert_eq!((w.state_hash(), w.steps()), (hash, steps));
    }
    // Handed right, it is the force added through `add_forces`.
    let mut w = World::new(WorldParams { dim: 2, dt: 0.1, ..Default::default() }).unwrap();
    w.add_particle(&[1.0, 2.0], &[0.0, 0.0], 2.0, false).unwrap();
    w.add_force_generator(Arc::new(Handing { len: Some(2), value: 4.0 })).unwrap();
    w.step(1).unwrap();
    assert_eq!(w.velocities(), &[0.2, 0.2]);
}

/// A force whose components are often negative zeros (`-0.0 * x`), the case where writing the
/// user forces over the accelerations (no built-in force) and adding them to zeros could part.
struct SignedZeros;

impl ForceGenerator for SignedZeros {
    fn add_forces(&self, t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        for (i, ((fi, xi), vi)) in f.iter_mut().zip(x).zip(v).enumerate() {
            *fi += if i % 2 == 0 { -0.0 * xi } else { -xi - 0.3 * vi + t.sin() };
        }
        Ok(())
    }
}

/// With no built-in force, a user force's accelerations are written over the buffer instead of
/// added to the zeros the built-in forces would leave there: the same bits as a world with a
/// zero gravity (built-in forces that write zeros), for every method, one or two user forces.
#[test]
fn user_forces_alone_step_bitwise_as_with_a_zero_built_in_force() {
    for info in &INFOS {
        for forces in 1..=2 {
            let make = |zero_gravity: bool| {
                let mut w = World::new(WorldParams {
                    dim: 3,
                    method: info.name.into(),
                    dt: 0.05,
                    ..Default::default()
                })
                .unwrap();
                let x = [1.0, -2.0, 0.5, 0.0, 3.0, -1.0];
                w.add_particles(&x, Some(&[0.2, 0.0, -0.1, 0.4, 0.0, 0.0]), Some(&[2.0, 0.5]), false)
                    .unwrap();
                for _ in 0..forces {
                    w.add_force_generator(Arc::new(SignedZeros)).unwrap();
                }
                if zero_gravity {
                    w.add_force(Force::Gravity { g: [0.0; 3] }).unwrap();
                }
                w
            };
            let (mut a, mut b) = (make(false), make(true));
            a.step(40).unwrap();
            b.step(40).unwrap();
            let bits = |v: &[f64]| v.iter().map(|c| c.to_bits()).collect::<Vec<u64>>();
            let what = format!("{}, {forces} user force(s)", info.name);
            assert_eq!(bits(a.positions()), bits(b.positions()), "{what}");
            assert_eq!(bits(a.velocities()), bits(b.velocities()), "{what}");
            assert_eq!(bits(a.accelerations().unwrap()), bits(b.accelerations().unwrap()), "{what}");
        }
    }
}

/// A force that depends on the particle and its state alone: `f = 3 x - v + i / 7` on entry
/// `i`.
struct Affine;

impl ForceGenerator for Affine {
    fn add_forces(&self, _t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        for (i, ((fi, xi), vi)) in f.iter_mut().zip(x).zip(v).enumerate() {
            *fi += 3.0 * xi - vi + i as f64 / 7.0;
        }
        Ok(())
    }
}

/// The accelerations of user forces are `w (0 + f)` entry by entry (`w` the particle's inverse
/// mass, 0 for a static one), added to the built-in forces' (a gravity here), in every dimension,
/// for equal and unequal masses, small worlds and worlds large enough to be summed in parallel
/// tasks: read back after a step and compared with the sum written out here.
#[test]
fn user_force_accelerations_are_the_inverse_mass_times_the_force_in_every_path() {
    for dim in 1..=3 {
        for n in [5, 70_001] {
            for (equal, gravity) in [(true, false), (false, false), (false, true)] {
                let mut w = World::new(WorldParams {
                    dim,
                    method: "symplectic-euler".into(),
                    dt: 0.01,
                    ..Default::default()
                })
                .unwrap();
                let x: Vec<f64> = (0..n * dim).map(|i| (i as f64 * 0.37).sin()).collect();
                let m: Vec<f64> =
                    (0..n).map(|p| if equal { 2.5 } else { 1.0 + (p % 13) as f64 / 3.0 }).collect();
                // Unequal masses end with a static particle (inverse mass 0).
                let dynamic = if equal { n } else { n - 1 };
                w.add_particles(&x[..dynamic * dim], None, Some(&m[..dynamic]), false).unwrap();
                if !equal {
                    w.add_particle(&x[dynamic * dim..], &vec![0.0; dim], m[n - 1], true).unwrap();
                }
                w.add_force_generator(Arc::new(Affine)).unwrap();
                let g = [0.5, -9.81, 1.25];
                if gravity {
                    w.add_force(Force::Gravity { g }).unwrap();
                }
                w.step(2).unwrap();
                let (x, v) = (w.positions().to_vec(), w.velocities().to_vec());
                let a = w.accelerations().unwrap();
                let what = format!("dim {dim}, {n} particles, equal masses {equal}, gravity {gravity}");
                for i in 0..n * dim {
                    let p = i / dim;
                    let inv = if p < dynamic { 1.0 / m[p] } else { 0.0 };
                    let f = 3.0 * x[i] - v[i] + i as f64 / 7.0;
                    let built_in = if gravity && inv > 0.0 { g[i % dim] } else { 0.0 };
                    let want = built_in + inv * (0.0 + f);
                    assert_eq!(a[i].to_bits(), want.to_bits(), "{what}: entry {i}: {} vs {want}", a[i]);
                }
            }
        }
    }
}
