//! Times the Newton matrix's complete Cholesky factorisation on an n x n cloth's springs.
use physstep::linalg::{cg, Blocks, CgParams, CgWork, NewtonMatrix, Preconditioner};
use std::time::Instant;

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(32);
    let reps: usize = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(50);
    let id = |r: usize, c: usize| r * n + c;
    let mut links = Vec::new();
    for r in 0..n {
        for c in 0..n {
            if c + 1 < n {
                links.push((id(r, c), id(r, c + 1)));
            }
            if r + 1 < n {
                links.push((id(r + 1, c), id(r, c)));
            }
            if r + 1 < n && c + 1 < n {
                links.push((id(r, c), id(r + 1, c + 1)));
                links.push((id(r, c + 1), id(r + 1, c)));
            }
        }
    }
    let mut mass = vec![0.01; n * n];
    mass[id(n - 1, 0)] = f64::INFINITY;
    mass[id(n - 1, n - 1)] = f64::INFINITY;
    let mut b = Blocks::default();
    b.reset(3, &mass);
    for (e, &(i, j)) in links.iter().enumerate() {
        let a = e as f64 * 0.37;
        let u = [a.cos(), a.sin() * 0.5, 0.3];
        let nu = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        let mut k = [[0.0; 3]; 3];
        for r in 0..3 {
            for c in 0..3 {
                k[r][c] = -1e5 * (0.9 * u[r] * u[c] / (nu * nu) + if r == c { 0.1 } else { 0.0 });
            }
        }
        b.pairs.push((i, j, k, [[0.0; 3]; 3]));
    }
    let mut m = NewtonMatrix::default();
    let t = Instant::now();
    assert!(m.build(&b, 1.0 / 60.0, Preconditioner::Cholesky));
    println!(
        "first build (order + factor) {:.3} ms, {} blocks",
        t.elapsed().as_secs_f64() * 1e3,
        m.factor_blocks()
    );
    println!(
        "cost in solves {:.1}, products {:.0}",
        m.factor_cost_in_solves(),
        m.factor_cost_in_solves() * 2.0 * m.factor_blocks() as f64
    );
    let mut best = f64::MAX;
    for _ in 0..reps {
        let t = Instant::now();
        assert!(m.build(&b, 1.0 / 60.0, Preconditioner::Cholesky));
        best = best.min(t.elapsed().as_secs_f64());
    }
    let rhs: Vec<f64> = (0..3 * n * n).map(|k| (k as f64 * 0.7).sin()).collect();
    let mut x = vec![0.0; rhs.len()];
    let r = cg(&m, &rhs, &mut x, CgParams::default(), &mut CgWork::default());
    let h: u64 = x.iter().fold(0u64, |h, v| h.rotate_left(5) ^ v.to_bits());
    println!("n = {n}: build + factor best {:.3} ms; cg {r:?}; solution hash {h:#x}", best * 1e3);
}
