//! Scene files: `read_scene` (a TOML file into a World and its run length) and
//! `scene_file_text` (a World written as one). The engine parses and writes; this is glue.

use crate::convert::{float, text};
use crate::handle::World;
use crate::py_err;
use pyo3::prelude::*;

/// Reads the scene file at `path`: the World it describes and its `until` (None when the
/// file has none). ValueError naming the file, the line and the field for a bad file.
#[pyfunction]
pub(crate) fn read_scene(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<(World, Option<f64>)> {
    let path = text(path, "path")?;
    let loaded = py.detach(|| physstep::scenes::file::load(std::path::Path::new(&path))).map_err(py_err)?;
    crate::errors::warn_conflicts(py, loaded.world.constraint_conflicts())?;
    Ok((World::wrap(loaded.world), loaded.until))
}

/// `world` as the text of a scene file (`title` in its first comment line, `until` if
/// given). ValueError for what a file cannot hold (Python forces and flows, body springs,
/// bodies of a world that has stepped).
#[pyfunction]
#[pyo3(signature = (world, title, until=None))]
pub(crate) fn scene_file_text(
    world: &World,
    title: &Bound<'_, PyAny>,
    until: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let title = text(title, "title")?;
    let until = until.filter(|u| !u.is_none()).map(|u| float(u, "until")).transpose()?;
    let mut inner = world.lock()?;
    let engine = inner.flush()?;
    physstep::scenes::file::export(engine, &title, until).map_err(py_err)
}
