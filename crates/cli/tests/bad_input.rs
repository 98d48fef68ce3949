//! The bad-input corpus `fixtures/bad/` through the whole command-line tool: every
//! broken file gives exit code 1 and exactly one `error:` line (pinned here), and a
//! failed `smooth` neither creates its output nor touches an existing one. The one
//! valid file of the corpus (isolated vertices) reads and smooths, and its isolated
//! vertices do not move.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use insta::assert_snapshot;

#[allow(dead_code)]
#[path = "../examples/make_bad_fixtures.rs"]
mod make_bad_fixtures;

/// The broken files, in the order of `fixtures/README.md`.
const BAD: &[&str] = &[
    "truncated_ascii.ply",
    "truncated_binary.ply",
    "count_exceeds_ascii.ply",
    "count_exceeds_binary.ply",
    "four_billion_vertices.ply",
    "x_is_list.ply",
    "unknown_property_type.ply",
    "face_indices_float.ply",
    "garbage.ply",
    "garbage.stl",
    "garbage.obj",
    "empty.ply",
    "empty.stl",
    "empty.obj",
    "nan_ascii.ply",
    "inf_ascii.ply",
    "nan_binary.ply",
    "nan.obj",
    "inf.obj",
    "index_out_of_range.ply",
    "index_negative.ply",
    "index_out_of_range.obj",
    "index_zero.obj",
    "index_negative.obj",
    "repeated_vertex.obj",
    "nonmanifold_edge.obj",
    "nonmanifold_vertex.obj",
    "inconsistent_orientation.obj",
    "stl_count_mismatch.stl",
    "stl_broken_facet.stl",
];

fn bad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/bad")
}

fn s(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

fn beltrami(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Checks a failed run (exit code 1, nothing on stdout, one `error:` line) and
/// returns its line with the fixture folder and the temporary folder replaced by
/// stable placeholders.
fn error_line(out: &Output, what: &str, tmp: &Path) -> String {
    let stderr = String::from_utf8(out.stderr.clone()).expect("UTF-8 stderr");
    assert_eq!(out.status.code(), Some(1), "{what}: exit code, {stderr:?}");
    assert_eq!(
        stderr.lines().count(),
        1,
        "{what}: exactly one line: {stderr:?}"
    );
    assert!(stderr.starts_with("error: "), "{what}: {stderr:?}");
    assert!(out.stdout.is_empty(), "{what}: nothing on stdout");
    stderr
        .trim_end()
        .replace(&format!("{}/", s(&bad_dir())), "<bad>/")
        .replace(&format!("{}/", s(tmp)), "<tmp>/")
}

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("read the temporary folder")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

#[test]
fn committed_corpus_matches_the_generator() {
    let files = make_bad_fixtures::files();
    for (name, bytes) in &files {
        let committed = std::fs::read(bad_dir().join(name))
            .unwrap_or_else(|e| panic!("{name}: {e} (run the make_bad_fixtures example)"));
        assert!(
            &committed == bytes,
            "{name} is stale: run `cargo run -p beltrami-cli --example make_bad_fixtures`"
        );
    }
    let mut names: Vec<&str> = files.iter().map(|(n, _)| *n).collect();
    names.sort_unstable();
    let mut on_disk = entries(&bad_dir());
    on_disk.retain(|n| n != "README.md");
    assert_eq!(
        on_disk, names,
        "fixtures/bad holds exactly the generated files"
    );
    let mut listed: Vec<&str> = BAD.to_vec();
    listed.push("isolated_vertices.obj");
    listed.sort_unstable();
    assert_eq!(listed, names, "every generated file is tested");
}

#[test]
fn every_bad_file_gives_one_error_line_and_exit_code_1() {
    for name in BAD {
        let input = bad_dir().join(name);
        let tmp = tempfile::tempdir().expect("a temporary folder");

        let info = beltrami(&["info", s(&input)]);
        let info_line = error_line(&info, &format!("info {name}"), tmp.path());
        assert_snapshot!(format!("info__{name}"), info_line);

        // No output file is created...
        let output = tmp.path().join("out.ply");
        let smooth = beltrami(&["smooth", s(&input), s(&output)]);
        let smooth_line = error_line(&smooth, &format!("smooth {name}"), tmp.path());
        assert_eq!(
            smooth_line, info_line,
            "{name}: smooth reports the same as info"
        );
        assert!(entries(tmp.path()).is_empty(), "{name}: nothing written");

        // ...and an existing one is left byte for byte.
        let precious = b"precious bytes\n\x00\xff";
        std::fs::write(&output, precious).expect("write the existing output");
        let smooth = beltrami(&["smooth", s(&input), s(&output)]);
        assert_eq!(
            error_line(&smooth, &format!("smooth {name} over a file"), tmp.path()),
            info_line
        );
        assert_eq!(
            std::fs::read(&output).expect("the output is still there"),
            precious,
            "{name}: the existing output is untouched"
        );
        assert_eq!(entries(tmp.path()), ["out.ply"], "{name}: no leftovers");
    }
}

#[test]
fn four_billion_vertex_header_fails_fast() {
    let input = bad_dir().join("four_billion_vertices.ply");
    for command in ["info", "smooth"] {
        let tmp = tempfile::tempdir().expect("a temporary folder");
        let output = tmp.path().join("out.ply");
        let start = Instant::now();
        let out = match command {
            "info" => beltrami(&["info", s(&input)]),
            _ => beltrami(&["smooth", s(&input), s(&output)]),
        };
        // A generous bound: reading the header alone must not allocate or loop over
        // billions of elements.
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "{command} took {:?}",
            start.elapsed()
        );
        let line = error_line(&out, command, tmp.path());
        assert!(line.contains("4000000000 vertices"), "{line}");
        assert!(!output.exists());
    }
}

#[test]
fn isolated_vertices_are_counted_and_never_move() {
    let input = bad_dir().join("isolated_vertices.obj");
    let info = beltrami(&["info", s(&input), "--json"]);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&info.stdout).expect("one JSON object");
    assert_eq!(j["vertices"], 7);
    assert_eq!(j["faces"], 6);
    assert_eq!(j["isolated_vertices"], 2);

    let before = beltrami_io::read_mesh(&input).expect("the input reads");
    let isolated = [4, 6]; // 0-based: the OBJ's vertices 5 and 7
    for boundary in ["fixed", "free", "curve"] {
        for scheme in ["uniform", "distance", "cotangent"] {
            let tmp = tempfile::tempdir().expect("a temporary folder");
            let output = tmp.path().join("out.ply");
            let out = beltrami(&[
                "smooth",
                s(&input),
                s(&output),
                "--weights",
                scheme,
                "--boundary",
                boundary,
            ]);
            assert!(
                out.status.success(),
                "{scheme}/{boundary}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let after = beltrami_io::read_mesh(&output).expect("the output reads");
            assert_eq!(after.positions.len(), 7, "{scheme}/{boundary}");
            for v in isolated {
                assert_eq!(
                    after.positions[v].to_array().map(f64::to_bits),
                    before.positions[v].to_array().map(f64::to_bits),
                    "{scheme}/{boundary}: isolated vertex {v} moved"
                );
            }
            // The surface itself did move, so the run really smoothed something.
            assert_ne!(
                after.positions[3], before.positions[3],
                "{scheme}/{boundary}"
            );
            assert!(after.positions.iter().all(|p| p.is_finite()));
        }
    }
}
