//! Unit tests of the mass properties: meshes against closed forms, the eigen-decomposition,
//! validation messages.
#![allow(clippy::cast_precision_loss, clippy::float_cmp, clippy::many_single_char_names)]
use std::f64::consts::PI;

use glam::{DMat3, DVec3};

use super::*;

fn mat(a: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&a)
}

/// Largest absolute difference of two 3x3 matrices.
fn diff(a: DMat3, b: DMat3) -> f64 {
    (a - b).to_cols_array().iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn props(shape: &Shape, mass: f64) -> MassProperties {
    shape.mass_properties(Some(mass), None).unwrap()
}

/// The surface of revolution about z of a profile `(rho, z)` running from a pole on the axis
/// (top) to a pole on the axis (bottom), with `n` segments: triangles outward and
/// counter-clockwise. The poles' `rho` is ignored.
fn revolve(profile: &[(f64, f64)], n: usize) -> Shape {
    let rings = profile.len() - 2;
    let mut vertices = vec![[0.0, 0.0, profile[0].1]];
    for &(rho, z) in &profile[1..=rings] {
        for i in 0..n {
            let phi = 2.0 * PI * i as f64 / n as f64;
            vertices.push([rho * phi.cos(), rho * phi.sin(), z]);
        }
    }
    vertices.push([0.0, 0.0, profile[rings + 1].1]);
    let ring = |k: usize, i: usize| 1 + (k - 1) * n + i % n;
    let south = 1 + rings * n;
    let mut triangles = Vec::new();
    for i in 0..n {
        triangles.push([0, ring(1, i), ring(1, i + 1)]);
        for k in 1..rings {
            let (a, b, c, d) = (ring(k, i), ring(k, i + 1), ring(k + 1, i), ring(k + 1, i + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
        triangles.push([south, ring(rings, i + 1), ring(rings, i)]);
    }
    Shape::Mesh { vertices, triangles }
}

/// An arc of radius `r` about `(0, z0)` from polar angle `from` to `to` in `steps` steps.
fn arc(r: f64, z0: f64, from: f64, to: f64, steps: usize) -> Vec<(f64, f64)> {
    (0..=steps)
        .map(|j| from + (to - from) * j as f64 / steps as f64)
        .map(|theta| (r * theta.sin(), z0 + r * theta.cos()))
        .collect()
}

fn uv_sphere(r: f64, n: usize) -> Shape {
    revolve(&arc(r, 0.0, 0.0, PI, n), 2 * n)
}

fn capsule_mesh(r: f64, h: f64, n: usize) -> Shape {
    let mut profile = arc(r, h / 2.0, 0.0, PI / 2.0, n);
    profile.extend(arc(r, -h / 2.0, PI / 2.0, PI, n));
    revolve(&profile, 4 * n)
}

/// Largest relative difference between the inertia of a mesh and of a closed form, and
/// their relative difference in volume.
fn mesh_error(mesh: &Shape, closed: &Shape) -> (f64, f64) {
    let (a, b) = (props(mesh, 2.0), props(closed, 2.0));
    let scale = b.principal_moments[2];
    (diff(mat(a.inertia), mat(b.inertia)) / scale, (a.volume / b.volume - 1.0).abs())
}

fn tetra() -> Shape {
    let vertices = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    Shape::Mesh { vertices, triangles: vec![[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] }
}

fn transformed(shape: &Shape, rot: DMat3, shift: DVec3) -> Shape {
    let Shape::Mesh { vertices, triangles } = shape else { unreachable!() };
    let vertices = vertices.iter().map(|&v| (rot * DVec3::from_array(v) + shift).to_array()).collect();
    Shape::Mesh { vertices, triangles: triangles.clone() }
}

fn rotation() -> DMat3 {
    DMat3::from_axis_angle(DVec3::new(1.0, -2.0, 3.0).normalize(), 0.7)
}

fn assert_eigen(a: [[f64; 3]; 3], values: [f64; 3], axes: [[f64; 3]; 3], tol: f64) {
    let r = mat(axes); // the rows of `axes` as columns
    assert!(diff(r.transpose() * r, DMat3::IDENTITY) < 1e-14, "{axes:?} not orthonormal");
    assert!((r.determinant() - 1.0).abs() < 1e-14, "{axes:?} left-handed");
    assert!(values[0] <= values[1] && values[1] <= values[2], "{values:?} not ascending");
    let d = DMat3::from_diagonal(DVec3::from_array(values));
    assert!(diff(mat(a) * r, r * d) < tol, "A v != lambda v: {a:?} {values:?} {axes:?}");
}

#[test]
fn unit_cube_mesh_equals_the_box() {
    let h = [1.0, 1.0, 1.0];
    let (mesh, closed) = (box_mesh(h).mass_properties(None, None).unwrap(), Shape::Box { half_extents: h });
    let closed = closed.mass_properties(None, None).unwrap();
    assert!((mesh.volume - 8.0).abs() < 1e-12 && (mesh.mass - 8.0).abs() < 1e-12);
    assert!((closed.volume - 8.0).abs() < 1e-12 && (closed.mass - 8.0).abs() < 1e-12);
    // m/3 (1 + 1) = 16/3 about every axis.
    let want = DMat3::from_diagonal(DVec3::splat(16.0 / 3.0));
    assert!(diff(mat(mesh.inertia), want) < 1e-12, "{:?}", mesh.inertia);
    assert!(diff(mat(closed.inertia), want) < 1e-12);
    assert!(DVec3::from_array(mesh.center).length() < 1e-12);
    // An oblong box too.
    let h = [0.5, 1.5, 2.5];
    let (a, b) = (props(&box_mesh(h), 3.0), props(&Shape::Box { half_extents: h }, 3.0));
    assert!(diff(mat(a.inertia), mat(b.inertia)) < 1e-12 && (a.volume - 15.0).abs() < 1e-12);
    assert!((b.inertia[0][0] - 3.0 / 3.0 * (1.5f64.powi(2) + 2.5f64.powi(2))).abs() < 1e-12);
}

#[test]
fn canonical_tetrahedron_matches_its_closed_form() {
    // int x^a y^b z^c over the tetrahedron (0, e1, e2, e3) is a! b! c! / (a + b + c + 3)!.
    let (volume, first, xx, xy) = (1.0 / 6.0, 1.0 / 24.0, 2.0 / 120.0, 1.0 / 120.0);
    let c = first / volume;
    // Second moments about the centroid (density 1), then the inertia.
    let (cxx, cxy) = (xx - volume * c * c, xy - volume * c * c);
    let rho = 5.0;
    let (diag, off) = (rho * 2.0 * cxx, -rho * cxy);
    let want = DMat3::from_cols_array_2d(&[[diag, off, off], [off, diag, off], [off, off, diag]]);
    let p = tetra().mass_properties(None, Some(rho)).unwrap();
    assert!((p.volume - volume).abs() < 1e-15 && (p.mass - rho * volume).abs() < 1e-14);
    assert!(DVec3::from_array(p.center).distance(DVec3::splat(0.25)) < 1e-15);
    assert!(diff(mat(p.inertia), want) < 1e-12, "{:?} vs {want}", p.inertia);
    // The same: I = m (3/40 on the diagonal, 1/80 off it).
    assert!((p.inertia[0][0] - p.mass * 3.0 / 40.0).abs() < 1e-12);
    assert!((p.inertia[0][1] - p.mass / 80.0).abs() < 1e-12);
    // Moved and rotated, the tensor turns with it: R^T I' R = I.
    let (rot, shift) = (rotation(), DVec3::new(-4.0, 7.0, 0.5));
    let q = transformed(&tetra(), rot, shift).mass_properties(None, Some(rho)).unwrap();
    assert!(DVec3::from_array(q.center).distance(rot * DVec3::splat(0.25) + shift) < 1e-12);
    assert!(diff(rot.transpose() * mat(q.inertia) * rot, want) < 1e-12);
}

#[test]
fn regular_tetrahedron_is_isotropic() {
    // Edge a = 2 sqrt 2: I = m a^2 / 20 = 2/5 m about every axis, volume a^3 / (6 sqrt 2) = 8/3.
    let vertices = vec![[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]];
    let mesh = Shape::Mesh { vertices, triangles: vec![[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]] };
    let p = props(&mesh, 10.0);
    assert!((p.volume - 8.0 / 3.0).abs() < 1e-14);
    assert!(diff(mat(p.inertia), DMat3::from_diagonal(DVec3::splat(4.0))) < 1e-13, "{:?}", p.inertia);
    assert_eigen(p.inertia, p.principal_moments, p.principal_axes, 1e-13);
}

#[test]
fn moved_rotated_box_mesh() {
    let (h, m) = ([1.0, 2.0, 3.0], 5.0);
    let (rot, shift) = (rotation(), DVec3::new(3.0, -2.0, 5.0));
    let p = props(&transformed(&box_mesh(h), rot, shift), m);
    let want = props(&Shape::Box { half_extents: h }, m);
    assert!(DVec3::from_array(p.center).distance(shift) < 1e-10, "{:?}", p.center);
    assert!((p.volume - 48.0).abs() < 1e-10 && p.mass == m);
    assert!(diff(rot.transpose() * mat(p.inertia), mat(want.inertia) * rot.transpose()) < 1e-10);
    assert!(diff(rot.transpose() * mat(p.inertia) * rot, mat(want.inertia)) < 1e-10);
    // Box moments: x 13/3 m, y 10/3 m, z 5/3 m, so ascending z, y, x.
    let moments = [5.0 / 3.0 * m, 10.0 / 3.0 * m, 13.0 / 3.0 * m];
    // The closed form's tensor is diagonal: its moments are its diagonal, sorted, exactly.
    assert_eq!(want.principal_moments, [want.inertia[2][2], want.inertia[1][1], want.inertia[0][0]]);
    assert!(want.principal_moments.iter().zip(moments).all(|(a, b)| (a - b).abs() < 1e-12));
    for (k, moment) in moments.into_iter().enumerate() {
        assert!((p.principal_moments[k] - moment).abs() < 1e-10, "{:?}", p.principal_moments);
        let axis = DVec3::from_array(p.principal_axes[k]);
        let column = rot.col(2 - k);
        assert!((axis.dot(column).abs() - 1.0).abs() < 1e-10, "axis {k}: {axis} vs {column}");
    }
    assert_eigen(p.inertia, p.principal_moments, p.principal_axes, 1e-10);
}

#[test]
fn the_vertex_mean_is_only_a_shift() {
    // The +x face fanned around an extra vertex, and an unused vertex far away: the vertex
    // mean is far from the centre of mass, the results are those of the box.
    let (h, m, shift) = ([1.0, 2.0, 3.0], 5.0, DVec3::new(3.0, -2.0, 5.0));
    let Shape::Mesh { mut vertices, mut triangles } = box_mesh(h) else { unreachable!() };
    vertices.extend([[1.0, 0.0, 0.0], [50.0, 60.0, 70.0]]);
    triangles.truncate(10);
    triangles.extend([[1, 3, 8], [3, 7, 8], [7, 5, 8], [5, 1, 8]]);
    let fanned = transformed(&Shape::Mesh { vertices, triangles }, DMat3::IDENTITY, shift);
    let (p, want) = (props(&fanned, m), props(&Shape::Box { half_extents: h }, m));
    assert!(DVec3::from_array(p.center).distance(shift) < 1e-12, "{:?}", p.center);
    assert!((p.volume - 48.0).abs() < 1e-12);
    assert!(diff(mat(p.inertia), mat(want.inertia)) < 1e-12, "{:?}", p.inertia);
}

#[test]
fn eigen_of_a_diagonal_matrix_is_exact() {
    let (values, axes) = symmetric_eigen(&[[3.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]);
    assert_eq!(values, [1.0, 2.0, 3.0]);
    assert_eq!(axes, [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]);
    // An odd permutation: the last axis turns round to stay right-handed.
    let (values, axes) = symmetric_eigen(&[[2.0, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 3.0]]);
    assert_eq!(values, [0.1, 2.0, 3.0]);
    assert_eq!(axes, [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]);
    let (values, axes) = symmetric_eigen(&[[0.0; 3]; 3]);
    assert_eq!((values, axes), ([0.0; 3], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]));
    // Closed forms are diagonal, so their moments are their diagonal exactly.
    let p = Shape::Cylinder { radius: 1.0, height: 0.1 }.mass_properties(None, Some(3.0)).unwrap();
    assert_eq!(p.principal_moments, [p.inertia[0][0], p.inertia[1][1], p.inertia[2][2]]);
    assert_eq!(p.principal_axes, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let p = Shape::Cylinder { radius: 1.0, height: 5.0 }.mass_properties(None, Some(3.0)).unwrap();
    assert_eq!(p.principal_moments, [p.inertia[2][2], p.inertia[0][0], p.inertia[1][1]]);
    assert_eq!(p.principal_axes, [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
}

#[test]
fn eigen_of_full_and_degenerate_matrices() {
    let mut s = 12345u64;
    let mut next = move || {
        s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    };
    for _ in 0..200 {
        let mut a = [[0.0; 3]; 3];
        for (i, j) in [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)] {
            a[i][j] = next();
            a[j][i] = a[i][j];
        }
        let (values, axes) = symmetric_eigen(&a);
        assert_eigen(a, values, axes, 1e-14);
        let trace = a[0][0] + a[1][1] + a[2][2];
        assert!((values.iter().sum::<f64>() - trace).abs() < 1e-14);
    }
    // A double eigenvalue, turned by a rotation, and a triple one.
    let r = rotation();
    for d in [[1.0, 1.0, 2.0], [2.0, 1.0, 1.0], [1.0, 1.0, 1.0]] {
        let a = (r * DMat3::from_diagonal(DVec3::from_array(d)) * r.transpose()).to_cols_array_2d();
        let (values, axes) = symmetric_eigen(&a);
        assert_eigen(a, values, axes, 1e-14);
        let mut sorted = d;
        sorted.sort_by(f64::total_cmp);
        assert!(values.iter().zip(sorted).all(|(x, y)| (x - y).abs() < 1e-14), "{values:?}");
    }
}

#[test]
fn cylinder_mesh_is_the_exact_prism_and_tends_to_the_closed_form() {
    let (r, h, m) = (0.7, 2.3, 4.0);
    let closed = props(&Shape::Cylinder { radius: r, height: h }, m);
    assert!((closed.inertia[2][2] - m * r * r / 2.0).abs() < 1e-15);
    assert!((closed.inertia[0][0] - m * (3.0 * r * r + h * h) / 12.0).abs() < 1e-15);
    let mut last = f64::INFINITY;
    for n in [5, 16, 64, 256] {
        let mesh = revolve(&[(0.0, h / 2.0), (r, h / 2.0), (r, -h / 2.0), (0.0, -h / 2.0)], n);
        let p = props(&mesh, m);
        // A regular n-gon of circumradius r: int |x|^2 dA = A r^2 (2 + cos(2 pi / n)) / 6.
        let polar = r * r * (2.0 + (2.0 * PI / n as f64).cos()) / 6.0;
        let want = DMat3::from_diagonal(DVec3::new(
            m * (polar / 2.0 + h * h / 12.0),
            m * (polar / 2.0 + h * h / 12.0),
            m * polar,
        ));
        assert!(diff(mat(p.inertia), want) < 1e-12, "n {n}: {:?} vs {want}", p.inertia);
        let volume = n as f64 / 2.0 * r * r * (2.0 * PI / n as f64).sin() * h;
        assert!((p.volume - volume).abs() < 1e-12 * volume);
        // Its gap to the closed form is m r^2 (1 - cos(2 pi / n)) / 6 at most.
        let gap = diff(mat(p.inertia), mat(closed.inertia));
        let bound = m * r * r * (1.0 - (2.0 * PI / n as f64).cos()) / 6.0;
        assert!(gap <= bound * (1.0 + 1e-9) && gap < last, "n {n}: {gap} vs {bound}");
        last = gap;
    }
    assert!(last / closed.principal_moments[2] < 1e-4);
}

#[test]
fn sphere_and_capsule_meshes_converge_to_the_closed_forms() {
    type Mesher = fn(usize) -> Shape;
    let cases: [(Shape, Mesher); 4] = [
        (Shape::Sphere { radius: 1.3 }, |n| uv_sphere(1.3, n)),
        (Shape::Capsule { radius: 0.5, height: 2.0 }, |n| capsule_mesh(0.5, 2.0, n)),
        (Shape::Capsule { radius: 1.0, height: 0.25 }, |n| capsule_mesh(1.0, 0.25, n)),
        (Shape::Capsule { radius: 0.1, height: 3.0 }, |n| capsule_mesh(0.1, 3.0, n)),
    ];
    for (closed, mesher) in cases {
        // Inscribed polyhedra: errors O(1/n^2), so doubling n divides them by about 4.
        let (coarse, coarse_v) = mesh_error(&mesher(48), &closed);
        let (fine, fine_v) = mesh_error(&mesher(96), &closed);
        assert!(fine < coarse / 3.0 && fine_v < coarse_v / 3.0, "{closed:?}: {coarse} {fine}");
        assert!(fine < 1e-3 && fine_v < 1e-3, "{closed:?}: {fine} {fine_v}");
        // Richardson: the extrapolated tensor is closer still, by an order of magnitude.
        let (a, b, c) = (props(&mesher(48), 2.0), props(&mesher(96), 2.0), props(&closed, 2.0));
        let extrapolated = (mat(b.inertia) * 4.0 - mat(a.inertia)) * (1.0 / 3.0);
        let err = diff(extrapolated, mat(c.inertia)) / c.principal_moments[2];
        assert!(err < fine / 10.0, "{closed:?}: {err} vs {fine}");
    }
    // The sphere's closed form itself.
    let p = props(&Shape::Sphere { radius: 1.3 }, 2.0);
    assert_eq!(p.inertia[0][0], 0.4 * 2.0 * 1.3 * 1.3);
}

#[test]
fn volumes() {
    let v = |s: Shape| s.volume().unwrap();
    assert!((v(Shape::Sphere { radius: 2.0 }) - 32.0 / 3.0 * PI).abs() < 1e-13);
    assert_eq!(v(Shape::Box { half_extents: [0.5, 1.0, 2.0] }), 8.0);
    assert!((v(Shape::Cylinder { radius: 2.0, height: 3.0 }) - 12.0 * PI).abs() < 1e-13);
    assert!((v(Shape::Capsule { radius: 2.0, height: 3.0 }) - (12.0 + 32.0 / 3.0) * PI).abs() < 1e-13);
    assert!((v(box_mesh([0.5, 1.0, 2.0])) - 8.0).abs() < 1e-14);
    assert!((v(tetra()) - 1.0 / 6.0).abs() < 1e-15);
}

#[test]
fn mass_or_density() {
    let shape = box_mesh([1.0, 2.0, 3.0]);
    let unit = shape.mass_properties(None, None).unwrap();
    assert!((unit.mass - 48.0).abs() < 1e-12 && unit.mass == unit.volume, "density 1 by default");
    let dense = shape.mass_properties(None, Some(2.5)).unwrap();
    assert!((dense.mass - 120.0).abs() < 1e-12 && dense.volume == unit.volume);
    assert!(diff(mat(dense.inertia), mat(unit.inertia) * 2.5) < 1e-12);
    let heavy = shape.mass_properties(Some(120.0), None).unwrap();
    assert_eq!(heavy.mass, 120.0);
    assert!(diff(mat(heavy.inertia), mat(dense.inertia)) < 1e-12 && heavy.center == dense.center);
    // m (y^2 + z^2) / 3 with the box's own numbers.
    assert!((heavy.inertia[0][0] - 120.0 * 13.0 / 3.0).abs() < 1e-11);
    let capsule = Shape::Capsule { radius: 1.0, height: 2.0 };
    let (a, b) =
        (capsule.mass_properties(Some(7.0), None).unwrap(), capsule.mass_properties(None, None).unwrap());
    assert!(diff(mat(a.inertia), mat(b.inertia) * (7.0 / b.mass)) < 1e-12);
    // Cylinder 2 pi, caps 4/3 pi: Izz = 2 pi / 2 + 2/5 4/3 pi, Ixx = 2 pi (1/4 + 1/3) + 4/3 pi (2/5 + 1 + 3/4).
    assert!((b.inertia[2][2] - (PI + 8.0 / 15.0 * PI)).abs() < 1e-13);
    assert!((b.inertia[0][0] - (2.0 * PI * 7.0 / 12.0 + 4.0 / 3.0 * PI * 2.15)).abs() < 1e-13);
}

/// The field and the message of an [`Error::InvalidValue`].
fn invalid<T: std::fmt::Debug>(result: Result<T>) -> (String, String) {
    match result {
        Err(e @ Error::InvalidValue { .. }) => {
            let Error::InvalidValue { field, .. } = &e else { unreachable!() };
            (field.clone(), e.to_string())
        }
        other => panic!("expected an invalid value, got {other:?}"),
    }
}

fn mesh_with(edit: impl FnOnce(&mut Vec<[f64; 3]>, &mut Vec<[usize; 3]>)) -> Shape {
    let Shape::Mesh { mut vertices, mut triangles } = box_mesh([1.0, 1.0, 1.0]) else { unreachable!() };
    edit(&mut vertices, &mut triangles);
    Shape::Mesh { vertices, triangles }
}

/// A bad input: shape, mass, density, the field named, a part of the message.
type Case = (Shape, Option<f64>, Option<f64>, &'static str, &'static str);

#[test]
fn every_bad_input_is_named() {
    let sphere = |radius| Shape::Sphere { radius };
    let cases: Vec<Case> = vec![
        (sphere(-1.0), None, None, "radius", "invalid radius = -1: must be a finite number > 0"),
        (sphere(f64::NAN), None, None, "radius", "radius = NaN"),
        (sphere(1e13), None, None, "radius", "radius = 10000000000000: must be"),
        (sphere(1e-13), None, None, "radius", "radius = 1e-13"),
        (Shape::Box { half_extents: [1.0, 0.0, 1.0] }, None, None, "half_extents[1]", "half_extents[1] = 0"),
        (Shape::Cylinder { radius: 1.0, height: f64::INFINITY }, None, None, "height", "height = inf"),
        (Shape::Cylinder { radius: -2.0, height: 1.0 }, None, None, "radius", "radius = -2"),
        (Shape::Capsule { radius: 1.0, height: 0.0 }, None, None, "height", "height = 0"),
        (sphere(1.0), Some(-1.0), None, "mass", "invalid mass = -1: must be a finite number > 0"),
        (sphere(1.0), Some(f64::NAN), None, "mass", "mass = NaN"),
        (sphere(1.0), None, Some(0.0), "density", "density = 0"),
        (sphere(1.0), Some(2.0), Some(3.0), "mass", "mass = 2: must be given alone"),
        (sphere(-1.0), Some(2.0), Some(3.0), "mass", "not both"),
        (mesh_with(|v, _| v.truncate(3)), None, None, "vertices", "vertices = 3 vertices: must be at least 4"),
        (mesh_with(|_, t| t.truncate(3)), None, None, "triangles", "triangles = 3 triangles"),
        (mesh_with(|v, _| v[3][2] = f64::NAN), None, None, "vertices[3][2]", "vertices[3][2] = NaN"),
        (mesh_with(|v, _| v[0][0] = -2e12), None, None, "vertices[0][0]", "= -2000000000000: must be finite"),
        (mesh_with(|_, t| t[5][1] = 8), None, None, "triangles[5][1]", "triangles[5][1] = 8: must be a vertex index < 8"),
        (mesh_with(|_, t| t[4] = [3, 1, 3]), None, None, "triangles[4]", "triangles[4] = [3, 1, 3]: must be three distinct"),
        (mesh_with(|_, t| { t.remove(0); }), None, None, "triangles[0]", "[1, 2, 3]: must be part of a closed, consistently oriented mesh, but its edge (1, 2) has no reverse (2, 1)"),
        (mesh_with(|_, t| t[0] = [0, 1, 2]), None, None, "triangles[0]", "edge (0, 1) is in 2 triangles"),
        (mesh_with(|_, t| t.push([0, 2, 1])), None, None, "triangles[0]", "edge (0, 2) is in 2 triangles"),
        (mesh_with(|_, t| t.iter_mut().for_each(|x| x.swap(1, 2))), None, None, "triangles", "invalid triangles = signed volume -8: must be wound counter-clockwise seen from outside; the mesh is inside out (triangles wound clockwise seen from outside)"),
        (mesh_with(|v, _| v.iter_mut().for_each(|x| x[2] = 0.5)), None, None, "triangles", "triangles = signed volume 0: must be a mesh enclosing a volume"),
    ];
    for (shape, mass, density, field, text) in cases {
        let (got, message) = invalid(shape.mass_properties(mass, density));
        assert_eq!(got, field, "{message}");
        assert!(message.contains(text), "{message:?} lacks {text:?}");
        assert!(!message.contains('\n'));
        if mass.is_none() && density.is_none() {
            assert_eq!(invalid(shape.validate()), (got.clone(), message.clone()));
            assert_eq!(invalid(shape.volume()), (got, message));
        }
    }
    // Every valid shape validates.
    for shape in
        [sphere(1.0), box_mesh([1e-3, 1.0, 1e3]), tetra(), uv_sphere(1.0, 8), capsule_mesh(1.0, 1.0, 4)]
    {
        shape.validate().unwrap();
    }
}
