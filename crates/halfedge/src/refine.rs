//! The connectivity of a uniform 1-to-4 triangle split: [`HalfedgeMesh::split_triangles`].

use rayon::prelude::*;

use crate::build::check_count;
use crate::error::TopologyError;
use crate::ids::{EdgeId, FaceId, HalfedgeId, VertexId};
use crate::mesh::{HalfedgeMesh, INVALID};
use crate::raw::invert_next;

impl HalfedgeMesh {
    /// The connectivity of one 1-to-4 split of every triangle at its edge midpoints: the
    /// topology of a Loop (or midpoint) subdivision step, without positions.
    ///
    /// Numbering: vertex `v` keeps its id; the new vertex on edge `e` is
    /// `n_vertices + e`. Face `f` with vertices `[a, b, c]` (from
    /// [`vertices_around_face`](Self::vertices_around_face)) becomes faces `4f` to
    /// `4f + 3`: `[a, ab, ca]`, `[b, bc, ab]`, `[c, ca, bc]` and `[ab, bc, ca]`, where
    /// `ab` is the vertex on the edge from `a` to `b`. The result is exactly what
    /// [`from_polygons`](Self::from_polygons) builds from that face list — the same
    /// edge numbering (by first appearance), halfedge directions, outgoing halfedges
    /// and boundary links — but built in closed form: no sorting or hashing, and no
    /// validation pass, since the split of a valid triangle mesh is valid by
    /// construction (debug builds check it, and the tests compare it with
    /// `from_polygons` on closed, open and isolated-vertex meshes).
    ///
    /// # Errors
    /// [`TopologyError::NotTriangle`] naming the first face that is not a triangle;
    /// [`TopologyError::TooManyElements`] when the result would not fit in `u32`
    /// handles (checked before any work).
    ///
    /// # Complexity
    /// O(V + E + F) time and memory, in parallel on rayon's threads (one prefix sum over
    /// the faces is sequential); the result does not depend on the number of threads.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::HalfedgeMesh;
    ///
    /// let tet = HalfedgeMesh::from_polygons(4, [[0u32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])?;
    /// let fine = tet.split_triangles()?;
    /// assert_eq!((fine.n_vertices(), fine.n_edges(), fine.n_faces()), (10, 24, 16));
    /// fine.check_integrity()?;
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    pub fn split_triangles(&self) -> Result<HalfedgeMesh, TopologyError> {
        if let Some(f) = self.faces().find(|&f| self.face_valence(f) != 3) {
            return Err(TopologyError::NotTriangle {
                face: f.raw(),
                len: self.face_valence(f),
            });
        }
        let (nv, ne, nf) = (self.n_vertices(), self.n_edges(), self.n_faces());
        check_count("vertices", nv + ne)?;
        check_count("halfedges", 2 * (2 * ne + 3 * nf))?;
        check_count("faces", 4 * nf)?;
        let fine = refine(self);
        debug_assert_eq!(fine.check_integrity(), Ok(()));
        Ok(fine)
    }
}

// Face `f` of the coarse mesh, with `h0` its halfedge ending at its first vertex `a`,
// `h1 = next(h0)` ending at `b` and `h2 = next(h1)` ending at `c`, becomes the four
// triangles `[a, ab, ca]`, `[b, bc, ab]`, `[c, ca, bc]`, `[ab, bc, ca]` (faces `4f` to
// `4f + 3`), where `ab`, `bc`, `ca` are the points of the edges of `h1`, `h2`, `h0`.
// Their twelve corners are `12f + i`, corner `i` starting the directed edge from the
// `i % 3`-th vertex of triangle `i / 3` to the next one. `HalfedgeMesh::from_polygons`
// of this face list numbers an edge by the first corner (in corner order) that runs
// along it, with halfedge `2e` in that corner's direction; the arrays below follow
// that rule, so the result equals it array for array, without sorting.
//
// The corners of face `f` that can open an edge are 0..=8: the interior edges at
// corners 1, 4 and 7 (their mates are the middle triangle's corners 11, 9 and 10) and
// the halves of the coarse edges. Coarse halfedge `hj` (`j` in 0..3) is split into its
// first half, from its source to its point, at corner `FIRST[j]`, and its second half at
// corner `SECOND[j]`; both open an edge unless the face across `hj` comes before `f`,
// where the same halves were met first (the first half of `hj` is the second half of its
// twin, and the other way round).

/// The corner of the first half (source → point) of halfedge `hj` of a face.
const FIRST: [usize; 3] = [6, 0, 3];
/// The corner of the second half (point → target) of halfedge `hj` of a face.
const SECOND: [usize; 3] = [2, 5, 8];
/// The middle triangle's corner that starts at the point of `hj`: the last corner at
/// that point within the face.
const MIDDLE: [usize; 3] = [11, 9, 10];
/// For corners 0..=8, the halfedge `hj` whose half it is, or 3 for an interior edge.
const HALF_OF: [usize; 9] = [1, 3, 0, 2, 3, 1, 0, 3, 2];
/// `RANK[mask][i]`: how many of corners `0..i` open an edge in a face whose halves open
/// as `mask` says (bit `j` for the halves of `hj`).
const RANK: [[u32; 9]; 8] = rank_table();
/// Faces per parallel task of the builder.
const FACE_CHUNK: usize = 1 << 10;

const fn rank_table() -> [[u32; 9]; 8] {
    let mut table = [[0; 9]; 8];
    let mut mask = 0;
    while mask < 8 {
        let mut count = 0;
        let mut i = 0;
        while i < 9 {
            table[mask][i] = count;
            if HALF_OF[i] == 3 || mask & (1 << HALF_OF[i]) != 0 {
                count += 1;
            }
            i += 1;
        }
        mask += 1;
    }
    table
}

/// Whether corner `i` (0..=8) opens an edge in a face whose halves open as `mask` says.
#[inline]
fn opens_at(mask: u8, i: usize) -> bool {
    HALF_OF[i] == 3 || mask & (1 << HALF_OF[i]) != 0
}

/// The next corner within the same triangle.
#[inline]
fn next_corner(i: usize) -> usize {
    if i % 3 == 2 { i - 2 } else { i + 1 }
}

/// The corner of the twin of the half at corner `i` (a half of `hj`), in the face across
/// where the twin of `hj` is at position `jg`.
#[inline]
fn across(i: usize, j: usize, jg: usize) -> usize {
    if FIRST[j] == i { SECOND[jg] } else { FIRST[jg] }
}

/// What the closed form reads of the coarse mesh.
struct Coarse<'a> {
    mesh: &'a HalfedgeMesh,
    /// Per halfedge, its position `j` in its face (unused on the boundary).
    position: Vec<u8>,
    /// Per face, bit `j` set when the halves of `hj` open their edges in this face.
    opens: Vec<u8>,
    /// Per face, the first fine edge it opens; one more entry, the number of edges.
    base: Vec<u32>,
}

impl Coarse<'_> {
    /// `[h0, h1, h2]` of face `f`.
    #[inline]
    fn halfedges(&self, f: usize) -> [HalfedgeId; 3] {
        let h0 = self.mesh.face_halfedge(FaceId::new(f as u32));
        let h1 = self.mesh.next(h0);
        [h0, h1, self.mesh.next(h1)]
    }

    /// The face of the inner halfedge `h` and the position of `h` in it.
    #[inline]
    fn locate(&self, h: HalfedgeId) -> (usize, usize) {
        let g = self.mesh.face(h).map_or(0, |g| g.index());
        (g, usize::from(self.position[h.index()]))
    }

    /// The fine edge opened at corner `i` (0..=8, an opening one) of face `f`.
    #[inline]
    fn opened_edge(&self, f: usize, i: usize) -> u32 {
        self.base[f] + RANK[usize::from(self.opens[f])][i]
    }

    /// The fine halfedges of the twelve corners of face `f`.
    fn corner_halfedges(&self, f: usize, out: &mut [u32]) {
        let mask = self.opens[f];
        let hs = self.halfedges(f);
        for i in 0..9 {
            out[i] = if opens_at(mask, i) {
                2 * self.opened_edge(f, i)
            } else {
                // The face across, earlier in order, opened this half from its side.
                let j = HALF_OF[i];
                let (g, jg) = self.locate(hs[j].twin());
                2 * self.opened_edge(g, across(i, j, jg)) + 1
            };
        }
        out[9] = out[4] | 1;
        out[10] = out[7] | 1;
        out[11] = out[1] | 1;
    }
}

/// Splits `data` into consecutive pieces of the given lengths.
fn split_pieces<'a, T>(mut data: &'a mut [T], lengths: &[usize]) -> Vec<&'a mut [T]> {
    let mut pieces = Vec::with_capacity(lengths.len());
    for &len in lengths {
        let (piece, rest) = data.split_at_mut(len);
        pieces.push(piece);
        data = rest;
    }
    pieces
}

/// The closed-form split of `mesh` (a valid triangle mesh whose result fits `u32`).
fn refine(mesh: &HalfedgeMesh) -> HalfedgeMesh {
    let coarse = Coarse::new(mesh);
    let corner_he = coarse.all_corner_halfedges();
    let v_out = coarse.outgoing_halfedges(&corner_he);
    let [h_to, h_next, h_face] = coarse.halfedge_arrays(&corner_he, &v_out);
    let f_he: Vec<u32> = (0..4 * mesh.n_faces())
        .into_par_iter()
        .with_min_len(4 * FACE_CHUNK)
        .map(|t| corner_he[3 * t + 2])
        .collect();

    let h_prev = invert_next(&h_next);
    HalfedgeMesh {
        v_out,
        h_to,
        h_next,
        h_prev,
        h_face,
        f_he,
    }
}

impl<'a> Coarse<'a> {
    /// Reads the halfedge positions, the opening masks and the first fine edge of every
    /// face of `mesh`.
    fn new(mesh: &'a HalfedgeMesh) -> Self {
        let (ne, nf) = (mesh.n_edges(), mesh.n_faces());
        let position: Vec<u8> = (0..2 * ne)
            .into_par_iter()
            .with_min_len(4 * FACE_CHUNK)
            .map(|h| {
                let h = HalfedgeId::new(h as u32);
                mesh.face(h).map_or(3, |f| {
                    let h0 = mesh.face_halfedge(f);
                    if h == h0 {
                        0
                    } else if h == mesh.next(h0) {
                        1
                    } else {
                        2
                    }
                })
            })
            .collect();
        // A face opens the halves of its halfedges whose twin is on the boundary or in a
        // later face.
        let opens: Vec<u8> = (0..nf)
            .into_par_iter()
            .with_min_len(FACE_CHUNK)
            .map(|f| {
                let h0 = mesh.face_halfedge(FaceId::new(f as u32));
                let h1 = mesh.next(h0);
                let mut mask = 0u8;
                for (j, h) in [h0, h1, mesh.next(h1)].into_iter().enumerate() {
                    if mesh.face(h.twin()).is_none_or(|g| g.index() > f) {
                        mask |= 1 << j;
                    }
                }
                mask
            })
            .collect();
        let mut base = Vec::with_capacity(nf + 1);
        let mut total = 0u32;
        for &mask in &opens {
            base.push(total);
            total += 3 + 2 * mask.count_ones();
        }
        base.push(total);
        debug_assert_eq!(total as usize, 2 * ne + 3 * nf);
        Coarse {
            mesh,
            position,
            opens,
            base,
        }
    }

    /// The fine halfedge of every corner: twelve per coarse face.
    fn all_corner_halfedges(&self) -> Vec<u32> {
        let mut corner_he = vec![0u32; 12 * self.mesh.n_faces()];
        corner_he
            .par_chunks_mut(12)
            .with_min_len(FACE_CHUNK)
            .enumerate()
            .for_each(|(f, out)| self.corner_halfedges(f, out));
        corner_he
    }

    /// Outgoing halfedges of the fine vertices (coarse vertices, then edge points): at a
    /// boundary vertex the boundary halfedge leaving it (the twin of a half met from the
    /// inside); otherwise the halfedge leaving it in its last face, as `from_polygons`
    /// chooses.
    fn outgoing_halfedges(&self, corner_he: &[u32]) -> Vec<u32> {
        let mesh = self.mesh;
        let nv = mesh.n_vertices();
        (0..nv + mesh.n_edges())
            .into_par_iter()
            .with_min_len(FACE_CHUNK)
            .map(|v| {
                if v < nv {
                    let Some(out) = mesh.outgoing_halfedge(VertexId::new(v as u32)) else {
                        return INVALID;
                    };
                    if mesh.is_boundary_halfedge(out) {
                        // Coarse boundary v → w: the fine boundary v → point is the twin
                        // of the second half of the inner w → v.
                        let (g, j) = self.locate(out.twin());
                        return corner_he[12 * g + SECOND[j]] ^ 1;
                    }
                    let last = mesh
                        .halfedges_around_vertex(VertexId::new(v as u32))
                        .max_by_key(|&h| mesh.face(h).map_or(0, |f| f.index()))
                        .unwrap_or(out);
                    let (f, j) = self.locate(last);
                    corner_he[12 * f + FIRST[j]]
                } else {
                    let [h, t] = EdgeId::new((v - nv) as u32).halfedges();
                    match (mesh.face(h), mesh.face(t)) {
                        // Boundary edge: the fine boundary halfedge leaving the point is
                        // the twin of the first half of the inner halfedge.
                        (Some(_), None) => {
                            let (g, j) = self.locate(h);
                            corner_he[12 * g + FIRST[j]] ^ 1
                        }
                        (None, Some(_)) => {
                            let (g, j) = self.locate(t);
                            corner_he[12 * g + FIRST[j]] ^ 1
                        }
                        (fh, ft) => {
                            let (f, j) = self.locate(if fh > ft { h } else { t });
                            corner_he[12 * f + MIDDLE[j]]
                        }
                    }
                }
            })
            .collect()
    }

    /// The fine `[to, next, face]` arrays, filled in parallel by blocks of the edges
    /// that a chunk of faces opens.
    fn halfedge_arrays(&self, corner_he: &[u32], v_out: &[u32]) -> [Vec<u32>; 3] {
        let nf = self.mesh.n_faces();
        let n_halfedges = 2 * self.base[nf] as usize;
        let mut h_to = vec![INVALID; n_halfedges];
        let mut h_next = vec![INVALID; n_halfedges];
        let mut h_face = vec![INVALID; n_halfedges];
        let chunk_starts: Vec<usize> = (0..nf).step_by(FACE_CHUNK).chain([nf]).collect();
        let lengths: Vec<usize> = chunk_starts
            .windows(2)
            .map(|w| 2 * (self.base[w[1]] - self.base[w[0]]) as usize)
            .collect();
        let pieces: Vec<_> = split_pieces(&mut h_to, &lengths)
            .into_iter()
            .zip(split_pieces(&mut h_next, &lengths))
            .zip(split_pieces(&mut h_face, &lengths))
            .zip(chunk_starts.windows(2))
            .collect();
        pieces.into_par_iter().for_each(|(((to, next), face), w)| {
            let first_halfedge = 2 * self.base[w[0]];
            for f in w[0]..w[1] {
                let arrays = [&mut *to, &mut *next, &mut *face];
                self.fill_face(f, corner_he, v_out, first_halfedge, arrays);
            }
        });
        [h_to, h_next, h_face]
    }

    /// Writes `to`, `next` and `face` of both halfedges of every fine edge that face `f`
    /// opens, into arrays starting at fine halfedge `first_halfedge`.
    #[inline]
    fn fill_face(
        &self,
        f: usize,
        corner_he: &[u32],
        v_out: &[u32],
        first_halfedge: u32,
        [to, next, face]: [&mut [u32]; 3],
    ) {
        let mesh = self.mesh;
        let nv = mesh.n_vertices();
        let mask = self.opens[f];
        let hs = self.halfedges(f);
        let [a, b, c] = hs.map(|h| mesh.to_vertex(h).raw());
        let point = |h: HalfedgeId| (nv + h.edge().index()) as u32;
        let (ab, bc, ca) = (point(hs[1]), point(hs[2]), point(hs[0]));
        let verts = [a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca];
        let he = &corner_he[12 * f..12 * f + 12];
        let fine_face = 4 * f as u32;
        for i in (0..9).filter(|&i| opens_at(mask, i)) {
            let h = (he[i] - first_halfedge) as usize;
            let n = next_corner(i);
            to[h] = verts[n];
            next[h] = he[n];
            face[h] = fine_face + (i / 3) as u32;
            // The twin runs along the mate corner, or on the boundary.
            to[h + 1] = verts[i];
            let j = HALF_OF[i];
            if j == 3 {
                let mate = match i {
                    1 => 11,
                    4 => 9,
                    _ => 10,
                };
                next[h + 1] = he[next_corner(mate)];
                face[h + 1] = fine_face + 3;
            } else if mesh.is_boundary_halfedge(hs[j].twin()) {
                // After a boundary halfedge comes the boundary halfedge leaving its
                // target.
                next[h + 1] = v_out[verts[i] as usize];
            } else {
                let (g, jg) = self.locate(hs[j].twin());
                let mate = across(i, j, jg);
                next[h + 1] = corner_he[12 * g + next_corner(mate)];
                face[h + 1] = (4 * g + mate / 3) as u32;
            }
        }
    }
}
