//! Contact solvers, chosen by name ([`super::SOLVERS`]; a solver is one `step` and an [`super::Info`], as
//! the integrators are). The one here is Box2D v3's soft step (Catto, "Solver2D", 2024):
//!
//! ```text
//! collide     boxes widened by the speculative distance, sweep and prune (pairs joined by a
//!             joint left out), parry's manifolds; each point: arms from the centres,
//!             effective masses, the normal speed before the step (for restitution), last
//!             step's impulses matched by feature id; each joint: its arms and frames
//! substep     h = dt / substeps, `substeps` times:
//!   integrate   v += h g (dynamic solids); in space the gyroscopic term, implicit
//!   warm start  the accumulated impulses applied again (joints', then contacts')
//!   solve       the joints' rows (joint/rows.rs), then each point: the normal impulse with a soft
//!               bias toward zero separation (a spring of `contact_hertz`, damping ratio
//!               `damping_ratio`, pushing at most `push_speed`); the separation kept current
//!               by the bodies' motion since the step began (no new narrow phase); friction
//!               clamped to mu times the normal
//!   drift       x += h v, the orientation turned exactly by h w
//!   relax       the same without the bias (the velocity the soft push left removed)
//! restitution the normal speed set to -e times the fastest it closed at before the contact
//!             acted (where that was faster than `restitution_threshold`)
//! project     optionally (`joint_projection`), jointed solids moved back together
//! ```
//!
//! A point that is apart is speculative: it lets the bodies close the gap in one step and no
//! more, so nothing tunnels at game speeds.

use super::space::{Space, Touch, Vect};
use super::{broad, joint, ContactReport, Kind, Solids};

/// A soft constraint's coefficients for a substep `h` (Catto's `b2MakeSoft`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Soft {
    pub(crate) bias_rate: f64,
    pub(crate) mass_scale: f64,
    pub(crate) impulse_scale: f64,
}

impl Soft {
    pub(crate) fn new(hertz: f64, zeta: f64, h: f64) -> Self {
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self { bias_rate: omega / a1, mass_scale: a2 * a3, impulse_scale: a3 }
    }
}

/// One contact point being solved.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Point<S: Space> {
    a: u32,
    b: u32,
    normal: S::V,
    tangents: [S::V; 2],
    ra: S::V,
    rb: S::V,
    /// Separation minus the arms' part, so that the separation now is
    /// `(dp_b + dq_b rb - dp_a - dq_a ra) . n + adjusted`.
    adjusted: f64,
    normal_mass: f64,
    tangent_mass: [f64; 2],
    normal_impulse: f64,
    tangent_impulse: [f64; 2],
    total_normal: f64,
    total_friction: f64,
    max_normal: f64,
    /// The fastest closing normal speed of the step before the contact acted (negative:
    /// closing): at the step's start, or in a substep's solve.
    approach: f64,
    friction: f64,
    restitution: f64,
    /// Against a static or kinematic solid: the stiffer softness.
    rigid_other: bool,
    id: u64,
    depth: f64,
    at: S::V,
    /// Where the point first touched, in each body's frame about its centre of mass: static
    /// friction holds the two together (kept while the point sticks, moved when it slides).
    anchor_a: S::V,
    anchor_b: S::V,
    /// How far the anchors had slid apart along each tangent when the step began.
    slip: [f64; 2],
}

/// What a body is during a step: velocities, and the motion since the step began.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Motion<S: Space> {
    pub(crate) v: S::V,
    pub(crate) w: S::W,
    pub(crate) dp: S::V,
    pub(crate) dq: S::Delta,
    pub(crate) inv_mass: f64,
    pub(crate) inv_i: S::InvI,
    /// Dynamic: impulses move it.
    pub(crate) moves: bool,
}

impl<S: Space> Motion<S> {
    /// What never moves (the world's end of a joint).
    pub(crate) fn fixed() -> Self {
        Self {
            v: S::V::default(),
            w: S::W::default(),
            dp: S::V::default(),
            dq: S::no_delta(),
            inv_mass: 0.0,
            inv_i: S::no_inertia(),
            moves: false,
        }
    }
}

/// What a point carries to the next step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Warm<S: Space> {
    key: (u32, u32, u64),
    normal: f64,
    tangent: [f64; 2],
    anchor_a: S::V,
    anchor_b: S::V,
}

/// The solver's memory between steps (last step's impulses for warm starting) and scratch.
#[derive(Debug, Clone)]
pub(crate) struct State<S: Space> {
    points: Vec<Point<S>>,
    /// Each pair's points: `points[ranges[k].0..ranges[k].1]`.
    ranges: Vec<(usize, usize)>,
    /// Last step's impulses and friction anchors by `(a, b, id)`, sorted.
    warm: Vec<Warm<S>>,
    order: Vec<u32>,
    lo: Vec<[f64; 3]>,
    hi: Vec<[f64; 3]>,
    moves: Vec<bool>,
    pairs: Vec<(u32, u32)>,
    touches: Vec<Touch<S::V>>,
    motion: Vec<Motion<S>>,
    /// A pair's arms turned by each body's rotation since the step began, found by the
    /// normal solve and used again by friction (no solid turns between the two).
    turned: Vec<(S::V, S::V)>,
}

impl<S: Space> Default for State<S> {
    fn default() -> Self {
        Self {
            points: Vec::new(),
            ranges: Vec::new(),
            warm: Vec::new(),
            order: Vec::new(),
            lo: Vec::new(),
            hi: Vec::new(),
            moves: Vec::new(),
            pairs: Vec::new(),
            touches: Vec::new(),
            motion: Vec::new(),
            turned: Vec::new(),
        }
    }
}

impl<S: Space> State<S> {
    /// Appends the warm starts: their count, then each one's pair, feature id (its bits),
    /// impulses and anchors.
    pub(crate) fn write_warm(&self, out: &mut Vec<f64>) {
        out.push(self.warm.len() as f64);
        for w in &self.warm {
            out.extend_from_slice(&[
                f64::from(w.key.0),
                f64::from(w.key.1),
                f64::from_bits(w.key.2),
                w.normal,
                w.tangent[0],
                w.tangent[1],
            ]);
            w.anchor_a.write(out);
            w.anchor_b.write(out);
        }
    }

    /// Reads what [`State::write_warm`] wrote, for `n` solids, checked.
    pub(crate) fn read_warm(&self, data: &[f64], n: usize) -> std::result::Result<Vec<Warm<S>>, String> {
        let d = S::DIM;
        let per = 6 + 2 * d;
        let count = data.first().copied().unwrap_or(-1.0);
        if !(count >= 0.0 && count.fract() == 0.0 && data.len() == 1 + count as usize * per) {
            return Err("the solids' warm starts do not fit their length".into());
        }
        let mut out = Vec::with_capacity(count as usize);
        for c in data[1..].chunks_exact(per) {
            let pair_ok = |x: f64| x >= 0.0 && x.fract() == 0.0 && (x as usize) < n;
            if !(pair_ok(c[0]) && pair_ok(c[1]) && c[0] < c[1]) {
                return Err(format!("a warm start names solids {} and {}", c[0], c[1]));
            }
            let rest = [c[3], c[4], c[5]].into_iter().chain(c[6..].iter().copied());
            if rest.clone().any(|x| !x.is_finite()) {
                return Err("a warm start is not finite".into());
            }
            out.push(Warm {
                key: (c[0] as u32, c[1] as u32, c[2].to_bits()),
                normal: c[3],
                tangent: [c[4], c[5]],
                anchor_a: S::V::read(&c[6..6 + d]),
                anchor_b: S::V::read(&c[6 + d..]),
            });
        }
        if out.windows(2).any(|w| w[0].key >= w[1].key) {
            return Err("the solids' warm starts are not in order".into());
        }
        Ok(out)
    }

    /// Takes the warm starts read by [`State::read_warm`]; the latest contacts are forgotten
    /// (the next step finds them again).
    pub(crate) fn set_warm(&mut self, warm: Vec<Warm<S>>) {
        self.warm = warm;
        self.points.clear();
        self.ranges.clear();
    }

    /// Copies the contacts and warm starts into `into` (the scratch is not kept).
    pub(crate) fn save(&self, into: &mut State<S>) {
        into.points.clone_from(&self.points);
        into.ranges.clone_from(&self.ranges);
        into.warm.clone_from(&self.warm);
        into.order.clone_from(&self.order);
    }

    pub(crate) fn report(&self) -> Vec<ContactReport<S::V>> {
        self.points
            .iter()
            .map(|p| ContactReport {
                pair: (p.a as usize, p.b as usize),
                point: p.at,
                normal: p.normal,
                depth: p.depth,
                normal_impulse: p.total_normal,
                friction_impulse: p.total_friction,
            })
            .collect()
    }
}

pub(crate) fn effective_mass<S: Space>(ma: &Motion<S>, mb: &Motion<S>, ra: S::V, rb: S::V, d: S::V) -> f64 {
    let (ca, cb) = (S::cross_vv(ra, d), S::cross_vv(rb, d));
    let k = ma.inv_mass + mb.inv_mass + ca.dot(S::apply(ma.inv_i, ca)) + cb.dot(S::apply(mb.inv_i, cb));
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

pub(crate) fn relative_velocity<S: Space>(ma: &Motion<S>, mb: &Motion<S>, ra: S::V, rb: S::V) -> S::V {
    mb.v + S::cross_wv(mb.w, rb) - ma.v - S::cross_wv(ma.w, ra)
}

/// Applies the impulse `p` at the arms: `-p` to `a`, `p` to `b`. A solid the solver does not
/// move (static, kinematic: no inverse mass) is left alone rather than given `p` times zero:
/// that sum changed no bit of its velocity (but a minus zero's sign, or a NaN from a runaway
/// `p`, which the dynamic solid carries as well), and without it the points on the ground
/// are independent of each other (no store and reload of the ground's velocities between
/// them), so the processor overlaps their solves.
pub(crate) fn push<S: Space>(ma: &mut Motion<S>, mb: &mut Motion<S>, ra: S::V, rb: S::V, p: S::V) {
    if ma.moves {
        ma.v -= p * ma.inv_mass;
        ma.w -= S::apply(ma.inv_i, S::cross_vv(ra, p));
    }
    if mb.moves {
        mb.v += p * mb.inv_mass;
        mb.w += S::apply(mb.inv_i, S::cross_vv(rb, p));
    }
}

/// Two distinct motions, mutably.
pub(crate) fn two<S: Space>(m: &mut [Motion<S>], a: u32, b: u32) -> (&mut Motion<S>, &mut Motion<S>) {
    let (a, b) = (a as usize, b as usize);
    if a < b {
        let (x, y) = m.split_at_mut(b);
        (&mut x[a], &mut y[0])
    } else {
        let (x, y) = m.split_at_mut(a);
        (&mut y[0], &mut x[b])
    }
}

/// Finds the contacts of the solids as they are and prepares them for the step.
fn collide<S: Space>(solids: &mut Solids<S>) {
    let margin = solids.settings.speculative_distance;
    let st = &mut solids.solver;
    st.lo.clear();
    st.hi.clear();
    st.moves.clear();
    for (b, shape) in solids.bodies.iter().zip(&solids.shapes) {
        let (lo, hi) = S::aabb(shape, b.origin(), b.q, margin / 2.0);
        st.lo.push(lo);
        st.hi.push(hi);
        st.moves.push(b.kind == Kind::Dynamic);
    }
    broad::pairs(&st.lo, &st.hi, &st.moves, &mut st.order, &mut st.pairs);
    if !solids.no_collide.is_empty() {
        // Solids joined by a joint do not collide (unless the joint says they do).
        st.pairs.retain(|p| solids.no_collide.binary_search(p).is_err());
    }
    st.points.clear();
    st.ranges.clear();
    for &(a, b) in &st.pairs {
        let (ba, bb) = (&solids.bodies[a as usize], &solids.bodies[b as usize]);
        st.touches.clear();
        S::touches(
            (&solids.shapes[a as usize], ba.origin(), ba.q),
            (&solids.shapes[b as usize], bb.origin(), bb.q),
            margin,
            &mut st.touches,
        );
        if st.touches.is_empty() {
            continue;
        }
        let (pa, pb) = (&solids.params[a as usize], &solids.params[b as usize]);
        let friction = (pa.friction * pb.friction).sqrt();
        let restitution = pa.restitution.max(pb.restitution);
        let start = st.points.len();
        for t in &st.touches {
            let at = (t.on_a + t.on_b) * 0.5;
            let (ra, rb) = (at - ba.c, at - bb.c);
            let key = (a, b, t.id);
            let (ni, ti, anchor_a, anchor_b) = match st.warm.binary_search_by(|w| w.key.cmp(&key)) {
                Ok(k) => {
                    let w = &st.warm[k];
                    (w.normal, w.tangent, w.anchor_a, w.anchor_b)
                }
                Err(_) => (0.0, [0.0; 2], S::unrotate(ba.q, ra), S::unrotate(bb.q, rb)),
            };
            let tangents = S::tangents(t.normal);
            let apart = S::rotate(bb.q, anchor_b) + bb.c - S::rotate(ba.q, anchor_a) - ba.c;
            let slip = [apart.dot(tangents[0]), apart.dot(tangents[1])];
            st.points.push(Point {
                a,
                b,
                normal: t.normal,
                tangents,
                ra,
                rb,
                adjusted: t.separation - (rb - ra).dot(t.normal),
                normal_mass: 0.0,
                tangent_mass: [0.0; 2],
                normal_impulse: ni,
                tangent_impulse: ti,
                total_normal: 0.0,
                total_friction: 0.0,
                max_normal: 0.0,
                approach: 0.0,
                friction,
                restitution,
                rigid_other: ba.kind != Kind::Dynamic || bb.kind != Kind::Dynamic,
                id: t.id,
                depth: -t.separation,
                at,
                anchor_a,
                anchor_b,
                slip,
            });
        }
        st.ranges.push((start, st.points.len()));
    }
}

/// One step of the soft step.
pub(crate) fn step<S: Space>(solids: &mut Solids<S>, dt: f64, gravity: S::V) {
    let set = solids.settings.clone();
    let n = set.substeps.max(1);
    let h = dt / f64::from(n);
    let inv_h = 1.0 / h;
    collide(solids);
    let hertz = set.contact_hertz.min(0.125 / h);
    let (soft, rigid) =
        (Soft::new(hertz, set.damping_ratio, h), Soft::new(2.0 * hertz, set.damping_ratio, h));
    let joint_soft = Soft::new(set.joint_hertz.min(0.25 / h), set.joint_damping_ratio, h);
    joint::prepare(&mut solids.joints, &solids.bodies, h);
    let joints = &mut solids.joints;

    let st = &mut solids.solver;
    st.motion.clear();
    for b in &solids.bodies {
        st.motion.push(Motion {
            v: b.v,
            w: b.w,
            dp: S::V::default(),
            dq: S::no_delta(),
            inv_mass: b.inv_mass,
            inv_i: S::world_inverse_inertia(b.q, b.inv_i_local),
            moves: b.kind == Kind::Dynamic,
        });
    }
    if !joints.is_empty() {
        // The world, for joints to it: the last motion, which never moves.
        st.motion.push(Motion::fixed());
    }
    for p in &mut st.points {
        let (ma, mb) = (&st.motion[p.a as usize], &st.motion[p.b as usize]);
        p.normal_mass = effective_mass(ma, mb, p.ra, p.rb, p.normal);
        for k in 0..S::TANGENTS {
            p.tangent_mass[k] = effective_mass(ma, mb, p.ra, p.rb, p.tangents[k]);
        }
        p.approach = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
    }

    let mut bodies = std::mem::take(&mut solids.bodies);
    for _ in 0..n {
        // Integrate velocities: drag, springs and loads (forces.rs), gravity, and in space the
        // gyroscopic term (implicit).
        super::forces::integrate(&mut solids.forces, &bodies, &mut st.motion, h);
        for (b, m) in bodies.iter().zip(st.motion.iter_mut()) {
            if b.kind == Kind::Dynamic {
                m.v += gravity * h;
                m.w = S::gyroscopic(b.q, b.i_local, m.w, h);
            }
        }
        if !joints.is_empty() {
            joint::warm_start(joints, &mut st.motion);
        }
        warm_start(st);
        for _ in 0..set.iterations {
            if !joints.is_empty() {
                joint::solve(joints, &mut st.motion, h, Some(joint_soft));
            }
            solve(st, inv_h, Some((soft, rigid, set.push_speed)));
        }
        // Integrate positions.
        for (b, m) in bodies.iter_mut().zip(st.motion.iter_mut()) {
            if b.kind == Kind::Static {
                continue;
            }
            b.c += m.v * h;
            m.dp += m.v * h;
            (b.q, m.dq) = S::turn(b.q, m.dq, m.w, h);
        }
        for _ in 0..set.iterations {
            if !joints.is_empty() {
                joint::solve(joints, &mut st.motion, h, None);
            }
            solve(st, inv_h, None);
        }
        // The impulse a point applies in a substep is its accumulated impulse (the warm
        // start and the increments): the step's is their sum.
        for p in &mut st.points {
            p.total_normal += p.normal_impulse;
            p.total_friction += S::friction_size(p.tangent_impulse);
        }
    }
    restitution(st, set.restitution_threshold);
    if !joints.is_empty() && set.joint_projection > 0 {
        joint::project(joints, &mut bodies, set.joint_projection);
    }
    for (b, m) in bodies.iter_mut().zip(&st.motion) {
        b.v = m.v;
        b.w = m.w;
    }
    solids.bodies = bodies;
    st.warm.clear();
    for p in &st.points {
        let t = p.tangent_impulse;
        let sliding = S::friction_size(t) >= 0.999 * p.friction * p.normal_impulse;
        let (anchor_a, anchor_b) = if sliding || p.normal_impulse == 0.0 {
            // Sliding (or not pressed): static friction lets go, and takes hold again where
            // the point is now.
            let (ba, bb) = (&solids.bodies[p.a as usize], &solids.bodies[p.b as usize]);
            let at = p.at + (st.motion[p.a as usize].dp + st.motion[p.b as usize].dp) * 0.5;
            (S::unrotate(ba.q, at - ba.c), S::unrotate(bb.q, at - bb.c))
        } else {
            (p.anchor_a, p.anchor_b)
        };
        st.warm.push(Warm {
            key: (p.a, p.b, p.id),
            normal: p.normal_impulse,
            tangent: t,
            anchor_a,
            anchor_b,
        });
    }
    // The points come in pair order, so the keys usually are in order already.
    if !st.warm.is_sorted_by_key(|w| w.key) {
        st.warm.sort_unstable_by_key(|w| w.key);
    }
    st.warm.dedup_by(|x, y| x.key == y.key);
}

#[allow(clippy::needless_range_loop)] // k indexes a point's tangents and impulses alike
fn warm_start<S: Space>(st: &mut State<S>) {
    for p in &st.points {
        let (ma, mb) = two(&mut st.motion, p.a, p.b);
        let mut imp = p.normal * p.normal_impulse;
        for k in 0..S::TANGENTS {
            imp += p.tangents[k] * p.tangent_impulse[k];
        }
        push(ma, mb, p.ra, p.rb, imp);
    }
}

#[allow(clippy::needless_range_loop)] // k indexes a point's tangents, masses and impulses alike
/// One pass over every pair: normal impulses (with the soft bias when `bias` is given), and
/// friction in the relax pass (without the bias).
fn solve<S: Space>(st: &mut State<S>, inv_h: f64, bias: Option<(Soft, Soft, f64)>) {
    for &(s, e) in &st.ranges {
        st.turned.clear();
        for p in &mut st.points[s..e] {
            let (ma, mb) = two(&mut st.motion, p.a, p.b);
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            st.turned.push((ta, tb));
            let d = mb.dp + tb - ma.dp - ta;
            let sep = d.dot(p.normal) + p.adjusted;
            let (mut vbias, mut mass_scale, mut impulse_scale) = (0.0, 1.0, 0.0);
            if sep > 0.0 {
                // Apart: close the gap in this substep and no more.
                vbias = sep * inv_h;
            } else if let Some((soft, rigid, push_speed)) = bias {
                let k = if p.rigid_other { rigid } else { soft };
                vbias = (k.mass_scale * k.bias_rate * sep).max(-push_speed);
                mass_scale = k.mass_scale;
                impulse_scale = k.impulse_scale;
            }
            let vn = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
            if bias.is_some() && p.restitution > 0.0 {
                // The speed a bouncing point arrives at: gravity keeps adding to it over the
                // step's substeps until the contact stops it (the step's start undercounts
                // it by up to g dt, a few % of a bounce's height).
                p.approach = p.approach.min(vn);
            }
            let imp = -p.normal_mass * (mass_scale * vn + vbias) - impulse_scale * p.normal_impulse;
            let new = (p.normal_impulse + imp).max(0.0);
            let imp = new - p.normal_impulse;
            p.normal_impulse = new;
            p.max_normal = p.max_normal.max(imp);
            push(ma, mb, p.ra, p.rb, p.normal * imp);
        }
        for (p, &(ta, tb)) in st.points[s..e].iter_mut().zip(&st.turned) {
            let (ma, mb) = two(&mut st.motion, p.a, p.b);
            let limit = p.friction * p.normal_impulse;
            let dv = relative_velocity(ma, mb, p.ra, p.rb);
            let mut new = [0.0; 2];
            // With the bias, static friction pulls the anchors back together as softly as a
            // contact pushes (so a box on a ramp steeper than it can slide on does not
            // creep); without it, friction stops the sliding velocity.
            let moved = if bias.is_some() { mb.dp + tb - p.rb - ma.dp - ta + p.ra } else { S::V::default() };
            for k in 0..S::TANGENTS {
                let vt = dv.dot(p.tangents[k]);
                new[k] = match bias {
                    Some((soft, rigid, push_speed)) => {
                        let c = if p.rigid_other { rigid } else { soft };
                        let err = p.slip[k] + moved.dot(p.tangents[k]);
                        let vbias = (c.mass_scale * c.bias_rate * err).clamp(-push_speed, push_speed);
                        p.tangent_impulse[k]
                            - p.tangent_mass[k] * (c.mass_scale * vt + vbias)
                            - c.impulse_scale * p.tangent_impulse[k]
                    }
                    None => p.tangent_impulse[k] - p.tangent_mass[k] * vt,
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
                imp += p.tangents[k] * (new[k] - p.tangent_impulse[k]);
            }
            p.tangent_impulse = new;
            push(ma, mb, p.ra, p.rb, imp);
        }
    }
}

/// After the substeps: the normal speed of each point that closed faster than `threshold`
/// and was pushed set to `-e` times its speed before the step.
fn restitution<S: Space>(st: &mut State<S>, threshold: f64) {
    for &(s, e) in &st.ranges {
        for p in &mut st.points[s..e] {
            if p.restitution == 0.0 || p.approach > -threshold || p.max_normal == 0.0 {
                continue;
            }
            let (ma, mb) = two(&mut st.motion, p.a, p.b);
            let vn = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
            let imp = -p.normal_mass * (vn + p.restitution * p.approach);
            let new = (p.normal_impulse + imp).max(0.0);
            let imp = new - p.normal_impulse;
            p.normal_impulse = new;
            p.total_normal += imp;
            push(ma, mb, p.ra, p.rb, p.normal * imp);
        }
    }
}
