//! Copies and pickles of a `World`. A copy clones the engine (Python callables shared, as
//! functions are). A pickle is the engine's own: the world's structure as scene text
//! (`physstep::scenes::file::structure`: every part a world can hold but its code) and its
//! snapshot, with the Python callables the engine cannot hold beside them (forces, forces at
//! body points, a flow), pickled as Python pickles functions. `_world_from_scene` parses the
//! text, adds the callables back in order and restores the snapshot, so the copy continues
//! bitwise. The bindings keep no record of what was added: the engine is asked.
//!
//! The pickled `parts` are a dict: `scene` (the text), `loop` and `substeps` (the loop
//! variant to rebuild under: the text's own unless changed, as the demos do to switch a
//! world's loop), `forces` (the Python forces' specs), `body_forces` (`(body, point, spec)`),
//! `solid_forces` (`(solid, point, spec)`; absent from older pickles), `flow` (a Python
//! flow's spec, or None), and `family`, `force_ids`, `next_force_id` (the World's family
//! token and its forces' ids, so handles taken before pickling reach the same forces after;
//! absent from pickles written before handles, whose forces get ids in order), and
//! `contact_ids` (the ids of the solids, joints, solid springs and forces on solids with
//! their counters; absent from older pickles), and
//! `particle_ids`, `body_ids`, `constraint_ids`, `next_entity_ids` (the entities' ids and
//! counters, so handles of particles and constraints reach the same ones after a removal;
//! absent from older pickles, whose entities get ids in order), and `implicit` (the implicit
//! methods' settings, `set_implicit`'s and `line_search`; absent from older pickles, which
//! step with the defaults).

use crate::convert::{bytes, text};
use crate::force::PyForce;
use crate::handle::{raise, Inner, World};
use crate::py_err;
use crate::slot::Slot;
use physstep::clock::LoopMode;
use physstep::flows::Flow;
use physstep::forces::ForceId;
use physstep::world::{
    BodyForceId, BodyId, BodySpringId, ConstraintId, ParticleId, World as Engine, WorldParams,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

/// What `__reduce__` returns: the rebuilding function and its arguments.
pub(crate) type Reduce<'py> = (Bound<'py, PyAny>, (Bound<'py, PyAny>, Bound<'py, PyAny>));

/// `World.__reduce__` of a flushed world.
pub(crate) fn reduce<'py>(py: Python<'py>, g: &Inner) -> PyResult<Reduce<'py>> {
    let w = &g.engine;
    let scene = physstep::scenes::file::structure(w).map_err(py_err)?;
    let d = PyDict::new(py);
    d.set_item("scene", scene)?;
    let mode = w.clock().params().mode;
    d.set_item("loop", mode.name())?;
    d.set_item("substeps", if let LoopMode::StepsPerFrame(n) = mode { n } else { 1 })?;
    let forces = PyList::new(py, g.user.iter().map(|u| u.bind(py)))?;
    let body_forces = PyList::empty(py);
    for (body, point, spec) in &g.body_forces {
        body_forces.append((*body, point.to_vec(), spec.bind(py)))?;
    }
    let solid_forces = PyList::empty(py);
    for (solid, point, spec) in &g.solid_forces {
        solid_forces.append((*solid, point.clone(), spec.bind(py)))?;
    }
    if let (Some(Flow::User { .. }), None) = (w.flow(), &g.flow) {
        return Err(PyValueError::new_err("this World's flow is not a Python one: it cannot be pickled"));
    }
    // A callable that does not pickle (a lambda, a closure) is named here in one line, not
    // deep inside pickle's traceback.
    let pickle = py.import("pickle")?;
    let (dumps, refused) = (pickle.getattr("dumps")?, pickle.getattr("PicklingError")?);
    let check = |what: String, spec: &Bound<'py, PyAny>| -> PyResult<()> {
        dumps.call1((spec,)).map(|_| ()).map_err(|e| {
            let msg = format!(
                "this World cannot be pickled: its {what} does not pickle ({}); define it at module \
                 level, or copy the World instead (copy.copy)",
                physstep::error::one_line(&e.value(py).to_string())
            );
            refused.call1((msg,)).map_or_else(|e| e, PyErr::from_value)
        })
    };
    for (k, spec) in forces.iter().enumerate() {
        let name: String = spec.get_item(4)?.extract()?;
        check(format!("Python force {k} ('{name}')"), &spec)?;
    }
    for (k, item) in body_forces.iter().enumerate() {
        let name: String = item.get_item(2)?.get_item(4)?.extract()?;
        check(format!("Python force {k} at a body point ('{name}')"), &item)?;
    }
    for (k, item) in solid_forces.iter().enumerate() {
        let name: String = item.get_item(2)?.get_item(4)?.extract()?;
        check(format!("Python force {k} at a solid's point ('{name}')"), &item)?;
    }
    if let Some(f) = &g.flow {
        check("Python flow".into(), f.bind(py))?;
    }
    // The forces' ids and the family, so the handles taken before pickling reach the same
    // forces after (scene text carries no ids).
    d.set_item("family", g.family)?;
    d.set_item("force_ids", w.force_ids().iter().map(|id| id.0).collect::<Vec<u64>>())?;
    d.set_item("next_force_id", w.next_force_id().0)?;
    // The contact side's ids: solids, joints, solid springs, forces on solids, with their
    // counters (absent from older pickles: the ids in order).
    let contact_ids: [Vec<u64>; 4] = [
        w.solid_ids().iter().map(|i| i.0).collect(),
        w.joint_ids().iter().map(|i| i.0).collect(),
        w.solid_spring_ids().iter().map(|i| i.0).collect(),
        w.solid_force_ids().iter().map(|i| i.0).collect(),
    ];
    d.set_item("contact_ids", (contact_ids, w.next_solid_ids()))?;
    d.set_item("particle_ids", w.particle_ids().iter().map(|id| id.0).collect::<Vec<u64>>())?;
    d.set_item("body_ids", w.body_ids().iter().map(|id| id.0).collect::<Vec<u64>>())?;
    d.set_item("constraint_ids", w.constraint_ids().iter().map(|id| id.0).collect::<Vec<u64>>())?;
    let next = [w.next_particle_id().0, w.next_body_id().0, w.next_constraint_id().0];
    d.set_item("next_entity_ids", next.to_vec())?;
    d.set_item("body_spring_ids", w.body_spring_ids().iter().map(|id| id.0).collect::<Vec<u64>>())?;
    d.set_item("body_force_ids", w.body_force_ids().iter().map(|id| id.0).collect::<Vec<u64>>())?;
    d.set_item("next_body_link_ids", w.next_body_link_ids().to_vec())?;
    // The implicit methods' settings (`set_implicit`; absent from older pickles: the
    // defaults).
    let p = w.implicit();
    let implicit = PyDict::new(py);
    implicit.set_item("tol", p.tol)?;
    implicit.set_item("max_iter", p.max_iter)?;
    implicit.set_item("cg_tol", p.cg.tol)?;
    implicit.set_item("cg_max_iter", p.cg.max_iter)?;
    implicit.set_item("preconditioner", p.cg.preconditioner.name())?;
    implicit.set_item("dense_up_to", p.dense_up_to)?;
    implicit.set_item("line_search", p.line_search)?;
    implicit.set_item("exact_jacobian", p.exact_jacobian)?;
    implicit.set_item("energy_halvings", p.energy_halvings)?;
    d.set_item("implicit", implicit)?;
    d.set_item("forces", forces)?;
    d.set_item("body_forces", body_forces)?;
    d.set_item("solid_forces", solid_forces)?;
    d.set_item("flow", g.flow.as_ref().map(|f| f.bind(py)))?;
    let rebuild = py.import("physstep._core")?.getattr("_world_from_scene")?;
    Ok((rebuild, (d.into_any(), PyBytes::new(py, &w.snapshot()).into_any())))
}

/// Rebuilds a World pickled by `World.__reduce__`.
#[pyfunction]
pub(crate) fn _world_from_scene(
    py: Python<'_>,
    parts: &Bound<'_, PyDict>,
    snapshot: &Bound<'_, PyAny>,
) -> PyResult<World> {
    let get = |k: &str| -> PyResult<Bound<'_, PyAny>> {
        parts.get_item(k)?.ok_or_else(|| PyValueError::new_err(format!("invalid parts: no '{k}'")))
    };
    let scene = text(&get("scene")?, "scene")?;
    let mode =
        LoopMode::from_name(&text(&get("loop")?, "loop")?, get("substeps")?.extract()?).map_err(py_err)?;
    let mut engine =
        physstep::scenes::file::parse_structure(&scene, "a pickled World", mode).map_err(py_err)?.world;
    let slot = Slot::default();
    let flow = get("flow")?;
    let flow_spec = if flow.is_none() {
        None
    } else {
        let (func, jacobian, name, n): (Py<PyAny>, Option<Py<PyAny>>, String, usize) = flow.extract()?;
        let c = engine.clock().params();
        let params = WorldParams {
            dim: engine.dim(),
            method: engine.integrator().info().name.to_string(),
            dt: engine.dt(),
            mode,
            max_steps_per_frame: c.max_steps_per_frame,
            max_frame_time: c.max_frame_time,
            ..WorldParams::default()
        };
        let generator = crate::force::PyFlow { name, func, jacobian, slot: slot.clone() };
        let user_flow = Flow::User { n, generator: std::sync::Arc::new(generator) };
        engine = Engine::with_flow(user_flow, &vec![0.0; n], params).map_err(py_err)?;
        Some(flow.clone().unbind())
    };
    let mut user = Vec::new();
    for spec in get("forces")?.try_iter()? {
        let spec = spec?;
        let force = PyForce::from_spec(&spec, engine.dim(), &slot)?;
        engine.add_force_generator(std::sync::Arc::new(force)).map_err(py_err)?;
        user.push(spec.unbind());
    }
    let mut body_forces = Vec::new();
    for item in get("body_forces")?.try_iter()? {
        let item = item?;
        let (body, point): (usize, [f64; 3]) = (item.get_item(0)?.extract()?, item.get_item(1)?.extract()?);
        let spec = item.get_item(2)?.unbind();
        crate::world_bodies::add_force(py, &mut engine, &mut body_forces, body, point, spec, &slot)?;
    }
    let mut solid_forces = Vec::new();
    if let Some(items) = parts.get_item("solid_forces")? {
        for item in items.try_iter()? {
            let item = item?;
            let (solid, point): (usize, Vec<f64>) =
                (item.get_item(0)?.extract()?, item.get_item(1)?.extract()?);
            let spec = item.get_item(2)?.unbind();
            crate::world_solids::add_force(py, &mut engine, &mut solid_forces, solid, point, spec, &slot)?;
        }
    }
    // A pickle written before handles has no ids: the forces keep the ones given in order.
    if let (Some(ids), Some(next)) = (parts.get_item("force_ids")?, parts.get_item("next_force_id")?) {
        let ids: Vec<u64> = ids.extract()?;
        let ids: Vec<ForceId> = ids.into_iter().map(ForceId).collect();
        engine.set_force_ids(&ids, next.extract()?).map_err(py_err)?;
    }
    if let Some(ids) = parts.get_item("contact_ids")? {
        let (ids, next): ([Vec<u64>; 4], [u64; 4]) = ids.extract()?;
        engine.set_solid_ids([&ids[0], &ids[1], &ids[2], &ids[3]], next).map_err(py_err)?;
    }
    // The entities' ids likewise (the snapshot checks them once one was removed).
    if let Some(next) = parts.get_item("next_entity_ids")? {
        let next: [u64; 3] = next.extract()?;
        let ids = |k: &str| -> PyResult<Vec<u64>> { get(k)?.extract() };
        let p: Vec<ParticleId> = ids("particle_ids")?.into_iter().map(ParticleId).collect();
        let b: Vec<BodyId> = ids("body_ids")?.into_iter().map(BodyId).collect();
        let c: Vec<ConstraintId> = ids("constraint_ids")?.into_iter().map(ConstraintId).collect();
        engine.set_entity_ids(&p, &b, &c, next).map_err(py_err)?;
    }
    if let Some(next) = parts.get_item("next_body_link_ids")? {
        let next: [u64; 2] = next.extract()?;
        let springs: Vec<u64> = get("body_spring_ids")?.extract()?;
        let forces: Vec<u64> = get("body_force_ids")?.extract()?;
        let springs: Vec<BodySpringId> = springs.into_iter().map(BodySpringId).collect();
        let forces: Vec<BodyForceId> = forces.into_iter().map(BodyForceId).collect();
        engine.set_body_link_ids(&springs, &forces, next).map_err(py_err)?;
    }
    if let Some(implicit) = parts.get_item("implicit")? {
        let item = |k: &str| -> PyResult<Bound<'_, PyAny>> {
            implicit
                .get_item(k)
                .map_err(|_| PyValueError::new_err(format!("invalid parts: no implicit '{k}'")))
        };
        let mut p = engine.implicit();
        p.tol = item("tol")?.extract()?;
        p.max_iter = item("max_iter")?.extract()?;
        p.cg.tol = item("cg_tol")?.extract()?;
        p.cg.max_iter = item("cg_max_iter")?.extract()?;
        let name = text(&item("preconditioner")?, "preconditioner")?;
        p.cg.preconditioner = physstep::linalg::Preconditioner::named(&name)
            .ok_or_else(|| PyValueError::new_err(format!("invalid parts: preconditioner '{name}'")))?;
        p.dense_up_to = item("dense_up_to")?.extract()?;
        p.line_search = item("line_search")?.extract()?;
        p.exact_jacobian = item("exact_jacobian")?.extract()?;
        p.energy_halvings = item("energy_halvings")?.extract()?;
        engine.set_implicit(p).map_err(py_err)?;
    }
    engine.restore(&bytes(snapshot, "snapshot")?).map_err(|e| raise(&slot, e))?;
    let world = World::with_parts(engine, slot, user, flow_spec);
    let mut g = world.lock()?;
    g.body_forces = body_forces;
    g.solid_forces = solid_forces;
    if let Some(family) = parts.get_item("family")? {
        g.family = family.extract()?;
    }
    drop(g);
    Ok(world)
}
