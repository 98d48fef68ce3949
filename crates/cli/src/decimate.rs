//! `beltrami decimate`: quadric-error decimation to a target vertex count.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::{
    DecimateError, DecimateOptions, DecimateReport, DecimateStop, Placement, decimate,
};
use serde::Serialize;

use crate::edit_report::{EditOutputArgs, QualityChange};
use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load};
use crate::output::refuse_height_map_output;
use crate::text::number;

/// Arguments of `beltrami decimate`.
#[derive(Debug, clap::Args)]
pub(crate) struct DecimateArgs {
    /// The triangle mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The decimated mesh (.ply, .stl, .obj or .off by extension).
    output: PathBuf,
    /// Keep this many vertices (give this or --ratio).
    #[arg(long, value_name = "N")]
    vertices: Option<usize>,
    /// Keep this fraction of the vertices, in (0, 1] (give this or --vertices).
    #[arg(long, value_name = "R")]
    ratio: Option<f64>,
    /// Refuse a collapse whose quadric error, as a distance in the mesh's unit (the
    /// area-weighted RMS distance of the new position to the planes of the merged
    /// triangles), exceeds this.
    #[arg(long, value_name = "E")]
    max_error: Option<f64>,
    /// Refuse a collapse that turns a triangle's normal by more than this, in degrees
    /// (0 to 180), from any input triangle merged into it. Flips are always refused.
    #[arg(long, value_name = "DEG")]
    max_normal_deviation: Option<f64>,
    /// Never remove a boundary vertex (the boundary stays bit for bit).
    #[arg(long)]
    keep_boundary: bool,
    /// Move the kept vertex to the quadric's minimiser instead of keeping it in place.
    #[arg(long)]
    optimal: bool,
    /// Refuse a collapse that makes a triangle of a larger aspect ratio (1 for an
    /// equilateral triangle; at least 1) unless it improves on the triangles it replaces.
    #[arg(long, value_name = "A")]
    max_aspect_ratio: Option<f64>,
    /// Refuse a collapse that leaves an input vertex farther than this (in the mesh's
    /// unit) from the output surface.
    #[arg(long, value_name = "D")]
    max_distance: Option<f64>,
    #[command(flatten)]
    outputs: EditOutputArgs,
    #[command(flatten)]
    read: ReadArgs,
}

/// Refusal counts of `decimate --json`.
#[derive(Debug, Serialize)]
struct Refused {
    topology: usize,
    boundary: usize,
    max_error: usize,
    normal_flip: usize,
    max_normal_deviation: usize,
    max_aspect_ratio: usize,
    max_distance: usize,
}

/// The JSON of `decimate --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    vertices_before: usize,
    vertices_after: usize,
    faces_before: usize,
    faces_after: usize,
    target_vertices: usize,
    target_reached: bool,
    /// `"target reached"` or `"no collapse left"`.
    stop: &'static str,
    collapses: usize,
    refused: Refused,
    placement: &'static str,
    /// The largest quadric error of a collapse done, as a distance in the mesh's unit.
    max_quadric_error: f64,
    /// The symmetric Hausdorff distance output <-> input, in the mesh's unit.
    hausdorff: f64,
    hausdorff_to_input: f64,
    hausdorff_from_input: f64,
    seconds: f64,
}

/// The options, or a usage error naming the bad one.
fn options(args: &DecimateArgs) -> Result<DecimateOptions, CliError> {
    let usage = |m: String| Err(CliError::Usage(m));
    let mut options = DecimateOptions::default();
    options = match (args.vertices, args.ratio) {
        (Some(_), Some(_)) | (None, None) => {
            return usage("give exactly one of --vertices N and --ratio R".into());
        }
        (Some(0), None) => return usage("--vertices must be at least 1".into()),
        (Some(n), None) => options.vertices(n),
        (None, Some(r)) if !(r > 0.0 && r <= 1.0) => {
            return usage(format!("--ratio must be in (0, 1], got {}", number(r)));
        }
        (None, Some(r)) => options.ratio(r),
    };
    if let Some(e) = args.max_error {
        if !(e >= 0.0 && e.is_finite()) {
            return usage(format!("--max-error must be >= 0, got {}", number(e)));
        }
        options = options.max_error(e);
    }
    if let Some(d) = args.max_normal_deviation {
        if !(0.0..=180.0).contains(&d) {
            return usage(format!(
                "--max-normal-deviation must be between 0 and 180 degrees, got {}",
                number(d)
            ));
        }
        options = options.max_normal_deviation(d.to_radians());
    }
    if let Some(a) = args.max_aspect_ratio {
        if !(a >= 1.0 && a.is_finite()) {
            return usage(format!(
                "--max-aspect-ratio must be >= 1, got {}",
                number(a)
            ));
        }
        options = options.max_aspect_ratio(a);
    }
    if let Some(d) = args.max_distance {
        if !(d >= 0.0 && d.is_finite()) {
            return usage(format!("--max-distance must be >= 0, got {}", number(d)));
        }
        options = options.max_distance(d);
    }
    if args.optimal {
        options = options.placement(Placement::Optimal);
    }
    Ok(options.keep_boundary(args.keep_boundary))
}

/// Why the target was missed, in words: the checks that refused most.
fn why_not(report: &DecimateReport) -> String {
    let r = &report.refused;
    let mut reasons = [
        (r.topology, "the topology"),
        (r.boundary, "--keep-boundary"),
        (r.error, "--max-error"),
        (r.normal_flip, "triangles that would flip"),
        (r.normal_deviation, "--max-normal-deviation"),
        (r.aspect_ratio, "--max-aspect-ratio"),
        (r.distance, "--max-distance"),
    ];
    reasons.sort_by_key(|r| std::cmp::Reverse(r.0));
    let named: Vec<&str> = reasons
        .iter()
        .filter(|(n, _)| *n > 0)
        .take(2)
        .map(|(_, s)| *s)
        .collect();
    if named.is_empty() {
        "no collapse left".to_string()
    } else {
        format!(
            "no collapse left, refused mostly by {}",
            named.join(" and ")
        )
    }
}

/// Runs `beltrami decimate`.
pub(crate) fn run(args: &DecimateArgs, out: &mut impl Write) -> Result<(), CliError> {
    let options = options(args)?;
    refuse_height_map_output(
        &args.output,
        "decimate",
        "decimation leaves an irregular mesh",
    )?;
    args.outputs.check(&args.output, &args.input)?;
    let loaded = load(&args.input, &args.read)?;
    loaded.require_faces(&args.input, "decimate")?;
    let start = std::time::Instant::now();
    let (mesh, positions, report) =
        decimate(&loaded.mesh, &loaded.positions, &options).map_err(|e| CliError::Input {
            path: args.input.clone(),
            message: match e {
                DecimateError::NotTriangle { face, len } => not_triangles("decimate", face, len),
                e => e.to_string(),
            },
        })?;
    let seconds = start.elapsed().as_secs_f64();
    let quality = QualityChange::measure(
        &args.input,
        "decimate",
        (&loaded.mesh, &loaded.positions),
        (&mesh, &positions),
    )?;
    let r = &report.refused;
    let summary = Summary {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        vertices_before: report.vertices_before,
        vertices_after: report.vertices_after,
        faces_before: report.faces_before,
        faces_after: report.faces_after,
        target_vertices: report.target_vertices,
        target_reached: report.target_reached,
        stop: match report.stop {
            DecimateStop::TargetReached => "target reached",
            _ => "no collapse left",
        },
        collapses: report.collapses,
        refused: Refused {
            topology: r.topology,
            boundary: r.boundary,
            max_error: r.error,
            normal_flip: r.normal_flip,
            max_normal_deviation: r.normal_deviation,
            max_aspect_ratio: r.aspect_ratio,
            max_distance: r.distance,
        },
        placement: if args.optimal { "optimal" } else { "endpoint" },
        max_quadric_error: report.max_quadric_error,
        hausdorff: report.hausdorff,
        hausdorff_to_input: report.hausdorff_to_input,
        hausdorff_from_input: report.hausdorff_from_input,
        seconds,
    };
    if args
        .outputs
        .write(&args.output, &mesh, positions, &summary, &quality, out)?
    {
        return Ok(());
    }
    for line in &loaded.repair_lines {
        writeln!(out, "{line}")?;
    }
    let target = if report.target_reached {
        format!("target {} reached", report.target_vertices)
    } else {
        format!(
            "target {} not reached: {}",
            report.target_vertices,
            why_not(&report)
        )
    };
    writeln!(
        out,
        "decimated {} -> {}: {} -> {} vertices ({target}); Hausdorff distance to the input {}",
        args.input.display(),
        args.output.display(),
        report.vertices_before,
        report.vertices_after,
        number(report.hausdorff),
    )?;
    quality.write_table(out)?;
    Ok(())
}
