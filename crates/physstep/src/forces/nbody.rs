//! Softened n-body gravity, each pair evaluated once.
//!
//! The particles are cut into blocks of [`BLOCK`]; block `I` takes the pairs `(i, j)`, `i`
//! in `I`, `j > i`, adding to `a_i` and subtracting from `a_j` (Newton's third law). The
//! blocks are dealt to a fixed number of [`LANES`], each with its own accumulator, and the
//! lanes are summed in lane order at the end: every sum is taken in the same order whether
//! the lanes run on one thread or many, so the bits never depend on the thread count.
//! Positions are copied into one array per axis first, so the inner loop over `j` loads
//! vectors.

use rayon::prelude::*;

/// Particles per block.
const BLOCK: usize = 64;
/// Accumulators (a fixed number: the order of the sums must not follow the thread count).
const LANES: usize = 8;
/// Interleaved partial sums of a row (two vectors of four doubles).
const W: usize = 8;
/// From this many particles on, the lanes run in parallel.
const PARALLEL_MIN: usize = 256;

/// Adds `G sum_{j != i} m_j (x_j - x_i) / (r^2 + eps^2)^(3/2)` to every dynamic particle `i`.
/// A pair with `r^2 + eps^2 = 0` contributes 0.
pub(super) fn accel(dim: usize, g: f64, eps: f64, x: &[f64], mass: &[f64], inv_mass: &[f64], a: &mut [f64]) {
    match dim {
        1 => accel_d::<1>(g, eps, x, mass, inv_mass, a),
        2 => accel_d::<2>(g, eps, x, mass, inv_mass, a),
        _ => accel_d::<3>(g, eps, x, mass, inv_mass, a),
    }
}

fn accel_d<const D: usize>(g: f64, eps: f64, x: &[f64], mass: &[f64], inv_mass: &[f64], a: &mut [f64]) {
    let n = mass.len();
    let eps2 = eps * eps;
    // One array per axis.
    let axes: [Vec<f64>; D] = std::array::from_fn(|k| (0..n).map(|i| x[i * D + k]).collect());
    // A stop requested (Ctrl-C) is looked at between blocks, on the stepping thread's terms
    // (never inside a replay): the lanes leave their sums unfinished and the accelerations are
    // poisoned, so the step fails and is rolled back (`World::run`).
    let watch = crate::interrupt::watching();
    let lane = |l: usize| {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
            // `target_feature` function.
            return unsafe { lane_avx2::<D>(l, eps2, &axes, mass, watch) };
        }
        lane_sums::<D, false>(l, eps2, &axes, mass, watch)
    };
    let lanes: Vec<[Vec<f64>; D]> = if n >= PARALLEL_MIN {
        (0..LANES).into_par_iter().map(lane).collect()
    } else {
        (0..LANES).map(lane).collect()
    };
    if watch && crate::interrupt::requested() {
        a.fill(f64::NAN);
        return;
    }
    for (i, ai) in a.chunks_exact_mut(D).enumerate() {
        if inv_mass[i] > 0.0 {
            for (k, ak) in ai.iter_mut().enumerate() {
                let mut sum = 0.0;
                for acc in &lanes {
                    sum += acc[k][i];
                }
                *ak += g * sum;
            }
        }
    }
}

/// The sums of lane `l`: its blocks' pairs, per axis. Only `+ - * / sqrt` of IEEE doubles,
/// no fused multiply-add: the AVX2 build gives the same bits as the baseline one.
#[inline(always)]
fn lane_sums<const D: usize, const AVX2: bool>(
    l: usize,
    eps2: f64,
    axes: &[Vec<f64>; D],
    mass: &[f64],
    watch: bool,
) -> [Vec<f64>; D] {
    let n = mass.len();
    let mut acc: [Vec<f64>; D] = std::array::from_fn(|_| vec![0.0; n]);
    for b in (l..n.div_ceil(BLOCK)).step_by(LANES) {
        if watch && crate::interrupt::requested() {
            break;
        }
        for i in b * BLOCK..((b + 1) * BLOCK).min(n) {
            let rest = i + 1;
            let xi: [f64; D] = std::array::from_fn(|k| axes[k][i]);
            let ax: [&[f64]; D] = std::array::from_fn(|k| &axes[k][rest..n]);
            let mj = &mass[rest..n];
            let mi = mass[i];
            let mut out = acc.each_mut().map(|v| &mut v[rest..n]);
            // The row's W interleaved partial sums (see `pairs`).
            let mut part = [[0.0; W]; D];
            let len = mj.len();
            let whole = len / W * W;
            for j0 in (0..whole).step_by(W) {
                let ax_w: [&[f64]; D] = std::array::from_fn(|k| &ax[k][j0..j0 + W]);
                let out_w = out.each_mut().map(|o| &mut o[j0..j0 + W]);
                #[cfg(target_arch = "x86_64")]
                if AVX2 {
                    // SAFETY: `AVX2` is set only by `lane_avx2`, which runs where the CPU has
                    // AVX2; every slice has W elements.
                    unsafe { pairs_avx2::<D>(&xi, eps2, ax_w, &mj[j0..j0 + W], mi, &mut part, out_w) };
                    continue;
                }
                pairs::<D>(&xi, eps2, ax_w, &mj[j0..j0 + W], mi, &mut part, out_w);
            }
            for j in whole..len {
                let w = j - whole;
                let mut d = [0.0; D];
                let mut s = eps2;
                for k in 0..D {
                    d[k] = ax[k][j] - xi[k];
                    s += d[k] * d[k];
                }
                let inv = 1.0 / (s * s.sqrt());
                let c = if s > 0.0 { inv } else { 0.0 };
                let (cj, ci) = (mj[j] * c, mi * c);
                for k in 0..D {
                    part[k][w] += cj * d[k];
                    out[k][j] -= ci * d[k];
                }
            }
            // Pairwise, in a fixed order.
            let sum: [f64; D] = std::array::from_fn(|k| {
                let p = &part[k];
                ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]))
            });
            for k in 0..D {
                acc[k][i] += sum[k];
            }
        }
    }
    acc
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn lane_avx2<const D: usize>(
    l: usize,
    eps2: f64,
    axes: &[Vec<f64>; D],
    mass: &[f64],
    watch: bool,
) -> [Vec<f64>; D] {
    lane_sums::<D, true>(l, eps2, axes, mass, watch)
}

/// W pairs `(i, j)` at once (`xj` and `mj` the W partners' coordinates and masses, `out`
/// their accelerations' sums), as arrays: `d = x_j - x_i`, `s = eps^2 + |d|^2`,
/// `c = 1 / (s sqrt(s))` (0 where `s` is not above 0), `part += m_j c d`, `out -= m_i c d`.
/// The row's sums stay in W interleaved partial sums (j mod W), added in a fixed order at the
/// end: a sum order of our choosing, the same on every path, that vector code can take.
#[inline(always)]
fn pairs<const D: usize>(
    xi: &[f64; D],
    eps2: f64,
    xj: [&[f64]; D],
    mj: &[f64],
    mi: f64,
    part: &mut [[f64; W]; D],
    out: [&mut [f64]; D],
) {
    let mut d = [[0.0; W]; D];
    let mut s = [eps2; W];
    for k in 0..D {
        for w in 0..W {
            d[k][w] = xj[k][w] - xi[k];
            s[w] += d[k][w] * d[k][w];
        }
    }
    let mut cj = [0.0; W];
    let mut ci = [0.0; W];
    for w in 0..W {
        let inv = 1.0 / (s[w] * s[w].sqrt());
        let c = if s[w] > 0.0 { inv } else { 0.0 };
        cj[w] = mj[w] * c;
        ci[w] = mi * c;
    }
    for (k, o) in out.into_iter().enumerate() {
        for w in 0..W {
            part[k][w] += cj[w] * d[k][w];
            o[w] -= ci[w] * d[k][w];
        }
    }
}

/// [`pairs`] in AVX2 instructions, two vectors of four doubles for the W pairs: the same
/// operations in the same order (IEEE `+ - * / sqrt`, no fused multiply-add, the comparison
/// false for NaN as `s > 0.0` is), so the same bits. Written out rather than left to the
/// compiler, whose vectorisation of [`pairs`] depends on how the crate is cut into codegen
/// units (it lost it at 16 units).
///
/// # Safety
/// The CPU has AVX2; each slice of `xj`, `mj` and `out` has W elements.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn pairs_avx2<const D: usize>(
    xi: &[f64; D],
    eps2: f64,
    xj: [&[f64]; D],
    mj: &[f64],
    mi: f64,
    part: &mut [[f64; W]; D],
    mut out: [&mut [f64]; D],
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_and_pd, _mm256_cmp_pd, _mm256_div_pd, _mm256_loadu_pd, _mm256_mul_pd,
        _mm256_set1_pd, _mm256_setzero_pd, _mm256_sqrt_pd, _mm256_storeu_pd, _mm256_sub_pd, _CMP_GT_OQ,
    };
    const H: usize = W / 2;
    let (zero, one, m_i) = (_mm256_setzero_pd(), _mm256_set1_pd(1.0), _mm256_set1_pd(mi));
    for half in 0..2 {
        let o = half * H;
        let mut s = _mm256_set1_pd(eps2);
        let mut d = [zero; D];
        for k in 0..D {
            d[k] = _mm256_sub_pd(_mm256_loadu_pd(xj[k][o..o + H].as_ptr()), _mm256_set1_pd(xi[k]));
            s = _mm256_add_pd(s, _mm256_mul_pd(d[k], d[k]));
        }
        let inv = _mm256_div_pd(one, _mm256_mul_pd(s, _mm256_sqrt_pd(s)));
        let c = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(s, zero), inv);
        let cj = _mm256_mul_pd(_mm256_loadu_pd(mj[o..o + H].as_ptr()), c);
        let ci = _mm256_mul_pd(m_i, c);
        for (k, ok) in out.iter_mut().enumerate() {
            let p = part[k][o..o + H].as_mut_ptr();
            _mm256_storeu_pd(p, _mm256_add_pd(_mm256_loadu_pd(p), _mm256_mul_pd(cj, d[k])));
            let q = ok[o..o + H].as_mut_ptr();
            _mm256_storeu_pd(q, _mm256_sub_pd(_mm256_loadu_pd(q), _mm256_mul_pd(ci, d[k])));
        }
    }
}

/// `-sum_{i<j} G m_i m_j / sqrt(r^2 + eps^2)`, J (pairs with `r^2 + eps^2 = 0` skipped).
#[inline(never)]
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
    fn pairs_once_match_the_sum_over_all_pairs() {
        // Each pair taken once, in blocks and lanes, against the textbook double sum.
        for (n, dim) in [(2, 1), (3, 2), (17, 3), (65, 1), (100, 2), (513, 3), (1000, 3)] {
            let w = world(n, dim, 7 * n as u64);
            let got = w.accel(&nbody_set(n, dim));
            let (g, eps2) = (0.8, 0.05 * 0.05);
            for i in 0..n {
                let mut want = vec![0.0; dim];
                for j in (0..n).filter(|&j| j != i) {
                    let d: Vec<f64> = (0..dim).map(|k| w.x[j * dim + k] - w.x[i * dim + k]).collect();
                    let s = eps2 + d.iter().map(|c| c * c).sum::<f64>();
                    for k in 0..dim {
                        want[k] += g * w.m[j] * d[k] / (s * s.sqrt());
                    }
                }
                let scale = want.iter().map(|c| c.abs()).sum::<f64>().max(1e-300);
                for k in 0..dim {
                    let err = (got[i * dim + k] - want[k]).abs();
                    assert!(err <= 1e-12 * scale * n as f64, "n {n} dim {dim} particle {i}: {err}");
                }
            }
        }
    }

    #[test]
    fn coincident_particles_without_softening_do_not_pull() {
        let w = super::super::tests::W {
            dim: 2,
            x: vec![1.0, 1.0, 1.0, 1.0, 4.0, 5.0],
            v: vec![0.0; 6],
            m: vec![1.0, 2.0, 3.0],
        };
        let mut fs = ForceSet::new();
        fs.add(Force::NBody { g: 1.0, softening: 0.0 }, 3, 2).unwrap();
        let a = w.accel(&fs);
        assert!(a.iter().all(|c| c.is_finite()), "{a:?}");
        // Particles 0 and 1 coincide: each feels only particle 2, at distance 5.
        assert!(
            (a[0] - 3.0 * 3.0 / 125.0).abs() < 1e-15 && (a[2] - 3.0 * 3.0 / 125.0).abs() < 1e-15,
            "{a:?}"
        );
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
