//! Uniform gravity.

/// `-sum m g . x` over particles of finite mass, J.
// A loop over every particle: kept out of line, so the potential of a set of springs is
// not paid for with its set-up.
#[inline(never)]
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
