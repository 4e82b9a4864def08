//! Mass properties of rigid-body shapes: volume, mass, centre of mass, the inertia tensor
//! about the centre of mass, and its principal moments and axes, in SI units (m, kg,
//! kg m^2) for a body of constant density.
//!
//! The primitives ([`Shape::Sphere`], [`Shape::Box`], [`Shape::Cylinder`],
//! [`Shape::Capsule`]) use closed forms; a closed triangle mesh ([`Shape::Mesh`]) is
//! integrated exactly with the divergence theorem (see [`Shape::Mesh`]).

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::{DMat3, DVec3};

use crate::error::{num, Error, Result};
use crate::limits::{PARAM_MAX, PARAM_MIN};

/// A rigid-body shape in its own (body) frame. Sizes are in metres.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A solid ball centred on the origin.
    Sphere {
        /// Radius, m.
        radius: f64,
    },
    /// A solid box centred on the origin, its edges along the axes.
    Box {
        /// Half the edge lengths along x, y and z, m.
        half_extents: [f64; 3],
    },
    /// A solid circular cylinder centred on the origin, its axis along local z.
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Length along z, m.
        height: f64,
    },
    /// A capsule centred on the origin along local z: a cylinder of length `height` and
    /// radius `radius`, closed by two solid hemispheres of the same radius, so its total
    /// length is `height + 2 radius`.
    Capsule {
        /// Radius of the cylinder and of the caps, m.
        radius: f64,
        /// Length of the cylindrical part alone, m.
        height: f64,
    },
    /// A closed, consistently oriented triangle mesh bounding a solid: every triangle is
    /// wound counter-clockwise seen from outside (its normal `(b - a) x (c - a)` points
    /// out), and every directed edge `(a, b)` of a triangle appears exactly once, its
    /// reverse `(b, a)` exactly once in another triangle.
    ///
    /// Integrated exactly: each triangle `(a, b, c)` spans, with the origin, a signed
    /// tetrahedron of volume `d / 6` (`d = a . (b x c)`); by the divergence theorem the
    /// signed tetrahedra add up to the solid, whose integrals are then sums of
    /// `V = sum d / 6`, `int x = sum d (a + b + c) / 24` and
    /// `int x x^T = sum d (a a^T + b b^T + c c^T + s s^T) / 120` with `s = a + b + c` (the
    /// moments of a tetrahedron with a vertex at the origin). The vertices are first moved
    /// so that their mean is the origin, which keeps the sums well conditioned.
    Mesh {
        /// Vertex positions, m.
        vertices: Vec<[f64; 3]>,
        /// Triangles, as indices into `vertices`, counter-clockwise seen from outside.
        triangles: Vec<[usize; 3]>,
    },
}

/// The mass properties of a shape of constant density.
#[derive(Debug, Clone, PartialEq)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f64,
    /// Volume, m^3.
    pub volume: f64,
    /// Centre of mass in the shape's frame, m.
    pub center: [f64; 3],
    /// Inertia tensor about the centre of mass, axes those of the shape's frame, kg m^2.
    /// Symmetric: `inertia[i][j] == inertia[j][i]`.
    pub inertia: [[f64; 3]; 3],
    /// The eigenvalues of `inertia`, ascending, kg m^2.
    pub principal_moments: [f64; 3],
    /// The principal axes, one per row: `principal_axes[k]` is the unit eigenvector of
    /// `inertia` for `principal_moments[k]`, in the shape's frame. The rows are orthonormal
    /// and right-handed (as a matrix, determinant +1), so `R = principal_axes` gives
    /// `R inertia R^T = diag(principal_moments)`.
    pub principal_axes: [[f64; 3]; 3],
}

/// Volume, centre and inertia about the centre for density 1.
struct Unit {
    volume: f64,
    center: DVec3,
    inertia: DMat3,
}

impl Shape {
    /// Checks the shape: sizes finite and in [1e-12, 1e12]; for a mesh, at least 4
    /// vertices and 4 triangles, finite coordinates at most 1e12 in magnitude, indices in
    /// range, no repeated index in a triangle, closed and consistently oriented, and a
    /// positive enclosed volume (not inside out, not flat).
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the first bad field (`radius`, `half_extents[1]`,
    /// `height`, `vertices[3][2]`, `triangles[5][1]`, `triangles[5]`, ...).
    pub fn validate(&self) -> Result<()> {
        self.unit().map(|_| ())
    }

    /// The volume, m^3.
    ///
    /// # Errors
    /// As [`Shape::validate`].
    pub fn volume(&self) -> Result<f64> {
        self.unit().map(|u| u.volume)
    }

    /// The mass properties for a given `mass` (kg) or `density` (kg/m^3): at most one may
    /// be given; with neither, the density is 1 kg/m^3 (so the mass equals the volume).
    /// Each must be finite and in [1e-12, 1e12].
    ///
    /// Closed forms (mass `m`): sphere `I = 2/5 m r^2` about every axis; box with half
    /// extents `(x, y, z)`: `Ixx = m (y^2 + z^2) / 3` and so on; cylinder
    /// `Izz = m r^2 / 2`, `Ixx = Iyy = m (3 r^2 + h^2) / 12`. Capsule (cylinder of
    /// length `h`, two hemispherical caps of radius `r`): with
    /// `V = pi r^2 h + 4/3 pi r^3`, the cylinder's mass `mc = m pi r^2 h / V` and both
    /// caps' mass `ms = m 4/3 pi r^3 / V`,
    /// `Izz = mc r^2 / 2 + 2/5 ms r^2` and
    /// `Ixx = Iyy = mc (r^2 / 4 + h^2 / 12) + ms (2/5 r^2 + h^2 / 4 + 3/8 h r)`:
    /// a hemisphere of mass `mh` has `2/5 mh r^2` about a diameter of its flat face, so
    /// `(2/5 - 9/64) mh r^2` about its own centroid `3r/8` from that face, which lies
    /// `h/2 + 3r/8` from the capsule's centre.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `mass` when both are given, `mass` or `density` when
    /// out of range, or the bad field of the shape (as [`Shape::validate`]).
    pub fn mass_properties(&self, mass: Option<f64>, density: Option<f64>) -> Result<MassProperties> {
        if let (Some(m), Some(_)) = (mass, density) {
            return Err(Error::invalid("mass", num(m), "given alone: pass a mass or a density, not both"));
        }
        if let Some(m) = mass {
            size("mass", m)?;
        }
        if let Some(rho) = density {
            size("density", rho)?;
        }
        let unit = self.unit()?;
        let (mass, density) = if let Some(m) = mass {
            (m, m / unit.volume)
        } else {
            let rho = density.unwrap_or(1.0);
            (rho * unit.volume, rho)
        };
        let inertia = (unit.inertia * density).to_cols_array_2d();
        let (principal_moments, principal_axes) = symmetric_eigen(&inertia);
        Ok(MassProperties {
            mass,
            volume: unit.volume,
            center: unit.center.to_array(),
            inertia,
            principal_moments,
            principal_axes,
        })
    }

    /// Validates and integrates the shape at density 1.
    fn unit(&self) -> Result<Unit> {
        let diag = |x: f64, y: f64, z: f64| DMat3::from_diagonal(DVec3::new(x, y, z));
        match self {
            Self::Sphere { radius: r } => {
                let r = size("radius", *r)?;
                let volume = 4.0 / 3.0 * PI * r.powi(3);
                let i = 0.4 * volume * r * r;
                Ok(Unit { volume, center: DVec3::ZERO, inertia: diag(i, i, i) })
            }
            Self::Box { half_extents: h } => {
                for (k, &v) in h.iter().enumerate() {
                    size(&format!("half_extents[{k}]"), v)?;
                }
                let [x, y, z] = h.map(|v| v * v);
                let volume = 8.0 * h[0] * h[1] * h[2];
                let m3 = volume / 3.0;
                Ok(Unit {
                    volume,
                    center: DVec3::ZERO,
                    inertia: diag(m3 * (y + z), m3 * (x + z), m3 * (x + y)),
                })
            }
            Self::Cylinder { radius, height } => {
                let (r, h) = (size("radius", *radius)?, size("height", *height)?);
                let volume = PI * r * r * h;
                let (axial, across) = (volume * r * r / 2.0, volume * (3.0 * r * r + h * h) / 12.0);
                Ok(Unit { volume, center: DVec3::ZERO, inertia: diag(across, across, axial) })
            }
            Self::Capsule { radius, height } => {
                let (r, h) = (size("radius", *radius)?, size("height", *height)?);
                let (mc, ms) = (PI * r * r * h, 4.0 / 3.0 * PI * r.powi(3));
                let axial = mc * r * r / 2.0 + 0.4 * ms * r * r;
                let across =
                    mc * (r * r / 4.0 + h * h / 12.0) + ms * (0.4 * r * r + h * h / 4.0 + 0.375 * h * r);
                Ok(Unit { volume: mc + ms, center: DVec3::ZERO, inertia: diag(across, across, axial) })
            }
            Self::Mesh { vertices, triangles } => mesh_unit(vertices, triangles),
        }
    }
}

/// A 12-triangle box mesh centred on the origin, wound counter-clockwise seen from outside:
/// vertex `ix + 2 iy + 4 iz` is at `((2 ix - 1) hx, (2 iy - 1) hy, (2 iz - 1) hz)`.
/// Its mass properties equal those of [`Shape::Box`] with the same half extents.
#[must_use]
pub fn box_mesh(half_extents: [f64; 3]) -> Shape {
    let [hx, hy, hz] = half_extents;
    let vertices = (0..8)
        .map(|i| {
            let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
            [sign(1) * hx, sign(2) * hy, sign(4) * hz]
        })
        .collect();
    let triangles = vec![
        [0, 2, 1], // -z
        [1, 2, 3],
        [4, 5, 7], // +z
        [4, 7, 6],
        [0, 1, 5], // -y
        [0, 5, 4],
        [2, 6, 7], // +y
        [2, 7, 3],
        [0, 4, 6], // -x
        [0, 6, 2],
        [1, 3, 7], // +x
        [1, 7, 5],
    ];
    Shape::Mesh { vertices, triangles }
}

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations (until the
/// off-diagonal norm is below 1e-15 times the Frobenius norm, at most 50 sweeps).
///
/// Returns the eigenvalues ascending and the eigenvectors as rows, orthonormal and
/// right-handed (determinant +1). A diagonal matrix gives its diagonal exactly (sorted, ties
/// in axis order) and the matching coordinate axes (the last one negated when the sort is
/// an odd permutation). Only the symmetric part of `matrix` is used; entries should stay
/// below about 1e150 in magnitude (the norms square them), and a non-finite entry gives
/// non-finite results.
#[must_use]
#[allow(clippy::many_single_char_names)] // the textbook's names
pub(crate) fn symmetric_eigen(matrix: &[[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut a = *matrix;
    for (p, q) in [(0, 1), (0, 2), (1, 2)] {
        let mean = 0.5 * a[p][q] + 0.5 * a[q][p];
        (a[p][q], a[q][p]) = (mean, mean);
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let norm = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _ in 0..50 {
        let off = (a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2]).sqrt();
        if off.is_nan() || off <= 1e-15 * norm {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            let apq = a[p][q];
            if apq == 0.0 {
                continue;
            }
            // The rotation J (c on the diagonal, s at (p, q), -s at (q, p)) with
            // J^T A J zero at (p, q): t = tan(theta), the smaller root of
            // t^2 + 2 tau t - 1 = 0.
            let tau = (a[q][q] - a[p][p]) / (2.0 * apq);
            let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
            let c = 1.0 / (1.0 + t * t).sqrt();
            let s = t * c;
            let r = 3 - p - q;
            let (arp, arq) = (a[r][p], a[r][q]);
            a[p][p] -= t * apq;
            a[q][q] += t * apq;
            (a[p][q], a[q][p]) = (0.0, 0.0);
            a[r][p] = c * arp - s * arq;
            a[p][r] = a[r][p];
            a[r][q] = s * arp + c * arq;
            a[q][r] = a[r][q];
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let values = order.map(|j| a[j][j]);
    let mut axes = order.map(|j| [v[0][j], v[1][j], v[2][j]]);
    let [e0, e1, e2] = axes.map(DVec3::from_array);
    if e0.cross(e1).dot(e2) < 0.0 {
        axes[2] = axes[2].map(|x| -x);
    }
    (values, axes)
}

/// Checks a size: finite and in [1e-12, 1e12].
fn size(field: &str, value: f64) -> Result<f64> {
    if (PARAM_MIN..=PARAM_MAX).contains(&value) {
        Ok(value)
    } else {
        Err(Error::invalid(field, num(value), "a finite number > 0, in [1e-12, 1e12]"))
    }
}

/// `a b^T`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Checks that the mesh is a closed, consistently oriented triangle mesh (all but the sign
/// of its volume).
fn check_mesh(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> Result<()> {
    let n = vertices.len();
    if n < 4 {
        return Err(Error::invalid(
            "vertices",
            format!("{n} vertices"),
            "at least 4 vertices (a closed mesh)",
        ));
    }
    if triangles.len() < 4 {
        let value = format!("{} triangles", triangles.len());
        return Err(Error::invalid("triangles", value, "at least 4 triangles (a closed mesh)"));
    }
    for (i, v) in vertices.iter().enumerate() {
        for (k, &x) in v.iter().enumerate() {
            if !x.is_finite() || x.abs() > PARAM_MAX {
                let expected = "finite, at most 1e12 in magnitude";
                return Err(Error::invalid(format!("vertices[{i}][{k}]"), num(x), expected));
            }
        }
    }
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(k) = tri.iter().position(|&i| i >= n) {
            let expected = format!("a vertex index < {n} (the number of vertices)");
            return Err(Error::invalid(format!("triangles[{t}][{k}]"), tri[k], expected));
        }
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] {
            let expected = "three distinct vertex indices (a repeated index is a degenerate triangle)";
            return Err(Error::invalid(format!("triangles[{t}]"), format!("{tri:?}"), expected));
        }
    }
    let edges = |tri: &[usize; 3]| [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])];
    let mut count: HashMap<(usize, usize), usize> = HashMap::with_capacity(3 * triangles.len());
    for tri in triangles {
        for e in edges(tri) {
            *count.entry(e).or_insert(0) += 1;
        }
    }
    for (t, tri) in triangles.iter().enumerate() {
        for (a, b) in edges(tri) {
            let (fwd, back) = (count[&(a, b)], count.get(&(b, a)).copied().unwrap_or(0));
            let why = if fwd > 1 {
                format!(
                    "its edge ({a}, {b}) is in {fwd} triangles (a flipped triangle or a non-manifold edge)"
                )
            } else if back == 0 {
                format!("its edge ({a}, {b}) has no reverse ({b}, {a}) in any triangle (a hole or a flipped triangle)")
            } else if back > 1 {
                format!("the reverse ({b}, {a}) of its edge ({a}, {b}) is in {back} triangles (a non-manifold edge)")
            } else {
                continue;
            };
            let expected = format!("part of a closed, consistently oriented mesh, but {why}");
            return Err(Error::invalid(format!("triangles[{t}]"), format!("{tri:?}"), expected));
        }
    }
    Ok(())
}

/// Validates a mesh and integrates it at density 1 (see [`Shape::Mesh`]).
fn mesh_unit(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> Result<Unit> {
    check_mesh(vertices, triangles)?;
    #[allow(clippy::cast_precision_loss)] // a vertex count is far below 2^53
    let count = vertices.len() as f64;
    let origin = vertices.iter().map(|&v| DVec3::from_array(v)).sum::<DVec3>() / count;
    let (mut six_volume, mut six_abs) = (0.0, 0.0);
    let (mut first, mut second) = (DVec3::ZERO, DMat3::ZERO);
    for tri in triangles {
        let [p, q, r] = tri.map(|i| DVec3::from_array(vertices[i]) - origin);
        let det = p.dot(q.cross(r));
        let sum = p + q + r;
        six_volume += det;
        six_abs += det.abs();
        first += sum * det;
        second += (outer(p, p) + outer(q, q) + outer(r, r) + outer(sum, sum)) * det;
    }
    let volume = six_volume / 6.0;
    // Rounding in the sum is at most a few ulps of the sum of magnitudes: below that, the
    // mesh encloses nothing measurable.
    if six_volume.abs() <= 1e-12 * six_abs {
        let expected = "a mesh enclosing a volume, not a flat one";
        return Err(Error::invalid("triangles", format!("signed volume {}", num(volume)), expected));
    }
    if volume < 0.0 {
        let expected = concat!(
            "wound counter-clockwise seen from outside; the mesh is inside out ",
            "(triangles wound clockwise seen from outside)"
        );
        return Err(Error::invalid("triangles", format!("signed volume {}", num(volume)), expected));
    }
    let offset = first / (4.0 * six_volume);
    // Second moments about the centre of mass (parallel-axis theorem), then the inertia.
    let moments = second * (1.0 / 120.0) - outer(offset, offset) * volume;
    let trace = moments.x_axis.x + moments.y_axis.y + moments.z_axis.z;
    let inertia = DMat3::from_diagonal(DVec3::splat(trace)) - moments;
    Ok(Unit { volume, center: origin + offset, inertia })
}

#[cfg(test)]
#[path = "inertia_tests.rs"]
mod tests;
