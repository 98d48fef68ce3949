//! Writing the study of one given surface: report.md, results.csv, results.json,
//! timings.csv and the best meshes.

use std::fmt::Write as _;
use std::path::Path;

use beltrami_halfedge::MeshData;
use beltrami_io::WriteOptions;
use serde::Serialize;

use super::config::{ScanMethod, TAUBIN_LAMBDA, TAUBIN_MU};
use super::run::{ScanBest, ScanResults, ScanRow};
use crate::error::StudyError;
use crate::findings::sig;

/// The header of a scan's results.csv.
pub const SCAN_CSV_HEADER: &str = "scheme,method,iteration,step,rms,max,volume_ratio,area_ratio,removed_sa,removed_sq,removed_sz,shift,min_angle_deg,flipped_faces";

/// The heading of report.md's last section, the timings: everything above it is the
/// same bytes on every run; the section itself is not.
pub const TIME_HEADING: &str = "## Time";

/// The iteration counts the report's tables show (where observed).
pub const REPORT_ITERATIONS: [usize; 8] = [1, 2, 3, 5, 10, 20, 50, 100];

/// What [`write_scan`] wrote, relative to its directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ScanWritten {
    /// Every file, in the order written.
    pub files: Vec<String>,
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(String::new, |x| format!("{x:e}"))
}

/// The rows as CSV text with [`SCAN_CSV_HEADER`]: numbers in Rust's shortest
/// round-trip notation (exact), empty fields for values that do not apply.
#[must_use]
pub fn scan_csv(rows: &[ScanRow]) -> String {
    let mut out = String::with_capacity(rows.len() * 160);
    out.push_str(SCAN_CSV_HEADER);
    out.push('\n');
    for r in rows {
        let _ = writeln!(
            out,
            "{},{},{},{:e},{},{},{},{:e},{},{},{},{},{},{}",
            r.scheme,
            r.method,
            r.iteration,
            r.step,
            opt(r.rms),
            opt(r.max),
            opt(r.volume_ratio),
            r.area_ratio,
            opt(r.removed_sa),
            opt(r.removed_sq),
            opt(r.removed_sz),
            opt(r.shift),
            opt(r.min_angle_deg),
            r.flipped_faces.map_or_else(String::new, |n| n.to_string())
        );
    }
    out
}

#[derive(Serialize)]
struct SurfaceJson<'a> {
    name: &'a str,
    vertices: usize,
    faces: usize,
    closed: bool,
}

#[derive(Serialize)]
struct ConfigJson<'a> {
    schemes: Vec<&'a str>,
    methods: Vec<&'static str>,
    lambda: f64,
    taubin_lambda: f64,
    taubin_mu: f64,
    hc_alpha: f64,
    hc_beta: f64,
    max_iterations: usize,
    observed_iterations: Vec<usize>,
    implicit_steps: &'a [f64],
    boundary: String,
    update: String,
}

#[derive(Serialize)]
struct Json<'a> {
    input: SurfaceJson<'a>,
    reference: Option<SurfaceJson<'a>>,
    config: ConfigJson<'a>,
    warnings: &'a [String],
    best: &'a [ScanBest],
    rows: &'a [ScanRow],
}

fn surface_json(s: &super::run::ScanSurface) -> SurfaceJson<'_> {
    SurfaceJson {
        name: &s.name,
        vertices: s.mesh.n_vertices(),
        faces: s.mesh.n_faces(),
        closed: s.mesh.is_closed(),
    }
}

fn write(dir: &Path, name: &str, bytes: &[u8], files: &mut Vec<String>) -> Result<(), StudyError> {
    let path = dir.join(name);
    beltrami_io::write_bytes_atomic(&path, bytes)
        .map_err(|source| StudyError::Write { path, source })?;
    files.push(name.to_string());
    Ok(())
}

/// Writes the results into `dir` (which must exist): `report.md`, `results.csv` (one
/// row per observation, [`SCAN_CSV_HEADER`]), `results.json` (settings, best
/// observations and rows), `timings.csv` (smoothing time per run; not deterministic)
/// and, with a reference, `best-<scheme>-<method>.ply` for every scheme and method
/// (binary PLY, exact doubles, the input's faces). Every file but `timings.csv` and
/// report.md's last section ([`TIME_HEADING`]) is the same bytes on every run.
///
/// # Errors
/// [`StudyError::Write`] naming the file that could not be written.
pub fn write_scan(results: &ScanResults, dir: &Path) -> Result<ScanWritten, StudyError> {
    let mut files = Vec::new();
    write(
        dir,
        "results.csv",
        scan_csv(&results.rows).as_bytes(),
        &mut files,
    )?;
    let config = &results.config;
    let json = Json {
        input: surface_json(&results.input),
        reference: results.reference.as_ref().map(surface_json),
        config: ConfigJson {
            schemes: config.schemes.iter().map(|s| s.name()).collect(),
            methods: config.methods.iter().map(|m| m.label()).collect(),
            lambda: config.lambda,
            taubin_lambda: TAUBIN_LAMBDA,
            taubin_mu: TAUBIN_MU,
            hc_alpha: 0.1,
            hc_beta: 0.6,
            max_iterations: config.max_iterations,
            observed_iterations: config.observed_iterations(),
            implicit_steps: &config.implicit_steps,
            boundary: format!("{:?}", config.boundary).to_lowercase(),
            update: format!("{:?}", config.update).to_lowercase(),
        },
        warnings: &results.warnings,
        best: &results.best,
        rows: &results.rows,
    };
    let mut text =
        serde_json::to_string_pretty(&json).map_err(|e| StudyError::Config(e.to_string()))?;
    text.push('\n');
    write(dir, "results.json", text.as_bytes(), &mut files)?;
    let mut timings = String::from("scheme,method,smoothing_s\n");
    for t in &results.timings {
        let _ = writeln!(timings, "{},{},{:e}", t.scheme, t.method, t.smoothing_s);
    }
    write(dir, "timings.csv", timings.as_bytes(), &mut files)?;
    for (best, positions) in results.best.iter().zip(&results.best_positions) {
        let path = dir.join(&best.file);
        let data = MeshData {
            positions: positions.clone(),
            faces: results.input.data.faces.clone(),
        };
        beltrami_io::write_mesh(&path, &data, &WriteOptions::default())
            .map_err(|source| StudyError::Write { path, source })?;
        files.push(best.file.clone());
    }
    write(dir, "report.md", markdown(results).as_bytes(), &mut files)?;
    Ok(ScanWritten { files })
}

fn num(x: f64) -> String {
    sig(x)
}

fn onum(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), num)
}

fn percent_change(value: f64, base: f64) -> String {
    if base > 0.0 {
        format!("{:+.1} %", 100.0 * (value / base - 1.0))
    } else {
        "–".into()
    }
}

/// The `beltrami smooth` options that reproduce one observation.
#[must_use]
pub fn smooth_options(
    config: &super::ScanConfig,
    scheme: &str,
    method: &str,
    iteration: usize,
    step: f64,
) -> String {
    let mut s = format!("--weights {scheme}");
    match ScanMethod::from_label(method) {
        Ok(ScanMethod::Plain) => {
            let _ = write!(s, " --lambda {} --iterations {iteration}", config.lambda);
        }
        Ok(ScanMethod::Taubin) => {
            let _ = write!(
                s,
                " --method taubin --lambda {TAUBIN_LAMBDA} --mu {TAUBIN_MU} --iterations {iteration}"
            );
        }
        Ok(ScanMethod::Hc) => {
            let _ = write!(
                s,
                " --method hc --lambda {} --iterations {iteration}",
                config.lambda
            );
        }
        Ok(ScanMethod::Implicit) => {
            let _ = write!(
                s,
                " --method implicit --solver cholesky --lambda {step} --iterations 1"
            );
        }
        Err(_) => {}
    }
    let boundary = format!("{:?}", config.boundary).to_lowercase();
    if boundary != "fixed" {
        let _ = write!(s, " --boundary {boundary}");
    }
    let update = format!("{:?}", config.update).to_lowercase();
    if update != "every" {
        let _ = write!(s, " --update {update}");
    }
    s
}

fn count_text(row: &ScanRow) -> String {
    if row.method == "implicit" {
        format!("1 step of {}", row.step)
    } else {
        row.iteration.to_string()
    }
}

fn markdown(results: &ScanResults) -> String {
    let mut s = String::new();
    intro(&mut s, results);
    setup_section(&mut s, results);
    warnings_section(&mut s, results);
    if let Some(base_rms) = results.baseline().rms {
        best_sections(&mut s, results, base_rms);
    }
    effect_section(&mut s, results);
    files_section(&mut s, results);
    timing_section(&mut s, results);
    s
}

/// The title and what the study did.
fn intro(s: &mut String, results: &ScanResults) {
    let input = &results.input;
    let _ = writeln!(s, "# Smoothing study of `{}`\n", input.name);
    let _ = writeln!(
        s,
        "Every weight scheme and smoothing method run on one given surface, observed iteration by iteration{}. Lengths are in the input's unit.\n",
        if results.reference.is_some() {
            ", and measured against a clean reference"
        } else {
            " (no reference given: there is no ground truth, so this report shows what smoothing does and does not name a best count)"
        }
    );
}

/// The input, reference, schemes, methods and observed iterations.
fn setup_section(s: &mut String, results: &ScanResults) {
    let config = &results.config;
    let input = &results.input;
    let _ = writeln!(s, "## Setup\n");
    let _ = writeln!(
        s,
        "- Input: `{}`, {} vertices, {} faces, {}.",
        input.name,
        input.mesh.n_vertices(),
        input.mesh.n_faces(),
        if input.mesh.is_closed() {
            "closed"
        } else {
            "open"
        }
    );
    match &results.reference {
        Some(r) => {
            let _ = writeln!(
                s,
                "- Reference: `{}`, {} vertices, {} faces. Distances are from each vertex to the closest point of the reference surface (as `beltrami compare` measures them), so any clean mesh of the part serves.",
                r.name,
                r.mesh.n_vertices(),
                r.mesh.n_faces()
            );
        }
        None => {
            let _ = writeln!(s, "- Reference: none.");
        }
    }
    let schemes: Vec<&str> = config.schemes.iter().map(|x| x.name()).collect();
    let _ = writeln!(s, "- Schemes: {}.", schemes.join(", "));
    let mut methods = Vec::new();
    for m in &config.methods {
        methods.push(match m {
            ScanMethod::Plain => format!("plain (explicit diffusion, λ = {})", config.lambda),
            ScanMethod::Taubin => format!("taubin (λ = {TAUBIN_LAMBDA}, μ = {TAUBIN_MU})"),
            ScanMethod::Hc => format!("hc (λ = {}, α = 0.1, β = 0.6)", config.lambda),
            ScanMethod::Implicit => format!(
                "implicit (one backward-Euler step of time step {}, sparse Cholesky)",
                config
                    .implicit_steps
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        });
    }
    let _ = writeln!(s, "- Methods: {}.", methods.join("; "));
    let _ = writeln!(
        s,
        "- Explicit iterations observed: every one from 1 to {}, then every {}th up to {}. Boundary {}, weights recomputed {}, weight-sum normalisation (the defaults of `beltrami smooth`).",
        super::config::OBSERVE_EVERY_UP_TO.min(config.max_iterations),
        super::config::OBSERVE_STRIDE,
        config.max_iterations,
        format!("{:?}", config.boundary).to_lowercase(),
        match config.update {
            beltrami_smooth::WeightUpdate::Once => "once from the input",
            _ => "every iteration",
        }
    );
    let _ = writeln!(s);
}

/// The warnings of the run, when there are any.
fn warnings_section(s: &mut String, results: &ScanResults) {
    if !results.warnings.is_empty() {
        let _ = writeln!(s, "## Warnings\n");
        for w in &results.warnings {
            let _ = writeln!(s, "- {w}");
        }
        let _ = writeln!(s);
    }
}

/// The files written beside the report.
fn files_section(s: &mut String, results: &ScanResults) {
    let _ = writeln!(s, "## Files\n");
    let _ = writeln!(
        s,
        "- `results.csv`: one row per scheme, method and observed iteration (implicit: per time step), the input first (scheme `input`, iteration 0). Columns: `rms`, `max` (distance to the reference; empty without one), `volume_ratio` (closed meshes), `area_ratio`, `removed_sa`, `removed_sq`, `removed_sz`, `shift` (the removed residual), `min_angle_deg`, `flipped_faces`."
    );
    let _ = writeln!(
        s,
        "- `results.json`: the settings, the best observations and the same rows."
    );
    if !results.best.is_empty() {
        let _ = writeln!(
            s,
            "- `best-<scheme>-<method>.ply`: the mesh at each scheme's and method's smallest RMS (binary PLY, the input's faces)."
        );
    }
    let _ = writeln!(
        s,
        "- `timings.csv`: smoothing time per run (differs from run to run).\n"
    );
}

/// The smoothing time of every run (differs from run to run).
fn timing_section(s: &mut String, results: &ScanResults) {
    let _ = writeln!(s, "{TIME_HEADING}\n");
    let _ = writeln!(
        s,
        "Smoothing time per run, metrics excluded (this section differs from run to run), {} threads available; the whole study took {:.1} s.\n",
        rayon::current_num_threads(),
        results.wall_time_s
    );
    let _ = writeln!(s, "| scheme | method | smoothing time (s) |");
    let _ = writeln!(s, "|---|---|---:|");
    for t in &results.timings {
        let _ = writeln!(s, "| {} | {} | {:.3} |", t.scheme, t.method, t.smoothing_s);
    }
}

fn best_sections(s: &mut String, results: &ScanResults, base_rms: f64) {
    let config = &results.config;
    let Some(overall) = results
        .best
        .iter()
        .reduce(|a, b| if b.rms < a.rms { b } else { a })
    else {
        return;
    };
    let _ = writeln!(s, "## Recommendation\n");
    let better = overall.rms < base_rms;
    let _ = writeln!(
        s,
        "The smallest RMS distance to the reference, {} (the input's: {}, {}), comes from **{} weights with the {} method at {}**; `beltrami smooth INPUT OUT {}` reproduces `{}`.{}\n",
        num(overall.rms),
        num(base_rms),
        percent_change(overall.rms, base_rms),
        overall.scheme,
        overall.method,
        if overall.method == "implicit" {
            format!("one step of time step {}", overall.step)
        } else {
            format!("{} iterations", overall.iteration)
        },
        smooth_options(
            config,
            &overall.scheme,
            &overall.method,
            overall.iteration,
            overall.step
        ),
        overall.file,
        if better {
            ""
        } else {
            " No observation comes closer to the reference than the input itself: smoothing does not help here."
        }
    );
    if let Some(default) = results
        .rows
        .iter()
        .find(|r| r.scheme == "cotangent" && r.method == "plain" && r.iteration == 10)
        .and_then(|r| r.rms.map(|rms| (r, rms)))
    {
        let _ = writeln!(
            s,
            "`beltrami smooth`'s defaults (cotangent, plain, λ = 0.8, 10 iterations) give an RMS of {} ({} against the input): {}.\n",
            num(default.1),
            percent_change(default.1, base_rms),
            if default.1 > base_rms {
                "further from the reference than the input"
            } else {
                "closer to the reference than the input"
            }
        );
    }
    let _ = writeln!(s, "## Best iteration count per scheme and method\n");
    let _ = writeln!(
        s,
        "The observation with the smallest RMS distance to the reference. \"vs input\" compares it with the input's RMS ({}); a count marked † is the last one observed, so the minimum may lie beyond it.\n",
        num(base_rms)
    );
    let _ = writeln!(
        s,
        "| scheme | method | best count | RMS | vs input | max | file |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---|");
    let _ = writeln!(
        s,
        "| input | – | 0 | {} | – | {} | – |",
        num(base_rms),
        onum(results.baseline().max)
    );
    for b in &results.best {
        let count = if b.method == "implicit" {
            format!("1 step of {}", b.step)
        } else {
            b.iteration.to_string()
        };
        let _ = writeln!(
            s,
            "| {} | {} | {}{} | {} | {} | {} | `{}` |",
            b.scheme,
            b.method,
            count,
            if b.at_last_observed { " †" } else { "" },
            num(b.rms),
            percent_change(b.rms, base_rms),
            num(b.max),
            b.file
        );
    }
    let _ = writeln!(s);
}

fn effect_section(s: &mut String, results: &ScanResults) {
    let config = &results.config;
    let closed = results.input.mesh.is_closed();
    let with_ref = results.baseline().rms.is_some();
    let _ = writeln!(s, "## What smoothing removes and how much it shrinks\n");
    let _ = writeln!(
        s,
        "Per scheme and method at {} iterations (where observed; implicit: every time step). The *removed residual* is the input's signed normal deviation from the smoothed mesh (as `beltrami residual INPUT SMOOTHED` measures it): Sq and Sz (ISO 25178-2) say how much noise and texture the smoothing took away; its area-weighted mean, the shift, is the mean displacement against the smoothed surface's normals (positive: the surface moved against its normals, inwards on a closed mesh: shrinkage). {} Minimum angle and flipped faces (normals turned by more than 90° against the input) show the mesh quality.{}\n",
        REPORT_ITERATIONS
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", "),
        if closed {
            "The volume ratio is the enclosed volume over the input's."
        } else {
            "The mesh is open, so the shrinkage shows in the shift and the area ratio (surface area over the input's)."
        },
        if with_ref {
            ""
        } else {
            " Without a reference no row is \"best\": a larger Sq removed is more noise gone or more form lost, which only a reference can tell apart; the shift and the volume or area ratio show when the form starts to go."
        }
    );
    let mut header = String::from("| scheme | method | count |");
    let mut rule = String::from("|---|---|---:|");
    if with_ref {
        header.push_str(" RMS |");
        rule.push_str("---:|");
    }
    if closed {
        header.push_str(" volume ratio |");
        rule.push_str("---:|");
    }
    header.push_str(" area ratio | shift | removed Sq | removed Sz | min angle (°) | flipped |");
    rule.push_str("---:|---:|---:|---:|---:|---:|");
    let _ = writeln!(s, "{header}\n{rule}");
    let line = |s: &mut String, r: &ScanRow, count: String| {
        let mut l = format!("| {} | {} | {} |", r.scheme, r.method, count);
        if with_ref {
            let _ = write!(l, " {} |", onum(r.rms));
        }
        if closed {
            let _ = write!(l, " {} |", onum(r.volume_ratio));
        }
        let _ = write!(
            l,
            " {} | {} | {} | {} | {} | {} |",
            num(r.area_ratio),
            onum(r.shift),
            onum(r.removed_sq),
            onum(r.removed_sz),
            onum(r.min_angle_deg),
            r.flipped_faces
                .map_or_else(|| "–".into(), |n| n.to_string())
        );
        let _ = writeln!(s, "{l}");
    };
    line(s, results.baseline(), "0".into());
    for scheme in &config.schemes {
        for method in &config.methods {
            for r in results.rows_of(scheme.name(), method.label()) {
                if *method == ScanMethod::Implicit || REPORT_ITERATIONS.contains(&r.iteration) {
                    line(s, r, count_text(r));
                }
            }
        }
    }
    let _ = writeln!(s);
}
