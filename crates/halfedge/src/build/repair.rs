//! The builder's opt-in repairs on the polygon list: re-orientation and the split of
//! non-manifold vertices.

use std::collections::HashMap;

use super::corners::{Corners, corner_fans};
use super::{BuildReport, Origin, VertexSplit, check_count};
use crate::error::TopologyError;
use crate::ids::VertexId;
use crate::mesh::INVALID;
use crate::polygons::PolygonList;

/// Flip faces so that every component is consistently oriented (breadth-first from the
/// lowest face of each component).
pub(super) fn reorient(
    list: &mut PolygonList,
    origin: Origin<'_>,
    report: &mut BuildReport,
) -> Result<(), TopologyError> {
    let corners = Corners::new(list);
    let (sorted, starts) = corners.edge_groups();
    let n_faces = list.len();
    // Face adjacency across manifold edges: (neighbour, whether the two faces traverse
    // the edge in the same direction, i.e. disagree).
    let mut adjacency: Vec<Vec<(u32, bool)>> = vec![Vec::new(); n_faces];
    for g in starts.windows(2) {
        if let [k1, k2] = sorted[g[0]..g[1]] {
            let same = corners.from(k1) == corners.from(k2);
            let (f1, f2) = (corners.face(k1), corners.face(k2));
            adjacency[f1].push((f2 as u32, same));
            adjacency[f2].push((f1 as u32, same));
        }
    }
    let mut flip: Vec<Option<bool>> = vec![None; n_faces];
    let mut queue = std::collections::VecDeque::new();
    for start in 0..n_faces {
        if flip[start].is_some() {
            continue;
        }
        flip[start] = Some(false);
        queue.push_back(start);
        while let Some(f) = queue.pop_front() {
            let flip_f = flip[f].unwrap_or(false);
            for &(n, same) in &adjacency[f] {
                let want = flip_f ^ same;
                match flip[n as usize] {
                    None => {
                        flip[n as usize] = Some(want);
                        queue.push_back(n as usize);
                    }
                    Some(have) if have != want => {
                        return Err(TopologyError::NonOrientable {
                            face: origin.of(start),
                        });
                    }
                    Some(_) => {}
                }
            }
        }
    }
    if flip.iter().all(|f| *f != Some(true)) {
        return Ok(());
    }
    let mut fixed = PolygonList::with_capacity(list.len(), list.n_corners());
    let mut buf = Vec::new();
    for (f, face) in list.iter().enumerate() {
        buf.clear();
        buf.extend_from_slice(face);
        if flip[f] == Some(true) {
            buf[1..].reverse();
            report.flipped_faces.push(origin.of(f));
        }
        fixed.push(&buf);
    }
    *list = fixed;
    Ok(())
}

pub(super) fn split_nonmanifold_vertices(
    list: &mut PolygonList,
    n_vertices: &mut usize,
    report: &mut BuildReport,
) -> Result<(), TopologyError> {
    let corners = Corners::new(list);
    let (sorted, starts) = corners.edge_groups();
    let fans = corner_fans(&corners, &sorted, &starts);
    let mut first_root = vec![INVALID; *n_vertices];
    let mut new_vertex: HashMap<u32, u32> = HashMap::new();
    let mut rewritten = list.indices().to_vec();
    for k in 0..corners.indices.len() as u32 {
        let v = corners.from(k);
        let root = fans.find(k);
        let first = &mut first_root[v as usize];
        if *first == INVALID {
            *first = root;
        } else if *first != root {
            let id = match new_vertex.get(&root) {
                Some(&id) => id,
                None => {
                    check_count("vertices", *n_vertices + 1)?;
                    let id = *n_vertices as u32;
                    *n_vertices += 1;
                    new_vertex.insert(root, id);
                    report.split_vertices.push(VertexSplit {
                        vertex: VertexId::new(id),
                        original: VertexId::new(v),
                    });
                    id
                }
            };
            rewritten[k as usize] = id;
        }
    }
    if report.split_vertices.is_empty() {
        return Ok(());
    }
    let mut fixed = PolygonList::with_capacity(list.len(), rewritten.len());
    for f in 0..list.len() {
        fixed.push(&rewritten[list.face_range(f)]);
    }
    *list = fixed;
    Ok(())
}
