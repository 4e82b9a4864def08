//! The Gauss-Seidel passes four pairs at a time (Box2D v3's wide contact solve, in f64
//! lanes): the pairs of one colour share no solid that moves (`passes::colour`), so four of
//! them are solved side by side, a lane each, with each lane's arithmetic exactly
//! [`super::passes`]' `solve_pair` of that pair, operation for operation. A pass over the
//! quads therefore gives bitwise what the one-pair-at-a-time pass gives in the coloured
//! order; the vector code (AVX2 where the CPU has it: four lanes in one register) only does
//! it in fewer instructions. This file holds the lanes' arithmetic (`F4`, `M4`), what the
//! plane's and space's quads share (`Pairs`, `chunks`, `normal`, `arrival`) and the entry
//! points the solver calls, which take the plane's to `plane.rs` and space's to `space.rs`.
//! `crate::simd::set_vector_paths(false)` takes the one-pair path instead
//! (tests/it/vector_paths.rs holds the two to the same bits on every scene with solids).
//!
//! The points are packed into the quads once a step, after their effective masses
//! (`pack`); the warm start and the passes read and write the quads' impulses and the
//! solids' motions, each substep's impulses are added to the quads' totals (`accumulate`),
//! and impulses and totals go back to the points and contacts after the substeps (`unpack`),
//! where restitution and the step's end read them.

// A lane loop indexes the lanes of several arrays alike.
#![allow(clippy::needless_range_loop)]

mod plane;
mod space;

pub(super) use plane::Quad;
pub(super) use space::{Quad as Quad3, Slot as Slot3};

use super::points::{Coefs, Contact, Pair, Point, State};
use super::space::{Plane, Space, Space3};
use glam::{DVec2, DVec3};
use std::any::Any;

/// Lanes in a quad.
pub(super) const W: usize = 4;
/// An empty lane's pair.
pub(super) const NONE: u32 = u32::MAX;

/// Four doubles, one a lane: each operation is the scalar one lane by lane (the compiler
/// makes one vector instruction of it), so a lane's result is the scalar code's, bitwise.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(align(32))]
pub(super) struct F4(pub(super) [f64; W]);

/// Four lanes' yes or no: all bits set or none.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(align(32))]
pub(super) struct M4(pub(super) [u64; W]);

macro_rules! lanewise {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl std::ops::$tr for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                let mut r = [0.0; W];
                for l in 0..W {
                    r[l] = self.0[l] $op o.0[l];
                }
                F4(r)
            }
        }
    )*};
}
lanewise!(Add add +, Sub sub -, Mul mul *, Div div /);

impl std::ops::Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        self.map(|x| -x)
    }
}

macro_rules! maskwise {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl std::ops::$tr for M4 {
            type Output = M4;
            #[inline(always)]
            fn $f(self, o: M4) -> M4 {
                let mut r = [0; W];
                for l in 0..W {
                    r[l] = self.0[l] $op o.0[l];
                }
                M4(r)
            }
        }
    )*};
}
maskwise!(BitAnd bitand &, BitOr bitor |);

impl M4 {
    /// Whether some lane says yes.
    #[inline(always)]
    pub(super) fn any(self) -> bool {
        (self.0[0] | self.0[1] | self.0[2] | self.0[3]) != 0
    }
    /// Whether every lane says yes.
    #[inline(always)]
    pub(super) fn all(self) -> bool {
        (self.0[0] & self.0[1] & self.0[2] & self.0[3]) != 0
    }
}

impl F4 {
    #[inline(always)]
    pub(super) fn splat(x: f64) -> F4 {
        F4([x; W])
    }
    #[inline(always)]
    pub(super) fn map(self, f: impl Fn(f64) -> f64) -> F4 {
        let mut r = [0.0; W];
        for l in 0..W {
            r[l] = f(self.0[l]);
        }
        F4(r)
    }
    #[inline(always)]
    pub(super) fn zip(self, o: F4, f: impl Fn(f64, f64) -> f64) -> F4 {
        let mut r = [0.0; W];
        for l in 0..W {
            r[l] = f(self.0[l], o.0[l]);
        }
        F4(r)
    }
    #[inline(always)]
    pub(super) fn test(self, o: F4, f: impl Fn(f64, f64) -> bool) -> M4 {
        let mut r = [0; W];
        for l in 0..W {
            r[l] = if f(self.0[l], o.0[l]) { u64::MAX } else { 0 };
        }
        M4(r)
    }
    #[inline(always)]
    pub(super) fn gt(self, o: F4) -> M4 {
        self.test(o, |a, b| a > b)
    }
    #[inline(always)]
    pub(super) fn lt(self, o: F4) -> M4 {
        self.test(o, |a, b| a < b)
    }
    #[inline(always)]
    pub(super) fn ne(self, o: F4) -> M4 {
        self.test(o, |a, b| a != b)
    }
    /// `f64::max` lane by lane.
    #[inline(always)]
    pub(super) fn max(self, o: F4) -> F4 {
        self.zip(o, f64::max)
    }
    /// `f64::min` lane by lane.
    #[inline(always)]
    pub(super) fn min(self, o: F4) -> F4 {
        self.zip(o, f64::min)
    }
    /// `f64::clamp` lane by lane (`lo <= hi`).
    #[inline(always)]
    pub(super) fn clamp(self, lo: F4, hi: F4) -> F4 {
        let x = pick(self.lt(lo), lo, self);
        pick(x.gt(hi), hi, x)
    }
}

/// Lane by lane, `a` where `m`, else `b`.
#[inline(always)]
pub(super) fn pick(m: M4, a: F4, b: F4) -> F4 {
    let mut r = [0.0; W];
    for l in 0..W {
        r[l] = f64::from_bits((a.0[l].to_bits() & m.0[l]) | (b.0[l].to_bits() & !m.0[l]));
    }
    F4(r)
}

/// Four pairs side by side (in the plane and in space): which, their solids, and their
/// coefficients.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Pairs {
    /// Each lane's pair (an index into `touching`), [`NONE`] for an empty lane.
    pub(super) pair: [u32; W],
    pub(super) a: [u32; W],
    pub(super) b: [u32; W],
    pub(super) bias: F4,
    pub(super) mass_scale: F4,
    pub(super) impulse_scale: F4,
    pub(super) friction_bias: F4,
    pub(super) friction: F4,
    pub(super) restitution: F4,
}

impl Pairs {
    /// Four empty lanes.
    pub(super) fn empty() -> Pairs {
        Pairs { pair: [NONE; W], ..Pairs::default() }
    }

    /// Lane `l` is pair `k`.
    pub(super) fn set(&mut self, l: usize, k: u32, pair: &Pair) {
        let c: Coefs = pair.soft;
        self.pair[l] = k;
        (self.a[l], self.b[l]) = (pair.a, pair.b);
        (self.bias.0[l], self.mass_scale.0[l], self.impulse_scale.0[l], self.friction_bias.0[l]) =
            (c.bias, c.mass_scale, c.impulse_scale, c.friction_bias);
        (self.friction.0[l], self.restitution.0[l]) = (pair.friction, pair.restitution);
    }
}

/// The coloured pairs (`coloured`, each colour ending at its `ends`) four at a time, a colour's
/// pairs never with another's; the last colour's one at a time where its pairs share solids
/// (`colour` ran out of colours).
pub(super) fn chunks<'a>(
    coloured: &'a [u32],
    ends: &'a [u32],
    shared_last: bool,
) -> impl Iterator<Item = &'a [u32]> + 'a {
    ends.iter().enumerate().flat_map(move |(c, &end)| {
        let begin = if c == 0 { 0 } else { ends[c - 1] as usize };
        let lanes = if shared_last && c + 1 == ends.len() { 1 } else { W };
        coloured[begin..end as usize].chunks(lanes)
    })
}

/// The plane's state, where `st` is the plane's.
fn plane<S: Space>(st: &mut State<S>) -> Option<&mut State<Plane>> {
    (st as &mut dyn Any).downcast_mut::<State<Plane>>()
}

/// Space's state, where `st` is space's.
fn space<S: Space>(st: &mut State<S>) -> Option<&mut State<Space3>> {
    (st as &mut dyn Any).downcast_mut::<State<Space3>>()
}

/// Packs the points into quads in the coloured order (`st.coloured`, `st.colour_ends`) when
/// the vector paths are allowed (and in the plane, where no pair has more than two points);
/// sets `st.lanes` to whether it did.
pub(super) fn pack<S: Space>(st: &mut State<S>) {
    st.lanes = false;
    if !crate::simd::enabled() {
        return;
    }
    if let Some(st) = space(st) {
        space::pack(st);
        st.lanes = true;
    } else if let Some(st) = plane(st) {
        st.lanes = plane::pack(st);
    }
}

/// Adds each point's impulses of the substep to its contact's totals, as the solver's step
/// does for the points (`total_normal += normal_impulse`, `total_friction +=
/// friction_size(tangent_impulse)`), if the points are packed: true if it did.
pub(super) fn accumulate<S: Space>(st: &mut State<S>) -> bool {
    if !st.lanes {
        return false;
    }
    if let Some(st) = space(st) {
        space::accumulate(st);
    } else if let Some(st) = plane(st) {
        plane::accumulate(st);
    }
    true
}

/// Writes the quads' impulses and totals back to the points and contacts (after the
/// substeps), if the points are packed.
pub(super) fn unpack<S: Space>(st: &mut State<S>) {
    if !st.lanes {
        return;
    }
    if let Some(st) = space(st) {
        space::unpack(st);
    } else if let Some(st) = plane(st) {
        plane::unpack(st);
    }
}

/// One Gauss-Seidel pass over the quads, if the points are packed (`pack`): true if it ran.
pub(super) fn pass<S: Space, const BIAS: bool>(
    st: &mut State<S>,
    inv_h: f64,
    push_speed: f64,
    gravity: S::V,
) -> bool {
    if !st.lanes {
        return false;
    }
    let g: &dyn Any = &gravity;
    if let (Some(st), Some(&g)) = (space(st), g.downcast_ref::<DVec3>()) {
        space::pass::<BIAS>(st, inv_h, push_speed, g);
    } else if let (Some(st), Some(&g)) = (plane(st), g.downcast_ref::<DVec2>()) {
        plane::pass::<BIAS>(st, inv_h, push_speed, g);
    }
    true
}

/// The accumulated impulses applied again, four pairs at a time, if the points are packed
/// (`pack`): true if it ran.
pub(super) fn warm_start<S: Space>(st: &mut State<S>) -> bool {
    if !st.lanes {
        return false;
    }
    if let Some(st) = space(st) {
        space::warm_start(st);
    } else if let Some(st) = plane(st) {
        plane::warm_start(st);
    }
    true
}

/// What the plane's and space's point slots share: a point's normal row in four lanes (which
/// lanes hold a point, its separation's offset and effective mass, its impulses and the
/// step's totals).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Row {
    pub(super) active: M4,
    pub(super) adjusted: F4,
    pub(super) normal_mass: F4,
    pub(super) normal_impulse: F4,
    pub(super) max_normal: F4,
    pub(super) approach: F4,
    /// The step's sums of the substeps' impulses (the contact's report).
    pub(super) total_normal: F4,
    pub(super) total_friction: F4,
}

impl Row {
    /// Lane `l` holds point `p` (its report `c`).
    pub(super) fn set<S: Space>(&mut self, l: usize, p: &Point<S>, c: &Contact<S>) {
        self.active.0[l] = u64::MAX;
        (self.adjusted.0[l], self.normal_mass.0[l]) = (p.adjusted, p.normal_mass);
        (self.normal_impulse.0[l], self.max_normal.0[l], self.approach.0[l]) =
            (p.normal_impulse, p.max_normal, p.approach);
        (self.total_normal.0[l], self.total_friction.0[l]) = (c.total_normal, c.total_friction);
    }

    /// Lane `l`'s impulses and totals written back to its point and report.
    pub(super) fn put<S: Space>(&self, l: usize, p: &mut Point<S>, c: &mut Contact<S>) {
        (p.normal_impulse, p.max_normal, p.approach) =
            (self.normal_impulse.0[l], self.max_normal.0[l], self.approach.0[l]);
        (c.total_normal, c.total_friction) = (self.total_normal.0[l], self.total_friction.0[l]);
    }

    /// The substep's impulses added to the totals (`friction`: the friction impulse's size).
    #[inline(always)]
    pub(super) fn accumulate(&mut self, friction: F4) {
        self.total_normal = pick(self.active, self.total_normal + self.normal_impulse, self.total_normal);
        self.total_friction = pick(self.active, self.total_friction + friction, self.total_friction);
    }

    /// The point's normal impulse, as `solve_pair`: apart (`sep > 0`), the bias that closes the
    /// gap in this substep and no more; else, in a solve pass (`BIAS`), the soft push (at most
    /// the push speed, `-pull`); the accumulated impulse kept at zero or more, and the largest
    /// increment. Returns the increment (applied where `active`).
    #[inline(always)]
    pub(super) fn solve<const BIAS: bool>(
        &mut self,
        p: &Pairs,
        sep: F4,
        vn: F4,
        (inv_h, pull): (F4, F4),
    ) -> F4 {
        let (zero, one) = (F4::splat(0.0), F4::splat(1.0));
        let apart = sep.gt(zero);
        let (vbias, mass_scale, impulse_scale) = if BIAS {
            (
                pick(apart, sep * inv_h, (p.bias * sep).max(pull)),
                pick(apart, one, p.mass_scale),
                pick(apart, zero, p.impulse_scale),
            )
        } else {
            (pick(apart, sep * inv_h, zero), one, zero)
        };
        let ni = self.normal_impulse;
        let imp = -self.normal_mass * (mass_scale * vn + vbias) - impulse_scale * ni;
        let new = (ni + imp).max(zero);
        let imp = new - ni;
        self.normal_impulse = pick(self.active, new, ni);
        self.max_normal = pick(self.active, self.max_normal.max(imp), self.max_normal);
        imp
    }
}

/// [`super::passes`]' `arrival`, lane by lane, without early returns (the same values).
#[inline(always)]
pub(super) fn arrival(vn: F4, sep: F4, closing: F4, h: F4) -> F4 {
    let (zero, half, two) = (F4::splat(0.0), F4::splat(0.5), F4::splat(2.0));
    let c = -vn - half * closing * h;
    let r = c * c + two * closing * sep;
    let arrived = -(half * closing * h + r.map(f64::sqrt));
    pick(sep.gt(zero) & vn.lt(zero) & c.gt(zero) & r.gt(zero), arrived, vn)
}
