//! [`SurfaceIndex`]: the closest point of a triangle mesh to any point, and the signed
//! distance, through a bounding-volume hierarchy.

use std::sync::OnceLock;

use beltrami_halfedge::geometry::DEGENERACY_RATIO;
use beltrami_halfedge::{DVec3, EdgeId, FaceId, HalfedgeMesh, TopologyError, VertexId};
use rayon::prelude::*;

use super::bvh::{Bvh, Stack, box_distance_squared, morton_order};
use super::sampling::SplitMix64;
use super::triangle::{PreparedTriangle, TriangleFeature, TrianglePoint};
use crate::MetricsError;

/// The largest coordinate magnitude accepted for reference positions and query points.
///
/// Squared distances and the products of four coordinate differences in the point–triangle
/// computation must stay finite; `1e60` leaves them far from overflow and is far beyond any
/// physical length in any unit.
pub const MAX_COORDINATE: f64 = 1e60;

/// Queries are processed in chunks of this many points, each chunk sequentially, so that
/// results do not depend on how rayon schedules the chunks.
const CHUNK: usize = 1024;

/// The part of the reference surface that holds a closest point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Feature {
    /// The interior of [`ClosestPoint::face`].
    Face,
    /// The relative interior of an edge of the face.
    Edge(EdgeId),
    /// A vertex of the face.
    Vertex(VertexId),
}

/// The closest point of a reference surface to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The closest point on the surface, in the positions' unit.
    pub point: DVec3,
    /// The squared distance from the query point, in unit².
    pub distance_squared: f64,
    /// The face that holds the point. When several faces are at the same computed distance
    /// (a closest point on an edge or a vertex), the one with the smallest id.
    pub face: FaceId,
    /// Where on the face the point lies.
    pub feature: Feature,
}

impl ClosestPoint {
    /// The distance from the query point, in the positions' unit.
    #[must_use]
    pub fn distance(&self) -> f64 {
        self.distance_squared.sqrt()
    }
}

/// What consecutive queries pass on: the previous answer's leaf position (its distance
/// bounds the next search), and the traversal stack (reused, never cleared element by
/// element).
#[derive(Debug)]
struct Hint {
    leaf: Option<usize>,
    stack: Stack,
}

impl Default for Hint {
    fn default() -> Self {
        Self {
            leaf: None,
            stack: Stack::new(),
        }
    }
}

/// The values of one chunk of points and the points it put off, with what for.
type Deferred<T, W> = (Vec<T>, Vec<(u32, W)>);

/// Face normals and edge pseudo-normals (not normalised; only their direction is used).
/// The vertices' angle-weighted pseudo-normals are kept apart: a batch of signed queries
/// computes only those of the vertices its closest points lie on.
#[derive(Debug)]
struct PseudoNormals {
    face: Vec<DVec3>,
    edge: Vec<DVec3>,
}

/// A reusable search structure over a reference triangle mesh: build it once, then ask for
/// closest points and signed distances of any number of points.
///
/// It owns copies of what it needs (the triangles in hierarchy order, the face–vertex and
/// face–edge incidences, the positions), about 170 bytes per face, so the reference mesh
/// can be dropped; the first signed query adds the pseudo-normals, about 70 bytes per
/// face. Queries take `&self` and run in parallel with rayon; batch results are
/// identical for any thread count.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{primitives, DVec3};
/// use beltrami_metrics::distance::SurfaceIndex;
///
/// let cube = primitives::cube();
/// let index = SurfaceIndex::new(&cube.mesh()?, &cube.positions)?;
/// let outside = index.closest_point(DVec3::new(0.5, 0.5, 1.25))?;
/// assert!((outside.distance() - 0.25).abs() < 1e-15);
/// assert!((index.signed_distance(DVec3::new(0.5, 0.5, 0.75))? + 0.25).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// - D. Eberly: *Distance Between Point and Triangle in 3D*. Geometric Tools, 1999.
/// - J. A. Bærentzen, H. Aanæs: *Signed distance computation using the angle weighted
///   pseudonormal*. IEEE Transactions on Visualization and Computer Graphics 11(3),
///   2005.
#[derive(Debug)]
pub struct SurfaceIndex {
    bvh: Bvh,
    /// Triangles in leaf order, prepared for the point–triangle routine.
    triangles: Vec<PreparedTriangle>,
    /// The face at each leaf position.
    leaf_faces: Vec<u32>,
    /// Vertex ids per face, in the face's order.
    face_vertices: Vec<[u32; 3]>,
    /// Edge ids per face: edge `k` joins corners `k` and `k + 1`.
    face_edges: Vec<[u32; 3]>,
    positions: Vec<DVec3>,
    n_edges: usize,
    pseudo_normals: OnceLock<PseudoNormals>,
    /// Every vertex's angle-weighted pseudo-normal, computed when a single signed query
    /// first needs one.
    vertex_normals: OnceLock<Vec<DVec3>>,
}

impl SurfaceIndex {
    /// Builds the index over a triangle mesh with one position per vertex.
    ///
    /// # Errors
    /// - [`MetricsError::Topology`] with [`TopologyError::PositionCount`] when
    ///   `positions.len()` is not the vertex count, or [`TopologyError::NotTriangle`] when
    ///   a face is not a triangle;
    /// - [`MetricsError::Empty`] when the mesh has no face;
    /// - [`MetricsError::NonFinite`] for a NaN or infinite position (`"reference
    ///   position"`), [`MetricsError::InvalidParameter`] for a coordinate beyond
    ///   [`MAX_COORDINATE`].
    ///
    /// # Complexity
    /// O(F log F) time (the hierarchy build runs in parallel), O(F) memory.
    pub fn new(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<Self, MetricsError> {
        if positions.len() != mesh.n_vertices() {
            return Err(TopologyError::PositionCount {
                positions: positions.len(),
                vertices: mesh.n_vertices(),
            }
            .into());
        }
        check_points(positions, "surface vertex")?;
        if mesh.n_faces() == 0 {
            return Err(MetricsError::Empty {
                what: "reference mesh",
            });
        }
        if !mesh.is_triangle_mesh()
            && let Some(f) = mesh.faces().find(|&f| mesh.face_valence(f) != 3)
        {
            return Err(TopologyError::NotTriangle {
                face: f.raw(),
                len: mesh.face_valence(f),
            }
            .into());
        }
        let (face_vertices, face_edges): (Vec<[u32; 3]>, Vec<[u32; 3]>) = (0..mesh.n_faces())
            .into_par_iter()
            .map(|f| {
                // h0 ends at corner 0, h1 runs 0 → 1, h2 runs 1 → 2, so h0 runs 2 → 0.
                let h0 = mesh.face_halfedge(FaceId::new(f as u32));
                let h1 = mesh.next(h0);
                let h2 = mesh.next(h1);
                (
                    [
                        mesh.to_vertex(h0).raw(),
                        mesh.to_vertex(h1).raw(),
                        mesh.to_vertex(h2).raw(),
                    ],
                    [h1.edge().raw(), h2.edge().raw(), h0.edge().raw()],
                )
            })
            .unzip();
        let corners = |vs: &[u32; 3]| vs.map(|v| positions[v as usize]);
        let (bvh, order) = Bvh::build(face_vertices.len(), |f| {
            let [a, b, c] = corners(&face_vertices[f]);
            [a.min(b).min(c), a.max(b).max(c)]
        });
        let triangles = order
            .par_iter()
            .map(|&f| PreparedTriangle::new(corners(&face_vertices[f as usize])))
            .collect();
        Ok(Self {
            bvh,
            triangles,
            leaf_faces: order,
            face_vertices,
            face_edges,
            positions: positions.par_iter().copied().collect(),
            n_edges: mesh.n_edges(),
            pseudo_normals: OnceLock::new(),
            vertex_normals: OnceLock::new(),
        })
    }

    /// The number of faces of the reference mesh.
    #[must_use]
    pub fn n_faces(&self) -> usize {
        self.face_vertices.len()
    }

    /// The reference positions, one per vertex.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The corners of face `f` in the face's order, or `None` when `f` is not a face of
    /// the reference.
    #[must_use]
    pub fn triangle(&self, f: FaceId) -> Option<[DVec3; 3]> {
        let vs = self.face_vertices.get(f.index())?;
        Some(vs.map(|v| self.positions[v as usize]))
    }

    /// The vertices of face `f` in the face's order (that of
    /// `HalfedgeMesh::triangle_vertices`), or `None` when `f` is not a face of the
    /// reference. One look-up in the index's own face table.
    #[must_use]
    pub fn triangle_vertices(&self, f: FaceId) -> Option<[VertexId; 3]> {
        let vs = self.face_vertices.get(f.index())?;
        Some(vs.map(VertexId::new))
    }

    /// The closest point of the reference surface to `p`: the closest point on the closest
    /// triangle (not the closest vertex), with the face and the feature that hold it.
    ///
    /// # Errors
    /// [`MetricsError::NonFinite`] (`"query point"`, index 0) for a NaN or infinite `p`,
    /// [`MetricsError::InvalidParameter`] for a coordinate beyond [`MAX_COORDINATE`].
    ///
    /// # Complexity
    /// About O(log F) for a well-shaped surface.
    pub fn closest_point(&self, p: DVec3) -> Result<ClosestPoint, MetricsError> {
        check_points(&[p], "query point")?;
        Ok(self.query(p, &mut Hint::default()))
    }

    /// The signed distance from `p` to the reference surface, in the positions' unit:
    /// `± |p − q|` with `q` the closest point, positive on the side the normals point to
    /// (outside of a closed mesh oriented counter-clockwise seen from outside).
    ///
    /// The sign is that of `(p − q) · n`, with `n` the face normal when `q` is inside a
    /// face, and otherwise the angle-weighted pseudo-normal of the edge (the sum of its
    /// faces' normals) or of the vertex (the sum of its faces' normals weighted by their
    /// angles at the vertex). Bærentzen and Aanæs prove that this sign is right for every
    /// point off a closed, consistently oriented surface, whereas the normal of the closest
    /// face alone (CloudCompare's rule) can be wrong near edges and vertices. Degenerate
    /// faces contribute nothing to pseudo-normals. When `(p − q) · n` is exactly zero, the
    /// closest face's normal decides, and a point still undecided counts as outside.
    ///
    /// # Errors
    /// As for [`closest_point`](Self::closest_point).
    ///
    /// # References
    /// J. A. Bærentzen, H. Aanæs, IEEE TVCG 11(3), 2005.
    pub fn signed_distance(&self, p: DVec3) -> Result<f64, MetricsError> {
        let closest = self.closest_point(p)?;
        Ok(self.sign(p, &closest))
    }

    /// The signed distance of `p` given its closest point (see
    /// [`signed_distance`](Self::signed_distance)). `closest` must come from this index.
    ///
    /// # Panics
    /// If `closest` names a face, edge or vertex that this index does not have.
    #[must_use]
    pub fn signed_distance_from(&self, p: DVec3, closest: &ClosestPoint) -> f64 {
        self.sign(p, closest)
    }

    /// The closest point of every point of `points` (see
    /// [`closest_point`](Self::closest_point)), in parallel.
    ///
    /// Points are processed in fixed chunks of consecutive points, and each search starts
    /// from the bound given by the previous point's triangle, so the results are identical
    /// for any thread count and agree with [`closest_point`](Self::closest_point) up to
    /// rounding (at an exact tie between faces, the same face).
    ///
    /// # Errors
    /// [`MetricsError::NonFinite`] naming the first non-finite point (`"query point"`),
    /// [`MetricsError::InvalidParameter`] for a coordinate beyond [`MAX_COORDINATE`].
    pub fn closest_points(&self, points: &[DVec3]) -> Result<Vec<ClosestPoint>, MetricsError> {
        check_points(points, "query point")?;
        Ok(self.map_points(points, |p, hint| self.query(p, hint)))
    }

    /// The distance of every point of `points` to the surface, in parallel (see
    /// [`closest_points`](Self::closest_points)).
    ///
    /// # Errors
    /// As for [`closest_points`](Self::closest_points).
    pub fn distances(&self, points: &[DVec3]) -> Result<Vec<f64>, MetricsError> {
        check_points(points, "query point")?;
        Ok(self.map_points(points, |p, hint| self.query(p, hint).distance()))
    }

    /// The signed distance of every point of `points` (see
    /// [`signed_distance`](Self::signed_distance)), in parallel.
    ///
    /// Unless a single signed query has computed every vertex's pseudo-normal before,
    /// only those of the vertices that are closest points are computed (the same sums,
    /// so the same bits).
    ///
    /// # Errors
    /// As for [`closest_points`](Self::closest_points).
    pub fn signed_distances(&self, points: &[DVec3]) -> Result<Vec<f64>, MetricsError> {
        check_points(points, "query point")?;
        self.pseudo_normals();
        if let Some(vertex) = self.vertex_normals.get() {
            return Ok(self.map_points(points, |p, hint| {
                let closest = self.query(p, hint);
                self.sign_with(p, &closest, |v| vertex[v])
            }));
        }
        // The points whose closest point is a vertex wait for the pseudo-normals of
        // those vertices, which are then computed alone (the same sums, in the same
        // order, as for all vertices).
        let (mut signed, waiting) = self.map_points_deferred(points, |p, hint| {
            let closest = self.query(p, hint);
            match closest.feature {
                Feature::Vertex(_) if closest.distance_squared != 0.0 => Err(closest),
                _ => Ok(self.sign_with(p, &closest, |_| DVec3::ZERO)),
            }
        });
        if !waiting.is_empty() {
            let mut needed = vec![false; self.positions.len()];
            for (_, closest) in &waiting {
                if let Feature::Vertex(v) = closest.feature {
                    needed[v.index()] = true;
                }
            }
            let vertex = self.vertex_pseudo_normals(Some(&needed));
            for (i, closest) in &waiting {
                signed[*i as usize] = self.sign_with(points[*i as usize], closest, |v| vertex[v]);
            }
        }
        Ok(signed)
    }

    /// Computes the face normals and edge pseudo-normals that signed queries need now,
    /// rather than on the first signed query (so that a caller can time the index build
    /// and the queries apart). The vertices' pseudo-normals are left to the queries: a
    /// batch ([`signed_distances`](Self::signed_distances)) computes those of the
    /// vertices its closest points lie on, a single query all of them on first use.
    /// Idempotent and cheap after the first call.
    pub fn prepare_signed(&self) {
        self.pseudo_normals();
    }

    /// `count` points distributed uniformly by area over the surface, reproducibly: the
    /// same `count` and `seed` give the same points on every machine and thread count.
    ///
    /// Each sample draws three numbers from a SplitMix64 stream seeded with `seed`: one
    /// picks a face with probability proportional to its area, two pick a point uniformly
    /// in it (`a (1 − √u) + b √u (1 − v) + c √u v`). When the total area is zero, faces
    /// are picked with equal probability.
    ///
    /// # References
    /// - G. Turk: *Generating random points in triangles*. Graphics Gems, 1990.
    /// - G. L. Steele, D. Lea, C. H. Flood: *Fast splittable pseudorandom number
    ///   generators*. OOPSLA 2014 (SplitMix64).
    #[must_use]
    pub fn sample_surface(&self, count: usize, seed: u64) -> Vec<DVec3> {
        let mut cumulative = Vec::with_capacity(self.n_faces());
        let mut total = 0.0;
        for f in 0..self.n_faces() {
            let [a, b, c] = self.face_vertices[f].map(|v| self.positions[v as usize]);
            total += 0.5 * (b - a).cross(c - a).length();
            cumulative.push(total);
        }
        let uniform = !(total > 0.0 && total.is_finite());
        let last = self.n_faces() - 1;
        let mut rng = SplitMix64::new(seed);
        (0..count)
            .map(|_| {
                let u = rng.next_f64();
                let f = if uniform {
                    ((u * self.n_faces() as f64) as usize).min(last)
                } else {
                    let target = u * total;
                    cumulative.partition_point(|&c| c <= target).min(last)
                };
                let [a, b, c] = self.face_vertices[f].map(|v| self.positions[v as usize]);
                let r1 = rng.next_f64().sqrt();
                let r2 = rng.next_f64();
                a * (1.0 - r1) + b * (r1 * (1.0 - r2)) + c * (r1 * r2)
            })
            .collect()
    }

    /// For every vertex, in vertex order, whether it belongs to a face (isolated vertices
    /// are not on the surface).
    pub(crate) fn on_surface(&self) -> Vec<bool> {
        let mut used = vec![false; self.positions.len()];
        for vs in &self.face_vertices {
            for &v in vs {
                used[v as usize] = true;
            }
        }
        used
    }

    /// The positions of the vertices that belong to a face, in vertex order.
    pub(crate) fn surface_vertices(&self) -> Vec<DVec3> {
        self.positions
            .iter()
            .zip(self.on_surface())
            .filter_map(|(&p, u)| u.then_some(p))
            .collect()
    }

    /// Applies `f` to every point, in parallel, and returns the results in the order of
    /// `points`.
    ///
    /// The points are visited along a Morton (Z-order) curve, so that consecutive queries are
    /// close and each can start from its predecessor's triangle (`f` gets and updates that
    /// hint), and the curve is cut into chunks of fixed length, each processed sequentially.
    /// The order and the chunks depend on the points only, so the results are identical
    /// for any thread count.
    fn map_points<T: Send>(
        &self,
        points: &[DVec3],
        f: impl Fn(DVec3, &mut Hint) -> T + Sync,
    ) -> Vec<T> {
        let order = morton_order(points);
        let chunks: Vec<Vec<T>> = order
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut hint = Hint::default();
                chunk
                    .iter()
                    .map(|&i| f(points[i as usize], &mut hint))
                    .collect()
            })
            .collect();
        let mut out: Vec<Option<T>> = Vec::with_capacity(points.len());
        out.resize_with(points.len(), || None);
        for (&i, value) in order.iter().zip(chunks.into_iter().flatten()) {
            out[i as usize] = Some(value);
        }
        out.into_iter()
            .map(|value| value.expect("every point is visited once"))
            .collect()
    }

    /// [`map_points`](Self::map_points) for an `f` that may put a point off: the values
    /// (`T::default()` for the points put off) and, in the order of the visits, the
    /// points put off with what `f` gave for them.
    fn map_points_deferred<T: Send + Default + Clone, W: Send>(
        &self,
        points: &[DVec3],
        f: impl Fn(DVec3, &mut Hint) -> Result<T, W> + Sync,
    ) -> (Vec<T>, Vec<(u32, W)>) {
        let order = morton_order(points);
        let chunks: Vec<Deferred<T, W>> = order
            .par_chunks(CHUNK)
            .map(|chunk| {
                let mut hint = Hint::default();
                let mut waiting = Vec::new();
                let values = chunk
                    .iter()
                    .map(|&i| match f(points[i as usize], &mut hint) {
                        Ok(value) => value,
                        Err(wait) => {
                            waiting.push((i, wait));
                            T::default()
                        }
                    })
                    .collect();
                (values, waiting)
            })
            .collect();
        let mut out = vec![T::default(); points.len()];
        let mut waiting = Vec::new();
        let mut at = order.iter();
        for (values, wait) in chunks {
            for (value, &i) in values.into_iter().zip(at.by_ref()) {
                out[i as usize] = value;
            }
            waiting.extend(wait);
        }
        (out, waiting)
    }

    /// The closest point, starting from the bound given by leaf position `hint`, which is
    /// then set to the answer's leaf position.
    fn query(&self, p: DVec3, hint: &mut Hint) -> ClosestPoint {
        let mut best_k = usize::MAX;
        let mut best_face = u32::MAX;
        let mut best = TrianglePoint {
            point: DVec3::ZERO,
            distance_squared: f64::INFINITY,
            feature: TriangleFeature::Interior,
        };
        if let Some(k) = hint.leaf {
            best = self.triangles[k].closest_point(p);
            best_k = k;
            best_face = self.leaf_faces[k];
        }
        self.bvh
            .nearest(p, best.distance_squared, &mut hint.stack, |k| {
                let triangle = &self.triangles[k];
                // The triangle's own box first: a leaf's box is the union of up to eight of
                // them, and many of the triangles of a visited leaf are farther
                // than the best so far. The box distance is computed as the hierarchy's node
                // test computes it (a triangle alone in a leaf was already pruned by this very
                // test), and a box at exactly the bound is not skipped (ties go to the face
                // order below).
                let [a, b, c] = triangle.corners;
                if box_distance_squared(a.min(b).min(c), a.max(b).max(c), p) > best.distance_squared
                {
                    return best.distance_squared;
                }
                let candidate = triangle.closest_point(p);
                let face = self.leaf_faces[k];
                if candidate.distance_squared < best.distance_squared
                    || (candidate.distance_squared == best.distance_squared && face < best_face)
                {
                    best = candidate;
                    best_k = k;
                    best_face = face;
                }
                best.distance_squared
            });
        if best_k == usize::MAX {
            // Unreachable for validated input (every distance is finite, so the search
            // finds a triangle); kept so that no input can index out of range.
            best_k = 0;
            best_face = self.leaf_faces[0];
            best = self.triangles[0].closest_point(p);
        }
        hint.leaf = Some(best_k);
        let face = best_face as usize;
        let feature = match best.feature {
            TriangleFeature::Interior => Feature::Face,
            TriangleFeature::Edge(k) => Feature::Edge(EdgeId::new(self.face_edges[face][k])),
            TriangleFeature::Vertex(k) => {
                Feature::Vertex(VertexId::new(self.face_vertices[face][k]))
            }
        };
        ClosestPoint {
            point: best.point,
            distance_squared: best.distance_squared,
            face: FaceId::new(best_face),
            feature,
        }
    }

    /// `± distance` by the pseudo-normal rule.
    fn sign(&self, p: DVec3, closest: &ClosestPoint) -> f64 {
        self.sign_with(p, closest, |v| self.vertex_normals()[v])
    }

    /// `± distance` by the pseudo-normal rule, with `vertex(v)` the pseudo-normal of
    /// vertex `v` (asked for only when the closest point is that vertex).
    fn sign_with(&self, p: DVec3, closest: &ClosestPoint, vertex: impl Fn(usize) -> DVec3) -> f64 {
        let d = closest.distance();
        if d == 0.0 {
            return 0.0;
        }
        let normals = self.pseudo_normals();
        let n = match closest.feature {
            Feature::Face => normals.face[closest.face.index()],
            Feature::Edge(e) => normals.edge[e.index()],
            Feature::Vertex(v) => vertex(v.index()),
        };
        let offset = p - closest.point;
        let mut side = offset.dot(n);
        if side == 0.0 {
            side = offset.dot(normals.face[closest.face.index()]);
        }
        if side < 0.0 { -d } else { d }
    }

    /// The face normals and edge pseudo-normals, computed on first use.
    fn pseudo_normals(&self) -> &PseudoNormals {
        self.pseudo_normals.get_or_init(|| {
            // The face normals in one parallel pass, then the edge sums in face order
            // (the same bits for any thread count).
            let face: Vec<DVec3> = self
                .face_vertices
                .par_iter()
                .map(|vs| {
                    let [a, b, c] = vs.map(|v| self.positions[v as usize]);
                    unit_normal(a, b, c)
                })
                .collect();
            let mut edge = vec![DVec3::ZERO; self.n_edges];
            for (n, es) in face.iter().zip(&self.face_edges) {
                if *n == DVec3::ZERO {
                    continue;
                }
                for &e in es {
                    edge[e as usize] += *n;
                }
            }
            PseudoNormals { face, edge }
        })
    }

    /// Every vertex's pseudo-normal, computed on first use.
    fn vertex_normals(&self) -> &[DVec3] {
        self.vertex_normals
            .get_or_init(|| self.vertex_pseudo_normals(None))
    }

    /// The angle-weighted pseudo-normals of the vertices `needed` says (all of them for
    /// `None`; zero for the others): the sum, in face order, of each face's unit normal
    /// times its angle at the vertex, degenerate faces left out.
    ///
    /// The vertices are split into ranges, one per parallel task; each task reads every
    /// face and adds to the vertices of its range, in face order, so the sums are the
    /// same bits for any number of tasks and for any `needed`.
    fn vertex_pseudo_normals(&self, needed: Option<&[bool]>) -> Vec<DVec3> {
        let face = &self.pseudo_normals().face;
        let n_vertices = self.positions.len();
        let tasks = if self.face_vertices.len() < 1 << 16 {
            1
        } else {
            rayon::current_num_threads().clamp(1, 8)
        };
        let mut vertex = vec![DVec3::ZERO; n_vertices];
        let mut pieces = Vec::with_capacity(tasks);
        let mut rest = &mut vertex[..];
        let mut v0 = 0;
        for t in 1..=tasks {
            let v1 = t * n_vertices / tasks;
            let (piece, tail) = rest.split_at_mut(v1 - v0);
            pieces.push((v0, piece));
            rest = tail;
            v0 = v1;
        }
        pieces.into_par_iter().for_each(|(v0, piece)| {
            let range = v0..v0 + piece.len();
            for (vs, &n) in self.face_vertices.iter().zip(face) {
                if n == DVec3::ZERO {
                    continue;
                }
                for (k, &v) in vs.iter().enumerate() {
                    let v = v as usize;
                    if range.contains(&v) && needed.is_none_or(|needed| needed[v]) {
                        let corners = vs.map(|v| self.positions[v as usize]);
                        piece[v - v0] += n * corner_angle(corners, k);
                    }
                }
            }
        });
        vertex
    }
}

/// The angle of triangle `corners` at corner `k`, in radians.
#[inline]
fn corner_angle(corners: [DVec3; 3], k: usize) -> f64 {
    let at = corners[k];
    let u = corners[(k + 1) % 3] - at;
    let w = corners[(k + 2) % 3] - at;
    u.cross(w).length().atan2(u.dot(w))
}

/// The unit normal `(b − a) × (c − a) / |…|`, or zero for a degenerate triangle (twice the
/// area at most [`DEGENERACY_RATIO`] times the longest edge squared).
fn unit_normal(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (u, w) = (b - a, c - a);
    let cross = u.cross(w);
    let two_area = cross.length();
    let longest2 = u
        .length_squared()
        .max(w.length_squared())
        .max((c - b).length_squared());
    if two_area > DEGENERACY_RATIO * longest2 {
        cross / two_area
    } else {
        DVec3::ZERO
    }
}

/// Checks that every point is finite and within [`MAX_COORDINATE`].
pub(crate) fn check_points(points: &[DVec3], what: &'static str) -> Result<(), MetricsError> {
    if u32::try_from(points.len()).is_err() {
        return Err(MetricsError::InvalidParameter {
            name: what,
            reason: "more than u32::MAX points",
        });
    }
    for (index, p) in points.iter().enumerate() {
        if !p.is_finite() {
            return Err(MetricsError::NonFinite { what, index });
        }
        if p.abs().max_element() > MAX_COORDINATE {
            let value = [p.x, p.y, p.z]
                .into_iter()
                .find(|c| c.abs() > MAX_COORDINATE)
                .unwrap_or(p.x);
            return Err(MetricsError::CoordinateTooLarge {
                what,
                index,
                value,
                limit: MAX_COORDINATE,
            });
        }
    }
    Ok(())
}
