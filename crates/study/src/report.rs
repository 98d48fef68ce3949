//! Writing a study: results.csv, results.json, plots, renders and report.md.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::closed_form::{predicted_radius, weighted_mean_edge_sq};
use crate::error::StudyError;
use crate::figures::{Figure, shown_iteration, write_figures};
use crate::findings::{
    Comparison, Finding, FindingsContext, MedianTimeRatios, REL_TOL, Spread, TIMED_SURFACES,
    compare, findings_with, sig,
};
use crate::optimum::{Optimum, optima};
use crate::results::{Row, to_csv};
use crate::run::{EARLY_ITERATIONS, StudyResults, SurfaceResult};

/// What [`write_study`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// The rows of results.csv (every seed).
    pub rows: Vec<Row>,
    /// The findings of report.md.
    pub findings: Vec<Finding>,
    /// The RMS-optimal iteration count per surface and scheme.
    pub optima: Vec<Optimum>,
    /// The plots and renders.
    pub figures: Vec<Figure>,
}

#[derive(Serialize)]
struct SurfaceInfo<'a> {
    name: &'a str,
    unit: &'a str,
    vertices: usize,
    faces: usize,
    closed: bool,
    noise_sigma: f64,
    ring_profiles: Vec<RingsJson>,
}

#[derive(Serialize)]
struct RingsJson {
    scheme: String,
    iteration: usize,
    /// (ring, vertices, rms) per ring.
    rings: Vec<(u32, usize, f64)>,
}

#[derive(Serialize)]
struct ConfigJson<'a> {
    surfaces: Vec<&'a str>,
    size: String,
    schemes: Vec<&'a str>,
    iterations: &'a [usize],
    lambda: f64,
    noise: String,
    seed: u64,
    seeds: usize,
    boundary: String,
    update: String,
    negative_weights: String,
    /// `sum`, or `area (mixed)` / `area (barycentric)`, where `lambda` is the fraction
    /// of each run's largest stable explicit step.
    normalization: String,
}

#[derive(Serialize)]
struct Json<'a> {
    version: &'static str,
    machine: Machine,
    wall_time_s: f64,
    config: ConfigJson<'a>,
    surfaces: Vec<SurfaceInfo<'a>>,
    findings: &'a [Finding],
    optima: &'a [Optimum],
    rms_curve: Vec<&'a crate::run::RmsPoint>,
    figures: &'a [Figure],
    rows: &'a [Row],
    countermeasure_rows: &'a [Row],
    units: Option<&'a crate::units::UnitsComparison>,
}

#[derive(Serialize)]
struct Machine {
    os: &'static str,
    arch: &'static str,
    threads: usize,
}

fn machine() -> Machine {
    Machine {
        os: std::env::consts::OS,
        arch: std::env::consts::ARCH,
        threads: rayon::current_num_threads(),
    }
}

fn config_json(results: &StudyResults) -> ConfigJson<'_> {
    let c = &results.config;
    ConfigJson {
        surfaces: results.surfaces.iter().map(|s| s.case.clean.name).collect(),
        size: format!("{:?}", c.size).to_lowercase(),
        schemes: c.schemes.iter().map(|s| s.name()).collect(),
        iterations: &c.iterations,
        lambda: c.lambda,
        noise: match c.noise {
            beltrami_surfaces::NoiseLevel::Absolute(s) => format!("sigma = {s} (absolute)"),
            beltrami_surfaces::NoiseLevel::RelativeToMeanEdge(r) => {
                format!("sigma = {r} x mean edge length")
            }
        },
        seed: c.seed,
        seeds: c.seeds,
        boundary: format!("{:?}", c.boundary).to_lowercase(),
        update: format!("{:?}", c.update).to_lowercase(),
        negative_weights: format!("{:?}", c.negative).to_lowercase(),
        normalization: match c.normalization {
            beltrami_weights::Normalization::Area(
                beltrami_halfedge::geometry::VertexAreaKind::Barycentric,
            ) => "area (barycentric)".to_string(),
            beltrami_weights::Normalization::Area(_) => "area (mixed)".to_string(),
            _ => "sum".to_string(),
        },
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> Result<(), StudyError> {
    let path = dir.join(name);
    beltrami_io::write_bytes_atomic(&path, bytes)
        .map_err(|source| StudyError::Write { path, source })
}

fn mkdir(path: &Path) -> Result<(), StudyError> {
    std::fs::create_dir_all(path).map_err(|source| StudyError::CreateDir {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes the study into `dir` (created if needed): `results.csv`, `results.json`,
/// `plots/*.svg|png`, `renders/*.png` and `report.md`. Every file is written atomically.
///
/// # Errors
/// [`StudyError::CreateDir`], [`StudyError::Write`], [`StudyError::Plot`],
/// [`StudyError::Image`] or [`StudyError::Metrics`].
pub fn write_study(results: &StudyResults, dir: &Path) -> Result<Written, StudyError> {
    mkdir(dir)?;
    mkdir(&dir.join("plots"))?;
    mkdir(&dir.join("renders"))?;
    let rows = results.all_seed_rows();
    let findings = findings_with(&rows, &findings_context(results));
    let curve: Vec<crate::run::RmsPoint> = results
        .surfaces
        .iter()
        .flat_map(|s| s.rms_curve.iter().cloned())
        .collect();
    let optima = optima(&curve);
    let figures = write_figures(results, &rows, dir)?;
    if let Some(scan) = &results.scan {
        let scan_dir = dir.join("scan");
        mkdir(&scan_dir)?;
        crate::scan::write_scan(scan, &scan_dir)?;
    }
    write(dir, "results.csv", to_csv(&rows).as_bytes())?;
    let countermeasure_rows: Vec<Row> = results
        .surfaces
        .iter()
        .flat_map(|s| s.countermeasures.iter().map(|m| m.row.clone()))
        .collect();
    if !countermeasure_rows.is_empty() {
        write(
            dir,
            "countermeasures.csv",
            to_csv(&countermeasure_rows).as_bytes(),
        )?;
    }
    let surfaces = results
        .surfaces
        .iter()
        .map(|s| SurfaceInfo {
            name: s.case.clean.name,
            unit: s.case.clean.unit,
            vertices: s.case.mesh.n_vertices(),
            faces: s.case.mesh.n_faces(),
            closed: s.case.mesh.is_closed(),
            noise_sigma: s.case.sigma,
            ring_profiles: s
                .measured
                .iter()
                .filter_map(|m| {
                    m.rings.as_ref().map(|r| RingsJson {
                        scheme: m.row.scheme.clone(),
                        iteration: m.row.iteration,
                        rings: r.rings.iter().map(|g| (g.ring, g.count, g.rms)).collect(),
                    })
                })
                .collect(),
        })
        .collect();
    let json = Json {
        version: env!("CARGO_PKG_VERSION"),
        machine: machine(),
        wall_time_s: results.wall_time_s,
        config: config_json(results),
        surfaces,
        findings: &findings,
        optima: &optima,
        rms_curve: curve.iter().collect(),
        figures: &figures,
        rows: &rows,
        countermeasure_rows: &countermeasure_rows,
        units: results.units.as_ref(),
    };
    let mut text =
        serde_json::to_string_pretty(&json).map_err(|e| StudyError::Config(e.to_string()))?;
    text.push('\n');
    write(dir, "results.json", text.as_bytes())?;
    write(
        dir,
        "report.md",
        markdown(results, &rows, &findings, &figures, &optima).as_bytes(),
    )?;
    Ok(Written {
        rows,
        findings,
        optima,
        figures,
    })
}

/// The study's step and, with the sphere, the mean squared edge length of the clean
/// sphere (per vertex, over its neighbours, then averaged), for the closed-form radius.
fn findings_context(results: &StudyResults) -> FindingsContext {
    let sphere = results
        .surfaces
        .iter()
        .find(|s| s.case.kind == beltrami_surfaces::SurfaceKind::Sphere);
    // The closed form of the findings' evidence is that of weight-sum rows.
    let weight_sum = results.config.normalization == beltrami_weights::Normalization::WeightSum;
    let sphere_mean_edge_sq = sphere.filter(|_| weight_sum).and_then(|s| {
        let mesh = &s.case.mesh;
        let p = &s.case.clean.positions;
        let mut sum = vec![0.0; mesh.n_vertices()];
        let mut count = vec![0usize; mesh.n_vertices()];
        for h in mesh.halfedges() {
            let (a, b) = (mesh.to_vertex(h.twin()), mesh.to_vertex(h));
            sum[a.index()] += p[a.index()].distance_squared(p[b.index()]);
            count[a.index()] += 1;
        }
        let per: Vec<f64> = sum
            .iter()
            .zip(&count)
            .filter(|(_, c)| **c > 0)
            .map(|(s, c)| s / *c as f64)
            .collect();
        (!per.is_empty()).then(|| per.iter().sum::<f64>() / per.len() as f64)
    });
    let median_time_ratios = results.timings.as_ref().map(|t| {
        let pair = |num: &str, den: &str| TIMED_SURFACES.map(|s| t.ratio(s, num, den));
        MedianTimeRatios {
            cotangent_uniform: pair("cotangent", "uniform"),
            cotangent_distance: pair("cotangent", "distance"),
            distance_uniform: pair("distance", "uniform"),
        }
    });
    FindingsContext {
        lambda: results.config.lambda,
        median_time_ratios,
        sphere_mean_edge_sq,
    }
}

fn num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&x.abs()) {
        format!("{x:.5}")
    } else {
        format!("{x:.4e}")
    }
}

fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), num)
}

/// The report: set-up, findings with verdicts, and per surface a table, plots and renders.
fn markdown(
    results: &StudyResults,
    rows: &[Row],
    findings: &[Finding],
    figures: &[Figure],
    optima: &[Optimum],
) -> String {
    let shown = shown_iteration(results);
    let mut s = String::new();
    let _ = writeln!(s, "# Laplace–Beltrami weight schemes compared\n");
    let _ = writeln!(
        s,
        "This report reproduces the comparison of *Comparison of discrete Laplacian-Beltrami operators and their applications in surface metrology* with beltrami {}: each surface gets Gaussian noise along its vertex normals, is smoothed by explicit diffusion x ← x + λ L x with each weight scheme, and is compared with the clean surface after each requested number of iterations. Every number below is computed by `beltrami study`; the verdicts are derived from the data.\n",
        env!("CARGO_PKG_VERSION")
    );
    setup_section(&mut s, results);
    recommendation_section(&mut s, results, rows, optima, shown);
    findings_section(&mut s, findings);
    optimum_section(&mut s, results, rows, optima, shown);
    surface_sections(&mut s, results, rows, figures, shown);
    countermeasure_section(&mut s, results, shown);
    quality_section(&mut s, results, rows, shown);
    if let Some(c) = &results.remeshing {
        crate::remeshing::remesh_section(&mut s, c, &results.config);
    }
    if let Some(t) = &results.timings {
        crate::timing::timing_section(&mut s, t);
    }
    edge_section(&mut s, results);
    if let Some(scan) = &results.scan {
        scan_section(&mut s, scan);
    }
    units_section(&mut s, results);
    differences_section(&mut s, results);
    s
}

/// The set-up: the configuration, the machine and wall time, and one row per surface.
fn setup_section(s: &mut String, results: &StudyResults) {
    let c = config_json(results);
    let m = machine();
    let _ = writeln!(s, "## Set-up\n");
    let _ = writeln!(s, "| parameter | value |\n|---|---|");
    let _ = writeln!(
        s,
        "| surfaces | {} ({} size) |",
        c.surfaces.join(", "),
        c.size
    );
    let _ = writeln!(s, "| weight schemes | {} |", c.schemes.join(", "));
    let _ = writeln!(
        s,
        "| iterations observed | {} (one run per surface and scheme) |",
        c.iterations
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(s, "| λ | {} |", c.lambda);
    let _ = writeln!(
        s,
        "| noise | {} along area-weighted vertex normals |",
        c.noise
    );
    let on_all: Vec<String> = results
        .config
        .seed_schemes()
        .iter()
        .map(|x| x.name().to_string())
        .collect();
    let _ = writeln!(
        s,
        "| noise seeds | {} ({}); {} run on every seed, any other scheme on seed {} only; tables give the mean over the seeds and, in brackets, the range [min–max]; plots draw the mean and, as thin dashed lines, the range; renders and counter-measures use seed {} |",
        c.seeds,
        (0..c.seeds)
            .map(|k| (c.seed.wrapping_add(k as u64)).to_string())
            .collect::<Vec<_>>()
            .join(", "),
        on_all.join(", "),
        c.seed,
        c.seed
    );
    let _ = writeln!(s, "| boundary | {} |", c.boundary);
    let _ = writeln!(s, "| weights computed | {} iteration |", c.update);
    let _ = writeln!(s, "| negative weights | {} |", c.negative_weights);
    let _ = writeln!(
        s,
        "| normalisation | {} |",
        if results.config.normalization == beltrami_weights::Normalization::WeightSum {
            "weight sum (paper Eq. 2)"
        } else {
            "vertex area (paper Eq. 6); λ is the fraction of each run's largest stable explicit step (the edge-preservation comparison and the worked example keep weight-sum rows)"
        }
    );
    let info = results
        .timings
        .as_ref()
        .map_or_else(crate::timing::machine_info, |t| t.machine.clone());
    let _ = writeln!(
        s,
        "| machine | {}, {} {}, {} threads |",
        info.cpu, m.os, m.arch, m.threads
    );
    let _ = writeln!(s, "| commit | {} |", info.commit);
    let _ = writeln!(s, "| load (at the timing) | {} |", info.load_text());
    let _ = writeln!(
        s,
        "| wall time of the study | {:.1} s |\n",
        results.wall_time_s
    );

    let _ = writeln!(
        s,
        "| surface | vertices | faces | closed | unit | noise σ (unit) |\n|---|---|---|---|---|---|"
    );
    for r in &results.surfaces {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.case.clean.name,
            r.case.mesh.n_vertices(),
            r.case.mesh.n_faces(),
            if r.case.mesh.is_closed() { "yes" } else { "no" },
            r.case.clean.unit,
            num(r.case.sigma)
        );
    }
    let _ = writeln!(s);
}

/// The paper's findings with their verdicts, then the notes of those that have one.
fn findings_section(s: &mut String, findings: &[Finding]) {
    let _ = writeln!(s, "## The paper's findings, checked\n");
    let _ = writeln!(
        s,
        "Each statement of the paper that these data can test, in the paper's words, beside our numbers (means over the noise seeds, ranges in brackets). A verdict is *reproduced* or *contradicted* only when the difference that decides it exceeds the stated tolerance and the ranges over the seeds do not overlap; otherwise it is *inconclusive*. Two values within the tolerance count as equal (a tie, not a ranking).\n"
    );
    let count = |v: crate::Verdict| findings.iter().filter(|f| f.verdict == v).count();
    let _ = writeln!(
        s,
        "Of {} statements: {} reproduced, {} contradicted, {} inconclusive, {} not evaluated.\n",
        findings.len(),
        count(crate::Verdict::Reproduced),
        count(crate::Verdict::Contradicted),
        count(crate::Verdict::Inconclusive),
        count(crate::Verdict::NotEvaluated)
    );
    let _ = writeln!(
        s,
        "| the paper says | verdict | our numbers | tolerance |\n|---|---|---|---|"
    );
    for f in findings {
        let _ = writeln!(
            s,
            "| {} | **{}** | {} | {} |",
            f.claim,
            f.verdict.label(),
            f.evidence,
            f.tolerance
        );
    }
    let _ = writeln!(s);
    for f in findings.iter().filter(|f| !f.note.is_empty()) {
        let _ = writeln!(s, "- *{}* ({}): {}", f.id, f.verdict.label(), f.note);
    }
    let _ = writeln!(s);
}

/// Per surface: the metrics of every scheme after `shown` iterations (and of the input),
/// then the surface's figures.
fn surface_sections(
    s: &mut String,
    results: &StudyResults,
    rows: &[Row],
    figures: &[Figure],
    shown: usize,
) {
    for r in &results.surfaces {
        let name = r.case.clean.name;
        let _ = writeln!(s, "## {name}\n");
        let predicted = predicted_radii(results, r, shown);
        metrics_table(s, results, r, rows, &predicted, shown);
        if !predicted.is_empty() {
            predicted_radius_note(s, results, r, &predicted, shown);
        }
        for f in figures.iter().filter(|f| f.surface == name) {
            let file = if f.path.ends_with(".png") {
                f.path.clone()
            } else {
                format!("{}.png", f.path)
            };
            let _ = writeln!(s, "![{}]({file})\n\n*{}*\n", f.caption, f.caption);
        }
    }
}

/// The metrics of the input and of every scheme of surface `r` after `shown`
/// iterations, with the closed-form radius when `predicted` has any.
fn metrics_table(
    s: &mut String,
    results: &StudyResults,
    r: &crate::run::SurfaceResult,
    rows: &[Row],
    predicted: &[(String, f64)],
    shown: usize,
) {
    let name = r.case.clean.name;
    let seeds = results.config.seeds;
    let _ = writeln!(
        s,
        "After {shown} iterations (input = the noisy surface before smoothing); {}:\n",
        if seeds > 1 {
            format!("mean over {seeds} noise seeds, range [min–max] in brackets")
        } else {
            "one noise seed".to_string()
        }
    );
    let u = crate::figures::unit_label(r.case.clean.unit);
    let _ = writeln!(
        s,
        "| scheme | RMS{u} | max{u} | normal dev. (°) | volume ratio (1) | sphere radius{u} |{} boundary mean{u} | feature dihedral (°) | time (s) |\n|---|---|---|---|---|---|{}---|---|---|",
        if predicted.is_empty() {
            ""
        } else {
            " predicted radius, closed form (clean radii) |"
        },
        if predicted.is_empty() { "" } else { "---|" },
    );
    let mut schemes = vec!["input"];
    schemes.extend(r.runs.iter().map(|x| x.scheme.as_str()));
    for scheme in schemes {
        let it = if scheme == "input" { 0 } else { shown };
        let cell = |f: fn(&Row) -> Option<f64>| {
            let v: Vec<f64> = rows
                .iter()
                .filter(|x| x.surface == name && x.scheme == scheme && x.iteration == it)
                .filter_map(f)
                .collect();
            Spread::of(&v).map_or_else(|| "–".into(), |sp| sp.text())
        };
        let closed = if predicted.is_empty() {
            String::new()
        } else {
            let p = predicted.iter().find(|(n, _)| n == scheme).map(|x| x.1);
            format!(" {} |", if scheme == "input" { num(1.0) } else { opt(p) })
        };
        let _ = writeln!(
            s,
            "| {scheme} | {} | {} | {} | {} | {} |{closed} {} | {} | {} |",
            cell(|x| Some(x.rms)),
            cell(|x| Some(x.max)),
            cell(|x| Some(x.normal_mean_deg)),
            cell(|x| x.volume_ratio),
            cell(|x| x.sphere_radius),
            cell(|x| x.boundary_mean),
            cell(|x| x.feature_dihedral_deg),
            if it == 0 {
                "–".into()
            } else {
                cell(|x| Some(x.time_s))
            }
        );
    }
    let _ = writeln!(s);
}

/// How the predicted radii of the metrics table are computed, with each scheme's
/// weighted mean squared edge length.
fn predicted_radius_note(
    s: &mut String,
    results: &StudyResults,
    r: &crate::run::SurfaceResult,
    predicted: &[(String, f64)],
    shown: usize,
) {
    let _ = writeln!(
        s,
        "The predicted radius is the closed form r₀ (1 − λ⟨ℓ²⟩_w/2r₀²)ⁿ for the clean unit sphere (r₀ = 1, n = {shown}, λ = {}), with each scheme's weighted mean squared edge length ⟨ℓ²⟩_w = Σⱼ wᵢⱼ ℓᵢⱼ² / Σⱼ wᵢⱼ averaged over the vertices of the clean sphere ({}); the noise is left out. The radius plot shows it dashed in the scheme's colour.\n",
        results.config.lambda,
        predicted
            .iter()
            .map(|(n, _)| {
                let l2 = results
                    .config
                    .schemes
                    .iter()
                    .find(|x| x.name() == n)
                    .and_then(|x| {
                        weighted_mean_edge_sq(&r.case.mesh, &r.case.clean.positions, x.as_ref())
                    });
                format!("{n} {}", opt(l2))
            })
            .collect::<Vec<_>>()
            .join(", ")
    );
}

/// Per scheme of `r`'s runs, the closed-form radius after `shown` iterations on the
/// unit sphere (empty for other surfaces).
fn predicted_radii(
    results: &StudyResults,
    r: &crate::run::SurfaceResult,
    shown: usize,
) -> Vec<(String, f64)> {
    // The closed form is that of weight-sum rows (an area-normalised run's step is a
    // share of its own stability limit, not λ).
    if r.case.kind != beltrami_surfaces::SurfaceKind::Sphere
        || results.config.normalization != beltrami_weights::Normalization::WeightSum
    {
        return Vec::new();
    }
    results
        .config
        .schemes
        .iter()
        .filter(|x| r.runs.iter().any(|run| run.scheme == x.name()))
        .filter_map(|x| {
            weighted_mean_edge_sq(&r.case.mesh, &r.case.clean.positions, x.as_ref()).map(|l2| {
                (
                    x.name().to_string(),
                    predicted_radius(1.0, results.config.lambda, l2, shown),
                )
            })
        })
        .collect()
}

/// Under the weight-sum normalisation, the paper's Eq. 6 reading of λ against each
/// surface's stable area-normalised step (empty otherwise, or without limits).
fn stability_note(results: &StudyResults) -> String {
    let c = &results.config;
    let limits: Vec<(String, f64)> = results
        .surfaces
        .iter()
        .filter_map(|r| {
            r.area_step_limit.map(|l| {
                let unit = r.case.clean.unit;
                let unit = if unit.is_empty() || unit == "1" {
                    String::new()
                } else {
                    format!(" {unit}²")
                };
                (format!("{} {}{unit}", r.case.clean.name, sig(l)), l)
            })
        })
        .collect();
    let unstable: Vec<&(String, f64)> = limits.iter().filter(|(_, l)| c.lambda > *l).collect();
    if limits.is_empty() || c.normalization != beltrami_weights::Normalization::WeightSum {
        String::new()
    } else {
        let names = unstable
            .iter()
            .map(|(n, _)| n.split(' ').next().unwrap_or_default())
            .collect::<Vec<_>>()
            .join(", ");
        let verdict = if unstable.is_empty() {
            "so λ is within it on every surface here".to_string()
        } else {
            let worst = unstable
                .iter()
                .map(|(_, l)| c.lambda / l)
                .fold(0.0_f64, f64::max);
            format!(
                "so λ exceeds it on {names} (up to {worst:.0}×) and the frequencies near the mesh's resolution would grow there (`smooth --normalize area --lambda {}` refuses such a step; `study --normalize area` takes λ as the fraction of each run's limit)",
                c.lambda
            )
        };
        format!(
            " Read as Eq. 6, λ = {} is a time step in length², and an explicit step is stable only up to 1 / max_i (Σ_j w_ij / A_i); on the noisy inputs that limit is {}, {verdict}.",
            c.lambda,
            limits
                .iter()
                .map(|(t, _)| t.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// Where the study's set-up departs from the paper's, and where the data are.
fn differences_section(s: &mut String, results: &StudyResults) {
    let c = &results.config;
    let _ = writeln!(s, "## Where this study differs from the paper\n");
    let _ = writeln!(
        s,
        "Each point below is an interpretation of what the paper leaves open or a deliberate departure from it; a verdict above may depend on it.\n"
    );
    let stability = stability_note(results);
    let _ = writeln!(
        s,
        "- **Cotangent normalisation.** {} (the paper's Eq. 2, x ← x + λ Σ w_ij (x_j − x_i) / Σ w_ij), not by 1/(2A_i) as in the paper's Eq. 6; the area normalisation is available in `smooth --normalize area` and `study --normalize area`.{stability}",
        if c.normalization == beltrami_weights::Normalization::WeightSum {
            "Every scheme, cotangent included, is normalised by its weight sum"
        } else {
            "This run normalises by the vertex area (`--normalize area`); the study's default normalises every scheme by its weight sum"
        }
    );
    let _ = writeln!(
        s,
        "- **Negative cotangent weights** are {} (the paper: \"usually the absolute value is used\"); `--cotangent-negative abs|clamp` (in `smooth` and `study`) offers the alternatives.",
        match c.negative {
            beltrami_weights::NegativeWeights::Clamp =>
                "clamped to 0 in this run (`--cotangent-negative clamp`)",
            beltrami_weights::NegativeWeights::Abs =>
                "replaced by their absolute value in this run (`--cotangent-negative abs`)",
            _ => "kept as they are",
        }
    );
    let _ = writeln!(
        s,
        "- **Boundary.** The boundary is {} (the paper does not say; its F-lens loses its outline, which only a free boundary does).",
        format!("{:?}", c.boundary).to_lowercase()
    );
    let _ = writeln!(
        s,
        "- **Noise level.** The paper does not state it; here σ = {} along the vertex normals, a common level in mesh-denoising benchmarks, with {} seed(s). Rankings at small differences may depend on it.",
        match c.noise {
            beltrami_surfaces::NoiseLevel::Absolute(x) => format!("{x} (absolute)"),
            beltrami_surfaces::NoiseLevel::RelativeToMeanEdge(r) =>
                format!("{r} × mean edge length"),
        },
        c.seeds
    );
    let _ = writeln!(
        s,
        "- **Surfaces.** The paper does not publish its surfaces. The F-lens is a biconic + XY-polynomial free-form on a 68 × 33 grid inferred from the paper's vertex and face counts (2244 / 4288); the block is a synthetic genus-3 box with three through-holes of about the paper's size (8780 vertices instead of 8771); the golf ball is a synthetic regulation ball with 362 dimples on a 79 212-vertex geodesic mesh (the paper measured a real ball with 78 721 vertices). See `crates/surfaces`."
    );
    let _ = writeln!(
        s,
        "- **Weight updates and timing.** Weights that depend on the positions are recomputed {} iteration, as the paper times them; times are those of this implementation, where every scheme computes its weights in one pass over the halfedges, so the paper's cotangent timings reflect its implementation, not the method.",
        format!("{:?}", c.update).to_lowercase()
    );
    let _ = writeln!(
        s,
        "- **Remeshing.** The paper remeshes its surfaces in MeshLab before adding noise; the study's runs use the surfaces as generated, {}",
        if results.remeshing.is_some() {
            "and \"Remeshing before smoothing\" measures what an isotropic remesh changes for the cotangent scheme."
        } else {
            "and this study skipped the remeshing comparison."
        }
    );
    let _ = writeln!(
        s,
        "- **Beyond the paper.** RMS distances are measured on the synthetic golf ball too (the paper had no reference); the RMS is observed at every iteration from 0 to {EARLY_ITERATIONS} (the paper starts at 10), which moves the optimum into view."
    );
    let _ = writeln!(
        s,
        "\nThe full data are in `results.csv` (every seed; the `seed` column) and `results.json` next to this report."
    );
}

/// Mesh quality beside accuracy: flipped faces against the clean mesh and the smallest
/// angle, per scheme (mean over the seeds) and per counter-measure (first seed).
fn quality_section(s: &mut String, results: &StudyResults, rows: &[Row], shown: usize) {
    if !rows.iter().any(|r| r.flipped_faces.is_some()) {
        return;
    }
    let _ = writeln!(
        s,
        "## Mesh quality beside accuracy
"
    );
    let _ = writeln!(
        s,
        "After {shown} iterations: faces whose normal points against the clean mesh's (folds), and the smallest corner angle. Plain schemes: mean over the seeds [range]; counter-measures (`scheme/method`, `once` = weights computed once from the noisy input): seed {}.\n",
        results.config.seed
    );
    let _ = writeln!(
        s,
        "| surface | run | flipped faces | smallest angle (°) |\n|---|---|---|---|"
    );
    for r in &results.surfaces {
        let name = r.case.clean.name;
        let mut labels: Vec<&str> = vec!["input"];
        labels.extend(r.runs.iter().map(|x| x.scheme.as_str()));
        for label in labels {
            let it = if label == "input" { 0 } else { shown };
            let of: Vec<&Row> = rows
                .iter()
                .filter(|x| x.surface == name && x.scheme == label && x.iteration == it)
                .collect();
            let flipped: Vec<f64> = of
                .iter()
                .filter_map(|x| x.flipped_faces.map(|n| n as f64))
                .collect();
            let angle: Vec<f64> = of.iter().filter_map(|x| x.min_angle_deg).collect();
            let _ = writeln!(
                s,
                "| {name} | {label} | {} | {} |",
                Spread::of(&flipped).map_or_else(|| "–".into(), |v| v.text()),
                Spread::of(&angle).map_or_else(|| "–".into(), |v| v.text())
            );
        }
        for m in r
            .countermeasures
            .iter()
            .filter(|m| m.row.iteration == shown)
        {
            let _ = writeln!(
                s,
                "| {name} | {} | {} | {} |",
                m.row.scheme,
                m.row
                    .flipped_faces
                    .map_or_else(|| "–".into(), |n| n.to_string()),
                opt(m.row.min_angle_deg)
            );
        }
    }
    let _ = writeln!(s);
    for r in &results.surfaces {
        let at = |suffix: &str| {
            r.countermeasures
                .iter()
                .find(|m| m.row.iteration == shown && m.row.scheme.ends_with(suffix))
                .and_then(|m| m.row.flipped_faces.map(|n| (m.row.scheme.clone(), n)))
        };
        if let (Some((plain, p)), Some((once, o))) = (at("/plain"), at("/once")) {
            let cause = if p > o {
                "so recomputing the weights from the moving positions causes the folding"
            } else {
                "so recomputing the weights does not add folds here"
            };
            let _ = writeln!(
                s,
                "- {}: `{plain}` (weights recomputed every iteration) has {p} flipped faces after {shown} iterations, `{once}` (weights computed once) {o}, {cause}.",
                r.case.clean.name
            );
        }
    }
    let _ = writeln!(s);
}

/// The RMS-optimal iteration counts per surface and scheme.
fn optimum_section(
    s: &mut String,
    results: &StudyResults,
    rows: &[Row],
    optima: &[Optimum],
    shown: usize,
) {
    if optima.is_empty() {
        return;
    }
    let _ = writeln!(s, "## The RMS-optimal iteration count\n");
    let _ = writeln!(
        s,
        "The RMS distance to the clean surface first falls (the noise is removed) and then grows (the surface shrinks). Observed at every iteration from 0 to {EARLY_ITERATIONS} and at the iterations of the set-up, per seed; the optimum is the iteration with the smallest RMS (the range over the seeds when they differ). `≥` marks an optimum at the last observed iteration, which may lie further out.\n"
    );
    let _ = writeln!(
        s,
        "| surface | scheme | optimal iterations | RMS at the optimum (unit) | input RMS (unit) | RMS at {shown} it. (unit) | RMS at {shown} / at the optimum (1) |\n|---|---|---|---|---|---|---|"
    );
    for o in optima {
        let at = rms_at(rows, &o.surface, &o.scheme, shown);
        let unit = unit_of(results, &o.surface);
        let _ = writeln!(
            s,
            "| {} | {} | {}{} | {}{unit} | {}{unit} | {} | {} |",
            o.surface,
            o.scheme,
            if o.at_last_observed { "≥ " } else { "" },
            o.iterations_text(),
            o.rms.text(),
            o.input_rms.text(),
            at.map_or_else(|| "–".into(), |a| format!("{}{unit}", a.text())),
            at.map_or_else(|| "–".into(), |a| format!("{:.1}×", a.mean / o.rms.mean))
        );
    }
    let _ = writeln!(s);
}

fn rms_at(rows: &[Row], surface: &str, scheme: &str, it: usize) -> Option<Spread> {
    let v: Vec<f64> = rows
        .iter()
        .filter(|x| x.surface == surface && x.scheme == scheme && x.iteration == it)
        .map(|x| x.rms)
        .collect();
    Spread::of(&v)
}

fn time_at(rows: &[Row], surface: &str, scheme: &str, it: usize) -> Option<f64> {
    let v: Vec<f64> = rows
        .iter()
        .filter(|x| x.surface == surface && x.scheme == scheme && x.iteration == it)
        .map(|x| x.time_s)
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

fn unit_of(results: &StudyResults, surface: &str) -> String {
    results
        .surfaces
        .iter()
        .find(|r| r.case.clean.name == surface)
        .map(|r| r.case.clean.unit)
        .filter(|u| *u != "1")
        .map_or_else(String::new, |u| format!(" {u}"))
}

/// The schemes of `optima` on `surface` whose optimal RMS equals the best one within
/// the tolerance ([`REL_TOL`] of the best) or within the spread over the seeds, best
/// first.
fn best_optima<'a>(optima: &'a [Optimum], surface: &str) -> Vec<&'a Optimum> {
    let mut of: Vec<&Optimum> = optima.iter().filter(|o| o.surface == surface).collect();
    of.sort_by(|a, b| a.rms.mean.total_cmp(&b.rms.mean));
    let Some(best) = of.first().copied() else {
        return of;
    };
    let tol = REL_TOL * best.rms.mean;
    of.into_iter()
        .filter(|o| compare(&o.rms, &best.rms, tol) != Comparison::Greater)
        .collect()
}

fn names(list: &[&Optimum]) -> String {
    let n: Vec<String> = list.iter().map(|o| format!("`{}`", o.scheme)).collect();
    match n.len() {
        0 => String::new(),
        1 => n[0].clone(),
        _ => format!("{} and {}", n[..n.len() - 1].join(", "), n[n.len() - 1]),
    }
}

/// Which operator, which method and how many iterations for which surface, generated
/// from the optima, the rows at the shown iteration and the counter-measure rows.
fn recommendation_section(
    s: &mut String,
    results: &StudyResults,
    rows: &[Row],
    optima: &[Optimum],
    shown: usize,
) {
    if optima.is_empty() {
        return;
    }
    let _ = writeln!(s, "## Recommendation\n");
    let _ = writeln!(
        s,
        "Generated from the numbers of this report (means over the noise seeds; \"tie\" means within {} % or within the seeds' range). The criterion is the RMS distance to the clean surface, the paper's accuracy metric.\n",
        100.0 * REL_TOL
    );
    for r in &results.surfaces {
        let name = r.case.clean.name;
        let unit = unit_of(results, name);
        let best = best_optima(optima, name);
        let Some(first) = best.first() else {
            continue;
        };
        let mut text = best_sentence(name, &unit, &best, optima);
        text.push('.');
        paper_count_sentence(&mut text, r, rows, &unit, shown, first);
        countermeasure_sentence(&mut text, r, results.config.seed, &unit, shown);
        let _ = writeln!(s, "{text}");
    }
    // How many iterations overall.
    let (lo, hi) = optima.iter().fold((usize::MAX, 0), |a, o| {
        (a.0.min(o.iterations.0), a.1.max(o.iterations.1))
    });
    let _ = writeln!(
        s,
        "\nHow many iterations: with λ = {}, the optimum lies between {lo} and {hi} iterations on every surface and scheme studied; the paper's counts (10 to 200) are past it wherever the optimum is below 10.\n",
        results.config.lambda
    );
    let _ = writeln!(
        s,
        "On your own surface: `beltrami study --input SCAN --reference CLEAN` runs every scheme with plain, Taubin, HC and implicit smoothing on a given mesh, observes every iteration against the clean one, names the RMS-optimal count of each and writes its mesh (`best-<scheme>-<method>.ply`); without a reference it reports shrinkage, residual parameters and mesh quality (docs/study-input.md). The section \"The study on a given surface\" below runs it on this study's noisy block.\n"
    );
}

/// The recommendation's first sentence for surface `name`: the best schemes at their
/// optima (`best`, from [`best_optima`]), and the best of the paper's schemes when none
/// of them is first.
fn best_sentence(name: &str, unit: &str, best: &[&Optimum], optima: &[Optimum]) -> String {
    let first = best[0];
    let mut text = format!(
        "- **{name}**: the smallest RMS is reached after {} {} with {} ({}{unit}, {:.0} % of the input's {}{unit})",
        first.iterations_text(),
        if first.iterations == (1, 1) {
            "iteration"
        } else {
            "iterations"
        },
        names(&best[..1]),
        first.rms.text(),
        100.0 * first.rms.mean / first.input_rms.mean,
        first.input_rms.text()
    );
    if best.len() > 1 {
        let _ = write!(
            text,
            "; {} {} with it at their optima ({})",
            names(&best[1..]),
            if best.len() > 2 { "tie" } else { "ties" },
            best[1..]
                .iter()
                .map(|o| format!("{} after {}", o.rms.text(), o.iterations_text()))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if !crate::config::PAPER_SCHEMES.contains(&first.scheme.as_str()) {
        let paper: Vec<Optimum> = optima
            .iter()
            .filter(|o| {
                o.surface == name && crate::config::PAPER_SCHEMES.contains(&o.scheme.as_str())
            })
            .cloned()
            .collect();
        let best_paper = best_optima(&paper, name);
        if let Some(p) = best_paper.first() {
            let _ = write!(
                text,
                "; of the paper's schemes, {} reaches {}{unit} after {} {}",
                names(&best_paper[..1]),
                p.rms.text(),
                p.iterations_text(),
                if p.iterations == (1, 1) {
                    "iteration"
                } else {
                    "iterations"
                }
            );
            if best_paper.len() > 1 {
                let _ = write!(
                    text,
                    " ({} {} with it)",
                    names(&best_paper[1..]),
                    if best_paper.len() > 2 { "tie" } else { "ties" }
                );
            }
        }
    }
    text
}

/// The recommendation's sentences at the paper's iteration count `shown`: how far the
/// RMS is from the optimum of `first`, the best scheme there and its time against
/// `uniform`.
fn paper_count_sentence(
    text: &mut String,
    r: &SurfaceResult,
    rows: &[Row],
    unit: &str,
    shown: usize,
    first: &Optimum,
) {
    let name = r.case.clean.name;
    let at: Vec<(&str, Spread)> = r
        .runs
        .iter()
        .filter_map(|x| rms_at(rows, name, &x.scheme, shown).map(|v| (x.scheme.as_str(), v)))
        .collect();
    if let Some((b, v)) = at
        .iter()
        .copied()
        .min_by(|a, b| a.1.mean.total_cmp(&b.1.mean))
    {
        let _ = write!(
            text,
            " After {shown} iterations, the paper's count, the RMS is {:.1}× the optimum of `{}`; the best scheme there is `{b}` ({}{unit})",
            v.mean / first.rms.mean,
            first.scheme,
            v.text()
        );
        if b != first.scheme {
            text.push_str(", so the ranking at the optimum and at the paper's count differ");
        }
        text.push('.');
        if let (Some(tb), Some(tu)) = (
            time_at(rows, name, b, shown),
            time_at(rows, name, "uniform", shown),
        ) && b != "uniform"
            && tu > 0.0
        {
            let _ = write!(text, " `{b}` takes {:.1}× the time of `uniform`.", tb / tu);
        }
    }
}

/// The recommendation's sentence on counter-measures: the one that keeps the RMS lowest
/// after `shown` iterations against plain diffusion (first noise seed `seed`).
fn countermeasure_sentence(
    text: &mut String,
    r: &SurfaceResult,
    seed: u64,
    unit: &str,
    shown: usize,
) {
    let cm: Vec<&Row> = r
        .countermeasures
        .iter()
        .map(|m| &m.row)
        .filter(|x| x.iteration == shown)
        .collect();
    if let (Some(best_cm), Some(plain)) = (
        cm.iter().copied().min_by(|a, b| a.rms.total_cmp(&b.rms)),
        cm.iter().copied().find(|x| x.scheme.ends_with("/plain")),
    ) && best_cm.scheme != plain.scheme
    {
        let _ = write!(
            text,
            " If many iterations are needed, `{}` keeps the RMS at {}{unit} after {shown} iterations against {}{unit} for `{}` (seed {}).",
            best_cm.scheme,
            sig(best_cm.rms),
            sig(plain.rms),
            plain.scheme,
            seed
        );
    }
}

/// The iterations shown in the counter-measure tables: 10, 50, 100 and 200 where
/// observed, else the first, middle and last observed.
fn countermeasure_iterations(observed: &[usize]) -> Vec<usize> {
    let preferred: Vec<usize> = [10, 50, 100, 200]
        .into_iter()
        .filter(|i| observed.contains(i))
        .collect();
    if preferred.len() >= 2 {
        return preferred;
    }
    let mut picked = vec![
        observed[0],
        observed[observed.len() / 2],
        observed[observed.len() - 1],
    ];
    picked.dedup();
    picked
}

/// "1 iteration", "12 iterations".
fn counted_iterations(n: usize) -> String {
    if n == 1 {
        "1 iteration".to_string()
    } else {
        format!("{n} iterations")
    }
}

/// The study of the noisy block as a given surface: the best count per scheme and
/// method against the input and `smooth`'s defaults.
fn scan_section(s: &mut String, scan: &crate::scan::ScanResults) {
    let _ = writeln!(
        s,
        "## The study on a given surface
"
    );
    let _ = writeln!(
        s,
        "`beltrami study --input SCAN --reference CLEAN` runs every scheme with plain, Taubin, HC and implicit smoothing on a mesh you give, observes every iteration against the clean one and writes the best mesh of each (docs/study-input.md). Here it runs on this study's {} against the {}, with the paper's schemes; its whole report is [scan/report.md](scan/report.md).\n",
        scan.input.name,
        scan.reference
            .as_ref()
            .map_or("reference", |r| r.name.as_str())
    );
    let Some(base) = scan.baseline().rms else {
        return;
    };
    let _ = writeln!(
        s,
        "| scheme | method | best count | step | RMS at the best (mm) | change from the input |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|");
    for b in &scan.best {
        let _ = writeln!(
            s,
            "| {} | {} | {}{} | {} | {} | {:+.1} % |",
            b.scheme,
            b.method,
            b.iteration,
            if b.at_last_observed {
                " (last observed)"
            } else {
                ""
            },
            sig(b.step),
            sig(b.rms),
            100.0 * (b.rms / base - 1.0)
        );
    }
    let defaults = scan
        .rows_of("cotangent", "plain")
        .find(|r| r.iteration == 10)
        .and_then(|r| r.rms);
    let best = scan.best.iter().min_by(|a, b| a.rms.total_cmp(&b.rms));
    if let (Some(d), Some(b)) = (defaults, best) {
        let _ = writeln!(
            s,
            "\nThe noisy input is {} mm from the clean block (RMS). `smooth`'s defaults (cotangent, λ = {}, 10 plain iterations) leave it {} mm away ({:+.1} %); the closest is `{}` with `{}` smoothing, {} ({} mm, {:+.1} %).\n",
            sig(base),
            sig(scan.config.lambda),
            sig(d),
            100.0 * (d / base - 1.0),
            b.scheme,
            b.method,
            if b.method == "implicit" {
                format!("one step of time {}", sig(b.step))
            } else {
                format!("after {}", counted_iterations(b.iteration))
            },
            sig(b.rms),
            100.0 * (b.rms / base - 1.0)
        );
    }
}

/// The section on shrinkage counter-measures: per surface, the metric that shows
/// shrinkage (sphere radius, volume ratio or boundary displacement) against iterations.
fn countermeasure_section(s: &mut String, results: &StudyResults, shown: usize) {
    let with: Vec<_> = results
        .surfaces
        .iter()
        .filter(|r| !r.countermeasures.is_empty())
        .collect();
    if with.is_empty() {
        return;
    }
    let columns = countermeasure_iterations(&results.config.iterations);
    let _ = writeln!(s, "## Shrinkage counter-measures\n");
    let _ = writeln!(
        s,
        "Plain diffusion shrinks (a discrete mean-curvature flow). Beside it, with the same scheme and noisy input: Taubin's λ|μ filter (λ = 0.6307, μ = −0.6732, pass band k_PB = 0.1), the HC push-back towards the input (α = 0.1, β = 0.6; local, so it works on open patches), the volume-preserving rescale about the surface centroid (closed surfaces only), and plain diffusion with the weights computed once from the noisy input (`once`). Each Taubin iteration is two sweeps. Labels are `scheme/method`; all rows are in `countermeasures.csv`.\n"
    );
    for r in with {
        let name = r.case.clean.name;
        let rows: Vec<&Row> = r.countermeasures.iter().map(|m| &m.row).collect();
        let (metric, pick): (&str, fn(&Row) -> Option<f64>) =
            if rows.iter().any(|x| x.sphere_radius.is_some()) {
                ("fitted sphere radius (clean: 1)", |x| x.sphere_radius)
            } else if rows.iter().any(|x| x.volume_ratio.is_some()) {
                ("volume / clean volume", |x| x.volume_ratio)
            } else {
                ("mean boundary displacement", |x| x.boundary_mean)
            };
        let u = crate::figures::unit_label(r.case.clean.unit);
        let metric_unit = if metric.starts_with("mean boundary") {
            u.clone()
        } else {
            " (1)".to_string()
        };
        let _ = writeln!(s, "### {name}: {metric}{metric_unit}\n");
        let mut header = String::from("| method |");
        let mut rule = String::from("|---|");
        for i in &columns {
            let _ = write!(header, " {i} it. |");
            rule.push_str("---|");
        }
        let _ = write!(header, " RMS at {shown} it.{u} |");
        rule.push_str("---|");
        let has_dihedral = rows.iter().any(|x| x.feature_dihedral_deg.is_some());
        if has_dihedral {
            let _ = write!(header, " feature dihedral at {shown} it. (°) |");
            rule.push_str("---|");
        }
        let _ = writeln!(s, "{header}\n{rule}");
        let mut labels: Vec<&str> = Vec::new();
        for x in &rows {
            if !labels.contains(&x.scheme.as_str()) {
                labels.push(&x.scheme);
            }
        }
        for label in labels {
            let of = |i: usize| rows.iter().find(|x| x.scheme == label && x.iteration == i);
            let mut line = format!("| {label} |");
            for &i in &columns {
                let _ = write!(line, " {} |", opt(of(i).and_then(|x| pick(x))));
            }
            let _ = write!(line, " {} |", opt(of(shown).map(|x| x.rms)));
            if has_dihedral {
                let _ = write!(
                    line,
                    " {} |",
                    opt(of(shown).and_then(|x| x.feature_dihedral_deg))
                );
            }
            let _ = writeln!(s, "{line}");
        }
        let _ = writeln!(s);
    }
}

/// The section on the edge-preserving scheme against its reference on the block.
fn edge_section(s: &mut String, results: &StudyResults) {
    let Some(e) = &results.edge_preservation else {
        return;
    };
    let _ = writeln!(s, "## Edge preservation on the block\n");
    let _ = writeln!(
        s,
        "`{}` (an edge-preserving scheme written through the public plug-in API, `crates/schemes`) against `{}`, both with λ = {} from the same noisy block, each run until the RMS distance of the {} flat-side vertices away from the edges to their planes is at most {} (a quarter of the input's). Then the mean absolute error of the dihedral angle at the {} feature edges and the volume loss are compared.\n",
        e.scheme.scheme,
        e.reference.scheme,
        results.config.lambda,
        e.flat_vertices,
        num(e.target_flat_rms),
        e.feature_edges
    );
    let _ = writeln!(
        s,
        "| run | iterations | flat-side RMS (mm) | dihedral error (°) | volume loss (%) | reached the target |\n|---|---|---|---|---|---|"
    );
    let line = |s: &mut String, name: &str, m: &crate::Measures, reached: &str| {
        let _ = writeln!(
            s,
            "| {name} | {} | {} | {} | {} | {reached} |",
            m.iterations,
            num(m.flat_rms),
            num(m.dihedral_error_deg),
            m.volume_loss()
                .map_or_else(|| "–".into(), |v| format!("{:.3} %", 100.0 * v))
        );
    };
    line(s, "noisy input", &e.input, "–");
    for o in [&e.scheme, &e.reference] {
        line(
            s,
            &o.scheme,
            &o.measures,
            if o.reached_target { "yes" } else { "no" },
        );
    }
    let _ = writeln!(
        s,
        "\nThe flat sides of the two runs differ by {:.1} %. Verdict: `{}` {} at equal flat-side smoothness.\n",
        100.0 * e.smoothness_mismatch(),
        e.scheme.scheme,
        if e.scheme_is_better() {
            format!(
                "keeps the feature edges and the volume better than `{}`",
                e.reference.scheme
            )
        } else {
            format!(
                "does not keep both the feature edges and the volume better than `{}`",
                e.reference.scheme
            )
        }
    );
}

/// The section on physical units: one cut-off wavelength on spheres of several densities.
fn units_section(s: &mut String, results: &StudyResults) {
    let Some(u) = &results.units else {
        return;
    };
    let _ = writeln!(s, "## Physical units: one cut-off, any mesh density\n");
    let _ = writeln!(
        s,
        "Clean unit icospheres of several densities, smoothed with `{}` (weight-sum normalisation, largest step λ = {}) for a Gaussian cut-off wavelength λc = {} radii, i.e. a diffusion time t = 0.017558 λc² = {}; the continuous mean-curvature flow ends at radius √(1 − 4t) = {}. Beside it, the same λ × {} iterations (the finest sphere's count) on every sphere.\n",
        u.scheme,
        u.lambda,
        u.cutoff,
        num(u.time),
        num(u.expected_radius),
        u.iterations_fixed
    );
    let _ = writeln!(
        s,
        "| level | vertices | iterations for λc | radius, λc (clean radii) | radius, fixed λ × iterations (clean radii) | radius, one implicit step of t (clean radii) | implicit step (s) |\n|---|---|---|---|---|---|---|"
    );
    for r in &u.rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} |",
            r.level,
            r.vertices,
            r.iterations_cutoff,
            num(r.radius_cutoff),
            num(r.radius_fixed),
            num(r.radius_implicit),
            num(r.implicit_seconds)
        );
    }
    let spread = |f: fn(&crate::units::UnitsRow) -> f64| {
        let v: Vec<f64> = u.rows.iter().map(f).collect();
        v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - v.iter().copied().fold(f64::INFINITY, f64::min)
    };
    let _ = writeln!(
        s,
        "\nSpread of the radii over the densities: {} with the cut-off, {} with a fixed λ × iterations, {} with one implicit step (backward Euler, (M + tK) x' = M x, cotangent stiffness K and barycentric mass M: unconditionally stable, so the whole time is one step; see docs/implicit.md).\n",
        num(spread(|r| r.radius_cutoff)),
        num(spread(|r| r.radius_fixed)),
        num(spread(|r| r.radius_implicit))
    );
}
