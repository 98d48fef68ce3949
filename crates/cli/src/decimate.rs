//! `beltrami decimate`: quadric-error decimation to a target vertex count.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::{
    BlockedBy, DecimateError, DecimateOptions, DecimateReport, DecimateStop, Placement,
    decimate_with_progress,
};
use serde::Serialize;

use crate::edit_report::{EditOutputArgs, QualityChange};
use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load};
use crate::output::{notes_for_output, refuse_height_map_output};
use crate::text::{exact, number};

/// Arguments of `beltrami decimate`.
#[derive(Debug, clap::Args)]
pub(crate) struct DecimateArgs {
    /// The triangle mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The decimated mesh (.ply, .stl, .obj or .off by extension).
    output: PathBuf,
    /// Keep this many vertices (give this or --ratio).
    #[arg(long, allow_hyphen_values = true, value_name = "N")]
    vertices: Option<usize>,
    /// Keep this fraction of the vertices, in (0, 1] (give this or --vertices).
    #[arg(long, allow_hyphen_values = true, value_name = "R")]
    ratio: Option<f64>,
    /// Refuse a collapse whose quadric error, as a distance in the mesh's unit (the
    /// area-weighted RMS distance of the new position to the planes of the merged
    /// triangles), exceeds this.
    #[arg(long, allow_hyphen_values = true, value_name = "E")]
    max_error: Option<f64>,
    /// Refuse a collapse that turns a triangle's normal by more than this, in degrees
    /// (0 to 180), from any input triangle merged into it. Flips are always refused.
    #[arg(long, allow_hyphen_values = true, value_name = "DEG")]
    max_normal_deviation: Option<f64>,
    /// Never remove a boundary vertex (the boundary stays bit for bit).
    #[arg(long)]
    keep_boundary: bool,
    /// Where the kept vertex of a collapse goes: the quadric's minimiser (optimal), or
    /// its own position (endpoint, OpenMesh's choice: the output's vertices are input
    /// vertices, bit for bit).
    #[arg(long, value_enum, default_value_t = PlacementArg::Optimal)]
    placement: PlacementArg,
    /// The same as --placement optimal, the default (kept for scripts written when
    /// endpoint was the default).
    #[arg(long, hide = true, conflicts_with = "placement")]
    optimal: bool,
    /// Make collapses that create a triangle of shape quality below Q cost more (quality
    /// 4·area / (√3·longest edge²): 1 for an equilateral triangle, about 0.3 for a 15°
    /// needle), so that well-shaped collapses go first; 0 turns the penalty off. It
    /// orders collapses and never refuses one. In [0, 1].
    #[arg(
        long,
        value_name = "Q",
        default_value_t = 0.4,
        allow_hyphen_values = true
    )]
    quality_threshold: f64,
    /// How each input triangle's plane counts in the vertex quadrics: by its area
    /// (Garland and Heckbert's and OpenMesh's choice) or once (uniform, MeshLib's).
    #[arg(long, value_enum, default_value_t = PlaneWeightsArg::Area)]
    plane_weights: PlaneWeightsArg,
    /// The weight of a pull of each vertex towards its input position, relative to one
    /// triangle plane (MeshLib uses 0.001); it makes the optimal position well defined
    /// in flat regions. At least 0.
    #[arg(
        long,
        value_name = "W",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    stabilizer: f64,
    /// After the collapses, flip edges towards valence 6 (4 on the boundary) where a flip
    /// moves the surface by at most F times the largest collapse error, turns no triangle
    /// over and leaves no triangle below shape quality 0.4 unless the two it replaces
    /// were worse; 0 turns the flips off. At least 0 (default 0.2). No flips with
    /// --max-distance or --max-normal-deviation, so a tolerance above 0 given with
    /// either is refused.
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    flip_tolerance: Option<f64>,
    /// Rounds of the final fit to the input: after the collapses and flips, the vertices
    /// move (mostly along the normal) to bring the output surface closer to the input's
    /// triangles, keeping every triangle's orientation and shape (quality 0.3, or no
    /// worse); 0 turns it off (default 2, at most 100). No fit with --placement endpoint,
    /// --max-distance or --max-normal-deviation, so a count above 0 given with any of
    /// them is refused; none either when nothing was collapsed (the report then says 0
    /// rounds).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    fit_rounds: Option<usize>,
    /// OpenMesh's plain quadric decimation (DecimaterT with ModQuadricT): endpoint
    /// placement, no shape penalty, area-weighted planes, no stabilizer, no flips and no
    /// fit.
    #[arg(long, conflicts_with_all = ["placement", "optimal", "quality_threshold", "plane_weights", "stabilizer", "flip_tolerance", "fit_rounds"])]
    openmesh: bool,
    /// Refuse a collapse that makes a triangle of a larger aspect ratio (1 for an
    /// equilateral triangle; at least 1) unless it improves on the triangles it replaces.
    #[arg(long, allow_hyphen_values = true, value_name = "A")]
    max_aspect_ratio: Option<f64>,
    /// Refuse a collapse that leaves an input vertex farther than this (in the mesh's
    /// unit) from the output surface.
    #[arg(long, allow_hyphen_values = true, value_name = "D")]
    max_distance: Option<f64>,
    /// Skip measuring the Hausdorff distance between the result and the input (it is
    /// only reported, never used by the decimation, and can take about as long as the
    /// decimation itself).
    #[arg(long)]
    no_distance: bool,
    #[command(flatten)]
    outputs: EditOutputArgs,
    #[command(flatten)]
    read: ReadArgs,
}

/// `--placement`.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum PlacementArg {
    /// The quadric's minimiser.
    Optimal,
    /// The kept vertex's own position.
    Endpoint,
}

/// `--plane-weights`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum PlaneWeightsArg {
    /// Each plane weighted by its triangle's area.
    Area,
    /// Each plane weighted 1.
    Uniform,
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
    /// The shape-quality threshold of the penalty (0: none).
    quality_threshold: f64,
    /// `"area"` or `"uniform"`: how the triangle planes are weighted.
    plane_weights: &'static str,
    /// The weight of the pull towards the input positions (0: none).
    stabilizer: f64,
    /// The valence flips' tolerance, a fraction of the largest collapse error (0: none).
    flip_tolerance: f64,
    /// Edges flipped towards valence 6 after the collapses.
    flips: usize,
    /// Rounds of the final fit to the input done (0: none).
    fit_rounds: usize,
    /// The area-weighted RMS distance of the input's face centroids, along their
    /// normals, to the output before and after the fit (null without a fit).
    fit_rms_before: Option<f64>,
    fit_rms_after: Option<f64>,
    /// The largest quadric error of a collapse done, as a distance in the mesh's unit.
    max_quadric_error: f64,
    /// The symmetric Hausdorff distance output <-> input, in the mesh's unit (null
    /// with `--no-distance`).
    hausdorff: Option<f64>,
    hausdorff_to_input: Option<f64>,
    hausdorff_from_input: Option<f64>,
    /// The decimation alone (garbage collection included; reading, writing and the
    /// measurements excluded).
    seconds: f64,
    /// Measuring the Hausdorff distance (null with `--no-distance`).
    seconds_measure: Option<f64>,
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
            return usage(format!("--ratio must be in (0, 1], got {}", exact(r)));
        }
        (None, Some(r)) => options.ratio(r),
    };
    if let Some(e) = args.max_error {
        if !(e >= 0.0 && e.is_finite()) {
            return usage(format!(
                "--max-error must be a finite number >= 0, got {}",
                exact(e)
            ));
        }
        options = options.max_error(e);
    }
    if let Some(d) = args.max_normal_deviation {
        if !(0.0..=180.0).contains(&d) {
            return usage(format!(
                "--max-normal-deviation must be between 0 and 180 degrees, got {}",
                exact(d)
            ));
        }
        options = options.max_normal_deviation(d.to_radians());
    }
    if let Some(a) = args.max_aspect_ratio {
        if !(a >= 1.0 && a.is_finite()) {
            return usage(format!(
                "--max-aspect-ratio must be a finite number >= 1, got {}",
                exact(a)
            ));
        }
        options = options.max_aspect_ratio(a);
    }
    if let Some(d) = args.max_distance {
        if !(d >= 0.0 && d.is_finite()) {
            return usage(format!(
                "--max-distance must be a finite number >= 0, got {}",
                exact(d)
            ));
        }
        options = options.max_distance(d);
    }
    if !(0.0..=1.0).contains(&args.quality_threshold) {
        return usage(format!(
            "--quality-threshold must be in [0, 1], got {}",
            exact(args.quality_threshold)
        ));
    }
    if !(args.stabilizer >= 0.0 && args.stabilizer.is_finite()) {
        return usage(format!(
            "--stabilizer must be a finite number >= 0, got {}",
            exact(args.stabilizer)
        ));
    }
    let flip_tolerance = args
        .flip_tolerance
        .unwrap_or(DecimateOptions::default().flip_tolerance);
    if !(flip_tolerance >= 0.0 && flip_tolerance.is_finite()) {
        return usage(format!(
            "--flip-tolerance must be a finite number >= 0, got {}",
            exact(flip_tolerance)
        ));
    }
    let fit_rounds = args
        .fit_rounds
        .unwrap_or(beltrami_algorithms::DEFAULT_FIT_ROUNDS);
    if fit_rounds > beltrami_algorithms::MAX_FIT_ROUNDS {
        return usage(format!(
            "--fit-rounds must be at most {} (the distance stops falling after a few rounds), got {fit_rounds}",
            beltrami_algorithms::MAX_FIT_ROUNDS
        ));
    }
    // Options given explicitly that the run could not honour are refused, not dropped
    // (`--openmesh` excludes both in the arguments already).
    let placement = match args.placement {
        PlacementArg::Optimal => Placement::Optimal,
        PlacementArg::Endpoint => Placement::Endpoint,
    };
    let planned = options.placement(placement);
    let name = |blocker| match blocker {
        BlockedBy::EndpointPlacement => "--placement endpoint",
        BlockedBy::MaxDistance => "--max-distance",
        BlockedBy::MaxNormalDeviation => "--max-normal-deviation",
        _ => "the other options",
    };
    if args.fit_rounds.is_some_and(|n| n > 0)
        && let Some(blocker) = planned.fit_blocked_by()
    {
        return usage(format!(
            "--fit-rounds cannot be used with {}, with which no fit is made (leave --fit-rounds out or give 0)",
            name(blocker)
        ));
    }
    if args.flip_tolerance.is_some_and(|f| f > 0.0)
        && let Some(blocker) = planned.flips_blocked_by()
    {
        return usage(format!(
            "--flip-tolerance cannot be used with {}, with which no flips are made (leave --flip-tolerance out or give 0)",
            name(blocker)
        ));
    }
    options = if args.openmesh {
        options
            .placement(Placement::Endpoint)
            .quality_threshold(0.0)
            .flip_tolerance(0.0)
            .fit_rounds(0)
    } else {
        options
            .placement(placement)
            .quality_threshold(args.quality_threshold)
            .area_weighted(args.plane_weights == PlaneWeightsArg::Area)
            .stabilizer(args.stabilizer)
            .flip_tolerance(flip_tolerance)
            .fit_rounds(fit_rounds)
    };
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
    crate::repair::refuse_stl_after_split(&args.output, loaded.repair.as_ref())?;
    let input_error = |e: DecimateError| CliError::Input {
        path: args.input.clone(),
        message: match e {
            DecimateError::NotTriangle { face, len } => not_triangles("decimate", face, len),
            e => e.to_string(),
        },
    };
    let start = std::time::Instant::now();
    // A bar on a terminal for meshes whose decimation takes a noticeable time (about a
    // second from 500 000 faces).
    // Its length is the planned collapses, which the first call gives.
    let long = loaded.mesh.n_faces() >= 500_000;
    let result = crate::progress::with_bar(0, "collapses", long, |show| {
        decimate_with_progress(
            &loaded.mesh,
            &loaded.positions,
            &options.measure_distance(false),
            show,
        )
    });
    let (mesh, positions, mut report) = result.map_err(input_error)?;
    let seconds = start.elapsed().as_secs_f64();
    let seconds_measure = if args.no_distance {
        None
    } else {
        let start = std::time::Instant::now();
        report
            .measure_distance((&loaded.mesh, &loaded.positions), (&mesh, &positions))
            .map_err(input_error)?;
        Some(start.elapsed().as_secs_f64())
    };
    let measured = |x: f64| report.distance_measured.then_some(x);
    // No fit ran: null, not a 0 that reads as a perfect fit.
    let fitted = |x: f64| (report.fit_rounds > 0).then_some(x);
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
        placement: match (args.openmesh, args.placement) {
            (false, PlacementArg::Optimal) => "optimal",
            _ => "endpoint",
        },
        quality_threshold: if args.openmesh {
            0.0
        } else {
            args.quality_threshold
        },
        plane_weights: match args.plane_weights {
            PlaneWeightsArg::Uniform if !args.openmesh => "uniform",
            _ => "area",
        },
        stabilizer: if args.openmesh { 0.0 } else { args.stabilizer },
        flip_tolerance: options.flip_tolerance,
        flips: report.flips,
        fit_rounds: report.fit_rounds,
        fit_rms_before: fitted(report.fit_rms_before),
        fit_rms_after: fitted(report.fit_rms_after),
        max_quadric_error: report.max_quadric_error,
        hausdorff: measured(report.hausdorff),
        hausdorff_to_input: measured(report.hausdorff_to_input),
        hausdorff_from_input: measured(report.hausdorff_from_input),
        seconds,
        seconds_measure,
    };
    let mut notes = notes_for_output(&args.output, &loaded.repair_lines, &mesh);
    let early = notes.len();
    // Printed after the summary line, and in the report's `notes` too.
    let isolated = loaded.mesh.n_isolated_vertices();
    let isolated_note = (isolated > 0).then(|| {
        format!(
            "note: the input has {} in no face; {it} kept as {it} and counted in the vertex counts and the target (--repair removes them)",
            crate::text::counted(isolated, "isolated vertex", "isolated vertices"),
            it = crate::text::plural(isolated, "it is", "they are"),
        )
    });
    notes.extend(isolated_note.iter().cloned());
    if args.outputs.write(
        &args.output,
        &mesh,
        positions,
        &summary,
        &quality,
        &notes,
        out,
    )? {
        return Ok(());
    }
    for line in &notes[..early] {
        writeln!(out, "{line}")?;
    }
    let target = if report.target_vertices > report.vertices_before {
        format!(
            "target {}: the input already has fewer vertices, nothing to collapse",
            report.target_vertices
        )
    } else if report.target_reached {
        format!("target {} reached", report.target_vertices)
    } else {
        format!(
            "target {} not reached: {}",
            report.target_vertices,
            why_not(&report)
        )
    };
    let distance = if report.distance_measured {
        format!(
            "; Hausdorff distance to the input {}",
            number(report.hausdorff)
        )
    } else {
        String::new()
    };
    let fit = if report.fit_rounds > 0 {
        format!(
            "; fitted to the input in {} rounds (RMS plane distance {} -> {})",
            report.fit_rounds,
            number(report.fit_rms_before),
            number(report.fit_rms_after)
        )
    } else {
        String::new()
    };
    writeln!(
        out,
        "decimated {} -> {}: {} -> {} vertices ({target}){fit}{distance}",
        args.input.display(),
        args.output.display(),
        report.vertices_before,
        report.vertices_after,
    )?;
    if let Some(note) = &isolated_note {
        writeln!(out, "{note}")?;
    }
    quality.write_table(out)?;
    Ok(())
}
