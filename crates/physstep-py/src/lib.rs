//! Python bindings of physstep: conversion and error mapping only, no physics.
//!
//! One file per concern: `errors` (exception types and the mapping of engine errors),
//! `convert` (arguments in, arrays out), `registry` (methods and scenes), `record`
//! (`simulate`), `world` (`World`). Nothing panics across the boundary: every engine call
//! returns a `Result`, and every bad argument is a `ValueError` that names it.

mod convert;
mod errors;
mod force;
mod pickle;
mod record;
mod registry;
mod world;
mod world_build;
mod world_state;

use pyo3::prelude::*;

pub(crate) use errors::py_err;

/// The native module `physstep._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    registry::register(m)?;
    m.add_function(wrap_pyfunction!(record::simulate, m)?)?;
    m.add_class::<world::World>()?;
    m.add_function(wrap_pyfunction!(pickle::_world_from_parts, m)?)?;
    errors::register(m)?;
    Ok(())
}
