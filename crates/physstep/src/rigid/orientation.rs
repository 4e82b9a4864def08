//! Orientation rules: how a drift of `h` seconds moves a rigid body's orientation.
//!
//! A rigid body carries its orientation `q` (a unit quaternion, body -> world; the matrix
//! `R` of `q` maps body coordinates to world coordinates) and its angular momentum `L` in the
//! world frame. Its principal inverse inertia `inv_inertia` is given in the body frame (the
//! principal axes are the body axes; a zero entry means an infinite moment about that axis).
//! The world angular velocity is `omega = R diag(inv_inertia) R^T L` ([`omega`]) and the
//! kinetic energy `L . omega / 2` ([`kinetic`]).
//!
//! A drift ([`drift`]) moves `q` over `h` seconds with `L` held constant: torque-free motion.
//! Torques enter only through the kicks `L += tau h` between drifts, which are not this
//! module's business. Since no rule ever touches `L`, `|L|` is exact under every rule; what
//! differs is how well the orientation (and with it the kinetic energy, which depends on `q`
//! through `omega`) follows the torque-free flow. Four rules, by [`Rule`]:
//!
//! * [`Rule::Matrix`]: the notes' `R' = R + h skew(omega) R`, re-orthonormalised by the polar
//!   decomposition. Exact axis, angle `atan(h |omega|)` instead of `h |omega|`: first order
//!   for a general body, second order when `omega` is constant (a sphere).
//! * [`Rule::Quaternion`]: the notes' `q' = q + h/2 (0, omega) q`, normalised. Angle
//!   `2 atan(h |omega| / 2)`: first order in general, second order for a sphere.
//! * [`Rule::Exponential`]: `q' = exp(h/2 (0, omega)) q` with `omega` frozen at the start of
//!   the step: exact for a sphere, first order in general.
//! * [`Rule::Splitting`] (the default): a symmetric composition of exact free rotations
//!   (Dullweber, Leimkuhler and McLachlan 1997; Touma and Wisdom 1994). Second order,
//!   symplectic, time-reversible; exact for a sphere and for an axisymmetric body. See
//!   [`drift`] for the pieces and their order.
//!
//! Every rule accepts a negative `h` (Yoshida's composition runs a substep backwards) and
//! returns a unit quaternion.

use glam::{DMat3, DQuat, DVec3};

use crate::error::{num, Error, Result};

/// A rule that moves an orientation over a drift, with the angular momentum held fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rule {
    /// The notes' matrix update `R' = R + h skew(omega) R`, re-orthonormalised (polar
    /// decomposition) and converted back to a quaternion. First order.
    Matrix,
    /// The notes' quaternion update `q' = q + h/2 (0, omega) q`, normalised. First order.
    Quaternion,
    /// The exact rotation `exp(h/2 (0, omega)) q` with `omega` frozen at the start of the step.
    /// First order in general, exact when `omega` is constant (a sphere).
    Exponential,
    /// Symmetric splitting into exact free rotations about `L` and the body axes. Second
    /// order, symplectic, time-reversible; exact for spheres and axisymmetric bodies.
    #[default]
    Splitting,
}

/// Every rule, in the order the notes introduce them (then the better ones).
pub const RULES: [Rule; 4] = [Rule::Matrix, Rule::Quaternion, Rule::Exponential, Rule::Splitting];

impl Rule {
    /// The rule's name: `matrix`, `quaternion`, `exponential` or `splitting`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Matrix => "matrix",
            Self::Quaternion => "quaternion",
            Self::Exponential => "exponential",
            Self::Splitting => "splitting",
        }
    }

    /// The rule of a name (as [`Rule::name`] gives it).
    ///
    /// # Errors
    /// [`Error::UnknownName`] (kind `orientation rule`) listing the valid names.
    pub fn from_name(name: &str) -> Result<Rule> {
        RULES
            .into_iter()
            .find(|r| r.name() == name)
            .ok_or_else(|| Error::unknown("orientation rule", name, RULES.iter().map(|r| r.name())))
    }

    /// One line on what the rule does.
    #[must_use]
    pub fn doc(self) -> &'static str {
        match self {
            Self::Matrix => {
                "R' = R + h skew(omega) R, polar re-orthonormalisation (first order; the notes' matrix rule)"
            }
            Self::Quaternion => "q' = q + h/2 (0, omega) q, normalised (first order; the notes' quaternion rule)",
            Self::Exponential => {
                "q' = exp(h/2 (0, omega)) q, omega frozen at the step's start (first order; exact for a sphere)"
            }
            Self::Splitting => {
                "symmetric splitting into exact free rotations (second order, symplectic, reversible)"
            }
        }
    }
}

/// Catto's implicit gyroscopic rate in the body frame: one Newton step on
/// `I (w - w1) + h w x I w = 0` from `w1`, `d w / h = -J^-1 (w1 x I w1)` with
/// `J = I + h (skew(w1) I - skew(I w1))` (GDC 2015, "Numerical methods"; Box2D, Bullet):
/// stable at any spin where the explicit term `-I^-1 (w x I w)` gains energy. `inertia` is
/// the body-frame inertia (not its inverse); at `h = 0` this is the explicit term.
#[must_use]
pub fn implicit_gyroscopic_rate(inertia: DMat3, w: DVec3, h: f64) -> DVec3 {
    let iw = inertia * w;
    let skew = |v: DVec3| {
        DMat3::from_cols(DVec3::new(0.0, v.z, -v.y), DVec3::new(-v.z, 0.0, v.x), DVec3::new(v.y, -v.x, 0.0))
    };
    let j = inertia + (skew(w) * inertia - skew(iw)) * h;
    -(j.inverse() * w.cross(iw))
}

/// The world angular velocity `omega = R diag(inv_inertia) R^T L`: `L` rotated into the body
/// frame, scaled by the principal inverse inertia, rotated back. `q` must be a unit quaternion.
#[must_use]
pub fn omega(q: DQuat, inv_inertia: DVec3, l: DVec3) -> DVec3 {
    q * (inv_inertia * (q.conjugate() * l))
}

/// The kinetic energy of rotation `L . omega / 2 = sum_i inv_inertia_i Pi_i^2 / 2`, with
/// `Pi = R^T L` the body-frame angular momentum.
#[must_use]
pub fn kinetic(q: DQuat, inv_inertia: DVec3, l: DVec3) -> f64 {
    let pi = q.conjugate() * l;
    0.5 * pi.dot(inv_inertia * pi)
}

/// Moves the orientation `q` (unit, body -> world) by a drift of `h` seconds (any sign) with
/// the world angular momentum `l` held fixed, by `rule`. Returns a unit quaternion.
///
/// # The splitting
///
/// In the body frame, with `Pi = R^T L` and `a` any number, the free Hamiltonian splits as
///
/// ```text
/// H = sum_i inv_inertia_i Pi_i^2 / 2 = a |Pi|^2 / 2 + sum_i (inv_inertia_i - a) Pi_i^2 / 2.
/// ```
///
/// Each piece has an exact flow. The piece `c_i Pi_i^2 / 2` keeps `Pi_i` and turns the body
/// about its own axis `e_i` at the constant body rate `c_i Pi_i`: `q' = q exp(e_i theta / 2)`
/// with `theta = h c_i Pi_i` (right multiplication: a rotation about a body axis). The piece
/// `a |Pi|^2 / 2` turns the body about the fixed world vector `L` at the rate `a |L|`:
/// `q' = exp(a h L / 2) q`. That piece commutes with every other one (`|Pi|^2` is a Casimir:
/// turning the body about `L` leaves `Pi` unchanged), so it costs no splitting error at all.
///
/// Choosing `a` equal to one of the `inv_inertia_i` removes that axis's piece. We choose the
/// median of the three: the two pieces left then have the smallest coefficients possible
/// (`inv_max - inv_mid` and `inv_mid - inv_min`, rather than the full spread
/// `inv_max - inv_min` that another choice leaves on one of them), and whenever two moments
/// are equal (a sphere, an axisymmetric body) the median is the repeated value, at most one
/// piece is left, and the drift is the exact solution. (The plain three-axis splitting,
/// `a = 0`, has three pieces that do not commute even for a sphere, so it is not exact there.)
/// For a body with three distinct moments
/// the step is the Strang composition
///
/// ```text
/// outer(h/2), then [middle(h) and the rotation about L by a |L| h], then outer(h/2),
/// ```
///
/// each sub-rotation computing `Pi` from the current orientation. The middle piece is the
/// axis with the *largest* moment (smallest inverse inertia) and the outer piece the one with
/// the smallest moment: measured on the 1 : 2 : 3 racket and on a generic 1 : 2 : 3 spin, that
/// order has the smallest error constant of the six (3.3 times smaller in angle than the
/// reverse order, 1.4 times in energy; see the tests). The composition is symmetric with
/// exact pieces, so the map is symplectic, time-reversible (`drift(-h)` undoes `drift(h)`)
/// and of second order; its energy error stays bounded over long runs.
///
/// A zero inverse inertia (an infinite moment) needs no special case.
#[must_use]
pub fn drift(rule: Rule, q: DQuat, inv_inertia: DVec3, l: DVec3, h: f64) -> DQuat {
    match rule {
        Rule::Matrix => drift_matrix(q, inv_inertia, l, h),
        Rule::Quaternion => {
            let w = omega(q, inv_inertia, l);
            (q + pure(w) * q * (0.5 * h)).normalize()
        }
        Rule::Exponential => (exp_pure(omega(q, inv_inertia, l) * (0.5 * h)) * q).normalize(),
        Rule::Splitting => drift_splitting(q, inv_inertia, l, h),
    }
}

/// Checks a user's quaternion, given as `[w, x, y, z]`, and returns it normalised (as a glam
/// quaternion, whose storage is `(x, y, z, w)`).
///
/// # Errors
/// [`Error::InvalidValue`] naming `field[i]` for a non-finite entry, or `field` when the
/// length is below `1e-12` (no rotation to normalise).
pub(crate) fn validate_quaternion(field: &str, wxyz: [f64; 4]) -> Result<DQuat> {
    crate::error::all_finite(field, &wxyz)?;
    // Scaled by the largest entry, so a huge quaternion (1e200) does not overflow to an
    // infinite length and a tiny one's length is computed exactly enough to compare.
    let scale = wxyz.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let length = if scale > 0.0 {
        scale * wxyz.iter().map(|v| (v / scale) * (v / scale)).sum::<f64>().sqrt()
    } else {
        0.0
    };
    if length < 1e-12 {
        let value = format!("[{}, {}, {}, {}]", num(wxyz[0]), num(wxyz[1]), num(wxyz[2]), num(wxyz[3]));
        return Err(Error::invalid(
            field,
            value,
            format!("a quaternion [w, x, y, z] of length >= 1e-12 (its length is {})", num(length)),
        ));
    }
    let [w, x, y, z] = wxyz.map(|v| (v / scale) / (length / scale));
    Ok(DQuat::from_xyzw(x, y, z, w).normalize())
}

/// Spherical linear interpolation between the orientations `a` and `b` (unit), for rendering
/// between two physics states.
///
/// Takes the shortest arc: if `a . b < 0` it interpolates towards `-b` (the same rotation), so
/// the turn is at most half a revolution. For `alpha` in `[0, 1]` the result turns from `a`
/// (`alpha = 0`) to `b` (`alpha = 1`, possibly as `-b`) about one fixed axis at a constant
/// angular rate: the orientation at the fraction `alpha` of the angle between them. Outside
/// `[0, 1]` it extrapolates along the same great circle. The angle is computed with `atan2`
/// and the weights with `sin(x)/x` (a series near 0), so nearly equal orientations
/// interpolate without dividing by a vanishing sine. Returns a unit quaternion.
#[must_use]
pub fn slerp(a: DQuat, b: DQuat, alpha: f64) -> DQuat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    // The angle between a and b as unit 4-vectors, in [0, pi/2] since a . b >= 0.
    let phi = 2.0 * (b - a).length().atan2((b + a).length());
    // sin(t phi) / sin(phi) = t sinc(t phi) / sinc(phi): finite as phi -> 0.
    let weight = |t: f64| t * sinc(t * phi) / sinc(phi);
    (a * weight(1.0 - alpha) + b * weight(alpha)).normalize()
}

/// The pure quaternion `(0, v)`.
fn pure(v: DVec3) -> DQuat {
    DQuat::from_xyzw(v.x, v.y, v.z, 0.0)
}

/// `sin(x) / x`, by its Taylor series near 0 (where the quotient would lose its meaning at
/// `x = 0` and relative accuracy is not needed from `sin` itself).
fn sinc(x: f64) -> f64 {
    let x2 = x * x;
    if x2 < 1e-6 {
        // Next term x^6 / 5040 < 2e-22: below the rounding of 1.
        1.0 - x2 / 6.0 * (1.0 - x2 / 20.0)
    } else {
        x.sin() / x
    }
}

/// `exp((0, v)) = (cos |v|, sin |v| v / |v|)`: the rotation by the angle `2 |v|` about `v`.
/// Accurate for small `|v|` (series for `sin(x)/x`) and for `v = 0` (the identity).
fn exp_pure(v: DVec3) -> DQuat {
    let angle = v.length();
    let s = sinc(angle);
    DQuat::from_xyzw(v.x * s, v.y * s, v.z * s, angle.cos())
}

/// `skew(w)`, the matrix with `skew(w) v = w x v`.
fn skew(w: DVec3) -> DMat3 {
    DMat3::from_cols(DVec3::new(0.0, w.z, -w.y), DVec3::new(-w.z, 0.0, w.x), DVec3::new(w.y, -w.x, 0.0))
}

/// The notes' matrix rule. `R' = (I + h skew(omega)) R` is not a rotation (its columns
/// stretch by `sqrt(1 + h^2 |omega|^2)` across `omega`); we replace it by its polar factor, the
/// nearest rotation in the Frobenius norm. Gram-Schmidt on the columns would keep the first
/// column's direction and push the error into the others, so the result would depend on the
/// body axes' order; the polar factor treats the axes alike and, here, is exactly the rotation
/// about `omega` by `atan(h |omega|)`: the axis stays exact, only the angle lags (by
/// `(h |omega|)^3 / 3` a step).
fn drift_matrix(q: DQuat, inv_inertia: DVec3, l: DVec3, h: f64) -> DQuat {
    let r = DMat3::from_quat(q);
    let stepped = r + skew(omega(q, inv_inertia, l)) * r * h;
    let rotation = polar(stepped);
    let q1 = DQuat::from_mat3(&rotation).normalize();
    // Continuity with the input: of the two quaternions of the rotation, the one near q.
    if q1.dot(q) < 0.0 {
        -q1
    } else {
        q1
    }
}

/// The orthogonal polar factor `M (M^T M)^(-1/2)` of a matrix with a positive determinant, by
/// Newton's iteration `X <- (X + X^-T) / 2` (Higham), scaled by `|det X|^(-1/3)` while far from
/// converged. It converges for every nonsingular `M` (here `det M = 1 + h^2 |omega|^2 > 0`),
/// quadratically near the end: a rotation to rounding in a few iterations.
fn polar(m: DMat3) -> DMat3 {
    let mut x = m;
    let mut scaled = true;
    for _ in 0..100 {
        let y = if scaled {
            let gamma = x.determinant().abs().cbrt().recip();
            x * gamma
        } else {
            x
        };
        let next = (y + y.inverse().transpose()) * 0.5;
        let change = (next - x).to_cols_array().iter().fold(0.0_f64, |acc, v| acc.max(v.abs()));
        x = next;
        if change < 1e-3 {
            scaled = false;
        }
        if change < 1e-9 {
            // Quadratic convergence: one more iteration takes the change below rounding.
            return (x + x.inverse().transpose()) * 0.5;
        }
    }
    x
}

/// The splitting rule (see [`drift`]).
fn drift_splitting(q: DQuat, inv_inertia: DVec3, l: DVec3, h: f64) -> DQuat {
    splitting(q, inv_inertia, l, h, split_axes(inv_inertia))
}

/// The axes `[outer, reference, middle]` of the splitting: by inverse inertia, decreasing
/// (stable: ties keep the axis order). The outer piece is the smallest moment, the reference
/// (`a`, whose piece vanishes) the median, the middle piece the largest moment.
fn split_axes(inv_inertia: DVec3) -> [usize; 3] {
    let inv = inv_inertia.to_array();
    let above = |i: usize, j: usize| inv[i].total_cmp(&inv[j]).is_gt();
    // Insertion sort of three, swapping only on a strict order: stable, without a call.
    let mut o = [0_usize, 1, 2];
    if above(o[1], o[0]) {
        o.swap(0, 1);
    }
    if above(o[2], o[1]) {
        o.swap(1, 2);
        if above(o[1], o[0]) {
            o.swap(0, 1);
        }
    }
    o
}

/// One splitting step with the axes `[outer, reference, middle]`:
/// `outer(h/2)`, `middle(h)` with the turn about `L`, `outer(h/2)`.
fn splitting(q: DQuat, inv_inertia: DVec3, l: DVec3, h: f64, axes: [usize; 3]) -> DQuat {
    let inv = inv_inertia.to_array();
    let [outer, reference, middle] = axes;
    let a = inv[reference];
    let c_outer = inv[outer] - a;
    let c_middle = inv[middle] - a;

    let q = body_turn(q, l, outer, c_outer, 0.5 * h);
    // The middle body piece and the turn about L commute (the turn about L leaves Pi
    // unchanged): apply both at once. The product of unit quaternions stays unit to
    // rounding; one normalisation at the end of the step is enough.
    let pi_middle = body_component(q, l, middle);
    let length = l.length();
    let about_l = if length > 0.0 {
        let (s, c) = sin_cos(0.5 * a * h * length);
        let u = l * (s / length);
        DQuat::from_xyzw(u.x, u.y, u.z, c)
    } else {
        DQuat::IDENTITY
    };
    let q = about_l * turn(q, middle, h * c_middle * pi_middle);
    body_turn(q, l, outer, c_outer, 0.5 * h).normalize()
}

/// The exact flow of `c Pi_i^2 / 2` over `h`: the body turns about its axis `i` by `h c Pi_i`.
#[inline]
fn body_turn(q: DQuat, l: DVec3, i: usize, c: f64, h: f64) -> DQuat {
    if c == 0.0 {
        return q;
    }
    turn(q, i, h * c * body_component(q, l, i))
}

/// `Pi_i = (R^T L)_i = (R e_i) . L`: the body-frame component `i` of `l`, from column `i` of
/// the rotation matrix of `q` (unit), without rotating the whole vector.
#[inline]
fn body_component(q: DQuat, l: DVec3, i: usize) -> f64 {
    let (x, y, z, w) = (q.x, q.y, q.z, q.w);
    let column = match i {
        0 => DVec3::new(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)),
        1 => DVec3::new(2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)),
        _ => DVec3::new(2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)),
    };
    column.dot(l)
}

/// `q exp(e_i angle / 2)`: `q` turned about its own axis `i` by `angle` (one `sin_cos`): the
/// product with a quaternion of one nonzero vector entry, written out (the same bits as the
/// full product, whose other terms are zeros).
#[inline]
fn turn(q: DQuat, i: usize, angle: f64) -> DQuat {
    let (s, c) = sin_cos(0.5 * angle);
    let (x, y, z, w) = (q.x, q.y, q.z, q.w);
    match i {
        0 => DQuat::from_xyzw(w * s + x * c, y * c + z * s, z * c - y * s, w * c - x * s),
        1 => DQuat::from_xyzw(x * c - z * s, w * s + y * c, z * c + x * s, w * c - y * s),
        _ => DQuat::from_xyzw(x * c + y * s, y * c - x * s, w * s + z * c, w * c - z * s),
    }
}

/// Below this angle (rad), [`sin_cos`] takes its Taylor polynomials.
const SMALL_ANGLE: f64 = 0.125;

/// `(sin x, cos x)`: the Taylor polynomials for `|x| <= 1/8` (the half angles of a game step:
/// `omega h / 2` is 0.008 on the racket), else the library's. The terms kept reach `x^11`
/// and `x^12`; the first left out is below `1/8^13 / 13! = 3e-22` for sin and `1/8^14 / 14!
/// = 5e-25` for cos, far under half an ulp, so the sum is as accurate as the library's
/// (within one rounding) at a fraction of its cost, and the same bits on every platform.
#[inline]
fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > SMALL_ANGLE {
        return x.sin_cos();
    }
    let x2 = x * x;
    let s = x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0 + x2 * (-1.0 / 39_916_800.0))));
    let s = x + x * (x2 * (-1.0 / 6.0 + s));
    let c = x2
        * (1.0 / 24.0
            + x2 * (-1.0 / 720.0
                + x2 * (1.0 / 40_320.0 + x2 * (-1.0 / 3_628_800.0 + x2 * (1.0 / 479_001_600.0)))));
    let c = 1.0 + x2 * (-0.5 + c);
    (s, c)
}

#[cfg(test)]
#[path = "orientation_tests.rs"]
mod tests;
