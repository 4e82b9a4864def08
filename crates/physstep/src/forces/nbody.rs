//! Softened n-body gravity.

use rayon::prelude::*;

/// From this many particles on, the rows are computed in parallel.
const PARALLEL_MIN: usize = 512;

/// Adds `G sum_{j != i} m_j (x_j - x_i) / (r^2 + eps^2)^(3/2)` to every dynamic particle `i`.
///
/// Each row sums over `j` in index order, whether run serially or with rayon, so the result is
/// bitwise independent of the thread count. A pair with `r^2 + eps^2 = 0` contributes 0.
pub(super) fn accel(dim: usize, g: f64, eps: f64, x: &[f64], mass: &[f64], inv_mass: &[f64], a: &mut [f64]) {
    let eps2 = eps * eps;
    let row = |(i, ai): (usize, &mut [f64])| {
        if inv_mass[i] > 0.0 {
            match dim {
                1 => row_d::<1>(i, g, eps2, x, mass, ai),
                2 => row_d::<2>(i, g, eps2, x, mass, ai),
                _ => row_d::<3>(i, g, eps2, x, mass, ai),
            }
        }
    };
    if inv_mass.len() >= PARALLEL_MIN {
        a.par_chunks_mut(dim).enumerate().with_min_len(16).for_each(row);
    } else {
        a.chunks_mut(dim).enumerate().for_each(row);
    }
}

#[inline]
fn row_d<const D: usize>(i: usize, g: f64, eps2: f64, x: &[f64], mass: &[f64], ai: &mut [f64]) {
    let mut xi = [0.0; D];
    xi.copy_from_slice(&x[i * D..(i + 1) * D]);
    let mut acc = [0.0; D];
    let mut sum = |js: std::ops::Range<usize>| {
        for j in js {
            let mut d = [0.0; D];
            let mut s = eps2;
            for k in 0..D {
                d[k] = x[j * D + k] - xi[k];
                s += d[k] * d[k];
            }
            let c = if s > 0.0 { mass[j] / (s * s.sqrt()) } else { 0.0 };
            for k in 0..D {
                acc[k] += c * d[k];
            }
        }
    };
    sum(0..i);
    sum(i + 1..mass.len());
    for (ak, acck) in ai.iter_mut().zip(acc) {
        *ak += g * acck;
    }
}

/// `-sum_{i<j} G m_i m_j / sqrt(r^2 + eps^2)`, J (pairs with `r^2 + eps^2 = 0` skipped).
pub(super) fn potential(dim: usize, g: f64, eps: f64, x: &[f64], mass: &[f64]) -> f64 {
    let eps2 = eps * eps;
    let mut u = 0.0;
    for i in 0..mass.len() {
        let xi = &x[i * dim..(i + 1) * dim];
        let mut ui = 0.0;
        for j in i + 1..mass.len() {
            let xj = &x[j * dim..(j + 1) * dim];
            let s = eps2 + xi.iter().zip(xj).map(|(p, q)| (q - p) * (q - p)).sum::<f64>();
            if s > 0.0 {
                ui += mass[j] / s.sqrt();
            }
        }
        u -= g * mass[i] * ui;
    }
    u
}

#[cfg(test)]
mod tests {
    use super::super::tests::world;
    use super::super::{Force, ForceSet};

    fn nbody_set(n: usize, dim: usize) -> ForceSet {
        let mut fs = ForceSet::new();
        fs.add(Force::NBody { g: 0.8, softening: 0.05 }, n, dim).unwrap();
        fs
    }

    #[test]
    fn momentum_is_conserved() {
        for (n, dim) in [(7, 1), (13, 2), (40, 3), (600, 3)] {
            let w = world(n, dim, n as u64);
            let a = w.accel(&nbody_set(n, dim));
            for k in 0..dim {
                let (mut p, mut scale) = (0.0, 0.0);
                for i in 0..n {
                    p += w.m[i] * a[i * dim + k];
                    scale += (w.m[i] * a[i * dim + k]).abs();
                }
                assert!(p.abs() <= 1e-12 * scale, "n {n} dim {dim} axis {k}: {p} vs {scale}");
            }
        }
    }

    #[test]
    fn thread_count_does_not_matter() {
        let (n, dim) = (600, 3);
        let w = world(n, dim, 42);
        let fs = nbody_set(n, dim);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let a = pool.install(|| w.accel(&fs));
            a.iter().map(|a| a.to_bits()).collect::<Vec<_>>()
        };
        let one = run(1);
        assert_eq!(one, run(2));
        assert_eq!(one, run(3));
    }

    #[test]
    fn two_bodies_exact() {
        // 1D, no softening: a_0 = G m_1 / r^2 toward body 1
        let w = super::super::tests::W { dim: 1, x: vec![0.0, 2.0], v: vec![0.0; 2], m: vec![3.0, 8.0] };
        let mut fs = ForceSet::new();
        fs.add(Force::NBody { g: 0.5, softening: 0.0 }, 2, 1).unwrap();
        assert_eq!(w.accel(&fs), vec![1.0, -0.375]);
        assert_eq!(fs.potential(1, &w.x, &w.m), -6.0);
    }
}
