//! A scene file's document into a [`World`]: the top-level settings, then the flow or the
//! particles, bodies, forces, springs, constraints and collisions, in that order (the parts
//! that carry state, `[[particles]]` with balls among them, `[[bodies]]` and `[collisions]`,
//! at the end).

use super::doc::{Doc, Table};
use super::SceneFile;
use crate::clock::LoopMode;
use crate::constraints::Constraint;
use crate::error::{Error, Result};
use crate::flows::Flow;
use crate::forces::{Endpoint, Force};
use crate::rigid::inertia::Shape;
use crate::world::{BodyParams, World, WorldParams};
use toml::de::DeTable;

const TOP: [&str; 19] = [
    "dimension",
    "method",
    "dt",
    "until",
    "constraint_iterations",
    "loop",
    "rigid",
    "flow",
    "particles",
    "bodies",
    "forces",
    "springs",
    "body_springs",
    "constraints",
    "collisions",
    "contact",
    "solids",
    "joints",
    "solid_springs",
];

/// The whole file; `mode`, when given, in place of the file's loop variant.
pub(super) fn scene(doc: &Doc<'_>, mode: Option<LoopMode>) -> Result<SceneFile> {
    let root = toml::de::DeTable::parse(doc.text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start);
        let msg = e.message().lines().next().unwrap_or("").trim().to_string();
        doc.err(at, "", format!("not valid TOML: {msg}"))
    })?;
    let top = Table { table: root.get_ref(), at: 0, path: "" };
    doc.keys(top, &TOP)?;
    let dim = doc
        .index(top, "dimension")?
        .ok_or_else(|| doc.err(0, "dimension", "is missing: must be 1, 2 or 3"))?;
    if !(1..=3).contains(&dim) {
        return Err(doc.range(top, "dimension", dim as f64, "1, 2 or 3"));
    }
    let mut params = WorldParams { dim, ..WorldParams::default() };
    if let Some(m) = doc.str(top, "method")? {
        params.method = m.to_string();
    }
    if let Some(dt) = doc.f64(top, "dt")? {
        params.dt = dt;
    }
    let until = doc.f64(top, "until")?;
    if let Some(u) = until {
        if !(u.is_finite() && u >= 0.0) {
            return Err(doc.range(top, "until", u, "a finite number >= 0, s"));
        }
    }
    // Where a value the world refuses was given (World::new names the field): its key's line.
    let mut given: Vec<(&str, usize, &str)> = vec![
        ("dt", top.table.get("dt").map_or(0, |v| v.span().start), "dt"),
        ("method", top.table.get("method").map_or(0, |v| v.span().start), "method"),
    ];
    if let Some((t, at)) = doc.table(top, "loop")? {
        let t = Table { table: t, at, path: "loop" };
        doc.keys(t, &["mode", "substeps", "max_steps_per_frame", "max_frame_time"])?;
        let key_at = |key: &str| t.table.get(key).map_or(at, |v| v.span().start);
        given.push(("max_frame_time", key_at("max_frame_time"), "loop.max_frame_time"));
        given.push(("max_steps_per_frame", key_at("max_steps_per_frame"), "loop.max_steps_per_frame"));
        given.push(("steps_per_frame", key_at("substeps"), "loop.substeps"));
        let substeps = doc.index(t, "substeps")?.unwrap_or(1);
        let substeps = u32::try_from(substeps).ok().filter(|&s| s >= 1).ok_or_else(|| {
            doc.range(t, "substeps", substeps as f64, "a whole number from 1 to 4294967295")
        })?;
        if let Some(mode) = doc.str(t, "mode")? {
            params.mode = LoopMode::from_name(mode, substeps)
                .map_err(|e| doc.engine(key_at("mode"), "loop.mode", e))?;
        }
        if let Some(n) = doc.index(t, "max_steps_per_frame")? {
            params.max_steps_per_frame = u32::try_from(n)
                .map_err(|_| doc.range(t, "max_steps_per_frame", n as f64, "at most 4294967295"))?;
        }
        if let Some(x) = doc.f64(t, "max_frame_time")? {
            params.max_frame_time = x;
        }
    }
    if let Some(mode) = mode {
        params.mode = mode;
    }
    // A value World::new refuses is reported at its key, named as the file names it.
    let at_key = |e: Error| {
        let field = match &e {
            Error::InvalidValue { field, .. } => field.as_str(),
            Error::UnknownName { kind, .. } | Error::Unsupported { method: kind, .. } if kind == "method" => {
                "method"
            }
            Error::Unsupported { .. } => "method",
            _ => "",
        };
        match given.iter().find(|(f, _, _)| *f == field) {
            Some(&(_, at, path)) => doc.engine(at, path, e),
            None => doc.engine(given[1].1, "", e),
        }
    };
    // The step, the loop and the method checked as a world of particles checks them (a
    // flow's own checks follow), each error at its key.
    let world = World::new(params.clone()).map_err(at_key)?;
    let mut world = match doc.table(top, "flow")? {
        Some((t, at)) => flow(doc, Table { table: t, at, path: "flow" }, params)?,
        None => world,
    };
    if let Some((t, at)) = doc.table(top, "rigid")? {
        let t = Table { table: t, at, path: "rigid" };
        doc.keys(t, &["orientation", "angular_form"])?;
        if let Some(r) = doc.str(t, "orientation")? {
            let rule = crate::rigid::orientation::Rule::from_name(r)
                .map_err(|e| doc.engine(at, "rigid.orientation", e))?;
            world.set_orientation_rule(rule);
        }
        if let Some(f) = doc.str(t, "angular_form")? {
            let form = crate::rigid::body::AngularForm::from_name(f)
                .map_err(|e| doc.engine(at, "rigid.angular_form", e))?;
            world.set_angular_form(form);
        }
    }
    particles(doc, top, &mut world)?;
    bodies(doc, top, &mut world)?;
    forces(doc, top, &mut world)?;
    springs(doc, top, &mut world)?;
    body_springs(doc, top, &mut world)?;
    constraints(doc, top, &mut world)?;
    if let Some(n) = doc.index(top, "constraint_iterations")? {
        let n = u32::try_from(n).unwrap_or(u32::MAX);
        let at = top.table.get("constraint_iterations").map_or(0, |v| v.span().start);
        world.set_constraint_iterations(n).map_err(|e| doc.engine(at, "constraint_iterations", e))?;
    }
    collisions(doc, top, &mut world)?;
    super::solids::read(doc, top, &mut world)?;
    Ok(SceneFile { world, until })
}

/// `[flow]`: kind and parameters, `state`.
fn flow(doc: &Doc<'_>, t: Table<'_, '_>, params: WorldParams) -> Result<World> {
    let kind = doc
        .str(t, "kind")?
        .ok_or_else(|| doc.err(t.at, "flow.kind", "is missing: must be lorenz, rossler or thomas"))?;
    let (flow, keys): (Flow, &[&str]) = match kind {
        "lorenz" => (
            Flow::Lorenz {
                sigma: doc.f64_req(t, "sigma")?,
                rho: doc.f64_req(t, "rho")?,
                beta: doc.f64_req(t, "beta")?,
            },
            &["kind", "state", "sigma", "rho", "beta"],
        ),
        "rossler" => (
            Flow::Rossler { a: doc.f64_req(t, "a")?, b: doc.f64_req(t, "b")?, c: doc.f64_req(t, "c")? },
            &["kind", "state", "a", "b", "c"],
        ),
        "thomas" => (Flow::Thomas { b: doc.f64_req(t, "b")? }, &["kind", "state", "b"]),
        other => {
            return Err(doc.err(t.at, "flow.kind", format!("= '{other}': must be lorenz, rossler or thomas")))
        }
    };
    doc.keys(t, keys)?;
    let y0 = doc.vec_req(t, "state", 3)?;
    if params.dim != 3 {
        return Err(doc.range(
            Table { path: "", ..t },
            "dimension",
            params.dim as f64,
            "3 for a flow of 3 coordinates",
        ));
    }
    World::with_flow(flow, &y0, params).map_err(|e| doc.engine(t.at, "flow", e))
}

/// `j = INDEX` or `anchor = [..]` of a spring, rod or constraint.
pub(super) fn endpoint(doc: &Doc<'_>, t: Table<'_, '_>, dim: usize) -> Result<Endpoint> {
    match (doc.index(t, "j")?, doc.vec(t, "anchor", Some(dim))?) {
        (Some(j), None) => Ok(Endpoint::Particle(j)),
        (None, Some(a)) => {
            let mut p = [0.0; 3];
            p[..dim].copy_from_slice(&a);
            Ok(Endpoint::Anchor(p))
        }
        _ => Err(doc.err(
            t.at,
            &super::doc::join(t.path, "j"),
            "needs exactly one of j (a particle index) or anchor (a point)",
        )),
    }
}

/// `dim` numbers padded to 3.
pub(super) fn pad(v: &[f64]) -> [f64; 3] {
    let mut p = [0.0; 3];
    p[..v.len()].copy_from_slice(v);
    p
}

pub(super) fn each<'t, 'i>(
    doc: &Doc<'_>,
    top: Table<'t, 'i>,
    key: &str,
) -> Result<Vec<(&'t DeTable<'i>, usize, String)>> {
    Ok(doc
        .tables(top, key)?
        .into_iter()
        .enumerate()
        .map(|(k, (t, at))| (t, at, format!("{key}[{k}]")))
        .collect())
}

/// `[[forces]]`: gravity, drag, central-gravity, nbody, rod.
fn forces(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let dim = w.dim();
    for (table, at, path) in each(doc, top, "forces")? {
        let t = Table { table, at, path: &path };
        let kind = doc.str(t, "kind")?.unwrap_or("");
        let (force, keys): (Force, &[&str]) = match kind {
            "gravity" => (Force::Gravity { g: pad(&doc.vec_req(t, "g", dim)?) }, &["kind", "g"]),
            "drag" => (
                Force::Drag {
                    linear: doc.f64(t, "linear")?.unwrap_or(0.0),
                    quadratic: doc.f64(t, "quadratic")?.unwrap_or(0.0),
                },
                &["kind", "linear", "quadratic"],
            ),
            "central-gravity" => (
                Force::CentralGravity {
                    center: pad(&doc.vec_req(t, "center", dim)?),
                    gm: doc.f64_req(t, "gm")?,
                },
                &["kind", "center", "gm"],
            ),
            "nbody" => (
                Force::NBody { g: doc.f64_req(t, "g")?, softening: doc.f64(t, "softening")?.unwrap_or(0.0) },
                &["kind", "g", "softening"],
            ),
            "rod" => (
                Force::Rod {
                    i: doc.index_req(t, "i")?,
                    j: endpoint(doc, t, dim)?,
                    length: doc.f64_req(t, "length")?,
                },
                &["kind", "i", "j", "anchor", "length"],
            ),
            other => {
                return Err(doc.err(
                    at,
                    &format!("{path}.kind"),
                    format!("= '{other}': must be gravity, drag, central-gravity, nbody or rod"),
                ))
            }
        };
        doc.keys(t, keys)?;
        w.add_force(force).map_err(|e| doc.engine(at, &path, e))?;
    }
    Ok(())
}

/// `[[springs]]`: `i`, `j` or `anchor`, `stiffness`, `rest_length`, `damping`.
fn springs(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let dim = w.dim();
    for (table, at, path) in each(doc, top, "springs")? {
        let t = Table { table, at, path: &path };
        doc.keys(t, &["i", "j", "anchor", "stiffness", "rest_length", "damping"])?;
        let force = Force::Spring {
            i: doc.index_req(t, "i")?,
            j: endpoint(doc, t, dim)?,
            stiffness: doc.f64_req(t, "stiffness")?,
            rest_length: doc.f64(t, "rest_length")?.unwrap_or(0.0),
            damping: doc.f64(t, "damping")?.unwrap_or(0.0),
        };
        w.add_force(force).map_err(|e| doc.engine(at, &path, e))?;
    }
    Ok(())
}

/// `[[constraints]]`: distance, pin, rope, limit, plane.
fn constraints(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let dim = w.dim();
    for (table, at, path) in each(doc, top, "constraints")? {
        let t = Table { table, at, path: &path };
        let kind = doc.str(t, "kind")?.unwrap_or("");
        let (c, keys): (Constraint, &[&str]) = match kind {
            "distance" => (
                Constraint::Distance {
                    i: doc.index_req(t, "i")?,
                    j: endpoint(doc, t, dim)?,
                    length: doc.f64_req(t, "length")?,
                    compliance: doc.f64(t, "compliance")?.unwrap_or(0.0),
                },
                &["kind", "i", "j", "anchor", "length", "compliance"],
            ),
            "pin" => (
                Constraint::Pin { i: doc.index_req(t, "i")?, point: pad(&doc.vec_req(t, "point", dim)?) },
                &["kind", "i", "point"],
            ),
            "rope" => (
                Constraint::Limit {
                    i: doc.index_req(t, "i")?,
                    j: endpoint(doc, t, dim)?,
                    min: 0.0,
                    max: doc.f64_req(t, "max")?,
                },
                &["kind", "i", "j", "anchor", "max"],
            ),
            "limit" => (
                Constraint::Limit {
                    i: doc.index_req(t, "i")?,
                    j: endpoint(doc, t, dim)?,
                    min: doc.f64_req(t, "min")?,
                    max: doc.f64_req(t, "max")?,
                },
                &["kind", "i", "j", "anchor", "min", "max"],
            ),
            "plane" => (
                Constraint::Plane {
                    normal: pad(&doc.vec_req(t, "normal", dim)?),
                    offset: doc.f64(t, "offset")?.unwrap_or(0.0),
                },
                &["kind", "normal", "offset"],
            ),
            other => {
                return Err(doc.err(
                    at,
                    &format!("{path}.kind"),
                    format!("= '{other}': must be distance, pin, rope, limit or plane"),
                ))
            }
        };
        doc.keys(t, keys)?;
        w.add_constraint(c).map_err(|e| doc.engine(at, &path, e))?;
    }
    Ok(())
}

/// A body's `shape` table into a [`Shape`].
pub(super) fn shape(doc: &Doc<'_>, t: Table<'_, '_>) -> Result<Shape> {
    let kind = doc.str(t, "kind")?.unwrap_or("");
    let (s, keys): (Shape, &[&str]) = match kind {
        "sphere" => (Shape::Sphere { radius: doc.f64_req(t, "radius")? }, &["kind", "radius"]),
        "box" => {
            let h = doc.vec_req(t, "half_extents", 3)?;
            (Shape::Box { half_extents: [h[0], h[1], h[2]] }, &["kind", "half_extents"])
        }
        "cylinder" => (
            Shape::Cylinder { radius: doc.f64_req(t, "radius")?, height: doc.f64_req(t, "height")? },
            &["kind", "radius", "height"],
        ),
        "capsule" => (
            Shape::Capsule { radius: doc.f64_req(t, "radius")?, height: doc.f64_req(t, "height")? },
            &["kind", "radius", "height"],
        ),
        "mesh" => {
            let v =
                doc.rows(t, "vertices", 3)?.ok_or_else(|| doc.err(t.at, "shape.vertices", "is missing"))?;
            let tri =
                doc.rows(t, "triangles", 3)?.ok_or_else(|| doc.err(t.at, "shape.triangles", "is missing"))?;
            let mut triangles = Vec::with_capacity(tri.len());
            for (k, row) in tri.iter().enumerate() {
                let mut ids = [0usize; 3];
                for (c, x) in row.iter().enumerate() {
                    if !(x.fract() == 0.0 && *x >= 0.0 && *x < 4e9) {
                        return Err(doc.err(
                            t.at,
                            &format!("{}.triangles[{k}][{c}]", t.path),
                            "must be a vertex index",
                        ));
                    }
                    ids[c] = *x as usize;
                }
                triangles.push(ids);
            }
            let vertices = v.iter().map(|r| [r[0], r[1], r[2]]).collect();
            (Shape::Mesh { vertices, triangles }, &["kind", "vertices", "triangles"])
        }
        other => {
            return Err(doc.err(
                t.at,
                &format!("{}.kind", t.path),
                format!("= '{other}': must be sphere, box, cylinder, capsule or mesh"),
            ))
        }
    };
    doc.keys(t, keys)?;
    s.validate().map_err(|e| doc.engine(t.at, t.path, e))?;
    Ok(s)
}

/// The fields of a `[[bodies]]` table other than its shape.
pub(super) fn body(doc: &Doc<'_>, t: Table<'_, '_>, shape: Shape) -> Result<BodyParams> {
    let d = BodyParams::default();
    let v3 = |key: &str, or: [f64; 3]| -> Result<[f64; 3]> {
        Ok(doc.vec(t, key, Some(3))?.map_or(or, |v| pad(&v)))
    };
    let q = doc.vec(t, "orientation", Some(4))?.map_or(d.orientation, |q| [q[0], q[1], q[2], q[3]]);
    Ok(BodyParams {
        shape,
        mass: doc.f64(t, "mass")?,
        density: doc.f64(t, "density")?,
        position: v3("position", d.position)?,
        orientation: q,
        velocity: v3("velocity", d.velocity)?,
        angular_velocity: v3("angular_velocity", d.angular_velocity)?,
        pivot: doc.vec(t, "pivot", Some(3))?.map(|v| pad(&v)),
        angular_drag: doc.f64(t, "angular_drag")?.unwrap_or(0.0),
    })
}

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
            if doc.restoring {
                w.add_ball_as_found(&pos, &vel, r, mass).map_err(field)?;
            } else {
                w.add_ball(&pos, &vel, r, mass).map_err(field)?;
            }
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
    for (table, at, path) in each(doc, top, "body_springs")? {
        let t = Table { table, at, path: &path };
        doc.keys(t, &["body", "point", "arm", "j", "anchor", "stiffness", "rest_length", "damping"])?;
        let body = doc.index_req(t, "body")?;
        let point = doc.vec(t, "point", Some(3))?.map_or([0.0; 3], |p| [p[0], p[1], p[2]]);
        let other = endpoint(doc, t, w.dim())?;
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
        let added = if doc.restoring { w.add_walls_as_found(&lo, &hi) } else { w.add_walls(&lo, &hi) };
        added.map_err(|e| doc.engine(wat, "collisions.walls", e))?;
    }
    Ok(())
}
