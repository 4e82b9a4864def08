//! The plane's quads (`super`): two point slots a pair (the plane's manifolds have at most
//! two), one tangent, the turns since the step began as `(cos, sin)`, each lane the plane's
//! `solve_pair` written out.

use super::{arrival, chunks, pick, Pairs, Row, F4, M4, NONE, W};
use crate::contact::points::{Motion, State};
use crate::contact::space::Plane;
use glam::DVec2;

/// One point of each of four pairs (a lane each): what the passes read and write.
#[derive(Debug, Clone, Copy, Default)]
struct Slot {
    row: Row,
    nx: F4,
    ny: F4,
    rax: F4,
    ray: F4,
    rbx: F4,
    rby: F4,
    tangent_mass: F4,
    slip: F4,
    tangent_impulse: F4,
    /// The second tangent's impulse as the scalar pass leaves it (0, scaled by the friction
    /// clamp: kept for the bits).
    tangent_other: F4,
}

/// Four pairs of one colour, side by side, with up to two points each (the plane's manifolds
/// have at most two).
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::contact) struct Quad {
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

/// Packs the plane's points into quads; false (nothing packed) where a pair has more than two.
pub(super) fn pack(st: &mut State<Plane>) -> bool {
    if st.touching.iter().any(|p| p.end - p.start > 2) {
        return false;
    }
    st.quads.clear();
    for chunk in chunks(&st.coloured, &st.colour_ends, st.shared_last) {
        let mut q = Quad { p: Pairs::empty(), ..Quad::default() };
        for (l, &k) in chunk.iter().enumerate() {
            let pair = &st.touching[k as usize];
            q.p.set(l, k, pair);
            let points = &st.points[pair.start as usize..pair.end as usize];
            let contacts = &st.contacts[pair.start as usize..pair.end as usize];
            for ((s, p), c) in q.slots.iter_mut().zip(points).zip(contacts) {
                s.row.set(l, p, c);
                (s.nx.0[l], s.ny.0[l]) = (p.normal.x, p.normal.y);
                (s.rax.0[l], s.ray.0[l], s.rbx.0[l], s.rby.0[l]) = (p.ra.x, p.ra.y, p.rb.x, p.rb.y);
                s.tangent_mass.0[l] = p.tangent_mass[0];
                s.slip.0[l] = p.slip[0];
                (s.tangent_impulse.0[l], s.tangent_other.0[l]) = (p.tangent_impulse[0], p.tangent_impulse[1]);
            }
        }
        st.quads.push(q);
    }
    true
}

/// `super::accumulate` for the plane (`Plane::friction_size` with its one tangent).
pub(super) fn accumulate(st: &mut State<Plane>) {
    for q in &mut st.quads {
        for s in &mut q.slots {
            let (zero, tiny, huge) = (F4::splat(0.0), F4::splat(1e-150), F4::splat(1e150));
            let (t, other) = (s.tangent_impulse, s.tangent_other);
            let a = t.map(f64::abs);
            let plain =
                other.test(zero, |x, y| x == y) & (a.test(zero, |x, y| x == y) | (a.gt(tiny) & a.lt(huge)));
            let size = pick(plain, a, (t * t + other * other).map(f64::sqrt));
            s.row.accumulate(size);
        }
    }
}

/// `super::unpack` for the plane.
pub(super) fn unpack(st: &mut State<Plane>) {
    for q in &st.quads {
        for l in 0..W {
            if q.p.pair[l] == NONE {
                continue;
            }
            let start = st.touching[q.p.pair[l] as usize].start as usize;
            for (k, s) in q.slots.iter().enumerate() {
                if s.row.active.0[l] == 0 {
                    continue;
                }
                let p = &mut st.points[start + k];
                s.row.put(l, p, &mut st.contacts[start + k]);
                p.tangent_impulse = [s.tangent_impulse.0[l], s.tangent_other.0[l]];
            }
        }
    }
}

/// `super::pass` for the plane.
pub(super) fn pass<const BIAS: bool>(st: &mut State<Plane>, inv_h: f64, push_speed: f64, g: DVec2) {
    let State { quads, motion, .. } = st;
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        unsafe { quads_avx2::<BIAS>(quads, motion, inv_h, push_speed, g) };
        return;
    }
    for q in quads.iter_mut() {
        quad::<BIAS>(q, motion, inv_h, push_speed, g);
    }
}

/// `super::warm_start` for the plane.
pub(super) fn warm_start(st: &mut State<Plane>) {
    let State { quads, motion, .. } = st;
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2 (checked by `avx2`), the only requirement of a
        // `target_feature` function.
        unsafe { warm_avx2(quads, motion) };
        return;
    }
    for q in quads.iter() {
        warm(q, motion);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn warm_avx2(quads: &[Quad], motion: &mut [Motion<Plane>]) {
    for q in quads {
        warm(q, motion);
    }
}

/// `passes::warm_start` on one quad: each point's `normal * normal_impulse + tangent *
/// tangent_impulse` pushed.
#[inline(always)]
fn warm(q: &Quad, motion: &mut [Motion<Plane>]) {
    let (mut a, mut b) = (gather(q, &q.p.a, motion), gather(q, &q.p.b, motion));
    for s in &q.slots {
        let (tx, ty) = (-s.ny, s.nx);
        let p = (
            s.nx * s.row.normal_impulse + tx * s.tangent_impulse,
            s.ny * s.row.normal_impulse + ty * s.tangent_impulse,
        );
        push(&mut a, &mut b, s.row.active, (s.rax, s.ray), (s.rbx, s.rby), p);
    }
    scatter(q, &a, &b, motion);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn quads_avx2<const BIAS: bool>(
    quads: &mut [Quad],
    motion: &mut [Motion<Plane>],
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
fn quad<const BIAS: bool>(q: &mut Quad, motion: &mut [Motion<Plane>], inv_h: f64, push_speed: f64, g: DVec2) {
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
        let sep = (dx * s.nx + dy * s.ny) + s.row.adjusted;
        let (rvx, rvy) = relative_velocity(&a, &b, (s.rax, s.ray), (s.rbx, s.rby));
        let vn = rvx * s.nx + rvy * s.ny;
        if BIAS {
            let (gx, gy) = (F4::splat(g.x), F4::splat(g.y));
            let (fax, fay) = (pick(a.moves, gx, zero), pick(a.moves, gy, zero));
            let (fbx, fby) = (pick(b.moves, gx, zero), pick(b.moves, gy, zero));
            let closing = -((fbx - fax) * s.nx + (fby - fay) * s.ny);
            let arrived = s.row.approach.min(arrival(vn, sep, closing, h4));
            s.row.approach = pick(s.row.active & q.p.restitution.gt(zero), arrived, s.row.approach);
        }
        let imp = s.row.solve::<BIAS>(&q.p, sep, vn, (inv_h4, pull4));
        push(&mut a, &mut b, s.row.active, (s.rax, s.ray), (s.rbx, s.rby), (s.nx * imp, s.ny * imp));
    }
    let (tiny, huge) = (F4::splat(1e-150), F4::splat(1e150));
    for (s, t) in q.slots.iter_mut().zip(&turned) {
        let limit = q.p.friction * s.row.normal_impulse;
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
        // (The root and the quotient only where a lane needs them: the same bits, the
        // latencies off the common path, a normal-sized impulse within its limit.)
        let size = new.map(f64::abs);
        let normal = size.gt(tiny) & size.lt(huge);
        let size =
            if normal.all() { size } else { pick(normal, size, (new * new + zero * zero).map(f64::sqrt)) };
        let over = size.gt(limit);
        let mut other = zero;
        if over.any() {
            let f = pick(size.gt(zero), limit / size, zero);
            new = pick(over, new * f, new);
            other = pick(over, zero * f, zero);
        }
        let d = new - ti;
        s.tangent_impulse = pick(s.row.active, new, ti);
        s.tangent_other = pick(s.row.active, other, s.tangent_other);
        push(&mut a, &mut b, s.row.active, ra, rb, (zero + tx * d, zero + ty * d));
    }
    scatter(q, &a, &b, motion);
}

/// The lanes' velocities written back to their solids' motions.
#[inline(always)]
fn scatter(q: &Quad, a: &Side, b: &Side, motion: &mut [Motion<Plane>]) {
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
fn gather(q: &Quad, idx: &[u32; W], motion: &[Motion<Plane>]) -> Side {
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
