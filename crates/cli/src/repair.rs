//! `beltrami repair`: write a mesh that every command accepts, and say what changed,
//! per element. Also the report that `--repair` prints on every reading command.

use std::io::Write;
use std::path::PathBuf;

use beltrami_algorithms::{FlatError, FlatOptions, FlatReport, remove_flat_triangles};
use beltrami_halfedge::RepairReport;
use beltrami_io::MeshData;
use serde::Serialize;

use crate::error::{CliError, not_triangles};
use crate::load::{ReadArgs, load_repaired};
use crate::output::{Outputs, Staged, notes_for_output};
use crate::text::counted;

/// Arguments of `beltrami repair`.
#[derive(Debug, clap::Args)]
pub(crate) struct RepairArgs {
    /// The mesh to repair (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    input: PathBuf,
    /// The repaired mesh (.ply, .stl, .obj or .off by extension).
    output: PathBuf,
    /// Print what was repaired as one JSON object, every element listed.
    #[arg(long)]
    json: bool,
    /// Write PLY (and STL) as ascii text instead of binary.
    #[arg(long)]
    ascii: bool,
    /// Replace OUTPUT even when it is the input (an edit in place) or write-protected.
    #[arg(long)]
    force: bool,
    /// Also remove flat triangles (zero-area slivers: a corner on the opposite edge, or
    /// two corners at one point) by flipping their longest edge, deleting them on the
    /// boundary (or alone), or collapsing an edge of length zero: edits that leave the
    /// surface where it is. A triangle mesh only.
    #[arg(long)]
    flat_faces: bool,
    /// With --flat-faces: a triangle is flat when its height is at most this share of
    /// its longest edge (default 1e-12, the triangles cotangent weights treat as
    /// absent). Larger values take near-slivers too, whose flip or deletion moves the
    /// surface by up to their height (reported). At most 0.1.
    #[arg(
        long,
        value_name = "RATIO",
        requires = "flat_faces",
        allow_hyphen_values = true
    )]
    flat_ratio: Option<f64>,
    /// With --flat-faces: let a collapse move a vertex by up to this distance (in the
    /// mesh's unit) where no flip or deletion removes a sliver (default 0: nothing
    /// moves). The vertex's other triangles move with it.
    #[arg(
        long,
        value_name = "DISTANCE",
        requires = "flat_faces",
        allow_hyphen_values = true
    )]
    flat_max_move: Option<f64>,
    #[command(flatten)]
    read: ReadArgs,
}

/// What `repair --json` prints of `--flat-faces`.
#[derive(Debug, Serialize)]
struct FlatJson {
    /// Flat triangles before and left after.
    before: usize,
    after: usize,
    /// Edges flipped (caps), caps deleted on the boundary, flat triangles alone
    /// deleted, edges collapsed (needles).
    flips: usize,
    deleted: usize,
    alone: usize,
    collapses: usize,
    /// The longest distance a collapse moved a vertex.
    max_move: f64,
    /// The largest height of a triangle flipped away or deleted: how far those edits
    /// moved the surface at most.
    max_height: f64,
}

impl From<&FlatReport> for FlatJson {
    fn from(r: &FlatReport) -> Self {
        Self {
            before: r.flat_before,
            after: r.flat_after,
            flips: r.flips,
            deleted: r.deleted,
            alone: r.alone,
            collapses: r.collapses,
            max_move: r.max_move,
            max_height: r.max_height,
        }
    }
}

impl RepairArgs {
    /// The options of `--flat-faces`, checked (a usage error before anything is read).
    fn flat_options(&self) -> Result<Option<FlatOptions>, CliError> {
        if !self.flat_faces {
            return Ok(None);
        }
        let mut options = FlatOptions::default();
        if let Some(r) = self.flat_ratio {
            options = options.max_height_ratio(r);
        }
        if let Some(d) = self.flat_max_move {
            options = options.max_move(d);
        }
        match options.check() {
            Ok(()) => Ok(Some(options)),
            Err(FlatError::Options { reason }) => {
                Err(CliError::Usage(format!("--flat-faces: {reason}")))
            }
            Err(e) => Err(CliError::Usage(e.to_string())),
        }
    }
}

/// What `repair --json` prints: every repair, per element, in the input's indices.
#[derive(Debug, Serialize)]
pub(crate) struct RepairJson {
    /// `[vertex, the vertex it merged into]`.
    pub(crate) merged_vertices: Vec<[u32; 2]>,
    /// Faces with fewer than three distinct vertices.
    pub(crate) dropped_degenerate_faces: Vec<usize>,
    /// `[face, the earlier face it repeats]` (either orientation).
    pub(crate) dropped_duplicate_faces: Vec<[usize; 2]>,
    /// Faces that listed a vertex twice in a row, kept with it once.
    pub(crate) shortened_faces: Vec<usize>,
    /// Faces of more than three corners split into triangles (`--triangulate`).
    pub(crate) triangulated_faces: Vec<usize>,
    /// `[a, b]`: edges of more than two faces, cut into manifold sheets.
    pub(crate) cut_edges: Vec<[u32; 2]>,
    /// `[a, b]`: edges opened to make a component orientable or to untangle sheets.
    pub(crate) opened_edges: Vec<[u32; 2]>,
    /// Faces whose orientation was reversed.
    pub(crate) flipped_faces: Vec<usize>,
    /// `[input vertex, new output vertex]`: pinched vertices split into one copy per fan.
    pub(crate) split_vertices: Vec<[u32; 2]>,
    /// Vertices that no face used, removed.
    pub(crate) removed_vertices: Vec<u32>,
}

impl From<&RepairReport> for RepairJson {
    fn from(r: &RepairReport) -> Self {
        Self {
            merged_vertices: r.merged_vertices.iter().map(|&(a, b)| [a, b]).collect(),
            dropped_degenerate_faces: r.dropped_degenerate_faces.clone(),
            dropped_duplicate_faces: r
                .dropped_duplicate_faces
                .iter()
                .map(|&(a, b)| [a, b])
                .collect(),
            shortened_faces: r.shortened_faces.clone(),
            triangulated_faces: r.triangulated_faces.clone(),
            cut_edges: r.cut_edges.iter().map(|&(a, b)| [a, b]).collect(),
            opened_edges: r.opened_edges.iter().map(|&(a, b)| [a, b]).collect(),
            flipped_faces: r.flipped_faces.clone(),
            split_vertices: r.split_vertices.iter().map(|&(a, b)| [a, b]).collect(),
            removed_vertices: r.removed_vertices.clone(),
        }
    }
}

/// Refuses an STL `output` of a mesh whose repair split vertices (cut non-manifold
/// edges, pinched vertices, opened edges): STL keeps no vertex indices, so a copy split
/// off, still at its original's position, is joined to it again when the file is read,
/// undoing the repair. For every command that writes a mesh after `--repair`: those
/// that keep the input's positions (`repair`, `fill-holes`, `delaunay`) and those that
/// keep the boundary's (`remesh`, `decimate`, `subdivide` keep the split copies where
/// they are; `smooth` with its default fixed boundary too), where the copies stay
/// together.
///
/// # Errors
/// [`CliError::Input`] naming `output`, when it is an STL file and `repair` split
/// vertices.
pub(crate) fn refuse_stl_after_split(
    output: &std::path::Path,
    repair: Option<&RepairReport>,
) -> Result<(), CliError> {
    let split = repair.map_or(0, |r| r.split_vertices.len());
    match beltrami_io::MeshFormat::from_path(output).map(|f| f.loses_split_vertices(split)) {
        Ok(Some(message)) => Err(CliError::Input {
            path: output.to_path_buf(),
            message,
        }),
        _ => Ok(()),
    }
}

/// Refuses vertex indices given by `option` (numbering INPUT's vertices) after a
/// `--repair` that renumbered the vertices (merged, removed or split some): they would
/// name other vertices.
///
/// # Errors
/// [`CliError::Input`] naming `input`.
pub(crate) fn refuse_indices_after_renumbering(
    option: &str,
    input: &std::path::Path,
    repair: Option<&RepairReport>,
) -> Result<(), CliError> {
    match repair {
        Some(r)
            if !(r.merged_vertices.is_empty()
                && r.removed_vertices.is_empty()
                && r.split_vertices.is_empty()) =>
        {
            Err(CliError::Input {
                path: input.to_path_buf(),
                message: format!(
                    "--repair renumbered the vertices (merged, removed or split some), so {option} would name other vertices; repair the mesh first with `beltrami repair` and give {option} in the repaired file's numbering"
                ),
            })
        }
        _ => Ok(()),
    }
}

/// One line per kind of repair, naming the first elements: what `--repair` and
/// `beltrami repair` print.
pub(crate) fn describe(r: &RepairReport) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = |n: usize, what: String, items: String| {
        if n > 0 {
            lines.push(format!("repaired: {what} ({items})"));
        }
    };
    line(
        r.merged_vertices.len(),
        format!(
            "merged {}",
            counted(r.merged_vertices.len(), "vertex", "vertices")
        ),
        list(
            r.merged_vertices
                .iter()
                .map(|(a, b)| format!("{a} into {b}")),
        ),
    );
    line(
        r.dropped_degenerate_faces.len(),
        format!(
            "dropped {}",
            counted(
                r.dropped_degenerate_faces.len(),
                "degenerate face",
                "degenerate faces"
            )
        ),
        format!("input faces {}", list(r.dropped_degenerate_faces.iter())),
    );
    line(
        r.dropped_duplicate_faces.len(),
        format!(
            "dropped {}",
            counted(
                r.dropped_duplicate_faces.len(),
                "duplicate face",
                "duplicate faces"
            )
        ),
        list(
            r.dropped_duplicate_faces
                .iter()
                .map(|(a, b)| format!("face {a} repeats face {b}")),
        ),
    );
    line(
        r.shortened_faces.len(),
        format!(
            "removed a repeated corner from {}",
            counted(r.shortened_faces.len(), "face", "faces")
        ),
        format!("input faces {}", list(r.shortened_faces.iter())),
    );
    line(
        r.triangulated_faces.len(),
        format!(
            "split {} into triangles",
            counted(r.triangulated_faces.len(), "polygon", "polygons")
        ),
        format!("input faces {}", list(r.triangulated_faces.iter())),
    );
    line(
        r.cut_edges.len(),
        format!(
            "cut {} into manifold sheets",
            counted(r.cut_edges.len(), "non-manifold edge", "non-manifold edges")
        ),
        list(r.cut_edges.iter().map(|(a, b)| format!("{a}-{b}"))),
    );
    line(
        r.opened_edges.len(),
        format!(
            "opened {} to make the surface orientable",
            counted(r.opened_edges.len(), "edge", "edges")
        ),
        list(r.opened_edges.iter().map(|(a, b)| format!("{a}-{b}"))),
    );
    line(
        r.flipped_faces.len(),
        format!(
            "re-oriented {}",
            counted(r.flipped_faces.len(), "face", "faces")
        ),
        format!("input faces {}", list(r.flipped_faces.iter())),
    );
    line(
        r.split_vertices.len(),
        format!(
            "split pinched vertices into {}",
            counted(r.split_vertices.len(), "new vertex", "new vertices")
        ),
        format!(
            "input vertices {}",
            list(r.split_vertices.iter().map(|(a, _)| a))
        ),
    );
    line(
        r.removed_vertices.len(),
        format!(
            "removed {}",
            counted(
                r.removed_vertices.len(),
                "unreferenced vertex",
                "unreferenced vertices"
            )
        ),
        format!("input vertices {}", list(r.removed_vertices.iter())),
    );
    lines
}

/// The lines of `--flat-faces`: what removed the flat triangles, and those left.
/// `ratio_given`: whether `--flat-ratio` was (then how far flips and deletions moved the
/// surface is said); `max_move`: `--flat-max-move`.
fn describe_flat(f: &FlatReport, ratio_given: bool, max_move: Option<f64>) -> Vec<String> {
    let mut lines = Vec::new();
    let removed = f.flat_before.saturating_sub(f.flat_after);
    if removed > 0 {
        let mut how = Vec::new();
        if f.flips > 0 {
            how.push(counted(f.flips, "edge flipped", "edges flipped"));
        }
        if f.deleted > 0 {
            how.push(format!(
                "{} on the boundary deleted",
                counted(f.deleted, "cap", "caps")
            ));
        }
        if f.alone > 0 {
            how.push(format!(
                "{} deleted",
                counted(f.alone, "triangle alone", "triangles alone")
            ));
        }
        if f.collapses > 0 && f.max_move == 0.0 {
            how.push(counted(
                f.collapses,
                "zero-length edge collapsed",
                "zero-length edges collapsed",
            ));
        } else if f.collapses > 0 {
            how.push(format!(
                "{} (vertices moved by at most {})",
                counted(f.collapses, "edge collapsed", "edges collapsed"),
                crate::text::number(f.max_move)
            ));
        }
        if ratio_given && f.max_height > 0.0 {
            how.push(format!(
                "the surface moved by at most {} where near-slivers were flipped or deleted",
                crate::text::number(f.max_height)
            ));
        }
        lines.push(format!(
            "repaired: removed {} ({})",
            counted(removed, "flat triangle", "flat triangles"),
            how.join(", ")
        ));
    }
    if f.flat_after > 0 {
        let (it, within, advice) = (
            if f.flat_after == 1 { "it" } else { "them" },
            max_move.map_or(String::new(), |d| {
                format!(" within --flat-max-move {}", crate::text::number(d))
            }),
            if max_move.is_some() {
                "a larger --flat-max-move lets a collapse move a vertex farther"
            } else {
                "--flat-max-move DISTANCE lets a collapse move a vertex that far"
            },
        );
        lines.push(format!(
            "note: {} left: no flip, deletion or collapse{within} removes {it} without folding a triangle over; {advice}",
            counted(f.flat_after, "flat triangle", "flat triangles"),
        ));
    }
    lines
}

/// At most 10 items, comma-separated, then "and N more".
fn list<T: std::fmt::Display>(items: impl ExactSizeIterator<Item = T>) -> String {
    let n = items.len();
    let mut text: Vec<String> = items.take(10).map(|i| i.to_string()).collect();
    if n > 10 {
        text.push(format!("and {} more", n - 10));
    }
    text.join(", ")
}

/// The JSON of `repair --json`.
#[derive(Debug, Serialize)]
struct Summary {
    input: String,
    output: String,
    vertices_in: usize,
    faces_in: usize,
    vertices: usize,
    faces: usize,
    repairs: RepairJson,
    /// With `--flat-faces`: what removing the flat triangles did; null without it.
    flat_triangles: Option<FlatJson>,
    /// The lines printed before the sentence (what the output format leaves out).
    notes: Vec<String>,
}

/// Runs `beltrami repair`.
pub(crate) fn run(args: &RepairArgs, out: &mut impl Write) -> Result<(), CliError> {
    let flat_options = args.flat_options()?;
    crate::output::refuse_unknown_output(&args.output, "repair")?;
    let mut outputs = Outputs::new();
    outputs.add_mesh(&args.output, "OUTPUT");
    outputs.check(&[&args.input], args.force)?;
    let loaded = load_repaired(&args.input, &args.read)?;
    let report = loaded.repair.clone().unwrap_or_default();
    if loaded.faces.is_empty() && loaded.input_counts.1 > 0 {
        return Err(CliError::Input {
            path: args.input.clone(),
            message: format!(
                "the repair left none of the {}: every one was degenerate or a duplicate{}; nothing written",
                counted(loaded.input_counts.1, "face", "faces"),
                match args.read.merge_distance {
                    Some(d) => format!(
                        " once vertices closer than {} were merged (is --merge-distance in the mesh's unit?)",
                        crate::text::number(d)
                    ),
                    None => String::new(),
                }
            ),
        });
    }
    refuse_stl_after_split(&args.output, Some(&report))?;
    let mut lines = loaded.repair_lines.clone();
    let (data, flat) = if let Some(options) = flat_options {
        let (mesh, positions, flat) = remove_flat_triangles(
            &loaded.mesh,
            &loaded.positions,
            options,
        )
        .map_err(|e| match e {
            FlatError::Options { reason } => CliError::Usage(format!("--flat-faces: {reason}")),
            FlatError::NotTriangle { face, len } => CliError::Input {
                path: args.input.clone(),
                message: not_triangles("--flat-faces", face, len),
            },
            e => CliError::Input {
                path: args.input.clone(),
                message: e.to_string(),
            },
        })?;
        if mesh.n_faces() == 0 {
            return Err(CliError::Input {
                path: args.input.clone(),
                message: format!(
                    "removing the flat triangles left no face: every one of the {} was flat{}; nothing written",
                    counted(loaded.mesh.n_faces(), "triangle", "triangles"),
                    if args.flat_ratio.is_some() {
                        " at this --flat-ratio"
                    } else {
                        ""
                    }
                ),
            });
        }
        lines.extend(describe_flat(
            &flat,
            args.flat_ratio.is_some(),
            args.flat_max_move,
        ));
        lines = notes_for_output(&args.output, &lines, &mesh);
        let faces = mesh.to_polygons();
        (MeshData { positions, faces }, Some(flat))
    } else {
        lines = notes_for_output(&args.output, &lines, &loaded.mesh);
        let data = MeshData {
            positions: loaded.positions,
            faces: loaded.faces,
        };
        (data, None)
    };
    let mut staged = Staged::new();
    staged.push_mesh(&args.output, &data, args.ascii)?;
    staged.commit()?;
    if args.json {
        let summary = Summary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            vertices_in: loaded.input_counts.0,
            faces_in: loaded.input_counts.1,
            vertices: data.positions.len(),
            faces: data.faces.len(),
            repairs: RepairJson::from(&report),
            flat_triangles: flat.as_ref().map(FlatJson::from),
            notes: lines,
        };
        serde_json::to_writer_pretty(&mut *out, &summary).map_err(std::io::Error::from)?;
        writeln!(out)?;
        return Ok(());
    }
    for line in &lines {
        writeln!(out, "{line}")?;
    }
    let flat_text = flat.as_ref().map_or_else(String::new, |f| {
        let sep = if report.is_empty() { "" } else { "; " };
        if f.flat_before == 0 {
            format!("{sep}no flat triangles")
        } else {
            format!(
                "{sep}{} of {} removed",
                f.flat_before.saturating_sub(f.flat_after),
                counted(f.flat_before, "flat triangle", "flat triangles")
            )
        }
    });
    // With --flat-faces alone, "no repair needed" would contradict the flat triangles.
    let topology = if report.is_empty() && flat.is_some() {
        String::new()
    } else {
        report.to_string()
    };
    writeln!(
        out,
        "repaired {} ({}, {}): {topology}{flat_text} -> {} ({}, {})",
        args.input.display(),
        counted(loaded.input_counts.0, "vertex", "vertices"),
        counted(loaded.input_counts.1, "face", "faces"),
        args.output.display(),
        counted(data.positions.len(), "vertex", "vertices"),
        counted(data.faces.len(), "face", "faces"),
    )?;
    Ok(())
}
