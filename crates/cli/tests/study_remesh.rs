//! `beltrami study --remesh L | --remesh-relative R | --no-remesh`: the remeshing
//! comparison's target length, refused before any work when it makes no sense.

mod common;

use common::{beltrami, s};

#[test]
fn remesh_lengths_that_make_no_sense_are_usage_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    for extra in [
        vec!["--remesh", "0"],
        vec!["--remesh", "-1"],
        vec!["--remesh-relative", "nan"],
        vec!["--remesh", "1", "--remesh-relative", "2"],
        vec!["--remesh", "1", "--no-remesh"],
    ] {
        let mut args = vec!["study", "--out", s(&out), "--small"];
        args.extend(extra.iter().copied());
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("remesh"), "{extra:?}: {err}");
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
}

#[test]
fn a_small_study_reports_remeshing_at_the_chosen_length_or_skips_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let base = [
        "study",
        "--out",
        s(&out),
        "--small",
        "--surfaces",
        "block",
        "--weights",
        "uniform,cotangent",
        "--iterations",
        "10,100",
        "--seeds",
        "1",
        "--no-countermeasures",
    ];
    let mut args = base.to_vec();
    args.extend(["--remesh-relative", "1.5"]);
    let o = beltrami(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Remeshing before smoothing"), "{report}");
    assert!(report.contains("L = 1.5 × the clean mesh's mean edge length"));
    assert!(report.contains("## Timing"));
    // A target of 1.5 mean edge lengths resolves the block: no caution.
    assert!(!report.contains("**Caution:**"), "{report}");
    // A coarser remesh has fewer vertices: the table's "before → after" shows it.
    let row = report
        .lines()
        .find(|l| l.starts_with("| block | ") && l.contains(" → "))
        .unwrap();
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    let (before, after) = cells[2].split_once(" → ").unwrap();
    let (before, after): (usize, usize) = (before.parse().unwrap(), after.parse().unwrap());
    assert!(after < before, "{row}");

    let mut args = base.to_vec();
    args.push("--no-remesh");
    let o = beltrami(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(!report.contains("## Remeshing before smoothing"));
}

#[test]
fn a_remesh_target_as_long_as_the_surface_is_flagged_in_the_report_and_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let args = [
        "study",
        "--out",
        s(&out),
        "--small",
        "--surfaces",
        "sphere",
        "--weights",
        "uniform,cotangent",
        "--iterations",
        "10",
        "--seeds",
        "1",
        "--no-countermeasures",
        "--remesh",
        "2",
    ];
    let o = beltrami(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    // The remeshed sphere is a handful of vertices: the table says how many, and the
    // caution names the count the table shows.
    let row = report
        .lines()
        .find(|l| l.starts_with("| sphere | ") && l.contains(" → "))
        .unwrap();
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    let after: usize = cells[2].split_once(" → ").unwrap().1.parse().unwrap();
    assert!(after < beltrami_study::TOO_COARSE_VERTICES, "{row}");
    let said = format!("the remeshed sphere has only {after} vertices");
    assert!(report.contains(&format!("**Caution:** {said}")), "{report}");
    let warning = err
        .lines()
        .find(|l| l.starts_with("warning: "))
        .unwrap_or_else(|| panic!("no warning: {err}"));
    assert!(warning.contains(&said), "{warning}");
    assert!(warning.contains("--remesh"), "{warning}");

    // Longer still, the few vertices are drawn together on the sphere: refused with one
    // line, no report.
    let out = dir.path().join("refused");
    let mut args = args.to_vec();
    args[2] = s(&out);
    *args.last_mut().unwrap() = "1e9";
    let o = beltrami(&args);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("too long for this surface"), "{err}");
    assert!(!out.join("report.md").exists());
}
