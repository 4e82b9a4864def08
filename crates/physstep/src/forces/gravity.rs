//! Uniform gravity.

/// Adds `g` to the acceleration of every dynamic particle.
#[inline]
pub(super) fn accel(dim: usize, g: [f64; 3], inv_mass: &[f64], a: &mut [f64]) {
    match dim {
        1 => add::<1>(g, inv_mass, a),
        2 => add::<2>(g, inv_mass, a),
        _ => add::<3>(g, inv_mass, a),
    }
}

/// Writes `0 + g` (what [`accel`] adds to zeros, bitwise) to every dynamic particle and 0 to
/// static ones.
#[inline]
pub(super) fn set(dim: usize, g: [f64; 3], inv_mass: &[f64], a: &mut [f64]) {
    match dim {
        1 => write::<1>(g, inv_mass, a),
        2 => write::<2>(g, inv_mass, a),
        _ => write::<3>(g, inv_mass, a),
    }
}

#[inline]
fn write<const D: usize>(g: [f64; 3], inv_mass: &[f64], a: &mut [f64]) {
    for (ap, &im) in a.chunks_exact_mut(D).zip(inv_mass) {
        for k in 0..D {
            ap[k] = if im > 0.0 { 0.0 + g[k] } else { 0.0 };
        }
    }
}

/// [`accel`] with the dimension known at compile time, so the loop vectorises.
#[inline]
fn add<const D: usize>(g: [f64; 3], inv_mass: &[f64], a: &mut [f64]) {
    for (ap, &im) in a.chunks_exact_mut(D).zip(inv_mass) {
        if im > 0.0 {
            for k in 0..D {
                ap[k] += g[k];
            }
        }
    }
}

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
