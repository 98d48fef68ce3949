//! Reading a mesh file and building its connectivity, the way every command does.

use std::path::Path;

use beltrami_halfedge::{
    DVec3, HalfedgeMesh, PolygonList, RepairOptions, RepairReport, TopologyError, repair,
};
use beltrami_io::{
    HeightMapReport, MeshData, MeshFormat, ReadOptions, ReadReport, Weld, read_mesh_with,
};

use crate::error::CliError;
use crate::smooth::kept::KeptPositions;
use crate::text::{counted, number};

/// The options of every command that reads a mesh.
#[derive(Clone, Debug, Default, clap::Args)]
pub(crate) struct ReadArgs {
    /// Repair the input instead of failing, as `beltrami repair` does: drop degenerate
    /// and duplicate faces, cut non-manifold edges, re-orient, split pinched vertices,
    /// remove unreferenced vertices; say what changed. Results are written with the
    /// repaired faces.
    #[arg(long)]
    pub(crate) repair: bool,
    /// Weld an STL's triangle corners closer than this fraction of the bounding-box
    /// diagonal into one vertex (CAD exporters write 2.7e-16 where 0 was meant), or 0
    /// to weld identical coordinates only (at most 0.01). Indexed formats (PLY, OBJ,
    /// OFF) are read as they are.
    #[arg(long, value_name = "FRACTION", default_value_t = Weld::DEFAULT_RELATIVE, allow_hyphen_values = true)]
    pub(crate) weld_tolerance: f64,
    /// With --repair (and in `repair`): first merge vertices closer than this distance,
    /// in the mesh's length unit, into the lowest-numbered one (coincident vertices a
    /// CAD exporter wrote 1e-16 apart, seams of a mesh split for texturing). Off by
    /// default.
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub(crate) merge_distance: Option<f64>,
    /// With --repair (and in `repair`): also split every face of more than three
    /// corners into triangles, by ear clipping in its own plane (a quadrilateral along
    /// its shorter diagonal inside it), for the commands that need triangles. The
    /// vertices stay as they are.
    #[arg(long)]
    pub(crate) triangulate: bool,
    /// Read a PLY file that holds more than its header declares (extra values on a
    /// line, data after the last element) for what the header declares, or an X3P
    /// file whose checksums do not match, and say what was ignored, instead of
    /// failing.
    #[arg(long)]
    pub(crate) lenient: bool,
}

impl ReadArgs {
    /// The reader's options: the weld tolerance.
    fn options(&self) -> Result<ReadOptions, CliError> {
        let weld = if self.weld_tolerance == 0.0 {
            Weld::Exact
        } else {
            Weld::Relative(self.weld_tolerance)
        };
        weld.check()
            .map_err(|e| CliError::Usage(format!("--weld-tolerance: {e}")))?;
        if self.weld_tolerance > MAX_WELD_TOLERANCE {
            return Err(CliError::Usage(format!(
                "--weld-tolerance {} is a fraction of the bounding-box diagonal and at most {MAX_WELD_TOLERANCE}; larger values weld the part's own features together",
                self.weld_tolerance
            )));
        }
        Ok(ReadOptions::default().weld(weld).lenient(self.lenient))
    }

    /// The repair a load applies: `None` without `--repair`; a usage error for
    /// `--merge-distance` without it.
    fn load_repair_options(&self) -> Result<Option<RepairOptions>, CliError> {
        match (self.repair, self.merge_distance, self.triangulate) {
            (true, _, _) => Ok(Some(self.repair_options()?)),
            (false, None, false) => Ok(None),
            (false, Some(_), _) => Err(CliError::Usage(
                "--merge-distance applies with --repair (or in 'beltrami repair')".into(),
            )),
            (false, None, true) => Err(CliError::Usage(
                "--triangulate applies with --repair (or in 'beltrami repair')".into(),
            )),
        }
    }

    /// The repair options: merging with `--merge-distance`.
    fn repair_options(&self) -> Result<RepairOptions, CliError> {
        if let Some(d) = self.merge_distance
            && !(d >= 0.0 && d.is_finite())
        {
            return Err(CliError::Usage(format!(
                "--merge-distance must be a finite distance >= 0, got {d}"
            )));
        }
        Ok(RepairOptions::new()
            .merge_distance(self.merge_distance)
            .triangulate(self.triangulate))
    }
}

/// The largest `--weld-tolerance`: a hundredth of the bounding-box diagonal already
/// joins features of a coarse mesh; anything larger is a unit slip.
const MAX_WELD_TOLERANCE: f64 = 0.01;

/// The merge distance suggested for a mesh that does not build: a millionth of the
/// bounding-box diagonal (as the STL weld), rounded up to one significant digit, when
/// merging within it joins vertices and leaves no edge to cut and no vertex to split.
/// Returns the number of vertices it would merge and the distance.
fn near_duplicates(positions: &[DVec3], faces: &PolygonList) -> Option<(usize, f64)> {
    let (report, distance) = merge_trial(positions, faces)?;
    // Suggested only when merging is the cure: nothing left to cut or split after it.
    let cured = report.cut_edges.is_empty()
        && report.split_vertices.is_empty()
        && report.opened_edges.is_empty();
    let merged = report.merged_vertices.len();
    (merged > 0 && cured).then_some((merged, distance))
}

/// Vertices within a millionth of the bounding-box diagonal of another (rounded up to
/// one significant digit), or `None` when there are none. A mesh split at texture seams
/// or written by a CAD exporter has them; the surface then falls apart into pieces
/// along them. So does a mesh that `repair` cut along a non-manifold edge or split at
/// a pinched vertex, whose copies a merge would join again.
pub(crate) fn coincident_vertices(positions: &[DVec3], faces: &PolygonList) -> Option<Coincident> {
    let (report, distance) = merge_trial(positions, faces)?;
    let merged = report.merged_vertices.len();
    // The repair after the merge splits the copies whose joining made the surface
    // non-manifold again (a pinched vertex, an edge of more than two faces): one new
    // vertex each.
    let rejoined = report.split_vertices.len();
    (merged > 0).then_some(Coincident {
        vertices: merged,
        distance,
        rejoined,
    })
}

/// What [`coincident_vertices`] found.
pub(crate) struct Coincident {
    /// The number of vertices a merge would join.
    pub(crate) vertices: usize,
    /// The merge distance, in the positions' unit.
    pub(crate) distance: f64,
    /// About how many of them the repair after the merge would split apart again
    /// (joined, they make the surface non-manifold: copies that `repair` split off); 0
    /// when the merge leaves a manifold surface.
    pub(crate) rejoined: usize,
}

/// The repair report of merging within the suggested distance, and the distance.
fn merge_trial(positions: &[DVec3], faces: &PolygonList) -> Option<(RepairReport, f64)> {
    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let diagonal = (hi - lo).length();
    if !(diagonal.is_finite() && diagonal > 0.0) {
        return None;
    }
    let raw = diagonal * Weld::DEFAULT_RELATIVE;
    let scale = 10f64.powf(raw.log10().floor());
    let distance = (raw / scale).ceil() * scale;
    let report = repair(
        positions,
        faces,
        &RepairOptions::new().merge_distance(Some(distance)),
    )
    .ok()?
    .report;
    Some((report, distance))
}

/// A mesh read from a file: connectivity, positions and what repairs changed.
pub(crate) struct LoadedMesh {
    pub(crate) format: MeshFormat,
    pub(crate) mesh: HalfedgeMesh,
    pub(crate) positions: Vec<DVec3>,
    /// The faces to write results with: the input's faces as read, or after a repair
    /// the repaired ones (numbered as `positions`).
    pub(crate) faces: PolygonList,
    /// The vertex and face counts of the file.
    pub(crate) input_counts: (usize, usize),
    /// What `--repair` changed; `None` without it.
    pub(crate) repair: Option<RepairReport>,
    /// One line per kind of repair made, for the command's output.
    pub(crate) repair_lines: Vec<String>,
    /// Wall time of reading and decoding the file, in seconds.
    pub(crate) parse_seconds: f64,
    /// Wall time of building and validating the half-edge connectivity, in seconds.
    pub(crate) build_seconds: f64,
}

impl LoadedMesh {
    /// The lines saying what reading `path` did besides reading it (its height-map grid,
    /// what a lenient read skipped, what `--weld` merged, what `--repair` changed), for a
    /// command that reports on the file as read. With `name_file` (a command reading two
    /// meshes) every line that does not name the file already starts with it.
    pub(crate) fn read_notes(&self, path: &Path, name_file: bool) -> Vec<String> {
        let shown = path.display().to_string();
        self.repair_lines
            .iter()
            .map(|line| {
                if name_file && !line.contains(&shown) {
                    format!("{shown}: {line}")
                } else {
                    line.clone()
                }
            })
            .collect()
    }

    /// Fails with [`CliError::NoFaces`] for a mesh without faces (points only, a
    /// wireframe, an empty file), which `command` cannot work on.
    pub(crate) fn require_faces(&self, path: &Path, command: &'static str) -> Result<(), CliError> {
        if self.mesh.n_faces() == 0 {
            return Err(CliError::NoFaces {
                path: path.to_path_buf(),
                needed_by: command,
                vertices: self.mesh.n_vertices(),
            });
        }
        Ok(())
    }
}

/// Reads `path` and builds its half-edge connectivity, repairing it first when
/// `read.repair` is set (the report says what changed).
pub(crate) fn load(path: &Path, read: &ReadArgs) -> Result<LoadedMesh, CliError> {
    load_checked(path, read, |_| Ok(()))
}

/// [`load`], with `check` run on the data as read, before the connectivity is built
/// (the step that needs most memory): an error from `check` ends the load.
pub(crate) fn load_checked(
    path: &Path,
    read: &ReadArgs,
    check: impl FnOnce(&MeshData) -> Result<(), CliError>,
) -> Result<LoadedMesh, CliError> {
    let options = read.load_repair_options()?;
    load_inner(path, read, options, check, false).map(|(loaded, _)| loaded)
}

/// [`load_checked`], also keeping a copy of the positions (for a summary after a run
/// that changes them) in a temporary file ([`KeptPositions`]): written before the
/// connectivity is built, so that the build (the step of the load that needs most
/// memory) does not hold the positions, which are read back after it. With a repair
/// (which keeps the input for its notes) or where no temporary file can be written, the
/// positions stay in memory through the build.
pub(crate) fn load_checked_keeping(
    path: &Path,
    read: &ReadArgs,
    check: impl FnOnce(&MeshData) -> Result<(), CliError>,
) -> Result<(LoadedMesh, KeptPositions), CliError> {
    let options = read.load_repair_options()?;
    let (loaded, kept) = load_inner(path, read, options, check, true)?;
    let kept = match kept {
        Some(kept) => kept,
        None => KeptPositions::keep(&loaded.positions),
    };
    Ok((loaded, kept))
}

/// [`load`], always repairing (with `--merge-distance` when given).
pub(crate) fn load_repaired(path: &Path, read: &ReadArgs) -> Result<LoadedMesh, CliError> {
    let options = read.repair_options()?;
    load_inner(path, read, Some(options), |_| Ok(()), false).map(|(loaded, _)| loaded)
}

fn load_inner(
    path: &Path,
    read: &ReadArgs,
    options: Option<RepairOptions>,
    check: impl FnOnce(&MeshData) -> Result<(), CliError>,
    keep: bool,
) -> Result<(LoadedMesh, Option<KeptPositions>), CliError> {
    let io = |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    };
    let format = MeshFormat::from_path(path).map_err(io)?;
    let read_options = read.options()?;
    let t0 = std::time::Instant::now();
    let (data, read_report) = read_mesh_with(path, &read_options).map_err(io)?;
    let parse_seconds = t0.elapsed().as_secs_f64();
    check(&data)?;
    let input_counts = (data.positions.len(), data.faces.len());
    let t1 = std::time::Instant::now();
    let topology = |source, positions: &[DVec3], faces: &PolygonList| {
        topology_error(path, read, source, positions, faces)
    };
    // With a repair, the input is kept for the notes about it.
    let (positions, faces, report, input) = match options {
        None => (
            data.positions,
            data.faces,
            None,
            (Vec::new(), PolygonList::new()),
        ),
        Some(options) => {
            let repaired = repair(&data.positions, &data.faces, &options)
                .map_err(|e| topology(e, &data.positions, &data.faces))?;
            (
                repaired.positions,
                repaired.faces,
                Some(repaired.report),
                (data.positions, data.faces),
            )
        }
    };
    // Positions kept in a file are not held while the connectivity is built.
    let n_positions = positions.len();
    let mut positions = positions;
    let kept = (keep && report.is_none()).then(|| KeptPositions::keep(&positions));
    let spilled = kept.as_ref().is_some_and(KeptPositions::in_file);
    if spilled {
        // Freed so that glibc gives the memory back (see `release`).
        beltrami_halfedge::release(std::mem::take(&mut positions));
    }
    let built = HalfedgeMesh::from_polygon_list(n_positions, &faces);
    let mut kept = kept;
    if let Some(kept) = kept.as_mut().filter(|_| spilled) {
        positions = kept
            .read_all()
            .map_err(|e| crate::smooth::kept::read_back_error(path, e))?;
    }
    let mesh = built.map_err(|e| topology(e, &positions, &faces))?;
    let build_seconds = t1.elapsed().as_secs_f64();
    let mut repair_lines = Vec::new();
    if let Some(grid) = &read_report.height_map {
        repair_lines.push(height_map_note(path, grid));
    }
    repair_lines.extend(lenient_note(path, &read_report));
    repair_lines.extend(weld_note(path, read, &read_report));
    if let Some(report) = &report {
        repair_lines.extend(crate::repair::describe(report));
        repair_lines.extend(merge_hint(read, report, &input.0, &input.1));
    }
    let loaded = LoadedMesh {
        format,
        mesh,
        positions,
        faces,
        input_counts,
        repair: report,
        repair_lines,
        parse_seconds,
        build_seconds,
    };
    Ok((loaded, kept))
}

/// The error of a mesh that does not build: whether `--repair` would help and, for a
/// non-manifold element without `--merge-distance`, near-duplicate vertices that
/// merging would join.
fn topology_error(
    path: &Path,
    read: &ReadArgs,
    source: TopologyError,
    positions: &[DVec3],
    faces: &PolygonList,
) -> CliError {
    let repairable = !read.repair && source.is_repairable();
    let merge_helps = read.merge_distance.is_none()
        && matches!(
            source,
            TopologyError::NonManifoldVertex { .. } | TopologyError::NonManifoldEdge { .. }
        );
    CliError::Topology {
        path: path.to_path_buf(),
        repairable,
        near_duplicates: if merge_helps {
            near_duplicates(positions, faces)
        } else {
            None
        },
        source,
    }
}

/// `note: read … leniently, ignoring …`: what a lenient read skipped, if anything.
fn lenient_note(path: &Path, read_report: &ReadReport) -> Option<String> {
    if !read_report.ignored_anything() {
        return None;
    }
    let mut parts = Vec::new();
    if let Some(first) = read_report.checksum_mismatches.first() {
        parts.push(format!(
            "{} that {} not match ({first})",
            counted(
                read_report.checksum_mismatches.len(),
                "checksum",
                "checksums"
            ),
            if read_report.checksum_mismatches.len() == 1 {
                "does"
            } else {
                "do"
            }
        ));
    }
    if let Some(first) = read_report.lines_with_extra_values.first() {
        parts.push(format!(
            "values beyond the header's properties on {} (the first: line {first})",
            counted(read_report.lines_with_extra_values.len(), "line", "lines")
        ));
    }
    if read_report.ignored_trailing_lines > 0 {
        parts.push(format!(
            "{} after the last element",
            counted(read_report.ignored_trailing_lines, "line", "lines")
        ));
    }
    if read_report.ignored_trailing_bytes > 0 {
        parts.push(format!(
            "{} bytes after the last element",
            read_report.ignored_trailing_bytes
        ));
    }
    Some(format!(
        "note: read {} leniently, ignoring {}",
        path.display(),
        parts.join(", ")
    ))
}

/// `note: welded …`: the STL corners welded and the triangles dropped, if any.
fn weld_note(path: &Path, read: &ReadArgs, read_report: &ReadReport) -> Option<String> {
    if read_report.welded_vertices == 0 && read_report.dropped_faces.is_empty() {
        return None;
    }
    Some(format!(
        "note: welded {} of {} within {} (--weld-tolerance {} of the diagonal; 0 welds identical coordinates only){}",
        counted(read_report.welded_vertices, "vertex", "vertices"),
        path.display(),
        number(read_report.weld_distance.unwrap_or(0.0)),
        number(read.weld_tolerance),
        if read_report.dropped_faces.is_empty() {
            String::new()
        } else {
            format!(
                "; dropped {} that collapsed",
                counted(read_report.dropped_faces.len(), "triangle", "triangles")
            )
        }
    ))
}

/// After a repair that split vertices or cut edges without `--merge-distance`: the
/// near-duplicate vertices of the input that merging would join instead.
fn merge_hint(
    read: &ReadArgs,
    report: &RepairReport,
    positions: &[DVec3],
    faces: &PolygonList,
) -> Option<String> {
    // Pinches and cut edges from vertices that should have been one: say so.
    if read.merge_distance.is_none()
        && (!report.split_vertices.is_empty() || !report.cut_edges.is_empty())
        && let Some((n, d)) = near_duplicates(positions, faces)
    {
        return Some(format!(
            "note: {} within {} of another; --merge-distance {} joins them instead of cutting the surface apart",
            counted(n, "vertex lies", "vertices lie"),
            number(d),
            number(d)
        ));
    }
    None
}

/// `note: read scan.x3p as a height map of 640 × 480 points 1.5e-6 × 1.5e-6 m apart,
/// coordinates in m; left out (holes) 12 invalid points`: what a grid became.
pub(crate) fn height_map_note(path: &Path, grid: &HeightMapReport) -> String {
    let mut left_out = Vec::new();
    if grid.stats.invalid_points > 0 {
        left_out.push(counted(
            grid.stats.invalid_points,
            "invalid point",
            "invalid points",
        ));
    }
    if grid.stats.unused_points > 0 {
        left_out.push(format!(
            "{} in no cell of four valid points",
            counted(grid.stats.unused_points, "point", "points")
        ));
    }
    format!(
        "note: read {} as a height map of {} × {} points {} × {} {unit} apart, coordinates in {unit}{}",
        path.display(),
        grid.nx,
        grid.ny,
        number(grid.dx),
        number(grid.dy),
        if left_out.is_empty() {
            String::new()
        } else {
            format!("; left out (holes) {}", left_out.join(" and "))
        },
        unit = grid.unit,
    )
}
