//! Space (3D): a quaternion, an inertia tensor; parry3d-f64 for the narrow phase.

use super::{pack, Space, Space3, Swept, Touch, CORE_FRACTION};
use glam::{DMat3, DQuat, DVec3};
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
    fn unbasis(q: DQuat) -> DQuat {
        q.conjugate()
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
        // Torque-free spin changes w only by `w x I w`, zero where the inertia is a multiple of
        // the identity (a cube, a sphere): w is then constant, exactly (the Newton step would
        // give it back with the roundings of two rotations and a solve).
        let isotropic = || i_local == DMat3::from_diagonal(DVec3::splat(i_local.x_axis.x));
        if w == DVec3::ZERO || i_local == DMat3::ZERO || isotropic() {
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
