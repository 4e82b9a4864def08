//! Gravity toward a fixed center.

/// `-gm m / r` over particles of finite mass (0 at `r = 0`), J.
// A loop over every particle: kept out of line, so the potential of a set of springs is
// not paid for with its set-up.
#[inline(never)]
pub(super) fn potential(dim: usize, center: [f64; 3], gm: f64, x: &[f64], mass: &[f64]) -> f64 {
    let mut u = 0.0;
    for (xp, &m) in x.chunks_exact(dim).zip(mass) {
        let r2: f64 = xp.iter().zip(center).map(|(xk, ck)| (xk - ck) * (xk - ck)).sum();
        if m.is_finite() && r2 > 0.0 {
            u -= gm * m / r2.sqrt();
        }
    }
    u
}

/// Adds `da/dx = -gm / r^3 (I - 3 u u^T)` per dynamic particle to `dadx`.
pub(super) fn jacobian(dim: usize, center: [f64; 3], gm: f64, x: &[f64], inv_mass: &[f64], dadx: &mut [f64]) {
    let len = inv_mass.len() * dim;
    for (p, (xp, &im)) in x.chunks_exact(dim).zip(inv_mass).enumerate() {
        let mut d = [0.0; 3];
        for k in 0..dim {
            d[k] = xp[k] - center[k];
        }
        let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if im == 0.0 || r2 == 0.0 {
            continue;
        }
        let s = -gm / (r2 * r2.sqrt());
        for a in 0..dim {
            let row = (p * dim + a) * len + p * dim;
            for b in 0..dim {
                let id = if a == b { 1.0 } else { 0.0 };
                dadx[row + b] += s * (id - 3.0 * d[a] * d[b] / r2);
            }
        }
    }
}
