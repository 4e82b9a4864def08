//! Nested dissection of the springs' graph (George 1973), found from the graph alone: a
//! connected set of more than [`LEAF`] particles is cut in two halves by a separator, the
//! particles joining them, and each half is cut again. The separators are eliminated after
//! the halves they join (the deepest first, the first cut last) and the minimum-degree order
//! of [`super::order`] orders the particles within each stage: on a cloth's grid a straight
//! separator of one row, where minimum degree alone lets the fill spread (a 100 x 100 cloth
//! with shear springs: 14.6 million block products -> 10.2 million, and the factorisation
//! 1.5x faster; 32 x 32: 317,000 -> 243,000).
//!
//! A cut comes from the graph's spectral embedding (Pothen, Simon and Liou 1990): two
//! vectors of the Laplacian's smallest nonzero eigenvalues (Lanczos runs from fixed starts),
//! whose values vary smoothly across the graph, like coordinates; the set is split at the
//! median of a combination of the two, in the direction whose separator is smallest. No
//! positions are read: the order depends on the springs alone (a restored world orders as the
//! one it was saved from), and each cut's arithmetic runs in a fixed order (large sets cut
//! their halves on two threads, each half on its own: the same stages on one thread or two).
//! It costs about as much as the minimum-degree elimination it guides, once while the
//! springs stay the same.

/// Sets of at most this many particles are not cut (minimum degree orders them).
const LEAF: usize = 64;

/// Lanczos steps a cut takes at most (its smooth vectors need not have converged).
const LANCZOS: usize = 24;

/// Halving steps of the direction about the best of [`ANGLES`].
const REFINE: usize = 10;

/// Smoothing passes over the start vector.
const SMOOTH: usize = 200;

/// Directions tried in the plane of the two vectors (evenly spaced over half a turn).
const ANGLES: usize = 8;

/// The stage of each particle: 0 for the particles of the sets left whole, and for those of
/// a separator found at depth `d` (the first cut at depth 0) `u32::MAX - d`; particles that
/// do not move are stage 0 too (they are not ordered). Eliminating by stage, then by degree,
/// takes the halves before the separators that join them.
pub(super) fn stages(adj: &[Vec<u32>], free: &[bool]) -> Vec<u32> {
    let n = adj.len();
    let mut stage = vec![0u32; n];
    let set: Vec<u32> = (0..n as u32).filter(|&p| free[p as usize]).collect();
    for (p, s) in dissect(adj, set, 0, &mut vec![NONE; n]) {
        stage[p as usize] = s;
    }
    stage
}

/// Sets at least this large cut their two halves at once, on two threads (each half's cuts
/// are its own: the same stages on one thread or two).
const PARALLEL_FROM: usize = 2000;

/// The separators' particles and stages of the nested dissection of `set` (cut at `depth`);
/// `local` is scratch of one entry a particle, all NONE.
fn dissect(adj: &[Vec<u32>], set: Vec<u32>, depth: u32, local: &mut [u32]) -> Vec<(u32, u32)> {
    if set.len() <= LEAF {
        return Vec::new();
    }
    let graph = Local::new(adj, &set, local);
    let parts = graph.components();
    if parts.len() > 1 {
        let mut out = Vec::new();
        for part in parts {
            out.extend(dissect(adj, part.iter().map(|&i| set[i as usize]).collect(), depth, local));
        }
        return out;
    }
    let Some(side) = graph.cut() else { return Vec::new() };
    let mut out = Vec::new();
    let mut halves = [Vec::new(), Vec::new()];
    for (i, &s) in side.iter().enumerate() {
        match s {
            Side::Separator => out.push((set[i], u32::MAX - depth)),
            Side::Half(h) => halves[usize::from(h)].push(set[i]),
        }
    }
    let [a, b] = halves;
    if set.len() >= PARALLEL_FROM {
        let mut other = vec![NONE; local.len()];
        let (left, right) =
            rayon::join(|| dissect(adj, a, depth + 1, local), || dissect(adj, b, depth + 1, &mut other));
        out.extend(left);
        out.extend(right);
    } else {
        out.extend(dissect(adj, a, depth + 1, local));
        out.extend(dissect(adj, b, depth + 1, local));
    }
    out
}

const NONE: u32 = u32::MAX;

/// Where a particle of a cut set goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Half(bool),
    Separator,
}

/// The graph induced on a set of particles, numbered by their place in the set.
struct Local {
    start: Vec<usize>,
    nb: Vec<u32>,
}

impl Local {
    /// The springs among `set`'s particles (`local` is left all NONE, as found).
    fn new(adj: &[Vec<u32>], set: &[u32], local: &mut [u32]) -> Self {
        for (i, &p) in set.iter().enumerate() {
            local[p as usize] = i as u32;
        }
        let mut start = vec![0];
        let mut nb = Vec::new();
        for &p in set {
            nb.extend(adj[p as usize].iter().map(|&q| local[q as usize]).filter(|&i| i != NONE));
            start.push(nb.len());
        }
        for &p in set {
            local[p as usize] = NONE;
        }
        Self { start, nb }
    }

    fn len(&self) -> usize {
        self.start.len() - 1
    }

    fn neighbours(&self, i: usize) -> &[u32] {
        &self.nb[self.start[i]..self.start[i + 1]]
    }

    /// The connected components (local numbers, ascending within each).
    fn components(&self) -> Vec<Vec<u32>> {
        let m = self.len();
        let mut seen = vec![false; m];
        let mut parts = Vec::new();
        for s in 0..m {
            if seen[s] {
                continue;
            }
            seen[s] = true;
            let mut part = vec![s as u32];
            let mut k = 0;
            while k < part.len() {
                let i = part[k] as usize;
                k += 1;
                for &j in self.neighbours(i) {
                    if !seen[j as usize] {
                        seen[j as usize] = true;
                        part.push(j);
                    }
                }
            }
            part.sort_unstable();
            parts.push(part);
        }
        parts
    }

    /// `y = L x`, `L` the graph's Laplacian (degree minus adjacency).
    fn laplacian(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            let nb = self.neighbours(i);
            *yi = nb.len() as f64 * x[i] - nb.iter().map(|&j| x[j as usize]).sum::<f64>();
        }
    }

    /// A cut of a connected set: its spectral embedding, split at the median along the
    /// direction whose separator is smallest (the directions evenly spaced, then halving
    /// steps about the best so far; ties to the one tried first); `None` where no vector was
    /// found (the set is then not cut).
    fn cut(&self) -> Option<Vec<Side>> {
        let m = self.len();
        let vectors = self.embedding();
        if vectors.iter().flatten().any(|v| !v.is_finite()) {
            return None;
        }
        let first = vectors.first()?;
        let second = vectors.get(1).unwrap_or(first);
        let mut order: Vec<u32> = (0..m as u32).collect();
        let mut coordinate = vec![0.0; m];
        let mut split = |angle: f64| {
            let (c, s) = (angle.cos(), angle.sin());
            for (k, u) in coordinate.iter_mut().enumerate() {
                *u = c * first[k] + s * second[k];
            }
            order.sort_unstable_by(|&i, &j| {
                coordinate[i as usize].total_cmp(&coordinate[j as usize]).then(i.cmp(&j))
            });
            let mut side = vec![Side::Half(true); m];
            for &i in &order[..m / 2] {
                side[i as usize] = Side::Half(false);
            }
            // The separator: the particles of one half with a neighbour in the other (the
            // smaller of the two such sets; ties to the second half's).
            let touches =
                |i: usize, side: &[Side]| self.neighbours(i).iter().any(|&j| side[j as usize] != side[i]);
            let rims: [Vec<usize>; 2] = [false, true]
                .map(|h| (0..m).filter(|&i| side[i] == Side::Half(h) && touches(i, &side)).collect());
            let rim = if rims[0].len() < rims[1].len() { &rims[0] } else { &rims[1] };
            for &i in rim {
                side[i] = Side::Separator;
            }
            (rim.len(), side)
        };
        let mut best = (usize::MAX, Vec::new(), 0.0);
        let step = std::f64::consts::PI / ANGLES as f64;
        for a in 0..ANGLES {
            let angle = step * a as f64;
            let (size, side) = split(angle);
            if size < best.0 {
                best = (size, side, angle);
            }
        }
        let mut delta = step / 2.0;
        for _ in 0..REFINE {
            let centre = best.2;
            for angle in [centre - delta, centre + delta] {
                let (size, side) = split(angle);
                if size < best.0 {
                    best = (size, side, angle);
                }
            }
            delta /= 2.0;
        }
        Some(best.1)
    }

    /// Two vectors of the Laplacian's smallest nonzero eigenvalues, the smallest first: the
    /// second from a run kept orthogonal to the first (one Lanczos run finds one vector of an
    /// eigenvalue however many it has: a square grid's two lowest modes, along each side,
    /// share theirs). Fewer where the set is too small.
    fn embedding(&self) -> Vec<Vec<f64>> {
        let mut found = Vec::new();
        for _ in 0..2 {
            match self.smallest(&found) {
                Some(v) => found.push(v),
                None => break,
            }
        }
        found
    }

    /// The Ritz vector of the smallest Ritz value of a Lanczos run on the Laplacian, from a
    /// fixed start made smooth, orthogonal to the constant vector and to the unit vectors
    /// `against` (fully reorthogonalised); `None` where nothing is left.
    fn smallest(&self, against: &[Vec<f64>]) -> Option<Vec<f64>> {
        let m = self.len();
        let steps = LANCZOS.min(m.saturating_sub(1 + against.len()));
        if steps == 0 {
            return None;
        }
        let ones = vec![1.0 / (m as f64).sqrt(); m];
        let deflate = |q: &mut [f64], basis: &[Vec<f64>]| {
            for b in std::iter::once(&ones).chain(against).chain(basis) {
                let d = dot(q, b);
                q.iter_mut().zip(b).for_each(|(v, bv)| *v -= d * bv);
            }
        };
        // A fixed start (an LCG), another for each vector (the same start would hold, of a
        // repeated eigenvalue's vectors, only the one found before).
        let mut seed = 0x9e37_79b9_7f4a_7c15u64 ^ against.len() as u64;
        let mut q: Vec<f64> = (0..m)
            .map(|_| {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        // Smoothed first: `q <- q - L q / (2 d)`, `d` the largest degree (the factor
        // `1 - lambda / (2 d)` is in [0, 1] for every eigenvalue), which damps the high
        // frequencies: the Krylov space the run builds is then that of the smooth vectors.
        let d_max = (0..m).map(|i| self.neighbours(i).len()).max().unwrap_or(1).max(1) as f64;
        let mut w = vec![0.0; m];
        for k in 0..SMOOTH {
            if k % 16 == 0 {
                deflate(&mut q, &[]);
            }
            self.laplacian(&q, &mut w);
            q.iter_mut().zip(&w).for_each(|(v, lv)| *v -= lv / (2.0 * d_max));
        }
        let mut basis: Vec<Vec<f64>> = Vec::with_capacity(steps);
        let (mut alpha, mut beta) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
        let mut scale = 0.0f64;
        for _ in 0..steps {
            // Full reorthogonalisation.
            deflate(&mut q, &basis);
            let norm = dot(&q, &q).sqrt();
            if !(norm > 1e-10 * scale.max(1.0) || basis.is_empty() && norm > 0.0) {
                break; // an invariant subspace: the basis holds what it can
            }
            if !basis.is_empty() {
                beta.push(norm);
            }
            q.iter_mut().for_each(|v| *v /= norm);
            self.laplacian(&q, &mut w);
            let a = dot(&q, &w);
            alpha.push(a);
            scale = scale.max(a.abs()).max(norm);
            basis.push(std::mem::replace(&mut q, w.clone()));
        }
        let k = basis.len();
        if k == 0 {
            return None;
        }
        let coefficients = lowest(&alpha, &beta);
        let mut y = vec![0.0; m];
        for (i, b) in basis.iter().enumerate() {
            let c = coefficients[i];
            y.iter_mut().zip(b).for_each(|(yv, bv)| *yv += c * bv);
        }
        deflate(&mut y, &[]);
        let norm = dot(&y, &y).sqrt();
        (norm > 0.0).then(|| y.into_iter().map(|v| v / norm).collect())
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The unit eigenvector of the smallest eigenvalue of the symmetric tridiagonal matrix with
/// diagonal `alpha` and off-diagonal `beta` (one shorter): the eigenvalue by bisection on the
/// Sturm count (the negative pivots of `T - x I`), then inverse iteration just below it, where
/// `T - x I` is positive definite and its tridiagonal elimination needs no pivoting.
fn lowest(alpha: &[f64], beta: &[f64]) -> Vec<f64> {
    let k = alpha.len();
    let b = |i: usize| if i < beta.len() { beta[i].abs() } else { 0.0 };
    let reach = |i: usize| b(i) + if i > 0 { b(i - 1) } else { 0.0 };
    // Gershgorin's interval.
    let lo0 = (0..k).map(|i| alpha[i] - reach(i)).fold(f64::INFINITY, f64::min);
    let hi0 = (0..k).map(|i| alpha[i] + reach(i)).fold(f64::NEG_INFINITY, f64::max);
    let width = (hi0 - lo0).max(f64::MIN_POSITIVE);
    let below = |x: f64| {
        // Eigenvalues below x: the negative pivots of T - x I.
        let (mut d, mut count) = (1.0f64, 0usize);
        for i in 0..k {
            let off = if i > 0 { beta[i - 1] * beta[i - 1] / d } else { 0.0 };
            d = alpha[i] - x - off;
            if d == 0.0 {
                d = -f64::EPSILON * width;
            }
            count += usize::from(d < 0.0);
        }
        count
    };
    let (mut lo, mut hi) = (lo0, hi0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if below(mid) >= 1 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let shift = lo - 1e-10 * width;
    let mut y = vec![1.0; k];
    let (mut c, mut z) = (vec![0.0; k], vec![0.0; k]);
    for _ in 0..3 {
        // (T - shift I) z = y by elimination down the diagonal, then back.
        let mut d = alpha[0] - shift;
        c[0] = if k > 1 { beta[0] / d } else { 0.0 };
        z[0] = y[0] / d;
        for i in 1..k {
            d = alpha[i] - shift - beta[i - 1] * c[i - 1];
            c[i] = if i < beta.len() { beta[i] / d } else { 0.0 };
            z[i] = (y[i] - beta[i - 1] * z[i - 1]) / d;
        }
        for i in (0..k - 1).rev() {
            z[i] -= c[i] * z[i + 1];
        }
        let norm = dot(&z, &z).sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            break;
        }
        y.iter_mut().zip(&z).for_each(|(yv, zv)| *yv = zv / norm);
    }
    y
}

#[cfg(test)]
mod tests {
    use super::{lowest, stages, LEAF};

    /// The springs of an `n x n` grid with its diagonals (a cloth's structural and shear
    /// springs), as the elimination graph's lists.
    fn grid(n: usize) -> Vec<Vec<u32>> {
        let id = |r: usize, c: usize| (r * n + c) as u32;
        let mut adj = vec![Vec::new(); n * n];
        for r in 0..n {
            for c in 0..n {
                for (dr, dc) in [(0, 1), (1, 0), (1, 1), (1, -1)] {
                    let (r2, c2) = (r as i64 + dr, c as i64 + dc);
                    if r2 < n as i64 && (0..n as i64).contains(&c2) {
                        let (a, b) = (id(r, c), id(r2 as usize, c2 as usize));
                        adj[a as usize].push(b);
                        adj[b as usize].push(a);
                    }
                }
            }
        }
        adj.iter_mut().for_each(|l| l.sort_unstable());
        adj
    }

    #[test]
    fn a_grid_is_first_cut_along_one_row_or_column_into_equal_halves() {
        let n = 24;
        let stage = stages(&grid(n), &vec![true; n * n]);
        let top: Vec<usize> = (0..n * n).filter(|&p| stage[p] == u32::MAX).collect();
        assert_eq!(top.len(), n, "the first separator: {top:?}");
        let (rows, cols): (Vec<usize>, Vec<usize>) = top.iter().map(|&p| (p / n, p % n)).unzip();
        let line = rows.iter().all(|&r| r == rows[0]) || cols.iter().all(|&c| c == cols[0]);
        assert!(line, "not a row or a column: {top:?}");
        let at = if rows.iter().all(|&r| r == rows[0]) { rows[0] } else { cols[0] };
        assert!((n / 2 - 1..=n / 2).contains(&at), "cut at {at} of {n}");
        // The halves are cut again: 24 x 12 each, more than a leaf.
        assert!(n * n / 2 > LEAF && (0..n * n).any(|p| stage[p] == u32::MAX - 1));
    }

    #[test]
    fn the_stages_are_the_same_on_one_thread_or_two() {
        // 60 x 60 = 3,600 particles: the halves of the first cut are cut at once.
        let adj = grid(60);
        let free = vec![true; adj.len()];
        let one =
            rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| stages(&adj, &free));
        let two =
            rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap().install(|| stages(&adj, &free));
        assert_eq!(one, two);
        assert!(one.contains(&(u32::MAX - 2)), "cut at depth 2");
    }

    #[test]
    fn a_chain_is_cut_at_a_few_particles_and_a_static_particle_is_left_out() {
        let n = 1000;
        let mut adj = vec![Vec::new(); n];
        for i in 0..n - 1 {
            adj[i].push(i as u32 + 1);
            adj[i + 1].push(i as u32);
        }
        let mut free = vec![true; n];
        free[0] = false;
        adj[1].retain(|&j| j != 0);
        adj[0].clear();
        let stage = stages(&adj, &free);
        assert_eq!(stage[0], 0);
        // The smooth vectors are not converged (24 Lanczos steps on 999 particles): a cut may
        // cross the chain a few times, not once, each crossing a particle.
        for depth in 0..3 {
            let count = stage.iter().filter(|&&s| s == u32::MAX - depth).count();
            assert!(
                (1 << depth..=8 << depth).contains(&count),
                "{count} particles in the separators at depth {depth}"
            );
        }
        // Pieces of at most LEAF particles are left whole.
        let cut = stage.iter().filter(|&&s| s != 0).count();
        assert!(cut < n / LEAF * 2, "{cut} particles in separators");
    }

    #[test]
    fn a_graph_in_pieces_is_cut_piece_by_piece() {
        // Two grids side by side, unconnected: each cut on its own at depth 0.
        let g = grid(12);
        let m = g.len();
        let mut adj = g.clone();
        adj.extend(g.iter().map(|l| l.iter().map(|&j| j + m as u32).collect::<Vec<_>>()));
        let stage = stages(&adj, &vec![true; 2 * m]);
        let top = |range: std::ops::Range<usize>| range.filter(|&p| stage[p] == u32::MAX).count();
        assert_eq!((top(0..m), top(m..2 * m)), (12, 12));
    }

    #[test]
    fn the_lowest_eigenvector_of_a_tridiagonal_matrix() {
        // 2 on the diagonal, -1 beside it: eigenvectors sin(j k pi / (n + 1)), the lowest k = 1.
        let n = 30;
        let y = lowest(&vec![2.0; n], &vec![-1.0; n - 1]);
        let exact: Vec<f64> =
            (1..=n).map(|j| (j as f64 * std::f64::consts::PI / (n + 1) as f64).sin()).collect();
        let norm = exact.iter().map(|v| v * v).sum::<f64>().sqrt();
        let sign = y[0].signum();
        for (a, e) in y.iter().zip(&exact) {
            assert!((sign * a - e / norm).abs() < 1e-9, "{a} against {}", e / norm);
        }
    }
}
