//! Counts, topology and geometry of a mesh in one record ([`MeshSummary`]), as
//! `beltrami info` prints them.

use glam::DVec3;

use super::Geometry;

/// Counts, topology and geometry of a mesh: what `beltrami info` and the Python
/// `beltrami.info` report. See [`Geometry::summary`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct MeshSummary {
    /// The number of vertices, isolated ones included.
    pub vertices: usize,
    /// The number of faces.
    pub faces: usize,
    /// The number of edges.
    pub edges: usize,
    /// Whether every face is a triangle.
    pub triangle_mesh: bool,
    /// The number of edges of each boundary loop, longest first.
    pub boundary_loop_lengths: Vec<usize>,
    /// The number of connected components (an isolated vertex is one).
    pub components: usize,
    /// The Euler characteristic `V − E + F`.
    pub euler_characteristic: i64,
    /// Whether the mesh has faces and no boundary.
    pub closed: bool,
    /// The genus of a connected mesh, open or closed (χ = 2 − 2g − b); `None` for several
    /// components (see [`component_genus`](Self::component_genus)) or a mesh without
    /// faces.
    pub genus: Option<u32>,
    /// The genus of each connected component, in the order of their lowest vertex;
    /// `None` for an isolated vertex.
    pub component_genus: Vec<Option<u32>>,
    /// The number of vertices in no edge.
    pub isolated_vertices: usize,
    /// The number of faces of zero area (see [`Geometry::is_degenerate_face`]).
    pub degenerate_faces: usize,
    /// The corners `(min, max)` of the axis-aligned bounding box; `None` without
    /// vertices.
    pub bounding_box: Option<(DVec3, DVec3)>,
    /// The mean edge length; `None` without edges.
    pub mean_edge_length: Option<f64>,
    /// The surface area, in unit². When the face areas overflow (coordinates beyond
    /// about 1e154) it is computed again at a power-of-two scale, so that `inf` means
    /// that the true area is beyond `f64`.
    pub area: f64,
    /// The enclosed volume of a closed mesh, in unit³; `None` for an open one.
    pub volume: Option<f64>,
}

impl Geometry<'_> {
    /// Counts, topology and geometry of the mesh in one record.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::primitives;
    /// let cube = primitives::cube();
    /// let mesh = cube.mesh()?;
    /// let summary = Geometry::new(&mesh, &cube.positions)?.summary();
    /// assert_eq!((summary.vertices, summary.faces, summary.genus), (8, 12, Some(0)));
    /// assert_eq!(summary.area, 6.0);
    /// assert!((summary.volume.unwrap() - 1.0).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub fn summary(&self) -> MeshSummary {
        let mesh = self.mesh();
        let mut boundary_loop_lengths: Vec<usize> =
            mesh.boundary_loops().map(|l| l.len()).collect();
        boundary_loop_lengths.sort_unstable_by(|a, b| b.cmp(a));
        let components = mesh.connected_components();
        let component_genus: Vec<Option<u32>> =
            components.summaries.iter().map(|c| c.genus()).collect();
        MeshSummary {
            vertices: mesh.n_vertices(),
            faces: mesh.n_faces(),
            edges: mesh.n_edges(),
            triangle_mesh: mesh.is_triangle_mesh(),
            boundary_loop_lengths,
            components: components.count(),
            euler_characteristic: mesh.euler_characteristic(),
            closed: mesh.n_faces() > 0 && mesh.is_closed(),
            genus: match component_genus.as_slice() {
                [only] => *only,
                _ => None,
            },
            component_genus,
            isolated_vertices: mesh.n_isolated_vertices(),
            degenerate_faces: mesh.faces().filter(|&f| self.is_degenerate_face(f)).count(),
            bounding_box: self.bounding_box(),
            mean_edge_length: self.mean_edge_length(),
            area: self.unscaled_surface_area(),
            // A mesh without faces has no boundary either, but encloses nothing.
            volume: self.volume().ok().filter(|_| mesh.n_faces() > 0),
        }
    }

    /// The surface area, computed again at a power-of-two scale when the face areas
    /// overflow, so that `inf` means that the true area is beyond `f64`.
    fn unscaled_surface_area(&self) -> f64 {
        let area = self.surface_area();
        if area.is_finite() {
            return area;
        }
        let positions = self.positions();
        let largest = positions
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0f64, f64::max);
        if !largest.is_finite() || largest == 0.0 {
            return area;
        }
        // 2^-k with 2^k near the largest coordinate: exact scaling, areas scale by 4^-k.
        let k = largest.log2().ceil();
        let scale = (-k).exp2();
        let scaled: Vec<DVec3> = positions.iter().map(|p| *p * scale).collect();
        match Geometry::new(self.mesh(), &scaled) {
            Ok(g) => g.surface_area() * (2.0 * k).exp2(),
            Err(_) => area,
        }
    }
}
