use super::*;

/// A 3-particle 2D system: particle 0 anchored (kd), a pair 0-1 and a pair 1-2, particle 2
/// static; dense `A` built by hand from the same blocks.
fn blocks() -> Blocks {
    let mut b = Blocks::default();
    b.reset(2, &[2.0, 3.0, f64::INFINITY]);
    b.kd[0] = [[-5.0, 1.0, 0.0], [1.0, -4.0, 0.0], [0.0, 0.0, 0.0]];
    b.dd[1] = [[-0.5, 0.0, 0.0], [0.0, -0.5, 0.0], [0.0, 0.0, 0.0]];
    b.pairs.push((0, 1, [[-7.0, 2.0, 0.0], [2.0, -3.0, 0.0], [0.0; 3]], [[0.0; 3]; 3]));
    b.pairs.push((1, 2, [[-1.0, 0.0, 0.0], [0.0, -2.0, 0.0], [0.0; 3]], [[0.0; 3]; 3]));
    b
}

fn dense(b: &Blocks, c: f64) -> Vec<Vec<f64>> {
    let n = 4; // the two free particles' coordinates
    let mut a = vec![vec![0.0; n]; n];
    for p in 0..2 {
        for r in 0..2 {
            a[2 * p + r][2 * p + r] += b.mass[p];
            for k in 0..2 {
                a[2 * p + r][2 * p + k] -= c * b.dd[p][r][k] + c * c * b.kd[p][r][k];
            }
        }
    }
    for &(i, j, ref k, _) in &b.pairs {
        for r in 0..2 {
            for col in 0..2 {
                let m = -c * c * k[r][col];
                for (p, q, s) in [(i, i, 1.0), (j, j, 1.0), (i, j, -1.0), (j, i, -1.0)] {
                    if p < 2 && q < 2 {
                        a[2 * p + r][2 * q + col] += s * m;
                    }
                }
            }
        }
    }
    a
}

#[test]
fn the_newton_matrix_applies_as_its_dense_assembly() {
    let (b, c) = (blocks(), 0.1);
    let mut m = NewtonMatrix::default();
    assert!(m.build(&b, c, Preconditioner::BlockJacobi));
    let a = dense(&b, c);
    let x = [0.3, -1.2, 2.0, 0.7, 5.0, -5.0];
    let mut y = [0.0; 6];
    m.apply(&x, &mut y);
    for r in 0..4 {
        let want: f64 = (0..4).map(|k| a[r][k] * x[k]).sum();
        assert!((y[r] - want).abs() < 1e-12, "row {r}: {} vs {want}", y[r]);
    }
    // The static particle's rows are the identity.
    assert_eq!(&y[4..], &x[4..]);
}

#[test]
fn conjugate_gradients_solve_the_newton_system() {
    let (b, c) = (blocks(), 0.1);
    let mut m = NewtonMatrix::default();
    assert!(m.build(&b, c, Preconditioner::BlockJacobi));
    let rhs = [1.0, -2.0, 0.5, 3.0, 0.0, 0.0];
    let mut x = [0.0; 6];
    let r = cg(
        &m,
        &rhs,
        &mut x,
        CgParams { tol: 1e-14, max_iter: 50, ..CgParams::default() },
        &mut CgWork::default(),
    );
    assert!(r.converged && r.iterations <= 4, "{r:?}");
    let mut y = [0.0; 6];
    m.apply(&x, &mut y);
    for (a, b) in y.iter().zip(&rhs) {
        assert!((a - b).abs() < 1e-12);
    }
}

#[test]
fn a_block_inverse_is_the_inverse_and_a_singular_block_has_none() {
    let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.0], [0.5, 0.0, 2.0]];
    let inv = inverse(&m).unwrap();
    for r in 0..3 {
        for k in 0..3 {
            let e: f64 = (0..3).map(|j| m[r][j] * inv[j][k]).sum();
            assert!((e - f64::from(u8::from(r == k))).abs() < 1e-14);
        }
    }
    assert!(inverse(&[[1.0, 2.0, 0.0], [2.0, 4.0, 0.0], [0.0, 0.0, 1.0]]).is_none());
}

/// `-(s I + t u u^T)` for a direction made from `seed` (negative semidefinite, as the
/// springs' blocks).
fn spring_block(seed: f64, s: f64, t: f64) -> Block {
    let u = [seed.sin(), (2.0 * seed).cos(), 0.5 + 0.3 * seed.cos()];
    let r = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let mut b = [[0.0; 3]; 3];
    for a in 0..3 {
        for k in 0..3 {
            b[a][k] = -t * u[a] * u[k] / (r * r);
        }
        b[a][a] -= s;
    }
    b
}

/// `n` 3D particles of 10 g joined by stiff springs `links`, particle `fixed` static.
fn network(n: usize, links: &[(usize, usize)], fixed: usize) -> Blocks {
    let mut mass = vec![0.01; n];
    mass[fixed] = f64::INFINITY;
    let mut b = Blocks::default();
    b.reset(3, &mass);
    for (e, &(i, j)) in links.iter().enumerate() {
        b.pairs.push((i, j, spring_block(e as f64 + 0.3, 1e3, 1e5), [[0.0; 3]; 3]));
    }
    b
}

/// CG on `b`'s Newton matrix at dt = 1/60 with `pre`: the result, and the residual of the
/// solution checked by applying the matrix.
fn solve(b: &Blocks, pre: Preconditioner) -> (CgResult, Preconditioner) {
    let mut m = NewtonMatrix::default();
    assert!(m.build(b, 1.0 / 60.0, pre));
    let n = 3 * b.mass.len();
    let rhs: Vec<f64> = (0..n).map(|k| if m.free(k / 3) { (k as f64 * 0.7).sin() } else { 0.0 }).collect();
    let mut x = vec![0.0; n];
    let params = CgParams { tol: 1e-12, max_iter: 10_000, preconditioner: pre };
    let r = cg(&m, &rhs, &mut x, params, &mut CgWork::default());
    let mut y = vec![0.0; n];
    m.apply(&x, &mut y);
    let norm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
    let err = y.iter().zip(&rhs).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
    assert!(err <= 1e-10 * norm, "{pre:?}: residual {err} against {norm}");
    (r, m.preconditioner())
}

#[test]
fn incomplete_cholesky_is_exact_on_a_chain() {
    // A path drops no fill: the factor is the matrix's, and CG converges in one iteration
    // (a second takes the rounding of the first below 1e-12), where block Jacobi takes about
    // as many as the chain has links.
    let links: Vec<(usize, usize)> = (0..40).map(|i| (i + 1, i)).collect();
    let b = network(41, &links, 0);
    let (ic, used) = solve(&b, Preconditioner::IncompleteCholesky);
    assert_eq!(used, Preconditioner::IncompleteCholesky);
    assert!(ic.converged && ic.iterations <= 2, "{ic:?}");
    let (jacobi, used) = solve(&b, Preconditioner::BlockJacobi);
    assert_eq!(used, Preconditioner::BlockJacobi);
    assert!(jacobi.converged && jacobi.iterations >= 20, "{jacobi:?}");
}

#[test]
fn incomplete_cholesky_on_a_grid_with_shear_springs_converges_faster_than_block_jacobi() {
    // A 12 x 12 cloth's pattern (structural and both shear springs, a spring listed twice):
    // the elimination's fill is dropped, the factor is approximate, CG still converges to
    // the solution, in fewer iterations.
    let n = 12;
    let mut links = grid_links(n);
    links.push((3 * n + 3, 3 * n + 4));
    let b = network(n * n, &links, (n - 1) * n);
    let (ic, used) = solve(&b, Preconditioner::IncompleteCholesky);
    assert_eq!(used, Preconditioner::IncompleteCholesky);
    let (jacobi, _) = solve(&b, Preconditioner::BlockJacobi);
    assert!(ic.converged && jacobi.converged);
    assert!(2 * ic.iterations <= jacobi.iterations, "IC {ic:?}, block Jacobi {jacobi:?}");
}

/// A `n` x `n` cloth's springs: structural and both shear diagonals.
fn grid_links(n: usize) -> Vec<(usize, usize)> {
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
    links
}

#[test]
fn the_complete_cholesky_factor_solves_a_cloth_in_one_iteration() {
    // The exact solve: CG's first iteration lands on the solution (a second may take its
    // rounding below 1e-12) on a 24 x 24 cloth with a spring listed twice and a pinned
    // particle, where incomplete Cholesky takes tens; the order keeps the fill to a few times
    // the matrix (the matrix: 5 blocks a particle, its diagonal and 4 springs).
    let n = 24;
    let mut links = grid_links(n);
    links.push((3 * n + 3, 3 * n + 4));
    let b = network(n * n, &links, n * (n - 1));
    let (full, used) = solve(&b, Preconditioner::Cholesky);
    assert_eq!(used, Preconditioner::Cholesky);
    assert!(full.converged && full.iterations <= 2, "{full:?}");
    let (ic, _) = solve(&b, Preconditioner::IncompleteCholesky);
    assert!(ic.iterations >= 10 * full.iterations, "IC {ic:?}, Cholesky {full:?}");
    let mut m = NewtonMatrix::default();
    assert!(m.build(&b, 1.0 / 60.0, Preconditioner::Cholesky));
    let per = m.factor_blocks() as f64 / (n * n - 1) as f64;
    assert!((5.0..20.0).contains(&per), "{per} blocks a particle");
}

/// The complete Cholesky factor of `b`'s Newton matrix at dt = 1/60 applied to a fixed
/// right-hand side: the result's bits.
fn factor_solve_bits(b: &Blocks) -> Vec<u64> {
    let mut m = NewtonMatrix::default();
    assert!(m.build(b, 1.0 / 60.0, Preconditioner::Cholesky));
    let rhs: Vec<f64> = (0..3 * b.mass.len()).map(|k| (k as f64 * 0.3).cos()).collect();
    let mut z = vec![0.0; rhs.len()];
    m.precondition(&rhs, &mut z);
    z.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn the_complete_cholesky_factor_takes_the_same_bits_on_either_vector_path() {
    // The factorisation and its solve run AVX2 code where the CPU has it: the same IEEE
    // operations in the same order as the baseline build, so the same bits (crate::simd).
    let n = 20;
    let b = network(n * n, &grid_links(n), 0);
    let run = |vector: bool| {
        crate::simd::set_vector_paths(vector);
        factor_solve_bits(&b)
    };
    let (plain, vector) = (run(false), run(true));
    crate::simd::set_vector_paths(true);
    assert_eq!(plain, vector);
}

#[test]
fn the_complete_cholesky_factor_takes_the_same_bits_on_one_thread_and_on_two() {
    // A 24 x 24 cloth's factorisation is past SPLIT_MIN: two subtrees of the elimination
    // tree factored at once, then their ancestors in a fixed order.
    let n = 24;
    let b = network(n * n, &grid_links(n), 0);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| factor_solve_bits(&b))
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_complete_factorisation_that_breaks_down_leaves_the_next_one_exact() {
    // Springs of the wrong sign in the cloth's far corner make the matrix indefinite: the
    // factorisation stops at a pivot that is not positive definite, partway, and that
    // matrix is preconditioned otherwise; the next, positive definite, is factored afresh.
    let n = 24;
    let mut bad = network(n * n, &grid_links(n), 0);
    let last = bad.pairs.len() - 1;
    bad.pairs[last].2 = spring_block(0.5, -1e7, 0.0);
    let mut m = NewtonMatrix::default();
    assert!(m.build(&bad, 1.0 / 60.0, Preconditioner::Cholesky));
    assert_ne!(m.preconditioner(), Preconditioner::Cholesky);
    let good = network(n * n, &grid_links(n), 0);
    assert!(m.build(&good, 1.0 / 60.0, Preconditioner::Cholesky));
    assert_eq!(m.preconditioner(), Preconditioner::Cholesky);
    let rhs: Vec<f64> =
        (0..3 * n * n).map(|k| if m.free(k / 3) { (k as f64 * 0.7).sin() } else { 0.0 }).collect();
    let mut x = vec![0.0; rhs.len()];
    let params = CgParams { tol: 1e-12, max_iter: 10, preconditioner: Preconditioner::Cholesky };
    let r = cg(&m, &rhs, &mut x, params, &mut CgWork::default());
    assert!(r.converged && r.iterations <= 2, "{r:?}");
}

#[test]
fn the_complete_cholesky_factor_is_the_dense_solve() {
    // The 3-particle system of `blocks()` (2D, a static particle): the preconditioner itself
    // applied to b is A^-1 b to rounding, the static row passed through.
    let (b, c) = (blocks(), 0.1);
    let mut m = NewtonMatrix::default();
    assert!(m.build(&b, c, Preconditioner::Cholesky));
    assert_eq!(m.preconditioner(), Preconditioner::Cholesky);
    let rhs = [1.0, -2.0, 0.5, 3.0, 4.0, -1.0];
    let mut x = [0.0; 6];
    m.precondition(&rhs, &mut x);
    let mut y = [0.0; 6];
    m.apply(&x, &mut y);
    for (k, (a, b)) in y.iter().zip(&rhs).enumerate() {
        assert!((a - b).abs() < 1e-13, "row {k}: {a} against {b}");
    }
}

#[test]
fn the_complete_cholesky_factor_solves_a_three_dimensional_lattice_and_a_graph_in_pieces() {
    // The nested dissection's cuts on what is not a cloth: a 9 x 9 x 9 lattice with its face
    // diagonals (729 particles, cut into slabs), and the same lattice twice beside a chain,
    // unconnected, with a static particle in each: the exact solve either way.
    let n = 9;
    let id = |x: usize, y: usize, z: usize| (x * n + y) * n + z;
    let mut lattice = Vec::new();
    for x in 0..n {
        for y in 0..n {
            for z in 0..n {
                let steps: [(usize, usize, usize); 6] =
                    [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, 1, 1), (1, 0, 1)];
                for (dx, dy, dz) in steps {
                    if x + dx < n && y + dy < n && z + dz < n {
                        lattice.push((id(x, y, z), id(x + dx, y + dy, z + dz)));
                    }
                }
            }
        }
    }
    let (r, used) = solve(&network(n * n * n, &lattice, 0), Preconditioner::Cholesky);
    assert_eq!(used, Preconditioner::Cholesky);
    assert!(r.converged && r.iterations <= 2, "{r:?}");
    let m = n * n * n;
    let mut pieces = lattice.clone();
    pieces.extend(lattice.iter().map(|&(i, j)| (i + m, j + m)));
    pieces.extend((2 * m..2 * m + 199).map(|i| (i, i + 1)));
    let mut b = network(2 * m + 200, &pieces, m + 5);
    b.mass[2 * m + 100] = f64::INFINITY;
    let (r, used) = solve(&b, Preconditioner::Cholesky);
    assert_eq!(used, Preconditioner::Cholesky);
    assert!(r.converged && r.iterations <= 2, "{r:?}");
}

#[test]
fn a_network_past_the_fill_limit_is_preconditioned_by_incomplete_cholesky() {
    // Every particle joined to every other: the factor is dense, past the limit when there
    // are more particles than FILL_LIMIT; below it, the complete factor.
    let all =
        |n: usize| -> Vec<(usize, usize)> { (0..n).flat_map(|i| (0..i).map(move |j| (i, j))).collect() };
    let big = FILL_LIMIT * 2 + 10;
    let (r, used) = solve(&network(big, &all(big), 0), Preconditioner::Cholesky);
    assert_eq!(used, Preconditioner::IncompleteCholesky);
    assert!(r.converged);
    let (r, used) = solve(&network(40, &all(40), 0), Preconditioner::Cholesky);
    assert_eq!(used, Preconditioner::Cholesky);
    assert!(r.converged && r.iterations <= 2, "{r:?}");
}

#[test]
fn preconditioners_are_named() {
    for name in Preconditioner::NAMES {
        assert_eq!(Preconditioner::named(name).map(Preconditioner::name), Some(name));
    }
    assert_eq!(Preconditioner::named("ilu"), None);
    assert_eq!(Preconditioner::default(), Preconditioner::Cholesky);
}
