//! Uniform subdivision of triangle meshes: [`loop_subdivide`] and [`sqrt3_subdivide`].
//!
//! Each step builds the finer mesh directly from the coarse one; nothing is edited in
//! place, so the coarse mesh stays usable and the result does not depend on an order of
//! edits. A Loop step takes the refined connectivity from
//! [`HalfedgeMesh::split_triangles`], which writes it in closed form (every coarse edge
//! becomes two edges, every face three interior edges and four faces): O(n), no sorting
//! or hashing, in parallel, valid by construction. The arrays are exactly those
//! [`HalfedgeMesh::from_polygons`] makes of the step's face list (same edge numbering,
//! halfedge directions, outgoing halfedges and face halfedges), which a test checks. A √3 step computes its face list and builds it with
//! [`HalfedgeMesh::from_polygons`] (O(C log C) for C corners).
//!
//! Conventions shared by both schemes:
//! - positions are `f64` in the units of the input; subdivision is affine, so the
//!   result is in the same units and moves with the input under any affine map;
//! - the old vertices keep their ids (`0..n_vertices`) and the new ones are appended,
//!   numbered as the scheme's documentation says;
//! - isolated vertices are kept where they are;
//! - the output depends only on the input: the position pass runs on rayon's threads,
//!   but every position is computed by one thread in a fixed order of operations, so
//!   the result is bit-identical on one thread or many.

use beltrami_halfedge::{EdgeId, FaceId, HalfedgeMesh, MAX_ELEMENTS, VertexId};
use glam::DVec3;

use crate::error::SubdivisionError;

mod r#loop;
mod sqrt3;

pub use r#loop::loop_subdivide;
pub use sqrt3::sqrt3_subdivide;

/// A subdivision scheme, chosen at run time (for example by a command-line option).
///
/// # Examples
/// ```
/// use beltrami_algorithms::Scheme;
/// use beltrami_halfedge::primitives;
///
/// let grid = primitives::grid(4, 3);
/// let mesh = grid.mesh()?;
/// let scheme = Scheme::from_name("sqrt3").unwrap();
/// let counts = scheme.counts(&mesh, 2);
/// let (fine, _) = scheme.subdivide(&mesh, &grid.positions, 2)?;
/// assert_eq!(counts.vertices, fine.n_vertices() as u64);
/// assert_eq!(counts.faces, fine.n_faces() as u64);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Scheme {
    /// Loop subdivision, [`loop_subdivide`]: every triangle becomes four.
    Loop,
    /// √3 subdivision, [`sqrt3_subdivide`]: every triangle becomes three.
    Sqrt3,
}

impl Scheme {
    /// Every scheme, in the order of their names in [`Scheme::name`].
    pub const ALL: [Scheme; 2] = [Scheme::Loop, Scheme::Sqrt3];

    /// The scheme's name: `"loop"` or `"sqrt3"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Loop => "loop",
            Scheme::Sqrt3 => "sqrt3",
        }
    }

    /// The scheme named `name` ([`Scheme::name`]), if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Subdivides with this scheme: [`loop_subdivide`] or [`sqrt3_subdivide`].
    ///
    /// # Errors
    /// As the scheme's function.
    pub fn subdivide(
        self,
        mesh: &HalfedgeMesh,
        positions: &[DVec3],
        steps: usize,
    ) -> Result<(HalfedgeMesh, Vec<DVec3>), SubdivisionError> {
        match self {
            Scheme::Loop => loop_subdivide(mesh, positions, steps),
            Scheme::Sqrt3 => sqrt3_subdivide(mesh, positions, steps),
        }
    }

    /// Bytes a run holds at its peak per face of its result: the subdivided positions
    /// and connectivity, the builder's sorted corners, the face list and a written copy,
    /// with the coarse mesh beside them. Measured peaks, less the process's base: about
    /// 200 bytes per face of a Loop result and 220 of a √3 result
    /// (`docs/subdivision.md`).
    pub const BYTES_PER_FACE: u64 = 256;

    /// Whether `steps` steps on `mesh` make a mesh within the element limits and, when
    /// `budget` (bytes) is given, within it: [`Scheme::bytes_needed`] with `base` bytes
    /// (the process's own) added.
    #[must_use]
    pub fn fits(self, mesh: &HalfedgeMesh, steps: usize, budget: Option<u64>, base: u64) -> bool {
        let c = self.counts(mesh, steps);
        let max = MAX_ELEMENTS as u64;
        let elements = c.vertices <= max && c.halfedges() <= max && c.faces <= max;
        elements && budget.is_none_or(|b| Self::bytes_needed(c.faces, base) <= b)
    }

    /// The memory a run making `faces` faces needs, in bytes:
    /// [`Scheme::BYTES_PER_FACE`] per face plus `base` (saturated at `u64::MAX`).
    #[must_use]
    pub fn bytes_needed(faces: u64, base: u64) -> u64 {
        faces
            .saturating_mul(Self::BYTES_PER_FACE)
            .saturating_add(base)
    }

    /// The most steps, up to `steps`, that [`fit`](Self::fits) (0 when none does):
    /// results only grow with the steps, so the first that does not fit ends the search.
    #[must_use]
    pub fn most_steps_that_fit(
        self,
        mesh: &HalfedgeMesh,
        steps: usize,
        budget: Option<u64>,
        base: u64,
    ) -> usize {
        (1..=steps)
            .take_while(|&s| self.fits(mesh, s, budget, base))
            .last()
            .unwrap_or(0)
    }

    /// The element counts after `steps` steps of this scheme, computed from the counts
    /// alone (nothing is subdivided), saturating at `u64::MAX`. Exact for a triangle
    /// mesh: the counts of [`subdivide`](Self::subdivide)'s result are these.
    ///
    /// Loop: `V + E` vertices, `2E + 3F` edges, `4F` faces, twice the boundary edges.
    /// √3, even step (the first, third, …): `V + F` vertices, `E + 3F` edges, `3F`
    /// faces, the same boundary edges; odd step: each boundary edge gains two vertices
    /// and every face without a boundary edge one, `E + 3F + B` edges, `3F` faces,
    /// three times the `B` boundary edges.
    ///
    /// # Complexity
    /// O(H) for the boundary count, then O(steps), ending early once the counts stop
    /// changing (saturated, or a mesh without faces).
    #[must_use]
    pub fn counts(self, mesh: &HalfedgeMesh, steps: usize) -> MeshCounts {
        let mut c = MeshCounts::of(mesh);
        for step in 0..steps {
            let next = match self {
                Scheme::Loop => MeshCounts {
                    vertices: c.vertices.saturating_add(c.edges),
                    edges: c
                        .edges
                        .saturating_mul(2)
                        .saturating_add(c.faces.saturating_mul(3)),
                    faces: c.faces.saturating_mul(4),
                    boundary_edges: c.boundary_edges.saturating_mul(2),
                },
                Scheme::Sqrt3 if step % 2 == 0 => MeshCounts {
                    vertices: c.vertices.saturating_add(c.faces),
                    edges: c.edges.saturating_add(c.faces.saturating_mul(3)),
                    faces: c.faces.saturating_mul(3),
                    boundary_edges: c.boundary_edges,
                },
                // After an even step every boundary face has exactly one boundary edge,
                // so B faces are split along their boundary edge and F - B get a
                // centre.
                Scheme::Sqrt3 => MeshCounts {
                    vertices: c
                        .vertices
                        .saturating_add(c.boundary_edges)
                        .saturating_add(c.faces),
                    edges: c
                        .edges
                        .saturating_add(c.faces.saturating_mul(3))
                        .saturating_add(c.boundary_edges),
                    faces: c.faces.saturating_mul(3),
                    boundary_edges: c.boundary_edges.saturating_mul(3),
                },
            };
            // Counts that no longer change (no faces, or saturated) stay so under the
            // following steps (of a saturated √3 result only the boundary count could
            // still grow, and such a result is refused in any case): a huge `steps`
            // ends here.
            if next == c {
                break;
            }
            c = next;
        }
        c
    }
}

impl std::fmt::Display for Scheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Element counts of a mesh, as [`Scheme::counts`] predicts them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshCounts {
    /// Vertices, isolated ones included.
    pub vertices: u64,
    /// Edges.
    pub edges: u64,
    /// Faces.
    pub faces: u64,
    /// Boundary edges (edges with one face).
    pub boundary_edges: u64,
}

impl MeshCounts {
    /// The counts of `mesh`.
    #[must_use]
    pub fn of(mesh: &HalfedgeMesh) -> Self {
        Self {
            vertices: mesh.n_vertices() as u64,
            edges: mesh.n_edges() as u64,
            faces: mesh.n_faces() as u64,
            boundary_edges: mesh.n_boundary_halfedges() as u64,
        }
    }

    /// Halfedges: twice the edges (saturating).
    #[must_use]
    pub fn halfedges(&self) -> u64 {
        self.edges.saturating_mul(2)
    }
}

/// Checks what both schemes need before any work: one position per vertex, triangles
/// only, and a result that fits in a mesh.
pub(crate) fn check_input(
    scheme: Scheme,
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    steps: usize,
) -> Result<(), SubdivisionError> {
    if positions.len() != mesh.n_vertices() {
        return Err(SubdivisionError::PositionCount {
            positions: positions.len(),
            vertices: mesh.n_vertices(),
        });
    }
    if !mesh.is_triangle_mesh() {
        let (face, len) = mesh
            .faces()
            .map(|f| (f.index(), mesh.face_valence(f)))
            .find(|&(_, len)| len != 3)
            .unwrap_or((0, 0));
        return Err(SubdivisionError::NotTriangle { face, len });
    }
    let counts = scheme.counts(mesh, steps);
    for (kind, count) in [
        ("vertices", counts.vertices),
        ("halfedges", counts.halfedges()),
        ("faces", counts.faces),
    ] {
        if count > MAX_ELEMENTS as u64 {
            return Err(SubdivisionError::TooLarge {
                scheme: scheme.name(),
                steps,
                kind,
                count,
                max: MAX_ELEMENTS,
            });
        }
    }
    Ok(())
}

/// Builds the subdivided connectivity from its triangles.
pub(crate) fn build(
    n_vertices: usize,
    triangles: &[[u32; 3]],
) -> Result<HalfedgeMesh, SubdivisionError> {
    Ok(HalfedgeMesh::from_polygons(n_vertices, triangles)?)
}

/// The id of vertex `i` (checked to fit by [`check_input`]).
#[inline]
pub(crate) fn vertex(i: usize) -> VertexId {
    VertexId::new(i as u32)
}

/// The id of edge `i`.
#[inline]
pub(crate) fn edge(i: usize) -> EdgeId {
    EdgeId::new(i as u32)
}

/// The id of face `i`.
#[inline]
pub(crate) fn face(i: usize) -> FaceId {
    FaceId::new(i as u32)
}

/// The sum of the one-ring of the interior vertex `v`, clockwise from its outgoing
/// halfedge (the order of OpenMesh's vertex-vertex circulator), and the valence.
pub(crate) fn ring_sum(mesh: &HalfedgeMesh, p: &[DVec3], v: VertexId) -> (DVec3, usize) {
    let mut sum = DVec3::ZERO;
    let mut valence = 0;
    if let Some(start) = mesh.outgoing_halfedge(v) {
        let mut h = start;
        loop {
            sum += p[mesh.to_vertex(h).index()];
            valence += 1;
            h = mesh.cw_rotated(h);
            if h == start {
                break;
            }
        }
    }
    (sum, valence)
}

/// The two boundary neighbours of the boundary vertex `v`: the target of its outgoing
/// boundary halfedge and the source of the boundary halfedge before it.
pub(crate) fn boundary_neighbours(
    mesh: &HalfedgeMesh,
    v: VertexId,
) -> Option<(VertexId, VertexId)> {
    let out = mesh.outgoing_halfedge(v)?;
    let next = mesh.to_vertex(out);
    let prev = mesh.from_vertex(mesh.prev(out));
    Some((next, prev))
}
