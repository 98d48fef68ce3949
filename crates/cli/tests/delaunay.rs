//! `beltrami delaunay` as a user runs it: every triangle fixture flips into the
//! library's result with no negative cotangent weight left (or those the dihedral bound
//! keeps), a broken or non-triangle input gives one error line and no output, and bad
//! usage exits with code 2 before anything is written.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{DelaunayOptions, delaunay_flip};
use beltrami_io::read_mesh;
use common::{beltrami, error_line, s};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

#[test]
fn every_triangle_fixture_flips_into_the_library_result() {
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
    let mut flipped = 0;
    for input in files {
        let data = read_mesh(&input).unwrap();
        let mesh = data.mesh().unwrap();
        let out = dir.path().join("out.ply");
        let o = beltrami(&["delaunay", s(&input), s(&out), "--json", "--force"]);
        if !mesh.is_triangle_mesh() {
            assert_eq!(o.status.code(), Some(1), "{input:?}");
            assert!(error_line(&o, dir.path()).contains("needs a triangle mesh"));
            continue;
        }
        assert!(
            o.status.success(),
            "{input:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        let (want, positions, report) =
            delaunay_flip(&mesh, &data.positions, DelaunayOptions::default()).unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{input:?}");
        assert_eq!(got.faces, want.to_polygons(), "{input:?}");
        assert_eq!(summary["flips"], report.flips);
        assert_eq!(summary["negative_after"], 0, "{input:?}");
        assert_eq!(summary["negative_before"], report.negative_before);
        flipped += usize::from(report.flips > 0);
    }
    assert!(flipped >= 2, "some fixtures have non-Delaunay edges");
}

#[test]
fn the_dihedral_bound_keeps_edges_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("flens_68x33.ply");
    let out = dir.path().join("out.ply");
    let o = beltrami(&["delaunay", s(&input), s(&out), "--max-dihedral", "2"]);
    assert!(o.status.success());
    let line = String::from_utf8(o.stdout).unwrap();
    assert!(line.contains("by --max-dihedral"), "{line}");
    let free = beltrami(&["delaunay", s(&input), s(&out), "--json", "--force"]);
    let bound = beltrami(&[
        "delaunay",
        s(&input),
        s(&out),
        "--json",
        "--force",
        "--max-dihedral",
        "2",
    ]);
    let (free, bound): (Value, Value) = (
        serde_json::from_slice(&free.stdout).unwrap(),
        serde_json::from_slice(&bound.stdout).unwrap(),
    );
    let deviation = |v: &Value| v["max_deviation"].as_f64().unwrap();
    assert!(deviation(&bound) < deviation(&free));
    assert!(bound["kept_by_dihedral"].as_u64().unwrap() > 0);
    // One flip allowed: the rest is left by the limit, not called unflippable.
    let limited = beltrami(&[
        "delaunay",
        s(&input),
        s(&out),
        "--force",
        "--max-flips",
        "1",
    ]);
    let line = String::from_utf8(limited.stdout).unwrap();
    assert!(
        line.contains("left at the flip limit (--max-flips)"),
        "{line}"
    );
    assert!(!line.contains("not flippable"), "{line}");
    let limited: Value = serde_json::from_slice(
        &beltrami(&[
            "delaunay",
            s(&input),
            s(&out),
            "--json",
            "--force",
            "--max-flips",
            "1",
        ])
        .stdout,
    )
    .unwrap();
    assert_eq!(limited["hit_flip_limit"], true);
    assert_eq!(
        limited["kept_by_flip_limit"].as_u64().unwrap()
            + limited["kept_by_topology"].as_u64().unwrap(),
        limited["negative_after"].as_u64().unwrap()
    );
    assert!(limited["kept_by_flip_limit"].as_u64().unwrap() > 0);
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
        let o = beltrami(&["delaunay", s(&bad), s(&out)]);
        assert_eq!(o.status.code(), Some(1), "{bad:?}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{bad:?}"
        );
        assert!(!out.exists(), "{bad:?}");
    }
    let input = fixtures().join("grid_4x3.ply");
    for args in [
        &["--max-dihedral", "200"][..],
        &["--max-dihedral", "-1"][..],
        &["--max-flips", "many"][..],
    ] {
        let mut all = vec!["delaunay", s(&input), s(&out)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!out.exists());
    }
    // The input is not overwritten without --force.
    let o = beltrami(&["delaunay", s(&input), s(&input)]);
    assert_eq!(o.status.code(), Some(2));
}
