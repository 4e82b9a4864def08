//! Sleeping: a group of solids at rest leaves the solver until something reaches it, as
//! Box2D's islands do (docs/contact.md, "Sleeping").
//!
//! With [`Settings::sleep_time`](super::Settings::sleep_time) above 0, after each step the
//! awake dynamic solids are joined into islands by the contacts the step found (touching or
//! within the speculative distance), their joints and their springs. An island whose every
//! solid has been slow for `sleep_time` (its speed, and its angular speed times its largest
//! radius, below [`SLEEP_SPEED`]) falls asleep: its velocities set to 0, each solid keeping
//! the island's number (its lowest index). For a step a sleeping solid is static: no gravity,
//! no motion, immovable to what touches it; the broad phase passes over its pairs with other
//! sleeping or static solids, whose warm starts are kept for when it wakes.
//!
//! Before each step an island wakes, whole, when a moving solid (a dynamic one awake and not
//! slow, or a kinematic one with a velocity) comes within reach of one of its solids (their
//! bounding boxes overlap, the mover's grown by how far it can go in the step), a joint or a
//! spring joins it to a moving solid, a load (applied by hand or a user force) acts on it, or
//! gravity changed. A contact that missed (a slow solid creeping into a sleeper) wakes it
//! after the step, for the next. Setting a solid's motion by hand, applying a load, adding,
//! changing or removing a joint, spring or user force at it, wakes its island at once, and a
//! removal wakes every island. Everything is serial and in index order: the same bits on any
//! number of threads.

use super::points::Warm;
use super::{broad, Body, Kind, Solids, Space, Vect};

/// A solid is slow while its speed and its angular speed times its largest radius are below
/// this, m/s (Box2D v3's default).
pub const SLEEP_SPEED: f64 = 0.05;

/// The sleeping state's scratch, kept from step to step (no allocation once warm).
#[derive(Debug)]
pub(super) struct Scratch<S: Space> {
    /// The solids hidden from this step (asleep): index, inverse mass, inverse inertia and
    /// inertia, put back after it.
    hidden: Vec<(u32, f64, S::InvI, S::InvI)>,
    /// Warm starts of pairs no awake solid is in, kept over the step.
    kept: Vec<Warm<S>>,
    /// The wake test's boxes, movers and broad-phase order and pairs.
    lo: Vec<[f64; 3]>,
    hi: Vec<[f64; 3]>,
    movers: Vec<bool>,
    order: Vec<u32>,
    pairs: Vec<(u32, u32)>,
    /// Union-find parents of the islands, and each island's shortest idle time (at its root).
    parent: Vec<u32>,
    least: Vec<f64>,
    /// The gravity of the latest step (`None` before the first one): rolled back with it.
    pub(super) gravity: Option<S::V>,
}

impl<S: Space> Default for Scratch<S> {
    fn default() -> Self {
        Self {
            hidden: Vec::new(),
            kept: Vec::new(),
            lo: Vec::new(),
            hi: Vec::new(),
            movers: Vec::new(),
            order: Vec::new(),
            pairs: Vec::new(),
            parent: Vec::new(),
            least: Vec::new(),
            gravity: None,
        }
    }
}

/// Scratch: a copy starts afresh, but for the gravity last seen.
impl<S: Space> Clone for Scratch<S> {
    fn clone(&self) -> Self {
        Self { gravity: self.gravity, ..Self::default() }
    }
}

/// The root of `i` (halving the path).
fn root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[i as usize];
        parent[i as usize] = parent[p as usize];
        i = p;
    }
    i
}

/// Joins the islands of `a` and `b` under the lower root.
fn join(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (root(parent, a), root(parent, b));
    let (lo, hi) = (ra.min(rb), ra.max(rb));
    parent[hi as usize] = lo;
}

/// Solid `b`'s speed for sleeping: the larger of its speed and its angular speed times its
/// largest radius.
fn speed<S: Space>(b: &Body<S>) -> f64 {
    b.v.dot(b.v).sqrt().max(b.w.dot(b.w).sqrt() * b.max_extent)
}

/// Whether solid `b` wakes the sleepers it reaches: a dynamic solid awake and not slow, or a
/// kinematic one that moves. (An awake slow solid near a sleeping one wakes it only once
/// their contact is found, after the step: else two neighbours a little apart, not in one
/// island, would wake each other in turn for ever.)
fn mover<S: Space>(b: &Body<S>) -> bool {
    match b.kind {
        Kind::Dynamic => !b.asleep && speed(b) >= SLEEP_SPEED,
        Kind::Kinematic => speed(b) > 0.0,
        Kind::Static => false,
    }
}

/// The two solids of every joint and spring (`None`: the world).
fn links<'a, S: Space>(
    joints: &'a [super::joint::Joint<S>],
    springs: &'a [super::forces::Spring<S>],
) -> impl Iterator<Item = (Option<usize>, usize)> + 'a {
    joints.iter().map(|j| j.solids()).chain(springs.iter().map(|s| s.solids()))
}

impl<S: Space> Solids<S> {
    /// Wakes the islands of the sleeping solids among `solids`, in one pass over the solids
    /// (a wake test can name many solids of one island).
    fn wake_islands(&mut self, solids: &[usize]) {
        let mut islands: Vec<u32> = solids
            .iter()
            .filter_map(|&i| self.bodies.get(i).filter(|b| b.asleep).map(|b| b.island))
            .collect();
        if islands.is_empty() {
            return;
        }
        islands.sort_unstable();
        islands.dedup();
        for b in self.bodies.iter_mut().filter(|b| b.asleep && islands.binary_search(&b.island).is_ok()) {
            b.asleep = false;
            b.idle = 0.0;
        }
    }

    /// Wakes solid `i`'s island (nothing when it is awake).
    pub(crate) fn wake(&mut self, i: usize) {
        let Some(b) = self.bodies.get(i) else { return };
        if !b.asleep {
            self.bodies[i].idle = 0.0;
            return;
        }
        let island = b.island;
        for b in self.bodies.iter_mut().filter(|b| b.asleep && b.island == island) {
            b.asleep = false;
            b.idle = 0.0;
        }
    }

    /// Wakes the islands of a link's two solids (`None`: the world).
    pub(crate) fn wake_ends(&mut self, (a, b): (Option<usize>, usize)) {
        if let Some(a) = a {
            self.wake(a);
        }
        self.wake(b);
    }

    /// Wakes every solid.
    pub(crate) fn wake_all(&mut self) {
        for b in &mut self.bodies {
            b.asleep = false;
            b.idle = 0.0;
        }
    }

    /// A snapshot's block without its sleep (the last three numbers a solid while sleeping
    /// is on), and the sleep, checked.
    ///
    /// # Errors
    /// What does not fit, in words.
    pub(super) fn sleep_split<'a>(&self, data: &'a [f64]) -> Result<(&'a [f64], &'a [f64]), String> {
        if self.settings.sleep_time == 0.0 {
            return Ok((data, &[]));
        }
        let n = self.bodies.len();
        let at = data.len().checked_sub(3 * n).ok_or("truncated sleep")?;
        let (data, sleep) = data.split_at(at);
        for (i, (s, b)) in sleep.chunks_exact(3).zip(&self.bodies).enumerate() {
            let asleep = s[0] == 1.0 && b.kind == Kind::Dynamic;
            let island = s[2].fract() == 0.0 && s[2] >= 0.0 && s[2] < n as f64;
            if !((asleep || s[0] == 0.0) && s[1].is_finite() && s[1] >= 0.0 && island) {
                return Err(format!(
                    "solid {i}'s sleep [{}, {}, {}] does not fit this world",
                    s[0], s[1], s[2]
                ));
            }
        }
        Ok((data, sleep))
    }

    /// Which solids are asleep.
    #[must_use]
    pub fn asleep(&self) -> Vec<bool> {
        self.bodies.iter().map(|b| b.asleep).collect()
    }

    /// Before a step of `dt` under `gravity`: wakes the islands something reaches, then hides
    /// the sleeping solids from the step (static to it). Nothing without sleepers.
    pub(super) fn sleep_begin(&mut self, dt: f64, gravity: S::V) {
        let seen = self.sleep.gravity.replace(gravity);
        if self.settings.sleep_time == 0.0 || seen.is_some_and(|g| g != gravity) {
            if self.bodies.iter().any(|b| b.asleep) {
                self.wake_all();
            }
            if self.settings.sleep_time == 0.0 {
                return;
            }
        }
        if !self.bodies.iter().any(|b| b.asleep) {
            return;
        }
        let mut wake = Vec::new();
        // Loads on a sleeper.
        for (i, (f, t)) in self.forces.load.iter().enumerate() {
            if self.bodies.get(i).is_some_and(|b| b.asleep) && (f.dot(*f) > 0.0 || t.dot(*t) > 0.0) {
                wake.push(i);
            }
        }
        // Joints and springs from a sleeper to a moving solid.
        for (a, b) in links(&self.joints, &self.forces.springs) {
            let Some(a) = a else { continue };
            let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
            if ba.asleep && mover(bb) {
                wake.push(a);
            } else if bb.asleep && mover(ba) {
                wake.push(b);
            }
        }
        // Movers within reach of a sleeper: their boxes grown by how far they can go (twice
        // their speed for the turning, and gravity's gain).
        let margin = self.settings.speculative_distance / 2.0;
        let sc = &mut self.sleep;
        if !self.bodies.iter().any(mover) {
            sc.pairs.clear();
        } else {
            sc.lo.clear();
            sc.hi.clear();
            sc.movers.clear();
            for (b, shape) in self.bodies.iter().zip(&self.shapes) {
                let moves = mover(b);
                let reach =
                    if moves { (2.0 * speed(b) + gravity.dot(gravity).sqrt() * dt) * dt } else { 0.0 };
                let (lo, hi) = S::aabb(shape, b.origin(), S::basis(b.q), margin + reach);
                sc.lo.push(lo);
                sc.hi.push(hi);
                sc.movers.push(moves);
            }
            broad::pairs(&sc.lo, &sc.hi, &sc.movers, &mut sc.order, &mut sc.pairs);
        }
        for &(a, b) in &sc.pairs {
            let (a, b) = (a as usize, b as usize);
            if self.bodies[a].asleep && sc.movers[b] {
                wake.push(a);
            } else if self.bodies[b].asleep && sc.movers[a] {
                wake.push(b);
            }
        }
        self.wake_islands(&wake);
        // Hidden: static to the step; their warm starts with static solids and each other kept.
        let sc = &mut self.sleep;
        sc.hidden.clear();
        for (i, b) in self.bodies.iter_mut().enumerate().filter(|(_, b)| b.asleep) {
            sc.hidden.push((i as u32, b.inv_mass, b.inv_i_local, b.i_local));
            b.kind = Kind::Static;
            b.inv_mass = 0.0;
            b.inv_i_local = S::no_inertia();
            b.i_local = S::no_inertia();
        }
        let bodies = &self.bodies;
        let still = |k: u32| bodies[k as usize].kind != Kind::Dynamic;
        sc.kept.clear();
        sc.kept.extend(self.solver.warm.iter().filter(|w| still(w.key.0) && still(w.key.1)).copied());
    }

    /// After a step of `dt`: the hidden solids put back (their warm starts with them), then
    /// the awake dynamic solids' idle times, their islands, and the islands that fall asleep.
    pub(super) fn sleep_end(&mut self, dt: f64) {
        let sc = &mut self.sleep;
        for &(i, inv_mass, inv_i, i_local) in &sc.hidden {
            let b = &mut self.bodies[i as usize];
            (b.kind, b.inv_mass, b.inv_i_local, b.i_local) = (Kind::Dynamic, inv_mass, inv_i, i_local);
        }
        sc.hidden.clear();
        if !sc.kept.is_empty() {
            let warm = &mut self.solver.warm;
            warm.append(&mut sc.kept);
            warm.sort_unstable_by_key(|w| w.key);
            warm.dedup_by(|x, y| x.key == y.key);
        }
        if self.settings.sleep_time == 0.0 {
            return;
        }
        let dynamic_awake = |b: &Body<S>| b.kind == Kind::Dynamic && !b.asleep;
        for b in self.bodies.iter_mut().filter(|b| dynamic_awake(b)) {
            b.idle = if speed(b) < SLEEP_SPEED { b.idle + dt } else { 0.0 };
        }
        let n = self.bodies.len();
        let parent = &mut sc.parent;
        parent.clear();
        parent.extend(0..n as u32);
        let mut woken = Vec::new();
        let pairs = self.solver.touching.iter().map(|p| (Some(p.a as usize), p.b as usize));
        for (a, b) in pairs.chain(links(&self.joints, &self.forces.springs)) {
            let Some(a) = a else { continue };
            let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
            if dynamic_awake(ba) && dynamic_awake(bb) {
                join(parent, a as u32, b as u32);
            } else if ba.asleep && dynamic_awake(bb) {
                // Reached within the step (the test before it missed): awake from the next.
                woken.push(a);
            } else if bb.asleep && dynamic_awake(ba) {
                woken.push(b);
            }
        }
        // Each island's shortest idle time, at its root.
        let least = &mut sc.least;
        least.clear();
        least.resize(n, f64::INFINITY);
        for i in 0..n {
            if dynamic_awake(&self.bodies[i]) {
                let r = root(parent, i as u32) as usize;
                least[r] = least[r].min(self.bodies[i].idle);
            }
        }
        for i in 0..n {
            if dynamic_awake(&self.bodies[i]) {
                let r = root(parent, i as u32);
                if least[r as usize] >= self.settings.sleep_time {
                    let b = &mut self.bodies[i];
                    (b.asleep, b.island, b.v, b.w) = (true, r, S::V::default(), S::W::default());
                }
            }
        }
        self.wake_islands(&woken);
    }
}
