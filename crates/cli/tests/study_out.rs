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

#[test]
fn the_entries_of_a_study_of_a_given_surface_are_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    // A study of a given surface writes its best meshes; the paper's study does not.
    std::fs::write(out.join("best-cotangent-plain.ply"), "").unwrap();
    let paper = beltrami(&["study", "--small", "--out", s(&out)]);
    assert_eq!(paper.status.code(), Some(2));
    assert!(
        error_line(&paper, dir.path()).contains("holds 'best-cotangent-plain.ply'"),
        "{paper:?}"
    );
    // For --input the same directory passes the check; the missing input fails next.
    let scan = beltrami(&["study", "--input", "missing.ply", "--out", s(&out)]);
    assert!(!error_line(&scan, dir.path()).contains("holds"), "{scan:?}");
}
