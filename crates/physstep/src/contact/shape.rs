//! The shapes of solids, as a user names them, validated, and built into the narrow phase's
//! shapes of the plane or of space.

use crate::error::{num, Error, Result};
use glam::{DVec2, DVec3};
use std::fmt;

/// A collision shape in its own frame (sizes in m). The same names serve the plane and space:
/// `Circle` is a disc in 2D and a sphere in 3D, `Box` takes as many half extents as the
/// world has dimensions, `Polygon` is a convex polygon in 2D (its corners in order) and the
/// convex hull of its points in 3D.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A disc (2D) or a sphere (3D).
    Circle {
        /// Radius, m (> 0).
        radius: f64,
    },
    /// A box of half extents `half` (one per dimension, each > 0).
    Box {
        /// Half extents, m.
        half: Vec<f64>,
    },
    /// A capsule along the shape's y axis: a segment of half length `half_height`, swept by
    /// a disc or sphere of `radius`.
    Capsule {
        /// Half the length of the core segment, m (> 0).
        half_height: f64,
        /// Radius, m (> 0).
        radius: f64,
    },
    /// A convex polygon (2D: the corners in order, either way round) or the convex hull of
    /// points (3D); flat coordinates, `dim` a point.
    Polygon {
        /// The points, flat.
        points: Vec<f64>,
    },
    /// A segment from `a` to `b`, thickened by `radius` (0: a bare segment, static or
    /// kinematic only: it has no area).
    Segment {
        /// One end, m.
        a: Vec<f64>,
        /// The other end, m.
        b: Vec<f64>,
        /// Radius, m (>= 0).
        radius: f64,
    },
    /// The half-space behind a plane through the body's origin (a line in 2D) with outward
    /// unit `normal`: the ground. Static or kinematic only.
    Plane {
        /// Outward normal (normalised when built).
        normal: Vec<f64>,
    },
    /// A triangle mesh (3D, static or kinematic only): `vertices` flat, three a vertex;
    /// `triangles` index them.
    Mesh {
        /// Vertices, flat.
        vertices: Vec<f64>,
        /// Triangles, three vertex indices each.
        triangles: Vec<[u32; 3]>,
    },
}

impl fmt::Display for Shape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

fn finite_positive(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, num(v), "finite and > 0"))
    }
}

fn finite_all(field: &str, v: &[f64]) -> Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(Error::invalid(format!("{field}[{i}]"), num(v[i]), "finite")),
        None => Ok(()),
    }
}

fn length(field: &str, v: &[f64], dim: usize) -> Result<()> {
    if v.len() == dim {
        Ok(())
    } else {
        Err(Error::invalid(format!("len({field})"), v.len(), format!("{dim}, the dimension")))
    }
}

fn list(v: &[f64]) -> String {
    let p: Vec<String> = v.iter().map(|x| num(*x)).collect();
    format!("[{}]", p.join(", "))
}

impl Shape {
    /// The shape's name (`circle`, `box`, ...), as scene files and the bindings spell it.
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Circle { .. } => "circle",
            Shape::Box { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Polygon { .. } => "polygon",
            Shape::Segment { .. } => "segment",
            Shape::Plane { .. } => "plane",
            Shape::Mesh { .. } => "mesh",
        }
    }

    /// Whether the shape encloses no volume (a plane, a mesh, a bare segment): such a solid
    /// can only be static or kinematic.
    #[must_use]
    pub fn is_massless(&self) -> bool {
        matches!(self, Shape::Plane { .. } | Shape::Mesh { .. } | Shape::Segment { radius: 0.0, .. })
    }

    /// Checks sizes and lengths for a world of `dim` dimensions.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the field (`radius`, `half[1]`, `points`, `normal`, ...)
    /// and the value.
    pub fn check(&self, dim: usize) -> Result<()> {
        match self {
            Shape::Circle { radius } => finite_positive("radius", *radius),
            Shape::Box { half } => {
                length("half", half, dim)?;
                for (i, h) in half.iter().enumerate() {
                    finite_positive(&format!("half[{i}]"), *h)?;
                }
                Ok(())
            }
            Shape::Capsule { half_height, radius } => {
                finite_positive("half_height", *half_height)?;
                finite_positive("radius", *radius)
            }
            Shape::Polygon { points } => {
                finite_all("points", points)?;
                if points.len() % dim != 0 {
                    return Err(Error::invalid("len(points)", points.len(), format!("a multiple of {dim}")));
                }
                let need = dim + 1;
                if points.len() / dim < need {
                    return Err(Error::invalid(
                        "points",
                        list(points),
                        format!("at least {need} points enclosing an area"),
                    ));
                }
                if dim == 2 {
                    convex_ccw(points).map(|_| ())
                } else {
                    Ok(())
                }
            }
            Shape::Segment { a, b, radius } => {
                length("a", a, dim)?;
                length("b", b, dim)?;
                finite_all("a", a)?;
                finite_all("b", b)?;
                if !(radius.is_finite() && *radius >= 0.0) {
                    return Err(Error::invalid("radius", num(*radius), "finite and >= 0"));
                }
                if a == b {
                    return Err(Error::invalid("b", list(b), "apart from a: a segment has a length"));
                }
                Ok(())
            }
            Shape::Plane { normal } => {
                length("normal", normal, dim)?;
                finite_all("normal", normal)?;
                let n: f64 = normal.iter().map(|x| x * x).sum::<f64>().sqrt();
                if n > 0.0 && n.is_finite() {
                    Ok(())
                } else {
                    Err(Error::invalid("normal", list(normal), "a non-zero direction"))
                }
            }
            Shape::Mesh { vertices, triangles } => {
                if dim != 3 {
                    return Err(Error::invalid("shape", "mesh", "a shape of a 3D world (meshes are 3D)"));
                }
                finite_all("vertices", vertices)?;
                if vertices.len() % 3 != 0 || vertices.len() < 9 {
                    return Err(Error::invalid(
                        "len(vertices)",
                        vertices.len(),
                        "a multiple of 3, at least 3 vertices",
                    ));
                }
                if triangles.is_empty() {
                    return Err(Error::invalid("triangles", "[]", "at least one triangle"));
                }
                let nv = vertices.len() / 3;
                for (t, tri) in triangles.iter().enumerate() {
                    if let Some(&k) = tri.iter().find(|&&k| k as usize >= nv) {
                        return Err(Error::invalid(
                            format!("triangles[{t}]"),
                            k,
                            format!("a vertex index below {nv}"),
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// The narrow phase's shape in the plane.
    ///
    /// # Errors
    /// As [`Shape::check`] with `dim = 2`.
    pub(crate) fn plane(&self) -> Result<parry2d_f64::shape::SharedShape> {
        use parry2d_f64::shape::SharedShape as S;
        self.check(2)?;
        Ok(match self {
            Shape::Circle { radius } => S::ball(*radius),
            Shape::Box { half } => S::cuboid(half[0], half[1]),
            Shape::Capsule { half_height, radius } => S::capsule_y(*half_height, *radius),
            Shape::Polygon { points } => {
                let p = convex_ccw(points)?;
                S::convex_polyline(p).ok_or_else(|| {
                    Error::invalid("points", list(points), "a convex polygon enclosing an area")
                })?
            }
            Shape::Segment { a, b, radius } => {
                let (a, b) = (DVec2::new(a[0], a[1]), DVec2::new(b[0], b[1]));
                if *radius > 0.0 {
                    S::capsule(a, b, *radius)
                } else {
                    S::segment(a, b)
                }
            }
            Shape::Plane { normal } => S::halfspace(DVec2::new(normal[0], normal[1]).normalize()),
            Shape::Mesh { .. } => {
                return Err(Error::invalid("shape", "mesh", "a shape of a 3D world (meshes are 3D)"));
            }
        })
    }

    /// The narrow phase's shape in space.
    ///
    /// # Errors
    /// As [`Shape::check`] with `dim = 3`, and `points` when they do not span a volume,
    /// `triangles` when the mesh is degenerate.
    pub(crate) fn space(&self) -> Result<parry3d_f64::shape::SharedShape> {
        use parry3d_f64::shape::SharedShape as S;
        self.check(3)?;
        let v3 = |c: &[f64]| DVec3::new(c[0], c[1], c[2]);
        Ok(match self {
            Shape::Circle { radius } => S::ball(*radius),
            Shape::Box { half } => S::cuboid(half[0], half[1], half[2]),
            Shape::Capsule { half_height, radius } => S::capsule_y(*half_height, *radius),
            Shape::Polygon { points } => {
                let p: Vec<DVec3> = points.chunks(3).map(v3).collect();
                let hull = S::convex_hull(&p)
                    .ok_or_else(|| Error::invalid("points", list(points), "points spanning a volume"))?;
                if hull.mass_properties(1.0).inv_mass <= 0.0 {
                    return Err(Error::invalid("points", list(points), "points spanning a volume"));
                }
                hull
            }
            Shape::Segment { a, b, radius } => {
                if *radius > 0.0 {
                    S::capsule(v3(a), v3(b), *radius)
                } else {
                    S::segment(v3(a), v3(b))
                }
            }
            Shape::Plane { normal } => S::halfspace(v3(normal).normalize()),
            Shape::Mesh { vertices, triangles } => {
                let v: Vec<DVec3> = vertices.chunks(3).map(v3).collect();
                S::trimesh(v, triangles.clone()).map_err(|e| {
                    Error::invalid("triangles", triangles.len(), format!("a valid mesh ({e})"))
                })?
            }
        })
    }
}

/// The corners of a 2D polygon, counter-clockwise, if they are convex and enclose an area.
fn convex_ccw(points: &[f64]) -> Result<Vec<DVec2>> {
    let mut p: Vec<DVec2> = points.chunks(2).map(|c| DVec2::new(c[0], c[1])).collect();
    let n = p.len();
    let area: f64 = (0..n).map(|i| p[i].perp_dot(p[(i + 1) % n])).sum::<f64>() / 2.0;
    let scale = p.iter().map(|q| q.length_squared()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    if area.abs() <= 1e-12 * scale {
        return Err(Error::invalid("points", list(points), "corners enclosing an area"));
    }
    if area < 0.0 {
        p.reverse();
    }
    for i in 0..n {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        if (b - a).perp_dot(c - b) < -1e-12 * scale {
            return Err(Error::invalid(
                "points",
                list(points),
                format!(
                    "a convex polygon, its corners in order (the turn at corner {} goes the other way)",
                    (i + 1) % n
                ),
            ));
        }
    }
    Ok(p)
}
