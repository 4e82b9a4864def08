//! SHAKE and RATTLE: the rigid distances of a method whose constraint mode is
//! [`Mode::Rattle`] (velocity Verlet's), solved along the gradient at the step's start
//! positions (Ryckaert, Ciccotti, Berendsen 1977), then the velocities made tangent to them
//! (Andersen 1983). The projection
//! (PBD / XPBD) sweeps are the parent module's; both run in its [`Solver::positions`].

use super::{dot, sep, Mode, Solver, TOLERANCE};
use crate::constraints::Constraint;
use crate::forces::Endpoint;

/// Whether a distance is solved by SHAKE: rigid, under the RATTLE solver.
#[inline]
pub(super) fn rigid(compliance: f64, mode: Mode) -> bool {
    compliance == 0.0 && mode == Mode::Rattle
}

impl Solver {
    /// One SHAKE update of `|x_i - x_j|^2 = L^2` along the gradient at the start positions
    /// `r0 = x_i(t) - x_j(t)`: with `d` the current separation and `C = d.d - L^2`,
    /// `mu = -C / (2 (w_i + w_j) d.r0)`, `x_i += w_i mu r0`, `x_j -= w_j mu r0` (one Newton
    /// step on the multiplier). Returns the relative length error before the update.
    pub(super) fn shake(&mut self, x: &mut [f64], dim: usize, i: usize, j: Endpoint, length: f64) -> f64 {
        let wsum = self.w[i] + self.w_of(j);
        if wsum == 0.0 {
            return 0.0;
        }
        let d = sep(x, dim, i, j);
        let r0 = sep(&self.start, dim, i, j);
        let l2 = length * length;
        let c = dot(&d, &d) - l2;
        let err = c.abs() / (2.0 * l2);
        if err <= TOLERANCE {
            return err;
        }
        let dr = dot(&d, &r0);
        // The gradient at the start no longer sees the constraint (a step that turned the
        // rod by ~90 degrees): fall back to the current direction.
        let g = if dr > 0.1 * dot(&d, &d).sqrt() * dot(&r0, &r0).sqrt() { r0 } else { d };
        let den = 2.0 * wsum * dot(&d, &g);
        if den != 0.0 {
            self.apply(x, dim, i, j, -c / den, &g);
        }
        err
    }

    /// RATTLE's velocity half: pinned particles at rest, then up to `iterations` sweeps that
    /// remove the velocity along each rigid distance, `k = -(d . w) / ((w_i + w_j) d.d)`,
    /// `v_i += w_i k d`, `v_j -= w_j k d`, until every `d . w` is within [`TOLERANCE`] of
    /// `|d| |w|`.
    pub fn tangent(&self, list: &[Constraint], iterations: u32, dim: usize, x: &[f64], v: &mut [f64]) {
        for c in list {
            if let Constraint::Pin { i, .. } = *c {
                v[i * dim..(i + 1) * dim].fill(0.0);
            }
        }
        for _ in 0..iterations {
            let mut worst: f64 = 0.0;
            for c in list {
                let Constraint::Distance { i, j, compliance, .. } = *c else { continue };
                if compliance != 0.0 {
                    continue;
                }
                let wsum = self.w[i] + self.w_of(j);
                let d = sep(x, dim, i, j);
                let rel = match j {
                    // An anchor does not move: the relative velocity is v_i.
                    Endpoint::Anchor(_) => {
                        let mut r = [0.0; 3];
                        r[..dim].copy_from_slice(&v[i * dim..(i + 1) * dim]);
                        r
                    }
                    Endpoint::Particle(_) => sep(v, dim, i, j),
                };
                let (dd, cv) = (dot(&d, &d), dot(&d, &rel));
                let scale = (dd * dot(&rel, &rel)).sqrt();
                if wsum == 0.0 || dd == 0.0 || scale == 0.0 {
                    continue;
                }
                worst = worst.max(cv.abs() / scale);
                self.apply(v, dim, i, j, -cv / (wsum * dd), &d);
            }
            if worst <= TOLERANCE {
                break;
            }
        }
    }
}
