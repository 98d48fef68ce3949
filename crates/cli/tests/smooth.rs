//! `beltrami smooth` as a user runs it.

mod common;

use std::path::{Path, PathBuf};

use beltrami_halfedge::primitives;
use beltrami_io::{MeshData, WriteOptions, read_mesh, write_mesh};
use beltrami_smooth::{Boundary, SmoothConfig, Summation, WeightUpdate, smooth};
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};
use insta::assert_snapshot;
use serde_json::Value;

use common::{beltrami, error_line, s, write};

/// A noisy icosphere written as binary PLY; returns its path and data.
fn noisy_sphere(dir: &Path) -> (PathBuf, MeshData) {
    let p = primitives::icosphere(3);
    let mut state = 17u64;
    let positions = p
        .positions
        .iter()
        .map(|&x| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            x * (1.0 + 0.02 * r)
        })
        .collect();
    let data = MeshData {
        positions,
        faces: p.faces,
    };
    let path = dir.join("noisy.ply");
    write_mesh(&path, &data, &WriteOptions::default()).unwrap();
    (path, data)
}

#[test]
fn cli_output_equals_the_library_for_every_scheme_update_and_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let (input, data) = noisy_sphere(dir.path());
    // Open the sphere by dropping a face so the boundary modes differ.
    let faces: Vec<&[u32]> = data.faces.iter().skip(1).collect();
    let open = MeshData {
        positions: data.positions.clone(),
        faces: faces.into_iter().collect(),
    };
    let open_path = dir.path().join("open.ply");
    write_mesh(&open_path, &open, &WriteOptions::default()).unwrap();
    let mesh =
        beltrami_halfedge::HalfedgeMesh::from_polygons(open.positions.len(), open.faces.iter())
            .unwrap();

    let schemes: [(&str, &dyn WeightScheme); 3] = [
        ("uniform", &Uniform),
        ("distance", &InverseDistance),
        ("cotangent", &Cotangent),
    ];
    for (name, scheme) in schemes {
        for (update, u) in [("every", WeightUpdate::Every), ("once", WeightUpdate::Once)] {
            for (boundary, b) in [
                ("fixed", Boundary::Fixed),
                ("free", Boundary::Free),
                ("curve", Boundary::Curve),
            ] {
                let output = dir.path().join(format!("{name}-{update}-{boundary}.ply"));
                let out = beltrami(&[
                    "smooth",
                    s(&open_path),
                    s(&output),
                    "--weights",
                    name,
                    "--update",
                    update,
                    "--boundary",
                    boundary,
                    "--iterations",
                    "6",
                    "--lambda",
                    "0.7",
                ]);
                assert!(
                    out.status.success(),
                    "{}",
                    String::from_utf8_lossy(&out.stderr)
                );
                let got = read_mesh(&output).unwrap();
                let want = smooth(
                    &mesh,
                    &open.positions,
                    scheme,
                    SmoothConfig::new(0.7, 6).update(u).boundary(b),
                )
                .unwrap();
                assert_eq!(got.faces, open.faces, "faces are kept exactly");
                assert_eq!(got.positions, want.positions, "{name} {update} {boundary}");
                assert_ne!(got.positions, open.positions);
            }
        }
    }
    let _ = input;
}

#[test]
fn report_json_has_parameters_and_per_iteration_stats() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = noisy_sphere(dir.path());
    let output = dir.path().join("out.obj");
    let report = dir.path().join("report.json");
    let out = beltrami(&[
        "smooth",
        s(&input),
        s(&output),
        "--weights",
        "distance",
        "--iterations",
        "4",
        "--report",
        s(&report),
    ]);
    assert!(out.status.success());
    let j: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(j["parameters"]["weights"], "distance");
    assert_eq!(j["parameters"]["lambda"], 0.8);
    assert_eq!(j["parameters"]["boundary"], "fixed");
    assert_eq!(j["parameters"]["update"], "every");
    assert_eq!(j["iterations"], 4);
    assert_eq!(j["stop"], "completed");
    assert_eq!(j["steps"].as_array().unwrap().len(), 4);
    assert_eq!(j["vertices"], 642);
    // Diffusion damps the noise: each iteration moves less than the one before.
    let moves: Vec<f64> = j["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["mean_displacement"].as_f64().unwrap())
        .collect();
    assert!(moves.windows(2).all(|w| w[1] < w[0]), "{moves:?}");
    // Reading is split into decoding the file and building the connectivity.
    let t = |k: &str| {
        j["seconds"][k]
            .as_f64()
            .unwrap_or_else(|| panic!("seconds.{k}"))
    };
    for k in ["read", "parse", "build", "weights", "updates", "write"] {
        assert!(t(k) >= 0.0 && t(k).is_finite(), "seconds.{k} = {}", t(k));
    }
    assert!(t("parse") + t("build") <= t("read"), "{}", j["seconds"]);
    // OBJ output keeps the vertex count.
    assert_eq!(read_mesh(&output).unwrap().positions.len(), 642);
}

#[test]
fn bad_parameters_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = noisy_sphere(dir.path());
    let output = dir.path().join("out.ply");
    let out = beltrami(&["smooth", s(&input), s(&output), "--weights", "cot"]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @r#"error: unknown weight scheme "cot" (known: uniform, distance, cotangent, bilateral) (see 'beltrami --help')"#);
    let out = beltrami(&["smooth", s(&input), s(&output), "--lambda", "1.5"]);
    assert_eq!(out.status.code(), Some(2));
    assert_snapshot!(error_line(&out, dir.path()), @"error: lambda must be in (0, 1] with weight-sum normalisation, got 1.5 (see 'beltrami smooth --help')");
    let out = beltrami(&["smooth", s(&input), s(&output), "--boundary", "sideways"]);
    assert_eq!(out.status.code(), Some(2));
    error_line(&out, dir.path());
    assert!(!output.exists(), "no output after a failed run");
}

#[test]
fn a_failed_run_leaves_an_existing_output_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = noisy_sphere(dir.path());
    let output = dir.path().join("out.ply");
    std::fs::write(&output, b"precious").unwrap();
    // A pinned vertex that does not exist fails after the input was read.
    let out = beltrami(&["smooth", s(&input), s(&output), "--pin", "1,100000"]);
    assert_eq!(out.status.code(), Some(1));
    error_line(&out, dir.path());
    assert_eq!(std::fs::read(&output).unwrap(), b"precious");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 2, "{leftovers:?}");
}

#[test]
fn pinned_vertices_do_not_move() {
    let dir = tempfile::tempdir().unwrap();
    let (input, data) = noisy_sphere(dir.path());
    let output = dir.path().join("out.ply");
    let out = beltrami(&[
        "smooth",
        s(&input),
        s(&output),
        "--pin",
        "0,5,7",
        "--iterations",
        "3",
    ]);
    assert!(out.status.success());
    let got = read_mesh(&output).unwrap();
    for i in [0, 5, 7] {
        assert_eq!(got.positions[i], data.positions[i]);
    }
    assert_ne!(got.positions[1], data.positions[1]);
    let out = beltrami(&["smooth", s(&input), s(&output), "--pin", "9999"]);
    assert_eq!(out.status.code(), Some(1));
    assert_snapshot!(error_line(&out, dir.path()), @"error: noisy.ply: pinned vertex 9999 does not exist (the mesh has 642 vertices)");
}

#[test]
fn step_statistics_can_be_left_out_without_changing_the_result() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _) = noisy_sphere(dir.path());
    let run = |name: &str, extra: &[&str]| {
        let output = dir.path().join(format!("{name}.ply"));
        let report = dir.path().join(format!("{name}.json"));
        let mut args = vec![
            "smooth",
            s(&input),
            s(&output),
            "--iterations",
            "5",
            "--report",
            s(&report),
        ];
        args.extend_from_slice(extra);
        let out = beltrami(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let j: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
        (std::fs::read(&output).unwrap(), j)
    };
    let (with, j_with) = run("with", &[]);
    let (without, j_without) = run("without", &["--no-step-stats"]);
    assert_eq!(with, without, "the smoothed file depends on the statistics");
    assert_eq!(j_with["steps"].as_array().unwrap().len(), 5);
    assert_eq!(j_without["steps"].as_array().unwrap().len(), 0);
    assert_eq!(j_without["iterations"], 5);
    // Without --report the flag is refused: there would be nothing to leave out.
    let out = beltrami(&[
        "smooth",
        s(&input),
        s(&dir.path().join("x.ply")),
        "--no-step-stats",
    ]);
    assert_eq!(out.status.code(), Some(2));
}

/// `--summation scatter`: the library's scattered summation (the same bytes) for
/// cotangent and inverse-distance weights, within rounding of the default's rows,
/// counted in the report; refused (exit 2, nothing written) where it would change
/// nothing; and a note where it did not apply.
#[test]
fn scatter_summation_is_the_librarys_and_says_when_it_did_not_apply() {
    let dir = tempfile::tempdir().unwrap();
    let (input, data) = noisy_sphere(dir.path());
    let (rows, scattered) = (dir.path().join("rows.ply"), dir.path().join("scatter.ply"));
    let report = dir.path().join("report.json");
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec!["smooth", s(&input), s(out), "--iterations", "6"];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    let mesh =
        beltrami_halfedge::HalfedgeMesh::from_polygons(data.positions.len(), data.faces.iter())
            .unwrap();
    let schemes: [(&str, &dyn WeightScheme); 2] =
        [("cotangent", &Cotangent), ("distance", &InverseDistance)];
    for (name, scheme) in schemes {
        run(&rows, &["--weights", name, "--force"]);
        let said = run(
            &scattered,
            &[
                "--weights",
                name,
                "--summation",
                "scatter",
                "--report",
                s(&report),
                "--force",
            ],
        );
        assert!(!said.contains("note:"), "{said}");
        let j: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
        assert_eq!(j["parameters"]["summation"], "scatter");
        assert_eq!(j["scattered_sweeps"], 6);
        let config = SmoothConfig::new(0.8, 6).summation(Summation::Scatter);
        let want = smooth(&mesh, &data.positions, scheme, config).unwrap();
        let got = read_mesh(&scattered).unwrap().positions;
        assert_eq!(got, want.positions, "{name}: the library's bytes");
        let by_rows = read_mesh(&rows).unwrap().positions;
        let far = by_rows
            .iter()
            .zip(&got)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0, f64::max);
        assert!(far > 0.0 && far < 1e-14, "{name}: {far:e}");
    }
    // A quad mesh: cotangent rows are summed as usual, and the command says so;
    // inverse distances are scattered by edges.
    let quads = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/cube_quads.obj");
    let on_quads = |weights: &str| {
        let o = beltrami(&[
            "smooth",
            s(&quads),
            s(&dir.path().join("quads.obj")),
            "--weights",
            weights,
            "--summation",
            "scatter",
            "--iterations",
            "2",
            "--force",
        ]);
        assert!(o.status.success());
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    let said = on_quads("cotangent");
    assert!(
        said.contains("note: 2 of 2 iterations were summed by rows, not scattered (the mesh has polygon faces)"),
        "{said}"
    );
    let said = on_quads("distance");
    assert!(!said.contains("note:"), "{said}");
    // Where it would change nothing: a usage error, nothing written.
    let refused = dir.path().join("refused.ply");
    for (extra, needed) in [
        (
            &["--update", "once"][..],
            "weights recomputed every iteration",
        ),
        (
            &["--weights", "uniform"][..],
            "cotangent or inverse-distance weights",
        ),
        (&["--method", "taubin"][..], "plain explicit diffusion"),
        (
            &["--weights", "distance", "--normalize", "area"][..],
            "weight-sum normalisation",
        ),
        (
            &["--cotangent-negative", "clamp"][..],
            "negative weights kept",
        ),
    ] {
        let mut args = vec!["smooth", s(&input), s(&refused), "--summation", "scatter"];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}");
        let line = error_line(&o, dir.path());
        assert!(
            line.starts_with(&format!("error: --summation scatter needs {needed};")),
            "{line}"
        );
        assert!(!refused.exists());
    }
}

/// `--pin` numbers the input file's vertices: after a `--repair` that renumbered them
/// (an unused vertex removed) the indices would pin other vertices, so the run is
/// refused, as remesh refuses `--feature-edges`; without a renumbering it runs.
#[test]
fn pin_is_refused_after_a_repair_that_renumbers() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(2);
    let mut positions = vec![glam::DVec3::new(9.0, 9.0, 9.0)];
    positions.extend(sphere.positions.iter().copied());
    let triangles: Vec<[u32; 3]> = sphere
        .faces
        .iter()
        .map(|f| [f[0] + 1, f[1] + 1, f[2] + 1])
        .collect();
    let input = write(
        dir.path(),
        "unused.ply",
        positions,
        beltrami_halfedge::PolygonList::from_triangles(&triangles),
    );
    let out = dir.path().join("out.ply");
    let o = beltrami(&["smooth", s(&input), s(&out), "--repair", "--pin", "5"]);
    assert_eq!(o.status.code(), Some(1), "{o:?}");
    let line = error_line(&o, dir.path());
    assert!(
        line.contains("--repair renumbered the vertices")
            && line.contains("--pin would name other vertices"),
        "{line}"
    );
    assert!(!out.exists());
    let o = beltrami(&["smooth", s(&input), s(&out), "--repair"]);
    assert!(o.status.success(), "{o:?}");
    let clean = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/icosphere_2.ply");
    let o = beltrami(&[
        "smooth",
        s(&clean),
        s(&out),
        "--repair",
        "--pin",
        "5",
        "--force",
    ]);
    assert!(o.status.success(), "{o:?}");
}

/// `--preserve-volume` rescales about one centroid: on a mesh of separate parts it says
/// that the parts keep their volume together and move apart; one part gets no note.
#[test]
fn preserving_the_volume_of_separate_parts_says_how() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = primitives::icosphere(2);
    let n = sphere.positions.len() as u32;
    let mut positions: Vec<glam::DVec3> = sphere
        .positions
        .iter()
        .map(|&p| p - glam::DVec3::X * 3.0)
        .collect();
    positions.extend(sphere.positions.iter().map(|&p| p + glam::DVec3::X * 3.0));
    let mut triangles: Vec<[u32; 3]> = sphere.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
    triangles.extend(sphere.faces.iter().map(|f| [f[0] + n, f[1] + n, f[2] + n]));
    let two = write(
        dir.path(),
        "two.ply",
        positions,
        beltrami_halfedge::PolygonList::from_triangles(&triangles),
    );
    let one = write(
        dir.path(),
        "one.ply",
        sphere.positions.clone(),
        sphere.faces.clone(),
    );
    let out = dir.path().join("out.ply");
    let note =
        "note: --preserve-volume rescales the whole mesh about one centroid: its 2 separate parts";
    for (input, expected) in [(&two, true), (&one, false)] {
        let o = beltrami(&["smooth", s(input), s(&out), "--preserve-volume", "--force"]);
        assert!(o.status.success(), "{o:?}");
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert_eq!(stdout.contains(note), expected, "{stdout}");
    }
}

/// An implicit run whose steps draw the surface together (a time step of 0.8 length²
/// given on a unit sphere, which mean-curvature flow shrinks to a point by t = 0.25)
/// fails in its solver; the error line says why and what to change, and a smaller step
/// runs.
#[test]
fn an_implicit_run_that_collapses_the_surface_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/icosphere_2.ply");
    let out = dir.path().join("out.ply");
    let implicit_area = |lambda: &str| {
        beltrami(&[
            "smooth",
            s(&input),
            s(&out),
            "--method",
            "implicit",
            "--normalize",
            "area",
            "--lambda",
            lambda,
        ])
    };
    let o = implicit_area("0.8");
    assert_eq!(o.status.code(), Some(1), "{o:?}");
    let line = error_line(&o, dir.path());
    assert!(
        line.contains("the steps may have drawn the surface together")
            && line.contains("--lambda is a time step in length², here 0.8")
            && line.contains("give a smaller --lambda"),
        "{line}"
    );
    assert!(!out.exists());
    let o = implicit_area("0.01");
    assert!(o.status.success(), "{o:?}");
}
