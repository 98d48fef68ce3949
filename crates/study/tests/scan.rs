//! The study of one given surface (`study --input`): the best count against a
//! reference, the numbers without one, the files written and their determinism.

use beltrami_halfedge::{DVec3, MeshData, primitives};
use beltrami_metrics::distance::SurfaceIndex;
use beltrami_study::{
    SCAN_CSV_HEADER, ScanConfig, ScanMethod, ScanResults, ScanSurface, StudyError, TIME_HEADING,
    run_scan, write_scan,
};
use beltrami_surfaces::{NoiseLevel, add_normal_noise};
use beltrami_weights::{Cotangent, Uniform, WeightScheme};
use std::sync::Arc;

/// A level-3 icosphere (642 vertices) and the same with normal noise of 0.2 × the
/// mean edge length.
fn noisy_sphere() -> (MeshData, MeshData) {
    let clean = primitives::icosphere(3);
    let mesh = clean.mesh().unwrap();
    let (noisy, _) = add_normal_noise(
        &mesh,
        &clean.positions,
        NoiseLevel::RelativeToMeanEdge(0.2),
        7,
    )
    .unwrap();
    let noisy = MeshData::new(noisy, clean.faces.clone());
    (noisy, clean)
}

fn small_config() -> ScanConfig {
    let schemes: Vec<Arc<dyn WeightScheme>> = vec![Arc::new(Uniform), Arc::new(Cotangent)];
    ScanConfig::default()
        .schemes(schemes)
        .max_iterations(30)
        .implicit_steps(vec![0.5, 2.0, 8.0])
}

fn with_reference() -> ScanResults {
    let (noisy, clean) = noisy_sphere();
    run_scan(
        ScanSurface::new("noisy.ply", noisy).unwrap(),
        Some(ScanSurface::new("clean.ply", clean).unwrap()),
        &small_config(),
        &mut |_| {},
    )
    .unwrap()
}

fn rms_to(reference: &MeshData, positions: &[DVec3]) -> f64 {
    let index = SurfaceIndex::new(&reference.mesh().unwrap(), &reference.positions).unwrap();
    let d = index.distances(positions).unwrap();
    (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt()
}

#[test]
fn with_a_reference_the_best_count_smooths_and_beats_the_input() {
    let results = with_reference();
    let input_rms = results.baseline().rms.unwrap();
    assert_eq!(results.baseline().iteration, 0);
    assert_eq!(results.best.len(), 2 * 4, "one best per scheme and method");
    for b in &results.best {
        assert!(b.iteration >= 1, "{b:?}");
        assert!(b.rms < input_rms, "{b:?} against the input's {input_rms}");
        // The best is the smallest RMS of its rows.
        let smallest = results
            .rows_of(&b.scheme, &b.method)
            .filter_map(|r| r.rms)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(b.rms, smallest, "{b:?}");
        assert_eq!(b.file, format!("best-{}-{}.ply", b.scheme, b.method));
    }
    // Plain diffusion removes the noise in a few iterations and then shrinks the
    // sphere: the optimum lies well inside the observed range.
    let plain = results
        .best
        .iter()
        .find(|b| b.scheme == "cotangent" && b.method == "plain")
        .unwrap();
    assert!(plain.iteration < 20 && !plain.at_last_observed, "{plain:?}");
    let thirty = results
        .rows_of("cotangent", "plain")
        .find(|r| r.iteration == 30)
        .unwrap();
    assert!(
        thirty.rms.unwrap() > plain.rms,
        "shrinkage after the optimum"
    );
    assert!(thirty.volume_ratio.unwrap() < 0.99, "{thirty:?}");
    // The best row carries the detailed numbers even off the report's counts.
    for b in &results.best {
        let row = results
            .rows_of(&b.scheme, &b.method)
            .find(|r| r.iteration == b.iteration && r.step == b.step)
            .unwrap();
        assert!(row.removed_sq.is_some_and(|sq| sq > 0.0), "{row:?}");
    }
}

#[test]
fn the_best_mesh_files_hold_the_reported_rms() {
    let results = with_reference();
    let (_, clean) = noisy_sphere();
    let dir = tempfile::tempdir().unwrap();
    let written = write_scan(&results, dir.path()).unwrap();
    for b in &results.best {
        assert!(written.files.contains(&b.file));
        let mesh = beltrami_io::read_mesh(dir.path().join(&b.file)).unwrap();
        assert_eq!(mesh.faces, results.input.data.faces, "the input's faces");
        let rms = rms_to(&clean, &mesh.positions);
        assert_eq!(rms, b.rms, "{}", b.file);
    }
    let csv = std::fs::read_to_string(dir.path().join("results.csv")).unwrap();
    assert!(csv.starts_with(SCAN_CSV_HEADER));
    assert_eq!(csv.lines().count(), 1 + results.rows.len());
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(report.contains("## Recommendation"), "{report}");
    assert!(report.contains("## Best iteration count per scheme and method"));
    for b in &results.best {
        assert!(report.contains(&format!("`{}`", b.file)), "{}", b.file);
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("results.json")).unwrap()).unwrap();
    assert_eq!(json["best"].as_array().unwrap().len(), results.best.len());
    assert_eq!(json["rows"].as_array().unwrap().len(), results.rows.len());
}

#[test]
fn without_a_reference_there_is_no_best_but_shrinkage_and_residual_numbers() {
    let (noisy, _) = noisy_sphere();
    let results = run_scan(
        ScanSurface::new("noisy.ply", noisy).unwrap(),
        None,
        &small_config(),
        &mut |_| {},
    )
    .unwrap();
    assert!(results.best.is_empty() && results.best_positions.is_empty());
    assert!(
        results
            .rows
            .iter()
            .all(|r| r.rms.is_none() && r.max.is_none())
    );
    // The closed sphere shrinks: the volume ratio falls below 1 with the iterations.
    let plain: Vec<_> = results.rows_of("uniform", "plain").collect();
    assert_eq!(plain.len(), 20 + 2, "1..=20, 25, 30 observed");
    let v = |i: usize| {
        plain
            .iter()
            .find(|r| r.iteration == i)
            .and_then(|r| r.volume_ratio)
            .unwrap()
    };
    assert!(
        v(1) < 1.0 && v(10) < v(1) && v(30) < v(10),
        "{} {} {}",
        v(1),
        v(10),
        v(30)
    );
    // The removed residual grows with smoothing, at the report's counts.
    let sq = |i: usize| {
        plain
            .iter()
            .find(|r| r.iteration == i)
            .and_then(|r| r.removed_sq)
            .unwrap()
    };
    assert!(sq(1) > 0.0 && sq(10) > sq(1), "{} {}", sq(1), sq(10));
    assert!(
        plain
            .iter()
            .find(|r| r.iteration == 7)
            .is_some_and(|r| r.removed_sq.is_none()),
        "the residual is measured at the report's counts only"
    );
    // Shrinkage: the surface moves against its (outward) normals.
    assert!(
        plain
            .iter()
            .find(|r| r.iteration == 30)
            .unwrap()
            .shift
            .unwrap()
            > 0.0
    );
    let dir = tempfile::tempdir().unwrap();
    let written = write_scan(&results, dir.path()).unwrap();
    assert!(
        written.files.iter().all(|f| !f.starts_with("best-")),
        "{written:?}"
    );
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(report.contains("no ground truth"), "{report}");
    assert!(!report.contains("## Recommendation"));
    assert!(report.contains("volume ratio"));
}

#[test]
fn the_files_are_the_same_bytes_on_one_thread_and_many() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let results = pool.install(with_reference);
        let dir = tempfile::tempdir().unwrap();
        let written = write_scan(&results, dir.path()).unwrap();
        let mut files = Vec::new();
        for name in written.files.iter().filter(|f| *f != "timings.csv") {
            let mut bytes = std::fs::read(dir.path().join(name)).unwrap();
            if name == "report.md" {
                let text = String::from_utf8(bytes).unwrap();
                bytes = text.as_bytes()[..text.find(TIME_HEADING).unwrap()].to_vec();
            }
            files.push((name.clone(), bytes));
        }
        files
    };
    let one = run(1);
    let many = run(3);
    assert_eq!(one.len(), many.len());
    for ((a, x), (b, y)) in one.iter().zip(&many) {
        assert_eq!(a, b);
        assert!(x == y, "{a} differs between one thread and three");
    }
}

#[test]
fn bad_inputs_and_settings_are_typed_errors() {
    let points = MeshData::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], Default::default());
    assert!(matches!(
        ScanSurface::new("points.ply", points),
        Err(StudyError::Input(m)) if m.contains("no faces")
    ));
    let mut nan = primitives::icosphere(1);
    nan.positions[3].x = f64::NAN;
    assert!(matches!(
        ScanSurface::new("nan.ply", nan),
        Err(StudyError::Input(m)) if m.contains("vertex 3")
    ));
    for config in [
        ScanConfig::default().lambda(1.5),
        ScanConfig::default().max_iterations(0),
        ScanConfig::default().implicit_steps(vec![1.0, -2.0]),
        ScanConfig::default().implicit_steps(Vec::new()),
        ScanConfig::default().methods(Vec::new()),
        ScanConfig::default().methods(vec![ScanMethod::Hc, ScanMethod::Hc]),
        ScanConfig::default().schemes(Vec::new()),
    ] {
        assert!(
            matches!(config.validate(), Err(StudyError::Config(_))),
            "{config:?}"
        );
    }
    assert!(
        ScanConfig::default()
            .methods(vec![ScanMethod::Plain])
            .implicit_steps(Vec::new())
            .validate()
            .is_ok(),
        "no implicit steps are needed without the implicit method"
    );
    assert!(ScanMethod::from_label("jacobi").is_err());
    assert_eq!(ScanMethod::from_label("hc").unwrap(), ScanMethod::Hc);
}

#[test]
fn a_reference_elsewhere_gives_a_warning() {
    let (noisy, clean) = noisy_sphere();
    let far = MeshData::new(
        clean.positions.iter().map(|p| *p * 10.0).collect(),
        clean.faces.clone(),
    );
    let results = run_scan(
        ScanSurface::new("noisy.ply", noisy).unwrap(),
        Some(ScanSurface::new("far.ply", far).unwrap()),
        &small_config()
            .methods(vec![ScanMethod::Plain])
            .max_iterations(3),
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(results.warnings.len(), 1, "{:?}", results.warnings);
    assert!(results.warnings[0].contains("bounding box"));
}

#[test]
fn the_observed_counts() {
    let c = ScanConfig::default();
    let observed = c.observed_iterations();
    assert_eq!(&observed[..20], &(1..=20).collect::<Vec<_>>()[..]);
    assert_eq!(
        &observed[20..],
        &[
            25, 30, 35, 40, 45, 50, 55, 60, 65, 70, 75, 80, 85, 90, 95, 100
        ]
    );
    assert_eq!(
        ScanConfig::default()
            .max_iterations(23)
            .observed_iterations()
            .last(),
        Some(&23)
    );
    assert_eq!(
        ScanConfig::default()
            .max_iterations(23)
            .detailed_iterations(),
        vec![1, 2, 3, 5, 10, 20, 23]
    );
}
