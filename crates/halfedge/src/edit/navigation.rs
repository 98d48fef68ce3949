//! Reading an [`EditMesh`]: links, status queries and counter-clockwise circulators,
//! named as on [`HalfedgeMesh`](crate::HalfedgeMesh).

use std::iter::FusedIterator;

use super::storage::EditMesh;
use crate::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};

/// The live elements of one kind, in index order. See [`EditMesh::vertices`].
#[derive(Clone, Debug)]
pub struct LiveElements<'a, I> {
    deleted: &'a [bool],
    cursor: usize,
    _kind: std::marker::PhantomData<I>,
}

impl<I: ElementId> Iterator for LiveElements<'_, I> {
    type Item = I;
    fn next(&mut self) -> Option<I> {
        while self.cursor < self.deleted.len() {
            let i = self.cursor;
            self.cursor += 1;
            if !self.deleted[i] {
                return Some(I::from_index(i));
            }
        }
        None
    }
}
impl<I: ElementId> FusedIterator for LiveElements<'_, I> {}

/// Outgoing halfedges of a vertex of an [`EditMesh`], counter-clockwise. See
/// [`EditMesh::halfedges_around_vertex`].
pub type HalfedgesAroundVertex<'a> = crate::circulators::HalfedgesAroundVertex<'a, EditMesh>;

/// Halfedges of a face or boundary loop of an [`EditMesh`], following `next`. See
/// [`EditMesh::halfedges_around_face`].
pub type HalfedgesAroundFace<'a> = crate::circulators::HalfedgesAroundFace<'a, EditMesh>;

crate::circulators::navigation!(
    EditMesh,
    outgoing: "An outgoing halfedge of `v`, `None` for an isolated vertex; a boundary halfedge \
               whenever `v` is on the boundary.",
    face_halfedge: "One halfedge of face `f`."
);

impl EditMesh {
    /// The live vertices in index order.
    #[must_use]
    pub fn vertices(&self) -> LiveElements<'_, VertexId> {
        live(&self.v_deleted)
    }

    /// The live edges in index order.
    #[must_use]
    pub fn edges(&self) -> LiveElements<'_, EdgeId> {
        live(&self.e_deleted)
    }

    /// The live halfedges in index order.
    pub fn halfedges(&self) -> impl Iterator<Item = HalfedgeId> + '_ {
        self.edges().flat_map(EdgeId::halfedges)
    }

    /// The live faces in index order.
    #[must_use]
    pub fn faces(&self) -> LiveElements<'_, FaceId> {
        live(&self.f_deleted)
    }

    /// Whether the live mesh has no boundary halfedge.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.halfedges().all(|h| !self.is_boundary_halfedge(h))
    }

    /// The live faces as vertex lists, counter-clockwise, in face index order.
    #[must_use]
    pub fn face_vertex_lists(&self) -> Vec<Vec<VertexId>> {
        self.faces()
            .map(|f| self.vertices_around_face(f).collect())
            .collect()
    }
}

fn live<I>(deleted: &[bool]) -> LiveElements<'_, I> {
    LiveElements {
        deleted,
        cursor: 0,
        _kind: std::marker::PhantomData,
    }
}
