//! `beltrami study --input SCAN [--reference CLEAN]`: the study on a given surface.

mod common;

use std::path::Path;

use common::{beltrami, error_line, s};
use serde_json::Value;

/// A noisy level-2 sphere and its clean original, written by `generate`.
fn generated(dir: &Path) -> (String, String) {
    let noisy = dir.join("noisy.ply");
    let clean = dir.join("clean.ply");
    let out = beltrami(&[
        "generate",
        "sphere",
        s(&noisy),
        "--level",
        "2",
        "--noise",
        "0.2",
        "--clean",
        s(&clean),
    ]);
    assert!(out.status.success(), "{out:?}");
    (s(&noisy).to_string(), s(&clean).to_string())
}

/// The quick settings of these tests: two schemes, two methods, 25 iterations.
const QUICK: [&str; 8] = [
    "--weights",
    "uniform,cotangent",
    "--methods",
    "plain,implicit",
    "--iterations",
    "25",
    "--implicit-steps",
    "0.5,2",
];

fn study(args: &[&str]) -> std::process::Output {
    let mut all = vec!["study"];
    all.extend_from_slice(args);
    all.extend_from_slice(&QUICK);
    beltrami(&all)
}

fn results_json(dir: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(dir.join("results.json")).unwrap()).unwrap()
}

#[test]
fn with_a_reference_it_writes_the_best_meshes_that_compare_agrees_with() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, clean) = generated(dir.path());
    let out_dir = dir.path().join("scan");
    let out = study(&[
        "--input",
        &noisy,
        "--reference",
        &clean,
        "--out",
        s(&out_dir),
    ]);
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.starts_with("study of noisy.ply: 2 schemes x 2 methods"),
        "{stdout}"
    );
    assert!(stdout.contains("best-cotangent-plain.ply"), "{stdout}");
    let json = results_json(&out_dir);
    let best = json["best"].as_array().unwrap();
    assert_eq!(best.len(), 4);
    let input_rms = json["rows"][0]["rms"].as_f64().unwrap();
    for b in best {
        let file = out_dir.join(b["file"].as_str().unwrap());
        let rms = b["rms"].as_f64().unwrap();
        assert!(rms < input_rms, "{b}");
        let compare = common::json(&["compare", s(&file), &clean, "--json"]);
        let measured = compare["distance"]["rms"]
            .as_f64()
            .or_else(|| compare["rms"].as_f64())
            .unwrap_or_else(|| panic!("an rms in {compare}"));
        assert!(
            (measured - rms).abs() <= 1e-12 * rms,
            "{}: compare says {measured}, the study {rms}",
            file.display()
        );
    }
    let report = std::fs::read_to_string(out_dir.join("report.md")).unwrap();
    assert!(report.contains("## Recommendation"));
    assert!(report.contains("`beltrami smooth`'s defaults"), "{report}");
}

#[test]
fn the_reported_smooth_options_reproduce_the_best_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, clean) = generated(dir.path());
    let out_dir = dir.path().join("scan");
    let out = study(&[
        "--input",
        &noisy,
        "--reference",
        &clean,
        "--out",
        s(&out_dir),
    ]);
    assert!(out.status.success(), "{out:?}");
    let json = results_json(&out_dir);
    let best = json["best"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["scheme"] == "cotangent" && b["method"] == "plain")
        .unwrap();
    let iterations = best["iteration"].as_u64().unwrap().to_string();
    let smoothed = dir.path().join("smoothed.ply");
    let out = beltrami(&[
        "smooth",
        &noisy,
        s(&smoothed),
        "--weights",
        "cotangent",
        "--iterations",
        &iterations,
    ]);
    assert!(out.status.success(), "{out:?}");
    let a = beltrami_io::read_mesh(&smoothed).unwrap();
    let b = beltrami_io::read_mesh(out_dir.join("best-cotangent-plain.ply")).unwrap();
    assert!(
        a.positions == b.positions,
        "the same positions, bit for bit"
    );
}

#[test]
fn without_a_reference_no_best_meshes_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, _) = generated(dir.path());
    let out_dir = dir.path().join("scan");
    let out = study(&["--input", &noisy, "--out", s(&out_dir)]);
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.contains("no ground truth"), "{stdout}");
    let mut names: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["report.md", "results.csv", "results.json", "timings.csv"]
    );
    let json = results_json(&out_dir);
    assert!(json["reference"].is_null());
    assert!(json["best"].as_array().unwrap().is_empty());
    let row = &json["rows"].as_array().unwrap()[10];
    assert!(row["volume_ratio"].as_f64().unwrap() < 1.0, "{row}");
}

#[test]
fn two_runs_write_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, clean) = generated(dir.path());
    let run = |name: &str| {
        let out_dir = dir.path().join(name);
        let out = study(&[
            "--input",
            &noisy,
            "--reference",
            &clean,
            "--out",
            s(&out_dir),
        ]);
        assert!(out.status.success(), "{out:?}");
        out_dir
    };
    let (a, b) = (run("a"), run("b"));
    for name in ["results.csv", "results.json", "best-uniform-implicit.ply"] {
        assert!(
            std::fs::read(a.join(name)).unwrap() == std::fs::read(b.join(name)).unwrap(),
            "{name}"
        );
    }
    let report = |d: &Path| {
        let text = std::fs::read_to_string(d.join("report.md")).unwrap();
        text[..text.find("## Time").unwrap()].to_string()
    };
    assert_eq!(report(&a), report(&b));
}

#[test]
fn usage_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, clean) = generated(dir.path());
    let out_dir = dir.path().join("scan");
    for (args, expected) in [
        (vec!["study", "--input", &noisy, "--small"], "--small"),
        (
            vec!["study", "--input", &noisy, "--surfaces", "flens"],
            "--surfaces",
        ),
        (vec!["study", "--input", &noisy, "--seeds", "2"], "--seeds"),
        (
            vec!["study", "--input", &noisy, "--noise", "0.1"],
            "--noise",
        ),
        (vec!["study", "--reference", &clean], "--input"),
        (vec!["study", "--methods", "plain"], "--input"),
    ] {
        let mut args = args.clone();
        args.extend(["--out", s(&out_dir)]);
        let out = beltrami(&args);
        let line = error_line(&out, dir.path());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {line}");
        // The parser's message: the problem, then the usage line.
        assert!(
            line.lines().take(2).any(|l| l.contains(expected)),
            "{args:?}: {line}"
        );
        assert!(!out_dir.exists());
    }
    for (extra, expected) in [
        (
            vec!["--iterations", "10,20"],
            "--iterations takes one number",
        ),
        (
            vec!["--methods", "jacobi"],
            "--methods: unknown method 'jacobi'",
        ),
        (
            vec!["--implicit-steps", "0"],
            "implicit time steps must be positive",
        ),
    ] {
        let mut args = vec!["study", "--input", &noisy, "--out", s(&out_dir)];
        args.extend(extra);
        let out = beltrami(&args);
        let line = error_line(&out, dir.path());
        assert_eq!(out.status.code(), Some(2), "{line}");
        assert_eq!(line.lines().count(), 1, "{line}");
        assert!(line.contains(expected), "{line}");
        assert!(!out_dir.exists());
    }
}

#[test]
fn bad_input_exits_1_and_writes_no_directory() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, _) = generated(dir.path());
    let out_dir = dir.path().join("scan");
    let missing = dir.path().join("missing.ply");
    let garbage = dir.path().join("garbage.ply");
    std::fs::write(&garbage, b"ply\nthis is not a mesh\n").unwrap();
    let points = common::write(
        dir.path(),
        "points.ply",
        vec![glam::DVec3::ZERO, glam::DVec3::X, glam::DVec3::Y],
        beltrami_halfedge::PolygonList::new(),
    );
    for (input, reference) in [
        (s(&missing), None),
        (s(&garbage), None),
        (s(&points), None),
        (noisy.as_str(), Some(s(&missing))),
    ] {
        let mut args = vec!["study", "--input", input, "--out", s(&out_dir)];
        if let Some(r) = reference {
            args.extend(["--reference", r]);
        }
        let out = beltrami(&args);
        let line = error_line(&out, dir.path());
        assert_eq!(out.status.code(), Some(1), "{args:?}: {line}");
        assert_eq!(line.lines().count(), 1, "{line}");
        assert!(!out_dir.exists(), "{args:?}");
        let leftovers: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().starts_with(".beltrami-"))
            .collect();
        assert!(leftovers.is_empty(), "{leftovers:?}");
    }
}

#[test]
fn an_out_dir_holding_other_files_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, _) = generated(dir.path());
    let out_dir = dir.path().join("scan");
    std::fs::create_dir(&out_dir).unwrap();
    std::fs::write(out_dir.join("notes.txt"), b"mine").unwrap();
    let out = study(&["--input", &noisy, "--out", s(&out_dir)]);
    let line = error_line(&out, dir.path());
    assert_eq!(out.status.code(), Some(2), "{line}");
    assert!(line.contains("'notes.txt'"), "{line}");
    assert_eq!(std::fs::read(out_dir.join("notes.txt")).unwrap(), b"mine");
}
