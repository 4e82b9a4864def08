//! Element-wise kernels: where every force is uniform gravity and linear drag, a particle's
//! acceleration component `a_j` depends on its own velocity component `v_j` alone, so a
//! method's step is its recipe on one number pair `(x_j, v_j)` at a time, an
//! [`Element`]: the method file's own recipe, written once generic over the storage it runs
//! on ([`Method::element_step`]), not a copy of it. It runs over chunks of particles whose
//! inverse masses and gravity are laid out per element, all the steps of a run while a chunk
//! sits in L1, and the compiler turns the loop over elements into vector code.
//!
//! `tests/it/kernels.rs` checks every method with an element form against the staged step
//! bitwise; the acceleration is [`Local`](crate::forces::local::Local)'s per-particle
//! function in its element-wise case.

use super::tiles::Run;
use crate::dynamics::Element;
use crate::integrators::Method;
use crate::limits::runaway as bad;

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

/// The evaluations a step of `method` takes on elements, or `None` when it has no
/// element-wise form ([`Method::element_step`]): counted on a step of a probe element.
pub(super) fn evals<M: Method>(method: &M, velocity: bool) -> Option<u64> {
    let mut e = Element::at(0.0, 1.0, [0.0, 0.0], velocity, |_, _| 0.0);
    method.element_step(&mut e).then_some(e.evals)
}

/// Whether a step of `method` reads no evaluation but the one at its start: its new state is
/// the same bits whatever the evaluations inside the step return (probed on an element, under
/// forces that do and do not read the velocity). Explicit and symplectic Euler; not velocity
/// Verlet (its closing kick reads the end), RK4 or the position-first Euler. Such a method
/// steps particles under any forces from the stored derivative ([`given`]).
pub(super) fn start_only<M: Method>(method: &M) -> bool {
    [false, true].into_iter().all(|velocity| {
        let step = |inside: f64| {
            let mut e = Element::new(0.0, 0.5, [0.3, -0.7], [-0.7, 1.9], velocity, move |_, _| inside);
            method.element_step(&mut e).then_some(e.y.map(f64::to_bits))
        };
        matches!((step(0.0), step(1e3)), (Some(a), Some(b)) if a == b)
    })
}

/// One step of particles (positions `x`, velocities `v`, flat) by `method`'s element-wise
/// form from the accelerations `a` at the start (the stored derivative, of any forces; for a
/// [`start_only`] method), the state at the start kept in `sx`, `sv` as it is read. Whether
/// every new value is within the runaway limit.
#[inline(always)]
pub(super) fn given<M: Method>(
    method: &M,
    h: f64,
    (x, v): (&mut [f64], &mut [f64]),
    a: &[f64],
    (sx, sv): (&mut [f64], &mut [f64]),
) -> bool {
    let mut flag = false;
    let saved = sx.iter_mut().zip(sv.iter_mut());
    let new = x.iter_mut().zip(v.iter_mut()).zip(a);
    for (((x, v), &a), (sx, sv)) in new.zip(saved) {
        (*sx, *sv) = (*x, *v);
        // (The evaluation at the end is the world's own, of all its forces: not this one.)
        let mut e = Element::new(0.0, h, [*x, *v], [*v, a], false, |_, _| 0.0);
        method.element_step(&mut e);
        [*x, *v] = e.y;
        flag |= bad(e.y[0]) | bad(e.y[1]);
    }
    !flag
}

/// Whether a step of `method` evaluates the forces once without being [`start_only`]: under
/// forces that do not read the velocity, its new state is a function of its start, the
/// derivative there and that one evaluation, made at a point that is a function of the start
/// alone (it is made before any evaluation is known). Velocity Verlet. Such a method steps
/// particles under any velocity-independent forces in two passes from the stored derivative:
/// [`given_point`], the forces evaluated at that point, [`given_end`].
pub(super) fn one_eval<M: Method>(method: &M) -> bool {
    evals(method, false) == Some(1) && !start_only(method)
}

/// Where a [`one_eval`] method evaluates the forces, element by element from its start (`x`,
/// `v`, the stored accelerations `a`; forces that do not read the velocity), written over `x`
/// and `v`; the start kept in `sx`, `sv` as it is read.
#[inline(always)]
pub(super) fn given_point<M: Method>(
    method: &M,
    h: f64,
    (x, v): (&mut [f64], &mut [f64]),
    a: &[f64],
    (sx, sv): (&mut [f64], &mut [f64]),
) {
    let saved = sx.iter_mut().zip(sv.iter_mut());
    for (((x, v), &a), (sx, sv)) in x.iter_mut().zip(v.iter_mut()).zip(a).zip(saved) {
        (*sx, *sv) = (*x, *v);
        let at = std::cell::Cell::new([*x, *v]);
        let mut e = Element::new(0.0, h, [*x, *v], [*v, a], false, |xe, ve| {
            at.set([xe, ve]);
            0.0
        });
        method.element_step(&mut e);
        [*x, *v] = at.get();
    }
}

/// The end of a [`one_eval`] method's step, element by element from the start kept in `sx`,
/// `sv` and its stored accelerations `a`, given the accelerations `a_end` evaluated where
/// [`given_point`] put the state: the new state written to `x`, `v`. Whether every new value
/// is within the runaway limit.
#[inline(always)]
pub(super) fn given_end<M: Method>(
    method: &M,
    h: f64,
    (x, v): (&mut [f64], &mut [f64]),
    (a, a_end): (&[f64], &[f64]),
    (sx, sv): (&[f64], &[f64]),
) -> bool {
    let mut flag = false;
    let start = sx.iter().zip(sv).zip(a.iter().zip(a_end));
    for ((x, v), ((&sx, &sv), (&a, &a_end))) in x.iter_mut().zip(v.iter_mut()).zip(start) {
        let mut e = Element::new(0.0, h, [sx, sv], [sv, a], false, |_, _| a_end);
        method.element_step(&mut e);
        [*x, *v] = e.y;
        flag |= bad(e.y[0]) | bad(e.y[1]);
    }
    !flag
}

/// Particles per chunk: a chunk's positions, velocities, inverse masses and gravity per
/// element (`4 * CHUNK * dim` values) stay in L1 for all the steps of a run.
const CHUNK: usize = 64;

/// The inverse masses of a run's particles: one a particle, or, where every particle has the
/// same, that one number (the kernel then reads no array for them).
#[derive(Debug, Clone, Copy)]
pub(super) enum Masses<'a> {
    Each(&'a [f64]),
    /// The inverse mass of each of `n` particles.
    All(f64, usize),
}

impl<'a> Masses<'a> {
    /// How many particles.
    pub(super) fn len(self) -> usize {
        match self {
            Self::Each(w) => w.len(),
            Self::All(_, n) => n,
        }
    }

    /// Those of particles `a..b`.
    pub(super) fn range(self, a: usize, b: usize) -> Self {
        match self {
            Self::Each(w) => Self::Each(&w[a..b]),
            Self::All(w, _) => Self::All(w, b - a),
        }
    }
}

/// `run.n` steps of `run.h` of particles (positions `x`, velocities `v`, flat, `D` per
/// particle) by `method`'s element-wise form, chunk by chunk, the state at the start kept in
/// `sx`, `sv` when `run.save`; returns the first step at which a new value or acceleration
/// ran away (or `run.n`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn run<const D: usize, M: Method>(
    method: &M,
    k: Flat,
    velocity: bool,
    run: Run,
    masses: Masses<'_>,
    (x, v): (&mut [f64], &mut [f64]),
    (sx, sv): (&mut [f64], &mut [f64]),
) -> u64 {
    let (h, mut good) = (run.h, run.n);
    let c = CHUNK * D;
    let chunks = x.chunks_mut(c).zip(v.chunks_mut(c)).zip(sx.chunks_mut(c).zip(sv.chunks_mut(c)));
    // Inverse mass and gravity per element (gravity 0 on a static particle): set per chunk,
    // or once where every particle has the same inverse mass.
    let (mut im, mut gm) = ([0.0; CHUNK * 3], [0.0; CHUNK * 3]);
    let all_bounded = match masses {
        Masses::All(w, _) => fill::<D>(k, &[w; CHUNK], &mut im, &mut gm),
        Masses::Each(_) => false,
    };
    for (q, ((xc, vc), (sxc, svc))) in chunks.enumerate() {
        if run.save {
            sxc.copy_from_slice(xc);
            svc.copy_from_slice(vc);
        }
        let bounded = match masses {
            Masses::All(..) => all_bounded,
            Masses::Each(w) => fill::<D>(k, &w[q * CHUNK..q * CHUNK + xc.len() / D], &mut im, &mut gm),
        };
        let m = xc.len();
        let (im, gm) = (&im[..m], &gm[..m]);
        let steps = if bounded {
            chunk::<M, false>(method, k, velocity, h, good, (xc, vc), im, gm)
        } else {
            chunk::<M, true>(method, k, velocity, h, good, (xc, vc), im, gm)
        };
        good = good.min(steps);
    }
    good
}

/// Sets the inverse mass and gravity per element (gravity 0 on a static particle) of the
/// particles whose inverse masses are `ws`; whether the acceleration is bounded on them:
/// where |s / m| <= 1/2 and |g| <= 1e90, |a| <= |v| / 2 + 1e90 stays finite and within the
/// runaway limit whenever v does, so the acceleration at the new state cannot fail the check,
/// and a recipe that computes it only for the check (explicit or symplectic Euler, RK4: their
/// last evaluation) does not compute it.
#[inline(always)]
fn fill<const D: usize>(k: Flat, ws: &[f64], im: &mut [f64], gm: &mut [f64]) -> bool {
    let g = |w: f64, c: usize| if w > 0.0 { k.g[c] } else { 0.0 };
    // Four particles at a time, each writing `4 * D` elements of fixed place: the compiler
    // turns the spreading into shuffles of whole vectors.
    let quads = ws.len() / 4;
    // The largest inverse mass: one running maximum a lane of the quads, one for the rest.
    let (mut hi, mut rest) = ([0.0f64; 4], 0.0f64);
    for ((w, im), gm) in ws.chunks_exact(4).zip(im.chunks_exact_mut(4 * D)).zip(gm.chunks_exact_mut(4 * D)) {
        for p in 0..4 {
            for c in 0..D {
                im[p * D + c] = w[p];
                gm[p * D + c] = g(w[p], c);
            }
            hi[p] = if w[p] > hi[p] { w[p] } else { hi[p] };
        }
    }
    for (p, &w) in ws.iter().enumerate().skip(4 * quads) {
        for c in 0..D {
            im[p * D + c] = w;
            gm[p * D + c] = g(w, c);
        }
        rest = if w > rest { w } else { rest };
    }
    let w_max = hi.iter().fold(rest, |a, &w| if w > a { w } else { a });
    k.s.abs() * w_max <= 0.5 && k.g.iter().all(|g| g.abs() <= 1e90)
}

/// Up to `n` steps of one chunk's elements; the first step that ran away (or `n`). With `A`
/// the acceleration at the new state is checked too.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn chunk<M: Method, const A: bool>(
    method: &M,
    k: Flat,
    velocity: bool,
    h: f64,
    n: u64,
    (xc, vc): (&mut [f64], &mut [f64]),
    im: &[f64],
    gm: &[f64],
) -> u64 {
    let m = xc.len();
    let (xc, vc, im, gm) = (&mut xc[..m], &mut vc[..m], &im[..m], &gm[..m]);
    // Element `j`'s step; whether a new value (or, with `A`, the new acceleration) ran away.
    // The acceleration at the start is evaluated again, not kept from the last step: the same
    // bits, and one array less to carry.
    let mut one = |j: usize| {
        let (im, g) = (im[j], gm[j]);
        let mut e = Element::at(0.0, h, [xc[j], vc[j]], velocity, |_, v| k.acc(v, im, g));
        method.element_step(&mut e);
        [xc[j], vc[j]] = e.y;
        u64::from(bad(xc[j]) | bad(vc[j]) | (A && bad(e.f[1])))
    };
    // A loop over a multiple of 8 elements, then the rest: the compiler then runs the first in
    // whole vectors to its end (over all `m` it kept the last 8 for an element-at-a-time tail
    // in every pass, ~5% of a chunk-resident step).
    let whole = m & !7;
    for s in 0..n {
        let mut flag = 0u64;
        for j in 0..whole {
            flag |= one(j);
        }
        for j in whole..m {
            flag |= one(j);
        }
        if flag != 0 {
            return s;
        }
    }
    n
}

#[cfg(test)]
mod tests {
    use super::evals;
    use crate::dynamics::{Element, Second, SecondOrder, Step};
    use crate::integrators::registry::Visit;
    use crate::integrators::{Integrator, Method, INFOS};

    /// One coordinate under `a = acc(x, v)`, as a system the staged step runs on.
    struct One<A>(A, bool);

    impl<A: Fn(f64, f64) -> f64> SecondOrder for One<A> {
        fn len(&self) -> usize {
            1
        }
        fn accel(&mut self, _t: f64, x: &[f64], v: &[f64], a: &mut [f64]) {
            a[0] = (self.0)(x[0], v[0]);
        }
        fn velocity_dependent(&self) -> bool {
            self.1
        }
    }

    /// A method's steps on an element and the staged steps on the same one-coordinate system
    /// (a spring, with drag when `velocity`): the same bits and evaluations, step after step.
    /// The evaluations of a step, or `None` when the method has no element-wise form.
    struct Agree {
        velocity: bool,
    }

    impl Visit for Agree {
        type Out = Option<u64>;

        fn visit<M: Method + Clone + Send + Sync>(self, m: &mut M) -> Option<u64> {
            let velocity = self.velocity;
            let c = if velocity { 0.7 } else { 0.0 };
            let acc = |x: f64, v: f64| (0.0 + -c * v + (-3.0 * (x - 0.25) - 0.2 * c * v)) * 0.8 - 9.81;
            let per_step = evals(m, velocity)?;
            let mut y = [1.3, -0.4];
            let mut f = [y[1], acc(y[0], y[1])];
            let mut one = One(acc, velocity);
            let mut sys = Second(&mut one);
            for k in 0..60 {
                let h = [0.01, 0.1, 0.37][k % 3];
                let mut e = Element::new(0.0, h, y, f, velocity, acc);
                assert!(m.element_step(&mut e));
                let mut n = 0;
                m.step(&mut Step::new(&mut sys, 0.0, h, &mut y, &mut f, &mut n, None)).unwrap();
                let what = format!("{} (velocity {velocity}), step {k}", M::INFO.name);
                assert_eq!(e.y.map(f64::to_bits), y.map(f64::to_bits), "{what}: y");
                assert_eq!(e.f.map(f64::to_bits), f.map(f64::to_bits), "{what}: f");
                assert_eq!((e.evals, n), (per_step, per_step), "{what}: evaluations");
            }
            Some(per_step)
        }
    }

    /// The methods for which [`super::one_eval`] (`once`) or [`super::start_only`] says yes.
    fn methods_where(once: bool) -> Vec<&'static str> {
        struct Probe(bool);
        impl Visit for Probe {
            type Out = bool;
            fn visit<M: Method + Clone + Send + Sync>(self, m: &mut M) -> bool {
                if self.0 {
                    super::one_eval(m)
                } else {
                    super::start_only(m)
                }
            }
        }
        INFOS
            .iter()
            .filter(|info| Integrator::new(info.name).unwrap().visit(Probe(once)))
            .map(|info| info.name)
            .collect()
    }

    #[test]
    fn the_methods_whose_step_reads_only_its_start_are_the_two_eulers() {
        assert_eq!(methods_where(false), ["explicit-euler", "symplectic-euler"]);
    }

    #[test]
    fn the_methods_that_evaluate_once_at_a_point_of_their_own_are_velocity_verlet() {
        assert_eq!(methods_where(true), ["velocity-verlet"]);
    }

    #[test]
    fn an_element_steps_bitwise_as_the_staged_step() {
        let mut forms = Vec::new();
        for info in &INFOS {
            let mut m = Integrator::new(info.name).unwrap();
            let still = m.visit(Agree { velocity: false });
            let moving = m.visit(Agree { velocity: true });
            assert_eq!(still.is_some(), moving.is_some(), "{}", info.name);
            if let Some(e) = still {
                // The kernels run element-wise forms on any part of the particles at a time.
                assert!(m.fresh_local().is_some(), "{}: an element-wise form but not local", info.name);
                assert_eq!(e, u64::from(info.evals), "{}: evaluations as INFO gives them", info.name);
                forms.push(info.name);
            }
        }
        // The fast paths the README's performance table measures.
        for name in ["explicit-euler", "symplectic-euler", "velocity-verlet", "rk4"] {
            assert!(forms.contains(&name), "{name} lost its element-wise form");
        }
    }
}
