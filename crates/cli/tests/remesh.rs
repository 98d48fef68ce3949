//! `beltrami remesh` as a user runs it: a generated sphere and every triangle fixture
//! remesh into the library's result with the summary's numbers, the sentence names the
//! counts, lengths and distance, and bad usage (exit 2) or a bad input (exit 1) gives
//! one error line and writes nothing.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{RemeshOptions, remesh};
use beltrami_io::read_mesh;
use common::{beltrami, error_line, f, json, s};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

#[test]
fn a_generated_sphere_remeshes_to_the_target_length() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = dir.path().join("sphere.ply");
    let o = beltrami(&["generate", "sphere", s(&sphere), "--level", "3"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("coarse.ply");
    let summary = json(&[
        "remesh",
        s(&sphere),
        s(&out),
        "--edge-length",
        "0.2",
        "--json",
    ]);
    for key in [
        "input",
        "output",
        "target_edge_length",
        "iterations",
        "splits",
        "collapses",
        "flips",
        "vertices_before",
        "faces_before",
        "vertices",
        "faces",
        "mean_edge_length_before",
        "edge_length_cv_before",
        "mean_edge_length",
        "edge_length_cv",
        "feature_edges",
        "boundary_edges",
        "corners",
        "hausdorff",
        "feature_angle_degrees",
        "projection",
        "smooth_projection",
        "seconds",
    ] {
        assert!(summary.get(key).is_some(), "missing {key}: {summary}");
    }
    assert_eq!(f(&summary["target_edge_length"]), 0.2);
    assert!((f(&summary["mean_edge_length"]) / 0.2 - 1.0).abs() < 0.15);
    assert!(f(&summary["edge_length_cv"]) < 0.25);
    // Lifted onto the smooth surface through the level-3 icosphere's triangles: off
    // them by up to their depth below the unit sphere (4.5e-3 at the centroids).
    let hausdorff = f(&summary["hausdorff"]);
    assert!(hausdorff > 1e-4 && hausdorff < 4.6e-3, "{hausdorff}");
    assert_eq!(summary["iterations"], 10);
    assert_eq!(summary["projection"], true);
    assert_eq!(summary["smooth_projection"], true);
    let written = read_mesh(&out).unwrap();
    let mesh = written.mesh().unwrap();
    assert_eq!(summary["vertices"], mesh.n_vertices());
    assert_eq!(summary["faces"], mesh.n_faces());
    assert!(mesh.is_closed());
    assert_eq!(mesh.euler_characteristic(), 2);

    // The sentence: counts before -> after, mean length and variation, distance.
    let o = beltrami(&["remesh", s(&sphere), s(&out), "--force"]);
    assert!(o.status.success());
    let line = String::from_utf8(o.stdout).unwrap();
    // The sentence, then the quality table: a header and six rows.
    assert_eq!(line.lines().count(), 8, "{line}");
    assert!(
        line.lines().nth(1).unwrap().starts_with("quality"),
        "{line}"
    );
    assert!(line.contains("642 vertices, 1280 faces ->"), "{line}");
    assert!(line.contains("mean edge length"), "{line}");
    assert!(line.contains("variation"), "{line}");
    assert!(
        line.contains("of the input's triangles (on the smooth surface through them)"),
        "{line}"
    );

    // --faceted: every vertex on the input's triangles.
    let faceted = dir.path().join("faceted.ply");
    let summary = json(&[
        "remesh",
        s(&sphere),
        s(&faceted),
        "--edge-length",
        "0.2",
        "--faceted",
        "--json",
    ]);
    assert!(f(&summary["hausdorff"]) < 1e-12, "{summary}");
    assert_eq!(summary["smooth_projection"], false);
    let o = beltrami(&["remesh", s(&sphere), s(&faceted), "--faceted", "--force"]);
    let line = String::from_utf8(o.stdout).unwrap();
    assert!(
        line.contains("of the input's triangles, the input's vertices within "),
        "{line}"
    );
    // It makes no sense without projection.
    let o = beltrami(&[
        "remesh",
        s(&sphere),
        s(&faceted),
        "--faceted",
        "--no-projection",
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn every_triangle_fixture_remeshes_into_the_library_result() {
    let dir = tempfile::tempdir().unwrap();
    let mut files: Vec<PathBuf> = fs::read_dir(fixtures())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension()
                .is_some_and(|e| ["ply", "stl", "obj", "off"].contains(&e.to_str().unwrap()))
        })
        .collect();
    files.sort();
    let mut remeshed = 0;
    for input in files {
        let data = read_mesh(&input).unwrap();
        let Ok(mesh) = data.mesh() else {
            continue; // a fixture that needs --repair; the bad-input test covers those
        };
        let out = dir.path().join("out.ply");
        let o = beltrami(&[
            "remesh",
            s(&input),
            s(&out),
            "--json",
            "--force",
            "--features",
            "45",
            "--iterations",
            "3",
        ]);
        if !mesh.is_triangle_mesh() {
            assert_eq!(o.status.code(), Some(1), "{input:?}");
            assert!(error_line(&o, dir.path()).contains("needs a triangle mesh"));
            assert!(!out.exists());
            continue;
        }
        assert!(
            o.status.success(),
            "{input:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        let options = RemeshOptions::default()
            .feature_angle(45f64.to_radians())
            .iterations(3);
        let (want, positions, report) = remesh(&mesh, &data.positions, &options).unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{input:?}");
        assert_eq!(got.faces, want.to_polygons(), "{input:?}");
        let written = got.mesh().unwrap();
        assert_eq!(written.euler_characteristic(), mesh.euler_characteristic());
        assert_eq!(summary["splits"], report.splits);
        assert_eq!(summary["collapses"], report.collapses);
        assert_eq!(summary["faces"], want.n_faces());
        assert_eq!(f(&summary["hausdorff"]), report.hausdorff);
        assert_eq!(
            summary["degenerate_faces_before"],
            report.degenerate_faces_before
        );
        assert_eq!(summary["degenerate_faces"], report.degenerate_faces);
        fs::remove_file(&out).unwrap();
        remeshed += 1;
    }
    assert!(remeshed >= 5, "{remeshed} fixtures remeshed");
}

#[test]
fn usage_errors_exit_2_with_one_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("out.ply");
    for args in [
        &["--edge-length", "0.1", "--edge-length-relative", "2"][..],
        &["--edge-length", "0"][..],
        &["--edge-length", "-1"][..],
        &["--edge-length", "nan"][..],
        &["--edge-length-relative", "0"][..],
        &["--edge-length-relative", "inf"][..],
        &["--features", "200"][..],
        &["--features", "-5"][..],
        &["--iterations", "many"][..],
        &["--min-edge", "0.1"][..],
        &["--adaptive", "--min-edge", "-0.1"][..],
        &["--adaptive", "--error", "nan"][..],
        &[
            "--adaptive",
            "--min-edge",
            "0.5",
            "--max-edge",
            "0.1",
            "--error",
            "0.01",
        ][..],
        &[
            "--adaptive",
            "--min-edge",
            "0.1",
            "--max-edge",
            "0.5",
            "--error",
            "0",
        ][..],
        &[
            "--adaptive",
            "--min-edge",
            "0.1",
            "--max-edge",
            "0.5",
            "--error",
            "0.01",
            "--edge-length",
            "0.2",
        ][..],
    ] {
        let mut all = vec!["remesh", s(&input), s(&out)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let line = error_line(&o, dir.path());
        assert!(!line.is_empty(), "{args:?}");
        assert!(!out.exists(), "{args:?}");
    }
    // One line for the errors found after parsing.
    let o = beltrami(&["remesh", s(&input), s(&out), "--edge-length", "0"]);
    assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
    // The input is not overwritten without --force.
    let o = beltrami(&["remesh", s(&input), s(&input)]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn bad_input_exits_1_with_one_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ply");
    for bad in fs::read_dir(fixtures().join("bad")).unwrap() {
        let bad = bad.unwrap().path();
        if bad.ends_with("isolated_vertices.obj") {
            continue; // the one valid file of the corpus
        }
        let o = beltrami(&["remesh", s(&bad), s(&out)]);
        assert_eq!(o.status.code(), Some(1), "{bad:?}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{bad:?}"
        );
        assert!(!out.exists(), "{bad:?}");
    }
    // A target so small for the surface that the result would be enormous.
    let input = fixtures().join("icosphere_2.ply");
    let o = beltrami(&["remesh", s(&input), s(&out), "--edge-length", "1e-7"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(error_line(&o, dir.path()).contains("triangles"));
    assert!(!out.exists());
}

#[test]
fn features_keep_the_cube_corners() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("cube_ascii.ply");
    let out = dir.path().join("cube.ply");
    let summary = json(&[
        "remesh",
        s(&input),
        s(&out),
        "--edge-length",
        "0.25",
        "--features",
        "45",
        "--json",
    ]);
    assert_eq!(summary["feature_edges"], 12);
    assert_eq!(summary["corners"], 8);
    let got = read_mesh(&out).unwrap();
    for i in 0..8u32 {
        let corner = glam::DVec3::new(f64::from(i & 1), f64::from((i >> 1) & 1), f64::from(i >> 2));
        assert!(got.positions.contains(&corner), "corner {corner}");
    }
}

#[test]
fn adaptive_sizing_matches_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("adaptive.ply");
    let summary = json(&[
        "remesh",
        s(&input),
        s(&out),
        "--adaptive",
        "--min-edge",
        "0.05",
        "--max-edge",
        "1",
        "--error",
        "0.002",
        "--json",
    ]);
    assert_eq!(summary["adaptive"], true);
    let data = read_mesh(&input).unwrap();
    let options = RemeshOptions::default().adaptive(0.05, 1.0, 0.002);
    let (want, positions, report) =
        remesh(&data.mesh().unwrap(), &data.positions, &options).unwrap();
    let got = read_mesh(&out).unwrap();
    assert_eq!(got.positions, positions);
    assert_eq!(got.faces, want.to_polygons());
    assert_eq!(f(&summary["target_edge_length"]), report.target_edge_length);
    // The chord length of the error on the unit sphere, about 0.11.
    let chord = (6.0f64 * 0.002 - 3.0 * 0.002 * 0.002).sqrt();
    assert!((f(&summary["mean_edge_length"]) / chord - 1.0).abs() < 0.2);
    assert_eq!(f(&summary["min_edge"]), 0.05);
    assert_eq!(f(&summary["max_edge"]), 1.0);
    assert_eq!(f(&summary["approx_error"]), 0.002);
}

#[test]
fn adaptive_sizing_works_with_its_defaults_and_says_what_it_derived() {
    let dir = tempfile::tempdir().unwrap();
    // On a sphere every vertex has the median curvature, so the defaults keep the
    // input's density.
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("adaptive.ply");
    let o = beltrami(&["remesh", s(&input), s(&out), "--adaptive"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains("(--min-edge, --max-edge, --error derived from the input)"),
        "{text}"
    );
    let summary = json(&[
        "remesh",
        s(&input),
        s(&out),
        "--adaptive",
        "--force",
        "--json",
    ]);
    let mean_before = f(&summary["mean_edge_length_before"]);
    assert!((f(&summary["min_edge"]) - mean_before / 4.0).abs() < 1e-15);
    assert!((f(&summary["max_edge"]) - 4.0 * mean_before).abs() < 1e-15);
    let ratio = f(&summary["vertices"]) / f(&summary["vertices_before"]);
    assert!((0.85..1.15).contains(&ratio), "{ratio}");
    assert!((f(&summary["mean_edge_length"]) / mean_before - 1.0).abs() < 0.1);

    // A value given is kept, and the derived ones respect it.
    let summary = json(&[
        "remesh",
        s(&input),
        s(&out),
        "--adaptive",
        "--max-edge",
        "0.05",
        "--force",
        "--json",
    ]);
    assert_eq!(f(&summary["min_edge"]), 0.05);
    assert_eq!(f(&summary["max_edge"]), 0.05);
    let o = beltrami(&[
        "remesh",
        s(&input),
        s(&out),
        "--adaptive",
        "--error",
        "0.01",
        "--force",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains("approximation error 0.01 (--min-edge, --max-edge derived from the input)"),
        "{text}"
    );
}

#[test]
fn the_summary_counts_the_features_and_says_when_every_edge_is_one() {
    let dir = tempfile::tempdir().unwrap();
    let cube = fixtures().join("cube_ascii.ply");
    let out = dir.path().join("cube.ply");
    let run = |input: &std::path::Path, angle: &str| {
        let o = beltrami(&[
            "remesh",
            s(input),
            s(&out),
            "--edge-length",
            "0.25",
            "--features",
            angle,
            "--force",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    // The cube's 12 edges are features, its 6 face diagonals are flat: no note.
    let text = run(&cube, "45");
    assert!(
        text.contains("features: 12 of 18 interior edges sharper than 45° kept as feature curves, 8 corners fixed"),
        "{text}"
    );
    assert!(!text.contains("note:"), "{text}");
    // On a sphere every edge is sharper than 0°: the note says why nothing moved.
    let sphere = fixtures().join("icosphere_2.ply");
    let text = run(&sphere, "0");
    let note = text
        .lines()
        .find(|l| l.starts_with("note: "))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        note.contains("every interior edge is sharper than --features 0°"),
        "{note}"
    );
    let input = read_mesh(&sphere).unwrap();
    assert_eq!(read_mesh(&out).unwrap().positions, input.positions);
    // Without --features there is no features line.
    let o = beltrami(&[
        "remesh",
        s(&sphere),
        s(&out),
        "--edge-length",
        "0.25",
        "--force",
    ]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("features:"));
}

/// A huge target length is refused as too long like 1e100 is, whether its square
/// overflows or not (it used to return a sliver tetrahedron from about 1.3e154 on), and
/// the message prints the length in six significant digits.
#[test]
fn a_huge_target_length_is_refused_as_too_long() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("out.ply");
    for args in [
        &["--edge-length", "1e100"][..],
        &["--edge-length", "1e155"][..],
        &["--edge-length", "1.7e308"][..],
        &["--edge-length-relative", "1e200"][..],
        &["--adaptive", "--min-edge", "1e155", "--max-edge", "1e155"][..],
        &["--adaptive", "--min-edge", "1e200"][..],
        &["--adaptive", "--error", "1e200", "--max-edge", "1e200"][..],
    ] {
        let mut all = vec!["remesh", s(&input), s(&out)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let line = error_line(&o, dir.path());
        assert!(line.contains("is too long for this surface"), "{line}");
        assert!(!line.contains("00000000"), "{line}");
        assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
        assert!(!out.exists(), "{args:?}");
    }
}

/// Isolated vertices are no part of the surface: the extent check measures the
/// triangles, so the fixture with two far-away isolated vertices remeshes.
#[test]
fn a_mesh_with_isolated_vertices_remeshes() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("bad/isolated_vertices.obj");
    let out = dir.path().join("out.obj");
    for args in [&[][..], &["--edge-length", "0.1"][..]] {
        let mut all = vec!["remesh", s(&input), s(&out), "--force"];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
}

/// A triangle whose corners lie on a line has edges but no area: the error says so.
#[test]
fn a_flat_triangle_is_refused_for_having_no_area() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("flat.obj");
    fs::write(&input, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    let out = dir.path().join("out.ply");
    let o = beltrami(&["remesh", s(&input), s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let line = error_line(&o, dir.path());
    assert!(line.contains("zero area"), "{line}");
    assert!(!out.exists());
}

/// A negative or infinite number given as a separate argument reaches the option's own
/// range check (exit 2, one line), not the parser's "unexpected argument" with a tip
/// that would make it a positional argument; values are echoed exactly, not rounded.
#[test]
fn negative_and_out_of_range_numbers_get_the_options_own_message() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("out.ply");
    for (args, message) in [
        (
            &["--edge-length", "-1"][..],
            "--edge-length must be a finite number > 0, got -1",
        ),
        (
            &["--edge-length", "-inf"][..],
            "--edge-length must be a finite number > 0, got -inf",
        ),
        (
            &["--edge-length-relative", "inf"][..],
            "--edge-length-relative must be a finite number > 0, got inf",
        ),
        (
            &["--adaptive", "--min-edge", "-0.5"][..],
            "--min-edge must be a finite number > 0, got -0.5",
        ),
        (
            &["--features", "180.0001"][..],
            "--features must be between 0 and 180 degrees, got 180.0001",
        ),
        (
            &["--iterations", "1000000"][..],
            "remeshing takes at most 1000 iterations (it settles within 10 to 20), got 1000000",
        ),
    ] {
        let mut all = vec!["remesh", s(&input), s(&out)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(message), "{stderr}");
        assert!(!out.exists());
    }
    // The positionals still parse around an option given a negative value.
    let o = beltrami(&["remesh", "--edge-length", "-1", s(&input), s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("finite number > 0"));
    // A tiny length prints in six significant digits, and no "inf" count.
    let o = beltrami(&["remesh", s(&input), s(&out), "--edge-length", "1e-300"]);
    assert_eq!(o.status.code(), Some(1));
    let line = error_line(&o, dir.path());
    assert!(line.contains("a target edge length of 1e-300"), "{line}");
    assert!(!line.contains("inf"), "{line}");
}

/// `--feature-edges FILE`: the middle line of a flat, jittered grid is kept as edges
/// covering its whole length (it is not without the file); a line that is not two
/// indices, or a pair that is no edge, is one clear error naming its line.
#[test]
fn feature_edges_from_a_file_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An 8 × 8 grid of unit cells, interior vertices pushed about in the plane (those
    // on the line y = 4 along it only).
    let n = 8usize;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (mut x, mut y) = (i as f64, j as f64);
            let k = j * (n + 1) + i;
            if i > 0 && i < n && j > 0 && j < n {
                x += 0.3 * ((k * 7 % 5) as f64 / 5.0 - 0.4);
                if j != 4 {
                    y += 0.3 * ((k * 3 % 7) as f64 / 7.0 - 0.4);
                }
            }
            obj.push_str(&format!("v {x} {y} 0\n"));
        }
    }
    let id = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            obj.push_str(&format!(
                "f {} {} {}\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1)
            ));
            obj.push_str(&format!(
                "f {} {} {}\n",
                id(i, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            ));
        }
    }
    let input = d.join("grid.obj");
    fs::write(&input, obj).unwrap();
    let mut edges = String::from("# the line y = 4, as 0-based vertex pairs\n");
    for i in 0..n {
        edges.push_str(&format!("{} {}\n", id(i, 4) - 1, id(i + 1, 4) - 1));
    }
    let file = d.join("line.txt");
    fs::write(&file, edges).unwrap();
    let covered = |path: &Path| -> f64 {
        let m = read_mesh(path).unwrap();
        let mut sum = 0.0;
        for face in m.faces.iter() {
            for k in 0..3 {
                let (a, b) = (
                    m.positions[face[k] as usize],
                    m.positions[face[(k + 1) % 3] as usize],
                );
                if a.y == 4.0 && b.y == 4.0 {
                    // Each interior edge is seen from both sides.
                    sum += 0.5 * a.distance(b);
                }
            }
        }
        sum
    };
    let out = d.join("out.ply");
    let j = json(&[
        "remesh",
        s(&input),
        s(&out),
        "--edge-length",
        "1.3",
        "--feature-edges",
        s(&file),
        "--json",
    ]);
    assert_eq!(j["given_feature_edges"], 8, "{j}");
    assert!((covered(&out) - 8.0).abs() < 1e-9, "{}", covered(&out));
    let text = String::from_utf8(
        beltrami(&[
            "remesh",
            s(&input),
            s(&out),
            "--edge-length",
            "1.3",
            "--feature-edges",
            s(&file),
            "--force",
        ])
        .stdout,
    )
    .unwrap();
    assert!(
        text.contains("features: 8 interior edges given in") && text.contains("corners fixed"),
        "{text}"
    );
    let free = d.join("free.ply");
    beltrami(&["remesh", s(&input), s(&free), "--edge-length", "1.3"]);
    assert!(covered(&free) < 7.0, "{}", covered(&free));
    // The file cannot be the OUTPUT; with --repair that renumbers the vertices the
    // pairs would name other edges: refused.
    let named = d.join("line.obj");
    fs::copy(&file, &named).unwrap();
    let o = beltrami(&["remesh", s(&input), s(&named), "--feature-edges", s(&named)]);
    assert!(!o.status.success());
    assert!(
        error_line(&o, d).contains("line.obj"),
        "{}",
        error_line(&o, d)
    );
    assert_eq!(fs::read(&named).unwrap(), fs::read(&file).unwrap());
    // Nor can the report, or OUTPUT, replace it with --force (which lets only the
    // result mesh replace INPUT): exit 2, the file untouched.
    for args in [
        ["--report", s(&named), "--force"],
        ["--force", "--iterations", "1"],
    ] {
        let out = if args[0] == "--report" {
            d.join("elsewhere.ply")
        } else {
            named.clone()
        };
        let mut line = vec!["remesh", s(&input), s(&out), "--feature-edges", s(&named)];
        line.extend(args);
        let o = beltrami(&line);
        assert_eq!(o.status.code(), Some(2), "{}", error_line(&o, d));
        assert!(
            error_line(&o, d).contains("is the input file"),
            "{}",
            error_line(&o, d)
        );
        assert_eq!(fs::read(&named).unwrap(), fs::read(&file).unwrap());
        assert!(!d.join("elsewhere.ply").exists());
    }
    let stray = d.join("stray.obj");
    fs::write(
        &stray,
        format!("{}v 9 9 9\n", fs::read_to_string(&input).unwrap()),
    )
    .unwrap();
    let o = beltrami(&[
        "remesh",
        s(&stray),
        s(&d.join("r.ply")),
        "--feature-edges",
        s(&file),
        "--repair",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        error_line(&o, d).contains("--repair renumbered the vertices"),
        "{}",
        error_line(&o, d)
    );
    assert!(!d.join("r.ply").exists());
    // Bad files: one line, exit 1, nothing written.
    for (content, expected) in [
        (
            "0 1\n0 x\n",
            "line 2: expected two vertex indices (0-based integers), got \"0 x\"",
        ),
        (
            "# c\n\n0 20\n",
            "line 3: 0 20 is not an edge of grid.obj: no edge joins them",
        ),
        (
            "0 1 2\n",
            "line 1: expected two vertex indices (0-based integers), got \"0 1 2\"",
        ),
        (
            "0 99\n",
            "line 1: 0 99 is not an edge of grid.obj: vertex 99 is out of range (81 vertices)",
        ),
    ] {
        fs::write(&file, content).unwrap();
        let bad = d.join("bad.ply");
        let o = beltrami(&["remesh", s(&input), s(&bad), "--feature-edges", s(&file)]);
        assert_eq!(o.status.code(), Some(1), "{content}");
        assert_eq!(
            error_line(&o, d),
            format!("error: line.txt: {expected}"),
            "{content}"
        );
        assert!(!bad.exists());
    }
}

/// Without `--features` the remesher rounds sharp edges off. When the input's sharp
/// edges run on in chains (a machined part's, not the scattered ones noise makes), the
/// command says so and names the option; a run that fails for it (the 8-vertex cube at
/// its own mean edge length shrinks) names it in its error line.
#[test]
fn a_machined_parts_edges_get_a_note_and_noise_gets_none() {
    let dir = tempfile::tempdir().unwrap();
    let cube = fixtures().join("cube_ascii.ply");
    let out = dir.path().join("out.ply");
    let note = "of the input's edges are sharper than 60° and run on in chains";

    let o = beltrami(&["remesh", s(&cube), s(&out)]);
    assert_eq!(o.status.code(), Some(1));
    let line = error_line(&o, dir.path());
    assert!(line.contains("would shrink to"), "{line}");
    assert!(
        line.contains("keep the input's 12 edges sharper than 60°")
            && line.contains("--features 45"),
        "{line}"
    );
    assert!(!out.exists());
    // With --features the error (if any) gives no such advice, and the run keeps them.
    let o = beltrami(&["remesh", s(&cube), s(&out), "--features", "45"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!String::from_utf8_lossy(&o.stdout).contains(note));

    let o = beltrami(&[
        "remesh",
        s(&cube),
        s(&out),
        "--edge-length",
        "0.25",
        "--force",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!("note: 12 {note}")) && stdout.contains("--features 45 keeps them"),
        "{stdout}"
    );
    let summary = json(&[
        "remesh",
        s(&cube),
        s(&out),
        "--edge-length",
        "0.25",
        "--force",
        "--json",
    ]);
    let notes = summary["notes"].as_array().expect("notes");
    assert!(
        notes
            .iter()
            .any(|n| n.as_str().is_some_and(|n| n.contains(note))),
        "{summary}"
    );

    // A machined part with light noise still has its chains apart from the rest;
    // noisy smooth surfaces have none, from light noise to the heaviest of the
    // denoising benchmarks (0.7 mean edge lengths), where sharp edges chain but no
    // longer stand apart from the bent ones; under noise of 0.2 the block's own edges
    // no longer stand apart either.
    let generated = |surface: &str, noise: &str, level: Option<&str>| {
        let path = dir.path().join(format!("{surface}-{noise}.ply"));
        let mut args = vec!["generate", surface, s(&path), "--noise", noise];
        if let Some(level) = level {
            args.extend(["--level", level]);
        }
        let o = beltrami(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        path
    };
    for (input, expected) in [
        (generated("block", "0.05", None), true),
        (generated("block", "0.2", None), false),
        (generated("sphere", "0.2", Some("4")), false),
        (generated("sphere", "0.7", Some("4")), false),
        (generated("flens", "0.5", None), false),
        (fixtures().join("noisy_icosphere_4.ply"), false),
        (fixtures().join("noisy_torus_36x12.ply"), false),
        (fixtures().join("icosphere_2.ply"), false),
    ] {
        let o = beltrami(&["remesh", s(&input), s(&out), "--force"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            stdout.contains(note),
            expected,
            "{}: {stdout}",
            input.display()
        );
    }
}
