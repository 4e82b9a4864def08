//! The contact points every contact solver works on, and what finds them: the pairs of
//! solids in contact and their points (arms, normal, effective masses, impulses, the warm
//! start matched by feature id), each solid's motion during a step, the memory a step leaves
//! for the next (warm starts), and `collide`, the broad and narrow phases that make them at the
//! start of a step. How a solver then moves the solids is its own file ([`super::solver`]).
//! Also the soft-constraint coefficients ([`Soft`]) the contacts and the joints share.

use super::space::{Space, Touch, Vect};
use super::{broad, ContactReport, Kind, Solids};

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
pub(super) struct Coefs {
    /// `mass_scale * bias_rate` (the product the bias is made of, taken once).
    pub(super) bias: f64,
    pub(super) mass_scale: f64,
    pub(super) impulse_scale: f64,
    /// The bias with which static friction pulls a point's anchors back together (0: friction
    /// only stops the sliding velocity).
    pub(super) friction_bias: f64,
}

impl Coefs {
    /// A soft contact's, whose static friction holds its anchors as softly as it pushes.
    pub(super) fn of(k: Soft) -> Self {
        let bias = k.mass_scale * k.bias_rate;
        Self { bias, mass_scale: k.mass_scale, impulse_scale: k.impulse_scale, friction_bias: bias }
    }

    /// A rigid contact's with a Baumgarte bias of `beta / h` (the fraction `beta` of the
    /// overlap removed a step), plain friction.
    pub(super) fn baumgarte(beta: f64, inv_h: f64) -> Self {
        Self { bias: beta * inv_h, mass_scale: 1.0, impulse_scale: 0.0, friction_bias: 0.0 }
    }

    /// A rigid contact's with a Baumgarte bias of `beta / h` whose static friction pulls the
    /// anchors together by `friction_beta / h` of their distance a step (sticky friction).
    pub(super) fn sticky(beta: f64, friction_beta: f64, inv_h: f64) -> Self {
        Self { friction_bias: friction_beta * inv_h, ..Self::baumgarte(beta, inv_h) }
    }
}

/// Two solids in contact: what their points share, and where the points are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Pair {
    pub(super) a: u32,
    pub(super) b: u32,
    /// The points: `points[start..end]` (and `contacts[start..end]`).
    pub(super) start: u32,
    pub(super) end: u32,
    pub(super) friction: f64,
    pub(super) restitution: f64,
    /// Against a static or kinematic solid: the stiffer softness.
    pub(super) rigid_other: bool,
    /// The softness of this step's substeps (the stiffer one where `rigid_other`).
    pub(super) soft: Coefs,
}

/// One contact point as the passes solve it: what they read and write, kept together and
/// apart from what they do not ([`Contact`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Point<S: Space> {
    pub(super) normal: S::V,
    /// The tangents (kept in space; the normal turned a quarter in the plane).
    pub(super) frame: S::Frame,
    pub(super) ra: S::V,
    pub(super) rb: S::V,
    /// Separation minus the arms' part, so that the separation now is
    /// `(dp_b + dq_b rb - dp_a - dq_a ra) . n + adjusted`.
    pub(super) adjusted: f64,
    pub(super) normal_mass: f64,
    pub(super) tangent_mass: [f64; 2],
    pub(super) normal_impulse: f64,
    pub(super) tangent_impulse: [f64; 2],
    pub(super) max_normal: f64,
    /// The fastest closing normal speed of the step before the contact acted (negative:
    /// closing): at the step's start, or in a substep's solve.
    pub(super) approach: f64,
    /// How far the anchors had slid apart along each tangent when the step began.
    pub(super) slip: [f64; 2],
}

/// What the passes do not read of a contact point: what it reports, and what it carries to
/// the next step besides its impulses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Contact<S: Space> {
    pub(super) a: u32,
    pub(super) b: u32,
    pub(super) id: u64,
    pub(super) normal: S::V,
    pub(super) depth: f64,
    pub(super) at: S::V,
    pub(super) total_normal: f64,
    pub(super) total_friction: f64,
    /// Where the point first touched, in each body's frame about its centre of mass: static
    /// friction holds the two together (kept while the point sticks, moved when it slides).
    pub(super) anchor_a: S::V,
    pub(super) anchor_b: S::V,
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
    pub(super) key: (u32, u32, u64),
    pub(super) normal: f64,
    pub(super) tangent: [f64; 2],
    pub(super) anchor_a: S::V,
    pub(super) anchor_b: S::V,
}

/// The solver's memory between steps (last step's impulses for warm starting, the latest
/// contacts for reports) and scratch.
#[derive(Debug, Clone)]
pub(crate) struct State<S: Space> {
    /// The latest step's contact points as the passes solve them (scratch between steps:
    /// the next step finds them again).
    pub(super) points: Vec<Point<S>>,
    /// The same points' reports and anchors (kept between steps).
    pub(super) contacts: Vec<Contact<S>>,
    /// The pairs in contact and their points (scratch between steps).
    pub(super) touching: Vec<Pair>,
    /// Last step's impulses and friction anchors by `(a, b, id)`, sorted.
    pub(super) warm: Vec<Warm<S>>,
    pub(super) order: Vec<u32>,
    pub(super) lo: Vec<[f64; 3]>,
    pub(super) hi: Vec<[f64; 3]>,
    pub(super) moves: Vec<bool>,
    /// Each solid's orientation made ready to turn vectors, and its shape's origin.
    pub(super) basis: Vec<(S::Basis, S::V)>,
    /// Each solid's turn back made ready (`Space::unbasis`), once asked for in a step's end
    /// (scratch, `solver::finish`).
    pub(super) unbasis: Vec<Option<S::Basis>>,
    pub(super) pairs: Vec<(u32, u32)>,
    pub(super) touches: Vec<Touch<S::V>>,
    pub(super) motion: Vec<Motion<S>>,
    /// The pairs (indices into `touching`) in the order the Gauss-Seidel passes take them:
    /// by colour, no two pairs of a colour sharing a solid that moves (scratch, `colour`).
    pub(super) coloured: Vec<u32>,
    /// Where each colour's pairs end in `coloured` (scratch, `colour`).
    pub(super) colour_ends: Vec<u32>,
    /// Whether the last colour in `colour_ends` is the one whose pairs share solids.
    pub(super) shared_last: bool,
    /// The colours each solid's pairs took so far, a bit each, and each pair's colour
    /// (scratch, `colour`).
    pub(super) colours: Vec<u64>,
    pub(super) pair_colour: Vec<u8>,
    /// The points packed four pairs at a time for the plane's vector passes (scratch,
    /// `lanes/`), and whether this step's are.
    pub(super) quads: Vec<super::lanes::Quad>,
    pub(super) quads3: Vec<super::lanes::Quad3>,
    pub(super) slots3: Vec<super::lanes::Slot3>,
    pub(super) lanes: bool,
    /// The passes over the contacts the latest step made (solve, relax and position passes,
    /// counted as they ran).
    pub(super) passes: u32,
    /// A Jacobi pass's motions as the pass began (scratch).
    pub(super) pass_start: Vec<Motion<S>>,
    /// A Jacobi pass's count of pairs each solid is in (scratch).
    pub(super) shares: Vec<f64>,
    /// The position-based solvers' poses of a substep's start and each point's position
    /// impulses (scratch, `xpbd.rs`).
    pub(super) substep_start: Vec<(S::V, S::Delta)>,
    pub(super) lambda: Vec<[f64; 2]>,
    /// Continuous collision's poses of the step's start (toi.rs).
    pub(super) sweeps: super::toi::Sweeps<S>,
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
            unbasis: Vec::new(),
            pairs: Vec::new(),
            touches: Vec::new(),
            motion: Vec::new(),
            coloured: Vec::new(),
            colour_ends: Vec::new(),
            shared_last: false,
            colours: Vec::new(),
            pair_colour: Vec::new(),
            quads: Vec::new(),
            quads3: Vec::new(),
            slots3: Vec::new(),
            lanes: false,
            passes: 0,
            pass_start: Vec::new(),
            shares: Vec::new(),
            substep_start: Vec::new(),
            lambda: Vec::new(),
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
pub(super) fn collide<S: Space>(solids: &mut Solids<S>) {
    let margin = solids.settings.speculative_distance;
    let st = &mut solids.solver;
    st.lo.clear();
    st.hi.clear();
    st.moves.clear();
    st.basis.clear();
    st.points.clear();
    st.contacts.clear();
    st.touching.clear();
    if !solids.bodies.iter().any(|b| b.kind == Kind::Dynamic) {
        // Nothing moves (every solid static, kinematic or asleep): no contact.
        st.pairs.clear();
        return;
    }
    for (b, shape) in solids.bodies.iter().zip(&solids.shapes) {
        // `Body::origin`, with the rotation made ready once for the solid's every point.
        let basis = S::basis(b.q);
        let origin = b.c - S::rotate_by(basis, b.com);
        let (lo, hi) = S::aabb(shape, origin, basis, margin / 2.0);
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
    // The last step's warm starts are sorted by `(a, b, id)` with no key twice, and the pairs
    // come sorted by `(a, b)`: each pair's are the block a cursor reaches next, found by a
    // walk of both lists rather than a binary search a point (the same entries: 6% of the
    // 20-row pyramid's step at 3 substeps went to those searches).
    let mut cursor = 0;
    for &(a, b) in &st.pairs {
        while st.warm.get(cursor).is_some_and(|w| (w.key.0, w.key.1) < (a, b)) {
            cursor += 1;
        }
        let block = st.warm[cursor..].iter().take_while(|w| (w.key.0, w.key.1) == (a, b)).count();
        let warm = &st.warm[cursor..cursor + block];
        let (ba, bb) = (&solids.bodies[a as usize], &solids.bodies[b as usize]);
        let ((qa, oa), (qb, ob)) = (st.basis[a as usize], st.basis[b as usize]);
        st.touches.clear();
        S::touches(
            (&solids.shapes[a as usize], oa, qa),
            (&solids.shapes[b as usize], ob, qb),
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
            let (ni, ti, anchor_a, anchor_b) = match warm.iter().find(|w| w.key.2 == t.id) {
                Some(w) => (w.normal, w.tangent, w.anchor_a, w.anchor_b),
                None => (0.0, [0.0; 2], S::unrotate(ba.q, ra), S::unrotate(bb.q, rb)),
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
