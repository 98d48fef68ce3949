//! `beltrami info` as a user runs it: real files in, numbers or one error line out.

mod common;

use std::path::{Path, PathBuf};

use common::{beltrami, error_line};
use insta::assert_snapshot;
use serde_json::Value;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

fn info_json(path: &Path) -> Value {
    let out = beltrami(&["info", path.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn close(value: &Value, expected: f64, tol: f64) -> bool {
    (value.as_f64().expect("a number") - expected).abs() <= tol
}

#[test]
fn cube_in_every_format_gives_the_same_numbers() {
    for name in [
        "cube_binary.stl",
        "cube_ascii.stl",
        "cube.obj",
        "cube_ascii.ply",
    ] {
        let j = info_json(&fixture(name));
        assert_eq!(j["vertices"], 8, "{name}");
        assert_eq!(j["faces"], 12, "{name}");
        assert_eq!(j["edges"], 18, "{name}");
        assert_eq!(j["boundary_loops"], 0, "{name}");
        assert_eq!(j["components"], 1, "{name}");
        assert_eq!(j["euler_characteristic"], 2, "{name}");
        assert_eq!(j["closed"], true, "{name}");
        assert_eq!(j["genus"], 0, "{name}");
        assert!(close(&j["area"], 6.0, 1e-12), "{name}");
        assert!(close(&j["volume"], 1.0, 1e-12), "{name}");
        assert_eq!(j["bbox_min"], serde_json::json!([0.0, 0.0, 0.0]), "{name}");
        assert_eq!(j["bbox_max"], serde_json::json!([1.0, 1.0, 1.0]), "{name}");
        // 12 unit edges and 6 face diagonals of length √2.
        let mean = (12.0 + 6.0 * 2f64.sqrt()) / 18.0;
        assert!(close(&j["mean_edge_length"], mean, 1e-12), "{name}");
    }
}

#[test]
fn open_mesh_reports_boundary_and_null_volume() {
    let j = info_json(&fixture("grid_4x3.obj"));
    assert_eq!(j["vertices"], 20);
    assert_eq!(j["faces"], 24);
    assert_eq!(j["boundary_loops"], 1);
    assert_eq!(j["boundary_loop_lengths"], serde_json::json!([14]));
    assert_eq!(j["closed"], false);
    assert_eq!(j["volume"], Value::Null);
    // A disc: χ = 1 = 2 − 2g − b with one boundary loop.
    assert_eq!(j["genus"], 0);
    assert_eq!(j["component_genus"], serde_json::json!([0]));
    assert!(close(&j["area"], 12.0, 1e-12));
}

#[test]
fn torus_has_genus_one() {
    let j = info_json(&fixture("torus_12x8.ply"));
    assert_eq!(j["euler_characteristic"], 0);
    assert_eq!(j["genus"], 1);
    assert!(j["volume"].as_f64().unwrap() > 0.0);
}

#[test]
fn table_output_lists_the_counts() {
    let out = beltrami(&["info", fixture("tetrahedron_ascii.ply").to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for expected in [
        "vertices              4",
        "faces                 4 (triangles)",
        "edges                 6",
        "closed                yes",
        "genus                 0",
    ] {
        assert!(text.contains(expected), "missing {expected:?} in\n{text}");
    }
}

#[test]
fn invalid_topology_is_one_error_line_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let bowtie = dir.path().join("bowtie.obj");
    std::fs::write(
        &bowtie,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n",
    )
    .unwrap();
    let out = beltrami(&["info", bowtie.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: bowtie.obj: non-manifold vertex 0: its faces form 2 separate fans (pass --repair, or keep a repaired copy with 'beltrami repair bowtie.obj REPAIRED')");

    let out = beltrami(&["info", bowtie.to_str().unwrap(), "--repair", "--json"]);
    assert!(out.status.success());
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["vertices"], 6);
    assert_eq!(j["components"], 2);
    // [input vertex, its new copy]: vertex 0 split, the copy numbered after the 5 others.
    assert_eq!(j["repairs"]["split_vertices"], serde_json::json!([[0, 5]]));
}

#[test]
fn flipped_face_is_reported_and_repairable() {
    let dir = tempfile::tempdir().unwrap();
    let quad = dir.path().join("quad.obj");
    std::fs::write(
        &quad,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 4 3\n",
    )
    .unwrap();
    let out = beltrami(&["info", quad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: quad.obj: inconsistent orientation: faces 0 and 1 both traverse edge 2 -> 0 (pass --repair, or keep a repaired copy with 'beltrami repair quad.obj REPAIRED')");
    let out = beltrami(&["info", quad.to_str().unwrap(), "--repair"]);
    assert!(out.status.success());
    assert!(
        String::from_utf8(out.stdout)
            .unwrap()
            .contains("repaired: re-oriented 1 face (input faces 1)")
    );
}

#[test]
fn unreadable_files_are_one_error_line_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.ply");
    let out = beltrami(&["info", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out, dir.path());
    assert!(line.starts_with("error: missing.ply: "), "{line}");

    let garbage = dir.path().join("garbage.stl");
    std::fs::write(&garbage, [0xffu8, 0x00, 0x13, 0x37, 0x42]).unwrap();
    let out = beltrami(&["info", garbage.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(error_line(&out, dir.path()).starts_with("error: garbage.stl: "));

    let unknown = dir.path().join("mesh.xyz");
    std::fs::write(&unknown, "1 2 3\n").unwrap();
    let out = beltrami(&["info", unknown.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(error_line(&out, dir.path()).starts_with("error: mesh.xyz: "));
}

#[test]
fn bad_usage_is_one_error_line_and_exit_2() {
    let dir = Path::new("/nonexistent");
    for args in [
        &["info"][..],
        &["info", "a.ply", "--frobnicate"],
        &["smoosh"],
    ] {
        let out = beltrami(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        error_line(&out, dir);
    }
    let out = beltrami(&["info", "--frobnicate", "a.ply"]);
    assert_snapshot!(error_line(&out, dir), @r#"
error: unexpected argument '--frobnicate' found

  tip: to pass '--frobnicate' as a value, use '-- --frobnicate'

Usage: beltrami info [OPTIONS] <MESH>

For more information, try '--help'.
"#);
}

#[test]
fn help_goes_to_stdout_with_exit_0() {
    let out = beltrami(&["info", "--help"]);
    assert!(out.status.success());
    assert!(String::from_utf8(out.stdout).unwrap().contains("--json"));
}

/// `beltrami schemes | head -1`: when the reader of stdout has gone, the command ends
/// without an error line (exit 141, as a shell reports a program ended by SIGPIPE).
#[test]
fn a_closed_stdout_ends_the_command_quietly() {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args([
            "info",
            fixture("noisy_icosphere_4.ply").to_str().unwrap(),
            "--quality",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Close the only read end before the command has started to write.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(stderr.is_empty(), "{stderr}");
    // 0 only if the whole output fitted into the pipe before the reader went.
    assert!(
        matches!(out.status.code(), Some(141 | 0)),
        "{:?}",
        out.status
    );
}

#[test]
fn quality_figures_match_the_library() {
    for name in [
        "obtuse_grid_24x16.ply",
        "noisy_icosphere_4.ply",
        "holes_30x20.ply",
    ] {
        let path = fixture(name);
        let out = beltrami(&["info", path.to_str().unwrap(), "--json", "--quality"]);
        assert!(out.status.success(), "{name}");
        let j: Value = serde_json::from_slice(&out.stdout).unwrap();
        let q = &j["quality"];
        let data = beltrami_io::read_mesh(&path).unwrap();
        let want =
            beltrami_algorithms::mesh_quality(&data.mesh().unwrap(), &data.positions).unwrap();
        let shape = want.shape.unwrap();
        assert_eq!(q["min_angle_degrees"], shape.min_angle, "{name}");
        assert_eq!(q["max_aspect_ratio"], shape.max_aspect_ratio, "{name}");
        assert_eq!(q["negative_cotangent_edges"], want.negative_cotangent_edges);
        assert_eq!(q["edge_length_cv"], want.edge_length.unwrap().cv);
        assert_eq!(
            q["valence_histogram"].as_array().unwrap().len(),
            want.valence_histogram.len()
        );
        assert!(q["flipped_faces"].is_null());
        let histogram: usize = q["aspect_ratio_histogram"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_u64().unwrap() as usize)
            .sum();
        assert_eq!(histogram + want.degenerate_faces, want.faces, "{name}");
    }
    // The obtuse grid is the fixture made to have negative cotangent weights.
    let j = info_json_quality(&fixture("obtuse_grid_24x16.ply"));
    assert!(j["quality"]["negative_cotangent_edges"].as_u64().unwrap() > 0);
    // Without --quality the key is absent.
    assert!(info_json(&fixture("cube.obj")).get("quality").is_none());
}

fn info_json_quality(path: &Path) -> Value {
    let out = beltrami(&["info", path.to_str().unwrap(), "--json", "--quality"]);
    assert!(out.status.success());
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn quality_table_and_flipped_faces_against_a_reference() {
    let dir = tempfile::tempdir().unwrap();
    let grid = fixture("grid_4x3.ply");
    // The same grid with one interior vertex dragged across its neighbours.
    let mut data = beltrami_io::read_mesh(&grid).unwrap();
    data.positions[6].x += 3.0;
    let moved = dir.path().join("moved.ply");
    beltrami_io::write_mesh(&moved, &data, &beltrami_io::WriteOptions::default()).unwrap();
    let out = beltrami(&[
        "info",
        moved.to_str().unwrap(),
        "--quality",
        "--reference",
        grid.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    for key in [
        "angles",
        "aspect ratio",
        "edge length",
        "valences",
        "negative cotangent",
    ] {
        assert!(text.lines().any(|l| l.starts_with(key)), "{key}: {text}");
    }
    let flipped = text
        .lines()
        .find(|l| l.starts_with("flipped faces"))
        .expect("a flipped-faces row");
    let n: usize = flipped.split_whitespace().nth(2).unwrap().parse().unwrap();
    assert!(n > 0, "{flipped}");

    // A reference with other faces is refused with one line, exit 1.
    let cube = fixture("cube.obj");
    let out = beltrami(&[
        "info",
        moved.to_str().unwrap(),
        "--quality",
        "--reference",
        cube.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(error_line(&out, dir.path()).contains("same faces"));
    // The same sphere as STL (welded, renumbered): as many faces, numbered otherwise,
    // and the line says so instead of "320 faces against 320".
    let out = beltrami(&[
        "info",
        fixture("icosphere_2.ply").to_str().unwrap(),
        "--quality",
        "--reference",
        fixture("icosphere_2.stl").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let line = error_line(&out, dir.path());
    assert!(line.contains("numbered differently"), "{line}");
    assert!(!line.contains("320 faces against 320"), "{line}");
    // --reference without --quality is a usage error.
    let out = beltrami(&[
        "info",
        moved.to_str().unwrap(),
        "--reference",
        cube.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    // A polygon mesh has no triangle quality.
    let out = beltrami(&[
        "info",
        fixture("cube_quads.obj").to_str().unwrap(),
        "--quality",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(error_line(&out, dir.path()).contains("needs a triangle mesh"));
}
