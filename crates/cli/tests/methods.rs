//! `beltrami smooth` beyond plain diffusion: Taubin, HC, volume rescale, physical time
//! and cut-off, convergence stop — each reachable from the command line, with the
//! library's results and its errors.

mod common;

use common::{beltrami, error_line, s, write};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, PolygonList, primitives};
use beltrami_io::read_mesh;
use beltrami_smooth::{DiffusionTime, Method, SmoothConfig, smooth};
use beltrami_weights::Cotangent;
use insta::assert_snapshot;
use serde_json::Value;

fn sphere(dir: &std::path::Path) -> (std::path::PathBuf, Vec<DVec3>, PolygonList) {
    let p = primitives::icosphere(3);
    let path = write(dir, "sphere.ply", p.positions.clone(), p.faces.clone());
    (path, p.positions, p.faces)
}

fn smoothed(path: &std::path::Path) -> (Vec<DVec3>, PolygonList) {
    let data = read_mesh(path).unwrap();
    (data.positions, data.faces)
}

fn volume(positions: &[DVec3], faces: &PolygonList) -> f64 {
    let mesh =
        beltrami_halfedge::HalfedgeMesh::from_polygons(positions.len(), faces.iter()).unwrap();
    Geometry::new(&mesh, positions).unwrap().volume().unwrap()
}

fn ok(args: &[&str]) -> String {
    let out = beltrami(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn each_method_matches_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let (input, x, faces) = sphere(dir.path());
    let mesh = beltrami_halfedge::HalfedgeMesh::from_polygons(x.len(), faces.iter()).unwrap();
    let out = dir.path().join("out.ply");
    let cases: [(&[&str], SmoothConfig); 4] = [
        (
            &["--method", "taubin", "--lambda", "0.5", "--mu", "-0.53"],
            SmoothConfig::new(0.5, 10).method(Method::Taubin { mu: -0.53 }),
        ),
        (
            &["--method", "hc", "--hc-alpha", "0.2", "--hc-beta", "0.5"],
            SmoothConfig::new(0.8, 10).method(Method::Hc {
                alpha: 0.2,
                beta: 0.5,
            }),
        ),
        (
            &["--preserve-volume"],
            SmoothConfig::new(0.8, 10).preserve_volume(true),
        ),
        (
            &["--cutoff", "0.5"],
            SmoothConfig::new(0.8, 10).duration(DiffusionTime::Cutoff(0.5)),
        ),
    ];
    for (flags, config) in cases {
        let mut args = vec!["smooth", s(&input), s(&out)];
        args.extend_from_slice(flags);
        ok(&args);
        let expected = smooth(&mesh, &x, &Cotangent, config).unwrap().positions;
        let (got, _) = smoothed(&out);
        assert_eq!(got, expected, "{flags:?}");
    }
}

#[test]
fn preserve_volume_keeps_the_volume_and_the_report_says_what_ran() {
    let dir = tempfile::tempdir().unwrap();
    let (input, x, faces) = sphere(dir.path());
    let out = dir.path().join("out.ply");
    let report = dir.path().join("report.json");
    let stdout = ok(&[
        "smooth",
        s(&input),
        s(&out),
        "--iterations",
        "50",
        "--preserve-volume",
        "--report",
        s(&report),
    ]);
    assert!(stdout.contains("explicit + volume"), "{stdout}");
    let (y, _) = smoothed(&out);
    let (v0, v1) = (volume(&x, &faces), volume(&y, &faces));
    // The PLY stores f64: the volume survives the file.
    assert!((v1 / v0 - 1.0).abs() < 1e-9, "{v0} -> {v1}");
    let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["parameters"]["preserve_volume"], true);
    assert_eq!(r["parameters"]["method"], "explicit");
}

#[test]
fn a_cutoff_chooses_the_iterations_and_reports_them() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _, _) = sphere(dir.path());
    let out = dir.path().join("out.ply");
    let report = dir.path().join("report.json");
    let stdout = ok(&[
        "smooth",
        s(&input),
        s(&out),
        "--cutoff",
        "0.5",
        "--report",
        s(&report),
    ]);
    let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let t = r["parameters"]["time"].as_f64().unwrap();
    assert!((t - 0.017_558 * 0.25).abs() < 1e-6, "{t}");
    let planned = r["parameters"]["iterations_planned"].as_u64().unwrap();
    assert_eq!(r["iterations"].as_u64().unwrap(), planned);
    assert!(r["parameters"]["lambda_used"].as_f64().unwrap() <= 0.8);
    assert!(stdout.contains("diffusion time"), "{stdout}");
}

#[test]
fn until_change_stops_early_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let g = primitives::grid(10, 10);
    let x: Vec<DVec3> = g
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| DVec3::new(p.x, p.y, if i % 7 == 3 { 0.3 } else { 0.0 }))
        .collect();
    let input = write(dir.path(), "grid.ply", x, g.faces.clone());
    let out = dir.path().join("out.ply");
    let report = dir.path().join("report.json");
    let stdout = ok(&[
        "smooth",
        s(&input),
        s(&out),
        "--weights",
        "uniform",
        "--update",
        "once",
        "--iterations",
        "100000",
        "--until-change",
        "1e-6",
        "--report",
        s(&report),
    ]);
    assert!(stdout.contains("converged"), "{stdout}");
    let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["stop"], "converged");
    assert!(r["iterations"].as_u64().unwrap() < 100_000);
}

#[test]
fn bad_method_parameters_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _, _) = sphere(dir.path());
    let g = primitives::grid(3, 3);
    let open = write(dir.path(), "grid.ply", g.positions.clone(), g.faces.clone());
    let out = dir.path().join("out.ply");
    // A bad value or combination of options is a usage error (exit 2) that does not
    // start with the input's path; a mesh that does not suit the options is exit 1.
    let run = |extra: &[&str], input: &std::path::Path, code: i32| {
        let mut args = vec!["smooth", s(input), s(&out)];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(code), "{extra:?}");
        assert!(!out.exists(), "{extra:?} wrote an output");
        error_line(&o, dir.path())
    };
    assert_snapshot!(run(&["--method", "taubin", "--mu", "-0.1"], &input, 2), @"error: Taubin's mu = -0.1 with lambda = 0.6307 is invalid: the pass band 1/lambda + 1/mu must be positive, i.e. mu < -lambda; with --mu -0.1, take --lambda below 0.1 (see 'beltrami --help')");
    assert_snapshot!(run(&["--method", "taubin", "--lambda", "0.8"], &input, 2), @"error: Taubin's mu = -0.869565 with lambda = 0.8 is invalid: the highest frequency would grow: (1 - 2 lambda)(1 - 2 mu) must exceed -1; leave --lambda out for Taubin's classic pair (lambda 0.6307, mu -0.6732, pass band 0.1) (see 'beltrami --help')");
    assert_snapshot!(run(&["--method", "hc", "--hc-alpha", "2"], &input, 2), @"error: HC parameters must lie in [0, 1], got alpha = 2, beta = 0.6 (see 'beltrami smooth --help')");
    assert_snapshot!(run(&["--preserve-volume"], &open, 1), @"error: grid.ply: volume preservation needs a closed mesh, this one has 1 boundary loop; use the HC or Taubin method on open patches");
    assert_snapshot!(run(&["--time", "-1"], &input, 2), @"error: invalid diffusion time: the time must be finite and >= 0, got -1 (see 'beltrami smooth --help')");
    assert_snapshot!(run(&["--cutoff", "-1"], &input, 2), @"error: invalid diffusion time: the cut-off must be finite and >= 0, got -1 (see 'beltrami smooth --help')");
    assert_snapshot!(run(&["--cutoff", "1e300"], &input, 2), @"error: invalid diffusion time: the cut-off must be finite and >= 0 and give a finite time, got 1e300 (time inf) (see 'beltrami smooth --help')");
    assert_snapshot!(run(&["--method", "hc", "--cutoff", "1"], &input, 2), @"error: --time and --cutoff apply to plain diffusion (--method explicit or implicit), not to --method hc (see 'beltrami --help')");
    assert_snapshot!(run(&["--until-change", "0"], &input, 2), @"error: the convergence threshold must be positive and finite, got 0 (see 'beltrami smooth --help')");
    // Options that the method would ignore are refused, not dropped silently.
    assert_snapshot!(run(&["--mu", "-0.9"], &input, 2), @"error: --mu applies to --method taubin only, not to --method explicit (see 'beltrami --help')");
    assert_snapshot!(run(&["--method", "taubin", "--hc-alpha", "0.2"], &input, 2), @"error: --hc-alpha applies to --method hc only, not to --method taubin (see 'beltrami --help')");
    assert_snapshot!(run(&["--solver", "cholesky"], &input, 2), @"error: --solver applies to --method implicit only, not to --method explicit (see 'beltrami --help')");
    assert_eq!(
        run(&["--vertex-area", "barycentric"], &input, 2),
        "error: --vertex-area applies to --normalize area only (weight-sum rows use no vertex area) (see 'beltrami --help')"
    );
    // An explicit area-normalised step beyond the stability limit, with the limit.
    let o = run(&["--normalize", "area", "--lambda", "0.8"], &input, 2);
    assert!(o.starts_with("error: lambda 0.8 is not a stable explicit step with area normalisation on this mesh: the largest stable step is "), "{o}");
    // A cut-off in the wrong unit: the plan is refused before it runs.
    let o = run(&["--cutoff", "10000"], &input, 2);
    assert!(o.contains("more than --max-iterations 1000000"), "{o}");
}

#[test]
fn taubin_runs_with_its_defaults_and_negative_values_are_values() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _, _) = sphere(dir.path());
    let out = dir.path().join("out.ply");
    let o = beltrami(&["smooth", s(&input), s(&out), "--method", "taubin"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8(o.stdout).unwrap();
    assert!(stdout.contains("taubin (mu -0.673156)"), "{stdout}");
    assert!(stdout.contains("lambda 0.6307"), "{stdout}");
    // A negative λ reaches the range check instead of being taken for an option.
    let o = beltrami(&["smooth", s(&input), s(&out), "--lambda", "-0.5", "--force"]);
    assert_eq!(o.status.code(), Some(2));
    assert_snapshot!(error_line(&o, dir.path()), @"error: lambda must be in (0, 1] with weight-sum normalisation, got -0.5 (see 'beltrami smooth --help')");
}

#[test]
fn a_time_of_area_normalised_steps_finds_its_own_stable_step() {
    let dir = tempfile::tempdir().unwrap();
    let (input, _, _) = sphere(dir.path());
    let out = dir.path().join("out.ply");
    // λ 0.8 is far beyond the stability limit; --time picks the iterations itself.
    let o = beltrami(&[
        "smooth",
        s(&input),
        s(&out),
        "--normalize",
        "area",
        "--time",
        "0.001",
        "--verbose",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (y, _) = smoothed(&out);
    assert!(
        y.iter()
            .all(|p| p.is_finite() && (p.length() - 1.0).abs() < 0.05)
    );
    let stderr = String::from_utf8(o.stderr).unwrap();
    assert!(stderr.contains("note: planned "), "{stderr}");
}

#[test]
fn implicit_steps_match_the_library_and_take_a_physical_time() {
    use beltrami_halfedge::geometry::VertexAreaKind;
    use beltrami_smooth::{ImplicitSolver, WeightUpdate};
    let implicit = |t: f64, steps| {
        SmoothConfig::new(t, steps).method(Method::implicit(ImplicitSolver::Cholesky))
    };
    use beltrami_weights::{LaplacianOptions, Normalization};

    let dir = tempfile::tempdir().unwrap();
    let (input, x, faces) = sphere(dir.path());
    let mesh = beltrami_halfedge::HalfedgeMesh::from_polygons(x.len(), faces.iter()).unwrap();
    let out = dir.path().join("out.ply");
    let report = dir.path().join("report.json");
    // λ = 5 would blow up an explicit step; the implicit one is stable. The default
    // solver is conjugate gradient (tolerance 1e-10); `--solver cholesky` factorises.
    let cg = ImplicitSolver::conjugate_gradient();
    for (flags, solver) in [
        (&[][..], cg),
        (&["--solver", "cg"][..], cg),
        (&["--solver", "cholesky"][..], ImplicitSolver::Cholesky),
    ] {
        let mut args = vec![
            "smooth",
            s(&input),
            s(&out),
            "--method",
            "implicit",
            "--lambda",
            "5",
            "--iterations",
            "3",
            "--update",
            "once",
            "--report",
            s(&report),
        ];
        args.extend_from_slice(flags);
        ok(&args);
        let expected = smooth(
            &mesh,
            &x,
            &Cotangent,
            implicit(5.0, 3)
                .update(WeightUpdate::Once)
                .method(Method::implicit(solver)),
        )
        .unwrap();
        assert_eq!(smoothed(&out).0, expected.positions, "{flags:?}");
        let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
        let figures = &r["implicit"];
        assert_eq!(r["iterations"], 3, "{flags:?}");
        match solver {
            ImplicitSolver::Cholesky => {
                assert_eq!(figures["solver"], "cholesky");
                // Frozen weights: one factorisation serves the three steps.
                assert_eq!(figures["numeric_factorizations"], 1);
                assert!(figures["factor_nonzeros"].as_u64().unwrap() > 0);
                assert_eq!(figures["cg_iterations"], 0);
            }
            _ => {
                assert_eq!(figures["solver"], "cg", "{flags:?}");
                assert_eq!(figures["numeric_factorizations"], 0);
                assert_eq!(figures["factor_nonzeros"], 0);
                let iterations = figures["cg_iterations"].as_u64().unwrap();
                assert!(iterations > 0, "{flags:?}");
                assert_eq!(
                    iterations as usize,
                    expected.report.solver.as_ref().unwrap().cg_iterations
                );
                // Every step met the tolerance, and the result agrees with the exact
                // solve.
                for step in &expected.report.steps {
                    assert!(step.solve.unwrap().cg_iterations > 0);
                    assert!(step.solve.unwrap().residual.unwrap() <= 1e-10, "{step:?}");
                }
                let exact = smooth(
                    &mesh,
                    &x,
                    &Cotangent,
                    implicit(5.0, 3).update(WeightUpdate::Once),
                )
                .unwrap()
                .positions;
                for (a, b) in expected.positions.iter().zip(&exact) {
                    assert!((*a - *b).length() < 1e-8, "{a} vs {b}");
                }
            }
        }
    }

    // One backward-Euler step of the cut-off's time, area-normalised cotangent: close to
    // the mean-curvature flow's radius √(1 − 4t).
    ok(&[
        "smooth",
        s(&input),
        s(&out),
        "--method",
        "implicit",
        "--cutoff",
        "0.5",
        "--normalize",
        "area",
        "--vertex-area",
        "barycentric",
    ]);
    let area =
        LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::Barycentric));
    let t = DiffusionTime::Cutoff(0.5).time();
    let expected = smooth(
        &mesh,
        &x,
        &Cotangent,
        implicit(t, 1).laplacian(area).method(Method::implicit(cg)),
    )
    .unwrap()
    .positions;
    let (y, _) = smoothed(&out);
    assert_eq!(y, expected);
    let r = y.iter().map(|p| p.length()).sum::<f64>() / y.len() as f64;
    assert!((r - (1.0 - 4.0 * t).sqrt()).abs() < 2e-3, "{r}");

    // Without --normalize a time takes the weight-sum operator, as an explicit run
    // does: steps of at most λ (0.8 by default) that add up to the time.
    let report = dir.path().join("time.json");
    ok(&[
        "smooth",
        s(&input),
        s(&out),
        "--method",
        "implicit",
        "--time",
        "0.01",
        "--report",
        s(&report),
        "--force",
    ]);
    let expected = smooth(
        &mesh,
        &x,
        &Cotangent,
        SmoothConfig::new(0.8, 1)
            .duration(DiffusionTime::Time(0.01))
            .method(Method::implicit(cg)),
    )
    .unwrap();
    let (y, _) = smoothed(&out);
    assert_eq!(y, expected.positions);
    let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    let planned = expected.report.config.iterations;
    assert!(planned > 1, "{planned}");
    assert_eq!(r["iterations"], planned);
    assert_eq!(r["parameters"]["normalize"], "sum");
    assert!(r["parameters"]["lambda_used"].as_f64().unwrap() <= 0.8);
    // The explicit run for the same time lands on nearly the same radius: both follow
    // the same diffusion.
    let explicit_out = dir.path().join("explicit.ply");
    ok(&["smooth", s(&input), s(&explicit_out), "--time", "0.01"]);
    let radius = |p: &[DVec3]| p.iter().map(|p| p.length()).sum::<f64>() / p.len() as f64;
    let (z, _) = smoothed(&explicit_out);
    let (ri, re) = (radius(&y), radius(&z));
    assert!(
        ri < 1.0 && (ri - re).abs() < 0.05 * (1.0 - re),
        "{ri} vs {re}"
    );

    // --until-change stops an implicit run as it stops an explicit one.
    ok(&[
        "smooth",
        s(&input),
        s(&out),
        "--method",
        "implicit",
        "--lambda",
        "50",
        "--iterations",
        "1000",
        "--until-change",
        "1e-3",
        "--report",
        s(&report),
        "--force",
    ]);
    let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
    assert_eq!(r["stop"], "converged");
    let done = r["iterations"].as_u64().unwrap();
    assert!(done > 1 && done < 1000, "{done}");
    let last = &r["steps"][done as usize - 1];
    assert!(last["max_displacement"].as_f64().unwrap() <= 1e-3);
}

#[test]
fn implicit_output_does_not_depend_on_the_thread_count() {
    // Level 5: 10 242 vertices, three parallel chunks of 4096 rows, so two threads
    // really split the conjugate-gradient sums and the assembly.
    let dir = tempfile::tempdir().unwrap();
    let p = primitives::icosphere(5);
    let noisy: Vec<DVec3> = p
        .positions
        .iter()
        .map(|&x| x * (1.0 + 0.01 * (7.0 * x.x).sin() * (5.0 * x.y).cos()))
        .collect();
    let input = write(dir.path(), "sphere.ply", noisy, p.faces);
    let output = dir.path().join("out.ply");
    let bytes = |threads: usize, extra: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_beltrami"))
            .args(["smooth", s(&input), s(&output), "--method", "implicit"])
            .args(["--iterations", "3", "--update", "once"])
            .args(extra)
            .env("RAYON_NUM_THREADS", threads.to_string())
            .output()
            .expect("the binary runs");
        assert!(
            out.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        std::fs::read(&output).unwrap()
    };
    for extra in [
        &[][..],
        &["--normalize", "area", "--lambda", "1e-3"][..],
        &["--solver", "cholesky"][..],
    ] {
        assert!(
            bytes(1, extra) == bytes(2, extra),
            "{extra:?}: 1 and 2 threads differ"
        );
    }
}

/// An implicit step so long that conjugate gradient cannot finish it (λ = 0.8 given is a
/// diffusion time of 0.8 length² with area normalisation: the unit sphere shrinks to a
/// point) stops with exit 1, no output, and a line that says what to change.
#[test]
fn an_implicit_step_that_does_not_converge_says_what_to_change() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.ply");
    let output = dir.path().join("out.ply");
    let generated = beltrami(&["generate", "sphere", s(&input), "--level", "3"]);
    assert!(generated.status.success());
    let implicit_area = |extra: &[&str]| {
        let mut args = vec!["smooth", s(&input), s(&output), "--method", "implicit"];
        args.extend_from_slice(&["--normalize", "area"]);
        args.extend_from_slice(extra);
        beltrami(&args)
    };
    let out = implicit_area(&["--lambda", "0.8"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(!output.exists());
    let line = error_line(&out, dir.path());
    assert!(
        line.starts_with("error: sphere.ply: conjugate gradient did not converge in iteration "),
        "{line}"
    );
    assert!(
        line.ends_with("; the steps may have drawn the surface together until its system degenerated (with --normalize area, --lambda is a time step in length², here 0.8; mean-curvature flow shrinks a unit sphere to a point by t = 0.25): give a smaller --lambda, or --update once to keep the first step's weights"),
        "{line}"
    );
    // The smaller step the line suggests goes through.
    let out = implicit_area(&["--lambda", "1e-3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn area_normalisation_without_lambda_takes_a_share_of_the_stable_step() {
    use beltrami_halfedge::geometry::VertexAreaKind;
    use beltrami_smooth::area_step;
    use beltrami_weights::{LaplacianOptions, Normalization};
    let dir = tempfile::tempdir().unwrap();
    let (input, x, faces) = sphere(dir.path());
    let mesh = beltrami_halfedge::HalfedgeMesh::from_polygons(x.len(), faces.iter()).unwrap();
    let out = dir.path().join("out.ply");
    let report = dir.path().join("report.json");
    let area =
        LaplacianOptions::new().normalization(Normalization::Area(VertexAreaKind::MixedVoronoi));
    let config = SmoothConfig::new(0.8, 10).laplacian(area);
    let limit = area_step(&mesh, &x, &Cotangent, &config, 1.0)
        .unwrap()
        .unwrap();
    // The limit is the one a step given directly is refused beyond.
    let o = beltrami(&[
        "smooth",
        s(&input),
        s(&out),
        "--normalize",
        "area",
        "--lambda",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let line = error_line(&o, dir.path());
    let said: f64 = line
        .split("the largest stable step is ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!((said / limit - 1.0).abs() < 1e-5, "{said} {limit}");
    let mean_move = |y: &[DVec3]| {
        x.iter()
            .zip(y)
            .map(|(a, b)| (*a - *b).length())
            .sum::<f64>()
            / x.len() as f64
    };
    // The weight-sum default's smoothing, for comparison.
    ok(&["smooth", s(&input), s(&out), "--force"]);
    let sum_move = mean_move(&smoothed(&out).0);
    for (method, fraction) in [
        ("explicit", 0.8),
        ("implicit", 0.8),
        ("taubin", 0.6307),
        ("hc", 0.8),
    ] {
        let o = beltrami(&[
            "smooth",
            s(&input),
            s(&out),
            "--normalize",
            "area",
            "--method",
            method,
            "--report",
            s(&report),
            "--force",
        ]);
        assert!(
            o.status.success(),
            "{method}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let stderr = String::from_utf8(o.stderr).unwrap();
        assert!(
            stderr.contains("note: --normalize area without --lambda: lambda ")
                && stderr.contains(&format!(", {fraction} of the largest stable explicit step")),
            "{method}: {stderr}"
        );
        let r: Value = serde_json::from_slice(&std::fs::read(&report).unwrap()).unwrap();
        let used = r["parameters"]["lambda_used"].as_f64().unwrap();
        let expected = area_step(&mesh, &x, &Cotangent, &config, fraction)
            .unwrap()
            .unwrap();
        assert_eq!(used, expected, "{method}");
        if method == "taubin" {
            // μ and the pass band scale with λ: Taubin's classic pair times the limit.
            let mu = r["parameters"]["mu"].as_f64().unwrap();
            assert!((mu / limit + 0.6732).abs() < 1e-4, "{mu} {limit}");
        }
        // Plain diffusion shrinks the sphere about as much as the weight-sum default
        // (on this near-regular mesh the two steps are the same); Taubin and HC keep it.
        let (y, _) = smoothed(&out);
        let moved = mean_move(&y);
        let radii = || y.iter().map(|p| p.length());
        if matches!(method, "explicit" | "implicit") {
            assert!(radii().all(|r| r > 0.85 && r < 0.95), "{method}");
            assert!(
                moved > 0.8 * sum_move && moved < 1.25 * sum_move,
                "{method}: {moved} against {sum_move}"
            );
        } else {
            assert!(radii().all(|r| (r - 1.0).abs() < 0.01), "{method}");
            assert!(moved > 0.0 && moved < 0.2 * sum_move, "{method}: {moved}");
        }
    }
    // A Taubin μ given alone is a step of its own: the pair is checked against the
    // limit (it would amplify), with the classic pair that fits.
    let o = beltrami(&[
        "smooth",
        s(&input),
        s(&out),
        "--normalize",
        "area",
        "--method",
        "taubin",
        "--mu",
        "-0.53",
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let line = error_line(&o, dir.path());
    assert!(
        line.contains("(1 - 2 lambda/L)(1 - 2 mu/L) must exceed -1")
            && line.contains("Taubin's classic pair is --lambda "),
        "{line}"
    );
    // A run refused for another reason says only that (no note first).
    let o = beltrami(&[
        "smooth",
        s(&input),
        s(&out),
        "--normalize",
        "area",
        "--hc-alpha",
        "2",
        "--method",
        "hc",
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        !String::from_utf8(o.stderr.clone())
            .unwrap()
            .contains("note:")
    );
    // A λ given is the caller's: no note, and beyond the limit still refused.
    let o = beltrami(&[
        "smooth",
        s(&input),
        s(&out),
        "--normalize",
        "area",
        "--lambda",
        "1e-4",
        "--force",
    ]);
    assert!(o.status.success());
    assert!(
        !String::from_utf8(o.stderr)
            .unwrap()
            .contains("note: --normalize area")
    );
}
