//! The two spaces solids live in, as one trait: the plane (2D: an angle, a scalar inertia)
//! and space (3D: a quaternion, an inertia tensor). The solver, the broad phase and the
//! bodies are written once over [`Space`]; what differs (how a rotation turns a vector, how
//! an angular velocity crosses an arm, how a shape meets another) lives here, and the
//! narrow phase is parry's (parry2d-f64 / parry3d-f64, on the glam types physstep uses).
//! The trait and what both share are here; the plane's impl in `plane.rs`, space's in
//! `space3.rs`.

use glam::{DVec2, DVec3};
use std::fmt::Debug;
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A vector of a space (a position, a velocity) or an angular quantity (a scalar in the
/// plane, a vector in space).
pub trait Vect:
    Copy
    + Default
    + Debug
    + PartialEq
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
{
    /// The dot product.
    fn dot(self, other: Self) -> f64;
    /// The components, in order.
    fn write(self, out: &mut Vec<f64>);
    /// Built from components (`c.len()` is the dimension).
    fn read(c: &[f64]) -> Self;
}

impl Vect for f64 {
    fn dot(self, other: Self) -> f64 {
        self * other
    }
    fn write(self, out: &mut Vec<f64>) {
        out.push(self);
    }
    fn read(c: &[f64]) -> Self {
        c[0]
    }
}

impl Vect for DVec2 {
    fn dot(self, other: Self) -> f64 {
        DVec2::dot(self, other)
    }
    fn write(self, out: &mut Vec<f64>) {
        out.extend_from_slice(&[self.x, self.y]);
    }
    fn read(c: &[f64]) -> Self {
        DVec2::new(c[0], c[1])
    }
}

impl Vect for DVec3 {
    fn dot(self, other: Self) -> f64 {
        DVec3::dot(self, other)
    }
    fn write(self, out: &mut Vec<f64>) {
        out.extend_from_slice(&[self.x, self.y, self.z]);
    }
    fn read(c: &[f64]) -> Self {
        DVec3::new(c[0], c[1], c[2])
    }
}

/// One contact point a narrow phase found, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch<V> {
    /// The point on the first shape.
    pub on_a: V,
    /// The point on the second shape.
    pub on_b: V,
    /// Unit normal from the first shape to the second.
    pub normal: V,
    /// Signed distance along the normal, m (negative: penetration).
    pub separation: f64,
    /// The two features that touch (for warm starting a point from step to step).
    pub id: u64,
}

/// The plane or space solids move in.
pub trait Space: Copy + Debug + Send + Sync + 'static {
    /// Number of coordinates of a point.
    const DIM: usize;
    /// Number of coordinates of an orientation as exported (an angle; a quaternion).
    const ROT: usize;
    /// A point or a linear velocity.
    type V: Vect;
    /// An angular velocity (a scalar in the plane).
    type W: Vect;
    /// An absolute orientation: the angle in the plane (exact), a unit quaternion in space.
    type Rot: Copy + Debug + PartialEq + Send + Sync;
    /// A rotation since the step began: the unit complex number (cos, sin) in the plane.
    type Delta: Copy + Debug + Send + Sync;
    /// An inverse inertia: a scalar in the plane, a matrix in space.
    type InvI: Copy + Debug + Send + Sync;
    /// The inverse inertia of a solid that does not turn (static, kinematic): zero (not
    /// glam's `Default`, which for a matrix is the identity).
    fn no_inertia() -> Self::InvI;
    /// The collision shape (parry's).
    type Shape: Clone + Send + Sync;

    /// The orientation that turns nothing.
    fn identity() -> Self::Rot;
    /// The rotation of nothing.
    fn no_delta() -> Self::Delta;
    /// `w x r`: the velocity of an arm `r` under angular velocity `w`.
    fn cross_wv(w: Self::W, r: Self::V) -> Self::V;
    /// `r x v`: the moment of `v` about the arm's origin.
    fn cross_vv(r: Self::V, v: Self::V) -> Self::W;
    /// The inverse inertia applied to an angular quantity.
    fn apply(i: Self::InvI, w: Self::W) -> Self::W;
    /// `v` turned by `q`.
    fn rotate(q: Self::Rot, v: Self::V) -> Self::V;
    /// `v` turned back by `q` (into the frame `q` turns).
    fn unrotate(q: Self::Rot, v: Self::V) -> Self::V;
    /// `v` turned by a rotation since the step began.
    fn rotate_delta(q: Self::Delta, v: Self::V) -> Self::V;
    /// The orientation after turning at `w` for `h` seconds (exact for a constant `w`: the
    /// angle moves by `h w` in the plane; the quaternion by the exponential map in space),
    /// and the rotation since the step began moved the same way.
    fn turn(q: Self::Rot, d: Self::Delta, w: Self::W, h: f64) -> (Self::Rot, Self::Delta);
    /// The world inverse inertia of a body at `q` whose inverse inertia in its own frame is
    /// `local`.
    fn world_inverse_inertia(q: Self::Rot, local: Self::InvI) -> Self::InvI;
    /// Unit tangents completing `n` to an orthonormal frame (one in the plane).
    fn tangents(n: Self::V) -> [Self::V; 2];
    /// What a contact point keeps of its tangents: nothing in the plane (the tangent is the
    /// normal turned a quarter, exactly), the two of [`Space::tangents`] in space.
    type Frame: Copy + Debug + PartialEq + Send + Sync;
    /// The frame kept for a normal `n`.
    fn frame(n: Self::V) -> Self::Frame;
    /// Tangent `k` of the normal `n` with its kept frame: `tangents(n)[k]`, to the bit.
    fn tangent(n: Self::V, frame: Self::Frame, k: usize) -> Self::V;
    /// A rotation made ready to turn many vectors (its sine and cosine in the plane).
    type Basis: Copy + Debug + Send + Sync;
    /// The ready form of `q`.
    fn basis(q: Self::Rot) -> Self::Basis;
    /// `v` turned by `q` given as [`Space::basis`]: `rotate(q, v)`, to the bit.
    fn rotate_by(b: Self::Basis, v: Self::V) -> Self::V;
    /// The ready form of turning back by `q`: `rotate_by(unbasis(q), v)` is `unrotate(q, v)`,
    /// to the bit.
    fn unbasis(q: Self::Rot) -> Self::Basis;
    /// Number of tangents (1 in the plane, 2 in space).
    const TANGENTS: usize;
    /// The size of a friction impulse `t` (its components along the tangents),
    /// `sqrt(t0^2 + t1^2)`, to the bit.
    fn friction_size(t: [f64; 2]) -> f64 {
        (t[0] * t[0] + t[1] * t[1]).sqrt()
    }
    /// The orientation's exported numbers (the angle; the quaternion w, x, y, z, as bodies').
    fn write_rot(q: Self::Rot, out: &mut Vec<f64>);
    /// Reads an orientation (an angle; a quaternion, normalised).
    fn read_rot(c: &[f64]) -> Self::Rot;
    /// Reads an orientation as [`Space::write_rot`] wrote it, bitwise (not normalised).
    fn read_rot_exact(c: &[f64]) -> Self::Rot;

    /// The orientation of `b` seen from `a` (what a joint keeps as its reference).
    fn relative(a: Self::Rot, b: Self::Rot) -> Self::Rot;
    /// A joint's rotation error when a step begins: how far `b` is turned from `a` turned by
    /// the reference `rel` (the angle in the plane; the rotation `qb (qa rel)^-1` in space).
    fn offset(a: Self::Rot, b: Self::Rot, rel: Self::Rot) -> Self::Rot;
    /// The rotation error now, after the two bodies turned by `da` and `db` since the step
    /// began: the angle in the plane (unbounded), the rotation vector in space (world frame;
    /// its rate is `w_b - w_a`).
    fn rotation_error(offset: Self::Rot, da: Self::Delta, db: Self::Delta) -> Self::W;
    /// A direction fixed in a body (a hinge axis, in its frame) seen in the world; in the
    /// plane every angular direction is the plane's normal, `1`.
    fn turn_axis(q: Self::Rot, axis: Self::W) -> Self::W;
    /// Number of angular directions a hinge locks besides its axis (0 in the plane, 2 in space).
    const SWINGS: usize;
    /// The directions a hinge about `axis` locks (the first [`Space::SWINGS`] are used).
    fn swing_axes(axis: Self::W) -> [Self::W; 2];
    /// Solves `K x = rhs` for the point constraint between arms `ra` of `a` and `rb` of `b`
    /// (`K` the velocity change at the point per unit impulse); zero where `K` is singular.
    fn point_solve(a: (f64, Self::InvI, Self::V), b: (f64, Self::InvI, Self::V), rhs: Self::V) -> Self::V;
    /// Solves `(Ia^-1 + Ib^-1) x = rhs` for an angular constraint; zero where singular.
    fn angular_solve(ia: Self::InvI, ib: Self::InvI, rhs: Self::W) -> Self::W;

    /// The angular velocity after `h` of torque-free spin (`I w' = -w x I w`, the gyroscopic
    /// term) of a solid of inertia `i_local` in its frame ([`Space::inertia`]), by [`crate::rigid::orientation::implicit_gyroscopic_rate`] (stable at any
    /// spin). Nothing in the plane (there `w x I w` is zero).
    fn gyroscopic(q: Self::Rot, i_local: Self::InvI, w: Self::W, h: f64) -> Self::W;
    /// The inertia of an inverse inertia (in a body's frame): its inverse, or zero where it is
    /// singular (a solid that does not turn).
    fn inertia(inv_i: Self::InvI) -> Self::InvI;
    /// The narrow phase's shape of a user's shape.
    ///
    /// # Errors
    /// As [`crate::contact::Shape::check`].
    fn build(shape: &crate::contact::Shape) -> crate::error::Result<Self::Shape>;
    /// Twice the kinetic energy of spin, `w . I w`, from the inverse inertia (0 where it is 0).
    fn spin_energy(inv_i: Self::InvI, w: Self::W) -> f64;
    /// Mass, centre of mass in the shape's frame and inverse inertia about it in the shape's
    /// frame, at `density`.
    fn mass_properties(shape: &Self::Shape, density: f64) -> (f64, Self::V, Self::InvI);
    /// The axis-aligned box around the shape placed at `p` turned by `basis` ([`Space::basis`]
    /// of its orientation), widened by `margin`.
    fn aabb(shape: &Self::Shape, p: Self::V, basis: Self::Basis, margin: f64) -> ([f64; 3], [f64; 3]);
    /// A shape's smallest and largest extents about `com` (a point in its frame): the
    /// thickness a fast motion must not cross (a box's smallest half extent, a ball's radius),
    /// and the radius of the ball about `com` that holds it.
    fn extents(shape: &Self::Shape, com: Self::V) -> (f64, f64);
    /// The orientation a fraction `t` of the way from `q0` to `q1` as a sweep takes it (the
    /// normalised linear interpolation, Box2D's and parry's).
    fn sweep_rotation(q0: Self::Rot, q1: Self::Rot, t: f64) -> Self::Rot;
    /// Continuous collision: the earliest fraction of the step in (0, `max`) at which `fast`,
    /// moving from its start pose to its end pose, comes within `slop` of `other` (parry's
    /// time of impact of endpoint-interpolated sweeps, Box2D's conservative advancement);
    /// `None` when it does not. Where the two overlap at the start, or where `core_only` says
    /// they were in contact then, only the solid's core (a ball of a quarter of its smallest
    /// extent about its centre of mass) is swept: it hits only a solid it would pass through.
    fn time_of_impact(
        fast: &Swept<'_, Self>,
        min_extent: f64,
        other: &Swept<'_, Self>,
        core_only: bool,
        slop: f64,
        max: f64,
    ) -> Option<f64>;
    /// The contact points of two shapes placed at their poses (origin, [`Space::basis`] of the
    /// orientation: in the plane the sine and cosine, computed once a solid rather than once a
    /// pair) that are closer than `prediction`, appended to `out`.
    fn touches(
        a: (&Self::Shape, Self::V, Self::Basis),
        b: (&Self::Shape, Self::V, Self::Basis),
        prediction: f64,
        out: &mut Vec<Touch<Self::V>>,
    );
}

/// A solid's motion over a step as continuous collision sweeps it: its shape, its centre of
/// mass in the shape's frame, and the shape's poses (origin, orientation) at the step's start
/// and end.
#[derive(Clone, Copy)]
pub struct Swept<'a, S: Space> {
    /// The shape.
    pub shape: &'a S::Shape,
    /// The centre of mass in the shape's frame.
    pub com: S::V,
    /// Origin and orientation when the step began.
    pub start: (S::V, S::Rot),
    /// Origin and orientation now.
    pub end: (S::V, S::Rot),
}

/// The fraction of a solid's smallest extent its core (the ball swept where it already
/// touches) has for radius: Box2D's `B2_CORE_FRACTION`.
const CORE_FRACTION: f64 = 0.25;

/// The time of impact of a fast solid's sweep against another's (one text for both of parry's
/// crates). Half-spaces have no proxy in parry's sweeps: against one, the fraction is the first
/// at which the proxy's deepest point comes within the target, found by bisection (a half-space
/// cannot be passed through, so where the end is clear of it nothing was crossed).
macro_rules! sweep_toi {
    ($parry:ident, $pose:expr, $fast:expr, $min_extent:expr, $other:expr, $core_only:expr, $slop:expr, $max:expr) => {{
        use $parry::query::{
            contact, sweep_time_of_impact, sweep_time_of_impact_composite, Sweep, SweepCompositeFastShape,
            ToiProxy,
        };
        let (fast, other, slop, max) = ($fast, $other, $slop, $max);
        let pose = $pose;
        let fast_sweep = Sweep::from_poses(&pose(fast.start), &pose(fast.end), fast.com);
        let other_sweep = Sweep::from_poses(&pose(other.start), &pose(other.end), other.com);
        let core = ToiProxy::point(fast.com, CORE_FRACTION * $min_extent);
        let whole = if $core_only { None } else { ToiProxy::from_shape(fast.shape.as_ref()) };
        let hit = |f: f64| (f > 0.0 && f < max).then_some(f);
        let swept = if let Some(plane) = other.shape.as_halfspace() {
            let normal = plane.normal;
            let fraction = |proxy: &ToiProxy| {
                // The surfaces `slop` apart (for a ball, its centre `radius + slop` away).
                let target = proxy.radius + slop;
                let gap = |t: f64| {
                    let (xf, xp) = (fast_sweep.transform_at(t), other_sweep.transform_at(t));
                    let n = xp.transform_vector(normal);
                    let deepest = proxy
                        .points()
                        .iter()
                        .map(|p| n.dot(xf.transform_point(*p)))
                        .fold(f64::INFINITY, f64::min);
                    deepest - n.dot(xp.translation) - target
                };
                let start = gap(0.0);
                if start.is_nan() || start <= 0.0 {
                    return 0.0;
                }
                if gap(max) > 0.0 {
                    return max;
                }
                let (mut lo, mut hi) = (0.0, max);
                for _ in 0..50 {
                    let mid = 0.5 * (lo + hi);
                    if gap(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            };
            let f = whole.as_ref().map_or(0.0, |w| fraction(w));
            hit(if f == 0.0 { fraction(&core) } else { f })
        } else if let Some(proxy) = ToiProxy::from_shape(other.shape.as_ref()) {
            let cast =
                |p: &ToiProxy| sweep_time_of_impact(&proxy, &other_sweep, p, &fast_sweep, max, slop).fraction;
            // parry stops rounded shapes `slop` deep (its target is the sum of the radii less
            // the slop): a solid's rounding grown by twice the slop stops them `slop` apart,
            // as it does shapes with corners.
            let grown = whole
                .as_ref()
                .filter(|w| w.radius + proxy.radius > 0.0)
                .map(|w| ToiProxy::from_points(w.points(), w.radius + 2.0 * slop));
            let f = grown.as_ref().or(whole.as_ref()).map_or(0.0, |w| cast(w));
            hit(if f == 0.0 { cast(&core) } else { f })
        } else if other.start == other.end {
            // A mesh (static: parry sweeps against a composite that does not move), with its own
            // fallback to a ball where the solid starts in contact.
            let grown = whole
                .as_ref()
                .filter(|w| w.radius > 0.0)
                .map(|w| ToiProxy::from_points(w.points(), w.radius + 2.0 * slop));
            let proxy = grown.as_ref().or(whole.as_ref()).unwrap_or(&core);
            let shape = SweepCompositeFastShape {
                proxy,
                sweep: &fast_sweep,
                local_centroid: fast.com,
                min_extent: $min_extent,
            };
            sweep_time_of_impact_composite(
                other.shape.as_ref(),
                &pose(other.start),
                shape,
                false,
                false,
                max,
                slop,
            )
            .and_then(|o| hit(o.fraction))
        } else {
            None
        };
        // A pair in contact when the step began: the solver held the points it found, but a
        // part of the solid that was farther than the speculative distance (the far corner of
        // a box tumbling onto the ground) may have turned deep into the other. Where the end of
        // the sweep is more than `slop` deep and its start was not, the solid is put back to
        // where it was half `slop` deep (found by bisection on parry's penetration depth).
        let turned = if $core_only {
            let depth = |t: f64| {
                let (a, b) = (fast_sweep.transform_at(t), other_sweep.transform_at(t));
                // The other first: parry 0.31's contact of a shape with a half-space second
                // takes the half-space's pose the wrong way round.
                contact(&b, other.shape.as_ref(), &a, fast.shape.as_ref(), 0.0)
                    .ok()
                    .flatten()
                    .map_or(0.0, |c| -c.dist)
            };
            if depth(max) > slop && depth(0.0) < 0.5 * slop {
                let (mut lo, mut hi) = (0.0, max);
                for _ in 0..30 {
                    let mid = 0.5 * (lo + hi);
                    if depth(mid) > 0.5 * slop {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                hit(lo)
            } else {
                None
            }
        } else {
            None
        };
        match (swept, turned) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }};
}

/// The plane: an angle, a scalar inertia.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plane;

/// Space: a quaternion, an inertia tensor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Space3;

/// A contact point's id: its two features, the subshapes it is on, and how many points before
/// it in its manifold have the same two features (`same`).
///
/// Feature ids of parry are packed u32s; the subshape indices (triangles of a mesh) keep
/// points of different triangles apart. Parry can give two points of one manifold the same
/// pair of features (in the plane, both points where two boxes' faces meet, side by side or
/// stacked), which would make them one key: the warm start would then hand both points the
/// impulses and friction anchors of one of them. `same` tells them apart, in the order parry
/// gives them, which is the same from step to step while the features are. Mixing it all into
/// 64 bits is only a key for matching a point with last step's: a collision costs a warm
/// start, never a result.
fn pack(a: u32, b: u32, sub_a: u32, sub_b: u32, same: usize) -> u64 {
    let f = (u64::from(a) << 32) | u64::from(b);
    f ^ (u64::from(sub_a).wrapping_mul(0x9E37_79B9_7F4A_7C15))
        ^ (u64::from(sub_b).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        ^ (same as u64).wrapping_mul(0x1656_67B1_9E37_79F9)
}

/// The contact points of two shapes placed at poses `pa` and `pb`, from parry's contact
/// manifolds (one text for both of parry's crates: their types differ, their calls do not).
macro_rules! manifold_touches {
    ($parry:ident, $ga:expr, $gb:expr, $pa:expr, $pb:expr, $prediction:expr, $out:expr) => {{
        use $parry::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
        let (pa, pb) = ($pa, $pb);
        let pos12 = pa.inv_mul(&pb);
        let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
        // Every pair of the shapes physstep builds has a manifold generator in parry.
        if DefaultQueryDispatcher
            .contact_manifolds(&pos12, $ga.as_ref(), $gb.as_ref(), $prediction, &mut manifolds, &mut None)
            .is_ok()
        {
            for m in &manifolds {
                // A composite shape (a mesh, a polyline) gives points in its subshape's frame.
                let (sa, sb) = match &m.subshape_poses {
                    Some(s) => (s.pos1.map_or(pa, |p| pa * p), s.pos2.map_or(pb, |p| pb * p)),
                    None => (pa, pb),
                };
                let normal = sa.rotation * m.local_n1;
                for (k, c) in m.points.iter().enumerate() {
                    let same = m.points[..k].iter().filter(|e| (e.fid1, e.fid2) == (c.fid1, c.fid2)).count();
                    $out.push(Touch {
                        on_a: sa * c.local_p1,
                        on_b: sb * c.local_p2,
                        normal,
                        separation: c.dist,
                        id: pack(c.fid1.0, c.fid2.0, m.subshape1, m.subshape2, same),
                    });
                }
            }
        }
    }};
}

mod plane;
mod space3;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_on_the_same_two_features_get_ids_of_their_own_that_last_from_step_to_step() {
        use crate::contact::Shape;
        // Where two unit boxes' faces meet (one on the other, or side by side 1 cm apart),
        // parry gives both points of the manifold the same pair of features.
        let unit = Shape::Box { half: vec![0.5, 0.5] }.plane().unwrap();
        let ids = |at: DVec2| {
            let mut out = Vec::new();
            let q = Plane::basis(0.0);
            Plane::touches((&unit, DVec2::ZERO, q), (&unit, at, q), 0.02, &mut out);
            out.iter().map(|t| t.id).collect::<Vec<u64>>()
        };
        for (at, moved) in [
            (DVec2::new(0.1, 0.999), DVec2::new(0.1001, 0.9985)),
            (DVec2::new(1.01, 0.0), DVec2::new(1.0098, 0.0)),
        ] {
            let (before, after) = (ids(at), ids(moved));
            assert_eq!(before.len(), 2, "{at}: {before:?}");
            assert_ne!(before[0], before[1], "{at}: two points, one key");
            assert_eq!(before, after, "{at} -> {moved}: the ids moved with the points");
        }
        // In space: a cube on a cube, four points, four keys.
        let cube = Shape::Box { half: vec![0.5; 3] }.space().unwrap();
        let mut out = Vec::new();
        let (up, q) = (glam::DVec3::new(0.1, 0.999, 0.05), glam::DQuat::IDENTITY);
        Space3::touches((&cube, glam::DVec3::ZERO, q), (&cube, up, q), 0.02, &mut out);
        let mut ids: Vec<u64> = out.iter().map(|t| t.id).collect();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!((out.len(), ids.len()), (4, 4), "a cube on a cube");
    }

    #[test]
    fn the_planes_friction_size_is_the_square_roots_to_the_bit() {
        let sqrt = |x: f64| (x * x + 0.0 * 0.0).sqrt();
        let mut x = 0x2545_f491_4f6c_dd1d_u64;
        let mut checked = 0;
        for _ in 0..200_000 {
            // Random bit patterns (xorshift), every exponent, both signs.
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f64::from_bits(x);
            if !v.is_finite() {
                continue;
            }
            for t in [v, v * 1e-300, v * 1e300, -v, 1.0 + v.fract() * 1e-16] {
                if t.is_finite() {
                    assert_eq!(Plane::friction_size([t, 0.0]).to_bits(), sqrt(t).to_bits(), "{t:e}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 500_000);
        for t in [0.0, -0.0, 1e-150, 1e150, f64::MIN_POSITIVE, 5e-324, f64::MAX, f64::NAN, f64::INFINITY] {
            assert_eq!(Plane::friction_size([t, 0.0]).to_bits(), sqrt(t).to_bits(), "{t:e}");
            assert_eq!(Plane::friction_size([t, -0.0]).to_bits(), sqrt(t).to_bits(), "{t:e}");
        }
        // A second component (never set in the plane) is not dropped.
        assert_eq!(Plane::friction_size([3.0, 4.0]), 5.0);
        assert_eq!(Space3::friction_size([3.0, 4.0]), 5.0);
    }
}
