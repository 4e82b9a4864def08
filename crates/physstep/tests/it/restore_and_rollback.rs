//! The state as it was: `restore` refuses a corrupt or foreign snapshot and leaves the world
//! unchanged, and a step that diverges rolls the state and the method's memory back bitwise.

use super::common::resign;
use physstep::prelude::*;

fn two_particles(method: &str, second_static: bool) -> World {
    let mut w = World::new(WorldParams { dim: 2, method: method.into(), ..Default::default() }).unwrap();
    w.add_particle(&[1.0, 0.0], &[0.0, 1.0], 1.0, false).unwrap();
    w.add_particle(&[0.0, 0.0], &[0.0, 0.0], 1.0, second_static).unwrap();
    w.add_force(Force::Spring {
        i: 0,
        j: Endpoint::Particle(1),
        stiffness: 4.0,
        rest_length: 0.5,
        damping: 0.0,
    })
    .unwrap();
    w
}

/// Offset of float `k` after the header of a snapshot of a world using `method`.
fn float_at(method: &str, k: usize) -> usize {
    8 + 40 + method.len() + 8 * k
}

fn set_f64(bytes: &mut [u8], at: usize, v: f64) {
    bytes[at..at + 8].copy_from_slice(&v.to_le_bytes());
}

#[test]
fn corrupt_or_foreign_snapshots_are_refused_and_the_world_is_unchanged() {
    let method = "leapfrog";
    let mut w = two_particles(method, false);
    w.step(7).unwrap();
    let good = w.snapshot();
    let hash = w.state_hash();
    // floats: t, hi, lo, epoch t, epoch steps, epoch dt, memory length, y (8), memory ...
    let y0 = float_at(method, 7);
    let mut cases: Vec<(&str, Vec<u8>)> = Vec::new();
    let mut nan_x = good.clone();
    set_f64(&mut nan_x, y0, f64::NAN);
    cases.push(("not finite", resign(nan_x)));
    let mut inf_v = good.clone();
    set_f64(&mut inf_v, y0 + 8 * 5, f64::INFINITY);
    cases.push(("not finite", resign(inf_v)));
    let mut nan_acc = good.clone();
    set_f64(&mut nan_acc, float_at(method, 1), f64::NAN);
    cases.push(("accumulator is NaN", resign(nan_acc)));
    let mut epoch = good.clone();
    set_f64(&mut epoch, float_at(method, 4), 8.0);
    cases.push(("epoch step 8", resign(epoch)));
    let mut steps = good.clone();
    steps[8 + 24..8 + 32].copy_from_slice(&u64::MAX.to_le_bytes());
    cases.push(("more than 2^53", resign(steps)));
    let mut time = good.clone();
    set_f64(&mut time, float_at(method, 0), 123.0);
    cases.push(("does not follow", resign(time)));
    // Memory: a flag that is not 0 or 1, a missing and an extra entry.
    let mem0 = y0 + 8 * 8;
    let mut flag = good.clone();
    set_f64(&mut flag, mem0, 0.5);
    cases.push(("memory does not fit", resign(flag)));
    let mut short = good.clone();
    short.drain(mem0 + 8 * 2..mem0 + 8 * 3);
    set_f64(&mut short, float_at(method, 6), 5.0);
    cases.push(("memory does not fit", resign(short)));
    let mut long = good.clone();
    for b in 0u8..8 {
        long.insert(mem0 + 8 * 2, b);
    }
    set_f64(&mut long, float_at(method, 6), 7.0);
    cases.push(("memory does not fit", resign(long)));
    let mut damaged = good.clone();
    damaged[y0 + 3] ^= 1;
    cases.push(("checksum", damaged));
    cases.push(("truncated", good[..20].to_vec()));
    cases.push(("not a physstep snapshot", b"hello".to_vec()));
    for (want, bytes) in cases {
        let e = w.restore(&bytes).unwrap_err();
        assert!(matches!(e, Error::Corrupt { .. }), "{want}: {e:?}");
        assert!(e.to_string().contains(want), "{want}: {e}");
        assert_eq!(w.state_hash(), hash, "{want}: world changed");
    }
    w.restore(&good).unwrap();
    assert_eq!(w.state_hash(), hash);
}

#[test]
fn a_snapshot_of_a_dynamic_particle_is_refused_where_it_is_static() {
    let mut dynamic = two_particles("rk4", false);
    dynamic.step(3).unwrap();
    let snap = dynamic.snapshot();
    let mut fixed = two_particles("rk4", true);
    let hash = fixed.state_hash();
    let e = fixed.restore(&snap).unwrap_err();
    assert!(e.to_string().contains("particle 1 is dynamic in the snapshot, static in this world"), "{e}");
    assert_eq!(fixed.state_hash(), hash);
}

#[test]
fn a_diverged_step_rolls_back_method_memory_bitwise() {
    for method in ["verlet", "leapfrog", "symplectic-euler-alternating"] {
        let mut s = scenes::build("spring", &[("k", 1e12), ("m", 1.0)], method, 1.0).unwrap();
        let w = &mut s.world;
        let e = loop {
            let (hash, memory) = (w.state_hash(), w.integrator().memory());
            match w.step(1) {
                Ok(()) => assert!(w.steps() < 100, "{method}: no divergence"),
                Err(e) => {
                    assert_eq!(w.state_hash(), hash, "{method}");
                    let bits = |m: Vec<f64>| m.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(w.integrator().memory()), bits(memory), "{method}");
                    break e;
                }
            }
        };
        assert!(matches!(e, Error::Diverged { .. }), "{method}: {e:?}");
    }
}
