//! `--cotangent-kernel`: the one-ring kernel writes the same bytes as the per-triangle
//! one, and `auto` takes it when only it fits the memory limit.

mod common;

use std::fs;

use common::{beltrami, s};

/// The "about X MiB" estimate of a refused run's error line, in MiB.
fn estimate_mib(stderr: &[u8]) -> f64 {
    let text = String::from_utf8_lossy(stderr);
    let after = text
        .split("needs about ")
        .nth(1)
        .unwrap_or_else(|| panic!("no estimate in {text}"));
    let number = after.split(' ').next().unwrap();
    assert!(after[number.len()..].starts_with(" MiB"), "{text}");
    number.parse().unwrap()
}

#[test]
fn both_kernels_write_the_same_bytes_and_auto_falls_back_to_the_ring() {
    let dir = tempfile::tempdir().unwrap();
    // 10 242 vertices: the per-triangle table is about 1.9 MiB of the estimate.
    let input = common::squashed_sphere(dir.path(), "scan.ply", 5);
    let run = |out: &str, extra: &[&str]| {
        let output = dir.path().join(out);
        let mut args = vec!["smooth", s(&input), s(&output), "--iterations", "3"];
        args.extend_from_slice(extra);
        (beltrami(&args), output)
    };

    let (default, default_out) = run("default.ply", &[]);
    assert!(default.status.success() && default.stderr.is_empty());
    for kernel in ["per-triangle", "ring"] {
        let (out, path) = run(&format!("{kernel}.ply"), &["--cotangent-kernel", kernel]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(
            fs::read(&path).unwrap(),
            fs::read(&default_out).unwrap(),
            "{kernel}"
        );
    }

    // The two estimates, from the refusals of a limit nothing fits.
    let refused = |kernel: &str| {
        let (out, path) = run(
            "refused.ply",
            &["--cotangent-kernel", kernel, "--max-memory", "1M"],
        );
        assert_eq!(out.status.code(), Some(1));
        assert!(!path.exists());
        estimate_mib(&out.stderr)
    };
    let (table, ring) = (refused("per-triangle"), refused("ring"));
    assert!(
        ring < table - 1.0,
        "ring {ring} MiB, per-triangle {table} MiB"
    );
    // `auto` reports the default kernel's figure when neither fits.
    assert_eq!(refused("auto"), table);

    // A limit between the two: the per-triangle kernel is refused, auto takes the ring
    // (and says so), with the same bytes.
    let limit = format!("{:.2}M", (table + ring) / 2.0);
    let (out, path) = run(
        "tight.ply",
        &["--cotangent-kernel", "per-triangle", "--max-memory", &limit],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(!path.exists());
    let (out, path) = run("auto.ply", &["--max-memory", &limit]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let note = String::from_utf8(out.stderr).unwrap();
    assert!(note.contains("one-ring"), "{note}");
    assert_eq!(fs::read(&path).unwrap(), fs::read(&default_out).unwrap());
}

/// With `--summation scatter` the cotangent sweeps use no per-triangle table: `auto` takes the
/// one-ring kernel from the start (no note, the same bytes as asking for it), and the
/// estimate is the one-ring kernel's plus the sorted triangles (12 bytes per face and 8
/// per vertex: about 0.31 MiB here) and a permutation (8 bytes per vertex).
#[test]
fn scatter_summation_takes_the_ring_kernel() {
    let dir = tempfile::tempdir().unwrap();
    let input = common::squashed_sphere(dir.path(), "scan.ply", 5);
    let run = |out: &str, extra: &[&str]| {
        let output = dir.path().join(out);
        let mut args = vec![
            "smooth",
            s(&input),
            s(&output),
            "--iterations",
            "3",
            "--summation",
            "scatter",
        ];
        args.extend_from_slice(extra);
        (beltrami(&args), output)
    };
    let (auto, auto_out) = run("auto.ply", &[]);
    assert!(auto.status.success() && auto.stderr.is_empty());
    let (per_triangle, per_triangle_out) =
        run("table.ply", &["--cotangent-kernel", "per-triangle"]);
    assert!(per_triangle.status.success());
    assert_eq!(
        fs::read(&auto_out).unwrap(),
        fs::read(&per_triangle_out).unwrap()
    );
    let refused = |extra: &[&str]| {
        let mut args = extra.to_vec();
        args.extend_from_slice(&["--max-memory", "1M"]);
        let (out, path) = run("refused.ply", &args);
        assert_eq!(out.status.code(), Some(1));
        assert!(!path.exists());
        estimate_mib(&out.stderr)
    };
    let (auto, ring) = (refused(&[]), refused(&["--cotangent-kernel", "ring"]));
    assert_eq!(auto, ring);
    // 10 242 vertices, 20 480 faces: 0.31 MiB more than summing rows with the ring
    // kernel for the sorted triangles, and 0.08 for the permutation a small mesh may
    // take for the sweep (before the estimate's margin).
    let (out, _) = {
        let output = dir.path().join("rows.ply");
        let args = [
            "smooth",
            s(&input),
            s(&output),
            "--cotangent-kernel",
            "ring",
            "--max-memory",
            "1M",
        ];
        (beltrami(&args), output)
    };
    let rows = estimate_mib(&out.stderr);
    assert!(
        ring - rows > 0.39 && ring - rows < 0.6,
        "{ring} against {rows}"
    );
}
