//! The half-edge arrays from a polygon list whose faces are individually valid, with
//! the edge and vertex checks that name the offending input faces.

use rayon::prelude::*;

use super::corners::{Corners, PARALLEL_CHUNK, count_fans};
use super::{Origin, check_count};
use crate::error::TopologyError;
use crate::mesh::{HalfedgeMesh, INVALID};
use crate::polygons::PolygonList;

/// Builds the half-edge arrays from a list whose faces are individually valid.
pub(super) fn assemble(
    n_vertices: usize,
    list: &PolygonList,
    origin: Origin<'_>,
) -> Result<HalfedgeMesh, TopologyError> {
    let corners = Corners::new(list);
    let n_corners = corners.indices.len();
    let mate = match mates(&corners, n_vertices) {
        Some(mate) => mate,
        None => mates_from_groups(&corners, origin)?,
    };

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
    let f_he: Vec<u32> = list.offsets()[1..]
        .iter()
        .map(|&end| corner_he[end - 1])
        .collect();

    let mesh = HalfedgeMesh {
        v_out,
        h_to,
        h_next,
        h_prev,
        h_face,
        f_he,
    };

    // A vertex whose fans are all closed (or one open fan plus closed ones) shows up as
    // a circulation shorter than its degree. Rotating an outgoing halfedge
    // (`twin(prev(h))`) is a permutation of the halfedges, so every circulation closes;
    // each one covers a vertex's outgoing halfedges exactly when the circulations of
    // all vertices together cover every halfedge. That sum is computed in parallel;
    // only when it falls short are the vertices checked one by one, in order, for the
    // first one at fault.
    let covered: usize = (0..n_vertices)
        .into_par_iter()
        .with_min_len(PARALLEL_CHUNK)
        .map(|v| circulation_length(&mesh, v, n_halfedges))
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
    Ok(mesh)
}

/// The corner running the other way along each corner's edge (`INVALID` on the
/// boundary), or `None` when some edge is used by more than two corners or twice in the
/// same direction.
///
/// The corners leaving each vertex are listed together (a counting sort by vertex);
/// the mate of corner `a -> b` is then the one corner in `b`'s list that ends at `a`.
/// A valid mesh is checked this way without sorting the edges: a vertex pair with
/// more than two corners, or with two in the same direction, shows up either as two
/// corners `b -> a` (when some corner runs `a -> b`) or, for a pair without a corner
/// `b -> a`, as a second corner `a -> b` in `a`'s list, which is checked for boundary
/// corners only. When the check fails, [`mates_from_groups`] finds the error to report.
fn mates(corners: &Corners<'_>, n_vertices: usize) -> Option<Vec<u32>> {
    let n_corners = corners.indices.len();
    // `start[v]..start[v + 1]` lists, in `out_to`, where the corners leaving `v` end,
    // and in `out_corner` which corners they are (in corner order).
    let mut start = vec![0u32; n_vertices + 1];
    for &v in corners.indices {
        start[v as usize + 1] += 1;
    }
    for v in 0..n_vertices {
        start[v + 1] += start[v];
    }
    let mut out_to = vec![0u32; n_corners];
    let mut out_corner = vec![0u32; n_corners];
    let mut fill = start[..n_vertices].to_vec();
    for k in 0..n_corners as u32 {
        let slot = &mut fill[corners.from(k) as usize];
        out_to[*slot as usize] = corners.to(k);
        out_corner[*slot as usize] = k;
        *slot += 1;
    }
    drop(fill);
    let leaving = |v: u32| start[v as usize] as usize..start[v as usize + 1] as usize;

    let mut mate = vec![INVALID; n_corners];
    let valid = mate
        .par_chunks_mut(PARALLEL_CHUNK)
        .enumerate()
        .all(|(chunk, mates)| {
            let first = (chunk * PARALLEL_CHUNK) as u32;
            mates.iter_mut().zip(first..).all(|(mate, k)| {
                let (a, b) = (corners.from(k), corners.to(k));
                let back = leaving(b);
                let mut found = INVALID;
                for i in back {
                    if out_to[i] == a {
                        if found != INVALID {
                            return false;
                        }
                        found = out_corner[i];
                    }
                }
                *mate = found;
                found != INVALID || out_to[leaving(a)].iter().filter(|&&to| to == b).count() == 1
            })
        });
    valid.then_some(mate)
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

    /// Triangles and quads over a few vertices: many shared edges, and every kind of
    /// edge defect (a pair used three times, twice the same way round).
    fn polygon_soup() -> impl Strategy<Value = (usize, PolygonList)> {
        (4usize..9).prop_flat_map(|n| {
            let face =
                prop::sample::subsequence((0..n as u32).collect::<Vec<_>>(), 3..=4).prop_shuffle();
            (Just(n), prop::collection::vec(face, 1..12)).prop_map(|(n, faces)| {
                let mut list = PolygonList::new();
                for f in &faces {
                    list.push(f);
                }
                (n, list)
            })
        })
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
