//! The position-based contact solvers: `projection` (the notes' Verlet position projection,
//! one step of the position passes below without the velocity pass: `step`'s doc) and `xpbd`,
//! rigid-body XPBD (Mueller, Macklin, Chentanez, Jeschke, Lee, Macklin: "Detailed Rigid Body
//! Simulation with Extended Position Based Dynamics", 2020), with one position pass a substep
//! as the paper recommends:
//!
//! ```text
//! begin       as every solver (solver.rs): the contact points found once, with their arms
//!             and the separation kept current by the solids' motion since the step began
//! substep     h = dt / (substeps x solver_iterations), that many times:
//!   integrate   v += h (g + forces), the gyroscopic term in space; the joints the xpbd
//!               form does not cover: their rows with the soft bias (joint/rows.rs)
//!   drift       the pose kept; x += h v, the orientation turned by h w
//!   positions   the joints in xpbd form (joint/positions.rs); then each contact point that
//!               overlaps: the overlap removed (at most `push_speed` h of it) by a position
//!               impulse lambda_n = -c / (w_a + w_b), w = 1/m + (r x n) . I^-1 (r x n)
//!               (compliance 0); then static friction:
//!               the point's anchors' tangential distance taken back by a position impulse
//!               lambda_t of at most mu lambda_n
//!   velocities  v = dx / h, w from the orientation's change over h
//!   velocity    each point the position pass pushed: the normal speed set to -e times the
//!               normal speed before the position pass where that closed faster than
//!               `restitution_threshold`, to 0 otherwise; dynamic friction: the tangential
//!               speed taken away by an impulse of at most mu times the substep's normal
//!               impulse (lambda_n / h and this one), less lambda_t / h; then the other
//!               joints' rows without the bias
//! finish      as every solver (solver.rs): the optional joint projection, continuous
//!             collision, the warm starts and friction anchors kept
//! ```
//!
//! What differs from the paper:
//!
//! - The contacts are found once a step (as the paper's broad phase is; its narrow phase runs
//!   each substep), so a point's separation is the shared preparation's, `(dp_b + q_b rb -
//!   dp_a - q_a ra) . n + adjusted`, on the step's start's normal; the inverse inertias are
//!   the step's start's.
//! - At most `push_speed` h of an overlap is removed a substep (the settings' push speed, the
//!   soft step's cap on its bias): a solid that came deeper than the speculative distance in
//!   a step (a jointed link whipped into the ground: jointed solids are not swept by
//!   continuous collision) is pushed out at that speed. Removed in one substep, its `v = dx /
//!   h` threw it: the ball-chain at 32 substeps tore apart (5 m) after a link came 0.77 m into
//!   the ground.
//! - Static friction: the paper removes the points' tangential motion since the substep
//!   began, all of it where its lambda_t is below mu_s lambda_n, none of it above. Measured,
//!   that lets a box resting on the ground creep at 5 mm/s (each corner's normal correction
//!   turns the box and moves the other corner sideways, a substep at a time) and a box on a
//!   ramp steeper than its friction allows slip 7 cm in 5 s (the lighter, uphill corner
//!   cannot hold its half); here the distance is the anchors' (where the point first touched,
//!   kept while it sticks, as the soft step's static friction keeps them), and a point that
//!   cannot hold all of it holds mu lambda_n of it (the heavier point holds the rest).
//! - Dynamic friction bounds the friction impulse by mu times the substep's whole normal
//!   impulse, the position pass's lambda_n / h and the velocity pass's (the paper writes the
//!   bound as a velocity, `h mu_d |f_n|`, from lambda_n alone: measured, a box sliding down a
//!   ramp then accelerated 9% faster than g (sin a - mu cos a)), less what static friction
//!   took this substep. The normal speed is set first, then friction.
//! - One coefficient for static and dynamic friction (the pair's, as the other solvers take
//!   it).
//! - Orientations are turned exactly (the exponential map, `Space::turn`), not by the paper's
//!   linearised quaternion update.
//! - The joints in xpbd form are rigid (they have no compliance); a hinge with a limit or a
//!   motor, a slider, a spring or a rope and a soft weld keep their velocity rows
//!   (joint/positions.rs).
//! - No warm start (nothing to warm-start): a step's impulses are kept as a substep's mean,
//!   for a soft step that takes over. The reports' normal impulse is the step's: lambda_n / h
//!   summed over the substeps, and the velocity pass's normal impulses; the friction impulse
//!   the static lambda_t / h and the dynamic impulses summed.
//!
//! Equal cost: `2 x substeps x solver_iterations` passes a step, as the soft step makes:
//! `substeps x solver_iterations` substeps of one position pass and one velocity pass.

use super::points::{push, relative_velocity, Motion, Soft, State};
use super::space::{Space, Vect};
use super::{joint, solver, Body, Kind, Solids};

/// `1/m + (r x d) . I^-1 (r x d)`: how far a unit position impulse along `d` (unit) at arm `r`
/// moves that point along `d` (0 for a solid the solver does not move).
pub(crate) fn weight<S: Space>(m: &Motion<S>, r: S::V, d: S::V) -> f64 {
    if !m.moves {
        return 0.0;
    }
    let c = S::cross_vv(r, d);
    m.inv_mass + c.dot(S::apply(m.inv_i, c))
}

/// `u . I^-1 u`: how far a unit angular position impulse about `u` (unit) turns the solid
/// about `u` (0 for a solid the solver does not move).
pub(crate) fn angular_weight<S: Space>(m: &Motion<S>, u: S::W) -> f64 {
    if m.moves {
        u.dot(S::apply(m.inv_i, u))
    } else {
        0.0
    }
}

/// Moves a solid by the position impulse `p` at arm `arm`: its centre by `p / m`, its
/// orientation turned by `I^-1 (arm x p)` (a solid the solver does not move is left alone).
pub(crate) fn shift<S: Space>(b: &mut Body<S>, m: &mut Motion<S>, arm: S::V, p: S::V) {
    if !m.moves {
        return;
    }
    let d = p * m.inv_mass;
    b.c += d;
    m.dp += d;
    (b.q, m.dq) = S::turn(b.q, m.dq, S::apply(m.inv_i, S::cross_vv(arm, p)), 1.0);
}

/// Turns a solid by the angular position impulse `l`: by `I^-1 l`.
pub(crate) fn turn_by<S: Space>(b: &mut Body<S>, m: &mut Motion<S>, l: S::W) {
    if m.moves {
        (b.q, m.dq) = S::turn(b.q, m.dq, S::apply(m.inv_i, l), 1.0);
    }
}

/// The position impulse `p` at arms `ra` of `a` and `rb` of `b`: `-p` to `a`, `p` to `b`
/// (`a` may be the world, `bodies.len()`: a joint's, left alone).
pub(crate) fn apart<S: Space>(
    bodies: &mut [Body<S>],
    motion: &mut [Motion<S>],
    (a, b): (usize, usize),
    (ra, rb): (S::V, S::V),
    p: S::V,
) {
    if a < bodies.len() {
        shift(&mut bodies[a], &mut motion[a], ra, -p);
    }
    shift(&mut bodies[b], &mut motion[b], rb, p);
}

/// One step of the position-based solvers: xpbd (the module's doc: `substeps x iterations`
/// substeps of one position pass and one velocity pass) or the Verlet projection (one step of
/// `2 x substeps x iterations` position passes, the velocities the motion they leave: no
/// velocity pass, so no restitution and no friction beyond the position pass's).
pub(super) fn step<S: Space>(solids: &mut Solids<S>, dt: f64, gravity: S::V) {
    let set = solids.settings.clone();
    let m = set.substeps.max(1) * set.iterations.max(1);
    let projection = set.schedule() == super::Schedule::Projection;
    // (substeps, position passes a substep)
    let (n, passes) = if projection { (1, 2 * m) } else { (m, 1) };
    let h = dt / f64::from(n);
    let inv_h = 1.0 / h;
    solver::begin(solids, h);
    let joint_soft = Soft::new(set.joint_hertz.min(0.25 / h), set.joint_damping_ratio, h);
    joint::clear_positional(&mut solids.joints);
    // The joints that keep their velocity rows, solved apart (and put back after the step).
    let mut rows: Vec<_> = solids.joints.iter().filter(|j| !j.positional()).copied().collect();
    let st = &mut solids.solver;
    st.passes = 0;
    for p in &mut st.points {
        p.normal_impulse = 0.0;
        p.tangent_impulse = [0.0; 2];
    }
    let mut bodies = std::mem::take(&mut solids.bodies);
    // The scratch kept in the solver's state (no allocation a step once they have grown).
    let mut prev = std::mem::take(&mut st.substep_start);
    let mut lambda = std::mem::take(&mut st.lambda);
    lambda.clear();
    lambda.resize(st.points.len(), [0.0; 2]);
    for _ in 0..n {
        super::forces::integrate(&mut solids.forces, &bodies, &mut st.motion, h);
        for (b, m) in bodies.iter().zip(st.motion.iter_mut()) {
            if b.kind == Kind::Dynamic {
                m.v += gravity * h;
                m.w = S::gyroscopic(b.q, b.i_local, m.w, h);
            }
        }
        if !rows.is_empty() {
            joint::warm_start(&rows, &mut st.motion);
            joint::solve(&mut rows, &mut st.motion, h, Some(joint_soft));
        }
        approach(st);
        prev.clear();
        for (b, m) in bodies.iter_mut().zip(st.motion.iter_mut()) {
            prev.push((m.dp, m.dq));
            if b.kind == Kind::Static {
                continue;
            }
            b.c += m.v * h;
            m.dp += m.v * h;
            (b.q, m.dq) = S::turn(b.q, m.dq, m.w, h);
        }
        for _ in 0..passes {
            if !solids.joints.is_empty() {
                joint::solve_positions(&mut solids.joints, &mut st.motion, &mut bodies, h);
            }
            positions(st, &mut bodies, &mut lambda, inv_h, set.push_speed * h);
            st.passes += 1;
        }
        for ((b, m), &(dp, dq)) in bodies.iter().zip(st.motion.iter_mut()).zip(&prev) {
            if b.kind == Kind::Dynamic {
                m.v = (m.dp - dp) * inv_h;
                m.w = S::rotation_error(S::identity(), dq, m.dq) * inv_h;
            }
        }
        if !projection {
            velocities(st, &lambda, inv_h, set.restitution_threshold);
            st.passes += 1;
        }
        if !rows.is_empty() {
            joint::solve(&mut rows, &mut st.motion, h, None);
        }
    }
    for (j, r) in solids.joints.iter_mut().filter(|j| !j.positional()).zip(rows) {
        *j = r;
    }
    joint::average_positional(&mut solids.joints, n);
    let mean = 1.0 / f64::from(n);
    for p in &mut st.points {
        p.normal_impulse *= mean;
        p.tangent_impulse = [p.tangent_impulse[0] * mean, p.tangent_impulse[1] * mean];
    }
    (st.substep_start, st.lambda) = (prev, lambda);
    solver::finish(solids, bodies, dt, h, gravity);
}

/// Each point's normal speed before the substep's position pass (negative: closing), kept in
/// its `approach` for the velocity pass's restitution.
fn approach<S: Space>(st: &mut State<S>) {
    for pair in &st.touching {
        let (ma, mb) = (&st.motion[pair.a as usize], &st.motion[pair.b as usize]);
        for p in &mut st.points[pair.start as usize..pair.end as usize] {
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            p.approach = relative_velocity(ma, mb, ta, tb).dot(p.normal);
        }
    }
}

/// The position pass over the contact points: each overlap removed, then static friction
/// (the module's doc); `lambda[k]`: point `k`'s normal and friction position impulses (0
/// where apart).
fn positions<S: Space>(
    st: &mut State<S>,
    bodies: &mut [Body<S>],
    lambda: &mut [[f64; 2]],
    inv_h: f64,
    most: f64,
) {
    let State { touching, points, contacts, motion, .. } = st;
    for pair in touching.iter() {
        let ends = (pair.a as usize, pair.b as usize);
        for k in pair.start as usize..pair.end as usize {
            let (p, c) = (&mut points[k], &mut contacts[k]);
            lambda[k] = [0.0; 2];
            let n = p.normal;
            let (ma, mb) = (&motion[ends.0], &motion[ends.1]);
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            let sep = (mb.dp + tb - ma.dp - ta).dot(n) + p.adjusted;
            let w = weight(ma, ta, n) + weight(mb, tb, n);
            if !(sep < 0.0 && w > 0.0) {
                continue;
            }
            // At most `push_speed` h of the overlap a substep: a deep overlap (a solid that
            // came in farther than the speculative distance in a step) pushed out at that
            // speed, not in one substep (whose `v = dx / h` would throw it).
            let ln = -sep.max(-most) / w;
            lambda[k][0] = ln;
            p.normal_impulse += ln * inv_h;
            c.total_normal += ln * inv_h;
            apart(bodies, motion, ends, (ta, tb), n * ln);
            if pair.friction <= 0.0 {
                continue;
            }
            // Static friction: how far the points' anchors have slid apart across the normal
            // (as they had when the step began, and by the two points' motion since; the arms
            // turned as the normal correction left them), taken back by a position impulse of
            // at most mu lambda_n.
            let (ma, mb) = (&motion[ends.0], &motion[ends.1]);
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            let moved = mb.dp + tb - p.rb - ma.dp - ta + p.ra;
            let mut across = moved - n * moved.dot(n);
            for (k, slip) in p.slip.iter().enumerate().take(S::TANGENTS) {
                across += S::tangent(n, p.frame, k) * *slip;
            }
            let size = across.dot(across).sqrt();
            if size == 0.0 {
                continue;
            }
            let t = across * (1.0 / size);
            let wt = weight(ma, ta, t) + weight(mb, tb, t);
            if wt == 0.0 {
                continue;
            }
            let lt = (size / wt).min(pair.friction * ln);
            lambda[k][1] = lt;
            let imp = t * -lt;
            for (k, ti) in p.tangent_impulse.iter_mut().enumerate().take(S::TANGENTS) {
                *ti += imp.dot(S::tangent(n, p.frame, k)) * inv_h;
            }
            c.total_friction += lt * inv_h;
            apart(bodies, motion, ends, (ta, tb), imp);
        }
    }
}

/// The velocity pass over the points the position pass pushed (`lambda[k][0] > 0`): the
/// normal speed (restitution), then dynamic friction, as the module's doc says.
fn velocities<S: Space>(st: &mut State<S>, lambda: &[[f64; 2]], inv_h: f64, threshold: f64) {
    let State { touching, points, contacts, motion, .. } = st;
    for pair in touching.iter() {
        let (ia, ib) = (pair.a as usize, pair.b as usize);
        let (mut ma, mut mb) = (motion[ia], motion[ib]);
        for k in pair.start as usize..pair.end as usize {
            let [ln, lt] = lambda[k];
            if ln <= 0.0 {
                continue;
            }
            let (p, c) = (&mut points[k], &mut contacts[k]);
            let n = p.normal;
            let (ta, tb) = (S::rotate_delta(ma.dq, p.ra), S::rotate_delta(mb.dq, p.rb));
            let vn = relative_velocity(&ma, &mb, ta, tb).dot(n);
            let e = if p.approach < -threshold { pair.restitution } else { 0.0 };
            let target = (-e * p.approach).max(0.0);
            let w = weight(&ma, ta, n) + weight(&mb, tb, n);
            let jn = if w > 0.0 { (target - vn) / w } else { 0.0 };
            push(&mut ma, &mut mb, ta, tb, n * jn);
            p.normal_impulse += jn;
            c.total_normal += jn;
            let dv = relative_velocity(&ma, &mb, ta, tb);
            let vt = dv - n * dv.dot(n);
            let size = vt.dot(vt).sqrt();
            let most = pair.friction * (ln * inv_h + jn).max(0.0) - lt * inv_h;
            if size > 0.0 && most > 0.0 {
                let t = vt * (1.0 / size);
                let wt = weight(&ma, ta, t) + weight(&mb, tb, t);
                if wt > 0.0 {
                    let f = (size / wt).min(most);
                    let imp = t * -f;
                    for (k, ti) in p.tangent_impulse.iter_mut().enumerate().take(S::TANGENTS) {
                        *ti += imp.dot(S::tangent(n, p.frame, k));
                    }
                    c.total_friction += f;
                    push(&mut ma, &mut mb, ta, tb, imp);
                }
            }
        }
        (motion[ia].v, motion[ia].w) = (ma.v, ma.w);
        (motion[ib].v, motion[ib].w) = (mb.v, mb.w);
    }
}
