//! Graph distance from the boundary (ring index) and a per-vertex error per ring.

use std::collections::VecDeque;

use beltrami_halfedge::{EdgeId, HalfedgeMesh, VertexId, VertexMap, VerticesAroundVertex};
use petgraph::visit::{Bfs, GraphBase, GraphRef, IntoNeighbors, VisitMap, Visitable};

use crate::MetricsError;

/// The statistics of a per-vertex error over the vertices of one ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingError {
    /// The ring index: the number of edges from the boundary.
    pub ring: u32,
    /// The number of vertices on the ring (at least 1).
    pub count: usize,
    /// The mean of the error (signed), in the error's unit.
    pub mean: f64,
    /// The root mean square of the error, `sqrt(Σ e² / count)`.
    pub rms: f64,
    /// The largest absolute error, `max |e|`.
    pub max: f64,
}

/// A per-vertex error against the graph distance from the boundary: one entry per ring,
/// ring 0 (the boundary) first, up to the deepest ring. See [`error_by_ring`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RingProfile {
    /// One entry per ring index `0, 1, …, r_max`, in that order. Every ring has at least
    /// one vertex. Empty when the mesh has no boundary.
    pub rings: Vec<RingError>,
    /// The number of vertices without a ring index: isolated vertices, and the vertices of
    /// components without a boundary (all vertices of a closed mesh).
    pub unreached: usize,
}

/// The ring index of every vertex: the number of edges on a shortest edge path from the
/// vertex to a boundary vertex (0 on the boundary, 1 for their other neighbours, …).
///
/// `None` for vertices that cannot reach the boundary: isolated vertices and all vertices
/// of a component without boundary (so every vertex of a closed mesh).
///
/// The distance is combinatorial (edges, not length): on a regular mesh it counts rows of
/// vertices, which is how far an explicit smoother's stencil carries boundary effects per
/// iteration.
///
/// # Complexity
/// O(V + H): one multi-source breadth-first search from all boundary vertices, run by
/// petgraph's [`Bfs`] over the half-edge connectivity (no graph is copied).
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, VertexId};
/// use beltrami_metrics::distortion::boundary_rings;
///
/// let grid = primitives::grid(4, 2);
/// let rings = boundary_rings(&grid.mesh()?);
/// // Vertex (i, j) has index 5 j + i; only the middle row is inside.
/// assert_eq!(rings[VertexId::new(6)], Some(1));
/// assert_eq!(rings[VertexId::new(0)], Some(0));
///
/// let closed = primitives::cube().mesh()?;
/// assert!(boundary_rings(&closed).as_slice().iter().all(Option::is_none));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn boundary_rings(mesh: &HalfedgeMesh) -> VertexMap<Option<u32>> {
    let mut rings: VertexMap<Option<u32>> = mesh.vertex_map(None);
    let sources: VecDeque<VertexId> = mesh
        .vertices()
        .filter(|&v| {
            mesh.outgoing_halfedge(v)
                .is_some_and(|h| mesh.is_boundary_halfedge(h))
        })
        .collect();
    let graph = VertexGraph(mesh);
    let mut discovered = graph.visit_map();
    for &v in &sources {
        discovered.visit(v);
        rings[v] = Some(0);
    }
    // A multi-source search: all boundary vertices start in the queue, as discovered.
    let mut bfs = Bfs {
        stack: sources,
        discovered,
    };
    // The search pops vertices in order of non-decreasing distance, so when an interior
    // vertex is popped the neighbour that discovered it (one ring closer) already has its
    // ring, and no neighbour has a smaller one.
    while let Some(v) = bfs.next(graph) {
        if rings[v].is_none() {
            rings[v] = mesh
                .vertices_around_vertex(v)
                .filter_map(|w| rings[w])
                .min()
                .map(|r| r + 1);
        }
    }
    rings
}

/// The RMS and maximum of a per-vertex error on every ring of vertices at the same graph
/// distance from the boundary (see [`boundary_rings`]); this shows how far boundary
/// distortion reaches into the surface.
///
/// `error[v]` is any per-vertex error the caller chooses, e.g. the distance of the
/// smoothed vertex to the reference surface, or its displacement. On ring `r` with vertex
/// set `R`: `mean = Σ e / |R|`, `rms = sqrt(Σ e² / |R|)`, `max = max |e|`.
///
/// A mesh without boundary (closed) gives an empty profile with every vertex
/// [`unreached`](RingProfile::unreached); this is not an error.
///
/// # Errors
/// - [`MetricsError::FieldLength`] when `error` does not have one value per vertex;
/// - [`MetricsError::NonFinite`] with `what = "per-vertex error"` for a NaN or infinite
///   value.
///
/// # Complexity
/// O(V + H).
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::distortion::error_by_ring;
///
/// let grid = primitives::grid(4, 4);
/// let mesh = grid.mesh()?;
/// // An error that decays inwards: 1 on the border, 0.5 one ring in, 0 at the centre.
/// let error: Vec<f64> = grid.positions.iter().map(|p| {
///     let r = p.x.min(p.y).min(4.0 - p.x).min(4.0 - p.y);
///     1.0 - 0.5 * r
/// }).collect();
/// let profile = error_by_ring(&mesh, &error)?;
/// assert_eq!(profile.rings.len(), 3);
/// assert_eq!((profile.rings[0].count, profile.rings[0].max), (16, 1.0));
/// assert_eq!((profile.rings[1].count, profile.rings[1].rms), (8, 0.5));
/// assert_eq!((profile.rings[2].count, profile.rings[2].max), (1, 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn error_by_ring(mesh: &HalfedgeMesh, error: &[f64]) -> Result<RingProfile, MetricsError> {
    if error.len() != mesh.n_vertices() {
        return Err(MetricsError::FieldLength {
            what: "per-vertex error",
            got: error.len(),
            expected: mesh.n_vertices(),
        });
    }
    if let Some(index) = error.iter().position(|e| !e.is_finite()) {
        return Err(MetricsError::NonFinite {
            what: "per-vertex error",
            index,
        });
    }
    let rings = boundary_rings(mesh);
    let depth = rings
        .as_slice()
        .iter()
        .flatten()
        .max()
        .map_or(0, |&r| r as usize + 1);
    // Per ring: count, Σ e, Σ e², max |e|.
    let mut acc = vec![(0usize, 0.0f64, 0.0f64, 0.0f64); depth];
    let mut unreached = 0;
    for (ring, &e) in rings.as_slice().iter().zip(error) {
        match ring {
            Some(r) => {
                let a = &mut acc[*r as usize];
                a.0 += 1;
                a.1 += e;
                a.2 += e * e;
                a.3 = a.3.max(e.abs());
            }
            None => unreached += 1,
        }
    }
    let rings = acc
        .into_iter()
        .zip(0u32..)
        .map(|((count, sum, sum_sq, max), ring)| {
            // Breadth-first layers are contiguous, so every ring up to the deepest has a
            // vertex; `max(1)` only guards the division.
            let n = count.max(1) as f64;
            RingError {
                ring,
                count,
                mean: sum / n,
                rms: (sum_sq / n).sqrt(),
                max,
            }
        })
        .collect();
    Ok(RingProfile { rings, unreached })
}

/// The vertex–edge graph of a half-edge mesh, seen through petgraph's visitor traits:
/// nodes are vertices, neighbours come from the one-ring circulator. Nothing is copied.
#[derive(Clone, Copy)]
struct VertexGraph<'a>(&'a HalfedgeMesh);

impl GraphBase for VertexGraph<'_> {
    type EdgeId = EdgeId;
    type NodeId = VertexId;
}

impl GraphRef for VertexGraph<'_> {}

impl<'a> IntoNeighbors for VertexGraph<'a> {
    type Neighbors = VerticesAroundVertex<'a>;

    fn neighbors(self, v: VertexId) -> VerticesAroundVertex<'a> {
        self.0.vertices_around_vertex(v)
    }
}

impl Visitable for VertexGraph<'_> {
    type Map = Discovered;

    fn visit_map(&self) -> Discovered {
        Discovered(vec![false; self.0.n_vertices()])
    }

    fn reset_map(&self, map: &mut Discovered) {
        map.0.clear();
        map.0.resize(self.0.n_vertices(), false);
    }
}

/// One flag per vertex: discovered by the search or not.
struct Discovered(Vec<bool>);

impl VisitMap<VertexId> for Discovered {
    fn visit(&mut self, v: VertexId) -> bool {
        !std::mem::replace(&mut self.0[v.index()], true)
    }

    fn is_visited(&self, v: &VertexId) -> bool {
        self.0[v.index()]
    }

    fn unvisit(&mut self, v: VertexId) -> bool {
        std::mem::replace(&mut self.0[v.index()], false)
    }
}
