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
    let (sorted, starts) = corners.edge_groups();
    let n_corners = corners.indices.len();

    // Validate edge groups and pair each corner with the corner that runs the other
    // way along its edge (`INVALID` on the boundary); among violations report the one
    // met first in face order.
    let mut worst: Option<(u32, TopologyError)> = None;
    let mut mate = vec![INVALID; n_corners];
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
                    worst = Some((first, group_error(&corners, group, origin)));
                }
            }
        }
    }
    if let Some((_, err)) = worst {
        return Err(err);
    }
    drop(sorted);
    drop(starts);

    // Edge `e` is numbered by its first corner in corner order: a corner starts a new
    // edge unless its mate comes before it.
    let n_edges = mate
        .iter()
        .enumerate()
        .filter(|&(k, &m)| m == INVALID || k < m as usize)
        .count();
    check_count("halfedges", 2 * n_edges)?;
    let n_halfedges = 2 * n_edges;
    let mut corner_he = vec![INVALID; n_corners];
    let mut h_to = vec![INVALID; n_halfedges];
    let mut h_face = vec![INVALID; n_halfedges];
    let mut h_next = vec![INVALID; n_halfedges];
    let mut h_prev = vec![INVALID; n_halfedges];
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
    for k in 0..n_corners {
        let h = corner_he[k] as usize;
        let nk = corners.next[k] as usize;
        h_to[h] = corners.indices[nk];
        h_face[h] = corners.face[k];
        h_next[h] = corner_he[nk];
        h_prev[corner_he[nk] as usize] = h as u32;
    }
    // Link boundary loops: after b -> a comes the boundary halfedge leaving a.
    for t in (1..n_halfedges).step_by(2) {
        if h_face[t] == INVALID && h_to[t] != INVALID {
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
