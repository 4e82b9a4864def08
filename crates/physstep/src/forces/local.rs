//! The forces that act on each particle alone (gravity, drag, central gravity, springs to
//! anchors), as one per-particle function: the whole-array evaluation and the fused particle
//! kernels both call it, so they compute bitwise the same accelerations.

use super::{Endpoint, Force};

/// A spring from one particle to a fixed anchor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AnchorSpring {
    /// The particle.
    pub i: usize,
    /// The anchor, m (zero beyond `dim`).
    pub at: [f64; 3],
    /// Stiffness, rest length, damping.
    pub p: [f64; 3],
}

/// The per-particle forces of a set, gathered: accelerations of particle `p` depend on its
/// own position, velocity and inverse mass only.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Local {
    /// Sum of the uniform gravities, m/s^2.
    g: [f64; 3],
    /// Sums of the drag coefficients.
    c1: f64,
    c2: f64,
    drag: bool,
    /// Central gravities `(center, gm)`, in canonical order.
    central: Vec<([f64; 3], f64)>,
    /// Springs to anchors, sorted by particle (canonical order within a particle).
    anchors: Vec<AnchorSpring>,
    /// Whether every force of the set is per-particle.
    pub all: bool,
}

impl Default for Local {
    /// No force: every (absent) force is per-particle.
    fn default() -> Self {
        Self {
            g: [0.0; 3],
            c1: 0.0,
            c2: 0.0,
            drag: false,
            central: Vec::new(),
            anchors: Vec::new(),
            all: true,
        }
    }
}

impl AnchorSpring {
    /// The force this spring is.
    fn force(&self) -> Force {
        let [stiffness, rest_length, damping] = self.p;
        Force::Spring { i: self.i, j: Endpoint::Anchor(self.at), stiffness, rest_length, damping }
    }
}

impl Local {
    /// Takes in `force`, just added to `forces` (the whole set, in canonical order). A spring
    /// to an anchor goes to its canonical place (a chain of many is built in O(n log n));
    /// the uniform forces are summed again over the set in canonical order, so the sums do
    /// not depend on the order the forces were added in.
    pub(crate) fn add<'a>(&mut self, force: &Force, forces: impl Iterator<Item = &'a Force>) {
        match *force {
            Force::Spring { i, j: Endpoint::Anchor(at), stiffness, rest_length, damping } => {
                let key = force.key();
                let k = self.anchors.partition_point(|s| s.force().key() <= key);
                self.anchors.insert(k, AnchorSpring { i, at, p: [stiffness, rest_length, damping] });
            }
            Force::Spring { .. } | Force::Rod { .. } | Force::NBody { .. } => self.all = false,
            Force::Gravity { .. } | Force::Drag { .. } | Force::CentralGravity { .. } => self.uniform(forces),
        }
    }

    /// Gravity, drag and central gravity summed over `forces` in canonical order.
    fn uniform<'a>(&mut self, forces: impl Iterator<Item = &'a Force>) {
        (self.g, self.c1, self.c2, self.drag) = ([0.0; 3], 0.0, 0.0, false);
        self.central.clear();
        for f in forces {
            match *f {
                Force::Gravity { g } => {
                    for (lk, gk) in self.g.iter_mut().zip(g) {
                        *lk += gk;
                    }
                }
                Force::Drag { linear, quadratic } => {
                    self.drag = true;
                    self.c1 += linear;
                    self.c2 += quadratic;
                }
                Force::CentralGravity { center, gm } => self.central.push((center, gm)),
                _ => {}
            }
        }
    }

    /// Gravity and drag as element-wise parts (uniform gravity `g`, drag factor `s`), when
    /// they are all there is: no quadratic drag, central gravity or spring.
    pub(crate) fn element_wise(&self) -> Option<(f64, [f64; 3])> {
        let plain = self.all && self.c2 == 0.0 && self.central.is_empty() && self.anchors.is_empty();
        // The drag factor exactly as `particle` computes it with no quadratic term; with no
        // drag, 0: `(0 + 0 v) / m` is the `0` it starts from (v is finite at every accepted
        // state, and a non-finite one fails the step either way).
        let s = if self.drag { -(self.c1 + self.c2 * 0.0) } else { 0.0 };
        plain.then_some((s, self.g))
    }

    /// Gravity, drag and springs to anchors as element-wise parts (uniform gravity `g`, drag
    /// factor `s`, the springs), when each acceleration component is a function of its own
    /// coordinate and velocity component: no quadratic drag or central gravity, every
    /// spring of zero rest length and at most one per particle.
    pub(crate) fn element_springs(&self) -> Option<(f64, [f64; 3], &[AnchorSpring])> {
        let linear = self.anchors.iter().all(|s| s.p[1] == 0.0);
        let single = self.anchors.windows(2).all(|w| w[0].i != w[1].i);
        let plain = self.all && self.c2 == 0.0 && self.central.is_empty() && linear && single;
        // The drag factor as `element_wise` gives it.
        let s = if self.drag { -(self.c1 + self.c2 * 0.0) } else { 0.0 };
        plain.then_some((s, self.g, self.anchors.as_slice()))
    }

    /// The springs to anchors of particles `p0..p1`.
    #[inline]
    pub(crate) fn anchors(&self, p0: usize, p1: usize) -> &[AnchorSpring] {
        let lo = self.anchors.partition_point(|s| s.i < p0);
        let hi = lo + self.anchors[lo..].partition_point(|s| s.i < p1);
        &self.anchors[lo..hi]
    }

    /// Fills `a` with the accelerations of particles `p0..` at positions `x` and velocities
    /// `v` (flat, `D` per particle), `inv_mass` theirs, `springs` their springs to anchors (as
    /// [`Local::anchors`] gives them).
    #[inline(always)]
    pub(crate) fn accel<const D: usize>(
        &self,
        p0: usize,
        x: &[f64],
        v: &[f64],
        inv_mass: &[f64],
        springs: &[AnchorSpring],
        a: &mut [f64],
    ) {
        if !self.drag && springs.is_empty() && self.central.is_empty() && self.g.iter().all(|g| *g == 0.0) {
            // No force at all: every acceleration is `0 + 0` (what the loop gives), bit for bit.
            a.fill(0.0);
            return;
        }
        let mut s = 0;
        let rows = x.chunks_exact(D).zip(v.chunks_exact(D)).zip(a.chunks_exact_mut(D)).zip(inv_mass);
        for (p, (((xp, vp), ap), &im)) in rows.enumerate() {
            let start = s;
            while s < springs.len() && springs[s].i == p0 + p {
                s += 1;
            }
            let out = self.particle::<D>(xp, vp, im, &springs[start..s]);
            ap.copy_from_slice(&out);
        }
    }

    /// The acceleration of one particle at `x`, `v` with inverse mass `im` and its springs to
    /// anchors: `a = F / m + g + central`, `F` the drag and springs.
    #[inline(always)]
    fn particle<const D: usize>(&self, x: &[f64], v: &[f64], im: f64, springs: &[AnchorSpring]) -> [f64; D] {
        let mut f = [0.0; D];
        if self.drag {
            // sqrt only where the quadratic term needs it: c1 + 0 * |v| is c1 either way.
            let speed = if self.c2 == 0.0 { 0.0 } else { v.iter().map(|x| x * x).sum::<f64>().sqrt() };
            let s = -(self.c1 + self.c2 * speed);
            for k in 0..D {
                f[k] += s * v[k];
            }
        }
        for sp in springs {
            let [k, rest, c] = sp.p;
            let mut d = [0.0; 3];
            for kk in 0..D {
                d[kk] = x[kk] - sp.at[kk];
            }
            if rest == 0.0 {
                for kk in 0..D {
                    f[kk] += -k * d[kk] - c * v[kk];
                }
                continue;
            }
            let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            let s = if r2 > 0.0 {
                let r = r2.sqrt();
                let mut wd = 0.0;
                for kk in 0..D {
                    wd += v[kk] * d[kk];
                }
                -k * (r - rest) / r - c * wd / r2
            } else {
                -k
            };
            for kk in 0..D {
                f[kk] += s * d[kk];
            }
        }
        let mut a = [0.0; D];
        if self.drag || !springs.is_empty() {
            for k in 0..D {
                a[k] = f[k] * im;
            }
        }
        // Gravity on dynamic particles; `+ 0` on the others (and with no gravity), so the
        // element-wise kernels add the same numbers without a branch.
        let dynamic = im > 0.0;
        for (ak, gk) in a.iter_mut().zip(self.g) {
            *ak += if dynamic { gk } else { 0.0 };
        }
        if dynamic {
            for (center, gm) in &self.central {
                let mut d = [0.0; 3];
                for k in 0..D {
                    d[k] = x[k] - center[k];
                }
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if r2 > 0.0 {
                    let s = -gm / (r2 * r2.sqrt());
                    for k in 0..D {
                        a[k] += s * d[k];
                    }
                }
            }
        }
        a
    }
}
