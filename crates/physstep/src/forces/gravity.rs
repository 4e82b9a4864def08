//! Uniform gravity.

/// `-sum m g . x` over particles of finite mass, J.
pub(super) fn potential(dim: usize, g: [f64; 3], x: &[f64], mass: &[f64]) -> f64 {
    let mut u = 0.0;
    for (xp, &m) in x.chunks_exact(dim).zip(mass) {
        if m.is_finite() {
            let gx: f64 = xp.iter().zip(g).map(|(xk, gk)| xk * gk).sum();
            u -= m * gx;
        }
    }
    u
}
