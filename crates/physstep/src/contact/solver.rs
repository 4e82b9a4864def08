//! Contact solvers, chosen by name ([`super::SOLVERS`]; a solver is one `step` and an [`super::Info`], as
//! the integrators are), on the points `collide` (`points.rs`, shared by every solver) finds
//! at the step's start. Six schedules of the same passes ([`super::Schedule`], each laid out
//! by a `Plan` that makes `2 x substeps x iterations` passes a step, counted in
//! `State::passes`): PGS (one step of rigid passes with a Baumgarte bias), PGS with NGS (rigid
//! passes, then position passes after the drift, `ngs`), soft PGS (one step of soft solve and
//! relax passes), sticky TGS (substeps of one rigid pass on the separation as it is now, no
//! warm start, relax passes at the end), Jacobi (soft PGS's plan, each pass solved from the
//! velocities of its start with the masses split among a solid's pairs, `solve_jacobi`), and
//! the default, Box2D v3's soft step (Catto, "Solver2D", 2024):
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

use super::passes::{colour, ngs, restitution, solve, solve_jacobi, split_mass, warm_start, BAUMGARTE};
use super::points::{
    collide, effective_mass, relative_velocity, Coefs, Motion, Pair, Point, Soft, State, Warm,
};
use super::space::{Space, Vect};
use super::{joint, lanes, Kind, Schedule, Solids};

/// Sticky TGS's Baumgarte fraction of the separation a substep, and its static friction's
/// fraction of the anchors' distance (Solver2D's `solve_tgs_sticky.c`).
const STICKY_BETA: f64 = 0.8;
const STICKY_FRICTION_BETA: f64 = 0.5;

/// How a schedule solves its joints (each solver in its own form).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Joints {
    /// Soft rows (the joint's `joint_hertz`, at most this fraction of the substep rate).
    Soft(f64),
    /// Rigid rows with a Baumgarte bias of this fraction of the error a step (PGS).
    Baumgarte(f64),
    /// Rigid rows without a bias, then position passes after the drift that move the jointed
    /// solids back together (NGS: Box2D v2.4 solves its joints' positions with its contacts').
    Ngs,
}

impl Default for Joints {
    fn default() -> Self {
        Self::Soft(0.25)
    }
}

/// The coefficients a schedule gives its contacts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
enum Contacts {
    /// Soft contacts whose static friction holds anchors (the soft step).
    #[default]
    Soft,
    /// Soft contacts with plain Coulomb friction (Solver2D's soft PGS and Jacobi).
    SoftPlain,
    /// Rigid contacts with a Baumgarte bias of this fraction of the overlap a step, plain
    /// friction (PGS; 0 for PGS with NGS).
    Baumgarte(f64),
    /// Rigid contacts with sticky TGS's bias and friction anchors.
    Sticky,
}

/// How a schedule lays out a step's passes.
#[derive(Debug, Clone, Copy, Default)]
struct Plan {
    /// Substeps.
    n: u32,
    /// Solve passes (with the bias) a substep.
    solves: u32,
    /// Relax passes (without it) a substep, after the drift.
    relaxes: u32,
    /// NGS position passes a substep, after the drift.
    positions: u32,
    /// Relax passes after the last substep only.
    last_relaxes: u32,
    /// The contacts' impulses start from zero and accumulate over the substeps (no warm start
    /// from the last step, none applied again each substep).
    carry: bool,
    /// Jacobi passes instead of Gauss-Seidel ones.
    jacobi: bool,
    /// The contacts' stiffness at most this fraction of the substep rate, Hz (soft schedules).
    hertz_cap: f64,
    /// The contacts' coefficients.
    contacts: Contacts,
    /// The joints' form.
    joints: Joints,
}

impl Plan {
    /// The layout of `schedule` for `substeps` and `iterations`: every schedule makes `all =
    /// 2 x substeps x iterations` passes over the contacts a step (equal cost). None for
    /// XPBD, whose step is its own (`xpbd.rs`).
    fn of(schedule: Schedule, substeps: u32, iterations: u32) -> Option<Self> {
        let all = 2 * substeps.max(1) * iterations;
        let quarter = (all / 4).max(1);
        let one_step = Self { n: 1, ..Self::default() };
        Some(match schedule {
            Schedule::SoftStep => Self {
                n: substeps.max(1),
                solves: iterations,
                relaxes: iterations,
                hertz_cap: 0.125,
                ..Self::default()
            },
            Schedule::Pgs => Self {
                solves: all,
                contacts: Contacts::Baumgarte(BAUMGARTE),
                joints: Joints::Baumgarte(BAUMGARTE),
                ..one_step
            },
            Schedule::PgsNgs => Self {
                solves: all - quarter,
                positions: quarter,
                contacts: Contacts::Baumgarte(0.0),
                joints: Joints::Ngs,
                ..one_step
            },
            Schedule::SoftPgs => Self {
                solves: all / 2,
                relaxes: all / 2,
                hertz_cap: 0.5,
                contacts: Contacts::SoftPlain,
                joints: Joints::Soft(0.5),
                ..one_step
            },
            Schedule::Jacobi => Self {
                solves: all / 2,
                relaxes: all / 2,
                hertz_cap: 1.0 / 3.0,
                jacobi: true,
                contacts: Contacts::SoftPlain,
                joints: Joints::Soft(0.5),
                ..one_step
            },
            Schedule::TgsSticky => Self {
                n: all - quarter,
                solves: 1,
                last_relaxes: quarter,
                carry: true,
                contacts: Contacts::Sticky,
                ..Self::default()
            },
            Schedule::Xpbd | Schedule::Projection => return None,
        })
    }
}

/// What every solver does before its passes, for substeps of `h`: the contacts found
/// (`collide`), the joints' arms and frames, continuous collision's start poses, and each
/// solid's motion (its velocities, no motion yet; the world's, for joints to it, last).
pub(super) fn begin<S: Space>(solids: &mut Solids<S>, h: f64) {
    collide(solids);
    joint::prepare(&mut solids.joints, &solids.bodies, h);
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
    if !solids.joints.is_empty() {
        // The world, for joints to it: the last motion, which never moves.
        st.motion.push(Motion::fixed());
    }
}

/// One step of the chosen solver ([`Schedule`], laid out by [`Plan`]); XPBD's is its own
/// (`xpbd.rs`), on the same [`begin`] and [`finish`].
pub(crate) fn step<S: Space>(solids: &mut Solids<S>, dt: f64, gravity: S::V) {
    let set = solids.settings.clone();
    // The soft step: substeps of one solve pass, a drift and one relax pass each (times
    // `iterations`); the one-step schedules: as many passes in one step as the soft step
    // makes in all; sticky TGS: as many substeps of one pass, a quarter of them kept for the
    // relax passes at the end.
    // XPBD and the Verlet projection: xpbd.rs.
    let Some(plan) = Plan::of(set.schedule(), set.substeps, set.iterations) else {
        super::xpbd::step(solids, dt, gravity);
        return;
    };
    let n = plan.n;
    let h = dt / f64::from(n);
    let inv_h = 1.0 / h;
    begin(solids, h);
    let hertz = set.contact_hertz.min(plan.hertz_cap / h);
    let (soft, rigid) =
        (Soft::new(hertz, set.damping_ratio, h), Soft::new(2.0 * hertz, set.damping_ratio, h));
    let joint_soft = match plan.joints {
        Joints::Soft(cap) => Soft::new(set.joint_hertz.min(cap / h), set.joint_damping_ratio, h),
        Joints::Baumgarte(beta) => Soft { bias_rate: beta * inv_h, mass_scale: 1.0, impulse_scale: 0.0 },
        Joints::Ngs => Soft { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0 },
    };
    let joints = &mut solids.joints;
    let st = &mut solids.solver;
    if plan.jacobi {
        // Each solid's share of the pairs it is in (mass splitting, below).
        st.shares.clear();
        st.shares.resize(st.motion.len(), 0.0);
        for pair in &st.touching {
            st.shares[pair.a as usize] += 1.0;
            st.shares[pair.b as usize] += 1.0;
        }
    }
    for pair in &mut st.touching {
        let k = if pair.rigid_other { rigid } else { soft };
        pair.soft = match plan.contacts {
            Contacts::Soft => Coefs::of(k),
            Contacts::SoftPlain => Coefs { friction_bias: 0.0, ..Coefs::of(k) },
            Contacts::Baumgarte(beta) => Coefs::baumgarte(beta, inv_h),
            Contacts::Sticky => Coefs::sticky(STICKY_BETA, STICKY_FRICTION_BETA, inv_h),
        };
        let (ma, mb) = (&st.motion[pair.a as usize], &st.motion[pair.b as usize]);
        let shares = plan.jacobi.then(|| (st.shares[pair.a as usize], st.shares[pair.b as usize]));
        for p in &mut st.points[pair.start as usize..pair.end as usize] {
            let mass = |d| match shares {
                None => effective_mass(ma, mb, p.ra, p.rb, d),
                Some(n) => split_mass(ma, mb, p.ra, p.rb, d, n),
            };
            p.normal_mass = mass(p.normal);
            for k in 0..S::TANGENTS {
                p.tangent_mass[k] = mass(S::tangent(p.normal, p.frame, k));
            }
            p.approach = relative_velocity(ma, mb, p.ra, p.rb).dot(p.normal);
            if plan.carry {
                p.normal_impulse = 0.0;
                p.tangent_impulse = [0.0; 2];
            }
        }
    }

    // The order of the warm start and the Gauss-Seidel passes, and their four-lane form
    // (lanes/; Jacobi's passes take the pairs as they come).
    colour(st);
    if !plan.jacobi {
        lanes::pack(st);
    } else {
        st.lanes = false;
    }
    let mut bodies = std::mem::take(&mut solids.bodies);
    st.passes = 0;
    let pass = |st: &mut State<S>, bias: bool| match (plan.jacobi, bias) {
        (false, true) => solve::<S, true>(st, inv_h, set.push_speed, gravity),
        (false, false) => solve::<S, false>(st, inv_h, set.push_speed, gravity),
        (true, true) => solve_jacobi::<S, true>(st, inv_h, set.push_speed, gravity),
        (true, false) => solve_jacobi::<S, false>(st, inv_h, set.push_speed, gravity),
    };
    for substep in 0..n {
        let last = substep + 1 == n;
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
        if !plan.carry {
            warm_start(st);
        }
        for _ in 0..plan.solves {
            if !joints.is_empty() {
                joint::solve(joints, &mut st.motion, h, Some(joint_soft));
            }
            pass(st, true);
            st.passes += 1;
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
        for _ in 0..plan.positions {
            ngs(st, &mut bodies);
            st.passes += 1;
        }
        let relaxes = plan.relaxes + if last { plan.last_relaxes } else { 0 };
        for _ in 0..relaxes {
            if !joints.is_empty() {
                joint::solve(joints, &mut st.motion, h, None);
            }
            pass(st, false);
            st.passes += 1;
        }
        // The impulse a point applies in a substep is its accumulated impulse (the warm
        // start and the increments): the step's is their sum. Carried over the substeps,
        // the accumulated impulse is the step's.
        if (!plan.carry || last) && !lanes::accumulate(st) {
            for (p, c) in st.points.iter().zip(&mut st.contacts) {
                c.total_normal += p.normal_impulse;
                c.total_friction += S::friction_size(p.tangent_impulse);
            }
        }
    }
    lanes::unpack(st);
    restitution(st, set.restitution_threshold);
    // NGS's joint passes (its quarter of the passes), before the world's own projection.
    if plan.joints == Joints::Ngs && !joints.is_empty() {
        joint::project(joints, &mut bodies, plan.positions);
    }
    finish(solids, bodies, dt, h, gravity);
}

/// What every solver does after its passes (substeps of `h` in a step of `dt`), `bodies`
/// being the solids as the passes left them (the velocities in the motions): the optional
/// joint projection, the velocities written back, continuous collision, and the warm starts
/// and friction anchors kept for the next step.
pub(super) fn finish<S: Space>(
    solids: &mut Solids<S>,
    mut bodies: Vec<super::Body<S>>,
    dt: f64,
    h: f64,
    gravity: S::V,
) {
    let set = &solids.settings;
    let joints = &mut solids.joints;
    let st = &mut solids.solver;
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
    // Each solid's turn back is made ready once, for the points that take hold again (an
    // unpressed speculative point does every step: two `sin_cos` a point in the plane).
    st.unbasis.clear();
    st.unbasis.resize(solids.bodies.len(), None);
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
                let ua = *st.unbasis[c.a as usize].get_or_insert_with(|| S::unbasis(ba.q));
                let ub = *st.unbasis[c.b as usize].get_or_insert_with(|| S::unbasis(bb.q));
                (c.anchor_a, c.anchor_b) = (S::rotate_by(ua, at - ba.c), S::rotate_by(ub, at - bb.c));
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
    // One warm start a point, in pair order (the pairs sorted by `(a, b)`): sorting each
    // pair's few points by their ids sorts them all (the ids of a pair's points are distinct,
    // so the order is the one a sort of the whole gives; that sort took 3-5% of the 20-row
    // pyramid's step, its pairs' two points seldom in id order).
    for pair in &st.touching {
        st.warm[pair.start as usize..pair.end as usize].sort_by_key(|w| w.key);
    }
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
