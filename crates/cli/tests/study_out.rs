//! `beltrami study --out DIR`: the output directory is checked before any work, for the
//! paper's study and for `--input`, with one line and exit code 2.

mod common;

use common::{beltrami, error_line, s};

#[test]
fn a_directory_holding_other_files_is_refused_before_the_study_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let expected = "error: --out out holds 'notes.txt', which a study does not write; give a new or empty directory, or one holding an earlier study (which is replaced) (see 'beltrami --help')";
    let paper = beltrami(&["study", "--small", "--out", s(&out)]);
    assert_eq!(paper.status.code(), Some(2));
    assert_eq!(error_line(&paper, dir.path()), expected);
    let scan = beltrami(&["study", "--input", "missing.ply", "--out", s(&out)]);
    assert_eq!(scan.status.code(), Some(2));
    assert_eq!(error_line(&scan, dir.path()), expected);
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        1,
        "nothing written"
    );
}

#[test]
fn a_file_given_as_the_directory_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("report");
    std::fs::write(&file, "mine").unwrap();
    let run = beltrami(&["study", "--small", "--out", s(&file)]);
    assert_eq!(run.status.code(), Some(2));
    assert_eq!(
        error_line(&run, dir.path()),
        "error: --out report is not a directory (see 'beltrami --help')"
    );
    assert_eq!(std::fs::read(&file).unwrap(), b"mine");
}

/// Either kind of study replaces an earlier study of either kind (the directory is
/// replaced as a whole); a directory holding only names a study writes, but no study's
/// results.json (the user's own report.md), is no earlier study and is refused.
#[test]
fn an_earlier_study_of_either_kind_is_replaced_and_a_lookalike_is_not() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let scan_input = fixtures.join("noisy_icosphere_4.ply");
    let scan = [
        "study",
        "--input",
        s(&scan_input),
        "--weights",
        "uniform",
        "--methods",
        "plain",
        "--iterations",
        "3",
        "--out",
        s(&out),
    ];
    let paper = [
        "study",
        "--small",
        "--surfaces",
        "flens",
        "--weights",
        "uniform",
        "--iterations",
        "2",
        "--seeds",
        "1",
        "--no-countermeasures",
        "--no-remesh",
        "--no-scan-example",
        "--out",
        s(&out),
    ];
    for (first, second) in [(&scan[..], &paper[..]), (&paper[..], &scan[..])] {
        let _ = std::fs::remove_dir_all(&out);
        let run = beltrami(first);
        assert!(run.status.success(), "{run:?}");
        let run = beltrami(second);
        assert!(run.status.success(), "{run:?}");
        // The second study's entries alone: the first's are gone.
        let has = |name: &str| out.join(name).exists();
        assert_eq!(has("timings.csv"), second == &scan[..]);
        assert_eq!(has("plots"), second == &paper[..]);
    }
    // The user's own report.md, alone or beside a best mesh: refused, and kept.
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("report.md"), "my own notes").unwrap();
    for command in [&paper[..], &scan[..]] {
        let run = beltrami(command);
        assert_eq!(run.status.code(), Some(2), "{run:?}");
        assert_eq!(
            error_line(&run, dir.path()),
            "error: --out out holds 'report.md' but no results.json of a study, so it is no earlier study (which would be replaced); give a new or empty directory (see 'beltrami --help')"
        );
        assert_eq!(
            std::fs::read(out.join("report.md")).unwrap(),
            b"my own notes"
        );
    }
    // A results.json that is no study's (an array, an object without `config`): the
    // same.
    for text in ["[0]", "{\"rows\": []}"] {
        std::fs::write(out.join("results.json"), text).unwrap();
        let run = beltrami(&paper);
        assert_eq!(run.status.code(), Some(2), "{text}: {run:?}");
        assert!(
            error_line(&run, dir.path()).contains("no results.json of a study"),
            "{text}"
        );
    }
}

/// Options of one kind of study are refused by the other, and values a study cannot
/// use are usage errors (exit 2) before any work.
#[test]
fn options_a_study_cannot_use_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for (args, wanted) in [
        (
            &["--methods", "plain"][..],
            "--methods applies to the study of a given surface",
        ),
        (
            &["--implicit-steps", "1"][..],
            "--implicit-steps applies to the study of a given surface",
        ),
        (
            &["--reference", "clean.ply"][..],
            "--reference applies to the study of a given surface",
        ),
        (
            &["--iterations", "2000000"][..],
            "iteration counts must be at most 1000000",
        ),
        (
            &["--iterations", "1,18446744073709551615"][..],
            "iteration counts must be at most 1000000",
        ),
        (
            &["--noise", "nan"][..],
            "the noise level must be finite and not negative, got NaN",
        ),
        (
            &["--noise", "-1"][..],
            "the noise level must be finite and not negative, got -1",
        ),
        (
            &["--noise", "1e300"][..],
            "the noise level must be at most 10 mean edge lengths",
        ),
        (
            &["--surfaces", "sphere,sphere"][..],
            "surface 'sphere' given twice",
        ),
        (
            &["--weights", "uniform,uniform"][..],
            "weight scheme 'uniform' given twice",
        ),
    ] {
        let mut all = vec!["study", "--small", "--out", s(&out)];
        all.extend_from_slice(args);
        let run = beltrami(&all);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {run:?}");
        let line = error_line(&run, dir.path());
        assert!(line.contains(wanted), "{args:?}: {line}");
        assert_eq!(
            String::from_utf8_lossy(&run.stderr).lines().count(),
            1,
            "{args:?}"
        );
        assert!(!out.exists(), "{args:?}");
    }
    // Without --small as well (an option that conflicts with --input made clap skip
    // its own check).
    for option in [
        &["--methods", "plain"][..],
        &["--reference", "clean.ply"][..],
    ] {
        let mut all = vec!["study", "--out", s(&out)];
        all.extend_from_slice(option);
        let run = beltrami(&all);
        assert_eq!(run.status.code(), Some(2), "{option:?}: {run:?}");
        assert_eq!(
            String::from_utf8_lossy(&run.stderr).lines().count(),
            1,
            "{run:?}"
        );
        assert!(!out.exists());
    }
    let input = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/noisy_icosphere_4.ply");
    let run = beltrami(&[
        "study",
        "--input",
        s(&input),
        "--iterations",
        "2000000",
        "--out",
        s(&out),
    ]);
    assert_eq!(run.status.code(), Some(2), "{run:?}");
    assert!(
        error_line(&run, dir.path()).contains("at most 1000000"),
        "{run:?}"
    );
}
