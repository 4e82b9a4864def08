//! The kernels' AVX2 code path and the baseline one give bitwise the same trajectories. The
//! switch is process-wide: the other tests of this binary that run meanwhile take the same
//! bits on either path, only slower.

use physstep::forces::{Endpoint, Force};
use physstep::prelude::*;
use physstep::world::set_vector_paths;

fn run(method: &str, forces: &[Force], vector: bool) -> (u64, Vec<u64>) {
    set_vector_paths(vector);
    let mut w =
        World::new(WorldParams { dim: 3, method: method.into(), dt: 0.01, ..Default::default() }).unwrap();
    let n: usize = 70_001; // past the parallel threshold, with partial tiles and blocks
    let x: Vec<f64> = (0..3 * n).map(|i| ((i * 7919) % 1000) as f64 / 250.0 - 2.0).collect();
    let v: Vec<f64> = (0..3 * n).map(|i| ((i * 1009) % 1000) as f64 / 500.0 - 1.0).collect();
    let m: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
    w.add_particles(&x, Some(&v), Some(&m), false).unwrap();
    w.add_particle(&[0.0; 3], &[0.0; 3], 1.0, true).unwrap();
    for f in forces {
        w.add_force(*f).unwrap();
    }
    w.step(30).unwrap();
    let a = w.accelerations().unwrap().iter().map(|x| x.to_bits()).collect();
    (w.state_hash(), a)
}

#[test]
fn avx2_and_baseline_paths_agree_bitwise() {
    let g = Force::Gravity { g: [0.0, 0.0, -9.81] };
    let mixes = [
        vec![g, Force::Drag { linear: 0.3, quadratic: 0.0 }],
        vec![g, Force::Drag { linear: 0.1, quadratic: 0.05 }],
        vec![Force::Spring {
            i: 5,
            j: Endpoint::Anchor([0.0; 3]),
            stiffness: 4.0,
            rest_length: 1.0,
            damping: 0.1,
        }],
    ];
    let nbody = [Force::NBody { g: 1e-6, softening: 0.05 }];
    let runs = ["explicit-euler", "symplectic-euler", "velocity-verlet", "rk4", "heun", "yoshida4"]
        .into_iter()
        .flat_map(|m| mixes.iter().map(move |f| (m, f.as_slice())));
    for (method, forces) in runs {
        {
            let vector = run(method, forces, true);
            let baseline = run(method, forces, false);
            assert!(vector == baseline, "{method} with {forces:?}: the code paths differ");
        }
    }
    // n-body gravity (each pair once, its AVX2 path written in intrinsics); fewer particles,
    // the same switch, in each dimension.
    for (method, dim) in [("leapfrog", 3), ("rk4", 3), ("leapfrog", 2), ("leapfrog", 1)] {
        let (vector, baseline) =
            (run_small(method, dim, &nbody, true), run_small(method, dim, &nbody, false));
        assert!(vector == baseline, "{method} with n-body gravity in {dim}D: the code paths differ");
    }
    set_vector_paths(true);
}

fn run_small(method: &str, dim: usize, forces: &[Force], vector: bool) -> u64 {
    set_vector_paths(vector);
    let mut w =
        World::new(WorldParams { dim, method: method.into(), dt: 0.01, ..Default::default() }).unwrap();
    let n: usize = 700;
    let x: Vec<f64> = (0..dim * n).map(|i| ((i * 7919) % 1000) as f64 / 250.0 - 2.0).collect();
    let m: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
    w.add_particles(&x, None, Some(&m), false).unwrap();
    for f in forces {
        w.add_force(*f).unwrap();
    }
    w.step(10).unwrap();
    w.state_hash()
}

/// The contact solvers' four-lane passes (`contact/lanes/`: `plane.rs` in the plane,
/// `space.rs` in space) and the one pair at a time passes: every scene with solids, under every solver that
/// has them (the Gauss-Seidel ones), the same bits after a second and a half.
#[test]
fn the_four_lane_contact_passes_and_the_pair_at_a_time_ones_agree_bitwise() {
    let run = |name: &str, solver: &str, vector: bool| {
        set_vector_paths(vector);
        let spec = scenes::spec(name).unwrap();
        let mut w = scenes::build(name, &[], spec.method, spec.dt).unwrap().world;
        w.set_contact_solver(solver).unwrap();
        for _ in 0..90 {
            if w.step(1).is_err() {
                break;
            }
        }
        // The state, and the contacts' reported impulses (the substeps' sums).
        let c = w.contacts();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        (w.state_hash(), bits(&w.solid_positions()), bits(&c.normal_impulses), bits(&c.friction_impulses))
    };
    let mut checked = 0;
    for spec in scenes::SCENES {
        let w = scenes::build(spec.name, &[], spec.method, spec.dt).unwrap().world;
        if w.solid_count() == 0 {
            continue;
        }
        for solver in ["soft-step", "pgs", "pgs-ngs", "soft-pgs", "tgs-sticky"] {
            let (vector, baseline) = (run(spec.name, solver, true), run(spec.name, solver, false));
            assert!(vector == baseline, "{} under {solver}: the code paths differ", spec.name);
        }
        checked += 1;
    }
    set_vector_paths(true);
    assert!(checked >= 20, "only {checked} scenes with solids");
}
