//! `World`'s methods that build it: particles, the built-in forces, Python forces.

use crate::convert::{array, float, index, text, vector};
use crate::entity_handle::{particle, ConstraintHandle, ParticleHandle, ParticleHandles};
use crate::force::PyForce;
use crate::force_handle::{ForceHandle, PYTHON};
use crate::handle::{Inner, World};
use crate::py_err;
use physstep::forces::{Endpoint, Force, ForceId};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The other end of a spring or rod: a particle index or an anchor point.
/// A `ParticleHandle` of the World whose state `g` is stands for the particle's current row.
pub(crate) fn endpoint(o: &Bound<'_, PyAny>, field: &str, g: &Inner) -> PyResult<Endpoint> {
    let dim = g.engine.dim();
    if crate::entity_handle::is_handle(o) {
        return Ok(Endpoint::Particle(particle(o, field, g)?));
    }
    if o.extract::<i64>().is_ok() && !o.is_instance_of::<pyo3::types::PyBool>() {
        return Ok(Endpoint::Particle(index(o, field)?));
    }
    let p = array(o, field, Some(dim), None)
        .map_err(|_| crate::convert::invalid(field, o, "a particle index or an anchor point"))?;
    let mut out = [0.0; 3];
    out[..dim].copy_from_slice(&p);
    Ok(Endpoint::Anchor(out))
}

/// The handle of force `id` of `world`, built-in or Python.
fn handle_of(world: &Bound<'_, World>, g: &Inner, id: ForceId) -> ForceHandle {
    let kind = g.engine.force(id).map_or(PYTHON, |f| f.kind());
    ForceHandle::new(world, g.family, id, kind)
}

#[pymethods]
impl World {
    /// Adds one particle at `position` (dim numbers, m) with `velocity` (m/s, default 0) and
    /// `mass` (kg, default 1; `inf` or `static=True` makes it immovable). Returns its handle
    /// (a `ParticleHandle`: `w.positions[h]`, `w.remove(h)`). Checked at once (ValueError naming the field); added in a batch before the world is
    /// next read or stepped, so spawn loops cost O(1) per particle.
    #[pyo3(signature = (position, velocity=None, mass=None, r#static=None))]
    fn add_particle(
        slf: &Bound<'_, Self>,
        position: &Bound<'_, PyAny>,
        velocity: Option<&Bound<'_, PyAny>>,
        mass: Option<&Bound<'_, PyAny>>,
        r#static: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ParticleHandle> {
        let mut g = slf.get().lock()?;
        let d = g.engine.dim();
        let position = vector(position, "position", d)?;
        let velocity = match velocity.filter(|v| !v.is_none()) {
            Some(v) => vector(v, "velocity", d)?,
            None => [0.0; 3],
        };
        let mass = mass.map_or(Ok(1.0), |m| float(m, "mass"))?;
        let fixed = r#static.map_or(Ok(false), |s| crate::convert::flag(s, "static"))?;
        let Inner { engine, pending, .. } = &mut *g;
        pending.push(engine, &position[..d], &velocity[..d], mass, fixed).map_err(py_err)?;
        // The waiting particles get their ids in order when they are added.
        let id = g.engine.next_particle_id().0 + g.pending.len() as u64 - 1;
        Ok(ParticleHandle { world: slf.clone().unbind(), family: g.family, id })
    }

    /// Adds many particles: `positions` (k, dim), optional `velocities` (k, dim) and
    /// `masses` (k,). Returns their handles as one `ParticleHandles` (a sequence of
    /// `ParticleHandle`s; `np.asarray` of it is their rows).
    #[pyo3(signature = (positions, velocities=None, masses=None, r#static=None))]
    fn add_particles<'py>(
        slf: &Bound<'py, Self>,
        positions: &Bound<'py, PyAny>,
        velocities: Option<&Bound<'py, PyAny>>,
        masses: Option<&Bound<'py, PyAny>>,
        r#static: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<ParticleHandles> {
        let mut g = slf.get().lock()?;
        let w = g.grow()?;
        let d = w.dim();
        let fixed = r#static.map_or(Ok(false), |s| crate::convert::flag(s, "static"))?;
        let x = array(positions, "positions", None, Some(d))?;
        let k = x.len() / d;
        let v = velocities
            .filter(|v| !v.is_none())
            .map(|v| array(v, "velocities", Some(k), Some(d)))
            .transpose()?;
        let m = masses.filter(|m| !m.is_none()).map(|m| array(m, "masses", Some(k), None)).transpose()?;
        let first = w.next_particle_id().0;
        w.add_particles(&x, v.as_deref(), m.as_deref(), fixed).map_err(py_err)?;
        Ok(ParticleHandles { world: slf.clone().unbind(), family: g.family, first, len: k as u64 })
    }

    /// Adds uniform gravity `g` (dim numbers, m/s^2) on every dynamic particle; returns its
    /// handle.
    fn add_gravity(slf: &Bound<'_, Self>, g: &Bound<'_, PyAny>) -> PyResult<ForceHandle> {
        let mut guard = slf.get().lock()?;
        let w = guard.flush()?;
        let g = vector(g, "g", w.dim())?;
        let id = w.add_force(Force::Gravity { g }).map_err(py_err)?;
        Ok(handle_of(slf, &guard, id))
    }

    /// Adds a damped spring (`stiffness` N/m, `damping` N s/m) from particle `i` to particle
    /// `j_or_anchor` or to a fixed anchor point; `rest_length` (m) defaults to the current
    /// distance. A zero rest length makes the linear spring F = -k d - c w. Returns its
    /// handle (`h.stiffness = ...`).
    #[pyo3(signature = (i, j_or_anchor, stiffness, rest_length=None, damping=None))]
    fn add_spring(
        slf: &Bound<'_, Self>,
        i: &Bound<'_, PyAny>,
        j_or_anchor: &Bound<'_, PyAny>,
        stiffness: &Bound<'_, PyAny>,
        rest_length: Option<&Bound<'_, PyAny>>,
        damping: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ForceHandle> {
        let mut guard = slf.get().lock()?;
        guard.flush()?;
        let i = particle(i, "i", &guard)?;
        let j = endpoint(j_or_anchor, "j_or_anchor", &guard)?;
        let w = &mut guard.engine;
        let stiffness = float(stiffness, "stiffness")?;
        let rest_length =
            rest_length.filter(|r| !r.is_none()).map(|r| float(r, "rest_length")).transpose()?;
        let damping = damping.map_or(Ok(0.0), |c| float(c, "damping"))?;
        let id = w.add_spring(i, j, stiffness, rest_length, damping).map_err(py_err)?;
        Ok(handle_of(slf, &guard, id))
    }

    /// Adds drag F = -(linear + quadratic |v|) v on every particle (N s/m, N s^2/m^2);
    /// returns its handle.
    #[pyo3(signature = (linear=None, quadratic=None))]
    fn add_drag(
        slf: &Bound<'_, Self>,
        linear: Option<&Bound<'_, PyAny>>,
        quadratic: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ForceHandle> {
        let linear = linear.map_or(Ok(0.0), |c| float(c, "linear"))?;
        let quadratic = quadratic.map_or(Ok(0.0), |c| float(c, "quadratic"))?;
        let mut g = slf.get().lock()?;
        let id = g.flush()?.add_force(Force::Drag { linear, quadratic }).map_err(py_err)?;
        Ok(handle_of(slf, &g, id))
    }

    /// Adds gravity towards a fixed `center` with parameter `gm` (m^3/s^2): a = -gm r / |r|^3;
    /// returns its handle.
    fn add_central_gravity(
        slf: &Bound<'_, Self>,
        center: &Bound<'_, PyAny>,
        gm: &Bound<'_, PyAny>,
    ) -> PyResult<ForceHandle> {
        let gm = float(gm, "gm")?;
        let mut g = slf.get().lock()?;
        let w = g.flush()?;
        let center = vector(center, "center", w.dim())?;
        let id = w.add_force(Force::CentralGravity { center, gm }).map_err(py_err)?;
        Ok(handle_of(slf, &g, id))
    }

    /// Adds mutual gravity between all particles (constant `g`, `softening` length m);
    /// returns its handle.
    #[pyo3(signature = (g=None, softening=None))]
    fn add_nbody_gravity(
        slf: &Bound<'_, Self>,
        g: Option<&Bound<'_, PyAny>>,
        softening: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ForceHandle> {
        let gval = g.map_or(Ok(1.0), |g| float(g, "g"))?;
        let softening = softening.map_or(Ok(0.0), |s| float(s, "softening"))?;
        let mut guard = slf.get().lock()?;
        let id = guard.flush()?.add_force(Force::NBody { g: gval, softening }).map_err(py_err)?;
        Ok(handle_of(slf, &guard, id))
    }

    /// Adds the notes' force-based rod from particle `i` to `j_or_anchor` (a particle or an
    /// anchor point); it holds the current distance (`length`, when given, must equal it).
    /// Returns its handle.
    #[pyo3(signature = (i, j_or_anchor, length=None))]
    fn add_rod(
        slf: &Bound<'_, Self>,
        i: &Bound<'_, PyAny>,
        j_or_anchor: &Bound<'_, PyAny>,
        length: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ForceHandle> {
        let mut guard = slf.get().lock()?;
        guard.flush()?;
        let i = particle(i, "i", &guard)?;
        let j = endpoint(j_or_anchor, "j_or_anchor", &guard)?;
        let w = &mut guard.engine;
        let length = length.filter(|l| !l.is_none()).map(|l| float(l, "length")).transpose()?;
        let id = w.add_rod(i, j, length).map_err(py_err)?;
        Ok(handle_of(slf, &guard, id))
    }

    /// Adds a force written in Python: `func(t, x, v)` gets the time and the positions and
    /// velocities of all particles as read-only (n, dim) arrays and returns the forces
    /// (n, dim), N; with `inplace=True` it is `func(t, x, v, out)` and writes the forces into
    /// `out` (n, dim, zeroed), returning None. It is called once per force evaluation; `x`
    /// and `v` are valid during the call only: views of the World's own state where the
    /// method evaluates there (no copy), else reused copies (keeping one past its call is
    /// warned once: keep `x.copy()`). `potential(x)` (J) makes the energy known;
    /// `jacobian(t, x, v)` returns (dF/dx, dF/dv), each (n dim, n dim), for the implicit
    /// methods; `velocity_dependent=False` saves re-evaluations when the force ignores v
    /// (velocity Verlet then evaluates once a step, from the stored derivative).
    /// An exception raised inside propagates unchanged, with the step rolled back. Returns
    /// the force's handle (kind `python`), which `remove` takes.
    #[pyo3(signature = (func, *, potential=None, jacobian=None, velocity_dependent=None, name=None, inplace=None))]
    #[allow(clippy::too_many_arguments)]
    fn add_force(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        func: &Bound<'_, PyAny>,
        potential: Option<&Bound<'_, PyAny>>,
        jacobian: Option<&Bound<'_, PyAny>>,
        velocity_dependent: Option<&Bound<'_, PyAny>>,
        name: Option<&Bound<'_, PyAny>>,
        inplace: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<ForceHandle> {
        let callable = |o: Option<&Bound<'_, PyAny>>, field: &str| -> PyResult<Option<Py<PyAny>>> {
            match o.filter(|o| !o.is_none()) {
                Some(o) if o.is_callable() => Ok(Some(o.clone().unbind())),
                Some(o) => Err(crate::convert::invalid(field, o, "callable")),
                None => Ok(None),
            }
        };
        let func = callable(Some(func), "func")?
            .ok_or_else(|| PyValueError::new_err("invalid func = None: must be callable"))?;
        let potential = callable(potential, "potential")?;
        let jacobian = callable(jacobian, "jacobian")?;
        let velocity_dependent =
            velocity_dependent.map_or(Ok(true), |v| crate::convert::flag(v, "velocity_dependent"))?;
        let inplace = inplace.map_or(Ok(false), |v| crate::convert::flag(v, "inplace"))?;
        let mut g = slf.get().lock()?;
        let k = g.engine.model().user_forces();
        let name = match name {
            Some(n) => text(n, "name")?,
            None => func
                .bind(py)
                .getattr("__name__")
                .and_then(|n| n.extract::<String>())
                .unwrap_or_else(|_| format!("force {k}")),
        };
        let slot = g.slot.clone();
        let w = g.flush()?;
        let force = PyForce::new(name, w.dim(), func, potential, jacobian, velocity_dependent, inplace, slot);
        let spec = force.spec(py)?.unbind();
        let id = w.add_force_generator(std::sync::Arc::new(force)).map_err(py_err)?;
        g.user.push(spec);
        Ok(ForceHandle::new(slf, g.family, id, PYTHON))
    }

    /// Removes what `handle` names: a force (what `add_gravity`, `add_spring`, `add_drag`,
    /// `add_central_gravity`, `add_nbody_gravity`, `add_rod` and `add_force` return), a
    /// particle or ball (`add_particle`, `add_ball`; `add_particles` and `add_balls` return
    /// `ParticleHandles`, removed all at once), or a constraint (`add_distance_constraint`,
    /// `add_pin`, `add_rope`, `add_distance_limit`, `add_plane`), a rigid body (`add_body`:
    /// with the body springs and forces at its points), a body spring (`add_body_spring`) or
    /// a force at a body point (`add_body_force`). The World then steps
    /// bitwise as one that never had it. A particle takes with it the springs, rods, body
    /// springs and constraints with an end on it (their handles are no longer alive); the
    /// particles after it move up a row, in their order. The other handles stay valid.
    ///
    /// Also a solid, joint, solid spring or force on a solid (their handles; a solid takes
    /// its joints, springs and forces with it: docs/contact.md).
    fn remove(&self, handle: &Bound<'_, PyAny>) -> PyResult<()> {
        if crate::solid_handles::remove_solid_like(self, handle)?
            || crate::joint_handle::remove_joint(self, handle)?
        {
            return Ok(());
        }
        if let Ok(h) = handle.cast::<ParticleHandle>() {
            let mut g = self.lock()?;
            g.grow()?;
            let row = h.get().row_in(&g, "particle")?;
            let id = g.engine.particle_id(row).ok_or_else(|| PyValueError::new_err("invalid particle"))?;
            g.engine.remove_particle(id).map_err(py_err)?;
            return Ok(());
        }
        if let Ok(h) = handle.cast::<ParticleHandles>() {
            let mut g = self.lock()?;
            g.grow()?;
            // Every one checked before any goes: the World unchanged on an error.
            let rows = h.get().rows_in(&g)?;
            let ids: Vec<_> = rows.iter().filter_map(|&r| g.engine.particle_id(r)).collect();
            g.engine.remove_particles(&ids).map_err(py_err)?;
            return Ok(());
        }
        if let Ok(h) = handle.cast::<crate::entity_handle::BodyHandle>() {
            let mut g = self.lock()?;
            g.grow()?;
            let b = h.get().row_in(&g, "body")?;
            let id = g.engine.body_id(b).ok_or_else(|| PyValueError::new_err("invalid body"))?;
            let (gone, _) = g.engine.remove_body(id).map_err(py_err)?;
            // The Python forces at its points went with it; the others' bodies move up.
            for k in gone.into_iter().rev() {
                g.body_forces.remove(k);
            }
            for f in &mut g.body_forces {
                if f.0 > b {
                    f.0 -= 1;
                }
            }
            return Ok(());
        }
        if let Ok(h) = handle.cast::<crate::body_link_handle::BodySpringHandle>() {
            let mut g = self.lock()?;
            let id = h.get().id_in(&g)?;
            return g.flush()?.remove_body_spring(id).map_err(py_err);
        }
        if let Ok(h) = handle.cast::<crate::body_link_handle::BodyForceHandle>() {
            let mut g = self.lock()?;
            let id = h.get().id_in(&g)?;
            let k = g.flush()?.remove_body_force(id).map_err(py_err)?;
            g.body_forces.remove(k);
            return Ok(());
        }
        if let Ok(h) = handle.cast::<ConstraintHandle>() {
            let mut g = self.lock()?;
            let id = h.get().id_in(&g)?;
            return g.flush()?.remove_constraint(id).map_err(py_err);
        }
        let h = handle.cast::<ForceHandle>().map_err(|_| {
            crate::convert::invalid(
                "handle",
                handle,
                "a ForceHandle, ParticleHandle, ParticleHandles, ConstraintHandle, BodyHandle, BodySpringHandle, BodyForceHandle, SolidHandle, JointHandle, SolidSpringHandle or SolidForceHandle (what an add_* returns)",
            )
        })?;
        let mut g = self.lock()?;
        let id = h.get().id_in(g.family)?;
        let at = g.engine.user_force_index(id);
        g.flush()?.remove_force(id).map_err(py_err)?;
        if let Some(at) = at {
            g.user.remove(at);
        }
        Ok(())
    }

    /// The handle in this World of the force `handle` names (a handle of the World this one
    /// was copied or unpickled from reaches the same force here).
    fn force(slf: &Bound<'_, Self>, handle: &Bound<'_, PyAny>) -> PyResult<ForceHandle> {
        let h = handle.cast::<ForceHandle>().map_err(|_| {
            crate::convert::invalid("handle", handle, "a ForceHandle (what an add_* of a force returns)")
        })?;
        let g = slf.get().lock()?;
        let id = h.get().id_in(g.family)?;
        if g.engine.force(id).is_none() && !g.engine.is_user_force(id) {
            return Err(PyValueError::new_err(format!(
                "invalid force = ForceHandle(id={id}, kind='{}'): this World holds no such force (it was removed)",
                h.get().kind_name()
            )));
        }
        Ok(handle_of(slf, &g, id))
    }

    /// Handles of every force of the World: the built-in ones in the World's canonical order
    /// (the order they act in), then the Python forces in the order they were added.
    #[getter]
    fn forces(slf: &Bound<'_, Self>) -> PyResult<Vec<ForceHandle>> {
        let g = slf.get().lock()?;
        Ok(g.engine.force_ids().into_iter().map(|id| handle_of(slf, &g, id)).collect())
    }
}
