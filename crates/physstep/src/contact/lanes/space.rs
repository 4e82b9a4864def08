//! Space's quads (`super`): the Gauss-Seidel passes four pairs at a time for solids in 3D (quaternion
//! turns, inertia tensors, two tangents; a quad has as many point slots as its pair with the
//! most points, in `State::slots3`), each lane's arithmetic exactly `passes::solve_pair`'s
//! of that pair in space, operation for operation (glam's quaternion and matrix products
//! written out in their order), so the bits are those of the one-pair passes in the coloured
//! order. A quad's masses and inertias, which a step does not change, are gathered once, when
//! it is packed.

use super::{arrival, chunks, pick, Pairs, Row, F4, M4, NONE, W};
use crate::contact::points::{Motion, State};
use crate::contact::space::Space3;
use glam::DVec3;

/// A vector of four lanes.
#[derive(Debug, Clone, Copy, Default)]
struct V3 {
    x: F4,
    y: F4,
    z: F4,
}

impl V3 {
    #[inline(always)]
    fn splat(v: DVec3) -> V3 {
        V3 { x: F4::splat(v.x), y: F4::splat(v.y), z: F4::splat(v.z) }
    }
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3 { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3 { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
    #[inline(always)]
    fn scale(self, s: F4) -> V3 {
        V3 { x: self.x * s, y: self.y * s, z: self.z * s }
    }
    /// glam's `dot`: `x x' + y y' + z z'`, left to right.
    #[inline(always)]
    fn dot(self, o: V3) -> F4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// glam's `cross`.
    #[inline(always)]
    fn cross(self, o: V3) -> V3 {
        V3 { x: self.y * o.z - o.y * self.z, y: self.z * o.x - o.z * self.x, z: self.x * o.y - o.x * self.y }
    }
    #[inline(always)]
    fn pick(m: M4, a: V3, b: V3) -> V3 {
        V3 { x: pick(m, a.x, b.x), y: pick(m, a.y, b.y), z: pick(m, a.z, b.z) }
    }
    #[inline(always)]
    fn set(&mut self, l: usize, v: DVec3) {
        (self.x.0[l], self.y.0[l], self.z.0[l]) = (v.x, v.y, v.z);
    }
}

/// One point of each of four pairs (a lane each).
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::contact) struct Slot {
    row: Row,
    n: V3,
    t0: V3,
    t1: V3,
    ra: V3,
    rb: V3,
    tangent_mass: [F4; 2],
    slip: [F4; 2],
    tangent_impulse: [F4; 2],
}

/// Four pairs of one colour, side by side; their points are the slots `slots.0..slots.1` of
/// `State::slots3` (as many as the quad's pair with the most points).
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::contact) struct Quad {
    p: Pairs,
    slots: (u32, u32),
    /// The two sides' masses and inertias.
    mass: [Mass; 2],
}

/// One side of four lanes' pairs: the solids' motions, gathered.
#[derive(Debug, Clone, Copy, Default)]
struct Side {
    v: V3,
    w: V3,
    dp: V3,
    /// The turn since the step began (a quaternion: its vector part and `w`).
    dq: V3,
    dqw: F4,
    mass: Mass,
}

/// One side of four lanes' pairs: what of the solids' motions stays the same over a step,
/// gathered once (`pack`).
#[derive(Debug, Clone, Copy, Default)]
struct Mass {
    inv_mass: F4,
    /// The world inverse inertia's columns.
    inv_i: [V3; 3],
    moves: M4,
}

/// Packs the points into quads (`super::pack` for space).
pub(super) fn pack(st: &mut State<Space3>) {
    st.quads3.clear();
    st.slots3.clear();
    for chunk in chunks(&st.coloured, &st.colour_ends, st.shared_last) {
        let at = st.slots3.len();
        let most = chunk.iter().map(|&k| st.touching[k as usize]).map(|p| p.end - p.start).max();
        st.slots3.resize(at + most.unwrap_or(0) as usize, Slot::default());
        let mut q = Quad { p: Pairs::empty(), slots: (at as u32, st.slots3.len() as u32), ..Quad::default() };
        let slots = &mut st.slots3[at..];
        for (l, &k) in chunk.iter().enumerate() {
            let pair = &st.touching[k as usize];
            q.p.set(l, k, pair);
            let range = pair.start as usize..pair.end as usize;
            for ((s, p), c) in slots.iter_mut().zip(&st.points[range.clone()]).zip(&st.contacts[range]) {
                s.row.set(l, p, c);
                s.n.set(l, p.normal);
                s.t0.set(l, p.frame[0]);
                s.t1.set(l, p.frame[1]);
                s.ra.set(l, p.ra);
                s.rb.set(l, p.rb);
                for k in 0..2 {
                    s.tangent_mass[k].0[l] = p.tangent_mass[k];
                    s.slip[k].0[l] = p.slip[k];
                    s.tangent_impulse[k].0[l] = p.tangent_impulse[k];
                }
            }
        }
        for (side, idx) in [q.p.a, q.p.b].iter().enumerate() {
            let m = &mut q.mass[side];
            for l in 0..W {
                let motion = &st.motion[if q.p.pair[l] == NONE { 0 } else { idx[l] as usize }];
                m.inv_mass.0[l] = motion.inv_mass;
                m.inv_i[0].set(l, motion.inv_i.x_axis);
                m.inv_i[1].set(l, motion.inv_i.y_axis);
                m.inv_i[2].set(l, motion.inv_i.z_axis);
                m.moves.0[l] = if motion.moves { u64::MAX } else { 0 };
            }
        }
        st.quads3.push(q);
    }
}

/// `super::unpack` for space.
pub(super) fn unpack(st: &mut State<Space3>) {
    for q in &st.quads3 {
        for l in 0..W {
            if q.p.pair[l] == NONE {
                continue;
            }
            let start = st.touching[q.p.pair[l] as usize].start as usize;
            for (k, s) in st.slots3[q.slots.0 as usize..q.slots.1 as usize].iter().enumerate() {
                if s.row.active.0[l] == 0 {
                    continue;
                }
                let p = &mut st.points[start + k];
                s.row.put(l, p, &mut st.contacts[start + k]);
                p.tangent_impulse = [s.tangent_impulse[0].0[l], s.tangent_impulse[1].0[l]];
            }
        }
    }
}

/// `super::accumulate` for space: `friction_size` is `sqrt(t0^2 + t1^2)`.
pub(super) fn accumulate(st: &mut State<Space3>) {
    {
        for s in &mut st.slots3 {
            let [t0, t1] = s.tangent_impulse;
            let size = (t0 * t0 + t1 * t1).map(f64::sqrt);
            s.row.accumulate(size);
        }
    }
}

/// The warm start over the quads (`super::warm_start` for space).
pub(super) fn warm_start(st: &mut State<Space3>) {
    let State { quads3, slots3, motion, .. } = st;
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        unsafe { warm_avx2(quads3, slots3, motion) };
        return;
    }
    for q in quads3.iter() {
        warm(q, slots3, motion);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn warm_avx2(quads: &[Quad], slots: &[Slot], motion: &mut [Motion<Space3>]) {
    for q in quads {
        warm(q, slots, motion);
    }
}

/// `passes::warm_start` on one quad: `normal * normal_impulse + t0 * ti0 + t1 * ti1` pushed.
#[inline(always)]
fn warm(q: &Quad, slots: &[Slot], motion: &mut [Motion<Space3>]) {
    let (mut a, mut b) = (gather(q, &q.p.a, q.mass[0], motion), gather(q, &q.p.b, q.mass[1], motion));
    for s in &slots[q.slots.0 as usize..q.slots.1 as usize] {
        let p =
            s.n.scale(s.row.normal_impulse)
                .add(s.t0.scale(s.tangent_impulse[0]))
                .add(s.t1.scale(s.tangent_impulse[1]));
        push(&mut a, &mut b, s.row.active, s.ra, s.rb, p);
    }
    scatter(q, &a, &b, motion);
}

/// One Gauss-Seidel pass over the quads (`super::pass` for space).
pub(super) fn pass<const BIAS: bool>(st: &mut State<Space3>, inv_h: f64, push_speed: f64, g: DVec3) {
    let State { quads3, slots3, motion, .. } = st;
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        unsafe { quads_avx2::<BIAS>(quads3, slots3, motion, inv_h, push_speed, g) };
        return;
    }
    for q in quads3.iter() {
        quad::<BIAS>(q, slots3, motion, inv_h, push_speed, g);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn quads_avx2<const BIAS: bool>(
    quads: &[Quad],
    slots: &mut [Slot],
    motion: &mut [Motion<Space3>],
    inv_h: f64,
    push_speed: f64,
    g: DVec3,
) {
    for q in quads {
        quad::<BIAS>(q, slots, motion, inv_h, push_speed, g);
    }
}

/// glam's `DQuat * DVec3` (`mul_vec3`) of the turns `(dq, dqw)` on `v`, lane by lane.
#[inline(always)]
fn rotate(dq: V3, dqw: F4, v: V3) -> V3 {
    let two = F4::splat(2.0);
    let b2 = dq.dot(dq);
    v.scale(dqw * dqw - b2).add(dq.scale(v.dot(dq) * two)).add(dq.cross(v).scale(dqw * two))
}

/// glam's `DMat3 * DVec3`: the columns scaled by the components, summed in order.
#[inline(always)]
fn apply(m: &[V3; 3], v: V3) -> V3 {
    m[0].scale(v.x).add(m[1].scale(v.y)).add(m[2].scale(v.z))
}

/// `relative_velocity`: `mb.v + mb.w x rb - ma.v - ma.w x ra`.
#[inline(always)]
fn relative_velocity(a: &Side, b: &Side, ra: V3, rb: V3) -> V3 {
    b.v.add(b.w.cross(rb)).sub(a.v).sub(a.w.cross(ra))
}

/// `push` where `on`: `-p` to `a`, `p` to `b`, each only if it moves.
#[inline(always)]
fn push(a: &mut Side, b: &mut Side, on: M4, ra: V3, rb: V3, p: V3) {
    let ia = on & a.mass.moves;
    a.v = V3::pick(ia, a.v.sub(p.scale(a.mass.inv_mass)), a.v);
    a.w = V3::pick(ia, a.w.sub(apply(&a.mass.inv_i, ra.cross(p))), a.w);
    let ib = on & b.mass.moves;
    b.v = V3::pick(ib, b.v.add(p.scale(b.mass.inv_mass)), b.v);
    b.w = V3::pick(ib, b.w.add(apply(&b.mass.inv_i, rb.cross(p))), b.w);
}

/// One side's motions (an empty lane takes the first solid's, which it never writes), with
/// the side's masses packed with the quad.
#[inline(always)]
fn gather(q: &Quad, idx: &[u32; W], mass: Mass, motion: &[Motion<Space3>]) -> Side {
    let mut s = Side::default();
    for l in 0..W {
        let m = &motion[if q.p.pair[l] == NONE { 0 } else { idx[l] as usize }];
        s.v.set(l, m.v);
        s.w.set(l, m.w);
        s.dp.set(l, m.dp);
        s.dq.set(l, DVec3::new(m.dq.x, m.dq.y, m.dq.z));
        s.dqw.0[l] = m.dq.w;
    }
    s.mass = mass;
    s
}

/// The lanes' velocities written back to their solids' motions.
#[inline(always)]
fn scatter(q: &Quad, a: &Side, b: &Side, motion: &mut [Motion<Space3>]) {
    for l in 0..W {
        if q.p.pair[l] == NONE {
            continue;
        }
        for (i, s) in [(q.p.a[l], a), (q.p.b[l], b)] {
            let m = &mut motion[i as usize];
            m.v = DVec3::new(s.v.x.0[l], s.v.y.0[l], s.v.z.0[l]);
            m.w = DVec3::new(s.w.x.0[l], s.w.y.0[l], s.w.z.0[l]);
        }
    }
}

/// The pass on one quad, as `solve_pair` in space: normal impulses of every point, then their
/// friction along the two tangents.
#[inline(always)]
fn quad<const BIAS: bool>(
    q: &Quad,
    slots: &mut [Slot],
    motion: &mut [Motion<Space3>],
    inv_h: f64,
    push_speed: f64,
    g: DVec3,
) {
    let (mut a, mut b) = (gather(q, &q.p.a, q.mass[0], motion), gather(q, &q.p.b, q.mass[1], motion));
    let slots = &mut slots[q.slots.0 as usize..q.slots.1 as usize];
    let zero = F4::splat(0.0);
    let (inv_h4, h4) = (F4::splat(inv_h), F4::splat(1.0 / inv_h));
    let (push4, pull4) = (F4::splat(push_speed), F4::splat(-push_speed));
    let none = V3::default();
    // The arms turned by the motion since the step began, kept from the normal solve for
    // friction (no solid turns between the two) for the first `KEPT` slots.
    const KEPT: usize = 8;
    let mut turned = [(none, none); KEPT];
    for (k, s) in slots.iter_mut().enumerate() {
        let (ta, tb) = (rotate(a.dq, a.dqw, s.ra), rotate(b.dq, b.dqw, s.rb));
        if k < KEPT {
            turned[k] = (ta, tb);
        }
        let d = b.dp.add(tb).sub(a.dp).sub(ta);
        let sep = d.dot(s.n) + s.row.adjusted;
        let vn = relative_velocity(&a, &b, s.ra, s.rb).dot(s.n);
        if BIAS {
            let g3 = V3::splat(g);
            let (fa, fb) = (V3::pick(a.mass.moves, g3, none), V3::pick(b.mass.moves, g3, none));
            let closing = -fb.sub(fa).dot(s.n);
            let arrived = s.row.approach.min(arrival(vn, sep, closing, h4));
            s.row.approach = pick(s.row.active & q.p.restitution.gt(zero), arrived, s.row.approach);
        }
        let imp = s.row.solve::<BIAS>(&q.p, sep, vn, (inv_h4, pull4));
        push(&mut a, &mut b, s.row.active, s.ra, s.rb, s.n.scale(imp));
    }
    for (k, s) in slots.iter_mut().enumerate() {
        let (ta, tb) =
            if k < KEPT { turned[k] } else { (rotate(a.dq, a.dqw, s.ra), rotate(b.dq, b.dqw, s.rb)) };
        let limit = q.p.friction * s.row.normal_impulse;
        let dv = relative_velocity(&a, &b, s.ra, s.rb);
        let moved = b.dp.add(tb).sub(s.rb).sub(a.dp).sub(ta).add(s.ra);
        let anchored = q.p.friction_bias.test(zero, |x, y| x != y);
        let mut new = [zero; 2];
        for (k, t) in [s.t0, s.t1].into_iter().enumerate() {
            let vt = dv.dot(t);
            let ti = s.tangent_impulse[k];
            let plain = ti - s.tangent_mass[k] * vt;
            new[k] = if BIAS {
                let err = s.slip[k] + moved.dot(t);
                let vbias = (q.p.friction_bias * err).clamp(pull4, push4);
                let held = ti - s.tangent_mass[k] * (q.p.mass_scale * vt + vbias) - q.p.impulse_scale * ti;
                pick(anchored, held, plain)
            } else {
                plain
            };
        }
        // The root, the quotient and the clamp only where a lane may be over its limit: a
        // lane whose square is below `limit^2 (1 - 2^-40)`, computed (a product rounded twice
        // is still below `limit^2`), has its root at most `limit` (the root rounded to
        // nearest does not pass a double above its exact value), so it is not over; with
        // `limit` below 1e150 its square is finite. The same bits, the latencies off the
        // common path (friction within its cone).
        let square = new[0] * new[0] + new[1] * new[1];
        let under = square.lt(limit * limit * F4::splat(1.0 - 1.0 / (1u64 << 40) as f64))
            & limit.lt(F4::splat(1e150));
        if !under.all() {
            let size = square.map(f64::sqrt);
            let over = size.gt(limit);
            let f = pick(size.gt(zero), limit / size, zero);
            new = [pick(over, new[0] * f, new[0]), pick(over, new[1] * f, new[1])];
        }
        let imp = V3::default()
            .add(s.t0.scale(new[0] - s.tangent_impulse[0]))
            .add(s.t1.scale(new[1] - s.tangent_impulse[1]));
        for k in 0..2 {
            s.tangent_impulse[k] = pick(s.row.active, new[k], s.tangent_impulse[k]);
        }
        push(&mut a, &mut b, s.row.active, s.ra, s.rb, imp);
    }
    scatter(q, &a, &b, motion);
}
