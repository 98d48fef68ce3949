//! [`MeshSummary`]: what a mesh is, in a few stable lines.

use std::fmt;

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};
use serde::Serialize;

use crate::round::{SUMMARY_DIGITS, format_significant, round_significant};

/// Counts, boundary loops and the main measures of a mesh, rounded for snapshots.
///
/// Every `f64` field holds its value rounded to [`SUMMARY_DIGITS`] significant digits
/// (see [`round_significant`]), so two summaries compare equal, print the same and
/// serialise the same when the meshes differ only in the last bits. Counts are exact.
/// `Display` prints one `key: value` line per field; `serde` gives the same fields.
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_testkit::MeshSummary;
///
/// let cube = primitives::cube();
/// let mesh = cube.mesh()?;
/// let summary = MeshSummary::new(&mesh, &cube.positions)?;
/// assert_eq!(summary.faces, 12);
/// assert_eq!(summary.volume, Some(1.0));
/// assert!(summary.to_string().contains("boundary loops: none"));
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshSummary {
    /// Number of vertices (isolated ones included).
    pub vertices: usize,
    /// Number of edges.
    pub edges: usize,
    /// Number of faces.
    pub faces: usize,
    /// Number of halfedges (twice the edges).
    pub halfedges: usize,
    /// Number of boundary halfedges (halfedges without a face).
    pub boundary_halfedges: usize,
    /// The length (in edges) of every boundary loop, longest first.
    pub boundary_loops: Vec<usize>,
    /// Number of connected components.
    pub components: usize,
    /// V − E + F.
    pub euler_characteristic: i64,
    /// The genus of a connected mesh (with or without boundary), `None` otherwise.
    pub genus: Option<u32>,
    /// Lower corner of the bounding box (rounded).
    pub bbox_min: [f64; 3],
    /// Upper corner of the bounding box (rounded).
    pub bbox_max: [f64; 3],
    /// Length of the bounding-box diagonal (rounded).
    pub bbox_diagonal: f64,
    /// Total face area (rounded).
    pub surface_area: f64,
    /// Enclosed volume of a closed mesh (rounded), `None` for an open one.
    pub volume: Option<f64>,
    /// Mean edge length (rounded), `None` without edges.
    pub mean_edge_length: Option<f64>,
}

fn round(x: f64) -> f64 {
    round_significant(x, SUMMARY_DIGITS)
}

fn round3(v: DVec3) -> [f64; 3] {
    [round(v.x), round(v.y), round(v.z)]
}

impl MeshSummary {
    /// Summarises `mesh` with vertex positions `positions`.
    ///
    /// # Errors
    /// [`TopologyError::PositionCount`] when `positions` does not have one entry per
    /// vertex.
    ///
    /// # Complexity
    /// O(V + H).
    pub fn new(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<Self, TopologyError> {
        let geometry = Geometry::new(mesh, positions)?;
        let mut boundary_loops: Vec<usize> = mesh.boundary_loops().map(|l| l.len()).collect();
        boundary_loops.sort_unstable_by(|a, b| b.cmp(a));
        let components = mesh.connected_components();
        let genus = match components.summaries.as_slice() {
            [only] => only.genus(),
            _ => None,
        };
        let (lo, hi) = geometry
            .bounding_box()
            .unwrap_or((DVec3::ZERO, DVec3::ZERO));
        Ok(Self {
            vertices: mesh.n_vertices(),
            edges: mesh.n_edges(),
            faces: mesh.n_faces(),
            halfedges: mesh.n_halfedges(),
            boundary_halfedges: mesh.n_boundary_halfedges(),
            boundary_loops,
            components: components.count(),
            euler_characteristic: mesh.euler_characteristic(),
            genus,
            bbox_min: round3(lo),
            bbox_max: round3(hi),
            bbox_diagonal: round((hi - lo).length()),
            surface_area: round(geometry.surface_area()),
            volume: geometry.volume().ok().map(round),
            mean_edge_length: geometry.mean_edge_length().map(round),
        })
    }
}

fn fmt_num(x: f64) -> String {
    format_significant(x, SUMMARY_DIGITS)
}

fn fmt_point(p: [f64; 3]) -> String {
    format!("({}, {}, {})", fmt_num(p[0]), fmt_num(p[1]), fmt_num(p[2]))
}

impl fmt::Display for MeshSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "vertices: {}, edges: {}, faces: {}, halfedges: {}",
            self.vertices, self.edges, self.faces, self.halfedges
        )?;
        writeln!(f, "boundary halfedges: {}", self.boundary_halfedges)?;
        if self.boundary_loops.is_empty() {
            writeln!(f, "boundary loops: none")?;
        } else {
            let lengths: Vec<String> = self.boundary_loops.iter().map(|l| l.to_string()).collect();
            writeln!(
                f,
                "boundary loops: {} ({})",
                self.boundary_loops.len(),
                lengths.join(", ")
            )?;
        }
        let genus = self
            .genus
            .map_or_else(|| "-".to_string(), |g| g.to_string());
        writeln!(
            f,
            "components: {}, euler characteristic: {}, genus: {genus}",
            self.components, self.euler_characteristic
        )?;
        writeln!(
            f,
            "bounding box: {} .. {}",
            fmt_point(self.bbox_min),
            fmt_point(self.bbox_max)
        )?;
        writeln!(f, "bounding-box diagonal: {}", fmt_num(self.bbox_diagonal))?;
        writeln!(f, "surface area: {}", fmt_num(self.surface_area))?;
        match self.volume {
            Some(v) => writeln!(f, "volume: {}", fmt_num(v))?,
            None => writeln!(f, "volume: - (open)")?,
        }
        match self.mean_edge_length {
            Some(l) => writeln!(f, "mean edge length: {}", fmt_num(l)),
            None => writeln!(f, "mean edge length: -"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::primitives;

    #[test]
    fn the_summary_of_a_grid_is_what_the_grid_is() {
        let grid = primitives::grid(4, 3);
        let mesh = grid.mesh().unwrap();
        let s = MeshSummary::new(&mesh, &grid.positions).unwrap();
        assert_eq!((s.vertices, s.edges, s.faces), (20, 43, 24));
        assert_eq!(s.boundary_loops, [14]);
        assert_eq!(s.genus, Some(0));
        assert_eq!(s.bbox_diagonal, 5.0);
        assert_eq!(s.surface_area, 12.0);
        assert_eq!(s.volume, None);
    }

    #[test]
    fn last_bit_changes_do_not_change_the_summary() {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let nudged: Vec<DVec3> = sphere
            .positions
            .iter()
            .map(|p| {
                DVec3::new(
                    f64::from_bits(p.x.to_bits() ^ 1),
                    p.y,
                    f64::from_bits(p.z.to_bits() ^ 1),
                )
            })
            .collect();
        let a = MeshSummary::new(&mesh, &sphere.positions).unwrap();
        let b = MeshSummary::new(&mesh, &nudged).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.to_string(), b.to_string());
    }

    #[test]
    fn a_real_change_shows() {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let scaled: Vec<DVec3> = sphere.positions.iter().map(|p| *p * 1.001).collect();
        let a = MeshSummary::new(&mesh, &sphere.positions).unwrap();
        let b = MeshSummary::new(&mesh, &scaled).unwrap();
        assert_ne!(a.volume, b.volume);
        assert_ne!(a.to_string(), b.to_string());
    }

    #[test]
    fn the_wrong_number_of_positions_is_an_error() {
        let grid = primitives::grid(1, 1);
        let mesh = grid.mesh().unwrap();
        assert!(MeshSummary::new(&mesh, &grid.positions[..3]).is_err());
    }
}
