//! The engine's kernels, timed by criterion: `cargo bench -p physstep-bench`.
//!
//! Particles under gravity and drag (the element-wise kernel; with quadratic drag, the
//! recipe-on-tiles kernel), a one-particle spring (a small system's per-step cost), n-body
//! gravity and a rigid body. Speed is measured here and in `bench/` (against peers), never
//! asserted in a test.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use physstep::forces::Force;
use physstep::prelude::*;

fn particles(method: &str, n: usize, quadratic: f64) -> World {
    let mut w =
        World::new(WorldParams { dim: 3, method: method.into(), dt: 1.0 / 120.0, ..Default::default() })
            .expect("a valid world");
    let x: Vec<f64> = (0..3 * n).map(|i| (i % 1000) as f64 * 1e-3).collect();
    let v: Vec<f64> = (0..3 * n).map(|i| (i % 777) as f64 * 1e-3).collect();
    w.add_particles(&x, Some(&v), Some(&vec![1.0; n]), false).expect("valid particles");
    w.add_force(Force::Gravity { g: [0.0, 0.0, -9.81] }).expect("valid gravity");
    w.add_force(Force::Drag { linear: 0.1, quadratic }).expect("valid drag");
    w
}

fn bench_particles(c: &mut Criterion) {
    let n = 100_000;
    let mut g = c.benchmark_group("particles 1e5, 10 steps per call");
    g.throughput(Throughput::Elements((10 * n) as u64));
    for (kernel, quadratic) in [("element-wise", 0.0), ("tiles", 0.01)] {
        for method in ["symplectic-euler", "velocity-verlet", "rk4"] {
            let mut w = particles(method, n, quadratic);
            g.bench_function(BenchmarkId::new(kernel, method), |b| {
                b.iter(|| w.step(10).expect("a stable run"))
            });
        }
    }
    g.finish();
}

fn bench_small(c: &mut Criterion) {
    let mut g = c.benchmark_group("small systems, 1000 steps per call");
    g.throughput(Throughput::Elements(1000));
    for scene in ["spring", "racket"] {
        let mut w =
            physstep::scenes::build(scene, &[], "symplectic-euler", 1.0 / 120.0).expect("a scene").world;
        g.bench_function(scene, |b| b.iter(|| w.step(1000).expect("a stable run")));
    }
    g.finish();
}

fn bench_nbody(c: &mut Criterion) {
    let mut g = c.benchmark_group("n-body, one leapfrog step");
    g.sample_size(20);
    for n in [256.0, 1000.0] {
        let mut w = physstep::scenes::build("nbody", &[("n", n)], "leapfrog", 1e-4).expect("a scene").world;
        g.bench_function(BenchmarkId::from_parameter(n), |b| b.iter(|| w.step(1).expect("a stable run")));
    }
    g.finish();
}

criterion_group!(benches, bench_particles, bench_small, bench_nbody);
criterion_main!(benches);
