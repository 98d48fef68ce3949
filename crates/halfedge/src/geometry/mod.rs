//! Geometry over a positions slice (`&[DVec3]`, f64): edge lengths, face normals and
//! areas, corner angles and cotangents, vertex normals and areas, bounding box, surface
//! area, enclosed volume.
//!
//! [`Geometry`] borrows a [`HalfedgeMesh`] and its vertex positions, checks once that
//! there is one position per vertex, and then answers per-element queries without
//! further checks. It holds no caches: building one is free, so a smoother can build a
//! new view on every iterate.
//!
//! # Conventions
//!
//! - **Units.** Lengths are in the unit of the positions, areas in unit², volumes in
//!   unit³, angles in radians.
//! - **Orientation.** A face's vertices run counter-clockwise seen from the side its
//!   normal points to (right-hand rule); a closed mesh with outward normals has positive
//!   volume.
//! - **Degeneracy.** A face is degenerate when twice its area is at most
//!   [`DEGENERACY_RATIO`] times its longest edge squared. The test is scale-invariant and
//!   also holds when all edges have zero length. For a triangle it is made at each
//!   corner, with the corner's own cross product (`|u × v|`, `u` and `v` the edges
//!   leaving the corner) and the three edges as plain differences of their endpoints;
//!   a cotangent is 0 when the test fails at its corner, and a triangle is degenerate
//!   when it fails at all three. So no result depends on which vertex a face starts at
//!   or in which row a corner is computed: the three corners' tests differ only by
//!   rounding, for triangles within about 10⁻⁴ (relative) of the threshold. A degenerate
//!   triangle contributes 0 to every cotangent and to mixed Voronoi areas, and nothing
//!   to area- and angle-weighted vertex normals.
//! - **Finite results.** For finite positions no query returns NaN and none panics on
//!   geometry: degenerate faces, coincident vertices and isolated vertices give 0 or the
//!   zero vector as documented per query. Lengths, areas and volumes are infinite only
//!   when their exact value exceeds `f64::MAX`. Edge vectors are rescaled by a power of
//!   two (exactly) when their products could overflow or underflow (components beyond
//!   about 10^±60), so that scale-invariant results (normals, angles, cotangents,
//!   degeneracy) stay accurate at any scale; in the usual range the arithmetic is the
//!   plain textbook one. Positions are assumed finite.
//! - **Agreement with OpenMesh.** Face normals, edge lengths and the
//!   [`Mean`](NormalWeighting::Mean) vertex normal follow OpenMesh's arithmetic operation
//!   by operation (`calc_face_normal`, `calc_edge_length` and `update_normals` of a
//!   `TriMesh` or `PolyMesh` with `f64` points; vertex normals sum the faces in the order
//!   of OpenMesh's clockwise vertex-face circulator, from the same start), so results agree
//!   to the last bit when OpenMesh built the mesh from the same face list.
//! - **Sums.** Whole-mesh sums (surface area, volume, centroid, mean edge length) are
//!   compensated (Neumaier), so they are accurate to about one rounding on meshes of any
//!   size. Per-vertex sums are plain, in circulation order.
//! - **Bulk queries.** [`Geometry::vertex_areas_into`], [`Geometry::face_cotangents_into`],
//!   [`Geometry::triangle_cotangents_into`], [`distances_into`] and
//!   [`ring_cotangents_with`] answer for many elements at once — in parallel with fixed chunks, or two at a time in SIMD lanes —
//!   with the bits of the per-element queries, whatever the thread count. The weight
//!   kernels and the smoothers use them, so "the same bits as the geometry" holds by
//!   construction.
//!
//! # Examples
//!
//! ```
//! use beltrami_halfedge::geometry::{Geometry, NormalWeighting, VertexAreaKind};
//! use beltrami_halfedge::primitives;
//! use beltrami_halfedge::{DVec3, VertexId};
//!
//! let cube = primitives::cube();
//! let mesh = cube.mesh()?;
//! let geometry = Geometry::new(&mesh, &cube.positions)?;
//!
//! assert!((geometry.surface_area() - 6.0).abs() < 1e-15);
//! assert!((geometry.volume()? - 1.0).abs() < 1e-15);
//!
//! // The angle-weighted normal at a corner of the cube is the diagonal, whatever the
//! // triangulation of the sides.
//! let n = geometry.vertex_normal(VertexId::new(7), NormalWeighting::Angle);
//! assert!((n - DVec3::ONE / 3f64.sqrt()).length() < 1e-15);
//!
//! let areas = geometry.vertex_areas(VertexAreaKind::MixedVoronoi)?;
//! let total: f64 = areas.as_slice().iter().sum();
//! assert!((total - 6.0).abs() < 1e-14);
//! # Ok::<(), beltrami_halfedge::TopologyError>(())
//! ```
//!
//! # References
//!
//! - M. Meyer, M. Desbrun, P. Schröder, A. H. Barr: *Discrete differential-geometry
//!   operators for triangulated 2-manifolds*. Visualization and Mathematics III, 2003
//!   (mixed Voronoi areas, cotangent formula).
//! - G. Thürmer, C. A. Wüthrich: *Computing vertex normals from polygonal facets*.
//!   Journal of Graphics Tools 3(1), 1998 (angle-weighted vertex normals).
//! - M. E. Newell's method for plane equations of polygons, as given by I. E. Sutherland,
//!   R. F. Sproull, R. A. Schumacker: *A characterization of ten hidden-surface
//!   algorithms*. ACM Computing Surveys 6(1), 1974.

mod angles;
mod areas;
mod batch;
mod edges;
mod faces;
mod kernel;
mod lanes;
mod measures;
mod normals;
mod summary;
mod triangles;

use glam::DVec3;

pub use areas::VertexAreaKind;
pub use kernel::CompensatedSum;

/// The distance `|q − p|`: the same bits as `(q - p).length()` wherever that is
/// accurate, and finite (rescaled by a power of two) whenever the distance is
/// representable, even where squaring the components would overflow or underflow.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{geometry::distance, DVec3};
/// assert_eq!(distance(DVec3::ZERO, DVec3::new(3.0, 4.0, 0.0)), 5.0);
/// assert_eq!(distance(DVec3::ZERO, DVec3::splat(1e300)), 1e300 * 3f64.sqrt());
/// ```
#[must_use]
pub fn distance(p: glam::DVec3, q: glam::DVec3) -> f64 {
    kernel::distance(p, q)
}
/// The barycentric coordinates `[α, β, γ]` of `p` in triangle `(a, b, c)`, with
/// `p = α a + β b + γ c` when `p` lies in the triangle's plane (otherwise those of its
/// orthogonal projection onto the plane); `α + β + γ = 1`. Not clamped: a point outside
/// the triangle has a negative coordinate. Equal thirds for a degenerate triangle (no
/// area, or not finite).
///
/// # Examples
/// ```
/// use beltrami_halfedge::{geometry::barycentric, DVec3};
/// let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
/// assert_eq!(barycentric(DVec3::new(0.25, 0.5, 0.0), a, b, c), [0.25, 0.25, 0.5]);
/// assert_eq!(barycentric(DVec3::X, a, b, 2.0 * b), [1.0 / 3.0; 3]);
/// ```
#[must_use]
pub fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let (u, v, w) = (b - a, c - a, p - a);
    let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
    let (wu, wv) = (w.dot(u), w.dot(v));
    let det = uu * vv - uv * uv;
    if det.is_nan() || det <= 0.0 {
        return [1.0 / 3.0; 3];
    }
    let s = (vv * wu - uv * wv) / det;
    let t = (uu * wv - uv * wu) / det;
    [1.0 - s - t, s, t]
}

pub use batch::{
    BLOCK, blocked_index, distances_into, distances_with, lengths_with, ring_cotangents_with,
};
pub use normals::NormalWeighting;
pub use summary::MeshSummary;
pub use triangles::{
    TriangleGeometry, triangle_cotangents_blocked_into, triangle_cotangents_into, vertex_area_share,
};

use crate::error::TopologyError;
use crate::ids::{FaceId, VertexId};
use crate::mesh::HalfedgeMesh;

use kernel::{Polygon, Triangle};

/// The ratio below which a face counts as degenerate: twice its area at most
/// `DEGENERACY_RATIO × (longest edge)²`.
///
/// For a triangle, twice the area over the longest edge squared is the height over the
/// longest edge divided by that edge, so a triangle is degenerate when it is flatter than
/// one part in 10¹². Its smallest angle is then below about 10⁻¹² rad and a cotangent
/// would exceed 10¹², so cotangent weights treat it as absent.
pub const DEGENERACY_RATIO: f64 = 1e-12;

/// A borrowed view of a mesh with its vertex positions, answering geometric queries.
///
/// Build it with [`Geometry::new`], which checks the number of positions once; every
/// per-element query is then infallible for valid ids. See the [module
/// documentation](self) for units, orientation, degeneracy and finiteness conventions.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::{DVec3, FaceId, HalfedgeMesh};
///
/// let mesh = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 2]])?;
/// let positions = [DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
/// let geometry = Geometry::new(&mesh, &positions)?;
/// assert_eq!(geometry.face_area(FaceId::new(0)), 1.0);
/// assert_eq!(geometry.face_normal(FaceId::new(0)), DVec3::Z);
/// # Ok::<(), beltrami_halfedge::TopologyError>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Geometry<'a> {
    mesh: &'a HalfedgeMesh,
    positions: &'a [DVec3],
}

impl<'a> Geometry<'a> {
    /// A view of `mesh` with vertex `v` at `positions[v.index()]`.
    ///
    /// # Errors
    /// [`TopologyError::PositionCount`] when `positions.len()` differs from the number of
    /// vertices (isolated vertices included).
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};
    /// let mesh = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 2]])?;
    /// let err = Geometry::new(&mesh, &[DVec3::ZERO; 2]).unwrap_err();
    /// assert_eq!(err, TopologyError::PositionCount { positions: 2, vertices: 3 });
    /// # Ok::<(), TopologyError>(())
    /// ```
    pub fn new(mesh: &'a HalfedgeMesh, positions: &'a [DVec3]) -> Result<Self, TopologyError> {
        if positions.len() != mesh.n_vertices() {
            return Err(TopologyError::PositionCount {
                positions: positions.len(),
                vertices: mesh.n_vertices(),
            });
        }
        Ok(Self { mesh, positions })
    }

    /// The mesh.
    #[must_use]
    pub fn mesh(&self) -> &'a HalfedgeMesh {
        self.mesh
    }

    /// The positions, one per vertex.
    #[must_use]
    pub fn positions(&self) -> &'a [DVec3] {
        self.positions
    }

    /// The position of `v`.
    ///
    /// # Panics
    /// If `v` is not a vertex of the mesh.
    #[inline]
    #[must_use]
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.positions[v.index()]
    }

    /// The positions of triangle `f` in face order, or `None` when `f` has more than three
    /// vertices.
    #[inline]
    fn triangle(&self, f: FaceId) -> Option<Triangle> {
        let m = self.mesh;
        let h0 = m.face_halfedge(f);
        let h1 = m.next(h0);
        let h2 = m.next(h1);
        (m.next(h2) == h0).then(|| {
            Triangle([
                self.position(m.to_vertex(h0)),
                self.position(m.to_vertex(h1)),
                self.position(m.to_vertex(h2)),
            ])
        })
    }

    /// The positions of face `f` in face order, as a general polygon.
    fn polygon(&self, f: FaceId) -> Polygon {
        Polygon(
            self.mesh
                .vertices_around_face(f)
                .map(|v| self.position(v))
                .collect(),
        )
    }
}
