//! Reading a mesh file and building its connectivity, the way every command does.

use std::path::Path;

use beltrami_halfedge::{
    BuildOptions, BuildReport, DVec3, HalfedgeMesh, PolygonList, TopologyError,
};
use beltrami_io::{MeshData, MeshFormat, read_mesh};

use crate::error::CliError;

/// A mesh read from a file: connectivity, positions and what repairs changed.
pub(crate) struct LoadedMesh {
    pub(crate) format: MeshFormat,
    pub(crate) mesh: HalfedgeMesh,
    pub(crate) positions: Vec<DVec3>,
    /// The faces as read (before any repair), to write results with the input's faces.
    pub(crate) faces: PolygonList,
    pub(crate) report: BuildReport,
    /// Wall time of reading and decoding the file, in seconds.
    pub(crate) parse_seconds: f64,
    /// Wall time of building and validating the half-edge connectivity, in seconds.
    pub(crate) build_seconds: f64,
}

/// Reads `path` and builds its half-edge connectivity, applying every repair when
/// `repair` is set (the report says what changed).
pub(crate) fn load(path: &Path, repair: bool) -> Result<LoadedMesh, CliError> {
    load_checked(path, repair, |_| Ok(()))
}

/// [`load`], with `check` run on the data as read, before the connectivity is built
/// (the step that needs most memory): an error from `check` ends the load.
pub(crate) fn load_checked(
    path: &Path,
    repair: bool,
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
    let options = if repair {
        BuildOptions::repair_all()
    } else {
        BuildOptions::new()
    };
    let (mesh, report) = HalfedgeMesh::build(data.positions.len(), data.faces.iter(), &options)
        .map_err(|source| CliError::Topology {
            path: path.to_path_buf(),
            repairable: !repair && is_repairable(&source),
            source,
        })?;
    let mut positions = data.positions;
    for split in &report.split_vertices {
        positions.push(positions[split.original.index()]);
    }
    let build_seconds = t1.elapsed().as_secs_f64();
    Ok(LoadedMesh {
        format,
        mesh,
        positions,
        faces: data.faces,
        report,
        parse_seconds,
        build_seconds,
    })
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
