//! The valence bookkeeping of the edge flips towards valence 6 that remeshing and
//! decimation share.

use beltrami_halfedge::{EditMesh, VertexId};

/// How an edge flip changes the valences of its quad `[v0, v1, a, b]`: the edge leaves
/// `v0` and `v1` and joins `a` and `b`.
const FLIP_CHANGE: [i64; 4] = [-1, -1, 1, 1];

/// Each vertex's valence, kept up to date through the flips made.
pub(crate) struct Valences(Vec<i64>);

impl Valences {
    /// The valences of `mesh`'s live vertices.
    pub(crate) fn new(mesh: &EditMesh) -> Self {
        let mut valence = vec![0i64; mesh.vertex_capacity()];
        for v in mesh.vertices() {
            valence[v.index()] = mesh.valence(v) as i64;
        }
        Self(valence)
    }

    /// Whether flipping the edge `v0 v1` of the quad `[v0, v1, a, b]` lowers
    /// `Σ (valence − optimal)²` over its four vertices, the optimal valence being 6
    /// inside and 4 on the boundary (Botsch and Kobbelt's flip rule, pmp-library's
    /// `Remeshing::flip_edges`).
    pub(crate) fn flip_improves(&self, mesh: &EditMesh, quad: [VertexId; 4]) -> bool {
        let (mut before, mut after) = (0, 0);
        for (&v, d) in quad.iter().zip(FLIP_CHANGE) {
            let optimal = if mesh.is_boundary_vertex(v) { 4 } else { 6 };
            let off = self.0[v.index()] - optimal;
            before += off * off;
            after += (off + d) * (off + d);
        }
        after < before
    }

    /// Records the flip of the edge `v0 v1` of the quad `[v0, v1, a, b]`.
    pub(crate) fn flipped(&mut self, quad: [VertexId; 4]) {
        for (&v, d) in quad.iter().zip(FLIP_CHANGE) {
            self.0[v.index()] += d;
        }
    }
}
