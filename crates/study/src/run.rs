//! Running the study: one smoothing run per surface and scheme, observed at every
//! requested iteration.

use std::ops::ControlFlow;
use std::time::Instant;

use beltrami_halfedge::{DVec3, MeshData};
use beltrami_smooth::{SmoothConfig, Smoother};
use beltrami_surfaces::{Size, SurfaceKind, add_normal_noise};
use beltrami_weights::LaplacianOptions;
use rayon::prelude::*;

use crate::case::SurfaceCase;
use crate::config::StudyConfig;
use crate::countermeasures::countermeasure_surface;
use crate::error::StudyError;
use crate::measure::{Measured, Reference};
use crate::preservation::{self, EdgePreservation, EdgePreservationOptions};
use crate::remeshing::{RemeshComparison, remesh_comparison};
use crate::results::Row;
use crate::scan::{ScanConfig, ScanResults, ScanSurface, run_scan};
use crate::timing::{Timings, time_schemes};
use crate::units::{UnitsComparison, units_comparison};

/// The cut-off wavelength of the density comparison on unit spheres, in radii.
pub const UNITS_CUTOFF: f64 = 0.5;

/// The positions of one run at one observed iteration.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// Iterations done.
    pub iteration: usize,
    /// Cumulative smoothing wall time, seconds.
    pub time_s: f64,
    /// Vertices that could not move in that iteration.
    pub stuck_vertices: usize,
    /// The positions.
    pub positions: Vec<DVec3>,
}

/// One scheme's run on one surface.
#[derive(Clone, Debug)]
pub struct SchemeRun {
    /// The scheme's name.
    pub scheme: String,
    /// The observed iterations, ascending.
    pub snapshots: Vec<Snapshot>,
    /// Every iteration from 1 to [`EARLY_ITERATIONS`] (or the run's length), for the
    /// RMS-optimal iteration count; empty for counter-measure runs.
    pub early: Vec<Snapshot>,
}

/// Every iteration up to this one is observed (RMS only), for the RMS-optimal
/// iteration count, which lies at a few iterations on the paper's surfaces.
pub const EARLY_ITERATIONS: usize = 10;

/// The RMS distance to the clean surface of one run at one iteration (early iterations
/// and the observed ones, every seed).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RmsPoint {
    /// The surface's name.
    pub surface: String,
    /// The scheme's name (`"input"` at iteration 0).
    pub scheme: String,
    /// The seed of the noise.
    pub seed: u64,
    /// Iterations done.
    pub iteration: usize,
    /// RMS distance to the clean surface, in the surface's unit.
    pub rms: f64,
}

/// Everything the study computed for one surface.
#[derive(Debug)]
pub struct SurfaceResult {
    /// The surface.
    pub case: SurfaceCase,
    /// One run per scheme, in the configured order.
    pub runs: Vec<SchemeRun>,
    /// The metrics of the noisy input and of every snapshot.
    pub measured: Vec<Measured>,
    /// The metrics of the counter-measure runs (see
    /// [`StudyConfig::countermeasures`]); their rows name the scheme as
    /// `scheme/label`, e.g. `cotangent/taubin`. Empty for surfaces without them.
    pub countermeasures: Vec<Measured>,
    /// The rows of the further noise seeds (see [`StudyConfig::seeds`]): the same
    /// schemes and iterations from inputs with other noise.
    pub seed_rows: Vec<Row>,
    /// The RMS at every iteration from 0 to [`EARLY_ITERATIONS`] and at every observed
    /// iteration, per scheme and seed.
    pub rms_curve: Vec<RmsPoint>,
    /// The largest stable explicit step of the cotangent scheme with the paper's
    /// Eq. 6 normalisation (by the mixed vertex area) on the noisy input, in length²
    /// ([`Smoother::stable_step_limit`]); `None` without the cotangent scheme.
    pub area_step_limit: Option<f64>,
}

/// The study's results.
#[derive(Debug)]
pub struct StudyResults {
    /// The configuration that produced them.
    pub config: StudyConfig,
    /// Per surface, in the configured order.
    pub surfaces: Vec<SurfaceResult>,
    /// The edge-preserving scheme against its reference on the block, at equal
    /// smoothness of the flat sides (see [`StudyConfig::edge_comparison`]).
    pub edge_preservation: Option<EdgePreservation>,
    /// Filtering unit spheres of several densities with one cut-off wavelength against
    /// one λ × iterations (with the counter-measure scheme; `None` without it or
    /// without the sphere).
    pub units: Option<UnitsComparison>,
    /// Remeshing before smoothing against the original meshes (see
    /// [`StudyConfig::remesh`]).
    pub remeshing: Option<RemeshComparison>,
    /// Timings apart from the runs (see [`StudyConfig::timing`]); never in the rows.
    pub timings: Option<Timings>,
    /// The study of the noisy block as a given surface (see
    /// [`StudyConfig::scan_example`]).
    pub scan: Option<ScanResults>,
    /// Wall time of the whole study, seconds.
    pub wall_time_s: f64,
}

impl StudyResults {
    /// One row per surface, scheme and iteration (the noisy input as iteration 0 with
    /// scheme `"input"`), in the configured order.
    #[must_use]
    pub fn rows(&self) -> Vec<Row> {
        self.surfaces
            .iter()
            .flat_map(|s| s.measured.iter().map(|m| m.row.clone()))
            .collect()
    }

    /// [`rows`](Self::rows) followed by the rows of the further noise seeds.
    #[must_use]
    pub fn all_seed_rows(&self) -> Vec<Row> {
        let mut rows = self.rows();
        rows.extend(
            self.surfaces
                .iter()
                .flat_map(|s| s.seed_rows.iter().cloned()),
        );
        rows
    }
}

/// What the study reports while it runs.
#[derive(Clone, Copy, Debug)]
pub enum Progress<'a> {
    /// A run starts: surface, scheme, number of iterations.
    RunStarted(&'a str, &'a str, usize),
    /// An iteration of the current run is done.
    Iteration(usize),
    /// The current run is done.
    RunFinished,
}

fn prepare(kind: SurfaceKind, config: &StudyConfig) -> Result<SurfaceCase, StudyError> {
    let clean = kind.generate_sized(config.size);
    let mesh = clean
        .mesh()
        .map_err(|e| StudyError::Config(format!("surface {}: {e}", clean.name)))?;
    with_noise(kind, clean, mesh, config, config.seed)
}

fn with_noise(
    kind: SurfaceKind,
    clean: beltrami_surfaces::Surface,
    mesh: beltrami_halfedge::HalfedgeMesh,
    config: &StudyConfig,
    seed: u64,
) -> Result<SurfaceCase, StudyError> {
    let (noisy, sigma) = add_normal_noise(&mesh, &clean.positions, config.noise, seed)
        .map_err(|e| StudyError::Config(format!("noise on {}: {e}", clean.name)))?;
    Ok(SurfaceCase {
        kind,
        clean,
        noisy,
        sigma,
        mesh,
        seed,
    })
}

/// `smooth` with its steps read as the study reads them under area normalisation: λ (in
/// (0, 1], as with weight-sum rows) and a Taubin μ are fractions of the run's largest
/// stable explicit step on `positions` ([`beltrami_smooth::area_step`]), so that every
/// surface, whatever its unit and density, and every scheme take the same share of its
/// stable range, as λ does of the weight sum's (stable up to 1). Unchanged with
/// weight-sum rows, or when no row moves.
///
/// # Errors
/// The operator's, as [`Smoother::new`] reports them.
pub(crate) fn with_area_steps(
    mesh: &beltrami_halfedge::HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn beltrami_weights::WeightScheme,
    mut smooth: SmoothConfig,
) -> Result<SmoothConfig, beltrami_smooth::SmoothError> {
    if smooth.laplacian.normalization == beltrami_weights::Normalization::WeightSum {
        return Ok(smooth);
    }
    if let Some(limit) = beltrami_smooth::area_step(mesh, positions, scheme, &smooth, 1.0)? {
        smooth.lambda *= limit;
        if let beltrami_smooth::Method::Taubin { mu } = smooth.method {
            smooth.method = beltrami_smooth::Method::Taubin { mu: mu * limit };
        }
    }
    Ok(smooth)
}

fn smooth_config(config: &StudyConfig) -> SmoothConfig {
    SmoothConfig::new(config.lambda, config.max_iterations())
        .boundary(config.boundary)
        .update(config.update)
        .laplacian(
            LaplacianOptions::new()
                .normalization(config.normalization)
                .negative(config.negative),
        )
}

/// Runs the study. Smoothing runs one after the other (so their timings are not
/// disturbed); metrics are computed afterwards, in parallel.
///
/// Per surface, in the configured order: the scheme runs, the counter-measure runs,
/// the metrics of every snapshot, then the density comparison (on the sphere) and the
/// edge-preservation comparison (on the block). After all surfaces: the timings (one
/// run after the other) and the remeshing comparison (in parallel over the surfaces).
///
/// # Errors
/// [`StudyError::Config`] for an invalid configuration, [`StudyError::Smooth`] and
/// [`StudyError::Metrics`] naming the surface and scheme that failed.
pub fn run_study(
    config: &StudyConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<StudyResults, StudyError> {
    config.validate()?;
    let start = Instant::now();
    let mut surfaces = Vec::with_capacity(config.surfaces.len());
    let mut edge_preservation = None;
    let mut units = None;
    for &kind in &config.surfaces {
        let case = prepare(kind, config)?;
        let runs = run_schemes(&case, config, progress)?;
        let cm_runs = run_countermeasures(&case, config, progress)?;
        let (measured, countermeasures) = measure_runs(&case, &runs, &cm_runs)?;
        let mut rms_curve = rms_curve(&case, &runs, &measured)?;
        let mut seed_rows = Vec::new();
        let seed_config = StudyConfig {
            schemes: config.seed_schemes(),
            ..config.clone()
        };
        for k in 1..config.seeds {
            let other = with_noise(
                kind,
                case.clean.clone(),
                case.mesh.clone(),
                config,
                config.seed.wrapping_add(k as u64),
            )?;
            let other_runs = run_schemes(&other, &seed_config, progress)?;
            let (other_measured, _) = measure_runs(&other, &other_runs, &[])?;
            rms_curve.extend(self::rms_curve(&other, &other_runs, &other_measured)?);
            seed_rows.extend(other_measured.into_iter().map(|m| m.row));
        }
        if let Some(comparison) = sphere_units(kind, config)? {
            units = Some(comparison);
        }
        if let Some(comparison) = block_edges(kind, &case, config)? {
            edge_preservation = Some(comparison);
        }
        let area_step_limit = area_step_limit(&case, config);
        surfaces.push(SurfaceResult {
            case,
            runs,
            measured,
            countermeasures,
            seed_rows,
            rms_curve,
            area_step_limit,
        });
    }
    let cases: Vec<&SurfaceCase> = surfaces.iter().map(|s| &s.case).collect();
    let timings = if config.timing {
        Some(time_schemes(&cases, &config.seed_schemes(), config)?)
    } else {
        None
    };
    let cotangent = config.schemes.iter().find(|s| s.name() == "cotangent");
    let remeshing = match (&config.remesh, cotangent) {
        (Some(options), Some(scheme)) => {
            Some(remesh_comparison(&cases, config, options, scheme.as_ref())?)
        }
        _ => None,
    };
    let scan = if config.scan_example {
        scan_example(&cases, config)?
    } else {
        None
    };
    Ok(StudyResults {
        config: config.clone(),
        surfaces,
        edge_preservation,
        units,
        remeshing,
        timings,
        scan,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// The study of a given surface ([`run_scan`]) on the first seed's noisy block against
/// the clean block, with the paper's schemes among the configured ones; `None` without
/// the block or without any of them.
fn scan_example(
    cases: &[&SurfaceCase],
    config: &StudyConfig,
) -> Result<Option<ScanResults>, StudyError> {
    let Some(block) = cases.iter().find(|c| c.kind == SurfaceKind::Block) else {
        return Ok(None);
    };
    let schemes: Vec<_> = config
        .schemes
        .iter()
        .filter(|s| crate::PAPER_SCHEMES.contains(&s.name()))
        .cloned()
        .collect();
    if schemes.is_empty() {
        return Ok(None);
    }
    let faces = block.clean.faces.clone();
    let input = ScanSurface::new(
        format!("noisy block (seed {})", block.seed),
        MeshData::new(block.noisy.clone(), faces.clone()),
    )?;
    let reference = ScanSurface::new("clean block", block.clean.data.clone())?;
    let scan = ScanConfig::default()
        .schemes(schemes)
        .lambda(config.lambda)
        .update(config.update);
    run_scan(input, Some(reference), &scan, &mut |_| {}).map(Some)
}

/// The largest stable explicit step of the cotangent scheme normalised by the mixed
/// vertex area (paper Eq. 6) on the noisy input, in length²; `None` without the
/// cotangent scheme or when the operator cannot be set up (an auxiliary figure never
/// fails the study). A curve boundary, which needs the weight sum, counts as free.
fn area_step_limit(case: &SurfaceCase, config: &StudyConfig) -> Option<f64> {
    let cotangent = config.schemes.iter().find(|s| s.name() == "cotangent")?;
    let boundary = match config.boundary {
        beltrami_smooth::Boundary::Curve => beltrami_smooth::Boundary::Free,
        b => b,
    };
    let smooth = SmoothConfig::new(config.lambda, 1)
        .boundary(boundary)
        .laplacian(
            LaplacianOptions::new()
                .normalization(beltrami_weights::Normalization::Area(
                    beltrami_halfedge::geometry::VertexAreaKind::MixedVoronoi,
                ))
                .negative(config.negative),
        );
    Smoother::new(&case.mesh, &case.noisy, cotangent.as_ref(), smooth)
        .ok()?
        .stable_step_limit()
}

/// One run per configured scheme on `case`, in the configured order.
fn run_schemes(
    case: &SurfaceCase,
    config: &StudyConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<SchemeRun>, StudyError> {
    let mut runs = Vec::with_capacity(config.schemes.len());
    for scheme in &config.schemes {
        let run = run_reported(
            case,
            scheme.as_ref(),
            scheme.name(),
            config,
            smooth_config(config),
            true,
            progress,
        )?;
        runs.push(run);
    }
    Ok(runs)
}

/// The counter-measure runs on `case` (named `scheme/label`): none without a
/// counter-measure scheme or on a surface that does not get them, and only the
/// counter-measures that apply to the mesh (open or closed).
fn run_countermeasures(
    case: &SurfaceCase,
    config: &StudyConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<SchemeRun>, StudyError> {
    let mut runs = Vec::new();
    let Some(scheme) = &config.countermeasure_scheme else {
        return Ok(runs);
    };
    if !countermeasure_surface(case.kind) {
        return Ok(runs);
    }
    for cm in &config.countermeasures {
        if !cm.applies(case.mesh.is_closed()) {
            continue;
        }
        let label = format!("{}/{}", scheme.name(), cm.label);
        let smooth = smooth_config(config)
            .lambda(cm.lambda)
            .method(cm.method)
            .preserve_volume(cm.preserve_volume)
            .update(if cm.weights_once {
                beltrami_smooth::WeightUpdate::Once
            } else {
                config.update
            });
        runs.push(run_reported(
            case,
            scheme.as_ref(),
            &label,
            config,
            smooth,
            false,
            progress,
        )?);
    }
    Ok(runs)
}

/// [`run_one`] between the progress reports of its start and end, with a failure named
/// by surface and `label`.
fn run_reported(
    case: &SurfaceCase,
    scheme: &dyn beltrami_weights::WeightScheme,
    label: &str,
    config: &StudyConfig,
    smooth: SmoothConfig,
    early: bool,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<SchemeRun, StudyError> {
    progress(Progress::RunStarted(
        case.clean.name,
        label,
        config.max_iterations(),
    ));
    let run = run_one(
        case,
        scheme,
        label,
        &config.iterations,
        smooth,
        early,
        progress,
    )
    .map_err(|source| StudyError::Smooth {
        surface: case.clean.name.to_string(),
        scheme: label.to_string(),
        source,
    })?;
    progress(Progress::RunFinished);
    Ok(run)
}

/// The metrics, in parallel, of the noisy input (as scheme `"input"`, iteration 0) and
/// every snapshot of `runs`, and of every snapshot of the counter-measure runs.
fn measure_runs(
    case: &SurfaceCase,
    runs: &[SchemeRun],
    cm_runs: &[SchemeRun],
) -> Result<(Vec<Measured>, Vec<Measured>), StudyError> {
    let failed = |scheme: &str, source| StudyError::Metrics {
        surface: case.clean.name.to_string(),
        scheme: scheme.to_string(),
        source,
    };
    let reference = Reference::new(case).map_err(|source| failed("input", source))?;
    let mut jobs: Vec<(&str, usize, f64, usize, &[DVec3])> =
        vec![("input", 0, 0.0, 0, &case.noisy)];
    for run in runs {
        for s in &run.snapshots {
            jobs.push((
                &run.scheme,
                s.iteration,
                s.time_s,
                s.stuck_vertices,
                &s.positions,
            ));
        }
    }
    let measured = jobs
        .par_iter()
        .map(|&(scheme, iteration, time_s, stuck, positions)| {
            reference
                .measure(scheme, iteration, time_s, stuck, positions)
                .map_err(|source| failed(scheme, source))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let countermeasures = cm_runs
        .par_iter()
        .flat_map_iter(|run| run.snapshots.iter().map(move |s| (run, s)))
        .map(|(run, s)| {
            reference
                .measure(
                    &run.scheme,
                    s.iteration,
                    s.time_s,
                    s.stuck_vertices,
                    &s.positions,
                )
                .map_err(|source| failed(&run.scheme, source))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((measured, countermeasures))
}

/// The RMS of the input, of every early iteration and of every observed iteration, for
/// each run of `case`.
fn rms_curve(
    case: &SurfaceCase,
    runs: &[SchemeRun],
    measured: &[Measured],
) -> Result<Vec<RmsPoint>, StudyError> {
    let reference = Reference::new(case).map_err(|source| StudyError::Metrics {
        surface: case.clean.name.to_string(),
        scheme: "input".to_string(),
        source,
    })?;
    let point = |scheme: &str, iteration: usize, rms: f64| RmsPoint {
        surface: case.clean.name.to_string(),
        scheme: scheme.to_string(),
        seed: case.seed,
        iteration,
        rms,
    };
    let early: Vec<(&str, &Snapshot)> = runs
        .iter()
        .flat_map(|r| {
            r.early
                .iter()
                .filter(|s| !r.snapshots.iter().any(|t| t.iteration == s.iteration))
                .map(move |s| (r.scheme.as_str(), s))
        })
        .collect();
    let mut out: Vec<RmsPoint> = early
        .par_iter()
        .map(|&(scheme, s)| {
            reference
                .rms(&s.positions)
                .map(|rms| point(scheme, s.iteration, rms))
                .map_err(|source| StudyError::Metrics {
                    surface: case.clean.name.to_string(),
                    scheme: scheme.to_string(),
                    source,
                })
        })
        .collect::<Result<_, _>>()?;
    out.extend(
        measured
            .iter()
            .map(|m| point(&m.row.scheme, m.row.iteration, m.row.rms)),
    );
    let order = |scheme: &str| runs.iter().position(|r| r.scheme == scheme);
    out.sort_by_key(|p| (order(&p.scheme), p.iteration));
    Ok(out)
}

/// On the sphere, with a counter-measure scheme: unit spheres of several densities
/// filtered with one cut-off wavelength ([`UNITS_CUTOFF`]) against one λ × iterations.
fn sphere_units(
    kind: SurfaceKind,
    config: &StudyConfig,
) -> Result<Option<UnitsComparison>, StudyError> {
    let Some(scheme) = &config.countermeasure_scheme else {
        return Ok(None);
    };
    if kind != SurfaceKind::Sphere {
        return Ok(None);
    }
    let levels: &[u32] = match config.size {
        Size::Paper => &[3, 4, 5, 6],
        _ => &[2, 3, 4],
    };
    let comparison = units_comparison(scheme.as_ref(), config.lambda, UNITS_CUTOFF, levels)
        .map_err(|source| StudyError::Smooth {
            surface: "sphere (cut-off)".to_string(),
            scheme: scheme.name().to_string(),
            source,
        })?;
    Ok(Some(comparison))
}

/// On the block, with an edge comparison configured: the edge-preserving scheme against
/// its reference at equal smoothness of the flat sides, with the study's λ.
fn block_edges(
    kind: SurfaceKind,
    case: &SurfaceCase,
    config: &StudyConfig,
) -> Result<Option<EdgePreservation>, StudyError> {
    let Some((scheme, reference)) = &config.edge_comparison else {
        return Ok(None);
    };
    if kind != SurfaceKind::Block {
        return Ok(None);
    }
    let options = EdgePreservationOptions::new().lambda(config.lambda);
    let comparison = preservation::edge_preservation(
        &case.mesh,
        &case.clean.positions,
        &case.noisy,
        scheme.as_ref(),
        reference.as_ref(),
        &options,
    )?;
    Ok(Some(comparison))
}

fn run_one(
    case: &SurfaceCase,
    scheme: &dyn beltrami_weights::WeightScheme,
    label: &str,
    iterations: &[usize],
    smooth_config: SmoothConfig,
    record_early: bool,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<SchemeRun, beltrami_smooth::SmoothError> {
    let mut snapshots = Vec::with_capacity(iterations.len());
    let mut early = Vec::new();
    let mut wanted = iterations.iter().copied().peekable();
    let smooth_config = with_area_steps(&case.mesh, &case.noisy, scheme, smooth_config)?;
    // Smoothing time only: the clock runs while the smoother works and stops while the
    // observer copies positions.
    let mut elapsed = 0.0;
    let mut resumed = Instant::now();
    let smoother = Smoother::new(&case.mesh, &case.noisy, scheme, smooth_config)?;
    // An explicit step by the area normalisation beyond the stable limit makes the high
    // frequencies grow: refused, as `smooth` refuses it (a fraction in (0, 1] of the
    // limit never is).
    smoother.check_stable_steps()?;
    elapsed += resumed.elapsed().as_secs_f64();
    resumed = Instant::now();
    smoother.run(|it| {
        elapsed += resumed.elapsed().as_secs_f64();
        progress(Progress::Iteration(it.index));
        if record_early && it.index <= EARLY_ITERATIONS {
            early.push(Snapshot {
                iteration: it.index,
                time_s: elapsed,
                stuck_vertices: it.stats().stuck_vertices,
                positions: it.positions().to_vec(),
            });
        }
        if wanted.peek() == Some(&it.index) {
            wanted.next();
            snapshots.push(Snapshot {
                iteration: it.index,
                time_s: elapsed,
                stuck_vertices: it.stats().stuck_vertices,
                positions: it.positions().to_vec(),
            });
        }
        resumed = Instant::now();
        ControlFlow::Continue(())
    })?;
    Ok(SchemeRun {
        scheme: label.to_string(),
        snapshots,
        early,
    })
}
