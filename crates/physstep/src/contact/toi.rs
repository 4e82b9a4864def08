//! Continuous collision of fast solids against static and kinematic ones (Box2D v3's, after
//! its `b2SolveContinuous`).
//!
//! On by default (`Settings::continuous`; `World.continuous_collision` in Python, `continuous`
//! in a scene file's `[contact]`).
//!
//! A contact is found only between solids closer than the speculative distance when a step
//! begins, so a solid that moves farther than that in a step can start it clear of the ground
//! and end it deep inside (or past a thin wall). After the substeps, each dynamic solid not held
//! by a joint that would move farther than the speculative distance in a step at the
//! velocities it ends this one with (its speed plus its spin times its largest extent) is
//! swept from its pose at the step's start to its pose
//! now against the static and kinematic solids whose boxes its swept box meets, in index
//! order, by parry's time of impact ([`Space::time_of_impact`]). If it meets one, it is put
//! where the sweep first comes within the slop of it (1% of its smallest extent), but no
//! farther back than its contacts with dynamic solids let it go (a neighbour that pushed it
//! there has moved on since: put back into it, jammed circles overlapped 5.4 cm where they
//! rest at 4.8), with the velocity a free fall under gravity has at the height it is put
//! back to (`back_in_time`: neither gaining nor losing the height); the next step's contact
//! stops it. A bullet ([`super::SolidParams::bullet`]) is swept after the others, against the
//! dynamic solids that are not bullets too (where they ended the step). A pair that was in
//! contact when the step began was the solver's: only the solid's core is swept against it
//! (it hits only what the solid would pass through), and where the solid ended the step more
//! than the slop deep in it (a box's far corner turned into the ground) it is put back to
//! where it was half the slop deep. Solids that moved less than the speculative distance cost
//! one comparison.

use super::space::{Space, Swept, Vect};
use super::{Body, Kind};

/// Where a solid was when the step began.
#[derive(Debug, Clone, Copy)]
struct Start<S: Space> {
    c: S::V,
    q: S::Rot,
}

/// Continuous collision's memory of a step: the solids' poses when it began, and scratch.
#[derive(Debug, Clone)]
pub(crate) struct Sweeps<S: Space> {
    start: Vec<Start<S>>,
    /// The static and kinematic solids, by index.
    fixed: Vec<u32>,
    /// What a bullet is swept against: those, then the dynamic solids that are not bullets.
    targets: Vec<u32>,
    /// The solids this step put back, by index, in order.
    pub(crate) rolled: Vec<u32>,
}

impl<S: Space> Default for Sweeps<S> {
    fn default() -> Self {
        Self { start: Vec::new(), fixed: Vec::new(), targets: Vec::new(), rolled: Vec::new() }
    }
}

/// The axis-aligned box of `shape` at `(origin, q)` widened by `margin`.
fn aabb<S: Space>(shape: &S::Shape, origin: S::V, q: S::Rot, margin: f64) -> ([f64; 3], [f64; 3]) {
    S::aabb(shape, origin, S::basis(q), margin)
}

fn union(a: ([f64; 3], [f64; 3]), b: ([f64; 3], [f64; 3])) -> ([f64; 3], [f64; 3]) {
    let mut out = a;
    for k in 0..3 {
        out.0[k] = a.0[k].min(b.0[k]);
        out.1[k] = a.1[k].max(b.1[k]);
    }
    out
}

fn overlap(a: &([f64; 3], [f64; 3]), b: &([f64; 3], [f64; 3])) -> bool {
    (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

/// How long ago a free fall under `gravity` that now has velocity `v` was displaced by
/// `back` from where it is, so that the velocity put back with the pose (`v - gravity tau`)
/// keeps the energy the step's substeps of `h` keep (`|v + g h / 2|^2 / 2 - g . x`): a solid
/// put back up toward where it came from is given the speed it had at that height, neither
/// more (Box2D's, which keeps `v`: an elastic ball then gains the height it is put back by,
/// 5 times its bounce height in 100 bounces) nor less (the velocity a fraction `t` of the
/// step back is that of a point above the straight sweep's: up to 1% of the height lost in
/// 100 bounces). The root nearest 0 (the caller keeps it within the step); `None` where it
/// is not a number.
fn back_in_time<V: Vect>(v: V, gravity: V, back: V, h: f64) -> Option<f64> {
    let a = gravity.dot(gravity);
    if a == 0.0 {
        return Some(0.0);
    }
    let b = gravity.dot(v + gravity * (0.5 * h));
    let c = gravity.dot(back);
    let disc = b * b + 2.0 * a * c;
    let tau = if disc < 0.0 {
        // No time on the arc reaches that height: the nearest to it.
        b / a
    } else {
        let den = b + disc.sqrt().copysign(b);
        if den == 0.0 {
            0.0
        } else {
            -2.0 * c / den
        }
    };
    tau.is_finite().then_some(tau.max(0.0))
}

impl<S: Space> Sweeps<S> {
    /// Keeps the solids' poses as the step begins.
    pub(crate) fn record(&mut self, bodies: &[Body<S>]) {
        self.start.clear();
        self.start.extend(bodies.iter().map(|b| Start { c: b.c, q: b.q }));
        self.rolled.clear();
    }

    /// After the substeps: each fast dynamic solid swept against the static and kinematic
    /// solids and put back to its time of impact. `in_contact(a, b)` says whether the pair
    /// `a < b` was in contact when the step began; `spec` is the speculative distance and
    /// `no_collide` the pairs that do not collide (sorted).
    #[allow(clippy::too_many_arguments)] // the solver's parts it reads, each borrowed apart
    pub(crate) fn advance(
        &mut self,
        bodies: &mut [Body<S>],
        shapes: &[S::Shape],
        no_collide: &[(u32, u32)],
        spec: f64,
        (dt, h): (f64, f64),
        gravity: S::V,
        jointed: impl Fn(usize) -> bool,
        in_contact: impl Fn(u32, u32) -> bool,
        room: impl Fn(usize, S::V, &dyn Fn(usize) -> S::V, f64) -> f64,
    ) {
        self.rolled.clear();
        self.fixed.clear();
        self.targets.clear();
        let mut fixed_ready = false;
        let n = bodies.len();
        // The solids that are not bullets, then the bullets (against where the others ended).
        let bullets = bodies.iter().any(|b| b.bullet);
        let order = (0..n).map(|i| (i, false)).chain((0..if bullets { n } else { 0 }).map(|i| (i, true)));
        for (i, pass) in order {
            let b = &bodies[i];
            if b.kind != Kind::Dynamic || b.bullet != pass {
                continue;
            }
            // How far its farthest point goes in a step at the velocities it ends the step
            // with (Box2D's measure: a soft contact's push, which the relax pass takes back,
            // does not make a solid fast).
            let speed = b.v.dot(b.v).sqrt() + b.w.dot(b.w).sqrt() * b.max_extent;
            let motion = speed * dt;
            // Slow (or not finite: the runaway check names it), or held by a joint (putting
            // one end back would pull the joint apart): nothing to do.
            if !(motion > spec && motion < crate::limits::PARAM_MAX) || jointed(i) {
                continue;
            }
            let s = self.start[i];
            let d = b.c - s.c;
            if !fixed_ready {
                self.fixed.extend(
                    bodies.iter().enumerate().filter(|(_, o)| o.kind != Kind::Dynamic).map(|(j, _)| j as u32),
                );
                fixed_ready = true;
            }
            let origin = |c: S::V, q: S::Rot, com: S::V| c - S::rotate(q, com);
            let fast = Swept::<S> {
                shape: &shapes[i],
                com: b.com,
                start: (origin(s.c, s.q, b.com), s.q),
                end: (origin(b.c, b.q, b.com), b.q),
            };
            let margin = 0.5 * spec;
            let swept = union(
                aabb::<S>(fast.shape, fast.start.0, fast.start.1, margin),
                aabb::<S>(fast.shape, fast.end.0, fast.end.1, margin),
            );
            let slop = 0.01 * b.min_extent;
            let mut best = 1.0;
            if pass && self.targets.is_empty() {
                self.targets.extend_from_slice(&self.fixed);
                self.targets.extend(
                    bodies
                        .iter()
                        .enumerate()
                        .filter(|(_, o)| o.kind == Kind::Dynamic && !o.bullet)
                        .map(|(j, _)| j as u32),
                );
            }
            let targets = if pass { &self.targets } else { &self.fixed };
            for &j in targets {
                let (o, so) = (&bodies[j as usize], self.start[j as usize]);
                let pair = ((i as u32).min(j), (i as u32).max(j));
                if !no_collide.is_empty() && no_collide.binary_search(&pair).is_ok() {
                    continue;
                }
                let other = Swept::<S> {
                    shape: &shapes[j as usize],
                    com: o.com,
                    start: (origin(so.c, so.q, o.com), so.q),
                    end: (origin(o.c, o.q, o.com), o.q),
                };
                let mut its = aabb::<S>(other.shape, other.start.0, other.start.1, margin);
                if o.kind != Kind::Static {
                    its = union(its, aabb::<S>(other.shape, other.end.0, other.end.1, margin));
                }
                if !overlap(&swept, &its) {
                    continue;
                }
                let core_only = in_contact(pair.0, pair.1);
                if let Some(t) = S::time_of_impact(&fast, b.min_extent, &other, core_only, slop, best) {
                    best = t;
                }
            }
            if best < 1.0 {
                // Not back into a dynamic neighbour: only as far back as its contacts with
                // dynamic solids let it go (one that pushed it there has moved on since).
                let start = &self.start;
                let moved = |j: usize| bodies[j].c - start[j].c;
                let u = room(i, -d, &moved, slop).clamp(0.0, 1.0);
                best = best.max(1.0 - u);
            }
            if best < 1.0 {
                let b = &mut bodies[i];
                let end = b.c;
                b.c = s.c + d * best;
                b.q = S::sweep_rotation(s.q, b.q, best);
                b.v -= gravity
                    * back_in_time(b.v, gravity, b.c - end, h).map_or(dt * (1.0 - best), |t| t.min(dt));
                self.rolled.push(i as u32);
            }
        }
        if bullets {
            // The solver looks the solids put back up by index.
            self.rolled.sort_unstable();
        }
    }

    /// How far solid `i` moved since the step began.
    pub(crate) fn moved(&self, i: usize, c: S::V) -> S::V {
        c - self.start[i].c
    }
}
