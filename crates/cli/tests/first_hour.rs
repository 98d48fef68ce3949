//! A new user's first hour: the cases a careless and a hostile user tried, each with
//! what must happen now. Files from the wild are in `tests/wild/` (see its README).

mod common;

use std::path::{Path, PathBuf};

use common::{beltrami, error_line, s};

fn wild(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/wild")
        .join(name)
}

fn wild_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/wild")
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

/// Whether `text` has `line` as one of its lines.
fn text_has(text: &str, line: &str) -> bool {
    text.lines().any(|l| l == line)
}

fn stdout(args: &[&str]) -> String {
    let out = beltrami(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn info(path: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["info", s(path), "--json"];
    args.extend_from_slice(extra);
    serde_json::from_str(&stdout(&args)).unwrap()
}

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".beltrami-"))
        .collect()
}

// A. An output is never lost.

#[test]
fn two_outputs_naming_one_file_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = fixture("icosphere_2.ply");
    let out = d.join("out.ply");
    let o = beltrami(&["smooth", s(&input), s(&out), "--report", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        error_line(&o, d),
        "error: OUTPUT and --report name the same file out.ply; each output needs its own file (see 'beltrami --help')"
    );
    assert!(!out.exists());
    // The same file by another spelling, a symbolic link or a hard link.
    std::fs::write(&out, b"old").unwrap();
    let alias = d.join(".").join("out.ply");
    let hard = d.join("hard.ply");
    std::fs::hard_link(&out, &hard).unwrap();
    let mut aliases = vec![alias, hard];
    #[cfg(unix)]
    {
        let link = d.join("link.json");
        std::os::unix::fs::symlink(&out, &link).unwrap();
        aliases.push(link);
    }
    for report in &aliases {
        let o = beltrami(&["smooth", s(&input), s(&out), "--report", s(report)]);
        assert_eq!(o.status.code(), Some(2), "{report:?}");
        assert_eq!(std::fs::read(&out).unwrap(), b"old");
    }
    let g = d.join("g.ply");
    let o = beltrami(&[
        "generate",
        "flens",
        s(&g),
        "--noise",
        "0.1",
        "--clean",
        s(&g),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(error_line(&o, d).contains("OUTPUT and --clean name the same file"));
    assert!(!g.exists());
    let o = beltrami(&[
        "compare",
        s(&input),
        s(&input),
        "--scalars",
        s(&d.join("x.ply")),
        "--png",
        s(&d.join("x.ply")),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_failed_run_writes_nothing_and_names_the_path_given() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("r.ply");
    std::fs::write(&out, b"old").unwrap();
    let missing = d.join("nonexist").join("r.json");
    let o = beltrami(&[
        "smooth",
        s(&fixture("icosphere_2.ply")),
        s(&out),
        "--report",
        s(&missing),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let line = error_line(&o, d);
    assert!(
        line.starts_with("error: nonexist/r.json: failed to find the output's directory: "),
        "{line}"
    );
    assert!(line.contains("nonexist"), "{line}");
    assert!(!line.contains(".beltrami-"), "{line}");
    assert!(o.stdout.is_empty());
    assert_eq!(std::fs::read(&out).unwrap(), b"old");
    assert!(temporaries(d).is_empty());
}

#[cfg(unix)]
#[test]
fn a_write_protected_output_is_refused_without_force_and_a_link_is_written_through() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = fixture("icosphere_2.ply");
    let out = d.join("ro.ply");
    std::fs::write(&out, b"old").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o444)).unwrap();
    let o = beltrami(&["smooth", s(&input), s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        error_line(&o, d),
        "error: ro.ply: the file is write-protected (pass --force to replace it)"
    );
    assert_eq!(std::fs::read(&out).unwrap(), b"old");
    stdout(&["smooth", s(&input), s(&out), "--force"]);
    assert_ne!(std::fs::read(&out).unwrap(), b"old");
    assert!(
        std::fs::metadata(&out).unwrap().permissions().readonly(),
        "the file keeps its permissions"
    );

    let target = d.join("target.ply");
    std::fs::write(&target, b"old").unwrap();
    let link = d.join("link.ply");
    std::os::unix::fs::symlink("target.ply", &link).unwrap();
    stdout(&["smooth", s(&input), s(&link)]);
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        beltrami_io::read_mesh(&target).unwrap().positions.len(),
        162
    );
}

// B and G. Files from the wild: read as the other tools read them, or refused with a
// message naming what is wrong (and a repair that works).

#[test]
fn files_from_the_wild_read_right_or_fail_with_the_line_or_element() {
    // (file, vertices, faces, closed)
    for (name, vertices, faces, closed) in [
        ("bom.obj", 4, 4, true),
        ("cr_only.obj", 4, 4, true),
        ("continuation.obj", 4, 4, true),
        ("cube.off", 8, 12, true),
        ("cad_roundoff.stl", 8, 12, true),
        ("tristrips.ply", 4, 2, false),
        ("lines_only.obj", 3, 0, false),
    ] {
        let j = info(&wild(name), &[]);
        assert_eq!(j["vertices"], vertices, "{name}");
        assert_eq!(j["faces"], faces, "{name}");
        assert_eq!(j["closed"], closed, "{name}");
    }
    let dir = wild_dir();
    for (name, message) in [
        (
            "ply_renamed.obj",
            "line 1: \"ply\" is not an obj statement; is this a ply file? rename it to .ply",
        ),
        (
            "extra_faces.ply",
            "line 17: unexpected data after the 3 faces the header declares (pass --lenient to read what the header declares and ignore the rest)",
        ),
        (
            "trailing_bytes.ply",
            "22 unexpected bytes after the 4 faces the header declares (pass --lenient to read what the header declares and ignore the rest)",
        ),
        (
            "duplicate_property.ply",
            "line 5: invalid ply header: property \"x\" of element \"vertex\" is declared twice",
        ),
    ] {
        let o = beltrami(&["info", s(&wild(name))]);
        assert_eq!(o.status.code(), Some(1), "{name}");
        assert_eq!(error_line(&o, &dir), format!("error: {name}: {message}"));
    }
    // A CAD part welded by exact bits only: cracks, which the default tolerance closes.
    let o = beltrami(&[
        "info",
        s(&wild("cad_roundoff.stl")),
        "--weld-tolerance",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let text = stdout(&["info", s(&wild("cad_roundoff.stl"))]);
    assert!(text.contains("note: welded 11 vertices"), "{text}");
    // A tolerance that would weld the part's own corners is a usage error.
    for bad in ["-1", "1e300", "0.5"] {
        let o = beltrami(&[
            "info",
            s(&wild("cad_roundoff.stl")),
            "--weld-tolerance",
            bad,
        ]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
    }
}

#[test]
fn every_command_that_needs_faces_refuses_a_mesh_without_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let lines = wild("lines_only.obj");
    let empty = d.join("empty.ply");
    beltrami_io::write_mesh(
        &empty,
        &beltrami_io::MeshData::default(),
        &beltrami_io::WriteOptions::default(),
    )
    .unwrap();
    let out = d.join("out.ply");
    let repaired = d.join("repaired.ply");
    let png = d.join("out.png");
    for args in [
        vec!["smooth", s(&lines), s(&out)],
        vec!["repair", s(&lines), s(&repaired)],
        vec!["render", s(&lines), s(&png)],
        vec!["compare", s(&lines), s(&lines)],
        vec!["residual", s(&lines), s(&lines)],
    ] {
        let o = beltrami(&args);
        if args[0] == "repair" {
            // A wireframe repaired is still a wireframe: written, with no faces.
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            continue;
        }
        let line = error_line(&o, &wild_dir());
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert!(line.contains("has 3 vertices but no faces"), "{line}");
    }
    let o = beltrami(&["smooth", s(&empty), s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(error_line(&o, d).contains("the mesh is empty"));
    assert!(!out.exists());
}

// D. A repaired mesh you can keep.

#[test]
fn a_duplicate_face_is_dropped_not_turned_into_a_pinch() {
    let j = info(&wild("tet_duplicate_face.obj"), &["--repair"]);
    assert_eq!(j["vertices"], 4);
    assert_eq!(j["components"], 1);
    assert_eq!(j["closed"], true);
    assert_eq!(
        j["repairs"]["dropped_duplicate_faces"],
        serde_json::json!([[4, 1]])
    );
}

#[test]
fn repair_writes_a_mesh_every_command_accepts() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = wild("two_tets_on_an_edge.obj");
    // The error names a command that exists and fixes it.
    let o = beltrami(&["smooth", s(&input), s(&d.join("s.ply"))]);
    assert_eq!(o.status.code(), Some(1));
    let line = error_line(&o, &wild_dir());
    assert!(
        line.ends_with(
            "(pass --repair, or keep a repaired copy with 'beltrami repair two_tets_on_an_edge.obj REPAIRED')"
        ),
        "{line}"
    );
    let repaired = d.join("repaired.ply");
    let text = stdout(&["repair", s(&input), s(&repaired)]);
    assert!(
        text.contains("repaired: cut 1 non-manifold edge into manifold sheets (0-1)"),
        "{text}"
    );
    let j = info(&repaired, &[]);
    assert_eq!(j["components"], 2);
    assert_eq!(j["closed"], true);
    assert_eq!(j["component_genus"], serde_json::json!([0, 0]));
    stdout(&["smooth", s(&repaired), s(&d.join("s.ply"))]);
    // --repair on the reading command does the same in one step.
    let text = stdout(&["smooth", s(&input), s(&d.join("t.ply")), "--repair"]);
    assert!(text.contains("repaired: cut 1 non-manifold edge"), "{text}");
    // With --json the editing commands say it in their `notes`.
    for (command, extra) in [
        ("remesh", None),
        ("decimate", Some(["--ratio", "0.9"])),
        ("fill-holes", None),
        ("delaunay", None),
        ("subdivide", None),
    ] {
        let output = d.join(format!("{command}.ply"));
        let mut args = vec![command, s(&input), s(&output), "--repair", "--json"];
        args.extend(extra.iter().flatten());
        let j: serde_json::Value = serde_json::from_str(&stdout(&args)).unwrap();
        let notes = j["notes"]
            .as_array()
            .unwrap_or_else(|| panic!("{command}: {j}"));
        assert!(
            notes.iter().any(|n| n
                .as_str()
                .unwrap()
                .starts_with("repaired: cut 1 non-manifold edge")),
            "{command}: {j}"
        );
    }
    // --json lists every element.
    let j: serde_json::Value = serde_json::from_str(&stdout(&[
        "repair",
        s(&input),
        s(&d.join("u.obj")),
        "--json",
    ]))
    .unwrap();
    assert_eq!(j["repairs"]["cut_edges"], serde_json::json!([[0, 1]]));
    assert_eq!(j["vertices"], 8);
    // STL keeps no vertex indices: the copies the cut split off would be welded back on
    // reading, so a repair into STL is refused, and no file is written.
    let stl = d.join("repaired.stl");
    let o = beltrami(&["repair", s(&input), s(&stl)]);
    assert_eq!(o.status.code(), Some(1));
    let line = error_line(&o, d);
    assert_eq!(
        line,
        "error: repaired.stl: an STL file keeps no vertex indices, so the 2 vertices the repair split off would be joined again when it is read; write .ply, .obj or .off"
    );
    assert!(!stl.exists());
    // The same for every command that writes a mesh after --repair: they keep the
    // input's positions, or at least the boundary's, where the copies lie.
    for (command, extra) in [
        ("fill-holes", None),
        ("delaunay", None),
        ("remesh", None),
        ("decimate", Some("--ratio=0.5")),
        ("subdivide", None),
        ("smooth", None),
    ] {
        let mut args = vec![command, s(&input), s(&stl), "--repair"];
        args.extend(extra);
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(1), "{command}");
        assert!(error_line(&o, d).contains("an STL file keeps no vertex indices"));
        assert!(!stl.exists());
    }
    // `info` of a repaired open fan (three triangles on one edge) sees the split copies
    // beside their originals and does not advise a merge that would undo the repair.
    let fan = d.join("fan.off");
    std::fs::write(
        &fan,
        "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n3 0 1 2\n3 1 0 3\n3 0 1 4\n",
    )
    .unwrap();
    let repaired = d.join("fan.ply");
    stdout(&["repair", s(&fan), s(&repaired)]);
    let table = stdout(&["info", s(&repaired)]);
    assert!(
        table.contains(
            "note: 2 vertices lie within 3e-6 of another, so the surface is in pieces along them; joined, they would make it non-manifold"
        ) && !table.contains("--merge-distance"),
        "{table}"
    );
    // A seam (two squares side by side, their shared edge written twice) beside two
    // triangles touching at a corner: the merge is advised for the seam, and the corner
    // is said to come apart again.
    let mixed = d.join("mixed.obj");
    std::fs::write(
        &mixed,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 5 5 0\nv 6 5 0\nv 5 6 0\nv 5 5 0\nv 4 5 0\nv 5 4 0\nf 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\nf 9 10 11\nf 12 13 14\n",
    )
    .unwrap();
    let table = stdout(&["info", s(&mixed)]);
    assert!(
        table.contains("note: 3 vertices lie within")
            && table.contains(
                "joins them where the surface stays manifold (1 would be split apart again)"
            ),
        "{table}"
    );
}

#[test]
fn near_duplicate_vertices_merge_with_a_distance() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Two triangles of a square whose shared edge is duplicated 1e-9 apart.
    let soup = d.join("soup.obj");
    std::fs::write(
        &soup,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 1e-9\nv 1 1 1e-9\nv 0 1 0\nf 1 2 3\nf 4 5 6\n",
    )
    .unwrap();
    let out = d.join("merged.ply");
    let text = stdout(&["repair", s(&soup), s(&out), "--merge-distance", "1e-6"]);
    assert!(
        text.contains("repaired: merged 2 vertices (3 into 0, 4 into 2)"),
        "{text}"
    );
    let j = info(&out, &[]);
    assert_eq!(j["vertices"], 4);
    assert_eq!(j["boundary_loops"], 1);
    let o = beltrami(&["repair", s(&soup), s(&out), "--merge-distance", "-1"]);
    assert_eq!(o.status.code(), Some(2));
    // A distance in the wrong unit merges everything: nothing is left, nothing written.
    let emptied = d.join("emptied.ply");
    let o = beltrami(&["repair", s(&soup), s(&emptied), "--merge-distance", "1e300"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        error_line(&o, d),
        "error: soup.obj: the repair left none of the 2 faces: every one was degenerate or a duplicate once vertices closer than 1e300 were merged (is --merge-distance in the mesh's unit?); nothing written"
    );
    assert!(!emptied.exists());
}

// E. Messages and exit codes.

#[test]
fn usage_errors_keep_the_parsers_whole_message() {
    let o = beltrami(&["smooth", "in.ply"]);
    assert_eq!(o.status.code(), Some(2));
    let text = String::from_utf8(o.stderr).unwrap();
    assert!(
        text.starts_with(
            "error: the following required arguments were not provided:\n  <OUTPUT>\n"
        ),
        "{text}"
    );
    assert!(text.contains("Usage: beltrami smooth"), "{text}");
    let o = beltrami(&["smooth", "a.ply", "b.ply", "--method", "taubn"]);
    let text = String::from_utf8(o.stderr).unwrap();
    assert!(
        text.contains("[possible values: explicit, taubin, hc, implicit]"),
        "{text}"
    );
    assert!(
        text.contains("tip: a similar value exists: 'taubin'"),
        "{text}"
    );
}

#[test]
fn every_command_exits_2_for_usage_and_1_for_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bad = d.join("bad.ply");
    std::fs::write(&bad, b"not a ply file").unwrap();
    let good = fixture("icosphere_2.ply");
    let out = d.join("o.ply");
    let png = d.join("o.png");
    let nowhere = d.join("missing").join("x.ply");
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec!["info", s(&good), "--frobnicate"],
            vec!["info", s(&bad)],
        ),
        (
            vec!["smooth", s(&good), s(&out), "--lambda", "2"],
            vec!["smooth", s(&bad), s(&out)],
        ),
        (
            vec!["repair", s(&good), s(&out), "--merge-distance", "nan"],
            vec!["repair", s(&bad), s(&out)],
        ),
        (
            vec!["generate", "teapot", s(&out)],
            vec!["generate", "flens", s(&nowhere)],
        ),
        (
            vec!["compare", s(&good)],
            vec!["compare", s(&bad), s(&good)],
        ),
        (
            vec!["fit", "cone", s(&good)],
            vec!["fit", "sphere", s(&bad)],
        ),
        (
            vec!["residual", s(&good), s(&good), "--scalars", "x.obj"],
            vec!["residual", s(&bad), s(&good)],
        ),
        (
            vec!["render", s(&good), s(&png), "--size", "0x0"],
            vec!["render", s(&bad), s(&png)],
        ),
        (vec!["schemes", "--frobnicate"], vec![]),
        (vec!["study", "--surfaces", "teapot"], vec![]),
    ];
    for (usage, input) in cases {
        let o = beltrami(&usage);
        assert_eq!(o.status.code(), Some(2), "{usage:?}");
        let line = error_line(&o, d);
        assert!(
            !line.starts_with(&format!("error: {}", s(&good))),
            "a usage error starts with the input path: {line}"
        );
        if !input.is_empty() {
            let o = beltrami(&input);
            assert_eq!(o.status.code(), Some(1), "{input:?}");
            error_line(&o, d);
        }
    }
}

#[test]
fn numbers_read_as_english_and_with_sensible_digits() {
    let text = stdout(&["info", s(&fixture("flens_68x33.ply"))]);
    assert!(
        text.contains("bbox min              (-30.0362, -14.552, -0.34809)"),
        "{text}"
    );
    assert!(text.contains("mean edge length      1.09288"), "{text}");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.ply");
    let text = stdout(&["generate", "sphere", s(&out), "--level", "0"]);
    assert!(
        text.starts_with("generated sphere (12 vertices, 20 faces, unitless) -> "),
        "{text}"
    );
    // The area is inf only when the true area is beyond f64.
    let big = dir.path().join("big.obj");
    std::fs::write(&big, "v 0 0 0\nv 1.5e154 0 0\nv 0 1.5e154 0\nf 1 2 3\n").unwrap();
    let area = info(&big, &[])["area"].as_f64().unwrap();
    assert!((area / 1.125e308 - 1.0).abs() < 1e-15, "{area}");
    let huge = dir.path().join("huge.obj");
    std::fs::write(&huge, "v 0 0 0\nv 1e200 0 0\nv 0 1e200 0\nf 1 2 3\n").unwrap();
    assert!(stdout(&["info", s(&huge)]).contains("area                  inf"));
    // A fit on coordinates beyond its arithmetic says so.
    let far = dir.path().join("far.obj");
    std::fs::write(
        &far,
        "v 1e200 0 0\nv 0 1e200 0\nv 0 0 1e200\nv -1e200 0 0\nv 0 -1e200 0\nv 0 0 -1e200\n",
    )
    .unwrap();
    let o = beltrami(&["fit", "sphere", s(&far)]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        error_line(&o, dir.path()),
        "error: far.obj: point 0 has the coordinate 1e200, beyond the 1e150 this computation supports; express the mesh in a larger unit"
    );
}

#[test]
fn smooth_summarises_boundary_displacement_and_volume() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.ply");
    let text = stdout(&["smooth", s(&fixture("icosphere_2.ply")), s(&out)]);
    assert!(
        text.contains(", no boundary, completed; mean displacement "),
        "{text}"
    );
    assert!(text.contains(", volume 4.04704 -> "), "{text}");
    let text = stdout(&["smooth", s(&fixture("flens_68x33.ply")), s(&out), "--force"]);
    assert!(
        text.contains(", fixed boundary, completed; mean displacement "),
        "{text}"
    );
    assert!(!text.contains("volume"), "{text}");
}

// F. What a user expects to find.

#[test]
fn the_schemes_are_listed_where_a_user_looks() {
    let text = stdout(&["schemes"]);
    for name in ["uniform", "distance", "cotangent", "bilateral"] {
        assert!(
            text.lines().any(|l| l.starts_with(name)),
            "{name} missing: {text}"
        );
    }
    let help = stdout(&["smooth", "--help"]);
    assert!(help.contains("bilateral"), "{help}");
    assert!(help.contains("'beltrami schemes' lists them"), "{help}");
    let help = stdout(&["study", "--help"]);
    assert!(
        help.contains("[default: 10,20,30,40,50,60,70,80,90,100,200]"),
        "{help}"
    );
}

#[test]
fn study_refuses_a_directory_that_holds_other_files() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("thesis.tex"), b"precious").unwrap();
    let o = beltrami(&["study", "--out", s(dir.path()), "--small"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(error_line(&o, dir.path()).contains("holds 'thesis.tex'"));
    assert_eq!(
        std::fs::read(dir.path().join("thesis.tex")).unwrap(),
        b"precious"
    );
}

#[test]
fn noise_is_relative_to_the_mean_edge_in_generate_as_in_study() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("n.ply");
    let text = stdout(&["generate", "flens", s(&out), "--noise", "0.2"]);
    assert!(
        text.contains("normal noise sigma = 0.21052 mm, 0.2 x the mean edge length"),
        "{text}"
    );
    let text = stdout(&[
        "generate",
        "flens",
        s(&out),
        "--noise",
        "0.2",
        "--absolute-noise",
    ]);
    assert!(
        text.contains("normal noise sigma = 0.2 mm (seed 1)"),
        "{text}"
    );
}

#[test]
fn study_replaces_an_earlier_study_as_a_whole() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let args = [
        "study",
        "--out",
        s(&out),
        "--small",
        "--surfaces",
        "flens",
        "--weights",
        "uniform",
        "--iterations",
        "1",
        "--no-countermeasures",
    ];
    let text = stdout(&args);
    assert!(
        text.contains(&format!(
            "the paper's statements checked (evidence and numbers in {}):",
            s(&out.join("report.md"))
        )),
        "{text}"
    );
    // A plot of an earlier, larger study does not survive the next one.
    let stale = out.join("plots").join("rms_golfball.svg");
    std::fs::write(&stale, b"stale").unwrap();
    stdout(&args);
    assert!(!stale.exists());
    assert!(out.join("report.md").exists());
    assert!(temporaries(dir.path()).is_empty());
}

#[test]
fn a_closed_part_with_mixed_winding_is_repaired_facing_outward() {
    let dir = tempfile::tempdir().unwrap();
    let input = wild("mixed_winding_cube.obj");
    let o = beltrami(&["info", s(&input)]);
    assert_eq!(o.status.code(), Some(1));
    let out = dir.path().join("cube.ply");
    stdout(&["repair", s(&input), s(&out)]);
    // Consistent and outward: the unit cube's volume is +1, not -1.
    let j = info(&out, &[]);
    assert_eq!(j["closed"], true);
    assert_eq!(j["volume"], 1.0);
}

#[test]
fn near_duplicate_vertices_are_named_in_the_error_and_merged_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let input = wild("cad_near_duplicates.obj");
    let o = beltrami(&["smooth", s(&input), s(&dir.path().join("s.ply"))]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        error_line(&o, &wild_dir()),
        "error: cad_near_duplicates.obj: non-manifold vertex 8: its faces form 2 separate fans (1 vertex lies within 2e-6 of another: pass --repair --merge-distance 2e-6, or keep a repaired copy with 'beltrami repair cad_near_duplicates.obj REPAIRED --merge-distance 2e-6')"
    );
    // Cutting the pinch apart works but opens the surface; the note says why.
    let cut = dir.path().join("cut.ply");
    let text = stdout(&["repair", s(&input), s(&cut)]);
    assert!(
        text.contains(
            "note: 1 vertex lies within 2e-6 of another; --merge-distance 2e-6 joins them"
        ),
        "{text}"
    );
    assert_eq!(info(&cut, &[])["closed"], false);
    // The suggested command gives the closed cube back.
    let merged = dir.path().join("merged.ply");
    stdout(&["repair", s(&input), s(&merged), "--merge-distance", "2e-6"]);
    let j = info(&merged, &[]);
    assert_eq!(
        (j["vertices"].as_u64(), j["closed"].as_bool()),
        (Some(8), Some(true))
    );
    stdout(&[
        "smooth",
        s(&input),
        s(&dir.path().join("s.ply")),
        "--repair",
        "--merge-distance",
        "2e-6",
    ]);
    // Without --repair the distance is refused rather than ignored.
    let o = beltrami(&["info", s(&input), "--merge-distance", "2e-6"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_ply_header_without_elements_is_an_empty_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty_header.ply");
    std::fs::write(&path, "ply\nformat ascii 1.0\nend_header\n").unwrap();
    let j = info(&path, &[]);
    assert_eq!(
        (j["vertices"].as_u64(), j["faces"].as_u64()),
        (Some(0), Some(0))
    );
    std::fs::write(&path, "ply\nformat ascii 1.0\nend_header\n1 2 3\n").unwrap();
    let o = beltrami(&["info", s(&path)]);
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn a_ply_that_holds_more_than_its_header_reads_with_lenient() {
    let dir = wild_dir();
    for (name, faces, ignored) in [
        (
            "extra_faces.ply",
            3,
            "ignoring 1 line after the last element",
        ),
        (
            "trailing_bytes.ply",
            4,
            "ignoring 22 bytes after the last element",
        ),
    ] {
        let o = beltrami(&["info", s(&wild(name))]);
        assert_eq!(o.status.code(), Some(1));
        assert!(
            error_line(&o, &dir)
                .ends_with("(pass --lenient to read what the header declares and ignore the rest)"),
            "{name}"
        );
        let text = stdout(&["info", s(&wild(name)), "--lenient"]);
        assert!(text.contains(ignored), "{text}");
        assert_eq!(info(&wild(name), &["--lenient"])["faces"], faces, "{name}");
    }
    // Extra values on a line: the declared ones are read, the rest ignored.
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("extra_values.ply");
    std::fs::write(
        &path,
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 9 1 1 1 1 1 1 1 1 1\n",
    )
    .unwrap();
    let o = beltrami(&["info", s(&path)]);
    assert_eq!(o.status.code(), Some(1));
    let text = stdout(&["info", s(&path), "--lenient"]);
    assert!(
        text.contains(
            "ignoring values beyond the header's properties on 1 line (the first: line 13)"
        ),
        "{text}"
    );
    assert_eq!(info(&path, &["--lenient"])["faces"], 1);
}

#[test]
fn a_mesh_split_at_seams_is_pointed_to_its_merge() {
    // A cube as six separate quads, each with its own four corners (as exporters write
    // texture seams): it reads as six pieces, and `info` says how to join them.
    let dir = tempfile::tempdir().unwrap();
    let cube = beltrami_halfedge::primitives::cube_quads();
    let mut text = String::new();
    for face in cube.faces.iter() {
        for &v in face {
            let p = cube.positions[v as usize];
            text.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
        }
    }
    for f in 0..cube.faces.len() {
        let k = 4 * f + 1;
        text.push_str(&format!("f {} {} {} {}\n", k, k + 1, k + 2, k + 3));
    }
    let path = dir.path().join("seams.obj");
    std::fs::write(&path, text).unwrap();
    let j = info(&path, &[]);
    assert_eq!(j["components"], 6);
    let table = stdout(&["info", s(&path)]);
    assert!(
        table.contains(
            "note: 16 vertices lie within 2e-6 of another, so the surface is in pieces along them"
        ),
        "{table}"
    );
    let joined = dir.path().join("joined.ply");
    stdout(&["repair", s(&path), s(&joined), "--merge-distance", "2e-6"]);
    let j = info(&joined, &[]);
    assert_eq!(
        (
            j["vertices"].as_u64(),
            j["components"].as_u64(),
            j["closed"].as_bool()
        ),
        (Some(8), Some(1), Some(true))
    );
}

/// The pipeline of docs/pipeline.md: a scan-like lens (noise and three holes) is
/// filled, remeshed and smoothed, and each step brings it closer to the clean lens.
#[test]
fn scan_fill_remesh_smooth_residual_each_step_helps() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    stdout(&[
        "generate",
        "flens",
        s(&p("scan.ply")),
        "--noise",
        "0.2",
        "--holes",
        "3",
        "--clean",
        s(&p("lens.ply")),
    ]);
    stdout(&["fill-holes", s(&p("scan.ply")), s(&p("filled.ply"))]);
    stdout(&["remesh", s(&p("filled.ply")), s(&p("even.ply"))]);
    stdout(&["smooth", s(&p("even.ply")), s(&p("smooth.ply"))]);
    let compare = |name: &str| -> serde_json::Value {
        serde_json::from_str(&stdout(&[
            "compare",
            s(&p(name)),
            s(&p("lens.ply")),
            "--json",
        ]))
        .unwrap()
    };
    let f = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap();
    let (scan, filled, even, smooth) = (
        compare("scan.ply"),
        compare("filled.ply"),
        compare("even.ply"),
        compare("smooth.ply"),
    );
    // Filling: the lens is covered again (the reference's farthest point from the mesh
    // falls from a hole's radius to the noise's reach), and only the outline is open.
    assert!(
        f(&filled, "hausdorff_reference_to_mesh") < f(&scan, "hausdorff_reference_to_mesh") / 3.0
    );
    assert_eq!(info(&p("filled.ply"), &[])["boundary_loops"], 1);
    // Each later step lowers the RMS distance to the clean lens.
    assert!(f(&filled, "rms") <= f(&scan, "rms") * 1.01);
    assert!(f(&even, "rms") < f(&filled, "rms"));
    assert!(f(&smooth, "rms") < 0.7 * f(&even, "rms"));
    // The residual of the remeshed scan from its smoothed version is the noise: its Sq
    // is of the order of the noise's σ (0.2 of the mean edge length).
    let residual: serde_json::Value = serde_json::from_str(&stdout(&[
        "residual",
        s(&p("even.ply")),
        s(&p("smooth.ply")),
        "--json",
    ]))
    .unwrap();
    let sigma = 0.2
        * info(&p("lens.ply"), &[])["mean_edge_length"]
            .as_f64()
            .unwrap();
    let sq = residual["sq"].as_f64().unwrap();
    assert!(
        sq > 0.5 * sigma && sq < 1.2 * sigma,
        "Sq {sq}, sigma {sigma}"
    );
}

/// An STL file stores triangles only: a vertex in no face is not written, and every
/// command that writes one says so (in its sentence's notes, `--json` and `--report`),
/// while PLY keeps it without a note.
#[test]
fn stl_output_says_it_leaves_out_vertices_in_no_face() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = d.join("stray.ply");
    std::fs::write(
        &input,
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty double x\nproperty double y\nproperty double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n5 5 5\n3 0 1 2\n3 1 3 2\n",
    )
    .unwrap();
    let note = "note: an STL file stores triangles only: the 1 vertex in no face is not written (.ply, .obj and .off keep them)";
    for (command, extra) in [
        ("smooth", &[][..]),
        ("subdivide", &[][..]),
        ("delaunay", &[][..]),
        ("fill-holes", &[][..]),
        ("remesh", &["--edge-length", "0.5"][..]),
        ("decimate", &["--ratio", "0.9"][..]),
    ] {
        let stl = d.join(format!("{command}.stl"));
        let mut args = vec![command, s(&input), s(&stl)];
        args.extend_from_slice(extra);
        let text = stdout(&args);
        assert!(text.lines().any(|l| l == note), "{command}: {text}");
        let written = beltrami_io::read_mesh(&stl).unwrap();
        assert!(
            written.positions.iter().all(|p| p.x < 2.0),
            "{command}: the stray vertex was written"
        );
        let ply = d.join(format!("{command}.ply"));
        let mut args = vec![command, s(&input), s(&ply)];
        args.extend_from_slice(extra);
        let text = stdout(&args);
        assert!(!text.contains("STL"), "{command}: {text}");
        assert!(
            beltrami_io::read_mesh(&ply)
                .unwrap()
                .positions
                .iter()
                .any(|p| p.x == 5.0),
            "{command}: PLY lost the stray vertex"
        );
        if command == "smooth" {
            let report = d.join("smooth.json");
            let args = [
                command,
                s(&input),
                s(&stl),
                "--report",
                s(&report),
                "--force",
            ];
            stdout(&args);
            let j: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
            assert_eq!(j["notes"], serde_json::json!([note]), "{j}");
        } else {
            let mut args = vec![command, s(&input), s(&stl), "--json", "--force"];
            args.extend_from_slice(extra);
            let j: serde_json::Value = serde_json::from_str(&stdout(&args)).unwrap();
            // Decimation also notes the isolated vertex it keeps, after the summary line
            // and in the report.
            let mut notes = vec![note.to_string()];
            if command == "decimate" {
                notes.push("note: the input has 1 isolated vertex in no face; it is kept as it is and counted in the vertex counts and the target (--repair removes them)".into());
                let mut plain = vec![command, s(&input), s(&stl), "--force"];
                plain.extend_from_slice(extra);
                assert!(text_has(&stdout(&plain), &notes[1]), "{command}");
            }
            assert_eq!(j["notes"], serde_json::json!(notes), "{command}: {j}");
        }
    }
}

/// A square closed by a cap (a vertex on the diagonal, a zero-area triangle): `info`
/// names it and the command that removes it; `repair --flat-faces` flips it away without
/// moving the surface; its options are checked; a polygon mesh is refused.
#[test]
fn repair_removes_flat_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cap = d.join("cap.obj");
    std::fs::write(
        &cap,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 0\nf 1 2 5\nf 2 3 5\nf 1 3 4\nf 1 5 3\n",
    )
    .unwrap();
    let table = stdout(&["info", s(&cap)]);
    assert!(
        table.contains("note: 1 face is of zero area") && table.contains("--flat-faces"),
        "{table}"
    );
    let out = d.join("clean.ply");
    let text = stdout(&["repair", s(&cap), s(&out), "--flat-faces"]);
    assert_eq!(
        text.lines().collect::<Vec<_>>(),
        [
            "repaired: removed 1 flat triangle (1 edge flipped)".to_string(),
            format!(
                "repaired {} (5 vertices, 4 faces): 1 of 1 flat triangle removed -> {} (5 vertices, 4 faces)",
                cap.display(),
                out.display()
            )
        ]
    );
    let j = info(&out, &[]);
    assert_eq!(
        (j["degenerate_faces"].as_u64(), j["area"].as_f64()),
        (Some(0), Some(1.0))
    );
    assert!(!stdout(&["info", s(&out)]).contains("zero area"));
    // `delaunay` flips no flat triangle (it has no cotangent weight) and says so.
    let flipped = d.join("flipped.ply");
    let text = stdout(&["delaunay", s(&cap), s(&flipped)]);
    assert!(
        text.contains("note: 1 face of zero area left (flat for its size)")
            && text.contains("--flat-faces"),
        "{text}"
    );
    assert!(!stdout(&["delaunay", s(&out), s(&flipped), "--force"]).contains("zero area"));
    let j: serde_json::Value = serde_json::from_str(&stdout(&[
        "repair",
        s(&cap),
        s(&out),
        "--flat-faces",
        "--json",
        "--force",
    ]))
    .unwrap();
    assert_eq!(
        j["flat_triangles"],
        serde_json::json!({"before": 1, "after": 0, "flips": 1, "deleted": 0, "alone": 0, "collapses": 0, "max_move": 0.0, "max_height": 0.0})
    );
    // Without --flat-faces the cap stays, and the JSON says null.
    let j: serde_json::Value =
        serde_json::from_str(&stdout(&["repair", s(&cap), s(&out), "--json", "--force"])).unwrap();
    assert_eq!(j["flat_triangles"], serde_json::Value::Null);
    assert_eq!(info(&out, &[])["degenerate_faces"], 1);
    // Usage errors: the options need --flat-faces and their ranges.
    // They are checked before the input is read (a missing input is not named).
    for args in [
        vec!["--flat-ratio", "1e-3"],
        vec!["--flat-faces", "--flat-ratio", "0.2"],
        vec!["--flat-faces", "--flat-max-move", "-1"],
    ] {
        for input in [cap.clone(), d.join("missing.obj")] {
            let mut all = vec!["repair", s(&input), s(&out), "--force"];
            all.extend(args.iter().copied());
            let o = beltrami(&all);
            assert_eq!(o.status.code(), Some(2), "{args:?}");
        }
    }
    // A mesh of slivers only: removing them would leave nothing, which is refused.
    let slivers = d.join("slivers.obj");
    std::fs::write(&slivers, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    let o = beltrami(&[
        "repair",
        s(&slivers),
        s(&d.join("none.ply")),
        "--flat-faces",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(error_line(&o, d).contains("left no face"));
    assert!(!d.join("none.ply").exists());
    // A polygon mesh: one clear line.
    let quad = d.join("quad.obj");
    std::fs::write(&quad, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    let o = beltrami(&["repair", s(&quad), s(&d.join("q.ply")), "--flat-faces"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        error_line(&o, d),
        "error: quad.obj: face 0 has 4 vertices; --flat-faces needs a triangle mesh (--triangulate splits the polygons into triangles)"
    );
    assert!(!d.join("q.ply").exists());
}

/// A quad mesh (the cube of `cube_quads.obj`) for the commands that need triangles:
/// `repair --triangulate` splits each quad into two triangles on the same vertices,
/// `--repair --triangulate` does it on reading, and `--triangulate` alone is a usage
/// error, as `--merge-distance` alone is.
#[test]
fn polygons_are_split_into_triangles_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let quads = fixture("cube_quads.obj");
    let triangles = d.join("cube.ply");
    let text = stdout(&["repair", s(&quads), s(&triangles), "--triangulate"]);
    assert!(
        text.contains("repaired: split 6 polygons into triangles (input faces 0, 1, 2, 3, 4, 5)"),
        "{text}"
    );
    let mesh = beltrami_io::read_mesh(&triangles).unwrap();
    let original = beltrami_io::read_mesh(&quads).unwrap();
    assert_eq!(mesh.positions, original.positions);
    assert_eq!(mesh.faces.len(), 12);
    assert!(mesh.faces.is_triangles());
    // Each quad's two triangles use its four corners, wound as it is.
    for (f, quad) in original.faces.iter().enumerate() {
        let pair: Vec<&[u32]> = mesh.faces.iter().skip(2 * f).take(2).collect();
        let corners: std::collections::BTreeSet<u32> = pair.concat().into_iter().collect();
        assert_eq!(corners, quad.iter().copied().collect(), "face {f}");
        // Wound as the quad: each triangle's corners come in the quad's cyclic order.
        for t in pair {
            let at = |v: u32| quad.iter().position(|&q| q == v).unwrap();
            let (a, b, c) = (at(t[0]), at(t[1]), at(t[2]));
            let steps = (b + 4 - a) % 4 + (c + 4 - b) % 4 + (a + 4 - c) % 4;
            assert_eq!(steps, 4, "face {f}: triangle {t:?} of quad {quad:?}");
        }
    }
    let info = stdout(&["info", s(&triangles), "--json"]);
    let j: serde_json::Value = serde_json::from_str(&info).unwrap();
    assert_eq!(j["closed"], true, "{j}");
    let j: serde_json::Value = serde_json::from_str(&stdout(&[
        "repair",
        s(&quads),
        s(&d.join("j.ply")),
        "--triangulate",
        "--json",
    ]))
    .unwrap();
    assert_eq!(
        j["repairs"]["triangulated_faces"],
        serde_json::json!([0, 1, 2, 3, 4, 5])
    );
    // On reading, for a command that needs triangles.
    let out = d.join("fine.ply");
    let o = beltrami(&["subdivide", s(&quads), s(&out), "--repair", "--triangulate"]);
    assert!(o.status.success(), "{}", error_line(&o, d));
    assert_eq!(beltrami_io::read_mesh(&out).unwrap().faces.len(), 48);
    let o = beltrami(&["subdivide", s(&quads), s(&d.join("x.ply")), "--triangulate"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        error_line(&o, d),
        "error: --triangulate applies with --repair (or in 'beltrami repair') (see 'beltrami --help')"
    );
}
