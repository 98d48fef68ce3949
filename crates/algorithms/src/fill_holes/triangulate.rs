//! The minimum-weight triangulation of one boundary loop (Liepa 2003, §3.1): dynamic
//! programming over the sub-polygons `[i, k]` of the loop, O(n³) time and O(n²) memory.

use std::collections::HashMap;

use beltrami_halfedge::{DVec3, EditMesh, HalfedgeId, VertexId};

/// The weight of a (partial) triangulation: its largest dihedral angle, measured as
/// `1 − cos θ` between neighbouring triangle normals (monotone in θ), and its area. Two
/// weights compare lexicographically: the angle first, the area to break ties. The sum
/// of two weights is the larger angle and the summed area.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Weight {
    angle: f64,
    area: f64,
}

impl Weight {
    const ZERO: Self = Self {
        angle: 0.0,
        area: 0.0,
    };
    const INFINITE: Self = Self {
        angle: f64::INFINITY,
        area: f64::INFINITY,
    };

    fn plus(self, other: Self) -> Self {
        Self {
            angle: self.angle.max(other.angle),
            area: self.area + other.area,
        }
    }

    fn less(self, other: Self) -> bool {
        self.angle < other.angle || (self.angle == other.angle && self.area < other.area)
    }

    fn is_finite(self) -> bool {
        self.angle.is_finite() && self.area.is_finite()
    }
}

/// The unit normal of triangle `(a, b, c)`, or zero for a degenerate one.
fn unit_normal(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    (b - a).cross(c - a).normalize_or_zero()
}

/// `1 − cos θ` between two unit normals (1 when either is zero: a degenerate triangle
/// counts as a right-angle fold).
fn fold(n: DVec3, m: DVec3) -> f64 {
    1.0 - n.dot(m)
}

/// Why a loop cannot be triangulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum TriangulateError {
    /// A loop vertex appears twice in the loop or has more than one boundary gap.
    NonManifold(VertexId),
    /// Every triangulation would duplicate an existing edge.
    NoTriangulation,
}

/// The boundary halfedges of the loop through `h`, in `next` order.
pub(super) fn trace_loop(mesh: &EditMesh, h: HalfedgeId) -> Vec<HalfedgeId> {
    mesh.halfedges_around_cycle(h).collect()
}

/// The triangles (loop indices `i < m < k`, in the order they are to be added) of the
/// minimum-weight triangulation of `hole` (boundary halfedges in `next` order; loop
/// vertex `i` is `to_vertex(hole[i])`). Nothing is written.
pub(super) fn plan(
    mesh: &EditMesh,
    hole: &[HalfedgeId],
) -> Result<Vec<[VertexId; 3]>, TriangulateError> {
    let n = hole.len();
    let vertex: Vec<VertexId> = hole.iter().map(|&h| mesh.to_vertex(h)).collect();
    let index_of = loop_indices(mesh, &vertex)?;
    if n < 3 || (n == 3 && closes_a_face(mesh, hole)) {
        return Err(TriangulateError::NoTriangulation);
    }
    let position: Vec<DVec3> = vertex.iter().map(|&v| mesh.position(v)).collect();
    let joined = joined_pairs(mesh, &vertex, &index_of);
    let outside = outside_normals(mesh, hole);
    let (weight, split) = minimum_weights(&position, &joined, &outside);
    if !weight[n - 1].is_finite() {
        return Err(TriangulateError::NoTriangulation);
    }
    Ok(read_triangles(&vertex, &split))
}

/// Whether the three-edge loop `hole` is the rim of one existing face (a lone triangle,
/// or the open side of a one-face sheet): its only triangulation would repeat that face
/// on the same three vertices, a duplicate face that `repair` drops and that closes the
/// sheet into a flat two-face pillow.
fn closes_a_face(mesh: &EditMesh, hole: &[HalfedgeId]) -> bool {
    let outside = |h: HalfedgeId| mesh.face(h.twin());
    outside(hole[0]).is_some() && hole.iter().all(|&h| outside(h) == outside(hole[0]))
}

/// The loop index of each loop vertex.
///
/// # Errors
/// [`TriangulateError::NonManifold`] when a vertex comes twice in the loop or has more
/// than one boundary fan.
fn loop_indices(
    mesh: &EditMesh,
    vertex: &[VertexId],
) -> Result<HashMap<VertexId, usize>, TriangulateError> {
    let mut index_of: HashMap<VertexId, usize> = HashMap::with_capacity(vertex.len());
    for (i, &v) in vertex.iter().enumerate() {
        if index_of.insert(v, i).is_some() || mesh.boundary_fans(v) > 1 {
            return Err(TriangulateError::NonManifold(v));
        }
    }
    Ok(index_of)
}

/// `joined[i * n + j]`: loop vertices `i` and `j` share an existing edge that is not a
/// loop edge; a triangle using it would give that edge a third face.
fn joined_pairs(
    mesh: &EditMesh,
    vertex: &[VertexId],
    index_of: &HashMap<VertexId, usize>,
) -> Vec<bool> {
    let n = vertex.len();
    let mut joined = vec![false; n * n];
    for (i, &v) in vertex.iter().enumerate() {
        for w in mesh.vertices_around_vertex(v) {
            if let Some(&j) = index_of.get(&w) {
                let rim = i.abs_diff(j) == 1 || (i.min(j) == 0 && i.max(j) == n - 1);
                if !rim {
                    joined[i * n + j] = true;
                    joined[j * n + i] = true;
                }
            }
        }
    }
    joined
}

/// The unit normal of the existing face across loop edge (i − 1, i), i.e. across
/// `hole[i]` (Newell's normal, so any polygon works); zero where there is none.
fn outside_normals(mesh: &EditMesh, hole: &[HalfedgeId]) -> Vec<DVec3> {
    hole.iter()
        .map(|&h| {
            let t = h.twin();
            let mut normal = DVec3::ZERO;
            if mesh.face(t).is_some() {
                for g in mesh.halfedges_around_cycle(t) {
                    let a = mesh.position(mesh.from_vertex(g));
                    let b = mesh.position(mesh.to_vertex(g));
                    normal += a.cross(b);
                }
            }
            normal.normalize_or_zero()
        })
        .collect()
}

/// The dynamic programme of the minimum-weight triangulation: per loop range `i..=k`
/// (entry `i * n + k`), the weight of its best triangulation (infinite when there is
/// none) and the apex `m` of its triangle on `(i, k)`.
fn minimum_weights(
    position: &[DVec3],
    joined: &[bool],
    outside: &[DVec3],
) -> (Vec<Weight>, Vec<usize>) {
    let n = position.len();
    let mut weight = vec![Weight::INFINITE; n * n];
    let mut split = vec![usize::MAX; n * n];
    for i in 0..n - 1 {
        weight[i * n + i + 1] = Weight::ZERO;
    }
    let normal = |a: usize, b: usize, c: usize| unit_normal(position[a], position[b], position[c]);
    for span in 2..n {
        for i in 0..n - span {
            let k = i + span;
            if joined[i * n + k] {
                continue;
            }
            let mut best = Weight::INFINITE;
            let mut best_m = usize::MAX;
            for m in i + 1..k {
                let (left, right) = (weight[i * n + m], weight[m * n + k]);
                if !left.is_finite() || !right.is_finite() {
                    continue;
                }
                let n0 = normal(i, m, k);
                let across_left = if m == i + 1 {
                    outside[m]
                } else {
                    normal(i, split[i * n + m], m)
                };
                let across_right = if k == m + 1 {
                    outside[k]
                } else {
                    normal(m, split[m * n + k], k)
                };
                let mut angle = fold(n0, across_left).max(fold(n0, across_right));
                if i == 0 && k == n - 1 {
                    angle = angle.max(fold(n0, outside[0]));
                }
                let area = 0.5
                    * (position[m] - position[i])
                        .cross(position[k] - position[i])
                        .length();
                let w = left.plus(right).plus(Weight { angle, area });
                if w.less(best) {
                    best = w;
                    best_m = m;
                }
            }
            weight[i * n + k] = best;
            split[i * n + k] = best_m;
        }
    }
    (weight, split)
}

/// The triangles of the whole loop's best triangulation, from the apexes `split`, in
/// the order they are to be added.
fn read_triangles(vertex: &[VertexId], split: &[usize]) -> Vec<[VertexId; 3]> {
    let n = vertex.len();
    let mut triangles = Vec::with_capacity(n - 2);
    let mut todo = vec![(0, n - 1)];
    while let Some((i, k)) = todo.pop() {
        if k - i < 2 {
            continue;
        }
        let m = split[i * n + k];
        triangles.push([vertex[i], vertex[m], vertex[k]]);
        todo.push((i, m));
        todo.push((m, k));
    }
    triangles
}
