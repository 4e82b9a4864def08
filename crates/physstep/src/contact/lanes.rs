//! The Gauss-Seidel passes four pairs at a time (Box2D v3's wide contact solve, in f64
//! lanes): the pairs of one colour share no solid that moves (`passes::colour`), so four of
//! them are solved side by side, a lane each, with each lane's arithmetic exactly
//! [`super::passes`]' `solve_pair` of that pair, operation for operation. A pass over the
//! quads therefore gives bitwise what the one-pair-at-a-time pass gives in the coloured
//! order; the vector code (AVX2 where the CPU has it: four lanes in one register) only does
//! it in fewer instructions. This file holds the lanes' arithmetic (`F4`, `M4`), the plane's
//! quads and the entry points, which take space's to `lanes3.rs`.
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

use super::lanes3;
use super::points::{Coefs, Pair, State};
use super::space::{Plane, Space, Space3};
use glam::DVec2;
use glam::DVec3;
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

/// One point of each of four pairs (a lane each): what the passes read and write.
#[derive(Debug, Clone, Copy, Default)]
struct Slot {
    active: M4,
    nx: F4,
    ny: F4,
    rax: F4,
    ray: F4,
    rbx: F4,
    rby: F4,
    adjusted: F4,
    normal_mass: F4,
    tangent_mass: F4,
    slip: F4,
    normal_impulse: F4,
    tangent_impulse: F4,
    /// The second tangent's impulse as the scalar pass leaves it (0, scaled by the friction
    /// clamp: kept for the bits).
    tangent_other: F4,
    max_normal: F4,
    approach: F4,
    /// The step's sums of the substeps' impulses (the contact's report).
    total_normal: F4,
    total_friction: F4,
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

/// Four pairs of one colour, side by side, with up to two points each (the plane's manifolds
/// have at most two).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Quad {
    p: Pairs,
    slots: [Slot; 2],
}

/// One side of four lanes' pairs: the solids' motions, gathered.
#[derive(Debug, Clone, Copy, Default)]
struct Side {
    vx: F4,
    vy: F4,
    w: F4,
    dpx: F4,
    dpy: F4,
    dqx: F4,
    dqy: F4,
    inv_mass: F4,
    inv_i: F4,
    moves: M4,
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
/// the vector paths are allowed and no pair has more points than a quad holds (two in the
/// plane, four in space: `lanes3.rs`); sets `st.lanes` to whether it did.
pub(super) fn pack<S: Space>(st: &mut State<S>) {
    st.lanes = false;
    if !crate::simd::enabled() {
        return;
    }
    if let Some(st) = space(st) {
        lanes3::pack(st);
        st.lanes = true;
        return;
    }
    let Some(st) = plane(st) else { return };
    if st.touching.iter().any(|p| p.end - p.start > 2) {
        return;
    }
    st.quads.clear();
    for chunk in chunks(&st.coloured, &st.colour_ends, st.shared_last) {
        let mut q = Quad { p: Pairs::empty(), ..Quad::default() };
        for (l, &k) in chunk.iter().enumerate() {
            let pair = &st.touching[k as usize];
            q.p.set(l, k, pair);
            let points = &st.points[pair.start as usize..pair.end as usize];
            for (s_index, (s, p)) in q.slots.iter_mut().zip(points).enumerate() {
                s.active.0[l] = u64::MAX;
                (s.nx.0[l], s.ny.0[l]) = (p.normal.x, p.normal.y);
                (s.rax.0[l], s.ray.0[l], s.rbx.0[l], s.rby.0[l]) = (p.ra.x, p.ra.y, p.rb.x, p.rb.y);
                s.adjusted.0[l] = p.adjusted;
                s.normal_mass.0[l] = p.normal_mass;
                s.tangent_mass.0[l] = p.tangent_mass[0];
                s.slip.0[l] = p.slip[0];
                s.normal_impulse.0[l] = p.normal_impulse;
                (s.tangent_impulse.0[l], s.tangent_other.0[l]) = (p.tangent_impulse[0], p.tangent_impulse[1]);
                s.max_normal.0[l] = p.max_normal;
                s.approach.0[l] = p.approach;
                let c = &st.contacts[pair.start as usize + s_index];
                (s.total_normal.0[l], s.total_friction.0[l]) = (c.total_normal, c.total_friction);
            }
        }
        st.quads.push(q);
    }
    st.lanes = true;
}

/// Adds each point's impulses of the substep to its contact's totals, as the solver's step
/// does for the points (`total_normal += normal_impulse`, `total_friction +=
/// Plane::friction_size(tangent_impulse)`), if the points are packed: true if it did.
pub(super) fn accumulate<S: Space>(st: &mut State<S>) -> bool {
    if !st.lanes {
        return false;
    }
    if let Some(st) = space(st) {
        lanes3::accumulate(st);
        return true;
    }
    let Some(st) = plane(st) else { return false };
    for q in &mut st.quads {
        for s in &mut q.slots {
            let (zero, tiny, huge) = (F4::splat(0.0), F4::splat(1e-150), F4::splat(1e150));
            let (t, other) = (s.tangent_impulse, s.tangent_other);
            let a = t.map(f64::abs);
            let plain =
                other.test(zero, |x, y| x == y) & (a.test(zero, |x, y| x == y) | (a.gt(tiny) & a.lt(huge)));
            let size = pick(plain, a, (t * t + other * other).map(f64::sqrt));
            s.total_normal = pick(s.active, s.total_normal + s.normal_impulse, s.total_normal);
            s.total_friction = pick(s.active, s.total_friction + size, s.total_friction);
        }
    }
    true
}

/// Writes the quads' impulses and totals back to the points and contacts (after the
/// substeps).
pub(super) fn unpack<S: Space>(st: &mut State<S>) {
    if !st.lanes {
        return;
    }
    if let Some(st) = space(st) {
        lanes3::unpack(st);
        return;
    }
    let Some(st) = plane(st) else { return };
    for q in &st.quads {
        for l in 0..W {
            if q.p.pair[l] == NONE {
                continue;
            }
            let start = st.touching[q.p.pair[l] as usize].start as usize;
            for (k, s) in q.slots.iter().enumerate() {
                if s.active.0[l] == 0 {
                    continue;
                }
                let p = &mut st.points[start + k];
                p.normal_impulse = s.normal_impulse.0[l];
                p.tangent_impulse = [s.tangent_impulse.0[l], s.tangent_other.0[l]];
                p.max_normal = s.max_normal.0[l];
                p.approach = s.approach.0[l];
                let c = &mut st.contacts[start + k];
                (c.total_normal, c.total_friction) = (s.total_normal.0[l], s.total_friction.0[l]);
            }
        }
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
    if let (Some(st), Some(&g)) = (space(st), (&gravity as &dyn Any).downcast_ref::<DVec3>()) {
        lanes3::pass::<BIAS>(st, inv_h, push_speed, g);
        return true;
    }
    let (Some(st), Some(&g)) = (plane(st), (&gravity as &dyn Any).downcast_ref::<DVec2>()) else {
        return false;
    };
    let State { quads, motion, .. } = st;
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        unsafe { quads_avx2::<BIAS>(quads, motion, inv_h, push_speed, g) };
        return true;
    }
    for q in quads.iter_mut() {
        quad::<BIAS>(q, motion, inv_h, push_speed, g);
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
        lanes3::warm_start(st);
        return true;
    }
    let Some(st) = plane(st) else { return false };
    let State { quads, motion, .. } = st;
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        unsafe { warm_avx2(quads, motion) };
        return true;
    }
    for q in quads.iter() {
        warm(q, motion);
    }
    true
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn warm_avx2(quads: &[Quad], motion: &mut [super::points::Motion<Plane>]) {
    for q in quads {
        warm(q, motion);
    }
}

/// `passes::warm_start` on one quad: each point's `normal * normal_impulse + tangent *
/// tangent_impulse` pushed.
#[inline(always)]
fn warm(q: &Quad, motion: &mut [super::points::Motion<Plane>]) {
    let (mut a, mut b) = (gather(q, &q.p.a, motion), gather(q, &q.p.b, motion));
    for s in &q.slots {
        let (tx, ty) = (-s.ny, s.nx);
        let p = (
            s.nx * s.normal_impulse + tx * s.tangent_impulse,
            s.ny * s.normal_impulse + ty * s.tangent_impulse,
        );
        push(&mut a, &mut b, s.active, (s.rax, s.ray), (s.rbx, s.rby), p);
    }
    scatter(q, &a, &b, motion);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn quads_avx2<const BIAS: bool>(
    quads: &mut [Quad],
    motion: &mut [super::points::Motion<Plane>],
    inv_h: f64,
    push_speed: f64,
    g: DVec2,
) {
    for q in quads.iter_mut() {
        quad::<BIAS>(q, motion, inv_h, push_speed, g);
    }
}

/// The pass on one quad: gathers the lanes' motions, solves each lane's points as
/// `solve_pair` does (normal impulses of both points, then their friction), scatters.
#[inline(always)]
fn quad<const BIAS: bool>(
    q: &mut Quad,
    motion: &mut [super::points::Motion<Plane>],
    inv_h: f64,
    push_speed: f64,
    g: DVec2,
) {
    let (mut a, mut b) = (gather(q, &q.p.a, motion), gather(q, &q.p.b, motion));
    let zero = F4::splat(0.0);
    let (inv_h4, h4) = (F4::splat(inv_h), F4::splat(1.0 / inv_h));
    let (push4, pull4) = (F4::splat(push_speed), F4::splat(-push_speed));
    // The arms turned by the motion since the step began (`rotate_delta`), kept from the
    // normal solve for friction (no solid turns between the two).
    let mut turned = [[zero; 4]; 2];
    for (s, t) in q.slots.iter_mut().zip(&mut turned) {
        let tax = a.dqx * s.rax - a.dqy * s.ray;
        let tay = a.dqy * s.rax + a.dqx * s.ray;
        let tbx = b.dqx * s.rbx - b.dqy * s.rby;
        let tby = b.dqy * s.rbx + b.dqx * s.rby;
        *t = [tax, tay, tbx, tby];
        let dx = b.dpx + tbx - a.dpx - tax;
        let dy = b.dpy + tby - a.dpy - tay;
        let sep = (dx * s.nx + dy * s.ny) + s.adjusted;
        let (rvx, rvy) = relative_velocity(&a, &b, (s.rax, s.ray), (s.rbx, s.rby));
        let vn = rvx * s.nx + rvy * s.ny;
        if BIAS {
            let (gx, gy) = (F4::splat(g.x), F4::splat(g.y));
            let (fax, fay) = (pick(a.moves, gx, zero), pick(a.moves, gy, zero));
            let (fbx, fby) = (pick(b.moves, gx, zero), pick(b.moves, gy, zero));
            let closing = -((fbx - fax) * s.nx + (fby - fay) * s.ny);
            let arrived = s.approach.min(arrival(vn, sep, closing, h4));
            s.approach = pick(s.active & q.p.restitution.gt(zero), arrived, s.approach);
        }
        let imp = normal::<BIAS>(
            &q.p,
            sep,
            vn,
            (inv_h4, pull4),
            s.active,
            s.normal_mass,
            &mut s.normal_impulse,
            &mut s.max_normal,
        );
        push(&mut a, &mut b, s.active, (s.rax, s.ray), (s.rbx, s.rby), (s.nx * imp, s.ny * imp));
    }
    let (tiny, huge) = (F4::splat(1e-150), F4::splat(1e150));
    for (s, t) in q.slots.iter_mut().zip(&turned) {
        let limit = q.p.friction * s.normal_impulse;
        let (ra, rb) = ((s.rax, s.ray), (s.rbx, s.rby));
        let (dvx, dvy) = relative_velocity(&a, &b, ra, rb);
        let (tx, ty) = (-s.ny, s.nx);
        let vt = dvx * tx + dvy * ty;
        let ti = s.tangent_impulse;
        let plain = ti - s.tangent_mass * vt;
        // With the bias and anchors, static friction pulls the anchors back together.
        let mut new = if BIAS {
            let mx = b.dpx + t[2] - rb.0 - a.dpx - t[0] + ra.0;
            let my = b.dpy + t[3] - rb.1 - a.dpy - t[1] + ra.1;
            let err = s.slip + (mx * tx + my * ty);
            let vbias = (q.p.friction_bias * err).clamp(pull4, push4);
            let anchored = ti - s.tangent_mass * (q.p.mass_scale * vt + vbias) - q.p.impulse_scale * ti;
            pick(q.p.friction_bias.ne(zero), anchored, plain)
        } else {
            plain
        };
        // `Plane::friction_size([new, 0.0])`, and the clamp to the friction limit.
        let size = new.map(f64::abs);
        let size = pick(size.gt(tiny) & size.lt(huge), size, (new * new + zero * zero).map(f64::sqrt));
        let over = size.gt(limit);
        let f = pick(size.gt(zero), limit / size, zero);
        new = pick(over, new * f, new);
        let other = pick(over, zero * f, zero);
        let d = new - ti;
        s.tangent_impulse = pick(s.active, new, ti);
        s.tangent_other = pick(s.active, other, s.tangent_other);
        push(&mut a, &mut b, s.active, ra, rb, (zero + tx * d, zero + ty * d));
    }
    scatter(q, &a, &b, motion);
}

/// The lanes' velocities written back to their solids' motions.
#[inline(always)]
fn scatter(q: &Quad, a: &Side, b: &Side, motion: &mut [super::points::Motion<Plane>]) {
    for l in 0..W {
        if q.p.pair[l] == NONE {
            continue;
        }
        for (i, s) in [(q.p.a[l], a), (q.p.b[l], b)] {
            let m = &mut motion[i as usize];
            (m.v.x, m.v.y, m.w) = (s.vx.0[l], s.vy.0[l], s.w.0[l]);
        }
    }
}

/// One side's motions (`idx`: the lanes' solids; an empty lane takes the first solid's,
/// which it never writes).
#[inline(always)]
fn gather(q: &Quad, idx: &[u32; W], motion: &[super::points::Motion<Plane>]) -> Side {
    let mut s = Side::default();
    for l in 0..W {
        let m = &motion[if q.p.pair[l] == NONE { 0 } else { idx[l] as usize }];
        (s.vx.0[l], s.vy.0[l], s.w.0[l]) = (m.v.x, m.v.y, m.w);
        (s.dpx.0[l], s.dpy.0[l], s.dqx.0[l], s.dqy.0[l]) = (m.dp.x, m.dp.y, m.dq.x, m.dq.y);
        (s.inv_mass.0[l], s.inv_i.0[l]) = (m.inv_mass, m.inv_i);
        s.moves.0[l] = if m.moves { u64::MAX } else { 0 };
    }
    s
}

/// A point's normal impulse in four lanes, as `solve_pair`: apart (`sep > 0`), the bias that
/// closes the gap in this substep and no more; else, in a solve pass (`BIAS`), the soft push
/// (at most the push speed, `-pull`); the accumulated impulse kept at zero or more, and the
/// largest increment. Returns the increment (applied where `active`).
#[allow(clippy::too_many_arguments)] // a point's fields, each its own lanes
#[inline(always)]
pub(super) fn normal<const BIAS: bool>(
    p: &Pairs,
    sep: F4,
    vn: F4,
    (inv_h, pull): (F4, F4),
    active: M4,
    normal_mass: F4,
    impulse: &mut F4,
    max_normal: &mut F4,
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
    let ni = *impulse;
    let imp = -normal_mass * (mass_scale * vn + vbias) - impulse_scale * ni;
    let new = (ni + imp).max(zero);
    let imp = new - ni;
    *impulse = pick(active, new, ni);
    *max_normal = pick(active, max_normal.max(imp), *max_normal);
    imp
}

/// `relative_velocity`: `mb.v + cross_wv(mb.w, rb) - ma.v - cross_wv(ma.w, ra)`.
#[inline(always)]
fn relative_velocity(a: &Side, b: &Side, ra: (F4, F4), rb: (F4, F4)) -> (F4, F4) {
    let x = b.vx + -b.w * rb.1 - a.vx - -a.w * ra.1;
    let y = b.vy + b.w * rb.0 - a.vy - a.w * ra.0;
    (x, y)
}

/// `push` where `on`: `-p` to `a`, `p` to `b`, each only if it moves.
#[inline(always)]
fn push(a: &mut Side, b: &mut Side, on: M4, ra: (F4, F4), rb: (F4, F4), (px, py): (F4, F4)) {
    let ia = on & a.moves;
    a.vx = pick(ia, a.vx - px * a.inv_mass, a.vx);
    a.vy = pick(ia, a.vy - py * a.inv_mass, a.vy);
    a.w = pick(ia, a.w - a.inv_i * (ra.0 * py - ra.1 * px), a.w);
    let ib = on & b.moves;
    b.vx = pick(ib, b.vx + px * b.inv_mass, b.vx);
    b.vy = pick(ib, b.vy + py * b.inv_mass, b.vy);
    b.w = pick(ib, b.w + b.inv_i * (rb.0 * py - rb.1 * px), b.w);
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
