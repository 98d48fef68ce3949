//! A reduced study (small surfaces, few iterations) run end to end.

use std::sync::Arc;

use beltrami_halfedge::HalfedgeId;
use beltrami_study::{CSV_HEADER, StudyConfig, Verdict, run_study, write_study};
use beltrami_surfaces::Size;
use beltrami_weights::{WeightContext, WeightRegistry, WeightScheme};

/// A plug-in scheme the study has never heard of.
struct Squared;
impl WeightScheme for Squared {
    fn name(&self) -> &str {
        "inverse-squared"
    }
    fn weight(&self, ctx: &WeightContext<'_>, h: HalfedgeId) -> f64 {
        let d = ctx.edge_length(h) + 1e-12;
        1.0 / (d * d)
    }
}

fn small_config(registry: &WeightRegistry) -> StudyConfig {
    let mut config = StudyConfig::paper(registry);
    config.size = Size::Small;
    config.iterations = vec![2, 5, 10];
    config.seeds = 1;
    config
}

/// Rounds every number of a CSV line to 3 significant digits (times are dropped:
/// they differ between runs).
fn rounded(csv: &str) -> String {
    csv.lines()
        .map(|line| {
            line.split(',')
                .enumerate()
                .map(|(i, field)| {
                    if i == 3 && field != "time_s" {
                        return "t".to_string();
                    }
                    match field.parse::<f64>() {
                        Ok(x) if field.contains('e') || field.contains('.') => format!("{x:.3e}"),
                        _ => field.to_string(),
                    }
                })
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn reduced_study_writes_everything_and_includes_plug_in_schemes() {
    let mut registry = WeightRegistry::with_builtins();
    registry.register(Squared).unwrap();
    let config = small_config(&registry);
    let mut runs = Vec::new();
    let results = run_study(&config, &mut |p| {
        if let beltrami_study::Progress::RunStarted(s, w, n) = p {
            runs.push((s.to_string(), w.to_string(), n));
        }
    })
    .unwrap();
    // One run per surface and scheme, each to the largest iteration count, plus the
    // counter-measures: plain, Taubin, HC on the F-lens; and the volume rescale too on
    // the sphere and the block.
    assert_eq!(runs.len(), 4 * 4 + 4 + 5 + 5);
    assert!(runs.iter().any(|r| r.0 == "flens" && r.1 == "cotangent/hc"));
    assert!(
        !runs
            .iter()
            .any(|r| r.0 == "flens" && r.1 == "cotangent/volume")
    );
    assert!(runs.iter().all(|r| r.2 == 10));
    assert!(runs.iter().any(|r| r.1 == "inverse-squared"));

    let dir = tempfile::tempdir().unwrap();
    let written = write_study(&results, dir.path()).unwrap();
    // 4 surfaces × (1 input + 4 schemes × 3 iterations).
    assert_eq!(written.rows.len(), 4 * (1 + 4 * 3));
    for name in ["results.csv", "results.json", "report.md"] {
        let len = std::fs::metadata(dir.path().join(name)).unwrap().len();
        assert!(len > 100, "{name} is {len} bytes");
    }
    // The worked example of `study --input` on the noisy block: its own report, and a
    // section whose best counts beat the noisy input, with `smooth`'s defaults beside.
    let scan = results
        .scan
        .as_ref()
        .expect("the block is studied as a given surface");
    assert_eq!(scan.best.len(), 3 * 4, "paper schemes × methods");
    let input_rms = scan.baseline().rms.unwrap();
    assert!(scan.best.iter().all(|b| b.rms < input_rms));
    assert!(dir.path().join("scan/report.md").is_file());
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    let section = report
        .split("## The study on a given surface")
        .nth(1)
        .expect("the section");
    assert!(section.contains("scan/report.md") && section.contains("`smooth`'s defaults"));
    for f in &written.figures {
        let files: Vec<String> = if f.path.ends_with(".png") {
            vec![f.path.clone()]
        } else {
            vec![format!("{}.svg", f.path), format!("{}.png", f.path)]
        };
        for file in files {
            let len = std::fs::metadata(dir.path().join(&file)).unwrap().len();
            assert!(len > 1000, "{file} is {len} bytes");
        }
    }
    // The paper's figures are there: RMS, time, radius, volume, boundary, profiles, renders.
    for stem in [
        "plots/rms_flens",
        "plots/time_sphere",
        "plots/radius_sphere",
        "plots/radius_golfball",
        "plots/volume_block",
        "plots/boundary_flens",
        "plots/rings_flens",
        "plots/profile_flens",
        "plots/profile_block",
        "plots/dihedral_block",
        "renders/flens.png",
        "renders/golfball.png",
    ] {
        assert!(
            written.figures.iter().any(|f| f.path == stem),
            "missing {stem}"
        );
    }
    assert!(
        written
            .figures
            .iter()
            .any(|f| f.path == "renders/golfball_valence5.png")
    );
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(report.contains("inverse-squared"));
    // Remeshing, timing and the closed-form radius are in the report.
    for heading in [
        "## Remeshing before smoothing",
        "## Timing",
        "predicted radius, closed form",
    ] {
        assert!(report.contains(heading), "missing {heading}");
    }
    let remeshing = results.remeshing.as_ref().unwrap();
    assert_eq!(remeshing.rows.len(), 4);
    let timings = results.timings.as_ref().unwrap();
    // The paper's three schemes on every surface, with positive medians.
    assert_eq!(timings.rows.len(), 4 * 3);
    assert!(
        timings
            .rows
            .iter()
            .all(|r| r.total_s > 0.0 && r.build_s > 0.0)
    );
    // Timings stay out of the CSV: its header is unchanged.
    assert!(
        !std::fs::read_to_string(dir.path().join("results.csv"))
            .unwrap()
            .contains("build")
    );
    assert!(report.contains("](renders/flens.png)"));
    for f in &written.findings {
        assert!(report.contains(f.claim));
    }
    let csv = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
    assert!(csv.starts_with(CSV_HEADER));
    assert!(csv.contains("flens,inverse-squared,10,"));

    // Smoothing reduces the distance to the clean surface on every surface.
    for s in ["flens", "sphere", "block"] {
        let input = written
            .rows
            .iter()
            .find(|r| r.surface == s && r.scheme == "input")
            .unwrap();
        let cot = written
            .rows
            .iter()
            .find(|r| r.surface == s && r.scheme == "cotangent" && r.iteration == 2)
            .unwrap();
        assert!(cot.rms < input.rms, "{s}: {} !< {}", cot.rms, input.rms);
    }
    // Every metric is finite.
    for r in &written.rows {
        for v in [
            r.rms,
            r.mean,
            r.max,
            r.area_rms,
            r.normal_mean_deg,
            r.normal_rms_deg,
        ] {
            assert!(v.is_finite(), "{r:?}");
        }
    }
    insta::assert_snapshot!("reduced_study_csv", rounded(&csv));

    // The counter-measures, measured and reported.
    let cm = |surface: &str, label: &str| -> Vec<&beltrami_study::Row> {
        results
            .surfaces
            .iter()
            .flat_map(|s| s.countermeasures.iter().map(|m| &m.row))
            .filter(|r| r.surface == surface && r.scheme == format!("cotangent/{label}"))
            .collect()
    };
    assert!(report.contains("## Shrinkage counter-measures"));
    // Mesh quality beside accuracy: every row counts folds and has a smallest angle of a
    // real triangle; weights computed once are run beside plain diffusion.
    assert!(report.contains("## Mesh quality beside accuracy"));
    for r in &written.rows {
        assert!(r.flipped_faces.is_some(), "{r:?}");
        let a = r.min_angle_deg.unwrap();
        assert!(a > 0.0 && a <= 60.0, "{r:?}");
    }
    assert_eq!(cm("block", "once").len(), 3);
    assert_eq!(cm("flens", "once").len(), 3);
    let cm_csv = std::fs::read_to_string(dir.path().join("countermeasures.csv")).unwrap();
    assert!(cm_csv.starts_with(CSV_HEADER));
    assert!(cm_csv.contains("block,cotangent/taubin,10,"));
    // The volume rescale keeps the volume of the noisy input at every observation.
    for surface in ["sphere", "block"] {
        let volume = cm(surface, "volume");
        assert_eq!(volume.len(), 3);
        let first = volume[0].volume.unwrap();
        for r in &volume {
            assert!((r.volume.unwrap() / first - 1.0).abs() < 1e-9, "{r:?}");
        }
        // Plain diffusion loses volume, Taubin and HC much less.
        let last = |label| cm(surface, label)[2].volume.unwrap();
        let lost = |v: f64| (1.0 - v / first).abs();
        assert!(lost(last("hc")) < 0.25 * lost(last("plain")), "{surface}");
        assert!(
            lost(last("taubin")) < 0.25 * lost(last("plain")),
            "{surface}"
        );
    }
    // One cut-off on spheres of several densities: the radii agree far better than with
    // one λ × iterations.
    let units = results.units.as_ref().unwrap();
    assert_eq!(units.rows.len(), 3);
    let spread = |f: fn(&beltrami_study::UnitsRow) -> f64| {
        let v: Vec<f64> = units.rows.iter().map(f).collect();
        v.iter().copied().fold(f64::MIN, f64::max) - v.iter().copied().fold(f64::MAX, f64::min)
    };
    assert!(spread(|r| r.radius_cutoff) < 0.01 * spread(|r| r.radius_fixed));
    for r in &units.rows {
        assert!(
            (r.radius_cutoff - units.expected_radius).abs() < 1e-3,
            "{r:?}"
        );
    }
    assert!(report.contains("## Physical units"));
    // On the open F-lens, HC moves the boundary less than plain diffusion.
    let hc = cm("flens", "hc")[2].boundary_mean.unwrap();
    let plain = cm("flens", "plain")[2].boundary_mean.unwrap();
    assert!(hc < 0.75 * plain, "HC {hc}, plain {plain}");
}

#[test]
fn verdicts_come_from_the_data() {
    let registry = WeightRegistry::with_builtins();
    let mut config = small_config(&registry);
    config.surfaces = vec![beltrami_surfaces::SurfaceKind::Sphere];
    config.iterations = vec![3];
    let results = run_study(&config, &mut |_| {}).unwrap();
    let rows = results.rows();
    let findings = beltrami_study::findings(&rows);
    // Only the sphere was studied: F-lens, block and golf-ball findings are not evaluated.
    for f in &findings {
        let sphere = f.id.starts_with("sphere")
            || f.id == "cotangent_much_slower"
            || f.id == "distance_as_fast_as_uniform"
            || f.id == "distance_is_the_compromise";
        assert_eq!(
            f.verdict == Verdict::NotEvaluated,
            !sphere,
            "{}: {:?}",
            f.id,
            f.verdict
        );
    }
    // Flip the data and the verdict flips with it.
    let rms = |rows: &[beltrami_study::Row], s: &str| {
        rows.iter()
            .find(|r| r.scheme == s && r.iteration == 3)
            .unwrap()
            .rms
    };
    let before = findings
        .iter()
        .find(|f| f.id == "sphere_rms_cotangent_best")
        .unwrap()
        .verdict;
    let mut swapped = rows.clone();
    let (u, c) = (rms(&rows, "uniform"), rms(&rows, "cotangent"));
    for r in &mut swapped {
        if r.iteration == 3 && r.scheme == "uniform" {
            r.rms = c.min(u) * 0.5;
        }
    }
    let after = beltrami_study::findings(&swapped)
        .into_iter()
        .find(|f| f.id == "sphere_rms_cotangent_best")
        .unwrap()
        .verdict;
    assert_eq!(after, Verdict::Contradicted);
    assert_ne!(before, Verdict::NotEvaluated);
}

#[test]
fn several_seeds_give_spreads_optima_and_the_early_plot() {
    let mut registry = WeightRegistry::with_builtins();
    registry.register(Squared).unwrap();
    let mut config = small_config(&registry);
    config.surfaces = vec![beltrami_surfaces::SurfaceKind::FLens];
    config.iterations = vec![20, 40];
    config.seeds = 2;
    config.countermeasure_scheme = None;
    config.edge_comparison = None;
    let results = run_study(&config, &mut |_| {}).unwrap();
    let rows = results.all_seed_rows();
    // Seed 2 runs the paper's three schemes only.
    let seed2: Vec<_> = rows.iter().filter(|r| r.seed == 2).collect();
    assert_eq!(seed2.len(), 1 + 3 * 2);
    assert!(seed2.iter().all(|r| r.scheme != "inverse-squared"));
    assert_eq!(rows.iter().filter(|r| r.seed == 1).count(), 1 + 4 * 2);
    // The seeds' inputs differ, so their RMS differs.
    let input = |seed: u64| {
        rows.iter()
            .find(|r| r.seed == seed && r.scheme == "input")
            .unwrap()
            .rms
    };
    assert!((input(1) - input(2)).abs() > 1e-9);
    // The RMS is observed at every iteration from 0 to EARLY_ITERATIONS.
    let curve = &results.surfaces[0].rms_curve;
    for it in 0..=beltrami_study::EARLY_ITERATIONS {
        let scheme = if it == 0 { "input" } else { "cotangent" };
        assert_eq!(
            curve
                .iter()
                .filter(|p| p.scheme == scheme && p.iteration == it)
                .count(),
            2,
            "iteration {it}"
        );
    }
    // On the F-lens the optimum lies at a few iterations, far below the input's RMS and
    // below the RMS at 40 iterations.
    let optima = beltrami_study::optima(curve);
    let cot = optima.iter().find(|o| o.scheme == "cotangent").unwrap();
    assert!(cot.iterations.1 < 20, "{cot:?}");
    assert_eq!(cot.rms.n, 2);
    assert!(cot.rms.mean < 0.5 * cot.input_rms.mean, "{cot:?}");
    let dir = tempfile::tempdir().unwrap();
    let written = write_study(&results, dir.path()).unwrap();
    assert_eq!(written.rows, rows);
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(report.contains("## Recommendation"));
    assert!(report.contains("## The RMS-optimal iteration count"));
    assert!(report.contains("| noise seeds | 2 (1, 2)"));
    assert!(report.contains("Cotangent normalisation"));
    assert!(dir.path().join("plots/rms_early_flens.png").exists());
    // The plots draw the mean over the seeds with their range: the caption says so, and
    // the range's bounds are left out of the legend.
    let rms = written
        .figures
        .iter()
        .find(|f| f.path == "plots/rms_flens")
        .unwrap();
    assert!(
        rms.caption.contains("mean over the noise seeds"),
        "{}",
        rms.caption
    );
    let svg = std::fs::read_to_string(dir.path().join("plots/rms_flens.svg")).unwrap();
    assert!(svg.contains("cotangent") && !svg.contains("seed range"));
    let csv = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
    let seed_column = CSV_HEADER.split(',').position(|c| c == "seed").unwrap();
    assert!(csv.lines().any(
        |l| l.starts_with("flens,cotangent,40,") && l.split(',').nth(seed_column) == Some("2")
    ));
}

#[test]
fn invalid_configurations_are_errors() {
    let registry = WeightRegistry::with_builtins();
    let mut config = small_config(&registry);
    config.iterations = vec![5, 3];
    let err = run_study(&config, &mut |_| {}).unwrap_err();
    assert_eq!(
        err.to_string(),
        "iteration counts must be strictly ascending"
    );
    config.iterations = vec![];
    assert!(run_study(&config, &mut |_| {}).is_err());
    config.iterations = vec![1];
    config.seeds = 0;
    assert_eq!(
        run_study(&config, &mut |_| {}).unwrap_err().to_string(),
        "the number of noise seeds must be at least 1"
    );
    config.seeds = 1;
    config.schemes = Vec::<Arc<dyn WeightScheme>>::new();
    assert_eq!(
        run_study(&config, &mut |_| {}).unwrap_err().to_string(),
        "no weight scheme selected"
    );
}

#[test]
fn the_area_normalisation_takes_its_step_as_a_share_of_each_runs_limit() {
    let registry = WeightRegistry::with_builtins();
    let mut config = small_config(&registry);
    config.surfaces = vec![beltrami_surfaces::SurfaceKind::Sphere];
    config.timing = false;
    config.remesh = None;
    config.countermeasures = Vec::new();
    config.countermeasure_scheme = None;
    // The weight-sum run reports the limit an area-normalised step would have.
    let results = run_study(&config, &mut |_| {}).unwrap();
    let limit = results.surfaces[0].area_step_limit.unwrap();
    assert!(limit > 0.0 && limit < config.lambda, "{limit}");
    let dir = tempfile::tempdir().unwrap();
    write_study(&results, dir.path()).unwrap();
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(
        report.contains("that limit is sphere") && report.contains("so λ exceeds it on sphere"),
        "no stability sentence"
    );
    assert!(report.contains("predicted radius, closed form"));
    // With the area normalisation λ = 0.8 is 0.8 of each run's largest stable step (a
    // time of 0.8 length² would be far beyond it, above): every scheme runs, and on
    // this near-regular sphere takes about the weight-sum run's step, so it shrinks
    // the sphere about as much.
    let radius = |results: &beltrami_study::StudyResults, scheme: &str| {
        results
            .rows()
            .iter()
            .find(|r| r.scheme == scheme && r.iteration == 10)
            .and_then(|r| r.sphere_radius)
            .unwrap()
    };
    let input = results
        .rows()
        .iter()
        .find(|r| r.scheme == "input")
        .unwrap()
        .sphere_radius
        .unwrap();
    config.normalization = beltrami_weights::Normalization::Area(
        beltrami_halfedge::geometry::VertexAreaKind::MixedVoronoi,
    );
    let area = run_study(&config, &mut |_| {}).unwrap();
    for scheme in ["uniform", "distance", "cotangent"] {
        let (sum_shrink, area_shrink) = (
            input - radius(&results, scheme),
            input - radius(&area, scheme),
        );
        assert!(area_shrink > 0.0 && sum_shrink > 0.0, "{scheme}");
        assert!(
            area_shrink > 0.5 * sum_shrink && area_shrink < 2.0 * sum_shrink,
            "{scheme}: {area_shrink} against {sum_shrink}"
        );
    }
    write_study(&area, dir.path()).unwrap();
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(
        report.contains("| normalisation | vertex area (paper Eq. 6); λ is the fraction of each run's largest stable explicit step (the edge-preservation comparison and the worked example keep weight-sum rows) |"),
        "no normalisation row"
    );
    let json = std::fs::read_to_string(dir.path().join("results.json")).unwrap();
    assert!(
        json.contains("\"normalization\": \"area (mixed)\""),
        "{json:.400}"
    );
    // The closed-form radius is that of weight-sum rows: not shown for area rows.
    assert!(!report.contains("predicted radius, closed form"));
}
