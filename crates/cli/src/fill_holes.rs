//! `beltrami fill-holes`: close the holes of a triangle mesh (Liepa 2003), leaving the
//! outer boundary of an open surface open unless `--all` is given.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::{
    FillError, FillOptions, FillReport, SkipReason, fill_holes_with_progress,
};
use serde::Serialize;

use crate::edit_report::{EditOutputArgs, QualityChange};
use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load};
use crate::output::{notes_for_output, refuse_height_map_output};
use crate::text::{counted, number};

/// Arguments of `beltrami fill-holes`.
#[derive(Debug, clap::Args)]
pub(crate) struct FillHolesArgs {
    /// The triangle mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The filled mesh (.ply, .stl, .obj or .off by extension): the input's vertices
    /// in the same order and bit for bit, the new vertices after them.
    output: PathBuf,
    /// Leave loops of more edges open (at least 3; default 500). The triangulation
    /// costs O(n^3) in the number of edges of a loop.
    #[arg(long, allow_hyphen_values = true, value_name = "N")]
    max_loop_edges: Option<usize>,
    /// Fill every loop, each component's one of the largest perimeter too (a closed
    /// part). Without it, that loop is taken for the outer boundary of an open surface (a
    /// scan of an open part) and left open, one per connected component.
    #[arg(long)]
    all: bool,
    /// Do not refine the patches: only the triangulation of each hole, no new vertex
    /// (and so nothing to fair).
    #[arg(long)]
    no_refine: bool,
    /// Do not fair the patches: the new vertices stay where the refinement put them,
    /// flat between the rim vertices.
    #[arg(long)]
    no_fair: bool,
    #[command(flatten)]
    outputs: EditOutputArgs,
    #[command(flatten)]
    read: ReadArgs,
}

/// One filled hole in the JSON summary.
#[derive(Debug, Serialize)]
struct Hole {
    boundary_edges: usize,
    /// In the mesh's unit.
    perimeter: f64,
    faces_added: usize,
    vertices_added: usize,
    /// In the mesh's unit squared.
    area: f64,
    /// The fairing order used (2 thin plate, 1 membrane), null when not faired.
    faired_order: Option<u8>,
}

/// One loop left open in the JSON summary.
#[derive(Debug, Serialize)]
struct Skipped {
    boundary_edges: usize,
    perimeter: f64,
    /// `outer_boundary`, `too_large`, `non_manifold_vertex` or
    /// `no_manifold_triangulation`.
    reason: &'static str,
}

/// The JSON of `fill-holes --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    vertices: usize,
    faces: usize,
    loops: usize,
    filled: Vec<Hole>,
    skipped: Vec<Skipped>,
    faces_added: usize,
    vertices_added: usize,
    boundary_loops_left: usize,
    max_loop_edges: usize,
    seconds: f64,
}

fn reason_key(reason: SkipReason) -> &'static str {
    match reason {
        SkipReason::OuterBoundary => "outer_boundary",
        SkipReason::TooLarge => "too_large",
        SkipReason::NonManifoldVertex => "non_manifold_vertex",
        _ => "no_manifold_triangulation",
    }
}

/// Runs `beltrami fill-holes`.
pub(crate) fn run(args: &FillHolesArgs, out: &mut impl Write) -> Result<(), CliError> {
    if let Some(n) = args.max_loop_edges
        && n < 3
    {
        return Err(CliError::Usage(format!(
            "--max-loop-edges must be at least 3 (a triangle), got {n}"
        )));
    }
    refuse_height_map_output(
        &args.output,
        "fill-holes",
        "the filled patches add vertices off the grid",
    )?;
    args.outputs.check(&args.output, &args.input)?;
    let loaded = load(&args.input, &args.read)?;
    crate::repair::refuse_stl_after_split(&args.output, loaded.repair.as_ref())?;
    loaded.require_faces(&args.input, "fill-holes")?;
    let mut options = FillOptions::default()
        .fill_all(args.all)
        .refine(!args.no_refine)
        .fair(!args.no_fair);
    if let Some(n) = args.max_loop_edges {
        options = options.max_loop_edges(n);
    }
    let start = std::time::Instant::now();
    // A bar on a terminal for scans with many holes (each loop is a step; a loop of a
    // few edges takes well under a millisecond, one of hundreds up to a second).
    let loops = loaded.mesh.boundary_loops().count();
    let result = crate::progress::with_bar(loops, "boundary loops", loops >= 100, |show| {
        fill_holes_with_progress(&loaded.mesh, &loaded.positions, &options, show)
    });
    let (mesh, positions, report) = result.map_err(|e| CliError::Input {
        path: args.input.clone(),
        message: match e {
            FillError::NotTriangle { face, len } => not_triangles("fill-holes", face, len),
            e => e.to_string(),
        },
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let quality = QualityChange::measure(
        &args.input,
        "fill-holes",
        (&loaded.mesh, &loaded.positions),
        (&mesh, &positions),
    )?;
    let summary = summarise(args, &mesh, &report, options.max_loop_edges, seconds);
    let notes = notes_for_output(&args.output, &loaded.repair_lines, &mesh);
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
    for line in &notes {
        writeln!(out, "{line}")?;
    }
    let share = outer_share(&loaded.mesh, &loaded.positions, &report);
    let open = open_note(&report, options.max_loop_edges, share);
    let area: f64 = report.filled.iter().map(|h| h.area).sum();
    writeln!(
        out,
        "filled {} of {} -> {}: {} and {} added, patch area {}{open}",
        counted(report.filled.len(), "hole", "holes"),
        args.input.display(),
        args.output.display(),
        counted(report.faces_added, "face", "faces"),
        counted(report.vertices_added, "vertex", "vertices"),
        number(area),
    )?;
    quality.write_table(out)?;
    Ok(())
}

/// The JSON summary of a fill.
fn summarise(
    args: &FillHolesArgs,
    mesh: &beltrami_halfedge::HalfedgeMesh,
    report: &FillReport,
    max_loop_edges: usize,
    seconds: f64,
) -> Summary {
    Summary {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        vertices: mesh.n_vertices(),
        faces: mesh.n_faces(),
        loops: report.loops,
        filled: report
            .filled
            .iter()
            .map(|h| Hole {
                boundary_edges: h.boundary_edges,
                perimeter: h.perimeter,
                faces_added: h.faces_added,
                vertices_added: h.vertices_added,
                area: h.area,
                faired_order: h.faired_order,
            })
            .collect(),
        skipped: report
            .skipped
            .iter()
            .map(|s| Skipped {
                boundary_edges: s.boundary_edges,
                perimeter: s.perimeter,
                reason: reason_key(s.reason),
            })
            .collect(),
        faces_added: report.faces_added,
        vertices_added: report.vertices_added,
        boundary_loops_left: mesh.boundary_loops().count(),
        max_loop_edges,
        seconds,
    }
}

/// Below this share of its component's area, a loop left open as an outer boundary
/// looks like a hole of a closed part, and the summary says that `--all` fills it. The
/// rim of an open scan spans most of its surface (a hemisphere's: half), a hole cut into
/// a closed part a few per cent at most.
const CLOSED_PART_SHARE: f64 = 0.05;

/// The area each loop left open as an outer boundary spans (the length of its vector
/// area, `|Σ pᵢ × pᵢ₊₁| / 2`, the area of the flattest patch it can bound), as a share
/// of its connected component's surface area: the smallest of these shares, or `None`
/// when no loop was left open for that reason or a component has no area.
fn outer_share(
    mesh: &beltrami_halfedge::HalfedgeMesh,
    positions: &[glam::DVec3],
    report: &FillReport,
) -> Option<f64> {
    let outer: Vec<_> = report
        .skipped
        .iter()
        .filter(|s| s.reason == SkipReason::OuterBoundary)
        .map(|s| s.halfedge)
        .collect();
    if outer.is_empty() {
        return None;
    }
    // A share does not depend on the unit: a mesh far from unit size is measured at a
    // power of two times its size (exact), where the squares in the areas neither
    // underflow nor overflow.
    let largest = positions
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0_f64, f64::max);
    let unit: Vec<glam::DVec3>;
    let positions = if largest.is_normal() && !(1e-12..=1e12).contains(&largest) {
        let k = -(largest.log2().floor() as i32);
        let factor = 2f64.powi(k.clamp(-1022, 1022));
        unit = positions.iter().map(|&p| p * factor).collect();
        &unit[..]
    } else {
        positions
    };
    let components = mesh.connected_components();
    let geometry = beltrami_halfedge::geometry::Geometry::new(mesh, positions).ok()?;
    let mut area = vec![0.0; components.count()];
    for f in mesh.faces() {
        area[components.face_component[f] as usize] += geometry.face_area(f);
    }
    let point = |h: &beltrami_halfedge::HalfedgeId| positions[mesh.to_vertex(*h).index()];
    mesh.boundary_loops()
        .filter(|l| l.first().is_some_and(|h| outer.contains(h)))
        .map(|boundary| {
            let spanned = boundary
                .iter()
                .zip(boundary.iter().cycle().skip(1))
                .map(|(a, b)| point(a).cross(point(b)))
                .sum::<glam::DVec3>()
                .length()
                / 2.0;
            let whole = area[components.vertex_component[mesh.to_vertex(boundary[0])] as usize];
            (whole > 0.0).then(|| spanned / whole)
        })
        .try_fold(f64::INFINITY, |least, share| share.map(|s| least.min(s)))
}

/// `; left N loops open: …`: the loops left open, by reason (empty when none).
/// `outer_share` is the smallest share of its component's area that a loop left open as
/// an outer boundary spans ([`outer_share`]).
fn open_note(report: &FillReport, max_loop_edges: usize, outer_share: Option<f64>) -> String {
    let count = |reason: SkipReason| report.skipped.iter().filter(|s| s.reason == reason).count();
    let mut open = Vec::new();
    let outer = count(SkipReason::OuterBoundary);
    if outer == 1 {
        open.push(match outer_share {
            Some(share) if share < CLOSED_PART_SHARE => format!(
                "the largest loop, taken for the outer boundary of an open surface, though it spans only {:.2}% of the surface's area as a hole in a closed part does (--all fills it)",
                100.0 * share
            ),
            _ => "the outer boundary (largest perimeter; --all fills it)".to_string(),
        });
    } else if outer > 1 {
        open.push(match outer_share {
            Some(share) if share < CLOSED_PART_SHARE => format!(
                "the largest loop of each of {outer} components, taken for their outer boundaries, though one spans only {:.2}% of its component's area as a hole in a closed part does (--all fills them)",
                100.0 * share
            ),
            _ => format!(
                "the outer boundaries of {outer} components (each one's largest perimeter; --all fills them)"
            ),
        });
    }
    let large = count(SkipReason::TooLarge);
    if large > 0 {
        open.push(format!(
            "{} with more than {} edges (--max-loop-edges)",
            large, max_loop_edges
        ));
    }
    let pinched = count(SkipReason::NonManifoldVertex);
    if pinched > 0 {
        open.push(format!("{pinched} through a vertex on two loops"));
    }
    let stuck = report.skipped.len() - count(SkipReason::OuterBoundary) - large - pinched;
    if stuck > 0 {
        open.push(format!(
            "{stuck} with no triangulation that keeps the mesh manifold"
        ));
    }
    if open.is_empty() {
        String::new()
    } else {
        format!(
            "; left {} open: {}",
            counted(report.skipped.len(), "loop", "loops"),
            open.join(", ")
        )
    }
}
