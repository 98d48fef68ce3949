//! Face queries: normal, vector area, area, centroid, degeneracy.

use glam::DVec3;

use super::Geometry;
use crate::ids::FaceId;
use crate::map::FaceMap;

impl Geometry<'_> {
    /// The unit normal of face `f`, or [`DVec3::ZERO`] when it is undefined (all vertices
    /// collinear or coincident). Never NaN.
    ///
    /// Triangles use exactly OpenMesh's arithmetic: with `p0, p1, p2` the vertices in face
    /// order ([`vertices_around_face`](crate::HalfedgeMesh::vertices_around_face)),
    /// `n = (p2 − p1) × (p0 − p1)` and the result is `n * (1.0 / |n|)` (a multiplication by
    /// the reciprocal, as OpenMesh does). Larger polygons use Newell's method as OpenMesh
    /// writes it (`a = p_i − p_{i+1}`, `b = p_i + p_{i+1}`,
    /// `n += (a.y·b.z, a.z·b.x, a.x·b.y)`), normalised the same way.
    ///
    /// Only a zero `n` gives the zero vector: a nearly degenerate face still has a unit
    /// normal, however noisy its direction (use
    /// [`is_degenerate_face`](Self::is_degenerate_face) to tell).
    ///
    /// # Panics
    /// If `f` is not a face of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{primitives, DVec3, FaceId};
    /// let cube = primitives::cube();
    /// let mesh = cube.mesh()?;
    /// let geometry = Geometry::new(&mesh, &cube.positions)?;
    /// assert_eq!(geometry.face_normal(FaceId::new(0)), -DVec3::Z); // the z = 0 side
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    ///
    /// # References
    /// Newell's method: Sutherland, Sproull, Schumacker, ACM Computing Surveys 6(1), 1974.
    #[must_use]
    pub fn face_normal(&self, f: FaceId) -> DVec3 {
        match self.triangle(f) {
            Some(t) => t.normal(),
            None => self.polygon(f).normal(),
        }
    }

    /// The unit normal of every face (see [`face_normal`](Self::face_normal)).
    ///
    /// # Complexity
    /// O(F + H).
    #[must_use]
    pub fn face_normals(&self) -> FaceMap<DVec3> {
        FaceMap::from_vec(self.mesh.faces().map(|f| self.face_normal(f)).collect())
    }

    /// The vector area of face `f` in unit²: its area times its unit normal.
    ///
    /// For a triangle `½ (p1 − p0) × (p2 − p0)`; for a polygon half of Newell's vector,
    /// `½ Σ (p_i − p0) × (p_{i+1} − p0)`, evaluated around the first vertex so that no
    /// digits are lost far from the origin. For a non-planar polygon this is the vector
    /// area of the fan from the first vertex, which does not depend on that choice.
    ///
    /// # Panics
    /// If `f` is not a face of the mesh.
    #[must_use]
    pub fn face_vector_area(&self, f: FaceId) -> DVec3 {
        match self.triangle(f) {
            Some(t) => t.vector_area(),
            None => self.polygon(f).vector_area(),
        }
    }

    /// The area of face `f` in unit²: `½ |(p1 − p0) × (p2 − p0)|` for a triangle, half the
    /// length of Newell's vector for a polygon (the length of
    /// [`face_vector_area`](Self::face_vector_area)). Zero for a face whose vertices are
    /// collinear or coincident.
    ///
    /// # Panics
    /// If `f` is not a face of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{primitives, FaceId};
    /// let hexagon = primitives::hexagon_fan();
    /// let mesh = hexagon.mesh()?;
    /// let geometry = Geometry::new(&mesh, &hexagon.positions)?;
    /// // Six equilateral triangles of side 1.
    /// assert!((geometry.face_area(FaceId::new(0)) - 3f64.sqrt() / 4.0).abs() < 1e-15);
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    #[must_use]
    pub fn face_area(&self, f: FaceId) -> f64 {
        match self.triangle(f) {
            Some(t) => t.area(),
            None => self.polygon(f).area(),
        }
    }

    /// The area of every face in unit² (see [`face_area`](Self::face_area)).
    ///
    /// # Complexity
    /// O(F + H).
    #[must_use]
    pub fn face_areas(&self) -> FaceMap<f64> {
        FaceMap::from_vec(self.mesh.faces().map(|f| self.face_area(f)).collect())
    }

    /// The centroid of face `f`: the average of its vertex positions, summed in face order
    /// and divided by the number of vertices (OpenMesh's `calc_face_centroid`). For a
    /// triangle this is also its centre of area; for a larger polygon it generally is not.
    ///
    /// # Panics
    /// If `f` is not a face of the mesh.
    #[must_use]
    pub fn face_centroid(&self, f: FaceId) -> DVec3 {
        let mut sum = DVec3::ZERO;
        let mut k = 0u32;
        for v in self.mesh.vertices_around_face(f) {
            sum += self.position(v);
            k += 1;
        }
        sum / f64::from(k)
    }

    /// Whether face `f` is degenerate: twice its area is at most
    /// [`DEGENERACY_RATIO`](super::DEGENERACY_RATIO) times its longest edge squared
    /// (true when all its vertices coincide). Scale-invariant.
    ///
    /// A degenerate triangle contributes 0 to every cotangent and to mixed Voronoi areas,
    /// and nothing to area- and angle-weighted vertex normals.
    ///
    /// # Panics
    /// If `f` is not a face of the mesh.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::geometry::Geometry;
    /// use beltrami_halfedge::{DVec3, FaceId, HalfedgeMesh};
    /// let mesh = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 2]])?;
    /// let flat = [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1e-13, 0.0)];
    /// let needle = [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1e-9, 0.0)];
    /// assert!(Geometry::new(&mesh, &flat)?.is_degenerate_face(FaceId::new(0)));
    /// assert!(!Geometry::new(&mesh, &needle)?.is_degenerate_face(FaceId::new(0)));
    /// # Ok::<(), beltrami_halfedge::TopologyError>(())
    /// ```
    #[must_use]
    pub fn is_degenerate_face(&self, f: FaceId) -> bool {
        match self.triangle(f) {
            Some(t) => t.is_degenerate(),
            None => self.polygon(f).is_degenerate(),
        }
    }
}
