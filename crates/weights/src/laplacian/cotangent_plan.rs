//! The cotangent kernel's per-face data: each triangle's cotangents once per refresh,
//! gathered into the row slots.

use beltrami_halfedge::geometry::{BLOCK, blocked_index, triangle_cotangents_blocked_into};
use beltrami_halfedge::{DVec3, FaceId, HalfedgeMesh, VertexId};
use rayon::prelude::*;

use super::layout::slot_values;
use crate::PAR_CHUNK;

/// The cotangent kernel's per-face data: cotangents are computed once per triangle,
/// in parallel, into `face_cots` (in blocks of [`BLOCK`] triangles, see
/// [`blocked_index`]), then every row slot gathers its two.
#[derive(Clone, Debug)]
pub(super) struct CotangentPlan {
    /// Vertex ids of each triangle in face order, triangles sorted by their smallest
    /// vertex id (so that a chunk of triangles reads nearby positions).
    pub(super) triangles: Vec<[VertexId; 3]>,
    /// Per row slot (halfedge `h`), the indices in `face_cots` of the cotangents
    /// opposite `h` and opposite its twin ([`blocked_index`]); the index of the trailing
    /// 0 (`3 × BLOCK × ⌈triangles / BLOCK⌉`) for a boundary halfedge or a face that is
    /// not a triangle.
    pub(super) slot_cots: Vec<[u32; 2]>,
    /// The three cotangents of each triangle (opposite the halfedges ending at its
    /// first, second and third vertex), in blocks of [`BLOCK`] triangles, then one 0.
    pub(super) face_cots: Vec<f64>,
}

/// Triangles per parallel work unit of the cotangent kernel, at most.
const FACE_CHUNK: usize = 4096;

/// Triangles per parallel work unit of the cotangent kernel over `n` triangles:
/// [`FACE_CHUNK`], or on a mesh too small for four of them per thread, a quarter of each
/// thread's share (at least 256), so that a small mesh's triangles are shared by the
/// threads; a multiple of [`BLOCK`], so that the chunks are whole blocks of the table.
/// Each triangle's cotangents are computed alone, so the chunks change no bit.
fn face_chunk(n: usize) -> usize {
    n.div_ceil(4 * rayon::current_num_threads().max(1))
        .clamp(256, FACE_CHUNK)
        .next_multiple_of(BLOCK)
}

impl CotangentPlan {
    /// The plan for `mesh` with rows at `offsets` (each row's outgoing halfedges
    /// counter-clockwise), or `None` when the indices do not fit in `u32`.
    pub(super) fn new(mesh: &HalfedgeMesh, offsets: &[u32]) -> Option<Self> {
        let n_faces = mesh.n_faces();
        u32::try_from(3 * n_faces).ok()?;
        // Each triangle's smallest vertex id (the sort key), in parallel; `u32::MAX` for
        // a face that is not a triangle. (A key per face, 4 bytes, rather than its three
        // vertices: the vertices are read again from the mesh when the triangle is
        // placed, which keeps the mesh's own memory the largest thing held.)
        let keys: Vec<u32> = (0..n_faces)
            .into_par_iter()
            .with_min_len(PAR_CHUNK)
            .map(|f| {
                let h0 = mesh.face_halfedge(FaceId::new(f as u32));
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                if mesh.next(h2) == h0 {
                    let [a, b, c] = [h0, h1, h2].map(|h| mesh.to_vertex(h).raw());
                    a.min(b).min(c)
                } else {
                    u32::MAX
                }
            })
            .collect();
        // Triangles by their smallest vertex id (a counting sort: stable, O(F + V)).
        let mut counts = vec![0u32; mesh.n_vertices() + 1];
        for &k in keys.iter().filter(|&&k| k != u32::MAX) {
            counts[k as usize + 1] += 1;
        }
        for i in 1..counts.len() {
            counts[i] += counts[i - 1];
        }
        let n_triangles = counts[mesh.n_vertices()] as usize;
        let n_cots = 3 * BLOCK * n_triangles.div_ceil(BLOCK);
        let sentinel = u32::try_from(n_cots).ok()?;
        let mut triangles = vec![[VertexId::new(0); 3]; n_triangles];
        // Where the cotangent opposite each halfedge lands in `face_cots` (the sentinel
        // for a boundary halfedge or a face that is not a triangle): triangle `p`'s
        // halfedges in face order take `blocked_index(p, 0..3)`.
        let mut cot_of = vec![sentinel; mesh.n_halfedges()];
        for (f, &k) in keys.iter().enumerate() {
            if k != u32::MAX {
                let slot = &mut counts[k as usize];
                let p = *slot;
                *slot += 1;
                let h0 = mesh.face_halfedge(FaceId::new(f as u32));
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                triangles[p as usize] = [h0, h1, h2].map(|h| mesh.to_vertex(h));
                let at = |k| blocked_index(p as usize, k) as u32;
                cot_of[h0.index()] = at(0);
                cot_of[h1.index()] = at(1);
                cot_of[h2.index()] = at(2);
            }
        }
        drop(keys);
        let slot_cots: Vec<[u32; 2]> = slot_values(mesh, offsets, |h| {
            [cot_of[h.index()], cot_of[h.twin().index()]]
        });
        // Freed before the cotangent table is made: the two are never held together.
        drop(cot_of);
        Some(Self {
            triangles,
            slot_cots,
            face_cots: vec![0.0; n_cots + 1],
        })
    }

    /// The bytes of heap memory the plan holds (the capacities of its arrays).
    pub(super) fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        size_of::<[VertexId; 3]>() * self.triangles.capacity()
            + size_of::<[u32; 2]>() * self.slot_cots.capacity()
            + size_of::<f64>() * self.face_cots.capacity()
    }

    /// Recomputes `face_cots` from the positions (in parallel; each triangle's bits are
    /// the geometry's, whatever the chunks). Reads no mesh.
    pub(super) fn refresh(&mut self, positions: &[DVec3]) {
        let n = self.triangles.len();
        let chunk = face_chunk(n);
        let n_cots = self.face_cots.len() - 1;
        self.face_cots[..n_cots]
            .par_chunks_mut(3 * chunk)
            .zip(self.triangles.par_chunks(chunk))
            .for_each(|(out, tris)| triangle_cotangents_blocked_into(positions, tris, out));
    }
}
