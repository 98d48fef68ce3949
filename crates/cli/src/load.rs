//! Reading a mesh file and building its connectivity, the way every command does.

use std::path::Path;

use beltrami_halfedge::{
    DVec3, HalfedgeMesh, PolygonList, RepairOptions, RepairReport, TopologyError, repair,
};
use beltrami_io::{MeshData, MeshFormat, ReadOptions, Weld, read_mesh_with};

use crate::error::CliError;
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
    /// to weld identical coordinates only. Indexed formats (PLY, OBJ, OFF) are read as
    /// they are.
    #[arg(long, value_name = "FRACTION", default_value_t = Weld::DEFAULT_RELATIVE, allow_negative_numbers = true)]
    pub(crate) weld_tolerance: f64,
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
        Ok(ReadOptions::default().with_weld(weld))
    }
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
    let options = read.repair.then(RepairOptions::new);
    load_inner(path, read, options, check)
}

/// [`load`], always repairing with `options` (`None`: as `read` says).
pub(crate) fn load_with(
    path: &Path,
    read: &ReadArgs,
    options: Option<RepairOptions>,
) -> Result<LoadedMesh, CliError> {
    let options = options.or_else(|| read.repair.then(RepairOptions::new));
    load_inner(path, read, options, |_| Ok(()))
}

fn load_inner(
    path: &Path,
    read: &ReadArgs,
    options: Option<RepairOptions>,
    check: impl FnOnce(&MeshData) -> Result<(), CliError>,
) -> Result<LoadedMesh, CliError> {
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
    let topology = |source| CliError::Topology {
        path: path.to_path_buf(),
        repairable: !read.repair && is_repairable(&source),
        source,
    };
    let (positions, faces, report) = match options {
        None => (data.positions, data.faces, None),
        Some(options) => {
            let repaired = repair(&data.positions, &data.faces, &options).map_err(topology)?;
            (repaired.positions, repaired.faces, Some(repaired.report))
        }
    };
    let mesh = HalfedgeMesh::from_polygons(positions.len(), faces.iter()).map_err(topology)?;
    let build_seconds = t1.elapsed().as_secs_f64();
    let mut repair_lines = Vec::new();
    if read_report.welded_vertices > 0 || !read_report.dropped_faces.is_empty() {
        repair_lines.push(format!(
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
        ));
    }
    if let Some(report) = &report {
        repair_lines.extend(crate::repair::describe(report));
    }
    Ok(LoadedMesh {
        format,
        mesh,
        positions,
        faces,
        input_counts,
        repair: report,
        repair_lines,
        parse_seconds,
        build_seconds,
    })
}

/// Whether `beltrami repair` (and `--repair`) fixes `e`: every topological problem of
/// a face list with valid indices.
fn is_repairable(e: &TopologyError) -> bool {
    matches!(
        e,
        TopologyError::FaceTooSmall { .. }
            | TopologyError::RepeatedVertex { .. }
            | TopologyError::NonManifoldEdge { .. }
            | TopologyError::InconsistentOrientation { .. }
            | TopologyError::NonManifoldVertex { .. }
            | TopologyError::NonOrientable { .. }
    )
}
