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
//!             acted, counted where it meets the other solid (a point still apart gains
//!             gravity's share across the gap), where that was faster than
//!             `restitution_threshold`
//! project     optionally (`joint_projection`), jointed solids moved back together
//! continuous  a dynamic solid that moved farther than the speculative distance swept from
//!             its start pose against the static and kinematic solids, and put back to its
//!             time of impact (toi.rs)
//! ```
//!
//! A point that is apart is speculative: it lets the bodies close the gap in one step and no
//! more; what moves farther than the speculative distance in a step is continuous collision's.

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

/// The coefficients of a pair's softness as the passes use them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Coefs {
    /// `mass_scale * bias_rate` (the product the bias is made of, taken once).
    bias: f64,
    mass_scale: f64,
    impulse_scale: f64,
}

impl Coefs {
    fn of(k: Soft) -> Self {
        Self { bias: k.mass_scale * k.bias_rate, mass_scale: k.mass_scale, impulse_scale: k.impulse_scale }
    }
}

/// Two solids in contact: what their points share, and where the points are.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pair {
    a: u32,
    b: u32,
    /// The points: `points[start..end]` (and `contacts[start..end]`).
    start: u32,
    end: u32,
    friction: f64,
    restitution: f64,
    /// Against a static or kinematic solid: the stiffer softness.
    rigid_other: bool,
    /// The softness of this step's substeps (the stiffer one where `rigid_other`).
    soft: Coefs,
}

/// One contact point as the passes solve it: what they read and write, kept together and
/// apart from what they do not ([`Contact`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Point<S: Space> {
    normal: S::V,
    /// The tangents (kept in space; the normal turned a quarter in the plane).
    frame: S::Frame,
    ra: S::V,
    rb: S::V,
    /// Separation minus the arms' part, so that the separation now is
    /// `(dp_b + dq_b rb - dp_a - dq_a ra) . n + adjusted`.
    adjusted: f64,
    normal_mass: f64,
    tangent_mass: [f64; 2],
    normal_impulse: f64,
    tangent_impulse: [f64; 2],
    max_normal: f64,
    /// The fastest closing normal speed of the step before the contact acted (negative:
    /// closing): at the step's start, or in a substep's solve.
    approach: f64,
    /// How far the anchors had slid apart along each tangent when the step began.
    slip: [f64; 2],
}

/// What the passes do not read of a contact point: what it reports, and what it carries to
/// the next step besides its impulses.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Contact<S: Space> {
    a: u32,
    b: u32,
    id: u64,
    normal: S::V,
    depth: f64,
    at: S::V,
    total_normal: f64,
    total_friction: f64,
    /// Where the point first touched, in each body's frame about its centre of mass: static
    /// friction holds the two together (kept while the point sticks, moved when it slides).
    anchor_a: S::V,
    anchor_b: S::V,
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

/// The solver's memory between steps (last step's impulses for warm starting, the latest
/// contacts for reports) and scratch.
#[derive(Debug, Clone)]
pub(crate) struct State<S: Space> {
    /// The latest step's contact points as the passes solve them (scratch between steps:
    /// the next step finds them again).
    points: Vec<Point<S>>,
    /// The same points' reports and anchors (kept between steps).
    contacts: Vec<Contact<S>>,
    /// The pairs in contact and their points (scratch between steps).
    touching: Vec<Pair>,
    /// Last step's impulses and friction anchors by `(a, b, id)`, sorted.
    warm: Vec<Warm<S>>,
    order: Vec<u32>,
    lo: Vec<[f64; 3]>,
    hi: Vec<[f64; 3]>,
    moves: Vec<bool>,
    /// Each solid's orientation made ready to turn vectors, and its shape's origin.
    basis: Vec<(S::Basis, S::V)>,
    pairs: Vec<(u32, u32)>,
    touches: Vec<Touch<S::V>>,
    motion: Vec<Motion<S>>,
    /// Continuous collision's poses of the step's start (toi.rs).
    sweeps: super::toi::Sweeps<S>,
}

impl<S: Space> Default for State<S> {
    fn default() -> Self {
        Self {
            points: Vec::new(),
            contacts: Vec::new(),
            touching: Vec::new(),
            warm: Vec::new(),
            order: Vec::new(),
            lo: Vec::new(),
            hi: Vec::new(),
            moves: Vec::new(),
            basis: Vec::new(),
            pairs: Vec::new(),
            touches: Vec::new(),
            motion: Vec::new(),
            sweeps: super::toi::Sweeps::default(),
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
        self.contacts.clear();
        self.touching.clear();
    }

    /// Takes solid `k` out: its warm starts and latest contacts dropped, the others' kept
    /// and renumbered (their order stays sorted: the renumbering keeps it), the broad phase's
    /// order renumbered; the passes' scratch forgotten (the next step finds it again).
    pub(crate) fn remove_solid(&mut self, k: usize) {
        let k32 = k as u32;
        let s = |i: u32| if i > k32 { i - 1 } else { i };
        self.warm.retain(|w| w.key.0 != k32 && w.key.1 != k32);
        for w in &mut self.warm {
            w.key = (s(w.key.0), s(w.key.1), w.key.2);
        }
        self.contacts.retain(|c| c.a != k32 && c.b != k32);
        for c in &mut self.contacts {
            (c.a, c.b) = (s(c.a), s(c.b));
        }
        self.order.retain(|&i| i != k32);
        for i in &mut self.order {
            *i = s(*i);
        }
        self.points.clear();
        self.touching.clear();
    }

    /// Forgets the warm starts of solid `k`'s contacts (it was moved by hand: last step's
    /// impulses and friction anchors no longer fit where it is).
    pub(crate) fn forget(&mut self, k: usize) {
        let k = k as u32;
        self.warm.retain(|w| w.key.0 != k && w.key.1 != k);
    }

    /// Copies what the next step and the reports read into `into`: the contacts, the warm
    /// starts and the broad phase's order (the passes' points are scratch, found again by
    /// the next step, and not kept).
    pub(crate) fn save(&self, into: &mut State<S>) {
        into.contacts.clone_from(&self.contacts);
        into.warm.clone_from(&self.warm);
        into.order.clone_from(&self.order);
    }

    /// Puts back what [`State::save`] kept in `from` (its buffers reused).
    pub(crate) fn restore(&mut self, from: &State<S>) {
        from.save(self);
    }

    pub(crate) fn report(&self) -> Vec<ContactReport<S::V>> {
        self.contacts
            .iter()
            .map(|c| ContactReport {
                pair: (c.a as usize, c.b as usize),
                point: c.at,
                normal: c.normal,
                depth: c.depth,
                normal_impulse: c.total_normal,
                friction_impulse: c.total_friction,
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
#[allow(clippy::needless_range_loop)] // k indexes a point's tangents and slips alike
fn collide<S: Space>(solids: &mut Solids<S>) {
    let margin = solids.settings.speculative_distance;
    let st = &mut solids.solver;
    st.lo.clear();
    st.hi.clear();
    st.moves.clear();
    st.basis.clear();
    for (b, shape) in solids.bodies.iter().zip(&solids.shapes) {
        // `Body::origin`, with the rotation made ready once for the solid's every point.
        let basis = S::basis(b.q);
        let origin = b.c - S::rotate_by(basis, b.com);
        let (lo, hi) = S::aabb(shape, origin, b.q, margin / 2.0);
        st.lo.push(lo);
        st.hi.push(hi);
        st.moves.push(b.kind == Kind::Dynamic);
        st.basis.push((basis, origin));
    }
    broad::pairs(&st.lo, &st.hi, &st.moves, &mut st.order, &mut st.pairs);
    if !solids.no_collide.is_empty() {
        // Solids joined by a joint do not collide (unless the joint says they do).
        st.pairs.retain(|p| solids.no_collide.binary_search(p).is_err());
    }
    st.points.clear();
    st.contacts.clear();
    st.touching.clear();
    for &(a, b) in &st.pairs {
        let (ba, bb) = (&solids.bodies[a as usize], &solids.bodies[b as usize]);
        let ((qa, oa), (qb, ob)) = (st.basis[a as usize], st.basis[b as usize]);
        st.touches.clear();
        S::touches(
            (&solids.shapes[a as usize], oa, ba.q),
            (&solids.shapes[b as usize], ob, bb.q),
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
            let frame = S::frame(t.normal);
            let apart = S::rotate_by(qb, anchor_b) + bb.c - S::rotate_by(qa, anchor_a) - ba.c;
            let mut slip = [0.0; 2];
            for k in 0..S::TANGENTS {
                slip[k] = apart.dot(S::tangent(t.normal, frame, k));
            }
            st.points.push(Point {
                normal: t.normal,
                frame,
                ra,
                rb,
                adjusted: t.separation - (rb - ra).dot(t.normal),
                normal_mass: 0.0,
                tangent_mass: [0.0; 2],
                normal_impulse: ni,
                tangent_impulse: ti,
                max_normal: 0.0,
                approach: 0.0,
                slip,
            });
            st.contacts.push(Contact {
                a,
                b,
                id: t.id,
                normal: t.normal,
                depth: -t.separation,
                at,
                total_normal: 0.0,
                total_friction: 0.0,
                anchor_a,
                anchor_b,
            });
        }
        st.touching.push(Pair {
            a,
            b,
            start: start as u32,
            end: st.points.len() as u32,
            friction,
            restitution,
            rigid_other: ba.kind != Kind::Dynamic || bb.kind != Kind::Dynamic,
            soft: Coefs::default(),
        });
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
    st.sweeps.record(&solids.bodies);
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
    for pair in &mut st.touching {
        pair.soft = Coefs::of(if pair.rigid_other { rigid } else { soft });
        let (ma, mb) = (&st.motion[pair.a as usize], &st.motion[pair.b as usize]);
        for p in &mut st.points[pair.start as usize..pair.end as usize] {
            p.normal_mass = effective_mass(ma, mb, p.ra, p.rb, p.normal);
            for k in 0..S::TANGENTS {
                p.tangent_mass[k] = effective_mass(ma, mb, p.ra, p.rb, S::tangent(p.normal, p.frame, k));
            }
            p.approach = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
        }
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
            solve::<S, true>(st, inv_h, set.push_speed, gravity);
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
            solve::<S, false>(st, inv_h, set.push_speed, gravity);
        }
        // The impulse a point applies in a substep is its accumulated impulse (the warm
        // start and the increments): the step's is their sum.
        for (p, c) in st.points.iter().zip(&mut st.contacts) {
            c.total_normal += p.normal_impulse;
            c.total_friction += S::friction_size(p.tangent_impulse);
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
    // Continuous collision: fast solids put back to where they first met a static or
    // kinematic solid (toi.rs).
    let (touching, points, motion) = (&st.touching, &st.points, &st.motion);
    if set.continuous {
        st.sweeps.advance(
            &mut solids.bodies,
            &solids.shapes,
            &solids.no_collide,
            set.speculative_distance,
            (dt, h),
            gravity,
            |i| joints.iter().any(|j| j.joins(i)),
            |a, b| touching.binary_search_by(|p| (p.a, p.b).cmp(&(a, b))).is_ok(),
            |i, back, moved, slop| room(touching, points, motion, i, back, moved, slop),
        );
    }
    let rolled = &st.sweeps.rolled;
    for &i in rolled {
        st.motion[i as usize].dp = st.sweeps.moved(i as usize, solids.bodies[i as usize].c);
    }
    st.warm.clear();
    for pair in &st.touching {
        let range = pair.start as usize..pair.end as usize;
        for (p, c) in st.points[range.clone()].iter().zip(&mut st.contacts[range]) {
            let t = p.tangent_impulse;
            let sliding = S::friction_size(t) >= 0.999 * pair.friction * p.normal_impulse;
            let put_back = !rolled.is_empty()
                && (rolled.binary_search(&c.a).is_ok() || rolled.binary_search(&c.b).is_ok());
            if sliding || p.normal_impulse == 0.0 || put_back {
                // Sliding (or not pressed, or put back by continuous collision): static
                // friction lets go, and takes hold again where the point is now.
                let (ba, bb) = (&solids.bodies[c.a as usize], &solids.bodies[c.b as usize]);
                let at = c.at + (st.motion[c.a as usize].dp + st.motion[c.b as usize].dp) * 0.5;
                (c.anchor_a, c.anchor_b) = (S::unrotate(ba.q, at - ba.c), S::unrotate(bb.q, at - bb.c));
            }
            st.warm.push(Warm {
                key: (c.a, c.b, c.id),
                normal: p.normal_impulse,
                tangent: t,
                anchor_a: c.anchor_a,
                anchor_b: c.anchor_b,
            });
        }
    }
    // The points come in pair order, so the keys usually are in order already.
    if !st.warm.is_sorted_by_key(|w| w.key) {
        st.warm.sort_unstable_by_key(|w| w.key);
    }
    st.warm.dedup_by(|x, y| x.key == y.key);
}

/// How far (a fraction `u` of `back`, 0 to 1) solid `i` may be moved back from where it is
/// without closing a contact point it has with a dynamic solid deeper than that point is now
/// (or than touching) by more than `slop`: continuous collision puts a solid back no farther
/// (toi.rs). `moved(j)`: how far solid `j` is from where the step began (a solid put back
/// already is where it was put). The points are this step's, found when it began; a pair
/// that was not then is not looked at. Each point's separation is linear in `u`.
fn room<S: Space>(
    touching: &[Pair],
    points: &[Point<S>],
    motion: &[Motion<S>],
    i: usize,
    back: S::V,
    moved: &dyn Fn(usize) -> S::V,
    slop: f64,
) -> f64 {
    let mut u = 1.0_f64;
    for pair in touching {
        let (a, b) = (pair.a as usize, pair.b as usize);
        if a != i && b != i {
            continue;
        }
        let other = if a == i { b } else { a };
        if !motion[other].moves {
            continue;
        }
        // The separation changes by `u * back . n` where `i` is `b`, by `-u * back . n` where
        // it is `a`.
        let sign = if a == i { -1.0 } else { 1.0 };
        for p in &points[pair.start as usize..pair.end as usize] {
            let rate = sign * back.dot(p.normal);
            if rate >= 0.0 {
                continue;
            }
            let (ta, tb) = (S::rotate_delta(motion[a].dq, p.ra), S::rotate_delta(motion[b].dq, p.rb));
            let sep = (moved(b) + tb - moved(a) - ta).dot(p.normal) + p.adjusted;
            let floor = sep.min(0.0) - slop;
            u = u.min(((floor - sep) / rate).max(0.0));
        }
    }
    u
}

#[allow(clippy::needless_range_loop)] // k indexes a point's tangents and impulses alike
fn warm_start<S: Space>(st: &mut State<S>) {
    for pair in &st.touching {
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

/// One pass over every pair: normal impulses, then friction, with the soft bias (`BIAS`,
/// the solve) or without it (the relax pass). The two solids' motions are held in
/// registers over the pair's points and stored once. `gravity` is what the bounce of a point
/// still apart gains on its way across the gap ([`arrival`]).
#[allow(clippy::needless_range_loop)] // k indexes a point's tangents, masses and impulses alike
fn solve<S: Space, const BIAS: bool>(st: &mut State<S>, inv_h: f64, push_speed: f64, gravity: S::V) {
    for pair in &st.touching {
        let (ia, ib) = (pair.a as usize, pair.b as usize);
        let (mut ma, mut mb) = (st.motion[ia], st.motion[ib]);
        let c = pair.soft;
        let points = &mut st.points[pair.start as usize..pair.end as usize];
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
            let vn = relative_velocity(&ma, &mb, p.ra, p.rb).dot(p.normal);
            if BIAS && pair.restitution > 0.0 {
                // The speed a bouncing point arrives at: gravity keeps adding to it over the
                // step's substeps until the contact stops it (the step's start undercounts
                // it by up to g dt, a few % of a bounce's height), and across the gap it
                // still has to close (the speculative contact stops it at the surface).
                let fall = |m: &Motion<S>| if m.moves { gravity } else { S::V::default() };
                let closing = -(fall(&mb) - fall(&ma)).dot(p.normal);
                p.approach = p.approach.min(arrival(vn, sep, closing, 1.0 / inv_h));
            }
            let imp = -p.normal_mass * (mass_scale * vn + vbias) - impulse_scale * p.normal_impulse;
            let new = (p.normal_impulse + imp).max(0.0);
            let imp = new - p.normal_impulse;
            p.normal_impulse = new;
            p.max_normal = p.max_normal.max(imp);
            push(&mut ma, &mut mb, p.ra, p.rb, p.normal * imp);
        }
        for p in points.iter_mut() {
            let limit = pair.friction * p.normal_impulse;
            let dv = relative_velocity(&ma, &mb, p.ra, p.rb);
            let mut new = [0.0; 2];
            // With the bias, static friction pulls the anchors back together as softly as a
            // contact pushes (so a box on a ramp steeper than it can slide on does not
            // creep); without it, friction stops the sliding velocity. The arms are turned
            // again as the normal solve turned them (no solid turns between the two).
            let moved = if BIAS {
                let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
                mb.dp + tb - p.rb - ma.dp - ta + p.ra
            } else {
                S::V::default()
            };
            for k in 0..S::TANGENTS {
                let t = S::tangent(p.normal, p.frame, k);
                let vt = dv.dot(t);
                new[k] = if BIAS {
                    let err = p.slip[k] + moved.dot(t);
                    let vbias = (c.bias * err).clamp(-push_speed, push_speed);
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
            push(&mut ma, &mut mb, p.ra, p.rb, imp);
        }
        (st.motion[ia].v, st.motion[ia].w) = (ma.v, ma.w);
        (st.motion[ib].v, st.motion[ib].w) = (mb.v, mb.w);
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
fn restitution<S: Space>(st: &mut State<S>, threshold: f64) {
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
