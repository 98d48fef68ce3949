//! Running the study of one given surface: every scheme × method, observed per
//! iteration.

use std::ops::ControlFlow;
use std::time::Instant;

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, MeshData};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::SurfaceIndex;
use beltrami_metrics::residual::{ArealOptions, areal_parameters, normal_residual};
use beltrami_smooth::{SmoothConfig, Smoother, Statistics};
use beltrami_weights::WeightScheme;
use rayon::prelude::*;
use serde::Serialize;

use super::config::{ScanConfig, ScanMethod};
use crate::error::StudyError;
use crate::run::Progress;

/// A surface given as a file: its name (for the report), faces and positions, and its
/// half-edge connectivity.
#[derive(Clone, Debug)]
pub struct ScanSurface {
    /// The name the report gives it (e.g. the file name).
    pub name: String,
    /// Positions and faces, as read (the best meshes are written with these faces).
    pub data: MeshData,
    /// The connectivity of `data`.
    pub mesh: HalfedgeMesh,
}

impl ScanSurface {
    /// Builds the connectivity of `data`.
    ///
    /// # Errors
    /// [`StudyError::Input`] when the faces do not form an oriented 2-manifold, when
    /// there is no face, or when a position is not finite.
    pub fn new(name: impl Into<String>, data: MeshData) -> Result<Self, StudyError> {
        let name = name.into();
        let mesh = data
            .mesh()
            .map_err(|e| StudyError::Input(format!("{name}: {e}")))?;
        if mesh.n_faces() == 0 {
            return Err(StudyError::Input(format!("{name}: the mesh has no faces")));
        }
        if let Some(i) = data.positions.iter().position(|p| !p.is_finite()) {
            return Err(StudyError::Input(format!(
                "{name}: vertex {i} has a non-finite coordinate"
            )));
        }
        Ok(Self { name, data, mesh })
    }

    fn bounding_box(&self) -> (DVec3, DVec3) {
        self.data.positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }
}

/// One observation: a scheme and method after some iterations (or the input itself).
///
/// Lengths are in the input's unit. The *removed residual* is the input's signed
/// normal deviation from the smoothed mesh (what `beltrami residual INPUT SMOOTHED`
/// measures): its ISO 25178-2 height parameters say how much texture and noise the
/// smoothing took away; its area-weighted mean (`shift`) is the mean displacement
/// against the smoothed surface's normals, positive when the smoothed surface lies
/// inside the input (shrinkage, on a closed mesh with outward normals).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScanRow {
    /// The scheme's name (`"input"` for the baseline).
    pub scheme: String,
    /// The method's label (`"input"` for the baseline).
    pub method: String,
    /// Iterations done (implicit: 1 step; the baseline: 0).
    pub iteration: usize,
    /// The step of each iteration: λ (explicit) or the time step (implicit).
    pub step: f64,
    /// RMS distance of the vertices to the reference surface; `None` without one.
    pub rms: Option<f64>,
    /// Largest distance of a vertex to the reference surface; `None` without one.
    pub max: Option<f64>,
    /// Enclosed volume over the input's (closed meshes only).
    pub volume_ratio: Option<f64>,
    /// Surface area over the input's.
    pub area_ratio: f64,
    /// Sa of the removed residual. This and the following fields are measured at the
    /// counts of [`ScanConfig::detailed_iterations`], at every implicit step and at
    /// each run's best count; `None` elsewhere.
    pub removed_sa: Option<f64>,
    /// Sq of the removed residual.
    pub removed_sq: Option<f64>,
    /// Sz of the removed residual.
    pub removed_sz: Option<f64>,
    /// Area-weighted mean of the removed residual (positive: moved against the normals).
    pub shift: Option<f64>,
    /// The smallest interior angle of any face, degrees (also `None` if every face is
    /// degenerate).
    pub min_angle_deg: Option<f64>,
    /// Faces whose normal turned by more than 90° against the input.
    pub flipped_faces: Option<usize>,
}

/// The best observation of one scheme and method against the reference: the smallest
/// RMS distance.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScanBest {
    /// The scheme's name.
    pub scheme: String,
    /// The method's label.
    pub method: String,
    /// The iteration count at the smallest RMS (implicit: 1).
    pub iteration: usize,
    /// The step: λ (explicit) or the implicit time step at the smallest RMS.
    pub step: f64,
    /// The smallest RMS.
    pub rms: f64,
    /// The largest vertex distance at that count.
    pub max: f64,
    /// Whether the best is the last observation (the minimum may lie beyond it).
    pub at_last_observed: bool,
    /// The file name of the best mesh, `best-<scheme>-<method>.ply`.
    pub file: String,
}

/// The timing of one run (not deterministic; kept out of the CSV and JSON).
#[derive(Clone, Debug, PartialEq)]
pub struct ScanTiming {
    /// The scheme's name.
    pub scheme: String,
    /// The method's label.
    pub method: String,
    /// Smoothing wall time of the whole run (every implicit step for implicit),
    /// seconds, metrics excluded.
    pub smoothing_s: f64,
}

/// What [`run_scan`] found.
#[derive(Debug)]
pub struct ScanResults {
    /// The configuration.
    pub config: ScanConfig,
    /// The input.
    pub input: ScanSurface,
    /// The reference, if given.
    pub reference: Option<ScanSurface>,
    /// The input's row (scheme and method `"input"`, iteration 0), then one per
    /// scheme, method and observed iteration (implicit: per time step).
    pub rows: Vec<ScanRow>,
    /// With a reference: the best observation per scheme and method, in the configured
    /// order; empty without one.
    pub best: Vec<ScanBest>,
    /// The best meshes' positions, in the order of `best`.
    pub best_positions: Vec<Vec<DVec3>>,
    /// Remarks on the inputs (e.g. a reference whose bounding box differs wildly).
    pub warnings: Vec<String>,
    /// Per run, its smoothing time.
    pub timings: Vec<ScanTiming>,
    /// Wall time of the whole study, seconds.
    pub wall_time_s: f64,
}

impl ScanResults {
    /// The input's row (iteration 0).
    #[must_use]
    pub fn baseline(&self) -> &ScanRow {
        &self.rows[0]
    }

    /// The rows of one scheme and method.
    pub fn rows_of<'a>(
        &'a self,
        scheme: &'a str,
        method: &'a str,
    ) -> impl Iterator<Item = &'a ScanRow> + 'a {
        self.rows
            .iter()
            .filter(move |r| r.scheme == scheme && r.method == method)
    }
}

/// What every observation is measured against: the input, and the reference if any.
struct Observer<'a> {
    input: &'a ScanSurface,
    input_area: f64,
    input_volume: Option<f64>,
    reference: Option<SurfaceIndex>,
}

impl<'a> Observer<'a> {
    fn new(input: &'a ScanSurface, reference: Option<&ScanSurface>) -> Result<Self, MetricsError> {
        let geometry = Geometry::new(&input.mesh, &input.data.positions)?;
        let input_volume = if input.mesh.is_closed() {
            Some(geometry.volume()?)
        } else {
            None
        };
        let reference = reference
            .map(|r| SurfaceIndex::new(&r.mesh, &r.data.positions))
            .transpose()?;
        Ok(Self {
            input,
            input_area: geometry.surface_area(),
            input_volume,
            reference,
        })
    }

    /// The RMS and maximum distance of `positions` to the reference.
    fn distances(&self, positions: &[DVec3]) -> Result<Option<(f64, f64)>, MetricsError> {
        let Some(index) = &self.reference else {
            return Ok(None);
        };
        let d = index.distances(positions)?;
        let sum: f64 = d.iter().map(|x| x * x).sum();
        let max = d.iter().copied().fold(0.0, f64::max);
        Ok(Some(((sum / d.len() as f64).sqrt(), max)))
    }

    /// The row of one observation: distances, volume and area always; the removed
    /// residual and the mesh quality when `detailed`.
    fn measure(
        &self,
        scheme: &str,
        method: &str,
        iteration: usize,
        step: f64,
        positions: &[DVec3],
        detailed: bool,
    ) -> Result<ScanRow, MetricsError> {
        let mesh = &self.input.mesh;
        let geometry = Geometry::new(mesh, positions)?;
        let distances = self.distances(positions)?;
        let volume_ratio = match self.input_volume {
            Some(v0) => Some(geometry.volume()? / v0).filter(|r| r.is_finite()),
            None => None,
        };
        let area = geometry.surface_area();
        let mut row = ScanRow {
            scheme: scheme.to_string(),
            method: method.to_string(),
            iteration,
            step,
            rms: distances.map(|d| d.0),
            max: distances.map(|d| d.1),
            volume_ratio,
            area_ratio: if self.input_area > 0.0 {
                area / self.input_area
            } else {
                1.0
            },
            removed_sa: None,
            removed_sq: None,
            removed_sz: None,
            shift: None,
            min_angle_deg: None,
            flipped_faces: None,
        };
        if detailed {
            let input = Geometry::new(mesh, &self.input.data.positions)?;
            let residual = normal_residual(&input, &geometry)?;
            let areal = areal_parameters(&geometry, residual.as_slice(), &ArealOptions::default())?;
            row.removed_sa = Some(areal.sa);
            row.removed_sq = Some(areal.sq);
            row.removed_sz = Some(areal.sz);
            row.shift = Some(areal.mean);
            row.min_angle_deg = beltrami_algorithms::mesh_quality(mesh, positions)
                .ok()
                .and_then(|q| q.shape)
                .map(|s| s.min_angle);
            row.flipped_faces =
                beltrami_algorithms::flipped_faces(mesh, positions, &self.input.data.positions)
                    .ok();
        }
        Ok(row)
    }
}

/// The bounding boxes of input and reference differ wildly: diagonals more than a
/// factor 2 apart, or centres more than half a diagonal apart.
fn reference_warning(input: &ScanSurface, reference: &ScanSurface) -> Option<String> {
    let (a_lo, a_hi) = input.bounding_box();
    let (b_lo, b_hi) = reference.bounding_box();
    let (da, db) = ((a_hi - a_lo).length(), (b_hi - b_lo).length());
    let offset = ((a_lo + a_hi) - (b_lo + b_hi)).length() / 2.0;
    let ratio = da / db;
    if !(0.5..=2.0).contains(&ratio) || offset > 0.5 * da.max(db) {
        Some(format!(
            "the reference's bounding box differs wildly from the input's (diagonal {} against {}, centres {} apart): is it the same part, in the same unit and position?",
            crate::findings::sig(db),
            crate::findings::sig(da),
            crate::findings::sig(offset)
        ))
    } else {
        None
    }
}

/// Runs every configured scheme and method on `input`, observing each explicit run at
/// [`ScanConfig::observed_iterations`] and each implicit time step once, and measures
/// every observation against the input (and the reference, if given). The runs go in
/// parallel (each one's smoothing and metrics in order); `progress` hears one
/// [`Progress::RunStarted`] for all of them, one [`Progress::Iteration`] per finished
/// run and one [`Progress::RunFinished`]. The results do not depend on the thread
/// count.
///
/// With a reference, the best observation per scheme and method is the one with the
/// smallest RMS distance to it, and its positions are kept.
///
/// # Errors
/// [`StudyError::Config`] for an invalid configuration, [`StudyError::Smooth`] and
/// [`StudyError::Metrics`] naming the input and the run that failed.
pub fn run_scan(
    input: ScanSurface,
    reference: Option<ScanSurface>,
    config: &ScanConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<ScanResults, StudyError> {
    config.validate()?;
    let start = Instant::now();
    let warnings: Vec<String> = reference
        .as_ref()
        .and_then(|r| reference_warning(&input, r))
        .into_iter()
        .collect();
    let metrics = |label: &str| {
        let surface = input.name.clone();
        let scheme = label.to_string();
        move |source| StudyError::Metrics {
            surface,
            scheme,
            source,
        }
    };
    let observer = Observer::new(&input, reference.as_ref()).map_err(metrics("input"))?;
    let mut rows = vec![
        observer
            .measure("input", "input", 0, 0.0, &input.data.positions, true)
            .map_err(metrics("input"))?,
    ];
    let jobs: Vec<(&dyn WeightScheme, ScanMethod)> = config
        .schemes
        .iter()
        .flat_map(|scheme| config.methods.iter().map(move |&m| (scheme.as_ref(), m)))
        .collect();
    let outcomes = run_jobs(&observer, &jobs, config, progress);
    let mut best = Vec::new();
    let mut best_positions = Vec::new();
    let mut timings = Vec::new();
    for (&(scheme, method), outcome) in jobs.iter().zip(outcomes) {
        let label = format!("{}/{}", scheme.name(), method.label());
        let run = outcome.map_err(|e| match e {
            RunError::Smooth(source) => StudyError::Smooth {
                surface: input.name.clone(),
                scheme: label.clone(),
                source,
            },
            RunError::Metrics(source) => metrics(&label)(source),
        })?;
        if let Some((row, positions)) = run.best {
            best.push(scan_best(scheme, method, &row, &run.rows));
            best_positions.push(positions);
        }
        rows.extend(run.rows);
        timings.push(ScanTiming {
            scheme: scheme.name().to_string(),
            method: method.label().to_string(),
            smoothing_s: run.smoothing_s,
        });
    }
    drop(observer);
    Ok(ScanResults {
        config: config.clone(),
        input,
        reference,
        rows,
        best,
        best_positions,
        warnings,
        timings,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// Runs the jobs in parallel, each on its own, while the calling thread reports
/// progress, one step per finished run; the outcomes come in the jobs' order.
fn run_jobs(
    observer: &Observer<'_>,
    jobs: &[(&dyn WeightScheme, ScanMethod)],
    config: &ScanConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Vec<Result<MethodRun, RunError>> {
    progress(Progress::RunStarted(
        &observer.input.name,
        "every scheme and method",
        jobs.len(),
    ));
    let (sender, finished) = std::sync::mpsc::channel::<()>();
    let outcomes: Vec<Result<MethodRun, RunError>> = std::thread::scope(|scope| {
        let worker = scope.spawn(move || {
            jobs.par_iter()
                .map_with(sender, |sender, &(scheme, method)| {
                    let run = run_method(observer, scheme, method, config);
                    // The receiver lives until every sender is gone.
                    let _ = sender.send(());
                    run
                })
                .collect::<Vec<_>>()
        });
        for (done, ()) in finished.iter().enumerate() {
            progress(Progress::Iteration(done + 1));
        }
        worker
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    });
    progress(Progress::RunFinished);
    outcomes
}

/// The best observation `row` of `scheme` with `method`, among the run's `rows`.
fn scan_best(
    scheme: &dyn WeightScheme,
    method: ScanMethod,
    row: &ScanRow,
    rows: &[ScanRow],
) -> ScanBest {
    let last = rows.last().map(|r| (r.iteration, r.step));
    ScanBest {
        scheme: scheme.name().to_string(),
        method: method.label().to_string(),
        iteration: row.iteration,
        step: row.step,
        rms: row.rms.unwrap_or(f64::NAN),
        max: row.max.unwrap_or(f64::NAN),
        at_last_observed: last == Some((row.iteration, row.step)),
        file: format!("best-{}-{}.ply", scheme.name(), method.label()),
    }
}

enum RunError {
    Smooth(beltrami_smooth::SmoothError),
    Metrics(MetricsError),
}

struct MethodRun {
    rows: Vec<ScanRow>,
    best: Option<(ScanRow, Vec<DVec3>)>,
    smoothing_s: f64,
}

/// Keeps `row` and `positions` as the best when its RMS is smaller than the best's
/// (the earlier observation wins a tie).
fn keep_best(best: &mut Option<(ScanRow, Vec<DVec3>)>, row: &ScanRow, positions: &[DVec3]) {
    let Some(rms) = row.rms else { return };
    if best
        .as_ref()
        .is_none_or(|(b, _)| rms < b.rms.unwrap_or(f64::INFINITY))
    {
        *best = Some((row.clone(), positions.to_vec()));
    }
}

/// Runs `scheme` with `method` on the observer's input and measures its observations.
fn run_method(
    observer: &Observer<'_>,
    scheme: &dyn WeightScheme,
    method: ScanMethod,
    config: &ScanConfig,
) -> Result<MethodRun, RunError> {
    let base = SmoothConfig::new(config.lambda, config.max_iterations)
        .boundary(config.boundary)
        .update(config.update)
        .method(method.method())
        .statistics(Statistics::OnDemand);
    if method == ScanMethod::Implicit {
        return run_implicit(observer, scheme, method, config, &base);
    }
    let step = method.explicit_step(config.lambda);
    let mut run = run_explicit(observer, scheme, method, config, base, step)?;
    measure_best_fully(observer, scheme, method, step, &mut run)?;
    Ok(run)
}

/// One implicit step from the input per configured time step, each measured in full.
fn run_implicit(
    observer: &Observer<'_>,
    scheme: &dyn WeightScheme,
    method: ScanMethod,
    config: &ScanConfig,
    base: &SmoothConfig,
) -> Result<MethodRun, RunError> {
    let input = observer.input;
    let mut rows = Vec::new();
    let mut best = None;
    let mut smoothing_s = 0.0;
    for &t in &config.implicit_steps {
        let clock = Instant::now();
        let smoothed = Smoother::new(
            &input.mesh,
            &input.data.positions,
            scheme,
            base.clone().lambda(t).iterations(1),
        )
        .and_then(|s| s.run(|_| ControlFlow::Continue(())))
        .map_err(RunError::Smooth)?;
        smoothing_s += clock.elapsed().as_secs_f64();
        let row = observer
            .measure(
                scheme.name(),
                method.label(),
                1,
                t,
                &smoothed.positions,
                true,
            )
            .map_err(RunError::Metrics)?;
        keep_best(&mut best, &row, &smoothed.positions);
        rows.push(row);
    }
    Ok(MethodRun {
        rows,
        best,
        smoothing_s,
    })
}

/// One explicit run of `config.max_iterations` iterations of step `step` with `base`'s
/// other settings, measured at the observed iterations (in detail at the detailed
/// ones); the smoothing time leaves the measurements out.
fn run_explicit(
    observer: &Observer<'_>,
    scheme: &dyn WeightScheme,
    method: ScanMethod,
    config: &ScanConfig,
    base: SmoothConfig,
    step: f64,
) -> Result<MethodRun, RunError> {
    let input = observer.input;
    let mut rows = Vec::new();
    let mut best = None;
    let mut smoothing_s = 0.0;
    let observed = config.observed_iterations();
    let detailed = config.detailed_iterations();
    let mut wanted = observed.iter().copied().peekable();
    let mut failed = None;
    let mut resumed = Instant::now();
    let smoother = Smoother::new(
        &input.mesh,
        &input.data.positions,
        scheme,
        base.lambda(step),
    )
    .map_err(RunError::Smooth)?;
    smoother
        .run(|it| {
            smoothing_s += resumed.elapsed().as_secs_f64();
            if wanted.peek() == Some(&it.index) {
                wanted.next();
                match observer.measure(
                    scheme.name(),
                    method.label(),
                    it.index,
                    step,
                    it.positions(),
                    detailed.contains(&it.index),
                ) {
                    Ok(row) => {
                        keep_best(&mut best, &row, it.positions());
                        rows.push(row);
                    }
                    Err(e) => {
                        failed = Some(e);
                        return ControlFlow::Break(());
                    }
                }
            }
            resumed = Instant::now();
            ControlFlow::Continue(())
        })
        .map_err(RunError::Smooth)?;
    if let Some(e) = failed {
        return Err(RunError::Metrics(e));
    }
    Ok(MethodRun {
        rows,
        best,
        smoothing_s,
    })
}

/// Measures the best observation in full when it was measured without the details,
/// replacing its row.
fn measure_best_fully(
    observer: &Observer<'_>,
    scheme: &dyn WeightScheme,
    method: ScanMethod,
    step: f64,
    run: &mut MethodRun,
) -> Result<(), RunError> {
    if let Some((row, positions)) = &mut run.best
        && row.removed_sq.is_none()
    {
        let full = observer
            .measure(
                scheme.name(),
                method.label(),
                row.iteration,
                step,
                positions,
                true,
            )
            .map_err(RunError::Metrics)?;
        if let Some(r) = run.rows.iter_mut().find(|r| r.iteration == full.iteration) {
            *r = full.clone();
        }
        *row = full;
    }
    Ok(())
}
