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
/// returns the acceleration at the new state (with `A`; 0 without).
#[inline(always)]
fn element<const R: u8, const A: bool>(
    k: Flat,
    velocity: bool,
    h: f64,
    x: &mut f64,
    v: &mut f64,
    im: f64,
    g: f64,
) -> f64 {
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
    // The acceleration at the new state, for the check: not needed where it is bounded by
    // the velocity's (see `run_r`).
    if A {
        acc(*v)
    } else {
        0.0
    }
}

/// Whether `x` is NaN, infinite or past [`RUNAWAY`].
#[inline(always)]
fn bad(x: f64) -> bool {
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    !(x.abs() <= RUNAWAY)
}

/// Particles per chunk: a chunk's positions, velocities, inverse masses and gravity per
/// element (`4 * CHUNK * dim` values) stay in L1 for all the steps of a run.
const CHUNK: usize = 64;

/// `n` steps of `h` of particles (positions `x`, velocities `v`, flat, `D` per particle),
/// chunk by chunk, the state at the start kept in `sx`, `sv`; returns the first step at which
/// a new value or acceleration ran away (or `n`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn run<const D: usize>(
    r: Recipe,
    k: Flat,
    velocity: bool,
    h: f64,
    n: u64,
    inv_mass: &[f64],
    xv: (&mut [f64], &mut [f64]),
    saved: (&mut [f64], &mut [f64]),
) -> u64 {
    match r {
        Recipe::ExplicitEuler => run_r::<D, EXPLICIT_EULER>(k, velocity, h, n, inv_mass, xv, saved),
        Recipe::SymplecticEuler => run_r::<D, SYMPLECTIC_EULER>(k, velocity, h, n, inv_mass, xv, saved),
        Recipe::VelocityVerlet => run_r::<D, VELOCITY_VERLET>(k, velocity, h, n, inv_mass, xv, saved),
        Recipe::Rk4 => run_r::<D, RK4>(k, velocity, h, n, inv_mass, xv, saved),
    }
}

#[inline(always)]
fn run_r<const D: usize, const R: u8>(
    k: Flat,
    velocity: bool,
    h: f64,
    n: u64,
    inv_mass: &[f64],
    (x, v): (&mut [f64], &mut [f64]),
    (sx, sv): (&mut [f64], &mut [f64]),
) -> u64 {
    let mut good = n;
    let c = CHUNK * D;
    let chunks = x.chunks_mut(c).zip(v.chunks_mut(c)).zip(sx.chunks_mut(c).zip(sv.chunks_mut(c)));
    // Inverse mass and gravity per element (gravity 0 on a static particle), set per chunk.
    let (mut im, mut gm) = ([0.0; CHUNK * 3], [0.0; CHUNK * 3]);
    for (((xc, vc), (sxc, svc)), ic) in chunks.zip(inv_mass.chunks(CHUNK)) {
        sxc.copy_from_slice(xc);
        svc.copy_from_slice(vc);
        for (p, &w) in ic.iter().enumerate() {
            for c in 0..D {
                im[p * D + c] = w;
                gm[p * D + c] = if w > 0.0 { k.g[c] } else { 0.0 };
            }
        }
        let m = xc.len();
        let (im, gm) = (&im[..m], &gm[..m]);
        // Where |s / m| <= 1/2 and |g| <= 1e90, |a| <= |v| / 2 + 1e90 stays finite and within
        // the runaway limit whenever v does: a new acceleration that explicit or symplectic
        // Euler or RK4 only computes for the check cannot fail it, and is not computed.
        let w_max = ic.iter().fold(0.0f64, |a, &w| if w > a { w } else { a });
        let bounded = k.s.abs() * w_max <= 0.5 && k.g.iter().all(|g| g.abs() <= 1e90);
        let steps = if bounded && R != VELOCITY_VERLET {
            chunk::<R, false>(k, velocity, h, good, (xc, vc), im, gm)
        } else {
            chunk::<R, true>(k, velocity, h, good, (xc, vc), im, gm)
        };
        good = good.min(steps);
    }
    good
}

/// Up to `n` steps of one chunk's elements; the first step that ran away (or `n`).
#[inline(always)]
fn chunk<const R: u8, const A: bool>(
    k: Flat,
    velocity: bool,
    h: f64,
    n: u64,
    (xc, vc): (&mut [f64], &mut [f64]),
    im: &[f64],
    gm: &[f64],
) -> u64 {
    for s in 0..n {
        let mut flag = 0u64;
        for j in 0..xc.len() {
            let a = element::<R, A>(k, velocity, h, &mut xc[j], &mut vc[j], im[j], gm[j]);
            flag |= u64::from(bad(xc[j]) | bad(vc[j]) | (A && bad(a)));
        }
        if flag != 0 {
            return s;
        }
    }
    n
}
