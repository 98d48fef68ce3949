//! Per-corner facts of a polygon list: directed edges grouped by vertex pair, and the
//! fans of faces around each vertex.

use petgraph::unionfind::UnionFind;
use rayon::prelude::*;

use crate::polygons::PolygonList;

/// Per-corner facts of a polygon list. Corner `k` is entry `k` of the flat index
/// buffer; it starts the directed edge `indices[k] -> indices[next(k)]`.
///
/// For a list of triangles only, a corner's face and successor follow from its index
/// (`k / 3`, and the next corner of the same triple), and no per-corner arrays are kept.
pub(crate) struct Corners<'a> {
    pub(crate) indices: &'a [u32],
    /// Face of each corner; empty for a list of triangles only.
    face: Vec<u32>,
    /// Successor of each corner in its face; empty for a list of triangles only.
    next: Vec<u32>,
    /// Predecessor of each corner in its face; empty for a list of triangles only.
    prev: Vec<u32>,
}

impl<'a> Corners<'a> {
    pub(crate) fn new(list: &'a PolygonList) -> Self {
        Self::with_triangles(list, list.is_triangles())
    }

    /// [`new`](Self::new) for a list whose faces all have three corners or more: it is
    /// a list of triangles exactly when it has three corners per face, which needs no
    /// pass over the faces.
    pub(crate) fn of_valid(list: &'a PolygonList) -> Self {
        debug_assert!(list.iter().all(|face| face.len() >= 3));
        Self::with_triangles(list, list.n_corners() == 3 * list.len())
    }

    fn with_triangles(list: &'a PolygonList, triangles: bool) -> Self {
        if triangles {
            return Self {
                indices: list.indices(),
                face: Vec::new(),
                next: Vec::new(),
                prev: Vec::new(),
            };
        }
        let n = list.n_corners();
        let mut face = Vec::with_capacity(n);
        let mut next = Vec::with_capacity(n);
        let mut prev = Vec::with_capacity(n);
        for f in 0..list.len() {
            let w = list.face_range(f);
            for k in w.clone() {
                face.push(f as u32);
                next.push(if k + 1 == w.end { w.start } else { k + 1 } as u32);
                prev.push(if k == w.start { w.end - 1 } else { k - 1 } as u32);
            }
        }
        Self {
            indices: list.indices(),
            face,
            next,
            prev,
        }
    }

    /// The same faces and corners with other vertex indices (`indices[k]` for corner
    /// `k`), as after renumbering the vertices.
    pub(crate) fn with_indices<'b>(&self, indices: &'b [u32]) -> Corners<'b> {
        debug_assert_eq!(indices.len(), self.indices.len());
        Corners {
            indices,
            face: self.face.clone(),
            next: self.next.clone(),
            prev: self.prev.clone(),
        }
    }

    /// Whether the per-corner arrays are implicit (a list of triangles only).
    #[inline]
    pub(crate) fn triangles(&self) -> bool {
        self.next.is_empty()
    }

    /// The corner after `k` in its face.
    #[inline]
    pub(crate) fn next(&self, k: u32) -> u32 {
        if self.triangles() {
            if k % 3 == 2 { k - 2 } else { k + 1 }
        } else {
            self.next[k as usize]
        }
    }

    /// The face of corner `k` and the corners after and before it in the face, with
    /// one division for a list of triangles.
    #[inline]
    pub(crate) fn links(&self, k: u32) -> (u32, u32, u32) {
        if self.triangles() {
            let f = k / 3;
            let first = 3 * f;
            let next = if k == first + 2 { first } else { k + 1 };
            let prev = if k == first { first + 2 } else { k - 1 };
            (f, next, prev)
        } else {
            let k = k as usize;
            (self.face[k], self.next[k], self.prev[k])
        }
    }

    /// Calls `f(k, from, to)` for every corner `k` of `range`, in order, with its
    /// directed edge `from -> to`. For a list of triangles whose `range` starts at a
    /// multiple of three, a triangle at a time.
    #[inline]
    pub(crate) fn edges_in(&self, range: std::ops::Range<usize>, mut f: impl FnMut(u32, u32, u32)) {
        if self.triangles() && range.start.is_multiple_of(3) {
            let whole = range.start + (range.end - range.start) / 3 * 3;
            for (t, tri) in self.indices[range.start..whole].chunks_exact(3).enumerate() {
                let k = (range.start + 3 * t) as u32;
                // One call site, so that `f` is inlined.
                for j in 0..3 {
                    f(k + j as u32, tri[j], tri[if j == 2 { 0 } else { j + 1 }]);
                }
            }
            for k in whole..range.end {
                let k = k as u32;
                f(k, self.from(k), self.to(k));
            }
        } else {
            for k in range {
                let k = k as u32;
                f(k, self.from(k), self.to(k));
            }
        }
    }

    /// The vertex corner `k` sits at: where its directed edge starts.
    #[inline]
    pub(crate) fn from(&self, k: u32) -> u32 {
        self.indices[k as usize]
    }

    /// Where the directed edge of corner `k` ends.
    #[inline]
    pub(crate) fn to(&self, k: u32) -> u32 {
        self.indices[self.next(k) as usize]
    }

    /// The face of corner `k`.
    #[inline]
    pub(crate) fn face(&self, k: u32) -> usize {
        if self.triangles() {
            k as usize / 3
        } else {
            self.face[k as usize] as usize
        }
    }

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

/// About how many corners one parallel task of the builder handles.
pub(super) const PARALLEL_CHUNK: usize = 1 << 16;

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

/// Union-find over corners: two corners at the same vertex are joined when their faces
/// share a consistently oriented manifold edge at that vertex. Each class is one fan.
pub(super) fn corner_fans(
    corners: &Corners<'_>,
    sorted: &[u32],
    starts: &[usize],
) -> UnionFind<u32> {
    let mut fans = UnionFind::new(corners.indices.len());
    for g in starts.windows(2) {
        if let [k1, k2] = sorted[g[0]..g[1]]
            && corners.from(k1) == corners.to(k2)
        {
            // k1: a -> b, k2: b -> a. The corner of a in k2's face is next(k2).
            fans.union(k1, corners.next(k2));
            fans.union(corners.next(k1), k2);
        }
    }
    fans
}

/// The number of fans of faces around vertex `v`.
pub(super) fn count_fans(list: &PolygonList, v: u32) -> usize {
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
