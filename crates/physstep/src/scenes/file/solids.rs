//! Solids in scene files: `[contact]` (the contact solver, its substeps and iterations, and
//! the contacts' and joints' tuning and `continuous` where not the default), `[[solids]]` (each solid as
//! it was added: shape, kind, pose, velocities, density, friction, restitution, drag,
//! bullet) and
//! `[[joints]]` (each joint as it was made: kind, the two solids, anchors, axis, lengths,
//! limits, motor) and `[[solid_springs]]` (each spring between solids' points as made: the
//! two ends, stiffness, rest length, damping).

use super::doc::{Doc, Table};
use crate::contact::{JointKind, JointParams, Kind, Settings, Shape, SolidParams, SolidSpring};
use crate::error::Result;
use crate::world::World;
use std::fmt::Write;

fn num(x: f64) -> String {
    super::write::num(x)
}

fn arr(v: &[f64]) -> String {
    super::write::arr(v)
}

fn rows(flat: &[f64], per: usize) -> String {
    let r: Vec<String> = flat.chunks(per).map(arr).collect();
    format!("[{}]", r.join(", "))
}

/// The `shape = { ... }` of a solid.
fn shape(s: &Shape, dim: usize) -> String {
    match s {
        Shape::Circle { radius } => format!("kind = \"circle\", radius = {}", num(*radius)),
        Shape::Box { half } => format!("kind = \"box\", half = {}", arr(half)),
        Shape::Capsule { half_height, radius } => {
            format!("kind = \"capsule\", half_height = {}, radius = {}", num(*half_height), num(*radius))
        }
        Shape::Polygon { points } => format!("kind = \"polygon\", points = {}", rows(points, dim)),
        Shape::Segment { a, b, radius } => {
            format!("kind = \"segment\", a = {}, b = {}, radius = {}", arr(a), arr(b), num(*radius))
        }
        Shape::Plane { normal } => format!("kind = \"plane\", normal = {}", arr(normal)),
        Shape::Mesh { vertices, triangles } => {
            let t: Vec<String> =
                triangles.iter().map(|t| format!("[{}, {}, {}]", t[0], t[1], t[2])).collect();
            format!("kind = \"mesh\", vertices = {}, triangles = [{}]", rows(vertices, 3), t.join(", "))
        }
    }
}

/// Appends `[contact]` and the `[[solids]]` of `world` (as they were added).
pub(super) fn write(world: &World, s: &mut String) {
    let set = world.contact_settings();
    if world.solid_count() == 0 && set == Settings::default() {
        return;
    }
    let _ = writeln!(
        s,
        "\n[contact]\nsolver = \"{}\"\nsubsteps = {}\niterations = {}",
        set.solver, set.substeps, set.iterations
    );
    let default = Settings::default();
    for ((key, v), (_, d)) in tuning(&set).into_iter().zip(tuning(&default)) {
        if v != d {
            let _ = writeln!(s, "{key} = {}", num(v));
        }
    }
    if set.continuous != default.continuous {
        let _ = writeln!(s, "continuous = {}", set.continuous);
    }
    for p in world.solid_params() {
        let _ = writeln!(
            s,
            "\n[[solids]]\nshape = {{ {} }}\nkind = \"{}\"\nposition = {}\norientation = {}\nvelocity = {}\nangular_velocity = {}\ndensity = {}\nfriction = {}\nrestitution = {}",
            shape(&p.shape, world.dim()),
            p.kind.name(),
            arr(&p.position),
            arr(&p.orientation),
            arr(&p.velocity),
            arr(&p.angular_velocity),
            num(p.density),
            num(p.friction),
            num(p.restitution)
        );
        for (key, v) in [("linear_damping", p.linear_damping), ("angular_damping", p.angular_damping)] {
            if v != 0.0 {
                let _ = writeln!(s, "{key} = {}", num(v));
            }
        }
        if p.bullet {
            let _ = writeln!(s, "bullet = true");
        }
    }
    write_joints(world, s);
    write_springs(world, s);
}

/// Appends the `[[solid_springs]]` of `world` (as they were made, rest lengths resolved).
fn write_springs(world: &World, s: &mut String) {
    for p in world.solid_springs() {
        let _ = write!(s, "\n[[solid_springs]]\na = {}\npoint_a = {}\n", p.a, arr(&p.point_a));
        if let Some(b) = p.b {
            let _ = writeln!(s, "b = {b}");
        }
        let _ = writeln!(s, "point_b = {}\nstiffness = {}", arr(&p.point_b), num(p.stiffness));
        if let Some(r) = p.rest_length {
            let _ = writeln!(s, "rest_length = {}", num(r));
        }
        if p.damping != 0.0 {
            let _ = writeln!(s, "damping = {}", num(p.damping));
        }
    }
}

/// `[[solid_springs]]` into `w` (after its solids).
fn read_springs(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let dim = w.dim();
    for (k, (table, at)) in doc.tables(top, "solid_springs")?.into_iter().enumerate() {
        let path = format!("solid_springs[{k}]");
        let t = Table { table, at, path: &path };
        doc.keys(t, &["a", "point_a", "b", "point_b", "stiffness", "rest_length", "damping"])?;
        let p = SolidSpring {
            a: doc.index_req(t, "a")?,
            point_a: doc.vec_req(t, "point_a", dim)?,
            b: doc.index(t, "b")?,
            point_b: doc.vec_req(t, "point_b", dim)?,
            stiffness: doc.f64_req(t, "stiffness")?,
            rest_length: doc.f64(t, "rest_length")?,
            damping: doc.f64(t, "damping")?.unwrap_or(0.0),
        };
        w.add_solid_spring(p).map_err(|e| doc.engine(at, &path, e))?;
    }
    Ok(())
}

/// The contact solver's tuning numbers by their `[contact]` keys (written where they are
/// not the default).
fn tuning(s: &Settings) -> [(&'static str, f64); 9] {
    [
        ("contact_hertz", s.contact_hertz),
        ("damping_ratio", s.damping_ratio),
        ("push_speed", s.push_speed),
        ("restitution_threshold", s.restitution_threshold),
        ("speculative_distance", s.speculative_distance),
        ("joint_hertz", s.joint_hertz),
        ("joint_damping_ratio", s.joint_damping_ratio),
        ("joint_projection", f64::from(s.joint_projection)),
        ("sleep_time", s.sleep_time),
    ]
}

/// Appends the `[[joints]]` of `world` (as they were made; optional keys where set).
fn write_joints(world: &World, s: &mut String) {
    for j in world.joint_params() {
        let _ = write!(s, "\n[[joints]]\nkind = \"{}\"\na = {}\n", j.kind.name(), j.a);
        if let Some(b) = j.b {
            let _ = writeln!(s, "b = {b}");
        }
        let _ = writeln!(s, "anchor = {}", arr(&j.anchor));
        for (key, v) in [("anchor_b", &j.anchor_b), ("axis", &j.axis)] {
            if let Some(v) = v {
                let _ = writeln!(s, "{key} = {}", arr(v));
            }
        }
        for (key, v) in [
            ("length", j.length),
            ("min_length", j.min_length),
            ("max_length", j.max_length),
            ("lower", j.lower),
            ("upper", j.upper),
        ] {
            if let Some(v) = v {
                let _ = writeln!(s, "{key} = {}", num(v));
            }
        }
        let fresh = JointParams::new(j.kind, j.a, j.b, &j.anchor);
        for (key, v, d) in [
            ("hertz", j.hertz, fresh.hertz),
            ("damping_ratio", j.damping_ratio, fresh.damping_ratio),
            ("motor_speed", j.motor_speed, fresh.motor_speed),
            ("max_motor", j.max_motor, fresh.max_motor),
        ] {
            if v != d {
                let _ = writeln!(s, "{key} = {}", num(v));
            }
        }
        if j.collide {
            let _ = writeln!(s, "collide = true");
        }
    }
}

/// `[[joints]]` into `w` (after its solids).
fn read_joints(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    let dim = w.dim();
    for (k, (table, at)) in doc.tables(top, "joints")?.into_iter().enumerate() {
        let path = format!("joints[{k}]");
        let t = Table { table, at, path: &path };
        doc.keys(
            t,
            &[
                "kind",
                "a",
                "b",
                "anchor",
                "anchor_b",
                "axis",
                "length",
                "min_length",
                "max_length",
                "hertz",
                "damping_ratio",
                "lower",
                "upper",
                "motor_speed",
                "max_motor",
                "collide",
            ],
        )?;
        let kind = doc.str(t, "kind")?.ok_or_else(|| doc.err(at, &format!("{path}.kind"), "is missing"))?;
        let kind = JointKind::by_name(kind).map_err(|e| doc.engine(at, &format!("{path}.kind"), e))?;
        let mut p = JointParams::new(
            kind,
            doc.index_req(t, "a")?,
            doc.index(t, "b")?,
            &doc.vec_req(t, "anchor", dim)?,
        );
        p.anchor_b = doc.vec(t, "anchor_b", Some(dim))?;
        p.axis = doc.vec(t, "axis", Some(dim))?;
        p.length = doc.f64(t, "length")?;
        p.min_length = doc.f64(t, "min_length")?;
        p.max_length = doc.f64(t, "max_length")?;
        p.lower = doc.f64(t, "lower")?;
        p.upper = doc.f64(t, "upper")?;
        p.hertz = doc.f64(t, "hertz")?.unwrap_or(p.hertz);
        p.damping_ratio = doc.f64(t, "damping_ratio")?.unwrap_or(p.damping_ratio);
        p.motor_speed = doc.f64(t, "motor_speed")?.unwrap_or(p.motor_speed);
        p.max_motor = doc.f64(t, "max_motor")?.unwrap_or(p.max_motor);
        p.collide = doc.bool(t, "collide")?.unwrap_or(false);
        w.add_joint(p).map_err(|e| doc.engine(at, &path, e))?;
    }
    Ok(())
}

/// A solid's `shape` table.
fn read_shape(doc: &Doc<'_>, t: Table<'_, '_>, dim: usize) -> Result<Shape> {
    let kind = doc.str(t, "kind")?.unwrap_or("");
    let flat = |key: &str, per: usize| -> Result<Vec<f64>> {
        Ok(doc
            .rows(t, key, per)?
            .ok_or_else(|| doc.err(t.at, &format!("{}.{key}", t.path), "is missing"))?
            .concat())
    };
    let (s, keys): (Shape, &[&str]) = match kind {
        "circle" => (Shape::Circle { radius: doc.f64_req(t, "radius")? }, &["kind", "radius"]),
        "box" => (Shape::Box { half: doc.vec_req(t, "half", dim)? }, &["kind", "half"]),
        "capsule" => (
            Shape::Capsule { half_height: doc.f64_req(t, "half_height")?, radius: doc.f64_req(t, "radius")? },
            &["kind", "half_height", "radius"],
        ),
        "polygon" => (Shape::Polygon { points: flat("points", dim)? }, &["kind", "points"]),
        "segment" => (
            Shape::Segment {
                a: doc.vec_req(t, "a", dim)?,
                b: doc.vec_req(t, "b", dim)?,
                radius: doc.f64(t, "radius")?.unwrap_or(0.0),
            },
            &["kind", "a", "b", "radius"],
        ),
        "plane" => (Shape::Plane { normal: doc.vec_req(t, "normal", dim)? }, &["kind", "normal"]),
        "mesh" => {
            let tri = flat("triangles", 3)?;
            if let Some(k) = tri.iter().position(|x| !(x.fract() == 0.0 && *x >= 0.0 && *x < 4e9)) {
                return Err(doc.err(
                    t.at,
                    &format!("{}.triangles[{}][{}]", t.path, k / 3, k % 3),
                    "must be a vertex index",
                ));
            }
            let triangles = tri.chunks(3).map(|c| [c[0] as u32, c[1] as u32, c[2] as u32]).collect();
            (Shape::Mesh { vertices: flat("vertices", 3)?, triangles }, &["kind", "vertices", "triangles"])
        }
        other => {
            return Err(doc.err(
                t.at,
                &format!("{}.kind", t.path),
                format!("= '{other}': must be circle, box, capsule, polygon, segment, plane or mesh"),
            ))
        }
    };
    doc.keys(t, keys)?;
    Ok(s)
}

/// `[contact]` and `[[solids]]` into `w`.
pub(super) fn read(doc: &Doc<'_>, top: Table<'_, '_>, w: &mut World) -> Result<()> {
    if let Some((t, at)) = doc.table(top, "contact")? {
        let t = Table { table: t, at, path: "contact" };
        let mut known = vec!["solver", "substeps", "iterations", "continuous"];
        known.extend(tuning(&Settings::default()).iter().map(|(k, _)| *k));
        doc.keys(t, &known)?;
        if let Some(name) = doc.str(t, "solver")? {
            w.set_contact_solver(name).map_err(|e| doc.engine(at, "contact.solver", e))?;
        }
        if let Some(n) = doc.index(t, "substeps")? {
            let n = u32::try_from(n).unwrap_or(u32::MAX);
            w.set_substeps(n).map_err(|e| doc.engine(at, "contact.substeps", e))?;
        }
        if let Some(n) = doc.index(t, "iterations")? {
            let n = u32::try_from(n).unwrap_or(u32::MAX);
            w.set_solver_iterations(n).map_err(|e| doc.engine(at, "contact.iterations", e))?;
        }
        let mut set = w.contact_settings();
        for (key, _) in tuning(&Settings::default()) {
            let Some(v) = doc.f64(t, key)? else { continue };
            let field = format!("contact.{key}");
            match key {
                "contact_hertz" => set.contact_hertz = v,
                "damping_ratio" => set.damping_ratio = v,
                "push_speed" => set.push_speed = v,
                "restitution_threshold" => set.restitution_threshold = v,
                "speculative_distance" => set.speculative_distance = v,
                "joint_hertz" => set.joint_hertz = v,
                "joint_damping_ratio" => set.joint_damping_ratio = v,
                "sleep_time" => set.sleep_time = v,
                _ => {
                    if !(v.fract() == 0.0 && (0.0..=1000.0).contains(&v)) {
                        return Err(doc.err(at, &field, format!("= {v}: must be a whole number 0 to 1000")));
                    }
                    set.joint_projection = v as u32;
                }
            }
        }
        if let Some(on) = doc.bool(t, "continuous")? {
            set.continuous = on;
        }
        w.set_contact_settings(set).map_err(|e| doc.engine(at, "contact", e))?;
    }
    let dim = w.dim();
    for (k, (table, at)) in doc.tables(top, "solids")?.into_iter().enumerate() {
        let path = format!("solids[{k}]");
        let t = Table { table, at, path: &path };
        doc.keys(
            t,
            &[
                "shape",
                "kind",
                "position",
                "orientation",
                "velocity",
                "angular_velocity",
                "density",
                "friction",
                "restitution",
                "linear_damping",
                "angular_damping",
                "bullet",
            ],
        )?;
        let spath = format!("{path}.shape");
        let (st, sat) =
            doc.table(t, "shape")?.ok_or_else(|| doc.err(at, &spath, "is missing: must be a table"))?;
        let s = read_shape(doc, Table { table: st, at: sat, path: &spath }, dim)?;
        let mut p = SolidParams::new(s, &doc.vec_req(t, "position", dim)?);
        if let Some(kind) = doc.str(t, "kind")? {
            p.kind = Kind::by_name(kind).map_err(|e| doc.engine(at, &format!("{path}.kind"), e))?;
        }
        if let Some(q) = doc.vec(t, "orientation", None)? {
            p.orientation = q;
        }
        if let Some(v) = doc.vec(t, "velocity", None)? {
            p.velocity = v;
        }
        if let Some(v) = doc.vec(t, "angular_velocity", None)? {
            p.angular_velocity = v;
        }
        p.density = doc.f64(t, "density")?.unwrap_or(p.density);
        p.friction = doc.f64(t, "friction")?.unwrap_or(p.friction);
        p.restitution = doc.f64(t, "restitution")?.unwrap_or(p.restitution);
        p.linear_damping = doc.f64(t, "linear_damping")?.unwrap_or(0.0);
        p.angular_damping = doc.f64(t, "angular_damping")?.unwrap_or(0.0);
        p.bullet = doc.bool(t, "bullet")?.unwrap_or(false);
        w.add_solid(p).map_err(|e| doc.engine(at, &path, e))?;
    }
    read_joints(doc, top, w)?;
    read_springs(doc, top, w)
}
