//! Element-wise kernels: where every force is uniform gravity and linear drag, a particle's
//! acceleration component `a_j` depends on its own velocity component `v_j` alone, so
//! explicit Euler, symplectic Euler, velocity Verlet and RK4 are recipes on one number pair
//! `(x_j, v_j)` at a time. These recipes run over blocks of four particles whose inverse
//! masses and gravity are laid out per element, which the compiler turns into vector code.
//!
//! Each recipe is the method file's recipe written for one element, operation for operation
//! (`tests/kernels.rs` checks every method against the staged step bitwise), and the
//! acceleration is [`Local`](crate::forces::local::Local)'s per-particle function in its
//! element-wise case.

use crate::integrators::registry::RUNAWAY;

/// The element-wise recipes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Recipe {
    ExplicitEuler,
    SymplecticEuler,
    VelocityVerlet,
    Rk4,
}

impl Recipe {
    /// The recipe of the method registered as `name`, if it has one.
    pub(super) fn of(name: &str) -> Option<Self> {
        Some(match name {
            "explicit-euler" => Self::ExplicitEuler,
            "symplectic-euler" => Self::SymplecticEuler,
            "velocity-verlet" => Self::VelocityVerlet,
            "rk4" => Self::Rk4,
            _ => return None,
        })
    }

    /// Evaluations a step takes, as the method file counts them.
    pub(super) fn evals(self, velocity: bool) -> u64 {
        match self {
            Self::ExplicitEuler | Self::SymplecticEuler => 1,
            Self::VelocityVerlet if velocity => 3,
            Self::VelocityVerlet => 1,
            Self::Rk4 => 4,
        }
    }
}

/// Gravity and linear drag, element by element.
#[derive(Debug, Clone, Copy)]
pub(super) struct Flat {
    /// `-(c1 + c2 * 0)`, the drag factor (`c2` is 0), or 0 without drag.
    pub s: f64,
    /// Uniform gravity, m/s^2.
    pub g: [f64; 3],
}

impl Flat {
    /// `a = (0 + s v) / m + g` (`g` is 0 on a static particle), as the per-particle function
    /// computes it.
    #[inline(always)]
    fn acc(self, v: f64, im: f64, g: f64) -> f64 {
        (0.0 + self.s * v) * im + g
    }
}

// The recipes as constants, so each is compiled on its own (no branch in the loop).
const EXPLICIT_EULER: u8 = 0;
const SYMPLECTIC_EULER: u8 = 1;
const VELOCITY_VERLET: u8 = 2;
const RK4: u8 = 3;

/// One step of `h` of the element `(x, v)` with inverse mass `im` and gravity component `g`;
/// returns the acceleration at the new state.
#[inline(always)]
fn element<const R: u8>(k: Flat, velocity: bool, h: f64, x: &mut f64, v: &mut f64, im: f64, g: f64) -> f64 {
    let acc = |v: f64| k.acc(v, im, g);
    let a0 = acc(*v);
    match R {
        EXPLICIT_EULER => {
            *x += h * *v;
            *v += h * a0;
        }
        SYMPLECTIC_EULER => {
            *v += h * a0;
            *x += h * *v;
        }
        VELOCITY_VERLET => {
            let hh = 0.5 * h;
            *v += hh * a0;
            *x += h * *v;
            let mut a = acc(*v);
            if velocity {
                let v_half = *v;
                for _ in 0..2 {
                    *v = v_half + hh * a;
                    a = acc(*v);
                }
            } else {
                *v += hh * a;
            }
            return a;
        }
        _ => {
            let (x0, v0) = (*x, *v);
            let hh = 0.5 * h;
            let va = v0 + hh * a0;
            let aa = acc(va);
            let vb = v0 + hh * aa;
            let ab = acc(vb);
            let h1 = 1.0 * h;
            let vc = v0 + h1 * ab;
            let ac = acc(vc);
            let h6 = h / 6.0;
            *x = x0 + h6 * (v0 + 2.0 * va + 2.0 * vb + vc);
            *v = v0 + h6 * (a0 + 2.0 * aa + 2.0 * ab + ac);
        }
    }
    acc(*v)
}

/// Whether `x` is NaN, infinite or past [`RUNAWAY`].
#[inline(always)]
fn bad(x: f64) -> bool {
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    !(x.abs() <= RUNAWAY)
}

/// One step of particles (positions `x`, velocities `v`, flat, `D` per particle); whether
/// any new value or acceleration ran away.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn step<const D: usize>(
    r: Recipe,
    k: Flat,
    velocity: bool,
    h: f64,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
) -> bool {
    match r {
        Recipe::ExplicitEuler => step_r::<D, EXPLICIT_EULER>(k, velocity, h, inv_mass, x, v),
        Recipe::SymplecticEuler => step_r::<D, SYMPLECTIC_EULER>(k, velocity, h, inv_mass, x, v),
        Recipe::VelocityVerlet => step_r::<D, VELOCITY_VERLET>(k, velocity, h, inv_mass, x, v),
        Recipe::Rk4 => step_r::<D, RK4>(k, velocity, h, inv_mass, x, v),
    }
}

#[inline(always)]
fn step_r<const D: usize, const R: u8>(
    k: Flat,
    velocity: bool,
    h: f64,
    inv_mass: &[f64],
    x: &mut [f64],
    v: &mut [f64],
) -> bool {
    // Blocks of four particles: 4 D elements, a whole number of vectors for every D.
    let mut g = [0.0; 12];
    for (j, gj) in g.iter_mut().enumerate().take(4 * D) {
        *gj = k.g[j % D];
    }
    // One flag per lane, folded at the end: no dependency from block to block.
    let mut lanes = [0u64; 12];
    let n = inv_mass.len() / 4 * 4;
    let (xh, xt) = x.split_at_mut(n * D);
    let (vh, vt) = v.split_at_mut(n * D);
    let uniform =
        inv_mass.first().copied().filter(|w| inv_mass[..n].iter().all(|u| u.to_bits() == w.to_bits()));
    if let Some(w) = uniform {
        // Every particle of the task has the same mass: inverse mass and gravity are the
        // same vectors for every block, and the recipe runs on the arrays in place.
        let gm = if w > 0.0 { g } else { [0.0; 12] };
        for (xb, vb) in xh.chunks_exact_mut(4 * D).zip(vh.chunks_exact_mut(4 * D)) {
            for j in 0..4 * D {
                let a = element::<R>(k, velocity, h, &mut xb[j], &mut vb[j], w, gm[j]);
                lanes[j] |= u64::from(bad(xb[j]) | bad(vb[j]) | bad(a));
            }
        }
    } else {
        let blocks = xh.chunks_exact_mut(4 * D).zip(vh.chunks_exact_mut(4 * D)).zip(inv_mass.chunks_exact(4));
        for ((xb, vb), ib) in blocks {
            let (im, gm) = expand::<D>(ib, &g);
            for j in 0..4 * D {
                let a = element::<R>(k, velocity, h, &mut xb[j], &mut vb[j], im[j], gm[j]);
                lanes[j] |= u64::from(bad(xb[j]) | bad(vb[j]) | bad(a));
            }
        }
    }
    // The last particles (fewer than four).
    let (im, gm) = expand::<D>(&inv_mass[n..], &g);
    for j in 0..xt.len() {
        let a = element::<R>(k, velocity, h, &mut xt[j], &mut vt[j], im[j], gm[j]);
        lanes[j] |= u64::from(bad(xt[j]) | bad(vt[j]) | bad(a));
    }
    lanes.iter().any(|b| *b != 0)
}

/// Inverse masses and gravity per element of up to four particles (gravity 0 on a static
/// particle).
#[inline(always)]
fn expand<const D: usize>(inv_mass: &[f64], g: &[f64; 12]) -> ([f64; 12], [f64; 12]) {
    let (mut im, mut gm) = ([0.0; 12], [0.0; 12]);
    for (p, &w) in inv_mass.iter().enumerate() {
        for c in p * D..(p + 1) * D {
            im[c] = w;
            gm[c] = if w > 0.0 { g[c] } else { 0.0 };
        }
    }
    (im, gm)
}
