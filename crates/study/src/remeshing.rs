//! Remeshing before smoothing: the paper prepares its meshes in MeshLab (an isotropic
//! remesh) before adding noise. Per surface, the clean mesh is remeshed
//! ([`beltrami_algorithms::remesh`], feature edges kept), noise of the same level and
//! seed is added, and the cotangent scheme smooths both inputs; the section shows what
//! remeshing does to the negative cotangent weights, the smallest angle and the
//! cotangent scheme's RMS distance to the clean surface.

use std::ops::ControlFlow;

use beltrami_algorithms::{EdgeLength, RemeshOptions, mesh_quality, remesh};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_metrics::distance::{DistanceStats, SurfaceIndex};
use beltrami_smooth::{SmoothConfig, Smoother, Statistics};
use beltrami_surfaces::add_normal_noise;
use beltrami_weights::{LaplacianOptions, WeightScheme};
use rayon::prelude::*;
use serde::Serialize;

use crate::case::SurfaceCase;
use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::measure::FEATURE_THRESHOLD_DEG;
use crate::run::EARLY_ITERATIONS;

/// The remeshing iterations of the study's default (split–collapse–flip–relax): three
/// bring the edge-length variation of the paper's surfaces most of the way to its
/// value after ten at a third of the cost.
pub const REMESH_ITERATIONS: usize = 3;

/// The longer iteration count the remeshing comparison reports beside 10 (the paper's
/// count).
pub const REMESH_LONG_ITERATIONS: usize = 100;

/// The study's default remeshing: target edge length the clean mesh's mean edge length,
/// [`REMESH_ITERATIONS`] iterations, edges sharper than [`FEATURE_THRESHOLD_DEG`] kept
/// as features (the block's edges), vertices projected back onto the clean mesh's
/// triangles.
///
/// The projection is the faceted one ([`RemeshOptions::smooth_projection`] off), as
/// MeshLab's, the paper's tool: the comparison measures distances to the clean mesh, and
/// a lift onto the smooth surface through its triangles would move every remeshed vertex
/// off them by up to a triangle's sagitta, a change of geometry where the comparison asks
/// only what a new triangulation does.
#[must_use]
pub fn default_remesh() -> RemeshOptions {
    RemeshOptions::default()
        .relative_edge_length(1.0)
        .iterations(REMESH_ITERATIONS)
        .feature_angle(FEATURE_THRESHOLD_DEG.to_radians())
        .smooth_projection(false)
}

/// Mesh figures that decide how cotangent weights behave.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshFigures {
    /// Vertices.
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
    /// Mean edge length of the clean mesh, in the surface's unit.
    pub mean_edge_length: f64,
    /// Share of the clean mesh's interior edges with a negative cotangent weight
    /// (`cot α + cot β < 0`), 0 to 1.
    pub negative_share_clean: f64,
    /// The same share on the noisy input, 0 to 1.
    pub negative_share_noisy: f64,
    /// The smallest corner angle of the clean mesh, degrees.
    pub min_angle_deg: Option<f64>,
    /// The noise σ added, in the surface's unit.
    pub sigma: f64,
}

/// The cotangent scheme's RMS distance to the clean surface on one input.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CotangentRms {
    /// RMS of the noisy input, in the surface's unit.
    pub input: f64,
    /// The iteration (1 to [`EARLY_ITERATIONS`]) with the smallest RMS.
    pub optimum_iteration: usize,
    /// The RMS there.
    pub optimum: f64,
    /// The RMS after 10 iterations.
    pub at_10: f64,
    /// The RMS after [`REMESH_LONG_ITERATIONS`] iterations.
    pub at_long: f64,
}

/// One surface before and after remeshing.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RemeshRow {
    /// The surface's name.
    pub surface: String,
    /// The surface's length unit.
    pub unit: String,
    /// The target edge length the remesh aimed at, in the surface's unit.
    pub target_edge_length: f64,
    /// The largest distance of a remeshed vertex from the clean surface.
    pub hausdorff: f64,
    /// The original mesh.
    pub before: MeshFigures,
    /// The remeshed mesh.
    pub after: MeshFigures,
    /// Cotangent smoothing of the original noisy input.
    pub original: CotangentRms,
    /// Cotangent smoothing of the remeshed noisy input (distances to the original
    /// clean surface).
    pub remeshed: CotangentRms,
}

/// The remeshing comparison of a study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RemeshComparison {
    /// The target edge length as configured, in words.
    pub target: String,
    /// Remeshing iterations.
    pub iterations: usize,
    /// The feature angle, degrees (`None`: no feature edges).
    pub feature_angle_deg: Option<f64>,
    /// One row per surface, in the study's order.
    pub rows: Vec<RemeshRow>,
}

/// Fewer vertices than this after remeshing: the surface is no longer resolved, and the
/// row says nothing about the scheme ([`RemeshComparison::cautions`]).
pub const TOO_COARSE_VERTICES: usize = 100;

impl RemeshComparison {
    /// One sentence per surface whose remeshed mesh has fewer than
    /// [`TOO_COARSE_VERTICES`] vertices: the target edge length is close to the
    /// surface's size, so the remeshed mesh no longer resembles it (a sphere remeshed
    /// with a target of its diameter is a tetrahedron). The report prints them in its
    /// remeshing section and the CLI on standard error; empty when every surface is
    /// resolved.
    #[must_use]
    pub fn cautions(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter(|r| r.after.vertices < TOO_COARSE_VERTICES)
            .map(|r| {
                format!(
                    "the remeshed {} has only {} vertices (from {}; mean edge length {} against {} before): the target edge length is close to the surface's size, so its remeshing rows say nothing about the scheme; choose a shorter --remesh or --remesh-relative",
                    r.surface,
                    r.after.vertices,
                    r.before.vertices,
                    crate::findings::sig(r.after.mean_edge_length),
                    crate::findings::sig(r.before.mean_edge_length),
                )
            })
            .collect()
    }
}

/// The target edge length of `options` in words.
#[must_use]
pub fn describe_target(options: &RemeshOptions) -> String {
    match options.edge_length {
        EdgeLength::Absolute(l) => format!("L = {l} (in each surface's unit)"),
        EdgeLength::Relative(1.0) => "L = the clean mesh's mean edge length".into(),
        EdgeLength::Relative(r) => format!("L = {r} × the clean mesh's mean edge length"),
        EdgeLength::Adaptive(_) => "curvature-adaptive".into(),
        _ => "other".into(),
    }
}

/// Runs the comparison on every surface (in parallel over the surfaces; the smoothing
/// times are not reported, so parallel work does not disturb them), with the study's
/// λ, boundary, update policy, noise level and first seed.
///
/// # Errors
/// [`StudyError::Config`] when a surface cannot be remeshed or get noise,
/// [`StudyError::Smooth`] and [`StudyError::Metrics`] naming the surface.
pub(crate) fn remesh_comparison(
    cases: &[&SurfaceCase],
    config: &StudyConfig,
    options: &RemeshOptions,
    scheme: &dyn WeightScheme,
) -> Result<RemeshComparison, StudyError> {
    let rows = cases
        .par_iter()
        .map(|case| remesh_row(case, config, options, scheme))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RemeshComparison {
        target: describe_target(options),
        iterations: options.iterations,
        feature_angle_deg: options.feature_angle.map(f64::to_degrees),
        rows,
    })
}

fn figures(
    mesh: &HalfedgeMesh,
    clean: &[DVec3],
    noisy: &[DVec3],
    sigma: f64,
    name: &str,
) -> Result<MeshFigures, StudyError> {
    let failed = |e: beltrami_algorithms::QualityError| {
        StudyError::Config(format!("mesh quality of {name}: {e}"))
    };
    let q = mesh_quality(mesh, clean).map_err(failed)?;
    let qn = mesh_quality(mesh, noisy).map_err(failed)?;
    Ok(MeshFigures {
        vertices: mesh.n_vertices(),
        faces: mesh.n_faces(),
        mean_edge_length: q.edge_length.map_or(0.0, |e| e.mean),
        negative_share_clean: q.negative_cotangent_share(),
        negative_share_noisy: qn.negative_cotangent_share(),
        min_angle_deg: q.shape.as_ref().map(|s| s.min_angle),
        sigma,
    })
}

fn remesh_row(
    case: &SurfaceCase,
    config: &StudyConfig,
    options: &RemeshOptions,
    scheme: &dyn WeightScheme,
) -> Result<RemeshRow, StudyError> {
    let name = case.clean.name;
    let (mesh, clean, report) = remesh(&case.mesh, &case.clean.positions, options)
        .map_err(|e| StudyError::Config(format!("remeshing {name}: {e}")))?;
    let (noisy, sigma) = add_normal_noise(&mesh, &clean, config.noise, config.seed)
        .map_err(|e| StudyError::Config(format!("noise on the remeshed {name}: {e}")))?;
    let metrics = |source| StudyError::Metrics {
        surface: name.to_string(),
        scheme: scheme.name().to_string(),
        source,
    };
    let index = SurfaceIndex::new(&case.mesh, &case.clean.positions).map_err(metrics)?;
    let original = cotangent_rms(&case.mesh, &case.noisy, &index, config, scheme, name)?;
    let remeshed = cotangent_rms(&mesh, &noisy, &index, config, scheme, name)?;
    Ok(RemeshRow {
        surface: name.to_string(),
        unit: case.clean.unit.to_string(),
        target_edge_length: report.target_edge_length,
        hausdorff: report.hausdorff,
        before: figures(
            &case.mesh,
            &case.clean.positions,
            &case.noisy,
            case.sigma,
            name,
        )?,
        after: figures(&mesh, &clean, &noisy, sigma, name)?,
        original,
        remeshed,
    })
}

/// The RMS distance of `positions` to the surface of `index`.
fn rms(index: &SurfaceIndex, positions: &[DVec3]) -> Result<f64, beltrami_metrics::MetricsError> {
    let d = index.distances(positions)?;
    Ok(DistanceStats::new(&d, &vec![1.0; d.len()])?.rms)
}

fn cotangent_rms(
    mesh: &HalfedgeMesh,
    noisy: &[DVec3],
    index: &SurfaceIndex,
    config: &StudyConfig,
    scheme: &dyn WeightScheme,
    name: &str,
) -> Result<CotangentRms, StudyError> {
    let smooth_failed = |source| StudyError::Smooth {
        surface: format!("{name} (remeshing comparison)"),
        scheme: scheme.name().to_string(),
        source,
    };
    let smooth = SmoothConfig::new(config.lambda, REMESH_LONG_ITERATIONS)
        .boundary(config.boundary)
        .update(config.update)
        .statistics(Statistics::OnDemand)
        .laplacian(
            LaplacianOptions::new()
                .normalization(config.normalization)
                .negative(config.negative),
        );
    let smooth = crate::run::with_area_steps(mesh, noisy, scheme, smooth).map_err(smooth_failed)?;
    let mut kept: Vec<(usize, Vec<DVec3>)> = Vec::new();
    Smoother::new(mesh, noisy, scheme, smooth)
        .map_err(smooth_failed)?
        .run(|it| {
            if it.index <= EARLY_ITERATIONS || it.index == REMESH_LONG_ITERATIONS {
                kept.push((it.index, it.positions().to_vec()));
            }
            ControlFlow::Continue(())
        })
        .map_err(smooth_failed)?;
    let metrics = |source| StudyError::Metrics {
        surface: format!("{name} (remeshing comparison)"),
        scheme: scheme.name().to_string(),
        source,
    };
    let input = rms(index, noisy).map_err(metrics)?;
    let values = kept
        .iter()
        .map(|(it, p)| rms(index, p).map(|r| (*it, r)))
        .collect::<Result<Vec<_>, _>>()
        .map_err(metrics)?;
    let at = |n: usize| {
        values
            .iter()
            .find(|(it, _)| *it == n)
            .map_or(f64::NAN, |v| v.1)
    };
    let (optimum_iteration, optimum) = values
        .iter()
        .filter(|(it, _)| *it <= EARLY_ITERATIONS)
        .copied()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, input));
    Ok(CotangentRms {
        input,
        optimum_iteration,
        optimum,
        at_10: at(10),
        at_long: at(REMESH_LONG_ITERATIONS),
    })
}

/// A share of negative weights changes only by more than this (0.1 percentage point)
/// besides [`REL_TOL`](crate::REL_TOL) of its value: shares near 0 are not compared
/// relatively.
pub const SHARE_TOL: f64 = 0.001;

/// How `after` compares with `before`: `"lower"` or `"higher"` when they differ by more
/// than `rel_tol` of `before`'s magnitude and more than `abs_tol`, `"the same"`
/// otherwise (or when either is not finite: `"not comparable"`).
#[must_use]
pub(crate) fn change_word(before: f64, after: f64, rel_tol: f64, abs_tol: f64) -> &'static str {
    if !(before.is_finite() && after.is_finite()) {
        return "not comparable";
    }
    let tol = (rel_tol * before.abs()).max(abs_tol);
    if after < before - tol {
        "lower"
    } else if after > before + tol {
        "higher"
    } else {
        "the same"
    }
}

fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

fn angle(x: Option<f64>) -> String {
    x.map_or_else(|| "–".into(), |a| format!("{a:.1}"))
}

/// The "Remeshing before smoothing" section of the report.
pub(crate) fn remesh_section(s: &mut String, comparison: &RemeshComparison, config: &StudyConfig) {
    use std::fmt::Write as _;
    remesh_intro(s, comparison, config);
    for caution in comparison.cautions() {
        let _ = writeln!(s, "**Caution:** {caution}.\n");
    }
    mesh_table(s, comparison);
    rms_table(s, comparison);
    remesh_summary(s, comparison);
}

/// The section's heading and how the comparison was made.
fn remesh_intro(s: &mut String, comparison: &RemeshComparison, config: &StudyConfig) {
    use std::fmt::Write as _;
    let tol = crate::findings::REL_TOL;
    let _ = writeln!(s, "## Remeshing before smoothing\n");
    let _ = writeln!(
        s,
        "The paper prepares its meshes in MeshLab before adding noise. Here each clean surface is remeshed isotropically (Botsch & Kobbelt 2004; {}, {} split–collapse–flip–relax iterations, {}, vertices projected back onto the clean surface), gets noise of the same level and seed {} as the study's first input, and the cotangent scheme smooths both inputs with the study's λ = {}, boundary and weight updates. Distances are to the original clean surface. One seed, so a difference counts only beyond {} % of the original value (`beltrami study --remesh L` or `--remesh-relative R` choose another target length).\n",
        comparison.target,
        comparison.iterations,
        comparison.feature_angle_deg.map_or_else(
            || "no feature edges".into(),
            |a| format!("edges whose faces meet at more than {a:.0}° kept as features")
        ),
        config.seed,
        config.lambda,
        100.0 * tol
    );
}

/// The meshes before and after remeshing: size, edge length, angles, negative weights.
fn mesh_table(s: &mut String, comparison: &RemeshComparison) {
    use std::fmt::Write as _;
    let _ = writeln!(
        s,
        "| surface | vertices | mean edge length | smallest angle (°) | negative cotangent weights, clean mesh | negative cotangent weights, noisy input |\n|---|---|---|---|---|---|"
    );
    for r in &comparison.rows {
        let u = crate::figures::unit_label(&r.unit);
        let _ = writeln!(
            s,
            "| {} | {} → {} | {} → {}{u} | {} → {} | {} → {} | {} → {} |",
            r.surface,
            r.before.vertices,
            r.after.vertices,
            crate::findings::sig(r.before.mean_edge_length),
            crate::findings::sig(r.after.mean_edge_length),
            angle(r.before.min_angle_deg),
            angle(r.after.min_angle_deg),
            pct(r.before.negative_share_clean),
            pct(r.after.negative_share_clean),
            pct(r.before.negative_share_noisy),
            pct(r.after.negative_share_noisy),
        );
    }
}

/// The cotangent scheme's RMS on the original and the remeshed input.
fn rms_table(s: &mut String, comparison: &RemeshComparison) {
    use std::fmt::Write as _;
    let _ = writeln!(
        s,
        "\nCotangent smoothing, original → remeshed input (RMS distance to the clean surface, in the surface's unit; the optimum is the smallest RMS over iterations 1 to {EARLY_ITERATIONS}):\n"
    );
    let _ = writeln!(
        s,
        "| surface | noise σ | input RMS | RMS-optimal iterations | RMS at the optimum | RMS after 10 | RMS after {REMESH_LONG_ITERATIONS} |\n|---|---|---|---|---|---|---|"
    );
    let g = crate::findings::sig;
    for r in &comparison.rows {
        let (a, b) = (&r.original, &r.remeshed);
        let u = crate::figures::unit_label(&r.unit);
        let _ = writeln!(
            s,
            "| {}{u} | {} → {} | {} → {} | {} → {} | {} → {} | {} → {} | {} → {} |",
            r.surface,
            g(r.before.sigma),
            g(r.after.sigma),
            g(a.input),
            g(b.input),
            a.optimum_iteration,
            b.optimum_iteration,
            g(a.optimum),
            g(b.optimum),
            g(a.at_10),
            g(b.at_10),
            g(a.at_long),
            g(b.at_long),
        );
    }
}

/// What remeshing changes, per surface, in words generated from the tables.
fn remesh_summary(s: &mut String, comparison: &RemeshComparison) {
    use std::fmt::Write as _;
    let tol = crate::findings::REL_TOL;
    let _ = writeln!(
        s,
        "\nWhat remeshing does (generated from the tables; RMS compared relative to each input's RMS, because σ follows each mesh's mean edge length):\n"
    );
    for r in &comparison.rows {
        let (a, b) = (&r.original, &r.remeshed);
        let neg = change_word(
            r.before.negative_share_noisy,
            r.after.negative_share_noisy,
            tol,
            SHARE_TOL,
        );
        let neg_clean = change_word(
            r.before.negative_share_clean,
            r.after.negative_share_clean,
            tol,
            SHARE_TOL,
        );
        let ang = match (r.before.min_angle_deg, r.after.min_angle_deg) {
            (Some(x), Some(y)) => change_word(x, y, tol, 0.0),
            _ => "not comparable",
        };
        let rel = |x: &CotangentRms, v: f64| v / x.input;
        let opt_word = change_word(rel(a, a.optimum), rel(b, b.optimum), tol, 0.0);
        let long_word = change_word(rel(a, a.at_long), rel(b, b.at_long), tol, 0.0);
        let _ = writeln!(
            s,
            "- **{}**: the share of negative cotangent weights is {neg} on the remeshed noisy input ({} → {}; clean mesh: {neg_clean}, {} → {}), the smallest angle {ang} ({} → {}°). The cotangent scheme's RMS at its optimum, relative to the input's, is {opt_word} ({} → {}); after {REMESH_LONG_ITERATIONS} iterations it is {long_word} ({} → {}).",
            r.surface,
            pct(r.before.negative_share_noisy),
            pct(r.after.negative_share_noisy),
            pct(r.before.negative_share_clean),
            pct(r.after.negative_share_clean),
            angle(r.before.min_angle_deg),
            angle(r.after.min_angle_deg),
            pct(rel(a, a.optimum)),
            pct(rel(b, b.optimum)),
            pct(rel(a, a.at_long)),
            pct(rel(b, b.at_long)),
        );
    }
    let _ = writeln!(
        s,
        "\nA share of negative weights counts as changed beyond {} % of its value and {} percentage point; an angle or a relative RMS beyond {} %.\n",
        100.0 * tol,
        100.0 * SHARE_TOL,
        100.0 * tol
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn change_word_uses_the_tolerance() {
        assert_eq!(change_word(1.0, 0.98, 0.01, 0.0), "lower");
        assert_eq!(change_word(1.0, 1.02, 0.01, 0.0), "higher");
        assert_eq!(change_word(1.0, 1.005, 0.01, 0.0), "the same");
        assert_eq!(change_word(1.0, 0.995, 0.01, 0.0), "the same");
        assert_eq!(change_word(0.0, 0.0, 0.01, 0.0), "the same");
        assert_eq!(change_word(0.0, 1e-9, 0.01, 0.0), "higher");
        // Near zero the absolute tolerance decides.
        assert_eq!(change_word(2e-5, 0.0, 0.01, SHARE_TOL), "the same");
        assert_eq!(change_word(0.133, 0.009, 0.01, SHARE_TOL), "lower");
        assert_eq!(change_word(f64::NAN, 1.0, 0.01, 0.0), "not comparable");
    }

    #[test]
    fn remeshing_a_block_keeps_its_edges_and_the_section_follows_the_numbers() {
        use beltrami_surfaces::{Size, SurfaceKind};
        use beltrami_weights::WeightRegistry;
        let registry = WeightRegistry::with_builtins();
        let mut config = StudyConfig::paper(&registry);
        config.size = Size::Small;
        let clean = SurfaceKind::Block.generate_sized(Size::Small);
        let mesh = clean.mesh().unwrap();
        let (noisy, sigma) = add_normal_noise(&mesh, &clean.positions, config.noise, 1).unwrap();
        let case = SurfaceCase {
            kind: SurfaceKind::Block,
            clean,
            noisy,
            sigma,
            mesh,
            seed: 1,
        };
        let cot = registry.get("cotangent").unwrap();
        let c = remesh_comparison(&[&case], &config, &default_remesh(), cot.as_ref()).unwrap();
        let r = &c.rows[0];
        // The remeshed vertices lie on the clean surface (the box keeps its edges).
        assert!(
            r.hausdorff < 1e-9 * r.target_edge_length.max(1.0),
            "{}",
            r.hausdorff
        );
        assert!((r.after.mean_edge_length / r.target_edge_length - 1.0).abs() < 0.2);
        // Smoothing helps on both inputs, and the optimum is at least as good as 10
        // iterations.
        for x in [&r.original, &r.remeshed] {
            assert!(x.optimum < x.input);
            assert!(x.optimum <= x.at_10);
            assert!((1..=EARLY_ITERATIONS).contains(&x.optimum_iteration));
        }
        let mut text = String::new();
        remesh_section(&mut text, &c, &config);
        assert!(text.starts_with("## Remeshing before smoothing"));
        let word = change_word(
            r.before.negative_share_noisy,
            r.after.negative_share_noisy,
            crate::findings::REL_TOL,
            SHARE_TOL,
        );
        assert!(text.contains(&format!("negative cotangent weights is {word}")));
        // A changed number changes the text.
        let mut other = c.clone();
        other.rows[0].remeshed.optimum = other.rows[0].original.optimum * 10.0;
        other.rows[0].remeshed.input = other.rows[0].original.input;
        let mut changed = String::new();
        remesh_section(&mut changed, &other, &config);
        assert!(changed.contains("relative to the input's, is higher"));
    }
}
