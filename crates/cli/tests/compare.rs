//! `beltrami compare` as a user runs it: mesh files in, distances out.

mod common;

use common::{beltrami, error_line, f, json, s};

use std::path::{Path, PathBuf};

use beltrami_halfedge::{DVec3, primitives};
use beltrami_io::{MeshData, WriteOptions, write_mesh};
use beltrami_metrics::distance::SurfaceIndex;
use beltrami_viz::render::ColorMap;
use insta::assert_snapshot;
use ply_rs_bw::ply::{DefaultElement, Property};
use serde_json::Value;

fn write(
    dir: &Path,
    name: &str,
    positions: Vec<DVec3>,
    faces: &beltrami_halfedge::PolygonList,
) -> PathBuf {
    let path = dir.join(name);
    let data = MeshData {
        positions,
        faces: faces.clone(),
    };
    write_mesh(&path, &data, &WriteOptions::default()).unwrap();
    path
}

fn text(args: &[&str], dir: &Path) -> String {
    let out = beltrami(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .replace(&format!("{}/", dir.display()), "")
}

/// The one stderr line of a failed run, with the temporary directory removed.
/// The smallest distance from the origin to the plane of a face of an icosphere: the
/// polyhedron lies between this radius and 1 (the chordal bound).
fn inradius(sphere: &primitives::Primitive) -> f64 {
    sphere
        .faces
        .iter()
        .map(|face| {
            let [a, b, c] = [0, 1, 2].map(|k| sphere.positions[face[k] as usize]);
            (b - a).cross(c - a).normalize().dot(a)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn grown_icosphere_is_the_scale_offset_from_its_original() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(3);
    let h = inradius(&sphere);
    assert!(h > 0.98 && h < 1.0);
    let reference = write(
        dir.path(),
        "sphere.ply",
        sphere.positions.clone(),
        &sphere.faces,
    );
    let scale = 1.01;
    let grown = write(
        dir.path(),
        "grown.obj",
        sphere.positions.iter().map(|p| *p * scale).collect(),
        &sphere.faces,
    );
    let j = json(&["compare", s(&grown), s(&reference), "--json"]);
    // Each grown vertex is 0.01 straight above its original, the closest point of the
    // convex reference.
    for key in ["rms", "mean", "max", "area_rms"] {
        assert!((f(&j[key]) - 0.01).abs() < 1e-12, "{key}: {}", j[key]);
    }
    assert!((f(&j["signed"]["min"]) - 0.01).abs() < 1e-12, "all outside");
    assert!((f(&j["signed"]["mean"]) - 0.01).abs() < 1e-12);
    assert!(f(&j["signed"]["std_dev"]) < 1e-12);
    // The reference's vertices lie inside the grown polyhedron, (s − 1)·h_f below the
    // planes of their faces.
    let back = f(&j["hausdorff_reference_to_mesh"]);
    assert!(back < 0.01 && back >= 0.01 * h - 1e-12, "{back}");
    assert!((f(&j["hausdorff_mesh_to_reference"]) - 0.01).abs() < 1e-12);
    assert_eq!(j["hausdorff"], j["hausdorff_mesh_to_reference"]);
    assert_eq!(j["hausdorff_samples"], 0);
    // Same topology: the plain displacement and the (unchanged) normals.
    assert_eq!(j["same_topology"], true);
    assert!((f(&j["displacement"]["max"]) - 0.01).abs() < 1e-12);
    let normals = &j["normal_deviation_deg"];
    assert!(f(&normals["max"]) < 1e-6 && f(&normals["mean"]) < 1e-6);
    assert_eq!(normals["faces"], 1280);
    assert!(f(&j["normal_area_weighted_error"]) < 1e-8);
    // Areas scale by s², volumes by s³.
    let (am, ar) = (f(&j["area"]["mesh"]), f(&j["area"]["reference"]));
    assert!((am / ar - scale * scale).abs() < 1e-12);
    assert!(ar < 4.0 * std::f64::consts::PI && ar > 0.98 * 4.0 * std::f64::consts::PI);
    let ratio = f(&j["volume"]["ratio"]);
    assert!((ratio - scale.powi(3)).abs() < 1e-12, "{ratio}");
    let vr = f(&j["volume"]["reference"]);
    assert!(vr < 4.0 / 3.0 * std::f64::consts::PI && vr > 0.97 * 4.0 / 3.0 * std::f64::consts::PI);
    assert_eq!(j["mesh"]["closed"], true);
    assert_eq!(j["scalars"], Value::Null);
}

#[test]
fn shrunk_icosphere_in_stl_lies_inside_within_the_chordal_bound() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(3);
    let h = inradius(&sphere);
    let reference = write(
        dir.path(),
        "sphere.ply",
        sphere.positions.clone(),
        &sphere.faces,
    );
    let scale = 0.98;
    let shrunk = write(
        dir.path(),
        "shrunk.stl",
        sphere.positions.iter().map(|p| *p * scale).collect(),
        &sphere.faces,
    );
    let j = json(&["compare", s(&shrunk), s(&reference), "--json"]);
    // A vertex s·v is (1 − s)·h_f below the plane of each face f around v.
    let (lo, hi) = ((1.0 - scale) * h, 1.0 - scale);
    for key in ["rms", "mean", "max"] {
        let d = f(&j[key]);
        assert!(
            d >= lo - 1e-12 && d <= hi + 1e-12,
            "{key} = {d} not in [{lo}, {hi}]"
        );
    }
    assert!(f(&j["signed"]["max"]) < 0.0, "every vertex is inside");
    assert!((f(&j["signed"]["mean"]) + f(&j["mean"])).abs() < 1e-15);
    assert!((f(&j["volume"]["ratio"]) - scale.powi(3)).abs() < 1e-6);
}

#[test]
fn surface_samples_find_the_face_interiors_that_vertices_miss() {
    let dir = tempfile::tempdir().unwrap();
    // The coarse icosphere's vertices are vertices of the fine one, but its faces cut
    // through the sphere: their middles are a sagitta below the fine surface.
    let coarse = primitives::icosphere(1);
    let fine = primitives::icosphere(4);
    let sagitta = 1.0 - inradius(&coarse);
    let mesh = write(
        dir.path(),
        "coarse.ply",
        coarse.positions.clone(),
        &coarse.faces,
    );
    let reference = write(dir.path(), "fine.obj", fine.positions.clone(), &fine.faces);
    let vertices = json(&["compare", s(&mesh), s(&reference), "--json"]);
    assert!(f(&vertices["hausdorff_mesh_to_reference"]) < 1e-12);
    assert!(f(&vertices["max"]) < 1e-12);
    let sampled = json(&[
        "compare",
        s(&mesh),
        s(&reference),
        "--json",
        "--samples",
        "20000",
    ]);
    assert_eq!(sampled["hausdorff_samples"], 20000);
    let forward = f(&sampled["hausdorff_mesh_to_reference"]);
    assert!(
        forward > 0.8 * sagitta && forward <= sagitta,
        "{forward} vs sagitta {sagitta}"
    );
    assert!(f(&sampled["hausdorff"]) >= forward);
    // The same run gives the same samples.
    let again = json(&[
        "compare",
        s(&mesh),
        s(&reference),
        "--json",
        "--samples",
        "20000",
    ]);
    assert_eq!(again["hausdorff"], sampled["hausdorff"]);
    // Different topologies: no per-vertex displacement, no normal deviation.
    assert_eq!(sampled["same_topology"], false);
    assert_eq!(sampled["displacement"], Value::Null);
    assert_eq!(sampled["normal_deviation_deg"], Value::Null);
    assert_eq!(sampled["normal_area_weighted_error"], Value::Null);
    assert!(sampled["volume"].is_object());
    let table = text(&["compare", s(&mesh), s(&reference)], dir.path());
    let rows: Vec<&str> = table
        .lines()
        .filter(|l| l.contains("displacement") || l.contains("normal deviation"))
        .collect();
    assert_snapshot!(rows.join("\n"), @r"
      displacement        - (the meshes do not share their topology: 42 vertices vs 2562)
      normal deviation    - (the meshes do not share their topology: 42 vertices vs 2562)
    ");
}

#[test]
fn open_meshes_have_no_volume_and_the_table_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let grid = primitives::grid(4, 3);
    let reference = write(dir.path(), "grid.obj", grid.positions.clone(), &grid.faces);
    let lifted = write(
        dir.path(),
        "lifted.ply",
        grid.positions.iter().map(|p| *p + DVec3::Z * 0.5).collect(),
        &grid.faces,
    );
    let j = json(&["compare", s(&lifted), s(&reference), "--json"]);
    assert_eq!(j["volume"], Value::Null);
    assert_eq!(j["mesh"]["closed"], false);
    assert_eq!(j["rms"], 0.5);
    assert_eq!(
        j["signed"]["min"], 0.5,
        "lifted along the normals: positive"
    );
    assert_eq!(j["area"]["mesh"], 12.0);
    assert_snapshot!(text(&["compare", s(&lifted), s(&reference)], dir.path()), @r"
    mesh                  lifted.ply (20 vertices, 24 faces, open)
    reference             grid.obj (20 vertices, 24 faces, open)
    unit                  the files' length unit (areas in unit², volumes in unit³), not scaled
    distance of the mesh's vertices to the reference surface (closest point on the closest triangle)
      rms                 0.5
      mean                0.5
      max                 0.5
      area-weighted rms   0.5
    signed distance (positive on the side the reference's normals point to: outside)
      mean                0.5
      min                 0.5
      max                 0.5
      std dev             0
    surfaces
      hausdorff           0.5 (mesh -> reference 0.5, reference -> mesh 0.5; from vertices)
      displacement        rms 0.5, mean 0.5, max 0.5, area-weighted rms 0.5 (vertex i to vertex i)
      normal deviation    mean 0°, rms 0°, max 0° over 24 faces; area-weighted error 0
      area                mesh 12, reference 12
      volume              - (both meshes are open)
    ");

    // A closed mesh against an open reference: still no volume pair.
    let cube = primitives::cube();
    let closed = write(dir.path(), "cube.stl", cube.positions.clone(), &cube.faces);
    let j = json(&["compare", s(&closed), s(&reference), "--json"]);
    assert_eq!(j["volume"], Value::Null);
    let table = text(&["compare", s(&closed), s(&reference)], dir.path());
    let volume = table.lines().find(|l| l.starts_with("  volume")).unwrap();
    assert_snapshot!(volume, @"  volume              - (grid.obj is open)");
}

/// A closed but flat reference (a tetrahedron squashed into its base plane) encloses no
/// volume: the ratio is left out (null in the JSON), not printed as inf or NaN.
#[test]
fn a_reference_of_no_volume_has_no_volume_ratio() {
    let dir = tempfile::tempdir().unwrap();
    let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.3, 0.3, 0.0)];
    let faces = beltrami_halfedge::PolygonList::from_triangles(&[
        [0, 2, 1],
        [0, 1, 3],
        [0, 3, 2],
        [1, 2, 3],
    ]);
    let flat = write(dir.path(), "flat.ply", positions.clone(), &faces);
    // The same in a tilted plane, where its volume is not 0 but rounding (1e-17).
    let tilt = |p: DVec3| DVec3::new(p.x, p.y, 0.3 * p.x + 0.7 * p.y + 0.1);
    let tilted = write(
        dir.path(),
        "tilted.ply",
        positions.iter().map(|&p| tilt(p)).collect(),
        &faces,
    );
    let mut lifted = positions;
    lifted[3].z = 1.0;
    let tetra = write(dir.path(), "tetra.ply", lifted, &faces);
    for reference in [&flat, &tilted] {
        for mesh in [&flat, &tetra] {
            let j = json(&["compare", s(mesh), s(reference), "--json"]);
            assert!(f(&j["volume"]["reference"]).abs() < 1e-15, "{j}");
            if reference == &tilted {
                // Rounding, not zero: the case the threshold is for.
                assert_ne!(f(&j["volume"]["reference"]), 0.0, "{j}");
            }
            assert_eq!(j["volume"]["ratio"], Value::Null, "{j}");
            let table = text(&["compare", s(mesh), s(reference)], dir.path());
            let volume = table.lines().find(|l| l.starts_with("  volume")).unwrap();
            assert!(
                volume.ends_with("ratio - (the reference encloses no volume)"),
                "{volume}"
            );
        }
    }
    // Against the tetrahedron the ratio is there.
    let j = json(&["compare", s(&flat), s(&tetra), "--json"]);
    assert_eq!(j["volume"]["ratio"], 0.0);
}

#[test]
fn scalars_ply_holds_the_library_signed_distances_and_a_diverging_colour_map() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(3);
    let reference = write(
        dir.path(),
        "sphere.ply",
        sphere.positions.clone(),
        &sphere.faces,
    );
    // A bumpy copy: some vertices out, some in.
    let bumpy: Vec<DVec3> = sphere
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| *p * (1.0 + 0.02 * ((i as f64) * 0.7).sin()))
        .collect();
    let mesh = write(dir.path(), "bumpy.obj", bumpy.clone(), &sphere.faces);
    let out_ply = dir.path().join("distances.ply");
    let j = json(&[
        "compare",
        s(&mesh),
        s(&reference),
        "--json",
        "--scalars",
        s(&out_ply),
    ]);

    let index = SurfaceIndex::new(&sphere.mesh().unwrap(), &sphere.positions).unwrap();
    let want = index.signed_distances(&bumpy).unwrap();
    let largest = want.iter().fold(0.0f64, |m, d| m.max(d.abs()));
    assert_eq!(j["scalars"]["file"], s(&out_ply));
    assert_eq!(f(&j["scalars"]["color_range"]), largest);

    let mut file = std::fs::File::open(&out_ply).unwrap();
    let ply = ply_rs_bw::parser::Parser::<DefaultElement>::new()
        .read_ply(&mut file)
        .unwrap();
    let vertices = &ply.payload["vertex"];
    assert_eq!(vertices.len(), 642);
    assert_eq!(ply.payload["face"].len(), 1280);
    let double = |e: &DefaultElement, k: &str| match e[k] {
        Property::Double(v) => v,
        ref other => panic!("{k} is {other:?}"),
    };
    let uchar = |e: &DefaultElement, k: &str| match e[k] {
        Property::UChar(v) => v,
        ref other => panic!("{k} is {other:?}"),
    };
    let (mut outside, mut inside) = (0, 0);
    for (i, e) in vertices.iter().enumerate() {
        assert_eq!(double(e, "x"), bumpy[i].x, "positions as read");
        let d = double(e, "signed_distance");
        assert_eq!(d, want[i], "vertex {i}");
        let rgb = [uchar(e, "red"), uchar(e, "green"), uchar(e, "blue")];
        assert_eq!(rgb, ColorMap::symmetric(largest).color(d));
        if d > 1e-3 {
            assert!(rgb[0] > rgb[2], "outside is red: {d} {rgb:?}");
            outside += 1;
        } else if d < -1e-3 {
            assert!(rgb[2] > rgb[0], "inside is blue: {d} {rgb:?}");
            inside += 1;
        }
        if d.abs() == largest {
            assert!(rgb == ColorMap::HIGH || rgb == ColorMap::LOW);
        }
    }
    assert!(outside > 100 && inside > 100, "{outside} {inside}");
    assert_eq!(ColorMap::symmetric(largest).color(0.0), [255, 255, 255]);
}

#[test]
fn bad_input_is_one_error_line_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(1);
    let good = write(
        dir.path(),
        "sphere.ply",
        sphere.positions.clone(),
        &sphere.faces,
    );
    let empty = dir.path().join("empty.ply");
    std::fs::write(
        &empty,
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\nproperty double y\nproperty double z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
    )
    .unwrap();
    let out = beltrami(&["compare", s(&empty), s(&good)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: empty.ply: the mesh is empty");
    let out = beltrami(&["compare", s(&good), s(&empty)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: empty.ply: the mesh is empty");

    let cloud = dir.path().join("cloud.obj");
    std::fs::write(&cloud, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let out = beltrami(&["compare", s(&good), s(&cloud)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: cloud.obj: the mesh has 3 vertices but no faces (points or lines only; compare needs a surface of triangles)");

    let quad = dir.path().join("quad.obj");
    std::fs::write(&quad, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    let out = beltrami(&["compare", s(&good), s(&quad)]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: quad.obj: face 0 has 4 vertices; this operation needs a triangle mesh");

    let missing = dir.path().join("missing.stl");
    let out = beltrami(&["compare", s(&good), s(&missing)]);
    assert_eq!(out.status.code(), Some(1));
    assert!(error_line(&out, dir.path()).starts_with("error: missing.stl: "));
}

#[test]
fn bad_usage_is_exit_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(1);
    let good = write(
        dir.path(),
        "sphere.ply",
        sphere.positions.clone(),
        &sphere.faces,
    );
    let stl = dir.path().join("out.stl");
    let out = beltrami(&["compare", s(&good), s(&good), "--scalars", s(&stl)]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @"error: --scalars writes a PLY file (per-vertex scalars need PLY), got 'out.stl' (see 'beltrami --help')");
    assert!(!stl.exists());
    let out = beltrami(&["compare", s(&good), s(&good), "--samples", "0"]);
    assert_eq!(out.status.code(), Some(2));
    error_line(&out, dir.path());
    let out = beltrami(&["compare", s(&good)]);
    assert_eq!(out.status.code(), Some(2));
    error_line(&out, dir.path());
}
