//! Scene files: every built-in scene exported and loaded back runs bitwise the built-in
//! trajectory; bad files are refused with one line naming the file, the line and the field.

use super::common;
use physstep::prelude::*;
use physstep::scenes::file;

#[test]
fn every_scene_exported_and_loaded_back_runs_bitwise_the_same() {
    for spec in scenes::SCENES {
        let small: &[(&str, f64)] = if spec.name == "stiff-cloth" { &[("n", 5.0)] } else { &[] };
        let mut built = scenes::build(spec.name, small, common::recorded_method(spec.name), spec.dt).unwrap();
        let text = file::export(&built.world, spec.name, Some(spec.until)).unwrap();
        let mut loaded =
            file::parse(&text, "x.toml").unwrap_or_else(|e| panic!("{}: {e}\n{text}", spec.name));
        assert_eq!(loaded.until, Some(spec.until));
        assert_eq!(loaded.world.state_hash(), built.world.state_hash(), "{} at t = 0", spec.name);
        built.world.step(200).unwrap();
        loaded.world.step(200).unwrap();
        assert_eq!(loaded.world.state_hash(), built.world.state_hash(), "{} after 200 steps", spec.name);
        // Exporting the loaded world gives the same file.
        assert_eq!(
            file::export(&file::parse(&text, "x").unwrap().world, spec.name, Some(spec.until)).unwrap(),
            text
        );
    }
}

#[test]
fn a_stepped_world_of_particles_exports_its_current_state() {
    let mut s = scenes::build("chain", &[], "velocity-verlet", 1e-3).unwrap();
    s.world.step(10).unwrap();
    let text = file::export(&s.world, "chain", None).unwrap();
    let mut w = file::parse(&text, "x").unwrap().world;
    assert_eq!(w.positions(), s.world.positions());
    assert_eq!(w.velocities(), s.world.velocities());
    w.step(1).unwrap();
}

fn err(text: &str) -> String {
    let e = file::parse(text, "bad.toml").map(|_| ()).unwrap_err();
    assert!(matches!(e, Error::SceneFile { .. }), "{e:?}");
    let msg = e.to_string();
    assert!(!msg.contains('\n'), "{msg}");
    assert!(msg.starts_with("scene file bad.toml:"), "{msg}");
    msg
}

#[test]
fn bad_files_are_refused_with_the_file_line_and_field() {
    assert_eq!(err(""), "scene file bad.toml:1: dimension: is missing: must be 1, 2 or 3");
    assert!(err("dimension = 2\nthis is not toml").contains("bad.toml:2: not valid TOML"));
    assert_eq!(
        err("dimension = \"two\""),
        "scene file bad.toml:1: dimension: is string: must be a whole number >= 0"
    );
    assert_eq!(err("dimension = 4"), "scene file bad.toml:1: dimension: = 4: must be 1, 2 or 3");
    let m = err("dimension = 1\n\n[[particles]]\nposition = [0.0]\nmass = -1.0\n");
    assert_eq!(m, "scene file bad.toml:3: particles[0]: invalid mass = -1: must be > 0 with a finite inverse 1/m (about 5.6e-309 or more), at most 1e100 (inf for a static particle)");
    let m = err("dimension = 1\ncolour = 3\n");
    assert_eq!(m, "scene file bad.toml:2: colour: unknown key; valid keys here: dimension, method, dt, until, constraint_iterations, loop, rigid, flow, particles, bodies, forces, springs, body_springs, constraints, collisions, contact, solids, joints, solid_springs");
    let m = err("dimension = 1\n[[particles]]\nposition = [0.0]\nmas = 2.0\n");
    assert!(m.starts_with("scene file bad.toml:4: particles[0].mas: unknown key"), "{m}");
    let m = err("dimension = 2\n[[particles]]\nposition = [0.0, 1.0]\n[[constraints]]\nkind = \"distance\"\ni = 0\nj = 7\nlength = 1.0\n");
    assert_eq!(
        m,
        "scene file bad.toml:4: constraints[0]: invalid j = 7: must be a particle index < 1 other than i = 0"
    );
    let m = err("dimension = 2\n[[particles]]\nposition = [0.0]\n");
    assert_eq!(m, "scene file bad.toml:3: particles[0].position: has 1 numbers: must have 2");
    let m = err("dimension = 2\n[[particles]]\nposition = [0.0, nan]\n");
    assert_eq!(m, "scene file bad.toml:3: particles[0].position[1]: must be a number (nan is not one)");
    let m = err("dimension = 2\nmethod = \"eulr\"\n");
    assert!(m.starts_with("scene file bad.toml:2: method: unknown method 'eulr'; valid methods: "), "{m}");
    let m = err("dimension = 2\ndt = -1\n");
    assert!(m.contains("invalid dt = -1"), "{m}");
}

#[test]
fn a_mesh_that_is_not_closed_is_refused_at_its_body() {
    // A tetrahedron with one face missing.
    let text = "dimension = 3\n\n[[bodies]]\nmass = 1.0\nshape = { kind = \"mesh\", vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], triangles = [[0, 2, 1], [0, 1, 3], [0, 3, 2]] }\n";
    let m = err(text);
    assert!(m.starts_with("scene file bad.toml:5: bodies[0].shape: invalid "), "{m}");
    // Closed, it loads.
    let closed = text.replace("[0, 3, 2]]", "[0, 3, 2], [1, 2, 3]]");
    let w = file::parse(&closed, "ok.toml").unwrap().world;
    assert_eq!(w.bodies().len(), 1);
}

#[test]
fn a_file_that_cannot_be_read_is_named() {
    let e = file::load(std::path::Path::new("/nonexistent/scene.toml")).unwrap_err().to_string();
    assert!(e.starts_with("scene file /nonexistent/scene.toml: cannot be read: "), "{e}");
}

#[test]
fn values_the_world_refuses_are_reported_at_their_key() {
    // They were reported at line 1 with no field.
    let head = "dimension = 2\n# a comment\n\n";
    let tail = "[[particles]]\nposition = [0.0, 0.0]\n";
    assert_eq!(
        err(&format!("{head}until = 1\ndt = 0\n{tail}")),
        "scene file bad.toml:5: dt: invalid dt = 0: must be a finite number > 0"
    );
    assert_eq!(
        err(&format!("{head}dt = 0.01\nconstraint_iterations = 0\n{tail}")),
        "scene file bad.toml:5: constraint_iterations: invalid constraint_iterations = 0: must be a whole number from 1 to 1000000"
    );
    assert_eq!(
        err(&format!("{head}dt = 0.01\n\n[loop]\nmax_frame_time = -1\n{tail}")),
        "scene file bad.toml:7: loop.max_frame_time: invalid max_frame_time = -1: must be a finite number > 0"
    );
    assert_eq!(
        err(&format!("{head}dt = 0.01\n[loop]\nmode = \"steps-per-frame\"\nsubsteps = 0\n{tail}")),
        "scene file bad.toml:7: loop.substeps: = 0: must be a whole number from 1 to 4294967295"
    );
    // A whole number past 64 bits is the number it is, not NaN.
    let text = format!("{head}dt = 0.01\n[[particles]]\nposition = [99999999999999999999, 0]\n");
    let w = file::parse(&text, "s.toml").unwrap().world;
    assert_eq!(w.positions()[0], 1e20);
    assert_eq!(
        err(&format!("{head}dt = 0.01\n[[particles]]\nposition = [0x1ffffffffffffffff, 0]\n")),
        "scene file bad.toml:6: particles[0].position[0]: = 0x1ffffffffffffffff: a hexadecimal, octal or binary number must fit in 64 bits"
    );
}

#[test]
fn a_file_is_not_written_with_an_until_it_could_not_load() {
    // scene_text(..., until=nan) wrote `until = NaN`, which the loader refuses.
    let w = physstep::scenes::build("spring", &[], "rk4", 0.1).unwrap().world;
    for bad in [f64::NAN, f64::INFINITY, -1.0] {
        let e = file::export(&w, "t", Some(bad)).unwrap_err().to_string();
        assert!(e.starts_with("invalid until = ") && e.ends_with("must be a finite number >= 0, s"), "{e}");
    }
    let text = file::export(&w, "t", Some(2.5)).unwrap();
    assert_eq!(file::parse(&text, "t.toml").unwrap().until, Some(2.5));
}

#[test]
fn a_bad_solid_in_a_file_is_refused_naming_its_table_and_field() {
    let m = err(
        "dimension = 2\n[[solids]]\nshape = { kind = \"box\", half = [1.0, -1.0] }\nposition = [0.0, 0.0]\n",
    );
    assert_eq!(m, "scene file bad.toml:2: solids[0]: invalid half[1] = -1: must be finite and > 0");
    let m = err("dimension = 2\n[[solids]]\nshape = { kind = \"cone\" }\nposition = [0.0, 0.0]\n");
    assert!(m.contains("solids[0].shape.kind: = 'cone': must be circle, box"), "{m}");
    let m = err("dimension = 2\n[contact]\nsubsteps = 0\n");
    assert!(m.contains("contact.substeps: invalid substeps = 0: must be 1 to 1000"), "{m}");
}

#[test]
fn continuous_collision_is_written_where_it_is_off_and_read_back() {
    // On by default: a file without the key has it on; `continuous = false` turns it off,
    // and a world with it off writes that line (so a pickle, the same text, keeps it).
    let on = file::parse("dimension = 2\n[contact]\nsubsteps = 8\n", "on.toml").unwrap().world;
    assert!(on.contact_settings().continuous);
    let off = file::parse("dimension = 2\n[contact]\ncontinuous = false\n", "off.toml").unwrap().world;
    assert!(!off.contact_settings().continuous);
    let text = file::export(&off, "off", None).unwrap();
    assert!(text.contains("\ncontinuous = false\n"), "{text}");
    assert!(!file::parse(&text, "x").unwrap().world.contact_settings().continuous);
    assert!(!file::export(&on, "on", None).unwrap().contains("continuous"));
    let m = err("dimension = 2\n[contact]\ncontinuous = 1\n");
    assert!(m.contains("contact.continuous: is integer: must be true or false"), "{m}");
    assert!(!m.contains('\n'), "{m}");
}

#[test]
fn a_bullet_is_written_and_read_back_and_refused_on_a_static_solid() {
    let solid = "\n[[solids]]\nshape = { kind = \"circle\", radius = 0.05 }\nposition = [0.0, 0.0]\n";
    let w = file::parse(&format!("dimension = 2{solid}bullet = true\n"), "b.toml").unwrap().world;
    assert!(w.solid_params()[0].bullet);
    let text = file::export(&w, "b", None).unwrap();
    assert!(text.contains("\nbullet = true\n"), "{text}");
    assert!(file::parse(&text, "x").unwrap().world.solid_params()[0].bullet);
    let plain = file::parse(&format!("dimension = 2{solid}"), "p.toml").unwrap().world;
    assert!(!plain.solid_params()[0].bullet);
    assert!(!file::export(&plain, "p", None).unwrap().contains("bullet"));
    let m = err(&format!("dimension = 2{solid}kind = \"static\"\nbullet = true\n"));
    assert!(m.contains("solids[0]: invalid bullet = true: must be false for a static solid"), "{m}");
    let m = err(&format!("dimension = 2{solid}bullet = \"yes\"\n"));
    assert!(m.contains("solids[0].bullet: is string: must be true or false"), "{m}");
}
