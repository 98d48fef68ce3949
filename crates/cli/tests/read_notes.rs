//! The metric commands (`compare`, `fit`, `residual`, `render`) say what reading did
//! besides reading: a `--repair` of the input is printed and listed in the JSON `notes`,
//! as `info` and the editing commands do. And negative option values in scientific
//! notation are values, not options.

mod common;

use std::path::{Path, PathBuf};

use beltrami_io::read_mesh;
use common::{beltrami, json, s, write};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

/// The level-2 icosphere with its first face turned over: `--repair` turns it back.
fn flipped(dir: &Path) -> PathBuf {
    let mesh = read_mesh(fixtures().join("icosphere_2.ply")).unwrap();
    let mut triangles: Vec<[u32; 3]> = mesh.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
    triangles[0].swap(1, 2);
    write(
        dir,
        "flipped.ply",
        mesh.positions,
        beltrami_halfedge::PolygonList::from_triangles(&triangles),
    )
}

#[test]
fn the_metric_commands_say_what_repair_changed() {
    let dir = tempfile::tempdir().unwrap();
    let input = flipped(dir.path());
    let reference = fixtures().join("icosphere_2.ply");
    let png = dir.path().join("out.png");
    let repaired = |line: &str| line.contains("repaired:");
    for (args, named) in [
        (vec!["compare", s(&input), s(&reference), "--repair"], true),
        (vec!["fit", "sphere", s(&input), "--repair"], false),
        (
            vec!["residual", s(&input), "--form", "sphere", "--repair"],
            false,
        ),
        (vec!["render", s(&input), s(&png), "--repair"], false),
    ] {
        let out = beltrami(&args);
        assert!(out.status.success(), "{args:?}: {out:?}");
        let stdout = String::from_utf8_lossy(&out.stdout);
        let lines: Vec<&str> = stdout.lines().filter(|l| repaired(l)).collect();
        assert_eq!(lines.len(), 1, "{args:?}: {stdout}");
        // A command reading two meshes names the file.
        assert_eq!(lines[0].starts_with(s(&input)), named, "{}", lines[0]);
        // Without --repair the file is refused (so the note is about the repair).
        let plain: Vec<&str> = args.iter().copied().filter(|a| *a != "--repair").collect();
        assert_eq!(beltrami(&plain).status.code(), Some(1), "{plain:?}");
        if args[0] != "render" {
            let mut with_json = args.clone();
            with_json.push("--json");
            let j = json(&with_json);
            let notes = j["notes"].as_array().expect("notes");
            assert_eq!(notes.len(), 1, "{j}");
            assert!(repaired(notes[0].as_str().unwrap()), "{j}");
        }
    }
    // Nothing to say, nothing said: an empty list.
    let j = json(&["fit", "sphere", s(&reference), "--json"]);
    assert_eq!(j["notes"], serde_json::json!([]));
}

#[test]
fn negative_values_in_scientific_notation_are_values() {
    let reference = fixtures().join("icosphere_2.ply");
    let j = json(&[
        "residual",
        s(&reference),
        "--form",
        "sphere",
        "--smr",
        "-1e-7",
        "--json",
    ]);
    assert_eq!(j["smr"][0]["height"], -1e-7);
    // A bad negative value gets the option's own message, not the parser's.
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("out.ply");
    let out = beltrami(&["smooth", s(&reference), s(&out_path), "--lambda", "-1e-3"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("lambda must be in (0, 1]"), "{stderr}");
}

/// STL holds triangles: a polygon mesh written as STL says its faces became fans; the
/// same run to OBJ says nothing of the kind.
#[test]
fn polygons_written_to_stl_are_said_to_become_fans() {
    let dir = tempfile::tempdir().unwrap();
    let quads = fixtures().join("cube_quads.obj");
    let note = "note: STL holds triangles only: 6 polygon faces are written as triangle fans";
    for (name, expected) in [("out.stl", true), ("out.obj", false)] {
        let out = dir.path().join(name);
        let o = beltrami(&["smooth", s(&quads), s(&out), "--weights", "uniform"]);
        assert!(o.status.success(), "{o:?}");
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert_eq!(stdout.contains(note), expected, "{stdout}");
    }
}
