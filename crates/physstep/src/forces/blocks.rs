//! The built-in forces' Jacobians as 3 x 3 blocks for the sparse Newton solve
//! ([`crate::linalg`]), each kept symmetric negative semidefinite.

// Small dense blocks read best as the formulas index them.
#![allow(clippy::needless_range_loop)]

use super::{dot, separation, Endpoint, Force, ForceSet};
use crate::linalg::{Block, Blocks};

/// `s I + t u u^T` (leading `dim` part; identity-free beyond it).
fn iso_plus_outer(dim: usize, s: f64, t: f64, u: &[f64; 3]) -> Block {
    let mut b = [[0.0; 3]; 3];
    for r in 0..dim {
        for k in 0..dim {
            b[r][k] = t * u[r] * u[k];
        }
        b[r][r] += s;
    }
    b
}

fn add(a: &mut Block, b: &Block) {
    for r in 0..3 {
        for k in 0..3 {
            a[r][k] += b[r][k];
        }
    }
}

/// `(dF_i/dd, dF_i/dw)` of a spring for the Newton matrix, with `d = x_i - x_j`,
/// `u = d / r`: a zero-rest spring is linear (`-k I`, `-c I`); a stretched one
/// `-k ((1 - rest/r) I + rest/r u u^T)` and `-c u u^T`. Left out, to keep them semidefinite:
/// a compressed spring's sideways term (`-k (1 - rest/r) (I - u u^T)`, which pushes the
/// wrong way) and the damping's coupling to the direction (`-c/r (u (P w)^T + (w.u) P)`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn spring(
    dim: usize,
    x: &[f64],
    i: usize,
    j: Endpoint,
    k: f64,
    rest: f64,
    c: f64,
    exact: bool,
) -> (Block, Block) {
    if rest == 0.0 {
        return (iso_plus_outer(dim, -k, 0.0, &[0.0; 3]), iso_plus_outer(dim, -c, 0.0, &[0.0; 3]));
    }
    let d = separation(dim, x, i, j);
    let r2 = dot(&d, &d);
    if r2 == 0.0 {
        return (iso_plus_outer(dim, -k, 0.0, &d), [[0.0; 3]; 3]);
    }
    let r = r2.sqrt();
    let u = [d[0] / r, d[1] / r, d[2] / r];
    let ratio = if exact { rest / r } else { (rest / r).min(1.0) };
    (iso_plus_outer(dim, -k * (1.0 - ratio), -k * ratio, &u), iso_plus_outer(dim, 0.0, -c, &u))
}

impl ForceSet {
    /// Fills `out` (reset by the caller for these particles) with the forces' Jacobians as
    /// blocks and returns `true`; `false` when a force has none (n-body gravity couples every
    /// pair, a rod has no analytic Jacobian): the implicit methods then solve densely.
    pub(crate) fn blocks(&self, x: &[f64], v: &[f64], out: &mut Blocks) -> bool {
        let dim = out.dim;
        for force in self.iter() {
            match *force {
                Force::Gravity { .. } => {}
                // Between two particles: from their own list, below.
                Force::Spring { j: Endpoint::Particle(_), .. } => {}
                Force::Spring { i, j, stiffness, rest_length, damping } => {
                    let (k, d) = spring(dim, x, i, j, stiffness, rest_length, damping, out.exact);
                    add(&mut out.kd[i], &k);
                    add(&mut out.dd[i], &d);
                }
                Force::Drag { linear, quadratic } => {
                    for (p, vp) in v.chunks_exact(dim).enumerate() {
                        let mut w = [0.0; 3];
                        w[..dim].copy_from_slice(vp);
                        let speed = dot(&w, &w).sqrt();
                        // -(c1 + c2 |v|) I - c2 v v^T / |v|, in u = v / |v|: - c2 |v| u u^T.
                        let u =
                            if speed > 0.0 { [w[0] / speed, w[1] / speed, w[2] / speed] } else { [0.0; 3] };
                        let b = iso_plus_outer(dim, -(linear + quadratic * speed), -quadratic * speed, &u);
                        add(&mut out.dd[p], &b);
                    }
                }
                Force::CentralGravity { center, gm } => {
                    for (p, xp) in x.chunks_exact(dim).enumerate() {
                        let mut d = [0.0; 3];
                        for k in 0..dim {
                            d[k] = xp[k] - center[k];
                        }
                        let r2 = dot(&d, &d);
                        let m = out.mass[p];
                        if r2 == 0.0 || !m.is_finite() {
                            continue;
                        }
                        // m gm / r^3 (3 u u^T - I), less its radial part (2 m gm / r^3 along
                        // u, which pulls the wrong way for the matrix): -m gm / r^3 (I - u u^T).
                        let r = r2.sqrt();
                        let u = [d[0] / r, d[1] / r, d[2] / r];
                        let s = -m * gm / (r2 * r);
                        add(&mut out.kd[p], &iso_plus_outer(dim, s, -s, &u));
                    }
                }
                Force::NBody { .. } | Force::Rod { .. } => return false,
            }
        }
        match dim {
            1 => pair_blocks::<1>(self.springs(), x, out),
            2 => pair_blocks::<2>(self.springs(), x, out),
            _ => pair_blocks::<3>(self.springs(), x, out),
        }
        true
    }
}

/// The blocks of the springs between two particles (`(i, j, [k, rest, c])`, in canonical
/// order), on particles of `D` coordinates: as [`spring`] at any `dim`, the same bits.
#[inline(never)]
fn pair_blocks<const D: usize>(springs: &[(usize, usize, [f64; 3])], x: &[f64], out: &mut Blocks) {
    for &(i, j, [k, rest, c]) in springs {
        let (kb, db) = spring(D, x, i, Endpoint::Particle(j), k, rest, c, out.exact);
        out.pairs.push((i, j, kb, db));
    }
}
