//! Linear and quadratic drag.

/// Adds `da/dv = -inv_m (c1 I + c2 (|v| I + v v^T / |v|))` per particle to `dadv`.
pub(super) fn jacobian(dim: usize, v: &[f64], c1: f64, c2: f64, inv_mass: &[f64], dadv: &mut [f64]) {
    let len = inv_mass.len() * dim;
    for (p, (vp, &im)) in v.chunks_exact(dim).zip(inv_mass).enumerate() {
        let speed = vp.iter().map(|x| x * x).sum::<f64>().sqrt();
        let outer = if speed > 0.0 { c2 / speed } else { 0.0 };
        for a in 0..dim {
            let row = (p * dim + a) * len + p * dim;
            for b in 0..dim {
                let diag = if a == b { c1 + c2 * speed } else { 0.0 };
                dadv[row + b] -= im * (diag + outer * vp[a] * vp[b]);
            }
        }
    }
}
