//! Python bindings of physstep: conversion and error mapping only, no physics.
//!
//! One file per concern: `errors` (exception types and the mapping of engine errors),
//! `convert` (arguments in, arrays out), `registry` (methods and scenes), `record`
//! (`simulate`), `views` (zero-copy `positions` and `velocities`), `world` (`World`; `world_build`, `world_state`, `world_bodies`, `world_constraints` hold its
//! methods by concern), `shapes` (rigid-body shapes and their mass properties), `scene_file` (TOML scene files in
//! and out), `force_handle` (what an `add_*` of a force returns), `entity_views`
//! (`w.particles[i]`, `w.bodies[b]`), `solid_handles` (what `add_solid`, `add_joint`,
//! `add_solid_spring`, `add_solid_force` return; `w.solids[i]`). Nothing
//! panics across the boundary: every engine call returns a `Result`, and every bad argument
//! is a `ValueError` that names it.

mod body_link_handle;
mod convert;
mod entity_handle;
mod entity_views;
mod errors;
mod force;
mod force_handle;
mod handle;
mod identity;
mod interrupt;
mod joint_handle;
mod lease;
mod pickle;
mod record;
mod registry;
mod scene_file;
mod shapes;
mod slot;
mod solid_handles;
mod views;
mod world;
mod world_balls;
mod world_bodies;
mod world_build;
mod world_constraints;
mod world_implicit;
mod world_solids;
mod world_state;

use pyo3::prelude::*;

pub(crate) use errors::py_err;

/// Large blocks (a recording's columns, a large world's state) as huge pages, kept for
/// reuse when freed: `physstep::alloc`.
#[global_allocator]
static ALLOC: physstep::alloc::HugePages = physstep::alloc::HugePages;

/// The native module `physstep._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    registry::register(m)?;
    m.add_function(wrap_pyfunction!(record::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(scene_file::read_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene_file::scene_file_text, m)?)?;
    m.add_class::<handle::World>()?;
    m.add_class::<force_handle::ForceHandle>()?;
    m.add_class::<entity_handle::ParticleHandle>()?;
    m.add_class::<entity_handle::ParticleHandles>()?;
    m.add_class::<entity_handle::ConstraintHandle>()?;
    m.add_class::<entity_handle::BodyHandle>()?;
    m.add_class::<body_link_handle::BodySpringHandle>()?;
    m.add_class::<body_link_handle::BodyForceHandle>()?;
    m.add_class::<entity_views::Particles>()?;
    m.add_class::<entity_views::Particle>()?;
    m.add_class::<entity_views::Bodies>()?;
    m.add_class::<entity_views::Body>()?;
    m.add_class::<solid_handles::SolidHandle>()?;
    m.add_class::<joint_handle::JointHandle>()?;
    m.add_class::<solid_handles::SolidSpringHandle>()?;
    m.add_class::<solid_handles::SolidForceHandle>()?;
    m.add_class::<solid_handles::Solids>()?;
    m.add_class::<shapes::Shape>()?;
    m.add_class::<shapes::Sphere>()?;
    m.add_class::<shapes::BoxShape>()?;
    m.add_class::<shapes::Cylinder>()?;
    m.add_class::<shapes::Capsule>()?;
    m.add_class::<shapes::Mesh>()?;
    m.add_class::<shapes::MassProperties>()?;
    m.add_class::<shapes::SolidShape>()?;
    m.add_class::<shapes::Circle>()?;
    m.add_class::<shapes::Polygon>()?;
    m.add_class::<shapes::Segment>()?;
    m.add_class::<shapes::PlaneShape>()?;
    m.add_function(wrap_pyfunction!(world_solids::contact_solvers, m)?)?;
    m.add_function(wrap_pyfunction!(world_solids::solver_infos, m)?)?;
    m.add_function(wrap_pyfunction!(world_bodies::orientation_rules, m)?)?;
    m.add_function(wrap_pyfunction!(world_bodies::angular_forms, m)?)?;
    m.add_function(wrap_pyfunction!(pickle::_world_from_scene, m)?)?;
    errors::register(m)?;
    Ok(())
}
