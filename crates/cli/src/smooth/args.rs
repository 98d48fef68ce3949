//! The arguments of `beltrami smooth`, their defaults and how they become a
//! configuration.

use std::path::PathBuf;

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_smooth::{
    Boundary, DiffusionTime, ImplicitSolver, Method, SmoothConfig, Statistics, Summation,
    WeightUpdate,
};
use beltrami_weights::{LaplacianOptions, NegativeWeights, Normalization};
use clap::ValueEnum;
use serde::Serialize;

use crate::error::CliError;
use crate::load::ReadArgs;
use crate::memory::parse_size;

/// Arguments of `beltrami smooth`.
///
/// The defaults are the paper's explicit scheme with the most accurate weights:
/// cotangent weights recomputed every iteration (the geometric flow), λ = 0.8,
/// 10 iterations, weight-sum normalisation, and a fixed boundary so that a measured
/// patch keeps its outline.
#[derive(Debug, clap::Args)]
pub(crate) struct SmoothArgs {
    /// The input mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    pub(crate) input: PathBuf,
    /// The output mesh (.ply, .stl, .obj or .off); same vertices and faces, new positions.
    pub(crate) output: PathBuf,
    /// The weight scheme: uniform, distance, cotangent, or a registered name.
    #[arg(long, default_value = "cotangent")]
    pub(crate) weights: String,
    /// The step. Weight-sum normalisation: a fraction in (0, 1]. Area
    /// normalisation: a diffusion time per iteration, in length², which an explicit
    /// run must keep below its stability limit (checked before the run). Default 0.8;
    /// 0.6307 for --method taubin (Taubin's classic pair with μ = -0.6732, pass band
    /// 0.1); with --normalize area, that fraction of the largest stable explicit step
    /// on the input (with cotangent weights about 0.2 h² on a regular mesh of edge
    /// length h; μ and the pass band scaled alike), printed in a note.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) lambda: Option<f64>,
    /// The number of iterations (the upper limit with --until-change).
    #[arg(long, default_value_t = 10)]
    pub(crate) iterations: usize,
    /// Refuse a run that plans more iterations than this (a --time or --cutoff in the
    /// wrong unit can mean millions).
    #[arg(long, default_value_t = DEFAULT_MAX_ITERATIONS)]
    pub(crate) max_iterations: usize,
    /// How boundary vertices move: fixed (never), free (like interior ones), curve
    /// (along the boundary polyline only).
    #[arg(long, value_enum, default_value_t = BoundaryArg::Fixed)]
    pub(crate) boundary: BoundaryArg,
    /// When weights are computed: every iteration (geometric flow) or once from the
    /// input (a linear filter, as OpenMesh does).
    #[arg(long, value_enum, default_value_t = UpdateArg::Every)]
    pub(crate) update: UpdateArg,
    /// Treatment of negative weights (cotangent weights of edges whose opposite angles
    /// sum to more than 180°): keep them, clamp them to 0, or take their absolute value.
    #[arg(long, value_enum, default_value_t = NegativeArg::Keep)]
    pub(crate) cotangent_negative: NegativeArg,
    /// How cotangents are computed (the same results either way): per-triangle (each
    /// triangle once, a per-face table of about 120 bytes per vertex), ring (from each
    /// vertex's one-ring: no table, about 1.4 times the time), or auto (per-triangle,
    /// ring when only that fits the memory available or --max-memory; ring with
    /// --summation scatter, whose sweeps use neither, and with --update once, which
    /// computes the weights once).
    #[arg(long, value_enum, default_value_t = CotangentKernelArg::Auto)]
    pub(crate) cotangent_kernel: CotangentKernelArg,
    /// How each vertex's weighted neighbours are summed: rows (around each vertex's
    /// one-ring, as OpenMesh does, with OpenMesh's bits; the default) or scatter (each
    /// triangle's three cotangents, or each edge's inverse distance, computed once and
    /// added into its vertices' sums: 22 to 47 % less time per iteration with inverse
    /// distances, 11 to 36 % less with cotangents; the same results to rounding but not
    /// bit for bit). scatter applies to
    /// --weights cotangent (with --cotangent-negative keep) and --weights distance, with
    /// --update every, --normalize sum and --method explicit, without
    /// --preserve-volume.
    #[arg(long, value_enum, default_value_t = SummationArg::Rows)]
    pub(crate) summation: SummationArg,
    /// Row normalisation: sum (divide by the weight sum, paper Eq. 2) or area (divide
    /// by the vertex area, paper Eq. 6). Default: sum, for every method (a --time or
    /// --cutoff is converted to steps either way).
    #[arg(long, value_enum)]
    pub(crate) normalize: Option<NormalizeArg>,
    /// The vertex area for --normalize area (only): mixed (Meyer et al.'s mixed Voronoi
    /// area, the default) or barycentric.
    #[arg(long, value_enum)]
    pub(crate) vertex_area: Option<AreaArg>,
    /// The method: explicit (plain diffusion, shrinks), taubin (λ|μ: a λ sweep then a
    /// μ sweep per iteration, keeps the form), hc (pushes each vertex back towards the
    /// input; for open patches), implicit (backward Euler, (M − λL) x' = M x per step,
    /// stable for any λ; with --time/--cutoff steps of at most λ that add up to the
    /// time). See docs/methods.md and docs/implicit.md.
    #[arg(long, value_enum, default_value_t = MethodArg::Explicit)]
    pub(crate) method: MethodArg,
    /// The linear solver of --method implicit (only): cg (Jacobi-preconditioned
    /// conjugate gradient to a relative residual of 1e-10, no set-up, memory linear in
    /// the mesh; the default) or cholesky (sparse factorisation, exact to rounding,
    /// factorised once while the weights are frozen; pays off for many frozen steps of
    /// a large λ on a mesh small enough to factorise).
    #[arg(long, value_enum)]
    pub(crate) solver: Option<SolverArg>,
    /// Taubin's negative step μ (--method taubin only; μ < -λ, pass band 1/λ + 1/μ).
    /// Default: the μ giving a pass band of 0.1 (with --normalize area and no --lambda,
    /// 0.1 over the largest stable explicit step: μ = -0.6732 times that step).
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) mu: Option<f64>,
    /// HC (--method hc only): the pull towards the input positions, in [0, 1].
    /// Default 0.1.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) hc_alpha: Option<f64>,
    /// HC (--method hc only): the weight of a vertex's own correction against its
    /// neighbours', in [0, 1]. Default 0.6.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) hc_beta: Option<f64>,
    /// Rescale about the centroid after every iteration so that the enclosed volume
    /// stays the input's (closed meshes only).
    #[arg(long)]
    pub(crate) preserve_volume: bool,
    /// Diffuse for this time, in length² of the mesh's unit (e.g. mm²), instead of
    /// --iterations; --lambda is then the largest step and the iteration count follows.
    #[arg(long, allow_hyphen_values = true, conflicts_with_all = ["cutoff", "iterations"])]
    pub(crate) time: Option<f64>,
    /// Gaussian-filter cut-off wavelength λc in the mesh's length unit (50 % amplitude
    /// transmission; t = 0.017558 λc²), instead of --iterations.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "iterations")]
    pub(crate) cutoff: Option<f64>,
    /// Stop once an iteration moves no vertex farther than this distance (mesh unit);
    /// --iterations stays the upper limit.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) until_change: Option<f64>,
    /// Vertices that never move, as 0-based indices: --pin 3,17,42.
    #[arg(long, value_delimiter = ',')]
    pub(crate) pin: Vec<u32>,
    /// Write a JSON report (parameters, iterations, timings, counts) to this file.
    #[arg(long)]
    pub(crate) report: Option<PathBuf>,
    /// Leave out the per-iteration displacement statistics (the report's `steps` is then
    /// empty). They cost a square root per vertex and iteration; without --report they
    /// are never computed. The positions are the same either way.
    #[arg(long, requires = "report")]
    pub(crate) no_step_stats: bool,
    /// Write PLY output as ascii text instead of binary (STL likewise).
    #[arg(long)]
    pub(crate) ascii: bool,
    /// Replace OUT even when it is the input file (an edit in place), and OUT or the
    /// --report file even when write-protected. No other output replaces an input.
    #[arg(long)]
    pub(crate) force: bool,
    /// Fail before building the mesh when the run is estimated to need more memory
    /// than this: bytes, or with a binary unit K, M, G, T (512M, 2G, 1.5G). Without
    /// it, a run stops when its estimate exceeds the memory available to it (Linux:
    /// MemAvailable plus free swap, within the process's address-space limit and its
    /// control group's memory limit); a size given here overrides that.
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub(crate) max_memory: Option<u64>,
    /// Print the estimated memory and the planned iterations of the run on stderr
    /// (printed anyway for more than a million vertices or 10 000 iterations).
    #[arg(long)]
    pub(crate) verbose: bool,
    #[command(flatten)]
    pub(crate) read: ReadArgs,
}

/// The default of `--max-iterations`.
pub(crate) const DEFAULT_MAX_ITERATIONS: usize = 1_000_000;

/// Runs planning more iterations than this print their plan without `--verbose`.
pub(crate) const LARGE_RUN_ITERATIONS: usize = 10_000;

pub(crate) use beltrami_smooth::{DEFAULT_LAMBDA, TAUBIN_LAMBDA, TAUBIN_PASS_BAND};

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum BoundaryArg {
    Fixed,
    Free,
    Curve,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum UpdateArg {
    Every,
    Once,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum NegativeArg {
    Keep,
    Clamp,
    Abs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum MethodArg {
    Explicit,
    Taubin,
    Hc,
    Implicit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum CotangentKernelArg {
    Auto,
    PerTriangle,
    Ring,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum SummationArg {
    Rows,
    Scatter,
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum SolverArg {
    Cholesky,
    Cg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum NormalizeArg {
    Sum,
    Area,
}

/// The row normalisation of `--normalize` and `--vertex-area`.
pub(crate) fn normalization(normalize: NormalizeArg, area: AreaArg) -> Normalization {
    match (normalize, area) {
        (NormalizeArg::Sum, _) => Normalization::WeightSum,
        (NormalizeArg::Area, AreaArg::Mixed) => Normalization::Area(VertexAreaKind::MixedVoronoi),
        (NormalizeArg::Area, AreaArg::Barycentric) => {
            Normalization::Area(VertexAreaKind::Barycentric)
        }
    }
}

impl NegativeArg {
    /// The negative-weight policy of `--cotangent-negative`.
    pub(crate) fn policy(self) -> NegativeWeights {
        match self {
            Self::Keep => NegativeWeights::Keep,
            Self::Clamp => NegativeWeights::Clamp,
            Self::Abs => NegativeWeights::Abs,
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum AreaArg {
    Mixed,
    Barycentric,
}

impl SmoothArgs {
    /// λ as given, or the method's default.
    pub(crate) fn lambda(&self) -> f64 {
        self.lambda.unwrap_or(match self.method {
            MethodArg::Taubin => TAUBIN_LAMBDA,
            _ => DEFAULT_LAMBDA,
        })
    }

    /// The normalisation as given, or the default: weight sum.
    pub(crate) fn normalize(&self) -> NormalizeArg {
        self.normalize.unwrap_or(NormalizeArg::Sum)
    }

    pub(crate) fn solver(&self) -> SolverArg {
        self.solver.unwrap_or(SolverArg::Cg)
    }

    /// Refuses options that the chosen method would ignore, before any work.
    pub(crate) fn check_combination(&self) -> Result<(), CliError> {
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
        if self.vertex_area.is_some() && self.normalize() != NormalizeArg::Area {
            return Err(CliError::Usage(
                "--vertex-area applies to --normalize area only (weight-sum rows use no vertex area)".into(),
            ));
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

    /// `--vertex-area`, mixed when not given.
    pub(crate) fn vertex_area(&self) -> AreaArg {
        self.vertex_area.unwrap_or(AreaArg::Mixed)
    }

    pub(crate) fn config(&self) -> SmoothConfig {
        let normalization = normalization(self.normalize(), self.vertex_area());
        let negative = self.cotangent_negative.policy();
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
        if self.report.is_none() || self.no_step_stats {
            config = config.statistics(Statistics::OnDemand);
        }
        config.summation(match self.summation {
            SummationArg::Rows => Summation::Rows,
            SummationArg::Scatter => Summation::Scatter,
        })
    }

    pub(crate) fn method(&self) -> Method {
        match self.method {
            MethodArg::Explicit => Method::Laplacian,
            MethodArg::Implicit => Method::implicit(match self.solver() {
                SolverArg::Cholesky => ImplicitSolver::Cholesky,
                SolverArg::Cg => ImplicitSolver::conjugate_gradient(),
            }),
            MethodArg::Taubin => Method::taubin_or_pass_band(self.lambda(), self.mu),
            MethodArg::Hc => Method::hc_or_default(self.hc_alpha, self.hc_beta),
        }
    }
}
