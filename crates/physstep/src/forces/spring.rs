//! Damped springs between two particles or a particle and an anchor.

use super::{dot, relative, separation, Endpoint};

/// Adds the force on `i` (and its opposite on `j`) to `f`, N; `p = [k, rest, c]`.
///
/// `F_i = -k (r - rest) d / r - c (w . d) d / r^2`, `d = x_i - x_j`, `w = v_i - v_j`;
/// `F_i = -k d` at `r = 0`. A zero-rest-length spring is linear, `F_i = -k d - c w`: no
/// square root, and its damping does not vanish (or jump) where `d = 0`.
#[inline(always)]
pub(super) fn force(dim: usize, x: &[f64], v: &[f64], i: usize, j: Endpoint, p: [f64; 3], f: &mut [f64]) {
    let [k, rest, c] = p;
    let d = separation(dim, x, i, j);
    if rest == 0.0 {
        let w = relative(dim, v, i, j);
        for kk in 0..dim {
            let fk = -k * d[kk] - c * w[kk];
            f[i * dim + kk] += fk;
            if let Endpoint::Particle(j) = j {
                f[j * dim + kk] -= fk;
            }
        }
        return;
    }
    let r2 = dot(&d, &d);
    let s = if r2 > 0.0 {
        let w = relative(dim, v, i, j);
        let r = r2.sqrt();
        -k * (r - rest) / r - c * dot(&w, &d) / r2
    } else {
        -k
    };
    for (kk, dk) in d.iter().enumerate().take(dim) {
        let fk = s * dk;
        f[i * dim + kk] += fk;
        if let Endpoint::Particle(j) = j {
            f[j * dim + kk] -= fk;
        }
    }
}

/// Elastic energy `k (r - rest)^2 / 2`, J.
#[inline]
pub(super) fn potential(dim: usize, x: &[f64], i: usize, j: Endpoint, k: f64, rest: f64) -> f64 {
    let d = separation(dim, x, i, j);
    if rest == 0.0 {
        return 0.5 * k * dot(&d, &d);
    }
    let e = dot(&d, &d).sqrt() - rest;
    0.5 * k * e * e
}

/// `dF_i/dd` and `dF_i/dw` of one spring (3x3, the leading `dim` block used).
pub(super) struct Jacobian {
    kx: [[f64; 3]; 3],
    kv: [[f64; 3]; 3],
}

impl Jacobian {
    /// With `P = I - u u^T`:
    /// `dF/dd = -k (I - rest/r P) - c/r (u (P w)^T + (w . u) P)`, `dF/dw = -c u u^T`;
    /// at `r = 0`: `-k I` and 0; for a zero rest length (the linear spring): `-k I`, `-c I`.
    pub(super) fn new(dim: usize, x: &[f64], v: &[f64], i: usize, j: Endpoint, p: [f64; 3]) -> Self {
        let [k, rest, c] = p;
        let d = separation(dim, x, i, j);
        let r2 = dot(&d, &d);
        let mut kx = [[0.0; 3]; 3];
        let mut kv = [[0.0; 3]; 3];
        if rest == 0.0 {
            for a in 0..3 {
                kx[a][a] = -k;
                kv[a][a] = -c;
            }
            return Self { kx, kv };
        }
        if r2 == 0.0 {
            for (a, row) in kx.iter_mut().enumerate() {
                row[a] = -k;
            }
            return Self { kx, kv };
        }
        let w = relative(dim, v, i, j);
        let r = r2.sqrt();
        let u = d.map(|dk| dk / r);
        let wu = dot(&w, &u);
        let pw = [w[0] - wu * u[0], w[1] - wu * u[1], w[2] - wu * u[2]];
        for a in 0..3 {
            for b in 0..3 {
                let id = if a == b { 1.0 } else { 0.0 };
                let proj = id - u[a] * u[b];
                kx[a][b] = -k * (id - rest / r * proj) - c / r * (u[a] * pw[b] + wu * proj);
                kv[a][b] = -c * u[a] * u[b];
            }
        }
        Self { kx, kv }
    }

    /// Adds the blocks `+-inv_m_p dF/dd` to `dadx` and `+-inv_m_p dF/dw` to `dadv`.
    pub(super) fn add(
        &self,
        dim: usize,
        i: usize,
        j: Endpoint,
        inv_mass: &[f64],
        dadx: &mut [f64],
        dadv: &mut [f64],
    ) {
        let len = inv_mass.len() * dim;
        let mut block = |p: usize, q: usize, sign: f64| {
            let s = sign * inv_mass[p];
            for a in 0..dim {
                let row = (p * dim + a) * len + q * dim;
                for b in 0..dim {
                    dadx[row + b] += s * self.kx[a][b];
                    dadv[row + b] += s * self.kv[a][b];
                }
            }
        };
        block(i, i, 1.0);
        if let Endpoint::Particle(j) = j {
            block(i, j, -1.0);
            block(j, i, -1.0);
            block(j, j, 1.0);
        }
    }
}
