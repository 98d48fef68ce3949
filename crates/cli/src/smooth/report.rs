//! The JSON of `beltrami smooth --report` and the method label of its sentence.

use std::time::Duration;

use beltrami_io::MeshData;
use beltrami_smooth::{Method, SmoothReport};

use crate::text::number;
use serde::Serialize;

use super::args::{
    AreaArg, BoundaryArg, MethodArg, NegativeArg, NormalizeArg, SmoothArgs, SolverArg,
    SummationArg, UpdateArg,
};

/// The JSON written by `--report`.
#[derive(Debug, Serialize)]
pub(crate) struct Report<'a> {
    pub(crate) input: String,
    pub(crate) output: String,
    pub(crate) vertices: usize,
    pub(crate) faces: usize,
    pub(crate) parameters: Parameters<'a>,
    pub(crate) iterations: usize,
    pub(crate) stop: &'static str,
    /// The largest number of vertices that could not move in one iteration (weights
    /// summing to ≤ 0, zero area).
    pub(crate) max_stuck_vertices: usize,
    /// Iterations summed element by element (`--summation scatter`; 0 otherwise).
    pub(crate) scattered_sweeps: usize,
    /// The lines printed before the sentence: what `--repair` changed, what `--lenient`
    /// ignored, what OUTPUT's format leaves out.
    pub(crate) notes: Vec<String>,
    pub(crate) seconds: Seconds,
    pub(crate) steps: Vec<Step>,
    /// Solver figures of --method implicit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) implicit: Option<ImplicitFigures>,
}

/// What the implicit solver did (`--method implicit`).
#[derive(Debug, Serialize)]
pub(crate) struct ImplicitFigures {
    pub(crate) solver: SolverArg,
    pub(crate) time_step: f64,
    pub(crate) numeric_factorizations: usize,
    pub(crate) factor_nonzeros: usize,
    pub(crate) cg_iterations: usize,
    pub(crate) seconds_assembly: f64,
    pub(crate) seconds_analysis: f64,
    pub(crate) seconds_factorization: f64,
    pub(crate) seconds_solve: f64,
}

#[derive(Debug, Serialize)]
pub(crate) struct Parameters<'a> {
    pub(crate) weights: &'a str,
    pub(crate) lambda: f64,
    pub(crate) iterations: usize,
    pub(crate) boundary: BoundaryArg,
    pub(crate) update: UpdateArg,
    pub(crate) cotangent_negative: NegativeArg,
    /// How the rows were summed (`rows` or `scatter`).
    pub(crate) summation: SummationArg,
    pub(crate) normalize: NormalizeArg,
    pub(crate) vertex_area: AreaArg,
    pub(crate) pinned: usize,
    pub(crate) method: MethodArg,
    /// Taubin's μ (taubin only).
    pub(crate) mu: Option<f64>,
    /// HC's α and β (hc only).
    pub(crate) hc: Option<[f64; 2]>,
    pub(crate) preserve_volume: bool,
    /// The diffusion time asked for, length² (with --time or --cutoff).
    pub(crate) time: Option<f64>,
    /// The cut-off wavelength asked for (with --cutoff).
    pub(crate) cutoff: Option<f64>,
    pub(crate) until_change: Option<f64>,
    /// The step actually used (differs from `lambda` with --time or --cutoff, and with
    /// --normalize area without --lambda, where `lambda` is the fraction of the largest
    /// stable step that was taken).
    pub(crate) lambda_used: f64,
    /// The iteration count planned (differs from `iterations` with --time or --cutoff).
    pub(crate) iterations_planned: usize,
}

#[derive(Debug, Serialize)]
pub(crate) struct Seconds {
    /// Everything up to the built mesh: memory checks, `parse` and `build`.
    pub(crate) read: f64,
    /// Reading and decoding the file.
    pub(crate) parse: f64,
    /// Building and validating the half-edge connectivity.
    pub(crate) build: f64,
    pub(crate) weights: f64,
    pub(crate) updates: f64,
    pub(crate) write: f64,
}

#[derive(Debug, Serialize)]
pub(crate) struct Step {
    pub(crate) iteration: usize,
    pub(crate) max_displacement: f64,
    pub(crate) mean_displacement: f64,
    pub(crate) stuck_vertices: usize,
}

/// The reading time of a run and its two parts, in seconds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ReadSeconds {
    pub(crate) total: f64,
    pub(crate) parse: f64,
    pub(crate) build: f64,
}

pub(crate) fn build_report<'a>(
    args: &'a SmoothArgs,
    data: &MeshData,
    r: &SmoothReport,
    read: ReadSeconds,
    write: f64,
    notes: &[String],
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
            summation: args.summation,
            normalize: args.normalize(),
            vertex_area: args.vertex_area(),
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
        scattered_sweeps: r.scattered_sweeps,
        notes: notes.to_vec(),
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
pub(crate) fn method_label(method: &Method, preserve_volume: bool) -> String {
    let mut label = match *method {
        Method::Taubin { mu } => format!("taubin (mu {})", number(mu)),
        Method::Hc { alpha, beta } => format!("hc (alpha {alpha}, beta {beta})"),
        Method::Implicit { .. } => "implicit".to_string(),
        _ => "explicit".to_string(),
    };
    if preserve_volume {
        label.push_str(" + volume");
    }
    label
}
