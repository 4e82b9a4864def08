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
    assert!(m.build(&b, c));
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
    assert!(m.build(&b, c));
    let rhs = [1.0, -2.0, 0.5, 3.0, 0.0, 0.0];
    let mut x = [0.0; 6];
    let r = cg(&m, &rhs, &mut x, CgParams { tol: 1e-14, max_iter: 50 }, &mut CgWork::default());
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
