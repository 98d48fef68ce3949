//! `beltrami.smooth`: the options of `beltrami smooth`, with its words and defaults.

use std::ops::ControlFlow;
use std::time::Duration;

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_smooth::{
    Boundary, DEFAULT_LAMBDA, DiffusionTime, ImplicitSolver, Method, SmoothConfig,
    SmoothError as Error, SmoothReport, Smoother, Statistics, StepStats, Summation, TAUBIN_LAMBDA,
    TAUBIN_PASS_BAND, WeightUpdate, area_step,
};
use beltrami_weights::{LaplacianOptions, NegativeWeights, Normalization, WeightScheme};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::smooth_error;
use crate::mesh::Mesh;
use crate::progress::Progress;
use crate::weights::scheme;

/// The default iteration count, as on the command line.
const DEFAULT_ITERATIONS: usize = 10;

/// One of `choices`, or a `ValueError` listing them.
fn choice<'a>(option: &str, value: &str, choices: &[&'a str]) -> PyResult<&'a str> {
    choices
        .iter()
        .find(|c| **c == value)
        .copied()
        .ok_or_else(|| {
            let list: Vec<String> = choices.iter().map(|c| format!("'{c}'")).collect();
            PyValueError::new_err(format!(
                "{option} must be one of {}, got '{value}'",
                list.join(", ")
            ))
        })
}

/// The options of one `smooth` call, checked.
struct Options {
    weights: String,
    lambda: Option<f64>,
    iterations: Option<usize>,
    boundary: &'static str,
    method: &'static str,
    update: &'static str,
    normalize: &'static str,
    vertex_area: &'static str,
    cotangent_negative: &'static str,
    summation: &'static str,
    time: Option<f64>,
    cutoff: Option<f64>,
    until_change: Option<f64>,
    mu: Option<f64>,
    hc_alpha: Option<f64>,
    hc_beta: Option<f64>,
    solver: &'static str,
    pin: Vec<u32>,
    preserve_volume: bool,
    max_iterations: usize,
    step_stats: bool,
}

impl Options {
    fn lambda(&self) -> f64 {
        self.lambda.unwrap_or(if self.method == "taubin" {
            TAUBIN_LAMBDA
        } else {
            DEFAULT_LAMBDA
        })
    }

    /// Refuses options that the chosen method would ignore, before any work.
    fn check_combination(&self, solver_given: bool) -> PyResult<()> {
        let method = self.method;
        let refuse = |option: &str, wanted: &str| {
            Err(PyValueError::new_err(format!(
                "{option} applies to method='{wanted}' only, not to method='{method}'"
            )))
        };
        if self.mu.is_some() && method != "taubin" {
            return refuse("mu", "taubin");
        }
        if self.hc_alpha.is_some() && method != "hc" {
            return refuse("hc_alpha", "hc");
        }
        if self.hc_beta.is_some() && method != "hc" {
            return refuse("hc_beta", "hc");
        }
        if solver_given && method != "implicit" {
            return refuse("solver", "implicit");
        }
        if method == "implicit" && self.preserve_volume {
            return Err(PyValueError::new_err(
                "preserve_volume does not apply to method='implicit'",
            ));
        }
        if matches!(method, "taubin" | "hc") && (self.time.is_some() || self.cutoff.is_some()) {
            return Err(PyValueError::new_err(format!(
                "time and cutoff apply to plain diffusion (method='explicit' or 'implicit'), not to method='{method}'"
            )));
        }
        if self.time.is_some() && self.cutoff.is_some() {
            return Err(PyValueError::new_err(
                "time and cutoff exclude each other: give one",
            ));
        }
        if (self.time.is_some() || self.cutoff.is_some()) && self.iterations.is_some() {
            return Err(PyValueError::new_err(
                "iterations and time (or cutoff) exclude each other: a time chooses the iteration count",
            ));
        }
        Ok(())
    }

    fn method(&self) -> Method {
        match self.method {
            "implicit" => Method::implicit(match self.solver {
                "cholesky" => ImplicitSolver::Cholesky,
                _ => ImplicitSolver::conjugate_gradient(),
            }),
            "taubin" => Method::taubin_or_pass_band(self.lambda(), self.mu),
            "hc" => Method::hc_or_default(self.hc_alpha, self.hc_beta),
            _ => Method::Laplacian,
        }
    }

    /// With `normalize="area"` and neither `lam` nor `time`/`cutoff`: the step scaled to
    /// the mesh, as `beltrami smooth` does: the method's default λ taken as a fraction of
    /// the largest stable explicit step on the input (`area_step`), and Taubin's μ with
    /// it (the pass band scaled alike) unless `mu` was given.
    fn scale_area_step(
        &self,
        mesh: &Mesh,
        scheme: &dyn WeightScheme,
        config: &mut SmoothConfig,
    ) -> Result<(), Error> {
        if self.lambda.is_some() || config.duration.is_some() || self.normalize != "area" {
            return Ok(());
        }
        let fraction = self.lambda();
        if let Some(step) = area_step(&mesh.mesh, &mesh.positions, scheme, config, fraction)? {
            config.lambda = step;
            if self.method == "taubin" && self.mu.is_none() {
                config.method = Method::taubin_pass_band(step, TAUBIN_PASS_BAND * fraction / step);
            }
        }
        Ok(())
    }

    /// The configuration `beltrami smooth` builds from the same options.
    fn config(&self) -> SmoothConfig {
        let normalization = match (self.normalize, self.vertex_area) {
            ("sum", _) => Normalization::WeightSum,
            (_, "barycentric") => Normalization::Area(VertexAreaKind::Barycentric),
            _ => Normalization::Area(VertexAreaKind::MixedVoronoi),
        };
        let negative = match self.cotangent_negative {
            "clamp" => NegativeWeights::Clamp,
            "abs" => NegativeWeights::Abs,
            _ => NegativeWeights::Keep,
        };
        let mut config =
            SmoothConfig::new(self.lambda(), self.iterations.unwrap_or(DEFAULT_ITERATIONS))
                .boundary(match self.boundary {
                    "free" => Boundary::Free,
                    "curve" => Boundary::Curve,
                    _ => Boundary::Fixed,
                })
                .update(match self.update {
                    "once" => WeightUpdate::Once,
                    _ => WeightUpdate::Every,
                })
                .laplacian(
                    LaplacianOptions::new()
                        .normalization(normalization)
                        .negative(negative),
                )
                .pinned(self.pin.iter().copied().map(VertexId::new).collect())
                .method(self.method())
                .preserve_volume(self.preserve_volume);
        config.duration = DiffusionTime::from_options(self.time, self.cutoff);
        config.until_change = self.until_change;
        if !self.step_stats {
            config = config.statistics(Statistics::OnDemand);
        }
        config.summation(match self.summation {
            "scatter" => Summation::Scatter,
            _ => Summation::Rows,
        })
    }
}

/// One iteration's statistics, with the keys of a step of the `--report` JSON.
fn step_dict<'py>(py: Python<'py>, index: usize, s: &StepStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("iteration", index)?;
    d.set_item("max_displacement", s.max_displacement)?;
    d.set_item("mean_displacement", s.mean_displacement)?;
    d.set_item("stuck_vertices", s.stuck_vertices)?;
    Ok(d)
}

/// Smooths a mesh by Laplacian diffusion, with the options of `beltrami smooth`.
///
/// Returns `(smoothed, report)`: a new `Mesh` with the same faces and the smoothed
/// positions, and a dict with the keys of the command line's `--report` JSON
/// (`input`, `output`, `vertices`, `faces`, `parameters`, `iterations`, `stop`,
/// `max_stuck_vertices`, `scattered_sweeps`, `seconds`, `steps`, and `implicit` for the
/// implicit method) but the command's `notes` about its files; `seconds` holds
/// `weights` and `updates` (no file is read or written).
///
/// The options and their defaults are those of `beltrami smooth`:
///
/// - `weights`: `"cotangent"`, `"uniform"`, `"distance"` or another registered name
///   (see `weight_schemes()`).
/// - `lam`: the step λ; None means 0.8, or 0.6307 with `method="taubin"`; with
///   `normalize="area"` (where λ is a time in length²), that fraction of the largest
///   stable explicit step on the input (`report["parameters"]["lambda_used"]`).
/// - `iterations`: the iteration count (None: 10); the upper limit with
///   `until_change`; excludes `time` and `cutoff`.
/// - `boundary`: `"fixed"` (never moves), `"free"`, `"curve"` (along the boundary).
/// - `method`: `"explicit"`, `"taubin"`, `"hc"`, `"implicit"`.
/// - `update`: `"every"` (weights recomputed each iteration) or `"once"`.
/// - `normalize`: `"sum"` (None) or `"area"`; `vertex_area` (with `"area"` only):
///   `"mixed"` (None) or `"barycentric"`; `cotangent_negative`: `"keep"`, `"clamp"`,
///   `"abs"`.
/// - `summation`: `"rows"` (each vertex's weighted neighbours summed around its
///   one-ring, OpenMesh's bits; the default) or `"scatter"` (each triangle's
///   cotangents, or each edge's inverse distance, computed once and added into its
///   vertices' sums: 22 to 47 % less time per iteration with inverse distances, 11
///   to 36 % less with cotangents; the same results to rounding but not bit for bit;
///   only for `weights="cotangent"` with `cotangent_negative="keep"` or
///   `weights="distance"`, with `update="every"`, `normalize="sum"`,
///   `method="explicit"`, no `preserve_volume`).
/// - `time` (length²) or `cutoff` (Gaussian cut-off wavelength): diffuse for a
///   physical time instead of a count; `until_change`: stop once no vertex moves
///   farther than this.
/// - `mu` (taubin; default: pass band 0.1), `hc_alpha`, `hc_beta` (hc; 0.1, 0.6),
///   `solver` (implicit: `"cg"`, the default, or `"cholesky"`).
/// - `pin`: vertex indices that never move; `preserve_volume`: rescale to the
///   input's volume after every iteration (closed meshes).
/// - `on_iteration(i, stats)`: called after iteration `i` (1-based) with a dict of
///   `iteration`, `max_displacement`, `mean_displacement`, `stuck_vertices`;
///   returning `False` stops the run (`report["stop"] == "observer"`); an
///   exception raised in it stops the run and propagates.
/// - `progress`: show a tqdm progress bar when tqdm is installed.
/// - `max_iterations`: refuse a run planning more iterations (a `time` in the wrong
///   unit can mean millions); `step_stats`: keep every iteration's statistics in
///   the report (the positions are the same either way).
///
/// The run holds no GIL except while calling `on_iteration` or the progress bar.
/// Raises `ValueError` for bad or conflicting options, `SmoothError` when the run
/// cannot be done on this mesh (an unstable step, a Taubin pair that amplifies, a
/// non-finite position).
#[pyfunction]
#[pyo3(signature = (
    mesh, weights = "cotangent", lam = None, iterations = None, boundary = "fixed",
    method = "explicit", update = "every", normalize = None, *, vertex_area = None,
    cotangent_negative = "keep", summation = "rows", time = None, cutoff = None,
    until_change = None,
    mu = None, hc_alpha = None, hc_beta = None, solver = None, pin = None,
    preserve_volume = false, on_iteration = None, progress = false,
    max_iterations = 1_000_000, step_stats = true
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn smooth<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    weights: &str,
    lam: Option<f64>,
    iterations: Option<i128>,
    boundary: &str,
    method: &str,
    update: &str,
    normalize: Option<&str>,
    vertex_area: Option<&str>,
    cotangent_negative: &str,
    summation: &str,
    time: Option<f64>,
    cutoff: Option<f64>,
    until_change: Option<f64>,
    mu: Option<f64>,
    hc_alpha: Option<f64>,
    hc_beta: Option<f64>,
    solver: Option<&str>,
    pin: Option<&Bound<'_, PyAny>>,
    preserve_volume: bool,
    on_iteration: Option<Py<PyAny>>,
    progress: bool,
    max_iterations: i128,
    step_stats: bool,
) -> PyResult<(Mesh, Bound<'py, PyDict>)> {
    // As `smooth --vertex-area` without `--normalize area`: given but unused.
    if vertex_area.is_some() && normalize != Some("area") {
        return Err(PyValueError::new_err(
            "vertex_area applies to normalize=\"area\" only (weight-sum rows use no vertex area)",
        ));
    }
    let pin = match pin {
        Some(pin) => crate::errors::vertex_indices("pin", pin)?,
        None => Vec::new(),
    };
    let options = Options {
        weights: weights.to_string(),
        lambda: lam,
        iterations: crate::errors::nonnegative_opt("iterations", iterations)?,
        boundary: choice("boundary", boundary, &["fixed", "free", "curve"])?,
        method: choice("method", method, &["explicit", "taubin", "hc", "implicit"])?,
        update: choice("update", update, &["every", "once"])?,
        normalize: choice("normalize", normalize.unwrap_or("sum"), &["sum", "area"])?,
        vertex_area: choice(
            "vertex_area",
            vertex_area.unwrap_or("mixed"),
            &["mixed", "barycentric"],
        )?,
        cotangent_negative: choice(
            "cotangent_negative",
            cotangent_negative,
            &["keep", "clamp", "abs"],
        )?,
        summation: choice("summation", summation, &["rows", "scatter"])?,
        time,
        cutoff,
        until_change,
        mu,
        hc_alpha,
        hc_beta,
        solver: choice("solver", solver.unwrap_or("cg"), &["cg", "cholesky"])?,
        pin,
        preserve_volume,
        max_iterations: crate::errors::nonnegative("max_iterations", max_iterations)?,
        step_stats,
    };
    let scheme = scheme(&options.weights)?;
    let failure = crate::scheme::failure_slot(&options.weights);
    options.check_combination(solver.is_some())?;
    if mesh.mesh.n_faces() == 0 {
        return Err(crate::errors::MeshError::new_err(format!(
            "the mesh has {} vertices but no faces; smooth needs a surface of triangles",
            mesh.mesh.n_vertices()
        )));
    }
    let mut config = options.config();
    if options.summation == "scatter"
        && let Some(needed) = config.scatter_unmet(scheme.as_ref())
    {
        return Err(PyValueError::new_err(format!(
            "summation='scatter' needs {needed}; it applies to weights='cotangent' (with cotangent_negative='keep') or 'distance', with update='every', normalize='sum', method='explicit' and no preserve_volume"
        )));
    }
    let mut observer = Progress::new();
    let stop = observer.stop();
    let smoothed = {
        crate::errors::interruptible(py, &stop, || {
            options
                .scale_area_step(mesh, scheme.as_ref(), &mut config)
                .map_err(|e| smooth_error(&e))?;
            let smoother = Smoother::new(&mesh.mesh, &mesh.positions, scheme.as_ref(), config)
                .map_err(|e| smooth_error(&e))?;
            let planned = check_planned_run(&smoother, options.max_iterations)?;
            Python::attach(|py| observer.open_bar(py, progress, planned, "smooth"))?;
            let result = smoother.run(|it| {
                let callback = on_iteration.as_ref().map(|callback| {
                    let (index, stats) = (it.index, it.stats());
                    move |py: Python<'_>| {
                        let answer = callback.call1(py, (index, step_dict(py, index, &stats)?))?;
                        // False, Python's or numpy's (`np.False_`, what a comparison
                        // of arrays gives), stops; anything else, None included, goes on.
                        let stop = answer.bind(py).extract::<bool>().is_ok_and(|b| !b);
                        Ok(if stop {
                            ControlFlow::Break(())
                        } else {
                            ControlFlow::Continue(())
                        })
                    }
                });
                observer.show_and_call(it.index, planned, callback)
            });
            result.map_err(|e| smooth_error(&e))
        })
    };
    let interrupted = stop.load(std::sync::atomic::Ordering::Relaxed);
    let smoothed = observer.finish_after(py, smoothed);
    // Taken in any case (so that a later call does not raise it); Ctrl-C comes first.
    if let Some(e) = crate::scheme::take(failure.as_ref())
        && !interrupted
    {
        return Err(e);
    }
    let smoothed = smoothed?;
    let report = report(py, mesh, &options, &smoothed.report)?;
    warn_stuck(py, mesh, &smoothed.report)?;
    Ok((mesh.with_positions(smoothed.positions), report))
}

/// A `UserWarning` when vertices could not move (the command's note): on a polygon mesh
/// the cotangent scheme, the default, has no weights, and the run would otherwise look
/// like a smoothing that changed nothing.
fn warn_stuck(py: Python<'_>, mesh: &Mesh, r: &beltrami_smooth::SmoothReport) -> PyResult<()> {
    if r.max_stuck_vertices == 0 {
        return Ok(());
    }
    // Uniform and inverse-distance weights exist on polygons too.
    let polygon_weights = matches!(r.scheme.as_str(), "uniform" | "distance");
    let why = if mesh.mesh.is_triangle_mesh() || polygon_weights {
        "weights summing to <= 0 or zero area".to_string()
    } else {
        format!(
            "the mesh has polygon faces, on which {} weights are 0; use weights=\"uniform\" or \"distance\", or read it with repair=True, triangulate=True",
            r.scheme
        )
    };
    crate::errors::warn_user(
        py,
        &format!(
            "up to {} {} per iteration could not move ({why}); the report's max_stuck_vertices counts them",
            r.max_stuck_vertices,
            if r.max_stuck_vertices == 1 {
                "vertex"
            } else {
                "vertices"
            },
        ),
    )
}

/// Refuses a run whose step given directly is unstable (`SmoothError`; a time chooses
/// its own stable step) or that plans more than `max_iterations` iterations
/// (`ValueError`); returns the planned iteration count.
fn check_planned_run(smoother: &Smoother<'_>, max_iterations: usize) -> PyResult<usize> {
    // Steps given directly must be stable (a time chooses its own stable step); with
    // area rows a Taubin pair is checked against the limit.
    smoother
        .check_stable_steps()
        .map_err(|e| smooth_error(&e))?;
    let planned = smoother.config().iterations;
    if planned > max_iterations {
        return Err(PyValueError::new_err(format!(
            "the run would take {planned} iterations of step {}, more than max_iterations={} (is time or cutoff in the mesh's length unit? raise max_iterations to run it anyway)",
            smoother.config().lambda,
            max_iterations
        )));
    }
    Ok(planned)
}

/// The report of a run, with the keys of `beltrami smooth --report`.
fn report<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    options: &Options,
    r: &SmoothReport,
) -> PyResult<Bound<'py, PyDict>> {
    let parameters = PyDict::new(py);
    parameters.set_item("weights", &options.weights)?;
    parameters.set_item("lambda", options.lambda())?;
    parameters.set_item(
        "iterations",
        options.iterations.unwrap_or(DEFAULT_ITERATIONS),
    )?;
    parameters.set_item("boundary", options.boundary)?;
    parameters.set_item("update", options.update)?;
    parameters.set_item("cotangent_negative", options.cotangent_negative)?;
    parameters.set_item("summation", options.summation)?;
    parameters.set_item("normalize", options.normalize)?;
    parameters.set_item("vertex_area", options.vertex_area)?;
    parameters.set_item("pinned", options.pin.len())?;
    parameters.set_item("method", options.method)?;
    parameters.set_item(
        "mu",
        match r.config.method {
            Method::Taubin { mu } => Some(mu),
            _ => None,
        },
    )?;
    parameters.set_item(
        "hc",
        match r.config.method {
            Method::Hc { alpha, beta } => Some([alpha, beta]),
            _ => None,
        },
    )?;
    parameters.set_item("preserve_volume", options.preserve_volume)?;
    parameters.set_item("time", r.config.duration.map(DiffusionTime::time))?;
    parameters.set_item("cutoff", options.cutoff)?;
    parameters.set_item("until_change", options.until_change)?;
    parameters.set_item("lambda_used", r.config.lambda)?;
    parameters.set_item("iterations_planned", r.config.iterations)?;

    let seconds = PyDict::new(py);
    let solver_setup = r
        .solver
        .as_ref()
        .map_or(Duration::ZERO, |s| s.analysis_time + s.factorization_time);
    seconds.set_item("weights", (r.weight_time + solver_setup).as_secs_f64())?;
    seconds.set_item("updates", r.update_time.as_secs_f64())?;

    let steps = r
        .steps
        .iter()
        .enumerate()
        .map(|(i, s)| step_dict(py, i + 1, s))
        .collect::<PyResult<Vec<_>>>()?;

    let d = PyDict::new(py);
    d.set_item(
        "input",
        mesh.source.as_ref().map(|(p, _)| p.display().to_string()),
    )?;
    d.set_item("output", py.None())?;
    d.set_item("vertices", mesh.positions.len())?;
    d.set_item("faces", mesh.faces.len())?;
    d.set_item("parameters", parameters)?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("stop", r.stop.name())?;
    d.set_item("max_stuck_vertices", r.max_stuck_vertices)?;
    d.set_item("scattered_sweeps", r.scattered_sweeps)?;
    d.set_item("seconds", seconds)?;
    d.set_item("steps", steps)?;
    if let Some(s) = &r.solver {
        let implicit = PyDict::new(py);
        implicit.set_item("solver", options.solver)?;
        implicit.set_item("time_step", r.config.lambda)?;
        implicit.set_item("numeric_factorizations", s.numeric_factorizations)?;
        implicit.set_item("factor_nonzeros", s.factor_nonzeros)?;
        implicit.set_item("cg_iterations", s.cg_iterations)?;
        implicit.set_item("seconds_assembly", r.weight_time.as_secs_f64())?;
        implicit.set_item("seconds_analysis", s.analysis_time.as_secs_f64())?;
        implicit.set_item("seconds_factorization", s.factorization_time.as_secs_f64())?;
        implicit.set_item("seconds_solve", r.update_time.as_secs_f64())?;
        d.set_item("implicit", implicit)?;
    }
    Ok(d)
}
