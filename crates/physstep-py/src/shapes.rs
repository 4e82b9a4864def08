//! Rigid-body shapes (`Sphere`, `Box`, `Cylinder`, `Capsule`, `Mesh`, subclasses of
//! `Shape`) and their mass properties (`MassProperties`); the shapes only solids take
//! (`Circle`, `Polygon`, `Segment`, `Plane`, subclasses of `SolidShape`), and the contact
//! shape of any shape object a solid takes (a solid also takes `Sphere`, `Box` with three
//! half extents or two in a 2D world, `Capsule` and a static `Mesh`).
//!
//! Native classes, not Python classes over a function: each holds the engine's
//! `rigid::inertia::Shape` itself, checked by the engine when it is made (a bad shape never
//! exists, and the ValueError is the engine's, naming the field), compared and hashed as
//! the engine's value, and taken by `World.add_body` as it is, with nothing to convert back.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

use crate::convert::{array, float, indices, invalid, matrix};
use crate::py_err;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use physstep::contact::Shape as Contact;
use physstep::rigid::inertia::{MassProperties as Props, Shape as Engine};
use pyo3::basic::CompareOp;
use pyo3::prelude::*;
use pyo3::types::{PyTuple, PyType};
use pyo3::PyClassInitializer;

/// A rigid-body shape in its own frame (sizes in m): Sphere, Box, Cylinder, Capsule or Mesh.
///
/// Shapes are immutable values: checked when made (ValueError naming the bad field), equal
/// when their sizes (a mesh's vertices and triangles) are, hashable, and they pickle.
#[pyclass(module = "physstep._core", subclass, frozen, name = "Shape")]
pub struct Shape(pub(crate) Engine);

/// Checks `shape` with the engine and makes it an instance of the subclass `sub`.
fn make<T: pyo3::PyClass<BaseType = Shape>>(shape: Engine, sub: T) -> PyResult<PyClassInitializer<T>> {
    shape.validate().map_err(py_err)?;
    Ok(PyClassInitializer::from(Shape(shape)).add_subclass(sub))
}

/// The engine shape of a Python one, or a ValueError naming `field`.
pub(crate) fn from_py(o: &Bound<'_, PyAny>, field: &str) -> PyResult<Engine> {
    match o.cast::<Shape>() {
        Ok(s) if matches!(s.get().0, Engine::Box { half_extents: [_, _, z] } if z == 0.0) => Err(invalid(
            field,
            o,
            "a 3D shape: Box(hx, hy) is a 2D box (for add_solid in a 2D world); give hz",
        )),
        Ok(s) => Ok(s.get().0.clone()),
        Err(_) => Err(invalid(field, o, "a shape: physstep.Sphere, Box, Cylinder, Capsule or Mesh")),
    }
}

/// `(n, 3)` int64 array of triangles.
fn triangle_array<'py>(py: Python<'py>, t: &[[usize; 3]]) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let flat: Vec<i64> = t.iter().flatten().map(|&i| i as i64).collect();
    let arr = Array2::from_shape_vec((t.len(), 3), flat)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    Ok(arr.into_pyarray(py))
}

#[pymethods]
impl Shape {
    /// The mass properties for a `mass` (kg) or a `density` (kg/m^3), at most one of them;
    /// with neither the density is 1 (mass = volume). ValueError naming `mass` or `density`.
    #[pyo3(signature = (mass=None, density=None))]
    fn mass_properties(
        &self,
        mass: Option<&Bound<'_, PyAny>>,
        density: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<MassProperties> {
        let mass = mass.filter(|m| !m.is_none()).map(|m| float(m, "mass")).transpose()?;
        let density = density.filter(|d| !d.is_none()).map(|d| float(d, "density")).transpose()?;
        self.0.mass_properties(mass, density).map(MassProperties).map_err(py_err)
    }

    /// Volume, m^3.
    #[getter]
    fn volume(&self) -> PyResult<f64> {
        self.0.volume().map_err(py_err)
    }

    fn __richcmp__(&self, other: &Bound<'_, PyAny>, op: CompareOp) -> PyResult<Py<PyAny>> {
        let py = other.py();
        let Ok(other) = other.cast::<Shape>() else { return Ok(py.NotImplemented()) };
        let same = self.0 == other.get().0;
        Ok(match op {
            CompareOp::Eq => same.into_pyobject(py)?.to_owned().into_any().unbind(),
            CompareOp::Ne => (!same).into_pyobject(py)?.to_owned().into_any().unbind(),
            _ => py.NotImplemented(),
        })
    }

    fn __hash__(&self) -> u64 {
        let mut h = DefaultHasher::new();
        // `+ 0.0` makes -0.0 hash as 0.0, which it equals; NaN never gets into a shape.
        let mut eat = |v: f64| (v + 0.0).to_bits().hash(&mut h);
        match &self.0 {
            Engine::Sphere { radius } => {
                eat(0.0);
                eat(*radius);
            }
            Engine::Box { half_extents } => {
                eat(1.0);
                half_extents.iter().for_each(|v| eat(*v));
            }
            Engine::Cylinder { radius, height } => {
                eat(2.0);
                eat(*radius);
                eat(*height);
            }
            Engine::Capsule { radius, height } => {
                eat(3.0);
                eat(*radius);
                eat(*height);
            }
            Engine::Mesh { vertices, triangles } => {
                eat(4.0);
                vertices.iter().flatten().for_each(|v| eat(*v));
                triangles.hash(&mut h);
            }
        }
        h.finish()
    }

    fn __repr__(&self) -> String {
        match &self.0 {
            Engine::Sphere { radius } => format!("Sphere(radius={radius:?})"),
            Engine::Box { half_extents: [x, y, z] } if *z == 0.0 => format!("Box(hx={x:?}, hy={y:?})"),
            Engine::Box { half_extents: [x, y, z] } => format!("Box(hx={x:?}, hy={y:?}, hz={z:?})"),
            Engine::Cylinder { radius, height } => format!("Cylinder(radius={radius:?}, height={height:?})"),
            Engine::Capsule { radius, height } => format!("Capsule(radius={radius:?}, height={height:?})"),
            Engine::Mesh { vertices, triangles } => {
                let volume = self.0.volume().unwrap_or(f64::NAN);
                format!(
                    "Mesh(<{} vertices>, <{} triangles>, volume={volume:?})",
                    vertices.len(),
                    triangles.len()
                )
            }
        }
    }

    /// Pickles as its class and its constructor's arguments.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyType>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let args = match &slf.get().0 {
            Engine::Sphere { radius } => PyTuple::new(py, [*radius])?,
            Engine::Box { half_extents: [x, y, z] } if *z == 0.0 => PyTuple::new(py, [*x, *y])?,
            Engine::Box { half_extents } => PyTuple::new(py, *half_extents)?,
            Engine::Cylinder { radius, height } | Engine::Capsule { radius, height } => {
                PyTuple::new(py, [*radius, *height])?
            }
            Engine::Mesh { vertices, triangles } => {
                let v = matrix(py, vertices.iter().flatten().copied().collect(), 3)?.into_any();
                PyTuple::new(py, [v, triangle_array(py, triangles)?.into_any()])?
            }
        };
        Ok((slf.get_type(), args))
    }
}

/// A solid ball of `radius` (m) centred on the origin. ValueError naming `radius` unless it
/// is in [1e-12, 1e12].
#[pyclass(module = "physstep._core", extends = Shape, frozen, name = "Sphere")]
pub struct Sphere;

#[pymethods]
impl Sphere {
    #[new]
    fn new(radius: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        make(Engine::Sphere { radius: float(radius, "radius")? }, Sphere)
    }

    /// Radius, m.
    #[getter]
    fn radius(slf: PyRef<'_, Self>) -> f64 {
        match slf.as_super().0 {
            Engine::Sphere { radius } => radius,
            _ => f64::NAN,
        }
    }
}

/// A solid box centred on the origin, edges along the axes, half edge lengths `hx`, `hy`,
/// `hz` (m). ValueError naming `half_extents[k]` unless each is in [1e-12, 1e12].
#[pyclass(module = "physstep._core", extends = Shape, frozen, name = "Box")]
pub struct BoxShape;

#[pymethods]
impl BoxShape {
    #[new]
    #[pyo3(signature = (hx, hy, hz=None))]
    fn new(
        hx: &Bound<'_, PyAny>,
        hy: &Bound<'_, PyAny>,
        hz: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (hx, hy) = (float(hx, "hx")?, float(hy, "hy")?);
        let Some(hz) = hz.filter(|z| !z.is_none()) else {
            // A 2D box (for a solid in a 2D world): hz = 0 marks it.
            physstep::contact::Shape::Box { half: vec![hx, hy] }.check(2).map_err(py_err)?;
            let flat = Engine::Box { half_extents: [hx, hy, 0.0] };
            return Ok(PyClassInitializer::from(Shape(flat)).add_subclass(BoxShape));
        };
        make(Engine::Box { half_extents: [hx, hy, float(hz, "hz")?] }, BoxShape)
    }

    /// Half the edge lengths along x, y and z, m.
    #[getter]
    fn half_extents(slf: PyRef<'_, Self>) -> (f64, f64, f64) {
        match slf.as_super().0 {
            Engine::Box { half_extents: [x, y, z] } => (x, y, z),
            _ => (f64::NAN, f64::NAN, f64::NAN),
        }
    }
}

/// The radius and height of a cylinder or capsule.
fn radius_height(s: &Engine) -> (f64, f64) {
    match s {
        Engine::Cylinder { radius, height } | Engine::Capsule { radius, height } => (*radius, *height),
        _ => (f64::NAN, f64::NAN),
    }
}

/// A solid circular cylinder of `radius` and length `height` (m) along its local z axis,
/// centred on the origin. ValueError naming `radius` or `height`.
#[pyclass(module = "physstep._core", extends = Shape, frozen, name = "Cylinder")]
pub struct Cylinder;

#[pymethods]
impl Cylinder {
    #[new]
    fn new(radius: &Bound<'_, PyAny>, height: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let (radius, height) = (float(radius, "radius")?, float(height, "height")?);
        make(Engine::Cylinder { radius, height }, Cylinder)
    }

    /// Radius, m.
    #[getter]
    fn radius(slf: PyRef<'_, Self>) -> f64 {
        radius_height(&slf.as_super().0).0
    }

    /// Length along local z, m.
    #[getter]
    fn height(slf: PyRef<'_, Self>) -> f64 {
        radius_height(&slf.as_super().0).1
    }
}

/// A capsule along local z centred on the origin: a cylinder of `radius` and length
/// `height` (m) closed by two hemispheres of the same radius (total length height + 2
/// radius). ValueError naming `radius` or `height`.
#[pyclass(module = "physstep._core", extends = Shape, frozen, name = "Capsule")]
pub struct Capsule;

#[pymethods]
impl Capsule {
    #[new]
    fn new(radius: &Bound<'_, PyAny>, height: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let (radius, height) = (float(radius, "radius")?, float(height, "height")?);
        make(Engine::Capsule { radius, height }, Capsule)
    }

    /// Radius of the cylinder and of the caps, m.
    #[getter]
    fn radius(slf: PyRef<'_, Self>) -> f64 {
        radius_height(&slf.as_super().0).0
    }

    /// Length of the cylindrical part alone, m.
    #[getter]
    fn height(slf: PyRef<'_, Self>) -> f64 {
        radius_height(&slf.as_super().0).1
    }
}

/// A closed, consistently oriented triangle mesh bounding a solid: `vertices` (n, 3), m,
/// and `triangles` (m, 3) vertex indices, each wound counter-clockwise seen from outside
/// (every edge shared by exactly two triangles, in opposite directions). Its mass
/// properties are exact. ValueError naming the bad field (`vertices[3][2]`,
/// `triangles[5]` for a hole, a flipped triangle or a non-manifold edge, `triangles` for
/// an inside-out or flat mesh).
#[pyclass(module = "physstep._core", extends = Shape, frozen, name = "Mesh")]
pub struct Mesh;

#[pymethods]
impl Mesh {
    #[new]
    fn new(vertices: &Bound<'_, PyAny>, triangles: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let v = array(vertices, "vertices", None, Some(3))?;
        let vertices = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let triangles = indices::<3>(triangles, "triangles")?;
        make(Engine::Mesh { vertices, triangles }, Mesh)
    }

    /// Vertex positions (n, 3), m: a copy.
    #[getter]
    fn vertices<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match &slf.as_super().0 {
            Engine::Mesh { vertices, .. } => matrix(py, vertices.iter().flatten().copied().collect(), 3),
            _ => matrix(py, Vec::new(), 3),
        }
    }

    /// Triangles (m, 3), vertex indices (int64): a copy.
    #[getter]
    fn triangles<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        match &slf.as_super().0 {
            Engine::Mesh { triangles, .. } => triangle_array(py, triangles),
            _ => triangle_array(py, &[]),
        }
    }
}

/// The mass properties of a shape of constant density (``Shape.mass_properties``): mass
/// (kg), volume (m^3), centre of mass (3,) in the shape's frame (m), inertia tensor about the
/// centre of mass (3, 3) in the shape's axes (kg m^2), its eigenvalues ascending
/// (``principal_moments``) and unit eigenvectors as rows (``principal_axes``, right-handed).
#[pyclass(module = "physstep._core", frozen, name = "MassProperties")]
pub struct MassProperties(Props);

#[pymethods]
impl MassProperties {
    /// Mass, kg.
    #[getter]
    fn mass(&self) -> f64 {
        self.0.mass
    }

    /// Volume, m^3.
    #[getter]
    fn volume(&self) -> f64 {
        self.0.volume
    }

    /// Centre of mass in the shape's frame (3,), m.
    #[getter]
    fn center<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.0.center)
    }

    /// Inertia tensor about the centre of mass (3, 3), shape axes, kg m^2 (symmetric).
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.0.inertia.iter().flatten().copied().collect(), 3)
    }

    /// The eigenvalues of ``inertia``, ascending (3,), kg m^2.
    #[getter]
    fn principal_moments<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.0.principal_moments)
    }

    /// The principal axes as rows (3, 3): ``R = principal_axes`` gives
    /// ``R @ inertia @ R.T == diag(principal_moments)``; orthonormal, determinant +1.
    #[getter]
    fn principal_axes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.0.principal_axes.iter().flatten().copied().collect(), 3)
    }

    fn __repr__(&self) -> String {
        let p = &self.0;
        format!(
            "MassProperties(mass={:?}, volume={:?}, center={:?}, principal_moments={:?})",
            p.mass, p.volume, p.center, p.principal_moments
        )
    }
}

/// A shape only solids take (sizes in m), checked when it is added to a world: `Circle`,
/// `Polygon`, `Segment` or `Plane`.
#[pyclass(module = "physstep._core", subclass, frozen, name = "SolidShape")]
pub struct SolidShape(pub(crate) Contact);

#[pymethods]
impl SolidShape {
    /// The shape's name: circle, polygon, segment or plane.
    #[getter]
    fn kind(&self) -> &'static str {
        self.0.name()
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

/// A disc in a 2D world, a sphere in a 3D one, of `radius` m.
#[pyclass(module = "physstep._core", extends = SolidShape, frozen, name = "Circle")]
pub struct Circle;

#[pymethods]
impl Circle {
    #[new]
    fn new(radius: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let radius = float(radius, "radius")?;
        Contact::Circle { radius }.check(2).map_err(py_err)?;
        Ok(PyClassInitializer::from(SolidShape(Contact::Circle { radius })).add_subclass(Circle))
    }
}

/// A convex polygon (2D: its corners in order, either way round) or the convex hull of
/// `points` (3D): an array of shape (n, dim), m.
#[pyclass(module = "physstep._core", extends = SolidShape, frozen, name = "Polygon")]
pub struct Polygon;

#[pymethods]
impl Polygon {
    #[new]
    fn new(points: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let raw = array(points, "points", None, Some(2))
            .or_else(|_| array(points, "points", None, Some(3)))
            .map_err(|_| invalid("points", points, "an array of real numbers of shape (n, 2) or (n, 3)"))?;
        Ok(PyClassInitializer::from(SolidShape(Contact::Polygon { points: raw })).add_subclass(Polygon))
    }
}

/// A segment from `a` to `b` (m), thickened by `radius` (0: a bare segment, static or
/// kinematic only).
#[pyclass(module = "physstep._core", extends = SolidShape, frozen, name = "Segment")]
pub struct Segment;

#[pymethods]
impl Segment {
    #[new]
    #[pyo3(signature = (a, b, radius=0.0))]
    fn new(a: &Bound<'_, PyAny>, b: &Bound<'_, PyAny>, radius: f64) -> PyResult<PyClassInitializer<Self>> {
        let a = array(a, "a", None, None)?;
        let b = array(b, "b", None, None)?;
        let s = Contact::Segment { a, b, radius };
        Ok(PyClassInitializer::from(SolidShape(s)).add_subclass(Segment))
    }
}

/// The ground: the half-space behind a plane (a line in 2D) through the solid's position,
/// with outward `normal`. Static or kinematic only.
#[pyclass(module = "physstep._core", extends = SolidShape, frozen, name = "Plane")]
pub struct PlaneShape;

#[pymethods]
impl PlaneShape {
    #[new]
    fn new(normal: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let normal = array(normal, "normal", None, None)?;
        Ok(PyClassInitializer::from(SolidShape(Contact::Plane { normal })).add_subclass(PlaneShape))
    }
}

/// The contact shape of any shape object a solid takes.
pub(crate) fn solid_shape(o: &Bound<'_, PyAny>) -> PyResult<Contact> {
    if let Ok(s) = o.cast::<SolidShape>() {
        return Ok(s.get().0.clone());
    }
    let expected = "a shape: physstep.Circle, Box, Capsule, Polygon, Segment, Plane, Sphere or Mesh";
    let Ok(s) = o.cast::<Shape>() else { return Err(invalid("shape", o, expected)) };
    Ok(match &s.get().0 {
        Engine::Sphere { radius } => Contact::Circle { radius: *radius },
        Engine::Box { half_extents: [x, y, z] } if *z == 0.0 => Contact::Box { half: vec![*x, *y] },
        Engine::Box { half_extents } => Contact::Box { half: half_extents.to_vec() },
        Engine::Capsule { radius, height } => Contact::Capsule { half_height: height / 2.0, radius: *radius },
        Engine::Mesh { vertices, triangles } => Contact::Mesh {
            vertices: vertices.iter().flatten().copied().collect(),
            triangles: triangles.iter().map(|t| t.map(|k| k as u32)).collect(),
        },
        Engine::Cylinder { .. } => {
            return Err(invalid("shape", o, "a shape solids take (a cylinder is not: use a Polygon hull)"))
        }
    })
}
