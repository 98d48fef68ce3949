//! Outputs never replace inputs without `--force`; `--max-memory` stops a run that
//! would need too much memory before the mesh is built.

mod common;

use std::fs;
use std::path::Path;

use beltrami_io::{WriteOptions, read_mesh, write_mesh};
use common::{beltrami, error_line, s};
use insta::assert_snapshot;

fn sphere(dir: &Path, name: &str) -> std::path::PathBuf {
    common::squashed_sphere(dir, name, 3)
}

fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn smooth_refuses_to_overwrite_its_input_by_any_name() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path(), "scan.ply");
    let before = fs::read(&input).unwrap();
    let hard = dir.path().join("hard.ply");
    fs::hard_link(&input, &hard).unwrap();
    let alias = dir.path().join(".").join("scan.ply");
    let mut outputs = vec![input.clone(), alias, hard.clone()];
    #[cfg(unix)]
    {
        let soft = dir.path().join("soft.ply");
        std::os::unix::fs::symlink(&input, &soft).unwrap();
        outputs.push(soft);
    }
    for output in &outputs {
        let out = beltrami(&["smooth", s(&input), s(output)]);
        assert_eq!(out.status.code(), Some(2), "{output:?}");
        let line = error_line(&out, dir.path());
        assert!(
            line.contains("refusing to overwrite the input file"),
            "{line}"
        );
        assert_eq!(fs::read(&input).unwrap(), before, "input untouched");
    }
    let out = beltrami(&["smooth", s(&input), s(&input)]);
    assert_snapshot!(error_line(&out, dir.path()), @"error: scan.ply: refusing to overwrite the input file scan.ply (pass --force to replace it)");

    // The report may not replace the input either.
    let output = dir.path().join("out.ply");
    let out = beltrami(&["smooth", s(&input), s(&output), "--report", s(&hard)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!output.exists());
    assert_eq!(fs::read(&input).unwrap(), before);

    // With --force the input is replaced by the smoothed mesh, whole.
    let out = beltrami(&["smooth", s(&input), s(&input), "--force"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let smoothed = read_mesh(&input).unwrap();
    assert_eq!(smoothed.positions.len(), 642);
    assert_ne!(fs::read(&input).unwrap(), before);
    // The hard link still names the old file: the rename replaced one name only.
    assert_eq!(fs::read(&hard).unwrap(), before);
}

#[test]
fn compare_and_residual_refuse_to_overwrite_their_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let a = sphere(dir.path(), "a.ply");
    let b = dir.path().join("b.ply");
    let out = beltrami(&["smooth", s(&a), s(&b)]);
    assert!(out.status.success());
    let (before_a, before_b) = (fs::read(&a).unwrap(), fs::read(&b).unwrap());

    // compare's --scalars is no result mesh of MESH: it never replaces an input, and
    // --force does not change that.
    for force in [&[][..], &["--force"][..]] {
        let mut args = vec!["compare", s(&a), s(&b), "--scalars", s(&b)];
        args.extend_from_slice(force);
        let out = beltrami(&args);
        assert_eq!(out.status.code(), Some(2));
        assert_eq!(
            error_line(&out, dir.path()),
            "error: b.ply: --scalars is the input file b.ply, which it would replace; give --scalars a file of its own (see 'beltrami --help')"
        );
    }
    let out = beltrami(&["residual", s(&a), s(&b), "--out", s(&a)]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @"error: a.ply: refusing to overwrite the input file a.ply (pass --force to replace it)");
    assert_eq!(fs::read(&a).unwrap(), before_a);
    assert_eq!(fs::read(&b).unwrap(), before_b);

    let out = beltrami(&["residual", s(&a), s(&b), "--out", s(&a), "--force"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_ne!(fs::read(&a).unwrap(), before_a);
}

#[test]
fn max_memory_stops_the_run_before_the_mesh_is_built() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path(), "scan.ply");
    let output = dir.path().join("out.ply");
    // 642 vertices, 1280 triangles: 16 MiB + 642 * 128 B + 3840 * 96 B.
    let out = beltrami(&["smooth", s(&input), s(&output), "--max-memory", "16M"]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: scan.ply: the run needs about 16.3 MiB (642 vertices, 1280 faces), more than --max-memory 16.0 MiB");
    assert_eq!(
        names(dir.path()),
        ["scan.ply"],
        "no output, no temporary file"
    );

    // OBJ declares no counts: the check runs on the data as read.
    let obj = dir.path().join("scan.obj");
    write_mesh(&obj, &read_mesh(&input).unwrap(), &WriteOptions::default()).unwrap();
    let out = beltrami(&["smooth", s(&obj), s(&output), "--max-memory", "16777216"]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: scan.obj: the run needs about 16.3 MiB (642 vertices, 1280 faces), more than --max-memory 16.0 MiB");
    assert!(!output.exists());

    // Under the limit the run goes through; --verbose prints the estimate.
    let out = beltrami(&[
        "smooth",
        s(&input),
        s(&output),
        "--max-memory",
        "1.5G",
        "--verbose",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        "note: this run needs about 16.3 MiB (642 vertices, 1280 faces) of memory\nnote: planned 10 iterations of step 0.8\n"
    );
    assert!(output.exists());
    // Small runs print nothing without --verbose.
    let out = beltrami(&["smooth", s(&input), s(&output)]);
    assert!(out.status.success() && out.stderr.is_empty());
}

#[test]
fn a_bad_size_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path(), "scan.ply");
    let output = dir.path().join("out.ply");
    let out = beltrami(&["smooth", s(&input), s(&output), "--max-memory", "12X"]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @r#"
error: invalid value '12X' for '--max-memory <SIZE>': unknown unit "X" (use K, M, G or T)

For more information, try '--help'.
"#);
    assert!(!output.exists());
}

#[test]
fn no_sync_writes_the_same_files_and_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = sphere(dir.path(), "scan.ply");
    let (a, b) = (dir.path().join("a.ply"), dir.path().join("b.ply"));
    let (ra, rb) = (dir.path().join("a.json"), dir.path().join("b.json"));
    let out = beltrami(&["smooth", s(&input), s(&a), "--report", s(&ra)]);
    assert!(out.status.success(), "{out:?}");
    // Before the subcommand's name and after it.
    let out = beltrami(&["--no-sync", "smooth", s(&input), s(&b), "--report", s(&rb)]);
    assert!(out.status.success(), "{out:?}");
    assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
    let out = beltrami(&["smooth", s(&input), s(&b), "--force", "--no-sync"]);
    assert!(out.status.success(), "{out:?}");
    assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
    let json =
        |p: &Path| serde_json::from_slice::<serde_json::Value>(&fs::read(p).unwrap()).unwrap();
    let (report_a, report_b) = (json(&ra), json(&rb));
    assert!(report_b["vertices"].as_u64().unwrap() > 0);
    assert_eq!(report_a["vertices"], report_b["vertices"]);
    assert_eq!(report_a["iterations"], report_b["iterations"]);
    assert!(
        names(dir.path())
            .iter()
            .all(|n| !n.starts_with(".beltrami-"))
    );
}
