//! Rigid rods as constraint accelerations.

use super::{dot, relative, separation, Endpoint};

/// Adds the rod's constraint acceleration to `a`, given everything else already in `a`:
/// `lambda = (-(w . w) / r - u . a_rel) / (inv_m_i + inv_m_j)`, `a_i += lambda inv_m_i u`,
/// `a_j -= lambda inv_m_j u`, so that `u . a_rel = -(w . w) / r` afterwards
/// (`d^2 |d|^2 / dt^2 = 0`).
#[inline]
pub(super) fn apply(
    dim: usize,
    i: usize,
    j: Endpoint,
    x: &[f64],
    v: &[f64],
    inv_mass: &[f64],
    a: &mut [f64],
) {
    let im_i = inv_mass[i];
    let im_j = match j {
        Endpoint::Particle(j) => inv_mass[j],
        Endpoint::Anchor(_) => 0.0,
    };
    let im = im_i + im_j;
    let d = separation(dim, x, i, j);
    let r2 = dot(&d, &d);
    if im == 0.0 || r2 == 0.0 {
        return;
    }
    let r = r2.sqrt();
    let u = d.map(|dk| dk / r);
    let w = relative(dim, v, i, j);
    let a_rel = relative(dim, a, i, j);
    let lambda = (-dot(&w, &w) / r - dot(&u, &a_rel)) / im;
    for (k, uk) in u.iter().enumerate().take(dim) {
        a[i * dim + k] += lambda * im_i * uk;
        if let Endpoint::Particle(j) = j {
            a[j * dim + k] -= lambda * im_j * uk;
        }
    }
}
