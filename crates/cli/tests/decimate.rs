//! `beltrami decimate` as a user runs it: a triangle fixture decimates into the library's
//! result, the JSON summary has its keys, constraints that stop the run say so, a broken
//! or non-triangle input gives one error line and no output, and bad usage exits with
//! code 2 and one line before anything is written.

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_algorithms::{DecimateOptions, Placement, decimate};
use beltrami_io::read_mesh;
use common::{beltrami, error_line, f, s};
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
}

#[test]
fn decimates_into_the_library_result() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["noisy_icosphere_4.ply", "flens_68x33.ply", "torus_12x8.ply"] {
        let input = fixtures().join(name);
        let out = dir.path().join("out.ply");
        let o = beltrami(&[
            "decimate",
            s(&input),
            s(&out),
            "--ratio",
            "0.25",
            "--json",
            "--force",
        ]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        let data = read_mesh(&input).unwrap();
        let mesh = data.mesh().unwrap();
        let (want, positions, report) = decimate(
            &mesh,
            &data.positions,
            &DecimateOptions::default().ratio(0.25),
        )
        .unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{name}");
        assert_eq!(got.faces, want.to_polygons(), "{name}");
        for key in [
            "input",
            "output",
            "vertices_before",
            "vertices_after",
            "faces_before",
            "faces_after",
            "target_vertices",
            "target_reached",
            "stop",
            "collapses",
            "refused",
            "placement",
            "max_quadric_error",
            "hausdorff",
            "hausdorff_to_input",
            "hausdorff_from_input",
            "seconds",
            "seconds_measure",
        ] {
            assert!(summary.get(key).is_some(), "{name}: no {key}");
        }
        assert_eq!(summary["vertices_after"], report.vertices_after);
        assert_eq!(summary["target_reached"], true);
        assert_eq!(summary["stop"], "target reached");
        assert_eq!(summary["hausdorff"].as_f64().unwrap(), report.hausdorff);
        assert_eq!(summary["placement"], "optimal");
        assert_eq!(summary["quality_threshold"], 0.4);
    }
}

#[test]
fn no_distance_skips_the_measurement_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec!["decimate", s(&input), s(out), "--ratio", "0.25"];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        o.stdout
    };
    let (measured, skipped) = (dir.path().join("a.ply"), dir.path().join("b.ply"));
    let with: Value = serde_json::from_slice(&run(&["--json"], &measured)).unwrap();
    let without: Value =
        serde_json::from_slice(&run(&["--json", "--no-distance"], &skipped)).unwrap();
    // The same mesh either way: the measurement is no part of the decimation.
    assert_eq!(fs::read(&measured).unwrap(), fs::read(&skipped).unwrap());
    assert!(with["hausdorff"].as_f64().unwrap() > 0.0);
    assert!(with["seconds_measure"].as_f64().unwrap() >= 0.0);
    assert!(with["seconds"].as_f64().unwrap() >= 0.0);
    for key in [
        "hausdorff",
        "hausdorff_to_input",
        "hausdorff_from_input",
        "seconds_measure",
    ] {
        assert!(without[key].is_null(), "{key}: {}", without[key]);
    }
    assert!(without["seconds"].as_f64().unwrap() >= 0.0);
    assert_eq!(with["vertices_after"], without["vertices_after"]);
    // The sentence leaves the distance out rather than printing a number not measured.
    let text = String::from_utf8(run(&["--no-distance", "--force"], &skipped)).unwrap();
    let sentence = text.lines().next().unwrap();
    assert!(sentence.contains("(target "), "{sentence}");
    assert!(!sentence.contains("Hausdorff"), "{sentence}");
    let text = String::from_utf8(run(&["--force"], &skipped)).unwrap();
    assert!(
        text.lines()
            .next()
            .unwrap()
            .contains("Hausdorff distance to the input")
    );
}

#[test]
fn openmesh_mode_and_endpoint_placement_keep_input_points() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let data = read_mesh(&input).unwrap();
    let mesh = data.mesh().unwrap();
    for (extra, options, threshold) in [
        (&["--openmesh"][..], DecimateOptions::openmesh(), 0.0),
        (
            &["--placement", "endpoint"],
            DecimateOptions::default().placement(Placement::Endpoint),
            0.4,
        ),
    ] {
        let out = dir.path().join("out.ply");
        let mut args = vec![
            "decimate",
            s(&input),
            s(&out),
            "--ratio",
            "0.3",
            "--json",
            "--force",
        ];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(
            o.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(summary["placement"], "endpoint", "{extra:?}");
        assert_eq!(summary["quality_threshold"], threshold, "{extra:?}");
        let (_, positions, _) = decimate(&mesh, &data.positions, &options.ratio(0.3)).unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{extra:?}");
        // Endpoint placement: every output vertex is an input vertex, bit for bit.
        assert!(
            got.positions.iter().all(|p| data.positions.contains(p)),
            "{extra:?}"
        );
    }
    for bad in [
        &["--quality-threshold", "1.5"][..],
        &["--openmesh", "--placement", "optimal"],
        &["--openmesh", "--quality-threshold", "0.2"],
        &["--openmesh", "--plane-weights", "uniform"],
        &["--openmesh", "--stabilizer", "0.001"],
        &["--placement", "middle"],
        &["--plane-weights", "volume"],
        &["--stabilizer=-0.001"],
        &["--stabilizer", "inf"],
        &["--flip-tolerance", "-0.1"],
        &["--flip-tolerance", "nan"],
        &["--openmesh", "--flip-tolerance", "0.5"],
        &["--fit-rounds", "-1"],
        &["--fit-rounds", "two"],
        // A count far beyond what the fit can use (a typing error that would run for
        // hours): 100 is the most.
        &["--fit-rounds", "101"],
        &["--fit-rounds", "4294967296"],
        &["--openmesh", "--fit-rounds", "1"],
        // Options that cannot take effect are refused, not dropped.
        &["--fit-rounds", "3", "--placement", "endpoint"],
        &["--fit-rounds", "3", "--max-distance", "0.1"],
        &["--fit-rounds", "1", "--max-normal-deviation", "30"],
        &["--flip-tolerance", "0.7", "--max-distance", "1"],
        &["--flip-tolerance", "0.2", "--max-normal-deviation", "30"],
    ] {
        let out = dir.path().join("bad.ply");
        let mut args = vec!["decimate", s(&input), s(&out), "--ratio", "0.3"];
        args.extend_from_slice(bad);
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(2), "{bad:?}");
        assert!(!out.exists(), "{bad:?}");
    }
}

#[test]
fn the_sentence_says_whether_the_target_was_reached() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("flens_68x33.ply");
    let out = dir.path().join("out.off");
    let o = beltrami(&[
        "decimate",
        s(&input),
        s(&out),
        "--vertices",
        "500",
        "--keep-boundary",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let line = String::from_utf8(o.stdout).unwrap();
    // The sentence, then the quality table: a header and six rows.
    assert_eq!(line.lines().count(), 8, "{line}");
    assert!(
        line.lines().nth(1).unwrap().starts_with("quality"),
        "{line}"
    );
    assert!(
        line.contains("2244 -> 500 vertices (target 500 reached)"),
        "{line}"
    );
    assert!(line.contains("Hausdorff"), "{line}");
    assert_eq!(read_mesh(&out).unwrap().positions.len(), 500);

    let o = beltrami(&[
        "decimate",
        s(&input),
        s(&out),
        "--ratio",
        "0.05",
        "--max-normal-deviation",
        "5",
        "--force",
    ]);
    assert!(o.status.success());
    let line = String::from_utf8(o.stdout).unwrap();
    assert!(line.contains("not reached"), "{line}");
    assert!(line.contains("--max-normal-deviation"), "{line}");
    let o = beltrami(&[
        "decimate",
        s(&input),
        s(&out),
        "--ratio",
        "0.2",
        "--optimal",
        "--max-aspect-ratio",
        "4",
        "--max-distance",
        "0.5",
        "--max-error",
        "1",
        "--json",
        "--force",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["placement"], "optimal");
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
        let o = beltrami(&["decimate", s(&bad), s(&out), "--ratio", "0.5"]);
        assert_eq!(o.status.code(), Some(1), "{bad:?}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{bad:?}"
        );
        assert!(!out.exists(), "{bad:?}");
    }
    let quads = fixtures().join("cube_quads.obj");
    let o = beltrami(&["decimate", s(&quads), s(&out), "--ratio", "0.5"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(error_line(&o, dir.path()).contains("needs a triangle mesh"));
    assert!(!out.exists());

    let input = fixtures().join("grid_4x3.ply");
    for args in [
        &[][..],
        &["--vertices", "10", "--ratio", "0.5"][..],
        &["--vertices", "0"][..],
        &["--ratio", "0"][..],
        &["--ratio", "1.5"][..],
        &["--ratio", "0.5", "--max-normal-deviation", "200"][..],
        &["--ratio", "0.5", "--max-error=-1"][..],
        &["--ratio", "0.5", "--max-aspect-ratio", "0.5"][..],
        &["--ratio", "0.5", "--max-distance=-1"][..],
    ] {
        let mut all = vec!["decimate", s(&input), s(&out)];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(!out.exists());
    }
    let o = beltrami(&["decimate", s(&input), s(&out), "--ratio", "many"]);
    assert_eq!(o.status.code(), Some(2));
    // The input is not overwritten without --force.
    let o = beltrami(&["decimate", s(&input), s(&input), "--ratio", "0.5"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn the_fit_rounds_reach_the_library_and_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let data = read_mesh(&input).unwrap();
    let mesh = data.mesh().unwrap();
    let out = dir.path().join("out.ply");
    for (extra, rounds) in [
        (&[][..], 2),
        (&["--fit-rounds", "0"][..], 0),
        (&["--fit-rounds", "3"][..], 3),
    ] {
        let mut args = vec!["decimate", s(&input), s(&out), "--ratio", "0.3", "--force"];
        args.extend_from_slice(extra);
        let text = beltrami(&args);
        assert!(
            text.status.success(),
            "{}",
            String::from_utf8_lossy(&text.stderr)
        );
        let text = String::from_utf8(text.stdout).unwrap();
        assert_eq!(
            text.contains(&format!("fitted to the input in {rounds} rounds")),
            rounds > 0,
            "{text}"
        );
        args.extend(["--json", "--no-distance"]);
        let summary: Value = serde_json::from_slice(&beltrami(&args).stdout).unwrap();
        let options = DecimateOptions::default().ratio(0.3).fit_rounds(rounds);
        let (want, positions, report) = decimate(&mesh, &data.positions, &options).unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{extra:?}");
        assert_eq!(got.faces, want.to_polygons(), "{extra:?}");
        assert_eq!(summary["fit_rounds"], rounds, "{extra:?}");
        if rounds > 0 {
            assert_eq!(f(&summary["fit_rms_before"]), report.fit_rms_before);
            assert_eq!(f(&summary["fit_rms_after"]), report.fit_rms_after);
            assert!(report.fit_rms_after < report.fit_rms_before, "{report:?}");
        } else {
            // No fit: null, not a 0.0 that reads as a perfect fit.
            assert!(summary["fit_rms_before"].is_null(), "{summary}");
            assert!(summary["fit_rms_after"].is_null(), "{summary}");
        }
    }
}

#[test]
fn the_flip_tolerance_reaches_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let data = read_mesh(&input).unwrap();
    let mesh = data.mesh().unwrap();
    let out = dir.path().join("out.ply");
    let mut flips = Vec::new();
    for (extra, tolerance) in [
        (&[][..], 0.2),
        (&["--flip-tolerance", "0"][..], 0.0),
        (&["--flip-tolerance", "0.5"][..], 0.5),
    ] {
        let mut args = vec![
            "decimate",
            s(&input),
            s(&out),
            "--ratio",
            "0.3",
            "--json",
            "--force",
            "--no-distance",
        ];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(
            o.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        let options = DecimateOptions::default()
            .ratio(0.3)
            .flip_tolerance(tolerance);
        let (want, positions, report) = decimate(&mesh, &data.positions, &options).unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{extra:?}");
        assert_eq!(got.faces, want.to_polygons(), "{extra:?}");
        assert_eq!(summary["flip_tolerance"], tolerance, "{extra:?}");
        assert_eq!(summary["flips"], report.flips, "{extra:?}");
        flips.push(report.flips);
    }
    // No flips at 0; a larger tolerance allows at least as many.
    assert!(
        flips[0] > 0 && flips[1] == 0 && flips[2] >= flips[0],
        "{flips:?}"
    );
    // OpenMesh's mode makes none.
    let o = beltrami(&[
        "decimate",
        s(&input),
        s(&out),
        "--ratio",
        "0.3",
        "--json",
        "--force",
        "--no-distance",
        "--openmesh",
    ]);
    let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["flips"], 0);
    assert_eq!(summary["flip_tolerance"], 0.0);
}

#[test]
fn plane_weights_and_the_stabilizer_reach_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let data = read_mesh(&input).unwrap();
    let mesh = data.mesh().unwrap();
    let mut outputs = Vec::new();
    for (extra, options, weights, stabilizer) in [
        (&[][..], DecimateOptions::default(), "area", 0.0),
        (
            &["--plane-weights", "uniform"][..],
            DecimateOptions::default().area_weighted(false),
            "uniform",
            0.0,
        ),
        (
            &["--plane-weights", "uniform", "--stabilizer", "0.001"][..],
            DecimateOptions::default()
                .area_weighted(false)
                .stabilizer(0.001),
            "uniform",
            0.001,
        ),
    ] {
        let out = dir.path().join("out.ply");
        let mut args = vec![
            "decimate",
            s(&input),
            s(&out),
            "--ratio",
            "0.3",
            "--json",
            "--force",
            "--no-distance",
        ];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(
            o.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(summary["plane_weights"], weights, "{extra:?}");
        assert_eq!(summary["stabilizer"], stabilizer, "{extra:?}");
        let (_, positions, _) = decimate(&mesh, &data.positions, &options.ratio(0.3)).unwrap();
        let got = read_mesh(&out).unwrap();
        assert_eq!(got.positions, positions, "{extra:?}");
        outputs.push(got.positions);
    }
    // Each setting changes where the kept vertices go.
    assert_ne!(outputs[0], outputs[1]);
    assert_ne!(outputs[1], outputs[2]);
}

/// An option left at its default, or turned off with 0, never triggers the refusal of
/// an option that cannot take effect; the refusal names both options on one line.
#[test]
fn fit_rounds_and_flip_tolerance_are_refused_only_when_they_could_not_take_effect() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let out = dir.path().join("out.ply");
    for ok in [
        &["--placement", "endpoint"][..],
        &["--max-distance", "1"],
        &["--max-normal-deviation", "30"],
        &["--fit-rounds", "0", "--placement", "endpoint"],
        &["--fit-rounds", "0", "--max-distance", "1"],
        &["--flip-tolerance", "0", "--max-distance", "1"],
        &["--flip-tolerance", "0.5", "--placement", "endpoint"],
    ] {
        let mut args = vec!["decimate", s(&input), s(&out), "--ratio", "0.25", "--force"];
        args.extend_from_slice(ok);
        let o = beltrami(&args);
        assert!(
            o.status.success(),
            "{ok:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let o = beltrami(&[
        "decimate",
        s(&input),
        s(&out),
        "--ratio",
        "0.25",
        "--force",
        "--fit-rounds",
        "3",
        "--placement",
        "endpoint",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("--fit-rounds") && stderr.contains("--placement endpoint"),
        "{stderr}"
    );
}

/// Without a fit (endpoint placement, a bound, --openmesh) the fit's RMS values are
/// null in --json and the sentence has no fit clause.
#[test]
fn the_fit_rms_is_null_when_no_fit_ran() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("noisy_icosphere_4.ply");
    let out = dir.path().join("out.ply");
    for extra in [
        &["--placement", "endpoint"][..],
        &["--openmesh"],
        &["--max-distance", "1"],
        &["--max-normal-deviation", "30"],
    ] {
        let mut args = vec!["decimate", s(&input), s(&out), "--ratio", "0.3", "--force"];
        args.extend_from_slice(extra);
        let text = beltrami(&args);
        assert!(text.status.success(), "{extra:?}");
        assert!(
            !String::from_utf8_lossy(&text.stdout).contains("fitted"),
            "{extra:?}"
        );
        args.extend(["--json", "--no-distance"]);
        let summary: Value = serde_json::from_slice(&beltrami(&args).stdout).unwrap();
        assert_eq!(summary["fit_rounds"], 0, "{extra:?}");
        assert!(summary["fit_rms_before"].is_null(), "{extra:?}: {summary}");
        assert!(summary["fit_rms_after"].is_null(), "{extra:?}: {summary}");
    }
}

/// An infinite bound is "not a finite number", not a contradiction ("must be >= 0, got
/// inf"), and a negative one given as a separate argument reaches the same check.
#[test]
fn bounds_must_be_finite_numbers_and_may_be_given_negative() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("out.ply");
    for (args, message) in [
        (
            &["--max-error=inf"][..],
            "--max-error must be a finite number >= 0, got inf",
        ),
        (
            &["--max-distance", "-1"][..],
            "--max-distance must be a finite number >= 0, got -1",
        ),
        (
            &["--stabilizer", "-inf"][..],
            "--stabilizer must be a finite number >= 0, got -inf",
        ),
        (
            &["--max-aspect-ratio", "inf"][..],
            "--max-aspect-ratio must be a finite number >= 1, got inf",
        ),
    ] {
        let mut all = vec!["decimate", s(&input), s(&out), "--ratio", "0.5"];
        all.extend_from_slice(args);
        let o = beltrami(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(message), "{stderr}");
    }
}

/// A target above the input's vertex count is not "reached": the sentence says the
/// input already has fewer vertices.
#[test]
fn a_target_above_the_input_count_says_there_is_nothing_to_collapse() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("icosphere_2.ply");
    let out = dir.path().join("out.ply");
    let o = beltrami(&["decimate", s(&input), s(&out), "--vertices", "163"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(
            "162 -> 162 vertices (target 163: the input already has fewer vertices, nothing to collapse)"
        ),
        "{text}"
    );
    let o = beltrami(&[
        "decimate",
        s(&input),
        s(&out),
        "--force",
        "--vertices",
        "162",
    ]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("(target 162 reached)"));
}

/// Isolated vertices (in no face) stay and count in the target: a note says so and
/// points to --repair, which removes them.
#[test]
fn isolated_vertices_get_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixtures().join("bad/isolated_vertices.obj");
    let out = dir.path().join("out.obj");
    let o = beltrami(&["decimate", s(&input), s(&out), "--ratio", "0.5"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("note: the input has 2 isolated vertices in no face"),
        "{text}"
    );
    let plain = fixtures().join("icosphere_2.ply");
    let o = beltrami(&["decimate", s(&plain), s(&out), "--force", "--ratio", "0.5"]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("isolated"));
}
