//! The dense kernels of the supernodal factorisation, on column-major panels of doubles: the
//! product of a block of rows with the transpose of its first rows (the update one supernode
//! sends another, and the update within a panel), and the blocked Cholesky factorisation of a
//! panel. Sums run over the columns in order, four rows at a time in the lanes of a vector,
//! each product added by a fused multiply-add (one rounding): the same bits on the AVX2 and
//! FMA path and the baseline, whose `mul_add` is the C library's correctly rounded `fma`
//! ([`crate::simd`]). Fused, the 100 x 100 cloth's linearly implicit step took about a fifth
//! less time than with a product and a sum (its products are most of the step).

/// Columns of a panel factored together (the rest of the panel's columns then updated by
/// [`syrk`] in one pass).
const CHUNK: usize = 12;

/// Rows a panel keeps past its last (zero): [`syrk`] reads whole vectors of four rows.
pub(super) const PAD: usize = 3;

/// Products of [`syrk`] past which it splits its columns between two threads (the hand-over
/// costs some microseconds; a product some nanoseconds).
const TWO_MIN: usize = 1 << 18;

/// `C = A B^T` (`SUB`: `C -= A B^T`) on the lower part (rows `i >= j`) of an `m x n` block,
/// `B` the first `n` rows of the `m x w` block `A` (`n <= m`): `C[i + j ldc]` and
/// `A[i + t lda]`, each entry `0 + a_i0 b_j0 + a_i1 b_j1 + ...`. `A`'s column may be read
/// [`PAD`] rows past `m` (finite values, not used).
///
/// With `two`, where the product is large (at least [`TWO_MIN`] multiply-adds), its columns
/// are split between the calling thread and a worker of the pool, where the work (the rows
/// below each column) halves, at a multiple of four. Every entry is the same sum as on one
/// thread: the same bits.
#[allow(clippy::too_many_arguments)]
pub(super) fn syrk<const SUB: bool>(
    c: &mut [f64],
    ldc: usize,
    a: &[f64],
    lda: usize,
    m: usize,
    n: usize,
    w: usize,
    two: bool,
) {
    let work = |j: usize| (m - j.min(m)) * 4;
    let total: usize = (0..n).step_by(4).map(work).sum();
    if !two || n < 8 || total * w < TWO_MIN {
        return syrk_columns::<SUB>(c, ldc, a, lda, m, 0..n, w);
    }
    let (mut split, mut done) = (0, 0);
    while split < n && 2 * done < total {
        done += work(split);
        split += 4;
    }
    // (The last block's start at most: the same blocks of four as on one thread.)
    let split = split.min((n - 1) / 4 * 4);
    let (lo, hi) = c.split_at_mut(split * ldc);
    rayon::in_place_scope(|s| {
        s.spawn(|_| syrk_columns::<SUB>(hi, ldc, a, lda, m, split..n, w));
        syrk_columns::<SUB>(lo, ldc, a, lda, m, 0..split, w);
    });
}

/// Columns `cols` (from a multiple of four) of [`syrk`], `c` starting at column `cols.start`.
#[inline(always)]
fn syrk_columns<const SUB: bool>(
    c: &mut [f64],
    ldc: usize,
    a: &[f64],
    lda: usize,
    m: usize,
    cols: std::ops::Range<usize>,
    w: usize,
) {
    let (first, n) = (cols.start, cols.end);
    let mut j = first;
    while j < n {
        let cj = j - first;
        match n - j {
            1 => columns::<1, SUB>(c, ldc, a, lda, m, w, j, cj),
            2 => columns::<2, SUB>(c, ldc, a, lda, m, w, j, cj),
            3 => columns::<3, SUB>(c, ldc, a, lda, m, w, j, cj),
            _ => columns::<4, SUB>(c, ldc, a, lda, m, w, j, cj),
        }
        j += 4;
    }
}

/// Columns `j..j + NJ` of [`syrk`] (columns `cj..cj + NJ` of `c`), from row `j` down: tiles
/// of eight rows, then four.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn columns<const NJ: usize, const SUB: bool>(
    c: &mut [f64],
    ldc: usize,
    a: &[f64],
    lda: usize,
    m: usize,
    w: usize,
    j: usize,
    cj: usize,
) {
    // The tiles read rows `i..i + 4 NV` of columns `0..w`: within `a` (checked once here).
    let reach = if w == 0 { 0 } else { (w - 1) * lda + m.div_ceil(4) * 4 };
    assert!(reach <= a.len() && (w == 0 || (w - 1) * lda + j + NJ <= a.len()), "syrk: A is short");
    #[cfg(target_arch = "x86_64")]
    if crate::simd::fma() {
        let mut i = j;
        while i < m {
            // SAFETY: the CPU has AVX2 and FMA (`fma`), and the tile reads within `a`
            // (asserted above: `i + 4 NV <= m` rounded up to 4).
            unsafe {
                if m - i > 4 {
                    tile_avx2::<2, NJ, SUB>(c, ldc, a, lda, w, i, j, cj, (m - i).min(8));
                } else {
                    tile_avx2::<1, NJ, SUB>(c, ldc, a, lda, w, i, j, cj, m - i);
                }
            }
            i += 8;
        }
        return;
    }
    let mut i = j;
    while i < m {
        if m - i > 4 {
            tile::<2, NJ, SUB>(c, ldc, a, lda, w, i, j, cj, (m - i).min(8));
            i += 8;
        } else {
            tile::<1, NJ, SUB>(c, ldc, a, lda, w, i, j, cj, m - i);
            i += 4;
        }
    }
}

/// [`tile`] in AVX2 registers (the same operations in the same order, the multiply-adds fused
/// as `mul_add` fuses them: the same bits).
///
/// # Safety
/// The CPU has AVX2 and FMA, and `a` holds rows `i..i + 4 NV` and `j..j + NJ` of columns `0..w`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn tile_avx2<const NV: usize, const NJ: usize, const SUB: bool>(
    c: &mut [f64],
    ldc: usize,
    a: &[f64],
    lda: usize,
    w: usize,
    i: usize,
    j: usize,
    cj: usize,
    rows: usize,
) {
    use std::arch::x86_64::{
        _mm256_broadcast_sd, _mm256_fmadd_pd, _mm256_loadu_pd, _mm256_setzero_pd, _mm256_storeu_pd,
        _mm256_sub_pd,
    };
    let mut acc = [[_mm256_setzero_pd(); NV]; NJ];
    let base = a.as_ptr();
    for t in 0..w {
        let col = base.add(t * lda);
        let mut x = [_mm256_setzero_pd(); NV];
        for (v, xv) in x.iter_mut().enumerate() {
            *xv = _mm256_loadu_pd(col.add(i + 4 * v));
        }
        for (jj, acc) in acc.iter_mut().enumerate() {
            let b = _mm256_broadcast_sd(&*col.add(j + jj));
            for v in 0..NV {
                acc[v] = _mm256_fmadd_pd(x[v], b, acc[v]);
            }
        }
    }
    for (jj, acc) in acc.iter().enumerate() {
        let out = &mut c[(cj + jj) * ldc + i..(cj + jj) * ldc + i + rows];
        if rows == 4 * NV {
            for (v, acc) in acc.iter().enumerate() {
                let o = out.as_mut_ptr().add(4 * v);
                if SUB {
                    _mm256_storeu_pd(o, _mm256_sub_pd(_mm256_loadu_pd(o), *acc));
                } else {
                    _mm256_storeu_pd(o, *acc);
                }
            }
            continue;
        }
        let mut lanes = [[0.0f64; 4]; NV];
        for v in 0..NV {
            _mm256_storeu_pd(lanes[v].as_mut_ptr(), acc[v]);
        }
        for (r, o) in out.iter_mut().enumerate() {
            let v = lanes[r / 4][r % 4];
            if SUB {
                *o -= v;
            } else {
                *o = v;
            }
        }
    }
}

/// Rows `i..i + rows` (`rows <= 4 NV`) of columns `j..j + NJ`, accumulated in registers and
/// written to `c`'s columns `cj..cj + NJ`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn tile<const NV: usize, const NJ: usize, const SUB: bool>(
    c: &mut [f64],
    ldc: usize,
    a: &[f64],
    lda: usize,
    w: usize,
    i: usize,
    j: usize,
    cj: usize,
    rows: usize,
) {
    let mut acc = [[[0.0f64; 4]; NV]; NJ];
    for t in 0..w {
        let col = &a[t * lda..];
        let mut x = [[0.0f64; 4]; NV];
        for (v, xv) in x.iter_mut().enumerate() {
            *xv = col[i + 4 * v..i + 4 * v + 4].try_into().unwrap_or([0.0; 4]);
        }
        let b: [f64; NJ] = col[j..j + NJ].try_into().unwrap_or([0.0; NJ]);
        for jj in 0..NJ {
            for v in 0..NV {
                for l in 0..4 {
                    acc[jj][v][l] = x[v][l].mul_add(b[jj], acc[jj][v][l]);
                }
            }
        }
    }
    for (jj, acc) in acc.iter().enumerate() {
        let out = &mut c[(cj + jj) * ldc + i..(cj + jj) * ldc + i + rows];
        for (r, o) in out.iter_mut().enumerate() {
            let v = acc[r / 4][r % 4];
            if SUB {
                *o -= v;
            } else {
                *o = v;
            }
        }
    }
}

/// Factors in place the `rows x cols` panel `p` (column-major, leading dimension `ld`, its
/// top `cols x cols` block the diagonal block, lower part read): `L` below the diagonal and
/// the reciprocals of `L`'s diagonal on it. Left-looking in chunks of [`CHUNK`] columns,
/// each updated by the columns before it ([`syrk`]) and then factored column by column.
/// `false` at a pivot that is not positive (or not finite).
#[inline(always)]
pub(super) fn factor_panel(p: &mut [f64], ld: usize, rows: usize, cols: usize, two: bool) -> bool {
    let mut c0 = 0;
    while c0 < cols {
        let c1 = (c0 + CHUNK).min(cols);
        if c0 > 0 {
            let (left, right) = p.split_at_mut(c0 * ld);
            syrk::<true>(&mut right[c0..], ld, &left[c0..], ld, rows - c0, c1 - c0, c0, two);
        }
        for c in c0..c1 {
            let (left, right) = p.split_at_mut(c * ld);
            let col = &mut right[c..rows];
            for t in c0..c {
                let lt = &left[t * ld + c..t * ld + rows];
                let x = lt[0];
                for (ci, li) in col.iter_mut().zip(lt) {
                    *ci = (-li).mul_add(x, *ci);
                }
            }
            let d = col[0];
            if !(d > 0.0 && d.is_finite()) {
                return false;
            }
            let inv = 1.0 / d.sqrt();
            col[0] = inv;
            for ci in &mut col[1..] {
                *ci *= inv;
            }
        }
        c0 = c1;
    }
    true
}

/// `sum_i a_i b_i` in four lanes (`i mod 4`), then the lanes summed in order.
#[inline(always)]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ar, br) = (ac.remainder(), bc.remainder());
    for (x, y) in ac.zip(bc) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    for (l, (x, y)) in ar.iter().zip(br).enumerate() {
        acc[l] += x * y;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symmetric positive definite `n x n` matrix (column-major, leading dimension `ld`).
    fn spd(n: usize, ld: usize) -> Vec<f64> {
        let mut a = vec![0.0; ld * n];
        for j in 0..n {
            for i in 0..n {
                let v = ((i * 7 + j * 13) % 11) as f64 * 0.1 - 0.5;
                a[j * ld + i] += v;
                a[i * ld + j] += v;
            }
            a[j * ld + j] += 2.0 * n as f64;
        }
        a
    }

    #[test]
    fn a_panel_factors_to_l_with_its_diagonal_inverted() {
        // Sizes across the chunk (12) and the tiles (8, 4): L L^T is the matrix.
        for n in [1, 3, 5, 12, 13, 29] {
            let ld = n + PAD;
            let a = spd(n, ld);
            let mut l = a.clone();
            assert!(factor_panel(&mut l, ld, n, n, false));
            for i in 0..n {
                for j in 0..=i {
                    let lij = |i: usize, j: usize| if i == j { 1.0 / l[j * ld + j] } else { l[j * ld + i] };
                    let s: f64 = (0..=j).map(|k| lij(i, k) * lij(j, k)).sum();
                    assert!((s - a[j * ld + i]).abs() < 1e-12 * n as f64, "n {n} ({i}, {j}): {s}");
                }
            }
        }
        let mut indefinite = spd(4, 4 + PAD);
        indefinite[2 * (4 + PAD) + 2] = -100.0;
        assert!(!factor_panel(&mut indefinite, 4 + PAD, 4, 4, false));
    }

    #[test]
    fn syrk_is_the_product_of_rows_with_the_first_rows() {
        let (m, n, w, lda) = (11, 6, 5, 11 + PAD);
        let a: Vec<f64> = (0..lda * w).map(|k| (k as f64 * 0.37).sin()).collect();
        let mut c = vec![7.0; m * n];
        syrk::<true>(&mut c, m, &a, lda, m, n, w, false);
        for j in 0..n {
            for i in j..m {
                let s: f64 = (0..w).map(|t| a[t * lda + i] * a[t * lda + j]).sum();
                assert!((c[j * m + i] - (7.0 - s)).abs() < 1e-14);
            }
        }
        assert_eq!(dot(&[1.0, 2.0, 3.0, 4.0, 5.0], &[1.0, 1.0, 1.0, 1.0, 2.0]), 20.0);
    }

    #[test]
    fn syrk_on_two_threads_gives_the_bits_of_one() {
        // Past TWO_MIN, with column counts that do and do not split at a multiple of four.
        for (m, n, w) in [(300, 200, 40), (257, 13, 900), (130, 130, 130), (400, 9, 900)] {
            let lda = m + PAD;
            let a: Vec<f64> = (0..lda * w).map(|k| (k as f64 * 0.731).sin()).collect();
            let c0: Vec<f64> = (0..m * n).map(|k| (k as f64 * 0.17).cos()).collect();
            let (mut one, mut two) = (c0.clone(), c0);
            syrk::<true>(&mut one, m, &a, lda, m, n, w, false);
            syrk::<true>(&mut two, m, &a, lda, m, n, w, true);
            assert!(m * n * w >= TWO_MIN);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&one), bits(&two), "m {m} n {n} w {w}");
        }
    }
}
