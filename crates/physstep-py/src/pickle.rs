//! Copies and pickles of a `World`: a copy clones the engine (user forces shared, as
//! functions are); a pickle is the world's parts (settings, particles, forces, flow) and its
//! snapshot, rebuilt by `_world_from_parts`. Python forces and flows pickle as their
//! callables do (a lambda does not).

use crate::convert::{bytes, text};
use crate::force::{PyForce, Slot};
use crate::py_err;
use crate::world::{raise, World};
use physstep::clock::{ClockParams, LoopMode};
use physstep::flows::Flow;
use physstep::forces::{Endpoint, Force};
use physstep::world::{World as Engine, WorldParams};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

pub(crate) fn end(py: Python<'_>, j: Endpoint, dim: usize) -> PyResult<Py<PyAny>> {
    Ok(match j {
        Endpoint::Particle(j) => j.into_pyobject(py)?.into_any().unbind(),
        Endpoint::Anchor(p) => PyList::new(py, &p[..dim])?.into_any().unbind(),
    })
}

pub(crate) fn parse_end(o: &Bound<'_, PyAny>) -> PyResult<Endpoint> {
    if let Ok(j) = o.extract::<usize>() {
        return Ok(Endpoint::Particle(j));
    }
    let v: Vec<f64> = o.extract()?;
    let mut p = [0.0; 3];
    p[..v.len().min(3)].copy_from_slice(&v[..v.len().min(3)]);
    Ok(Endpoint::Anchor(p))
}

fn v3(v: Vec<f64>) -> [f64; 3] {
    let mut p = [0.0; 3];
    p[..v.len().min(3)].copy_from_slice(&v[..v.len().min(3)]);
    p
}

/// The parts of `w` as plain Python data; `user` are the Python forces' specs, `flow` a
/// Python flow's spec.
pub(crate) fn parts<'py>(
    py: Python<'py>,
    w: &Engine,
    user: &[Py<PyAny>],
    flow: Option<&Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let dim = w.dim();
    let c: &ClockParams = w.clock().params();
    d.set_item("dim", dim)?;
    d.set_item("method", w.integrator().info().name)?;
    d.set_item("dt", c.dt)?;
    d.set_item("max_steps_per_frame", c.max_steps_per_frame)?;
    d.set_item("max_frame_time", c.max_frame_time)?;
    d.set_item("loop", c.mode.name())?;
    d.set_item("substeps", if let LoopMode::StepsPerFrame(n) = c.mode { n } else { 1 })?;
    d.set_item("masses", w.model().mass().to_vec())?;
    d.set_item("static", w.model().inv_mass().iter().map(|m| *m == 0.0).collect::<Vec<_>>())?;
    d.set_item("positions", w.positions().to_vec())?;
    let forces = PyList::empty(py);
    for f in w.model().forces().iter() {
        let item: Bound<'_, PyTuple> = match *f {
            Force::Gravity { g } => ("gravity", g[..dim].to_vec()).into_pyobject(py)?,
            Force::Spring { i, j, stiffness, rest_length, damping } => {
                ("spring", i, end(py, j, dim)?, stiffness, rest_length, damping).into_pyobject(py)?
            }
            Force::Drag { linear, quadratic } => ("drag", linear, quadratic).into_pyobject(py)?,
            Force::CentralGravity { center, gm } => {
                ("central", center[..dim].to_vec(), gm).into_pyobject(py)?
            }
            Force::NBody { g, softening } => ("nbody", g, softening).into_pyobject(py)?,
            Force::Rod { i, j, length } => ("rod", i, end(py, j, dim)?, length).into_pyobject(py)?,
        };
        forces.append(item)?;
    }
    d.set_item("forces", forces)?;
    d.set_item("user_forces", PyList::new(py, user.iter().map(|u| u.bind(py)))?)?;
    let flow_item: Option<Bound<'_, PyAny>> = match (w.flow(), flow) {
        (_, Some(spec)) => Some(("user", spec.bind(py)).into_pyobject(py)?.into_any()),
        (Some(Flow::Lorenz { sigma, rho, beta }), None) => {
            Some(("lorenz", *sigma, *rho, *beta).into_pyobject(py)?.into_any())
        }
        (Some(Flow::Rossler { a, b, c }), None) => {
            Some(("rossler", *a, *b, *c).into_pyobject(py)?.into_any())
        }
        (Some(Flow::Thomas { b }), None) => Some(("thomas", *b).into_pyobject(py)?.into_any()),
        (Some(Flow::User { .. }), None) => {
            return Err(PyValueError::new_err("this World's flow is not a Python one: it cannot be pickled"))
        }
        (None, None) => None,
    };
    d.set_item("flow", flow_item)?;
    d.set_item("balls", crate::world_balls::parts(py, w)?)?;
    Ok(d)
}

/// Rebuilds the engine from `parts` (without its Python forces, which the caller adds);
/// `flow` is the world's flow, rebuilt by the caller (`n` its length).
pub(crate) fn engine(parts: &Bound<'_, PyDict>, flow: Option<(Flow, usize)>) -> PyResult<Engine> {
    let get = |k: &str| -> PyResult<Bound<'_, PyAny>> {
        parts.get_item(k)?.ok_or_else(|| PyValueError::new_err(format!("invalid parts: no '{k}'")))
    };
    let substeps: u32 = get("substeps")?.extract()?;
    let params = WorldParams {
        dim: get("dim")?.extract()?,
        method: text(&get("method")?, "method")?,
        dt: get("dt")?.extract()?,
        mode: LoopMode::from_name(&text(&get("loop")?, "loop")?, substeps).map_err(py_err)?,
        max_steps_per_frame: get("max_steps_per_frame")?.extract()?,
        max_frame_time: get("max_frame_time")?.extract()?,
        ..WorldParams::default()
    };
    if let Some((flow, n)) = flow {
        return Engine::with_flow(flow, &vec![0.0; n], params).map_err(py_err);
    }
    let masses: Vec<f64> = get("masses")?.extract()?;
    let fixed: Vec<bool> = get("static")?.extract()?;
    let x: Vec<f64> = get("positions")?.extract()?;
    let mut w = Engine::new(params).map_err(py_err)?;
    let d = w.dim();
    for (p, (m, s)) in masses.iter().zip(&fixed).enumerate() {
        w.add_particle(&x[p * d..(p + 1) * d], &vec![0.0; d], *m, *s).map_err(py_err)?;
    }
    for f in get("forces")?.try_iter()? {
        let f = f?;
        let kind: String = f.get_item(0)?.extract()?;
        let a = |k: usize| f.get_item(k);
        let force = match kind.as_str() {
            "gravity" => Force::Gravity { g: v3(a(1)?.extract()?) },
            "spring" => Force::Spring {
                i: a(1)?.extract()?,
                j: parse_end(&a(2)?)?,
                stiffness: a(3)?.extract()?,
                rest_length: a(4)?.extract()?,
                damping: a(5)?.extract()?,
            },
            "drag" => Force::Drag { linear: a(1)?.extract()?, quadratic: a(2)?.extract()? },
            "central" => Force::CentralGravity { center: v3(a(1)?.extract()?), gm: a(2)?.extract()? },
            "nbody" => Force::NBody { g: a(1)?.extract()?, softening: a(2)?.extract()? },
            "rod" => Force::Rod { i: a(1)?.extract()?, j: parse_end(&a(2)?)?, length: a(3)?.extract()? },
            other => return Err(PyValueError::new_err(format!("invalid parts: unknown force '{other}'"))),
        };
        w.add_force(force).map_err(py_err)?;
    }
    crate::world_balls::rebuild(&mut w, parts.get_item("balls")?)?;
    Ok(w)
}

/// The built-in flow in `parts`, if any: `(flow, length)`.
pub(crate) fn builtin_flow(item: &Bound<'_, PyAny>) -> PyResult<Option<(Flow, usize)>> {
    let kind: String = item.get_item(0)?.extract()?;
    let a = |k: usize| -> PyResult<f64> { item.get_item(k)?.extract() };
    Ok(match kind.as_str() {
        "lorenz" => Some((Flow::Lorenz { sigma: a(1)?, rho: a(2)?, beta: a(3)? }, 3)),
        "rossler" => Some((Flow::Rossler { a: a(1)?, b: a(2)?, c: a(3)? }, 3)),
        "thomas" => Some((Flow::Thomas { b: a(1)? }, 3)),
        _ => None,
    })
}

/// What `__reduce__` returns: the rebuilding function and its arguments.
pub(crate) type Reduce<'py> = (Bound<'py, PyAny>, (Bound<'py, PyAny>, Bound<'py, PyAny>));

/// A Python force as kept for pickling: func, potential, jacobian, velocity_dependent, name,
/// inplace.
pub(crate) type ForceSpec = (Py<PyAny>, Option<Py<PyAny>>, Option<Py<PyAny>>, bool, String, bool);

/// Rebuilds a World pickled by `World.__reduce__`.
#[pyfunction]
pub(crate) fn _world_from_parts(
    py: Python<'_>,
    parts: &Bound<'_, pyo3::types::PyDict>,
    snapshot: &Bound<'_, PyAny>,
) -> PyResult<World> {
    let slot = Slot::default();
    let flow_item = parts.get_item("flow")?.filter(|f| !f.is_none());
    let (flow, flow_spec) = match &flow_item {
        None => (None, None),
        Some(item) => match crate::pickle::builtin_flow(item)? {
            Some(f) => (Some(f), None),
            None => {
                let spec = item.get_item(1)?;
                let (func, jacobian, name, n): (Py<PyAny>, Option<Py<PyAny>>, String, usize) =
                    spec.extract()?;
                let generator = crate::force::PyFlow { name, func, jacobian, slot: slot.clone() };
                let flow = physstep::flows::Flow::User { n, generator: std::sync::Arc::new(generator) };
                (Some((flow, n)), Some(spec.unbind()))
            }
        },
    };
    let mut engine = crate::pickle::engine(parts, flow)?;
    let mut user = Vec::new();
    if let Some(list) = parts.get_item("user_forces")? {
        for spec in list.try_iter()? {
            let spec = spec?;
            let (func, potential, jacobian, velocity_dependent, name, inplace): ForceSpec = spec.extract()?;
            let dim = engine.dim();
            let force =
                PyForce::new(name, dim, func, potential, jacobian, velocity_dependent, inplace, slot.clone());
            engine.add_force_generator(std::sync::Arc::new(force)).map_err(py_err)?;
            user.push(spec.unbind());
        }
    }
    let mut bodies = crate::world_bodies::BodyLog::default();
    crate::world_bodies::rebuild(&mut engine, &mut bodies, parts, &slot)?;
    crate::world_constraints::rebuild(&mut engine, parts)?;
    engine.restore(&bytes(snapshot, "snapshot")?).map_err(|e| raise(&slot, e))?;
    let _ = py;
    let world = World::with_parts(engine, slot, user, flow_spec);
    world.lock()?.bodies = bodies;
    Ok(world)
}
