//! The valence bookkeeping of the edge flips towards valence 6 that remeshing and
//! decimation share.

use beltrami_halfedge::{EditMesh, VertexId};

/// How an edge flip changes the valences of its quad `[v0, v1, a, b]`: the edge leaves
/// `v0` and `v1` and joins `a` and `b`.
const FLIP_CHANGE: [i64; 4] = [-1, -1, 1, 1];

/// The valence a vertex of a regular triangulation has: 6 inside, 4 on the boundary.
fn optimal_valence(mesh: &EditMesh, v: VertexId) -> i64 {
    if mesh.is_boundary_vertex(v) { 4 } else { 6 }
}

/// Each vertex's valence less its optimum (6 inside, 4 on the boundary), kept up to date
/// through the flips made. A flip of an interior edge changes no vertex's boundary
/// status, so the optimum is looked up once.
pub(crate) struct Valences(Vec<i64>);

impl Valences {
    /// The valences of `mesh`'s live vertices, less their optimum.
    pub(crate) fn new(mesh: &EditMesh) -> Self {
        let mut off = vec![0i64; mesh.vertex_capacity()];
        for v in mesh.vertices() {
            off[v.index()] = mesh.valence(v) as i64 - optimal_valence(mesh, v);
        }
        Self(off)
    }

    /// Whether flipping the edge `v0 v1` of the quad `[v0, v1, a, b]` lowers
    /// `Σ (valence − optimal)²` over its four vertices, the optimal valence being 6
    /// inside and 4 on the boundary (Botsch and Kobbelt's flip rule, pmp-library's
    /// `Remeshing::flip_edges`).
    pub(crate) fn flip_improves(&self, quad: [VertexId; 4]) -> bool {
        let (before, after) = self.flip_deviation(quad);
        after < before
    }

    /// Whether flipping the edge `v0 v1` of the quad leaves `Σ (valence − optimal)²`
    /// over its four vertices unchanged (the flip moves a 5–7 pair by one edge).
    pub(crate) fn flip_keeps(&self, quad: [VertexId; 4]) -> bool {
        let (before, after) = self.flip_deviation(quad);
        after == before
    }

    /// `Σ (valence − optimal)²` over the quad before and after flipping its edge.
    fn flip_deviation(&self, quad: [VertexId; 4]) -> (i64, i64) {
        let (mut before, mut after) = (0, 0);
        for (&v, d) in quad.iter().zip(FLIP_CHANGE) {
            let off = self.0[v.index()];
            before += off * off;
            after += (off + d) * (off + d);
        }
        (before, after)
    }

    /// Undoes [`flipped`](Self::flipped) for a flip made and undone.
    pub(crate) fn unflipped(&mut self, quad: [VertexId; 4]) {
        for (&v, d) in quad.iter().zip(FLIP_CHANGE) {
            self.0[v.index()] -= d;
        }
    }

    /// Records the flip of the edge `v0 v1` of the quad `[v0, v1, a, b]`.
    pub(crate) fn flipped(&mut self, quad: [VertexId; 4]) {
        for (&v, d) in quad.iter().zip(FLIP_CHANGE) {
            self.0[v.index()] += d;
        }
    }
}

/// Whether collapsing the interior edge `h` (both of its end points interior) into one
/// vertex keeps the valences near 6: the merged vertex (the end points' valences less
/// four) and the two vertices opposite the edge (one less each) end within one of their
/// optimum, and `Σ (valence − optimal)²` over the edge's end points and those two does
/// not grow (the optimum as in [`Valences::flip_improves`]). `false` for a boundary edge.
pub(crate) fn collapse_keeps_valences(mesh: &EditMesh, h: beltrami_halfedge::HalfedgeId) -> bool {
    let (Some(a), Some(b)) = (mesh.opposite_vertex(h), mesh.opposite_vertex(h.twin())) else {
        return false;
    };
    let valence = |v: VertexId| mesh.valence(v) as i64;
    let off = |v: VertexId, change: i64| {
        let d = valence(v) + change - optimal_valence(mesh, v);
        d * d
    };
    let (v0, v1) = (mesh.from_vertex(h), mesh.to_vertex(h));
    let before = off(v0, 0) + off(v1, 0) + off(a, 0) + off(b, 0);
    let merged = valence(v0) + valence(v1) - 4 - 6;
    let (a_after, b_after) = (off(a, -1), off(b, -1));
    let near = merged * merged <= 1 && a_after <= 1 && b_after <= 1;
    near && merged * merged + a_after + b_after <= before
}
