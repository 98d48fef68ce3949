//! The half-edge arrays from a polygon list whose faces are individually valid, with
//! the edge and vertex checks that name the offending input faces.

use rayon::prelude::*;

use super::corners::{Corners, PARALLEL_CHUNK, count_fans};
use super::{Origin, check_count};
use crate::error::TopologyError;
use crate::mesh::{HalfedgeMesh, INVALID};
use crate::polygons::PolygonList;

/// Corners whose edges one parallel task of the assembly numbers and pairs; fixed, so
/// that the chunks (and with them every result) do not depend on the thread count. A
/// multiple of three, so that a list of triangles is chunked a triangle at a time.
const CHUNK: usize = 3 << 15;
/// Edges whose halfedges one parallel task fills.
const EDGE_CHUNK: usize = PARALLEL_CHUNK / 2;

/// Builds the half-edge arrays from a list whose faces are individually valid.
///
/// Every step but the boundary's is a parallel pass over fixed chunks, each writing
/// its own part of an array: the corners leaving each vertex are listed (a counting
/// sort by vertex, in vertex ranges), each corner finds its mate in its target's list,
/// the edges are numbered by their first corner (a count per chunk, then a prefix),
/// and each edge's two halfedges are filled from its two corners (a gather, written in
/// halfedge order). The arrays are those of the sequential assembly in corner order,
/// entry for entry.
pub(super) fn assemble(
    n_vertices: usize,
    list: &PolygonList,
    origin: Origin<'_>,
) -> Result<HalfedgeMesh, TopologyError> {
    let corners = Corners::of_valid(list);
    let leaving = Leaving::new(&corners, n_vertices);
    let (mate, openers) = match leaving.mates(&corners) {
        Some(paired) => paired,
        None => {
            let mate = mates_from_groups(&corners, origin)?;
            let openers = mate
                .par_chunks(CHUNK)
                .enumerate()
                .map(|(c, mates)| {
                    (c * CHUNK..)
                        .zip(mates)
                        .filter(|&(k, &m)| opens(k, m))
                        .count()
                })
                .collect();
            (mate, openers)
        }
    };

    // Edge `e` is numbered by its first corner in corner order: a corner opens a new
    // edge unless its mate comes before it. `base[c]` is the first edge opened in
    // chunk `c`.
    let mut base = Vec::with_capacity(openers.len() + 1);
    base.push(0);
    for count in &openers {
        base.push(base[base.len() - 1] + count);
    }
    let n_edges = base[openers.len()];
    check_count("halfedges", 2 * n_edges)?;

    // The vertex's last corner (in corner order), while the lists are at hand.
    let mut v_out: Vec<u32> = leaving.last_corners();
    let Leaving { start, out } = leaving;
    crate::release(start);
    crate::release(out);

    let (edge_corners, corner_he, boundary) = number_edges(&mate, &openers, &base);
    crate::release(mate);

    // Interior vertices: the halfedge leaving the vertex in its last face (where
    // OpenMesh's `add_face` leaves it, so circulators start at the same neighbour).
    v_out.par_chunks_mut(CHUNK).for_each(|outs| {
        for out in outs {
            if *out != INVALID {
                *out = corner_he[*out as usize];
            }
        }
    });
    // Boundary vertices: the boundary halfedge leaving them, the twin of the one
    // boundary corner that ends there (a second one is a pinched vertex).
    if !boundary.is_empty() {
        let mut seen = vec![false; n_vertices];
        for &k in &boundary {
            let b = corners.to(k) as usize;
            if seen[b] {
                let fans = count_fans(list, b as u32).max(2);
                return Err(TopologyError::NonManifoldVertex {
                    vertex: b as u32,
                    fans,
                });
            }
            seen[b] = true;
            v_out[b] = corner_he[k as usize] | 1;
        }
    }

    let [h_to, h_next, mut h_prev, h_face] =
        fill_halfedges(&corners, &edge_corners, &corner_he, &v_out);
    crate::release(edge_corners);
    // Link boundary loops: the boundary halfedge after `t` has `t` before it.
    for &k in &boundary {
        let t = corner_he[k as usize] | 1;
        h_prev[h_next[t as usize] as usize] = t;
    }
    let f_he: Vec<u32> = (0..list.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|f| corner_he[list.face_range(f).end - 1])
        .collect();
    crate::release(corner_he);

    let mesh = HalfedgeMesh {
        v_out,
        h_to,
        h_next,
        h_prev,
        h_face,
        f_he,
    };
    check_manifold_vertices(&mesh, list)?;
    Ok(mesh)
}

/// Numbers the edges by their first corner, in parallel over the chunks of corners
/// (`base[c]`: the first edge that chunk `c` opens). Returns the corners of each edge
/// (the opener and its mate, `INVALID` on the boundary), every corner's halfedge
/// (`2e` for the opener of edge `e`, `2e + 1` for its mate) and the boundary corners
/// in corner order.
#[inline(never)] // one entry of its own in profiles
fn number_edges(
    mate: &[u32],
    openers: &[usize],
    base: &[usize],
) -> (Vec<[u32; 2]>, Vec<u32>, Vec<u32>) {
    let n_edges = base[openers.len()];
    let mut edge_corners = vec![[0u32; 2]; n_edges];
    let mut corner_he = vec![0u32; mate.len()];
    let mut pieces = Vec::with_capacity(openers.len());
    let mut rest = &mut edge_corners[..];
    for count in openers {
        let (piece, tail) = rest.split_at_mut(*count);
        pieces.push(piece);
        rest = tail;
    }
    // Per chunk, in corner order: an opener gets the next edge; a corner whose mate
    // lies in the same chunk (met before it) gets the mate's halfedge's twin; the
    // others, whose mates lie in earlier chunks, are listed for afterwards.
    let per_chunk: Vec<(Vec<u32>, Vec<u32>)> = corner_he
        .par_chunks_mut(CHUNK)
        .zip(mate.par_chunks(CHUNK))
        .zip(pieces)
        .enumerate()
        .map(|(c, ((hes, mates), edges))| {
            let first = c * CHUNK;
            let mut e = base[c] as u32;
            let mut slots = edges.iter_mut();
            let mut boundary = Vec::new();
            let mut later = Vec::new();
            for i in 0..hes.len() {
                let (k, m) = (first + i, mates[i]);
                if opens(k, m) {
                    hes[i] = 2 * e;
                    e += 1;
                    if let Some(slot) = slots.next() {
                        *slot = [k as u32, m];
                    }
                    if m == INVALID {
                        boundary.push(k as u32);
                    }
                } else if let Some(j) = (m as usize).checked_sub(first) {
                    hes[i] = hes[j] | 1;
                } else {
                    later.push(k as u32);
                }
            }
            (boundary, later)
        })
        .collect();
    let mut boundary = Vec::new();
    let mut later = Vec::new();
    for (b, l) in per_chunk {
        boundary.extend(b);
        later.extend(l);
    }
    let twins: Vec<u32> = later
        .par_iter()
        .map(|&k| corner_he[mate[k as usize] as usize] | 1)
        .collect();
    for (&k, twin) in later.iter().zip(twins) {
        corner_he[k as usize] = twin;
    }
    (edge_corners, corner_he, boundary)
}

/// Both halfedges of each edge from its corners (`to`, `next`, `prev`, `face`), in
/// parallel over chunks of edges. Every entry is written here (zeroed memory costs no
/// pass over it); a boundary halfedge's `prev` is left `INVALID`.
#[inline(never)] // one entry of its own in profiles
fn fill_halfedges(
    corners: &Corners<'_>,
    edge_corners: &[[u32; 2]],
    corner_he: &[u32],
    v_out: &[u32],
) -> [Vec<u32>; 4] {
    let n_halfedges = 2 * edge_corners.len();
    let mut h_to = vec![0u32; n_halfedges];
    let mut h_next = vec![0u32; n_halfedges];
    let mut h_prev = vec![0u32; n_halfedges];
    let mut h_face = vec![0u32; n_halfedges];
    h_to.par_chunks_mut(2 * EDGE_CHUNK)
        .zip(h_next.par_chunks_mut(2 * EDGE_CHUNK))
        .zip(h_prev.par_chunks_mut(2 * EDGE_CHUNK))
        .zip(h_face.par_chunks_mut(2 * EDGE_CHUNK))
        .zip(edge_corners.par_chunks(EDGE_CHUNK))
        .for_each(|((((to, next), prev), face), edges)| {
            let he = |k: u32| corner_he[k as usize];
            // Both halfedges of an edge at a time: `[2e, 2e + 1]`.
            let halves = to
                .chunks_exact_mut(2)
                .zip(next.chunks_exact_mut(2))
                .zip(prev.chunks_exact_mut(2))
                .zip(face.chunks_exact_mut(2))
                .zip(edges);
            for ((((to, next), prev), face), &[k, m]) in halves {
                let (f, nk, pk) = corners.links(k);
                to[0] = corners.from(nk);
                face[0] = f;
                next[0] = he(nk);
                prev[0] = he(pk);
                if m == INVALID {
                    // Boundary: b -> a after a -> b, then the boundary halfedge leaving a.
                    let a = corners.from(k);
                    to[1] = a;
                    face[1] = INVALID;
                    next[1] = v_out[a as usize];
                    prev[1] = INVALID;
                } else {
                    let (f, nm, pm) = corners.links(m);
                    to[1] = corners.from(nm);
                    face[1] = f;
                    next[1] = he(nm);
                    prev[1] = he(pm);
                }
            }
        });
    [h_to, h_next, h_prev, h_face]
}

/// Whether corner `k` with mate `m` opens its edge: it has no mate, or comes first.
#[inline]
fn opens(k: usize, m: u32) -> bool {
    m == INVALID || k < m as usize
}

/// A vertex whose fans are all closed (or one open fan plus closed ones) shows up as a
/// circulation shorter than its degree. Rotating an outgoing halfedge
/// (`twin(prev(h))`) is a permutation of the halfedges, so every circulation closes;
/// each one covers a vertex's outgoing halfedges exactly when the circulations of all
/// vertices together cover every halfedge. That sum is computed in parallel; only when
/// it falls short are the vertices checked one by one, in order, for the first one at
/// fault.
#[inline(never)] // one entry of its own in profiles
fn check_manifold_vertices(mesh: &HalfedgeMesh, list: &PolygonList) -> Result<(), TopologyError> {
    let n_vertices = mesh.v_out.len();
    let n_halfedges = mesh.h_to.len();
    let covered: usize = (0..n_vertices)
        .into_par_iter()
        .with_min_len(PARALLEL_CHUNK)
        .map(|v| circulation_length(mesh, v, n_halfedges))
        .sum();
    if covered != n_halfedges {
        let mut degree = vec![0u32; n_vertices];
        for h in 0..n_halfedges {
            degree[mesh.h_to[h ^ 1] as usize] += 1;
        }
        for v in mesh.vertices() {
            let d = degree[v.index()] as usize;
            if d > 0 && mesh.halfedges_around_vertex(v).take(d + 1).count() != d {
                let fans = count_fans(list, v.raw()).max(2);
                return Err(TopologyError::NonManifoldVertex {
                    vertex: v.raw(),
                    fans,
                });
            }
        }
    }
    Ok(())
}

/// The corners leaving each vertex, in corner order: `out[start[v]..start[v + 1]]`
/// holds, for each corner `k` at `v`, where its edge ends and `k` (`[to, k]`).
struct Leaving {
    start: Vec<u32>,
    out: Vec<[u32; 2]>,
}

impl Leaving {
    /// A counting sort of the corners by vertex. Both passes run in parallel over
    /// ranges of vertices: each task reads every corner and handles those at its
    /// vertices, so the lists are in corner order whatever the number of tasks.
    #[inline(never)] // one entry of its own in profiles
    fn new(corners: &Corners<'_>, n_vertices: usize) -> Self {
        let n_corners = corners.indices.len();
        let tasks = if n_corners < 2 * PARALLEL_CHUNK {
            1
        } else {
            rayon::current_num_threads().clamp(1, 8)
        };
        let bounds: Vec<usize> = (0..=tasks).map(|t| t * n_vertices / tasks).collect();
        let mut start = vec![0u32; n_vertices + 1];
        {
            let mut pieces = Vec::with_capacity(tasks);
            let mut rest = &mut start[1..];
            for w in bounds.windows(2) {
                let (piece, tail) = rest.split_at_mut(w[1] - w[0]);
                pieces.push((w[0], piece));
                rest = tail;
            }
            pieces.into_par_iter().for_each(|(v0, counts)| {
                let v1 = v0 + counts.len();
                for &v in corners.indices {
                    let v = v as usize;
                    if (v0..v1).contains(&v) {
                        counts[v - v0] += 1;
                    }
                }
            });
        }
        for v in 0..n_vertices {
            start[v + 1] += start[v];
        }
        let mut out = vec![[0u32; 2]; n_corners];
        {
            let mut pieces = Vec::with_capacity(tasks);
            let mut rest = &mut out[..];
            for w in bounds.windows(2) {
                let len = (start[w[1]] - start[w[0]]) as usize;
                let (piece, tail) = rest.split_at_mut(len);
                pieces.push((w[0], w[1], piece));
                rest = tail;
            }
            let start = &start;
            pieces.into_par_iter().for_each(|(v0, v1, piece)| {
                let base = start[v0];
                let mut fill: Vec<u32> = start[v0..v1].iter().map(|&s| s - base).collect();
                corners.edges_in(0..n_corners, |k, from, to| {
                    let v = from as usize;
                    if (v0..v1).contains(&v) {
                        let slot = &mut fill[v - v0];
                        piece[*slot as usize] = [to, k];
                        *slot += 1;
                    }
                });
            });
        }
        Self { start, out }
    }

    /// The entries of the corners leaving `v`.
    #[inline]
    fn of(&self, v: u32) -> &[[u32; 2]] {
        &self.out[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// The last corner at each vertex (`INVALID` for a vertex without faces).
    #[inline(never)] // one entry of its own in profiles
    fn last_corners(&self) -> Vec<u32> {
        self.start[1..]
            .par_iter()
            .zip(&self.start[..self.start.len() - 1])
            .with_min_len(CHUNK)
            .map(|(&end, &begin)| {
                if end > begin {
                    self.out[end as usize - 1][1]
                } else {
                    INVALID
                }
            })
            .collect()
    }

    /// The corner running the other way along each corner's edge (`INVALID` on the
    /// boundary) and the number of edges each chunk of corners opens, or `None` when
    /// some edge is used by more than two corners or twice in the same direction.
    ///
    /// The mate of corner `a -> b` is the one corner in `b`'s list that ends at `a`.
    /// A valid mesh is checked this way without sorting the edges: a vertex pair with
    /// more than two corners, or with two in the same direction, shows up either as
    /// two corners `b -> a` (when some corner runs `a -> b`) or, for a pair without a
    /// corner `b -> a`, as a second corner `a -> b` in `a`'s list, which is checked for
    /// boundary corners only. When the check fails, [`mates_from_groups`] finds the
    /// error to report.
    #[inline(never)] // one entry of its own in profiles
    fn mates(&self, corners: &Corners<'_>) -> Option<(Vec<u32>, Vec<usize>)> {
        let mut mate = vec![0u32; corners.indices.len()];
        let openers: Vec<Option<usize>> = mate
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, mates)| {
                let mut openers = 0;
                let mut valid = true;
                let first = c * CHUNK;
                corners.edges_in(first..first + mates.len(), |k, a, b| {
                    // The corners b -> a: one (an inner edge) or none (the boundary).
                    let mut found = INVALID;
                    for &[to, corner] in self.of(b) {
                        if to == a {
                            valid &= found == INVALID;
                            found = corner;
                        }
                    }
                    if found == INVALID {
                        valid &= self.of(a).iter().filter(|&&[to, _]| to == b).count() == 1;
                    }
                    mates[k as usize - first] = found;
                    openers += usize::from(opens(k as usize, found));
                });
                valid.then_some(openers)
            })
            .collect();
        let openers = openers.into_iter().collect::<Option<Vec<usize>>>()?;
        Some((mate, openers))
    }
}

/// The mates of [`mates`] from the corners sorted by vertex pair, validating every
/// pair: among the vertex pairs used by more than two corners or twice in the same
/// direction, the error names the one whose first corner comes first. This is the
/// path for lists [`mates`] rejects, and the reference it is tested against.
pub(super) fn mates_from_groups(
    corners: &Corners<'_>,
    origin: Origin<'_>,
) -> Result<Vec<u32>, TopologyError> {
    let (sorted, starts) = corners.edge_groups();
    let mut worst: Option<(u32, TopologyError)> = None;
    let mut mate = vec![INVALID; corners.indices.len()];
    for g in starts.windows(2) {
        let group = &sorted[g[0]..g[1]];
        match *group {
            [_] => {}
            [k1, k2] if corners.from(k1) != corners.from(k2) => {
                mate[k1 as usize] = k2;
                mate[k2 as usize] = k1;
            }
            _ => {
                // The error is made only for the group met first so far.
                let first = group[0];
                if worst.as_ref().is_none_or(|(k, _)| first < *k) {
                    worst = Some((first, group_error(corners, group, origin)));
                }
            }
        }
    }
    match worst {
        Some((_, err)) => Err(err),
        None => Ok(mate),
    }
}

/// The number of outgoing halfedges of `v` met by rotating around it from its
/// outgoing halfedge (0 for an isolated vertex); more than `limit` stops the walk.
fn circulation_length(mesh: &HalfedgeMesh, v: usize, limit: usize) -> usize {
    let start = mesh.v_out[v];
    if start == INVALID {
        return 0;
    }
    let mut h = start;
    let mut steps = 0;
    loop {
        steps += 1;
        let prev = mesh.h_prev[h as usize];
        if prev == INVALID {
            // Not reached for a mesh built this far; counted as a shortfall.
            return 0;
        }
        h = prev ^ 1;
        if h == start || steps > limit {
            return steps;
        }
    }
}

/// The error of an edge group that is neither a boundary edge nor a consistently
/// oriented pair.
fn group_error(corners: &Corners<'_>, group: &[u32], origin: Origin<'_>) -> TopologyError {
    match *group {
        [k1, k2] => TopologyError::InconsistentOrientation {
            from: corners.from(k1),
            to: corners.to(k1),
            faces: [origin.of(corners.face(k1)), origin.of(corners.face(k2))],
        },
        _ => {
            let (a, b) = (corners.from(group[0]), corners.to(group[0]));
            TopologyError::NonManifoldEdge {
                a: a.min(b),
                b: a.max(b),
                faces: group.iter().map(|&k| origin.of(corners.face(k))).collect(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// The pairing by vertex lists, without the edge counts.
    fn mates(corners: &Corners<'_>, n_vertices: usize) -> Option<Vec<u32>> {
        let leaving = Leaving::new(corners, n_vertices);
        let (mate, openers) = leaving.mates(corners)?;
        let counted: Vec<usize> = mate
            .chunks(CHUNK)
            .enumerate()
            .map(|(c, mates)| {
                (c * CHUNK..)
                    .zip(mates)
                    .filter(|&(k, &m)| opens(k, m))
                    .count()
            })
            .collect();
        assert_eq!(openers, counted);
        Some(mate)
    }

    /// The assembly as it was before it ran in parallel: one pass over the corners in
    /// order, scattering into the halfedge arrays (the reference of the tests).
    fn assemble_sequential(
        n_vertices: usize,
        list: &PolygonList,
        origin: Origin<'_>,
    ) -> Result<HalfedgeMesh, TopologyError> {
        let corners = Corners::new(list);
        let n_corners = corners.indices.len();
        let mate = mates_from_groups(&corners, origin)?;

        // Edge `e` is numbered by its first corner in corner order: a corner starts a new
        // edge unless its mate comes before it.
        let n_edges = mate
            .iter()
            .enumerate()
            .filter(|&(k, &m)| m == INVALID || k < m as usize)
            .count();
        check_count("halfedges", 2 * n_edges)?;
        let n_halfedges = 2 * n_edges;
        // Every entry of these four is written below (zeroed memory costs no pass over it);
        // `h_face` keeps `INVALID` on the boundary.
        let mut corner_he = vec![0; n_corners];
        let mut h_to = vec![0; n_halfedges];
        let mut h_next = vec![0; n_halfedges];
        let mut h_prev = vec![0; n_halfedges];
        let mut h_face = vec![INVALID; n_halfedges];
        let mut v_out = vec![INVALID; n_vertices];

        let mut e = 0u32;
        for k in 0..n_corners {
            let m = mate[k];
            if m != INVALID && (m as usize) < k {
                // The mate opened the edge and runs the first direction.
                corner_he[k] = corner_he[m as usize] | 1;
                continue;
            }
            let h = 2 * e;
            e += 1;
            corner_he[k] = h;
            if m == INVALID {
                // Boundary edge: the twin of the inner halfedge a -> b is b -> a, without face.
                let t = h | 1;
                h_to[t as usize] = corners.from(k as u32);
                let b = corners.to(k as u32) as usize;
                if v_out[b] != INVALID {
                    let fans = count_fans(list, b as u32).max(2);
                    return Err(TopologyError::NonManifoldVertex {
                        vertex: b as u32,
                        fans,
                    });
                }
                v_out[b] = t;
            }
        }
        drop(mate);
        if corners.triangles() {
            // The same as the general loop below, a triangle at a time.
            let triangles = corner_he
                .chunks_exact(3)
                .zip(corners.indices.chunks_exact(3));
            for (f, (he, to)) in triangles.enumerate() {
                for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                    let h = he[i] as usize;
                    h_to[h] = to[j];
                    h_face[h] = f as u32;
                    h_next[h] = he[j];
                    h_prev[he[j] as usize] = he[i];
                }
            }
        } else {
            for k in 0..n_corners {
                let h = corner_he[k] as usize;
                let nk = corners.next(k as u32) as usize;
                h_to[h] = corners.indices[nk];
                h_face[h] = corners.face(k as u32) as u32;
                h_next[h] = corner_he[nk];
                h_prev[corner_he[nk] as usize] = h as u32;
            }
        }
        // Link boundary loops: after b -> a comes the boundary halfedge leaving a.
        for t in (1..n_halfedges).step_by(2) {
            if h_face[t] == INVALID {
                let n = v_out[h_to[t] as usize];
                h_next[t] = n;
                h_prev[n as usize] = t as u32;
            }
        }
        // Interior vertices: the halfedge leaving the vertex in its last face (where
        // OpenMesh's `add_face` leaves it, so circulators start at the same neighbour).
        let on_boundary: Vec<bool> = v_out.iter().map(|&h| h != INVALID).collect();
        for (&v, &h) in corners.indices.iter().zip(&corner_he) {
            if !on_boundary[v as usize] {
                v_out[v as usize] = h;
            }
        }
        let f_he: Vec<u32> = (0..list.len())
            .map(|f| corner_he[list.face_range(f).end - 1])
            .collect();

        let mesh = HalfedgeMesh {
            v_out,
            h_to,
            h_next,
            h_prev,
            h_face,
            f_he,
        };

        // Pinched vertices, as the parallel assembly checks them.
        check_manifold_vertices(&mesh, list)?;
        Ok(mesh)
    }

    /// Faces of `len` corners (a range of lengths) over a few vertices: many shared
    /// edges, and every kind of edge defect (a pair used three times, twice the same way
    /// round), pinched vertices, boundaries.
    fn soup(len: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = (usize, PolygonList)> {
        (4usize..9).prop_flat_map(move |n| {
            let face = prop::sample::subsequence((0..n as u32).collect::<Vec<_>>(), len.clone())
                .prop_shuffle();
            (Just(n), prop::collection::vec(face, 1..12)).prop_map(|(n, faces)| {
                let mut list = PolygonList::new();
                for f in &faces {
                    list.push(f);
                }
                (n, list)
            })
        })
    }

    fn polygon_soup() -> impl Strategy<Value = (usize, PolygonList)> {
        soup(3..=4)
    }

    proptest! {
        /// The pairing by vertex lists accepts exactly the lists the pairing by sorted
        /// vertex pairs accepts, with the same mates.
        #[test]
        fn mates_agree_with_the_sorted_edge_groups((n, list) in polygon_soup()) {
            let corners = Corners::new(&list);
            let reference = mates_from_groups(&corners, Origin(&[]));
            match mates(&corners, n) {
                Some(mate) => prop_assert_eq!(Ok(mate), reference),
                None => prop_assert!(reference.is_err()),
            }
        }

        /// The parallel assembly gives the sequential one's mesh or error, for
        /// triangles and for mixed polygons.
        #[test]
        fn assembly_agrees_with_the_sequential_one((n, list) in polygon_soup()) {
            prop_assert_eq!(
                assemble(n, &list, Origin(&[])),
                assemble_sequential(n, &list, Origin(&[]))
            );
        }

        #[test]
        fn triangle_assembly_agrees_with_the_sequential_one((n, list) in soup(3..=3)) {
            prop_assert_eq!(
                assemble(n, &list, Origin(&[])),
                assemble_sequential(n, &list, Origin(&[]))
            );
        }
    }

    /// A grid of `nx × ny` squares cut into triangles (or kept as quads), with the
    /// faces for which `drop` holds left out.
    fn holed_grid(nx: u32, ny: u32, quads: bool, drop: impl Fn(u32) -> bool) -> PolygonList {
        let mut list = PolygonList::new();
        let id = |i: u32, j: u32| j * (nx + 1) + i;
        let mut f = 0;
        for j in 0..ny {
            for i in 0..nx {
                let [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                let faces: Vec<Vec<u32>> = if quads {
                    vec![vec![a, b, c, d]]
                } else {
                    vec![vec![a, b, c], vec![a, c, d]]
                };
                for face in faces {
                    if !drop(f) {
                        list.push(&face);
                    }
                    f += 1;
                }
            }
        }
        list
    }

    /// Large meshes (many chunks of corners and edges) with boundaries and holes, with
    /// and without pinched vertices: the same mesh or error as the sequential assembly,
    /// on one, two and three threads.
    #[test]
    fn large_meshes_agree_with_the_sequential_assembly() {
        let (nx, ny) = (160, 150);
        let n = ((nx + 1) * (ny + 1)) as usize;
        let hash = |f: u32| f.wrapping_mul(2_654_435_761) >> 20;
        let cases = [
            holed_grid(nx, ny, false, |_| false),
            holed_grid(nx, ny, true, |_| false),
            // Sparse holes: some vertices pinched (two triangles meeting at a corner).
            holed_grid(nx, ny, false, |f| hash(f) % 97 == 0),
            // Holes of whole squares only: boundaries, no pinched vertex.
            holed_grid(nx, ny, false, |f| {
                hash(f / 2) % 211 == 0 && (f / 2) % nx != 0
            }),
            holed_grid(nx, ny, true, |f| hash(f) % 150 == 3),
        ];
        let mut outcomes = Vec::new();
        for list in &cases {
            let reference = assemble_sequential(n, list, Origin(&[]));
            for threads in [1, 2, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("a thread pool");
                let built = pool.install(|| assemble(n, list, Origin(&[])));
                assert_eq!(built, reference, "{threads} threads");
            }
            outcomes.push(reference.is_ok());
        }
        // Both kinds of outcome are covered.
        assert!(
            outcomes.contains(&true) && outcomes.contains(&false),
            "{outcomes:?}"
        );
    }

    /// A closed triangle mesh pairs every corner.
    #[test]
    fn a_closed_mesh_pairs_every_corner() {
        let tet = PolygonList::from_triangles(&[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
        let corners = Corners::new(&tet);
        let mate = mates(&corners, 4).expect("valid");
        assert!(mate.iter().all(|&m| m != INVALID));
        assert_eq!(Ok(mate), mates_from_groups(&corners, Origin(&[])));
    }
}
