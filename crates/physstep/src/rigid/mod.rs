//! Rigid bodies: mass properties of shapes and meshes, and the rules that move an
//! orientation.

pub mod body;
pub mod inertia;
pub mod orientation;
