//! The two spaces solids live in, as one trait: the plane (2D: an angle, a scalar inertia)
//! and space (3D: a quaternion, an inertia tensor). The solver, the broad phase and the
//! bodies are written once over [`Space`]; what differs (how a rotation turns a vector, how
//! an angular velocity crosses an arm, how a shape meets another) lives here, and the
//! narrow phase is parry's (parry2d-f64 / parry3d-f64, on the glam types physstep uses).

use glam::{DMat3, DQuat, DVec2, DVec3};
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
    /// The axis-aligned box around the shape placed at `(p, q)`, widened by `margin`.
    fn aabb(shape: &Self::Shape, p: Self::V, q: Self::Rot, margin: f64) -> ([f64; 3], [f64; 3]);
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
    /// The contact points of two shapes placed at their poses that are closer than
    /// `prediction`, appended to `out`.
    fn touches(
        a: (&Self::Shape, Self::V, Self::Rot),
        b: (&Self::Shape, Self::V, Self::Rot),
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

fn pack(a: u32, b: u32, sub_a: u32, sub_b: u32) -> u64 {
    // Feature ids of parry are packed u32s; the subshape indices (triangles of a mesh) keep
    // points of different triangles apart. Mixing the two into 64 bits is only a key for
    // matching a point with last step's: a collision costs a warm start, never a result.
    let f = (u64::from(a) << 32) | u64::from(b);
    f ^ (u64::from(sub_a).wrapping_mul(0x9E37_79B9_7F4A_7C15))
        ^ (u64::from(sub_b).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
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
                for c in &m.points {
                    $out.push(Touch {
                        on_a: sa * c.local_p1,
                        on_b: sb * c.local_p2,
                        normal,
                        separation: c.dist,
                        id: pack(c.fid1.0, c.fid2.0, m.subshape1, m.subshape2),
                    });
                }
            }
        }
    }};
}

impl Space for Plane {
    const DIM: usize = 2;
    const ROT: usize = 1;
    const TANGENTS: usize = 1;
    type V = DVec2;
    type W = f64;
    type Rot = f64;
    type Delta = DVec2;
    type InvI = f64;
    type Shape = parry2d_f64::shape::SharedShape;

    fn identity() -> f64 {
        0.0
    }
    fn no_delta() -> DVec2 {
        DVec2::X
    }
    fn no_inertia() -> f64 {
        0.0
    }
    fn cross_wv(w: f64, r: DVec2) -> DVec2 {
        DVec2::new(-w * r.y, w * r.x)
    }
    fn cross_vv(r: DVec2, v: DVec2) -> f64 {
        r.perp_dot(v)
    }
    fn apply(i: f64, w: f64) -> f64 {
        i * w
    }
    fn rotate(q: f64, v: DVec2) -> DVec2 {
        Self::rotate_by(Self::basis(q), v)
    }
    type Basis = (f64, f64);
    fn basis(q: f64) -> (f64, f64) {
        q.sin_cos()
    }
    fn rotate_by((s, c): (f64, f64), v: DVec2) -> DVec2 {
        DVec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
    }
    fn unrotate(q: f64, v: DVec2) -> DVec2 {
        Self::rotate(-q, v)
    }
    fn rotate_delta(q: DVec2, v: DVec2) -> DVec2 {
        q.rotate(v)
    }
    fn turn(q: f64, d: DVec2, w: f64, h: f64) -> (f64, DVec2) {
        let (s, c) = (h * w).sin_cos();
        (q + h * w, DVec2::new(c, s).rotate(d))
    }
    fn world_inverse_inertia(_q: f64, local: f64) -> f64 {
        local
    }
    fn tangents(n: DVec2) -> [DVec2; 2] {
        [n.perp(), DVec2::ZERO]
    }
    type Frame = ();
    fn frame(_n: DVec2) {}
    fn tangent(n: DVec2, _frame: (), _k: usize) -> DVec2 {
        n.perp()
    }
    /// One tangent: `|t0|`, which is `sqrt(t0^2)` to the bit (in binary floating point the
    /// square root of a correctly rounded square is the number's size, while the square is
    /// a normal number), without a square root on the solver's critical path.
    #[inline]
    fn friction_size(t: [f64; 2]) -> f64 {
        /// Out of line, so that the compiler does not take the square root anyway and select.
        #[cold]
        #[inline(never)]
        fn root(t: [f64; 2]) -> f64 {
            (t[0] * t[0] + t[1] * t[1]).sqrt()
        }
        let a = t[0].abs();
        if t[1] == 0.0 && a > 1e-150 && a < 1e150 {
            a
        } else {
            root(t)
        }
    }
    fn write_rot(q: f64, out: &mut Vec<f64>) {
        out.push(q);
    }
    fn read_rot(c: &[f64]) -> f64 {
        c[0]
    }
    fn read_rot_exact(c: &[f64]) -> f64 {
        c[0]
    }

    fn gyroscopic(_q: f64, _i_local: f64, w: f64, _h: f64) -> f64 {
        w
    }
    fn inertia(inv_i: f64) -> f64 {
        if inv_i > 0.0 {
            1.0 / inv_i
        } else {
            0.0
        }
    }
    fn relative(a: f64, b: f64) -> f64 {
        b - a
    }
    fn offset(a: f64, b: f64, rel: f64) -> f64 {
        b - a - rel
    }
    fn rotation_error(offset: f64, da: DVec2, db: DVec2) -> f64 {
        offset + da.perp_dot(db).atan2(da.dot(db))
    }
    fn turn_axis(_q: f64, axis: f64) -> f64 {
        axis
    }
    const SWINGS: usize = 0;
    fn swing_axes(_axis: f64) -> [f64; 2] {
        [0.0; 2]
    }
    fn point_solve(a: (f64, f64, DVec2), b: (f64, f64, DVec2), rhs: DVec2) -> DVec2 {
        let ((ma, ia, ra), (mb, ib, rb)) = (a, b);
        let m = ma + mb;
        let xy = -ra.y * ra.x * ia - rb.y * rb.x * ib;
        let k = glam::DMat2::from_cols(
            DVec2::new(m + ra.y * ra.y * ia + rb.y * rb.y * ib, xy),
            DVec2::new(xy, m + ra.x * ra.x * ia + rb.x * rb.x * ib),
        );
        let det = k.determinant();
        if det.abs() > 0.0 {
            k.inverse() * rhs
        } else {
            DVec2::ZERO
        }
    }
    fn angular_solve(ia: f64, ib: f64, rhs: f64) -> f64 {
        let k = ia + ib;
        if k > 0.0 {
            rhs / k
        } else {
            0.0
        }
    }

    fn build(shape: &crate::contact::Shape) -> crate::error::Result<Self::Shape> {
        shape.plane()
    }
    fn spin_energy(inv_i: f64, w: f64) -> f64 {
        if inv_i > 0.0 {
            w * w / inv_i
        } else {
            0.0
        }
    }
    fn mass_properties(shape: &Self::Shape, density: f64) -> (f64, DVec2, f64) {
        let m = shape.mass_properties(density);
        let mass = if m.inv_mass > 0.0 { 1.0 / m.inv_mass } else { 0.0 };
        (mass, m.local_com, m.inv_principal_inertia)
    }

    fn aabb(shape: &Self::Shape, p: DVec2, q: f64, margin: f64) -> ([f64; 3], [f64; 3]) {
        let b = shape.compute_aabb(&parry2d_f64::math::Pose::new(p, q));
        ([b.mins.x - margin, b.mins.y - margin, 0.0], [b.maxs.x + margin, b.maxs.y + margin, 0.0])
    }

    fn extents(shape: &Self::Shape, com: DVec2) -> (f64, f64) {
        let ball = shape.compute_local_bounding_sphere();
        (shape.ccd_thickness(), (ball.center - com).length() + ball.radius)
    }
    fn sweep_rotation(q0: f64, q1: f64, t: f64) -> f64 {
        // The unit complex numbers of the two angles, interpolated and normalised; the angle
        // counted from `q0` (unwrapped).
        let ((s0, c0), (s1, c1)) = (q0.sin_cos(), q1.sin_cos());
        let (c, s) = (c0 + (c1 - c0) * t, s0 + (s1 - s0) * t);
        q0 + (c0 * s - s0 * c).atan2(c0 * c + s0 * s)
    }
    fn time_of_impact(
        fast: &Swept<'_, Self>,
        min_extent: f64,
        other: &Swept<'_, Self>,
        core_only: bool,
        slop: f64,
        max: f64,
    ) -> Option<f64> {
        use parry2d_f64::math::Pose;
        sweep_toi!(
            parry2d_f64,
            |(p, q): (DVec2, f64)| Pose::new(p, q),
            fast,
            min_extent,
            other,
            core_only,
            slop,
            max
        )
    }

    fn touches(
        a: (&Self::Shape, DVec2, f64),
        b: (&Self::Shape, DVec2, f64),
        prediction: f64,
        out: &mut Vec<Touch<DVec2>>,
    ) {
        use parry2d_f64::math::Pose;
        manifold_touches!(parry2d_f64, a.0, b.0, Pose::new(a.1, a.2), Pose::new(b.1, b.2), prediction, out);
    }
}

impl Space for Space3 {
    const DIM: usize = 3;
    const ROT: usize = 4;
    const TANGENTS: usize = 2;
    type V = DVec3;
    type W = DVec3;
    type Rot = DQuat;
    type Delta = DQuat;
    type InvI = DMat3;
    type Shape = parry3d_f64::shape::SharedShape;

    fn identity() -> DQuat {
        DQuat::IDENTITY
    }
    fn no_delta() -> DQuat {
        DQuat::IDENTITY
    }
    fn no_inertia() -> DMat3 {
        DMat3::ZERO
    }
    fn cross_wv(w: DVec3, r: DVec3) -> DVec3 {
        w.cross(r)
    }
    fn cross_vv(r: DVec3, v: DVec3) -> DVec3 {
        r.cross(v)
    }
    fn apply(i: DMat3, w: DVec3) -> DVec3 {
        i * w
    }
    fn rotate(q: DQuat, v: DVec3) -> DVec3 {
        q * v
    }
    type Basis = DQuat;
    fn basis(q: DQuat) -> DQuat {
        q
    }
    fn rotate_by(q: DQuat, v: DVec3) -> DVec3 {
        q * v
    }
    fn unrotate(q: DQuat, v: DVec3) -> DVec3 {
        q.conjugate() * v
    }
    fn rotate_delta(q: DQuat, v: DVec3) -> DVec3 {
        q * v
    }
    fn turn(q: DQuat, d: DQuat, w: DVec3, h: f64) -> (DQuat, DQuat) {
        let r = DQuat::from_scaled_axis(w * h);
        ((r * q).normalize(), (r * d).normalize())
    }
    fn world_inverse_inertia(q: DQuat, local: DMat3) -> DMat3 {
        let r = DMat3::from_quat(q);
        r * local * r.transpose()
    }
    fn tangents(n: DVec3) -> [DVec3; 2] {
        let (a, b) = n.any_orthonormal_pair();
        [a, b]
    }
    type Frame = [DVec3; 2];
    fn frame(n: DVec3) -> [DVec3; 2] {
        Self::tangents(n)
    }
    fn tangent(_n: DVec3, frame: [DVec3; 2], k: usize) -> DVec3 {
        frame[k]
    }
    fn write_rot(q: DQuat, out: &mut Vec<f64>) {
        out.extend_from_slice(&[q.w, q.x, q.y, q.z]);
    }
    fn read_rot(c: &[f64]) -> DQuat {
        Self::read_rot_exact(c).normalize()
    }
    fn read_rot_exact(c: &[f64]) -> DQuat {
        DQuat::from_xyzw(c[1], c[2], c[3], c[0])
    }

    fn gyroscopic(q: DQuat, i_local: DMat3, w: DVec3, h: f64) -> DVec3 {
        if w == DVec3::ZERO || i_local == DMat3::ZERO {
            return w;
        }
        let wb = q.conjugate() * w;
        q * (wb + crate::rigid::orientation::implicit_gyroscopic_rate(i_local, wb, h) * h)
    }
    fn inertia(inv_i: DMat3) -> DMat3 {
        if inv_i.determinant() > 0.0 {
            inv_i.inverse()
        } else {
            DMat3::ZERO
        }
    }
    fn relative(a: DQuat, b: DQuat) -> DQuat {
        a.conjugate() * b
    }
    fn offset(a: DQuat, b: DQuat, rel: DQuat) -> DQuat {
        b * (a * rel).conjugate()
    }
    fn rotation_error(offset: DQuat, da: DQuat, db: DQuat) -> DVec3 {
        let e = db * offset * da.conjugate();
        let e = if e.w < 0.0 { -e } else { e };
        let v = e.xyz();
        let s = v.length();
        if s < 1e-9 {
            v * 2.0
        } else {
            v * (2.0 * s.atan2(e.w) / s)
        }
    }
    fn turn_axis(q: DQuat, axis: DVec3) -> DVec3 {
        q * axis
    }
    const SWINGS: usize = 2;
    fn swing_axes(axis: DVec3) -> [DVec3; 2] {
        Self::tangents(axis)
    }
    fn point_solve(a: (f64, DMat3, DVec3), b: (f64, DMat3, DVec3), rhs: DVec3) -> DVec3 {
        // K = (ma + mb) 1 - [ra]x Ia^-1 [ra]x - [rb]x Ib^-1 [rb]x, [r]x v = r x v.
        let skew = |r: DVec3| {
            DMat3::from_cols(
                DVec3::new(0.0, r.z, -r.y),
                DVec3::new(-r.z, 0.0, r.x),
                DVec3::new(r.y, -r.x, 0.0),
            )
        };
        let ((ma, ia, ra), (mb, ib, rb)) = (a, b);
        let (sa, sb) = (skew(ra), skew(rb));
        let k = DMat3::from_diagonal(DVec3::splat(ma + mb)) - sa * ia * sa - sb * ib * sb;
        let det = k.determinant();
        if det.abs() > 0.0 {
            k.inverse() * rhs
        } else {
            DVec3::ZERO
        }
    }
    fn angular_solve(ia: DMat3, ib: DMat3, rhs: DVec3) -> DVec3 {
        let k = ia + ib;
        let det = k.determinant();
        if det.abs() > 0.0 {
            k.inverse() * rhs
        } else {
            DVec3::ZERO
        }
    }

    fn build(shape: &crate::contact::Shape) -> crate::error::Result<Self::Shape> {
        shape.space()
    }
    fn spin_energy(inv_i: DMat3, w: DVec3) -> f64 {
        if inv_i.determinant() > 0.0 {
            w.dot(inv_i.inverse() * w)
        } else {
            0.0
        }
    }
    fn mass_properties(shape: &Self::Shape, density: f64) -> (f64, DVec3, DMat3) {
        let m = shape.mass_properties(density);
        let mass = if m.inv_mass > 0.0 { 1.0 / m.inv_mass } else { 0.0 };
        let r = DMat3::from_quat(m.principal_inertia_local_frame);
        (mass, m.local_com, r * DMat3::from_diagonal(m.inv_principal_inertia) * r.transpose())
    }

    fn aabb(shape: &Self::Shape, p: DVec3, q: DQuat, margin: f64) -> ([f64; 3], [f64; 3]) {
        let b = shape.compute_aabb(&parry3d_f64::math::Pose::from_parts(p, q));
        (
            [b.mins.x - margin, b.mins.y - margin, b.mins.z - margin],
            [b.maxs.x + margin, b.maxs.y + margin, b.maxs.z + margin],
        )
    }

    fn extents(shape: &Self::Shape, com: DVec3) -> (f64, f64) {
        let ball = shape.compute_local_bounding_sphere();
        (shape.ccd_thickness(), (ball.center - com).length() + ball.radius)
    }
    fn sweep_rotation(q0: DQuat, q1: DQuat, t: f64) -> DQuat {
        let q0 = if q0.dot(q1) < 0.0 { -q0 } else { q0 };
        (q0 * (1.0 - t) + q1 * t).normalize()
    }
    fn time_of_impact(
        fast: &Swept<'_, Self>,
        min_extent: f64,
        other: &Swept<'_, Self>,
        core_only: bool,
        slop: f64,
        max: f64,
    ) -> Option<f64> {
        use parry3d_f64::math::Pose;
        sweep_toi!(
            parry3d_f64,
            |(p, q): (DVec3, DQuat)| Pose::from_parts(p, q),
            fast,
            min_extent,
            other,
            core_only,
            slop,
            max
        )
    }

    fn touches(
        a: (&Self::Shape, DVec3, DQuat),
        b: (&Self::Shape, DVec3, DQuat),
        prediction: f64,
        out: &mut Vec<Touch<DVec3>>,
    ) {
        use parry3d_f64::math::Pose;
        manifold_touches!(
            parry3d_f64,
            a.0,
            b.0,
            Pose::from_parts(a.1, a.2),
            Pose::from_parts(b.1, b.2),
            prediction,
            out
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
