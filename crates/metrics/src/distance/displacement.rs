//! Plain per-vertex displacement between two meshes of the same topology.

use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};

use super::stats::{DistanceStats, vertex_areas};
use crate::MetricsError;

/// Checks that two meshes share their topology: the same number of vertices, the same
/// number of faces, and face `f` of one lists the same vertices in the same order as face
/// `f` of the other.
///
/// # Errors
/// [`MetricsError::TopologyMismatch`] naming the first difference, e.g.
/// `"642 vertices vs 640"` or `"face 12 is [0, 1, 2] vs [0, 2, 1]"`.
///
/// # Complexity
/// O(H).
pub fn check_same_topology(mesh: &HalfedgeMesh, other: &HalfedgeMesh) -> Result<(), MetricsError> {
    let mismatch = |detail: String| Err(MetricsError::TopologyMismatch { detail });
    if mesh.n_vertices() != other.n_vertices() {
        return mismatch(format!(
            "{} vertices vs {}",
            mesh.n_vertices(),
            other.n_vertices()
        ));
    }
    if mesh.n_faces() != other.n_faces() {
        return mismatch(format!("{} faces vs {}", mesh.n_faces(), other.n_faces()));
    }
    if mesh == other {
        return Ok(());
    }
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for f in mesh.faces() {
        a.clear();
        b.clear();
        a.extend(mesh.vertices_around_face(f).map(|v| v.raw()));
        b.extend(other.vertices_around_face(f).map(|v| v.raw()));
        if a != b {
            return mismatch(format!("face {} is {a:?} vs {b:?}", f.raw()));
        }
    }
    Ok(())
}

/// The displacement `|x_i − y_i|` of every vertex between two meshes of the same topology
/// (`positions` = x, `reference_positions` = y), in the positions' unit.
///
/// # Errors
/// [`MetricsError::TopologyMismatch`] (see [`check_same_topology`]);
/// [`MetricsError::Topology`] when a positions slice does not match its mesh;
/// [`MetricsError::NonFinite`] for a non-finite position.
pub fn displacements(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    reference: &HalfedgeMesh,
    reference_positions: &[DVec3],
) -> Result<Vec<f64>, MetricsError> {
    check_same_topology(mesh, reference)?;
    for (p, m) in [(positions, mesh), (reference_positions, reference)] {
        if p.len() != m.n_vertices() {
            return Err(TopologyError::PositionCount {
                positions: p.len(),
                vertices: m.n_vertices(),
            }
            .into());
        }
    }
    super::index::check_points(positions, "vertex")?;
    super::index::check_points(reference_positions, "reference vertex")?;
    Ok(positions
        .iter()
        .zip(reference_positions)
        .map(|(x, y)| x.distance(*y))
        .collect())
}

/// Statistics of [`displacements`]: RMS, mean, max and the area-weighted RMS with the
/// barycentric vertex areas of `mesh`.
///
/// # Errors
/// As for [`displacements`]; [`MetricsError::Empty`] for meshes without vertices.
pub fn displacement_stats(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    reference: &HalfedgeMesh,
    reference_positions: &[DVec3],
) -> Result<DistanceStats, MetricsError> {
    let d = displacements(mesh, positions, reference, reference_positions)?;
    let areas = vertex_areas(mesh, positions)?;
    DistanceStats::new(&d, &areas)
}
