//! `beltrami smooth`: Laplacian diffusion smoothing of a mesh file.

use std::io::{IsTerminal, Write};
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_io::{MeshData, declared_counts, stage_bytes};
use beltrami_smooth::{
    Boundary, DiffusionTime, ImplicitSolver, Method, SmoothConfig, SmoothError, SmoothReport,
    Smoothed, Smoother, Statistics, WeightUpdate,
};
use beltrami_weights::WeightScheme;
use beltrami_weights::{LaplacianOptions, NegativeWeights, Normalization, WeightRegistry};
use clap::ValueEnum;
use serde::Serialize;

use crate::error::CliError;
use crate::load::{ReadArgs, load_checked};
use crate::memory::{self, LARGE_RUN_VERTICES, MemoryEstimate, parse_size};
use crate::output::{Outputs, Staged};
use crate::text::{number, plural};

/// Arguments of `beltrami smooth`.
///
/// The defaults are the paper's explicit scheme with the most accurate weights:
/// cotangent weights recomputed every iteration (the geometric flow), λ = 0.8,
/// 10 iterations, weight-sum normalisation, and a fixed boundary so that a measured
/// patch keeps its outline.
#[derive(Debug, clap::Args)]
pub(crate) struct SmoothArgs {
    /// The input mesh (.ply, .stl, .obj or .off).
    input: PathBuf,
    /// The output mesh (.ply, .stl, .obj or .off); same vertices and faces, new positions.
    output: PathBuf,
    /// The weight scheme: uniform, distance, cotangent, or a registered name.
    #[arg(long, default_value = "cotangent")]
    weights: String,
    /// The step. Weight-sum normalisation: a fraction in (0, 1]. Area
    /// normalisation: a diffusion time per iteration, in length², which an explicit
    /// run must keep below its stability limit (checked before the run). Default 0.8;
    /// 0.6307 for --method taubin (Taubin's classic pair with μ = -0.6732, pass band
    /// 0.1).
    #[arg(long, allow_negative_numbers = true)]
    lambda: Option<f64>,
    /// The number of iterations (the upper limit with --until-change).
    #[arg(long, default_value_t = 10)]
    iterations: usize,
    /// Refuse a run that plans more iterations than this (a --time or --cutoff in the
    /// wrong unit can mean millions).
    #[arg(long, default_value_t = DEFAULT_MAX_ITERATIONS)]
    max_iterations: usize,
    /// How boundary vertices move: fixed (never), free (like interior ones), curve
    /// (along the boundary polyline only).
    #[arg(long, value_enum, default_value_t = BoundaryArg::Fixed)]
    boundary: BoundaryArg,
    /// When weights are computed: every iteration (geometric flow) or once from the
    /// input (a linear filter, as OpenMesh does).
    #[arg(long, value_enum, default_value_t = UpdateArg::Every)]
    update: UpdateArg,
    /// Treatment of negative weights (cotangent weights of edges whose opposite angles
    /// sum to more than 180°): keep them, clamp them to 0, or take their absolute value.
    #[arg(long, value_enum, default_value_t = NegativeArg::Keep)]
    cotangent_negative: NegativeArg,
    /// Row normalisation: sum (divide by the weight sum, paper Eq. 2) or area (divide
    /// by the vertex area, paper Eq. 6). Default: sum, for every method (a --time or
    /// --cutoff is converted to steps either way).
    #[arg(long, value_enum)]
    normalize: Option<NormalizeArg>,
    /// The vertex area for --normalize area.
    #[arg(long, value_enum, default_value_t = AreaArg::Mixed)]
    vertex_area: AreaArg,
    /// The method: explicit (plain diffusion, shrinks), taubin (λ|μ: a λ sweep then a
    /// μ sweep per iteration, keeps the form), hc (pushes each vertex back towards the
    /// input; for open patches), implicit (backward Euler, (M − λL) x' = M x per step,
    /// stable for any λ; with --time/--cutoff steps of at most λ that add up to the
    /// time). See docs/methods.md and docs/implicit.md.
    #[arg(long, value_enum, default_value_t = MethodArg::Explicit)]
    method: MethodArg,
    /// The linear solver of --method implicit (only): cg (Jacobi-preconditioned
    /// conjugate gradient to a relative residual of 1e-10, no set-up, memory linear in
    /// the mesh; the default) or cholesky (sparse factorisation, exact to rounding,
    /// factorised once while the weights are frozen; pays off for many frozen steps of
    /// a large λ on a mesh small enough to factorise).
    #[arg(long, value_enum)]
    solver: Option<SolverArg>,
    /// Taubin's negative step μ (--method taubin only; μ < -λ, pass band 1/λ + 1/μ).
    /// Default: the μ giving a pass band of 0.1.
    #[arg(long, allow_negative_numbers = true)]
    mu: Option<f64>,
    /// HC (--method hc only): the pull towards the input positions, in [0, 1].
    /// Default 0.1.
    #[arg(long, allow_negative_numbers = true)]
    hc_alpha: Option<f64>,
    /// HC (--method hc only): the weight of a vertex's own correction against its
    /// neighbours', in [0, 1]. Default 0.6.
    #[arg(long, allow_negative_numbers = true)]
    hc_beta: Option<f64>,
    /// Rescale about the centroid after every iteration so that the enclosed volume
    /// stays the input's (closed meshes only).
    #[arg(long)]
    preserve_volume: bool,
    /// Diffuse for this time, in length² of the mesh's unit (e.g. mm²), instead of
    /// --iterations; --lambda is then the largest step and the iteration count follows.
    #[arg(long, allow_negative_numbers = true, conflicts_with_all = ["cutoff", "iterations"])]
    time: Option<f64>,
    /// Gaussian-filter cut-off wavelength λc in the mesh's length unit (50 % amplitude
    /// transmission; t = 0.017558 λc²), instead of --iterations.
    #[arg(long, allow_negative_numbers = true, conflicts_with = "iterations")]
    cutoff: Option<f64>,
    /// Stop once an iteration moves no vertex farther than this distance (mesh unit);
    /// --iterations stays the upper limit.
    #[arg(long, allow_negative_numbers = true)]
    until_change: Option<f64>,
    /// Vertices that never move, as 0-based indices: --pin 3,17,42.
    #[arg(long, value_delimiter = ',')]
    pin: Vec<u32>,
    /// Write a JSON report (parameters, iterations, timings, counts) to this file.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Leave out the per-iteration displacement statistics (the report's `steps` is then
    /// empty). They cost a square root per vertex and iteration; without --report they
    /// are never computed. The positions are the same either way.
    #[arg(long, requires = "report")]
    no_step_stats: bool,
    /// Write PLY output as ascii text instead of binary (STL likewise).
    #[arg(long)]
    ascii: bool,
    /// Replace OUT (or the --report file) even when it is the input file or
    /// write-protected.
    #[arg(long)]
    force: bool,
    /// Fail before building the mesh when the run is estimated to need more memory
    /// than this: bytes, or with a binary unit K, M, G, T (512M, 2G, 1.5G).
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    max_memory: Option<u64>,
    /// Print the estimated memory and the planned iterations of the run on stderr
    /// (printed anyway for more than a million vertices or 10 000 iterations).
    #[arg(long)]
    verbose: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// The default of `--max-iterations`.
const DEFAULT_MAX_ITERATIONS: usize = 1_000_000;

/// Runs planning more iterations than this print their plan without `--verbose`.
const LARGE_RUN_ITERATIONS: usize = 10_000;

/// The default λ, and Taubin's classic pair (λ, μ) = (0.6307, −0.6732), whose pass
/// band `1/λ + 1/μ` is 0.1 (Taubin 1995).
const DEFAULT_LAMBDA: f64 = 0.8;
const TAUBIN_LAMBDA: f64 = 0.6307;
const TAUBIN_PASS_BAND: f64 = 0.1;
const HC_ALPHA: f64 = 0.1;
const HC_BETA: f64 = 0.6;

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum BoundaryArg {
    Fixed,
    Free,
    Curve,
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum UpdateArg {
    Every,
    Once,
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum NegativeArg {
    Keep,
    Clamp,
    Abs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum MethodArg {
    Explicit,
    Taubin,
    Hc,
    Implicit,
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum SolverArg {
    Cholesky,
    Cg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum NormalizeArg {
    Sum,
    Area,
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
enum AreaArg {
    Mixed,
    Barycentric,
}

impl SmoothArgs {
    /// λ as given, or the method's default.
    fn lambda(&self) -> f64 {
        self.lambda.unwrap_or(match self.method {
            MethodArg::Taubin => TAUBIN_LAMBDA,
            _ => DEFAULT_LAMBDA,
        })
    }

    /// The normalisation as given, or the default: weight sum.
    fn normalize(&self) -> NormalizeArg {
        self.normalize.unwrap_or(NormalizeArg::Sum)
    }

    fn solver(&self) -> SolverArg {
        self.solver.unwrap_or(SolverArg::Cg)
    }

    /// Refuses options that the chosen method would ignore, before any work.
    fn check_combination(&self) -> Result<(), CliError> {
        let method = format!("{:?}", self.method).to_lowercase();
        let refuse = |option: &str, wanted: &str| {
            Err(CliError::Usage(format!(
                "{option} applies to --method {wanted} only, not to --method {method}"
            )))
        };
        if self.mu.is_some() && self.method != MethodArg::Taubin {
            return refuse("--mu", "taubin");
        }
        if self.hc_alpha.is_some() && self.method != MethodArg::Hc {
            return refuse("--hc-alpha", "hc");
        }
        if self.hc_beta.is_some() && self.method != MethodArg::Hc {
            return refuse("--hc-beta", "hc");
        }
        if self.solver.is_some() && self.method != MethodArg::Implicit {
            return refuse("--solver", "implicit");
        }
        if self.method == MethodArg::Implicit && self.preserve_volume {
            return Err(CliError::Usage(
                "--preserve-volume does not apply to --method implicit".into(),
            ));
        }
        if matches!(self.method, MethodArg::Taubin | MethodArg::Hc)
            && (self.time.is_some() || self.cutoff.is_some())
        {
            return Err(CliError::Usage(format!(
                "--time and --cutoff apply to plain diffusion (--method explicit or implicit), not to --method {method}"
            )));
        }
        Ok(())
    }

    fn config(&self) -> SmoothConfig {
        let normalization = match (self.normalize(), self.vertex_area) {
            (NormalizeArg::Sum, _) => Normalization::WeightSum,
            (NormalizeArg::Area, AreaArg::Mixed) => {
                Normalization::Area(VertexAreaKind::MixedVoronoi)
            }
            (NormalizeArg::Area, AreaArg::Barycentric) => {
                Normalization::Area(VertexAreaKind::Barycentric)
            }
        };
        let negative = match self.cotangent_negative {
            NegativeArg::Keep => NegativeWeights::Keep,
            NegativeArg::Clamp => NegativeWeights::Clamp,
            NegativeArg::Abs => NegativeWeights::Abs,
        };
        let mut config = SmoothConfig::new(self.lambda(), self.iterations)
            .boundary(match self.boundary {
                BoundaryArg::Fixed => Boundary::Fixed,
                BoundaryArg::Free => Boundary::Free,
                BoundaryArg::Curve => Boundary::Curve,
            })
            .update(match self.update {
                UpdateArg::Every => WeightUpdate::Every,
                UpdateArg::Once => WeightUpdate::Once,
            })
            .laplacian(LaplacianOptions {
                normalization,
                negative,
            })
            .pinned(self.pin.iter().copied().map(VertexId::new).collect())
            .method(self.method())
            .preserve_volume(self.preserve_volume);
        if let Some(t) = self.time {
            config = config.duration(DiffusionTime::Time(t));
        }
        if let Some(lc) = self.cutoff {
            config = config.duration(DiffusionTime::Cutoff(lc));
        }
        if let Some(eps) = self.until_change {
            config = config.until_change(eps);
        }
        if self.report.is_none() || self.no_step_stats {
            config = config.statistics(Statistics::OnDemand);
        }
        config
    }

    fn method(&self) -> Method {
        match self.method {
            MethodArg::Explicit => Method::Laplacian,
            MethodArg::Implicit => Method::implicit(match self.solver() {
                SolverArg::Cholesky => ImplicitSolver::Cholesky,
                SolverArg::Cg => ImplicitSolver::conjugate_gradient(),
            }),
            MethodArg::Taubin => match self.mu {
                Some(mu) => Method::Taubin { mu },
                None => Method::taubin_pass_band(self.lambda(), TAUBIN_PASS_BAND),
            },
            MethodArg::Hc => Method::Hc {
                alpha: self.hc_alpha.unwrap_or(HC_ALPHA),
                beta: self.hc_beta.unwrap_or(HC_BETA),
            },
        }
    }
}

/// The JSON written by `--report`.
#[derive(Debug, Serialize)]
struct Report<'a> {
    input: String,
    output: String,
    vertices: usize,
    faces: usize,
    parameters: Parameters<'a>,
    iterations: usize,
    stop: &'static str,
    /// The largest number of vertices that could not move in one iteration (weights
    /// summing to ≤ 0, zero area).
    max_stuck_vertices: usize,
    seconds: Seconds,
    steps: Vec<Step>,
    /// Solver figures of --method implicit.
    #[serde(skip_serializing_if = "Option::is_none")]
    implicit: Option<ImplicitFigures>,
}

/// What the implicit solver did (`--method implicit`).
#[derive(Debug, Serialize)]
struct ImplicitFigures {
    solver: SolverArg,
    time_step: f64,
    numeric_factorizations: usize,
    factor_nonzeros: usize,
    cg_iterations: usize,
    seconds_assembly: f64,
    seconds_analysis: f64,
    seconds_factorization: f64,
    seconds_solve: f64,
}

#[derive(Debug, Serialize)]
struct Parameters<'a> {
    weights: &'a str,
    lambda: f64,
    iterations: usize,
    boundary: BoundaryArg,
    update: UpdateArg,
    cotangent_negative: NegativeArg,
    normalize: NormalizeArg,
    vertex_area: AreaArg,
    pinned: usize,
    method: MethodArg,
    /// Taubin's μ (taubin only).
    mu: Option<f64>,
    /// HC's α and β (hc only).
    hc: Option<[f64; 2]>,
    preserve_volume: bool,
    /// The diffusion time asked for, length² (with --time or --cutoff).
    time: Option<f64>,
    /// The cut-off wavelength asked for (with --cutoff).
    cutoff: Option<f64>,
    until_change: Option<f64>,
    /// The step actually used (differs from `lambda` with --time or --cutoff).
    lambda_used: f64,
    /// The iteration count planned (differs from `iterations` with --time or --cutoff).
    iterations_planned: usize,
}

#[derive(Debug, Serialize)]
struct Seconds {
    /// Everything up to the built mesh: memory checks, `parse` and `build`.
    read: f64,
    /// Reading and decoding the file.
    parse: f64,
    /// Building and validating the half-edge connectivity.
    build: f64,
    weights: f64,
    updates: f64,
    write: f64,
}

#[derive(Debug, Serialize)]
struct Step {
    iteration: usize,
    max_displacement: f64,
    mean_displacement: f64,
    stuck_vertices: usize,
}

/// Runs `beltrami smooth`.
pub(crate) fn run(
    args: &SmoothArgs,
    registry: &WeightRegistry,
    out: &mut impl Write,
) -> Result<(), CliError> {
    let scheme = registry.get(&args.weights)?;
    args.check_combination()?;
    let mut outputs = Outputs::new();
    outputs
        .add(&args.output, "OUTPUT")
        .add_opt(args.report.as_ref(), "--report");
    outputs.check(&[&args.input], args.force)?;
    let t0 = Instant::now();
    // A first check on the counts the file declares (PLY header, binary STL count),
    // before anything is read; then on the exact counts, before the mesh is built.
    let memory = memory_run(args, scheme.as_ref());
    if let Ok(Some(declared)) = declared_counts(&args.input) {
        let faces = declared.faces;
        let estimate = match declared.vertices {
            Some(vertices) => {
                MemoryEstimate::new(&memory, vertices, faces, faces.saturating_mul(3))
            }
            None => MemoryEstimate::for_triangle_soup(&memory, faces),
        };
        check_memory(args, &estimate, false)?;
    }
    let loaded = load_checked(&args.input, &args.read, |data| {
        let estimate = MemoryEstimate::new(
            &memory,
            data.positions.len(),
            data.faces.len(),
            data.faces.n_corners(),
        );
        check_memory(args, &estimate, true)
    })?;
    loaded.require_faces(&args.input, "smooth")?;
    let read_seconds = t0.elapsed().as_secs_f64();
    let smoothed = run_smoother(args, &loaded.mesh, &loaded.positions, scheme.as_ref())?;

    let t1 = Instant::now();
    let change = Change::between(&loaded.mesh, &loaded.positions, &smoothed.positions);
    let data = MeshData {
        positions: smoothed.positions,
        faces: loaded.faces,
    };
    let mut staged = Staged::new();
    staged.push_mesh(&args.output, &data, args.ascii)?;
    let write_seconds = t1.elapsed().as_secs_f64();

    let r = &smoothed.report;
    if let Some(path) = &args.report {
        let read = ReadSeconds {
            total: read_seconds,
            parse: loaded.parse_seconds,
            build: loaded.build_seconds,
        };
        let report = build_report(args, &data, r, read, write_seconds);
        let mut json = serde_json::to_vec_pretty(&report).map_err(std::io::Error::from)?;
        json.push(b'\n');
        staged.push(path, |path| stage_bytes(path, &json))?;
    }
    staged.commit()?;

    for line in &loaded.repair_lines {
        writeln!(out, "{line}")?;
    }
    let boundary = if loaded.mesh.is_closed() {
        "no boundary".to_string()
    } else {
        format!("{} boundary", format!("{:?}", args.boundary).to_lowercase())
    };
    writeln!(
        out,
        "smoothed {} ({} vertices) with {} weights, {}: {} {}, lambda {}, {boundary}, {}; mean displacement {}{} -> {}",
        args.input.display(),
        data.positions.len(),
        r.scheme,
        method_label(args),
        r.iterations,
        plural(r.iterations, "iteration", "iterations"),
        number(r.config.lambda),
        r.stop.name(),
        number(change.mean_displacement),
        change
            .volume
            .map(|(before, after)| format!(
                ", volume {} -> {} ({:+.3} %)",
                number(before),
                number(after),
                100.0 * (after - before) / before
            ))
            .unwrap_or_default(),
        args.output.display()
    )?;
    if let Some(d) = r.config.duration {
        writeln!(
            out,
            "diffusion time {} (length²), Gaussian sigma {}",
            number(d.time()),
            number(d.sigma())
        )?;
    }
    if r.max_stuck_vertices > 0 {
        let why = if loaded.mesh.is_triangle_mesh() {
            "weights summing to <= 0 or zero area".to_string()
        } else {
            format!(
                "the mesh has polygon faces, on which {} weights are 0; use --weights uniform or distance, or triangulate the mesh",
                r.scheme
            )
        };
        writeln!(
            out,
            "note: up to {} {} per iteration could not move ({why})",
            r.max_stuck_vertices,
            plural(r.max_stuck_vertices, "vertex", "vertices"),
        )?;
    }
    Ok(())
}

/// How far a run moved the mesh: the mean vertex displacement, and for a closed mesh
/// the enclosed volume before and after.
struct Change {
    mean_displacement: f64,
    volume: Option<(f64, f64)>,
}

impl Change {
    fn between(mesh: &HalfedgeMesh, before: &[DVec3], after: &[DVec3]) -> Self {
        let n = before.len().max(1);
        let mean_displacement = before
            .iter()
            .zip(after)
            .map(|(a, b)| a.distance(*b))
            .sum::<f64>()
            / n as f64;
        let volume = |positions| {
            Geometry::new(mesh, positions)
                .ok()
                .and_then(|g| g.volume().ok())
        };
        let volume = if mesh.is_closed() {
            volume(before).zip(volume(after)).filter(|(b, _)| *b != 0.0)
        } else {
            None
        };
        Self {
            mean_displacement,
            volume,
        }
    }
}

/// An invalid Taubin pair, with a pair that works: Taubin's classic (0.6307, −0.6732),
/// or with the μ given, the largest λ that keeps both conditions.
fn taubin_hint(args: &SmoothArgs, e: CliError) -> CliError {
    let CliError::Smooth {
        source: source @ SmoothError::InvalidTaubin { .. },
        ..
    } = &e
    else {
        return e;
    };
    let hint = match args.mu {
        Some(mu) if mu.is_finite() && mu < 0.0 => {
            // λ < −μ (positive pass band) and (1 − 2λ)(1 − 2μ) > −1 (no growth).
            let limit = (-mu).min(0.5 * (1.0 + 1.0 / (1.0 - 2.0 * mu)));
            format!("with --mu {mu}, take --lambda below {}", number(limit))
        }
        _ => format!(
            "leave --lambda out for Taubin's classic pair (lambda {TAUBIN_LAMBDA}, mu -0.6732, pass band {TAUBIN_PASS_BAND})"
        ),
    };
    CliError::Usage(format!("{source}; {hint}"))
}

/// Fails with [`CliError::MemoryLimit`] when `estimate` exceeds `--max-memory`; with
/// `report` (the exact counts), prints the estimate on stderr for a large run or
/// with `--verbose`.
fn check_memory(
    args: &SmoothArgs,
    estimate: &MemoryEstimate,
    report: bool,
) -> Result<(), CliError> {
    if let Some(limit) = args.max_memory {
        if estimate.bytes > limit {
            return Err(CliError::MemoryLimit {
                path: args.input.clone(),
                estimate: *estimate,
                limit,
            });
        }
    }
    if report && (args.verbose || estimate.vertices > LARGE_RUN_VERTICES) {
        eprintln!("note: this run needs {estimate} of memory");
    }
    Ok(())
}

/// What the run does, as far as its memory goes: the method and solver, the weights'
/// path, the options that add buffers, and the iterations whose statistics it keeps
/// (unknown before the operator is built for an explicit run for a time).
fn memory_run(args: &SmoothArgs, scheme: &dyn WeightScheme) -> memory::Run {
    let implicit = args.method == MethodArg::Implicit;
    let for_time = args.time.is_some() || args.cutoff.is_some();
    memory::Run {
        method: match (args.method, args.solver()) {
            (MethodArg::Explicit, _) => memory::Method::Explicit,
            (MethodArg::Taubin, _) => memory::Method::Taubin,
            (MethodArg::Hc, _) => memory::Method::Hc,
            (MethodArg::Implicit, SolverArg::Cg) => memory::Method::ImplicitCg,
            (MethodArg::Implicit, SolverArg::Cholesky) => memory::Method::ImplicitCholesky,
        },
        weights: memory::Weights::of(scheme),
        preserve_volume: args.preserve_volume,
        area: args.normalize() == NormalizeArg::Area,
        iterations: match (implicit, for_time) {
            (true, true) => 1,
            (false, true) => 0,
            (_, false) => args.iterations,
        },
        report_steps: args.report.is_some() && !args.no_step_stats,
    }
}

/// The reading time of a run and its two parts, in seconds.
#[derive(Clone, Copy, Debug)]
struct ReadSeconds {
    total: f64,
    parse: f64,
    build: f64,
}

fn build_report<'a>(
    args: &'a SmoothArgs,
    data: &MeshData,
    r: &SmoothReport,
    read: ReadSeconds,
    write: f64,
) -> Report<'a> {
    Report {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        vertices: data.positions.len(),
        faces: data.faces.len(),
        parameters: Parameters {
            weights: &args.weights,
            lambda: args.lambda(),
            iterations: args.iterations,
            boundary: args.boundary,
            update: args.update,
            cotangent_negative: args.cotangent_negative,
            normalize: args.normalize(),
            vertex_area: args.vertex_area,
            pinned: args.pin.len(),
            method: args.method,
            mu: match r.config.method {
                Method::Taubin { mu } => Some(mu),
                _ => None,
            },
            hc: match r.config.method {
                Method::Hc { alpha, beta } => Some([alpha, beta]),
                _ => None,
            },
            preserve_volume: args.preserve_volume,
            time: r.config.duration.map(|d| d.time()),
            cutoff: args.cutoff,
            until_change: args.until_change,
            lambda_used: r.config.lambda,
            iterations_planned: r.config.iterations,
        },
        iterations: r.iterations,
        stop: r.stop.name(),
        max_stuck_vertices: r.max_stuck_vertices,
        seconds: Seconds {
            read: read.total,
            parse: read.parse,
            build: read.build,
            // An implicit run's weights include the matrix's analysis and factorisations.
            weights: (r.weight_time
                + r.solver
                    .as_ref()
                    .map_or(Duration::ZERO, |s| s.analysis_time + s.factorization_time))
            .as_secs_f64(),
            updates: r.update_time.as_secs_f64(),
            write,
        },
        steps: r
            .steps
            .iter()
            .enumerate()
            .map(|(i, s)| Step {
                iteration: i + 1,
                max_displacement: s.max_displacement,
                mean_displacement: s.mean_displacement,
                stuck_vertices: s.stuck_vertices,
            })
            .collect(),
        implicit: r.solver.as_ref().map(|s| ImplicitFigures {
            solver: args.solver(),
            time_step: r.config.lambda,
            numeric_factorizations: s.numeric_factorizations,
            factor_nonzeros: s.factor_nonzeros,
            cg_iterations: s.cg_iterations,
            seconds_assembly: r.weight_time.as_secs_f64(),
            seconds_analysis: s.analysis_time.as_secs_f64(),
            seconds_factorization: s.factorization_time.as_secs_f64(),
            seconds_solve: r.update_time.as_secs_f64(),
        }),
    }
}

/// The method as printed: `explicit`, `taubin (mu -0.53)`, `hc (alpha 0.1, beta 0.6)`,
/// with `+ volume` when the volume is preserved.
fn method_label(args: &SmoothArgs) -> String {
    let mut label = match args.method() {
        Method::Taubin { mu } => format!("taubin (mu {mu:.6})"),
        Method::Hc { alpha, beta } => format!("hc (alpha {alpha}, beta {beta})"),
        Method::Implicit { .. } => "implicit".to_string(),
        _ => "explicit".to_string(),
    };
    if args.preserve_volume {
        label.push_str(" + volume");
    }
    label
}

/// A progress bar on a terminal for runs of 20 iterations or more.
fn progress_bar(planned: usize) -> Option<indicatif::ProgressBar> {
    (std::io::stderr().is_terminal() && planned >= 20).then(|| {
        let bar = indicatif::ProgressBar::new(planned as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} iterations {elapsed}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    })
}

/// Every method (plain, Taubin, HC, implicit) through [`Smoother`].
fn run_smoother(
    args: &SmoothArgs,
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn WeightScheme,
) -> Result<Smoothed, CliError> {
    let smooth_error = |source| {
        taubin_hint(
            args,
            CliError::Smooth {
                path: args.input.clone(),
                source,
            },
        )
    };
    let smoother = Smoother::new(mesh, positions, scheme, args.config()).map_err(smooth_error)?;
    // A step given directly must be stable; a time chooses its own stable step.
    if let Some(limit) = smoother.stable_step_limit()
        && smoother.config().duration.is_none()
        && smoother.config().lambda > limit
    {
        return Err(smooth_error(SmoothError::UnstableStep {
            lambda: smoother.config().lambda,
            max_stable: limit,
        }));
    }
    check_plan(args, smoother.config().iterations, smoother.config().lambda)?;
    let progress = progress_bar(smoother.config().iterations);
    let smoothed = smoother
        .run(|it| {
            if let Some(bar) = &progress {
                bar.set_position(it.index as u64);
            }
            ControlFlow::Continue(())
        })
        .map_err(smooth_error)?;
    if let Some(bar) = progress {
        bar.finish_and_clear();
    }
    Ok(smoothed)
}

/// Refuses a run planning more than `--max-iterations` iterations, and prints the
/// plan on stderr with `--verbose` or for a long run.
fn check_plan(args: &SmoothArgs, iterations: usize, step: f64) -> Result<(), CliError> {
    if iterations > args.max_iterations {
        return Err(CliError::Usage(format!(
            "the run would take {iterations} iterations of step {}, more than --max-iterations {} (is --time or --cutoff in the mesh's length unit? raise --max-iterations to run it anyway)",
            number(step),
            args.max_iterations
        )));
    }
    if args.verbose || iterations > LARGE_RUN_ITERATIONS {
        eprintln!(
            "note: planned {iterations} {} of step {}",
            plural(iterations, "iteration", "iterations"),
            number(step)
        );
    }
    Ok(())
}
