//! Building a [`HalfedgeMesh`] from a polygon list, with validation and opt-in repairs.

use std::collections::HashMap;

use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use crate::error::TopologyError;
use crate::ids::VertexId;
use crate::mesh::{HalfedgeMesh, INVALID};
use crate::polygons::PolygonList;

/// The largest number of elements of one kind (handles are `u32`; `u32::MAX` is
/// reserved internally).
pub const MAX_ELEMENTS: usize = u32::MAX as usize;

/// Opt-in repairs applied while building. All are off by default: without them every
/// problem is an error. Each repair that acts is recorded in the [`BuildReport`].
///
/// # Examples
/// ```
/// use beltrami_halfedge::{BuildOptions, HalfedgeMesh};
/// // Face 1 is wound the other way round.
/// let faces = [[0u32, 1, 2], [0, 1, 3]];
/// assert!(HalfedgeMesh::from_polygons(4, &faces).is_err());
/// let (mesh, report) =
///     HalfedgeMesh::build(4, &faces, &BuildOptions::new().reorient(true)).unwrap();
/// assert_eq!(report.flipped_faces, [1]);
/// assert_eq!(mesh.n_faces(), 2);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BuildOptions {
    drop_degenerate_faces: bool,
    reorient: bool,
    split_nonmanifold_vertices: bool,
}

impl BuildOptions {
    /// No repairs: every problem is an error.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Every repair enabled.
    #[must_use]
    pub fn repair_all() -> Self {
        Self {
            drop_degenerate_faces: true,
            reorient: true,
            split_nonmanifold_vertices: true,
        }
    }

    /// Drop faces with fewer than three vertices or with a repeated vertex instead of
    /// failing. Out-of-range indices are still an error (the file is broken, not
    /// degenerate).
    #[must_use]
    pub fn drop_degenerate_faces(mut self, yes: bool) -> Self {
        self.drop_degenerate_faces = yes;
        self
    }

    /// Re-orient faces so that each connected component is consistently oriented. The
    /// lowest-numbered face of a component keeps its orientation; a flipped face keeps
    /// its first vertex and reverses the rest. Fails with
    /// [`TopologyError::NonOrientable`] when no consistent orientation exists.
    #[must_use]
    pub fn reorient(mut self, yes: bool) -> Self {
        self.reorient = yes;
        self
    }

    /// Give every extra fan of faces around a pinched vertex its own copy of the vertex.
    /// New vertices are numbered after the input vertices; the caller appends their
    /// positions (copies of the originals) in the order of
    /// [`BuildReport::split_vertices`].
    #[must_use]
    pub fn split_nonmanifold_vertices(mut self, yes: bool) -> Self {
        self.split_nonmanifold_vertices = yes;
        self
    }

    /// Whether degenerate faces are dropped.
    #[must_use]
    pub fn drops_degenerate_faces(&self) -> bool {
        self.drop_degenerate_faces
    }

    /// Whether faces are re-oriented.
    #[must_use]
    pub fn reorients(&self) -> bool {
        self.reorient
    }

    /// Whether non-manifold vertices are split.
    #[must_use]
    pub fn splits_nonmanifold_vertices(&self) -> bool {
        self.split_nonmanifold_vertices
    }
}

/// A vertex added by splitting a non-manifold vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexSplit {
    /// The new vertex (numbered after all input vertices).
    pub vertex: VertexId,
    /// The input vertex it copies.
    pub original: VertexId,
}

/// What the opt-in repairs of [`HalfedgeMesh::build`] changed. Empty when the input
/// needed no repair.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct BuildReport {
    /// Input indices of faces dropped as degenerate, ascending.
    pub dropped_faces: Vec<usize>,
    /// Input indices of faces whose orientation was reversed, ascending.
    pub flipped_faces: Vec<usize>,
    /// Vertices added by splitting non-manifold vertices, in the order of their ids.
    pub split_vertices: Vec<VertexSplit>,
    /// For each face of the built mesh, its input index. Empty when no face was dropped
    /// (then face `f` is input face `f`).
    pub face_origin: Vec<usize>,
}

impl BuildReport {
    /// Whether no repair acted.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.dropped_faces.is_empty()
            && self.flipped_faces.is_empty()
            && self.split_vertices.is_empty()
    }
}

impl HalfedgeMesh {
    /// Builds the connectivity of `n_vertices` vertices and the given faces, rejecting
    /// anything that is not an oriented 2-manifold (with boundary).
    ///
    /// Faces list vertex indices (0-based) counter-clockwise; triangles and larger
    /// polygons are accepted. Vertices used by no face are kept as isolated vertices.
    /// Edge `e` is numbered by the first appearance of its vertex pair when walking the
    /// faces in order, and its halfedge `2e` runs in that first direction (as in OpenMesh).
    ///
    /// # Errors
    /// The first problem found, with input indices: [`TopologyError::VertexOutOfRange`],
    /// [`FaceTooSmall`](TopologyError::FaceTooSmall),
    /// [`RepeatedVertex`](TopologyError::RepeatedVertex),
    /// [`NonManifoldEdge`](TopologyError::NonManifoldEdge),
    /// [`InconsistentOrientation`](TopologyError::InconsistentOrientation),
    /// [`NonManifoldVertex`](TopologyError::NonManifoldVertex),
    /// [`TooManyElements`](TopologyError::TooManyElements). Among edge problems, the one
    /// whose first face comes first in the input is reported.
    ///
    /// # Complexity
    /// O(C log C) time and O(C) memory for C face corners.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{HalfedgeMesh, TopologyError};
    /// let tet = [[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    /// let mesh = HalfedgeMesh::from_polygons(4, &tet).unwrap();
    /// assert!(mesh.is_closed());
    /// assert_eq!(mesh.euler_characteristic(), 2);
    ///
    /// let err = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 5]]).unwrap_err();
    /// assert_eq!(err.to_string(), "face 0 refers to vertex 5, but there are only 3 vertices");
    /// ```
    pub fn from_polygons<F: AsRef<[u32]>>(
        n_vertices: usize,
        faces: impl IntoIterator<Item = F>,
    ) -> Result<Self, TopologyError> {
        Self::build(n_vertices, faces, &BuildOptions::new()).map(|(mesh, _)| mesh)
    }

    /// Like [`from_polygons`](Self::from_polygons), with the opt-in repairs of `options`.
    /// Returns the mesh and a report of what was repaired.
    ///
    /// # Errors
    /// As [`from_polygons`](Self::from_polygons) for every problem that the enabled
    /// repairs do not fix, and [`TopologyError::NonOrientable`] when re-orientation is
    /// asked of a non-orientable component.
    pub fn build<F: AsRef<[u32]>>(
        n_vertices: usize,
        faces: impl IntoIterator<Item = F>,
        options: &BuildOptions,
    ) -> Result<(Self, BuildReport), TopologyError> {
        check_count("vertices", n_vertices)?;
        let mut report = BuildReport::default();
        let mut list = PolygonList::new();
        // Input index of each kept face; empty while no face was dropped (then face
        // `f` is input face `f`), so a mesh that needs no repair never fills it.
        let mut origin = Vec::new();
        let mut scratch = Vec::new();
        for (fi, face) in faces.into_iter().enumerate() {
            let face = face.as_ref();
            if let Some(&v) = face.iter().find(|&&v| v as usize >= n_vertices) {
                return Err(TopologyError::VertexOutOfRange {
                    face: fi,
                    vertex: v,
                    n_vertices,
                });
            }
            let problem = if face.len() < 3 {
                Some(TopologyError::FaceTooSmall {
                    face: fi,
                    len: face.len(),
                })
            } else {
                repeated_vertex(face, &mut scratch)
                    .map(|vertex| TopologyError::RepeatedVertex { face: fi, vertex })
            };
            match problem {
                Some(_) if options.drop_degenerate_faces => {
                    if report.dropped_faces.is_empty() {
                        origin.extend(0..fi);
                    }
                    report.dropped_faces.push(fi);
                }
                Some(err) => return Err(err),
                None => {
                    list.push(face);
                    if !report.dropped_faces.is_empty() {
                        origin.push(fi);
                    }
                }
            }
        }
        check_count("faces", list.len())?;
        check_count("halfedges", 2 * list.n_corners())?;

        let origin = Origin(&origin);
        if options.reorient {
            reorient(&mut list, origin, &mut report)?;
        }
        let mut n_vertices = n_vertices;
        if options.split_nonmanifold_vertices {
            split_nonmanifold_vertices(&mut list, &mut n_vertices, &mut report)?;
        }
        let mesh = assemble(n_vertices, &list, origin)?;
        if !report.dropped_faces.is_empty() {
            report.face_origin = origin.0.to_vec();
        }
        Ok((mesh, report))
    }
}

/// The input index of each face of the polygon list being built.
#[derive(Clone, Copy)]
struct Origin<'a>(&'a [usize]);

impl Origin<'_> {
    /// The input index of face `f` (`f` itself when no face was dropped).
    fn of(self, f: usize) -> usize {
        if self.0.is_empty() { f } else { self.0[f] }
    }
}

pub(crate) fn check_count(kind: &'static str, count: usize) -> Result<(), TopologyError> {
    if count > MAX_ELEMENTS {
        return Err(TopologyError::TooManyElements {
            kind,
            count,
            max: MAX_ELEMENTS,
        });
    }
    Ok(())
}

/// The first vertex that appears twice in `face` (in order of its second appearance).
pub(crate) fn repeated_vertex(face: &[u32], scratch: &mut Vec<u32>) -> Option<u32> {
    if face.len() <= 16 {
        for (i, &v) in face.iter().enumerate() {
            if face[..i].contains(&v) {
                return Some(v);
            }
        }
        None
    } else {
        scratch.clear();
        scratch.extend_from_slice(face);
        scratch.sort_unstable();
        scratch.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

/// Per-corner facts of a polygon list. Corner `k` is entry `k` of the flat index
/// buffer; it starts the directed edge `indices[k] -> indices[next[k]]`.
pub(crate) struct Corners<'a> {
    pub(crate) indices: &'a [u32],
    pub(crate) face: Vec<u32>,
    pub(crate) next: Vec<u32>,
}

impl<'a> Corners<'a> {
    pub(crate) fn new(list: &'a PolygonList) -> Self {
        let n = list.n_corners();
        let mut face = Vec::with_capacity(n);
        let mut next = Vec::with_capacity(n);
        for (f, w) in list.offsets().windows(2).enumerate() {
            for k in w[0]..w[1] {
                face.push(f as u32);
                next.push(if k + 1 == w[1] { w[0] } else { k + 1 } as u32);
            }
        }
        Self {
            indices: list.indices(),
            face,
            next,
        }
    }

    pub(crate) fn from(&self, k: u32) -> u32 {
        self.indices[k as usize]
    }

    pub(crate) fn to(&self, k: u32) -> u32 {
        self.indices[self.next[k as usize] as usize]
    }

    pub(crate) fn face(&self, k: u32) -> usize {
        self.face[k as usize] as usize
    }

    /// Directed edges grouped by their undirected vertex pair: a list of corners sorted
    /// by (pair, corner), and the start of each group (plus the end).
    ///
    /// A counting sort by the lower vertex of the pair (stable, so each bucket is in
    /// corner order), then a sort of each small bucket by (higher vertex, corner):
    /// O(C) plus the buckets' sorts, instead of one sort of all C keys.
    pub(crate) fn edge_groups(&self) -> (Vec<u32>, Vec<usize>) {
        let n_corners = self.indices.len();
        let n_vertices = self.indices.iter().max().map_or(0, |&m| m as usize + 1);
        let pair = |k: u32| {
            let (a, b) = (self.from(k), self.to(k));
            if a < b { (a, b) } else { (b, a) }
        };
        // bucket[v]..bucket[v + 1]: the corners whose pair has lower vertex v.
        let mut bucket = vec![0usize; n_vertices + 1];
        for k in 0..n_corners as u32 {
            bucket[pair(k).0 as usize + 1] += 1;
        }
        for v in 0..n_vertices {
            bucket[v + 1] += bucket[v];
        }
        // (higher vertex, corner) per corner, bucket by bucket.
        let mut keyed = vec![0u64; n_corners];
        let mut fill = bucket[..n_vertices].to_vec();
        for k in 0..n_corners as u32 {
            let (lo, hi) = pair(k);
            let slot = &mut fill[lo as usize];
            keyed[*slot] = (u64::from(hi) << 32) | u64::from(k);
            *slot += 1;
        }
        drop(fill);
        // Sort the buckets and find the groups, in parallel over ranges of vertices
        // with about the same number of corners (each range owns its part of `keyed`;
        // the group starts are concatenated in order, so the result does not depend
        // on the number of threads).
        let ranges = vertex_ranges(&bucket, PARALLEL_CHUNK);
        let mut pieces = Vec::with_capacity(ranges.len());
        let mut rest = &mut keyed[..];
        for w in ranges.windows(2) {
            let (piece, tail) = rest.split_at_mut(bucket[w[1]] - bucket[w[0]]);
            pieces.push((w[0], w[1], piece));
            rest = tail;
        }
        let chunk_starts: Vec<Vec<usize>> = pieces
            .into_par_iter()
            .map(|(v0, v1, piece)| {
                let base = bucket[v0];
                let mut starts = Vec::with_capacity(piece.len() / 2 + 1);
                for v in v0..v1 {
                    let (a, b) = (bucket[v] - base, bucket[v + 1] - base);
                    let group = &mut piece[a..b];
                    group.sort_unstable();
                    for i in 0..group.len() {
                        if i == 0 || group[i] >> 32 != group[i - 1] >> 32 {
                            starts.push(base + a + i);
                        }
                    }
                }
                starts
            })
            .collect();
        let mut starts = Vec::with_capacity(chunk_starts.iter().map(Vec::len).sum::<usize>() + 1);
        for chunk in chunk_starts {
            starts.extend(chunk);
        }
        starts.push(n_corners);
        // The low half of each key is the corner.
        #[allow(
            clippy::cast_possible_truncation,
            reason = "the low 32 bits are wanted"
        )]
        let sorted = keyed.into_iter().map(|key| key as u32).collect();
        (sorted, starts)
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

/// About how many corners one parallel task of the builder handles.
const PARALLEL_CHUNK: usize = 1 << 16;

/// Splits the vertices `0..n` (with `bucket` the running corner counts, `n + 1`
/// entries) into consecutive ranges of about `chunk` corners: the boundaries, from 0
/// to `n`.
fn vertex_ranges(bucket: &[usize], chunk: usize) -> Vec<usize> {
    let n = bucket.len() - 1;
    let mut ranges = vec![0];
    let mut next = chunk;
    for (v, &corners) in bucket.iter().enumerate().take(n).skip(1) {
        if corners >= next {
            ranges.push(v);
            next = corners + chunk;
        }
    }
    if n > 0 {
        ranges.push(n);
    }
    ranges
}

/// Flip faces so that every component is consistently oriented (breadth-first from the
/// lowest face of each component).
fn reorient(
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

/// Union-find over corners: two corners at the same vertex are joined when their faces
/// share a consistently oriented manifold edge at that vertex. Each class is one fan.
fn corner_fans(corners: &Corners<'_>, sorted: &[u32], starts: &[usize]) -> UnionFind<u32> {
    let mut fans = UnionFind::new(corners.indices.len());
    for g in starts.windows(2) {
        if let [k1, k2] = sorted[g[0]..g[1]] {
            if corners.from(k1) == corners.to(k2) {
                // k1: a -> b, k2: b -> a. The corner of a in k2's face is next(k2).
                fans.union(k1, corners.next[k2 as usize]);
                fans.union(corners.next[k1 as usize], k2);
            }
        }
    }
    fans
}

/// The number of fans of faces around vertex `v`.
fn count_fans(list: &PolygonList, v: u32) -> usize {
    let corners = Corners::new(list);
    let (sorted, starts) = corners.edge_groups();
    let fans = corner_fans(&corners, &sorted, &starts);
    let mut roots: Vec<u32> = (0..corners.indices.len() as u32)
        .filter(|&k| corners.from(k) == v)
        .map(|k| fans.find(k))
        .collect();
    roots.sort_unstable();
    roots.dedup();
    roots.len()
}

fn split_nonmanifold_vertices(
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
    let offsets = list.offsets();
    let mut fixed = PolygonList::with_capacity(list.len(), rewritten.len());
    for w in offsets.windows(2) {
        fixed.push(&rewritten[w[0]..w[1]]);
    }
    *list = fixed;
    Ok(())
}

/// Builds the half-edge arrays from a list whose faces are individually valid.
fn assemble(
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
