//! The relaxation sweeps: projection (PBD / XPBD, Jakobsen's relaxation) and SHAKE/RATTLE.
//!
//! Everything here works on flat particle slices (`x`, `v`, `a` of `n * dim`) and runs
//! serially, constraint after constraint in the order they were added (Gauss-Seidel), so the
//! bits never depend on the thread count.

use super::{Constraint, TOLERANCE};
use crate::forces::Endpoint;

/// Which solver a step uses: the world's method's [`Info::constraints`](crate::integrators::Info::constraints).
pub(crate) use crate::integrators::ConstraintMode as Mode;

/// The solver's scratch: reused from step to step, never state (rebuilt every step).
#[derive(Debug, Clone, Default)]
pub(crate) struct Solver {
    /// Positions at the start of the step (SHAKE's gradients).
    pub start: Vec<f64>,
    /// Positions after the method, before the sweeps.
    pub moved: Vec<f64>,
    /// Per particle: the inverse mass, 0 for a pinned particle.
    w: Vec<f64>,
    /// XPBD multipliers of this step, one per constraint.
    lambda: Vec<f64>,
    /// The largest relative correction of the last sweep of [`Solver::positions`] (above
    /// [`TOLERANCE`] when the sweeps ended at their cap with a constraint still off).
    pub last_worst: f64,
}

/// The other end's position component `k` (a particle's or the anchor's).
#[inline]
fn at(x: &[f64], dim: usize, j: Endpoint, k: usize) -> f64 {
    match j {
        Endpoint::Particle(j) => x[j * dim + k],
        Endpoint::Anchor(c) => c[k],
    }
}

/// `x_i - x_j` over `dim` components.
#[inline]
fn sep(x: &[f64], dim: usize, i: usize, j: Endpoint) -> [f64; 3] {
    let mut d = [0.0; 3];
    for (k, dk) in d.iter_mut().enumerate().take(dim) {
        *dk = x[i * dim + k] - at(x, dim, j, k);
    }
    d
}

/// Whether a distance is solved by SHAKE: rigid, under the RATTLE solver.
#[inline]
fn rigid(compliance: f64, mode: Mode) -> bool {
    compliance == 0.0 && mode == Mode::Rattle
}

#[inline]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Solver {
    /// Inverse mass of the other end (0 for an anchor).
    #[inline]
    fn w_of(&self, j: Endpoint) -> f64 {
        match j {
            Endpoint::Particle(j) => self.w[j],
            Endpoint::Anchor(_) => 0.0,
        }
    }

    /// Moves `x_i` by `wi s g` and `x_j` by `-wj s g`.
    #[inline]
    fn apply(&self, x: &mut [f64], dim: usize, i: usize, j: Endpoint, s: f64, g: &[f64; 3]) {
        let wi = self.w[i];
        for (k, gk) in g.iter().enumerate().take(dim) {
            x[i * dim + k] += wi * s * gk;
        }
        if let Endpoint::Particle(j) = j {
            let wj = self.w[j];
            for (k, gk) in g.iter().enumerate().take(dim) {
                x[j * dim + k] -= wj * s * gk;
            }
        }
    }

    /// The weights of this step: inverse masses, 0 for pinned particles (held where their
    /// pin is; a static particle is not moved by its pin).
    fn weigh(&mut self, list: &[Constraint], inv_mass: &[f64]) {
        self.w.clear();
        self.w.extend_from_slice(inv_mass);
        for c in list {
            if let Constraint::Pin { i, .. } = *c {
                self.w[i] = 0.0;
            }
        }
    }

    /// Relaxes the positions `x` (after the method's step of `h`) onto the constraints: pins
    /// set, then up to `iterations` sweeps, stopping early once a sweep finds no constraint
    /// off by more than [`TOLERANCE`] (relative). The positions before the sweeps are kept
    /// in `moved`. Returns the sweeps taken.
    #[allow(clippy::too_many_arguments)]
    pub fn positions(
        &mut self,
        list: &[Constraint],
        iterations: u32,
        mode: Mode,
        dim: usize,
        x: &mut [f64],
        inv_mass: &[f64],
        h: f64,
    ) -> u32 {
        self.moved.clear();
        self.moved.extend_from_slice(x);
        self.weigh(list, inv_mass);
        for c in list {
            if let Constraint::Pin { i, point } = *c {
                if inv_mass[i] > 0.0 {
                    x[i * dim..(i + 1) * dim].copy_from_slice(&point[..dim]);
                }
            }
        }
        self.lambda.clear();
        self.lambda.resize(list.len(), 0.0);
        let inv_h2 = 1.0 / (h * h);
        for sweep in 0..iterations {
            let mut worst: f64 = 0.0;
            for (k, c) in list.iter().enumerate() {
                let r = match *c {
                    Constraint::Distance { i, j, length, compliance } if rigid(compliance, mode) => {
                        self.shake(x, dim, i, j, length)
                    }
                    Constraint::Distance { i, j, length, compliance } => {
                        self.xpbd(x, dim, i, j, length, compliance * inv_h2, k)
                    }
                    Constraint::Limit { i, j, min, max } => {
                        let r = sep(x, dim, i, j);
                        let len = dot(&r, &r).sqrt();
                        if len > max {
                            self.xpbd(x, dim, i, j, max, 0.0, k)
                        } else if len < min && len > 0.0 {
                            self.xpbd(x, dim, i, j, min, 0.0, k)
                        } else {
                            0.0
                        }
                    }
                    Constraint::Pin { .. } => 0.0,
                    Constraint::Plane { normal, offset } => self.plane(x, dim, &normal, offset),
                };
                worst = worst.max(r);
            }
            self.last_worst = worst;
            if worst <= TOLERANCE {
                return sweep + 1;
            }
        }
        iterations
    }

    /// One XPBD update of `|x_i - x_j| = length` with `alpha = compliance / h^2` (0: rigid,
    /// plain PBD): `dl = (-C - alpha l) / (w_i + w_j + alpha)`, `x_i += w_i dl n`,
    /// `x_j -= w_j dl n` (Macklin, Muller, Chentanez 2016, eq. 18). Returns the correction
    /// relative to `length`.
    #[allow(clippy::too_many_arguments)]
    fn xpbd(
        &mut self,
        x: &mut [f64],
        dim: usize,
        i: usize,
        j: Endpoint,
        length: f64,
        alpha: f64,
        k: usize,
    ) -> f64 {
        let wsum = self.w[i] + self.w_of(j);
        let d = sep(x, dim, i, j);
        let r = dot(&d, &d).sqrt();
        if wsum == 0.0 || r == 0.0 {
            return 0.0;
        }
        let c = r - length;
        let dl = (-c - alpha * self.lambda[k]) / (wsum + alpha);
        self.lambda[k] += dl;
        self.apply(x, dim, i, j, dl / r, &d);
        (dl * wsum).abs() / length
    }

    /// One SHAKE update of `|x_i - x_j|^2 = L^2` along the gradient at the start positions
    /// `r0 = x_i(t) - x_j(t)`: with `d` the current separation and `C = d.d - L^2`,
    /// `mu = -C / (2 (w_i + w_j) d.r0)`, `x_i += w_i mu r0`, `x_j -= w_j mu r0` (one Newton
    /// step on the multiplier). Returns the relative length error before the update.
    fn shake(&mut self, x: &mut [f64], dim: usize, i: usize, j: Endpoint, length: f64) -> f64 {
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

    /// Pushes every movable particle behind the plane `normal . x >= offset` onto it;
    /// returns the deepest penetration relative to `1 + |offset|`.
    fn plane(&self, x: &mut [f64], dim: usize, normal: &[f64; 3], offset: f64) -> f64 {
        let mut worst: f64 = 0.0;
        for (p, w) in self.w.iter().enumerate() {
            if *w == 0.0 {
                continue;
            }
            let xp = &mut x[p * dim..(p + 1) * dim];
            let s = xp.iter().zip(normal).map(|(a, b)| a * b).sum::<f64>() - offset;
            if s < 0.0 {
                xp.iter_mut().zip(normal).for_each(|(a, n)| *a -= s * n);
                worst = worst.max(-s / (1.0 + offset.abs()));
            }
        }
        worst
    }

    /// `v += (x - moved) / h`: the velocity the relaxation's position change implies.
    pub fn implied(&self, x: &[f64], v: &mut [f64], inv_h: f64) {
        for ((vi, xi), mi) in v.iter_mut().zip(x).zip(&self.moved) {
            *vi += (xi - mi) * inv_h;
        }
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
