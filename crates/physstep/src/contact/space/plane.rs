//! The plane (2D): an angle, a scalar inertia; parry2d-f64 for the narrow phase.

use super::{pack, Plane, Space, Swept, Touch, CORE_FRACTION};
use glam::DVec2;
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
    fn unbasis(q: f64) -> (f64, f64) {
        Self::basis(-q)
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
        if t[1] == 0.0 && (a == 0.0 || (a > 1e-150 && a < 1e150)) {
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

    fn aabb(shape: &Self::Shape, p: DVec2, basis: (f64, f64), margin: f64) -> ([f64; 3], [f64; 3]) {
        let b = shape.compute_aabb(&pose(p, basis));
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
        a: (&Self::Shape, DVec2, (f64, f64)),
        b: (&Self::Shape, DVec2, (f64, f64)),
        prediction: f64,
        out: &mut Vec<Touch<DVec2>>,
    ) {
        manifold_touches!(parry2d_f64, a.0, b.0, pose(a.1, a.2), pose(b.1, b.2), prediction, out);
    }
}

/// parry's pose at `p` turned by `(sin, cos)` ([`Plane::basis`] of the angle): the pose
/// `Pose::new(p, angle)` makes, to the bit (parry's rotation from an angle is the standard
/// library's `sin_cos` of it, as `basis` is), without computing them again.
fn pose(p: DVec2, (s, c): (f64, f64)) -> parry2d_f64::math::Pose {
    parry2d_f64::math::Pose::from_parts(p, parry2d_f64::math::Rot2::from_cos_sin_unchecked(c, s))
}
