//! `beltrami fit` as a user runs it: a mesh file in, a fitted shape out.

mod common;

use common::{beltrami, error_line, f, json, s, write};

use std::f64::consts::TAU;
use std::path::Path;

use beltrami_halfedge::{DVec3, PolygonList, primitives};
use beltrami_io::{MeshData, WriteOptions, read_mesh, write_mesh};
use beltrami_metrics::fits::{FitOptions, FitPoints, fit_sphere};
use beltrami_surfaces::{GolfBallParams, golf_ball};
use insta::assert_snapshot;
use serde_json::Value;

fn vec3(v: &Value) -> DVec3 {
    DVec3::new(f(&v[0]), f(&v[1]), f(&v[2]))
}

/// An open tube of radius `radius` around the axis through `base` along unit `axis`,
/// `around` × `along` quads split into triangles, `length` long.
fn tube(base: DVec3, axis: DVec3, radius: f64, length: f64, around: u32, along: u32) -> MeshData {
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let mut positions = Vec::new();
    for j in 0..=along {
        let t = length * f64::from(j) / f64::from(along);
        for i in 0..around {
            let phi = TAU * f64::from(i) / f64::from(around);
            positions.push(base + axis * t + (e1 * phi.cos() + e2 * phi.sin()) * radius);
        }
    }
    let id = |i: u32, j: u32| j * around + i % around;
    let mut triangles = Vec::new();
    for j in 0..along {
        for i in 0..around {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    MeshData {
        positions,
        faces: PolygonList::from_triangles(&triangles),
    }
}

#[test]
fn sphere_fit_recovers_a_moved_sphere_plain_and_weighted() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(3);
    let center = DVec3::new(10.0, -20.0, 5.0);
    let path = write(
        dir.path(),
        "ball.obj",
        sphere.positions.iter().map(|p| center + *p * 2.5).collect(),
        sphere.faces.clone(),
    );
    for weighted in [false, true] {
        let mut args = vec!["fit", "sphere", s(&path), "--json"];
        if weighted {
            args.push("--weighted");
        }
        let j = json(&args);
        assert_eq!(j["shape"], "sphere");
        assert_eq!(j["weighted"], weighted);
        assert_eq!(j["points"], 642);
        assert!(
            vec3(&j["center"]).distance(center) < 1e-9,
            "{}",
            j["center"]
        );
        assert!((f(&j["radius"]) - 2.5).abs() < 1e-9);
        assert!(f(&j["rms_residual"]) < 1e-9 && f(&j["max_residual"]) < 1e-9);
        assert_eq!(j["converged"], true);
        assert!(j["iterations"].as_u64().unwrap() <= 100);
        assert!(j.get("axis").is_none(), "a sphere has no axis");
    }
}

#[test]
fn cylinder_fit_recovers_a_generated_tube() {
    let dir = tempfile::tempdir().unwrap();
    let axis = DVec3::new(1.0, 2.0, 2.0) / 3.0;
    let base = DVec3::new(3.0, -1.0, 4.0);
    let data = tube(base, axis, 1.5, 12.0, 32, 24);
    let path = dir.path().join("tube.ply");
    write_mesh(&path, &data, &WriteOptions::default()).unwrap();
    for weighted in [false, true] {
        let mut args = vec!["fit", "cylinder", s(&path), "--json"];
        if weighted {
            args.push("--weighted");
        }
        let j = json(&args);
        assert!((f(&j["radius"]) - 1.5).abs() < 1e-9, "{}", j["radius"]);
        let fitted = vec3(&j["axis"]);
        assert!((fitted.length() - 1.0).abs() < 1e-12);
        // Reported with its largest component positive: (1, 2, 2)/3 itself.
        assert!(fitted.dot(axis) > 1.0 - 1e-12, "{fitted}");
        // The reported centre is on the axis, in the middle of the tube.
        let c = vec3(&j["center"]);
        assert!((c - base).cross(axis).length() < 1e-9);
        assert!(((c - base).dot(axis) - 6.0).abs() < 1e-6, "{c}");
        assert!(f(&j["max_residual"]) < 1e-9);
        assert_eq!(j["converged"], true);
    }
    // A sphere through a tube fits badly, and says so in its residuals.
    let j = json(&["fit", "sphere", s(&path), "--json"]);
    assert!(f(&j["rms_residual"]) > 0.5);
}

#[test]
fn circle_fit_on_a_point_set_gives_centre_normal_and_radius() {
    let dir = tempfile::tempdir().unwrap();
    let normal = DVec3::new(0.0, 0.6, 0.8);
    let (e1, e2) = (DVec3::X, normal.cross(DVec3::X));
    let center = DVec3::new(-2.0, 1.0, 0.5);
    let obj: String = (0..24)
        .map(|k| {
            let phi = TAU * f64::from(k) / 24.0;
            let p = center + (e1 * phi.cos() + e2 * phi.sin()) * 7.0;
            format!("v {} {} {}\n", p.x, p.y, p.z)
        })
        .collect();
    let ring = dir.path().join("ring.obj");
    std::fs::write(&ring, obj).unwrap();
    let j = json(&["fit", "circle", s(&ring), "--json"]);
    assert!(vec3(&j["center"]).distance(center) < 1e-9);
    assert!(vec3(&j["axis"]).distance(normal) < 1e-12, "{}", j["axis"]);
    assert!((f(&j["radius"]) - 7.0).abs() < 1e-9);
    assert!(f(&j["plane_rms"]) < 1e-12);
    assert_eq!(j["points"], 24);

    // A point set has no surface to weigh by.
    let out = beltrami(&["fit", "circle", s(&ring), "--weighted"]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: ring.obj: the mesh has 24 vertices but no faces (points or lines only; --weighted needs a surface of triangles)");
}

#[test]
fn golf_ball_fits_a_sphere_a_little_smaller_than_the_ball() {
    let dir = tempfile::tempdir().unwrap();
    let params = GolfBallParams::default();
    let ball = golf_ball(&params);
    let path = write(
        dir.path(),
        "golfball.ply",
        ball.positions.clone(),
        ball.faces.clone(),
    );
    let j = json(&["fit", "sphere", s(&path), "--json"]);
    let r = f(&j["radius"]);
    // 42.67 mm across; the dimples (0.18 mm deep, covering most of the ball) pull the
    // least-squares sphere in by a fraction of their depth.
    let nominal = params.diameter / 2.0;
    assert!(
        r < nominal - 0.02 && r > nominal - params.dimple_depth,
        "{r}"
    );
    assert!(vec3(&j["center"]).length() < 1e-3);
    let max = f(&j["max_residual"]);
    assert!(max > 0.05 && max < params.dimple_depth, "{max}");
    // The binary computes what the library computes on the file's points.
    let read = read_mesh(&path).unwrap();
    let library = fit_sphere(&FitPoints::new(&read.positions), &FitOptions::default()).unwrap();
    assert_eq!(r, library.radius);
    assert_eq!(f(&j["rms_residual"]), library.rms_residual);

    let out = beltrami(&["fit", "sphere", s(&path)]);
    assert!(out.status.success());
    let table = String::from_utf8(out.stdout).unwrap();
    for row in [
        "center ",
        "radius ",
        "rms residual ",
        "max residual ",
        "iterations ",
    ] {
        assert!(table.contains(row), "{row:?} in\n{table}");
    }
    assert!(table.contains("(converged)"), "{table}");
}

#[test]
fn too_few_or_degenerate_points_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let tri = primitives::triangle();
    let path = write(dir.path(), "tri.obj", tri.positions, tri.faces);
    let out = beltrami(&["fit", "sphere", s(&path)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: tri.obj: sphere fit needs at least 4 points in general position, got 3");
    let out = beltrami(&["fit", "cylinder", s(&path), "--weighted"]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: tri.obj: cylinder fit needs at least 5 points in general position, got 3");

    let grid = primitives::grid(3, 3);
    let flat = write(dir.path(), "flat.stl", grid.positions, grid.faces);
    let out = beltrami(&["fit", "sphere", s(&flat)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: flat.stl: sphere fit is undetermined: the points are coplanar");

    let empty = dir.path().join("empty.ply");
    std::fs::write(
        &empty,
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
    )
    .unwrap();
    let out = beltrami(&["fit", "circle", s(&empty)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: empty.ply: the mesh is empty");
}

#[test]
fn unknown_shape_is_a_usage_error() {
    let dir = Path::new("/nonexistent");
    let out = beltrami(&["fit", "cone", "part.ply"]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir), @r#"
error: invalid value 'cone' for '<SHAPE>'
  [possible values: sphere, circle, cylinder]

  tip: a similar value exists: 'cylinder'

For more information, try '--help'.
"#);
    let out = beltrami(&["fit", "sphere"]);
    assert_eq!(out.status.code(), Some(2));
    error_line(&out, dir);
}
