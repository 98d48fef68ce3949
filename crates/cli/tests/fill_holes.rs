//! `beltrami fill-holes` as a user runs it: the holes of the fixture patch are filled
//! and its outer rim kept, as the library does it; `--all`, `--max-loop-edges`,
//! `--no-refine` and `--no-fair` change what the summary reports; a broken input gives
//! one error line and no output, and bad usage exits with code 2 before anything is
//! written.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{FillOptions, fill_holes};
use beltrami_io::read_mesh;
use common::{beltrami, error_line, json, s};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

fn holes() -> PathBuf {
    fixtures().join("holes_30x20.ply")
}

#[test]
fn the_holes_are_filled_and_the_rim_kept_as_the_library_does() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ply");
    let summary = json(&["fill-holes", s(&holes()), s(&out), "--json"]);
    for key in [
        "input",
        "output",
        "vertices",
        "faces",
        "loops",
        "filled",
        "skipped",
        "faces_added",
        "vertices_added",
        "boundary_loops_left",
        "max_loop_edges",
        "seconds",
    ] {
        assert!(summary.get(key).is_some(), "{key} missing: {summary}");
    }
    assert_eq!(summary["loops"], 6);
    assert_eq!(summary["filled"].as_array().unwrap().len(), 5);
    assert_eq!(summary["skipped"][0]["reason"], "outer_boundary");
    assert_eq!(summary["boundary_loops_left"], 1);
    for hole in summary["filled"].as_array().unwrap() {
        for key in [
            "boundary_edges",
            "perimeter",
            "faces_added",
            "vertices_added",
            "area",
            "faired_order",
        ] {
            assert!(hole.get(key).is_some(), "{key} missing: {hole}");
        }
    }

    let input = read_mesh(holes()).unwrap();
    let (want, positions, report) = fill_holes(
        &input.mesh().unwrap(),
        &input.positions,
        &FillOptions::default(),
    )
    .unwrap();
    let got = read_mesh(&out).unwrap();
    assert_eq!(got.positions, positions);
    assert_eq!(got.faces, want.to_polygons());
    assert_eq!(
        &got.positions[..input.positions.len()],
        &input.positions[..]
    );
    assert_eq!(summary["faces_added"], report.faces_added);
    assert_eq!(summary["vertices_added"], report.vertices_added);
    assert!(report.vertices_added > 0);

    // The sentence names what was filled and what was left open.
    let o = beltrami(&["fill-holes", s(&holes()), s(&out), "--force"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    // The sentence, then the quality table: a header and six rows.
    assert_eq!(text.lines().count(), 8, "{text}");
    assert!(
        text.lines().nth(1).unwrap().starts_with("quality"),
        "{text}"
    );
    assert!(text.starts_with("filled 5 holes of "), "{text}");
    assert!(
        text.contains("the outer boundary (largest perimeter; --all fills it)"),
        "{text}"
    );
    // The patch's rim spans the patch: not taken for a hole of a closed part.
    assert!(!text.contains("spans only"), "{text}");
}

#[test]
fn a_closed_part_with_holes_is_told_that_all_fills_the_largest() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("holed.ply");
    let out = dir.path().join("out.ply");
    let o = beltrami(&[
        "generate",
        "sphere",
        s(&input),
        "--level",
        "4",
        "--holes",
        "3",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = beltrami(&["fill-holes", s(&input), s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let first = text.lines().next().unwrap();
    assert!(first.starts_with("filled 2 holes of "), "{first}");
    // The share is the loop's vector area over the sphere's: about π r² / 4π for a
    // hole of radius r = 3 mean edge lengths, well under the 5 % threshold.
    let share: f64 = first
        .split("spans only ")
        .nth(1)
        .and_then(|t| t.split('%').next())
        .unwrap_or_else(|| panic!("{first}"))
        .parse()
        .unwrap();
    assert!(share > 0.0 && share < 5.0, "{first}");
    assert!(first.contains("(--all fills it)"), "{first}");
    // With --all every hole is filled and the sentence says nothing was left open.
    let o = beltrami(&["fill-holes", s(&input), s(&out), "--all", "--force"]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with("filled 3 holes of "), "{text}");
    assert!(!text.contains("left "), "{text}");
}

/// Two flat grids side by side (two components, no hole): each keeps its rim, and the
/// sentence says both were taken for outer boundaries.
#[test]
fn two_open_patches_keep_both_rims() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("two.off");
    let out = dir.path().join("out.ply");
    let n = 8;
    let mut text = String::new();
    let mut faces = Vec::new();
    let per = (n + 1) * (n + 1);
    for patch in 0..2 {
        for j in 0..n {
            for i in 0..n {
                let a = patch * per + j * (n + 1) + i;
                faces.push([a, a + 1, a + n + 2]);
                faces.push([a, a + n + 2, a + n + 1]);
            }
        }
    }
    text.push_str(&format!("OFF\n{} {} 0\n", 2 * per, faces.len()));
    for patch in 0..2 {
        for j in 0..=n {
            for i in 0..=n {
                let x = i as f64 / n as f64 + 2.0 * patch as f64;
                text.push_str(&format!("{x} {} 0\n", j as f64 / n as f64));
            }
        }
    }
    for [a, b, c] in faces {
        text.push_str(&format!("3 {a} {b} {c}\n"));
    }
    fs::write(&input, text).unwrap();
    let o = beltrami(&["fill-holes", s(&input), s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let first = String::from_utf8(o.stdout).unwrap();
    let first = first.lines().next().unwrap().to_string();
    assert!(first.starts_with("filled 0 holes of "), "{first}");
    assert!(
        first.contains(
            "the outer boundaries of 2 components (each one's largest perimeter; --all fills them)"
        ),
        "{first}"
    );
    let summary = json(&["info", s(&out), "--json"]);
    assert_eq!(summary["boundary_loops"], 2);
    assert_eq!(summary["faces"], 2 * 2 * n * n);
}

#[test]
fn options_change_what_is_filled() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ply");
    let input = holes();
    let run = |extra: &[&str]| -> Value {
        let mut args = vec!["fill-holes", s(&input), s(&out), "--json", "--force"];
        args.extend_from_slice(extra);
        json(&args)
    };
    // --all closes the outer rim too.
    let all = run(&["--all"]);
    assert_eq!(all["filled"].as_array().unwrap().len(), 6);
    assert_eq!(all["boundary_loops_left"], 0);
    // Only the missing triangle has at most 3 edges.
    let small = run(&["--max-loop-edges", "3"]);
    assert_eq!(small["filled"].as_array().unwrap().len(), 1);
    assert_eq!(small["faces_added"], 1);
    let reasons: Vec<&str> = small["skipped"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["reason"].as_str().unwrap())
        .collect();
    assert_eq!(
        reasons.iter().filter(|r| **r == "too_large").count(),
        4,
        "{reasons:?}"
    );
    let o = beltrami(&[
        "fill-holes",
        s(&holes()),
        s(&out),
        "--force",
        "--max-loop-edges",
        "3",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("with more than 3 edges"), "{text}");
    // --no-refine: the bare triangulations, no vertex added.
    let bare = run(&["--no-refine"]);
    assert_eq!(bare["vertices_added"], 0);
    // --no-fair: the same connectivity as with fairing, nothing faired.
    let flat = run(&["--no-fair"]);
    let faired = run(&[]);
    assert_eq!(flat["faces_added"], faired["faces_added"]);
    assert!(
        flat["filled"]
            .as_array()
            .unwrap()
            .iter()
            .all(|h| h["faired_order"].is_null())
    );
    assert!(
        faired["filled"]
            .as_array()
            .unwrap()
            .iter()
            .any(|h| h["faired_order"] == 2)
    );
}

#[test]
fn bad_input_and_usage_leave_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ply");
    for bad in fs::read_dir(fixtures().join("bad")).unwrap() {
        let bad = bad.unwrap().path();
        if bad.ends_with("isolated_vertices.obj") {
            continue; // the one valid file of the corpus
        }
        let o = beltrami(&["fill-holes", s(&bad), s(&out)]);
        assert_eq!(o.status.code(), Some(1), "{bad:?}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{bad:?}"
        );
        assert!(!out.exists(), "{bad:?}");
    }
    // A quad mesh: one line naming the problem.
    let o = beltrami(&["fill-holes", s(&fixtures().join("cube_quads.obj")), s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(error_line(&o, dir.path()).contains("needs a triangle mesh"));
    assert!(!out.exists());
    let input = holes();
    for args in [
        &["--max-loop-edges", "2"][..],
        &["--max-loop-edges", "-1"][..],
        &["--max-loop-edges", "many"][..],
        &["--fair-order", "2"][..],
    ] {
        let mut all = vec!["fill-holes", s(&input), s(&out)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!out.exists());
    }
    let o = beltrami(&["fill-holes", s(&holes()), s(&out), "--max-loop-edges", "2"]);
    assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
    // The input is not overwritten without --force.
    let o = beltrami(&["fill-holes", s(&holes()), s(&holes())]);
    assert_eq!(o.status.code(), Some(2));
}

/// `fill-holes --all` on a lone triangle leaves its rim open instead of writing a
/// duplicate face that `repair` would then drop as a defect.
#[test]
fn all_on_a_lone_triangle_adds_no_duplicate_face() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tri.obj");
    fs::write(&input, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = dir.path().join("out.obj");
    let summary = json(&["fill-holes", s(&input), s(&out), "--all", "--json"]);
    assert_eq!(summary["faces_added"], 0, "{summary}");
    assert_eq!(read_mesh(&out).unwrap().faces.len(), 1);
    let repaired = dir.path().join("rep.obj");
    let o = beltrami(&["repair", s(&out), s(&repaired)]);
    assert!(o.status.success());
    assert!(
        !String::from_utf8_lossy(&o.stdout).contains("duplicate"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}
