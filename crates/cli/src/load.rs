//! Reading a mesh file and building its connectivity, the way every command does.

use std::path::Path;

use beltrami_halfedge::{
    BuildOptions, BuildReport, DVec3, HalfedgeMesh, PolygonList, TopologyError,
};
use beltrami_io::{MeshData, MeshFormat, read_mesh};

use crate::error::CliError;
use crate::text::counted;

/// The options of every command that reads a mesh.
#[derive(Clone, Debug, Default, clap::Args)]
pub(crate) struct ReadArgs {
    /// Repair the input instead of failing, as `beltrami repair` does (drop degenerate
    /// faces, re-orient, split pinched vertices), and say what changed.
    #[arg(long)]
    pub(crate) repair: bool,
}

/// A mesh read from a file: connectivity, positions and what repairs changed.
pub(crate) struct LoadedMesh {
    pub(crate) format: MeshFormat,
    pub(crate) mesh: HalfedgeMesh,
    pub(crate) positions: Vec<DVec3>,
    /// The faces to write results with: the input's faces as read, or after a repair
    /// the repaired ones (numbered as `positions`).
    pub(crate) faces: PolygonList,
    pub(crate) report: BuildReport,
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

/// Reads `path` and builds its half-edge connectivity, applying every repair when
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
    let io = |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    };
    let format = MeshFormat::from_path(path).map_err(io)?;
    let t0 = std::time::Instant::now();
    let data = read_mesh(path).map_err(io)?;
    let parse_seconds = t0.elapsed().as_secs_f64();
    check(&data)?;
    let t1 = std::time::Instant::now();
    let options = if read.repair {
        BuildOptions::repair_all()
    } else {
        BuildOptions::new()
    };
    let (mesh, report) = HalfedgeMesh::build(data.positions.len(), data.faces.iter(), &options)
        .map_err(|source| CliError::Topology {
            path: path.to_path_buf(),
            repairable: !read.repair && is_repairable(&source),
            source,
        })?;
    let mut positions = data.positions;
    for split in &report.split_vertices {
        positions.push(positions[split.original.index()]);
    }
    let faces = if report.is_empty() {
        data.faces
    } else {
        mesh_faces(&mesh)
    };
    let build_seconds = t1.elapsed().as_secs_f64();
    let repair_lines = describe(&report);
    Ok(LoadedMesh {
        format,
        mesh,
        positions,
        faces,
        report,
        repair_lines,
        parse_seconds,
        build_seconds,
    })
}

/// The faces of `mesh` as vertex lists, in face order.
fn mesh_faces(mesh: &HalfedgeMesh) -> PolygonList {
    let mut faces = PolygonList::new();
    let mut corners = Vec::new();
    for f in mesh.faces() {
        corners.clear();
        corners.extend(mesh.vertices_around_face(f).map(|v| v.raw()));
        faces.push(&corners);
    }
    faces
}

/// One line per kind of repair in `report`.
fn describe(report: &BuildReport) -> Vec<String> {
    let mut lines = Vec::new();
    if !report.dropped_faces.is_empty() {
        lines.push(format!(
            "repaired: dropped {} (input faces {})",
            counted(
                report.dropped_faces.len(),
                "degenerate face",
                "degenerate faces"
            ),
            list(report.dropped_faces.iter())
        ));
    }
    if !report.flipped_faces.is_empty() {
        lines.push(format!(
            "repaired: re-oriented {} (input faces {})",
            counted(report.flipped_faces.len(), "face", "faces"),
            list(report.flipped_faces.iter())
        ));
    }
    if !report.split_vertices.is_empty() {
        lines.push(format!(
            "repaired: split pinched vertices into {} (input vertices {})",
            counted(report.split_vertices.len(), "new vertex", "new vertices"),
            list(report.split_vertices.iter().map(|s| s.original.raw()))
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

fn is_repairable(e: &TopologyError) -> bool {
    matches!(
        e,
        TopologyError::FaceTooSmall { .. }
            | TopologyError::RepeatedVertex { .. }
            | TopologyError::InconsistentOrientation { .. }
            | TopologyError::NonManifoldVertex { .. }
    )
}
