//! The parts of a scene file that carry state: `[[particles]]` (balls among them),
//! `[[bodies]]` and `[collisions]`.

use super::doc::{Doc, Table};
use super::read::{body, shape};
use crate::error::Result;
use crate::world::World;

/// `[[particles]]`: `position`, `velocity`, `mass`, `static`, and `radius` for a ball. Runs
/// of plain particles are added in one batch, balls one at a time (each checked for overlap).
pub(super) fn particles(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let dim = w.dim();
    let items = doc.tables(top, "particles")?;
    let (mut x, mut v, mut m) = (Vec::new(), Vec::new(), Vec::new());
    let mut run_static = false;
    let flush =
        |w: &mut World, x: &mut Vec<f64>, v: &mut Vec<f64>, m: &mut Vec<f64>, fixed: bool| -> Result<()> {
            if !m.is_empty() {
                w.add_particles(x, Some(v), Some(m), fixed).map_err(|e| doc.engine(0, "particles", e))?;
                x.clear();
                v.clear();
                m.clear();
            }
            Ok(())
        };
    for (k, (table, at)) in items.into_iter().enumerate() {
        let path = format!("particles[{k}]");
        let t = Table { table, at, path: &path };
        doc.keys(t, &["position", "velocity", "mass", "static", "radius"])?;
        let pos = doc.vec_req(t, "position", dim)?;
        let vel = doc.vec(t, "velocity", Some(dim))?.unwrap_or_else(|| vec![0.0; dim]);
        let mass = doc.f64(t, "mass")?.unwrap_or(1.0);
        let fixed = doc.bool(t, "static")?.unwrap_or(false);
        let field = |e: crate::Error| doc.engine(at, &path, e);
        w.check_particles(&pos, Some(&vel), Some(&[mass])).map_err(field)?;
        if let Some(r) = doc.f64(t, "radius")? {
            if fixed && mass != f64::INFINITY {
                return Err(doc.err(at, &format!("{path}.static"), "a ball is made static by mass = inf"));
            }
            flush(w, &mut x, &mut v, &mut m, run_static)?;
            w.add_ball(&pos, &vel, r, mass).map_err(field)?;
            continue;
        }
        if fixed != run_static {
            flush(w, &mut x, &mut v, &mut m, run_static)?;
            run_static = fixed;
        }
        x.extend_from_slice(&pos);
        v.extend_from_slice(&vel);
        m.push(mass);
    }
    flush(w, &mut x, &mut v, &mut m, run_static)
}

/// `[[bodies]]`: a `shape` table and the body's mass, pose and velocities.
pub(super) fn bodies(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    for (k, (table, at)) in doc.tables(top, "bodies")?.into_iter().enumerate() {
        let path = format!("bodies[{k}]");
        let t = Table { table, at, path: &path };
        doc.keys(
            t,
            &[
                "shape",
                "mass",
                "density",
                "position",
                "orientation",
                "velocity",
                "angular_velocity",
                "pivot",
                "angular_drag",
            ],
        )?;
        let spath = format!("{path}.shape");
        let (st, sat) =
            doc.table(t, "shape")?.ok_or_else(|| doc.err(at, &spath, "is missing: must be a table"))?;
        let s = shape(doc, Table { table: st, at: sat, path: &spath })?;
        let p = body(doc, t, s)?;
        w.add_body(&p).map_err(|e| doc.engine(at, &path, e))?;
    }
    Ok(())
}

/// `[[body_springs]]`: `body`, `point` (the shape's frame), `j` or `anchor`, `stiffness`,
/// `rest_length` (the current distance when left out), `damping`; `arm`, when given, the
/// point as the engine keeps it (from the body's reference point, principal frame: what
/// [`super::structure`] writes so that the spring reads back bitwise).
pub(super) fn body_springs(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    for (table, at, path) in super::read::each(doc, top, "body_springs")? {
        let t = Table { table, at, path: &path };
        doc.keys(t, &["body", "point", "arm", "j", "anchor", "stiffness", "rest_length", "damping"])?;
        let body = doc.index_req(t, "body")?;
        let point = doc.vec(t, "point", Some(3))?.map_or([0.0; 3], |p| [p[0], p[1], p[2]]);
        let other = super::read::endpoint(doc, t, w.dim())?;
        let stiffness = doc.f64_req(t, "stiffness")?;
        let rest_length = doc.f64(t, "rest_length")?;
        let damping = doc.f64(t, "damping")?.unwrap_or(0.0);
        w.add_body_spring(body, point, other, stiffness, rest_length, damping)
            .map_err(|e| doc.engine(at, &path, e))?;
        if let Some(arm) = doc.vec(t, "arm", Some(3))? {
            w.set_last_body_spring_arm([arm[0], arm[1], arm[2]]).map_err(|e| doc.engine(at, &path, e))?;
        }
    }
    Ok(())
}

/// `[collisions]`: `restitution`, `walls = { lo, hi }`.
pub(super) fn collisions(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let Some((table, at)) = doc.table(top, "collisions")? else { return Ok(()) };
    let t = Table { table, at, path: "collisions" };
    doc.keys(t, &["restitution", "walls"])?;
    if let Some(e) = doc.f64(t, "restitution")? {
        w.set_restitution(e).map_err(|e| doc.engine(at, "collisions.restitution", e))?;
    }
    if let Some((wt, wat)) = doc.table(t, "walls")? {
        let wt = Table { table: wt, at: wat, path: "collisions.walls" };
        doc.keys(wt, &["lo", "hi"])?;
        let (lo, hi) = (doc.vec_req(wt, "lo", w.dim())?, doc.vec_req(wt, "hi", w.dim())?);
        w.add_walls(&lo, &hi).map_err(|e| doc.engine(wat, "collisions.walls", e))?;
    }
    Ok(())
}
