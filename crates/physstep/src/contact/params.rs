//! What a solid is as added: its [`Kind`] and its [`SolidParams`] (shape, pose, velocities,
//! density, friction, restitution, drag), before [`super::Solids::add`] checks and builds it.

use super::Shape;
use crate::error::{Error, Result};

/// How a solid moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Moved by gravity, forces and contacts.
    Dynamic,
    /// Never moves (the ground, walls).
    Static,
    /// Moves at the velocity it is given, pushes dynamic solids, is pushed by nothing.
    Kinematic,
}

impl Kind {
    /// The kind by name (`dynamic`, `static`, `kinematic`).
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the three.
    pub fn by_name(name: &str) -> Result<Kind> {
        match name {
            "dynamic" => Ok(Kind::Dynamic),
            "static" => Ok(Kind::Static),
            "kinematic" => Ok(Kind::Kinematic),
            _ => Err(Error::UnknownName {
                kind: "kind".into(),
                name: name.into(),
                valid: vec!["dynamic".into(), "static".into(), "kinematic".into()],
            }),
        }
    }

    /// The kind's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Kind::Dynamic => "dynamic",
            Kind::Static => "static",
            Kind::Kinematic => "kinematic",
        }
    }
}

/// A solid as it is added: what a scene file keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct SolidParams {
    /// The shape, in the solid's frame.
    pub shape: Shape,
    /// Dynamic, static or kinematic.
    pub kind: Kind,
    /// Where the shape's origin is, m.
    pub position: Vec<f64>,
    /// The angle (2D, rad) or the unit quaternion w, x, y, z (3D; normalised when added).
    pub orientation: Vec<f64>,
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec<f64>,
    /// Angular velocity (2D: one number, rad/s; 3D: a vector).
    pub angular_velocity: Vec<f64>,
    /// Density, kg/m^2 (2D) or kg/m^3 (3D).
    pub density: f64,
    /// Coulomb friction coefficient (>= 0); a pair uses the geometric mean of its two.
    pub friction: f64,
    /// Restitution in [0, 1]; a pair uses the larger of its two.
    pub restitution: f64,
    /// Linear drag, 1/s (>= 0): in each substep `v *= 1 / (1 + h c)` (Box2D's form).
    pub linear_damping: f64,
    /// Angular drag, 1/s (>= 0): in each substep `w *= 1 / (1 + h c)`.
    pub angular_damping: f64,
    /// A bullet (Box2D's): continuous collision sweeps it against the dynamic solids that are
    /// not bullets too, not only the static and kinematic ones, so a small fast solid does
    /// not pass through a box that can move. Only a dynamic solid may be one.
    pub bullet: bool,
}

impl SolidParams {
    /// A dynamic solid of `shape` at `position`, at rest, density 1, friction 0.6, no bounce,
    /// no drag, not a bullet.
    #[must_use]
    pub fn new(shape: Shape, position: &[f64]) -> Self {
        let dim = position.len();
        Self {
            shape,
            kind: Kind::Dynamic,
            position: position.to_vec(),
            orientation: if dim == 3 { vec![1.0, 0.0, 0.0, 0.0] } else { vec![0.0] },
            velocity: vec![0.0; dim],
            angular_velocity: vec![0.0; if dim == 3 { 3 } else { 1 }],
            density: 1.0,
            friction: 0.6,
            restitution: 0.0,
            linear_damping: 0.0,
            angular_damping: 0.0,
            bullet: false,
        }
    }
}
