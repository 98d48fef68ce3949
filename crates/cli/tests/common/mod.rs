//! Helpers shared by the CLI integration tests: run the binary, write a mesh, read its
//! JSON output or its one error line.

#![allow(dead_code)] // each test file uses a different subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use beltrami_halfedge::{DVec3, PolygonList};
use beltrami_io::{MeshData, WriteOptions, write_mesh};
use serde_json::Value;

pub(crate) fn beltrami(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args(args)
        .output()
        .expect("the binary runs")
}

pub(crate) fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

pub(crate) fn write(dir: &Path, name: &str, positions: Vec<DVec3>, faces: PolygonList) -> PathBuf {
    let path = dir.join(name);
    write_mesh(
        &path,
        &MeshData { positions, faces },
        &WriteOptions::default(),
    )
    .unwrap();
    path
}

pub(crate) fn json(args: &[&str]) -> Value {
    let out = beltrami(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

pub(crate) fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The error message of a failed run, with `dir/` removed: one line, or for a usage
/// error found by the argument parser its whole message (the problem, the usage line,
/// tips), which ends with the pointer to `--help` and exits with code 2.
pub(crate) fn error_line(out: &Output, dir: &Path) -> String {
    let stderr = String::from_utf8(out.stderr.clone()).unwrap();
    if stderr.lines().count() > 1 {
        assert!(
            stderr
                .trim_end()
                .ends_with("For more information, try '--help'."),
            "one line, or the parser's usage message: {stderr:?}"
        );
        assert_eq!(out.status.code(), Some(2), "{stderr:?}");
    }
    assert!(stderr.starts_with("error: "), "{stderr:?}");
    assert!(out.stdout.is_empty(), "nothing on stdout");
    stderr
        .trim_end()
        .replace(&format!("{}/", dir.display()), "")
}

/// An icosphere of `level` squashed so that smoothing moves every vertex, written to
/// `dir/name` (the format by extension).
pub(crate) fn squashed_sphere(dir: &Path, name: &str, level: u32) -> PathBuf {
    let p = beltrami_halfedge::primitives::icosphere(level);
    let positions = p
        .positions
        .iter()
        .map(|x| *x * DVec3::new(1.0, 0.7, 1.3))
        .collect();
    write(dir, name, positions, p.faces)
}
