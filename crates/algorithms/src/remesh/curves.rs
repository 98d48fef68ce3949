//! Feature curves: which edges are features, which vertices are corners, and the
//! closest point on the input's feature curves.

use std::collections::HashMap;

use beltrami_halfedge::edit::{EdgeProperty, VertexProperty};
use beltrami_halfedge::{DVec3, EdgeId, EditMesh, FaceId, HalfedgeId, HalfedgeMesh, VertexId};

/// The angle between the normals of the two triangles of interior edge `e`, radians
/// (0 for a flat pair, 0 for a degenerate triangle).
pub(super) fn dihedral(mesh: &EditMesh, e: EdgeId) -> f64 {
    let [h, t] = e.halfedges();
    let (n, m) = (triangle_normal(mesh, h), triangle_normal(mesh, t));
    let angle = n.angle_between(m);
    if angle.is_finite() { angle } else { 0.0 }
}

/// The unnormalised normal (twice the area vector) of the triangle on the left of `h`;
/// zero on the boundary.
pub(super) fn triangle_normal(mesh: &EditMesh, h: HalfedgeId) -> DVec3 {
    let Some(o) = mesh.opposite_vertex(h) else {
        return DVec3::ZERO;
    };
    let a = mesh.position(mesh.from_vertex(h));
    let b = mesh.position(mesh.to_vertex(h));
    (b - a).cross(mesh.position(o) - a)
}

/// The number of feature edges at `v`.
pub(super) fn feature_count(mesh: &EditMesh, feature: EdgeProperty<bool>, v: VertexId) -> usize {
    // The column once, not a typed look-up per edge.
    let feature = mesh.values(feature);
    mesh.halfedges_around_vertex(v)
        .filter(|h| feature[h.edge().index()])
        .count()
}

/// The dihedral angle (radians, 150°) above which a feature edge is counted as a fold:
/// its two triangles turn back onto each other, as a scan's folded slivers do. Such
/// edges are kept as features like any other (a thin fin is one too), and counted so
/// that a caller can say so.
pub const FOLD_ANGLE: f64 = 5.0 * std::f64::consts::PI / 6.0;

/// What the detection found.
pub(super) struct Detected {
    /// Interior edges whose dihedral angle exceeds the feature angle.
    pub(super) feature_edges: usize,
    /// Interior edges the caller gave as features (whether or not sharp).
    pub(super) given_edges: usize,
    /// Those of them whose triangles fold back onto each other (dihedral angle above
    /// [`FOLD_ANGLE`]).
    pub(super) fold_edges: usize,
    /// Boundary edges (always constraint curves).
    pub(super) boundary_edges: usize,
    /// Vertices that never move.
    pub(super) corners: usize,
}

/// Flags the feature edges (interior edges sharper than `feature_angle`, those `given`
/// flags (indexed by edge; empty for none), and every boundary edge) and the corners:
/// vertices with one or more than two feature edges, and vertices whose two feature
/// edges turn by more than `corner_angle`.
pub(super) fn detect(
    mesh: &mut EditMesh,
    feature: EdgeProperty<bool>,
    corner: VertexProperty<bool>,
    feature_angle: Option<f64>,
    corner_angle: f64,
    given: &[bool],
) -> Detected {
    let mut found = Detected {
        feature_edges: 0,
        given_edges: 0,
        fold_edges: 0,
        boundary_edges: 0,
        corners: 0,
    };
    let edges: Vec<EdgeId> = mesh.edges().collect();
    for e in edges {
        let flag = if mesh.is_boundary_edge(e) {
            found.boundary_edges += 1;
            true
        } else {
            let is_given = given.get(e.index()).copied().unwrap_or(false);
            found.given_edges += usize::from(is_given);
            let sharp = feature_angle.is_some_and(|a| {
                let angle = dihedral(mesh, e);
                let sharp = angle > a;
                if sharp {
                    found.feature_edges += 1;
                    found.fold_edges += usize::from(angle > FOLD_ANGLE);
                }
                sharp
            });
            sharp || is_given
        };
        mesh.set(feature, e, flag);
    }
    let vertices: Vec<VertexId> = mesh.vertices().collect();
    for v in vertices {
        let ends: Vec<DVec3> = mesh
            .halfedges_around_vertex(v)
            .filter(|h| *mesh.get(feature, h.edge()))
            .map(|h| mesh.position(mesh.to_vertex(h)))
            .collect();
        let is_corner = match ends.as_slice() {
            [] => false,
            [a, b] => {
                let p = mesh.position(v);
                let turn = std::f64::consts::PI - (*a - p).angle_between(*b - p);
                !(turn.is_finite() && turn <= corner_angle)
            }
            _ => true,
        };
        if is_corner {
            found.corners += 1;
        }
        mesh.set(corner, v, is_corner);
    }
    found
}

/// The input's feature segments in a uniform grid, for closest-point queries on the
/// feature curves.
pub(super) struct CurveIndex {
    segments: Vec<[DVec3; 2]>,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
    /// The range of occupied cells, to end the ring search.
    lo: [i64; 3],
    hi: [i64; 3],
    /// For a segment that is no crease of the smooth surface (a feature edge given by
    /// the caller, not sharp): an input face beside it, that face's vertices (in
    /// [`HalfedgeMesh::triangle_vertices`](beltrami_halfedge::HalfedgeMesh::triangle_vertices)
    /// order) and the corners of the segment's two ends among them, so that a point on
    /// it can be lifted onto the smooth surface. `None` for creases.
    smooth: Vec<Option<SmoothSegment>>,
}

/// See [`CurveIndex::smooth`].
#[derive(Clone, Copy)]
pub(super) struct SmoothSegment {
    pub(super) face: FaceId,
    pub(super) vertices: [VertexId; 3],
    /// The corners of the segment's first and second end.
    pub(super) ends: [usize; 2],
}

impl CurveIndex {
    /// Indexes the feature edges of `mesh` (the editable copy of `input`, with its ids);
    /// `crease(e)` says whether feature edge `e` is a crease of the smooth surface.
    pub(super) fn new(
        mesh: &EditMesh,
        input: &HalfedgeMesh,
        feature: EdgeProperty<bool>,
        crease: impl Fn(EdgeId) -> bool,
    ) -> Self {
        let edges: Vec<EdgeId> = mesh.edges().filter(|&e| *mesh.get(feature, e)).collect();
        let segments: Vec<[DVec3; 2]> = edges
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edge_vertices(e);
                [mesh.position(a), mesh.position(b)]
            })
            .collect();
        let smooth = edges
            .iter()
            .map(|&e| {
                if crease(e) {
                    return None;
                }
                let [a, b] = input.edge_vertices(e);
                let face = e.halfedges().into_iter().find_map(|h| input.face(h))?;
                let vertices = input.triangle_vertices(face);
                let at = |v: VertexId| vertices.iter().position(|&w| w == v);
                Some(SmoothSegment {
                    face,
                    vertices,
                    ends: [at(a)?, at(b)?],
                })
            })
            .collect();
        let total: f64 = segments.iter().map(|[a, b]| a.distance(*b)).sum();
        let mean = total / segments.len().max(1) as f64;
        let cell = if mean > 0.0 && mean.is_finite() {
            2.0 * mean
        } else {
            1.0
        };
        let mut index = Self {
            segments,
            smooth,
            cell,
            cells: HashMap::new(),
            lo: [i64::MAX; 3],
            hi: [i64::MIN; 3],
        };
        for (i, [a, b]) in index.segments.iter().enumerate() {
            let (c0, c1) = (index.key(a.min(*b)), index.key(a.max(*b)));
            for x in c0[0]..=c1[0] {
                for y in c0[1]..=c1[1] {
                    for z in c0[2]..=c1[2] {
                        index.cells.entry([x, y, z]).or_default().push(i as u32);
                    }
                }
            }
            for k in 0..3 {
                index.lo[k] = index.lo[k].min(c0[k]);
                index.hi[k] = index.hi[k].max(c1[k]);
            }
        }
        index
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        let k = |x: f64| (x / self.cell).floor() as i64;
        [k(p.x), k(p.y), k(p.z)]
    }

    /// The closest point to `p` on the feature segments; `p` itself when there are none.
    ///
    /// Rings of cells around `p`'s cell are searched outwards until the best distance is
    /// smaller than the distance to the next ring. Ties go to the smaller segment index,
    /// so the answer is deterministic.
    ///
    /// With the point, for a point on a segment that is no crease, that segment's face
    /// and the point's barycentric weights in it.
    pub(super) fn closest(&self, p: DVec3) -> (DVec3, Option<(SmoothSegment, [f64; 3])>) {
        if self.segments.is_empty() {
            return (p, None);
        }
        let c = self.key(p);
        let mut best = (f64::INFINITY, u32::MAX, p);
        let reach = (0..3)
            .map(|k| (c[k] - self.lo[k]).abs().max((self.hi[k] - c[k]).abs()))
            .max()
            .unwrap_or(0);
        for r in 0..=reach {
            if best.0.is_finite() && best.0.sqrt() <= (r - 1).max(0) as f64 * self.cell {
                break;
            }
            for x in c[0] - r..=c[0] + r {
                for y in c[1] - r..=c[1] + r {
                    for z in c[2] - r..=c[2] + r {
                        let on_ring =
                            (x - c[0]).abs() == r || (y - c[1]).abs() == r || (z - c[2]).abs() == r;
                        if !on_ring {
                            continue;
                        }
                        let Some(list) = self.cells.get(&[x, y, z]) else {
                            continue;
                        };
                        for &i in list {
                            let [a, b] = self.segments[i as usize];
                            let q = closest_on_segment(p, a, b);
                            let d = q.distance_squared(p);
                            if d < best.0 || (d == best.0 && i < best.1) {
                                best = (d, i, q);
                            }
                        }
                    }
                }
            }
        }
        let (_, i, q) = best;
        let smooth = self.smooth.get(i as usize).copied().flatten().map(|s| {
            let [a, b] = self.segments[i as usize];
            let d = b - a;
            let t = if d.length_squared() > 0.0 {
                ((q - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut weights = [0.0; 3];
            weights[s.ends[0]] = 1.0 - t;
            weights[s.ends[1]] = t;
            (s, weights)
        });
        (q, smooth)
    }
}

/// The closest point to `p` on segment `a b`.
pub(super) fn closest_on_segment(p: DVec3, a: DVec3, b: DVec3) -> DVec3 {
    let d = b - a;
    let len2 = d.length_squared();
    if len2 == 0.0 {
        return a;
    }
    let t = ((p - a).dot(d) / len2).clamp(0.0, 1.0);
    if t == 0.0 {
        a
    } else if t == 1.0 {
        b
    } else {
        a + d * t
    }
}
