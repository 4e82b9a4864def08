//! The passes over the contact points that the contact solvers' schedules are made of
//! (`solver.rs` lays them out): the warm start, the solve and relax passes in Gauss-Seidel
//! order (`solve`, one pair at a time in registers: `solve_pair`) or Jacobi's (`solve_jacobi`,
//! with the masses split among a solid's pairs: `split_mass`), the non-linear Gauss-Seidel
//! position pass (`ngs`), and restitution after the substeps.

use super::points::{push, relative_velocity, two, Motion, Pair, Point, State};
use super::space::{Space, Vect};

/// The fraction of an overlap PGS's position bias removes in a step (Box2D v2's
/// `b2_baumgarte`).
pub(super) const BAUMGARTE: f64 = 0.2;

/// The overlap NGS leaves (Box2D v2's `b2_linearSlop`), m.
const SLOP: f64 = 0.005;
/// The most NGS moves a point in a pass (Box2D v2's `b2_maxLinearCorrection`), m.
const MAX_CORRECTION: f64 = 0.2;

/// One pass of non-linear Gauss-Seidel over every contact point: the separation now, from the
/// solids' motion since the step began (as the passes keep it), and where it overlaps by more
/// than the slop, both solids moved apart along the normal (and turned about their centres)
/// by the position impulse that removes `BAUMGARTE` of the excess, at most
/// `MAX_CORRECTION`, with the point's effective mass of the step's start.
pub(super) fn ngs<S: Space>(st: &mut State<S>, bodies: &mut [super::Body<S>]) {
    for pair in &st.touching {
        let (ia, ib) = (pair.a as usize, pair.b as usize);
        for p in &st.points[pair.start as usize..pair.end as usize] {
            let (ma, mb) = (&st.motion[ia], &st.motion[ib]);
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            let sep = (mb.dp + tb - ma.dp - ta).dot(p.normal) + p.adjusted;
            let c = (BAUMGARTE * (sep + SLOP)).clamp(-MAX_CORRECTION, 0.0);
            if c >= 0.0 {
                continue;
            }
            let push = p.normal * (-c * p.normal_mass);
            for (i, arm, sign) in [(ia, ta, -1.0), (ib, tb, 1.0)] {
                let (m, b) = (&mut st.motion[i], &mut bodies[i]);
                if !m.moves {
                    continue;
                }
                let d = push * (sign * m.inv_mass);
                b.c += d;
                m.dp += d;
                let turn = S::apply(m.inv_i, S::cross_vv(arm, push)) * sign;
                (b.q, m.dq) = S::turn(b.q, m.dq, turn, 1.0);
            }
        }
    }
}

/// The most colours [`colour`] gives; the pairs past them share the last, in pair order.
pub(super) const COLOURS: usize = 64;

/// Orders the pairs for the Gauss-Seidel passes (`st.coloured`, and where each colour ends in
/// it, `st.colour_ends`): greedily coloured in pair order, each pair the lowest colour neither
/// of its moving solids has yet (a solid that does not move, whose velocities no pass
/// changes, joins any number of a colour's pairs), then colour by colour, in pair order
/// within a colour. The pairs of a colour share no moving solid, so solving them one after
/// the other or side by side is the same (`lanes/` solves four at a time). The
/// pairs left when a solid's pairs have taken the first `COLOURS - 1` colours all go to the
/// last, which shares solids and is solved a pair at a time.
pub(super) fn colour<S: Space>(st: &mut State<S>) {
    let last = COLOURS - 1;
    st.colours.clear();
    st.colours.resize(st.motion.len(), 0);
    st.pair_colour.clear();
    let mut count = [0u32; COLOURS];
    for pair in &st.touching {
        let (a, b) = (pair.a as usize, pair.b as usize);
        let taken = |i: usize| if st.motion[i].moves { st.colours[i] } else { 0 };
        let c = ((taken(a) | taken(b)).trailing_ones() as usize).min(last);
        if c < last {
            for i in [a, b] {
                if st.motion[i].moves {
                    st.colours[i] |= 1 << c;
                }
            }
        }
        count[c] += 1;
        st.pair_colour.push(c as u8);
    }
    st.colour_ends.clear();
    let mut at = [0u32; COLOURS];
    let mut end = 0;
    for c in 0..COLOURS {
        at[c] = end;
        end += count[c];
        if count[c] > 0 {
            st.colour_ends.push(end);
        }
    }
    st.shared_last = count[last] > 0;
    st.coloured.clear();
    st.coloured.resize(st.touching.len(), 0);
    for (k, &c) in st.pair_colour.iter().enumerate() {
        st.coloured[at[c as usize] as usize] = k as u32;
        at[c as usize] += 1;
    }
}

/// The accumulated impulses applied again, pair by pair in the coloured order (`colour`).
#[allow(clippy::needless_range_loop)] // k indexes a point's tangents and impulses alike
pub(super) fn warm_start<S: Space>(st: &mut State<S>) {
    if super::lanes::warm_start(st) {
        return;
    }
    for &k in &st.coloured {
        let pair = &st.touching[k as usize];
        let (ia, ib) = (pair.a as usize, pair.b as usize);
        // The two solids' motions held in registers over the pair's points.
        let (mut ma, mut mb) = (st.motion[ia], st.motion[ib]);
        for p in &st.points[pair.start as usize..pair.end as usize] {
            let mut imp = p.normal * p.normal_impulse;
            for k in 0..S::TANGENTS {
                imp += S::tangent(p.normal, p.frame, k) * p.tangent_impulse[k];
            }
            push(&mut ma, &mut mb, p.ra, p.rb, imp);
        }
        (st.motion[ia].v, st.motion[ia].w) = (ma.v, ma.w);
        (st.motion[ib].v, st.motion[ib].w) = (mb.v, mb.w);
    }
}

/// One pass over every pair (Gauss-Seidel: each pair sees what the pairs before it did),
/// normal impulses, then friction, with the soft bias (`BIAS`, the solve) or without it (the
/// relax pass). The two solids' motions are held in registers over the pair's points and
/// stored once. `gravity` is what the bounce of a point still apart gains on its way across
/// the gap ([`arrival`]).
pub(super) fn solve<S: Space, const BIAS: bool>(
    st: &mut State<S>,
    inv_h: f64,
    push_speed: f64,
    gravity: S::V,
) {
    if super::lanes::pass::<S, BIAS>(st, inv_h, push_speed, gravity) {
        return;
    }
    for &k in &st.coloured {
        let pair = &st.touching[k as usize];
        let (ia, ib) = (pair.a as usize, pair.b as usize);
        let (mut ma, mut mb) = (st.motion[ia], st.motion[ib]);
        let points = &mut st.points[pair.start as usize..pair.end as usize];
        solve_pair::<S, BIAS>(pair, points, (&mut ma, &mut mb), inv_h, push_speed, gravity);
        (st.motion[ia].v, st.motion[ia].w) = (ma.v, ma.w);
        (st.motion[ib].v, st.motion[ib].w) = (mb.v, mb.w);
    }
}

/// One Jacobi pass: every pair solved from the motions of the pass's start (no pair sees
/// another's impulses until the pass ends), the changes of velocity summed over the pairs
/// and applied after the pass. Each pair's impulses are its own, so the pairs could be solved
/// in parallel; they are summed in pair order here (the same bits on any thread count).
pub(super) fn solve_jacobi<S: Space, const BIAS: bool>(
    st: &mut State<S>,
    inv_h: f64,
    push_speed: f64,
    gravity: S::V,
) {
    st.pass_start.clone_from(&st.motion);
    for pair in &st.touching {
        let (ia, ib) = (pair.a as usize, pair.b as usize);
        let (sa, sb) = (st.pass_start[ia], st.pass_start[ib]);
        let (mut ma, mut mb) = (sa, sb);
        let points = &mut st.points[pair.start as usize..pair.end as usize];
        solve_pair::<S, BIAS>(pair, points, (&mut ma, &mut mb), inv_h, push_speed, gravity);
        for (i, m, s) in [(ia, ma, sa), (ib, mb, sb)] {
            st.motion[i].v += m.v - s.v;
            st.motion[i].w += m.w - s.w;
        }
    }
}

/// A point's effective mass along `d` with each solid split into as many parts as it has pairs
/// in contact (`na`, `nb`: Tonge, Benevolenski and Voroshilov, "Mass splitting for jitter-free
/// parallel rigid body simulation", 2012): a Jacobi pass then applies each pair's impulse in
/// full, the sum over a solid's pairs being the average of its parts' velocities, and does
/// not overshoot where many pairs push one solid at once.
pub(super) fn split_mass<S: Space>(
    ma: &Motion<S>,
    mb: &Motion<S>,
    ra: S::V,
    rb: S::V,
    d: S::V,
    (na, nb): (f64, f64),
) -> f64 {
    let (ca, cb) = (S::cross_vv(ra, d), S::cross_vv(rb, d));
    let k = na * (ma.inv_mass + ca.dot(S::apply(ma.inv_i, ca)))
        + nb * (mb.inv_mass + cb.dot(S::apply(mb.inv_i, cb)));
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

/// One pair's points in a pass: normal impulses, then friction, on the two solids' motions.
#[allow(clippy::needless_range_loop)] // k indexes a point's tangents, masses and impulses alike
#[inline(always)]
fn solve_pair<S: Space, const BIAS: bool>(
    pair: &Pair,
    points: &mut [Point<S>],
    (ma, mb): (&mut Motion<S>, &mut Motion<S>),
    inv_h: f64,
    push_speed: f64,
    gravity: S::V,
) {
    let c = pair.soft;
    for p in points.iter_mut() {
        let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
        let d = mb.dp + tb - ma.dp - ta;
        let sep = d.dot(p.normal) + p.adjusted;
        let (mut vbias, mut mass_scale, mut impulse_scale) = (0.0, 1.0, 0.0);
        if sep > 0.0 {
            // Apart: close the gap in this substep and no more.
            vbias = sep * inv_h;
        } else if BIAS {
            vbias = (c.bias * sep).max(-push_speed);
            mass_scale = c.mass_scale;
            impulse_scale = c.impulse_scale;
        }
        let vn = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
        if BIAS && pair.restitution > 0.0 {
            // The speed a bouncing point arrives at: gravity keeps adding to it over the
            // step's substeps until the contact stops it (the step's start undercounts
            // it by up to g dt, a few % of a bounce's height), and across the gap it
            // still has to close (the speculative contact stops it at the surface).
            let fall = |m: &Motion<S>| if m.moves { gravity } else { S::V::default() };
            let closing = -(fall(mb) - fall(ma)).dot(p.normal);
            p.approach = p.approach.min(arrival(vn, sep, closing, 1.0 / inv_h));
        }
        let imp = -p.normal_mass * (mass_scale * vn + vbias) - impulse_scale * p.normal_impulse;
        let new = (p.normal_impulse + imp).max(0.0);
        let imp = new - p.normal_impulse;
        p.normal_impulse = new;
        p.max_normal = p.max_normal.max(imp);
        push(ma, mb, p.ra, p.rb, p.normal * imp);
    }
    for p in points.iter_mut() {
        let limit = pair.friction * p.normal_impulse;
        let dv = relative_velocity(ma, mb, p.ra, p.rb);
        let mut new = [0.0; 2];
        // With the bias and anchors (the soft step's, sticky TGS's), static friction pulls
        // the anchors back together as softly as a contact pushes (so a box on a ramp
        // steeper than it can slide on does not creep); without them (the relax pass, and
        // the solvers with plain friction, whose friction is rigid even where their normal
        // rows are soft, as Solver2D's soft PGS), friction stops the sliding velocity. The
        // arms are turned again as the normal solve turned them (no solid turns between the
        // two).
        let anchored = BIAS && c.friction_bias != 0.0;
        let moved = if anchored {
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            mb.dp + tb - p.rb - ma.dp - ta + p.ra
        } else {
            S::V::default()
        };
        for k in 0..S::TANGENTS {
            let t = S::tangent(p.normal, p.frame, k);
            let vt = dv.dot(t);
            new[k] = if anchored {
                let err = p.slip[k] + moved.dot(t);
                let vbias = (c.friction_bias * err).clamp(-push_speed, push_speed);
                p.tangent_impulse[k]
                    - p.tangent_mass[k] * (c.mass_scale * vt + vbias)
                    - c.impulse_scale * p.tangent_impulse[k]
            } else {
                p.tangent_impulse[k] - p.tangent_mass[k] * vt
            };
        }
        let size = S::friction_size(new);
        if size > limit {
            let f = if size > 0.0 { limit / size } else { 0.0 };
            new[0] *= f;
            new[1] *= f;
        }
        let mut imp = S::V::default();
        for k in 0..S::TANGENTS {
            imp += S::tangent(p.normal, p.frame, k) * (new[k] - p.tangent_impulse[k]);
        }
        p.tangent_impulse = new;
        push(ma, mb, p.ra, p.rb, imp);
    }
}

/// The normal speed (negative: closing) at which a point `sep` apart (> 0) that closes at
/// `vn` meets the other solid, under a `closing` acceleration (along the normal, toward it)
/// over substeps of `h`: the substeps' symplectic Euler keeps `(v - a h / 2)^2 / 2 + a x` of a
/// free fall, so the point arrives with `(|v| - a h / 2)^2 + 2 a sep` for `(|v_arrival| - a h
/// / 2)^2`. A speculative contact stops the point at the surface without that gain: a bounce
/// that took `vn` for its speed lost `closing * sep` of energy a unit mass (for an elastic
/// ball on a plane, the gap's height each bounce: 17% over 100 bounces put back by continuous
/// collision 1 mm above the ground). `vn` where the point is not apart or not closing, or
/// would not arrive in free fall.
fn arrival(vn: f64, sep: f64, closing: f64, h: f64) -> f64 {
    if !(sep > 0.0 && vn < 0.0) {
        return vn;
    }
    let c = -vn - 0.5 * closing * h;
    let r = c * c + 2.0 * closing * sep;
    if c > 0.0 && r > 0.0 {
        -(0.5 * closing * h + r.sqrt())
    } else {
        vn
    }
}

/// After the substeps: the normal speed of each point that closed faster than `threshold`
/// and was pushed set to `-e` times its speed before the step.
pub(super) fn restitution<S: Space>(st: &mut State<S>, threshold: f64) {
    for pair in &st.touching {
        if pair.restitution == 0.0 {
            continue;
        }
        let range = pair.start as usize..pair.end as usize;
        for (p, c) in st.points[range.clone()].iter_mut().zip(&mut st.contacts[range]) {
            if p.approach > -threshold || p.max_normal == 0.0 {
                continue;
            }
            let (ma, mb) = two(&mut st.motion, pair.a, pair.b);
            let vn = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
            let imp = -p.normal_mass * (vn + pair.restitution * p.approach);
            let new = (p.normal_impulse + imp).max(0.0);
            let imp = new - p.normal_impulse;
            p.normal_impulse = new;
            c.total_normal += imp;
            push(ma, mb, p.ra, p.rb, p.normal * imp);
        }
    }
}
