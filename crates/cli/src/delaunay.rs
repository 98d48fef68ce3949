//! `beltrami delaunay`: edge flips towards a Delaunay mesh on the same vertices, so that
//! no cotangent weight is negative.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::{DelaunayError, DelaunayOptions, delaunay_flip};
use serde::Serialize;

use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load};
use crate::output::{Outputs, notes_for_output, write_result};
use crate::text::{counted, number};

/// Arguments of `beltrami delaunay`.
#[derive(Debug, clap::Args)]
pub(crate) struct DelaunayArgs {
    /// The triangle mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The flipped mesh, the same vertices in the same order (.ply, .stl, .obj or .off by
    /// extension).
    output: PathBuf,
    /// Leave an edge alone when its two triangles meet at more than this angle, in
    /// degrees (0 to 180): keeps feature edges and bounds how much a flip can change a
    /// curved surface. Default: no bound (on a curved scan, try 1 to 5).
    #[arg(long, allow_hyphen_values = true, value_name = "DEG")]
    max_dihedral: Option<f64>,
    /// Stop after this many flips (default: ten per edge; a planar mesh never needs as
    /// many, a curved one could otherwise cycle).
    #[arg(long, allow_hyphen_values = true, value_name = "N")]
    max_flips: Option<usize>,
    /// Print a JSON summary instead of the sentence.
    #[arg(long)]
    json: bool,
    /// Write PLY (and STL) as ascii text instead of binary.
    #[arg(long)]
    ascii: bool,
    /// Replace OUTPUT even when it is the input (an edit in place) or write-protected.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// The JSON of `delaunay --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    vertices: usize,
    faces: usize,
    flips: usize,
    negative_before: usize,
    negative_after: usize,
    kept_by_dihedral: usize,
    kept_by_topology: usize,
    kept_by_flip_limit: usize,
    hit_flip_limit: bool,
    /// The distance between the input and output surfaces, in the mesh's unit.
    max_deviation: f64,
    max_dihedral_degrees: Option<f64>,
    /// What `--repair` changed (and the reading's other notes), one line each.
    notes: Vec<String>,
    seconds: f64,
}

/// Runs `beltrami delaunay`.
pub(crate) fn run(args: &DelaunayArgs, out: &mut impl Write) -> Result<(), CliError> {
    if let Some(d) = args.max_dihedral
        && !(0.0..=180.0).contains(&d)
    {
        return Err(CliError::Usage(format!(
            "--max-dihedral must be between 0 and 180 degrees, got {}",
            number(d)
        )));
    }
    crate::output::refuse_height_map_output(
        &args.output,
        "delaunay",
        "the flips change the triangles, and a height map keeps only the grid's own",
    )?;
    let mut outputs = Outputs::new();
    outputs.add_mesh(&args.output, "OUTPUT");
    outputs.check(&[&args.input], args.force)?;
    let loaded = load(&args.input, &args.read)?;
    crate::repair::refuse_stl_after_split(&args.output, loaded.repair.as_ref())?;
    loaded.require_faces(&args.input, "delaunay")?;
    let mut options = DelaunayOptions::default();
    if let Some(d) = args.max_dihedral {
        options = options.max_dihedral(d.to_radians());
    }
    if let Some(n) = args.max_flips {
        options = options.max_flips(n);
    }
    let start = std::time::Instant::now();
    let (mesh, positions, report) = delaunay_flip(&loaded.mesh, &loaded.positions, options)
        .map_err(|e| CliError::Input {
            path: args.input.clone(),
            message: match e {
                DelaunayError::NotTriangle { face, len } => not_triangles("delaunay", face, len),
                e => e.to_string(),
            },
        })?;
    let seconds = start.elapsed().as_secs_f64();
    let mut notes = notes_for_output(&args.output, &loaded.repair_lines, &mesh);
    // A flat triangle has no cotangent weight to make non-negative, and no flip here
    // removes it: say which command does.
    let flat = beltrami_halfedge::geometry::Geometry::new(&mesh, &positions).map_or(0, |g| {
        mesh.faces().filter(|&f| g.is_degenerate_face(f)).count()
    });
    if flat > 0 {
        notes.push(format!(
            "note: {} of zero area left (flat for {} size), whose cotangent weights are absent; `beltrami repair {} FIXED --flat-faces` removes flat triangles without moving the surface",
            counted(flat, "face", "faces"),
            if flat == 1 { "its" } else { "their" },
            args.output.display()
        ));
    }
    write_result(&args.output, &mesh, positions, args.ascii)?;

    if args.json {
        let summary = Summary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            vertices: mesh.n_vertices(),
            faces: mesh.n_faces(),
            flips: report.flips,
            negative_before: report.negative_before,
            negative_after: report.negative_after,
            kept_by_dihedral: report.kept_by_dihedral,
            kept_by_topology: report.kept_by_topology,
            kept_by_flip_limit: report.kept_by_flip_limit,
            hit_flip_limit: report.hit_flip_limit,
            max_deviation: report.max_deviation,
            max_dihedral_degrees: args.max_dihedral,
            notes,
            seconds,
        };
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
        return Ok(());
    }
    for line in &notes {
        writeln!(out, "{line}")?;
    }
    let mut kept = Vec::new();
    if report.kept_by_dihedral > 0 {
        kept.push(format!("{} by --max-dihedral", report.kept_by_dihedral));
    }
    if report.kept_by_topology > 0 {
        kept.push(format!(
            "{} not flippable (the flipped edge exists)",
            report.kept_by_topology
        ));
    }
    if report.kept_by_flip_limit > 0 {
        kept.push(format!(
            "{} left at the flip limit (--max-flips)",
            report.kept_by_flip_limit
        ));
    } else if report.hit_flip_limit {
        kept.push("the flip limit was reached".to_string());
    }
    let kept = if kept.is_empty() {
        String::new()
    } else {
        format!(" ({})", kept.join(", "))
    };
    writeln!(
        out,
        "flipped {} of {} -> {}: negative cotangent weights {} -> {}{kept}; surface moved by at most {}",
        counted(report.flips, "edge", "edges"),
        args.input.display(),
        args.output.display(),
        report.negative_before,
        report.negative_after,
        number(report.max_deviation),
    )?;
    Ok(())
}
