//! The small-world kernel: a recording of every step of a world of a few particles (at most
//! [`OBSERVED_MAX`]) whose every acceleration component is a function of its own coordinate
//! and velocity component (gravity, linear drag, springs of zero rest length to anchors, see
//! [`Local::element_springs`]), stepped by a method with an element-wise form. As in
//! [`super::flat`], a step is the method file's own recipe run on one number pair
//! `(x_j, v_j)` at a time ([`Method::element_step`]), and the acceleration is [`Local`]'s
//! per-particle function in its element-wise case (`tests/it/kernels.rs` checks both against
//! the staged step bitwise); a step costs little more than its arithmetic.
//!
//! Why the element-wise acceleration is the per-particle one bit for bit: that function sums
//! the force from `+0` (`+0 + s v` with drag, `s = 0` without: `+0 + 0 v` is `+0` for a
//! finite `v`), adds its one spring's `-k d - c v` (an element without one adds `+0`, chosen
//! rather than computed, to a sum that is never `-0`: the same sum at any position, a stage's
//! included), multiplies by `1/m` (a sum of `+0` times `1/m` is the `+0` the function starts
//! from when no force acts) and adds gravity (`0` on a static particle). A non-finite
//! velocity, at the new state or at a stage, fails the step either way (a stage's velocity
//! is part of the new position: RK4's weighted sum, velocity Verlet's drift).

use super::flat;
use super::tiles::{Run, OBSERVED_MAX};
use crate::dynamics::Element;
use crate::forces::local::Local;
use crate::integrators::Method;
use crate::limits::runaway as bad;

/// Most elements (coordinates) a small world has.
const CAP: usize = OBSERVED_MAX * 3;

/// The forces on one element: inverse mass, gravity (0 on a static particle), whether a
/// spring acts, and the spring's stiffness, damping and anchor (0 without one).
#[derive(Debug, Clone, Copy, Default)]
struct Param {
    im: f64,
    g: f64,
    spring: bool,
    k: f64,
    c: f64,
    at: f64,
}

/// The forces on each element of a small world.
pub(super) struct Elements {
    /// Elements: particles times dimensions.
    len: usize,
    /// The drag factor `-(c1 + c2 * 0)`, or 0 without drag.
    s: f64,
    /// Per element.
    p: [Param; CAP],
}

impl Elements {
    /// The elements of particles of inverse masses `inv_mass` in `dim` dimensions under
    /// `local`, when its forces are element-wise and the world is small.
    pub(super) fn of(local: &Local, dim: usize, inv_mass: &[f64]) -> Option<Self> {
        let (s, g, springs) = local.element_springs()?;
        if inv_mass.len() > OBSERVED_MAX {
            return None;
        }
        let mut e = Self { len: inv_mass.len() * dim, s, p: [Param::default(); CAP] };
        for (p, &w) in inv_mass.iter().enumerate() {
            for (q, gc) in e.p[p * dim..(p + 1) * dim].iter_mut().zip(g) {
                (q.im, q.g) = (w, if w > 0.0 { gc } else { 0.0 });
            }
        }
        for sp in springs {
            let [k, _, c] = sp.p;
            for (q, at) in e.p[sp.i * dim..(sp.i + 1) * dim].iter_mut().zip(sp.at) {
                (q.spring, q.k, q.c, q.at) = (true, k, c, at);
            }
        }
        Some(e)
    }

    /// The acceleration of an element with forces `p` at `x`, `v`:
    /// `(0 + s v + (-k (x - at) - c v)) / m + g`, as the per-particle function computes it.
    #[inline(always)]
    fn acc(&self, p: &Param, x: f64, v: f64) -> f64 {
        let spring = -p.k * (x - p.at) - p.c * v;
        ((0.0 + self.s * v) + if p.spring { spring } else { 0.0 }) * p.im + p.g
    }
}

/// Up to `run.n` steps of `run.h` of the state `y = [x; v]` by `method`'s element-wise form
/// (`None` when it has none), the state at the start kept in `saved` when `run.save`, `on_step(k, y, f)` called after
/// each good step `k` with the state and its derivative `[v; a]` (return `false` to stop
/// after it), as [`super::tiles::observed`] takes them; the steps taken, the evaluations a
/// step takes, and whether `on_step` stopped the run.
#[allow(clippy::too_many_arguments)]
pub(super) fn observed<M: Method>(
    method: &M,
    e: &Elements,
    velocity: bool,
    run: Run,
    y: &mut [f64],
    saved: &mut [f64],
    on_step: &mut impl FnMut(u64, &[f64], &[f64]) -> bool,
) -> Option<((u64, u64), bool)> {
    let evals = flat::evals(method, velocity)?;
    let (m, h, n) = (e.len, run.h, run.n);
    if run.save {
        saved.copy_from_slice(y);
    }
    let (mut ys, mut fs) = ([0.0; 2 * CAP], [0.0; 2 * CAP]);
    let (ys, f) = (&mut ys[..2 * m], &mut fs[..2 * m]);
    ys.copy_from_slice(y);
    for (j, p) in e.p[..m].iter().enumerate() {
        (f[j], f[m + j]) = (ys[m + j], e.acc(p, ys[j], ys[m + j]));
    }
    let (mut good, mut halted) = (n, false);
    for k in 0..n {
        let mut flag = false;
        let ((xs, vs), (dxs, acs)) = (ys.split_at_mut(m), f.split_at_mut(m));
        let rows = xs.iter_mut().zip(vs.iter_mut()).zip(dxs.iter_mut().zip(acs.iter_mut()));
        for (((x, v), (dx, a)), p) in rows.zip(&e.p[..m]) {
            let mut el = Element::new(0.0, h, [*x, *v], [*dx, *a], velocity, |x, v| e.acc(p, x, v));
            method.element_step(&mut el);
            ([*x, *v], [*dx, *a]) = (el.y, el.f);
            flag |= bad(*x) | bad(*v) | bad(*a);
        }
        if flag {
            good = k;
            break;
        }
        if !on_step(k, ys, f) {
            (good, halted) = (k + 1, true);
            break;
        }
    }
    y.copy_from_slice(ys);
    Some(((good, evals), halted))
}
