//! Vertex reordering for memory locality.
//!
//! A sweep over the vertices of a mesh (a Laplacian row per vertex) reads the positions
//! of each vertex's neighbours. When neighbours have nearby indices those reads hit the
//! cache; when they are scattered (the vertex order of a subdivided or scanned mesh, or
//! a shuffled one) every row waits on memory. A [`VertexPermutation`] renumbers the
//! vertices so that neighbours lie close together, [`apply_to_mesh`] builds the
//! renumbered connectivity ([`apply_to_mesh_in_place`] renumbers a mesh where it is, and
//! [`restore_mesh_in_place`] numbers it back), and [`permute`]/[`restore`] move
//! per-vertex data between the two numberings, so that an algorithm can work internally in the good order and give
//! its results back in the caller's.
//!
//! Renumbering the vertices changes nothing else: halfedge, edge and face ids, each
//! vertex's outgoing halfedge (hence the counter-clockwise order of its one-ring) and
//! each face's first vertex stay the same. Any per-vertex computation that depends only
//! on a vertex's one-ring, or per-face computation, gives the same bits in either
//! numbering.
//!
//! Two orders are offered:
//! - [`rcm_order`]: reverse Cuthill–McKee on the vertex graph (breadth-first from a
//!   peripheral vertex, neighbours by increasing valence, reversed). Neighbours end up
//!   within a narrow band of indices. Needs only the connectivity.
//! - [`hilbert_order`]: vertices sorted along a 3-D Hilbert curve through their
//!   positions' bounding box. Needs only the positions.
//!
//! [`apply_to_mesh`]: VertexPermutation::apply_to_mesh
//! [`apply_to_mesh_in_place`]: VertexPermutation::apply_to_mesh_in_place
//! [`restore_mesh_in_place`]: VertexPermutation::restore_mesh_in_place
//! [`permute`]: VertexPermutation::permute
//! [`restore`]: VertexPermutation::restore
//!
//! # Examples
//! ```
//! use beltrami_halfedge::{primitives, reorder};
//!
//! let sphere = primitives::icosphere(3);
//! let mesh = sphere.mesh().unwrap();
//! let perm = reorder::rcm_order(&mesh);
//! let fast_mesh = perm.apply_to_mesh(&mesh);
//! let fast_positions = perm.permute(&sphere.positions);
//! // ... work on (fast_mesh, fast_positions) ...
//! let back = perm.restore(&fast_positions);
//! assert_eq!(back, sphere.positions);
//! # let _ = fast_mesh;
//! ```

use std::collections::VecDeque;

use glam::DVec3;
use rayon::prelude::*;

use crate::ids::VertexId;
use crate::mesh::{HalfedgeMesh, INVALID};

/// A renumbering of the vertices of a mesh: vertex `new` of the renumbered mesh is
/// vertex [`new_to_old`](Self::new_to_old)`[new]` of the original.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexPermutation {
    new_to_old: Vec<u32>,
    old_to_new: Vec<u32>,
}

impl VertexPermutation {
    /// The identity on `n` vertices.
    ///
    /// # Panics
    /// If `n` does not fit in `u32`.
    #[must_use]
    pub fn identity(n: usize) -> Self {
        let n = u32::try_from(n).expect("vertex ids are u32");
        let ids: Vec<u32> = (0..n).collect();
        Self {
            new_to_old: ids.clone(),
            old_to_new: ids,
        }
    }

    /// The permutation whose new vertex `i` is old vertex `new_to_old[i]`, or `None`
    /// when `new_to_old` is not a permutation of `0..new_to_old.len()`.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::reorder::VertexPermutation;
    /// let p = VertexPermutation::from_new_to_old(vec![2, 0, 1]).unwrap();
    /// assert_eq!(p.old_to_new(), [1, 2, 0]);
    /// assert!(VertexPermutation::from_new_to_old(vec![0, 0]).is_none());
    /// ```
    #[must_use]
    pub fn from_new_to_old(new_to_old: Vec<u32>) -> Option<Self> {
        let n = new_to_old.len();
        u32::try_from(n).ok()?;
        let mut old_to_new = vec![INVALID; n];
        for (new, &old) in new_to_old.iter().enumerate() {
            let slot = old_to_new.get_mut(old as usize)?;
            if *slot != INVALID {
                return None;
            }
            *slot = new as u32;
        }
        Some(Self {
            new_to_old,
            old_to_new,
        })
    }

    /// The number of vertices.
    #[must_use]
    pub fn len(&self) -> usize {
        self.new_to_old.len()
    }

    /// Whether there are no vertices.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.new_to_old.is_empty()
    }

    /// Old vertex index per new index.
    #[must_use]
    pub fn new_to_old(&self) -> &[u32] {
        &self.new_to_old
    }

    /// New vertex index per old index.
    #[must_use]
    pub fn old_to_new(&self) -> &[u32] {
        &self.old_to_new
    }

    /// The new id of old vertex `v`.
    ///
    /// # Panics
    /// If `v` is out of range.
    #[must_use]
    pub fn to_new(&self, v: VertexId) -> VertexId {
        VertexId::new(self.old_to_new[v.index()])
    }

    /// The old id of new vertex `v`.
    ///
    /// # Panics
    /// If `v` is out of range.
    #[must_use]
    pub fn to_old(&self, v: VertexId) -> VertexId {
        VertexId::new(self.new_to_old[v.index()])
    }

    /// Per-vertex data in the new numbering: `out[new] = old[new_to_old[new]]`.
    ///
    /// # Panics
    /// If `old` does not have one entry per vertex.
    #[must_use]
    pub fn permute<T: Copy>(&self, old: &[T]) -> Vec<T> {
        assert_eq!(old.len(), self.len(), "one entry per vertex");
        self.new_to_old.iter().map(|&o| old[o as usize]).collect()
    }

    /// Per-vertex data back in the old numbering: `out[old] = new[old_to_new[old]]`.
    ///
    /// # Panics
    /// If `new` does not have one entry per vertex.
    #[must_use]
    pub fn restore<T: Copy>(&self, new: &[T]) -> Vec<T> {
        assert_eq!(new.len(), self.len(), "one entry per vertex");
        self.old_to_new.iter().map(|&n| new[n as usize]).collect()
    }

    /// [`restore`](Self::restore) into an existing buffer.
    ///
    /// # Panics
    /// If `new` or `out` does not have one entry per vertex.
    pub fn restore_into<T: Copy>(&self, new: &[T], out: &mut [T]) {
        assert_eq!(new.len(), self.len(), "one entry per vertex");
        assert_eq!(out.len(), self.len(), "one entry per vertex");
        for (o, &n) in out.iter_mut().zip(&self.old_to_new) {
            *o = new[n as usize];
        }
    }

    /// The mesh with its vertices renumbered: new vertex `i` is old vertex
    /// `new_to_old[i]`. Halfedge, edge and face ids, outgoing halfedges (so one-ring
    /// order) and face halfedges (so each face's first vertex) are unchanged.
    ///
    /// # Panics
    /// If the permutation does not have one entry per vertex of `mesh`.
    #[must_use]
    pub fn apply_to_mesh(&self, mesh: &HalfedgeMesh) -> HalfedgeMesh {
        assert_eq!(mesh.n_vertices(), self.len(), "one entry per vertex");
        HalfedgeMesh {
            v_out: self
                .new_to_old
                .iter()
                .map(|&o| mesh.v_out[o as usize])
                .collect(),
            h_to: mesh
                .h_to
                .iter()
                .map(|&v| self.old_to_new[v as usize])
                .collect(),
            h_next: mesh.h_next.clone(),
            h_prev: mesh.h_prev.clone(),
            h_face: mesh.h_face.clone(),
            f_he: mesh.f_he.clone(),
        }
    }

    /// [`apply_to_mesh`](Self::apply_to_mesh) without a second mesh: renumbers the
    /// vertices of `mesh` where it is, and gives the same mesh as `apply_to_mesh`. Only
    /// the outgoing halfedge per vertex is gathered into a new array (4 bytes per
    /// vertex, freed on return); the halfedges' target vertices are mapped in place and
    /// everything else is untouched.
    ///
    /// # Panics
    /// If the permutation does not have one entry per vertex of `mesh`.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{primitives, reorder};
    ///
    /// let sphere = primitives::icosphere(2);
    /// let mesh = sphere.mesh().unwrap();
    /// let perm = reorder::rcm_order(&mesh);
    /// let mut renumbered = mesh.clone();
    /// perm.apply_to_mesh_in_place(&mut renumbered);
    /// assert_eq!(renumbered, perm.apply_to_mesh(&mesh));
    /// // And back.
    /// perm.restore_mesh_in_place(&mut renumbered);
    /// assert_eq!(renumbered, mesh);
    /// ```
    pub fn apply_to_mesh_in_place(&self, mesh: &mut HalfedgeMesh) {
        renumber_in_place(mesh, &self.new_to_old, &self.old_to_new);
    }

    /// The inverse of [`apply_to_mesh_in_place`](Self::apply_to_mesh_in_place): gives a
    /// mesh renumbered by this permutation its original vertex numbering back, where it
    /// is (4 bytes per vertex of temporary memory).
    ///
    /// # Panics
    /// If the permutation does not have one entry per vertex of `mesh`.
    pub fn restore_mesh_in_place(&self, mesh: &mut HalfedgeMesh) {
        renumber_in_place(mesh, &self.old_to_new, &self.new_to_old);
    }
}

/// Renumbers the vertices of `mesh` where it is: new vertex `i` is old vertex
/// `new_to_old[i]`, old vertex `o` becomes `old_to_new[o]`.
fn renumber_in_place(mesh: &mut HalfedgeMesh, new_to_old: &[u32], old_to_new: &[u32]) {
    assert_eq!(mesh.n_vertices(), new_to_old.len(), "one entry per vertex");
    let v_out: Vec<u32> = new_to_old.iter().map(|&o| mesh.v_out[o as usize]).collect();
    crate::release(std::mem::replace(&mut mesh.v_out, v_out));
    mesh.h_to.par_chunks_mut(RENUMBER_CHUNK).for_each(|chunk| {
        for v in chunk {
            *v = old_to_new[*v as usize];
        }
    });
}

/// Halfedges per parallel work unit of [`renumber_in_place`].
const RENUMBER_CHUNK: usize = 1 << 16;

/// The largest difference between the indices of two vertices joined by an edge (0
/// for a mesh without edges): how far apart a sweep over the vertices in index order
/// finds neighbours. [`rcm_order`] makes it small.
///
/// # Complexity
/// O(E) time, no allocation.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, reorder};
///
/// let grid = primitives::grid(10, 4).mesh().unwrap();
/// // Rows of 11 vertices one after the other: a diagonal spans 12 indices.
/// assert_eq!(reorder::bandwidth(&grid), 12);
/// ```
#[must_use]
pub fn bandwidth(mesh: &HalfedgeMesh) -> usize {
    mesh.h_to
        .chunks_exact(2)
        .map(|e| e[0].abs_diff(e[1]) as usize)
        .max()
        .unwrap_or(0)
}

/// Reverse Cuthill–McKee order of the vertex graph: each connected component is
/// traversed breadth-first from a pseudo-peripheral vertex (the last vertex reached by a
/// breadth-first search from the component's lowest-numbered vertex), unvisited
/// neighbours taken by increasing valence (ties: one-ring order), and the whole order
/// is reversed. Isolated vertices keep their relative order. Deterministic.
///
/// # Complexity
/// O(V + E) time and O(V) memory.
///
/// # Panics
/// Never: the order lists every vertex once by construction (the `expect` states it).
#[must_use]
pub fn rcm_order(mesh: &HalfedgeMesh) -> VertexPermutation {
    let n = mesh.n_vertices();
    let mut order: Vec<u32> = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    let mut mark = vec![false; n];
    let mut queue = VecDeque::new();
    let mut ring: Vec<(usize, u32)> = Vec::new();
    for start in mesh.vertices() {
        if seen[start.index()] {
            continue;
        }
        // A pseudo-peripheral vertex: the last one a breadth-first search reaches.
        let mut last = start;
        queue.push_back(start);
        mark[start.index()] = true;
        // The component's vertices, for the check below (debug builds only: a buffer
        // of 4 bytes per vertex).
        #[cfg(debug_assertions)]
        let mut component = Vec::new();
        while let Some(v) = queue.pop_front() {
            last = v;
            #[cfg(debug_assertions)]
            component.push(v);
            for w in mesh.vertices_around_vertex(v) {
                if !mark[w.index()] {
                    mark[w.index()] = true;
                    queue.push_back(w);
                }
            }
        }
        // Cuthill–McKee from there.
        queue.push_back(last);
        seen[last.index()] = true;
        while let Some(v) = queue.pop_front() {
            order.push(v.raw());
            ring.clear();
            ring.extend(
                mesh.vertices_around_vertex(v)
                    .filter(|w| !seen[w.index()])
                    .map(|w| (mesh.valence(w), w.raw())),
            );
            // Stable: equal valences keep one-ring order.
            ring.sort_by_key(|&(valence, _)| valence);
            for &(_, w) in &ring {
                if !seen[w as usize] {
                    seen[w as usize] = true;
                    queue.push_back(VertexId::new(w));
                }
            }
        }
        #[cfg(debug_assertions)]
        debug_assert!(component.iter().all(|v| seen[v.index()]));
    }
    crate::release(seen);
    crate::release(mark);
    order.reverse();
    VertexPermutation::from_new_to_old(order).expect("every vertex once")
}

/// Bits per axis of the Hilbert key (3 × 21 = 63 bits).
const HILBERT_BITS: u32 = 21;

/// Vertices sorted along a 3-D Hilbert curve through the bounding box of their
/// positions (each axis quantised to 2²¹ cells of the largest extent; ties and
/// non-finite positions by index). Deterministic.
///
/// # Complexity
/// O(V log V) time and O(V) memory.
///
/// # Panics
/// Never: the sorted keys carry every index once (the `expect` states it).
#[must_use]
pub fn hilbert_order(positions: &[DVec3]) -> VertexPermutation {
    let finite = positions.iter().filter(|p| p.is_finite());
    let (lo, hi) = finite.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let extent = (hi - lo).max_element();
    let cells = f64::from((1u32 << HILBERT_BITS) - 1);
    let scale = if extent.is_finite() && extent > 0.0 {
        cells / extent
    } else {
        0.0
    };
    let mut keyed: Vec<(u64, u32)> = positions
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let key = if p.is_finite() {
                let q = ((p - lo) * scale).clamp(DVec3::ZERO, DVec3::splat(cells));
                hilbert_key([q.x as u32, q.y as u32, q.z as u32])
            } else {
                0
            };
            (key, i as u32)
        })
        .collect();
    keyed.sort_unstable();
    VertexPermutation::from_new_to_old(keyed.into_iter().map(|(_, i)| i).collect())
        .expect("every vertex once")
}

/// The index along the 3-D Hilbert curve of the cell `x` (each coordinate below
/// 2^`HILBERT_BITS`), by Skilling's transform ("Programming the Hilbert curve", AIP
/// Conference Proceedings 707, 2004).
fn hilbert_key(mut x: [u32; 3]) -> u64 {
    let m = 1u32 << (HILBERT_BITS - 1);
    // Inverse undo.
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    // Gray encode.
    for i in 1..3 {
        x[i] ^= x[i - 1];
    }
    let mut t = 0;
    let mut q = m;
    while q > 1 {
        if x[2] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for xi in &mut x {
        *xi ^= t;
    }
    // Interleave the transposed bits, most significant first.
    let mut key = 0u64;
    for b in (0..HILBERT_BITS).rev() {
        for xi in x {
            key = (key << 1) | u64::from((xi >> b) & 1);
        }
    }
    key
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    /// The bandwidth is the largest index difference along an edge: 0 without edges,
    /// and reverse Cuthill–McKee narrows a subdivided sphere's (whose new vertices are
    /// numbered after the old ones).
    #[test]
    fn bandwidth_is_the_widest_edge_in_index() {
        let lonely = HalfedgeMesh::from_polygons(3, std::iter::empty::<[u32; 3]>()).unwrap();
        assert_eq!(bandwidth(&lonely), 0);
        let tri = HalfedgeMesh::from_polygons(6, [[0u32, 5, 2]]).unwrap();
        assert_eq!(bandwidth(&tri), 5);
        let sphere = primitives::icosphere(4).mesh().unwrap();
        let wide = bandwidth(&sphere);
        let narrow = bandwidth(&rcm_order(&sphere).apply_to_mesh(&sphere));
        assert!(narrow * 4 < wide, "{narrow} against {wide}");
    }

    fn check(mesh: &HalfedgeMesh, perm: &VertexPermutation) {
        let new = perm.apply_to_mesh(mesh);
        new.check_integrity().unwrap();
        for v in mesh.vertices() {
            let ring: Vec<u32> = mesh
                .vertices_around_vertex(v)
                .map(|w| perm.to_new(w).raw())
                .collect();
            let new_ring: Vec<u32> = new
                .vertices_around_vertex(perm.to_new(v))
                .map(|w| w.raw())
                .collect();
            assert_eq!(ring, new_ring);
        }
        for f in mesh.faces() {
            let a: Vec<u32> = mesh
                .vertices_around_face(f)
                .map(|w| perm.to_new(w).raw())
                .collect();
            let b: Vec<u32> = new.vertices_around_face(f).map(|w| w.raw()).collect();
            assert_eq!(a, b);
        }
    }

    #[test]
    fn orders_are_permutations_that_keep_rings_and_faces() {
        let sphere = primitives::icosphere(3);
        let mesh = sphere.mesh().unwrap();
        for perm in [rcm_order(&mesh), hilbert_order(&sphere.positions)] {
            assert_eq!(perm.len(), mesh.n_vertices());
            check(&mesh, &perm);
            let p = perm.permute(&sphere.positions);
            assert_eq!(perm.restore(&p), sphere.positions);
        }
        let grid = primitives::grid(5, 4);
        let mesh = grid.mesh().unwrap();
        check(&mesh, &rcm_order(&mesh));
    }

    #[test]
    fn renumbering_in_place_equals_the_copy_and_restores() {
        let torus = primitives::torus(2.0, 0.5, 24, 12);
        let grid = primitives::grid(7, 5);
        let sphere = primitives::icosphere(3);
        let meshes = [
            torus.mesh().unwrap(),
            grid.mesh().unwrap(),
            sphere.mesh().unwrap(),
            // Vertex 4 is isolated.
            HalfedgeMesh::from_polygons(5, [[0u32, 1, 2], [0, 2, 3]]).unwrap(),
        ];
        for mesh in meshes {
            let n = mesh.n_vertices() as u32;
            // RCM and a reversal: neither is the identity.
            let reversed = VertexPermutation::from_new_to_old((0..n).rev().collect()).unwrap();
            for perm in [rcm_order(&mesh), reversed] {
                assert_ne!(perm, VertexPermutation::identity(mesh.n_vertices()));
                let mut m = mesh.clone();
                perm.apply_to_mesh_in_place(&mut m);
                assert_eq!(m, perm.apply_to_mesh(&mesh));
                assert_ne!(m, mesh);
                perm.restore_mesh_in_place(&mut m);
                assert_eq!(m, mesh);
            }
        }
    }

    #[test]
    fn rcm_narrows_the_band() {
        let sphere = primitives::icosphere(4);
        let mesh = sphere.mesh().unwrap();
        let band = |m: &HalfedgeMesh| {
            m.halfedges()
                .map(|h| m.from_vertex(h).raw().abs_diff(m.to_vertex(h).raw()))
                .max()
                .unwrap()
        };
        let perm = rcm_order(&mesh);
        assert!(band(&perm.apply_to_mesh(&mesh)) * 4 < band(&mesh));
    }

    #[test]
    fn hilbert_keys_are_a_walk_of_adjacent_cells() {
        // On a 4×4×4 corner of the grid, consecutive keys are face neighbours.
        let mut cells: Vec<(u64, [u32; 3])> = Vec::new();
        for x in 0..4 {
            for y in 0..4 {
                for z in 0..4 {
                    cells.push((hilbert_key([x, y, z]), [x, y, z]));
                }
            }
        }
        cells.sort_unstable();
        for w in cells.windows(2) {
            let d: u32 = (0..3).map(|i| w[0].1[i].abs_diff(w[1].1[i])).sum();
            assert_eq!(d, 1, "{w:?}");
        }
    }

    #[test]
    fn from_new_to_old_rejects_non_permutations() {
        assert!(VertexPermutation::from_new_to_old(vec![0, 2]).is_none());
        assert!(VertexPermutation::from_new_to_old(vec![1, 1]).is_none());
        assert_eq!(
            VertexPermutation::from_new_to_old(vec![0, 1]),
            Some(VertexPermutation::identity(2))
        );
    }
}
