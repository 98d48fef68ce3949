//! `beltrami remesh`: isotropic remeshing towards a target edge length, keeping the
//! boundary and sharp features.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::{AdaptiveSizing, RemeshError, RemeshOptions, remesh_with_feature_edges};
use serde::Serialize;

use crate::edit_report::{EditOutputArgs, QualityChange};
use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load};
use crate::output::{notes_for_output, refuse_height_map_output};
use crate::text::{counted, exact, number};

/// Arguments of `beltrami remesh`.
#[derive(Debug, clap::Args)]
pub(crate) struct RemeshArgs {
    /// The triangle mesh (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The remeshed mesh (.ply, .stl, .obj or .off by extension).
    output: PathBuf,
    /// The target edge length, in the mesh's unit. Default (without this and without
    /// --edge-length-relative): the input's mean edge length.
    #[arg(
        long,
        allow_hyphen_values = true,
        value_name = "L",
        conflicts_with = "edge_length_relative"
    )]
    edge_length: Option<f64>,
    /// The target edge length as a multiple of the input's mean edge length (default 1:
    /// the input's mean edge length).
    #[arg(long, allow_hyphen_values = true, value_name = "R")]
    edge_length_relative: Option<f64>,
    /// Curvature-adaptive edge lengths (Dunyach et al. 2013): short edges where the
    /// surface is curved, long where it is flat, each edge deviating by about --error
    /// from the surface, within [--min-edge, --max-edge]. Values not given are derived
    /// from the input's mean edge length L: --min-edge L/4, --max-edge 4L, and --error
    /// such that vertices of the median curvature keep edges of length L.
    #[arg(long, conflicts_with_all = ["edge_length", "edge_length_relative"])]
    adaptive: bool,
    /// With --adaptive: the smallest edge length, in the mesh's unit (default: a quarter
    /// of the input's mean edge length).
    #[arg(
        long,
        allow_hyphen_values = true,
        value_name = "A",
        requires = "adaptive"
    )]
    min_edge: Option<f64>,
    /// With --adaptive: the largest edge length, in the mesh's unit (default: four times
    /// the input's mean edge length).
    #[arg(
        long,
        allow_hyphen_values = true,
        value_name = "B",
        requires = "adaptive"
    )]
    max_edge: Option<f64>,
    /// With --adaptive: the allowed distance between an edge and the surface, in the
    /// mesh's unit (default: that of a chord as long as the input's mean edge on a circle
    /// of the input's median curvature).
    #[arg(
        long,
        allow_hyphen_values = true,
        value_name = "E",
        requires = "adaptive"
    )]
    error: Option<f64>,
    /// The number of split-collapse-flip-relax iterations (at most 1000; the counts
    /// settle within 10 to 20).
    #[arg(
        long,
        allow_hyphen_values = true,
        value_name = "N",
        default_value_t = 10
    )]
    iterations: usize,
    /// Keep edges whose two triangles meet at more than this angle, in degrees (0 to
    /// 180), as feature curves; corners of features stay. Default: no feature edges (the
    /// boundary is kept in any case).
    #[arg(long, allow_hyphen_values = true, value_name = "DEG")]
    features: Option<f64>,
    /// Also keep these edges as feature curves, for creases no angle finds (a datum
    /// line, the seam between two materials, a gentle fillet's border): a text file with
    /// one edge per line, the 0-based indices of its two vertices in INPUT as read; `#`
    /// starts a comment. With --repair, refused when the repair renumbers the vertices.
    /// Edges that are not sharp stay smooth: the surface runs across them as without
    /// them.
    #[arg(long, value_name = "FILE")]
    feature_edges: Option<PathBuf>,
    /// Do not project the vertices back onto the input surface (they then move only
    /// within their tangent planes, and a curved surface shrinks slightly).
    #[arg(long)]
    no_projection: bool,
    /// Project onto the input's flat triangles, not onto the smooth surface through them
    /// (Phong tessellation from the input's vertex normals, flat between feature edges):
    /// every vertex then lies on the input's triangles, and on a curved surface up to a
    /// triangle's sagitta below the surface they approximate.
    #[arg(long, conflicts_with = "no_projection")]
    faceted: bool,
    #[command(flatten)]
    outputs: EditOutputArgs,
    #[command(flatten)]
    read: ReadArgs,
}

/// The JSON of `remesh --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    /// The target edge length used, in the mesh's unit (with --adaptive, the mean of
    /// the sizing field over the input's vertices).
    target_edge_length: f64,
    adaptive: bool,
    /// With --adaptive: the smallest edge length used (given or derived).
    min_edge: Option<f64>,
    /// With --adaptive: the largest edge length used.
    max_edge: Option<f64>,
    /// With --adaptive: the approximation error used.
    approx_error: Option<f64>,
    iterations: usize,
    splits: usize,
    collapses: usize,
    flips: usize,
    vertices_before: usize,
    faces_before: usize,
    vertices: usize,
    faces: usize,
    mean_edge_length_before: f64,
    edge_length_cv_before: f64,
    mean_edge_length: f64,
    edge_length_cv: f64,
    feature_edges: usize,
    /// Interior edges given by --feature-edges (0 without it).
    given_feature_edges: usize,
    /// Feature edges whose triangles fold back onto each other (above 150°).
    fold_edges: usize,
    boundary_edges: usize,
    corners: usize,
    /// The largest distance from an output vertex to the input's triangles.
    hausdorff: f64,
    /// The largest distance from an input vertex to the output's triangles (sharp edges
    /// rounded off show here).
    hausdorff_from_input: f64,
    /// Degenerate triangles (flat for their size, or shrunk to a point) of the input.
    degenerate_faces_before: usize,
    /// Degenerate triangles of the output.
    degenerate_faces: usize,
    feature_angle_degrees: Option<f64>,
    projection: bool,
    /// Whether the vertices were projected onto the smooth surface through the input's
    /// triangles (not with `--faceted` or `--no-projection`).
    smooth_projection: bool,
    seconds: f64,
}

/// Checks the options that do not need the input.
fn options(args: &RemeshArgs) -> Result<RemeshOptions, CliError> {
    let positive = |name: &str, x: f64| {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(CliError::Usage(format!(
                "{name} must be a finite number > 0, got {}",
                exact(x)
            )))
        }
    };
    let mut options = RemeshOptions::default()
        .iterations(args.iterations)
        .projection(!args.no_projection)
        .smooth_projection(!args.faceted);
    if let Some(l) = args.edge_length {
        options = options.edge_length(positive("--edge-length", l)?);
    }
    if let Some(r) = args.edge_length_relative {
        options = options.relative_edge_length(positive("--edge-length-relative", r)?);
    }
    if args.adaptive {
        let given = |name: &str, x: Option<f64>| x.map(|x| positive(name, x)).transpose();
        let sizing = AdaptiveSizing {
            min_edge: given("--min-edge", args.min_edge)?,
            max_edge: given("--max-edge", args.max_edge)?,
            approx_error: given("--error", args.error)?,
        };
        if let (Some(a), Some(b)) = (sizing.min_edge, sizing.max_edge)
            && a > b
        {
            return Err(CliError::Usage(format!(
                "--min-edge ({}) must not exceed --max-edge ({})",
                exact(a),
                exact(b)
            )));
        }
        options = options.adaptive_sizing(sizing);
    }
    if let Some(d) = args.features {
        if !(0.0..=180.0).contains(&d) {
            return Err(CliError::Usage(format!(
                "--features must be between 0 and 180 degrees, got {}",
                exact(d)
            )));
        }
        options = options.feature_angle(d.to_radians());
    }
    Ok(options)
}

/// Reads a `--feature-edges` file: one edge per line, two 0-based vertex indices;
/// blank lines and `#` comments are skipped. Returns the pairs and the line (1-based)
/// of each.
///
/// # Errors
/// [`CliError::Io`] when the file cannot be read; [`CliError::Input`] naming the line
/// that is not two indices.
fn read_feature_edges(path: &std::path::Path) -> Result<(Vec<[u32; 2]>, Vec<usize>), CliError> {
    let text = std::fs::read_to_string(path).map_err(|source| CliError::Io {
        path: path.to_path_buf(),
        source: beltrami_io::IoError::Io {
            operation: "read the feature edges",
            source,
        },
    })?;
    let (mut pairs, mut lines) = (Vec::new(), Vec::new());
    for (number, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let pair = match fields.as_slice() {
            [a, b] => a.parse::<u32>().ok().zip(b.parse::<u32>().ok()),
            _ => None,
        };
        let Some((a, b)) = pair else {
            return Err(CliError::Input {
                path: path.to_path_buf(),
                message: format!(
                    "line {}: expected two vertex indices (0-based integers), got {line:?}",
                    number + 1
                ),
            });
        };
        pairs.push([a, b]);
        lines.push(number + 1);
    }
    Ok((pairs, lines))
}

/// Runs `beltrami remesh`.
pub(crate) fn run(args: &RemeshArgs, out: &mut impl Write) -> Result<(), CliError> {
    let options = options(args)?;
    refuse_height_map_output(
        &args.output,
        "remesh",
        "remeshing makes new vertices off the grid",
    )?;
    let mut inputs = vec![&args.input];
    inputs.extend(args.feature_edges.as_ref());
    args.outputs.check_inputs(&args.output, &inputs)?;
    let given = args
        .feature_edges
        .as_ref()
        .map(|path| read_feature_edges(path))
        .transpose()?;
    let loaded = load(&args.input, &args.read)?;
    loaded.require_faces(&args.input, "remesh")?;
    crate::repair::refuse_stl_after_split(&args.output, loaded.repair.as_ref())?;
    // The pairs name INPUT's vertices: a repair that renumbers them would make them name
    // other edges.
    if given.is_some() {
        crate::repair::refuse_indices_after_renumbering(
            "--feature-edges",
            &args.input,
            loaded.repair.as_ref(),
        )?;
    }
    let start = std::time::Instant::now();
    // A bar on a terminal for meshes whose iterations take a noticeable time (about a
    // tenth of a second each from 100 000 faces on two cores).
    let long = loaded.mesh.n_faces() >= 100_000;
    let pairs = given
        .as_ref()
        .map_or(&[][..], |(pairs, _)| pairs.as_slice());
    // Counted before the run: the note after it and the advice of a failed run use it.
    let creases = (args.features.is_none() && given.is_none())
        .then(|| crease_edges(&loaded.mesh, &loaded.positions))
        .flatten();
    let result = crate::progress::with_bar(options.iterations, "iterations", long, |show| {
        remesh_with_feature_edges(&loaded.mesh, &loaded.positions, pairs, &options, show)
    });
    let (mesh, positions, report) = result.map_err(|e| match e {
        RemeshError::Options { reason } => CliError::Usage(reason),
        RemeshError::FeatureEdge { index, a, b, why } => CliError::Input {
            path: args.feature_edges.clone().unwrap_or_default(),
            message: format!(
                "line {}: {a} {b} is not an edge of {}: {why}",
                given.as_ref().map_or(0, |(_, lines)| lines[index]),
                args.input.display()
            ),
        },
        RemeshError::NotTriangle { face, len } => CliError::Input {
            path: args.input.clone(),
            message: not_triangles("remesh", face, len),
        },
        e @ (RemeshError::Shrunk { .. } | RemeshError::Degenerate { .. }) => CliError::Input {
            path: args.input.clone(),
            message: match creases.filter(|_| args.features.is_none() && given.is_none()) {
                Some(n) => format!(
                    "{e} (or keep the input's {n} edges sharper than {}°, which run on in chains as a machined part's edges do, with --features 45: a surface held by its edges is not drawn together)",
                    number(CREASE_DEGREES)
                ),
                None => e.to_string(),
            },
        },
        e => CliError::Input {
            path: args.input.clone(),
            message: e.to_string(),
        },
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let quality = QualityChange::measure(
        &args.input,
        "remesh",
        (&loaded.mesh, &loaded.positions),
        (&mesh, &positions),
    )?;
    let summary = Summary {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        target_edge_length: report.target_edge_length,
        adaptive: args.adaptive,
        min_edge: report.adaptive.map(|a| a.min_edge),
        max_edge: report.adaptive.map(|a| a.max_edge),
        approx_error: report.adaptive.map(|a| a.approx_error),
        iterations: report.iterations.len(),
        splits: report.splits,
        collapses: report.collapses,
        flips: report.flips,
        vertices_before: report.vertices_before,
        faces_before: report.faces_before,
        vertices: report.vertices,
        faces: report.faces,
        mean_edge_length_before: report.mean_edge_length_before,
        edge_length_cv_before: report.edge_length_cv_before,
        mean_edge_length: report.mean_edge_length,
        edge_length_cv: report.edge_length_cv,
        feature_edges: report.feature_edges,
        given_feature_edges: report.given_feature_edges,
        fold_edges: report.fold_edges,
        boundary_edges: report.boundary_edges,
        corners: report.corners,
        hausdorff: report.hausdorff,
        hausdorff_from_input: report.hausdorff_from_input,
        degenerate_faces_before: report.degenerate_faces_before,
        degenerate_faces: report.degenerate_faces,
        feature_angle_degrees: args.features,
        projection: !args.no_projection,
        smooth_projection: options.projection && options.smooth_projection,
        seconds,
    };
    let mut notes = notes_for_output(&args.output, &loaded.repair_lines, &mesh);
    // Those printed before the summary line; the rest (below) after it, and all of
    // them in the report's `notes`.
    let early = notes.len();
    let interior = loaded.mesh.n_edges() - report.boundary_edges;
    let degenerate = degenerate_note(&report);
    let fold = args.features.and_then(|_| fold_note(&report));
    let rounded = creases
        .filter(|_| args.features.is_none() && given.is_none())
        .map(|n| {
            format!(
                "note: {n} of the input's edges are sharper than {}° and run on in chains, as a machined part's edges do; without --features they were rounded off (the input's vertices within {} of the result's): --features 45 keeps them as feature curves",
                number(CREASE_DEGREES),
                number(report.hausdorff_from_input),
            )
        });
    let every = args
        .features
        .filter(|_| interior > 0 && report.feature_edges == interior)
        .map(|angle| {
            format!(
                "note: every interior edge is sharper than --features {}°, so every edge is kept and no vertex off a feature is left to move; a larger angle (such as 45) keeps only the sharp edges, and no --features keeps none",
                number(angle),
            )
        });
    notes.extend(
        [&degenerate, &fold, &every, &rounded]
            .into_iter()
            .flatten()
            .cloned(),
    );
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
    writeln!(
        out,
        "remeshed {} -> {}: {} vertices, {} faces -> {} vertices, {} faces; mean edge length {} (target {}), variation {} (was {}); vertices within {} of the input's triangles{}, the input's vertices within {} of the result's",
        args.input.display(),
        args.output.display(),
        report.vertices_before,
        report.faces_before,
        report.vertices,
        report.faces,
        number(report.mean_edge_length),
        number(report.target_edge_length),
        number(report.edge_length_cv),
        number(report.edge_length_cv_before),
        number(report.hausdorff),
        if options.projection && options.smooth_projection {
            " (on the smooth surface through them)"
        } else {
            ""
        },
        number(report.hausdorff_from_input),
    )?;
    if let Some(a) = report.adaptive {
        let derived = [
            (args.min_edge, "--min-edge"),
            (args.max_edge, "--max-edge"),
            (args.error, "--error"),
        ]
        .iter()
        .filter(|(given, _)| given.is_none())
        .map(|(_, name)| *name)
        .collect::<Vec<_>>();
        writeln!(
            out,
            "adaptive sizing: edges from {} to {}, approximation error {}{}",
            number(a.min_edge),
            number(a.max_edge),
            number(a.approx_error),
            if derived.is_empty() {
                String::new()
            } else {
                format!(" ({} derived from the input)", derived.join(", "))
            },
        )?;
    }
    for note in [&degenerate, &rounded].into_iter().flatten() {
        writeln!(out, "{note}")?;
    }
    if let Some(angle) = args.features {
        writeln!(
            out,
            "features: {} of {} interior edges sharper than {}° kept as feature curves{}",
            report.feature_edges,
            interior,
            number(angle),
            if args.feature_edges.is_none() {
                format!(", {} corners fixed", report.corners)
            } else {
                String::new()
            },
        )?;
        for note in [&fold, &every].into_iter().flatten() {
            writeln!(out, "{note}")?;
        }
    }
    if let Some(path) = &args.feature_edges {
        writeln!(
            out,
            "features: {} given in {} kept as feature curves, {} corners fixed",
            counted(
                report.given_feature_edges,
                "interior edge",
                "interior edges"
            ),
            path.display(),
            report.corners
        )?;
    }
    quality.write_table(out)?;
    Ok(())
}

/// The note line when feature edges of the input are folds: their triangles turn back
/// onto each other, as a scan's folded slivers do, and stay in the output as feature
/// curves (with the degenerate triangles along them that the degenerate note counts).
fn fold_note(report: &beltrami_algorithms::RemeshReport) -> Option<String> {
    let n = report.fold_edges;
    let (is, their, stay) = if n == 1 {
        ("feature edge is a fold", "its", "stays")
    } else {
        ("feature edges are folds", "their", "stay")
    };
    (n > 0).then(|| {
        format!(
            "note: {n} {is} of the input ({their} two triangles turn back onto each other by more than {}°, as the folded slivers of a scan do) and {stay} folded in the output; remesh without --features to smooth them out, or repair the input first",
            number(beltrami_algorithms::FOLD_ANGLE.to_degrees()),
        )
    })
}

/// The dihedral angle, in degrees, above which [`crease_edges`] counts an edge as sharp:
/// below a machined part's right angles, above nearly all of the edges that normal noise
/// of a fifth of the mean edge length makes sharp (1 % of them exceed it).
const CREASE_DEGREES: f64 = 60.0;

/// The input's crease edges, when it has some: interior edges sharper than
/// [`CREASE_DEGREES`] that run on at both ends into another such edge. A machined part's
/// edges form such chains and stand apart from its other edges, which are nearly flat;
/// noise bends every edge by a spread of angles, and from about a fifth of the mean edge
/// length its sharp edges chain too. So a mesh counts as creased only when at least 3
/// chained edges are a fifth or more of its sharp ones, the sharp edges outnumber the
/// moderately bent ones (between half the angle and the angle: noise of a fifth of the
/// mean edge makes 4 times more of those than sharp ones), and the nearly flat ones
/// (under a quarter of the angle) are at least twice the moderately bent ones (noise of
/// half a mean edge or more leaves fewer flat edges than bent ones; the block has 97 %
/// flat edges, the 8-vertex cube its 6 face diagonals and no bent one). `None` for a
/// mesh without creases (or when its geometry cannot be measured).
fn crease_edges(
    mesh: &beltrami_halfedge::HalfedgeMesh,
    positions: &[beltrami_halfedge::DVec3],
) -> Option<usize> {
    let geometry = beltrami_halfedge::geometry::Geometry::new(mesh, positions).ok()?;
    let angles = beltrami_metrics::distortion::dihedral_angles(&geometry);
    // One pass over the angles: the sharp edges (and how many meet at each vertex),
    // the nearly flat and the moderately bent ones.
    let mut sharp = Vec::new();
    let mut at_vertex = vec![0u32; mesh.n_vertices()];
    let (mut flat, mut bent) = (0, 0);
    for e in mesh.edges() {
        match angles[e] {
            Some(a) if a > CREASE_DEGREES => {
                for v in mesh.edge_vertices(e) {
                    at_vertex[v.index()] += 1;
                }
                sharp.push(e);
            }
            Some(a) if a > 0.5 * CREASE_DEGREES => bent += 1,
            Some(a) if a < 0.25 * CREASE_DEGREES => flat += 1,
            _ => {}
        }
    }
    let chained = sharp
        .iter()
        .filter(|&&e| {
            mesh.edge_vertices(e)
                .iter()
                .all(|v| at_vertex[v.index()] >= 2)
        })
        .count();
    let n_sharp = sharp.len();
    (chained >= 3 && 5 * chained >= n_sharp && bent < n_sharp && flat >= 2 * bent)
        .then_some(chained)
}

/// The note line when the output has more degenerate triangles than the input.
fn degenerate_note(report: &beltrami_algorithms::RemeshReport) -> Option<String> {
    (report.degenerate_faces > report.degenerate_faces_before).then(|| {
        format!(
            "note: {} of the output are degenerate (flat for their size; the input had {}): passes of a run on noisy input with sharp features can leave a few; more --iterations or a longer target usually removes them",
            counted(report.degenerate_faces, "face", "faces"),
            report.degenerate_faces_before,
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_degenerate_note_appears_only_when_the_output_has_more_than_the_input() {
        let mut report = beltrami_algorithms::RemeshReport::default();
        assert_eq!(degenerate_note(&report), None);
        report.degenerate_faces_before = 2;
        report.degenerate_faces = 2;
        assert_eq!(degenerate_note(&report), None);
        report.degenerate_faces = 3;
        let note = degenerate_note(&report).unwrap();
        assert!(
            note.starts_with("note: 3 faces of the output are degenerate"),
            "{note}"
        );
        assert!(note.contains("the input had 2"), "{note}");
    }

    #[test]
    fn the_fold_note_counts_the_folded_feature_edges() {
        let mut report = beltrami_algorithms::RemeshReport::default();
        assert_eq!(fold_note(&report), None);
        report.fold_edges = 1;
        let one = fold_note(&report).unwrap();
        assert!(one.starts_with("note: 1 feature edge is a fold of the input (its two triangles turn back onto each other by more than 150°"), "{one}");
        assert!(one.contains("stays folded"), "{one}");
        report.fold_edges = 387;
        let many = fold_note(&report).unwrap();
        assert!(
            many.starts_with("note: 387 feature edges are folds of the input (their"),
            "{many}"
        );
        assert!(many.contains("remesh without --features"), "{many}");
    }
}
