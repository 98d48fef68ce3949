//! `beltrami smooth`: Laplacian diffusion smoothing of a mesh file.

use std::io::{IsTerminal, Write};
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::time::Instant;

use beltrami_halfedge::VertexId;
use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_io::{
    Encoding, MeshData, WriteOptions, declared_counts, write_bytes_atomic, write_mesh,
};
use beltrami_smooth::{Boundary, SmoothConfig, SmoothReport, Smoother, StopReason, WeightUpdate};
use beltrami_weights::{LaplacianOptions, NegativeWeights, Normalization, WeightRegistry};
use clap::ValueEnum;
use serde::Serialize;

use crate::error::CliError;
use crate::load::load_checked;
use crate::memory::{LARGE_RUN_VERTICES, MemoryEstimate, parse_size};
use crate::output::check_not_input;

/// Arguments of `beltrami smooth`.
///
/// The defaults are the paper's explicit scheme with the most accurate weights:
/// cotangent weights recomputed every iteration (the geometric flow), λ = 0.8,
/// 10 iterations, weight-sum normalisation, and a fixed boundary so that a measured
/// patch keeps its outline.
#[derive(Debug, clap::Args)]
pub(crate) struct SmoothArgs {
    /// The input mesh (.ply, .stl or .obj).
    input: PathBuf,
    /// The output mesh (.ply, .stl or .obj); same vertices and faces, new positions.
    output: PathBuf,
    /// The weight scheme: uniform, distance, cotangent, or a registered name.
    #[arg(long, default_value = "cotangent")]
    weights: String,
    /// The step. Weight-sum normalisation: a fraction in (0, 1]. Area
    /// normalisation: a diffusion time per iteration, in length².
    #[arg(long, default_value_t = 0.8)]
    lambda: f64,
    /// The number of iterations.
    #[arg(long, default_value_t = 10)]
    iterations: usize,
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
    /// by the vertex area, paper Eq. 6).
    #[arg(long, value_enum, default_value_t = NormalizeArg::Sum)]
    normalize: NormalizeArg,
    /// The vertex area for --normalize area.
    #[arg(long, value_enum, default_value_t = AreaArg::Mixed)]
    vertex_area: AreaArg,
    /// Vertices that never move, as 0-based indices: --pin 3,17,42.
    #[arg(long, value_delimiter = ',')]
    pin: Vec<u32>,
    /// Write a JSON report (parameters, iterations, timings, counts) to this file.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Write PLY output as ascii text instead of binary (STL likewise).
    #[arg(long)]
    ascii: bool,
    /// Replace OUT (or the --report file) even when it is the input file.
    #[arg(long)]
    force: bool,
    /// Fail before building the mesh when the run is estimated to need more memory
    /// than this: bytes, or with a binary unit K, M, G, T (512M, 2G, 1.5G).
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    max_memory: Option<u64>,
    /// Print the estimated memory of the run on stderr (printed anyway for more
    /// than a million vertices).
    #[arg(long)]
    verbose: bool,
}

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

#[derive(Clone, Copy, Debug, ValueEnum, Serialize)]
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
    fn config(&self) -> SmoothConfig {
        let normalization = match (self.normalize, self.vertex_area) {
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
        SmoothConfig::new(self.lambda, self.iterations)
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
}

#[derive(Debug, Serialize)]
struct Seconds {
    read: f64,
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
    check_not_input(&args.output, &[&args.input], args.force)?;
    if let Some(report) = &args.report {
        check_not_input(report, &[&args.input, &args.output], args.force)?;
    }
    let t0 = Instant::now();
    // A first check on the counts the file declares (PLY header, binary STL count),
    // before anything is read; then on the exact counts, before the mesh is built.
    if let Ok(Some(declared)) = declared_counts(&args.input) {
        let estimate = match declared.vertices {
            Some(vertices) => {
                MemoryEstimate::new(vertices, declared.faces, declared.faces.saturating_mul(3))
            }
            None => MemoryEstimate::for_triangle_soup(declared.faces),
        };
        check_memory(args, &estimate, false)?;
    }
    let loaded = load_checked(&args.input, false, |data| {
        let estimate = MemoryEstimate::new(
            data.positions.len(),
            data.faces.len(),
            data.faces.n_corners(),
        );
        check_memory(args, &estimate, true)
    })?;
    let read_seconds = t0.elapsed().as_secs_f64();
    let smooth_error = |source| CliError::Smooth {
        path: args.input.clone(),
        source,
    };
    let smoother = Smoother::new(
        &loaded.mesh,
        &loaded.positions,
        scheme.as_ref(),
        args.config(),
    )
    .map_err(smooth_error)?;

    let progress = (std::io::stderr().is_terminal() && args.iterations >= 20).then(|| {
        let bar = indicatif::ProgressBar::new(args.iterations as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} iterations {elapsed}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
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

    let t1 = Instant::now();
    let encoding = if args.ascii {
        Encoding::Ascii
    } else {
        Encoding::BinaryLittleEndian
    };
    let data = MeshData {
        positions: smoothed.positions,
        faces: loaded.faces,
    };
    write_mesh(
        &args.output,
        &data,
        &WriteOptions {
            encoding,
            ..WriteOptions::default()
        },
    )
    .map_err(|source| CliError::Io {
        path: args.output.clone(),
        source,
    })?;
    let write_seconds = t1.elapsed().as_secs_f64();

    let r = &smoothed.report;
    writeln!(
        out,
        "smoothed {} ({} vertices) with {} weights: {} iteration(s), lambda {}, {} boundary -> {}",
        args.input.display(),
        data.positions.len(),
        r.scheme,
        r.iterations,
        args.lambda,
        format!("{:?}", args.boundary).to_lowercase(),
        args.output.display()
    )?;
    if r.max_stuck_vertices > 0 {
        writeln!(
            out,
            "note: up to {} vertex(es) per iteration could not move (weights summing to <= 0 or zero area)",
            r.max_stuck_vertices
        )?;
    }
    if let Some(path) = &args.report {
        let report = build_report(args, &data, r, read_seconds, write_seconds);
        let mut json = serde_json::to_vec_pretty(&report).map_err(std::io::Error::from)?;
        json.push(b'\n');
        write_bytes_atomic(path, &json).map_err(|source| CliError::Io {
            path: path.clone(),
            source,
        })?;
    }
    Ok(())
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

fn build_report<'a>(
    args: &'a SmoothArgs,
    data: &MeshData,
    r: &SmoothReport,
    read: f64,
    write: f64,
) -> Report<'a> {
    Report {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        vertices: data.positions.len(),
        faces: data.faces.len(),
        parameters: Parameters {
            weights: &args.weights,
            lambda: args.lambda,
            iterations: args.iterations,
            boundary: args.boundary,
            update: args.update,
            cotangent_negative: args.cotangent_negative,
            normalize: args.normalize,
            vertex_area: args.vertex_area,
            pinned: args.pin.len(),
        },
        iterations: r.iterations,
        stop: match r.stop {
            StopReason::Completed => "completed",
            StopReason::Observer => "stopped",
            _ => "other",
        },
        max_stuck_vertices: r.max_stuck_vertices,
        seconds: Seconds {
            read,
            weights: r.weight_time.as_secs_f64(),
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
    }
}
