//! `beltrami smooth` writes the same bytes on every run and for every thread count:
//! the parallel chunks are fixed-size, so results do not depend on scheduling.

mod common;

use std::path::Path;
use std::process::Command;

use beltrami_halfedge::primitives;
use common::{s, write};

/// A rippled icosphere of level 5: 10242 vertices, more than one parallel chunk
/// (8192 rows), so two threads really split the work.
fn large_sphere(dir: &Path) -> std::path::PathBuf {
    let p = primitives::icosphere(5);
    assert!(p.positions.len() > 8192);
    let positions = p
        .positions
        .iter()
        .map(|&x| x * (1.0 + 0.01 * (7.0 * x.x).sin() * (5.0 * x.y).cos()))
        .collect();
    write(dir, "sphere.ply", positions, p.faces)
}

/// Runs `beltrami smooth` with `RAYON_NUM_THREADS=threads` and returns the output
/// file's bytes.
fn smooth_bytes(input: &Path, output: &Path, threads: usize, extra: &[&str]) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_beltrami"))
        .args(["smooth", s(input), s(output), "--iterations", "5"])
        .args(extra)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{extra:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(output).unwrap()
}

#[test]
fn smooth_output_is_identical_across_runs_and_thread_counts() {
    let dir = tempfile::tempdir().unwrap();
    let input = large_sphere(dir.path());
    let original = std::fs::read(&input).unwrap();
    let configurations: [&[&str]; 6] = [
        &["--weights", "uniform"],
        &["--weights", "distance"],
        &["--weights", "cotangent"],
        &["--weights", "cotangent", "--update", "once"],
        &[
            "--weights",
            "cotangent",
            "--normalize",
            "area",
            "--lambda",
            "1e-5",
        ],
        &["--weights", "distance", "--boundary", "free", "--ascii"],
    ];
    for extra in configurations {
        let output = dir.path().join("out.ply");
        let first = smooth_bytes(&input, &output, 1, extra);
        let again = smooth_bytes(&input, &output, 1, extra);
        let two = smooth_bytes(&input, &output, 2, extra);
        assert_ne!(first, original, "{extra:?}: smoothing moved the vertices");
        assert!(first == again, "{extra:?}: two runs on 1 thread differ");
        assert!(first == two, "{extra:?}: 1 and 2 threads differ");
    }
}
